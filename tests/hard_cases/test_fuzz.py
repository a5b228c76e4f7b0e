"""Property-based fuzzing of random rotational drive trains (hypothesis).

Each example is a row of 1 to 5 inertias (J in [0.01, 10]) joined by random
couplings -- Clutch (table ``mu_pos`` of one or two rows, ``peak`` in
[1, 1.5], ``f_normalized`` from a Constant or a Step), SpringDamper (c in
[10, 1e4], d in [0, 10]), Spring, Damper -- with, on each inertia, nothing,
a BearingFriction (``tau_pos`` one or two rows, positive and increasing,
``peak`` in [1, 1.5]) or a Brake; one or two Torque sources fed by a Sine or
a Step act on random inertias.  The friction elements sometimes get a
``w_small``, a ``K_locked`` (and Clutch and Brake a ``cgeo``) of their own.
Every inertia has fixed starts ``phi = 0`` and ``w`` in [-5, 5]; no two
inertias are rigidly joined (couplings are compliant or clutches), so these
starts are consistent.

Extreme and invalid values
--------------------------
Each example also draws a *chaos* level (0, 2, 5 or 15 %): the chance that each
parameter of the drive train -- inertias and start speeds, spring and damper
constants, every entry of the friction tables (abscissas included), peak,
fn_max, cgeo, w_small, K_locked, the blocks' offsets, heights, start times,
amplitudes, frequencies, phases -- is replaced by one of :data:`EXTREMES`
(nan, inf, -inf, 0, -1, 1e-12, 1e12).  The run settings are drawn too:
all seven methods (RK45, DOP853, Radau, BDF, LSODA adaptive, with or without
a ``max_step``; Euler and RK4 with a drawn fixed step ``max_step``), ``rtol``
(1e-10 to 1e-5), the output ``interval`` (0.002 to 0.1) and ``stop_time``
(0.2 to 1), each replaced with a chance of 0, 10 or 30 % by one of
:data:`SETTING_EXTREMES` (0, negative, nan, inf, 1e-12, 1e12, and rtol >= 1;
for the fixed step all but 1e12, see :data:`FIXED_STEP_RANGE`).  The heat
capacitors and power meters that measure the energy keep their values: they
are the instruments, not the drive train.

The property
------------
**Every outcome is a documented error or a finite result that passes the
energy audit**:

* ``simulate`` (or building the model) raises an :class:`AcausalError` that
  is a ValueError -- ParameterError and the other ModelDefinitionErrors, a
  StructuralError, an InitializationError, a SettingError -- with a message; or
* the run stops early: ``status == -1`` and ``result.error`` is a
  :class:`SimulationError` (SolverError, EventIterationError,
  ChatteringError) with a non-empty message and hint, and the partial result
  has a non-empty, non-decreasing time vector and finite states in every row;
  or
* the run completes (``status == 0``, last row at the stop time) with every
  column finite (states and computed variables), friction modes consistent
  with the relative speeds (mode 1 (forward) needs ``w_relfric >= -tol``,
  mode -1 ``w_relfric <= tol``, mode 0 ``|w_relfric| <= tol``, ``tol =
  1e-6*(1 + max|w|)`` plus the speed an event located to 4 ulp of the time
  leaves (see :func:`check_modes`), at rows that are not event instants; a
  locked element holds with ``|sa| <= tau0_max``), and the energy audit below.

Anything else fails: a raw Python exception (ZeroDivisionError, IndexError,
OverflowError, TypeError, KeyError, ...), a SimulationError raised instead of
returned, NaN or inf in a completed result, a hang.  Every run gets the
budgets ``max_steps=MAX_STEPS`` and ``timeout=TIMEOUT`` (which the engine
holds), and a watchdog (``SIGALRM``, :data:`HANG_SECONDS`) turns a run that
still does not return into a failure.

The engine bugs this fuzzing found are fixed, each reproduced by a test at
the end of the file; their switches stay (:func:`hits_massless_table_bugs`,
:data:`SKIP_MODE_SIGNS_FOR_EULER`).  One finding is the MSL's own friction
semantics and is kept: a friction element that a just-engaged clutch starts
may wait in its start flag while turning against it
(:func:`started_against_the_drive`); the mode check is skipped for such runs,
counted apart in the report, and their energy audit still runs.

The energy audit
----------------
Every dissipative element (BearingFriction, Brake, Clutch, Damper,
SpringDamper) has ``useHeatPort=True`` and its heat port on a HeatCapacitor
of its own (C = 1 J/K, T fixed at 0 K, see ``T_START``), so all the energy it
dissipates is ``C*(T_end - T_start)``; each source drives its inertia through
a test-local :class:`PowerMeter` that integrates, inside the model, the power
it delivers: ``der(W) = tau*w``.  At the end of a completed run::

    |W - dE_kin - dE_spring - sum C*dT| <= tol * max(1 J, |W|, E_kin(0), E_kin(end), E_spring(end), heat)

The scale is the energy that moved, not only ``|W|``: initial speeds bring
up to 125 J per inertia that friction turns into heat, and the integration
error is relative to that.  ``tol`` is :func:`audit_tolerance`: 1e-5 for the
adaptive methods at rtol <= 1e-8 (the integration error at rtol 1e-8 reaches
a few 1e-6), growing in proportion to rtol above it; for Euler and RK4 it
follows their error constants (:data:`FIXED_STEP_TOL`).  An imbalance that
is integration error shrinks when the integration is refined, a leak (a term
missing from the model, see test_energy_audit_detects_a_missing_term) does
not: a completed run above ``tol`` (never looser than 1e-3) still passes if
the same model, run again with a refined setting (rtol/100, or a quarter of
the fixed step), brings the imbalance below ``tol`` or at least halves it
(see :func:`check_energy_converges`).

When a property fails hypothesis prints the drawn spec and settings, a
readable summary of the model, the result's summary and last events and the
energy terms (``note``), then shrinks to a small failing model.

Number of examples, report
--------------------------
The default is :data:`DEFAULT_EXAMPLES` examples, drawn deterministically
(``derandomize=True``) so CI always runs the same models, plus the cases of
:data:`EXPLICIT_EXAMPLES` (every run, long ones too): a SettingError, a step
budget, a blow-up, chattering, an event iteration that does not settle, and a
J = 1e-12 shaft, outcomes a short derandomized draw rarely reaches.  For a long
exploratory run set the environment variable ``ACAUSAL_FUZZ_EXAMPLES``::

    ACAUSAL_FUZZ_EXAMPLES=500 ACAUSAL_FUZZ_REPORT=/tmp/fuzz500.json python -m pytest tests/hard_cases/test_fuzz.py -q

Any value other than the default also switches derandomization off (each
long run explores other models) and turns hypothesis' example database on
(``.hypothesis/``, git-ignored), so a failure found is replayed first on the
next run.  With ``ACAUSAL_FUZZ_REPORT=path.json`` the module writes, when it
ends, a summary of the property's runs: examples run, outcomes by kind
(``ok`` and each error class, raised or returned), by method, and the worst
relative energy imbalance among the completed runs (with its tolerance and
settings).

Engine bugs found by this fuzzing have minimal reproductions at the end of
the file: fixed ones guard the fix, open ones are strict xfail tests.
``AVOID_STEP_TO_EXACT_ZERO`` kept the random models clear of a step to
exactly zero (a parameter combination that vanished broke the generated
code); that is fixed and the switch is off.
"""

