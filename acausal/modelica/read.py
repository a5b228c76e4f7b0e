"""Reading Modelica text: a model's source becomes an acausal model class.

``load(path_or_text, name=None)`` parses the text with pymoca's Modelica
parser, finds the class asked for, and makes a Python class of it:

* a component whose class is in acausal's library (every library class
  declares its Modelica name) becomes that library class with the
  modifiers given (``Modelica.Mechanics.Rotational.Components.Inertia
  inertia1(J=2, w(start=1, fixed=true))`` is ``Inertia(J=2, w=dict(start=1,
  fixed=True))``);
* a class the text defines itself (a model, block or connector) is made
  from its declarations and equations, so a user's own component works;
  so is a class of a package on ``MODELICAPATH`` that acausal's library
  lacks (an example's utilities, ``Examples.OpAmps.OpAmpCircuits.Add``, or
  a parameter record such as ``Machines.Utilities.ParameterRecords.
  DcPermanentMagnetData``), read from its source when a name needs it;
* a record given whole as a modifier (``frictionParameters=
  dcpmData.frictionParameters``) binds each of its parameters (MLS 7.2.3),
  and a record given to a Modelica function passes its fields' values;
* a modifier may read the component it modifies (``vIn(rising=0.2/f,
  startTime=-(vIn.rising + vIn.width/2))``): the modification is read in
  the enclosing class, ``vIn.rising`` being the value it gives ``rising``
  (MLS 7.2);
* a connector takes no modifier in acausal; one that only restates its
  variables' own attributes (``out(i(start=0, fixed=false))``) is left out;
* parameters and variables of the built-in types (``Real``, ``Integer``,
  ``Boolean``, ``SI.Torque`` and the other types of ``Modelica.Units``)
  become declarations with their attributes, ``connect`` statements become
  ``connect``, equations (``der``, ``pre``, if, when, for, reinit, assert,
  terminate) become acausal's, and ``annotation(experiment(...))`` the
  ``Experiment`` (``annotation(__acausal(modelicaClass="..."))``, which
  :func:`acausal.modelica.dump` writes, the ``modelica_class``);
* Integer, Boolean and String parameters are structural (used by value
  while translating), Real ones tunable, unless the declaration's
  ``annotation(Evaluate=...)`` says otherwise (MLS 18.3); a parameter an
  equation passes to a Modelica function is structural too, since the
  function is evaluated when the model is read (``(b, a) = f(T, n)``, MLS
  8.3.1, gives each name on the left its output);
* array sizes are numbers, structural parameters or expressions of them
  (``Real a[n + 1]``); the attributes of an array a library class declares
  element by element (``y(start={0, 1})``) are given element by element.

Names are looked up as Modelica 3.6, section 5.3 says: the class's own
imports, then the enclosing classes from the innermost outwards (so
``Rotational.Components.Inertia`` inside
``Modelica.Mechanics.Rotational.Examples`` is
``Modelica.Mechanics.Rotational.Components.Inertia``).  The types of
``Modelica.Units`` come from ``Modelica/Units.mo`` on ``MODELICAPATH`` when
it is there (a name without it is a Real without unit).  ``Modelica.Icons``
classes carry no content: extending one adds nothing.

References
----------
Modelica Language Specification 3.6: chapter 4 (classes, declarations,
``within``), chapter 5 (scoping and name lookup), chapter 7 (``extends``
and modifications), chapter 8 (equations), chapter 9 (``connect``).
"""

from __future__ import annotations

import base64
import enum
import functools
import hashlib
import os
import pickle
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterable

import sympy as sp

from ..errors import ModelicaError, ModelicaSyntaxError
from ..language import (Boolean, Component, Connector, Eq, Experiment, Flow, Integer, Model, Parameter, Potential,
                        RealInput, RealOutput, Variable)
from .functions import FunctionScope, call_function

__all__ = ["load", "parse", "ModelicaSource", "modelica_path"]

#: The signal connectors of Modelica.Blocks.Interfaces: a model's own inputs and outputs.
_SIGNAL_CONNECTORS = {f"Modelica.Blocks.Interfaces.{kind}{way}": (kind, way.lower())
                      for kind in ("Real", "Boolean", "Integer") for way in ("Input", "Output")}

#: The classes pymoca puts into every tree (the built-in types).
_BUILTIN_CLASSES = frozenset({"Real", "Integer", "Boolean", "String", "StateSelect", "Clock"})

#: Modelica.Constants, as MSL 4.1 defines them (mathematical and machine constants).
_CONSTANTS = {
    "pi": float(sp.pi), "e": float(sp.E), "D2R": float(sp.pi / 180), "R2D": float(180 / sp.pi),
    "gamma": 0.57721566490153286061, "eps": 2.220446049250313e-16, "small": 2.2250738585072014e-308,
    "inf": 1e60, "Integer_inf": 2147483647, "g_n": 9.80665, "G": 6.67430e-11, "q": 1.602176634e-19,
    "F": 9.648533212331002e4, "h": 6.62607015e-34, "k": 1.380649e-23, "R": 8.31446261815324,
    "sigma": 5.670374419184429e-8, "N_A": 6.02214076e23, "mu_0": 1.25663706212e-6,
    "epsilon_0": 8.8541878128e-12, "T_zero": -273.15, "c": 299792458.0,
}


# ---------------------------------------------------------------------------
# Parsing
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class ModelicaSource:
    """Modelica text and where it came from (a file, or ``<text>``).

    Attributes
    ----------
    text : str
    origin : str
        The file's path, or ``"<text>"``.
    tree : pymoca.ast.Tree
        The parsed classes (``tree.classes``; ``within`` puts them inside
        their packages).
    """

    text: str
    origin: str
    tree: Any = field(repr=False, compare=False)

    def line_of(self, *words: str) -> int | None:
        """The first line (from 1) that has all of ``words`` as whole words, for messages
        (pymoca's tree keeps no positions)."""
        patterns = [re.compile(rf"(?<![\w.]){re.escape(w)}(?!\w)") for w in words if w]
        for number, line in enumerate(self.text.splitlines(), start=1):
            if all(p.search(line) for p in patterns):
                return number
        return None

    def where(self, *words: str) -> str:
        """``file:line`` of the first line that names ``words`` (``file`` alone if none does)."""
        line = self.line_of(*words)
        return f"{self.origin}:{line}" if line else self.origin


def _pymoca_parser():
    try:
        from pymoca import parser
    except ImportError as exc:  # an optional dependency
        raise ModelicaError("reading Modelica text needs the pymoca parser",
                            hint="pip install acausal[modelica] (or pip install pymoca)") from exc
    return parser


@functools.lru_cache(maxsize=64)
def _parsed(text: str):
    """pymoca's tree of ``text``: parsed once per text and process, and kept in acausal's
    disk cache like a compiled system (authenticated, and keyed by acausal's sources, so a
    tree made before a change of the parser's repairs is never read)."""
    parser = _pymoca_parser()
    cache = _parse_cache(text)
    if cache is not None:
        payload = cache.load("tree")
        if payload is not None:
            try:
                return pickle.loads(base64.b64decode(payload["pickle"]))  # noqa: S301 - an authenticated entry
            except Exception:  # noqa: BLE001 - an entry another pymoca wrote: parse again
                pass
    # pymoca's own cache is bypassed: its entries are neither authenticated nor aware of the repairs
    tree = parser.parse(text, bypass_cache=True)
    if cache is not None:
        cache.store("tree", {"pickle": base64.b64encode(pickle.dumps(tree)).decode("ascii")})
    return tree


def _parse_cache(text: str):
    """The disk cache entry of a parse of ``text``, or None when the disk cache is off."""
    from ..compiler.diskcache import DiskCache, cache_folder, disk_cache_enabled

    if not disk_cache_enabled():
        return None
    import pymoca

    key = hashlib.sha256(f"modelica parse, pymoca {pymoca.__version__}\n{text}".encode()).hexdigest()
    return DiskCache(cache_folder(), key)


def parse(source: str | os.PathLike, origin: str | None = None) -> ModelicaSource:
    """Parse Modelica text (or the file ``source`` names).

    Raises
    ------
    ModelicaSyntaxError
        With the file, line and column, and what the parser expected.
    """
    text, origin = _text_of(source, origin)
    try:
        tree = _parsed(text)
    except ModelicaError:
        raise
    except Exception as exc:  # pymoca reports a syntax error as its own exception or a ValueError
        message = str(exc).strip() or type(exc).__name__
        found = re.search(r"line (\d+)(?::(\d+))?", message)
        where = f"{origin}:{found.group(1)}" + (f":{found.group(2)}" if found and found.group(2) else "") \
            if found else origin
        raise ModelicaSyntaxError(f"{where}: {message.replace('(input, ', '(')}",
                                  hint="check the statement before this position (a missing ';' or 'end')") \
            from None
    return ModelicaSource(text, origin, tree)


def _text_of(source: str | os.PathLike, origin: str | None) -> tuple[str, str]:
    if isinstance(source, os.PathLike) or (isinstance(source, str) and "\n" not in source
                                            and source.strip().endswith(".mo")):
        path = Path(source)
        if not path.is_file():
            raise ModelicaError(f"no Modelica file {path}", hint="give the path of a .mo file, or its text")
        return path.read_text(encoding="utf-8"), origin or str(path)
    return str(source), origin or "<text>"


