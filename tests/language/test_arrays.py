"""Arrays in the language: declarations, Modelica indexing, array equations, arrays of
components, connect of arrays, and the errors of each (Modelica 3.6, chapter 10).

Every array is scalarised where it is declared, so the checks here are on
what the engine computes from the scalars: closed forms of linear systems
written with matrices, sums and products evaluated, and the names the
elements get (Modelica's, so that reference results match).
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from acausal import (ArrayIndexError, ArraySizeError, Component, ConnectorError, Eq, Experiment, Model, ModifierError, Parameter,
                     RealInput, RealOutput, Variable, der, simulate)
from acausal.arrays import (Array, cat, each, fill, identity, max as amax, min as amin, ones, product, scalar, size,
                            sum as asum, transpose, vector, zeros)
from acausal.components.rotational import Flange_b
from acausal import ComponentArray
from acausal.library.blocks import Constant, Sine
from acausal.library.rotational import Inertia
from acausal.library.thermal import FixedTemperature, HeatCapacitor, ThermalConductor


# -- the Array value ------------------------------------------------------------------------


X = Array(sp.symbols("x1:4"), "x")
M = Array([[1, 2, 3], [4, 5, 6]], "M")


def test_indices_count_from_one_and_slices_include_both_ends():
    x1, x2, x3 = sp.symbols("x1:4")
    assert X[1] == x1 and X[3] == x3
    assert X[2:3].flat == [x2, x3]
    assert M[2, 3] == 6 and M[:, 1].flat == [1, 4] and M[1, :].flat == [1, 2, 3]
    assert M[[2, 1], 1].flat == [4, 1]
    assert len(X) == 3 and size(M) == (2, 3) and size(M, 1) == 2 and size(M, 2) == 3


@pytest.mark.parametrize("index", [0, 4, -1])
def test_an_index_out_of_range_names_the_array_and_its_size(index):
    with pytest.raises(ArrayIndexError, match=rf"array x: index {index} is out of range; the size is \[3\]") as info:
        X[index]
    assert isinstance(info.value, IndexError) and "from 1 to 3" in info.value.hint


def test_a_non_integer_index_is_refused():
    with pytest.raises(ArrayIndexError, match="not an integer"):
        X[1.5]
    with pytest.raises(ArrayIndexError, match="2 dimensions, indexed with 3"):
        M[1, 1, 1]


def test_matrix_product_and_elementwise_arithmetic():
    x1, x2, x3 = sp.symbols("x1:4")
    assert (M @ X).flat == [x1 + 2 * x2 + 3 * x3, 4 * x1 + 5 * x2 + 6 * x3]
    assert (2 * X + 1).flat == [2 * x1 + 1, 2 * x2 + 1, 2 * x3 + 1]
    assert (X * X).flat == [x1 ** 2, x2 ** 2, x3 ** 2]
    assert (M @ transpose(M)).tolist() == [[14, 32], [32, 77]]
    with pytest.raises(ArraySizeError, match=r"sizes \[2, 3\] and \[2, 3\]: 3 columns against 2 rows"):
        M @ M
    with pytest.raises(ArraySizeError, match=r"sizes \[3\] and \[2\]"):
        X + Array([1, 2])


def test_the_array_functions_evaluate_as_in_modelica():
    x1, x2, x3 = sp.symbols("x1:4")
    assert asum(X) == x1 + x2 + x3 and asum(M) == 21
    assert product(X) == x1 * x2 * x3 and product(M) == 720
    assert fill(7, 2, 2).tolist() == [[7, 7], [7, 7]]
    assert zeros(3).flat == [0, 0, 0] and ones(2, 1).tolist() == [[1], [1]]
    assert identity(2).tolist() == [[1, 0], [0, 1]]
    assert cat(1, X, Array([5])).flat == [x1, x2, x3, 5]
    assert cat(2, M, Array([[7], [8]])).tolist() == [[1, 2, 3, 7], [4, 5, 6, 8]]
    assert amin(M) == 1 and amax(M) == 6 and amax(X) == sp.Max(x1, x2, x3)
    assert scalar(Array([[9]])) == 9 and vector(Array([[1], [2]])).flat == [1, 2]
    with pytest.raises(ArraySizeError, match="cat"):
        cat(1, M, X)


def test_an_array_equation_is_one_equation_per_element_and_checks_sizes():
    x1, x2, x3 = sp.symbols("x1:4")
    assert Eq(X, 0) == [sp.Eq(x1, 0, evaluate=False), sp.Eq(x2, 0, evaluate=False), sp.Eq(x3, 0, evaluate=False)]
    assert [e.lhs for e in Eq(der(X), X)] == [der(x1), der(x2), der(x3)]
    with pytest.raises(ArraySizeError, match=r"array equation with sizes \[3\] and \[2\]"):
        Eq(X, Array([1, 2]))


# -- declarations ---------------------------------------------------------------------------


class Linear(Component):
    """der(x) = A x + B u, y = C x (a state-space system written with arrays)."""

    A = Parameter([[0.0, 1.0], [-4.0, -0.4]])
    B = Parameter([[0.0], [1.0]])
    C = Parameter([[1.0, 0.0]])
    u = RealInput("size(B, 2)")
    y = RealOutput("size(C, 1)")
    x = Variable(shape="size(A, 1)", start=lambda c: [1.0] + [0.0] * (len(c.A) - 1), fixed=True)

    def equations(self):
        return [Eq(der(self.x), self.A @ self.x + self.B @ self.u), Eq(self.y, self.C @ self.x)]


class FreeOscillator(Model):
    experiment = Experiment(stop_time=5.0, interval=0.01)

    def build(self):
        self.plant = Linear()
        self.zero = Constant(k=0.0)
        self.connect(self.zero.y, self.plant.u[1])


def damped(t, wn=2.0, zeta=0.1):
    """x'' + 2 zeta wn x' + wn^2 x = 0, x(0) = 1, x'(0) = 0."""
    wd = wn * np.sqrt(1 - zeta ** 2)
    return np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t))


def test_a_system_written_with_matrices_follows_its_closed_form():
    result = simulate(FreeOscillator(), rtol=1e-10, atol=1e-12)
    assert result.success, result.message
    np.testing.assert_allclose(result["plant.x[1]"], damped(result.time), atol=1e-8)
    np.testing.assert_allclose(result["plant.y[1]"], result["plant.x[1]"], atol=1e-14)
    # the elements are named as Modelica names them, the matrix's elements are parameters
    assert {"plant.x[2]", "plant.u[1]", "plant.A[2,1]", "plant.B[2,1]"} <= set(result.names)
    assert result["plant.A[2,1]"][0] == -4.0


def test_matrix_elements_are_tunable_parameters():
    """A[2,1] = -9: the frequency becomes 3 rad/s with the same compiled systems."""
    result = simulate(FreeOscillator(), parameters={"plant.A[2,1]": -9.0, "plant.A[2,2]": -0.6},
                      rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(result["plant.x[1]"], damped(result.time, wn=3.0, zeta=0.1), atol=1e-8)


def test_a_matrix_given_at_construction_sets_the_sizes():
    """A 3-state chain of integrators: x3' = 1, x2' = x3, x1' = x2 from rest: x1 = t^3/6."""

    class Chain(Model):
        experiment = Experiment(stop_time=2.0, interval=0.1)

        def build(self):
            self.plant = Linear(A=[[0, 1, 0], [0, 0, 1], [0, 0, 0]], B=[[0], [0], [1]], C=[[1, 0, 0]],
                                x=dict(start=0.0))
            self.one = Constant(k=1.0)
            self.connect(self.one.y, self.plant.u[1])

    result = simulate(Chain(), rtol=1e-10, atol=1e-12)
    t = result.time
    np.testing.assert_allclose(result["plant.x[1]"], t ** 3 / 6, atol=1e-9)
    np.testing.assert_allclose(result["plant.x[3]"], t, atol=1e-9)


