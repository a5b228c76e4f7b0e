"""The figure of docs/tables.md: the six interpolations of one data set.

Run from the repository root::

    python docs/tables_figures.py

It writes ``docs/figures/tables_interpolations.png``: the value and the first
derivative of a CombiTable1Ds with each ``smoothness`` on Akima's third data
set (the MSL's ticket #1717 test data), extrapolated on both sides with
``LastTwoPoints``.  The curves are simulated (a ContinuousClock drives the
table, a Der block differentiates its output), not computed by the numeric
core alone.
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from acausal import Experiment, Model, simulate  # noqa: E402
from acausal.library.blocks import CombiTable1Ds, ContinuousClock, Der, Smoothness  # noqa: E402

FIGURES = Path(__file__).resolve().parent / "figures"

#: Akima's data set 3 (ModelicaTest.Tables.CombiTable1Ds.Test27): flat, then steep
DATA = [[0, 10], [2, 10], [3, 10], [5, 10], [6, 10], [8, 10], [9, 10.5], [11, 15], [12, 50], [14, 60],
        [15, 85]]


def interpolations() -> Model:
    class SixInterpolations(Model):
        """One clock, six tables of the same data, each with its derivative."""

        experiment = Experiment(start_time=-1.0, stop_time=16.0, interval=0.01)

        def build(self):
            self.clock = ContinuousClock(startTime=-1.0, offset=-1.0)
            for kind in Smoothness:
                table = CombiTable1Ds(table=DATA, smoothness=kind)
                derivative = Der()
                setattr(self, kind.name, table)
                setattr(self, f"d_{kind.name}", derivative)
                self.connect(self.clock.y, table.u)
                self.connect(table.y[1], derivative.u)

    return SixInterpolations()


def main() -> Path:
    result = simulate(interpolations())
    assert result.success, result.message
    t = result["clock.y"]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    for kind in Smoothness:
        top.plot(t, result[f"{kind.name}.y[1]"], label=kind.name)
        bottom.plot(t, result[f"d_{kind.name}.y"], label=kind.name)
    x, y = zip(*DATA)
    top.plot(x, y, "ko", label="table rows")
    top.set_ylabel("y")
    top.set_title("CombiTable1Ds: the six smoothness options on Akima's data set 3")
    top.legend(fontsize=8)
    bottom.set_ylabel("dy/du (a Der block)")
    bottom.set_xlabel("u")
    for axis in (top, bottom):
        axis.grid(alpha=0.3)
    fig.tight_layout()
    FIGURES.mkdir(exist_ok=True)
    path = FIGURES / "tables_interpolations.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


if __name__ == "__main__":
    print(f"wrote {main()}")
