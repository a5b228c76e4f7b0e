"""Nothing is lost when a run fails, and bad command-line input gets a clear message.

Three ways a simulation can stop early, each with a small model written here:

* the event-iteration limit: ``b = not pre(b)`` from a time event at t = 0.5
  never reaches a fixed point (:class:`~acausal.errors.EventIterationError`);
* chattering: ``der(x) = if x > 0 then -1 else 1`` from ``x = 0`` switches
  every 2e-10 s (the relation hysteresis) without time passing
  (:class:`~acausal.errors.ChatteringError`);
* solver failure: ``der(x) = x^2`` from ``x(0) = 1`` is ``1/(1 - t)``, which
  blows up at t = 1; RK45 gives up there (:class:`~acausal.errors.SolverError`).

Each must end with status -1, a message, ``result.error`` set (and pointing
back to the result), and every output row and event computed before the
failure: the rows are compared with a twin run that does not fail (the
flip moved past the stop time; the stop time moved before the blow-up).
``acausal simulate`` must write that partial CSV and exit with status 1,
the reason on stderr.

Bad command-line input (unknown model, file without a model, unknown
option, a tolerance that is not a number, a malformed reference folder)
must give exit status 2 and a one-paragraph message, never a traceback.
"""

from __future__ import annotations

import csv
import textwrap
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from acausal import Boolean, Eq, Experiment, If, Model, Parameter, Variable, der, simulate, time
from acausal.tools.cli import main
from acausal.errors import (
    AcausalError,
    ChatteringError,
    EventIterationError,
    ReferenceDataError,
    SimulationError,
    SolverError,
)
from acausal.components.logic import pre_boolean

HERE = Path(__file__).resolve()


# --------------------------------------------------------------------------
# models that fail (also loaded by the CLI from this file, as HERE:ClassName)


class FlipFlop(Model):
    """x = t; c = x > 0.25 (a state event); from t = flip_time on, b = not pre(b) forever."""

    experiment = Experiment(stop_time=1.0, interval=0.1)
    flip_time = Parameter(0.5)
    x = Variable(start=0.0, fixed=True)
    c = Boolean()
    b = Boolean(start=False, fixed=True)

    def equations(self):
        return [
            Eq(der(self.x), 1),
            Eq(self.c, self.x > 0.25),
            Eq(self.b, sp.And(time >= self.flip_time, sp.Not(pre_boolean(self.b)))),
        ]


class Chatter(Model):
    """der(x) = -1 if x > 0 else 1, from x = 0: x is held at 0 by infinitely fast switching."""

    experiment = Experiment(stop_time=1.0, interval=0.1)
    x = Variable(start=0.0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), If(self.x > 0, -1, 1))]


class BlowUp(Model):
    """der(x) = x^2 from x(0) = 1: x = 1/(1 - t), infinite at t = 1."""

    experiment = Experiment(stop_time=2.0, interval=0.01)
    x = Variable(start=1.0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), self.x ** 2)]


# --------------------------------------------------------------------------
# helpers


def check_failed_result(result, error_type, failure_time, *, abs_tol):
    """The common contract of a run that stopped early."""
    assert result.status == -1
    assert not result.success
    assert result.message and result.message.strip()
    assert isinstance(result.error, error_type)
    assert isinstance(result.error, SimulationError) and isinstance(result.error, AcausalError)
    assert result.error.result is result  # the partial result travels with the error
    assert str(result.error) == result.message
    with pytest.raises(error_type):
        result.raise_for_status()
    # rows up to the failure, in order, starting at the start time
    assert result.time.size >= 2
    assert result.time[0] == 0.0
    assert np.all(np.diff(result.time) >= 0)
    assert result.time[-1] == pytest.approx(failure_time, abs=abs_tol)
    # every column has one value per row, none lost on the way
    for name, values in result.columns.items():
        assert len(values) == result.time.size, name
    assert not np.any(np.isnan(result["x"]))
    # events up to then, the first being the initial one
    assert result.events and result.events[0].kind == "initial"
    assert all(e.time <= result.time[-1] for e in result.events)
    assert [e.time for e in result.events] == sorted(e.time for e in result.events)


