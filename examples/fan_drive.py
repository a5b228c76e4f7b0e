"""A constant torque against a quadratic load: the steady state of docs/linearization.md.

``T = 3 N.m`` drives ``J = 2 kg.m2`` against
``QuadraticSpeedDependentTorque(tau_nominal=-1.5, w_nominal=10)``, a load
torque ``k (w/w_nominal)^2``: the speed settles at ``w = 10 sqrt(3/1.5)``
while the angle keeps turning.
"""

from acausal import Model
from acausal.library.rotational import ConstantTorque, Inertia, QuadraticSpeedDependentTorque


class FanDrive(Model):
    """A constant torque against a quadratic load: T = k (w/w_nominal)^2."""

    def build(self):
        self.drive = ConstantTorque(tau_constant=3.0)
        self.J = Inertia(J=2.0)
        self.load = QuadraticSpeedDependentTorque(tau_nominal=-1.5, w_nominal=10.0)
        self.connect(self.drive.flange, self.J.flange_a)
        self.connect(self.J.flange_b, self.load.flange)
