"""Tests of acausal.tools.compare: the csv-compare tube test and the reference loader.

Hand-made curves use grids and tolerances chosen so that the window ends
``t +- dx`` fall exactly on sample times or clearly between them; then the
expected bounds can be written down without floating-point doubt.
"""

from __future__ import annotations

import re

import gzip
import math
import os
from pathlib import Path
from types import MappingProxyType

import numpy as np
import pytest

from acausal.tools import compare
from acausal.tools.compare import (
    Comparison,
    Reference,
    SignalComparison,
    compare_signals,
    load_reference,
    plot_signal,
    reference_dir,
    tube,
    tube_size,
)
from acausal.errors import ReferenceDataError

FIRST = "Modelica.Mechanics.Rotational.Examples.First"

REPO = Path(__file__).resolve().parents[2]

#: The references that ship with acausal (library/reference/msl-4.1.0 in the repository).
BUNDLED = REPO / "library" / "reference" / "msl-4.1.0"

#: The classes whose references ship: those the examples reproduce.
def _examples_classes() -> tuple[str, ...]:
    """The Modelica classes the examples reproduce (their models' ``modelica_class``)."""
    import importlib
    import inspect

    from acausal import Model

    examples = Path(__file__).resolve().parents[2] / "examples"
    found = set()
    for path in sorted(examples.glob("*.py")):
        module = importlib.import_module(f"examples.{path.stem}")
        found |= {klass.modelica_class for _, klass in inspect.getmembers(module, inspect.isclass)
                  if issubclass(klass, Model) and klass.__module__ == module.__name__
                  and getattr(klass, "modelica_class", None)}
    return tuple(sorted(found))


BUNDLED_CLASSES = _examples_classes()

#: The team's full copy of MAP-LIB_ReferenceResults v4.1.0, beside the checkout (may be absent).
#: The team's full copy of the reference results: $ACAUSAL_REFERENCE_DIR when set, else ../shared beside the checkout.
SHARED = (Path(os.environ["ACAUSAL_REFERENCE_DIR"]) if os.environ.get("ACAUSAL_REFERENCE_DIR")
          else Path(__file__).resolve().parents[3] / "shared" / "reference" / "msl-4.1.0")


# ---------------------------------------------------------------------------
# Helpers
# ---------------------------------------------------------------------------


def make_reference(time, signals: dict[str, np.ndarray], name: str = "Test.Model") -> Reference:
    """A Reference built in memory (no files)."""
    time = np.asarray(time, dtype=float)
    return Reference(
        modelica_class=name,
        time=time,
        signals=MappingProxyType({k: np.asarray(v, dtype=float) for k, v in signals.items()}),
        compared=tuple(signals),
        start_time=float(time[0]),
        stop_time=float(time[-1]),
        interval=None,
        tolerance=None,
        path=Path("."),
    )


def step_curve(at: float, n: int = 1001) -> tuple[np.ndarray, np.ndarray]:
    """0 before ``at``, 1 from ``at`` on, on a grid 0..1 with the event time twice."""
    grid = np.linspace(0.0, 1.0, n)
    t = np.sort(np.concatenate([grid[grid != at], [at, at]]))
    y = (t >= at).astype(float)
    first = np.searchsorted(t, at)
    y[first] = 0.0  # left limit of the event pair
    return t, y


# ---------------------------------------------------------------------------
# reference_dir
# ---------------------------------------------------------------------------


def test_reference_dir_prefers_override_then_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("ACAUSAL_REFERENCE_DIR", str(tmp_path / "from-env"))
    assert reference_dir(tmp_path / "given") == tmp_path / "given"
    assert reference_dir() == tmp_path / "from-env"

    monkeypatch.delenv("ACAUSAL_REFERENCE_DIR")
    assert reference_dir() == BUNDLED
    assert compare.bundled_reference_dir() == BUNDLED

    monkeypatch.setenv("ACAUSAL_REFERENCE_DIR", "")  # set but empty: as if unset
    assert reference_dir() == BUNDLED


