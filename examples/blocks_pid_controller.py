"""Modelica.Blocks.Examples.PID_Controller: a LimPID as PI controller drives a two-inertia drive train.

A KinematicPTP profile, integrated, gives the reference speed (zero until
0.5 s, then accelerating, cruising and braking to move ``driveAngle``).
The controller ``PI`` (a LimPID with ``controllerType = PI``, output
limited to +-12 N.m, anti-windup with ``Ni = 0.1``) drives the motor
inertia, which turns the load inertia through a stiff spring-damper against
a constant load torque of 10 N.m.  Everything starts in steady state: the
controller by its ``initType``, the drive by ``inertia1.phi = 0``,
``inertia1.a = 0``, ``spring.w_rel = 0`` and the initial equation
``der(spring.w_rel) = 0``.  While braking, the controller output sits at
its limit and the anti-windup compensation holds the integrator.

Run ``acausal compare examples/blocks_pid_controller.py`` to check it
against the MSL reference results.
"""

from acausal import Eq, Experiment, Model, Parameter, StateSelect, der
from acausal.library.blocks import Integrator
from acausal.library.blocks.sources import KinematicPTP
from acausal.library.blocks.continuous import Init, LimPID
from acausal.library.blocks.types import SimpleController
from acausal.library.rotational import ConstantTorque, Inertia, SpeedSensor, SpringDamper, Torque


class PIDController(Model):
    """Modelica.Blocks.Examples.PID_Controller."""

    modelica_class = "Modelica.Blocks.Examples.PID_Controller"
    experiment = Experiment(start_time=0.0, stop_time=4.0, interval=0.008)

    driveAngle = Parameter(1.570796326794897, unit="rad", description="Reference distance to move")  # noqa: N815

    def build(self):
        self.PI = LimPID(k=100.0, Ti=0.1, yMax=12.0, Ni=0.1, initType=Init.SteadyState,
                         controllerType=SimpleController.PI, limiter=dict(u=dict(start=0.0)), Td=0.1)
        self.inertia1 = Inertia(phi=dict(fixed=True, start=0.0), J=1.0, a=dict(fixed=True, start=0.0))
        self.torque = Torque()
        self.spring = SpringDamper(c=1e4, d=100.0, stateSelect=StateSelect.prefer, w_rel=dict(fixed=True))
        self.inertia2 = Inertia(J=2.0)
        self.kinematicPTP = KinematicPTP(startTime=0.5, deltaq=[self.driveAngle], qd_max=[1.0], qdd_max=[1.0])
        self.integrator = Integrator(initType=Init.InitialState)
        self.speedSensor = SpeedSensor()
        self.loadTorque = ConstantTorque(tau_constant=10.0, useSupport=False)

        self.connect(self.spring.flange_b, self.inertia2.flange_a)
        self.connect(self.inertia1.flange_b, self.spring.flange_a)
        self.connect(self.torque.flange, self.inertia1.flange_a)
        self.connect(self.kinematicPTP.y[1], self.integrator.u)
        self.connect(self.speedSensor.flange, self.inertia1.flange_b)
        self.connect(self.loadTorque.flange, self.inertia2.flange_b)
        self.connect(self.PI.y, self.torque.tau)
        self.connect(self.speedSensor.w, self.PI.u_m)
        self.connect(self.integrator.y, self.PI.u_s)

    def initial_equations(self):
        return [Eq(der(self.spring.w_rel), 0)]


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(PIDController())
    print(result.summary())
