"""help() and pydoc on the package, the language and the component classes.

pydoc used to crash on ``der``/``pre``/``initial`` (sympy undefined
functions have ``__module__ = None``), and a component's help listed its
declarations as ``<Parameter object>``.  A component class's docstring now
ends with numpydoc sections (Parameters, Connectors, Variables) generated
from its declarations, and declarations have a constructor-like repr.

The expected defaults and units of the Clutch and the Inertia are those of
the Modelica specification text (msl-rotational.md, sections 2.4, 2.10, 3.1
and 3.7), written in Modelica's unit syntax ("kg.m2" for kg·m²).
"""

from __future__ import annotations

import ast
import pydoc
import subprocess
import sys

import pytest
import sympy as sp

import acausal
from acausal.components.rotational import Flange_a, Support
from acausal.language import (
    Boolean,
    Component,
    Connector,
    Flow,
    Integer,
    Parameter,
    Potential,
    RealInput,
    RealOutput,
    StateSelect,
    Variable,
    der,
    initial,
    pre,
)
from acausal.library.rotational import Clutch, Inertia


def _help_text(obj) -> str:
    """What help(obj) prints, without pydoc's ' |  ' class margin."""
    text = pydoc.render_doc(obj, renderer=pydoc.plaintext)
    return "\n".join(line[4:] if line.startswith((" |  ", " |")) else line for line in text.splitlines())


def _section(text: str, title: str) -> dict[str, str]:
    """{name: summary} of the entries of a numpydoc section ("name : summary" lines)."""
    lines = text.splitlines()
    start = lines.index(title)
    assert lines[start + 1] == "-" * len(title), lines[start:start + 2]
    entries = {}
    for line in lines[start + 2:]:
        if not line.strip():
            break
        if not line.startswith(" "):
            name, _, summary = line.partition(" : ")
            entries[name] = summary
    return entries


def _fields(summary: str) -> dict[str, str]:
    """'default 1.0, unit N, min 0, structural' -> {'default': '1.0', 'unit': 'N', 'min': '0', 'structural': ''}."""
    parts, depth, current = [], 0, ""
    for char in summary:  # split at ", " outside brackets (a default may be a table)
        depth += (char in "([{") - (char in ")]}")
        if char == "," and depth == 0:
            parts.append(current)
            current = ""
        else:
            current += char
    parts.append(current)
    fields = {}
    for part in parts:
        key, _, value = part.strip().partition(" ")
        fields[key] = value
    return fields


# --------------------------------------------------------------------------
# pydoc on modules


@pytest.mark.parametrize("module", ["acausal", "acausal.language", "acausal.library.rotational"])
def test_pydoc_of_module_exits_zero(module):
    """``python -m pydoc MODULE`` succeeds and documents the language."""
    run = subprocess.run([sys.executable, "-m", "pydoc", module], capture_output=True, text=True,
                         timeout=120)
    assert run.returncode == 0, run.stderr[-2000:]
    assert "Traceback" not in run.stderr
    if module == "acausal.library.rotational":
        assert "class Clutch(" in run.stdout
        assert "fn_max : default 1.0, unit N, min 0" in run.stdout
    else:
        assert "der(expr): the time derivative" in run.stdout
        assert "class Parameter(Declaration)" in run.stdout


def test_help_of_package_in_process():
    """help(acausal) renders (the crash was in pydoc.classname on der.__module__ = None)."""
    text = _help_text(acausal)
    assert "pre(v): the left limit of the discrete variable" in text
    assert "initial(): true only while the initialization problem is solved" in text


@pytest.mark.parametrize("function, name", [(der, "der"), (pre, "pre"), (initial, "initial")])
def test_operators_are_still_the_plain_sympy_functions(function, name):
    """The documented der/pre/initial build exactly the expressions sympy.Function(name) builds."""
    x = sp.Symbol("x", real=True)
    plain = sp.Function(name)
    assert function.__module__ == "acausal.language"
    assert function.__doc__.startswith(f"{name}(")
    assert function == plain and plain == function
    assert hash(function) == hash(plain)
    assert function(x) == plain(x) and plain(x) == function(x)
    assert hash(function(x)) == hash(plain(x))
    assert sp.srepr(function(x)) == sp.srepr(plain(x)) == f"Function('{name}')(Symbol('x', real=True))"
    assert plain(x).has(function) and function(x).has(plain)
    assert function(x).func == plain


