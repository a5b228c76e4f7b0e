"""What a table's size costs: the ``tables`` section of ``acausal bench``.

The same small models (``table_models(rows)`` of ``examples/benchmarks.py``)
are simulated with interpolation tables of 10 to 100,000 rows:

* ``1-D in a loop``: ``der(x) = -f(x)`` with ``f`` a CombiTable1Ds of
  ``sin`` (linear segments): one look-up per right-hand side, at a state;
* ``time table, Akima``: a CombiTimeTable of ``sin(t)`` with smooth
  (Akima) interpolation, integrated (``der(x) = y``): no events, one
  look-up per right-hand side;
* ``2-D in a loop``: ``der(x) = -g(x, t)`` with ``g`` a bilinear
  CombiTable2Ds on an ``n x n`` grid (``n`` = the square root of the rows).

A look-up is a bisection (O(log n)) on precomputed coefficients
(:mod:`acausal.interpolation`), so the simulation time should barely grow
with the table: the table reports it against the 10-row table's.  The time
to translate (flatten, compile) is reported apart: it reads the table once
and computes its spline coefficients.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Callable, Sequence


__all__ = ["run_tables", "tables_markdown", "write_tables", "QUICK_ROWS", "FULL_ROWS"]

QUICK_ROWS = (10, 1_000, 100_000)
FULL_ROWS = (10, 100, 1_000, 10_000, 100_000)


def run_tables(models: Callable[[int], dict], rows: Sequence[int] = QUICK_ROWS, repeats: int = 3,
               log: Callable[[str], None] = lambda _s: None) -> list[dict]:
    """Translate and simulate each model for each table size: one record per (model, rows).

    ``models(rows)`` gives ``{name: model class}`` (the bench passes its suite's
    ``table_models``).
    """
    from acausal import simulate, translate

    records = []
    for size in rows:
        for name, make in models(int(size)).items():
            log(f"tables: {name}, {size} rows")
            t0 = time.perf_counter()
            translation = translate(make(), disk_cache=False)
            first = simulate(translation)
            translate_s = time.perf_counter() - t0
            best = float("inf")
            for _ in range(repeats):
                t1 = time.perf_counter()
                result = simulate(translation)
                best = min(best, time.perf_counter() - t1)
            records.append({"model": name, "rows": int(size), "translate_s": translate_s,
                            "simulate_s": best, "status": result.status, "steps": len(result.time),
                            "message": "" if first.success else first.message})
    for record in records:
        base = next(r for r in records if r["model"] == record["model"] and r["rows"] == min(rows))
        record["vs_smallest"] = record["simulate_s"] / base["simulate_s"]
    return records


def tables_markdown(records: Sequence[dict]) -> str:
    """The section's table: simulation time per model and size, and its ratio to the smallest."""
    lines = ["# What a table's size costs", "",
             "Simulation time (warm: translated once, best of the repeats) of the same model with "
             "tables of more rows; `x smallest` is the ratio to the smallest table's.  The goal: a "
             "100,000-row table within 2x a 10-row one.", "",
             "| model | rows | translate [s] | simulate [s] | x smallest | status |",
             "|---|---:|---:|---:|---:|---|"]
    for r in records:
        status = "ok" if r["status"] >= 0 and not r["message"] else f"failed: {r['message'][:60]}"
        lines.append(f"| {r['model']} | {r['rows']:,} | {r['translate_s']:.2f} | {r['simulate_s']:.3f} | "
                     f"{r['vs_smallest']:.2f} | {status} |")
    return "\n".join(lines) + "\n"


def write_tables(records: Sequence[dict], out_dir: Path) -> dict[str, Path]:
    """``tables.md`` and ``tables.png`` (simulation time against rows, log-log) in ``out_dir``."""
    files = {"tables.md": Path(out_dir) / "tables.md"}
    files["tables.md"].write_text(tables_markdown(records))
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # pragma: no cover - matplotlib is a dependency
        return files
    fig, ax = plt.subplots(figsize=(6, 4))
    for name in dict.fromkeys(r["model"] for r in records):
        mine = [r for r in records if r["model"] == name]
        ax.plot([r["rows"] for r in mine], [r["simulate_s"] for r in mine], marker="o", label=name)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("rows of the table")
    ax.set_ylabel("simulation time [s] (warm)")
    ax.set_title("A look-up is a bisection: table size barely matters")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    files["tables.png"] = Path(out_dir) / "tables.png"
    fig.savefig(files["tables.png"], dpi=120)
    plt.close(fig)
    return files
