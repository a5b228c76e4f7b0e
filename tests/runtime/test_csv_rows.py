"""The CSV body of a result: every value as ``repr`` writes it, however the columns repeat.

``_csv_rows`` formats a column once when it appears several times (aliases)
and a constant column once per value; the text must be what formatting
each value on its own gives, and read back as the same doubles bit for bit.
"""

from __future__ import annotations

import csv
import io

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from acausal.runtime.result import _csv_rows

doubles = st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True)


def one_by_one(columns, terminator="\r\n"):
    handle = io.StringIO()
    writer = csv.writer(handle, lineterminator=terminator)
    for row in zip(*columns):
        writer.writerow([repr(float(v)) for v in row])
    return handle.getvalue()


@st.composite
def column_sets(draw):
    rows = draw(st.integers(0, 12))
    distinct = draw(st.lists(st.one_of(
        st.lists(doubles, min_size=rows, max_size=rows),                 # any values
        doubles.map(lambda v: [v] * rows),                               # a constant (a parameter)
        st.just([0.0, -0.0] * (rows // 2) + [0.0] * (rows % 2)),         # equal but not the same bits
    ), min_size=1, max_size=5))
    order = draw(st.lists(st.integers(0, len(distinct) - 1), min_size=1, max_size=8))
    return [np.array(distinct[i], dtype=float) for i in order]          # repeats: aliases


@settings(max_examples=300, deadline=None)
@given(column_sets())
def test_rows_are_each_value_formatted_alone(columns):
    assert _csv_rows(columns, "\r\n") == one_by_one(columns)


@settings(max_examples=100, deadline=None)
@given(column_sets())
def test_rows_read_back_bit_for_bit(columns):
    text = _csv_rows(columns, "\n")
    back = [[float(v) for v in row] for row in csv.reader(io.StringIO(text))]
    expected = np.column_stack(columns) if len(columns[0]) else np.empty((0, len(columns)))
    got = np.array(back, dtype=float).reshape(expected.shape)
    nan = np.isnan(expected)
    np.testing.assert_array_equal(np.isnan(got), nan)  # NaN's sign and payload: repr writes "nan"
    assert got[~nan].tobytes() == expected[~nan].tobytes()


def test_a_mixed_sign_zero_column_is_not_taken_for_a_constant():
    assert _csv_rows([np.array([0.0, -0.0, 0.0])], "\n") == "0.0\n-0.0\n0.0\n"
