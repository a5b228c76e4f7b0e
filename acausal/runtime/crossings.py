"""Locating events: pure helpers of the simulation loop.

Like the small helpers of scipy's ``solve_ivp`` (``find_active_events``,
``solve_event_equation``), these know nothing of models: they take numbers,
the step's dense output and a function that says which watched relations
have flipped at a state.

* Time events have closed-form instants (a relation linear in time with
  parameter coefficients), which the translation gives
  (:meth:`~acausal.compiler.translate.Translation.time_events`):
  :func:`next_time_event` picks the next.
* State events are found by sampling the dense output of each accepted step
  (:func:`sample_times`: several samples a step and every output point in it,
  so that two sign changes inside one step are not missed, scipy issue
  #9228), then bracketed by bisection to the first instant the relation has
  flipped (:func:`locate_flip`).
* A step's dense output is evaluated once for all its samples and output
  points (:func:`states_at`, bit for bit what the dense output gives at each
  instant alone), and the relations are decided for all samples at once
  (:meth:`~acausal.runtime.events.DiscreteEvaluator.first_flip`, with the
  numpy versions of the generated functions a compiled system gives, its
  ``vectorised(name)``).
"""

from __future__ import annotations

import math
from typing import Callable, Mapping, Sequence

import numpy as np

from . import explicit_rk

__all__ = ["held_roots", "next_time_event", "sample_times", "locate_flip", "bisect_flip", "states_at",
           "state_at", "sample_states", "step_samples"]

#: Most samples taken in one step (a long step of a stuck model on a fine grid).
MAX_SAMPLES = 2000


def held_roots(found: tuple, values: Mapping) -> tuple[tuple[int, float], ...]:
    """``(relation index, instant)`` of the held time events (:func:`acausal.compiler.timing.held_time_events`)
    for the current held values."""
    return tuple((index, float(root(*(values[n] for n in names)))) for index, names, root in found)


def next_time_event(t: float, roots, relations: Sequence, values) -> float:
    """The first time event after ``t`` (or at ``t``, when its relation has yet to flip)."""
    best = math.inf
    for index, root in roots:
        if root > t or (root == t and relations[index].holds(0.0) != values[index]):
            best = min(best, root)
    return best


def tick_at_or_after(t: float, start: float, interval: float, strictly: bool) -> float:
    """The first tick ``start + i*interval`` (i = 0, 1, ...) at or after ``t`` (after, if
    ``strictly``).  Each tick is computed from its number, never by adding up
    intervals, so the ticks stay exact to round-off over any number of periods."""
    if t < start or (t == start and not strictly):
        return start
    i = math.floor((t - start) / interval)
    while start + i * interval < t or (strictly and start + i * interval == t):
        i += 1
    while i > 0 and (start + (i - 1) * interval > t or (not strictly and start + (i - 1) * interval == t)):
        i -= 1
    return start + i * interval


def next_tick(t: float, ticks: Sequence[tuple[float, float]]) -> tuple[float, frozenset]:
    """The first clock tick after ``t`` and the clocks that tick then (``inf`` if none)."""
    best, which = math.inf, []
    for k, (start, interval) in enumerate(ticks):
        at = tick_at_or_after(t, start, interval, strictly=True)
        if at < best:
            best, which = at, [k]
        elif at == best:
            which.append(k)
    return best, frozenset(which)


def ticking_at(t: float, ticks: Sequence[tuple[float, float]]) -> frozenset:
    """The clocks with a tick exactly at ``t``."""
    return frozenset(k for k, (start, interval) in enumerate(ticks)
                     if tick_at_or_after(t, start, interval, strictly=False) == t)


def sample_times(t_old: float, t_new: float, interval: float, grid: np.ndarray) -> np.ndarray:
    """Where to look for a flipped relation inside the step ``(t_old, t_new]``.

    At least 4 samples a step, and none coarser than the output interval:
    while a model is stuck its steps grow long, and a drive that crosses a
    threshold and returns within one step must not be missed.  The output
    points inside the step are samples too, so that no output row shows a
    relation at odds with its discrete state.
    """
    return _samples(t_old, t_new, interval, grid)[0]


