"""Examples of Modelica.Electrical.Analog with semiconductor devices.

- ``NandGate``: a CMOS NAND gate of two PMOS and two NMOS transistors
  (Utilities.Nand) driven by two trapezoidal pulse trains; its output node
  ``Nand.C4.v`` is high unless both inputs are.
- ``HeatingMOSInverter``: a CMOS inverter whose transistors' parameters
  follow their temperature; their losses warm a heat capacitor through
  thermal conductors.
- ``HeatingRectifier``: a half-wave rectifier with a temperature dependent
  diode, a smoothing capacitor and a load resistor; the diode's loss warms a
  heat capacitor.
- ``DifferenceAmplifier``: a differential pair of NPN transistors
  (Utilities.Transistor: an Ebers-Moll NPN with base and collector
  resistors and a base capacitance) fed by a damped sine.
- ``ThyristorBehaviourTest``: a thyristor fired by gate current pulses in a
  sine-fed R-L circuit (not yet compared: see its docstring).

The circuits are stiff (picosecond to nanosecond time constants beside the
sources' periods): the experiments name BDF, as Dymola's DASSL is.
"""

from acausal import Experiment, Model
from acausal.components.electrical import Pin
from acausal.language import Component
from acausal.library.electrical import (
    Capacitor,
    ExpSineVoltage,
    Ground,
    Inductor,
    PulseCurrent,
    RampCurrent,
    RampVoltage,
    Resistor,
    SineVoltage,
    TrapezoidVoltage,
)
from acausal.library.electrical.semiconductors import NMOS, NPN, PMOS, Diode, Thyristor
from acausal.library.thermal import FixedTemperature, HeatCapacitor, ThermalConductor


class Nand(Component):
    """CMOS NAND Gate (see Tietze/Schenk, page 157) (Modelica.Electrical.Analog.Examples.Utilities.Nand).

    Two PMOS in parallel from ``Vdd`` to the output ``y`` and two NMOS in
    series from ``y`` to ground, gates ``x1`` and ``x2``; the output node
    and the node between the NMOS each have a capacitance of 0.04 pF.
    """

    modelica_name = "Modelica.Electrical.Analog.Examples.Utilities.Nand"

    x1 = Pin(description="First input")
    x2 = Pin(description="Second input")
    Vdd = Pin(description="Supply")
    y = Pin(description="Output")

    def build(self):
        pmos = dict(W=6.5e-6, L=3.1e-6, Beta=1.05e-5, Vt=-1, K2=0.41, K5=0.8385, dW=-2.5e-6, dL=-2.1e-6)
        nmos = dict(W=6.5e-6, L=3.1e-6, Beta=4.1e-5, Vt=0.8, K2=1.144, K5=0.7311, dW=-2.5e-6, dL=-1.5e-6)
        self.TP1 = PMOS(**pmos)
        self.TP2 = PMOS(**pmos)
        self.TN1 = NMOS(**nmos)
        self.TN2 = NMOS(**nmos)
        self.C4 = Capacitor(C=0.4e-13)
        self.C7 = Capacitor(C=0.4e-13)
        self.Gnd = Ground()
        self.Gnd2 = Ground()
        self.Gnd3 = Ground()
        self.Gnd6 = Ground()
        self.Gnd7 = Ground()
        self.Gnd8 = Ground()
        self.connect(self.TN1.S, self.TN2.D)
        self.connect(self.TN2.B, self.Gnd.p)
        self.connect(self.TN2.D, self.C7.p)
        self.connect(self.TN2.S, self.Gnd.p)
        self.connect(self.TP1.S, self.TN1.D)
        self.connect(self.TP1.G, self.TN1.G)
        self.connect(self.C4.n, self.Gnd2.p)
        self.connect(self.C7.n, self.Gnd3.p)
        self.connect(self.TP2.B, self.Gnd6.p)
        self.connect(self.TN1.B, self.Gnd7.p)
        self.connect(self.TP1.B, self.Gnd8.p)
        self.connect(self.TP2.G, self.x1)
        self.connect(self.TP2.G, self.TN2.G)
        self.connect(self.TN1.G, self.x2)
        self.connect(self.TP2.S, self.TN1.D)
        self.connect(self.TN1.D, self.C4.p)
        self.connect(self.Vdd, self.TP1.D)
        self.connect(self.TP2.D, self.Vdd)
        self.connect(self.C4.p, self.y)


