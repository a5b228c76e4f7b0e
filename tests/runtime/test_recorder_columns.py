"""The result's columns of a warm run: what depends only on the translation (the names,
their rows, the parameters that have columns) is kept with it, and the columns are the
same as a cold run's, in the same order and of the same values and types."""

from __future__ import annotations

import numpy as np

from acausal import simulate
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
