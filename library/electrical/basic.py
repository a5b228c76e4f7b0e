"""Basic analog electrical components (Modelica.Electrical.Analog.Basic).

Ground, the linear elements R, G, C, L (fixed and variable, the resistive
ones with a temperature coefficient and a conditional heat port), the
saturating inductor, transformer, gyrator, the linear controlled sources, the
electromotive forces coupling a circuit to a rotational or translational
flange, the potentiometer and the simple operational amplifier.
"""

from __future__ import annotations

import sympy as sp

from acausal.hybrid import Assert, noEvent, smooth
from acausal.language import Component, Eq, Parameter, RealInput, Variable, der
from acausal.components import rotational, translational
from acausal.components.declarations import DerivedDefaults
from acausal.components.electrical import (
    EPS,
    NegativePin,
    OnePort,
    Pin,
    PositivePin,
    TemperatureDependence,
    TwoPort,
)

__all__ = [
    "Ground",
    "Resistor",
    "Conductor",
    "Capacitor",
    "Inductor",
    "SaturatingInductor",
    "Transformer",
    "Gyrator",
    "RotationalEMF",
    "TranslationalEMF",
    "VCV",
    "VCC",
    "CCV",
    "CCC",
    "OpAmp",
    "VariableResistor",
    "VariableConductor",
    "VariableCapacitor",
    "VariableInductor",
    "Potentiometer",
    "OpAmpDetailed",
    "M_Transformer",
]

#: Modelica.Constants.small: below it |i|/Ipar counts as zero in SaturatingInductor.
SMALL = 1e-60


class Ground(Component):
    """Ground node (Modelica.Electrical.Analog.Basic.Ground).

    ``p.v = 0``: the reference potential every circuit needs once.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.Ground"

    p = Pin(description="Ground pin")

    def equations(self):
        return [Eq(self.p.v, 0)]


class Resistor(OnePort, TemperatureDependence):
    """Ideal linear electrical resistor (Modelica.Electrical.Analog.Basic.Resistor).

    ``v = R_actual*i`` with ``R_actual = R*(1 + alpha*(T_heatPort - T_ref))``;
    the loss ``LossPower = v*i`` leaves through the conditional heat port
    (``useHeatPort``), else the resistor is at the fixed temperature ``T``
    (default ``T_ref``).
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.Resistor"

    R = Parameter(1.0, unit="Ohm", description="Resistance at temperature T_ref")
    R_actual = Variable(unit="Ohm", description="Actual resistance = R*(1 + alpha*(T_heatPort - T_ref))")

    def equations(self):
        return [Eq(self.R_actual, self.R * self.temperature_factor()),
                Eq(self.v, self.R_actual * self.i),
                Eq(self.LossPower, self.v * self.i)]


class Conductor(OnePort, TemperatureDependence):
    """Ideal linear electrical conductor (Modelica.Electrical.Analog.Basic.Conductor).

    ``i = G_actual*v`` with ``G_actual = G/(1 + alpha*(T_heatPort - T_ref))``;
    ``LossPower = v*i``.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.Conductor"

    G = Parameter(1.0, unit="S", description="Conductance at temperature T_ref")
    G_actual = Variable(unit="S", description="Actual conductance = G/(1 + alpha*(T_heatPort - T_ref))")

    def equations(self):
        return [Eq(self.G_actual, self.G / self.temperature_factor()),
                Eq(self.i, self.G_actual * self.v),
                Eq(self.LossPower, self.v * self.i)]


class Capacitor(OnePort):
    """Ideal linear electrical capacitor (Modelica.Electrical.Analog.Basic.Capacitor).

    ``i = C*der(v)``; ``v`` starts at 0 (give ``v=dict(fixed=True)`` to fix it).
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.Capacitor"

    C = Parameter(1.0, unit="F", min=0, description="Capacitance")
    v = Variable(unit="V", start=0.0, description="Voltage drop of the two pins (= p.v - n.v)")

    def equations(self):
        return [Eq(self.i, self.C * der(self.v))]


