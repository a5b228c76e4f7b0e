"""The unit check (acausal.compiler.units): Modelica unit strings, and the units of equations."""

from __future__ import annotations

import math
import warnings

import pytest
import sympy as sp

from acausal import Model, Parameter, Variable, der
from acausal.compiler.flatten import flatten
from acausal.compiler.units import UnitReport, check_units, format_unit, parse_unit
from acausal.errors import UnitError, UnitWarning
from acausal.language import Eq, If, time


# --------------------------------------------------------------------------
# unit strings


@pytest.mark.parametrize("one, other", [
    ("N.m", "kg.m2/s2"),
    ("W", "J/s"),
    ("J", "N.m"),
    ("N", "kg.m.s-2"),
    ("Hz", "1/s"),
    ("s-1", "1/s"),
    ("Pa", "N/m2"),
    ("J/(kg.K)", "J.kg-1.K-1"),
    ("W/K", "J/(s.K)"),
    ("rad/s", "1/s"),            # rad is dimensionless (SI, OpenModelica's checker)
    ("N.m.s/rad", "kg.m2/s"),
    ("degC", "K"),
    ("kg.m2", "J.s2"),
])
def test_equal_units(one, other):
    assert parse_unit(one).same_as(parse_unit(other)), (one, other)


def test_prefixes_scale_the_symbol():
    assert parse_unit("mm").exponents == parse_unit("m").exponents
    assert math.isclose(parse_unit("mm").scale, 1e-3)
    assert math.isclose(parse_unit("kN").scale, 1e3)
    assert math.isclose(parse_unit("MPa").scale, 1e6)
    assert math.isclose(parse_unit("uA").scale, 1e-6)
    assert math.isclose(parse_unit("kg").scale, 1.0)
    assert math.isclose(parse_unit("g").scale, 1e-3)
    # a whole symbol wins over a prefix: min is minutes, Pa is pascal, cd is candela
    assert math.isclose(parse_unit("min").scale, 60.0)
    assert not parse_unit("mm").same_as(parse_unit("m"))
    # the temperature symbols of Modelica.Units.NonSI: a degree Fahrenheit or Rankine is 5/9 K
    for symbol in ("degF", "degRk"):
        assert parse_unit(symbol).exponents == parse_unit("K").exponents
        assert math.isclose(parse_unit(symbol).scale, 5 / 9)


def test_exponents_and_dimensionless():
    assert parse_unit("m2").exponents == (parse_unit("m") ** 2).exponents
    assert parse_unit("1").is_dimensionless
    assert parse_unit("rad").is_dimensionless
    assert parse_unit("") is None  # unknown, not dimensionless
    assert not parse_unit("N.m").is_dimensionless


@pytest.mark.parametrize("text", ["foo", "m//s", "m/s/s", "N m", "m(2", "kg.", "2m"])
def test_bad_unit_strings(text):
    with pytest.raises(ValueError, match="unit"):
        parse_unit(text)


def test_format_in_modelica_syntax():
    assert format_unit(parse_unit("kg.m2/s2")) == "N.m"
    assert format_unit(parse_unit("m/s2")) == "m/s2"
    assert format_unit(parse_unit("J/(kg.K)")) == "m2/(s2.K)"
    assert format_unit(parse_unit("1/s")) == "1/s"
    assert format_unit(parse_unit("1")) == "1"


# --------------------------------------------------------------------------
# equations


def _check(model, **kw) -> tuple[UnitReport, list]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        report = check_units(flatten(model), **kw)
    return report, [w for w in caught if issubclass(w.category, UnitWarning)]


class SpeedPlusDamping(Model):
    """Adds rad/s to N.m.s/rad: the mistake the check is for."""

    d = Parameter(2.0, unit="N.m.s/rad")
    T = Parameter(0.5, unit="s")
    w = Variable(unit="rad/s", start=1.0, fixed=True)
    y = Variable(unit="rad/s")

    def equations(self):
        return [Eq(der(self.w), -self.w / self.T), Eq(self.y, self.w + self.d)]


class Consistent(Model):
    J = Parameter(2.0, unit="kg.m2")
    d = Parameter(0.5, unit="N.m.s/rad")
    phi = Variable(unit="rad", start=0.0, fixed=True)
    w = Variable(unit="rad/s", start=1.0, fixed=True)
    tau = Variable(unit="N.m")
    P = Variable(unit="W")

    def equations(self):
        return [Eq(der(self.phi), self.w), Eq(self.J * der(self.w), self.tau), Eq(self.tau, -self.d * self.w),
                Eq(self.P, self.tau * self.w)]


def test_rad_per_second_plus_damping_is_one_warning_naming_equation_and_units():
    report, caught = _check(SpeedPlusDamping())
    assert len(report.findings) == 1 and len(caught) == 1
    finding = report.findings[0]
    assert {finding.unit, finding.other_unit} == {"rad/s", "N.m.s/rad"}
    message = str(caught[0].message)
    assert "SpeedPlusDamping eq. 2" in message
    assert "y = d + w" in message
    assert "rad/s" in message and "N.m.s/rad" in message
    assert finding.origin.index == 1
    assert not report.ok


