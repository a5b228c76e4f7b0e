"""Analog electrical connectors and partial models (Modelica.Electrical.Analog.Interfaces).

A pin carries the electric potential ``v`` (V) and the current ``i`` (A)
flowing into the component.  The partial models give the usual two-pin and
two-port bookkeeping (voltage drop, current through), the base classes of the
sensors and sources, and the conditional heat port through which resistive
elements hand their losses to a thermal network.
"""

from __future__ import annotations

import sympy as sp

from acausal.hybrid import Assert
from acausal.language import Component, Connector, Eq, Flow, Parameter, Potential, RealOutput, Variable
from acausal.components.declarations import DerivedDefaults
from acausal.components.thermal import HeatPort_a

__all__ = [
    "Pin",
    "PositivePin",
    "NegativePin",
    "TwoPin",
    "OnePort",
    "FourPin",
    "TwoPort",
    "AbsoluteSensor",
    "RelativeSensor",
    "VoltageSource",
    "CurrentSource",
    "ConditionalHeatPort",
    "TemperatureDependence",
    "EPS",
]

#: Modelica.Constants.eps: the smallest relative change the MSL temperature checks accept.
EPS = 1e-15


class Pin(Connector):
    """Pin of an electrical component (Modelica.Electrical.Analog.Interfaces.Pin).

    A potential ``v`` (V) and a flow ``i`` (A; positive when the current
    flows into the component the pin belongs to).
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.Pin"

    family = "electrical"
    v = Potential(unit="V", description="Potential at the pin")
    i = Flow(unit="A", description="Current flowing into the pin")


class PositivePin(Pin):
    """Positive pin of an electrical component (Modelica.Electrical.Analog.Interfaces.PositivePin), identical to Pin."""

    modelica_name = "Modelica.Electrical.Analog.Interfaces.PositivePin"


class NegativePin(Pin):
    """Negative pin of an electrical component (Modelica.Electrical.Analog.Interfaces.NegativePin), identical to Pin."""

    modelica_name = "Modelica.Electrical.Analog.Interfaces.NegativePin"


class TwoPin(Component):
    """Component with two electrical pins (Modelica.Electrical.Analog.Interfaces.TwoPin).

    ``v = p.v - n.v``; the currents are left to the component.
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.TwoPin"

    v = Variable(unit="V", description="Voltage drop of the two pins (= p.v - n.v)")
    p = PositivePin(description="Positive electrical pin")
    n = NegativePin(description="Negative electrical pin")

    def equations(self):
        return [Eq(self.v, self.p.v - self.n.v)]


class OnePort(TwoPin):
    """Component with two electrical pins p and n and current i from p to n (Modelica.Electrical.Analog.Interfaces.OnePort).

    ``v = p.v - n.v``, ``0 = p.i + n.i``, ``i = p.i``: what enters at p
    leaves at n.
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.OnePort"

    i = Variable(unit="A", description="Current flowing from pin p to pin n")

    def equations(self):
        return [Eq(0, self.p.i + self.n.i), Eq(self.i, self.p.i)]


class FourPin(Component):
    """Component with two pairs of each two electrical pins (Modelica.Electrical.Analog.Interfaces.FourPin).

    ``v1 = p1.v - n1.v``, ``v2 = p2.v - n2.v``, ``i1 = p1.i``, ``i2 = p2.i``.
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.FourPin"

    v1 = Variable(unit="V", description="Voltage drop of port 1 (= p1.v - n1.v)")
    v2 = Variable(unit="V", description="Voltage drop of port 2 (= p2.v - n2.v)")
    i1 = Variable(unit="A", description="Current flowing from pos. to neg. pin of port 1")
    i2 = Variable(unit="A", description="Current flowing from pos. to neg. pin of port 2")
    p1 = PositivePin(description="Positive electrical pin of port 1")
    n1 = NegativePin(description="Negative electrical pin of port 1")
    p2 = PositivePin(description="Positive electrical pin of port 2")
    n2 = NegativePin(description="Negative electrical pin of port 2")

    def equations(self):
        return [Eq(self.v1, self.p1.v - self.n1.v), Eq(self.v2, self.p2.v - self.n2.v),
                Eq(self.i1, self.p1.i), Eq(self.i2, self.p2.i)]


