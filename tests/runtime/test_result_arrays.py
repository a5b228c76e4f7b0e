"""Results read back as arrays: ``result["x"]``, ``result["cell.T"]``, against closed forms.

Arrays are stored one column per element (``x[1]``, ``cell[3].T``); the name
without indices reads them as one array ``(len(time), n)`` (``(len(time), n,
m)`` for a matrix), elements in index order.  The models have exact
solutions:

* ``n`` uncoupled cells ``der(x[i]) = -i x[i]``, ``x(0) = 1``:
  ``x[i](t) = exp(-i t)``, a different rate per element, so an element read
  in the wrong place (``x[10]`` before ``x[9]``) shows;
* a heat rod (``examples/heat_rod.py``), a linear system whose exact solution
  is a matrix exponential, and whose stored heat ``sum(C T)`` grows by the
  heat flowing in.
"""

from __future__ import annotations

import math
import pickle

import numpy as np
import pytest
import scipy.linalg
from scipy.integrate import cumulative_trapezoid

from acausal import Boolean, Component, Eq, Experiment, Model, Parameter, Variable, der, simulate
from acausal.runtime.result import ColumnInfo, SimulationResult
from examples.heat_rod import HeatRod

N = 12  # more than 9: numeric order differs from the order of the names as text
RTOL, ATOL = 1e-10, 1e-12


class Decays(Model):
    """N uncoupled cells, der(x[i]) = -i x[i], and a matrix M[i,j] = j x[i] of them."""

    experiment = Experiment(stop_time=1.0, interval=0.01)

    x = Variable(shape=N, start=1.0, fixed=True, unit="m", description="Cell value")
    M = Variable(shape=(2, 3), unit="m", description="Scaled cells")
    low = Boolean(shape=3, description="Cell below one half")

    def equations(self):
        return ([Eq(der(self.x[i]), -i * self.x[i]) for i in range(1, N + 1)]
                + [Eq(self.M[i, j], j * self.x[i]) for i in (1, 2) for j in (1, 2, 3)]
                + [Eq(self.low[i], self.x[i] < 0.5) for i in (1, 2, 3)])


class Cell(Component):
    """der(x) = -k x, x(0) = 1."""

    k = Parameter(1.0, unit="1/s", description="Rate")
    x = Variable(start=1.0, fixed=True, unit="m", description="Cell value")

    def equations(self):
        return [Eq(der(self.x), -self.k * self.x)]


class Cells(Model):
    """An array of N cells, the i-th with rate i."""

    experiment = Experiment(stop_time=1.0, interval=0.01)

    def build(self):
        self.cell = [Cell(k=float(i)) for i in range(1, N + 1)]


@pytest.fixture(scope="module")
def decays() -> SimulationResult:
    result = simulate(Decays(), rtol=RTOL, atol=ATOL)
    assert result.success, result.message
    return result


@pytest.fixture(scope="module")
def cells() -> SimulationResult:
    result = simulate(Cells(), rtol=RTOL, atol=ATOL)
    assert result.success, result.message
    return result


def exact(t) -> np.ndarray:
    """exp(-i t) for i = 1 .. N, one row per time."""
    return np.exp(-np.outer(t, np.arange(1, N + 1)))


# -- reading arrays ----------------------------------------------------------------------------


def test_a_vector_variable_reads_as_one_array_in_index_order(decays):
    values = decays["x"]
    assert values.shape == (len(decays.time), N) and values.dtype == np.float64
    np.testing.assert_allclose(values, exact(decays.time), rtol=0, atol=1e-8)
    # the derivatives read as an array too
    np.testing.assert_allclose(decays["der(x)"], -np.arange(1, N + 1) * exact(decays.time), rtol=0, atol=1e-7)


def test_a_matrix_reads_with_two_axes_and_a_row_by_its_index(decays):
    t = decays.time
    matrix = decays["M"]
    assert matrix.shape == (len(t), 2, 3)
    for i in (1, 2):
        for j in (1, 2, 3):
            np.testing.assert_allclose(matrix[:, i - 1, j - 1], j * np.exp(-i * t), rtol=0, atol=1e-8)
    np.testing.assert_allclose(decays["M[2]"], np.outer(np.exp(-2 * t), [1, 2, 3]), rtol=0, atol=1e-8)
    assert decays.info("M").shape == (2, 3) and decays.info("M[2]").shape == (3,)