def rows_until(result, t_end):
    """(time, x) of the rows with time < t_end."""
    keep = result.time < t_end
    return result.time[keep], result["x"][keep]


def read_csv(path: Path) -> tuple[list[str], np.ndarray]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return rows[0], np.array([[float(v) for v in row] for row in rows[1:]])


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    """Run in an empty current directory (default outputs land there)."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


def write(folder: Path, name: str, text: str) -> Path:
    path = folder / name
    path.write_text(textwrap.dedent(text))
    return path


# --------------------------------------------------------------------------
# 1. the partial result of a failed run


@pytest.mark.parametrize("limit", [20, 3])
def test_event_iteration_limit_keeps_rows_and_events(limit):
    """b = not pre(b) from t = 0.5: EventIterationError at 0.5 with every row and event before it."""
    result = simulate(FlipFlop(), max_event_iterations=limit)
    check_failed_result(result, EventIterationError, 0.5, abs_tol=1e-12)
    assert "t = 0.5" in result.message and "b" in result.message
    assert f"{limit} iterations" in result.message
    # the state event at 0.25 (c becomes true) is kept; nothing after 0.5
    state = [e for e in result.events if e.kind == "state"]
    assert len(state) == 1 and state[0].time == pytest.approx(0.25, abs=1e-9)
    assert state[0].changes == (("c", False, True),)
    # the last row is the left limit at the failing event: x = 0.5, b still false
    assert result.final("x") == pytest.approx(0.5, abs=1e-12)
    assert np.all(result["b"] == 0)
    np.testing.assert_allclose(result["x"], result.time, rtol=0, atol=1e-12)
    # nothing lost: the same rows as a twin that never flips (flip after the stop time)
    twin = simulate(FlipFlop(flip_time=5.0))
    assert twin.status == 0, twin.message
    t_fail, x_fail = rows_until(result, 0.5)
    t_twin, x_twin = rows_until(twin, 0.5)
    np.testing.assert_allclose(t_fail, t_twin, rtol=0, atol=1e-12)  # steps end at 0.5 vs 1: round-off
    np.testing.assert_allclose(x_fail, x_twin, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(result["c"][result.time < 0.5], twin["c"][twin.time < 0.5])
    assert [str(e) for e in result.events] == [str(e) for e in twin.events if e.time < 0.5]


def test_chattering_keeps_rows_and_events():
    """x' = if x > 0 then -1 else 1 from 0: detected as chattering within microseconds, x held at 0.

    What it does: the first step leaves x = 0 upwards, the crossing of
    ``x > 0`` (hysteresis 1e-10) flips the slope, x comes back down through
    the hysteresis band, and so on: one state event every 2e-10 s.  After
    ``chattering_events`` (100) of them in a vanishing window the run stops
    with the partial result; the solution itself (x = 0) is right.
    """
    result = simulate(Chatter())
    check_failed_result(result, ChatteringError, 0.0, abs_tol=1e-6)
    assert "chattering" in result.message and "x > 0" in result.message
    state = [e for e in result.events if e.kind == "state"]
    assert 90 <= len(state) <= 100
    assert all(e.relations == ("x > 0",) for e in state)
    # every event leaves its two rows (left and right limit)
    event_times = [e.time for e in state]
    for t in event_times:
        assert np.count_nonzero(result.time == t) == 2
    # x stays on the switching surface
    assert np.max(np.abs(result["x"])) < 1e-9
    # the events come every ~2e-10 s: the run really did not advance
    assert 0 < result.time[-1] < 1e-6


def test_solver_failure_keeps_rows():
    """x' = x^2 from 1 with RK45: SolverError near t = 1, every earlier grid row kept and right."""
    result = simulate(BlowUp(), method="RK45", rtol=1e-6)
    check_failed_result(result, SolverError, 1.0, abs_tol=0.02)
    assert "RK45" in result.message and "t = 1" in result.message
    assert result.events == result.events[:1]  # only the initial event
    grid = np.round(np.arange(0.0, 0.99, 0.01), 12)
    early = result.time < 0.99
    np.testing.assert_allclose(result.time[early], grid, rtol=0, atol=1e-12)
    np.testing.assert_allclose(result["x"][early], 1 / (1 - grid), rtol=1e-3)
    # nothing lost: the rows agree with a twin that stops before the blow-up
    twin = simulate(BlowUp(), method="RK45", rtol=1e-6, stop_time=0.95)
    assert twin.status == 0, twin.message
    both = result.time <= 0.9
    np.testing.assert_array_equal(result.time[both], twin.time[twin.time <= 0.9])
    np.testing.assert_allclose(result["x"][both], twin["x"][twin.time <= 0.9], rtol=1e-9)


