"""Readable reprs (issue 24, item 6): Linearization, SteadyState and SweepResult.

Each shows a short text summary and, in a notebook, HTML tables with the
names; numbers below the tolerance of what computed them print as 0 (no
``-0.`` in an A matrix, no ``-1.000011e-10`` for a stuck speed), while the
arrays and tables keep their values.
"""

from __future__ import annotations

import dataclasses
import re
import sys
from pathlib import Path

import numpy as np
import pytest

from acausal import Experiment, Model, translate
from acausal.library.blocks import Constant
from acausal.library.rotational import BearingFriction, Inertia, Torque
from acausal.tools.linearize import Linearization, linearize, steady_state
from acausal.tools.sweep import sweep

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from examples.clutch_drive import ClutchDrive  # noqa: E402

pytestmark = pytest.mark.filterwarnings("ignore::acausal.errors.StartValueWarning")

#: A number printed with a negative zero, or in exponent notation below 1e-9.
NEGATIVE_ZERO = re.compile(r"-0(\.0*)?(?![.\d])")
TINY = re.compile(r"\de-(1\d|[2-9]\d|\d{3})")


@pytest.fixture(scope="module")
def sliding_clutch():
    """ClutchDrive linearized while its clutch slides: A holds an exact -0.0 (d der(w_rel) / d phi_rel)."""
    return linearize(translate(ClutchDrive()), at=0.833, inputs=["torque.tau"], outputs=["J2.w"])


# -- Linearization -------------------------------------------------------------------------------


def test_linearization_repr_is_a_short_summary(sliding_clutch):
    text = repr(sliding_clutch)
    assert text.splitlines() == [
        "Linearization of ClutchDrive at t = 0.833 in [clutch: Forward]",
        "  4 states, 1 input, 1 output: A 4x4, B 4x1, C 1x4, D 1x1",
        "  eigenvalues: -2.02, -1.49±13.99j, 0",
    ]


def test_negative_zeros_and_round_off_print_as_zero_but_the_arrays_keep_them(sliding_clutch):
    lin = sliding_clutch
    row, column = lin.state_names.index("clutch.w_rel"), lin.state_names.index("clutch.phi_rel")
    assert lin.A[row, column] == 0.0 and np.signbit(lin.A[row, column])  # the -0. of the complaint
    for shown in (repr(lin), str(lin), lin._repr_html_()):
        assert not NEGATIVE_ZERO.search(shown), shown
    # round-off far below the largest entry of its matrix: 0 in print, untouched in the array
    A = lin.A.copy()
    A[row, column] = -3e-15  # 1.5e-17 of max |A| = 200
    noisy = dataclasses.replace(lin, A=A)
    assert noisy.A[row, column] == -3e-15
    assert "e-15" not in str(noisy) and "e-15" not in noisy._repr_html_()
    assert "-0." not in str(noisy)
    # a small entry that is not round-off is printed as it is
    A[row, column] = -3e-9
    assert "-3e-09" in dataclasses.replace(lin, A=A)._repr_html_()


def test_linearization_html_has_the_matrices_as_tables_with_the_names(sliding_clutch):
    page = sliding_clutch._repr_html_()
    assert page.count("<table") == 4
    for name in ("A", "B", "C", "D"):
        assert f"<caption style=\"text-align:left\"><b>{name}</b></caption>" in page
    # A's columns and rows are the states; B's column the input; C's row the output
    assert page.count("<th>clutch.w_rel</th>") == 2  # the column headers of A and C
    assert page.count("<th>torque.tau</th>") == 2   # of B and D
    assert page.count("<th style=\"text-align:left\">J2.w</th>") == 2  # the rows of C and D
    assert "eigenvalues: -2.02, -1.49±13.99j, 0" in page
    # the entries of the sliding clutch's A (see docs/linearization.md)
    assert "<td style=\"text-align:right\">200</td>" in page
    assert "<td style=\"text-align:right\">-200</td>" in page


def test_a_big_linearization_shows_the_head_of_its_matrices():
    n = 15
    names = tuple(f"x{k}" for k in range(n))
    A = -np.eye(n)
    lin = Linearization(A, np.zeros((n, 0)), np.zeros((0, n)), np.zeros((0, 0)), names, (), (), np.zeros(n),
                        np.zeros(0), np.zeros(0), 0.0, (), "")
    assert repr(lin).splitlines()[2] == "  eigenvalues: -1, -1, -1, -1, -1, -1, -1, -1, ... (7 more)"
    page = lin._repr_html_()
    assert "<th>x11</th>" in page and "<th>x12</th>" not in page
    assert "... 3 more</th>" in page and "... 3 more rows" in page


