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
* Both stuck at the start: ``simulate`` raises StructurallySingularError
  (a StructuralError, a ValueError) naming the discrete state
  (``bf1.locked=True, bf2.locked=True``), the equations of both elements and a
  friction-specific hint: put a compliance (SpringDamper) between the
  elements or merge them into one.  (It used to recommend "an inertia or a
  compliance", but an inertia is rigid: bf1 -> inertia -> bf2 is still
  singular — bug E of docs/hard-cases.md, fixed.)
* Sliding first: the run returns ``status == -1`` with a SolverError whose
  message gives the time (the analytic stop t* = J w0 / (tau1 + tau2)) and the
  same diagnosis, and the result keeps everything up to t*.  The hint is
  stated once (it used to appear twice in this message — bug F, fixed).
"""

from __future__ import annotations

import re

import numpy as np
import pytest

from acausal import Model, simulate
from acausal.errors import AcausalError, SolverError, StructuralError, StructurallySingularError
from acausal.library.blocks import Constant
from acausal.library.rotational import BearingFriction, Brake, ConstantTorque, Inertia

REST = dict(start=0, fixed=True)
TAU1, TAU2, J = 1.0, 2.0, 1.0


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
        simulate(two_bearings(0.0, T), stop_time=1.0)
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
                      rtol=1e-10)
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
    result = simulate(BearingAndBrake(), stop_time=2.0, interval=0.02, rtol=1e-10)
    assert result.status == -1 and isinstance(result.error, SolverError)
    assert_clear_diagnosis(result.message, "bf", "brake")
    assert result.time[-1] == pytest.approx(1.0, abs=1e-9)  # 2 rad/s at (1 + 1) N.m / 1 kg.m2


def test_an_inertia_between_the_bearings_is_still_one_rigid_shaft():
    """Physics: an inertia is rigid, so bf1 -> inertia -> bf2 locked together is still singular."""
    with pytest.raises(StructurallySingularError) as info:
        simulate(two_bearings(0.0, 0.0, inertia_between=True), stop_time=1.0)
    assert_clear_diagnosis(str(info.value))


def test_hint_does_not_recommend_an_inertia():
    with pytest.raises(StructurallySingularError) as info:
        simulate(two_bearings(0.0, 0.0), stop_time=1.0)
    assert "inertia" not in info.value.hint


def test_mid_run_message_states_the_hint_once():
    result = simulate(two_bearings(3.0), stop_time=2.0)
    assert result.message.count("hint:") == 1
