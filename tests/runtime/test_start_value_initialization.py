"""Under-determined initialization completed from start values, as Modelica tools do it.

When the fixed start values and initial equations leave states open, the
states without ``fixed=True`` take their start values (0 when none is given)
and a :class:`~acausal.errors.StartValueWarning` names them; the
initialization problem records them (``from_start``) and the result's notes
say so.  A constant torque ``tau`` on an inertia ``J`` with only the speed
fixed has the closed form ``phi(t) = phi_start + w0*t + (tau/J)*t**2/2``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from acausal import Experiment, Model, simulate, translate
from acausal.errors import StartValueWarning
from acausal.library.blocks import Step
from acausal.library.rotational import BearingFriction, Clutch, ConstantTorque, Inertia
from acausal.library.thermal import HeatCapacitor
from acausal.runtime.events import DiscreteEvaluator
from acausal.runtime.initialization import initialize

TAU, J, W0 = 2.0, 0.5, 10.0


def driven_inertia(phi=None, w=None):
    """ConstantTorque TAU on an inertia J whose speed is fixed at W0 (``phi``, ``w``: its modifiers)."""

    class DrivenInertia(Model):
        experiment = Experiment(stop_time=2.0, interval=0.05)

        def build(self):
            self.src = ConstantTorque(tau_constant=TAU)
            self.body = Inertia(J=J, phi=phi or {}, w=w or dict(start=W0, fixed=True))
            self.connect(self.src.flange, self.body.flange_a)

    return DrivenInertia()


def start_value_warnings(record) -> list[str]:
    return [str(w.message) for w in record if issubclass(w.category, StartValueWarning)]


def test_only_the_speed_fixed_runs_and_the_angle_starts_from_its_default_start():
    """The angle (one state shared by the source and the inertia) starts at 0; phi(t) is the closed form."""
    with pytest.warns(StartValueWarning) as record:
        result = simulate(driven_inertia(), rtol=1e-10, atol=1e-10)
    (message,) = start_value_warnings(record)
    # one state: the source's angle and the inertia's angle are the same variable
    assert "src.phi (= body.phi) = 0" in message
    assert "body.w" not in message  # fixed: not named
    assert "DrivenInertia" in message
    t = result.time
    expected = W0 * t + TAU / J * t ** 2 / 2
    assert np.max(np.abs(result["body.phi"] - expected)) < 1e-7
    assert np.max(np.abs(result["src.phi"] - expected)) < 1e-7
    assert any("start value" in note and "src.phi" in note for note in result.notes)


def test_the_initial_system_records_the_states_taken_from_start_values():
    """``from_start`` lists exactly the unfixed states the problem needed, with their values."""
    translation = translate(driven_inertia(), cache=False)
    problem = translation.initial_system(())
    assert problem.from_start == (("src.phi", 0.0),)
    assert problem.relaxed == ()


def test_an_explicit_start_value_is_used():
    """phi start=2 (not fixed) is where the angle starts: phi(t) = 2 + w0 t + (tau/J) t^2/2."""
    with pytest.warns(StartValueWarning) as record:
        result = simulate(driven_inertia(phi=dict(start=2.0)), rtol=1e-10, atol=1e-10)
    (message,) = start_value_warnings(record)
    assert "\n  src.phi (= body.phi) = 2\n" in message
    t = result.time
    expected = 2.0 + W0 * t + TAU / J * t ** 2 / 2
    assert result["body.phi"][0] == pytest.approx(2.0, abs=1e-12)
    assert np.max(np.abs(result["body.phi"] - expected)) < 1e-7


def test_a_fully_fixed_model_gives_no_warning_and_no_note():
    """Angle and speed fixed: determined; no StartValueWarning, nothing in from_start."""
    model = driven_inertia(phi=dict(start=1.0, fixed=True))
    with warnings.catch_warnings():
        warnings.simplefilter("error", StartValueWarning)
        result = simulate(model)
    assert not any("start value" in note for note in result.notes)
    assert translate(model, cache=False).initial_system(()).from_start == ()


def test_a_state_implied_by_the_fixed_values_is_not_taken_from_its_start():
    """Two rigidly connected inertias, the second's speed fixed: the first's speed follows
    (not its start value); only the shared angle is taken from its start."""

    class Rigid(Model):
        def build(self):
            self.src = ConstantTorque(tau_constant=TAU)
            self.i1 = Inertia(J=J, w=dict(start=-4.0))  # a start value the model must not use
            self.i2 = Inertia(J=J, w=dict(start=W0, fixed=True))
            self.connect(self.src.flange, self.i1.flange_a)
            self.connect(self.i1.flange_b, self.i2.flange_a)

    translation = translate(Rigid(), cache=False)
    with pytest.warns(StartValueWarning) as record:
        state = initialize(translation, DiscreteEvaluator(translation), 0.0)
    (message,) = start_value_warnings(record)
    assert "w" not in {n.rpartition(".")[2] for n, _ in translation.initial_system(()).from_start}
    assert "-4" not in message
    assert state.initial_values["i1.w"] == pytest.approx(W0, abs=1e-12)


# --------------------------------------------------------------------------
# the model of issue 14: motor -> clutch (step normal force) -> load with a
# bearing whose heat, and the clutch's, goes into a heat capacitor

TAU_MOTOR, J_MOTOR, J_LOAD, C, T0 = 5.0, 0.1, 0.4, 20.0, 300.0


class MotorClutchLoad(Model):
    """Only the motor inertia's speed is fixed; every other state starts from its start value."""

    experiment = Experiment(stop_time=3.0, interval=0.01)

    def build(self):
        self.motor = ConstantTorque(tau_constant=TAU_MOTOR)
        self.shaft = Inertia(J=J_MOTOR, w=dict(start=W0, fixed=True))
        self.engage = Step(startTime=0.5, height=1.0)
        self.clutch = Clutch(fn_max=50.0, useHeatPort=True)
        self.load = Inertia(J=J_LOAD)
        self.bearing = BearingFriction(tau_pos=[[0.0, 1.0], [10.0, 1.5]], useHeatPort=True)
        self.housing = HeatCapacitor(C=C, T=dict(start=T0))
        self.connect(self.motor.flange, self.shaft.flange_a)
        self.connect(self.shaft.flange_b, self.clutch.flange_a)
        self.connect(self.engage.y, self.clutch.f_normalized)
        self.connect(self.clutch.flange_b, self.load.flange_a)
        self.connect(self.load.flange_b, self.bearing.flange_a)
        self.connect(self.bearing.heatPort, self.housing.port)
        self.connect(self.clutch.heatPort, self.housing.port)