from __future__ import annotations

import json
import math
import os
import signal
import threading
import time as _time
from collections import Counter
from contextlib import contextmanager
from dataclasses import dataclass, field

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, note, settings
from hypothesis import strategies as st

from acausal import Boolean, Component, Eq, Model, Parameter, Variable, der, simulate, time
from acausal.compiler.translate import translate
from acausal.errors import (AcausalError, ChatteringError, EventIterationError, InitializationError,
                            ModelDefinitionError, SettingError, SolverError, StructuralError)
from acausal.components.rotational import Flange_a, Flange_b
from acausal.library.blocks import Constant, Sine, Step
from acausal.library.rotational import (BearingFriction, Brake, Clutch, Damper, Inertia, Spring, SpringDamper,
                                Torque)
from acausal.library.thermal import HeatCapacitor

DEFAULT_EXAMPLES = 60
EXAMPLES = int(os.environ.get("ACAUSAL_FUZZ_EXAMPLES", DEFAULT_EXAMPLES))
LONG_RUN = EXAMPLES != DEFAULT_EXAMPLES
#: Where to write the summary of the property's runs (JSON), if set.
REPORT = os.environ.get("ACAUSAL_FUZZ_REPORT")

STOP_TIME = 1.0
INTERVAL = 0.01
RTOL = 1e-8
#: Start temperature of the heat capacitors.  The integrator controls each state's
#: error relative to its size, so at 293.15 K the heat C*dT would be resolved only
#: to about rtol*293 J per step (an energy imbalance of 6e-6 of the energy moved
#: after 570 events, measured); starting at 0 K the error is relative to the heat.
T_START = 0.0
CAPACITY = 1.0

ADAPTIVE = ("RK45", "DOP853", "Radau", "BDF", "LSODA")
FIXED_STEP = ("Euler", "RK4")
METHODS = ADAPTIVE + FIXED_STEP

#: Energy-audit tolerance (relative to the energy that moved) of the adaptive
#: methods at rtol <= 1e-8.  Measured at rtol 1e-8 over 300 random drive trains
#: each, the largest imbalances were 1.8e-6 (DOP853) and 2.6e-6 (RK45) -- stiff
#: spring chains (c = 1e4 on J = 0.01 oscillates 160 times a second) and runs
#: with hundreds of friction events -- and they shrink in proportion to rtol
#: (1e-10 gives 1e-9): integration error, not a leak.  A missing term is off by
#: far more (see test_energy_audit_detects_a_missing_term).  Over about 1 700
#: completed runs of the widened draw (rtol 1e-10 to 1e-5), the worst at
#: rtol <= 1e-8 were 5.1e-6 (BDF), 8e-8 (LSODA), 5e-8 (RK45), 4e-9 (Radau) and
#: 3e-9 (DOP853), and no adaptive run came above half its tolerance.
ENERGY_TOL = {"DOP853": 1e-5, "RK45": 1e-5, "Radau": 1e-5, "BDF": 1e-5, "LSODA": 1e-5}
#: Above rtol 1e-8 the adaptive methods' tolerance grows as ENERGY_TOL*rtol/1e-8.
ENERGY_TOL_RTOL = 1e-8
#: Euler and RK4: the audit tolerance is FIXED_STEP_TOL[method]*(h/1e-3)**order
#: (at least 1e-5), h the fixed step: the energy error of a fixed-step method
#: falls with h to the power of its order.  Measured over 1 400 random drive
#: trains (h from 1e-3 to 1e-2 for Euler, 2e-4 to 1e-2 for RK4), Euler's
#: imbalance reaches 2 (the energy grows in a stiff spring), RK4's 0.04.
FIXED_STEP_TOL = {"Euler": (0.05, 1), "RK4": (1e-4, 4)}
#: No tolerance is looser than this: above it the audit asks the refined run to
#: show that the imbalance is integration error (see check_energy_converges).
AUDIT_TOL_CAP = 1e-3

#: Budgets of every fuzzed run (the engine holds them: a run that exceeds one
#: stops with a SolverError, status -1) and the watchdog that catches a hang.
MAX_STEPS = 20_000
TIMEOUT = 5.0
HANG_SECONDS = 60.0

#: The values a chaotic draw puts in place of a parameter.
EXTREMES = (math.nan, math.inf, -math.inf, 0.0, -1.0, 1e-12, 1e12)
#: ... and in place of a run setting (rtol also >= 1).
SETTING_EXTREMES = (math.nan, math.inf, -math.inf, 0.0, -1.0, 1e-12, 1e12)
RTOL_EXTREMES = SETTING_EXTREMES + (1.0, 2.0)
#: ... and in place of the fixed step of Euler and RK4 (see FIXED_STEP_RANGE).
FIXED_STEP_EXTREMES = (math.nan, math.inf, -math.inf, 0.0, -1.0, 1e-12)
#: log10 of the fixed steps drawn for Euler and RK4.  Longer fixed steps (up to
#: 1e12, longer than the run) complete with a finite result whose energy is as
#: wrong as the step is long -- the user's choice of step, not an engine defect,
#: and nothing an audit can tell from a leak -- so they are not drawn.
FIXED_STEP_RANGE = {"Euler": (-3.0, -2.0), "RK4": (-3.7, -2.0)}

#: Raised before the run, these are documented (all ValueErrors).
ERRORS_BEFORE_RUN = (ModelDefinitionError, StructuralError, InitializationError, SettingError)
#: Returned in a result with status -1, these are documented.
ERRORS_OF_A_RUN = (SolverError, EventIterationError, ChatteringError)


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
    extra: tuple = ()  # (name, value) pairs: w_small, K_locked

    def __str__(self):
        more = "".join(f", {k}={_fmt(v)}" for k, v in self.extra)
        return f"BearingFriction(tau_pos={_fmt(self.tau_pos)}, peak={self.peak:.6g}{more})"


