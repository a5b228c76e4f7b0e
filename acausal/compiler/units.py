"""The unit check: every equation's terms in the same unit, as Modelica's "check model" does.

Units come from sympy.physics.units (already a dependency, kept with sympy): its
SI table gives each Modelica unit symbol and prefix its base dimensions and scale,
so only Modelica's small unit grammar is parsed here.

A unit is a vector of exponents over the seven SI base dimensions and a scale
(``mm`` is ``m`` with scale 1e-3).  The unit of every term of an equation is
derived from the declared ``unit=`` strings of the variables and parameters it
names; the terms of a sum (and so the two sides of an equation, whose residual
is ``lhs - rhs``), the two sides of a relation and the branches of an ``if``
must agree.

Choices, and why:

* ``rad`` (and ``sr``) are dimensionless, as in SI and in OpenModelica's unit
  checker (its table gives ``rad`` no dimension).  The MSL writes ``w`` in
  ``rad/s``, a rolling radius in ``m`` and ``phi*radius = s``; only with a
  dimensionless radian do all of these check.  Adding ``rad/s`` to
  ``N.m.s/rad`` is still caught: ``1/s`` is not ``kg.m2/s``.
* Numbers adapt (Modelica's literals have no unit): a number standing alone
  in a sum takes the unit of the others (``T = 293.15``), and a numeric
  coefficient other than a sign makes its product adapt too (``2*pi*f*t``
  may be added to a phase).  A sign (-1, which every residual has) does not.
* An empty unit (``""``) is unknown, not dimensionless: the variable is a
  wildcard, and so is every product it enters; only ``"1"`` is dimensionless.
* Results of functions acausal does not know (tables, prescribed signals)
  are wildcards; their arguments are still checked inside.

References
----------
.. [1] Modelica Association, *Modelica Language Specification* 3.6, chapter 19
   "Unit Expressions" (the grammar of unit strings parsed here).
.. [2] P. Aronsson and D. Broman, "Extendable Physical Unit Checking with
   Understandable Error Reporting", Proc. 7th Int. Modelica Conference, 2009.
"""

from __future__ import annotations

import functools
import math
import re
import warnings
from dataclasses import dataclass
from fractions import Fraction
from typing import Iterable, Mapping

import sympy as sp
from sympy.core.function import AppliedUndef
from sympy.logic.boolalg import Boolean as SympyBoolean
from sympy.physics import units as sympy_units
from sympy.physics.units.systems.si import SI, dimsys_SI

from .. import hybrid
from ..errors import UnitError, UnitWarning
from ..language import time as time_symbol
from ..names import parse
from .flatten import FlatModel, Origin

__all__ = [
    "Unit",
    "parse_unit",
    "format_unit",
    "UnitFinding",
    "UnitReport",
    "check_units",
    "check_equations",
]


# --------------------------------------------------------------------------
# units: exponents over the SI base dimensions, and a scale

#: The SI base dimensions, in the order Modelica writes units (kg.m2/s2).
_BASE = ("mass", "length", "time", "current", "temperature", "amount_of_substance", "luminous_intensity")
#: Their coherent SI units, for printing.
_BASE_SYMBOLS = ("kg", "m", "s", "A", "K", "mol", "cd")

#: Modelica unit symbols (spec 19.2) and the sympy quantity each one is.
_SYMBOL_QUANTITIES = {
    "m": "meter", "s": "second", "g": "gram", "A": "ampere", "K": "kelvin", "mol": "mole",
    "cd": "candela", "rad": "radian", "Hz": "hertz", "N": "newton", "Pa": "pascal",
    "J": "joule", "W": "watt", "C": "coulomb", "V": "volt", "F": "farad", "Ohm": "ohm",
    "S": "siemens", "Wb": "weber", "T": "tesla", "H": "henry", "lm": "lumen", "lx": "lux",
    "Bq": "becquerel", "Gy": "gray", "kat": "katal", "min": "minute", "h": "hour", "d": "day",
    "l": "liter", "L": "liter", "bar": "bar", "deg": "degree", "eV": "electronvolt",
    # a temperature difference in degC is one in K; the offset is not a unit matter
    "degC": "kelvin",
}
#: Dimensionless symbols sympy gives a dimension of their own (SI: sr = m2/m2).
_DIMENSIONLESS_SYMBOLS = {"sr": 1.0, "rev": 2 * math.pi}
#: Temperature symbols of Modelica.Units.NonSI sympy lacks, as their size in kelvin (a
#: difference of 1 degF or 1 degRk is 5/9 K; the offset of degF is not a unit matter).
_TEMPERATURE_SYMBOLS = {"degF": 5.0 / 9.0, "degRk": 5.0 / 9.0}

