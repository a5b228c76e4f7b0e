"""The work-precision benchmark: exact-solution cases, files written, effects on demand.

The cases are defined in ``examples/benchmarks.py`` (the suite, ``bench.suite()``);
``acausal.tools.bench`` is the machinery that runs them.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from acausal import Experiment, Model
from acausal.tools import bench

benchmarks = bench.suite()


def test_exact_solutions_are_consistent():
    t_b, t_s = benchmarks.stick_slip_times()
    assert t_b == pytest.approx(math.asin(0.1) / (2 * math.pi))
    assert 0.5 < t_s < 1.0 and abs(float(benchmarks.stick_slip_exact(t_s))) < 1e-12
    assert benchmarks.stick_slip_stop_time() == pytest.approx(1.1 * t_s)
    assert benchmarks.CD_T_STOP == 4.0
    np.testing.assert_allclose(benchmarks.coast_down_exact([0, 2, 4, 5]), [3, 1.5, 0, 0])


def test_the_suite_defines_the_cases():
    """bench.py runs what examples/benchmarks.py defines, in its order."""
    table = bench.cases()
    assert list(table) == ["CoastDown", "StickSlip", "First", "TwoMasses", "Friction", "CoupledClutches"]
    assert all(name in table for name in benchmarks.QUICK_CASES)
    assert all(name in table for name, _ in benchmarks.COMMAND_TARGETS)
    assert table["StickSlip"].stop_time == pytest.approx(benchmarks.stick_slip_stop_time())
    assert [c.name for c in table.values() if c.reference is None] == ["CoastDown", "StickSlip"]
    assert [name for name, _, _ in benchmarks.effects_cases(3)] == ["BearingHeating", "DriveTrain3 (heat ports)"]


@pytest.mark.parametrize("name", ["CoastDown", "StickSlip"])
def test_exact_cases_converge(name):
    run = bench.run_case(bench.get_case(name), ["RK45"], [1e-5, 1e-9], repeats=0)
    assert run.translation.status == 0 and run.translation.modes >= 1
    loose, tight = run.records
    for record in run.records:
        assert record.status == 0, record.message
        assert math.isfinite(record.error) and math.isfinite(record.event_error)
        assert record.sim_seconds > 0 and record.rhs_evaluations > 0
    if name == "StickSlip":
        assert tight.error < loose.error / 10
        assert tight.event_error < loose.event_error
        assert tight.error < 1e-6
    else:
        # w is linear in t, so every rtol integrates it exactly; what is left is
        # the relation hysteresis at the stop
        assert tight.error <= loose.error * 1.01 + 1e-12
        assert tight.event_error < 1e-7


def test_run_bench_writes_files(tmp_path):
    result = bench.run_bench(True, tmp_path, methods=["RK45"], rtols=[1e-4, 1e-7],
                             case_names=["CoastDown", "StickSlip"], effects=False, scaling_sizes=(2, 4),
                             isolate_scaling=False, commands=False, soak_runs=0, parameters=False,
                             storm=False, floors=False, table_sizes=False, repeats=1)
    for name in ("bench.md", "bench.csv", "work_precision.png", "scaling.md", "scaling.csv", "scaling.png"):
        assert (tmp_path / name).is_file() and (tmp_path / name).stat().st_size > 0, name
    assert not (tmp_path / "soak.md").exists() and result.soak is None
    assert len(result.records) == 4 and not result.failures
    text = (tmp_path / "bench.md").read_text()
    assert "| StickSlip | RK45 | 1e-04 |" in text and "Fastest method" in text
    assert (tmp_path / "bench.csv").read_text().count("\n") == 5
    assert [p["status"] for p in result.scaling] == ["ok", "ok"]
    assert math.isfinite(result.scaling_fits["translation"][1])


def test_pruning_keeps_the_requested_output():
    make = lambda: benchmarks.drive_train_model(4, heat_ports=True, stop_time=0.5)  # noqa: E731
    record = bench.run_effects_case("DriveTrain4", make, "inertia4.w", rtol=1e-9, repeats=1)
    assert record.status == "ok"
    assert record.max_rel_difference < 1e-6
    assert record.states_kept < record.states_total
    assert record.derivative_steps_kept < record.derivative_steps_full


def test_fresh_process_commands_pass_their_comparison():
    """The commands the speed target is measured on run as a user runs them, and pass."""
    from acausal.tools.compare import reference_dir

    if not (reference_dir() / "Modelica.Mechanics.Rotational.Examples.First").is_dir():
        pytest.skip(f"MSL reference results not found at {reference_dir()}; set ACAUSAL_REFERENCE_DIR "
                    f"(modelica/MAP-LIB_ReferenceResults, branch v4.1.0)")
    records, imports = bench.run_commands_with_floors(repeats=1)
    assert [(r["command"].split()[1], r["model"], r["disk_cache"]) for r in records] == [
        (verb, m, kind) for verb, m in (("compare", "First"), ("compare", "TwoMasses"),
                                        ("compare", "CoupledClutches"), ("simulate", "First"))
        for kind in ("cold", "warm")]
    assert all(r["passed"] for r in records)
    assert all(r["exit_statuses"] == "0" for r in records)
    # the import floors ran once after each round: one round per command
    assert [(r["label"], r["runs"]) for r in imports] == [("import numpy", 4), ("import numpy, scipy.integrate", 4)]
    walls = {r["command"]: r["import_numpy_wall"] for r in records}  # the floor of each command's own round
    for r in records:
        assert r["import_numpy_wall"] > 0 and r["numpy_scipy_wall"] > r["import_numpy_wall"] / 10
        assert r["x_import_numpy"] == pytest.approx(r["median_wall"] / r["import_numpy_wall"])
    assert imports[0]["min_wall"] <= min(walls.values()) and max(walls.values()) <= imports[0]["max_wall"]
    (ratio_row, *_) = bench.command_floor_ratios(records, imports)
    assert ratio_row["x_import_numpy"] == records[0]["x_import_numpy"]  # the floors section divides alike
    # the warm target commands are broken down by -X importtime; acausal's own import is in it
    broken_down = [r["command"] for r in records if "import_seconds" in r]
    assert broken_down == ["acausal compare examples/first.py", "acausal simulate examples/first.py"]
    for r in records:
        if "import_seconds" in r:
            assert r["import_status"] == 0 and r["import_acausal_seconds"] > 0
            assert r["warm_target_met"] == (r["x_import_numpy"] <= benchmarks.WARM_COMMAND_MAX_X_IMPORT_NUMPY)
    text = bench._commands_markdown(records)
    assert all(r["command"] in text for r in records)
    assert "## Targets" in text and "## Where a warm command's time goes" in text
    checks = bench.command_target_checks(records)
    assert [c.target.split("`")[1] for c in checks] == ["acausal simulate examples/first.py",
                                                       "acausal compare examples/first.py"]
    assert all(c.met is not None for c in checks)


def test_bench_without_reference_data_measures_the_exact_cases(tmp_path, monkeypatch):
    """Cases needing the MSL reference results are skipped with the reason, not crashed on."""
    monkeypatch.setenv("ACAUSAL_REFERENCE_DIR", str(tmp_path / "no-reference"))
    result = bench.run_bench(True, tmp_path, methods=["RK45"], rtols=[1e-6],
                             case_names=["StickSlip", "First"], effects=False, scaling_sizes=(),
                             soak_runs=0, parameters=False, storm=False, floors=False, table_sizes=False,
                             repeats=1)
    assert [run.case.name for run in result.runs] == ["StickSlip"]
    assert set(result.skipped) == {"case First", "fresh-process commands"}
    assert all("no-reference" in why for why in result.skipped.values())
    assert "## Not measured" in (tmp_path / "bench.md").read_text()
    assert (tmp_path / "work_precision.png").stat().st_size > 0


def test_a_failing_command_never_meets_the_target(tmp_path, monkeypatch):
    """Without reference data the commands fail at once, fast: that must not count as met."""
    monkeypatch.setenv("ACAUSAL_REFERENCE_DIR", str(tmp_path / "no-reference"))
    records = bench.run_commands(repeats=1, disk_caches=("cold",))
    compares = [r for r in records if r["command"].startswith("acausal compare")]
    assert [r["passed"] for r in compares] == [False, False, False]
    assert [r["met"] for r in compares] == [False, False, False]
    assert all("no-reference" in r["failure"] for r in compares)
    table = bench._commands_markdown(records).split("## Commands")[1]
    assert sum("**not met**" in line for line in table.splitlines() if "acausal compare" in line) == 3
    # simulate needs no reference results
    assert [r["passed"] for r in records if r["command"].startswith("acausal simulate")] == [True]


class _Spin(Model):
    """The tiniest model: one inertia turning freely."""

    experiment = Experiment(stop_time=0.1, interval=0.01)

    def build(self):
        from acausal.library.rotational import Inertia

        self.inertia = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=1, fixed=True))


def test_soak_records_time_and_memory_per_run(tmp_path):
    soak = bench.run_soak(6, make=_Spin, name="Spin", gc_every=2)
    assert soak.case == "Spin" and soak.n_runs == 6
    assert [(r.mode, r.run) for r in soak.runs] == [(m, i) for m in ("cached", "uncached") for i in range(1, 7)]
    for r in soak.runs:
        assert r.status == 0, r.message
        for value in (r.wall_seconds, r.translate_seconds, r.simulate_seconds, r.rss_mb):
            assert math.isfinite(value) and value > 0
        assert r.max_difference == 0.0  # the same model gives the same result every run
    assert [r.run for r in soak.runs if r.collected] == [2, 4, 6, 2, 4, 6]
    assert [s.mode for s in soak.summaries] == ["cached", "uncached"]
    for s in soak.summaries:
        assert s.runs == 6 and s.failed == 0 and s.window == 2 and s.rss_from_run == 4
        for value in (s.median_seconds, s.first_median_seconds, s.last_median_seconds, s.time_ratio,
                      s.rss_start_mb, s.rss_end_mb, s.median_translate_seconds):
            assert math.isfinite(value) and value > 0
        assert math.isfinite(s.rss_growth_mb_per_100)
        assert s.flat == (s.time_ratio <= bench.SOAK_TIME_RATIO
                          and s.rss_growth_mb_per_100 < bench.SOAK_RSS_MB_PER_100)
    # the cache reuses the translation: later cached runs translate faster than uncached ones
    cached, uncached = soak.summaries
    assert cached.median_translate_seconds < uncached.median_translate_seconds

    files = bench.write_soak(soak, tmp_path)
    assert set(files) == {"soak.md", "soak.csv", "soak.png"}
    assert all(path.stat().st_size > 0 for path in files.values())
    text = (tmp_path / "soak.md").read_text()
    assert "**Verdict: " in text and "| mode | runs | failed | median [s/run] |" in text
    summary = [line for line in text.splitlines() if line.startswith(("| cached |", "| uncached |"))]
    assert len(summary) == 2 + 2 * 4  # the summary rows, then runs 1, 2, 4, 6 of each mode
    with (tmp_path / "soak.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 12
    assert {"case", "mode", "run", "wall_seconds", "rss_mb", "collected", "status"} <= set(rows[0])
    assert all(float(row["wall_seconds"]) > 0 and float(row["rss_mb"]) > 0 for row in rows)


def test_bench_only_soak_writes_only_the_soak(tmp_path, monkeypatch):
    calls = []
    run_soak = bench.run_soak

    def fake_soak(n_runs, log=None):  # the tiny model instead of the suite's
        calls.append(n_runs)
        return run_soak(n_runs, make=_Spin, name="Spin", gc_every=1, log=log)

    monkeypatch.setattr(bench, "run_soak", fake_soak)
    assert bench.main(["--only", "soak", "--soak-runs", "3", "--out", str(tmp_path)]) == 0
    assert calls == [3]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["soak.csv", "soak.md", "soak.png"]


def test_parameter_change_rows_rebind_and_cost_less_than_translating():
    rows = bench.run_parameter_change(repeats=1)
    labels = [r["run"] for r in rows]
    assert labels[0].startswith("translated anew") and labels[1].startswith("same model again")
    assert any("rebound" in label for label in labels) and any("structural zero" in label for label in labels)
    # the start value changed at run time is a row of its own, next to the same value as a modifier
    assert any("start value at run time" in label for label in labels)
    assert all(r["status"] == 0 and r["wall_seconds"] > 0 for r in rows)
    assert all(r["translate_seconds"] >= 0 for r in rows)
    # (that a new value compiles nothing is tested in tests/compiler/test_parameters.py; how much
    # time that saves is what the bench measures, not something a test asserts on a shared machine)


def test_storm_clusters_and_whole_model_agree(tmp_path):
    """Each storm point in a fresh process, with and without clusters: the same events, fewer systems."""
    points = bench.run_storm((2, 3), whole_up_to=3, timeout=120)
    assert [(p["n"], p["mode"]) for p in points] == [(2, "clusters"), (2, "whole model"),
                                                     (3, "clusters"), (3, "whole model")]
    assert [p["status"] for p in points] == [0, 0, 0, 0], [p.get("message") or p["status"] for p in points]
    for n in (2, 3):
        clustered, whole = [p for p in points if p["n"] == n]
        assert clustered["parts"] == n and whole["parts"] == 1
        assert clustered["events"] == whole["events"] > n
        assert clustered["compiled_systems"] <= whole["compiled_systems"]
        # the parts integrated apart take other steps than one solver for all: equal to the tolerance
        assert clustered["final_watched"] == pytest.approx(whole["final_watched"], abs=1e-6)
        for p in (clustered, whole):
            assert p["translation"] > 0 and p["wall"] > p["translation"] and p["max_rss_mb"] > 0
    files = bench.write_storm(points, tmp_path, timeout=120)
    assert set(files) == {"storm.md", "storm.csv", "storm.png"}
    assert all(path.stat().st_size > 0 for path in files.values())
    text = (tmp_path / "storm.md").read_text()
    assert "| 3 | whole model |" in text and "## Reading" in text and "## Targets" in text
    assert "storm N = 200 ≤ 10 s" in text and "integration+events per event at N = 100" in text
    with (tmp_path / "storm.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    assert len(rows) == 4 and {"n", "mode", "status", "wall", "translation", "compiled_systems",
                               "events", "max_rss_mb"} <= set(rows[0])


def test_storm_point_that_does_not_finish_is_recorded(monkeypatch):
    """A point over its time limit is recorded as not finished, and the larger sizes of its mode skipped."""
    monkeypatch.setattr(bench, "_storm_point_subprocess",
                        lambda n, clusters, timeout: {"n": n, "mode": "clusters" if clusters else "whole model",
                                                      "status": f"not finished in {timeout:.0f} s"})
    points = bench.run_storm((4, 8), whole_up_to=0, timeout=7)
    assert [p["status"] for p in points] == ["not finished in 7 s", "skipped (N=4 not finished in 7 s)"]
    text = bench._storm_markdown(points, bench.storm_fits(points), 7)
    checks = bench.storm_target_checks(points, 7)
    assert [c.met for c in checks] == [None, None, None]  # none of the targets' sizes ran
    assert "not measured" in text and "N = 200 not run" in text


def test_bench_only_storm_writes_only_the_storm(tmp_path, monkeypatch):
    calls = []
    run_storm = bench.run_storm

    def small_storm(sizes, whole_up_to, timeout, log=None):
        calls.append((tuple(sizes), whole_up_to, timeout))
        return run_storm((2,), 2, timeout, log=log)

    monkeypatch.setattr(bench, "run_storm", small_storm)
    assert bench.main(["--only", "storm", "--quick", "--out", str(tmp_path)]) == 0
    assert calls == [(bench.QUICK_STORM, bench.QUICK_STORM_WHOLE_UP_TO, bench.QUICK_STORM_TIMEOUT_SECONDS)]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["storm.csv", "storm.md", "storm.png"]


def test_hand_coded_stick_slip_floor_agrees_with_acausal():
    """The floor is the same model: it matches the exact solution and acausal's final speed."""
    t_b, t_s = benchmarks.stick_slip_times()
    floor = benchmarks.stick_slip_floor(benchmarks.stick_slip_stop_time(), 0.001)
    assert [(old, new) for _, old, new in floor["events"]] == [(0, 1), (1, -1)]
    assert floor["events"][0][0] == pytest.approx(t_b, abs=1e-8)
    assert floor["events"][1][0] == pytest.approx(t_s, abs=1e-5)  # rtol 1e-6: acausal is as far off
    assert floor["final"] == floor["w"][-1]
    window = floor["time"] <= t_s
    # acausal's own error at rtol 1e-6 is 1.6e-5 rad/s (bench.md): the same integrator, the same error
    assert np.max(np.abs(floor["w"][window] - benchmarks.stick_slip_exact(floor["time"][window]))) < 1e-4
    case = benchmarks.floor_case()
    assert isinstance(case, bench.FloorCase) and case.case in bench.cases()
    assert case.floor is benchmarks.stick_slip_floor
    row = bench.run_hand_coded_floor(repeats=1)
    assert row["acausal_status"] == 0 and row["agree"], row
    assert (row["case"], row["output"], row["agreement"]) == (case.case, case.output, case.agreement)
    assert row["final_difference"] <= case.agreement
    assert row["acausal_seconds"] > 0 and row["floor_seconds"] > 0