def test_reference_dir_default_does_not_import_the_libraries():
    """Finding the bundled folder must not load the component libraries."""
    import subprocess
    import sys

    code = ("import sys; from acausal.tools.compare import bundled_reference_dir; "
            "print(bundled_reference_dir()); print('acausal.library' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.split("\n")[:2] == [str(BUNDLED), "False"]


# ---------------------------------------------------------------------------
# tube_size and tube on hand-made curves
# ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    "level, expected_dy",
    [
        (5.0, 2e-3 * 5.0),  # range 0, so |y_min| = 5 sets the height
        (-3.0, 2e-3 * 3.0),  # |y_min| of a negative constant
        (0.0, 2e-3 * 1e-3),  # the nominal value 1e-3 keeps the tube open
        (2e-4, 2e-3 * 1e-3),  # |y_min| below the nominal value
    ],
)
def test_constant_signal_tube(level, expected_dy):
    t = np.linspace(0.0, 2.0, 11)
    y = np.full_like(t, level)
    dx, dy = tube_size(t, y)
    assert dx == pytest.approx(2e-3 * 2.0)
    assert dy == pytest.approx(expected_dy)
    lower, upper = tube(t, y)
    np.testing.assert_allclose(lower, level - expected_dy)
    np.testing.assert_allclose(upper, level + expected_dy)


def test_tube_size_uses_range_or_lowest_magnitude():
    t = np.array([0.0, 1.0, 2.0, 4.0])
    # range 2 beats |y_min| = 1
    assert tube_size(t, [1.0, 3.0, 2.0, 1.5])[1] == pytest.approx(2e-3 * 2.0)
    # |y_min| = 10 beats range 1
    assert tube_size(t, [10.0, 11.0, 10.5, 10.0])[1] == pytest.approx(2e-3 * 10.0)
    # width from the time range
    assert tube_size(t, [0.0, 1.0, 0.0, 1.0], rel_tol=0.01)[0] == pytest.approx(0.04)


def test_ramp_tube_follows_the_shifted_ramp():
    # y = t sampled every 0.1; dx = dy = 2e-3.  Windows hold only their own
    # sample, so the extremes are the ramp's values at t -+ dx.
    t = np.linspace(0.0, 1.0, 11)
    lower, upper = tube(t, t)
    expected_upper = t + 2e-3 + 2e-3
    expected_lower = t - 2e-3 - 2e-3
    # At the ends the window is cut off by the data range.
    expected_upper[-1] = 1.0 + 2e-3
    expected_lower[0] = 0.0 - 2e-3
    np.testing.assert_allclose(upper, expected_upper, rtol=0, atol=1e-15)
    np.testing.assert_allclose(lower, expected_lower, rtol=0, atol=1e-15)


def test_tube_between_samples_interpolates_the_window_ends():
    t = np.linspace(0.0, 1.0, 11)
    lower, upper = tube(t, t, at=[0.05, 1.001, 1.01, -0.01])
    # 0.05: window [0.048, 0.052] holds no sample
    assert lower[0] == pytest.approx(0.048 - 2e-3)
    assert upper[0] == pytest.approx(0.052 + 2e-3)
    # 1.001: the window [0.999, 1.003] still meets the data
    assert lower[1] == pytest.approx(0.999 - 2e-3)
    assert upper[1] == pytest.approx(1.0 + 2e-3)
    # more than dx outside the data: undefined
    assert np.isnan(lower[2]) and np.isnan(upper[2])
    assert np.isnan(lower[3]) and np.isnan(upper[3])


