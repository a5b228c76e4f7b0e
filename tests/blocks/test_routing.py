"""Modelica.Blocks.Routing: multiplexers, demultiplexers, replicators, extractors, pass-throughs.

ModelicaTest.Blocks.MuxDemux lies in the csv-compare tube of the MSL
reference.  Each block is checked against a closed form: the sources are
clocks ``p + time`` (an offset ``p`` per signal), so every element of a
concatenation says where it came from; a multiplexer followed by a
demultiplexer of the same sizes gives its inputs back exactly, one of other
sizes splits the concatenation at other places.  Wrong sizes raise
ArraySizeError naming both sizes; an input element left unconnected is the
usual unconnected-input error naming the element.
"""

from __future__ import annotations

import inspect

import numpy as np
import pytest

from acausal import Experiment, Model, simulate
from acausal.errors import ModifierError, ArrayIndexError, ArraySizeError, ConnectorError
from acausal.language import ComponentArray
from acausal.library.blocks import (BooleanPulse, ContinuousClock, IntegerTable, Sine, routing)
from acausal.library.blocks.routing import (BooleanPassThrough, BooleanReplicator, DeMultiplex, DeMultiplex2,
                                            DeMultiplex3, DeMultiplex4, DeMultiplex5, DeMultiplex6, Extractor,
                                            ExtractSignal, IntegerPassThrough, IntegerReplicator, Multiplex,
                                            Multiplex2, Multiplex3, Multiplex4, Multiplex5, Multiplex6,
                                            RealPassThrough, Replicator)
from examples.blocks_mux_demux import MuxDemux
from tests.library_checks import assert_in_the_tube

MULTIPLEX = {2: Multiplex2, 3: Multiplex3, 4: Multiplex4, 5: Multiplex5, 6: Multiplex6}
DEMULTIPLEX = {2: DeMultiplex2, 3: DeMultiplex3, 4: DeMultiplex4, 5: DeMultiplex5, 6: DeMultiplex6}


def _clocks(count: int) -> ComponentArray:
    """``count`` clocks, clock ``p`` giving ``p + time``."""
    return ComponentArray.of(ContinuousClock, count, offset=list(range(1, count + 1)))


def _flat(block, prefix: str, parts: int) -> list:
    """The elements of ``prefix1`` ... ``prefix<parts>`` of ``block``, concatenated."""
    return [element for i in range(1, parts + 1) for element in getattr(block, f"{prefix}{i}").flat]


def _names(block_name: str, prefix: str, sizes) -> list[str]:
    return [f"{block_name}.{prefix}{i}[{k}]" for i, n in enumerate(sizes, start=1) for k in range(1, n + 1)]


# --------------------------------------------------------------------------
# the MSL reference


def test_mux_demux_example_matches_reference():
    result = assert_in_the_tube(MuxDemux)
    for name in ("y1", "y2", "y3", "y4", "y5", "mux5.y[3]", "demux5.y[5]"):
        np.testing.assert_allclose(result[name], result.time, rtol=0, atol=1e-12, err_msg=name)


# --------------------------------------------------------------------------
# multiplex and demultiplex


class _MuxThenDemux(Model):
    """Clocks ``p + time`` into MultiplexK(sizes_in), its output into DeMultiplexK(sizes_out)."""

    experiment = Experiment(stop_time=1.0, interval=0.1)
    parts = 3
    sizes_in: tuple = (2, 1, 3)
    sizes_out: tuple = (2, 1, 3)

    def build(self):
        sizes_in = {f"n{i}": n for i, n in enumerate(self.sizes_in, start=1)}
        sizes_out = {f"n{i}": n for i, n in enumerate(self.sizes_out, start=1)}
        self.clock = _clocks(sum(self.sizes_in))
        self.mux = MULTIPLEX[self.parts](**sizes_in)
        self.demux = DEMULTIPLEX[self.parts](**sizes_out)
        for clock, element in zip(self.clock, _flat(self.mux, "u", self.parts)):
            self.connect(clock.y, element)
        self.connect(self.mux.y, self.demux.u)


def test_multiplex3_then_demultiplex3_gives_back_the_inputs_exactly():
    result = simulate(_MuxThenDemux())
    assert result.success, result.message
    inputs = _names("mux", "u", (2, 1, 3))
    outputs = _names("demux", "y", (2, 1, 3))
    for p, (u, y) in enumerate(zip(inputs, outputs), start=1):
        np.testing.assert_array_equal(result[y], result[u])
        np.testing.assert_allclose(result[y], p + result.time, rtol=0, atol=1e-12)
        np.testing.assert_allclose(result[f"mux.y[{p}]"], p + result.time, rtol=0, atol=1e-12)


