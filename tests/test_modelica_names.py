"""Each library class declares its Modelica name once, as ``modelica_name``.

The one source of truth the Modelica reader (``Modelica.Mechanics.Rotational.
Components.Inertia inertia1(...)`` -> ``acausal.library.rotational.Inertia``), the
coverage table (``docs/coverage.py``) and ``acausal show Modelica....`` read,
through :func:`acausal.tools.catalog.msl_name`.  The checks: a class whose
docstring names an MSL class in its first paragraph declares that name itself
(not by inheritance); no two classes declare the same name (a sized subclass
made at run time is not a second class: it has its base's name); every name
is a Modelica (or ModelicaTest) name; ``acausal show NAME`` finds the class.
The MSL names of the docstrings are read here independently of the catalog.
"""

from __future__ import annotations

import enum
import importlib
import pkgutil
import re

import pytest

from acausal.language import Component, Connector, own_docstring
from acausal.tools.catalog import find_object, msl_name
from library_checks import exported_classes

#: The MSL class a docstring names: the first ``(Modelica.…`` of its first paragraph.
DOCSTRING_NAME = re.compile(r"\((Modelica(?:\.\w+)+)")

EXPORTED = exported_classes()

#: Classes whose docstring's parenthesis names an MSL package, not a class they reproduce:
#: they declare ``modelica_name = None`` (so the docstring is not read either).
NO_MSL_CLASS = {"acausal.library.blocks.tables._Options": "Modelica.Blocks.Types"}


def _docstring_name(klass: type) -> str | None:
    match = DOCSTRING_NAME.search(own_docstring(klass).split("\n\n", 1)[0])
    return match.group(1) if match else None


def _declared(klass: type) -> str | None:
    """The ``modelica_name`` the class declares itself (not an inherited one)."""
    return vars(klass).get("modelica_name")


def _library_classes() -> dict[str, type]:
    """Every class the modules of acausal.library and acausal.components define, by module path."""
    import acausal.components
    import acausal.library

    found = {}
    for package in (acausal.library, acausal.components):
        modules = [package] + [importlib.import_module(info.name) for info in
                               pkgutil.walk_packages(package.__path__, f"{package.__name__}.")]
        for module in modules:
            for name, value in vars(module).items():
                if isinstance(value, type) and value.__module__ == module.__name__:
                    found.setdefault(f"{value.__module__}.{value.__qualname__}", value)
    return found


LIBRARY_CLASSES = _library_classes()


@pytest.mark.parametrize("name", sorted(EXPORTED))
def test_an_exported_class_declares_the_modelica_name_its_docstring_gives(name):
    klass = EXPORTED[name]
    documented = _docstring_name(klass)
    if documented is None:
        assert _declared(klass) is None, f"{name}: declares a modelica_name its docstring does not give"
        return
    assert _declared(klass) == documented, (
        f"{name}: its docstring names {documented}, it declares modelica_name = {_declared(klass)!r}")
    assert msl_name(klass) == documented


def test_every_class_of_the_libraries_declares_the_name_its_docstring_gives():
    # the shared connectors and partials, the classes a package does not export, the classes
    # factories make (Multiplex2 ... DeMultiplex6) and the enumerations MSL defines as types
    wrong = {path: (_docstring_name(klass), _declared(klass)) for path, klass in LIBRARY_CLASSES.items()
             if _docstring_name(klass) != _declared(klass) and path not in NO_MSL_CLASS}
    assert not wrong, f"docstring name != modelica_name: {wrong}"
    assert sum(_declared(k) is not None for k in LIBRARY_CLASSES.values()) >= 269


def test_a_class_naming_an_msl_package_declares_no_modelica_name():
    for path, package in NO_MSL_CLASS.items():
        klass = LIBRARY_CLASSES[path]
        assert _docstring_name(klass) == package
        assert "modelica_name" in vars(klass) and _declared(klass) is None
        assert msl_name(klass) is None


