"""ModelicaTest.Tables.CombiTable2Ds: the 2-D table tests whose table is read from a file or from usertab.c.

Test10/11/12 (MAT v4, v6, v7), Test14 (text file), Test31 (UTF-8 text with
BOM and comments) and Test18_usertab (the table ``TestTable_2D`` of MSL's
usertab.h) lie in the csv-compare tube of the MSL 4.1.0 reference results.
Test13 (MAT v7.3, HDF5; commented out in the MSL, so no reference) gives
Test10's result: the same matrix.

Test15/16/17 evaluate the table ``akima2D`` of test_v4.mat with
ConstantSegments, LinearSegments and ContinuousDerivative on the grid of a
MultiBody surface visualizer, calling the table functions in an algorithm;
their reference compares ``time`` only.  Here they are table blocks: a
``CombiTable2Dv`` ``surface`` whose input pairs sweep the MSL's grid (u1
rises with time, u2[j] holds the grid's j-th value) and a ``CombiTable2Ds``
``t_new`` on the diagonal u1 = u2 = 60*time.  They run to the end, the surface
is the closed form (the node's value on constant segments, bilinear) or,
for Akima, passes through the nodes, and the diagonal lies in the tube of
Dymola's result of the inline-table test with the same table and smoothness
(Test9, Test6, Test3: u1 = u2 = time on [0, 60]).

The files are the MSL's own, found through ``modelica://`` URIs under
a MODELICAPATH root (``library_checks.msl_resources``; the tests skip without it); the
references come from ACAUSAL_REFERENCE_DIR (the tests skip when it lacks
the class).  The models extend the partial models of
``examples/tables_combi_table_2ds.py``.
"""

from __future__ import annotations


import numpy as np
import pytest

from library_checks import assert_in_the_tube, assert_same_run, msl_resources, reference_or_skip

from acausal import Eq, Experiment, Model, simulate, tablefiles, time
from acausal.library.blocks import CombiTable2Ds, CombiTable2Dv, Ramp, Smoothness
from acausal.tools.compare import compare_signals
from examples import tables_combi_table_2ds as combi_table_2ds

#: The MSL 4.1.0 resources laid out as a MODELICAPATH root (Modelica/Resources/Data/Tables/...)
MSL_RESOURCES = msl_resources()

_TABLES = "modelica://Modelica/Resources/Data/Tables/"
_PREFIX = "ModelicaTest.Tables.CombiTable2Ds."

#: MSL 4.1.0, Modelica/Resources/Data/Tables/usertab.h (BSD-3-Clause, Modelica Association):
#: the 2-D table TestTable_2D that Test18_usertab reads through usertab.c
TEST_TABLE_2D = [[0.0, 0.0, 3.0, 6.0],
                 [0.0, -1.0, 4.0, 11.0],
                 [1.0, 3.0, 10.0, 20.0],
                 [1.5, 4.0, 13.0, 20.5],
                 [2.0, 6.0, 15.0, 21.0]]


def _akima2d(file: str, smoothness=Smoothness.LinearSegments) -> dict:
    """The modifiers of a table block reading ``akima2D`` from ``file`` (a MSL resource URI)."""
    return dict(tableOnFile=True, tableName="akima2D", fileName=file, smoothness=smoothness)


# ---------------------------------------------------------------------------
# Test10-14, Test31: TestDer (bilinear) on akima2D, u1 = u2 = time on [0, 60]
# ---------------------------------------------------------------------------


class _OnFile(combi_table_2ds.TestDer):
    """CombiTable2Ds.TestDer reading ``akima2D`` of a file, clock1 -> u1, clock2 -> u2, on [0, 60]."""

    __test__ = False  # a model, not a pytest class
    experiment = Experiment(start_time=0, stop_time=60, interval=0.12)
    drive = "both"
    file = "test.txt"

    @property
    def table_options(self):
        return _akima2d(self.file if "://" in self.file else _TABLES + self.file)


class Test10(_OnFile):
    """MAT-File v4."""

    modelica_class = _PREFIX + "Test10"
    file = "test_v4.mat"