@pytest.mark.parametrize("parts", [2, 3, 4, 5, 6])
def test_multiplex_k_concatenates_in_order_and_demultiplex_k_splits_elsewhere(parts):
    sizes_in = tuple(i % 3 + 1 for i in range(1, parts + 1))
    sizes_out = tuple(reversed(sizes_in))  # the same total, split at other places

    class Run(_MuxThenDemux):
        pass

    Run.parts, Run.sizes_in, Run.sizes_out = parts, sizes_in, sizes_out
    result = simulate(Run())
    assert result.success, result.message
    total = sum(sizes_in)
    assert f"mux.y[{total}]" in result.names and f"mux.y[{total + 1}]" not in result.names
    for p, y in enumerate(_names("demux", "y", sizes_out), start=1):
        np.testing.assert_allclose(result[y], p + result.time, rtol=0, atol=1e-12, err_msg=y)


def test_multiplex_with_empty_parts():
    class Run(_MuxThenDemux):
        sizes_in = (0, 3, 0)
        sizes_out = (3, 0, 0)

    result = simulate(Run())
    assert result.success, result.message
    for p in (1, 2, 3):
        np.testing.assert_allclose(result[f"demux.y1[{p}]"], p + result.time, rtol=0, atol=1e-12)
    assert not any(name.startswith("demux.y2[") for name in result.names)


def test_generic_multiplex_and_demultiplex_pass_n_signals():
    class Run(Model):
        experiment = Experiment(stop_time=1.0, interval=0.1)

        def build(self):
            self.clock = _clocks(4)
            self.mux = Multiplex(n=4)
            self.demux = DeMultiplex(n=4)
            self.connect(self.clock.y, self.mux.u)
            self.connect(self.mux.y, self.demux.u)

    result = simulate(Run())
    assert result.success, result.message
    for p in range(1, 5):
        np.testing.assert_allclose(result[f"demux.y[{p}]"], p + result.time, rtol=0, atol=1e-12)


def test_the_concatenated_size_follows_the_parts():
    assert Multiplex4(n1=2, n3=0).y.shape == (4,)
    assert DeMultiplex2(n1=3, n2=5).u.shape == (8,)
    assert Multiplex2(n1=2, n2=3).y.shape == (5,)


def test_the_concatenated_size_is_not_a_parameter_of_its_own():
    """As in the MSL, y[n1 + n2] has no size parameter to contradict the parts."""
    with pytest.raises(ModifierError, match="has no parameter or variable named 'n'"):
        Multiplex2(n1=2, n2=1, n=4)


def test_connecting_vectors_of_other_sizes_names_both_sizes():
    class Run(Model):
        def build(self):
            self.mux = Multiplex2()
            self.demux = DeMultiplex3()
            self.connect(self.mux.y, self.demux.u)

    with pytest.raises(ArraySizeError) as caught:
        simulate(Run())
    assert "[2]" in str(caught.value) and "[3]" in str(caught.value)
    assert "mux.y" in str(caught.value) and "demux.u" in str(caught.value)


def test_an_input_element_left_unconnected_is_named():
    class Run(Model):
        def build(self):
            self.clock = ContinuousClock()
            self.mux = Multiplex(n=3)
            self.connect(self.clock.y, self.mux.u[1])
            self.connect(self.clock.y, self.mux.u[3])

    with pytest.raises(ConnectorError, match=r"mux\.u\[2\]"):
        simulate(Run())


# --------------------------------------------------------------------------
# replicators, signal extraction


def test_replicator_copies_its_input_to_every_output():
    class Run(Model):
        experiment = Experiment(stop_time=1.0, interval=0.01)

        def build(self):
            self.sine = Sine(f=2)
            self.replicator = Replicator(nout=3)
            self.connect(self.sine.y, self.replicator.u)

    result = simulate(Run())
    assert result.success, result.message
    expected = np.sin(2 * np.pi * 2 * result.time)
    for i in (1, 2, 3):
        np.testing.assert_allclose(result[f"replicator.y[{i}]"], expected, rtol=0, atol=1e-12)