#: Modelica's prefixes (spec 19.2): sympy's, with ``u`` for micro as Modelica writes it.
_PREFIXES = {**{name: float(p.scale_factor) for name, p in sympy_units.prefixes.PREFIXES.items()},
             "u": 1e-6}


@dataclass(frozen=True)
class Unit:
    """A physical unit: exponents of the SI base dimensions and a scale.

    Attributes
    ----------
    exponents : tuple of Fraction
        Exponents of kg, m, s, A, K, mol, cd.
    scale : float
        Its size in coherent SI units (1e-3 for ``mm``, 60 for ``min``).
    """

    exponents: tuple[Fraction, ...]
    scale: float = 1.0

    def __mul__(self, other: "Unit") -> "Unit":
        return Unit(tuple(a + b for a, b in zip(self.exponents, other.exponents)), self.scale * other.scale)

    def __truediv__(self, other: "Unit") -> "Unit":
        return Unit(tuple(a - b for a, b in zip(self.exponents, other.exponents)), self.scale / other.scale)

    def __pow__(self, power: Fraction) -> "Unit":
        return Unit(tuple(a * power for a in self.exponents), self.scale ** float(power))

    @property
    def is_dimensionless(self) -> bool:
        return not any(self.exponents)

    def same_as(self, other: "Unit") -> bool:
        """Same dimensions and the same scale (``mm`` is not ``m``)."""
        return self.exponents == other.exponents and math.isclose(self.scale, other.scale, rel_tol=1e-9)

    def __str__(self) -> str:
        return format_unit(self)


ONE = Unit((Fraction(0),) * len(_BASE))
SECOND = Unit(tuple(Fraction(int(b == "time")) for b in _BASE))


@functools.lru_cache(maxsize=None)
def _symbol_unit(symbol: str) -> Unit | None:
    """The unit of a Modelica unit symbol without prefix, or None."""
    if symbol in _DIMENSIONLESS_SYMBOLS:
        return Unit(ONE.exponents, _DIMENSIONLESS_SYMBOLS[symbol])
    if symbol in _TEMPERATURE_SYMBOLS:
        kelvin = _symbol_unit("K")
        return Unit(kelvin.exponents, _TEMPERATURE_SYMBOLS[symbol])
    name = _SYMBOL_QUANTITIES.get(symbol)
    if name is None:
        return None
    quantity = getattr(sympy_units, name)
    dependencies = dimsys_SI.get_dimensional_dependencies(SI.get_quantity_dimension(quantity))
    by_name = {str(dimension.name): Fraction(int(power)) for dimension, power in dependencies.items()}
    exponents = tuple(by_name.pop(base, Fraction(0)) for base in _BASE)
    if by_name:  # a dimension outside SI's seven: not a unit this check knows
        return None
    # sympy's base of mass is the gram: scale relative to the kilogram
    scale = float(SI.get_quantity_scale_factor(quantity)) / 1000.0 ** float(exponents[0])
    return Unit(exponents, scale)


_FACTOR = re.compile(r"([A-Za-z]+)([+-]?\d+)?$")