class Inductor(OnePort):
    """Ideal linear electrical inductor (Modelica.Electrical.Analog.Basic.Inductor).

    ``L*der(i) = v``; ``i`` starts at 0 (give ``i=dict(fixed=True)`` to fix it).
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.Inductor"

    L = Parameter(1.0, unit="H", min=0, description="Inductance")
    i = Variable(unit="A", start=0.0, description="Current flowing from pin p to pin n")

    def equations(self):
        return [Eq(self.L * der(self.i), self.v)]


class SaturatingInductor(DerivedDefaults, OnePort):
    """Simple model of an inductor with saturation (Modelica.Electrical.Analog.Basic.SaturatingInductor).

    The flux ``Psi = Linf*i + (Lzer - Linf)*Ipar*atan(i/Ipar)`` and ``v =
    der(Psi)``: the inductance falls from ``Lzer`` near zero current to
    ``Linf`` at large currents, through ``Lnom`` at ``Inom``.  ``Ipar`` is a
    parameter computed at initialization from ``(Lnom - Linf)/(Lzer - Linf) =
    Ipar/Inom*(pi/2 - atan(Ipar/Inom))``.  ``Lact`` is the present
    inductance ``Psi/i``.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.SaturatingInductor"

    derived_defaults = {"Lzer": lambda c: 2 * c.Lnom, "Linf": lambda c: c.Lnom / 2}

    Inom = Parameter(1.0, unit="A", description="Nominal current")
    Lnom = Parameter(1.0, unit="H", description="Nominal inductance at Nominal current")
    Lzer = Parameter(None, unit="H", description="Inductance near current=0 (default 2*Lnom)")
    Linf = Parameter(None, unit="H", description="Inductance at large currents (default Lnom/2)")
    Ipar = Parameter(0.1, unit="A", fixed=False,
                     description="Parameter of the atan characteristic (computed at initialization)")
    i = Variable(unit="A", start=0.0, description="Current flowing from pin p to pin n")
    Lact = Variable(unit="H", description="Present inductance")
    Psi = Variable(unit="Wb", description="Present flux")

    def initial_equations(self):
        ratio = self.Ipar / self.Inom
        return [Eq((self.Lnom - self.Linf) / (self.Lzer - self.Linf), ratio * (sp.pi / 2 - sp.atan(ratio)))]

    def equations(self):
        x = self.i / self.Ipar
        return [Assert(self.Lzer > self.Lnom * (1 + EPS), "Lzer has to be > Lnom"),
                Assert(self.Linf < self.Lnom * (1 - EPS), "Linf has to be < Lnom"),
                # the limit of atan(x)/x at x = 0 is 1; noEvent as in the MSL (no switching there)
                Eq(self.Lact, self.Linf + (self.Lzer - self.Linf)
                   * noEvent(sp.Piecewise((1, sp.Abs(x) < SMALL), (sp.atan(x) / x, True)))),
                Eq(self.Psi, self.Linf * self.i + (self.Lzer - self.Linf) * self.Ipar * sp.atan(x)),
                Eq(self.v, der(self.Psi))]


class Transformer(TwoPort):
    """Transformer with two ports (Modelica.Electrical.Analog.Basic.Transformer).

    ``v1 = L1*der(i1) + M*der(i2)`` and ``v2 = M*der(i1) + L2*der(i2)``,
    written as the MSL writes it, with the difference ``dv = (L1 - M)*der(i1)
    + (M - L2)*der(i2)`` and ``v2 = v1 - dv`` (so that ``L1 = L2 = M``
    loses a state in the structure, not only in the numbers).
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.Transformer"

    L1 = Parameter(1.0, unit="H", description="Primary inductance")
    L2 = Parameter(1.0, unit="H", description="Secondary inductance")
    M = Parameter(1.0, unit="H", description="Coupling inductance")
    i1 = Variable(unit="A", start=0.0, description="Current flowing from pos. to neg. pin of port 1")
    i2 = Variable(unit="A", start=0.0, description="Current flowing from pos. to neg. pin of port 2")
    dv = Variable(unit="V", description="Difference between voltage drop over primary inductor and voltage "
                                        "drop over secondary inductor")

    def equations(self):
        return [Eq(self.v1, self.L1 * der(self.i1) + self.M * der(self.i2)),
                Eq(self.dv, (self.L1 - self.M) * der(self.i1) + (self.M - self.L2) * der(self.i2)),
                Eq(self.v2, self.v1 - self.dv)]


class Gyrator(TwoPort):
    """Gyrator (Modelica.Electrical.Analog.Basic.Gyrator).

    ``i1 = G2*v2``, ``i2 = -G1*v1``.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.Gyrator"

    G1 = Parameter(1.0, unit="S", description="Primary gyration conductance")
    G2 = Parameter(1.0, unit="S", description="Secondary gyration conductance")

    def equations(self):
        return [Eq(self.i1, self.G2 * self.v2), Eq(self.i2, -self.G1 * self.v1)]


class VCV(TwoPort):
    """Linear voltage-controlled voltage source (Modelica.Electrical.Analog.Basic.VCV).

    ``v2 = gain*v1``, ``i1 = 0``.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.VCV"

    gain = Parameter(1.0, description="Voltage gain")

    def equations(self):
        return [Eq(self.v2, self.v1 * self.gain), Eq(self.i1, 0)]


class VCC(TwoPort):
    """Linear voltage-controlled current source (Modelica.Electrical.Analog.Basic.VCC).

    ``i2 = transConductance*v1``, ``i1 = 0``.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.VCC"

    transConductance = Parameter(1.0, unit="S", description="Transconductance")  # noqa: N815 - Modelica name

    def equations(self):
        return [Eq(self.i2, self.v1 * self.transConductance), Eq(self.i1, 0)]


class CCV(TwoPort):
    """Linear current-controlled voltage source (Modelica.Electrical.Analog.Basic.CCV).

    ``v2 = transResistance*i1``, ``v1 = 0``.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.CCV"

    transResistance = Parameter(1.0, unit="Ohm", description="Transresistance")  # noqa: N815 - Modelica name

    def equations(self):
        return [Eq(self.v2, self.i1 * self.transResistance), Eq(self.v1, 0)]


class CCC(TwoPort):
    """Linear current-controlled current source (Modelica.Electrical.Analog.Basic.CCC).

    ``i2 = gain*i1``, ``v1 = 0``.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.CCC"

    gain = Parameter(1.0, description="Current gain")

    def equations(self):
        return [Eq(self.i2, self.i1 * self.gain), Eq(self.v1, 0)]


