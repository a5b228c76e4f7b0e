"""``SimulationResult.at``: values at any time of the run, against closed forms.

Between output rows a continuous Real is interpolated linearly (exact for a
linear signal; for ``t**2`` off by exactly ``(t - t_i) (t_i+1 - t)``); at an
event, where the rows appear twice, ``side="right"`` gives the values after it
and ``side="left"`` those before; discrete values hold; times outside the run
are refused.
"""

from __future__ import annotations

import numpy as np
import pytest

from acausal import Eq, Integer, Model, Variable, When, der, pre, reinit, simulate, time
from acausal.runtime.result import ColumnInfo, SimulationResult

#: A coarse, uneven grid: interpolation is what is tested, not the sampling.
GRID = np.array([0.0, 0.1, 0.35, 0.5, 0.9, 1.0])


def made(time_, columns, kinds=None, **options) -> SimulationResult:
    kinds = kinds or {}
    info = {n: ColumnInfo(n, kind=kinds.get(n, "continuous")) for n in columns}
    return SimulationResult(np.asarray(time_, dtype=float),
                            {n: np.asarray(v, dtype=float) for n, v in columns.items()},
                            model_name="Made", column_info=info, **options)


def test_a_linear_signal_is_read_exactly_between_rows():
    result = made(GRID, {"y": 3.0 * GRID + 1.0})
    t = np.array([0.0, 0.03, 0.2, 0.499, 0.5, 0.77, 1.0])
    np.testing.assert_allclose(result.at(t, "y"), 3.0 * t + 1.0, rtol=0, atol=1e-14)
    assert result.at(0.2, "y") == pytest.approx(1.6, abs=1e-15)
    assert np.ndim(result.at(0.2, "y")) == 0  # a number for a number


def test_a_quadratic_is_off_by_the_chord_error_of_linear_interpolation():
    """Between t_i and t_i+1 the chord of t**2 lies (t - t_i)(t_i+1 - t) above it."""
    result = made(GRID, {"y": GRID ** 2})
    t = np.linspace(0.0, 1.0, 41)
    i = np.clip(np.searchsorted(GRID, t, side="right") - 1, 0, len(GRID) - 2)
    chord = t ** 2 + (t - GRID[i]) * (GRID[i + 1] - t)
    np.testing.assert_allclose(result.at(t, "y"), chord, rtol=0, atol=1e-14)
    assert np.max(chord - t ** 2) > 0.01  # the error is real: the dense output is not kept


def test_vectorised_over_any_shape_and_over_several_names():
    result = made(GRID, {"a": 2.0 * GRID, "b": -GRID})
    t = np.array([[0.05, 0.25], [0.6, 0.95]])
    both = result.at(t, ["a", "b"])
    assert set(both) == {"a", "b"} and both["a"].shape == (2, 2)
    np.testing.assert_allclose(both["a"], 2.0 * t, atol=1e-14)
    np.testing.assert_allclose(both["b"], -t, atol=1e-14)
    assert set(result.at(0.5)) == {"a", "b"}  # every column by default


def test_at_an_event_the_right_limit_by_default_and_the_left_on_request():
    """y = t up to the event at 0.5, then t - 0.5 (a reset): the rows at 0.5 hold 0.5 then 0."""
    t = np.array([0.0, 0.25, 0.5, 0.5, 0.75, 1.0])
    y = np.array([0.0, 0.25, 0.5, 0.0, 0.25, 0.5])
    mode = np.array([0, 0, 0, 1, 1, 1])
    result = made(t, {"y": y, "mode": mode}, kinds={"mode": "integer"})
    assert result.at(0.5, "y") == 0.0
    assert result.at(0.5, "y", side="left") == 0.5
    assert result.at(0.5, "mode") == 1 and result.at(0.5, "mode", side="left") == 0
    # just before and after: each side's line, not a ramp across the jump
    assert result.at(0.4, "y") == pytest.approx(0.4, abs=1e-15)
    assert result.at(0.6, "y") == pytest.approx(0.1, abs=1e-15)
    # away from events both sides agree
    assert result.at(0.25, "y", side="left") == result.at(0.25, "y") == 0.25
    both = result.at(np.array([0.5, 0.5, 0.6]), "y", side="left")
    np.testing.assert_allclose(both, [0.5, 0.5, 0.1], atol=1e-15)


