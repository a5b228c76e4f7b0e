"""Ideal switching elements of Modelica.Electrical.Analog.Ideal, in four MSL examples.

* ``CharacteristicIdealDiodes``: three ideal diodes driven by 1 Hz sines
  through 1 mOhm, one without losses (``Ron = Goff = 0``), one with ``Ron =
  Goff = 0.1``, one with a knee at 5 V: their voltages trace the three
  characteristics.
* ``IdealTriacCircuit``: a 5 V, 2 Hz source, 20 Ohm and an ideal triac
  (two antiparallel thyristors with an RC snubber) fired by a Boolean pulse.
* ``SwitchWithArc``: 50 V on an RL load (0.1 H, 1 Ohm), switched once per
  second by an ideal closing switch and by a closer with an arc model; the
  ideal switch cuts the current at once, the arc burns until the current has
  fallen to zero.
* ``Rectifier``: a B6 diode bridge on a 400 V, 50 Hz three-phase line with
  60 uH line inductors, feeding two 30 mF capacitors and a 500 A load.

Each reproduces the MSL class of ``modelica_class`` with the
experiment of its annotation.
"""

import sympy as sp

from acausal import Eq, Experiment, Model, Parameter, Variable
from acausal.library.blocks import BooleanPulse, Constant
from acausal.library.electrical import (
    Capacitor,
    ConstantVoltage,
    Ground,
    Inductor,
    Resistor,
    SignalCurrent,
    SineVoltage,
)
from acausal.library.electrical.ideal import CloserWithArc, IdealClosingSwitch, IdealDiode, IdealTriac


class CharacteristicIdealDiodes(Model):
    """Characteristic of ideal diodes."""

    modelica_class = "Modelica.Electrical.Analog.Examples.CharacteristicIdealDiodes"
    experiment = Experiment(start_time=0.0, stop_time=1.0)

    def build(self):
        self.Ideal = IdealDiode(Ron=0, Goff=0, Vknee=0)
        self.With_Ron_Goff = IdealDiode(Ron=0.1, Goff=0.1, Vknee=0)
        self.With_Ron_Goff_Vknee = IdealDiode(Ron=0.2, Goff=0.2, Vknee=5)
        self.SineVoltage1 = SineVoltage(V=10, offset=-9, f=1)
        self.Ground1 = Ground()
        self.R1 = Resistor(R=1e-3)
        self.R2 = Resistor(R=1e-3)
        self.R3 = Resistor(R=1e-3)
        self.SineVoltage2 = SineVoltage(V=10, offset=0, f=1)
        self.SineVoltage3 = SineVoltage(V=10, offset=0, f=1)
        self.connect(self.Ground1.p, self.SineVoltage1.n)
        self.connect(self.Ideal.n, self.R1.p)
        self.connect(self.With_Ron_Goff.n, self.R2.p)
        self.connect(self.With_Ron_Goff_Vknee.n, self.R3.p)
        self.connect(self.R1.n, self.R2.n)
        self.connect(self.R2.n, self.R3.n)
        self.connect(self.R3.n, self.Ground1.p)
        self.connect(self.SineVoltage2.p, self.Ideal.p)
        self.connect(self.SineVoltage2.n, self.Ground1.p)
        self.connect(self.SineVoltage1.p, self.With_Ron_Goff.p)
        self.connect(self.With_Ron_Goff_Vknee.p, self.SineVoltage3.p)
        self.connect(self.SineVoltage3.n, self.Ground1.p)


class IdealTriacCircuit(Model):
    """Ideal triac test circuit."""

    modelica_class = "Modelica.Electrical.Analog.Examples.IdealTriacCircuit"
    experiment = Experiment(start_time=0.0, stop_time=2.0)

    def build(self):
        self.ground = Ground()
        self.R = Resistor(R=20)
        self.V = SineVoltage(V=5, f=2)
        self.booleanPulse = BooleanPulse(width=50, period=0.25, startTime=0.1)  # noqa: N815
        self.idealTriac = IdealTriac(  # noqa: N815
            capacitor=dict(v=dict(start=0, fixed=True)),
            idealThyristor=dict(off=dict(start=True, fixed=True)),
            idealThyristor1=dict(off=dict(start=True, fixed=True)))
        self.connect(self.V.n, self.ground.p)
        self.connect(self.R.p, self.V.p)
        self.connect(self.R.n, self.idealTriac.n)
        self.connect(self.idealTriac.p, self.ground.p)
        self.connect(self.idealTriac.fire1, self.booleanPulse.y)