def test_hand_coded_floor_is_read_from_the_floor_case(tmp_path):
    """bench.py runs whatever floor the floor case gives it, and words its table with the case's words."""
    calls = []

    def constant_floor(stop_time, interval, rtol, atol):
        calls.append((stop_time, interval, rtol, atol))
        return {"final": 0.0, "events": [], "steps": 1, "rhs_evaluations": 1}

    case = bench.FloorCase(case="CoastDown", floor=constant_floor, output="inertia.w", unit="u",
                           agreement=1e-3, description="A constant floor.")
    row = bench.run_hand_coded_floor(repeats=1, floor_case=case)
    assert len(calls) == 2 and calls[0][2] == calls[0][3] == 1e-6
    assert calls[0][0] == pytest.approx(benchmarks.CD_STOP)
    assert row["case"] == "CoastDown" and row["floor_switches"] == 0
    assert row["agree"] == (abs(row["acausal_final"]) <= 1e-3)  # the inertia stops at t = 4 s
    files = bench.write_floors([row], tmp_path, floor_case=case)
    text = files["floors.md"].read_text()
    assert "## Warm CoastDown against a hand-coded floor" in text and "A constant floor." in text
    assert "final inertia.w floor [u]" in text and "The floor's switches: none." in text


def test_floors_rows_and_files(tmp_path):
    imports = bench.run_import_floors(repeats=1)
    assert [r["label"] for r in imports] == ["import numpy", "import numpy, scipy.integrate"]
    assert all(r["exit_statuses"] == "0" and r["median_wall"] > 0 for r in imports)
    command = {"model": "First", "command": "acausal compare examples/first.py", "runs": 1, "min_wall": 2.0,
               "median_wall": 2.0, "max_wall": 2.0, "exit_statuses": "0", "passed": True, "failure": "",
               "target": 1.0, "met": False}
    (ratio,) = bench.command_floor_ratios([command], imports)
    assert ratio["x_import_numpy"] == pytest.approx(2.0 / imports[0]["median_wall"])
    assert ratio["x_numpy_scipy"] == pytest.approx(2.0 / imports[1]["median_wall"])
    rows = bench.run_floors(repeats=1, command_records=[command])
    assert [r["kind"] for r in rows] == ["import floor", "import floor", "command", "in-process"]
    files = bench.write_floors(rows, tmp_path)
    assert set(files) == {"floors.md", "floors.csv"}
    text = (tmp_path / "floors.md").read_text()
    assert "× import numpy" in text and "× numpy+scipy.integrate" in text and "| agree |" in text
    # the hand-coded floor's target is measured; the warm command's is not (this command is not warm)
    assert "## Targets" in text and "warm StickSlip ≤ 2× the hand-coded floor" in text
    assert rows[-1]["target_ratio"] == benchmarks.floor_case().target_ratio
    assert rows[-1]["target_met"] == (rows[-1]["agree"] and rows[-1]["ratio"] <= rows[-1]["target_ratio"])
    with (tmp_path / "floors.csv").open() as handle:
        assert {"kind", "what", "median_wall", "x_import_numpy", "ratio", "agree", "target_ratio",
                "target_met"} <= set(next(csv.DictReader(handle)))