class NandGate(Model):
    """CMOS NAND Gate (see Tietze/Schenk, page 157)."""

    modelica_class = "Modelica.Electrical.Analog.Examples.NandGate"
    experiment = Experiment(start_time=0.0, stop_time=1e-7, interval=2e-11, method="BDF")

    def build(self):
        pulses = dict(V=3.5, rising=1e-9, width=19e-9, falling=1e-9, period=40e-9, nperiod=-1)
        self.VIN1 = TrapezoidVoltage(startTime=20e-9, **pulses)
        self.VIN2 = TrapezoidVoltage(startTime=10e-9, **pulses)
        self.VDD = RampVoltage(V=5, duration=1e-9)
        self.Gnd1 = Ground()
        self.Gnd4 = Ground()
        self.Gnd5 = Ground()
        self.Nand = Nand(C4=dict(v=dict(start=0, fixed=True)), C7=dict(v=dict(start=0, fixed=True)))
        self.connect(self.VDD.n, self.Gnd1.p)
        self.connect(self.VIN1.n, self.Gnd4.p)
        self.connect(self.VIN2.n, self.Gnd5.p)
        self.connect(self.Nand.Vdd, self.VDD.p)
        self.connect(self.VIN1.p, self.Nand.x1)
        self.connect(self.VIN2.p, self.Nand.x2)


class HeatingMOSInverter(Model):
    """Heating MOS Inverter."""

    modelica_class = "Modelica.Electrical.Analog.Examples.HeatingMOSInverter"
    experiment = Experiment(start_time=0.0, stop_time=5.0, interval=0.001, method="BDF")

    def build(self):
        self.G = Ground()
        self.Sin = SineVoltage(V=5, f=1)
        self.Capacitor1 = Capacitor(C=0.00001, v=dict(start=0, fixed=True))
        # the MSL's initial equation HeatCapacitor1.T = 293.15
        self.HeatCapacitor1 = HeatCapacitor(C=0.01, T=dict(start=293.15, fixed=True))
        self.TC1 = ThermalConductor(G=0.01)
        self.H_PMOS = PMOS(useTemperatureDependency=True)
        self.H_NMOS = NMOS(useTemperatureDependency=True)
        self.V = RampVoltage(V=5, duration=1e-2)
        self.TC2 = ThermalConductor(G=0.01)
        self.FixedTemperature1 = FixedTemperature(T=300)
        self.TC3 = ThermalConductor(G=0.01)
        self.connect(self.Sin.n, self.G.p)
        self.connect(self.Capacitor1.n, self.G.p)
        self.connect(self.H_PMOS.S, self.H_NMOS.D)
        self.connect(self.H_NMOS.D, self.Capacitor1.p)
        self.connect(self.H_NMOS.B, self.H_NMOS.S)
        self.connect(self.H_NMOS.S, self.G.p)
        self.connect(self.H_PMOS.B, self.H_PMOS.D)
        self.connect(self.V.p, self.H_PMOS.D)
        self.connect(self.V.n, self.G.p)
        self.connect(self.TC1.port_b, self.HeatCapacitor1.port)
        self.connect(self.TC2.port_b, self.HeatCapacitor1.port)
        self.connect(self.TC1.port_a, self.H_PMOS.heatPort)
        self.connect(self.TC2.port_a, self.H_NMOS.heatPort)
        self.connect(self.TC3.port_b, self.FixedTemperature1.port)
        self.connect(self.TC3.port_a, self.HeatCapacitor1.port)
        self.connect(self.Sin.p, self.H_NMOS.G)
        self.connect(self.H_PMOS.G, self.Sin.p)


