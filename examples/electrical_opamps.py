"""Operational amplifier circuits of Modelica.Electrical.Analog.Examples and Examples.OpAmps.

The OpAmps package's circuits are built from Modelica.Electrical.Analog.
Examples.OpAmps.OpAmpCircuits (an IdealizedOpAmpLimited with V0 = 15000 and
a +-15 V supply, wired into a four-pin subcircuit): the inverting adder
(``vOut = -(vIn1 + vIn2)``), the differentiator and integrator (gain 2 at
10 Hz) and the first-order low pass (1 Hz) driven by a 10 Hz trapezoid, the
voltage follower, the Schmitt trigger (hysteresis +-1 V) and the
rectangle-triangle signal generator (a Schmitt trigger and an integrator in
a loop, 10 V at 10 Hz).  From Modelica.Electrical.Analog.Examples:
the inverting amplifier with an IdealOpAmpLimited (gain -2), the fifth-order
Cauer low pass as a passive LC ladder and as its active simulation with
IdealOpAmp3Pin integrators (negative resistors included, as in the MSL), and
the saturating inductor beside a linear one.
"""

import math

from acausal import Component, Eq, Experiment, Model, Parameter, Variable
from acausal.library.blocks.nonlinear import LimiterHomotopy
from acausal.components.electrical import FourPin, NegativePin, PositivePin
from acausal.library.electrical import (
    Capacitor,
    ConstantVoltage,
    Ground,
    Inductor,
    Resistor,
    SaturatingInductor,
    SineVoltage,
    StepVoltage,
    TrapezoidVoltage,
    VoltageSensor,
)
from acausal.library.electrical.ideal_opamps import IdealOpAmp3Pin, IdealOpAmpLimited, IdealizedOpAmpLimited

#: The MSL examples' input: amplitude Vin = 5 V at f = 10 Hz.
VIN, F = 5.0, 10.0


def _trapezoid(V: float, offset: float, f: float = F) -> TrapezoidVoltage:
    """The examples' trapezoid: 0.2/f rising, 0.3/f high, 0.2/f falling, started mid-plateau.

    ``startTime = -(rising + width/2)``: at t = 0 the source is in the middle of its plateau.
    """
    rising, width = 0.2 / f, 0.3 / f
    return TrapezoidVoltage(V=V, rising=rising, width=width, falling=0.2 / f, period=1 / f, nperiod=-1,
                            offset=offset, startTime=-(rising + width / 2))


# --------------------------------------------------------------------------
# Modelica.Electrical.Analog.Examples.OpAmps.OpAmpCircuits


class PartialOpAmp(FourPin):
    """Partial circuit of operational amplifiers (Modelica.Electrical.Analog.Examples.OpAmps.OpAmpCircuits.PartialOpAmp).

    A FourPin around an IdealizedOpAmpLimited ``opAmp`` with gain ``V0``
    and the supply ``Vps``, ``Vns``; the input port's n1 and the output
    port's n2 are one node, on the op-amp's positive input.
    """

    modelica_name = "Modelica.Electrical.Analog.Examples.OpAmps.OpAmpCircuits.PartialOpAmp"

    Vps = Parameter(15.0, unit="V", description="Positive supply")
    Vns = Parameter(-15.0, unit="V", description="Negative supply")
    V0 = Parameter(15000.0, unit="1", description="No-load amplification")

    def build(self):
        self.opAmp = IdealizedOpAmpLimited(V0=self.V0, useSupply=False, Vps=self.Vps, Vns=self.Vns)
        # the MSL's out(i(start=0, fixed=false)) is the default start here (acausal's connectors take no modifier)
        self.connect(self.n1, self.n2)
        self.connect(self.opAmp.out, self.p2)
        self.connect(self.n1, self.opAmp.in_p)


