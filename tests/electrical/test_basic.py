"""Modelica.Electrical.Analog.Basic: declarations, units and behaviour against closed forms.

Every class is checked structurally (``check_declarations``, with defaults
and typical modifiers) and by the unit check, and simulated in a small
circuit whose answer is known independently: Ohm's law (with the
temperature coefficient), RC charging and its energy balance through a heat
port, RL and series RLC responses, the transformer against scipy's solution
of its two coupled equations, the gyrator and the controlled sources, the
EMF's torque and voltage constant, the saturating inductor's flux law, the
potentiometer's divider and the OpAmp's characteristic.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq
from library_checks import check_declarations

from acausal import Model, simulate
from acausal.compiler.flatten import flatten
from acausal.compiler.units import check_units
from acausal.errors import UnitWarning
from acausal.language import Boolean, Component, Connector, Integer, Parameter, Variable
from acausal.library import electrical
from acausal.library.blocks import BooleanConstant, Constant, IntegerConstant
from acausal.library.electrical import (
    CCC,
    CCV,
    VCC,
    VCV,
    Capacitor,
    Conductor,
    ConstantCurrent,
    ConstantVoltage,
    Ground,
    Gyrator,
    Inductor,
    OpAmp,
    Potentiometer,
    Resistor,
    RotationalEMF,
    SaturatingInductor,
    Transformer,
    TranslationalEMF,
    VariableCapacitor,
    VariableConductor,
    VariableInductor,
    VariableResistor,
)
from acausal.library.rotational import Inertia
from acausal.library.thermal import HeatCapacitor
from acausal.library.translational import Mass

# --------------------------------------------------------------------------
# declarations and units


@pytest.mark.parametrize("component", [
    Ground(),
    Resistor(), Resistor(R=10, alpha=0.004, useHeatPort=True), Resistor(T_ref=300, T=320),
    Conductor(), Conductor(G=2, useHeatPort=True),
    Capacitor(), Capacitor(C=1e-3, v=dict(fixed=True)),
    Inductor(), Inductor(L=1e-3, i=dict(fixed=True)),
    SaturatingInductor(), SaturatingInductor(Inom=2, Lnom=1, Lzer=3, Linf=0.2),
    Transformer(), Transformer(L1=2, L2=0.5, M=0.9),
    Gyrator(), VCV(), VCC(), CCV(), CCC(),
    RotationalEMF(), RotationalEMF(useSupport=True, k=0.5),
    TranslationalEMF(), TranslationalEMF(useSupport=True, k=2),
    OpAmp(), OpAmp(Slope=-100),
    VariableResistor(), VariableResistor(useHeatPort=True, alpha=0.01),
    VariableConductor(), VariableConductor(useHeatPort=True),
    VariableCapacitor(), VariableCapacitor(UIC=True, IC=2),
    VariableInductor(), VariableInductor(UIC=True, IC=1),
    Potentiometer(), Potentiometer(useRinput=True, useHeatPort=True),
], ids=lambda c: f"{type(c).__name__}({', '.join(f'{k}={v}' for k, v in c._modifiers.items())})")
def test_declarations(component):
    """Own names only, locally balanced, every Boolean defined once."""
    check_declarations(component)


def _electrical_classes():
    return {name: getattr(electrical, name) for name in electrical.__all__
            if isinstance(getattr(electrical, name), type) and issubclass(getattr(electrical, name), Component)
            and not issubclass(getattr(electrical, name), Connector)}


@pytest.mark.parametrize("name", sorted(_electrical_classes()))
def test_every_electrical_class_passes_the_unit_check(name):
    """Each class, its signal inputs fed by constants, has no equation mixing units."""
    klass = _electrical_classes()[name]

    class Harness(Model):
        def build(self):
            self.x = klass()
            self.x.ensure_built()
            for key, declaration in self.x.declarations().items():
                if (isinstance(declaration, Variable) and declaration.causality == "input"
                        and declaration.enabled(self.x)):
                    source = (BooleanConstant() if isinstance(declaration, Boolean) else
                              IntegerConstant() if isinstance(declaration, Integer) else Constant())
                    setattr(self, f"source_{key}", source)
                    self.connect(getattr(self, f"source_{key}").y, getattr(self.x, key))

    with warnings.catch_warnings():
        warnings.simplefilter("error", UnitWarning)
        check_units(flatten(Harness()))


def test_every_variable_and_parameter_has_a_unit():
    """Units V, A, Ohm, S, F, H, Wb, W, K on every physical declaration (dimensionless ones named)."""
    dimensionless = {"gain", "Slope", "absSlope", "rConstant", "rInt", "r", "useHeatPort", "useSupport",
                     "UIC", "useRinput", "stateSelect", "useConstantAmplitude", "useConstantFrequency"}
    for name, klass in _electrical_classes().items():
        for key, declaration in klass.declarations().items():
            if name.startswith("Pulse") and key == "width":
                continue  # percent of the period
            if isinstance(declaration, (Boolean, Integer)):
                continue  # a state or a switch, not a physical quantity
            if isinstance(declaration, (Parameter, Variable)) and key not in dimensionless:
                if isinstance(declaration, Parameter) and declaration.structural:
                    continue
                assert declaration.unit, f"{name}.{key} has no unit"


# --------------------------------------------------------------------------
# Ohm's law, temperature coefficient


class OhmsLaw(Model):
    def build(self):
        self.source = ConstantVoltage(V=12)
        self.resistor = Resistor(R=4, alpha=0.004, T_ref=300, T=325)  # fixed device temperature 25 K above T_ref
        self.conductor = Conductor(G=0.5)
        self.ground = Ground()
        self.connect(self.source.p, self.resistor.p)
        self.connect(self.source.p, self.conductor.p)
        self.connect(self.resistor.n, self.ground.p)
        self.connect(self.conductor.n, self.ground.p)
        self.connect(self.source.n, self.ground.p)


def test_ohms_law_with_temperature_coefficient():
    result = simulate(OhmsLaw(), stop_time=1, interval=0.5)
    r_actual = 4 * (1 + 0.004 * 25)
    assert result.final("resistor.R_actual") == pytest.approx(r_actual, rel=1e-12)
    assert result.final("resistor.i") == pytest.approx(12 / r_actual, rel=1e-12)
    assert result.final("resistor.LossPower") == pytest.approx(12 ** 2 / r_actual, rel=1e-12)
    assert result.final("conductor.i") == pytest.approx(6, rel=1e-12)
    # the source delivers both currents: it flows from p to n inside, so i = -(sum)
    assert result.final("source.i") == pytest.approx(-(6 + 12 / r_actual), rel=1e-12)


# --------------------------------------------------------------------------
# RC charging and its energy balance

U, R_RC, C_RC, C_TH, T0 = 10.0, 100.0, 1e-3, 2.0, 300.0


class RCCharging(Model):
    """A 10 V source charging 1 mF through 100 Ohm; the resistor's heat warms a heat capacitor."""

    def build(self):
        self.source = ConstantVoltage(V=U)
        self.resistor = Resistor(R=R_RC, useHeatPort=True)
        self.capacitor = Capacitor(C=C_RC, v=dict(start=0, fixed=True))
        self.heat = HeatCapacitor(C=C_TH, T=dict(start=T0, fixed=True))
        self.ground = Ground()
        self.connect(self.source.p, self.resistor.p)
        self.connect(self.resistor.n, self.capacitor.p)
        self.connect(self.capacitor.n, self.ground.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.resistor.heatPort, self.heat.port)


