"""Hard case 6: stiff coupling — a 1e8 N.m/rad spring between an inertia and a friction-loaded inertia.

What makes it hard
------------------
``5 sin(2 pi t)`` drives inertia1 (J = 1), which is coupled by a
SpringDamper (c = 1e8 N.m/rad, d = 2e4 N.m.s/rad: critically damped, time
constant 1e-4 s) to inertia2 (J = 1) on a bearing with tau0 = 1 N.m.  The
spring's eigenvalues (~ -1e4 1/s) are five orders of magnitude faster than
the motion, so an explicit method needs ~1e4 steps per second for
stability alone while an implicit one takes steps of the motion's scale.
The stick-slip logic sits on top: while inertia2 is stuck the bearing holds
the spring torque, which is the difference of two nearly equal numbers
(c*phi_rel with phi_rel ~ 1e-8 rad) — so the spring's ``phi_nominal`` must
be set to that scale (1e-8), or the default absolute tolerance (rtol times
the nominal 1e-4 rad) is worth 1e-2 N.m of torque and the breakaway is
found 3e-4 s off (BDF) or, for an undamped spring integrated with RK45,
a hundred spurious stick/slip events appear.

What physics gives
------------------
Quasi-statically the spring transmits the whole drive (the correction
J1*a1 is ~1e-6 N.m), so inertia2 breaks away at t_b = asin(1/5)/(2 pi);
after that both inertias move as one body, (J1 + J2) w' = drive - tau0
sign(w), reversing directly when w returns to 0 (the drive then exceeds
tau0).  The event times come from the closed-form oracle (brentq on the
integral of the drive).

Budgets
-------
An explicit method on a stiff coupling runs for as long as stability
demands (a stiffer spring, c = 1e12, would need ~1e6 steps per second).
``simulate(..., max_steps=N, timeout=seconds)`` bounds a run: one that
exceeds a budget stops with status -1 and a SolverError whose hint
suggests an implicit method, and keeps the rows computed so far
(``test_step_budget_stops_an_explicit_method``; added after this case
showed that ``simulate`` had no budget, gap G of docs/hard-cases.md).
The full, unbudgeted RK45 run still runs in a subprocess with a 60 s
timeout: that watchdog does not depend on the engine's own budget
machinery, so a hang anywhere (not only in the step loop) fails the test
instead of blocking pytest.
"""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
import time as _time
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

if __name__ == "__main__":  # run as a script by test_explicit_method_does_not_hang
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from acausal import Model, simulate  # noqa: E402
from acausal.errors import SolverError  # noqa: E402
from acausal.library.blocks import Sine  # noqa: E402
from acausal.library.rotational import BearingFriction, Inertia, SpringDamper, Torque  # noqa: E402

REST = dict(start=0, fixed=True)
A, F_HZ, TAU0, J1, J2 = 5.0, 1.0, 1.0, 1.0, 1.0
C, D = 1e8, 2e4
STOP = 1.0
OMEGA = 2 * math.pi * F_HZ


class StiffCoupling(Model):
    """Sine torque -> inertia1 -> SpringDamper(c = 1e8) -> inertia2 on BearingFriction(tau0 = 1)."""

    def build(self):
        self.sine = Sine(amplitude=A, f=F_HZ)
        self.torque = Torque()
        self.inertia1 = Inertia(J=J1, phi=REST, w=REST)
        self.spring = SpringDamper(c=C, d=D, phi_nominal=1e-8, phi_rel=REST, w_rel=REST)
        self.inertia2 = Inertia(J=J2)
        self.bearing = BearingFriction(tau_pos=[[0.0, TAU0]])
        self.connect(self.sine.y, self.torque.tau)
        self.connect(self.torque.flange, self.inertia1.flange_a)
        self.connect(self.inertia1.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.inertia2.flange_a)
        self.connect(self.inertia2.flange_b, self.bearing.flange_a)


