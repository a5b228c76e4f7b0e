"""``acausal show`` and ``acausal list``: what the libraries offer, from the command line.

::

    acausal show library.rotational.Clutch        # parameters, connectors, variables
    acausal show acausal.library.rotational.Clutch
    acausal show examples/coupled_clutches.py:CoupledClutches
    acausal list library.rotational                # the classes of a package

A name is a dotted Python name; the bundled libraries install inside the
``acausal`` package (``acausal.library.*``, ``acausal.components.*``), so
the ``acausal.`` prefix may be left out.  ``FILE.py:Class`` names a class
of a Python file, ``FILE.py`` alone the file's only component class.

Both functions return the exit status: 0 on success, 2 for a name that
names nothing (the message suggests close names).
"""

from __future__ import annotations

import argparse
import difflib
import importlib
import importlib.util
import inspect
import pkgutil
import re
import sys
from pathlib import Path
from types import ModuleType
from typing import Sequence

from ..language import Component, Connector, describe, own_docstring

__all__ = ["main_show", "main_list", "find_object", "component_classes", "NameNotFound"]

#: The package the libraries are installed in; a name may leave it out.
PACKAGE = "acausal"


class NameNotFound(LookupError):
    """A name that names no module, class or file; ``hint`` suggests close names."""

    def __init__(self, message: str, hint: str = "", depth: int = 0) -> None:
        super().__init__(message)
        self.hint = hint
        #: how many parts of a dotted name were found before this one failed
        self.depth = depth


# ---------------------------------------------------------------------------
# Finding what a name names
# ---------------------------------------------------------------------------


def find_object(name: str) -> object:
    """The module or class named by a dotted name or ``FILE.py[:Class]``.

    Parameters
    ----------
    name : str
        ``library.blocks.Gain``, ``acausal.library.blocks.Gain``,
        ``library.blocks``, ``models.py:MyModel`` or ``models.py``.

    Raises
    ------
    NameNotFound
        If nothing has that name; its hint lists close names.
    """
    path, _, class_name = name.partition(":")
    if path.endswith(".py") or class_name:
        module = _import_file(path)
        return _member(module, class_name, path) if class_name else module
    # our package first: the repository's top-level ``library`` folder may be
    # importable too (from the repository root), a second copy of every class
    candidates = [name] if name == PACKAGE or name.startswith(f"{PACKAGE}.") else [f"{PACKAGE}.{name}", name]
    errors: list[NameNotFound] = []
    for candidate in candidates:
        try:
            return _import_dotted(candidate)
        except NameNotFound as error:
            errors.append(error)
    # the attempt that got furthest names what is missing best (ours on a tie)
    error = max(errors, key=lambda error: error.depth)
    if error is errors[0] and len(errors) > 1:  # spoken of as the user wrote it: without our prefix
        error = NameNotFound(_without_prefix(str(error)), _without_prefix(error.hint), error.depth)
    raise error


def _without_prefix(text: str) -> str:
    return re.sub(rf"(?<![\w.]){PACKAGE}\.", "", text)


def _import_dotted(name: str) -> object:
    """The object named ``a.b.C``: the longest importable module prefix, then its attributes."""
    parts = name.split(".")
    if not all(part.isidentifier() for part in parts):
        raise NameNotFound(f"{name!r} is not a dotted Python name")
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
        raise NameNotFound(f"no module named {parts[0]!r}", _did_you_mean(parts[0], _top_names()))
    found: object = module
    for index in range(imported, len(parts)):
        part = parts[index]
        if not hasattr(found, part):
            where = ".".join(parts[:index])
            raise NameNotFound(f"{where} has nothing named {part!r}",
                               _did_you_mean(part, _public_names(found), prefix=f"{where}."), depth=index)
        found = getattr(found, part)
    return found


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
                           _did_you_mean(name, _public_names(module), prefix=f"{where}:"))
    return getattr(module, name)


def _public_names(owner: object) -> list[str]:
    """The names a module or package offers: its attributes and, for a package, its submodules."""
    names = [name for name in dir(owner) if not name.startswith("_")]
    if hasattr(owner, "__path__"):
        names += [info.name for info in pkgutil.iter_modules(owner.__path__) if not info.name.startswith("_")]
    return sorted(set(names))


def _top_names() -> list[str]:
    """Names that may start a dotted name: our subpackages (``library``) and ``acausal`` itself."""
    package = importlib.import_module(PACKAGE)
    return [PACKAGE] + [info.name for info in pkgutil.iter_modules(package.__path__)]


def _did_you_mean(name: str, candidates: Sequence[str], prefix: str = "") -> str:
    close = difflib.get_close_matches(name, list(candidates), n=3, cutoff=0.6)
    if not close:  # a different case is a likely slip too
        close = [c for c in candidates if c.lower() == name.lower()]
    return f"did you mean {', '.join(prefix + c for c in close)}?" if close else ""


# ---------------------------------------------------------------------------
# Listing a package
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


def _first_line(klass: type) -> str:
    text = own_docstring(klass)
    return text.splitlines()[0] if text else ""


def _subpackages(module: ModuleType) -> list[tuple[str, str]]:
    """(name, first docstring line) of a package's public submodules."""
    if not hasattr(module, "__path__"):
        return []
    found = []
    for info in pkgutil.iter_modules(module.__path__):
        if info.name.startswith("_") or not info.ispkg:
            continue
        sub = importlib.import_module(f"{module.__name__}.{info.name}")
        doc = inspect.getdoc(sub) or ""
        found.append((info.name, doc.splitlines()[0] if doc else ""))
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
        The arguments after ``show``: the class's name (``library.blocks.Gain``,
        ``acausal.library.blocks.Gain`` or ``FILE.py:Class``) and ``--width``.

    Returns
    -------
    int
        0, or 2 when the name names no component class.
    """
    parser = argparse.ArgumentParser(
        prog="acausal show",
        description="Print the parameters, connectors and variables of a component class "
                    "(defaults, units, limits, descriptions) and the sub-components of a model.")
    parser.add_argument("name", help="library.blocks.Gain, acausal.library.blocks.Gain or FILE.py:Class")
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
            names = ", ".join(c.__name__ for c in classes[:8]) + (", ..." if len(classes) > 8 else "")
            hint = f"; it has {names}" if classes else ""
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
        The arguments after ``list``: a package or module (``library.blocks``,
        ``acausal.library.blocks``, ``FILE.py``); none lists ``library``.

    Returns
    -------
    int
        0, or 2 when the name names no module.
    """
    parser = argparse.ArgumentParser(
        prog="acausal list",
        description="List the component classes of a package or file with the first line of their docstring.")
    parser.add_argument("name", nargs="?", default="library",
                        help="library.blocks, acausal.library.blocks or FILE.py (default: library)")
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
