"""Tests of :mod:`acausal.tools.linearize`: linearization per discrete state, and steady states.

The matrices are checked against closed forms (two inertias joined by a
spring and damper; a drive held by a stuck clutch against a shaft) to 1e-8
relative, and against central finite differences of the compiled
right-hand side of every discrete state a CoupledClutches run visits (an
independent check: the compiled code is generated from the same equations
but evaluated, not differentiated).  Steady states are checked against the
terminal speed of a drive against speed-dependent losses, and against a
bearing whose static limit decides whether the drive turns at all.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

from acausal import Experiment, Model, RealInput, simulate, translate
from acausal.errors import SettingError, SolverError
from acausal.library.blocks import Constant, Step
from acausal.library.rotational import (BearingFriction, ConstantTorque, Damper, Fixed, Inertia,
                                        QuadraticSpeedDependentTorque, SpringDamper, Torque)
from acausal.tools.linearize import Linearization, SteadyState, linearize, steady_state

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from examples.clutch_drive import ClutchDrive  # noqa: E402
from examples.coupled_clutches import CoupledClutches  # noqa: E402

pytestmark = pytest.mark.filterwarnings("ignore::acausal.errors.StartValueWarning")

J1, J2, C, D = 2.0, 5.0, 100.0, 3.0


class TwoInertias(Model):
    """A torque step on J1; J1 and J2 joined by a spring and damper in parallel."""

    experiment = Experiment(stop_time=1.0)

    def build(self):
        self.step = Step(height=2.0, startTime=0.2)
        self.torque = Torque()
        self.J1 = Inertia(J=J1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.spring = SpringDamper(c=C, d=D, phi_rel=dict(start=0, fixed=True), w_rel=dict(start=0, fixed=True))
        self.J2 = Inertia(J=J2)
        self.connect(self.step.y, self.torque.tau)
        self.connect(self.torque.flange, self.J1.flange_a)
        self.connect(self.J1.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.J2.flange_a)


#: The engine's possible states of TwoInertias as rows over q = (phi1, w1, phi2, w2).
COORDINATES = {
    "J1.phi": [1, 0, 0, 0], "J1.w": [0, 1, 0, 0], "J2.phi": [0, 0, 1, 0], "J2.w": [0, 0, 0, 1],
    "spring.phi_rel": [-1, 0, 1, 0], "spring.w_rel": [0, -1, 0, 1],
}


def two_inertias_closed_form(state_names):
    """A, B in the engine's states: ``T A_q T^-1`` and ``T B_q`` with ``x = T q``."""
    A_q = np.array([[0, 1, 0, 0],
                    [-C / J1, -D / J1, C / J1, D / J1],
                    [0, 0, 0, 1],
                    [C / J2, D / J2, -C / J2, -D / J2]])
    B_q = np.array([[0], [1 / J1], [0], [0]])
    T = np.array([COORDINATES[s] for s in state_names], dtype=float)
    return T @ A_q @ np.linalg.inv(T), T @ B_q, T


def assert_close(actual, expected, rtol):
    """Entry by entry to ``rtol`` relative to the largest entry (exact zeros stay zeros within that)."""
    scale = max(float(np.max(np.abs(expected))), 1e-300)
    np.testing.assert_allclose(actual, expected, rtol=rtol, atol=rtol * scale)


# -- closed forms ------------------------------------------------------------------------------


@pytest.mark.parametrize("source", ["step.y", "torque.tau"])
def test_two_inertias_match_the_closed_form(source):
    lin = linearize(TwoInertias(), at=0.5, inputs=[source], outputs=["J2.w", "spring.tau", source])
    assert isinstance(lin, Linearization)
    assert len(lin.state_names) == 4
    A, B, T = two_inertias_closed_form(lin.state_names)
    assert_close(lin.A, A, 1e-8)
    assert_close(lin.B, B, 1e-8)
    T_inv = np.linalg.inv(T)
    C_q = np.array([[0, 0, 0, 1], [-C, -D, C, D], [0, 0, 0, 0]], dtype=float)
    assert_close(lin.C, C_q @ T_inv, 1e-8)
    np.testing.assert_array_equal(lin.D, [[0.0], [0.0], [1.0]])
    # the operating point: after the step the input is its height
    assert lin.u0 == pytest.approx([2.0])
    assert lin.t == pytest.approx(0.5)
    assert lin.discrete_state and lin.discrete_key is not None


