"""ModelicaTest.Tables.CombiTable2Ds: the MSL 4.1.0 tests of the 2-D table block with an inline table.

The Modelica Standard Library tests ``Modelica.Blocks.Tables.CombiTable2Ds``
with the models ``ModelicaTest.Tables.CombiTable2Ds.Test1 ... Test33``.  This
file reproduces those whose table is given inline in the model, each under its
MSL name and with the experiment of its annotation:

* Test1-9: a table of 11 x 9 values on [0, 50] x [0, 40], its inputs driven
  by a clock and a constant 2 (or two clocks) on [0, 60], so that u1, u2 or
  both leave the table's range: Akima (ContinuousDerivative, two ``Der``
  blocks after the table: TestDer2), bilinear (LinearSegments, one ``Der``:
  TestDer) and ConstantSegments (no ``Der``: Test).
* Test19-21: tables with a single row or column of values (and their
  transposes), in 2-D and as a CombiTable1Ds, with ConstantSegments, bilinear
  and Akima interpolation (Ticket #1307).
* Test22-23: Akima extrapolation of u1 xor u2 to the left and right, and its
  derivative (Ticket #1465).
* Test24-30: Akima on tables of 2 to 4 rows and columns (Ticket #1820).

The tests that read their table from a file (Test10-17, Test31) or from
``usertab.c`` (Test18_usertab) are in ``tests/blocks/test_tables_2d_files.py``;
Test32 (CSV file), Test33 and OneSidedDerivative2D have no reference results
in MAP-LIB_ReferenceResults v4.1.0.

The partial models ``Test``, ``TestDer`` and ``TestDer2`` of the MSL are the
classes :class:`Test`, :class:`TestDer` and :class:`TestDer2` here; a test
gives the table block's modifiers (``table_options``) and which inputs the
clock drives (``drive``).

Run ``acausal compare examples/tables_combi_table_2ds.py`` to check every test
against the MSL reference results (``...py:Test1`` for one), with
``ACAUSAL_REFERENCE_DIR`` pointing at a MAP-LIB_ReferenceResults v4.1.0 folder.
"""

from math import pi

from acausal import Experiment, Model
from acausal.library.blocks import (CombiTable1Ds, CombiTable2Ds, Constant, ContinuousClock, Der, Sine,
                                    Smoothness)

#: The table of Test1-9 (u1 = 0, 5, ..., 50 down the first column, u2 = 0, 5, ..., 40 along the first row).
TABLE = [
    [0, 0, 5, 10, 15, 20, 25, 30, 35, 40],
    [0, 58.2, 61.5, 47.9, 62.3, 34.6, 45.5, 38.2, 41.2, 41.7],
    [5, 37.2, 40, 27, 41.3, 14.1, 24.5, 17.3, 20.2, 20.8],
    [10, 22.4, 22.5, 14.6, 22.5, 4.7, 7.2, 1.8, 2.1, 2.1],
    [15, 21.8, 20.5, 12.8, 17.6, 5.8, 7.6, 0.8, 0.6, 0.6],
    [20, 16.8, 14.4, 8.1, 6.9, 6.2, 0.6, 0.1, 0, 0],
    [25, 12, 8, 5.3, 2.9, 0.6, 0, 0, 0, 0],
    [30, 7.4, 4.8, 1.4, 0.1, 0, 0, 0, 0, 0],
    [35, 3.2, 0.7, 0, 0, 0, 0, 0, 0, 0],
    [40, 0, 0, 0, 0, 0, 0, 0, 0, 0],
    [45, 0, 0, 0, 0, 0, 0, 0, 0, 0],
    [50, 0, 0, 0, 0, 0, 0, 0, 0, 0],
]


def transpose(matrix):
    """Modelica's ``transpose`` of a table given as a list of rows."""
    return [list(column) for column in zip(*matrix)]


def _experiment(stop_time, start_time=0.0, points=500):
    return Experiment(start_time=start_time, stop_time=stop_time, interval=(stop_time - start_time) / points)


