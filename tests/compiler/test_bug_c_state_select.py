"""``stateSelect=always`` is honoured when a valid choice exists, and ``a = b - 0`` is an alias.

Fixed -- SpringDamper -- Inertia: the spring's relative angle is the inertia's angle
(``phi_rel = flange_b.phi - flange_a.phi`` with the fixed flange at 0).  Alias
elimination sees that once the constant is in, so the model needs no index reduction
for it, and ``stateSelect=always`` on the SpringDamper gives the states ``sd.phi_rel``
and ``sd.w_rel`` (as ``prefer`` does) instead of an error.  Between two free inertias
``phi_rel`` is no alias: index reduction differentiates the velocity constraint twice,
and a dummy ``der(der(phi_rel))`` must not count as ``phi_rel`` losing its state.

Expected values are the closed forms of the damped oscillator
``J phi'' + d phi' + c phi = 0`` and of a flywheel under constant torque and quadratic drag.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp

from acausal import Model, StateSelect, simulate, translate
from acausal.compiler.alias import eliminate_aliases
from acausal.compiler.flatten import FlatEquation, FlatVariable, Origin
from acausal.language import real_symbol
from acausal.library.rotational import Fixed, Inertia, SpringDamper
from examples.flywheel import Flywheel, exact_speed

J, C, D, PHI0, W0 = 2.0, 50.0, 4.0, 0.5, 1.0


def damped(t, J=J, c=C, d=D, phi0=PHI0, w0=W0):
    """phi, w of J phi'' + d phi' + c phi = 0 (underdamped): e^{-s t}(A cos wd t + B sin wd t)."""
    sigma = d / (2 * J)
    wd = math.sqrt(c / J - sigma ** 2)
    A, B = phi0, (w0 + sigma * phi0) / wd
    e = np.exp(-sigma * t)
    phi = e * (A * np.cos(wd * t) + B * np.sin(wd * t))
    w = e * ((B * wd - sigma * A) * np.cos(wd * t) - (A * wd + sigma * B) * np.sin(wd * t))
    return phi, w


class Grounded(Model):
    """Fixed -- SpringDamper(stateSelect) -- Inertia, start values on the spring or on the inertia."""

    def __init__(self, state_select=StateSelect.always, on_spring=True, **modifiers):
        self._state_select, self._on_spring = state_select, on_spring
        super().__init__(**modifiers)

    def build(self):
        start = dict(phi=dict(start=PHI0, fixed=True), w=dict(start=W0, fixed=True))
        spring_start = {"phi_rel": start["phi"], "w_rel": start["w"]} if self._on_spring else {}
        self.fixed = Fixed()
        self.sd = SpringDamper(c=C, d=D, stateSelect=self._state_select, **spring_start)
        self.inertia = Inertia(J=J, **({} if self._on_spring else start))
        self.connect(self.fixed.flange, self.sd.flange_a)
        self.connect(self.sd.flange_b, self.inertia.flange_a)


@pytest.mark.parametrize("state_select", [StateSelect.always, StateSelect.prefer], ids=["always", "prefer"])
@pytest.mark.parametrize("on_spring", [True, False], ids=["start-on-spring", "start-on-inertia"])
def test_grounded_spring_damper_states_and_closed_form(state_select, on_spring):
    model = Grounded(state_select, on_spring)
    translation = translate(model, cache=False)
    system = translation.system(())
    assert tuple(system.states) == ("sd.phi_rel", "sd.w_rel")
    # the fixed flange is at 0, so the relative angle is the inertia's angle: an alias
    assert system.aliases.aliases["inertia.phi"] == real_symbol("sd.phi_rel")
    result = simulate(translation, stop_time=3.0, interval=0.01, rtol=1e-9)
    assert result.success, result.message
    phi, w = damped(result.time)
    for name, expected in (("sd.phi_rel", phi), ("inertia.phi", phi), ("sd.w_rel", w), ("inertia.w", w)):
        assert np.max(np.abs(result[name] - expected)) <= 1e-6, name


class TwoInertias(Model):
    """Two free inertias joined by a SpringDamper(stateSelect=always): no fixed point."""

    J1, J2 = 1.0, 3.0

    def build(self):
        self.i1 = Inertia(J=self.J1, phi=dict(start=0.0, fixed=True), w=dict(start=0.0, fixed=True))
        self.sd = SpringDamper(c=C, d=D, stateSelect=StateSelect.always,
                               phi_rel=dict(start=PHI0, fixed=True), w_rel=dict(start=W0, fixed=True))
        self.i2 = Inertia(J=self.J2)
        self.connect(self.i1.flange_b, self.sd.flange_a)
        self.connect(self.sd.flange_b, self.i2.flange_a)