class Test11(_OnFile):
    """MAT-File v6."""

    modelica_class = _PREFIX + "Test11"
    file = "test_v6.mat"


class Test12(_OnFile):
    """MAT-File v7."""

    modelica_class = _PREFIX + "Test12"
    file = "test_v7.mat"


class Test13(_OnFile):
    """MAT-File v7.3 (commented out in the MSL: no reference result)."""

    modelica_class = _PREFIX + "Test13"
    file = "test_v7.3.mat"


class Test14(_OnFile):
    """ASCII Text file."""

    modelica_class = _PREFIX + "Test14"
    file = "test.txt"


class Test31(_OnFile):
    """Text file with UTF-8 BOM and comments (Ticket #2404)."""

    modelica_class = _PREFIX + "Test31"
    file = "modelica://ModelicaTest/Resources/Data/Tables/test_utf8.txt"


class Test18_usertab(combi_table_2ds.TestDer):  # noqa: N801 - the MSL's name
    """Test utilizing the usertab.c interface: ``TestTable_2D``, u1 = ramp to 2, u2 = ramp1 to 6.

    The MSL's ``initial equation dummy = getUsertab(t_new.y)`` only makes
    the tool compile usertab.c: left out.
    """

    __test__ = False
    modelica_class = _PREFIX + "Test18_usertab"
    experiment = Experiment(start_time=0, stop_time=1, interval=0.002)
    table_options = dict(tableOnFile=True, tableName="TestTable_2D")
    drive = "none"

    def build(self):
        super().build()
        self.ramp = Ramp(height=2, duration=1)
        self.ramp1 = Ramp(duration=1, height=6)
        self.connect(self.ramp1.y, self.t_new.u2)
        self.connect(self.ramp.y, self.t_new.u1)


# ---------------------------------------------------------------------------
# Test15-17: the surfaces of akima2D (test_v4.mat)
# ---------------------------------------------------------------------------


class _Surface(Model):
    """The MSL's surface ``Z[i, j] = getTable2DValue(tableID, X[i, j], Y[i, j])`` as table blocks.

    ``X[i, j] = (i - 1)*step``, ``Y[i, j] = (j - 1)*step`` for i = 1..nu,
    j = 1..nv.  ``surface`` (a CombiTable2Dv, n = nv) has u1[j] =
    (nu - 1)*step*time and u2[j] = (j - 1)*step, so at time (i - 1)/(nu - 1)
    (an output point) ``surface.y[j]`` is Z[i, j].  ``t_new`` (a
    CombiTable2Ds) has u1 = u2 = 60*time.
    """

    __test__ = False
    experiment = Experiment(start_time=0, stop_time=1, interval=0.01)
    smoothness = Smoothness.LinearSegments
    nu, nv, step = 101, 81, 0.5
    #: The inline-table test of the same table and smoothness, u1 = u2 = time on [0, 60]
    diagonal_reference = ""

    def build(self):
        options = _akima2d(_TABLES + "test_v4.mat", self.smoothness)
        self.surface = CombiTable2Dv(n=self.nv, **options)
        self.t_new = CombiTable2Ds(**options)

    def equations(self):
        x_max = (self.nu - 1) * self.step
        equations = [Eq(self.t_new.u1, 60 * time), Eq(self.t_new.u2, 60 * time)]
        for j in range(1, self.nv + 1):
            equations += [Eq(getattr(self.surface, f"u1[{j}]"), x_max * time),
                          Eq(getattr(self.surface, f"u2[{j}]"), (j - 1) * self.step)]
        return equations


class Test15(_Surface):
    """Constant 2D surface."""

    modelica_class = _PREFIX + "Test15"
    smoothness = Smoothness.ConstantSegments
    diagonal_reference = _PREFIX + "Test9"


class Test16(_Surface):
    """Bilinear surface."""

    modelica_class = _PREFIX + "Test16"
    smoothness = Smoothness.LinearSegments
    diagonal_reference = _PREFIX + "Test6"


