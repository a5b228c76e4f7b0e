"""Modelica.Blocks.Noise and the random numbers under it.

The generators are checked against a reimplementation here, from Vigna's
published xorshift algorithms, in numpy's wrapping uint64 arithmetic (the
library uses Python ints with explicit masks); the Modelica state is the
words' 32-bit halves.  The error functions and quantiles are checked against
scipy, and the blocks' outputs against the numbers drawn here, and against
values Dymola computed (the MSL reference of
Modelica.Blocks.Examples.Noise.UniformNoise).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.special
import scipy.stats

from acausal import Eq, Experiment, Model, Variable, der, simulate
from acausal.library.blocks import noise
from acausal.library.blocks.noise import (BandLimitedWhiteNoise, GlobalSeed, NormalNoise, TruncatedNormalNoise,
                                          UniformNoise)
from library_checks import check_declarations

U64 = np.uint64


# -- an independent xorshift suite --------------------------------------------------


def as_word(low: int, high: int) -> np.uint64:
    return U64((np.uint64(np.uint32(np.int64(high) & 0xFFFFFFFF)) << U64(32))
               | np.uint64(np.uint32(np.int64(low) & 0xFFFFFFFF)))


def as_halves(word: np.uint64) -> list[int]:
    low = int(np.uint64(word) & U64(0xFFFFFFFF))
    high = int(np.uint64(word) >> U64(32))
    return [int(np.int32(np.uint32(low).view(np.int32))), int(np.uint32(high).view(np.int32))]


def to_double(word: np.uint64) -> float:
    # the word read as int64, times 2^-64, plus 0.5
    return float(np.uint64(word).view(np.int64)) * 2.0 ** -64 + 0.5


def ref_xorshift64star(state):
    with np.errstate(over="ignore"):
        x = as_word(*state)
        x ^= x >> U64(12)
        x ^= x << U64(25)
        x ^= x >> U64(27)
        x = x * U64(2685821657736338717)
    return to_double(x), as_halves(x)


def ref_xorshift128plus(state):
    with np.errstate(over="ignore"):
        s1, s0 = as_word(state[0], state[1]), as_word(state[2], state[3])
        first = s0
        s1 ^= s1 << U64(23)
        second = (s1 ^ s0 ^ (s1 >> U64(17)) ^ (s0 >> U64(26))) + s0
    return to_double(second), as_halves(first) + as_halves(second)


def ref_xorshift1024star(state):
    words = [as_word(state[2 * i], state[2 * i + 1]) for i in range(16)]
    p = state[32] & 15
    with np.errstate(over="ignore"):
        s0 = words[p]
        p = (p + 1) & 15
        s1 = words[p]
        s1 ^= s1 << U64(31)
        s1 ^= s1 >> U64(11)
        s0 ^= s0 >> U64(30)
        words[p] = s0 ^ s1
        out = words[p] * U64(1181783497276652981)
    return to_double(out), [h for w in words for h in as_halves(w)] + [p]


def ref_seeded(local_seed, global_seed, n):
    """The MSL's seeding: xorshift64* from (local, global) stepped ten times, then pairs."""
    state = [126247697, global_seed] if local_seed == 0 and global_seed == 0 else [local_seed, global_seed]
    for _ in range(10):
        state = ref_xorshift64star(state)[1]
    out = list(state[:min(n, 2)])
    while len(out) + 2 <= n:
        out += ref_xorshift64star(out[-2:])[1]
    if len(out) < n:
        out.append(ref_xorshift64star(out[-2:])[1][0])
    return out


def draws(step, state, count):
    numbers = []
    for _ in range(count):
        r, state = step(state)
        numbers.append(r)
    return numbers, state


SEEDS = [(1, 67867967), (10, 67867967), (0, 0), (-5, 123), (2**31 - 1, -2**31), (614657, 30020)]


@pytest.mark.parametrize("local_seed, global_seed", SEEDS)
def test_initial_states_are_seeded_by_xorshift64star(local_seed, global_seed):
    assert noise.xorshift64star_initial_state(local_seed, global_seed) == ref_seeded(local_seed, global_seed, 2)
    assert noise.xorshift128plus_initial_state(local_seed, global_seed) == ref_seeded(local_seed, global_seed, 4)
    assert noise.xorshift1024star_initial_state(local_seed, global_seed) == ref_seeded(local_seed, global_seed, 33)
    for n in (1, 3, 5):
        assert noise.initial_state_with_xorshift64star(local_seed, global_seed, n) == \
            ref_seeded(local_seed, global_seed, n)