def test_rc_charging_follows_the_closed_form():
    tau = R_RC * C_RC
    result = simulate(RCCharging(), stop_time=5 * tau, interval=tau / 50, rtol=1e-9, atol=1e-12)
    assert result.success, result.message
    t = result.time
    np.testing.assert_allclose(result["capacitor.v"], U * (1 - np.exp(-t / tau)), rtol=0, atol=1e-6 * U)
    np.testing.assert_allclose(result["capacitor.i"], U / R_RC * np.exp(-t / tau), rtol=0, atol=1e-6 * U / R_RC)


def test_rc_energy_from_the_source_is_heat_plus_stored_energy():
    """Source energy U*C*u (the charge C*u moved through U) = heat in the resistor + C*u^2/2."""
    tau = R_RC * C_RC
    result = simulate(RCCharging(), stop_time=5 * tau, interval=tau / 50, rtol=1e-9, atol=1e-12)
    u = result["capacitor.v"]
    supplied = U * C_RC * u
    heat = C_TH * (result["heat.T"] - T0)
    stored = C_RC * u ** 2 / 2
    np.testing.assert_allclose(supplied, heat + stored, rtol=0, atol=1e-8 * U ** 2 * C_RC)
    # and the heat is the integral of the loss power (trapezoid on the output grid)
    loss = np.concatenate([[0], np.cumsum(np.diff(result.time) * (result["resistor.LossPower"][1:]
                                                                   + result["resistor.LossPower"][:-1]) / 2)])
    np.testing.assert_allclose(heat, loss, rtol=0, atol=2e-4 * U ** 2 * C_RC)