@pytest.mark.parametrize("method, t_fail, accuracy", [("RK4", 1.01, 1e-6), ("Euler", 1.12, 0.05)])
def test_solver_failure_with_fixed_step_method(method, t_fail, accuracy):
    """Fixed-step methods stop at the first step whose derivatives are not finite, rows kept."""
    with np.errstate(all="ignore"):
        result = simulate(BlowUp(), method=method, max_step=0.01)
    check_failed_result(result, SolverError, t_fail, abs_tol=1e-9)
    assert f"{method} failed" in result.message and "non-finite" in result.message
    early = result.time <= 0.5
    np.testing.assert_allclose(result["x"][early], 1 / (1 - result.time[early]), rtol=accuracy)


@pytest.mark.parametrize("method", ["RK4", "Euler"])
def test_fixed_step_failure_keeps_the_computed_values(method):
    """The rows kept before a fixed-step overflow are the integrator's values: finite and positive."""
    with np.errstate(all="ignore"):
        result = simulate(BlowUp(), method=method, max_step=0.01)
    assert result.status == -1
    assert np.all(np.isfinite(result["x"]))
    assert np.all(result["x"] > 0)


# --------------------------------------------------------------------------
# 2. acausal simulate writes the partial CSV and exits with 1


@pytest.mark.parametrize("model, words", [
    ("FlipFlop", ["did not converge", "t = 0.5"]),
    ("Chatter", ["chattering", "x > 0"]),
    ("BlowUp", ["RK45 failed", "t = 1"]),
])
def test_cli_writes_partial_csv_and_exits_1(in_tmp, capsys, model, words):
    """The CSV holds exactly the rows of the failed result; stderr gives the reason; status 1."""
    out = in_tmp / f"{model}.csv"
    status = main(["simulate", f"{HERE}:{model}", "--out", str(out)])
    captured = capsys.readouterr()
    assert status == 1
    assert "Traceback" not in captured.err
    assert "failed" in captured.err and "up to the failure" in captured.err
    for word in words:
        assert word in captured.err
    assert "FAILED" in captured.out and str(out) in captured.out
    header, data = read_csv(out)
    assert header[0] == "time" and "x" in header
    expected = simulate(globals()[model]())
    assert expected.status == -1
    np.testing.assert_array_equal(data[:, 0], expected.time)
    np.testing.assert_array_equal(data[:, header.index("x")], expected["x"])


def test_cli_partial_csv_with_selected_signals(in_tmp, capsys):
    """--signals: the partial CSV holds only the chosen columns, up to the failure."""
    out = in_tmp / "flip.csv"
    status = main(["simulate", f"{HERE}:FlipFlop", "--out", str(out), "--signals", "x,c"])
    assert status == 1
    assert "did not converge" in capsys.readouterr().err
    header, data = read_csv(out)
    assert header == ["time", "x", "c"]
    assert data[-1, 0] == pytest.approx(0.5) and data[-1, 1] == pytest.approx(0.5)
    assert data[0, 0] == 0.0


# --------------------------------------------------------------------------
# 3. bad command-line input: status 2 and a clear message


