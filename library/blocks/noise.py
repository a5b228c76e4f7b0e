"""Reproducible noise from pseudo-random numbers (Modelica.Blocks.Noise).

The blocks draw a uniform random number in ``(0, 1]`` at every sample instant
``startTime + i*samplePeriod`` (time events, the first at ``startTime``
itself) and map it through the quantile of a distribution; between samples
the output holds.  As in the MSL they use the xorshift128+ generator, whose
state (four 32-bit Integers, the halves of two 64-bit words) every block
holds in discrete Integer variables ``state[1..4]``, set at initialization
from a local and a global seed and advanced in a when-clause.  The
generators and the distributions are computed here bit for bit as
``ModelicaRandom.c`` and the Modelica functions of ``Modelica.Math.Random``,
``Modelica.Math.Distributions`` and ``Modelica.Math.Special`` compute them, so
the noise is the one Dymola and OpenModelica draw for the same seeds.

**The global seed.**  Modelica finds the ``inner`` :class:`GlobalSeed` by the
name ``globalSeed`` in the enclosing instances (``outer``); acausal does the
same: a noise block reads the parameters of the nearest component named
``globalSeed`` on the path from its parent up to the model.  Where there is
none, the block uses the defaults of a GlobalSeed (fixed seed 67867967, noise
enabled), as a Modelica tool adds a default inner one.  Import it from this
module (``from acausal.library.blocks.noise import GlobalSeed``): it has
parameters only, so the package does not export it with the blocks.

**Seeds.**  ``useAutomaticLocalSeed`` (the default) seeds a block with the
hash of its instance name, Modelica's ``getInstanceName()``: the model's
class name (the last part of its ``modelica_class``, else its Python class
name) and the block's dotted path.  Renaming a block changes its noise;
``useAutomaticLocalSeed=False`` with ``fixedLocalSeed`` keeps it.

Boolean parameters (``enableNoise``, ``useGlobalSeed``,
``useAutomaticLocalSeed``, ``useAutomaticSeed``) are structural: they decide
the equations.

The numeric functions (generators, seeds, distributions, error functions)
are plain Python functions of this module, usable on their own.

**The impure generator.**  :func:`initialize_impure_random`,
:func:`impure_random` and :func:`impure_random_integer` are the plain
functions, with one hidden state in this module as ``ModelicaRandom.c`` keeps
it.  In equations, :class:`ImpureRandomNumber` and :class:`ImpureRandomInteger`
are the same functions with the state of the run
(:class:`acausal.functions.ImpureFunction`): called in a when-clause they
draw once per firing, in the order of the events, and every run starts from
the seed again.  :class:`ImpureRandom` is the MSL's example block that uses
them.
"""

from __future__ import annotations

import datetime
import math
import os
from typing import Any, Sequence

import sympy as sp

from acausal.components.blocks import SO
from acausal.components.declarations import DerivedDefaults
from acausal.functions import ImpureFunction
from acausal.hybrid import When, sample
from acausal.language import Component, Eq, If, Integer, Parameter, Variable, initial, pre, time

__all__ = [
    "GlobalSeed",
    "PartialNoise",
    "UniformNoise",
    "NormalNoise",
    "TruncatedNormalNoise",
    "BandLimitedWhiteNoise",
    "xorshift64star",
    "xorshift64star_initial_state",
    "xorshift128plus",
    "xorshift128plus_initial_state",
    "xorshift1024star",
    "xorshift1024star_initial_state",
    "initial_state_with_xorshift64star",
    "automatic_global_seed",
    "automatic_local_seed",
    "hash_string",
    "initialize_impure_random",
    "impure_random",
    "impure_random_integer",
    "ImpureRandomNumber",
    "ImpureRandomInteger",
    "ImpureRandom",
    "erf",
    "erfc",
    "erf_inv",
    "erfc_inv",
    "uniform_quantile",
    "normal_cumulative",
    "normal_quantile",
    "truncated_normal_quantile",
    "weibull_cumulative",
    "weibull_quantile",
    "truncated_weibull_quantile",
]

# --------------------------------------------------------------------------
# 64-bit words and their Modelica form (Integer halves)
# --------------------------------------------------------------------------

_MASK64 = (1 << 64) - 1
_MASK32 = (1 << 32) - 1

#: 2^-64: maps a signed 64-bit integer into [-0.5, 0.5)
_INVM64 = 2.0 ** -64


def _word(low: int, high: int) -> int:
    """The unsigned 64-bit word whose low and high 32-bit halves are ``low`` and ``high``.

    ``ModelicaRandom.c`` overlays two ``int32_t`` on one ``uint64_t`` (a
    union); on the little-endian machines it runs on, the first Integer is
    the low half.
    """
    return ((int(high) & _MASK32) << 32) | (int(low) & _MASK32)


def _signed32(value: int) -> int:
    value &= _MASK32
    return value - (1 << 32) if value >= 1 << 31 else value


def _halves(word: int) -> list[int]:
    """The two signed 32-bit Integers (low half first) of a 64-bit word."""
    return [_signed32(word), _signed32(word >> 32)]


def _unit_interval(word: int) -> float:
    """A 64-bit word as a double in ``(0, 1]``: the word read as a signed integer,
    times 2^-64, plus 0.5 (``ModelicaRandom_RAND``, after Doornik's randomdouble)."""
    signed = word - (1 << 64) if word >> 63 else word
    return float(signed) * _INVM64 + 0.5


# --------------------------------------------------------------------------
# generators (Modelica.Math.Random.Generators)
# --------------------------------------------------------------------------