# ---------------------------------------------------------------------------
# MODELICAPATH: the packages' sources (the types of Modelica.Units)
# ---------------------------------------------------------------------------


def modelica_path() -> list[Path]:
    """The folders of ``MODELICAPATH`` (separated by the platform's path separator)."""
    return [Path(p) for p in os.environ.get("MODELICAPATH", "").split(os.pathsep) if p]


def _package_file(dotted: str) -> Path | None:
    """The file that defines the top-level-rooted class ``dotted`` on MODELICAPATH
    (``Modelica.Units`` -> ``Modelica/Units.mo``, or ``Modelica/Units/package.mo``)."""
    parts = dotted.split(".")
    for root in modelica_path():
        for k in range(len(parts), 0, -1):
            folder = root.joinpath(*parts[:k])
            if (folder / "package.mo").is_file():
                return folder / "package.mo"
            single = root.joinpath(*parts[:k - 1], parts[k - 1] + ".mo")
            if single.is_file():
                return single
    return None


def _path_key() -> tuple[str, ...]:
    return tuple(str(p) for p in modelica_path())


@functools.lru_cache(maxsize=512)
def _class_on_path(full: str, key: tuple[str, ...]) -> Any:
    """The class ``full`` as a package on MODELICAPATH defines it (pymoca's tree), or None
    (``key``: the path, so a changed MODELICAPATH reads again)."""
    path = _package_file(full)
    if path is None:
        return None
    node = parse(path).tree
    for part in full.split("."):
        node = node.classes.get(part) if node is not None else None
    return node


@functools.lru_cache(maxsize=8)
def _units_types(key: tuple[str, ...]) -> dict[str, dict[str, Any]]:
    """``{"Modelica.Units.SI.Torque": {"unit": "N.m", ...}}`` from ``Modelica/Units.mo`` on
    MODELICAPATH (``key``: the path, so a changed MODELICAPATH reads again); empty without it."""
    path = _package_file("Modelica.Units")
    if path is None:
        return {}
    tree = parse(path).tree
    units = tree.classes.get("Modelica").classes.get("Units") if "Modelica" in tree.classes else None
    found: dict[str, dict[str, Any]] = {}
    if units is None:
        return found

    def visit(node, prefix: str) -> None:
        for name, child in node.classes.items():
            full = f"{prefix}.{name}"
            if child.type == "type" and child.extends:
                base = child.extends[0]
                found[full] = {"base": _ref_text(base.component),
                               **_literal_attributes(base.class_modification)}
            elif child.type == "package":
                visit(child, full)

    visit(units, "Modelica.Units")
    return found


@functools.lru_cache(maxsize=256)
def _package_imports(package: str, key: tuple[str, ...]) -> dict:
    """The imports the package ``package`` declares in its ``package.mo`` on MODELICAPATH
    (``Modelica.Mechanics`` imports ``Modelica.Units.SI``); an MSL package found nowhere
    imports ``SI = Modelica.Units.SI``, as every MSL package does."""
    path = _package_file(package)
    if path is not None and path.name == "package.mo" and path.parent.name == package.rpartition(".")[2]:
        tree = parse(path).tree
        node = tree
        for part in package.split("."):
            node = node.classes.get(part) if node is not None else None
        if node is not None:
            return dict(node.imports)
    if package.startswith("Modelica."):
        return {"SI": _Alias("Modelica.Units.SI")}
    return {}


class _Alias:
    """An import ``alias = target`` made up for an MSL package found nowhere."""

    def __init__(self, target: str) -> None:
        self.components = [target]


def _literal_attributes(modification) -> dict[str, Any]:
    """The attributes a type declaration gives as literals (unit, quantity, displayUnit, min, ...)."""
    out = {}
    for argument in getattr(modification, "arguments", []) or []:
        value = getattr(argument, "value", None)
        component = getattr(value, "component", None)
        modifications = getattr(value, "modifications", None) or []
        if component is None or not modifications:
            continue
        literal = getattr(modifications[-1], "value", None)
        if literal is not None and not hasattr(modifications[-1], "arguments"):
            out[component.name] = literal
    return out


def _ref_text(ref) -> str:
    """``a.b.c`` of a pymoca ComponentRef (subscripts left out)."""
    if isinstance(ref, str):
        return ref
    parts = []
    while ref is not None:
        parts.append(ref.name)
        ref = ref.child[0] if getattr(ref, "child", None) else None
    return ".".join(parts)


# ---------------------------------------------------------------------------
# What a name names
# ---------------------------------------------------------------------------


@functools.lru_cache(maxsize=1)
def _library_index() -> tuple[dict[str, type], dict[str, type]]:
    """Modelica name -> acausal class, and Modelica type name -> enumeration, of acausal's
    libraries (each class declares its Modelica name)."""
    from ..tools.catalog import names

    classes = dict(names().msl)
    enumerations: dict[str, type] = {}
    for module in names().modules.values():
        for value in vars(module).values():
            if isinstance(value, type) and issubclass(value, enum.Enum):
                modelica = getattr(value, "modelica_name", None) or _enum_modelica_name(value)
                if modelica:
                    enumerations.setdefault(modelica, value)
        for modelica, value in (getattr(module, "MODELICA_TYPES", None) or {}).items():
            enumerations.setdefault(modelica, value)
    from ..interpolation import Extrapolation, Smoothness, TimeEvents
    from ..language import StateSelect

    enumerations.setdefault("StateSelect", StateSelect)
    for klass in (Smoothness, Extrapolation, TimeEvents):
        enumerations.setdefault(f"Modelica.Blocks.Types.{klass.__name__}", klass)
    return classes, enumerations


def _enum_modelica_name(klass: type) -> str | None:
    found = re.search(r"\((Modelica(?:\.\w+)+)\)", (klass.__doc__ or "").split("\n\n")[0])
    return found.group(1) if found else None


@dataclass(frozen=True)
class Resolved:
    """What a class name names.

    kind : {'library', 'file', 'type', 'builtin', 'icon', 'enumeration'}
    full : str
        The full Modelica name.
    target : object
        The acausal class, the pymoca class, the type's attributes, the
        built-in's name or the enumeration.
    """

    kind: str
    full: str
    target: Any


