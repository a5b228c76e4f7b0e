"""Modelica.Mechanics.Rotational.Examples.EddyCurrentBrake: an eddy current brake stops an inertia.

An inertia spinning at 20 rad/s is braked by an eddy current brake whose
excitation ramps from 0 to 1 between 0.1 s and 0.2 s.  The kinetic energy
lost heats the brake's heat capacity (1 J/K, adiabatic over the short
braking); the copper's temperature coefficient makes the warming brake
shift its torque peak to higher speeds.

Run ``acausal compare examples/rotational_eddy_current_brake.py`` to check it
against the MSL reference results.
"""

from acausal import Experiment, Model
from acausal.library.blocks import Ramp
from acausal.library.rotational import EddyCurrentTorque, Inertia
from acausal.library.thermal import HeatCapacitor

#: Modelica.Electrical.Machines.Thermal.Constants.alpha20Copper (1/K)
ALPHA20_COPPER = 3.920e-3


class EddyCurrentBrake(Model):
    """Demonstrate the usage of the rotational eddy current brake."""

    modelica_class = "Modelica.Mechanics.Rotational.Examples.EddyCurrentBrake"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001)

    def build(self):
        self.eddyCurrentTorque = EddyCurrentTorque(useExcitationInput=True, tau_nominal=100, w_nominal=10,
                                                   useSupport=False, alpha20=ALPHA20_COPPER, TRef=293.15,
                                                   useHeatPort=True)
        self.inertia = Inertia(phi=dict(fixed=True, start=0), J=1, w=dict(fixed=True, start=20))
        self.heatCapacitor = HeatCapacitor(C=1, T=dict(fixed=True))
        self.ramp = Ramp(height=1, duration=0.1, offset=0, startTime=0.1)

        self.connect(self.eddyCurrentTorque.flange, self.inertia.flange_a)
        self.connect(self.eddyCurrentTorque.heatPort, self.heatCapacitor.port)
        self.connect(self.ramp.y, self.eddyCurrentTorque.excitation)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(EddyCurrentBrake())
    print(result.summary())
    print("inertia.w(1) =", result.final("inertia.w"), " heatCapacitor.T(1) =", result.final("heatCapacitor.T"))