class HeatingRectifier(Model):
    """Heating rectifier."""

    modelica_class = "Modelica.Electrical.Analog.Examples.HeatingRectifier"
    experiment = Experiment(start_time=0.0, stop_time=5.0, interval=0.001, method="BDF")

    def build(self):
        self.HeatingDiode1 = Diode(useTemperatureDependency=True, useHeatPort=True)
        self.G = Ground()
        self.SineVoltage1 = SineVoltage(V=1, f=1)
        self.Capacitor1 = Capacitor(C=1, v=dict(start=0, fixed=True))
        # the MSL's initial equation HeatCapacitor1.T = 293.15
        self.HeatCapacitor1 = HeatCapacitor(C=1, T=dict(start=293.15, fixed=True))
        self.ThermalConductor1 = ThermalConductor(G=10)
        self.R = Resistor(R=1)
        self.connect(self.SineVoltage1.p, self.HeatingDiode1.p)
        self.connect(self.SineVoltage1.n, self.G.p)
        self.connect(self.Capacitor1.n, self.G.p)
        self.connect(self.HeatingDiode1.n, self.Capacitor1.p)
        self.connect(self.HeatingDiode1.heatPort, self.ThermalConductor1.port_a)
        self.connect(self.ThermalConductor1.port_b, self.HeatCapacitor1.port)
        self.connect(self.R.p, self.Capacitor1.p)
        self.connect(self.R.n, self.Capacitor1.n)


class Transistor(Component):
    """Transistor with resistance an capacitance (Modelica.Electrical.Analog.Examples.Utilities.Transistor).

    An Ebers-Moll NPN ``Tr`` (its collector-substrate voltage starting at 0)
    with a base resistor ``rtb`` of 0.05 Ohm, a collector resistor ``rtc`` of
    0.1 Ohm and a base capacitance ``ct`` of 0.1 nF to ground.
    """

    modelica_name = "Modelica.Electrical.Analog.Examples.Utilities.Transistor"

    c = Pin(description="Collector")
    b = Pin(description="Base")
    e = Pin(description="Emitter")

    def build(self):
        self.rtb = Resistor(R=0.05)
        self.rtc = Resistor(R=0.1)
        self.ct = Capacitor(C=1e-10)
        self.Tr = NPN(Bf=50, Br=0.1, Is=1e-16, Vak=0.02, Tauf=0.12e-9, Taur=5e-9, Ccs=1e-12, Cje=0.4e-12,
                      Cjc=0.5e-12, Phie=0.8, Me=0.4, Phic=0.8, Mc=0.333, Gbc=1e-15, Gbe=1e-15, Vt=0.02585,
                      UIC=True)
        self.Ground1 = Ground()
        self.connect(self.rtb.n, self.Tr.B)
        self.connect(self.rtb.n, self.ct.p)
        self.connect(self.ct.n, self.Ground1.p)
        self.connect(self.Tr.C, self.rtc.p)
        self.connect(self.rtc.n, self.c)
        self.connect(self.b, self.rtb.p)
        self.connect(self.Tr.E, self.e)