# --------------------------------------------------------------------------
# help of component classes


def test_clutch_help_lists_parameters_with_the_spec_defaults_and_units():
    """help(Clutch) shows fn_max, mu_pos, peak, cgeo and useHeatPort with default and unit.

    Spec 3.7: mu_pos = [0, 0.5] (friction coefficient, no unit), peak = 1
    (min 1), cgeo = 1 (min 0), fn_max [N] (min 0, start 1); 2.10:
    useHeatPort = false with Evaluate = true (a structural parameter).
    """
    text = _help_text(Clutch)
    assert text.index("Clutch with controlled normal force") < text.index("Parameters\n----------")
    parameters = {name: _fields(summary) for name, summary in _section(text, "Parameters").items()}

    fn_max = parameters["fn_max"]
    assert float(fn_max["default"]) == 1.0
    assert fn_max["unit"] == "N"
    assert float(fn_max["min"]) == 0.0

    mu_pos = parameters["mu_pos"]
    assert ast.literal_eval(mu_pos["default"]) == [[0, 0.5]]
    assert "unit" not in mu_pos

    assert float(parameters["peak"]["default"]) == 1.0
    assert float(parameters["peak"]["min"]) == 1.0
    assert "unit" not in parameters["peak"]
    assert float(parameters["cgeo"]["default"]) == 1.0
    assert float(parameters["cgeo"]["min"]) == 0.0
    assert "unit" not in parameters["cgeo"]

    assert parameters["useHeatPort"]["default"] == "False"
    assert "structural" in parameters["useHeatPort"]

    # inherited declarations are listed too (spec 2.4: phi_nominal = 1e-4 rad)
    assert float(parameters["phi_nominal"]["default"]) == 1e-4
    assert parameters["phi_nominal"]["unit"] == "rad"


def test_clutch_help_lists_connectors_and_variables():
    """The conditional heat port with its condition, the signal input, variables with units."""
    text = _help_text(Clutch)
    connectors = _section(text, "Connectors")
    assert connectors["heatPort"] == "HeatPort_a, if useHeatPort"
    assert connectors["flange_a"] == "Flange_a"
    assert connectors["f_normalized"].startswith("RealInput")
    variables = {name: _fields(summary) for name, summary in _section(text, "Variables").items()}
    assert variables["lossPower"]["unit"] == "W"  # spec 2.10
    assert variables["w_rel"]["unit"] == "rad/s"
    assert "Boolean" in variables["locked"]
    assert "fixed" in variables["startForward"]
    # descriptions follow their entry, indented
    assert "fn_max : default 1.0, unit N, min 0\n    Maximum normal force" in text


def test_clutch_help_shows_no_object_addresses():
    """The declarations pydoc lists among the class attributes read as constructor calls."""
    text = _help_text(Clutch)
    assert " object at 0x" not in text
    assert "<acausal.language.Parameter object>" not in text
    assert "fn_max = Parameter(1.0, unit='N', min=0, description='Maximum normal force')" in text
    declarations = repr(Clutch.declarations())
    assert "0x" not in declarations and "object>" not in declarations
    assert "'heatPort': HeatPort_a(condition='useHeatPort'," in declarations


def test_inertia_help_shows_J_in_kg_m2():
    """Spec 3.1: J [kg·m²], min 0, start 1."""
    parameters = {name: _fields(summary) for name, summary in _section(_help_text(Inertia), "Parameters").items()}
    assert parameters["J"]["unit"] == "kg.m2"
    assert float(parameters["J"]["default"]) == 1.0
    assert float(parameters["J"]["min"]) == 0.0