class Add(PartialOpAmp):
    """Adding operational amplifier circuit (Modelica.Electrical.Analog.Examples.OpAmps.OpAmpCircuits.Add).

    ``v2 = -(k1*v1 + k2*v1_2)``: the inputs p1 and p1_2 reach the inverting
    input through ``R/k1`` and ``R/k2``, the output feeds back through ``R``.
    """

    modelica_name = "Modelica.Electrical.Analog.Examples.OpAmps.OpAmpCircuits.Add"

    k1 = Parameter(1.0, min=0, description="Weight of input 1")
    k2 = Parameter(1.0, min=0, description="Weight of input 2")
    R = Parameter(1000.0, unit="Ohm", description="Resistance at output of OpAmp")
    v1_2 = Variable(unit="V", description="Voltage drop of port 1_2 (= p1_2.v - n1.v)")
    i1_2 = Variable(unit="A", description="Current flowing from pos. to neg. pin of port 1_2")
    p1_2 = PositivePin(description="Positive electrical pin 1.2")

    def build(self):
        super().build()
        self.r1 = Resistor(R=self.R / self.k1)
        self.r2 = Resistor(R=self.R / self.k2)
        self.r = Resistor(R=self.R)
        self.connect(self.p1, self.r1.p)
        self.connect(self.p1_2, self.r2.p)
        self.connect(self.r2.n, self.opAmp.in_n)
        self.connect(self.opAmp.in_n, self.r1.n)
        self.connect(self.opAmp.in_n, self.r.n)
        self.connect(self.opAmp.out, self.r.p)

    def equations(self):
        return [Eq(self.v1_2, self.p1_2.v - self.n1.v), Eq(self.i1_2, self.p1_2.i)]


class Der(PartialOpAmp):
    """Differentiating operational amplifier circuit (Modelica.Electrical.Analog.Examples.OpAmps.OpAmpCircuits.Der).

    ``v2 = -R*C*der(v1)``, with ``C = k/(2*pi*f*R)``: gain ``k`` at the
    frequency ``f``.  ``v`` is the capacitor's voltage (its state).
    """

    modelica_name = "Modelica.Electrical.Analog.Examples.OpAmps.OpAmpCircuits.Der"

    k = Parameter(1.0, min=0, description="Desired amplification at frequency f")
    f = Parameter(1.0, unit="Hz", description="Frequency")
    R = Parameter(1000.0, unit="Ohm", description="Resistance at output of OpAmp")
    v = Variable(unit="V", start=0.0, description="Capacitor voltage = state")

    def build(self):
        super().build()
        self.c = Capacitor(C=self.k / (2 * math.pi * self.f * self.R))
        self.r = Resistor(R=self.R)
        self.connect(self.c.n, self.opAmp.in_n)
        self.connect(self.opAmp.in_n, self.r.n)
        self.connect(self.opAmp.out, self.r.p)
        self.connect(self.c.p, self.p1)

    def equations(self):
        return [Eq(self.v, self.c.v)]


class Integrator(PartialOpAmp):
    """Integrating operational amplifier circuit (Modelica.Electrical.Analog.Examples.OpAmps.OpAmpCircuits.Integrator).

    ``der(v2) = -v1/(R*C)``, with ``C = 1/k/(2*pi*f*R)``: gain ``k`` at the
    frequency ``f``.  ``v`` is the capacitor's voltage (its state).
    """

    modelica_name = "Modelica.Electrical.Analog.Examples.OpAmps.OpAmpCircuits.Integrator"

    k = Parameter(1.0, min=0, description="Desired amplification at frequency f")
    f = Parameter(1.0, unit="Hz", description="Frequency")
    R = Parameter(1000.0, unit="Ohm", description="Resistance at negative input of OpAmp")
    v = Variable(unit="V", start=0.0, description="Capacitor voltage = state")
    v2 = Variable(unit="V", start=0.0, description="Voltage drop of port 2 (= p2.v - n2.v)")

    def build(self):
        super().build()
        self.c = Capacitor(C=1 / self.k / (2 * math.pi * self.f * self.R))
        self.r = Resistor(R=self.R)
        self.connect(self.r.p, self.p1)
        self.connect(self.r.n, self.opAmp.in_n)
        self.connect(self.opAmp.in_n, self.c.n)
        self.connect(self.opAmp.out, self.c.p)

    def equations(self):
        return [Eq(self.v, self.c.v)]