class Scope:
    """Name lookup over the classes of one source, acausal's library and MODELICAPATH.

    Parameters
    ----------
    source : ModelicaSource
    """

    def __init__(self, source: ModelicaSource) -> None:
        self.source = source
        self.file_classes: dict[str, Any] = {}
        for name, node in source.tree.classes.items():
            if name not in _BUILTIN_CLASSES:
                self._index(node, name)
        # classes of the packages on MODELICAPATH the library lacks, read from their sources when a
        # name needs them (an example's utilities: Examples.OpAmps.OpAmpCircuits.Add)
        self.path_classes: dict[str, Any] = {}
        self.library, self.enumerations = _library_index()
        self.units = _units_types(tuple(str(p) for p in modelica_path()))
        self._prefixes = self._known_prefixes()

    def _index(self, node, full: str) -> None:
        self.file_classes[full] = node
        for name, child in node.classes.items():
            self._index(child, f"{full}.{name}")

    def _known_prefixes(self) -> set[str]:
        found = set()
        for name in [*self.library, *self.units, *self.enumerations, *self.file_classes]:
            parts = name.split(".")
            found.update(".".join(parts[:k]) for k in range(1, len(parts) + 1))
        found.update({"Modelica", "Modelica.Constants", "Modelica.Icons", "Modelica.Units", "Modelica.Units.SI",
                      "Modelica.Math", "Modelica.Blocks.Types"})
        return found

    def exists(self, full: str) -> bool:
        return full in self._prefixes or full.startswith(("Modelica.Icons.", "Modelica.Constants.",
                                                          "Modelica.Math.")) or self.on_path(full) is not None

    def node(self, full: str) -> Any:
        """The class ``full`` as the source or a package on MODELICAPATH defines it (pymoca's tree), or None."""
        return self.file_classes.get(full) or self.path_classes.get(full)

    def on_path(self, full: str) -> Any:
        """The class ``full`` a package on MODELICAPATH defines (pymoca's tree), or None; its
        classes are then known to :meth:`node`."""
        if full in self.path_classes:
            return self.path_classes[full]
        if not modelica_path():
            return None
        node = _class_on_path(full, _path_key())
        if node is not None:
            self.path_classes[full] = node
        return node

    def full_name(self, name: str, enclosing: str) -> str | None:
        """The full name of ``name`` used inside the class ``enclosing`` (§5.3), or None."""
        if name in _BUILTIN_CLASSES or name == "time":
            return name
        first, _, rest = name.partition(".")
        parts = enclosing.split(".") if enclosing else []
        # the imports of the class and of its enclosing classes, innermost first (an
        # enclosing package the file does not define is read from MODELICAPATH)
        for k in range(len(parts), 0, -1):
            prefix = ".".join(parts[:k])
            node = self.node(prefix)
            imports = getattr(node, "imports", None) or {}
            if node is None or (not imports and not node.symbols and not node.equations):
                imports = _package_imports(prefix, tuple(str(p) for p in modelica_path())) or imports
            for alias, clause in imports.items():
                target = _import_target(clause)
                if target is None:
                    continue
                if alias == first:
                    return target + (f".{rest}" if rest else "")
                if alias == "*" or getattr(clause, "unqualified", False):
                    candidate = f"{target}.{first}"
                    if self.exists(candidate):
                        return candidate + (f".{rest}" if rest else "")
        for k in range(len(parts), -1, -1):
            candidate = ".".join([*parts[:k], first])
            if self.exists(candidate):
                return candidate + (f".{rest}" if rest else "")
        return None

    def resolve(self, name: str, enclosing: str, what: str = "class") -> Resolved:
        """The class ``name`` (used in ``enclosing``) names.

        Raises
        ------
        ModelicaError
            For a name nothing defines (with the close names), and for a
            Modelica Standard Library class acausal's library lacks.
        """
        if name in ("Real", "Integer", "Boolean", "String"):
            return Resolved("builtin", name, name)
        full = self.full_name(name, enclosing)
        if full is None:
            raise self._undefined(name, enclosing, what)
        if full in self.file_classes:
            node = self.file_classes[full]
            if node.type == "type" and node.extends:
                return self._type(full, node)
            return Resolved("file", full, node)
        if full in _SIGNAL_CONNECTORS:  # RealInput u[3]: a signal, declared as a variable
            base, causality = _SIGNAL_CONNECTORS[full]
            return Resolved("type", full, {"base": base, "causality": causality})
        if full in self.library:
            return Resolved("library", full, self.library[full])
        if full in self.enumerations:
            return Resolved("enumeration", full, self.enumerations[full])
        if full in self.units:
            return self._unit_type(full)
        if full.startswith("Modelica.Icons."):
            return Resolved("icon", full, None)
        if full.startswith("Modelica.Units."):  # no Units.mo on MODELICAPATH: a Real without unit
            return Resolved("type", full, {"base": "Real"})
        node = self.on_path(full)
        if node is not None and node.type == "type" and node.extends:
            return self._type(full, node)
        if node is not None and node.type in ("model", "block", "class", "record", "connector"):
            return Resolved("file", full, node)  # made from its source, as a class of the file
        if full.startswith(("Modelica.", "ModelicaTest.")):
            raise ModelicaError(f"{self.source.where(name.split('.')[-1])}: {full} is not in acausal's library yet",
                                hint="write the component in Python (see docs/tutorial.md, section 1), or "
                                     "define it in the Modelica file itself")
        raise self._undefined(name, enclosing, what)

    def _type(self, full: str, node) -> Resolved:
        base = node.extends[0]
        attributes = _literal_attributes(base.class_modification)
        enclosing = full.rpartition(".")[0]
        inner = self.resolve(_ref_text(base.component), enclosing, "type")
        merged = {**(inner.target if isinstance(inner.target, dict) else {"base": inner.target}), **attributes}
        return Resolved("type", full, merged)

    def _unit_type(self, full: str) -> Resolved:
        attributes = dict(self.units[full])
        seen = {full}
        while attributes.get("base") not in ("Real", "Integer", "Boolean", "String", None):
            base = attributes.pop("base")
            candidate = self.full_name(base, full.rpartition(".")[0]) or base
            if candidate in seen or candidate not in self.units:
                attributes["base"] = "Real"
                break
            seen.add(candidate)
            attributes = {**self.units[candidate], **{k: v for k, v in attributes.items() if k != "base"}}
        return Resolved("type", full, attributes)

    def _undefined(self, name: str, enclosing: str, what: str) -> ModelicaError:
        import difflib

        first = name.split(".")[0]
        visible = set()
        parts = enclosing.split(".") if enclosing else []
        for k in range(len(parts), -1, -1):
            prefix = ".".join(parts[:k])
            visible.update(n[len(prefix) + 1:].split(".")[0] if prefix else n.split(".")[0]
                           for n in self.file_classes if not prefix or n.startswith(prefix + "."))
        close = difflib.get_close_matches(first, sorted(visible - {""}), n=3)
        return ModelicaError(f"{self.source.where(first)}: undefined {what} name {name!r} in {enclosing or 'the file'}",
                             hint=(f"did you mean {', '.join(close)}?" if close else
                                   "import it, give its full name, or put the Modelica Standard Library on "
                                   "MODELICAPATH"))


def _import_target(clause) -> str | None:
    components = getattr(clause, "components", None)
    if components:
        return _ref_text(components[0])
    if hasattr(clause, "name"):
        return _ref_text(clause)
    return None


# ---------------------------------------------------------------------------
# Making acausal classes of Modelica classes
# ---------------------------------------------------------------------------


_KINDS = {"Real": Variable, "Integer": Integer, "Boolean": Boolean}


def _expressions():
    from . import expressions as module  # noqa: PLC0415 - the module, not the package

    return module


_PREFIX_WORDS = ("flow", "stream", "discrete", "parameter", "constant", "input", "output")


def _prefixes(symbol) -> set[str]:
    """The type prefixes of a declaration (pymoca joins ``discrete output`` into one word:
    the words are found inside)."""
    found = set()
    for prefix in getattr(symbol, "prefixes", None) or ():
        found.update(word for word in _PREFIX_WORDS if word in prefix)
    return found


def _modifications(modification) -> list[tuple[str, list]]:
    """``[(dotted element name, [ClassModification | value expression, ...]), ...]`` of a class
    modification, in order."""
    out = []
    for argument in getattr(modification, "arguments", None) or []:
        value = getattr(argument, "value", None)
        if getattr(argument, "redeclare", False):
            if _redeclared_type(argument) is not None:
                continue  # redeclare type T = ...: see _redeclared_types
            raise ModelicaError("redeclare of a component or a class is not supported",
                                hint="give the component's class directly (redeclare of a simple type, "
                                     "redeclare type T = Real(...), is)")
        component = getattr(value, "component", None)
        if component is None:  # a component clause or a short class definition in a modification
            raise ModelicaError(f"modification {type(value).__name__} is not supported")
        out.append((_ref_text(component), list(getattr(value, "modifications", None) or [])))
    return out


def _redeclared_type(argument) -> Any:
    """The short class definition of ``redeclare type T = Real(...)`` in a modification, or None."""
    value = getattr(argument, "value", None)
    if type(value).__name__ == "ShortClassDefinition" and getattr(value, "type", "") == "type":
        return value
    return None


def _redeclared_types(modification) -> dict[str, Any]:
    """``{T: definition}`` of the simple types a modification redeclares (MLS 7.3)."""
    found = {}
    for argument in getattr(modification, "arguments", None) or []:
        definition = _redeclared_type(argument) if getattr(argument, "redeclare", False) else None
        if definition is not None:
            found[definition.name] = definition
    return found


def _is_modification(item) -> bool:
    return type(item).__name__ == "ClassModification"


def _dimensions(symbol) -> list:
    """The declared array dimensions of a symbol (empty for a scalar)."""
    dims = getattr(symbol, "dimensions", None) or [[None]]
    flat = [d for group in dims for d in group]
    if all(getattr(d, "value", None) is None and not hasattr(d, "operator") and not hasattr(d, "name")
           for d in flat):
        return []
    return flat


@dataclass
class _ClassPlan:
    """What one Modelica class becomes: declarations, sub-components, connects, equations."""

    full: str
    node: Any
    declarations: dict[str, Any] = field(default_factory=dict)
    derived: dict[str, Any] = field(default_factory=dict)        # parameter -> binding expression
    components: list[tuple[str, Resolved, Any, list]] = field(default_factory=list)  # name, class, symbol, dims
    types: dict[str, Any] = field(default_factory=dict)  # simple types an instance redeclares