def test_an_operating_point_given_as_states_gives_the_same_matrices():
    at_time = linearize(TwoInertias(), at=0.5, inputs=["step.y"])
    point = dict(zip(at_time.state_names, at_time.x0))
    given = linearize(TwoInertias(), at=point, t=0.5, inputs=["step.y"])
    assert given.state_names == at_time.state_names
    np.testing.assert_allclose(given.A, at_time.A, rtol=1e-12)
    np.testing.assert_allclose(given.B, at_time.B, rtol=1e-12)


def test_a_variable_that_depends_on_the_states_cannot_be_an_input():
    with pytest.raises(SettingError, match=r"J2\.w cannot be an input"):
        linearize(TwoInertias(), at=0.5, inputs=["J2.w"])
    with pytest.raises(SettingError, match=r"spring\.tau cannot be an input"):
        linearize(TwoInertias(), at=0.5, inputs=["spring.tau"])
    with pytest.raises(SettingError, match="no variable 'J2.ww'"):
        linearize(TwoInertias(), at=0.5, inputs=["J2.ww"])
    with pytest.raises(SettingError, match="no continuous variable 'J9.w'"):
        linearize(TwoInertias(), at=0.5, outputs=["J9.w"])


class Plant(Model):
    """A top-level input drives an inertia against a damper."""

    u = RealInput()

    def build(self):
        self.torque = Torque()
        self.J = Inertia(J=J1)
        self.damper = Damper(d=D)
        self.fixed = Fixed()
        self.connect(self.u, self.torque.tau)
        self.connect(self.torque.flange, self.J.flange_a)
        self.connect(self.J.flange_b, self.damper.flange_a)
        self.connect(self.damper.flange_b, self.fixed.flange)


def test_a_top_level_input_is_linearized_at_a_given_point():
    lin = linearize(Plant(), at={"damper.phi_rel": 0.0, "damper.w_rel": -1.0, "u": 0.5}, inputs=["u"],
                    outputs=["J.w"])
    w_row = lin.state_names.index("damper.w_rel")  # w_rel = -J.w
    assert lin.A[w_row, w_row] == pytest.approx(-D / J1, rel=1e-12)
    assert lin.B[w_row, 0] == pytest.approx(-1 / J1, rel=1e-12)
    assert lin.C[0, w_row] == pytest.approx(-1.0)
    with pytest.raises(SettingError, match="operating point"):
        linearize(Plant(), at=0.5, inputs=["u"])


# -- per discrete state: a clutch drive -------------------------------------------------------


def mode_midpoints(result, stop_time, shortest=2e-3):
    """Times in the middle of every interval between events."""
    times = sorted({0.0, *(float(e.time) for e in result.events), stop_time})
    return [0.5 * (a + b) for a, b in zip(times, times[1:]) if b - a > shortest]


def central_differences(function, x0, step=1e-6):
    """The Jacobian of ``function`` at ``x0`` by central differences, column by column."""
    x0 = np.asarray(x0, dtype=float)
    columns = []
    for j in range(len(x0)):
        h = step * max(1.0, abs(x0[j]))
        up, down = x0.copy(), x0.copy()
        up[j] += h
        down[j] -= h
        columns.append((np.asarray(function(up)) - np.asarray(function(down))) / (2 * h))
    return np.column_stack(columns) if columns else np.zeros((len(x0), 0))


@pytest.fixture(scope="module")
def clutch_drive():
    translation = translate(ClutchDrive())
    result = simulate(translation).raise_for_status()
    found = {}
    for t in mode_midpoints(result, 2.0):
        lin = linearize(translation, at=t, inputs=["torque.tau"], outputs=["J2.w"])
        found.setdefault(lin.discrete_state, lin)
    return translation, found


def test_stuck_and_sliding_clutch_give_different_matrices(clutch_drive):
    _, found = clutch_drive
    stuck = found["clutch: Stuck (locked)"]
    sliding = [lin for name, lin in found.items() if name in ("clutch: Forward", "clutch: Backward")]
    assert sliding, f"no sliding state among {sorted(found)}"
    for lin in sliding:
        assert lin.state_names == stuck.state_names
        assert not np.allclose(lin.A, stuck.A), "a sliding clutch must change A"
    # stuck: J1 + J2 = 3 ride on the shaft as one body, s^2 + (d/J) s + c/J = 0
    J, c, d = 3.0, 400.0, 4.0
    expected = np.roots([1.0, d / J, c / J])
    oscillating = sorted((v for v in stuck.eigenvalues if abs(v.imag) > 1e-9), key=lambda v: v.imag)
    np.testing.assert_allclose(oscillating, sorted(expected, key=lambda v: v.imag), rtol=1e-8)


