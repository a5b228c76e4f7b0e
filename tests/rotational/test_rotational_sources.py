"""Modelica.Mechanics.Rotational.Sources and Sensors, and the SimpleGearShift and EddyCurrentBrake examples.

Every source and sensor passes the declaration checks (with defaults and
with modifiers).  Their behaviour is checked against closed forms: exact
tracking of Position and Speed, the filters' step responses, integration by
Accelerate, Move's use of the given derivatives, the terminal speeds an
inertia reaches against the speed-dependent torques, SignTorque's
regularized laws, the eddy current brake's peak at its nominal point and its
temperature shift, the energy balance of the EddyCurrentBrake example and the
gear ratios of SimpleGearShift.  Both examples are compared with the MSL
reference results where those are available (bundled or
``$ACAUSAL_REFERENCE_DIR``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import acausal.compiler.translate as translate_module
from acausal import Eq, Experiment, Model, der, simulate, translate
from acausal.errors import ParameterError, StructuralError
from acausal.language import Connector, Parameter, Variable
from acausal.library.blocks import Constant, Cosine, Ramp, Sine, Step
from acausal.library.rotational import Fixed, Inertia
from acausal.library.rotational.sensors import (
    AccSensor,
    AngleSensor,
    MultiSensor,
    PowerSensor,
    RelAccSensor,
    RelAngleSensor,
    RelSpeedSensor,
    SpeedSensor,
    TorqueSensor,
)
from acausal.library.rotational.sources import (
    Accelerate,
    ConstantSpeed,
    ConstantTorque,
    EddyCurrentTorque,
    InverseSpeedDependentTorque,
    LinearSpeedDependentTorque,
    Move,
    Position,
    QuadraticSpeedDependentTorque,
    Regularization,
    SignTorque,
    Speed,
    Torque,
    Torque2,
    TorqueStep,
)
from acausal.library.thermal import FixedTemperature
from acausal.tools.compare import compare_signals, load_reference, reference_dir
from examples.rotational_eddy_current_brake import ALPHA20_COPPER, EddyCurrentBrake
from examples.rotational_simple_gear_shift import SimpleGearShift

from library_checks import attach, check_declarations

# --------------------------------------------------------------------------
# declarations, with defaults and with modifiers

SPEED_LAW = dict(tau_nominal=-2.0, w_nominal=3.0)

COMPONENTS = [
    lambda: Position(),
    lambda: Position(exact=True),
    lambda: Position(useSupport=True, f_crit=10),
    lambda: Position(exact=True, useSupport=True),
    lambda: Speed(),
    lambda: Speed(exact=True),
    lambda: Speed(useSupport=True, f_crit=5),
    lambda: Accelerate(),
    lambda: Accelerate(useSupport=True),
    lambda: Move(),
    lambda: Move(useSupport=True),
    lambda: Torque(),
    lambda: Torque(useSupport=True),
    lambda: Torque2(),
    lambda: ConstantTorque(tau_constant=1.0),
    lambda: ConstantTorque(tau_constant=1.0, useSupport=True),
    lambda: ConstantSpeed(w_fixed=2.0),
    lambda: ConstantSpeed(w_fixed=2.0, useSupport=True),
    lambda: TorqueStep(),
    lambda: TorqueStep(stepTorque=3, offsetTorque=1, startTime=0.5, useSupport=True),
    lambda: LinearSpeedDependentTorque(**SPEED_LAW),
    lambda: LinearSpeedDependentTorque(TorqueDirection=False, useSupport=True, **SPEED_LAW),
    lambda: QuadraticSpeedDependentTorque(**SPEED_LAW),
    lambda: QuadraticSpeedDependentTorque(TorqueDirection=False, useSupport=True, **SPEED_LAW),
    lambda: InverseSpeedDependentTorque(**SPEED_LAW),
    lambda: InverseSpeedDependentTorque(TorqueDirection=False, w0=0.5, useSupport=True, **SPEED_LAW),
    *[(lambda reg=reg: SignTorque(tau_nominal=1.0, reg=reg)) for reg in Regularization],
    lambda: SignTorque(tau_nominal=1.0, reg=Regularization.Linear, w0=0.2, useSupport=True),
    lambda: EddyCurrentTorque(tau_nominal=10, w_nominal=5),
    lambda: EddyCurrentTorque(tau_nominal=10, w_nominal=5, useHeatPort=True),
    lambda: EddyCurrentTorque(tau_nominal=10, w_nominal=5, useExcitationInput=True),
    lambda: EddyCurrentTorque(tau_nominal=10, w_nominal=5, useExcitationInput=True, useHeatPort=True,
                              useSupport=True, alpha20=0.004, TRef=300, constantExcitation=0.5),
    lambda: AngleSensor(),
    lambda: SpeedSensor(),
    lambda: AccSensor(),
    lambda: TorqueSensor(),
    lambda: RelAngleSensor(),
    lambda: RelSpeedSensor(),
    lambda: RelAccSensor(),
    lambda: PowerSensor(),
    lambda: MultiSensor(),
]


def _label(make) -> str:
    """A test id: the class and its modifiers."""
    component = make()
    modifiers = ", ".join(f"{k}={getattr(v, 'name', v)}" for k, v in component._modifiers.items())
    return f"{type(component).__name__}({modifiers})"


@pytest.mark.parametrize("make", COMPONENTS, ids=_label)
def test_declarations(make):
    component = make()
    check_declarations(component)
    # every declaration says what it is; physical quantities carry their unit
    for name, declaration in component.declarations().items():
        assert declaration.description or isinstance(declaration, Connector) or name.startswith("flange"), name
        if isinstance(declaration, (Parameter, Variable)) and name in ("phi", "w", "a", "tau", "w_nominal", "w0"):
            assert declaration.unit, f"{type(component).__name__}.{name} has no unit"


def test_move_inputs_are_named_as_in_modelica():
    move = attach(Move(), "move")
    assert [s.name for s in move.vector("u")] == ["move.u[1]", "move.u[2]", "move.u[3]"]


def test_structural_choices_select_connectors():
    eddy = attach(EddyCurrentTorque(tau_nominal=1, w_nominal=1, useExcitationInput=True, useHeatPort=True))
    assert eddy.excitation.name == "x.excitation" and eddy.heatPort.enabled
    plain = attach(EddyCurrentTorque(tau_nominal=1, w_nominal=1))
    assert not plain.heatPort.enabled
    assert "excitation" not in {k for k, d in plain.declarations().items() if d.enabled(plain)}


# --------------------------------------------------------------------------
# bad parameters


@pytest.mark.parametrize("make, names", [
    (lambda: Position(f_crit=0), "pos.f_crit"),
    (lambda: Speed(f_crit=-1), "pos.f_crit"),
])
def test_filter_frequency_must_be_positive(make, names):
    class Bad(Model):
        def build(self):
            self.pos = make()

    with pytest.raises(ParameterError, match=names.replace(".", r"\.")):
        simulate(Bad())


def test_unknown_regularization_is_named():
    class Bad(Model):
        def build(self):
            self.sign = SignTorque(tau_nominal=1, reg=7)

    with pytest.raises(ParameterError, match=r"sign\.reg"):
        simulate(Bad())


@pytest.mark.parametrize("modifiers, name", [
    (dict(tau_nominal=1.0, w_nominal=0.0), "load.w_nominal"),
    (dict(w_nominal=1.0), "load.tau_nominal"),
])
def test_speed_law_parameters_are_checked(modifiers, name):
    class Bad(Model):
        def build(self):
            self.inertia = Inertia(J=1, phi=dict(fixed=True), w=dict(fixed=True))
            self.load = QuadraticSpeedDependentTorque(**modifiers)
            self.connect(self.load.flange, self.inertia.flange_a)

    with pytest.raises(ParameterError, match=name.replace(".", r"\.")):
        simulate(Bad())


# --------------------------------------------------------------------------
# motion sources

def _sine_motion(model, amplitude, f):
    """Sine, Cosine and Sine blocks giving angle, speed and acceleration of amplitude*sin(2*pi*f*t)."""
    omega = 2 * math.pi * f
    model.angle = Sine(amplitude=amplitude, f=f)
    model.speed = Cosine(amplitude=amplitude * omega, f=f)
    model.acceleration = Sine(amplitude=-amplitude * omega ** 2, f=f)


def test_position_exact_tracks_the_reference():
    amplitude, f, J = 2.0, 1.0, 2.0

    class Exact(Model):
        experiment = Experiment(stop_time=1.0)

        def build(self):
            self.sine = Sine(amplitude=amplitude, f=f)
            self.position = Position(exact=True, useSupport=True)
            self.fixed = Fixed()
            self.inertia = Inertia(J=J)
            self.connect(self.sine.y, self.position.phi_ref)
            self.connect(self.position.flange, self.inertia.flange_a)
            self.connect(self.position.support, self.fixed.flange)

    result = simulate(Exact())
    assert result.success, result.message
    t, omega = result.time, 2 * math.pi * f
    np.testing.assert_allclose(result["inertia.phi"], amplitude * np.sin(omega * t), atol=1e-12)
    np.testing.assert_allclose(result["inertia.w"], amplitude * omega * np.cos(omega * t), atol=1e-12)
    # the torque the source applies is J*phi_ref'' (index reduction differentiated the input twice);
    # the housing takes the reaction: support.tau = -flange.tau, balanced by the fixed flange
    driving = -result["position.flange.tau"]
    np.testing.assert_allclose(driving, -J * amplitude * omega ** 2 * np.sin(omega * t), atol=1e-10)
    np.testing.assert_allclose(result["position.support.tau"], driving, atol=1e-10)
    np.testing.assert_allclose(result["fixed.flange.tau"], -driving, atol=1e-10)


def test_position_filter_step_response():
    height, t_step, f_crit = 2.0, 0.01, 50.0

    class Filtered(Model):
        experiment = Experiment(stop_time=0.05, interval=1e-4)

        def build(self):
            self.step = Step(height=height, startTime=t_step)
            # w fixed at its start value 0: what Modelica tools do with the unfixed filter state
            self.position = Position(f_crit=f_crit, w=dict(fixed=True))
            self.inertia = Inertia(J=1)
            self.connect(self.step.y, self.position.phi_ref)
            self.connect(self.position.flange, self.inertia.flange_a)

    result = simulate(Filtered(), rtol=1e-8)
    assert result.success, result.message
    # phi/phi_ref = 1/(1 + af/w_crit*s + bf/w_crit^2*s^2): underdamped second order
    af, bf = Position.af, Position.bf
    w_crit = 2 * math.pi * f_crit
    w_n = w_crit / math.sqrt(bf)
    zeta = af / (2 * math.sqrt(bf))
    w_d = w_n * math.sqrt(1 - zeta ** 2)
    tau = np.clip(result.time - t_step, 0, None)
    expected = height * (1 - np.exp(-zeta * w_n * tau) * (np.cos(w_d * tau)
                                                          + zeta / math.sqrt(1 - zeta ** 2) * np.sin(w_d * tau)))
    np.testing.assert_allclose(result["position.phi"], expected, atol=1e-6 * height)
    np.testing.assert_allclose(result["inertia.phi"], result["position.phi"], atol=1e-12)


def test_speed_filter_step_response():
    height, t_step, f_crit = 3.0, 0.01, 50.0

    class Filtered(Model):
        experiment = Experiment(stop_time=0.05, interval=1e-4)

        def build(self):
            self.step = Step(height=height, startTime=t_step)
            self.speed = Speed(f_crit=f_crit)
            self.inertia = Inertia(J=2)
            self.connect(self.step.y, self.speed.w_ref)
            self.connect(self.speed.flange, self.inertia.flange_a)

    result = simulate(Filtered(), rtol=1e-8)
    assert result.success, result.message
    w_crit = 2 * math.pi * f_crit
    tau = np.clip(result.time - t_step, 0, None)
    np.testing.assert_allclose(result["inertia.w"], height * (1 - np.exp(-w_crit * tau)), atol=1e-6 * height)
    # phi starts at 0 (fixed) and integrates w
    angle = np.where(tau > 0, height * (tau - (1 - np.exp(-w_crit * tau)) / w_crit), 0)
    np.testing.assert_allclose(result["inertia.phi"], angle, atol=1e-7)


def test_speed_exact_tracks_the_reference():
    amplitude, J = 3.0, 2.0

    class Exact(Model):
        experiment = Experiment(stop_time=1.0)

        def build(self):
            self.sine = Sine(amplitude=amplitude)
            self.speed = Speed(exact=True)
            self.inertia = Inertia(J=J)
            self.connect(self.sine.y, self.speed.w_ref)
            self.connect(self.speed.flange, self.inertia.flange_a)

    result = simulate(Exact(), rtol=1e-9)
    assert result.success, result.message
    t, omega = result.time, 2 * math.pi
    np.testing.assert_allclose(result["inertia.w"], amplitude * np.sin(omega * t), atol=1e-12)
    np.testing.assert_allclose(result["inertia.phi"], amplitude * (1 - np.cos(omega * t)) / omega, atol=1e-8)
    np.testing.assert_allclose(-result["speed.flange.tau"], J * amplitude * omega * np.cos(omega * t), atol=1e-10)


def test_accelerate_integrates_a_constant_acceleration():
    acceleration = 3.0

    class Accelerated(Model):
        experiment = Experiment(stop_time=1.0)

        def build(self):
            self.constant = Constant(k=acceleration)
            self.accelerate = Accelerate()
            self.inertia = Inertia(J=2)
            self.connect(self.constant.y, self.accelerate.a_ref)
            self.connect(self.accelerate.flange, self.inertia.flange_a)

    result = simulate(Accelerated())
    assert result.success, result.message
    t = result.time
    np.testing.assert_allclose(result["inertia.phi"], acceleration * t ** 2 / 2, atol=1e-10)
    np.testing.assert_allclose(result["inertia.w"], acceleration * t, atol=1e-10)
    np.testing.assert_allclose(-result["accelerate.flange.tau"], 2 * acceleration, atol=1e-10)


def test_move_follows_angle_speed_and_acceleration():
    amplitude, f, J = 2.0, 1.0, 2.0

    class Moved(Model):
        experiment = Experiment(stop_time=1.0)

        def build(self):
            _sine_motion(self, amplitude, f)
            self.move = Move()
            self.inertia = Inertia(J=J)
            for k, source in enumerate((self.angle, self.speed, self.acceleration), start=1):
                self.connect(source.y, self.move.u[k])
            self.connect(self.move.flange, self.inertia.flange_a)

    result = simulate(Moved())
    assert result.success, result.message
    t, omega = result.time, 2 * math.pi * f
    np.testing.assert_allclose(result["inertia.phi"], amplitude * np.sin(omega * t), atol=1e-12)
    np.testing.assert_allclose(result["inertia.w"], amplitude * omega * np.cos(omega * t), atol=1e-12)
    np.testing.assert_allclose(-result["move.flange.tau"], -J * amplitude * omega ** 2 * np.sin(omega * t),
                               atol=1e-10)


def test_move_takes_the_derivatives_from_its_inputs():
    # an angle with zero speed and acceleration: only position-dependent terms (MSL's use case);
    # the inertia's speed and torque are then 0, not derivatives of the angle
    class PositionOnly(Model):
        experiment = Experiment(stop_time=1.0)

        def build(self):
            self.angle = Sine(amplitude=1.0)
            self.zero = Constant(k=0.0)
            self.move = Move(useSupport=True)
            self.fixed = Fixed()
            self.inertia = Inertia(J=1)
            self.connect(self.angle.y, getattr(self.move, "u[1]"))
            self.connect(self.zero.y, getattr(self.move, "u[2]"))
            self.connect(self.zero.y, getattr(self.move, "u[3]"))
            self.connect(self.move.flange, self.inertia.flange_a)
            self.connect(self.move.support, self.fixed.flange)

    result = simulate(PositionOnly())
    assert result.success, result.message
    np.testing.assert_allclose(result["inertia.phi"], np.sin(2 * math.pi * result.time), atol=1e-12)
    assert np.all(result["inertia.w"] == 0) and np.all(result["move.flange.tau"] == 0)


def test_move_refuses_a_third_derivative():
    """u[3] is the last derivative Move gives: an equation with der() of the acceleration is refused."""
    class Jerky(Model):
        jerk = Variable()

        def build(self):
            _sine_motion(self, 1.0, 1.0)
            self.move = Move()
            self.inertia = Inertia(J=1)
            for k, source in enumerate((self.angle, self.speed, self.acceleration), start=1):
                self.connect(source.y, self.move.u[k])
            self.connect(self.move.flange, self.inertia.flange_a)

        def equations(self):
            return [Eq(self.jerk, der(self.inertia.a))]

    with pytest.raises(StructuralError, match="order 3") as caught:
        simulate(Jerky(), stop_time=0.1)
    assert "move.phi" in caught.value.message and "u[3]" in caught.value.hint


def test_move_compiles_from_the_disk_cache(tmp_path, monkeypatch):
    """The derivatives index reduction makes of u[1] are the same function: compiled code that
    calls them is stored and loaded again (a fresh translation), with the same result."""
    monkeypatch.setenv("ACAUSAL_DISK_CACHE", "on")
    monkeypatch.setenv("ACAUSAL_CACHE_DIR", str(tmp_path / "cache"))

    class Moved(Model):
        def build(self):
            _sine_motion(self, 1.0, 1.0)
            self.move = Move()
            self.inertia = Inertia(J=2)
            for k, source in enumerate((self.angle, self.speed, self.acceleration), start=1):
                self.connect(source.y, self.move.u[k])
            self.connect(self.move.flange, self.inertia.flange_a)

    results = []
    for _ in range(2):
        translate_module._CACHE.clear()
        translate_module._STRUCTURES.clear()
        translation = translate(Moved())
        results.append(simulate(translation, stop_time=0.5))
    passes = [s.passes[0][0] for s in translation.systems.values()]
    assert passes and set(passes) == {"load"}, passes
    np.testing.assert_array_equal(results[0]["move.flange.tau"], results[1]["move.flange.tau"])


def test_constant_speed():
    class Driven(Model):
        experiment = Experiment(stop_time=1.0)

        def build(self):
            self.source = ConstantSpeed(w_fixed=5.0)
            self.inertia = Inertia(J=2, phi=dict(start=1.0, fixed=True))
            self.connect(self.source.flange, self.inertia.flange_a)

    result = simulate(Driven())
    assert result.success, result.message
    np.testing.assert_allclose(result["inertia.phi"], 1.0 + 5.0 * result.time, atol=1e-10)
    np.testing.assert_allclose(result["source.flange.tau"], 0, atol=1e-12)


def test_torque2_acts_between_its_flanges():
    class Pair(Model):
        experiment = Experiment(stop_time=1.0)

        def build(self):
            self.constant = Constant(k=2.0)
            self.torque = Torque2()
            self.a = Inertia(J=1, phi=dict(fixed=True), w=dict(fixed=True))
            self.b = Inertia(J=4, phi=dict(fixed=True), w=dict(fixed=True))
            self.connect(self.constant.y, self.torque.tau)
            self.connect(self.torque.flange_a, self.a.flange_b)
            self.connect(self.torque.flange_b, self.b.flange_a)

    result = simulate(Pair())
    t = result.time
    np.testing.assert_allclose(result["b.w"], 2.0 / 4 * t, atol=1e-10)
    np.testing.assert_allclose(result["a.w"], -2.0 * t, atol=1e-10)
    # no housing: the angular momentum stays 0
    np.testing.assert_allclose(result["a.w"] + 4 * result["b.w"], 0, atol=1e-10)


# --------------------------------------------------------------------------
# speed-dependent torques on an inertia driven by a constant torque

def _driven_against(load, drive=4.0, J=2.0, stop_time=3.0):
    class Run(Model):
        experiment = Experiment(stop_time=stop_time, interval=stop_time / 1000)

        def build(self):
            self.drive = ConstantTorque(tau_constant=drive)
            self.inertia = Inertia(J=J, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
            self.load = load
            self.connect(self.drive.flange, self.inertia.flange_a)
            self.connect(self.load.flange, self.inertia.flange_b)

    result = simulate(Run(), rtol=1e-8)
    assert result.success, result.message
    return result


def test_linear_speed_dependent_torque_terminal_speed():
    drive, J, tau_n, w_n = 4.0, 2.0, 8.0, 3.0
    result = _driven_against(LinearSpeedDependentTorque(tau_nominal=-tau_n, w_nominal=w_n, TorqueDirection=False),
                             drive, J)
    # J w' = drive - tau_n*w/w_n: w = w_inf*(1 - exp(-t/T)), w_inf = drive*w_n/tau_n, T = J*w_n/tau_n
    w_inf, T = drive * w_n / tau_n, J * w_n / tau_n
    np.testing.assert_allclose(result["inertia.w"], w_inf * (1 - np.exp(-result.time / T)), atol=1e-6)
    np.testing.assert_allclose(result["load.tau"], -tau_n * result["load.w"] / w_n, atol=1e-10)


def test_linear_speed_dependent_torque_same_direction_drives_both_ways():
    # TorqueDirection: tau = tau_nominal*|w/w_nominal|, so a negative tau_nominal brakes for w > 0 only
    load = LinearSpeedDependentTorque(tau_nominal=-8.0, w_nominal=3.0)
    result = _driven_against(load, drive=-4.0, stop_time=1.0)
    w = result["inertia.w"]
    assert np.all(w <= 0)
    np.testing.assert_allclose(result["load.tau"], -8.0 * np.abs(w) / 3.0, atol=1e-10)


@pytest.mark.parametrize("direction", [True, False])
def test_quadratic_speed_dependent_torque_terminal_speed(direction):
    drive, J, tau_n, w_n = 4.0, 2.0, 9.0, 3.0
    sign = 1.0 if direction else -1.0  # without TorqueDirection the load brakes in both directions
    result = _driven_against(QuadraticSpeedDependentTorque(tau_nominal=-tau_n, w_nominal=w_n,
                                                           TorqueDirection=direction), sign * drive, J)
    # J w' = drive - tau_n*(w/w_n)^2: w = w_inf*tanh(k*w_inf*t), k = tau_n/(J*w_n^2)
    w_inf = w_n * math.sqrt(drive / tau_n)
    k = tau_n / (J * w_n ** 2)
    np.testing.assert_allclose(result["inertia.w"], sign * w_inf * np.tanh(k * w_inf * result.time), atol=1e-6)
    assert not [e for e in result.events if e.kind == "state"]


class _ConstantPower(Model):
    """A constant-power drive (tau_n*w_n/|w| above w0) against a linear load d*w, from speed w_start."""

    tau_n, w_n, w0, J, d = 2.0, 5.0, 0.5, 1.0, 0.4
    experiment = Experiment(stop_time=30.0, interval=0.03)

    def __init__(self, w_start, **modifiers):
        super().__init__(**modifiers)
        self.w_start = w_start

    def build(self):
        self.drive = InverseSpeedDependentTorque(tau_nominal=self.tau_n, w_nominal=self.w_n, w0=self.w0)
        self.inertia = Inertia(J=self.J, phi=dict(start=0, fixed=True), w=dict(start=self.w_start, fixed=True))
        self.load = LinearSpeedDependentTorque(tau_nominal=-self.d, w_nominal=1.0, TorqueDirection=False)
        self.connect(self.drive.flange, self.inertia.flange_a)
        self.connect(self.load.flange, self.inertia.flange_b)


def test_inverse_speed_dependent_torque_terminal_speed():
    # started below w0 (not at rest: see the next test); terminal speed w_inf = sqrt(tau_n*w_n/d)
    tau_n, w_n, w0, J, d = _ConstantPower.tau_n, _ConstantPower.w_n, _ConstantPower.w0, _ConstantPower.J, \
        _ConstantPower.d
    w_start = 0.1
    result = simulate(_ConstantPower(w_start), rtol=1e-8)
    assert result.success, result.message
    t, w = result.time, result["inertia.w"]
    # below w0 the torque is constant, t0 = tau_n*w_n/w0: J*w' = t0 - d*w, closed form up to w0
    t0 = tau_n * w_n / w0
    crossing = [e.time for e in result.events if e.kind == "state"]
    t_cross = -J / d * math.log((t0 - d * w0) / (t0 - d * w_start))
    assert crossing == pytest.approx([t_cross], rel=1e-6)
    early = t < t_cross
    np.testing.assert_allclose(w[early], t0 / d + (w_start - t0 / d) * np.exp(-d * t[early] / J), atol=1e-8)
    # above w0: J*w*w' = P - d*w^2 gives w^2 = w_inf^2 + (w0^2 - w_inf^2)*exp(-2*d*(t - t_cross)/J)
    w_inf2 = tau_n * w_n / d
    late = t > t_cross + 1e-6
    expected = np.sqrt(w_inf2 + (w0 ** 2 - w_inf2) * np.exp(-2 * d * (t[late] - t_cross) / J))
    np.testing.assert_allclose(w[late], expected, rtol=1e-6)
    np.testing.assert_allclose(result["drive.tau"][late] * w[late], tau_n * w_n, rtol=1e-9)
    assert result.final("inertia.w") == pytest.approx(math.sqrt(w_inf2), rel=1e-6)


def test_inverse_speed_dependent_torque_from_rest():
    result = simulate(_ConstantPower(0.0), rtol=1e-8)
    assert result.success, result.message
    assert result.final("inertia.w") == pytest.approx(math.sqrt(_ConstantPower.tau_n * _ConstantPower.w_n
                                                                / _ConstantPower.d), rel=1e-6)


def test_inverse_speed_dependent_torque_without_direction():
    # not TorqueDirection: tau = tau_n*w/w0 below w0, tau_n*w_n/w above (MSL 4.1.0 as written)
    tau_n, w_n, w0 = 2.0, 5.0, 0.5

    class Swept(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            self.ramp = Ramp(height=4.0, offset=-2.0, duration=1.0)
            self.speed = Speed(exact=True)
            self.source = InverseSpeedDependentTorque(tau_nominal=tau_n, w_nominal=w_n, w0=w0,
                                                      TorqueDirection=False)
            self.connect(self.ramp.y, self.speed.w_ref)
            self.connect(self.speed.flange, self.source.flange)

    result = simulate(Swept())
    assert result.success, result.message
    switches = sorted(e.time for e in result.events if e.kind == "state")
    assert switches == pytest.approx([0.375, 0.625], abs=1e-8)
    # the law jumps at |w| = w0 (w_nominal != w0): the event rows hold both limits, leave them out
    between = np.all([np.abs(result.time - s) > 1e-9 for s in switches], axis=0)
    w, tau = result["source.w"][between], result["source.tau"][between]
    slow = np.abs(w) < w0
    np.testing.assert_allclose(tau[slow], tau_n * w[slow] / w0, rtol=1e-12)
    np.testing.assert_allclose(tau[~slow], tau_n * w_n / w[~slow], rtol=1e-12)


# --------------------------------------------------------------------------
# SignTorque: the regularized sign law, swept over the speed

def _sign_law(reg, w, w0):
    outside = np.abs(w) >= w0
    if reg is Regularization.Exp:
        return 2 / (1 + np.exp(-w / (0.01 * w0))) - 1
    if reg is Regularization.Sine:
        return np.where(outside, np.sign(w), np.sin(np.pi / 2 * w / w0))
    if reg is Regularization.Linear:
        return np.where(outside, np.sign(w), w / w0)
    return np.where(outside, np.sign(w), np.sign(w) * (1 - np.cos(np.pi / 2 * w / w0)))


@pytest.mark.parametrize("reg", list(Regularization))
def test_sign_torque_regularization(reg):
    tau_n, w0 = 5.0, 0.1

    class Swept(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            self.ramp = Ramp(height=6 * w0, offset=-3 * w0, duration=1.0)
            self.speed = Speed(exact=True)
            self.sign = SignTorque(tau_nominal=tau_n, w0=w0, reg=reg)
            self.connect(self.ramp.y, self.speed.w_ref)
            self.connect(self.speed.flange, self.sign.flange)

    result = simulate(Swept())
    assert result.success, result.message
    w, tau = result["sign.w"], result["sign.tau"]
    np.testing.assert_allclose(tau, tau_n * _sign_law(reg, w, w0), atol=1e-8 * tau_n)
    # at w = 0 (t = 0.5, a sample) no torque; far out (|w| = 3*w0) the full torque
    middle = int(np.argmin(np.abs(result.time - 0.5)))
    assert w[middle] == pytest.approx(0, abs=1e-12) and tau[middle] == pytest.approx(0, abs=1e-9)
    assert tau[0] == pytest.approx(-tau_n, rel=1e-12) and tau[-1] == pytest.approx(tau_n, rel=1e-12)
    # from |w| = w0 on, exactly +-tau_nominal but for Exp (2/(1 + exp(-100)) - 1 there); an event's
    # left-limit row may hold w one relation margin beyond w0 with the inner law still in force
    events = [e.time for e in result.events]
    outside = (np.abs(w) >= w0) & np.all([np.abs(result.time - e) > 1e-9 for e in events], axis=0)
    if reg is Regularization.Exp:
        assert np.all(np.abs(tau[outside]) >= tau_n * (1 - 1e-43))
    else:
        np.testing.assert_array_equal(tau[outside], tau_n * np.sign(w[outside]))
    # the switches at |w| = w0 are state events unless smooth() (Sine) or no switch (Exp)
    switches = [e.time for e in result.events if e.kind == "state"]
    if reg in (Regularization.Linear, Regularization.Cosine):
        assert switches == pytest.approx([1 / 3, 2 / 3], abs=1e-8)
    else:
        assert switches == []


# --------------------------------------------------------------------------
# EddyCurrentTorque: peak at the nominal point, temperature shift, losses

def _eddy_sweep(w_max, port_temperature=None, **modifiers):
    """The brake driven through speeds 0 .. w_max (Speed exact on a ramp), its heat port at a fixed temperature."""

    class Swept(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            self.ramp = Ramp(height=w_max, duration=1.0)
            self.speed = Speed(exact=True)
            self.brake = EddyCurrentTorque(**modifiers)
            self.connect(self.ramp.y, self.speed.w_ref)
            self.connect(self.speed.flange, self.brake.flange)
            if port_temperature is not None:
                self.ambient = FixedTemperature(T=port_temperature)
                self.connect(self.ambient.port, self.brake.heatPort)

    result = simulate(Swept(), rtol=1e-9)
    assert result.success, result.message
    return result


def test_eddy_current_torque_nominal_point():
    tau_n, w_n = 100.0, 10.0
    result = _eddy_sweep(4 * w_n, tau_nominal=tau_n, w_nominal=w_n)
    w, tau = result["brake.w"], result["brake.tau"]
    x = w / w_n
    np.testing.assert_allclose(tau, 2 * tau_n * x / (1 + x ** 2), rtol=1e-12)
    # the maximum, tau_nominal, lies at w_nominal (a sample falls on it: w = 40*t, t = 0.25)
    k = int(np.argmax(tau))
    assert w[k] == pytest.approx(w_n, rel=1e-9) and tau[k] == pytest.approx(tau_n, rel=1e-12)
    # braking (tau = flange.tau > 0 opposes w > 0); all mechanical power is dissipated
    np.testing.assert_allclose(result["brake.lossPower"], tau * w, rtol=1e-12)
    np.testing.assert_allclose(result["speed.flange.tau"], -tau, rtol=1e-12)


@pytest.mark.parametrize("heat_port", [False, True])
def test_eddy_current_torque_temperature_dependency(heat_port):
    tau_n, w_n, alpha20, T_ref, T = 100.0, 10.0, ALPHA20_COPPER, 313.15, 373.15
    # alpha20 converted to TRef (Machines.Thermal.convertAlpha), then linear in T - TRef
    alpha = alpha20 / (1 + alpha20 * (T_ref - 293.15))
    w_peak = w_n * (1 + alpha * (T - T_ref))
    thermal = dict(useHeatPort=True, port_temperature=T) if heat_port else dict(T=T)
    result = _eddy_sweep(2 * w_peak, tau_nominal=tau_n, w_nominal=w_n, alpha20=alpha20, TRef=T_ref, **thermal)
    w, tau = result["brake.w"], result["brake.tau"]
    x = w / w_peak
    np.testing.assert_allclose(tau, 2 * tau_n * x / (1 + x ** 2), rtol=1e-12)
    k = int(np.argmax(tau))
    assert w[k] == pytest.approx(w_peak, rel=1e-9) and tau[k] == pytest.approx(tau_n, rel=1e-12)
    assert float(np.interp(w_n, w, tau)) < tau_n  # the warm brake is weaker at its nominal speed
    if heat_port:
        np.testing.assert_allclose(result["brake.heatPort.Q_flow"], -result["brake.lossPower"], rtol=1e-12)
        np.testing.assert_allclose(result["brake.TheatPort"], T)


def test_eddy_current_brake_energy_balance():
    result = simulate(EddyCurrentBrake(), rtol=1e-8)
    assert result.success, result.message
    # adiabatic: the kinetic energy lost is the heat stored, 0.5*J*(w0^2 - w^2) = C*(T - T0)
    # (to 1e-6 of the 200 J the inertia starts with: the two sides come from different states)
    kinetic_lost = 0.5 * 1.0 * (20.0 ** 2 - result["inertia.w"] ** 2)
    heat = 1.0 * (result["heatCapacitor.T"] - 293.15)
    np.testing.assert_allclose(heat, kinetic_lost, rtol=0, atol=200 * 1e-6)
    assert heat[-1] > 150  # most of the 200 J are converted by t = 1 s
    # the excitation ramps from 0.1 s: no braking before
    before = result.time <= 0.1
    np.testing.assert_allclose(result["inertia.w"][before], 20.0)


def test_simple_gear_shift_ratios():
    result = simulate(SimpleGearShift())
    assert result.success, result.message
    ratio, t = result["gearRatio"], result.time
    # brake holds the ring: load/engine = 1/(1 + 75/50); clutch locked after the shift: 1
    first = (t > 1.0) & (t < 2.0)
    np.testing.assert_allclose(ratio[first], 1 / (1 + 1.5), rtol=1e-6)
    np.testing.assert_allclose(ratio[t > 2.2], 1.0, rtol=1e-6)
    # the clutch starts to slip as the ramp starts, the brake breaks away, then the clutch locks
    switched = [e.time for e in result.events if e.kind == "state" and e.changes]
    # (and at 2.1 the brake's normal force reaches 0: it is free, as in the reference)
    assert switched == pytest.approx([2.0, 2.040816, 2.040817, 2.1, 2.110790], abs=2e-6)


# --------------------------------------------------------------------------
# RelAccSensor

def test_rel_acc_sensor_on_a_known_motion():
    acceleration, amplitude, f = 2.0, 1.5, 1.0

    class Relative(Model):
        experiment = Experiment(stop_time=1.0)

        def build(self):
            self.constant = Constant(k=acceleration)
            self.accelerate = Accelerate()
            _sine_motion(self, amplitude, f)
            self.move = Move()
            self.sensor = RelAccSensor()
            for k, source in enumerate((self.angle, self.speed, self.acceleration), start=1):
                self.connect(source.y, self.move.u[k])
            self.connect(self.constant.y, self.accelerate.a_ref)
            self.connect(self.accelerate.flange, self.sensor.flange_a)
            self.connect(self.move.flange, self.sensor.flange_b)

    result = simulate(Relative())
    assert result.success, result.message
    t, omega = result.time, 2 * math.pi * f
    np.testing.assert_allclose(result["sensor.phi_rel"], amplitude * np.sin(omega * t) - acceleration * t ** 2 / 2,
                               atol=1e-10)
    np.testing.assert_allclose(result["sensor.w_rel"], amplitude * omega * np.cos(omega * t) - acceleration * t,
                               atol=1e-10)
    np.testing.assert_allclose(result["sensor.a_rel"], -amplitude * omega ** 2 * np.sin(omega * t) - acceleration,
                               atol=1e-10)
    # the sensor transmits no torque
    np.testing.assert_allclose(result["sensor.flange_a.tau"], 0, atol=1e-12)
    np.testing.assert_allclose(result["accelerate.flange.tau"], 0, atol=1e-12)


# --------------------------------------------------------------------------
# the MSL reference results

@pytest.mark.parametrize("model_class", [SimpleGearShift, EddyCurrentBrake])
def test_example_matches_reference(model_class):
    if not (reference_dir() / model_class.modelica_class).is_dir():
        pytest.skip(f"no reference results for {model_class.modelica_class} in {reference_dir()} "
                    f"(ACAUSAL_REFERENCE_DIR)")
    reference = load_reference(model_class.modelica_class)
    result = simulate(model_class())
    assert result.success, result.message
    comparison = compare_signals(reference, result.time, result.columns)
    assert comparison.passed, comparison.table()
