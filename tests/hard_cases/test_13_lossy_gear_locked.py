"""Hard case 13: a self-locking LossyGear held from both sides, then driven out of the lock.

What makes it hard
------------------
A gear with mesh efficiency 0.5 in both power directions (ratio 2) sits
between two inertias: a drive torque T_a acts on the flange_a side, a load
L on the flange_b side.  Locked, the gear holds the torque ``sa = T_a +
L/ratio`` (the torques its neighbours apply at zero acceleration), and it
stays locked while

    -T_a/eta_mf2 <= L/ratio <= -eta_mf1*T_a    (no bearing friction)

so neither side can drive the other inside a band whose *width depends on
the transmitted torque itself*.  Unlike a bearing, whose static limit is a
constant, the break-away conditions ``sa > tauLossMax_p`` and ``sa <
tauLossMin_m`` compare two algebraic unknowns of the locked mixed system:
the crossing functions are linear in the cut torque ``flange_a.tau``, which
the engine solves for at the acceleration level.  Leaving the lock takes
two events (start, then the speed crossing zero, ``mode`` Stuck -> Forward
or Backward), and the motion starts with zero acceleration (the net torque
passes zero linearly), so the speed grows like (t - t*)^2 and the second
event comes about 1e-5 s after the first.

The driving side decides which efficiency applies.  When the drive falls
below the lower limit, the gear turns *backward* while the drive torque on
flange_a is still positive: the load drives, power flows from flange_b to
flange_a, and the loss is quadrant 4 (``eta_mf2``), not the quadrant a naive
``sign(flange_a.tau)`` rule would pick.  This is the situation the MSL's
2009 fix (Bertsch, ticket #108) made reliable with ``tau_eta``.

Closed forms (J1 on flange_a, J2 on flange_b, w1 = speed of flange_a):

* rolling forward, flange_a driving:
  (J2/ratio + ratio*eta1*J1)*a1 = ratio*eta1*T_a - ratio*tau_bf1 + L
* rolling backward, flange_b driving:
  (J2/ratio + ratio*J1/eta2)*a1 = (ratio/eta2)*T_a + ratio*tau_bf2 + L

With ramps in T_a or L the right-hand side is linear in t and vanishes at
the break-away time t*, so w1 = k*(t - t*)^2/(2*J_eff).  The cases run with
and without bearing friction in the loss table (tau_bf1 = 1, tau_bf2 = 2
moves the limits to eta1*T_a + L/ratio > tau_bf1 and T_a/eta2 + tau_bf2 +
L/ratio < 0).

The third part is MSL LossyGearDemo3, the model that made the pre-2009
LossyGear fail: two equal inertias coast together through a gear whose
bearing friction is split so that ``tau_eta = flange_a.tau - tau_bf_a`` is
*identically zero* while they coast.  Either efficiency gives the same
deceleration, but the relation ``tau_eta >= 0`` sits on a knife edge for
the whole coast, its argument being round-off.  An engine that re-evaluates
it literally in every pass can chatter between the two quadrants; acausal
must stop the pair at the closed-form time and keep it locked afterwards
against a load below the static limit.
"""

from __future__ import annotations

import functools
import math

import numpy as np
import pytest

from acausal import Model, simulate
from acausal.library.blocks import Ramp, Sine, Step
from acausal.library.rotational import Inertia, Torque
from acausal.library.rotational.lossy_gear import LossyGear

REST = dict(start=0, fixed=True)
FORWARD, STUCK, BACKWARD = 1, 0, -1
RATIO, ETA1, ETA2 = 2.0, 0.5, 0.5
J1, J2 = 1.0, 1.5
STOP = 3.0


