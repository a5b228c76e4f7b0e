"""A sampled PI speed controller holding a drive against bearing friction, written from scratch.

A motor (an ideal torque source) drives an inertia that turns in a bearing
with Coulomb friction (``BearingFriction``: 2 N.m sliding, 3 N.m to break
away).  A digital PI controller, written here with a ``When(sample(...))``
clause, reads the speed every ``Ts`` seconds and holds its torque command
between samples (zero-order hold).  What the run shows:

- at standstill the command must wind up past the breakaway torque before
  the shaft moves (stick, then slip);
- with integral action the speed settles at the set point, and the motor then
  supplies exactly the sliding friction torque at that speed plus the load;
- a load step at ``t_load`` is rejected: the speed dips and returns;
- the command changes only at the sample instants ``k*Ts``, which acausal hits
  exactly as time events.

The controller's discrete variables (``e``, ``x``, ``y``) are held between
samples; the friction element's modes are decided by event iteration.

Run ``acausal simulate examples/sampled_speed_control.py --plot``.
"""

from acausal import Component, Eq, Experiment, If, Model, Parameter, RealInput, RealOutput, Variable, When, pre, sample
from acausal.library.blocks import Step
from acausal.library.rotational import BearingFriction, Inertia, SpeedSensor, Torque, TorqueStep


class SampledPI(Component):
    """Discrete PI controller with a zero-order hold: ``y = kp*(e + x)``, ``x += Ts/Ti*e`` at each sample.

    At each tick ``t = k*Ts`` the error ``e = w_ref - w`` is sampled, the
    integral state is advanced by the forward Euler rule (``x = pre(x) +
    Ts/Ti*e``) and the command is ``y = kp*(e + x)``, limited to
    ``[-y_max, y_max]`` with the integral clamped while limited (anti-windup).
    """

    Ts = Parameter(0.01, unit="s", min=0, description="Sample period")
    kp = Parameter(2.0, unit="N.m.s/rad", description="Proportional gain")
    Ti = Parameter(0.1, unit="s", min=0, description="Integral time")
    y_max = Parameter(20.0, unit="N.m", description="Limit of the torque command")
    w_ref = RealInput(unit="rad/s", description="Speed set point")
    w = RealInput(unit="rad/s", description="Measured speed")
    e = Variable(discrete=True, start=0.0, fixed=True, unit="rad/s", description="Sampled speed error")
    x = Variable(discrete=True, start=0.0, fixed=True, unit="rad/s", description="Integral state")
    y = RealOutput(discrete=True, start=0.0, fixed=True, unit="N.m", description="Held torque command")

    def equations(self):
        unlimited = self.kp * (self.e + pre(self.x) + self.Ts / self.Ti * self.e)
        limited = unlimited > self.y_max
        limited_below = unlimited < -self.y_max
        return [When(sample(0, self.Ts),
                     Eq(self.e, self.w_ref - self.w),
                     # anti-windup: the integral stands still while the command is limited
                     Eq(self.x, If(limited | limited_below, pre(self.x), pre(self.x) + self.Ts / self.Ti * self.e)),
                     Eq(self.y, If(limited, self.y_max, If(limited_below, -self.y_max, unlimited))))]


class SampledSpeedControl(Model):
    """A PI-controlled drive against Coulomb friction, with a load step."""

    experiment = Experiment(start_time=0.0, stop_time=5.0, interval=0.001)

    t_load = Parameter(3.0, unit="s", description="Time of the load step")
    tau_load = Parameter(-1.5, unit="N.m", description="Load torque after t_load")

    def build(self):
        self.reference = Step(height=10.0, offset=0.0, startTime=0.2)
        self.controller = SampledPI(Ts=0.01, kp=0.25, Ti=0.2)
        self.motor = Torque()
        self.shaft = Inertia(J=0.05, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.bearing = BearingFriction(tau_pos=[[0, 2.0], [100, 3.0]], peak=1.5)
        self.load = TorqueStep(stepTorque=self.tau_load, offsetTorque=0, startTime=self.t_load)
        self.speed = SpeedSensor()

        self.connect(self.reference.y, self.controller.w_ref)
        self.connect(self.speed.w, self.controller.w)
        self.connect(self.controller.y, self.motor.tau)
        self.connect(self.motor.flange, self.shaft.flange_a)
        self.connect(self.shaft.flange_b, self.bearing.flange_a)
        self.connect(self.bearing.flange_b, self.load.flange)
        self.connect(self.shaft.flange_a, self.speed.flange)
