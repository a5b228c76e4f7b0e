"""The result's columns of a warm run: what depends only on the translation (the names,
their rows, the parameters that have columns) is kept with it, and the columns are the
same as a cold run's, in the same order and of the same values and types."""

from __future__ import annotations

import math

import numpy as np
import sympy as sp

from acausal import Eq, Experiment, Model, Variable, der, simulate, time
from acausal.compiler.translate import translate
from acausal.tools.bench import get_case, suite


def test_a_warm_run_has_the_columns_of_the_first():
    case = get_case(suite().floor_case().case)
    translation = translate(case.make(), cache=False)
    first = simulate(translation, stop_time=case.stop_time)
    kept = translation.extras.get("column_names")
    assert kept is not None
    second = simulate(translation, stop_time=case.stop_time)
    # the names were not made again (no system was entered)
    assert translation.extras["column_names"] is kept
    assert list(first.columns) == list(second.columns)
    for name, values in first.columns.items():
        other = second.columns[name]
        assert values.dtype == other.dtype, name
        np.testing.assert_array_equal(values, other)
    # a parameter's column holds its value at every row
    model = translation.data
    for p in model.parameters:
        assert (first.columns[p.name] == p.value).all()


def _columns_in_blocks(monkeypatch, rows: int):
    """Make :func:`acausal.runtime.recorder._fill` work in blocks of ``rows`` rows, and count
    the blocks it fills."""
    from acausal.runtime import recorder

    blocks = []
    fill_rows = recorder._fill_rows

    def counted(block, *args):
        blocks.append(block.shape[1])
        return fill_rows(block, *args)

    monkeypatch.setattr(recorder, "_FILL_BLOCK_VALUES", 1)
    monkeypatch.setattr(recorder, "_FILL_BLOCK_ROWS", rows)
    monkeypatch.setattr(recorder, "_fill_rows", counted)
    return blocks


def test_columns_filled_in_blocks_of_rows_are_those_filled_at_once(monkeypatch):
    """A large model's stretch is filled some rows at a time (its working arrays stay
    small): every value is computed element by element, so the columns are the same, bit
    for bit, as one block gives."""
    case = get_case(suite().floor_case().case)
    translation = translate(case.make(), cache=False)
    whole = simulate(translation, stop_time=case.stop_time)
    blocks = _columns_in_blocks(monkeypatch, 7)
    blocked = simulate(translation, stop_time=case.stop_time)
    assert blocks and max(blocks) <= 7 and len(blocks) > len(whole.events)  # stretches cut into blocks
    assert list(whole.columns) == list(blocked.columns)
    for name, values in whole.columns.items():
        assert np.array_equal(values.view(np.int64), blocked.columns[name].view(np.int64)), name


class _OverflowingOutput(Model):
    """y = exp(5000 t) overflows at t = log(max float)/5000 = 0.14196..., the state stays finite."""

    experiment = Experiment(stop_time=0.5, interval=0.001)
    x = Variable(start=1.0, fixed=True)
    y = Variable()

    def equations(self):
        return [Eq(der(self.x), -self.x), Eq(self.y, sp.exp(5000 * time))]


def test_a_non_finite_output_in_a_later_block_cuts_the_rows_at_its_own_row(monkeypatch):
    """The first row whose output is not finite is found in its block and counted from the
    stretch's start: the run keeps the rows up to it, as when the stretch is one block."""
    with np.errstate(all="ignore"):
        whole = simulate(_OverflowingOutput())
        blocks = _columns_in_blocks(monkeypatch, 16)
        blocked = simulate(_OverflowingOutput())
    overflow = math.log(np.finfo(float).max) / 5000
    assert len(blocks) > 10  # the overflow is met after some blocks
    for result in (whole, blocked):
        assert result.status == -1 and "y" in result.error.message and "not finite" in result.error.message
        assert overflow <= result.time[-1] <= overflow + 0.001 + 1e-12
        assert np.isfinite(result["y"][:-1]).all() and not np.isfinite(result["y"][-1])
    np.testing.assert_array_equal(whole.time, blocked.time)
    np.testing.assert_array_equal(whole["x"], blocked["x"])
    assert whole.error.message == blocked.error.message


def test_the_column_names_come_from_one_snapshot_of_the_systems():
    """The threads of a sweep share one translation: another thread may enter a new discrete
    state (add a system) while a run names its columns. The names are made from the systems
    as they were when asked for (a loop over the live table failed a sweep's run with
    'dictionary changed size during iteration')."""
    import types

    from acausal.runtime.recorder import _column_names

    translation = translate(get_case(suite().floor_case().case).make(), cache=False)
    simulate(translation, stop_time=0.1)
    systems: dict = {}

    class EnteredMeanwhile:
        """A system whose names, when read, coincide with another thread adding a system."""

        def __init__(self, real):
            self.real = real

        @property
        def derivative_names(self):
            systems[("another", len(systems))] = self.real
            return self.real.derivative_names

    for key, system in translation.systems.items():
        systems[key] = EnteredMeanwhile(system)
    before = len(systems)
    shared = types.SimpleNamespace(data=translation.data, demand=None, extras={}, systems=systems)
    names, index, _parameters = _column_names(shared)
    assert len(systems) > before  # the table grew while the names were made
    expected = {d for s in translation.systems.values() for d in s.derivative_names}
    assert expected <= set(names) and set(index) == set(names)
