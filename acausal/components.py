"""Connectors and partial models shared by the component libraries: the repository folder ``components/`` as ``acausal.components``.

From a source checkout or an editable install this module loads the folder
as the package (see :mod:`acausal._checkout`); a wheel installs the folder
itself as ``acausal.components`` and this module is never run.
"""

from ._checkout import load_folder

load_folder(__name__, "components")