def held_gear(drive, load, tau_bf=(0.0, 0.0)):
    """Inertia J1 driven by ``drive`` -> LossyGear -> inertia J2 loaded by ``load`` (signal blocks)."""

    class HeldGear(Model):
        def build(self):
            self.drive = drive
            self.load = load
            self.torque1 = Torque()
            self.torque2 = Torque()
            self.inertia1 = Inertia(J=J1, phi=REST, w=REST)
            self.gear = LossyGear(ratio=RATIO, lossTable=[[0, ETA1, ETA2, *tau_bf]])
            self.inertia2 = Inertia(J=J2)
            self.connect(self.drive.y, self.torque1.tau)
            self.connect(self.load.y, self.torque2.tau)
            self.connect(self.torque1.flange, self.inertia1.flange_a)
            self.connect(self.inertia1.flange_b, self.gear.flange_a)
            self.connect(self.gear.flange_b, self.inertia2.flange_a)
            self.connect(self.inertia2.flange_b, self.torque2.flange)

    return HeldGear()


def ramp(value0, slope):
    return Ramp(offset=value0, height=slope * STOP, duration=STOP)


def mode_changes(result):
    return [e for e in result.events if e.kind == "state" and e.changes]


# --------------------------------------------------------------------------
# 1. held from both sides


def test_gear_held_from_both_sides_stays_locked():
    # T_a in [7, 13], L in [-25, -15]: inside [-4*T_a, -T_a] at every instant (margins >= 3 and 2 N.m)
    drive = Sine(amplitude=3.0, f=1.0, offset=10.0)
    load = Sine(amplitude=5.0, f=0.7, offset=-20.0)
    result = simulate(held_gear(drive, load), stop_time=STOP, interval=0.01)
    assert result.success
    assert not mode_changes(result)
    assert np.all(result["gear.mode"] == STUCK) and np.all(result["gear.locked"] == 1)
    assert np.all(result["inertia1.w"] == 0.0) and np.all(result["inertia2.w"] == 0.0)
    t = result.time
    T_a = 10.0 + 3.0 * np.sin(2 * math.pi * t)
    L = -20.0 + 5.0 * np.sin(2 * math.pi * 0.7 * t)  # torque2 applies the load block's output
    assert np.allclose(result["load.y"], L, atol=1e-12)
    holding_error = np.max(np.abs(result["gear.sa"] - (T_a + L / RATIO)))
    assert holding_error < 1e-9
    margin_backward = np.min(L + T_a / ETA2 * RATIO)   # L >= -(ratio/eta2)*T_a
    margin_forward = np.min(-RATIO * ETA1 * T_a - L)   # L <= -ratio*eta1*T_a
    print(f"\n[case 13] held 3 s from both sides: 0 mode changes, w == 0 exactly, margins to the "
          f"limits {margin_backward:.3f} / {margin_forward:.3f} N.m, "
          f"max |sa - (T_a + L/ratio)| = {holding_error:.1e}")
    assert margin_backward > 2.9 and margin_forward > 1.9


# --------------------------------------------------------------------------
# 2. one side leaves the band


def closed_form(drive0, drive_slope, load0, load_slope, tau_bf):
    """(direction, t*, k, J_eff): the break-away and the motion after it, w1 = k (t - t*)^2 / (2 J_eff)."""
    tau_bf1, tau_bf2 = tau_bf
    # forward, flange_a driving: rhs = ratio*eta1*T_a - ratio*tau_bf1 + L
    f0 = RATIO * ETA1 * drive0 - RATIO * tau_bf1 + load0
    f1 = RATIO * ETA1 * drive_slope + load_slope
    # backward, flange_b driving: rhs = (ratio/eta2)*T_a + ratio*tau_bf2 + L
    b0 = RATIO / ETA2 * drive0 + RATIO * tau_bf2 + load0
    b1 = RATIO / ETA2 * drive_slope + load_slope
    assert f0 < 0 < b0, "the gear must start inside its self-locking band"
    t_forward = -f0 / f1 if f1 > 0 else math.inf
    t_backward = -b0 / b1 if b1 < 0 else math.inf
    if t_forward < t_backward:
        return FORWARD, t_forward, f1, J2 / RATIO + RATIO * ETA1 * J1
    return BACKWARD, t_backward, b1, J2 / RATIO + RATIO * J1 / ETA2


