"""Bench of :func:`acausal.tools.sweep.sweep`: speed-up, overhead per task, and sizing.

``python -m acausal.tools.sweep_bench [--out FILE.png] [--no-dask]`` runs a
40-run sweep of the CoupledClutches example (``J1.J`` times the driving
sine's amplitude) in this process (``executor="serial"``), on 1 and on 2
workers of a process pool started beforehand (a pool of the user's), of the
pool :func:`~acausal.tools.sweep.sweep` makes itself (the default), and of a
Dask ``LocalCluster`` (when dask is installed), and prints:

* the wall time of the sweep and its setup (translation, the runs made here,
  the bundle: :attr:`~acausal.tools.sweep.SweepResult.setup_seconds`), and
  the speed-up of 2 workers over 1 of the same kind;
* the time of the runs in the workers (their own clocks) per run;
* the overhead per task: ``(workers x (wall - setup) - the shipped runs'
  own time) / tasks``, i.e. the time a worker spends per task not running:
  shipping, scheduling and gathering it, but also the pool's start and the
  workers idle at the end;
* the per-task overhead proper, by difference: the same runs on one worker
  of the default pool as one task each and as a single task,
  ``(wall(1 run a task) - wall(all in one)) / (tasks - 1)``; the target is
  10 ms at most;
* a sizing note: the speed-up the measured setup ``s``, run time ``r`` and
  overhead ``o`` give on W workers (see :func:`predicted_speedup`).

The user's pools are started before the clock starts (a pool is started once
per session, not per sweep), and one warm-up sweep precedes each timed one.
Every discrete state the grid reaches is compiled once before any timing, so
that no configuration compiles in its workers (the last column shows it).
"""

from __future__ import annotations

import argparse
import concurrent.futures
import math
import sys
import time as _time
from pathlib import Path

import numpy as np

__all__ = ["main", "measure", "per_task_overhead", "predicted_speedup"]

GRID = {"J1.J": [float(v) for v in np.linspace(0.8, 1.6, 8)], "sin1.amplitude": [8.0, 9.0, 10.0, 11.0, 12.0]}
OUTPUTS = ["J1.w", "J4.w"]
#: the most a task may cost a worker beyond its runs (issue 29)
TARGET_OVERHEAD = 0.010
#: runs made in this process before the others are shipped (the first and one pilot run)
PILOT = 2


def _model():
    root = Path(__file__).resolve().parents[2]
    if str(root) not in sys.path:
        sys.path.insert(0, str(root))
    from examples.coupled_clutches import CoupledClutches

    return CoupledClutches()


def measure(executor, workers: int, chunk_size: int | None = None, pilot: int = PILOT,
            warm_up: bool = True) -> dict:
    """One timed 40-run sweep on ``executor`` (after an untimed warm-up one).

    ``executor`` None: the pool the sweep makes, of ``workers`` processes.

    Returns
    -------
    dict
        ``wall``, ``setup`` (seconds), ``run_mean`` (seconds of a shipped
        run), ``tasks``, ``shipped`` (runs), ``overhead_per_task`` (seconds,
        see the module's docstring), ``parent_per_run`` (wall time per
        shipped run neither in the setup nor in a run: meaningful for
        ``"serial"``, where it is this process's share of each run), and the
        counts ``runs``, ``failed``, ``compiled_in_workers``.
    """
    from .sweep import sweep

    model = _model()
    options = dict(executor=executor, chunk_size=chunk_size, pilot=pilot,
                   workers=workers if executor is None else None)
    if warm_up:
        sweep(model, GRID, OUTPUTS, **options)
    order: list[int] = []
    cpu0 = _cpu_seconds()
    t0 = _time.perf_counter()
    result = sweep(model, GRID, OUTPUTS, progress=lambda done, total, outcome: order.append(outcome.index),
                   **options)
    wall = _time.perf_counter() - t0
    cpu = _cpu_seconds() - cpu0
    # every value of the grid is valid: the first ``pilot`` runs reported were made here
    here = set(order[:pilot])
    shipped = [o for o in result.runs if o.index not in here]
    run_seconds = sum(o.seconds for o in shipped)
    shipped_wall = max(wall - result.setup_seconds, 1e-9)
    tasks = max(result.tasks, 1)
    return {"workers": workers, "wall": wall, "setup": result.setup_seconds, "runs": len(result.runs),
            "failed": len(result.failed), "shipped": len(shipped), "run_mean": run_seconds / max(len(shipped), 1),
            "tasks": result.tasks, "overhead_per_task": max(workers * shipped_wall - run_seconds, 0.0) / tasks,
            "parent_per_run": max(shipped_wall - run_seconds, 0.0) / max(len(shipped), 1),
            "compiled_in_workers": result.compiled_in_workers, "cpu": cpu}


