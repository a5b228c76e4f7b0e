"""ModelicaTest.Tables.CombiTable1Ds: the MSL 4.1.0 tests of the 1-D table block with an inline table.

Each test feeds a ``ContinuousClock`` (``y = time``) into a
``CombiTable1Ds`` ``t_new`` and differentiates its first output once
(``TestDer``: ``d_t_new``) or twice (``TestDer2``: ``d2_t_new``), as the
MSL's partial models ``Test``, ``TestDer`` and ``TestDer2``: single-row
tables (Test1, 2, 29), linear interpolation with LastTwoPoints extrapolation
(Test7, 8, 11, 12), Akima (Test3-6, 15, 16, 29), Fritsch-Butland (Test26-28),
Steffen (Test30-32) and modified Akima (Test34).  The tests whose table is
read from a file or from usertab.c (Test18-25, 33) are in
``tests/blocks/test_tables_1d_files.py``; Test35 has no reference result.

Run ``acausal compare examples/tables_combi_table_1ds.py`` (or
``...py:Test3`` for one test) with ``ACAUSAL_REFERENCE_DIR`` pointing at
the MSL 4.1.0 reference results to check them.
"""

from acausal import Experiment, Model
from acausal.library.blocks import CombiTable1Ds, ContinuousClock, Der, Smoothness

__all__ = ["Test1", "Test2", "Test3", "Test4", "Test5", "Test6", "Test7", "Test8", "Test11", "Test12", "Test15",
           "Test16", "Test26", "Test27", "Test28", "Test29", "Test30", "Test31", "Test32", "Test34"]

_PREFIX = "ModelicaTest.Tables.CombiTable1Ds."


def _experiment(start: float, stop: float) -> Experiment:
    return Experiment(start_time=start, stop_time=stop, interval=(stop - start) / 500)


class Test(Model):
    """The MSL's partial model ``Test``: ``clock.y`` drives ``t_new.u``.

    A subclass gives the table's modifiers in ``table_modifiers``.
    """

    table_modifiers: dict = {}

    def build(self):
        self.t_new = CombiTable1Ds(**self.table_modifiers)
        self.clock = ContinuousClock()
        self.connect(self.clock.y, self.t_new.u)


class TestDer(Test):
    """``Test`` with ``d_t_new = der(t_new.y[1])``."""

    def build(self):
        super().build()
        self.d_t_new = Der()
        self.connect(self.t_new.y[1], self.d_t_new.u)


class TestDer2(TestDer):
    """``TestDer`` with ``d2_t_new = der(d_t_new.y)``."""

    def build(self):
        super().build()
        self.d2_t_new = Der()
        self.connect(self.d_t_new.y, self.d2_t_new.u)

    def differentiate_second_output(self) -> None:
        """``t_new.y[2]`` differentiated twice too (``d_t_new2``, ``d2_t_new2``: Test4, 6, 29)."""
        self.d_t_new2 = Der()
        self.d2_t_new2 = Der()
        self.connect(self.t_new.y[2], self.d_t_new2.u)
        self.connect(self.d_t_new2.y, self.d2_t_new2.u)


_AKIMA = Smoothness.ContinuousDerivative
_FRITSCH_BUTLAND = Smoothness.MonotoneContinuousDerivative1
_STEFFEN = Smoothness.MonotoneContinuousDerivative2
_THREE_COLUMNS = [[0.3, 0, 0], [0.4, 1, -1], [0.5, 0, 0], [0.6, -1, 1], [0.7, 0, 0]]
_TICKET_1039 = [[0, 5], [1, 3], [2, 1], [3, 1], [4, 1], [5, 3]]
_AKIMA_3 = [[0, 10], [2, 10], [3, 10], [5, 10], [6, 10], [8, 10], [9, 10.5], [11, 15], [12, 50], [14, 60], [15, 85]]
_RPN_14 = [[7.99, 0], [8.09, 2.76429e-5], [8.19, 4.37498e-2], [8.7, 0.169183], [9.2, 0.469428], [10, 0.94374],
           [12, 0.998636], [15, 0.999919], [20, 0.999994]]


class Test1(TestDer):
    """Single row, t_min = 0."""

    modelica_class = _PREFIX + "Test1"
    experiment = _experiment(0, 2.5)
    table_modifiers = dict(table=[[0, 1]])


class Test2(TestDer):
    """Single row, t_min > 0."""

    modelica_class = _PREFIX + "Test2"
    experiment = _experiment(0, 2.5)
    table_modifiers = dict(table=[[0.5, 1]])


class Test3(TestDer2):
    """Two columns, Akima."""

    modelica_class = _PREFIX + "Test3"
    experiment = _experiment(0, 1)
    table_modifiers = dict(table=[[0.3, 0], [0.4, 1], [0.5, 0], [0.6, -1], [0.7, 0]], smoothness=_AKIMA)