def xorshift64star(state: Sequence[int]) -> tuple[float, list[int]]:
    """One step of xorshift64*: ``(r, stateOut)`` from ``stateIn`` (two Integers).

    The MSL's ``Generators.Xorshift64star.random``: ``r`` is uniform in
    ``(0, 1]``, the state is one 64-bit word as two signed 32-bit halves.
    """
    x = _word(state[0], state[1])
    x ^= x >> 12
    x ^= (x << 25) & _MASK64
    x ^= x >> 27
    x = (x * 2685821657736338717) & _MASK64
    return _unit_interval(x), _halves(x)


def xorshift64star_initial_state(localSeed: int, globalSeed: int) -> list[int]:  # noqa: N803 - MSL names
    """The initial state of xorshift64* for a local and a global seed
    (``Generators.Xorshift64star.initialState``).

    The seeds are the two halves of the word (a fixed prime replaces a local
    seed of 0 when the global seed is 0 too); ten steps then give a good state
    even from a bad seed such as 1.
    """
    state = [126247697, int(globalSeed)] if localSeed == 0 and globalSeed == 0 else [int(localSeed), int(globalSeed)]
    for _ in range(10):
        _r, state = xorshift64star(state)
    return state


def initial_state_with_xorshift64star(localSeed: int, globalSeed: int,  # noqa: N803
                                      nState: int) -> list[int]:  # noqa: N803
    """A state vector of ``nState`` Integers filled by xorshift64*
    (``Random.Utilities.initialStateWithXorshift64star``).

    The first two are xorshift64*'s initial state; each further pair is the
    next state of the pair before it, and an odd last element the low half of
    the step after that.
    """
    if nState < 1:
        raise ValueError(f"initial_state_with_xorshift64star: nState = {nState} must be at least 1")
    aux = xorshift64star_initial_state(localSeed, globalSeed)
    state = [0] * nState
    state[:2] = aux[:min(nState, 2)]
    even = 2 * (nState // 2)
    for i in range(2, even, 2):
        _r, aux = xorshift64star(state[i - 2:i])
        state[i:i + 2] = aux
    if nState >= 3 and nState != even:
        _r, aux = xorshift64star(state[nState - 3:nState - 1])
        state[nState - 1] = aux[0]
    return state


def xorshift128plus(state: Sequence[int]) -> tuple[float, list[int]]:
    """One step of xorshift128+: ``(r, stateOut)`` from ``stateIn`` (four Integers)
    (``Generators.Xorshift128plus.random``)."""
    s1 = _word(state[0], state[1])
    s0 = _word(state[2], state[3])
    s1 ^= (s1 << 23) & _MASK64
    second = ((s1 ^ s0 ^ (s1 >> 17) ^ (s0 >> 26)) + s0) & _MASK64
    return _unit_interval(second), _halves(s0) + _halves(second)


def xorshift128plus_initial_state(localSeed: int, globalSeed: int) -> list[int]:  # noqa: N803
    """The initial state of xorshift128+ (``Generators.Xorshift128plus.initialState``)."""
    return initial_state_with_xorshift64star(localSeed, globalSeed, 4)


def _xorshift1024star_step(words: list[int], p: int) -> tuple[float, int]:
    """xorshift1024* on sixteen 64-bit words in place: the number and the new index."""
    p &= 15
    s0 = words[p]
    p = (p + 1) & 15
    s1 = words[p]
    s1 ^= (s1 << 31) & _MASK64
    s1 ^= s1 >> 11
    s0 ^= s0 >> 30
    words[p] = s0 ^ s1
    return _unit_interval((words[p] * 1181783497276652981) & _MASK64), p


def xorshift1024star(state: Sequence[int]) -> tuple[float, list[int]]:
    """One step of xorshift1024*: ``(r, stateOut)`` from ``stateIn`` (33 Integers: sixteen
    words as halves, then the index) (``Generators.Xorshift1024star.random``)."""
    words = [_word(state[2 * i], state[2 * i + 1]) for i in range(16)]
    r, p = _xorshift1024star_step(words, int(state[32]))
    out = [half for w in words for half in _halves(w)]
    return r, out + [p]


def xorshift1024star_initial_state(localSeed: int, globalSeed: int) -> list[int]:  # noqa: N803
    """The initial state of xorshift1024* (``Generators.Xorshift1024star.initialState``)."""
    return initial_state_with_xorshift64star(localSeed, globalSeed, 33)


# --------------------------------------------------------------------------
# seeds and the impure generator (Modelica.Math.Random.Utilities)
# --------------------------------------------------------------------------


def hash_string(text: str) -> int:
    """The Integer hash of a string (``Modelica.Utilities.Strings.hashString``).

    ``ModelicaStrings_hashString``: uthash's HASH_AP (Arash Partow's hash) over
    the string's bytes (UTF-8) in 32-bit unsigned arithmetic, read as a signed
    Integer.
    """
    h = 0xAAAAAAAA
    for i, byte in enumerate(text.encode("utf-8")):
        if i % 2 == 0:
            h ^= ((h << 7) ^ (byte * (h >> 3))) & _MASK32
        else:
            h ^= ~((h << 11) + (byte ^ (h >> 5))) & _MASK32
        h &= _MASK32
    return _signed32(h)


def automatic_local_seed(path: str) -> int:
    """A local seed from an instance name (``Random.Utilities.automaticLocalSeed``)."""
    return hash_string(path)


def automatic_global_seed() -> int:
    """A seed from the local time and the process id (``Random.Utilities.automaticGlobalSeed``):
    ``1 + ms + 1000*s + 60000*min + 3600000*h + 6007*pid``.  Impure: a new value at each call."""
    now = datetime.datetime.now()
    seed = (1 + now.microsecond // 1000 + 1000 * now.second + 1000 * 60 * now.minute
            + 1000 * 60 * 60 * now.hour + 6007 * os.getpid())
    return _signed32(seed)  # C's int arithmetic wraps


#: The impure generator's hidden state (``ModelicaRandom_s``, ``_p``, ``_id``): sixteen words,
#: the index and the id initialize_impure_random() returned.
_IMPURE: dict[str, Any] = {"words": [0] * 16, "p": 0, "id": 0}


def initialize_impure_random(seed: int) -> int:
    """Set the state of the impure generator from ``seed`` and return its id
    (``Random.Utilities.initializeImpureRandom``): xorshift1024* seeded by
    xorshift64* with the local seed 715827883."""
    local_seed = 715827883
    state = initial_state_with_xorshift64star(local_seed, int(seed), 33)
    _IMPURE["words"] = [_word(state[2 * i], state[2 * i + 1]) for i in range(16)]
    _IMPURE["p"] = state[32]
    _IMPURE["id"] = local_seed
    return local_seed


def impure_random(id: int) -> float:  # noqa: A002 - the MSL's name
    """The next number in ``(0, 1]`` of the impure generator (``Random.Utilities.impureRandom``).

    Raises
    ------
    RuntimeError
        When ``id`` is not the one :func:`initialize_impure_random` returned.
    """
    if int(id) != _IMPURE["id"]:
        raise RuntimeError("impure_random: not initialized with initialize_impure_random")
    r, _IMPURE["p"] = _xorshift1024star_step(_IMPURE["words"], _IMPURE["p"])
    return r


def impure_random_integer(id: int, imin: int = 1, imax: int = 268435456) -> int:  # noqa: A002
    """An Integer uniform in ``[imin, imax]`` from the impure generator
    (``Random.Utilities.impureRandomInteger``)."""
    r = impure_random(id)
    return min(int(imax), int(math.floor(r * (imax - imin + 1))) + int(imin))


# --------------------------------------------------------------------------
# error functions (Modelica.Math.Special: Boost's 53-bit rational approximations)
# --------------------------------------------------------------------------


def _poly(coefficients: Sequence[float], u: float) -> float:
    """``c[0] + u*(c[1] + u*(c[2] + ...))`` by Horner's rule (``Special.Internal.polyEval``)."""
    y = coefficients[-1]
    for c in reversed(coefficients[:-1]):
        y = c + u * y
    return y


_ERF_Y = 1.044948577880859375
_ERF_P = (0.0834305892146531832907, -0.338165134459360935041, -0.0509990735146777432841,
          -0.00772758345802133288487, -0.000322780120964605683831)
_ERF_Q = (1.0, 0.455004033050794024546, 0.0875222600142252549554, 0.00858571925074406212772,
          0.000370900071787748000569)

#: erfc(z) for z >= 0.5, by interval: (upper end, y, P, Q, shift); the last in 1/z
_ERFC_PIECES = (
    (1.5, 0.405935764312744140625,
     (-0.098090592216281240205, 0.178114665841120341155, 0.191003695796775433986, 0.0888900368967884466578,
      0.0195049001251218801359, 0.00180424538297014223957),
     (1.0, 1.84759070983002217845, 1.42628004845511324508, 0.578052804889902404909, 0.12385097467900864233,
      0.0113385233577001411017, 0.337511472483094676155e-5), 0.5),
    (2.5, 0.50672817230224609375,
     (-0.0243500476207698441272, 0.0386540375035707201728, 0.04394818964209516296, 0.0175679436311802092299,
      0.00323962406290842133584, 0.000235839115596880717416),
     (1.0, 1.53991494948552447182, 0.982403709157920235114, 0.325732924782444448493, 0.0563921837420478160373,
      0.00410369723978904575884), 1.5),
    (4.5, 0.5405750274658203125,
     (0.00295276716530971662634, 0.0137384425896355332126, 0.00840807615555585383007, 0.00212825620914618649141,
      0.000250269961544794627958, 0.113212406648847561139e-4),
     (1.0, 1.04217814166938418171, 0.442597659481563127003, 0.0958492726301061423444, 0.0105982906484876531489,
      0.000479411269521714493907), 3.5),
)
_ERFC_TAIL = (0.5579090118408203125,
              (0.00628057170626964891937, 0.0175389834052493308818, -0.212652252872804219852,
               -0.687717681153649930619, -2.5518551727311523996, -3.22729451764143718517, -2.8175401114513378771),
              (1.0, 2.79257750980575282228, 11.0567237927800161565, 15.930646027911794143, 22.9367376522880577224,
               13.5064170191802889145, 5.48409182238641741584))


def _erfc_large(z: float) -> float:
    """erfc(z) for ``z >= 0.5`` (``Special.Internal.erfcUtil``)."""
    for upper, y0, p, q, shift in _ERFC_PIECES:
        if z < upper:
            y = y0 + _poly(p, z - shift) / _poly(q, z - shift)
            break
    else:
        y0, p, q = _ERFC_TAIL
        y = y0 + _poly(p, 1 / z) / _poly(q, 1 / z)
    return y * (math.exp(-z * z) / z)


def erf(u: float) -> float:
    """The error function ``2/sqrt(pi) * integral_0^u exp(-t^2) dt`` (``Modelica.Math.Special.erf``)."""
    z = abs(u)
    if z < 0.5:
        if z <= 0:
            y = 0.0
        elif z < 1.0e-10:
            y = z * 1.125 + z * 0.003379167095512573896158903121545171688
        else:
            zz = z * z
            y = z * (_ERF_Y + _poly(_ERF_P, zz) / _poly(_ERF_Q, zz))
    elif z < 5.8:
        y = 1 - _erfc_large(z)
    else:
        y = 1.0
    return -y if u < 0 else y


def erfc(u: float) -> float:
    """The complementary error function ``1 - erf(u)`` (``Modelica.Math.Special.erfc``)."""
    if u < 0:
        if u < -0.5:
            return 2 - _erfc_large(-u) if u > -28 else 2.0
        return 1 + erf(-u)
    if u < 0.5:
        return 1 - erf(u)
    return _erfc_large(u) if u < 28 else 0.0


_INV_SMALL = (0.0891314744949340820313,
              (-0.000508781949658280665617, -0.00836874819741736770379, 0.0334806625409744615033,
               -0.0126926147662974029034, -0.0365637971411762664006, 0.0219878681111168899165,
               0.00822687874676915743155, -0.00538772965071242932965),
              (1.0, -0.970005043303290640362, -1.56574558234175846809, 1.56221558398423026363,
               0.662328840472002992063, -0.71228902341542847553, -0.0527396382340099713954,
               0.0795283687341571680018, -0.00233393759374190016776, 0.000886216390456424707504))
_INV_MIDDLE = (2.249481201171875,
               (-0.202433508355938759655, 0.105264680699391713268, 8.37050328343119927838, 17.6447298408374015486,
                -18.8510648058714251895, -44.6382324441786960818, 17.445385985570866523, 21.1294655448340526258,
                -3.67192254707729348546),
               (1.0, 6.24264124854247537712, 3.9713437953343869095, -28.6608180499800029974,
                -20.1432634680485188801, 48.5609213108739935468, 10.8268667355460159008, -22.6436933413139721736,
                1.72114765761200282724))
#: the tail, in x = sqrt(-log(q)), by interval: (upper end of x, shift, y, P, Q)
_INV_TAIL = (
    (3.0, 1.125, 0.807220458984375,
     (-0.131102781679951906451, -0.163794047193317060787, 0.117030156341995252019, 0.387079738972604337464,
      0.337785538912035898924, 0.142869534408157156766, 0.0290157910005329060432, 0.00214558995388805277169,
      -0.679465575181126350155e-6, 0.285225331782217055858e-7, -0.681149956853776992068e-9),
     (1.0, 3.46625407242567245975, 5.38168345707006855425, 4.77846592945843778382, 2.59301921623620271374,
      0.848854343457902036425, 0.152264338295331783612, 0.01105924229346489121)),
    (6.0, 3.0, 0.93995571136474609375,
     (-0.0350353787183177984712, -0.00222426529213447927281, 0.0185573306514231072324, 0.00950804701325919603619,
      0.00187123492819559223345, 0.000157544617424960554631, 0.460469890584317994083e-5,
      -0.230404776911882601748e-9, 0.266339227425782031962e-11),
     (1.0, 1.3653349817554063097, 0.762059164553623404043, 0.220091105764131249824, 0.0341589143670947727934,
      0.00263861676657015992959, 0.764675292302794483503e-4)),
    (18.0, 6.0, 0.98362827301025390625,
     (-0.0167431005076633737133, -0.00112951438745580278863, 0.00105628862152492910091,
      0.000209386317487588078668, 0.149624783758342370182e-4, 0.449696789927706453732e-6,
      0.462596163522878599135e-8, -0.281128735628831791805e-13, 0.99055709973310326855e-16),
     (1.0, 0.591429344886417493481, 0.138151865749083321638, 0.0160746087093676504695,
      0.000964011807005165528527, 0.275335474764726041141e-4, 0.282243172016108031869e-6)),
    (44.0, 18.0, 0.99714565277099609375,
     (-0.0024978212791898131227, -0.779190719229053954292e-5, 0.254723037413027451751e-4,
      0.162397777342510920873e-5, 0.396341011304801168516e-7, 0.411632831190944208473e-9,
      0.145596286718675035587e-11, -0.116765012397184275695e-17),
     (1.0, 0.207123112214422517181, 0.0169410838120975906478, 0.000690538265622684595676,
      0.145007359818232637924e-4, 0.144437756628144157666e-6, 0.509761276599778486139e-9)),
    (math.inf, 44.0, 0.99941349029541015625,
     (-0.000539042911019078575891, -0.28398759004727721098e-6, 0.899465114892291446442e-6,
      0.229345859265920864296e-7, 0.225561444863500149219e-9, 0.947846627503022684216e-12,
      0.135880130108924861008e-14, -0.348890393399948882918e-21),
     (1.0, 0.0845746234001899436914, 0.00282092984726264681981, 0.468292921940894236786e-4,
      0.399968812193862100054e-6, 0.161809290887904476097e-8, 0.231558608310259605225e-11)),
)


def _erf_inv_core(p: float, q: float) -> float:
    """erfInv of ``p`` given ``q = 1 - p`` computed apart (``Special.Internal.erfInvUtil``)."""
    if p <= 0.5:
        g = p * (p + 10)
        y0, pp, qq = _INV_SMALL
        r = _poly(pp, p) / _poly(qq, p)
        return g * y0 + g * r
    if q >= 0.25:
        g = math.sqrt(-2 * math.log(q))
        xs = q - 0.25
        y0, pp, qq = _INV_MIDDLE
        r = _poly(pp, xs) / _poly(qq, xs)
        return g / (y0 + r)
    x = math.sqrt(-math.log(q))
    for upper, shift, y0, pp, qq in _INV_TAIL:
        if x < upper:
            xs = x - shift
            r = _poly(pp, xs) / _poly(qq, xs)
            return y0 * x + r * x
    raise AssertionError("unreachable: the last interval is unbounded")


def erf_inv(u: float) -> float:
    """The inverse error function, ``erf(erf_inv(u)) = u`` for ``-1 <= u <= 1``
    (``Modelica.Math.Special.erfInv``); ``inf`` at 1 and beyond, ``-inf`` at -1 and below."""
    if u >= 1:
        return math.inf
    if u <= -1:
        return -math.inf
    if u == 0:
        return 0.0
    if u < 0:
        return -_erf_inv_core(-u, 1 + u)
    return _erf_inv_core(u, 1 - u)


def erfc_inv(u: float) -> float:
    """The inverse complementary error function for ``0 <= u <= 2`` (``Modelica.Math.Special.erfcInv``).

    Raises
    ------
    ValueError
        For ``u`` outside ``[0, 2]`` (the MSL's assertion).
    """
    if not 0 <= u <= 2:
        raise ValueError(f"erfc_inv: u = {u} is not in the range 0 <= u <= 2")
    if u == 0:
        return math.inf
    if u == 2:
        return -math.inf
    if u == 1:
        return 0.0
    if u > 1:
        return -_erf_inv_core(u - 1, 2 - u)
    return _erf_inv_core(1 - u, u)


# --------------------------------------------------------------------------
# distributions (Modelica.Math.Distributions)
# --------------------------------------------------------------------------

#: ModelicaServices.Machine.eps
_EPS = 2.2204460492503131e-16


def uniform_quantile(u: float, y_min: float = 0.0, y_max: float = 1.0) -> float:
    """Quantile of the uniform distribution on ``[y_min, y_max]`` (``Distributions.Uniform.quantile``)."""
    return u * (y_max - y_min) + y_min


def normal_cumulative(u: float, mu: float = 0.0, sigma: float = 1.0) -> float:
    """Cumulative distribution function of the normal distribution (``Distributions.Normal.cumulative``)."""
    return (1 + erf((u - mu) / (sigma * math.sqrt(2)))) / 2


def normal_quantile(u: float, mu: float = 0.0, sigma: float = 1.0) -> float:
    """Quantile of the normal distribution (``Distributions.Normal.quantile``):
    ``mu + sigma*sqrt(2)*erfInv(2*u - 1)``."""
    return mu + sigma * math.sqrt(2) * erf_inv(2 * u - 1)


def truncated_normal_quantile(u: float, y_min: float = 0.0, y_max: float = 1.0, mu: float | None = None,
                              sigma: float | None = None) -> float:
    """Quantile of the normal distribution truncated to ``[y_min, y_max]``
    (``Distributions.TruncatedNormal.quantile``); ``mu`` defaults to the middle of
    the band, ``sigma`` to a sixth of its width.  The result is clipped to the band,
    which round-off near ``u = 0`` and ``u = 1`` could leave."""
    mu = (y_max + y_min) / 2 if mu is None else mu
    sigma = (y_max - y_min) / 6 if sigma is None else sigma
    cdf_min = normal_cumulative(y_min, mu, sigma)
    cdf_max = normal_cumulative(y_max, mu, sigma)
    y = normal_quantile(cdf_min + u * (cdf_max - cdf_min), mu, sigma)
    return min(y_max, max(y_min, y))


def weibull_cumulative(u: float, lambda_: float = 1.0, k: float = 1.0) -> float:
    """Cumulative distribution function of the Weibull distribution (``Distributions.Weibull.cumulative``);
    ``lambda_`` is the MSL's scale parameter ``lambda``."""
    return 1 - math.exp(-(u / lambda_) ** k) if u >= 0 else 0.0


def weibull_quantile(u: float, lambda_: float = 1.0, k: float = 1.0) -> float:
    """Quantile of the Weibull distribution (``Distributions.Weibull.quantile``):
    ``lambda*(-log(1 - u))^(1/k)``."""
    return lambda_ * (-math.log(1 - u)) ** (1 / k)


def truncated_weibull_quantile(u: float, y_min: float = 0.0, y_max: float = 1.0, lambda_: float = 1.0,
                               k: float = 1.0) -> float:
    """Quantile of the Weibull distribution truncated to ``[y_min, y_max]``
    (``Distributions.TruncatedWeibull.quantile``), clipped to the band."""
    cdf_min = weibull_cumulative(y_min, lambda_, k)
    cdf_max = weibull_cumulative(y_max, lambda_, k)
    y = weibull_quantile(cdf_min + u * (cdf_max - cdf_min), lambda_, k)
    return min(y_max, max(y_min, y))


# --------------------------------------------------------------------------
# the functions as the equations call them
# --------------------------------------------------------------------------


def _number(value: Any) -> int | float:
    """A sympy number as Python's int or float."""
    return int(value) if value.is_Integer else float(value)


class _Computed(sp.Function):
    """A function of numbers that the generated code calls as Python (``_imp_``).

    Applied to numbers it evaluates at once (parameter bindings); otherwise it
    stays a call, whose partial derivatives are not defined: it is meant for
    discrete equations and parameters, which are never differentiated.
    """

    @classmethod
    def eval(cls, *args):
        if args and all(isinstance(a, sp.Number) for a in args):
            return sp.sympify(cls._imp_(*(_number(a) for a in args)))
        return None

    def _eval_is_real(self):
        return True

    def fdiff(self, argindex: int = 1):
        raise TypeError(f"{type(self).__name__} has no derivative: it is evaluated at events only")


def _state_element(k, *state) -> int:
    return xorshift128plus(state)[1][int(k) - 1]


def _random_number(*state) -> float:
    return xorshift128plus(state)[0]


def _initial_state_element(k, local_seed, global_seed) -> int:
    return xorshift128plus_initial_state(int(local_seed), int(global_seed))[int(k) - 1]


class _Xorshift128plusStateOut(_Computed):
    """Element ``k`` of the xorshift128+ state after one step from the state ``s1 .. s4``."""

    nargs = 5
    _imp_ = staticmethod(_state_element)


class _Xorshift128plusRandom(_Computed):
    """The number in ``(0, 1]`` xorshift128+ draws from the state ``s1 .. s4``."""

    nargs = 4
    _imp_ = staticmethod(_random_number)


class _Xorshift128plusInitialState(_Computed):
    """Element ``k`` of the initial xorshift128+ state for ``localSeed`` and ``globalSeed``."""

    nargs = 3
    _imp_ = staticmethod(_initial_state_element)


class _UniformQuantile(_Computed):
    """The uniform quantile ``u*(y_max - y_min) + y_min`` of the arguments ``u, y_min, y_max``."""

    nargs = 3
    _imp_ = staticmethod(uniform_quantile)


class _NormalQuantile(_Computed):
    """The normal quantile of the arguments ``u, mu, sigma``."""

    nargs = 3
    _imp_ = staticmethod(normal_quantile)


class _TruncatedNormalQuantile(_Computed):
    """The truncated normal quantile of the arguments ``u, y_min, y_max, mu, sigma``."""

    nargs = 5
    _imp_ = staticmethod(truncated_normal_quantile)


class _InitializeImpureRandom(_Computed):
    """The id of the impure generator, initialized from the argument ``seed`` (impure)."""

    nargs = 1
    _imp_ = staticmethod(lambda seed: initialize_impure_random(int(seed)))


# --------------------------------------------------------------------------
# the blocks
# --------------------------------------------------------------------------

#: GlobalSeed's defaults, used where a model has no globalSeed (Modelica's default inner)
_DEFAULT_FIXED_SEED = 67867967


class GlobalSeed(DerivedDefaults):
    """Global options of the noise blocks: a seed and a switch for all (Modelica.Blocks.Noise.GlobalSeed).

    Name it ``globalSeed`` (``self.globalSeed = GlobalSeed()``): the noise
    blocks below it in the model find it by that name (Modelica's
    ``inner``/``outer``).  ``seed`` is ``fixedSeed``, or with
    ``useAutomaticSeed`` a seed from the time and the process id, new for
    every translation.  ``enableNoise=False`` makes every noise block output
    its ``y_off``.  ``id_impure`` initializes the impure generator
    (:func:`impure_random`).
    """

    modelica_name = "Modelica.Blocks.Noise.GlobalSeed"

    enableNoise = Parameter(True, structural=True,  # noqa: N815
                            description="= true, if noise blocks generate noise as output; = false, if they "
                                        "generate a constant output")
    useAutomaticSeed = Parameter(False, structural=True,  # noqa: N815
                                 description="= true, choose a seed by system time and process id; = false, "
                                             "use fixedSeed")
    fixedSeed = Parameter(_DEFAULT_FIXED_SEED,  # noqa: N815
                          description="Fixed global seed for random number generators (if useAutomaticSeed = "
                                      "false)")
    seed = Parameter(None, description="Actually used global seed")
    id_impure = Parameter(None, description="ID for impure random number generators "
                                            "Modelica.Math.Random.Utilities.impureXXX")

    derived_defaults = {
        "seed": lambda block: automatic_global_seed() if block.useAutomaticSeed else block.fixedSeed,
        "id_impure": lambda block: _InitializeImpureRandom(block.seed),
    }


def _global_seed(block: Component) -> GlobalSeed | None:
    """The ``globalSeed`` a block's ``outer`` declaration finds: the nearest on the way up."""
    node = block._parent
    while node is not None:
        found = node.children.get("globalSeed")
        if isinstance(found, GlobalSeed):
            return found
        node = node._parent
    return None


def _instance_name(block: Component) -> str:
    """Modelica's ``getInstanceName()``: the simulated model's class name, then the block's path."""
    root = block
    while root._parent is not None:
        root = root._parent
    declared = getattr(root, "modelica_class", None)
    model = declared.rsplit(".", 1)[-1] if isinstance(declared, str) and declared else type(root).__name__
    return f"{model}.{block.path}" if block.path else model


class PartialNoise(DerivedDefaults, SO):
    """Partial noise generator (Modelica.Blocks.Interfaces.PartialNoise).

    At initialization the xorshift128+ state ``state[1..4]`` is set from
    ``localSeed`` and ``actualGlobalSeed`` and ``r_raw`` drawn from it; at each
    ``sample(startTime, samplePeriod)`` ``(r_raw, state)`` is the next draw from
    ``pre(state)`` (so the sample at ``startTime`` repeats the initial number).
    A subclass maps ``r_raw`` to ``r`` by :meth:`distribution`.
    ``y = y_off`` if the noise is off or before ``startTime``, else ``r``.
    """

    modelica_name = "Modelica.Blocks.Interfaces.PartialNoise"

    #: the state vector's length (xorshift128+)
    nState = 4  # noqa: N815

    samplePeriod = Parameter(0.01, unit="s", description="Period for sampling the raw random numbers")  # noqa: N815
    enableNoise = Parameter(None, structural=True,  # noqa: N815
                            description="= true: y = noise, otherwise y = y_off (default: globalSeed.enableNoise)")
    y_off = Parameter(0.0, description="Sets y = y_off if enableNoise=false (or time<startTime, see below)")
    useGlobalSeed = Parameter(True, structural=True,  # noqa: N815
                              description="= true: use global seed, otherwise ignore it")
    useAutomaticLocalSeed = Parameter(True, structural=True,  # noqa: N815
                                      description="= true: use automatic local seed, otherwise use fixedLocalSeed")
    fixedLocalSeed = Parameter(1, description="Local seed (any Integer number)")  # noqa: N815
    startTime = Parameter(0.0, unit="s", description="Start time for sampling the raw random numbers")  # noqa: N815
    localSeed = Parameter(None, description="The actual localSeed")  # noqa: N815
    actualGlobalSeed = Parameter(None, description="The global seed, which is actually used (protected)")  # noqa: N815

    state = Integer(shape=4, description="Internal state of random number generator (protected)")
    # the start values are the initial values: the continuous initial equations that read
    # the output (a running mean's ``mu = u``) see the first draw, as in Modelica where
    # r and r_raw are unknowns of the initialization problem
    r = Variable(discrete=True, start=lambda block: block.distribution(block._first_draw()),
                 description="Random number according to the desired distribution (protected)")
    r_raw = Variable(discrete=True, start=lambda block: block._first_draw(),
                     description="Uniform random number in the range (0,1] (protected)")

    derived_defaults = {
        "enableNoise": lambda block: block._outer_enable_noise(),
        "localSeed": lambda block: (automatic_local_seed(_instance_name(block)) if block.useAutomaticLocalSeed
                                    else block.fixedLocalSeed),
        "actualGlobalSeed": lambda block: block._outer_seed() if block.useGlobalSeed else 0,
    }

    def _outer_enable_noise(self) -> bool:
        inner = _global_seed(self)
        return True if inner is None else bool(inner.enableNoise)

    def _outer_seed(self) -> Any:
        inner = _global_seed(self)
        return _DEFAULT_FIXED_SEED if inner is None else inner.seed

    @property
    def generate_noise(self) -> bool:
        """``enableNoise and globalSeed.enableNoise`` (Modelica's protected ``generateNoise``)."""
        return bool(self.parameter_binding("enableNoise")) and self._outer_enable_noise()

    def _initial_state(self) -> list[sp.Expr]:
        """The generator's state at initialization, from ``localSeed`` and ``actualGlobalSeed``."""
        return [_Xorshift128plusInitialState(k, self.localSeed, self.actualGlobalSeed)
                for k in range(1, self.nState + 1)]

    def _first_draw(self) -> sp.Expr:
        """``r_raw`` at initialization: the number drawn from the initial state."""
        return _Xorshift128plusRandom(*self._initial_state())

    def distribution(self, u: sp.Expr) -> sp.Expr:
        """The distribution's quantile of the uniform number ``u`` (override)."""
        raise NotImplementedError(f"{type(self).__name__} does not define its distribution")

    def equations(self):
        state = [self.state[i] for i in range(1, self.nState + 1)]
        previous = [pre(s) for s in state]
        start = self._initial_state()
        at_initial = [*(Eq(s, s0) for s, s0 in zip(state, start)), Eq(self.r_raw, self._first_draw())]
        draws = [When(initial(), *at_initial), When(initial(), Eq(self.r, self.distribution(self.r_raw)))]
        if self.generate_noise:
            tick = sample(self.startTime, self.samplePeriod)
            draws = [
                When(initial(), *at_initial).elsewhen(
                    tick, *(Eq(s, _Xorshift128plusStateOut(k, *previous)) for k, s in enumerate(state, start=1)),
                    Eq(self.r_raw, _Xorshift128plusRandom(*previous))),
                When(initial(), Eq(self.r, self.distribution(self.r_raw))).elsewhen(
                    tick, Eq(self.r, self.distribution(self.r_raw))),
            ]
            output = Eq(self.y, If(time < self.startTime, self.y_off, self.r))
        else:
            output = Eq(self.y, self.y_off)
        return [*draws, output]


class UniformNoise(PartialNoise):
    """Noise generator with uniform distribution (Modelica.Blocks.Noise.UniformNoise).

    Uniform on ``[y_min, y_max]``: ``r = r_raw*(y_max - y_min) + y_min``.
    """

    modelica_name = "Modelica.Blocks.Noise.UniformNoise"

    y_min = Parameter(0.0, description="Lower limit of y")
    y_max = Parameter(1.0, description="Upper limit of y")

    def distribution(self, u):
        return _UniformQuantile(u, self.y_min, self.y_max)


class NormalNoise(PartialNoise):
    """Noise generator with normal distribution (Modelica.Blocks.Noise.NormalNoise).

    Mean ``mu`` and standard deviation ``sigma``:
    ``r = mu + sigma*sqrt(2)*erfInv(2*r_raw - 1)``.
    """

    modelica_name = "Modelica.Blocks.Noise.NormalNoise"

    mu = Parameter(0.0, description="Expectation (mean) value of the normal distribution")
    sigma = Parameter(1.0, description="Standard deviation of the normal distribution")

    def distribution(self, u):
        return _NormalQuantile(u, self.mu, self.sigma)


class TruncatedNormalNoise(PartialNoise):
    """Noise generator with truncated normal distribution (Modelica.Blocks.Noise.TruncatedNormalNoise).

    A normal distribution (``mu`` the middle of ``[y_min, y_max]``, ``sigma`` a
    sixth of its width by default) truncated to the band: every value is in it.
    """

    modelica_name = "Modelica.Blocks.Noise.TruncatedNormalNoise"

    y_min = Parameter(0.0, description="Lower limit of y")
    y_max = Parameter(1.0, description="Upper limit of y")
    mu = Parameter(None, description="Expectation (mean) value of the normal distribution "
                                     "(default (y_max + y_min)/2)")
    sigma = Parameter(None, description="Standard deviation of the normal distribution (default (y_max - y_min)/6)")

    derived_defaults = {
        "mu": lambda block: (block.y_max + block.y_min) / 2,
        "sigma": lambda block: (block.y_max - block.y_min) / 6,
    }

    def distribution(self, u):
        return _TruncatedNormalQuantile(u, self.y_min, self.y_max, self.mu, self.sigma)


class BandLimitedWhiteNoise(PartialNoise):
    """Noise generator to produce band-limited white noise with normal distribution
    (Modelica.Blocks.Noise.BandLimitedWhiteNoise).

    Normal with mean 0 and ``sigma = sqrt(noisePower/samplePeriod)``: the
    variance is the noise power times the bandwidth ``1/samplePeriod``.
    """

    modelica_name = "Modelica.Blocks.Noise.BandLimitedWhiteNoise"

    noisePower = Parameter(1.0, description="Power of white noise signal")  # noqa: N815
    mu = Parameter(0.0, description="Mean value (protected)")
    sigma = Parameter(None, description="Standard deviation sqrt(noisePower/samplePeriod) (protected)")

    derived_defaults = {"sigma": lambda block: sp.sqrt(block.noisePower / block.samplePeriod)}

    def distribution(self, u):
        return _NormalQuantile(u, self.mu, self.sigma)


# --------------------------------------------------------------------------
# the impure generator in equations (state of the run)
# --------------------------------------------------------------------------

#: the id initializeImpureRandom returns whatever its seed: the local seed it uses (a prime)
_IMPURE_ID = 715827883


def _impure_draw(state: dict, id: Any, seed: Any) -> float:  # noqa: A002 - the MSL's name
    """The next number in ``(0, 1]`` of the impure generator whose state is ``state``
    (a run's; seeded as :func:`initialize_impure_random` seeds it on the first call)."""
    if not state:
        start = initial_state_with_xorshift64star(_IMPURE_ID, int(seed), 33)
        state["words"] = [_word(start[2 * i], start[2 * i + 1]) for i in range(16)]
        state["p"] = start[32]
        state["id"] = _IMPURE_ID
    if int(id) != state["id"]:
        raise RuntimeError("impureRandom: not initialized with initializeImpureRandom "
                           f"(id = {int(id)}, expected {state['id']})")
    r, state["p"] = _xorshift1024star_step(state["words"], state["p"])
    return r


class ImpureRandomNumber(ImpureFunction):
    """Impure random number generator (with hidden state vector) (Modelica.Math.Random.Utilities.impureRandom).

    ``ImpureRandomNumber(id, seed)`` in an equation: the next number in
    ``(0, 1]`` of xorshift1024*, as ``impureRandom(id)`` draws it.  Its state
    belongs to the run (:class:`acausal.functions.ImpureFunction`): one
    number per firing of the when-clause that calls it, and every run starts
    from the state ``initializeImpureRandom(seed)`` sets.  ``id`` is that
    function's result (``globalSeed.id_impure``); acausal evaluates that
    parameter while translating, so the call also carries the ``seed`` the
    run's state is set from at its first draw (``globalSeed.seed``).

    Raises
    ------
    RuntimeError
        When ``id`` is not the one ``initializeImpureRandom`` returns.
    """

    modelica_name = "Modelica.Math.Random.Utilities.impureRandom"

    nargs = 2
    #: the state impureRandom and impureRandomInteger share (ModelicaRandom_s, _p, _id)
    stream = "Modelica.Math.Random.Utilities.impureRandom"

    @classmethod
    def _impure_(cls, state: dict, id: Any, seed: Any) -> float:  # noqa: A002
        return _impure_draw(state, id, seed)


class ImpureRandomInteger(ImpureFunction):
    """Impure random number generator for integer values (with hidden state vector)
    (Modelica.Math.Random.Utilities.impureRandomInteger).

    ``ImpureRandomInteger(id, seed, imin, imax)``: an Integer uniform in
    ``[imin, imax]``, ``min(imax, integer(r*(imax - imin + 1)) + imin)`` with
    ``r`` the next number of the generator :class:`ImpureRandomNumber` draws from
    (the same state: the two advance one generator).
    """

    modelica_name = "Modelica.Math.Random.Utilities.impureRandomInteger"

    nargs = (2, 3, 4)
    stream = ImpureRandomNumber.stream

    @classmethod
    def _impure_(cls, state: dict, id: Any, seed: Any, imin: Any = 1,  # noqa: A002
                 imax: Any = 268435456) -> int:
        r = _impure_draw(state, id, seed)
        return min(int(imax), int(math.floor(r * (int(imax) - int(imin) + 1))) + int(imin))

    def _eval_is_integer(self):
        return True


class ImpureRandom(DerivedDefaults, SO):
    """Block generating random numbers with the impure random number generator
    (Modelica.Blocks.Examples.Noise.Utilities.ImpureRandom).

    ``y = impureRandom(globalSeed.id_impure)`` at initialization and at every
    ``sample(samplePeriod, samplePeriod)``; the output holds in between.  The
    numbers are those of xorshift1024* from the state
    ``initializeImpureRandom(globalSeed.seed)`` gives, one per firing, shared
    with every other impure call of the model in the order of the events.
    ``globalSeed`` is found as the noise blocks find it (the nearest
    :class:`GlobalSeed` named ``globalSeed`` on the way up); without one, a
    default GlobalSeed's values.
    """

    modelica_name = "Modelica.Blocks.Examples.Noise.Utilities.ImpureRandom"

    samplePeriod = Parameter(None, unit="s", description="Sample period for random number generation")  # noqa: N815
    id_impure = Parameter(None, description="globalSeed.id_impure: the id of the impure generator (protected)")
    actualGlobalSeed = Parameter(None, description="globalSeed.seed, from which the run's impure "  # noqa: N815
                                                   "generator starts (protected)")

    derived_defaults = {
        "id_impure": lambda block: _IMPURE_ID if _global_seed(block) is None else _global_seed(block).id_impure,
        "actualGlobalSeed": lambda block: (_DEFAULT_FIXED_SEED if _global_seed(block) is None
                                           else _global_seed(block).seed),
    }

    def equations(self):
        return [When([initial(), sample(self.samplePeriod, self.samplePeriod)],
                     Eq(self.y, ImpureRandomNumber(self.id_impure, self.actualGlobalSeed)))]
