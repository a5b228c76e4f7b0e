"""Hard case 11: hard stops with friction — MassWithStopAndFriction sticking at and hitting its stops.

What makes it hard
------------------
A hard stop is an impulse: at the instant the body reaches ``smax - L/2``
(or ``smin + L/2``) its velocity jumps to zero (``when stopped <> 0 then
reinit(s, stop); reinit(v, 0)``), and from then on the body must rest
*against* the stop even though the applied force keeps pushing it there.
The friction state machine carries that contact force: while locked,
``sa`` takes the whole applied force, whatever its size, and starting to
slide into the stop is forbidden (``startForward`` needs ``s < smax - L/2``).
An engine gets this wrong in several ways:

* it integrates a step past the stop before detecting the crossing, so the
  position overshoots and the reinit happens at the wrong time (the impact
  time must be found by the event locator, not by the step size);
* after the reinit, ``s`` sits *exactly* on the relation ``s >= smax - L/2``;
  if the relation is re-evaluated with round-off, ``stopped`` flips back to
  0 and the when-clause fires again and again (chattering), or the mass
  drifts past the stop at a tiny speed;
* a force far above the friction limit pushes into the stop: without the
  stop condition in ``startForward`` the mass would break away *into* the
  stop at every event;
* pulled away from the stop by more than the static limit it must leave,
  with the speed starting from exactly 0, and it must come back and stop
  again as many times as the force says, with no spurious events.

(a) ``test_sticks_at_the_stop_*``: a mass resting at smax, pushed into it by
a force below or far above the friction limit: no event, s exactly at the
stop, v exactly 0.  Slid into the stop by a force above the limit: one
impact, then pressed against the stop with no further event.  Pulled
away by a step force below or above the limit: held, or leaves with the
closed-form motion.  Driven by ``4 + 8 sin(2 pi t)`` (pure Coulomb friction,
f0 = 3): every period it breaks away from the stop, sticks mid-way, breaks
away forward and hits the stop again; all event times and the motion
between them are compared with an exact event-by-event oracle (the motion is
a closed form in each phase; only the phase ends are found by root finding).

(b) ``test_slides_into_the_stop_*``: a mass launched towards a stop against
Coulomb + viscous friction (closed-form s(t)) and against Coulomb + Stribeck
friction (t(v) closed-form, s(v) by quadrature) hits it at a time found by
root finding on the closed form; the reinit must happen at that time to the
integration tolerance, the position must never be beyond the stop (beyond
the relation margin of 1e-10), and afterwards s = stop, v = 0 exactly.

Figures are printed with ``[case 11]`` prefixes (``pytest -s``).
"""

from __future__ import annotations

import math
import time as _time

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from acausal import Model, simulate
from acausal.library.blocks import Constant, Sine, Step
from acausal.library.translational.friction import MassWithStopAndFriction
from acausal.library.translational.sources import Force

FORWARD, STUCK, BACKWARD = 1, 0, -1
#: m = 1 kg, a 0.2 m long body between stops at -1 m and 1 m: its centre moves in [-0.9, 0.9]
GEOMETRY = dict(m=1.0, L=0.2, smin=-1.0, smax=1.0)
S_RIGHT, S_LEFT = 0.9, -0.9
#: pure Coulomb friction 3 N (f0_max = 1.001*3)
COULOMB = dict(F_prop=0.0, F_Coulomb=3.0, F_Stribeck=0.0)
F0_MAX = 3.0 * 1.001


def stop_model(s0, v0, signal=None, **parameters):
    class HardStop(Model):
        """A MassWithStopAndFriction starting at (s0, v0), optionally driven by a force signal."""

        def build(self):
            self.mass = MassWithStopAndFriction(s=dict(start=s0, fixed=True), v=dict(start=v0, fixed=True),
                                                **parameters)
            if signal is not None:
                self.signal = signal
                self.force = Force()
                self.connect(self.signal.y, self.force.f)
                self.connect(self.force.flange, self.mass.flange_a)

    return HardStop()


def timed(model, **options):
    start = _time.perf_counter()
    result = simulate(model, **options)
    return result, _time.perf_counter() - start


def changing_state_events(result):
    return [e for e in result.events if e.kind == "state" and e.changes]


