"""Functions with given derivatives inside algebraic loops and chains (issue 22, item 1).

``prescribed(p, u1, u2)`` (Modelica's ``derivative`` annotation with
``noDerivative``) *evaluates* to ``p``: its derivative inputs are not unknowns
of its order-0 value.  The engine used to match the equation
``u = prescribed(p, u1, u2)`` to ``u2`` (a singular Newton step at t = 0) and,
in a chain of adaptors with a spring-damper, to miss a third derivative.  Both
are the MSL's DirectMass/InverseMass and SpringDamper FMU patterns
(Modelica.Mechanics.Translational.Examples.GenerationOfFMUs).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from acausal import Eq, Experiment, Model, Variable, der, prescribed, simulate, time
from acausal.functions import settle
from acausal.library.blocks import Sine
from acausal.library.rotational import (
    AngleToTorqueAdaptor, Inertia, Spring, SpringDamper, Torque, TorqueToAngleAdaptor)
from acausal.library.translational import (
    Force, GeneralForceToPositionAdaptor, GeneralPositionToForceAdaptor, Mass)


def test_settle_replaces_an_application_by_the_signal_of_its_order():
    p, v, a = sp.symbols("p v a", real=True)
    x = prescribed(p, v, a, name="drive.p")
    assert settle(x) == p
    assert settle(x.diff(time)) == v
    assert settle(3 * x.diff(time, 2) + p) == 3 * a + p
    assert settle(p + v) == p + v            # nothing to settle: the same expression


class DirectInverseMass(Model):
    """A mass driven by a force, its motion handed through the General adaptors to a
    second mass, whose reaction force is handed back: one rigid body of m_a + m_b."""

    experiment = Experiment(stop_time=1.0, interval=0.001)

    def build(self):
        self.sine = Sine(f=2, amplitude=10)
        self.force = Force()
        self.massA = Mass(m=1.0, s=dict(start=0, fixed=True), v=dict(start=0, fixed=True))
        self.forceToPosition = GeneralForceToPositionAdaptor()
        self.positionToForce = GeneralPositionToForceAdaptor()
        self.massB = Mass(m=2.2)
        self.connect(self.sine.y, self.force.f)
        self.connect(self.force.flange, self.massA.flange_a)
        self.connect(self.massA.flange_b, self.forceToPosition.flange)
        self.connect(self.forceToPosition.p, self.positionToForce.p)
        self.connect(self.forceToPosition.pder, self.positionToForce.pder)
        self.connect(self.forceToPosition.pder2, self.positionToForce.pder2)
        self.connect(self.positionToForce.flange, self.massB.flange_a)
        self.connect(self.positionToForce.f, self.forceToPosition.f)


def test_direct_and_inverse_mass_move_as_one_body():
    result = simulate(DirectInverseMass(), rtol=1e-8, atol=1e-10)
    assert result.success, result.message
    t = result.time
    omega, mass = 4 * math.pi, 3.2       # (m_a + m_b) a = 10 sin(omega t), at rest at t = 0
    v = 10 / (mass * omega) * (1 - np.cos(omega * t))
    s = 10 / (mass * omega) * (t - np.sin(omega * t) / omega)
    assert np.max(np.abs(result["massA.v"] - v)) < 1e-6
    assert np.max(np.abs(result["massB.s"] - s)) < 1e-6
    # the force the second mass needs is handed back: f = -flange.f = m_b * a
    a = 10 / mass * np.sin(omega * t)
    assert np.max(np.abs(result["positionToForce.f"] - 2.2 * a)) < 1e-5


def test_the_order_zero_value_is_not_matched_to_a_derivative_input():
    """The states are the driven mass's: the second mass follows the adaptor's input
    (no start value of massB is needed, none is guessed)."""
    from acausal import translate

    translation = translate(DirectInverseMass())
    # the sine source's one relation (before its start time or not) selects the system
    for key in [(False,), (True,)]:
        assert set(translation.system(key).states) == {"massA.s", "massA.v"}


def _adaptor_chain(damped: bool) -> Model:
    class Chain(Model):
        """Two inertias joined by a spring(-damper) wrapped in angle-to-torque adaptors, the
        inertias wrapped in torque-to-angle adaptors (use_a = false): the MSL's FMU pattern."""

        experiment = Experiment(stop_time=1.0, interval=0.001)

        def build(self):
            self.sine = Sine(f=2, amplitude=10)
            self.torque = Torque()
            self.inertiaA = Inertia(J=1.1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
            self.toAngleA = TorqueToAngleAdaptor(use_a=False)
            self.toTorqueA = AngleToTorqueAdaptor(use_a=False)
            self.element = SpringDamper(c=1e4, d=100) if damped else Spring(c=1e4)
            self.toTorqueB = AngleToTorqueAdaptor(use_a=False)
            self.toAngleB = TorqueToAngleAdaptor(use_a=False)
            self.inertiaB = Inertia(J=2.2, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
            self.connect(self.sine.y, self.torque.tau)
            self.connect(self.torque.flange, self.inertiaA.flange_a)
            self.connect(self.inertiaA.flange_b, self.toAngleA.flange)
            self.connect(self.toAngleA.phi, self.toTorqueA.phi)
            self.connect(self.toAngleA.w, self.toTorqueA.w)
            self.connect(self.toTorqueA.tau, self.toAngleA.tau)
            self.connect(self.toTorqueA.flange, self.element.flange_a)
            self.connect(self.element.flange_b, self.toTorqueB.flange)
            self.connect(self.toAngleB.phi, self.toTorqueB.phi)
            self.connect(self.toAngleB.w, self.toTorqueB.w)
            self.connect(self.toTorqueB.tau, self.toAngleB.tau)
            self.connect(self.toAngleB.flange, self.inertiaB.flange_a)

    return Chain()


def _direct(damped: bool) -> Model:
    class Direct(Model):
        """The same two inertias joined directly."""

        experiment = Experiment(stop_time=1.0, interval=0.001)

        def build(self):
            self.sine = Sine(f=2, amplitude=10)
            self.torque = Torque()
            self.inertiaA = Inertia(J=1.1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
            self.element = SpringDamper(c=1e4, d=100) if damped else Spring(c=1e4)
            self.inertiaB = Inertia(J=2.2, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
            self.connect(self.sine.y, self.torque.tau)
            self.connect(self.torque.flange, self.inertiaA.flange_a)
            self.connect(self.inertiaA.flange_b, self.element.flange_a)
            self.connect(self.element.flange_b, self.inertiaB.flange_a)

    return Direct()


@pytest.mark.parametrize("damped", [False, True], ids=["spring", "spring-damper"])
def test_adaptor_chain_moves_as_the_directly_connected_drive(damped):
    """Cross-check: wrapping the elements in adaptors changes nothing physical."""
    chain = simulate(_adaptor_chain(damped), rtol=1e-9, atol=1e-11)
    assert chain.success, chain.message
    direct = simulate(_direct(damped), rtol=1e-9, atol=1e-11)
    for name in ("inertiaA.w", "inertiaB.w", "inertiaB.phi"):
        reference = np.interp(chain.time, direct.time, direct[name])
        scale = np.max(np.abs(reference))
        assert np.max(np.abs(chain[name] - reference)) < 1e-5 * scale, name
    # total momentum: J_a w_a + J_b w_b = integral of the drive torque
    omega = 4 * math.pi
    momentum = 10 / omega * (1 - np.cos(omega * chain.time))
    assert np.max(np.abs(1.1 * chain["inertiaA.w"] + 2.2 * chain["inertiaB.w"] - momentum)) < 1e-5


class InLoop(Model):
    """The order-0 value in an algebraic loop with its own derivative inputs."""

    experiment = Experiment(stop_time=1.0)
    p = Variable()
    u1 = Variable()
    u2 = Variable()
    y = Variable()

    def equations(self):
        return [Eq(self.p, time**2),
                Eq(self.u1, 2 * time + 0 * self.y),
                Eq(self.u2, 2.0),
                Eq(self.y + 0.5 * self.u2, prescribed(self.p, self.u1, self.u2, name="loop.p") + 1)]


def test_an_application_in_a_loop_is_solved_for_its_value():
    result = simulate(InLoop())
    assert result.success, result.message
    assert result.final("y") == pytest.approx(1.0 + 1.0 - 1.0)


class DirectInverseCapacity(Model):
    """The thermal form (Modelica.Thermal.HeatTransfer.Examples.GenerationOfFMUs, first part):
    a heat flow into a capacitor, its temperature handed through the General adaptors to a
    second capacitor, whose heat flow is handed back: one capacity of C_a + C_b."""

    experiment = Experiment(stop_time=1.0, interval=0.001)

    def build(self):
        from acausal.library.thermal import (
            GeneralHeatFlowToTemperatureAdaptor, GeneralTemperatureToHeatFlowAdaptor, HeatCapacitor,
            PrescribedHeatFlow)

        self.sine = Sine(f=2, amplitude=1000)
        self.heatFlow = PrescribedHeatFlow()
        self.capacitorA = HeatCapacitor(C=1.1, T=dict(start=293.15, fixed=True))
        self.heatFlowToTemperature = GeneralHeatFlowToTemperatureAdaptor()
        self.temperatureToHeatFlow = GeneralTemperatureToHeatFlowAdaptor()
        self.capacitorB = HeatCapacitor(C=2.2)
        self.connect(self.sine.y, self.heatFlow.Q_flow)
        self.connect(self.heatFlow.port, self.capacitorA.port)
        self.connect(self.capacitorA.port, self.heatFlowToTemperature.heatPort)
        self.connect(self.heatFlowToTemperature.p, self.temperatureToHeatFlow.p)
        self.connect(self.heatFlowToTemperature.pder, self.temperatureToHeatFlow.pder)
        self.connect(self.temperatureToHeatFlow.f, self.heatFlowToTemperature.f)
        self.connect(self.temperatureToHeatFlow.heatPort, self.capacitorB.port)


def test_direct_and_inverse_capacity_heat_as_one_capacity():
    result = simulate(DirectInverseCapacity(), rtol=1e-9, atol=1e-9)
    assert result.success, result.message
    omega, capacity = 4 * math.pi, 3.3
    T = 293.15 + 1000 / (capacity * omega) * (1 - np.cos(omega * result.time))
    assert np.max(np.abs(result["capacitorA.T"] - T)) < 1e-5
    assert np.max(np.abs(result["capacitorB.T"] - T)) < 1e-5
    # the heat the second capacitor takes is handed back: C_b * dT/dt
    heat = 2.2 * 1000 / capacity * np.sin(omega * result.time)
    assert np.max(np.abs(result["temperatureToHeatFlow.f"] - heat)) < 1e-6


def test_the_thermal_adaptors_fix_the_second_derivative():
    from acausal.errors import ParameterError
    from acausal.library.thermal import GeneralTemperatureToHeatFlowAdaptor

    class Bad(Model):
        def build(self):
            self.adaptor = GeneralTemperatureToHeatFlowAdaptor(use_pder2=True)

    with pytest.raises(ParameterError, match="use_pder2"):
        simulate(Bad())