def test_the_tables_section_measures_every_size(tmp_path, capsys):
    """``acausal bench --only tables``: each model with each table size, simulated to the end."""
    from acausal.tools import table_bench

    assert bench.main(["--only", "tables", "--quick", "--out", str(tmp_path)]) == 0
    text = (tmp_path / "tables.md").read_text()
    for rows in table_bench.QUICK_ROWS:
        assert f"| {rows:,} |" in text
    assert "failed" not in text and (tmp_path / "tables.png").stat().st_size > 0
    assert "What a table's size costs" in capsys.readouterr().out


def _rod_heat_stored(n: int, t: float) -> float:
    """The exact heat ``HeatRod(n)`` stores in ``t`` seconds, sum C (T_i(t) - T0), with its defaults.

    ``T[1] = T_hot``; ``u = T[2:] - T_hot`` solves ``du/dt = (G/C) K u`` (K the second
    difference, insulated at the far end), ``u(t) = expm(t (G/C) K) u(0)``.
    """
    import scipy.linalg

    from examples.heat_rod import HeatRod

    L, A, rho_c, k = HeatRod.L.default, HeatRod.A.default, HeatRod.rho_c.default, HeatRod.k.default
    T0, T_hot = HeatRod.T0.default, HeatRod.T_hot.default
    dx = L / n
    C, G = rho_c * A * dx, k * A / dx
    K = -2.0 * np.eye(n - 1) + np.eye(n - 1, k=1) + np.eye(n - 1, k=-1)
    K[-1, -1] = -1.0
    u = scipy.linalg.expm(t * G / C * K) @ np.full(n - 1, T0 - T_hot)
    return float(C * np.sum(u - (T0 - T_hot)))