class Reader:
    """Makes acausal classes of the classes of one source (each at most once).

    Parameters
    ----------
    source : ModelicaSource
    """

    def __init__(self, source: ModelicaSource) -> None:
        self.source = source
        self.scope = Scope(source)
        self.made: dict[str, type] = {}
        self._reading_path = False  # making a class of MODELICAPATH: its errors are said once, at the outermost
        self.functions = FunctionScope(find=self._function, where=self.source.where,
                                       constant=lambda name, subscripts, enclosing:
                                       self._global(name, subscripts, f"function {enclosing}"))

    # -- the class asked for -----------------------------------------------------------
    def main_class(self, name: str | None) -> str:
        """The full name of the class to load: ``name`` (full or short), or the one model the
        source defines."""
        # the models of the file: not those defined inside another model (its utilities)
        models = [full for full, node in self.scope.file_classes.items()
                  if node.type in ("model", "block", "class")
                  and getattr(self.scope.file_classes.get(full.rpartition(".")[0]), "type", "package")
                  == "package"]
        if name is not None:
            if name in self.scope.file_classes:
                return name
            matches = [full for full in self.scope.file_classes if full == name or full.endswith("." + name)]
            if len(matches) == 1:
                return matches[0]
            if not matches:
                import difflib

                close = difflib.get_close_matches(name, [m.rpartition(".")[2] for m in models], n=3)
                raise ModelicaError(f"{self.source.origin} defines no class {name!r}",
                                    hint=f"did you mean {', '.join(close)}?" if close else
                                    f"it defines {', '.join(models) or 'no model'}")
            raise ModelicaError(f"{name!r} names several classes of {self.source.origin}: {', '.join(matches)}",
                                hint="give the full name")
        # the classes nothing else in the file uses: the examples, not their utilities
        if len(models) == 1:
            return models[0]
        used = {m for m in models for other in models if other != m and m.rpartition(".")[2] in self.source.text
                and self._uses(other, m)}
        top = [m for m in models if m not in used]
        if len(top) == 1:
            return top[0]
        raise ModelicaError(f"{self.source.origin} defines several models ({', '.join(models) or 'none'})",
                            hint="name one: load(path, name=...) or FILE.mo:Model")

    def _uses(self, user: str, used: str) -> bool:
        node = self.scope.node(user)
        names = [_ref_text(s.type) for s in node.symbols.values()] + [_ref_text(e.component) for e in node.extends]
        return any(self.scope.full_name(n, user) == used for n in names)

    # -- classes -----------------------------------------------------------------------
    def make(self, full: str, top: bool = False, types: dict[str, Any] | None = None) -> type:
        """The acausal class of the Modelica class ``full`` defined in the source or read from a
        package on MODELICAPATH (with the simple types ``types`` redeclared: a class of its own
        per redeclaration).

        Raises
        ------
        ModelicaError
            For a class of MODELICAPATH that cannot be read: it names that class (the one
            acausal's library lacks), then what in its source could not be read.
        """
        if full in self.scope.file_classes or self._reading_path:
            return self._make(full, top, types)
        self._reading_path = True
        try:
            return self._make(full, top, types)
        except ModelicaError as exc:
            inner = re.sub(rf"^{re.escape(self.source.origin)}(:\d+)*: ", "", exc.message)
            raise ModelicaError(f"{self.source.where(full.rpartition('.')[2])}: {full} is not in acausal's "
                                f"library yet, and its source could not be read: {inner}",
                                hint=exc.hint) from None
        finally:
            self._reading_path = False

    def _make(self, full: str, top: bool, types: dict[str, Any] | None) -> type:
        key = f"{full}#top" if top else full
        if types:
            key += "#" + ";".join(f"{name}={_short_text(types[name])}" for name in sorted(types))
        if key in self.made:
            return self.made[key]
        node = self.scope.node(full)
        if node.type == "connector":
            made = self._connector(full, node)
        elif node.type in ("model", "block", "class", "record"):
            made = self._component(full, node, top, types or {})
        else:
            raise ModelicaError(f"{self.source.where(full.rpartition('.')[2])}: a {node.type} ({full}) cannot "
                                f"be instantiated", hint="instantiate a model, block or connector")
        self.made[key] = made
        return made

    def _bases(self, full: str, node) -> tuple[list[type], dict]:
        bases, modifiers = [], {}
        for clause in node.extends:
            name = _ref_text(clause.component)
            resolved = self.scope.resolve(name, full.rpartition(".")[0] if False else full, "class")
            if resolved.kind == "icon":
                continue
            if resolved.kind == "library":
                bases.append(resolved.target)
            elif resolved.kind == "file":
                bases.append(self.make(resolved.full))
            else:
                raise ModelicaError(f"{self.source.where('extends', name.split('.')[-1])}: extends {name}: "
                                    f"a {resolved.kind} cannot be extended here")
            for element, items in _modifications(clause.class_modification):
                modifiers[element] = items
        return bases, modifiers

    def _connector(self, full: str, node) -> type:
        namespace: dict[str, Any] = {"__module__": __name__, "__qualname__": full.rpartition(".")[2],
                                     "__doc__": node.comment or None, "family": full}
        for name, symbol in node.symbols.items():
            resolved = self.scope.resolve(_ref_text(symbol.type), full, "type")
            attributes = resolved.target if isinstance(resolved.target, dict) else {}
            kind = Flow if "flow" in _prefixes(symbol) else Potential
            namespace[name] = kind(unit=str(attributes.get("unit") or ""), description=symbol.comment or "")
        return type(full.rpartition(".")[2], (Connector,), namespace)

    def _component(self, full: str, node, top: bool, types: dict[str, Any] | None = None) -> type:
        bases, extends_modifiers = self._bases(full, node)
        root = Model if top else Component
        if not any(issubclass(b, Component) for b in bases):
            bases.append(root)
        elif top and not any(issubclass(b, Model) for b in bases):
            bases.append(Model)
        plan = _ClassPlan(full, node, types=dict(types or {}))
        for name, symbol in node.symbols.items():
            self._symbol(plan, name, symbol)
        self._function_inputs_structural(plan, node)
        reader = self
        namespace: dict[str, Any] = {"__module__": __name__, "__qualname__": full.rpartition(".")[2],
                                     "__doc__": node.comment or f"{full} (read from {self.source.origin})",
                                     **plan.declarations}
        if top:
            namespace["modelica_class"] = _modelica_class(getattr(node, "annotation", None)) or full
            experiment = _experiment(getattr(node, "annotation", None))
            if experiment is not None:
                namespace["experiment"] = experiment
        namespace["_modelica_source"] = self.source.origin
        namespace["_modelica_full"] = full  # the scope its expressions' names are looked up in

        made_class: list[type] = []  # this class, once made: its bases build first

        def build(self) -> None:
            for base in made_class[0].__mro__[1:]:
                own = vars(base).get("build")
                if own is not None and base is not Component:
                    own(self)
                    break
            reader._build(plan, self)

        def equations(self) -> list:
            return reader._equations(plan, self, node.equations)

        def initial_equations(self) -> list:
            return reader._equations(plan, self, getattr(node, "initial_equations", None) or [])

        namespace["build"] = build
        namespace["equations"] = equations
        namespace["initial_equations"] = initial_equations
        if plan.derived:
            def parameter_binding(self, name: str) -> Any:
                if name not in self._modifiers:
                    if name in plan.derived:
                        return reader._value(plan.derived[name], self, f"{full}.{name}", scope=full)
                    element = _ELEMENT_NAME.match(name)
                    if element and element.group(1) in plan.derived:  # A[1,2] of A = expression
                        whole = reader._value(plan.derived[element.group(1)], self, f"{full}.{name}", scope=full)
                        index = tuple(int(i) for i in element.group(2).split(","))
                        return _python(whole[index] if len(index) > 1 else whole[index[0]])
                return super(made, self).parameter_binding(name)

            namespace["parameter_binding"] = parameter_binding

            def _modifier_value(self, name: str, default: Any) -> Any:
                # a structural parameter bound to an expression (parameter Integer m = n): its
                # value, read where the language asks for a structural parameter's value
                if name not in self._modifiers and name in plan.derived:
                    return _python(reader._value(plan.derived[name], self, f"{full}.{name}", scope=full))
                return super(made, self)._modifier_value(name, default)

            namespace["_modifier_value"] = _modifier_value
        made = type(full.rpartition(".")[2], tuple(dict.fromkeys(bases)), namespace)
        made_class.append(made)
        if extends_modifiers:
            original_init = made.__init__

            def __init__(self, **modifiers: Any) -> None:
                # an extends modification is read in this class's scope (table=table reads the
                # constant this class declares): made once the instance exists, then the
                # modifiers given here win over it
                original_init(self, **modifiers)
                given = reader._modifier_dict(list(extends_modifiers.items()), self, full)
                self._apply_modifiers(_merge(given, modifiers))

            made.__init__ = __init__
        return made

    def _function_inputs_structural(self, plan: _ClassPlan, node) -> None:
        """Make structural the parameters an equation passes to a Modelica function
        (``(b, a) = padeCoefficients(delayTime, n, m)``).

        acausal evaluates a Modelica function when it reads the model (see
        :mod:`acausal.modelica.functions`), so its inputs must have values then; a
        structural parameter is one acausal uses by value while translating, as a tool
        evaluates such a parameter.  Modelica.Math's elementary functions are acausal's
        own and take any expression.
        """
        names: set[str] = set()
        only_functions = [False]  # in a binding: the built-in operators (atan(inclination)) take any expression

        def is_function(callee: str) -> bool:
            try:
                self._function(callee, plan.full)
            except ModelicaError:
                return False
            return True

        def visit(item) -> None:
            kind = type(item).__name__
            if kind == "Expression":
                operator = item.operator
                if not isinstance(operator, str):
                    callee = _ref_text(operator)
                    if callee.rpartition(".")[0] not in ("Modelica.Math", "Math") \
                            and (not only_functions[0] or is_function(callee)):
                        for operand in item.operands:
                            collect(operand)
                for operand in item.operands:
                    visit(operand)
            elif kind == "Array":
                for value in item.values:
                    visit(value)

        def collect(item) -> None:
            kind = type(item).__name__
            if kind == "ComponentRef":
                names.add(item.name)
            elif kind == "Expression":
                for operand in item.operands:
                    collect(operand)
            elif kind == "Array":
                for value in item.values:
                    collect(value)

        # a binding is evaluated like an equation (ViNominal = VaNominal - convertResistance(Ra, ...))
        only_functions[0] = True
        for name, binding in plan.derived.items():
            if not name.startswith("="):
                visit(binding)
        only_functions[0] = False
        for equation in [*(node.equations or []), *(getattr(node, "initial_equations", None) or [])]:
            if type(equation).__name__ == "Equation":
                visit(equation.right)
                if not isinstance(equation.left, list):
                    visit(equation.left)
        for name in names:
            declaration = plan.declarations.get(name)
            if isinstance(declaration, Parameter) and declaration.shape is None:
                declaration.structural = True

    # -- declarations ------------------------------------------------------------------
    def _symbol(self, plan: _ClassPlan, name: str, symbol) -> None:
        type_name = _ref_text(symbol.type)
        condition = self._condition(symbol, name)
        if type_name in plan.types:  # a simple type this instance redeclares
            definition = plan.types[type_name]
            base = self.scope.resolve(_ref_text(definition.component), plan.full, "type")
            inherited = base.target if isinstance(base.target, dict) else {"base": base.target}
            resolved = Resolved("type", type_name, {**inherited,
                                                    **_literal_attributes(definition.class_modification)})
        else:
            resolved = self.scope.resolve(type_name, plan.full, "type")
        dims = _dimensions(symbol)
        if resolved.kind in ("library", "file"):
            klass = resolved.target if resolved.kind == "library" else self.make(resolved.full)
            if isinstance(klass, type) and issubclass(klass, Connector):  # a connector of this class
                shape = self._shape(dims, plan.full) if dims else None
                plan.declarations[name] = klass(description=symbol.comment or "", shape=shape,
                                                condition=condition)
                return
            plan.components.append((name, resolved, symbol, dims))
            return
        if resolved.kind == "enumeration":
            attributes, base = {}, "enumeration"
        elif resolved.kind == "builtin":
            attributes, base = {}, resolved.target
        elif resolved.kind == "type":
            attributes = {k: v for k, v in resolved.target.items() if k != "base"}
            base = resolved.target.get("base", "Real")
        else:
            raise ModelicaError(f"{self.source.where(name)}: {type_name} is not a type of a variable "
                                f"or parameter", components=(name,))
        prefixes = _prefixes(symbol)
        if getattr(plan.node, "type", "") == "record" and not prefixes & {"constant", "input", "output"}:
            # a record's elements have the variability of the record's declaration (MLS 4.5):
            # records of data, as the MSL declares them, are parameters
            prefixes.add("parameter")
        given = dict(_modifications(symbol.class_modification))
        literal = {key: _literal(items[-1]) for key, items in given.items()
                   if items and not _is_modification(items[-1])}
        causality_of_type = attributes.get("causality")
        attributes.update({k: v for k, v in literal.items() if v is not _NOT_LITERAL})
        if causality_of_type:
            attributes["causality"] = causality_of_type
        unit = str(attributes.get("unit") or "")
        description = symbol.comment or ""
        value = getattr(symbol, "value", None)
        if "value" in given and given["value"] and not _is_modification(given["value"][-1]):
            value = given["value"][-1]  # pymoca keeps a binding `= expr` as the element "value"
        has_value = value is not None and not (getattr(value, "value", 0) is None and type(value).__name__ == "Primary")
        structural = ("parameter" in prefixes or "constant" in prefixes) and (base != "Real" or "constant" in prefixes)
        evaluate = _evaluate_annotation(symbol)
        if "parameter" in prefixes and evaluate is not None:
            # annotation(Evaluate=true) asks the tool to use the value while translating (MLS
            # 18.3): acausal's structural parameter; Evaluate=false keeps it tunable
            structural = evaluate
        # an array whose size its value gives (x[:]), and a structural array (a Python value): no shape
        open_size = any(type(d).__name__ == "Slice" for d in dims)
        shape = self._shape(dims, plan.full, plan.derived) if dims and not open_size and not structural else None
        if "parameter" in prefixes or "constant" in prefixes:
            default = None
            if has_value:
                default = _literal(value)
                if default is _NOT_LITERAL:
                    default = None
                    try:  # a constant expression ([1, 0; 0, 1], 2*pi): its value now
                        default = _python(self._value(value, None, name, scope=plan.full))
                    except Exception:  # noqa: BLE001 - it reads other parameters: per instance
                        plan.derived[name] = value
            if attributes.get("fixed") is False and default is None:
                default = _number(attributes.get("start"), 0.0)  # found at initialization, from its start
            declaration = Parameter(default, unit=unit, min=_number(attributes.get("min")),
                                    max=_number(attributes.get("max")), structural=structural,
                                    description=description, display_unit=str(attributes.get("displayUnit") or ""),
                                    fixed=attributes.get("fixed", True) is not False, shape=shape,
                                    condition=condition)
        else:
            causality = "input" if "input" in prefixes else "output" if "output" in prefixes else \
                str(attributes.pop("causality", ""))
            options = dict(start=_number(attributes.get("start"), 0.0), fixed=bool(attributes.get("fixed", False)),
                           description=description, causality=causality, shape=shape, condition=condition)
            if base == "Real":
                options.update(unit=unit, min=_number(attributes.get("min")), max=_number(attributes.get("max")),
                               nominal=_number(attributes.get("nominal")), discrete="discrete" in prefixes,
                               display_unit=str(attributes.get("displayUnit") or ""))
                declaration = Variable(**options)
            elif base in ("Boolean", "Integer"):
                options["start"] = bool(options["start"]) if base == "Boolean" else int(options["start"])
                declaration = _KINDS[base](**options)
            else:
                raise ModelicaError(f"{self.source.where(name)}: a {base} variable ({name}) is not supported",
                                    components=(name,))
            if has_value:  # Real x = expr: an equation
                plan.derived[f"={name}"] = value
        plan.declarations[name] = declaration

    def _condition(self, symbol, name: str) -> Callable[[Component], bool] | None:
        """A declaration's condition (``if useSupport``, MLS 4.4.5) as acausal's ``condition=``:
        read in the instance, where it must be a Boolean parameter expression."""
        node = getattr(symbol, "condition", None)
        if node is None:
            return None

        def enabled(instance: Component) -> bool:
            return self._enabled(node, instance, name)

        return enabled

    def _enabled(self, node, instance, name: str) -> bool:
        value = self._value(node, instance, f"the condition of {name}")
        if value in (True, False, sp.true, sp.false):
            return bool(value)
        raise ModelicaError(f"{self.source.where(name)}: the condition of {name} is {value}, not a Boolean "
                            "known when the model is built", components=(name,),
                            hint="a declaration's condition is a Boolean parameter expression")

    def _shape(self, dims: list, enclosing: str, derived: dict | None = None):
        out = []
        for dim in dims:
            literal = _literal(dim)
            if isinstance(literal, (int, float)) and literal is not _NOT_LITERAL:
                out.append(int(literal))
            elif hasattr(dim, "name") and not getattr(dim, "child", None) and dim.name not in (derived or {}):
                out.append(dim.name)  # a structural parameter
            elif type(dim).__name__ in ("Expression", "ComponentRef"):
                out.append(_SizeExpression(dim, f"{enclosing}: an array size", derived))  # n + 1
            else:
                raise ModelicaError(f"{self.source.origin}: an array size {dim} is not supported",
                                    hint="give the size as a number or a parameter name")
        return tuple(out)

    # -- instances ---------------------------------------------------------------------
    def _build(self, plan: _ClassPlan, instance: Component) -> None:
        pending = list(plan.components)
        while pending:
            # a modifier may read a sibling declared later (table=other.table): make the
            # others first and come back
            waiting = []
            for entry in pending:
                if not self._make_component(plan, instance, entry, later=[e[0] for e in pending if e is not entry]):
                    waiting.append(entry)
            if len(waiting) == len(pending):
                self._make_component(plan, instance, waiting[0], later=[])  # raises what is missing
            pending = waiting
        for left, right in self._connects(plan.node.equations, instance, {}):
            # Modelica removes a connection to a disabled conditional connector (section 4.4.5)
            if any(getattr(end, "enabled", True) is False for end in (left, right)):
                continue
            instance.connect(left, right)

    def _make_component(self, plan: _ClassPlan, instance: Component, entry: tuple, later: list[str]) -> bool:
        """Make one sub-component of ``instance`` (False: it reads a sibling in ``later``)."""
        name, resolved, symbol, dims = entry
        if getattr(symbol, "condition", None) is not None and not self._enabled(symbol.condition, instance, name):
            # a disabled conditional component: not made, and its connections are removed
            instance.__dict__.setdefault("_modelica_disabled", set()).add(name)
            return True
        redeclared = _redeclared_types(symbol.class_modification)
        if redeclared and resolved.kind == "library":
            raise ModelicaError(f"{self.source.where(name)}: {name}: redeclare type in a library class "
                                f"({resolved.full}) is not supported", components=(name,),
                                hint="acausal's library classes declare their types in Python")
        klass = resolved.target if resolved.kind == "library" else self.make(resolved.full, types=redeclared)
        try:
            modifiers = self._modifier_dict(_modifications(symbol.class_modification), instance, plan.full)
        except ModelicaError as exc:
            if any(f"undefined name '{other}." in exc.message or f"undefined name '{other}'" in exc.message
                   for other in later):
                return False
            if f"undefined name '{name}." not in exc.message:
                raise
            modifiers = self._self_modifiers(name, klass, _modifications(symbol.class_modification), instance,
                                             plan.full)
        # the modifiers from outside (an extends modification, a modifier of this model) win, and
        # they act before the component is made, as in Modelica (its sizes may follow them)
        outer = instance._nested_modifiers.get(name)
        if outer:
            modifiers = _merge(modifiers, outer)
        modifiers = _fitted(klass, modifiers, instance)
        try:
            if dims:
                n = int(self._value(dims[0], instance, name))
                made = [klass(**_element_modifiers(modifiers, i, n)) for i in range(n)]
            else:
                made = klass(**modifiers)
        except ModelicaError:
            raise
        except Exception as exc:  # a modifier the class refuses: say where it was written
            raise ModelicaError(f"{self.source.where(name)}: {name} ({resolved.full}): {exc}",
                                components=(name,)) from exc
        setattr(instance, name, made)
        return True

    def _connects(self, items, instance, loop: dict) -> Iterable[tuple]:
        for item in items:
            kind = type(item).__name__
            if kind == "ConnectClause":
                disabled = instance.__dict__.get("_modelica_disabled", ())
                if any(_ref_text(end).split(".")[0] in disabled for end in (item.left, item.right)):
                    continue  # a connection to a disabled conditional component (MLS 4.4.5)
                yield (self._reference(item.left, instance, loop), self._reference(item.right, instance, loop))
            elif kind == "ForEquation":
                for bound in self._loop(item, instance, loop):
                    yield from self._connects(item.equations, instance, bound)
            elif kind == "IfEquation" and any(type(e).__name__ == "ConnectClause"
                                             for block in item.blocks for e in block):
                for condition, block in zip(item.conditions, item.blocks):
                    chosen = condition is True or bool(self._value(condition, instance, "if", loop))
                    if chosen:
                        yield from self._connects(block, instance, loop)
                        break

    def _reference(self, ref, instance, loop: dict) -> Any:
        """The connector or signal a component reference of ``connect`` names."""
        return self._resolve(instance, loop, "connect", _ref_text(ref),
                             _subscripts(ref, self, instance, loop, "connect"))

    def _equations(self, plan: _ClassPlan, instance: Component, items) -> list:
        out = []
        if items is plan.node.equations:
            for key, value in plan.derived.items():
                if key.startswith("="):
                    name = key[1:]
                    if not plan.declarations[name].enabled(instance):
                        continue  # the binding of a disabled conditional variable
                    out.append(Eq(getattr(instance, name), self._value(value, instance, name)))
        out += self._statements(items, instance, {}, plan.full)
        return out

    def _statements(self, items, instance, loop: dict, full: str) -> list:
        from ..hybrid import Assert, When, reinit, terminate

        out = []
        for item in items:
            kind = type(item).__name__
            if kind == "ConnectClause":
                continue
            if kind == "Equation" and isinstance(item.left, list):  # (b, a) = f(...)
                out += self._outputs_equation(item, instance, loop)
            elif kind == "Equation":
                out.append(Eq(self._value(item.left, instance, "equation", loop),
                              self._value(item.right, instance, "equation", loop)))
            elif kind == "ForEquation":
                for bound in self._loop(item, instance, loop):
                    out += self._statements(item.equations, instance, bound, full)
            elif kind == "IfEquation":
                out += self._if_equation(item, instance, loop, full)
            elif kind == "WhenEquation":
                clause = None
                for condition, block in zip(item.conditions, item.blocks):
                    body = self._statements(block, instance, loop, full)
                    test = self._value(condition, instance, "when", loop)
                    clause = When(test, *body) if clause is None else clause.elsewhen(test, *body)
                out.append(clause)
            elif kind == "Function":
                arguments = [self._value(a, instance, item.name, loop) for a in item.arguments]
                if item.name == "assert":
                    level = "warning" if len(arguments) > 2 and "warning" in str(arguments[2]) else "error"
                    out.append(Assert(arguments[0], str(arguments[1]), level=level))
                elif item.name == "terminate":
                    out.append(terminate(str(arguments[0])))
                elif item.name == "reinit":
                    out.append(reinit(arguments[0], arguments[1]))
                else:
                    raise ModelicaError(f"{self.source.where(item.name)}: the equation {item.name}(...) is "
                                        f"not supported")
            else:
                raise ModelicaError(f"{self.source.origin}: {kind} in {full} is not supported",
                                    hint="equations, if, when, for, connect, assert, terminate and reinit are")
        return out

    def _outputs_equation(self, item, instance, loop: dict) -> list:
        """``(b, a) = f(x)`` (MLS 8.3.1): a function's outputs equal to the names on the left,
        in order; an empty place (``(, a) = f(x)``) takes no output.  The function is
        evaluated now (its inputs are parameters known when the model is built)."""
        call = item.right
        operator = getattr(call, "operator", None)
        if type(call).__name__ != "Expression" or operator is None or isinstance(operator, str):
            raise ModelicaError(f"{self.source.where('=')}: the right side of an equation with several "
                                "names on the left must be a function call")
        name = _ref_text(operator)
        node, full = self._function(name, self._enclosing(instance))
        positional, named = _expressions().call_arguments(call.operands, name)
        outputs = call_function(node, full, [self._value(a, instance, name, loop) for a in positional],
                                {k: self._value(a, instance, name, loop) for k, a in named.items()},
                                self.functions)
        if len(item.left) > len(outputs):
            raise ModelicaError(f"{self.source.where(name.split('.')[-1])}: {full}() has {len(outputs)} outputs, "
                                f"the equation names {len(item.left)}")
        out = []
        for target, value in zip(item.left, outputs):
            if target is None or (type(target).__name__ == "Primary" and target.value is None):
                continue
            out.append(Eq(self._value(target, instance, "equation", loop), value))
        return out

    def _if_equation(self, item, instance, loop: dict, full: str) -> list:
        conditions = [True if c is True else self._value(c, instance, "if", loop) for c in item.conditions]
        blocks = [self._statements(block, instance, loop, full) for block in item.blocks]
        if all(isinstance(c, bool) or isinstance(c, (int,)) for c in conditions):  # parameters only
            for condition, block in zip(conditions, blocks):
                if condition:
                    return block
            return []
        sizes = {len(b) for b in blocks}
        if len(sizes) != 1 or len(conditions) != len(blocks) or conditions[-1] is not True:
            raise ModelicaError(f"{self.source.origin}: an if-equation in {full} whose branches differ in "
                                f"number or lacks an else branch is not supported")
        from ..language import If

        out = []
        for k in range(sizes.pop()):
            residual = blocks[-1][k].lhs - blocks[-1][k].rhs
            for condition, block in zip(reversed(conditions[:-1]), reversed(blocks[:-1])):
                residual = If(condition, block[k].lhs - block[k].rhs, residual)
            out.append(Eq(0, residual))
        return out

    def _loop(self, item, instance, loop: dict) -> Iterable[dict]:
        names = [index.name for index in item.indices]
        ranges = [self._value(index.expression, instance, "for", loop) for index in item.indices]
        import itertools

        for values in itertools.product(*[list(r) for r in ranges]):
            yield {**loop, **dict(zip(names, (int(v) for v in values)))}

    # -- values ------------------------------------------------------------------------
    def _value(self, node, instance, where: str, loop: dict | None = None, scope: str | None = None) -> Any:
        """A Modelica expression of ``instance``'s names as a Python or sympy value (``scope``: the
        class it is written in, when not ``instance``'s own: a base class's binding reads the
        base's imports)."""
        resolve = functools.partial(self._resolve, instance, loop or {}, where, scope=scope)
        literal = _literal(node)
        if literal is not _NOT_LITERAL and not isinstance(literal, list):
            return literal  # a number, string or Boolean as it is written
        if type(node).__name__ == "ComponentRef":  # a name alone: no expression to convert
            return resolve(_ref_text(node), _subscripts(node, self, instance, loop or {}, where))
        enclosing = scope or self._enclosing(instance)
        try:
            value = _expressions().to_sympy(node, resolve, functools.partial(self._call, enclosing))
        except ModelicaError as exc:
            if self.source.origin in str(exc):
                raise
            raise ModelicaError(f"{self.source.where(where)}: {exc.message}", hint=exc.hint) from None
        return value

    def _resolve(self, instance, loop: dict, where: str, name: str, indices: list, scope: str | None = None) -> Any:
        if name in loop and not indices:
            return loop[name]
        head, _, rest = name.partition(".")
        target: Any = _MISSING
        if instance is not None and head in loop:
            target = loop[head]
        elif instance is not None and (hasattr(type(instance), head) or head in instance._children
                                       or head in getattr(instance, "_component_arrays", {})):
            target = getattr(instance, head)
        if target is not _MISSING:
            parts = rest.split(".") if rest else []
            return _walk(target, [head, *parts], indices)
        return self._global(name, indices, where,
                            scope or (self._enclosing(instance) if instance is not None else None))

    def _global(self, name: str, indices: list, where: str, scope: str | None = None) -> Any:
        # looked up from the class the expression is written in (its imports: pi of
        # ``import Modelica.Constants.pi``), then from the classes of the file
        enclosings = ([scope] if scope else []) + self._enclosings()
        for enclosing in enclosings:
            full = self.scope.full_name(name.rpartition(".")[0], enclosing) if "." in name else None
            if full and full in self.scope.enumerations:
                return self.scope.enumerations[full][name.rpartition(".")[2]]
        resolved_full = self.scope.full_name(name, next(iter(enclosings), ""))
        if resolved_full and resolved_full.startswith("Modelica.Constants."):
            return _CONSTANTS[resolved_full.rpartition(".")[2]]
        if name.startswith("StateSelect."):
            return self.scope.enumerations["StateSelect"][name.rpartition(".")[2]]
        if name.startswith("AssertionLevel."):  # the built-in enumeration: assert's level
            return name.rpartition(".")[2]
        constant = self._package_constant(resolved_full or name)
        if constant is not _MISSING:
            return constant
        raise ModelicaError(f"{self.source.where(name.split('.')[0])}: undefined name {name!r} in {where}",
                            hint="a parameter, variable or component of this class, a loop index, an "
                                 "enumeration literal or a constant of Modelica.Constants")

    # -- Modelica functions -------------------------------------------------------------
    def _call(self, enclosing: str, name: str, positional: list, named: dict) -> Any:
        """A call, inside the class ``enclosing``, of a Modelica function: its first output."""
        node, full = self._function(name, enclosing)
        # a record given to a function (brushVoltageDrop(brushParameters, i)): its fields' values
        positional = [_record_values(v) if isinstance(v, Component) else v for v in positional]
        named = {k: _record_values(v) if isinstance(v, Component) else v for k, v in named.items()}
        outputs = call_function(node, full, positional, named, self.functions)
        if not outputs:
            raise ModelicaError(f"{self.source.where(name.split('.')[-1])}: {full}() has no output, and is "
                                "used in an expression")
        return outputs[0]

    def _function(self, name: str, enclosing: str) -> tuple[Any, str]:
        """The function class ``name`` names inside ``enclosing`` (MLS 5.3): in the file, or
        in a package on MODELICAPATH."""
        first, _, rest = name.partition(".")
        candidates = []
        imported = self.scope.full_name(name, enclosing)
        if imported:
            candidates.append(imported)
        parts = enclosing.split(".") if enclosing else []
        candidates += [".".join([*parts[:k], name]) for k in range(len(parts), -1, -1)]
        for full in candidates:
            node = self.scope.node(full) or _class_on_path(full, _path_key())
            if node is not None:
                if getattr(node, "type", None) != "function":
                    raise ModelicaError(f"{self.source.where(name.split('.')[-1])}: {full} is a {node.type}, "
                                        "not a function", hint="only functions can be called in expressions")
                return node, full
        raise ModelicaError(f"{self.source.where(name.split('.')[-1])}: unsupported function {name}()",
                            hint="acausal reads Modelica's built-in operators, Modelica.Math's elementary "
                                 "functions and the Modelica functions of the file or of the packages on "
                                 "MODELICAPATH")

    def _package_constant(self, full: str) -> Any:
        """The value of a constant a package on MODELICAPATH declares
        (``Modelica.Electrical.Machines.Thermal.Constants.alpha20Copper``), or _MISSING."""
        package, _, member = full.rpartition(".")
        if not package or _package_file(package) is None:
            return _MISSING
        node = parse(_package_file(package)).tree
        for part in package.split("."):
            node = node.classes.get(part) if node is not None else None
        symbol = node.symbols.get(member) if node is not None else None
        if symbol is None or "constant" not in _prefixes(symbol):
            return _MISSING
        given = dict(_modifications(symbol.class_modification))
        value = given["value"][-1] if given.get("value") else getattr(symbol, "value", None)
        literal = _literal(value)
        return literal if literal is not _NOT_LITERAL and literal is not None else _MISSING

    def _enclosing(self, instance) -> str:
        """The class whose scope an expression of ``instance`` is read in (MLS 5.3): the class
        it was made of (a sized subclass inherits it), else the innermost class of the file."""
        return getattr(type(instance), "_modelica_full", None) or next(iter(self._enclosings()), "")

    def _enclosings(self) -> list[str]:
        return sorted(self.scope.file_classes, key=len, reverse=True)

    def _self_modifiers(self, name: str, klass: type, modifications: list, instance, full: str) -> dict:
        """The modifiers of the component ``name`` when some read its own parameters
        (``vIn(rising=0.2/f, startTime=-(vIn.rising + vIn.width/2))``).

        The modification is read in the enclosing class (MLS 7.2), where ``vIn.rising`` is the
        value the modification gives ``rising`` (or the class's default): the modifiers are read
        in the order their dependencies allow.
        """
        known: dict[str, Any] = {}
        own = _OwnValues(name, klass, known)
        pending = list(modifications)
        while pending:
            waiting = []
            for entry in pending:
                try:
                    known.update(self._modifier_dict([entry], instance, full, {name: own}))
                except ModelicaError as exc:
                    if f"undefined name '{name}." not in exc.message:
                        raise
                    waiting.append(entry)
            if len(waiting) == len(pending):
                self._modifier_dict(waiting[:1], instance, full, {name: own})  # raises what is missing
            pending = waiting
        return known

    def _modifier_dict(self, modifications: list, instance, full: str, loop: dict | None = None) -> dict:
        """A Modelica modification as acausal modifiers: values, and dicts for variable
        attributes and sub-components (``phi(start=0, fixed=true)`` is ``phi=dict(start=0, fixed=True)``)."""
        out: dict[str, Any] = {}
        for element, items in modifications:
            target = out
            *path, last = element.split(".")
            for part in path:
                target = target.setdefault(part, {})
            for item in items:
                if _is_modification(item):
                    nested = self._modifier_dict(_modifications(item), instance, full, loop)
                    nested = {_ATTRIBUTES.get(k, k): v for k, v in nested.items()}
                    existing = target.get(last)
                    target[last] = _merge(existing if isinstance(existing, dict) else {}, nested)
                else:
                    value = _python(self._value(item, instance, element, loop))
                    if isinstance(value, Component):  # a record given whole: its parameters, bound
                        value = _record_modifiers(value)
                    # p(displayUnit="rpm") = 2: the value; the attributes of a parameter given
                    # here only say how to show it
                    target[last] = value
        return out


