"""What a component offers, found without reading the library's source (issue 14, part 1).

``help(Class)`` lists every parameter with its default and unit, nothing
prints an object address, ``repr`` of an instance is its constructor call
with the modifiers, ``describe`` gives the table ``acausal show`` prints,
and ``acausal list`` lists a package's classes.
"""

from __future__ import annotations

import pydoc
import re

import pytest

import acausal
from acausal.language import Component, Connector, Model, Parameter, Variable, describe
from acausal.library import blocks, rotational, thermal, translational
from acausal.library.rotational import Clutch, Inertia
from acausal.tools.catalog import component_classes, find_object, main_list, main_show

LIBRARY_CLASSES = sorted({klass for package in (blocks, rotational, thermal, translational)
                          for klass in component_classes(package)},
                         key=lambda klass: f"{klass.__module__}.{klass.__name__}")
COMPONENT_CLASSES = [klass for klass in LIBRARY_CLASSES if issubclass(klass, Component)]

ADDRESS = re.compile(r"at 0x[0-9a-fA-F]+|object>")


def _ids(klass: type) -> str:
    return f"{klass.__module__.split('.')[2]}.{klass.__name__}"


def _help_text(obj) -> str:
    return pydoc.render_doc(obj, renderer=pydoc.plaintext)


def _parameters(klass: type) -> dict[str, Parameter]:
    return {name: d for name, d in klass.declarations().items() if isinstance(d, Parameter)}


def test_every_library_package_offers_component_classes():
    assert len(COMPONENT_CLASSES) > 100
    assert Clutch in COMPONENT_CLASSES and Inertia in COMPONENT_CLASSES


@pytest.mark.parametrize("klass", COMPONENT_CLASSES, ids=_ids)
def test_help_lists_every_parameter_with_default_and_unit(klass):
    """help(Class): one ``name : default ..., unit ...`` line per parameter, inherited ones too."""
    text = "\n".join(line[4:] if line.startswith(" |  ") else line for line in _help_text(klass).splitlines())
    for name, parameter in _parameters(klass).items():
        # the last such line: a docstring's own Parameters section comes before the generated one
        line = next((l for l in reversed(text.splitlines()) if l.startswith(f"{name} : ")), None)
        assert line is not None, f"help({klass.__name__}) does not list {name}"
        if parameter.default is not None:
            assert "default " in line, line
        if parameter.unit:
            assert f"unit {parameter.unit}" in line, line


@pytest.mark.parametrize("klass", LIBRARY_CLASSES, ids=_ids)
def test_no_object_address_in_help_repr_or_describe(klass):
    texts = [_help_text(klass), repr(klass.declarations() if issubclass(klass, Component) else klass.variables()),
             describe(klass)]
    if issubclass(klass, Component):
        instance = klass()
        texts += [repr(instance), describe(instance)]
    for text in texts:
        assert not ADDRESS.search(text), ADDRESS.search(text).group(0)


@pytest.mark.parametrize("klass", COMPONENT_CLASSES, ids=_ids)
def test_repr_of_an_unmodified_instance_is_short(klass):
    text = repr(klass())
    assert text.startswith(f"{klass.__name__}(") and text.endswith(")")
    assert len(text) < 200, text


@pytest.mark.parametrize("klass", COMPONENT_CLASSES, ids=_ids)
def test_describe_shows_every_parameter_with_default_and_unit(klass):
    lines = describe(klass, width=400).splitlines()  # wide: one line per declaration

    def row(name: str) -> str:
        # an array is one row, its name followed by its size: u[nin], x[size(A, 1)]
        found = [line for line in lines if re.match(rf"  {re.escape(name)}(\[[^\]]*\])?  ", line)]
        assert found, f"describe({klass.__name__}) does not list {name}"
        return found[0] + "  "

    for name, parameter in _parameters(klass).items():
        if parameter.unit:
            assert f"  {parameter.unit}  " in row(name), row(name)
        if parameter.default is not None:
            assert row(name).split("  ", 2)[2].strip(), row(name)
    for name, declaration in klass.declarations().items():
        if isinstance(declaration, (Variable, Connector)):
            row(name)


def test_a_docstring_with_its_own_parameters_section_keeps_it_and_gets_declared_parameters():
    from acausal.library.rotational import LossyGear

    doc = LossyGear.__doc__
    assert doc.count("\nParameters\n----------\n") == 1
    assert "\nDeclared parameters\n-------------------\nratio : default" in doc


def test_repr_of_an_instance_shows_the_modifiers():
    assert repr(Clutch(fn_max=100)) == "Clutch(fn_max=100)"
    assert repr(Inertia()) == "Inertia()"
    assert repr(Inertia(J=2, w=dict(start=1, fixed=True))) == "Inertia(J=2, w=dict(start=1, fixed=True))"
    assert repr(Parameter(1.0, unit="kg.m2", description="Moment of inertia")) == \
        "Parameter(1.0, unit='kg.m2', description='Moment of inertia')"


