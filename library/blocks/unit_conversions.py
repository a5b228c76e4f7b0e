"""Conversion blocks between SI and non-SI unit signals (Modelica.Blocks.Math.UnitConversions).

Every block is ``y = conversion(u)``, one of Modelica.Units.Conversions'
``to_<unit>`` (from the SI unit) or ``from_<unit>`` (to the SI unit), with
the two connectors in their units.  The 26 blocks differ only in the
conversion and the units, so they are made from one table,
:data:`CONVERSIONS`: a pair ``To_<name>``/``From_<name>`` per row, each
with its MSL name (``Modelica.Blocks.Math.UnitConversions.To_degC``) and its
own docstring.  Import them from this module (``from
acausal.library.blocks.unit_conversions import To_degC``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import sympy as sp

from acausal.language import Component, Eq, RealInput, RealOutput

__all__ = ["PartialConversionBlock", "CONVERSIONS", "Conversion"]

#: Absolute zero in degree Celsius (Modelica.Constants.T_zero)
T_ZERO = sp.Rational(-27315, 100)

class PartialConversionBlock(Component):
    """Partial block defining the interface for conversion blocks
    (Modelica.Blocks.Interfaces.PartialConversionBlock): ``u`` and ``y``, whose units the
    conversions set."""

    modelica_name = "Modelica.Blocks.Interfaces.PartialConversionBlock"

    u = RealInput(description="Connector of Real input signal to be converted")
    y = RealOutput(description="Connector of Real output signal containing input signal u in another unit")


@dataclass(frozen=True)
class Conversion:
    """One row of the table: the unit ``name`` (non-SI), its SI counterpart and both directions."""

    name: str
    si_unit: str
    unit: str
    to_unit: Callable[[sp.Expr], sp.Expr]
    from_unit: Callable[[sp.Expr], sp.Expr]
    to_text: str
    from_text: str


#: The MSL's conversions (Modelica.Units.Conversions), in the order of Modelica.Blocks.Math.UnitConversions.
CONVERSIONS: tuple[Conversion, ...] = (
    Conversion("degC", "K", "degC", lambda kelvin: kelvin + T_ZERO, lambda celsius: celsius - T_ZERO,
               "Kelvin to degCelsius", "degCelsius to Kelvin"),
    Conversion("degF", "K", "degF",
               lambda kelvin: (kelvin + T_ZERO) * sp.Rational(9, 5) + 32,
               lambda fahrenheit: (fahrenheit - 32) * sp.Rational(5, 9) - T_ZERO,
               "Kelvin to degFahrenheit", "degFahrenheit to Kelvin"),
    Conversion("degRk", "K", "degRk", lambda kelvin: sp.Rational(9, 5) * kelvin,
               lambda rankine: sp.Rational(5, 9) * rankine, "Kelvin to degRankine", "degRankine to Kelvin"),
    Conversion("deg", "rad", "deg", lambda radian: (180 / sp.pi) * radian, lambda degree: (sp.pi / 180) * degree,
               "radian to degree", "degree to radian"),
    Conversion("rpm", "rad/s", "rev/min", lambda rs: (30 / sp.pi) * rs, lambda rpm: (sp.pi / 30) * rpm,
               "radian per second to revolutions per minute", "revolutions per minute to radian per second"),
    Conversion("kmh", "m/s", "km/h", lambda ms: sp.Rational(36, 10) * ms, lambda kmh: kmh / sp.Rational(36, 10),
               "metre per second to kilometre per hour", "kilometre per hour to metre per second"),
    Conversion("day", "s", "d", lambda s: s / 86400, lambda day: 86400 * day, "second to day", "day to second"),
    Conversion("hour", "s", "h", lambda s: s / 3600, lambda hour: 3600 * hour, "second to hour", "hour to second"),
    Conversion("minute", "s", "min", lambda s: s / 60, lambda minute: 60 * minute,
               "second to minute", "minute to second"),
    Conversion("litre", "m3", "l", lambda m3: 1000 * m3, lambda litre: litre / 1000,
               "cubic metre to litre", "litre to cubic metre"),
    Conversion("kWh", "J", "kW.h", lambda joule: joule / sp.Integer(3600000), lambda kwh: 3600000 * kwh,
               "Joule to kilo Watt hour", "kilo Watt hour to Joule"),
    Conversion("bar", "Pa", "bar", lambda pa: pa / 100000, lambda bar: 100000 * bar,
               "Pascal to bar", "bar to Pascal"),
    Conversion("gps", "kg/s", "g/s", lambda kgps: 1000 * kgps, lambda gps: gps / 1000,
               "kilogram per second to gram per second", "gram per second to kilogram per second"),
)


def _conversion_block(name: str, function: Callable[[sp.Expr], sp.Expr], u_unit: str, y_unit: str,
                      text: str) -> type:
    """The block ``y = function(u)`` named ``Modelica.Blocks.Math.UnitConversions.<name>``."""

    def equations(self) -> list:
        return [Eq(self.y, function(self.u))]

    return type(name, (PartialConversionBlock,), {
        "__doc__": f"Convert from {text} (Modelica.Blocks.Math.UnitConversions.{name}): ``u`` in {u_unit}, "
                   f"``y`` in {y_unit}.",
        "__module__": __name__,
        "__qualname__": name,
        "modelica_name": f"Modelica.Blocks.Math.UnitConversions.{name}",
        "u": RealInput(unit=u_unit, description="Connector of Real input signal to be converted"),
        "y": RealOutput(unit=y_unit,
                        description="Connector of Real output signal containing input signal u in another unit"),
        "equations": equations,
    })


for _row in CONVERSIONS:
    for _name, _function, _u_unit, _y_unit, _text in (
            (f"To_{_row.name}", _row.to_unit, _row.si_unit, _row.unit, _row.to_text),
            (f"From_{_row.name}", _row.from_unit, _row.unit, _row.si_unit, _row.from_text)):
        globals()[_name] = _conversion_block(_name, _function, _u_unit, _y_unit, _text)
        __all__.append(_name)
del _row, _name, _function, _u_unit, _y_unit, _text