def test_heat_rod_scaling_rows_keep_the_energy_balance():
    """The scaling section's array case, the heat rod: a row per N, translated, and its short run
    stores exactly the heat that came in (the exact solution's)."""
    case = bench.array_scaling_case()
    assert case.name == "HeatRod" and (case.quantity, case.unit) == ("heat", "J")
    points = bench.run_array_scaling((5, 10), isolate=False)
    assert [(p["model"], p["n"], p["status"]) for p in points] == [("HeatRod", 5, "ok"), ("HeatRod", 10, "ok")]
    for p in points:
        n = p["n"]
        assert p["states"] == n - 1  # cell[1] follows the fixed temperature
        assert 0 < p["flatten"] < p["translation"] <= p["translation_all"]
        assert p["seconds_per_element"] == pytest.approx(p["translation"] / n)
        # the heat that came in is the heat stored, and both are the exact solution's
        exact = _rod_heat_stored(n, case.stop_time)
        assert p["stored"] == pytest.approx(exact, rel=1e-5)
        assert p["came_in"] == pytest.approx(exact, rel=1e-5)
        assert p["balance_error"] < 1e-6 and p["rate_balance_error"] < 1e-9
    assert math.isnan(points[0]["local_slope"]) and math.isfinite(points[1]["local_slope"])
    fits = bench.array_scaling_fits(points)
    assert set(fits) == set(bench.ARRAY_SCALING_FITTED) and all(math.isfinite(b) for _, b in fits.values())
    text = bench._array_scaling_markdown(points, fits, case, isolated=False)
    assert "## HeatRod: a model built with arrays" in text and "| 5 |" in text and "| 10 |" in text
    assert "N (cells)" in text and "heat stored [J]" in text and "slope b (time ≈ a·N^b)" in text