def impacts(result):
    return [e for e in result.events if any(n == "mass.stopped" and old == 0 for n, old, _ in e.changes)]


# --------------------------------------------------------------------------
# (a) sticking at the stop


@pytest.mark.parametrize("method", ["RK45", "Radau", "Euler"])
@pytest.mark.parametrize("F", [2.0, 10.0, 1e4], ids=["below-limit", "above-limit", "far-above"])
def test_sticks_at_the_stop_when_pushed_into_it(F, method):
    result, wall = timed(stop_model(S_RIGHT, 0.0, Constant(k=F), **GEOMETRY, **COULOMB), stop_time=2.0,
                         interval=0.01, method=method, max_step=0.01 if method == "Euler" else None)
    assert result.status == 0, result.message
    assert np.all(result["mass.s"] == S_RIGHT) and np.all(result["mass.v"] == 0)
    assert np.all(result["mass.stopped"] == 1) and np.all(result["mass.mode"] == STUCK)
    assert np.all(result["mass.locked"] == 1)
    np.testing.assert_allclose(result["mass.f"], F, rtol=1e-12)  # friction + stop hold the whole force
    assert [e for e in result.events if e.changes] == []
    print(f"\n[case 11a] F={F:g} pushing into smax, {method}: s - stop = 0, v = 0 in all "
          f"{len(result.time)} rows, 0 events with changes, {result.stats['steps']} steps, {wall:.3f} s")


def test_sticks_at_the_stop_after_sliding_into_it():
    """F = 10 > f0_max from rest at s = 0: a = 7, impact at t = sqrt(2*0.9/7), then pressed against smax."""
    t_impact = math.sqrt(2 * S_RIGHT / 7.0)
    result, wall = timed(stop_model(0.0, 0.0, Constant(k=10.0), **GEOMETRY, **COULOMB), stop_time=3.0,
                         interval=0.001, rtol=1e-8)
    assert result.status == 0, result.message
    (impact,) = impacts(result)
    assert impact.time == pytest.approx(t_impact, abs=1e-9)
    after = result.time > impact.time
    assert np.all(result["mass.s"][after] == S_RIGHT) and np.all(result["mass.v"][after] == 0)
    assert np.all(result["mass.locked"][after] == 1)
    assert not [e for e in changing_state_events(result) if e.time > impact.time]  # no chattering
    overshoot = float(np.max(result["mass.s"]) - S_RIGHT)
    assert overshoot <= 1e-9
    print(f"\n[case 11a] slid into smax under F = 10: impact at {impact.time:.12f} (exact {t_impact:.12f}, "
          f"error {impact.time - t_impact:.1e}), max overshoot {overshoot:.1e} m, "
          f"{len(changing_state_events(result))} state events with changes, none after the impact, {wall:.3f} s")


@pytest.mark.parametrize("pull", [-2.0, -10.0], ids=["held", "leaves"])
def test_sticks_at_the_stop_until_pulled_above_the_limit(pull):
    """Pressed against smax by 10 N, then at t = 1 pulled by `pull`: -2 is held, -10 gives a = -7."""
    result, _ = timed(stop_model(S_RIGHT, 0.0, Step(offset=10.0, height=pull - 10.0, startTime=1.0),
                                 **GEOMETRY, **COULOMB), stop_time=1.5, interval=0.001, rtol=1e-9)
    assert result.status == 0, result.message
    t, s, v = result.time, result["mass.s"], result["mass.v"]
    if pull > -F0_MAX:
        assert np.all(s == S_RIGHT) and np.all(v == 0)
        assert not changing_state_events(result)
        np.testing.assert_allclose(result.final("mass.f"), pull, rtol=1e-12)
    else:
        after = t > 1.0
        a = (pull + 3.0) / 1.0
        np.testing.assert_allclose(v[after], a * (t[after] - 1.0), rtol=0, atol=1e-8)
        np.testing.assert_allclose(s[after], S_RIGHT + a * (t[after] - 1.0) ** 2 / 2, rtol=0, atol=1e-8)
        assert np.all(s[t <= 1.0] == S_RIGHT)
        assert result.final("mass.mode") == BACKWARD and result.final("mass.stopped") == 0


# -- an exact oracle for pure Coulomb friction under F(t) = B + A sin(w t) -----------