# -- the rigid-body oracle ----------------------------------------------------------

T_B = math.asin(TAU0 / A) / OMEGA


def J_w(t, t_k, s):
    """(J1 + J2)*w(t) while sliding in direction s since t_k (w(t_k) = 0)."""
    return A * (math.cos(OMEGA * t_k) - math.cos(OMEGA * t)) / OMEGA - s * TAU0 * (t - t_k)


T_R = brentq(lambda t: J_w(t, T_B, 1), 0.5, 0.9, xtol=1e-15)  # forward slide ends: reversal


def oracle_w(t):
    """Rigid-body speed of both inertias on [0, STOP]."""
    if t < T_B:
        return 0.0
    if t < T_R:
        return J_w(t, T_B, 1) / (J1 + J2)
    return J_w(t, T_R, -1) / (J1 + J2)


def check_result(result, tol_t, tol_w):
    assert result.status == 0, result.message
    changes = [(e.time, old, new) for e in result.events for n, old, new in e.changes
               if n == "bearing.mode"]
    assert [(o, n) for _, o, n in changes] == [(0, 1), (1, -1)]
    start = [e.time for e in result.events if ("bearing.startForward", False, True) in e.changes]
    assert len(start) == 1 and abs(start[0] - T_B) < tol_t
    assert abs(changes[0][0] - T_B) < tol_t
    assert abs(changes[1][0] - T_R) < tol_t
    t = result.time
    exact = np.array([oracle_w(s) for s in t])
    for name in ("inertia1.w", "inertia2.w"):
        np.testing.assert_allclose(result[name], exact, rtol=0, atol=tol_w)
    stuck = t < T_B - tol_t
    assert np.max(np.abs(result["inertia2.w"][stuck])) <= 1e-9
    return changes


def test_oracle_premises():
    assert T_B == pytest.approx(0.0320471, abs=1e-7)
    assert abs(A * math.sin(OMEGA * T_R)) > TAU0  # direct reversal at T_R
    assert math.sqrt(C / J1) == pytest.approx(1e4)  # the stiff eigenfrequency


@pytest.mark.parametrize("method", ["Radau", "BDF", "LSODA"])
def test_implicit_methods_finish_quickly_and_right(method):
    t0 = _time.perf_counter()
    result = simulate(StiffCoupling(), stop_time=STOP, interval=1e-3, method=method)
    wall = _time.perf_counter() - t0
    changes = check_result(result, tol_t=1e-5, tol_w=1e-5)
    assert result.stats["steps"] < 1000   # steps of the motion's scale, not of the spring's
    assert wall < 15.0
    print(f"\n[case 6] c = 1e8, {method}: {result.stats['steps']} steps, "
          f"{result.stats['rhs_evaluations']} rhs evaluations, {wall:.2f} s wall (incl. translation), "
          f"breakaway {changes[0][0]:.9f} (oracle {T_B:.9f}), reversal {changes[1][0]:.9f} "
          f"(oracle {T_R:.9f})")


def _run_explicit(method="RK45"):
    """Body of the subprocess: simulate and report as JSON."""
    t0 = _time.perf_counter()
    result = simulate(StiffCoupling(), stop_time=STOP, interval=1e-3, method=method)
    report = dict(status=result.status, message=result.message, steps=result.stats["steps"],
                  nfev=result.stats["rhs_evaluations"], wall=_time.perf_counter() - t0,
                  events=[(e.time, [list(c) for c in e.changes]) for e in result.events],
                  t=result.time.tolist(), w1=result["inertia1.w"].tolist(),
                  w2=result["inertia2.w"].tolist())
    print(json.dumps(report))


