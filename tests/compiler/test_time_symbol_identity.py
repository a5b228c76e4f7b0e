"""``time`` stays the engine's own object when expressions are read back from text or
unpickled, whatever sympy's bounded cache has dropped meanwhile.

Was: after many compilations, reading a shipped system's aliases (``sympy.srepr`` text)
made an equal but distinct ``Symbol('time', real=True)``; sympy's cache of expressions
then handed ``step.startTime > time`` built from it to a Step flattened later, and
flattening refused "unknown name time".
"""

import pickle

import sympy as sp
from sympy.core.cache import clear_cache

from acausal import Model
from acausal.compiler.flatten import flatten
from acausal.compiler.persist import _BundlePickler, _expression
from acausal.language import real_symbol, time
from acausal.library.blocks import Step


class StepOnly(Model):
    def build(self):
        self.step = Step(height=1.0, startTime=0.5)


def relation_text() -> str:
    return sp.srepr(real_symbol("step.startTime") > time)


def test_text_read_back_after_the_cache_dropped_time_uses_the_engines_time():
    text = relation_text()
    clear_cache()  # what a long session does to sympy's bounded cache
    relation = _expression.__wrapped__(text)
    assert [s for s in relation.free_symbols if s.name == "time"][0] is time
    # and a model flattened afterwards (sympy may hand it the cached relation) is fine
    flat = flatten(StepOnly())
    assert any(s is time for eq in flat.equations for s in eq.residual.free_symbols)


def test_a_pickled_expression_unpickles_with_the_engines_time():
    import io

    buffer = io.BytesIO()
    _BundlePickler(buffer).dump(real_symbol("step.startTime") > time)
    clear_cache()
    relation = pickle.loads(buffer.getvalue())
    assert [s for s in relation.free_symbols if s.name == "time"][0] is time