class RotationalEMF(rotational.PartialElementaryOneFlangeAndSupport2):
    """Electromotoric force, electric/mechanic transformer (Modelica.Electrical.Analog.Basic.RotationalEMF).

    ``k*w = v`` and ``tau = -k*i`` (``tau = flange.tau``), with ``w =
    der(phi)`` the speed of the flange relative to the support: the
    electrical power ``v*i`` equals the mechanical power ``-tau*w`` given to
    the flange.  ``tauElectrical = -tau`` is the torque the current exerts on
    the shaft.  The reaction torque goes to the support (``useSupport``) or
    the grounded housing.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.RotationalEMF"

    k = Parameter(1.0, unit="N.m/A", description="Transformation coefficient")
    v = Variable(unit="V", description="Voltage drop between the two pins")
    i = Variable(unit="A", description="Current flowing from positive to negative pin")
    phi = Variable(unit="rad", description="Angle of shaft flange with respect to support (= flange.phi - support.phi)")
    w = Variable(unit="rad/s", description="Angular velocity of flange relative to support")
    tau = Variable(unit="N.m", description="Torque of flange")
    tauElectrical = Variable(unit="N.m", description="Electrical torque")  # noqa: N815 - Modelica name
    p = PositivePin(description="Positive electrical pin")
    n = NegativePin(description="Negative electrical pin")

    def equations(self):
        return [Eq(self.v, self.p.v - self.n.v),
                Eq(0, self.p.i + self.n.i),
                Eq(self.i, self.p.i),
                Eq(self.phi, self.flange.phi - self.phi_support),
                Eq(self.w, der(self.phi)),
                Eq(self.k * self.w, self.v),
                Eq(self.tau, -self.k * self.i),
                Eq(self.tauElectrical, -self.tau),
                Eq(self.tau, self.flange.tau)]


class TranslationalEMF(translational.PartialElementaryOneFlangeAndSupport2):
    """Electromotoric force, electric/mechanic transformer (Modelica.Electrical.Analog.Basic.TranslationalEMF).

    ``k*vel = v`` and ``f = -k*i`` (``f = flange.f``), with ``vel = der(s)``
    the velocity of the flange relative to the support.  ``fElectrical =
    -f``.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.TranslationalEMF"

    k = Parameter(1.0, unit="N/A", description="Transformation coefficient")
    v = Variable(unit="V", description="Voltage drop between the two pins")
    i = Variable(unit="A", description="Current flowing from positive to negative pin")
    vel = Variable(unit="m/s", description="Velocity of flange relative to support")
    f = Variable(unit="N", description="Force of flange")
    fElectrical = Variable(unit="N", description="Electrical force")  # noqa: N815 - Modelica name
    p = PositivePin(description="Positive electrical pin")
    n = NegativePin(description="Negative electrical pin")

    def equations(self):
        return [Eq(self.v, self.p.v - self.n.v),
                Eq(0, self.p.i + self.n.i),
                Eq(self.i, self.p.i),
                Eq(self.vel, der(self.s)),
                Eq(self.k * self.vel, self.v),
                Eq(self.f, -self.k * self.i),
                Eq(self.fElectrical, -self.f),
                Eq(self.f, self.flange.f)]


class OpAmp(Component):
    """Simple nonideal model of an OpAmp with limitation (Modelica.Electrical.Analog.Basic.OpAmp).

    No current flows into the inputs or the supply pins.  The output is
    ``out.v = (VMax.v + VMin.v)/2 + |Slope|*vin/(1 + |Slope|*|f*vin|)``
    with ``f = 2/(VMax.v - VMin.v)``: linear with slope ``|Slope|`` near
    ``vin = 0``, saturating smoothly at the supply voltages.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.OpAmp"

    Slope = Parameter(10000.0, description="Slope of the out.v/vin characteristic at vin=0")
    in_p = PositivePin(description="Positive pin of the input port")
    in_n = NegativePin(description="Negative pin of the input port")
    out = PositivePin(description="Output pin")
    VMax = PositivePin(description="Positive output voltage limitation")
    VMin = NegativePin(description="Negative output voltage limitation")
    vin = Variable(unit="V", description="Input voltage")
    f = Variable(unit="1/V", description="Auxiliary variable (protected)")
    absSlope = Variable(description="|Slope| (protected)")  # noqa: N815 - Modelica name

    def equations(self):
        return [Eq(self.in_p.i, 0), Eq(self.in_n.i, 0), Eq(self.VMax.i, 0), Eq(self.VMin.i, 0),
                Eq(self.vin, self.in_p.v - self.in_n.v),
                Eq(self.f, 2 / (self.VMax.v - self.VMin.v)),
                Eq(self.absSlope, sp.Abs(self.Slope)),
                Eq(self.out.v, (self.VMax.v + self.VMin.v) / 2 + self.absSlope * self.vin
                   / (1 + self.absSlope * smooth(0, sp.Abs(self.f * self.vin))))]


class VariableResistor(OnePort, TemperatureDependence):
    """Ideal linear electrical resistor with variable resistance (Modelica.Electrical.Analog.Basic.VariableResistor).

    ``v = R_actual*i`` with ``R_actual = R*(1 + alpha*(T_heatPort - T_ref))``
    and the resistance ``R`` a signal input.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.VariableResistor"

    R = RealInput(unit="Ohm", description="Resistance at temperature T_ref")
    R_actual = Variable(unit="Ohm", description="Actual resistance = R*(1 + alpha*(T_heatPort - T_ref))")

    def equations(self):
        return [Eq(self.R_actual, self.R * self.temperature_factor()),
                Eq(self.v, self.R_actual * self.i),
                Eq(self.LossPower, self.v * self.i)]