def test_step_tube_widens_by_dx_in_time():
    # Grid of 1/256, rel_tol 1/64: dx = 4 grid steps and dy = 1/64, all exact
    # in binary, so the closed window [t - dx, t + dx] is tested exactly.
    h = 1.0 / 256.0
    t, y = step_curve(0.5, n=257)
    dx, dy = tube_size(t, y, rel_tol=1 / 64)
    assert (dx, dy) == (4 * h, 1 / 64)

    lower, upper = tube(t, y, rel_tol=1 / 64)
    # upper jumps to 1 + dy as soon as the window reaches the step at 0.5
    np.testing.assert_array_equal(upper, np.where(t >= 0.5 - 4 * h, 1 + dy, dy))
    # lower stays at -dy while the window still reaches the left limit at 0.5
    np.testing.assert_array_equal(lower, np.where(t <= 0.5 + 4 * h, -dy, 1 - dy))

    # Half a grid step further out the window just misses the step.
    lo, hi = tube(t, y, rel_tol=1 / 64, at=[0.5 - 4.5 * h, 0.5 + 4.5 * h])
    assert hi[0] == dy and lo[0] == -dy
    assert hi[1] == 1 + dy and lo[1] == 1 - dy


def test_tube_matches_brute_force_on_random_curves():
    rng = np.random.default_rng(7)
    for _ in range(40):
        t = np.sort(rng.uniform(0.0, 1.0, rng.integers(2, 40)))
        t = np.sort(np.concatenate([t, t[rng.integers(0, t.size, 2)]]))  # events
        y = rng.normal(size=t.size)
        query = np.concatenate([t, rng.uniform(-0.2, 1.2, 30)])
        rel_tol = rng.uniform(0.001, 0.2)
        dx, dy = tube_size(t, y, rel_tol)
        lower, upper = tube(t, y, rel_tol, at=query)
        for q, lo, hi in zip(query, lower, upper):
            # the piecewise-linear curve, densely sampled on the window
            inside = (t >= q - dx) & (t <= q + dx)
            ends = [e for e in (q - dx, q + dx) if t[0] <= e <= t[-1]]
            values = list(y[inside]) + list(np.interp(ends, t, y))
            if not values:
                assert np.isnan(lo) and np.isnan(hi)
                continue
            assert lo == pytest.approx(min(values) - dy, abs=1e-12)
            assert hi == pytest.approx(max(values) + dy, abs=1e-12)


def test_tube_is_fast_on_long_curves():
    t = np.linspace(0.0, 1.0, 15001)
    y = np.sin(40 * t)
    lower, upper = tube(t, y)  # must not be O(n^2) in Python
    assert np.all(lower <= y) and np.all(upper >= y)


def test_tube_rejects_time_going_backwards():
    with pytest.raises(ValueError, match="non-decreasing"):
        tube([0.0, 1.0, 0.5], [0.0, 1.0, 2.0])


# ---------------------------------------------------------------------------
# compare_signals on hand-made curves
# ---------------------------------------------------------------------------


@pytest.fixture
def ramp_reference() -> Reference:
    # y = 1 + 0.1 t: dx = 2e-3, dy = 2e-3 * max(0.1, 1, 1e-3) = 2e-3
    t = np.linspace(0.0, 1.0, 1001)
    return make_reference(t, {"y": 1.0 + 0.1 * t})


@pytest.mark.parametrize("check_at", ["result", "reference", "both"])
def test_identical_signal_passes(ramp_reference, check_at):
    ref = ramp_reference
    outcome = compare_signals(ref, ref.time, ref.signals, check_at=check_at)
    assert isinstance(outcome, Comparison)
    assert outcome.passed and outcome.failures == ()
    (signal,) = outcome.signals
    assert signal == SignalComparison("y", True, 0.0, None, pytest.approx(2e-3), 0.0, 0, "")


def test_offset_by_two_dy_fails_by_one_dy(ramp_reference):
    ref = ramp_reference
    dy = 2e-3
    outcome = compare_signals(ref, ref.time, {"y": ref.signals["y"] + 2 * dy})
    signal = outcome["y"]
    assert not signal.passed and not outcome.passed
    # In the interior upper = y(t + dx) + dy = y + 0.1 dx + dy, so the excess is
    # (2 dy - dy - 0.1 dx) / dy = 0.9; at t = 1 the window is cut off and the
    # excess is exactly (2 dy - dy) / dy = 1.
    assert signal.worst_violation == pytest.approx(1.0)
    assert signal.first_failure_time == 0.0
    assert signal.failed_points == ref.time.size
    assert signal.max_abs_error == pytest.approx(2 * dy)
    assert outcome.failures == (signal,)


