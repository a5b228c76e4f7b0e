"""``acausal show`` and ``acausal list``: what the libraries offer, from the command line.

::

    acausal list                                   # the library packages
    acausal list blocks                            # the classes of a package
    acausal show Clutch                            # parameters, connectors, variables
    acausal show rotational.Clutch
    acausal show Modelica.Mechanics.Rotational.Components.Clutch
    acausal show examples/coupled_clutches.py:CoupledClutches

Every name these commands print is a name they accept.  A class or package
of the libraries may be named

* by what ``acausal list`` prints: a package (``blocks``), a class
  (``Clutch``; a name two packages share, such as ``Flange_a``, is an error
  that names both);
* short and dotted: ``rotational.Clutch``, ``blocks.CombiTable1Ds``;
* by its module path: ``acausal.library.rotational.Clutch``, or without the
  ``acausal.`` prefix, ``library.rotational.Clutch``;
  ``acausal.components.rotational.Flange`` (``components.rotational.Flange``);
* by its name in the Modelica Standard Library:
  ``Modelica.Mechanics.Rotational.Components.Clutch``.  Each library class
  names its MSL class in parentheses in the first paragraph of its docstring
  (``Clutch with controlled normal force
  (Modelica.Mechanics.Rotational.Components.Clutch).``); the map is built
  from those.  An MSL package lists what acausal has of it
  (``acausal list Modelica.Blocks.Sources``).

``FILE.py:Class`` names a class of a Python file, ``FILE.py`` alone the
file's only component class.  Another dotted name is imported as it is
(``mypackage.models.Valve``).

Both functions return the exit status: 0 on success, 2 for a name that
names nothing.  The message suggests close names, drawn from the packages
and component classes only (never from other attributes of a module).
"""

from __future__ import annotations

import argparse
import difflib
import functools
import importlib
import importlib.util
import inspect
import pkgutil
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path
from types import ModuleType
from typing import Sequence

from ..language import Component, Connector, describe, own_docstring

__all__ = ["main_show", "main_list", "find_object", "component_classes", "NameNotFound", "listing",
           "msl_name", "names", "Names"]

#: The package the libraries are installed in; a name may leave it out.
PACKAGE = "acausal"
#: The component libraries (``acausal.library.<package>``) and the shared connectors and partials.
LIBRARY = f"{PACKAGE}.library"
COMPONENTS = f"{PACKAGE}.components"

#: The MSL class a library class reproduces: the first parenthesis of its docstring's first
#: paragraph that starts with a Modelica name, ``(Modelica.Blocks.Sources.Step)``.
MSL_CLASS = re.compile(r"\((Modelica(?:\.\w+)+)")
#: The MSL package a library package reproduces: its docstring starts ``Modelica.Blocks: ...``.
MSL_PACKAGE = re.compile(r"^(Modelica(?:\.\w+)+)\s*:")


class NameNotFound(LookupError):
    """A name that names no module, class or file; ``hint`` suggests close names."""

    def __init__(self, message: str, hint: str = "", depth: int = 0) -> None:
        super().__init__(message)
        self.hint = hint
        #: how many parts of a dotted name were found before this one failed
        self.depth = depth


# ---------------------------------------------------------------------------
# The names the libraries offer
# ---------------------------------------------------------------------------


def _is_described(obj: object) -> bool:
    """Whether ``describe`` can show it: a component or connector class (not the bases themselves)."""
    return (isinstance(obj, type) and issubclass(obj, (Component, Connector))
            and obj not in (Component, Connector))


def component_classes(module: ModuleType) -> list[type]:
    """The component and connector classes a module offers, by name.

    Those it imports count (a package offers its submodules' classes);
    private names (``_Base``) do not.
    """
    return sorted((obj for name, obj in vars(module).items()
                   if not name.startswith("_") and _is_described(obj)),
                  key=lambda klass: klass.__name__)


def msl_name(klass: type) -> str | None:
    """The Modelica Standard Library class ``klass`` reproduces, or None.

    The ``modelica_name`` the class declares itself
    (``modelica_name = "Modelica.Mechanics.Rotational.Components.Clutch"``), never an
    inherited one: a subclass that reproduces another MSL class declares its own, and one
    that declares none reproduces none.  A sized subclass made at run time (its ``_unsized``
    base) has its base's name.  A class that declares no ``modelica_name`` falls back to the
    first ``(Modelica.…`` in the first paragraph of its own docstring:
    ``"Clutch with controlled normal force (Modelica.Mechanics.Rotational.Components.Clutch)."``
    """
    own = vars(klass)
    base = own.get("_unsized")
    if isinstance(base, type) and base is not klass:
        return msl_name(base)
    if "modelica_name" in own:
        declared = own["modelica_name"]
        return declared if isinstance(declared, str) else None
    paragraph = own_docstring(klass).split("\n\n", 1)[0]
    match = MSL_CLASS.search(paragraph)
    return match.group(1) if match else None