class FirstOrder(PartialOpAmp):
    """Lowpass filter operational amplifier circuit (Modelica.Electrical.Analog.Examples.OpAmps.OpAmpCircuits.FirstOrder).

    ``T*der(v2) + v2 = -k*v1`` with ``R2 = k*R1`` and ``C = T/R2``.
    """

    modelica_name = "Modelica.Electrical.Analog.Examples.OpAmps.OpAmpCircuits.FirstOrder"

    k = Parameter(1.0, min=0, description="Desired amplification")
    R1 = Parameter(1000.0, unit="Ohm", description="Resistance at negative input of OpAmp")
    T = Parameter(1.0, unit="s", description="Time constant")
    v = Variable(unit="V", start=0.0, description="Capacitor voltage = state")
    v2 = Variable(unit="V", start=0.0, description="Voltage drop of port 2 (= p2.v - n2.v)")

    def build(self):
        super().build()
        R2 = self.k * self.R1
        self.r1 = Resistor(R=self.R1)
        self.r2 = Resistor(R=R2)
        self.c = Capacitor(C=self.T / R2)
        self.connect(self.r1.p, self.p1)
        self.connect(self.r1.n, self.opAmp.in_n)
        self.connect(self.opAmp.in_n, self.r2.n)
        self.connect(self.opAmp.in_n, self.c.n)
        self.connect(self.opAmp.out, self.r2.p)
        self.connect(self.opAmp.out, self.c.p)

    def equations(self):
        return [Eq(self.v, self.c.v)]


# --------------------------------------------------------------------------
# Modelica.Electrical.Analog.Examples.OpAmps


class Adder(Model):
    """Inverting adder: a 5 V, 10 Hz sine plus 5 V DC, ``vOut = -(vIn1 + vIn2)``."""

    modelica_class = "Modelica.Electrical.Analog.Examples.OpAmps.Adder"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001, tolerance=1e-6)

    def build(self):
        self.ground = Ground()
        self.vIn1 = SineVoltage(V=VIN, f=F)
        self.vIn2 = ConstantVoltage(V=VIN)
        self.vOut = VoltageSensor()
        self.add = Add()  # the MSL's p1_2(i(start=0)): 0 is the default start
        self.connect(self.add.n1, self.ground.p)
        self.connect(self.vIn1.p, self.add.p1)
        self.connect(self.vIn2.p, self.add.p1_2)
        self.connect(self.ground.p, self.vIn2.n)
        self.connect(self.ground.p, self.vIn1.n)
        self.connect(self.add.p2, self.vOut.n)
        self.connect(self.add.n2, self.vOut.p)


class Differentiator(Model):
    """Differentiating amplifier: a +-5 V, 10 Hz trapezoid into ``Der(k=2, f=10)``."""

    modelica_class = "Modelica.Electrical.Analog.Examples.OpAmps.Differentiator"
    # stiff: while the op-amp is not saturated its finite gain V0 closes a loop around the capacitor
    # with the time constant R*C/(V0 + 1) = 2 us, so an implicit method (the reference used DASSL)
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001, tolerance=1e-6, method="BDF")

    def build(self):
        self.ground = Ground()
        self.vIn = _trapezoid(2 * VIN, -VIN)
        self.vOut = VoltageSensor()
        self.der_ = Der(k=2, f=F, v=dict(fixed=True))
        self.connect(self.vIn.p, self.der_.p1)
        self.connect(self.vIn.n, self.der_.n1)
        self.connect(self.der_.n1, self.ground.p)
        self.connect(self.der_.p2, self.vOut.p)
        self.connect(self.der_.n2, self.vOut.n)


class IntegratorExample(Model):
    """Integrating amplifier: a +-5 V, 10 Hz trapezoid into ``Integrator(k=2, f=10)``."""

    modelica_class = "Modelica.Electrical.Analog.Examples.OpAmps.Integrator"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001, tolerance=1e-6)

    def build(self):
        self.ground = Ground()
        self.vOut = VoltageSensor()
        self.integrator = Integrator(k=2, f=F, v=dict(fixed=True))
        self.vIn = _trapezoid(2 * VIN, -VIN)
        self.connect(self.integrator.n1, self.ground.p)
        self.connect(self.integrator.p2, self.vOut.p)
        self.connect(self.integrator.n2, self.vOut.n)
        self.connect(self.vIn.p, self.integrator.p1)
        self.connect(self.vIn.n, self.integrator.n1)


