"""Parameter sweeps and ensembles: many runs of one model, one translation.

:func:`sweep` translates the model once, in this process, runs the first
parameter set here (which compiles the discrete states it visits), and ships
the translation to the workers as plain data
(:meth:`~acausal.compiler.translate.Translation.export`): the flat and
partitioned model and every compiled system *as its generated source*, the
payloads of the persistent compile cache.  A worker builds its systems from
that source (:meth:`~acausal.compiler.translate.Translation.from_bundle`),
binds them to each run's parameter vector and simulates: it never flattens,
partitions or compiles what was shipped.

A discrete state is only known when a run reaches it: a run that visits one
the first run did not is compiled in the worker that meets it (once per
worker process; later runs there load it), and the result counts it
(:attr:`SweepResult.compiled_in_workers`).  A parameter value that changes
what the translation decided (a zero that removes a term, a relation of
parameters alone, a start value computed from a parameter for a variable that
is neither a state nor fixed) has its run translated in the worker
(:attr:`SweepResult.translated_in_workers`), as ``simulate(model,
parameters=...)`` would translate it.  Start values of states and fixed
variables are parameters of the shipped code: swept (``"J1.w.start"``) or
computed from a parameter, they cost no translation.

Executors: a process pool of the standard library (the default, sized to the
machine), any :class:`concurrent.futures.Executor`, a ``dask.distributed``
``Client`` or a scheduler address ``"tcp://host:port"`` (``pip install
acausal[dask]``), or ``"serial"`` (in this process).  Runs travel in chunks,
several parameter sets per task, so that the per-task overhead is paid once
per chunk.

The bundle reaches each worker once; a task carries only its digest and its
runs' values (a few hundred bytes a run, where the bundle is hundreds of
kilobytes).  A forked worker of a process pool made here inherits it (the
pool's initializer: nothing is copied); any other worker process (of a pool
of the user's, or started by spawn or a fork server) reads it once, from a
file in the sweep's private temporary folder, and if its workers cannot
(they run on another machine) it travels with every task instead; a Dask
cluster holds it as the result of one task.  The runs' values are resolved here while the workers
run the first chunks, so that this process's share of each run does not add
to the sweep's wall time.  ``python -m acausal.tools.sweep_bench`` measures
the overhead per task and how the speed-up follows from it.

What survives: a worker process that dies (the OOM killer, a signal) breaks a
process pool and fails every task on it; the pool is replaced and the runs
that had not come back are sent again, and a run that kills its worker twice
(the second time alone) is a failed row, ``error_type`` ``'WorkerDied'``.  A
task that raises (on Dask too, where a worker lost too often is
``KilledWorker``) has its runs retried one by one, and a run whose task
raises again is a failed row.  ``timeout=`` and ``max_steps=`` bound every
run.  Ctrl-C stops the workers and raises :class:`SweepInterrupted`, which
carries the runs that finished.
"""

from __future__ import annotations

import argparse
import collections
import concurrent.futures
import dataclasses
import itertools
import math
import multiprocessing
import os
import pickle
import shutil
import signal
import sys
import tempfile
import threading
import time as _time
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping, Sequence

import numpy as np

from ..compiler.diskcache import MemoryCache
from ..compiler.flatten import FlatModel, FlatParameter, _Flattener, tunable_starts_of
from ..compiler.initial import InitialSystem
from ..compiler.modes import ModeSystem
from ..compiler.translate import Translation, TranslationBundle, translate, with_start_values
from ..errors import AcausalError, SettingError, SimulationInterrupted
from ..language import Component
from ..runtime.result import SimulationResult
from ..runtime.simulate import TerminalProgress, progress_reporter, simulate
from .modelfile import CommandError, load_model_class

__all__ = ["sweep", "SweepResult", "RunOutcome", "SweepInterrupted", "parameter_sets", "main_sweep"]


# -- the parameter sets ---------------------------------------------------------------------------


def parameter_sets(parameters: Mapping[str, Sequence[float]] | Sequence[Mapping[str, float]], *,
                   samples: int | None = None, seed: int | None = None,
                   method: str = "lhs") -> list[dict[str, float]]:
    """The runs of a sweep, in a deterministic order.

    Parameters
    ----------
    parameters : mapping or sequence of mappings
        ``name -> list of values``: the full factorial grid, the last name
        varying fastest (``itertools.product`` order).  A sequence of
        ``name -> value`` mappings: those runs, in that order.  With
        ``samples``: ``name -> (low, high)``.
    samples : int, optional
        Draw this many points in the box ``low <= value <= high``.
    seed : int, optional
        Seed of the random numbers (the same seed gives the same points).
    method : {'lhs', 'uniform'}
        'lhs' (the default): a Latin hypercube (McKay, Beckman & Conover,
        1979) from :class:`scipy.stats.qmc.LatinHypercube`: each parameter's
        range is cut in ``samples`` equal strata and every stratum holds
        exactly one point.  'uniform': independent uniform draws.

    References
    ----------
    .. [1] M. D. McKay, R. J. Beckman and W. J. Conover, "A comparison of three
       methods for selecting values of input variables in the analysis of
       output from a computer code", Technometrics 21(2), 239-245, 1979.
    """
    if samples is not None:
        if not isinstance(parameters, Mapping):
            raise SettingError("samples= needs parameters as name -> (low, high)")
        if int(samples) < 1:
            raise SettingError(f"samples must be at least 1, not {samples}")
        names = list(parameters)
        bounds = []
        for name in names:
            try:
                low, high = (float(v) for v in parameters[name])
            except (TypeError, ValueError):
                raise SettingError(f"{name}: with samples=, give (low, high), not {parameters[name]!r}") from None
            bounds.append((low, high))
        if method == "lhs":
            from scipy.stats import qmc

            unit = qmc.LatinHypercube(d=len(names), seed=seed).random(int(samples))
        elif method == "uniform":
            unit = np.random.default_rng(seed).random((int(samples), len(names)))
        else:
            raise SettingError(f"unknown sampling method {method!r}", hint="choose 'lhs' or 'uniform'")
        low = np.array([b[0] for b in bounds])
        high = np.array([b[1] for b in bounds])
        points = low + unit * (high - low)
        return [{n: float(v) for n, v in zip(names, row)} for row in points]
    if isinstance(parameters, Mapping):
        names = list(parameters)
        values = [list(parameters[n]) if isinstance(parameters[n], (list, tuple, np.ndarray))
                  else [parameters[n]] for n in names]
        return [{n: float(v) for n, v in zip(names, row)} for row in itertools.product(*values)]
    return [{n: float(v) for n, v in run.items()} for run in parameters]


def _flat_values(model: Component, overrides: Mapping[str, float]) -> tuple[tuple[FlatParameter, ...], tuple]:
    """The flat model's parameters and variables for ``overrides``, without its equations.

    The first steps of :func:`~acausal.compiler.flatten.flatten` (declarations,
    the values given, bindings resolved and checked, variable attributes):
    a few milliseconds, where flattening the equations takes tens.
    """
    flattener = _Flattener(model, dict(overrides))
    for component in flattener.components:
        flattener._declare(component)
    flattener._apply_overrides()
    values = flattener.values = flattener._resolve_parameters()
    for component in flattener.components:
        flattener._declare_variables(component, values)
    parameters = tuple(FlatParameter(n, values[n], flattener.parameters[n][1], flattener.parameters[n][2].path)
                       for n in flattener.parameters if n not in flattener.unknown_parameters)
    return parameters, tuple(flattener.variables.values())


# -- one task: several runs in a worker -----------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class _RunSpec:
    """One run as a task carries it: the values given and the flat model's resolved ones."""

    index: int
    values: dict
    parameters: tuple  #: the flat model's parameter values, in the bundle's order
    variables: tuple | None  #: the flat model's variables when they differ from the bundle's
    #: its tunable start values (in the order of the bundle's ``tunable_starts``) when only they differ
    starts: tuple = ()


@dataclasses.dataclass(frozen=True)
class RunOutcome:
    """One run of a sweep.

    Attributes
    ----------
    index : int
        Its place in the sweep.
    values : dict
        The parameter values given.
    status : int
        As :attr:`SimulationResult.status`; -1 also for a run that raised.
    message : str
        The result's message, or the error's.
    error_type : str
        The class of the error that stopped the run ('' for none);
        ``'WorkerDied'`` for a run whose worker process died under it twice.
    result : SimulationResult or None
        Its time and the output columns (None when it raised before
        computing anything); the error object itself stays in the worker.
    seconds : float
        Wall time of the run in the worker.
    compiled : int
        Systems compiled in the worker for this run (0: everything came
        from the parent's translation).
    translated : bool
        Whether the worker translated the model for this run.
    """

    index: int
    values: dict
    status: int
    message: str
    error_type: str
    result: SimulationResult | None
    seconds: float
    compiled: int = 0
    translated: bool = False


