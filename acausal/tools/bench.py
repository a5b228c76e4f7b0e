"""Work-precision benchmark: accuracy against cost for every adaptive method.

``acausal bench [--quick] [--out DIR] [--methods M,...] [--rtols R,...] [--only SECTION,...]
[--soak-runs N]``
(or ``python -m acausal.tools.bench ...``)

This module is the machinery: it translates and simulates, times, compares,
fits and writes tables and plots.  *What* it runs -- the models, their exact
solutions and the words that describe them -- is defined in
``examples/benchmarks.py`` (the *suite*, see :func:`suite`), imported with
the examples folder on ``sys.path``.  The suite provides ``cases()`` (the
work-precision cases as :class:`Case`, in table order), ``QUICK_CASES``,
``EXACT_ERROR_TEXT``, ``effects_cases(n_units)``, ``scaling_model(n,
stop_time)`` with ``SCALING_DESCRIPTION`` and ``SCALING_SIZE_LABEL``,
``COMMAND_TARGETS`` and ``SIMULATE_COMMAND_TARGETS``, ``soak_case()``, ``parameter_case()``,
``storm_model(n)`` with ``STORM_DESCRIPTION``, ``STORM_SIZE_LABEL``,
``STORM_EVENTS_GROWTH``, ``STORM_WATCHED``, ``STORM_STOP_TIME`` and
``STORM_INTERVAL``, and ``floor_case()`` (a :class:`FloorCase`: one of its
cases written by hand without the engine); optionally ``array_scaling_case()``
(an :class:`ArrayScalingCase`; without it, ``scaling_case()`` of
``examples/heat_rod.py``).  The suite also sets the targets
(``TARGETS_SOURCE`` says where they come from): ``WARM_COMMAND_FILES`` with
``WARM_COMMAND_MAX_X_IMPORT_NUMPY``, the floor case's ``target_ratio``,
``STORM_PER_EVENT_TARGET``, ``STORM_WALL_TARGETS``, ``SCALING_TIME_TARGETS``
and ``SCALING_MEMORY_TARGET``.  The sections ``commands``, ``floors``,
``storm`` and ``scaling`` open their Markdown with a ``## Targets`` table
(:class:`TargetCheck`): each target, the measured figure, *met*, *not met*
or *not measured* (a size not run, whatever an extrapolation predicts), and
for the others why, and what meeting it would take, from the measured
figures where they tell.

Eight sections (``--only`` picks some: ``work-precision``, ``effects``,
``commands``, ``scaling``, ``soak``, ``parameters``, ``storm``,
``floors``; the files of the others are then left as they are), each
written into ``--out`` (default :func:`default_out`: ``acausal-bench`` in the
user's cache folder, never the working folder) as Markdown and CSV, and
printed at the end:

1. **Work-precision** (``bench.md``, ``bench.csv``, ``work_precision.png``;
   also ``work_precision_events.png`` for the event-time error and
   ``work_precision_rhs.png`` with right-hand side evaluations as the cost).
   Two kinds of case:

   * *Reference cases* (:func:`reference_case`): MSL examples of the
     examples folder against the MSL reference results.  *error* is the
     largest ``max |y - y_ref| / dy`` over the compared continuous signals
     at the reference's time points (``dy`` the tube half-height of
     csv-compare), a continuous measure; the tube test's worst violation (0
     when the result passes) is reported beside it.  The reference has its
     own error (Dymola's, at its tolerance), so *error* levels off where the
     reference's accuracy is reached.  *Event-time error*: every time at
     which a ``.mode`` column of the reference changes is matched with the
     nearest event of the result that changed a ``mode``; the largest
     distance.
   * *Exact-solution cases*: models whose solution is known in closed form;
     the case's ``evaluate`` measures *error* (in the case's
     ``error_unit``) and *event-time error* against it.

   A case is translated once (a fresh ``translate`` and a first simulation,
   which compiles the discrete states visited); each method × tolerance is
   then simulated with that translation, once to warm up (compiling any
   state not yet visited) and ``repeats`` times more, the smallest wall
   time counting.  A failed run (status -1 or an exception) is recorded
   with its message.

2. **Effects on demand** (``effects.md``, ``effects.csv``): full simulation
   against ``outputs=[one variable]`` on the suite's ``effects_cases``.

3. **Fresh-process commands** (``commands.md``, ``commands.csv``;
   :func:`run_commands_with_floors`): the wall time of ``acausal compare
   EXAMPLE`` (the suite's ``COMMAND_TARGETS``) and ``acausal simulate
   EXAMPLE`` (``SIMULATE_COMMAND_TARGETS``) in a new Python process, with
   the persistent compile cache off (*cold*) and filled (*warm*), each a
   multiple of ``python -c "import numpy"`` timed in alternation with them;
   each warm target command again under ``python -X importtime``
   (:func:`import_breakdown`: the import seconds per top-level package,
   median of :data:`IMPORT_BREAKDOWN_RUNS` runs).

4. **Scaling** (``scaling.md``, ``scaling.csv``, ``scaling.png``): the
   suite's ``scaling_model`` for growing ``N``; translation stage times and
   a short simulation; the growth exponent ``b`` of ``time = a N^b``; the
   full sizes include the targets' (:func:`full_scaling_sizes`, each point
   stopped after :data:`SCALING_BUDGET_SECONDS`).  Then the *array case*
   (:class:`ArrayScalingCase`, :func:`array_scaling_case`:
   the heat rod of ``examples/heat_rod.py``, built with arrays of
   components; :func:`run_array_scaling`, ``scaling_arrays.csv`` and a
   section of ``scaling.md``): translated for N = 10, 30, 100, 300, 1000
   (10, 30, 100 with ``--quick``), each in a fresh process; the
   translation seconds per N and per element, the slope of log(time)
   against log(N) (1 for linear time), and a short run whose conserved
   quantity (the heat) stored must equal what came in.

5. **Soak** (``soak.md``, ``soak.csv``, ``soak.png``; :func:`run_soak`):
   the suite's ``soak_case()`` simulated 200 times (21 with ``--quick``,
   ``--soak-runs N``) in this process, a fresh model instance every run,
   *cached* (``simulate(model)``, the translation cache reusing the compiled
   systems) and *uncached* (``simulate(model, cache=False)``).  Per run the
   wall time and the resident set size; a mode is *flat* when the median
   time of the last 10 runs is within 1.5x of that of runs 2-11 and the RSS
   grows less than 20 MB per 100 runs after run 10.

6. **A changed parameter** (``parameters.md``, ``parameters.csv``;
   :func:`run_parameter_change`): the suite's ``parameter_case()`` translated
   anew, from the cache, and with new values of a tunable parameter.

7. **Storm** (``storm.md``, ``storm.csv``, ``storm.png``; :func:`run_storm`):
   the suite's ``storm_model(N)`` -- N independent units, each a part of
   its own with its own events -- for N = 5 ... 200 and the targets' sizes
   (:func:`full_storm_sizes`; 3, 6 with ``--quick``), each point in a fresh
   process stopped after 240 s (60 s quick), the sizes after one that did
   not finish skipped; every N with clusters (one system per independent part and part
   mode, the default) and, for N <= 20 (6 quick), with
   ``EngineOptions(clusters=False)`` (the whole model
   compiled per discrete state).  Wall and translation seconds, compiled
   systems, events, the cost per event, peak RSS; the growth exponent ``b``
   of ``wall = a N^b`` per mode and the targets (the cost per event, the
   wall at N = 200 and 1000).
   Each point records the final value of the suite's ``STORM_WATCHED``
   (the same with and without clusters).

8. **Floors** (``floors.md``, ``floors.csv``; :func:`run_floors`): ``python
   -c "import numpy"`` and ``python -c "import numpy, scipy.integrate"`` in
   fresh processes, each command's median as a multiple of both (the
   commands section's runs and floors, timed in alternation, when it ran
   too, else both timed here likewise); and the warm case of the suite's
   ``floor_case()`` (its method, rtol 1e-6, best of 5) against the same
   model written by hand (the floor case's ``floor``;
   :func:`run_hand_coded_floor`), whose final value of the floor case's
   ``output`` must agree within its ``agreement``.

The timings measure whole ``simulate`` calls (setup of the discrete
evaluator, integration, event handling and building the result on the
output grid) by ``time.perf_counter``.
"""

from __future__ import annotations

import argparse
import csv
import gc
import json
import math
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from ..language import Model

__all__ = [
    "ADAPTIVE_METHODS", "QUICK_RTOLS", "FULL_RTOLS", "Case", "RunRecord", "CaseTranslation", "CaseRun",
    "BenchResult", "cases", "get_case", "run_case", "run_effects", "scaling_point", "run_scaling",
    "run_bench", "main", "suite", "reference_case", "example_factory", "fit_power_law",
    "SECTIONS", "run_parameter_change", "SoakRun", "SoakSummary", "SoakResult", "run_soak", "write_soak",
    "storm_point", "run_storm", "storm_fits", "write_storm", "run_import_floors", "command_floor_ratios",
    "FloorCase", "HAND_CODED_FLOOR_REPEATS", "run_hand_coded_floor", "run_floors", "write_floors",
    "FULL_ARRAY_SCALING", "QUICK_ARRAY_SCALING", "ArrayScalingCase", "array_scaling_case", "array_scaling_point",
    "run_array_scaling", "array_scaling_fits", "TargetCheck", "run_commands", "run_commands_with_floors",
    "import_breakdown", "IMPORT_BREAKDOWN_PACKAGES", "command_target_checks", "floor_target_check",
    "storm_target_checks", "scaling_target_checks", "full_scaling_sizes", "full_storm_sizes",
]

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"

#: The adaptive methods compared (Euler and RK4 have a fixed step and are not).
ADAPTIVE_METHODS = ("RK45", "DOP853", "Radau", "BDF", "LSODA")
QUICK_RTOLS = (1e-3, 1e-6, 1e-9)
FULL_RTOLS = tuple(10.0 ** -k for k in range(3, 11))
QUICK_SCALING = (10, 40)
#: The full scaling sizes; the sizes of the suite's scaling targets are run too (:func:`full_scaling_sizes`).
FULL_SCALING = (10, 30, 100, 300, 1000)
#: Wall-time budget of one scaling point in full mode (translation + two short runs).
SCALING_BUDGET_SECONDS = 180.0
#: Runs whose warm-up takes longer than this are not repeated.
SLOW_RUN_SECONDS = 5.0
#: Smallest error shown in the work-precision plots (exact results are clipped to it).
ERROR_FLOOR = 1e-16
#: The sections of the bench, as ``acausal bench --only`` names them.
SECTIONS = ("work-precision", "effects", "commands", "scaling", "soak", "parameters", "storm", "floors", "tables")


def _ensure_path() -> None:
    """Make ``library``, ``components`` and the examples importable."""
    for folder in (str(EXAMPLES), str(ROOT)):
        if folder not in sys.path:
            sys.path.insert(0, folder)


def suite():
    """The bench's cases: the module ``examples/benchmarks.py``.

    Imported with the examples folder first on ``sys.path`` (as the example
    modules the reference cases load), so the scaling points' fresh
    processes find it too.  See the module docstring for what it provides.
    """
    _ensure_path()
    import benchmarks

    return benchmarks


# ---------------------------------------------------------------------------
# Cases
# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class Case:
    """One work-precision case.

    ``make`` builds the model; ``evaluate(result, translation)`` returns
    ``{"error", "event_error"[, "tube"]}``; ``error_unit`` says what the
    error is measured in.
    """

    name: str
    make: Callable[[], Model]
    evaluate: Callable
    error_unit: str
    description: str
    stop_time: float | None = None
    #: The Modelica class whose reference results the error is measured against (None: exact).
    reference: str | None = None


def _reference_missing(modelica_class: str) -> str | None:
    """Why the reference results of ``modelica_class`` cannot be read (None: they can)."""
    from .compare import load_reference
    from ..errors import ReferenceDataError

    try:
        load_reference(modelica_class)
    except (ReferenceDataError, OSError) as exc:
        return str(exc).split("\n")[0]
    return None


def example_factory(module: str, cls: str) -> Callable[[], Model]:
    """A function making ``cls()`` of the module ``module`` of the examples folder (imported on first call)."""

    def make():
        _ensure_path()
        import importlib

        return getattr(importlib.import_module(module), cls)()
    return make


def _reference_evaluator(modelica_class: str):
    state: dict = {}

    def evaluate(result, translation) -> dict:
        from .compare import compare_signals, load_reference

        if "reference" not in state:
            ref = load_reference(modelica_class)
            state["reference"] = ref
            state["mode_times"] = _reference_mode_times(ref)
        ref = state["reference"]
        comparison = compare_signals(ref, result.time, result.columns)
        tube = max((s.worst_violation for s in comparison.signals), default=0.0)
        discrete = set(translation.partitioned.discrete_variables)
        continuous = [s for s in comparison.signals if s.name not in discrete]
        ratios = [s.max_abs_error / s.dy for s in continuous]
        error = max(ratios) if ratios and not any(math.isnan(r) for r in ratios) else math.nan
        ref_times = state["mode_times"]
        if ref_times:
            ours = np.array(sorted(e.time for e in result.events
                                   if any(n.endswith(".mode") and a != b for n, a, b in e.changes)))
            if ours.size:
                event_error = max(float(np.min(np.abs(ours - t))) for t in ref_times)
            else:
                event_error = math.inf
        else:
            event_error = math.nan
        return {"error": error, "event_error": event_error, "tube": tube}

    return evaluate


def _reference_mode_times(reference) -> list[float]:
    """Times where any ``.mode`` column of the reference changes."""
    times: set[float] = set()
    for name, y in reference.signals.items():
        if name.endswith(".mode"):
            changed = np.nonzero(np.diff(y) != 0)[0] + 1
            times.update(float(reference.time[i]) for i in changed)
    return sorted(times)


def reference_case(name: str, module: str, modelica_class: str) -> Case:
    """The example class ``name`` of ``examples/<module>.py`` measured against the reference results of
    ``modelica_class`` (error in tube half-heights)."""
    return Case(name, example_factory(module, name), _reference_evaluator(modelica_class), "max |y-y_ref|/dy",
                "MSL " + ".".join(modelica_class.split(".")[-3:]),
                reference=modelica_class)


def cases() -> dict[str, Case]:
    """Every work-precision case of the suite by name, in table order."""
    return {c.name: c for c in suite().cases()}


def get_case(name: str) -> Case:
    table = cases()
    if name not in table:
        raise KeyError(f"no bench case {name!r}; cases: {', '.join(table)}")
    return table[name]


# ---------------------------------------------------------------------------
# Running a case
# ---------------------------------------------------------------------------


@dataclass
class RunRecord:
    """One case × method × rtol."""

    case: str
    method: str
    rtol: float
    error: float = math.nan
    event_error: float = math.nan
    tube: float = math.nan
    sim_seconds: float = math.nan
    rhs_evaluations: int = 0
    steps: int = 0
    events: int = 0
    status: int = -1
    message: str = ""
    repeats: int = 0
    error_unit: str = ""

    @property
    def ok(self) -> bool:
        return self.status == 0 and math.isfinite(self.error)


@dataclass
class CaseTranslation:
    """Translation cost of one case: a fresh translate and a first simulation."""

    case: str
    flatten_seconds: float = math.nan
    translate_seconds: float = math.nan  #: flatten + compiled modes (their pass logs)
    first_simulate_seconds: float = math.nan  #: wall time of the first simulate (compiles)
    modes: int = 0
    initial_systems: int = 0
    stage_seconds: dict = field(default_factory=dict)  #: summed over compiled modes
    per_mode_seconds: float = math.nan
    modes_after_bench: int = 0
    status: int = -1
    message: str = ""


@dataclass
class CaseRun:
    case: Case
    translation: CaseTranslation
    records: list[RunRecord]


def _stage_sums(translation) -> dict:
    sums: dict = {}
    for system in translation.mode_systems():
        for stage, seconds in system.passes:
            sums[stage] = sums.get(stage, 0.0) + seconds
    return sums


def _timed_simulate(translation, **options):
    from ..runtime.simulate import simulate

    t0 = time.perf_counter()
    result = simulate(translation, **options)
    return result, time.perf_counter() - t0


def run_case(case: Case, methods: Sequence[str], rtols: Sequence[float], repeats: int = 2,
             log: Callable[[str], None] | None = None) -> CaseRun:
    """Translate ``case`` once, then simulate it for every method × rtol."""
    log = log or (lambda _s: None)
    info = CaseTranslation(case.name)
    records: list[RunRecord] = []
    options = {} if case.stop_time is None else {"stop_time": case.stop_time}
    try:
        translation = _fresh_translate(case.make())
        first, info.first_simulate_seconds = _timed_simulate(translation, **options)
        info.flatten_seconds = translation.flatten_seconds
        info.translate_seconds = translation.translation_seconds
        info.modes = len(translation.systems)
        info.initial_systems = len(translation.initial_systems)
        info.stage_seconds = _stage_sums(translation)
        compiled = translation.translation_seconds - translation.flatten_seconds
        info.per_mode_seconds = compiled / max(1, info.modes)
        info.status, info.message = first.status, first.message
    except Exception as exc:  # noqa: BLE001 - a bench never crashes on a model
        info.message = f"{type(exc).__name__}: {exc}"
        for method in methods:
            for rtol in rtols:
                records.append(RunRecord(case.name, method, rtol, error_unit=case.error_unit,
                                         message=f"translation failed: {info.message}"))
        return CaseRun(case, info, records)

    for method in methods:
        for rtol in rtols:
            record = RunRecord(case.name, method, float(rtol), error_unit=case.error_unit)
            try:
                before = len(translation.systems) + len(translation.initial_systems)
                result, warm = _timed_simulate(translation, method=method, rtol=rtol, **options)
                n_systems = len(translation.systems) + len(translation.initial_systems)
                if warm < SLOW_RUN_SECONDS:
                    n_repeats = repeats
                else:  # too slow to repeat: the warm-up counts unless it compiled a mode
                    n_repeats = 1 if n_systems != before else 0
                times = [_timed_simulate(translation, method=method, rtol=rtol, **options)[1]
                         for _ in range(n_repeats)] or [warm]
                if len(translation.systems) + len(translation.initial_systems) != n_systems:
                    raise RuntimeError("a repeated run compiled a new discrete state")
                record.sim_seconds = min(times)
                record.repeats = len(times)
                record.rhs_evaluations = int(result.stats.get("rhs_evaluations", 0))
                record.steps = int(result.stats.get("steps", 0))
                record.events = len(result.events)
                record.status = result.status
                record.message = result.message
                if result.status == 0:
                    values = case.evaluate(result, translation)
                    record.error = float(values["error"])
                    record.event_error = float(values.get("event_error", math.nan))
                    record.tube = float(values.get("tube", math.nan))
            except Exception as exc:  # noqa: BLE001
                record.status = -1
                record.message = f"{type(exc).__name__}: {exc}"
            records.append(record)
            log(f"  {case.name:16s} {method:7s} rtol={rtol:<7.0e} error={record.error:<10.3g} "
                f"event={record.event_error:<10.3g} t={record.sim_seconds:.4f}s "
                f"{'ok' if record.status == 0 else 'FAILED: ' + record.message[:60]}")
    info.modes_after_bench = len(translation.systems)
    return CaseRun(case, info, records)


# ---------------------------------------------------------------------------
# Effects on demand
# ---------------------------------------------------------------------------


@dataclass
class EffectsRecord:
    case: str
    output: str
    rtol: float
    states_kept: int = 0
    states_total: int = 0
    derivative_steps_kept: int = 0
    derivative_steps_full: int = 0
    steps_kept: int = 0
    steps_full: int = 0
    sim_seconds_full: float = math.nan
    sim_seconds_pruned: float = math.nan
    translate_seconds_full: float = math.nan
    translate_seconds_pruned: float = math.nan
    max_abs_difference: float = math.nan
    max_rel_difference: float = math.nan
    status: str = ""


def _first_system(translation):
    return next(iter(translation.systems.values()))


def _own_systems(system) -> tuple:
    """The compiled systems behind ``system``: its clusters' (composed) or itself."""
    return system.parts or (system,)


def _max_difference(t_full, y_full, t_pruned, y_pruned) -> float:
    same_grid = len(t_full) == len(t_pruned) and np.allclose(t_full, t_pruned, rtol=0,
                                                             atol=1e-9 * max(1.0, t_full[-1]))
    if same_grid:
        return float(np.max(np.abs(y_full - y_pruned)))
    return float(np.max(np.abs(y_full - np.interp(t_full, t_pruned, y_pruned))))