class LowPass(Model):
    """Low-pass filter: a 0..5 V, 10 Hz trapezoid into a first order of 1 Hz (``T = 1/(2*pi*fG)``)."""

    modelica_class = "Modelica.Electrical.Analog.Examples.OpAmps.LowPass"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001, tolerance=1e-6)

    def build(self):
        fG = F / 10
        self.ground = Ground()
        self.vOut = VoltageSensor()
        self.firstOrder = FirstOrder(T=1 / (2 * math.pi * fG), v=dict(fixed=True))
        self.vIn = _trapezoid(VIN, 0.0)
        self.connect(self.firstOrder.n1, self.ground.p)
        self.connect(self.firstOrder.p2, self.vOut.p)
        self.connect(self.firstOrder.n2, self.vOut.n)
        self.connect(self.vIn.p, self.firstOrder.p1)
        self.connect(self.vIn.n, self.firstOrder.n1)


class SchmittTrigger(Model):
    """Schmitt trigger with hysteresis: switches at +-vHys = +-1 V of a +-5 V trapezoid.

    Positive feedback through ``R2 = R1*Vps/vHys`` onto the non-inverting
    input, the inverting input grounded.
    """

    # With positive feedback the saturated branch Newton starts from ends at the threshold (the
    # clipping is noEvent): the one-unknown loop is then solved by bracketing (codegen.newton_solve).
    modelica_class = "Modelica.Electrical.Analog.Examples.OpAmps.SchmittTrigger"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001, tolerance=1e-6)

    def build(self):
        Vps, Vns, vHys, R1 = 15.0, -15.0, 1.0, 1000.0
        k = vHys / Vps
        self.opAmp = IdealizedOpAmpLimited(Vps=Vps, Vns=Vns)  # out(i(start=0)): the default start
        self.ground = Ground()
        self.vIn = _trapezoid(2 * VIN, -VIN)
        self.vOut = VoltageSensor()
        self.r1 = Resistor(R=R1)
        self.r2 = Resistor(R=R1 / k)
        self.connect(self.ground.p, self.vIn.n)
        self.connect(self.ground.p, self.vOut.n)
        self.connect(self.opAmp.out, self.vOut.p)
        self.connect(self.opAmp.in_n, self.ground.p)
        self.connect(self.opAmp.out, self.r2.n)
        self.connect(self.r2.p, self.opAmp.in_p)
        self.connect(self.r2.p, self.r1.n)
        self.connect(self.r1.p, self.vIn.p)


class SignalGenerator(Model):
    """Rectangle-triangle generator: a Schmitt trigger (opAmp1) and an integrator (opAmp2) in a loop.

    The triangle's amplitude is ``VAmp = 10 V`` (``R2 = R1*Vps/VAmp``), its
    frequency ``f = 10 Hz`` (``C = Vps/VAmp/(4*f*R)``).
    """

    # opAmp1 starts at its lower limit: initialization solves homotopy()'s simplified expression
    # first (hybrid.homotopy); at each threshold event iteration searches the opposite limit
    modelica_class = "Modelica.Electrical.Analog.Examples.OpAmps.SignalGenerator"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001, tolerance=1e-6)

    def build(self):
        Vps, VAmp, R1, f, R = 15.0, 10.0, 1000.0, 10.0, 1000.0
        Vns, R2, C = -Vps, R1 * Vps / VAmp, Vps / VAmp / (4 * f * R)
        self.opAmp1 = IdealizedOpAmpLimited(Vps=Vps, Vns=Vns, strict=False,
                                            homotopyType=LimiterHomotopy.LowerLimit)
        self.r2 = Resistor(R=R2, i=dict(start=Vps / R2))
        self.r1 = Resistor(R=R1)
        self.ground = Ground()
        self.opAmp2 = IdealizedOpAmpLimited(Vps=Vps, Vns=Vns, v_in=dict(start=0), strict=False)
        self.c = Capacitor(C=C, v=dict(fixed=True, start=0))
        self.r = Resistor(R=R)
        self.vOutRectangle = VoltageSensor()
        self.vOutTriangle = VoltageSensor()
        self.connect(self.opAmp1.out, self.r2.n)
        self.connect(self.opAmp1.in_p, self.r2.p)
        self.connect(self.opAmp1.in_n, self.ground.p)
        self.connect(self.opAmp1.out, self.r.p)
        self.connect(self.r.n, self.c.n)
        self.connect(self.c.p, self.opAmp2.out)
        self.connect(self.ground.p, self.opAmp2.in_p)
        self.connect(self.c.n, self.opAmp2.in_n)
        self.connect(self.r2.p, self.r1.p)
        self.connect(self.opAmp2.out, self.r1.n)
        self.connect(self.opAmp1.out, self.vOutRectangle.p)
        self.connect(self.ground.p, self.vOutRectangle.n)
        self.connect(self.opAmp2.out, self.vOutTriangle.p)
        self.connect(self.ground.p, self.vOutTriangle.n)


