"""Sweeps that survive (issue 23): a worker process killed under a run, a run that never ends, SIGINT and SIGTERM.

Every sweep here runs in a subprocess with a timeout of its own, so that a
regression fails instead of hanging.  The model is a decay x' = -k x, x(0) = 1,
whose rate passes through a Python function (a sympy Function with ``_imp_``,
as tables are called from generated code): x(1) = exp(-k) in closed form, and
the function does to its own process what the test's environment asks.
"""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

MODEL = '''
"""x' = -rate(k) x, x(0) = 1: x(1) = exp(-k).  rate(k) is k, and on the first call with a k in a process:

SWEEP_TEST_PIDS=folder  creates '<k>_<pid>' there (which process ran which run);
SWEEP_TEST_DELAY=s      sleeps s seconds (a run that takes time);
SWEEP_TEST_KILL=value   with k = value, kills its own process with SIGKILL, as the OOM killer does.
"""
import os
import signal
import time

import numpy as np
import sympy as sp

from acausal import Eq, Experiment, Model, Parameter, Variable, der

_SEEN = set()


class rate(sp.Function):
    nargs = 1

    @staticmethod
    def _imp_(k):
        values = np.atleast_1d(np.asarray(k, dtype=float))
        kill = os.environ.get("SWEEP_TEST_KILL")
        if kill is not None and np.any(values == float(kill)):
            os.kill(os.getpid(), signal.SIGKILL)
        if float(values[0]) not in _SEEN:
            _SEEN.add(float(values[0]))
            folder = os.environ.get("SWEEP_TEST_PIDS")
            if folder:
                open(os.path.join(folder, f"{float(values[0]):g}_{os.getpid()}"), "w").close()
            time.sleep(float(os.environ.get("SWEEP_TEST_DELAY", "0")))
        return k


class Decay(Model):
    experiment = Experiment(stop_time=1.0)
    k = Parameter(1.0)
    x = Variable(start=1.0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), -rate(self.k) * self.x)]
'''


@pytest.fixture
def folder(tmp_path: Path):
    """The model file, a folder for the pid notes and a TMPDIR of the sweep's own (its ledger goes there).

    Afterwards, a worker process the test started that is still alive (a
    regression: before issue 23 was fixed, SIGTERM left the workers of
    ``acausal sweep`` running) is killed.
    """
    (tmp_path / "decay.py").write_text(MODEL)
    (tmp_path / "pids").mkdir()
    (tmp_path / "tmp").mkdir()
    yield tmp_path
    for pid in _workers(tmp_path):
        if _alive(pid) and any(word in " ".join(_command_line(pid)) for word in ("acausal", "script.py")):
            os.kill(pid, signal.SIGKILL)


def _environment(folder: Path, **knobs: str) -> dict:
    env = dict(os.environ, MPLBACKEND="Agg", TMPDIR=str(folder / "tmp"), SWEEP_TEST_PIDS=str(folder / "pids"))
    env["PYTHONPATH"] = os.pathsep.join([str(REPO), str(folder), env.get("PYTHONPATH", "")])
    env.update({f"SWEEP_TEST_{name.upper()}": value for name, value in knobs.items()})
    return env


def _sweep(folder: Path, *args: str, timeout: float = 60, **knobs: str) -> subprocess.CompletedProcess:
    """``acausal sweep decay.py ARGS --out out`` in a subprocess."""
    return subprocess.run([sys.executable, "-m", "acausal", "sweep", "decay.py", *args, "--out", "out"],
                          cwd=folder, env=_environment(folder, **knobs), capture_output=True, text=True,
                          timeout=timeout)