@pytest.mark.parametrize("ours, reference, seeding", [
    (noise.xorshift64star, ref_xorshift64star, noise.xorshift64star_initial_state),
    (noise.xorshift128plus, ref_xorshift128plus, noise.xorshift128plus_initial_state),
    (noise.xorshift1024star, ref_xorshift1024star, noise.xorshift1024star_initial_state),
])
@pytest.mark.parametrize("local_seed, global_seed", SEEDS[:4])
def test_generators_are_bit_exact(ours, reference, seeding, local_seed, global_seed):
    state = seeding(local_seed, global_seed)
    expected, expected_state = draws(reference, state, 300)
    got, got_state = draws(ours, state, 300)
    assert got == expected  # every bit of every double
    assert got_state == expected_state
    assert all(0 < r <= 1 for r in got)
    assert all(-2**31 <= s < 2**31 for s in got_state)


def test_uniform_numbers_have_the_moments_of_a_uniform_distribution():
    numbers = np.array(draws(noise.xorshift128plus, noise.xorshift128plus_initial_state(1, 2), 40000)[0])
    assert abs(numbers.mean() - 0.5) < 0.01
    assert abs(numbers.var() - 1 / 12) < 0.003


#: uniformNoise2.y of the MSL reference (Dymola) at 0, 0.03 and 0.05 s: seed 10, band -1 .. 3
DYMOLA_UNIFORM_NOISE2 = (0.20217088936010374, 0.045513176341681394, 0.48067223544814341)


def test_uniform_noise_numbers_are_dymolas():
    state = noise.xorshift128plus_initial_state(10, 67867967)
    r0 = noise.xorshift128plus(state)[0]
    numbers, _ = draws(noise.xorshift128plus, state, 3)
    band = [noise.uniform_quantile(r, -1, 3) for r in (r0, numbers[1], numbers[2])]
    assert band == list(DYMOLA_UNIFORM_NOISE2)


# -- hash, seeds, impure generator ---------------------------------------------------


def ref_hash(text: str) -> int:
    h = np.uint32(0xAAAAAAAA)
    with np.errstate(over="ignore"):
        for i, c in enumerate(text.encode()):
            c = np.uint32(c)
            if i % 2 == 0:
                h ^= (h << np.uint32(7)) ^ (c * (h >> np.uint32(3)))
            else:
                h ^= ~((h << np.uint32(11)) + (c ^ (h >> np.uint32(5))))
    return int(h.view(np.int32))


@pytest.mark.parametrize("text", ["", "a", "UniformNoise.uniformNoise1", "AutomaticSeed.automaticSeed3",
                                  "x" * 200, "Grüße.ü"])
def test_hash_string_is_uthash_hash_ap(text):
    assert noise.hash_string(text) == ref_hash(text)
    assert noise.automatic_local_seed(text) == ref_hash(text)


def test_automatic_global_seed_is_an_integer_of_the_time_and_process():
    seed = noise.automatic_global_seed()
    assert isinstance(seed, int) and -2**31 <= seed < 2**31


def test_impure_random_continues_xorshift1024star_from_its_seeding():
    ident = noise.initialize_impure_random(30020)
    state = ref_seeded(715827883, 30020, 33)
    expected, _ = draws(ref_xorshift1024star, state, 50)
    assert [noise.impure_random(ident) for _ in range(50)] == expected
    r = ref_xorshift1024star(draws(ref_xorshift1024star, state, 50)[1])[0]
    assert noise.impure_random_integer(ident, -1234, 2345) == min(2345, math.floor(r * 3580) - 1234)
    with pytest.raises(RuntimeError, match="not initialized"):
        noise.impure_random(ident + 1)


# -- error functions and quantiles ---------------------------------------------------

ARGUMENTS = np.concatenate([np.linspace(-6, 6, 241), [-1e-12, 1e-12, 0.0, 0.49999, 0.5, 1.49, 2.51, 4.6, 27, 29]])


def test_erf_and_erfc_against_scipy():
    for u in ARGUMENTS:
        assert noise.erf(u) == pytest.approx(scipy.special.erf(u), rel=1e-14, abs=1e-300)
        assert noise.erfc(u) == pytest.approx(scipy.special.erfc(u), rel=2e-13, abs=1e-300)


