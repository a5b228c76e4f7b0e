"""The vector blocks of Modelica.Blocks.Math and the vector partials of Modelica.Blocks.Interfaces.

Each block against a closed form of its inputs (sines and clocks whose
values are known at every time): MultiSum and Sum are weighted sums,
MultiProduct a product, MinMax, Max and Min the extremes, MatrixGain a
matrix product, LinearDependency an affine combination, MultiSwitch the
expression of the first true input.  Sizes that disagree raise
ArraySizeError naming both; an input element left unconnected is named.
"""

from __future__ import annotations

import inspect

import numpy as np
import pytest

from acausal import Eq, Experiment, Model, simulate
from acausal.arrays import sum as array_sum
from acausal.components.blocks import MI2MO, MIMOs, MO
from acausal.errors import ArraySizeError, ConnectorError
from acausal.language import ComponentArray
from acausal.library.blocks import (BooleanPulse, BooleanStep, ContinuousClock, LinearDependency, MatrixGain,
                                    Max, Min, MinMax, MultiProduct, MultiSum, MultiSwitch, Sine, Sum)
from acausal.library.blocks import math as math_blocks

FREQUENCIES = (1.0, 2.0, 3.0)
PHASES = (0.0, 1.0, 2.0)


def _sines() -> ComponentArray:
    return ComponentArray.of(Sine, 3, f=list(FREQUENCIES), phase=list(PHASES))


def _sine_values(t: np.ndarray) -> np.ndarray:
    return np.array([np.sin(2 * np.pi * f * t + phase) for f, phase in zip(FREQUENCIES, PHASES)])


def _clocks(count: int) -> ComponentArray:
    """``count`` clocks, clock ``p`` giving ``p + time``."""
    return ComponentArray.of(ContinuousClock, count, offset=list(range(1, count + 1)))


class _ThreeSines(Model):
    """Three sines into the vector input ``u`` of ``block()``."""

    experiment = Experiment(stop_time=1.0, interval=0.001)

    def block(self):
        raise NotImplementedError

    def build(self):
        self.sine = _sines()
        self.b = self.block()
        self.connect(self.sine.y, self.b.u)


# --------------------------------------------------------------------------
# sums and products


def test_multi_sum_of_sines_is_the_weighted_sum():
    class Run(_ThreeSines):
        def block(self):
            return MultiSum(nu=3, k=[1, -2, 3])

    result = simulate(Run())
    assert result.success, result.message
    s = _sine_values(result.time)
    np.testing.assert_allclose(result["b.y"], s[0] - 2 * s[1] + 3 * s[2], rtol=0, atol=1e-12)
    assert {"b.k[1]", "b.k[2]", "b.k[3]"} <= set(result.names)


def test_multi_sum_gains_default_to_one_and_are_modifiable_from_outside():
    class Run(_ThreeSines):
        def block(self):
            return MultiSum(nu=3)

    for model, k in ((Run(), (1, 1, 1)), (Run(b=dict(k=[0.5, 0, -1])), (0.5, 0, -1))):
        result = simulate(model)
        assert result.success, result.message
        s = _sine_values(result.time)
        np.testing.assert_allclose(result["b.y"], k[0] * s[0] + k[1] * s[1] + k[2] * s[2], rtol=0, atol=1e-12)