def test_a_wrong_size_in_a_modifier_names_both_sizes():
    with pytest.raises(ArraySizeError, match=r"Linear.x.start has size \[2\], the value given has size \[3\]"):
        Linear(x=dict(start=[1.0, 2.0, 3.0]))


def test_each_and_per_element_attributes():
    plant = Linear(x=dict(start=each(0.5)), **{"x[2]": dict(start=-1.0)})
    assert [plant.attribute(f"x[{i}]", "start") for i in (1, 2)] == [0.5, -1.0]
    assert [Linear().attribute(f"x[{i}]", "start") for i in (1, 2)] == [1.0, 0.0]


class Gains(Component):
    """y[i] = k[i] * u[i] for n signals; the size n is a structural parameter."""

    n = Parameter(2, structural=True)
    k = Parameter(shape="n", default=1.0)
    u = RealInput("n")
    y = RealOutput("n")

    def equations(self):
        return [Eq(self.y, self.k * self.u)]


def test_sizes_from_a_structural_parameter_and_connect_of_whole_arrays():
    class Fan(Model):
        experiment = Experiment(stop_time=1.0, interval=0.5)

        def build(self):
            self.source = ComponentArray.of(Constant, 3, k=[1.0, 2.0, 3.0])
            self.gains = Gains(n=3, k=[10.0, 20.0, 30.0])
            self.connect(self.source.y, self.gains.u)

    result = simulate(Fan())
    assert [result[f"gains.y[{i}]"][-1] for i in (1, 2, 3)] == [10.0, 40.0, 90.0]


