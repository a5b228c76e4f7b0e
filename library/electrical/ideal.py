"""Ideal switching elements (Modelica.Electrical.Analog.Ideal).

The ideal diode, thyristors and triac, the ideal switches (opening, closing,
two-way, intermediate; driven by a Boolean signal or, the *Controlled*
ones, by the potential of a control pin against ``level``), the switches
with a simple arc model, the ideal transformer, and the idle and short
branches.  The operational amplifiers of the package are in
:mod:`acausal.library.electrical.ideal_opamps`.

As in the MSL, every switching element follows a parametric characteristic:
a dimensionless path parameter ``s`` walks along the conducting or the
blocking straight line, the Boolean ``off`` chooses which, and an event
(``s < 0``, ``control.v > level``) switches it.  Between events each
discrete state is an ordinary linear system, compiled once when first
visited (:class:`acausal.components.electrical.IdealSemiconductor`,
``IdealSwitch``, ``IdealSwitchWithArc``).
"""

from __future__ import annotations

import enum

import sympy as sp

from acausal.hybrid import When, div, integer, mod
from acausal.language import Component, Eq, If, Integer, Parameter, Variable, der
from acausal.components.logic import pre_boolean
from acausal.components.blocks import BooleanInput, IntegerInput, IntegerOutput
from acausal.components.electrical import (
    ConditionalHeatPort,
    IdealSemiconductor,
    IdealSwitch,
    IdealSwitchWithArc,
    NegativePin,
    OnePort,
    Pin,
    PositivePin,
    TwoPort,
    _UnitConstants,
)

from .basic import Capacitor, Resistor

__all__ = [
    "IdealDiode",
    "IdealThyristor",
    "IdealGTOThyristor",
    "IdealTriac",
    "IdealOpeningSwitch",
    "IdealClosingSwitch",
    "ControlledIdealOpeningSwitch",
    "ControlledIdealClosingSwitch",
    "OpenerWithArc",
    "CloserWithArc",
    "ControlledOpenerWithArc",
    "ControlledCloserWithArc",
    "IdealTwoWaySwitch",
    "ControlledIdealTwoWaySwitch",
    "IdealIntermediateSwitch",
    "ControlledIdealIntermediateSwitch",
    "IdealTransformer",
    "Idle",
    "Short",
]


# --------------------------------------------------------------------------
# semiconductors


class IdealDiode(IdealSemiconductor):
    """Ideal diode (Modelica.Electrical.Analog.Ideal.IdealDiode).

    ``off = s < 0``: blocking (``i = Goff*v``) below the knee voltage
    ``Vknee``, conducting (``v = Vknee + Ron*(i - Goff*Vknee)``) above it;
    the switch is a state event where ``s`` crosses zero.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealDiode"

    def equations(self):
        return [Eq(self.off, self.s < 0)]


class IdealThyristor(IdealSemiconductor):
    """Ideal thyristor (Modelica.Electrical.Analog.Ideal.IdealThyristor).

    ``off = s < 0 or pre(off) and not fire``: a blocking thyristor starts
    conducting only when ``fire`` is true (and it is forward biased); once
    on, it stays on until its current falls below the knee, whatever
    ``fire`` does.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealThyristor"

    fire = BooleanInput(description="Gate")

    def equations(self):
        return [Eq(self.off, sp.Or(self.s < 0, sp.And(pre_boolean(self.off), sp.Not(self.fire))))]


