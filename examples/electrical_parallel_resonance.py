"""Modelica.Electrical.Analog.Examples.ParallelResonance: a parallel resonant circuit.

Two identical circuits, each a current source feeding L = 0.1/(2*pi) H (in
series with 0.5 Ohm) parallel to C = 0.001/(2*pi) F: resonance at
1/(2*pi*sqrt(L*C)) = 100 Hz.  The sources' amplitude is 1 A and their
frequency ramps from 0 to 200 Hz in 1 s (``der(phi) = 2*pi*f``), one a sine,
the other a cosine, so the voltage across each circuit swells as the
frequency passes 100 Hz at t = 0.5 s.
"""

import math

from acausal import Experiment, Model
from acausal.library.blocks import Ramp
from acausal.library.electrical import (
    Capacitor,
    CosineCurrentVariableFrequencyAndAmplitude,
    Ground,
    Inductor,
    Resistor,
    SineCurrentVariableFrequencyAndAmplitude,
    VoltageSensor,
)


class ParallelResonance(Model):
    """Parallel resonance circuit."""

    modelica_class = "Modelica.Electrical.Analog.Examples.ParallelResonance"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=1e-4)

    def build(self):
        L, C = 0.1 / (2 * math.pi), 0.001 / (2 * math.pi)
        self.ramp = Ramp(height=200, duration=1, offset=0, startTime=0)

        self.sineCurrent = SineCurrentVariableFrequencyAndAmplitude(useConstantAmplitude=True,
                                                                    phi=dict(fixed=True))
        self.ground1 = Ground()
        self.resistor1 = Resistor(R=0.5)
        self.inductor1 = Inductor(i=dict(fixed=True), L=L)
        self.capacitor1 = Capacitor(v=dict(fixed=True), C=C)
        self.voltageSensor1 = VoltageSensor()
        self.connect(self.sineCurrent.p, self.ground1.p)
        self.connect(self.ramp.y, self.sineCurrent.f)
        self.connect(self.ground1.p, self.inductor1.n)
        self.connect(self.sineCurrent.n, self.resistor1.p)
        self.connect(self.resistor1.n, self.inductor1.p)
        self.connect(self.ground1.p, self.capacitor1.n)
        self.connect(self.sineCurrent.n, self.capacitor1.p)
        self.connect(self.sineCurrent.n, self.voltageSensor1.p)
        self.connect(self.ground1.p, self.voltageSensor1.n)

        self.cosineCurrent = CosineCurrentVariableFrequencyAndAmplitude(useConstantAmplitude=True,
                                                                        phi=dict(fixed=True))
        self.ground2 = Ground()
        self.resistor2 = Resistor(R=0.5)
        self.inductor2 = Inductor(i=dict(fixed=True), L=L)
        self.capacitor2 = Capacitor(v=dict(fixed=True), C=C)
        self.voltageSensor2 = VoltageSensor()
        self.connect(self.cosineCurrent.p, self.ground2.p)
        self.connect(self.ground2.p, self.inductor2.n)
        self.connect(self.cosineCurrent.n, self.resistor2.p)
        self.connect(self.resistor2.n, self.inductor2.p)
        self.connect(self.ground2.p, self.capacitor2.n)
        self.connect(self.cosineCurrent.n, self.capacitor2.p)
        self.connect(self.cosineCurrent.n, self.voltageSensor2.p)
        self.connect(self.ground2.p, self.voltageSensor2.n)
        self.connect(self.ramp.y, self.cosineCurrent.f)

if __name__ == "__main__":
    from acausal import simulate

    result = simulate(ParallelResonance())
    print(result.summary())
