"""Stage 12: simulation — integrate between events, handle events, record.

A thin driver over scipy's ODE solvers (as ``scipy.integrate.solve_ivp`` is),
written out because hybrid models need what ``solve_ivp`` does not offer:

* relations stay frozen between events; every accepted step the crossing
  functions are sampled on the step's dense output (not only at its ends, so
  two sign changes inside one step are not missed, scipy issue #9228) and a
  crossing is bracketed by bisection to the first instant the relation has
  flipped;
* time events (``time >= startTime``) are hit exactly by ending a segment there;
* at each event the result gets two rows (left and right limit) as the MSL
  reference files have, and event iteration decides the new discrete state,
  whose system is compiled on first visit;
* a failure (solver, event iteration, chattering) ends the run with a
  result that keeps everything computed so far, and the reason.

The loop is here; locating events is in :mod:`acausal.runtime.crossings`
(pure helpers), keeping rows and assembling the result's columns in
:mod:`acausal.runtime.recorder`.  A model of independent parts runs this
loop once per part, each with its own solver (:mod:`acausal.runtime.part_runs`),
when its discrete part links no two of them; otherwise one loop carries them
all, and the result's notes say why.
"""

from __future__ import annotations

import dataclasses
import math
import os
import sys
import time as _time
import warnings
from collections import deque
from typing import TYPE_CHECKING, Callable, Mapping, Sequence

import numpy as np

from ..errors import (AcausalError, AssertionViolation, ChatteringError, InitializationError, ModelDefinitionError,
                      RedundantConstraintWarning, SettingError, SimulationError, SimulationInterrupted, SolverError,
                      StructuralError, ZenoError)
from ..names import base_name, der_name
from ..options import DEFAULT_OPTIONS, EngineOptions
from ..compiler.run_context import activate
from .contract import CompiledModel, CompiledSystem, is_compiled_model
from .delays import DelayHistory
from .crossings import held_roots, locate_flip, next_tick, next_time_event, states_at, step_samples, ticking_at
from .events import evaluator_for, mode_values
from .initialization import initialize
from . import explicit_rk
from .integrators import RK4, Euler
from .part_runs import run_parts, separate_parts
from .recorder import Recorder, generated_line
from .result import Event, SimulationResult, describe_columns

if TYPE_CHECKING:  # a model is translated on demand: the compiler is imported when one is given
    from ..language import Component

__all__ = ["simulate", "METHODS", "MAX_OUTPUT_POINTS"]

#: Most output points a run may write (rows are kept in memory; a finer
#: interval is refused before anything is allocated).
MAX_OUTPUT_POINTS = 10_000_000

class _ScipyMethod:
    """One of scipy's implicit solvers, imported when a run first asks for it."""

    def __init__(self, name: str) -> None:
        self.name = name

    def __call__(self, *args, **kwargs):
        import scipy.integrate

        return getattr(scipy.integrate, self.name)(*args, **kwargs)

    def __repr__(self) -> str:
        return f"scipy.integrate.{self.name}"


#: The integration methods by name. The explicit Runge-Kutta pairs are acausal's own, in
#: numpy (:mod:`.explicit_rk`: the same steps as scipy's, bit for bit); the implicit ones are scipy's.
METHODS = {
    "RK45": explicit_rk.RK45,
    "DOP853": explicit_rk.DOP853,
    "Radau": _ScipyMethod("Radau"),
    "BDF": _ScipyMethod("BDF"),
    "LSODA": _ScipyMethod("LSODA"),
    "Euler": Euler,
    "RK4": RK4,
}


#: Seconds of wall time between two calls of a progress callback.
PROGRESS_PERIOD = 0.1


class TerminalProgress:
    """A one-line progress display on standard error: ``name  [#####.....]  42%  t = 4.2 s``.

    Rewritten in place with a carriage return; :meth:`close` ends the line.
    """

    def __init__(self, name: str, stream=None, width: int = 30) -> None:
        self.name = name
        self.stream = sys.stderr if stream is None else stream
        self.width = width
        self.drawn = False

    def __call__(self, t: float, t0: float, t1: float) -> None:
        share = min(max((t - t0) / (t1 - t0), 0.0), 1.0) if t1 > t0 else 1.0
        done = int(round(share * self.width))
        self.stream.write(f"\r{self.name}  [{'#' * done}{'.' * (self.width - done)}]  "
                          f"{share * 100:3.0f}%  t = {t:.6g}")
        self.stream.flush()
        self.drawn = True

    def close(self) -> None:
        if self.drawn:
            self.stream.write("\n")
            self.stream.flush()
            self.drawn = False


def _quiet_by_default() -> bool:
    """No progress line unless standard error is a terminal, outside CI and pytest."""
    stream = sys.stderr
    return (not (hasattr(stream, "isatty") and stream.isatty()) or bool(os.environ.get("CI"))
            or "PYTEST_CURRENT_TEST" in os.environ)


def progress_reporter(progress, name: str) -> "Callable[[float, float, float], object] | None":
    """The callable ``simulate`` reports progress to (None: none), from its ``progress`` argument."""
    if progress is None:
        return None if _quiet_by_default() else TerminalProgress(name)
    if progress is True:
        return TerminalProgress(name)
    if progress is False:
        return None
    if callable(progress):
        return progress
    raise SettingError(f"progress must be True, False, None or a callable, not {progress!r}",
                       hint="progress(t, start_time, stop_time) is called as the run advances")