def _operand_unit(text: str) -> Unit | None:
    """``text`` as a unit symbol, or a prefix and a symbol (the whole symbol wins: ``min``, ``Pa``)."""
    found = _symbol_unit(text)
    if found is not None:
        return found
    for size in (2, 1):
        prefix, rest = text[:size], text[size:]
        if prefix in _PREFIXES and rest:
            found = _symbol_unit(rest)
            if found is not None:
                return Unit(found.exponents, found.scale * _PREFIXES[prefix])
    return None


def _split_top(text: str, separator: str) -> list[str]:
    """``text`` split at ``separator`` outside parentheses."""
    parts, depth, start = [], 0, 0
    for i, char in enumerate(text):
        depth += (char == "(") - (char == ")")
        if depth < 0:
            raise ValueError("unbalanced parentheses")
        if char == separator and depth == 0:
            parts.append(text[start:i])
            start = i + 1
    if depth:
        raise ValueError("unbalanced parentheses")
    parts.append(text[start:])
    return parts


def _parse(text: str) -> Unit:
    if text.startswith("(") and _balanced_whole(text):
        return _parse(text[1:-1])
    parts = _split_top(text, "/")
    if len(parts) > 2:
        raise ValueError("more than one '/' outside parentheses")
    unit = _factors(parts[0])
    if len(parts) == 2:
        unit = unit / _factors(parts[1])
    return unit


def _balanced_whole(text: str) -> bool:
    """Whether the parenthesis at the start of ``text`` closes at its end."""
    depth = 0
    for i, char in enumerate(text):
        depth += (char == "(") - (char == ")")
        if depth == 0 and i < len(text) - 1:
            return False
    return True


def _factors(text: str) -> Unit:
    if text == "1":
        return ONE
    if text.startswith("(") and _balanced_whole(text):
        return _parse(text[1:-1])
    unit = ONE
    for factor in _split_top(text, "."):
        if factor.startswith("(") and _balanced_whole(factor):
            unit = unit * _parse(factor[1:-1])
            continue
        match = _FACTOR.match(factor)
        if match is None:
            raise ValueError(f"{factor!r} is not a unit factor")
        operand = _operand_unit(match.group(1))
        if operand is None:
            raise ValueError(f"unknown unit symbol {match.group(1)!r}")
        unit = unit * operand ** Fraction(int(match.group(2) or 1))
    return unit


@functools.lru_cache(maxsize=None)
def parse_unit(text: str) -> Unit | None:
    """The unit a Modelica unit string denotes; None for ``""`` (unknown).

    Parameters
    ----------
    text : str
        A unit expression of Modelica's grammar: factors joined by ``.``, one
        ``/``, integer exponents after the symbol (``kg.m2/s2``, ``s-1``),
        prefixes (``kN``, ``mm``), parentheses (``J/(kg.K)``); ``"1"`` is
        dimensionless.

    Raises
    ------
    ValueError
        If ``text`` is not a unit expression or names an unknown symbol.
    """
    text = text.strip()
    if not text:
        return None
    if any(char.isspace() for char in text):
        raise ValueError(f"unit {text!r}: Modelica unit strings have no spaces")
    try:
        return _parse(text)
    except ValueError as exc:
        raise ValueError(f"unit {text!r}: {exc}") from None


#: Derived units printed by name when a unit is exactly one of them.
_NAMED = ("N", "N.m", "W", "Pa", "N/m", "N.s/m", "N.m.s", "W/K", "J/K", "kg.m2")


@functools.lru_cache(maxsize=None)
def _named_units() -> dict[tuple[Fraction, ...], str]:
    return {parse_unit(name).exponents: name for name in _NAMED}


def format_unit(unit: Unit) -> str:
    """``unit`` in Modelica syntax, base units (``kg.m2/s``) or a common derived name (``N.m``)."""
    named = _named_units().get(unit.exponents) if math.isclose(unit.scale, 1.0) else None
    if named is not None:
        return named

    def power(symbol: str, exponent: Fraction) -> str:
        if exponent == 1:
            return symbol
        if exponent.denominator == 1:
            return f"{symbol}{exponent.numerator}"
        return f"{symbol}^({exponent})"  # not Modelica syntax: it has no fractional exponents

    numerator = [power(s, e) for s, e in zip(_BASE_SYMBOLS, unit.exponents) if e > 0]
    denominator = [power(s, -e) for s, e in zip(_BASE_SYMBOLS, unit.exponents) if e < 0]
    text = ".".join(numerator) or "1"
    if len(denominator) == 1:
        text += "/" + denominator[0]
    elif denominator:
        text += "/(" + ".".join(denominator) + ")"
    if not math.isclose(unit.scale, 1.0):
        text = f"{unit.scale:g}*{text}"
    return text