class Test17(_Surface):
    """Akima2D surface (nu = 51, nv = 41 on a grid of step 1)."""

    modelica_class = _PREFIX + "Test17"
    experiment = Experiment(start_time=0, stop_time=1, interval=0.02)
    smoothness = Smoothness.ContinuousDerivative
    nu, nv, step = 51, 41, 1.0
    diagonal_reference = _PREFIX + "Test3"


WITH_REFERENCE = [Test10, Test11, Test12, Test14, Test31, Test18_usertab]
SURFACES = [Test15, Test16, Test17]


@pytest.fixture(autouse=True)
def msl_resources(monkeypatch):
    """MODELICAPATH at the MSL resources, and usertab holding (only) the table of Test18_usertab."""
    if not MSL_RESOURCES.is_dir():
        pytest.skip(f"the MSL 4.1.0 table files are not at {MSL_RESOURCES} (a MODELICAPATH root holding "
                    f"Modelica/Resources/Data/Tables)")
    monkeypatch.setenv("MODELICAPATH", str(MSL_RESOURCES))
    monkeypatch.setattr(tablefiles, "_USERTABS", {})
    tablefiles.register_usertab("TestTable_2D", TEST_TABLE_2D)




def _name(model_class) -> str:
    return model_class.modelica_class.rsplit(".", 1)[-1]


@pytest.mark.parametrize("model_class", WITH_REFERENCE, ids=_name)
def test_matches_reference(model_class):
    """Every compared signal of the reference lies in the tube."""
    assert_in_the_tube(model_class)


def test_mat_v73_gives_the_mat_v4_result():
    """Test13 (MAT v7.3, HDF5) has no reference: its result is Test10's (MAT v4, the same matrix)."""
    pytest.importorskip("h5py", reason="MAT v7.3 files need h5py (pip install acausal[tables])")
    assert_same_run(Test10, Test13, ("t_new.y", "d_t_new.y"))


def test_usertab_table_is_the_one_of_usertab_h():
    """Test18_usertab reads TestTable_2D: bilinear in it, e.g. y(1.25, 4.5) from the four nodes around it."""
    result = simulate(Test18_usertab())
    assert result.success, result.message
    # u1 = 2*time, u2 = 6*time: at time 0.625, u1 = 1.25 (between 1 and 1.5), u2 = 3.75 (between 3 and 6)
    k = int(np.argmin(np.abs(result.time - 0.625)))
    u1, u2 = result.columns["ramp.y"][k], result.columns["ramp1.y"][k]
    a, b = (u1 - 1.0) / 0.5, (u2 - 3.0) / 3.0
    expected = (1 - a) * (1 - b) * 10.0 + a * (1 - b) * 13.0 + (1 - a) * b * 20.0 + a * b * 20.5
    assert result.columns["t_new.y"][k] == pytest.approx(expected, abs=1e-9)


@pytest.fixture(scope="module")
def surfaces():
    """Each surface model's run (once per module)."""
    runs = {}
    with pytest.MonkeyPatch.context() as patch:
        if MSL_RESOURCES.is_dir():
            patch.setenv("MODELICAPATH", str(MSL_RESOURCES))
            for model_class in SURFACES:
                runs[model_class] = simulate(model_class())
    return runs


def _grid(model_class, result):
    """(U1, U2, Z) of the surface, shaped (nu, nv): the inputs and the output of ``surface`` at each output point."""
    assert result.time.size == model_class.nu, "one output point per grid line i"
    columns = result.columns

    def stacked(name):
        return np.array([columns[f"surface.{name}[{j}]"] for j in range(1, model_class.nv + 1)]).T

    return stacked("u1"), stacked("u2"), stacked("y")


def _akima2d_matrix() -> np.ndarray:
    return tablefiles.read_table(_TABLES + "test_v4.mat", "akima2D", verbose=False)