def test_strict_raises_unit_error():
    with pytest.raises(UnitError, match="inconsistent units") as info:
        check_units(flatten(SpeedPlusDamping()), strict=True)
    assert "N.m.s/rad" in str(info.value)
    assert isinstance(info.value, ValueError)  # a model definition error


def test_consistent_model_gives_no_finding():
    report, caught = _check(Consistent())
    assert report.ok and not caught
    assert report.checked == 4


class DerivativeWithoutPerSecond(Model):
    s = Variable(unit="m", start=0.0, fixed=True)
    v = Variable(unit="m")  # wrong: der(s) is in m/s

    def equations(self):
        return [Eq(der(self.s), self.v)]


class DerivativeRight(Model):
    s = Variable(unit="m", start=0.0, fixed=True)
    v = Variable(unit="m/s", start=0.0, fixed=True)
    a = Variable(unit="m/s2")

    def equations(self):
        return [Eq(der(self.s), self.v), Eq(der(self.v), self.a), Eq(self.a, 9.81 - 0 * time)]


def test_der_divides_by_seconds():
    report, _ = _check(DerivativeWithoutPerSecond())
    assert len(report.findings) == 1
    assert {report.findings[0].unit, report.findings[0].other_unit} == {"m/s", "m"}
    assert _check(DerivativeRight())[0].ok


class SineOfLength(Model):
    x = Variable(unit="m")
    y = Variable(unit="1")
    f = Parameter(2.0, unit="Hz")

    def equations(self):
        return [Eq(self.x, 1 + 0 * time), Eq(self.y, sp.sin(self.x))]


class SineOfPhase(Model):
    y = Variable(unit="1")
    f = Parameter(2.0, unit="Hz")
    phase = Parameter(0.1, unit="rad")

    def equations(self):
        return [Eq(self.y, sp.sin(2 * sp.pi * self.f * time + self.phase) + sp.cos(self.phase))]


def test_sine_needs_a_dimensionless_argument():
    report, _ = _check(SineOfLength())
    assert len(report.findings) == 1
    assert "sin" in report.findings[0].hint and report.findings[0].unit == "m"
    assert _check(SineOfPhase())[0].ok


class Literals(Model):
    T = Variable(unit="K")
    s = Variable(unit="m")
    t_half = Parameter(3.0, unit="s")

    def equations(self):
        # a number alone adapts to the sum; a numeric coefficient adapts its product
        return [Eq(self.T, 293.15 + 0 * time), Eq(self.s, 0.5 * 9.81 * self.t_half**2)]


def test_literals_adapt():
    assert _check(Literals())[0].ok


class UnknownUnit(Model):
    k = Parameter(3.0)  # no unit: not checked
    x = Variable(unit="m")
    y = Variable(unit="s")

    def equations(self):
        return [Eq(self.x, self.k * self.y + 0 * time), Eq(self.y, 1 + 0 * time)]


def test_empty_unit_is_a_wildcard():
    assert _check(UnknownUnit())[0].ok


class BranchesAndRelations(Model):
    x = Variable(unit="m")
    v = Variable(unit="m/s")
    limit = Parameter(1.0, unit="m")
    speed = Parameter(1.0, unit="m/s")

    def equations(self):
        return [Eq(self.x, time * self.speed),
                Eq(self.v, If(self.x > self.speed, self.speed, -self.speed))]


class PowersAndMinMax(Model):
    A = Variable(unit="m2")
    r = Variable(unit="m")
    lo = Parameter(0.1, unit="m")

    def equations(self):
        return [Eq(self.r, sp.Max(self.lo, sp.sqrt(self.A))), Eq(self.A, self.lo**2 + 0 * time)]


def test_relation_sides_and_branches_share_a_unit():
    report, _ = _check(BranchesAndRelations())
    assert len(report.findings) == 1
    assert {report.findings[0].unit, report.findings[0].other_unit} == {"m", "m/s"}
    assert "relation" in report.findings[0].hint
    assert _check(PowersAndMinMax())[0].ok


class Scales(Model):
    a = Variable(unit="mm")
    b = Variable(unit="m")

    def equations(self):
        return [Eq(self.a, self.b), Eq(self.b, 1 + 0 * time)]


def test_same_dimension_other_scale_is_found():
    report, _ = _check(Scales())
    assert len(report.findings) == 1
    assert "scale" in report.findings[0].hint


class BadUnitString(Model):
    x = Variable(unit="furlong")

    def equations(self):
        return [Eq(self.x, time)]


def test_unit_strings_not_understood_are_reported_not_checked():
    report, caught = _check(BadUnitString())
    assert report.ok and not caught
    assert report.unparsed == (("x", "furlong"),)
    assert "furlong" in str(report)