def _package_msl_name(module: ModuleType) -> str | None:
    match = MSL_PACKAGE.match(inspect.getdoc(module) or "")
    return match.group(1) if match else None


def _import(name: str) -> ModuleType | None:
    try:
        return importlib.import_module(name)
    except ImportError:
        return None


def _public_submodules(module: ModuleType) -> list[str]:
    if not hasattr(module, "__path__"):
        return []
    return sorted(info.name for info in pkgutil.iter_modules(module.__path__) if not info.name.startswith("_"))


@dataclass
class Names:
    """Every package and class ``list`` and ``show`` know, under every spelling they accept.

    Attributes
    ----------
    modules : dict
        Full module path (``acausal.library.rotational``) -> module: the
        libraries, their packages and the packages' modules, and
        ``acausal.components`` with its modules.
    classes : dict
        Full path where a module offers a class (``acausal.library.rotational.Clutch``,
        also ``acausal.library.rotational.components.Clutch``) -> the class.
    packages : list of str
        The library packages (``acausal.library.blocks`` ...), what ``acausal list`` lists.
    msl : dict
        MSL class name -> the class reproducing it.
    msl_packages : dict
        MSL package name (``Modelica.Blocks``) -> the library package reproducing it.
    spellings : dict
        Every accepted spelling of a module or class -> its full path.
    """

    modules: dict[str, ModuleType] = field(default_factory=dict)
    classes: dict[str, type] = field(default_factory=dict)
    packages: list[str] = field(default_factory=list)
    msl: dict[str, type] = field(default_factory=dict)
    msl_packages: dict[str, ModuleType] = field(default_factory=dict)
    spellings: dict[str, str] = field(default_factory=dict)

    def spell(self, path: str) -> list[str]:
        """The spellings of a full path: itself, without ``acausal.``, and, for the library, short."""
        found = [path]
        if path.startswith(f"{PACKAGE}."):
            found.append(path[len(PACKAGE) + 1:])
        if path.startswith(f"{LIBRARY}."):
            found.append(path[len(LIBRARY) + 1:])
        return found

    def short(self, klass: type) -> str:
        """How a message names a class: ``rotational.Clutch`` (its library package), else the
        module defining it (``components.rotational.PartialCompliant``)."""
        paths = [path for path, obj in self.classes.items() if obj is klass]
        exported = [p for p in paths if p.rsplit(".", 1)[0] in self.packages]
        defining = [p for p in paths if p == f"{klass.__module__}.{klass.__name__}"]
        path = (exported or defining or sorted(paths, key=lambda p: (p.count("."), p))
                or [klass.__qualname__])[0]
        return self.spell(path)[-1]

    def bare(self, name: str) -> list[type]:
        """The distinct classes called ``name`` (as a package listing prints them)."""
        found: list[type] = []
        for path, klass in self.classes.items():
            if path.rsplit(".", 1)[-1] == name and klass not in found:
                found.append(klass)
        return found

    def in_form(self, form: str) -> dict[str, object]:
        """The spellings of one form (:func:`_form`) -> what they name.

        The short form also has the bare class names a package listing
        prints (a name packages share names several classes: it is left
        out) and ``library`` and ``components``, where the other forms start.
        """
        found: dict[str, object] = {}
        for spelling, path in self.spellings.items():
            if _form(spelling.split(".", 1)[0]) == form:
                found[spelling] = self.modules.get(path) or self.classes[path]
        if form == PACKAGE:
            found[PACKAGE] = sys.modules[PACKAGE]
        if form == "short":
            called: dict[str, set[int]] = {}
            for path, klass in self.classes.items():
                called.setdefault(_last(path), set()).add(id(klass))
            for path, klass in self.classes.items():
                if len(called[_last(path)]) == 1:
                    found.setdefault(_last(path), klass)
            for root in (LIBRARY, COMPONENTS):
                if root in self.modules:
                    found.setdefault(root.rsplit(".", 1)[-1], self.modules[root])
        return found

    def msl_children(self, prefix: str) -> tuple[list[str], dict[str, type]]:
        """Below the MSL package ``prefix``: the next names of deeper packages, and the classes in it."""
        packages, classes = set(), {}
        for name, klass in self.msl.items():
            if not name.startswith(prefix + "."):
                continue
            rest = name[len(prefix) + 1:].split(".")
            if len(rest) == 1:
                classes[rest[0]] = klass
            else:
                packages.add(rest[0])
        for name in self.msl_packages:
            if name.startswith(prefix + "."):
                packages.add(name[len(prefix) + 1:].split(".")[0])
        return sorted(packages), classes