def test_user_component_with_a_conditional_connector():
    """A class written by a user gets the sections; its docstring stays first, the condition is shown."""

    class Bearing(Component):
        """A bearing with an optional housing.

        More text.
        """

        useSupport = Parameter(False, structural=True, description="= true, if the support is enabled")
        d = Parameter(0.5, unit="N.m.s/rad", min=0, max=10, description="Damping constant")
        flange = Flange_a(description="The shaft")
        support = Support(condition="useSupport", description="Housing")
        housing2 = Support(condition=lambda c: c.useSupport)
        tau = Variable(unit="N.m", start=1.5, fixed=True, description="Friction torque")

        def equations(self):
            return []

    class Subclass(Bearing):
        k = Parameter(2.0, description="Extra")

    doc = Bearing.__doc__
    assert doc.startswith("A bearing with an optional housing.\n\nMore text.\n\nParameters\n----------\n")
    assert _section(doc, "Connectors") == {"flange": "Flange_a", "support": "Support, if useSupport",
                                           "housing2": "Support, conditional"}
    assert _section(doc, "Parameters") == {"useSupport": "default False, structural",
                                           "d": "default 0.5, unit N.m.s/rad, min 0, max 10"}
    assert _section(doc, "Variables") == {"tau": "Real, unit N.m, start 1.5, fixed"}
    assert "    Housing\n" in doc

    # inherited declarations after the own ones; a class without a docstring gets only the sections
    sub = Subclass.__doc__
    assert sub.startswith("Parameters\n----------\nk : default 2.0\n    Extra\nuseSupport : ")
    assert _section(sub, "Connectors")["support"] == "Support, if useSupport"
    assert "support : Support, if useSupport" in _help_text(Subclass)
    # instances see the same docstring
    assert Bearing().__doc__ == doc


def test_component_without_declarations_keeps_its_docstring():
    class Empty(Component):
        """Nothing declared."""

    class NoDoc(Component):
        pass

    assert Empty.__doc__ == "Nothing declared."
    assert NoDoc.__doc__ is None


# --------------------------------------------------------------------------
# repr of declarations


def _attributes(declaration) -> dict:
    return {key: value for key, value in vars(declaration).items() if key != "name"}


@pytest.mark.parametrize("declaration", [
    Parameter(0.5, unit="kg.m2", min=0, description="Moment of inertia"),
    Parameter(),
    Parameter([[0.0, 0.5], [1.0, 0.3]], structural=True, max=3.5, fixed=False, condition="useTable",
              description="it's a 'table'"),
    Parameter(StateSelect.prefer, structural=True),
    Variable(start=1.0, fixed=True, unit="rad", nominal=1e-3, state_select=StateSelect.always, min=-1, max=1,
             description="angle"),
    RealInput(unit="1", description="signal"),
    RealOutput(),
    Boolean(start=True, fixed=True),
    Integer(start=3, min=-1, max=3),
    Potential(unit="K"),
    Flow(unit="W"),
    Flange_a(condition="useSupport", description="flange"),
])
def test_repr_round_trips(declaration):
    """eval(repr(d)) is a declaration of the same class with the same attributes."""
    namespace = {cls.__name__: cls for cls in (Parameter, Variable, RealInput, RealOutput, Boolean, Integer,
                                                Potential, Flow, Flange_a, StateSelect)}
    text = repr(declaration)
    copy = eval(text, namespace)  # noqa: S307 - the point of the test
    assert type(copy) is type(declaration)
    assert _attributes(copy) == _attributes(declaration), text
    assert repr(copy) == text


def test_repr_shows_only_what_differs_from_the_defaults():
    assert (repr(Parameter(0.5, unit="kg.m2", min=0, description="Moment of inertia"))
            == "Parameter(0.5, unit='kg.m2', min=0, description='Moment of inertia')")
    assert repr(Parameter(unit="N")) == "Parameter(unit='N')"
    assert repr(Parameter(1.0, structural=True)) == "Parameter(1.0, structural=True)"
    assert repr(RealInput(unit="1")) == "RealInput(unit='1')"  # its causality is not an argument
    assert repr(Variable()) == "Variable()"
    assert repr(Variable(start=0)) == "Variable(start=0)"  # an int start is not the default 0.0
    assert repr(Boolean(start=True)) == "Boolean(start=True)"
    assert repr(Flange_a()) == "Flange_a()"
    assert repr(Variable(state_select=lambda c: c.stateSelect)).startswith(
        "Variable(state_select=<function test_repr_shows_only_what_differs_from_the_defaults.<locals>.<lambda>>")


def test_connector_class_repr():
    class Pin(Connector):
        family = "electrical"
        v = Potential(unit="V")
        i = Flow(unit="A")

    assert repr(Pin(condition="useHeatPort")) == "Pin(condition='useHeatPort')"
    assert Pin.variables()["v"].__repr__() == "Potential(unit='V')"