class CoulombOracle:
    """Exact motion of a mass m between stops against Coulomb friction F_C (static limit F0_max),
    driven by F(t) = B + A*sin(w*t).

    In each phase the motion is a closed form: stuck (s constant, v = 0) or sliding in
    direction sigma with ``m*v' = F(t) - sigma*F_C``.  The phase ends (breakaway
    |F| > F0_max, v back to 0, arrival at a stop) are roots of closed-form
    functions, bracketed on a 1e-4 s grid and refined with brentq to 1e-15 s.
    At v = 0 the mass sticks if |F| <= F0_max and reverses otherwise; at a stop
    the velocity becomes 0 (plastic impact) and the mass may leave only away
    from the stop.
    """

    def __init__(self, B, A, w, m, F_C, F0_max, s_left, s_right):
        self.B, self.A, self.w, self.m = B, A, w, m
        self.F_C, self.F0_max, self.s_left, self.s_right = F_C, F0_max, s_left, s_right

    def force(self, t):
        return self.B + self.A * np.sin(self.w * t)

    def slide(self, t, t0, s0, sigma):
        """(s, v) at t of a slide from rest at (t0, s0) in direction sigma."""
        B, A, w, m = self.B - sigma * self.F_C, self.A, self.w, self.m
        dt = t - t0
        v = (B * dt - A / w * (np.cos(w * t) - np.cos(w * t0))) / m
        s = s0 + (B * dt**2 / 2 - A / w * ((np.sin(w * t) - np.sin(w * t0)) / w - np.cos(w * t0) * dt)) / m
        return s, v

    @staticmethod
    def _first_root(g, t0, t1, grid=1e-4):
        ts = np.arange(t0, t1, grid)
        values = g(ts)  # g is vectorised
        crossings = np.flatnonzero(np.sign(values[:-1]) != np.sign(values[1:]))
        if crossings.size == 0:
            return None
        k = crossings[0]
        return brentq(g, ts[k], ts[k + 1], xtol=1e-15, rtol=4 * np.finfo(float).eps)

    def run(self, s0, t_end):
        """Phases (t_start, t_end, s_start, sigma) with sigma = 0 for stuck, and events (time, kind)."""
        phases, events = [], []
        t, s, sigma = 0.0, s0, 0
        while t < t_end:
            if sigma == 0:  # stuck: at a stop or in between
                at = 1 if s >= self.s_right else -1 if s <= self.s_left else 0
                candidates = []
                if at != 1:
                    candidates.append((self._first_root(lambda x: self.force(x) - self.F0_max, t + 1e-12, t_end), 1))
                if at != -1:
                    candidates.append((self._first_root(lambda x: self.force(x) + self.F0_max, t + 1e-12, t_end),
                                       -1))
                candidates = [c for c in candidates if c[0] is not None]
                if not candidates:
                    phases.append((t, t_end, s, 0))
                    break
                t_next, direction = min(candidates)
                phases.append((t, t_next, s, 0))
                events.append((t_next, "breakaway"))
                t, sigma = t_next, direction
            else:  # sliding from rest at (t, s)
                t0, s0_, sg = t, s, sigma
                stop = self.s_right if sg > 0 else self.s_left
                t_zero = self._first_root(lambda x: sg * self.slide(x, t0, s0_, sg)[1], t0 + 1e-9, t_end)
                t_hit = self._first_root(lambda x: sg * (self.slide(x, t0, s0_, sg)[0] - stop), t0 + 1e-9, t_end)
                ends = [(x, kind) for x, kind in ((t_zero, "zero"), (t_hit, "impact")) if x is not None]
                if not ends:
                    phases.append((t0, t_end, s0_, sg))
                    break
                t_next, kind = min(ends)
                phases.append((t0, t_next, s0_, sg))
                if kind == "impact":
                    events.append((t_next, "impact"))
                    t, s, sigma = t_next, stop, 0
                else:
                    s = self.slide(t_next, t0, s0_, sg)[0]
                    F = self.force(t_next)
                    if abs(F) > self.F0_max:  # direct reversal (not needed by the cases below)
                        events.append((t_next, "reversal"))
                        t, sigma = t_next, -sg
                    else:
                        events.append((t_next, "stick"))
                        t, sigma = t_next, 0
        return phases, events

    def evaluate(self, phases, times):
        s, v = np.empty_like(times), np.zeros_like(times)
        for t0, t1, s0, sigma in phases:
            inside = (times >= t0) & (times <= t1)
            if sigma == 0:
                s[inside] = s0
            else:
                s[inside], v[inside] = self.slide(times[inside], t0, s0, sigma)
        return s, v


