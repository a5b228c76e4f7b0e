"""Modelica.Electrical.Machines DC machines: declarations, units and behaviour against closed forms.

The DC machine is a circuit (armature resistance Ra, inductance La, brushes,
core losses parallel to the air gap) coupled to a shaft by the machine
constant ``k = turnsRatio*psi_e``: induced voltage ``k*w``, torque
``k*i``.  The tests compute what the machine must do independently of the
simulator — the steady state with every loss (friction, stray load, core,
brushes) solved with scipy, the no-load speed ``Va/k``, the locked-rotor
current ``Va/Ra*(1 - exp(-t*Ra/La))``, the series machine's quadratic
torque, the armature resistance at a heat port's temperature — and check
that the energy fed in equals what is stored, dissipated and delivered.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.optimize import fsolve
from library_checks import check_declarations, reference_or_skip

from acausal import Experiment, Model, simulate
from acausal.compiler.flatten import flatten
from acausal.compiler.units import check_units
from acausal.errors import UnitWarning
from acausal.library.electrical import (
    AirGapDC,
    Brush,
    CompoundDCExcitation,
    ConstantVoltage,
    Core,
    DC_ElectricalExcited,
    DC_PermanentMagnet,
    DC_SeriesExcited,
    Friction,
    Ground,
    InductorDC,
    StrayLoad,
)
from acausal.library.electrical.machines import (
    BrushParameters,
    CoreParameters,
    FrictionParameters,
    StrayLoadParameters,
    brush_voltage_drop,
    convert_alpha,
    convert_resistance,
)
from acausal.library.rotational import ConstantTorque, Fixed, Inertia
from acausal.library.thermal import FixedTemperature

#: The machines' defaults (DcPermanentMagnetData): 100 V, 100 A, 1425 rpm, Ra = 0.05 Ohm, La = 1.5 mH.
VA_NOMINAL, IA_NOMINAL, RA, LA, JR = 100.0, 100.0, 0.05, 0.0015, 0.15
W_NOMINAL = 1425 * 2 * math.pi / 60
AT_REST = dict(phiMechanical=dict(fixed=True), wMechanical=dict(fixed=True), ia=dict(fixed=True))

#: Losses switched on for the steady state and energy tests.
P_FRICTION, P_STRAY, P_CORE, V_BRUSH, I_LINEAR = 100.0, 50.0, 200.0, 1.0, 1.0
LOSSES = dict(frictionParameters=dict(PRef=P_FRICTION), strayLoadParameters=dict(PRef=P_STRAY),
              coreParameters=dict(PRef=P_CORE), brushParameters=dict(V=V_BRUSH, ILinear=I_LINEAR))


class Drive(Model):
    """A DC machine on a constant voltage, turning a load inertia against a constant torque."""

    experiment = Experiment(stop_time=1.5, interval=1e-3)

    def __init__(self, machine=None, Va=100.0, tau_load=0.0, J_load=0.15, **modifiers):  # noqa: N803
        # plain attributes (not sub-components): build() reads them
        for key, value in (("_machine", machine), ("_va", Va), ("_tau", tau_load), ("_j", J_load)):
            object.__setattr__(self, key, value)
        super().__init__(**modifiers)

    def build(self):
        self.dcpm = self._machine if self._machine is not None else DC_PermanentMagnet(**AT_REST)
        self.source = ConstantVoltage(V=self._va)
        self.ground = Ground()
        self.load = Inertia(J=self._j)
        self.loadTorque = ConstantTorque(tau_constant=-self._tau)
        self.connect(self.source.p, self.dcpm.pin_ap)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.dcpm.pin_an, self.source.n)
        self.connect(self.dcpm.flange, self.load.flange_a)
        self.connect(self.load.flange_b, self.loadTorque.flange)


def machine_constant(brush_drop: float = 0.0) -> float:
    """``turnsRatio*psi_e`` of the permanent magnet machine: ViNominal/wNominal (flux 1 Wb)."""
    return (VA_NOMINAL - RA * IA_NOMINAL - brush_drop) / W_NOMINAL


# --------------------------------------------------------------------------
# declarations, units, helpers


@pytest.mark.parametrize("make", [
    Friction, Brush, Core, StrayLoad, InductorDC, AirGapDC, CompoundDCExcitation,
    DC_PermanentMagnet, DC_ElectricalExcited, DC_SeriesExcited,
    lambda: InductorDC(quasiStatic=True), lambda: AirGapDC(quasiStatic=True),
    lambda: Friction(frictionParameters=dict(PRef=10.0, wRef=100.0), useHeatPort=True),
    lambda: Brush(brushParameters=dict(V=1.0), useHeatPort=True),
    lambda: Core(coreParameters=dict(PRef=10.0, VRef=90.0, wRef=100.0)),
    lambda: StrayLoad(strayLoadParameters=dict(PRef=10.0, IRef=100.0, wRef=100.0)),
    lambda: DC_PermanentMagnet(useThermalPort=True, useSupport=True),
    lambda: DC_ElectricalExcited(useThermalPort=True, **LOSSES),
    lambda: DC_SeriesExcited(useThermalPort=True, sigmae=0.1),
], ids=lambda make: getattr(make, "__name__", "modified"))
def test_declarations(make):
    check_declarations(make())


def test_the_records_compute_their_final_parameters_as_the_msl_does():
    assert FrictionParameters.PRef.structural and BrushParameters.V.structural  # they select equations
    flat = flatten(Drive(machine=DC_PermanentMagnet(**AT_REST, **LOSSES)))
    values = {p.name: float(p.value) for p in flat.parameters}
    assert values["dcpm.frictionParameters.tauRef"] == pytest.approx(P_FRICTION / W_NOMINAL)
    assert values["dcpm.frictionParameters.wLinear"] == pytest.approx(1e-3 * W_NOMINAL)
    assert values["dcpm.frictionParameters.tauLinear"] == pytest.approx(P_FRICTION / W_NOMINAL * 1e-6)
    assert values["dcpm.strayLoadParameters.tauRef"] == pytest.approx(P_STRAY / W_NOMINAL)
    vi = VA_NOMINAL - RA * IA_NOMINAL - V_BRUSH
    assert values["dcpm.ViNominal"] == pytest.approx(vi)
    assert values["dcpm.coreParameters.GcRef"] == pytest.approx(P_CORE / vi ** 2)
    assert values["dcpm.turnsRatio"] == pytest.approx(vi / W_NOMINAL)
    # the machine's records reach its loss models
    assert values["dcpm.friction.frictionParameters.tauRef"] == pytest.approx(P_FRICTION / W_NOMINAL)
    assert values["dcpm.brush.brushParameters.ILinear"] == pytest.approx(I_LINEAR)
    for record in (CoreParameters, StrayLoadParameters, BrushParameters):
        assert record.modelica_name.startswith("Modelica.Electrical.Machines.Losses.")


def test_the_thermal_conversions_and_the_brush_drop():
    assert convert_alpha(0.004, 293.15) == pytest.approx(0.004)
    assert convert_alpha(0.004, 353.15) == pytest.approx(0.004 / (1 + 0.004 * 60))
    # R(T) through a reference temperature other than 20 degC comes back to the 20 degC law
    r80 = convert_resistance(1.0, 293.15, 0.004, 353.15)
    assert r80 == pytest.approx(1.24)
    assert convert_resistance(r80, 353.15, 0.004, 293.15) == pytest.approx(1.0)
    assert brush_voltage_drop(0.0, 1.0, 50.0) == 0
    assert float(brush_voltage_drop(2.0, 1.0, 50.0)) == 2.0
    assert float(brush_voltage_drop(2.0, 1.0, -50.0)) == -2.0
    assert float(brush_voltage_drop(2.0, 1.0, 0.25)) == 0.5


@pytest.mark.parametrize("machine", [DC_PermanentMagnet, DC_ElectricalExcited])
def test_units_are_consistent(machine):
    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitWarning)
        check_units(flatten(Drive(machine=machine(**LOSSES))))


# --------------------------------------------------------------------------
# behaviour


def test_no_load_speed_is_the_voltage_over_the_machine_constant():
    """Without losses or load the machine runs up to w0 = Va/k (1500 rpm at 100 V) and draws no current."""
    result = simulate(Drive(Va=100.0))
    assert result.success, result.message
    k = machine_constant()
    assert result["dcpm.wMechanical"][-1] == pytest.approx(100.0 / k, rel=1e-5)
    assert result["dcpm.wMechanical"][-1] * 60 / (2 * math.pi) == pytest.approx(1500.0, rel=1e-5)
    assert abs(result["dcpm.ia"][-1]) < 1e-3


def test_locked_rotor_current_rises_as_an_rl_circuit():
    """Shaft held: ia(t) = Va/Ra (1 - exp(-t Ra/La)), the starting current Va/Ra = 2000 A."""

    class Locked(Model):
        experiment = Experiment(stop_time=0.2, interval=1e-3)

        def build(self):
            self.dcpm = DC_PermanentMagnet(ia=dict(fixed=True))
            self.source = ConstantVoltage(V=100.0)
            self.ground = Ground()
            self.fixed = Fixed()
            self.connect(self.source.p, self.dcpm.pin_ap)
            self.connect(self.source.n, self.ground.p)
            self.connect(self.dcpm.pin_an, self.source.n)
            self.connect(self.dcpm.flange, self.fixed.flange)

    result = simulate(Locked())
    assert result.success, result.message
    t = result.time
    expected = 100.0 / RA * (1 - np.exp(-t * RA / LA))
    np.testing.assert_allclose(result["dcpm.ia"], expected, rtol=1e-4, atol=1e-3)
    # the torque on the held shaft is k*ia
    np.testing.assert_allclose(result["dcpm.tauElectrical"], machine_constant() * expected, rtol=1e-4, atol=1e-3)


def test_steady_state_with_every_loss_matches_the_closed_form():
    """Speed and current at 100 V and 30 N.m load, friction, stray load, core and brush losses on.

    In steady state (no inductor voltage) the armature loop reads ``Va = Ra*ia + Vbrush + k*w`` with
    ``ia`` the air gap current plus the core current ``Gc*k*w``, and the shaft balances
    ``k*i_airgap = tau_load + tauRef_f*(w/wRef)^2 + tauRef_s*(ia/IRef)^2*(w/wRef)``.
    """
    tau_load, va = 30.0, 100.0
    result = simulate(Drive(machine=DC_PermanentMagnet(**AT_REST, **LOSSES), Va=va, tau_load=tau_load))
    assert result.success, result.message

    k = machine_constant(V_BRUSH)
    gc = P_CORE / (k * W_NOMINAL) ** 2
    tau_friction = P_FRICTION / W_NOMINAL
    tau_stray = P_STRAY / W_NOMINAL

    def residual(x):
        w, ia = x
        i_airgap = ia - gc * k * w
        return [va - RA * ia - V_BRUSH - k * w,
                k * i_airgap - tau_load - tau_friction * (w / W_NOMINAL) ** 2
                - tau_stray * (ia / IA_NOMINAL) ** 2 * (w / W_NOMINAL)]

    w, ia = fsolve(residual, [150.0, 50.0], xtol=1e-13)
    assert result["dcpm.wMechanical"][-1] == pytest.approx(w, rel=1e-6)
    assert result["dcpm.ia"][-1] == pytest.approx(ia, rel=1e-6)
    assert result["dcpm.core.i"][-1] == pytest.approx(gc * k * w, rel=1e-6)
    assert result["dcpm.tauShaft"][-1] == pytest.approx(tau_load, rel=1e-6)
    assert result["dcpm.brush.lossPower"][-1] == pytest.approx(V_BRUSH * ia, rel=1e-6)


def test_energy_balance_over_a_start():
    """Energy in at the terminals = magnetic + kinetic energy + every loss + the load's work."""

    class Start(Drive):
        experiment = Experiment(stop_time=1.0, interval=1e-4)

    tau_load, j_load = 30.0, 0.15
    result = simulate(Start(machine=DC_PermanentMagnet(**AT_REST, **LOSSES), tau_load=tau_load, J_load=j_load))
    assert result.success, result.message
    t, w, ia = result.time, result["dcpm.wMechanical"], result["dcpm.ia"]

    def integral(y):
        return float(np.sum((y[1:] + y[:-1]) * np.diff(t)) / 2)

    energy_in = integral(result["dcpm.va"] * ia)
    losses = sum(integral(result[name]) for name in ("dcpm.ra.LossPower", "dcpm.brush.lossPower",
                                                     "dcpm.core.lossPower", "dcpm.strayLoad.lossPower",
                                                     "dcpm.friction.lossPower"))
    stored = 0.5 * LA * result["dcpm.la.i"][-1] ** 2 + 0.5 * (JR + j_load) * w[-1] ** 2
    work = integral(tau_load * w)
    assert energy_in > 1e3
    assert losses + stored + work == pytest.approx(energy_in, rel=1e-4)


