"""The stick-slip example that ends against a hard stop, against what its physics implies.

While stuck at s = 0 the spring force grows as c*v_drive*t, so the first
breakaway is where it reaches the static limit (MassWithStopAndFriction's
f0_max = 1.001*(F_Coulomb + F_Stribeck)); at the stop the velocity is reset to
zero and the mass stays there, with no further event.
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import simulate
from examples.stick_slip_stop import StickSlipStop

C, V_DRIVE, SMAX = 100.0, 0.1, 0.3
F_STATIC = 1.001 * (5.0 + 10.0)


@pytest.fixture(scope="module")
def result():
    run = simulate(StickSlipStop(), rtol=1e-9)
    assert run.success, run.message
    return run


def test_first_breakaway_where_the_spring_force_reaches_the_static_limit(result):
    first = next(e for e in result.events if ("mass.mode", 0, 1) in e.changes)
    assert first.time == pytest.approx(F_STATIC / (C * V_DRIVE), abs=1e-7)
    stuck = result.time < first.time
    assert np.all(result["mass.s"][stuck] == 0.0)


def test_sticks_and_slips_before_the_stop(result):
    slips = [e.time for e in result.events if ("mass.mode", 0, 1) in e.changes]
    sticks = [e.time for e in result.events if ("mass.mode", 1, 0) in e.changes]
    assert len(slips) >= 2 and len(sticks) >= 2
    assert all(a < b for a, b in zip(slips, sticks))  # each slip ends before the next starts


def test_impact_resets_the_velocity_and_the_mass_stays_at_the_stop(result):
    impact = next(e for e in result.events if ("mass.stopped", 0, 1) in e.changes)
    assert any(change[0] == "reinit(mass.v)" and change[2] == 0.0 for change in impact.changes)
    assert result["mass.s"].max() <= SMAX + 1e-9
    after = result.time > impact.time
    assert np.all(result["mass.s"][after] == SMAX) and np.all(result["mass.v"][after] == 0.0)
    # the spring keeps pulling (above the static limit), yet nothing else happens
    assert C * (V_DRIVE * result.time[-1] - SMAX) > F_STATIC
    assert result.events[-1] is impact