# --------------------------------------------------------------------------
# RL and series RLC


def series_rlc(R, L, C=None):
    """A model: the 10 V source, R and L in series, and C after them unless None."""

    class SeriesRLC(Model):
        def build(self):
            self.source = ConstantVoltage(V=U)
            self.resistor = Resistor(R=R)
            self.inductor = Inductor(L=L, i=dict(start=0, fixed=True))
            self.ground = Ground()
            self.connect(self.source.p, self.resistor.p)
            self.connect(self.resistor.n, self.inductor.p)
            if C is None:
                self.connect(self.inductor.n, self.ground.p)
            else:
                self.capacitor = Capacitor(C=C, v=dict(start=0, fixed=True))
                self.connect(self.inductor.n, self.capacitor.p)
                self.connect(self.capacitor.n, self.ground.p)
            self.connect(self.source.n, self.ground.p)

    return SeriesRLC()


def test_rl_current_rises_exponentially():
    R, L = 5.0, 0.1
    tau = L / R
    result = simulate(series_rlc(R, L), stop_time=5 * tau, interval=tau / 50, rtol=1e-9, atol=1e-12)
    t = result.time
    np.testing.assert_allclose(result["inductor.i"], U / R * (1 - np.exp(-t / tau)), rtol=0, atol=1e-6 * U / R)


def test_underdamped_rlc_matches_the_closed_form():
    """u_C = U*(1 - exp(-a t)*(cos(wd t) + a/wd sin(wd t))), a = R/2L, wd = sqrt(1/LC - a^2)."""
    R, L, C = 2.0, 0.01, 1e-4
    a = R / (2 * L)
    wd = math.sqrt(1 / (L * C) - a ** 2)
    result = simulate(series_rlc(R, L, C), stop_time=0.05, interval=1e-4, rtol=1e-9, atol=1e-12)
    t = result.time
    expected = U * (1 - np.exp(-a * t) * (np.cos(wd * t) + a / wd * np.sin(wd * t)))
    np.testing.assert_allclose(result["capacitor.v"], expected, rtol=0, atol=1e-5 * U)
    np.testing.assert_allclose(result["inductor.i"], C * U * np.exp(-a * t) * (a ** 2 / wd + wd) * np.sin(wd * t),
                               rtol=0, atol=1e-5 * U)


# --------------------------------------------------------------------------
# transformer


def loaded_transformer(load):
    """A model: 10 V at 50 Hz on the primary of a transformer, ``load`` Ohm on its secondary (None: open)."""

    class LoadedTransformer(Model):
        def build(self):
            from acausal.library.electrical import SineVoltage

            self.source = SineVoltage(V=10, f=50)
            # an open secondary carries no current: i2 = 0 is then no state to fix
            self.transformer = Transformer(L1=0.2, L2=0.05, M=0.09, i1=dict(fixed=True),
                                           i2=dict(fixed=load is not None))
            self.ground1 = Ground()
            self.ground2 = Ground()
            self.connect(self.source.p, self.transformer.p1)
            self.connect(self.source.n, self.ground1.p)
            self.connect(self.transformer.n1, self.ground1.p)
            self.connect(self.transformer.n2, self.ground2.p)
            if load is not None:
                self.load = Resistor(R=load)
                self.connect(self.transformer.p2, self.load.p)
                self.connect(self.load.n, self.transformer.n2)

    return LoadedTransformer()


