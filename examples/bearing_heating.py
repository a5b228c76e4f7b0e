"""A bearing that heats up: mechanical energy turning into heat (written from scratch).

A sinusoidal torque drives an inertia whose bearing has Coulomb friction
(tau_pos: 1 N.m at rest rising to 1.5 N.m at 10 rad/s).  The bearing's heat
port feeds a heat capacitor, so every joule the friction dissipates shows up
as a temperature rise C·ΔT.  The shaft sticks whenever the drive torque is
below the friction torque and slides otherwise.

Energy balance: work of the torque source = kinetic energy gained + C·ΔT.
"""

import numpy as np

from acausal import Experiment, Model
from acausal.library.blocks import Sine
from acausal.library.rotational import BearingFriction, Inertia, Torque
from acausal.library.thermal import HeatCapacitor


class BearingHeating(Model):
    """Torque source, inertia, bearing friction with heat port, heat capacitor."""

    experiment = Experiment(start_time=0.0, stop_time=4.0, interval=0.001)

    def build(self):
        self.sine = Sine(amplitude=5.0, f=0.5)
        self.torque = Torque()
        self.shaft = Inertia(J=0.2, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.bearing = BearingFriction(tau_pos=[[0.0, 1.0], [10.0, 1.5]], peak=1.2, useHeatPort=True)
        self.housing = HeatCapacitor(C=50.0, T=dict(start=293.15, fixed=True))
        self.connect(self.sine.y, self.torque.tau)
        self.connect(self.torque.flange, self.shaft.flange_a)
        self.connect(self.shaft.flange_b, self.bearing.flange_a)
        self.connect(self.bearing.heatPort, self.housing.port)


def energy_balance(result):
    """(work of the source, kinetic energy, heat) along the result, trapezoid-integrated work."""
    from scipy.integrate import cumulative_trapezoid

    t = result.time
    power = result["torque.tau"] * result["shaft.w"]
    work = cumulative_trapezoid(power, t, initial=0.0)
    kinetic = 0.5 * 0.2 * result["shaft.w"] ** 2
    heat = 50.0 * (result["housing.T"] - 293.15)
    return work, kinetic, heat


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(BearingHeating(), rtol=1e-9)
    print(result.summary())
    work, kinetic, heat = energy_balance(result)
    imbalance = np.max(np.abs(work - kinetic - heat)) / np.max(np.abs(work))
    print(f"work {work[-1]:.6f} J = kinetic {kinetic[-1]:.6f} J + heat {heat[-1]:.6f} J "
          f"(largest imbalance {imbalance:.1e} of the work, trapezoid rule)")
    print(f"housing warmed by {result.final('housing.T') - 293.15:.6f} K; "
          f"{sum(1 for e in result.events if e.changes)} events changed a friction mode")