def run_effects_case(name: str, make: Callable[[], Model], output: str, rtol: float = 1e-6,
                     method: str = "RK45", repeats: int = 2) -> EffectsRecord:
    """Full against ``outputs=[output]`` for one model."""
    record = EffectsRecord(name, output, rtol)
    try:
        runs = {}
        for label, outputs in (("full", None), ("pruned", [output])):
            translation = _fresh_translate(make(), outputs)
            result, _ = _timed_simulate(translation, method=method, rtol=rtol)
            if result.status != 0:
                raise RuntimeError(f"{label} run failed: {result.message}")
            seconds = min(_timed_simulate(translation, method=method, rtol=rtol)[1] for _ in range(repeats))
            runs[label] = (translation, result, seconds)
        full_tr, full_res, full_s = runs["full"]
        pr_tr, pr_res, pr_s = runs["pruned"]
        pruned = _first_system(pr_tr)
        full = full_tr.systems.get(pruned.key) or _first_system(full_tr)
        record.states_kept = len(pruned.states)
        record.states_total = sum(len(p.structure.states) for p in _own_systems(pruned))
        record.derivative_steps_kept = sum(p.code.n_derivative_steps for p in _own_systems(pruned))
        record.derivative_steps_full = sum(p.code.n_derivative_steps for p in _own_systems(full))
        record.steps_kept = sum(p.code.n_steps for p in _own_systems(pruned))
        record.steps_full = sum(p.code.n_steps for p in _own_systems(full))
        record.sim_seconds_full, record.sim_seconds_pruned = full_s, pr_s
        record.translate_seconds_full = full_tr.translation_seconds
        record.translate_seconds_pruned = pr_tr.translation_seconds
        y_full, y_pr = full_res[output], pr_res[output]
        record.max_abs_difference = _max_difference(full_res.time, y_full, pr_res.time, y_pr)
        record.max_rel_difference = record.max_abs_difference / max(float(np.max(np.abs(y_full))), 1e-300)
        record.status = "ok"
    except Exception as exc:  # noqa: BLE001
        record.status = f"failed: {type(exc).__name__}: {exc}"
    return record


def run_effects(rtol: float = 1e-6, repeats: int = 2, n_units: int = 20,
                log: Callable[[str], None] | None = None) -> list[EffectsRecord]:
    """:func:`run_effects_case` for each of the suite's ``effects_cases(n_units)``."""
    log = log or (lambda _s: None)
    records = []
    for name, make, output in suite().effects_cases(n_units):
        record = run_effects_case(name, make, output, rtol=rtol, repeats=repeats)
        log(f"  effects {name}: states {record.states_kept}/{record.states_total}, derivative steps "
            f"{record.derivative_steps_kept}/{record.derivative_steps_full}, time "
            f"{record.sim_seconds_full:.3f}s -> {record.sim_seconds_pruned:.3f}s, "
            f"max diff {record.max_abs_difference:.2g} ({record.status})")
        records.append(record)
    return records


# ---------------------------------------------------------------------------
# Scaling
# ---------------------------------------------------------------------------

STAGES = ("specialise", "alias", "structure", "blt", "algebraic", "codegen")


def _fresh_translate(model: Model, outputs=None):
    """``translate`` without the in-process cache of translations (when there is one)."""
    from ..compiler.translate import translate

    try:
        return translate(model, outputs, cache=False)
    except TypeError:  # an engine without the cache
        return translate(model, outputs)


def _evaluator(translation):
    """The discrete evaluator ``simulate`` uses (built once per translation)."""
    from ..runtime.events import evaluator_for

    return evaluator_for(translation)


def _rss_mb() -> float:
    try:
        import resource

        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    except (ImportError, AttributeError):  # pragma: no cover - not on Linux
        return math.nan


def scaling_point(n: int, stop_time: float = 0.2, rtol: float = 1e-6, method: str = "RK45",
                  repeats: int = 1, progress: Callable[[dict], None] | None = None) -> dict:
    """Translate and simulate the suite's ``scaling_model`` of size ``n``.

    Phases, each timed: flatten+partition; building the discrete evaluator;
    initialization (which compiles the first discrete states and the
    initialization systems); the first simulation (compiling what is left);
    a second, warm simulation.  ``translated_initialized`` is the sum of the
    first three, what a user waits for before the first step is integrated
    (the scaling targets' measure).  ``progress`` receives the point
    measured so far after each phase, so a point stopped by a time budget
    keeps what it finished.
    """
    from ..runtime.initialization import initialize

    progress = progress or (lambda _p: None)
    point: dict = {"n": n, "status": "ok"}
    wall0 = time.perf_counter()

    def report(phase: str) -> None:
        point["phase"] = phase
        point["max_rss_mb"] = _rss_mb()
        point["wall"] = time.perf_counter() - wall0
        progress(dict(point))

    model = suite().scaling_model(n, stop_time)
    gc.collect()
    t0 = time.perf_counter()
    translation = _fresh_translate(model)
    point["flatten"] = time.perf_counter() - t0
    report("flattened; building the event evaluator")
    gc.collect()
    t0 = time.perf_counter()
    evaluator = _evaluator(translation)
    point["evaluator_setup"] = time.perf_counter() - t0
    report("initializing (compiling the first discrete states and the initialization systems)")
    t0 = time.perf_counter()
    initialize(translation, evaluator, translation.flat.experiment.start_time)
    init_wall = time.perf_counter() - t0
    system = _first_system(translation)
    for stage in STAGES:
        point[stage] = system.timings.get(stage, math.nan)
    point["translation"] = point["flatten"] + system.seconds
    point["states"] = len(system.structure.states)
    point["equations"] = len(system.equations)
    point["derivative_steps"] = system.code.n_derivative_steps
    compiled = translation.translation_seconds - translation.flatten_seconds
    point["initial_systems"] = translation.initial_seconds
    point["initialization"] = max(init_wall - compiled, 0.0)
    point["translated_initialized"] = point["flatten"] + point["evaluator_setup"] + init_wall
    # the peak so far: the model translated and initialized, before a result exists
    point["translated_rss_mb"] = _rss_mb()
    report("simulating (first run)")
    first, point["first_simulate"] = _timed_simulate(translation, method=method, rtol=rtol)
    point["translation_all_modes"] = translation.translation_seconds
    point["modes"] = len(translation.systems)
    status, message = first.status, first.message
    del first  # (a result of the large model is some hundred megabytes: not kept while the next is made)
    if status != 0:
        point["status"] = f"failed: {message}"
        point["simulate"] = math.nan
    else:
        report("simulating again (warm)")
        seconds, stats = [], None
        for _ in range(repeats):
            result, elapsed = _timed_simulate(translation, method=method, rtol=rtol)
            seconds.append(elapsed)
            stats = stats or dict(result.stats)
            del result
        point["simulate"] = min(seconds)
        point["steps"] = stats.get("steps", 0)
        point["rhs_evaluations"] = stats.get("rhs_evaluations", 0)
    point["wall"] = time.perf_counter() - wall0
    point["max_rss_mb"] = _rss_mb()
    point.pop("phase", None)
    return point


def _point_in_subprocess(call: str, timeout: float, env_extra: dict | None = None):
    """Run ``call`` (``scaling_point(...)``, ``array_scaling_point(...)`` or ``storm_point(...)``,
    given ``progress=report``) in a fresh process, the collector set as in an ``acausal``
    command (fewer pauses, landing in fewer stages at random).

    Returns ``(report, failure, wall, timed_out)``: the last report printed (the
    point, or on a timeout the last progress), the failure's last stderr line
    (None when it exited 0), the wall seconds, and whether the timeout ended it.
    """
    code = ("import gc, json, sys; sys.path.insert(0, {root!r}); from acausal.tools.collector import GC_THRESHOLD; "
            "gc.set_threshold(*GC_THRESHOLD); "
            "from acausal.tools.bench import array_scaling_point, scaling_point, storm_point; "
            "report = lambda p: print('@@' + json.dumps(p), flush=True); "
            "report({call})").format(root=str(ROOT), call=call)
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    env.update(env_extra or {})
    t0 = time.perf_counter()
    try:
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout,
                              cwd=str(ROOT), env=env)
    except subprocess.TimeoutExpired as exc:
        return _last_report(exc.stdout), None, time.perf_counter() - t0, True
    failure = None if proc.returncode == 0 else \
        f"failed (exit {proc.returncode}): {(proc.stderr.strip().splitlines() or ['no output'])[-1]}"
    return _last_report(proc.stdout), failure, time.perf_counter() - t0, False


def _scaling_point_subprocess(n: int, stop_time: float, timeout: float) -> dict:
    return _measured_point(n, f"scaling_point({n}, {stop_time!r}, progress=report)", timeout)


def _measured_point(n: int, call: str, timeout: float) -> dict:
    """The point ``call`` measures in a fresh process; what it finished, with the reason, when it
    stops early or fails."""
    report, failure, wall, timed_out = _point_in_subprocess(call, timeout)
    if timed_out:
        partial = report or {"n": n}
        phase = partial.pop("phase", "")
        partial.update(status=f"stopped after {timeout:.0f} s" + (f" ({phase})" if phase else ""), wall=wall)
        return partial
    if report is not None and failure is None:
        return report
    return {"n": n, "status": failure or "failed: no report", "wall": wall}


def _last_report(output) -> dict | None:
    if isinstance(output, bytes):
        output = output.decode(errors="replace")
    for line in reversed((output or "").splitlines()):
        if line.startswith("@@"):
            return json.loads(line[2:])
    return None


#: The target of a fresh-process command (the suite's ``COMMAND_TARGETS``), wall seconds.
COMMAND_TARGET_SECONDS = 1.0
#: Wall-time limit of one fresh-process command.
COMMAND_TIMEOUT_SECONDS = 60.0
#: ``python -X importtime`` output is broken down by these top-level packages (the rest is ``other``).
IMPORT_BREAKDOWN_PACKAGES = ("acausal", "sympy", "mpmath", "networkx", "scipy", "pandas", "matplotlib", "numpy")
#: Packages a warm run needs only to compile (sympy with its mpmath, networkx): a cache hit could do without.
COMPILER_PACKAGES = ("sympy", "mpmath", "networkx")
#: Packages a run of an explicit method needs only when used (implicit methods, data frames, plots).
ON_DEMAND_PACKAGES = ("scipy", "pandas", "matplotlib")
#: Runs under ``python -X importtime`` per command broken down (the median counts).
IMPORT_BREAKDOWN_RUNS = 3
_IMPORTTIME_LINE = re.compile(r"^import time:\s+(\d+)\s+\|\s+(\d+)\s+\|\s*(\S+)\s*$")


def _repository_env() -> dict:
    """This process's environment with the repository first on ``PYTHONPATH`` (as a fresh command needs).

    Bytecode is written and read as on a user's installation: ``PYTHONDONTWRITEBYTECODE``, which
    some containers set, is dropped.  With it, every fresh process compiles acausal's sources
    again (about 0.07 s a command; the commands section measures it when the variable is set)
    while numpy's and scipy's, compiled when pip installed them, are read as bytecode: the
    floors would not be measured alike.
    """
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT)] + ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    return env


def _timed_process(argv: Sequence[str], env: dict,
                   timeout: float = COMMAND_TIMEOUT_SECONDS) -> tuple[float, int | str, str]:
    """``(wall seconds, exit status or "timeout", stderr)`` of ``argv`` run in the repository's folder."""
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(list(argv), cwd=str(ROOT), env=env, capture_output=True, text=True, timeout=timeout)
        status, stderr = proc.returncode, proc.stderr
    except subprocess.TimeoutExpired:
        status, stderr = "timeout", f"no result within {timeout:g} s"
    return time.perf_counter() - t0, status, stderr


def import_breakdown(argv: Sequence[str], env: dict | None = None, runs: int = IMPORT_BREAKDOWN_RUNS,
                     timeout: float = COMMAND_TIMEOUT_SECONDS) -> dict:
    """Where a fresh-process command's imports go: ``runs`` runs under ``python -X importtime``.

    Parameters
    ----------
    argv : sequence of str
        The command, ``[python, arg, ...]``; run as ``[python, "-X", "importtime", arg, ...]`` in
        the repository's folder.
    env : dict, optional
        Its environment (default: this process's, the repository on ``PYTHONPATH``).
    runs : int
        Runs; every figure is the median over them (one run on a shared machine is noisy).
    timeout : float
        Seconds after which a run is stopped.

    Returns
    -------
    dict
        ``import_wall``: a run's wall seconds (the instrumentation slows the imports a little);
        ``import_<package>_seconds`` for each of :data:`IMPORT_BREAKDOWN_PACKAGES` and ``other``:
        the own times of the modules of that top-level package, whoever imported them;
        ``import_seconds``: their sum; ``import_runs``; ``import_status``: the first nonzero exit
        status of the runs (0 when none).
    """
    env = env if env is not None else _repository_env()
    packages = (*IMPORT_BREAKDOWN_PACKAGES, "other")
    walls, statuses, measured = [], [], []
    for _ in range(max(1, runs)):
        wall, status, stderr = _timed_process([argv[0], "-X", "importtime", *argv[1:]], env, timeout)
        by_package = dict.fromkeys(packages, 0.0)
        for line in stderr.splitlines():
            match = _IMPORTTIME_LINE.match(line)
            if match is None:  # the header line, or the command's own messages
                continue
            package = match.group(3).split(".")[0]
            by_package[package if package in by_package else "other"] += int(match.group(1)) * 1e-6
        walls.append(wall)
        statuses.append(status)
        measured.append(by_package)
    record = {f"import_{package}_seconds": float(np.median([m[package] for m in measured])) for package in packages}
    record = {"import_wall": float(np.median(walls)), "import_seconds": sum(record.values()),
              "import_runs": len(walls), "import_status": next((s for s in statuses if s != 0), 0), **record}
    return record


def _import_floor_record(label: str, code: str, walls: Sequence[float], statuses: Sequence) -> dict:
    return {"kind": "import floor", "what": f'python -c "{code}"', "label": label, "runs": len(walls),
            "min_wall": min(walls), "median_wall": float(np.median(walls)), "max_wall": max(walls),
            "exit_statuses": " ".join(map(str, statuses))}


def _command_lines(result_folder: str) -> list[tuple[str, str, list[str]]]:
    """``(case, example, argv)`` of the suite's commands: every ``acausal compare``, then every
    ``acausal simulate`` (its CSV written into ``result_folder``)."""
    benchmarks = suite()
    lines = [(name, example, [sys.executable, "-m", "acausal", "compare", example])
             for name, example in benchmarks.COMMAND_TARGETS]
    for name, example in getattr(benchmarks, "SIMULATE_COMMAND_TARGETS", ()):
        out = os.path.join(result_folder, f"{name}.csv")
        lines.append((name, example, [sys.executable, "-m", "acausal", "simulate", example, "--out", out]))
    return lines


def _is_warm_target(record: dict) -> bool:
    """Whether ``record`` is a warm command the suite's warm-command target applies to."""
    return record.get("disk_cache") == "warm" and record.get("example") in suite().WARM_COMMAND_FILES


def run_commands_with_floors(repeats: int = 5, log: Callable[[str], None] | None = None,
                             disk_caches: Sequence[str] = ("cold", "warm"),
                             breakdown: bool = True) -> tuple[list[dict], list[dict]]:
    """The fresh-process commands and the import floors, timed in alternation.

    The whole command as a user runs it: interpreter start, imports,
    translation, simulation and, for ``acausal compare``, reading the
    reference and the tube test.  The commands are the suite's
    ``COMMAND_TARGETS`` (``acausal compare EXAMPLE``) and
    ``SIMULATE_COMMAND_TARGETS`` (``acausal simulate EXAMPLE --out FILE``,
    the file in a folder of the bench's own), each run ``repeats`` times per
    disk cache; after each round every import floor of :data:`IMPORT_FLOORS`
    runs once, so that a machine getting busier or quieter meanwhile weighs
    on commands and floors alike.

    Parameters
    ----------
    repeats : int
        Timed runs of each command and disk cache.
    log : callable, optional
        Receives a line per command.
    disk_caches : sequence of str
        ``"cold"``: the persistent compile cache off (every run compiles);
        ``"warm"``: a cache folder of its own, filled by one run that is not
        timed (every timed run loads its systems).
    breakdown : bool
        Run each warm command the suite's warm-command target applies to
        again under ``python -X importtime`` (:func:`import_breakdown`;
        its keys join the command's record).

    Returns
    -------
    tuple of list of dict
        The commands' records -- ``model``, ``example``, ``command``,
        ``disk_cache``, ``runs``, ``min_wall``, ``median_wall``,
        ``max_wall``, ``exit_statuses``, ``passed`` (every run exited with
        0: the comparison passed, the simulation succeeded), ``failure``,
        ``target`` and ``met`` (passed, median under
        :data:`COMMAND_TARGET_SECONDS`), ``import_numpy_wall`` and
        ``numpy_scipy_wall`` (the median of each import floor over the runs
        in this command's rounds: the machine's load when it ran),
        ``x_import_numpy`` (the median over ``import_numpy_wall``); on the
        warm target rows also
        ``warm_target_x_import_numpy`` and ``warm_target_met`` -- and the
        import floors' records (:func:`run_import_floors`' keys).
    """
    log = log or (lambda _s: None)
    base = _repository_env()
    cache_folder = tempfile.TemporaryDirectory(prefix="acausal-bench-cache-")
    result_folder = tempfile.TemporaryDirectory(prefix="acausal-bench-results-")
    envs = {}
    for kind in disk_caches:
        env = dict(base)
        env["ACAUSAL_DISK_CACHE"] = "off" if kind == "cold" else "on"
        if kind != "cold":
            env["ACAUSAL_CACHE_DIR"] = cache_folder.name
        envs[kind] = env
    floor_walls: dict[str, list[float]] = {label: [] for label, _ in IMPORT_FLOORS}
    floor_statuses: dict[str, list] = {label: [] for label, _ in IMPORT_FLOORS}
    records = []
    try:
        for name, example, argv in _command_lines(result_folder.name):
            command = "acausal " + " ".join(argv[3:5])
            if "warm" in envs:  # fill the cache
                _timed_process(argv, envs["warm"])
            walls = {kind: [] for kind in envs}
            statuses = {kind: [] for kind in envs}
            failures = {kind: "" for kind in envs}
            round_floors: dict[str, list[float]] = {label: [] for label, _ in IMPORT_FLOORS}
            for _ in range(repeats):
                for kind, env in envs.items():
                    wall, status, stderr = _timed_process(argv, env)
                    walls[kind].append(wall)
                    statuses[kind].append(status)
                    if status != 0 and not failures[kind]:
                        lines = stderr.strip().splitlines() or [f"exit status {status}"]
                        # the command's own error line, or the last line of a traceback
                        failures[kind] = next((line for line in lines if line.startswith("acausal")), lines[-1])
                for label, code in IMPORT_FLOORS:
                    wall, status, _ = _timed_process([sys.executable, "-c", code], base)
                    floor_walls[label].append(wall)
                    floor_statuses[label].append(status)
                    round_floors[label].append(wall)
            for kind in envs:
                w = walls[kind]
                ok = all(status == 0 for status in statuses[kind])
                record = {"model": name, "command": command, "disk_cache": kind,
                          "runs": repeats, "min_wall": min(w), "median_wall": float(np.median(w)),
                          "max_wall": max(w), "exit_statuses": " ".join(map(str, statuses[kind])),
                          "passed": ok, "failure": failures[kind], "target": COMMAND_TARGET_SECONDS,
                          "met": ok and float(np.median(w)) < COMMAND_TARGET_SECONDS, "example": example}
                # the floors of this command's own rounds: the load of the machine when it ran
                for (label, _), key in zip(IMPORT_FLOORS, FLOOR_WALL_KEYS):
                    record[key] = float(np.median(round_floors[label])) if round_floors[label] else math.nan
                if breakdown and _is_warm_target(record):
                    record.update(import_breakdown(argv, envs[kind]))
                    if os.environ.get("PYTHONDONTWRITEBYTECODE"):
                        # what acausal's import costs where no bytecode was ever written (this
                        # environment, before the bench wrote some): an empty bytecode folder of
                        # its own, so that every module is compiled from its source
                        with tempfile.TemporaryDirectory(prefix="acausal-bench-nopyc-") as empty:
                            uncached = import_breakdown(argv, {**envs[kind], "PYTHONDONTWRITEBYTECODE": "1",
                                                               "PYTHONPYCACHEPREFIX": empty})
                        record["import_acausal_seconds_without_bytecode"] = uncached["import_acausal_seconds"]
                records.append(record)
                log(f"  {record['command']} ({kind} disk cache): min {record['min_wall']:.2f} s, "
                    f"median {record['median_wall']:.2f} s, " + ("passed" if ok else f"FAILED: {failures[kind]}"))
    finally:
        cache_folder.cleanup()
        result_folder.cleanup()
    imports = [_import_floor_record(label, code, floor_walls[label], floor_statuses[label])
               for label, code in IMPORT_FLOORS if floor_walls[label]]
    limit = suite().WARM_COMMAND_MAX_X_IMPORT_NUMPY
    for record in records:
        numpy_floor = record[FLOOR_WALL_KEYS[0]]
        record["x_import_numpy"] = record["median_wall"] / numpy_floor if numpy_floor > 0 else math.nan
        if _is_warm_target(record):
            record["warm_target_x_import_numpy"] = limit
            record["warm_target_met"] = bool(record["passed"] and record["x_import_numpy"] <= limit)
    for r in imports:
        log(f"  {r['what']} (between the commands): median {r['median_wall']:.3f} s over {r['runs']} runs")
    return records, imports


def run_commands(repeats: int = 5, log: Callable[[str], None] | None = None,
                 disk_caches: Sequence[str] = ("cold", "warm"), breakdown: bool = True) -> list[dict]:
    """The commands' records of :func:`run_commands_with_floors` (the import floors timed between them
    give their ``x_import_numpy``)."""
    return run_commands_with_floors(repeats, log, disk_caches, breakdown)[0]


def _command_text(row: dict) -> str:
    """The command of a commands record or of a floors section's command row."""
    return row.get("command") or row.get("what", "")


