"""Modelica.Blocks.Continuous.StateSpace and TransferFunction: closed forms, every initType, sizes.

The blocks are driven by constant inputs (or the ramp of ModelicaTest) and
compared with the analytic solutions of their linear systems; the
initialization of each initType is checked at t = 0 against what MSL 4.1.0
prescribes.  The last tests check the two blocks of
ModelicaTest.Blocks.Continuous (and its InitialOutput variant) against the
MSL reference results (``ACAUSAL_REFERENCE_DIR``).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from acausal import Eq, Experiment, Model, simulate
from acausal.errors import ArraySizeError, ModifierError, OverDeterminedError, StartValueWarning
from acausal.library.blocks.continuous import Init, StateSpace, TransferFunction
from acausal.library.blocks.sources import Ramp
from acausal.tools.compare import compare_signals, load_reference

#: The damped oscillator x'' + 2*zeta*wn*x' + wn^2*x = u as a state space system.
OSCILLATOR = dict(A=[[0.0, 1.0], [-4.0, -0.4]], B=[[0.0], [1.0]], C=[[1.0, 0.0]])
WN, ZETA = 2.0, 0.1


def _driven(block_factory, inputs: dict[str, float], stop_time: float = 5.0) -> Model:
    """A model holding ``block_factory()`` as ``blk``, its inputs (``"u"``, ``"u[2]"``) held at ``inputs``."""

    class Driven(Model):
        experiment = Experiment(stop_time=stop_time, interval=stop_time / 500)

        def build(self):
            self.blk = block_factory()

        def equations(self):
            return [Eq(getattr(self.blk, name), value) for name, value in inputs.items()]

    return Driven()


def _decay(t: np.ndarray, zeta: float, wn: float) -> tuple[np.ndarray, np.ndarray]:
    """Free response of x'' + 2*zeta*wn*x' + wn^2*x = 0 from x = 1, x' = 0: (x, x')."""
    sigma, wd = zeta * wn, wn * np.sqrt(1 - zeta**2)
    envelope = np.exp(-sigma * t)
    return envelope * (np.cos(wd * t) + sigma / wd * np.sin(wd * t)), -wn**2 / wd * envelope * np.sin(wd * t)


# --------------------------------------------------------------------------
# StateSpace
# --------------------------------------------------------------------------


def test_state_space_oscillator_from_x_start_follows_the_analytic_solution():
    model = _driven(lambda: StateSpace(**OSCILLATOR, x_start=[1.0, 0.0], initType=Init.InitialState),
                    {"u[1]": 0.0}, stop_time=10.0)
    r = simulate(model)
    x1, x2 = _decay(r.time, ZETA, WN)
    np.testing.assert_allclose(r["blk.x[1]"], x1, atol=2e-5)
    np.testing.assert_allclose(r["blk.x[2]"], x2, atol=2e-5)
    np.testing.assert_allclose(r["blk.y[1]"], r["blk.x[1]"], atol=1e-12)


def test_state_space_names_its_elements_as_modelica_and_its_matrices_are_tunable():
    model = _driven(lambda: StateSpace(**OSCILLATOR, x_start=[1.0, 0.0], initType="InitialState"),
                    {"u[1]": 0.0}, stop_time=3.0)
    r = simulate(model, parameters={"blk.A[2,1]": -WN**2 * 4, "blk.A[2,2]": -2 * ZETA * WN * 2})
    assert {"blk.x[1]", "blk.x[2]", "blk.u[1]", "blk.y[1]", "blk.A[2,1]", "blk.D[1,1]"} <= set(r.names)
    x1, _ = _decay(r.time, ZETA, 2 * WN)  # wn doubled by the new A
    np.testing.assert_allclose(r["blk.x[1]"], x1, atol=2e-5)


def test_state_space_feed_through_with_several_inputs_and_outputs():
    # one state, two inputs, two outputs: x' = -x + u1 + u2, y1 = x + u2, y2 = 2*x + u1
    model = _driven(lambda: StateSpace(A=[[-1.0]], B=[[1.0, 1.0]], C=[[1.0], [2.0]], D=[[0.0, 1.0], [1.0, 0.0]],
                                       initType=Init.InitialState),
                    {"u[1]": 1.0, "u[2]": 2.0})
    r = simulate(model)
    x = 3.0 * (1.0 - np.exp(-r.time))
    np.testing.assert_allclose(r["blk.x[1]"], x, atol=2e-5)
    np.testing.assert_allclose(r["blk.y[1]"], x + 2.0, atol=2e-5)
    np.testing.assert_allclose(r["blk.y[2]"], 2.0 * x + 1.0, atol=4e-5)


def test_state_space_steady_state_stays_at_the_equilibrium_for_a_constant_input():
    A = np.array([[-1.0, 0.5], [0.0, -2.0]])
    B = np.array([[1.0], [1.0]])
    model = _driven(lambda: StateSpace(A=A.tolist(), B=B.tolist(), C=[[1.0, 1.0]], initType=Init.SteadyState),
                    {"u[1]": 2.0})
    r = simulate(model)
    equilibrium = -np.linalg.solve(A, B[:, 0] * 2.0)  # [1.5, 1.0]
    for i in (1, 2):
        np.testing.assert_allclose(r[f"blk.x[{i}]"], equilibrium[i - 1], atol=1e-9)


def test_state_space_initial_output_takes_the_least_squares_states():
    # y(0) = x1(0) = y_start; MSL 4.1.0 picks the x2 that minimises |der(x)| = |(x2, u - 4*x1 - 0.4*x2)|
    model = _driven(lambda: StateSpace(**OSCILLATOR, y_start=[0.5], initType=Init.InitialOutput), {"u[1]": 1.0})
    r = simulate(model)
    assert r["blk.y[1]"][0] == pytest.approx(0.5, abs=1e-10)
    # d/dx2 of x2^2 + (1 - 2 - 0.4*x2)^2 = 0  ->  x2 = -0.4/1.16
    assert r["blk.x[2]"][0] == pytest.approx(-0.4 / 1.16, abs=1e-10)
    # afterwards a damped oscillation about x1 = u/4 from x1(0) = 0.5, x1'(0) = x2(0)
    sigma, wd = ZETA * WN, WN * np.sqrt(1 - ZETA**2)
    c1, c2 = 0.25, (-0.4 / 1.16 + sigma * 0.25) / wd
    x1 = 0.25 + np.exp(-sigma * r.time) * (c1 * np.cos(wd * r.time) + c2 * np.sin(wd * r.time))
    np.testing.assert_allclose(r["blk.x[1]"], x1, atol=2e-5)


def test_state_space_initial_output_of_the_modelica_test():
    # ModelicaTest.Blocks.Continuous_InitialOutput: A = I, B = [1; 1], C = [1, 1], u = 0.5, y_start = 2:
    # the least-squares states are x = [1, 1] (the reference result starts there)
    model = _driven(lambda: StateSpace(A=[[1.0, 0.0], [0.0, 1.0]], B=[[1.0], [1.0]], C=[[1.0, 1.0]],
                                       y_start=[2.0], initType=Init.InitialOutput),
                    {"u[1]": 0.5}, stop_time=1.0)
    r = simulate(model)
    assert r["blk.x[1]"][0] == pytest.approx(1.0, abs=1e-10)
    assert r["blk.x[2]"][0] == pytest.approx(1.0, abs=1e-10)
    np.testing.assert_allclose(r["blk.x[1]"], 1.5 * np.exp(r.time) - 0.5, rtol=2e-5)


def test_state_space_no_init_starts_from_x_start_as_a_guess():
    model = _driven(lambda: StateSpace(**OSCILLATOR, x_start=[1.0, 0.0]), {"u[1]": 0.0}, stop_time=2.0)
    with pytest.warns(StartValueWarning, match=r"blk\.x\[1\]"):
        r = simulate(model)
    x1, _ = _decay(r.time, ZETA, WN)
    np.testing.assert_allclose(r["blk.x[1]"], x1, atol=2e-5)


def test_state_space_sizes_come_from_the_matrices():
    block = StateSpace(A=[[-1.0]], B=[[1.0, 2.0, 3.0]], C=[[1.0], [1.0]])
    assert (block.nx, block.nin, block.nout) == (1, 3, 2)
    assert block.u.shape == (3,) and block.y.shape == (2,) and block.x.shape == (1,)
    assert block.D.shape == (2, 3)


def test_state_space_instances_of_one_size_keep_their_own_values():
    StateSpace(**OSCILLATOR, x_start=[1.0, 0.0], D=[[5.0]])
    second = StateSpace(**OSCILLATOR)
    assert [second.parameter_binding(f"x_start[{i}]") for i in (1, 2)] == [0.0, 0.0]
    assert second.parameter_binding("D[1,1]") == 0.0
    assert second.parameter_binding("A[2,1]") == -4.0


@pytest.mark.parametrize("matrices, message", [
    (dict(OSCILLATOR, B=[[0.0], [1.0], [2.0]]), r"B has 3 rows, A has 2"),
    (dict(OSCILLATOR, C=[[1.0, 0.0, 0.0]]), r"C has 3 columns, A has 2 rows"),
    (dict(OSCILLATOR, A=[[0.0, 1.0]]), r"A is 1 x 2, it must be square"),
    (dict(OSCILLATOR, D=[[1.0, 2.0]]), r"D is 1 x 2, but nout x nin is 1 x 1"),
    (dict(OSCILLATOR, B=[0.0, 1.0]), r"B is a matrix, the value given has size \[2\]"),
])
def test_state_space_matrices_of_sizes_that_do_not_fit_are_named(matrices, message):
    with pytest.raises(ArraySizeError, match=message):
        StateSpace(**matrices)


def test_state_space_sizes_are_final():
    with pytest.raises(ModifierError, match=r"nin = 2, but the number of columns of B is 1"):
        StateSpace(**OSCILLATOR, nin=2)


# --------------------------------------------------------------------------
# TransferFunction
# --------------------------------------------------------------------------


def test_transfer_function_first_order_step_response():
    r = simulate(_driven(lambda: TransferFunction(b=[1.0], a=[1.0, 1.0], initType=Init.InitialState), {"u": 1.0}))
    np.testing.assert_allclose(r["blk.y"], 1.0 - np.exp(-r.time), atol=2e-5)
    np.testing.assert_allclose(r["blk.x_scaled[1]"], r["blk.x[1]"], atol=1e-12)  # a_end = 1


def test_transfer_function_second_order_step_response_and_scaled_states():
    # 4/(s^2 + 0.8 s + 4): wn = 2, zeta = 0.2; a_end = 4 scales the states
    r = simulate(_driven(lambda: TransferFunction(b=[4.0], a=[1.0, 0.8, 4.0], initType=Init.InitialState),
                         {"u": 1.0}, stop_time=10.0))
    free, _ = _decay(r.time, 0.2, 2.0)
    np.testing.assert_allclose(r["blk.y"], 1.0 - free, atol=2e-5)
    np.testing.assert_allclose(r["blk.x[2]"], r["blk.y"] / 4.0, atol=1e-5)  # x = states of 1/a(s)
    np.testing.assert_allclose(r["blk.x_scaled[2]"], 4.0 * r["blk.x[2]"], atol=1e-9)
    assert r["blk.a_end"][0] == 4.0


def test_transfer_function_with_feed_through_from_its_initial_output():
    # (2 s + 4)/(s + 3) from y(0) = 1 with u = 1: y = 4/3 - exp(-3 t)/3
    r = simulate(_driven(lambda: TransferFunction(b=[2.0, 4.0], a=[1.0, 3.0], y_start=1.0,
                                                  initType=Init.InitialOutput), {"u": 1.0}, stop_time=3.0))
    np.testing.assert_allclose(r["blk.y"], 4.0 / 3.0 - np.exp(-3.0 * r.time) / 3.0, atol=2e-5)
    assert r["blk.d"][0] == 2.0


def test_transfer_function_initial_output_has_zero_output_derivatives():
    # second order from y(0) = 0.5, y'(0) = 0 (der(x_scaled[2:nx]) = 0) towards 1
    r = simulate(_driven(lambda: TransferFunction(b=[4.0], a=[1.0, 0.8, 4.0], y_start=0.5,
                                                  initType=Init.InitialOutput), {"u": 1.0}, stop_time=10.0))
    free, _ = _decay(r.time, 0.2, 2.0)
    np.testing.assert_allclose(r["blk.y"], 1.0 - 0.5 * free, atol=2e-5)


def test_transfer_function_steady_state_stays_for_a_constant_input():
    r = simulate(_driven(lambda: TransferFunction(b=[1.0, 1.0], a=[1.0, 3.0, 2.0], initType=Init.SteadyState),
                         {"u": 2.0}))
    np.testing.assert_allclose(r["blk.y"], 1.0, atol=1e-9)  # the static gain b[2]/a[3] = 1/2 times u
    np.testing.assert_allclose(r["blk.x[1]"], 0.0, atol=1e-9)


def test_transfer_function_initial_state_is_given_for_the_unscaled_states():
    # 1/(s + 2) from x(0) = 0.5 with u = 0: x_scaled(0) = 0.5*a_end = 1, y = x = 0.5*exp(-2 t)
    r = simulate(_driven(lambda: TransferFunction(b=[1.0], a=[1.0, 2.0], x_start=[0.5],
                                                  initType=Init.InitialState), {"u": 0.0}, stop_time=2.0))
    assert r["blk.x_scaled[1]"][0] == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(r["blk.y"], 0.5 * np.exp(-2.0 * r.time), atol=2e-5)


def test_transfer_function_with_a_vanishing_last_coefficient_is_not_scaled():
    # 1/(s^2 + s): a[end] = 0, a_end = 1; the step response is t - 1 + exp(-t)
    r = simulate(_driven(lambda: TransferFunction(b=[1.0], a=[1.0, 1.0, 0.0], initType=Init.InitialState),
                         {"u": 1.0}, stop_time=3.0))
    assert r["blk.a_end"][0] == 1.0
    np.testing.assert_allclose(r["blk.y"], r.time - 1.0 + np.exp(-r.time), atol=2e-5)


def test_transfer_function_without_states_is_a_gain():
    block = TransferFunction(b=[3.0], a=[2.0])
    assert block.nx == 0 and block.x.shape == (0,)
    r = simulate(_driven(lambda: TransferFunction(b=[3.0], a=[2.0]), {"u": 2.0}, stop_time=1.0))
    np.testing.assert_allclose(r["blk.y"], 3.0)


def test_transfer_function_initial_output_without_states_is_over_determined():
    # as in Modelica: y = b/a*u leaves nothing for y = y_start to choose
    with pytest.raises(OverDeterminedError, match=r"blk\.y = blk\.y_start"):
        simulate(_driven(lambda: TransferFunction(b=[3.0], a=[2.0], initType=Init.InitialOutput, y_start=1.0),
                         {"u": 2.0}, stop_time=1.0))


def test_transfer_function_must_be_proper():
    with pytest.raises(ArraySizeError, match=r"not proper: b has 3 coefficients, a has 2"):
        TransferFunction(b=[1.0, 2.0, 3.0], a=[1.0, 1.0])


def test_transfer_function_coefficients_are_vectors():
    with pytest.raises(ArraySizeError, match=r"a is empty"):
        TransferFunction(a=[])
    with pytest.raises(ArraySizeError, match=r"b is a vector, the value given has size \[1, 1\]"):
        TransferFunction(b=[[1.0]])


# --------------------------------------------------------------------------
# The MSL reference: ModelicaTest.Blocks.Continuous
# --------------------------------------------------------------------------


def _modelica_test(init: Init) -> Model:
    """The stateSpace and transferFunction of ModelicaTest.Blocks.Continuous[_InitialOutput], fed by its ramp1."""
    output = init is Init.InitialOutput

    class Continuous(Model):
        experiment = Experiment(stop_time=1.1, interval=1.1 / 5000)

        def build(self):
            self.ramp1 = Ramp(offset=0.5, startTime=0.5, duration=2)
            self.transferFunction = TransferFunction(a=[1, 1], b=[1], initType=init,
                                                     **({"y_start": 2} if output else {}))
            self.stateSpace = StateSpace(A=[[1, 0], [0, 1]], B=[[1], [1]], C=[[1, 1]], initType=init,
                                         **({"y_start": [2]} if output else {}))
            self.connect(self.ramp1.y, self.transferFunction.u)
            self.connect(self.ramp1.y, self.stateSpace.u[1])

    return Continuous()


@pytest.mark.parametrize("modelica_class, init", [
    ("ModelicaTest.Blocks.Continuous", Init.InitialState),
    ("ModelicaTest.Blocks.Continuous_InitialOutput", Init.InitialOutput),
], ids=["Continuous", "Continuous_InitialOutput"])
def test_blocks_lie_in_the_reference_tube(modelica_class, init):
    directory = os.environ.get("ACAUSAL_REFERENCE_DIR")
    if not directory:
        pytest.skip("ACAUSAL_REFERENCE_DIR is not set: the MSL reference results of ModelicaTest are not bundled")
    if not (Path(directory) / modelica_class).is_dir():
        pytest.skip(f"no reference results of {modelica_class} in {directory}")
    reference = load_reference(modelica_class, directory)
    model = _modelica_test(init)
    r = simulate(model, stop_time=reference.stop_time, interval=reference.interval, rtol=reference.tolerance)
    signals = ["stateSpace.x[1]", "stateSpace.x[2]", "transferFunction.x_scaled[1]"]
    assert set(signals) <= set(reference.compared)
    comparison = compare_signals(reference, r.time, {name: r[name] for name in signals}, signals,
                                 check_at="both")
    failed = [f"{s.name}: {s.worst_violation:.3g} dy outside (max error {s.max_abs_error:.3g})"
              for s in comparison.signals if not s.passed]
    assert not failed, "; ".join(failed)
