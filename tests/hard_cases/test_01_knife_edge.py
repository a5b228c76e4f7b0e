"""Hard case 1: the knife edge — a holding torque that touches the static limit exactly.

What makes it hard
------------------
A stuck friction element starts sliding when its holding torque ``sa``
exceeds ``tau0_max`` (``sa > tau0_max``, strictly).  In
ModelicaTest.Rotational.ForUsersGuide.SupportTorque1 (spec section 6.3) the
whole input torque ``sin(2*pi*t)`` reaches the locked bearing, whose static
limit is exactly 1: the relation function ``sa - tau0_max`` touches zero at
t = 0.25 (and its mirror at t = 0.75) without crossing it.  Mathematically
nothing ever moves and Dymola reports no state event, but a root finder
that looks at ``g <= 0 -> g >= 0`` sign changes, or an evaluation that is one
ulp high, starts a slip.  The same holds for a constant torque exactly
equal to ``tau0`` with ``peak = 1``, and it gets worse when the torque
reaches the bearing through arithmetic that rounds *up*: with a gear of
ratio 3 and an amplitude of 0.1 the bearing sees ``3*0.1 =
0.30000000000000004 > 0.3``, one ulp above its limit.

What acausal does
-----------------
Relations get a relative hysteresis (``relation_epsilon``, 1e-10): a relation
flips only when its argument passes zero by that margin, so touching the
limit (or exceeding it by round-off) is not a crossing.  Initialization
uses the same margin (|g| within it counts as g = 0): it used to evaluate
relations exactly, so a torque one ulp above the limit that was present
from t = 0 started a slip at the initial event (bug C of
docs/hard-cases.md, fixed; ``test_torque_one_ulp_above_tau0_from_the_start_does_not_move``).

Every expected value here is analytic: while locked ``a = 0``, so the
bearing holds exactly the applied torque and every speed stays 0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from acausal import Model, simulate
from acausal.library.blocks import Sine, Step
from acausal.library.rotational import BearingFriction, ConstantTorque, Fixed, IdealGear, Inertia, Torque

REST = dict(start=0, fixed=True)
STUCK = 0
ALL_METHODS = ("RK45", "DOP853", "Radau", "BDF", "LSODA", "Euler", "RK4")


def support_torque1(amplitude=1.0, tau0=1.0, J3=1.0, J4=1.0, ratio=1.0):
    """ModelicaTest.Rotational.ForUsersGuide.SupportTorque1, optionally rescaled.

    With the defaults it is the MSL test model: sine2 Sine(f=1) ->
    Torque(useSupport) -> inertia3 (J=1, phi/w fixed 0) -> IdealGear(ratio=1,
    useSupport) -> BearingFriction(useSupport) -> inertia4 (J=1), every support
    on one Fixed.
    """

    class SupportTorque1(Model):
        modelica_class = "ModelicaTest.Rotational.ForUsersGuide.SupportTorque1"

        def build(self):
            self.sine2 = Sine(f=1, amplitude=amplitude)
            self.torque2 = Torque(useSupport=True)
            self.fixed1 = Fixed()
            self.inertia3 = Inertia(J=J3, phi=REST, w=REST)
            self.idealGear2 = IdealGear(ratio=ratio, useSupport=True)
            self.inertia4 = Inertia(J=J4)
            self.bearingFriction1 = BearingFriction(useSupport=True, tau_pos=[[0.0, tau0]])
            self.connect(self.sine2.y, self.torque2.tau)
            self.connect(self.torque2.support, self.fixed1.flange)
            self.connect(self.torque2.flange, self.inertia3.flange_a)
            self.connect(self.fixed1.flange, self.idealGear2.support)
            self.connect(self.inertia3.flange_b, self.idealGear2.flange_a)
            self.connect(self.idealGear2.flange_b, self.bearingFriction1.flange_a)
            self.connect(self.bearingFriction1.flange_b, self.inertia4.flange_a)
            self.connect(self.fixed1.flange, self.bearingFriction1.support)

    return SupportTorque1()


def assert_nothing_moved(result, speeds, angles, mode_name):
    assert result.status == 0, result.message
    state_events = [e for e in result.events if e.kind == "state"]
    assert not state_events, [str(e) for e in state_events]
    assert not [e for e in result.events if e.changes], [str(e) for e in result.events]
    assert np.all(result[mode_name] == STUCK)
    for name in speeds + angles:
        assert np.max(np.abs(result[name])) == 0.0, name


def _fixed_step(method):
    return 1e-3 if method in ("Euler", "RK4") else None


@pytest.mark.parametrize("method", ALL_METHODS)
def test_support_torque1_never_starts_sliding(method):
    """sa = sin(2 pi t) touches tau0_max = 1 at t = 0.25 and -1 at 0.75: 0 mode changes, w == 0."""
    result = simulate(support_torque1(), stop_time=1.1, interval=1e-3, method=method,
                      max_step=_fixed_step(method))
    assert_nothing_moved(result, ["inertia3.w", "inertia4.w"], ["inertia3.phi", "inertia4.phi"],
                         "bearingFriction1.mode")
    assert np.all(result["bearingFriction1.startForward"] == 0)
    assert np.all(result["bearingFriction1.startBackward"] == 0)
    t, sa = result.time, result["bearingFriction1.sa"]
    # locked: a = 0, so the bearing holds exactly the input torque
    np.testing.assert_allclose(sa, np.sin(2 * np.pi * t), rtol=0, atol=1e-12)
    # ... and the knife edge really is touched (the grid contains 0.25 and 0.75)
    i_top, i_bottom = np.argmin(np.abs(t - 0.25)), np.argmin(np.abs(t - 0.75))
    assert abs(t[i_top] - 0.25) < 1e-12 and abs(t[i_bottom] - 0.75) < 1e-12
    assert sa[i_top] == pytest.approx(1.0, abs=1e-15)
    assert sa[i_bottom] == pytest.approx(-1.0, abs=1e-15)
    print(f"\n[case 1] SupportTorque1 {method}: {len(result.events)} event(s), "
          f"{sum(1 for e in result.events if e.changes)} with changes, max sa = {np.max(sa):.17g}, "
          f"max |w4| = {np.max(np.abs(result['inertia4.w'])):.1e}, "
          f"{result.stats['steps']} steps, {result.stats['simulate_seconds']:.3f} s")


@pytest.mark.parametrize("amplitude, tau0, J3, J4, ratio", [
    (2.5, 2.5, 3.0, 0.5, 1.0),      # other scale and inertias
    (1 / 3, 1.0, 2.0, 5.0, 3.0),    # 3*(1/3) rounds to exactly 1.0
    (0.1, 0.3, 1.0, 1.0, 3.0),      # 3*0.1 = 0.30000000000000004: one ulp ABOVE tau0_max
], ids=["scaled", "gear-exact", "gear-one-ulp-above"])
def test_knife_edge_after_a_gear(amplitude, tau0, J3, J4, ratio):
    """amplitude*ratio == tau0 mathematically: the bearing must stay stuck even when round-off overshoots."""
    result = simulate(support_torque1(amplitude, tau0, J3, J4, ratio), stop_time=1.1, interval=1e-3)
    assert_nothing_moved(result, ["inertia3.w", "inertia4.w"], ["inertia3.phi", "inertia4.phi"],
                         "bearingFriction1.mode")
    sa = result["bearingFriction1.sa"]
    np.testing.assert_allclose(sa, amplitude * ratio * np.sin(2 * np.pi * result.time), rtol=0,
                               atol=1e-12)
    overshoot = np.max(sa) - tau0
    assert overshoot >= -1e-15  # the limit is reached (or passed by round-off), never missed
    print(f"\n[case 1] knife edge after gear ratio {ratio}: max sa - tau0_max = {overshoot:.3g}, "
          f"no event")


def constant_torque(T, tau0, J, peak=1.0):
    class ConstantAgainstFriction(Model):
        def build(self):
            self.torque = ConstantTorque(tau_constant=T)
            self.inertia = Inertia(J=J, phi=REST, w=REST)
            self.bearing = BearingFriction(tau_pos=[[0.0, tau0]], peak=peak)
            self.connect(self.torque.flange, self.inertia.flange_a)
            self.connect(self.inertia.flange_b, self.bearing.flange_a)

    return ConstantAgainstFriction()


@pytest.mark.parametrize("method", ["RK45", "Radau", "Euler"])
@pytest.mark.parametrize("T, tau0, J", [
    (1.0, 1.0, 1.0), (1.0, 1.0, 2.0), (1.0, 1.0, 1e-6), (1.0, 1.0, 1e6), (7.3, 7.3, 0.37),
    (-1.0, 1.0, 1.0),
], ids=["unit", "J2", "J1e-6", "J1e6", "7.3", "negative"])
def test_constant_torque_exactly_tau0_peak1_does_not_move(T, tau0, J, method):
    """peak = 1 and |T| == tau0: a resting inertia stays at rest (no event, sa == T, w == 0)."""
    result = simulate(constant_torque(T, tau0, J), stop_time=2.0, interval=0.01, method=method,
                      max_step=1e-2 if method == "Euler" else None)
    assert_nothing_moved(result, ["inertia.w"], ["inertia.phi"], "bearing.mode")
    np.testing.assert_allclose(result["bearing.sa"], T, rtol=0, atol=1e-12)


def stepped_torque(T, tau0, J, t_step):
    class SteppedAgainstFriction(Model):
        def build(self):
            self.step = Step(height=T, startTime=t_step)
            self.torque = Torque()
            self.inertia = Inertia(J=J, phi=REST, w=REST)
            self.bearing = BearingFriction(tau_pos=[[0.0, tau0]])
            self.connect(self.step.y, self.torque.tau)
            self.connect(self.torque.flange, self.inertia.flange_a)
            self.connect(self.inertia.flange_b, self.bearing.flange_a)

    return SteppedAgainstFriction()


ONE_ULP = [(0.1 + 0.2, 0.3), (-(0.1 + 0.2), 0.3)]  # |0.1 + 0.2| = 0.30000000000000004 > 0.3


@pytest.mark.parametrize("T, tau0", ONE_ULP, ids=["above", "below-negative"])
def test_torque_one_ulp_above_tau0_arriving_during_the_run_does_not_move(T, tau0):
    """|T| = 0.1 + 0.2 against tau0 = 0.3, switched on at t = 0.5 by a Step: round-off starts no slip."""
    result = simulate(stepped_torque(T, tau0, 3.0, 0.5), stop_time=2.0, interval=0.01)
    assert result.status == 0, result.message
    assert not [e for e in result.events if e.changes], [str(e) for e in result.events]
    assert np.all(result["bearing.mode"] == STUCK)
    assert np.max(np.abs(result["inertia.w"])) == 0.0
    t, sa = result.time, result["bearing.sa"]
    away = t != 0.5  # the event instant has two rows: 0 (left limit) and T (right limit)
    assert np.all(sa[away] == np.where(t[away] < 0.5, 0.0, T))
    assert list(sa[t == 0.5]) == [0.0, T]


@pytest.mark.parametrize("T, tau0", ONE_ULP, ids=["above", "below-negative"])
def test_torque_one_ulp_above_tau0_from_the_start_does_not_move(T, tau0):
    """The same one-ulp knife edge as above, with the torque present from t = 0 (ConstantTorque)."""
    result = simulate(constant_torque(T, tau0, 3.0), stop_time=2.0, interval=0.01)
    assert result.status == 0, result.message
    assert not [e for e in result.events if e.changes], [str(e) for e in result.events]
    assert np.all(result["bearing.locked"] == 1)


def test_control_torque_clearly_above_tau0_does_move():
    """Not vacuous: a torque 1e-6 (relative) above the limit breaks away at t = 0, w = (T - tau0) t / J."""
    T, tau0, J = 1.0 + 1e-6, 1.0, 1.0
    result = simulate(constant_torque(T, tau0, J), stop_time=2.0, interval=0.01, method="DOP853",
                      rtol=1e-10)
    assert result.status == 0, result.message
    t, w = result.time, result["inertia.w"]
    np.testing.assert_allclose(w, (T - tau0) * t / J, rtol=0, atol=1e-12)
    assert result.final("bearing.mode") == 1
    assert math.isclose(result.final("inertia.w"), 2e-6, rel_tol=1e-6)
