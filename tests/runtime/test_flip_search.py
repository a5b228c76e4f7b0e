"""The search of a flip instant inside a step (``runtime.crossings.bisect_flip``).

Against closed-form roots: the instant found is the first point of a bracket
4 ulp wide around the root, with halving alone and with regula falsi
(Illinois); regula falsi needs fewer trials on a smooth crossing and falls
back to halving where the distance does not change sign cleanly.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from acausal.runtime.crossings import bisect_flip


class Counted:
    """A ``dense`` output: the state is (t,), and the calls are counted."""

    def __init__(self) -> None:
        self.calls = 0

    def __call__(self, t):
        self.calls += 1
        return np.array([t], dtype=float)


def search(g, lo, hi, with_distance):
    dense = Counted()

    def flipped(t, x):
        return (0,) if g(x[0]) >= 0.0 else ()

    distance = (lambda t, x: g(x[0])) if with_distance else None
    t, _, hit = bisect_flip(lo, hi, dense, flipped, np.array([hi]), distance)
    return t, hit, dense.calls


@pytest.mark.parametrize("g, root", [
    (lambda t: t - 0.3, 0.3),
    (lambda t: math.exp(t) - 2.0, math.log(2.0)),
    (lambda t: (t - 0.61) ** 3, 0.61),            # flat at the root
    (lambda t: math.tanh(50 * (t - 0.45)), 0.45),  # steep
])
def test_both_searches_find_the_root_to_the_bracket(g, root):
    tol = 4 * np.finfo(float).eps
    for with_distance in (False, True):
        t, hit, _ = search(g, 0.0, 1.0, with_distance)
        assert hit == (0,)
        assert g(t) >= 0.0 and root - tol <= t <= root + 2 * tol


def test_regula_falsi_needs_fewer_trials_on_a_smooth_crossing():
    g = lambda t: math.exp(t) - 2.0  # noqa: E731
    _, _, halving = search(g, 0.0, 1.0, False)
    _, _, secant = search(g, 0.0, 1.0, True)
    assert halving >= 50
    assert secant <= 25


def test_a_distance_without_a_clean_sign_change_falls_back_to_halving():
    """A distance that is positive at both ends (inconsistent with flipped) is not used."""
    dense = Counted()
    t, _, hit = bisect_flip(0.0, 1.0, dense, lambda t, x: (0,) if x[0] >= 0.25 else (),
                            np.array([1.0]), lambda t, x: 1.0)
    assert hit == (0,) and abs(t - 0.25) <= 8 * np.finfo(float).eps


def test_two_relations_in_one_step_are_searched_on_the_first_to_flip():
    """Several relations flip in one step: the search follows the largest signed distance
    (``DiscreteEvaluator.distance_to_first_flip``) to the first flip, with fewer trials than
    halving and the same bracket."""
    roots = (0.7, math.log(2.0))  # the second flips first

    def g(k, t):
        return t - roots[0] if k == 0 else math.exp(t) - 2.0

    def flipped(t, x):
        return tuple(k for k in (0, 1) if g(k, x[0]) >= 0.0)

    def first_distance(t, x):
        return max(g(0, x[0]), g(1, x[0]))

    found = {}
    for name, distance in (("halving", None), ("secant", first_distance)):
        dense = Counted()
        t, _, hit = bisect_flip(0.0, 1.0, dense, flipped, np.array([1.0]), distance)
        found[name] = (t, hit, dense.calls)
    tol = 4 * np.finfo(float).eps
    for t, hit, _ in found.values():
        assert hit == (1,) and min(roots) - tol <= t <= min(roots) + 2 * tol
    assert found["secant"][2] <= 25 <= 50 <= found["halving"][2]


def test_the_first_flip_distance_of_a_model_is_the_largest_of_its_relations():
    from acausal import simulate, translate
    from acausal.runtime.events import evaluator_for
    from examples.coupled_clutches import CoupledClutches

    translation = translate(CoupledClutches())
    simulate(translation)
    evaluator = evaluator_for(translation)
    system = next(iter(translation.systems.values()))
    relations = tuple(False for _ in evaluator.relations)
    candidates = tuple(k for k, r in enumerate(evaluator.relations) if not r.is_time_event)[:3]
    x = np.full(len(system.states), 0.3)
    for t in (0.0, 0.25, 0.5):
        each = [evaluator.distance_to_flip(system, relations, k)(t, x) for k in candidates]
        assert evaluator.distance_to_first_flip(system, relations, candidates)(t, x) == max(each)