@dataclass(frozen=True)
class BrakeSpec:
    fn_max: float
    mu_pos: tuple  # rows (w, mu)
    peak: float
    signal: Signal  # f_normalized
    extra: tuple = ()  # (name, value) pairs: w_small, K_locked, cgeo

    def __str__(self):
        more = "".join(f", {k}={_fmt(v)}" for k, v in self.extra)
        return (f"Brake(fn_max={self.fn_max:.6g}, mu_pos={_fmt(self.mu_pos)}, peak={self.peak:.6g}{more}, "
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


@dataclass(frozen=True)
class RunSettings:
    """The settings a fuzzed run is simulated with (``max_step`` None: the method's default)."""

    method: str = "DOP853"
    rtol: float = RTOL
    interval: float = INTERVAL
    stop_time: float = STOP_TIME
    max_step: float | None = None

    def kwargs(self) -> dict:
        return dict(method=self.method, rtol=self.rtol, interval=self.interval, stop_time=self.stop_time,
                    max_step=self.max_step)

    def refined(self) -> "RunSettings":
        """The same run integrated more accurately (rtol/100, or a quarter of the fixed step)."""
        if self.method in FIXED_STEP:
            return RunSettings(self.method, self.rtol, self.interval, self.stop_time, self.max_step / 4)
        return RunSettings(self.method, max(self.rtol / 100, 1e-13), self.interval, self.stop_time,
                           self.max_step)

    def __str__(self):
        step = "" if self.max_step is None else f", max_step={self.max_step:.6g}"
        return (f"{self.method}, rtol={self.rtol:.6g}, interval={self.interval:.6g}, "
                f"stop_time={self.stop_time:.6g}{step}")


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
def value(draw, lo, hi, chaos=0, extremes=EXTREMES):
    """A float in [lo, hi]; with a chance of ``chaos`` percent one of ``extremes`` instead.

    The gate shrinks towards 0, the ordinary value: a failing example shrinks
    to as few extreme values as it needs.
    """
    if chaos and draw(st.integers(0, 99)) >= 100 - chaos:
        return draw(st.sampled_from(extremes))
    return draw(_floats(lo, hi))


@st.composite
def log_value(draw, lo_exp, hi_exp, chaos=0, extremes=EXTREMES):
    """10**x for x in [lo_exp, hi_exp]; extremes as :func:`value`."""
    if chaos and draw(st.integers(0, 99)) >= 100 - chaos:
        return draw(st.sampled_from(extremes))
    return 10.0 ** draw(_floats(lo_exp, hi_exp))


@st.composite
def friction_table(draw, lo, hi, chaos=0):
    """One row [[0, y0]] or two rows [[0, y0], [w1, y1]] with y1 >= y0 (positive, increasing)."""
    w0 = draw(value(0.0, 0.0, chaos))
    y0 = draw(value(lo, hi, chaos))
    if draw(st.booleans()):
        return ((w0, y0),)
    w1 = draw(value(0.5, 20.0, chaos))
    y1 = y0 * draw(value(1.0, 2.0, chaos))
    return ((w0, y0), (w1, y1))


@st.composite
def friction_extras(draw, chaos, normal_force):
    """Optional w_small, K_locked (and cgeo for Clutch and Brake) of a friction element."""
    extra = []
    if draw(st.booleans()):
        extra.append(("w_small", draw(value(0.01, 100.0, chaos))))
    if draw(st.booleans()):
        extra.append(("K_locked", draw(value(0.0, 50.0, chaos))))
    if normal_force and draw(st.booleans()):
        extra.append(("cgeo", draw(value(0.5, 2.0, chaos))))
    return tuple(extra)


#: Engine bug (see test_parameter_sum_cancelling_to_zero_in_generated_code): a
#: Step whose offset + height is exactly 0 (a torque or clutch force stepping
#: to zero) makes the incidence analysis drop the unknown that this zero
#: coefficient multiplies in the power meter, and the generated code reads it
#: before assigning it (UnboundLocalError).  While that bug stands, such a
#: step ends at a small negative value instead (for a clutch force still
#: "disengaged"); set to False once the regression test passes.
AVOID_STEP_TO_EXACT_ZERO = False  # the engine bug it avoided is fixed; kept as a switch


@st.composite
def step_signal(draw, lo, hi, chaos=0):
    """A Step whose offset and offset + height both lie in [lo, hi], starting inside the run."""
    a = draw(value(lo, hi, chaos))
    b = draw(value(lo, hi, chaos))
    if AVOID_STEP_TO_EXACT_ZERO and abs(b) < 1e-6:
        b = -1e-3 * (hi - lo)
    start = draw(value(0.05, 0.95, chaos))
    return Signal("Step", (("offset", a), ("height", b - a), ("startTime", start)))


def clutch_force(chaos=0):
    return st.one_of(
        value(0.0, 1.0, chaos).map(lambda k: Signal("Constant", (("k", k),))),
        step_signal(0.0, 1.0, chaos),
    )


def torque_signal(chaos=0):
    return st.one_of(
        st.tuples(value(0.1, 20.0, chaos), value(0.2, 5.0, chaos), value(-math.pi, math.pi, chaos)).map(
            lambda p: Signal("Sine", (("amplitude", p[0]), ("f", p[1]), ("phase", p[2])))),
        step_signal(-10.0, 10.0, chaos),
    )


@st.composite
def coupling(draw, chaos=0):
    kind = draw(st.sampled_from(["Clutch", "SpringDamper", "Spring", "Damper"]))
    if kind == "Clutch":
        mu = draw(friction_table(0.1, 1.0, chaos))
        params = (("fn_max", draw(value(0.1, 50.0, chaos))), ("mu_pos", mu), ("peak", draw(value(1.0, 1.5, chaos))))
        params += draw(friction_extras(chaos, True))
        return Coupling(kind, params, draw(clutch_force(chaos)))
    if kind == "SpringDamper":
        return Coupling(kind, (("c", draw(value(10.0, 1e4, chaos))), ("d", draw(value(0.0, 10.0, chaos)))))
    if kind == "Spring":
        return Coupling(kind, (("c", draw(value(10.0, 1e4, chaos))),))
    return Coupling(kind, (("d", draw(value(0.0, 10.0, chaos))),))


def bearing(chaos=0):
    return st.builds(Bearing, friction_table(0.05, 5.0, chaos), value(1.0, 1.5, chaos),
                     friction_extras(chaos, False))


def brake(chaos=0):
    return st.builds(BrakeSpec, value(0.1, 20.0, chaos), friction_table(0.1, 1.0, chaos), value(1.0, 1.5, chaos),
                     clutch_force(chaos), friction_extras(chaos, True))


#: Chance (percent) that each parameter of a drive train is an extreme value;
#: the first (0: a physical drive train) is where examples shrink to.
CHAOS_LEVELS = (0, 2, 5, 15)


@st.composite
def drive_train(draw, chaos=None):
    if chaos is None:
        chaos = draw(st.sampled_from(CHAOS_LEVELS))
    n = draw(st.integers(1, 5))
    J = tuple(draw(st.lists(value(0.01, 10.0, chaos), min_size=n, max_size=n)))
    w0 = tuple(draw(st.lists(value(-5.0, 5.0, chaos), min_size=n, max_size=n)))
    couplings = tuple(draw(st.lists(coupling(chaos), min_size=n - 1, max_size=n - 1)))
    bearings = tuple(draw(st.lists(st.one_of(st.none(), bearing(chaos), brake(chaos)), min_size=n, max_size=n)))
    sources = tuple(draw(st.lists(st.builds(Source, st.integers(0, n - 1), torque_signal(chaos)),
                                  min_size=1, max_size=2)))
    return Spec(J, w0, couplings, bearings, sources)


#: Chance (percent) that each run setting is an extreme or invalid value.
WILD_LEVELS = (0, 10, 30)


@st.composite
def run_settings(draw):
    """Method, rtol, interval, stop time and (for Euler and RK4 always) max_step."""
    method = draw(st.sampled_from(METHODS))
    wild = draw(st.sampled_from(WILD_LEVELS))
    rtol = draw(log_value(-10.0, -5.0, wild, RTOL_EXTREMES))
    stop_time = draw(value(0.2, 1.0, wild, SETTING_EXTREMES))
    interval = draw(log_value(-2.7, -1.0, wild, SETTING_EXTREMES))
    if method in FIXED_STEP:
        max_step = draw(log_value(*FIXED_STEP_RANGE[method], wild, FIXED_STEP_EXTREMES))
    elif draw(st.booleans()):
        max_step = None
    else:
        max_step = draw(log_value(-3.0, -1.0, wild, SETTING_EXTREMES))
    return RunSettings(method, rtol, interval, stop_time, max_step)


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
                                               useHeatPort=True, **dict(b.extra))
                    setattr(self, bname, friction)
                elif isinstance(b, BrakeSpec):
                    bname = f"brake{i + 1}"
                    friction = Brake(fn_max=b.fn_max, mu_pos=[list(r) for r in b.mu_pos], peak=b.peak,
                                     useHeatPort=True, **dict(b.extra))
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
# running a spec