def test_explicit_method_does_not_hang():
    """RK45 must finish (or stop with a message) well within 60 s; run in a subprocess with a timeout."""
    radau = simulate(StiffCoupling(), stop_time=STOP, interval=1e-3, method="Radau")
    try:
        done = subprocess.run([sys.executable, __file__, "RK45"], capture_output=True, text=True,
                              timeout=60)
    except subprocess.TimeoutExpired:  # pragma: no cover - the failure this test guards against
        pytest.fail("RK45 on the stiff coupling did not finish within 60 s")
    assert done.returncode == 0, done.stderr[-2000:]
    report = json.loads(done.stdout.strip().splitlines()[-1])
    if report["status"] != 0:  # allowed: a clear stop
        assert report["message"] and "Traceback" not in report["message"]
        return
    # it finished: same physics as the implicit methods ...
    changes = [(t, o, n) for t, cs in report["events"] for name, o, n in cs if name == "bearing.mode"]
    assert [(o, n) for _, o, n in changes] == [(0, 1), (1, -1)]
    assert abs(changes[0][0] - T_B) < 1e-5 and abs(changes[1][0] - T_R) < 1e-5
    exact = np.array([oracle_w(s) for s in report["t"]])
    np.testing.assert_allclose(report["w2"], exact, rtol=0, atol=1e-5)
    # ... at the price of stability-limited steps: about 1e4 per second of simulated time
    assert report["steps"] > 20 * radau.stats["steps"]
    print(f"\n[case 6] c = 1e8, RK45: status {report['status']}, {report['steps']} steps "
          f"({report['steps'] / radau.stats['steps']:.0f}x Radau's {radau.stats['steps']}), "
          f"{report['nfev']} rhs evaluations, {report['wall']:.2f} s")


def test_step_budget_stops_an_explicit_method():
    """RK45 with max_steps=2000 stops early: status -1, a SolverError naming the step budget with a
    hint towards an implicit method, and the rows computed up to there (right, by the oracle)."""
    budget = 2000
    t0 = _time.perf_counter()
    result = simulate(StiffCoupling(), stop_time=STOP, interval=1e-3, method="RK45",
                      max_steps=budget)
    wall = _time.perf_counter() - t0
    assert wall < 5.0                      # RK45 needs ~1e4 steps for the whole run (~1.5 s)
    assert result.status == -1
    error = result.error
    assert isinstance(error, SolverError) and error.result is result
    assert result.message == str(error)
    assert f"budget of {budget} steps" in result.message
    assert "implicit method" in error.hint and "Radau" in error.hint
    assert result.message.count("hint:") == 1
    assert budget <= result.stats["steps"] <= budget + 1
    # the rows computed so far are kept: from the start, never backwards (an event has two rows
    # at one time), up to where the budget ran out, and well before the stop time
    named = re.search(r"by t = ([-+0-9.eE]+)", result.message)
    assert named
    t_stop = float(named.group(1))
    t = result.time
    assert len(t) > 0 and t[0] == 0.0
    assert np.all(np.diff(t) >= 0) and t[-1] > t[0]
    assert T_B < t[-1] <= t_stop < STOP
    # ... and they are right: the breakaway was found, and both speeds follow the oracle
    changes = [(e.time, old, new) for e in result.events for n, old, new in e.changes
               if n == "bearing.mode"]
    assert [(o, n) for _, o, n in changes] == [(0, 1)]
    assert abs(changes[0][0] - T_B) < 1e-5
    exact = np.array([oracle_w(s) for s in t])
    for name in ("inertia1.w", "inertia2.w"):
        np.testing.assert_allclose(result[name], exact, rtol=0, atol=1e-5)
    print(f"\n[case 6] c = 1e8, RK45 with max_steps={budget}: status {result.status} after "
          f"{result.stats['steps']} steps, {wall:.2f} s wall; kept {len(t)} rows up to t = {t[-1]:g} "
          f"(budget ran out at t = {t_stop:.6g}); {result.message.splitlines()[0]}; hint: {error.hint}")


if __name__ == "__main__":
    _run_explicit(sys.argv[1] if len(sys.argv) > 1 else "RK45")
