"""The result for analysis: metadata, typed columns, pandas, display, plots, CSV and MAT files.

Two small models with closed forms:

* ``Spin``: an inertia (J = 2 kg.m2) driven by a constant torque of 3 N.m
  from rest, so ``w = 1.5 t`` and ``phi = 0.75 t**2``;
* ``Breakaway``: an inertia (J = 2) held by a bearing friction of 1 N.m
  (stuck) until a torque step of 3 N.m at t = 0.5 breaks it away: a time
  event at 0.5, then the state event of the slip starting right after it,
  and ``w = (3 - 1)/2 (t - 0.5)`` once sliding forward.
"""

from __future__ import annotations

import csv

import matplotlib
import numpy as np
import pytest
import scipy.io

from acausal import Experiment, Model, SimulationResult, simulate
from acausal.library.blocks import Step
from acausal.library.rotational import BearingFriction, ConstantTorque, Inertia, Torque
from acausal.runtime import result as result_module
from acausal.runtime.result import ColumnInfo, read_csv, read_mat

matplotlib.use("Agg")

REST = dict(start=0, fixed=True)
STEP_TIME = 0.5
MODE_LABELS = ((-1, "Backward"), (0, "Stuck"), (1, "Forward"), (2, "Free"), (3, "Unknown"))


class Spin(Model):
    experiment = Experiment(stop_time=2.0, interval=0.25)

    def build(self):
        self.source = ConstantTorque(tau_constant=3.0)
        self.inertia = Inertia(J=2.0, phi=REST, w=REST)
        self.connect(self.source.flange, self.inertia.flange_a)


class Breakaway(Model):
    experiment = Experiment(stop_time=1.0, interval=0.1)

    def build(self):
        self.step = Step(height=3.0, startTime=STEP_TIME)
        self.torque = Torque()
        self.inertia = Inertia(J=2.0, phi=REST, w=REST)
        self.bearing = BearingFriction(tau_pos=[[0.0, 1.0]])
        self.connect(self.step.y, self.torque.tau)
        self.connect(self.torque.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.bearing.flange_a)


@pytest.fixture(scope="module")
def spin() -> SimulationResult:
    return simulate(Spin(), rtol=1e-10).raise_for_status()


@pytest.fixture(scope="module")
def breakaway() -> SimulationResult:
    return simulate(Breakaway(), rtol=1e-10).raise_for_status()


# -- metadata -------------------------------------------------------------------------------

def test_units_descriptions_and_kinds_come_from_the_declarations(breakaway):
    assert breakaway.unit("inertia.w") == "rad/s"
    assert breakaway.unit("inertia.phi") == "rad"
    assert breakaway.unit("bearing.tau") == "N.m"
    assert breakaway.unit("inertia.J") == "kg.m2"
    assert breakaway.unit("time") == "s"
    assert breakaway.unit("der(inertia.w)") == "rad/s2"
    assert breakaway.unit("bearing.mode") == ""
    info = breakaway.info
    assert info("inertia.w").kind == "continuous"
    assert info("inertia.J").kind == "parameter"
    assert info("bearing.locked").kind == "boolean"
    assert info("bearing.mode").kind == "integer"
    assert info("inertia.w").description == Inertia.declarations()["w"].description
    line = breakaway.describe("inertia.J")
    assert line == f"inertia.J [kg.m2] parameter: {Inertia.declarations()['J'].description}"


def test_mode_labels_are_the_component_class_constants(breakaway):
    # BearingFriction's class names each value of its mode, min .. max
    assert breakaway.info("bearing.mode").labels == MODE_LABELS
    assert "0 Stuck" in breakaway.describe("bearing.mode")
    # an Integer without named values has none
    assert all(not breakaway.info(n).labels for n in breakaway.names if n != "bearing.mode")


def test_a_translation_gives_units_and_descriptions_too():
    """The flat model carries them: a result of a translation knows as much as one of a model."""
    from acausal import translate
    from acausal.library.rotational import Inertia

    result = simulate(translate(Spin()))
    assert result.unit("inertia.w") == "rad/s"
    assert result.info("inertia.w").description == Inertia.w.description
    assert result.info("inertia.J").description == Inertia.J.description != ""


# -- discrete columns and unknown names ----------------------------------------------------