def simulate(model: "Component | CompiledModel", *, start_time: float | None = None,
             stop_time: float | None = None, interval: float | None = None, method: str | None = None,
             rtol: float | None = None, atol: float | None = None, max_step: float | None = None,
             relation_epsilon: float = 1e-10, max_event_iterations: int = 20,
             chattering_events: int = 100, outputs: Sequence[str] | None = None,
             max_steps: int | None = None, timeout: float | None = None,
             cache: bool = True, parameters: Mapping[str, float] | None = None,
             redundant_constraints: str = "relax",
             progress: "bool | Callable[[float, float, float], object] | None" = None,
             start: Mapping[str, float] | None = None, options: EngineOptions | None = None) -> SimulationResult:
    """Simulate a model.

    Parameters
    ----------
    model : Model instance or Translation
        A model, or the result of :func:`acausal.compiler.translate.translate` to
        reuse compiled systems.
    start_time, stop_time, interval : float, optional
        Default to the model's experiment annotation (interval: 500 points).
        At most :data:`MAX_OUTPUT_POINTS` output points.
    method : {'RK45', 'DOP853', 'Radau', 'BDF', 'LSODA', 'Euler', 'RK4'}, optional
        The last two have a fixed step, ``max_step``.  Defaults to the
        experiment's ``method`` (a stiff model names an implicit one, as
        Modelica models name theirs in the experiment annotation), else RK45.
    rtol, atol : float, optional
        ``rtol`` (0 < rtol < 1) defaults to the experiment's tolerance or
        1e-6; ``atol`` (>= 0) to ``rtol`` times each state's nominal value.
    max_step : float, optional
        Largest step (> 0); the step of the fixed-step methods.
    relation_epsilon : float
        Relative hysteresis of relations (see :mod:`acausal.compiler.partition`).
    max_event_iterations : int
        Passes of event iteration before it is declared not converging.
    chattering_events : int
        That many state events in a row within a vanishing time window stop
        the run with a :class:`~acausal.errors.ChatteringError`.
    outputs : sequence of str, optional
        Compute only these variables: states and equations that cannot
        influence them (nor the events) are left out of the right-hand side,
        and the result holds only these columns (and the discrete ones).
    max_steps, timeout : optional
        Budgets of integrator steps and wall-clock seconds, checked wherever
        time goes (steps, output points, compiling discrete states, event
        iteration); a run that exceeds one stops with a
        :class:`~acausal.errors.SolverError` that says where the time went,
        and keeps what it computed.
    cache : bool
        Reuse the compiled systems of an identical flat model translated
        before in this process (see :func:`~acausal.compiler.translate.translate`).
    parameters : mapping, optional
        New values of numeric parameters by dotted name, e.g.
        ``{"clutch1.fn_max": 100}``: parameters are tunable, as in Modelica, so
        the systems compiled for the model's own values are reused with a new
        parameter vector.  A value that changes the equations (a zero, which
        removes the terms it multiplies; a parameter a relation compares with
        a constant) makes a new translation, and the result's notes say so.
        Structural parameters (``structural=True``) are set when the model is
        built.  ``"J1.w.start"`` is a start value (as in ``start``).
    start : mapping, optional
        Start values by variable name, e.g. ``{"J1.w": 3.0, "housing.T":
        300}``, in place of the model's (OMPython's ``setParameters``, FMPy's
        ``start_values``).  The start values initialization reads, those of
        the states and of the variables with ``fixed=True``, are inputs of
        the generated code: the compiled systems are reused, and the result
        is the one the same value given as a modifier
        (``Inertia(w=dict(start=3))``) gives.  A Newton iteration whose first
        guess is such a start value is compiled anew, and the result's notes
        say so.  Unknown names, values that are not finite numbers, and
        variables whose start is not read by initialization raise a
        :class:`~acausal.errors.ParameterError`.
    progress : bool or callable, optional
        ``progress(t, start_time, stop_time)`` is called as the run advances
        (at most every :data:`PROGRESS_PERIOD` seconds of wall time, and once
        at the end).  True draws a progress line on standard error; the
        default (None) draws it only when standard error is a terminal and
        neither ``CI`` nor pytest is running, so pipes and tests stay quiet.
    redundant_constraints : {'relax', 'error'}
        What a discrete state gets in which two elements constrain the same
        motion (both stuck on one rigid shaft): a split of the holding force
        picked as Modelica tools do, with a warning, or the error (see
        :func:`~acausal.compiler.translate.translate`).  A translation
        given as ``model`` keeps its own choice.
    options : EngineOptions, optional
        How the engine works (:class:`~acausal.options.EngineOptions`), for
        the translation and for this run.  With a translation as ``model``,
        its own options by default; options given then may differ from the
        translation's only in the runtime's fields.

    Returns
    -------
    SimulationResult
        ``status`` 0 on success; -1 with ``message`` and ``error`` set, and
        everything computed so far, when the run stopped early.  A value that
        is not finite (a state, a derivative, a relation's side or an output)
        stops the run with an error naming it and the time.  After a
        successful run, the components of ``model`` whose class defines
        :meth:`~acausal.language.Component.finished` are given the result
        (not when ``model`` is a translation); a
        :class:`~acausal.errors.SimulationError` one raises makes it a failure.

    Raises
    ------
    SettingError
        For a setting out of range (before anything is computed).
    SimulationInterrupted
        On Ctrl-C (a ``KeyboardInterrupt``); its ``result`` is the partial
        result, status -2.
    """
    if method is not None and method not in METHODS:
        raise SettingError(f"unknown method {method!r}", hint=f"choose one of {', '.join(METHODS)}")
    t_setup = _time.perf_counter()
    given_model = not is_compiled_model(model)
    if not given_model:
        if outputs is not None and model.demand != frozenset(outputs):
            raise ValueError("outputs must be given to translate() when simulating a Translation")
        for given, what in ((parameters, "parameters"), (start, "start")):
            if given:
                raise SettingError(f"{what}= needs the model, not a translation",
                                   hint=f"simulate(model, {what}={{...}}) reuses the compiled systems")
        translation = model
        if options is not None and options.compiler_key != translation.options.compiler_key:
            raise SettingError(f"options {options} differ from those {model.data.name} was translated with "
                               f"({translation.options}) in the compiler's fields",
                               hint="translate(model, options=...) with these options, or simulate(model, "
                                    "options=...)")
    else:
        # the compiler, for a model (a translation given was made by it: already loaded)
        from ..compiler.translate import translate, with_start_values

        parameters = with_start_values(parameters, start)
        translation = translate(model, outputs, cache=cache, parameters=parameters,
                                redundant_constraints=redundant_constraints, options=options)
        # a cached translation may have been made for other runtime options: these are the run's
        options = DEFAULT_OPTIONS if options is None else options
    flatten_seconds = _time.perf_counter() - t_setup
    experiment = translation.data.experiment
    t0 = experiment.start_time if start_time is None else start_time
    t1 = experiment.stop_time if stop_time is None else stop_time
    t0, t1 = _finite_time("start time", t0), _finite_time("stop time", t1)
    if not t1 > t0:
        raise SettingError(f"stop time {t1:g} must be after start time {t0:g}")
    if interval is None:
        interval = experiment.interval or (t1 - t0) / 500
    if rtol is None:
        rtol = experiment.tolerance or 1e-6
    if method is None:
        method = experiment.method or "RK45"
        if method not in METHODS:
            raise SettingError(f"the experiment's method {method!r} is unknown",
                               hint=f"choose one of {', '.join(METHODS)}")
    _check_settings(t0, t1, interval, method, rtol, atol, max_step, relation_epsilon,
                    max_event_iterations, chattering_events, max_steps, timeout)
    reporter = progress_reporter(progress, translation.data.name)
    # translation time of this call: flattening (unless cached) plus the systems
    # compiled during the run (a reused translation may have them all already)
    compile_seconds_before = translation.translation_seconds - flatten_seconds
    structural = _structural_notes(translation, parameters)

    def make_run(compiled: CompiledModel) -> _Run:
        return _Run(compiled, method, float(rtol), atol, max_step, relation_epsilon, max_event_iterations,
                    chattering_events, options)

    # independent parts, each integrated with a solver of its own (acausal.runtime.part_runs)
    models, why = separate_parts(translation, atol, (translation.options if options is None else options).parts_apart)
    if models:
        wall = _time.perf_counter()
        result, why = run_parts(translation, models, make_run, t0, t1, float(interval), t_setup,
                                notes=structural, progress=reporter, max_steps=max_steps, timeout=timeout,
                                compile_seconds_before=compile_seconds_before)
        if isinstance(reporter, TerminalProgress):
            reporter.close()
        if result is not None:
            return _finish(model, parameters, result) if given_model else result
        if timeout is not None:
            timeout = max(timeout - (_time.perf_counter() - wall), 0.0)
    run = make_run(translation)
    run.notes.extend(structural)
    if why:
        run.notes.append(f"the independent parts were integrated with one solver: {why}")
    run.max_steps, run.timeout = max_steps, timeout
    run.progress = reporter
    run.compile_seconds_before = compile_seconds_before
    result = run.execute(t0, t1, float(interval), t_setup)
    if result.success and given_model:
        result = _finish(model, parameters, result)
    return result