class TwoPort(FourPin):
    """Component with two electrical ports, including current (Modelica.Electrical.Analog.Interfaces.TwoPort).

    FourPin with each port a one-port: ``0 = p1.i + n1.i``, ``0 = p2.i + n2.i``.
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.TwoPort"

    def equations(self):
        return [Eq(0, self.p1.i + self.n1.i), Eq(0, self.p2.i + self.n2.i)]


class AbsoluteSensor(Component):
    """Base class to measure the absolute value of a pin variable (Modelica.Electrical.Analog.Interfaces.AbsoluteSensor).

    A pin ``p`` and a signal output ``y``; the sensor gives the equations.
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.AbsoluteSensor"

    p = PositivePin(description="Positive electrical pin")
    y = RealOutput(description="Measured quantity as Real output signal")


class RelativeSensor(Component):
    """Base class to measure a relative variable between two pins (Modelica.Electrical.Analog.Interfaces.RelativeSensor).

    Pins ``p`` and ``n`` and a signal output ``y``; the sensor gives the equations.
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.RelativeSensor"

    p = PositivePin(description="Positive electrical pin")
    n = NegativePin(description="Negative electrical pin")
    y = RealOutput(description="Measured quantity as Real output signal")


class _SignalDriven(OnePort):
    """A one-port driven by a signal source block ``signalSource`` (built by :meth:`signal_source`)."""

    startTime = Parameter(0.0, unit="s", description="Time offset")  # noqa: N815 - Modelica name

    def signal_source(self) -> Component:
        """The block whose output drives the port (override); it gets ``offset`` and ``startTime``."""
        raise NotImplementedError(f"{type(self).__name__} defines no signal source")

    def build(self) -> None:
        # MSL: replaceable Modelica.Blocks.Interfaces.SignalSource signalSource(final offset=offset,
        # final startTime=startTime); each concrete source redeclares it with its own block
        self.signalSource = self.signal_source()  # noqa: N815 - Modelica name


class VoltageSource(_SignalDriven):
    """Interface for voltage sources (Modelica.Electrical.Analog.Interfaces.VoltageSource).

    ``v = signalSource.y``: a Modelica.Blocks source (Step, Sine, ...) that
    the concrete source builds with its own parameters, plus ``offset`` and
    ``startTime``.
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.VoltageSource"

    offset = Parameter(0.0, unit="V", description="Voltage offset")

    def equations(self):
        return [Eq(self.v, self.signalSource.y)]


class CurrentSource(_SignalDriven):
    """Interface for current sources (Modelica.Electrical.Analog.Interfaces.CurrentSource).

    ``i = signalSource.y``: a Modelica.Blocks source that the concrete source
    builds with its own parameters, plus ``offset`` and ``startTime``.
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.CurrentSource"

    offset = Parameter(0.0, unit="A", description="Current offset")

    def equations(self):
        return [Eq(self.i, self.signalSource.y)]


class ConditionalHeatPort(Component):
    """Conditional heat port for the power loss (Modelica.Electrical.Analog.Interfaces.ConditionalHeatPort).

    The component defines ``LossPower`` (W, the power it dissipates).  With
    ``useHeatPort`` the conditional ``heatPort`` exists, ``heatPort.T =
    T_heatPort`` and ``heatPort.Q_flow = -LossPower`` (the loss leaves the
    component as heat); otherwise ``T_heatPort`` is the fixed device
    temperature ``T``.
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.ConditionalHeatPort"

    useHeatPort = Parameter(False, structural=True,  # noqa: N815 - Modelica name
                            description="= true, if heatPort is enabled")
    T = Parameter(293.15, unit="K", description="Fixed device temperature if useHeatPort = false")
    heatPort = HeatPort_a(condition="useHeatPort",  # noqa: N815 - Modelica name
                          description="Conditional heat port")
    LossPower = Variable(unit="W", description="Loss power leaving component via heatPort")  # noqa: N815
    T_heatPort = Variable(unit="K", start=293.15, description="Temperature of heatPort")  # noqa: N815

    def equations(self):
        if self.useHeatPort:
            return [Eq(self.heatPort.T, self.T_heatPort), Eq(self.heatPort.Q_flow, -self.LossPower)]
        return [Eq(self.T_heatPort, self.T)]


