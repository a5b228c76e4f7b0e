"""Stage 10: simulation — integrate between events, handle events, record.

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
:mod:`acausal.runtime.recorder`.
"""

from __future__ import annotations

import time as _time
from collections import deque
from typing import Sequence

import numpy as np
import scipy.integrate as integrate

from ..compiler.translate import ModeSystem, Translation, translate
from ..errors import ChatteringError, SimulationError, SolverError, StructuralError
from ..language import Component
from ..names import base_name
from .crossings import locate_flip, next_time_event, sample_times, time_event_roots
from .events import evaluator_for, mode_values
from .initialization import initialize
from .integrators import RK4, Euler
from .recorder import Recorder
from .result import Event, SimulationResult

__all__ = ["simulate", "METHODS"]

METHODS = {
    "RK45": integrate.RK45,
    "DOP853": integrate.DOP853,
    "Radau": integrate.Radau,
    "BDF": integrate.BDF,
    "LSODA": integrate.LSODA,
    "Euler": Euler,
    "RK4": RK4,
}


def simulate(model: Component | Translation, *, start_time: float | None = None,
             stop_time: float | None = None, interval: float | None = None, method: str = "RK45",
             rtol: float | None = None, atol: float | None = None, max_step: float | None = None,
             relation_epsilon: float = 1e-10, max_event_iterations: int = 20,
             chattering_events: int = 100, outputs: Sequence[str] | None = None,
             max_steps: int | None = None, timeout: float | None = None) -> SimulationResult:
    """Simulate a model.

    Parameters
    ----------
    model : Model instance or Translation
        A model, or the result of :func:`acausal.compiler.translate.translate` to
        reuse compiled systems.
    start_time, stop_time, interval : float, optional
        Default to the model's experiment annotation (interval: 500 points).
    method : {'RK45', 'DOP853', 'Radau', 'BDF', 'LSODA', 'Euler', 'RK4'}
        The last two have a fixed step, ``max_step``.
    rtol, atol : float, optional
        ``rtol`` defaults to the experiment's tolerance or 1e-6; ``atol`` to
        ``rtol`` times each state's nominal value.
    relation_epsilon : float
        Relative hysteresis of relations (see :mod:`acausal.partition`).
    chattering_events : int
        That many state events in a row within a vanishing time window stop
        the run with a :class:`~acausal.errors.ChatteringError`.
    outputs : sequence of str, optional
        Compute only these variables: states and equations that cannot
        influence them (nor the events) are left out of the right-hand side,
        and the result holds only these columns (and the discrete ones).
    max_steps, timeout : optional
        Budgets of integrator steps and wall-clock seconds; a run that
        exceeds one stops with a :class:`~acausal.errors.SolverError` and
        keeps what it computed.

    Returns
    -------
    SimulationResult
        ``status`` 0 on success; -1 with ``message`` and ``error`` set, and
        everything computed so far, when the run stopped early.
    """
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {', '.join(METHODS)}")
    t_setup = _time.perf_counter()
    if isinstance(model, Translation):
        if outputs is not None and model.demand != frozenset(outputs):
            raise ValueError("outputs must be given to translate() when simulating a Translation")
        translation = model
    else:
        translation = translate(model, outputs)
    flatten_seconds = _time.perf_counter() - t_setup
    experiment = translation.flat.experiment
    t0 = experiment.start_time if start_time is None else float(start_time)
    t1 = experiment.stop_time if stop_time is None else float(stop_time)
    if not t1 > t0:
        raise ValueError(f"stop time {t1} must be after start time {t0}")
    if interval is None:
        interval = experiment.interval or (t1 - t0) / 500
    if rtol is None:
        rtol = experiment.tolerance or 1e-6
    run = _Run(translation, method, rtol, atol, max_step, relation_epsilon, max_event_iterations,
               chattering_events)
    run.max_steps, run.timeout = max_steps, timeout
    # translation time of this call: flattening (unless cached) plus the systems
    # compiled during the run (a reused translation may have them all already)
    run.compile_seconds_before = translation.translation_seconds - flatten_seconds
    return run.execute(t0, t1, interval, t_setup)