def simulated_kinds(result):
    """(time, kind) of the events as the oracle names them."""
    found = []
    for e in changing_state_events(result):
        changes = {n: (old, new) for n, old, new in e.changes}
        if "mass.stopped" in changes and changes["mass.stopped"][0] == 0:
            found.append((e.time, "impact"))
        elif changes.get("mass.locked") == (True, False):
            found.append((e.time, "breakaway"))
        elif changes.get("mass.locked") == (False, True):
            found.append((e.time, "stick"))
    return found


@pytest.mark.parametrize("method", ["RK45", "DOP853", "Radau"])
def test_sticks_at_the_stop_under_a_periodic_force(method):
    periods = 5
    oracle = CoulombOracle(B=4.0, A=8.0, w=2 * math.pi, m=1.0, F_C=3.0, F0_max=F0_MAX,
                           s_left=S_LEFT, s_right=S_RIGHT)
    phases, expected = oracle.run(S_RIGHT, float(periods))
    # per period: leave the stop, stick mid-way, break away forward, hit the stop again
    # (the impact of the last period falls after the stop time)
    pattern = ["breakaway", "stick", "breakaway", "impact"]
    assert [kind for _, kind in expected] == (pattern * periods)[:-1]

    result, wall = timed(stop_model(S_RIGHT, 0.0, Sine(amplitude=8.0, f=1.0, offset=4.0), **GEOMETRY, **COULOMB),
                         stop_time=float(periods), interval=0.001, method=method, rtol=1e-10)
    assert result.status == 0, result.message
    found = simulated_kinds(result)
    assert [k for _, k in found] == [k for _, k in expected]
    time_errors = np.array([abs(a - b) for (a, _), (b, _) in zip(found, expected)])
    assert time_errors.max() < 1e-7

    t, s, v = result.time, result["mass.s"], result["mass.v"]
    s_exact, v_exact = oracle.evaluate(phases, t)
    # away from the event instants (where rows hold left and right limits) the motion is the oracle's
    event_times = np.array([x for x, _ in expected])
    away = np.min(np.abs(t[:, None] - event_times[None, :]), axis=1) > 1e-6
    np.testing.assert_allclose(s[away], s_exact[away], rtol=0, atol=1e-8)
    np.testing.assert_allclose(v[away], v_exact[away], rtol=0, atol=1e-7)

    overshoot = float(np.max(s) - S_RIGHT)
    assert overshoot <= 1e-9 and np.min(s) > S_LEFT
    resting = (result["mass.stopped"] == 1) & (result["mass.locked"] == 1)
    assert np.all(s[resting] == S_RIGHT) and np.all(v[resting] == 0)  # no drift while held at the stop
    n_changes = len(changing_state_events(result))
    print(f"\n[case 11a] 4 + 8 sin(2 pi t) against smax, {method}, {periods} periods: {len(found)} of "
          f"{len(expected)} oracle events (breakaway/stick/breakaway/impact per period), max |t - t_exact| "
          f"{time_errors.max():.1e} s, max |s - s_exact| {np.max(np.abs(s - s_exact)[away]):.1e} m, "
          f"max overshoot {overshoot:.1e} m, {n_changes} state events with changes, "
          f"{result.stats['steps']} steps, {wall:.2f} s")


# --------------------------------------------------------------------------
# (b) hitting the stop while sliding


def viscous_coulomb_impact(v0, m, F_C, F_prop, distance):
    """Impact time for m*v' = -F_C - F_prop*v from v0 > 0 over `distance` (None if it stops short)."""
    r, v_inf = F_prop / m, F_C / F_prop

    def position(t):
        return (v0 + v_inf) * (1 - math.exp(-r * t)) / r - v_inf * t

    t_stop = math.log((v0 + v_inf) / v_inf) / r
    if position(t_stop) <= distance:
        return None
    return brentq(lambda t: position(t) - distance, 0.0, t_stop, xtol=1e-16, rtol=4 * np.finfo(float).eps)


