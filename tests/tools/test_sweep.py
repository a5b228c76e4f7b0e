"""Parameter sweeps (acausal.tools.sweep): one translation, runs on a process pool and on Dask."""

import dataclasses
import pickle

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

import acausal
from acausal.compiler.translate import Translation, translate
from acausal.tools.sweep import main_sweep, parameter_sets, sweep
from examples.coupled_clutches import CoupledClutches

OUTPUTS = ["J1.w", "J4.w", "clutch1.tau"]
#: 40 runs: 8 inertias of J1 times 5 amplitudes of the driving sine
GRID = {"J1.J": [float(v) for v in np.linspace(0.8, 1.6, 8)], "sin1.amplitude": [8.0, 9.0, 10.0, 11.0, 12.0]}


@pytest.fixture(scope="module")
def model():
    return CoupledClutches()


@pytest.fixture(scope="module")
def single_runs(model):
    """The 40 runs one by one, as a user would loop over simulate()."""
    return [acausal.simulate(model, parameters=values, outputs=OUTPUTS) for values in parameter_sets(GRID)]


def _same_as_single_runs(result, single_runs):
    assert len(result.runs) == 40
    for outcome, reference in zip(result.runs, single_runs):
        assert outcome.status == reference.status == 0, outcome.message
        assert np.array_equal(outcome.result.time, reference.time)
        for name in OUTPUTS:
            assert np.array_equal(outcome.result[name], reference[name]), (outcome.index, name)
        assert len(outcome.result.events) == len(reference.events)


def test_process_pool_sweep_equals_forty_single_runs(model, single_runs):
    result = sweep(model, GRID, OUTPUTS, workers=2, pilot=2)
    _same_as_single_runs(result, single_runs)
    assert result.workers == 2
    # the workers never translate; what they compile is only discrete states no run
    # made here reached, and most runs compile nothing at all
    assert result.translated_in_workers == 0
    assert sum(o.compiled == 0 for o in result.runs) >= 30
    table = result.table
    assert list(table["run"]) == list(range(40))
    assert table.loc[5, "J1.J"] == GRID["J1.J"][1] and table.loc[5, "sin1.amplitude"] == 8.0
    assert table.loc[7, "J4.w:final"] == single_runs[7]["J4.w"][-1]
    assert table.loc[7, "J1.w:max"] == single_runs[7]["J1.w"].max()
    assert (table["events"] > 0).all()
    series = result.series("J4.w", points=151)
    assert series.shape == (151, 40) and series.index[0] == 0.0 and series.index[-1] == 1.5
    assert np.isclose(series[3].iloc[-1], single_runs[3]["J4.w"][-1])
    figure = result.plot_envelope("J4.w")
    assert "rad/s" in figure.axes[0].get_ylabel()
    figure = result.plot_scalar("J4.w", against="J1.J")
    assert figure.axes[0].get_xlabel().startswith("J1.J")


def test_dask_local_cluster_sweep_equals_forty_single_runs(model, single_runs):
    distributed = pytest.importorskip("dask.distributed", reason="dask[distributed] is not installed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        result = sweep(model, GRID, OUTPUTS, executor=client, pilot=2)
    _same_as_single_runs(result, single_runs)
    assert result.workers == 2
    assert result.translated_in_workers == 0


def test_systems_travel_as_source_and_are_not_compiled_again(model):
    translation = translate(model, OUTPUTS, cache=False)
    acausal.simulate(translation)
    bundle = pickle.loads(pickle.dumps(translation.export()))
    assert bundle.payloads and all(isinstance(p["source"], str) for p in bundle.payloads.values())
    flat = bundle.unpacked()[0]
    loaded = Translation.from_bundle(bundle, flat)
    result = acausal.simulate(loaded)
    systems = [*loaded.systems.values(), *loaded.initial_systems.values()]
    assert result.status == 0 and systems
    assert all(s.passes[0][0] == "load" for s in systems)  # nothing specialised, nothing compiled
    reference = acausal.simulate(translation)
    assert np.array_equal(reference["J4.w"], result["J4.w"])
    # a value that removes a term (a structural zero) cannot use the shipped systems
    zero = dataclasses.replace(flat, parameters=tuple(dataclasses.replace(p, value=0.0) if p.name == "J1.J" else p
                                                      for p in flat.parameters))
    assert Translation.from_bundle(bundle, zero)._disk is False


def test_failed_runs_keep_their_reason_and_do_not_stop_the_others(model):
    runs = [{"J1.J": 1.0}, {"clutch1.fn_max": -1.0}, {"J1.J": 0.0}, {"J1.J": 1.2}]
    result = sweep(model, runs, ["J1.w"], executor="serial")
    table = result.table
    assert list(table["status"]) == [0, -1, -1, 0]
    assert table.loc[1, "error_type"] == "ParameterError" and "below its minimum" in table.loc[1, "message"]
    assert table.loc[2, "error_type"] == "StructurallySingularError"
    assert result.translated_in_workers == 1  # J1.J = 0 removes a term: translated for it
    assert [o.index for o in result.failed] == [1, 2]
    assert np.isnan(table.loc[1, "J1.w:final"]) and np.isfinite(table.loc[3, "J1.w:final"])
    seen = []
    sweep(model, runs[:2], ["J1.w"], executor="serial", progress=lambda done, total, o: seen.append((done, total)))
    assert seen == [(1, 2), (2, 2)]


def test_grid_and_samples_are_deterministic():
    grid = parameter_sets({"a": [1, 2], "b": [10, 20, 30]})
    assert grid == [{"a": 1.0, "b": 10.0}, {"a": 1.0, "b": 20.0}, {"a": 1.0, "b": 30.0},
                    {"a": 2.0, "b": 10.0}, {"a": 2.0, "b": 20.0}, {"a": 2.0, "b": 30.0}]
    box = {"a": (0.0, 1.0), "b": (10.0, 20.0)}
    first = parameter_sets(box, samples=8, seed=3)
    assert first == parameter_sets(box, samples=8, seed=3) != parameter_sets(box, samples=8, seed=4)
    # a Latin hypercube: one point in each of the 8 strata of every parameter
    assert sorted(int(p["a"] * 8) for p in first) == list(range(8))
    assert sorted(int((p["b"] - 10) / 10 * 8) for p in first) == list(range(8))
    uniform = parameter_sets(box, samples=5, seed=3, method="uniform")
    assert len(uniform) == 5 and all(10 <= p["b"] <= 20 for p in uniform)


def test_command_writes_the_table_series_and_plots(tmp_path, capsys):
    spec = "examples/coupled_clutches.py:CoupledClutches"
    code = main_sweep([spec, "--param", "J1.J=0.8:1.2:2", "--param", "clutch1.fn_max=20,-1", "--output", "J4.w",
                       "--workers", "1", "--out", str(tmp_path)])
    printed = capsys.readouterr().out
    assert code == 1  # one run failed (fn_max below its minimum), the others did not
    assert "4 runs of CoupledClutches" in printed and "2 succeeded, 2 failed" in printed
    import pandas as pd

    table = pd.read_csv(tmp_path / "runs.csv")
    assert list(table["status"]) == [0, -1, 0, -1]
    assert (tmp_path / "series_J4.w.csv").is_file() and (tmp_path / "envelope_J4.w.png").is_file()
    assert main_sweep([spec, "--param", "J1.J=oops", "--out", str(tmp_path)]) == 2