@functools.lru_cache(maxsize=1)
def names() -> Names:
    """The :class:`Names` of the installed libraries (imported on the first call)."""
    index = Names()
    roots = [root for root in (LIBRARY, COMPONENTS) if _import(root) is not None]
    for root in roots:
        module = sys.modules[root]
        index.modules[root] = module
        for sub in _public_submodules(module):
            child = _import(f"{root}.{sub}")
            if child is None:
                continue
            index.modules[child.__name__] = child
            if root == LIBRARY and hasattr(child, "__path__"):
                index.packages.append(child.__name__)
                for leaf in _public_submodules(child):
                    grandchild = _import(f"{child.__name__}.{leaf}")
                    if grandchild is not None:
                        index.modules[grandchild.__name__] = grandchild
    for path, module in index.modules.items():
        for klass in component_classes(module):
            index.classes[f"{path}.{klass.__name__}"] = klass
    # the MSL names: every class a library package offers, then the shared connectors and
    # partials whose docstring names the MSL class of their own name
    for package in index.packages:
        module = index.modules[package]
        if (msl := _package_msl_name(module)) is not None:
            index.msl_packages[msl] = module
        for klass in component_classes(module):
            if (msl := msl_name(klass)) is not None:
                index.msl.setdefault(msl, klass)
    for path, klass in index.classes.items():
        msl = msl_name(klass)
        if path.startswith(f"{COMPONENTS}.") and msl and msl.rsplit(".", 1)[-1] == klass.__name__:
            index.msl.setdefault(msl, klass)
        elif path.startswith(f"{LIBRARY}.") and msl and msl.rsplit(".", 1)[-1] == klass.__name__:
            # a class its package does not export under that name (Blocks.Continuous.StateSpace
            # beside the exported Blocks.Discrete.StateSpace): found by its MSL name too
            index.msl.setdefault(msl, klass)
    for path in [*index.modules, *index.classes]:
        for spelling in index.spell(path):
            index.spellings.setdefault(spelling, path)
    return index


# ---------------------------------------------------------------------------
# Finding what a name names
# ---------------------------------------------------------------------------


def find_object(name: str) -> object:
    """The module or class a name names (see the module docstring for the spellings).

    Parameters
    ----------
    name : str
        ``blocks``, ``Gain``, ``blocks.Gain``, ``library.blocks.Gain``,
        ``acausal.library.blocks.Gain``, ``Modelica.Blocks.Math.Gain``,
        ``models.py:MyModel`` or ``models.py``.

    Raises
    ------
    NameNotFound
        If nothing has that name (its hint lists close names), or if a class
        name that packages share names several classes.
    """
    path, _, class_name = name.partition(":")
    if path.endswith(".py") or class_name:
        module = _import_file(path)
        return _member(module, class_name, path) if class_name else module
    parts = name.split(".")
    if not all(part.isidentifier() for part in parts):
        raise NameNotFound(f"{name!r} is not a dotted Python name")
    if parts[0] == "Modelica":
        return _find_msl(name)
    # our package first: the repository's top-level ``library`` folder may be
    # importable too (from the repository root), a second copy of every class.
    # Each candidate: the name to import, and how many parts it puts before the name.
    if parts[0] == PACKAGE:
        candidates = [(name, 0)]
    else:
        candidates = [(f"{LIBRARY}.{name}", 2), (f"{PACKAGE}.{name}", 1), (name, 0)]
    failures: list[NameNotFound] = []
    for candidate, offset in candidates:
        if offset == 1 and len(parts) == 1:
            # a class as a package listing prints it, before acausal's own names
            found = _find_bare(name)
            if found is not None:
                return found
        try:
            return _import_dotted(candidate)
        except NameNotFound as error:
            error.depth -= offset  # counted in parts of the name as written
            failures.append(error)
    raise _not_found(name, failures)


