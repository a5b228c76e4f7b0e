"""ModelicaTest.Tables.CombiTimeTable: the MSL 4.1.0 tests of the time table with an inline table.

As the MSL's partial models ``Test``, ``TestDer`` and ``TestDer2``, most
tests differentiate the first output of a ``CombiTimeTable`` ``t_new`` once
(``d_t_new``) or twice (``d2_t_new``):

* Test1: jumps (repeated times) and Periodic extrapolation, t_min > 0;
* Test4: Akima (Ticket #1028);
* Test68: no internal time event, startTime > t_min > 0 (Ticket #1619);
* Test73, Test77: Fritsch-Butland and Steffen beside Akima (``t_new_2``);
* Test83: the simulation starts at the table's end, t_max (Ticket #2233),
  with a ``BooleanTable`` (built as MSL 4.1 builds it: a ConstantSegments
  ``combiTimeTable`` and a ``realToBoolean``, whose signals the reference
  compares);
* Test87: modified Akima, Akima, Fritsch-Butland and Steffen on one table.

Test50 reads its table from a file: it is in
``tests/blocks/test_tables_1d_files.py``.

Run ``acausal compare examples/tables_combi_time_table.py`` to check them
against the MSL reference results (they ship with acausal).
"""

from acausal import Experiment, Model
from acausal.library.blocks import BooleanTable, CombiTimeTable, Der, Extrapolation, Smoothness

__all__ = ["Test1", "Test4", "Test68", "Test73", "Test77", "Test83", "Test87"]

_PREFIX = "ModelicaTest.Tables.CombiTimeTable."


def _experiment(start: float, stop: float) -> Experiment:
    return Experiment(start_time=start, stop_time=stop, interval=(stop - start) / 500)


class Test(Model):
    """The MSL's partial model ``Test``: a ``CombiTimeTable`` ``t_new`` with ``table_modifiers``."""

    table_modifiers: dict = {}

    def build(self):
        self.t_new = CombiTimeTable(**self.table_modifiers)


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

    def differentiated_twice(self, suffix: str, **modifiers) -> None:
        """One more table ``t_new<suffix>`` with ``d_t_new<suffix>`` and ``d2_t_new<suffix>`` after it."""
        table, d, d2 = CombiTimeTable(**modifiers), Der(), Der()
        setattr(self, f"t_new{suffix}", table)
        setattr(self, f"d_t_new{suffix}", d)
        setattr(self, f"d2_t_new{suffix}", d2)
        self.connect(table.y[1], d.u)
        self.connect(d.y, d2.u)


_TICKET_1039 = [[0, 5], [1, 3], [2, 1], [3, 1], [4, 1], [5, 3]]


class Test1(TestDer):
    """Periodic, t_min > 0."""

    modelica_class = _PREFIX + "Test1"
    experiment = _experiment(0, 2.5)
    table_modifiers = dict(table=[[0.1, 0], [0.3, 0], [0.5, -1], [0.51, -2], [0.51, -3], [0.6, -2], [0.7, -2],
                                  [0.7, -2], [1, -4]], extrapolation=Extrapolation.Periodic)


class Test4(TestDer2):
    """Two columns, Akima (Ticket #1028)."""

    modelica_class = _PREFIX + "Test4"
    experiment = _experiment(0, 1)
    table_modifiers = dict(table=[[0.3, 0], [0.4, 1], [0.5, 0], [0.6, -1], [0.7, 0]],
                           smoothness=Smoothness.ContinuousDerivative)


class Test68(Model):
    """No internal event, startTime > t_min > 0 (Ticket #1619)."""

    modelica_class = _PREFIX + "Test68"
    experiment = _experiment(0, 8000)
    table = [[9.81594, 0], [90.7974, 7.2727], [181.5948, 23.1818], [279.7548, 43.6364], [382.8222, 67.2732],
             [478.5276, 88.1822], [623.31, 109.5452], [746.01, 125.4542], [895.704, 141.3632],
             [1013.496, 149.0912], [1057.668, 169.5452], [1121.472, 179.5452], [1207.362, 191.8182],
             [1332.516, 205.4542], [1442.946, 214.0912], [1604.91, 224.0912], [1747.242, 231.8182],
             [1943.556, 240.9092], [2157.054, 248.6362], [2346.012, 256.8182], [2544.786, 264.5452],
             [2760.738, 274.0912], [3190.182, 292.7272], [3418.404, 303.1822], [3663.804, 312.7272],
             [3909.204, 322.7272], [4053.99, 326.8182], [4164.42, 331.8182]]

    def build(self):
        self.startTime_0 = CombiTimeTable(table=self.table, extrapolation=Extrapolation.HoldLastPoint,
                                          offset=[33.1818])
        self.startTime = CombiTimeTable(table=self.table, extrapolation=Extrapolation.HoldLastPoint,
                                        offset=[33.1818], startTime=2000)


class Test73(TestDer2):
    """Fritsch-Butland, test data set (Ticket #1039), and Akima (``t_new_2``)."""

    modelica_class = _PREFIX + "Test73"
    experiment = _experiment(0, 4)
    table_modifiers = dict(table=_TICKET_1039, smoothness=Smoothness.MonotoneContinuousDerivative1)

    def build(self):
        super().build()
        self.differentiated_twice("_2", table=_TICKET_1039, smoothness=Smoothness.ContinuousDerivative)


class Test77(TestDer2):
    """Steffen, test data set (Ticket #1814), and Akima (``t_new_2``)."""

    modelica_class = _PREFIX + "Test77"
    experiment = _experiment(0, 4)
    table_modifiers = dict(table=_TICKET_1039, smoothness=Smoothness.MonotoneContinuousDerivative2)

    def build(self):
        super().build()
        self.differentiated_twice("_2", table=_TICKET_1039, smoothness=Smoothness.ContinuousDerivative)


class Test83(Model):
    """Simulation StartTime = t_max (Ticket #2233)."""

    modelica_class = _PREFIX + "Test83"
    experiment = _experiment(1, 3)

    def build(self):
        self.t_new = CombiTimeTable(table=[[0, 1], [0.4, 0], [1, 1]], smoothness=Smoothness.ConstantSegments,
                                    extrapolation=Extrapolation.HoldLastPoint, columns=[2])
        self.booleanTable = BooleanTable(table=[0, 0.4, 1])


class Test87(TestDer2):
    """Modified Akima, comparison, first test data set (Ticket #1039)."""

    modelica_class = _PREFIX + "Test87"
    experiment = _experiment(0, 11)
    table = [[1, 0], [2, 0], [3, 0], [4, 0.5], [5, 0.5], [5.5, 1.2], [7, 1.2], [8, 0.1], [9, 0], [9.5, 0.3],
             [10, 0.6]]
    table_modifiers = dict(table=table, smoothness=Smoothness.ModifiedContinuousDerivative)

    def build(self):
        super().build()
        self.differentiated_twice("_2", table=self.table, smoothness=Smoothness.ContinuousDerivative)
        self.differentiated_twice("_3", table=self.table, smoothness=Smoothness.MonotoneContinuousDerivative1)
        self.differentiated_twice("_4", table=self.table, smoothness=Smoothness.MonotoneContinuousDerivative2)
