"""DC machines (Modelica.Electrical.Machines.BasicMachines.DCMachines) and the pieces they are built of.

Written from the MSL 4.1.0 sources of Modelica.Electrical.Machines:

* the loss parameter records (``Machines.Losses.FrictionParameters``,
  ``CoreParameters``, ``StrayLoadParameters``, ``BrushParameters``): each a
  component holding only parameters, so that a machine's
  ``frictionParameters.PRef`` is named as in Modelica and modified as
  Modelica modifies a record (``DC_PermanentMagnet(frictionParameters=
  dict(PRef=100))``).  The reference values the MSL leaves without default
  (``wRef``, ``VRef``, ``IRef``) default to 1 here, so that a loss model
  stands alone; the machines bind them to their nominal values, as the MSL
  does.  Whether a loss is present (``PRef > 0``, ``V > 0``)
  selects its equations, as the MSL's ``if`` on those parameters does once a
  tool evaluates them: these parameters are structural;
* the loss models (``Machines.Losses.Friction``, ``Losses.DCMachines.Brush``,
  ``Core``, ``StrayLoad``), the linear air gap ``AirGapDC``, the armature and
  field inductor ``InductorDC`` and ``CompoundDCExcitation``;
* the power balance records (``Machines.Interfaces.DCMachines.
  PartialPowerBalanceDCMachines``, ``PowerBalanceDCPM``, ``PowerBalanceDCEE``,
  ``PowerBalanceDCSE``): each machine's ``powerBalance`` sub-component, its
  terms (W) bound by the machine as the MSL's ``final`` modifiers bind them
  (``powerArmature = va*ia``, ``powerMechanical = wMechanical*tauShaft``,
  ``powerInertiaRotor = J*a*w`` of the rotor inertia, ``lossPowerArmature =
  ra.LossPower`` ..., the excitation's power and losses), the record summing
  the losses into ``lossPowerTotal``.  As in the MSL, the windings' magnetic
  energy is in no term: the balance (electrical power = mechanical power +
  inertia powers + total losses) holds once the currents are steady;
* the three DC machines: permanent magnet, electrically (shunt/separately)
  excited and series excited, each with armature resistance and inductance,
  brushes, core, stray load and friction losses and rotor/stator inertias.

The thermal side is simplified (the MSL's ``thermalAmbient`` and its
composite ``thermalPort`` connector): without ``useThermalPort`` the
windings are at their operational temperatures (``TaOperational``,
``TeOperational``) and the loss models have no heat port (the MSL sends
their heat to fixed temperatures, which feeds nothing back); with ``useThermalPort`` every loss has a heat
port of its own on the machine, named as the MSL's thermal port's members
(``thermalPort_heatPortArmature`` for ``thermalPort.heatPortArmature``):
acausal has no connectors made of connectors, so the MSL's composite
``thermalPort`` stays a set of separate heat ports.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from acausal.hybrid import Assert, noEvent, smooth
from acausal.language import Component, Eq, Parameter, RealInput, Variable, der
from acausal.components.declarations import DerivedDefaults
from acausal.components.electrical import EPS, NegativePin, OnePort, PositivePin
from acausal.components.rotational import Flange_a
from acausal.components.thermal import HeatPort_a, PartialElementaryConditionalHeatPortWithoutT
from acausal.library.electrical.basic import Ground, Resistor
from acausal.library.electrical.sources import ConstantCurrent
from acausal.library.rotational.components import Fixed, Inertia

__all__ = [
    "FrictionParameters",
    "CoreParameters",
    "StrayLoadParameters",
    "BrushParameters",
    "Friction",
    "Brush",
    "Core",
    "StrayLoad",
    "InductorDC",
    "AirGapDC",
    "CompoundDCExcitation",
    "PartialPowerBalanceDCMachines",
    "PowerBalanceDCPM",
    "PowerBalanceDCEE",
    "PowerBalanceDCSE",
    "DC_PermanentMagnet",
    "DC_ElectricalExcited",
    "DC_SeriesExcited",
    "convert_alpha",
    "convert_resistance",
    "brush_voltage_drop",
]

#: Modelica.Constants.small: the lower bound of the reference speeds and currents.
SMALL = 1e-60
#: Modelica.Constants.pi.
PI = sp.pi


def convert_alpha(alpha1: Any, T2: Any, T1: Any = 293.15) -> Any:  # noqa: N803 - Modelica names
    """Temperature coefficient converted from T1 (default 20 degC) to T2 (Modelica.Electrical.Machines.Thermal.convertAlpha).

    Parameters
    ----------
    alpha1 : number or sympy expression
        Temperature coefficient at ``T1`` (1/K).
    T2, T1 : number or sympy expression
        The temperature to convert to and the one ``alpha1`` refers to (K).

    Returns
    -------
    number or sympy expression
        ``alpha1/(1 + alpha1*(T2 - T1))``.
    """
    return alpha1 / (1 + alpha1 * (T2 - T1))


def convert_resistance(RRef: Any, TRef: Any, alpha20: Any, T: Any) -> Any:  # noqa: N803 - Modelica names
    """Resistance at temperature T (Modelica.Electrical.Machines.Thermal.convertResistance).

    Parameters
    ----------
    RRef : number or sympy expression
        Resistance at ``TRef`` (Ohm).
    TRef : number or sympy expression
        Reference temperature (K).
    alpha20 : number or sympy expression
        Temperature coefficient at 20 degC (1/K).
    T : number or sympy expression
        Actual temperature (K).

    Returns
    -------
    number or sympy expression
        ``RRef*(1 + convert_alpha(alpha20, TRef)*(T - TRef))``.
    """
    return RRef * (1 + convert_alpha(alpha20, TRef) * (T - TRef))


def brush_voltage_drop(V: float, ILinear: Any, i: Any) -> Any:  # noqa: N803 - Modelica names
    """Voltage drop of carbon brushes (Modelica.Electrical.Machines.Losses.DCMachines.brushVoltageDrop).

    Parameters
    ----------
    V : float
        Total voltage drop of the brushes for currents above ``ILinear``
        (V; a value, since it decides whether there is a drop at all).
    ILinear : number or sympy expression
        Current below which the drop is linear (A).
    i : number or sympy expression
        Actual current (A).

    Returns
    -------
    number or sympy expression
        0 if ``V <= 0``; else ``V`` above ``ILinear``, ``-V`` below
        ``-ILinear`` and ``V*i/ILinear`` in between.
    """
    if V <= 0:
        return 0
    return sp.Piecewise((V, i > ILinear), (-V, i < -ILinear), (V * i / ILinear, True))


# --------------------------------------------------------------------------
# loss parameter records


class _Record(Component):
    """A Modelica record: parameters only, no equations, no connectors."""

    modelica_name = None


class FrictionParameters(DerivedDefaults, _Record):
    """Parameter record for friction losses (Modelica.Electrical.Machines.Losses.FrictionParameters).

    Friction losses ``PRef`` at the speed ``wRef``, the torque growing with
    ``w^power_w``; linear (``tauLinear*w/wLinear``) below ``wLinear =
    0.001*wRef``.  ``tauRef``, ``linear``, ``wLinear`` and ``tauLinear`` are
    final in the MSL: computed, not to be modified.
    """

    modelica_name = "Modelica.Electrical.Machines.Losses.FrictionParameters"

    derived_defaults = {
        "tauRef": lambda r: 0 if r.PRef <= 0 else r.PRef / r.wRef,
        "wLinear": lambda r: r.linear * r.wRef,
        "tauLinear": lambda r: 0 if r.PRef <= 0 else r.tauRef * (r.wLinear / r.wRef) ** r.power_w,
    }

    PRef = Parameter(0.0, unit="W", min=0, structural=True, description="Reference friction losses at wRef")
    wRef = Parameter(1.0, unit="rad/s", min=SMALL,
                     description="Reference angular velocity that the PRef refer to (MSL: no default)")
    power_w = Parameter(2.0, min=SMALL, description="Exponent of friction torque w.r.t. angular velocity")
    tauRef = Parameter(None, unit="N.m", description="Reference friction torque at reference angular velocity (final)")
    linear = Parameter(0.001, description="Linear angular velocity range with respect to reference angular velocity (final)")
    wLinear = Parameter(None, unit="rad/s", description="Linear angular velocity range (final)")
    tauLinear = Parameter(None, unit="N.m", description="Torque corresponding with linear angular velocity range (final)")


class CoreParameters(DerivedDefaults, _Record):
    """Parameter record for core losses (Modelica.Electrical.Machines.Losses.CoreParameters).

    Core losses ``PRef`` at the inner voltage ``VRef`` (and speed ``wRef``)
    give the conductance ``GcRef = PRef/VRef^2/m``; only eddy current
    losses (``ratioHysteresis = 0``, final in the MSL).
    """

    modelica_name = "Modelica.Electrical.Machines.Losses.CoreParameters"

    derived_defaults = {
        "GcRef": lambda r: 0 if r.PRef <= 0 else r.PRef / r.VRef ** 2 / r.m,
        "wMin": lambda r: 1e-6 * r.wRef,
    }

    m = Parameter(1, structural=True, description="Number of phases (1 for DC, 3 for induction machines)")
    PRef = Parameter(0.0, unit="W", min=0, structural=True,
                     description="Reference core losses at reference inner voltage VRef")
    VRef = Parameter(1.0, unit="V", min=SMALL,
                     description="Reference inner RMS voltage that reference core losses PRef refer to (MSL: no default)")
    wRef = Parameter(1.0, unit="rad/s", min=SMALL,
                     description="Reference angular velocity that reference core losses PRef refer to (MSL: no default)")
    ratioHysteresis = Parameter(0.0, min=0, max=1,  # noqa: N815 - Modelica name
                                description="Ratio of hysteresis losses with respect to the total core losses "
                                            "(final: hysteresis losses are not implemented)")
    GcRef = Parameter(None, unit="S", description="Reference conductance at reference frequency and voltage (final)")
    wMin = Parameter(None, unit="rad/s", description="Angular velocity limit (final)")  # noqa: N815 - Modelica name


class StrayLoadParameters(DerivedDefaults, _Record):
    """Parameter record for stray load losses (Modelica.Electrical.Machines.Losses.StrayLoadParameters).

    Stray load losses ``PRef`` at the current ``IRef`` and speed ``wRef``:
    a braking torque ``tauRef*(i/IRef)^2*(|w|/wRef)^power_w``.
    """

    modelica_name = "Modelica.Electrical.Machines.Losses.StrayLoadParameters"

    derived_defaults = {"tauRef": lambda r: 0 if r.PRef <= 0 else r.PRef / r.wRef}

    PRef = Parameter(0.0, unit="W", min=0, structural=True, description="Reference stray load losses at IRef and wRef")
    IRef = Parameter(1.0, unit="A", min=SMALL, description="Reference RMS current that PRef refers to (MSL: no default)")
    wRef = Parameter(1.0, unit="rad/s", min=SMALL,
                     description="Reference angular velocity that PRef refers to (MSL: no default)")
    power_w = Parameter(1.0, min=SMALL, description="Exponent of stray load loss torque w.r.t. angular velocity")
    tauRef = Parameter(None, unit="N.m",
                       description="Reference stray load torque at reference angular velocity and current (final)")


class BrushParameters(_Record):
    """Parameter record for brush losses (Modelica.Electrical.Machines.Losses.BrushParameters).

    The brushes drop ``V`` for currents above ``ILinear``, linearly less
    below.
    """

    modelica_name = "Modelica.Electrical.Machines.Losses.BrushParameters"

    V = Parameter(0.0, unit="V", structural=True, description="Total voltage drop of brushes for currents > ILinear")
    ILinear = Parameter(0.01, unit="A",  # noqa: N815 - Modelica name
                        description="Current indicating linear voltage region of brush voltage drop")


def _record_values(record: Component) -> dict[str, Any]:
    """A record's parameters as modifiers of another record of its class (Modelica's ``final r = other``)."""
    derived = set()
    for klass in type(record).__mro__:
        derived |= set(vars(klass).get("derived_defaults", {}))
    return {name: getattr(record, name) for name, declaration in record.declarations().items()
            if isinstance(declaration, Parameter) and name not in derived and name != "linear"
            and name != "ratioHysteresis"}


# --------------------------------------------------------------------------
# loss models


class _FlangeSupport(Component):
    """Shaft and support (Modelica.Electrical.Machines.Interfaces.FlangeSupport).

    ``phi = flange.phi - support.phi``, ``w = der(phi)``, ``tau =
    -flange.tau = support.tau``: the torque ``tau`` the element exerts.
    """

    modelica_name = "Modelica.Electrical.Machines.Interfaces.FlangeSupport"

    flange = Flange_a(description="Shaft end")
    support = Flange_a(description="Housing and support")
    phi = Variable(unit="rad", description="Angle between shaft and support")
    tau = Variable(unit="N.m", description="Torque")
    w = Variable(unit="rad/s", description="Relative angular velocity of flange and support")

    def equations(self):
        return [Eq(self.phi, self.flange.phi - self.support.phi),
                Eq(self.w, der(self.phi)),
                Eq(self.tau, -self.flange.tau),
                Eq(self.tau, self.support.tau)]


class Friction(_FlangeSupport, PartialElementaryConditionalHeatPortWithoutT):
    """Model of angular velocity dependent friction losses (Modelica.Electrical.Machines.Losses.Friction).

    ``tau = -tauRef*sign(w)*(|w|/wRef)^power_w`` above ``wLinear``,
    ``-tauLinear*w/wLinear`` below (continuous there, no event), none when
    ``frictionParameters.PRef <= 0``; ``lossPower = -tau*w``.  Give the
    record's values as ``frictionParameters=dict(PRef=..., wRef=...)``.
    """

    modelica_name = "Modelica.Electrical.Machines.Losses.Friction"

    def build(self) -> None:
        self.frictionParameters = FrictionParameters()  # noqa: N815 - Modelica name

    def equations(self):
        p = self.frictionParameters
        if p.PRef <= 0:
            law = 0
        else:
            law = -noEvent(sp.Piecewise(
                (p.tauRef * sp.sign(self.w) * (sp.Abs(self.w) / p.wRef) ** p.power_w, sp.Abs(self.w) > p.wLinear),
                (p.tauLinear * self.w / p.wLinear, True)))
        return [Eq(self.tau, law), Eq(self.lossPower, -self.tau * self.w)]


class Brush(OnePort, PartialElementaryConditionalHeatPortWithoutT):
    """Model considering voltage drop of carbon brushes (Modelica.Electrical.Machines.Losses.DCMachines.Brush).

    ``v = V`` for ``i > ILinear``, ``-V`` for ``i < -ILinear``, linear in
    between (the switches are events; the drop is continuous), ``v = 0``
    when ``brushParameters.V <= 0``; ``lossPower = v*i``.
    """

    modelica_name = "Modelica.Electrical.Machines.Losses.DCMachines.Brush"

    def build(self) -> None:
        self.brushParameters = BrushParameters()  # noqa: N815 - Modelica name

    def equations(self):
        p = self.brushParameters
        drop = 0 if p.V <= 0 else smooth(-1, brush_voltage_drop(p.V, p.ILinear, self.i))
        return [Eq(self.v, drop), Eq(self.lossPower, self.v * self.i)]


class Core(OnePort, PartialElementaryConditionalHeatPortWithoutT):
    """Model of core losses (Modelica.Electrical.Machines.Losses.DCMachines.Core).

    A conductance ``Gc = GcRef`` across the inner voltage (eddy current
    losses only), none (``Gc = 0``, ``i = 0``) when ``coreParameters.PRef
    <= 0``; ``lossPower = v*i``.  ``w`` is the remagnetization speed (an
    input the machine binds to its air gap's speed); ``wLimit =
    max(|w|, wMin)`` is kept for the hysteresis losses the MSL has not
    implemented.
    """

    modelica_name = "Modelica.Electrical.Machines.Losses.DCMachines.Core"

    w = RealInput(unit="rad/s", description="Remagnetization angular velocity")
    Gc = Variable(unit="S", description="Variable core loss conductance")
    wLimit = Variable(unit="rad/s", description="Limited angular velocity (protected)")  # noqa: N815 - Modelica name

    def build(self) -> None:
        self.coreParameters = CoreParameters(m=1)  # noqa: N815 - Modelica name

    def equations(self):
        p = self.coreParameters
        if p.PRef <= 0:
            loss = [Eq(self.Gc, 0), Eq(self.i, 0)]
        else:
            loss = [Eq(self.Gc, p.GcRef), Eq(self.i, self.Gc * self.v)]
        return [Eq(self.wLimit, noEvent(sp.Max(sp.Abs(self.w), p.wMin))),
                *loss,
                Eq(self.lossPower, self.v * self.i)]


class StrayLoad(OnePort, _FlangeSupport, PartialElementaryConditionalHeatPortWithoutT):
    """Model of stray load losses dependent on current and speed (Modelica.Electrical.Machines.Losses.DCMachines.StrayLoad).

    In series with the armature (``v = 0``), it brakes the shaft by ``tau =
    -tauRef*(i/IRef)^2*sign(w)*(|w|/wRef)^power_w`` (none when
    ``strayLoadParameters.PRef <= 0``); ``lossPower = -tau*w``.
    """

    modelica_name = "Modelica.Electrical.Machines.Losses.DCMachines.StrayLoad"

    def build(self) -> None:
        self.strayLoadParameters = StrayLoadParameters()  # noqa: N815 - Modelica name

    def equations(self):
        p = self.strayLoadParameters
        if p.PRef <= 0:
            law = 0
        else:
            # sign and abs expand to noEvent in Modelica: no events
            law = -p.tauRef * (self.i / p.IRef) ** 2 * noEvent(
                sp.sign(self.w) * (sp.Abs(self.w) / p.wRef) ** p.power_w)
        return [Eq(self.v, 0), Eq(self.tau, law), Eq(self.lossPower, -self.tau * self.w)]


# --------------------------------------------------------------------------
# electrical components of the machines


class InductorDC(OnePort):
    """Ideal linear electrical inductor for electrical DC machines (Modelica.Electrical.Machines.BasicMachines.Components.InductorDC).

    ``v = L*der(i)``, or ``v = 0`` when ``quasiStatic`` (no electrical
    transients).
    """

    modelica_name = "Modelica.Electrical.Machines.BasicMachines.Components.InductorDC"

    L = Parameter(1.0, unit="H", description="Inductance")
    quasiStatic = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                            description="No electrical transients if true")
    i = Variable(unit="A", start=0.0, description="Current flowing from pin p to pin n")

    def equations(self):
        return [Eq(self.v, 0 if self.quasiStatic else self.L * der(self.i))]


class AirGapDC(Component):
    """Linear airgap model of a DC machine (Modelica.Electrical.Machines.BasicMachines.Components.AirGapDC).

    The excitation flux ``psi_e = Le*ie`` induces ``vai =
    turnsRatio*psi_e*w`` in the armature and, with the armature current,
    the torque ``tauElectrical = turnsRatio*psi_e*ia`` on ``flange``
    (reaction on ``support``); ``vei = der(psi_e)`` (0 when
    ``quasiStatic``) across the excitation pins.  (PartialAirGapDC's
    equations with AirGapDC's flux law.)
    """

    modelica_name = "Modelica.Electrical.Machines.BasicMachines.Components.AirGapDC"

    quasiStatic = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                            description="No electrical transients if true")
    turnsRatio = Parameter(1.0, unit="1",  # noqa: N815 - Modelica name
                           description="Ratio of armature turns over number of turns of the excitation winding")
    Le = Parameter(1.0, unit="H", description="Excitation inductance")
    w = Variable(unit="rad/s", description="Angular velocity")
    vei = Variable(unit="V", description="Voltage drop across field excitation inductance")
    ie = Variable(unit="A", description="Excitation current")
    psi_e = Variable(unit="Wb", description="Excitation flux")
    vai = Variable(unit="V", description="Induced armature voltage")
    ia = Variable(unit="A", description="Armature current")
    tauElectrical = Variable(unit="N.m", description="Electrical torque")  # noqa: N815 - Modelica name
    flange = Flange_a(description="Shaft")
    support = Flange_a(description="Support at which the reaction torque is acting")
    pin_ap = PositivePin(description="Positive armature pin")
    pin_ep = PositivePin(description="Positive excitation pin")
    pin_an = NegativePin(description="Negative armature pin")
    pin_en = NegativePin(description="Negative excitation pin")

    def equations(self):
        return [Eq(self.vai, self.pin_ap.v - self.pin_an.v),
                Eq(self.ia, self.pin_ap.i),
                Eq(self.ia, -self.pin_an.i),
                Eq(self.vei, self.pin_ep.v - self.pin_en.v),
                Eq(self.ie, self.pin_ep.i),
                Eq(self.ie, -self.pin_en.i),
                Eq(self.vei, 0 if self.quasiStatic else der(self.psi_e)),
                Eq(self.w, der(self.flange.phi) - der(self.support.phi)),
                Eq(self.vai, self.turnsRatio * self.psi_e * self.w),
                Eq(self.tauElectrical, self.turnsRatio * self.psi_e * self.ia),
                Eq(self.flange.tau, -self.tauElectrical),
                Eq(self.support.tau, self.tauElectrical),
                # excitation flux: linearly dependent on excitation current
                Eq(self.psi_e, self.Le * self.ie)]


class CompoundDCExcitation(Component):
    """Compound excitation = shunt + series (Modelica.Electrical.Machines.BasicMachines.Components.CompoundDCExcitation).

    The air gap's excitation current is the shunt current plus
    ``excitationTurnsRatio`` times the series current (``-i = ie +
    excitationTurnsRatio*ise``); the induced voltage ``v`` appears across the
    shunt winding and, scaled, across the series winding.
    """

    modelica_name = "Modelica.Electrical.Machines.BasicMachines.Components.CompoundDCExcitation"

    excitationTurnsRatio = Parameter(1.0, unit="1",  # noqa: N815 - Modelica name
                                     description="Ratio of series excitation turns over shunt excitation turns")
    v = Variable(unit="V", description="Voltage to the air gap (= pin_p.v - pin_n.v)")
    i = Variable(unit="A", description="Current to the air gap (= pin_p.i)")
    ve = Variable(unit="V", description="Shunt excitation voltage")
    ie = Variable(unit="A", description="Shunt excitation current")
    vse = Variable(unit="V", description="Series excitation voltage")
    ise = Variable(unit="A", description="Series excitation current")
    pin_p = PositivePin(description="Positive pin to airgap")
    pin_n = NegativePin(description="Negative pin to airgap")
    pin_ep = PositivePin(description="Positive pin to shunt excitation")
    pin_en = NegativePin(description="Negative pin to shunt excitation")
    pin_sep = PositivePin(description="Positive pin to series excitation")
    pin_sen = NegativePin(description="Negative pin to series excitation")

    def equations(self):
        return [Eq(self.v, self.pin_p.v - self.pin_n.v), Eq(self.i, self.pin_p.i),
                Eq(self.ve, self.pin_ep.v - self.pin_en.v), Eq(self.ie, self.pin_ep.i),
                Eq(self.vse, self.pin_sep.v - self.pin_sen.v), Eq(self.ise, self.pin_sep.i),
                # current balances
                Eq(self.pin_p.i + self.pin_n.i, 0),
                Eq(self.pin_ep.i + self.pin_en.i, 0),
                Eq(self.pin_sep.i + self.pin_sen.i, 0),
                # compound currents
                Eq(-self.i, self.ie + self.excitationTurnsRatio * self.ise),
                # induced voltages
                Eq(self.ve, self.v),
                Eq(self.vse, self.v * self.excitationTurnsRatio)]


# --------------------------------------------------------------------------
# power balance records


def _power(description: str) -> Variable:
    return Variable(unit="W", description=description)


class PartialPowerBalanceDCMachines(Component):
    """Partial power balance of DC machines (Modelica.Electrical.Machines.Interfaces.DCMachines.PartialPowerBalanceDCMachines).

    A record of outputs: the machine binds every term (the MSL's ``final``
    modifiers of the machine's ``powerBalance``), the record itself only
    sums the losses into ``lossPowerTotal``.  In a motor, ``powerArmature``
    (plus the excitation power) = ``powerMechanical`` + ``powerInertiaRotor``
    + ``powerInertiaStator`` + ``lossPowerTotal`` + the rate of change of the
    magnetic energy of the windings, which the record leaves out.
    """

    modelica_name = "Modelica.Electrical.Machines.Interfaces.DCMachines.PartialPowerBalanceDCMachines"

    powerArmature = _power("Electrical armature power")  # noqa: N815 - Modelica name
    powerMechanical = _power("Mechanical power")  # noqa: N815 - Modelica name
    powerInertiaStator = _power("Stator inertia power")  # noqa: N815 - Modelica name
    powerInertiaRotor = _power("Rotor inertia power")  # noqa: N815 - Modelica name
    lossPowerTotal = _power("Total loss power")  # noqa: N815 - Modelica name
    lossPowerArmature = _power("Armature copper losses")  # noqa: N815 - Modelica name
    lossPowerCore = _power("Core losses")  # noqa: N815 - Modelica name
    lossPowerStrayLoad = _power("Stray load losses")  # noqa: N815 - Modelica name
    lossPowerFriction = _power("Friction losses")  # noqa: N815 - Modelica name
    lossPowerBrush = _power("Brush losses")  # noqa: N815 - Modelica name

    def loss_terms(self) -> list[Any]:
        """The losses every DC machine has; a variant's total adds its excitation (or magnet) losses."""
        return [self.lossPowerArmature, self.lossPowerCore, self.lossPowerStrayLoad,
                self.lossPowerFriction, self.lossPowerBrush]


class PowerBalanceDCPM(PartialPowerBalanceDCMachines):
    """Power balance of DC machines with permanent magnet (Modelica.Electrical.Machines.Interfaces.DCMachines.PowerBalanceDCPM).

    ``lossPowerTotal`` includes the magnets' losses ``lossPowerPermanentMagnet``.
    """

    modelica_name = "Modelica.Electrical.Machines.Interfaces.DCMachines.PowerBalanceDCPM"

    lossPowerPermanentMagnet = _power("Permanent magnet losses")  # noqa: N815 - Modelica name

    def equations(self):
        return [Eq(self.lossPowerTotal, sp.Add(*self.loss_terms(), self.lossPowerPermanentMagnet))]


class PowerBalanceDCEE(PartialPowerBalanceDCMachines):
    """Power balance of DC machines with electrical excitation (Modelica.Electrical.Machines.Interfaces.DCMachines.PowerBalanceDCEE).

    ``powerExcitation`` is the electrical power into the (shunt) field
    winding; ``lossPowerTotal`` includes its copper losses
    ``lossPowerExcitation``.
    """

    modelica_name = "Modelica.Electrical.Machines.Interfaces.DCMachines.PowerBalanceDCEE"

    powerExcitation = _power("Electrical (shunt) excitation power")  # noqa: N815 - Modelica name
    lossPowerExcitation = _power("Excitation losses")  # noqa: N815 - Modelica name

    def equations(self):
        return [Eq(self.lossPowerTotal, sp.Add(*self.loss_terms(), self.lossPowerExcitation))]


class PowerBalanceDCSE(PartialPowerBalanceDCMachines):
    """Power balance of DC machines with series excitation (Modelica.Electrical.Machines.Interfaces.DCMachines.PowerBalanceDCSE).

    ``powerSeriesExcitation`` is the electrical power into the series field
    winding; ``lossPowerTotal`` includes its copper losses
    ``lossPowerSeriesExcitation``.
    """

    modelica_name = "Modelica.Electrical.Machines.Interfaces.DCMachines.PowerBalanceDCSE"

    powerSeriesExcitation = _power("Electrical series excitation power")  # noqa: N815 - Modelica name
    lossPowerSeriesExcitation = _power("Series excitation losses")  # noqa: N815 - Modelica name

    def equations(self):
        return [Eq(self.lossPowerTotal, sp.Add(*self.loss_terms(), self.lossPowerSeriesExcitation))]


# --------------------------------------------------------------------------
# the machines


def _heat_port(description: str) -> HeatPort_a:
    return HeatPort_a(condition="useThermalPort", description=description)


class _PartialBasicMachine(DerivedDefaults, Component):
    """Partial model for all machines (Modelica.Electrical.Machines.Interfaces.PartialBasicMachine).

    The rotor inertia ``Jr`` between the air gap and ``flange``, the stator
    inertia ``Js`` on the housing (the ``support`` when ``useSupport``,
    else fixed), the friction losses between them.  ``phiMechanical``,
    ``wMechanical`` are the rotor's angle and speed against the stator,
    ``tauElectrical`` the air gap torque, ``tauShaft`` the torque the shaft
    delivers.
    """

    modelica_name = "Modelica.Electrical.Machines.Interfaces.PartialBasicMachine"

    derived_defaults = {"Js": lambda m: m.Jr}

    Jr = Parameter(0.15, unit="kg.m2", description="Rotor's moment of inertia")
    useSupport = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                           description="Enable / disable (=fixed stator) support")
    Js = Parameter(None, unit="kg.m2", description="Stator's moment of inertia (default Jr)")
    useThermalPort = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                               description="Enable / disable (=fixed temperatures) thermal port")
    phiMechanical = Variable(unit="rad", start=0.0,  # noqa: N815 - Modelica name
                             description="Mechanical angle of rotor against stator")
    wMechanical = Variable(unit="rad/s", start=0.0, display_unit="rev/min",  # noqa: N815 - Modelica name
                           description="Mechanical angular velocity of rotor against stator")
    tauElectrical = Variable(unit="N.m", description="Electromagnetic torque")  # noqa: N815 - Modelica name
    tauShaft = Variable(unit="N.m", description="Shaft torque")  # noqa: N815 - Modelica name
    flange = Flange_a(description="Shaft")
    support = Flange_a(condition="useSupport", description="Support at which the reaction torque is acting")

    def friction_reference_speed(self) -> Any:
        """The default ``frictionParameters.wRef`` (the DC machines: ``wNominal``)."""
        raise NotImplementedError

    def build(self) -> None:
        self.frictionParameters = FrictionParameters(wRef=self.friction_reference_speed())  # noqa: N815
        self.inertiaRotor = Inertia(J=self.Jr)  # noqa: N815 - Modelica name
        self.inertiaStator = Inertia(J=self.Js)  # noqa: N815 - Modelica name
        self.connect(self.inertiaRotor.flange_b, self.flange)
        if self.useSupport:
            self.connect(self.inertiaStator.flange_b, self.support)
        else:
            self.fixed = Fixed()
            self.connect(self.internal_support(), self.fixed.flange)
        self.friction = Friction(useHeatPort=self.useThermalPort,
                                 frictionParameters=_record_values(self.frictionParameters))
        self.connect(self.inertiaRotor.flange_b, self.friction.flange)
        self.connect(self.friction.support, self.internal_support())
        if self.useThermalPort:
            self.connect(self.friction.heatPort, self.thermalPort_heatPortFriction)

    def internal_support(self):
        """The stator's housing node (the MSL's protected ``internalSupport``)."""
        return self.inertiaStator.flange_a

    def equations(self):
        return [Eq(self.phiMechanical, self.flange.phi - self.internal_support().phi),
                Eq(self.wMechanical, der(self.phiMechanical)),
                Eq(self.tauElectrical, self.inertiaRotor.flange_a.tau),
                Eq(self.tauShaft, -self.flange.tau)]


class _PartialBasicDCMachine(_PartialBasicMachine):
    """Partial model for DC machine (Modelica.Electrical.Machines.Interfaces.PartialBasicDCMachine).

    From ``pin_ap``: stray load losses, the armature resistance ``ra``
    (``Ra`` at ``TaRef``, temperature coefficient ``alpha20a`` at 20 degC,
    at ``TaOperational`` without thermal port), the armature inductance
    ``la``, then the air gap (the concrete machine's), parallel to it the
    core losses, and the brushes to ``pin_an``.  ``turnsRatio =
    ViNominal/(wNominal*psi_eNominal)`` makes the induced voltage at
    nominal speed and flux ``ViNominal``, the nominal armature voltage less
    the resistive and brush drops at ``IaNominal``.
    """

    modelica_name = "Modelica.Electrical.Machines.Interfaces.PartialBasicDCMachine"

    derived_defaults = {
        "turnsRatio": lambda m: m.ViNominal / (m.wNominal * m.psi_eNominal),
    }

    TaOperational = Parameter(293.15, unit="K", description="Operational armature temperature")
    VaNominal = Parameter(100.0, unit="V", description="Nominal armature voltage")
    IaNominal = Parameter(100.0, unit="A", description="Nominal armature current (>0..Motor, <0..Generator)")
    wNominal = Parameter(1425 * 2 * 3.141592653589793 / 60, unit="rad/s", display_unit="rev/min",  # noqa: N815
                         description="Nominal speed")
    TaNominal = Parameter(293.15, unit="K", description="Nominal armature temperature")
    Ra = Parameter(0.05, unit="Ohm", description="Armature resistance at TaRef")
    TaRef = Parameter(293.15, unit="K", description="Reference temperature of armature resistance")
    alpha20a = Parameter(0.0, unit="1/K", description="Temperature coefficient of armature resistance")
    La = Parameter(0.0015, unit="H", description="Armature inductance")
    ViNominal = Parameter(None, unit="V", description="Nominal induced Voltage (protected, final)")
    psi_eNominal = Parameter(None, unit="Wb", description="Nominal magnetic flux (protected, final)")
    turnsRatio = Parameter(None, unit="1",  # noqa: N815 - Modelica name
                           description="Ratio of armature turns over number of turns of the excitation winding "
                                       "(protected)")
    va = Variable(unit="V", description="Armature voltage")
    ia = Variable(unit="A", start=0.0, description="Armature current")
    pin_ap = PositivePin(description="Positive armature pin")
    pin_an = NegativePin(description="Negative armature pin")
    thermalPort_heatPortArmature = _heat_port("Heat port of armature (thermalPort.heatPortArmature)")  # noqa: N815
    thermalPort_heatPortCore = _heat_port("Heat port of (optional) core losses")  # noqa: N815
    thermalPort_heatPortStrayLoad = _heat_port("Heat port of (optional) stray losses")  # noqa: N815
    thermalPort_heatPortFriction = _heat_port("Heat port of (optional) friction losses")  # noqa: N815
    thermalPort_heatPortBrush = _heat_port("Heat port of (optional) brush losses")  # noqa: N815

    #: The class of ``powerBalance`` (the MSL's replaceable record, redeclared by each machine).
    power_balance_record: type[PartialPowerBalanceDCMachines] = PartialPowerBalanceDCMachines

    def friction_reference_speed(self) -> Any:
        return self.wNominal

    def armature_drop(self) -> Any:
        """Armature resistance at ``TaNominal`` times ``IaNominal`` plus the brush drop at ``IaNominal``."""
        return (convert_resistance(self.Ra, self.TaRef, self.alpha20a, self.TaNominal) * self.IaNominal
                + brush_voltage_drop(self.brushParameters.V, self.brushParameters.ILinear, self.IaNominal))

    def build(self) -> None:
        super().build()
        self.coreParameters = CoreParameters(m=1, VRef=self.ViNominal, wRef=self.wNominal)  # noqa: N815
        self.strayLoadParameters = StrayLoadParameters(IRef=self.IaNominal, wRef=self.wNominal)  # noqa: N815
        self.brushParameters = BrushParameters(ILinear=0.01 * self.IaNominal)  # noqa: N815
        self.ra = Resistor(R=self.Ra, T_ref=self.TaRef, alpha=convert_alpha(self.alpha20a, self.TaRef),
                           useHeatPort=self.useThermalPort, T=self.TaOperational)
        self.la = InductorDC(L=self.La, quasiStatic=False)
        self.brush = Brush(useHeatPort=self.useThermalPort, brushParameters=_record_values(self.brushParameters))
        self.core = Core(useHeatPort=self.useThermalPort, coreParameters=_record_values(self.coreParameters))
        self.strayLoad = StrayLoad(useHeatPort=self.useThermalPort,  # noqa: N815 - Modelica name
                                   strayLoadParameters=_record_values(self.strayLoadParameters))
        self.airGapDC = AirGapDC(turnsRatio=self.turnsRatio, Le=self.main_excitation_inductance())  # noqa: N815
        self.powerBalance = self.power_balance_record()  # noqa: N815 - Modelica name
        self.connect(self.la.p, self.ra.n)
        self.connect(self.brush.n, self.pin_an)
        self.connect(self.pin_ap, self.strayLoad.p)
        self.connect(self.strayLoad.n, self.ra.p)
        self.connect(self.strayLoad.support, self.internal_support())
        self.connect(self.la.p, self.core.p)
        self.connect(self.core.n, self.brush.p)
        self.connect(self.inertiaRotor.flange_b, self.strayLoad.flange)
        self.connect(self.airGapDC.pin_ap, self.la.n)
        self.connect(self.airGapDC.support, self.internal_support())
        self.connect(self.airGapDC.flange, self.inertiaRotor.flange_a)
        self.connect(self.airGapDC.pin_an, self.brush.p)
        if self.useThermalPort:
            self.connect(self.ra.heatPort, self.thermalPort_heatPortArmature)
            self.connect(self.core.heatPort, self.thermalPort_heatPortCore)
            self.connect(self.strayLoad.heatPort, self.thermalPort_heatPortStrayLoad)
            self.connect(self.brush.heatPort, self.thermalPort_heatPortBrush)

    def main_excitation_inductance(self) -> Any:
        """The air gap's excitation inductance ``Lme``."""
        raise NotImplementedError

    def equations(self):
        balance = self.powerBalance
        return [Assert(self.ViNominal > EPS, "VaNominal has to be > (Ra[+Rse])*IaNominal"),
                Eq(self.va, self.pin_ap.v - self.pin_an.v),
                Eq(self.ia, self.pin_ap.i),
                Eq(self.core.w, self.airGapDC.w),
                # the power balance: the terms every DC machine has
                Eq(balance.powerArmature, self.va * self.ia),
                Eq(balance.powerMechanical, self.wMechanical * self.tauShaft),
                Eq(balance.powerInertiaStator, self.inertiaStator.J * self.inertiaStator.a * self.inertiaStator.w),
                Eq(balance.powerInertiaRotor, self.inertiaRotor.J * self.inertiaRotor.a * self.inertiaRotor.w),
                Eq(balance.lossPowerArmature, self.ra.LossPower),
                Eq(balance.lossPowerCore, self.core.lossPower),
                Eq(balance.lossPowerStrayLoad, self.strayLoad.lossPower),
                Eq(balance.lossPowerFriction, self.friction.lossPower),
                Eq(balance.lossPowerBrush, self.brush.lossPower)]


class DC_PermanentMagnet(_PartialBasicDCMachine):  # noqa: N801 - Modelica name
    """Permanent magnet DC machine (Modelica.Electrical.Machines.BasicMachines.DCMachines.DC_PermanentMagnet).

    The magnets are an equivalent excitation current ``IeNominal = 1 A``
    (source ``ie``) through the air gap's excitation inductance ``Lme =
    1 H``: the flux is 1 Wb and ``turnsRatio = ViNominal/wNominal`` is the
    machine constant (V.s/rad = N.m/A).  Steady state at armature voltage
    ``va`` and shaft torque ``tau``: ``ia = (tau + tau_losses)/turnsRatio``,
    ``w = (va - Ra*ia - brush drop)/turnsRatio``.  With ``useThermalPort``
    the (loss-free) magnets have a heat port of their own too.
    """

    modelica_name = "Modelica.Electrical.Machines.BasicMachines.DCMachines.DC_PermanentMagnet"

    power_balance_record = PowerBalanceDCPM

    derived_defaults = {
        "ViNominal": lambda m: m.VaNominal - m.armature_drop(),
        "psi_eNominal": lambda m: 1.0,
    }

    TpmOperational = Parameter(293.15, unit="K", description="Operational temperature of permanent magnet (final)")  # noqa: N815
    thermalPort_heatPortPermanentMagnet = _heat_port("Heat port of permanent magnets")  # noqa: N815

    #: Modelica: protected constants Lme = 1 H, IeNominal = 1 A.
    LME = 1.0
    IE_NOMINAL = 1.0

    def main_excitation_inductance(self) -> Any:
        return self.LME

    def build(self) -> None:
        super().build()
        self.eGround = Ground()  # noqa: N815 - Modelica name
        self.ie = ConstantCurrent(I=self.IE_NOMINAL)
        self.connect(self.eGround.p, self.ie.p)
        self.connect(self.airGapDC.pin_ep, self.ie.n)
        self.connect(self.airGapDC.pin_en, self.eGround.p)

    def equations(self):
        # the magnets are loss-free: nothing in the power balance, nothing into their heat port
        magnets = [Eq(self.powerBalance.lossPowerPermanentMagnet, 0)]
        if self.useThermalPort:
            magnets.append(Eq(self.thermalPort_heatPortPermanentMagnet.Q_flow, 0))
        return magnets


class _ExcitationWinding(_PartialBasicDCMachine):
    """What the electrically excited machines share: the winding ``re`` + ``lesigma`` from ``pin_ep``."""

    modelica_name = None

    derived_defaults = {"Lme": lambda m: m.Le * (1 - m.sigmae), "Lesigma": lambda m: m.Le * m.sigmae}

    TeRef = Parameter(293.15, unit="K", description="Reference temperature of excitation resistance")
    alpha20e = Parameter(0.0, unit="1/K", description="Temperature coefficient of excitation resistance")
    sigmae = Parameter(0.0, unit="1", min=0, max=0.99, description="Stray fraction of total excitation inductance")
    TeOperational = Parameter(293.15, unit="K", description="Operational excitation temperature")
    Lme = Parameter(None, unit="H", description="Main part of excitation inductance (protected, final)")
    Lesigma = Parameter(None, unit="H", description="Stray part of excitation inductance (protected, final)")
    ve = Variable(unit="V", description="Field excitation voltage")
    ie = Variable(unit="A", start=0.0, description="Field excitation current")
    pin_ep = PositivePin(description="Positive excitation pin")
    pin_en = NegativePin(description="Negative excitation pin")

    def main_excitation_inductance(self) -> Any:
        return self.Lme

    def build_winding(self) -> None:
        """The excitation resistance and stray inductance, the compound excitation and its grounds."""
        self.re = Resistor(R=self.Re, T_ref=self.TeRef, alpha=convert_alpha(self.alpha20e, self.TeRef),
                           useHeatPort=self.useThermalPort, T=self.TeOperational)
        self.lesigma = InductorDC(L=self.Lesigma, quasiStatic=False)
        self.compoundDCExcitation = CompoundDCExcitation(excitationTurnsRatio=1)  # noqa: N815
        self.ground = Ground()
        self.connect(self.re.n, self.lesigma.p)
        self.connect(self.airGapDC.pin_en, self.compoundDCExcitation.pin_n)
        self.connect(self.airGapDC.pin_ep, self.compoundDCExcitation.pin_p)
        self.connect(self.ground.p, self.airGapDC.pin_en)

    def equations(self):
        return [Eq(self.ve, self.pin_ep.v - self.pin_en.v), Eq(self.ie, self.pin_ep.i)]


class DC_ElectricalExcited(_ExcitationWinding):  # noqa: N801 - Modelica name
    """Electrical shunt/separate excited linear DC machine (Modelica.Electrical.Machines.BasicMachines.DCMachines.DC_ElectricalExcited).

    The field winding between ``pin_ep`` and ``pin_en``: resistance ``Re``
    (at ``TeRef``, ``alpha20e``, ``TeOperational``), stray inductance
    ``Le*sigmae`` and main inductance ``Lme = Le*(1 - sigmae)`` in the air
    gap, so the flux is ``Lme*ie``; ``psi_eNominal = Lme*IeNominal``.  Shunt
    or separate excitation is the user's circuit.
    """

    modelica_name = "Modelica.Electrical.Machines.BasicMachines.DCMachines.DC_ElectricalExcited"

    power_balance_record = PowerBalanceDCEE

    derived_defaults = {
        "ViNominal": lambda m: m.VaNominal - m.armature_drop(),
        "psi_eNominal": lambda m: m.Lme * m.IeNominal,
    }

    IeNominal = Parameter(1.0, unit="A", description="Nominal excitation current")
    Re = Parameter(100.0, unit="Ohm", description="Field excitation resistance at TeRef")
    Le = Parameter(1.0, unit="H", description="Total field excitation inductance")
    thermalPort_heatPortExcitation = _heat_port("Heat port of (shunt) excitation")  # noqa: N815

    def build(self) -> None:
        super().build()
        self.build_winding()
        self.groundSE = Ground()  # noqa: N815 - Modelica name
        self.connect(self.re.p, self.pin_ep)
        self.connect(self.groundSE.p, self.compoundDCExcitation.pin_sen)
        self.connect(self.pin_en, self.compoundDCExcitation.pin_en)
        self.connect(self.compoundDCExcitation.pin_ep, self.lesigma.n)
        if self.useThermalPort:
            self.connect(self.re.heatPort, self.thermalPort_heatPortExcitation)

    def equations(self):
        return [Eq(self.powerBalance.powerExcitation, self.ve * self.ie),
                Eq(self.powerBalance.lossPowerExcitation, self.re.LossPower)]


class DC_SeriesExcited(_ExcitationWinding):  # noqa: N801 - Modelica name
    """Series excited linear DC machine (Modelica.Electrical.Machines.BasicMachines.DCMachines.DC_SeriesExcited).

    The series winding between ``pin_ep`` and ``pin_en`` (resistance
    ``Re``, inductance ``Le``) is connected in series with the armature by
    the user's circuit (``pin_an`` to ``pin_ep``): the flux ``Lme*ia``
    grows with the current, the torque with its square.  ``VaNominal``
    includes the winding's drop; ``psi_eNominal = Lme*|IaNominal|``.
    """

    modelica_name = "Modelica.Electrical.Machines.BasicMachines.DCMachines.DC_SeriesExcited"

    power_balance_record = PowerBalanceDCSE

    derived_defaults = {
        "ViNominal": lambda m: (m.VaNominal - m.armature_drop()
                                - convert_resistance(m.Re, m.TeRef, m.alpha20e, m.TeNominal) * m.IaNominal),
        "psi_eNominal": lambda m: m.Lme * sp.Abs(m.IaNominal),
    }

    wNominal = Parameter(1410 * 2 * 3.141592653589793 / 60, unit="rad/s", display_unit="rev/min",  # noqa: N815
                         description="Nominal speed")
    Re = Parameter(0.01, unit="Ohm", description="Series excitation resistance at TeRef")
    Le = Parameter(0.0005, unit="H", description="Total field excitation inductance")
    TeNominal = Parameter(293.15, unit="K", description="Nominal series excitation temperature")
    thermalPort_heatPortSeriesExcitation = _heat_port("Heat port of series excitation")  # noqa: N815

    def build(self) -> None:
        super().build()
        self.build_winding()
        self.groundE = Ground()  # noqa: N815 - Modelica name
        self.connect(self.pin_ep, self.re.p)
        self.connect(self.compoundDCExcitation.pin_sen, self.pin_en)
        self.connect(self.compoundDCExcitation.pin_sep, self.lesigma.n)
        self.connect(self.compoundDCExcitation.pin_en, self.groundE.p)
        if self.useThermalPort:
            self.connect(self.re.heatPort, self.thermalPort_heatPortSeriesExcitation)

    def equations(self):
        return [Eq(self.powerBalance.powerSeriesExcitation, self.ve * self.ie),
                Eq(self.powerBalance.lossPowerSeriesExcitation, self.re.LossPower)]