def assert_usage_error(status, captured, *words):
    assert status == 2
    assert "Traceback" not in captured.err
    assert "error" in captured.err
    for word in words:
        assert word in captured.err, f"{word!r} not in {captured.err!r}"


def test_unknown_model_name(in_tmp, capsys):
    status = main(["simulate", f"{HERE}:Nope"])
    captured = capsys.readouterr()
    assert_usage_error(status, captured, "Nope", "FlipFlop", "Chatter", "BlowUp")
    assert not list(in_tmp.iterdir())  # nothing written


def test_name_that_is_not_a_model(in_tmp, capsys):
    status = main(["simulate", f"{HERE}:check_failed_result"])
    assert_usage_error(status, capsys.readouterr(), "check_failed_result", "not a Model")


def test_file_without_a_model(in_tmp, capsys):
    path = write(in_tmp, "helpers.py", """
        import math


        class Helper:
            pass


        def area(r):
            return math.pi * r ** 2
        """)
    status = main(["simulate", str(path)])
    assert_usage_error(status, capsys.readouterr(), "helpers.py", "no subclass of acausal.Model", "Helper")


def test_missing_file(in_tmp, capsys):
    status = main(["simulate", str(in_tmp / "nowhere.py")])
    assert_usage_error(status, capsys.readouterr(), "nowhere.py", "not found")


def test_file_with_several_models_needs_a_name(in_tmp, capsys):
    status = main(["simulate", str(HERE)])
    assert_usage_error(status, capsys.readouterr(), "several models", ":BlowUp")


@pytest.mark.parametrize("argv, words", [
    (["simulate", "{model}", "--frobnicate"], ["unrecognized arguments", "--frobnicate"]),
    (["--frobnicate", "simulate", "{model}"], ["unrecognized arguments", "--frobnicate"]),
    (["simulate", "{model}", "--rtol", "tight"], ["--rtol", "not a number", "tight"]),
    (["simulate", "{model}", "--rtol", "0"], ["--rtol", "positive"]),
    (["simulate", "{model}", "--rtol", "nan"], ["--rtol", "positive"]),
    (["simulate", "{model}", "--stop-time", "inf"], ["--stop-time", "finite"]),
    (["simulate", "{model}", "--interval", "-0.1"], ["--interval"]),
    (["simulate", "{model}", "--method", "Heun"], ["--method", "Heun", "RK45"]),
    (["simulate", "{model}", "--stop-time", "-1"], ["stop time", "start time"]),
    (["simulate"], ["MODEL"]),
    (["simulate", "{model}", "--rtol"], ["--rtol", "expected one argument"]),
    (["frobnicate"], ["invalid choice", "frobnicate"]),
    ([], ["simulate", "compare"]),
    (["compare", "{model}", "--rtol", "x"], ["--rtol", "not a number"]),
])
def test_bad_options(in_tmp, capsys, argv, words):
    """Unknown options, values that are not numbers, unknown methods: status 2, the culprit named."""
    argv = [a.format(model=f"{HERE}:BlowUp") for a in argv]
    status = main(argv)
    captured = capsys.readouterr()
    if argv:
        assert_usage_error(status, captured, *words)
    else:  # no command: the help goes to stderr
        assert status == 2
        for word in words:
            assert word in captured.err
    assert not list(in_tmp.glob("*.csv"))  # nothing simulated, nothing written


# --------------------------------------------------------------------------
# 4. acausal compare with a broken reference folder


MODELICA_CLASS = "Modelica.Test.Decay"

DECAY_SOURCE = f"""
    from acausal import Eq, Experiment, Model, Variable, der


    class Decay(Model):
        modelica_class = "{MODELICA_CLASS}"
        experiment = Experiment(stop_time=1.0, interval=0.1)
        x = Variable(start=1.0, fixed=True)

        def equations(self):
            return [Eq(der(self.x), -self.x)]
    """

GOOD_CSV = "\n".join(['"time","x"'] + [f"{t / 10!r},{float(np.exp(-t / 10))!r}" for t in range(11)]) + "\n"