def test_connect_of_arrays_of_different_sizes_names_both():
    class Mismatch(Model):
        def build(self):
            self.source = ComponentArray.of(Constant, 2, k=1.0)
            self.gains = Gains(n=3)
            self.connect(self.source.y, self.gains.u)

    with pytest.raises(ArraySizeError, match=r"connect\(source.y of size \[2\], gains.u of size \[3\]\)"):
        simulate(Mismatch())


def test_an_array_input_partly_connected_names_the_open_element():
    class Partly(Model):
        def build(self):
            self.one = Constant(k=1.0)
            self.gains = Gains(n=2)
            self.connect(self.one.y, self.gains.u[1])

    with pytest.raises(ConnectorError, match=r"gains\.u\[2\]"):
        simulate(Partly())


# -- arrays of components and of connectors --------------------------------------------------


class Rod(Model):
    """N cells on a fixed temperature, insulated at the far end (lumped conduction)."""

    experiment = Experiment(stop_time=50.0, interval=0.5)
    N = 5

    def build(self):
        n = self.N
        self.cell = [HeatCapacitor(C=2.0, T=dict(start=300.0, fixed=True)) for _ in range(n)]
        self.link = ComponentArray.of(ThermalConductor, n, G=[0.8] + [0.5] * (n - 1))
        self.wall = FixedTemperature(T=400.0)
        self.connect(self.wall.port, self.link[1].port_a)
        self.connect(self.link.port_b, self.cell.port)                    # n to n
        self.connect(self.cell[1:n - 1].port, self.link[2:n].port_a)      # slices, both ends included


def test_an_array_of_components_keeps_energy_and_names_its_elements():
    result = simulate(Rod(), rtol=1e-10, atol=1e-10)
    assert result.success, result.message
    names = set(result.names)
    assert {"cell[1].T", "cell[5].T", "link[1].G", "link[5].Q_flow"} <= names
    # the heat stored is the heat that came in through the first link
    stored = sum(2.0 * (result[f"cell[{i}].T"] - 300.0) for i in range(1, 6))
    flow = result["link[1].Q_flow"]
    came_in = np.concatenate([[0.0], np.cumsum(np.diff(result.time) * (flow[1:] + flow[:-1]) / 2)])
    np.testing.assert_allclose(stored, came_in, atol=1e-3 * stored.max())
    # heat flows down the rod: the cells are ordered by temperature
    final = [result[f"cell[{i}].T"][-1] for i in range(1, 6)]
    assert final == sorted(final, reverse=True) and 300.0 < final[-1] < final[0] < 400.0


def test_a_modifier_of_an_array_of_components_reaches_each_element():
    result = simulate(Rod(cell=dict(C=[2.0, 2.0, 2.0, 2.0, 4.0])), stop_time=1.0)
    assert result["cell[5].C"][0] == 4.0 and result["cell[1].C"][0] == 2.0
    with pytest.raises(ArraySizeError, match="is given 2 values for 5 components"):
        simulate(Rod(cell=dict(C=[1.0, 2.0])), stop_time=1.0)


def test_component_arrays_index_from_one():
    sines = ComponentArray.of(Sine, 3, f=[1.0, 2.0, 3.0], amplitude=each(2.0))
    assert [s.parameter_binding("f") for s in sines] == [1.0, 2.0, 3.0]
    assert sines[3].parameter_binding("amplitude") == 2.0
    assert [s.parameter_binding("f") for s in sines[2:3]] == [2.0, 3.0]
    with pytest.raises(ArrayIndexError, match="index 4 is out of range"):
        sines[4]