class Hang(BaseException):
    """A run did not return within HANG_SECONDS (a BaseException: no ``except Exception`` hides it)."""


@contextmanager
def watchdog(seconds: float, timeout: float = TIMEOUT):
    """Raise :class:`Hang` in the body if it runs longer than ``seconds`` (main thread, POSIX only).

    The alarm repeats every second after the first: a Hang raised while Python
    runs a finalizer (``__del__``, a weakref callback during garbage
    collection) is swallowed ("Exception ignored in ..."), and a one-shot
    alarm then leaves the hang running (seen: 10 minutes and 6 GB in the
    Pantelides loop of test_massless_shaft_on_flat_friction_table_returns_within_its_timeout).
    """
    if not hasattr(signal, "setitimer") or threading.current_thread() is not threading.main_thread():
        yield
        return
    armed = [True]

    def expired(signum, frame):
        if armed[0]:
            raise Hang(f"no answer within {seconds:g} s although simulate had timeout={timeout:g} s")

    previous = signal.signal(signal.SIGALRM, expired)
    signal.setitimer(signal.ITIMER_REAL, seconds, 1.0)
    try:
        yield
    finally:
        armed[0] = False
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


@dataclass
class Attempt:
    """What building and simulating one spec gave."""

    audit: Audit
    result: object = None  # SimulationResult, or None when an error was raised
    raised: AcausalError | None = None
    states: tuple = ()  # names of the continuous states of the systems compiled
    seconds: float = 0.0


def attempt(spec: Spec, run: RunSettings, budgets: float = 1.0) -> Attempt:
    """Build and simulate the model of ``spec`` with ``run`` and the budgets (times ``budgets``).

    Only AcausalErrors are caught (as ``raised``); anything else escapes.
    """
    cls, audit = model_class(spec)
    out = Attempt(audit)
    started = _time.perf_counter()
    try:
        with watchdog(HANG_SECONDS * budgets, TIMEOUT * budgets):
            translation = translate(cls())
            out.result = simulate(translation, max_steps=int(MAX_STEPS * budgets), timeout=TIMEOUT * budgets,
                                  **run.kwargs())
            out.states = tuple(sorted({s for system in translation.systems.values() for s in system.states}))
    except AcausalError as exc:  # judged by the caller: documented or not
        out.raised = exc
        _note(f"raised {type(exc).__name__}: {exc}")
    out.seconds = _time.perf_counter() - started
    return out


def run_spec(spec: Spec, method: str = "DOP853", run: RunSettings | None = None):
    """Simulate the model of ``spec``; (result or None, audit).  Only AcausalErrors may escape."""
    out = attempt(spec, run or RunSettings(method))
    return out.result, out.audit


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


def check_finite(result, names=None) -> None:
    """No NaN or inf in the columns ``names`` (default: every column) nor in the time vector."""
    names = list(result.columns) if names is None else names
    assert np.all(np.isfinite(result.time)), "time is not finite"
    bad = [n for n in names if not np.all(np.isfinite(np.asarray(result[n], dtype=float)))]
    assert not bad, f"not finite: {len(bad)} columns, e.g. " + ", ".join(
        f"{n} = {np.asarray(result[n], dtype=float)[~np.isfinite(np.asarray(result[n], dtype=float))][0]}"
        for n in bad[:5])


#: Fixed engine bug (see test_euler_output_between_steps_keeps_the_sign_of_the_speed):
#: Euler's dense output was the cubic Hermite interpolant of the step ends and
#: their derivatives, which dipped below both ends after a breakaway; it is now
#: linear, so the speed-sign part of check_modes runs for Euler too.
SKIP_MODE_SIGNS_FOR_EULER = False


def speed_tolerance(result, audit: Audit, name: str) -> float:
    """The tolerance of check_modes on the relative speed of friction element ``name``."""
    w_max = max(np.max(np.abs(result[f"{n}.w"])) for n, _ in audit.inertias)
    located = 8 * np.finfo(float).eps * max(1.0, float(np.max(np.abs(result.time))))
    return 1e-6 * (1 + w_max) + located * float(np.max(np.abs(result[f"{name}.a_relfric"])))


#: MSL semantics, not a bug (see
#: test_engaging_clutch_next_to_a_bearing_follows_the_msl_waiting_phase): a
#: clutch that engages with slip is locked in the first pass of the event
#: iteration (pre(mode) = Free); a friction element next to it then takes the
#: whole load, starts (startForward), and keeps starting through pre() once the
#: clutch slides, although its load is now below tau0_max: it waits in Stuck
#: while turning against its start direction, with negative loss power.  A
#: completed run that shows it (:func:`started_against_the_drive`) skips
#: check_modes and is counted as SKIPPED_START_AGAINST_DRIVE; its energy audit
#: still runs.
SKIPPED_START_AGAINST_DRIVE = "ok, mode check skipped: a friction element waits in a start flag against its drive (MSL semantics)"