class TemperatureDependence(DerivedDefaults, ConditionalHeatPort):
    """A conditional heat port whose fixed temperature defaults to the reference temperature ``T_ref``.

    What Resistor, Conductor and their variable forms share: ``parameter
    T_ref``, ``alpha`` and ``extends ConditionalHeatPort(T=T_ref)``, and the
    MSL's check that ``1 + alpha*(T_heatPort - T_ref)`` stays positive.
    """

    modelica_name = None

    derived_defaults = {"T": lambda component: component.T_ref}

    T_ref = Parameter(300.15, unit="K", description="Reference temperature")
    alpha = Parameter(0.0, unit="1/K",
                      description="Temperature coefficient (R_actual = R*(1 + alpha*(T_heatPort - T_ref)))")
    T = Parameter(None, unit="K", description="Fixed device temperature if useHeatPort = false (default T_ref)")

    def temperature_factor(self) -> sp.Expr:
        """``1 + alpha*(T_heatPort - T_ref)``."""
        return 1 + self.alpha * (self.T_heatPort - self.T_ref)

    def equations(self):
        return [Assert(self.temperature_factor() >= EPS, "Temperature outside scope of model!")]


# --------------------------------------------------------------------------
# ideal switching elements (Analog.Interfaces.IdealSemiconductor, IdealSwitch, IdealSwitchWithArc)

from acausal.hybrid import When, edge  # noqa: E402 - the switching partials' own imports
from acausal.language import Boolean, If, time  # noqa: E402
from acausal.components.logic import pre_boolean  # noqa: E402

__all__ += ["IdealSemiconductor", "IdealSwitch", "IdealSwitchWithArc"]

#: Modelica.Constants.inf, the start of IdealSwitchWithArc.tSwitch ("switched off long ago").
INF = 1e60


class _UnitConstants(Component):
    """The MSL's ``constant unitVoltage = 1 V`` and ``unitCurrent = 1 A`` of the parametric characteristics.

    The path parameter ``s`` is dimensionless; multiplied by these, each
    branch has the unit of its side.  The language has no ``final``: a value
    other than 1 would rescale the characteristic.
    """

    modelica_name = None

    unitVoltage = Parameter(1.0, unit="V", description="Unit constant 1 V (do not change)")  # noqa: N815
    unitCurrent = Parameter(1.0, unit="A", description="Unit constant 1 A (do not change)")  # noqa: N815