def _samples(t_old: float, t_new: float, interval: float, grid: np.ndarray) -> tuple[np.ndarray, int, int]:
    """:func:`sample_times`, and the output points among them: ``grid[lo:hi]``."""
    n = min(max(4, int(math.ceil((t_new - t_old) / interval))), MAX_SAMPLES)
    samples = _linspace(t_old, t_new, n + 1)[1:]
    lo_i = int(np.searchsorted(grid, t_old, side="right"))
    hi_i = int(np.searchsorted(grid, t_new, side="left"))
    if hi_i > lo_i:
        samples = _union(samples, grid[lo_i:hi_i])
    return samples, lo_i, hi_i


def _linspace(start: float, stop: float, num: int) -> np.ndarray:
    """``np.linspace(start, stop, num)`` for two floats and ``num >= 2``, bit for bit: the
    same operations as numpy's (``arange(num) * step + start``, the last point set to
    ``stop``), without the layers of conversion that cost more than the arithmetic at
    every step."""
    div = num - 1
    delta = float(stop) - float(start)
    step = delta / div
    y = np.arange(num, dtype=float)
    if step == 0:  # denormal steps, as numpy (gh-5437)
        y /= div
        y *= delta
    else:
        y *= step
    y += start
    y[-1] = stop
    return y