def started_against_the_drive(result, audit: Audit) -> list[str]:
    """Friction elements with rows (not event instants) in startForward with w_relfric < 0 or vice versa."""
    between = ~event_rows(result)
    found = []
    for name in audit.friction:
        tol = speed_tolerance(result, audit, name)
        w = result[f"{name}.w_relfric"][between]
        forward = result[f"{name}.startForward"][between] == 1
        backward = result[f"{name}.startBackward"][between] == 1
        if np.any(forward & (w < -tol)) or np.any(backward & (w > tol)):
            found.append(name)
    return found


def check_modes(result, audit: Audit, method: str | None = None) -> None:
    """Friction modes agree with the relative speeds; locked elements hold within their limit.

    The speed tolerance is ``1e-6*(1 + max|w|)`` plus what locating an event
    in time can leave: the bisection stops at 4 ulp of ``max(1, t)``, and an
    element with relative acceleration ``a`` (1e13 rad/s2 for J = 1e-12 on a
    clutch) then locks at a residual speed up to ``|a|*8*eps*max(1, t)``.
    """
    between = ~event_rows(result)
    for name in audit.friction:
        tol = speed_tolerance(result, audit, name)
        mode = result[f"{name}.mode"][between]
        w = result[f"{name}.w_relfric"][between]
        t = result.time[between]
        if method == "Euler" and SKIP_MODE_SIGNS_FOR_EULER:
            w = np.zeros_like(w)
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
    terms["relative"] = abs(terms["imbalance"]) / terms["scale"]
    return terms


def _note(text: str) -> None:
    """hypothesis' note inside a property, nothing elsewhere."""
    try:
        note(text)
    except Exception:  # noqa: BLE001 - outside a hypothesis test
        pass


def check_energy(result, audit: Audit, tol: float = 1e-6) -> dict:
    """|W - dE_kin - dE_spring - sum C*dT| <= tol * (the energy that moved, at least 1 J); the terms."""
    e = energy_terms(result, audit)
    _note("energy: " + ", ".join(f"{k}={v:.12g}" for k, v in e.items()))
    assert abs(e["imbalance"]) <= tol * e["scale"], (
        f"energy audit: work {e['work']:.12g} J != kinetic {e['kinetic']:.12g} + spring "
        f"{e['spring']:.12g} + heat {e['heat']:.12g} (imbalance {e['imbalance']:.3g} J, "
        f"{e['relative']:.3g} of the {e['scale']:.6g} J that moved, tolerance {tol:.3g})")
    return e


def audit_tolerance(run: RunSettings) -> float:
    """The energy-audit tolerance (relative to the energy that moved) of a run's settings."""
    if run.method in FIXED_STEP:
        constant, order = FIXED_STEP_TOL[run.method]
        return min(AUDIT_TOL_CAP, max(1e-5, constant * (run.max_step / 1e-3) ** order))
    return min(AUDIT_TOL_CAP, ENERGY_TOL[run.method] * max(1.0, run.rtol / ENERGY_TOL_RTOL))


def check_energy_converges(spec: Spec, run: RunSettings, result, audit: Audit) -> dict:
    """The energy audit of a completed run, allowing integration error that converges.

    Within :func:`audit_tolerance` the run passes.  Above it, the model is run
    again with ``run.refined()``: integration error shrinks with the step or
    rtol, a leak does not, so the run passes if the refined imbalance is
    within the tolerance or at most half the first one (Euler's error falls
    fourfold with a quarter of the step, RK4's 256-fold, the adaptive
    methods' about a hundredfold with rtol/100).
    """
    tol = audit_tolerance(run)
    e = energy_terms(result, audit)
    _note("energy: " + ", ".join(f"{k}={v:.12g}" for k, v in e.items()) + f", tolerance={tol:.3g}")
    e["tolerance"] = tol
    if e["relative"] <= tol:
        return e
    fine = run.refined()
    again = attempt(spec, fine, budgets=4.0)
    if again.result is None or again.result.status != 0:
        raise AssertionError(
            f"energy audit: imbalance {e['relative']:.3g} of the {e['scale']:.6g} J that moved is above "
            f"the tolerance {tol:.3g}, and the refined run ({fine}) did not complete to tell "
            f"integration error from a leak: "
            f"{again.raised if again.result is None else again.result.message}")
    f = energy_terms(again.result, again.audit)
    _note(f"energy of the refined run ({fine}): " + ", ".join(f"{k}={v:.12g}" for k, v in f.items()))
    assert f["relative"] <= tol or abs(f["imbalance"]) <= abs(e["imbalance"]) / 2, (
        f"energy audit: work {e['work']:.12g} J != kinetic {e['kinetic']:.12g} + spring "
        f"{e['spring']:.12g} + heat {e['heat']:.12g} (imbalance {e['imbalance']:.3g} J, "
        f"{e['relative']:.3g} of the {e['scale']:.6g} J that moved, tolerance {tol:.3g}), and refining "
        f"the integration ({fine}) leaves {f['imbalance']:.3g} J: a leak, not integration error")
    e["refined"] = f["relative"]
    return e


# --------------------------------------------------------------------------
# outcome figures (ACAUSAL_FUZZ_REPORT)


FIGURES: dict = {"examples": 0, "outcomes": Counter(), "by_method": {}, "worst": None, "worst_direct": None,
                 "worst_by_method": {}, "refined": 0, "seconds": 0.0, "slowest": 0.0}


def _record(kind: str, run: RunSettings, out: Attempt | None, energy: dict | None = None) -> None:
    FIGURES["examples"] += 1
    FIGURES["outcomes"][kind] += 1
    FIGURES["by_method"].setdefault(run.method, Counter())[kind] += 1
    if out is not None:
        FIGURES["seconds"] += out.seconds
        FIGURES["slowest"] = max(FIGURES["slowest"], out.seconds)
    if energy is not None:
        FIGURES["refined"] += "refined" in energy
        figure = {"relative": energy["relative"], "tolerance": energy["tolerance"],
                  "imbalance_J": energy["imbalance"], "scale_J": energy["scale"],
                  "refined_relative": energy.get("refined"), "settings": str(run)}
        for key in ("worst", ("worst_by_method", run.method)) + (() if "refined" in energy else ("worst_direct",)):
            table, name = (FIGURES, key) if isinstance(key, str) else (FIGURES[key[0]], key[1])
            if table.get(name) is None or figure["relative"] > table[name]["relative"]:
                table[name] = figure


