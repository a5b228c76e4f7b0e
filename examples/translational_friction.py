"""Modelica.Mechanics.Translational.Examples.Friction: Stribeck friction and hard stops.

One sine force 25·sin(2π·0.25·t) drives two sliding masses with the same
Stribeck characteristic ``F_prop*v + F_Coulomb + F_Stribeck*exp(-fexp*|v|)``:
``stop1``, a MassWithStopAndFriction whose stops (±25 m) are never reached,
and ``mass`` on a SupportFriction whose table ``f_pos`` samples the same
characteristic (so the two move alike).  ``stop2``, a MassWithStopAndFriction
with stops at ±0.9 m, starts at -5 m/s, hits its left stop (the velocity is
reset to 0) and is pushed off it again by a spring to a fixed point.
"""

import numpy as np

from acausal import Experiment, Model
from acausal.errors import ParameterError
from acausal.library.blocks import Sine
from acausal.library.translational import Fixed, Force, Mass, MassWithStopAndFriction, Spring, SupportFriction


def GenerateStribeckFrictionTable(F_prop: float, F_Coulomb: float,  # noqa: N802,N803 - Modelica names
                                  F_Stribeck: float, fexp: float, v_max: float,  # noqa: N803
                                  nTable: int = 100) -> list[list[float]]:  # noqa: N803
    """Table of the Stribeck characteristic
    (Modelica.Mechanics.Translational.Examples.Utilities.GenerateStribeckFrictionTable).

    ``nTable`` equidistant velocities from 0 to ``v_max`` with the friction
    force ``F_Coulomb + F_prop*v + F_Stribeck*exp(-fexp*v)`` at each: the
    ``f_pos`` table of a SupportFriction equivalent to a
    MassWithStopAndFriction with the same parameters.
    """
    if nTable < 2:
        raise ParameterError(f"GenerateStribeckFrictionTable: nTable = {nTable} is below its minimum 2",
                             hint="the table needs at least two points (v = 0 and v = v_max)")
    velocity = v_max * np.arange(nTable) / (nTable - 1)
    force = F_Coulomb + F_prop * velocity + F_Stribeck * np.exp(-fexp * velocity)
    return np.column_stack([velocity, force]).tolist()


class Friction(Model):
    """Use of model Stop."""

    modelica_class = "Modelica.Mechanics.Translational.Examples.Friction"
    experiment = Experiment(start_time=0.0, stop_time=5.0, interval=0.001)

    def build(self):
        self.stop1 = MassWithStopAndFriction(L=1, s=dict(fixed=True), v=dict(fixed=True), smax=25, smin=-25, m=1,
                                             F_prop=1, F_Coulomb=5, F_Stribeck=10, fexp=2)
        self.force = Force()
        self.sineForce = Sine(amplitude=25, f=0.25)
        self.stop2 = MassWithStopAndFriction(L=1, smax=0.9, smin=-0.9, F_Coulomb=3, F_Stribeck=5,
                                             s=dict(start=0, fixed=True), m=1, F_prop=1, fexp=2,
                                             v=dict(start=-5, fixed=True))
        self.spring = Spring(s_rel0=1, c=500)
        self.fixed2 = Fixed(s0=-1.75)
        self.force2 = Force()
        self.mass = Mass(m=1, L=1, s=dict(fixed=True), v=dict(fixed=True))
        self.supportFriction = SupportFriction(f_pos=GenerateStribeckFrictionTable(
            F_prop=1, F_Coulomb=5, F_Stribeck=10, fexp=2, v_max=12, nTable=50))

        self.connect(self.spring.flange_b, self.stop2.flange_a)
        self.connect(self.sineForce.y, self.force.f)
        self.connect(self.spring.flange_a, self.fixed2.flange)
        self.connect(self.force.flange, self.stop1.flange_a)
        self.connect(self.force2.flange, self.mass.flange_a)
        self.connect(self.mass.flange_b, self.supportFriction.flange_a)
        self.connect(self.sineForce.y, self.force2.f)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(Friction())
    print(result.summary())
    for event in result.events:
        print(" ", event)
    print("stop1.s(5) =", result.final("stop1.s"), " mass.s(5) =", result.final("mass.s"),
          " stop2.s(5) =", result.final("stop2.s"))