class IdealGTOThyristor(IdealSemiconductor):
    """Ideal GTO thyristor (Modelica.Electrical.Analog.Ideal.IdealGTOThyristor).

    ``off = s < 0 or not fire``: a gate turn-off thyristor conducts while
    ``fire`` is true and it is forward biased, and turns off with ``fire``.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealGTOThyristor"

    fire = BooleanInput(description="Gate")

    def equations(self):
        return [Eq(self.off, sp.Or(self.s < 0, sp.Not(self.fire)))]


class IdealTriac(Component):
    """Ideal triac, based on ideal thyristors (Modelica.Electrical.Analog.Ideal.IdealTriac).

    Two antiparallel :class:`IdealThyristor` (``idealThyristor`` from ``n``
    to ``p``, ``idealThyristor1`` from ``p`` to ``n``), both fired by
    ``fire1``, with an RC snubber (``resistor`` ``Rdis`` in series with
    ``capacitor`` ``Cdis``) across them for disturbance elimination.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealTriac"

    Ron = Parameter(1e-5, unit="Ohm", min=0, description="Closed triac resistance")
    Goff = Parameter(1e-5, unit="S", min=0, description="Opened triac conductance")
    Vknee = Parameter(0.8, unit="V", min=0, description="Threshold voltage for positive and negative phase")
    Rdis = Parameter(100.0, unit="Ohm", description="Resistance of disturbance elimination")
    Cdis = Parameter(0.005, unit="F", description="Capacity of disturbance elimination")
    fire1 = BooleanInput(description="Gate")
    n = NegativePin(description="Cathode")
    p = PositivePin(description="Anode")

    def build(self) -> None:
        self.idealThyristor = IdealThyristor(Ron=self.Ron, Goff=self.Goff, Vknee=self.Vknee)  # noqa: N815
        self.idealThyristor1 = IdealThyristor(Ron=self.Ron, Goff=self.Goff, Vknee=self.Vknee)  # noqa: N815
        self.resistor = Resistor(R=self.Rdis)
        self.capacitor = Capacitor(C=self.Cdis)
        self.connect(self.idealThyristor.n, self.capacitor.n)
        self.connect(self.capacitor.n, self.idealThyristor1.p)
        self.connect(self.idealThyristor1.n, self.resistor.p)
        self.connect(self.resistor.p, self.idealThyristor.p)
        self.connect(self.resistor.n, self.capacitor.p)
        self.connect(self.idealThyristor1.fire, self.fire1)
        self.connect(self.idealThyristor.fire, self.fire1)
        self.connect(self.n, self.idealThyristor.p)
        self.connect(self.idealThyristor1.p, self.p)


# --------------------------------------------------------------------------
# one-port switches


class IdealOpeningSwitch(IdealSwitch):
    """Ideal electrical opener (Modelica.Electrical.Analog.Ideal.IdealOpeningSwitch).

    ``off = control``: open while the Boolean input is true.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealOpeningSwitch"

    control = BooleanInput(description="true => switch open, false => p--n connected")

    def equations(self):
        return [Eq(self.off, self.control)]


class IdealClosingSwitch(IdealSwitch):
    """Ideal electrical closer (Modelica.Electrical.Analog.Ideal.IdealClosingSwitch).

    ``off = not control``: closed while the Boolean input is true.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealClosingSwitch"

    control = BooleanInput(description="true => p--n connected, false => switch open")

    def equations(self):
        return [Eq(self.off, sp.Not(self.control))]


class _PinControlled(Component):
    """A control pin that draws no current, compared against ``level`` (the *Controlled* switches)."""

    modelica_name = None

    level = Parameter(0.5, unit="V", description="Switch level")
    control = Pin(description="Control pin (control.v compared with level)")

    def equations(self):
        return [Eq(self.control.i, 0)]


class ControlledIdealOpeningSwitch(IdealSwitch, _PinControlled):
    """Controlled ideal electrical opener (Modelica.Electrical.Analog.Ideal.ControlledIdealOpeningSwitch).

    ``off = control.v > level``: open while the control pin is above
    ``level``; ``control.i = 0``.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.ControlledIdealOpeningSwitch"

    control = Pin(description="Control pin: control.v > level switch open, otherwise p--n connected")

    def equations(self):
        return [Eq(self.off, self.control.v > self.level)]


class ControlledIdealClosingSwitch(IdealSwitch, _PinControlled):
    """Controlled ideal electrical closer (Modelica.Electrical.Analog.Ideal.ControlledIdealClosingSwitch).

    ``off = control.v < level``: closed while the control pin is at or
    above ``level``; ``control.i = 0``.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.ControlledIdealClosingSwitch"

    control = Pin(description="Control pin: control.v > level switch closed, otherwise switch open")

    def equations(self):
        return [Eq(self.off, self.control.v < self.level)]