def _find_bare(name: str) -> type | None:
    """The one library class called ``name``; an error naming each if packages share the name."""
    index = names()
    found = index.bare(name)
    if len(found) > 1:
        each = ", ".join(f"{index.short(k)}" + (f" ({msl_name(k)})" if msl_name(k) else "") for k in found)
        raise NameNotFound(f"{name} names {len(found)} classes: {each}",
                           "say which with its package, as in " + index.short(found[0]))
    return found[0] if found else None


def _import_dotted(name: str) -> object:
    """The object named ``a.b.C``: the longest importable module prefix, then its attributes."""
    parts = name.split(".")
    module: ModuleType | None = None
    imported = 0
    for count in range(len(parts), 0, -1):
        prefix = ".".join(parts[:count])
        try:
            spec = importlib.util.find_spec(prefix)
        except (ImportError, ValueError):  # a parent that is not a package
            spec = None
        if spec is not None:
            module = importlib.import_module(prefix)
            imported = count
            break
    if module is None:
        raise NameNotFound(f"no module named {parts[0]!r}")
    found: object = module
    for index in range(imported, len(parts)):
        part = parts[index]
        if not hasattr(found, part):
            error = NameNotFound(f"has nothing named {part!r}", depth=index)
            error.owner = found  # type: ignore[attr-defined]
            raise error
        found = getattr(found, part)
    return found


def _not_found(name: str, failures: Sequence[NameNotFound]) -> NameNotFound:
    """The error for a name nothing has: what is missing where, and close names of packages
    and classes.

    The deepest part of the name that the libraries have in the spelling the
    user chose (:func:`_form`) says where; an import that got further (a
    module of the user's own, an engine module) says more, and then its
    submodules and component classes are the candidates.
    """
    parts = name.split(".")
    index = names()
    spelled = index.in_form(_form(parts[0]))
    known = 0
    while known < len(parts) and ".".join(parts[:known + 1]) in spelled:
        known += 1
    deeper = [f for f in failures if f.depth > known and hasattr(f, "owner")]
    if deeper:
        failure = max(deeper, key=lambda f: f.depth)
        where = ".".join(parts[:failure.depth])
        hint = _did_you_mean(parts[failure.depth], _real_names(failure.owner),  # type: ignore[attr-defined]
                             prefix=f"{where}.")
        return NameNotFound(f"{where} has nothing named {parts[failure.depth]!r}", hint, failure.depth)
    if known == len(parts):  # the libraries have it, yet it did not import: say what they have
        return NameNotFound(f"{name} cannot be imported", "", known)
    where = ".".join(parts[:known])
    children = [s for s in spelled if s.count(".") == known and (not where or s.startswith(f"{where}."))]
    hint = _did_you_mean(parts[known], children, key=_last)
    if not hint:  # the right name in the wrong package: anything called alike, in its shortest spelling
        shortest: dict[int, str] = {}
        for spelling, obj in spelled.items():
            if "." in name and "." not in spelling:
                continue  # a dotted name is answered with dotted names: rotational.Clutch, not Clutch
            if id(obj) not in shortest or len(spelling) < len(shortest[id(obj)]):
                shortest[id(obj)] = spelling
        hint = _did_you_mean(parts[known], sorted(shortest.values()), key=_last)
    what = (f"{where} has nothing named {parts[known]!r}" if where
            else f"no package or class named {parts[known]!r}")
    return NameNotFound(what, hint, known)


def _last(spelling: str) -> str:
    return spelling.rsplit(".", 1)[-1]


def _form(first: str) -> str:
    """How a name is spelled, by its first part: from ``acausal``, ``library``, ``components``, or short."""
    return first if first in (PACKAGE, "library", "components") else "short"


def _real_names(owner: object) -> list[str]:
    """What a module offers that ``list``/``show`` can use: its submodules and component classes."""
    if not isinstance(owner, ModuleType):
        return []
    return sorted({*_public_submodules(owner), *(k.__name__ for k in component_classes(owner))})


def _find_msl(name: str) -> object:
    """A class or package named by its MSL name; an MSL package acausal has classes of lists them."""
    index = names()
    if name in index.msl:
        return index.msl[name]
    if name in index.msl_packages:
        return index.msl_packages[name]
    packages, classes = index.msl_children(name)
    if packages or classes:
        return _msl_package(name, classes)
    parts = name.split(".")
    known = 1
    while known < len(parts) and _msl_has(index, ".".join(parts[:known + 1])):
        known += 1
    where = ".".join(parts[:known])
    below, here = index.msl_children(where)
    hint = _did_you_mean(parts[known], [*below, *here], prefix=f"{where}.")
    if not hint:  # the right class in the wrong package
        hint = _did_you_mean(parts[-1], sorted(index.msl), key=_last)
    raise NameNotFound(f"{where} has nothing named {parts[known]!r} that acausal reproduces", hint, known)