class VoltageFollower(Model):
    """Reproduce input voltage: a +-5 V trapezoid through 1 Ohm into a follower loaded with 1 Ohm."""

    modelica_class = "Modelica.Electrical.Analog.Examples.OpAmps.VoltageFollower"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001, tolerance=1e-6)

    def build(self):
        self.opAmp = IdealizedOpAmpLimited(Vps=15.0, Vns=-15.0, v_in=dict(start=0))
        self.ground = Ground()
        self.vIn = _trapezoid(2 * VIN, -VIN)
        self.vOut = VoltageSensor()
        self.ri = Resistor(R=1.0)
        self.rl = Resistor(R=1.0)
        self.connect(self.ground.p, self.vIn.n)
        self.connect(self.opAmp.out, self.vOut.p)
        self.connect(self.ground.p, self.vOut.n)
        self.connect(self.opAmp.out, self.opAmp.in_n)
        self.connect(self.vIn.p, self.ri.p)
        self.connect(self.ri.n, self.opAmp.in_p)
        self.connect(self.opAmp.out, self.rl.p)
        self.connect(self.ground.p, self.rl.n)


# --------------------------------------------------------------------------
# Modelica.Electrical.Analog.Examples


class InvertingAmp(Model):
    """Inverting amplifier: an IdealOpAmpLimited with gain ``-R2/R1 = -2`` on a +-5 V trapezoid, +-15 V supply."""

    modelica_class = "Modelica.Electrical.Analog.Examples.InvertingAmp"
    experiment = Experiment(start_time=0.0, stop_time=1.0, interval=0.001, tolerance=1e-6)

    def build(self):
        k, R1 = 2.0, 1000.0
        self.opAmp = IdealOpAmpLimited()  # out(i(start=0, fixed=false)): the default
        self.ground = Ground()
        self.vIn = _trapezoid(2 * VIN, -VIN)
        self.vOut = VoltageSensor()
        self.r1 = Resistor(R=R1)
        self.r2 = Resistor(R=k * R1)
        self.ground1 = Ground()
        self.vSourcePos = ConstantVoltage(V=15.0)
        self.vSourceNeg = ConstantVoltage(V=-15.0)
        self.connect(self.r1.n, self.r2.n)
        self.connect(self.r2.n, self.opAmp.in_n)
        self.connect(self.r2.p, self.opAmp.out)
        self.connect(self.ground.p, self.opAmp.in_p)
        self.connect(self.vIn.p, self.r1.p)
        self.connect(self.ground.p, self.vIn.n)
        self.connect(self.ground.p, self.vOut.n)
        self.connect(self.opAmp.out, self.vOut.p)
        self.connect(self.ground1.p, self.vSourcePos.n)
        self.connect(self.vSourcePos.p, self.opAmp.VMax)
        self.connect(self.vSourcePos.n, self.vSourceNeg.n)
        self.connect(self.vSourceNeg.p, self.opAmp.VMin)