def test_offset_below_fails_on_the_lower_side(ramp_reference):
    ref = ramp_reference
    outcome = compare_signals(ref, ref.time, {"y": ref.signals["y"] - 3 * 2e-3})
    # at t = 0 lower = y(0) - dy, so the excess is (3 dy - dy) / dy = 2
    assert outcome["y"].worst_violation == pytest.approx(2.0)
    assert outcome["y"].first_failure_time == 0.0


def test_offset_inside_the_tube_passes(ramp_reference):
    ref = ramp_reference
    outcome = compare_signals(ref, ref.time, {"y": ref.signals["y"] + 0.5 * 2e-3})
    assert outcome.passed
    assert outcome["y"].worst_violation == 0.0
    assert outcome["y"].max_abs_error == pytest.approx(1e-3)


@pytest.mark.parametrize("check_at", ["result", "reference", "both"])
def test_step_shifted_less_than_dx_passes(check_at):
    t, y = step_curve(0.5)  # dx = 2e-3, dy = 2e-3
    ref = make_reference(t, {"s": y})
    for shifted_to in (0.499, 0.501):
        rt, ry = step_curve(shifted_to)
        outcome = compare_signals(ref, rt, {"s": ry}, check_at=check_at)
        assert outcome.passed, outcome.table()


@pytest.mark.parametrize("check_at", ["result", "reference", "both"])
def test_step_shifted_more_than_dx_fails(check_at):
    t, y = step_curve(0.5)
    ref = make_reference(t, {"s": y})

    late_t, late_y = step_curve(0.505)
    late = compare_signals(ref, late_t, {"s": late_y}, check_at=check_at)["s"]
    assert not late.passed
    # The tube's lower bound rises to 1 - dy once the window has left the
    # step at 0.5, i.e. just after t = 0.502 (the grid step is 1e-3).
    assert 0.502 <= late.first_failure_time <= 0.503
    assert late.worst_violation == pytest.approx((1 - 2e-3) / 2e-3)

    early_t, early_y = step_curve(0.495)
    early = compare_signals(ref, early_t, {"s": early_y}, check_at=check_at)["s"]
    assert not early.passed
    # The result's right limit at 0.495 is the first point outside (at the
    # reference point 0.495 the left limit is used, so there it is 0.496).
    assert early.first_failure_time == pytest.approx(0.495 if check_at != "reference" else 0.496)


def test_event_pairs_are_matched_left_to_left_and_right_to_right():
    t, y = step_curve(0.5)
    ref = make_reference(t, {"s": y})
    # Result on another grid, with the same event pair at 0.5.
    rt, ry = step_curve(0.5, n=101)
    outcome = compare_signals(ref, rt, {"s": ry}, check_at="reference")
    assert outcome.passed
    assert outcome["s"].max_abs_error == 0.0


def test_coarse_result_checked_at_reference_points_is_stricter():
    t = np.linspace(0.0, 1.0, 1001)
    ref = make_reference(t, {"y": np.sin(2 * np.pi * t)})
    coarse = np.linspace(0.0, 1.0, 5)
    result = {"y": np.sin(2 * np.pi * coarse)}
    # Its own five samples are exact, which is all csv-compare looks at ...
    assert compare_signals(ref, coarse, result, check_at="result").passed
    # ... but linear interpolation between them cuts the sine's corners.
    assert not compare_signals(ref, coarse, result, check_at="reference").passed
    assert not compare_signals(ref, coarse, result, check_at="both").passed


def test_missing_signal_fails_with_a_note(ramp_reference):
    outcome = compare_signals(ramp_reference, ramp_reference.time, {})
    signal = outcome["y"]
    assert not signal.passed
    assert signal.worst_violation == math.inf
    assert "missing" in signal.note
    assert "missing" in outcome.table()