@pytest.fixture(scope="module", autouse=True)
def fuzz_report():
    """Write FIGURES to ACAUSAL_FUZZ_REPORT (JSON) when the module ends.

    ``examples`` counts every call of the property: the drawn examples, the
    explicit ones and, after a failure, the shrinking attempts.
    """
    yield
    if not REPORT or not FIGURES["examples"]:
        return
    report = {
        "examples": FIGURES["examples"],
        "max_examples": EXAMPLES,
        "derandomized": not LONG_RUN,
        "outcomes": dict(FIGURES["outcomes"].most_common()),
        "by_method": {m: dict(c.most_common()) for m, c in sorted(FIGURES["by_method"].items())},
        # relative imbalance |W - dE - heat| / (energy moved) among the completed runs:
        # the worst of all, the worst within the tolerance at once (no refined run
        # needed), and the worst of each method
        "worst_energy_imbalance": FIGURES["worst"],
        "worst_energy_imbalance_within_tolerance": FIGURES["worst_direct"],
        "worst_energy_imbalance_by_method": dict(sorted(FIGURES["worst_by_method"].items())),
        "audits_needing_the_refined_run": FIGURES["refined"],
        "simulate_seconds_total": round(FIGURES["seconds"], 2),
        "slowest_example_seconds": round(FIGURES["slowest"], 2),
        "budgets": {"max_steps": MAX_STEPS, "timeout": TIMEOUT, "hang_seconds": HANG_SECONDS},
    }
    with open(REPORT, "w") as handle:
        json.dump(report, handle, indent=2)
        handle.write("\n")


# --------------------------------------------------------------------------
# the property


def judge(spec: Spec, run: RunSettings, out: Attempt) -> tuple[str, dict | None]:
    """Check one attempt against the property; its outcome kind and (completed runs) energy terms."""
    if out.raised is not None:
        exc = out.raised
        assert isinstance(exc, ERRORS_BEFORE_RUN), (
            f"simulate raised {type(exc).__name__}, not an error documented before the run: {exc}")
        assert exc.message, f"{type(exc).__name__} without a message"
        return f"raised {type(exc).__name__}", None
    result = out.result
    note(result.summary())
    for event in result.events[-5:]:
        note(f"last events: {event}")
    assert result.status in (0, -1), result.status
    assert result.time.size >= 1, "no rows"
    assert np.all(np.diff(result.time) >= 0), "time goes backwards"
    if result.status == -1:
        error = result.error
        assert isinstance(error, ERRORS_OF_A_RUN), f"status -1 with {type(error).__name__}: {error!r}"
        assert error.message, f"{type(error).__name__} without a message"
        assert error.hint, f"{type(error).__name__} without a hint: {error.message}"
        check_finite(result, [s for s in out.states if s in result])
        return f"status -1 {type(error).__name__}", None
    assert result.error is None
    assert result.time[-1] == pytest.approx(run.stop_time, rel=1e-9, abs=0)
    check_finite(result)
    against = started_against_the_drive(result, out.audit) if run.method != "Euler" else []
    if against:
        note(f"{', '.join(against)} wait against the drive (MSL semantics): check_modes skipped")
        return SKIPPED_START_AGAINST_DRIVE, check_energy_converges(spec, run, result, out.audit)
    check_modes(result, out.audit, run.method)
    return "ok", check_energy_converges(spec, run, result, out.audit)


def _tables(spec: Spec):
    for b in spec.bearings:
        if isinstance(b, Bearing):
            yield b.tau_pos
        elif isinstance(b, BrakeSpec):
            yield b.mu_pos
    for c in spec.couplings:
        if c.kind == "Clutch":
            yield dict(c.params)["mu_pos"]


#: Both bugs that made these draws skip are fixed (see hits_massless_table_bugs).
SKIP_MASSLESS_TABLES = False


def hits_massless_table_bugs(spec: Spec) -> bool:
    """Fixed engine bugs: a massless inertia (J = 0) in a model with a friction table of two rows.

    * (Fixed: a bearing whose two-row table is flat on a J = 0 shaft sent the
      index reduction into a loop that never ended;
      test_massless_shaft_on_flat_friction_table_returns_within_its_timeout.)
    * (Fixed: a J = 0 shaft on a disengaged brake with a two-row table stopped
      at initialization with a bare ZeroDivisionError from the generated code,
      status -1, no rows, no hint; on an engaged flat clutch a failed Newton
      iteration, also with no rows.  A failure while solving for the initial
      values is now an InitializationError naming the variable and the line.)
      (test_massless_shaft_on_two_row_table_fails_with_a_documented_error).
    """
    return any(J == 0 for J in spec.J) and any(len(t) == 2 for t in _tables(spec))


#: The outcome kind of the draws left out while those bugs stand.
SKIPPED_MASSLESS_TABLE = "skipped: J = 0 with a two-row friction table (open engine bugs)"


def _constant(k):
    return Signal("Constant", (("k", k),))


_CLUTCH_ENGAGES = Spec(
    J=(1.0, 2.0), w0=(5.0, -1.0),
    couplings=(Coupling("Clutch", (("fn_max", 20.0), ("mu_pos", ((0.0, 0.5),)), ("peak", 1.1)),
                        Signal("Step", (("offset", 0.0), ("height", 1.0), ("startTime", 0.2)))),),
    bearings=(None, Bearing(((0.0, 0.5),), 1.0)),
    sources=(Source(0, Signal("Step", (("offset", 1.0), ("height", -2.0), ("startTime", 0.6)))),))