def test_integer_and_boolean_replicators_and_pass_throughs():
    class Run(Model):
        experiment = Experiment(stop_time=3.0, interval=0.01)

        def build(self):
            self.table = IntegerTable(table=[[0, 4], [1, -2], [2, 7]])
            self.pulse = BooleanPulse(period=0.5)
            self.integers = IntegerReplicator(nout=2)
            self.booleans = BooleanReplicator(nout=3)
            self.integer = IntegerPassThrough()
            self.boolean = BooleanPassThrough()
            self.connect(self.table.y, self.integers.u)
            self.connect(self.table.y, self.integer.u)
            self.connect(self.pulse.y, self.booleans.u)
            self.connect(self.pulse.y, self.boolean.u)

    result = simulate(Run())
    assert result.success, result.message
    t = result.time
    away = np.all([np.abs(t - s) > 1e-9 for s in np.arange(0, 3.01, 0.25)], axis=0)
    table = np.where(t < 1, 4, np.where(t < 2, -2, 7))
    pulse = (t % 0.5) < 0.25
    for name in ("integers.y[1]", "integers.y[2]", "integer.y"):
        np.testing.assert_array_equal(result[name][away], table[away], err_msg=name)
    for name in ("booleans.y[1]", "booleans.y[3]", "boolean.y"):
        np.testing.assert_array_equal(result[name][away].astype(bool), pulse[away], err_msg=name)


def test_real_pass_through():
    class Run(Model):
        experiment = Experiment(stop_time=1.0, interval=0.01)

        def build(self):
            self.sine = Sine(f=1, amplitude=3)
            self.pass_ = RealPassThrough()
            self.connect(self.sine.y, self.pass_.u)

    result = simulate(Run())
    np.testing.assert_allclose(result["pass_.y"], 3 * np.sin(2 * np.pi * result.time), rtol=0, atol=1e-12)


def test_extract_signal_takes_the_listed_inputs():
    class Run(Model):
        experiment = Experiment(stop_time=1.0, interval=0.1)

        def build(self):
            self.clock = _clocks(5)
            self.extract = ExtractSignal(nin=5, nout=4, extract=[5, 2, 2, 1])
            self.first = ExtractSignal(nin=5, nout=3)  # the default, 1:nout
            self.connect(self.clock.y, self.extract.u)
            self.connect(self.clock.y, self.first.u)

    result = simulate(Run())
    assert result.success, result.message
    for i, p in enumerate([5, 2, 2, 1], start=1):
        np.testing.assert_allclose(result[f"extract.y[{i}]"], p + result.time, rtol=0, atol=1e-12)
    for i in (1, 2, 3):
        np.testing.assert_allclose(result[f"first.y[{i}]"], i + result.time, rtol=0, atol=1e-12)


def test_extract_signal_of_the_wrong_size_or_out_of_range():
    class Run(Model):
        extract = [1]

        def build(self):
            self.clock = _clocks(3)
            self.block = ExtractSignal(nin=3, nout=2, extract=self.extract)
            self.connect(self.clock.y, self.block.u)

    with pytest.raises(ArraySizeError, match=r"\[1\].*\[2\]"):
        simulate(Run())
    Run.extract = [1, 4]
    with pytest.raises(ArrayIndexError, match="index 4 is out of range"):
        simulate(Run())


class _Extract(Model):
    """Clocks ``10 p + time`` into an Extractor whose index steps through 1, 2, 3, 0, 4."""

    experiment = Experiment(stop_time=5.0, interval=0.01)
    allow = True

    def build(self):
        self.index = IntegerTable(table=[[0, 1], [1, 2], [2, 3], [3, 0], [4, 4]])
        self.clock = ComponentArray.of(ContinuousClock, 3, offset=[10, 20, 30])
        self.extractor = Extractor(nin=3, allowOutOfRange=self.allow, outOfRangeValue=-7)
        self.connect(self.clock.y, self.extractor.u)
        self.connect(self.index.y, self.extractor.index)


def test_extractor_picks_the_indexed_element_or_the_out_of_range_value():
    result = simulate(_Extract())
    assert result.success, result.message
    t = result.time
    index = np.floor(t).clip(0, 4)
    expected = np.select([index == 0, index == 1, index == 2], [10 + t, 20 + t, 30 + t], default=-7.0)
    away = np.all([np.abs(t - s) > 1e-9 for s in (1, 2, 3, 4, 5)], axis=0)
    np.testing.assert_allclose(result["extractor.y"][away], expected[away], rtol=0, atol=1e-12)
    assert {1.0, 2.0, 3.0, 4.0} <= {round(e.time, 9) for e in result.events}


def test_extractor_out_of_range_is_an_error_unless_allowed():
    class Run(_Extract):
        allow = False

    result = simulate(Run())
    assert not result.success
    assert "out of range" in result.message
    assert result.time[-1] == pytest.approx(3.0)  # index 0 from t = 3 on
    k = int(np.argmin(np.abs(result.time - 2.5)))
    assert result["extractor.y"][k] == pytest.approx(32.5, abs=1e-12)


# --------------------------------------------------------------------------
# documentation


@pytest.mark.parametrize("name", routing.__all__)
def test_every_routing_block_names_its_msl_class(name):
    first = inspect.getdoc(getattr(routing, name)).split("\n\n", 1)[0]
    assert f"(Modelica.Blocks.Routing.{name})" in " ".join(first.split())