def test_separately_excited_machine_flux_follows_the_field_current():
    """Field on 100 V over Re = 100 Ohm, Le = 1 H: ie = 1 A (1 - exp(-t/10 ms)), so psi_e = Lme*ie."""

    class Separate(Model):
        experiment = Experiment(stop_time=1.0, interval=1e-3)

        def build(self):
            self.dcee = DC_ElectricalExcited(ie=dict(fixed=True), **AT_REST)
            self.armature = ConstantVoltage(V=50.0)
            self.field = ConstantVoltage(V=100.0)
            self.ground = Ground()
            self.groundExcitation = Ground()
            self.load = Inertia(J=0.15)
            self.connect(self.armature.p, self.dcee.pin_ap)
            self.connect(self.armature.n, self.ground.p)
            self.connect(self.dcee.pin_an, self.ground.p)
            self.connect(self.field.p, self.dcee.pin_ep)
            self.connect(self.field.n, self.dcee.pin_en)
            self.connect(self.field.n, self.groundExcitation.p)
            self.connect(self.dcee.flange, self.load.flange_a)

    result = simulate(Separate())
    assert result.success, result.message
    t = result.time
    np.testing.assert_allclose(result["dcee.ie"], 1 - np.exp(-t / 0.01), atol=1e-4)
    np.testing.assert_allclose(result["dcee.airGapDC.psi_e"], result["dcee.ie"], rtol=1e-9, atol=1e-12)
    # at full field the no-load speed is the armature voltage over k = ViNominal/wNominal
    assert result["dcee.wMechanical"][-1] == pytest.approx(50.0 / machine_constant(), rel=1e-4)