# --------------------------------------------------------------------------
# findings


@dataclass(frozen=True)
class UnitFinding:
    """An equation whose terms are in different units.

    Attributes
    ----------
    origin : Origin
        Where the equation comes from (component, class, equation number, text).
    unit : str
        The unit of the first term, in Modelica syntax (the declared unit
        string where the term is one variable or parameter).
    other_unit : str
        The unit of the first term that disagrees with it.
    hint : str
        Which terms disagree, and what to look at.
    kind : str
        'equation', 'initial equation', 'discrete equation' or 'reinit'.
    """

    origin: Origin
    unit: str
    other_unit: str
    hint: str
    kind: str = "equation"

    @property
    def where(self) -> str:
        """The equation's origin: component, its class, the class that wrote it and the number."""
        origin = self.origin
        component = origin.component or "(model)"
        if origin.declared_in in ("connect", "unconnected", "binding", "relaxation", ""):
            return f"{component}: {origin.declared_in or self.kind}"
        own = f"{origin.component_class}, " if origin.component_class and origin.component_class != origin.declared_in else ""
        return f"{component} ({own}{origin.declared_in} eq. {origin.index + 1})"

    @property
    def message(self) -> str:
        kind = "" if self.kind == "equation" else f" ({self.kind})"
        return f"{self.where}{kind}: {self.origin.text}: units differ: {self.unit} vs {self.other_unit}"

    def __str__(self) -> str:
        return f"{self.message}\n  hint: {self.hint}"


@dataclass(frozen=True)
class UnitReport:
    """What the unit check found in a flat model.

    Attributes
    ----------
    model : str
    checked : int
        Equations checked.
    findings : tuple of UnitFinding
        Equations whose terms are in different units.
    unparsed : tuple of (str, str)
        ``(name, unit string)`` of declarations whose unit string is not a
        Modelica unit expression (treated as unknown).
    """

    model: str
    checked: int
    findings: tuple[UnitFinding, ...] = ()
    unparsed: tuple[tuple[str, str], ...] = ()

    @property
    def ok(self) -> bool:
        """No equation with inconsistent units."""
        return not self.findings

    def __str__(self) -> str:
        lines = [f"units of {self.model}: {self.checked} equations checked, "
                 f"{len(self.findings)} with inconsistent units"]
        lines += [f"  {finding.message}\n    hint: {finding.hint}" for finding in self.findings]
        for name, text in self.unparsed:
            lines.append(f"  unit of {name} not understood: {text!r} (treated as unknown)")
        return "\n".join(lines)


# --------------------------------------------------------------------------
# deriving the unit of an expression


@dataclass(frozen=True)
class _Known:
    """A term's unit; ``text`` is the declared string when the term is one declaration."""

    unit: Unit
    text: str | None = None

    def shown(self) -> str:
        return self.text if self.text is not None else format_unit(self.unit)


#: A term whose unit adapts (a number, an unknown declaration, an unknown function).
_WILD = None

_DIMENSIONLESS = _Known(ONE)

#: Functions that need a dimensionless argument and give a dimensionless result.
_TRANSCENDENTAL = (sp.sin, sp.cos, sp.tan, sp.cot, sp.asin, sp.acos, sp.atan, sp.acot, sp.sinh, sp.cosh,
                   sp.tanh, sp.asinh, sp.acosh, sp.atanh, sp.exp, sp.log)
