"""Property-based fuzzing of random rotational drive trains (hypothesis).

Each example is a row of 1 to 5 inertias (J in [0.01, 10]) joined by random
couplings -- Clutch (table ``mu_pos`` of one or two rows, ``peak`` in
[1, 1.5], ``f_normalized`` from a Constant or a Step), SpringDamper (c in
[10, 1e4], d in [0, 10]), Spring, Damper -- with, on each inertia, nothing,
a BearingFriction (``tau_pos`` one or two rows, positive and increasing,
``peak`` in [1, 1.5]) or a Brake; one or two Torque sources fed by a Sine or
a Step act on random inertias.  Every inertia has fixed starts ``phi = 0``
and ``w`` in [-5, 5]; no two inertias are rigidly joined (couplings are
compliant or clutches), so these starts are consistent.  The integrator is
drawn too (DOP853 or RK45).

For the energy audit every dissipative element (BearingFriction, Brake,
Clutch, Damper, SpringDamper) has ``useHeatPort=True`` and its heat port on
a HeatCapacitor of its own (C = 1 J/K, T fixed at 0 K, see ``T_START``), so all the
energy it dissipates is ``C*(T_end - T_start)``; each source drives its
inertia through a test-local :class:`PowerMeter` that integrates, inside
the model, the power it delivers: ``der(W) = tau*w``.

Properties checked for every drawn model (stop time 1 s, rtol 1e-8):

* the run completes (status 0) or fails with one of the project's
  documented errors (``result.error`` is an ``AcausalError``, or
  ``simulate`` raises one for a model it rejects), never another exception;
* no NaN in any column;
* at every output row that is not an event instant, each friction element's
  mode agrees with its relative speed: mode 1 (forward) needs
  ``w_relfric >= -tol``, mode -1 (backward) ``w_relfric <= tol``, mode 0
  (stuck) ``|w_relfric| <= tol``, ``tol = 1e-6*(1 + max|w|)``; and a locked
  element holds with ``|sa| <= tau0_max`` (exceeding it starts sliding);
* energy audit at the end of a completed run::

      |W - dE_kin - dE_spring - sum C*dT| <= tol * max(1 J, |W|, E_kin(0), E_kin(end), E_spring(end), heat)

  with tol = 1e-5 (see ``ENERGY_TOL``: the integration error at rtol 1e-8
  reaches a few 1e-6).  The scale is the energy that moved, not only
  ``|W|``: initial speeds bring up to 125 J per inertia that friction turns
  into heat, and the integration error is relative to that.

When a property fails hypothesis prints the drawn spec, a readable summary
of the model, the result's summary and last events and the energy terms
(``note``), then shrinks to a small failing model.

Number of examples
------------------
The default is 15 examples, drawn deterministically (``derandomize=True``)
so CI always runs the same models (about 20 s of CPU).  For a long
exploratory run set the environment variable ``ACAUSAL_FUZZ_EXAMPLES``::

    ACAUSAL_FUZZ_EXAMPLES=500 python -m pytest tests/hard_cases/test_fuzz.py -q

Any value other than the default also switches derandomization off (each
long run explores other models) and turns hypothesis' example database on
(``.hypothesis/``, git-ignored), so a failure found is replayed first on the
next run.

Engine bugs found by this fuzzing have minimal reproductions at the end of
the file: fixed ones guard the fix, open ones are strict xfail tests.
``AVOID_STEP_TO_EXACT_ZERO`` kept the random models clear of a step to
exactly zero (a parameter combination that vanished broke the generated
code); that is fixed and the switch is off.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field

import numpy as np
import pytest
from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st

from acausal import Boolean, Component, Eq, Model, Parameter, Variable, der, simulate, time
from acausal.errors import AcausalError
from acausal.components.rotational import Flange_a, Flange_b
from acausal.library.blocks import Constant, Sine, Step
from acausal.library.rotational import (BearingFriction, Brake, Clutch, Damper, Inertia, Spring, SpringDamper,
                                Torque)
from acausal.library.thermal import HeatCapacitor

DEFAULT_EXAMPLES = 15
EXAMPLES = int(os.environ.get("ACAUSAL_FUZZ_EXAMPLES", DEFAULT_EXAMPLES))
LONG_RUN = EXAMPLES != DEFAULT_EXAMPLES

STOP_TIME = 1.0
INTERVAL = 0.01
RTOL = 1e-8
#: Start temperature of the heat capacitors.  The integrator controls each state's
#: error relative to its size, so at 293.15 K the heat C*dT would be resolved only
#: to about rtol*293 J per step (an energy imbalance of 6e-6 of the energy moved
#: after 570 events, measured); starting at 0 K the error is relative to the heat.
T_START = 0.0
CAPACITY = 1.0
#: Integrators drawn, with the energy-audit tolerance (relative to the energy that
#: moved).  Measured at rtol 1e-8 over 300 random drive trains each, the largest
#: imbalances were 1.8e-6 (DOP853) and 2.6e-6 (RK45) -- stiff spring chains
#: (c = 1e4 on J = 0.01 oscillates 160 times a second) and runs with hundreds of
#: friction events -- and they shrink in proportion to rtol (1e-10 gives 1e-9):
#: integration error, not a leak.  A missing term is off by far more (see
#: test_energy_audit_detects_a_missing_term).
ENERGY_TOL = {"DOP853": 1e-5, "RK45": 1e-5}


# --------------------------------------------------------------------------
# the measuring component


class PowerMeter(Component):
    """Rigid, massless flange pair measuring the power passing from flange_a to flange_b.

    ``power = flange_a.tau*w`` and ``der(W) = power`` from ``W(0) = 0``, so
    ``W`` is the work delivered through the meter, integrated with the model.
    """

    flange_a = Flange_a()
    flange_b = Flange_b()
    w = Variable(unit="rad/s", description="speed of both flanges")
    power = Variable(unit="W", description="power flowing from flange_a to flange_b")
    W = Variable(start=0.0, fixed=True, unit="J", description="work delivered so far")

    def equations(self):
        return [
            Eq(self.flange_a.phi, self.flange_b.phi),
            Eq(self.flange_a.tau + self.flange_b.tau, 0),
            Eq(self.w, der(self.flange_a.phi)),
            Eq(self.power, self.flange_a.tau * self.w),
            Eq(der(self.W), self.power),
        ]


# --------------------------------------------------------------------------
# the drawn specification


@dataclass(frozen=True)
class Signal:
    kind: str  # "Constant", "Step" or "Sine"
    params: tuple  # (name, value) pairs for the block

    def block(self):
        cls = {"Constant": Constant, "Step": Step, "Sine": Sine}[self.kind]
        return cls(**dict(self.params))

    def __str__(self):
        return f"{self.kind}({', '.join(f'{k}={v:.6g}' for k, v in self.params)})"


@dataclass(frozen=True)
class Coupling:
    kind: str  # "Clutch", "SpringDamper", "Spring", "Damper"
    params: tuple  # (name, value) pairs
    signal: Signal | None = None  # f_normalized of a Clutch

    def __str__(self):
        text = ", ".join(f"{k}={_fmt(v)}" for k, v in self.params)
        if self.signal is not None:
            text += f", f_normalized={self.signal}"
        return f"{self.kind}({text})"


@dataclass(frozen=True)
class Bearing:
    tau_pos: tuple  # rows (w, tau)
    peak: float

    def __str__(self):
        return f"BearingFriction(tau_pos={_fmt(self.tau_pos)}, peak={self.peak:.6g})"


@dataclass(frozen=True)
class BrakeSpec:
    fn_max: float
    mu_pos: tuple  # rows (w, mu)
    peak: float
    signal: Signal  # f_normalized

    def __str__(self):
        return (f"Brake(fn_max={self.fn_max:.6g}, mu_pos={_fmt(self.mu_pos)}, peak={self.peak:.6g}, "
                f"f_normalized={self.signal})")


@dataclass(frozen=True)
class Source:
    inertia: int
    signal: Signal

    def __str__(self):
        return f"Torque on inertia{self.inertia + 1} from {self.signal}"


@dataclass(frozen=True)
class Spec:
    J: tuple
    w0: tuple
    couplings: tuple  # len(J) - 1
    bearings: tuple  # Bearing, BrakeSpec or None per inertia
    sources: tuple  # 1 or 2 Source

    def describe(self) -> str:
        lines = []
        for i, (J, w0) in enumerate(zip(self.J, self.w0)):
            line = f"inertia{i + 1}: J={J:.6g}, w(0)={w0:.6g}"
            if self.bearings[i] is not None:
                line += f", {self.bearings[i]}"
            lines.append(line)
            if i < len(self.couplings):
                lines.append(f"  coupling{i + 1}: {self.couplings[i]}")
        lines += [str(s) for s in self.sources]
        return "\n".join(lines)


def _fmt(value):
    if isinstance(value, tuple):
        return "[" + ", ".join(_fmt(v) for v in value) + "]"
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


# --------------------------------------------------------------------------
# strategies

def _floats(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


@st.composite
def friction_table(draw, lo, hi):
    """One row [[0, y0]] or two rows [[0, y0], [w1, y1]] with y1 >= y0 (positive, increasing)."""
    y0 = draw(_floats(lo, hi))
    if draw(st.booleans()):
        return ((0.0, y0),)
    w1 = draw(_floats(0.5, 20.0))
    y1 = y0 * draw(_floats(1.0, 2.0))
    return ((0.0, y0), (w1, y1))


#: Engine bug (see test_parameter_sum_cancelling_to_zero_in_generated_code): a
#: Step whose offset + height is exactly 0 (a torque or clutch force stepping
#: to zero) makes the incidence analysis drop the unknown that this zero
#: coefficient multiplies in the power meter, and the generated code reads it
#: before assigning it (UnboundLocalError).  While that bug stands, such a
#: step ends at a small negative value instead (for a clutch force still
#: "disengaged"); set to False once the regression test passes.
AVOID_STEP_TO_EXACT_ZERO = False  # the engine bug it avoided is fixed; kept as a switch


@st.composite
def step_signal(draw, lo, hi):
    """A Step whose offset and offset + height both lie in [lo, hi], starting inside the run."""
    a = draw(_floats(lo, hi))
    b = draw(_floats(lo, hi))
    if AVOID_STEP_TO_EXACT_ZERO and abs(b) < 1e-6:
        b = -1e-3 * (hi - lo)
    start = draw(_floats(0.05, 0.95))
    return Signal("Step", (("offset", a), ("height", b - a), ("startTime", start)))


clutch_force = st.one_of(
    _floats(0.0, 1.0).map(lambda k: Signal("Constant", (("k", k),))),
    step_signal(0.0, 1.0),
)

torque_signal = st.one_of(
    st.tuples(_floats(0.1, 20.0), _floats(0.2, 5.0), _floats(-math.pi, math.pi)).map(
        lambda p: Signal("Sine", (("amplitude", p[0]), ("f", p[1]), ("phase", p[2])))),
    step_signal(-10.0, 10.0),
)


@st.composite
def coupling(draw):
    kind = draw(st.sampled_from(["Clutch", "SpringDamper", "Spring", "Damper"]))
    if kind == "Clutch":
        mu = draw(friction_table(0.1, 1.0))
        params = (("fn_max", draw(_floats(0.1, 50.0))), ("mu_pos", mu), ("peak", draw(_floats(1.0, 1.5))))
        return Coupling(kind, params, draw(clutch_force))
    if kind == "SpringDamper":
        return Coupling(kind, (("c", draw(_floats(10.0, 1e4))), ("d", draw(_floats(0.0, 10.0)))))
    if kind == "Spring":
        return Coupling(kind, (("c", draw(_floats(10.0, 1e4))),))
    return Coupling(kind, (("d", draw(_floats(0.0, 10.0))),))


bearing = st.builds(Bearing, friction_table(0.05, 5.0), _floats(1.0, 1.5))
brake = st.builds(BrakeSpec, _floats(0.1, 20.0), friction_table(0.1, 1.0), _floats(1.0, 1.5), clutch_force)


@st.composite
def drive_train(draw):
    n = draw(st.integers(1, 5))
    J = tuple(draw(st.lists(_floats(0.01, 10.0), min_size=n, max_size=n)))
    w0 = tuple(draw(st.lists(_floats(-5.0, 5.0), min_size=n, max_size=n)))
    couplings = tuple(draw(st.lists(coupling(), min_size=n - 1, max_size=n - 1)))
    bearings = tuple(draw(st.lists(st.one_of(st.none(), bearing, brake), min_size=n, max_size=n)))
    sources = tuple(draw(st.lists(st.builds(Source, st.integers(0, n - 1), torque_signal),
                                  min_size=1, max_size=2)))
    return Spec(J, w0, couplings, bearings, sources)


# --------------------------------------------------------------------------
# the model built from a spec


@dataclass
class Audit:
    """Names the checks need, filled while the model is built."""

    inertias: list = field(default_factory=list)  # (name, J)
    springs: list = field(default_factory=list)  # (name of phi_rel, c)
    capacitors: list = field(default_factory=list)  # names of the heat capacitors
    friction: list = field(default_factory=list)  # names of the friction elements
    meters: list = field(default_factory=list)  # names of the power meters


def model_class(spec: Spec):
    """A Model subclass whose build() creates the drive train of ``spec``; and its Audit."""
    audit = Audit()

    class FuzzDriveTrain(Model):
        def build(self):
            def heat_sink(element_name, element):
                cap = f"{element_name}_heat"
                setattr(self, cap, HeatCapacitor(C=CAPACITY, T=dict(start=T_START, fixed=True)))
                self.connect(element.heatPort, getattr(self, cap).port)
                audit.capacitors.append(cap)

            inertias = []
            for i, (J, w0) in enumerate(zip(spec.J, spec.w0)):
                name = f"inertia{i + 1}"
                inertia = Inertia(J=J, phi=dict(start=0.0, fixed=True), w=dict(start=w0, fixed=True))
                setattr(self, name, inertia)
                inertias.append(inertia)
                audit.inertias.append((name, J))
                b = spec.bearings[i]
                if isinstance(b, Bearing):
                    bname = f"bearing{i + 1}"
                    friction = BearingFriction(tau_pos=[list(r) for r in b.tau_pos], peak=b.peak,
                                               useHeatPort=True)
                    setattr(self, bname, friction)
                elif isinstance(b, BrakeSpec):
                    bname = f"brake{i + 1}"
                    friction = Brake(fn_max=b.fn_max, mu_pos=[list(r) for r in b.mu_pos], peak=b.peak,
                                     useHeatPort=True)
                    setattr(self, bname, friction)
                    setattr(self, f"{bname}_force", b.signal.block())
                    self.connect(getattr(self, f"{bname}_force").y, friction.f_normalized)
                if b is not None:
                    self.connect(inertia.flange_b, friction.flange_a)
                    audit.friction.append(bname)
                    heat_sink(bname, friction)
            for i, c in enumerate(spec.couplings):
                name = f"coupling{i + 1}"
                params = dict(c.params)
                if c.kind == "Clutch":
                    params["mu_pos"] = [list(r) for r in params["mu_pos"]]
                    element = Clutch(useHeatPort=True, **params)
                    audit.friction.append(name)
                elif c.kind == "SpringDamper":
                    element = SpringDamper(useHeatPort=True, **params)
                    audit.springs.append((f"{name}.phi_rel", params["c"]))
                elif c.kind == "Spring":
                    element = Spring(**params)
                    audit.springs.append((f"{name}.phi_rel", params["c"]))
                else:
                    element = Damper(useHeatPort=True, **params)
                setattr(self, name, element)
                self.connect(inertias[i].flange_b, element.flange_a)
                self.connect(element.flange_b, inertias[i + 1].flange_a)
                if c.kind != "Spring":
                    heat_sink(name, element)
                if c.signal is not None:
                    setattr(self, f"{name}_force", c.signal.block())
                    self.connect(getattr(self, f"{name}_force").y, element.f_normalized)
            for k, s in enumerate(spec.sources):
                signal, torque, meter = f"signal{k + 1}", f"torque{k + 1}", f"meter{k + 1}"
                setattr(self, signal, s.signal.block())
                setattr(self, torque, Torque())
                setattr(self, meter, PowerMeter())
                self.connect(getattr(self, signal).y, getattr(self, torque).tau)
                self.connect(getattr(self, torque).flange, getattr(self, meter).flange_a)
                self.connect(getattr(self, meter).flange_b, inertias[s.inertia].flange_a)
                audit.meters.append(meter)

    return FuzzDriveTrain, audit


# --------------------------------------------------------------------------
# the checks


def event_rows(result) -> np.ndarray:
    """True at the rows whose time is an event instant (left or right limit)."""
    times = np.array(sorted({e.time for e in result.events}))
    if times.size == 0:
        return np.zeros(result.time.shape, dtype=bool)
    return np.isin(result.time, times)


def check_no_nan(result) -> None:
    bad = [n for n, v in result.columns.items() if np.any(np.isnan(np.asarray(v, dtype=float)))]
    assert not bad, f"NaN in {len(bad)} columns, e.g. {bad[:5]}"


def check_modes(result, audit: Audit) -> None:
    """Friction modes agree with the relative speeds; locked elements hold within their limit."""
    w_max = max(np.max(np.abs(result[f"{name}.w"])) for name, _ in audit.inertias)
    tol = 1e-6 * (1 + w_max)
    between = ~event_rows(result)
    for name in audit.friction:
        mode = result[f"{name}.mode"][between]
        w = result[f"{name}.w_relfric"][between]
        t = result.time[between]
        for value, bad, what in ((1, w < -tol, "forward with w_relfric < 0"),
                                 (-1, w > tol, "backward with w_relfric > 0"),
                                 (0, np.abs(w) > tol, "stuck with w_relfric != 0")):
            wrong = (mode == value) & bad
            if np.any(wrong):
                k = int(np.argmax(wrong))
                raise AssertionError(f"{name}: {what} at {int(np.sum(wrong))} rows, first at "
                                     f"t = {t[k]:.9g} (w_relfric = {w[k]:.3g}, tol {tol:.3g})")
        # while locked the element holds with the torque sa, which cannot exceed the static
        # limit tau0_max: crossing it is the event that starts sliding
        locked = result[f"{name}.locked"][between] == 1
        sa = result[f"{name}.sa"][between]
        limit = result[f"{name}.tau0_max"][between]
        over = locked & (np.abs(sa) > limit + 1e-6 * (1 + np.abs(limit)))
        if np.any(over):
            k = int(np.argmax(over))
            raise AssertionError(f"{name}: locked with |sa| = {abs(sa[k]):.9g} above tau0_max = "
                                 f"{limit[k]:.9g} at {int(np.sum(over))} rows, first at t = {t[k]:.9g}")


def energy_terms(result, audit: Audit) -> dict:
    """Work of the sources and where it went, at the end of the run (J)."""
    def kinetic(row):
        return sum(0.5 * J * result[f"{n}.w"][row] ** 2 for n, J in audit.inertias)

    def spring(row):
        return sum(0.5 * c * result[p][row] ** 2 for p, c in audit.springs)

    terms = dict(
        work=sum(result[f"{m}.W"][-1] for m in audit.meters),
        kinetic=kinetic(-1) - kinetic(0),
        spring=spring(-1) - spring(0),
        heat=sum(CAPACITY * (result[f"{cap}.T"][-1] - T_START) for cap in audit.capacitors),
    )
    terms["imbalance"] = terms["work"] - terms["kinetic"] - terms["spring"] - terms["heat"]
    # the energy that moved: the initial speeds carry up to 125 J per inertia
    # into the heat capacitors, so that is the scale of the integration error
    terms["scale"] = max(1.0, abs(terms["work"]), kinetic(0), kinetic(-1), spring(-1), terms["heat"])
    return terms


def _note(text: str) -> None:
    """hypothesis' note inside a property, nothing elsewhere."""
    try:
        note(text)
    except Exception:  # noqa: BLE001 - outside a hypothesis test
        pass


