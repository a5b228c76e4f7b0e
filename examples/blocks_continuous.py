"""ModelicaTest.Blocks.Continuous and Continuous_InitialOutput: every continuous block on a ramp.

Two ramps (0.5, rising by 1 over 0.5 s ... 2.5 s) drive the continuous blocks
of Modelica.Blocks.Continuous side by side: Integrator, LimIntegrator,
Derivative, FirstOrder, SecondOrder, PI, PID on the first; LimPID (against
the constant measurement 1.5), TransferFunction ``1/(s + 1)``, StateSpace,
LowpassButterworth and CriticalDamping on the second; Der differentiates a
sine.  ``Continuous`` starts the blocks from their initial states;
``Continuous_InitialOutput`` gives their initial outputs instead, which
leaves the other states in steady state where the block says so (PID's and
LimPID's derivative parts, the filters) and picks the least-squares states
of the StateSpace.

Run ``acausal compare examples/blocks_continuous.py`` to check both against
the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Constant, CriticalDamping, LowpassButterworth, Ramp, Sine
from acausal.library.blocks.continuous import (PI, PID, Der, Derivative, FirstOrder, Init, Integrator,
                                               LimIntegrator, LimPID, SecondOrder, StateSpace, TransferFunction)


class ContinuousTest(Model):
    """ModelicaTest.Blocks.Continuous."""

    modelica_class = "ModelicaTest.Blocks.Continuous"
    experiment = Experiment(start_time=0.0, stop_time=1.1, interval=0.0022)

    def block_modifiers(self) -> dict[str, dict]:
        """The modifiers of each block beyond those of ModelicaTest.Blocks.Continuous (none here)."""
        return {}

    def build(self):
        extra = self.block_modifiers()
        initial_state = Init.InitialState

        def given(name: str, **modifiers) -> dict:
            return {**modifiers, **extra.get(name, {})}

        self.integrator = Integrator(**given("integrator"))
        self.limIntegrator = LimIntegrator(**given("limIntegrator", outMax=1.0))
        self.derivative = Derivative(**given("derivative", x_start=0.0, initType=initial_state))
        self.firstOrder = FirstOrder(**given("firstOrder", T=1.0, initType=initial_state))
        self.secondOrder = SecondOrder(**given("secondOrder", w=1.0, D=1.0, initType=initial_state))
        self.pI = PI(**given("pI", T=1.0, initType=initial_state))
        self.pID = PID(**given("pID", Ti=0.5, Td=0.1, initType=initial_state))
        self.limPID = LimPID(**given("limPID", Ti=0.5, Td=0.1, yMax=1.0, initType=initial_state))
        self.transferFunction = TransferFunction(**given("transferFunction", a=[1.0, 1.0], b=[1.0],
                                                         initType=initial_state))
        self.stateSpace = StateSpace(**given("stateSpace", A=[[1.0, 0.0], [0.0, 1.0]], B=[[1.0], [1.0]],
                                             C=[[1.0, 1.0]], initType=initial_state))
        self.lowpassButterworth = LowpassButterworth(**given("lowpassButterworth", f=1.0,
                                                             initType=initial_state))
        self.criticalDamping = CriticalDamping(**given("criticalDamping", normalized=False, f=1.0,
                                                       initType=initial_state))
        self.ramp = Ramp(offset=0.5, startTime=0.5, duration=2.0)
        self.ramp1 = Ramp(offset=0.5, startTime=0.5, duration=2.0)
        self.const = Constant(k=1.5)
        self.der1 = Der()
        self.sine = Sine(f=1.0)

        for block in (self.integrator, self.limIntegrator, self.derivative, self.firstOrder, self.secondOrder,
                      self.pI, self.pID):
            self.connect(self.ramp.y, block.u)
        self.connect(self.ramp1.y, self.limPID.u_s)
        self.connect(self.ramp1.y, self.transferFunction.u)
        self.connect(self.ramp1.y, self.stateSpace.u[1])
        self.connect(self.ramp1.y, self.lowpassButterworth.u)
        self.connect(self.ramp1.y, self.criticalDamping.u)
        self.connect(self.const.y, self.limPID.u_m)
        self.connect(self.sine.y, self.der1.u)


class ContinuousInitialOutput(ContinuousTest):
    """ModelicaTest.Blocks.Continuous_InitialOutput."""

    modelica_class = "ModelicaTest.Blocks.Continuous_InitialOutput"

    def block_modifiers(self) -> dict[str, dict]:
        output = Init.InitialOutput
        return {
            "integrator": dict(initType=output, y_start=2.0),
            "limIntegrator": dict(initType=output, y_start=0.5),
            "derivative": dict(initType=output, y_start=2.0),
            "firstOrder": dict(initType=output, y_start=2.0),
            "secondOrder": dict(initType=output, y_start=2.0),
            "pI": dict(initType=output, y_start=2.0),
            "pID": dict(initType=output, y_start=2.0),
            "limPID": dict(initType=output, yMax=3.0, y_start=2.0),
            "transferFunction": dict(initType=output, y_start=2.0),
            "stateSpace": dict(initType=output, y_start=[2.0]),
            "lowpassButterworth": dict(initType=output, y_start=2.0),
            "criticalDamping": dict(initType=output, y_start=2.0),
        }


if __name__ == "__main__":
    from acausal import simulate

    for model in (ContinuousTest(), ContinuousInitialOutput()):
        print(simulate(model).summary())