def test_transformer_against_its_coupled_equations():
    """[L1 M; M L2] d/dt [i1; i2] = [v1; -R*i2], solved by scipy."""
    L1, L2, M, R = 0.2, 0.05, 0.09, 8.0
    inductance = np.array([[L1, M], [M, L2]])
    result = simulate(loaded_transformer(8.0), stop_time=0.1, interval=1e-4, rtol=1e-9, atol=1e-12)

    def rhs(t, i):
        return np.linalg.solve(inductance, [10 * math.sin(2 * math.pi * 50 * t), -R * i[1]])

    reference = solve_ivp(rhs, (0, 0.1), [0, 0], t_eval=result.time, rtol=1e-11, atol=1e-13)
    np.testing.assert_allclose(result["transformer.i1"], reference.y[0], rtol=0, atol=1e-6)
    np.testing.assert_allclose(result["transformer.i2"], reference.y[1], rtol=0, atol=1e-6)
    np.testing.assert_allclose(result["transformer.v2"], -R * result["transformer.i2"], rtol=0, atol=1e-9)


def test_transformer_without_load_transforms_by_m_over_l1():
    """No secondary current: v2 = M/L1 * v1, the ratio of an open transformer."""
    result = simulate(loaded_transformer(None), stop_time=0.04, interval=1e-4, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(result["transformer.v2"], 0.09 / 0.2 * result["transformer.v1"], rtol=0, atol=1e-6)


# --------------------------------------------------------------------------
# gyrator and controlled sources (static)


def two_port_on_load(element_class, series, **parameters):
    """A model: a 3 V source on port 1 (through ``series`` Ohm if not 0), 2 Ohm on port 2."""

    class TwoPortOnLoad(Model):
        def build(self):
            self.source = ConstantVoltage(V=3)
            self.x = element_class(**parameters)
            self.load = Resistor(R=2)
            self.ground = Ground()
            if series:
                self.rin = Resistor(R=series)
                self.connect(self.source.p, self.rin.p)
                self.connect(self.rin.n, self.x.p1)
            else:
                self.connect(self.source.p, self.x.p1)
            self.connect(self.source.n, self.ground.p)
            self.connect(self.x.n1, self.ground.p)
            self.connect(self.x.p2, self.load.p)
            self.connect(self.load.n, self.x.n2)
            self.connect(self.x.n2, self.ground.p)

    return TwoPortOnLoad()


@pytest.mark.parametrize("element, parameters, series, expected", [
    # load current -i2 = v2/2 in every case
    (Gyrator, dict(G1=0.5, G2=0.25), 0.0, dict(v2=3.0, i2=-1.5, i1=0.75)),          # i2 = -G1*v1, v2 = -2*i2, i1 = G2*v2
    (VCV, dict(gain=4), 0.0, dict(v2=12.0, i2=-6.0, i1=0.0)),
    (VCC, dict(transConductance=0.5), 0.0, dict(v2=-3.0, i2=1.5, i1=0.0)),         # the current drives against the load
    (CCV, dict(transResistance=5), 1.0, dict(v1=0.0, i1=3.0, v2=15.0)),             # short input: i1 = 3 V/1 Ohm
    (CCC, dict(gain=2), 1.0, dict(v1=0.0, i1=3.0, i2=6.0, v2=-12.0)),
], ids=["Gyrator", "VCV", "VCC", "CCV", "CCC"])
def test_two_ports(element, parameters, series, expected):
    result = simulate(two_port_on_load(element, series, **parameters), stop_time=1, interval=0.5)
    for name, value in expected.items():
        assert result.final(f"x.{name}") == pytest.approx(value, abs=1e-12), name


# --------------------------------------------------------------------------
# electromotive forces

K_EMF, J_EMF, R_EMF = 0.5, 0.02, 2.0


def motor(use_support=False):
    """A model: 10 V through 2 Ohm into an EMF driving an inertia (the housing a huge inertia, if supported)."""

    class Motor(Model):
        def build(self):
            self.source = ConstantVoltage(V=U)
            self.resistor = Resistor(R=R_EMF)
            self.emf = RotationalEMF(k=K_EMF, useSupport=use_support)
            self.inertia = Inertia(J=J_EMF, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
            self.ground = Ground()
            self.connect(self.source.p, self.resistor.p)
            self.connect(self.resistor.n, self.emf.p)
            self.connect(self.emf.n, self.ground.p)
            self.connect(self.source.n, self.ground.p)
            self.connect(self.emf.flange, self.inertia.flange_a)
            if use_support:
                self.housing = Inertia(J=1e6, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
                self.connect(self.emf.support, self.housing.flange_a)

    return Motor()


def test_rotational_emf_drives_an_inertia():
    """J*dw/dt = k*i, i = (U - k*w)/R: w = U/k*(1 - exp(-t/T)), T = J*R/k^2; torque k*i, voltage k*w."""
    T = J_EMF * R_EMF / K_EMF ** 2
    result = simulate(motor(), stop_time=5 * T, interval=T / 50, rtol=1e-9, atol=1e-12)
    t = result.time
    w = U / K_EMF * (1 - np.exp(-t / T))
    np.testing.assert_allclose(result["inertia.w"], w, rtol=0, atol=1e-6 * U / K_EMF)
    np.testing.assert_allclose(result["emf.v"], K_EMF * result["emf.w"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(result["emf.tauElectrical"], K_EMF * result["emf.i"], rtol=0, atol=1e-9)
    # electrical power in = mechanical power out
    np.testing.assert_allclose(result["emf.v"] * result["emf.i"], result["emf.tauElectrical"] * result["emf.w"],
                               rtol=0, atol=1e-9)


def test_rotational_emf_reaction_goes_to_the_support():
    result = simulate(motor(use_support=True), stop_time=0.1, interval=0.01, rtol=1e-9)
    np.testing.assert_allclose(result["emf.support.tau"], -result["emf.flange.tau"], rtol=0, atol=1e-12)


class Linear(Model):
    def build(self):
        self.source = ConstantVoltage(V=U)
        self.resistor = Resistor(R=R_EMF)
        self.emf = TranslationalEMF(k=K_EMF)
        self.mass = Mass(m=J_EMF, s=dict(start=0, fixed=True), v=dict(start=0, fixed=True))
        self.ground = Ground()
        self.connect(self.source.p, self.resistor.p)
        self.connect(self.resistor.n, self.emf.p)
        self.connect(self.emf.n, self.ground.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.emf.flange, self.mass.flange_a)


def test_translational_emf_drives_a_mass():
    T = J_EMF * R_EMF / K_EMF ** 2
    result = simulate(Linear(), stop_time=5 * T, interval=T / 50, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(result["mass.v"], U / K_EMF * (1 - np.exp(-result.time / T)),
                               rtol=0, atol=1e-6 * U / K_EMF)
    np.testing.assert_allclose(result["emf.fElectrical"], K_EMF * result["emf.i"], rtol=0, atol=1e-9)


# --------------------------------------------------------------------------
# variable elements


class VariableCircuit(Model):
    """A constant current of 2 A through a variable resistor, conductor, inductor and capacitor in series."""

    def build(self):
        self.source = ConstantCurrent(I=2)
        self.R = VariableResistor()
        self.G = VariableConductor()
        self.L = VariableInductor()
        self.C = VariableCapacitor(UIC=True, IC=1.0)
        self.ground = Ground()
        self.values = {name: Constant(k=k) for name, k in (("R", 3.0), ("G", 0.25), ("L", 0.5), ("C", 0.1))}
        for name, block in self.values.items():
            setattr(self, f"{name}_value", block)
            self.connect(block.y, getattr(getattr(self, name), name))
        self.connect(self.source.n, self.R.p)
        self.connect(self.R.n, self.G.p)
        self.connect(self.G.n, self.L.p)
        self.connect(self.L.n, self.C.p)
        self.connect(self.C.n, self.ground.p)
        self.connect(self.source.p, self.ground.p)


def test_variable_elements_with_constant_inputs():
    result = simulate(VariableCircuit(), stop_time=1, interval=0.1, rtol=1e-9, atol=1e-12)
    t = result.time
    np.testing.assert_allclose(result["R.v"], 6.0, rtol=1e-12)
    np.testing.assert_allclose(result["G.v"], 8.0, rtol=1e-12)
    np.testing.assert_allclose(result["L.v"], 0.0, atol=1e-9)          # constant current: no voltage
    np.testing.assert_allclose(result["L.Psi"], 1.0, rtol=1e-12)       # Psi = L*i
    np.testing.assert_allclose(result["C.v"], 1.0 + 2.0 / 0.1 * t, rtol=1e-9)  # from IC, dv/dt = i/C


# --------------------------------------------------------------------------
# saturating inductor


class Saturating(Model):
    def build(self):
        self.source = ConstantVoltage(V=1)
        self.inductor = SaturatingInductor(Inom=1, Lnom=1, Lzer=2, Linf=0.5, i=dict(start=0, fixed=True))
        self.ground = Ground()
        self.connect(self.source.p, self.inductor.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.inductor.n, self.ground.p)


def test_saturating_inductor_flux_law():
    """Ipar solves its defining equation; with 1 V applied Psi = t, and i follows from Psi(i) = t."""
    result = simulate(Saturating(), stop_time=3, interval=0.1, rtol=1e-10, atol=1e-12)
    assert result.success, result.message
    ipar = brentq(lambda x: x * (math.pi / 2 - math.atan(x)) - (1 - 0.5) / (2 - 0.5), 1e-9, 100)
    assert result.final("inductor.Ipar") == pytest.approx(ipar, rel=1e-8)

    def psi(i):
        return 0.5 * i + 1.5 * ipar * math.atan(i / ipar)

    expected = [brentq(lambda i: psi(i) - t, -1, 100) if t > 0 else 0.0 for t in result.time]
    np.testing.assert_allclose(result["inductor.Psi"], result.time, rtol=0, atol=1e-7)
    np.testing.assert_allclose(result["inductor.i"], expected, rtol=0, atol=1e-6)
    # the present inductance Psi/i falls from Lzer towards Linf
    lact = result["inductor.Lact"]
    assert lact[0] == pytest.approx(2.0) and np.all(np.diff(lact) < 0) and lact[-1] > 0.5


# --------------------------------------------------------------------------
# potentiometer and OpAmp


class Divider(Model):
    def build(self):
        self.source = ConstantVoltage(V=U)
        self.pot = Potentiometer(R=100, rConstant=0.3)
        self.ground = Ground()
        self.load = Resistor(R=1e15)  # an open contact, kept in the circuit
        self.connect(self.source.p, self.pot.pin_p)
        self.connect(self.pot.pin_n, self.ground.p)
        self.connect(self.source.n, self.ground.p)
        self.connect(self.pot.contact, self.load.p)
        self.connect(self.load.n, self.ground.p)


def test_potentiometer_divides_the_voltage():
    result = simulate(Divider(), stop_time=1, interval=0.5)
    assert result.final("pot.contact.v") == pytest.approx(0.3 * U, rel=1e-9)
    assert result.final("pot.Rp") == pytest.approx(70, rel=1e-12)
    assert result.final("pot.Rn") == pytest.approx(30, rel=1e-12)
    assert result.final("pot.LossPower") == pytest.approx(U ** 2 / 100, rel=1e-9)


class OpenLoopOpAmp(Model):
    def build(self):
        from acausal.library.electrical import SineVoltage

        self.vin = SineVoltage(V=0.01, f=1)
        self.vmax = ConstantVoltage(V=15)
        self.vmin = ConstantVoltage(V=10)  # n at -10 V
        self.opamp = OpAmp(Slope=1e4)
        self.load = Resistor(R=1e3)
        self.ground = Ground()
        self.connect(self.vin.p, self.opamp.in_p)
        self.connect(self.vin.n, self.ground.p)
        self.connect(self.opamp.in_n, self.ground.p)
        self.connect(self.vmax.p, self.opamp.VMax)
        self.connect(self.vmin.n, self.opamp.VMin)
        self.connect(self.vmax.n, self.ground.p)
        self.connect(self.vmin.p, self.ground.p)
        self.connect(self.opamp.out, self.load.p)
        self.connect(self.load.n, self.ground.p)


def test_opamp_characteristic():
    """out = (VMax + VMin)/2 + S*vin/(1 + S*|2*vin/(VMax - VMin)|): saturating between the supplies."""
    result = simulate(OpenLoopOpAmp(), stop_time=1, interval=0.01)
    vin = 0.01 * np.sin(2 * np.pi * result.time)
    expected = 2.5 + 1e4 * vin / (1 + 1e4 * np.abs(2 * vin / 25))
    np.testing.assert_allclose(result["opamp.out.v"], expected, rtol=1e-9, atol=1e-9)
    assert np.max(result["opamp.out.v"]) < 15 and np.min(result["opamp.out.v"]) > -10
    np.testing.assert_allclose(result["opamp.in_p.i"], 0, atol=0)