#: Functions whose result has the unit of their argument.
_PASS_THROUGH = (sp.Abs, sp.floor, sp.ceiling, hybrid.NoEvent, hybrid.floor, hybrid.ceil, hybrid.integer)
#: Functions whose arguments share one unit, which is also the result's.
_SAME_UNIT = (sp.Min, sp.Max, hybrid.mod, hybrid.rem, sp.Mod)
_RELATIONS = (sp.StrictGreaterThan, sp.GreaterThan, sp.StrictLessThan, sp.LessThan, sp.Equality, sp.Unequality)


class _Mismatch(Exception):
    """Terms of one sum (or relation, or branches) in different units."""

    def __init__(self, terms: list[tuple[sp.Basic, _Known]], what: str) -> None:
        super().__init__(what)
        self.terms, self.what = terms, what
        self.first = terms[0][1]
        self.other = next(known for _, known in terms if not known.unit.same_as(self.first.unit))


class _Deriver:
    """Derives the unit of expressions from the declared units of the symbols they name."""

    def __init__(self, units: Mapping[str, str]) -> None:
        self.declared: dict[str, _Known | None] = {}
        self.unparsed: list[tuple[str, str]] = []
        for name, text in units.items():
            try:
                unit = parse_unit(text)
            except ValueError:
                self.unparsed.append((name, text))
                unit = None
            self.declared[name] = _WILD if unit is None else _Known(unit, text.strip())
        self.mismatches: list[_Mismatch] = []

    # the symbols ---------------------------------------------------------

    def symbol(self, symbol: sp.Symbol) -> _Known | None:
        if symbol == time_symbol:
            return _Known(SECOND, "s")
        name = symbol.name
        if name in self.declared:
            return self.declared[name]
        meaning = parse(name)
        if meaning.kind == "derivative":
            return self.derivative(self.declared.get(meaning.base), meaning.order)
        if meaning.kind == "pre":
            return self.declared.get(meaning.base)
        return _WILD  # relation indicators, clocks, initial(): Booleans; the engine's own variables

    @staticmethod
    def derivative(of: _Known | None, order: int) -> _Known | None:
        if of is None:
            return _WILD
        unit = of.unit / SECOND ** Fraction(order)
        text = None
        if of.text is not None and "(" not in of.text:
            # rad/s -> rad/s2, m -> m/s: the declared form, still Modelica syntax
            numerator, slash, denominator = of.text.partition("/")
            if not slash:
                text = f"{numerator}/s{order if order > 1 else ''}"
            elif re.fullmatch(r"s(\d*)", denominator):
                text = f"{numerator}/s{int(denominator[1:] or 1) + order}"
        return _Known(unit, text)

    # expressions ---------------------------------------------------------

    def unit_of(self, expr: sp.Basic) -> _Known | None:
        """The unit of ``expr``, None where it adapts; a sum that disagrees raises _Mismatch."""
        if isinstance(expr, sp.Symbol):
            return self.symbol(expr)
        if isinstance(expr, (sp.Number, sp.NumberSymbol)) or expr in (sp.pi, sp.E):
            return _WILD
        if isinstance(expr, SympyBoolean):
            self.boolean(expr)
            return _WILD
        if isinstance(expr, sp.Add):
            return self.same(expr.args, "the terms of a sum")
        if isinstance(expr, sp.Mul):
            return self.product(expr)
        if isinstance(expr, sp.Pow):
            return self.power(expr)
        if isinstance(expr, sp.Piecewise):
            for _, condition in expr.args:
                self.boolean(condition)
            return self.same([value for value, _ in expr.args], "the branches of an if-expression")
        if isinstance(expr, _TRANSCENDENTAL):
            self.dimensionless(expr.args, f"the argument of {type(expr).__name__}")
            return _DIMENSIONLESS
        if isinstance(expr, sp.atan2):
            self.same(expr.args, "the arguments of atan2")
            return _DIMENSIONLESS
        if isinstance(expr, (sp.sign, sp.Heaviside)):
            for arg in expr.args:
                self.unit_of(arg)
            return _DIMENSIONLESS
        if isinstance(expr, _PASS_THROUGH):
            found = self.unit_of(expr.args[0])
            return None if found is None else _Known(found.unit)
        if isinstance(expr, _SAME_UNIT):
            found = self.same(expr.args, f"the arguments of {type(expr).__name__}")
            return None if found is None else _Known(found.unit)
        if isinstance(expr, hybrid.div):
            a, b = (self.unit_of(arg) for arg in expr.args)
            return None if a is None or b is None else _Known(a.unit / b.unit)
        if isinstance(expr, AppliedUndef) and type(expr).__name__ == "der" and len(expr.args) == 1:
            return self.derivative(self.unit_of(expr.args[0]), 1)
        if isinstance(expr, AppliedUndef) and type(expr).__name__ == "pre" and len(expr.args) == 1:
            return self.unit_of(expr.args[0])
        # a function the check does not know (a table, a prescribed signal): its
        # result adapts, but what its arguments compute is still checked
        for arg in expr.args:
            if isinstance(arg, sp.Basic):
                self.unit_of(arg)
        return _WILD

    def same(self, terms: Iterable[sp.Basic], what: str) -> _Known | None:
        """The common unit of ``terms`` (None if every one adapts)."""
        known = [(term, found) for term in terms if (found := self.unit_of(term)) is not None]
        if any(not found.unit.same_as(known[0][1].unit) for _, found in known[1:]):
            raise _Mismatch(known, what)
        return known[0][1] if known else _WILD

    def product(self, expr: sp.Mul) -> _Known | None:
        result, adapts, texts = ONE, False, []
        for factor in expr.args:
            if isinstance(factor, sp.Number) and abs(factor) == 1:
                continue  # a sign: residuals are lhs - rhs
            found = self.unit_of(factor)
            if found is None:
                adapts = True  # go on: the other factors are still checked inside
                continue
            result = result * found.unit
            texts.append(found.text)
        if adapts:
            return _WILD
        # -x keeps x's declared text; a real product is shown in base units
        return _Known(result, texts[0] if len(texts) == 1 else None)

    def power(self, expr: sp.Pow) -> _Known | None:
        base, exponent = expr.args
        found = self.unit_of(base)
        if isinstance(exponent, sp.Rational):
            if found is None:
                return _WILD
            return _Known(found.unit ** Fraction(int(exponent.p), int(exponent.q)))
        if isinstance(exponent, sp.Number):  # a float exponent: only a dimensionless base keeps a unit
            self.dimensionless([base], "the base of a non-rational power")
            return _DIMENSIONLESS if found is not None else _WILD
        self.dimensionless([base, exponent], "a power with a variable exponent")
        return _DIMENSIONLESS

    def dimensionless(self, args: Iterable[sp.Basic], what: str) -> None:
        for arg in args:
            found = self.unit_of(arg)
            if found is not None and not found.unit.is_dimensionless:
                raise _Mismatch([(arg, found), (sp.Integer(1), _Known(ONE, "1"))],
                                f"{what} (it must be dimensionless)")

    def boolean(self, expr: sp.Basic) -> None:
        """Check the relations inside a condition (their two sides in one unit)."""
        if isinstance(expr, _RELATIONS):
            self.same(expr.args, "the two sides of a relation")
        elif isinstance(expr, SympyBoolean):
            for arg in expr.args:
                if isinstance(arg, sp.Basic):
                    self.boolean(arg) if isinstance(arg, SympyBoolean) else self.unit_of(arg)
        else:
            self.unit_of(expr)