class VariableConductor(OnePort, TemperatureDependence):
    """Ideal linear electrical conductor with variable conductance (Modelica.Electrical.Analog.Basic.VariableConductor).

    ``i = G_actual*v`` with ``G_actual = G/(1 + alpha*(T_heatPort - T_ref))``
    and the conductance ``G`` a signal input.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.VariableConductor"

    G = RealInput(unit="S", description="Conductance at temperature T_ref")
    G_actual = Variable(unit="S", description="Actual conductance = G/(1 + alpha*(T_heatPort - T_ref))")

    def equations(self):
        return [Eq(self.G_actual, self.G / self.temperature_factor()),
                Eq(self.i, self.G_actual * self.v),
                Eq(self.LossPower, self.v * self.i)]


class VariableCapacitor(OnePort):
    """Ideal linear electrical capacitor with variable capacitance (Modelica.Electrical.Analog.Basic.VariableCapacitor).

    ``Q = max(C, Cmin)*v`` and ``i = der(Q)``, the capacitance ``C`` a signal
    input (bounded below by ``Cmin`` so that the state never vanishes).  With
    ``UIC`` the voltage starts at ``IC``.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.VariableCapacitor"

    Cmin = Parameter(EPS, unit="F", description="Lower bound for variable capacitance")
    IC = Parameter(0.0, unit="V", description="Initial Value")
    UIC = Parameter(False, structural=True, description="Decision if initial value IC shall be used")
    C = RealInput(unit="F", description="Capacitance")
    Q = Variable(unit="C", description="Charge")

    def initial_equations(self):
        return [Eq(self.v, self.IC)] if self.UIC else []

    def equations(self):
        return [Assert(self.C >= 0, "Capacitance C has to be >= 0!"),
                # noEvent as in the MSL: the bound protects the solver, it is no switch
                Eq(self.Q, noEvent(sp.Max(self.C, self.Cmin)) * self.v),
                Eq(self.i, der(self.Q))]


class VariableInductor(OnePort):
    """Ideal linear electrical inductor with variable inductance (Modelica.Electrical.Analog.Basic.VariableInductor).

    ``Psi = max(L, Lmin)*i`` and ``v = der(Psi)``, the inductance ``L`` a
    signal input.  With ``UIC`` the current starts at ``IC``.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.VariableInductor"

    Lmin = Parameter(EPS, unit="H", description="Lower bound for variable inductance")
    IC = Parameter(0.0, unit="A", description="Initial Value")
    UIC = Parameter(False, structural=True, description="Decision if initial value IC shall be used")
    L = RealInput(unit="H", description="Inductance")
    Psi = Variable(unit="Wb", description="Magnetic flux")

    def initial_equations(self):
        return [Eq(self.i, self.IC)] if self.UIC else []

    def equations(self):
        return [Assert(self.L >= 0, "Inductance L has to be >= 0!"),
                Eq(self.Psi, noEvent(sp.Max(self.L, self.Lmin)) * self.i),
                Eq(self.v, der(self.Psi))]


class Potentiometer(TemperatureDependence):
    """Adjustable resistor (Modelica.Electrical.Analog.Basic.Potentiometer).

    A resistance ``R*(1 + alpha*(T_heatPort - T_ref))`` between ``pin_p`` and
    ``pin_n`` with a ``contact`` at the relative position ``r`` (0 at
    pin_n, 1 at pin_p, clipped to [0, 1]): ``Rp`` lies between pin_p and the
    contact, ``Rn`` between contact and pin_n.  ``r`` is the input ``r``
    (``useRinput``) or the parameter ``rConstant``; ``rInt`` is the value
    used.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.Potentiometer"

    R = Parameter(1.0, unit="Ohm", description="Resistance at temperature T_ref")
    T_ref = Parameter(293.15, unit="K", description="Reference temperature")
    useRinput = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                          description="Use input for 0<r<1 (else constant)")
    rConstant = Parameter(0.5, min=0, max=1, description="Contact between n (r=0) and p (r=1)")  # noqa: N815
    Rp = Variable(unit="Ohm", description="Actual resistance between pin_p and contact")
    Rn = Variable(unit="Ohm", description="Actual resistance between contact and pin_n")
    pin_p = PositivePin(description="Positive pin")
    contact = PositivePin(description="Contact")
    pin_n = NegativePin(description="Negative pin")
    r = RealInput(condition="useRinput", description="Contact between n (r=0) and p (r=1)")
    rInt = Variable(description="Contact position used: r or rConstant (protected)")  # noqa: N815

    def equations(self):
        position = sp.Min(1, sp.Max(0, self.rInt))
        resistance = self.R * self.temperature_factor()
        return [Eq(self.rInt, self.r if self.useRinput else self.rConstant),
                Eq(self.pin_p.i + self.pin_n.i + self.contact.i, 0),
                Eq(self.Rp, resistance * (1 - position)),
                Eq(self.Rn, resistance * position),
                Eq(self.pin_p.v - self.contact.v, self.Rp * self.pin_p.i),
                Eq(self.pin_n.v - self.contact.v, self.Rn * self.pin_n.i),
                Eq(self.LossPower, (self.pin_p.v - self.contact.v) * self.pin_p.i
                   + (self.pin_n.v - self.contact.v) * self.pin_n.i)]


# --------------------------------------------------------------------------
# detailed operational amplifier


