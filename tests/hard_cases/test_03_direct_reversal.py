"""Hard case 3: direct reversal — Forward -> Backward in one event, with no stuck interval.

What makes it hard
------------------
An inertia sliding forward (w0 = 1) against friction tau0 = 1 with a
constant backward drive of -5 N.m decelerates at (5 + 1)/J, stops at
t* = J*w0/6 and — because the drive exceeds the static limit tau0_max —
immediately slides backward at (5 - 1)/J.  At t* the friction state
machine must go Forward -> (Stuck) -> Backward *within one event
iteration*: the intermediate Stuck mode is only a step of the fixed-point
iteration (``pre(mode)`` Forward gives ``mode = Stuck`` because ``w > 0``
fails; with ``pre(mode)`` Stuck the locked torque ``sa = -5`` exceeds
``-tau0_max`` and ``startBackward`` makes ``mode = Backward``).  An engine
that integrates in between, even for one step, creates a stuck interval of
positive length and a kink in w.

Analytic solution:  w = w0 - (|T| + tau0) t / J  for t < t*,
                    w = -(|T| - tau0)(t - t*) / J  after,
t* = J w0 / (|T| + tau0).

When the drive lies between tau0 and tau0_max (peak > 1) the physical answer
is different: at t* the static friction can hold the drive, so the inertia
must stick (w = 0 afterwards).  The MSL friction equations admit both the
stuck and the reverse-sliding solution of the mixed system at that instant.
acausal used to pick reverse sliding (bug B of docs/hard-cases.md): the
pass with ``pre(mode)`` Stuck started from the previous pass's guess
``locked = False``.  Now, after the pre values change, the event iteration
first re-evaluates the discrete equations that read no relation, so a
just-stopped element is tried locked first, and it sticks
(``test_drive_between_tau0_and_tau0_max_sticks``).
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import Model, simulate
from acausal.library.rotational import BearingFriction, ConstantTorque, Inertia

REST = dict(start=0, fixed=True)
FORWARD, STUCK, BACKWARD = 1, 0, -1
METHODS = ("RK45", "DOP853", "Radau", "Euler", "RK4")


def sliding_against_drive(T, tau0, peak, J, w0):
    class Reversal(Model):
        """An inertia sliding at w0 against BearingFriction(tau0, peak) and a constant drive T."""

        def build(self):
            self.torque = ConstantTorque(tau_constant=T)
            self.inertia = Inertia(J=J, phi=REST, w=dict(start=w0, fixed=True))
            self.bearing = BearingFriction(tau_pos=[[0.0, tau0]], peak=peak)
            self.connect(self.torque.flange, self.inertia.flange_a)
            self.connect(self.inertia.flange_b, self.bearing.flange_a)

    return Reversal()


def run(T, tau0, peak, J, w0, method="DOP853", t_end_factor=3.0):
    t_star = J * abs(w0) / (abs(T) + tau0)
    fixed = method in ("Euler", "RK4")
    result = simulate(sliding_against_drive(T, tau0, peak, J, w0), stop_time=t_end_factor * t_star,
                      interval=t_star / 100, method=method, rtol=1e-10,
                      max_step=t_star / 1000 if fixed else None)
    return result, t_star


def mode_events(result):
    return [e for e in result.events
            if e.kind != "initial" and any(n == "bearing.mode" for n, _, _ in e.changes)]


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("T, tau0, peak, J, w0", [
    (-5.0, 1.0, 1.0, 1.0, 1.0),     # the brief's case
    (-5.0, 1.0, 1.5, 2.0, 1.0),     # with a static peak, still exceeded
    (5.0, 1.0, 1.0, 1.0, -1.0),     # mirrored: Backward -> Forward
    (-5.0, 1.0, 1.0, 1e-6, 1.0),    # tiny inertia: t* = 1.7e-7 s
    (-1.2, 1.0, 1.0, 1.0, 1.0),     # drive just above tau0 = tau0_max
], ids=["brief", "peak1.5", "mirrored", "tinyJ", "just-above"])
def test_direct_reversal_in_one_event(T, tau0, peak, J, w0, method):
    result, t_star = run(T, tau0, peak, J, w0, method)
    assert result.status == 0, result.message
    s = 1.0 if w0 > 0 else -1.0
    first, second = (FORWARD, BACKWARD) if w0 > 0 else (BACKWARD, FORWARD)

    events = mode_events(result)
    assert len(events) == 1, [str(e) for e in result.events]
    (event,) = events
    assert ("bearing.mode", first, second) in event.changes   # net change: one event, 1 -> -1
    assert event.kind == "state"
    # located where w crosses -1e-10 (the hysteresis margin), i.e. 1e-10*J/(|T|+tau0) after t*
    assert abs(event.time - t_star) <= 1e-9 * max(1.0, t_star) + 1e-10 * J / (abs(T) + tau0)

    t, w, mode = result.time, result["inertia.w"], result["bearing.mode"]
    # no stuck interval of positive length: mode 0 never appears in any row
    assert not np.any(mode == STUCK)
    at = np.flatnonzero(t == event.time)
    assert len(at) == 2 and mode[at[0]] == first and mode[at[1]] == second
    assert np.all(mode[t < event.time] == first) and np.all(mode[t > event.time] == second)

    # the analytic motion on both sides
    before, after = t < event.time, t > event.time
    scale = abs(w0)
    np.testing.assert_allclose(w[before], s * (abs(w0) - (abs(T) + tau0) * t[before] / J), rtol=0,
                               atol=1e-8 * scale)
    np.testing.assert_allclose(w[after], -s * (abs(T) - tau0) * (t[after] - t_star) / J, rtol=0,
                               atol=1e-8 * scale)
    print(f"\n[case 3] T={T:g} tau0={tau0:g} peak={peak:g} J={J:g} {method}: event at "
          f"{event.time:.15g} (t* = {t_star:.15g}), {event.iterations} iteration passes, "
          f"changes {event.changes}")


@pytest.mark.parametrize("T", [-0.5, -1.0], ids=["below-tau0", "equal-tau0_max"])
def test_drive_within_the_static_limit_sticks(T):
    """|T| <= tau0_max (peak 1): at t* the inertia sticks for good, w = 0 afterwards."""
    result, t_star = run(T, 1.0, 1.0, 1.0, 1.0)
    assert result.status == 0, result.message
    (event,) = mode_events(result)
    assert ("bearing.mode", FORWARD, STUCK) in event.changes
    t, w = result.time, result["inertia.w"]
    after = t > event.time
    assert np.max(np.abs(w[after])) <= 1e-9
    assert np.all(result["bearing.mode"][after] == STUCK)
    assert result.final("bearing.sa") == pytest.approx(T, abs=1e-12)


@pytest.mark.parametrize("method", ["DOP853", "Radau"])
def test_drive_between_tau0_and_tau0_max_sticks(method):
    """tau0 = 1 < |T| = 1.2 < tau0_max = 1.5: at t* = 1/2.2 the inertia must stick (w = 0 after)."""
    result, t_star = run(-1.2, 1.0, 1.5, 1.0, 1.0, method)
    assert result.status == 0, result.message
    (event,) = mode_events(result)
    print(f"\n[case 3] T=-1.2 tau0=1 peak=1.5: {event}")
    assert ("bearing.mode", FORWARD, STUCK) in event.changes
    after = result.time > event.time
    assert np.max(np.abs(result["inertia.w"][after])) <= 1e-9