# -- the targets each section states ------------------------------------------------------------


def test_the_suite_sets_the_targets_and_the_full_sizes_reach_them():
    """The targets live in the suite; the full storm and scaling sizes include the targets' sizes."""
    assert benchmarks.TARGETS_SOURCE and benchmarks.WARM_COMMAND_MAX_X_IMPORT_NUMPY == 2.0
    assert set(benchmarks.WARM_COMMAND_FILES) <= {example for _, example in benchmarks.COMMAND_TARGETS}
    assert benchmarks.floor_case().target_ratio == 2.0
    small, large, _ = benchmarks.STORM_PER_EVENT_TARGET
    assert {small, large} | {n for n, _ in benchmarks.STORM_WALL_TARGETS} <= set(bench.full_storm_sizes())
    assert set(bench.FULL_STORM) <= set(bench.full_storm_sizes())
    assert {n for n, _ in benchmarks.SCALING_TIME_TARGETS} <= set(bench.full_scaling_sizes())
    assert benchmarks.SCALING_MEMORY_TARGET[0] in bench.full_scaling_sizes()
    assert list(bench.full_scaling_sizes()) == sorted(bench.full_scaling_sizes())


def test_targets_markdown_says_met_not_met_and_not_measured():
    checks = [bench.TargetCheck("a ≤ 1 s", "0.5 s", True), bench.TargetCheck("b | c ≤ 1 s", "2 s", False, "why"),
              bench.TargetCheck("d ≤ 1 s", "-", None, "not run")]
    assert [c.verdict for c in checks] == ["met", "not met", "not measured"]
    text = bench._targets_markdown(checks)
    assert "| a ≤ 1 s | 0.5 s | met | - |" in text
    assert "| b \\| c ≤ 1 s | 2 s | **not met** | why |" in text
    assert "| d ≤ 1 s | - | not measured | not run |" in text
    assert bench._targets_markdown([]) == ""