def check_energy(result, audit: Audit, tol: float = 1e-6) -> None:
    """|W - dE_kin - dE_spring - sum C*dT| <= tol * (the energy that moved, at least 1 J)."""
    e = energy_terms(result, audit)
    _note("energy: " + ", ".join(f"{k}={v:.12g}" for k, v in e.items()))
    assert abs(e["imbalance"]) <= tol * e["scale"], (
        f"energy audit: work {e['work']:.12g} J != kinetic {e['kinetic']:.12g} + spring "
        f"{e['spring']:.12g} + heat {e['heat']:.12g} (imbalance {e['imbalance']:.3g} J, "
        f"{abs(e['imbalance']) / e['scale']:.3g} of the {e['scale']:.6g} J that moved)")


def run_spec(spec: Spec, method: str = "DOP853"):
    """Simulate the model of ``spec``; (result or None, audit).  Only AcausalErrors may escape."""
    cls, audit = model_class(spec)
    try:
        result = simulate(cls(), stop_time=STOP_TIME, interval=INTERVAL, rtol=RTOL, method=method)
    except AcausalError as exc:  # a documented error for a bad model
        _note(f"simulate raised {type(exc).__name__}: {exc}")
        return None, audit
    return result, audit


@settings(max_examples=EXAMPLES, deadline=None, derandomize=not LONG_RUN,
          **({} if LONG_RUN else {"database": None}), report_multiple_bugs=False,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(spec=drive_train(), method=st.sampled_from(sorted(ENERGY_TOL)))
def test_random_drive_train(spec, method):
    """Random drive trains complete or fail with a documented error; NaN-free, consistent modes, energy kept."""
    note(spec.describe())
    result, audit = run_spec(spec, method)
    if result is None:  # simulate raised an AcausalError: a model the engine rejects
        return
    note(result.summary())
    for event in result.events[-5:]:
        note(f"last events: {event}")
    assert result.status in (0, -1)
    if result.status != 0:
        assert isinstance(result.error, AcausalError), repr(result.error)
        assert result.message
    else:
        assert result.error is None
        assert result.time[-1] == pytest.approx(STOP_TIME)
    assert result.time.size >= 1
    check_no_nan(result)
    check_modes(result, audit)
    if result.status == 0:
        check_energy(result, audit, ENERGY_TOL[method])


# --------------------------------------------------------------------------
# hand-picked drive trains: the checks themselves are exercised on known cases


HAND_PICKED = {
    "bearing_heating_like": Spec(
        J=(0.2,), w0=(0.0,), couplings=(),
        bearings=(Bearing(((0.0, 1.0), (10.0, 1.5)), 1.2),),
        sources=(Source(0, Signal("Sine", (("amplitude", 5.0), ("f", 0.5), ("phase", 0.0)))),)),
    "clutch_engages": Spec(
        J=(1.0, 2.0), w0=(5.0, -1.0),
        couplings=(Coupling("Clutch", (("fn_max", 20.0), ("mu_pos", ((0.0, 0.5),)), ("peak", 1.1)),
                            Signal("Step", (("offset", 0.0), ("height", 1.0), ("startTime", 0.2)))),),
        bearings=(None, Bearing(((0.0, 0.5),), 1.0)),
        sources=(Source(0, Signal("Step", (("offset", 1.0), ("height", -2.0), ("startTime", 0.6)))),)),
    "spring_chain": Spec(
        J=(0.5, 1.0, 0.1), w0=(1.0, 0.0, -2.0),
        couplings=(Coupling("SpringDamper", (("c", 1000.0), ("d", 2.0))),
                   Coupling("Spring", (("c", 50.0),))),
        bearings=(None, None, Bearing(((0.0, 0.2), (5.0, 0.3)), 1.3)),
        sources=(Source(1, Signal("Sine", (("amplitude", 3.0), ("f", 2.0), ("phase", 0.5)))),
                 Source(2, Signal("Sine", (("amplitude", 1.0), ("f", 1.0), ("phase", 0.0)))))),
}


@pytest.mark.parametrize("name", sorted(HAND_PICKED))
def test_hand_picked_drive_train(name):
    """Known drive trains complete and pass every check (so the fuzz checks are not vacuous)."""
    spec = HAND_PICKED[name]
    result, audit = run_spec(spec)
    assert result is not None and result.status == 0, result and result.message
    check_no_nan(result)
    check_modes(result, audit)
    check_energy(result, audit)
    e = energy_terms(result, audit)
    assert abs(e["work"]) > 0.01 and e["heat"] > 0.0  # the audit measured something


def test_energy_audit_detects_a_missing_term():
    """The audit is sharp: leaving one heat capacitor out of the sum breaks the balance."""
    result, audit = run_spec(HAND_PICKED["clutch_engages"])
    assert result.status == 0
    audit.capacitors = audit.capacitors[1:]
    with pytest.raises(AssertionError, match="energy audit"):
        check_energy(result, audit)


# --------------------------------------------------------------------------
# engine bugs the fuzzing found (minimal reproductions)


class CancellingCoefficient(Model):
    """P = (a + b)*u with a = 1, b = -1: a coefficient that is zero only numerically.

    The first two equations come first so that the sorting has no other
    reason to compute ``u`` before ``P``.
    """

    a = Parameter(1.0)
    b = Parameter(-1.0)
    x = Variable(start=0.0, fixed=True)
    u = Variable()
    P = Variable()
    W = Variable(start=0.0, fixed=True)

    def equations(self):
        return [Eq(self.P, (self.a + self.b) * self.u), Eq(der(self.W), self.P),
                Eq(der(self.x), 1), Eq(self.u, 2 * self.x)]


def test_parameter_sum_cancelling_to_zero_in_generated_code():
    """A coefficient a + b that is numerically 0 must not break the generated code."""
    result = simulate(CancellingCoefficient(), stop_time=1.0, interval=0.1)
    assert result.status == 0, result.message
    np.testing.assert_allclose(result["W"], 0.0, atol=1e-12)
    np.testing.assert_allclose(result["u"], 2 * result.time, atol=1e-9)


def test_torque_step_to_zero_through_power_meter():
    """The drive train that found the bug: one inertia, a torque stepping from 1 N.m to 0 at t = 0.5."""
    spec = Spec(J=(1.0,), w0=(0.0,), couplings=(), bearings=(None,),
                sources=(Source(0, Signal("Step", (("offset", 1.0), ("height", -1.0),
                                                   ("startTime", 0.5)))),))
    result, audit = run_spec(spec)
    assert result is not None and result.status == 0, result and result.message
    # w = t until 0.5, then constant: W = 1/2*J*w^2 = 0.125
    assert result.final("inertia1.w") == pytest.approx(0.5, abs=1e-9)
    assert result.final("meter1.W") == pytest.approx(0.125, abs=1e-9)
    check_energy(result, audit)


class Dip(Model):
    """x = (t - 0.5)^2 - 1e-6 is negative only for |t - 0.5| < 1e-3; neg = x < 0."""

    x = Variable(start=0.25 - 1e-6, fixed=True)
    neg = Boolean()

    def equations(self):
        return [Eq(der(self.x), 2 * (time - 0.5)), Eq(self.neg, self.x < 0)]


# Fixed: output-grid points inside a step are crossing samples too (an excursion
# spanning an output point is always found; a shorter one between output points
# is a documented limitation, docs/hard-cases.md).
@pytest.mark.parametrize("method", ["DOP853", "Radau"])
def test_short_sign_excursion_inside_one_step_is_an_event(method):
    """x dips below 0 for 2 ms: two state events, and neg is true at the row t = 0.5."""
    result = simulate(Dip(), stop_time=1.0, interval=0.1, method=method, rtol=1e-8)
    assert result.status == 0
    row = int(np.argmin(np.abs(result.time - 0.5)))
    assert result["x"][row] < 0
    assert result["neg"][row] == 1
    times = [e.time for e in result.events if e.kind == "state"]
    assert len(times) == 2
    assert times[0] == pytest.approx(0.499, abs=1e-6) and times[1] == pytest.approx(0.501, abs=1e-6)


#: The drawn drive train where the fuzzing found the missed excursion (rounded
#: values reproduce it): brake2 should stick on (0.70958, 0.71061), but one
#: DOP853 step of 17 ms covers that millisecond.
BRAKE_STICK_STEPPED_OVER = Spec(
    J=(2.2094112333283733, 0.14179053121967658, 7.497303540127568),
    w0=(0.41869180704317976, 0.0, 1.3201229316465266),
    couplings=(Coupling("Clutch", (("fn_max", 2.00001), ("mu_pos", ((0.0, 0.15736510435713008),
                                                                     (12.411408152293776, 0.31473020871426016))),
                                   ("peak", 1.3597040528807338)), Signal("Constant", (("k", 0.5),))),
               Coupling("Spring", (("c", 273.15),))),
    bearings=(BrakeSpec(2.00001, ((0.0, 0.2887491974734266),), 1.4133057192821639,
                        Signal("Constant", (("k", 1e-08),))),
              BrakeSpec(7.040387919993659, ((0.0, 0.88077969113368),), 1.1728329925058778,
                        Signal("Constant", (("k", 0.04144093905624469),))),
              None),
    sources=(Source(2, Signal("Step", (("offset", 0.0), ("height", -2.627759682107408),
                                       ("startTime", 0.06353322029977176)))),
             Source(0, Signal("Step", (("offset", 8.134878626109376), ("height", -11.792084166233128),
                                       ("startTime", 0.08025237019190848))))))


# Fixed: output-grid points inside a step are crossing samples too (an excursion
# spanning an output point is always found; a shorter one between output points
# is a documented limitation, docs/hard-cases.md).
def test_brake_stick_phase_not_stepped_over():
    """The fuzz-found drive train: brake2 sticks near t = 0.7096 and slides again at 0.7106."""
    result, audit = run_spec(BRAKE_STICK_STEPPED_OVER, "DOP853")
    assert result.status == 0, result.message
    check_modes(result, audit)
    stuck = [e.time for e in result.events if ("brake2.mode", 1, 0) in e.changes]
    assert any(abs(t - 0.70958) < 1e-4 for t in stuck)


def _decay_class(rate: float):
    """A model class made on the fly, as the fuzzing makes them: der(x) = -rate*x."""

    class Decay(Model):
        x = Variable(start=1.0, fixed=True)

        def equations(self):
            return [Eq(der(self.x), -rate * self.x)]

    return Decay


def test_model_classes_made_on_the_fly_are_not_confused():
    """Ten classes with the same name and different equations, each simulated once: each result is its own."""
    import gc

    for rate in (1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0):
        cls = _decay_class(rate)
        result = simulate(cls(), stop_time=1.0, interval=0.5, rtol=1e-10)
        assert result.final("x") == pytest.approx(math.exp(-rate), rel=1e-6), f"rate {rate}"
        del cls, result
        gc.collect()