class SwitchWithArc(Model):
    """Comparison of switch models both with and without arc."""

    modelica_class = "Modelica.Electrical.Analog.Examples.SwitchWithArc"
    # stiff: the open switch is Goff = 1e-5 S in series with 0.1 H (L*Goff = 1e-6 s), as DASSL is
    experiment = Experiment(start_time=0.0, stop_time=2.0, interval=0.00025, tolerance=1e-6, method="BDF")

    def build(self):
        self.booleanPulse = BooleanPulse(period=1)  # noqa: N815
        self.ground1 = Ground()
        self.constantVoltage1 = ConstantVoltage(V=50)  # noqa: N815
        self.inductor1 = Inductor(L=0.1, i=dict(start=0, fixed=True))
        self.resistor1 = Resistor(R=1)
        self.switch1 = IdealClosingSwitch()
        self.ground2 = Ground()
        self.constantVoltage2 = ConstantVoltage(V=50)  # noqa: N815
        self.inductor2 = Inductor(L=0.1, i=dict(start=0, fixed=True))
        self.resistor2 = Resistor(R=1)
        self.switch2 = CloserWithArc(dVdt=10000, V0=30, Vmax=60, off=dict(fixed=True))
        self.connect(self.inductor1.n, self.resistor1.p)
        self.connect(self.resistor1.n, self.ground1.p)
        self.connect(self.constantVoltage1.n, self.ground1.p)
        self.connect(self.switch1.n, self.inductor1.p)
        self.connect(self.constantVoltage1.p, self.switch1.p)
        self.connect(self.inductor2.n, self.resistor2.p)
        self.connect(self.resistor2.n, self.ground2.p)
        self.connect(self.constantVoltage2.n, self.ground2.p)
        self.connect(self.switch2.n, self.inductor2.p)
        self.connect(self.constantVoltage2.p, self.switch2.p)
        self.connect(self.booleanPulse.y, self.switch1.control)
        self.connect(self.booleanPulse.y, self.switch2.control)