# ---------------------------------------------------------------------------
# The partial models of the MSL package: Test, TestDer, TestDer2
# ---------------------------------------------------------------------------


class Test(Model):
    """partial model Test: the table block ``t_new``, whose inputs the clock drives.

    ``drive`` says which inputs: ``"u1"`` (``clock`` -> u1, ``const`` (k = 2) ->
    u2), ``"u2"`` (``const`` -> u1, ``clock`` -> u2) or ``"both"`` (``clock1``
    -> u1, ``clock2`` -> u2); ``"none"`` leaves them to the subclass.
    """

    __test__ = False  # not a pytest test class when imported into a test module
    table_options: dict = {}
    drive = "both"

    def options(self) -> dict:
        """The modifiers of ``t_new``."""
        return self.table_options

    def build(self):
        self.t_new = CombiTable2Ds(**self.options())
        if self.drive == "u1":
            self.clock = ContinuousClock()
            self.const = Constant(k=2)
            self.connect(self.clock.y, self.t_new.u1)
            self.connect(self.const.y, self.t_new.u2)
        elif self.drive == "u2":
            self.const = Constant(k=2)
            self.clock = ContinuousClock()
            self.connect(self.const.y, self.t_new.u1)
            self.connect(self.clock.y, self.t_new.u2)
        elif self.drive == "both":
            self.clock1 = ContinuousClock()
            self.clock2 = ContinuousClock()
            self.connect(self.clock1.y, self.t_new.u1)
            self.connect(self.clock2.y, self.t_new.u2)


class TestDer(Test):
    """partial model TestDer: Test with ``d_t_new = der(t_new.y)``."""

    def build(self):
        super().build()
        self.d_t_new = Der()
        self.connect(self.t_new.y, self.d_t_new.u)


class TestDer2(TestDer):
    """partial model TestDer2: TestDer with ``d2_t_new = der(d_t_new.y)``."""

    def build(self):
        super().build()
        self.d2_t_new = Der()
        self.connect(self.d_t_new.y, self.d2_t_new.u)


def _akima(table):
    """The modifiers of an Akima (ContinuousDerivative) table."""
    return {"table": table, "smoothness": Smoothness.ContinuousDerivative}


AKIMA = _akima(TABLE)
BILINEAR = {"table": TABLE}  # LinearSegments, the default
CONSTANT = {"table": TABLE, "smoothness": Smoothness.ConstantSegments}


# ---------------------------------------------------------------------------
# Test1-9: the 11x9 table, Akima, bilinear and constant segments
# ---------------------------------------------------------------------------


class Test1(TestDer2):
    """Akima, u1 extrapolation."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test1"
    experiment = _experiment(60)
    table_options, drive = AKIMA, "u1"


class Test2(TestDer2):
    """Akima, u2 extrapolation."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test2"
    experiment = _experiment(60)
    table_options, drive = AKIMA, "u2"


class Test3(TestDer2):
    """Akima, u1 and u2 extrapolation."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test3"
    experiment = _experiment(60)
    table_options, drive = AKIMA, "both"


class Test4(TestDer):
    """Bilinear, u1 extrapolation."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test4"
    experiment = _experiment(60)
    table_options, drive = BILINEAR, "u1"


class Test5(TestDer):
    """Bilinear, u2 extrapolation."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test5"
    experiment = _experiment(60)
    table_options, drive = BILINEAR, "u2"


class Test6(TestDer):
    """Bilinear, u1 and u2 extrapolation."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test6"
    experiment = _experiment(60)
    table_options, drive = BILINEAR, "both"


class Test7(Test):
    """Constant segments, u1 extrapolation."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test7"
    experiment = _experiment(60)
    table_options, drive = CONSTANT, "u1"


class Test8(Test):
    """Constant segments, u2 extrapolation."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test8"
    experiment = _experiment(60)
    table_options, drive = CONSTANT, "u2"