def test_import_breakdown_counts_each_package_once():
    import sys

    record = bench.import_breakdown([sys.executable, "-c", "import numpy, json"], runs=2)
    assert record["import_status"] == 0 and record["import_wall"] > 0 and record["import_runs"] == 2
    assert record["import_numpy_seconds"] > 0 and record["import_sympy_seconds"] == 0
    assert record["import_other_seconds"] > 0  # json, encodings, site ...
    parts = sum(record[f"import_{p}_seconds"] for p in (*bench.IMPORT_BREAKDOWN_PACKAGES, "other"))
    assert record["import_seconds"] == pytest.approx(parts)


def _command_row(verb: str, median: float, passed: bool = True, **extra) -> dict:
    return {"model": "First", "command": f"acausal {verb} examples/first.py", "example": "examples/first.py",
            "disk_cache": "warm", "runs": 3, "median_wall": median, "passed": passed, "failure": "",
            "x_import_numpy": median / 0.1, "import_numpy_wall": 0.1, **extra}


def test_warm_command_target_is_met_only_when_measured_so():
    breakdown = {"import_wall": 1.0, "import_seconds": 0.8, "import_acausal_seconds": 0.2,
                 "import_sympy_seconds": 0.3, "import_networkx_seconds": 0.1, "import_numpy_seconds": 0.1,
                 "import_scipy_seconds": 0.1}
    met, slow = bench.command_target_checks([_command_row("simulate", 0.15), _command_row("compare", 1.0, **breakdown)])
    assert met.met is True and met.why == "" and "1.5×" in met.measured
    assert slow.met is False and "10.0×" in slow.measured
    # the reason comes from the breakdown: 2x the floor, the imports' share, what a hit without sympy saves
    assert "0.20 s, 0.80 s less" in slow.why and "80%" in slow.why and "sympy 0.30" in slow.why
    assert "save about 0.50 s, leaving about 0.50 s (5.0× the floor), of which acausal's own import is about 0.20 s" \
        in slow.why
    (failed,) = [c for c in bench.command_target_checks([_command_row("simulate", 0.15, passed=False)])
                 if "simulate" in c.target]
    assert failed.met is False and "failed" in failed.why
    cold = dict(_command_row("simulate", 0.15), disk_cache="cold")
    assert [c.met for c in bench.command_target_checks([cold])] == [None, None]


