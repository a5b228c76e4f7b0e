"""Modelica.Mechanics.Rotational.Examples.SimpleGearShift: an automatic gear shift.

An engine (a torque step of 20 N.m at 0.5 s on an inertia) drives a load
through a planetary gear: the engine on the sun, the load (with a quadratic
speed-dependent drag) on the carrier.  Until 2 s the brake holds the ring
and the clutch between sun and ring is open, so the load turns at
1/(1 + ratio) of the engine speed; a ramp from 2 s to 2.1 s releases the
brake and closes the clutch, locking the gear: load and engine then turn
together.

Run ``acausal compare examples/rotational_simple_gear_shift.py`` to check it
against the MSL reference results.
"""

import sympy as sp

from acausal import Eq, Experiment, Model, Variable
from acausal.library.blocks import Constant, Feedback, Ramp
from acausal.library.rotational import (
    Brake,
    Clutch,
    IdealPlanetary,
    Inertia,
    QuadraticSpeedDependentTorque,
    TorqueStep,
)


class SimpleGearShift(Model):
    """Simple gear shift with a planetary gear, a clutch and a brake."""

    modelica_class = "Modelica.Mechanics.Rotational.Examples.SimpleGearShift"
    experiment = Experiment(start_time=0.0, stop_time=5.0, interval=0.01)

    wEngine = Variable(unit="rad/s", description="Speed of engine")  # noqa: N815 - MSL name
    wLoad = Variable(unit="rad/s", description="Speed of load")  # noqa: N815
    gearRatio = Variable(description="Gear ratio load/engine")  # noqa: N815

    def build(self):
        rest = dict(start=0, fixed=True)
        self.torqueStep = TorqueStep(offsetTorque=0, startTime=0.5, stepTorque=20)
        self.engine = Inertia(J=1)
        self.idealPlanetary = IdealPlanetary(ratio=75 / 50)
        self.load = Inertia(J=10, phi=rest, w=rest)
        # w_nominal = 100 rpm
        self.quadraticSpeedDependentTorque = QuadraticSpeedDependentTorque(w_nominal=10.471975511966,
                                                                           tau_nominal=-20)
        self.clutch = Clutch(cgeo=2, fn_max=100, phi_rel=dict(fixed=True), w_rel=dict(fixed=True))
        self.brake = Brake(cgeo=2, fn_max=100)
        self.feedback = Feedback()
        self.const1 = Constant(k=1)
        self.ramp = Ramp(height=1, offset=0, startTime=2, duration=0.1)

        self.connect(self.torqueStep.flange, self.engine.flange_a)
        self.connect(self.quadraticSpeedDependentTorque.flange, self.load.flange_b)
        self.connect(self.feedback.y, self.brake.f_normalized)
        self.connect(self.engine.flange_b, self.idealPlanetary.sun)
        self.connect(self.idealPlanetary.sun, self.clutch.flange_a)
        self.connect(self.idealPlanetary.ring, self.clutch.flange_b)
        self.connect(self.idealPlanetary.ring, self.brake.flange_a)
        self.connect(self.idealPlanetary.carrier, self.load.flange_a)
        self.connect(self.const1.y, self.feedback.u1)
        self.connect(self.feedback.u2, self.clutch.f_normalized)
        self.connect(self.ramp.y, self.clutch.f_normalized)

    def equations(self):
        return [
            Eq(self.wEngine, self.engine.w),
            Eq(self.wLoad, self.load.w),
            # max() makes no event (Modelica expands it into noEvent)
            Eq(self.gearRatio, self.wLoad / sp.Max(self.wEngine, 1e-6)),
        ]


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(SimpleGearShift())
    print(result.summary())
    for event in result.events:
        print(" ", event)
