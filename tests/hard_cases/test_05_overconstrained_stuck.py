"""Hard case 5: an over-constrained stuck mode — two friction elements locking one rigid shaft.

What makes it hard
------------------
Two BearingFrictions (or a bearing and a Brake) on one rigid shaft are fine
while they slide: each contributes its sliding torque.  When both are stuck,
each imposes ``a = 0`` on the same motion and the split of the holding
torque between them (``sa1 + sa2 = drive``) is undetermined: the system of
that discrete state is structurally singular.  The mode is only known at
run time — it may be the initial one or be reached after seconds of
sliding — and the engine must stop with a message that names the discrete
state and both elements, not with a KeyError, an IndexError, a
ZeroDivisionError or a LinAlgError from deep inside.

What acausal does
-----------------
By default, as Modelica tools do, it picks a split: in the stuck-stuck
state one of the two constraints is left out and one element's share of the
holding torque is set to zero (``relax_redundant``), with a
RedundantConstraintWarning that names both.  The physics that the split does
not decide is then checked:

* the shaft stays at rest while the drive is below the combined static limit
  ``tau1 + tau2`` (whatever the split, the element that gets too much starts
  sliding at its limit and the other holds the rest), and breaks away with
  ``a = (T - tau1 - tau2)/J`` above it;
* sliding first, both stop at the analytic ``t* = J|w0|/(tau1 + tau2 -+ T)``
  and stay stopped;
* the holding torques add up to the drive (the torque balance of the shaft).

With ``redundant_constraints="error"`` the state is refused instead:

* both stuck at the start: ``simulate`` raises StructurallySingularError
  (a StructuralError, a ValueError) naming the discrete state
  (``bf1.locked=True, bf2.locked=True``), the equations of both elements and a
  friction-specific hint: put a compliance (SpringDamper) between the
  elements or merge them into one.  (It used to recommend "an inertia or a
  compliance", but an inertia is rigid: bf1 -> inertia -> bf2 is still
  singular — bug E of docs/hard-cases.md, fixed.)
* sliding first: the run returns ``status == -1`` with a SolverError whose
  message gives the time (the analytic stop t* = J w0 / (tau1 + tau2)) and the
  same diagnosis, and the result keeps everything up to t*.  The hint is
  stated once (it used to appear twice in this message — bug F, fixed).
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

from acausal import Model, simulate
from acausal.errors import (
    AcausalError,
    RedundantConstraintWarning,
    SolverError,
    StructuralError,
    StructurallySingularError,
)
from acausal.library.blocks import Constant
from acausal.library.rotational import BearingFriction, Brake, ConstantTorque, Inertia

REST = dict(start=0, fixed=True)
TAU1, TAU2, J = 1.0, 2.0, 1.0
#: refuse the stuck-stuck state instead of picking a split of the holding torque
STRICT = dict(redundant_constraints="error")


def two_bearings(w0, T=0.0, inertia_between=False):
    class TwoBearingsOneShaft(Model):
        """inertia -> bf1 -> bf2 (optionally bf1 -> inertia2 -> bf2): one rigid shaft."""

        def build(self):
            self.torque = ConstantTorque(tau_constant=T)
            self.inertia = Inertia(J=J, phi=REST, w=dict(start=w0, fixed=True))
            self.bf1 = BearingFriction(tau_pos=[[0.0, TAU1]])
            self.bf2 = BearingFriction(tau_pos=[[0.0, TAU2]])
            self.connect(self.torque.flange, self.inertia.flange_a)
            self.connect(self.inertia.flange_b, self.bf1.flange_a)
            if inertia_between:
                self.inertia2 = Inertia(J=1.0)
                self.connect(self.bf1.flange_b, self.inertia2.flange_a)
                self.connect(self.inertia2.flange_b, self.bf2.flange_a)
            else:
                self.connect(self.bf1.flange_b, self.bf2.flange_a)

    return TwoBearingsOneShaft()


class BearingAndBrake(Model):
    """A BearingFriction and an engaged Brake on one shaft, coasting from w0 = 2."""

    def build(self):
        self.inertia = Inertia(J=J, phi=REST, w=dict(start=2.0, fixed=True))
        self.bf = BearingFriction(tau_pos=[[0.0, 1.0]])
        self.brake = Brake(fn_max=2.0)  # tau0 = mu 0.5 * cgeo 1 * fn 2 = 1 N.m
        self.one = Constant(k=1.0)
        self.connect(self.one.y, self.brake.f_normalized)
        self.connect(self.inertia.flange_b, self.bf.flange_a)
        self.connect(self.bf.flange_b, self.brake.flange_a)


def assert_clear_diagnosis(text, first="bf1", second="bf2"):
    for element in (first, second):
        assert f"{element}.locked=True" in text      # the discrete state
        assert f"{element} (" in text                 # the element's equations are listed
    assert "structurally singular" in text
    assert "hint:" in text and "friction" in text and "stuck" in text
    for raw in ("Traceback", "KeyError", "IndexError", "ZeroDivisionError", "LinAlgError"):
        assert raw not in text


@pytest.mark.parametrize("T", [0.0, 0.5, 5.0], ids=["no-drive", "small-drive", "large-drive"])
def test_both_stuck_at_start_raises_structurally_singular(T):
    with pytest.raises(StructurallySingularError) as info:
        simulate(two_bearings(0.0, T), stop_time=1.0, **STRICT)
    error = info.value
    assert isinstance(error, StructuralError) and isinstance(error, ValueError)
    assert_clear_diagnosis(str(error))
    assert "holding torque" in error.hint
    print(f"\n[case 5] both stuck at t = 0 (drive {T:g}): {type(error).__name__}: "
          f"{str(error).splitlines()[0][:160]}...")


@pytest.mark.parametrize("w0, T", [(3.0, 0.0), (3.0, 1.0), (-3.0, 0.0)])
@pytest.mark.parametrize("method", ["RK45", "Radau"])
def test_sticking_mid_run_stops_with_reason_and_partial_result(w0, T, method):
    """Sliding at w0, decelerated by tau1 + tau2 (+ drive): both stick at t* = J|w0|/(tau1 + tau2 -+ T)."""
    s = np.sign(w0)
    decel = TAU1 + TAU2 - s * T
    t_star = J * abs(w0) / decel
    result = simulate(two_bearings(w0, T), stop_time=2 * t_star, interval=t_star / 50, method=method,
                      rtol=1e-10, **STRICT)
    assert result.status == -1
    assert isinstance(result.error, SolverError) and isinstance(result.error, AcausalError)
    assert result.error.result is result
    assert result.message == str(result.error)
    assert_clear_diagnosis(result.message)
    # the time named is the stop, analytically t* = J |w0| / (tau1 + tau2 -+ T)
    named = re.search(r"at t = ([-+0-9.eE]+) ", result.message)
    assert named and float(named.group(1)) == pytest.approx(t_star, abs=1e-9)
    # the partial result: the analytic deceleration up to the failure
    t, w = result.time, result["inertia.w"]
    assert t[-1] == pytest.approx(t_star, abs=1e-9)
    ok = t < t_star
    np.testing.assert_allclose(w[ok], s * (abs(w0) - decel * t[ok] / J), rtol=0, atol=1e-8)
    print(f"\n[case 5] both stick mid-run ({method}, w0={w0:g}, T={T:g}): status {result.status}, "
          f"last row t = {t[-1]:.12g} (t* = {t_star:.12g}); {result.message.splitlines()[0][:100]}...")


def test_bearing_and_brake_on_one_shaft():
    result = simulate(BearingAndBrake(), stop_time=2.0, interval=0.02, rtol=1e-10, **STRICT)
    assert result.status == -1 and isinstance(result.error, SolverError)
    assert_clear_diagnosis(result.message, "bf", "brake")
    assert result.time[-1] == pytest.approx(1.0, abs=1e-9)  # 2 rad/s at (1 + 1) N.m / 1 kg.m2


def test_an_inertia_between_the_bearings_is_still_one_rigid_shaft():
    """Physics: an inertia is rigid, so bf1 -> inertia -> bf2 locked together is still singular."""
    with pytest.raises(StructurallySingularError) as info:
        simulate(two_bearings(0.0, 0.0, inertia_between=True), stop_time=1.0, **STRICT)
    assert_clear_diagnosis(str(info.value))


def test_hint_does_not_recommend_an_inertia():
    with pytest.raises(StructurallySingularError) as info:
        simulate(two_bearings(0.0, 0.0), stop_time=1.0, **STRICT)
    assert "inertia" not in info.value.hint


def test_mid_run_message_states_the_hint_once():
    result = simulate(two_bearings(3.0), stop_time=2.0, **STRICT)
    assert result.message.count("hint:") == 1


# ---------------------------------------------------------------------------
# The default: a split is picked, and the physics it does not decide holds
# ---------------------------------------------------------------------------

def simulate_relaxed(model, **options):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = simulate(model, **options)
    return result, [w for w in caught if issubclass(w.category, RedundantConstraintWarning)]


@pytest.mark.parametrize("T", [0.0, 0.5, -0.5, 2.5, -2.9])
def test_both_stuck_below_the_combined_limit_stay_at_rest(T):
    """|T| < tau1 + tau2: the shaft does not move, and the elements hold the drive between them."""
    result, _ = simulate_relaxed(two_bearings(0.0, T), stop_time=2.0, interval=0.01, rtol=1e-10)
    assert result.status == 0, result.message
    assert np.max(np.abs(result["inertia.w"])) <= 1e-9
    assert np.max(np.abs(result["inertia.phi"])) <= 1e-9
    # torque balance of the shaft at rest: the friction torques hold the drive
    held = result["bf1.tau"] + result["bf2.tau"]
    np.testing.assert_allclose(held, T, atol=1e-9)
    # and neither exceeds its static limit
    assert np.max(np.abs(result["bf1.tau"])) <= TAU1 + 1e-9
    assert np.max(np.abs(result["bf2.tau"])) <= TAU2 + 1e-9


def test_the_split_is_named_in_a_warning():
    result, caught = simulate_relaxed(two_bearings(0.0, 0.5), stop_time=1.0, cache=False)
    assert result.status == 0
    assert len(caught) == 1
    text = str(caught[0].message)
    assert "bf1.locked=True" in text and "bf2.locked=True" in text   # the discrete state
    first, *details = text.splitlines()
    assert re.match(r"bf[12]: ", first)                                # the components first
    assert any(re.fullmatch(r"  left out: bf[12] \(PartialFriction eq\. \d+\)", line) for line in details)
    assert any(re.match(r"  set to 0: bf[12]\.\S+ ", line) for line in details)
    assert "redundant_constraints='error'" in text                    # how to refuse instead


def test_both_stuck_above_the_combined_limit_break_away():
    """T = 5 > tau1 + tau2 = 3: both slide at once, a = (T - tau1 - tau2)/J = 2."""
    T = 5.0
    result, _ = simulate_relaxed(two_bearings(0.0, T), stop_time=2.0, interval=0.01, rtol=1e-10)
    assert result.status == 0, result.message
    t, w = result.time, result["inertia.w"]
    np.testing.assert_allclose(w, (T - TAU1 - TAU2) / J * t, atol=1e-7)


@pytest.mark.parametrize("w0, T", [(3.0, 0.0), (3.0, 1.0), (-3.0, 0.0)])
@pytest.mark.parametrize("method", ["RK45", "Radau"])
def test_sticking_mid_run_stays_stuck(w0, T, method):
    """Sliding at w0: both stick at t* = J|w0|/(tau1 + tau2 -+ T) and stay at rest."""
    s = np.sign(w0)
    decel = TAU1 + TAU2 - s * T
    t_star = J * abs(w0) / decel
    result, caught = simulate_relaxed(two_bearings(w0, T), stop_time=2 * t_star, interval=t_star / 50,
                                      method=method, rtol=1e-10)
    assert result.status == 0, result.message
    stops = [e for e in result.events if ("bf1.mode", s, 0) in e.changes]
    assert len(stops) == 1 and stops[0].time == pytest.approx(t_star, abs=1e-9)
    assert ("bf2.mode", s, 0) in stops[0].changes
    t, w = result.time, result["inertia.w"]
    before, after = t < t_star, t > t_star + 1e-6
    np.testing.assert_allclose(w[before], s * (abs(w0) - decel * t[before] / J), rtol=0, atol=1e-8)
    assert np.max(np.abs(w[after])) <= 1e-9
    np.testing.assert_allclose((result["bf1.tau"] + result["bf2.tau"])[after], T, atol=1e-9)
    assert len(caught) <= 1  # compiled once (none when an earlier test compiled it)


def test_bearing_and_brake_stop_together_and_stay():
    """2 rad/s against (1 + 1) N.m on 1 kg.m2: stop at t = 1 s, then rest."""
    result, _ = simulate_relaxed(BearingAndBrake(), stop_time=2.0, interval=0.02, rtol=1e-10)
    assert result.status == 0, result.message
    t, w = result.time, result["inertia.w"]
    np.testing.assert_allclose(w[t < 1.0], 2.0 - 2.0 * t[t < 1.0], atol=1e-8)
    assert np.max(np.abs(w[t > 1.0])) <= 1e-9