def _finding(origin: Origin, mismatch: _Mismatch, kind: str) -> UnitFinding:
    first, other = mismatch.first, mismatch.other
    # residuals are lhs - rhs: a term is shown without the sign that put it on the left
    listed = ", ".join(f"{-term if term.could_extract_minus_sign() else term} [{known.shown()}]"
                       for term, known in mismatch.terms[:6])
    more = " ..." if len(mismatch.terms) > 6 else ""
    if first.unit.exponents == other.unit.exponents:
        hint = (f"{mismatch.what} have one dimension but different scales ({listed}{more}): "
                f"a conversion factor is missing")
    else:
        hint = (f"{mismatch.what} must have one unit: {listed}{more}; check the unit= of the "
                f"declarations these terms name")
    return UnitFinding(origin, first.shown(), other.shown(), hint, kind)


def check_equations(equations: Iterable[tuple[sp.Basic, Origin]], units: Mapping[str, str],
                    model: str = "", kind: str = "equation") -> UnitReport:
    """The unit check of ``(residual, origin)`` pairs, with ``units`` the declared unit of each name.

    A residual may also be a sympy ``Equality`` (its two sides are compared),
    and may contain ``der(x)`` and ``pre(x)`` applied to a declaration, as a
    component's equations do before flattening.  No warning is given: see
    :func:`check_units`.
    """
    deriver = _Deriver(units)
    findings, count = [], 0
    for residual, origin in equations:
        count += 1
        try:
            if isinstance(residual, sp.Equality):
                deriver.same(residual.args, "the two sides")
            elif isinstance(residual, sp.Add):
                deriver.same(residual.args, "the terms of both sides")
            else:
                deriver.unit_of(residual)
        except _Mismatch as mismatch:
            findings.append(_finding(origin, mismatch, kind))
    return UnitReport(model, count, tuple(findings), tuple(deriver.unparsed))