class Test9(Test):
    """Constant segments, u1 and u2 extrapolation."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test9"
    experiment = _experiment(60)
    table_options, drive = CONSTANT, "both"


# ---------------------------------------------------------------------------
# Test19-21: one row or column of values, 2-D against 1-D (Ticket #1307)
# ---------------------------------------------------------------------------

#: Test19-21's tables: one value column (u2 = 1 only) and two (u2 = 0, 6).
ONE_COLUMN = [[1, 1], [2, 4], [3, 9], [4, 16]]
TWO_COLUMNS = [[1, 0, 6], [2, 4, 4], [3, 9, 9], [4, 16, 16]]


class _Ticket1307(Model):
    """Test19-21: the clock drives both inputs of four 2-D tables and the input of a 1-D table.

    ``combiTable2D1D`` has one value column, ``combiTable2D1DT`` is its
    transpose (one value row), ``combiTable1D`` the 1-D table that
    ``combiTable2D1D`` reduces to for u1 >= 2; ``combiTable2D`` and
    ``combiTable2DT`` have two value columns (rows).  With ``ders``, a
    ``Der`` block after each table (``der1 ... der5``).
    """

    smoothness = Smoothness.LinearSegments
    ders = True

    def build(self):
        s = self.smoothness
        self.combiTable2D1D = CombiTable2Ds(table=ONE_COLUMN, smoothness=s)
        self.combiTable2D1DT = CombiTable2Ds(table=transpose(ONE_COLUMN), smoothness=s)
        self.clock1 = ContinuousClock()
        self.combiTable1D = CombiTable1Ds(table=ONE_COLUMN[1:], smoothness=s)
        self.combiTable2D = CombiTable2Ds(table=TWO_COLUMNS, smoothness=s)
        self.combiTable2DT = CombiTable2Ds(table=transpose(TWO_COLUMNS), smoothness=s)
        self.connect(self.clock1.y, self.combiTable1D.u)
        outputs = [self.combiTable2D1D.y, self.combiTable2D1DT.y, getattr(self.combiTable1D, "y[1]"),
                   self.combiTable2D.y, self.combiTable2DT.y]
        for table in (self.combiTable2D1D, self.combiTable2D1DT, self.combiTable2D, self.combiTable2DT):
            self.connect(self.clock1.y, table.u1)
            self.connect(self.clock1.y, table.u2)
        if self.ders:
            for k, output in enumerate(outputs, 1):
                der = Der()
                setattr(self, f"der{k}", der)
                self.connect(output, der.u)


class Test19(_Ticket1307):
    """Constant 2D (Ticket #1307)."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test19"
    experiment = _experiment(6)
    smoothness, ders = Smoothness.ConstantSegments, False


class Test20(_Ticket1307):
    """Bilinear (Ticket #1307)."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test20"
    experiment = _experiment(6)
    smoothness = Smoothness.LinearSegments


class Test21(_Ticket1307):
    """Akima2D (Ticket #1307)."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test21"
    experiment = _experiment(6)
    smoothness = Smoothness.ContinuousDerivative


# ---------------------------------------------------------------------------
# Test22-23: Akima extrapolation of u1 xor u2 (Ticket #1465)
# ---------------------------------------------------------------------------

#: Table matrix for right extrapolation.
TABLE_R = [[0, 75, 83, 88], [18, 778, 773, 769], [28, 970, -950, 938], [33, 860, 1030, 1039]]
#: Table matrix for left extrapolation.
TABLE_L = [[0, 75, 80, 88], [18, 1039, 1030, 860], [23, 938, -950, 970], [33, 769, 773, 778]]


class Test22(Model):
    """Akima extrapolation of either u1 xor u2 (Ticket #1465).

    Four Akima tables, each followed by a ``Der`` block: ``combiTable2D_1R``
    (table R) and ``combiTable2D_2R`` (its transpose) are extrapolated to the
    right in u1 and u2 by the first source, the other input held by the
    second; ``combiTable2D_1L`` and ``combiTable2D_2L`` to the left by the
    third source, the other input held by the fourth (``sources()``, as
    (name, block); Test23 changes them).
    """

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test22"
    experiment = _experiment(1)

    def sources(self):
        return (("sine_R", Sine(amplitude=3, f=0.5, phase=pi / 2, offset=33)),
                ("const_R", Constant(k=81)),
                ("sine_L", Sine(amplitude=-3, f=0.5, phase=pi / 2, offset=18)),
                ("const_L", Constant(k=82)))

    def build(self):
        akima = Smoothness.ContinuousDerivative
        self.combiTable2D_1R = CombiTable2Ds(table=TABLE_R, smoothness=akima)
        self.der_1R = Der()
        self.combiTable2D_2R = CombiTable2Ds(table=transpose(TABLE_R), smoothness=akima)
        self.der_2R = Der()
        self.combiTable2D_1L = CombiTable2Ds(table=TABLE_L, smoothness=akima)
        self.der_1L = Der()
        self.combiTable2D_2L = CombiTable2Ds(table=transpose(TABLE_L), smoothness=akima)
        self.der_2L = Der()
        sources = self.sources()
        for name, block in sources:
            setattr(self, name, block)
        (_, a_r), (_, b_r), (_, a_l), (_, b_l) = sources
        for side, a, b in (("R", a_r, b_r), ("L", a_l, b_l)):
            table_1 = getattr(self, f"combiTable2D_1{side}")
            table_2 = getattr(self, f"combiTable2D_2{side}")
            self.connect(a.y, table_1.u1)
            self.connect(b.y, table_1.u2)
            self.connect(b.y, table_2.u1)
            self.connect(a.y, table_2.u2)
            self.connect(table_1.y, getattr(self, f"der_1{side}").u)
            self.connect(table_2.y, getattr(self, f"der_2{side}").u)


class Test23(Test22):
    """Derivative of Akima extrapolation (Ticket #1465): Test22 with a fast cosine and a slow sine."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test23"
    experiment = _experiment(4)

    def sources(self):
        return (("cosine_R", Sine(amplitude=3, f=10, phase=pi / 2, offset=33)),
                ("sine_R", Sine(amplitude=10, f=1 / 3, offset=81, startTime=1)),
                ("cosine_L", Sine(amplitude=-3, f=10, phase=pi / 2, offset=18)),
                ("sine_L", Sine(amplitude=-10, f=1 / 3, offset=82, startTime=1)))


# ---------------------------------------------------------------------------
# Test24-30: Akima on small tables (Ticket #1820)
# ---------------------------------------------------------------------------


class _Ticket1820(TestDer2):
    """Test24-30: Akima on a table of 2 to 4 rows and columns, u1 = u2 = time on [0, 1]."""

    experiment = _experiment(1)
    drive = "both"


class Test24(_Ticket1820):
    """2x3 table, Akima (Ticket #1820)."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test24"
    table_options = _akima([[0, 0, 1], [0.5, 1, 2]])


class Test25(_Ticket1820):
    """3x2 table, Akima (Ticket #1820)."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test25"
    table_options = _akima([[0, 0.5], [0, 1], [1, 2]])


class Test26(_Ticket1820):
    """2x4 table, Akima (Ticket #1820)."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test26"
    table_options = _akima([[0, 0, 0.5, 1], [0.5, 1, 2, 1]])


class Test27(_Ticket1820):
    """4x2 table, Akima (Ticket #1820)."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test27"
    table_options = _akima([[0, 0.5], [0, 1], [0.5, 2], [1, 1]])


class Test28(_Ticket1820):
    """3x3 table, Akima (Ticket #1820)."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test28"
    table_options = _akima([[0, 0, 1], [0, 0, 1], [1, 1, 1]])


class Test29(_Ticket1820):
    """3x4 table, Akima (Ticket #1820)."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test29"
    table_options = _akima([[0, 0, 0.5, 1], [0, 1, 2, 1], [1, 1, 1, 1]])


class Test30(_Ticket1820):
    """4x3 table, Akima (Ticket #1820)."""

    modelica_class = "ModelicaTest.Tables.CombiTable2Ds.Test30"
    table_options = _akima([[0, 0, 1], [0, 1, 1], [0.5, 2, 1], [1, 1, 1]])