def test_three_rows_at_one_instant_give_the_first_and_the_last():
    t = np.array([0.0, 1.0, 1.0, 1.0, 2.0])
    y = np.array([0.0, 1.0, 5.0, 7.0, 8.0])
    result = made(t, {"y": y})
    assert result.at(1.0, "y", side="left") == 1.0 and result.at(1.0, "y") == 7.0
    assert result.at(1.5, "y") == pytest.approx(7.5)


def test_discrete_values_hold_and_keep_their_types():
    t = np.array([0.0, 0.4, 1.0])
    result = made(t, {"b": [0.0, 1.0, 1.0], "n": [2.0, 3.0, 3.0], "d": [1.0, 4.0, 4.0]},
                  kinds={"b": "boolean", "n": "integer", "d": "discrete"})
    before, after = result.at(0.3, "b"), result.at(0.5, "b")
    assert type(before) is bool and not before and after       # one time: Python numbers
    assert result.at(0.3, "n") == 2 and type(result.at(0.3, "n")) is int
    assert type(result.at(0.3, "d")) is float
    # several times: arrays of the column's type
    assert result.at([0.3, 0.5], "b").dtype == bool and result.at([0.3, 0.5], "n").dtype.kind == "i"
    assert result.at(0.3, "d") == 1.0  # a discrete Real holds: not 1 + 3 * 0.75
    assert result.at(0.4, "d") == 4.0


def test_times_outside_the_run_and_bad_arguments_are_refused():
    result = made(GRID, {"y": GRID})
    with pytest.raises(ValueError, match=r"t = 1\.5 is outside the run's span, t = 0 \.\. 1 s"):
        result.at(1.5, "y")
    with pytest.raises(ValueError, match=r"outside the run's span"):
        result.at([0.5, -0.1], "y")
    with pytest.raises(ValueError, match="not a finite time"):
        result.at(np.nan, "y")
    with pytest.raises(ValueError, match="side='middle'"):
        result.at(0.5, "y", side="middle")
    with pytest.raises(KeyError, match="did you mean y"):
        result.at(0.5, "yy")
    with pytest.raises(ValueError, match="no output points"):
        made([], {"y": []}).at(0.0, "y")


def test_a_run_that_stopped_early_says_so_when_asked_past_its_end():
    result = made([0.0, 0.3], {"y": [0.0, 0.3]}, status=-1, message="the solver failed at t = 0.3")
    with pytest.raises(ValueError, match=r"t = 0 \.\. 0\.3 s \(the run stopped early: the solver failed"):
        result.at(0.5, "y")


class Saw(Model):
    """x' = 1 from 0; at t = 0.5 (a time event) x is set back to 0 and n counts it."""

    x = Variable(start=0.0, fixed=True, unit="m")
    n = Integer(start=0)

    def equations(self):
        return [Eq(der(self.x), 1.0),
                When(time >= 0.5, reinit(self.x, 0.0)),
                When(time >= 0.5, Eq(self.n, pre(self.n) + 1))]


def test_a_simulated_reset_read_between_rows_and_at_the_event():
    result = simulate(Saw(), stop_time=1.0, interval=0.1)
    assert result.status == 0, result.message
    assert np.count_nonzero(result.time == 0.5) >= 2  # the event's left and right limits
    t = np.array([0.0, 0.123, 0.45, 0.55, 0.987, 1.0])
    np.testing.assert_allclose(result.at(t, "x"), np.where(t < 0.5, t, t - 0.5), atol=1e-9)
    assert result.at(0.5, "x") == pytest.approx(0.0, abs=1e-12)
    assert result.at(0.5, "x", side="left") == pytest.approx(0.5, abs=1e-9)
    assert result.at(0.5, "n") == 1 and result.at(0.5, "n", side="left") == 0
    with pytest.raises(ValueError, match="outside the run's span"):
        result.at(1.0 + 1e-9, "x")