class Test4(TestDer2):
    """Three columns, Akima."""

    modelica_class = _PREFIX + "Test4"
    experiment = _experiment(0, 1)
    table_modifiers = dict(table=_THREE_COLUMNS, smoothness=_AKIMA)

    def build(self):
        super().build()
        self.differentiate_second_output()


class Test5(TestDer2):
    """Third column, Akima."""

    modelica_class = _PREFIX + "Test5"
    experiment = _experiment(0, 1)
    table_modifiers = dict(table=_THREE_COLUMNS, columns=[3], smoothness=_AKIMA)


class Test6(TestDer2):
    """Three columns, Akima (columns = {2, 3})."""

    modelica_class = _PREFIX + "Test6"
    experiment = _experiment(0, 1)
    table_modifiers = dict(table=_THREE_COLUMNS, columns=[2, 3], smoothness=_AKIMA)

    def build(self):
        super().build()
        self.differentiate_second_output()


class Test7(TestDer):
    """Two rows, t_min = 0."""

    modelica_class = _PREFIX + "Test7"
    experiment = _experiment(0, 2.5)
    table_modifiers = dict(table=[[0, 1], [1, 0]])


class Test8(TestDer):
    """Two rows, t_min > 0."""

    modelica_class = _PREFIX + "Test8"
    experiment = _experiment(0, 2.5)
    table_modifiers = dict(table=[[0.25, 1], [1.25, 0]])


class Test11(TestDer):
    """Three rows, t_min = 0."""

    modelica_class = _PREFIX + "Test11"
    experiment = _experiment(0, 2.5)
    table_modifiers = dict(table=[[0, 1], [0.5, 2], [1, 0]])


class Test12(TestDer):
    """Three rows, "t_min > 0" (the MSL's table is that of Test11)."""

    modelica_class = _PREFIX + "Test12"
    experiment = _experiment(0, 2.5)
    table_modifiers = dict(table=[[0, 1], [0.5, 2], [1, 0]])


class Test15(TestDer2):
    """Problematic Akima."""

    modelica_class = _PREFIX + "Test15"
    experiment = _experiment(0, 3)
    table_modifiers = dict(table=_TICKET_1039, smoothness=_AKIMA)


class Test16(TestDer2):
    """Problematic Akima, flipped."""

    modelica_class = _PREFIX + "Test16"
    experiment = _experiment(0, 3)
    table_modifiers = dict(table=[[0, 3], [1, 1], [2, 1], [3, 1], [4, 3], [5, 5]], smoothness=_AKIMA)


class Test26(TestDer2):
    """Fritsch-Butland, test data set (Ticket #1039)."""

    modelica_class = _PREFIX + "Test26"
    experiment = _experiment(0, 4)
    table_modifiers = dict(table=_TICKET_1039, smoothness=_FRITSCH_BUTLAND)


class Test27(TestDer2):
    """Fritsch-Butland, data set AKIMA 3 (Ticket #1717)."""

    modelica_class = _PREFIX + "Test27"
    experiment = _experiment(0, 15)
    table_modifiers = dict(table=_AKIMA_3, smoothness=_FRITSCH_BUTLAND)


class Test28(TestDer2):
    """Fritsch-Butland, data set RPN 14 (Ticket #1717)."""

    modelica_class = _PREFIX + "Test28"
    experiment = _experiment(7.99, 20)
    table_modifiers = dict(table=_RPN_14, smoothness=_FRITSCH_BUTLAND)


class Test29(TestDer2):
    """Single row, Akima (Ticket #1820)."""

    modelica_class = _PREFIX + "Test29"
    experiment = _experiment(0, 1)
    table_modifiers = dict(table=[[0, 1, 2]], smoothness=_AKIMA)

    def build(self):
        super().build()
        self.differentiate_second_output()


class Test30(TestDer2):
    """Steffen, test data set (Ticket #1814)."""

    modelica_class = _PREFIX + "Test30"
    experiment = _experiment(0, 4)
    table_modifiers = dict(table=_TICKET_1039, smoothness=_STEFFEN)


class Test31(TestDer2):
    """Steffen, data set AKIMA 3 (Ticket #1814)."""

    modelica_class = _PREFIX + "Test31"
    experiment = _experiment(0, 15)
    table_modifiers = dict(table=_AKIMA_3, smoothness=_STEFFEN)


class Test32(TestDer2):
    """Steffen, data set RPN 14 (Ticket #1814)."""

    modelica_class = _PREFIX + "Test32"
    experiment = _experiment(7.99, 20)
    table_modifiers = dict(table=_RPN_14, smoothness=_STEFFEN)


class Test34(TestDer2):
    """Modified Akima, test data set (Ticket #1039)."""

    modelica_class = _PREFIX + "Test34"
    experiment = _experiment(0, 4)
    table_modifiers = dict(table=_TICKET_1039, smoothness=Smoothness.ModifiedContinuousDerivative)