def test_an_array_of_components_reads_as_one_array(cells):
    t = cells.time
    np.testing.assert_allclose(cells["cell.x"], exact(t), rtol=0, atol=1e-8)
    # a parameter of every element: constant in time, the element's own value
    rates = cells["cell.k"]
    assert rates.shape == (len(t), N)
    np.testing.assert_array_equal(rates, np.tile(np.arange(1.0, N + 1), (len(t), 1)))
    assert cells.elements("cell.x") == tuple(f"cell[{i}].x" for i in range(1, N + 1))
    assert cells.arrays["cell.x"] == (N,) and cells.arrays["cell.k"] == (N,)


def test_a_boolean_array_reads_as_bool_and_switches_at_its_closed_form_times(decays):
    """low[i] = x[i] < 1/2 becomes true at t = ln(2) / i."""
    low = decays["low"]
    assert low.dtype == np.bool_ and low.shape == (len(decays.time), 3)
    away = np.ones(len(decays.time), dtype=bool)
    for i in (1, 2, 3):
        away &= np.abs(decays.time - math.log(2) / i) > 1e-6  # not at an event row
    expected = decays.time[:, None] > math.log(2) / np.arange(1, 4)
    np.testing.assert_array_equal(low[away], expected[away])


def test_a_name_that_is_a_column_reads_as_before(decays):
    one = decays["x[10]"]
    assert one.shape == (len(decays.time),)
    np.testing.assert_allclose(one, np.exp(-10 * decays.time), rtol=0, atol=1e-8)
    assert decays.final("x[10]") == pytest.approx(math.exp(-10), abs=1e-8)
    # the columns and their names stay element by element
    assert "x" not in decays.columns and "x" not in decays.names and f"x[{N}]" in decays.names


def test_the_elements_are_ordered_by_index_whatever_the_columns_order():
    """Columns stored as x[10], x[2], x[1], ... read back as x[1] ... x[10]."""
    order = [10, 2, 1, 9, 3, 8, 4, 7, 5, 6]
    columns = {f"x[{i}]": np.full(3, float(i)) for i in order}
    columns.update({f"A[{i},{j}]": np.full(3, 10.0 * i + j) for i in (11, 2, 1, 10, 3, 4, 5, 6, 7, 8, 9)
                    for j in (2, 1)})
    result = SimulationResult(np.array([0.0, 0.5, 1.0]), columns, model_name="Made")
    np.testing.assert_array_equal(result["x"][0], np.arange(1.0, 11.0))
    np.testing.assert_array_equal(result["A"][0], 10.0 * np.arange(1, 12)[:, None] + np.array([1.0, 2.0]))


# -- what an array is ---------------------------------------------------------------------------


def test_unit_describe_and_info_of_an_array_name(cells):
    rod = simulate(HeatRod(n=4), stop_time=1.0)
    assert rod.unit("cell.T") == "K" and rod.unit("link.Q_flow") == "W" and rod.unit("cell.C") == "J/K"
    info = rod.info("cell.T")
    assert (info.name, info.unit, info.kind, info.shape) == ("cell.T", "K", "continuous", (4,))
    assert info.description == "Temperature of element"
    assert rod.describe("cell.T") == "cell.T [K] continuous, array of 4: Temperature of element"
    assert rod.info("cell.C").kind == "parameter"
    assert cells.describe("cell.x").startswith("cell.x [m] continuous, array of 12")
    assert rod.info("cell[2].T").shape == ()  # a column is no array


