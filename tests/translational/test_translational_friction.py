"""Translational friction elements: SupportFriction, Brake, MassWithStopAndFriction.

Declaration checks with defaults and typical modifiers, parameter errors,
and the motion of a mass against each element compared with closed forms
derived by hand from Newton's law with Coulomb (or Stribeck) friction:

* SupportFriction under a constant force below the static limit holds the
  mass (v = 0, friction force = applied force); above it the mass slides with
  m*a = F - F_friction(v), for a constant and for a linear characteristic;
* a Brake engaged on a moving mass stops it at t* = v0*m/F_brake, it stays
  at rest, and the heat it sends to a capacitor is the kinetic energy lost;
* MassWithStopAndFriction coasting against Coulomb and Stribeck friction
  stops at the time given by integrating m*dv/dt = -(F_C + F_S*exp(-k*v)).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from library_checks import attach, check_declarations, collect, own_names

from acausal import Model, simulate
from acausal.errors import ParameterError
from acausal.hybrid import Assert, Reinit, When
from acausal.library.blocks import Constant, Step
from acausal.library.thermal import HeatCapacitor
from acausal.library.translational.components import Fixed, Mass
from acausal.library.translational.friction import Brake, MassWithStopAndFriction, SupportFriction
from acausal.library.translational.sources import Force

FORWARD, STUCK, BACKWARD, FREE = 1, 0, -1, 2


# --------------------------------------------------------------------------
# declarations


@pytest.mark.parametrize("component", [
    SupportFriction(),
    SupportFriction(f_pos=[[0, 2], [1, 3], [2, 5]], peak=1.2, useSupport=True, useHeatPort=True),
    Brake(),
    Brake(fn_max=100, mu_pos=[[0, 0.4], [10, 0.3]], peak=1.1, cgeo=0.5, useSupport=True, useHeatPort=True),
], ids=["SupportFriction", "SupportFriction-modified", "Brake", "Brake-modified"])
def test_declarations(component):
    check_declarations(component)


def _when_items(component):
    return [item for when in collect(component) if isinstance(when, When)
            for _, items in when.branches for item in items]


@pytest.mark.parametrize("component", [
    MassWithStopAndFriction(),
    MassWithStopAndFriction(L=1, smax=0.9, smin=-0.9, m=2, F_prop=0, F_Coulomb=3, F_Stribeck=5, fexp=2,
                            useHeatPort=True, s=dict(start=0, fixed=True), v=dict(start=-5, fixed=True)),
], ids=["defaults", "modified"])
def test_mass_with_stop_declarations(component):
    """check_declarations' rules (a when-clause counts as the variables it assigns: the impact
    reinit and the initial assertions assign none), and what its two when-clauses do."""
    check_declarations(component)
    x = component
    allowed = own_names(x)
    items = _when_items(x)
    reinits = {item.variable for item in items if isinstance(item, Reinit)}
    assert reinits == {x.s, x.v}
    assert sum(isinstance(item, Assert) for item in items) == 2
    for item in items:
        expression = item.value if isinstance(item, Reinit) else item.condition
        assert {s.name for s in expression.free_symbols} <= allowed


@pytest.mark.parametrize("make, match", [
    (lambda: SupportFriction(f_pos=[[0, -1]]), "f_pos"),
    (lambda: SupportFriction(f_pos=[[1, 0], [0, 1]]), "f_pos"),
    (lambda: SupportFriction(peak=0.5), "peak"),
    (lambda: Brake(mu_pos=[[-1, 0.5], [1, 0.5]]), "mu_pos"),
    (lambda: Brake(peak=0.9), "peak"),
    (lambda: Brake(fn_max=-1), "fn_max"),
    (lambda: MassWithStopAndFriction(L=2, smin=-0.5, smax=0.5), "smax"),
], ids=["negative-force", "decreasing-v", "peak-SF", "negative-v", "peak-Brake", "fn_max", "stops-too-close"])
def test_bad_parameters(make, match):
    with pytest.raises(ParameterError, match=match) as info:
        attach(make(), "element")
    assert "element" in str(info.value)


def test_table_messages_speak_of_forces_and_velocities():
    """The friction-table checks shared with Rotational use the translational names."""
    with pytest.raises(ParameterError) as info:
        attach(SupportFriction(f_pos=[[0, 1], [1, -2]]), "element")
    assert "element.f_pos" in info.value.message and "friction force must not be negative" in info.value.hint
    with pytest.raises(ParameterError) as info:
        attach(Brake(mu_pos=[[-1, 0.5], [1, 0.5]]), "element")
    assert "relative speed v >= 0, in m/s" in info.value.message and "v = 0" in info.value.hint


# --------------------------------------------------------------------------
# SupportFriction: stuck below the static limit, sliding above it


def support_friction_model(F, m=2.0, **friction):
    class Pushed(Model):
        """A mass on SupportFriction, pushed by a constant force F from rest."""

        def build(self):
            self.source = Constant(k=F)
            self.force = Force()
            self.mass = Mass(m=m, s=dict(start=0, fixed=True), v=dict(start=0, fixed=True))
            self.friction = SupportFriction(**friction)
            self.connect(self.source.y, self.force.f)
            self.connect(self.force.flange, self.mass.flange_a)
            self.connect(self.mass.flange_b, self.friction.flange_a)

    return Pushed()


@pytest.mark.parametrize("F", [3.0, -3.0, 4.0, 4.7], ids=["below", "below-negative", "equal-f0", "below-peak"])
def test_support_friction_holds_below_the_static_limit(F):
    # f0 = 4, peak 1.2: f0_max = 4.8; 4.7 lies between sliding and static friction
    result = simulate(support_friction_model(F, f_pos=[[0, 4.0]], peak=1.2), stop_time=2.0, interval=0.01)
    assert result.status == 0, result.message
    assert np.all(result["mass.v"] == 0) and np.all(result["mass.s"] == 0)
    assert np.all(result["friction.locked"] == 1) and np.all(result["friction.mode"] == STUCK)
    np.testing.assert_allclose(result["friction.f"], F, rtol=1e-12)   # the friction takes the whole force
    assert not [e for e in result.events if e.kind == "state" and e.changes]


@pytest.mark.parametrize("F", [6.0, -6.0], ids=["forward", "backward"])
def test_support_friction_slides_above_the_static_limit(F):
    """Constant characteristic f0 = 4: a = (F - sign(F)*4)/m from t = 0."""
    m = 2.0
    result = simulate(support_friction_model(F, m=m, f_pos=[[0, 4.0]], peak=1.2), stop_time=2.0, interval=0.01)
    assert result.status == 0, result.message
    t = result.time
    a = (F - math.copysign(4.0, F)) / m
    np.testing.assert_allclose(result["mass.v"], a * t, rtol=0, atol=1e-9)
    np.testing.assert_allclose(result["mass.s"], a * t**2 / 2, rtol=0, atol=1e-9)
    assert result.final("friction.mode") == math.copysign(1, F)


def test_support_friction_linear_characteristic():
    """f(v) = c0 + c1*v: m*dv/dt = F - c0 - c1*v, so v = (F - c0)/c1*(1 - exp(-c1*t/m)).

    The table [0, c0; 1, c0 + c1] is extrapolated linearly beyond v = 1.
    """
    m, F, c0, c1 = 1.5, 10.0, 2.0, 3.0
    result = simulate(support_friction_model(F, m=m, f_pos=[[0, c0], [1, c0 + c1]]), stop_time=3.0,
                      interval=0.01, rtol=1e-9)
    assert result.status == 0, result.message
    t = result.time
    v_inf, rate = (F - c0) / c1, c1 / m
    np.testing.assert_allclose(result["mass.v"], v_inf * (1 - np.exp(-rate * t)), rtol=0, atol=1e-7)
    np.testing.assert_allclose(result["mass.s"], v_inf * (t - (1 - np.exp(-rate * t)) / rate), rtol=0, atol=1e-7)
    np.testing.assert_allclose(result["friction.f"], c0 + c1 * result["mass.v"], rtol=1e-9)


# --------------------------------------------------------------------------
# Brake: stops a moving mass at v0*m/F_brake, then it stays at rest


def braked_mass(v0, m, fn_max, mu, u=1.0, use_support=False, heat_capacity=None, push=None):
    class Braked(Model):
        """A mass moving at v0, a Brake engaged from t = 0 with normal force fn_max*u."""

        def build(self):
            self.mass = Mass(m=m, s=dict(start=0, fixed=True), v=dict(start=v0, fixed=True))
            self.brake = Brake(fn_max=fn_max, mu_pos=[[0, mu]], useSupport=use_support,
                               useHeatPort=heat_capacity is not None)
            self.normal = Constant(k=u)
            self.connect(self.mass.flange_b, self.brake.flange_a)
            self.connect(self.normal.y, self.brake.f_normalized)
            if use_support:
                self.fixed = Fixed(s0=0.3)
                self.connect(self.brake.support, self.fixed.flange)
            if heat_capacity is not None:
                self.capacitor = HeatCapacitor(C=heat_capacity, T=dict(start=300, fixed=True))
                self.connect(self.brake.heatPort, self.capacitor.port)
            if push is not None:
                self.push = Step(height=push, startTime=10.0)
                self.force = Force()
                self.connect(self.push.y, self.force.f)
                self.connect(self.force.flange, self.mass.flange_a)

    return Braked()


@pytest.mark.parametrize("v0, use_support", [(2.0, False), (-2.0, False), (2.0, True)],
                         ids=["forward", "backward", "with-support"])
def test_brake_stops_the_mass_at_the_closed_form_time(v0, use_support):
    m, fn_max, mu, u = 3.0, 10.0, 0.4, 0.5
    F_brake = mu * fn_max * u  # 2 N
    t_stop = abs(v0) * m / F_brake  # 3 s
    result = simulate(braked_mass(v0, m, fn_max, mu, u, use_support), stop_time=2 * t_stop, interval=0.01)
    assert result.status == 0, result.message
    stops = [e for e in result.events if ("brake.mode", math.copysign(1, v0), STUCK) in e.changes]
    assert len(stops) == 1
    assert stops[0].time == pytest.approx(t_stop, abs=1e-8)
    t, v, s = result.time, result["mass.v"], result["mass.s"]
    before, after = t < stops[0].time, t > stops[0].time
    np.testing.assert_allclose(v[before], v0 - math.copysign(F_brake / m, v0) * t[before], rtol=0, atol=1e-9)
    s_stop = v0 * t_stop / 2
    np.testing.assert_allclose(s[after], s_stop, rtol=0, atol=1e-9)
    assert np.all(np.abs(v[after]) <= 1e-9)
    assert np.all(result["brake.locked"][after] == 1)
    # the only mode changes: the stop (sliding -> stuck)
    assert len([e for e in result.events if e.kind == "state" and e.changes]) == 1


def test_brake_holds_a_force_below_its_limit_and_yields_above():
    """After the stop a step force of 1.5 N (< F_brake = 2 N) at t = 10 is held;
    with 3 N the mass breaks away and accelerates at (3 - 2)/m."""
    m, fn_max, mu, u = 3.0, 10.0, 0.4, 0.5
    held = simulate(braked_mass(2.0, m, fn_max, mu, u, push=1.5), stop_time=12.0, interval=0.01)
    assert held.status == 0, held.message
    late = held.time > 3.0 + 1e-6
    assert np.all(np.abs(held["mass.v"][late]) <= 1e-9)
    np.testing.assert_allclose(held.final("brake.f"), 1.5, rtol=1e-12)

    pushed = simulate(braked_mass(2.0, m, fn_max, mu, u, push=3.0), stop_time=12.0, interval=0.01)
    assert pushed.status == 0, pushed.message
    after = pushed.time > 10.0
    np.testing.assert_allclose(pushed["mass.v"][after], (3.0 - 2.0) / m * (pushed.time[after] - 10.0),
                               rtol=0, atol=1e-8)
    assert pushed.final("brake.mode") == FORWARD


def test_brake_heat_equals_the_kinetic_energy_lost():
    """Energy: the heat in the capacitor is m*v0^2/2, so C*(T - T0) = m*v0^2/2."""
    m, v0, C = 3.0, 2.0, 0.5
    result = simulate(braked_mass(v0, m, 10.0, 0.4, 0.5, heat_capacity=C), stop_time=5.0, interval=0.01,
                      rtol=1e-9)
    assert result.status == 0, result.message
    heat = C * (result.final("capacitor.T") - 300.0)
    assert heat == pytest.approx(m * v0**2 / 2, rel=1e-7)


def test_brake_is_free_without_normal_force():
    result = simulate(braked_mass(1.5, 1.0, 10.0, 0.4, u=0.0), stop_time=1.0, interval=0.01)
    assert result.status == 0, result.message
    np.testing.assert_allclose(result["mass.v"], 1.5, rtol=0, atol=1e-12)
    assert np.all(result["brake.mode"] == FREE) and np.all(result["brake.f"] == 0)


# --------------------------------------------------------------------------
# MassWithStopAndFriction: coasting against Coulomb and Stribeck friction


def coasting_mass(v0, **parameters):
    class Coasting(Model):
        """A MassWithStopAndFriction launched at v0, far from its stops."""

        def build(self):
            self.mass = MassWithStopAndFriction(s=dict(start=0, fixed=True), v=dict(start=v0, fixed=True),
                                                **parameters)

    return Coasting()


@pytest.mark.parametrize("v0", [3.0, -3.0], ids=["forward", "backward"])
def test_mass_with_stop_coulomb_coast_down(v0):
    """F_prop = F_Stribeck = 0: constant deceleration F_C/m, stop at t* = |v0|*m/F_C."""
    m, F_C = 2.0, 4.0
    t_stop = abs(v0) * m / F_C
    result = simulate(coasting_mass(v0, m=m, F_prop=0, F_Coulomb=F_C, F_Stribeck=0), stop_time=2 * t_stop,
                      interval=0.01)
    assert result.status == 0, result.message
    (stop,) = [e for e in result.events if ("mass.mode", math.copysign(1, v0), STUCK) in e.changes]
    assert stop.time == pytest.approx(t_stop, abs=1e-8)
    t, v, s = result.time, result["mass.v"], result["mass.s"]
    before, after = t < stop.time, t > stop.time
    np.testing.assert_allclose(v[before], v0 - math.copysign(F_C / m, v0) * t[before], rtol=0, atol=1e-9)
    np.testing.assert_allclose(s[after], v0 * t_stop / 2, rtol=0, atol=1e-9)
    # stuck with the speed at which the stop was detected (the relation margin, 1e-10 m/s)
    assert np.all(np.abs(v[after]) <= 1e-9) and np.all(result["mass.locked"][after] == 1)
    assert np.all(result["mass.stopped"] == 0)


def test_mass_with_stop_stribeck_coast_down():
    """F_prop = 0: m*dv/dt = -(C + S*exp(-k*v)) for v > 0.  Separating,
    t(v) = m/(k*C) * ln((C*exp(k*v0) + S)/(C*exp(k*v) + S)), so the mass stops
    at t* = m/(k*C) * ln((C*exp(k*v0) + S)/(C + S))."""
    m, C, S, k, v0 = 1.5, 2.0, 3.0, 1.5, 2.5
    t_stop = m / (k * C) * math.log((C * math.exp(k * v0) + S) / (C + S))
    result = simulate(coasting_mass(v0, m=m, F_prop=0, F_Coulomb=C, F_Stribeck=S, fexp=k), stop_time=1.5 * t_stop,
                      interval=t_stop / 200, rtol=1e-10)
    assert result.status == 0, result.message
    (stop,) = [e for e in result.events if ("mass.mode", FORWARD, STUCK) in e.changes]
    assert stop.time == pytest.approx(t_stop, abs=1e-7)
    before = result.time < stop.time
    v = result["mass.v"][before]
    t_of_v = m / (k * C) * np.log((C * math.exp(k * v0) + S) / (C * np.exp(k * v) + S))
    np.testing.assert_allclose(t_of_v, result.time[before], rtol=0, atol=1e-7)
    np.testing.assert_allclose(result["mass.f"][before], C + S * np.exp(-k * v), rtol=1e-9)
    assert np.all(np.abs(result["mass.v"][result.time > stop.time]) <= 1e-9)


def test_mass_with_stop_equals_support_friction_with_the_stribeck_table():
    """The MSL Friction example's claim: a Mass on a SupportFriction whose table samples the
    Stribeck characteristic moves like MassWithStopAndFriction (here: a coast-down from 2.5 m/s,
    the table fine enough that linear interpolation is within 1e-3 N)."""
    m, C, S, k, Fp, v0 = 1.0, 5.0, 10.0, 2.0, 1.0, 2.5
    speeds = np.linspace(0, 3, 301)
    table = np.column_stack([speeds, C + Fp * speeds + S * np.exp(-k * speeds)]).tolist()

    class Both(Model):
        def build(self):
            self.stop = MassWithStopAndFriction(m=m, F_prop=Fp, F_Coulomb=C, F_Stribeck=S, fexp=k,
                                                s=dict(start=0, fixed=True), v=dict(start=v0, fixed=True))
            self.mass = Mass(m=m, s=dict(start=0, fixed=True), v=dict(start=v0, fixed=True))
            self.friction = SupportFriction(f_pos=table)
            self.connect(self.mass.flange_b, self.friction.flange_a)

    result = simulate(Both(), stop_time=1.0, interval=0.005, rtol=1e-9)
    assert result.status == 0, result.message
    np.testing.assert_allclose(result["mass.v"], result["stop.v"], rtol=0, atol=2e-4)
    stops = [e.time for e in result.events if ("stop.mode", FORWARD, STUCK) in e.changes
             or ("friction.mode", FORWARD, STUCK) in e.changes]
    assert len(stops) == 2 and abs(stops[0] - stops[1]) < 1e-3