#: The Cauer low pass's filter coefficients (normalized, cut-off 1 rad/s).
L1, L2, C1, C3, C5 = 1.304, 0.8586, 1.072, 1.682, 0.7262
C2, C4 = 1 / (1.704992 ** 2 * L1), 1 / (1.179945 ** 2 * L2)


class CauerLowPassAnalog(Model):
    """Cauer low pass filter with analog components: a fifth-order LC ladder between two 1 Ohm terminations.

    A 1 V step at t = 1 s; the two series inductors carry the parallel
    capacitors C2, C4 that place the transmission zeros.
    """

    modelica_class = "Modelica.Electrical.Analog.Examples.CauerLowPassAnalog"
    experiment = Experiment(start_time=0.0, stop_time=60.0)

    def build(self):
        self.G = Ground()
        self.C1 = Capacitor(C=C1, v=dict(start=0, fixed=True))
        self.C2 = Capacitor(C=C2)
        self.C3 = Capacitor(C=C3, v=dict(start=0, fixed=True))
        self.C4 = Capacitor(C=C4)
        self.C5 = Capacitor(C=C5, v=dict(start=0, fixed=True))
        self.L1 = Inductor(L=L1, i=dict(start=0, fixed=True))
        self.L2 = Inductor(L=L2, i=dict(start=0, fixed=True))
        self.R1 = Resistor(R=1)
        self.R2 = Resistor(R=1)
        self.V = StepVoltage(startTime=1, offset=0, V=1)
        for a, b in [("R1.n", "C1.p"), ("C1.n", "G.p"), ("L1.p", "C2.p"), ("L1.p", "C1.p"),
                     ("L1.n", "C2.n"), ("C2.n", "C3.p"), ("C2.n", "C4.p"), ("C2.n", "L2.p"),
                     ("L2.n", "C4.n"), ("C4.n", "C5.p"), ("C4.n", "R2.p"), ("C1.n", "C3.n"),
                     ("C1.n", "C5.n"), ("R2.n", "C1.n"), ("R1.p", "V.p"), ("V.n", "G.p")]:
            self.connect(self._pin(a), self._pin(b))

    def _pin(self, dotted: str):
        component, pin = dotted.split(".")
        return getattr(getattr(self, component), pin)


