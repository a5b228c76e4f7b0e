"""Tests of the ``acausal`` command line (acausal.tools.cli, python -m acausal)."""

from __future__ import annotations

import csv
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from acausal.tools.cli import main
from acausal.tools.compare import bundled_reference_dir, reference_dir

REPO = Path(__file__).resolve().parents[2]
FIRST = REPO / "examples" / "first.py"
TWO_MASSES = REPO / "examples" / "two_masses.py"

#: Final value of inertia3.w in the MSL reference result of Rotational.Examples.First.
FIRST_W3_FINAL = -0.138332


def read_csv(path: Path) -> tuple[list[str], list[list[float]]]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return rows[0], [[float(v) for v in row] for row in rows[1:]]


def write_model(folder: Path, name: str, source: str) -> Path:
    path = folder / name
    path.write_text(textwrap.dedent(source))
    return path


def needs_reference(modelica_class: str) -> None:
    folder = reference_dir() / modelica_class
    # the bundled copy holds the examples' references: skip only for a folder chosen by the environment
    if reference_dir() != bundled_reference_dir() and not folder.is_dir():
        pytest.skip(f"no reference results for {modelica_class} in {reference_dir()} "
                    f"(ACAUSAL_REFERENCE_DIR; unset it to use the bundled copy)")


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    """Run in an empty current directory (default outputs land there)."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


# ---------------------------------------------------------------------------
# simulate
# ---------------------------------------------------------------------------


def test_simulate_selected_signals(in_tmp, capsys):
    out = in_tmp / "tmp.csv"
    status = main(["simulate", str(FIRST), "--out", str(out),
                   "--signals", "inertia3.w,damper.phi_rel"])
    assert status == 0
    header, rows = read_csv(out)
    assert header == ["time", "inertia3.w", "damper.phi_rel"]
    assert rows[0][0] == 0.0 and rows[-1][0] == pytest.approx(1.0)
    assert rows[-1][1] == pytest.approx(FIRST_W3_FINAL, abs=1e-3)
    printed = capsys.readouterr().out
    assert "First: ok" in printed
    assert str(out) in printed


def test_simulate_writes_every_variable_by_default(in_tmp, capsys):
    assert main(["simulate", str(FIRST), "--stop-time", "0.1"]) == 0
    header, rows = read_csv(in_tmp / "First.csv")
    assert header[0] == "time"
    # states, algebraic variables and aliases eliminated by the engine
    for name in ("inertia1.w", "idealGear.flange_a.tau", "inertia3.w", "damper.phi_rel"):
        assert name in header
    assert rows[-1][0] == pytest.approx(0.1)


def test_simulate_options_are_passed_on(in_tmp):
    out = in_tmp / "short.csv"
    status = main(["simulate", f"{FIRST}:First", "--start-time", "0", "--stop-time", "0.2",
                   "--interval", "0.05", "--method", "radau", "--rtol", "1e-5", "--atol", "1e-8",
                   "--out", str(out), "--signals", "inertia3.w"])
    assert status == 0
    _, rows = read_csv(out)
    assert [r[0] for r in rows] == pytest.approx([0.0, 0.05, 0.1, 0.15, 0.2])


def test_simulate_failure_keeps_partial_csv(in_tmp, capsys):
    path = write_model(in_tmp, "blow.py", """
        from acausal import Eq, Experiment, Model, Variable, der


        class Blow(Model):
            experiment = Experiment(stop_time=2.0, interval=0.01)
            x = Variable(start=1.0, fixed=True)

            def equations(self):
                return [Eq(der(self.x), self.x ** 2)]  # x = 1/(1 - t) blows up at t = 1
        """)
    assert main(["simulate", str(path)]) == 1
    err = capsys.readouterr().err
    assert "failed" in err and "Traceback" not in err
    header, rows = read_csv(in_tmp / "Blow.csv")
    assert header[:2] == ["time", "x"]
    assert 0.9 < rows[-1][0] < 1.1  # stopped near the blow-up, earlier rows kept


def test_simulate_unknown_signal(in_tmp, capsys):
    status = main(["simulate", str(FIRST), "--stop-time", "0.01", "--signals", "inertia3.ww"])
    assert status == 2
    err = capsys.readouterr().err
    assert "inertia3.ww" in err and "inertia3.w" in err


# ---------------------------------------------------------------------------
# compare
# ---------------------------------------------------------------------------


def test_compare_first_passes(in_tmp, capsys):
    needs_reference("Modelica.Mechanics.Rotational.Examples.First")
    assert main(["compare", str(FIRST)]) == 0
    out = capsys.readouterr().out
    assert "4 of 4 signals passed" in out
    assert "inertia3.w" in out


def test_compare_two_masses_with_plots(in_tmp, capsys):
    needs_reference("Modelica.Thermal.HeatTransfer.Examples.TwoMasses")
    plots = in_tmp / "plots"
    assert main(["compare", str(TWO_MASSES), "--plot", str(plots)]) == 0
    written = sorted(p.name for p in plots.glob("*.png"))
    assert written == ["TwoMasses.png"]  # one figure per model, a panel per signal
    assert main(["compare", str(TWO_MASSES), "--plot", str(plots), "--plot-per-signal"]) == 0
    written = sorted(p.name for p in plots.glob("*.png"))
    assert written == ["TwoMasses.png", "mass1.T.png", "mass2.T.png"]
    for name in written:
        assert (plots / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_compare_fails_with_status_1(in_tmp, capsys):
    needs_reference("Modelica.Mechanics.Rotational.Examples.First")
    path = write_model(in_tmp, "wrong_first.py", """
        from acausal import Parameter
        from examples.first import First  # the repository root is put on sys.path


        class WrongFirst(First):
            Jload = Parameter(4.0, unit="kg.m2")  # twice the load inertia: not the reference
        """)
    status = main(["compare", str(path)])
    captured = capsys.readouterr()
    assert status == 1
    assert "FAIL" in captured.out
    assert "outside the tube" in captured.err


def test_compare_needs_modelica_class(in_tmp, capsys):
    path = write_model(in_tmp, "plain.py", """
        from acausal import Eq, Model, Variable, der


        class Decay(Model):
            x = Variable(start=1.0, fixed=True)

            def equations(self):
                return [Eq(der(self.x), -self.x)]
        """)
    assert main(["compare", str(path)]) == 2
    assert "modelica_class" in capsys.readouterr().err


def test_compare_missing_reference(in_tmp, capsys):
    path = write_model(in_tmp, "unknown_ref.py", """
        from acausal import Eq, Model, Variable, der


        class Decay(Model):
            modelica_class = "Modelica.Nowhere.Decay"
            x = Variable(start=1.0, fixed=True)

            def equations(self):
                return [Eq(der(self.x), -self.x)]
        """)
    assert main(["compare", str(path), "--reference-dir", str(in_tmp)]) == 2
    err = capsys.readouterr().err
    assert "Modelica.Nowhere.Decay" in err and "Traceback" not in err


def test_compare_uses_the_bundled_references_by_default(in_tmp, capsys, monkeypatch):
    """Without ACAUSAL_REFERENCE_DIR the examples compare against the copy that ships with acausal."""
    monkeypatch.delenv("ACAUSAL_REFERENCE_DIR", raising=False)
    assert main(["compare", str(TWO_MASSES)]) == 0
    assert "2 of 2 signals passed" in capsys.readouterr().out


def test_compare_class_not_bundled_says_how_to_get_it(in_tmp, capsys, monkeypatch):
    monkeypatch.delenv("ACAUSAL_REFERENCE_DIR", raising=False)
    path = write_model(in_tmp, "unbundled.py", """
        from acausal import Eq, Model, Variable, der


        class Decay(Model):
            modelica_class = "Modelica.Nowhere.Decay"
            x = Variable(start=1.0, fixed=True)

            def equations(self):
                return [Eq(der(self.x), -self.x)]
        """)
    assert main(["compare", str(path)]) == 2
    err = capsys.readouterr().err
    assert "Modelica.Nowhere.Decay" in err and "Traceback" not in err
    assert str(bundled_reference_dir()) in err
    assert "ACAUSAL_REFERENCE_DIR" in err and "--reference-dir" in err


# ---------------------------------------------------------------------------
# explain
# ---------------------------------------------------------------------------


def test_explain_command(in_tmp, capsys):
    assert main(["explain", str(FIRST), "--out", str(in_tmp / "pics")]) == 0
    out = capsys.readouterr().out
    assert "States chosen" in out and "BLT" in out
    picture = in_tmp / "pics" / "incidence_First.png"
    assert picture.is_file()
    assert f"wrote {picture}" in out


# ---------------------------------------------------------------------------
# bad input
# ---------------------------------------------------------------------------


def test_missing_file(in_tmp, capsys):
    assert main(["simulate", "no_such_model.py"]) == 2
    assert "no_such_model.py" in capsys.readouterr().err


def test_unknown_model_name_lists_models(in_tmp, capsys):
    assert main(["simulate", f"{FIRST}:Nope"]) == 2
    err = capsys.readouterr().err
    assert "Nope" in err and "First" in err


def test_file_without_model(in_tmp, capsys):
    path = write_model(in_tmp, "nomodel.py", """
        class Helper:
            pass
        """)
    assert main(["simulate", str(path)]) == 2
    err = capsys.readouterr().err
    assert "no subclass of acausal.Model" in err and "Helper" in err


def test_file_with_several_models(in_tmp, capsys):
    path = write_model(in_tmp, "two.py", """
        from acausal import Eq, Model, Variable, der


        class A(Model):
            x = Variable(start=1.0, fixed=True)

            def equations(self):
                return [Eq(der(self.x), -self.x)]


        class B(A):
            pass
        """)
    assert main(["simulate", str(path)]) == 2
    err = capsys.readouterr().err
    assert "A, B" in err
    assert main(["simulate", f"{path}:B", "--out", str(in_tmp / "b.csv")]) == 0


def test_file_that_fails_to_import(in_tmp, capsys):
    path = write_model(in_tmp, "broken_import.py", """
        import no_such_module_anywhere
        """)
    assert main(["simulate", str(path)]) == 2
    err = capsys.readouterr().err
    assert "broken_import.py" in err and "no_such_module_anywhere" in err
    assert "Traceback" not in err


def test_syntax_error(in_tmp, capsys):
    path = write_model(in_tmp, "syntax.py", "class Oops(:\n")
    assert main(["explain", str(path)]) == 2
    assert "SyntaxError" in capsys.readouterr().err


def test_unknown_option(in_tmp, capsys):
    assert main(["simulate", str(FIRST), "--bogus"]) == 2
    assert "--bogus" in capsys.readouterr().err


def test_no_command(capsys):
    assert main([]) == 2
    assert "usage" in capsys.readouterr().err


def test_unknown_method(in_tmp, capsys):
    assert main(["simulate", str(FIRST), "--method", "Magic"]) == 2
    err = capsys.readouterr().err
    assert "Magic" in err and "RK45" in err


@pytest.mark.parametrize("option, value", [("--rtol", "-1"), ("--interval", "0"),
                                           ("--stop-time", "abc")])
def test_bad_numbers(in_tmp, capsys, option, value):
    assert main(["simulate", str(FIRST), option, value]) == 2
    assert option in capsys.readouterr().err


def test_stop_before_start(in_tmp, capsys):
    assert main(["simulate", str(FIRST), "--start-time", "1", "--stop-time", "0.5"]) == 2
    assert "stop time" in capsys.readouterr().err


def test_build_raising_acausal_error(in_tmp, capsys):
    path = write_model(in_tmp, "bad_build.py", """
        from acausal import Model
        from acausal.errors import ModelDefinitionError


        class Broken(Model):
            def build(self):
                raise ModelDefinitionError("broken on purpose", hint="it is a test")
        """)
    assert main(["simulate", str(path)]) == 2
    err = capsys.readouterr().err
    assert "broken on purpose" in err and "it is a test" in err
    assert "Traceback" not in err


def test_structural_error_is_a_model_error(in_tmp, capsys):
    path = write_model(in_tmp, "under.py", """
        from acausal import Eq, Model, Variable, der


        class Under(Model):
            x = Variable(start=1.0, fixed=True)
            y = Variable()

            def equations(self):
                return [Eq(der(self.x), self.y)]
        """)
    for command in ("simulate", "explain"):
        assert main([command, str(path)]) == 2
        err = capsys.readouterr().err
        assert "under-determined" in err and "Traceback" not in err


def test_bad_modifier_at_instantiation(in_tmp, capsys):
    path = write_model(in_tmp, "bad_modifier.py", """
        from acausal import Model
        from acausal.library.rotational import Inertia


        class M(Model):
            def build(self):
                self.inertia = Inertia(Jx=1)
        """)
    assert main(["simulate", str(path)]) == 2
    err = capsys.readouterr().err
    assert "Jx" in err and "Traceback" not in err


# ---------------------------------------------------------------------------
# python -m acausal
# ---------------------------------------------------------------------------


def run_module(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    env["MPLBACKEND"] = "Agg"
    return subprocess.run([sys.executable, "-m", "acausal", *args], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=120)


def test_python_dash_m_simulate(tmp_path):
    out = tmp_path / "tmp.csv"
    done = run_module("simulate", "examples/first.py", "--out", str(out),
                      "--signals", "inertia3.w,damper.phi_rel", cwd=REPO)
    assert done.returncode == 0, done.stderr
    header, rows = read_csv(out)
    assert header == ["time", "inertia3.w", "damper.phi_rel"]
    assert rows[-1][1] == pytest.approx(FIRST_W3_FINAL, abs=1e-3)


def test_python_dash_m_error_status(tmp_path):
    done = run_module("simulate", "examples/missing.py", cwd=REPO)
    assert done.returncode == 2
    assert "examples/missing.py" in done.stderr
    assert "Traceback" not in done.stderr