def test_blocks_of_one_size_keep_their_own_gains():
    # a block sized like an earlier one with gains given takes its declared default
    class Run(_ThreeSines):
        def build(self):
            super().build()
            self.plain = MultiSum(nu=3)
            self.sum = Sum(nin=3)
            self.weighted = Sum(nin=3, k=[5, 6, 7])
            self.identity = MatrixGain()
            self.gain = MatrixGain(K=[[2, 3], [4, 5]])
            for block in (self.plain, self.sum, self.weighted):
                self.connect(self.sine.y, block.u)
            for block in (self.identity, self.gain):
                self.connect(self.sine[1].y, block.u[1])
                self.connect(self.sine[2].y, block.u[2])

        def block(self):
            return MultiSum(nu=3, k=[1, -2, 3])

    result = simulate(Run())
    assert result.success, result.message
    s = _sine_values(result.time)
    np.testing.assert_allclose(result["b.y"], s[0] - 2 * s[1] + 3 * s[2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["plain.y"], s.sum(axis=0), rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["sum.y"], s.sum(axis=0), rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["weighted.y"], 5 * s[0] + 6 * s[1] + 7 * s[2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["identity.y[2]"], s[1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["gain.y[2]"], 4 * s[0] + 5 * s[1], rtol=0, atol=1e-12)


def test_multi_sum_and_multi_product_without_inputs_are_zero():
    class Run(Model):
        experiment = Experiment(stop_time=1.0, interval=0.1)

        def build(self):
            self.sum = MultiSum()
            self.product = MultiProduct()

    result = simulate(Run())
    assert result.success, result.message
    np.testing.assert_array_equal(result["sum.y"], 0.0)
    np.testing.assert_array_equal(result["product.y"], 0.0)


def test_multi_product_of_three_clocks():
    class Run(Model):
        experiment = Experiment(stop_time=2.0, interval=0.01)

        def build(self):
            self.clock = _clocks(3)
            self.product = MultiProduct(nu=3)
            self.connect(self.clock.y, self.product.u)

    result = simulate(Run())
    t = result.time
    np.testing.assert_allclose(result["product.y"], (1 + t) * (2 + t) * (3 + t), rtol=1e-14, atol=0)


def test_sum_of_the_input_vector():
    class Run(_ThreeSines):
        def build(self):
            super().build()
            self.weighted = Sum(nin=3, k=[2, 0.5, -4])
            self.connect(self.sine.y, self.weighted.u)

        def block(self):
            return Sum(nin=3)

    result = simulate(Run())
    assert result.success, result.message
    s = _sine_values(result.time)
    np.testing.assert_allclose(result["b.y"], s.sum(axis=0), rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["weighted.y"], 2 * s[0] + 0.5 * s[1] - 4 * s[2], rtol=0, atol=1e-12)


def test_sum_gains_of_another_size_are_refused_naming_both_sizes():
    with pytest.raises(ArraySizeError) as caught:
        Sum(nin=3, k=[1, 2])
    assert "[3]" in str(caught.value) and "[2]" in str(caught.value)


# --------------------------------------------------------------------------
# extremes


def test_min_max_of_three_sines():
    class Run(_ThreeSines):
        def block(self):
            return MinMax(nu=3)

    result = simulate(Run())
    assert result.success, result.message
    s = _sine_values(result.time)
    np.testing.assert_allclose(result["b.yMax"], s.max(axis=0), rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["b.yMin"], s.min(axis=0), rtol=0, atol=1e-12)


def test_min_max_needs_an_input():
    class Run(Model):
        def build(self):
            self.extremes = MinMax(nu=0)

    with pytest.raises(ArraySizeError, match=r"size \[0\]"):
        simulate(Run())


def test_max_and_min_of_two_signals():
    class Run(Model):
        experiment = Experiment(stop_time=1.0, interval=0.001)

        def build(self):
            self.sine = _sines()
            self.max = Max()
            self.min = Min()
            for block in (self.max, self.min):
                self.connect(self.sine[1].y, block.u1)
                self.connect(self.sine[2].y, block.u2)

    result = simulate(Run())
    s = _sine_values(result.time)
    np.testing.assert_allclose(result["max.y"], np.maximum(s[0], s[1]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["min.y"], np.minimum(s[0], s[1]), rtol=0, atol=1e-12)


# --------------------------------------------------------------------------
# linear maps


def test_linear_dependency():
    class Run(Model):
        experiment = Experiment(stop_time=1.0, interval=0.01)

        def build(self):
            self.sine = _sines()
            self.linear = LinearDependency(y0=0.5, k1=2, k2=-3)
            self.connect(self.sine[1].y, self.linear.u1)
            self.connect(self.sine[3].y, self.linear.u2)

    result = simulate(Run())
    s = _sine_values(result.time)
    np.testing.assert_allclose(result["linear.y"], 0.5 + 2 * s[0] - 3 * s[2], rtol=0, atol=1e-12)


def test_matrix_gain_takes_its_sizes_from_the_matrix():
    class Run(Model):
        experiment = Experiment(stop_time=1.0, interval=0.01)

        def build(self):
            self.clock = _clocks(3)
            self.gain = MatrixGain(K=[[1, 2, 3], [4, 5, -6]])
            self.connect(self.clock.y, self.gain.u)

    result = simulate(Run())
    assert result.success, result.message
    t = result.time
    u = np.array([1 + t, 2 + t, 3 + t])
    np.testing.assert_allclose(result["gain.y[1]"], u[0] + 2 * u[1] + 3 * u[2], rtol=1e-14, atol=0)
    np.testing.assert_allclose(result["gain.y[2]"], 4 * u[0] + 5 * u[1] - 6 * u[2], rtol=1e-14, atol=0)
    assert "gain.y[3]" not in result.names and "gain.K[2,3]" in result.names


def test_matrix_gain_sizes_that_disagree_with_the_matrix_are_refused():
    with pytest.raises(ArraySizeError, match=r"nin = 3.*\[1, 2\]"):
        MatrixGain(K=[[1, 2]], nin=3)
    assert MatrixGain().u.shape == (2,)  # the MSL's default, the 2 x 2 identity


# --------------------------------------------------------------------------
# switch


def test_multi_switch_takes_the_expression_of_the_first_true_input():
    class Run(Model):
        experiment = Experiment(stop_time=4.0, interval=0.01)

        def build(self):
            self.pulse = BooleanPulse(period=1, startTime=0.5)
            self.step2 = BooleanStep(startTime=2)
            self.step1 = BooleanStep(startTime=1)
            self.clock = ContinuousClock()
            self.switch = MultiSwitch(nu=3, expr=[2 * self.clock.y, 5, -1], y_default=9)
            self.connect(self.pulse.y, self.switch.u[1])
            self.connect(self.step2.y, self.switch.u[2])
            self.connect(self.step1.y, self.switch.u[3])

    result = simulate(Run())
    assert result.success, result.message
    t = result.time
    pulse = (t >= 0.5) & ((t - 0.5) % 1 < 0.5)
    first = np.select([pulse, t >= 2, t >= 1], [1, 2, 3], default=0)
    expected = np.select([first == 1, first == 2, first == 3], [2 * t, 5.0, -1.0], default=9.0)
    away = np.all([np.abs(t - s) > 1e-9 for s in np.arange(0, 4.01, 0.5)], axis=0)
    np.testing.assert_array_equal(result["switch.firstActiveIndex"][away], first[away])
    np.testing.assert_allclose(result["switch.y"][away], expected[away], rtol=0, atol=1e-12)


# --------------------------------------------------------------------------
# unconnected inputs, connections of other sizes


def test_an_input_element_left_unconnected_is_named():
    class Run(Model):
        def build(self):
            self.clock = ContinuousClock()
            self.sum = MultiSum(nu=3)
            self.connect(self.clock.y, self.sum.u[1])
            self.connect(self.clock.y, self.sum.u[3])

    with pytest.raises(ConnectorError, match=r"input sum\.u\[2\] of MultiSum is not connected"):
        simulate(Run())


def test_connecting_a_vector_of_another_size_names_both_sizes():
    class Run(Model):
        def build(self):
            self.sine = _sines()
            self.sum = Sum(nin=2)
            self.connect(self.sine.y, self.sum.u)

    with pytest.raises(ArraySizeError) as caught:
        simulate(Run())
    assert "[3]" in str(caught.value) and "[2]" in str(caught.value)


# --------------------------------------------------------------------------
# the vector partials of Modelica.Blocks.Interfaces


class _Difference(MI2MO):
    def equations(self):
        return [Eq(self.y, self.u1 - self.u2)]


class _Doubled(MIMOs):
    def equations(self):
        return [Eq(self.y, 2 * self.u)]


class _Ramps(MO):
    def equations(self):
        from acausal import time
        return [Eq(self.y[i], i * time) for i in range(1, self.nout + 1)]


def test_vector_partials():
    class Run(Model):
        experiment = Experiment(stop_time=1.0, interval=0.01)

        def build(self):
            self.ramps = _Ramps(nout=3)
            self.clock = _clocks(3)
            self.difference = _Difference(n=3)
            self.doubled = _Doubled(n=3)
            self.connect(self.ramps.y, self.difference.u1)
            self.connect(self.clock.y, self.difference.u2)
            self.connect(self.difference.y, self.doubled.u)

    result = simulate(Run())
    assert result.success, result.message
    t = result.time
    for i in (1, 2, 3):
        np.testing.assert_allclose(result[f"doubled.y[{i}]"], 2 * (i * t - (i + t)), rtol=0, atol=1e-12)


def test_array_sum_is_zero_for_an_empty_vector():
    assert array_sum([]) == 0


@pytest.mark.parametrize("name", ["MatrixGain", "MultiSum", "MultiProduct", "MultiSwitch", "Sum", "Max", "Min",
                                  "MinMax", "LinearDependency"])
def test_every_vector_block_names_its_msl_class(name):
    first = inspect.getdoc(getattr(math_blocks, name)).split("\n\n", 1)[0]
    assert f"(Modelica.Blocks.Math.{name})" in " ".join(first.split())