def test_result_that_stops_early_fails(ramp_reference):
    ref = ramp_reference
    half = ref.time <= 0.5
    outcome = compare_signals(ref, ref.time[half], {"y": ref.signals["y"][half]})
    signal = outcome["y"]
    assert not signal.passed
    assert signal.worst_violation == 0.0  # the points it has are fine
    assert "covers" in signal.note


def test_nan_in_result_fails(ramp_reference):
    ref = ramp_reference
    y = ref.signals["y"].copy()
    y[300] = np.nan
    signal = compare_signals(ref, ref.time, {"y": y})["y"]
    assert not signal.passed
    assert signal.worst_violation == math.inf
    assert signal.first_failure_time == pytest.approx(0.3)
    assert "NaN" in signal.note


def test_bad_arguments_are_rejected(ramp_reference):
    ref = ramp_reference
    with pytest.raises(ValueError, match="non-decreasing"):
        compare_signals(ref, ref.time[::-1], ref.signals)
    with pytest.raises(ValueError, match="result signal y"):
        compare_signals(ref, ref.time, {"y": ref.signals["y"][:-1]})
    with pytest.raises(ReferenceDataError, match="nope"):
        compare_signals(ref, ref.time, ref.signals, signals=["nope"])
    with pytest.raises(ValueError, match="check_at"):
        compare_signals(ref, ref.time, ref.signals, check_at="everywhere")


def test_table_lists_every_signal():
    t = np.linspace(0.0, 1.0, 101)
    ref = make_reference(t, {"a": t, "b": 2 * t})
    outcome = compare_signals(ref, t, {"a": t, "b": 2 * t + 1})
    text = outcome.table()
    lines = text.splitlines()
    assert lines[0].split()[:2] == ["signal", "result"]
    assert lines[2].split()[:2] == ["a", "pass"]
    assert lines[3].split()[:2] == ["b", "FAIL"]
    assert "1 of 2 signals passed" in lines[-1]


