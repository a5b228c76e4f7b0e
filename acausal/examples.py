"""The examples: the repository folder ``examples/`` as ``acausal.examples``.

From a source checkout or an editable install this module loads the folder
as the package (see :mod:`acausal._checkout`); a wheel installs the folder
itself as ``acausal.examples`` and this module is never run.
"""

from ._checkout import load_folder

load_folder(__name__, "examples")