class OpenerWithArc(IdealSwitchWithArc):
    """Ideal opening switch with simple arc model (Modelica.Electrical.Analog.Ideal.OpenerWithArc).

    ``off = control``; on opening, an arc burns until the current is quenched.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.OpenerWithArc"

    control = BooleanInput(description="false => p--n connected, true => switch open")

    def equations(self):
        return [Eq(self.off, self.control)]


class CloserWithArc(IdealSwitchWithArc):
    """Ideal closing switch with simple arc model (Modelica.Electrical.Analog.Ideal.CloserWithArc).

    ``off = not control``; on opening, an arc burns until the current is quenched.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.CloserWithArc"

    control = BooleanInput(description="true => p--n connected, false => switch open")

    def equations(self):
        return [Eq(self.off, sp.Not(self.control))]


class ControlledOpenerWithArc(IdealSwitchWithArc, _PinControlled):
    """Controlled ideal electrical opener with simple arc model (Modelica.Electrical.Analog.Ideal.ControlledOpenerWithArc).

    ``off = control.v > level``; ``control.i = 0``.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.ControlledOpenerWithArc"

    control = Pin(description="Control pin: control.v > level switch open, otherwise p--n connected")

    def equations(self):
        return [Eq(self.off, self.control.v > self.level)]


class ControlledCloserWithArc(IdealSwitchWithArc, _PinControlled):
    """Controlled ideal electrical closer with simple arc model (Modelica.Electrical.Analog.Ideal.ControlledCloserWithArc).

    ``off = control.v < level``; ``control.i = 0``.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.ControlledCloserWithArc"

    control = Pin(description="Control pin: control.v > level switch closed, otherwise switch open")

    def equations(self):
        return [Eq(self.off, self.control.v < self.level)]


# --------------------------------------------------------------------------
# two-way and intermediate switches


class _MultiPortSwitch(ConditionalHeatPort, _UnitConstants):
    """What the two-way and intermediate switches share: ``Ron``, ``Goff`` and the switching condition.

    ``switched()`` is the condition of the second position (``control``, or
    ``control.v > level``); each path between two pins is a switch on the
    parametric characteristic, closed in one position and open in the other.
    """

    modelica_name = None

    Ron = Parameter(1e-5, unit="Ohm", min=0, description="Closed switch resistance")
    Goff = Parameter(1e-5, unit="S", min=0, description="Opened switch conductance")

    def switched(self) -> sp.Basic:
        """The condition under which the switch is in its second position (override)."""
        raise NotImplementedError

    def switch_path(self, s: sp.Basic, closed: sp.Basic) -> tuple[sp.Basic, sp.Basic]:
        """Voltage and current of one path on the characteristic: closed ``Ron``, else open ``Goff``."""
        return (s * self.unitCurrent * If(closed, self.Ron, 1),
                s * self.unitVoltage * If(closed, 1, self.Goff))


class _TwoWaySwitch(_MultiPortSwitch):
    """Two-way switch: ``p`` connected to ``n1``, or (``switched()``) to ``n2``."""

    modelica_name = None

    p = PositivePin(description="Positive electrical pin")
    n1 = NegativePin(description="Negative electrical pin 1")
    n2 = NegativePin(description="Negative electrical pin 2")
    s1 = Variable(unit="1", description="Auxiliary variable of path p--n1 (protected)")
    s2 = Variable(unit="1", description="Auxiliary variable of path p--n2 (protected)")

    def equations(self):
        to_n2 = self.switched()
        v1, i1 = self.switch_path(self.s1, sp.Not(to_n2))
        v2, i2 = self.switch_path(self.s2, to_n2)
        return [Eq(0, self.p.i + self.n2.i + self.n1.i),
                Eq(self.p.v - self.n1.v, v1), Eq(self.n1.i, -i1),
                Eq(self.p.v - self.n2.v, v2), Eq(self.n2.i, -i2),
                Eq(self.LossPower, self.p.i * self.p.v + self.n1.i * self.n1.v + self.n2.i * self.n2.v)]


