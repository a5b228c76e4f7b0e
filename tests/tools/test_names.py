"""`acausal list` and `acausal show` accept every name they print, and the MSL's names (issue 24, item 4).

A new user's session: ``acausal list`` prints the packages (``blocks``,
``thermal``, ...), ``acausal list blocks`` their classes (``CombiTable1Ds``);
each of those names, the dotted short names (``rotational.Clutch``), the
module paths (``acausal.library.rotational.Clutch``) and the names of the
Modelica Standard Library (``Modelica.Mechanics.Rotational.Components.Clutch``)
must find the class.  The MSL names are read here from the docstrings, as
the library writes them (the class's MSL name in parentheses in the first
paragraph), independently of the catalog's own reading.  A name that names
nothing is answered with close names of packages and classes only; every
name suggested must itself be found.
"""

from __future__ import annotations

import contextlib
import importlib
import io
import re
import subprocess
import sys
from pathlib import Path

import pytest

from acausal.language import Component, Connector, describe, own_docstring
from acausal.tools.catalog import NameNotFound, find_object, main_list, main_show

ROOT = Path(__file__).resolve().parents[2]


# --------------------------------------------------------------------------
# What `acausal list` prints


def _list(*argv: str) -> str:
    """What ``acausal list ARGV`` prints (it must succeed)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main_list(list(argv))
    assert status == 0, f"acausal list {' '.join(argv)}: exit {status}: {err.getvalue()}"
    return out.getvalue()


def _section(text: str, title: str) -> list[str]:
    """The names a listing prints under ``title`` (``Packages``, ``Components``, ...)."""
    names, inside = [], False
    for line in text.splitlines():
        if not line.startswith(" "):
            inside = line.strip() == title
        elif inside:
            names.append(line.split()[0])
    return names


@pytest.fixture(scope="module")
def printed() -> list[tuple[str, str]]:
    """(package, class) for every class `acausal list PACKAGE` prints, for every package `acausal list` prints."""
    packages = _section(_list(), "Packages")
    assert {"blocks", "rotational", "thermal", "translational"} <= set(packages), packages
    return [(package, name) for package in packages
            for title in ("Models", "Components", "Connectors")
            for name in _section(_list(package), title)]


def _exported(package: str, name: str) -> type:
    return getattr(importlib.import_module(f"acausal.library.{package}"), name)


MSL_IN_PARENTHESES = re.compile(r"\((Modelica(?:\.[A-Za-z_]\w*)+)")


def _msl(klass: type) -> str | None:
    match = MSL_IN_PARENTHESES.search(own_docstring(klass).split("\n\n")[0])
    return match.group(1) if match else None


def test_every_listed_class_names_its_msl_class_and_no_two_share_one(printed):
    assert len(printed) > 150
    owners: dict[str, set[type]] = {}
    for package, name in printed:
        klass = _exported(package, name)
        msl = _msl(klass)
        assert msl, f"{package}.{name}: its docstring names no MSL class in parentheses"
        owners.setdefault(msl, set()).add(klass)
    shared = {msl: classes for msl, classes in owners.items() if len(classes) > 1}
    assert not shared, f"MSL names claimed by several classes: {shared}"


def test_show_finds_every_listed_class_by_what_list_prints_and_by_its_msl_name(printed, capsys):
    by_name: dict[str, set[type]] = {}
    for package, name in printed:
        by_name.setdefault(name, set()).add(_exported(package, name))
    # a class a library module defines without its package exporting it under that name
    # (blocks.continuous.StateSpace beside the exported discrete one) shares the bare name too
    from acausal.tools.catalog import names

    for path, klass in names().classes.items():
        if path.startswith("acausal.library.") and klass.__name__ in by_name:
            by_name[klass.__name__].add(klass)
    failures = []
    for package, name in printed:
        klass = _exported(package, name)
        table = describe(klass)
        spellings = [f"{package}.{name}", f"acausal.library.{package}.{name}", f"library.{package}.{name}",
                     _msl(klass)]
        if len(by_name[name]) == 1:
            spellings.append(name)  # the name as the package listing prints it
        for spelling in spellings:
            status = main_show([spelling])
            captured = capsys.readouterr()
            if status != 0 or captured.out != table:
                failures.append(f"acausal show {spelling}: exit {status} {captured.err.strip()}")
    assert not failures, f"{len(failures)} names not found:\n" + "\n".join(failures[:20])


def test_a_class_name_two_packages_share_names_both_and_each_is_found(printed, capsys):
    packages_of: dict[str, list[str]] = {}
    for package, name in printed:
        if _exported(package, name) not in [_exported(p, name) for p in packages_of.get(name, [])]:
            packages_of.setdefault(name, []).append(package)
    shared = {name: packages for name, packages in packages_of.items() if len(packages) > 1}
    assert "Flange_a" in shared and "Damper" in shared
    for name, packages in shared.items():
        assert main_show([name]) == 2
        err = capsys.readouterr().err
        for package in packages:
            assert f"{package}.{name}" in err, err
            assert find_object(f"{package}.{name}") is _exported(package, name)


# --------------------------------------------------------------------------
# The names of the issue


@pytest.mark.parametrize("name, package, klass", [
    ("rotational.Clutch", "rotational", "Clutch"),
    ("blocks.CombiTable1Ds", "blocks", "CombiTable1Ds"),
    ("acausal.library.rotational.Clutch", "rotational", "Clutch"),
    ("library.rotational.Clutch", "rotational", "Clutch"),
    ("Clutch", "rotational", "Clutch"),
    ("Modelica.Mechanics.Rotational.Components.Clutch", "rotational", "Clutch"),
    ("Modelica.Blocks.Sources.CombiTimeTable", "blocks", "CombiTimeTable"),
    ("Modelica.Thermal.HeatTransfer.Components.HeatCapacitor", "thermal", "HeatCapacitor"),
    ("Modelica.Thermal.HeatTransfer.Celsius.FixedTemperature", "thermal", "CelsiusFixedTemperature"),
    ("Modelica.Mechanics.Translational.Components.Mass", "translational", "Mass"),
    ("Modelica.Mechanics.Rotational.Interfaces.Flange_a", "rotational", "Flange_a"),
])
def test_show_the_names_of_the_issue(name, package, klass, capsys):
    assert main_show([name]) == 0, capsys.readouterr().err
    assert capsys.readouterr().out == describe(_exported(package, klass))


@pytest.mark.parametrize("name, package", [
    ("blocks", "blocks"), ("thermal", "thermal"), ("library.thermal", "thermal"),
    ("acausal.library.thermal", "thermal"), ("Modelica.Thermal.HeatTransfer", "thermal"),
    ("Modelica.Blocks", "blocks"),
])
def test_list_the_packages_of_the_issue(name, package):
    assert _list(name) == _list(f"acausal.library.{package}")


def test_list_an_msl_package_lists_what_acausal_has_of_it():
    sources = _list("Modelica.Blocks.Sources")
    assert "CombiTimeTable" in _section(sources, "Components")
    assert "Gain" not in sources  # Modelica.Blocks.Math.Gain
    mechanics = _section(_list("Modelica.Mechanics"), "Packages")
    assert mechanics == ["rotational", "translational"]
    everything = _section(_list("Modelica"), "Packages")
    assert sorted(everything) == ["blocks", "electrical", "rotational", "thermal", "translational"]


# --------------------------------------------------------------------------
# Did you mean: real packages and classes only


def _suggestions(err: str) -> list[str]:
    match = re.search(r"did you mean (.*)\?", err)
    return [name.strip() for name in match.group(1).split(",")] if match else []


@pytest.mark.parametrize("command, name, expected", [
    (main_list, "thermall", "thermal"),
    (main_list, "blokcs", "blocks"),
    (main_show, "rotational.Clutchh", "rotational.Clutch"),
    (main_show, "rotationl.Clutch", "rotational"),
    (main_show, "blocks.Clutch", "rotational.Clutch"),  # the right class in the wrong package
    (main_show, "Cluth", "Clutch"),
    (main_show, "library.rotational.Clutchh", "library.rotational.Clutch"),
    (main_show, "acausal.library.blocks.CombiTable1D", "acausal.library.blocks.CombiTable1Ds"),
    (main_show, "Modelica.Mechanics.Rotational.Components.Clutchh",
     "Modelica.Mechanics.Rotational.Components.Clutch"),
    (main_show, "Modelica.Mechanics.Rotational.Sources.Clutch",  # the wrong MSL package
     "Modelica.Mechanics.Rotational.Components.Clutch"),
    (main_list, "Modelica.Mechanics.Rotatonal", "Modelica.Mechanics.Rotational"),
])
def test_a_wrong_name_suggests_the_close_real_name(command, name, expected, capsys):
    assert command([name]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert expected in _suggestions(captured.err), captured.err


@pytest.mark.parametrize("name", [
    "thermall", "terminl", "rotational.Potentia", "rotational.Clutchh", "blocks.Clutch", "Cluth", "Flange",
    "library.rotationl.Clutch", "acausal.library.thermal.HeatCapacito", "acausal.terminl", "componets",
    "components.rotational.Flang", "Modelica.Blocks.Sources.Stepp", "Modelica.Mechanics.Rotational.Sensors.Clutch",
])
def test_every_suggestion_is_a_package_or_class_that_is_found(name, capsys):
    for command in (main_list, main_show):
        assert command([name]) == 2
        err = capsys.readouterr().err
        for suggestion in _suggestions(err):
            found = find_object(suggestion)
            assert isinstance(found, type(sys)) or (
                isinstance(found, type) and issubclass(found, (Component, Connector))), (
                f"{name!r}: suggested {suggestion!r}, which is {found!r}: {err}")


def test_no_suggestion_is_an_attribute_of_the_acausal_package(capsys):
    # what the did-you-mean drew from before: dir(acausal), acausal.hybrid.terminal, acausal.Potential
    assert main_list(["thermall"]) == 2
    assert "terminal" not in capsys.readouterr().err
    assert main_show(["rotational.Potentia"]) == 2
    # a real class may be suggested (electrical.PotentialSensor), acausal.Potential may not
    assert re.search(r"(?<![\w.])(acausal\.)?Potential\b", capsys.readouterr().err) is None
    assert main_show(["acausal.terminl"]) == 2
    assert "terminal" not in capsys.readouterr().err


def test_a_name_of_a_module_of_ones_own_is_still_imported(tmp_path, monkeypatch, capsys):
    (tmp_path / "my_valves.py").write_text(
        "from acausal import Component, Parameter\n\n"
        "class Valve(Component):\n"
        "    '''A valve.'''\n"
        "    opening = Parameter(0.5, unit='1', description='How open')\n", encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    assert main_show(["my_valves.Valve"]) == 0
    assert "opening" in capsys.readouterr().out
    assert main_show(["my_valves.Valv"]) == 2
    assert "my_valves.Valve" in _suggestions(capsys.readouterr().err)
    with pytest.raises(NameNotFound):
        find_object("my_valves.Valve.opening.nothing")


# --------------------------------------------------------------------------
# The command itself, in a folder of the user's


def test_the_command_round_trips_in_a_folder_outside_the_checkout(tmp_path):
    def acausal(*argv: str) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "acausal", *argv], cwd=tmp_path, capture_output=True,
                              text=True, timeout=300)

    packages = acausal("list")
    assert packages.returncode == 0, packages.stderr
    assert "thermal" in _section(packages.stdout, "Packages")
    thermal = acausal("list", "thermal")
    assert thermal.returncode == 0, thermal.stderr
    assert "HeatCapacitor" in _section(thermal.stdout, "Components")
    for name in ("HeatCapacitor", "thermal.HeatCapacitor", "Modelica.Thermal.HeatTransfer.Components.HeatCapacitor"):
        shown = acausal("show", name)
        assert shown.returncode == 0, shown.stderr
        assert shown.stdout == describe(_exported("thermal", "HeatCapacitor"))