#: Modelica's attribute names that acausal spells in Python's way.
_ATTRIBUTES = {"displayUnit": "display_unit", "stateSelect": "state_select"}

_ELEMENT_NAME = re.compile(r"^(\w+)\[(\d+(?:,\d+)*)\]$")

_MISSING = object()
_NOT_LITERAL = object()


def _record_modifiers(record: Component) -> dict:
    """A record instance given as a modifier (``frictionParameters=data.frictionParameters``) as
    the modifiers of each of its parameters, bound to the record's (MLS 7.2.3: a record
    modification binds every component), its own records included."""
    record.ensure_built()
    out: dict[str, Any] = {name: getattr(record, name) for name, declaration in type(record).declarations().items()
                           if isinstance(declaration, Parameter)}
    for name, child in record._children.items():
        out[name] = _record_modifiers(child)
    return out


def _record_values(record: Component) -> dict:
    """A record instance as a function takes it: its parameters' values (a parameter acausal
    keeps symbolic stays a symbol, refused by the function only if it reads it), its records
    as dicts."""
    record.ensure_built()
    out: dict[str, Any] = {}
    for name, declaration in type(record).declarations().items():
        if isinstance(declaration, Parameter):
            out[name] = _evaluated(getattr(record, name), record)
    for name, child in record._children.items():
        out[name] = _record_values(child)
    return out


