"""``python -m acausal``: the same command line as the ``acausal`` script."""

from .tools.cli import run

run()
