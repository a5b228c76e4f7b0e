"""``acausal check``: check_model and main_check's report and exit statuses on model files."""

from __future__ import annotations

import textwrap

import pytest

from acausal.tools.check import check_model, main_check

MODELS = textwrap.dedent('''
    from acausal import Model, Parameter, Variable, der
    from acausal.language import Eq


    class Good(Model):
        J = Parameter(2.0, unit="kg.m2")
        d = Parameter(0.5, unit="N.m.s/rad")
        w = Variable(unit="rad/s", start=1.0, fixed=True)

        def equations(self):
            return [Eq(self.J * der(self.w), -self.d * self.w)]


    class MixedUnits(Model):
        d = Parameter(0.5, unit="N.m.s/rad")
        T = Parameter(0.5, unit="s")
        w = Variable(unit="rad/s", start=1.0, fixed=True)
        y = Variable(unit="rad/s")

        def equations(self):
            return [Eq(der(self.w), -self.w / self.T), Eq(self.y, self.w + self.d)]


    class Underdetermined(Model):
        T = Parameter(0.5, unit="s")
        w = Variable(unit="rad/s", start=1.0, fixed=True)
        y = Variable(unit="rad/s")

        def equations(self):
            return [Eq(der(self.w), -self.w / self.T)]
''')


@pytest.fixture()
def model_file(tmp_path):
    path = tmp_path / "models.py"
    path.write_text(MODELS)
    return str(path)


def test_consistent_model_passes(model_file, capsys):
    assert main_check([f"{model_file}:Good"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("Good: passed")
    assert "0 inconsistent" in out


def test_mixed_units_warn_and_fail_only_when_strict(model_file, capsys):
    assert main_check([f"{model_file}:MixedUnits"]) == 0
    out = capsys.readouterr().out
    assert "passed with 1 unit warning" in out
    assert "MixedUnits eq. 2" in out and "rad/s" in out and "N.m.s/rad" in out
    assert main_check([f"{model_file}:MixedUnits", "--strict"]) == 1
    out = capsys.readouterr().out
    assert "FAILED" in out and "error (units)" in out


def test_structural_error_fails(model_file, capsys):
    assert main_check([f"{model_file}:Underdetermined"]) == 1
    out = capsys.readouterr().out
    assert "FAILED" in out and "error (structure)" in out and "UnderDeterminedError" in out


def test_usage_errors_are_status_2(model_file, tmp_path, capsys):
    assert main_check([str(tmp_path / "missing.py")]) == 2
    assert "file not found" in capsys.readouterr().err
    assert main_check([f"{model_file}:Nope"]) == 2
    assert "no model 'Nope'" in capsys.readouterr().err
    assert main_check([model_file]) == 2  # several models: name one
    assert "several models" in capsys.readouterr().err
    assert main_check([]) == 2
    assert main_check(["--help"]) == 0


def test_check_model_report_fields(model_file):
    from acausal.tools.cli import load_model_class

    mixed = load_model_class(f"{model_file}:MixedUnits")
    report = check_model(mixed())
    assert report.ok and report.exit_code() == 0 and report.unit_findings == 1
    strict = check_model(mixed(), strict=True)
    assert not strict.ok and strict.exit_code() == 1
    broken = check_model(load_model_class(f"{model_file}:Underdetermined")())
    assert broken.problems[0].stage == "structure"
