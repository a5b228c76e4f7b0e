"""docs/tables.md: its code runs and its figure shows what the page says it shows."""

from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import numpy as np

from acausal import simulate

DOCS = Path(__file__).resolve().parents[2] / "docs"


def test_the_pages_code_runs_and_gives_the_tables_values(capsys):
    blocks = re.findall(r"```python\n(.*?)```", (DOCS / "tables.md").read_text(), re.S)
    assert blocks
    namespace: dict = {}
    for block in blocks:
        exec(compile(block, "docs/tables.md", "exec"), namespace)
    curve, profile = (float(v) for v in capsys.readouterr().out.split())
    assert 4.0 < curve < 16.0           # u = 3 between the rows (2, 4) and (4, 16), monotone
    assert profile == 3.0               # t = 3 is t = 1 of the period: the later row of the jump


def _figure_module():
    spec = importlib.util.spec_from_file_location("tables_figures", DOCS / "tables_figures.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_figure_shows_the_six_interpolations_as_described():
    figures = _figure_module()
    result = simulate(figures.interpolations())
    assert result.success, result.message
    u = result["clock.y"]
    x, y = (np.array(c, dtype=float) for c in zip(*figures.DATA))
    inside = (u >= x[0]) & (u <= x[-1])
    np.testing.assert_allclose(result["LinearSegments.y[1]"][inside], np.interp(u[inside], x, y), atol=1e-9)
    steps = y[np.clip(np.searchsorted(x, u[inside], side="right") - 1, 0, len(x) - 1)]
    right = np.append(np.diff(u[inside]) > 0, True)
    np.testing.assert_allclose(result["ConstantSegments.y[1]"][inside][right], steps[right], atol=1e-9)
    # the data never fall: the monotone splines never fall either, Akima's does (the dip near 13)
    for name in ("MonotoneContinuousDerivative1", "MonotoneContinuousDerivative2"):
        assert np.min(result[f"d_{name}.y"][inside]) >= -1e-9, name
    assert np.min(result["d_ContinuousDerivative.y"][inside]) < -0.1
    # every curve passes through the rows
    for name in ("ContinuousDerivative", "MonotoneContinuousDerivative1", "MonotoneContinuousDerivative2",
                 "ModifiedContinuousDerivative"):
        at_rows = np.interp(x, u, result[f"{name}.y[1]"])
        np.testing.assert_allclose(at_rows, y, atol=1e-6, err_msg=name)
