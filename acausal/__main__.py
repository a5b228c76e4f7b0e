"""``python -m acausal``: the same command line as the ``acausal`` script."""

from .cli import run

run()
