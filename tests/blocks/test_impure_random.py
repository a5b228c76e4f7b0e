"""Impure functions in equations: Modelica.Math.Random.Utilities.impureRandom and the
ImpureRandom block (Modelica.Blocks.Examples.Noise.Utilities.ImpureRandom).

The numbers are checked against xorshift1024* written here again from Vigna's
published algorithm in numpy's wrapping uint64 arithmetic, seeded as the MSL's
``initializeImpureRandom`` seeds it (xorshift64* from the local seed 715827883
and the global seed, ``initialStateWithXorshift64star``).  The semantics (one
value per firing, in the order of the events; the state belongs to the run) are
checked with a counter whose every call is visible, and by counting draws
against the firings of the when-clauses.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from acausal import Eq, Experiment, Model, Variable, der, simulate, translate
from acausal.errors import EquationError
from acausal.functions import ImpureFunction
from acausal.hybrid import When, sample
from acausal.language import Integer, initial
from acausal.library.blocks import noise
from acausal.library.blocks.noise import GlobalSeed, ImpureRandom, ImpureRandomInteger, ImpureRandomNumber
from acausal.runtime.events import evaluator_for
from library_checks import check_declarations

U64 = np.uint64
LOCAL_SEED = 715827883  # initializeImpureRandom's constant local seed (its id)


# -- an independent xorshift64* / xorshift1024* ----------------------------------------------


def _word(low: int, high: int) -> np.uint64:
    return (U64(high & 0xFFFFFFFF) << U64(32)) | U64(low & 0xFFFFFFFF)


def _halves(word: np.uint64) -> tuple[int, int]:
    low, high = int(word & U64(0xFFFFFFFF)), int(word >> U64(32))
    return tuple(v - (1 << 32) if v >= 1 << 31 else v for v in (low, high))


def _xorshift64star(low: int, high: int) -> tuple[int, int]:
    with np.errstate(over="ignore"):
        x = _word(low, high)
        x ^= x >> U64(12)
        x ^= x << U64(25)
        x ^= x >> U64(27)
        x = x * U64(2685821657736338717)
    return _halves(x)


def reference_numbers(seed: int, n: int) -> list[float]:
    """The first ``n`` numbers of impureRandom after ``initializeImpureRandom(seed)``."""
    pair = (LOCAL_SEED, seed)
    for _ in range(10):  # Xorshift64star.initialState: ten steps from (localSeed, globalSeed)
        pair = _xorshift64star(*pair)
    ints = list(pair)
    for _ in range(15):  # each further pair: one step from the pair before
        ints += _xorshift64star(*ints[-2:])
    ints.append(_xorshift64star(*ints[-2:])[0])  # the 33rd: the low half of one more step
    s = [_word(ints[2 * i], ints[2 * i + 1]) for i in range(16)]
    p = ints[32] & 15
    out = []
    with np.errstate(over="ignore"):
        for _ in range(n):
            s0 = s[p]
            p = (p + 1) & 15
            s1 = s[p]
            s1 ^= s1 << U64(31)
            s1 ^= s1 >> U64(11)
            s0 ^= s0 >> U64(30)
            s[p] = s0 ^ s1
            word = s[p] * U64(1181783497276652981)
            out.append(float(word.view(np.int64)) * 2.0 ** -64 + 0.5)
    return out


def after_events(result, name: str, times) -> list[float]:
    """The value of ``name`` in the last row at each of ``times`` (after the event)."""
    column = result[name]
    out = []
    for t in times:
        rows = np.flatnonzero(np.isclose(result.time, t, rtol=0, atol=1e-12))
        assert rows.size, f"no row at t = {t}"
        out.append(float(column[rows[-1]]))
    return out


# -- models ------------------------------------------------------------------------------------


class ImpureGenerator(Model):
    """Modelica.Blocks.Examples.Noise.ImpureGenerator (shorter)."""

    modelica_class = "Modelica.Blocks.Examples.Noise.ImpureGenerator"
    experiment = Experiment(stop_time=0.5, interval=0.01)

    def build(self):
        self.globalSeed = GlobalSeed(useAutomaticSeed=False, fixedSeed=4711)
        self.impureRandom = ImpureRandom(samplePeriod=0.01)


class Counter(ImpureFunction):
    """Counts its own calls (the state of the run): 1, 2, 3, ..."""

    nargs = 0
    stream = "test.counter"

    @classmethod
    def _impure_(cls, state: dict) -> int:
        state["n"] = state.get("n", 0) + 1
        return state["n"]


class CountedFirings(Model):
    """A when-clause on a clock and one on a continuous relation, each counting; a discrete
    Integer that reads the count makes event iteration run several passes."""

    experiment = Experiment(stop_time=1.1, interval=0.1)
    x = Variable(start=0.0, fixed=True)
    n = Integer(start=0, fixed=True)
    m = Integer(start=0, fixed=True)
    twice = Integer(start=0)

    def equations(self):
        return [Eq(der(self.x), 1.0),
                When([initial(), sample(0.25, 0.25)], Eq(self.n, Counter())),
                When(self.x > 0.6, Eq(self.m, Counter())),
                Eq(self.twice, 2 * self.n)]


# -- the numbers -------------------------------------------------------------------------------


def test_the_block_sampled_at_its_period_gives_xorshift1024star_from_the_seed():
    result = simulate(ImpureGenerator())
    times = [0.01 * k for k in range(51)]  # initial() and sample(0.01, 0.01) up to the stop time
    drawn = after_events(result, "impureRandom.y", times)
    assert drawn == reference_numbers(4711, len(times))
    # held between the samples
    mid = result.at([0.005, 0.255], "impureRandom.y")
    assert list(np.ravel(mid)) == [drawn[0], drawn[25]]


def test_the_plain_functions_continue_the_same_sequence():
    ident = noise.initialize_impure_random(4711)
    assert ident == LOCAL_SEED
    assert [noise.impure_random(ident) for _ in range(20)] == reference_numbers(4711, 20)


def test_two_runs_give_identical_outputs_and_leave_the_plain_generator_alone():
    ident = noise.initialize_impure_random(99)
    first_plain = noise.impure_random(ident)
    translation = translate(ImpureGenerator())
    one = simulate(translation)
    two = simulate(translation)
    three = simulate(ImpureGenerator())
    assert np.array_equal(one["impureRandom.y"], two["impureRandom.y"])
    assert np.array_equal(one["impureRandom.y"], three["impureRandom.y"])
    # the runs' generator is theirs: the module's own continues where it was
    assert noise.impure_random(ident) == reference_numbers(99, 2)[1] != first_plain


def test_the_global_seed_changes_the_numbers():
    class OtherSeed(ImpureGenerator):
        def build(self):
            self.globalSeed = GlobalSeed(fixedSeed=30020)
            self.impureRandom = ImpureRandom(samplePeriod=0.1)

    result = simulate(OtherSeed())
    times = [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]
    assert after_events(result, "impureRandom.y", times) == reference_numbers(30020, len(times))


def test_without_a_global_seed_the_default_seed_is_used():
    class Alone(Model):
        experiment = Experiment(stop_time=0.35, interval=0.1)

        def build(self):
            self.impureRandom = ImpureRandom(samplePeriod=0.1)

    result = simulate(Alone())
    assert after_events(result, "impureRandom.y", [0.0, 0.1, 0.2, 0.3]) == reference_numbers(67867967, 4)


def test_two_blocks_and_the_integer_function_share_one_generator_in_the_order_of_events():
    class Shared(Model):
        experiment = Experiment(stop_time=0.45, interval=0.05)
        k = Integer(start=0, fixed=True)

        def build(self):
            self.globalSeed = GlobalSeed(fixedSeed=12345)
            self.a = ImpureRandom(samplePeriod=0.1)  # t = 0 (initial), 0.1, 0.2, ...

        def equations(self):
            seed = self.globalSeed
            # at 0.05, 0.15, ...: between the block's draws
            return [When(sample(0.05, 0.1), Eq(self.k, ImpureRandomInteger(seed.id_impure, seed.seed, -3, 7)))]

    result = simulate(Shared())
    numbers = reference_numbers(12345, 9)
    # the order of firings: a at 0 (initialization), k at 0.05, a at 0.1, k at 0.15, ...
    assert after_events(result, "a.y", [0.0, 0.1, 0.2, 0.3, 0.4]) == numbers[0::2]
    expected_k = [min(7, math.floor(r * 11) - 3) for r in numbers[1::2]]
    assert after_events(result, "k", [0.05, 0.15, 0.25, 0.35]) == expected_k


# -- the semantics -----------------------------------------------------------------------------


def test_an_event_iteration_with_several_passes_advances_the_generator_once():
    translation = translate(ImpureGenerator())
    result = simulate(translation)
    samples = [e for e in result.events if e.kind == "time"]
    assert len(samples) == 50
    # the discrete equations are evaluated in several passes at each sample...
    assert all(e.iterations > 1 for e in samples)
    # ...and the generator advanced once per firing: initial() and 50 samples
    assert evaluator_for(translation).impure.calls == 51
    assert after_events(result, "impureRandom.y", [0.5])[0] == reference_numbers(4711, 51)[-1]


def test_a_counter_counts_firings_not_evaluations():
    translation = translate(CountedFirings())
    result = simulate(translation)
    # the clock's clause fires at initialization (1), 0.25 (2) and 0.5 (3); the relation's at
    # 0.6 (4); the clock's again at 0.75 (5) and 1.0 (6)
    assert after_events(result, "n", [0.0, 0.25, 0.5, 0.75, 1.0]) == [1, 2, 3, 5, 6]
    assert after_events(result, "twice", [0.0, 0.25, 0.5, 0.75, 1.0]) == [2, 4, 6, 10, 12]
    state_event = [e for e in result.events if e.kind not in ("time", "initial")]
    assert len(state_event) == 1 and abs(state_event[0].time - 0.6) < 1e-9
    assert after_events(result, "m", [state_event[0].time]) == [4]
    assert max(e.iterations for e in result.events) > 1
    evaluator = evaluator_for(translation)
    assert evaluator.impure.calls == 6
    assert evaluator.impure.streams == {"test.counter": {"n": 6}}
    # a second run starts from an empty state again
    again = simulate(translation)
    assert np.array_equal(again["n"], result["n"]) and np.array_equal(again["m"], result["m"])


def test_outside_event_iteration_a_call_does_not_move_the_state():
    translation = translate(CountedFirings())
    simulate(translation)
    evaluator = evaluator_for(translation)
    evaluator.start_run()
    site = 0
    # no event iteration open: the value the next call would give, twice, state unchanged
    assert evaluator._impure_call(site, Counter) == 1
    assert evaluator._impure_call(site, Counter) == 1
    assert evaluator.impure.streams.get("test.counter", {}) == {}
    evaluator.open_instant()
    assert [evaluator._impure_call(site, Counter) for _ in range(3)] == [1, 1, 1]
    assert evaluator._impure_call(site + 1, Counter) == 2  # another call site draws its own
    evaluator.close_instant()
    evaluator.open_instant()
    assert evaluator._impure_call(site, Counter) == 3  # the next event: a new value
    evaluator.close_instant()
    assert evaluator.impure.calls == 3


def test_an_impure_function_applied_to_numbers_stays_a_call():
    call = ImpureRandomNumber(LOCAL_SEED, 4711)
    assert isinstance(call, ImpureRandomNumber)
    x = sp.Symbol("x")
    with pytest.raises(TypeError, match="no derivative"):
        ImpureRandomNumber(x, 4711).diff(x)


def test_an_impure_function_in_a_continuous_equation_is_refused():
    class Continuous(Model):
        experiment = Experiment(stop_time=0.1, interval=0.05)
        y = Variable()

        def equations(self):
            return [Eq(self.y, ImpureRandomNumber(LOCAL_SEED, 1))]

    with pytest.raises(EquationError, match="impure function ImpureRandomNumber is called in a continuous"):
        translate(Continuous())


def test_a_wrong_id_is_refused_as_the_c_code_refuses_it():
    with pytest.raises(RuntimeError, match="initializeImpureRandom"):
        ImpureRandomNumber._impure_({}, 1, 4711)


def test_the_block_declarations():
    check_declarations(ImpureRandom(samplePeriod=0.1))
