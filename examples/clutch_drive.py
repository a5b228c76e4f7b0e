"""A clutch drive whose linearization differs by friction mode (docs/linearization.md).

A sine torque drives J1; a clutch couples it to J2, which an elastic shaft
(SpringDamper) holds to the ground.  While the clutch is stuck, J1 and J2
move together against the shaft; while it slips, J1 is decoupled from the
spring and only the friction torque (whose coefficient rises with the slip
speed) couples them: the two modes have different A matrices.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Constant, Sine
from acausal.library.rotational import Clutch, Fixed, Inertia, SpringDamper, Torque


class ClutchDrive(Model):
    """A sine torque drives J1; a clutch couples it to J2, held by an elastic shaft."""

    experiment = Experiment(stop_time=2.0)

    def build(self):
        rest = dict(start=0, fixed=True)
        self.drive = Sine(amplitude=60.0, f=1.0)
        self.torque = Torque()
        self.J1 = Inertia(J=1.0, phi=rest, w=rest)
        self.clutch = Clutch(mu_pos=[[0.0, 0.4], [10.0, 0.6]], peak=1.1, fn_max=100.0)
        self.pressure = Constant(k=1.0)
        self.J2 = Inertia(J=2.0)
        self.shaft = SpringDamper(c=400.0, d=4.0)
        self.fixed = Fixed()
        self.connect(self.drive.y, self.torque.tau)
        self.connect(self.torque.flange, self.J1.flange_a)
        self.connect(self.J1.flange_b, self.clutch.flange_a)
        self.connect(self.clutch.flange_b, self.J2.flange_a)
        self.connect(self.pressure.y, self.clutch.f_normalized)
        self.connect(self.J2.flange_b, self.shaft.flange_a)
        self.connect(self.shaft.flange_b, self.fixed.flange)


if __name__ == "__main__":
    from acausal.tools.linearize import linearize

    for at in (0.05, 0.5):
        lin = linearize(ClutchDrive(), at=at, inputs=["torque.tau"], outputs=["J2.w"])
        print(f"t = {at}: {lin.discrete_state}")
        print(lin.A)