def _limited_sum(q_sum, q_sum_ltf, v_pos, v_neg, vcp, vcm) -> sp.Expr:
    """The MSL's ``FCNq_sum_limit``: ``q_sum`` held at a supply rail once the lagged ``q_sum_ltf`` reached it.

    Relations in a function body do not generate events (noEvent).
    """
    upper, lower = v_pos - vcp, v_neg + vcm
    return noEvent(sp.Piecewise((upper, sp.And(q_sum > upper, q_sum_ltf >= upper)),
                                (lower, sp.And(q_sum < lower, q_sum_ltf <= lower)),
                                (q_sum, True)))


def _limited_output_current(v_source, v_out, Rout, Imaxsi_val, Imaxso_val) -> sp.Expr:  # noqa: N803 - MSL names
    """The MSL's ``FCNiout_limit``: ``(v_out - v_source)/Rout`` clipped to ``[-Imaxso_val, Imaxsi_val]``."""
    return noEvent(sp.Piecewise((Imaxsi_val, v_out > v_source + Rout * Imaxsi_val),
                                (-Imaxso_val, v_out < v_source - Rout * Imaxso_val),
                                ((v_out - v_source) / Rout, True)))


class OpAmpDetailed(DerivedDefaults, Component):
    """Detailed model of an operational amplifier (Modelica.Electrical.Analog.Basic.OpAmpDetailed).

    A macromodel after Conelly and Choi (Macromodelling with SPICE, 1992) in
    five stages, each holding its own data sheet parameters:

    * **input**: the offset voltage ``Vos`` in series with ``p``, the bias
      currents ``I1 = Ib + Ios/2`` (from ``p``) and ``I2 = Ib - Ios/2``
      (from ``m``) with the common-mode resistances ``Rcm`` to ground, and
      the differential resistance ``Rdm`` parallel to ``Cin`` carrying
      ``v_in = p.v - Vos - m.v``;
    * **frequency response**: first-order lags at ``fp2`` and ``fp4`` and a
      lead-lag (zero ``fz``, pole ``fp3``) from ``v_in`` to ``q_fr3``;
    * **gain**: ``q_sum = Avd0_val*q_fr3 + Avcm_val*(v_3 + v_4)`` with the
      differential gain ``Avd0_val = 10^(Avd0/20)`` and the common-mode gain
      ``Avcm_val = Avd0_val/10^(CMRR/20)/2``, held at the supply rails
      (less ``vcp``, ``vcm``), then the dominant pole ``fp1`` to ``q_fp1``;
    * **slew rate**: ``v_source`` follows ``q_fp1`` with the time constant
      ``Ts``, its slope clipped to ``[-sr_m, sr_p]``;
    * **output**: ``Rout`` from ``v_source`` to ``outp``, the current
      clipped to ``Imaxso`` (sourced) and ``Imaxsi`` (sunk).

    At DC and in the linear range the open-loop output is ``Avd0_val*v_in +
    Avcm_val*(v_3 + v_4)``.  No current flows into the supply pins; their
    potentials only set the limits.  The MSL's ``v_source = q_fp1`` and
    ``x = 0`` are the initial equations; the other states start from their
    start values (0).  Relations in the MSL's two limiting functions do not
    generate events, as in any Modelica function.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.OpAmpDetailed"

    # the MSL's final parameters (bindings of the parameters above them)
    derived_defaults = {
        "vcp_abs": lambda c: sp.Abs(c.vcp),
        "vcm_abs": lambda c: sp.Abs(c.vcm),
        "I1": lambda c: c.Ib + c.Ios / 2,
        "I2": lambda c: c.Ib - c.Ios / 2,
        "Avd0_val": lambda c: 10 ** (c.Avd0 / 20),
        "Avcm_val": lambda c: c.Avd0_val / 10 ** (c.CMRR / 20) / 2,
        "sr_p_val": lambda c: sp.Abs(c.sr_p),
        "sr_m_val": lambda c: -sp.Abs(c.sr_m),
        "Imaxso_val": lambda c: sp.Abs(c.Imaxso),
        "Imaxsi_val": lambda c: sp.Abs(c.Imaxsi),
    }

    Rdm = Parameter(2.0e6, unit="Ohm", description="Input resistance (differential input mode)")
    Rcm = Parameter(2.0e9, unit="Ohm", description="Input resistance (common mode)")
    Cin = Parameter(1.4e-12, unit="F", description="Input capacitance")
    Vos = Parameter(1.0e-3, unit="V", description="Input offset voltage")
    Ib = Parameter(80.0e-9, unit="A", description="Input bias current")
    Ios = Parameter(20.0e-9, unit="A", description="Input offset current")
    vcp = Parameter(0.0, unit="V", description="Correction value for limiting by p_supply")
    vcm = Parameter(0.0, unit="V", description="Correction value for limiting by msupply")
    Avd0 = Parameter(106.0, unit="1", description="Differential amplifier [dB]")
    CMRR = Parameter(90.0, unit="1", description="Common-mode rejection [dB]")
    fp1 = Parameter(5.0, unit="Hz", description="Dominant pole")
    fp2 = Parameter(2.0e6, unit="Hz", description="Pole frequency")
    fp3 = Parameter(20.0e6, unit="Hz", description="Pole frequency")
    fp4 = Parameter(100.0e6, unit="Hz", description="Pole frequency")
    fz = Parameter(5.0e6, unit="Hz", description="Zero frequency")
    sr_p = Parameter(0.5e6, unit="V/s", description="Slew rate for increase")
    sr_m = Parameter(0.5e6, unit="V/s", description="Slew rate for decrease")
    Rout = Parameter(75.0, unit="Ohm", description="Output resistance")
    Imaxso = Parameter(25.0e-3, unit="A", description="Maximal output current (source current)")
    Imaxsi = Parameter(25.0e-3, unit="A", description="Maximal output current (sink current)")
    Ts = Parameter(0.0000012, unit="s", description="Sampling time")
    vcp_abs = Parameter(None, unit="V", description="Positive correction value for limiting by p_supply (final)")
    vcm_abs = Parameter(None, unit="V", description="Positive correction value for limiting by msupply (final)")
    I1 = Parameter(None, unit="A", description="Current of internal source I1 (final)")
    I2 = Parameter(None, unit="A", description="Current of internal source I2 (final)")
    Avd0_val = Parameter(None, unit="1", description="Differential mode gain (final)")
    Avcm_val = Parameter(None, unit="1", description="Common mode gain (final)")
    sr_p_val = Parameter(None, unit="V/s", description="Value of slew rate for increase (final)")
    sr_m_val = Parameter(None, unit="V/s", description="Negative value of slew rate for increase (final)")
    Imaxso_val = Parameter(None, unit="A", description="Orientation out outp (final)")
    Imaxsi_val = Parameter(None, unit="A", description="Orientation into outp (final)")

    p = PositivePin(description="Positive pin of the input port")
    m = NegativePin(description="Negative pin of the input port")
    outp = PositivePin(description="Output pin")
    p_supply = PositivePin(description="Positive output voltage limitation")
    m_supply = NegativePin(description="Negative output voltage limitation")

    v_pos = Variable(unit="V", description="Potential of the positive supply")
    v_neg = Variable(unit="V", description="Potential of the negative supply")
    v_vos = Variable(unit="V", description="Input offset voltage source")
    v_3 = Variable(unit="V", description="Potential of the internal node behind the offset source")
    v_in = Variable(unit="V", start=0.0, description="Differential input voltage at Rdm and Cin")
    v_4 = Variable(unit="V", description="Potential of the negative input")
    i_vos = Variable(unit="A", description="Current through the offset source")
    i_3 = Variable(unit="A", description="Current of the positive input to ground (I1 and Rcm)")
    i_r2 = Variable(unit="A", description="Current through Rdm")
    i_c3 = Variable(unit="A", description="Current through Cin")
    i_4 = Variable(unit="A", description="Current of the negative input to ground (I2 and Rcm)")
    # Real in the MSL; each is a lagged copy of v_in, so a voltage
    q_fr1 = Variable(unit="V", start=0.0, description="Output of the first pole (fp2)")
    q_fr2 = Variable(unit="V", start=0.0, description="Output of the zero (fz) and pole (fp3)")
    q_fr3 = Variable(unit="V", start=0.0, description="Output of the pole fp4")
    q_sum = Variable(unit="V", description="Sum of differential and common mode gain")
    q_sum_help = Variable(unit="V", description="q_sum limited to the supply")
    q_fp1 = Variable(unit="V", start=0.0, description="Output of the dominant pole (fp1)")
    v_source = Variable(unit="V", start=0.0, description="Slew rate limited internal source voltage")
    x = Variable(unit="V", start=0.0, description="Auxiliary variable for slew rate")
    v_out = Variable(unit="V", description="Output voltage")
    i_out = Variable(unit="A", description="Current into the output pin")

    def initial_equations(self):
        return [Eq(self.v_source, self.q_fp1), Eq(self.x, 0)]

    def equations(self):
        two_pi = 2 * sp.pi
        dx = der(self.x)
        return [
            Assert(self.Rout > 0, "Rout must be > 0.0."),
            # power supply
            Eq(self.v_pos, self.p_supply.v),
            Eq(self.v_neg, self.m_supply.v),
            # input stage
            Eq(self.p.i, self.i_vos),
            Eq(self.m.i, self.i_4 - self.i_r2 - self.i_c3),
            Eq(0, self.i_3 + self.i_r2 + self.i_c3 - self.i_vos),
            Eq(self.p.v - self.m.v, self.v_vos + self.v_in),
            Eq(self.v_4, self.m.v),
            Eq(self.v_3, self.p.v - self.v_vos),
            Eq(self.v_vos, self.Vos),
            Eq(self.i_3, self.I1 + self.v_3 / self.Rcm),
            Eq(self.v_in, self.Rdm * self.i_r2),
            Eq(self.i_c3, self.Cin * der(self.v_in)),
            Eq(self.i_4, self.I2 + self.v_4 / self.Rcm),
            # frequency response: the poles fp2, fp4 and the lead-lag fz/fp3
            Eq(der(self.q_fr1), two_pi * self.fp2 * (self.v_in - self.q_fr1)),
            Eq(self.q_fr2 + der(self.q_fr2) / (two_pi * self.fp3), self.q_fr1 + der(self.q_fr1) / (two_pi * self.fz)),
            Eq(der(self.q_fr3), two_pi * self.fp4 * (self.q_fr2 - self.q_fr3)),
            # gain stage
            Eq(self.q_sum, self.Avd0_val * self.q_fr3 + self.Avcm_val * (self.v_3 + self.v_4)),
            Eq(self.q_sum_help, _limited_sum(self.q_sum, self.q_fp1, self.v_pos, self.v_neg,
                                             self.vcp_abs, self.vcm_abs)),
            Eq(der(self.q_fp1), two_pi * self.fp1 * (self.q_sum_help - self.q_fp1)),
            # slew rate stage: x only carries its derivative, the unlimited slope
            Eq(dx, (self.q_fp1 - self.v_source) / self.Ts),
            Eq(der(self.v_source), smooth(0, noEvent(sp.Piecewise((self.sr_p_val, dx > self.sr_p_val),
                                                                  (self.sr_m_val, dx < self.sr_m_val),
                                                                  (dx, True))))),
            # output stage
            Eq(self.v_out, self.outp.v),
            Eq(self.i_out, self.outp.i),
            Eq(self.i_out, _limited_output_current(self.v_source, self.v_out, self.Rout,
                                                   self.Imaxsi_val, self.Imaxso_val)),
            Eq(self.p_supply.i, 0),
            Eq(self.m_supply.i, 0),
        ]


# --------------------------------------------------------------------------
# transformer with N coupled inductors


def _triangle_index(N: int, row: int, column: int) -> int:  # noqa: N803 - Modelica name
    """1-based position in ``L`` of the inductance ``Lm[row, column]`` (``row <= column``).

    ``L`` lists the upper triangle of the symmetric inductance matrix row by
    row: ``L11, L12, ..., L1N, L22, ..., LNN``.
    """
    return (row - 1) * N - (row - 1) * row // 2 + column


class M_Transformer(Component):  # noqa: N801 - Modelica name
    """Generic transformer with free number of inductors (Modelica.Electrical.Analog.Basic.M_Transformer).

    ``N`` inductors, inductor ``j`` between ``p[j]`` and ``n[j]``, coupled
    by the symmetric inductance matrix ``Lm``: ``v = Lm*der(i)``.  ``L``
    gives the ``N*(N + 1)/2`` entries of its upper triangle row by row
    (``L11, L12, ..., L1N, L22, ..., LNN``); ``Lm`` is filled from it at
    initialization (a parameter with ``fixed = false``, as in the MSL).  The
    currents start at 0 (``fixed = true``).  The default ``L`` is for the
    default ``N = 3``; another ``N`` needs its own ``L``.  The MSL's
    protected ``dimL`` is the size of ``L``, computed from ``N``.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.M_Transformer"

    N = Parameter(3, structural=True, min=1, description="Number of inductors")
    L = Parameter((1.0, 0.1, 0.2, 2.0, 0.3, 3.0), unit="H", shape=lambda value: _dim_l(value("N")),
                  description="Inductances and coupling inductances")
    Lm = Parameter(0.0, unit="H", fixed=False, shape=("N", "N"),
                   description="Complete symmetric inductance matrix, calculated internally")
    p = PositivePin(shape="N", description="Positive pin")
    n = NegativePin(shape="N", description="Negative pin")
    v = Variable(unit="V", shape="N", description="Voltage drop over inductors")
    i = Variable(unit="A", shape="N", start=0.0, fixed=True, description="Current through inductors")

    def initial_equations(self):
        N = self.N  # noqa: N806 - Modelica name
        found = []
        for row in range(1, N + 1):
            found.append(Eq(self.Lm[row, row], self.L[_triangle_index(N, row, row)]))
            for column in range(row + 1, N + 1):
                coupling = self.L[_triangle_index(N, row, column)]
                found += [Eq(self.Lm[row, column], coupling), Eq(self.Lm[column, row], coupling)]
        return found

    def equations(self):
        found = []
        for j in range(1, self.N + 1):
            found += [Eq(self.v[j], self.p[j].v - self.n[j].v),
                      Eq(0, self.p[j].i + self.n[j].i),
                      Eq(self.i[j], self.p[j].i)]
        return found + [Eq(self.v, self.Lm @ self.i.applyfunc(der))]


