"""Every reproduced MSL example lies in the csv-compare tube of its reference result.

These are the acceptance checks of the project: the Modelica Association's
reference results (Dymola, DASSL, tolerance 1e-6) against acausal at its
default settings.  They skip, saying where they looked, when the data is absent.
"""

from __future__ import annotations

import importlib

import pytest

from acausal import simulate
from acausal.tools.compare import compare_signals, load_reference, reference_dir

EXAMPLES = [
    ("first", "First", 0),
    ("two_masses", "TwoMasses", 0),
    ("friction", "Friction", 8),
    ("coupled_clutches", "CoupledClutches", 9),
    ("friction_elements", "TestFriction", 8),
]


def _reference_or_skip(modelica_class):
    directory = reference_dir()
    if not (directory / modelica_class).is_dir():
        pytest.skip(f"MSL reference results not found at {directory}; set ACAUSAL_REFERENCE_DIR "
                    f"(modelica/MAP-LIB_ReferenceResults, branch v4.1.0)")
    return load_reference(modelica_class)


@pytest.mark.parametrize("module, name, state_events", EXAMPLES, ids=[e[1] for e in EXAMPLES])
def test_example_matches_reference(module, name, state_events):
    """All compared signals (states, modes, start flags) lie in the tube."""
    model_class = getattr(importlib.import_module(f"examples.{module}"), name)
    reference = _reference_or_skip(model_class.modelica_class)
    result = simulate(model_class())
    assert result.success, result.message
    comparison = compare_signals(reference, result.time, result.columns)
    assert comparison.passed, comparison.table()
    # the same number of mode-changing state events as Dymola reports
    changing = [e for e in result.events if e.kind == "state" and e.changes]
    assert len(changing) == state_events, [str(e) for e in changing]