class IdealTwoWaySwitch(_TwoWaySwitch):
    """Ideal two-way switch (Modelica.Electrical.Analog.Ideal.IdealTwoWaySwitch).

    ``control`` true: ``p`` connected to ``n2``; false: to ``n1``.  Each
    path is an ideal switch (``Ron`` closed, ``Goff`` open).
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealTwoWaySwitch"

    control = BooleanInput(description="true => p--n2 connected, false => p--n1 connected")

    def switched(self) -> sp.Basic:
        return self.control


class ControlledIdealTwoWaySwitch(_TwoWaySwitch, _PinControlled):
    """Controlled ideal two-way switch (Modelica.Electrical.Analog.Ideal.ControlledIdealTwoWaySwitch).

    ``control.v > level``: ``p`` connected to ``n2``, otherwise to ``n1``;
    ``control.i = 0``.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.ControlledIdealTwoWaySwitch"

    control = Pin(description="Control pin: if control.v > level p--n2 connected, otherwise p--n1 connected")

    def switched(self) -> sp.Basic:
        return self.control.v > self.level


class _IntermediateSwitch(_MultiPortSwitch):
    """Intermediate switch: ``p1--n1``, ``p2--n2``, or (``switched()``) crossed ``p1--n2``, ``p2--n1``."""

    modelica_name = None

    p1 = PositivePin(description="Positive electrical pin 1")
    p2 = PositivePin(description="Positive electrical pin 2")
    n1 = NegativePin(description="Negative electrical pin 1")
    n2 = NegativePin(description="Negative electrical pin 2")
    s1 = Variable(unit="1", description="Auxiliary variable of path p1--n1 (protected)")
    s2 = Variable(unit="1", description="Auxiliary variable of path p2--n2 (protected)")
    s3 = Variable(unit="1", description="Auxiliary variable of path p1--n2 (protected)")
    s4 = Variable(unit="1", description="Auxiliary variable of path p2--n1 (protected)")

    def equations(self):
        crossed = self.switched()
        v1, i1 = self.switch_path(self.s1, sp.Not(crossed))   # p1--n1
        v2, i2 = self.switch_path(self.s2, sp.Not(crossed))   # p2--n2
        v3, i3 = self.switch_path(self.s3, crossed)           # p1--n2
        v4, i4 = self.switch_path(self.s4, crossed)           # p2--n1
        return [Eq(self.p1.v - self.n1.v, v1), Eq(self.p2.v - self.n2.v, v2),
                Eq(self.p1.v - self.n2.v, v3), Eq(self.p2.v - self.n1.v, v4),
                Eq(self.p1.i, i1 + i3), Eq(self.p2.i, i2 + i4),
                Eq(self.n1.i, -i1 - i4), Eq(self.n2.i, -i2 - i3),
                Eq(self.LossPower, self.p1.i * self.p1.v + self.p2.i * self.p2.v
                   + self.n1.i * self.n1.v + self.n2.i * self.n2.v)]


class IdealIntermediateSwitch(_IntermediateSwitch):
    """Ideal intermediate switch (Modelica.Electrical.Analog.Ideal.IdealIntermediateSwitch).

    ``control`` true: ``p1--n2`` and ``p2--n1`` connected; false: ``p1--n1``
    and ``p2--n2``.  Each of the four paths is an ideal switch.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealIntermediateSwitch"

    control = BooleanInput(description="true => p1--n2, p2--n1 connected, otherwise p1--n1, p2--n2 connected")

    def switched(self) -> sp.Basic:
        return self.control


class ControlledIdealIntermediateSwitch(_IntermediateSwitch, _PinControlled):
    """Controlled ideal intermediate switch (Modelica.Electrical.Analog.Ideal.ControlledIdealIntermediateSwitch).

    ``control.v > level``: ``p1--n2`` and ``p2--n1`` connected, otherwise
    ``p1--n1`` and ``p2--n2``; ``control.i = 0``.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.ControlledIdealIntermediateSwitch"

    control = Pin(description="Control pin: if control.v > level p1--n2, p2--n1 connected, "
                              "otherwise p1--n1, p2--n2 connected")

    def switched(self) -> sp.Basic:
        return self.control.v > self.level


# --------------------------------------------------------------------------
# transformer, idle and short