def test_describe_of_a_class_is_a_table_with_defaults_units_limits_and_descriptions():
    text = describe(Clutch, width=200)
    assert text.startswith("Clutch (acausal.library.rotational.components.Clutch)\n")
    lines = text.splitlines()
    header = lines.index("Parameters") + 1
    assert lines[header].split() == ["name", "default", "unit", "min", "notes", "description"]
    fn_max = next(line for line in lines if line.startswith("  fn_max "))
    assert fn_max.split() == ["fn_max", "1.0", "N", "0", "Maximum", "normal", "force"]
    assert "Connectors" in lines and "Variables" in lines
    heat_port = next(line for line in lines if line.startswith("  heatPort "))
    assert "if useHeatPort" in heat_port


def test_describe_of_an_instance_shows_the_modified_values():
    text = describe(Inertia(J=3, w=dict(start=2, fixed=True)), width=200)
    assert text.startswith("Inertia(J=3, w=dict(start=2, fixed=True))\n")
    j = next(line for line in text.splitlines() if line.startswith("  J "))
    assert j.split()[:4] == ["J", "3", "kg.m2", "0"] and "modified" in j
    w = next(line for line in text.splitlines() if line.startswith("  w "))
    assert w.split()[:4] == ["w", "Real", "rad/s", "2"] and "fixed" in w


def test_describe_of_a_model_lists_its_sub_components_with_the_nested_modifiers():
    class Pair(Model):
        def build(self):
            self.first = Inertia(J=2)
            self.second = Inertia()

    text = describe(Pair(second=dict(J=7)))
    assert "Components" in text
    assert re.search(r"first\s+Inertia\s+Inertia\(J=2\)", text)
    assert re.search(r"second\s+Inertia\s+Inertia\(J=7\)", text)
    model = Pair()
    describe(model)
    assert not model._built  # describing builds a copy, not the user's instance


def test_describe_is_exported_and_rejects_other_objects():
    assert acausal.describe is describe
    with pytest.raises(TypeError):
        describe(42)


# --------------------------------------------------------------------------
# acausal show / acausal list


@pytest.mark.parametrize("name", ["library.rotational.Clutch", "acausal.library.rotational.Clutch"])
def test_show_prints_the_table(name, capsys):
    assert main_show([name]) == 0
    out = capsys.readouterr().out
    assert out == describe(Clutch)
    assert re.search(r"fn_max\s+1\.0\s+N\s+0\s+Maximum normal force", out)


def test_show_a_class_of_a_file(tmp_path, capsys):
    path = tmp_path / "mymodels.py"
    path.write_text("from acausal import Component, Parameter\n\n"
                    "class Valve(Component):\n"
                    "    '''A valve.'''\n"
                    "    opening = Parameter(0.5, unit='1', min=0, max=1, description='How open')\n")
    assert main_show([f"{path}:Valve"]) == 0
    out = capsys.readouterr().out
    assert re.search(r"opening\s+0\.5\s+1\s+0\s+1\s+How open", out)
    assert main_show([str(path)]) == 0  # the file's only component class
    assert "opening" in capsys.readouterr().out
    assert main_show([f"{path}:Valv"]) == 2
    assert f"did you mean {path}:Valve?" in capsys.readouterr().err


@pytest.mark.parametrize("name, suggestion", [
    ("library.rotational.Clutchh", "library.rotational.Clutch"),
    ("library.rotationl.Clutch", "library.rotational"),
    ("acausal.library.rotational.Clutchh", "acausal.library.rotational.Clutch"),
])
def test_show_an_unknown_name_suggests_and_exits_2(name, suggestion, capsys):
    assert main_show([name]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert f"did you mean {suggestion}" in captured.err


def test_show_a_package_or_a_parameter_is_a_usage_error(capsys):
    assert main_show(["library.rotational"]) == 2
    assert "acausal list library.rotational" in capsys.readouterr().err
    assert main_show(["library.rotational.Clutch.fn_max"]) == 2
    assert "not a component class" in capsys.readouterr().err
    assert main_show([]) == 2  # argparse: the name is required


def test_list_a_package(capsys):
    assert main_list(["library.rotational"]) == 0
    out = capsys.readouterr().out
    assert re.search(r"^  Clutch\s+Clutch with controlled normal force", out, re.MULTILINE)
    assert re.search(r"^  Inertia\s+1D rotational component with inertia", out, re.MULTILINE)
    assert "Connectors" in out and "Flange_a" in out
    assert "_" + "NormalForceFriction" not in out  # private classes are not offered


def test_list_without_a_name_lists_the_library_packages(capsys):
    assert main_list([]) == 0
    out = capsys.readouterr().out
    for package in ("blocks", "rotational", "thermal", "translational"):
        assert re.search(rf"^  {package}\s+Modelica\.", out, re.MULTILINE)


def test_list_an_unknown_package_suggests_and_exits_2(capsys):
    assert main_list(["library.rotationl"]) == 2
    assert "did you mean library.rotational" in capsys.readouterr().err
    assert main_list(["library.rotational.Clutch"]) == 2
    assert "acausal show library.rotational.Clutch" in capsys.readouterr().err


def test_find_object_prefers_the_installed_package():
    assert find_object("library.rotational.Clutch") is Clutch
    assert find_object("acausal.library.rotational.Clutch") is Clutch
