"""The README's "Everyday use" block runs as written, and does what its comments say."""

import re
import sys
import warnings
from pathlib import Path

import matplotlib
import numpy as np

ROOT = Path(__file__).resolve().parent.parent


def everyday_block() -> str:
    text = (ROOT / "README.md").read_text()
    section = text.split("## Everyday use", 1)[1]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_the_everyday_block_runs(tmp_path, monkeypatch):
    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(ROOT))
    namespace: dict = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        exec(compile(everyday_block(), "README.md", "exec"), namespace)
    result, frame, figure = namespace["result"], namespace["frame"], namespace["figure"]
    assert result.status == 0
    # the nested modifier and the run-time parameter both took effect
    assert result["clutch1.fn_max"][0] == 100 and result["J1.J"][0] == 2.0
    assert result.describe("J1.w").startswith("J1.w [rad/s]")
    assert frame.index.is_unique and frame.attrs["units"]["J1.w"] == "rad/s"
    np.testing.assert_array_equal(frame["J1.w"].to_numpy(), result["J1.w"][~_left_rows(result)])
    assert [ax.get_ylabel() for ax in figure.axes][:1] == ["J1.w [rad/s]"]
    assert (tmp_path / "CoupledClutches.mat").stat().st_size > 0
    # a start value at run time: the run starts there
    restarted = namespace["restarted"]
    assert restarted.status == 0 and restarted["J1.w"][0] == 3.0
    # values at any time: linear between the rows around 0.5; the left limit at an event
    rows = ~_left_rows(result)
    assert result.at(0.5, "J1.w") == np.interp(0.5, result.time[rows], result["J1.w"][rows])
    # display units: rpm is 60/(2 pi) of rad/s
    np.testing.assert_allclose(result.in_unit("J1.w", "rpm"), result["J1.w"] * 60 / (2 * np.pi))
    rpm = namespace["rpm"]
    assert rpm.attrs["units"]["J1.w"] == "rpm"
    np.testing.assert_allclose(rpm["J1.w"].to_numpy(), frame["J1.w"].to_numpy() * 60 / (2 * np.pi))
    sys.modules.pop("examples.coupled_clutches", None)


def _left_rows(result):
    """Rows followed by another at the same time (the left limits at events)."""
    t = result.time
    return np.append(t[1:] == t[:-1], False)


def test_the_analyses_block_runs_after_the_everyday_block(tmp_path, monkeypatch):
    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(ROOT))
    text = (ROOT / "README.md").read_text()
    analyses = re.search(r"```python\n(.*?)```", text.split("## Analyses", 1)[1], re.S).group(1)
    namespace: dict = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        exec(compile(everyday_block(), "README.md", "exec"), namespace)
        exec(compile(analyses, "README.md", "exec"), namespace)
    table = namespace["study"].table
    assert len(table) == 6 and (table["status"] == 0).all()
    assert sorted(set(table["J1.J"])) == [0.5, 1, 2]
    lin = namespace["lin"]
    assert lin.A.shape == (len(lin.state_names),) * 2 and lin.input_names == ("sin1.y",)
    assert "clutch1" in lin.discrete_state