@dataclasses.dataclass(frozen=True)
class _Shipped:
    """What a task carries of the bundle: its digest, and where a worker that lacks it reads it.

    Attributes
    ----------
    digest : str
        The bundle's :attr:`~acausal.compiler.translate.TranslationBundle.digest`,
        under which a worker process holds it.
    path : str or None
        A file holding the bundle pickled, which a worker that does not hold
        it reads with its first task.
    """

    digest: str
    path: str | None = None


class _BundleMissing(Exception):
    """A worker holds no bundle of the task's digest and cannot read its file (it runs elsewhere)."""


@dataclasses.dataclass
class _Held:
    """A bundle as a process holds it: its flat model and payload store are made on first use
    (a worker given the bundle at its start reads it with its first task, whose errors are the
    task's, instead of breaking the pool)."""

    bundle: TranslationBundle
    base: FlatModel | None = None
    store: MemoryCache | None = None


#: the bundle this process holds, by digest (one sweep at a time per process)
_WORKER_STATE: dict[str, _Held] = {}
#: the threads of a pool of threads read a bundle once, not once each
_STATE_LOCK = threading.Lock()


def _hold(bundle: TranslationBundle) -> _Held:
    """Hold ``bundle`` in this process, in place of the previous sweep's."""
    _WORKER_STATE.clear()
    held = _WORKER_STATE[bundle.digest] = _Held(bundle)
    return held


def _worker_state(bundle: TranslationBundle | _Shipped) -> tuple[TranslationBundle, FlatModel, MemoryCache]:
    """The bundle of a task, its base flat model and its payload store, read once per process.

    Raises
    ------
    _BundleMissing
        ``bundle`` is a digest this process does not hold, and its file
        cannot be read here.
    """
    held = _WORKER_STATE.get(bundle.digest)
    if held is None or held.base is None:
        with _STATE_LOCK:
            held = _WORKER_STATE.get(bundle.digest)
            if held is None:
                held = _hold(bundle if isinstance(bundle, TranslationBundle) else _read_shipped(bundle))
            if held.base is None:
                # the store first: a thread that sees the base outside the lock finds both
                if held.store is None:
                    held.store = held.bundle.store()
                held.base = held.bundle.unpacked()[0]
    return held.bundle, held.base, held.store


def _read_shipped(shipped: _Shipped) -> TranslationBundle:
    """The bundle from the file a pool of the user's reads it from (once per worker process)."""
    try:
        if shipped.path is None:
            raise OSError("the task carries no file of the bundle")
        with open(shipped.path, "rb") as file:
            bundle = pickle.load(file)
    except (OSError, EOFError, pickle.UnpicklingError) as exc:
        raise _BundleMissing(f"the sweep's bundle cannot be read in this worker: {exc}") from None
    if not isinstance(bundle, TranslationBundle) or bundle.digest != shipped.digest:
        raise _BundleMissing(f"{shipped.path} does not hold the sweep's bundle here")
    return bundle


def _compiled_systems(translation: Translation) -> int:
    """Systems of ``translation`` that were compiled, not loaded from the bundle."""
    tables = (translation.systems, translation.parts, translation.initial_systems, translation.initial_parts)
    return sum(isinstance(s, (ModeSystem, InitialSystem)) and not (s.passes[:1] and s.passes[0][0] == "load")
               for table in tables for s in table.values())


def _compact(result: SimulationResult, outputs: Sequence[str] | None) -> SimulationResult:
    """``result`` with only the output columns, its error left behind (it need not pickle)."""
    keep = list(result.columns) if outputs is None else [n for n in outputs if n in result.columns]
    return dataclasses.replace(result, columns={n: result.columns[n] for n in keep}, error=None,
                               column_info={n: i for n, i in result.column_info.items() if n in keep})


def _run_one(bundle: TranslationBundle | _Shipped, spec: _RunSpec, outputs, options: dict) -> RunOutcome:
    bundle, base, store = _worker_state(bundle)
    t0 = _time.perf_counter()
    translation = None
    try:
        parameters = tuple(dataclasses.replace(p, value=v) for p, v in zip(base.parameters, spec.parameters))
        flat = dataclasses.replace(base, parameters=parameters,
                                   variables=base.variables if spec.variables is None else spec.variables)
        if spec.starts:  # start values are parameters of the shipped code: no translation
            flat = flat.with_starts(dict(zip(base.tunable_starts, spec.starts)))
        translation = Translation.from_bundle(bundle, flat, store)
        result = simulate(translation, progress=False, **options)
    except Exception as exc:  # noqa: BLE001 - a failed run is a row of the table, the others go on
        return RunOutcome(spec.index, spec.values, -1, str(getattr(exc, "message", None) or exc),
                          type(exc).__name__, None, _time.perf_counter() - t0,
                          _compiled_systems(translation) if translation is not None else 0,
                          translation is not None and translation._disk is False)
    return RunOutcome(spec.index, spec.values, result.status, result.message,
                      type(result.error).__name__ if result.error is not None else "",
                      _compact(result, outputs), _time.perf_counter() - t0, _compiled_systems(translation),
                      translation._disk is False)


def _run_chunk(bundle: TranslationBundle | _Shipped, specs: Sequence[_RunSpec], outputs, options: dict,
               ledger: str | None = None) -> list[RunOutcome]:
    """A task: several runs in one worker (module level, so that spawned processes find it).

    ``bundle`` is the bundle itself (in this process, on Dask, or when the
    workers cannot read its file) or, once the workers hold it, its digest
    (:class:`_Shipped`).  With a ``ledger`` folder (see :class:`_Ledger`),
    each run is noted there while it is in progress.
    """
    _worker_state(bundle)  # before any run is noted: a bundle missing here is the task's error
    outcomes = []
    for spec in specs:
        if ledger is not None:
            _Ledger.note(ledger, spec.index)
        outcomes.append(_run_one(bundle, spec, outputs, options))
        if ledger is not None:
            _Ledger.note(ledger, None)
    return outcomes