def test_discrete_columns_come_back_as_bool_and_int(breakaway):
    assert breakaway["bearing.locked"].dtype == np.bool_
    assert breakaway["bearing.mode"].dtype == np.int64
    assert breakaway["inertia.w"].dtype == np.float64
    # the stored columns stay float (compare and the CSV writer read those)
    assert breakaway.columns["bearing.mode"].dtype == np.float64
    locked = breakaway["bearing.locked"]
    before = breakaway.time < STEP_TIME
    assert locked[before].all() and not locked[breakaway.time > STEP_TIME + 1e-6].any()
    assert set(breakaway["bearing.mode"][before]) == {0}
    assert breakaway["bearing.mode"][-1] == 1


def test_unknown_name_suggests_the_close_ones(breakaway):
    with pytest.raises(KeyError, match=r"did you mean inertia\.w"):
        breakaway["inertia.ww"]
    with pytest.raises(KeyError, match=r"did you mean .*inertia\.w"):
        breakaway["w"]  # the name without its component path
    with pytest.raises(KeyError, match="not a variable of Breakaway"):
        breakaway.unit("nope")


# -- pandas --------------------------------------------------------------------------------

def test_to_pandas_matches_the_closed_form(spin):
    df = spin.to_pandas()
    assert df.index.name == "time"
    t = df.index.to_numpy()
    np.testing.assert_allclose(t, np.arange(0, 2.0001, 0.25))
    np.testing.assert_allclose(df["inertia.w"], 1.5 * t, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(df["inertia.phi"], 0.75 * t ** 2, rtol=1e-8, atol=1e-12)
    assert df.attrs["units"]["inertia.w"] == "rad/s"
    assert df.attrs["units"]["time"] == "s"
    assert df.attrs["kinds"]["inertia.J"] == "parameter"
    assert df.attrs["model"] == "Spin"
    # the initial event is the only one: only the first row is an event row
    assert df["event"].tolist() == [True] + [False] * (len(t) - 1)


def test_to_pandas_flags_the_event_rows_and_keeps_one_row_per_time_if_asked(breakaway):
    df = breakaway.to_pandas(["inertia.w", "bearing.mode", "bearing.locked"])
    assert df["bearing.locked"].dtype == bool and df["bearing.mode"].dtype == np.int64
    at_event = np.isclose(df.index, STEP_TIME, rtol=0, atol=1e-6)
    # the time event at 0.5 and the slip right after it: left and right limit rows each
    assert at_event.sum() == 4 and not df.index.is_unique
    assert df["event"][at_event].all()
    assert not df["event"][~at_event & (df.index > 0)].any()
    for how, mode in (("last", 1), ("first", 0)):
        one = breakaway.to_pandas(["inertia.w", "bearing.mode"], events=how)
        assert one.index.is_unique
        assert one["bearing.mode"][np.isclose(one.index, STEP_TIME, rtol=0, atol=1e-6)].tolist()[-1] == mode
    last = breakaway.to_pandas(["inertia.w"], events="last", event_column=None)
    assert list(last.columns) == ["inertia.w"]
    sliding = last.index > STEP_TIME + 0.01
    np.testing.assert_allclose(last["inertia.w"][sliding], (3 - 1) / 2 * (last.index[sliding] - STEP_TIME),
                               rtol=1e-6)
    with pytest.raises(ValueError, match="events="):
        breakaway.to_pandas(events="middle")


# -- display -------------------------------------------------------------------------------

def test_repr_is_one_short_line(breakaway):
    text = repr(breakaway)
    assert len(text) < 300 and "\n" not in text
    assert "Breakaway" in text and "ok" in text
    assert f"{len(breakaway.events)} events" in text and f"{len(breakaway.time)} points" in text


def test_html_repr_is_a_small_table_with_units(breakaway):
    page = breakaway._repr_html_()
    assert page.count("<table") == 2 and "rad/s" in page and "The simulation reached the stop time." in page
    assert len(page) < 5000


# -- plots ---------------------------------------------------------------------------------

def test_plot_has_units_event_lines_and_mode_names(breakaway):
    import acausal.tools.plotting as plotting

    figure = plotting.plot(breakaway, ["inertia.w", "bearing.mode", ["bearing.locked", "bearing.startForward"]])
    axes = figure.axes
    assert len(axes) == 3
    assert axes[0].get_ylabel() == "inertia.w [rad/s]"
    assert axes[-1].get_xlabel() == "time [s]"
    ticks = [label.get_text() for label in axes[1].get_yticklabels()]
    assert ticks == [f"{name} ({value})" for value, name in MODE_LABELS]
    # dotted event lines at the event instants (the initial one excepted), on every panel
    vertical = {line.get_xdata()[0] for line in axes[0].get_lines() if line.get_linestyle() == ":"}
    assert vertical == {e.time for e in breakaway.events if e.kind != "initial"}
    assert min(vertical) == STEP_TIME
    assert axes[2].get_legend() is not None
    # the method goes through the plotter the tools module registered
    assert len(breakaway.plot("inertia.w").axes) == 1


def test_plot_method_works_after_import_acausal_alone(tmp_path):
    """The façade registers the plotter: no tools import needed, and matplotlib loads only on plot."""
    import subprocess
    import sys

    code = ("import sys, acausal\n"
            "from acausal.library.rotational import ConstantTorque, Inertia\n"
            "class Spin(acausal.Model):\n"
            "    def build(self):\n"
            "        self.src = ConstantTorque(tau_constant=1.0)\n"
            "        self.j = Inertia(J=1.0, phi=dict(fixed=True), w=dict(fixed=True))\n"
            "        self.connect(self.src.flange, self.j.flange_a)\n"
            "r = acausal.simulate(Spin(), stop_time=1.0)\n"
            "assert 'matplotlib' not in sys.modules\n"
            "import matplotlib; matplotlib.use('Agg')\n"
            "print(len(r.plot('j.w').axes))\n")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300,
                         cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    assert run.stdout.split()[-1] == "1"


def test_plot_method_without_a_plotter_says_what_to_import(breakaway, monkeypatch):
    monkeypatch.setattr(result_module, "_PLOTTER", [])
    with pytest.raises(RuntimeError, match="import acausal.tools.plotting"):
        breakaway.plot("inertia.w")


# -- CSV -----------------------------------------------------------------------------------

def test_csv_round_trip(breakaway, tmp_path):
    path = breakaway.to_csv(tmp_path / "plain.csv")
    with path.open() as handle:
        header = next(csv.reader(handle))
    assert header == ["time", *breakaway.names]  # the layout of the reference files, unchanged
    back = read_csv(path)
    np.testing.assert_array_equal(back.time, breakaway.time)
    assert back.names == breakaway.names
    for name in breakaway.names:
        np.testing.assert_array_equal(back.columns[name], breakaway.columns[name])
    assert back.info("inertia.w") == ColumnInfo("inertia.w")  # no metadata written


def test_csv_with_metadata_round_trip_and_stays_readable_as_a_reference(breakaway, tmp_path):
    from acausal.tools.compare import _read_csv

    path = breakaway.to_csv(tmp_path / "meta.csv", metadata=True)
    back = SimulationResult.from_csv(path)
    assert back.model_name == "Breakaway"
    for name in breakaway.names:
        np.testing.assert_array_equal(back.columns[name], breakaway.columns[name])
        original = breakaway.info(name)
        assert (back.unit(name), back.info(name).kind, back.info(name).description) == (
            original.unit, original.kind, original.description)
    assert back["bearing.mode"].dtype == np.int64 and back["bearing.locked"].dtype == np.bool_
    # the event instants are found again by their repeated times
    np.testing.assert_array_equal(back.event_rows[1:], breakaway.event_rows[1:])
    # the reference reader skips the metadata rows as comments
    time, signals = _read_csv(path)
    np.testing.assert_array_equal(time, breakaway.time)
    np.testing.assert_array_equal(signals["inertia.w"], breakaway.columns["inertia.w"])


# -- MAT (dsres.mat layout) ----------------------------------------------------------------

def _strings(chars: np.ndarray) -> list[str]:
    """Columns of a char matrix as strings (binTrans: one name per column)."""
    return ["".join(column).rstrip() for column in chars.T]


def test_mat_file_has_the_dymola_layout(breakaway, tmp_path):
    path = breakaway.to_mat(tmp_path / "dsres.mat")
    mat = scipy.io.loadmat(path, chars_as_strings=False)
    assert ["".join(row).rstrip() for row in mat["Aclass"]] == ["Atrajectory", "1.1", "", "binTrans"]
    names = _strings(mat["name"])
    parameters = [n for n in breakaway.names if breakaway.info(n).kind == "parameter"]
    others = [n for n in breakaway.names if n not in parameters]
    assert names == ["time", *parameters, *others]
    assert mat["name"].shape == (max(map(len, names)), len(names))
    descriptions = _strings(mat["description"])
    assert descriptions[names.index("inertia.w")] == (
        f"{breakaway.info('inertia.w').description} [rad/s]")
    info = mat["dataInfo"]
    assert info.shape == (4, len(names)) and info.dtype == np.int32
    assert info[:, 0].tolist() == [0, 1, 0, -1]  # time: the abscissa
    data_1, data_2 = mat["data_1"], mat["data_2"]
    assert data_1.shape == (1 + len(parameters), 2) and data_2.shape == (1 + len(others), len(breakaway.time))
    np.testing.assert_array_equal(data_1[0], [breakaway.time[0], breakaway.time[-1]])
    np.testing.assert_array_equal(data_2[0], breakaway.time)
    for k, name in enumerate(names[1:], start=1):
        data_set, column = info[0, k], info[1, k]
        if name in parameters:
            assert data_set == 1 and info[3, k] == 0
            assert data_1[column - 1].tolist() == [breakaway.columns[name][0]] * 2
        else:
            assert data_set == 2 and info[3, k] == -1
            np.testing.assert_array_equal(data_2[column - 1], breakaway.columns[name])


def test_mat_round_trip(breakaway, tmp_path):
    back = read_mat(breakaway.to_mat(tmp_path / "r.mat"))
    np.testing.assert_array_equal(back.time, breakaway.time)
    assert set(back.names) == set(breakaway.names)
    for name in breakaway.names:
        np.testing.assert_array_equal(back.columns[name], breakaway.columns[name])
        assert back.unit(name) == breakaway.unit(name)
        assert back.info(name).description == breakaway.info(name).description
    assert back.info("inertia.J").kind == "parameter"
    assert SimulationResult.from_mat(tmp_path / "r.mat").names == back.names


def test_mat_round_trip_of_coupled_clutches(tmp_path):
    from examples.coupled_clutches import CoupledClutches

    result = simulate(CoupledClutches()).raise_for_status()
    back = read_mat(result.to_mat(tmp_path / "CoupledClutches.mat"))
    assert set(back.names) == set(result.names)
    np.testing.assert_array_equal(back.time, result.time)
    for name in result.names:
        np.testing.assert_array_equal(back.columns[name], result.columns[name])
        assert back.unit(name) == result.unit(name)


def test_mat_reader_reads_the_normal_orientation_and_negated_aliases(tmp_path):
    """A binNormal file (one variable per row of the matrices), with an alias stored
    negated (dataInfo column -2), as Dymola writes some."""
    path = tmp_path / "normal.mat"
    names = ["time", "a.k", "x", "minus_x"]
    width = max(map(len, names))
    time = np.array([0.0, 0.5, 1.0])
    scipy.io.savemat(path, {
        "Aclass": np.array([list(s.ljust(11)) for s in ("Atrajectory", "1.1", "", "binNormal")]),
        "name": np.array([list(n.ljust(width)) for n in names]),
        "description": np.array([list(d.ljust(12)) for d in ("Time [s]", "gain [1]", "x [m]", "minus x [m]")]),
        "dataInfo": np.array([[0, 1, 0, -1], [1, 2, 0, 0], [2, 2, 0, -1], [2, -2, 0, -1]], dtype=np.int32),
        "data_1": np.array([[0.0, 4.0], [1.0, 4.0]]),
        "data_2": np.column_stack([time, time ** 2]),
    }, format="4")
    back = read_mat(path)
    np.testing.assert_array_equal(back.time, time)
    np.testing.assert_array_equal(back.columns["x"], time ** 2)
    np.testing.assert_array_equal(back.columns["minus_x"], -time ** 2)
    np.testing.assert_array_equal(back.columns["a.k"], [4.0] * 3)
    assert back.unit("x") == "m" and back.info("minus_x").description == "minus x"
    assert back.info("a.k").kind == "parameter"