class IdealTransformer(TwoPort):
    """Ideal transformer core with or without magnetization (Modelica.Electrical.Analog.Ideal.IdealTransformer).

    ``v1 = n*v2`` and the magnetization current w.r.t. the primary side
    ``im1 = i1 + i2/n``: without magnetization ``im1 = 0`` (the currents
    are in the inverse ratio), with it (``considerMagnetization``) the flux
    ``psim1 = Lm1*im1`` and ``v1 = der(psim1)``.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealTransformer"

    n = Parameter(1.0, unit="1", description="Turns ratio primary:secondary voltage")
    considerMagnetization = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                                      description="Choice of considering magnetization")
    Lm1 = Parameter(1.0, unit="H", description="Magnetization inductance w.r.t. primary side")
    im1 = Variable(unit="A", description="Magnetization current w.r.t. primary side (protected)")
    psim1 = Variable(unit="Wb", description="Magnetic flux w.r.t. primary side (protected)")

    def equations(self):
        if self.considerMagnetization:
            magnetization = [Eq(self.psim1, self.Lm1 * self.im1), Eq(self.v1, der(self.psim1))]
        else:
            magnetization = [Eq(self.psim1, 0), Eq(self.im1, 0)]
        return [Eq(self.im1, self.i1 + self.i2 / self.n), *magnetization, Eq(self.v1, self.n * self.v2)]


class Idle(OnePort):
    """Idle branch (Modelica.Electrical.Analog.Ideal.Idle): ``i = 0``."""

    modelica_name = "Modelica.Electrical.Analog.Ideal.Idle"

    def equations(self):
        return [Eq(self.i, 0)]


class Short(OnePort):
    """Short cut branch (Modelica.Electrical.Analog.Ideal.Short): ``v = 0``."""

    modelica_name = "Modelica.Electrical.Analog.Ideal.Short"

    def equations(self):
        return [Eq(self.v, 0)]


# --------------------------------------------------------------------------
# analog-digital converters

# appended section: its own imports, kept next to the only classes that need them



class Logic(enum.IntEnum):
    """Nine-valued logic of IEEE 1164 STD_ULOGIC (Modelica.Electrical.Digital.Interfaces.Logic).

    The values are Modelica's ordinals.  The MSL's literals ``'0'``, ``'1'``
    and ``'-'`` are no Python names; they are :attr:`Zero`, :attr:`One` and
    :attr:`DontCare` here.  A digital signal (the MSL's ``DigitalInput`` /
    ``DigitalOutput``, connectors of this type) is an Integer signal holding
    one of these values.
    """

    U = 1  #: 'U' uninitialized
    X = 2  #: 'X' forcing unknown
    Zero = 3  #: '0' forcing 0
    One = 4  #: '1' forcing 1
    Z = 5  #: 'Z' high impedance
    W = 6  #: 'W' weak unknown
    L = 7  #: 'L' weak 0
    H = 8  #: 'H' weak 1
    DontCare = 9  #: '-' don't care


# set after the body: in an IntEnum's body a str would become a member
Logic.modelica_name = "Modelica.Electrical.Digital.Interfaces.Logic"


def DigitalInput(**kw) -> Integer:  # noqa: N802 - Modelica's connector name
    """A digital signal input (Modelica.Electrical.Digital.Interfaces.DigitalInput).

    An Integer input holding a :class:`Logic` value.
    """
    return IntegerInput(min=int(Logic.U), max=int(Logic.DontCare), **kw)


def DigitalOutput(**kw) -> Integer:  # noqa: N802
    """A digital signal output (Modelica.Electrical.Digital.Interfaces.DigitalOutput).

    An Integer output holding a :class:`Logic` value.
    """
    return IntegerOutput(min=int(Logic.U), max=int(Logic.DontCare), **kw)


def _is_high(signal: sp.Basic) -> sp.Basic:
    """``signal`` is a forcing or a weak 1 (the MSL's ``s == L.'1' or s == L.'H'``)."""
    return sp.Or(sp.Eq(signal, int(Logic.One)), sp.Eq(signal, int(Logic.H)))


class AD_Converter(Component):  # noqa: N801 - Modelica's name
    """Simple n-bit analog to digital converter (Modelica.Electrical.Analog.Ideal.AD_Converter).

    The input voltage ``u = p.v - n.v`` drives ``i = u/Rin`` through the
    input resistance.  Where the trigger ``trig`` becomes ``'1'`` or ``'H'``
    the converter samples ``u`` and writes the code
    ``k = integer((u - VRefLow)/(VRefHigh - VRefLow)*(2^N - 1) + 0.5)``
    (0 for ``u <= VRefLow``) to ``y`` in binary, least significant bit
    first (``y[1]``), as ``'1'``/``'0'`` (:class:`Logic`).  ``y`` is ``'X'``
    until the first trigger.  The MSL shifts ``z`` right once per bit, so
    after a conversion ``z = div(k, 2^N)``: 0 unless the input was above
    the range (then the bits are ``k``'s lowest ``N``).
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.AD_Converter"

    N = Parameter(8, structural=True, min=1, description="Resolution in bits - output signal width")
    VRefHigh = Parameter(10.0, unit="V", description="High reference voltage")  # noqa: N815 - Modelica name
    VRefLow = Parameter(0.0, unit="V", description="Low reference voltage")  # noqa: N815
    Rin = Parameter(1e6, unit="Ohm", description="Input resistance")
    p = PositivePin()
    n = NegativePin()
    y = DigitalOutput(shape="N", start=int(Logic.X), fixed=True, description="Digital output")
    trig = DigitalInput(description="Trigger input")
    z = Integer(start=0, fixed=True, description="Code left after shifting out the N bits")
    u = Variable(unit="V", description="Input voltage")

    def equations(self):
        steps = 2 ** int(self.N) - 1
        code = If(self.u > self.VRefLow,
                  integer((self.u - self.VRefLow) / (self.VRefHigh - self.VRefLow) * steps + sp.Rational(1, 2)),
                  sp.Integer(0))
        # bit i (from 1) of the code: what the MSL's loop of mod and div leaves in y[i]
        bits = [Eq(self.y[i], If(mod(div(code, 2 ** (i - 1)), 2) > 0, int(Logic.One), int(Logic.Zero)))
                for i in range(1, int(self.N) + 1)]
        return [Eq(self.p.v - self.n.v, self.u),
                Eq(self.p.i * self.Rin, self.u),
                Eq(self.p.i + self.n.i, 0),
                When(_is_high(self.trig), *bits, Eq(self.z, div(code, 2 ** int(self.N))))]


class DA_Converter(Component):  # noqa: N801 - Modelica's name
    """Simple digital to analog converter (Modelica.Electrical.Analog.Ideal.DA_Converter).

    Where the trigger ``trig`` becomes ``'1'`` or ``'H'`` the converter reads
    the bits ``x`` (least significant first; ``'1'`` and ``'H'`` count as 1,
    every other value as 0), ``y = sum(x[i]*2^(i-1))``, and sets the ideal
    voltage source between its pins to ``vout = y*Vref/(2^N - 1)``, held
    until the next trigger; 0 before the first.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.DA_Converter"

    trig = DigitalInput(description="Trigger input")
    x = DigitalInput(shape="N", description="Digital input")
    p = PositivePin()
    n = NegativePin()
    vout = Variable(unit="V", start=0.0, fixed=True, description="Output voltage")
    y = Variable(unit="1", start=0.0, fixed=True, description="Value of the input code")
    N = Parameter(8, structural=True, min=1, description="Resolution - input signal width")
    Vref = Parameter(10.0, unit="V", description="Reference voltage")

    def equations(self):
        code = sp.Add(*[If(_is_high(self.x[i]), 2 ** (i - 1), 0) for i in range(1, int(self.N) + 1)])
        return [When(_is_high(self.trig),
                     Eq(self.y, code),
                     Eq(self.vout, code * self.Vref / (2 ** int(self.N) - 1))),
                Eq(self.p.v - self.n.v, self.vout),
                Eq(self.p.i + self.n.i, 0)]


__all__ += ["Logic", "DigitalInput", "DigitalOutput", "AD_Converter", "DA_Converter"]