def test_no_two_classes_declare_the_same_modelica_name():
    owners: dict[str, list[str]] = {}
    for path, klass in LIBRARY_CLASSES.items():
        if _declared(klass) is not None:
            owners.setdefault(_declared(klass), []).append(path)
    shared = {name: paths for name, paths in owners.items() if len(paths) > 1}
    assert not shared, f"one Modelica name, several classes: {shared}"


def test_every_modelica_name_is_a_modelica_name():
    for path, klass in LIBRARY_CLASSES.items():
        name = _declared(klass)
        if name is not None:
            assert isinstance(name, str) and name.startswith(("Modelica.", "ModelicaTest.")), (path, name)
            assert re.fullmatch(r"\w+(\.\w+)+", name), (path, name)


@pytest.mark.parametrize("name", sorted(EXPORTED))
def test_a_sized_subclass_has_its_base_modelica_name(name):
    # Component.__new__ and VectorBlock.__new__ make a subclass per sizes: it is the same
    # MSL class, and no second owner of the name
    klass = EXPORTED[name]
    sized = type(klass())
    if sized is klass:
        return
    assert vars(sized)["_unsized"] is klass
    assert "modelica_name" not in vars(sized)
    assert msl_name(sized) == msl_name(klass) == sized.modelica_name


@pytest.mark.parametrize("name", sorted(EXPORTED))
def test_acausal_show_finds_an_exported_class_by_its_modelica_name(name):
    klass = EXPORTED[name]
    if _declared(klass) is not None:
        assert find_object(_declared(klass)) is klass


def test_acausal_show_finds_every_component_and_connector_class_by_its_modelica_name():
    # the classes a package does not export under their MSL name are found too when the
    # name ends in the class's own (Modelica.Blocks.Continuous.StateSpace)
    for path, klass in LIBRARY_CLASSES.items():
        name = _declared(klass)
        if (name is not None and issubclass(klass, (Component, Connector)) and not path.rsplit(".", 1)[-1].startswith("_")
                and name.rsplit(".", 1)[-1] == klass.__name__):
            assert find_object(name) is klass, (path, name)


def test_the_factory_classes_declare_their_names():
    from acausal.library.blocks import routing

    for parts in range(2, 7):
        for kind in ("Multiplex", "DeMultiplex"):
            klass = getattr(routing, f"{kind}{parts}")
            assert _declared(klass) == f"Modelica.Blocks.Routing.{kind}{parts}"


def test_the_enumerations_msl_defines_as_types_declare_their_names_and_stay_enumerations():
    from acausal.library.blocks.continuous import Init
    from acausal.library.blocks.nonlinear import LimiterHomotopy, VariableLimiterHomotopy
    from acausal.library.blocks.types import Regularization

    for klass, members in ((Init, 4), (LimiterHomotopy, 4), (VariableLimiterHomotopy, 3), (Regularization, 4)):
        assert issubclass(klass, enum.IntEnum)
        assert _declared(klass) == f"Modelica.Blocks.Types.{klass.__name__}"
        assert msl_name(klass) == _declared(klass)
        # a str in an IntEnum's body would be a member: the name is set after the body
        assert "modelica_name" not in klass.__members__ and len(klass) == members


def test_msl_name_reads_the_declared_name_first_and_never_an_inherited_one():
    # (on Component, not a library class: docs/coverage.py would count this file as a test of it)
    class Documented(Component):
        """A flywheel (Modelica.Mechanics.Rotational.Components.Disc)."""

    class Declared(Component):
        """A flywheel (Modelica.Mechanics.Rotational.Components.Disc)."""

        modelica_name = "Modelica.Mechanics.Rotational.Components.Inertia"

    class Silent(Component):
        """A flywheel of mine."""

    class OptedOut(Component):
        """A flywheel (Modelica.Mechanics.Rotational.Components.Disc)."""

        modelica_name = None

    assert msl_name(Documented) == "Modelica.Mechanics.Rotational.Components.Disc"  # the docstring
    assert msl_name(Declared) == "Modelica.Mechanics.Rotational.Components.Inertia"  # the attribute first
    assert msl_name(Silent) is None  # not inherited
    assert msl_name(OptedOut) is None