class _Run:
    """One simulation run: the loop over segments and events (state in attributes)."""

    def __init__(self, translation: Translation, method, rtol, atol, max_step, relation_epsilon,
                 max_event_iterations, chattering_events) -> None:
        self.translation = translation
        self.evaluator = evaluator_for(translation, relation_epsilon, max_event_iterations)
        self.relations = translation.partitioned.relations
        self.method = method
        self.rtol = rtol
        self.atol = atol
        self.max_step = np.inf if max_step is None else max_step
        self.chattering_events = chattering_events
        self.events: list[Event] = []
        self.modes: list[str] = []
        self.notes: list[str] = []
        self.nfev = 0
        self.steps = 0
        self._time_roots = time_event_roots(self.relations, translation.cache.parameters.symbols)

    def _next_time_event(self, t: float, relations) -> float:
        return next_time_event(t, self._time_roots, self.relations, relations)

    # -- main loop ----------------------------------------------------------------

    def execute(self, t0: float, t1: float, interval: float, t_setup: float) -> SimulationResult:
        error = None
        message = "The simulation reached the stop time."
        self.recorder = Recorder(t0, t1, interval)
        self.wall_start = _time.perf_counter()
        try:
            state = initialize(self.translation, self.evaluator, t0)
            self.notes.extend(state.notes)
            outcome = state.outcome
            # Like Dymola, only the values after the post-initialization event
            # iteration are written at the start time (one row, not two).
            self.events.append(Event(t0, "initial", (), outcome.changes, outcome.iterations))
            try:
                self._integrate(t0, t1, outcome)
            except StructuralError as exc:
                # a discrete state reached during the run cannot be solved: stop
                # with the reason, keeping what was computed
                t_fail = self.recorder.last_time if self.recorder.rows else t0
                raise SolverError(f"at t = {t_fail:.12g} the model entered a discrete state it "
                                  f"cannot solve: {exc.message}", hint=exc.hint,
                                  components=exc.components) from exc
        except SimulationError as exc:
            error = exc
            message = str(exc)
        except (ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
            if isinstance(exc, SimulationError) or type(exc).__module__.startswith("acausal"):
                raise
            error = SolverError(f"the simulation stopped: {type(exc).__name__}: {exc}")
            message = str(error)
        return self._result(t_setup, message, error)

    def _record_mode(self, system: ModeSystem) -> None:
        if system.description not in self.modes:
            self.modes.append(system.description)

    def _integrate(self, t: float, t1: float, outcome) -> None:
        recorder = self.recorder
        system = outcome.system
        discrete = outcome.discrete
        relations = outcome.relations
        values = outcome.values
        self._record_mode(system)
        x = np.array([values[s] for s in system.states], dtype=float)
        recorder.add(t, system, x, discrete)
        recorder.skip_grid_through(t, round_off=False)
        recent = deque(maxlen=self.chattering_events)
        while t < t1:
            t_bound = min(t1, self._next_time_event(t, relations))
            if not system.states:
                recorder.emit_grid_until(t_bound, inclusive=False, system=system, x_at=lambda s: x,
                                         discrete=discrete)
                t_new, x_new, event_at = t_bound, x, None
            else:
                t_new, x_new, event_at = self._segment(system, t, x, t_bound, discrete, relations)
            if event_at is not None:
                t_e, x_e, fired = event_at
                kind = "state"
                recent.append((t_e, fired, tuple(sorted(discrete.items()))))
                self._check_chattering(recent, t1)
            elif t_new >= t1 and not any(root == t_new for _, root in self._time_roots
                                         if self._next_time_event(t, relations) == t_new):
                recorder.add(t_new, system, x_new, discrete)
                return
            else:
                # a time event (also one exactly at the stop time: it is processed,
                # and the run ends on its right limit)
                t_e, x_e = t_new, np.array(x_new, dtype=float)
                fired = tuple(self.relations[i].text for i, root in self._time_roots if root == t_e)
                kind = "time"
            # left limit, event iteration, right limit
            recorder.add(t_e, system, x_e, discrete)
            values = mode_values(system, t_e, x_e)
            fired_indices = frozenset(k for k, r in enumerate(self.relations) if r.text in fired)
            outcome = self.evaluator.iterate(t_e, values, discrete, relations, fired=fired_indices)
            self.events.append(Event(t_e, kind, tuple(fired), outcome.changes, outcome.iterations))
            system, discrete, relations = outcome.system, outcome.discrete, outcome.relations
            self._record_mode(system)
            x = np.array([outcome.values[s] for s in system.states], dtype=float)
            recorder.add(t_e, system, x, discrete)
            t = t_e
            if t >= t1:
                return
            # a grid point at the event time is represented by the two event rows
            recorder.skip_grid_through(t_e)

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
        owners = tuple(dict.fromkeys(n.rpartition(".")[0] for n in changing))
        own = self.translation.flat.hints_for("chattering", owners)
        raise ChatteringError(
            f"chattering: {len(recent)} state events between t = {recent[0][0]:.12g} "
            f"and {recent[-1][0]:.12g}; the crossing firing most is {worst}",
            hint="; ".join(("the model switches back and forth without time passing; check the "
                            "relation named (a threshold that its own switching crosses)", *own)),
            components=owners)

    def _segment(self, system: ModeSystem, t: float, x, t_bound: float, discrete, relations):
        """Integrate one mode until t_bound or the first crossing.

        Returns ``(t_end, x_end, event)``, event = ``(t_e, x_e, fired names)`` or None.
        """
        recorder = self.recorder
        nominal = np.array([self.translation.continuous[base_name(s)].nominal for s in system.states])
        atol = self.rtol * nominal if self.atol is None else self.atol

        def fun(tt, xx):
            return np.array(system.derivatives(tt, xx), dtype=float)

        solver = METHODS[self.method](fun, t, x, t_bound, rtol=self.rtol, atol=atol,
                                      max_step=self.max_step)
        watched = self.evaluator.relevant_relations(discrete, relations)
        evaluator = self.evaluator

        def flipped(tt, xx):
            return evaluator.flipped_relations(system, tt, xx, relations, watched)

        while True:
            t_old = solver.t
            message = solver.step()
            self.steps += 1
            self._check_budgets(solver)
            if solver.status == "failed":
                self.nfev += solver.nfev
                raise SolverError(f"{self.method} failed at t = {solver.t:.12g}: {message}",
                                  hint="try a smaller tolerance, an implicit method (Radau, BDF) "
                                       "or a max_step")
            t_new = solver.t
            dense = solver.dense_output() if (watched or recorder.grid_left) else None
            event = None
            if watched and t_new > t_old:
                samples = sample_times(t_old, t_new, recorder.interval, recorder.grid)
                event = locate_flip(t_old, samples, dense, solver.y, flipped)
            if event is not None:
                t_e, x_e, fired = event
                recorder.emit_grid_until(t_e, inclusive=False, system=system, x_at=dense,
                                         discrete=discrete)
                self.nfev += solver.nfev
                names = tuple(self.relations[k].text for k in fired)
                return t_e, x_e, (t_e, x_e, names)

            def x_at(s, dense=dense, y=solver.y.copy(), t_new=t_new):
                # a grid point at the step end (up to round-off) takes the step's value
                if dense is None or abs(s - t_new) <= 1e-12 * max(1.0, abs(t_new)):
                    return y
                return dense(s)

            recorder.emit_grid_until(t_new, inclusive=t_new < t_bound, system=system, x_at=x_at,
                                     discrete=discrete)
            if solver.status == "finished":
                self.nfev += solver.nfev
                return t_new, solver.y.copy(), None

    def _check_budgets(self, solver) -> None:
        over_steps = self.max_steps is not None and self.steps > self.max_steps
        over_time = self.timeout is not None and _time.perf_counter() - self.wall_start > self.timeout
        if not (over_steps or over_time):
            return
        self.nfev += solver.nfev  # count this segment's evaluations before stopping
        if over_steps:
            raise SolverError(f"{self.method} used its budget of {self.max_steps} steps by "
                              f"t = {solver.t:.12g}",
                              hint="the model may be stiff: try an implicit method (Radau, BDF)")
        raise SolverError(f"the simulation used its time budget of {self.timeout:g} s by "
                          f"t = {solver.t:.12g}",
                          hint="the model may be stiff: try an implicit method (Radau, BDF)")

    # -- result ------------------------------------------------------------------------

    def _result(self, t_setup: float, message: str, error) -> SimulationResult:
        translation = self.translation
        times, columns = self.recorder.columns(translation)
        stats = {
            "steps": self.steps,
            "rhs_evaluations": self.nfev,
            "events": len(self.events),
            "translate_seconds": translation.translation_seconds - self.compile_seconds_before,
            "simulate_seconds": _time.perf_counter() - t_setup
            - (translation.translation_seconds - self.compile_seconds_before),
            "method": self.method,
            "rtol": self.rtol,
        }
        return SimulationResult(times, columns, 0 if error is None else -1, message, tuple(self.events),
                                tuple(self.modes), translation.compiled_systems, stats, tuple(self.notes),
                                error, translation.flat.name)
