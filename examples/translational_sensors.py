"""Modelica.Mechanics.Translational.Examples.Sensors: the translational sensors on a driven mass.

A sine force (10 N, 4 Hz) pushes a 1 kg mass of length 1 m, starting at rest
at s = 0, through a ForceSensor and a MultiSensor; position, speed and
acceleration sensors read the mass's flanges.  Analytically
``mass.v = 10/(2*pi*4)*(1 - cos(2*pi*4*t))`` and
``mass.s = 10/(2*pi*4)*(t - sin(2*pi*4*t)/(2*pi*4))``; the force sensors read
the sine, ``multiSensor.power = f*v``, and ``positionSensor2.s`` is one mass
length ahead of ``positionSensor1.s``.

Run ``acausal compare examples/translational_sensors.py`` to check it against
the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Sine
from acausal.library.translational import (
    AccSensor,
    Force,
    ForceSensor,
    Mass,
    MultiSensor,
    PositionSensor,
    SpeedSensor,
)


class Sensors(Model):
    """Sensors for translational systems."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.Sensors"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001)

    def build(self):
        self.forceSensor = ForceSensor()
        self.multiSensor = MultiSensor()
        self.speedSensor1 = SpeedSensor()
        self.positionSensor1 = PositionSensor()
        self.accSensor1 = AccSensor()
        self.positionSensor2 = PositionSensor()
        self.mass = Mass(L=1, m=1, s=dict(fixed=True), v=dict(fixed=True))
        self.force = Force()
        self.sineForce = Sine(amplitude=10, f=4)

        self.connect(self.sineForce.y, self.force.f)
        self.connect(self.forceSensor.flange_a, self.force.flange)
        self.connect(self.mass.flange_a, self.positionSensor1.flange)
        self.connect(self.mass.flange_a, self.speedSensor1.flange)
        self.connect(self.mass.flange_a, self.accSensor1.flange)
        self.connect(self.mass.flange_b, self.positionSensor2.flange)
        self.connect(self.forceSensor.flange_b, self.multiSensor.flange_a)
        self.connect(self.multiSensor.flange_b, self.mass.flange_a)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(Sensors())
    print(result.summary())
    for name in ("mass.s", "mass.v", "multiSensor.power", "positionSensor2.s"):
        print(f"{name}(1) = {result.final(name)}")