class CauerLowPassOPV(Model):
    """Cauer low pass filter with operational amplifiers: the ladder simulated by five IdealOpAmp3Pin integrators.

    The same filter as :class:`CauerLowPassAnalog` (capacitances standing
    for the ladder's inductances and capacitances), with the MSL's negative
    resistors R4, R5, R8, R9 (-1 Ohm) that invert signs.  The MSL's
    protected pins n1 ... n14, p1 ... p4 and out1 are plain nodes
    (:class:`_Node`).  A 1 V step at t = 1 s (its n pin on the input).
    """

    modelica_class = "Modelica.Electrical.Analog.Examples.CauerLowPassOPV"
    experiment = Experiment(start_time=0.0, stop_time=60.0)

    def build(self):
        self.C1 = Capacitor(C=C1 + C2, v=dict(start=0, fixed=True))
        self.C2 = Capacitor(C=C2, v=dict(start=0, fixed=True))
        self.C3 = Capacitor(C=L1, v=dict(start=0, fixed=True))
        self.C4 = Capacitor(C=C4, v=dict(start=0, fixed=True))
        self.C5 = Capacitor(C=C2)
        self.C6 = Capacitor(C=C2 + C3 + C4)
        self.C7 = Capacitor(C=L2, v=dict(start=0, fixed=True))
        self.C8 = Capacitor(C=C4)
        self.C9 = Capacitor(C=C4 + C5)
        for name, R in [("R1", 1), ("R2", 1), ("R3", 1), ("R4", -1), ("R5", -1), ("R6", 1), ("R7", 1),
                        ("R8", -1), ("R9", -1), ("R10", 1), ("R11", 1)]:
            setattr(self, name, Resistor(R=R))
        for name in ["Op1", "Op2", "Op3", "Op4", "Op5"]:
            setattr(self, name, IdealOpAmp3Pin())
        for name in ["G", "G1", "G2", "G3", "G4", "Ground1"]:
            setattr(self, name, Ground())
        for k in range(1, 15):
            setattr(self, f"n{k}", _Node())
        for k in range(1, 5):
            setattr(self, f"p{k}", _Node())
        self.out1 = _Node()
        self.V = StepVoltage(startTime=1, V=1)
        pairs = ("Op1.in_p G.p;G1.p Op2.in_p;R1.n n1;n1 Op1.in_n;C2.n n1;R2.n n2;n1 n2;n2 n3;n3 C1.p;n3 R3.p;"
                 "C1.n n4;R3.n n4;n4 Op1.out;R4.p Op1.out;C5.p Op1.out;R4.n n5;n5 Op2.in_n;C3.p n5;R5.n n5;"
                 "R5.p p1;C2.p p1;C3.n n6;n6 Op2.out;R2.p n6;Op2.out R7.p;R7.n n7;n7 Op3.in_n;C5.n n7;"
                 "R6.n n8;n7 n8;C6.p p2;n8 p2;C4.n p2;C6.n Op3.out;R9.p Op3.out;Op3.out out1;p1 out1;"
                 "out1 C8.p;C4.p p3;p3 R8.p;R8.n n9;n9 n10;R9.n n10;n10 Op4.in_n;n9 C7.p;C7.n n11;"
                 "R6.p n11;n11 Op4.out;Op4.out R10.p;G2.p Op3.in_p;R11.n n12;p3 n12;C9.n n13;n12 n13;"
                 "n13 Op5.out;C9.p p4;R11.p p4;R10.n n14;p4 n14;Op5.in_n n14;C8.n n14;Op4.in_p G3.p;"
                 "Op5.in_p G4.p;V.p Ground1.p;V.n R1.p")
        for pair in pairs.split(";"):
            a, b = pair.split()
            self.connect(self._pin(a), self._pin(b))

    def _pin(self, dotted: str):
        # "n3" is a node (its pin), "C1.p" a component's pin
        component, _, pin = dotted.partition(".")
        return getattr(getattr(self, component), pin or "pin")


class _Node(Component):
    """A node with no current of its own: the MSL's protected connector ``Pin nK`` inside a model."""

    modelica_name = None

    pin = PositivePin(description="The node")

    def equations(self):
        # a connector of the top-level model that nothing outside connects: no current leaves through it
        return [Eq(self.pin.i, 0)]


class ShowSaturatingInductor(Model):
    """Simple demo to show behaviour of SaturatingInductor component: a 1.25 V cosine on it and on a linear 1 H."""

    modelica_class = "Modelica.Electrical.Analog.Examples.ShowSaturatingInductor"
    experiment = Experiment(start_time=0.0, stop_time=6.2832, interval=0.01)

    def build(self):
        self.SineVoltage1 = SineVoltage(V=1.25, phase=math.pi / 2, f=1 / (2 * math.pi))
        self.Ground1 = Ground()
        self.SaturatingInductance1 = SaturatingInductor(Lzer=2, Lnom=1, Inom=1, Linf=0.5, i=dict(fixed=True))
        self.Inductance1 = Inductor(L=1, i=dict(fixed=True))
        self.connect(self.SineVoltage1.n, self.Ground1.p)
        self.connect(self.SineVoltage1.n, self.SaturatingInductance1.n)
        self.connect(self.SaturatingInductance1.p, self.SineVoltage1.p)
        self.connect(self.Inductance1.p, self.SineVoltage1.p)
        self.connect(self.Inductance1.n, self.SineVoltage1.n)


if __name__ == "__main__":
    from acausal import simulate

    for model in (Adder(), Differentiator(), IntegratorExample(), LowPass(), SchmittTrigger(), SignalGenerator(),
                  VoltageFollower(), InvertingAmp(), CauerLowPassAnalog(), CauerLowPassOPV(),
                  ShowSaturatingInductor()):
        print(type(model).__name__, simulate(model).summary())