def _storm(n: int, events: int, simulate: float, translation: float = 0.5, mode: str = "clusters") -> dict:
    return {"n": n, "mode": mode, "status": 0, "events": events, "simulate": simulate, "translation": translation,
            "wall": simulate + translation, "max_rss_mb": 100.0, "compiled_systems": 4 * n}


def test_storm_targets_from_the_points():
    flat = [_storm(10, 50, 0.25), _storm(100, 1000, 6.0), _storm(200, 2000, 9.0), _storm(1000, 10000, 55.0)]
    per_event, n200, n1000 = bench.storm_target_checks(flat, 240)
    assert per_event.met is True and "1.20×" in per_event.measured  # 6 ms against 5 ms
    assert n200.met is True and n1000.met is True
    # a size over its limit: the cost per event it allows, and what would bring it there
    slow = flat[:-1] + [_storm(1000, 100000, 150.0)]
    n1000 = bench.storm_target_checks(slow, 240)[2]
    assert n1000.met is False and "0.6 ms per event, 2.5× less" in n1000.why and "stepped together" in n1000.why
    growing = [_storm(10, 50, 0.25), _storm(100, 1000, 20.0), {"n": 200, "mode": "clusters",
                                                                 "status": "not finished in 240 s"},
               {"n": 1000, "mode": "clusters", "status": "skipped (N=200 not finished in 240 s)"}]
    per_event, n200, n1000 = bench.storm_target_checks(growing, 240)
    assert per_event.met is False and "N^0.60" in per_event.why  # 20 ms against 5 ms: 4x over a decade
    assert n200.met is False and n200.measured == "not finished in 240 s" and "predicts" in n200.why
    assert n1000.met is None and "skipped" in n1000.why
    # a timeout shorter than the limit proves nothing
    _, n200, _ = bench.storm_target_checks(growing, 5)
    assert n200.met is None