class Rectifier(Model):
    """B6 diode bridge.

    A diode that turns on in series with a line inductor has, at that
    instant, ``s`` (its current) of about 1e-10 A against hundreds of
    amperes: round-off of ``s = (v - Vknee)/Ron``.  Event iteration keeps the
    crossed relation at the value its crossing gave it (see
    ``DiscreteEvaluator._keep_crossed``) instead of deciding that round-off.
    """

    modelica_class = "Modelica.Electrical.Analog.Examples.Rectifier"
    # stiff: each diode's Ron = 1 mOhm against 60 uH (and Goff against it: 60 ms .. 60 ns)
    experiment = Experiment(start_time=0.0, stop_time=0.1, interval=1e-5, method="BDF")

    VAC = Parameter(400.0, unit="V", description="RMS line-to-line")
    f = Parameter(50.0, unit="Hz", description="Line frequency")
    LAC = Parameter(60e-6, unit="H", description="Line inductor")
    Ron = Parameter(1e-3, unit="Ohm", description="Diode forward resistance")
    Goff = Parameter(1e-3, unit="S", description="Diode backward conductance")
    Vknee = Parameter(2.0, unit="V", description="Diode threshold voltage")
    CDC = Parameter(15e-3, unit="F", description="DC capacitance")
    IDC = Parameter(500.0, unit="A", description="Load current")
    uDC = Variable(unit="V")  # noqa: N815 - Modelica name
    iAC = Variable(unit="A", shape=(3,))  # noqa: N815 - Modelica name
    uAC = Variable(unit="V", shape=(3,))  # noqa: N815 - Modelica name
    Losses = Variable(unit="W")

    def build(self):
        VAC, f, LAC, CDC = self.VAC, self.f, self.LAC, self.CDC
        diode = dict(Ron=self.Ron, Goff=self.Goff, Vknee=self.Vknee)
        amplitude = VAC * sp.sqrt(sp.Rational(2, 3))
        self.SineVoltage1 = SineVoltage(f=f, V=amplitude)
        self.SineVoltage2 = SineVoltage(f=f, phase=-2 * sp.pi / 3, V=amplitude)
        self.SineVoltage3 = SineVoltage(f=f, phase=-4 * sp.pi / 3, V=amplitude)
        self.Inductor1 = Inductor(L=LAC)
        self.Inductor2 = Inductor(L=LAC, i=dict(start=0, fixed=True))
        self.Inductor3 = Inductor(L=LAC, i=dict(start=0, fixed=True))
        for k in range(1, 7):
            setattr(self, f"IdealDiode{k}", IdealDiode(**diode))
        self.Capacitor1 = Capacitor(C=2 * CDC)
        self.Capacitor2 = Capacitor(C=2 * CDC)
        self.Ground1 = Ground()
        self.SignalCurrent1 = SignalCurrent()
        self.Constant1 = Constant(k=self.IDC)
        self.connect(self.SineVoltage1.n, self.SineVoltage2.n)
        self.connect(self.SineVoltage2.n, self.SineVoltage3.n)
        self.connect(self.SineVoltage1.p, self.Inductor1.p)
        self.connect(self.SineVoltage2.p, self.Inductor2.p)
        self.connect(self.SineVoltage3.p, self.Inductor3.p)
        self.connect(self.IdealDiode1.p, self.IdealDiode4.n)
        self.connect(self.IdealDiode2.p, self.IdealDiode5.n)
        self.connect(self.IdealDiode3.p, self.IdealDiode6.n)
        self.connect(self.IdealDiode1.n, self.IdealDiode2.n)
        self.connect(self.IdealDiode2.n, self.IdealDiode3.n)
        self.connect(self.IdealDiode4.p, self.IdealDiode5.p)
        self.connect(self.IdealDiode5.p, self.IdealDiode6.p)
        self.connect(self.Capacitor2.n, self.IdealDiode6.p)
        self.connect(self.IdealDiode3.n, self.Capacitor1.p)
        self.connect(self.Capacitor1.n, self.Capacitor2.p)
        self.connect(self.Capacitor2.p, self.Ground1.p)
        self.connect(self.Capacitor1.p, self.SignalCurrent1.p)
        self.connect(self.SignalCurrent1.n, self.Capacitor2.n)
        self.connect(self.Constant1.y, self.SignalCurrent1.i)
        self.connect(self.Inductor1.n, self.IdealDiode1.p)
        self.connect(self.Inductor2.n, self.IdealDiode2.p)
        self.connect(self.Inductor3.n, self.IdealDiode3.p)

    def initial_equations(self):
        return [Eq(self.Capacitor1.v, self.VAC * sp.sqrt(2) / 2),
                Eq(self.Capacitor2.v, self.VAC * sp.sqrt(2) / 2)]

    def equations(self):
        diodes = [getattr(self, f"IdealDiode{k}") for k in range(1, 7)]
        inductors = [self.Inductor1, self.Inductor2, self.Inductor3]
        return [Eq(self.uDC, self.Capacitor1.v + self.Capacitor2.v),
                *[Eq(self.iAC[k + 1], inductors[k].i) for k in range(3)],
                *[Eq(self.uAC[k + 1], inductors[k].n.v - inductors[(k + 1) % 3].n.v) for k in range(3)],
                Eq(self.Losses, sum(d.v * d.i for d in diodes))]


if __name__ == "__main__":
    from acausal import simulate

    for model in (CharacteristicIdealDiodes(), IdealTriacCircuit(), SwitchWithArc(), Rectifier()):
        print(simulate(model).summary())
