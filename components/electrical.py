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