CASES = {
    # name: (drive0, drive slope, load0, load slope)
    "drive rises": (10.0, 10.0, -25.0, 0.0),
    "drive falls": (10.0, -5.0, -25.0, 0.0),
    "load eases": (10.0, 0.0, -25.0, 10.0),
    "load grows": (10.0, 0.0, -25.0, -10.0),
}


@functools.lru_cache(maxsize=None)
def run(name, tau_bf, method="RK45"):
    drive0, drive_slope, load0, load_slope = CASES[name]
    model = held_gear(ramp(drive0, drive_slope), ramp(load0, load_slope), tau_bf)
    fixed_step = dict(max_step=1e-3) if method in ("Euler", "RK4") else {}
    return simulate(model, stop_time=STOP, interval=0.01, method=method, rtol=1e-8, **fixed_step)


@pytest.mark.parametrize("tau_bf", [(0.0, 0.0), (1.0, 2.0)], ids=["no bearing", "bearing 1/2"])
@pytest.mark.parametrize("name", list(CASES))
def test_gear_leaves_the_lock_in_the_right_direction_at_the_closed_form_time(name, tau_bf):
    direction, t_star, k, J_eff = closed_form(*CASES[name], tau_bf)
    assert t_star < STOP - 0.5
    result = run(name, tau_bf)
    assert result.success, result.message
    changes = mode_changes(result)
    assert len(changes) == 2, [str(e) for e in changes]
    start, roll = changes
    flag = "gear.startForward" if direction == FORWARD else "gear.startBackward"
    assert (flag, False, True) in start.changes and ("gear.locked", True, False) in start.changes
    assert ("gear.mode", STUCK, direction) in roll.changes
    assert start.time == pytest.approx(t_star, abs=1e-8)
    # the speed passes the relation's hysteresis after sqrt(2*J_eff*eps/|k|)
    delay = roll.time - start.time
    assert 0 < delay < 1e-4

    t, w = result.time, result["inertia1.w"]
    before = t < start.time
    assert np.all(w[before] == 0.0)
    after = t > roll.time
    exact = direction * abs(k) * (t[after] - t_star) ** 2 / (2 * J_eff)
    error = np.max(np.abs(w[after] - exact))
    assert error < 1e-6 * np.max(np.abs(exact))
    assert np.all(result["gear.mode"][after] == direction)
    # the driving side: forward the drive drives (eta_mf1), backward the load drives (eta_mf2),
    # although the drive torque on flange_a stays positive
    assert np.all(result["gear.flange_a.tau"][after] > 0)
    assert np.all(result["gear.tau_etaPos"][after] == 1)
    loss = result["gear.tauLoss"][after]
    tau_a = result["gear.flange_a.tau"][after]
    if direction == FORWARD:
        expected_loss = (1 - ETA1) * tau_a + tau_bf[0]
    else:
        expected_loss = (1 - 1 / ETA2) * tau_a - tau_bf[1]
    assert np.allclose(loss, expected_loss, rtol=1e-9, atol=1e-9)
    print(f"\n[case 13] {name}, tau_bf={tau_bf}: break {'forward' if direction > 0 else 'backward'} at "
          f"t={start.time:.10f} (closed form {t_star:.10f}, error {start.time - t_star:.1e}), "
          f"mode changes {delay:.2e} s later, max |w - w_exact| = {error:.1e} rad/s "
          f"(w(3) = {w[-1]:.6f}), {result.stats['steps']} steps, "
          f"{result.stats['simulate_seconds']:.2f} s")


@pytest.mark.parametrize("method", ["Radau", "DOP853", "RK4"])
def test_break_away_with_other_methods(method):
    # implicit, high-order and fixed-step integrators find the same break-away
    direction, t_star, k, J_eff = closed_form(*CASES["drive falls"], (1.0, 2.0))
    result = run("drive falls", (1.0, 2.0), method)
    assert result.success
    start, roll = mode_changes(result)
    assert start.time == pytest.approx(t_star, abs=1e-8)
    assert result["gear.mode"][-1] == direction
    exact = direction * abs(k) * (STOP - t_star) ** 2 / (2 * J_eff)
    assert result["inertia1.w"][-1] == pytest.approx(exact, rel=1e-5)
    print(f"\n[case 13] drive falls, {method}: break at {start.time:.10f} (closed form {t_star:.10f}), "
          f"w(3) = {result['inertia1.w'][-1]:.8f} (closed form {exact:.8f})")