def _msl_has(index: Names, prefix: str) -> bool:
    """Whether ``prefix`` is an MSL package acausal reproduces something of."""
    packages, classes = index.msl_children(prefix)
    return bool(packages or classes)


def _msl_package(name: str, classes: dict[str, type]) -> ModuleType:
    """A module standing for an MSL package: the classes acausal has of it, the library packages below it."""
    module = ModuleType(name, f"What acausal has of {name}.")
    for klass_name, klass in classes.items():
        setattr(module, klass_name, klass)
    module.__acausal_packages__ = [  # type: ignore[attr-defined]
        package.__name__ for msl, package in names().msl_packages.items() if msl.startswith(f"{name}.")]
    return module


def _import_file(filename: str) -> ModuleType:
    """A Python file imported as a module, its folder on ``sys.path`` (so it imports its neighbours)."""
    path = Path(filename)
    if not path.is_file():
        raise NameNotFound(f"no file {filename}")
    folder = str(path.resolve().parent)
    if folder not in sys.path:
        sys.path.insert(0, folder)
    module_name = "_acausal_catalog_" + re.sub(r"\W", "_", path.stem)
    spec = importlib.util.spec_from_file_location(module_name, path)
    if spec is None or spec.loader is None:
        raise NameNotFound(f"cannot import {filename}: not a Python file")
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module
    spec.loader.exec_module(module)
    return module


def _member(module: ModuleType, name: str, where: str) -> object:
    if not hasattr(module, name):
        raise NameNotFound(f"{where} defines nothing named {name!r}",
                           _did_you_mean(name, [k.__name__ for k in component_classes(module)],
                                         prefix=f"{where}:"))
    return getattr(module, name)


def _did_you_mean(name: str, candidates: Sequence[str], prefix: str = "", key=None) -> str:
    """``did you mean a, b?`` with up to three close candidates (compared by ``key``), or ''."""
    key = key or (lambda candidate: candidate)
    keyed: dict[str, list[str]] = {}
    for candidate in candidates:
        keyed.setdefault(key(candidate), []).append(candidate)
    close_keys = difflib.get_close_matches(key(name), list(keyed), n=3, cutoff=0.6)
    if not close_keys:  # a different case is a likely slip too
        close_keys = [k for k in keyed if k.lower() == key(name).lower()]
    close = [c for k in close_keys for c in keyed[k]][:4]
    return f"did you mean {', '.join(prefix + c for c in close)}?" if close else ""


# ---------------------------------------------------------------------------
# Listing a package
# ---------------------------------------------------------------------------


def _first_line(klass: type) -> str:
    text = own_docstring(klass)
    return text.splitlines()[0] if text else ""


def _module_summary(module: ModuleType) -> str:
    doc = inspect.getdoc(module) or ""
    return doc.splitlines()[0] if doc else ""


def _subpackages(module: ModuleType) -> list[tuple[str, str]]:
    """(name as ``acausal list`` accepts it, first docstring line) of a package's public subpackages."""
    named = getattr(module, "__acausal_packages__", None)
    if named is not None:  # an MSL package: the library packages that reproduce its parts
        return [(name.rsplit(".", 1)[-1], _module_summary(importlib.import_module(name))) for name in named]
    if not hasattr(module, "__path__"):
        return []
    found = []
    for info in pkgutil.iter_modules(module.__path__):
        if info.name.startswith("_") or not info.ispkg:
            continue
        sub = importlib.import_module(f"{module.__name__}.{info.name}")
        found.append((info.name, _module_summary(sub)))
    return found


def listing(module: ModuleType) -> str:
    """The text ``acausal list`` prints: subpackages, then classes by kind, with their summary line."""
    lines: list[str] = []
    packages = _subpackages(module)
    if packages:
        width = max(len(name) for name, _ in packages)
        lines += ["Packages"] + [f"  {name.ljust(width)}  {doc}".rstrip() for name, doc in packages]
    classes = component_classes(module)
    groups = (("Models", [c for c in classes if issubclass(c, Component) and _is_model(c)]),
              ("Components", [c for c in classes if issubclass(c, Component) and not _is_model(c)]),
              ("Connectors", [c for c in classes if issubclass(c, Connector)]))
    for title, members in groups:
        if not members:
            continue
        width = max(len(c.__name__) for c in members)
        lines += ([""] if lines else []) + [title]
        lines += [f"  {c.__name__.ljust(width)}  {_first_line(c)}".rstrip() for c in members]
    return "\n".join(lines)