def _package_seconds(row: dict, packages: Sequence[str]) -> float:
    return sum(float(row.get(f"import_{package}_seconds", 0.0) or 0.0) for package in packages)


def _warm_command_why(row: dict, limit: float) -> str:
    """Why a warm command misses ``limit`` × ``import numpy``, and what meeting it would take, from
    its import breakdown (:func:`import_breakdown`) when the row has one."""
    if not row.get("passed"):
        return f"the command failed: {row.get('failure', '')}"
    floor = row["median_wall"] / row["x_import_numpy"]
    parts = [f"{limit:g}× the floor is {limit * floor:.2f} s, {row['median_wall'] - limit * floor:.2f} s "
             "less than the median"]
    imports, wall = row.get("import_seconds"), row.get("import_wall")
    if _finite(imports) and _finite(wall) and wall > 0:
        listed = sorted(((package, float(row.get(f"import_{package}_seconds", 0.0) or 0.0))
                         for package in (*IMPORT_BREAKDOWN_PACKAGES, "other")), key=lambda item: -item[1])
        parts.append(f"imports are {imports / wall:.0%} of a run under `python -X importtime` ({imports:.2f} of "
                     f"{wall:.2f} s: " + ", ".join(f"{package} {seconds:.2f}" for package, seconds in listed
                                                     if seconds >= 0.005) + ")")
        # the instrumented seconds scaled to the median run
        scale = row["median_wall"] / wall
        compiler = _package_seconds(row, COMPILER_PACKAGES) * scale
        on_demand = _package_seconds(row, ON_DEMAND_PACKAGES) * scale
        if compiler + on_demand >= 0.005:
            left = row["median_wall"] - compiler - on_demand
            parts.append("a cache hit that loads neither " + "/".join(COMPILER_PACKAGES)
                         + (" nor " + "/".join(p for p in ON_DEMAND_PACKAGES
                                               if row.get(f"import_{p}_seconds", 0.0)) if on_demand >= 0.005 else "")
                         + f" would save about {compiler + on_demand:.2f} s, leaving about {left:.2f} s "
                         f"({left / floor:.1f}× the floor), of which acausal's own import is about "
                         f"{_package_seconds(row, ('acausal',)) * scale:.2f} s")
        else:
            parts.append("the compiler's packages are no longer loaded: what is left is acausal's own import "
                         f"({float(row.get('import_acausal_seconds', 0.0)) * scale:.2f} s) and its work")
    return "; ".join(parts) + "."


def command_target_checks(rows: Sequence[dict]) -> list[TargetCheck]:
    """The suite's warm-command target (``WARM_COMMAND_FILES``, ``WARM_COMMAND_MAX_X_IMPORT_NUMPY``)
    against ``rows``: the records of :func:`run_commands_with_floors` or the floors section's
    command rows.  One check per example and command (``simulate``, ``compare``)."""
    benchmarks = suite()
    limit = benchmarks.WARM_COMMAND_MAX_X_IMPORT_NUMPY
    checks = []
    for example in benchmarks.WARM_COMMAND_FILES:
        for verb in ("simulate", "compare"):
            command = f"acausal {verb} {example}"
            target = f'warm `{command}` ≤ {limit:g}× `python -c "import numpy"`'
            row = next((r for r in rows if r.get("disk_cache") == "warm" and _command_text(r) == command), None)
            if row is None or not _finite(row.get("x_import_numpy")):
                checks.append(TargetCheck(target, "-", None, "not timed warm beside `import numpy` in this run"))
                continue
            floor = row["median_wall"] / row["x_import_numpy"]
            same_rounds = " in the same rounds" if _finite(row.get("import_numpy_wall")) else ""
            measured = (f"{row['median_wall']:.2f} s = {row['x_import_numpy']:.1f}× ({floor:.3f} s), medians of "
                        f"{row['runs']} runs{same_rounds}")
            met = bool(row.get("passed")) and row["x_import_numpy"] <= limit
            checks.append(TargetCheck(target, measured, met, "" if met else _warm_command_why(row, limit)))
    return checks


def _import_breakdown_table(rows: Sequence[dict]) -> str:
    """A row per command broken down by :func:`import_breakdown` (empty when none was)."""
    measured = [r for r in rows if _finite(r.get("import_seconds"))]
    if not measured:
        return ""
    packages = (*IMPORT_BREAKDOWN_PACKAGES, "other")
    table = _md_table(("command", "disk cache", "wall under -X importtime [s]", "imports [s]", "imports / wall",
                       *(f"{p} [s]" for p in packages)),
                      [(_command_text(r), r.get("disk_cache", ""), r["import_wall"], r["import_seconds"],
                        f"{r['import_seconds'] / r['import_wall']:.0%}",
                        *(float(r.get(f"import_{p}_seconds", 0.0) or 0.0) for p in packages)) for r in measured])
    return "\n".join([
        "## Where a warm command's time goes", "",
        "Each warm target command run again under `python -X importtime`: every module's own import "
        "time, counted for its top-level package whoever imported it (sympy's mpmath apart); the median "
        f"of {measured[0].get('import_runs', 1)} runs per column. The instrumentation slows the imports, so "
        "read the shares. Bytecode is written and read as on a user's installation (the bench drops "
        "`PYTHONDONTWRITEBYTECODE`).", "", table, ""] + _without_bytecode_lines(measured))


def _without_bytecode_lines(rows: Sequence[dict]) -> list[str]:
    """What the warm commands' import of acausal costs where ``PYTHONDONTWRITEBYTECODE`` is set
    (measured only when the bench's own environment sets it)."""
    lines = [f"- `{_command_text(r)}`: acausal's own import {r['import_acausal_seconds_without_bytecode']:.3f} s "
             f"compiled from source against {float(r.get('import_acausal_seconds', 0.0)):.3f} s from bytecode"
             for r in rows if _finite(r.get("import_acausal_seconds_without_bytecode"))]
    if not lines:
        return []
    return ["This environment sets `PYTHONDONTWRITEBYTECODE=1`: where no bytecode was ever written, every "
            "fresh process compiles acausal's sources again, while numpy's were compiled when pip installed "
            "it. The same commands with an empty bytecode folder of their own (`PYTHONPYCACHEPREFIX`):", "",
            *lines, ""]


def _commands_markdown(records: Sequence[dict]) -> str:
    rows = [(r["command"], r.get("disk_cache", "warm"), r["runs"], f"{r['min_wall']:.2f}",
             f"{r['median_wall']:.2f}", f"{r['max_wall']:.2f}", _fmt(r.get("import_numpy_wall", math.nan), 3),
             _fmt(r.get("x_import_numpy", math.nan), 2),
             "yes" if r["passed"] else f"**no**: {r['failure']}",
             "met" if r["met"] else "**not met**") for r in records]
    table = _md_table(("command", "disk cache", "runs", "min wall [s]", "median wall [s]", "max wall [s]",
                       "import numpy in its rounds [s]", "× import numpy", "passed (exit status 0, every run)",
                       f"passed, median < {COMMAND_TARGET_SECONDS:g} s"), rows)
    floors = [r["import_numpy_wall"] for r in records if _finite(r.get("import_numpy_wall"))]
    floor_text = (f"`python -c \"import numpy\"` in the command's own rounds (timed once after each round; "
                  f"its medians {min(floors):.3f}–{max(floors):.3f} s over the commands)" if floors
                  else "`python -c \"import numpy\"` (not timed)")
    return "\n".join([
        "# Fresh-process commands", "",
        "Each command in a new Python process (`python -m acausal ...`), timed from outside: "
        "interpreter start, imports, translation, simulation and, for `compare`, reference reading and "
        "the tube test; `simulate` writes its CSV into a folder of the bench's own. A command passes when "
        "every run exited with status 0 (the comparison passed; the simulation succeeded). *cold*: the "
        "persistent compile cache off, every run compiles; *warm*: a cache folder filled by one untimed "
        "run, every timed run loads its compiled systems from it. *× import numpy*: the median over the "
        f"median of {floor_text}.", "",
        _targets_markdown(command_target_checks(records)),
        "## Commands", "", table, "",
        _import_breakdown_table(records)])


def fit_power_law(ns: Sequence[float], seconds: Sequence[float]) -> tuple[float, float]:
    """``(a, b)`` of ``seconds ≈ a n^b`` by least squares in log–log (NaN if < 2 points)."""
    pts = [(n, s) for n, s in zip(ns, seconds) if s is not None and s > 0 and math.isfinite(s)]
    if len(pts) < 2:
        return math.nan, math.nan
    x = np.log([p[0] for p in pts])
    y = np.log([p[1] for p in pts])
    b, log_a = np.polyfit(x, y, 1)
    return float(math.exp(log_a)), float(b)


def full_scaling_sizes() -> tuple[int, ...]:
    """The full bench's scaling sizes: :data:`FULL_SCALING` and the sizes of the suite's scaling targets
    (``SCALING_TIME_TARGETS``, ``SCALING_MEMORY_TARGET``), in order."""
    benchmarks = suite()
    targets = {n for n, _ in benchmarks.SCALING_TIME_TARGETS} | {benchmarks.SCALING_MEMORY_TARGET[0]}
    return tuple(sorted(set(FULL_SCALING) | targets))


def run_scaling(sizes: Sequence[int], stop_time: float = 0.2, isolate: bool = False,
                budget: float = SCALING_BUDGET_SECONDS,
                log: Callable[[str], None] | None = None) -> list[dict]:
    """Scaling points for ``sizes``; with ``isolate`` each in its own process under ``budget``.

    A point that does not finish within the budget keeps the phases it
    finished; the larger sizes are then skipped.  ``predicted_wall`` is the
    wall time the power law of the two previous points predicted.
    """
    log = log or (lambda _s: None)
    points: list[dict] = []
    stopped = None
    for n in sizes:
        if stopped is not None:
            points.append({"n": n, "status": f"skipped ({stopped})"})
            continue
        done = [p for p in points if p.get("status") == "ok"]
        predicted = math.nan
        if len(done) >= 2:
            a, b = fit_power_law([p["n"] for p in done[-2:]], [p["wall"] for p in done[-2:]])
            predicted = a * n ** b
        if isolate:
            point = _scaling_point_subprocess(n, stop_time, budget)
        else:
            try:
                point = scaling_point(n, stop_time)
            except Exception as exc:  # noqa: BLE001
                point = {"n": n, "status": f"failed: {type(exc).__name__}: {exc}"}
        point["predicted_wall"] = predicted
        points.append(point)
        log(f"  scaling N={n}: translation {point.get('translation', math.nan):.2f}s, structure "
            f"{point.get('structure', math.nan):.2f}s, simulate {point.get('simulate', math.nan):.2f}s, "
            f"wall {point.get('wall', math.nan):.1f}s ({point['status']})")
        if point["status"] != "ok":
            stopped = f"N={n} {point['status']}"
    return points


# ---------------------------------------------------------------------------
# Scaling with arrays: a model of any size that conserves a quantity
# ---------------------------------------------------------------------------

#: Sizes of the array case the scaling section translates, full and ``--quick``.
FULL_ARRAY_SCALING = (10, 30, 100, 300, 1000)
QUICK_ARRAY_SCALING = (10, 30, 100)
#: Output intervals of the array case's short run after translating.
ARRAY_SCALING_POINTS = 500
#: Wall-time budget of one array case point in its fresh process.
ARRAY_SCALING_BUDGET_SECONDS = 300.0
#: Translation whose log-log slope against N exceeds this grows clearly faster than linearly.
LINEAR_SLOPE_LIMIT = 1.3
#: The quantities of an array case point fitted as ``seconds ≈ a N^b``.
ARRAY_SCALING_FITTED = ("translation", "flatten", "compile", "translation_all", "simulate")


@dataclass(frozen=True)
class ArrayScalingCase:
    """The scaling section's array case: a model of any size built with arrays, conserving a quantity.

    Attributes
    ----------
    name : str
        The model's name in the table.
    make : callable
        ``make(n)``: the model of size ``n``.
    description : str
        What the model is, for ``scaling.md`` (Markdown).
    size_label : str
        What N counts (``"cells"``).
    quantity : str
        The conserved quantity, and ``unit`` its unit.
    unit : str
    balance : callable
        ``balance(result)``: ``(stored, came_in, rate_error)``, the quantity
        stored since the start and the quantity that came in (a quadrature
        of its inflow over the output points) at every output point, and the
        largest mismatch of their rates relative to the largest inflow.
    stop_time : float
        Seconds simulated after translating (RK45, :data:`ARRAY_SCALING_POINTS`
        output intervals).
    """

    name: str
    make: Callable[[int], Model]
    description: str
    size_label: str
    quantity: str
    unit: str
    balance: Callable[..., tuple]
    stop_time: float = 1.0


def array_scaling_case() -> ArrayScalingCase:
    """The scaling section's array case: the suite's ``array_scaling_case()``."""
    return suite().array_scaling_case()


def array_scaling_point(n: int, case: ArrayScalingCase | None = None, rtol: float = 1e-6,
                        progress: Callable[[dict], None] | None = None) -> dict:
    """Translate the array case of size ``n``, then simulate it briefly and check its balance.

    Parameters
    ----------
    n : int
        The size (``case.make(n)``).
    case : ArrayScalingCase, optional
        Default :func:`array_scaling_case`.
    rtol : float
        Relative tolerance of the short run (RK45).
    progress : callable, optional
        Receives the point measured so far after each phase (so a point stopped by a
        time budget keeps what it finished).

    Returns
    -------
    dict
        ``model``, ``n``; ``flatten`` (building, flattening and partitioning
        the model), ``compile`` (the stages of its first system),
        ``translation`` (their sum, as the drive train's *translation (1
        mode)*) and ``translation_all`` (with the initialization system), in
        seconds; ``seconds_per_element`` (``translation / n``); ``states``,
        ``equations``; ``simulate`` (the run's wall seconds); ``came_in`` and
        ``stored`` (the conserved quantity at the end of the run, see
        :class:`ArrayScalingCase`), ``balance_error``
        (``|stored - came_in| / |came_in|``) and ``rate_balance_error``;
        ``wall``, ``max_rss_mb``, ``status``.
    """
    from ..runtime.initialization import initialize

    case = case or array_scaling_case()
    progress = progress or (lambda _p: None)
    point: dict = {"model": case.name, "n": n, "status": "ok"}
    wall0 = time.perf_counter()

    def report(phase: str) -> None:
        point["phase"] = phase
        point["max_rss_mb"] = _rss_mb()
        point["wall"] = time.perf_counter() - wall0
        progress(dict(point))

    gc.collect()
    t0 = time.perf_counter()
    translation = _fresh_translate(case.make(n))
    point["flatten"] = time.perf_counter() - t0
    report("flattened; compiling")
    evaluator = _evaluator(translation)
    initialize(translation, evaluator, translation.flat.experiment.start_time)
    system = _first_system(translation)
    point["compile"] = system.seconds
    point["translation"] = point["flatten"] + system.seconds
    # the same flattening measure (the wall around building and translating) plus everything
    # compiled: the translation's own flatten_seconds leaves the model's building out
    point["translation_all"] = point["flatten"] + translation.translation_seconds - translation.flatten_seconds
    point["seconds_per_element"] = point["translation"] / n
    point["states"] = len(system.structure.states)
    point["equations"] = len(system.equations)
    report("simulating")
    result, point["simulate"] = _timed_simulate(translation, method="RK45", rtol=rtol, stop_time=case.stop_time,
                                                interval=case.stop_time / ARRAY_SCALING_POINTS)
    if result.status != 0:
        point["status"] = f"failed: {result.message}"
    else:
        stored, came_in, rate_error = case.balance(result)
        point["came_in"] = float(came_in[-1])
        point["stored"] = float(stored[-1])
        point["balance_error"] = abs(point["stored"] - point["came_in"]) / abs(point["came_in"])
        point["rate_balance_error"] = float(rate_error)
    point["wall"] = time.perf_counter() - wall0
    point["max_rss_mb"] = _rss_mb()
    point.pop("phase", None)
    return point


def _array_scaling_point_subprocess(n: int, timeout: float) -> dict:
    return _measured_point(n, f"array_scaling_point({n}, progress=report)", timeout)


def run_array_scaling(sizes: Sequence[int] = FULL_ARRAY_SCALING, case: ArrayScalingCase | None = None,
                      isolate: bool = False, budget: float = ARRAY_SCALING_BUDGET_SECONDS,
                      log: Callable[[str], None] | None = None) -> list[dict]:
    """Points of the array case (:func:`array_scaling_point`) for ``sizes``, each with ``local_slope``.

    With ``isolate`` each point runs in a fresh process (sympy's caches cold, as a
    user's first translation; the default case only) under ``budget`` seconds.
    After a point that does not finish the larger sizes are skipped.
    ``local_slope`` is the slope of log(translation) against log(N) from the
    previous size (NaN for the first).
    """
    if isolate and case is not None:
        raise ValueError("a case of its own runs in this process (isolate=False): a fresh process "
                         "makes the default case")
    log = log or (lambda _s: None)
    name = (case or array_scaling_case()).name
    points: list[dict] = []
    stopped = None
    for n in sizes:
        if stopped is not None:
            points.append({"model": name, "n": n, "status": f"skipped ({stopped})"})
            continue
        if isolate:
            point = _array_scaling_point_subprocess(n, budget)
        else:
            try:
                point = array_scaling_point(n, case)
            except Exception as exc:  # noqa: BLE001 - recorded, the bench goes on
                point = {"n": n, "status": f"failed: {type(exc).__name__}: {exc}"}
        point.setdefault("model", name)
        previous = next((p for p in reversed(points) if _finite(p.get("translation"))), None)
        point["local_slope"] = (fit_power_law([previous["n"], n], [previous["translation"], point["translation"]])[1]
                                if previous is not None and _finite(point.get("translation")) else math.nan)
        points.append(point)
        log(f"  {name} N={n}: translation {point.get('translation', math.nan):.2f}s "
            f"({1000 * point.get('seconds_per_element', math.nan):.2f} ms per element), simulate "
            f"{point.get('simulate', math.nan):.2f}s, balance error {point.get('balance_error', math.nan):.1e} "
            f"({point['status']})")
        if point["status"] != "ok":
            stopped = f"N={n} {point['status']}"
    return points


def _finite(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def array_scaling_fits(points: Sequence[dict]) -> dict[str, tuple[float, float]]:
    """``{quantity: (a, b)}`` of ``seconds ≈ a N^b`` (least squares in log-log) for
    :data:`ARRAY_SCALING_FITTED`; ``b`` is the slope (1 for linear time)."""
    fits = {}
    for key in ARRAY_SCALING_FITTED:
        measured = [p for p in points if _finite(p.get(key))]
        if len(measured) >= 2:
            fits[key] = fit_power_law([p["n"] for p in measured], [p[key] for p in measured])
    return fits


def _array_scaling_markdown(points: Sequence[dict], fits: dict, case: ArrayScalingCase,
                            isolated: bool = True) -> str:
    """The array case's part of ``scaling.md``: a row per N, the slopes, and a verdict."""
    rows = [(p["n"], p.get("states", math.nan), p.get("equations", math.nan), p.get("flatten", math.nan),
             p.get("compile", math.nan), p.get("translation", math.nan), p.get("translation_all", math.nan),
             1000.0 * p.get("seconds_per_element", math.nan), p.get("local_slope", math.nan),
             p.get("simulate", math.nan), p.get("came_in", math.nan), p.get("stored", math.nan),
             p.get("balance_error", math.nan), p.get("rate_balance_error", math.nan), p.get("wall", math.nan),
             p.get("max_rss_mb", math.nan), p.get("status", "")) for p in points]
    table = _md_table((f"N ({case.size_label})", "states", "equations", "flatten+partition [s]", "compile [s]",
                       "translation [s]", "translation + initialization [s]", "translation per element [ms]",
                       "slope from previous N", f"simulate {case.stop_time:g} s [s]",
                       f"{case.quantity} in [{case.unit}]", f"{case.quantity} stored [{case.unit}]",
                       "balance error", "rate balance error", "wall [s]", "max RSS [MB]", "status"), rows)
    fit_rows = []
    for key, (a, b) in fits.items():
        ns = [p["n"] for p in points if _finite(p.get(key))]
        fit_rows.append((key, _fmt(a), _fmt(b), ", ".join(map(str, ns))))
    fit_table = _md_table(("quantity", "a", "slope b (time ≈ a·N^b)", "fitted on N ="), fit_rows)
    slope = fits.get("translation", (math.nan, math.nan))[1]
    if not math.isfinite(slope):
        verdict = "Too few sizes finished to fit the slope."
    elif slope > LINEAR_SLOPE_LIMIT:
        verdict = (f"**Translation grows faster than linearly: slope {slope:.2f} > {LINEAR_SLOPE_LIMIT:g}** "
                   "(linear time gives 1).")
    else:
        verdict = f"Translation grows as N^{slope:.2f}: linear time gives a slope of 1."
    return "\n".join([
        f"## {case.name}: a model built with arrays", "",
        case.description + " " +
        ("Each size in a fresh process. " if isolated else "In the bench's own process (sympy's caches warm). ") +
        "Translation = flatten+partition (building the model's instances included) + compiling its first "
        "system; + initialization adds the initialization system. Then a "
        f"{case.stop_time:g} s run (RK45, rtol 1e-6, {ARRAY_SCALING_POINTS} output intervals): the balance "
        f"error is |stored - in| / |in| of the {case.quantity} at its end (what came in: trapezoid rule over "
        "the output points), the rate balance error the largest mismatch of the rates relative to the "
        "largest inflow.", "", verdict, "", table, "", fit_table, ""])


# ---------------------------------------------------------------------------
# Tables and plots
# ---------------------------------------------------------------------------


def _fmt(value, digits: int = 3) -> str:
    if value is None:
        return "-"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, str):
        return value
    if math.isnan(value):
        return "-"
    if math.isinf(value):
        return "inf"
    if value == 0:
        return "0"
    return f"{value:.{digits}g}"