class DifferenceAmplifier(Model):
    """Simple NPN transistor amplifier circuit.

    The experiment is that of the reference result (StopTime = 1 s, as the
    MSL 4.0.0 annotation had it; MSL 4.1.0 corrected it to 1e-8 s), so that
    the comparison covers the reference's whole time range.
    """

    modelica_class = "Modelica.Electrical.Analog.Examples.DifferenceAmplifier"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=2e-4, method="BDF")

    def build(self):
        self.V1 = ExpSineVoltage(V=0.2, f=0.2e9, damping=0.1e8)
        self.V2 = RampVoltage(V=15, duration=1e-9)
        self.I1 = RampCurrent(I=0.16, duration=1e-9)
        self.R1 = Resistor(R=0.0001)
        self.R2 = Resistor(R=100)
        self.R3 = Resistor(R=0.0001)
        self.R4 = Resistor(R=100)
        for name in ("C1", "C4", "C5", "C2", "C3"):
            setattr(self, name, Capacitor(C=1e-10, v=dict(start=0, fixed=True)))
        for name in ("Gnd1", "Gnd9", "Gnd3", "Gnd2", "Gnd6", "Gnd7", "Gnd8", "Gnd5", "Gnd4"):
            setattr(self, name, Ground())
        self.Transistor1 = Transistor(ct=dict(v=dict(start=0, fixed=True)))
        self.Transistor2 = Transistor(ct=dict(v=dict(start=0, fixed=True)))
        self.connect(self.V1.n, self.Gnd1.p)
        self.connect(self.C1.n, self.Gnd2.p)
        self.connect(self.I1.n, self.Gnd7.p)
        self.connect(self.C5.n, self.Gnd8.p)
        self.connect(self.C3.n, self.Gnd5.p)
        self.connect(self.R3.n, self.Gnd4.p)
        self.connect(self.C2.n, self.Gnd3.p)
        self.connect(self.C4.p, self.Gnd6.p)
        self.connect(self.I1.p, self.C5.p)
        self.connect(self.R1.p, self.V1.p)
        self.connect(self.R2.p, self.V2.p)
        self.connect(self.R4.p, self.V2.p)
        self.connect(self.V2.n, self.Gnd9.p)
        self.connect(self.R1.n, self.Transistor1.b)
        self.connect(self.Transistor1.b, self.C1.p)
        self.connect(self.Transistor1.c, self.C2.p)
        self.connect(self.R2.n, self.Transistor1.c)
        self.connect(self.Transistor1.e, self.I1.p)
        self.connect(self.Transistor2.b, self.R3.p)
        self.connect(self.Transistor2.b, self.C3.p)
        self.connect(self.C4.n, self.Transistor2.c)
        self.connect(self.R4.n, self.Transistor2.c)
        self.connect(self.C5.p, self.Transistor2.e)


class ThyristorBehaviourTest(Model):
    """Thyristor demonstration example (Modelica.Electrical.Analog.Examples.ThyristorBehaviourTest).

    Stiff: the blocking thyristor (1 MOhm) in series with 2 uH makes a time
    constant of 2 ps. Its anode-cathode voltage is solved by Newton from the
    inductor current, and a residual of 1e-10 A is still 0.1 mV there: the
    Newton iteration also asks its step to be small
    (:func:`acausal.compiler.codegen.newton_solve`), or the integrator's
    Jacobian would not see the voltage follow the current.
    """

    modelica_class = "Modelica.Electrical.Analog.Examples.ThyristorBehaviourTest"
    experiment = Experiment(start_time=0.0, stop_time=0.0002, interval=4e-8, method="BDF")

    def build(self):
        self.ground = Ground()
        self.sineVoltage = SineVoltage(V=30, f=10000)
        self.resistor = Resistor(R=10)
        self.pulseCurrent = PulseCurrent(width=10, period=0.0001, startTime=0.00002, I=0.005)
        self.thyristor_v4_1 = Thyristor(vControl=dict(fixed=True), vAK=dict(start=0), vGK=dict(start=0))
        self.inductor = Inductor(L=2e-6, i=dict(start=0, fixed=True))
        self.connect(self.sineVoltage.n, self.ground.p)
        self.connect(self.sineVoltage.p, self.thyristor_v4_1.Anode)
        self.connect(self.resistor.p, self.thyristor_v4_1.Cathode)
        self.connect(self.pulseCurrent.n, self.thyristor_v4_1.Gate)
        self.connect(self.resistor.p, self.pulseCurrent.p)
        self.connect(self.resistor.n, self.inductor.p)
        self.connect(self.inductor.n, self.ground.p)


if __name__ == "__main__":
    from acausal import simulate

    for model in (NandGate, HeatingMOSInverter, HeatingRectifier, DifferenceAmplifier, ThyristorBehaviourTest):
        print(simulate(model()).summary())