class _OwnValues:
    """A component's parameters as its own modification reads them: the values given so far,
    else the class's defaults (numbers); another name is undefined, to be read later."""

    def __init__(self, name: str, klass: type, known: dict) -> None:
        self._name, self._klass, self._known = name, klass, known

    def __getattr__(self, attribute: str) -> Any:
        if attribute.startswith("_"):
            raise AttributeError(attribute)
        if attribute in self._known and not isinstance(self._known[attribute], dict):
            return self._known[attribute]
        declaration = self._klass.declarations().get(attribute)
        if attribute not in self._known and isinstance(declaration, Parameter) \
                and isinstance(declaration.default, (int, float)) and not isinstance(declaration.default, bool):
            return declaration.default
        raise ModelicaError(f"undefined name '{self._name}.{attribute}' (not given yet)")


def _short_text(definition) -> str:
    """A key for a redeclared type: its base and its literal attributes."""
    return f"{_ref_text(definition.component)}{sorted(_literal_attributes(definition.class_modification).items())}"


def _literal(node) -> Any:
    """The Python value of a literal (a number, string, Boolean, or array of them), else _NOT_LITERAL."""
    kind = type(node).__name__
    if kind == "Primary":
        return node.value
    if isinstance(node, (bool, int, float, str)):
        return node
    if kind == "Expression" and node.operator == "-" and len(node.operands) == 1:
        inner = _literal(node.operands[0])
        return -inner if isinstance(inner, (int, float)) and not isinstance(inner, bool) else _NOT_LITERAL
    if kind == "Array":
        values = [_literal(v) for v in node.values]
        return _NOT_LITERAL if any(v is _NOT_LITERAL for v in values) else values
    return _NOT_LITERAL


