"""Modelica.Mechanics.Translational.Components: declarations and behaviour against closed forms.

Every class is checked structurally (``check_declarations``, with defaults
and typical modifiers) and simulated in a small model whose answer is known
independently: a mass on a spring (period and amplitude), a damped
oscillator (closed form), a rod carrying a force at a fixed length, the
ElastoGap contact law (no force across a gap, the MSL law in contact, never
a pulling force), the energy balance of a damper heating a capacitor, the
relative motion of two masses set up by RelativeStates, the initial values
InitializeFlange imposes, and both signal adaptors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from library_checks import check_declarations

from acausal import Model, StateSelect, simulate
from acausal.errors import ParameterError, StructuralError
from acausal.library.blocks import Constant, Sine
from acausal.library.blocks.continuous import FirstOrder
from acausal.library.thermal import HeatCapacitor
from acausal.library.translational.components import (
    Damper,
    ElastoGap,
    Fixed,
    GeneralForceToPositionAdaptor,
    GeneralPositionToForceAdaptor,
    InitializeFlange,
    Mass,
    RelativeStates,
    Rod,
    Spring,
    SpringDamper,
)
from acausal.library.translational.sources import Force

# --------------------------------------------------------------------------
# declarations


@pytest.mark.parametrize("component", [
    Fixed(), Fixed(s0=0.5),
    Mass(), Mass(m=2, L=0.3, stateSelect=StateSelect.prefer),
    Rod(), Rod(L=0.7),
    Spring(), Spring(c=50, s_rel0=0.1),
    Damper(), Damper(d=3, useHeatPort=True),
    SpringDamper(), SpringDamper(c=5, d=2, s_rel0=1, useHeatPort=True, stateSelect=StateSelect.avoid),
    ElastoGap(), ElastoGap(c=1e5, d=20, s_rel0=0.01, n=1.5, s_ref=0.001, f_ref=10, useHeatPort=True),
    RelativeStates(),
    InitializeFlange(), InitializeFlange(use_s_start=False, use_a_start=False),
    InitializeFlange(use_s_start=False, use_v_start=False, use_a_start=False, stateSelect=StateSelect.prefer),
    GeneralForceToPositionAdaptor(), GeneralForceToPositionAdaptor(use_pder2=False),
    GeneralForceToPositionAdaptor(use_pder=False),
    GeneralPositionToForceAdaptor(), GeneralPositionToForceAdaptor(use_pder2=False),
    GeneralPositionToForceAdaptor(use_pder=False),
], ids=lambda c: f"{type(c).__name__}({', '.join(f'{k}={v}' for k, v in c._modifiers.items())})")
def test_declarations(component):
    """Own names only, locally balanced, every Boolean defined once."""
    check_declarations(component)


def test_conditional_connectors_follow_their_switches():
    assert Damper(useHeatPort=True).heatPort.enabled and not Damper().heatPort.enabled
    initialize = InitializeFlange(use_v_start=False)
    assert initialize.s_start.name and initialize.a_start.name
    assert "v_start" not in {k for k, d in initialize.declarations().items() if d.enabled(initialize)}
    adaptor = GeneralPositionToForceAdaptor(use_pder2=False)
    enabled = {k for k, d in adaptor.declarations().items() if d.enabled(adaptor)}
    assert "pder" in enabled and "pder2" not in enabled


# --------------------------------------------------------------------------
# mass on a spring: period and amplitude

M_SPRING, C_SPRING, S0 = 2.0, 50.0, 0.1


class MassOnSpring(Model):
    """A mass of length 1 m whose flange_a hangs on a spring from a wall at -1.5 m (equilibrium s = 0)."""

    def build(self):
        self.wall = Fixed(s0=-1.5)
        self.spring = Spring(c=C_SPRING, s_rel0=1)
        self.mass = Mass(m=M_SPRING, L=1, s=dict(start=S0, fixed=True), v=dict(start=0, fixed=True))
        self.connect(self.wall.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.mass.flange_a)


def _upward_zero_crossings(t, y):
    i = np.nonzero((y[:-1] < 0) & (y[1:] >= 0))[0]
    return t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])


def test_mass_on_spring_period_and_amplitude():
    """s = S0*cos(w t), w = sqrt(c/m): crossings one period 2*pi*sqrt(m/c) apart, amplitude S0 kept."""
    period = 2 * math.pi * math.sqrt(M_SPRING / C_SPRING)
    result = simulate(MassOnSpring(), stop_time=4 * period, interval=period / 400, rtol=1e-9)
    assert result.success, result.message
    t, s = result.time, result["mass.s"]
    crossings = _upward_zero_crossings(t, s)
    assert len(crossings) == 4
    np.testing.assert_allclose(np.diff(crossings), period, rtol=1e-6)
    assert np.max(s) == pytest.approx(S0, rel=1e-5) and np.min(s) == pytest.approx(-S0, rel=1e-5)
    # the spring force pulls the mass back: f = c*(s_rel - s_rel0) = c*s
    np.testing.assert_allclose(result["spring.f"], C_SPRING * s, rtol=0, atol=1e-12)


# --------------------------------------------------------------------------
# damped oscillator (SpringDamper, and Spring parallel to Damper)

M_OSC, C_OSC, D_OSC, X0, V0 = 1.5, 40.0, 3.0, 0.2, -0.5


class DampedOscillator(Model):
    """Two identical damped oscillators: one SpringDamper, one Spring parallel to a Damper."""

    def build(self):
        start = dict(s=dict(start=X0, fixed=True), v=dict(start=V0, fixed=True))
        self.wall = Fixed()
        self.springDamper = SpringDamper(c=C_OSC, d=D_OSC)
        self.mass1 = Mass(m=M_OSC, **start)
        self.spring = Spring(c=C_OSC)
        self.damper = Damper(d=D_OSC)
        self.mass2 = Mass(m=M_OSC, **start)
        self.connect(self.wall.flange, self.springDamper.flange_a)
        self.connect(self.springDamper.flange_b, self.mass1.flange_a)
        self.connect(self.wall.flange, self.spring.flange_a)
        self.connect(self.wall.flange, self.damper.flange_a)
        self.connect(self.spring.flange_b, self.mass2.flange_a)
        self.connect(self.damper.flange_b, self.mass2.flange_a)


def test_damped_oscillator_matches_closed_form():
    """m x'' + d x' + c x = 0, underdamped: x = exp(-sigma t)(A cos wd t + B sin wd t)."""
    sigma = D_OSC / (2 * M_OSC)
    wd = math.sqrt(C_OSC / M_OSC - sigma**2)
    result = simulate(DampedOscillator(), stop_time=3.0, interval=0.01, rtol=1e-9)
    assert result.success, result.message
    t = result.time
    a, b = X0, (V0 + sigma * X0) / wd
    x = np.exp(-sigma * t) * (a * np.cos(wd * t) + b * np.sin(wd * t))
    v = np.exp(-sigma * t) * ((b * wd - sigma * a) * np.cos(wd * t) - (a * wd + sigma * b) * np.sin(wd * t))
    for mass in ("mass1", "mass2"):
        np.testing.assert_allclose(result[f"{mass}.s"], x, rtol=0, atol=1e-7)
        np.testing.assert_allclose(result[f"{mass}.v"], v, rtol=0, atol=1e-6)
    np.testing.assert_allclose(result["springDamper.v_rel"], v, rtol=0, atol=1e-6)


