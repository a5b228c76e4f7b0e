"""ModelicaTest.Blocks.ResetHoldIntegrator: an integrator reset by a falling edge.

A BooleanPulse (period 1 s, width 50 %) switches the integrator's input
between 1 and 0; on the pulse's falling edge a FallingEdge block resets the
integrator (``reinit(y, y_start = 0)``), which then holds 0 until the next
pulse.  So ``y = 2*(t - k)`` on ``[k, k + 0.5)`` and ``y = 0`` on
``[k + 0.5, k + 1)``.  ``integrator.y`` is the one continuous state.

Run ``acausal compare examples/blocks_reset_integrator.py`` to check it
against the MSL reference results (ModelicaTest.Blocks.ResetHoldIntegrator).
"""

from acausal import Experiment, Model
from acausal.library.blocks import BooleanPulse, Constant, FallingEdge, Integrator, Switch


class ResetHoldIntegrator(Model):
    """Test of Modelica.Blocks.Continuous.Integrator with a reset input."""

    modelica_class = "ModelicaTest.Blocks.ResetHoldIntegrator"
    experiment = Experiment(start_time=0.0, stop_time=5.0, interval=5.0 / 5000)

    def build(self):
        self.integrator = Integrator(k=2.0, use_reset=True)
        self.const1 = Constant(k=1.0)
        self.switch = Switch()
        self.const0 = Constant(k=0.0)
        self.booleanPulse = BooleanPulse(period=1.0)
        self.fallingEdge = FallingEdge()

        self.connect(self.switch.y, self.integrator.u)
        self.connect(self.integrator.reset, self.fallingEdge.y)
        self.connect(self.const1.y, self.switch.u1)
        self.connect(self.const0.y, self.switch.u3)
        self.connect(self.booleanPulse.y, self.switch.u2)
        self.connect(self.fallingEdge.u, self.booleanPulse.y)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(ResetHoldIntegrator())
    print(result.summary())
    print("integrator.y(5) =", result.final("integrator.y"))