class _SizeExpression:
    """An array size written as an expression of structural parameters (``Real a[n + 1]``): the
    language calls it with ``value(name)``, which reads the instance's structural parameters."""

    def __init__(self, node, where: str, derived: dict | None = None) -> None:
        self.node = node
        self.where = where
        self.derived = derived if derived is not None else {}  # parameter -> its binding's node
        self.text = str(_expressions().to_sympy(node, lambda name, indices: sp.Symbol(name)))

    def __call__(self, value: Callable[[str], Any]) -> int:
        def resolve(name: str, indices: list) -> Any:
            found = value(name)
            if found is None and name in self.derived:  # parameter Integer m = n: n's value
                found = _expressions().to_sympy(self.derived[name], resolve)
            for group in indices:
                for i in group:
                    found = found[int(i) - 1]
            return found

        size = _expressions().to_sympy(self.node, resolve)
        if not getattr(size, "is_Integer", False) and not isinstance(size, int):
            raise ModelicaError(f"{self.where} {self.text} is {size}, not an Integer known when the "
                                "model is built", hint="an array size reads structural parameters only")
        return int(size)


def _evaluate_annotation(symbol) -> bool | None:
    """The value of a declaration's ``annotation(Evaluate=...)``, or None without one."""
    try:
        elements = _modifications(getattr(symbol, "annotation", None))
    except ModelicaError:  # an annotation holding what a modification does not (graphics, choices)
        return None
    for element, items in elements:
        if element == "Evaluate" and items and not _is_modification(items[-1]):
            value = _literal(items[-1])
            if isinstance(value, bool):
                return value
    return None


