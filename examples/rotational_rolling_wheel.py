"""Modelica.Mechanics.Rotational.Examples.RollingWheel: coupling rotation and translation.

A torque step (10 N.m at t = 0.1 s) drives an inertia (J = 1 kg.m2) whose
shaft turns an ideal rolling wheel (radius 1 m).  The wheel pushes a mass
(m = 1 kg) against a quadratic drag force (10 N at 5 m/s, always braking),
so the speed approaches the value where drive and drag balance: with the
effective inertia J + m*radius^2 = 2 kg.m2 and drag 10*(v/5)^2 N, the end
speed is v = 5 m/s (w = 5 rad/s).

Run ``acausal compare examples/rotational_rolling_wheel.py`` to check it
against the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.rotational import IdealRollingWheel, Inertia, TorqueStep
from acausal.library.translational import Mass, QuadraticSpeedDependentForce


class RollingWheel(Model):
    """Demonstrate coupling Rotational - Translational."""

    modelica_class = "Modelica.Mechanics.Rotational.Examples.RollingWheel"
    experiment = Experiment(start_time=0.0, stop_time=5.0, interval=0.001)

    def build(self):
        self.idealRollingWheel = IdealRollingWheel(radius=1)
        self.inertia = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.torqueStep = TorqueStep(stepTorque=10, offsetTorque=0, startTime=0.1, useSupport=False)
        self.mass = Mass(L=0, m=1)
        self.quadraticSpeedDependentForce = QuadraticSpeedDependentForce(f_nominal=-10, ForceDirection=False,
                                                                         v_nominal=5)

        self.connect(self.torqueStep.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.idealRollingWheel.flangeR)
        self.connect(self.idealRollingWheel.flangeT, self.mass.flange_a)
        self.connect(self.quadraticSpeedDependentForce.flange, self.mass.flange_b)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(RollingWheel())
    print(result.summary())