def _worker_init(bundle: TranslationBundle | None = None) -> None:
    """The start of every worker process of a pool made here.

    Ctrl-C in a terminal reaches every process of the foreground group, but
    it is the parent's to handle (it stops the workers and keeps what they
    finished): the workers ignore SIGINT.  A forked worker inherits the
    SIGTERM handler of ``acausal sweep``; it gets the default action back, so
    that terminating it ends it.

    ``bundle``: the sweep's, for a forked process, which inherits it with
    the pool's ``initargs`` (see :func:`_process_pool`); the tasks name it by
    digest.  A forked process may hold it already, with the code the
    parent's runs loaded (:func:`sweep`'s pilot runs): that is kept.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    if bundle is not None and bundle.digest not in _WORKER_STATE:
        _hold(bundle)


# -- executors ------------------------------------------------------------------------------------

#: ``error_type`` of a run whose worker process died under it
WORKER_DIED = "WorkerDied"
#: seconds a terminated worker process gets to end before it is killed
_STOP_GRACE = 5.0
#: pool breakages with no run in progress after which the runs still to do are given up
_DEATHS_OUTSIDE_RUNS = 3


def _is_dask_client(executor: Any) -> bool:
    """A ``dask.distributed.Client`` (duck-typed: dask is not imported to check)."""
    return type(executor).__name__ == "Client" and hasattr(executor, "submit") and hasattr(executor, "gather")


def _died(spec: _RunSpec, how: str) -> RunOutcome:
    """The row of a run given up because its worker process died (``how``: when, and what followed)."""
    return RunOutcome(spec.index, spec.values, -1,
                      f"the worker process died (e.g. killed by the OOM killer or a signal) {how}",
                      WORKER_DIED, None, 0.0)


def _task_failed(chunk: list[_RunSpec], exc: Exception) -> tuple[list[list[_RunSpec]], list[RunOutcome]]:
    """What follows a task that raised: ``(chunks to send again, rows of failed runs)``.

    A run's own errors are rows already (:func:`_run_one`); what reaches here
    is the task's (a result that does not pickle, a Dask worker lost while
    running it).  It may be one run's doing, so a chunk's runs are sent
    again one by one and its neighbours are not failed with it; a single run
    is a failed row with the error.
    """
    if len(chunk) > 1:
        return [[spec] for spec in chunk], []
    spec = chunk[0]
    if type(exc).__name__ == "KilledWorker":  # Dask retried it on other workers, and they died too
        return [], [_died(spec, "while running it, on each Dask worker that tried it (KilledWorker); "
                                "the other runs went on")]
    return [], [RunOutcome(spec.index, spec.values, -1, str(exc) or type(exc).__name__, type(exc).__name__,
                           None, 0.0)]


class _Ledger:
    """Which runs the workers are doing: a folder with a file per worker process (and thread).

    A worker writes the index of the run it starts at the beginning of its
    file, opened once, and blanks it when the run ends: two ``pwrite`` calls
    per run (creating and removing a file per run instead made each run of a
    small model 0.1 ms slower).  A process pool whose worker dies fails every
    task it holds without saying which one was running where; once its
    processes are gone, the files name the runs that were in progress, in
    the process that died and in those the pool terminated after it.
    """

    #: in a worker: (folder, process, thread) -> descriptor of its file, for the current sweep's folder
    _files: dict[tuple[str, int, int], int] = {}
    #: the threads of a pool of threads open their files, and close the previous sweep's, one at a time
    _opening = threading.Lock()
    _WIDTH = 20
    #: the file in the folder that holds the bundle, for workers that lack it (see :meth:`_Pool._shipped`)
    BUNDLE = "bundle.pickle"

    def __init__(self) -> None:
        self.folder = tempfile.mkdtemp(prefix="acausal-sweep-")

    @classmethod
    def note(cls, folder: str, index: int | None) -> None:
        """In a worker: run ``index`` starts (None: the run ended)."""
        key = (folder, os.getpid(), threading.get_ident())
        try:
            fd = cls._files.get(key)
            if fd is None:
                with cls._opening:
                    for old in [k for k in cls._files if k[0] != folder]:  # one sweep at a time per process
                        os.close(cls._files.pop(old))
                    fd = cls._files[key] = os.open(os.path.join(folder, f"{key[1]}-{key[2]}"),
                                                   os.O_WRONLY | os.O_CREAT, 0o600)
            os.pwrite(fd, (b"" if index is None else str(index).encode()).rjust(cls._WIDTH), 0)
        except OSError:  # the ledger only guides retries; the run goes on without it
            pass

    def in_progress(self) -> set[int]:
        """The runs the files say were in progress (read once the pool's processes are gone).

        The files go: their processes are gone, and a run in progress in one
        is dealt with now.
        """
        found = set()
        for name in os.listdir(self.folder):
            if name == self.BUNDLE:  # not a worker's file: a replacement pool's tasks may still read it
                continue
            path = os.path.join(self.folder, name)
            try:
                with open(path, "rb") as file:
                    text = file.read().strip()
                os.remove(path)
            except OSError:
                continue
            if text.isdigit():
                found.add(int(text))
        return found

    def remove(self) -> None:
        shutil.rmtree(self.folder, ignore_errors=True)


def _process_pool(workers: int, context=None,
                  bundle: TranslationBundle | None = None) -> concurrent.futures.ProcessPoolExecutor:
    """A process pool of ``workers`` made here (its workers leave Ctrl-C to the parent).

    A forked worker inherits ``bundle`` (see :func:`_worker_init`): nothing
    is copied.  Any other is given nothing at its start and reads the bundle
    from the sweep's file with its first task: a spawned process (or one a
    fork server starts) gets its ``initargs`` through a pipe that the parent
    writes whole before the child reads it, and should the child die while
    starting (an import that fails), CPython (3.11 to 3.13) leaves the write
    of a bundle, far larger than the pipe, blocked for ever.
    """
    context = context or multiprocessing.get_context()
    given = bundle if context.get_start_method() == "fork" else None
    return concurrent.futures.ProcessPoolExecutor(max_workers=workers, mp_context=context,
                                                  initializer=_worker_init, initargs=(given,))


def _terminate(pool: concurrent.futures.ProcessPoolExecutor) -> None:
    """End a process pool made here now, the runs in progress included.

    ``shutdown()`` waits for the running tasks, which may take minutes; their
    processes are terminated first (killed if they do not end within
    :data:`_STOP_GRACE` seconds), and the pool then fails every task it
    holds, as after any death.  No future is cancelled here: the pool would
    then try to fail a cancelled one, and its thread dies with an
    ``InvalidStateError`` (Python 3.11).  The standard library has
    ``terminate_workers()`` only from Python 3.14 on; before, ``_processes``
    is the one handle on the workers.
    """
    processes = list((getattr(pool, "_processes", None) or {}).values())
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join(_STOP_GRACE)
        if process.is_alive():
            process.kill()
            process.join()
    pool.shutdown(wait=True)


class _Serial:
    """Runs tasks in this process, in order."""

    def __init__(self) -> None:
        self.tasks = 0  #: tasks run

    def map_chunks(self, bundle, chunks, outputs, options) -> Iterator[list[RunOutcome]]:
        for chunk in chunks:
            self.tasks += 1
            yield _run_chunk(bundle, chunk, outputs, options)

    def stop(self) -> None:
        pass

    def close(self) -> None:
        pass


class _Pool:
    """A :class:`concurrent.futures.Executor`: tasks submitted at once, gathered as they finish.

    A process pool survives the death of its workers.  A worker process that
    dies (the OOM killer, a signal, a crash in compiled code) breaks a
    :class:`~concurrent.futures.ProcessPoolExecutor`: it terminates its other
    workers and fails every task it holds.  The runs that were in progress
    then (the :class:`_Ledger` names them) are *suspects*.  The pool is
    replaced by a new one of the same size, in which each suspect runs again
    *alone*: a death then is surely its own, the second, and the run is a
    failed row (:data:`WORKER_DIED`).  The other runs of a chunk that held a
    suspect are sent again one by one, the chunks that had not started as
    they were, and the sweep goes on.  Results already gathered are kept
    throughout.

    The bundle reaches each worker process once (see :meth:`_shipped` and
    :func:`_process_pool`); the chunks may be made while the pool runs (an
    iterator), and each is sent as soon as it is made.

    Parameters
    ----------
    executor : concurrent.futures.Executor
    owned : bool
        Made here: shut down here, and its workers terminated on Ctrl-C.
        A replacement pool is always made here (the user's own pool, once
        broken, is only shut down: it cannot run anything any more).
    bundle : TranslationBundle, optional
        The sweep's bundle, which a replacement pool's forked workers inherit.
    """

    def __init__(self, executor: concurrent.futures.Executor, owned: bool,
                 bundle: TranslationBundle | None = None) -> None:
        self.executor = executor
        self.made: list[concurrent.futures.ProcessPoolExecutor] = [executor] if owned else []
        self.futures: dict[concurrent.futures.Future, list[_RunSpec]] = {}  #: in flight, with their chunk
        self.ledger: _Ledger | None = None
        self.alone: _RunSpec | None = None  #: the suspect running alone, if one is
        self.deaths_outside_runs = 0
        self.bundle = bundle
        self.by_value = False  #: the workers could not read the bundle's file: it travels with every task
        self.fresh: Iterator[list[_RunSpec]] | None = None  #: chunks not made yet
        self.tasks = 0  #: tasks submitted, the retries included

    def map_chunks(self, bundle, chunks, outputs, options) -> Iterator[list[RunOutcome]]:
        self.ledger = ledger = _Ledger()
        self.bundle = bundle
        shipped = self._shipped(bundle, ledger)
        self.fresh = iter(chunks)
        waiting: collections.deque[list[_RunSpec]] = collections.deque()  # chunks to send (again)
        suspects: collections.deque[_RunSpec] = collections.deque()  # each to run again alone

        def submit(chunk: list[_RunSpec]) -> None:
            future = self.executor.submit(_run_chunk, bundle if self.by_value else shipped, chunk, outputs,
                                          options, ledger.folder)
            self.futures[future] = chunk
            self.tasks += 1

        try:
            while waiting or suspects or self.futures or self.fresh is not None:
                lost: list[list[_RunSpec]] = []
                broken = not self._send(waiting, suspects, submit)
                if not broken:
                    # while chunks are still being made, only what has finished is gathered, and
                    # the next chunk is made at once; then (or while a suspect runs alone) it waits
                    making = self.fresh is not None and not suspects
                    done, _ = concurrent.futures.wait(self.futures, timeout=0 if making else None,
                                                      return_when=concurrent.futures.FIRST_COMPLETED)
                    for future in done:
                        yield from self._gather(future, lost, waiting, suspects)
                if broken or lost:
                    # a worker died: the pool fails every task it holds, now or in a moment
                    for future in concurrent.futures.wait(self.futures)[0]:
                        yield from self._gather(future, lost, waiting, suspects)
                    failed = self._after_death(lost, waiting, suspects)
                    if failed:
                        yield failed
        finally:
            ledger.remove()

    def _send(self, waiting: collections.deque, suspects: collections.deque, submit) -> bool:
        """Submit what may run now: the next suspect alone, or else every chunk waiting and the
        next chunk made (one at a time, so that finished tasks are gathered in between).

        False if the pool is broken already (a worker died since the last
        look); what was not sent stays in its queue.
        """
        try:
            if suspects:
                if not self.futures:  # nothing else in the pool while a suspect runs
                    submit([suspects[0]])
                    self.alone = suspects.popleft()
            else:
                if self.fresh is not None:
                    chunk = next(self.fresh, None)
                    if chunk is None:
                        self.fresh = None
                    else:
                        waiting.append(chunk)
                while waiting:
                    submit(waiting[0])
                    waiting.popleft()
        except BrokenProcessPool:
            return False
        return True

    def _shipped(self, bundle: TranslationBundle, ledger: _Ledger) -> _Shipped:
        """What the tasks carry of ``bundle``: its digest and its file.

        A forked worker of a pool made here holds it from its start.  Any
        other reads it from the file, once per process, in the sweep's
        private temporary folder (the ledger's); if it cannot (it runs on
        another machine), :meth:`_gather` sends the bundle with every task.
        """
        path = os.path.join(ledger.folder, _Ledger.BUNDLE)
        with open(path, "wb") as file:
            pickle.dump(bundle, file, protocol=pickle.HIGHEST_PROTOCOL)
        return _Shipped(bundle.digest, path)

    def _gather(self, future: concurrent.futures.Future, lost: list, waiting: collections.deque,
                suspects: collections.deque):
        """The outcomes of a finished task; a task lost with its pool goes to ``lost``, one whose
        worker could not read the bundle goes back to its queue."""
        chunk = self.futures.pop(future)
        try:
            outcomes = future.result()
        except BrokenProcessPool:
            lost.append(chunk)
            return
        except _BundleMissing:
            # the user's workers do not see this machine's files: the bundle goes with every task
            self.by_value = True
            if chunk[0] is self.alone:  # a suspect: it runs again alone
                self.alone = None
                suspects.appendleft(chunk[0])
            else:
                waiting.append(chunk)
            return
        except Exception as exc:  # noqa: BLE001 - the task's error becomes its runs' rows
            retry, outcomes = _task_failed(chunk, exc)
            waiting.extend(retry)
        if chunk[0] is self.alone:
            self.alone = None
        if outcomes:
            yield outcomes

    def _after_death(self, lost: list[list[_RunSpec]], waiting: collections.deque,
                     suspects: collections.deque) -> list[RunOutcome]:
        """A worker died and took the tasks ``lost``: who is suspected, what is sent again.

        Returns the rows of the runs given up.
        """
        self._replace()
        lost_runs = {spec.index for chunk in lost for spec in chunk}
        in_progress = self.ledger.in_progress() & lost_runs if self.ledger is not None else set()
        if self.alone is not None:
            # it ran alone: the death is its own, and its second
            spec, self.alone = self.alone, None
            return [_died(spec, "while running it, twice (the second time alone in its process); "
                                "the other runs went on")]
        if not in_progress:
            # a worker died outside any run (reading a task, between runs): everything is
            # sent again, a few times, so that a pool that cannot live does not loop for ever
            self.deaths_outside_runs += 1
            if self.deaths_outside_runs < _DEATHS_OUTSIDE_RUNS:
                waiting.extend(lost)
                return []
            given_up = [spec for chunk in (*lost, *waiting, *(self.fresh or ())) for spec in chunk] + list(suspects)
            waiting.clear()
            suspects.clear()
            self.fresh = None
            return [_died(spec, f"{self.deaths_outside_runs} times outside any run; the runs not done, this "
                                f"one among them, were given up") for spec in given_up]
        for chunk in lost:
            held = [spec for spec in chunk if spec.index in in_progress]
            if not held:  # not started (or finished, its result lost with the pool): as it was
                waiting.append(chunk)
                continue
            suspects.extend(held)
            waiting.extend([spec] for spec in chunk if spec.index not in in_progress)
        return []

    def _replace(self) -> None:
        """A new process pool of the size of the broken one, once the broken one's processes are gone."""
        old = self.executor
        old.shutdown(wait=True)  # broken, it has terminated its workers: this waits until they end
        workers = getattr(old, "_max_workers", None) or os.cpu_count() or 1
        # its forked workers inherit the bundle too (the others read its file)
        self.executor = _process_pool(workers, getattr(old, "_mp_context", None), self.bundle)
        self.made.append(self.executor)

    def stop(self) -> None:
        """Ctrl-C: the workers of the pools made here are terminated.

        In a pool given by the user, the tasks not started are cancelled and
        the runs in progress finish there (ending them would break the
        user's pool).
        """
        if self.executor not in self.made:
            for future in self.futures:
                future.cancel()
        for pool in self.made:
            _terminate(pool)
        if self.ledger is not None:
            self.ledger.remove()

    def close(self) -> None:
        for pool in self.made:
            pool.shutdown(wait=True, cancel_futures=True)
        if self.ledger is not None:
            self.ledger.remove()