def test_plot_signal_writes_a_png(tmp_path):
    pytest.importorskip("matplotlib")
    t, y = step_curve(0.5, n=201)
    ref = make_reference(t, {"s": y})
    rt, ry = step_curve(0.52, n=201)
    path = plot_signal(ref, "s", rt, {"s": ry}, tmp_path / "s.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


# ---------------------------------------------------------------------------
# Real MSL reference data
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def first() -> Reference:
    folder = reference_dir()
    # the bundled copy is always there; a folder chosen with ACAUSAL_REFERENCE_DIR may lack the class
    if folder != BUNDLED and not (folder / FIRST).is_dir():
        pytest.skip(
            f"MSL reference results not found at {folder} (ACAUSAL_REFERENCE_DIR); unset it to "
            "use the bundled copy, or point it at modelica/MAP-LIB_ReferenceResults (branch v4.1.0)"
        )
    return load_reference(FIRST)


def test_load_first(first):
    assert first.modelica_class == FIRST
    assert first.compared == ("damper.phi_rel", "damper.w_rel", "inertia3.phi", "inertia3.w")
    assert set(first.compared) <= set(first.signals)
    assert (first.start_time, first.stop_time) == (0.0, 1.0)
    assert first.interval == 5e-4
    assert first.tolerance == 1e-6
    assert first.time[0] == 0.0 and first.time[-1] == 1.0
    assert np.all(np.diff(first.time) >= 0)
    for values in first.signals.values():
        assert values.shape == first.time.shape
        assert not values.flags.writeable


def test_first_compared_with_itself_passes(first):
    outcome = compare_signals(first, first.time, first.signals, check_at="both")
    assert outcome.passed, outcome.table()
    assert all(s.worst_violation == 0.0 for s in outcome.signals)


def test_first_perturbed_fails(first):
    values = dict(first.signals)
    values["inertia3.w"] = values["inertia3.w"] * 1.01
    outcome = compare_signals(first, first.time, values)
    assert [s.name for s in outcome.failures] == ["inertia3.w"]


# ---------------------------------------------------------------------------
# Malformed reference folders
# ---------------------------------------------------------------------------


GOOD_CSV = '"time","a.x","a.v"\n0,0,1\n0.5,0.5,1\n0.5,0.5,2\n1,1.5,2\n'


def write_folder(root: Path, name: str = "Pkg.Model", csv_text: str = GOOD_CSV,
                 signals: str | None = "time\na.x\na.v\n",
                 creation: str | None = "StartTime=0\nStopTime=1 // from model\nInterval=0.5\n") -> Path:
    folder = root / name
    folder.mkdir(parents=True)
    (folder / f"{name.rsplit('.', 1)[-1]}.csv").write_text(csv_text)
    if signals is not None:
        (folder / "comparisonSignals.txt").write_text(signals)
    if creation is not None:
        (folder / "creation.txt").write_text(creation)
    return folder


def test_load_small_folder(tmp_path):
    write_folder(tmp_path)
    ref = load_reference("Pkg.Model", tmp_path)
    np.testing.assert_array_equal(ref.time, [0, 0.5, 0.5, 1])
    np.testing.assert_array_equal(ref.signals["a.v"], [1, 1, 2, 2])
    assert ref.compared == ("a.x", "a.v")
    assert (ref.start_time, ref.stop_time, ref.interval, ref.tolerance) == (0.0, 1.0, 0.5, None)


def test_missing_folder(tmp_path):
    with pytest.raises(ReferenceDataError) as error:
        load_reference("Pkg.Absent", tmp_path)
    message = str(error.value)
    assert str(tmp_path / "Pkg.Absent") in message
    assert "MAP-LIB_ReferenceResults" in message and "v4.1.0" in message
    assert "ACAUSAL_REFERENCE_DIR" in message


def test_a_reference_listing_only_time_compares_nothing(tmp_path):
    """MAP-LIB's own references do this for models whose check is that they run."""
    write_folder(tmp_path, signals="time\n")
    reference = load_reference("Pkg.Model", tmp_path)
    assert reference.compared == ()
    comparison = compare_signals(reference, reference.time, {})
    assert comparison.passed and comparison.signals == ()
    assert "0 of 0 signals passed" in comparison.table()


def test_missing_folder_uses_environment(tmp_path, monkeypatch):
    monkeypatch.setenv("ACAUSAL_REFERENCE_DIR", str(tmp_path / "elsewhere"))
    with pytest.raises(ReferenceDataError, match="elsewhere"):
        load_reference("Pkg.Model")


@pytest.mark.parametrize(
    "kwargs, file_name, words",
    [
        ({"signals": None}, "comparisonSignals.txt", "not found"),
        ({"signals": "\n"}, "comparisonSignals.txt", "no signals"),
        ({"signals": "time\na.x\na.w\n"}, "comparisonSignals.txt", "a.w"),
        ({"creation": None}, "creation.txt", "not found"),
        ({"creation": "StartTime=0\n"}, "creation.txt", "StopTime"),
        ({"creation": "StartTime=0\nStopTime=soon\n"}, "creation.txt", "not a number"),
        ({"csv_text": GOOD_CSV.replace("0.5,0.5,2", "0.5,abc,2")}, "Model.csv", "'abc'"),
        ({"csv_text": GOOD_CSV.replace("0.5,0.5,2", "0.5,2")}, "Model.csv", "2 values for 3 columns"),
        ({"csv_text": GOOD_CSV.replace('"time"', '"t_"')}, "Model.csv", "no 'time' column"),
        ({"csv_text": GOOD_CSV.replace("1,1.5,2", "0.2,1.5,2")}, "Model.csv", "backwards"),
        ({"csv_text": '"time","a.x","a.v"\n'}, "Model.csv", "data line"),
        ({"csv_text": ""}, "Model.csv", "empty"),
        ({"csv_text": GOOD_CSV.replace("0,0,1", "0,nan,1")}, "Model.csv", "finite"),
    ],
)
def test_malformed_folder(tmp_path, kwargs, file_name, words):
    write_folder(tmp_path, **kwargs)
    with pytest.raises(ReferenceDataError) as error:
        load_reference("Pkg.Model", tmp_path)
    message = str(error.value)
    assert file_name in message
    assert words in message
    assert "hint:" in message
    assert isinstance(error.value, ValueError)


def test_nested_map_lib_layout_is_found(tmp_path):
    """A MAP-LIB_ReferenceResults checkout nests the class path in folders; it loads the same."""
    import shutil

    source = reference_dir() / "Modelica.Mechanics.Rotational.Examples.First"
    if reference_dir() != BUNDLED and not source.is_dir():
        pytest.skip(f"MSL reference results not found at {reference_dir()} (ACAUSAL_REFERENCE_DIR)")
    nested = tmp_path.joinpath("Modelica", "Mechanics", "Rotational", "Examples", "First")
    shutil.copytree(source, nested)
    flat = load_reference("Modelica.Mechanics.Rotational.Examples.First")
    deep = load_reference("Modelica.Mechanics.Rotational.Examples.First", tmp_path)
    assert deep.compared == flat.compared
    np.testing.assert_array_equal(deep.time, flat.time)


# ---------------------------------------------------------------------------
# The references bundled with acausal
# ---------------------------------------------------------------------------


def test_bundled_folder_holds_exactly_the_examples_references():
    assert sorted(p.name for p in BUNDLED.iterdir()) == sorted(BUNDLED_CLASSES)
    for modelica_class in BUNDLED_CLASSES:
        name = modelica_class.rsplit(".", 1)[-1]
        assert sorted(p.name for p in (BUNDLED / modelica_class).iterdir()) == sorted(
            [f"{name}.csv.gz", "comparisonSignals.txt", "creation.txt"])
    assert (BUNDLED.parent / "LICENSE").is_file()
    assert "Modelica Association" in (BUNDLED.parent / "LICENSE").read_text()
    assert "MAP-LIB_ReferenceResults" in (BUNDLED.parent / "README.md").read_text()


def test_bundled_archives_are_reproducible():
    """``gzip -9n``: no file name and no time stamp in the header, so the bytes depend on the data only."""
    for path in BUNDLED.rglob("*.gz"):
        header = path.read_bytes()[:10]
        assert header[:3] == b"\x1f\x8b\x08", path
        assert header[3] & 0x08 == 0, f"{path} stores a file name"
        assert header[4:8] == b"\0\0\0\0", f"{path} stores a time stamp"


def test_bundled_files_are_the_team_copy_unchanged():
    """Every bundled file, decompressed, is byte-identical to MAP-LIB_ReferenceResults (the shared copy)."""
    if not SHARED.is_dir():
        pytest.skip(f"the full reference copy {SHARED} is absent; nothing to compare the bundled files with")
    files = sorted(p for p in BUNDLED.rglob("*") if p.is_file())
    assert len(files) == 3 * len(BUNDLED_CLASSES)
    for path in files:
        relative = path.relative_to(BUNDLED)
        if path.suffix == ".gz":
            data, original = gzip.decompress(path.read_bytes()), SHARED / relative.with_suffix("")
        else:
            data, original = path.read_bytes(), SHARED / relative
        assert data == original.read_bytes(), f"{path} differs from {original}"


@pytest.mark.parametrize("modelica_class", BUNDLED_CLASSES)
def test_bundled_references_load(modelica_class):
    ref = load_reference(modelica_class, BUNDLED)
    assert ref.path == BUNDLED / modelica_class
    # Dymola's tolerance: 1e-6 where the model has no tolerance annotation, else the annotation's
    # (a tenth of it in MAP-LIB's runs: 1e-7 for most electrical examples, 1e-10 for
    # NormalNoiseProperties), as the creation log says
    creation = (BUNDLED / modelica_class / "creation.txt").read_text()
    logged = float(re.search(r"^Tolerance\s*=\s*([0-9.eE+-]+)", creation, re.M).group(1))
    assert ref.tolerance == logged and ref.tolerance in (1e-6, 1e-7, 1e-10)
    assert set(ref.compared) <= set(ref.signals)
    assert ref.time[0] == ref.start_time and ref.time[-1] == ref.stop_time


def test_class_not_bundled_names_the_bundled_folder_and_the_environment(monkeypatch):
    monkeypatch.delenv("ACAUSAL_REFERENCE_DIR", raising=False)
    with pytest.raises(ReferenceDataError) as error:
        load_reference("Modelica.Mechanics.Rotational.Examples.ElasticBearing")
    message = str(error.value)
    assert str(BUNDLED) in message
    assert "bundled" in message
    assert "ACAUSAL_REFERENCE_DIR" in message and "--reference-dir" in message
    assert "MAP-LIB_ReferenceResults" in message
    assert FIRST in message  # the classes that are there
    assert isinstance(error.value, ValueError)


def test_class_missing_from_the_environment_folder_names_it(tmp_path, monkeypatch):
    monkeypatch.setenv("ACAUSAL_REFERENCE_DIR", str(tmp_path))
    with pytest.raises(ReferenceDataError) as error:
        load_reference(FIRST)
    message = str(error.value)
    assert str(tmp_path / FIRST) in message
    assert "ACAUSAL_REFERENCE_DIR" in message
    assert "bundled" not in message


def test_csv_gz_and_csv_load_the_same(tmp_path):
    plain = write_folder(tmp_path / "plain")
    packed = write_folder(tmp_path / "packed")
    csv_path = packed / "Model.csv"
    (packed / "Model.csv.gz").write_bytes(gzip.compress(csv_path.read_bytes()))
    csv_path.unlink()
    a = load_reference("Pkg.Model", tmp_path / "plain")
    b = load_reference("Pkg.Model", tmp_path / "packed")
    assert b.path == packed and a.path == plain
    assert a.compared == b.compared
    np.testing.assert_array_equal(a.time, b.time)
    assert a.signals.keys() == b.signals.keys()
    for name in a.signals:
        np.testing.assert_array_equal(a.signals[name], b.signals[name])


def test_real_csv_gz_and_csv_load_the_same(tmp_path):
    """The bundled First.csv.gz and the same file decompressed give the same reference."""
    import shutil

    folder = tmp_path / FIRST
    shutil.copytree(BUNDLED / FIRST, folder)
    (folder / "First.csv").write_bytes(gzip.decompress((folder / "First.csv.gz").read_bytes()))
    (folder / "First.csv.gz").unlink()
    a = load_reference(FIRST, tmp_path)
    b = load_reference(FIRST, BUNDLED)
    assert (a.compared, a.start_time, a.stop_time, a.interval, a.tolerance) == (
        b.compared, b.start_time, b.stop_time, b.interval, b.tolerance)
    np.testing.assert_array_equal(a.time, b.time)
    assert a.signals.keys() == b.signals.keys()
    for name in a.signals:
        np.testing.assert_array_equal(a.signals[name], b.signals[name])


def test_plain_csv_is_preferred_to_csv_gz(tmp_path):
    folder = write_folder(tmp_path)
    other = GOOD_CSV.replace("1,1.5,2", "1,1.5,3")
    (folder / "Model.csv.gz").write_bytes(gzip.compress(other.encode()))
    np.testing.assert_array_equal(load_reference("Pkg.Model", tmp_path).signals["a.v"], [1, 1, 2, 2])
    (folder / "Model.csv").unlink()
    np.testing.assert_array_equal(load_reference("Pkg.Model", tmp_path).signals["a.v"], [1, 1, 2, 3])


def test_broken_csv_gz(tmp_path):
    folder = write_folder(tmp_path)
    (folder / "Model.csv.gz").write_bytes(gzip.compress(GOOD_CSV.encode())[:-12])  # truncated
    (folder / "Model.csv").unlink()
    with pytest.raises(ReferenceDataError) as error:
        load_reference("Pkg.Model", tmp_path)
    assert "Model.csv.gz" in str(error.value) and "hint:" in str(error.value)
    (folder / "Model.csv.gz").write_bytes(GOOD_CSV.encode())  # not compressed at all
    with pytest.raises(ReferenceDataError, match="Model.csv.gz"):
        load_reference("Pkg.Model", tmp_path)
