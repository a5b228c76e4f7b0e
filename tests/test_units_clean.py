"""Every component of the libraries and every example passes the unit check.

Each exported component class is flattened inside a small model that feeds
its signal inputs from constants (whose output has no unit, so they check
nothing) and gives parameters without a default the value 1; each model in
``examples/*.py`` is flattened as it is.  No equation may have terms in
different units.

The friction elements and the lossy gear check too: their path parameter
``sa`` is declared in the unit of the torque (force) it is compared with, and
where it stands for an acceleration it is multiplied by the element's unit
constants (``unitAngularAcceleration/unitTorque``,
``unitAcceleration/unitForce``, as in the MSL).
"""

from __future__ import annotations

import importlib
import warnings
from pathlib import Path

import pytest

from acausal.compiler.flatten import flatten
from acausal.compiler.units import check_units
from acausal.errors import UnitWarning
from acausal.language import Model, Parameter, Variable
from acausal.library.blocks import BooleanConstant, Constant, IntegerTable
from library_checks import exported_classes

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _stand_in(declaration: Parameter) -> float:
    """A value for a parameter without default that respects its upper limit."""
    if declaration.max is not None and declaration.max < 1:
        return declaration.max - 1.0
    return 1.0


def _harness(klass: type) -> Model:
    """A model holding one ``klass`` instance with every signal input fed by a constant."""

    class Harness(Model):
        def build(self):
            probe = klass()
            missing = {key: _stand_in(d) for key, d in probe.declarations().items()
                       if isinstance(d, Parameter) and d.default is None and not d.structural}
            self.x = klass(**missing)
            self.x.ensure_built()
            for key, declaration in self.x.declarations().items():
                if (isinstance(declaration, Variable) and declaration.causality == "input"
                        and declaration.enabled(self.x)):
                    source = (BooleanConstant() if declaration.kind == "boolean" else
                              IntegerTable(table=[[0.0, 1]]) if declaration.kind == "integer" else Constant())
                    setattr(self, f"source_{key}", source)
                    self.connect(source.y, getattr(self.x, key))

    Harness.__name__ = f"Harness{klass.__name__}"
    return Harness()


def _example_models() -> dict[str, type]:
    found = {}
    for path in sorted(EXAMPLES.glob("*.py")):
        if path.name == "__init__.py":
            continue
        module = importlib.import_module(f"examples.{path.stem}")
        for name, value in vars(module).items():
            if isinstance(value, type) and issubclass(value, Model) and value.__module__ == module.__name__:
                found[f"{path.stem}:{name}"] = value
    return found


def _assert_clean(model: Model) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UnitWarning)
        report = check_units(flatten(model))
    assert not report.unparsed, f"unit strings not understood: {report.unparsed}"
    assert not report.findings, "\n".join(str(f) for f in report.findings)


LIBRARY = exported_classes()
MODELS = _example_models()


@pytest.mark.parametrize("name", sorted(LIBRARY))
def test_library_component_units(name):
    _assert_clean(_harness(LIBRARY[name]))


@pytest.mark.parametrize("name", sorted(MODELS))
def test_example_units(name):
    _assert_clean(MODELS[name]())


def test_the_lists_are_not_empty():
    assert len(LIBRARY) > 100 and len(MODELS) > 30
