"""Bench of :func:`acausal.tools.sweep.sweep`: speed-up on two workers and overhead per task.

``python -m acausal.tools.sweep_bench [--out FILE.png] [--no-dask]`` runs a
40-run sweep of the CoupledClutches example (``J1.J`` times the driving
sine's amplitude) on 1 and on 2 workers, for the standard library's process
pool and for a Dask ``LocalCluster`` (when dask is installed), and prints:

* the wall time of the sweep (translation, the first runs here, and the
  workers' runs) and the speed-up of 2 workers over 1;
* the time of the runs in the workers (sum of their own clocks) per run;
* the overhead per task: (workers x wall time of the shipped part - the
  runs' own time) / tasks, i.e. what shipping, scheduling and gathering a
  task costs a worker.

The pools are started before the clock starts (a pool is started once per
session, not per sweep), and one warm-up sweep makes every worker load the
bundle, as a long study does once.  Every discrete state the grid reaches is
compiled once before any timing, so that no configuration compiles in its
workers (the last column shows it).
"""

from __future__ import annotations

import argparse
import concurrent.futures
import sys
import time as _time
from pathlib import Path

import numpy as np

__all__ = ["main", "measure"]

GRID = {"J1.J": [float(v) for v in np.linspace(0.8, 1.6, 8)], "sin1.amplitude": [8.0, 9.0, 10.0, 11.0, 12.0]}
OUTPUTS = ["J1.w", "J4.w"]


def _model():
    root = Path(__file__).resolve().parents[2]
    if str(root) not in sys.path:
        sys.path.insert(0, str(root))
    from examples.coupled_clutches import CoupledClutches

    return CoupledClutches()


def measure(executor, workers: int, chunk_size: int | None = None, pilot: int = 2) -> dict:
    """One timed 40-run sweep on ``executor`` (after an untimed warm-up one)."""
    from .sweep import sweep

    model = _model()
    sweep(model, GRID, OUTPUTS, executor=executor, chunk_size=chunk_size, pilot=pilot)  # warm-up
    t0 = _time.perf_counter()
    result = sweep(model, GRID, OUTPUTS, executor=executor, chunk_size=chunk_size, pilot=pilot)
    wall = _time.perf_counter() - t0
    shipped = [o for o in result.runs if o.index != 0]
    run_seconds = sum(o.seconds for o in shipped)
    tasks = -(-len(shipped) // (chunk_size or max(1, -(-len(shipped) // (4 * workers)))))
    here = sum(o.seconds for o in result.runs) - run_seconds  # runs made in this process
    shipped_wall = max(wall - here, 1e-9)
    return {"workers": workers, "wall": wall, "runs": len(result.runs), "failed": len(result.failed),
            "run_mean": run_seconds / max(len(shipped), 1), "tasks": tasks,
            "overhead_per_task": max(workers * shipped_wall - run_seconds, 0.0) / tasks,
            "compiled_in_workers": result.compiled_in_workers}


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
    rows = []
    for workers in (1, 2):
        with concurrent.futures.ProcessPoolExecutor(max_workers=workers) as pool:
            rows.append(("process pool", measure(pool, workers)))
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
          f"{'overhead/task ms':>16} {'compiled in workers':>19}")
    single = {}
    for name, row in rows:
        if row["workers"] == 1:
            single[name] = row["wall"]
        speedup = single.get(name, row["wall"]) / row["wall"]
        print(f"{name:<18} {row['workers']:>7} {row['wall']:>7.2f} {speedup:>8.2f} {row['run_mean'] * 1e3:>7.0f} "
              f"{row['tasks']:>5} {row['overhead_per_task'] * 1e3:>16.1f} {row['compiled_in_workers']:>19}")
    from matplotlib.figure import Figure

    figure = Figure(figsize=(6, 3.5))
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