@pytest.mark.parametrize("model_class", SURFACES, ids=_name)
def test_surface_runs_to_the_end(model_class, surfaces):
    """The reference compares ``time`` only: the run reaches the stop time, with the reference's time range."""
    result = surfaces[model_class]
    assert result.success, result.message
    assert result.time[-1] == pytest.approx(model_class.experiment.stop_time)
    reference = reference_or_skip(model_class.modelica_class, required=False)
    if reference is not None:
        assert reference.compared == ()  # comparisonSignals.txt lists time only
        assert reference.start_time == result.time[0]
        assert reference.stop_time == pytest.approx(result.time[-1])
    # the grid: u1 = X[i, j] = (i - 1)*step down the rows, u2 = Y[i, j] = (j - 1)*step along the columns
    u1, u2, _ = _grid(model_class, result)
    np.testing.assert_allclose(u1, np.add.outer(np.arange(model_class.nu) * model_class.step,
                                                np.zeros(model_class.nv)), atol=1e-9)
    np.testing.assert_allclose(u2, np.add.outer(np.zeros(model_class.nu),
                                                np.arange(model_class.nv) * model_class.step), atol=0)


def test_constant_surface(surfaces):
    """Test15: ConstantSegments gives the value of the node at or left/below the point (MSL's C code)."""
    u1, u2, z = _grid(Test15, surfaces[Test15])
    table = _akima2d_matrix()
    x, y, values = table[1:, 0], table[0, 1:], table[1:, 1:]
    i = np.clip(np.searchsorted(x, u1, side="right") - 1, 0, x.size - 1)
    j = np.clip(np.searchsorted(y, u2, side="right") - 1, 0, y.size - 1)
    np.testing.assert_allclose(z, values[i, j], rtol=0, atol=1e-12)
    assert np.unique(z).size <= values.size  # piecewise constant: only table values


def test_bilinear_surface(surfaces):
    """Test16: LinearSegments is bilinear between the four nodes around the point."""
    u1, u2, z = _grid(Test16, surfaces[Test16])
    table = _akima2d_matrix()
    x, y, values = table[1:, 0], table[0, 1:], table[1:, 1:]
    i = np.clip(np.searchsorted(x, u1, side="right") - 1, 0, x.size - 2)
    j = np.clip(np.searchsorted(y, u2, side="right") - 1, 0, y.size - 2)
    a = (u1 - x[i]) / (x[i + 1] - x[i])
    b = (u2 - y[j]) / (y[j + 1] - y[j])
    expected = ((1 - a) * (1 - b) * values[i, j] + a * (1 - b) * values[i + 1, j]
                + (1 - a) * b * values[i, j + 1] + a * b * values[i + 1, j + 1])
    np.testing.assert_allclose(z, expected, rtol=0, atol=1e-9)


def test_akima_surface(surfaces):
    """Test17: the Akima surface passes through the nodes and is not the bilinear one between them."""
    u1, u2, z = _grid(Test17, surfaces[Test17])
    table = _akima2d_matrix()
    x, y, values = table[1:, 0], table[0, 1:], table[1:, 1:]
    # grid step 1, nodes every 5: Z[5k, 5l] is the table's value
    rows = [int(round(v)) for v in x]
    cols = [int(round(v)) for v in y]
    np.testing.assert_allclose(z[np.ix_(rows, cols)], values, rtol=0, atol=1e-9)
    # between the nodes it is a bicubic surface, not the bilinear one (Test16)
    bilinear = _grid(Test16, surfaces[Test16])[2][::2, ::2]  # Test16's grid (step 0.5) at Test17's points
    assert np.max(np.abs(z - bilinear)) > 1.0


@pytest.mark.parametrize("model_class", SURFACES, ids=_name)
def test_surface_diagonal_matches_dymola(model_class, surfaces):
    """``t_new`` (u1 = u2 = 60*time) lies in the tube of Dymola's inline-table test with u1 = u2 = time on [0, 60]."""
    result = surfaces[model_class]
    assert result.success, result.message
    reference = reference_or_skip(model_class.diagonal_reference)
    comparison = compare_signals(reference, 60 * result.time, {"t_new.y": result.columns["t_new.y"]},
                                 signals=["t_new.y"])
    assert comparison.passed, comparison.table()
