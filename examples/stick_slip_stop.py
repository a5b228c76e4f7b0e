"""A stick-slip mass that ends against a hard stop, written from scratch.

A mass lies on a table with Stribeck friction (15 N to break away, 5 N
Coulomb friction when sliding fast, plus 1 N.s/m viscous) and is pulled
through a spring whose far end moves at a constant 0.1 m/s.  Pulled slowly
against a friction force that falls with speed, the mass sticks and slips
in turns: it sticks until the spring force reaches the static limit, slides
(the friction drops, so it overshoots and sheds the spring force), and
sticks again.  At ``smax`` a hard stop ends the motion: at the impact the
stop's when-clause resets the velocity to zero (``reinit``), and from then
on the spring pulls the mass into the stop, where it stays.

The mass is Modelica.Mechanics.Translational.Components.MassWithStopAndFriction
(its stop logic is a ``when`` with ``reinit``, its sticking the friction
state machine); the rest is a Spring and a ConstantSpeed source.

Run ``acausal simulate examples/stick_slip_stop.py --plot``.
"""

from acausal import Experiment, Model, Parameter
from acausal.library.translational import ConstantSpeed, MassWithStopAndFriction, Spring


class StickSlipStop(Model):
    """Stick-slip of a mass pulled through a spring, until it meets a hard stop."""

    experiment = Experiment(start_time=0.0, stop_time=8.0, interval=0.001)

    v_drive = Parameter(0.1, unit="m/s", description="Speed of the spring's far end")
    c = Parameter(100.0, unit="N/m", description="Spring stiffness")
    smax = Parameter(0.3, unit="m", description="Position of the hard stop")

    def build(self):
        self.mass = MassWithStopAndFriction(m=1.0, F_prop=1.0, F_Coulomb=5.0, F_Stribeck=10.0, fexp=2.0,
                                            smax=self.smax, smin=-1.0, L=0.0,
                                            s=dict(start=0.0, fixed=True), v=dict(start=0.0, fixed=True))
        self.spring = Spring(c=self.c, s_rel0=0.0)
        self.drive = ConstantSpeed(v_fixed=self.v_drive, s=dict(start=0.0, fixed=True))
        self.connect(self.mass.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.drive.flange)