def test_series_machine_steady_state_torque_is_quadratic_in_the_current():
    """Series machine on 100 V against 40 N.m: tau = kse*ia^2 gives ia, the loop gives w.

    ``kse = turnsRatio*Lme`` with ``turnsRatio = ViNominal/(wNominal*Lme*IaNominal)`` and
    ``ViNominal = 100 - (Ra + Re)*100``; then ``ia = sqrt(tau/kse)`` and
    ``w = (Va - (Ra + Re)*ia)/(kse*ia)``.
    """

    class Series(Model):
        # the series machine settles slowly (its torque falls only as 1/w^2 near the operating point)
        experiment = Experiment(stop_time=30.0, interval=1e-2)

        def build(self):
            self.dcse = DC_SeriesExcited(**AT_REST)
            self.source = ConstantVoltage(V=100.0)
            self.ground = Ground()
            self.load = Inertia(J=0.15)
            self.loadTorque = ConstantTorque(tau_constant=-40.0)
            self.connect(self.source.p, self.dcse.pin_ap)
            self.connect(self.dcse.pin_an, self.dcse.pin_ep)
            self.connect(self.dcse.pin_en, self.source.n)
            self.connect(self.source.n, self.ground.p)
            self.connect(self.dcse.flange, self.load.flange_a)
            self.connect(self.load.flange_b, self.loadTorque.flange)

    result = simulate(Series())
    assert result.success, result.message
    re, w_nominal = 0.01, 1410 * 2 * math.pi / 60
    kse = (100.0 - (RA + re) * 100.0) / (w_nominal * 100.0)
    ia = math.sqrt(40.0 / kse)
    assert result["dcse.ia"][-1] == pytest.approx(ia, rel=1e-5)
    assert result["dcse.wMechanical"][-1] == pytest.approx((100.0 - (RA + re) * ia) / (kse * ia), rel=1e-5)
    assert result["dcse.ie"][-1] == pytest.approx(result["dcse.ia"][-1], rel=1e-9)  # the same winding current


