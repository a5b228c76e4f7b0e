"""Unit tests of alias elimination (:func:`acausal.compiler.alias.eliminate_aliases`).

Every expected value here is derived by hand from the equations: which
variables are aliases of which (with sign), which representative the
documented preference picks, how derivatives and start values carry over.
"""

from __future__ import annotations

import pytest
import sympy as sp

from acausal import StateSelect, time
from acausal.compiler.alias import eliminate_aliases
from acausal.compiler.flatten import FlatEquation, FlatVariable, Origin
from acausal.errors import InitializationError
from acausal.language import real_symbol


# --------------------------------------------------------------------------
# helpers (the same small constructors as in test_structure.py)


def var(name: str, **attributes) -> FlatVariable:
    """A continuous FlatVariable with neutral attributes, overridden by ``attributes``."""
    fields = dict(name=name, kind="continuous", start=0.0, fixed=False, nominal=1.0,
                  state_select=StateSelect.default, unit="", component="c")
    fields.update(attributes)
    return FlatVariable(**fields)


def equation(residual, index: int, text: str = "") -> FlatEquation:
    return FlatEquation(residual, Origin("c", "C", "C", index, text or str(residual)))


S = real_symbol


# --------------------------------------------------------------------------
# eliminate_aliases


def _alias_system(**attributes):
    """a = b, b = -c, d = 5 and two equations that are not aliases (one uses der(a), one der(d))."""
    a, b, c, d, x, y = (S(n) for n in "abcdxy")
    equations = (
        equation(a - b, 0, "a = b"),
        equation(b + c, 1, "b = -c"),
        equation(d - 5, 2, "d = 5"),
        equation(S("der(a)") - x, 3, "der(a) = x"),
        equation(y - x * time - S("der(d)"), 4, "y = x*time + der(d)"),
    )
    variables = {n: var(n, **attributes.get(n, {})) for n in "abcdxy"}
    return equations, variables


def test_eliminate_aliases_signs_and_constants():
    """With c preferred as state: a = -c, b = -c, d = 5; two equations left, three eliminated."""
    equations, variables = _alias_system(c=dict(state_select=StateSelect.prefer))
    result = eliminate_aliases(equations, variables, set())
    c = S("c")
    assert result.aliases == {"a": -c, "b": -c, "d": 5}
    assert set(result.variables) == {"c", "x", "y"}
    assert len(result.equations) == 2
    assert [e.origin.index for e in result.eliminated] == [0, 1, 2]


def test_eliminate_aliases_representative_has_the_highest_state_select():
    """Preferring a instead makes a the representative: b = a, c = -a."""
    equations, variables = _alias_system(a=dict(state_select=StateSelect.prefer))
    result = eliminate_aliases(equations, variables, set())
    a = S("a")
    assert result.aliases["b"] == a
    assert result.aliases["c"] == -a
    assert "a" in result.variables and "c" not in result.variables
    assert result.variables["a"].state_select == StateSelect.prefer


def test_eliminate_aliases_rewrites_derivatives_with_the_sign():
    """der(a) becomes -der(c) when a = -c, and der(d) of the constant d becomes 0."""
    equations, variables = _alias_system(c=dict(state_select=StateSelect.prefer))
    result = eliminate_aliases(equations, variables, set())
    x, y = S("x"), S("y")
    residuals = {e.origin.index: e.residual for e in result.equations}
    assert sp.simplify(residuals[3] - (-S("der(c)") - x)) == 0
    assert sp.simplify(residuals[4] - (y - x * time)) == 0


def test_eliminate_aliases_merges_fixed_start_with_sign():
    """a fixed at 2 and a = -c: the representative c gets the fixed start -2."""
    equations, variables = _alias_system(a=dict(start=2.0, fixed=True),
                                         c=dict(state_select=StateSelect.prefer))
    result = eliminate_aliases(equations, variables, set())
    merged = result.variables["c"]
    assert merged.fixed and merged.start == -2.0


def test_eliminate_aliases_consistent_fixed_starts_are_accepted():
    """a = 1 (fixed) and c = -1 (fixed) agree through a = -c: no error."""
    equations, variables = _alias_system(a=dict(start=1.0, fixed=True), c=dict(start=-1.0, fixed=True))
    result = eliminate_aliases(equations, variables, set())
    (rep,) = [n for n in "abc" if n in result.variables]
    assert result.variables[rep].fixed
    assert result.variables[rep].start == {"a": 1.0, "b": 1.0, "c": -1.0}[rep]


def test_eliminate_aliases_conflicting_fixed_starts_raise():
    """a fixed at 1 and b fixed at 2 with a = b cannot both hold: InitializationError naming both."""
    equations, variables = _alias_system(a=dict(start=1.0, fixed=True), b=dict(start=2.0, fixed=True))
    with pytest.raises(InitializationError) as info:
        eliminate_aliases(equations, variables, set())
    message = str(info.value)
    assert "a" in message and "b" in message and info.value.hint


def test_eliminate_aliases_keep_prevents_elimination():
    """A variable in ``keep`` is never eliminated: with a and b kept, a = b stays an equation."""
    equations, variables = _alias_system()
    result = eliminate_aliases(equations, variables, set(), keep=frozenset({"a", "b"}))
    assert "a" not in result.aliases and "b" not in result.aliases
    assert any(e.origin.index == 0 for e in result.equations)
