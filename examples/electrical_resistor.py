"""Modelica.Electrical.Analog.Examples.Resistor: a resistor with a simple thermal network.

A sine voltage of 220 V at 1 Hz drives a 100 Ohm resistor whose resistance
grows with its temperature (``alpha`` = 1e-3 1/K from 20 degC).  Its loss
``LossPower = v*i`` leaves through the heat port and a thermal conductor of
50 W/K to the environment at 20 degC; with no heat capacity in the network
the resistor's temperature follows the loss at once,
``T = 293.15 K + LossPower/50``, which closes an algebraic loop through
``R_actual``.
"""

from acausal import Experiment, Model
from acausal.library.electrical import Ground, Resistor, SineVoltage
from acausal.library.thermal import CelsiusFixedTemperature, ThermalConductor


class ResistorExample(Model):
    """Resistor with simple thermal network."""

    modelica_class = "Modelica.Electrical.Analog.Examples.Resistor"
    experiment = Experiment(start_time=0.0, stop_time=5.0, interval=0.001)

    def build(self):
        self.resistor = Resistor(R=100, alpha=1e-3, T_ref=293.15, i=dict(start=0), useHeatPort=True)
        self.G = Ground()
        self.SineVoltage1 = SineVoltage(V=220, f=1)
        self.thermalConductor = ThermalConductor(G=50)
        self.fixedTemperature = CelsiusFixedTemperature(T=20)
        self.connect(self.SineVoltage1.n, self.G.p)
        self.connect(self.resistor.heatPort, self.thermalConductor.port_a)
        self.connect(self.SineVoltage1.p, self.resistor.p)
        self.connect(self.G.p, self.resistor.n)
        self.connect(self.thermalConductor.port_b, self.fixedTemperature.port)


if __name__ == "__main__":
    from acausal import simulate

    result = simulate(ResistorExample())
    print(result.summary())