def test_always_survives_a_dummy_second_derivative():
    """phi_rel = i2.phi - i1.phi is differentiated twice; phi_rel and w_rel stay the states."""
    translation = translate(TwoInertias(), cache=False)
    system = translation.system(())
    states = set(system.states)
    assert {"sd.phi_rel", "sd.w_rel"} <= states
    assert len(states) == 4  # plus the angle and speed of one inertia
    result = simulate(translation, stop_time=3.0, interval=0.01, rtol=1e-9)
    assert result.success, result.message
    # relative motion: a damped oscillator of the reduced inertia J1 J2 / (J1 + J2)
    j1, j2 = TwoInertias.J1, TwoInertias.J2
    phi, w = damped(result.time, J=j1 * j2 / (j1 + j2))
    assert np.max(np.abs(result["sd.phi_rel"] - phi)) <= 1e-6
    assert np.max(np.abs(result["sd.w_rel"] - w)) <= 1e-6
    np.testing.assert_allclose(result["i2.phi"] - result["i1.phi"], result["sd.phi_rel"], rtol=0, atol=1e-9)
    # no external torque: the angular momentum stays J2 * W0 (i1 starts at rest, i2 at w_rel)
    momentum = j1 * result["i1.w"] + j2 * result["i2.w"]
    np.testing.assert_allclose(momentum, j2 * W0, rtol=0, atol=1e-7)


def test_always_that_cannot_be_a_state_is_still_refused():
    """Two inertias rigidly joined cannot both keep their angle: always on both is an error."""

    class Rigid(Model):
        def build(self):
            self.i1 = Inertia(J=1.0, stateSelect=StateSelect.always)
            self.i2 = Inertia(J=2.0, stateSelect=StateSelect.always)
            self.connect(self.i1.flange_b, self.i2.flange_a)

    with pytest.raises(Exception, match="state_select=always but cannot be a state"):
        translate(Rigid(), cache=False).system(())


def test_flywheel_needs_no_index_reduction():
    """motor.phi = flange.phi - phi_support with phi_support = 0 is an alias, not a constraint."""
    translation = translate(Flywheel(), cache=False)
    system = translation.system(())
    assert system.structure.differentiated == ()
    assert system.structure.dummy_derivatives == ()
    assert set(system.states) == {"flywheel.phi", "flywheel.w"}
    assert system.aliases.aliases["motor.phi"] == real_symbol("flywheel.phi")
    result = simulate(translation, rtol=1e-8)
    assert result.success, result.message
    expected = np.array([exact_speed(t) for t in result.time])
    assert np.max(np.abs(result["flywheel.w"] - expected)) <= 1e-5
    np.testing.assert_array_equal(result["motor.phi"], result["flywheel.phi"])


# -- alias elimination on its own ----------------------------------------------------------------


def _var(name: str) -> FlatVariable:
    return FlatVariable(name=name, kind="continuous", start=0.0, fixed=False, nominal=1.0,
                        state_select=StateSelect.default, unit="", component="c")


def _eq(residual, index: int) -> FlatEquation:
    return FlatEquation(residual, Origin("c", "C", "C", index, str(residual)))


def test_constants_folded_make_alias_equations():
    """Equations that become ``a = ±b`` or ``a = constant`` once the constants found are put
    in are alias equations, also when the constant is found later (in the order, or in a
    later pass); a sum with a parameter (not zero) stays an equation."""
    a, b, c, d, e, f, g, h, x = (real_symbol(n) for n in "abcdefghx")
    k = real_symbol("k")
    equations = (
        _eq(a - b + c, 0),          # a = b - c            -> a = b once c = 0
        _eq(e + d - f - g, 1),      # e = -d + f + g       -> e = -d once f = g = 0 (second pass)
        _eq(g - f, 2),              # g = f                (an alias as written)
        _eq(h - b - k, 3),          # h = b + k            (k a parameter: stays)
        _eq(c, 4),                  # c = 0
        _eq(f - 2 * c, 5),          # f = 2 c              -> f = 0 once c = 0 (first pass)
        _eq(x - sp.sin(a), 6),      # not linear: stays
    )
    variables = {n: _var(n) for n in "abcdefghx"}
    result = eliminate_aliases(equations, variables, {"k"})
    aliases = result.aliases
    assert aliases["c"] == 0 and aliases["f"] == 0 and aliases["g"] == 0
    # representatives: the one declared first of equal rank
    assert aliases["b"] == a
    assert aliases["e"] == -d
    assert "a" not in aliases and "d" not in aliases and "h" not in aliases
    assert [eq.origin.index for eq in result.equations] == [3, 6]
    assert result.equations[0].residual == h - a - k
    assert [eq.origin.index for eq in result.eliminated] == [0, 1, 2, 4, 5]
    # the same result again (the memo of the first call reused)
    from acausal.compiler.alias import AliasMemo
    memo = AliasMemo()
    first = eliminate_aliases(equations, variables, {"k"}, memo=memo)
    again = eliminate_aliases(equations, variables, {"k"}, memo=memo)
    assert again.aliases == first.aliases == aliases
    assert again.equations == first.equations == result.equations
