"""Ideal operational amplifiers (Modelica.Electrical.Analog.Ideal: the op-amp models).

The nullator-norator pair (:class:`IdealOpAmp`, :class:`IdealOpAmp3Pin`):
the input port has neither voltage nor current, the output takes whatever
voltage and current the circuit around it needs, so a negative feedback
circuit's gain is set by its resistors alone.  :class:`IdealOpAmpLimited`
keeps that behaviour between the supply voltages and saturates outside,
written in the MSL's parametric form (one curve parameter ``s`` gives both
the input voltage and the output voltage, so the switch between the three
branches never leaves an equation singular).  :class:`IdealizedOpAmpLimited`
has a large but finite gain ``V0`` and clips its output to the supply.
"""

from __future__ import annotations

import sympy as sp

from acausal.hybrid import homotopy, noEvent, smooth
from acausal.language import Component, Eq, Parameter, Variable
from acausal.components.electrical import NegativePin, PositivePin, TwoPort

from ..blocks.nonlinear import LimiterHomotopy

__all__ = ["IdealOpAmp", "IdealOpAmp3Pin", "IdealOpAmpLimited", "IdealizedOpAmpLimited"]

#: The MSL's protected ``constant SI.Voltage unitVoltage = 1``: turns the curve parameter into a voltage.
UNIT_VOLTAGE = 1.0


class IdealOpAmp(TwoPort):
    """Ideal operational amplifier (norator-nullator pair) (Modelica.Electrical.Analog.Ideal.IdealOpAmp).

    A two-port whose left port is a nullator, ``v1 = 0`` and ``i1 = 0``, and
    whose right port is a norator: any ``v2`` and any ``i2``.  The MSL
    declares the two-port's variables itself; they are TwoPort's here.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealOpAmp"

    def equations(self):
        return [Eq(self.v1, 0), Eq(self.i1, 0)]


class IdealOpAmp3Pin(Component):
    """Ideal operational amplifier (norator-nullator pair), but 3 pins (Modelica.Electrical.Analog.Ideal.IdealOpAmp3Pin).

    ``in_p.v = in_n.v`` and no input current; the output pin ``out`` (the
    norator, against the implicit ground) takes any voltage and current.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealOpAmp3Pin"

    in_p = PositivePin(description="Positive pin of the input port")
    in_n = NegativePin(description="Negative pin of the input port")
    out = PositivePin(description="Output pin")

    def equations(self):
        return [Eq(self.in_p.v, self.in_n.v), Eq(self.in_p.i, 0), Eq(self.in_n.i, 0)]


