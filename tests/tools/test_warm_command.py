"""The warm ``acausal simulate``: a run saved whole, run again without the compiler.

A cold command that simulated a model whose run needs no more than the
continuous systems, discrete equations and time events saves it (``Translation.saved``,
``acausal.compiler.saved``); the next command of the same model loads it,
checks the digests of the model's file and of the modules it imported, and
runs it with the runtime alone.  The results are the cold command's, bit for
bit; the warm process imports neither sympy nor networkx; a changed model
file is translated again; a state the saved run did not visit is compiled
through the one callback into the compiler.
"""

from __future__ import annotations

import dataclasses
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from acausal import simulate, translate
from acausal.compiler.saved import LoadedModel, SavedModel
from examples.coupled_clutches import CoupledClutches
from examples.first import First
from examples.sampled_speed_control import SampledSpeedControl

REPO = Path(__file__).resolve().parents[2]

#: Runs ``acausal simulate`` in this process and reports which heavy packages it loaded.
RUNNER = """
import sys
from acausal.tools.cli import main
status = main(sys.argv[1:])
print("LOADED", sorted(m for m in ("sympy", "networkx", "scipy", "pandas", "matplotlib") if m in sys.modules))
sys.exit(status)
"""


def command(folder: Path, *args: str, verb: str = "simulate") -> subprocess.CompletedProcess:
    env = dict(os.environ, ACAUSAL_DISK_CACHE="on", ACAUSAL_CACHE_DIR=str(folder / "cache"),
               PYTHONPATH=str(REPO))
    return subprocess.run([sys.executable, "-c", RUNNER, verb, *args], cwd=folder, env=env,
                          capture_output=True, text=True, timeout=300)


def loaded_packages(done: subprocess.CompletedProcess) -> str:
    return next(line for line in done.stdout.splitlines() if line.startswith("LOADED"))


def test_a_warm_command_gives_the_cold_result_without_sympy_or_networkx(tmp_path):
    model = tmp_path / "first.py"
    model.write_text((REPO / "examples" / "first.py").read_text())
    cold = command(tmp_path, str(model), "--out", "cold.csv")
    assert cold.returncode == 0, cold.stderr
    assert "sympy" in loaded_packages(cold)  # it translated
    warm = command(tmp_path, str(model), "--out", "warm.csv")
    assert warm.returncode == 0, warm.stderr
    assert loaded_packages(warm) == "LOADED []"
    assert (tmp_path / "warm.csv").read_bytes() == (tmp_path / "cold.csv").read_bytes()


def test_a_changed_model_file_is_translated_again(tmp_path):
    model = tmp_path / "first.py"
    source = (REPO / "examples" / "first.py").read_text()
    model.write_text(source)
    assert command(tmp_path, str(model), "--out", "a.csv").returncode == 0
    changed = source.replace("amplitude = Parameter(10.0,", "amplitude = Parameter(5.0,")
    assert changed != source, "the example declares amplitude = Parameter(10.0, ...)"
    model.write_text(changed)
    again = command(tmp_path, str(model), "--out", "b.csv")
    assert again.returncode == 0, again.stderr
    assert "sympy" in loaded_packages(again)  # translated: the saved run was not used
    assert (tmp_path / "a.csv").read_bytes() != (tmp_path / "b.csv").read_bytes()
    # and the new run is saved in turn
    warm = command(tmp_path, str(model), "--out", "c.csv")
    assert loaded_packages(warm) == "LOADED []"
    assert (tmp_path / "c.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()


def test_a_model_whose_run_needs_the_compiler_is_not_saved():
    translation = translate(SampledSpeedControl())
    simulate(translation)
    assert translation.saved() == "the model has sample clocks"
    for model in (First(), CoupledClutches()):
        saved = translate(model)
        simulate(saved)
        assert isinstance(saved.saved(), SavedModel)


def test_a_warm_command_with_discrete_equations_gives_the_cold_result(tmp_path):
    """CoupledClutches: friction modes (discrete equations), time events, several states."""
    model = tmp_path / "coupled_clutches.py"
    model.write_text((REPO / "examples" / "coupled_clutches.py").read_text())
    assert command(tmp_path, str(model), "--out", "cold.csv").returncode == 0
    warm = command(tmp_path, str(model), "--out", "warm.csv")
    assert warm.returncode == 0, warm.stderr
    assert loaded_packages(warm) == "LOADED []"
    assert (tmp_path / "warm.csv").read_bytes() == (tmp_path / "cold.csv").read_bytes()


def test_a_state_the_saved_run_did_not_visit_is_compiled_through_the_callback():
    translation = translate(First(), cache=False)
    cold = simulate(translation)
    saved = translation.saved()
    asked = []

    def translate_again():
        asked.append(True)
        return translate(First(), cache=False)

    # nothing saved but the data: every system comes from the compiler, once
    loaded = LoadedModel(dataclasses.replace(saved, systems=(), initial_systems=()), translate_again)
    fallback = simulate(loaded)
    assert asked == [True]
    whole = LoadedModel(saved, translate_again)
    warm = simulate(whole)
    assert asked == [True]  # everything was saved: no translation
    for result in (fallback, warm):
        np.testing.assert_array_equal(result.time, cold.time)
        for name in cold.columns:
            np.testing.assert_array_equal(result[name], cold[name])


def test_a_warm_compare_tube_tests_the_saved_run(tmp_path):
    """``acausal compare`` uses the saved run too (the reference bundled with acausal): the same
    verdict and the same per-signal lines, without executing the model's file."""
    model = tmp_path / "first.py"
    model.write_text((REPO / "examples" / "first.py").read_text())
    cold = command(tmp_path, str(model), verb="compare")
    warm = command(tmp_path, str(model), verb="compare")
    assert cold.returncode == warm.returncode == 0, (cold.stderr, warm.stderr)
    assert "sympy" in loaded_packages(cold)
    assert loaded_packages(warm) == "LOADED []"

    def lines(done):  # the comparison, without the run's timings
        return [line for line in done.stdout.splitlines()
                if "_seconds" not in line and not line.startswith("LOADED")]

    assert lines(warm) == lines(cold)
