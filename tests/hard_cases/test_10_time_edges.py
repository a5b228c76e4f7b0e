"""Hard case 10: events at the edges of time — at the start time and at the stop time.

What makes it hard
------------------
* At the start time there is no "before": a Step with ``startTime`` equal to
  the start time, or a torque that exceeds the static limit from the first
  instant, must be handled by the event iteration that follows
  initialization, and the result must show one row at t0 — the values
  *after* that iteration (as the MSL reference files do) — not a left limit
  that never existed.
* Inside the run every event gives exactly two rows (left and right limit).
* At the stop time the integration ends exactly where an event falls: a
  coast-down whose stop t* equals the stop time, or a Step with
  ``startTime = stop_time``.  The run must end cleanly at t = stop_time
  without stepping past it, without a crash and without a spurious event.

A time event at the stop time (bug D of docs/hard-cases.md, fixed)
-------------------------------------------------------------------
A time event exactly at the stop time used to be left unprocessed: the
last row was the left limit (Step output 0 although ``time < startTime`` is
false at t = stop_time).  Dymola and OpenModelica (since OpenModelica PR
#7761, "Handle pending events at final time", for issue #7758) handle an
event pending at the final time, and so does acausal now: the event is
processed and the run ends on its right limit, so t = stop_time has two
rows like any other event, the last one with the Step's new output
(``test_step_at_the_stop_time_shows_its_value_at_the_end``).
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import Model, simulate
from acausal.library.blocks import Step
from acausal.library.rotational import BearingFriction, ConstantTorque, Inertia, Torque

REST = dict(start=0, fixed=True)


def stepped(height, start_time, w0=0.0):
    class SteppedFriction(Model):
        """Step(height, startTime) -> torque -> J = 1 on BearingFriction(tau0 = 1, peak = 1)."""

        def build(self):
            self.step = Step(height=height, startTime=start_time)
            self.torque = Torque()
            self.inertia = Inertia(J=1.0, phi=REST, w=dict(start=w0, fixed=True))
            self.bearing = BearingFriction(tau_pos=[[0.0, 1.0]])
            self.connect(self.step.y, self.torque.tau)
            self.connect(self.torque.flange, self.inertia.flange_a)
            self.connect(self.inertia.flange_b, self.bearing.flange_a)

    return SteppedFriction()


class ConstantFromStart(Model):
    """A constant torque of 3 N.m on a resting J = 1 against tau0 = 1: breakaway at t = 0."""

    def build(self):
        self.torque = ConstantTorque(tau_constant=3.0)
        self.inertia = Inertia(J=1.0, phi=REST, w=REST)
        self.bearing = BearingFriction(tau_pos=[[0.0, 1.0]])
        self.connect(self.torque.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.bearing.flange_a)


def sim(model, method, t0=0.0, t1=1.0, interval=0.1):
    return simulate(model, start_time=t0, stop_time=t1, interval=interval, method=method, rtol=1e-10,
                    max_step=1e-3 if method in ("Euler", "RK4") else None)


def assert_rows_well_formed(result, t0, t1):
    t = result.time
    assert t[0] == t0 and t[-1] == t1
    assert np.all(np.diff(t) >= 0)                         # never backwards, never past the end
    values, counts = np.unique(t, return_counts=True)
    assert counts.max() <= 2                               # at most left + right limit
    assert np.sum(t == t0) == 1                            # one row at the start
    # every repeated time is an event (left and right limit)
    event_times = {e.time for e in result.events}
    assert set(values[counts == 2]) <= event_times


@pytest.mark.parametrize("method", ["RK45", "Radau", "Euler"])
@pytest.mark.parametrize("which", ["step-at-start", "constant-torque"])
def test_breakaway_at_the_start_time(which, method):
    model = stepped(3.0, 0.0) if which == "step-at-start" else ConstantFromStart()
    result = sim(model, method)
    assert result.status == 0, result.message
    assert_rows_well_formed(result, 0.0, 1.0)
    first = result.events[0]
    assert first.kind == "initial" and first.time == 0.0
    assert ("bearing.startForward", False, True) in first.changes
    # the single row at t = 0 holds the values after the post-initialization iteration
    assert result["bearing.startForward"][0] == 1 and result["bearing.locked"][0] == 0
    if which == "step-at-start":
        assert result["step.y"][0] == 3.0
    # sliding from the first instant: J w' = 3 - 1
    np.testing.assert_allclose(result["inertia.w"], 2.0 * result.time, rtol=0, atol=1e-9)
    assert result.final("bearing.mode") == 1
    print(f"\n[case 10] {which} {method}: rows at t=0: {np.sum(result.time == 0.0)}; events: "
          + "; ".join(str(e) for e in result.events))


def test_breakaway_at_a_nonzero_start_time():
    result = sim(stepped(3.0, 2.0), "RK45", t0=2.0, t1=3.0)
    assert result.status == 0, result.message
    assert_rows_well_formed(result, 2.0, 3.0)
    assert result.events[0].time == 2.0 and result["step.y"][0] == 3.0
    np.testing.assert_allclose(result["inertia.w"], 2.0 * (result.time - 2.0), rtol=0, atol=1e-9)


def test_step_at_the_start_time_below_the_limit():
    result = sim(stepped(0.5, 0.0), "RK45")
    assert result.status == 0, result.message
    assert_rows_well_formed(result, 0.0, 1.0)
    assert result["step.y"][0] == 0.5
    assert not [e for e in result.events if e.changes]
    assert np.max(np.abs(result["inertia.w"])) == 0.0


@pytest.mark.parametrize("method", ["RK45", "Euler"])
def test_events_inside_the_run_have_two_rows(method):
    # a time event at 0.5 (breakaway) ...
    result = sim(stepped(3.0, 0.5), method)
    assert result.status == 0, result.message
    assert_rows_well_formed(result, 0.0, 1.0)
    at = np.flatnonzero(result.time == 0.5)
    assert len(at) == 2
    assert list(result["step.y"][at]) == [0.0, 3.0]
    assert list(result["bearing.startForward"][at]) == [0.0, 1.0]
    # ... and a state event at the analytic stop t* = 1 of a coast-down (w0 = 1, tau0 = 1)
    coast = sim(stepped(0.0, 5.0, w0=1.0), method, t1=2.0)
    assert coast.status == 0, coast.message
    assert_rows_well_formed(coast, 0.0, 2.0)
    (stop,) = [e for e in coast.events if e.kind == "state"]
    assert abs(stop.time - 1.0) <= 1e-9
    at = np.flatnonzero(coast.time == stop.time)
    assert len(at) == 2 and list(coast["bearing.mode"][at]) == [1.0, 0.0]


@pytest.mark.parametrize("method", ["RK45", "DOP853", "Radau", "Euler", "RK4"])
def test_coast_down_stopping_exactly_at_the_stop_time(method):
    """w0 = 1, tau0 = 1, J = 1: w reaches 0 at t* = 1 = stop_time."""
    result = sim(stepped(0.0, 5.0, w0=1.0), method)
    assert result.status == 0, result.message
    assert_rows_well_formed(result, 0.0, 1.0)
    assert np.sum(result.time == 1.0) == 1
    assert not [e for e in result.events if e.kind == "state"]   # w never passes -1e-10 before the end
    assert abs(result.final("inertia.w")) <= 1e-12
    phi_tol = 6e-4 if method == "Euler" else 1e-9              # Euler's O(h) error in phi
    assert result.final("inertia.phi") == pytest.approx(0.5, abs=phi_tol)


@pytest.mark.parametrize("method", ["RK45", "Radau", "Euler"])
def test_step_at_the_stop_time_finishes_cleanly(method):
    result = sim(stepped(3.0, 1.0), method)
    assert result.status == 0, result.message
    assert_rows_well_formed(result, 0.0, 1.0)
    assert np.max(np.abs(result["inertia.w"])) == 0.0   # the torque never acted before the end
    print(f"\n[case 10] Step(startTime = stop_time) {method}: {np.sum(result.time == 1.0)} row(s) at "
          f"t = 1, step.y there = {result['step.y'][result.time == 1.0]}, events: "
          + "; ".join(str(e) for e in result.events))


def test_step_at_the_stop_time_shows_its_value_at_the_end():
    result = sim(stepped(3.0, 1.0), "RK45")
    assert result.final("step.y") == 3.0
