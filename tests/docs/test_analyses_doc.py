"""docs/analyses.md: the worked study runs as written and gives the table it shows."""

import contextlib
import io
import re
import warnings
from pathlib import Path

import matplotlib
import pytest

ROOT = Path(__file__).resolve().parents[2]
DOC = (ROOT / "docs" / "analyses.md").read_text()


def test_the_worked_study_gives_the_breakaway_times_of_its_table(tmp_path, monkeypatch):
    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(ROOT))
    section = DOC.split("### Worked study", 1)[1]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    printed = io.StringIO()
    with warnings.catch_warnings(), contextlib.redirect_stdout(printed):
        warnings.simplefilter("ignore")
        exec(compile(code, "docs/analyses.md", "exec"), {})
    measured = [tuple(map(float, line.split())) for line in printed.getvalue().splitlines()]
    table = re.search(r"\| `clutch\.peak` \|(.*)\|\n\|[-| ]+\|\n\| breakaway \[s\] \|(.*)\|", section)
    peaks = [float(v) for v in table.group(1).split("|")]
    shown = [float(v) for v in table.group(2).split("|")]
    assert [p for p, _ in measured] == peaks
    assert [t for _, t in measured] == pytest.approx(shown, abs=1e-3)  # shown to 3 decimals
    assert (tmp_path / "envelope.png").stat().st_size > 0