class IdealSemiconductor(OnePort, ConditionalHeatPort, _UnitConstants):
    """Ideal semiconductor (Modelica.Electrical.Analog.Interfaces.IdealSemiconductor).

    The characteristic is two straight lines joined at the knee ``(v, i) =
    (Vknee, Goff*Vknee)``, followed along the path parameter ``s`` (``s = 0``
    at the knee, ``s < 0`` blocking, ``s > 0`` conducting)::

        v = s*unitCurrent*(if off then 1 else Ron) + Vknee
        i = s*unitVoltage*(if off then Goff else 1) + Goff*Vknee

    so that neither ``Ron = 0`` nor ``Goff = 0`` makes a branch singular.
    The subclass decides the Boolean ``off`` (by an event-generating relation
    on ``s``); ``LossPower = v*i``.  The electrical behaviour does not depend
    on the temperature of the conditional heat port.
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.IdealSemiconductor"

    Ron = Parameter(1e-5, unit="Ohm", min=0, description="Forward state-on differential resistance (closed resistance)")
    Goff = Parameter(1e-5, unit="S", min=0, description="Backward state-off conductance (opened conductance)")
    Vknee = Parameter(0.0, unit="V", min=0, description="Forward threshold voltage")
    off = Boolean(start=True, description="Switching state")
    s = Variable(start=0.0, unit="1",
                 description="Auxiliary variable for actual position on the ideal diode characteristic (protected)")

    def equations(self):
        return [Eq(self.v, self.s * self.unitCurrent * If(self.off, 1, self.Ron) + self.Vknee),
                Eq(self.i, self.s * self.unitVoltage * If(self.off, self.Goff, 1) + self.Goff * self.Vknee),
                Eq(self.LossPower, self.v * self.i)]


class IdealSwitch(OnePort, ConditionalHeatPort, _UnitConstants):
    """Ideal electrical switch (Modelica.Electrical.Analog.Interfaces.IdealSwitch).

    ``v = s*unitCurrent*(if off then 1 else Ron)``, ``i = s*unitVoltage*(if
    off then Goff else 1)``: open, a conductance ``Goff``; closed, a
    resistance ``Ron`` (either may be exactly 0).  The subclass decides
    ``off``; ``LossPower = v*i``; the heat port's fixed temperature is
    293.15 K (``final`` in the MSL).
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.IdealSwitch"

    Ron = Parameter(1e-5, unit="Ohm", min=0, description="Closed switch resistance")
    Goff = Parameter(1e-5, unit="S", min=0, description="Opened switch conductance")
    off = Boolean(description="Indicates off-state (protected)")
    s = Variable(unit="1", description="Auxiliary variable (protected)")

    def equations(self):
        return [Eq(self.v, self.s * self.unitCurrent * If(self.off, 1, self.Ron)),
                Eq(self.i, self.s * self.unitVoltage * If(self.off, self.Goff, 1)),
                Eq(self.LossPower, self.v * self.i)]


class IdealSwitchWithArc(OnePort, ConditionalHeatPort, _UnitConstants):
    """Ideal switch with simple arc model (Modelica.Electrical.Analog.Interfaces.IdealSwitchWithArc).

    Closed (``not off``): ``v = Ron*i``.  When ``off`` becomes true the
    switch does not interrupt the current at once: an arc burns with the
    voltage ``min(Vmax, V0 + dVdt*(time - tSwitch))*sign(i)`` (``tSwitch``
    the instant ``off`` rose), opposing the current, until the current has
    fallen to the open conductance's ``|i| <= |v|*Goff`` (``quenched``, an
    event); from then on ``i = Goff*v``.  Closing is immediate.
    ``LossPower = v*i``; the heat port's fixed temperature is 293.15 K.
    """

    modelica_name = "Modelica.Electrical.Analog.Interfaces.IdealSwitchWithArc"

    Ron = Parameter(1e-5, unit="Ohm", description="Closed switch resistance")
    Goff = Parameter(1e-5, unit="S", description="Opened switch conductance")
    V0 = Parameter(30.0, unit="V", description="Initial arc voltage")
    dVdt = Parameter(10e3, unit="V/s", description="Arc voltage slope")
    Vmax = Parameter(60.0, unit="V", description="Max. arc voltage")
    off = Boolean(start=True, description="Indicates off-state (but maybe not quenched)")
    quenched = Boolean(start=True, fixed=True, description="Indicating quenched arc (if switch is off) (protected)")
    tSwitch = Variable(discrete=True, start=-INF, fixed=True, unit="s",  # noqa: N815 - Modelica name
                       description="Last switch off time instant (protected)")

    def equations(self):
        arc = sp.Min(self.Vmax, self.V0 + self.dVdt * (time - self.tSwitch)) * sp.sign(self.i)
        return [When(edge(self.off), Eq(self.tSwitch, time)),
                Eq(self.quenched, sp.And(self.off, sp.Or(sp.Abs(self.i) <= sp.Abs(self.v) * self.Goff,
                                                         pre_boolean(self.quenched)))),
                # the MSL's nested if-equation as one residual, each branch in volts (the
                # quenched one's current residual times 1 V/A: the branches of an if share a unit)
                Eq(0, If(self.off, If(self.quenched, (self.i - self.Goff * self.v) * self.unitVoltage / self.unitCurrent,
                                      self.v - arc),
                         self.v - self.Ron * self.i)),
                Eq(self.LossPower, self.v * self.i)]
