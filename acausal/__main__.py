"""``python -m acausal``: the same command line as the ``acausal`` script."""

import sys

from .cli import main

sys.exit(main())