# -- SteadyState ----------------------------------------------------------------------------------


# the bearing drive of the steady-state tests (tau(w) = 1 + 0.1 w, static limit 1.2, J = 2)
sys.path.insert(0, str(Path(__file__).parent))
from test_linearize import BearingDrive  # noqa: E402


def test_steady_state_repr_lists_the_discrete_state_and_every_state():
    found = steady_state(BearingDrive(1.5))  # slides at w = (1.5 - 1)/0.1 = 5 rad/s
    assert repr(found).splitlines() == [
        "SteadyState of BearingDrive at t = 0 in [bearing: Forward] (after 2 discrete states tried)",
        "  state  value  unit   der(x)",
        "  J.phi      0  rad         5  free: moves at a constant rate",
        "  J.w        5  rad/s       0",
        f"  max |der(x)| at rest = 0 (tolerance {found.tolerance:.3g})",
    ]
    page = found._repr_html_()
    assert "<b>SteadyState of BearingDrive at t = 0 in [bearing: Forward]" in page
    assert "<td style=\"text-align:left\">J.w</td><td style=\"text-align:right\">5</td>" in page


def test_a_stuck_speed_of_round_off_prints_as_zero_but_is_kept():
    """The complaint: a stuck speed printed as -1.000011e-10."""
    with pytest.warns(UserWarning, match="J.w"):
        found = steady_state(BearingDrive(1.1))  # stuck
    speed = -1.000011e-10
    noisy = dataclasses.replace(found, states={**found.states, "J.w": speed},
                                derivatives={**found.derivatives, "der(J.phi)": speed})
    assert noisy.states["J.w"] == speed
    text = repr(noisy)
    assert "1.00001e-10" not in text and not NEGATIVE_ZERO.search(text)
    assert re.search(r"J\.w +0  rad/s +0  undetermined: kept as it was", text), text
    assert re.search(r"J\.phi +0  rad +0  free\n", text), text  # its rate is that speed: not moving
    assert "[bearing: Stuck (locked)]" in text
    assert "1.00001e-10" not in noisy._repr_html_()


# -- SweepResult ----------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def swept():
    """Four drives in a bearing for 1 s: two turn, two stay stuck; a zero inertia fails to start."""
    return sweep(BearingDrive(1.1), {"source.k": [-3.0, 0.5, 1.1, 3.0], "J.J": [2.0, 0.0]}, ["J.w"],
                 executor="serial", progress=False)


def test_sweep_repr_counts_runs_and_names_parameters_and_outputs(swept):
    lines = repr(swept).splitlines()
    assert re.fullmatch(r"SweepResult: 8 runs in [\d.]+ s, 4 ok, 4 failed", lines[0])
    assert lines[1:] == [
        "  parameters: source.k -3 .. 3 (4 values); J.J 0 .. 2 (2 values)",
        "  outputs: J.w",
        "  failed runs: 1 (InitializationError), 3 (InitializationError), 5 (InitializationError), "
        "7 (InitializationError)",
    ]


def test_sweep_html_shows_the_head_of_the_table_with_round_off_as_zero(swept):
    table = swept.table.copy()
    speed = -1.000011e-10  # a stuck speed at the end of run 2, next to the others' 0.975 rad/s
    table.loc[2, "J.w:final"] = speed
    noisy = dataclasses.replace(swept, table=table)
    page = noisy._repr_html_()
    assert "SweepResult: 8 runs" in page and "<table" in page
    assert "<th>J.w:final</th>" in page and "<th>source.k</th>" in page
    assert "e-10" not in page and not TINY.search(page)
    assert noisy.table.loc[2, "J.w:final"] == speed  # the table keeps it
    final = float(swept.table.loc[6, "J.w:final"])
    assert 0.5 < final < 1.5 and f"<td>{final:.6g}</td>" in page
    # the head only: ten rows of a longer sweep
    longer = dataclasses.replace(swept, table=swept.table.loc[[*range(8), *range(8)]].reset_index(drop=True))
    page = longer._repr_html_()
    assert page.count("<tr") == 1 + 10 and "... 6 more runs" in page