def test_erf_inv_and_erfc_inv_against_scipy():
    p = np.concatenate([np.linspace(-0.999, 0.999, 401), [1e-300, 1e-10, 0.3, 0.5, 0.75, 1 - 1e-6, 1 - 1e-10,
                                                           -(1 - 1e-15), 1 - 2**-52]])
    for u in p:
        assert noise.erf_inv(u) == pytest.approx(scipy.special.erfinv(u), rel=1e-14, abs=1e-300)
        assert noise.erfc_inv(1 - u) == pytest.approx(scipy.special.erfcinv(1 - u), rel=1e-13, abs=1e-300)
    for q in (1e-300, 1e-100, 1e-20, 1e-5):  # the tail pieces of erfcInv
        assert noise.erfc_inv(q) == pytest.approx(scipy.special.erfcinv(q), rel=1e-14)
    assert noise.erf_inv(1) == math.inf and noise.erf_inv(-1) == -math.inf and noise.erf_inv(0) == 0
    # the MSL's documented values
    assert noise.erf_inv(0.5) == pytest.approx(0.4769362762044699, rel=1e-15)
    assert noise.erf_inv(0.999999) == pytest.approx(3.458910737275499, rel=1e-15)
    with pytest.raises(ValueError):
        noise.erfc_inv(2.5)


UNIT = np.concatenate([np.linspace(1e-6, 1 - 1e-6, 199), [0.5, 0.025, 0.975]])


def test_quantiles_against_scipy_stats():
    for u in UNIT:
        # 2*u - 1 rounds: near the tails the quantile carries that round-off, as the MSL's does
        tight = 1e-13 if 0.01 < u < 0.99 else 1e-9
        assert noise.uniform_quantile(u, -1, 3) == pytest.approx(scipy.stats.uniform.ppf(u, -1, 4), rel=1e-14)
        assert noise.normal_quantile(u, 3, 0.5) == pytest.approx(scipy.stats.norm.ppf(u, 3, 0.5), rel=tight)
        assert noise.normal_cumulative(noise.normal_quantile(u, 3, 0.5), 3, 0.5) == pytest.approx(u, rel=1e-12)
        # TruncatedNormal: mu and sigma default to the middle and a sixth of the band
        a, b = (-1 - 1) / (4 / 6), (3 - 1) / (4 / 6)
        assert noise.truncated_normal_quantile(u, -1, 3) == pytest.approx(
            scipy.stats.truncnorm.ppf(u, a, b, loc=1, scale=4 / 6), rel=1e-10, abs=1e-12)
        assert noise.weibull_quantile(u, 3, 1.5) == pytest.approx(
            scipy.stats.weibull_min.ppf(u, 1.5, scale=3), rel=tight)
        lo, hi = scipy.stats.weibull_min.cdf([0.5, 4], 1.5, scale=3)
        assert noise.truncated_weibull_quantile(u, 0.5, 4, 3, 1.5) == pytest.approx(
            scipy.stats.weibull_min.ppf(lo + u * (hi - lo), 1.5, scale=3), rel=1e-12)
    assert noise.weibull_cumulative(-1, 3, 1.5) == 0
    # the band's ends, to round-off, and never outside it
    assert noise.truncated_normal_quantile(0.0, -1, 3) == pytest.approx(-1, abs=1e-14)
    assert noise.truncated_normal_quantile(1.0, -1, 3) == pytest.approx(3, abs=1e-14)
    assert all(-1 <= noise.truncated_normal_quantile(u, -1, 3) <= 3 for u in (0.0, 1e-300, 1 - 2**-53, 1.0))


# -- the blocks ----------------------------------------------------------------------

PERIOD = 0.1
#: the middle of each sample interval of a 1 s run
MIDDLES = np.arange(PERIOD / 2, 1.0, PERIOD)


def noise_numbers(local_seed, global_seed, count):
    """The raw numbers a noise block holds in its sample intervals (the sample at startTime
    repeats the number drawn at initialization)."""
    state = ref_seeded(local_seed, global_seed, 4)
    numbers, _ = draws(ref_xorshift128plus, state, count)
    return numbers


def held(result, name, times=MIDDLES):
    return np.interp(times, result.time, result[name])


def run(build, stop_time=1.0):
    class Harness(Model):
        experiment = Experiment(stop_time=stop_time, interval=PERIOD / 10)

        def build(self):
            build(self)

    result = simulate(Harness())
    assert result.success, result.message
    return result


def test_uniform_noise_holds_the_drawn_numbers_between_samples():
    def build(m):
        m.globalSeed = GlobalSeed(fixedSeed=4711)
        m.noise = UniformNoise(samplePeriod=PERIOD, y_min=-2, y_max=5, useAutomaticLocalSeed=False, fixedLocalSeed=3)

    result = run(build)
    expected = [r * 7 - 2 for r in noise_numbers(3, 4711, len(MIDDLES))]
    assert held(result, "noise.y").tolist() == expected  # bit for bit
    assert result["noise.y"][0] == expected[0]  # the initial number is the first sample's