def _union(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.union1d(a, b)`` (the sorted distinct values), without its layers of calls."""
    out = np.concatenate((a, b))
    out.sort()
    keep = np.empty(len(out), dtype=bool)
    keep[:1] = True
    np.not_equal(out[1:], out[:-1], out=keep[1:])
    return out[keep]


def step_samples(t_old: float, t_new: float, interval: float, grid: np.ndarray, dense: Callable,
                 y_new: np.ndarray, first_row: int, stop_row: int):
    """The samples of the step ``(t_old, t_new]`` (:func:`sample_times`), and the states at
    them and at the output points ``grid[first_row:stop_row]``: one evaluation of the
    step's dense output for both.

    Returns ``(samples, at samples, at rows)``, states as rows: at a sample before
    ``t_new`` the dense output, at ``t_new`` the solver's own ``y_new``; at an output
    point the dense output (the step's end included: the caller decides).
    """
    samples, lo_i, hi_i = _samples(t_old, t_new, interval, grid)
    # the samples increase to t_new: as a rule only the last is not before it (a step a
    # few ulps long may round several onto it)
    last_only = len(samples) < 2 or samples[-2] < t_new
    if last_only:
        inside = samples[:-1]
    else:
        before = samples < t_new
        inside = samples[before]
    rows = grid[first_row:stop_row]
    if first_row >= stop_row or (lo_i <= first_row and stop_row <= hi_i):
        times = inside  # every output point is a sample
    else:  # output points at the step's end (or before the step) as well
        times = np.union1d(inside, rows)
    states = states_at(dense, times)
    at_samples = np.empty((len(samples), len(y_new)))
    at_inside = states if times is inside else states[np.searchsorted(times, inside)]
    if last_only:
        at_samples[:-1] = at_inside
        at_samples[-1] = y_new
    else:
        at_samples[before] = at_inside
        at_samples[~before] = y_new
    at_rows = states[np.searchsorted(times, rows)] if len(rows) else states[:0]
    return samples, at_samples, at_rows


def locate_flip(t_old: float, samples: np.ndarray, dense: Callable, y_new: np.ndarray,
                flipped: Callable, first_flip: Callable | None = None,
                states: np.ndarray | None = None,
                narrow: Callable | None = None) -> tuple[float, np.ndarray, tuple] | None:
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
    first_flip : callable, optional
        ``first_flip(times, states)`` -> ``(index, flipped)`` of the first sample
        at which ``flipped`` is not empty, or None: the samples decided at once
        (default: ``flipped`` at each sample in turn).
    states : ndarray, optional
        The states at the samples as rows (default: :func:`states_at` inside the
        step, ``y_new`` at its end).
    narrow : callable, optional
        ``narrow(indices)`` -> ``(flipped, distance)``: a ``flipped`` that looks
        at those relations only, and the signed distance of the first of them
        to flip (None: halving only, see :func:`bisect_flip`): the bisection then
        follows the relations that flipped at the sample
        (a relation that flips and flips back between two samples is not seen
        by the sampling either), and a model of many independent parts
        evaluates only the parts that own them.

    Returns
    -------
    (t, x, indices) or None
        The instant (to a few ulps), the state there and what flipped.
    """
    if states is None:
        states = sample_states(dense, samples, y_new)
    if first_flip is None:
        found = None
        for i, s in enumerate(samples):
            hit = flipped(s, states[i])
            if hit:
                found = i, hit
                break
    else:
        found = first_flip(samples, states)
    if found is None:
        return None
    i, hit = found
    lo = samples[i - 1] if i else t_old
    # bisection starts from the very state that flipped
    if narrow is None:
        return bisect_flip(lo, samples[i], dense, flipped, states[i])
    among, distance = narrow(tuple(hit))
    return bisect_flip(lo, samples[i], dense, among, states[i], distance)


def sample_states(dense: Callable, samples: np.ndarray, y_new: np.ndarray) -> np.ndarray:
    """The states at ``samples`` as rows: the dense output inside the step, the
    solver's own value at its end (the last sample)."""
    before = samples < samples[-1]
    out = np.empty((len(samples), np.size(y_new)))
    out[before] = states_at(dense, samples[before])
    out[~before] = y_new
    return out


def bisect_flip(lo: float, hi: float, dense: Callable, flipped: Callable, x_hi,
                distance: Callable | None = None) -> tuple[float, np.ndarray, tuple]:
    """Narrow ``[lo, hi]`` (not flipped at lo, flipped at hi with state ``x_hi``) to the flip instant.

    The bracket shrinks until it is 4 ulp wide; ``flipped`` decides every trial
    point.  With ``distance`` (``distance(t, x)``: negative where no relation
    watched has flipped, positive where one has: the largest of their signed
    distances) the trial points
    come from the Illinois variant of regula falsi [1]_, with a plain halving
    every third step, so that a smooth crossing takes about ten trials instead
    of fifty; without it, every step halves.

    References
    ----------
    .. [1] M. Dowell and P. Jarratt, "A modified regula falsi method for computing
       the root of an equation", BIT 11, 168-174, 1971.
    """
    hit = flipped(hi, x_hi)
    tol = 4 * np.finfo(float).eps * max(1.0, abs(hi))
    g_lo = g_hi = 0.0
    if distance is not None:
        g_lo, g_hi = distance(lo, state_at(dense, lo)), distance(hi, x_hi)
        if not (math.isfinite(g_lo) and math.isfinite(g_hi) and g_lo <= 0.0 <= g_hi and g_lo < g_hi):
            distance = None  # not a clean sign change: halving only
    kept = 0  # +1: hi moved last (lo kept), -1: lo moved last
    for step in range(1, 201):
        if hi - lo <= tol:
            break
        mid = 0.5 * (lo + hi)
        if distance is not None and step % 3:
            secant = hi - g_hi * (hi - lo) / (g_hi - g_lo)
            # strictly inside, a quarter of the final width from either end
            mid = min(max(secant, lo + 0.25 * tol), hi - 0.25 * tol)
            if not lo < mid < hi:
                mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        x_mid = state_at(dense, mid)  # dense(mid), bit for bit
        now = flipped(mid, x_mid)
        g_mid = distance(mid, x_mid) if distance is not None else 0.0
        if distance is not None and not math.isfinite(g_mid):
            distance = None
        if now:
            hi, x_hi, hit = mid, x_mid, now
            if distance is not None:
                g_hi = max(g_mid, 0.0)
                if kept == 1:  # the same end moved twice: Illinois halves the other's weight
                    g_lo *= 0.5
                kept = 1
        else:
            lo = mid
            if distance is not None:
                g_lo = min(g_mid, 0.0)
                if kept == -1:
                    g_hi *= 0.5
                kept = -1
        if distance is not None and not g_lo < g_hi:
            distance = None
    return hi, np.array(x_hi, dtype=float), hit


# -- many instants at once ------------------------------------------------------------------------

def states_at(dense: Callable, times) -> np.ndarray:
    """The dense output at each of ``times``, as rows: ``m x n``.

    Row ``j`` is bit for bit ``dense(times[j])``.  scipy's dense outputs, called
    with an array, compute the polynomials with one matrix product whose
    rounding differs from that of a call at one instant; here the same matrix-
    vector products are made for all instants in one call (``np.matmul`` on a
    stack), so rows written to the result are what the loop of one call per
    output point gave.  Dense outputs of other kinds are called per instant.
    """
    times = np.asarray(times, dtype=float).reshape(-1)
    batched = _BATCHED.get(type(dense))
    if batched is None and not _SCIPY_KINDS[0]:
        _fast_paths(type(dense))
        batched = _BATCHED.get(type(dense))
    if batched is not None and batched[1] is not False and len(times):
        try:
            out = batched[0](dense, times)
        except (AttributeError, TypeError, ValueError):  # a scipy with other internals
            out = None
        if out is not None and batched[1] is None:
            # the first use in this process: check against the per-instant calls
            batched[1] = _identical(out[:16], _per_instant(dense, times[:16]))
        if out is not None and batched[1]:
            return out
    return _per_instant(dense, times)


def state_at(dense: Callable, t: float) -> np.ndarray:
    """``dense(t)`` at one instant, bit for bit, without the overhead of scipy's call
    (for the dense outputs of RK23, RK45 and Radau; others are called)."""
    kind = type(dense)
    point = _POINT.get(kind)
    if point is None and not _SCIPY_KINDS[0]:
        _fast_paths(kind)
        point = _POINT.get(kind)
    if point is not None and point[1] is not False:
        try:
            y = point[0](dense, t)
        except (AttributeError, TypeError, ValueError):  # a scipy with other internals
            point[1] = False
            return dense(t)
        if point[1] is None:  # the first use in this process: check against the call
            point[1] = _identical(y, dense(t))
            if not point[1]:
                return dense(t)
        return y
    return dense(t)


def _rk_point(d, t):
    """scipy's ``RkDenseOutput`` and acausal's ``QuarticDenseOutput`` at one instant."""
    x = (t - d.t_old) / d.h
    p = [x]
    for _ in range(d.order):  # np.cumprod of the repeated x, one product at a time
        p.append(p[-1] * x)
    y = d.h * np.dot(d.Q, np.array(p, dtype=float))
    y += d.y_old
    return y


def _radau_point(d, t):
    x = (t - d.t_old) / d.h
    p = [x]
    for _ in range(d.order):
        p.append(p[-1] * x)
    y = np.dot(d.Q, np.array(p, dtype=float))
    y += d.y_old
    return y


def _identical(a, b) -> bool:
    """Bit for bit (a NaN equal to itself, -0.0 not equal to 0.0)."""
    a, b = np.ascontiguousarray(a, dtype=float), np.ascontiguousarray(b, dtype=float)
    return a.shape == b.shape and bool(np.array_equal(a.view(np.int64), b.view(np.int64)))


def _per_instant(dense: Callable, times: np.ndarray) -> np.ndarray:
    rows = [np.asarray(dense(t), dtype=float) for t in times]
    if not rows:
        return np.empty((0, np.size(dense(dense.t))))
    return np.array(rows).reshape(len(rows), -1)


def _gemv_rows(A: np.ndarray, P: np.ndarray) -> np.ndarray:
    """``np.dot(A, p)`` for every row ``p`` of ``P``: one stacked product, the same
    matrix-vector call (and rounding) as each alone."""
    return np.matmul(A, P[:, :, None])[:, :, 0]


def _powers(x: np.ndarray, k: int) -> np.ndarray:
    """Rows ``x, x*x, (x*x)*x, ...`` (``k`` of them): the products ``np.cumprod`` of the
    repeated ``x`` makes, one at a time."""
    p = np.empty((len(x), k))
    p[:, 0] = x
    for j in range(1, k):
        np.multiply(p[:, j - 1], x, out=p[:, j])
    return p


def _rk_states(d, t):
    """scipy's ``RkDenseOutput`` (RK23, RK45), and acausal's ``QuarticDenseOutput``, at
    instants one by one."""
    y = d.h * _gemv_rows(d.Q, _powers((t - d.t_old) / d.h, d.order + 1))
    y += d.y_old
    return y


def _radau_states(d, t):
    y = _gemv_rows(d.Q, _powers((t - d.t_old) / d.h, d.order + 1))
    y += d.y_old
    return y


def _bdf_states(d, t):
    p = np.cumprod((t[:, None] - d.t_shift) / d.denom, axis=1)
    y = _gemv_rows(d.D[1:].T, np.ascontiguousarray(p))
    y += d.D[0]
    return y


def _lsoda_states(d, t):
    # the powers instant by instant: numpy's power of an array may round otherwise
    p = np.array([((s - d.t) / d.h) ** d.p for s in t])
    return _gemv_rows(d.yh, p)


def _columns_as_rows(d, t):
    """A dense output that works element by element (DOP853's), or instant by instant
    (acausal's RK45): an array call is what one call per instant gives."""
    return np.asarray(d(t), dtype=float).T.reshape(len(t), -1)


def _batched_kinds() -> dict:
    """Dense output class -> [function, verified]: None until checked once in this process."""
    from scipy.integrate._ivp.bdf import BdfDenseOutput
    from scipy.integrate._ivp.lsoda import LsodaDenseOutput
    from scipy.integrate._ivp.radau import RadauDenseOutput
    from scipy.integrate._ivp.rk import Dop853DenseOutput, RkDenseOutput

    return {RkDenseOutput: [_rk_states, None], RadauDenseOutput: [_radau_states, None],
            BdfDenseOutput: [_bdf_states, None], LsodaDenseOutput: [_lsoda_states, None],
            Dop853DenseOutput: [_columns_as_rows, None]}


def _point_kinds() -> dict:
    from scipy.integrate._ivp.radau import RadauDenseOutput
    from scipy.integrate._ivp.rk import RkDenseOutput

    return {RkDenseOutput: [_rk_point, None], RadauDenseOutput: [_radau_point, None]}


# acausal's own Runge-Kutta pairs: an array of instants gives, column by column, what
# one instant gives (checked once per process all the same); scipy's kinds are added
# when a scipy solver's dense output first comes (a run with an explicit method never
# imports scipy)
_BATCHED: dict = {explicit_rk.QuarticDenseOutput: [_rk_states, None],
                  explicit_rk.Dop853DenseOutput: [_columns_as_rows, None]}
# (the quartic of acausal's RK45 has the attributes and arithmetic of scipy's RkDenseOutput)
_POINT: dict = {explicit_rk.QuarticDenseOutput: [_rk_point, None]}
_SCIPY_KINDS = [False]  # whether scipy's kinds were looked up


def _fast_paths(kind: type) -> None:
    """Add scipy's dense-output kinds once ``kind`` is one of scipy's."""
    if not _SCIPY_KINDS[0] and kind.__module__.startswith("scipy."):
        _SCIPY_KINDS[0] = True
        try:
            _BATCHED.update(_batched_kinds())
            _POINT.update(_point_kinds())
        except ImportError:  # another scipy layout: one call per instant
            pass