# --------------------------------------------------------------------------
# 3. the driving side is undetermined (MSL LossyGearDemo3)


def demo3():
    class LossyGearDemo3(Model):
        """Modelica.Mechanics.Rotational.Examples.LossyGearDemo3 (no reference result is published)."""

        def build(self):
            self.gear = LossyGear(ratio=1, lossTable=[[0, 0.25, 0.25, 0.625, 2.5]])
            self.Inertia1 = Inertia(J=0.001, w=dict(start=10))
            self.torque1 = Torque()
            self.torque2 = Torque()
            self.step = Step(height=0)
            self.step1 = Step(startTime=0.5, height=1, offset=0)
            self.Inertia2 = Inertia(J=0.001, phi=REST, w=dict(start=10, fixed=True))
            self.connect(self.Inertia1.flange_b, self.gear.flange_a)
            self.connect(self.torque1.flange, self.Inertia1.flange_a)
            self.connect(self.step.y, self.torque1.tau)
            self.connect(self.gear.flange_b, self.Inertia2.flange_a)
            self.connect(self.Inertia2.flange_b, self.torque2.flange)
            self.connect(self.step1.y, self.torque2.tau)

    return LossyGearDemo3()


@pytest.mark.parametrize("method", ["RK45", "Radau", "RK4"])
def test_coast_with_undetermined_driving_side(method):
    # tau_bf_a = (tau_bf1 - tau_bf2)/(eta1 - 1/eta2) = (0.625 - 2.5)/(0.25 - 4) = 0.5.  Coasting with
    # no torque, J*a = -tau_a on both sides and tau_a = tauLoss/2; quadrant 1 gives
    # 0.75*tau_a + 0.625 = 2*tau_a, quadrant 2 gives -3*tau_a + 2.5 = 2*tau_a: both tau_a = 0.5 =
    # tau_bf_a, so tau_eta = 0 and a = -tau_a/J = -500 rad/s2 either way.  Stop at t* = 10/500.
    # Locked after t = 0.5 under the load 1 N.m: sa = 1 < tauLossMax_p = tau_bf2_0 = 2.5.
    fixed_step = dict(max_step=1e-3) if method == "RK4" else {}
    result = simulate(demo3(), stop_time=1.0, interval=0.001, method=method, **fixed_step)
    assert result.success
    t_star, a = 0.02, -500.0
    changes = [e for e in result.events if e.changes]
    stops = [e for e in changes if ("gear.mode", FORWARD, STUCK) in e.changes]
    assert len(stops) == 1 and stops[0].time == pytest.approx(t_star, abs=1e-9)
    assert len(changes) == 2, [str(e) for e in changes]  # the initial event and the stop
    t, w = result.time, result["Inertia2.w"]
    coasting = t < t_star
    assert np.allclose(w[coasting], 10.0 + a * t[coasting], rtol=1e-9, atol=1e-9)
    tau_eta = result["gear.tau_eta"][coasting]
    assert np.max(np.abs(tau_eta)) < 1e-12
    assert np.allclose(result["gear.flange_a.tau"][coasting], 0.5, rtol=1e-12)
    held = t > 0.5
    assert np.all(result["gear.locked"][held] == 1) and np.all(np.abs(w[held]) < 1e-9)
    assert np.allclose(result["gear.sa"][held], 1.0, rtol=1e-12)
    print(f"\n[case 13] LossyGearDemo3, {method}: tau_eta within {np.max(np.abs(tau_eta)):.1e} of 0 "
          f"while coasting, stop at {stops[0].time:.10f} (closed form 0.02), {len(changes)} events "
          f"with changes, held after the load step (sa = 1 < 2.5)")
