"""The repository folders that install inside the package, imported from a source checkout.

``pyproject.toml`` installs the repository's folders ``components/``,
``library/`` and ``examples/`` as ``acausal.components``, ``acausal.library``
and ``acausal.examples`` (``package-dir``).  Python run in the checkout's root
folder (``python -c``, ``python -m pytest``, the REPL: the working folder is
first on ``sys.path``) imports ``acausal`` from the checkout's ``acausal/``
folder instead of the installed package, and that folder has no such
subpackages: with acausal installed from a wheel, or not installed at all,
``import acausal.components`` failed there.  The modules
``acausal/components.py``, ``acausal/library.py`` and ``acausal/examples.py``
stand in: each loads its repository folder as the package of its name, so
``acausal.components`` is the same package whichever way it is found.  An
editable install (``pip install -e .``) finds these modules too, and they load
the same folders; a wheel puts the folders themselves into
``site-packages/acausal/``, where Python finds a package before a module of
the same name, and these modules are never run.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

#: The checkout's root folder: the parent of ``acausal/``.
ROOT = Path(__file__).resolve().parent.parent


def load_folder(name: str, folder: str) -> None:
    """Put the package ``name`` into ``sys.modules``: the repository folder ``folder``.

    Called by the module that is being imported as ``name``; the import
    system then hands out what ``sys.modules[name]`` holds, the package.
    """
    init = ROOT / folder / "__init__.py"
    if not init.is_file():
        raise ModuleNotFoundError(f"No module named {name!r}: the folder {folder}/ is not beside "
                                  f"{ROOT / 'acausal'} (install acausal: pip install -e .)", name=name)
    spec = importlib.util.spec_from_file_location(name, init, submodule_search_locations=[str(init.parent)])
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        sys.modules.pop(name, None)
        raise
