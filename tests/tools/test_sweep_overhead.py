"""Sweeps at scale (issue 29): the bundle reaches each worker once, and tasks carry only the runs' values.

The bundle of a CoupledClutches sweep is about 460 kB pickled; a task's runs
are a few hundred bytes each.  The tests count how often the bundle is
pickled in this process (a ``copyreg`` reducer: every pickler of this process
consults it, the pools' queues included) and how often the workers take it
in (forked workers inherit the module patched here), and compare the runs
with those of a serial sweep, number for number.
"""

from __future__ import annotations

import concurrent.futures
import copyreg
import io
import multiprocessing
import os
import pickle

import numpy as np
import pytest

from acausal.compiler.translate import TranslationBundle
from acausal.tools import sweep as module
from examples.coupled_clutches import CoupledClutches

OUTPUTS = ["J1.w", "J4.w"]
#: 12 runs: the first is run here, 11 are shipped
GRID = {"J1.J": [0.8, 1.0, 1.2, 1.4], "sin1.amplitude": [8.0, 10.0, 12.0]}
WORKERS = 2


def _start_methods() -> list:
    return [m for m in ("fork", "spawn") if m in multiprocessing.get_all_start_methods()]


@pytest.fixture(scope="module")
def model():
    return CoupledClutches()


@pytest.fixture(scope="module")
def serial(model):
    """The sweep in this process: the reference every pool must give number for number."""
    return module.sweep(model, GRID, OUTPUTS, executor="serial")


@pytest.fixture
def pickled(monkeypatch):
    """The bundles pickled in this process, one entry per pickling."""
    bundles: list[TranslationBundle] = []

    def reduce(bundle: TranslationBundle):
        bundles.append(bundle)
        return TranslationBundle, (bundle.model, bundle.demand, bundle.redundant_constraints, bundle.payloads,
                                   bundle.digest)

    monkeypatch.setitem(copyreg.dispatch_table, TranslationBundle, reduce)
    return bundles


def _size(obj) -> int:
    """Bytes of ``obj`` pickled, past the counting reducer of ``pickled``."""
    pickler = pickle.Pickler(buffer := io.BytesIO(), protocol=pickle.HIGHEST_PROTOCOL)
    pickler.dispatch_table = {}
    pickler.dump(obj)
    return len(buffer.getvalue())


@pytest.fixture
def taken(monkeypatch, tmp_path):
    """Notes, in files, which processes took a bundle in (held it, or read it from its file).

    The module's state is emptied first, so that what this process held from
    an earlier sweep does not reach forked workers.
    """
    monkeypatch.setattr(module, "_WORKER_STATE", {})
    hold, read = module._hold, module._read_shipped

    def noted(name: str, function):
        def wrapper(*args):
            with open(tmp_path / name, "a") as file:
                file.write(f"{os.getpid()}\n")
            return function(*args)
        return wrapper

    monkeypatch.setattr(module, "_hold", noted("held", hold))
    monkeypatch.setattr(module, "_read_shipped", noted("read", read))

    def pids(name: str) -> list[int]:
        path = tmp_path / name
        return [int(line) for line in path.read_text().split()] if path.exists() else []

    return pids