def test_clutch_drive_matches_finite_differences_in_each_mode(clutch_drive):
    translation, found = clutch_drive
    for name, lin in found.items():
        system = translation.system(lin.discrete_key)
        assert tuple(system.states) == lin.state_names

        def f(x):
            return system.derivatives(lin.t, x)

        assert_close(lin.A, central_differences(f, lin.x0), 1e-6)


# -- per discrete state: CoupledClutches against finite differences ---------------------------


@pytest.fixture(scope="module")
def coupled():
    translation = translate(CoupledClutches())
    result = simulate(translation).raise_for_status()
    points = [linearize(translation, at=t, inputs=["sin1.y"], outputs=["J4.w"])
              for t in mode_midpoints(result, 1.5)]
    return translation, result, points


def test_coupled_clutches_visits_several_named_discrete_states(coupled):
    translation, result, points = coupled
    names = {lin.discrete_state for lin in points}
    assert len(names) >= 5
    assert any("clutch1: Stuck" in n for n in names)
    assert any("clutch1: Backward" in n for n in names)
    # the engine's description of each is one the run visited
    assert {lin.discrete_description for lin in points} <= set(result.modes)
    # stuck and sliding clutch 1 (clutch 2 stuck, clutch 3 free): the input acts differently
    stuck = next(p for p in points if p.discrete_state.startswith("clutch1: Stuck (locked), clutch2: Stuck"))
    sliding = next(p for p in points if p.discrete_state.startswith("clutch1: Backward, clutch2: Stuck"))
    assert not np.allclose(stuck.B, sliding.B)


def test_coupled_clutches_A_matches_finite_differences_in_each_visited_state(coupled):
    translation, _, points = coupled
    for lin in points:
        system = translation.system(lin.discrete_key)
        assert tuple(system.states) == lin.state_names
        numeric = central_differences(lambda x: system.derivatives(lin.t, x), lin.x0)
        assert_close(lin.A, numeric, 1e-6)


def test_coupled_clutches_B_matches_finite_differences_of_the_source(coupled):
    """B by perturbing the sine's amplitude a: d f/d a = B * d sin1.y/d a = B sin(2 pi 5 t)."""
    translation, _, points = coupled
    h = 1e-4
    up = translate(CoupledClutches(), parameters={"sin1.amplitude": 10.0 + h})
    down = translate(CoupledClutches(), parameters={"sin1.amplitude": 10.0 - h})
    checked = 0
    for lin in points:
        key, t, x = lin.discrete_key, lin.t, lin.x0
        numeric = (np.asarray(up.system(key).derivatives(t, x)) - np.asarray(down.system(key).derivatives(t, x))) / (2 * h)
        exact = lin.B[:, 0] * math.sin(2 * math.pi * 5.0 * t)
        # relative to B itself: where the sine is near zero both sides are round-off
        np.testing.assert_allclose(exact, numeric, rtol=1e-6, atol=1e-6 * np.max(np.abs(lin.B)))
        checked += abs(math.sin(2 * math.pi * 5.0 * t)) > 0.1
    assert checked >= 3


# -- steady states ------------------------------------------------------------------------------


T_DRIVE, D_LOSS = 3.0, 0.4


class DampedDrive(Model):
    """A constant torque against a damper to ground: w* = T/d."""

    def build(self):
        self.drive = ConstantTorque(tau_constant=T_DRIVE)
        self.J = Inertia(J=2.0)
        self.damper = Damper(d=D_LOSS)
        self.fixed = Fixed()
        self.connect(self.drive.flange, self.J.flange_a)
        self.connect(self.J.flange_b, self.damper.flange_a)
        self.connect(self.damper.flange_b, self.fixed.flange)


K_FAN, W_NOMINAL = 1.5, 10.0


class FanDrive(Model):
    """A constant torque against a quadratic load: T = k (w/w_nominal)^2."""

    def build(self):
        self.drive = ConstantTorque(tau_constant=T_DRIVE)
        self.J = Inertia(J=2.0)
        self.load = QuadraticSpeedDependentTorque(tau_nominal=-K_FAN, w_nominal=W_NOMINAL)
        self.connect(self.drive.flange, self.J.flange_a)
        self.connect(self.J.flange_b, self.load.flange)