def _number(value: Any, default: Any = None) -> Any:
    if value is None or value is _NOT_LITERAL:
        return default
    return value


def _python(value: Any) -> Any:
    """A sympy number as a Python number, an Array of numbers as nested lists; anything else as is."""
    from ..arrays import Array

    if isinstance(value, Array):
        return [_python(v) for v in value.tolist()] if value.ndim else value
    if isinstance(value, list):
        return [_python(v) for v in value]
    if isinstance(value, enum.Enum):
        return value
    if isinstance(value, sp.Basic):
        if value in (sp.true, sp.false):
            return bool(value)
        if value.is_Integer:
            return int(value)
        if value.is_number:
            return float(value)
    return value


def _subscripts(ref, reader: "Reader", instance, loop: dict, where: str) -> list:
    """The subscripts of each part of a ComponentRef, as Python values (1-based)."""
    out = []
    while ref is not None:
        group = [i for i in (getattr(ref, "indices", None) or [[None]])[0] if i is not None] \
            if getattr(ref, "indices", None) else []
        out.append([reader._value(i, instance, where, loop) for i in group])
        ref = ref.child[0] if getattr(ref, "child", None) else None
    return out


def _walk(target: Any, parts: list[str], indices: list) -> Any:
    """``a.b[i].c`` from the object ``a``: attributes, then Modelica's 1-based subscripts."""
    value = target
    for k, part in enumerate(parts):
        if k:
            if isinstance(value, Component):  # a record's member is made when it is built
                value.ensure_built()
            value = getattr(value, part)
        subscripts = indices[k] if k < len(indices) else None
        if subscripts:
            value = value[tuple(subscripts)] if len(subscripts) > 1 else value[subscripts[0]]
    return value


def _merge(inner: dict, outer: dict) -> dict:
    merged = dict(inner)
    for key, value in outer.items():
        if isinstance(value, dict) and isinstance(merged.get(key), dict):
            merged[key] = _merge(merged[key], value)
        else:
            merged[key] = value
    return merged


def _fitted(klass: type, modifiers: dict, instance) -> dict:
    """``modifiers`` as ``klass``'s declarations take them.

    * The attributes of an array of variables a class declares element by
      element (``y(start={0, 1}, each fixed=true)``): one dict per element,
      as such a class takes them.
    * A matrix parameter given one row: pymoca reads Modelica's ``[0, -1]``
      (a 1 x 2 matrix) as the vector ``{0, -1}``; a parameter whose default
      is a matrix takes it as one row.
    * A structural parameter (a table, a size) given an expression of the
      enclosing model's parameters (``table=tableR``): their values, as a
      Modelica tool evaluates such a parameter.
    """
    declarations = klass.declarations()
    out = dict(modifiers)
    arrays = klass.array_declarations() if hasattr(klass, "array_declarations") else {}
    for key, value in modifiers.items():
        declaration = declarations.get(key)
        if declaration is None and key in arrays and isinstance(value, dict) \
                and any(isinstance(v, list) for v in value.values()):
            out[key] = _per_element_attributes(value, key)
            continue
        if isinstance(declaration, Connector) and isinstance(value, dict) and _restates(declaration, value):
            # out(i(start=0, fixed=false)): a connector takes no modifier in acausal, but one that
            # restates its variables' own attributes changes nothing and is left out
            del out[key]
            continue
        if not isinstance(declaration, Parameter):
            continue
        if declaration.structural and instance is not None:
            value = _evaluated(value, instance)
        default = declaration.default
        if isinstance(value, list) and value and not isinstance(value[0], list) \
                and isinstance(default, (list, tuple)) and default and isinstance(default[0], (list, tuple)):
            value = [value]
        out[key] = value
    return out


def _restates(connector: Connector, modifier: dict) -> bool:
    """Whether ``modifier`` (``{"i": {"start": 0, "fixed": False}}``) gives the variables of
    ``connector`` only the attributes they already have."""
    variables = type(connector).variables()
    for name, attributes in modifier.items():
        variable = variables.get(name)
        if variable is None or not isinstance(attributes, dict):
            return False
        for attribute, value in attributes.items():
            own = getattr(variable, attribute, _MISSING)
            if own is _MISSING or isinstance(value, (dict, list)) or not bool(value == own):
                return False
    return True


def _per_element_attributes(attributes: dict, name: str) -> list[dict]:
    """``dict(start=[0, 1], fixed=True)`` as ``[dict(start=0, fixed=True), dict(start=1, fixed=True)]``:
    a list gives each element its value, anything else is every element's."""
    sizes = {len(v) for v in attributes.values() if isinstance(v, list)}
    if len(sizes) != 1:
        raise ModelicaError(f"the attributes of {name} give arrays of different sizes ({sorted(sizes)})")
    n = sizes.pop()
    return [{a: (v[i] if isinstance(v, list) else v) for a, v in attributes.items()} for i in range(n)]


def _evaluated(value: Any, instance) -> Any:
    """``value`` with the parameters of ``instance`` (and below) replaced by their values."""
    from ..arrays import Array

    if isinstance(value, list):
        return [_evaluated(v, instance) for v in value]
    if isinstance(value, Array):
        return _evaluated(value.tolist(), instance)
    if not isinstance(value, sp.Basic) or not value.free_symbols:
        return value
    prefix = f"{instance.path}." if instance.path else ""
    values = {}
    for symbol in value.free_symbols:
        dotted = symbol.name[len(prefix):] if symbol.name.startswith(prefix) else symbol.name
        owner_path, _, member = dotted.rpartition(".")
        owner = instance
        for part in owner_path.split(".") if owner_path else []:
            owner = owner._children.get(part) if owner is not None else None
        if owner is None or not isinstance(owner.declarations().get(member), Parameter):
            # a variable (a time-varying input given to such a parameter, as MSL's
            # ``number=multiSwitch1.y``): it stays a symbol, only parameters have values now
            continue
        binding = owner.parameter_binding(member)
        values[symbol] = _evaluated(binding, owner)
    return _python(value.xreplace({k: sp.sympify(v) for k, v in values.items()}))


def _element_modifiers(modifiers: dict, i: int, n: int) -> dict:
    """The modifiers of element ``i`` of an array of ``n`` components (a list of ``n`` values
    gives one to each; anything else is every element's, Modelica's ``each``)."""
    out = {}
    for key, value in modifiers.items():
        if isinstance(value, dict):
            out[key] = _element_modifiers(value, i, n)
        elif isinstance(value, list) and len(value) == n:
            out[key] = value[i]
        else:
            out[key] = value
    return out


def _modelica_class(annotation) -> str | None:
    """The class a model written by :func:`acausal.modelica.dump` reproduces:
    ``annotation(__acausal(modelicaClass="..."))``, or None."""
    for element, items in _modifications(annotation) if annotation is not None else []:
        if element != "__acausal":
            continue
        for item in items:
            if _is_modification(item):
                for key, inner in _modifications(item):
                    literal = _literal(inner[-1]) if inner else _NOT_LITERAL
                    if key == "modelicaClass" and isinstance(literal, str) and literal:
                        return literal
    return None


def _experiment(annotation) -> Experiment | None:
    """``annotation(experiment(StartTime=..., StopTime=..., Interval=..., Tolerance=...))``."""
    for element, items in _modifications(annotation) if annotation is not None else []:
        if element != "experiment":
            continue
        values = {}
        for item in items:
            if _is_modification(item):
                for key, inner in _modifications(item):
                    literal = _literal(inner[-1]) if inner else _NOT_LITERAL
                    if literal is not _NOT_LITERAL:
                        values[key] = literal
        names = {"StartTime": "start_time", "StopTime": "stop_time", "Interval": "interval",
                 "Tolerance": "tolerance"}
        return Experiment(**{names[k]: float(v) for k, v in values.items() if k in names})
    return None


# ---------------------------------------------------------------------------
# The entry point
# ---------------------------------------------------------------------------


def load(source: str | os.PathLike, name: str | None = None) -> type[Model]:
    """The acausal model class of a Modelica model.

    Parameters
    ----------
    source : str or path
        A ``.mo`` file's path, or Modelica text.
    name : str, optional
        The class to load (short or full name); default the one model the
        text defines that no other of its models uses.

    Returns
    -------
    type
        A subclass of :class:`~acausal.Model` whose ``modelica_class`` is the
        class's full name (so ``compare`` finds its reference results) and
        whose ``experiment`` is the annotation's.

    Raises
    ------
    ModelicaSyntaxError
        For text that does not parse (file, line, column).
    ModelicaError
        For an undefined name (with the close names), an unsupported
        construct, or a Modelica Standard Library class acausal lacks.
    """
    reader = Reader(parse(source))
    return reader.make(reader.main_class(name), top=True)