def test_thermal_port_sets_the_armature_temperature_and_takes_its_losses():
    """Copper armature held at 80 degC through the thermal port: R = Ra*(1 + 0.00393*60) (from 20 degC);
    the locked-rotor current settles at Va/R and the port takes R*ia^2."""
    alpha = 0.00393

    class Hot(Model):
        experiment = Experiment(stop_time=0.5, interval=1e-3)

        def build(self):
            self.dcpm = DC_PermanentMagnet(ia=dict(fixed=True), useThermalPort=True, alpha20a=alpha)
            self.source = ConstantVoltage(V=10.0)
            self.ground = Ground()
            self.fixed = Fixed()
            self.winding = FixedTemperature(T=353.15)
            self.connect(self.source.p, self.dcpm.pin_ap)
            self.connect(self.source.n, self.ground.p)
            self.connect(self.dcpm.pin_an, self.source.n)
            self.connect(self.dcpm.flange, self.fixed.flange)
            self.connect(self.dcpm.thermalPort_heatPortArmature, self.winding.port)
            for name in ("Core", "StrayLoad", "Friction", "Brush", "PermanentMagnet"):
                setattr(self, f"ambient{name}", FixedTemperature(T=293.15))
                self.connect(getattr(self.dcpm, f"thermalPort_heatPort{name}"), getattr(self, f"ambient{name}").port)

    result = simulate(Hot())
    assert result.success, result.message
    r_hot = RA * (1 + alpha * 60)
    assert result["dcpm.ia"][-1] == pytest.approx(10.0 / r_hot, rel=1e-6)
    assert result["winding.port.Q_flow"][-1] == pytest.approx(r_hot * (10.0 / r_hot) ** 2, rel=1e-6)  # heat into the sink


@pytest.mark.parametrize("name", ["DCPM_Start", "DCEE_Start", "DCSE_Start"])
def test_the_msl_examples_lie_in_the_reference_tube(name):
    from library_checks import assert_in_the_tube

    from examples import electrical_dc_machines

    model = getattr(electrical_dc_machines, name)
    reference_or_skip(model.modelica_class)
    result = assert_in_the_tube(model)
    # a load step at 1.5 s (PM, EE): the machine ends near nominal speed and current
    if name != "DCSE_Start":
        machine = "dcpm" if name == "DCPM_Start" else "dcee"
        assert result[f"{machine}.ia"][-1] == pytest.approx(63.66 / machine_constant(), rel=2e-3)
