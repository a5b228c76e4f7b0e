"""Display units: results shown in rpm, degC, deg or bar while their values stay in SI units,
and summaries that print values below the run's tolerance as 0.

Conversions are checked against closed forms (300 K is 26.85 degC, 2 pi rad/s is
60 rpm); runs of models whose solution is known (a speed 2 pi t, a cooling
exponential) are shown in other units through every door: ``in_unit``,
``to_pandas``, ``plot``, ``summary`` and ``acausal simulate --display-unit``.
"""

from __future__ import annotations

import csv
import math
import textwrap
from types import SimpleNamespace

import numpy as np
import pytest

from acausal import Eq, Model, Parameter, Variable, der, simulate
from acausal.runtime.result import ColumnInfo, SimulationResult, convert_unit, describe_columns
from acausal.tools.cli import main

# ---------------------------------------------------------------------------
# convert_unit: closed forms
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("values, unit, to, expected", [
    ([0.0, 273.15, 300.0, 373.15], "K", "degC", [-273.15, 0.0, 26.85, 100.0]),
    ([-40.0, 0.0, 100.0], "degC", "K", [233.15, 273.15, 373.15]),
    ([-40.0, 32.0, 212.0], "degF", "degC", [-40.0, 0.0, 100.0]),
    ([300.0], "K", "°C", [26.85]),
    ([2 * math.pi, 100.0], "rad/s", "rpm", [60.0, 100.0 * 60.0 / (2 * math.pi)]),
    ([3000.0], "rpm", "rad/s", [3000.0 * 2 * math.pi / 60.0]),
    ([math.pi, -math.pi / 2], "rad", "deg", [180.0, -90.0]),
    ([1.0], "rad/s", "deg/s", [180.0 / math.pi]),
    ([1e5, 2.5e6], "Pa", "bar", [1.0, 25.0]),
    ([36.0], "km/h", "m/s", [10.0]),
    ([1.0], "K/s", "degC/s", [1.0]),  # a rate: no offset
    ([3.0], "N.m", "N.m", [3.0]),
])
def test_conversions_match_the_closed_forms(values, unit, to, expected):
    np.testing.assert_allclose(convert_unit(values, unit, to), expected, rtol=1e-12, atol=1e-12)


def test_a_round_trip_through_an_affine_unit_is_the_identity():
    kelvin = np.array([0.0, 250.0, 293.15, 1000.0])
    back = convert_unit(convert_unit(kelvin, "K", "degF"), "°F", "K")
    np.testing.assert_allclose(back, kelvin, rtol=0, atol=1e-12)


@pytest.mark.parametrize("unit, to, words", [
    ("rad/s", "bar", ["'rad/s'", "'bar'", "rad/s", "Pa"]),
    ("K", "m", ["'K'", "'m'"]),
    ("rad/s", "Hz", ["'rad/s'", "'Hz'", "1/s"]),  # the radian counts: rpm, not Hz, is a speed
    ("rad", "1", ["'rad'", "'1'"]),
    ("rad/s", "furlong", ["'furlong'", "unknown unit symbol"]),
    ("", "rpm", ["no unit", "'rpm'"]),
])
def test_incompatible_or_unknown_units_are_errors_naming_both(unit, to, words):
    with pytest.raises(ValueError) as info:
        convert_unit([1.0], unit, to, name="J1.w")
    message = str(info.value)
    assert "J1.w" in message
    for word in words:
        assert word in message, (word, message)


def test_the_values_given_are_left_as_they_were():
    values = np.array([300.0, 310.0])
    convert_unit(values, "K", "degC")
    assert values.tolist() == [300.0, 310.0]


# ---------------------------------------------------------------------------
# Per call: in_unit, to_pandas, plot on a run with a known solution
# ---------------------------------------------------------------------------


class Spin(Model):
    """w = 2 pi t (rad/s), so 60 t rpm; phi = pi t^2 (rad), so 180 t^2 deg."""

    phi = Variable(start=0.0, fixed=True, unit="rad")
    w = Variable(start=0.0, fixed=True, unit="rad/s")

    def equations(self):
        return [Eq(der(self.phi), self.w), Eq(der(self.w), 2 * math.pi)]


