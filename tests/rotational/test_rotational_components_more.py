"""Rotational components beyond the basic set: R2T couplings, backlash, Disc, states, adaptors.

Declaration checks with defaults and typical modifiers, parameter errors,
and behaviour against closed forms derived by hand:

* IdealRollingWheel / IdealGearR2T: an inertia driving a mass through the
  coupling accelerates as one body of inertia J + m*r^2 (J + m/ratio^2);
  s - s_support = r*(phi - phi_support) with moved supports; the power
  flangeR.tau*w + flangeT.f*v is 0; the supports take the reactions;
* ElastoBacklash: the torque law (0 in the gap, spring + limited damper out
  of it, never pulling), the contact times of an inertia coasting through
  the gap and bouncing off an undamped spring, energy conservation without
  damping and the heat-port audit with damping;
* ElastoBacklash2: the damped contact phase and its release event against
  the closed form of the damped oscillator;
* Disc, RelativeStates, InitializeFlange and the four signal adaptors.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from library_checks import check_declarations

from acausal import Model, simulate, translate
from acausal.errors import ParameterError
from acausal.library.blocks import Constant, Sine
from acausal.library.rotational.components import (
    AngleToTorqueAdaptor,
    Disc,
    ElastoBacklash,
    ElastoBacklash2,
    Fixed,
    GeneralAngleToTorqueAdaptor,
    GeneralTorqueToAngleAdaptor,
    IdealGearR2T,
    IdealRollingWheel,
    Inertia,
    InitializeFlange,
    RelativeStates,
    Spring,
    TorqueToAngleAdaptor,
)
from acausal.library.rotational.sources import ConstantTorque
from acausal.library.thermal import HeatCapacitor
from acausal.library.translational.components import Fixed as TranslationalFixed
from acausal.library.translational.components import Mass

REST = dict(start=0, fixed=True)


# --------------------------------------------------------------------------
# declarations


@pytest.mark.parametrize("component", [
    IdealRollingWheel(),
    IdealRollingWheel(radius=0.5, useSupportR=True),
    IdealRollingWheel(useSupportT=True),
    IdealRollingWheel(radius=2, useSupportR=True, useSupportT=True),
    IdealGearR2T(),
    IdealGearR2T(ratio=10, useSupportR=True, useSupportT=True),
    ElastoBacklash(),
    ElastoBacklash(c=2e4, d=50, b=0.1, phi_rel0=0.2, phi_nominal=1, useHeatPort=True),
    ElastoBacklash2(),
    ElastoBacklash2(c=2e4, d=50, b=0.1, phi_rel0=-0.2, useHeatPort=True),
    Disc(),
    Disc(deltaPhi=0.3),
    RelativeStates(),
    RelativeStates(phi_nominal=1e-3),
    InitializeFlange(),
    InitializeFlange(use_phi_start=False, use_a_start=False),
    InitializeFlange(use_phi_start=False, use_w_start=False, use_a_start=False),
    TorqueToAngleAdaptor(),
    TorqueToAngleAdaptor(use_w=False),
    TorqueToAngleAdaptor(use_w=False, use_a=False),
    AngleToTorqueAdaptor(),
    AngleToTorqueAdaptor(use_a=False),
    AngleToTorqueAdaptor(use_w=False, use_a=False),
    AngleToTorqueAdaptor(use_w=False, use_a=True),
    GeneralTorqueToAngleAdaptor(),
    GeneralTorqueToAngleAdaptor(use_pder2=False),
    GeneralTorqueToAngleAdaptor(use_pder=False),
    GeneralAngleToTorqueAdaptor(),
    GeneralAngleToTorqueAdaptor(use_pder2=False),
    GeneralAngleToTorqueAdaptor(use_pder=False),
], ids=lambda c: type(c).__name__ + "".join(f"-{k}={v}" for k, v in c._modifiers.items()))
def test_declarations(component):
    check_declarations(component)


def test_conditional_connectors():
    assert not IdealRollingWheel.supportR.enabled(IdealRollingWheel())
    assert IdealRollingWheel.supportT.enabled(IdealRollingWheel(useSupportT=True))
    assert AngleToTorqueAdaptor.w.enabled(AngleToTorqueAdaptor(use_w=False, use_a=True))
    assert not AngleToTorqueAdaptor.w.enabled(AngleToTorqueAdaptor(use_w=False, use_a=False))
    assert not GeneralTorqueToAngleAdaptor.pder2.enabled(GeneralTorqueToAngleAdaptor(use_pder=False))


@pytest.mark.parametrize("klass", [ElastoBacklash, ElastoBacklash2])
@pytest.mark.parametrize("modifier, words", [
    (dict(c=0), ["c = 0", "> 0"]),
    (dict(b=-0.1), ["b = -0.1", "backlash"]),
    (dict(d=-1), ["d = -1", "damping"]),
])
def test_bad_backlash_parameters(klass, modifier, words):
    class Bad(Model):
        def build(self):
            self.gear = klass(**modifier)

    with pytest.raises(ParameterError) as caught:
        translate(Bad(), cache=False)
    text = str(caught.value) + " " + str(getattr(caught.value, "hint", ""))
    assert "gear" in text
    for word in words:
        assert word in text


# --------------------------------------------------------------------------
# rotational <-> translational


class WheelDrive(Model):
    """Constant torque -> inertia -> coupling -> mass; supports grounded or fixed at offsets."""

    def __init__(self, klass, supports, **modifiers):
        super().__init__()
        self._klass, self._supports, self._modifiers_of_coupling = klass, supports, modifiers

    def build(self):
        self.torque = ConstantTorque(tau_constant=TAU)
        self.inertia = Inertia(J=J, phi=dict(start=PHI_SUPPORT if self._supports else 0, fixed=True), w=REST)
        self.coupling = self._klass(useSupportR=self._supports, useSupportT=self._supports,
                                    **self._modifiers_of_coupling)
        self.mass = Mass(m=M)
        self.connect(self.torque.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.coupling.flangeR)
        self.connect(self.coupling.flangeT, self.mass.flange_a)
        if self._supports:
            self.housingR = Fixed(phi0=PHI_SUPPORT)
            self.housingT = TranslationalFixed(s0=S_SUPPORT)
            self.connect(self.coupling.supportR, self.housingR.flange)
            self.connect(self.coupling.supportT, self.housingT.flange)


TAU, J, M = 10.0, 1.0, 2.0
PHI_SUPPORT, S_SUPPORT = 0.3, -1.5


@pytest.mark.parametrize("supports", [False, True], ids=["grounded", "supports"])
@pytest.mark.parametrize("klass, modifiers, rad_per_m", [
    (IdealRollingWheel, dict(radius=0.5), 1 / 0.5),
    (IdealGearR2T, dict(ratio=4.0), 4.0),
], ids=["IdealRollingWheel", "IdealGearR2T"])
def test_r2t_kinematics_and_power(klass, modifiers, rad_per_m, supports):
    result = simulate(WheelDrive(klass, supports, **modifiers), stop_time=1.0, interval=0.01, rtol=1e-9, atol=1e-12)
    assert result.success
    t = result.time
    # one body: J_eff = J + m/ratio^2 seen from the shaft
    alpha = TAU / (J + M / rad_per_m ** 2)
    phi0 = PHI_SUPPORT if supports else 0.0
    s0 = S_SUPPORT if supports else 0.0
    np.testing.assert_allclose(result["inertia.w"], alpha * t, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(result["inertia.phi"], phi0 + alpha * t ** 2 / 2, rtol=1e-7, atol=1e-9)
    # kinematics relative to the supports
    np.testing.assert_allclose(result["mass.s"] - s0, (result["inertia.phi"] - phi0) / rad_per_m, atol=1e-9)
    # the coupling is lossless: the power in at the shaft is the power out at the rod
    w, v = result["inertia.w"], result["mass.v"]
    power = result["coupling.flangeR.tau"] * w + result["coupling.flangeT.f"] * v
    np.testing.assert_allclose(power, 0.0, atol=1e-9)
    # the rod force accelerates the mass: -flangeT.f = m*a
    np.testing.assert_allclose(-result["coupling.flangeT.f"], M * alpha / rad_per_m, rtol=1e-7)
    if supports:
        np.testing.assert_allclose(result["coupling.supportR.tau"], -result["coupling.flangeR.tau"], atol=1e-12)
        np.testing.assert_allclose(result["coupling.supportT.f"], -result["coupling.flangeT.f"], atol=1e-12)


# --------------------------------------------------------------------------
# backlash


class Rattle(Model):
    """An inertia on a backlash element to ground, started with a speed or an angle."""

    def __init__(self, klass, phi0=0.0, w0=0.0, heat=False, **modifiers):
        super().__init__()
        self._klass, self._phi0, self._w0, self._heat, self._element = klass, phi0, w0, heat, modifiers

    def build(self):
        self.fixed = Fixed()
        self.gear = self._klass(useHeatPort=self._heat, **self._element)
        self.inertia = Inertia(J=J_R, phi=dict(start=self._phi0, fixed=True), w=dict(start=self._w0, fixed=True))
        self.connect(self.fixed.flange, self.gear.flange_a)
        self.connect(self.gear.flange_b, self.inertia.flange_a)
        if self._heat:
            self.housing = HeatCapacitor(C=C_HEAT, T=dict(start=T0, fixed=True))
            self.connect(self.gear.heatPort, self.housing.port)


J_R, C_R, B_R, W0 = 2.0, 800.0, 0.2, 1.5
C_HEAT, T0 = 0.5, 300.0


def test_backlash_coasting_contact_times_and_energy():
    """No damping: coast through half the gap, a spring half-period, coast the whole gap, ..."""
    half_period = math.pi * math.sqrt(J_R / C_R)
    gap = B_R / W0
    result = simulate(Rattle(ElastoBacklash, w0=W0, c=C_R, d=0, b=B_R, phi_rel0=0.0),
                      stop_time=1.2, interval=0.001, rtol=1e-9, atol=1e-12)
    assert result.success
    edges = [e.time for e in result.events if e.kind == "state"
             and any("gear.b/2" in str(r) for r in e.relations)]
    expected = []
    t = gap / 2
    while t < 1.2:
        expected.append(t)
        t += half_period
        if t < 1.2:
            expected.append(t)
        t += gap
    assert len(edges) == len(expected)
    np.testing.assert_allclose(edges, expected, atol=1e-7)
    # energy is conserved: kinetic + spring (measured from the gap edge); the state after each
    # event comes from the integrator's interpolant, a few 1e-8 off at rtol 1e-9
    x = np.maximum(np.abs(result["gear.phi_diff"]) - B_R / 2, 0.0)
    energy = 0.5 * J_R * result["inertia.w"] ** 2 + 0.5 * C_R * x ** 2
    np.testing.assert_allclose(energy, 0.5 * J_R * W0 ** 2, rtol=1e-6)
    # the speed in the gap is +-W0
    in_gap = np.abs(result["gear.phi_diff"]) < B_R / 2 - 1e-6
    np.testing.assert_allclose(np.abs(result["inertia.w"][in_gap]), W0, rtol=1e-6)


@pytest.mark.parametrize("phi_rel0", [0.0, 0.1])
def test_elasto_backlash_torque_law(phi_rel0):
    c, d = C_R, 30.0
    result = simulate(Rattle(ElastoBacklash, phi0=phi_rel0 + 0.25, c=c, d=d, b=B_R, phi_rel0=phi_rel0),
                      stop_time=1.5, interval=0.0005, rtol=1e-8, atol=1e-10)
    assert result.success
    phi_diff = result["inertia.phi"] - phi_rel0
    w_rel = result["inertia.w"]
    tau = result["gear.tau"]
    b_max = B_R / 2
    tau_c = np.where(phi_diff > b_max, c * (phi_diff - b_max), np.where(phi_diff < -b_max, c * (phi_diff + b_max), 0))
    tau_d = d * w_rel
    forward, backward = phi_diff > b_max, phi_diff < -b_max
    expected = np.where(forward, np.where(tau_c + tau_d <= 0, 0, tau_c + np.minimum(tau_c, tau_d)),
                        np.where(backward, np.where(tau_c + tau_d >= 0, 0, tau_c + np.maximum(tau_c, tau_d)), 0))
    t = result.time
    settled = t > 0  # the initial row uses the initialization characteristic
    np.testing.assert_allclose(tau[settled], expected[settled], atol=1e-6 * c * B_R)
    # no torque in the gap; in contact it only pushes; |damping part| <= spring part
    assert np.all(np.abs(tau[settled & ~forward & ~backward]) < 1e-9)
    assert np.all(tau[forward] >= 0) and np.all(tau[backward] <= 0)
    assert np.all(np.abs(tau - tau_c)[settled] <= np.abs(tau_c)[settled] + 1e-6)
    # the pulling cut-off really happens in this run (the damped return)
    assert np.any(forward & (tau_c + tau_d <= 0)) or np.any(backward & (tau_c + tau_d >= 0))
    # lost energy: lossPower >= 0
    assert np.all(result["gear.lossPower"] >= -1e-9)


@pytest.mark.parametrize("klass", [ElastoBacklash, ElastoBacklash2])
@pytest.mark.parametrize("torque", [5.0, 200.0])
def test_backlash_initialization_characteristic(klass, torque):
    """Started in equilibrium (w = a = 0) under a torque, the angle is found through the monotone
    initialization characteristic: (c/3)*phi_diff inside 1.5*bMax, c*(phi_diff - bMax) beyond."""

    class SteadyStart(Model):
        def build(self):
            self.fixed = Fixed()
            self.gear = klass(c=C_R, b=B_R)
            self.inertia = Inertia(J=J_R, w=dict(start=0, fixed=True), a=dict(start=0, fixed=True))
            self.torque = ConstantTorque(tau_constant=torque)
            self.connect(self.fixed.flange, self.gear.flange_a)
            self.connect(self.gear.flange_b, self.inertia.flange_a)
            self.connect(self.torque.flange, self.inertia.flange_b)

    result = simulate(SteadyStart(), stop_time=0.02, interval=0.01, rtol=1e-9, atol=1e-12)
    inside = 3 * torque / C_R
    expected = inside if inside <= 1.5 * B_R / 2 else B_R / 2 + torque / C_R
    assert result["inertia.phi"][0] == pytest.approx(expected, rel=1e-9)
    if inside <= 1.5 * B_R / 2:
        # after initialization the flange is inside the gap: no torque, free acceleration
        np.testing.assert_allclose(result["gear.tau"], 0.0, atol=1e-12)
        np.testing.assert_allclose(result["inertia.w"], torque / J_R * result.time, rtol=1e-8)
    else:
        # in contact the two characteristics agree: the equilibrium holds
        np.testing.assert_allclose(result["inertia.phi"], expected, rtol=1e-8)


def test_elasto_backlash_heat_port_audit():
    """With damping, the heat the capacitor receives is the integral of lossPower, and
    until the first release the energy kinetic + spring + heat is conserved."""
    c, d = C_R, 30.0
    result = simulate(Rattle(ElastoBacklash, w0=W0, heat=True, c=c, d=d, b=B_R),
                      stop_time=1.0, interval=0.0005, rtol=1e-9, atol=1e-12)
    assert result.success
    loss = result["gear.lossPower"]
    np.testing.assert_allclose(result["gear.heatPort.Q_flow"], -loss, atol=1e-12)
    # the capacitor warms by exactly the loss: C*der(T) = lossPower (the loss drops to 0 without an
    # event at each release, so a quadrature of the output rows would not be exact)
    np.testing.assert_allclose(C_HEAT * result["der(housing.T)"], loss, atol=1e-9)
    heat = C_HEAT * (result["housing.T"] - T0)
    assert np.all(np.diff(heat) >= -1e-12)  # heat only flows out of the element
    x = np.maximum(result["gear.phi_diff"] - B_R / 2, 0.0)
    energy = 0.5 * J_R * result["inertia.w"] ** 2 + 0.5 * c * x ** 2 + heat
    tau_c, tau_d = result["gear.tau_c"], result["gear.tau_d"]
    released = np.nonzero((x > 0) & (tau_c + tau_d <= 0))[0]
    first_release = released[0]
    assert heat[first_release] > 0.01 * 0.5 * J_R * W0 ** 2  # the damper really worked
    np.testing.assert_allclose(energy[:first_release], 0.5 * J_R * W0 ** 2, rtol=1e-6)
    # after the release the massless spring's remaining energy is gone: never more than before
    assert np.all(energy <= 0.5 * J_R * W0 ** 2 * (1 + 1e-6))


def test_elasto_backlash2_damped_contact_and_release_event():
    """ElastoBacklash2: after the gap, x'' = -(c x + d x')/J until c x + d x' = 0 (an event)."""
    c, d = C_R, 30.0
    result = simulate(Rattle(ElastoBacklash2, w0=W0, heat=True, c=c, d=d, b=B_R),
                      stop_time=0.3, interval=0.0005, rtol=1e-9, atol=1e-12)
    assert result.success
    t_contact = B_R / 2 / W0
    wn, zeta = math.sqrt(c / J_R), d / (2 * math.sqrt(c * J_R))
    wd = wn * math.sqrt(1 - zeta ** 2)

    def x(s):
        return W0 / wd * math.exp(-zeta * wn * s) * math.sin(wd * s)

    def v(s):
        return W0 * math.exp(-zeta * wn * s) * (math.cos(wd * s) - zeta * wn / wd * math.sin(wd * s))

    release = brentq(lambda s: c * x(s) + d * v(s), 0.5 * math.pi / wd, math.pi / wd)
    state_events = [e.time for e in result.events if e.kind == "state"]
    assert any(abs(e - t_contact) < 1e-8 for e in state_events)
    assert any(abs(e - (t_contact + release)) < 1e-7 for e in state_events)
    # the torque jumps by d*W0 at contact, and the motion follows the closed form
    t = result.time
    contact = (t > t_contact) & (t < t_contact + release)
    s = t[contact] - t_contact
    np.testing.assert_allclose(result["gear.phi_diff"][contact] - B_R / 2, [x(q) for q in s], atol=1e-8)
    contact_event = min(state_events, key=lambda e: abs(e - t_contact))
    rows = np.nonzero(t == contact_event)[0]  # left and right limit
    assert result["gear.tau"][rows[0]] == 0
    assert result["gear.tau"][rows[-1]] == pytest.approx(d * W0, rel=1e-6)
    # after release: free coasting with the release speed, torque 0
    coast = (t > t_contact + release + 1e-6) & (result["gear.phi_diff"] > -B_R / 2)
    np.testing.assert_allclose(result["inertia.w"][coast], v(release), rtol=1e-6)
    np.testing.assert_allclose(result["gear.tau"][coast], 0.0, atol=1e-12)
    # the damper's loss is the heat: until release, kinetic + spring + heat is conserved
    heat = C_HEAT * (result["housing.T"] - T0)
    xs = np.maximum(result["gear.phi_diff"] - B_R / 2, 0.0)
    energy = 0.5 * J_R * result["inertia.w"] ** 2 + 0.5 * c * xs ** 2 + heat
    before = t < t_contact + release - 1e-6
    np.testing.assert_allclose(energy[before], 0.5 * J_R * W0 ** 2, rtol=1e-6)


# --------------------------------------------------------------------------
# Disc, RelativeStates, InitializeFlange


class DiscPair(Model):
    def build(self):
        self.torque = ConstantTorque(tau_constant=3.0)
        self.inertia1 = Inertia(J=1.0, phi=REST, w=REST)
        self.disc = Disc(deltaPhi=0.7)
        self.inertia2 = Inertia(J=2.0)
        self.connect(self.torque.flange, self.inertia1.flange_a)
        self.connect(self.inertia1.flange_b, self.disc.flange_a)
        self.connect(self.disc.flange_b, self.inertia2.flange_a)


def test_disc_offset_and_rigid_transmission():
    result = simulate(DiscPair(), stop_time=1.0, interval=0.1, rtol=1e-9, atol=1e-12)
    t = result.time
    np.testing.assert_allclose(result["inertia2.phi"] - result["inertia1.phi"], 0.7, atol=1e-12)
    np.testing.assert_allclose(result["disc.phi"], result["inertia1.phi"] + 0.35, atol=1e-12)
    np.testing.assert_allclose(result["inertia1.w"], t, rtol=1e-8, atol=1e-12)  # 3 N.m on 3 kg.m2
    np.testing.assert_allclose(result["disc.flange_b.tau"], -2.0, rtol=1e-8)  # what accelerates inertia2


class TwoInertias(Model):
    def __init__(self, relative_states):
        super().__init__()
        self._relative = relative_states

    def build(self):
        self.inertia1 = Inertia(J=1.0, phi=dict(start=0.0, fixed=True), w=dict(start=1.0, fixed=True))
        self.spring = Spring(c=100.0)
        self.inertia2 = Inertia(J=1.0, phi=dict(start=0.2, fixed=True), w=REST)
        self.connect(self.inertia1.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.inertia2.flange_a)
        if self._relative:
            self.relativeStates = RelativeStates()
            self.connect(self.inertia1.flange_b, self.relativeStates.flange_a)
            self.connect(self.inertia2.flange_a, self.relativeStates.flange_b)


def test_relative_states_are_states_and_change_nothing():
    translation = translate(TwoInertias(True), cache=False)
    states = set(translation.system(()).states)
    assert {"relativeStates.phi_rel", "relativeStates.w_rel"} <= states
    with_states = simulate(translation, stop_time=1.0, interval=0.01, rtol=1e-10, atol=1e-12)
    # closed form: centre of mass moves at 0.5 rad/s; relative angle oscillates at sqrt(2c/J)
    t = with_states.time
    omega = math.sqrt(200.0)
    rel = 0.2 * np.cos(omega * t) - 1.0 / omega * np.sin(omega * t)
    np.testing.assert_allclose(with_states["relativeStates.phi_rel"], rel, atol=1e-7)
    np.testing.assert_allclose(with_states["relativeStates.flange_a.tau"], 0.0, atol=1e-12)
    np.testing.assert_allclose((with_states["inertia1.phi"] + with_states["inertia2.phi"]) / 2, 0.1 + 0.5 * t,
                               atol=1e-7)


class Initialized(Model):
    def __init__(self, **uses):
        super().__init__()
        self._uses = uses

    def build(self):
        self.inertia1 = Inertia(J=2.0)
        self.spring = Spring(c=50.0)
        self.inertia2 = Inertia(J=1.0, w=REST)
        self.initializer = InitializeFlange(**self._uses)
        self.connect(self.inertia1.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.inertia2.flange_a)
        self.connect(self.initializer.flange, self.inertia1.flange_a)
        for name, value in (("phi_start", 0.5), ("w_start", -1.0), ("a_start", 3.0)):
            if getattr(self.initializer, f"use_{name}"):
                source = Constant(k=value)
                setattr(self, f"{name}_source", source)
                self.connect(source.y, getattr(self.initializer, name))


def test_initialize_flange_sets_angle_speed_and_acceleration():
    result = simulate(Initialized(), stop_time=0.1, interval=0.01, rtol=1e-10, atol=1e-12)
    assert result["inertia1.phi"][0] == pytest.approx(0.5)
    assert result["inertia1.w"][0] == pytest.approx(-1.0)
    assert result["inertia1.a"][0] == pytest.approx(3.0)
    # J1*a1 = c*(phi2 - phi1): the acceleration fixes the spring, hence phi2
    assert result["inertia2.phi"][0] == pytest.approx(0.5 + 2.0 * 3.0 / 50.0)
    np.testing.assert_allclose(result["initializer.flange.tau"], 0.0, atol=1e-12)
    # it exerts no torque afterwards: momentum J1*w1 + J2*w2 is conserved
    np.testing.assert_allclose(2.0 * result["inertia1.w"] + result["inertia2.w"], -2.0, atol=1e-8)


def test_initialize_flange_without_acceleration():
    class Free(Model):
        def build(self):
            self.inertia = Inertia(J=1.0)
            self.initializer = InitializeFlange(use_a_start=False)
            self.phi_source = Constant(k=0.25)
            self.w_source = Constant(k=2.0)
            self.connect(self.initializer.flange, self.inertia.flange_a)
            self.connect(self.phi_source.y, self.initializer.phi_start)
            self.connect(self.w_source.y, self.initializer.w_start)

    result = simulate(Free(), stop_time=1.0, interval=0.1, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(result["inertia.phi"], 0.25 + 2.0 * result.time, atol=1e-9)


# --------------------------------------------------------------------------
# adaptors


class TorqueDriven(Model):
    def __init__(self, klass, **uses):
        super().__init__()
        self._klass, self._uses = klass, uses

    def build(self):
        self.source = Constant(k=2.0)
        self.adaptor = self._klass(**self._uses)
        self.inertia = Inertia(J=4.0, phi=dict(start=0.1, fixed=True), w=dict(start=0.5, fixed=True))
        self.connect(self.adaptor.flange, self.inertia.flange_a)
        self.connect(self.source.y, self.adaptor.tau if self._klass is TorqueToAngleAdaptor else self.adaptor.f)


@pytest.mark.parametrize("uses", [dict(), dict(use_a=False), dict(use_w=False, use_a=False)])
def test_torque_to_angle_adaptor(uses):
    result = simulate(TorqueDriven(TorqueToAngleAdaptor, **uses), stop_time=1.0, interval=0.1, rtol=1e-10)
    t = result.time
    # the input torque drives the inertia: flange.tau = tau is the torque the adaptor's flange takes,
    # so the inertia sees -2 N.m
    np.testing.assert_allclose(result["inertia.w"], 0.5 - 0.5 * t, atol=1e-9)
    np.testing.assert_allclose(result["adaptor.phi"], 0.1 + 0.5 * t - 0.25 * t ** 2, atol=1e-9)
    if uses.get("use_w", True):
        np.testing.assert_allclose(result["adaptor.w"], result["inertia.w"], atol=1e-9)
    else:
        np.testing.assert_allclose(result["adaptor.w_internal"], 0.0)
    if uses.get("use_a", True):
        np.testing.assert_allclose(result["adaptor.a"], -0.5, atol=1e-9)
    else:
        np.testing.assert_allclose(result["adaptor.a_internal"], 0.0)


@pytest.mark.parametrize("uses", [dict(), dict(use_pder2=False), dict(use_pder=False)])
def test_general_torque_to_angle_adaptor(uses):
    result = simulate(TorqueDriven(GeneralTorqueToAngleAdaptor, **uses), stop_time=1.0, interval=0.1, rtol=1e-10)
    t = result.time
    np.testing.assert_allclose(result["adaptor.p"], 0.1 + 0.5 * t - 0.25 * t ** 2, atol=1e-9)
    if uses.get("use_pder", True):
        np.testing.assert_allclose(result["adaptor.pder"], 0.5 - 0.5 * t, atol=1e-9)
    if uses.get("use_pder", True) and uses.get("use_pder2", True):
        np.testing.assert_allclose(result["adaptor.pder2"], -0.5, atol=1e-9)


class AngleDriven(Model):
    """phi = sin(t), w = cos(t) and an acceleration input that is deliberately *not* der(w)."""

    def __init__(self, klass, names, a_value, **uses):
        super().__init__()
        self._klass, self._names, self._a, self._uses = klass, names, a_value, uses

    def build(self):
        self.adaptor = self._klass(**self._uses)
        self.inertia = Inertia(J=3.0)
        self.connect(self.adaptor.flange, self.inertia.flange_a)
        phi, w, a = self._names
        self.angle = Sine(amplitude=1.0, f=1 / (2 * math.pi))
        self.connect(self.angle.y, getattr(self.adaptor, phi))
        if getattr(self._klass, w).enabled(self.adaptor):
            self.speed = Sine(amplitude=1.0, f=1 / (2 * math.pi), phase=math.pi / 2)
            self.connect(self.speed.y, getattr(self.adaptor, w))
        if getattr(self._klass, a).enabled(self.adaptor):
            self.acceleration = Constant(k=self._a)
            self.connect(self.acceleration.y, getattr(self.adaptor, a))


@pytest.mark.parametrize("klass, names, torque", [
    (AngleToTorqueAdaptor, ("phi", "w", "a"), "tau"),
    (GeneralAngleToTorqueAdaptor, ("p", "pder", "pder2"), "f"),
])
@pytest.mark.parametrize("uses, expected_acceleration", [
    ("all", lambda t: np.full_like(t, 0.7)),    # the given acceleration is used as der(w)
    ("speed", lambda t: -np.sin(t)),            # der(w) of the speed input
    ("angle", lambda t: -np.sin(t)),            # der(der(phi)) of the angle input
])
def test_angle_to_torque_adaptors(klass, names, torque, uses, expected_acceleration):
    first, second = ("use_w", "use_a") if klass is AngleToTorqueAdaptor else ("use_pder", "use_pder2")
    flags = {"all": {}, "speed": {second: False}, "angle": {first: False, second: False}}[uses]
    result = simulate(AngleDriven(klass, names, 0.7, **flags), stop_time=2.0, interval=0.05, rtol=1e-10)
    assert result.success
    t = result.time
    np.testing.assert_allclose(result["inertia.phi"], np.sin(t), atol=1e-9)
    np.testing.assert_allclose(result["inertia.w"], np.cos(t) if uses != "angle" else np.cos(t), atol=1e-7)
    # the torque needed to move the inertia: J*a
    np.testing.assert_allclose(result[f"adaptor.{torque}"], 3.0 * expected_acceleration(t), atol=1e-6)
