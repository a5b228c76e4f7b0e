"""Modelica.Electrical.Machines.Examples.DCMachines: starting the three DC machines.

The machines have the MSL's default data (the ``Utilities.ParameterRecords``
DcPermanentMagnetData, DcElectricalExcitedData, DcSeriesExcitedData: 100 V,
100 A, Ra = 0.05 Ohm, La = 1.5 mH, Jr = Js = 0.15 kg.m2, no friction, core,
stray load or brush losses) and drive a load inertia of 0.15 kg.m2.

* DCPM_Start: a permanent magnet machine; the armature voltage ramps from 0
  to 100 V between 0.2 s and 1 s, at 1.5 s the nominal load torque 63.66
  N.m steps in.  The machine constant is ``(100 - 0.05*100)/wNominal``
  (wNominal = 1425 rpm): no-load speed ``100 V/k`` = 1500 rpm, at
  nominal load 1425 rpm and 100 A.
* DCEE_Start: the same with a separately excited field (100 V on Re =
  100 Ohm, Le = 1 H): the field current rises with a time constant of
  10 ms from the start.
* DCSE_Start: a series excited machine on 100 V through a series resistor
  that ramps from 1 Ohm to 0 between 0.1 s and 1 s, against a load torque
  quadratic in the speed (63.66 N.m at 1410 rpm).
"""

import math

from acausal import Experiment, Model
from acausal.library.blocks import Ramp
from acausal.library.electrical import (
    ConstantVoltage,
    DC_ElectricalExcited,
    DC_PermanentMagnet,
    DC_SeriesExcited,
    Ground,
    SignalVoltage,
    VariableResistor,
)
from acausal.library.rotational import Inertia, QuadraticSpeedDependentTorque, TorqueStep

#: The examples' load: nominal torque (N.m) and the load's moment of inertia (kg.m2).
T_LOAD, J_LOAD = 63.66, 0.15

#: DcPermanentMagnetData: the armature, nominal values and inertias every example's machine has.
ARMATURE = dict(VaNominal=100.0, IaNominal=100.0, TaNominal=293.15, Ra=0.05, TaRef=293.15, La=0.0015,
                Jr=0.15, Js=0.15, useSupport=False, TaOperational=293.15, alpha20a=0.0)

#: The machines start at rest with no armature current.
AT_REST = dict(phiMechanical=dict(fixed=True), wMechanical=dict(fixed=True), ia=dict(fixed=True))


class DCPM_Start(Model):  # noqa: N801 - Modelica name
    """Test example: DC with permanent magnet starting with voltage ramp."""

    modelica_class = "Modelica.Electrical.Machines.Examples.DCMachines.DCPM_Start"
    experiment = Experiment(start_time=0.0, stop_time=2.0, interval=1e-4, tolerance=1e-6)

    def build(self):
        self.dcpm = DC_PermanentMagnet(wNominal=1425 * 2 * math.pi / 60, **ARMATURE, **AT_REST)
        self.ramp = Ramp(duration=0.8, height=100.0, startTime=0.2)
        self.signalVoltage = SignalVoltage()
        self.ground = Ground()
        self.loadInertia = Inertia(J=J_LOAD)
        self.loadTorqueStep = TorqueStep(startTime=1.5, stepTorque=-T_LOAD, useSupport=False, offsetTorque=0)
        self.connect(self.ramp.y, self.signalVoltage.v)
        self.connect(self.signalVoltage.p, self.dcpm.pin_ap)
        self.connect(self.signalVoltage.n, self.ground.p)
        self.connect(self.dcpm.pin_an, self.signalVoltage.n)
        self.connect(self.loadInertia.flange_b, self.loadTorqueStep.flange)
        self.connect(self.dcpm.flange, self.loadInertia.flange_a)


class DCEE_Start(Model):  # noqa: N801 - Modelica name
    """Test example: DC with electrical excitation starting with voltage ramp."""

    modelica_class = "Modelica.Electrical.Machines.Examples.DCMachines.DCEE_Start"
    experiment = Experiment(start_time=0.0, stop_time=2.0, interval=1e-4, tolerance=1e-6)

    def build(self):
        self.dcee = DC_ElectricalExcited(wNominal=1425 * 2 * math.pi / 60, IeNominal=1.0, Re=100.0, TeRef=293.15,
                                         Le=1.0, sigmae=0.0, alpha20e=0.0, TeOperational=293.15,
                                         ie=dict(fixed=True), **ARMATURE, **AT_REST)
        self.ramp = Ramp(duration=0.8, height=100.0, startTime=0.2)
        self.signalVoltage = SignalVoltage()
        self.ground = Ground()
        self.constantVoltage = ConstantVoltage(V=100.0)
        self.groundExcitation = Ground()
        self.loadInertia = Inertia(J=J_LOAD)
        self.loadTorqueStep = TorqueStep(startTime=1.5, stepTorque=-T_LOAD, useSupport=False, offsetTorque=0)
        self.connect(self.ramp.y, self.signalVoltage.v)
        self.connect(self.signalVoltage.p, self.dcee.pin_ap)
        self.connect(self.signalVoltage.n, self.ground.p)
        self.connect(self.dcee.pin_an, self.ground.p)
        self.connect(self.constantVoltage.n, self.groundExcitation.p)
        self.connect(self.dcee.pin_ep, self.constantVoltage.p)
        self.connect(self.dcee.pin_en, self.constantVoltage.n)
        self.connect(self.loadInertia.flange_b, self.loadTorqueStep.flange)
        self.connect(self.dcee.flange, self.loadInertia.flange_a)


class DCSE_Start(Model):  # noqa: N801 - Modelica name
    """Test example: DC with serial excitation starting with voltage ramp."""

    modelica_class = "Modelica.Electrical.Machines.Examples.DCMachines.DCSE_Start"
    experiment = Experiment(start_time=0.0, stop_time=2.0, interval=1e-4, tolerance=1e-6)

    def build(self):
        w_load = 1410 * 2 * math.pi / 60
        self.dcse = DC_SeriesExcited(wNominal=w_load, TeNominal=293.15, Re=0.01, TeRef=293.15, Le=0.0005,
                                     sigmae=0.0, alpha20e=0.0, TeOperational=293.15, **ARMATURE, **AT_REST)
        self.ramp = Ramp(duration=0.9, startTime=0.1, height=-1.0, offset=1.0)
        self.constantVoltage = ConstantVoltage(V=100.0)
        self.ground = Ground()
        self.loadInertia = Inertia(J=J_LOAD)
        self.quadraticLoadTorque = QuadraticSpeedDependentTorque(w_nominal=w_load, TorqueDirection=False,
                                                                 tau_nominal=-T_LOAD, useSupport=False)
        self.variableResistor = VariableResistor()
        self.connect(self.constantVoltage.n, self.ground.p)
        self.connect(self.loadInertia.flange_b, self.quadraticLoadTorque.flange)
        self.connect(self.dcse.pin_an, self.dcse.pin_ep)
        self.connect(self.dcse.pin_en, self.constantVoltage.n)
        self.connect(self.dcse.flange, self.loadInertia.flange_a)
        self.connect(self.constantVoltage.p, self.variableResistor.p)
        self.connect(self.variableResistor.n, self.dcse.pin_ap)
        self.connect(self.ramp.y, self.variableResistor.R)


if __name__ == "__main__":
    from acausal import simulate

    for model in (DCPM_Start, DCEE_Start, DCSE_Start):
        print(simulate(model()).summary())