class Cooling(Model):
    """T from 100 degC towards 20 degC with time constant 1 s: T = 20 + 80 exp(-t) degC."""

    T_amb = Parameter(293.15, unit="K")
    T = Variable(start=373.15, fixed=True, unit="K")

    def equations(self):
        return [Eq(der(self.T), -(self.T - self.T_amb))]


@pytest.fixture(scope="module")
def spin():
    result = simulate(Spin(), stop_time=1.0, interval=0.05, rtol=1e-9)
    assert result.status == 0, result.message
    return result


@pytest.fixture(scope="module")
def cooling():
    result = simulate(Cooling(), stop_time=2.0, interval=0.1, rtol=1e-9)
    assert result.status == 0, result.message
    return result


def test_in_unit_gives_rpm_and_degrees_of_the_known_motion(spin):
    t = spin.time
    np.testing.assert_allclose(spin.in_unit("w", "rpm"), 60.0 * t, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(spin.in_unit("phi", "deg"), 180.0 * t ** 2, rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(spin.in_unit("time", "min"), t / 60.0)
    np.testing.assert_allclose(spin["w"], 2 * math.pi * t, rtol=1e-7, atol=1e-9)  # still SI
    assert spin.in_unit("w") is spin["w"]  # no display unit declared: the values as they are


def test_to_pandas_in_display_units_with_a_dict(cooling):
    frame = cooling.to_pandas(display_units={"T": "degC", "T_amb": "degC"}, events="last")
    t = frame.index.to_numpy()
    np.testing.assert_allclose(frame["T"].to_numpy(), 20.0 + 80.0 * np.exp(-t), rtol=1e-7)
    np.testing.assert_allclose(frame["T_amb"].to_numpy(), 20.0, rtol=1e-12)
    assert frame.attrs["units"]["T"] == "degC" and frame.attrs["units"]["time"] == "s"
    plain = cooling.to_pandas(events="last")  # the default stays in the declared units
    assert plain.attrs["units"]["T"] == "K"
    np.testing.assert_allclose(plain["T"].to_numpy(), 293.15 + 80.0 * np.exp(-t), rtol=1e-9)
    with pytest.raises(ValueError, match=r"T cannot be shown in 'rpm': 'K' measures K"):
        cooling.to_pandas(display_units={"T": "rpm"})
    with pytest.raises(KeyError, match="did you mean T"):
        cooling.to_pandas(display_units={"TT": "degC"})


def test_plot_draws_in_the_units_asked_for(spin):
    import matplotlib

    matplotlib.use("Agg")
    import acausal.tools.plotting  # noqa: F401 - registers the plotter

    figure = spin.plot(["w", "phi"], units={"w": "rpm", "phi": "deg"})
    (w_axes, phi_axes) = figure.axes
    assert w_axes.get_ylabel() == "w [rpm]" and phi_axes.get_ylabel() == "phi [deg]"
    x, y = w_axes.lines[0].get_data()
    np.testing.assert_allclose(y, 60.0 * np.asarray(x), rtol=1e-7, atol=1e-9)
    assert spin.plot(["w"]).axes[0].get_ylabel() == "w [rad/s]"
    with pytest.raises(ValueError, match="'bar'"):
        spin.plot(["w"], units={"w": "bar"})


# ---------------------------------------------------------------------------
# Declared display units
# ---------------------------------------------------------------------------


def test_the_declaration_takes_a_display_unit_and_a_modifier_may_set_it():
    declared = Variable(unit="rad/s", display_unit="rpm")
    assert declared.display_unit == "rpm" and "display_unit='rpm'" in repr(declared)
    assert Parameter(1e5, unit="Pa", display_unit="bar").display_unit == "bar"
    Cooling(T=dict(display_unit="degC"))  # an attribute modifiers may set (no ModifierError)


def test_columns_read_the_display_unit_and_nominal_of_the_flat_model():
    """What describe_columns reads from a flat variable and parameter (any object with the fields)."""
    variable = SimpleNamespace(name="T", kind="continuous", is_discrete=False, unit="K", description="",
                               labels=(), display_unit="degC", nominal=300.0)
    parameter = SimpleNamespace(name="p", unit="Pa", description="", display_unit="bar")
    flat = SimpleNamespace(variables=(variable,), parameters=(parameter,))
    info = describe_columns(flat, ["T", "p", "der(T)"])
    assert info["T"].display_unit == "degC" and info["T"].nominal == 300.0
    assert info["p"].display_unit == "bar" and info["p"].kind == "parameter"
    assert info["der(T)"].unit == "K/s" and info["der(T)"].display_unit == ""
    assert info["T"].line().endswith("(display unit degC)")


def declared_result() -> SimulationResult:
    t = np.array([0.0, 1.0])
    columns = {"T": np.array([373.15, 300.0]), "w": np.array([0.0, 2 * math.pi]),
               "p": np.array([2e5, 2e5])}
    info = {"T": ColumnInfo("T", "K", display_unit="degC"), "w": ColumnInfo("w", "rad/s", display_unit="rpm"),
            "p": ColumnInfo("p", "Pa", kind="parameter", display_unit="bar")}
    return SimulationResult(t, columns, model_name="Declared", column_info=info, stats={"rtol": 1e-6})


def test_declared_display_units_are_used_by_default_where_values_are_shown():
    result = declared_result()
    assert result.display_unit("T") == "degC" and result.in_unit("T").tolist() == pytest.approx([100.0, 26.85])
    frame = result.to_pandas(display_units=True)
    assert frame["w"].tolist() == pytest.approx([0.0, 60.0]) and frame["p"].tolist() == pytest.approx([2.0, 2.0])
    assert frame.attrs["units"] == {"time": "s", "T": "degC", "w": "rpm", "p": "bar"}
    # a dict overrides one column; the others keep their declared display unit
    frame = result.to_pandas(display_units={"T": "K"})
    assert frame["T"].tolist() == [373.15, 300.0] and frame["w"].tolist() == pytest.approx([0.0, 60.0])
    assert result.to_pandas().attrs["units"]["T"] == "K"  # the default: declared units
    summary = result.summary(signals=["T", "w", "p"])
    assert "T  26.85 degC" in summary and "w  60 rpm" in summary and "p  2 bar" in summary
    assert "<td>degC</td>" in result._repr_html_() and "<td>26.85</td>" in result._repr_html_()


def test_a_declared_display_unit_that_cannot_be_used_warns_and_shows_the_unit():
    t = np.array([0.0, 1.0])
    result = SimulationResult(t, {"w": np.array([1.0, 2.0])}, model_name="Typo",
                              column_info={"w": ColumnInfo("w", "rad/s", display_unit="rmp")})
    with pytest.warns(UserWarning, match=r"display unit of w is not used.*'rmp'"):
        assert result.display_unit("w") == "rad/s"
    with pytest.warns(UserWarning):
        assert "w  2 rad/s" in result.summary(signals=["w"])


class DeclaredCooling(Model):
    T_amb = Parameter(293.15, unit="K", display_unit="degC")
    T = Variable(start=373.15, fixed=True, unit="K", display_unit="degC")

    def equations(self):
        return [Eq(der(self.T), -(self.T - self.T_amb))]


def test_a_declared_display_unit_reaches_the_result_of_a_run():
    result = simulate(DeclaredCooling(), stop_time=1.0, interval=0.5, rtol=1e-9)
    assert result.info("T").display_unit == "degC" and result.info("T_amb").display_unit == "degC"
    assert result.in_unit("T")[-1] == pytest.approx(20.0 + 80.0 * math.exp(-1.0), rel=1e-7)
    modified = simulate(Cooling(T=dict(display_unit="degF")), stop_time=1.0, interval=0.5)
    assert modified.info("T").display_unit == "degF"


# ---------------------------------------------------------------------------
# Values below the tolerance print as 0 (in summaries only)
# ---------------------------------------------------------------------------


def stuck(value: float, *, nominal: float = 1.0, stats=None, kind: str = "continuous") -> SimulationResult:
    t = np.array([0.0, 1.0])
    return SimulationResult(t, {"w": np.array([1.0, value])}, model_name="Stuck",
                            column_info={"w": ColumnInfo("w", "rad/s", kind=kind, nominal=nominal)},
                            stats={"rtol": 1e-6} if stats is None else stats)


def final_line(result: SimulationResult, **options) -> str:
    return next(line for line in result.summary(signals=["w"], **options).splitlines()
                if line.strip().startswith("w "))


def test_a_stuck_speed_prints_as_zero_and_keeps_its_value():
    result = stuck(-1.000011e-10)
    assert final_line(result).split() == ["w", "0", "rad/s"]
    assert "(0: smaller than the run's absolute tolerance" in result.summary(signals=["w"])
    assert result["w"][-1] == -1.000011e-10  # the arrays are never snapped
    assert final_line(result, units={"w": "rpm"}).split() == ["w", "0", "rpm"]
    assert result.resolution("w") == pytest.approx(1e-6)


def test_the_threshold_follows_the_tolerance_and_the_nominal_value():
    assert final_line(stuck(5e-6)).split() == ["w", "5e-06", "rad/s"]  # above rtol * nominal
    # a variable whose nominal is 1e-12: its tolerance is 1e-18, so 1e-10 is a real value
    assert final_line(stuck(-1.000011e-10, nominal=1e-12)).split() == ["w", "-1.00001e-10", "rad/s"]
    assert final_line(stuck(5e-6, nominal=100.0)).split() == ["w", "0", "rad/s"]  # below 1e-4
    # a run given one atol uses it for every state
    assert final_line(stuck(-1e-10, stats={"rtol": 1e-6, "atol": 1e-12})).split()[1] == "-1e-10"
    assert final_line(stuck(-1e-10, stats={"rtol": 1e-3, "atol": 1e-9})).split()[1] == "0"
    # a result that does not know its tolerance (read from a file), or a parameter: as they are
    assert final_line(stuck(-1e-10, stats={})).split()[1] == "-1e-10"
    assert final_line(stuck(-1e-10, kind="parameter")).split()[1] == "-1e-10"
    assert "(0: smaller" not in stuck(5e-6).summary(signals=["w"])


def test_a_real_decay_below_the_tolerance_prints_as_zero():
    class Decay(Model):
        w = Variable(start=1.0, fixed=True, unit="rad/s")

        def equations(self):
            return [Eq(der(self.w), -50.0 * self.w)]

    result = simulate(Decay(), stop_time=1.0, rtol=1e-6)  # exp(-50) = 2e-22: below 1e-6
    line = next(l for l in result.summary().splitlines() if l.strip().startswith("w "))
    assert line.split() == ["w", "0", "rad/s"]
    assert abs(result["w"][-1]) < 1e-6


# ---------------------------------------------------------------------------
# The command line
# ---------------------------------------------------------------------------

SPIN_FILE = """
    import math

    from acausal import Eq, Experiment, Model, Variable, der


    class Spin(Model):
        experiment = Experiment(stop_time=1.0, interval=0.1)
        phi = Variable(start=0.0, fixed=True, unit="rad")
        w = Variable(start=0.0, fixed=True, unit="rad/s")

        def equations(self):
            return [Eq(der(self.phi), self.w), Eq(der(self.w), 2 * math.pi)]
    """


@pytest.fixture
def spin_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "spin.py"
    path.write_text(textwrap.dedent(SPIN_FILE))
    return path


def test_simulate_prints_the_summary_in_the_display_unit_and_writes_si(spin_file, capsys):
    status = main(["simulate", str(spin_file), "--out", "spin.csv", "--display-unit", "w=rpm",
                   "--display-unit", "phi=deg"])
    out = capsys.readouterr().out
    assert status == 0
    lines = {line.split()[0]: line.split()[1:] for line in out.splitlines() if line.startswith("    ")}
    assert lines["w"] == ["60", "rpm"] and lines["phi"] == ["180", "deg"]
    with open("spin.csv", newline="") as handle:
        rows = list(csv.reader(handle))
    last = dict(zip(rows[0], map(float, rows[-1])))
    assert last["w"] == pytest.approx(2 * math.pi, rel=1e-6)  # the CSV stays in rad/s


@pytest.mark.parametrize("option, words", [
    ("w=bar", ["--display-unit w=bar", "'rad/s'", "'bar'"]),
    ("ww=rpm", ["ww", "did you mean w"]),
    ("w", ["NAME=UNIT"]),
    ("w=furlong", ["'furlong'"]),
])
def test_simulate_refuses_a_display_unit_it_cannot_use_before_running(spin_file, capsys, option, words):
    assert main(["simulate", str(spin_file), "--out", "spin.csv", "--display-unit", option]) == 2
    err = capsys.readouterr().err
    for word in words:
        assert word in err, (word, err)
    assert not (spin_file.parent / "spin.csv").exists()  # refused before the run