def _shipped(bundle: TranslationBundle) -> TranslationBundle:
    """The task that holds the bundle on a Dask worker (the runs' tasks depend on it)."""
    return bundle


class _Dask:
    """A ``dask.distributed.Client``: the bundle travels to each worker once, as a task's result.

    Dask itself survives the loss of a worker (the task runs on another, and
    ``KilledWorker`` after ``distributed.scheduler.allowed-failures``
    deaths); a task that raises has its runs retried one by one, and fails
    them one by one (:func:`_task_failed`), as the process pool does.
    """

    def __init__(self, client, owned: bool) -> None:
        self.client = client
        self.owned = owned  #: connected here (to a scheduler address): closed here
        self.futures: dict[str, tuple[Any, list[_RunSpec]]] = {}  #: in flight by key, with their chunk
        self.tasks = 0  #: tasks submitted, the retries included

    def map_chunks(self, bundle, chunks, outputs, options) -> Iterator[list[RunOutcome]]:
        from dask.distributed import as_completed

        # a task, not scattered data: when every worker holding it dies, Dask computes it
        # again, where scattered data would be lost and the tasks needing it cancelled
        shipped = self.client.submit(_shipped, bundle, pure=False)

        def submit(chunk: list[_RunSpec]):
            future = self.client.submit(_run_chunk, shipped, chunk, outputs, options, pure=False)
            self.futures[future.key] = (future, chunk)
            self.tasks += 1
            return future

        finished = as_completed([submit(chunk) for chunk in chunks])
        try:
            for future in finished:
                _, chunk = self.futures.pop(future.key)
                try:
                    outcomes = future.result()
                except Exception as exc:  # noqa: BLE001 - the task's error becomes its runs' rows
                    retry, outcomes = _task_failed(chunk, exc)
                    for again in retry:
                        finished.add(submit(again))
                if outcomes:
                    yield outcomes
        finally:
            self.stop()

    def stop(self) -> None:
        """Tasks not finished are cancelled; one running on a worker ends with its run."""
        if self.futures:
            self.client.cancel([future for future, _ in self.futures.values()])
            self.futures.clear()

    def close(self) -> None:
        self.stop()
        if self.owned:
            self.client.close()


def _executor_for(executor, workers: int | None, bundle: TranslationBundle | None = None):
    """The runner (``map_chunks``, ``stop``, ``close``, ``tasks``) for the ``executor`` argument of
    :func:`sweep`; a pool made here gives ``bundle`` to each of its workers at their start."""
    if executor == "serial":
        return _Serial()
    if executor is None:
        return _Pool(_process_pool(workers or os.cpu_count() or 1, bundle=bundle), owned=True, bundle=bundle)
    if isinstance(executor, str):
        if not executor.startswith(("tcp://", "tls://", "ucx://", "inproc://")):
            raise SettingError(f"unknown executor {executor!r}",
                               hint="give None (a process pool), 'serial', a scheduler address "
                                    "'tcp://host:port', a dask Client or a concurrent.futures Executor")
        try:
            from dask.distributed import Client
        except ImportError:
            raise SettingError("a scheduler address needs dask.distributed",
                               hint="pip install 'acausal[dask]'") from None
        return _Dask(Client(executor), owned=True)
    if _is_dask_client(executor):
        return _Dask(executor, owned=False)
    if isinstance(executor, concurrent.futures.Executor):
        return _Pool(executor, owned=False)
    raise SettingError(f"executor must be None, 'serial', a scheduler address, a dask Client or a "
                       f"concurrent.futures.Executor, not {type(executor).__name__}")


# -- progress -------------------------------------------------------------------------------------


class _SweepLine(TerminalProgress):
    """The terminal line of a sweep: ``sweep of M  [####......]  40%  16/40 runs``."""

    def __call__(self, done: int, total: int) -> None:  # type: ignore[override]
        share = done / total if total else 1.0
        filled = int(round(share * self.width))
        self.stream.write(f"\r{self.name}  [{'#' * filled}{'.' * (self.width - filled)}]  "
                          f"{share * 100:3.0f}%  {done}/{total} runs")
        self.stream.flush()
        self.drawn = True