#: Drawn cases (values rounded) that CI always runs besides its derandomized
#: draw, one per kind of outcome the draw rarely reaches in 60 examples.
EXPLICIT_EXAMPLES = {
    # rtol = 0: SettingError before anything runs
    "rtol_zero": (_CLUTCH_ENGAGES, RunSettings("Radau", 0.0)),
    # a fixed step of 1e-12: the step budget stops Euler (SolverError, status -1, 1 row)
    "euler_step_budget": (_CLUTCH_ENGAGES, RunSettings("Euler", 1e-6, 0.01, 1.0, 1e-12)),
    # RK4 with h*omega = 6.8 on a stiff spring: non-finite at t = 0.427 (SolverError, status -1)
    "rk4_blows_up": (
        Spec(J=(0.01, 0.01), w0=(-4.91243, 0.0),
             couplings=(Coupling("SpringDamper", (("c", 9567.68), ("d", 0.0766546))),), bearings=(None, None),
             sources=(Source(0, Signal("Step", (("offset", -6.48949), ("height", -1.43068),
                                                ("startTime", 0.930652)))),)),
        RunSettings("RK4", 6.42587e-08, 0.0315266, 0.559723, 0.00711387)),
    # peak = 1e12, w_small = 1e-12, f_normalized = 1e12 on a brake: ChatteringError at t = 1e-12
    "brake_chatters": (
        Spec(J=(0.5, 2.17364), w0=(-2.92163, 0.5),
             couplings=(Coupling("Clutch", (("fn_max", 1e12), ("mu_pos", ((0.0, 0.99999), (0.5, 0.99999))),
                                            ("peak", 1.0), ("K_locked", 1e-12)), _constant(0.0)),),
             bearings=(BrakeSpec(0.99999, ((0.0, 0.831789),), 1e12, _constant(1e12),
                                 (("w_small", 1e-12), ("cgeo", 1.70433))), None),
             sources=(Source(1, Signal("Sine", (("amplitude", 0.1), ("f", 0.2), ("phase", 0.0)))),)),
        RunSettings("RK45", 1e-10, 0.00199526, 0.2, 0.001)),
    # K_locked = 50 on a bearing that starts at w = 1e-6: EventIterationError at t = 0.0217
    "k_locked_event_iteration": (
        Spec(J=(3.5631, 2.63563, 9.95056, 6.14228), w0=(1e-06, 0.0, -1.37513, -3.80212),
             couplings=(Coupling("Spring", (("c", 184.121),)),
                        Coupling("SpringDamper", (("c", 2612.67), ("d", 5.79465))),
                        Coupling("SpringDamper", (("c", 1071.97), ("d", 8.62289)))),
             bearings=(Bearing(((0.0, 0.513598),), 1.0, (("K_locked", 50.0),)), None,
                       Bearing(((0.0, 0.267205),), 1.5), None),
             sources=(Source(0, Signal("Sine", (("amplitude", 1.0), ("f", 0.2), ("phase", 0.0)))),)),
        RunSettings("RK45", 1e-10, 0.00199526, 0.2, 0.001)),
    # J = 1e-12 dragged by a clutch: locks within 1e-12 s at a residual slip of 1.2e-3 rad/s
    # (|a| = 3.6e12 rad/s2 times the 4-ulp event location, see check_modes); completes
    "tiny_inertia_locks": (
        Spec(J=(8.34372, 1e-12, 6.75877), w0=(-3.48237, -1e-05, 0.0),
             couplings=(Coupling("Clutch", (("fn_max", 26.1586), ("mu_pos", ((0.0, 0.403777),)), ("peak", 1.46636),
                                            ("w_small", 0.5)),
                                 Signal("Step", (("offset", 0.366545), ("height", 0.467939), ("startTime", 0.60639)))),
                        Coupling("Damper", (("d", 0.0728529),))),
             bearings=(None, None, Bearing(((0.0, 4.9386), (1.5, 9.46239)), 1.1, (("w_small", 0.5),))),
             sources=(Source(0, Signal("Sine", (("amplitude", 0.1), ("f", 0.2), ("phase", 0.0)))),)),
        RunSettings("RK45", 1e-10, 0.00199526, 0.2, 0.001)),
}


def _with_explicit_examples(test):
    for spec, run in reversed(list(EXPLICIT_EXAMPLES.values())):
        test = example(spec=spec, run=run)(test)
    return test


# numpy's overflow warning from the generated code of a run that blows up
# (e.g. rk4_blows_up) comes before the engine stops it with a SolverError
@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")
@settings(max_examples=EXAMPLES, deadline=None, derandomize=not LONG_RUN,
          **({} if LONG_RUN else {"database": None}), report_multiple_bugs=False,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
@given(spec=drive_train(), run=run_settings())
@_with_explicit_examples
def test_random_drive_train(spec, run):
    """Every drawn drive train and setting: a documented error, or a finite result passing the energy audit."""
    note(spec.describe())
    note(f"settings: {run}")
    if SKIP_MASSLESS_TABLES and hits_massless_table_bugs(spec):
        _record(SKIPPED_MASSLESS_TABLE, run, None)
        return
    out = None
    try:
        out = attempt(spec, run)
        kind, energy = judge(spec, run, out)
    except BaseException as exc:
        _record(f"FAILED {type(exc).__name__}", run, out)
        raise
    _record(kind, run, out, energy)


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


class EulerBreakaway(Model):
    """An inertia on a bearing (tau0 = 1) driven by 2*sin(2*pi*t): breakaway at t = 1/12."""

    def build(self):
        self.inertia = Inertia(J=1.0, phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=True))
        self.bearing = BearingFriction(tau_pos=[[0.0, 1.0]], peak=1.0)
        self.drive = Sine(amplitude=2.0, f=1.0)
        self.torque = Torque()
        self.connect(self.drive.y, self.torque.tau)
        self.connect(self.torque.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.bearing.flange_a)


# Engine bug found by the fuzzing, fixed (Euler's dense output is now linear): Euler's
# dense output was a cubic Hermite interpolant using the derivative at the step
# end, which Euler's step does not follow.  In the first step after the
# breakaway the start derivative is 0 (sa = tau0_max exactly), so both step
# ends have w = 0 while the end derivative is positive: the cubic dips below 0
# in between, and the output rows there show the bearing waiting to slide
# forward (mode 0, startForward) with w_relfric down to -1.6e-4, although the
# drive only ever pushes forward.  (RK4 and RK45 give no such row.)  Euler's
# own interpolant is linear between the step ends.
def test_euler_output_between_steps_keeps_the_sign_of_the_speed():
    """Output rows inside Euler steps never show a speed against the drive (w >= 0 throughout)."""
    result = simulate(EulerBreakaway(), stop_time=0.2, interval=0.001, method="Euler", max_step=0.01)
    assert result.status == 0, result.message
    w = result["bearing.w_relfric"]
    assert np.min(w) >= -1e-9, (f"{int(np.sum(w < -1e-9))} rows with w_relfric < 0, down to {np.min(w):.3g} "
                                f"at t = {result.time[np.argmin(w)]:.6g}")


class MasslessShaftOnFlatBearing(Model):
    """A massless shaft (J = 0) on a bearing whose friction table is flat: tau_pos = [[0, 1], [1, 1]].

    With a one-row table the engine says StructurallySingularError at once,
    with a rising table InitializationError.
    """

    def build(self):
        self.shaft = Inertia(J=0.0)
        self.bearing = BearingFriction(tau_pos=[[0.0, 1.0], [1.0, 1.0]])
        self.connect(self.shaft.flange_b, self.bearing.flange_a)


# Engine bug found by the fuzzing, fixed: the index reduction of the initial
# system (initialize -> Translation.system -> compile_mode -> analyse ->
# pantelides) differentiated equations for ever.  Pantelides is now bounded (an
# equation differentiated more often than there are equations means a singular
# system: StructurallySingularError).  The watchdog guards the fix.
@pytest.mark.skipif(not hasattr(signal, "setitimer"), reason="the watchdog needs signal.setitimer (POSIX)")
def test_massless_shaft_on_flat_friction_table_returns_within_its_timeout():
    """simulate(timeout=0.5) returns (or raises a documented error) well within 3 s."""
    with watchdog(3.0, 0.5):
        try:
            result = simulate(MasslessShaftOnFlatBearing(), stop_time=1.0, timeout=0.5, max_steps=1000)
        except ERRORS_BEFORE_RUN:
            return
    assert result.status == -1 and isinstance(result.error, ERRORS_OF_A_RUN) and result.error.hint


class MasslessShaftOnFreeBrake(Model):
    """A massless shaft (J = 0, started fixed) on a disengaged brake whose mu_pos has two rows."""

    def build(self):
        self.shaft = Inertia(J=0.0, phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=True))
        self.brake = Brake(mu_pos=[[0.0, 1.0], [1.0, 2.0]])
        self.force = Constant(k=0.0)
        self.connect(self.force.y, self.brake.f_normalized)
        self.connect(self.shaft.flange_b, self.brake.flange_a)


