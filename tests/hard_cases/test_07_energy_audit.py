"""Hard case 7: a long stick-slip run with an energy audit.

What makes it hard
------------------
A sinusoidally driven spring-mass oscillator with Coulomb friction sticks
and slips ~160 times in 100 s.  Every stick and every breakaway is an event
that restarts the integrator; an engine that loses a little energy at each
of them (a velocity that is not exactly continuous through the event
iteration, a friction torque evaluated in the wrong mode for part of a
step, a missed or doubled event) accumulates the error.  The bearing's
heat port feeds a HeatCapacitor, so the dissipated energy is measurable.

The audit
---------
The work of the torque source is integrated *inside the model*: a
PowerSensor between the source and the inertia measures ``tau*w`` and a
an Integrator (library.blocks) integrates the power into the work.  Then, at every output
row (not only at the end)::

    W = J w^2 / 2  +  c phi^2 / 2  +  C (T - T0)      (kinetic + spring + heat)

to 1e-6 of the work done (acausal reaches ~1e-10 at rtol 1e-9).  Friction only
dissipates, so the temperature never decreases; a stuck inertia has no
kinetic energy.  The 100 s run takes ~1-2 s, so it always runs.
"""

from __future__ import annotations

import time as _time

import numpy as np
import pytest

from acausal import Model, simulate
from acausal.library.blocks import Integrator, Sine
from acausal.library.rotational import BearingFriction, Fixed, Inertia, PowerSensor, Spring, Torque
from acausal.library.thermal import HeatCapacitor

REST = dict(start=0, fixed=True)
J, C_SPRING, C_HEAT, T0 = 1.0, 20.0, 2.0, 300.0
A, F_HZ = 3.0, 0.4
TAU_POS, PEAK = [[0.0, 2.0], [10.0, 2.5]], 1.2
STOP = 100.0




class StickSlipOscillator(Model):
    """Sine torque -> power sensor -> inertia on a spring to ground; bearing friction -> heat capacitor."""

    def build(self):
        self.sine = Sine(amplitude=A, f=F_HZ)
        self.torque = Torque()
        self.powerSensor = PowerSensor()
        self.workMeter = Integrator()  # the work: integral of the power
        self.inertia = Inertia(J=J, phi=REST, w=REST)
        self.spring = Spring(c=C_SPRING)
        self.fixed = Fixed()
        self.bearing = BearingFriction(tau_pos=TAU_POS, peak=PEAK, useHeatPort=True)
        self.housing = HeatCapacitor(C=C_HEAT, T=dict(start=T0, fixed=True))
        self.connect(self.sine.y, self.torque.tau)
        self.connect(self.torque.flange, self.powerSensor.flange_a)
        self.connect(self.powerSensor.flange_b, self.inertia.flange_a)
        self.connect(self.powerSensor.power, self.workMeter.u)
        self.connect(self.inertia.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.fixed.flange)
        self.connect(self.inertia.flange_b, self.bearing.flange_a)
        self.connect(self.bearing.heatPort, self.housing.port)


def audit(result):
    W = result["workMeter.y"]
    kinetic = 0.5 * J * result["inertia.w"] ** 2
    spring = 0.5 * C_SPRING * result["inertia.phi"] ** 2   # the spring's other end is fixed at 0
    heat = C_HEAT * (result["housing.T"] - T0)
    return W, kinetic, spring, heat


def mode_changes(result):
    return [(e.time, old, new) for e in result.events for n, old, new in e.changes
            if n == "bearing.mode"]


@pytest.fixture(scope="module")
def runs():
    out = {}
    for method in ("DOP853", "RK45", "Radau"):
        t0 = _time.perf_counter()
        result = simulate(StickSlipOscillator(), stop_time=STOP, interval=0.01, method=method,
                          rtol=1e-9)
        out[method] = (result, _time.perf_counter() - t0)
    return out


@pytest.mark.parametrize("method", ["DOP853", "RK45", "Radau"])
def test_energy_audit_over_100_s(runs, method):
    result, wall = runs[method]
    assert result.status == 0, result.message
    assert result.time[-1] == STOP
    W, kinetic, spring, heat = audit(result)
    imbalance = W - kinetic - spring - heat
    scale = np.max(np.abs(W))
    assert scale > 50.0                                  # real work was done
    worst = np.max(np.abs(imbalance)) / scale
    final = abs(imbalance[-1]) / abs(W[-1])
    assert worst <= 1e-6                                 # throughout
    assert final <= 1e-6                                 # and at the end
    # friction only dissipates
    assert np.all(np.diff(result["housing.T"]) >= -1e-12)
    assert np.all(result["bearing.lossPower"] >= -1e-9)
    # real stick-slip: many sticks, and no kinetic energy while stuck
    changes = mode_changes(result)
    sticks = [c for c in changes if c[2] == 0]
    assert len(sticks) >= 50
    stuck = result["bearing.mode"] == 0
    assert 0.1 < np.mean(stuck) < 0.9
    assert np.max(kinetic[stuck]) <= 1e-18
    print(f"\n[case 7] {method}, {STOP:g} s: {len(changes)} mode changes ({len(sticks)} sticks), "
          f"{len(result.events)} events, stuck {100 * np.mean(stuck):.0f}% of the rows; work "
          f"{W[-1]:.9f} J = kinetic {kinetic[-1]:.3e} + spring {spring[-1]:.6f} + heat {heat[-1]:.9f}; "
          f"largest imbalance {worst:.1e} of the work (end: {final:.1e}); "
          f"{result.stats['steps']} steps, {wall:.2f} s")


def test_methods_agree_on_the_stick_slip_sequence(runs):
    """Three integrators, one physics: the same sequence of mode changes at the same times."""
    sequences = {m: mode_changes(r) for m, (r, _) in runs.items()}
    reference = sequences["DOP853"]
    for method, seq in sequences.items():
        assert [(o, n) for _, o, n in seq] == [(o, n) for _, o, n in reference], method
        np.testing.assert_allclose([t for t, _, _ in seq], [t for t, _, _ in reference], rtol=0,
                                   atol=1e-5)
