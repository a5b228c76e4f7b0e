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
import importlib
import os
import pickle
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from acausal import simulate, translate
from acausal.compiler.saved import LoadedModel, SavedModel
from examples.coupled_clutches import CoupledClutches
from examples.first import First
from examples.blocks_noise import UniformNoiseExample

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
    # a random number generator's call sites call back into the run's evaluator
    translation = translate(UniformNoiseExample())
    simulate(translation)
    assert translation.saved() == "the model's discrete equations call an impure function"
    for model in (First(), CoupledClutches()):
        saved = translate(model)
        simulate(saved)
        assert isinstance(saved.saved(), SavedModel)


def cold_then_warm(folder: Path, filename: str, text: str, *options: str):
    """``acausal simulate`` of ``text`` (written to ``folder/filename``) twice with ``options``:
    the second loads no compiler and writes the first's bytes.  Returns both processes."""
    model = folder / filename
    model.write_text(text)
    cold = command(folder, str(model), *options, "--out", "cold.csv")
    assert cold.returncode == 0, cold.stderr
    warm = command(folder, str(model), *options, "--out", "warm.csv")
    assert warm.returncode == 0, warm.stderr
    assert loaded_packages(warm) == "LOADED []"
    assert (folder / "warm.csv").read_bytes() == (folder / "cold.csv").read_bytes()
    return cold, warm


def test_a_warm_command_with_discrete_equations_gives_the_cold_result(tmp_path):
    """CoupledClutches: friction modes (discrete equations), time events, several states."""
    cold_then_warm(tmp_path, "coupled_clutches.py", (REPO / "examples" / "coupled_clutches.py").read_text())


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


WHEN_CLAUSES = '''
from acausal import Assert, Boolean, Eq, Experiment, If, Model, Parameter, Variable, When, der, pre, reinit, terminate


class BallWithLimits(Model):
    """A bouncing ball whose run ends by terminate(), with an assertion warning on the way."""

    experiment = Experiment(stop_time=10.0, interval=0.01)
    e = Parameter(0.8)
    h = Variable(start=1.0, fixed=True)
    v = Variable(start=0.0, fixed=True)
    bounces = Variable(start=0.0, fixed=True)

    def equations(self):
        return [
            Eq(der(self.h), self.v),
            Eq(der(self.v), -9.81),
            Eq(der(self.bounces), 0.0),
            When(self.h <= 0, reinit(self.v, -self.e * pre(self.v)), reinit(self.bounces, pre(self.bounces) + 1)),
            When(self.bounces >= 3, terminate("three bounces")),
            Assert(self.h < 0.95, "starts high", level="warning"),
        ]
'''


def test_a_warm_command_runs_when_clauses_and_assertions_as_the_cold_one(tmp_path):
    """reinit(), terminate() and an assertion warning are saved with the run: the warm command
    loads no compiler, ends at the same terminate() and writes the cold command's bytes."""
    cold, warm = cold_then_warm(tmp_path, "ball.py", WHEN_CLAUSES)
    for done in (cold, warm):  # the reason the run ended, as the cold run says it
        assert "terminate() at t = 1.75" in done.stdout and "three bounces" in done.stdout, done.stdout
    rows = (tmp_path / "warm.csv").read_text().splitlines()
    assert float(rows[-1].split(",")[0]) < 10.0  # terminated before the stop time


def test_a_loaded_model_gives_the_cold_notes_events_and_message(tmp_path):
    """The same through the Python API: the assertion's warning note, the events, the termination
    message and every column, without a call into the compiler."""
    namespace: dict = {}
    exec(compile(WHEN_CLAUSES, str(tmp_path / "ball.py"), "exec"), namespace)
    translation = translate(namespace["BallWithLimits"](), cache=False)
    cold = simulate(translation)
    saved = translation.saved()
    assert isinstance(saved, SavedModel), saved

    def no_compiler():
        raise AssertionError("the loaded model asked for the compiler")

    warm = simulate(LoadedModel(saved, no_compiler))
    assert any("starts high" in note for note in cold.notes), cold.notes
    assert_same_run(warm, cold)


def assert_same_run(warm, cold) -> None:
    """The same run: status, notes, message, events, times and every column, bit for bit."""
    assert warm.notes == cold.notes and warm.message == cold.message and warm.status == cold.status
    assert [(e.time, e.kind) for e in warm.events] == [(e.time, e.kind) for e in cold.events]
    np.testing.assert_array_equal(warm.time, cold.time)
    for name in cold.columns:
        np.testing.assert_array_equal(warm[name], cold[name])


def _cold_and_loaded(model_class):
    translation = translate(model_class(), cache=False)
    cold = simulate(translation)
    saved = translation.saved()
    assert isinstance(saved, SavedModel), saved

    def no_compiler():
        raise AssertionError("the loaded model asked for the compiler")

    # through pickle, as the saved run is stored
    return cold, simulate(LoadedModel(pickle.loads(pickle.dumps(saved)), no_compiler))


@pytest.mark.parametrize("example, name", [
    ("friction", "Friction"),                     # BearingFriction's tau_pos: a segment table
    ("tables_combi_table_1ds", "Test1"),          # CombiTable1Ds: an output of a Table1D
    ("tables_combi_table_2ds", "Test1"),          # CombiTable2Ds: a Table2D
    ("electrical_dc_machines", "DCPM_Start"),     # assertions of the electrical library
    ("electrical_opamps", "LowPass"),             # sample clocks
    ("tables_combi_time_table", "Test1"),         # a time table: discrete Reals, time events at held values
    ("electrical_semiconductors", "ThyristorBehaviourTest"),  # states sharing one compiled system
])
def test_tables_and_assertions_are_saved_and_give_the_cold_run_bit_for_bit(example, name):
    module = importlib.import_module(f"examples.{example}")
    assert_same_run(*reversed(_cold_and_loaded(getattr(module, name))))


def test_a_warm_command_with_a_friction_table_loads_no_compiler(tmp_path):
    cold_then_warm(tmp_path, "friction.py", (REPO / "examples" / "friction.py").read_text())


def test_a_model_with_delays_is_saved_and_gives_the_cold_run_bit_for_bit():
    """delay(): the generated code reads the run's history through a light function, which the
    saved run calls as the cold one does (x' = -x(t - 0.5) + y, y set by a when-clause)."""
    from tests.hybrid.test_delay import DelayedFeedback

    cold, warm = _cold_and_loaded(DelayedFeedback)
    assert cold.success
    assert_same_run(warm, cold)


def test_runs_with_param_and_start_are_saved_apart_and_give_the_cold_bytes(tmp_path):
    """``--param``/``--start`` runs are saved under their own key: the warm run of the same options
    loads no compiler and writes the cold bytes; other options are not served by it."""
    cold, _warm = cold_then_warm(tmp_path, "first.py", (REPO / "examples" / "first.py").read_text(),
                                 "--param", "amplitude=5", "--start", "inertia1.w=1")
    assert "sympy" in loaded_packages(cold)
    model = tmp_path / "first.py"
    # the model as declared is another run: translated, and its result differs
    plain = command(tmp_path, str(model), "--out", "plain.csv")
    assert plain.returncode == 0 and "sympy" in loaded_packages(plain)
    assert (tmp_path / "plain.csv").read_bytes() != (tmp_path / "cold.csv").read_bytes()
    other = command(tmp_path, str(model), "--param", "amplitude=6", "--out", "other.csv")
    assert other.returncode == 0 and "sympy" in loaded_packages(other)
