"""Locating events: pure helpers of the simulation loop.

Like the small helpers of scipy's ``solve_ivp`` (``find_active_events``,
``solve_event_equation``), these know nothing of models: they take numbers,
the step's dense output and a function that says which watched relations
have flipped at a state.

* Time events have closed-form instants (a relation linear in time with
  parameter coefficients): :func:`time_event_roots`, :func:`next_time_event`.
* State events are found by sampling the dense output of each accepted step
  (:func:`sample_times`: several samples a step and every output point in it,
  so that two sign changes inside one step are not missed, scipy issue
  #9228), then bracketed by bisection to the first instant the relation has
  flipped (:func:`locate_flip`).
"""

from __future__ import annotations

import math
from typing import Callable, Mapping, Sequence

import numpy as np
import sympy as sp

from ..language import time as time_symbol

__all__ = ["time_event_roots", "next_time_event", "sample_times", "locate_flip", "bisect_flip"]

#: Most samples taken in one step (a long step of a stuck model on a fine grid).
MAX_SAMPLES = 2000


def time_event_roots(relations: Sequence, parameter_symbols: Mapping) -> tuple[tuple[int, float], ...]:
    """``(relation index, instant)`` of every time event (``inf`` if it never crosses)."""
    roots = []
    for rel in relations:
        if rel.is_time_event:
            g = sp.sympify(rel.g).xreplace(parameter_symbols)
            slope = float(sp.diff(g, time_symbol))
            offset = float(g.xreplace({time_symbol: 0}))
            roots.append((rel.index, -offset / slope if slope else math.inf))
    return tuple(roots)


def next_time_event(t: float, roots, relations: Sequence, values) -> float:
    """The first time event after ``t`` (or at ``t``, when its relation has yet to flip)."""
    best = math.inf
    for index, root in roots:
        if root > t or (root == t and relations[index].holds(0.0) != values[index]):
            best = min(best, root)
    return best


def sample_times(t_old: float, t_new: float, interval: float, grid: np.ndarray) -> np.ndarray:
    """Where to look for a flipped relation inside the step ``(t_old, t_new]``.

    At least 4 samples a step, and none coarser than the output interval:
    while a model is stuck its steps grow long, and a drive that crosses a
    threshold and returns within one step must not be missed.  The output
    points inside the step are samples too, so that no output row shows a
    relation at odds with its discrete state.
    """
    n = min(max(4, int(math.ceil((t_new - t_old) / interval))), MAX_SAMPLES)
    samples = np.linspace(t_old, t_new, n + 1)[1:]
    lo_i = np.searchsorted(grid, t_old, side="right")
    hi_i = np.searchsorted(grid, t_new, side="left")
    if hi_i > lo_i:
        samples = np.union1d(samples, grid[lo_i:hi_i])
    return samples


def locate_flip(t_old: float, samples: np.ndarray, dense: Callable, y_new: np.ndarray,
                flipped: Callable) -> tuple[float, np.ndarray, tuple] | None:
    """The first instant in the step at which a watched relation has flipped.

    Parameters
    ----------
    t_old : float
        The step's start (nothing flipped there).
    samples : ndarray
        Increasing sample times, the last one the step's end.
    dense : callable
        The step's dense output, ``dense(t)`` or ``dense(array)``.
    y_new : ndarray
        The state at the step's end (the solver's own value).
    flipped : callable
        ``flipped(t, x)`` -> the indices of the relations that have flipped.

    Returns
    -------
    (t, x, indices) or None
        The instant (to a few ulps), the state there and what flipped.
    """
    t_new = samples[-1]
    # the dense output at all samples in one call (the step end: its own value)
    inside = samples[samples < t_new]
    states_at = dense(inside).T if len(inside) else ()
    lo = t_old
    for i, s in enumerate(samples):
        xs = states_at[i] if s < t_new else y_new
        if flipped(s, xs):
            # bisection starts from the very state that flipped (the dense output
            # evaluated alone can differ in the last bit)
            return bisect_flip(lo, s, dense, flipped, xs)
        lo = s
    return None


def bisect_flip(lo: float, hi: float, dense: Callable, flipped: Callable, x_hi) -> tuple[float, np.ndarray, tuple]:
    """Narrow ``[lo, hi]`` (not flipped at lo, flipped at hi with state ``x_hi``) to the flip instant."""
    hit = flipped(hi, x_hi)
    tol = 4 * np.finfo(float).eps * max(1.0, abs(hi))
    for _ in range(200):
        if hi - lo <= tol:
            break
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        x_mid = dense(mid)
        now = flipped(mid, x_mid)
        if now:
            hi, x_hi, hit = mid, x_mid, now
        else:
            lo = mid
    return hi, np.array(x_hi, dtype=float), hit
