"""ModelicaTest.Blocks.IntegerTable: four Integer tables.

``IntegerTable`` as MSL 4.1 builds it (a CombiTimeTable with constant
segments and a RealToInteger): the output holds ``table[i, 2]`` from
``table[i, 1]`` on, and the last value after the table (HoldLastPoint).
``integerTable3`` starts at t = 2: before it, its one row's value holds too.

Run ``acausal compare examples/blocks_integer_table.py`` to check it against
the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import IntegerTable


class IntegerTableTest(Model):
    """ModelicaTest.Blocks.IntegerTable."""

    modelica_class = "ModelicaTest.Blocks.IntegerTable"
    experiment = Experiment(start_time=0.0, stop_time=3.0, interval=0.006)

    def build(self):
        self.integerTable = IntegerTable(table=[[0, 1], [1, 4], [1.5, 5], [2, 6]])
        self.integerTable2 = IntegerTable(table=[[0, -1]])
        self.integerTable3 = IntegerTable(table=[[2, -2]])
        self.integerTable4 = IntegerTable(table=[[0, 1], [1, 4], [1.5, 5], [2, 6], [4, 7]])


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(IntegerTableTest())
    print(result.summary())