def _cpu_seconds() -> float:
    """CPU seconds of this process and of its children that ended (a pool the sweep made is
    shut down, its workers joined, before :func:`~acausal.tools.sweep.sweep` returns)."""
    import resource

    return sum(usage.ru_utime + usage.ru_stime for usage in (resource.getrusage(resource.RUSAGE_SELF),
                                                             resource.getrusage(resource.RUSAGE_CHILDREN)))


def per_task_overhead(repeats: int = 3) -> dict:
    """The per-task overhead of the default pool by difference, on one worker.

    The same shipped runs go as one task each and as one task for all,
    alternately; the best of ``repeats`` timed sweeps of each (after a
    warm-up) are compared: ``(wall(one run a task) - wall(one task)) /
    (tasks - 1)``.  ``cpu_overhead`` is the same difference of the CPU time
    of this process and the pool's workers: what a task costs in work, which
    other jobs on a shared machine disturb less than the wall time.
    """
    measure(None, 1, chunk_size=1)  # the warm-up (this process's translation, the compiled code)
    many, one = [], []
    for _ in range(repeats):
        many.append(measure(None, 1, chunk_size=1, warm_up=False))
        one.append(measure(None, 1, chunk_size=len(_runs()), warm_up=False))
    tasks = max(many[0]["tasks"] - one[0]["tasks"], 1)
    best_many, best_one = min(many, key=lambda m: m["wall"]), min(one, key=lambda m: m["wall"])
    return {"overhead": (best_many["wall"] - best_one["wall"]) / tasks,
            "cpu_overhead": (min(m["cpu"] for m in many) - min(m["cpu"] for m in one)) / tasks,
            "many": best_many, "one": best_one}


def _runs() -> list:
    from .sweep import parameter_sets

    return parameter_sets(GRID)


def predicted_speedup(workers: int, runs: int, run: float, overhead: float, setup: float,
                      chunk: int | None = None) -> float:
    """The speed-up of ``workers`` workers over one, for ``runs`` shipped runs of ``run`` seconds.

    A sweep is its setup ``s`` (serial: translation, the runs made here, the
    bundle) and then ``T = ceil(N / c)`` tasks of ``c`` runs, each costing a
    worker ``c r + o``; the W workers take them ``ceil(T / W)`` deep::

        t(W) = s + ceil(T / W) (c r + o),    S(W) = t(1) / t(W)

    (Amdahl's law with the setup as the serial part, the per-task overhead
    ``o`` paid once per chunk, and the rounding of tasks to workers).  ``c``
    defaults to the sweep's own choice for each W, about four tasks per
    worker.  This holds while the parent keeps the workers fed: it resolves
    each run's values in ``p`` seconds while they run, so ``W p < r + o / c``.
    """
    def wall(w: int) -> float:
        c = chunk or max(1, math.ceil(runs / (4 * w)))
        return setup + math.ceil(math.ceil(runs / c) / w) * (c * run + overhead)

    return wall(1) / wall(workers)


def _sizing(serial: dict, pool_rows: list[dict], overhead: float) -> str:
    """The sizing note, with the measured figures."""
    one = next(row for row in pool_rows if row["workers"] == 1)
    s, r, o, p = one["setup"], one["run_mean"], overhead, serial["parent_per_run"]
    lines = [f"sizing: a sweep of N runs of r s each on W workers, in tasks of c runs, takes about "
             f"t(W) = s + ceil(ceil(N/c)/W) (c r + o), so W workers give S(W) = t(1)/t(W) over one "
             f"(Amdahl's law: the setup s is the serial part, the per-task overhead o is paid once per chunk).  "
             f"Measured here: s = {s * 1e3:.0f} ms (translation, {PILOT} runs made here, the bundle), "
             f"r = {r * 1e3:.1f} ms, o = {max(o, 0.0) * 1e3:.1f} ms; sweep() picks c for about 4 tasks a worker."]
    for row in pool_rows:
        if row["workers"] > 1:
            lines.append(f"  {row['workers']} workers, N = {row['shipped']}: predicted "
                         f"{predicted_speedup(row['workers'], row['shipped'], r, max(o, 0.0), s):.2f}x, "
                         f"measured {one['wall'] / row['wall']:.2f}x (a shared {_cores()}-core machine)")
    needed = next((n for n in range(40, 100001, 20) if predicted_speedup(16, n, r, max(o, 0.0), s) >= 12), None)
    lines.append(f"  16 workers: {predicted_speedup(16, one['shipped'], r, max(o, 0.0), s):.1f}x for these "
                 f"{one['shipped']} runs, {predicted_speedup(16, 1000, r, max(o, 0.0), s):.1f}x for 1000; "
                 f">= 12x from N = {needed} runs (where the setup is under about 2 % of the serial work)"
                 if needed else "  16 workers: below 12x for any N with these figures")
    # the parent's share of each run (resolving its values, gathering its result) runs while
    # the workers do: it bounds the workers it keeps fed, and takes W p / r of a core
    fed = r / p if p > 0 else math.inf
    lines.append(f"  the parent's share of a run, p = {p * 1e3:.2f} ms (its values resolved, its result gathered), "
                 f"overlaps the workers' runs: it keeps up to r/p = {fed:.0f} workers fed, and takes W p/r of a "
                 f"core ({16 * p / r * 100 if r else 0:.0f} % of one for W = 16)")
    return "\n".join(lines)


