"""Hard case 4: simultaneous events — two elements switching at one instant; a time event on a state event.

What makes it hard
------------------
* Two identical inertia + bearing branches driven by the same sine cross
  their breakaway relations at *the same* instant.  A locator that handles
  one crossing per event must not lose the second one, nor put it at a
  slightly different time; the event iteration must switch both elements
  in one pass of the fixed-point iteration.
* With different inertias (J = 1 and J = 3) the analytic slip/stop times are
  still identical (with Coulomb friction ``J*w(t)`` is a function of the
  drive only), but the velocities — the crossing functions — differ in
  scale: both stops must be found at the same time.
* A coast-down that stops exactly at t = 1 while a Step switches a drive on
  at t = 1: a time event and a state event coincide.  Depending on the drive
  the inertia must continue forward, reverse, or stick.

The expected event times come from a small closed-form oracle (Coulomb
friction, peak = 1, sine drive: ``J*w`` is an explicit integral between
events; the zeros are found with brentq on that formula).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from acausal import Model, simulate
from acausal.library.blocks import Sine, Step
from acausal.library.rotational import BearingFriction, Inertia, Torque

REST = dict(start=0, fixed=True)
A, F_HZ, TAU0, STOP = 2.0, 1.0, 1.0, 2.0
OMEGA = 2 * math.pi * F_HZ


def coulomb_oracle(stop):
    """Mode changes [(t, old, new)] of J*w' = A sin(wt) - tau0*sign(w) from rest, peak = 1.

    Independent of J.  While stuck the breakaway is where |A sin| first exceeds
    tau0; while sliding in direction s from t_k, J*w = A(cos w t_k - cos w t)/w
    - s tau0 (t - t_k) and the slide ends at its next zero; there the drive
    decides between reversing (|A sin| > tau0) and sticking.
    """
    changes, t, mode = [], 0.0, 0
    while True:
        if mode == 0:
            g = lambda u: abs(A * math.sin(OMEGA * u)) - TAU0  # noqa: E731
            grid = np.arange(t + 1e-9, stop, 1e-3)
            crossing = next((k for k in range(len(grid) - 1) if g(grid[k]) <= 0 < g(grid[k + 1])), None)
            if crossing is None:
                return changes
            t = brentq(g, grid[crossing], grid[crossing + 1], xtol=1e-15)
            new = 1 if math.sin(OMEGA * t) > 0 else -1
            changes.append((t, 0, new))
            mode = new
        else:
            tk, s = t, mode
            H = lambda u: s * (A * (math.cos(OMEGA * tk) - math.cos(OMEGA * u)) / OMEGA  # noqa: E731
                               - s * TAU0 * (u - tk))
            grid = np.arange(tk + 1e-6, stop, 1e-3)
            crossing = next((k for k in range(len(grid) - 1) if H(grid[k]) > 0 >= H(grid[k + 1])), None)
            if crossing is None:
                return changes
            t = brentq(H, grid[crossing], grid[crossing + 1], xtol=1e-15)
            drive = A * math.sin(OMEGA * t)
            new = (1 if drive > 0 else -1) if abs(drive) > TAU0 else 0
            changes.append((t, mode, new))
            mode = new


EXPECTED = coulomb_oracle(STOP)


def twin_branches(J1, J2):
    class TwinBranches(Model):
        """One sine drives two independent inertia + bearing branches."""

        def build(self):
            self.sine = Sine(amplitude=A, f=F_HZ)
            self.torque1 = Torque()
            self.torque2 = Torque()
            self.inertia1 = Inertia(J=J1, phi=REST, w=REST)
            self.inertia2 = Inertia(J=J2, phi=REST, w=REST)
            self.bearing1 = BearingFriction(tau_pos=[[0.0, TAU0]])
            self.bearing2 = BearingFriction(tau_pos=[[0.0, TAU0]])
            self.connect(self.sine.y, self.torque1.tau)
            self.connect(self.sine.y, self.torque2.tau)
            self.connect(self.torque1.flange, self.inertia1.flange_a)
            self.connect(self.inertia1.flange_b, self.bearing1.flange_a)
            self.connect(self.torque2.flange, self.inertia2.flange_a)
            self.connect(self.inertia2.flange_b, self.bearing2.flange_a)

    return TwinBranches()


def changes_of(result, name):
    return [(e, old, new) for e in result.events for n, old, new in e.changes if n == name]


def test_oracle_premises():
    """The oracle's picture: breakaway at asin(1/2)/(2 pi) = 1/12, then direct reversals (|drive| > tau0)."""
    assert EXPECTED[0][0] == pytest.approx(1 / 12, abs=1e-14)
    assert [(o, n) for _, o, n in EXPECTED] == [(0, 1), (1, -1), (-1, 1), (1, -1)]


