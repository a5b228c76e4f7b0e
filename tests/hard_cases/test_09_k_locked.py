"""Hard case 9: K_locked — a stuck velocity under a fixed-step integrator.

What makes it hard
------------------
The MSL friction elements hold a stuck element at the *acceleration* level
(``a_relfric = 0`` while locked); nothing pulls the velocity itself back to
zero.  Whatever relative speed the element has when it locks stays, and a
fixed-step integrator (explicit Euler here, step 1e-3 s, as on a real-time
target) has no error control to notice.  The project's extension
``K_locked`` replaces the locked equation by ``a_relfric = -K_locked *
w_relfric``, a first-order pull to zero.

Which drift shows in acausal
----------------------------
The round-off drift one might expect (|w| growing step by step because
the locked acceleration comes out as 1e-17 instead of 0) does not occur:
acausal always selects ``w_relfric`` itself as a state and the locked
equation makes its derivative *symbolically* zero, so Euler keeps
``w`` exactly constant — an element that starts stuck keeps w == 0.0 bit
for bit (first test).  The drift that remains comes from the stop: the
stop is located where ``w`` has crossed zero by the relation hysteresis
(``relation_epsilon``, 1e-10 rad/s), so the element locks with that residual
speed.  With K_locked = 0 the residual persists for the whole stuck
interval and the "stuck" inertia creeps: its angle changes by w_res *
(t_end - t_lock).  With K_locked > 0 Euler multiplies w by (1 - K h) each
step, so it decays and the creep is bounded by w_res / K.

K_locked has a limit, too: explicit Euler is unstable for K*h > 2.  Then
the "stuck" velocity grows geometrically until it leaves the hysteresis
band; the element breaks away and locks again within a millisecond, over
and over (a limit cycle with |w| below 1e-3 rad/s).  RK4's stability limit
(~2.79) is higher, so the same K is stable there.  This is documented
behaviour, not a bug being fixed (limitation H of docs/hard-cases.md):
nothing says that K_locked * h is the cause of the spurious events.

Model: J = 1 coasting from w0 = 2 against tau0 = 1 (peak 1.5) with a slowly
varying drive 0.5 sin(2 pi 0.05 t), below the sliding friction all the time,
so after the stop (t ~ 2.45 s) the inertia must stay stuck until t = 10 s.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from acausal import Model, simulate
from acausal.errors import AcausalError
from acausal.library.blocks import Sine
from acausal.library.rotational import BearingFriction, Inertia, Torque

REST = dict(start=0, fixed=True)
H, STOP = 1e-3, 10.0


def coast_and_hold(K, w0=2.0):
    class CoastAndHold(Model):
        def build(self):
            self.sine = Sine(amplitude=0.5, f=0.05)
            self.torque = Torque()
            self.inertia = Inertia(J=1.0, phi=REST, w=dict(start=w0, fixed=True))
            self.bearing = BearingFriction(tau_pos=[[0.0, 1.0]], peak=1.5, K_locked=K)
            self.connect(self.sine.y, self.torque.tau)
            self.connect(self.torque.flange, self.inertia.flange_a)
            self.connect(self.inertia.flange_b, self.bearing.flange_a)

    return CoastAndHold()


@functools.lru_cache(maxsize=None)
def run(K, method="Euler", epsilon=1e-10, w0=2.0):
    return simulate(coast_and_hold(K, w0), stop_time=STOP, interval=0.01, method=method, max_step=H,
                    relation_epsilon=epsilon)


def stuck_phase(result):
    """(lock time, index of the right limit of the lock event, speeds while stuck)."""
    mode = result["bearing.mode"]
    stuck = np.flatnonzero(mode == 0)
    i0 = int(stuck[0])
    return result.time[i0], i0, result["bearing.w"][stuck]


@pytest.mark.parametrize("K", [0.0, 100.0])
def test_starting_stuck_the_speed_stays_exactly_zero(K):
    """Locked from rest: der(w_relfric) is symbolically 0 (or -K*0), so Euler keeps w == 0.0 exactly."""
    result = run(K, w0=0.0)
    assert result.status == 0, result.message
    assert np.all(result["bearing.mode"] == 0)
    assert np.max(np.abs(result["bearing.w"])) == 0.0
    assert np.max(np.abs(result["inertia.phi"])) == 0.0


@pytest.mark.parametrize("epsilon", [1e-10, 1e-6])
def test_k_locked_zero_keeps_the_residual_speed_and_creeps(epsilon):
    result = run(0.0, epsilon=epsilon)
    assert result.status == 0, result.message
    t_lock, i0, w_stuck = stuck_phase(result)
    assert 2.4 < t_lock < 2.5
    assert np.all(result["bearing.mode"][i0:] == 0)        # it stays stuck to the end
    w_res = w_stuck[0]
    # the lock happens once w has crossed zero by the hysteresis margin ...
    assert -1.01 * epsilon < w_res < -0.99 * epsilon
    # ... and with K_locked = 0 that speed never decays: it is the same in every stuck row (up to
    # an ulp: output rows between steps come from the dense-output interpolant)
    np.testing.assert_allclose(w_stuck, w_res, rtol=1e-14, atol=0)
    creep = result["inertia.phi"][-1] - result["inertia.phi"][i0]
    assert creep == pytest.approx(w_res * (STOP - t_lock), rel=1e-6)
    print(f"\n[case 9] K_locked = 0, relation_epsilon {epsilon:g}: locked at {t_lock:.6f} s with "
          f"w = {w_res:.3e} rad/s; max |w| while stuck {np.max(np.abs(w_stuck)):.3e}; the stuck "
          f"inertia crept {creep:.3e} rad by t = {STOP:g} s")


@pytest.mark.parametrize("epsilon", [1e-10, 1e-6])
@pytest.mark.parametrize("K", [1.0, 100.0, 1999.0])
def test_k_locked_positive_pulls_the_speed_to_zero(K, epsilon):
    reference = run(0.0, epsilon=epsilon)
    result = run(K, epsilon=epsilon)
    assert result.status == 0, result.message
    t_lock, i0, w_stuck = stuck_phase(result)
    assert np.all(result["bearing.mode"][i0:] == 0)
    w_res = w_stuck[0]
    # never larger than at the lock, and decayed by (1 - K h)^n: to below 1e-3 of it by the end
    assert np.max(np.abs(w_stuck)) == pytest.approx(abs(w_res), rel=1e-12)
    n_steps = (STOP - t_lock) / H
    bound = abs(w_res) * max(abs(1 - K * H) ** (n_steps - 1), 1e-300)
    assert abs(w_stuck[-1]) <= max(bound * 1.01, 1e-300)
    assert abs(w_stuck[-1]) < 1e-3 * abs(w_res)
    # the creep is bounded by w_res / K (the geometric series of the decaying speed; for K h
    # near 2 the partial sums alternate around it), up to the round-off of phi ~ 4.7 rad itself
    phi = result["inertia.phi"]
    creep = phi[-1] - phi[i0]
    assert abs(creep) <= abs(w_res) / K * 1.01 + 16 * np.spacing(phi[-1])
    _, j0, _ = stuck_phase(reference)
    creep0 = reference["inertia.phi"][-1] - reference["inertia.phi"][j0]
    assert abs(creep) < abs(creep0)
    print(f"\n[case 9] K_locked = {K:g} (K h = {K * H:g}), eps {epsilon:g}: w {w_res:.2e} -> "
          f"{w_stuck[-1]:.2e} rad/s, creep {creep:.2e} rad (K_locked = 0: {creep0:.2e})")


def test_k_locked_too_large_for_euler_makes_the_stuck_speed_grow():
    """K h = 2.1 > 2: explicit Euler amplifies w by |1 - K h| = 1.1 per step while 'stuck'.

    The speed grows until it leaves the hysteresis band; the element then breaks
    away (its breakaway torque is met: pre(startForward) keeps it sliding, as in
    Modelica's event iteration) and stops again within a millisecond, again and
    again: a limit cycle that keeps |w| small, instead of a stuck inertia."""
    K = 2100.0
    result = run(K)
    _, _, w_stuck = stuck_phase(result)
    w_res = w_stuck[0]
    assert np.max(np.abs(w_stuck)) > 1e3 * abs(w_res)   # grows instead of decaying
    assert result.status == 0, result.message
    after = result.time > 2.5
    assert np.max(np.abs(result["inertia.w"][after])) < 1e-2   # bounded by the lock/slip cycle
    locks = [e for e in result.events if ("bearing.mode", 1, 0) in e.changes]
    assert len(locks) > 10                                    # the cycle shows as spurious events
    # the same K is stable for RK4 (stability limit ~2.79 > K h): one lock, then stuck
    rk4 = run(K, method="RK4")
    assert rk4.status == 0, rk4.message
    _, _, w_rk4 = stuck_phase(rk4)
    assert abs(w_rk4[-1]) < 1e-3 * abs(w_rk4[0])
    assert len([e for e in rk4.events if ("bearing.mode", 1, 0) in e.changes]) == 1
    print(f"\n[case 9] K_locked = {K:g} with Euler h = {H:g}: |w| grew from {abs(w_res):.1e} to "
          f"{np.max(np.abs(w_stuck)):.1e} rad/s while stuck, then {len(locks)} lock/slip cycles with "
          f"|w| <= {np.max(np.abs(result['inertia.w'][after])):.1e}; RK4 with the same K: w -> {w_rk4[-1]:.1e}")