# --------------------------------------------------------------------------
# Rod: a massless link of fixed length

M1_ROD, M2_ROD, L_ROD, C_ROD = 1.0, 3.0, 0.25, 100.0


class RodChain(Model):
    """wall - spring - mass1 (L = 0.2) - rod (L = 0.25) - mass2 (L = 0.4)."""

    def build(self):
        self.wall = Fixed()
        self.spring = Spring(c=C_ROD, s_rel0=0.5)
        self.mass1 = Mass(m=M1_ROD, L=0.2, s=dict(start=0.7, fixed=True), v=dict(start=0, fixed=True))
        self.rod = Rod(L=L_ROD)
        self.mass2 = Mass(m=M2_ROD, L=0.4)
        self.connect(self.wall.flange, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.mass1.flange_a)
        self.connect(self.mass1.flange_b, self.rod.flange_a)
        self.connect(self.rod.flange_b, self.mass2.flange_a)


def test_rod_keeps_its_length_and_transmits_the_force():
    """The rod moves both masses as one body (w = sqrt(c/(m1+m2))) and pushes mass2 with m2*a."""
    result = simulate(RodChain(), stop_time=2.0, interval=0.005, rtol=1e-9)
    assert result.success, result.message
    t = result.time
    # spring stretched by 0.1 at t = 0 (s_rel = 0.7 - 0.1 = 0.6 vs 0.5): x = 0.1*cos(w t) around rest
    w = math.sqrt(C_ROD / (M1_ROD + M2_ROD))
    np.testing.assert_allclose(result["mass1.s"], 0.6 + 0.1 * np.cos(w * t), rtol=0, atol=1e-7)
    np.testing.assert_allclose(result["rod.flange_b.s"] - result["rod.flange_a.s"], L_ROD, rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["mass2.s"] - result["mass1.s"], 0.1 + L_ROD + 0.2, rtol=0, atol=1e-12)
    # no mass, no net force: what enters at flange_a leaves at flange_b, and it accelerates mass2
    np.testing.assert_allclose(result["rod.flange_a.f"] + result["rod.flange_b.f"], 0, rtol=0, atol=1e-9)
    np.testing.assert_allclose(result["rod.flange_a.f"], M2_ROD * result["mass2.a"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(result["mass2.a"], -0.1 * w**2 * np.cos(w * t), rtol=0, atol=1e-5)


# --------------------------------------------------------------------------
# ElastoGap: a mass bouncing off a wall

M_GAP, C_GAP, D_GAP, V_IMPACT, GAP0, C_GAP_HEAT = 1.0, 400.0, 30.0, -1.0, 0.5, 0.1


class Bounce(Model):
    """A point mass moving at -1 m/s towards an ElastoGap on a wall; contact when s < 0.5 (s_rel0)."""

    #: modifiers of the ElastoGap besides c, d, s_rel0 and useHeatPort
    gap_modifiers: dict = {}

    def build(self):
        self.wall = Fixed()
        self.gap = ElastoGap(c=C_GAP, d=D_GAP, s_rel0=GAP0, useHeatPort=True, **self.gap_modifiers)
        self.heat = HeatCapacitor(C=C_GAP_HEAT, T=dict(start=300, fixed=True))
        self.mass = Mass(m=M_GAP, s=dict(start=1.0, fixed=True), v=dict(start=V_IMPACT, fixed=True))
        self.connect(self.wall.flange, self.gap.flange_a)
        self.connect(self.gap.flange_b, self.mass.flange_a)
        self.connect(self.gap.heatPort, self.heat.port)


def bounce(**gap_modifiers) -> Bounce:
    """A Bounce model whose ElastoGap gets these extra modifiers."""
    return type("Bounce", (Bounce,), {"gap_modifiers": gap_modifiers})()


def _contact_force_law(contact, s_rel, v_rel, f_ref, s_ref, n):
    """The MSL contact law, written from its documentation: spring force plus a damper force bounded by it."""
    compression = GAP0 - s_rel
    f_c = np.where(contact, -f_ref * np.abs(compression / s_ref) ** n, 0.0)
    f_d2 = np.where(contact, D_GAP * v_rel, 0.0)
    f_d = np.clip(f_d2, f_c, -f_c)
    return f_c + f_d


@pytest.mark.parametrize("n, gap, f_ref, s_ref", [
    (1.0, {}, C_GAP, 1.0),  # default f_ref = c*s_ref: f_c = -c*|s_rel - s_rel0|
    (1.5, dict(n=1.5, s_ref=0.1, f_ref=20.0), 20.0, 0.1),  # Hertzian exponent with reference force
], ids=["linear", "hertz"])
def test_elasto_gap_contact_law(n, gap, f_ref, s_ref):
    """No force across the gap, the MSL law in contact, never a pulling force, and the lost energy is heat."""
    # DOP853: the clip of the damper force is a kink under noEvent that the integrator steps
    # over; RK45's error estimate lets ~1e-6 J of energy slip there even at rtol 1e-9
    result = simulate(bounce(**gap), stop_time=1.5, interval=0.001, rtol=1e-9, method="DOP853")
    assert result.success, result.message
    s_rel, v_rel, f = result["gap.s_rel"], result["gap.v_rel"], result["gap.f"]
    contact = result["gap.contact"] == 1
    apart = s_rel > GAP0 + 1e-9
    touching = s_rel < GAP0 - 1e-9
    assert apart.any() and touching.any()
    # contact is s_rel < s_rel0 (at an event row it may hold its left-limit value within the
    # event location tolerance, hence the band)
    assert np.all(contact[touching]) and not np.any(contact[apart])
    # a gap transmits nothing: the mass coasts
    assert np.all(f[apart] == 0)
    # in contact: f_c = -f_ref*|ratio|^n plus the damper force clipped to |f_d| <= |f_c|
    np.testing.assert_allclose(f, _contact_force_law(contact, s_rel, v_rel, f_ref, s_ref, n), rtol=1e-9, atol=1e-9)
    # the no-pulling rule: f <= 0 always, and it is active (d*v_rel > -f_c) near the end of contact
    assert np.all(f <= 1e-12)
    f_c = result["gap.f_c"]
    clipped = touching & (D_GAP * v_rel > -f_c + 1e-6)
    assert clipped.any() and np.all(np.abs(f[clipped]) < 1e-9)
    # the mass bounces back slower (inelastic contact) ...
    v_end = result["mass.v"][-1]
    assert 0 < v_end < -V_IMPACT
    # ... and the kinetic energy lost is the heat stored (lossPower = f_d*v_rel goes to the port)
    lost = 0.5 * M_GAP * (V_IMPACT**2 - v_end**2)
    assert C_GAP_HEAT * (result["heat.T"][-1] - 300) == pytest.approx(lost, rel=1e-6)
    assert result["gap.contact"][-1] == 0


def test_elasto_gap_rejects_exponent_below_one():
    with pytest.raises(ParameterError, match=r"gap\.n"):
        simulate(bounce(n=0.5), stop_time=0.1)


# --------------------------------------------------------------------------
# Damper with heat port: dissipated power = heat flow

M_DAMP, D_DAMP, V_DAMP, C_HEAT = 2.0, 4.0, 3.0, 5.0


class DamperHeating(Model):
    """A sliding mass braked by a damper to the wall; the damper heats a capacitor."""

    def build(self):
        self.wall = Fixed()
        self.damper = Damper(d=D_DAMP, useHeatPort=True)
        self.mass = Mass(m=M_DAMP, s=dict(start=0, fixed=True), v=dict(start=V_DAMP, fixed=True))
        self.heat = HeatCapacitor(C=C_HEAT, T=dict(start=293.15, fixed=True))
        self.connect(self.wall.flange, self.damper.flange_a)
        self.connect(self.damper.flange_b, self.mass.flange_a)
        self.connect(self.damper.heatPort, self.heat.port)


def test_damper_heat_port_energy_balance():
    """v = v0*exp(-d t/m); lossPower = d*v^2 = -heatPort.Q_flow; heat stored = kinetic energy lost."""
    result = simulate(DamperHeating(), stop_time=2.0, interval=0.01, rtol=1e-9)
    assert result.success, result.message
    t, v = result.time, result["mass.v"]
    np.testing.assert_allclose(v, V_DAMP * np.exp(-D_DAMP * t / M_DAMP), rtol=1e-6, atol=0)
    np.testing.assert_allclose(result["damper.lossPower"], D_DAMP * v**2, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(result["damper.heatPort.Q_flow"], -result["damper.lossPower"], rtol=0, atol=1e-12)
    heat = C_HEAT * (result["heat.T"] - 293.15)
    kinetic_lost = 0.5 * M_DAMP * (V_DAMP**2 - v**2)
    np.testing.assert_allclose(heat, kinetic_lost, rtol=0, atol=1e-7)


# --------------------------------------------------------------------------
# RelativeStates: initial values given relative to another mass

M_A, M_B, C_AB, S_REL0, V_REL0 = 1.0, 3.0, 12.0, 0.3, 0.4


class TwoMassesRelative(Model):
    """Two free masses joined by a spring; the relative position and speed are set by RelativeStates."""

    def build(self):
        self.massA = Mass(m=M_A, s=dict(start=0, fixed=True), v=dict(start=0, fixed=True))
        self.spring = Spring(c=C_AB, s_rel0=0.2)
        self.massB = Mass(m=M_B)
        self.relativeStates = RelativeStates(s_rel=dict(start=S_REL0, fixed=True),
                                             v_rel=dict(start=V_REL0, fixed=True))
        self.connect(self.massA.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.massB.flange_a)
        self.connect(self.massA.flange_b, self.relativeStates.flange_a)
        self.connect(self.massB.flange_a, self.relativeStates.flange_b)


def test_relative_states_give_the_two_body_solution():
    """The relative motion oscillates at sqrt(c/mu) about 0.2 m; the centre of mass moves at constant speed."""
    result = simulate(TwoMassesRelative(), stop_time=2.0, interval=0.01, rtol=1e-9)
    assert result.success, result.message
    t = result.time
    w = math.sqrt(C_AB * (M_A + M_B) / (M_A * M_B))
    x = 0.2 + (S_REL0 - 0.2) * np.cos(w * t) + V_REL0 / w * np.sin(w * t)
    np.testing.assert_allclose(result["relativeStates.s_rel"], x, rtol=0, atol=1e-7)
    np.testing.assert_allclose(result["massB.s"] - result["massA.s"], x, rtol=0, atol=1e-7)
    # it transmits no force: the momentum M_B*V_REL0 given at t = 0 is kept
    momentum = M_A * result["massA.v"] + M_B * result["massB.v"]
    np.testing.assert_allclose(momentum, M_B * V_REL0, rtol=0, atol=1e-8)
    np.testing.assert_allclose(result["relativeStates.flange_a.f"], 0, atol=0)


# --------------------------------------------------------------------------
# InitializeFlange: position, speed and acceleration at the start

M_INIT, S_INIT, V_INIT, A_INIT = 2.0, 1.0, -0.5, 3.0


class InitializedMass(Model):
    """A mass pushed by a first-order lag whose free initial output is fixed by a_start."""

    def build(self):
        self.initialize = InitializeFlange()
        self.s_start = Constant(k=S_INIT)
        self.v_start = Constant(k=V_INIT)
        self.a_start = Constant(k=A_INIT)
        self.zero = Constant(k=0)
        self.lag = FirstOrder(T=1, k=1)  # initType NoInit: y(0) is an unknown
        self.force = Force()
        self.mass = Mass(m=M_INIT)
        self.connect(self.s_start.y, self.initialize.s_start)
        self.connect(self.v_start.y, self.initialize.v_start)
        self.connect(self.a_start.y, self.initialize.a_start)
        self.connect(self.initialize.flange, self.mass.flange_b)
        self.connect(self.zero.y, self.lag.u)
        self.connect(self.lag.y, self.force.f)
        self.connect(self.force.flange, self.mass.flange_a)


def test_initialize_flange_sets_position_speed_and_acceleration():
    """a = A*exp(-t) (force = m*A*exp(-t)), so s = s0 + v0 t + A (t - 1 + exp(-t))."""
    result = simulate(InitializedMass(), stop_time=2.0, interval=0.01, rtol=1e-9)
    assert result.success, result.message
    t = result.time
    assert result["lag.y"][0] == pytest.approx(M_INIT * A_INIT, rel=1e-9)
    np.testing.assert_allclose(result["mass.a"], A_INIT * np.exp(-t), rtol=0, atol=1e-6)
    np.testing.assert_allclose(result["mass.v"], V_INIT + A_INIT * (1 - np.exp(-t)), rtol=0, atol=1e-6)
    np.testing.assert_allclose(result["initialize.s_flange"],
                               S_INIT + V_INIT * t + A_INIT * (t - 1 + np.exp(-t)), rtol=0, atol=1e-6)
    np.testing.assert_allclose(result["initialize.flange.f"], 0, atol=0)


class InitializedOscillator(Model):
    """A mass on a spring, its position and speed set through InitializeFlange (no acceleration input)."""

    def build(self):
        self.initialize = InitializeFlange(use_a_start=False)
        self.s_start = Constant(k=0.3)
        self.v_start = Constant(k=0.8)
        self.mass = Mass(m=1)
        self.spring = Spring(c=4)
        self.fixed = Fixed()
        self.connect(self.s_start.y, self.initialize.s_start)
        self.connect(self.v_start.y, self.initialize.v_start)
        self.connect(self.initialize.flange, self.mass.flange_a)
        self.connect(self.mass.flange_b, self.spring.flange_b)
        self.connect(self.spring.flange_a, self.fixed.flange)


def test_initialize_flange_without_acceleration_input():
    """s = 0.3 cos 2t + 0.4 sin 2t (w = sqrt(c/m) = 2)."""
    result = simulate(InitializedOscillator(), stop_time=2.0, interval=0.01, rtol=1e-9)
    assert result.success, result.message
    t = result.time
    np.testing.assert_allclose(result["mass.s"], 0.3 * np.cos(2 * t) + 0.4 * np.sin(2 * t), rtol=0, atol=1e-7)


# --------------------------------------------------------------------------
# signal adaptors

M_AD = 2.0


class PositionDriven(Model):
    """p = sin t with its derivatives as inputs moves a mass; the adaptor outputs the force it takes."""

    def build(self):
        f = 1 / (2 * math.pi)
        self.p = Sine(amplitude=1, f=f)
        self.pder = Sine(amplitude=1, f=f, phase=math.pi / 2)
        self.pder2 = Sine(amplitude=-1, f=f)
        self.adaptor = GeneralPositionToForceAdaptor()
        self.mass = Mass(m=M_AD)
        self.connect(self.p.y, self.adaptor.p)
        self.connect(self.pder.y, self.adaptor.pder)
        self.connect(self.pder2.y, self.adaptor.pder2)
        self.connect(self.adaptor.flange, self.mass.flange_a)


def test_position_to_force_adaptor_uses_the_given_derivatives():
    """The mass follows s = sin t, v = cos t exactly (no states), and f = -flange.f = m*a = -m sin t."""
    result = simulate(PositionDriven(), stop_time=3.0, interval=0.01)
    assert result.success, result.message
    t = result.time
    np.testing.assert_allclose(result["mass.s"], np.sin(t), rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["mass.v"], np.cos(t), rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["adaptor.f"], -M_AD * np.sin(t), rtol=0, atol=1e-12)


def test_position_to_force_adaptor_needs_the_second_derivative_for_a_mass():
    """Without pder2 the mass's acceleration is unavailable: a clear error, not a silent zero."""
    class OnlyFirst(Model):
        def build(self):
            self.p = Sine(amplitude=1, f=1)
            self.pder = Sine(amplitude=2 * math.pi, f=1, phase=math.pi / 2)
            self.adaptor = GeneralPositionToForceAdaptor(use_pder2=False)
            self.mass = Mass(m=M_AD)
            self.connect(self.p.y, self.adaptor.p)
            self.connect(self.pder.y, self.adaptor.pder)
            self.connect(self.adaptor.flange, self.mass.flange_a)

    with pytest.raises(StructuralError, match="order 2") as caught:
        simulate(OnlyFirst(), stop_time=0.1)
    assert "adaptor.p" in caught.value.message and "use_pder2" in caught.value.hint


class ForceDriven(Model):
    """A constant force input acts on a mass through the adaptor; position, speed, acceleration are outputs."""

    def build(self):
        self.force = Constant(k=3.0)
        self.adaptor = GeneralForceToPositionAdaptor()
        self.mass = Mass(m=M_AD, s=dict(start=0.5, fixed=True), v=dict(start=0, fixed=True))
        self.connect(self.force.y, self.adaptor.f)
        self.connect(self.adaptor.flange, self.mass.flange_b)


def test_force_to_position_adaptor_outputs_the_motion():
    """flange.f = f is the force on the adaptor, so the mass feels -f: a = -f/m, p = 0.5 + a t^2/2."""
    result = simulate(ForceDriven(), stop_time=2.0, interval=0.01, rtol=1e-9)
    assert result.success, result.message
    t = result.time
    a = -3.0 / M_AD
    np.testing.assert_allclose(result["adaptor.p"], 0.5 + a * t**2 / 2, rtol=0, atol=1e-9)
    np.testing.assert_allclose(result["adaptor.pder"], a * t, rtol=0, atol=1e-9)
    np.testing.assert_allclose(result["adaptor.pder2"], a, rtol=0, atol=1e-9)