def _md_table(header: Sequence[str], rows: Sequence[Sequence]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    lines += ["| " + " | ".join(_fmt(c) if not isinstance(c, str) else c for c in row) + " |" for row in rows]
    return "\n".join(lines)


@dataclass(frozen=True)
class TargetCheck:
    """One of a section's targets (the suite's) against what the bench measured.

    Attributes
    ----------
    target : str
        The target in words (Markdown).
    measured : str
        The measured figure in words (Markdown); ``"-"`` when nothing was measured.
    met : bool or None
        Whether the measurement meets the target; None when it was not measured
        (a prediction is never a measurement).
    why : str
        For a target not met or not measured: why, and what meeting it would
        take, from the measured figures where they tell.
    """

    target: str
    measured: str
    met: bool | None
    why: str = ""

    @property
    def verdict(self) -> str:
        """``met``, ``not met`` or ``not measured``."""
        return "not measured" if self.met is None else "met" if self.met else "not met"


def _cell(text: str) -> str:
    """``text`` as one Markdown table cell (its pipes escaped, on one line)."""
    return text.replace("|", "\\|").replace("\n", " ")


def _targets_markdown(checks: Sequence[TargetCheck]) -> str:
    """The ``## Targets`` part of a section's Markdown: a row per check ("" for none)."""
    if not checks:
        return ""
    verdicts = {"met": "met", "not met": "**not met**", "not measured": "not measured"}
    rows = [(_cell(c.target), _cell(c.measured), verdicts[c.verdict], _cell(c.why) or "-") for c in checks]
    return "\n".join([
        "## Targets", "",
        f"The targets of {suite().TARGETS_SOURCE} (`examples/benchmarks.py`) against this run. Met only when "
        "measured so; a size not run is *not measured*, whatever an extrapolation says. " + _machine_load(), "",
        _md_table(("target", "measured", "verdict", "why / what it would take"), rows), ""])


def _machine_load() -> str:
    """The machine's CPUs and load averages now, in words: the targets are wall times, which other
    work on a shared machine stretches."""
    try:
        one, five, fifteen = os.getloadavg()
    except (AttributeError, OSError):  # pragma: no cover - not on this platform
        return f"Machine: {os.cpu_count()} CPUs."
    return (f"Machine: {os.cpu_count()} CPUs, load average {one:.1f} / {five:.1f} / {fifteen:.1f} over the last "
            "1 / 5 / 15 minutes when this was written (the bench's own processes included); a load above the "
            "CPUs stretches every wall time.")


def _status_text(record: RunRecord) -> str:
    if record.status == 0:
        return "ok"
    return "FAILED: " + record.message.replace("|", "/").replace("\n", " ")[:90]


def _work_precision_summary(runs: Sequence[CaseRun]) -> tuple[str, str, str]:
    """(fastest method per accuracy target, cost per decade, fixed cost) as Markdown."""
    fastest_rows = []
    decade_rows = []
    for run in runs:
        ok = [r for r in run.records if r.ok]
        if not ok:
            continue
        errors = [max(r.error, ERROR_FLOOR) for r in ok]
        hi = math.floor(math.log10(max(errors)))
        lo = math.ceil(math.log10(min(errors)))
        for k in range(hi, lo - 1, -1):
            target = 10.0 ** k
            reaching = [r for r in ok if r.error <= target]
            if reaching:
                best = min(reaching, key=lambda r: r.sim_seconds)
                cheapest = min(reaching, key=lambda r: r.rhs_evaluations)
                fastest_rows.append((run.case.name, f"{target:.0e}", best.method, f"{best.rtol:.0e}",
                                     best.error, best.sim_seconds, best.rhs_evaluations,
                                     f"{cheapest.method} ({cheapest.rtol:.0e})", cheapest.rhs_evaluations))
        floor = min(errors)
        for method in dict.fromkeys(r.method for r in run.records):
            mine = sorted((r for r in ok if r.method == method), key=lambda r: -r.rtol)
            if len(mine) < 2:
                continue
            # time per decade of error, on the points above the case's floor (3x)
            usable = [r for r in mine if r.error >= 3 * floor and r.error > ERROR_FLOOR]
            if len(usable) >= 3 and max(r.error for r in usable) / min(r.error for r in usable) > 10:
                s_err = np.polyfit(-np.log10([r.error for r in usable]),
                                   np.log10([r.sim_seconds for r in usable]), 1)[0]
                per_err = 10 ** s_err
            else:
                per_err = math.nan
            s_rtol_t = np.polyfit(-np.log10([r.rtol for r in mine]),
                                  np.log10([r.sim_seconds for r in mine]), 1)[0]
            s_rtol_f = np.polyfit(-np.log10([r.rtol for r in mine]),
                                  np.log10([max(r.rhs_evaluations, 1) for r in mine]), 1)[0]
            decade_rows.append((run.case.name, method, per_err, 10 ** s_rtol_t, 10 ** s_rtol_f,
                                min(r.sim_seconds for r in mine), max(r.sim_seconds for r in mine)))
    overhead_rows = []
    for run in runs:
        ok = [r for r in run.records if r.status == 0 and math.isfinite(r.sim_seconds)]
        if len(ok) < 3 or len({r.rhs_evaluations for r in ok}) < 2:
            continue
        nfev = np.array([r.rhs_evaluations for r in ok], dtype=float)
        secs = np.array([r.sim_seconds for r in ok])
        slope, intercept = np.polyfit(nfev, secs, 1)
        share = intercept / np.median(secs) if np.median(secs) > 0 else math.nan
        overhead_rows.append((run.case.name, intercept, slope * 1e6, share, int(nfev.min()), int(nfev.max())))
    fastest = _md_table(("case", "error ≤", "fastest method", "rtol", "error", "sim time [s]", "rhs evals",
                         "fewest rhs evals: method (rtol)", "its rhs evals"), fastest_rows)
    overhead = _md_table(("case", "fixed cost per simulate call [s]", "µs per rhs evaluation",
                          "fixed cost / median run", "rhs evals min", "rhs evals max"), overhead_rows)
    decades = _md_table(("case", "method", "time × per decade of error", "time × per decade of rtol",
                         "rhs evals × per decade of rtol", "min time [s]", "max time [s]"), decade_rows)
    return fastest, decades, overhead


def _bench_markdown(runs: Sequence[CaseRun], quick: bool, wall: float) -> str:
    parts = [f"# Work-precision benchmark ({'quick' if quick else 'full'})", "",
             f"Python {platform.python_version()}, {platform.machine()}, {os.cpu_count()} CPUs; "
             f"bench wall time {wall:.1f} s.", "",
             f"*error*: {suite().EXACT_ERROR_TEXT}; "
             "MSL cases: max over compared continuous signals of max |y - y_ref| / dy at the reference "
             "times (dy = csv-compare tube half-height, rel. tol. 2e-3), limited below by the reference's "
             "own accuracy. *tube*: worst violation of the tube test in dy (0 = pass). "
             "*event-time error* in s. Sim time: the smallest wall time of the repeated "
             "`simulate(translation, ...)` calls after a warm-up.", "",
             "## Translation (once per case: fresh translate + first simulate)", ""]
    trows = []
    for run in runs:
        info = run.translation
        stages = info.stage_seconds
        trows.append((run.case.name, info.flatten_seconds, info.modes, info.initial_systems,
                      stages.get("alias", math.nan), stages.get("structure", math.nan),
                      stages.get("blt", math.nan), stages.get("algebraic", math.nan),
                      stages.get("codegen", math.nan), info.per_mode_seconds, info.translate_seconds,
                      info.first_simulate_seconds, info.modes_after_bench,
                      "ok" if info.status == 0 else "FAILED: " + info.message[:80]))
    parts.append(_md_table(("case", "flatten+partition [s]", "modes", "init systems", "alias [s]",
                            "structure [s]", "blt [s]", "algebraic [s]", "codegen [s]", "per mode [s]",
                            "translate_seconds", "first simulate [s]", "modes after bench", "status"), trows))
    parts += ["", "Stage columns are summed over the modes compiled by the first simulation; "
              "`first simulate` is its wall time (compiling modes and initialization systems included); "
              "`modes after bench` counts the discrete states compiled once every method and tolerance ran.",
              "", "## Runs", ""]
    rows = []
    for run in runs:
        for r in run.records:
            rows.append((r.case, r.method, f"{r.rtol:.0e}", r.error, r.tube, r.event_error, r.sim_seconds,
                         r.rhs_evaluations, r.steps, r.events, _status_text(r)))
    parts.append(_md_table(("case", "method", "rtol", "error", "tube [dy]", "event-time error [s]",
                            "sim time [s]", "rhs evals", "steps", "events", "status"), rows))
    fastest, decades, overhead = _work_precision_summary(runs)
    parts += ["", "## Fastest method per accuracy", "",
              "For each error level the quickest run (any method and rtol) reaching it, and the run "
              "reaching it with the fewest right-hand side evaluations (the integrator's own work, free "
              "of the fixed cost of a call, see below).", "", fastest,
              "", "## Cost per decade", "",
              "Growth factor of the simulation time (and of the rhs evaluations) per decade, from a "
              "least-squares line in log-log; per decade of error only on the points above three "
              "times the case's smallest error (where the reference's accuracy is not yet reached).",
              "", decades, "",
              "## Fixed cost of a simulate call", "",
              "Least-squares line sim time ≈ c0 + c1 · rhs evaluations over all successful runs of a case "
              "(every method and rtol): c0 is what a call costs whatever the tolerance (initialization, "
              "event iterations, starting the solver in each discrete state, building the result on the "
              "output grid), c1 the cost of one right-hand side evaluation with its share of the step "
              "(for Radau and BDF including their finite-difference Jacobians and linear solves).", "",
              overhead, ""]
    return "\n".join(parts)


def _write_bench_csv(path: Path, runs: Sequence[CaseRun]) -> None:
    fields = ("case", "method", "rtol", "error", "error_unit", "tube", "event_error", "sim_seconds",
              "rhs_evaluations", "steps", "events", "status", "message", "repeats", "translate_seconds",
              "first_simulate_seconds")
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(fields)
        for run in runs:
            for r in run.records:
                writer.writerow([r.case, r.method, repr(r.rtol), repr(r.error), r.error_unit, repr(r.tube),
                                 repr(r.event_error), repr(r.sim_seconds), r.rhs_evaluations, r.steps,
                                 r.events, r.status, r.message, r.repeats,
                                 repr(run.translation.translate_seconds),
                                 repr(run.translation.first_simulate_seconds)])


_METHOD_STYLE = {"RK45": ("tab:blue", "o"), "DOP853": ("tab:orange", "s"), "Radau": ("tab:green", "^"),
                 "BDF": ("tab:purple", "D"), "LSODA": ("tab:brown", "v"), "Euler": ("tab:gray", "<"),
                 "RK4": ("tab:olive", ">")}


def _log_limits(values: Sequence[float], min_decades: float) -> tuple[float, float]:
    """Axis limits around ``values`` spanning at least ``min_decades`` decades."""
    lo, hi = math.log10(min(values)), math.log10(max(values))
    pad = max(0.15 * (hi - lo), 0.5 * max(0.0, min_decades - (hi - lo)), 0.1)
    return 10 ** (lo - pad), 10 ** (hi + pad)


def _annotate_apart(ax, labels) -> None:
    """Write ``rtol`` labels at their points, skipping any that would overlap one already written."""
    if not labels:
        return
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    span_x = math.log10(x1 / x0) or 1.0
    span_y = math.log10(y1 / y0) or 1.0
    written: list[tuple[float, float]] = []
    for rtol, x, y, color in labels:
        u, v = math.log10(x / x0) / span_x, math.log10(y / y0) / span_y
        if any(abs(u - a) < 0.14 and abs(v - b) < 0.06 for a, b in written):
            continue
        written.append((u, v))
        ax.annotate(f"rtol {rtol:.0e}", (x, y), textcoords="offset points", xytext=(4, 6), fontsize=7,
                    color=color)


def _plot_work_precision(runs: Sequence[CaseRun], path: Path, quantity: str,
                         cost: str = "sim_seconds") -> Path | None:
    """One subplot per case: ``quantity`` (x, log) against ``cost`` (y, log), a line per method."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.ticker import LogLocator, NullFormatter
    from matplotlib.transforms import blended_transform_factory

    def label_of(q: str) -> str:
        return "error" if q == "error" else "event-time error"

    shown = [run for run in runs if quantity == "error" or
             any(r.ok and math.isfinite(r.event_error) for r in run.records)]
    if not shown:
        return None
    ncols = min(3, len(shown))
    nrows = math.ceil(len(shown) / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(5.4 * ncols, 4.3 * nrows + 0.8), squeeze=False)
    for ax in axes.flat[len(shown):]:
        ax.set_visible(False)
    all_methods: list[str] = []
    any_failed = False
    for ax, run in zip(axes.flat, shown):
        methods = list(dict.fromkeys(r.method for r in run.records))
        all_methods += [m for m in methods if m not in all_methods]
        clipped = False
        xs_all, ys_all = [], []
        labels: list = []
        for i, method in enumerate(methods):
            color, marker = _METHOD_STYLE.get(method, ("black", "o"))
            mine = sorted((r for r in run.records if r.method == method and r.ok
                           and math.isfinite(getattr(r, quantity))), key=lambda r: -r.rtol)
            if not mine:
                continue
            x = [max(getattr(r, quantity), ERROR_FLOOR) for r in mine]
            clipped |= any(getattr(r, quantity) < ERROR_FLOOR for r in mine)
            y = [max(float(getattr(r, cost)), 1e-9) for r in mine]
            xs_all += x
            ys_all += y
            ax.plot(x, y, "-", color=color, marker=marker, ms=5, lw=1.3, alpha=0.9)
            if i == 0:  # label (some of) the tolerances along the first method's line
                labels = [(r.rtol, xx, yy, color) for r, xx, yy in zip(mine, x, y)
                          if round(-math.log10(r.rtol)) % 3 == 0 or r is mine[-1]]
        failed = [r for r in run.records if r.status != 0 or not math.isfinite(getattr(r, quantity))]
        if xs_all:
            ax.set_xlim(*_log_limits(xs_all, 2.0))
            if max(xs_all) <= 1.5 * min(xs_all):
                ax.text(0.03, 0.97, f"every run: {label_of(quantity)} ≈ {np.median(xs_all):.2g}",
                        transform=ax.transAxes, va="top", fontsize=8)
        if failed:
            any_failed = True
            ok_y = [float(getattr(r, cost)) for r in run.records if r.ok]
            fallback = float(np.nanmax(ok_y)) if ok_y else 1.0
            ys = []
            for r in failed:
                y = float(getattr(r, cost))
                ys.append(y if math.isfinite(y) and y > 0 else fallback)
            ys_all += ys
            trans = blended_transform_factory(ax.transAxes, ax.transData)
            ax.plot([0.97] * len(ys), ys, "x", color="red", ms=9, mew=2, transform=trans, clip_on=False)
            ax.text(0.97, 0.02, f"{len(failed)} failed", transform=ax.transAxes, ha="right", va="bottom",
                    fontsize=8, color="red")
        if ys_all:
            ax.set_ylim(*_log_limits(ys_all, 1.0))
        log_axes = []
        if xs_all:
            ax.set_xscale("log")
            log_axes.append(ax.xaxis)
        else:  # every run failed or had nothing to measure: an empty log axis cannot be drawn
            ax.text(0.5, 0.5, f"no {label_of(quantity)} measured", transform=ax.transAxes,
                    ha="center", va="center", fontsize=9)
        if ys_all:
            ax.set_yscale("log")
            log_axes.append(ax.yaxis)
        _annotate_apart(ax, labels)
        for axis in log_axes:
            axis.set_major_locator(LogLocator(base=10, numticks=8))
            axis.set_minor_formatter(NullFormatter())
        unit = run.case.error_unit if quantity == "error" else "s"
        label = label_of(quantity)
        ax.set_xlabel(f"{label} [{unit}]" + (f" (0 shown at {ERROR_FLOOR:.0e})" if clipped else ""))
        ax.set_ylabel("simulation time [s]" if cost == "sim_seconds" else "right-hand side evaluations")
        ax.set_title(run.case.name, fontsize=11)
        ax.grid(True, which="major", alpha=0.4)
        ax.grid(True, which="minor", alpha=0.12)
    handles = [Line2D([], [], color=_METHOD_STYLE.get(m, ("black", "o"))[0],
                      marker=_METHOD_STYLE.get(m, ("black", "o"))[1], label=m) for m in all_methods]
    if any_failed:
        handles.append(Line2D([], [], color="red", marker="x", ls="", mew=2, ms=8, label="failed run"))
    what = "simulation time" if cost == "sim_seconds" else "right-hand side evaluations"
    title = (f"Work-precision: error against {what} (one marker per rtol)"
             if quantity == "error" else f"Work-precision: event-time error against {what}")
    fig.suptitle(title, fontsize=12)
    height = 4.3 * nrows + 0.8
    fig.legend(handles=handles, loc="upper center", ncol=len(handles), fontsize=9, frameon=False,
               bbox_to_anchor=(0.5, 1 - 0.32 / height))
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.62 / height))
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _effects_markdown(records: Sequence[EffectsRecord]) -> str:
    rows = [(r.case, r.output, f"{r.rtol:.0e}", f"{r.states_kept} / {r.states_total}",
             f"{r.derivative_steps_kept} / {r.derivative_steps_full}", f"{r.steps_kept} / {r.steps_full}",
             r.sim_seconds_full, r.sim_seconds_pruned,
             (r.sim_seconds_full / r.sim_seconds_pruned) if r.sim_seconds_pruned else math.nan,
             r.max_abs_difference, r.max_rel_difference, r.status) for r in records]
    table = _md_table(("model", "requested output", "rtol", "states kept / total",
                       "derivative steps kept / full", "all steps kept / full", "sim full [s]",
                       "sim pruned [s]", "speed-up", "max \\|Δ output\\|", "max \\|Δ\\| / max \\|y\\|", "status"), rows)
    return "\n".join([
        "# Effects on demand", "",
        "`simulate(..., outputs=[one speed])` against the full model: states and equations that cannot "
        "influence the requested output or the watched relations are left out. States and steps of the "
        "first compiled system; simulation time: the smallest of the repeated runs with a reused "
        "translation (RK45).", "", table, ""])


def _per_equation_kb(point: dict, key: str = "max_rss_mb") -> float:
    """Peak resident memory per equation, in kB (what the process holds, the
    interpreter and libraries included: the small sizes overstate it).  ``key``:
    ``max_rss_mb`` (the whole point, its simulations and results included) or
    ``translated_rss_mb`` (the peak until the model is translated and initialized)."""
    rss, equations = point.get(key, math.nan), point.get("equations", math.nan)
    try:
        return 1000.0 * float(rss) / float(equations)
    except (TypeError, ValueError, ZeroDivisionError):
        return math.nan


#: The phases of a scaling point that make up its ``translated_initialized`` seconds, as the table names them.
SCALING_PHASES = (("flatten", "flatten+partition"), ("specialise", "specialise"), ("alias", "alias"),
                  ("structure", "structure"),
                  ("blt", "blt"), ("algebraic", "algebraic"), ("codegen", "codegen"),
                  ("evaluator_setup", "event setup"), ("initial_systems", "initialization systems"),
                  ("initialization", "initialization"))


def _local_power_law(finished: Sequence[dict], key: str) -> tuple[float, float, str]:
    """``(a, b, basis)``: the power law of ``key`` through the two largest of ``finished`` (NaN, NaN, "" when
    fewer than two), ``basis`` saying so in words."""
    measured = [p for p in finished if _finite(p.get(key))]
    if len(measured) < 2:
        return math.nan, math.nan, ""
    p, q = measured[-2:]
    a, b = fit_power_law([p["n"], q["n"]], [p[key], q[key]])
    return a, b, f"the power law through N = {p['n']} and {q['n']} (b = {b:.2f})"


def _scaling_time_why(point: dict, limit: float, finished: Sequence[dict]) -> str:
    """Why ``point`` took longer than ``limit`` to translate and initialize, and what it would take."""
    seconds, equations = point["translated_initialized"], point.get("equations", math.nan)
    phases = sorted(((label, point[key]) for key, label in SCALING_PHASES if _finite(point.get(key))),
                    key=lambda item: -item[1])
    parts = [f"{seconds - limit:.3g} s over"]
    if _finite(equations) and equations > 0:
        parts[0] += (f": {1e3 * limit / equations:.2f} ms per equation needed, {1e3 * seconds / equations:.2f} "
                     f"measured ({seconds / limit:.1f}× too slow)")
    # initialization compiles every discrete state its event iteration visits, not only the first
    rest = seconds - sum(value for _, value in phases)
    if rest > 0.05 * seconds:
        phases = sorted(phases + [("the other discrete states compiled at initialization", rest)],
                        key=lambda item: -item[1])
    if phases:
        parts.append("largest phases " + ", ".join(f"{label} {value:.2g} s" for label, value in phases[:4]))
    smaller = [p for p in finished if p["n"] < point["n"]]
    _, b, _ = _local_power_law(smaller + [point], "translated_initialized")
    if math.isfinite(b):
        parts.append(f"growth b = {b:.2f} up to N = {point['n']}" + (
            ": already about linear, so it takes less work per equation (the same structure "
            "compiled once per class, not once per instance), not a better growth" if b < LINEAR_SLOPE_LIMIT
            else ": faster than linear, so the growth itself has to come down first"))
    return "; ".join(parts) + "."


def scaling_target_checks(points: Sequence[dict], budget: float | None = SCALING_BUDGET_SECONDS) -> list[TargetCheck]:
    """The suite's ``SCALING_TIME_TARGETS`` and ``SCALING_MEMORY_TARGET`` against the scaling points.

    A point stopped by the time ``budget`` (a fresh process's; None: no
    budget) has not met a time target no larger than the budget; a size
    not run is not measured, with the local power law's prediction as the
    reason.
    """
    benchmarks = suite()
    by_n = {p["n"]: p for p in points}
    finished = [p for p in points if p.get("status") == "ok"]
    checks = []
    for n, limit in benchmarks.SCALING_TIME_TARGETS:
        target = f"N = {n}: translated and initialized ≤ {limit:g} s"
        point = by_n.get(n)
        a, b, basis = _local_power_law([p for p in finished if p["n"] < n], "translated_initialized")
        predicted = a * n ** b if math.isfinite(b) else math.nan
        prediction = f"{basis} predicts {predicted:.3g} s" if math.isfinite(predicted) else ""
        if point is not None and point.get("status") == "ok" and _finite(point.get("translated_initialized")):
            seconds, equations = point["translated_initialized"], point.get("equations", math.nan)
            measured = f"{seconds:.3g} s ({_fmt(equations)} equations)"
            met = seconds <= limit
            checks.append(TargetCheck(target, measured, met, "" if met else _scaling_time_why(point, limit, finished)))
        elif (point is not None and str(point.get("status", "")).startswith("stopped") and budget is not None
              and budget >= limit):
            done = [label for key, label in SCALING_PHASES if _finite(point.get(key))]
            why = (f"stopped after the budget of {budget:g} s" + (f", having finished {', '.join(done)}" if done
                                                                  else " before flattening finished")
                   + (f"; {prediction}" if prediction else "") + ".")
            checks.append(TargetCheck(target, f"not finished: {point['status']}", False, why))
        else:
            reason = (f"N = {n} {point['status']}" if point is not None else f"N = {n} not run")
            checks.append(TargetCheck(target, "-", None, reason + (f"; {prediction}" if prediction else "") + "."))
    n, kb_limit = benchmarks.SCALING_MEMORY_TARGET
    # (the measure of the time target it goes with: the model translated and initialized;
    # the whole point's peak, its runs' results included, is given beside it)
    key = "translated_rss_mb"
    target = f"N = {n}: peak memory translated and initialized ≤ {kb_limit:g} kB per equation"
    point = by_n.get(n)
    kb = _per_equation_kb(point, key) if point is not None and point.get("status") == "ok" else math.nan
    if not math.isfinite(kb):
        reason = f"N = {n} {point['status']}" if point is not None else f"N = {n} not run"
        checks.append(TargetCheck(target, "-", None, reason + "."))
    else:
        measured = (f"{kb:.3g} kB ({point[key]:.0f} MB peak RSS, {_fmt(point['equations'])} equations); "
                    f"with its two simulations and their results {_per_equation_kb(point):.3g} kB "
                    f"({point['max_rss_mb']:.0f} MB)")
        met = kb <= kb_limit
        why = ""
        smaller = [p for p in finished if p["n"] < n and _finite(_per_equation_kb(p, key))]
        if not met and smaller:
            first, previous = smaller[0], smaller[-1]
            marginal = (1000.0 * (point[key] - previous[key])
                        / (point["equations"] - previous["equations"]))
            why = (f"the process holds {first[key]:.0f} MB at N = {first['n']} (interpreter, libraries); "
                   f"from N = {previous['n']} to {n} the peak grows by {marginal:.3g} kB per added equation")
            why += (f": {kb_limit:g} kB needs the memory held per equation cut {marginal / kb_limit:.1f}×."
                    if marginal > kb_limit else
                    ", within the target: the fixed part is what weighs at this size.")
        elif not met:
            why = "no smaller size to tell the fixed part from the part per equation."
        checks.append(TargetCheck(target, measured, met, why))
    return checks


def _scaling_markdown(points: Sequence[dict], fits: dict, isolated: bool = True,
                      budget: float | None = SCALING_BUDGET_SECONDS) -> str:
    rows = []
    for p in points:
        rows.append((p["n"], p.get("states", math.nan), p.get("equations", math.nan),
                     p.get("modes", math.nan), p.get("flatten", math.nan), p.get("alias", math.nan),
                     p.get("structure", math.nan), p.get("blt", math.nan), p.get("algebraic", math.nan),
                     p.get("codegen", math.nan), p.get("translation", math.nan),
                     p.get("translation_all_modes", math.nan), p.get("evaluator_setup", math.nan),
                     p.get("initial_systems", math.nan), p.get("initialization", math.nan),
                     p.get("translated_initialized", math.nan), p.get("first_simulate", math.nan),
                     p.get("simulate", math.nan), p.get("wall", math.nan), p.get("predicted_wall", math.nan),
                     p.get("translated_rss_mb", math.nan), _per_equation_kb(p, "translated_rss_mb"),
                     p.get("max_rss_mb", math.nan), _per_equation_kb(p), p.get("status", "")))
    table = _md_table(("N", "states", "equations", "modes", "flatten+partition [s]", "alias [s]",
                       "structure [s]", "blt [s]", "algebraic [s]", "codegen [s]", "translation (1 mode) [s]",
                       "translation (all modes) [s]", "event setup [s]", "initialization systems [s]",
                       "initialization [s]", "translated + initialized [s]",
                       "first simulate [s]", "simulate 0.2 s [s]", "wall [s]", "predicted wall [s]",
                       "max RSS translated [MB]", "per equation [kB]",
                       "max RSS [MB]", "RSS per equation [kB]", "status"),
                      rows)
    fit_rows = []
    for name, (a, b) in fits.items():
        ns = [p["n"] for p in points if isinstance(p.get(name), (int, float)) and math.isfinite(p[name])]
        fit_rows.append((name, _fmt(a), _fmt(b), ", ".join(map(str, ns))))
    fit_table = _md_table(("quantity", "a", "b (time ≈ a·N^b)", "fitted on N ="), fit_rows)
    ok = [p["n"] for p in points if p.get("status") == "ok"]
    not_ok = [p for p in points if p.get("status") != "ok"]
    if not_ok:
        first = not_ok[0]
        limit = (f"**The bench stopped at N = {max(ok)}**" if ok else "**No size finished**") + \
            (f": N = {first['n']} {first['status']}" + ("; larger sizes were not tried." if len(not_ok) > 1
                                                      else ".") + " Phases a stopped point finished are "
             "in the table and in the fits.")
    else:
        limit = f"Every size finished (largest N = {max(ok)})." if ok else ""
    return "\n".join([
        "# Scaling", "",
        suite().SCALING_DESCRIPTION + "; " +
        ("each size in a fresh process (sympy's caches cold, as for a user's first translation; the "
         "garbage collector set as in an `acausal` command). " if isolated else
         "in the bench's own process (sympy's caches warm from earlier translations, so faster than a "
         "first translation). ") +
        "Translation (1 mode) = flatten+partition (in a fresh process with it the compiler's import, "
        "which `import acausal` leaves to the first translation) + the stages (alias, structure, blt, "
        "algebraic, codegen) of the first compiled system; all modes: flatten+partition + every discrete "
        "state compiled by the first simulation. Event setup: building the discrete evaluator (once per "
        "translation). Initialization systems: compiling the initialization problems (matching, BLT, "
        "solving, code; their modes' systems are in the stage columns). Initialization: solving them "
        "and the event iteration at the start time, nothing compiled. Translated + initialized: "
        "flatten+partition, event setup and the initialization with everything it compiles, what a user "
        "waits for before the first step (the targets' measure). First simulate: wall time of the first "
        "run after initialization (it repeats the "
        "initialization with everything compiled). Simulate: a second 0.2 s run "
        "with the translation reused (RK45, rtol 1e-6, 500 output points). Predicted wall: the power "
        "law through the two previous sizes. Max RSS translated: the peak resident memory of the process "
        "until the model is translated and initialized (the memory target's measure); max RSS: the "
        "peak of the whole point, its two simulations and their results (every variable's column at "
        "501 points) included; per equation: either over the equations (the interpreter and libraries "
        "included, which the small sizes overstate).",
        "", limit, "", _targets_markdown(scaling_target_checks(points, budget if isolated else None)),
        "## Sizes", "", table, "", fit_table, ""])


def _size_axis(ax, sizes, label: str) -> None:
    """A logarithmic x axis of model sizes with a tick at each size measured."""
    from matplotlib.ticker import FixedFormatter, FixedLocator, NullFormatter, NullLocator

    ax.xaxis.set_major_locator(FixedLocator(list(sizes)))
    ax.xaxis.set_major_formatter(FixedFormatter([str(n) for n in sizes]))
    ax.xaxis.set_minor_locator(NullLocator())
    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel(label)


def _plot_scaling(points: Sequence[dict], fits: dict, path: Path) -> Path | None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    done = [p for p in points if isinstance(p.get("flatten"), (int, float))]
    if not done:
        return None
    ns = np.array([p["n"] for p in done], dtype=float)
    fig, ax = plt.subplots(figsize=(10.5, 5.5))
    series = [("flatten", "flatten+partition", "tab:gray", "o"), ("alias", "alias", "tab:cyan", "v"),
              ("structure", "structure", "tab:red", "s"), ("blt", "blt", "tab:pink", "<"),
              ("algebraic", "algebraic", "tab:olive", ">"), ("codegen", "codegen", "tab:purple", "D"),
              ("translation", "translation (1 mode)", "black", "o"),
              ("evaluator_setup", "event setup", "tab:brown", "^"),
              ("initial_systems", "initialization systems", "tab:green", "X"),
              ("initialization", "initialization (solve only)", "tab:orange", "P"),
              ("translated_initialized", "translated + initialized", "darkgreen", "h"),
              ("simulate", "simulate 0.2 s (warm)", "tab:blue", "*")]
    for key, label, color, marker in series:
        ys = np.array([p.get(key, math.nan) for p in done], dtype=float)
        if np.count_nonzero(np.isfinite(ys)) == 0:
            continue
        if key in fits and math.isfinite(fits[key][1]):
            label += f" (b={fits[key][1]:.2f})"
        lw = 2.2 if key in ("translation", "translated_initialized", "simulate") else 1.2
        ax.plot(ns, ys, "-", marker=marker, color=color, label=label, lw=lw)
    for key in ("translation", "structure"):
        a, b = fits.get(key, (math.nan, math.nan))
        if math.isfinite(b):
            grid = np.geomspace(ns.min(), ns.max(), 50)
            ax.plot(grid, a * grid ** b, ":", color="black" if key == "translation" else "tab:red", lw=1)
    skipped = [p for p in points if p.get("status") != "ok"]
    if skipped:
        ax.text(0.02, 0.98, "\n".join(f"N={p['n']}: {p['status']}" for p in skipped), transform=ax.transAxes,
                va="top", fontsize=8, color="red")
    ax.set_xscale("log")
    ax.set_yscale("log")
    _size_axis(ax, [p["n"] for p in points], suite().SCALING_SIZE_LABEL)
    ax.set_ylabel("seconds")
    ax.set_title("Scaling of translation and simulation with model size (dotted: power-law fits)")
    ax.grid(True, which="major", alpha=0.4)
    ax.grid(True, which="minor", alpha=0.12)
    ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5), frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _write_dict_csv(path: Path, rows: Sequence[dict]) -> None:
    keys: list[str] = []
    for row in rows:
        for k in row:
            if k not in keys:
                keys.append(k)
    with path.open("w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=keys)
        writer.writeheader()
        for row in rows:
            writer.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in row.items()})


# ---------------------------------------------------------------------------
# Soak
# ---------------------------------------------------------------------------

#: Runs per mode of the soak section (``--quick`` and full); 21: runs 2-11 and 12-21 are the windows.
QUICK_SOAK_RUNS = 21
FULL_SOAK_RUNS = 200
#: ``gc.collect()`` before the RSS reading of every this many runs (and of the last).
SOAK_GC_EVERY = 10
#: Runs in the first and last windows compared, and the run from which the RSS growth is fitted.
SOAK_WINDOW = 10
#: A mode is flat when last-window median / first-window median <= this ...
SOAK_TIME_RATIO = 1.5
#: ... and the RSS grows less than this many MB per 100 runs after run ``SOAK_WINDOW``.
SOAK_RSS_MB_PER_100 = 20.0
#: ``cached``: ``simulate(model)``; ``uncached``: ``simulate(model, cache=False)``.
SOAK_MODES = ("cached", "uncached")


def _current_rss_mb() -> float:
    """The process's resident set size now in MB (``/proc/self/statm``; without it the peak)."""
    try:
        with open("/proc/self/statm") as handle:
            pages = int(handle.read().split()[1])
        return pages * os.sysconf("SC_PAGE_SIZE") / 2 ** 20
    except (OSError, ValueError, IndexError, AttributeError):  # pragma: no cover - not on Linux
        return _rss_mb()


@dataclass
class SoakRun:
    """One run of the soak: a fresh model instance simulated in one mode."""

    mode: str
    run: int
    wall_seconds: float = math.nan  #: building the model instance + the simulate call
    build_seconds: float = math.nan  #: building the model instance
    cpu_seconds: float = math.nan  #: this process's CPU time over the run (less sensitive to other load)
    translate_seconds: float = math.nan  #: the simulate call's translation (``stats``)
    simulate_seconds: float = math.nan  #: the simulate call's integration (``stats``)
    rss_mb: float = math.nan  #: resident set size after the run
    collected: bool = False  #: ``gc.collect()`` ran before the RSS reading
    status: int = -1
    events: int = 0
    compiled_modes: int = 0
    #: max |y - y_run1| over every column on the output grid (inf: the grids differ)
    max_difference: float = math.nan
    message: str = ""


@dataclass
class SoakSummary:
    """One mode of the soak, summed up."""

    mode: str
    runs: int
    failed: int
    median_seconds: float
    window: int  #: runs in the first and last windows
    first_median_seconds: float  #: runs 2 .. window+1
    last_median_seconds: float  #: the last ``window`` runs
    time_ratio: float  #: last / first
    cpu_ratio: float  #: the same for the CPU time
    median_translate_seconds: float
    rss_from_run: int  #: the first RSS reading (after gc.collect()) of the growth fit
    rss_start_mb: float  #: at ``rss_from_run``
    rss_end_mb: float
    rss_growth_mb_per_100: float  #: least-squares slope of the collected readings from ``rss_from_run``
    max_difference: float
    flat: bool
    reasons: str = ""  #: why the mode is not flat


@dataclass
class SoakResult:
    case: str
    n_runs: int
    runs: list[SoakRun]
    summaries: list[SoakSummary]
    gc_every: int
    gc_threshold: tuple
    wall_seconds: float

    @property
    def flat(self) -> bool:
        return bool(self.summaries) and all(s.flat for s in self.summaries)


def _result_difference(reference: tuple, result) -> float:
    """max |y - y_ref| over the columns of ``reference = (time, columns)`` (inf if the grids differ)."""
    time_ref, columns_ref = reference
    if len(result.time) != len(time_ref) or set(result.columns) != set(columns_ref):
        return math.inf
    worst = float(np.max(np.abs(np.asarray(result.time, float) - time_ref))) if len(time_ref) else 0.0
    for name, ref in columns_ref.items():
        y = np.asarray(result.columns[name], dtype=float)
        if y.shape != ref.shape:
            return math.inf
        diff = np.abs(y - ref)
        both_nan = np.isnan(y) & np.isnan(ref)
        if np.any(np.isnan(diff) & ~both_nan):
            return math.inf
        if diff.size and not np.all(both_nan):
            worst = max(worst, float(np.nanmax(diff)))
    return worst


def _soak_mode(mode: str, make: Callable[[], Model], n_runs: int, gc_every: int,
               log: Callable[[str], None]) -> list[SoakRun]:
    from ..runtime.simulate import simulate

    rows: list[SoakRun] = []
    reference = None
    gc.collect()
    for i in range(1, n_runs + 1):
        row = SoakRun(mode, i)
        try:
            c0, t0 = time.process_time(), time.perf_counter()
            model = make()
            t1 = time.perf_counter()
            result = simulate(model, cache=(mode == "cached"))
            t2, c2 = time.perf_counter(), time.process_time()
            row.wall_seconds, row.build_seconds, row.cpu_seconds = t2 - t0, t1 - t0, c2 - c0
            row.translate_seconds = float(result.stats.get("translate_seconds", math.nan))
            row.simulate_seconds = float(result.stats.get("simulate_seconds", math.nan))
            row.status, row.message = result.status, result.message
            row.events, row.compiled_modes = len(result.events), int(result.compiled_modes)
            if result.status == 0:
                if reference is None:  # copies of the arrays only: nothing of the translation is kept
                    reference = (np.array(result.time, dtype=float),
                                 {k: np.array(v, dtype=float) for k, v in result.columns.items()})
                row.max_difference = _result_difference(reference, result)
            del model, result
        except Exception as exc:  # noqa: BLE001 - a bench never crashes on a model
            row.status, row.message = -1, f"{type(exc).__name__}: {exc}"
        row.collected = i % gc_every == 0 or i == n_runs or row.status != 0
        if row.collected:
            gc.collect()
        row.rss_mb = _current_rss_mb()
        rows.append(row)
        if row.collected:
            log(f"  soak {mode:8s} run {i:4d}: {row.wall_seconds:.3f} s, RSS {row.rss_mb:.1f} MB"
                + ("" if row.status == 0 else f" FAILED: {row.message[:80]}"))
        if row.status != 0:  # a failing model measures nothing: the mode stops
            break
    return rows


def _soak_summary(mode: str, rows: Sequence[SoakRun], gc_every: int) -> SoakSummary:
    n = len(rows)
    times = np.array([r.wall_seconds for r in rows], dtype=float)
    failed = sum(r.status != 0 for r in rows)
    window = max(1, min(SOAK_WINDOW, (n - 1) // 2))
    first = float(np.median(times[1:1 + window])) if n > 1 else math.nan
    last = float(np.median(times[-window:])) if n > 1 else math.nan
    ratio = last / first if first > 0 else math.nan
    cpu = np.array([r.cpu_seconds for r in rows], dtype=float)
    cpu_first = float(np.median(cpu[1:1 + window])) if n > 1 else math.nan
    cpu_ratio = float(np.median(cpu[-window:])) / cpu_first if cpu_first > 0 else math.nan
    readings = [r for r in rows if r.collected and math.isfinite(r.rss_mb)]
    start_run = min(SOAK_WINDOW, max(1, n // 2))
    fitted = [r for r in readings if r.run >= start_run]
    if len(fitted) >= 2:
        slope = float(np.polyfit([r.run for r in fitted], [r.rss_mb for r in fitted], 1)[0])
        growth = 100.0 * slope
    else:
        growth = math.nan
    differences = [r.max_difference for r in rows if r.status == 0]
    reasons = []
    if failed:
        reasons.append(f"{failed} run failed")
    if not ratio <= SOAK_TIME_RATIO:
        reasons.append(f"time grew {ratio:.2f}x (limit {SOAK_TIME_RATIO:g}x)")
    if not growth < SOAK_RSS_MB_PER_100:
        reasons.append(f"RSS grew {growth:.1f} MB per 100 runs (limit {SOAK_RSS_MB_PER_100:g})")
    return SoakSummary(
        mode, n, failed, float(np.median(times)) if n else math.nan, window, first, last, ratio, cpu_ratio,
        float(np.nanmedian([r.translate_seconds for r in rows])) if n else math.nan,
        fitted[0].run if fitted else 0, fitted[0].rss_mb if fitted else math.nan,
        readings[-1].rss_mb if readings else math.nan, growth,
        max(differences) if differences else math.nan, not reasons, "; ".join(reasons))


def run_soak(n_runs: int = FULL_SOAK_RUNS, make: Callable[[], Model] | None = None, name: str | None = None,
             modes: Sequence[str] = SOAK_MODES, gc_every: int = SOAK_GC_EVERY,
             log: Callable[[str], None] | None = None) -> SoakResult:
    """Simulate one model ``n_runs`` times in this process in each of ``modes``, recording time and RSS.

    ``make`` (default: the suite's ``soak_case()``) builds a fresh model
    instance for every run.  *cached*: ``simulate(model)``, the in-process
    translation cache reusing the compiled systems of the first run;
    *uncached*: ``simulate(model, cache=False)``, a fresh translation and
    compilation every run.  Each run records its wall time (building the
    instance and the simulate call) and the resident set size after it;
    every ``gc_every``-th run (and the last) the RSS is read after
    ``gc.collect()``.  A failing run ends its mode.
    """
    log = log or (lambda _s: None)
    if make is None:
        default_name, make = suite().soak_case()
        name = name or default_name
    name = name or getattr(make, "__name__", "model")
    for mode in modes:
        if mode not in SOAK_MODES:
            raise ValueError(f"unknown soak mode {mode!r}; choose from {', '.join(SOAK_MODES)}")
    if n_runs < 2:
        raise ValueError("a soak needs at least 2 runs per mode")
    wall0 = time.perf_counter()
    rows: list[SoakRun] = []
    summaries = []
    for mode in modes:
        mine = _soak_mode(mode, make, n_runs, max(1, int(gc_every)), log)
        rows += mine
        summaries.append(_soak_summary(mode, mine, gc_every))
        s = summaries[-1]
        log(f"  soak {mode}: median {s.median_seconds:.3f} s/run, last/first {s.time_ratio:.2f} "
            f"(CPU {s.cpu_ratio:.2f}), "
            f"RSS {s.rss_start_mb:.0f} -> {s.rss_end_mb:.0f} MB ({s.rss_growth_mb_per_100:+.1f} MB/100 runs), "
            + ("flat" if s.flat else "NOT flat: " + s.reasons))
    return SoakResult(name, n_runs, rows, summaries, gc_every, tuple(gc.get_threshold()),
                      time.perf_counter() - wall0)


def _soak_summary_table(soak: SoakResult) -> str:
    rows = []
    for s in soak.summaries:
        rows.append((s.mode, s.runs, s.failed, s.median_seconds, s.median_translate_seconds,
                     s.first_median_seconds, s.last_median_seconds, f"{s.time_ratio:.2f}", f"{s.cpu_ratio:.2f}",
                     s.rss_start_mb, s.rss_end_mb, f"{s.rss_growth_mb_per_100:+.2f}", s.max_difference,
                     "yes" if s.flat else f"**no**: {s.reasons}"))
    w = soak.summaries[0].window if soak.summaries else SOAK_WINDOW
    start = soak.summaries[0].rss_from_run if soak.summaries else SOAK_WINDOW
    return _md_table(("mode", "runs", "failed", "median [s/run]", "median translate [s/run]",
                      f"runs 2–{w + 1} median [s/run]", f"last {w} median [s/run]", "last / first",
                      "last / first (CPU)", f"RSS at run {start} [MB]", "RSS at end [MB]", "RSS growth [MB / 100 runs]",
                      "max Δ vs run 1", "flat"), rows)


def _soak_markdown(soak: SoakResult) -> str:
    if soak.flat:
        verdict = (f"**Verdict: flat.** Both modes stay within the limits over {soak.n_runs} runs: "
                   + "; ".join(f"{s.mode} last/first {s.time_ratio:.2f}, RSS {s.rss_growth_mb_per_100:+.1f} "
                               f"MB per 100 runs" for s in soak.summaries) + ".")
    else:
        verdict = "**Verdict: not flat.** " + "; ".join(f"{s.mode}: {s.reasons}" for s in soak.summaries
                                                        if not s.flat) + "."
    w = soak.summaries[0].window if soak.summaries else SOAK_WINDOW
    start = soak.summaries[0].rss_from_run if soak.summaries else SOAK_WINDOW
    checkpoints = [r for r in soak.runs if r.run == 1 or r.collected]
    rows = [(r.mode, r.run, r.wall_seconds, r.translate_seconds, r.simulate_seconds, r.rss_mb,
             r.compiled_modes, r.events, r.max_difference,
             "ok" if r.status == 0 else "FAILED: " + r.message.replace("|", "/")[:80]) for r in checkpoints]
    return "\n".join([
        "# Soak", "",
        f"{soak.case} simulated {soak.n_runs} times in one process in each mode, one mode after the other "
        "(" + ", ".join(s.mode for s in soak.summaries) + "), a fresh model instance every run:", "",
        "- *cached*: `simulate(model)`. The in-process translation cache recognises the flat model (every "
        "run flattens) and reuses the translation and the systems compiled so far; run 1 translates and "
        "compiles (unless the process translated the same model before).",
        "- *uncached*: `simulate(model, cache=False)`: every run flattens, partitions and compiles each "
        "discrete state it visits afresh.", "",
        "Time of a run: building the model instance and the `simulate` call (wall clock); *CPU*: this "
        "process's CPU time over the same span (other load on the machine inflates it less than the wall "
        "time; the verdict uses the wall time); *translate*: the call's translation time from its `stats`. "
        "RSS: the process's resident set size "
        f"(`/proc/self/statm`) after the run; runs {soak.gc_every}, {2 * soak.gc_every}, … and the last "
        "are read after `gc.collect()`, and only those readings enter the RSS columns. Both modes share "
        "the process, so the second starts from the RSS the first left. Collector thresholds "
        f"{soak.gc_threshold}. *max Δ vs run 1*: the largest absolute difference of any column on the "
        "output grid from the mode's first run (0: every run gave the same result).", "",
        f"A mode is *flat* when the median time of the last {w} runs is within {SOAK_TIME_RATIO:g}× of the "
        f"median of runs 2–{w + 1} (run 1 compiles) and the RSS grows less than "
        f"{SOAK_RSS_MB_PER_100:g} MB per 100 runs after run {start} (least-squares slope through the "
        "readings after `gc.collect()`). The machine may be shared: read the times as ratios within "
        f"this run. Soak wall time {soak.wall_seconds:.1f} s.", "",
        verdict, "",
        _soak_summary_table(soak), "",
        "## Runs (run 1 and every run read after `gc.collect()`; every run in soak.csv)", "",
        _md_table(("mode", "run", "time [s]", "translate [s]", "simulate [s]", "RSS [MB]", "compiled modes",
                   "events", "max Δ vs run 1", "status"), rows), ""])


def _plot_soak(soak: SoakResult, path: Path) -> Path | None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if not soak.runs:
        return None
    colors = {"cached": "tab:blue", "uncached": "tab:orange"}
    fig, (ax_t, ax_m) = plt.subplots(2, 1, figsize=(9.5, 7.0), sharex=True)
    for s in soak.summaries:
        mine = [r for r in soak.runs if r.mode == s.mode]
        color = colors.get(s.mode, "black")
        runs = [r.run for r in mine]
        ax_t.plot(runs, [r.wall_seconds for r in mine], ".-", ms=3, lw=0.8, color=color,
                  label=f"{s.mode} (last/first {s.time_ratio:.2f})")
        if math.isfinite(s.first_median_seconds):
            for level, lo, hi in ((s.first_median_seconds, 2, 1 + s.window),
                                  (s.last_median_seconds, mine[-1].run - s.window + 1, mine[-1].run)):
                ax_t.hlines(level, lo, hi, colors="black", linestyles="--", lw=2.0, zorder=5)
        ax_m.plot(runs, [r.rss_mb for r in mine], "-", lw=0.8, color=color, alpha=0.5)
        collected = [r for r in mine if r.collected]
        ax_m.plot([r.run for r in collected], [r.rss_mb for r in collected], "o", ms=4, color=color,
                  label=f"{s.mode} after gc.collect() ({s.rss_growth_mb_per_100:+.1f} MB / 100 runs)")
    ax_t.set_yscale("log")
    ax_t.set_ylabel("time per run [s]")
    ax_t.set_title(f"Soak: {soak.case} simulated {soak.n_runs}× per mode in one process "
                   f"({'flat' if soak.flat else 'NOT flat'}; black dashes: medians of the first and last windows)",
                   fontsize=10)
    ax_m.set_ylabel("resident set size [MB]")
    ax_m.set_xlabel("run")
    for ax in (ax_t, ax_m):
        ax.grid(True, alpha=0.35)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def write_soak(soak: SoakResult, out_dir: Path) -> dict:
    """Write ``soak.md``, ``soak.csv`` (one row per run) and ``soak.png`` into ``out_dir``; their paths."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    files = {"soak.md": out_dir / "soak.md", "soak.csv": out_dir / "soak.csv"}
    files["soak.md"].write_text(_soak_markdown(soak))
    _write_dict_csv(files["soak.csv"], [{"case": soak.case, **vars(r)} for r in soak.runs])
    path = _plot_soak(soak, out_dir / "soak.png")
    if path is not None:
        files["soak.png"] = path
    return files


# ---------------------------------------------------------------------------
# Storm: many independent hybrid parts
# ---------------------------------------------------------------------------

#: Sizes of the storm section (``--quick`` and full), and the largest N also run as a whole model.
QUICK_STORM = (3, 6)
FULL_STORM = (5, 10, 20, 50, 100, 200)
QUICK_STORM_WHOLE_UP_TO = 6
FULL_STORM_WHOLE_UP_TO = 20
#: Wall-time limit of one storm point (a fresh process), full and ``--quick``.
STORM_TIMEOUT_SECONDS = 240.0
QUICK_STORM_TIMEOUT_SECONDS = 60.0
#: The two ways a storm point is compiled.
STORM_MODES = ("clusters", "whole model")


def full_storm_sizes() -> tuple[int, ...]:
    """The full bench's storm sizes: :data:`FULL_STORM` and the sizes of the suite's storm targets
    (``STORM_PER_EVENT_TARGET``, ``STORM_WALL_TARGETS``), in order; a size after one that did not
    finish is skipped, so a target size out of reach costs nothing."""
    benchmarks = suite()
    small, large, _ = benchmarks.STORM_PER_EVENT_TARGET
    return tuple(sorted(set(FULL_STORM) | {small, large} | {n for n, _ in benchmarks.STORM_WALL_TARGETS}))


def storm_point(n: int, clusters: bool = True, progress: Callable[[dict], None] | None = None) -> dict:
    """Translate and simulate the suite's ``storm_model(n)`` once, with or without clusters.

    ``translate(model, cache=False)`` then ``simulate(translation, stop_time,
    interval)`` -- what ``simulate(model)`` does in a fresh process -- with
    ``EngineOptions(clusters=clusters)``.  ``wall`` is the time of both
    calls; ``translation`` the translation's ``translation_seconds`` at the
    end (flattening, every system compiled, the initialization systems);
    ``simulate`` the rest (integration, events, result); ``final_watched``
    the final value of the suite's ``STORM_WATCHED`` (NaN if the result has
    no such variable).
    """
    from ..compiler.translate import translate
    from ..options import EngineOptions
    from ..runtime.simulate import simulate

    benchmarks = suite()
    progress = progress or (lambda _p: None)
    point: dict = {"n": n, "mode": STORM_MODES[0] if clusters else STORM_MODES[1]}
    model = benchmarks.storm_model(n)
    watched = benchmarks.STORM_WATCHED
    progress(dict(point, phase="translating and simulating"))
    gc.collect()
    t0 = time.perf_counter()
    translation = translate(model, cache=False, options=EngineOptions(clusters=bool(clusters)))
    result = simulate(translation, stop_time=benchmarks.STORM_STOP_TIME, interval=benchmarks.STORM_INTERVAL)
    wall = time.perf_counter() - t0
    clustering = translation.clustering
    point.update({
        "status": int(result.status),
        "message": "" if result.status == 0 else result.message,
        "parts": len(clustering.clusters) if clustering is not None else 1,
        "states_visited": len(result.modes),
        "events": len(result.events),
        "compiled_systems": int(result.compiled_modes),
        "steps": int(result.stats.get("steps", 0)),
        "translation": translation.translation_seconds,
        "simulate": wall - translation.translation_seconds,
        "wall": wall,
        "final_watched": result.final(watched) if watched in result else math.nan,
        "integrated": _storm_integration(result),
        "max_rss_mb": _rss_mb(),
    })
    return point


def _storm_integration(result) -> str:
    """How a storm run was integrated: each part with its own solver, or one solver for all
    (with the reason the result's notes give)."""
    if result.stats.get("parts"):
        return f"parts apart ({result.stats['parts']} solvers)"
    why = next((note.split("one solver: ", 1)[1] for note in result.notes if "integrated with one solver: " in note),
               "")
    return f"one solver: {why}" if why else "one solver"


def _storm_point_subprocess(n: int, clusters: bool, timeout: float) -> dict:
    # cold: nothing compiled by an earlier process (translate(cache=False) too)
    report, failure, wall, timed_out = _point_in_subprocess(
        f"storm_point({n}, {bool(clusters)}, progress=report)", timeout, {"ACAUSAL_DISK_CACHE": "off"})
    mode = STORM_MODES[0] if clusters else STORM_MODES[1]
    if timed_out:
        return {"n": n, "mode": mode, "status": f"not finished in {timeout:.0f} s", "process_wall": wall}
    if report is not None and failure is None and "status" in report:
        report["process_wall"] = wall
        return report
    return {"n": n, "mode": mode, "status": failure or "failed: no report", "process_wall": wall}


def run_storm(sizes: Sequence[int] = FULL_STORM, whole_up_to: int = FULL_STORM_WHOLE_UP_TO,
              timeout: float = STORM_TIMEOUT_SECONDS, isolate: bool = True,
              log: Callable[[str], None] | None = None) -> list[dict]:
    """The storm points: the suite's ``storm_model(N)`` for every N in ``sizes``.

    Each N with clusters (the default engine) and, for ``N <= whole_up_to``,
    once more with ``EngineOptions(clusters=False)`` (the whole model compiled per
    discrete state).  With ``isolate`` (default) each point runs in a fresh
    process stopped after ``timeout`` seconds (status ``"not finished in T
    s"``); once a mode has a point that did not finish, its larger sizes are
    skipped.  Without ``isolate`` the points run in this process (no
    timeout).  Rows: :func:`storm_point`'s keys, ``status`` 0 for a run
    that reached the stop time.
    """
    log = log or (lambda _s: None)
    points: list[dict] = []
    stopped: dict[str, str] = {}
    for n in sizes:
        for clusters in (True, False):
            mode = STORM_MODES[0] if clusters else STORM_MODES[1]
            if not clusters and n > whole_up_to:
                continue
            if mode in stopped:
                points.append({"n": n, "mode": mode, "status": f"skipped ({stopped[mode]})"})
                continue
            if isolate:
                point = _storm_point_subprocess(n, clusters, timeout)
            else:
                try:
                    point = storm_point(n, clusters)
                except Exception as exc:  # noqa: BLE001 - a bench never crashes on a model
                    point = {"n": n, "mode": mode, "status": f"failed: {type(exc).__name__}: {exc}"}
            points.append(point)
            if point["status"] != 0:
                stopped[mode] = f"N={n} {point['status'] if isinstance(point['status'], str) else 'failed'}"
            log(f"  storm N={n} {mode}: wall {point.get('wall', math.nan):.2f} s, translation "
                f"{point.get('translation', math.nan):.2f} s, {point.get('events', '-')} events, "
                f"{point.get('compiled_systems', '-')} systems compiled (status {point['status']})")
    return points


def _storm_finished(points: Sequence[dict], mode: str) -> list[dict]:
    return [p for p in points if p.get("mode") == mode and p.get("status") == 0]


def storm_fits(points: Sequence[dict]) -> dict:
    """``mode -> (a, b)`` of ``wall ≈ a N^b`` over the finished points of each mode."""
    fits = {}
    for mode in STORM_MODES:
        done = _storm_finished(points, mode)
        fits[mode] = fit_power_law([p["n"] for p in done], [p["wall"] for p in done])
    return fits


def _local_exponents(done: Sequence[dict], key: str = "wall") -> list[tuple[int, int, float]]:
    """``(N1, N2, b)`` of the power law through each two consecutive finished points."""
    return [(p["n"], q["n"], fit_power_law([p["n"], q["n"]], [p[key], q[key]])[1]) for p, q in zip(done, done[1:])]


def _storm_per_event_ms(point: dict) -> float:
    """A storm point's integration+events milliseconds per event (NaN without events)."""
    events, simulate = point.get("events"), point.get("simulate")
    return 1e3 * simulate / events if _finite(events) and events > 0 and _finite(simulate) else math.nan


def _storm_wall_per_event_ms(point: dict) -> float:
    """A storm point's wall milliseconds per event, translation included (NaN without events)."""
    events, wall = point.get("events"), point.get("wall")
    return 1e3 * wall / events if _finite(events) and events > 0 and _finite(wall) else math.nan


def _storm_per_event_check(points: Sequence[dict]) -> TargetCheck:
    """The suite's ``STORM_PER_EVENT_TARGET`` against the points with clusters."""
    small, large, limit = suite().STORM_PER_EVENT_TARGET
    target = f"integration+events per event at N = {large} ≤ {limit:g}× that at N = {small}"
    done = {p["n"]: p for p in _storm_finished(points, STORM_MODES[0])}
    missing = [n for n in (small, large) if n not in done]
    if missing:
        statuses = {p["n"]: p["status"] for p in points if p.get("mode") == STORM_MODES[0]}
        return TargetCheck(target, "-", None, "; ".join(
            f"N = {n} {statuses[n]}" if n in statuses else f"N = {n} not run" for n in missing) + ".")
    first, last = done[small], done[large]
    ratio = _storm_per_event_ms(last) / _storm_per_event_ms(first)
    wall_ratio = _storm_wall_per_event_ms(last) / _storm_wall_per_event_ms(first)
    measured = (f"{_storm_per_event_ms(last):.3g} ms against {_storm_per_event_ms(first):.3g} ms: {ratio:.2f}× "
                f"(wall per event, translation included: {_storm_wall_per_event_ms(last):.3g} against "
                f"{_storm_wall_per_event_ms(first):.3g} ms, {wall_ratio:.2f}×)")
    if ratio <= limit:
        return TargetCheck(target, measured, True)
    span = math.log(large / small)
    b_cost = math.log(ratio) / span
    b_events = math.log(last["events"] / first["events"]) / span
    why = (f"the cost of an event grows as N^{b_cost:.2f} (N^{math.log(limit) / span:.2f} at most for "
           f"{limit:g}×) and the events as N^{b_events:.2f}, so the integration+events time grows as "
           f"N^{b_cost + b_events:.2f}; it takes an event whose cost does not depend on the parts it does not "
           "involve: each independent part on its own solver, restarted only at its own events, its rows at "
           "the others' events from its dense output")
    return TargetCheck(target, measured, False, why + ".")


def _storm_wall_checks(points: Sequence[dict], timeout: float) -> list[TargetCheck]:
    """The suite's ``STORM_WALL_TARGETS`` against the points with clusters.

    A point not finished within ``timeout`` (no smaller than the target's
    limit) or failed has not met it; a size not run (or skipped) is not
    measured, the power law through the two largest finished sizes
    predicting its wall and events as the reason, with the cost per event
    that would meet the limit.
    """
    finished = _storm_finished(points, STORM_MODES[0])
    done = {p["n"]: p for p in finished}
    others = {p["n"]: p for p in points if p.get("mode") == STORM_MODES[0] and p.get("status") != 0}
    a, b = (fit_power_law([p["n"] for p in finished[-2:]], [p["wall"] for p in finished[-2:]])
            if len(finished) >= 2 else (math.nan, math.nan))
    a_events, b_events = (fit_power_law([p["n"] for p in finished[-2:]], [p["events"] for p in finished[-2:]])
                          if len(finished) >= 2 else (math.nan, math.nan))
    basis = (f"the power law through N = {finished[-2]['n']} and {finished[-1]['n']}" if len(finished) >= 2 else "")
    checks = []
    for n, limit in suite().STORM_WALL_TARGETS:
        target = f"storm N = {n} ≤ {limit:g} s (translated and simulated, fresh process)"
        predicted, events = a * n ** b, a_events * n ** b_events
        estimate = ""
        if math.isfinite(predicted) and n not in done:
            largest = finished[-1]
            estimate = (f"{basis} predicts {predicted:.3g} s (b = {b:.2f}) and {events:.3g} events (b = "
                        f"{b_events:.2f}): {limit:g} s allows {1e3 * limit / events:.2g} ms per event, translation "
                        f"included, against {_storm_wall_per_event_ms(largest):.3g} ms at N = {largest['n']}")
        if n in done:
            wall = done[n]["wall"]
            allowed, measured_ms = 1e3 * limit / done[n]["events"], _storm_wall_per_event_ms(done[n])
            why = "" if wall <= limit else (
                f"{done[n]['events']} events at {measured_ms:.3g} ms each (translation "
                f"included): {limit:g} s allows {allowed:.2g} ms per event, {measured_ms / allowed:.2g}× less. "
                "Each part runs its own event loop (its event iteration, locating the flip, restarting its "
                "solver, its steps), whose cost per event does not grow with N; cutting it that much takes "
                "the parts of one shape stepped together: one numpy step for all the parts in one mode, "
                "their flips located and their events iterated in one pass.")
            checks.append(TargetCheck(target, f"{wall:.3g} s", wall <= limit, why))
            continue
        point = others.get(n)
        status = str(point["status"]) if point is not None else ""
        not_finished = status.startswith("not finished") and timeout >= limit
        failed = point is not None and not status.startswith(("not finished", "skipped"))
        if not_finished or failed:
            measured = f"not finished in {timeout:.0f} s" if not_finished else f"failed: {status}"
            checks.append(TargetCheck(target, measured, False, (estimate + ".") if estimate else ""))
        else:
            reason = f"N = {n} {status}" if point is not None else f"N = {n} not run"
            checks.append(TargetCheck(target, "-", None, reason + (f"; {estimate}." if estimate else ".")))
    return checks


def storm_target_checks(points: Sequence[dict], timeout: float = STORM_TIMEOUT_SECONDS) -> list[TargetCheck]:
    """The suite's storm targets (``STORM_PER_EVENT_TARGET``, ``STORM_WALL_TARGETS``) against the points
    with clusters; ``timeout`` is the limit a point that did not finish ran into."""
    return [_storm_per_event_check(points)] + _storm_wall_checks(points, timeout)


def _storm_markdown(points: Sequence[dict], fits: dict, timeout: float) -> str:
    rows = []
    for p in points:
        status = p.get("status", "")
        status_text = ("ok" if status == 0 else f"status {status}: {p.get('message', '')}"
                       if isinstance(status, int) else status)
        rows.append((p["n"], p["mode"], p.get("parts", math.nan), p.get("states_visited", math.nan),
                     p.get("events", math.nan), p.get("compiled_systems", math.nan),
                     p.get("translation", math.nan), p.get("simulate", math.nan), _storm_per_event_ms(p),
                     p.get("wall", math.nan), _storm_wall_per_event_ms(p), p.get("max_rss_mb", math.nan),
                     p.get("integrated", ""), status_text))
    table = _md_table(("N", "mode", "parts", "discrete states visited", "events", "compiled systems",
                       "translation [s]", "integration+events [s]", "per event [ms]", "wall [s]",
                       "wall per event [ms]", "max RSS [MB]", "integrated", "status"), rows)
    fit_rows = []
    for mode in STORM_MODES:
        a, b = fits.get(mode, (math.nan, math.nan))
        ns = [p["n"] for p in _storm_finished(points, mode)]
        fit_rows.append((mode, _fmt(a), _fmt(b), ", ".join(map(str, ns)) or "-"))
    fit_table = _md_table(("mode", "a", "b (wall ≈ a·N^b)", "fitted on N ="), fit_rows)
    reading = []
    for mode in STORM_MODES:
        a, b = fits.get(mode, (math.nan, math.nan))
        done = _storm_finished(points, mode)
        if math.isfinite(b):
            local = ", ".join(f"{b2:.2f} ({n1}→{n2})" for n1, n2, b2 in _local_exponents(done))
            reading.append(f"- {mode}: wall ≈ {a:.3g}·N^{b:.2f} over N = {done[0]['n']} ... {done[-1]['n']}; "
                           f"between consecutive sizes b = {local}.")
    clustered = {p["n"]: p for p in _storm_finished(points, STORM_MODES[0])}
    whole = {p["n"]: p for p in _storm_finished(points, STORM_MODES[1])}
    both = sorted(set(clustered) & set(whole))
    if both:
        reading.append("- Clusters against the whole model (wall, compiled systems): " + "; ".join(
            f"N = {n}: {whole[n]['wall'] / clustered[n]['wall']:.2g}x faster, "
            f"{clustered[n]['compiled_systems']} vs {whole[n]['compiled_systems']} systems" for n in both) + ".")
        mismatched = [n for n in both if clustered[n]["events"] != whole[n]["events"]]
        reading.append("- Events: " + ("the same number in both modes at every N." if not mismatched else
                                       "**different numbers** at N = " + ", ".join(map(str, mismatched)) + "."))
    benchmarks = suite()
    done = list(clustered.values())
    if len(done) >= 2:
        _, b_events = fit_power_law([p["n"] for p in done], [p["events"] for p in done])
        reading.append(f"- The events themselves grow as N^{b_events:.2f} ({benchmarks.STORM_EVENTS_GROWTH}); "
                       "with clusters the integration+events time per event goes from "
                       f"{1e3 * done[0]['simulate'] / done[0]['events']:.3g} ms (N = {done[0]['n']}) to "
                       f"{1e3 * done[-1]['simulate'] / done[-1]['events']:.3g} ms (N = {done[-1]['n']}), and "
                       f"the peak RSS from {done[0]['max_rss_mb']:.0f} MB to {done[-1]['max_rss_mb']:.0f} MB.")
    return "\n".join([
        "# Storm: many independent parts with events", "",
        benchmarks.STORM_DESCRIPTION + ". "
        f"Simulated for {benchmarks.STORM_STOP_TIME:g} s with output interval {benchmarks.STORM_INTERVAL:g} s "
        "(RK45, rtol 1e-6), each point in a fresh process (sympy's caches cold, the persistent compile "
        f"cache off, the garbage collector as in an `acausal` command) stopped after {timeout:.0f} s. "
        "*clusters*: the default engine, one system per independent part and part mode; *whole model*: "
        "`EngineOptions(clusters=False)`, the whole model compiled per discrete state "
        "(the old behaviour). Wall: `translate(model, cache=False)` and `simulate(translation)`, what "
        "`simulate(model)` does; translation: the translation's `translation_seconds` at the end "
        "(flattening, every system compiled, the initialization systems); integration+events: the rest. "
        "Parts: the independent parts the translation found (1: none used). Integrated: each part with a "
        "solver of its own (`acausal.runtime.part_runs`), or one solver for all and why. Discrete states "
        "visited: `len(result.modes)` (parts apart: the parts' own states). Compiled systems: "
        "`result.compiled_modes` (with clusters, every part's systems count). Per event: integration+events "
        "over the events (the cost of an event); wall per event: the wall over the events, translation "
        "included. Max RSS: the process's peak.",
        "", _targets_markdown(storm_target_checks(points, timeout)), "## Sizes", "", table, "", fit_table, "",
        "## Reading", ""] + reading + [""])


def _plot_storm(points: Sequence[dict], fits: dict, path: Path, timeout: float) -> Path | None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if not any(p.get("mode") in STORM_MODES for p in points):
        return None
    fig, ax = plt.subplots(figsize=(8.5, 5.5))
    styles = {STORM_MODES[0]: ("tab:blue", "o"), STORM_MODES[1]: ("tab:red", "s")}
    for mode in STORM_MODES:
        color, marker = styles[mode]
        done = _storm_finished(points, mode)
        if done:
            ns = np.array([p["n"] for p in done], dtype=float)
            label = f"{mode}: wall"
            a, b = fits.get(mode, (math.nan, math.nan))
            if math.isfinite(b):
                label += f" (b={b:.2f})"
                grid = np.geomspace(ns.min(), ns.max(), 50)
                ax.plot(grid, a * grid ** b, ":", color=color, lw=1)
            ax.plot(ns, [p["wall"] for p in done], "-", marker=marker, color=color, lw=2, label=label)
            ax.plot(ns, [p["translation"] for p in done], "--", marker=marker, color=color, lw=1, alpha=0.6,
                    mfc="none", label=f"{mode}: translation")
        stopped = [p for p in points if p.get("mode") == mode and isinstance(p.get("status"), str)
                   and p["status"].startswith("not finished")]
        if stopped:
            ax.plot([p["n"] for p in stopped], [timeout] * len(stopped), "^", color=color, ms=10,
                    label=f"{mode}: not finished in {timeout:.0f} s")
    wall_targets = suite().STORM_WALL_TARGETS
    for n, limit in wall_targets:
        ax.plot([n], [limit], "*", color="tab:green", ms=12)
        ax.annotate(f"target N={n}: {limit:g} s", (n, limit), textcoords="offset points", xytext=(-10, 8),
                    ha="right", fontsize=8, color="tab:green")
    ax.set_xscale("log")
    ax.set_yscale("log")
    _size_axis(ax, sorted({p["n"] for p in points} | {n for n, _ in wall_targets}), suite().STORM_SIZE_LABEL)
    ax.set_ylabel("seconds (fresh process)")
    ax.set_title("Storm: translation + simulation with and without clusters (dotted: power-law fits)")
    ax.grid(True, which="major", alpha=0.4)
    ax.grid(True, which="minor", alpha=0.12)
    if ax.get_legend_handles_labels()[0]:
        ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def write_storm(points: Sequence[dict], out_dir: Path, timeout: float = STORM_TIMEOUT_SECONDS) -> dict:
    """Write ``storm.md``, ``storm.csv`` and ``storm.png`` into ``out_dir``; their paths."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    fits = storm_fits(points)
    files = {"storm.md": out_dir / "storm.md", "storm.csv": out_dir / "storm.csv"}
    files["storm.md"].write_text(_storm_markdown(points, fits, timeout))
    _write_dict_csv(files["storm.csv"], points)
    path = _plot_storm(points, fits, out_dir / "storm.png", timeout)
    if path is not None:
        files["storm.png"] = path
    return files


# ---------------------------------------------------------------------------
# Floors: what the same work costs without the engine
# ---------------------------------------------------------------------------

#: ``(label, code)``: the fresh-process floors the commands are divided by.
IMPORT_FLOORS = (("import numpy", "import numpy"),
                 ("import numpy, scipy.integrate", "import numpy, scipy.integrate"))
#: A command record's keys of the import floors (in :data:`IMPORT_FLOORS`' order) timed in its own rounds,
#: and of its ratios to them.
FLOOR_WALL_KEYS = ("import_numpy_wall", "numpy_scipy_wall")
FLOOR_RATIO_KEYS = ("x_import_numpy", "x_numpy_scipy")
#: Warm runs of the hand-coded floor's case (acausal and the floor); the best counts.
HAND_CODED_FLOOR_REPEATS = 5


@dataclass(frozen=True)
class FloorCase:
    """The floors section's hand-coded floor: one of the suite's cases written without the engine.

    ``case`` names a work-precision case of the suite (its model and stop
    time; the output interval is its model's experiment's).  ``floor(stop_time,
    interval, rtol=..., atol=...)`` simulates the same model written by hand
    and returns a dict with ``final`` (the last value of ``output``),
    ``events`` (its switches, each a tuple whose first item is the time),
    ``steps`` and ``rhs_evaluations``.  acausal's and the floor's final values
    of ``output`` (in ``unit``) agree when they differ by at most
    ``agreement``.  ``description`` (Markdown) says what the model is and how
    the floor is written; ``events_note`` how acausal's events and the
    floor's switches correspond.  Both run with ``method``, the same rtol and
    atol.  ``target_ratio``: the warm run's target, at most this multiple of
    the floor's time (None: no target).
    """

    case: str
    floor: Callable[..., dict]
    output: str
    unit: str
    agreement: float
    description: str
    events_note: str = ""
    method: str = "RK45"
    target_ratio: float | None = None


def run_import_floors(repeats: int = 5, log: Callable[[str], None] | None = None) -> list[dict]:
    """Wall time of ``python -c "import numpy"`` and ``python -c "import numpy, scipy.integrate"``.

    In new processes, like the commands (same interpreter, folder and
    environment): what any command built on numpy and scipy pays before
    doing anything.
    """
    log = log or (lambda _s: None)
    env = _repository_env()
    records = []
    for label, code in IMPORT_FLOORS:
        walls, statuses = [], []
        for _ in range(repeats):
            wall, status, _ = _timed_process([sys.executable, "-c", code], env)
            walls.append(wall)
            statuses.append(status)
        record = _import_floor_record(label, code, walls, statuses)
        records.append(record)
        log(f"  {record['what']}: min {record['min_wall']:.3f} s, median {record['median_wall']:.3f} s")
    return records


def command_floor_ratios(command_records: Sequence[dict], import_records: Sequence[dict]) -> list[dict]:
    """The commands' rows with their median wall time as a multiple of each import floor's median.

    Keys ``x_import_numpy`` and ``x_numpy_scipy`` (the columns "× import
    numpy", "× numpy+scipy.integrate").  A record with the floors of its own
    rounds (:data:`FLOOR_WALL_KEYS`, from :func:`run_commands_with_floors`)
    is divided by those; otherwise by ``import_records``' medians.
    """
    floors = {r["label"]: r["median_wall"] for r in import_records}
    rows = []
    for record in command_records:
        row = {"kind": "command", "what": record["command"], **{k: v for k, v in record.items() if k != "command"}}
        for (label, _), wall_key, key in zip(IMPORT_FLOORS, FLOOR_WALL_KEYS, FLOOR_RATIO_KEYS):
            floor = record.get(wall_key)
            floor = floor if _finite(floor) else floors.get(label, math.nan)
            row[key] = record["median_wall"] / floor if floor and math.isfinite(floor) else math.nan
        rows.append(row)
    return rows


def run_hand_coded_floor(repeats: int = HAND_CODED_FLOOR_REPEATS, rtol: float = 1e-6,
                         log: Callable[[str], None] | None = None, floor_case: FloorCase | None = None) -> dict:
    """A warm case in acausal against the same model written by hand (default: the suite's ``floor_case()``).

    The case's stop time and its model's output interval, the floor's method
    at ``rtol``: acausal translated once and simulated once to warm up, then
    the best of ``repeats`` runs with the translation reused; the floor
    likewise (one warm-up, best of ``repeats``).  ``agree``: the final values
    of the floor case's ``output`` differ by at most its ``agreement``.
    """
    log = log or (lambda _s: None)
    fc = floor_case if floor_case is not None else suite().floor_case()
    case = get_case(fc.case)
    translation = _fresh_translate(case.make())
    options = {"method": fc.method, "rtol": rtol}
    if case.stop_time is not None:
        options["stop_time"] = case.stop_time
    result, _ = _timed_simulate(translation, **options)  # warm-up (compiles the modes visited)
    acausal_times = [_timed_simulate(translation, **options)[1] for _ in range(repeats)]
    stop = case.stop_time if case.stop_time is not None else translation.flat.experiment.stop_time
    interval = translation.flat.experiment.interval or stop / 500
    floor = fc.floor(stop, interval, rtol=rtol, atol=rtol)
    floor_times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fc.floor(stop, interval, rtol=rtol, atol=rtol)
        floor_times.append(time.perf_counter() - t0)
    final_acausal, final_floor = result.final(fc.output), float(floor["final"])
    difference = abs(final_acausal - final_floor)
    row = {"kind": "in-process", "what": f"{fc.case} {fc.method} rtol {rtol:g}, warm, to t = {stop:.6g} s",
           "case": fc.case, "method": fc.method, "output": fc.output, "unit": fc.unit,
           "repeats": repeats, "acausal_seconds": min(acausal_times), "floor_seconds": min(floor_times),
           "ratio": min(acausal_times) / min(floor_times), "acausal_final": final_acausal,
           "floor_final": final_floor, "final_difference": difference, "agreement": fc.agreement,
           "agree": difference <= fc.agreement,
           "acausal_status": result.status, "acausal_events": len(result.events),
           "floor_switches": len(floor["events"]),
           "floor_switch_times": " ".join(f"{event[0]:.9g}" for event in floor["events"]),
           "acausal_steps": int(result.stats.get("steps", 0)), "floor_steps": floor["steps"],
           "acausal_rhs_evaluations": int(result.stats.get("rhs_evaluations", 0)),
           "floor_rhs_evaluations": floor["rhs_evaluations"],
           "target_ratio": fc.target_ratio if fc.target_ratio is not None else math.nan}
    row["target_met"] = bool(row["agree"] and row["ratio"] <= fc.target_ratio) if fc.target_ratio is not None else None
    log(f"  {fc.case} warm: acausal {row['acausal_seconds'] * 1e3:.2f} ms, hand-coded floor "
        f"{row['floor_seconds'] * 1e3:.2f} ms (x{row['ratio']:.1f}); final {fc.output} {final_acausal:.9g} "
        f"vs {final_floor:.9g}")
    return row


def run_floors(repeats: int = 5, command_records: Sequence[dict] | None = None, commands: bool = True,
               log: Callable[[str], None] | None = None,
               floor_repeats: int = HAND_CODED_FLOOR_REPEATS,
               import_records: Sequence[dict] | None = None) -> list[dict]:
    """The floors section: import floors, the commands against them, and the hand-coded floor.

    ``command_records`` and ``import_records`` (from
    :func:`run_commands_with_floors`: the commands and the floors timed in
    alternation) are reused when given.  Otherwise, with ``commands``, both
    are timed here in alternation (``repeats`` runs of each command), or
    without commands the import floors alone (``repeats`` runs each).  The
    suite's hand-coded floor (:func:`run_hand_coded_floor`) is the best of
    ``floor_repeats``.  Rows with a ``kind``: ``import floor``, ``command``,
    ``in-process``.
    """
    log = log or (lambda _s: None)
    if command_records is None and commands:
        command_records, imports = run_commands_with_floors(repeats, log=log)
        imports = import_records if import_records is not None else imports
    else:
        imports = import_records if import_records is not None else run_import_floors(repeats, log=log)
    rows = list(imports) + command_floor_ratios(command_records or [], imports)
    rows.append(run_hand_coded_floor(floor_repeats, log=log))
    return rows


def floor_target_check(row: dict) -> TargetCheck | None:
    """The hand-coded floor's target (its floor case's ``target_ratio``) against the floors section's
    in-process row (:func:`run_hand_coded_floor`); None when the floor case sets no target."""
    limit = row.get("target_ratio")
    if not _finite(limit):
        return None
    target = f"warm {row['case']} ≤ {limit:g}× the hand-coded floor"
    acausal_ms, floor_ms = 1e3 * row["acausal_seconds"], 1e3 * row["floor_seconds"]
    measured = f"{acausal_ms:.2f} ms against {floor_ms:.2f} ms: {row['ratio']:.1f}× (best of {row['repeats']})"
    if not row["agree"]:
        return TargetCheck(target, measured, False,
                           f"the final {row['output']} differ by {_fmt(row['final_difference'])} {row['unit']}, more "
                           f"than {row['agreement']:g}: not the same result.")
    if row["ratio"] <= limit:
        return TargetCheck(target, measured, True)
    rhs_ratio = row["acausal_rhs_evaluations"] / max(row["floor_rhs_evaluations"], 1)
    at_floor_cost = floor_ms * rhs_ratio  # acausal's evaluations at the floor's cost per evaluation
    beyond = acausal_ms - at_floor_cost
    why = (f"{limit:g}× is {limit * floor_ms:.2f} ms, {acausal_ms - limit * floor_ms:.2f} ms less than measured; "
           f"acausal makes {rhs_ratio:.2f}× the floor's right-hand side evaluations ({row['acausal_rhs_evaluations']} "
           f"/ {row['floor_rhs_evaluations']}) in {row['acausal_steps']} steps against {row['floor_steps']}, "
           f"{at_floor_cost:.2f} ms at the floor's cost per evaluation: the other {beyond:.2f} ms "
           f"({beyond / acausal_ms:.0%}) are work the floor does not do ({row['acausal_events']} events against "
           f"{row['floor_switches']} switches, the event evaluator and initialization, columns for every variable)"
           if beyond > 0 else
           f"{limit:g}× is {limit * floor_ms:.2f} ms; acausal makes {rhs_ratio:.2f}× the floor's right-hand side "
           "evaluations: the integration itself costs more per evaluation")
    return TargetCheck(target, measured, False, why + ".")


def _floors_markdown(rows: Sequence[dict], floor_case: FloorCase | None = None) -> str:
    """The floors table; the hand-coded floor described by ``floor_case`` (default: the suite's)."""
    imports = [r for r in rows if r["kind"] == "import floor"]
    commands = [r for r in rows if r["kind"] == "command"]
    in_process = [r for r in rows if r["kind"] == "in-process"]
    checks = command_target_checks(commands) if commands else []
    checks += [check for check in map(floor_target_check, in_process) if check is not None]
    parts = ["# Floors", "",
             "What the same work costs without the engine: the commands against a bare interpreter that "
             "imports numpy (and scipy's integrators), and a warm simulation against the same model written "
             "by hand (the suite's `floor_case()`).", "", _targets_markdown(checks)]
    if imports:
        parts += ["## Fresh-process floors", "",
                  "Each in a new Python process (same interpreter, folder and environment as the commands), "
                  "timed from outside.", "",
                  _md_table(("floor", "runs", "min wall [s]", "median wall [s]", "max wall [s]"),
                            [(r["what"].replace("|", "\\|"), r["runs"], f"{r['min_wall']:.3f}",
                              f"{r['median_wall']:.3f}", f"{r['max_wall']:.3f}") for r in imports]), ""]
    if commands:
        parts += ["## Commands against the floors", "",
                  "Median wall time of each command (as in the commands section) divided by each floor's median: "
                  "when the commands ran in the same bench, the floor runs of the command's own rounds (timed in "
                  "alternation with it), else the table above. *cold*: "
                  "the persistent compile cache off (every run compiles); *warm*: every run loads its compiled "
                  "systems from a cache filled by an untimed run.", "",
                  _md_table(("command", "disk cache", "runs", "median wall [s]", "× import numpy",
                             "× numpy+scipy.integrate", "passed"),
                            [(r["what"], r.get("disk_cache", "warm"), r["runs"], f"{r['median_wall']:.2f}",
                              f"{r['x_import_numpy']:.1f}", f"{r['x_numpy_scipy']:.1f}",
                              "yes" if r["passed"] else f"**no**: {r['failure']}")
                             for r in commands]), ""]
    if in_process and floor_case is None:
        floor_case = suite().floor_case()
    for r in in_process:
        unit = r["unit"]
        check = "agree" if r["agree"] else f"**WARNING: differ by more than {r['agreement']:g} {unit}**"
        switches = f"at t = {r['floor_switch_times']} s" if r["floor_switch_times"] else "none"
        note = (f"{floor_case.events_note} (its switches {switches})." if floor_case.events_note
                else f"The floor's switches: {switches}.")
        parts += [f"## Warm {r['case']} against a hand-coded floor", "",
                  floor_case.description + f" Both with {r['method']}, the same rtol and atol, the same output "
                  "grid. acausal: translated once, simulated once to warm up, best of the repeats with the "
                  "translation reused (`simulate(translation)`: event evaluator, initialization, integration, "
                  "events, the result's columns for every variable); the floor: best of the repeats after one "
                  "warm-up.", "",
                  _md_table(("run", "repeats", "acausal [ms]", "hand-coded floor [ms]", "acausal / floor",
                             "steps (acausal / floor)", "rhs evaluations (acausal / floor)", "events / switches",
                             f"final {r['output']} acausal [{unit}]", f"final {r['output']} floor [{unit}]",
                             "\\|Δ\\|", "check"),
                            [(r["what"], r["repeats"], f"{r['acausal_seconds'] * 1e3:.2f}",
                              f"{r['floor_seconds'] * 1e3:.2f}", f"{r['ratio']:.1f}",
                              f"{r['acausal_steps']} / {r['floor_steps']}",
                              f"{r['acausal_rhs_evaluations']} / {r['floor_rhs_evaluations']}",
                              f"{r['acausal_events']} / {r['floor_switches']}",
                              f"{r['acausal_final']:.9g}", f"{r['floor_final']:.9g}",
                              _fmt(r["final_difference"]), check)]), "",
                  note, ""]
    return "\n".join(parts)


def write_floors(rows: Sequence[dict], out_dir: Path, floor_case: FloorCase | None = None) -> dict:
    """Write ``floors.md`` and ``floors.csv`` into ``out_dir``; their paths.

    ``floor_case`` describes the hand-coded floor's row (default: the suite's ``floor_case()``).
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    files = {"floors.md": out_dir / "floors.md", "floors.csv": out_dir / "floors.csv"}
    files["floors.md"].write_text(_floors_markdown(rows, floor_case))
    _write_dict_csv(files["floors.csv"], rows)
    return files


# ---------------------------------------------------------------------------
# The whole bench
# ---------------------------------------------------------------------------


@dataclass
class BenchResult:
    """Everything the bench measured and the files it wrote."""

    quick: bool
    runs: list[CaseRun]
    effects: list[EffectsRecord]
    scaling: list[dict]
    scaling_fits: dict
    files: dict
    tables: dict
    wall_seconds: float
    #: What was not measured, and why (reference results missing).
    skipped: dict = field(default_factory=dict)
    soak: SoakResult | None = None
    #: The storm section's points (:func:`run_storm`) and the floors section's rows (:func:`run_floors`).
    storm: list = field(default_factory=list)
    floors: list = field(default_factory=list)
    #: The scaling section's array case points (:func:`run_array_scaling`) and their fits
    #: (:func:`array_scaling_fits`).
    array_scaling: list = field(default_factory=list)
    array_scaling_fits: dict = field(default_factory=dict)

    @property
    def records(self) -> list[RunRecord]:
        return [r for run in self.runs for r in run.records]

    @property
    def failures(self) -> list[RunRecord]:
        return [r for r in self.records if r.status != 0]


def run_parameter_change(repeats: int = 5, log: Callable[[str], None] | None = None) -> list[dict]:
    """What a changed tunable parameter costs, against translating anew.

    The suite's parameter case (``parameter_case()``): one run translated
    from scratch (``cache=False``), the same model again (the cache), each
    of several new values of one tunable parameter (the compiled systems
    rebound to a new parameter vector), the value 0 (a structural zero:
    a new translation), and new start values of one state (``start_case()``:
    start values are inputs of the generated code too).  Wall seconds and
    the run's own translation seconds, median of ``repeats`` for the
    repeatable rows.
    """
    from ..runtime.simulate import simulate

    name, make, parameter, values = suite().parameter_case()
    rows = []

    def timed(label: str, repeat: int, run: Callable[[], object]) -> None:
        walls, translates, status = [], [], 0
        for _ in range(repeat):
            t0 = time.perf_counter()
            result = run()
            walls.append(time.perf_counter() - t0)
            translates.append(result.stats.get("translate_seconds", math.nan))
            status = min(status, result.status)
        rows.append({"model": name, "run": label, "repeats": repeat,
                     "wall_seconds": float(np.median(walls)),
                     "translate_seconds": float(np.median(translates)), "status": status})
        if log:
            log(f"  {label}: {rows[-1]['wall_seconds']:.3f} s (translation {rows[-1]['translate_seconds']:.3f} s)")

    timed("translated anew (cache=False)", repeats, lambda: simulate(make(), cache=False))
    simulate(make())  # the cache's first translation of the structure
    timed("same model again (cache)", repeats, lambda: simulate(make()))
    for value in values:
        timed(f"{parameter} = {value:g} (new value, systems rebound)", 1,
              lambda value=value: simulate(make(), parameters={parameter: value}))
    timed(f"{parameter} = 0 (structural zero: translated anew)", 1,
          lambda: simulate(make(), parameters={parameter: 0.0}))
    start_name, start_values = suite().start_case()
    for value in start_values:
        timed(f"{start_name} start = {value:g} (start value at run time, systems rebound)", 1,
              lambda value=value: simulate(make(), start={start_name: value}))
    return rows


def _parameters_markdown(rows: list[dict]) -> str:
    lines = ["# A changed parameter", "",
             "Each new value of a tunable parameter reuses the systems compiled for the model's own "
             "values, bound to a new parameter vector; what is left of the translation is "
             "flattening (always done: the cache keys on the flat model) and binding. A zero is a "
             "structural zero and translates anew. A start value given at run time (`start=`) is a "
             "parameter of the generated code too: rebound, not translated. Wall seconds per run (median of the repeats), "
             "translation seconds as the run's `stats` count them.", "",
             "| model | run | repeats | wall [s] | translation [s] | status |", "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['model']} | {r['run']} | {r['repeats']} | {r['wall_seconds']:.3f} | "
                     f"{r['translate_seconds']:.3f} | {r['status']} |")
    return "\n".join(lines) + "\n"


def run_bench(quick: bool, out_dir: Path, methods: Sequence[str] | None = None,
              rtols: Sequence[float] | None = None, *, case_names: Sequence[str] | None = None,
              effects: bool = True, scaling_sizes: Sequence[int] | None = None,
              repeats: int | None = None, isolate_scaling: bool = True,
              commands: bool = True, soak_runs: int | None = None, verbose: bool = False,
              parameters: bool = True, storm: bool = True, storm_sizes: Sequence[int] | None = None,
              floors: bool = True, table_sizes: bool = True,
              array_sizes: Sequence[int] | None = None) -> BenchResult:
    """Run the benchmark and write its tables and plots into ``out_dir``.

    Parameters
    ----------
    quick : bool
        Quick: the suite's ``QUICK_CASES``; rtol 1e-3, 1e-6, 1e-9;
        2 repeats; scaling N = 10, 40.  Full: every case, rtol 1e-3 ... 1e-10;
        3 repeats; scaling N = 10 ... 1000 within a time budget per point.
    methods, rtols : optional
        Override the adaptive methods and tolerances.
    case_names, effects, scaling_sizes, repeats, commands, soak_runs :
        Reduce the bench (tests): the cases to run (``()`` for none: no
        ``bench.md`` then), whether to run the effects section, the scaling
        sizes (``()`` for none), whether to time the fresh-process commands,
        the soak's runs per mode (default 20 quick, 200 full; 0 for none).
    parameters, storm, floors, table_sizes : bool
        Whether to run the parameter-change, storm, floors and table-size
        (:mod:`acausal.tools.table_bench`) sections.
    storm_sizes : optional
        The storm's N (default 3, 6 quick; 5 ... 200 full); each N <= 6
        (quick) or 20 (full) also without clusters.
    array_sizes : optional
        The sizes of the scaling section's array case (:func:`run_array_scaling`;
        default 10, 30, 100 quick, 10 ... 1000 full, when the scaling section
        runs at all; ``()`` for none), isolated as the scaling points.
    isolate_scaling : bool
        Run each scaling point in a fresh process (default), so that every
        translation starts with sympy's caches cold, as a user's first
        translation does, and memory is returned; in-process points after
        other translations come out faster.
    """
    from ..runtime.simulate import METHODS

    wall0 = time.perf_counter()
    _ensure_path()
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    methods = tuple(methods) if methods else ADAPTIVE_METHODS
    for m in methods:
        if m not in METHODS:
            raise ValueError(f"unknown method {m!r}; choose from {', '.join(METHODS)}")
    rtols = tuple(float(r) for r in rtols) if rtols else (QUICK_RTOLS if quick else FULL_RTOLS)
    repeats = repeats if repeats is not None else (2 if quick else 3)
    all_cases = cases()
    if case_names is not None:
        names = tuple(case_names)
    else:
        names = suite().QUICK_CASES if quick else tuple(all_cases)
    sizes = tuple(scaling_sizes) if scaling_sizes is not None else (QUICK_SCALING if quick else full_scaling_sizes())
    if array_sizes is None:
        array_sizes = (QUICK_ARRAY_SCALING if quick else FULL_ARRAY_SCALING) if sizes else ()
    array_sizes = tuple(array_sizes)
    if soak_runs is None:
        soak_runs = QUICK_SOAK_RUNS if quick else FULL_SOAK_RUNS
    log = (lambda s: print(s, flush=True)) if verbose else (lambda _s: None)

    sections: dict = {}

    def cpu() -> float:  # this process and its finished children (the scaling points)
        t = os.times()
        return t.user + t.system + t.children_user + t.children_system

    def section(label: str, start: tuple[float, float]) -> None:
        sections[label] = (time.perf_counter() - start[0], cpu() - start[1])
        log(f"[{label}: {sections[label][0]:.1f} s wall, {sections[label][1]:.1f} s CPU]")

    runs = []
    skipped: dict[str, str] = {}  # what was not measured, and why
    for name in names:
        missing = _reference_missing(all_cases[name].reference) if all_cases[name].reference else None
        if missing:
            skipped[f"case {name}"] = missing
            log(f"case {name} skipped: {missing}")
            continue
        log(f"case {name}")
        start = (time.perf_counter(), cpu())
        runs.append(run_case(all_cases[name], methods, rtols, repeats, log))
        section(name, start)

    start = (time.perf_counter(), cpu())
    effect_records = run_effects(repeats=1 if quick else repeats, log=log) if effects else []
    if effects:
        section("effects", start)
    if commands:
        # the commands compare with the reference results: without them they only fail
        for name, _example_file in suite().COMMAND_TARGETS:
            missing = _reference_missing(all_cases[name].reference)
            if missing:
                skipped["fresh-process commands"] = missing
                log(f"fresh-process commands skipped: {missing}")
                commands = False
                break
    command_records: list[dict] = []
    command_import_floors: list[dict] = []
    command_repeats = 3 if quick else 7
    if commands:
        log("fresh-process commands")
        start = (time.perf_counter(), cpu())
        command_records, command_import_floors = run_commands_with_floors(command_repeats, log=log)
        section("commands", start)
    if sizes or array_sizes:
        log("scaling")
    start = (time.perf_counter(), cpu())
    points = run_scaling(sizes, isolate=isolate_scaling, log=log) if sizes else []
    array_case = array_scaling_case() if array_sizes else None
    array_points = run_array_scaling(array_sizes, isolate=isolate_scaling, log=log) if array_sizes else []
    array_fits = array_scaling_fits(array_points)
    if sizes or array_sizes:
        section("scaling", start)

    def timed(label: str, run: Callable[[], object]):
        log(label)
        start = (time.perf_counter(), cpu())
        out = run()
        section(label, start)
        return out

    soak = timed("soak", lambda: run_soak(soak_runs, log=log)) if soak_runs else None
    parameter_rows = (timed("parameters", lambda: run_parameter_change(3 if quick else 5, log=log))
                      if parameters else [])
    storm_timeout = QUICK_STORM_TIMEOUT_SECONDS if quick else STORM_TIMEOUT_SECONDS
    if storm_sizes is None:
        storm_sizes = QUICK_STORM if quick else full_storm_sizes()
    storm_points = (timed("storm", lambda: run_storm(
        tuple(storm_sizes), QUICK_STORM_WHOLE_UP_TO if quick else FULL_STORM_WHOLE_UP_TO, storm_timeout, log=log))
        if storm and storm_sizes else [])
    floor_rows: list[dict] = []
    if floors:
        # the commands compare with the reference results: without them only the other floors are measured
        floor_commands = True
        if not command_records:
            for name, _example_file in suite().COMMAND_TARGETS:
                missing = _reference_missing(all_cases[name].reference)
                if missing:
                    skipped["floors: fresh-process commands"] = missing
                    floor_commands = False
                    break
        floor_rows = timed("floors", lambda: run_floors(command_repeats, command_records or None,
                                                        commands=floor_commands, log=log,
                                                        import_records=command_import_floors or None))
    table_rows: list[dict] = []
    if table_sizes:
        from .table_bench import FULL_ROWS, QUICK_ROWS, run_tables

        table_rows = timed("tables", lambda: run_tables(suite().table_models, QUICK_ROWS if quick else FULL_ROWS,
                                                        2 if quick else 3, log=log))
    fits = {}
    for key in ("translation", "structure", "flatten", "alias", "blt", "algebraic", "codegen",
                "evaluator_setup", "initial_systems", "initialization", "translated_initialized", "simulate"):
        # a point stopped by the budget still counts for the phases it finished
        measured = [p for p in points if isinstance(p.get(key), (int, float)) and math.isfinite(p[key])]
        if len(measured) >= 2:
            fits[key] = fit_power_law([p["n"] for p in measured], [p[key] for p in measured])

    wall = time.perf_counter() - wall0
    files: dict = {}
    tables: dict = {}
    if names:  # the work-precision section was asked for
        bench_md = _bench_markdown(runs, quick, wall)
        if skipped:
            bench_md += ("\n## Not measured\n\n" + "\n".join(f"- {what}: {why}" for what, why in skipped.items())
                         + "\n")
        tables["bench"] = bench_md
        files["bench.md"] = out_dir / "bench.md"
        files["bench.md"].write_text(bench_md)
        files["bench.csv"] = out_dir / "bench.csv"
        _write_bench_csv(files["bench.csv"], runs)
        for quantity, cost, fname in (("error", "sim_seconds", "work_precision.png"),
                                      ("event_error", "sim_seconds", "work_precision_events.png"),
                                      ("error", "rhs_evaluations", "work_precision_rhs.png")):
            path = _plot_work_precision(runs, out_dir / fname, quantity, cost)
            if path is not None:
                files[fname] = path

    def table(key: str, markdown: str, rows: list[dict]) -> None:
        """``key``.md and ``key``.csv, and the markdown for the summary printed at the end."""
        tables[key] = markdown
        files[f"{key}.md"] = out_dir / f"{key}.md"
        files[f"{key}.md"].write_text(markdown)
        files[f"{key}.csv"] = out_dir / f"{key}.csv"
        _write_dict_csv(files[f"{key}.csv"], rows)

    if effect_records:
        table("effects", _effects_markdown(effect_records), [vars(r) for r in effect_records])
    if command_records:
        table("commands", _commands_markdown(command_records), command_records)
    if points or array_points:
        markdown = _scaling_markdown(points, fits, isolate_scaling) if points else "# Scaling\n"
        if array_points:
            markdown += "\n" + _array_scaling_markdown(array_points, array_fits, array_case, isolate_scaling)
            files["scaling_arrays.csv"] = out_dir / "scaling_arrays.csv"
            _write_dict_csv(files["scaling_arrays.csv"], array_points)
        table("scaling", markdown, points)
        path = _plot_scaling(points, fits, out_dir / "scaling.png") if points else None
        if path is not None:
            files["scaling.png"] = path
    if parameter_rows:
        table("parameters", _parameters_markdown(parameter_rows), parameter_rows)
    if storm_points:
        files.update(write_storm(storm_points, out_dir, storm_timeout))
        tables["storm"] = files["storm.md"].read_text()
    if floor_rows:
        files.update(write_floors(floor_rows, out_dir))
        tables["floors"] = files["floors.md"].read_text()
    if table_rows:
        from .table_bench import write_tables

        files.update(write_tables(table_rows, out_dir))
        tables["tables"] = files["tables.md"].read_text()
    if soak is not None:
        files.update(write_soak(soak, out_dir))
        tables["soak"] = _soak_markdown(soak).split("\n## Runs")[0].rstrip() + "\n"
    wall = time.perf_counter() - wall0
    return BenchResult(quick, runs, effect_records, points, fits, files, tables, wall, skipped, soak,
                       storm_points, floor_rows, array_points, array_fits)


def _split(text: str) -> list[str]:
    return [s.strip() for s in text.split(",") if s.strip()]


def default_out() -> Path:
    """The folder ``acausal bench`` writes into without ``--out``: ``acausal-bench`` in the user's
    cache folder (``$XDG_CACHE_HOME``, else ``~/.cache``; ``~/Library/Caches`` on macOS;
    ``%LOCALAPPDATA%`` on Windows), outside any source tree and beside, not inside, the
    compile cache's folder.  The bench prints it."""
    if sys.platform == "darwin":
        base = Path.home() / "Library" / "Caches"
    elif os.name == "nt":
        base = Path(os.environ.get("LOCALAPPDATA") or Path.home() / "AppData" / "Local")
    else:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / "acausal-bench"


def main(argv: Sequence[str] | None = None) -> int:
    """``acausal bench``: run the benchmark, write the files, print the tables; exit status 0."""
    from .collector import GC_THRESHOLD

    # the collector as in every `acausal` command, however the bench is started
    gc.set_threshold(*GC_THRESHOLD)
    parser = argparse.ArgumentParser(prog="acausal bench",
                                     description="Work-precision benchmark of the adaptive methods, "
                                                 "effects of output demand, scaling with model size, a "
                                                 "soak (one model simulated many times in one process), "
                                                 "a storm of independent hybrid parts, floors (the "
                                                 "same work without the engine), and what a table's "
                                                 "size costs.")
    parser.add_argument("--quick", action="store_true",
                        help="a reduced bench (4 cases, rtol 1e-3/1e-6/1e-9, N = 10, 40; arrays N = 10, 30, "
                             "100; storm N = 3, 6)")
    parser.add_argument("--out", metavar="DIR",
                        help=f"output folder (default {default_out()}, the user's cache folder)")
    parser.add_argument("--methods", metavar="M,...",
                        help=f"comma-separated methods (default {','.join(ADAPTIVE_METHODS)})")
    parser.add_argument("--rtols", metavar="R,...", help="comma-separated relative tolerances")
    parser.add_argument("--only", metavar="SECTION,...",
                        help=f"run only these sections ({', '.join(SECTIONS)}); the others' files are "
                             "left as they are")
    parser.add_argument("--soak-runs", type=int, metavar="N",
                        help=f"runs per mode of the soak (default {QUICK_SOAK_RUNS} with --quick, "
                             f"else {FULL_SOAK_RUNS}; 0: no soak)")
    args = parser.parse_args(argv)
    only = set(SECTIONS)
    if args.only is not None:
        only = {s.lower() for s in _split(args.only)}
        unknown = sorted(only - set(SECTIONS))
        if unknown or not only:
            parser.error(f"--only: unknown section {unknown[0] if unknown else args.only!r}; "
                         f"choose from {', '.join(SECTIONS)}")
    if args.soak_runs is not None and args.soak_runs != 0 and args.soak_runs < 2:
        parser.error("--soak-runs: at least 2 (or 0 for none)")
    methods = _split(args.methods) if args.methods else None
    if methods:
        from ..runtime.simulate import METHODS

        known = {m.lower(): m for m in METHODS}
        unknown = [m for m in methods if m.lower() not in known]
        if unknown:
            parser.error(f"--methods: unknown method {unknown[0]!r}; choose from {', '.join(METHODS)}")
        methods = [known[m.lower()] for m in methods]
    try:
        rtols = [float(r) for r in _split(args.rtols)] if args.rtols else None
    except ValueError:
        parser.error(f"--rtols: not a list of numbers: {args.rtols!r}")
    reduced: dict = {}
    if "work-precision" not in only:
        reduced["case_names"] = ()
    if "effects" not in only:
        reduced["effects"] = False
    if "commands" not in only:
        reduced["commands"] = False
    if "scaling" not in only:
        reduced["scaling_sizes"] = ()
    if "parameters" not in only:
        reduced["parameters"] = False
    if "storm" not in only:
        reduced["storm"] = False
    if "floors" not in only:
        reduced["floors"] = False
    if "tables" not in only:
        reduced["table_sizes"] = False
    if "soak" not in only:
        reduced["soak_runs"] = 0
    elif args.soak_runs is not None:
        reduced["soak_runs"] = args.soak_runs
    out = Path(args.out) if args.out else default_out()
    if not args.out:
        print(f"acausal bench: writing into {out} (--out DIR for another folder)", flush=True)
    result = run_bench(args.quick, out, methods, rtols, verbose=True, **reduced)
    print()
    for key in ("bench", "effects", "commands", "scaling", "soak", "parameters", "storm", "floors", "tables"):
        if key in result.tables:
            print(result.tables[key])
            print()
    for name, path in result.files.items():
        print(f"wrote {path}")
    for what, why in result.skipped.items():
        print(f"not measured: {what}: {why}")
    failed = len(result.failures)
    print(f"bench finished in {result.wall_seconds:.1f} s ({len(result.records)} runs, {failed} failed)")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