def _dim_l(N: int) -> int:  # noqa: N803 - Modelica name
    """``div(N*(N + 1), 2)``: the number of entries of a symmetric N x N matrix's upper triangle."""
    return int(N) * (int(N) + 1) // 2


# --------------------------------------------------------------------------
# signal adaptors (a oneport as an input/output block, e.g. for an FMU)

# appended section: its own imports, kept next to the only classes that need them
from acausal.components.checks import where  # noqa: E402
from acausal.functions import prescribed  # noqa: E402
from acausal.language import RealOutput  # noqa: E402


class _ElectricalAdaptor(Component):
    """The oneport and the switches of both electrical adaptors (each declares its protected signals, in its units).

    The MSL builds them on Modelica.Blocks.Interfaces.Adaptors'
    FlowToPotentialAdaptor and PotentialToFlowAdaptor with ``use_pder2 =
    use_fder2 = false`` (final): a potential and a flow with at most their
    first derivatives.  Unlike the mechanical adaptors they keep the flow
    derivative ``use_fder``, so the generic classes of
    :mod:`acausal.components.adaptors` (which leave it out) are not used;
    the equations here are theirs with those two switches false.
    """

    use_pder = Parameter(True, structural=True, description="Use signal for 1st derivative of potential (dv)")
    use_fder = Parameter(True, structural=True, description="Use signal for 1st derivative of flow (di)")
    v = Variable(unit="V", description="Voltage drop between the two pins (= p.v - n.v)")
    i = Variable(unit="A", description="Current flowing from pin p to pin n")
    pin_p = PositivePin(description="Positive pin")
    pin_n = NegativePin(description="Negative pin")

    def oneport(self) -> list:
        """The pins' equations: ``v = pin_p.v - pin_n.v``, ``i = pin_p.i``, ``pin_p.i + pin_n.i = 0``."""
        return [Eq(self.v, self.pin_p.v - self.pin_n.v),
                Eq(self.i, self.pin_p.i),
                Eq(self.pin_p.i + self.pin_n.i, 0)]

    def prescribed_input(self, value: sp.Basic, use_derivative: bool, name: str) -> sp.Basic:
        """``u``: the input ``value`` whose time derivative is the input ``u1`` if given.

        The MSL's ``state1({value, u1}, time)``; a second derivative is that
        of ``u1`` (``differentiate_last``: a Modelica tool differentiates the
        body of ``state1der1``, which has no derivative of its own).
        """
        if not use_derivative:
            return value
        return prescribed(value, self.u1, name=f"{where(self)}.{name}", differentiate_last=True)


