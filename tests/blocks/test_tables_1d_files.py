"""ModelicaTest.Tables: the 1-D table tests whose table is read from a file or from usertab.c.

CombiTable1Ds Test18 (a text file line of 2500 columns), Test19/20/21 (MAT
v4, v6, v7), Test23/24 (text file, comma and TAB separated), Test33 (UTF-8
text with BOM and comments), Test25_usertab (a table of MSL's usertab.h) and
CombiTimeTable Test50 (the long line again) lie in the csv-compare tube of
the MSL 4.1.0 reference results.  Test22 (MAT v7.3, HDF5) has no reference:
it gives the same result as Test21 (v7), the same matrix.

The files are the MSL's own, found through ``modelica://`` URIs under
a MODELICAPATH root (``library_checks.msl_resources``; the tests skip without it); the
references come from ACAUSAL_REFERENCE_DIR (the tests skip when it lacks
the class).  The models extend the partial models of
``examples/tables_combi_table_1ds.py`` and ``examples/tables_combi_time_table.py``.
"""

from __future__ import annotations


import pytest

from library_checks import assert_in_the_tube, assert_same_run, msl_resources

from acausal import Experiment
from acausal import tablefiles
from acausal.library.blocks import Der
from examples import tables_combi_table_1ds as combi_table_1ds
from examples import tables_combi_time_table as combi_time_table

#: The MSL 4.1.0 resources laid out as a MODELICAPATH root (Modelica/Resources/Data/Tables/...)
MSL_RESOURCES = msl_resources()

_TABLES = "modelica://Modelica/Resources/Data/Tables/"
_PREFIX = "ModelicaTest.Tables.CombiTable1Ds."

#: MSL 4.1.0, Modelica/Resources/Data/Tables/usertab.h (BSD-3-Clause, Modelica Association):
#: the 1-D table TestTable_1D_b that Test25_usertab reads through usertab.c
TEST_TABLE_1D_B = [[0.0, 0.0, 0.0],
                   [1.0, 2.0, 0.5],
                   [2.0, 3.0, 1.0],
                   [3.0, 5.0, 2.0],
                   [4.0, 7.0, 4.5]]


class _OnFile(combi_table_1ds.TestDer):
    """CombiTable1Ds.TestDer reading table ``a`` of a file, from 0 to 100 s (Test19-24, 33)."""

    __test__ = False  # a model, not a pytest class
    experiment = Experiment(start_time=0, stop_time=100, interval=0.2)
    file = "test.txt"

    @property
    def table_modifiers(self):
        return dict(tableOnFile=True, tableName="a", fileName=_TABLES + self.file)


class Test18(combi_table_1ds.TestDer):
    """ASCII Text file (Very long line length): columns 2 and 2500 of ``longLine``."""

    __test__ = False
    modelica_class = _PREFIX + "Test18"
    experiment = Experiment(start_time=0, stop_time=1, interval=0.002)
    table_modifiers = dict(tableOnFile=True, tableName="longLine", fileName=_TABLES + "test.txt",
                           columns=[2, 2500])

    def build(self):
        super().build()
        self.d_t_new2 = Der()
        self.connect(getattr(self.t_new, "y[2]"), self.d_t_new2.u)


class Test19(_OnFile):
    """MAT-File v4."""

    modelica_class = _PREFIX + "Test19"
    file = "test_v4.mat"


class Test20(_OnFile):
    """MAT-File v6."""

    modelica_class = _PREFIX + "Test20"
    file = "test_v6.mat"


class Test21(_OnFile):
    """MAT-File v7."""

    modelica_class = _PREFIX + "Test21"
    file = "test_v7.mat"


class Test22(_OnFile):
    """MAT-File v7.3 (commented out in the MSL: no reference result)."""

    modelica_class = _PREFIX + "Test22"
    file = "test_v7.3.mat"


class Test23(_OnFile):
    """ASCII Text file."""

    modelica_class = _PREFIX + "Test23"


class Test24(_OnFile):
    """ASCII Text file (TAB separated): table ``a_tab``."""

    modelica_class = _PREFIX + "Test24"
    table_modifiers = dict(tableOnFile=True, tableName="a_tab", fileName=_TABLES + "test.txt")


class Test33(_OnFile):
    """Text file with UTF-8 BOM and comments (Ticket #2404)."""

    modelica_class = _PREFIX + "Test33"
    table_modifiers = dict(tableOnFile=True, tableName="a",
                           fileName="modelica://ModelicaTest/Resources/Data/Tables/test_utf8.txt")


class Test25_usertab(combi_table_1ds.TestDer):  # noqa: N801 - the MSL's name
    """Test utilizing the usertab.c interface: ``TestTable_1D_b``, columns 2 and 3.

    The MSL's ``initial equation dummy = getUsertab(t_new.y)`` only makes
    the tool compile usertab.c: left out.
    """

    __test__ = False
    modelica_class = _PREFIX + "Test25_usertab"
    experiment = Experiment(start_time=0, stop_time=4, interval=0.008)
    table_modifiers = dict(tableOnFile=True, tableName="TestTable_1D_b", columns=[2, 3])


class TimeTableTest50(combi_time_table.TestDer):
    """CombiTimeTable Test50: ASCII Text file (Very long line length)."""

    __test__ = False
    modelica_class = "ModelicaTest.Tables.CombiTimeTable.Test50"
    experiment = Experiment(start_time=0, stop_time=1, interval=0.002)
    table_modifiers = dict(tableOnFile=True, tableName="longLine", fileName=_TABLES + "test.txt",
                           columns=[2, 2500])


WITH_REFERENCE = [Test18, Test19, Test20, Test21, Test23, Test24, Test33, Test25_usertab, TimeTableTest50]


@pytest.fixture(autouse=True)
def msl_resources(monkeypatch):
    """MODELICAPATH at the MSL resources, and usertab holding (only) the table of Test25_usertab."""
    if not MSL_RESOURCES.is_dir():
        pytest.skip(f"the MSL 4.1.0 table files are not at {MSL_RESOURCES} (a MODELICAPATH root holding "
                    f"Modelica/Resources/Data/Tables)")
    monkeypatch.setenv("MODELICAPATH", str(MSL_RESOURCES))
    monkeypatch.setattr(tablefiles, "_USERTABS", {})
    tablefiles.register_usertab("TestTable_1D_b", TEST_TABLE_1D_B)




@pytest.mark.parametrize("model_class", WITH_REFERENCE,
                         ids=[c.modelica_class.removeprefix("ModelicaTest.Tables.") for c in WITH_REFERENCE])
def test_matches_reference(model_class):
    """Every compared signal of the reference lies in the tube."""
    assert_in_the_tube(model_class)


def test_mat_v73_gives_the_mat_v7_result():
    """Test22 (MAT v7.3, HDF5) has no reference: its result is Test21's (MAT v7, the same matrix)."""
    pytest.importorskip("h5py", reason="MAT v7.3 files need h5py (pip install acausal[tables])")
    assert_same_run(Test21, Test22, ("t_new.y[1]", "d_t_new.y"))
