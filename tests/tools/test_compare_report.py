"""Tests of the comparison's self-explaining output: the table's legend, discrete
signals judged by their change times, and one figure per model with units and
value names.

Hand-made references use a grid 0..1 (so ``dx = 2e-3``) with event times
written twice, as the MSL reference files do.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from test_compare import make_reference
import pytest

from acausal.tools.compare import (
    Reference,
    SignalInfo,
    compare_signals,
    comparison_figure,
    plot_comparison,
    signal_info,
)

REPO = Path(__file__).resolve().parents[2]

#: Names of a mode's values, as a component class would define them.
MODE_NAMES = {-1: "Backward", 0: "Stuck", 1: "Forward", 2: "Free"}


def reference_of(time, signals: dict[str, np.ndarray]) -> Reference:
    """A Reference built in memory."""
    return make_reference(time, signals)


def steps(changes: list[tuple[float, float]], first: float = 0.0, n: int = 1001):
    """A piecewise constant curve on 0..1: ``first``, then each ``(time, new value)``; events twice."""
    grid = np.linspace(0.0, 1.0, n)
    times = [at for at, _ in changes]
    t = np.sort(np.concatenate([grid[~np.isin(grid, times)], times, times]))
    y = np.full(t.shape, first)
    for at, value in changes:
        # from the second sample at the event time (the right limit) on
        y[np.searchsorted(t, at, side="left") + 1:] = value
    return t, y


MODE = SignalInfo(kind="integer", labels=MODE_NAMES)


# ---------------------------------------------------------------------------
# The table explains itself
# ---------------------------------------------------------------------------


def test_table_has_a_legend_that_explains_every_column():
    t = np.linspace(0.0, 1.0, 101)
    ref = reference_of(t, {"a": t})
    text = compare_signals(ref, t, {"a": t}).table()
    lines = text.splitlines()
    assert lines[0].split()[:2] == ["signal", "result"]
    assert "outside tube [dy]" in lines[0] and "first failure [s]" in lines[0]
    assert "legend:" in lines
    legend = lines[lines.index("legend:") + 1:-1]
    for column in ("result", "outside tube [dy]", "first failure [s]", "max |error|", "note"):
        assert any(line.strip().startswith(f"{column}:") for line in legend), column
    assert any("half-height" in line and "dy" in line for line in legend)
    assert any("dx = 0.002 s" in line for line in legend)
    assert "1 of 1 signals passed" in lines[-1]
    assert "legend:" not in compare_signals(ref, t, {"a": t}).table(legend=False)


def test_units_follow_max_error_and_discrete_rows_show_their_changes():
    t, mode = steps([(0.5, 1.0)])
    ref = reference_of(t, {"w": t, "mode": mode})
    info = {"w": SignalInfo(unit="rad/s", kind="continuous"), "mode": MODE}
    outcome = compare_signals(ref, t, {"w": t + 1e-4, "mode": mode}, info=info)
    rows = {line.split()[0]: line for line in outcome.table().splitlines()[2:4]}
    assert rows["w"].split()[1] == "pass" and "0.0001 rad/s" in rows["w"]
    assert "changes at 0.5 (all within dx)" in rows["mode"]
    assert rows["mode"].split()[1:5] == ["pass", "-", "-", "-"]  # no tube figure, no max |error|


def test_summary_counts_discrete_signals_in_the_right_number():
    t, mode = steps([(0.5, 1.0)])
    ref = reference_of(t, {"mode": mode})
    one = compare_signals(ref, t, {"mode": mode}, info={"mode": MODE})
    assert "1 discrete signal judged by the times it changes" in one.table().splitlines()[-1]

    ref_two = reference_of(t, {"a": mode, "b": mode})
    two = compare_signals(ref_two, t, {"a": mode, "b": mode}, info={"a": MODE, "b": MODE})
    assert "2 discrete signals judged by the times they change" in two.table().splitlines()[-1]


def test_values_that_differ_are_counted_in_the_right_number():
    # the result makes the reference's change, but starts from another value
    t = np.array([0.0, 0.5, 0.5, 1.0])
    ref = reference_of(t, {"mode": np.array([0.0, 0.0, 1.0, 1.0])})
    outcome = compare_signals(ref, t, {"mode": np.array([2.0, 2.0, 1.0, 1.0])}, info={"mode": MODE})["mode"]
    assert not outcome.passed and outcome.unmatched_changes == ()
    assert outcome.note == "changes at 0.5 (all within dx); values differ at 1 point"
    assert outcome.first_failure_time == 0.0

    # one sample off by one, with no event: the result changes twice where the reference does not
    t, mode = steps([(0.5, 1.0)])
    ours = mode.copy()
    ours[np.flatnonzero(np.isclose(t, 0.2))] = 2.0
    outcome = compare_signals(reference_of(t, {"mode": mode}), t, {"mode": ours},
                              info={"mode": MODE})["mode"]
    assert not outcome.passed
    assert outcome.note == "changes at 0.5 (all within dx); result also changes at 0.2x2"
    assert outcome.first_failure_time == pytest.approx(0.2)


# ---------------------------------------------------------------------------
# Discrete signals judged by their changes
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("shift", [-0.0015, 0.0, 0.0015])
def test_a_change_within_dx_passes(shift):
    t, mode = steps([(0.3, 1.0), (0.6, 2.0)])
    ours_t, ours = steps([(0.3 + shift, 1.0), (0.6, 2.0)])
    outcome = compare_signals(reference_of(t, {"mode": mode}), ours_t, {"mode": ours},
                              info={"mode": MODE})["mode"]
    assert outcome.discrete
    assert outcome.passed, outcome.note
    assert outcome.reference_changes == (0.3, 0.6)
    assert outcome.note == "changes at 0.3 0.6 (all within dx)"


@pytest.mark.parametrize("shift", [-0.004, 0.004])
def test_a_change_shifted_beyond_dx_fails(shift):
    t, mode = steps([(0.3, 1.0), (0.6, 2.0)])
    ours_t, ours = steps([(0.3 + shift, 1.0), (0.6, 2.0)])
    outcome = compare_signals(reference_of(t, {"mode": mode}), ours_t, {"mode": ours},
                              info={"mode": MODE})["mode"]
    assert not outcome.passed
    assert outcome.unmatched_changes == (0.3,)
    assert outcome.first_failure_time == pytest.approx(min(0.3, 0.3 + shift))
    assert "not matched within dx: 0.3" in outcome.note
    assert outcome.failed_points > 0


def test_a_missed_change_and_an_extra_change_fail():
    t, mode = steps([(0.5, 1.0)])
    ref = reference_of(t, {"mode": mode})
    never = compare_signals(ref, t, {"mode": np.zeros_like(mode)}, info={"mode": MODE})["mode"]
    assert not never.passed and never.unmatched_changes == (0.5,)

    extra_t, extra = steps([(0.2, 2.0), (0.25, 0.0), (0.5, 1.0)])
    outcome = compare_signals(ref, extra_t, {"mode": extra}, info={"mode": MODE})["mode"]
    assert not outcome.passed
    assert outcome.unmatched_changes == ()
    assert "result also changes at 0.2 0.25" in outcome.note
    assert outcome.first_failure_time == pytest.approx(0.2)


def test_a_change_to_another_value_is_not_a_match():
    t, mode = steps([(0.5, 1.0)])
    ours_t, ours = steps([(0.5, -1.0)])
    outcome = compare_signals(reference_of(t, {"mode": mode}), ours_t, {"mode": ours},
                              info={"mode": MODE})["mode"]
    assert not outcome.passed and outcome.unmatched_changes == (0.5,)


def test_a_pulse_within_one_event_is_shown_once_with_its_count():
    # 0 -> 1 -> 0 within a few microseconds, as a start flag during an event
    t, flag = steps([(0.4, 1.0), (0.400001, 0.0)], n=1001)
    outcome = compare_signals(reference_of(t, {"flag": flag}), t, {"flag": flag},
                              info={"flag": SignalInfo(kind="boolean", labels={0: "false", 1: "true"})})
    assert outcome.passed
    assert outcome["flag"].note == "changes at 0.4x2 (all within dx)"


def test_discrete_without_a_kind_needs_an_integer_column():
    """A float column of 0s and 1s keeps the tube test; an integer or Boolean column is discrete."""
    t, mode = steps([(0.5, 1.0)])
    ref = reference_of(t, {"s": mode})
    assert not compare_signals(ref, t, {"s": mode})["s"].discrete
    assert compare_signals(ref, t, {"s": mode.astype(int)})["s"].discrete
    assert compare_signals(ref, t, {"s": mode.astype(bool)})["s"].discrete
    # a continuous kind keeps the tube test even for an integer column
    kept = compare_signals(ref, t, {"s": mode.astype(int)}, info={"s": SignalInfo(kind="continuous")})
    assert not kept["s"].discrete


def test_a_reference_that_is_not_integer_keeps_the_tube_test():
    t = np.linspace(0.0, 1.0, 101)
    ref = reference_of(t, {"s": 0.5 * t})
    outcome = compare_signals(ref, t, {"s": 0.5 * t}, info={"s": MODE})["s"]
    assert not outcome.discrete and outcome.passed


# ---------------------------------------------------------------------------
# Units, kinds and value names from the model
# ---------------------------------------------------------------------------


def test_signal_info_reads_units_kinds_and_value_names_from_the_model():
    from acausal.tools.cli import load_model_class

    model = load_model_class(str(REPO / "examples" / "coupled_clutches.py"))()
    info = signal_info(model, ["J1.w", "clutch1.mode", "clutch1.startForward", "nope"])
    assert set(info) == {"J1.w", "clutch1.mode", "clutch1.startForward"}
    assert info["J1.w"] == SignalInfo(unit="rad/s", kind="continuous", labels={})
    assert info["clutch1.mode"].kind == "integer"
    # found from the integer class attributes of the component's class
    assert {-1: "Backward", 0: "Stuck", 1: "Forward", 2: "Free"}.items() <= info["clutch1.mode"].labels.items()
    assert info["clutch1.startForward"].labels == {0: "false", 1: "true"}


# ---------------------------------------------------------------------------
# One figure per model
# ---------------------------------------------------------------------------


@pytest.fixture
def two_signals():
    t, mode = steps([(0.3, 1.0), (0.6, -1.0)])
    w = np.sin(3 * t)
    ref = reference_of(t, {"J1.w": w, "clutch.mode": mode})
    info = {"J1.w": SignalInfo(unit="rad/s", kind="continuous"), "clutch.mode": MODE}
    ours_t, ours_mode = steps([(0.3, 1.0), (0.61, -1.0)])  # second change beyond dx: fails
    values = {"J1.w": np.sin(3 * ours_t), "clutch.mode": ours_mode}
    return ref, ours_t, values, info


def test_figure_has_a_panel_per_signal_with_units_and_value_names(two_signals):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    ref, t, values, info = two_signals
    figure = comparison_figure(ref, t, values, info=info)
    axes = figure.axes
    assert len(axes) == 2
    assert axes[0].get_ylabel() == "J1.w [rad/s]"
    assert axes[1].get_ylabel() == "clutch.mode"
    assert axes[-1].get_xlabel() == "time [s]"
    assert [label.get_text() for label in axes[1].get_yticklabels()] == ["Backward", "Stuck", "Forward"]
    assert "PASS" in axes[0].get_title()
    assert "FAIL" in axes[1].get_title()
    # the tube is drawn: a shaded band in the continuous panel, the dx bands in the discrete one
    assert axes[0].collections and axes[1].patches
    # the failure is marked
    assert any(line.get_label().startswith("change not matched") for line in axes[1].get_lines())
    assert "1 of 2 signals passed" in figure._suptitle.get_text()


def test_figure_without_names_shows_integers(two_signals):
    pytest.importorskip("matplotlib")
    ref, t, values, _ = two_signals
    figure = comparison_figure(ref, t, values, ["clutch.mode"])
    assert len(figure.axes) == 1
    assert figure.axes[0].get_ylabel() == "clutch.mode"
    # no kind known: a float column keeps the tube test, and the ticks are matplotlib's own
    assert figure.axes[0].collections


def test_plot_comparison_writes_one_file_per_model_and_per_signal_files_on_request(two_signals, tmp_path):
    pytest.importorskip("matplotlib")
    ref, t, values, info = two_signals
    written = plot_comparison(ref, t, values, tmp_path / "Model.png", info=info)
    assert written == [tmp_path / "Model.png"]
    assert written[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    written = plot_comparison(ref, t, values, tmp_path / "Model.png", info=info, per_signal=True)
    assert [p.name for p in written] == ["Model.png", "J1.w.png", "clutch.mode.png"]
    assert all(p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for p in written)


# ---------------------------------------------------------------------------
# Several models: one table, the legend once (acausal compare A B ...)
# ---------------------------------------------------------------------------

FIRST = REPO / "examples" / "first.py"
TWO_MASSES = REPO / "examples" / "two_masses.py"


def test_a_report_has_a_row_per_model_with_what_failed():
    from acausal.tools.compare import ComparisonReport, ModelOutcome

    t = np.linspace(0.0, 1.0, 101)
    ref = reference_of(t, {"a": t, "b": t})
    good = compare_signals(ref, t, {"a": t, "b": t})
    bad = compare_signals(ref, t, {"a": t, "b": t + 0.1})  # b: 0.1 off, a tube of 0.002 * 1
    report = ComparisonReport(["good.py:Good", "bad.py:Bad", "broken.py"])
    report.add(ModelOutcome("good.py:Good", good, "pass", seconds=0.25))
    report.add(ModelOutcome("bad.py:Bad", bad, "FAIL", seconds=1.5))
    report.add(ModelOutcome("broken.py", None, "error", "ReferenceDataError: no reference\n  hint: ..."))
    lines = report.table().splitlines()
    assert len(lines) == 2 + 3  # the header, its rule, a row per model
    rows = {line.split()[0]: line.split() for line in lines[2:]}
    assert rows["good.py:Good"][1:6] == ["pass", "2/2", "0", "-", "0.25"]
    bad_row = rows["bad.py:Bad"]
    assert bad_row[1:3] == ["FAIL", "1/2"] and float(bad_row[3]) == pytest.approx(49, abs=1)
    assert bad_row[4] == "0" and "failed: b" in lines[3]  # b is outside the tube from the start
    assert rows["broken.py"][1:3] == ["error", "-"] and lines[4].endswith("no reference")  # one line
    assert report.passed == 1
    # every column starts where its header does
    start = lines[0].index("signals")
    assert all(line[start - 1] == " " for line in lines[2:])
    legend = report.legend().splitlines()
    for column in ("result", "signals", "outside tube [dy]", "first failure [s]", "time [s]", "note"):
        assert any(line.strip().startswith(f"{column}:") for line in legend), column
    assert not any("max |error|" in line for line in legend)  # no per-signal table to explain
    assert any("max |error|" in line for line in report.legend(signals=True).splitlines())


def test_a_second_outcome_for_the_model_started_replaces_the_first():
    from acausal.tools.compare import ComparisonReport, ModelOutcome

    report = ComparisonReport(["a.py"])
    report.start("a.py")
    report.add(ModelOutcome("a.py", result="interrupted"))
    report.add(ModelOutcome("a.py", result="error", note="boom"))
    assert [o.result for o in report.outcomes] == ["error"]
    assert report.outcomes[0].seconds >= 0  # timed from start()


def _compare_output(capsys, *arguments) -> tuple[int, list[str]]:
    from acausal.tools.cli import main

    status = main(["compare", *arguments])
    return status, capsys.readouterr().out.splitlines()


def test_several_models_print_one_table_and_the_legend_once(capsys, monkeypatch):
    monkeypatch.delenv("ACAUSAL_REFERENCE_DIR", raising=False)  # the bundled references
    status, lines = _compare_output(capsys, str(FIRST), str(TWO_MASSES))
    assert status == 0
    assert lines.count("legend:") == 1
    assert lines[0].split()[:3] == ["model", "result", "signals"]
    rows = [line.split() for line in lines[2:4]]
    assert [row[:3] for row in rows] == [[str(FIRST), "pass", "4/4"], [str(TWO_MASSES), "pass", "2/2"]]
    # no per-signal tables and no run summaries: the table, the legend and the verdict
    assert not any(line.startswith(("signal ", "inertia3.w", "mass1.T", "First: ok")) for line in lines)
    assert lines[-1] == "== 2 of 2 models match their reference results"
    assert len(lines) < 20


def test_verbose_adds_each_models_tables_and_keeps_one_legend(capsys, monkeypatch):
    monkeypatch.delenv("ACAUSAL_REFERENCE_DIR", raising=False)
    status, lines = _compare_output(capsys, str(FIRST), str(TWO_MASSES), "--verbose")
    assert status == 0
    assert lines.count("legend:") == 1
    assert lines[0] == f"== [1/2] {FIRST}" and f"== [2/2] {TWO_MASSES}" in lines
    assert sum(line.startswith("signal ") for line in lines) == 2  # a per-signal table per model
    assert any(line.startswith("inertia3.w ") for line in lines)
    assert any(line.startswith("mass1.T ") for line in lines)
    assert any(line.startswith("First: ok") for line in lines)
    assert sum(line.split()[:1] == ["model"] for line in lines) == 1  # the table of models, at the end
    legend = lines[lines.index("legend:"):]
    assert any("max |error|" in line for line in legend)


def test_a_single_model_keeps_its_table_with_the_legend(capsys, monkeypatch):
    monkeypatch.delenv("ACAUSAL_REFERENCE_DIR", raising=False)
    status, lines = _compare_output(capsys, str(FIRST))
    assert status == 0
    assert lines[0].startswith("First: ok")
    assert any(line.startswith("signal ") for line in lines) and "legend:" in lines
    assert lines[-1].startswith("Modelica.Mechanics.Rotational.Examples.First: 4 of 4 signals passed")
    assert not any(line.split()[:1] == ["model"] for line in lines)