def _finish(model: Component, parameters: Mapping[str, float] | None,
            result: SimulationResult) -> SimulationResult:
    """Call the finish hooks (:meth:`~acausal.language.Component.finished`) of a successful run.

    A SimulationError a hook raises makes the run a failure (the result, status -1,
    with that error); the hooks after it are not called.
    """
    from ..language import finish_hooks, structural_names, with_structural

    hooks = finish_hooks(model)
    if not hooks:
        return result  # no class defines a hook (no walk), or none of this model's components
    structural = structural_names(model, parameters or {})
    if structural:
        # the run simulated an instance built anew for these values (translate()): its
        # components, not the given model's, are the ones that ran
        hooks = finish_hooks(with_structural(model, {n: parameters[n] for n in structural}))
    for component in hooks:
        try:
            component.finished(result)
        except SimulationError as exc:
            return dataclasses.replace(result, status=-1, message=str(exc), error=exc)
    return result


def _structural_notes(translation: CompiledModel, parameters: Mapping[str, float] | None) -> list[str]:
    """Which of the parameters given change the equations, so that the model was translated for them."""
    notes = []
    structural = translation.data.structural_parameters
    for name in sorted(parameters or ()):
        value = translation.data.parameter_table.get(name)
        if name not in structural and name not in translation.data.parameter_values:
            continue  # a start value: it decides no equation
        if name in structural:
            notes.append(f"{name} = {structural[name]!r} is a structural parameter: the model was built "
                         f"and translated anew for this value")
        elif name in translation.data.evaluated_parameters:
            notes.append(f"{name} = {value:g} decides a relation of parameters alone: it is structural, "
                         f"and the model was translated for this value")
        elif value == 0:
            notes.append(f"{name} = 0 removes the terms it multiplies (a structural zero): the model was "
                         f"translated for this value")
    return notes


def _finite_time(what: str, value) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise SettingError(f"{what} must be a number, not {value!r}") from None
    if not math.isfinite(value):
        raise SettingError(f"{what} must be finite, not {value}")
    return value


def _check_settings(t0, t1, interval, method, rtol, atol, max_step, relation_epsilon,
                    max_event_iterations, chattering_events, max_steps, timeout) -> None:
    """Every setting in range, before anything is allocated or integrated."""
    def number(what, value, low=None, high=None, *, strict_low=True, allow_inf=False, hint=None):
        try:
            value = float(value)
        except (TypeError, ValueError):
            raise SettingError(f"{what} must be a number, not {value!r}") from None
        bad = math.isnan(value) or (math.isinf(value) and not allow_inf)
        bad = bad or (low is not None and (value <= low if strict_low else value < low))
        bad = bad or (high is not None and value >= high)
        if bad:
            limits = []
            if low is not None:
                limits.append(f"{'>' if strict_low else '>='} {low:g}")
            if high is not None:
                limits.append(f"< {high:g}")
            raise SettingError(f"{what} = {value} is out of range; it must be "
                               f"{'finite and ' if not allow_inf else ''}{' and '.join(limits)}", hint=hint)
        return value

    def count(what, value, low):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
            raise SettingError(f"{what} = {value!r} must be an integer >= {low}")

    interval = number("interval", interval, 0.0, hint="the output interval, e.g. (stop - start) / 500")
    points = (t1 - t0) / interval + 1
    if points > MAX_OUTPUT_POINTS:
        raise SettingError(f"interval {interval:g} over [{t0:g}, {t1:g}] would write {points:.3g} output "
                           f"points (at most {MAX_OUTPUT_POINTS:,})",
                           hint="choose a coarser interval; events are located exactly whatever "
                                "the interval")
    number("rtol", rtol, 0.0, 1.0, hint="a relative tolerance such as 1e-6")
    if atol is not None:
        values = np.atleast_1d(np.asarray(atol, dtype=float)) if not isinstance(atol, str) else None
        if values is None or not np.all(np.isfinite(values)) or np.any(values < 0):
            raise SettingError(f"atol = {atol!r} must be finite and >= 0 (a number or one per state)")
    if max_step is not None:
        number("max_step", max_step, 0.0, allow_inf=method not in ("Euler", "RK4"),
               hint="the largest step, or the step of Euler and RK4")
    number("relation_epsilon", relation_epsilon, 0.0, strict_low=False)
    count("max_event_iterations", max_event_iterations, 1)
    count("chattering_events", chattering_events, 2)
    if max_steps is not None:
        count("max_steps", max_steps, 1)
    if timeout is not None:
        number("timeout", timeout, 0.0, allow_inf=True)


class _Budget(Exception):
    """A budget ran out (internal: turned into a SolverError saying where the time went)."""


