"""A bouncing ball, written from scratch: when-clauses and reinit.

The ball falls from h0; at each impact its speed reverses, scaled by the
coefficient of restitution e.  Left alone the impacts come ever faster and
accumulate at a finite time (Zeno behaviour): acausal stops such a run with a
:class:`~acausal.errors.ZenoError` that names the accumulation time.  This
model ends the bouncing with a rule of its own, as a Modelica model would: when
the speed after an impact is below ``v_small`` the ball rests.

Run ``acausal simulate examples/bouncing_ball.py --plot``.
"""

from acausal import Boolean, Eq, Experiment, If, Model, Parameter, Variable, When, der, pre, reinit


class BouncingBall(Model):
    """A ball bouncing on a floor until it comes to rest."""

    experiment = Experiment(start_time=0.0, stop_time=6.0, interval=0.001)

    e = Parameter(0.8, description="Coefficient of restitution")
    g = Parameter(9.81, unit="m/s2", description="Gravity")
    v_small = Parameter(0.05, unit="m/s", description="Below this speed after an impact the ball rests")
    h = Variable(start=1.0, fixed=True, unit="m", description="Height above the floor")
    v = Variable(start=0.0, fixed=True, unit="m/s", description="Speed, upwards positive")
    resting = Boolean(start=False, fixed=True, description="true once the ball rests on the floor")

    def equations(self):
        return [
            Eq(der(self.h), self.v),
            Eq(der(self.v), If(self.resting, 0, -self.g)),
            When(self.h <= 0,
                 reinit(self.v, If(-self.e * pre(self.v) < self.v_small, 0, -self.e * pre(self.v))),
                 Eq(self.resting, -self.e * pre(self.v) < self.v_small)),
        ]