# -- the result -----------------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class SweepResult:
    """The runs of a sweep, gathered.

    Attributes
    ----------
    parameters : pandas.DataFrame
        One row per run (index ``run``), one column per parameter given.
    table : pandas.DataFrame
        One row per run: ``run``, each parameter, ``status``, ``message``,
        ``error_type``, ``events`` (events recorded), ``seconds``, and for
        each output ``<name>:final``, ``<name>:min``, ``<name>:max``.
    outputs : tuple of str
        The outputs summarised.
    runs : tuple of RunOutcome
        Every run, in sweep order, with its (compact) result.
    units : dict
        Units of the outputs and parameters ('' when none).
    compiled_in_workers : int
        Systems compiled in the workers (discrete states the first run did not
        visit; once per worker process).
    translated_in_workers : int
        Runs the workers translated (values that change the equations).
    seconds : float
        Wall time of the sweep, translation included.
    workers : int or None
        Workers of the executor, when known.
    setup_seconds : float
        Wall time before the first task was sent: the translation, the runs
        made here (the first and the pilot runs) and the bundle.  The part of
        :attr:`seconds` that more workers do not shorten.
    tasks : int
        Tasks sent to the executor (chunks of runs), the retries included.
    """

    parameters: Any
    table: Any
    outputs: tuple[str, ...]
    runs: tuple[RunOutcome, ...]
    units: dict
    compiled_in_workers: int = 0
    translated_in_workers: int = 0
    seconds: float = 0.0
    workers: int | None = None
    setup_seconds: float = 0.0
    tasks: int = 0

    @property
    def failed(self) -> tuple[RunOutcome, ...]:
        """The runs that did not end as the model asked (status not 0 or 1)."""
        return tuple(r for r in self.runs if r.status not in (0, 1))

    def __repr__(self) -> str:
        """The runs, how many ended as asked and how many failed, the parameters and the outputs."""
        failed = self.failed
        ok = len(self.runs) - len(failed)
        seconds = f" in {self.seconds:.3g} s" if self.seconds else ""
        lines = [f"SweepResult: {len(self.runs)} run{'' if len(self.runs) == 1 else 's'}{seconds}, "
                 f"{ok} ok, {len(failed)} failed"]
        swept = []
        for name in self.parameters.columns:
            values = self.parameters[name].dropna()
            if len(values):
                # parameter values are inputs, printed as given (never rounded to 0)
                swept.append(f"{name} {float(values.min()):.6g} .. {float(values.max()):.6g} "
                             f"({values.nunique()} value{'' if values.nunique() == 1 else 's'})")
        lines.append(f"  parameters: {'; '.join(swept) or 'none'}")
        lines.append(f"  outputs: {', '.join(self.outputs) or 'none'}")
        if failed:
            shown = ", ".join(f"{r.index} ({r.error_type or f'status {r.status}'})" for r in failed[:5])
            lines.append(f"  failed runs: {shown}{', ...' if len(failed) > 5 else ''}")
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        """The summary and the head of :attr:`table`.

        An output's value below the solver tolerance (the runs' ``rtol``
        times the largest magnitude of that output over the sweep, the
        absolute tolerance the integrator works to) is shown as 0 — a stuck
        speed of ``-1e-10`` is a 0 — in what is printed only: :attr:`table`
        keeps the values.
        """
        import html

        import pandas as pd

        rows = 10
        head = self.table.head(rows).copy()
        given = [r.result.stats.get("rtol") for r in self.runs if r.result is not None]
        rtol = max((float(v) for v in given if v), default=1e-6)  # simulate's default rtol
        for name in self.outputs:
            columns = [c for c in (f"{name}:final", f"{name}:min", f"{name}:max") if c in head.columns]
            if not columns:
                continue
            values = np.abs(self.table[columns].to_numpy(dtype=float))
            finite = values[np.isfinite(values)]
            if not finite.size:
                continue
            zero = rtol * float(finite.max())
            for column in columns:
                head[column] = head[column].where(~(head[column].abs() <= zero), 0.0)
        summary = html.escape(repr(self)).replace("\n", "<br>")
        more = f"<p>... {len(self.table) - len(head)} more runs</p>" if len(self.table) > len(head) else ""
        with pd.option_context("display.max_colwidth", 80):
            table = head.to_html(index=False, float_format=lambda v: f"{v:.6g}", na_rep="")
        return f"<div><p>{summary}</p>{table}{more}</div>"

    def series(self, name: str, points: int = 501):
        """The time series of ``name``: a DataFrame, time as index, one column per run.

        The common grid is ``points`` equally spaced instants from the
        earliest start to the latest stop time of the runs; each run is
        interpolated linearly on it (at an event instant, the value after the
        event), NaN after a failed run's last time.
        """
        import pandas as pd

        results = [r.result for r in self.runs if r.result is not None and name in r.result.columns]
        if not results:
            raise KeyError(f"no run holds {name!r}; the sweep kept {', '.join(self.outputs) or 'nothing'}")
        start = min(float(r.time[0]) for r in results)
        stop = max(float(r.time[-1]) for r in results)
        grid = np.linspace(start, stop, points)
        columns = {}
        for outcome in self.runs:
            result = outcome.result
            if result is None or name not in result.columns or len(result.time) == 0:
                columns[outcome.index] = np.full(points, np.nan)
                continue
            values = np.interp(grid, result.time, result.columns[name])
            values[(grid > result.time[-1]) | (grid < result.time[0])] = np.nan
            columns[outcome.index] = values
        frame = pd.DataFrame(columns, index=pd.Index(grid, name="time"))
        frame.columns.name = "run"
        return frame

    def plot_envelope(self, name: str, runs: int = 5, points: int = 501):
        """The band between the runs' smallest and largest ``name``, with ``runs`` of them drawn.

        Returns a matplotlib Figure.
        """
        from matplotlib.figure import Figure

        frame = self.series(name, points)
        figure = Figure(figsize=(7, 4))
        axes = figure.add_subplot()
        time = frame.index.to_numpy()
        axes.fill_between(time, frame.min(axis=1).to_numpy(), frame.max(axis=1).to_numpy(), alpha=0.3,
                          label=f"min-max of {frame.shape[1]} runs")
        shown = np.unique(np.linspace(0, frame.shape[1] - 1, min(runs, frame.shape[1])).astype(int))
        for k in shown:
            run = frame.columns[k]
            axes.plot(time, frame[run].to_numpy(), lw=1, label=f"run {run}: {_values_text(self.runs[k].values)}")
        axes.set_xlabel("time [s]")
        unit = self.units.get(name, "")
        axes.set_ylabel(f"{name} [{unit}]" if unit else name)
        axes.legend(fontsize="small")
        axes.grid(True, alpha=0.3)
        figure.tight_layout()
        return figure

    def plot_scalar(self, output: str, against: str):
        """A scalar result against a swept parameter: ``output`` is a column of :attr:`table`
        (``'<name>:final'``, ``':min'``, ``':max'``, ``'events'``, ``'seconds'``) or a
        name (its final value).  Failed runs are drawn hollow.  Returns a matplotlib Figure."""
        from matplotlib.figure import Figure

        column = output if output in self.table.columns else f"{output}:final"
        if column not in self.table.columns:
            raise KeyError(f"the table has no column {output!r}")
        if against not in self.table.columns:
            raise KeyError(f"{against!r} was not swept; swept: {', '.join(self.parameters.columns)}")
        figure = Figure(figsize=(6, 4))
        axes = figure.add_subplot()
        ok = self.table["status"].isin((0, 1))
        order = self.table.sort_values(against)
        good = order[ok.loc[order.index]]
        axes.plot(good[against], good[column], "o-", ms=4, label="runs")
        bad = order[~ok.loc[order.index]]
        if len(bad):
            axes.plot(bad[against], bad[column], "o", mfc="none", label="failed runs")
        unit_x = self.units.get(against, "")
        name = column.rpartition(":")[0] if ":" in column else column
        unit_y = self.units.get(name, "")
        axes.set_xlabel(f"{against} [{unit_x}]" if unit_x else against)
        axes.set_ylabel(f"{column} [{unit_y}]" if unit_y else column)
        axes.grid(True, alpha=0.3)
        axes.legend(fontsize="small")
        figure.tight_layout()
        return figure


def _values_text(values: Mapping[str, float]) -> str:
    return ", ".join(f"{n} = {v:.4g}" for n, v in values.items())


