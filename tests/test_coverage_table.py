"""docs/coverage.md is what docs/coverage.py writes from the library, the examples and the tests."""

from __future__ import annotations

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _coverage_script():
    spec = importlib.util.spec_from_file_location("coverage_script", ROOT / "docs" / "coverage.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_coverage_table_is_up_to_date():
    written = (ROOT / "docs" / "coverage.md").read_text()
    assert written == _coverage_script().table(), "docs/coverage.md is stale: run python docs/coverage.py"


def test_a_class_found_by_name_must_name_its_modelica_class():
    # the Rotational Brake must not count as the Translational one
    script = _coverage_script()
    rotational = script.implemented("Modelica.Mechanics.Rotational.Components")
    translational = script.implemented("Modelica.Mechanics.Translational.Components")
    assert "Inertia" in rotational and "Mass" in translational
    if "Brake" in rotational and "Brake" in translational:
        assert rotational["Brake"] is not translational["Brake"]
