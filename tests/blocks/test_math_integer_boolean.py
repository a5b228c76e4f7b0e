"""Modelica.Blocks.MathBoolean, MathInteger, Interaction.Show and Logical.LogicalDelay.

The gates with any number of inputs against their truth tables (three
pulses of periods 1, 2 and 4 s pass through all eight input combinations),
the edge blocks and TriggeredAdd by counting transitions, the MultiSwitches
by the input that decides, the Integer Sum/Product against their closed
forms, the Show blocks by the value they pass on, LogicalDelay against the
delayed edges.  The three Modelica.Blocks.Examples networks lie in the
csv-compare tube.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from acausal import Experiment, Model, simulate
from acausal.library.blocks import BooleanPulse, BooleanTable, IntegerConstant, IntegerStep, Sine
from acausal.library.blocks import interaction, math_boolean, math_integer
from acausal.library.blocks.logical import LogicalDelay
from acausal.tools.compare import compare_signals, load_reference, reference_dir
from examples.blocks_networks import BooleanNetwork1, IntegerNetwork1, RealNetwork1


def _between_events(result):
    """Rows at no event instant (an event's two rows hold its left and right limits)."""
    keep = np.ones(len(result.time), dtype=bool)
    for event in result.events:
        keep &= np.abs(result.time - event.time) > 1e-9
    return keep


def _value_at(result, name: str, t: float) -> float:
    k = int(np.argmin(np.abs(result.time - t)))
    return float(result[name][k])


@pytest.mark.parametrize("model_class", [RealNetwork1, IntegerNetwork1, BooleanNetwork1])
def test_networks_match_reference(model_class):
    if not (reference_dir() / model_class.modelica_class).is_dir():
        pytest.skip(f"no reference results for {model_class.modelica_class} in {reference_dir()}")
    result = simulate(model_class())
    assert result.success, result.message
    comparison = compare_signals(load_reference(model_class.modelica_class), result.time, result.columns)
    assert comparison.passed, comparison.table()


# --------------------------------------------------------------------------
# gates


class _Gates(Model):
    experiment = Experiment(stop_time=3.99, interval=0.01)

    def build(self):
        self.p1 = BooleanPulse(period=1.0, startTime=-0.5)  # false on [0, 0.5), true on [0.5, 1) ...
        self.p2 = BooleanPulse(period=2.0, startTime=-1.0)
        self.p3 = BooleanPulse(period=4.0, startTime=-2.0)
        self.and3 = math_boolean.And(nu=3)
        self.or3 = math_boolean.Or(nu=3)
        self.xor3 = math_boolean.Xor(nu=3)
        self.nand3 = math_boolean.Nand(nu=3)
        self.nor3 = math_boolean.Nor(nu=3)
        for gate in (self.and3, self.or3, self.xor3, self.nand3, self.nor3):
            for i, pulse in enumerate((self.p1, self.p2, self.p3), start=1):
                self.connect(pulse.y, gate.u[i])
        self.not1 = math_boolean.Not()
        self.connect(self.p1.y, self.not1.u)
        self.and0 = math_boolean.And(nu=0)
        self.or0 = math_boolean.Or(nu=0)


def test_gates_against_truth_tables():
    result = simulate(_Gates())
    assert result.success, result.message
    rows = _between_events(result)
    inputs = np.column_stack([result[f"p{i}.y"][rows] for i in (1, 2, 3)]).astype(bool)
    seen = {tuple(row) for row in inputs}
    assert seen == set(itertools.product((False, True), repeat=3))  # every combination was visited
    expected = {
        "and3.y": [all(row) for row in inputs],
        "or3.y": [any(row) for row in inputs],
        "xor3.y": [sum(row) == 1 for row in inputs],
        "nand3.y": [not all(row) for row in inputs],
        "nor3.y": [not any(row) for row in inputs],
        "not1.y": [not row[0] for row in inputs],
    }
    for name, values in expected.items():
        assert np.array_equal(result[name][rows].astype(bool), np.array(values)), name
    assert result.final("and0.y") and not result.final("or0.y")  # the empty and / or


# --------------------------------------------------------------------------
# edges, TriggeredAdd, MultiSwitch


class _Edges(Model):
    """A pulse (period 1, true on [0, 0.5)) into the three edge blocks, each counted by a
    TriggeredAdd; a Boolean MultiSwitch set by the rising edges, reset by the falling ones."""

    experiment = Experiment(stop_time=3.8, interval=0.01)

    def build(self):
        self.pulse = BooleanPulse(period=1.0)
        self.one = IntegerConstant(k=1)
        self.rising = math_boolean.RisingEdge()
        self.falling = math_boolean.FallingEdge()
        self.changing = math_boolean.ChangingEdge()
        self.risingStart = math_boolean.RisingEdge(pre_u_start=True)
        for name in ("rising", "falling", "changing", "risingStart"):
            edge = getattr(self, name)
            counter = math_integer.TriggeredAdd(y_start=10)
            setattr(self, f"count_{name}", counter)
            self.connect(self.pulse.y, edge.u)
            self.connect(edge.y, counter.trigger)
            self.connect(self.one.y, counter.u)
        self.latch = math_boolean.MultiSwitch(nu=2, expr=[True, False])
        self.connect(self.rising.y, self.latch.u[1])
        self.connect(self.falling.y, self.latch.u[2])


def test_edges_counted_by_triggered_add():
    result = simulate(_Edges())
    assert result.success, result.message
    # the pulse rises at 0 (from pre(u) = false), 1, 2, 3 and falls at 0.5, 1.5, 2.5, 3.5; the edge
    # at 0 is true during initialization, where a when-clause does not fire (Modelica 8.3.5)
    assert result.final("count_rising.y") == 10 + 3
    assert result.final("count_falling.y") == 10 + 4
    assert result.final("count_changing.y") == 10 + 7
    assert result.final("count_risingStart.y") == 10 + 3
    assert _value_at(result, "count_rising.y", 1.7) == 11


def test_boolean_multiswitch_latches_the_last_edge():
    result = simulate(_Edges())
    rows = _between_events(result)
    # set at every rising edge, reset at every falling one, holding pre(y) in between: the pulse
    assert np.array_equal(result["latch.y"][rows], result["pulse.y"][rows])
    assert set(result["latch.firstActiveIndex"][rows]) == {0.0}  # the edges are true at events only


class _IntegerBlocks(Model):
    experiment = Experiment(stop_time=3.0, interval=0.01)

    def build(self):
        self.step = IntegerStep(height=3, offset=-1, startTime=1.0)  # -1, then 2 from t = 1
        self.five = IntegerConstant(k=5)
        self.sum = math_integer.Sum(nu=2, k=[2, -3])
        self.product = math_integer.Product(nu=2)
        self.empty = math_integer.Sum(nu=0)
        for block in (self.sum, self.product):
            self.connect(self.step.y, block.u[1])
            self.connect(self.five.y, block.u[2])
        self.p1 = BooleanPulse(period=1.0, width=30)  # true on [0, 0.3), [1, 1.3) ...
        self.p2 = BooleanPulse(period=2.0, width=80)  # true on [0, 1.6), [2, 3.6)
        self.holding = math_integer.MultiSwitch(nu=2, expr=[4, 6], y_default=2)
        self.forgetting = math_integer.MultiSwitch(nu=2, expr=[4, 6], y_default=2, use_pre_as_default=False)
        for switch in (self.holding, self.forgetting):
            self.connect(self.p1.y, switch.u[1])
            self.connect(self.p2.y, switch.u[2])
        self.resettable = math_integer.TriggeredAdd(use_reset=True, use_set=True, y_start=1)
        self.connect(self.five.y, self.resettable.u)
        self.p3 = BooleanPulse(period=1.0, width=30, startTime=0.7)  # rises at 0.7, 1.7, 2.7
        self.connect(self.p3.y, self.resettable.trigger)
        self.connect(self.p2.y, self.resettable.reset)
        self.connect(self.step.y, self.resettable.set)


def test_integer_blocks_against_closed_forms():
    result = simulate(_IntegerBlocks())
    assert result.success, result.message
    for t, u1 in ((0.5, -1), (2.5, 2)):
        assert _value_at(result, "sum.y", t) == 2 * u1 - 3 * 5
        assert _value_at(result, "product.y", t) == u1 * 5
    assert result.final("empty.y") == 0
    # first true input: p1 -> 4, else p2 -> 6, else hold (pre) or the default 2
    for t, holding, forgetting in ((0.1, 4, 4), (0.5, 6, 6), (1.7, 6, 2), (1.9, 6, 2), (2.1, 4, 4)):
        assert _value_at(result, "holding.y", t) == holding, t
        assert _value_at(result, "forgetting.y", t) == forgetting, t
    # y_start until the first trigger (the reset true at 0 is so during initialization, where a
    # when-clause does not fire); a trigger while reset is true takes set (= step: -1, from 1 on 2)
    # as the MSL's equation says, one while it is false adds 5, and the reset at 2 sets it
    for t, expected in ((0.5, 1), (1.0, -1), (1.8, 4), (2.5, 2), (2.99, 2)):
        assert _value_at(result, "resettable.y", t) == expected, t


# --------------------------------------------------------------------------
# Show and LogicalDelay


class _Shown(Model):
    experiment = Experiment(stop_time=1.0, interval=0.01)

    def build(self):
        self.sine = Sine(f=1.0)
        self.count = IntegerStep(height=4, startTime=0.5)
        self.pulse = BooleanPulse(period=0.4)
        self.real = interaction.RealValue()
        self.realNumber = interaction.RealValue(use_numberPort=False, number=2 * self.sine.y)
        self.integer = interaction.IntegerValue()
        self.integerNumber = interaction.IntegerValue(use_numberPort=False, number=7)
        self.boolean = interaction.BooleanValue()
        self.booleanActive = interaction.BooleanValue(use_activePort=False, active=True)
        self.connect(self.sine.y, self.real.numberPort)
        self.connect(self.count.y, self.integer.numberPort)
        self.connect(self.pulse.y, self.boolean.activePort)


def test_show_blocks_pass_the_value_on():
    result = simulate(_Shown())
    assert result.success, result.message
    assert np.allclose(result["real.showNumber"], np.sin(2 * np.pi * result.time), atol=1e-12)
    assert np.allclose(result["realNumber.showNumber"], 2 * np.sin(2 * np.pi * result.time), atol=1e-12)
    assert np.array_equal(result["integer.showNumber"], result["count.y"])
    assert set(result["integerNumber.showNumber"]) == {7.0}
    assert np.array_equal(result["boolean.showActive"], result["pulse.y"])
    assert set(result["booleanActive.showActive"]) == {1.0}


class _Delayed(Model):
    experiment = Experiment(stop_time=5.0, interval=0.01)

    def build(self):
        # u true on [0, 1), [2, 2.2), [3, 4.5)
        self.table = BooleanTable(table=[1, 2, 2.2, 3, 4.5], startValue=True)
        self.delay = LogicalDelay(delayTime=0.5)
        self.connect(self.table.y, self.delay.u)


def test_logical_delay_delays_the_edges():
    result = simulate(_Delayed())
    assert result.success, result.message
    rows = _between_events(result)
    t = result.time[rows]
    u = ((t < 1) | ((t >= 2) & (t < 2.2)) | ((t >= 3) & (t < 4.5)))
    # y1: rising edges at once, falling ones 0.5 s later; y2: rising ones 0.5 s later (a pulse
    # shorter than the delay is lost), falling ones at once; u true from the start is not delayed
    y1 = ((t < 1.5) | ((t >= 2) & (t < 2.7)) | ((t >= 3) & (t < 5.0)))
    y2 = ((t < 1) | ((t >= 3.5) & (t < 4.5)))
    assert np.array_equal(result["delay.u"][rows].astype(bool), u)
    assert np.array_equal(result["delay.y1"][rows].astype(bool), y1)
    assert np.array_equal(result["delay.y2"][rows].astype(bool), y2)