def _table(outcomes: Sequence[RunOutcome], names: Sequence[str], outputs: Sequence[str]):
    import pandas as pd

    rows = []
    for outcome in outcomes:
        row: dict = {"run": outcome.index, **{n: outcome.values.get(n, np.nan) for n in names},
                     "status": outcome.status, "message": outcome.message, "error_type": outcome.error_type,
                     "events": len(outcome.result.events) if outcome.result is not None else 0,
                     "seconds": outcome.seconds}
        for name in outputs:
            column = None if outcome.result is None else outcome.result.columns.get(name)
            empty = column is None or len(column) == 0
            row[f"{name}:final"] = np.nan if empty else float(column[-1])
            row[f"{name}:min"] = np.nan if empty else float(np.min(column))
            row[f"{name}:max"] = np.nan if empty else float(np.max(column))
        rows.append(row)
    # the columns named, so that the table of an interrupted sweep with no run finished has them
    columns = ["run", *names, "status", "message", "error_type", "events", "seconds",
               *(f"{name}:{what}" for name in outputs for what in ("final", "min", "max"))]
    return pd.DataFrame(rows, columns=columns)


# -- the sweep ------------------------------------------------------------------------------------


class SweepInterrupted(SimulationInterrupted):
    """Ctrl-C during a sweep: the workers were stopped, and the runs that finished are kept.

    A :class:`~acausal.errors.SimulationInterrupted`, hence a
    :class:`KeyboardInterrupt` (so it still ends a script and is not caught by
    ``except Exception``), as :func:`~acausal.runtime.simulate.simulate`
    raises on Ctrl-C.

    Attributes
    ----------
    result : SweepResult
        The runs that finished before the interrupt, in sweep order (each
        keeps its index: :attr:`SweepResult.runs` and the ``run`` column of
        its table skip those that did not finish).
    total : int
        The runs the sweep had.
    """

    def __init__(self, message: str, hint: str | None = None, result: "SweepResult | None" = None,
                 total: int = 0) -> None:
        super().__init__(message, hint, result)
        self.total = total

    def with_result(self, result) -> "SweepInterrupted":
        """The same interrupt carrying ``result``."""
        new = SweepInterrupted(self.message, self.hint, result, self.total)
        new.__cause__, new.__context__, new.__traceback__ = self.__cause__, self.__context__, self.__traceback__
        return new


def _check_budgets(timeout: float | None, max_steps: int | None) -> None:
    """The budgets of every run, checked once here rather than failing every run."""
    if timeout is not None:
        try:
            bad = math.isnan(float(timeout)) or float(timeout) <= 0
        except (TypeError, ValueError):
            bad = True
        if bad:
            raise SettingError(f"timeout = {timeout!r} must be a number of seconds > 0")
    if max_steps is not None and (isinstance(max_steps, bool) or not isinstance(max_steps, (int, np.integer))
                                  or max_steps < 1):
        raise SettingError(f"max_steps = {max_steps!r} must be an integer >= 1")


def sweep(model: Component, parameters: Mapping[str, Sequence[float]] | Sequence[Mapping[str, float]],
          outputs: Sequence[str] | None = None, *, executor: Any = None, samples: int | None = None,
          seed: int | None = None, progress: "bool | Callable[[int, int, RunOutcome], object] | None" = None,
          chunk_size: int | None = None, workers: int | None = None, sampling: str = "lhs",
          pilot: int = 1, timeout: float | None = None, max_steps: int | None = None,
          start: Mapping[str, float] | None = None, **simulate_options) -> SweepResult:
    """Simulate ``model`` for many parameter sets, translated once.

    Parameters
    ----------
    model : Model instance
    parameters : mapping or sequence of mappings
        ``name -> values`` (a full factorial grid), a list of ``name ->
        value`` runs, or with ``samples`` ``name -> (low, high)`` (see
        :func:`parameter_sets`).  Numeric parameters, and start values
        named ``<variable>.start`` (``{"J1.w.start": [1, 2, 3]}``): those of
        states and fixed variables are parameters of the compiled code, so
        a start value swept costs no translation either.
    outputs : sequence of str, optional
        The variables kept and summarised; the model computes only what they
        need (as ``simulate(..., outputs=...)``).  Default: every column.
    executor : optional
        None: a :class:`concurrent.futures.ProcessPoolExecutor` of
        ``workers`` (default ``os.cpu_count()``) processes, made and closed
        here.  A :class:`concurrent.futures.Executor` or a
        ``dask.distributed.Client`` is used as it is; a string
        ``"tcp://host:port"`` connects a Client to that scheduler;
        ``"serial"`` runs every run in this process.
    samples, seed : int, optional
        Draw ``samples`` points (Latin hypercube by default, ``sampling``).
    progress : bool or callable, optional
        ``progress(finished, total, outcome)`` after every run; True draws a
        line on standard error, None (default) draws it only when standard
        error is a terminal outside CI and pytest.
    chunk_size : int, optional
        Runs per task (default: about four tasks per worker).
    workers : int, optional
        Size of the default process pool.
    sampling : {'lhs', 'uniform'}
    pilot : int
        Runs made here before the others are shipped (the first, then
        runs spread over the sweep): the discrete states they reach are
        compiled once, here, rather than in every worker that reaches them.
    timeout : float, optional
        Seconds of wall time each run may take, in the worker (see
        :func:`~acausal.runtime.simulate.simulate`): a run over its budget
        stops with a ``SolverError`` row saying where its time went, and
        the others go on.
    max_steps : int, optional
        Integrator steps each run may take, likewise.
    start : mapping, optional
        Start values by variable name (``{"J1.w": 3.0}``), the same for every
        run (as :func:`~acausal.runtime.simulate.simulate`'s ``start``); a
        start value that varies is a name ``<variable>.start`` of
        ``parameters``.
    **simulate_options
        Passed to :func:`~acausal.runtime.simulate.simulate` for every run
        (``stop_time``, ``rtol``, ``method``, ...).

    Returns
    -------
    SweepResult
        Runs that fail are rows with their status and reason; the others
        are not affected.

    Raises
    ------
    SettingError
        For settings out of range, before anything runs.
    SweepInterrupted
        On Ctrl-C (a ``KeyboardInterrupt``): the workers of a pool made here
        are terminated, the tasks not started are cancelled, and
        ``exc.result`` is the :class:`SweepResult` of the runs that finished.

    Notes
    -----
    The model is translated once with the first parameter set, which is run
    here (with ``pilot - 1`` more): the discrete states they visit are
    compiled here and shipped; a state first reached by another run is
    compiled by the worker that reaches it, once per worker process (counted
    in :attr:`SweepResult.compiled_in_workers`).

    A worker process of a process pool that dies (killed by the OOM killer
    or a signal) costs the sweep no finished run: the pool is replaced and
    the runs that had not come back are sent again; the runs that were in
    progress then run again alone, and one that kills its worker a second
    time is a failed row with ``error_type`` ``'WorkerDied'``.

    Sizing: the setup ``s`` (:attr:`SweepResult.setup_seconds`) is serial;
    then ``N`` runs of ``r`` seconds go in ``T = ceil(N / c)`` tasks of
    ``c = chunk_size`` runs, each costing a worker ``c r + o``, where ``o``,
    the overhead per task, is about a millisecond on one machine (the bundle
    is not part of it).  ``W`` workers take about ``s + ceil(T / W) (c r +
    o)``, while this process, which resolves each run's values as the
    workers run, keeps up (see ``python -m acausal.tools.sweep_bench``).
    """
    t_start = _time.perf_counter()
    runs = parameter_sets(parameters, samples=samples, seed=seed, method=sampling)
    if not runs:
        raise SettingError("the sweep has no runs")
    names = list(dict.fromkeys(n for run in runs for n in run))
    options = dict(simulate_options)
    for refused in ("parameters", "outputs", "cache", "progress"):
        if refused in options:
            raise SettingError(f"sweep() sets {refused}= itself")
    _check_budgets(timeout, max_steps)
    options.update({k: v for k, v in (("timeout", timeout), ("max_steps", max_steps)) if v is not None})
    redundant = options.pop("redundant_constraints", "relax")
    total = len(runs)
    reporter = _progress(progress, type(model).__name__)
    outcomes: dict[int, RunOutcome] = {}

    def report(outcome: RunOutcome) -> None:
        outcomes[outcome.index] = outcome
        if reporter is not None:
            reporter(len(outcomes), total, outcome)

    first: int | None = None
    bundle: TranslationBundle | None = None
    runner = None
    n_workers = None
    setup_seconds = 0.0
    try:
        # the first run whose values resolve is translated and run here
        for index, values in enumerate(runs):
            if _resolved(model, index, values, start, report) is not None:
                first = index
                break
        if first is not None:
            # this process's translation of the model is reused (a second sweep compiles
            # nothing); what it compiles keeps its stages, which the bundle ships
            translation = translate(model, outputs, parameters=with_start_values(runs[first], start),
                                    redundant_constraints=redundant, disk_cache=False)
            bundle_flat = translation.flat
            report(_run_here(translation, first, runs[first], outputs, options))
            bundle = translation.export()
            rest = list(range(first + 1, total))

            def spec_of(index: int) -> _RunSpec | None:
                return _spec(model, bundle_flat, index, runs[index], start, report)

            if pilot > 1 and rest:
                # more runs here, spread over the sweep: the discrete states they reach are
                # compiled once, here, and shipped, instead of once in every worker
                chosen = [rest[k] for k in sorted(set(np.linspace(0, len(rest) - 1,
                                                                  min(pilot - 1, len(rest))).astype(int)))]
                for index in chosen:
                    spec = spec_of(index)
                    if spec is not None:
                        report(dataclasses.replace(_run_one(bundle, spec, outputs, options), compiled=0))
                _, base, store = _worker_state(bundle)
                bundle = bundle.extended(store.payloads)
                # this process holds the extended bundle too, with the store its runs used: a
                # worker forked from it starts with the code they loaded; and the entry of the
                # bundle before stays, so that the next sweep of the model (whose translation
                # exports that bundle again) ships what this one's runs compiled as well
                _WORKER_STATE[bundle.digest] = _Held(bundle, base, store)
                rest = [index for index in rest if index not in set(chosen)]
            # every other run's values are resolved (without flattening equations) as its chunk
            # is made, while the workers run the chunks made before: invalid ones fail as
            # simulate() would raise, the others travel as plain numbers
            specs = (spec for spec in map(spec_of, rest) if spec is not None)
            head = next(specs, None)
            if head is not None:
                setup_seconds = _time.perf_counter() - t_start
                runner = _executor_for(executor, workers, bundle)
                n_workers = _worker_count(executor, runner, workers)
                size = chunk_size or max(1, math.ceil(len(rest) / (4 * (n_workers or 1))))
                chunks = _chunks(itertools.chain([head], specs), size)
                for chunk_outcomes in runner.map_chunks(bundle, chunks, outputs, options):
                    for outcome in chunk_outcomes:
                        report(outcome)
                runner.close()  # here, so that an interrupt while it closes still keeps every run
        tasks = getattr(runner, "tasks", 0)
        runner = None
        if isinstance(reporter, _Reporter):
            reporter.close()
        return _gathered(outcomes, names, outputs, bundle, first, t_start, n_workers, setup_seconds, tasks)
    except KeyboardInterrupt:
        # Ctrl-C (or the SIGTERM of ``acausal sweep``): the workers stop now, what finished is kept
        tasks = getattr(runner, "tasks", 0)
        if runner is not None:
            runner.stop()
            runner = None
        if isinstance(reporter, _Reporter):
            reporter.close()
        partial = _gathered(outcomes, names, outputs, bundle, first, t_start, n_workers, setup_seconds, tasks)
        raise SweepInterrupted(f"the sweep was interrupted: {len(outcomes)} of {total} runs finished",
                               hint="exc.result holds the runs that finished", result=partial,
                               total=total) from None
    finally:
        if runner is not None:  # another error: the tasks not started are dropped
            runner.close()