class _Recording(concurrent.futures.ProcessPoolExecutor):
    """A process pool that notes what each task carries: its first argument and its pickled size."""

    made: list["_Recording"] = []

    def __init__(self, *args, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.initargs = kwargs.get("initargs", ())
        self.carried: list = []
        self.sizes: list[int] = []
        _Recording.made.append(self)

    def submit(self, fn, /, *args, **kwargs):
        self.carried.append(args[0])
        self.sizes.append(_size((fn, args, kwargs)))
        return super().submit(fn, *args, **kwargs)


def _same_runs(result, reference) -> None:
    assert len(result.runs) == len(reference.runs) == 12
    for outcome, expected in zip(result.runs, reference.runs):
        assert outcome.index == expected.index and outcome.status == expected.status == 0, outcome.message
        assert np.array_equal(outcome.result.time, expected.result.time), outcome.index
        for name in OUTPUTS:
            assert np.array_equal(outcome.result[name], expected.result[name]), (outcome.index, name)
        assert len(outcome.result.events) == len(expected.result.events)


@pytest.mark.parametrize("start_method", _start_methods())
def test_the_default_pool_sends_the_bundle_once_not_per_task(model, serial, pickled, taken, monkeypatch,
                                                             start_method):
    """The pool sweep() makes: a task carries the bundle's digest and file, never the bundle.

    Forked workers inherit the bundle at their start (each holds it once,
    none reads the file); spawned ones read the file with their first task,
    and their start data holds no bundle (a pipe the parent writes whole: a
    child dying while it starts would leave that write blocked for ever).
    The bundle is pickled once, into its file; sending it with every task
    pickled it once per task: 6 times here.
    """
    real = multiprocessing.get_context
    monkeypatch.setattr(multiprocessing, "get_context", lambda method=None: real(method or start_method))
    monkeypatch.setattr(_Recording, "made", [])
    monkeypatch.setattr(concurrent.futures, "ProcessPoolExecutor", _Recording)
    result = module.sweep(model, GRID, OUTPUTS, workers=WORKERS, chunk_size=2)
    _same_runs(result, serial)
    (pool,) = _Recording.made
    assert result.tasks == len(pool.carried) == 6  # 11 shipped runs, 2 a task
    (bundle,) = pickled  # into its file, once
    assert all(isinstance(what, module._Shipped) and what.digest == bundle.digest and what.path
               for what in pool.carried)
    # a task is its runs' values: a few hundred bytes a run, against the ~460 kB of the bundle
    assert max(pool.sizes) < 4000 < _size(bundle) / 50
    if start_method == "fork":
        (given,) = pool.initargs
        assert given.digest == bundle.digest
        held = taken("held")  # each worker held it once, at its start
        assert len(held) == len(set(held)) == WORKERS and os.getpid() not in held
        assert taken("read") == []
    else:
        assert pool.initargs == (None,)


def test_a_pool_of_the_user_reads_the_bundle_once_per_worker_from_a_file(model, serial, pickled, taken,
                                                                        monkeypatch):
    """A pool given to sweep() started before the bundle existed: its workers read it from a file, once each."""
    if "fork" not in multiprocessing.get_all_start_methods():
        pytest.skip("the workers' reads are counted in forked processes")
    monkeypatch.setattr(_Recording, "made", [])
    with _Recording(WORKERS, mp_context=multiprocessing.get_context("fork")) as pool:
        result = module.sweep(model, GRID, OUTPUTS, executor=pool, chunk_size=1)
    _same_runs(result, serial)
    assert result.tasks == len(pool.carried) == 11
    assert all(isinstance(what, module._Shipped) and what.path for what in pool.carried)
    assert len(pickled) == 1  # written to its file once
    reads = taken("read")
    assert 1 <= len(reads) == len(set(reads)) <= WORKERS and os.getpid() not in reads
    assert max(pool.sizes) < 4000
    assert not os.path.exists(pool.carried[0].path)  # the file went with the sweep's folder


def _elsewhere() -> None:
    """The initializer of a pool whose workers do not see this machine's files (another host)."""

    def missing(shipped):
        raise module._BundleMissing(f"{shipped.path}: no such file on this host")

    module._read_shipped = missing


def test_workers_that_cannot_read_the_file_get_the_bundle_with_every_task(model, serial, monkeypatch):
    """The fallback for a pool of the user's on other machines: the bundle travels per task, as before."""
    if "fork" not in multiprocessing.get_all_start_methods():
        pytest.skip("the initializer patches forked processes")
    monkeypatch.setattr(module, "_WORKER_STATE", {})
    monkeypatch.setattr(_Recording, "made", [])
    with _Recording(WORKERS, mp_context=multiprocessing.get_context("fork"), initializer=_elsewhere) as pool:
        result = module.sweep(model, GRID, OUTPUTS, executor=pool, chunk_size=2)
    _same_runs(result, serial)
    kinds = [type(what).__name__ for what in pool.carried]
    # the first tasks named the file and came back refused; they and the others then carried the bundle
    assert kinds[0] == "_Shipped" and "TranslationBundle" in kinds
    assert kinds.count("TranslationBundle") == 6 and result.tasks == len(kinds)


def test_a_pool_of_threads_shares_one_reading_of_the_bundle(model, serial, taken):
    """Threads of this process read the bundle's file once between them, and a second sweep not at all.

    In the second sweep both threads at once close the files the first left
    in the ledger (a race that once failed a run with a ``KeyError``).
    """
    with concurrent.futures.ThreadPoolExecutor(WORKERS) as pool:
        for _ in range(2):
            result = module.sweep(model, GRID, OUTPUTS, executor=pool, chunk_size=1)
            _same_runs(result, serial)
    assert taken("read") == [os.getpid()]


def test_bundles_of_one_model_with_other_outputs_are_other_bundles():
    """A process keeps what it read of a bundle by its digest (a forked worker inherits it):
    a bundle of the same model and systems with another output demand, or another choice for
    redundant constraints, must not pass for it (a sweep of other outputs after a sweep in
    threads once got the first sweep's columns: 'clutch1.tau' is not a variable)."""
    same = dict(model=b"flat model", payloads={"mode (0,)": {"source": "..."}})
    first = TranslationBundle(demand=frozenset({"J1.w", "J4.w"}), redundant_constraints="relax", **same)
    assert TranslationBundle(demand=frozenset({"J4.w", "J1.w"}), redundant_constraints="relax",
                             **same).digest == first.digest
    others = [TranslationBundle(demand=frozenset({"J1.w", "clutch1.tau"}), redundant_constraints="relax", **same),
              TranslationBundle(demand=None, redundant_constraints="relax", **same),
              TranslationBundle(demand=frozenset({"J1.w", "J4.w"}), redundant_constraints="error", **same)]
    assert len({first.digest, *(b.digest for b in others)}) == 4