def _is_model(klass: type) -> bool:
    from ..language import Model

    return issubclass(klass, Model)


# ---------------------------------------------------------------------------
# The commands
# ---------------------------------------------------------------------------

_NAME_HELP = ("a package or class as acausal list prints it (blocks, Gain), dotted (blocks.Gain), "
              "its module path (acausal.library.blocks.Gain), its Modelica name "
              "(Modelica.Blocks.Math.Gain), or FILE.py[:Class]")


def _parse(parser: argparse.ArgumentParser, argv: Sequence[str]) -> argparse.Namespace | int:
    """The parsed arguments, or the exit status argparse chose (2 for a usage error, 0 for --help)."""
    try:
        return parser.parse_args(list(argv))
    except SystemExit as exit_:
        return int(exit_.code or 0)


def _parse_and_find(command: str, parser: argparse.ArgumentParser, argv: Sequence[str]):
    """``(args, the object args.name names)``, or the exit status when there is none
    (argparse's for a usage error or --help, 2 for a name that names nothing)."""
    args = _parse(parser, argv)
    if isinstance(args, int):
        return args
    try:
        return args, find_object(args.name)
    except NameNotFound as error:
        hint = f"; {error.hint}" if error.hint else ""
        print(f"acausal {command}: {error}{hint}", file=sys.stderr)
        return 2


def main_show(argv: list[str]) -> int:
    """``acausal show NAME``: print the declaration table of a component or connector class.

    Parameters
    ----------
    argv : list of str
        The arguments after ``show``: the class's name (``Gain``,
        ``blocks.Gain``, ``acausal.library.blocks.Gain``,
        ``Modelica.Blocks.Math.Gain`` or ``FILE.py:Class``) and ``--width``.

    Returns
    -------
    int
        0, or 2 when the name names no component class.
    """
    parser = argparse.ArgumentParser(
        prog="acausal show",
        description="Print the parameters, connectors and variables of a component class "
                    "(defaults, units, limits, descriptions) and the sub-components of a model.")
    parser.add_argument("name", help=_NAME_HELP)
    parser.add_argument("--width", type=int, default=100, help="line width (default 100)")
    parsed = _parse_and_find("show", parser, argv)
    if isinstance(parsed, int):
        return parsed
    args, found = parsed
    if isinstance(found, ModuleType):
        classes = component_classes(found)
        if args.name.endswith(".py") and len(classes) == 1:
            found = classes[0]
        else:
            names_ = ", ".join(c.__name__ for c in classes[:8]) + (", ..." if len(classes) > 8 else "")
            hint = f"; it has {names_}" if classes else ""
            print(f"acausal show: {args.name} is a module, not a component class{hint} "
                  f"(acausal list {args.name} lists them)", file=sys.stderr)
            return 2
    if not _is_described(found):
        print(f"acausal show: {args.name} is a {type(found).__name__}, not a component class",
              file=sys.stderr)
        return 2
    print(describe(found, width=args.width), end="")
    return 0


def main_list(argv: list[str]) -> int:
    """``acausal list PACKAGE``: the component classes of a package with their summary line.

    Parameters
    ----------
    argv : list of str
        The arguments after ``list``: a package or module (``blocks``,
        ``library.blocks``, ``acausal.library.blocks``, ``Modelica.Blocks``,
        ``FILE.py``); none lists the library packages.

    Returns
    -------
    int
        0, or 2 when the name names no module.
    """
    parser = argparse.ArgumentParser(
        prog="acausal list",
        description="List the component classes of a package or file with the first line of their docstring.")
    parser.add_argument("name", nargs="?", default="library",
                        help="a package as acausal list prints it (blocks), library.blocks, "
                             "acausal.library.blocks, Modelica.Blocks or FILE.py (default: the library "
                             "packages)")
    parsed = _parse_and_find("list", parser, argv)
    if isinstance(parsed, int):
        return parsed
    args, found = parsed
    if not isinstance(found, ModuleType):
        what = "a component class" if _is_described(found) else f"a {type(found).__name__}"
        print(f"acausal list: {args.name} is {what}, not a module"
              + (f" (acausal show {args.name} describes it)" if _is_described(found) else ""),
              file=sys.stderr)
        return 2
    text = listing(found)
    print(text if text else f"{args.name}: no component classes")
    return 0