def test_terminal_speed_against_a_damper():
    found = steady_state(DampedDrive())
    assert isinstance(found, SteadyState)
    assert found["J.w"] == pytest.approx(T_DRIVE / D_LOSS, rel=1e-8)
    # the angle keeps turning: held, not solved for, and its rate is the speed
    assert found.free and all("phi" in s for s in found.free)
    assert found.residual < 1e-10
    assert abs(found.derivatives[f"der({found.free[0]})"]) == pytest.approx(T_DRIVE / D_LOSS, rel=1e-8)


def test_terminal_speed_against_a_quadratic_load_and_its_linearization():
    found = steady_state(FanDrive(), guess={"J.w": 1.0})
    w = W_NOMINAL * math.sqrt(T_DRIVE / K_FAN)
    assert found["J.w"] == pytest.approx(w, rel=1e-8)
    lin = linearize(FanDrive(), at=found.states, inputs=[], outputs=["J.w"])
    row = lin.state_names.index("J.w")
    # d/dw (T - k (w/wn)^2) / J
    assert lin.A[row, row] == pytest.approx(-2 * K_FAN * w / W_NOMINAL ** 2 / 2.0, rel=1e-8)


class BearingDrive(Model):
    """A constant torque on an inertia in a bearing: tau(w) = 1 + 0.1 w, static limit 1.2."""

    experiment = Experiment(stop_time=1.0)

    def __init__(self, drive: float, **modifiers) -> None:
        self.drive = drive
        super().__init__(**modifiers)

    def build(self):
        self.source = Constant(k=self.drive)
        self.torque = Torque()
        self.J = Inertia(J=2.0, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.bearing = BearingFriction(tau_pos=[[0.0, 1.0], [10.0, 2.0]], peak=1.2)
        self.connect(self.source.y, self.torque.tau)
        self.connect(self.torque.flange, self.J.flange_a)
        self.connect(self.J.flange_b, self.bearing.flange_a)


def test_below_the_static_limit_the_steady_state_is_stuck():
    found = steady_state(BearingDrive(1.1))
    assert found["J.w"] == 0.0
    assert found.discrete_state == "bearing: Stuck (locked)"


def test_above_the_static_limit_the_steady_state_slides_at_the_closed_form_speed():
    found = steady_state(BearingDrive(1.5))
    assert found["J.w"] == pytest.approx((1.5 - 1.0) / 0.1, rel=1e-8)
    assert found.discrete_state == "bearing: Forward"
    assert found.rounds == 2  # stuck first, then the event iteration starts the slip
    assert found.discrete_description in translate(BearingDrive(1.5)).describe(found.discrete_key)


def test_a_drive_without_loss_has_no_steady_state():
    class Accelerating(Model):
        def build(self):
            self.drive = ConstantTorque(tau_constant=1.0)
            self.J = Inertia(J=1.0)
            self.connect(self.drive.flange, self.J.flange_a)

    with pytest.raises(SolverError, match="no steady state"):
        steady_state(Accelerating())


# -- python-control ------------------------------------------------------------------------------


def test_to_control_gives_a_state_space_with_the_names():
    control = pytest.importorskip("control")
    lin = linearize(TwoInertias(), at=0.5, inputs=["step.y"], outputs=["J2.w"])
    system = lin.to_control()
    assert isinstance(system, control.StateSpace)
    np.testing.assert_array_equal(system.A, lin.A)
    # python-control reserves '.' in signal names
    assert list(system.state_labels) == [n.replace(".", "_") for n in lin.state_names]
    assert list(system.input_labels) == ["step_y"] and list(system.output_labels) == ["J2_w"]
    s = 2j
    expected = lin.C @ np.linalg.solve(s * np.eye(4) - lin.A, lin.B) + lin.D
    assert complex(system(s)) == pytest.approx(complex(expected[0, 0]), rel=1e-10)


def test_to_control_without_python_control_says_how_to_install_it(monkeypatch):
    lin = linearize(TwoInertias(), at=0.5, inputs=["step.y"], outputs=["J2.w"])
    monkeypatch.setitem(sys.modules, "control", None)
    with pytest.raises(ImportError, match="pip install control"):
        lin.to_control()
