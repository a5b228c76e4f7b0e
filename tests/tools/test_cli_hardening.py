"""The command line never loses work and never ends in a traceback.

* Output paths (``simulate --out``, ``compare --plot``, ``explain --out``)
  are checked before anything is simulated: an unwritable one is a usage
  error (status 2) naming the path and why.  The tests run as root, so an
  unwritable path is a directory given as a file, or a path below a regular
  file.  If writing still fails after the run (the path changed meanwhile),
  the error is printed and the status is 1.
* A model whose own code (``__init__``, ``build()``, ``equations()``)
  raises is a model error: status 2, one line naming the class, the
  exception and the file and line of the user's code.
* Ctrl-C: a run interrupted with a partial result (status -2, message
  "interrupted ..."), whether ``simulate()`` returns it or raises it
  attached to a KeyboardInterrupt (``SimulationInterrupted``), still gets its
  CSV written, status 130; a bare KeyboardInterrupt gives status 130, no
  CSV and no traceback.
"""

from __future__ import annotations

import csv
import dataclasses
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from acausal.tools import cli
from acausal.tools.cli import main

REPO = Path(__file__).resolve().parents[2]
FIRST = REPO / "examples" / "first.py"
TWO_MASSES = REPO / "examples" / "two_masses.py"


def write_model(folder: Path, name: str, source: str) -> Path:
    path = folder / name
    path.write_text(textwrap.dedent(source))
    return path


def read_csv(path: Path) -> tuple[list[str], list[list[float]]]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return rows[0], [[float(v) for v in row] for row in rows[1:]]


def one_line_error(err: str, *words: str) -> str:
    """The stderr of a failed command: one line, no traceback, holding every word."""
    assert "Traceback" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    for word in words:
        assert word in lines[0], f"{word!r} not in {lines[0]!r}"
    return lines[0]


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.fixture
def no_simulation(monkeypatch):
    """Fail the test if the command simulates anything."""

    def refuse(*args, **kwargs):
        raise AssertionError("simulated although the output path cannot be written")

    monkeypatch.setattr(cli, "_simulate", refuse)