class IdealOpAmpLimited(Component):
    """Ideal operational amplifier with limitation (Modelica.Electrical.Analog.Ideal.IdealOpAmpLimited).

    Between the limits given by the potentials of ``VMax`` and ``VMin`` it
    is an ideal op-amp (``vin = 0``, ``out.v`` free); outside, ``out.v``
    sticks to the limit and ``vin`` is what the circuit makes it.  Written
    with the curve parameter ``s``::

        vin   = unitVoltage*(s + 1 if s < -1, s - 1 if s > 1, else 0)
        out.v = VMin.v if s < -1, VMax.v if s > 1,
                else (VMax.v - VMin.v)*s/2 + (VMax.v + VMin.v)/2

    both under ``smooth(0, ...)`` as in the MSL, so no events are generated:
    the curve is continuous and the nonlinear solver moves along it.  No
    current flows into any pin but ``out``.
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealOpAmpLimited"

    in_p = PositivePin(description="Positive pin of the input port")
    in_n = NegativePin(description="Negative pin of the input port")
    out = PositivePin(description="Output pin")
    VMax = PositivePin(description="Positive output voltage limitation")
    VMin = NegativePin(description="Negative output voltage limitation")
    vin = Variable(unit="V", description="Input voltage")
    s = Variable(start=0.0, unit="1", description="Auxiliary variable (protected)")

    def equations(self):
        s = self.s
        return [Eq(self.in_p.i, 0), Eq(self.in_n.i, 0), Eq(self.VMax.i, 0), Eq(self.VMin.i, 0),
                Eq(self.vin, self.in_p.v - self.in_n.v),
                Eq(self.in_p.v - self.in_n.v,
                   UNIT_VOLTAGE * smooth(0, sp.Piecewise((s + 1, s < -1), (s - 1, s > 1), (0, True)))),
                Eq(self.out.v, smooth(0, sp.Piecewise(
                    (self.VMin.v, s < -1), (self.VMax.v, s > 1),
                    ((self.VMax.v - self.VMin.v) * s / 2 + (self.VMax.v + self.VMin.v) / 2, True))))]


class IdealizedOpAmpLimited(Component):
    """Idealized operational amplifier with limitation (Modelica.Electrical.Analog.Ideal.IdealizedOpAmpLimited).

    No input current, the output ``v_out = V0*v_in`` clipped to the supply
    ``[vns, vps]``.  The supply is the parameters ``Vps``, ``Vns`` or, with
    ``useSupply``, the potentials of the pins ``s_p``, ``s_n``, which then
    deliver the supply current ``i_s = p_s/(vps - vns)`` (the power the
    inputs and the output draw).  With ``strict`` (the default) the clipping
    is evaluated literally (``noEvent``); without it the limits are state
    events.  ``homotopyType`` selects the simplified expression of
    ``homotopy()`` that initialization starts from (:func:`acausal.homotopy`).
    """

    modelica_name = "Modelica.Electrical.Analog.Ideal.IdealizedOpAmpLimited"

    V0 = Parameter(15000.0, unit="1", description="No-load amplification")
    useSupply = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                          description="Use supply pins (otherwise constant supply)")
    Vps = Parameter(15.0, unit="V", description="Positive supply voltage")
    Vns = Parameter(-15.0, unit="V", description="Negative supply voltage")
    strict = Parameter(True, structural=True, description="= true, if strict limits with noEvent(..)")
    homotopyType = Parameter(LimiterHomotopy.NoHomotopy, structural=True,  # noqa: N815 - Modelica name
                             description="Simplified model for homotopy-based initialization")
    vps = Variable(unit="V", description="Positive supply voltage")
    vns = Variable(unit="V", description="Negative supply voltage")
    v_in = Variable(unit="V", description="Input voltage difference")
    v_out = Variable(unit="V", description="Output voltage to ground")
    p_in = Variable(unit="W", description="Input power")
    p_out = Variable(unit="W", description="Output power")
    p_s = Variable(unit="W", description="Supply power")
    i_s = Variable(unit="A", description="Supply current")
    in_p = PositivePin(description="Positive pin of the input port")
    in_n = NegativePin(description="Negative pin of the input port")
    out = PositivePin(description="Output pin")
    s_p = PositivePin(condition="useSupply", description="Optional positive supply pin")
    s_n = NegativePin(condition="useSupply", description="Optional negative supply pin")
    simplifiedExpr = Variable(unit="V",  # noqa: N815 - Modelica name
                              description="Simplified expression for homotopy-based initialization (protected)")

    def _simplified(self) -> sp.Expr:
        # the MSL's if-chain on the (evaluated) homotopyType, picked here in Python
        kind = LimiterHomotopy(int(self.homotopyType))
        return {LimiterHomotopy.Linear: self.V0 * self.v_in, LimiterHomotopy.UpperLimit: self.vps,
                LimiterHomotopy.LowerLimit: self.vns}.get(kind, sp.Integer(0))

    def equations(self):
        gained = self.V0 * self.v_in
        clipped = sp.Piecewise((self.vps, gained > self.vps), (self.vns, gained < self.vns), (gained, True))
        # strict: relations literal (noEvent) inside smooth(0, .); otherwise the limits are state events
        # (smooth of order 0 would drop them, so the non-strict form is written without it)
        limited = smooth(0, noEvent(clipped)) if self.strict else clipped
        if LimiterHomotopy(int(self.homotopyType)) != LimiterHomotopy.NoHomotopy:
            limited = homotopy(limited, self.simplifiedExpr)
        supply = ([Eq(self.s_p.i, self.i_s), Eq(self.s_p.v, self.vps),
                   Eq(self.s_n.i, -self.i_s), Eq(self.s_n.v, self.vns)] if self.useSupply
                  else [Eq(self.vps, self.Vps), Eq(self.vns, self.Vns)])
        return supply + [
            Eq(self.v_in, self.in_p.v - self.in_n.v),
            Eq(self.v_out, self.out.v),
            Eq(self.p_in, self.in_p.v * self.in_p.i + self.in_n.v * self.in_n.i),
            Eq(self.p_out, self.out.v * self.out.i),
            Eq(self.p_s, -(self.p_in + self.p_out)),
            Eq(self.i_s, self.p_s / (self.vps - self.vns)),
            Eq(self.in_p.i, 0), Eq(self.in_n.i, 0),
            Eq(self.simplifiedExpr, self._simplified()),
            Eq(self.v_out, limited)]
