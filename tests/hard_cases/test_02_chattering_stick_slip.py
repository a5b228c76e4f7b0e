"""Hard case 2: chattering-prone stick-slip — a tiny inertia just above breakaway.

What makes it hard
------------------
An inertia of J = 1e-6 kg.m2 on a bearing with Coulomb friction tau0 = 1
N.m is driven by ``1.05*sin(2*pi*t)``: the drive exceeds the static limit
for only ~0.1 s per half period, and the tiny inertia turns every torque
difference into an acceleration a million times larger.  The relative
speed leaves zero and comes back to it steeply, the "waiting" phase between
``startForward`` and ``mode = Forward`` lasts ~1e-8 s, and a solver that
gets the bookkeeping wrong produces runs of zero-length slips (Forward ->
Stuck -> Forward at one instant) or chattering.

What physics gives
------------------
With constant Coulomb friction the speed is ``w(t) = F(t)/J`` with ``F(t) =
A(cos(2 pi t_b) - cos(2 pi t))/(2 pi) - tau0 (t - t_b)`` from the breakaway
``t_b = asin(tau0/A)/(2 pi)`` until ``F`` returns to zero at ``t_s``.  Neither
time depends on J (a tiny J only scales the speed), so the slip does *not*
end when the drive falls below tau0 (at 0.5 - t_b) but later, at t_s =
0.3491 s; at t_s the drive 1.05 sin(2 pi t_s) = 0.86 < tau0 so the inertia
sticks.  By symmetry the backward slip runs from t_b + 0.5 to t_s + 0.5.
So: exactly four mode changes per period (0 -> 1, 1 -> 0, 0 -> -1,
-1 -> 0), every slip lasting t_s - t_b = 0.1484 s, every stick 0.3516 s.

The step-size trap (bug A of docs/hard-cases.md, fixed)
-------------------------------------------------------
While the inertia is stuck every state derivative is exactly zero, so the
adaptive solvers grow the step tenfold per step, and the breakaway relation
``sa > tau0_max`` is true for only ~0.14 s per half period.  When crossing
functions were sampled at 4 points per step, that window fell between the
samples: with the default ``max_step`` RK45, DOP853 and Radau reported no
breakaway at all, BDF and LSODA only some.  acausal now samples them at
least at the output-grid resolution inside a long step, and
``test_default_max_step_finds_every_breakaway`` checks that the default
finds all 20 mode changes.  The detailed test keeps ``max_step=0.01``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from acausal import Model, simulate
from acausal.library.blocks import Sine
from acausal.library.rotational import BearingFriction, Inertia, Torque

REST = dict(start=0, fixed=True)
J, TAU0, A, F_HZ, PERIODS = 1e-6, 1.0, 1.05, 1.0, 5
STOP = PERIODS / F_HZ
OMEGA = 2 * math.pi * F_HZ

T_B = math.asin(TAU0 / A) / OMEGA  # first breakaway (forward)


def F(t):
    """J*w(t) during the first forward slip (closed form of the integral of A sin - tau0)."""
    return A * (math.cos(OMEGA * T_B) - math.cos(OMEGA * t)) / OMEGA - TAU0 * (t - T_B)


T_S = brentq(F, 0.25 / F_HZ, 0.5 / F_HZ, xtol=1e-15)  # the slip ends where F returns to 0
SLIP = T_S - T_B
W_MAX = F(0.5 / F_HZ - T_B) / J  # largest speed: where the drive falls back to tau0

# the expected mode changes: (time, old, new)
EXPECTED = []
for k in range(2 * PERIODS):
    sign = 1 if k % 2 == 0 else -1
    EXPECTED += [(T_B + k * 0.5 / F_HZ, 0, sign), (T_S + k * 0.5 / F_HZ, sign, 0)]


class TinyInertiaStickSlip(Model):
    """1.05 sin(2 pi t) on an inertia J = 1e-6 against BearingFriction(tau0 = 1, peak = 1)."""

    def build(self):
        self.sine = Sine(amplitude=A, f=F_HZ)
        self.torque = Torque()
        self.inertia = Inertia(J=J, phi=REST, w=REST)
        self.bearing = BearingFriction(tau_pos=[[0.0, TAU0]])
        self.connect(self.sine.y, self.torque.tau)
        self.connect(self.torque.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.bearing.flange_a)


def mode_changes(result):
    out = []
    for e in result.events:
        for name, old, new in e.changes:
            if name == "bearing.mode":
                out.append((e.time, old, new))
    return out


def test_physics_premises():
    """The analytic picture used below: the drive at the stop is below tau0, so the inertia sticks."""
    assert abs(A * math.sin(OMEGA * T_S)) < TAU0
    assert 0.5 / F_HZ - T_B < T_S < 0.5 / F_HZ  # the slip outlasts the drive's excess over tau0
    assert SLIP == pytest.approx(0.14842, abs=1e-5)


@pytest.mark.parametrize("method", ["RK45", "DOP853", "Radau", "BDF", "LSODA"])
def test_four_mode_changes_per_period_no_zero_length_slips(method):
    """Exactly 4 mode changes per period at the analytic times; every slip lasts t_s - t_b."""
    result = simulate(TinyInertiaStickSlip(), stop_time=STOP, interval=1e-3, method=method,
                      rtol=1e-8, max_step=0.01)
    assert result.status == 0, result.message
    changes = mode_changes(result)
    assert [(old, new) for _, old, new in changes] == [(old, new) for _, old, new in EXPECTED]
    times = np.array([t for t, _, _ in changes])
    expected = np.array([t for t, _, _ in EXPECTED])
    # the breakaway is a crossing of sa - tau0_max (exact up to the locator); the slip end is a
    # crossing of w through -1e-10 rad/s, which with |dw/dt| ~ 1e5 rad/s2 is 1e-15 s late
    np.testing.assert_allclose(times, expected, rtol=0, atol=1e-6)

    # no zero-length slips and no zero-length sticks: every interval has its analytic length
    slips = times[1::2] - times[0::2]
    sticks = times[2::2] - times[1:-1:2]
    np.testing.assert_allclose(slips, SLIP, rtol=0, atol=2e-6)
    np.testing.assert_allclose(sticks, 0.5 / F_HZ - SLIP, rtol=0, atol=2e-6)
    assert slips.min() > 1e-9 and sticks.min() > 1e-9

    # events are bounded: 4 mode changes per period plus the waiting phase of the first breakaway
    assert len(result.events) <= 1 + 2 * len(EXPECTED)

    # the speed follows w = F(t)/J (mirrored for the backward slips), up to 3282 rad/s
    t, w = result.time, result["inertia.w"]
    for k in range(2 * PERIODS):
        sign = 1 if k % 2 == 0 else -1
        t0 = k * 0.5 / F_HZ
        sel = (t > t0 + T_B + 1e-6) & (t < t0 + T_S - 1e-6)
        exact = sign * np.array([F(s - t0) for s in t[sel]]) / J
        np.testing.assert_allclose(w[sel], exact, rtol=0, atol=1e-5 * W_MAX)
        stuck = (t > t0 + T_S + 1e-6) & (t < t0 + 0.5 / F_HZ + T_B - 1e-6)
        assert np.max(np.abs(w[stuck])) <= 1e-9
    assert np.max(np.abs(w)) == pytest.approx(W_MAX, rel=1e-4)
    print(f"\n[case 2] {method}: {len(result.events)} events, {len(changes)} mode changes in "
          f"{PERIODS} periods ({len(changes) / PERIODS:.0f}/period), shortest slip {slips.min():.6f} s "
          f"(analytic {SLIP:.6f}), max |t_event - t_exact| = {np.max(np.abs(times - expected)):.1e} s, "
          f"max |w| = {np.max(np.abs(w)):.1f} rad/s, {result.stats['steps']} steps, "
          f"{result.stats['simulate_seconds']:.2f} s")


@pytest.mark.parametrize("method", ["RK45", "Radau", "BDF"])
def test_default_max_step_finds_every_breakaway(method):
    """The same run without max_step must find the same 20 mode changes."""
    result = simulate(TinyInertiaStickSlip(), stop_time=STOP, interval=1e-3, method=method, rtol=1e-8)
    assert result.status == 0, result.message
    print(f"\n[case 2] default max_step, {method}: {len(mode_changes(result))} mode changes "
          f"(expected {len(EXPECTED)}), {result.stats['steps']} steps")
    assert len(mode_changes(result)) == len(EXPECTED)
