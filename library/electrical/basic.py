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