def stribeck_impact(v0, m, C, S, k, distance):
    """Impact time for m*v' = -(C + S*exp(-k*v)): t(v) in closed form, s(v) by quadrature."""
    def travelled(v):
        return m * quad(lambda u: u / (C + S * math.exp(-k * u)), v, v0, epsabs=0.0, epsrel=1e-12)[0]

    v_impact = brentq(lambda v: travelled(v) - distance, 0.0, v0, xtol=1e-15)
    return m / (k * C) * math.log((C * math.exp(k * v0) + S) / (C * math.exp(k * v_impact) + S))


CASES = {
    # name: (s0, v0, friction, exact impact time)
    "viscous-right": (0.0, 3.0, dict(F_prop=1.5, F_Coulomb=2.0, F_Stribeck=0.0),
                      viscous_coulomb_impact(3.0, 1.0, 2.0, 1.5, S_RIGHT)),
    "viscous-left": (0.0, -3.0, dict(F_prop=1.5, F_Coulomb=2.0, F_Stribeck=0.0),
                     viscous_coulomb_impact(3.0, 1.0, 2.0, 1.5, S_RIGHT)),
    "stribeck-right": (0.3, 2.5, dict(F_prop=0.0, F_Coulomb=1.0, F_Stribeck=2.0, fexp=1.5),
                       stribeck_impact(2.5, 1.0, 1.0, 2.0, 1.5, S_RIGHT - 0.3)),
}


@pytest.mark.parametrize("method, rtol", [(method, rtol) for method in ("RK45", "DOP853", "Radau", "BDF", "LSODA")
                                          for rtol in (1e-6, 1e-10)] + [("RK4", 1e-6)])
@pytest.mark.parametrize("case", list(CASES))
def test_slides_into_the_stop_and_stays(case, method, rtol):
    s0, v0, friction, t_impact = CASES[case]
    stop = S_RIGHT if v0 > 0 else S_LEFT
    side = 1 if v0 > 0 else -1
    fixed = method == "RK4"  # fixed step h = 1e-3: its error (of order h^4) is below the tolerance
    result, wall = timed(stop_model(s0, v0, **GEOMETRY, **friction), stop_time=1.5, interval=0.001,
                         method=method, rtol=rtol, max_step=1e-3 if fixed else None)
    assert result.status == 0, result.message
    events = changing_state_events(result)
    assert len(events) == 1, [str(e) for e in result.events]
    (impact,) = events
    changes = {n: (old, new) for n, old, new in impact.changes}
    assert changes["mass.stopped"] == (0, side) and changes["mass.mode"] == (side, STUCK)
    assert changes["reinit(mass.v)"][1] == 0.0 and changes["reinit(mass.s)"][1] == stop
    # to the integration tolerance (a 1 s run at speeds of order 1 m/s), plus the time the
    # body needs to pass the relation margin (1e-10 relative to max(1, |s|)) at its impact speed
    v_impact = abs(changes["reinit(mass.v)"][0])
    error = impact.time - t_impact
    assert abs(error) <= 30 * rtol + 1e-10 / v_impact
    t, s, v = result.time, result["mass.s"], result["mass.v"]
    overshoot = float(np.max(side * (s - stop)))
    assert overshoot <= 1e-9  # the left-limit row of the impact is past the stop by the relation margin only
    after = t > impact.time
    # the states stay exactly at the stop; RK4's output rows are cubic Hermite interpolants, which
    # reproduce a constant state only to 1 ulp (engine note in docs/hard-cases-translational.md)
    ulps = 2 * np.spacing(abs(stop)) if fixed else 0.0
    assert np.all(np.abs(s[after] - stop) <= ulps) and np.all(v[after] == 0)
    assert np.all(result["mass.mode"][after] == STUCK) and np.all(result["mass.stopped"][after] == side)
    print(f"\n[case 11b] {case}, {method}, rtol {rtol:g}: impact at {impact.time:.12f} "
          f"(exact {t_impact:.12f}, error {error:.1e} s), "
          f"max overshoot {overshoot:.1e} m, 1 state event with changes, {result.stats['steps']} steps, {wall:.3f} s")
