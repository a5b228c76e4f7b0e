"""ModelicaTest.Blocks.LimPID: four PI loops with a limited output, started in steady state.

Each loop is a LimPID (PI, ``Ti = 1``, output limited to ``0..1``) that
drives a first order plant ``1/(s + 1)`` whose output is fed back as the
measurement; set points step at t = 1.  Both the controller and the plant
start in steady state, which for loops 2 and 3 puts the limiter at its
upper and lower limit: the set points 2 and -1 cannot be reached, and the
anti-windup compensation holds the integrator where the cut-off output
balances the control error.  The MSL varies ``homotopyType`` between the
loops; acausal has no homotopy-based initialization, so the four loops
differ only in their set points.

Run ``acausal compare examples/blocks_lim_pid.py`` to check it against the
MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Step
from acausal.library.blocks.continuous import FirstOrder, Init, LimPID
from acausal.library.blocks.nonlinear import LimiterHomotopy
from acausal.library.blocks.types import SimpleController


class LimPIDTest(Model):
    """ModelicaTest.Blocks.LimPID."""

    modelica_class = "ModelicaTest.Blocks.LimPID"
    experiment = Experiment(start_time=0.0, stop_time=10.0, interval=0.02)

    def build(self):
        loops = [  # (homotopyType, step height, step offset)
            (LimiterHomotopy.Linear, 0.4, 0.5),
            (LimiterHomotopy.UpperLimit, -1.5, 2.0),
            (LimiterHomotopy.LowerLimit, 1.5, -1.0),
            (LimiterHomotopy.NoHomotopy, 0.4, 0.5),
        ]
        for number, (homotopy, height, offset) in enumerate(loops, start=1):
            pid = LimPID(Ti=1.0, yMax=1.0, yMin=0.0, initType=Init.SteadyState,
                         controllerType=SimpleController.PI, homotopyType=homotopy)
            step = Step(height=height, offset=offset, startTime=1.0)
            plant = FirstOrder(T=1.0, initType=Init.SteadyState)
            setattr(self, f"PID{number}", pid)
            setattr(self, f"step{number}", step)
            setattr(self, f"firstOrder{number}", plant)
            self.connect(plant.y, pid.u_m)
            self.connect(pid.y, plant.u)
            self.connect(step.y, pid.u_s)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(LimPIDTest())
    print(result.summary())
