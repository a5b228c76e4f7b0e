"""The sampled PI speed controller example against what its equations imply by hand.

The controller is a difference equation, so while the shaft sticks its
command follows a closed form; once the loop settles, integral action makes
the motor supply exactly the sliding friction torque (plus the load).
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import simulate
from examples.sampled_speed_control import SampledSpeedControl

TS, KP, TI = 0.01, 0.25, 0.2        # the controller's parameters in the example
W_REF, T_REF = 10.0, 0.2            # the speed step
TAU0, PEAK, SLOPE = 2.0, 1.5, 0.01  # tau_pos = [[0, 2], [100, 3]]: 2 + 0.01*w N.m
TAU_LOAD, T_LOAD = 1.5, 3.0


@pytest.fixture(scope="module")
def result():
    run = simulate(SampledSpeedControl())
    assert run.success, run.message
    return run


def test_command_changes_only_at_sample_instants(result):
    y = result["controller.y"]
    changed = result.time[1:][np.diff(y) != 0]
    assert len(changed) > 100
    ticks = changed / TS
    assert np.max(np.abs(ticks - np.round(ticks))) * TS < 1e-12


def test_breakaway_at_the_sample_where_the_command_exceeds_the_static_limit(result):
    # while stuck the error stays W_REF: x_k = k*Ts/Ti*W_REF, y_k = kp*(W_REF + x_k)
    k = 1
    while KP * (W_REF + k * TS / TI * W_REF) <= PEAK * TAU0:
        k += 1
    t_breakaway = T_REF + (k - 1) * TS
    w = result["shaft.w"]
    assert np.all(w[result.time < t_breakaway] == 0)
    moving = result.time[w > 0]
    assert moving[0] == pytest.approx(t_breakaway, abs=2e-3)
    first = [e for e in result.events if e.kind == "state" and e.changes][0]
    assert first.time == pytest.approx(t_breakaway, abs=1e-9)


def test_integral_action_supplies_the_friction_torque_then_the_load(result):
    def at(name, t):
        return result[name][np.searchsorted(result.time, t)]

    assert at("shaft.w", T_LOAD - 0.01) == pytest.approx(W_REF, abs=0.02)
    assert at("controller.y", T_LOAD - 0.01) == pytest.approx(TAU0 + SLOPE * W_REF, abs=0.005)
    assert at("shaft.w", 4.99) == pytest.approx(W_REF, abs=0.05)
    assert at("controller.y", 4.99) == pytest.approx(TAU0 + SLOPE * W_REF + TAU_LOAD, abs=0.01)
