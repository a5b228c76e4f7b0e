"""ModelicaTest.Blocks.Logical: every block of Modelica.Blocks.Logical at once.

Two Boolean tables (``table1`` true on [2, 4) and [6, 8), ``table2`` on
[1, 3) and [5, 7)) drive the gates, the pre/edge/change blocks, a logical
switch, a triggered trapezoid, a timer and an RS flip-flop; a sine
``2*sin(pi*t)`` and a ramp ``0.625*t`` drive the comparisons, the
zero-crossing detector, the hysteresis and the on-off controller.  MSL 4.1.0
adds a Boolean pulse feeding an assertion at warning level (false every other
quarter second): it only writes a note.

Run ``acausal compare examples/blocks_logical.py`` to check it against the
MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import (
    And,
    AssertCondition,
    BooleanPulse,
    BooleanTable,
    Change,
    Edge,
    FallingEdge,
    Greater,
    GreaterEqual,
    GreaterEqualThreshold,
    GreaterThreshold,
    Hysteresis,
    Less,
    LessEqual,
    LessEqualThreshold,
    LessThreshold,
    LogicalSwitch,
    Nand,
    Nor,
    Not,
    OnOffController,
    Or,
    Pre,
    RSFlipFlop,
    Ramp,
    Sine,
    Switch,
    Timer,
    TriggeredTrapezoid,
    Xor,
    ZeroCrossing,
)


class LogicalTest(Model):
    """Test of the Modelica.Blocks.Logical blocks (ModelicaTest.Blocks.Logical)."""

    modelica_class = "ModelicaTest.Blocks.Logical"
    experiment = Experiment(start_time=0.0, stop_time=10.0, interval=10.0 / 5000)

    def build(self):
        self.table1 = BooleanTable(table=(2, 4, 6, 8))
        self.table2 = BooleanTable(table=(1, 3, 5, 7))
        self.and1 = And()
        self.or1 = Or()
        self.xor = Xor()
        self.nor = Nor()
        self.nand = Nand()
        self.not1 = Not()
        self.pre1 = Pre()
        self.edge1 = Edge()
        self.fallingEdge = FallingEdge()
        self.change1 = Change()
        self.greaterThreshold = GreaterThreshold(threshold=0.1)
        self.sine = Sine(amplitude=2, f=0.5)
        self.greaterEqualThreshold = GreaterEqualThreshold(threshold=-0.1)
        self.lessThreshold = LessThreshold(threshold=0.1)
        self.lessEqualThreshold = LessEqualThreshold(threshold=-0.1)
        self.greater = Greater()
        self.ramp = Ramp(height=5, duration=8)
        self.greaterEqual = GreaterEqual()
        self.less = Less()
        self.lessEqual = LessEqual()
        self.zeroCrossing = ZeroCrossing()
        self.logicalSwitch = LogicalSwitch()
        self.switch1 = Switch()
        self.hysteresis = Hysteresis(uLow=-0.5, uHigh=0.5)
        self.onOffController = OnOffController(bandwidth=0.5)
        self.triggeredTrapezoid = TriggeredTrapezoid(rising=1, falling=0.5)
        self.timer = Timer()
        self.rSFlipFlop = RSFlipFlop(Qini=False)
        self.assertCondition = AssertCondition(assertionLevel="warning")
        self.booleanPulse = BooleanPulse(width=50, period=0.5, startTime=0)

        # the 43 connections of the MSL model, in its order
        c = self.connect
        c(self.table1.y, self.and1.u1)
        c(self.table2.y, self.and1.u2)
        c(self.and1.y, self.or1.u1)
        c(self.table2.y, self.or1.u2)
        c(self.table1.y, self.xor.u1)
        c(self.and1.y, self.xor.u2)
        c(self.xor.y, self.nor.u1)
        c(self.or1.y, self.nor.u2)
        c(self.nor.y, self.nand.u1)
        c(self.table2.y, self.nand.u2)
        c(self.or1.y, self.not1.u)
        c(self.not1.y, self.pre1.u)
        c(self.or1.y, self.edge1.u)
        c(self.or1.y, self.fallingEdge.u)
        c(self.or1.y, self.change1.u)
        c(self.sine.y, self.greaterThreshold.u)
        c(self.sine.y, self.greaterEqualThreshold.u)
        c(self.sine.y, self.lessThreshold.u)
        c(self.sine.y, self.lessEqualThreshold.u)
        c(self.ramp.y, self.greater.u2)
        c(self.ramp.y, self.greaterEqual.u2)
        c(self.less.u2, self.greaterEqual.u2)
        c(self.lessEqual.u2, self.greaterEqual.u2)
        c(self.greater.u1, self.lessEqualThreshold.u)
        c(self.greaterEqual.u1, self.lessEqualThreshold.u)
        c(self.less.u1, self.lessEqualThreshold.u)
        c(self.lessEqual.u1, self.lessEqualThreshold.u)
        c(self.zeroCrossing.u, self.greaterThreshold.u)
        c(self.greaterThreshold.y, self.zeroCrossing.enable)
        c(self.nand.y, self.logicalSwitch.u1)
        c(self.pre1.y, self.logicalSwitch.u2)
        c(self.table2.y, self.logicalSwitch.u3)
        c(self.change1.y, self.switch1.u2)
        c(self.switch1.u1, self.lessEqualThreshold.u)
        c(self.switch1.u3, self.greaterEqual.u2)
        c(self.sine.y, self.hysteresis.u)
        c(self.onOffController.reference, self.lessEqualThreshold.u)
        c(self.onOffController.u, self.greaterEqual.u2)
        c(self.table2.y, self.triggeredTrapezoid.u)
        # MSL: connect(timer.u, logicalSwitch.u3), an input-input connection of a Boolean
        # signal; the engine gives Boolean input-input connections no merged alias set
        # (logicalSwitch.u3 would be defined twice), so timer.u is connected to the
        # output that drives that set, table2.y: the same flat equations
        c(self.table2.y, self.timer.u)
        c(self.nand.y, self.rSFlipFlop.S)
        c(self.pre1.y, self.rSFlipFlop.R)
        c(self.booleanPulse.y, self.assertCondition.u)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(LogicalTest())
    print(result.summary())
    for event in result.events:
        print(event)