@pytest.mark.parametrize("method", ["RK45", "DOP853", "Radau"])
def test_identical_branches_switch_in_the_same_event(method):
    result = simulate(twin_branches(1.0, 1.0), stop_time=STOP, interval=1e-3, method=method, rtol=1e-10)
    assert result.status == 0, result.message
    c1, c2 = changes_of(result, "bearing1.mode"), changes_of(result, "bearing2.mode")
    assert [(o, n) for _, o, n in c1] == [(o, n) for _, o, n in EXPECTED]
    assert [(o, n) for _, o, n in c2] == [(o, n) for _, o, n in EXPECTED]
    # each mode change of bearing2 happens in the very same Event as bearing1's
    assert all(e1 is e2 for (e1, _, _), (e2, _, _) in zip(c1, c2))
    # the breakaway too: both startForward flags in one event, fired by both relations
    starts = [e for e in result.events if ("bearing1.startForward", False, True) in e.changes]
    assert len(starts) == 1 and ("bearing2.startForward", False, True) in starts[0].changes
    # one crossing per bearing; with peak = 1 each bearing's `sa > tau0_max` and `sa > tau0`
    # are the same relation and cross together
    assert {r.split(".")[0] for r in starts[0].relations} == {"bearing1", "bearing2"}
    assert {r.split(" ")[0] for r in starts[0].relations} == {"bearing1.sa", "bearing2.sa"}
    assert starts[0].time == pytest.approx(1 / 12, abs=1e-9)
    times = np.array([e.time for e, _, _ in c1])
    # mode changes into sliding follow startForward after the ~4e-6 s waiting phase
    np.testing.assert_allclose(times, [t for t, _, _ in EXPECTED], rtol=0, atol=1e-5)
    np.testing.assert_allclose(times[1:], [t for t, _, _ in EXPECTED[1:]], rtol=0, atol=1e-9)
    # the two branches are the same computation: identical speeds in every row
    np.testing.assert_array_equal(result["inertia1.w"], result["inertia2.w"])
    state_events = [e for e in result.events if e.kind == "state"]
    assert len(state_events) == len(EXPECTED) + 1  # + the waiting phase after startForward
    print(f"\n[case 4] identical branches {method}: {len(state_events)} state events for "
          f"{2 * len(EXPECTED)} mode changes (both elements in each), max |t - t_exact| after "
          f"breakaway = {np.max(np.abs(times[1:] - [t for t, _, _ in EXPECTED[1:]])):.1e} s")


@pytest.mark.parametrize("method", ["RK45", "DOP853", "Radau"])
def test_different_inertias_switch_at_the_same_instant(method):
    """J = 1 and J = 3: identical analytic event times, speeds w_i = J1*w1/J_i."""
    J1, J2 = 1.0, 3.0
    result = simulate(twin_branches(J1, J2), stop_time=STOP, interval=1e-3, method=method, rtol=1e-10)
    assert result.status == 0, result.message
    expected = np.array([t for t, _, _ in EXPECTED])
    starts = [e for e in result.events if ("bearing1.startForward", False, True) in e.changes]
    assert len(starts) == 1 and ("bearing2.startForward", False, True) in starts[0].changes
    for name in ("bearing1.mode", "bearing2.mode"):
        c = changes_of(result, name)
        assert [(o, n) for _, o, n in c] == [(o, n) for _, o, n in EXPECTED]
        times = np.array([e.time for e, _, _ in c])
        np.testing.assert_allclose(times[1:], expected[1:], rtol=0, atol=1e-9)
        assert abs(times[0] - expected[0]) < 1e-5  # waiting phase, grows like sqrt(J)
    t1 = np.array([e.time for e, _, _ in changes_of(result, "bearing1.mode")])
    t2 = np.array([e.time for e, _, _ in changes_of(result, "bearing2.mode")])
    gap = np.max(np.abs(t1[1:] - t2[1:]))
    assert gap <= 1e-9
    np.testing.assert_allclose(J2 * result["inertia2.w"], J1 * result["inertia1.w"], rtol=0,
                               atol=1e-8)
    print(f"\n[case 4] J = 1 and 3, {method}: {len([e for e in result.events if e.kind == 'state'])} "
          f"state events, largest gap between the two elements' stop/reversal events {gap:.1e} s")


