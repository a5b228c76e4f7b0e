"""Declarations and equations of the component libraries, checked without a simulator.

Each component is instantiated (with defaults and with modifiers), attached to
a Model, built, and its equations are collected along the MRO as the
flattener does.  The checks: equations are sympy objects naming only the
component's own declarations, every discrete variable is defined by an
equation with it on the left, each component is locally balanced (Modelica's
rule: equations = non-input variables + connector potentials), the friction
logic and signal sources give the values of the spec when substituted, and
the table functions interpolate and extrapolate as CombiTable1D does.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from acausal.errors import ConnectorError, ModifierError, ParameterError
from acausal.language import (
    Boolean,
    Integer,
    Model,
    StateSelect,
    initial,
    pre,
    time,
)
from acausal.tables import table_function, validate_table
from acausal.components.friction import Backward, Forward, Free, PartialFriction, Stuck, Unknown
from acausal.library.blocks import Add, Constant, Cosine, ExpSine, Feedback, Gain, Integrator, Product, Ramp, Sine, Step
from acausal.library.rotational import (
    AccSensor,
    AngleSensor,
    BearingFriction,
    Brake,
    Clutch,
    ConstantTorque,
    Damper,
    Fixed,
    IdealGear,
    IdealPlanetary,
    Inertia,
    MultiSensor,
    OneWayClutch,
    PowerSensor,
    RelAngleSensor,
    RelSpeedSensor,
    SpeedSensor,
    Spring,
    SpringDamper,
    Torque,
    TorqueSensor,
    TorqueStep,
)
from acausal.library.thermal import (
    Celsius,
    CelsiusFixedTemperature,
    CelsiusTemperatureSensor,
    Convection,
    FixedHeatFlow,
    FixedTemperature,
    HeatCapacitor,
    HeatFlowSensor,
    PrescribedHeatFlow,
    PrescribedTemperature,
    TemperatureSensor,
    ThermalConductor,
    ThermalResistor,
)

from library_checks import check_declarations, exported_classes, attach, collect, enabled_declarations, local_balance, own_names, params, rhs_of, value  # noqa: F401


# --------------------------------------------------------------------------
# every component, with defaults and with modifiers

DEFAULTS = [
    Inertia, Fixed, Spring, Damper, SpringDamper, IdealGear, IdealPlanetary, BearingFriction, Clutch,
    Brake, OneWayClutch, Torque, ConstantTorque, TorqueStep, AngleSensor, SpeedSensor, AccSensor,
    TorqueSensor, RelAngleSensor, RelSpeedSensor, PowerSensor, MultiSensor,
    HeatCapacitor, ThermalConductor, ThermalResistor, Convection, FixedTemperature,
    PrescribedTemperature, FixedHeatFlow, PrescribedHeatFlow, TemperatureSensor, HeatFlowSensor,
    CelsiusFixedTemperature, CelsiusTemperatureSensor,
    Constant, Step, Ramp, Sine, Cosine, ExpSine, Gain, Product, Add, Feedback, Integrator,
]

MODIFIED = [
    lambda: Inertia(J=2, phi=dict(start=0, fixed=True), w=dict(start=10, fixed=True),
                    stateSelect=StateSelect.always),
    lambda: Fixed(phi0=0.5),
    lambda: Spring(c=1e4, phi_rel=dict(fixed=True)),
    lambda: Damper(d=10, useHeatPort=True),
    lambda: SpringDamper(c=160, d=1, phi_nominal=1, w_rel=dict(fixed=True, nominal=1e-4)),
    lambda: IdealGear(ratio=10, useSupport=True),
    lambda: IdealPlanetary(ratio=1.5),
    lambda: BearingFriction(tau_pos=[[0, 0.5], [1, 1]], peak=1.1, useSupport=True, useHeatPort=True),
    lambda: BearingFriction(tau_pos=np.array([[0.0, 5.0], [100.0, 5.0]]), peak=1.001, K_locked=10),
    lambda: Clutch(fn_max=160, peak=1.1, cgeo=1.2, mu_pos=[[0, 1]], useHeatPort=True,
                   phi_rel=dict(fixed=True), w_rel=dict(fixed=True)),
    lambda: Brake(fn_max=1600, useSupport=True, useHeatPort=True, w_small=1),
    lambda: OneWayClutch(fn_max=1, useHeatPort=True, phi_rel=dict(fixed=True), w_rel=dict(fixed=True),
                         startForward=dict(fixed=True), stuck=dict(fixed=True)),
    lambda: Torque(useSupport=True),
    lambda: ConstantTorque(tau_constant=-0.3, useSupport=True),
    lambda: TorqueStep(stepTorque=20, offsetTorque=0, startTime=0.5),
    lambda: HeatCapacitor(C=15, T=dict(start=373.15, fixed=True)),
    lambda: ThermalConductor(G=10),
    lambda: ThermalResistor(R=0.1),
    lambda: FixedTemperature(T=293.15),
    lambda: FixedHeatFlow(Q_flow=10, alpha=0.01),
    lambda: PrescribedHeatFlow(T_ref=368.15, alpha=3.03e-3),
    lambda: Celsius.FixedTemperature(T=25),
    lambda: Constant(k=20),
    lambda: Step(height=-1, offset=1, startTime=0.5),
    lambda: Ramp(height=5, duration=2, offset=-10),
    lambda: Sine(amplitude=10, f=5, phase=0.3, continuous=True),
    lambda: Cosine(amplitude=2, f=0.2, continuous=True),
    lambda: ExpSine(f=2, damping=0.5),
    lambda: Gain(k=3),
    lambda: Add(k1=1, k2=-1),
]

ALL_INSTANCES = [pytest.param(cls, id=cls.__name__) for cls in DEFAULTS] + [
    pytest.param(make, id=f"modified{i}") for i, make in enumerate(MODIFIED)]


@pytest.mark.parametrize("make", ALL_INSTANCES)
def test_equations_are_sympy_and_use_own_names(make):
    x = attach(make())
    allowed = own_names(x)
    equations = collect(x)
    assert equations, "every component has equations"
    for eq in equations:
        assert isinstance(eq, sp.Basic), f"{eq!r} is not a sympy object"
        assert eq not in (sp.true, sp.false), f"{type(x).__name__} has a trivial equation {eq}"
        assert isinstance(eq, sp.Equality)
        for sym in eq.free_symbols:
            assert sym is time or sym.name in allowed, f"{type(x).__name__}: unknown name {sym.name} in {eq}"
    for eq in collect(x, "initial_equations"):
        assert isinstance(eq, sp.Basic)


@pytest.mark.parametrize("make", ALL_INSTANCES)
def test_locally_balanced(make):
    x = attach(make())
    n_equations, n_unknowns = local_balance(x)
    assert n_equations == n_unknowns, f"{type(x).__name__}: {n_equations} equations, {n_unknowns} unknowns"


@pytest.mark.parametrize("make", ALL_INSTANCES)
def test_discrete_variables_are_defined_with_the_variable_on_the_left(make):
    x = attach(make())
    lhs = [e.lhs for e in collect(x) if isinstance(e, sp.Equality)]
    for key, decl in enabled_declarations(x).items():
        if isinstance(decl, (Boolean, Integer)):
            assert lhs.count(getattr(x, key)) == 1, f"{key} needs exactly one defining equation"


@pytest.mark.parametrize("name, klass", sorted(exported_classes().items()), ids=sorted(exported_classes()))
def test_every_exported_class_passes_the_declaration_checks(name, klass):
    """Each class of the libraries, with its defaults: own names only, balanced, discrete
    variables defined once (their behaviour is tested in the library test folders)."""
    check_declarations(klass())


@pytest.mark.parametrize("name, klass", sorted(exported_classes().items()), ids=sorted(exported_classes()))
def test_every_array_a_class_declares_is_shown_with_its_size(name, klass):
    """``acausal show`` (describe) lists each array once, ``u[3]`` for an instance, ``u[nin]`` or
    ``u[3]`` for the class, and not element by element."""
    from acausal import describe

    instance = klass()
    arrays = type(instance).array_declarations()
    for text in (describe(instance, width=400), describe(klass, width=400)):
        rows = [line.split()[0] for line in text.splitlines() if line.startswith("  ") and line.split()]
        for array, (_, shape) in arrays.items():
            if not all(shape):
                continue  # an empty array (a default size 0) has nothing to show
            assert any(row.startswith(f"{array}[") for row in rows), f"{name}: {array} not shown\n{text}"
            first = f"{array}[{','.join('1' * len(shape))}]"
            assert first not in rows or shape == (1,) * len(shape), f"{name}: {array} listed element by element"


def test_modifiers_are_applied():
    x = attach(Inertia(J=2, w=dict(start=10, fixed=True), stateSelect=StateSelect.always))
    assert x.parameter_binding("J") == 2
    assert x.attribute("w", "start") == 10 and x.attribute("w", "fixed") is True
    assert x.attribute("phi", "state_select") == StateSelect.always
    assert x.attribute("w", "state_select") == StateSelect.always
    assert attach(Inertia()).attribute("phi", "state_select") == StateSelect.default
    assert x.J == sp.Symbol("x.J", real=True)


def test_defaults_from_the_spec():
    assert Inertia.J.default == 1 and Inertia.J.min == 0
    assert Spring.c.default == 1e5 and Damper.d.default == 0
    assert SpringDamper.c.default == 1e5 and SpringDamper.d.default == 0
    assert Clutch.fn_max.default == 1 and Clutch.cgeo.default == 1 and Clutch.peak.default == 1
    assert BearingFriction.tau_pos.default == [[0.0, 1.0]] and BearingFriction.tau_pos.structural
    assert Clutch.mu_pos.default == [[0.0, 0.5]] and Brake.mu_pos.default == [[0.0, 0.5]]
    assert BearingFriction.w_small.default == 1e10 and BearingFriction.K_locked.default == 0
    assert Constant.k.default == 1 and Sine.f.default == 1 and ExpSine.f.default == 2
    assert Ramp.duration.default == 2 and Step.height.default == 1
    assert Sine.continuous.default is False and Sine.continuous.structural
    assert Clutch.phi_nominal.default == 1e-4 and Clutch.stateSelect.default == StateSelect.prefer
    assert PartialFriction.mode.start == Unknown == 3 and PartialFriction.mode.fixed
    assert PartialFriction.mode.min == -1 and PartialFriction.mode.max == 3
    assert PartialFriction.startForward.fixed and PartialFriction.startBackward.fixed
    assert not PartialFriction.locked.fixed
    assert not OneWayClutch.startForward.fixed and not OneWayClutch.stuck.fixed
    assert (Unknown, Free, Forward, Stuck, Backward) == (3, 2, 1, 0, -1)
    assert Inertia.phi.unit == "rad" and Inertia.w.unit == "rad/s" and Inertia.J.unit == "kg.m2"
    assert HeatCapacitor.T.start == 293.15 and HeatCapacitor.C.unit == "J/K"


def test_relative_states_prefer_and_nominal():
    x = attach(Clutch())
    assert x.attribute("phi_rel", "state_select") == StateSelect.prefer
    assert x.attribute("w_rel", "state_select") == StateSelect.prefer
    nominal = x.attribute("phi_rel", "nominal")
    assert value(nominal, {x.phi_nominal: 1e-4}) == 1e-4
    assert value(nominal, {x.phi_nominal: 0.0}) == 1.0


@pytest.mark.parametrize("cls, name", [(Inertia, "Jj"), (Spring, "k"), (Clutch, "fnmax"),
                                       (Sine, "freqHz"), (BearingFriction, "tau_neg")])
def test_unknown_modifier_raises(cls, name):
    with pytest.raises(ModifierError):
        cls(**{name: 1})


def test_modifier_kind_mismatch_raises():
    with pytest.raises(ModifierError):
        Inertia(w=10)  # a variable takes a dict of attributes
    with pytest.raises(ModifierError):
        Inertia(J=dict(start=1))  # a parameter takes a value
    with pytest.raises(ModifierError):
        BearingFriction(flange_a=1)  # connectors take no modifier


# --------------------------------------------------------------------------
# parameter checks


@pytest.mark.parametrize("make, fragment", [
    (lambda: BearingFriction(tau_pos=[]), "empty"),
    (lambda: BearingFriction(tau_pos=[[1, 1], [0, 2]]), "strictly increasing"),
    (lambda: BearingFriction(tau_pos=[[0, 1], [0, 2]]), "strictly increasing"),
    (lambda: BearingFriction(tau_pos=[[-1, 1], [0, 2]]), "w >= 0"),
    (lambda: BearingFriction(tau_pos=[[0, 1, 2]]), "n x 2"),
    (lambda: BearingFriction(tau_pos=[[0, np.nan]]), "non-finite"),
    (lambda: BearingFriction(peak=0.5), "peak"),
    (lambda: Clutch(fn_max=-1), "fn_max"),
    (lambda: Clutch(peak=0.5), "peak"),
    (lambda: Clutch(mu_pos=[[2, 0.5], [1, 0.4]]), "strictly increasing"),
    (lambda: Brake(fn_max=-1), "fn_max"),
    (lambda: Brake(mu_pos=[]), "empty"),
    (lambda: OneWayClutch(fn_max=-0.1), "fn_max"),
    (lambda: OneWayClutch(mu_pos=[0, 0.5]), "n x 2"),
])
def test_parameter_checks(make, fragment):
    component = make()
    with pytest.raises(ParameterError) as info:
        attach(component, "bf1")
    message = str(info.value)
    assert fragment in message
    assert "bf1." in message, "the message names the component path"
    assert "hint:" in message
    assert isinstance(info.value, ValueError)


def test_check_parameters_runs_in_build_and_accepts_valid_values():
    x = BearingFriction(tau_pos=[[0, 0.5], [1, 1]], peak=1)
    x.check_parameters()
    attach(x)
    Clutch(fn_max=0).check_parameters()
    Brake(peak=sp.Symbol("p")).check_parameters()  # expressions are checked when flattening


# --------------------------------------------------------------------------
# conditional connectors


def test_disabled_support_raises_connection_error():
    x = attach(Torque())
    with pytest.raises(ConnectorError):
        x.support.phi
    with pytest.raises(ConnectorError):
        attach(BearingFriction()).support.tau
    with pytest.raises(ConnectorError):
        attach(Damper()).heatPort.Q_flow


def test_support_equations_follow_use_support():
    grounded = attach(IdealGear())
    eqs = collect(grounded)
    assert sp.Eq(grounded.phi_support, 0) in eqs
    assert not any("support." in str(s) for e in eqs for s in e.free_symbols)

    housed = attach(IdealGear(useSupport=True))
    eqs = collect(housed)
    assert sp.Eq(housed.support.phi, housed.phi_support) in eqs
    assert sp.Eq(housed.support.tau, -housed.flange_a.tau - housed.flange_b.tau) in eqs
    assert sp.Eq(housed.phi_support, 0) not in eqs

    torque = attach(Torque(useSupport=True))
    assert sp.Eq(torque.support.tau, -torque.flange.tau) in collect(torque)


def test_heat_port_equation():
    x = attach(BearingFriction(useHeatPort=True))
    eqs = collect(x)
    assert sp.Eq(x.heatPort.Q_flow, -x.lossPower) in eqs
    assert sp.Eq(x.lossPower, x.tau * x.w_relfric) in eqs
    assert sp.Symbol("x.heatPort.T", real=True) == x.heatPort.T


# --------------------------------------------------------------------------
# equation content


def test_inertia_equations():
    x = attach(Inertia())
    eqs = collect(x)
    assert sp.Eq(x.J * x.a, x.flange_a.tau + x.flange_b.tau) in eqs
    assert len(eqs) == 5


def test_bearing_friction_equations_reference_friction_symbols():
    x = attach(BearingFriction())
    names = {s.name for e in collect(x) for s in e.free_symbols}
    for name in ("x.sa", "x.locked", "x.startForward", "x.startBackward", "x.mode", "x.w_relfric",
                 "x.tau0_max", "x.free", "x.w_small", "x.K_locked", "x.peak"):
        assert name in names
    assert rhs_of(x, x.tau0) == sp.Float(1.0)  # tau_pos = [0, 1] at 0
    assert rhs_of(x, x.free) == sp.false


def friction_state(x, *, locked=False, free=False, start_forward=False, start_backward=False,
                   pre_mode=Stuck, initial_=False, pre_start_forward=False, pre_start_backward=False):
    return {x.locked: locked, x.free: free, x.startForward: start_forward,
            x.startBackward: start_backward, pre(x.mode): pre_mode, initial(): initial_,
            pre(x.startForward): pre_start_forward, pre(x.startBackward): pre_start_backward}


def test_friction_a_relfric_branches_in_order():
    x = attach(BearingFriction())
    a = rhs_of(x, x.a_relfric, PartialFriction)
    base = {x.sa: 5.0, x.tau0_max: 2.0, x.w_relfric: -3.0, x.K_locked: 0.0,
            x.unitAngularAcceleration: 1.0, x.unitTorque: 1.0}
    assert value(a, {**base, **friction_state(x, locked=True)}) == 0.0
    assert value(a, {**base, x.K_locked: 4.0, **friction_state(x, locked=True)}) == 12.0
    assert value(a, {**base, **friction_state(x, free=True)}) == 5.0
    assert value(a, {**base, **friction_state(x, start_forward=True, start_backward=True)}) == 3.0
    assert value(a, {**base, **friction_state(x, start_backward=True)}) == 7.0
    assert value(a, {**base, **friction_state(x, pre_mode=Forward)}) == 3.0
    assert value(a, {**base, **friction_state(x, pre_mode=Backward)}) == 7.0
    # the final (v4.1.0) branch: sa - sign(w_relfric)*tau0_max
    assert value(a, {**base, **friction_state(x, pre_mode=Stuck)}) == 7.0
    assert any(isinstance(n, sp.sign) for n in sp.preorder_traversal(a))


def test_friction_start_and_mode_logic():
    x = attach(BearingFriction())
    sf, sb = rhs_of(x, x.startForward), rhs_of(x, x.startBackward)
    locked, mode = rhs_of(x, x.locked), rhs_of(x, x.mode)
    cont = {x.sa: 1.2, x.tau0_max: 1.5, x.tau0: 1.0, x.w_relfric: 0.0, x.w_small: 1e10}
    # hysteresis: sa > tau0 keeps starting only if it was starting
    assert sf.subs({**cont, **friction_state(x, pre_start_forward=True)}) == sp.true
    assert sf.subs({**cont, **friction_state(x)}) == sp.false
    assert sf.subs({**cont, x.sa: 1.6, **friction_state(x)}) == sp.true
    assert sb.subs({**cont, x.sa: -1.6, **friction_state(x)}) == sp.true
    # a strict limit: sa == tau0_max does not start sliding
    assert sf.subs({**cont, x.sa: 1.5, **friction_state(x)}) == sp.false
    # initialization: pre(mode) = Unknown, starts only from the sign of w
    assert sf.subs({**cont, x.w_relfric: 1.0, **friction_state(x, pre_mode=Unknown, initial_=True)}) == sp.true
    assert sb.subs({**cont, x.w_relfric: 1.0, **friction_state(x, pre_mode=Unknown, initial_=True)}) == sp.false
    # locked unless free or sliding/starting
    assert locked.subs(friction_state(x)) == sp.true
    assert locked.subs(friction_state(x, pre_mode=Forward)) == sp.false
    assert locked.subs(friction_state(x, free=True)) == sp.false
    # mode: the waiting phase stays Stuck until w has the sign
    assert value(mode, {x.w_relfric: 0.0, **friction_state(x, start_forward=True)}) == Stuck
    assert value(mode, {x.w_relfric: 1e-9, **friction_state(x, start_forward=True)}) == Forward
    assert value(mode, {x.w_relfric: -1e-9, **friction_state(x, pre_mode=Free)}) == Backward
    assert value(mode, {x.w_relfric: 1.0, **friction_state(x, free=True)}) == Free


def test_sign_selection_clutch_quirk():
    table = [[0, 0.5], [1, 0.3]]  # slope -0.2: table(2) = 0.1, table(-2) = 0.9
    w = 2.0
    bearing = attach(BearingFriction(tau_pos=table), "b")
    brake = attach(Brake(mu_pos=table), "k")
    clutch = attach(Clutch(mu_pos=table), "c")
    backward_b = {bearing.w: w, **friction_state(bearing, start_backward=True)}
    assert value(rhs_of(bearing, bearing.tau), backward_b) == pytest.approx(-0.9)
    assert value(rhs_of(brake, brake.mu), {brake.w_relfric: w, **friction_state(brake, start_backward=True)}) \
        == pytest.approx(-0.9)
    # Clutch: (s1, s2) = (+1, -1) when starting backward (MSL quirk); mu is written in w_relfric (= w_rel)
    assert value(rhs_of(clutch, clutch.mu), {clutch.w_relfric: w, **friction_state(clutch, start_backward=True)}) \
        == pytest.approx(-0.1)
    for x, speed in ((bearing, bearing.w), (clutch, clutch.w_relfric)):
        forward = rhs_of(x, x.tau if x is bearing else x.mu)
        assert value(forward, {speed: w, **friction_state(x, start_forward=True)}) == pytest.approx(0.1)
        assert value(forward, {speed: w, **friction_state(x, pre_mode=Forward)}) == pytest.approx(0.1)
        assert value(forward, {speed: -w, **friction_state(x, pre_mode=Backward)}) == pytest.approx(-0.1)


def test_clutch_torque_and_normal_force():
    x = attach(Clutch(fn_max=160, cgeo=2))
    tau = rhs_of(x, x.tau)
    assert value(tau, {x.sa: 7.0, **friction_state(x, locked=True)}) == 7.0
    assert value(tau, {x.sa: 7.0, **friction_state(x, free=True)}) == 0.0
    assert value(tau, {x.mu: 0.5, x.cgeo: 2, x.fn: 160, **friction_state(x, pre_mode=Forward)}) == 160.0
    assert rhs_of(x, x.free) == (x.fn <= 0)
    assert value(rhs_of(x, x.tau0), {x.cgeo: 2, x.fn: 160}) == 160.0


def test_one_way_clutch_equations():
    x = attach(OneWayClutch(fn_max=1))
    p = {x.fn_max: 1, x.cgeo: 1, x.peak: 1}
    assert value(rhs_of(x, x.tau0_max), {**p, x.free: True, x.tau0: 0}) == pytest.approx(5e-5)
    assert value(rhs_of(x, x.tau0_max), {**p, x.free: False, x.tau0: 10}) == pytest.approx(10 * 1.0001)
    sf = rhs_of(x, x.startForward)
    state = {pre(x.stuck): True, pre(x.startForward): False, initial(): False, x.w_rel: 0.0,
             x.w_small: 1e10, x.tau0: 0.0, x.tau0_max: 5e-5}
    assert sf.subs({**state, x.sa: 6e-5}) == sp.true
    assert sf.subs({**state, x.sa: 4e-5}) == sp.false
    assert rhs_of(x, x.stuck).subs({x.locked: False, x.w_rel: 0.0}) == sp.true
    assert value(rhs_of(x, x.lossPower), {x.stuck: True, x.tau: 3, x.w_rel: 2}) == 0.0


def test_step_ramp_and_sine_values():
    s = attach(Step(height=100, offset=1, startTime=0.5))
    y = rhs_of(s, s.y)
    p = params(s, height=100, offset=1, startTime=0.5)
    assert value(y, {**p, time: 0.4}) == 1.0 and value(y, {**p, time: 0.5}) == 101.0

    r = attach(Ramp(height=5, duration=2, offset=-10, startTime=1))
    y = rhs_of(r, r.y)
    p = params(r, height=5, duration=2, offset=-10, startTime=1)
    assert [value(y, {**p, time: t}) for t in (0.5, 2.0, 4.0)] == [-10.0, -7.5, -5.0]

    for cls, g in ((Sine, np.sin), (Cosine, np.cos)):
        plain = attach(cls())
        cont = attach(cls(continuous=True))
        p = dict(amplitude=2, f=5, phase=0.3, offset=1, startTime=0.5)
        before, after = 0.25, 0.6
        assert value(rhs_of(plain, plain.y), {**params(plain, **p), time: before}) == 1.0
        assert value(rhs_of(cont, cont.y), {**params(cont, **p), time: before}) == pytest.approx(1 + 2 * g(0.3))
        expected = 1 + 2 * g(2 * np.pi * 5 * (after - 0.5) + 0.3)
        assert value(rhs_of(plain, plain.y), {**params(plain, **p), time: after}) == pytest.approx(expected)
        assert value(rhs_of(cont, cont.y), {**params(cont, **p), time: after}) == pytest.approx(expected)

    e = attach(ExpSine())
    p = params(e, amplitude=1, f=2, phase=0, damping=1, offset=0, startTime=0)
    assert value(rhs_of(e, e.y), {**p, time: 0.1}) == pytest.approx(np.exp(-0.1) * np.sin(0.4 * np.pi))


def test_thermal_and_math_equations():
    c = attach(Celsius.TemperatureSensor())
    assert value(rhs_of(c, c.T), {c.port.T: 298.15}) == pytest.approx(25.0)
    f = attach(Celsius.FixedTemperature(T=25))
    assert sp.Eq(f.port.T, f.T + 273.15) in collect(f)
    h = attach(PrescribedHeatFlow())
    assert value(rhs_of(h, h.port.Q_flow), {h.Q_flow: 10, h.alpha: 0, h.port.T: 300, h.T_ref: 293.15}) == -10
    a = attach(Add())
    assert value(rhs_of(a, a.y), {a.k1: 1, a.k2: -2, a.u1: 3, a.u2: 1}) == 1
    fb = attach(Feedback())
    assert rhs_of(fb, fb.y) == fb.u1 - fb.u2


def test_equations_are_deterministic():
    """Building twice gives equal equations (the table classes are cached by name and table)."""
    x = attach(Clutch(mu_pos=[[0, 0.5], [1, 0.4]]))
    assert collect(x) == collect(x)


def test_table_named_after_component_path():
    m = Model()
    m.drive = Model()
    m.drive.bf = BearingFriction(tau_pos=[[0, 1], [1, 2]])
    m.drive.bf.ensure_built()
    tables = {f.func.__name__ for e in collect(m.drive.bf) for f in e.atoms(sp.Function)
              if hasattr(f.func, "table")}
    assert tables == {"drive_bf_tau_pos"}


# --------------------------------------------------------------------------
# table functions


def test_table_interpolation_and_extrapolation():
    T = table_function("T", [[0, 1], [1, 3]])
    assert float(T(2)) == 5 and float(T(-1)) == -1 and float(T(0.5)) == 2
    assert isinstance(T(0), sp.Float) and float(T(0)) == 1
    assert T.numeric(2.0) == 5.0 and T._imp_(-1.0) == -1.0
    np.testing.assert_allclose(T.evaluate([-1, 0, 0.5, 1, 2]), [-1, 1, 2, 3, 5])


def test_table_several_segments():
    T = table_function("multi", [[0, 0], [1, 2], [3, 3]])
    for x, y in [(-1, -2), (0, 0), (0.5, 1), (1, 2), (2, 2.5), (3, 3), (5, 4)]:
        assert T.numeric(x) == pytest.approx(y)
        assert float(T(x)) == pytest.approx(y)
    np.testing.assert_allclose(T.evaluate(np.array([[-1, 0.5], [2, 5]])), [[-2, 1], [2.5, 4]])
    assert T.numeric(3.0) == 3.0  # exact at the last breakpoint


def test_table_one_row_is_constant():
    T = table_function("const", [[0, 2.5]])
    w = sp.Symbol("w", real=True)
    assert T(w) == sp.Float(2.5) and float(T(-100)) == 2.5 and T.numeric(7.0) == 2.5
    np.testing.assert_allclose(T.evaluate([-1, 0, 1]), [2.5, 2.5, 2.5])


def test_table_derivative():
    w = sp.Symbol("w", real=True)
    T = table_function("d", [[0, 0], [1, 2], [3, 3]])
    dT = sp.diff(T(w), w)
    slope = dT.func
    assert slope is not T and slope.__name__ == "d_slope"
    # piecewise constant, the right segment's slope at a breakpoint
    for x, s in [(-1, 2), (0, 2), (0.5, 2), (1, 0.5), (2, 0.5), (3, 0.5), (9, 0.5)]:
        assert float(dT.subs(w, x)) == pytest.approx(s)
        assert slope.numeric(x) == pytest.approx(s)
    assert sp.diff(T(w), w, 2) == 0
    assert sp.diff(table_function("two", [[0, 1], [2, 2]])(w), w) == sp.Float(0.5)
    # chain rule through a sign: d/dw T(-w) = -T'(-w)
    assert float(sp.diff(T(-w), w).subs(w, -0.5)) == -2


def test_table_lambdify_uses_the_implementation():
    w = sp.Symbol("w", real=True)
    T = table_function("lam", [[0, 1], [1, 3]])
    f = sp.lambdify(w, 2 * T(w) + sp.diff(T(w), w))
    assert f(0.5) == pytest.approx(6.0)
    np.testing.assert_allclose(f(np.array([0.0, 2.0])), [4.0, 12.0])


def test_table_names_and_caching():
    a = table_function("clutch1.mu_pos", [[0, 0.5]])
    assert a.__name__ == "clutch1_mu_pos"
    assert table_function("clutch1.mu_pos", [[0, 0.5]]) is a
    assert table_function("clutch1.mu_pos", [[0, 0.6]]) is not a
    assert table_function("1 bad-name", [[0, 1]]).__name__.isidentifier()
    assert issubclass(a, sp.Function) and a.nargs == {1}


@pytest.mark.parametrize("table, fragment", [
    ([], "empty"), (np.zeros((0, 2)), "empty"), ([[0, 1, 2]], "n x 2"), ([1, 2], "n x 2"),
    ([[0, 1], [0, 2]], "strictly increasing"), ([[1, 1], [0, 2]], "strictly increasing"),
    ([[0, np.inf]], "non-finite"), ([[np.nan, 1]], "non-finite"), ([["a", 1]], "numeric"),
])
def test_table_validation(table, fragment):
    with pytest.raises(ParameterError) as info:
        table_function("bad", table)
    assert fragment in str(info.value)
    with pytest.raises(ValueError):
        validate_table(table)


def test_integrator_matches_closed_form():
    """Integrator: y = y_start + k*∫u; for u = 2 sin(2πt) that is 1 + 3·2(1 - cos 2πt)/(2π)."""
    import math

    import numpy as np

    from acausal import Model, simulate
    from acausal.library.blocks import Integrator, Sine

    class Integrate(Model):
        def build(self):
            self.sine = Sine(amplitude=2, f=1)
            self.integrator = Integrator(k=3, y_start=1)
            self.connect(self.sine.y, self.integrator.u)

    result = simulate(Integrate(), rtol=1e-10)
    t = result.time
    exact = 1 + 3 * 2 * (1 - np.cos(2 * math.pi * t)) / (2 * math.pi)
    assert np.max(np.abs(result["integrator.y"] - exact)) < 1e-7