def _resolved(model: Component, index: int, values: dict, start: Mapping[str, float] | None,
              report: Callable[[RunOutcome], None]) -> tuple | None:
    """Run ``index``'s flat parameters and variables (:func:`_flat_values`), or None after
    reporting its row when its values are invalid (as ``simulate()`` would raise)."""
    try:
        return _flat_values(model, with_start_values(values, start) or {})
    except AcausalError as exc:
        report(RunOutcome(index, values, -1, exc.message, type(exc).__name__, None, 0.0))
        return None


def _spec(model: Component, bundle_flat: FlatModel, index: int, values: dict, start: Mapping[str, float] | None,
          report: Callable[[RunOutcome], None]) -> _RunSpec | None:
    """Run ``index`` as a task carries it, or None after reporting its row (values invalid)."""
    resolved = _resolved(model, index, values, start, report)
    if resolved is None:
        return None
    flat_parameters, variables = resolved
    by_name = {p.name: p.value for p in flat_parameters}
    try:  # start values travel as numbers, the variables only when they differ otherwise
        starts, other = tunable_starts_of(bundle_flat, variables, with_start_values(values, start) or {})
    except AcausalError as exc:
        report(RunOutcome(index, values, -1, exc.message, type(exc).__name__, None, 0.0))
        return None
    return _RunSpec(index, values, tuple(by_name[p.name] for p in bundle_flat.parameters),
                    variables if other else None, () if other else starts)


def _chunks(specs: Iterator[_RunSpec], size: int) -> Iterator[list[_RunSpec]]:
    """``specs`` in chunks of ``size``, each made when it is asked for."""
    while chunk := list(itertools.islice(specs, size)):
        yield chunk


def _gathered(outcomes: Mapping[int, RunOutcome], names: Sequence[str], outputs: Sequence[str] | None,
              bundle: TranslationBundle | None, first: int | None, t_start: float,
              n_workers: int | None, setup_seconds: float = 0.0, tasks: int = 0) -> SweepResult:
    """The :class:`SweepResult` of the runs in ``outcomes`` (every run, or those that finished)."""
    import pandas as pd

    ordered = tuple(outcomes[k] for k in sorted(outcomes))
    kept = _kept_outputs(ordered, outputs)
    table = _table(ordered, names, kept)
    parameter_table = pd.DataFrame([{n: o.values.get(n, np.nan) for n in names} for o in ordered],
                                   index=pd.Index([o.index for o in ordered], name="run"), columns=list(names))
    return SweepResult(parameter_table, table, tuple(kept), ordered, _units(ordered, bundle),
                       sum(o.compiled for o in ordered if o.index != first),
                       sum(o.translated for o in ordered), _time.perf_counter() - t_start, n_workers,
                       setup_seconds, tasks)


def _run_here(translation: Translation, index: int, values: dict, outputs, options: dict) -> RunOutcome:
    """The first run, in this process, on the translation made for it."""
    t0 = _time.perf_counter()
    try:
        result = simulate(translation, progress=False, **options)
    except Exception as exc:  # noqa: BLE001 - a failed run is a row of the table
        return RunOutcome(index, values, -1, str(getattr(exc, "message", None) or exc), type(exc).__name__,
                          None, _time.perf_counter() - t0)
    return RunOutcome(index, values, result.status, result.message,
                      type(result.error).__name__ if result.error is not None else "",
                      _compact(result, outputs), _time.perf_counter() - t0)


def _worker_count(executor, runner, workers: int | None) -> int | None:
    if executor == "serial":
        return 1
    if executor is None:
        return workers or os.cpu_count() or 1
    if isinstance(runner, _Dask):
        try:
            return len(runner.client.scheduler_info().get("workers", {})) or None
        except Exception:  # noqa: BLE001 - the count only sizes the chunks
            return None
    return getattr(executor, "_max_workers", None)


def _kept_outputs(outcomes: Sequence[RunOutcome], outputs: Sequence[str] | None) -> list[str]:
    if outputs is not None:
        return list(outputs)
    for outcome in outcomes:
        if outcome.result is not None:
            return [n for n in outcome.result.columns
                    if outcome.result.column_info.get(n) is None or outcome.result.column_info[n].kind
                    not in ("boolean", "integer")]
    return []


def _units(outcomes: Sequence[RunOutcome], bundle: TranslationBundle | None) -> dict:
    units: dict[str, str] = {}
    if bundle is not None:
        flat: FlatModel = bundle.unpacked()[0]
        units.update({p.name: p.unit or "" for p in (*flat.parameters, *flat.start_parameters)})
    for outcome in outcomes:
        if outcome.result is not None:
            for name, info in outcome.result.column_info.items():
                units.setdefault(name, getattr(info, "unit", "") or "")
    return units


class _Reporter:
    """Progress of a sweep: the user's callback, or the terminal line."""

    def __init__(self, callback, line: _SweepLine | None) -> None:
        self.callback = callback
        self.line = line

    def __call__(self, finished: int, total: int, outcome: RunOutcome) -> None:
        if self.callback is not None:
            self.callback(finished, total, outcome)
        if self.line is not None:
            self.line(finished, total)

    def close(self) -> None:
        if self.line is not None:
            self.line.close()


def _progress(progress, name: str) -> _Reporter | None:
    if callable(progress) and not isinstance(progress, bool):
        return _Reporter(progress, None)
    # the same rule as a single run's progress line (a terminal, outside CI and pytest)
    if progress_reporter(progress, name) is None:
        return None
    return _Reporter(None, _SweepLine(f"sweep of {name}"))