class TwoShafts(Component):
    """Two flanges as one connector array, each driven by its own torque tau[i]."""

    tau = Parameter([1.0, -2.0])
    flange = Flange_b(shape=2)

    def equations(self):
        return [Eq(self.flange[i].tau, -self.tau[i]) for i in (1, 2)]


def test_a_connector_array_connects_element_by_element():
    class Driven(Model):
        experiment = Experiment(stop_time=1.0, interval=0.1)

        def build(self):
            self.drive = TwoShafts()
            self.body = ComponentArray.of(Inertia, 2, J=[1.0, 4.0],
                                          phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=True))
            self.connect(self.drive.flange, self.body.flange_a)

    result = simulate(Driven(), rtol=1e-10, atol=1e-12)
    t = result.time
    np.testing.assert_allclose(result["body[1].w"], 1.0 * t, atol=1e-9)
    np.testing.assert_allclose(result["body[2].w"], -0.5 * t, atol=1e-9)
    assert "drive.flange[2].tau" in result.names


# -- arrays shown as one entry ----------------------------------------------------------------


def test_array_groups_bring_the_elements_of_an_array_together_in_index_order():
    from acausal.arrays import array_groups

    names = ["k", "x[2]", "x[10]", "A[1,2]", "x[1]", "A[1,1]"] + [f"x[{i}]" for i in range(3, 10)]
    groups = array_groups(names)
    assert [(name, shape) for name, shape, _ in groups] == [("k", None), ("x", (10,)), ("A", (1, 2))]
    assert groups[1][2] == [f"x[{i}]" for i in range(1, 11)]      # numeric order: x[10] last
    # an array with an element missing is not complete: its elements stay as they are
    assert [name for name, _, _ in array_groups(["y[1]", "y[3]"])] == ["y[1]", "y[3]"]


def test_explain_shows_an_array_parameter_once_with_its_size_and_values(tmp_path):
    from acausal.tools.explain import explain

    text = str(explain(FreeOscillator(), out_dir=tmp_path, html=tmp_path / "page"))
    assert "plant.A[2, 2] = [[0, 1], [-4, -0.4]]" in text      # the values Linear declares
    assert "plant.A[1,1] =" not in text
    assert "plant.x[2] = [1, 0]" in text                          # its fixed start values, [1, 0]
    page = (tmp_path / "page" / "index.html").read_text()
    assert "<summary><code>plant.A[2, 2]</code> (4 elements)" in page
    assert "<summary><code>plant.x[2]</code> (2 elements)" in page


def test_an_instance_s_values_do_not_become_the_defaults_of_the_next():
    """The sized class is shared by every instance of one size: each keeps its own values."""

    class Pair(Component):
        v = Parameter([0.0, 0.0])

    assert Pair(v=[1.0, 2.0]).parameter_binding("v[1]") == 1.0
    assert Pair().parameter_binding("v[1]") == 0.0
    assert type(Pair(v=[5.0, 6.0])) is type(Pair())


def test_an_empty_slice_is_empty_as_in_modelica():
    assert Array([1])[2:1].shape == (0,)
    assert asum(Array([1, 2, 3])[3:2]) == 0


def test_a_size_changed_from_outside_after_the_arrays_were_made_is_refused():
    class Sized(Component):
        n = Parameter(2, structural=True)
        x = Variable(shape="n")

        def equations(self):
            return [Eq(der(self.x), -self.x)]

    class Holder(Model):
        def build(self):
            self.s = Sized()

    with pytest.raises(ModifierError, match=r"Holder.s.n = 3 sizes arrays that were made with n = 2"):
        simulate(Holder(s=dict(n=3)))
    assert len(Sized(n=3).x) == 3     # given where it is made, it sizes the arrays


def test_a_model_with_arrays_pickles_and_runs_the_same_after(tmp_path):
    """Sized classes are made at run time; their instances still pickle (multiprocessing, caches)."""
    import pickle

    model = FreeOscillator()
    copy = pickle.loads(pickle.dumps(model))
    plant = pickle.loads(pickle.dumps(Linear(x=dict(start=[0.5, 0.0]))))
    assert type(plant) is type(Linear()) and plant.attribute("x[1]", "start") == 0.5
    first, second = simulate(model, stop_time=1.0), simulate(copy, stop_time=1.0)
    assert np.array_equal(first["plant.x[1]"], second["plant.x[1]"])