def test_the_motor_clutch_bearing_model_runs_with_only_the_speed_fixed_and_its_energy_balances():
    """The warning names the angles, the clutch's relative states and the temperature; the
    motor's work = kinetic energy gained + heat C*(T - T0) into the capacitor."""
    with pytest.warns(StartValueWarning) as record:
        result = simulate(MotorClutchLoad(), rtol=1e-9, atol=1e-9)
    (message,) = start_value_warnings(record)
    for name in ("motor.phi", "shaft.phi", "clutch.phi_rel", "clutch.w_rel", "housing.T = 300"):
        assert name in message
    assert "shaft.w" not in message
    assert result["housing.T"][0] == pytest.approx(T0, abs=1e-12)
    assert result["load.w"][0] == pytest.approx(W0, abs=1e-12)  # clutch.w_rel = 0: the load turns with the motor
    assert sum(1 for e in result.events if e.changes) >= 2  # the clutch engages, the load sticks or slips

    # a constant torque's work is tau times the angle turned: no quadrature error
    work = TAU_MOTOR * (result["motor.phi"] - result["motor.phi"][0])
    kinetic = 0.5 * J_MOTOR * result["shaft.w"] ** 2 + 0.5 * J_LOAD * result["load.w"] ** 2
    heat = C * (result["housing.T"] - T0)
    imbalance = np.max(np.abs(work - (kinetic - kinetic[0]) - heat))
    assert heat[-1] > 1.0  # the friction did work
    assert imbalance < 1e-7 * max(np.max(np.abs(work)), np.max(kinetic))  # 3e-9 seen at rtol 1e-9


def test_independent_parts_carry_their_start_values_into_the_composed_problem():
    """Two unconnected drive trains (compiled as separate clusters when hybrid): the composed
    initialization problem lists the states of both."""

    class TwoTrains(Model):
        experiment = Experiment(stop_time=0.5, interval=0.05)

        def build(self):
            for k in (1, 2):
                setattr(self, f"src{k}", ConstantTorque(tau_constant=TAU))
                setattr(self, f"body{k}", Inertia(J=J, w=dict(start=W0 * k, fixed=True)))
                setattr(self, f"bearing{k}", BearingFriction(tau_pos=[[0.0, 1.0]]))
                self.connect(getattr(self, f"src{k}").flange, getattr(self, f"body{k}").flange_a)
                self.connect(getattr(self, f"body{k}").flange_b, getattr(self, f"bearing{k}").flange_a)

    translation = translate(TwoTrains(), cache=False)
    with pytest.warns(StartValueWarning) as record:
        state = initialize(translation, DiscreteEvaluator(translation), 0.0)
    (message,) = start_value_warnings(record)
    assert "src1.phi" in message and "src2.phi" in message
    # the problem of the discrete state initialization settled in (compiled last)
    problem = list(translation.initial_systems.values())[-1]
    names = [n for n, _ in problem.from_start]
    assert "src1.phi" in names and "src2.phi" in names
    assert translation.clustering is not None
    assert len(problem.parts) == 2
    assert [part.from_start for part in problem.parts] == [(("src1.phi", 0.0),), (("src2.phi", 0.0),)]


def test_a_run_from_the_disk_cache_warns_too(tmp_path):
    """The compiled initialization problem is stored on disk with the states it takes from
    their start values: a second process that loads it warns the same."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    script = tmp_path / "run.py"
    script.write_text(
        "import warnings, sys\n"
        f"sys.path.insert(0, {str(Path(__file__).parent)!r})\n"
        "from test_start_value_initialization import driven_inertia\n"
        "from acausal import simulate\n"
        "from acausal.errors import StartValueWarning\n"
        "with warnings.catch_warnings(record=True) as caught:\n"
        "    warnings.simplefilter('always')\n"
        "    simulate(driven_inertia())\n"
        "print(sum(issubclass(w.category, StartValueWarning) for w in caught))\n")
    env = dict(os.environ, ACAUSAL_DISK_CACHE="on", ACAUSAL_CACHE_DIR=str(tmp_path / "cache"))
    runs = [subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env,
                           timeout=300) for _ in range(2)]
    for run in runs:
        assert run.returncode == 0, run.stderr
    assert [run.stdout.split()[-1] for run in runs] == ["1", "1"]
    assert any((tmp_path / "cache").rglob("*")), "nothing was stored on disk"