# -- the command ----------------------------------------------------------------------------------


def _parse_values(text: str, sampled: bool) -> tuple[str, list[float]]:
    """``NAME=a:b:n`` (n values from a to b), ``NAME=a,b,c``, or with samples ``NAME=low:high``."""
    name, sep, spec = text.partition("=")
    if not sep or not name.strip():
        raise SettingError(f"--param {text!r}: write NAME=a:b:n, NAME=a,b,c or (with --samples) NAME=low:high")
    try:
        if ":" in spec:
            parts = [float(p) for p in spec.split(":")]
            if sampled and len(parts) == 2:
                return name.strip(), parts
            if len(parts) != 3 or parts[2] < 1 or parts[2] != int(parts[2]):
                raise ValueError
            return name.strip(), [float(v) for v in np.linspace(parts[0], parts[1], int(parts[2]))]
        values = [float(p) for p in spec.split(",") if p.strip()]
        if not values or (sampled and len(values) != 2):
            raise ValueError
        return name.strip(), values
    except ValueError:
        raise SettingError(f"--param {text!r}: write NAME=a:b:n (n >= 1 values from a to b), NAME=a,b,c, "
                           f"or with --samples NAME=low:high") from None


class _StopSignals:
    """SIGINT and SIGTERM as Ctrl-C while ``acausal sweep`` runs; the previous handlers after.

    While armed, the first signal raises :class:`KeyboardInterrupt` in the
    main thread, so that :func:`sweep` stops its workers and keeps what
    finished.  Later signals, and any after :meth:`disarm` (the table is
    being written), are only noted: the cleanup and the writing finish, and
    the command then exits with the status of the first signal.
    """

    def __init__(self) -> None:
        self.received: int | None = None
        self.armed = True
        self.previous: dict[int, Any] = {}

    def __enter__(self) -> "_StopSignals":
        if threading.current_thread() is threading.main_thread():  # handlers live in the main thread
            for signum in (signal.SIGINT, signal.SIGTERM):
                # a signal ignored stays ignored (``nohup``, a background job's SIGINT)
                if signal.getsignal(signum) is not signal.SIG_IGN:
                    self.previous[signum] = signal.signal(signum, self._handle)
        return self

    def __exit__(self, *exc_info) -> None:
        for signum, handler in self.previous.items():
            if handler is not None:  # None: set outside Python, and cannot be set back from here
                signal.signal(signum, handler)

    def _handle(self, signum: int, frame) -> None:
        first = self.received is None
        if first:
            self.received = signum
        if first and self.armed:
            raise KeyboardInterrupt

    def disarm(self) -> None:
        self.armed = False

    @property
    def status(self) -> int:
        """The exit status of a process ended by the signal received (130 for SIGINT, 143 for SIGTERM)."""
        return 128 + int(self.received if self.received is not None else signal.SIGINT)

    @property
    def name(self) -> str:
        return signal.Signals(self.received if self.received is not None else signal.SIGINT).name


def _write_outputs(result: SweepResult, out: Path, outputs: Sequence[str]) -> tuple[list[str], list[str]]:
    """Write ``runs.csv`` and each output's series and envelope into ``out``: ``(written, warnings)``."""
    out.mkdir(parents=True, exist_ok=True)
    result.table.to_csv(out / "runs.csv", index=False)
    written, warnings = ["runs.csv"], []
    for name in outputs:
        safe = name.replace("/", "_")
        try:
            result.series(name).to_csv(out / f"series_{safe}.csv")
            result.plot_envelope(name).savefig(out / f"envelope_{safe}.png", dpi=100)
            written += [f"series_{safe}.csv", f"envelope_{safe}.png"]
        except KeyError as exc:
            warnings.append(exc.args[0])
    return written, warnings


def main_sweep(argv: list[str]) -> int:
    """``acausal sweep FILE.py[:Model] --param NAME=a:b:n ... --out DIR``.

    Writes ``DIR/runs.csv`` (:attr:`SweepResult.table`), and for each
    ``--output`` ``DIR/series_<name>.csv`` and ``DIR/envelope_<name>.png``;
    prints a summary.  Returns 0 when every run succeeded, 1 when some
    failed, 2 for a usage error.  SIGINT (Ctrl-C) and SIGTERM (sent by
    ``timeout``, systemd, SLURM, a CI cancellation) stop the workers, the
    runs that finished are written as above, one line on standard error
    says how many and where, and the status is 130 for SIGINT, 143 for
    SIGTERM.
    """
    parser = argparse.ArgumentParser(prog="acausal sweep", description="Simulate a model for many parameter sets.")
    parser.add_argument("model", help="FILE.py[:Model]")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=a:b:n|a,b,c",
                        help="values of a parameter (repeat for a grid)")
    parser.add_argument("--samples", type=int, help="draw N Latin-hypercube points (--param NAME=low:high)")
    parser.add_argument("--seed", type=int, help="seed of the samples")
    parser.add_argument("--output", action="append", default=None, metavar="NAME", help="a variable to keep")
    parser.add_argument("--scheduler", help="a dask scheduler address, tcp://host:port")
    parser.add_argument("--workers", type=int, help="processes of the local pool (default: the CPUs)")
    parser.add_argument("--chunk", type=int, help="runs per task")
    parser.add_argument("--stop-time", type=float, help="stop time of every run")
    parser.add_argument("--timeout", type=float, metavar="SECONDS",
                        help="wall time each run may take; a run over it fails, the others go on")
    parser.add_argument("--max-steps", type=int, metavar="N", help="integrator steps each run may take")
    parser.add_argument("--out", required=True, help="folder for runs.csv, series and plots")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0) and 2
    out = Path(args.out)
    with _StopSignals() as signals:
        try:
            if not args.param:
                raise SettingError("give at least one --param NAME=a:b:n")
            grid = dict(_parse_values(p, args.samples is not None) for p in args.param)
            model_class = load_model_class(args.model)
            options = {} if args.stop_time is None else {"stop_time": args.stop_time}
            result = sweep(model_class(), grid, args.output, executor=args.scheduler, samples=args.samples,
                           seed=args.seed, chunk_size=args.chunk, workers=args.workers, timeout=args.timeout,
                           max_steps=args.max_steps, **options)
        except (AcausalError, CommandError) as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
        except KeyboardInterrupt as exc:
            signals.disarm()
            return _interrupted(signals, getattr(exc, "result", None), getattr(exc, "total", None), out,
                                args.output or ())
        signals.disarm()
        written, warnings = _write_outputs(result, out, args.output or ())
        if signals.received is not None:  # it came while the table was written: all runs finished
            return _interrupted(signals, result, len(result.runs), out, None)
    for warning in warnings:
        print(f"warning: {warning}", file=sys.stderr)
    failed = result.failed
    print(f"{len(result.runs)} runs of {model_class.__name__} in {result.seconds:.2f} s"
          f"{f' on {result.workers} workers' if result.workers else ''}: {len(result.runs) - len(failed)} "
          f"succeeded, {len(failed)} failed")
    if result.compiled_in_workers or result.translated_in_workers:
        print(f"  compiled in workers: {result.compiled_in_workers} systems; "
              f"translated in workers: {result.translated_in_workers} runs")
    for outcome in failed[:10]:
        print(f"  run {outcome.index} ({_values_text(outcome.values)}): {outcome.error_type or 'failed'}: "
              f"{outcome.message}")
    if len(failed) > 10:
        print(f"  ... and {len(failed) - 10} more (see runs.csv)")
    for name in args.output or ():
        column = f"{name}:final"
        if column in result.table:
            values = result.table[column]
            print(f"  {name} at the end: min {values.min():.6g}, max {values.max():.6g}")
    print(f"wrote {', '.join(written)} to {out}")
    return 1 if failed else 0


def _interrupted(signals: _StopSignals, result: SweepResult | None, total: int | None, out: Path,
                 outputs: Sequence[str] | None) -> int:
    """Write what an interrupted sweep finished (``outputs`` None: written already), say so in one
    line, and return the signal's status."""
    what = f"acausal sweep: interrupted ({signals.name})"
    if result is None:  # before the sweep began (loading the model file)
        print(f"{what} before any run; nothing written", file=sys.stderr)
        return signals.status
    try:
        if outputs is not None:
            _write_outputs(result, out, outputs)
    except OSError as exc:
        print(f"{what}: {len(result.runs)} of {total} runs finished, but {out} cannot be written: "
              f"{exc.strerror or exc}", file=sys.stderr)
        return signals.status
    print(f"{what}: {len(result.runs)} of {total} runs finished; their table is {out / 'runs.csv'}",
          file=sys.stderr)
    return signals.status