def run_cli(*args: str, cwd: Path, timeout: float = 120) -> subprocess.CompletedProcess:
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    return subprocess.run([sys.executable, "-m", "acausal", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=timeout)


# ---------------------------------------------------------------------------
# 1. Output paths are checked before simulating
# ---------------------------------------------------------------------------


def test_simulate_out_is_a_directory(in_tmp, capsys, no_simulation):
    (in_tmp / "results").mkdir()
    assert main(["simulate", str(FIRST), "--out", "results"]) == 2
    captured = capsys.readouterr()
    one_line_error(captured.err, "--out", "results", "is a directory")
    assert captured.out == ""


def test_simulate_out_below_a_regular_file(in_tmp, capsys, no_simulation):
    (in_tmp / "notes.txt").write_text("a file, not a folder")
    assert main(["simulate", str(FIRST), "--out", "notes.txt/first.csv"]) == 2
    one_line_error(capsys.readouterr().err, "notes.txt/first.csv", "notes.txt is not a directory")


def test_simulate_default_out_is_a_directory(in_tmp, capsys, no_simulation):
    """Without --out the result goes to <Model>.csv in the current directory: checked as well."""
    (in_tmp / "First.csv").mkdir()
    assert main(["simulate", str(FIRST)]) == 2
    one_line_error(capsys.readouterr().err, "First.csv", "is a directory")


def test_simulate_out_in_a_new_folder_is_fine(in_tmp, capsys):
    out = in_tmp / "new" / "deeper" / "first.csv"
    assert main(["simulate", str(FIRST), "--stop-time", "0.1", "--out", str(out),
                 "--signals", "inertia3.w"]) == 0
    assert read_csv(out)[0] == ["time", "inertia3.w"]


def test_compare_plot_below_a_regular_file(in_tmp, capsys, no_simulation):
    (in_tmp / "plots").write_text("a file, not a folder")
    assert main(["compare", str(TWO_MASSES), "--plot", "plots/two_masses"]) == 2
    one_line_error(capsys.readouterr().err, "plots/two_masses", "plots is not a directory")


def test_compare_plot_is_a_regular_file(in_tmp, capsys, no_simulation):
    (in_tmp / "plots").write_text("a file, not a folder")
    assert main(["compare", str(TWO_MASSES), "--plot", "plots"]) == 2
    one_line_error(capsys.readouterr().err, "plots", "not a directory")


@pytest.mark.parametrize("out", ["pictures", "pictures/first"])
def test_explain_out_not_a_folder(in_tmp, capsys, monkeypatch, out):
    def refuse(*args, **kwargs):
        raise AssertionError("translated although the output folder cannot be written")

    monkeypatch.setattr(cli, "_translate", refuse)
    (in_tmp / "pictures").write_text("a file, not a folder")
    assert main(["explain", str(FIRST), "--out", out]) == 2
    one_line_error(capsys.readouterr().err, out, "not a directory")


def test_out_replaced_by_a_directory_during_the_run(in_tmp, capsys, monkeypatch):
    """The path was fine when checked, but is a directory when the run ends: status 1, no traceback."""
    out = in_tmp / "first.csv"
    real = cli._simulate

    def simulate_then_block(model, **options):
        result = real(model, **options)
        out.mkdir()
        return result

    monkeypatch.setattr(cli, "_simulate", simulate_then_block)
    assert main(["simulate", str(FIRST), "--stop-time", "0.1", "--out", str(out)]) == 1
    captured = capsys.readouterr()
    line = one_line_error(captured.err, str(out), "not saved")
    assert line.startswith("acausal simulate: error: cannot write")
    assert "First: ok" in captured.out  # the run's summary is still shown


def test_plot_folder_replaced_by_a_file_during_the_run(in_tmp, capsys, monkeypatch):
    plots = in_tmp / "plots"
    real = cli._simulate

    def simulate_then_block(model, **options):
        result = real(model, **options)
        plots.write_text("in the way")
        return result

    monkeypatch.setattr(cli, "_simulate", simulate_then_block)
    assert main(["compare", str(TWO_MASSES), "--plot", str(plots)]) == 1
    captured = capsys.readouterr()
    one_line_error(captured.err, str(plots), "cannot write the plots")
    assert "2 of 2 signals passed" in captured.out  # the comparison is still reported


def test_unwritable_out_in_a_real_process(tmp_path):
    (tmp_path / "results").mkdir()
    done = run_cli("simulate", str(FIRST), "--out", "results", cwd=tmp_path)
    assert done.returncode == 2
    one_line_error(done.stderr, "results", "is a directory")


# ---------------------------------------------------------------------------
# 2. The model's own code raises
# ---------------------------------------------------------------------------


BUILD_RAISES = """
    from acausal import Model


    class Boom(Model):
        def build(self):
            raise RuntimeError("boom")
    """

BUILD_VALUE_ERROR = """
    from acausal import Model


    class Parse(Model):
        def build(self):
            self.n = int("twelve")
    """


@pytest.mark.parametrize("command", ["simulate", "explain"])
def test_build_raising_runtime_error(in_tmp, capsys, command):
    path = write_model(in_tmp, "boom.py", BUILD_RAISES)
    assert main([command, str(path)]) == 2
    line = one_line_error(capsys.readouterr().err, "Boom", "RuntimeError: boom", "boom.py:7")
    assert line.startswith(f"acausal {command}: error: ")


def test_build_raising_value_error(in_tmp, capsys):
    path = write_model(in_tmp, "parse.py", BUILD_VALUE_ERROR)
    assert main(["simulate", str(path)]) == 2
    one_line_error(capsys.readouterr().err, "Parse", "ValueError", "twelve", "parse.py:7")


def test_build_raising_in_compare(in_tmp, capsys):
    path = write_model(in_tmp, "boom_compare.py", """
        from acausal import Model


        class Boom(Model):
            modelica_class = "Modelica.Thermal.HeatTransfer.Examples.TwoMasses"

            def build(self):
                raise RuntimeError("boom")
        """)
    assert main(["compare", str(path)]) == 2
    one_line_error(capsys.readouterr().err, "Boom", "RuntimeError: boom", "boom_compare.py:9")


def test_equations_raising(in_tmp, capsys):
    path = write_model(in_tmp, "eqs.py", """
        from acausal import Model, Variable


        class Eqs(Model):
            x = Variable(start=1.0, fixed=True)

            def equations(self):
                raise RuntimeError("no equations today")
        """)
    assert main(["simulate", str(path)]) == 2
    one_line_error(capsys.readouterr().err, "Eqs", "no equations today")


def test_init_raising(in_tmp, capsys):
    path = write_model(in_tmp, "init.py", """
        from acausal import Model


        class Init(Model):
            def __init__(self):
                raise LookupError("no such thing")
        """)
    assert main(["simulate", str(path)]) == 2
    one_line_error(capsys.readouterr().err, "Init", "LookupError: no such thing", "init.py:7")


def test_error_in_a_helper_module_names_the_helper(in_tmp, capsys):
    """The frame named is the user's, even when it is in a module the model file imports."""
    write_model(in_tmp, "helper_parts.py", """
        from acausal import Component


        class Part(Component):
            def build(self):
                raise ZeroDivisionError("the part is broken")
        """)
    path = write_model(in_tmp, "uses_helper.py", """
        from acausal import Model
        from helper_parts import Part


        class UsesHelper(Model):
            def build(self):
                self.part = Part()
        """)
    assert main(["simulate", str(path)]) == 2
    one_line_error(capsys.readouterr().err, "UsesHelper", "ZeroDivisionError", "helper_parts.py:7")


def test_multi_line_exception_message_stays_on_one_line(in_tmp, capsys):
    path = write_model(in_tmp, "lines.py", """
        from acausal import Model


        class Lines(Model):
            def build(self):
                raise RuntimeError("first line\\nsecond line")
        """)
    assert main(["simulate", str(path)]) == 2
    one_line_error(capsys.readouterr().err, "first line second line")


def test_build_raising_in_a_real_process(tmp_path):
    write_model(tmp_path, "boom.py", BUILD_RAISES)
    done = run_cli("simulate", "boom.py", cwd=tmp_path)
    assert done.returncode == 2
    one_line_error(done.stderr, "Boom", "RuntimeError: boom", "boom.py:7")


# ---------------------------------------------------------------------------
# 3. Ctrl-C
# ---------------------------------------------------------------------------


class Interrupted(KeyboardInterrupt):
    """Ctrl-C carrying the partial result, as ``acausal.errors.SimulationInterrupted`` does."""

    def __init__(self, message: str, result) -> None:
        super().__init__(message)
        self.result = result


def interrupted_at(stop: float, raised: bool = False):
    """A stand-in for simulate(): the run interrupted at ``stop`` (status -2, the result up to then),
    returned, or raised attached to a KeyboardInterrupt."""
    from acausal.runtime import simulate as runtime

    real = runtime.simulate

    def fake(model, **options):
        result = real(model, **{**options, "stop_time": stop})
        message = f"interrupted at t = {stop:g} (Ctrl-C); the result holds what was computed until then"
        partial = dataclasses.replace(result, status=-2, message=message)
        if raised:
            raise Interrupted(message, partial)
        return partial

    return fake


def raise_interrupt(*args, **kwargs):
    raise KeyboardInterrupt


@pytest.mark.parametrize("raised", [False, True], ids=["returned", "raised"])
def test_simulate_interrupted_writes_the_partial_csv(in_tmp, capsys, monkeypatch, raised):
    monkeypatch.setattr("acausal.runtime.simulate.simulate", interrupted_at(0.3, raised))
    out = in_tmp / "first.csv"
    assert main(["simulate", str(FIRST), "--out", str(out), "--signals", "inertia3.w"]) == 130
    captured = capsys.readouterr()
    one_line_error(captured.err, "interrupted", "t = 0.3", str(out))
    header, rows = read_csv(out)
    assert header == ["time", "inertia3.w"]
    assert rows[0][0] == 0.0 and rows[-1][0] == pytest.approx(0.3)
    assert f"wrote {out}" in captured.out


def test_simulate_keyboard_interrupt(in_tmp, capsys, monkeypatch):
    monkeypatch.setattr("acausal.runtime.simulate.simulate", raise_interrupt)
    out = in_tmp / "first.csv"
    assert main(["simulate", str(FIRST), "--out", str(out)]) == 130
    one_line_error(capsys.readouterr().err, "interrupted")
    assert not out.exists()


@pytest.mark.parametrize("raised", [False, True], ids=["returned", "raised"])
def test_compare_interrupted_stops_there(in_tmp, capsys, monkeypatch, raised):
    calls = []
    fake = interrupted_at(0.3, raised)

    def counting(model, **options):
        calls.append(model)
        return fake(model, **options)

    monkeypatch.setattr("acausal.runtime.simulate.simulate", counting)
    assert main(["compare", str(FIRST), str(TWO_MASSES)]) == 130
    captured = capsys.readouterr()
    one_line_error(captured.err, "First", "interrupted", "t = 0.3")
    assert len(calls) == 1  # the second model is not simulated
    assert "signals passed" not in captured.out  # an interrupted run is not compared
    assert "1 not compared" in captured.out


@pytest.mark.parametrize("several", [False, True])
def test_compare_keyboard_interrupt(in_tmp, capsys, monkeypatch, several):
    monkeypatch.setattr("acausal.runtime.simulate.simulate", raise_interrupt)
    models = [str(FIRST), str(TWO_MASSES)] if several else [str(FIRST)]
    assert main(["compare", *models]) == 130
    one_line_error(capsys.readouterr().err, "interrupted")


LONG_RUN = """
    from pathlib import Path

    from acausal import Eq, Experiment, Model, Variable, der


    class Spin(Model):
        experiment = Experiment(stop_time=1e7, interval=100.0)  # a row every few hundred steps
        x = Variable(start=1.0, fixed=True)
        v = Variable(start=0.0, fixed=True)

        def equations(self):
            Path("started").write_text("")  # translation has begun: the command runs
            return [Eq(der(self.x), self.v), Eq(der(self.v), -self.x)]
    """


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT")
def test_sigint_during_a_run(tmp_path):
    """A real Ctrl-C during the run: status 130, no traceback, and the CSV holds the run up to then."""
    write_model(tmp_path, "spin.py", LONG_RUN)
    env = dict(os.environ, MPLBACKEND="Agg")
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    process = subprocess.Popen([sys.executable, "-m", "acausal", "simulate", "spin.py", "--out",
                                "spin.csv"], cwd=tmp_path, env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True,
                               # Python handles SIGINT only if it is not ignored when it starts
                               preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        deadline = time.monotonic() + 60
        while not (tmp_path / "started").exists():
            assert process.poll() is None, process.communicate()
            assert time.monotonic() < deadline, "the command did not start"
            time.sleep(0.05)
        time.sleep(2.0)  # well into the run (translating this model takes milliseconds)
        process.send_signal(signal.SIGINT)
        out, err = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    assert process.returncode == 130, err
    one_line_error(err, "interrupted", "spin.csv")
    header, rows = read_csv(tmp_path / "spin.csv")
    assert header[0] == "time" and len(rows) > 1 and 0 < rows[-1][0] < 1e7
    assert "wrote spin.csv" in out