def _scaling(n: int, seconds: float, rss: float, status: str = "ok") -> dict:
    # (the peak of the whole point, its simulations' results included, is some more)
    return {"n": n, "status": status, "equations": 33 * n, "translated_initialized": seconds,
            "translated_rss_mb": rss, "max_rss_mb": 1.5 * rss, "flatten": seconds / 4, "codegen": seconds / 3}


def test_scaling_targets_from_the_points():
    points = [_scaling(100, 1.0, 150.0), _scaling(300, 3.0, 300.0), _scaling(1000, 9.0, 600.0)]
    n1000, n10000, memory = bench.scaling_target_checks(points)
    assert n1000.met is True and n1000.measured.startswith("9 s")
    assert n10000.met is None and "not run" in n10000.why and "predicts" in n10000.why
    # the peak translated and initialized: 600 MB / 33000 equations = 18 kB (the whole point's
    # 900 MB, 27 kB, is reported beside it)
    assert memory.met is True and "18.2 kB" in memory.measured and "27.3 kB" in memory.measured
    points[-1].update(translated_initialized=14.0, translated_rss_mb=1400.0)
    points.append({"n": 10000, "status": "stopped after 180 s (flattened; building the event evaluator)",
                   "flatten": 40.0})
    n1000, n10000, memory = bench.scaling_target_checks(points, budget=180)
    assert n1000.met is False and "4 s over" in n1000.why and "codegen" in n1000.why
    assert n10000.met is False and "flatten+partition" in n10000.why
    assert memory.met is False and "per added equation" in memory.why
    # without a budget (points in this process) a stopped point proves nothing
    assert bench.scaling_target_checks(points, budget=None)[1].met is None


def test_floor_target_check():
    row = {"case": "StickSlip", "output": "inertia.w", "unit": "rad/s", "repeats": 5, "agree": True,
           "agreement": 1e-4, "final_difference": 1e-8, "acausal_seconds": 0.006, "floor_seconds": 0.002,
           "ratio": 3.0, "acausal_rhs_evaluations": 150, "floor_rhs_evaluations": 125, "acausal_steps": 23,
           "floor_steps": 20, "acausal_events": 4, "floor_switches": 2, "target_ratio": 2.0}
    check = bench.floor_target_check(row)
    assert check.met is False and "2 ms less" not in check.why and "2.00 ms less" in check.why
    assert "1.20× the floor's right-hand side evaluations" in check.why
    assert bench.floor_target_check(dict(row, acausal_seconds=0.003, ratio=1.5)).met is True
    assert bench.floor_target_check(dict(row, agree=False, ratio=1.5)).met is False
    assert bench.floor_target_check(dict(row, target_ratio=math.nan)) is None