class MasslessShaftBeforeFlatClutch(Model):
    """a -- spring -- massless shaft b (J = 0) -- engaged clutch (flat mu_pos) -- c, all started fixed."""

    def build(self):
        self.a = Inertia(J=1.0, phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=True))
        self.spring = Spring(c=1.0)
        self.b = Inertia(J=0.0, phi=dict(start=0.0, fixed=True), w=dict(start=-0.5, fixed=True))
        self.clutch = Clutch(mu_pos=[[0.0, 0.1], [0.5, 0.1]])
        self.c = Inertia(J=1.0, phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=True))
        self.force = Constant(k=1.0)
        self.connect(self.a.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.b.flange_a)
        self.connect(self.b.flange_b, self.clutch.flange_a)
        self.connect(self.clutch.flange_b, self.c.flange_a)
        self.connect(self.force.y, self.clutch.f_normalized)


# Engine bug found by the fuzzing, fixed (a failure while solving for the
# initial values is now an InitializationError naming the variable and the
# generated line): initialization failed inside the generated code of the
# initial system, and the failure came back as a result with status -1 and *no
# rows*, not as a raised InitializationError.  On the free brake the generated ``outputs``
# divides by J = 0 and the error is the runtime's catch-all "the simulation
# stopped: ZeroDivisionError: float division by zero", without a hint (with a
# one-row table the engine says StructurallySingularError, without the fixed
# starts InitializationError); behind the engaged flat clutch a Newton
# iteration on clutch.mu fails (singular Jacobian; a hint, but still no rows).
@pytest.mark.parametrize("model", [MasslessShaftOnFreeBrake, MasslessShaftBeforeFlatClutch])
def test_massless_shaft_on_two_row_table_fails_with_a_documented_error(model):
    """A documented error raised before the run, or a result with rows (and a hint if it failed)."""
    try:
        result = simulate(model(), stop_time=1.0, timeout=5.0, max_steps=1000)
    except ERRORS_BEFORE_RUN:
        return
    assert "ZeroDivisionError" not in result.message, result.message
    assert result.time.size >= 1, f"status {result.status} with no rows: {result.message}"
    assert result.status == 0 or result.error.hint


class EngageNextToBearing(Model):
    """a -- spring -- b (w(0) = 1) -- clutch, engaged at t = 0.25 -- c on a bearing (tau0 = 1, tau0_max = peak).

    Once engaged, the sliding clutch drags c with mu*fn = 0.5 N.m, below the
    bearing's breakaway torque tau0 = 1.
    """

    peak = 1.5

    def build(self):
        self.a = Inertia(J=1.0, phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=True))
        self.spring = Spring(c=91.0)
        self.b = Inertia(J=1.0, phi=dict(start=0.0, fixed=True), w=dict(start=1.0, fixed=True))
        self.clutch = Clutch(mu_pos=[[0.0, 0.5]], fn_max=1.0)
        self.c = Inertia(J=2.0, phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=True))
        self.bearing = BearingFriction(tau_pos=[[0.0, 1.0]], peak=self.peak)
        self.engage = Step(height=1.0, startTime=0.25)
        self.connect(self.a.flange_b, self.spring.flange_a)
        self.connect(self.spring.flange_b, self.b.flange_a)
        self.connect(self.b.flange_b, self.clutch.flange_a)
        self.connect(self.clutch.flange_b, self.c.flange_a)
        self.connect(self.c.flange_b, self.bearing.flange_a)
        self.connect(self.engage.y, self.clutch.f_normalized)


class EngageNextToBearingWithoutPeak(EngageNextToBearing):
    peak = 1.0


# A property of the MSL friction equations, reproduced on purpose (found by the
# fuzzing; spec msl-rotational.md, "re-engagement" and "waiting phase").  At
# t = 0.25 the clutch's first event-iteration pass has pre(mode) = Free and no
# start flag, so (F3) makes it *locked* although its slip is 1 rad/s; the
# bearing then takes the spring load of b and of the stopping b itself,
# above tau0_max = 1.5, and startForward becomes true.  In the next
# pass the clutch slides (pre(mode) = Backward) and drags c with 0.5 N.m; the
# bearing's (F1) keeps startForward through ``pre(startForward) and sa > tau0``
# with sa = a_relfric + tau0_max, and (F4) makes a_relfric = sa - tau0_max.
# With tau = tau_pos(0) = tau0 = 1 on c:  2*a = 0.5 - 1, so a = -0.25 rad/s2
# and sa = 1.25 > tau0: the bearing waits in startForward (mode Stuck) while c
# turns backwards, as the spec's waiting phase allows ("it may even be
# negative"); its loss power w*tau is negative.  Dymola and OpenModelica
# iterate the same way (pre() is the previous pass's value), so acausal keeps
# the MSL's behaviour; peak = 1 (no hysteresis band between tau0 and
# tau0_max) does not have it.  The fuzzing skips the mode check of such runs
# (SKIPPED_START_AGAINST_DRIVE) and still audits their energy.
def test_engaging_clutch_next_to_a_bearing_follows_the_msl_waiting_phase():
    """After the engagement c accelerates at (0.5 - tau0)/J = -0.25 rad/s2, bearing in startForward."""
    result = simulate(EngageNextToBearing(), stop_time=0.5, interval=0.05, rtol=1e-8, method="DOP853")
    assert result.status == 0, result.message
    after = result.time > 0.25
    expected = -0.25 * (result.time[after] - 0.25)
    np.testing.assert_allclose(result["c.w"][after], expected, rtol=0, atol=1e-9)
    assert np.all(result["bearing.startForward"][after] == 1)
    assert np.all(result["bearing.mode"][after] == 0)
    np.testing.assert_allclose(result["bearing.sa"][after], 1.25, atol=1e-9)
    assert np.max(np.abs(result["c.w"][~after])) <= 1e-12


def test_engaging_clutch_next_to_a_bearing_without_peak_leaves_it_at_rest():
    """peak = 1: the second pass finds sa = 0.75 < tau0, the bearing locks and holds the 0.5 N.m drag."""
    result = simulate(EngageNextToBearingWithoutPeak(), stop_time=0.5, interval=0.05, rtol=1e-8,
                      method="DOP853")
    assert result.status == 0, result.message
    assert np.max(np.abs(result["c.w"])) <= 1e-9, f"c moves: w down to {np.min(result['c.w']):.3g} rad/s"
    assert np.all(result["bearing.locked"][result.time > 0.25] == 1)
    np.testing.assert_allclose(np.abs(result["bearing.sa"][result.time > 0.25]), 0.5, atol=1e-9)
    assert np.min(result["bearing.lossPower"]) >= -1e-12, "negative friction loss power"
