"""Modelica.Mechanics.Translational.Examples.Vehicle: one-dimensional vehicles with driving resistances.

Three 100 kg vehicles (wheel radius 0.25 m, no drive-train inertia) on the
same road, whose inclination (column 3 of a time table) is 0.05 between 20
and 25 s.  ``vehicle`` is driven by a torque proportional to a time-table
profile (column 2), scaled so that the profile value 1 balances drag, rolling
and grade resistance at the nominal speed ``vNom = 25/3.5 m/s``.
``vehicle1`` gets twice that torque and pulls ``trailer``, an identical
vehicle coupled through a MultiSensor, so both move like ``vehicle``.  The
rolling resistance switches at |v| = vReg (state events) around standstill.

Run ``acausal compare examples/translational_vehicle.py`` to check it against
the MSL reference results.
"""

import sympy as sp

from acausal import Experiment, Model, Parameter
from acausal.library.blocks import CombiTimeTable, Extrapolation, Gain
from acausal.library.rotational import Torque
from acausal.library.translational import G_N, MultiSensor, Vehicle as VehicleModel

#: [time, torque profile, inclination]
TORQUE_AND_INCLINATION = [
    [0, 0, 0], [5, 0, 0], [5, 5.6, 0], [10.8, 5.6, 0], [10.8, 1, 0], [20, 1, 0], [20, 2.8, 0.05],
    [25, 2.8, 0.05], [25, 1, 0], [50, 1, 0], [50, -5, 0], [55, -5, 0], [55, 0, 0], [60, 0, 0],
]


class Vehicle(Model):
    """One-dimensional vehicle with driving resistances."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.Vehicle"
    experiment = Experiment(start_time=0.0, stop_time=60.0, interval=0.01)

    m = Parameter(100.0, unit="kg", description="Mass of vehicle")
    R = Parameter(0.25, unit="m", description="Radius of wheel")
    A = Parameter(1.0, unit="m2", description="Cross section of vehicle")
    Cd = Parameter(0.5, description="Drag resistance coefficient")
    rho = Parameter(1.18, unit="kg/m3", description="Density of air")
    vWind = Parameter(0.0, unit="m/s", description="Constant wind velocity")  # noqa: N815
    Cr = Parameter(0.01, description="Rolling resistance coefficient")
    inclination = Parameter(0.0, description="Constant inclination = tan(angle)")
    vNom = Parameter(25 / 3.5, unit="m/s", description="Nominal velocity")  # noqa: N815

    def build(self):
        # the MSL's final parameters fDrag, alpha, fRoll and fGrav: the resistances at vNom
        alpha = sp.atan(self.inclination)
        f_drag = self.Cd * self.A * self.rho * (self.vNom - self.vWind) ** 2 / 2
        f_roll = self.Cr * self.m * G_N * sp.cos(alpha)
        f_grav = self.m * G_N * sp.sin(alpha)
        common = dict(m=self.m, J=0, R=self.R, A=self.A, Cd=self.Cd, CrConstant=self.Cr,
                      vWindConstant=self.vWind, useInclinationInput=True)
        self.vehicle = VehicleModel(**common, s=dict(fixed=True), v=dict(fixed=True))
        self.vehicle1 = VehicleModel(**common, s=dict(fixed=True), v=dict(fixed=True))
        self.trailer = VehicleModel(**common, s=dict(fixed=False), v=dict(fixed=False))
        self.multiSensor = MultiSensor()
        self.timeTableTorqueInclination = CombiTimeTable(table=TORQUE_AND_INCLINATION,
                                                         extrapolation=Extrapolation.HoldLastPoint)
        self.torque = Torque()
        self.torque1 = Torque()
        self.gain = Gain(k=(f_drag + f_roll + f_grav) * self.R)
        self.gain1 = Gain(k=2)

        table = self.timeTableTorqueInclination
        self.connect(table.y[1], self.gain.u)
        self.connect(table.y[2], self.vehicle.inclination)
        self.connect(self.gain.y, self.torque.tau)
        self.connect(self.torque.flange, self.vehicle.flangeR)
        self.connect(self.torque1.flange, self.vehicle1.flangeR)
        self.connect(self.vehicle.inclination, self.vehicle1.inclination)
        self.connect(self.vehicle1.inclination, self.trailer.inclination)
        self.connect(self.gain.y, self.gain1.u)
        self.connect(self.gain1.y, self.torque1.tau)
        self.connect(self.vehicle1.flangeT, self.multiSensor.flange_a)
        self.connect(self.multiSensor.flange_b, self.trailer.flangeT)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(Vehicle())
    print(result.summary())
    for name in ("vehicle.v", "vehicle1.v", "trailer.v"):
        print(f"{name}(60) = {result.final(name)}")
