"""Modelica.Blocks.Examples RealNetwork1, IntegerNetwork1 and BooleanNetwork1.

Three small networks of the vector blocks, one per signal type, with the
value displays of Modelica.Blocks.Interaction.Show as their outputs:

* ``RealNetwork1``: a sine plus a step (MultiSum), a step times a constant
  (MultiProduct), their linear combination and their extrema; a MultiSwitch
  picks 4 while the 1 s Boolean pulse is on, else 6 while the 2 s one is,
  else 2.
* ``IntegerNetwork1``: the same with Integers (MathInteger.Sum of a rounded
  sine, a step and a constant; MathInteger.Product), a TriggeredAdd counting
  the pulses and an Integer MultiSwitch without memory (``use_pre_as_default
  = false``).
* ``BooleanNetwork1``: the MathBoolean gates chained (And of three inputs,
  Or, Xor, Nand, Nor, Not), the edge detectors, a Boolean MultiSwitch set by
  the rising edges and reset by the falling ones, an OnDelay of a Boolean
  table, a TriggeredAdd counting the changes of a pulse, and an RS flip-flop
  set and reset by two sample triggers.

Run ``acausal compare examples/blocks_networks.py`` to check them against
the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import (BooleanPulse, BooleanStep, BooleanTable, Constant, IntegerConstant, IntegerStep,
                                    LinearDependency, MinMax, MultiProduct, MultiSum, MultiSwitch, RealToInteger,
                                    RSFlipFlop, SampleTrigger, Sine, Step)
from acausal.library.blocks import math_boolean, math_integer
from acausal.library.blocks.interaction import BooleanValue, IntegerValue, RealValue


class RealNetwork1(Model):
    """Modelica.Blocks.Examples.RealNetwork1: demonstrates the usage of blocks from Modelica.Blocks.Math."""

    modelica_class = "Modelica.Blocks.Examples.RealNetwork1"
    experiment = Experiment(start_time=0.0, stop_time=10.0, interval=10.0 / 5000)

    def build(self):
        self.add = MultiSum(nu=2)
        self.sine = Sine(amplitude=3, f=0.1)
        self.integerStep = Step(height=3, startTime=2)
        self.integerConstant = Constant(k=1)
        self.showValue = RealValue()
        self.product = MultiProduct(nu=2)
        self.showValue1 = RealValue(significantDigits=2)
        self.booleanPulse1 = BooleanPulse(period=1)
        self.multiSwitch = MultiSwitch(nu=2, expr=[4, 6], y_default=2)
        self.booleanPulse2 = BooleanPulse(period=2, width=80)
        self.showValue3 = RealValue(use_numberPort=False, number=self.multiSwitch.y, significantDigits=1)
        self.linearDependency1 = LinearDependency(y0=1, k1=2, k2=3)
        self.minMax = MinMax(nu=2)
        self.connect(self.booleanPulse1.y, self.multiSwitch.u[1])
        self.connect(self.booleanPulse2.y, self.multiSwitch.u[2])
        self.connect(self.sine.y, self.add.u[1])
        self.connect(self.integerStep.y, self.add.u[2])
        self.connect(self.add.y, self.showValue.numberPort)
        self.connect(self.integerStep.y, self.product.u[1])
        self.connect(self.integerConstant.y, self.product.u[2])
        self.connect(self.product.y, self.showValue1.numberPort)
        self.connect(self.add.y, self.linearDependency1.u1)
        self.connect(self.product.y, self.linearDependency1.u2)
        self.connect(self.add.y, self.minMax.u[1])
        self.connect(self.product.y, self.minMax.u[2])


class IntegerNetwork1(Model):
    """Modelica.Blocks.Examples.IntegerNetwork1: demonstrates the usage of blocks from
    Modelica.Blocks.MathInteger."""

    modelica_class = "Modelica.Blocks.Examples.IntegerNetwork1"
    experiment = Experiment(start_time=0.0, stop_time=10.0, interval=10.0 / 5000)

    def build(self):
        self.sum = math_integer.Sum(nu=3)
        self.sine = Sine(amplitude=3, f=0.1)
        self.realToInteger = RealToInteger()
        self.integerStep = IntegerStep(height=3, startTime=2)
        self.integerConstant = IntegerConstant(k=1)
        self.showValue = IntegerValue()
        self.product = math_integer.Product(nu=2)
        self.showValue1 = IntegerValue()
        self.triggeredAdd = math_integer.TriggeredAdd(use_reset=False, use_set=False)
        self.booleanPulse1 = BooleanPulse(period=1)
        self.showValue2 = IntegerValue()
        self.multiSwitch1 = math_integer.MultiSwitch(nu=2, expr=[4, 6], y_default=2, use_pre_as_default=False)
        self.booleanPulse2 = BooleanPulse(period=2, width=80)
        self.showValue3 = IntegerValue(use_numberPort=False, number=self.multiSwitch1.y)
        self.connect(self.sine.y, self.realToInteger.u)
        self.connect(self.realToInteger.y, self.sum.u[1])
        self.connect(self.integerStep.y, self.sum.u[2])
        self.connect(self.integerConstant.y, self.sum.u[3])
        self.connect(self.sum.y, self.showValue.numberPort)
        self.connect(self.sum.y, self.product.u[1])
        self.connect(self.integerStep.y, self.product.u[2])
        self.connect(self.product.y, self.showValue1.numberPort)
        self.connect(self.integerConstant.y, self.triggeredAdd.u)
        self.connect(self.booleanPulse1.y, self.triggeredAdd.trigger)
        self.connect(self.triggeredAdd.y, self.showValue2.numberPort)
        self.connect(self.booleanPulse1.y, self.multiSwitch1.u[1])
        self.connect(self.booleanPulse2.y, self.multiSwitch1.u[2])


class BooleanNetwork1(Model):
    """Modelica.Blocks.Examples.BooleanNetwork1: demonstrates the usage of blocks from
    Modelica.Blocks.MathBoolean."""

    modelica_class = "Modelica.Blocks.Examples.BooleanNetwork1"
    experiment = Experiment(start_time=0.0, stop_time=10.0, interval=10.0 / 5000)

    def build(self):
        self.showValue = BooleanValue()
        self.and1 = math_boolean.And(nu=3)
        self.booleanPulse1 = BooleanPulse(width=20, period=1)
        self.booleanPulse2 = BooleanPulse(period=1, width=80)
        self.booleanStep = BooleanStep(startTime=1.5)
        self.or1 = math_boolean.Or(nu=2)
        self.xor1 = math_boolean.Xor(nu=2)
        self.showValue2 = BooleanValue()
        self.showValue3 = BooleanValue()
        self.nand1 = math_boolean.Nand(nu=2)
        self.or2 = math_boolean.Nor(nu=2)
        self.showValue4 = BooleanValue()
        self.nor1 = math_boolean.Not()
        self.onDelay = math_boolean.OnDelay(delayTime=1)
        self.rising = math_boolean.RisingEdge()
        self.set1 = math_boolean.MultiSwitch(nu=2, expr=[False, True])
        self.falling = math_boolean.FallingEdge()
        self.booleanTable = BooleanTable(table=[2, 4, 6, 6.5, 7, 9, 11])
        self.changing = math_boolean.ChangingEdge()
        self.triggeredAdd = math_integer.TriggeredAdd()
        self.integerConstant = IntegerConstant(k=2)
        self.showValue1 = IntegerValue()
        self.showValue5 = BooleanValue()
        self.showValue6 = BooleanValue()
        self.rSFlipFlop = RSFlipFlop()
        self.sampleTriggerSet = SampleTrigger(period=0.5, startTime=0)
        self.sampleTriggerReset = SampleTrigger(period=0.5, startTime=0.3)
        self.connect(self.booleanPulse1.y, self.and1.u[1])
        self.connect(self.booleanStep.y, self.and1.u[2])
        self.connect(self.booleanPulse2.y, self.and1.u[3])
        self.connect(self.and1.y, self.or1.u[1])
        self.connect(self.booleanPulse2.y, self.or1.u[2])
        self.connect(self.or1.y, self.xor1.u[1])
        self.connect(self.booleanPulse2.y, self.xor1.u[2])
        self.connect(self.and1.y, self.showValue.activePort)
        self.connect(self.or1.y, self.showValue2.activePort)
        self.connect(self.xor1.y, self.showValue3.activePort)
        self.connect(self.xor1.y, self.nand1.u[1])
        self.connect(self.booleanPulse2.y, self.nand1.u[2])
        self.connect(self.nand1.y, self.or2.u[1])
        self.connect(self.booleanPulse2.y, self.or2.u[2])
        self.connect(self.or2.y, self.nor1.u)
        self.connect(self.nor1.y, self.showValue4.activePort)
        self.connect(self.booleanPulse2.y, self.rising.u)
        self.connect(self.rising.y, self.set1.u[1])
        self.connect(self.falling.y, self.set1.u[2])
        self.connect(self.booleanPulse2.y, self.falling.u)
        self.connect(self.booleanTable.y, self.onDelay.u)
        self.connect(self.booleanPulse2.y, self.changing.u)
        self.connect(self.integerConstant.y, self.triggeredAdd.u)
        self.connect(self.changing.y, self.triggeredAdd.trigger)
        self.connect(self.triggeredAdd.y, self.showValue1.numberPort)
        self.connect(self.set1.y, self.showValue5.activePort)
        self.connect(self.onDelay.y, self.showValue6.activePort)
        self.connect(self.sampleTriggerSet.y, self.rSFlipFlop.S)
        self.connect(self.sampleTriggerReset.y, self.rSFlipFlop.R)


if __name__ == "__main__":
    from acausal import simulate

    for model in (RealNetwork1(), IntegerNetwork1(), BooleanNetwork1()):
        print(simulate(model).summary())