# -- a time event on top of a state event ---------------------------------------------


def coast_then_step(height, peak=1.0):
    class CoastThenStep(Model):
        """J = 1 coasting from w0 = 1 against tau0 = 1 stops at t = 1, when Step(height) switches on."""

        def build(self):
            self.step = Step(height=height, startTime=1.0)
            self.torque = Torque()
            self.inertia = Inertia(J=1.0, phi=REST, w=dict(start=1.0, fixed=True))
            self.bearing = BearingFriction(tau_pos=[[0.0, 1.0]], peak=peak)
            self.connect(self.step.y, self.torque.tau)
            self.connect(self.torque.flange, self.inertia.flange_a)
            self.connect(self.inertia.flange_b, self.bearing.flange_a)

    return CoastThenStep()


def run_coincident(height, method, peak=1.0):
    fixed = method in ("Euler", "RK4")
    result = simulate(coast_then_step(height, peak), stop_time=2.0, interval=0.01, method=method,
                      rtol=1e-10, max_step=1e-3 if fixed else None)
    assert result.status == 0, result.message
    t = result.time
    # the time event gives two rows at exactly t = 1: step output 0 then height
    at = np.flatnonzero(t == 1.0)
    assert len(at) == 2
    assert list(result["step.y"][at]) == [0.0, height]
    time_events = [e for e in result.events if e.kind == "time"]
    assert [e.time for e in time_events] == [1.0]
    # at most one more event, within 1e-9 s (the state event w = -1e-10)
    near = [e for e in result.events if 1.0 <= e.time <= 1.0 + 1e-9]
    assert 1 <= len(near) <= 2 and len(result.events) == 1 + len(near)
    before = t < 1.0
    np.testing.assert_allclose(result["inertia.w"][before], 1.0 - t[before], rtol=0, atol=1e-8)
    return result


@pytest.mark.parametrize("method", ["RK45", "DOP853", "Radau", "Euler"])
@pytest.mark.parametrize("height, expect", [(3.0, "forward"), (-3.0, "backward"), (0.5, "stick")])
def test_time_event_coincides_with_stop(height, expect, method):
    result = run_coincident(height, method)
    t, w, mode = result.time, result["inertia.w"], result["bearing.mode"]
    after = t > 1.0 + 1e-9
    if expect == "forward":      # 3 > tau0_max: keeps sliding forward, J a = 3 - 1
        np.testing.assert_allclose(w[after], 2.0 * (t[after] - 1.0), rtol=0, atol=1e-8)
        assert np.all(mode[after] == 1)
    elif expect == "backward":   # -3: reverses at once, J a = -3 + 1
        np.testing.assert_allclose(w[after], -2.0 * (t[after] - 1.0), rtol=0, atol=1e-8)
        assert np.all(mode[after] == -1)
    else:                        # 0.5 < tau0: sticks at phi = 1/2
        assert np.max(np.abs(w[after])) <= 1e-9
        assert np.all(mode[after] == 0)
        # (explicit Euler integrates phi with its O(h) error: h/2 = 5e-4 rad)
        np.testing.assert_allclose(result["inertia.phi"][after], 0.5, rtol=0,
                                   atol=6e-4 if method == "Euler" else 1e-8)
    print(f"\n[case 4] stop at t = 1 with Step({height:g}) at t = 1, {method}: "
          + "; ".join(str(e) for e in result.events[1:]))


def test_time_event_coincides_with_stop_ambiguous_drive():
    """Drive 1.2 between tau0 = 1 and tau0_max = 1.5 exactly when w reaches 0: a knife edge.

    Switched on a moment earlier the drive would keep the inertia sliding
    (1.2 > tau0); a moment later the stopped inertia would be held (1.2 <
    tau0_max).  Both continuations are consistent; the run must produce one
    of them, not a mixture.
    """
    result = run_coincident(1.2, "DOP853", peak=1.5)
    t, w, mode = result.time, result["inertia.w"], result["bearing.mode"]
    after = t > 1.0 + 1e-9
    stuck = np.max(np.abs(w[after])) <= 1e-9 and np.all(mode[after] == 0)
    sliding = (np.allclose(w[after], 0.2 * (t[after] - 1.0), rtol=0, atol=1e-8)
               and np.all(mode[after] == 1))
    assert stuck or sliding
    print(f"\n[case 4] ambiguous drive 1.2 (tau0 1, tau0_max 1.5) at the stop: acausal "
          f"{'sticks' if stuck else 'keeps sliding forward'}")