def test_in_unit_converts_every_element():
    rod = simulate(HeatRod(n=5), stop_time=10.0)
    kelvin = rod["cell.T"]
    np.testing.assert_allclose(rod.in_unit("cell.T", "degC"), kelvin - 273.15, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(rod.in_unit("cell.T"), kelvin)  # no display unit declared: as declared
    np.testing.assert_allclose(rod.in_unit("link.Q_flow", "mW"), 1000.0 * rod["link.Q_flow"], rtol=1e-15)
    with pytest.raises(ValueError, match="cannot be shown in 'm'"):
        rod.in_unit("cell.T", "m")


def test_elements_with_different_units_have_no_unit_of_the_array():
    info = {"p[1]": ColumnInfo("p[1]", "K"), "p[2]": ColumnInfo("p[2]", "W")}
    result = SimulationResult(np.array([0.0, 1.0]), {n: np.zeros(2) for n in info}, model_name="Made",
                              column_info=info)
    assert result["p"].shape == (2, 2) and result.info("p").unit == ""
    with pytest.raises(ValueError, match=r"different units \('K', 'W'\)"):
        result.unit("p")
    with pytest.raises(ValueError, match="different units"):
        result.in_unit("p", "K")


# -- values at any time -------------------------------------------------------------------------


def test_at_gives_the_elements_at_a_time(cells, decays):
    # at an output row: the row's values; between rows: within linear interpolation's error
    np.testing.assert_allclose(cells.at(0.5, "cell.x"), np.exp(-0.5 * np.arange(1, N + 1)), rtol=0, atol=1e-8)
    t = np.array([0.123, 0.5, 0.987])
    between = cells.at(t, "cell.x")
    assert between.shape == (3, N)
    # linear interpolation of exp(-i t) on a 0.01 grid: off by at most h**2 i**2 / 8
    bound = 0.01 ** 2 * np.arange(1, N + 1) ** 2 / 8 + 1e-8
    assert np.all(np.abs(between - exact(t)) <= bound)
    both = decays.at(0.25, ["x", "x[3]", "M"])
    assert both["x"].shape == (N,) and both["M"].shape == (2, 3)
    assert both["x[3]"] == pytest.approx(math.exp(-0.75), abs=1e-8)
    assert isinstance(both["x[3]"], float)
    low = decays.at(1.0, "low")
    assert low.dtype == np.bool_ and low.tolist() == [True, True, True]


def test_final_of_an_array(decays):
    np.testing.assert_allclose(decays.final("x"), np.exp(-np.arange(1, N + 1)), rtol=0, atol=1e-8)


# -- the heat rod: closed form and a conserved quantity ------------------------------------------


def rod_exact(n: int, t: np.ndarray) -> np.ndarray:
    """The cells' temperatures of ``HeatRod(n)`` with its default parameters, one row per time.

    ``T[1] = T_hot``; for the others ``C dT/dt = G (T[i-1] - 2 T[i] + T[i+1])``
    and ``C dT[n]/dt = G (T[n-1] - T[n])``: ``u = T - T_hot`` solves
    ``du/dt = (G/C) K u``, ``u(t) = expm(t (G/C) K) u(0)``.
    """
    L, A, rho_c, k = (HeatRod.L.default, HeatRod.A.default, HeatRod.rho_c.default, HeatRod.k.default)
    T0, T_hot = HeatRod.T0.default, HeatRod.T_hot.default
    dx = L / n
    rate = (k * A / dx) / (rho_c * A * dx)
    m = n - 1  # cells 2 .. n
    K = -2.0 * np.eye(m) + np.eye(m, k=1) + np.eye(m, k=-1)
    K[-1, -1] = -1.0  # the insulated end
    u0 = np.full(m, T0 - T_hot)
    u = np.array([scipy.linalg.expm(rate * ti * K) @ u0 for ti in t])
    return np.column_stack([np.full(len(t), T_hot), u + T_hot])


def test_the_heat_rod_matches_its_exact_solution():
    n = 12
    result = simulate(HeatRod(n=n), stop_time=300.0, interval=5.0, rtol=RTOL, atol=1e-9)
    assert result.success, result.message
    temperatures = result["cell.T"]
    assert temperatures.shape == (len(result.time), n)
    np.testing.assert_allclose(temperatures, rod_exact(n, result.time), rtol=0, atol=1e-6)


def test_the_heat_rod_stores_the_heat_that_flows_in():
    """d/dt sum(C T) = Q_in at every point, and its integral over the run."""
    rod = simulate(HeatRod(n=10), stop_time=200.0, interval=0.05, rtol=RTOL, atol=1e-9)
    capacities = rod["cell.C"][0]
    heat_in_rate = -rod["hot.port.Q_flow"]
    # the rate: exact up to rounding (the connection equations)
    np.testing.assert_allclose(rod["cell.der_T"] @ capacities, heat_in_rate, rtol=0,
                               atol=1e-9 * np.max(np.abs(heat_in_rate)))
    # the integral: to the trapezoid rule's error
    stored = (rod["cell.T"] - rod["cell.T"][0]) @ capacities
    came_in = cumulative_trapezoid(heat_in_rate, rod.time, initial=0.0)
    np.testing.assert_allclose(stored, came_in, rtol=0, atol=1e-5 * came_in[-1])
    # the heat goes down the rod: the cells are ordered by temperature, between T0 and T_hot
    final = rod.final("cell.T")
    assert np.all(np.diff(final) < 0)
    assert HeatRod.T0.default < final[-1] and final[0] == pytest.approx(HeatRod.T_hot.default)


# -- names that are no array ---------------------------------------------------------------------


def test_an_unknown_name_still_raises_a_key_error_with_the_close_names(cells, decays):
    with pytest.raises(KeyError, match=r"'cel\.x' is not a variable of Cells; did you mean cell\.x"):
        cells["cel.x"]
    with pytest.raises(KeyError, match=r"'cell\[13\]\.x' is not a variable of Cells; cell\.x is an array "
                                       r"of 12, cell\[1\]\.x \.\.\. cell\[12\]\.x"):
        cells["cell[13].x"]
    with pytest.raises(KeyError, match=r"did you mean"):
        decays.info("xx")
    for method in (decays.unit, decays.describe, decays.in_unit, decays.elements):
        with pytest.raises(KeyError, match="'nothing' is not a variable of Decays"):
            method("nothing")
    with pytest.raises(KeyError, match="'M\\[3\\]' is not a variable"):
        decays.at(0.5, "M[3]")
    assert "x" in decays and "M[1]" in decays and "x[13]" not in decays and "cell.y" not in decays


class Vector(Component):
    """A vector of n values, each constant: y[i] = i."""

    n = Parameter(2, structural=True)
    y = Variable(shape="n", unit="m")

    def equations(self):
        return [Eq(self.y[i], float(i)) for i in range(1, self.n + 1)]


def test_elements_of_different_sizes_read_one_by_one():
    class Ragged(Model):
        experiment = Experiment(stop_time=1.0, interval=0.5)

        def build(self):
            self.part = [Vector(n=2), Vector(n=3)]

    result = simulate(Ragged())
    np.testing.assert_array_equal(result["part[2].y"][-1], [1.0, 2.0, 3.0])
    with pytest.raises(KeyError, match=r"'part\.y' names 5 elements .* do not fill a rectangular array"):
        result["part.y"]
    assert "part.y" not in result and "part.y" not in result.arrays
    assert result.info("part[1].y").shape == (2,) and result.unit("part[2].y") == "m"


# -- arrays in the lists of names -----------------------------------------------------------------


def test_an_array_name_stands_for_its_elements_in_tables_and_files(cells, tmp_path):
    frame = cells.to_pandas(["cell.x"], event_column=None)
    assert list(frame.columns) == [f"cell[{i}].x" for i in range(1, N + 1)]
    np.testing.assert_allclose(frame.to_numpy(), exact(cells.time), rtol=0, atol=1e-8)
    shown = cells.to_pandas(["cell.x"], display_units={"cell.x": "mm"}, event_column=None)
    np.testing.assert_allclose(shown.to_numpy(), 1000.0 * exact(cells.time), rtol=0, atol=1e-5)
    path = cells.to_csv(tmp_path / "cells.csv", ["cell.x"])
    back = SimulationResult.from_csv(path)
    np.testing.assert_allclose(back["cell.x"], exact(back.time), rtol=0, atol=1e-8)
    assert "cell[12].x" in cells.summary(signals=["cell.x"])


def test_a_copy_of_a_result_reads_its_arrays(cells):
    cells["cell.x"]  # builds the lookup kept with the result
    copied = pickle.loads(pickle.dumps(cells))
    np.testing.assert_array_equal(copied["cell.x"], cells["cell.x"])


def test_plot_draws_an_array_in_one_panel(cells):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import acausal.tools.plotting  # noqa: F401 - registers the plotter

    figure = cells.plot("cell.x", events=False)
    assert len(figure.axes) == 1 and len(figure.axes[0].lines) == N
    assert [line.get_label() for line in figure.axes[0].lines][:2] == ["cell[1].x [m]", "cell[2].x [m]"]
    # the plotting module called directly reads the array name the same way
    from acausal.tools.plotting import plot

    direct = plot(cells, [["cell.x"]], events=False)
    assert len(direct.axes) == 1 and len(direct.axes[0].lines) == N