class _Run:
    """One simulation run: the loop over segments and events (state in attributes)."""

    #: Most output rows evaluated and written at once (memory and budget checks stay bounded).
    _ROWS_AT_ONCE = 65536

    def __init__(self, translation: CompiledModel, method, rtol, atol, max_step, relation_epsilon,
                 max_event_iterations, chattering_events, options: EngineOptions | None = None) -> None:
        self.translation = translation
        options = translation.options if options is None else options
        self.evaluator = evaluator_for(translation, relation_epsilon, max_event_iterations,
                                       options.incremental_events)
        #: whether the flip instant of a single relation is searched with regula falsi
        #: (Illinois) rather than by halving alone (:func:`~acausal.runtime.crossings.bisect_flip`)
        self.secant = options.secant
        self.relations = translation.data.relations
        self.method = method
        self.rtol = rtol
        self.atol = atol
        self.max_step = np.inf if max_step is None else max_step
        #: the run's history for delay() (None: the model has none, and pays nothing)
        self.delays = (DelayHistory(translation.data.delays, translation.delay_numbers())
                       if translation.data.delays else None)
        if self.delays is not None:
            # t - T never lies in the step being taken (fixed delays)
            self.max_step = min(self.max_step, self.delays.max_step)
        self.chattering_events = chattering_events
        self.events: list[Event] = []
        self.terminated: tuple | None = None  #: (time, messages) of a terminate()
        self.modes: list[str] = []
        self._modes_seen: set[str] = set()  #: (the same, for the test of a new one)
        self.notes: list[str] = []
        #: how many notes the translation had before this run (its later ones are this run's)
        self.translation_notes_before = len(translation.notes)
        self.nfev = 0
        self.steps = 0
        self.max_steps: int | None = None
        self.timeout: float | None = None
        self.progress: Callable[[float, float, float], object] | None = None
        self._next_progress = 0.0
        self.t_start = self.t_stop = 0.0
        # where the wall time goes, for a budget's message
        self.seconds = {"output": 0.0, "events": 0.0}
        self._static_time_roots, self._held_time_events = translation.time_events()
        self._time_roots = self._static_time_roots
        try:
            self._ticks = translation.clock_ticks()
        except ValueError as exc:
            raise ModelDefinitionError(str(exc), hint="sample(start, interval) needs an interval > 0") \
                from exc
        self._clock_texts = [c.text for c in translation.data.clocks]
        #: state events per relation and direction: their last times (Zeno detection)
        self._state_event_times: dict[tuple, list[float]] = {}
        self._relation_of_text = {rel.text: rel.index for rel in self.relations}
        self._relations_of_text: dict[str, tuple[int, ...]] = {}
        for k, rel in enumerate(self.relations):
            self._relations_of_text[rel.text] = (*self._relations_of_text.get(rel.text, ()), k)
        self._warned: set = set()
        #: per system entered: (system, its states' nominal values, their derivatives' names)
        self._per_system: dict[int, tuple] = {}
        #: the accepted steps with their dense output, kept for rows at other instants (a part
        #: integrated apart, :mod:`acausal.runtime.part_runs`); None: not kept
        self.history = None

    def _update_time_roots(self, values) -> None:
        """Time events at instants set by held discrete Reals move when those are set."""
        if self._held_time_events:
            self._time_roots = self._static_time_roots + held_roots(self._held_time_events, values)

    def _next_time_event(self, t: float, relations) -> float:
        found = next_time_event(t, self._time_roots, self.relations, relations)
        if self._ticks:
            found = min(found, next_tick(t, self._ticks)[0])
        return found

    # -- main loop ----------------------------------------------------------------

    def execute(self, t0: float, t1: float, interval: float, t_setup: float) -> SimulationResult:
        # every run starts the compiled functions' Newton solves from the start values,
        # not from where an earlier run of this translation left them: runs repeat exactly
        self.translation.reset_warm_starts()
        if self.delays is None:
            return self._execute(t0, t1, interval, t_setup)
        # the generated code of this thread reads this run's history (initialization,
        # integration, events and the result's columns)
        with activate(self.delays):
            return self._execute(t0, t1, interval, t_setup)

    def _execute(self, t0: float, t1: float, interval: float, t_setup: float) -> SimulationResult:
        error = None
        status = -1
        message = "The simulation reached the stop time."
        self.recorder = Recorder(t0, t1, interval)
        self.wall_start = _time.perf_counter()
        self.t_start, self.t_stop = t0, t1
        self._next_progress = self.wall_start + PROGRESS_PERIOD
        self.compiled_before_run = self.translation.translation_seconds
        self.t = t0
        try:
            try:
                state = initialize(self.translation, self.evaluator, t0)
            except (ArithmeticError, ValueError, np.linalg.LinAlgError, SolverError) as exc:
                if isinstance(exc, AcausalError) and not isinstance(exc, SolverError):
                    raise  # already says what is wrong with the initial values
                # nothing is computed yet: a failure here is the initial values' problem
                raise self._initialization_error(exc) from exc
            self.notes.extend(state.notes)
            outcome = state.outcome
            # Like Dymola, only the values after the post-initialization event
            # iteration are written at the start time (one row, not two).
            self._add_event(t0, "initial", tuple(self._clock_texts[k] for k in sorted(state.ticks)), outcome)
            try:
                if outcome.terminated:
                    self.recorder = Recorder(t0, t1, interval)
                    x = np.array([outcome.values[s] for s in outcome.system.states], dtype=float)
                    self.recorder.add(t0, outcome.system, x, outcome.discrete)
                    self.terminated = (t0, outcome.terminated)
                else:
                    self._integrate(t0, t1, outcome)
            except StructuralError as exc:
                # a discrete state reached during the run cannot be solved: stop
                # with the reason, keeping what was computed
                t_fail = self.recorder.last_time if self.recorder.row_count else t0
                raise SolverError(f"at t = {t_fail:.12g} the model entered a discrete state it "
                                  f"cannot solve: {exc.message}", hint=exc.hint,
                                  components=exc.components) from exc
        except _Budget as exc:
            error = self._budget_error(str(exc))
        except SimulationError as exc:
            error = exc
        except KeyboardInterrupt:
            t_now = self.recorder.last_time if self.recorder.row_count else t0
            error = SimulationInterrupted(f"interrupted at t = {t_now:.12g} (Ctrl-C); the result "
                                          f"holds what was computed until then")
            status = -2
        except (ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
            if isinstance(exc, SimulationError) or type(exc).__module__.startswith("acausal"):
                raise
            error = SolverError(f"the simulation stopped: {type(exc).__name__}: {exc}")
        if error is not None:
            message = str(error)
        elif self.terminated is not None:
            t_end, reasons = self.terminated
            message = f"terminate() at t = {t_end:.12g}: {'; '.join(reasons)}"
            status = 1
        if self.progress is not None:
            self.progress(self.recorder.last_time if self.recorder.row_count else t0, t0, t1)
            if isinstance(self.progress, TerminalProgress):
                self.progress.close()
        result = self._result(t_setup, message, error, status)
        if isinstance(error, SimulationInterrupted):
            raise result.error
        return result

    def _initialization_error(self, exc: BaseException) -> InitializationError:
        """A failure while solving for the initial values, naming the variable and the equation."""
        translation = self.translation
        # (snapshots of the tables: a sweep's threads share them and may add to them meanwhile)
        sources = [source for s in tuple(translation.initial_systems.values()) for source in s.sources]
        sources += [source for s in tuple(translation.systems.values()) for source in s.sources]
        variable, line = generated_line(exc, sources, translation.data.identifiers)
        what = exc.message if isinstance(exc, AcausalError) else f"{type(exc).__name__}: {exc}"
        where = (f" computing {variable} ({line})" if line and variable != "a value"
                 else f" in: {line}" if line else "")
        if len(where) > 300:  # a long generated line (a Newton call with its equations)
            where = where[:297] + "..."
        return InitializationError(
            f"initialization of {translation.data.name} failed{where}: {what}",
            hint=(exc.hint if isinstance(exc, AcausalError) and exc.hint else
                  "the initial values make an equation leave its domain (a division by a zero "
                  "parameter or value, a root of a negative number); check the start values and "
                  "the parameters of the components named"),
            components=tuple(dict.fromkeys(n.rpartition(".")[0] for n in [variable] if "." in n)))

    def _record_mode(self, system: CompiledSystem) -> None:
        if system.description not in self._modes_seen:
            self._modes_seen.add(system.description)
            self.modes.append(system.description)
            relaxed = getattr(system, "relaxed", None)
            if relaxed is not None:
                # said by the run, not by the compiler: a system loaded from the
                # disk cache (or compiled by an earlier run) warns as a new one does
                message = relaxed.message(self.translation.data.name, system.description)
                self.notes.append(message)
                warnings.warn(message, RedundantConstraintWarning, stacklevel=4)

    def _integrate(self, t: float, t1: float, outcome) -> None:
        recorder = self.recorder
        system = outcome.system
        discrete = outcome.discrete
        relations = outcome.relations
        values = outcome.values
        self._record_mode(system)
        self._update_time_roots(values)
        x = np.array([values[s] for s in system.states], dtype=float)
        recorder.add(t, system, x, discrete)
        delays = self.delays
        if delays is not None:
            delays.add_point(t, x, system)
            delays.discontinuity(t, 0, t1)
        # assertions hold from the start: a violated one stops the run at its first row
        self._check_asserts(t, system, x, discrete)
        recorder.skip_grid_through(t, round_off=False)
        recent = deque(maxlen=self.chattering_events)
        while t < t1:
            self.t = t
            self._check_budgets()
            t_bound = min(t1, self._next_time_event(t, relations))
            if delays is not None:
                t_bound = min(t_bound, delays.next_break(t))
                delays.segment_start = t
            if not system.states and not self.evaluator.relevant_relations(discrete, relations):
                # nothing to integrate and no crossing to look for: straight to the next time event
                self._emit(t_bound, False, system, lambda s: x, discrete)
                if self.history is not None:
                    self.history.add(t, t_bound, None, x, system, discrete)
                t_new, x_new, event_at = t_bound, x, None
            else:
                t_new, x_new, event_at = self._segment(system, t, x, t_bound, discrete, relations)
            if delays is not None and event_at is None and t_new < t1 and delays.pass_break(t_new, t1) \
                    and self._next_time_event(t, relations) != t_new:
                # a discontinuity of a delayed value: the integrator restarts here, no event
                t, x = t_new, np.array(x_new, dtype=float)
                continue
            if event_at is not None:
                t_e, x_e, fired = event_at
                kind = "state"
                ticks = frozenset()
                recent.append((t_e, fired, tuple(sorted(discrete.items()))))
                self._check_chattering(recent, t1)
                self._check_zeno(t_e, fired, t1, relations)
            elif t_new >= t1 and not (self._next_time_event(t, relations) == t_new and (
                    any(root == t_new for _, root in self._time_roots) or ticking_at(t_new, self._ticks))):
                self._check_asserts(t_new, system, x_new, discrete)
                recorder.add(t_new, system, x_new, discrete)
                self._terminal_iteration(t_new, system, x_new, discrete, relations)
                return
            else:
                # a time event (also one exactly at the stop time: it is processed,
                # and the run ends on its right limit)
                t_e, x_e = t_new, np.array(x_new, dtype=float)
                fired = tuple(self.relations[i].text for i, root in self._time_roots if root == t_e)
                ticks = ticking_at(t_e, self._ticks) if self._ticks else frozenset()
                fired += tuple(self._clock_texts[k] for k in sorted(ticks))
                kind = "time"
                # time events that do not move time on (a relation that keeps firing at its
                # own instant) are chattering too
                recent.append((t_e, fired, tuple(sorted(discrete.items()))))
                self._check_chattering(recent, t1)
            # left limit, event iteration, right limit
            recorder.add(t_e, system, x_e, discrete)
            self.t = t_e
            started = _time.perf_counter()
            compiled = self.translation.translation_seconds
            values = mode_values(system, t_e, x_e)
            fired_indices = frozenset(k for text in fired for k in self._relations_of_text.get(text, ()))
            outcome = self.evaluator.iterate(t_e, values, discrete, relations, fired=fired_indices,
                                             ticks=ticks)
            # (compiling a newly visited state is counted apart, from the pass logs)
            self.seconds["events"] += (_time.perf_counter() - started
                                       - (self.translation.translation_seconds - compiled))
            self._add_event(t_e, kind, tuple(fired), outcome)
            system, discrete, relations = outcome.system, outcome.discrete, outcome.relations
            self._record_mode(system)
            self._update_time_roots(outcome.values)
            x = np.array([outcome.values[s] for s in system.states], dtype=float)
            _check_finite(t_e, system.states, x, "the states after the event")
            if delays is not None:
                delays.add_point(t_e, x, system)
                delays.discontinuity(t_e, 0, t1)
            self._check_asserts(t_e, system, x, discrete)
            recorder.add(t_e, system, x, discrete)
            t = t_e
            if outcome.terminated:
                self.terminated = (t_e, outcome.terminated)
                return
            if t >= t1:
                self._terminal_iteration(t, system, x, discrete, relations)
                return
            # a grid point at the event time is represented by the two event rows
            recorder.skip_grid_through(t_e)

    def _add_event(self, t: float, kind: str, fired: tuple, outcome) -> None:
        changes = outcome.changes + tuple((f"reinit({n})", a, b) for n, a, b in outcome.reinits)
        self.events.append(Event(t, kind, fired, changes, outcome.iterations))

    def _check_asserts(self, t: float, system: CompiledSystem, x, discrete, terminal: bool = False,
                       pre=None) -> None:
        """Assertions at an accepted step, after an event or at the end (``terminal``, with the
        ``pre`` values before its event iteration): an error stops the run (what was computed is
        kept), a warning is noted once per assertion."""
        for item, message in self.evaluator.check_asserts(t, system, x, discrete, discrete if pre is None else pre,
                                                          terminal=terminal):
            if item.level == "error":
                raise AssertionViolation(message, hint="the model's own assertion; the result holds "
                                                       "the run up to the last accepted step",
                                         components=(item.origin.component,))
            if id(item) not in self._warned:
                self._warned.add(id(item))
                self.notes.append(message)

    def _asserts_in_step(self, rows, at_rows, dense, y_new, t_new: float, system: CompiledSystem, discrete) -> None:
        """Assertions at the output points of a step: the rows before the first one that
        violates an error-level assertion are written, and the run stops there."""
        if not len(rows):
            return
        states = at_rows if at_rows is not None else (states_at(dense, rows) if dense is not None else
                                                      np.tile(y_new, (len(rows), 1)))
        for i, (t_row, x_row) in enumerate(zip(rows, states)):
            try:
                self._check_asserts(float(t_row), system, x_row, discrete)
            except AssertionViolation:
                self._emit_rows(rows[:i + 1], states[:i + 1], system, discrete)
                raise

    def _terminal_iteration(self, t: float, system: CompiledSystem, x, discrete, relations) -> None:
        """At the end of a successful run, ``terminal()`` is true in one more event
        iteration (only if the model uses it); its values are the last row."""
        if not self.evaluator.uses_terminal:
            return
        values = mode_values(system, t, x)
        outcome = self.evaluator.iterate(t, values, discrete, relations, terminal=True)
        self._add_event(t, "terminal", ("terminal()",), outcome)
        x = np.array([outcome.values[s] for s in outcome.system.states], dtype=float)
        self.recorder.add(t, outcome.system, x, outcome.discrete)
        # an assertion of a when-clause with terminal() (Modelica's check at the end of a run)
        self._check_asserts(t, outcome.system, x, outcome.discrete, terminal=True, pre=discrete)

    #: Zeno detection: this many state events of one relation in a row whose intervals
    #: shrink by a steady ratio ...
    ZENO_EVENTS = 12
    #: ... below this ratio ...
    ZENO_RATIO = 0.98
    #: ... until the interval is this fraction of the run's span.
    ZENO_SPAN = 1e-4

    def _check_zeno(self, t_e: float, fired: tuple, t1: float, relations) -> None:
        """Events of one relation that accumulate at a finite time (a ball bouncing to rest).

        The intervals between its last events shrink geometrically with a steady
        ratio ``r``, the last one is below ``ZENO_SPAN`` of the run's span, and the
        events would accumulate at ``t* = t_e + dt*r/(1 - r)``.  Without this rule
        the intervals would shrink until the relation's margin (1e-10) swallows a
        bounce and the ball falls through the floor: a wrong result, silently.
        """
        span = t1 - self.recorder.grid[0]
        index = self._relation_of_text
        for name in fired:
            # a relation's flips one way (h <= 0 becoming true) are timed apart from its flips back
            times = self._state_event_times.setdefault((name, bool(relations[index[name]])), [])
            times.append(t_e)
            if len(times) > self.ZENO_EVENTS + 1:
                del times[0]
            if len(times) <= self.ZENO_EVENTS:
                continue
            gaps = np.diff(times)
            if gaps[-1] > self.ZENO_SPAN * span or np.any(gaps <= 0):
                continue
            ratios = gaps[1:] / gaps[:-1]
            if not (np.all(ratios < self.ZENO_RATIO) and ratios.max() - ratios.min() < 0.1 * ratios.mean()):
                continue
            r = float(np.exp(np.mean(np.log(ratios))))
            t_star = t_e + gaps[-1] * r / (1 - r)
            owners = self.relations[index[name]].components
            raise ZenoError(
                f"Zeno behaviour: the events of {name} come ever faster (each interval {r:.3g} times "
                f"the one before, the last {gaps[-1]:.3g} s) and would accumulate at "
                f"t = {t_star:.12g}; the run stops at the last event, t = {t_e:.12g}",
                hint="an infinite number of events in finite time (a ball bouncing to rest); add a "
                     "rule to the model that ends it, e.g. a Boolean that stops the bouncing when the "
                     "speed after an impact is small (see docs/hybrid.md)", components=owners)

    def _emit(self, t_end: float, inclusive: bool, system: CompiledSystem, x_at, discrete) -> None:
        """Output points up to ``t_end`` (timed, and within the budgets)."""
        started = _time.perf_counter()
        try:
            self.recorder.emit_grid_until(t_end, inclusive, system, x_at, discrete,
                                          check=self._check_budgets if self.timeout is not None else None)
        finally:
            self.seconds["output"] += _time.perf_counter() - started

    def _emit_rows(self, times, states, system: CompiledSystem, discrete) -> None:
        """Rows at the next output points ``times``, states given as rows (timed, within the
        budgets, a block of at most ``_ROWS_AT_ONCE`` rows at a time)."""
        block = self._ROWS_AT_ONCE
        for k in range(0, len(times), block):
            started = _time.perf_counter()
            try:
                self.recorder.emit_rows(times[k:k + block], states[k:k + block], system, discrete,
                                        check=self._check_budgets if self.timeout is not None else None)
            finally:
                self.seconds["output"] += _time.perf_counter() - started

    def _emit_step(self, rows, at_rows, dense, y_new, t_new: float, system: CompiledSystem, discrete) -> None:
        """The output points ``rows`` of a step ending at ``t_new``: states from ``at_rows``
        (None: from the dense output, a block at a time), the step's own value at
        its end (up to round-off)."""
        near = 1e-12 * max(1.0, abs(t_new))
        block = self._ROWS_AT_ONCE
        for k in range(0, len(rows), block):
            part = rows[k:k + block]
            started = _time.perf_counter()
            if at_rows is not None:
                states = at_rows[k:k + block]
            elif dense is not None:
                states = states_at(dense, part)
            else:
                states = np.empty((len(part), len(y_new)))
            at_end = np.abs(part - t_new) <= near
            if dense is None:
                at_end[:] = True
            states[at_end] = y_new
            self.seconds["output"] += _time.perf_counter() - started
            self._emit_rows(part, states, system, discrete)

    def _check_chattering(self, recent: deque, t1: float) -> None:
        """Chattering: many state events in a row, ping-ponging between at most
        two discrete states, within a vanishing window (a millionth of the
        span, or a microsecond) — far below any physical period."""
        window = max(1e-6 * (t1 - self.recorder.grid[0]), 1e-6)
        if not (len(recent) == recent.maxlen and recent[-1][0] - recent[0][0] <= window
                and len({d for _, _, d in recent}) <= 2):
            return
        counts: dict = {}
        for _, names, _ in recent:
            for n in names:
                counts[n] = counts.get(n, 0) + 1
        worst = max(counts, key=counts.get)
        states = list(recent)
        changing = sorted({n for (_, _, a), (_, _, b) in zip(states, states[1:])
                           for (n, va), (_, vb) in zip(a, b) if va != vb})
        fired = {text for _, names, _ in recent for text in names}
        owners = tuple(dict.fromkeys([*(c for r in self.relations if r.text in fired for c in r.components),
                                      *(n.rpartition(".")[0] for n in changing)]))
        own = self.translation.data.hints_for("chattering", owners)
        raise ChatteringError(
            f"chattering: {len(recent)} events between t = {recent[0][0]:.12g} "
            f"and {recent[-1][0]:.12g}; the crossing firing most is {worst}",
            hint="; ".join(("the model switches back and forth without time passing; check the "
                            "relation named (a threshold that its own switching crosses)", *own)),
            components=owners)

    def _names_of(self, system: CompiledSystem) -> tuple[np.ndarray, list[str]]:
        """The nominal values of ``system``'s states and the names of their derivatives,
        made once per system in a run (a run enters the same few modes again and again)."""
        found = self._per_system.get(id(system))
        if found is None or found[0] is not system:
            variables = self.translation.data.variable_map
            found = self._per_system[id(system)] = (
                system, np.array([variables[base_name(s)].nominal for s in system.states]),
                [der_name(s) for s in system.states])
        return found[1], found[2]

    def _segment(self, system: CompiledSystem, t: float, x, t_bound: float, discrete, relations):
        """Integrate one mode until t_bound or the first crossing.

        Returns ``(t_end, x_end, event)``, event = ``(t_e, x_e, fired names)`` or None.
        """
        recorder = self.recorder
        states = system.states
        nominal, derivative_names = self._names_of(system)
        atol = self.rtol * nominal if self.atol is None else self.atol
        # A derivative that is not finite at the start would give the solver a
        # NaN first step, and some of scipy's solvers then never return.
        _check_finite(t, states, x, "the states")
        _check_finite(t, derivative_names, system.derivatives(t, x), "the derivatives")
        evaluator = self.evaluator
        watched = evaluator.relevant_relations(discrete, relations)
        if watched:
            _check_crossings(t, system, x, watched, self.relations)

        def fun(tt, xx):
            return np.array(system.derivatives(tt, xx), dtype=float)

        solver = METHODS[self.method](fun, t, x, t_bound, rtol=self.rtol, atol=atol,
                                      max_step=self.max_step)

        def flipped(tt, xx):
            return evaluator.flipped_relations(system, tt, xx, relations, watched)

        def first_flip(times, states):
            return evaluator.first_flip(system, times, states, relations, watched)

        def narrow(candidates):
            return evaluator.flip_search(system, relations, candidates, self.secant)

        try:
            while True:
                t_old = solver.t
                self.t = t_old
                message = solver.step()
                self.steps += 1
                self._check_budgets()
                if solver.status == "failed":
                    raise SolverError(f"{self.method} failed at t = {solver.t:.12g}: {message}",
                                      hint="try a smaller tolerance, an implicit method (Radau, BDF) "
                                           "or a max_step")
                t_new = solver.t
                # an accepted step: finite states and derivatives, and time moving on
                _check_finite(t_new, states, solver.y, "the states")
                f_new = getattr(solver, "f", None)
                _check_finite(t_new, derivative_names, fun(t_new, solver.y) if f_new is None else f_new,
                              "the derivatives")
                if not (solver.step_size is None or math.isfinite(solver.step_size)) or (
                        t_new <= t_old and solver.status == "running"):
                    raise SolverError(f"{self.method} makes no progress at t = {t_new:.12g} (step size "
                                      f"{solver.step_size})",
                                      hint="try a smaller tolerance, an implicit method (Radau, BDF) "
                                           "or a max_step")
                delays = self.delays
                history = self.history
                dense = (solver.dense_output() if (watched or recorder.grid_left or delays or history is not None)
                         else None)
                y_new = solver.y.copy()
                if delays is not None and t_new > t_old:
                    delays.add_step(t_old, t_new, dense, system)
                # the output points of this step, and the states there and at the samples
                # from one evaluation of the dense output
                rows = recorder.pending(t_new, t_new < t_bound)
                event = None
                if watched and t_new > t_old:
                    _check_crossings(t_new, system, y_new, watched, self.relations)
                    samples, at_samples, at_rows = step_samples(
                        t_old, t_new, recorder.interval, recorder.grid, dense, y_new, recorder.next_grid,
                        recorder.next_grid + len(rows))
                    event = locate_flip(t_old, samples, dense, y_new, flipped, first_flip, at_samples, narrow)
                else:
                    at_rows = None  # evaluated as they are written
                if event is not None:
                    t_e, x_e, fired = event
                    if delays is not None and t_new > t_old:
                        delays.trim_last(t_e)
                    before = rows[rows < t_e]
                    if self.evaluator.asserts:
                        # the output points before the event are accepted values too
                        self._asserts_in_step(before, at_rows[:len(before)], dense, x_e, t_e, system, discrete)
                    self._emit_rows(before, at_rows[:len(before)], system, discrete)
                    if history is not None:
                        history.add(t_old, t_e, dense, x_e, system, discrete)
                    names = tuple(self.relations[k].text for k in fired)
                    return t_e, x_e, (t_e, x_e, names)
                if self.evaluator.asserts:
                    self._asserts_in_step(rows, at_rows, dense, y_new, t_new, system, discrete)
                self._emit_step(rows, at_rows, dense, y_new, t_new, system, discrete)
                if history is not None:
                    history.add(t_old, t_new, dense, y_new, system, discrete)
                if self.evaluator.asserts:
                    self._check_asserts(t_new, system, y_new, discrete)
                if solver.status == "finished":
                    return t_new, solver.y.copy(), None
        finally:
            # every evaluation counts, whatever ended the segment (an interrupt too)
            self.nfev += solver.nfev

    # -- budgets --------------------------------------------------------------------

    def _check_budgets(self) -> None:
        if self.progress is not None:
            now = _time.perf_counter()
            if now >= self._next_progress:
                self._next_progress = now + PROGRESS_PERIOD
                self.progress(self.t, self.t_start, self.t_stop)
        over_steps = self.max_steps is not None and self.steps > self.max_steps
        over_time = self.timeout is not None and _time.perf_counter() - self.wall_start > self.timeout
        if not (over_steps or over_time):
            return
        if over_steps:
            raise _Budget(f"{self.method} used its budget of {self.max_steps} steps")
        raise _Budget(f"the simulation used its time budget of {self.timeout:g} s")

    def _budget_error(self, what: str) -> SolverError:
        """Where the time went, and a hint fitting the biggest share."""
        wall = _time.perf_counter() - self.wall_start
        compiling = self.translation.translation_seconds - self.compiled_before_run
        shares = {
            "compiling discrete states": compiling,
            "writing output points": self.seconds["output"],
            "event iteration": self.seconds["events"],
        }
        shares["integrating"] = max(wall - sum(shares.values()), 0.0)
        counts = {"compiling discrete states": f"{len(self.translation.systems)} states compiled",
                  "writing output points": f"{self.recorder.row_count} rows",
                  "event iteration": f"{len(self.events)} events",
                  "integrating": f"{self.steps} steps"}
        hints = {"compiling discrete states": "many discrete states are visited; each new combination "
                                              "of modes of elements that share equations needs a "
                                              "system of its own (independent parts are compiled "
                                              "apart)",
                 "writing output points": "choose a coarser interval",
                 "event iteration": "events come thick and fast; check the relations that fire",
                 "integrating": "the model may be stiff: try an implicit method (Radau, BDF)"}
        order = sorted(shares, key=shares.get, reverse=True)
        where = ", ".join(f"{shares[k]:.3g} s {k} ({counts[k]})" for k in order)
        return SolverError(f"{what} by t = {self.t:.12g}; the time went into: {where}",
                           hint=hints[order[0]])

    # -- result ------------------------------------------------------------------------

    def _result(self, t_setup: float, message: str, error, status: int = -1) -> SimulationResult:
        translation = self.translation
        times, columns, bad = self.recorder.columns(translation)
        if bad is not None:
            # An output that is not finite stops the run there, whatever ended it and whatever
            # the method: the rows after the first such row go.  Where the run went on past
            # it and then failed for another reason, the output is the first failure.
            row, names, reason = bad
            keep = row + 1
            went_on = keep < len(times)
            times = times[:keep]
            columns = {n: c[:keep] for n, c in columns.items()}
            if error is None or went_on:
                later = "" if error is None else f" (the run went on and then stopped: {error.message})"
                error = SolverError(f"at t = {times[-1]:.12g} {', '.join(names[:8])} "
                                    f"{'is' if len(names) == 1 else 'are'} not finite ({reason}){later}",
                                    hint="the equations computing it leave their domain here (a square "
                                         "root or logarithm of a negative value, a division by zero, "
                                         "an overflow)",
                                    components=tuple(dict.fromkeys(n.rpartition('.')[0] for n in names)))
                message = str(error)
                status = -1
        stats = {
            "steps": self.steps,
            "rhs_evaluations": self.nfev,
            "events": len(self.events),
            "translate_seconds": translation.translation_seconds - self.compile_seconds_before,
            "simulate_seconds": _time.perf_counter() - t_setup
            - (translation.translation_seconds - self.compile_seconds_before),
            "method": self.method,
            "rtol": self.rtol,
            "atol": self.atol,
        }
        return SimulationResult(times, columns, status if error is not None or status == 1 else 0, message, tuple(self.events),
                                tuple(self.modes), translation.compiled_systems, stats,
                                # and what the translation noted while this run compiled its systems
                                (*self.notes, *translation.notes[self.translation_notes_before:]),
                                error, translation.data.name,
                                describe_columns(translation.data, list(columns)))


def _all_finite(values) -> bool:
    """Whether every one of ``values`` is finite: the tuple of a few floats a generated
    function returns (or the list a part's system gathers from it) is checked in Python
    (a numpy call costs more than the check), anything else with numpy."""
    if (type(values) is tuple or type(values) is list) and len(values) <= _FEW_VALUES:
        try:
            return all(map(math.isfinite, values))
        except TypeError:  # not plain numbers: numpy decides (or raises) as below
            pass
    return bool(np.isfinite(np.asarray(values, dtype=float)).all())


#: Up to this many values, :func:`_all_finite` checks a tuple or list in Python.
_FEW_VALUES = 64


def _check_finite(t: float, names, values, what: str) -> None:
    """Stop the run when some of ``values`` (named ``names``) are not finite."""
    if _all_finite(values):
        return
    values = np.asarray(values, dtype=float)
    if values.size:
        bad = [(n, v) for n, v in zip(names, values.tolist()) if not math.isfinite(v)]
        raise SolverError(f"at t = {t:.12g} {what} are not finite: "
                          f"{', '.join(f'{n} = {v}' for n, v in bad[:8])}",
                          hint="a parameter, a start value or an equation gives an infinite or "
                               "undefined value (NaN) here",
                          components=tuple(dict.fromkeys(base_name(n).rpartition(".")[0] for n, _ in bad)))


def _check_crossings(t: float, system: CompiledSystem, x, watched, relations) -> None:
    """The sides of the watched relations must be finite: NaN makes every relation false."""
    raw = system.crossings(t, x)
    if _all_finite(raw):
        return
    raw = np.asarray(raw, dtype=float)
    bad = [relations[k].text for k in watched
           if not (math.isfinite(raw[2 * k]) and math.isfinite(raw[2 * k + 1]))]
    if bad:
        raise SolverError(f"at t = {t:.12g} the relation{'s' if len(bad) > 1 else ''} "
                          f"{'; '.join(bad[:5])} cannot be decided: a side is not finite",
                          hint="a parameter, a start value or an equation gives an infinite or "
                               "undefined value (NaN) here")