def _script(folder: Path, code: str, timeout: float = 90, **knobs: str) -> dict:
    """Run ``code`` (which prints one JSON line last) in a subprocess; its JSON."""
    (folder / "script.py").write_text(textwrap.dedent(code))
    done = subprocess.run([sys.executable, "script.py"], cwd=folder, env=_environment(folder, **knobs),
                          capture_output=True, text=True, timeout=timeout)
    assert done.returncode == 0, done.stderr[-3000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


def _table(path: Path) -> list[dict]:
    import pandas as pd

    return pd.read_csv(path).to_dict("records")


def _closed_form(row: dict) -> None:
    assert row["status"] == 0, row
    assert row["x:final"] == pytest.approx(math.exp(-row["k"]), rel=1e-4, abs=1e-6), row


def _workers(folder: Path, parent: int | None = None) -> set[int]:
    """The processes that computed a run (from the pid notes), the parent's excepted."""
    return {int(name.rpartition("_")[2]) for name in os.listdir(folder / "pids")} - {parent}


def _command_line(pid: int) -> list[str]:
    try:
        return Path(f"/proc/{pid}/cmdline").read_text().split("\0")
    except OSError:
        return []


def _alive(pid: int) -> bool:
    try:
        import psutil
    except ImportError:
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        return True
    try:
        return psutil.Process(pid).status() != psutil.STATUS_ZOMBIE
    except psutil.NoSuchProcess:
        return False


def test_a_run_that_kills_its_worker_fails_alone_and_the_sweep_goes_on(folder):
    """k = 7 kills the worker process running it (SIGKILL); it shares a chunk of three with k = 5 and 6."""
    done = _sweep(folder, "--param", "k=1:10:10", "--output", "x", "--workers", "2", "--chunk", "3", kill="7")
    assert "Traceback" not in done.stderr, done.stderr
    assert done.returncode == 1, done.stderr  # one run failed
    assert "10 runs of Decay" in done.stdout and "9 succeeded, 1 failed" in done.stdout
    rows = _table(folder / "out" / "runs.csv")
    assert [row["k"] for row in rows] == [float(k) for k in range(1, 11)]
    killer = rows[6]
    assert killer["status"] == -1 and killer["error_type"] == "WorkerDied"
    assert "worker process died" in killer["message"] and "twice" in killer["message"]
    for row in rows[:6] + rows[7:]:  # its chunk's neighbours (k = 5, 6) included
        _closed_form(row)
    assert (folder / "out" / "series_x.csv").is_file()
    # it killed two processes: the pool was made again, twice, and the runs went on in new workers
    assert len(_workers(folder)) >= 4
    assert os.listdir(folder / "tmp") == []  # the ledger of runs in progress is gone


def test_a_run_that_never_ends_is_stopped_by_its_budget(folder):
    """k = 1e9 is stiff: RK45 needs ~1e9 steps.  --timeout and --max-steps end that run, not the sweep."""
    start = time.monotonic()
    done = _sweep(folder, "--param", "k=1,2,3,1e9", "--workers", "2", "--timeout", "2")
    assert time.monotonic() - start < 30
    assert done.returncode == 1, done.stderr
    rows = _table(folder / "out" / "runs.csv")
    for row in rows[:3]:
        _closed_form(row)
    assert rows[3]["status"] == -1 and rows[3]["error_type"] == "SolverError"
    assert "time budget of 2 s" in rows[3]["message"]
    assert 2.0 <= rows[3]["seconds"] < 10

    done = _sweep(folder, "--param", "k=1,1e9", "--workers", "1", "--max-steps", "2000")
    assert done.returncode == 1, done.stderr
    rows = _table(folder / "out" / "runs.csv")
    _closed_form(rows[0])
    assert rows[1]["status"] == -1 and "budget of 2000 steps" in rows[1]["message"]

    refused = _sweep(folder, "--param", "k=1,2", "--timeout", "0")
    assert refused.returncode == 2 and "timeout" in refused.stderr


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")
@pytest.mark.parametrize("signum, status", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_a_signal_writes_the_finished_runs_and_stops_every_worker(folder, signum, status):
    """SIGTERM (timeout, systemd, SLURM, CI) or SIGINT after the first runs: their table, one line, no process."""
    process = subprocess.Popen(
        [sys.executable, "-m", "acausal", "sweep", "decay.py", "--param", "k=1:12:12", "--output", "x",
         "--workers", "2", "--chunk", "1", "--out", "out"],
        cwd=folder, env=_environment(folder, delay="0.4"), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        text=True, preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + 60
        while len(os.listdir(folder / "pids")) < 5:  # runs 1-3 done, 4 and 5 running (0.4 s each)
            assert process.poll() is None, process.communicate()
            assert time.monotonic() < deadline, "the sweep did not start"
            time.sleep(0.02)
        workers = _workers(folder, process.pid)
        sent = time.monotonic()
        process.send_signal(signum)
        # a worker left running would hold the pipes open: communicate() would wait for it
        out, err = process.communicate(timeout=30)
        stopped = time.monotonic() - sent
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    assert process.returncode == status, err
    assert "Traceback" not in err, err
    assert stopped < 10
    assert workers and not [pid for pid in workers if _alive(pid)]
    rows = _table(folder / "out" / "runs.csv")
    assert 1 <= len(rows) < 12
    for row in rows:
        _closed_form(row)
    line = err.strip().splitlines()[-1]
    name = signal.Signals(signum).name
    assert line == f"acausal sweep: interrupted ({name}): {len(rows)} of 12 runs finished; their table is " \
                   f"{Path('out') / 'runs.csv'}", err
    assert (folder / "out" / "series_x.csv").is_file()
    assert os.listdir(folder / "tmp") == []


def test_ctrl_c_in_the_api_raises_with_the_runs_that_finished(folder):
    """sweep() on Ctrl-C: a KeyboardInterrupt (SimulationInterrupted) carrying the partial SweepResult."""
    found = _script(folder, """
        import json, multiprocessing, os, signal, time
        from acausal.errors import SimulationInterrupted
        from acausal.tools.sweep import SweepResult, sweep
        from decay import Decay

        signal.signal(signal.SIGINT, signal.default_int_handler)  # if it started ignored (a background job)

        def progress(finished, total, outcome):
            if finished == 3:
                os.kill(os.getpid(), signal.SIGINT)  # Ctrl-C

        start = time.monotonic()
        try:
            sweep(Decay(), {"k": [float(k) for k in range(1, 13)]}, ["x"], workers=2, chunk_size=1,
                  progress=progress)
            print(json.dumps({"interrupt": False}))
        except KeyboardInterrupt as exc:
            result = exc.result
            print(json.dumps({"interrupt": isinstance(exc, SimulationInterrupted), "total": exc.total,
                              "message": exc.message, "sweep": isinstance(result, SweepResult),
                              "rows": result.table.to_dict("records"), "runs": [o.index for o in result.runs],
                              "children": len(multiprocessing.active_children()),
                              "seconds": time.monotonic() - start}))
    """, delay="0.3")
    assert found["interrupt"] and found["sweep"] and found["total"] == 12
    assert found["runs"] == [0, 1, 2] and [row["run"] for row in found["rows"]] == [0, 1, 2]
    assert found["message"] == "the sweep was interrupted: 3 of 12 runs finished"
    for row in found["rows"]:
        _closed_form(row)
    assert found["children"] == 0 and found["seconds"] < 10  # the workers were terminated, not waited for
    assert not [pid for pid in _workers(folder) if _alive(pid)]


def test_the_pools_that_replace_a_broken_one_get_the_bundle_as_the_first_did(folder):
    """k = 5 kills its worker, twice: the two pools made after get the bundle as the first did (inherited
    by forked workers, else read from the sweep's file); no task, before or after, carries the bundle."""
    found = _script(folder, """
        import concurrent.futures, json, multiprocessing
        from acausal.tools.sweep import sweep
        from decay import Decay

        carried, given = [], []

        class Recording(concurrent.futures.ProcessPoolExecutor):
            def __init__(self, *args, **kwargs):
                super().__init__(*args, **kwargs)
                given.append(getattr(kwargs.get("initargs", (None,))[0], "digest", None))

            def submit(self, fn, *args, **kwargs):
                carried.append([type(args[0]).__name__, args[0].digest])
                return super().submit(fn, *args, **kwargs)

        concurrent.futures.ProcessPoolExecutor = Recording  # the pools sweep() makes
        result = sweep(Decay(), {"k": [float(k) for k in range(1, 9)]}, ["x"], workers=2, chunk_size=1)
        print(json.dumps({"rows": result.table.to_dict("records"), "carried": carried, "given": given,
                          "tasks": result.tasks, "fork": multiprocessing.get_start_method() == "fork"}))
    """, kill="5")
    rows = found["rows"]
    assert rows[4]["k"] == 5.0 and rows[4]["error_type"] == "WorkerDied"
    for row in rows[:4] + rows[5:]:
        _closed_form(row)
    assert len(found["given"]) == 3  # the first pool and two replacements
    assert {kind for kind, _ in found["carried"]} == {"_Shipped"}
    digests = {digest for _, digest in found["carried"]}
    assert set(found["given"]) == (digests if found["fork"] else {None})
    assert found["tasks"] == len(found["carried"]) > 7  # the lost runs were sent again


def test_a_broken_pool_of_the_user_is_replaced(folder):
    """A ProcessPoolExecutor given to sweep() breaks when k = 5 kills its worker; a pool made here goes on."""
    found = _script(folder, """
        import json
        from concurrent.futures import ProcessPoolExecutor
        from acausal.tools.sweep import sweep
        from decay import Decay

        with ProcessPoolExecutor(2) as pool:
            result = sweep(Decay(), {"k": [float(k) for k in range(1, 9)]}, ["x"], executor=pool)
        print(json.dumps(result.table.to_dict("records")))
    """, kill="5")
    assert [row["error_type"] for row in found if row["status"] != 0] == ["WorkerDied"]
    assert found[4]["k"] == 5.0 and found[4]["status"] == -1
    for row in found[:4] + found[5:]:
        _closed_form(row)


def test_a_task_that_raises_fails_only_its_own_run(folder, monkeypatch):
    """A task's own error (not a run's, which is a row already): its chunk is retried one run at a time."""
    from concurrent.futures import ThreadPoolExecutor

    from acausal.tools import sweep as module
    from acausal.tools.modelfile import load_model_class

    run_chunk = module._run_chunk

    def failing(bundle, specs, *args, **kwargs):
        if any(spec.values["k"] == 3.0 for spec in specs):
            raise RuntimeError("the task of k = 3 failed")
        return run_chunk(bundle, specs, *args, **kwargs)

    monkeypatch.setattr(module, "_run_chunk", failing)
    decay = load_model_class(f"{folder / 'decay.py'}:Decay")
    with ThreadPoolExecutor(2) as pool:
        result = module.sweep(decay(), {"k": [1.0, 2.0, 3.0, 4.0, 5.0]}, ["x"], executor=pool, chunk_size=2)
    rows = result.table.to_dict("records")
    assert rows[2]["status"] == -1 and rows[2]["error_type"] == "RuntimeError"
    assert rows[2]["message"] == "the task of k = 3 failed"
    for row in rows[:2] + rows[3:]:  # k = 2 shared its chunk
        _closed_form(row)


def test_a_dask_task_that_fails_is_a_row_and_the_others_go_on(folder):
    """On Dask a worker killed too often is KilledWorker: the same WorkerDied row, every other run kept."""
    pytest.importorskip("dask.distributed", reason="dask[distributed] is not installed")
    found = _script(folder, """
        import json
        import dask
        from dask import distributed
        from acausal.tools.sweep import sweep
        from decay import Decay

        if __name__ == "__main__":
            # KilledWorker after two deaths (not four), and a worker holds only the task it runs, so
            # that no other task is blamed for the deaths
            with dask.config.set({"distributed.scheduler.allowed-failures": 1,
                                  "distributed.scheduler.worker-saturation": 1.0}), \\
                    distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                             dashboard_address=None) as cluster, \\
                    distributed.Client(cluster) as client:
                result = sweep(Decay(), {"k": [float(k) for k in range(1, 9)]}, ["x"], executor=client,
                               chunk_size=3)
            print(json.dumps(result.table.to_dict("records")))
    """, kill="5", timeout=120)
    assert [row["k"] for row in found] == [float(k) for k in range(1, 9)]
    killer = found[4]
    assert killer["status"] == -1 and killer["error_type"] == "WorkerDied" and "KilledWorker" in killer["message"]
    for row in found[:4] + found[5:]:
        _closed_form(row)