def _flat_units(flat: FlatModel) -> dict[str, str]:
    units = {p.name: p.unit for p in flat.parameters}
    for variable in flat.variables:
        # Booleans and Integers have no unit in Modelica
        units[variable.name] = "" if variable.is_discrete else variable.unit
    return units


def check_units(flat: FlatModel, strict: bool = False) -> UnitReport:
    """Check that the terms of every equation of ``flat`` are in one unit.

    The equations, initial equations, discrete equations (``v := rhs``) and
    reinits are checked; each inconsistent one is a :class:`UnitWarning`
    naming its origin and both units.

    Parameters
    ----------
    flat : FlatModel
        The output of :func:`~acausal.compiler.flatten.flatten`.
    strict : bool
        Raise :class:`~acausal.errors.UnitError` instead of warning.

    Returns
    -------
    UnitReport
        Every finding (also when warned), and unit strings not understood.

    Raises
    ------
    UnitError
        With ``strict``, if some equation's units are inconsistent.
    """
    units = _flat_units(flat)
    pairs: list[tuple[sp.Basic, Origin, str]] = [(e.residual, e.origin, "equation") for e in flat.equations]
    pairs += [(e.residual, e.origin, "initial equation") for e in flat.initial_equations]
    for e in flat.discrete_equations:
        pairs.append((sp.Equality(sp.Symbol(e.variable), e.rhs, evaluate=False)
                      if isinstance(e.rhs, sp.Expr) else e.rhs, e.origin, "discrete equation"))
    for r in flat.hybrid.reinits:
        pairs.append((sp.Equality(sp.Symbol(r.variable), r.value, evaluate=False), r.origin, "reinit"))
    findings, unparsed, count = [], (), 0
    for kind in ("equation", "initial equation", "discrete equation", "reinit"):
        part = check_equations([(residual, origin) for residual, origin, k in pairs if k == kind],
                               units, flat.name, kind)
        findings += part.findings
        count += part.checked
        unparsed = part.unparsed
    report = UnitReport(flat.name, count, tuple(findings), unparsed)
    if report.findings:
        if strict:
            shown = report.findings[:10]
            more = len(report.findings) - len(shown)
            lines = "\n  ".join(f.message for f in shown) + (f"\n  ... and {more} more" if more > 0 else "")
            raise UnitError(f"{flat.name}: {len(report.findings)} equation(s) with inconsistent units:\n  {lines}",
                            hint=report.findings[0].hint,
                            components=tuple(dict.fromkeys(f.origin.component for f in report.findings)))
        for finding in report.findings:
            warnings.warn(UnitWarning(str(finding)), stacklevel=2)
    return report
