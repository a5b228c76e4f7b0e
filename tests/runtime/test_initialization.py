"""Unit tests of initialization (:func:`acausal.runtime.initialization.initialize`).

Drive trains small enough to solve by hand: a constant torque T on two
rigidly connected inertias accelerates both at T/(J1 + J2); the second
inertia's speed equals the first's, so fixing it as well is redundant
(relaxed, with a note) when the values agree and a conflict when they do not.
"""

from __future__ import annotations

import pytest

from acausal import Model, translate
from acausal.errors import InitializationError, StartValueWarning
from acausal.library.rotational import ConstantTorque, Inertia, TorqueStep
from acausal.runtime.events import DiscreteEvaluator
from acausal.runtime.initialization import InitialState, initialize

T, J1, J2, PHI0, W0 = 3.0, 1.0, 2.0, 0.2, 1.5


def two_inertias(w2_start=None):
    """ConstantTorque T on i1 (phi, w fixed), i1 rigidly connected to i2 (w fixed at ``w2_start`` if given)."""

    class TwoInertias(Model):
        def build(self):
            self.src = ConstantTorque(tau_constant=T)
            self.i1 = Inertia(J=J1, phi=dict(start=PHI0, fixed=True), w=dict(start=W0, fixed=True))
            extra = {} if w2_start is None else dict(w=dict(start=w2_start, fixed=True))
            self.i2 = Inertia(J=J2, **extra)
            self.connect(self.src.flange, self.i1.flange_a)
            self.connect(self.i1.flange_b, self.i2.flange_a)

    return TwoInertias()


def initial_state(model, start_time: float = 0.0) -> InitialState:
    translation = translate(model, cache=False)
    return initialize(translation, DiscreteEvaluator(translation), start_time)


@pytest.mark.parametrize("start_time", [0.0, 1.25])
def test_fixed_start_values_are_honoured(start_time):
    """phi1 = 0.2 and w1 = 1.5 as fixed; i2 follows rigidly; a = T/(J1 + J2) = 1; the torque source sees -T."""
    state = initial_state(two_inertias(), start_time)
    values = state.initial_values
    assert state.time == start_time
    assert values["i1.phi"] == pytest.approx(PHI0, abs=1e-12)
    assert values["i1.w"] == pytest.approx(W0, abs=1e-12)
    assert values["i2.phi"] == pytest.approx(PHI0, abs=1e-12)
    assert values["i2.w"] == pytest.approx(W0, abs=1e-12)
    alpha = T / (J1 + J2)
    assert values["i1.a"] == pytest.approx(alpha, abs=1e-12)
    assert values["i2.a"] == pytest.approx(alpha, abs=1e-12)
    # i1 passes J2*alpha on to i2: i2.flange_a.tau = J2*alpha
    assert values["i2.flange_a.tau"] == pytest.approx(J2 * alpha, abs=1e-12)
    assert values["src.flange.tau"] == pytest.approx(-T, abs=1e-12)
    assert state.notes == ()


def test_a_redundant_fixed_start_is_relaxed_with_a_note():
    """i2.w fixed at 1.5 = i1.w: implied by the others, dropped from the problem, and said so."""
    state = initial_state(two_inertias(w2_start=W0))
    assert state.initial_values["i2.w"] == pytest.approx(W0, abs=1e-12)
    assert state.initial_values["i1.w"] == pytest.approx(W0, abs=1e-12)
    assert len(state.notes) == 1
    (note,) = state.notes
    assert "i2.w" in note and "1.5" in note and "implied" in note


def test_conflicting_fixed_starts_raise_naming_the_variable():
    """i2.w fixed at 2 while i1.w is fixed at 1.5 and w2 = w1: InitializationError naming i2.w and both values."""
    with pytest.raises(InitializationError) as info:
        initial_state(two_inertias(w2_start=2.0))
    message = str(info.value)
    assert "i2.w" in message and "conflicting" in message
    assert "2" in message and "1.5" in message
    assert info.value.hint and "i2.w" in info.value.hint


def test_an_unfixed_state_takes_its_start_value_with_a_warning_naming_it():
    """A driven inertia with only phi fixed: its speed takes its start value (0), as in Modelica tools."""

    class OnlyAngle(Model):
        def build(self):
            self.src = ConstantTorque(tau_constant=T)
            self.body = Inertia(J=J1, phi=dict(start=0.0, fixed=True))
            self.connect(self.src.flange, self.body.flange_a)

    with pytest.warns(StartValueWarning) as record:
        state = initial_state(OnlyAngle())
    message = str(record[0].message)
    assert "body.w = 0" in message
    assert "body.phi" not in message  # phi is fixed: not named
    assert "fixed=True" in message
    assert state.initial_values["body.w"] == 0.0
    assert any("body.w" in note for note in state.notes)


def test_nothing_fixed_names_both_states():
    """A lone inertia with no fixed start: its two states, angle and speed, start from 0 and are named."""

    class Free(Model):
        def build(self):
            self.body = Inertia(J=J1)

    with pytest.warns(StartValueWarning) as record:
        initial_state(Free())
    message = str(record[0].message)
    assert "body.phi" in message and "body.w" in message


@pytest.mark.parametrize("start_time, step_time, torque", [
    (0.0, 0.0, 2.5),   # time < startTime is false at time = startTime: offset + step
    (1.0, 2.0, 0.5),   # before the step: the offset only
    (1.0, 1.0, 2.5),
])
def test_a_time_relation_at_the_start_time_has_its_exact_value(start_time, step_time, torque):
    """TorqueStep(offset 0.5, step 2, startTime) on J = 4: a = torque/4 at the start, before and after the event iteration."""

    class Stepped(Model):
        def build(self):
            self.src = TorqueStep(stepTorque=2.0, offsetTorque=0.5, startTime=step_time)
            self.body = Inertia(J=4.0, phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=True))
            self.connect(self.src.flange, self.body.flange_a)

    state = initial_state(Stepped(), start_time)
    assert state.initial_values["body.a"] == pytest.approx(torque / 4.0, abs=1e-12)
    assert state.outcome.values["body.a"] == pytest.approx(torque / 4.0, abs=1e-12)
    assert state.outcome.values["src.tau"] == pytest.approx(torque, abs=1e-12)
