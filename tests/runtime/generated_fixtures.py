"""Generated code for the tests of the watched-only crossings (``test_watched_crossings.py``,
numpy; ``test_watched_scalar_crossings.py``, scalar): one small system of two linear
solves, a Piecewise and a function called element by element, its symbols, the values
hypothesis draws, and CoupledClutches' evaluator.  Import it as ``from generated_fixtures
import ...`` (pytest puts this folder on ``sys.path``)."""

from __future__ import annotations

import functools
import math
import types

import numpy as np
import sympy as sp
from hypothesis import strategies as st

from acausal import translate
from acausal.compiler.algebraic import Assign, LinearSolve
from acausal.compiler.codegen import generate
from acausal.compiler.generated import CompiledFunctions
from acausal.language import real_symbol, time
from acausal.runtime.events import evaluator_for

S = real_symbol
x1, x2, k, a, b, c, d = (S(n) for n in ("x1", "x2", "k", "a", "b", "c", "d"))
KNIFE = st.sampled_from([0.0, -0.0, 1.0, -1.0, 2.0, 0.5, 1e-300, 3.0, math.pi])
VALUE = KNIFE | st.floats(-5, 5, allow_nan=False, allow_infinity=False)

#: the crossings of :func:`solve_steps`' system (the scalar tests add a log and a pole)
CROSSINGS = (a, x2, c, time, d, k, b, sp.Float(0.5), x1 ** 3 - x2 / 3, sp.sqrt(k + x2 ** 2))


def bit_identical(p, q) -> bool:
    """Bit for bit (NaN equal to NaN, -0.0 not equal to 0.0)."""
    p, q = np.asarray(p, dtype=float), np.asarray(q, dtype=float)
    return p.shape == q.shape and np.array_equal(p.view(np.int64), q.view(np.int64))


class Compiled(types.SimpleNamespace, CompiledFunctions):
    """A compiled stand-in for a ModeSystem: its generated functions and text, with what a
    ModeSystem offers besides (CompiledFunctions')."""

    parts = None


def compiled_system(steps, crossings, unknowns, states=("x1", "x2"), name="w") -> Compiled:
    """``steps`` and ``crossings`` generated and bound to ``k = 1.5``."""
    code = generate(steps, states, (), unknowns, ("k",), crossings=crossings, name=name)
    _derivatives, crossing_fn, outputs = code.make([1.5])
    return Compiled(crossings=crossing_fn, outputs=outputs, code=code, states=states)


def solve_steps() -> list:
    """Two 1x1 linear solves (their guards, the temporary ``_a`` assigned twice), a function
    called element by element, an exponential, a Piecewise: each crossing reads some of them."""
    return [
        Assign("a", sp.Piecewise((x1 ** 2 + sp.sin(time), x1 > 0), (sp.exp(-x2), True)), None),
        LinearSolve(("c",), ((x1,),), (x2,), (), ("e1",)),
        LinearSolve(("d",), ((x2 - 1,),), (x1 + k,), (), ("e2",)),
        Assign("b", sp.Max(x1, x2) + c * d, None),
    ]


@functools.lru_cache(maxsize=1)
def clutches_evaluator():
    """CoupledClutches' discrete evaluator (its relations' kinds and margins), made once."""
    return evaluator_for(translate(_coupled_clutches()))


def _coupled_clutches():
    from examples.coupled_clutches import CoupledClutches

    return CoupledClutches()