def reference_folder(root: Path, *, csv_text=GOOD_CSV, signals="time\nx\n",
                     creation="StartTime=0\nStopTime=1\nInterval=0.1\nTolerance=1e-6\n") -> Path:
    """A reference folder for MODELICA_CLASS under root; None for a file leaves it out."""
    folder = root / MODELICA_CLASS
    folder.mkdir(parents=True)
    for name, text in (("Decay.csv", csv_text), ("comparisonSignals.txt", signals),
                       ("creation.txt", creation)):
        if text is not None:
            (folder / name).write_text(text)
    return root


def test_compare_with_good_reference_folder_passes(in_tmp, capsys):
    """The hand-made reference folder is valid: the comparison runs and passes (status 0)."""
    model = write(in_tmp, "decay.py", DECAY_SOURCE)
    refs = reference_folder(in_tmp / "refs")
    status = main(["compare", str(model), "--reference-dir", str(refs)])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    assert "1 of 1 signals passed" in captured.out


@pytest.mark.parametrize("broken, words", [
    (dict(signals=None), ["comparisonSignals.txt", "not found"]),
    (dict(signals="\n"), ["comparisonSignals.txt", "lists no signals"]),
    (dict(signals="time\ny\n"), ["comparisonSignals.txt", "y", "not a column"]),
    (dict(csv_text=GOOD_CSV.replace("0.5,", "zero.five,")), ["Decay.csv", "line 7", "not a number"]),
    (dict(csv_text='"time","x"\n0,1,2\n0.1,0.9\n'), ["Decay.csv", "line 2", "3 values for 2 columns"]),
    (dict(csv_text='"t","x"\n0,1\n1,0.3\n'), ["Decay.csv", "no 'time' column"]),
    (dict(csv_text='"time","x"\n0,1\n'), ["Decay.csv", "at least 2"]),
    (dict(csv_text=""), ["Decay.csv", "empty"]),
    (dict(csv_text='"time","x"\n0.5,1\n0.1,0.9\n'), ["Decay.csv", "time goes backwards"]),
    (dict(csv_text='"time","x"\n0,1\n0.1,inf\n'), ["Decay.csv", "line 3", "finite"]),
    (dict(csv_text=None), ["Decay.csv", "not found"]),
    (dict(creation="StartTime=0\n"), ["creation.txt", "StopTime"]),
    (dict(creation="StartTime=0\nStopTime=one\n"), ["creation.txt", "not a number"]),
])
def test_compare_with_broken_reference_folder(in_tmp, capsys, broken, words):
    """Malformed reference files: ReferenceDataError named with the file (and line), status 2."""
    model = write(in_tmp, "decay.py", DECAY_SOURCE)
    refs = reference_folder(in_tmp / "refs", **broken)
    status = main(["compare", str(model), "--reference-dir", str(refs)])
    captured = capsys.readouterr()
    assert_usage_error(status, captured, "ReferenceDataError", *words)
    assert "hint:" in captured.err


def test_compare_reference_dir_without_the_class(in_tmp, capsys):
    """A reference folder without the model's class: status 2, the available classes listed."""
    model = write(in_tmp, "decay.py", DECAY_SOURCE)
    refs = in_tmp / "refs"
    (refs / "Modelica.Other.Model").mkdir(parents=True)
    status = main(["compare", str(model), "--reference-dir", str(refs)])
    assert_usage_error(status, capsys.readouterr(), MODELICA_CLASS, "Modelica.Other.Model")


def test_reference_errors_are_documented_errors(tmp_path):
    """load_reference raises ReferenceDataError (an AcausalError and a ValueError) for the same folders."""
    from acausal.tools.compare import load_reference

    refs = reference_folder(tmp_path, signals=None)
    with pytest.raises(ReferenceDataError) as info:
        load_reference(MODELICA_CLASS, refs)
    assert isinstance(info.value, AcausalError) and isinstance(info.value, ValueError)
    assert info.value.hint