def _cores() -> int:
    import os

    return os.cpu_count() or 1


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m acausal.tools.sweep_bench")
    parser.add_argument("--out", default="sweep_bench.png", help="PNG of the wall times")
    parser.add_argument("--no-dask", action="store_true", help="skip the Dask LocalCluster")
    args = parser.parse_args(argv)
    from .sweep import sweep

    # Every discrete state the grid reaches is compiled here first (untimed), so that
    # every timed sweep ships them all: no configuration pays for compiling in its
    # workers, which would flatter the speed-up of the ones measured after it.
    sweep(_model(), GRID, OUTPUTS, executor="serial")
    serial = measure("serial", 1)
    rows = [("serial", serial)]
    for workers in (1, 2):
        with concurrent.futures.ProcessPoolExecutor(max_workers=workers) as pool:
            rows.append(("process pool", measure(pool, workers)))
    default_rows = [measure(None, workers) for workers in (1, 2)]
    rows += [("default pool", row) for row in default_rows]
    if not args.no_dask:
        try:
            from dask.distributed import Client, LocalCluster
        except ImportError:
            print("dask.distributed is not installed: the Dask rows are skipped", file=sys.stderr)
        else:
            for workers in (1, 2):
                with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, Client(cluster) as client:
                    rows.append(("dask LocalCluster", measure(client, workers)))
    print(f"{'executor':<18} {'workers':>7} {'wall s':>7} {'speed-up':>8} {'run ms':>7} {'tasks':>5} "
          f"{'overhead/task ms':>16} {'compiled in workers':>19} {'setup s':>7}")
    single = {}
    for name, row in rows:
        if row["workers"] == 1:
            single[name] = row["wall"]
        speedup = single.get(name, row["wall"]) / row["wall"]
        overhead = "-" if name == "serial" else f"{row['overhead_per_task'] * 1e3:.1f}"
        print(f"{name:<18} {row['workers']:>7} {row['wall']:>7.2f} {speedup:>8.2f} {row['run_mean'] * 1e3:>7.0f} "
              f"{row['tasks']:>5} {overhead:>16} {row['compiled_in_workers']:>19} {row['setup']:>7.2f}")
    found = per_task_overhead()
    overhead = found["overhead"]
    print(f"per-task overhead (default pool, 1 worker, {found['many']['tasks']} tasks of 1 run vs "
          f"{found['one']['tasks']} of {found['one']['shipped']}): {overhead * 1e3:.1f} ms of wall time "
          f"({found['cpu_overhead'] * 1e3:.1f} ms of CPU time); target <= {TARGET_OVERHEAD * 1e3:.0f} ms: "
          f"{'met' if overhead <= TARGET_OVERHEAD else 'NOT met'}")
    print(_sizing(serial, default_rows, overhead))
    from matplotlib.figure import Figure

    figure = Figure(figsize=(7, 3.5))
    axes = figure.add_subplot()
    labels = [f"{name}\n{row['workers']} worker{'s' if row['workers'] > 1 else ''}" for name, row in rows]
    axes.bar(range(len(rows)), [row["wall"] for _, row in rows])
    axes.set_xticks(range(len(rows)), labels, fontsize="small")
    axes.set_ylabel("wall time of 40 runs [s]")
    axes.set_title(f"{type(_model()).__name__}: 40-run sweep")
    figure.tight_layout()
    figure.savefig(args.out, dpi=100)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