class GeneralCurrentToVoltageAdaptor(_ElectricalAdaptor):
    """Current and its derivative in, voltage and its derivative out
    (Modelica.Electrical.Analog.Basic.GeneralCurrentToVoltageAdaptor).

    Wraps the circuit between ``pin_p`` and ``pin_n`` as a signal block:
    the input current ``f`` enters ``pin_p`` (``i = f``; the circuit
    delivers it), the output ``p = v`` is the voltage between the pins and
    ``pder = der(v)`` (if ``use_pder``).  Where the circuit needs ``der(i)``
    (an inductor) it takes the input ``fder`` (if ``use_fder``), which must
    be consistent, ``fder = der(f)``.  The adaptor has no ground.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.GeneralCurrentToVoltageAdaptor"

    p = RealOutput(unit="V", description="Output for potential (v)")
    pder = RealOutput(unit="V/s", condition="use_pder", description="Optional output for der(potential) (dv)")
    f = RealInput(unit="A", description="Input for flow (i)")
    fder = RealInput(unit="A/s", condition="use_fder", description="Optional input for der(flow) (di)")
    # the protected signals: output = voltage, input = current
    y = Variable(unit="V", description="Output signal (protected)")
    y1 = Variable(unit="V/s", description="Optional 1st derivative of output (protected)")
    y2 = Variable(unit="V/s2", description="Optional 2nd derivative of output (protected)")
    u = Variable(unit="A", description="Input signal (protected)")
    u1 = Variable(unit="A/s", description="Optional 1st derivative of input (protected)")
    u2 = Variable(unit="A/s2", description="Optional 2nd derivative of input (protected)")

    def equations(self):
        equations = [
            Eq(self.y, self.p),
            Eq(self.y1, der(self.y) if self.use_pder else 0),
            Eq(self.y2, 0),
            Eq(self.u1, self.fder if self.use_fder else 0),
            Eq(self.u2, 0),
            Eq(self.u, self.prescribed_input(self.f, self.use_fder, "f")),
            *self.oneport(),
            Eq(self.y, self.v),  # output = potential = voltage
            Eq(self.u, self.i),  # input = flow = current
        ]
        if self.use_pder:
            equations.append(Eq(self.pder, self.y1))
        return equations


class GeneralVoltageToCurrentAdaptor(_ElectricalAdaptor):
    """Voltage and its derivative in, current and its derivative out
    (Modelica.Electrical.Analog.Basic.GeneralVoltageToCurrentAdaptor).

    Wraps the circuit between ``pin_p`` and ``pin_n`` as a signal block:
    the input ``p`` is the voltage between the pins, the output ``f = -i``
    the current the circuit draws out of ``pin_p`` and ``fder = der(f)``
    (if ``use_fder``).  Where the circuit needs ``der(v)`` (a capacitor) it
    takes the input ``pder`` (if ``use_pder``), which must be consistent,
    ``pder = der(p)``.  The adaptor has no ground.
    """

    modelica_name = "Modelica.Electrical.Analog.Basic.GeneralVoltageToCurrentAdaptor"

    p = RealInput(unit="V", description="Input for potential (v)")
    pder = RealInput(unit="V/s", condition="use_pder", description="Optional input for der(potential) (dv)")
    f = RealOutput(unit="A", description="Output for flow (i)")
    fder = RealOutput(unit="A/s", condition="use_fder", description="Optional output for der(flow) (di)")
    # the protected signals: output = current, input = voltage
    y = Variable(unit="A", description="Output signal (protected)")
    y1 = Variable(unit="A/s", description="Optional 1st derivative of output (protected)")
    y2 = Variable(unit="A/s2", description="Optional 2nd derivative of output (protected)")
    u = Variable(unit="V", description="Input signal (protected)")
    u1 = Variable(unit="V/s", description="Optional 1st derivative of input (protected)")
    u2 = Variable(unit="V/s2", description="Optional 2nd derivative of input (protected)")

    def equations(self):
        equations = [
            Eq(self.y, -self.f),
            Eq(self.y1, -der(self.y) if self.use_fder else 0),
            Eq(self.y2, 0),
            Eq(self.u1, self.pder if self.use_pder else 0),
            Eq(self.u2, 0),
            Eq(self.u, self.prescribed_input(self.p, self.use_pder, "p")),
            *self.oneport(),
            Eq(self.y, self.i),  # output = flow = current
            Eq(self.u, self.v),  # input = potential = voltage
        ]
        if self.use_fder:
            equations.append(Eq(self.fder, self.y1))
        return equations


__all__ += ["GeneralCurrentToVoltageAdaptor", "GeneralVoltageToCurrentAdaptor"]