def test_distributions_map_the_same_raw_numbers():
    def build(m):
        m.globalSeed = GlobalSeed()
        common = dict(samplePeriod=PERIOD, useAutomaticLocalSeed=False, fixedLocalSeed=7)
        m.normal = NormalNoise(mu=3, sigma=0.5, **common)
        m.truncated = TruncatedNormalNoise(y_min=-1, y_max=3, **common)
        m.white = BandLimitedWhiteNoise(noisePower=2, **common)

    result = run(build)
    raw = np.array(noise_numbers(7, 67867967, len(MIDDLES)))
    np.testing.assert_allclose(held(result, "normal.y"), scipy.stats.norm.ppf(raw, 3, 0.5), rtol=1e-9)
    a, b = (-1 - 1) / (4 / 6), (3 - 1) / (4 / 6)
    np.testing.assert_allclose(held(result, "truncated.y"), scipy.stats.truncnorm.ppf(raw, a, b, 1, 4 / 6),
                               rtol=1e-10)
    np.testing.assert_allclose(held(result, "white.y"), scipy.stats.norm.ppf(raw, 0, math.sqrt(2 / PERIOD)),
                               rtol=1e-9)


def test_start_time_y_off_and_the_switches():
    def build(m):
        m.globalSeed = GlobalSeed(fixedSeed=99)
        m.late = UniformNoise(samplePeriod=PERIOD, startTime=0.45, y_off=-7, useAutomaticLocalSeed=False)
        m.off = UniformNoise(samplePeriod=PERIOD, enableNoise=False, y_off=2.5)
        m.local = UniformNoise(samplePeriod=PERIOD, useGlobalSeed=False, useAutomaticLocalSeed=False,
                               fixedLocalSeed=5)
        m.named = UniformNoise(samplePeriod=PERIOD)

    result = run(build)
    late = held(result, "late.y")
    assert (late[MIDDLES < 0.45] == -7).all()
    # from 0.45 on it samples every period; its first sample repeats the initial draw
    first = noise_numbers(1, 99, 6)
    assert late[MIDDLES > 0.45].tolist() == first
    assert (result["off.y"] == 2.5).all()
    assert held(result, "local.y").tolist() == noise_numbers(5, 0, len(MIDDLES))
    # the automatic local seed: the hash of the instance name (model class name and path)
    assert held(result, "named.y").tolist() == noise_numbers(ref_hash("Harness.named"), 99, len(MIDDLES))


def test_global_switch_turns_every_block_off_and_a_missing_global_seed_takes_the_defaults():
    def build(m):
        m.globalSeed = GlobalSeed(enableNoise=False)
        m.noise = NormalNoise(samplePeriod=PERIOD, y_off=1.25)

    assert (run(build)["noise.y"] == 1.25).all()

    def build_without(m):
        m.noise = UniformNoise(samplePeriod=PERIOD, useAutomaticLocalSeed=False, fixedLocalSeed=10)

    result = run(build_without)
    assert held(result, "noise.y").tolist() == noise_numbers(10, 67867967, len(MIDDLES))


def test_a_nested_block_finds_the_global_seed_of_an_enclosing_model():
    class Sensor(Model):
        def build(self):
            self.noise = UniformNoise(samplePeriod=PERIOD, useAutomaticLocalSeed=False, fixedLocalSeed=2)

    def build(m):
        m.globalSeed = GlobalSeed(fixedSeed=-31)
        m.sensor = Sensor()

    assert held(run(build), "sensor.noise.y").tolist() == noise_numbers(2, -31, len(MIDDLES))


@pytest.mark.parametrize("make", [UniformNoise, NormalNoise, TruncatedNormalNoise, BandLimitedWhiteNoise,
                                  lambda: UniformNoise(enableNoise=False)])
def test_declarations(make):
    check_declarations(make())


def test_continuous_initial_equations_see_the_first_draw():
    # Modelica solves r and r_raw with the initial equations: a value fixed at
    # initialization from the noise output holds the first number, not the start 0
    class Holder(Model):
        x = Variable(description="Holds the noise output of the start")

        def build(self):
            self.globalSeed = GlobalSeed()
            self.noise = TruncatedNormalNoise(samplePeriod=PERIOD, useAutomaticLocalSeed=False, fixedLocalSeed=4)

        def equations(self):
            return [Eq(der(self.x), 0)]

        def initial_equations(self):
            return [Eq(self.x, self.noise.y)]

    result = simulate(Holder(), stop_time=0.3)
    first = noise.truncated_normal_quantile(noise_numbers(4, 67867967, 1)[0])
    assert result["x"][0] == result["x"][-1] == first


def test_an_automatic_global_seed_draws_valid_noise():
    def build(m):
        m.globalSeed = GlobalSeed(useAutomaticSeed=True)
        m.noise = UniformNoise(samplePeriod=PERIOD, y_min=2, y_max=3)

    values = held(run(build), "noise.y")
    assert ((values > 2) & (values <= 3)).all() and len(set(values.tolist())) == len(values)
