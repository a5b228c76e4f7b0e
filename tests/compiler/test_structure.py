"""Unit tests of the structure stage on small hand-made systems.

Matching, the balance check, index reduction (Pantelides, dummy derivatives),
state selection and differentiation.  Every expected value here is derived
by hand from the definition of the stage: matchings from the incidence
pattern, states and dummy derivatives from Pantelides' algorithm and the
dummy-derivative rules, motion of a gear train from Newton's law.  (BLT
sorting is tested in test_blt.py, alias elimination in test_alias.py.)
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from acausal import Model, StateSelect, simulate, time
from acausal.errors import (
    OverDeterminedError,
    StructurallySingularError,
    UnderDeterminedError,
)
from acausal.compiler.flatten import FlatEquation, FlatVariable, Origin
from acausal.language import real_symbol
from acausal.compiler.structure import analyse, augmenting_path, check_balance, differentiate, priority_matching
from acausal.compiler.translate import translate
from acausal.library.rotational import ConstantTorque, IdealGear, Inertia


# --------------------------------------------------------------------------
# helpers


def var(name: str, **attributes) -> FlatVariable:
    """A continuous FlatVariable with neutral attributes, overridden by ``attributes``."""
    fields = dict(name=name, kind="continuous", start=0.0, fixed=False, nominal=1.0,
                  state_select=StateSelect.default, unit="", component="c")
    fields.update(attributes)
    return FlatVariable(**fields)


def equation(residual, index: int, text: str = "") -> FlatEquation:
    return FlatEquation(residual, Origin("c", "C", "C", index, text or str(residual)))


S = real_symbol


def mode_of(model):
    """The compiled continuous system of a model without discrete parts."""
    translation = translate(model)
    return translation, translation.system(translation.key_of({}))


# --------------------------------------------------------------------------
# augmenting_path / priority_matching


def test_priority_matching_finds_unique_perfect_matching():
    """G = [[0,1],[0],[1,2]] has the single perfect matching e0-v1, e1-v0, e2-v2; greedy e0-v0 must be undone."""
    G = [[0, 1], [0], [1, 2]]
    assign = priority_matching(G, 3, range(3))
    assert assign == [1, 0, 2]


def test_augmenting_path_reroutes_a_chain_of_three_matched_equations():
    """e3 needs v0, forcing the shift e0:v0->v1, e1:v1->v2, e2:v2->v3 (an augmenting path of length 7)."""
    G = [[0, 1], [1, 2], [2, 3], [0]]
    assign = [0, 1, 2, -1]  # e0-v0, e1-v1, e2-v2; v3 free
    assert augmenting_path(3, G, assign, lambda j: True, set(), set())
    assert assign == [3, 0, 1, 2]


def test_augmenting_path_backtracks_out_of_a_dead_end():
    """e2 tries v1 first (its owner e1 has no alternative), must backtrack and go via v0/e0 to free v2."""
    G = [[0, 2], [1], [1, 0]]
    assign = [0, 1, -1]
    assert augmenting_path(2, G, assign, lambda j: True, set(), set())
    assert assign == [2, 1, 0]


def test_augmenting_path_failure_colours_the_visited_part():
    """Two equations in the single unknown v0: the path from e1 fails and colours e0, e1 and v0 (Pantelides' set)."""
    G = [[0], [0]]
    assign = [0]
    visited_eqs, visited_vars = set(), set()
    assert not augmenting_path(1, G, assign, lambda j: True, visited_eqs, visited_vars)
    assert assign == [0]
    assert visited_eqs == {0, 1}
    assert visited_vars == {0}


def test_augmenting_path_respects_allowed():
    """An unknown that is not allowed (e.g. not a highest derivative) is never assigned."""
    G = [[0, 1]]
    assign = [-1, -1]
    assert augmenting_path(0, G, assign, lambda j: j != 0, set(), set())
    assert assign == [-1, 0]
    assign = [-1]
    assert not augmenting_path(0, [[0]], assign, lambda j: False, set(), set())
    assert assign == [-1]


def test_structurally_singular_pattern_leaves_the_last_priority_equation_unmatched():
    """e0 and e1 both contain only v0: whichever comes later in the order stays unmatched."""
    G = [[0], [0], [1, 2]]
    assign = priority_matching(G, 3, [0, 1, 2])
    assert assign[0] == 0 and 1 not in assign
    assert assign[1] == 2 and assign[2] == -1  # e2 takes its first free unknown, v1
    assign = priority_matching(G, 3, [1, 0, 2])
    assert assign[0] == 1 and 0 not in assign


@pytest.mark.parametrize("order, unmatched", [([0, 1, 2], 2), ([2, 0, 1], 1), ([1, 2, 0], 0)])
def test_priority_matching_never_drops_an_earlier_equation(order, unmatched):
    """Three equations, two unknowns (G=[[0],[0,1],[1]]): the equation last in priority is the one left out."""
    G = [[0], [0, 1], [1]]
    assign = priority_matching(G, 2, order)
    matched = set(assign)
    assert -1 not in assign
    assert matched == {0, 1, 2} - {unmatched}


# --------------------------------------------------------------------------
# check_balance


def _balance_case(incidence):
    eqs = [equation(sp.Integer(0), i, f"eq{i}") for i in range(len(incidence))]
    return eqs, [set(names) for names in incidence]


def test_check_balance_accepts_a_derivative_as_its_family():
    """der(x) belongs to the family x: {der(x), y} and {x} match x and y perfectly."""
    eqs, inc = _balance_case([{"der(x)", "y"}, {"x"}])
    check_balance(eqs, inc, ["x", "y"])


def test_check_balance_classifies_the_three_failures():
    """More equations -> over-determined; fewer -> under-determined; equal but unpairable -> singular."""
    eqs, inc = _balance_case([{"x"}, {"x"}, {"x", "y"}])
    with pytest.raises(OverDeterminedError, match="3 equations for 2"):
        check_balance(eqs, inc, ["x", "y"])
    eqs, inc = _balance_case([{"x", "y"}])
    with pytest.raises(UnderDeterminedError) as info:
        check_balance(eqs, inc, ["x", "y", "z"])
    assert "z" in str(info.value)
    eqs, inc = _balance_case([{"x"}, {"x"}])
    with pytest.raises(StructurallySingularError) as info:
        check_balance(eqs, inc, ["x", "y"])
    assert "eq0" in str(info.value) and "eq1" in str(info.value) and "y" in str(info.value)


# --------------------------------------------------------------------------
# analyse: index reduction and state selection


def test_analyse_hand_made_index_two_system():
    """der(x) = y, x = sin(time): x is no state; der(x) becomes a dummy and the constraint is differentiated once."""
    x, y = S("x"), S("y")
    equations = [equation(S("der(x)") - y, 0), equation(x - sp.sin(time), 1)]
    result = analyse(equations, {"x": var("x"), "y": var("y")}, {})
    assert result.states == ()
    assert result.dummy_derivatives == ("der(x)",)
    assert result.differentiated == ((2, 1),)
    assert sp.simplify(result.equations[2].residual - (S("der(x)") - sp.cos(time))) == 0
    # y is solved from der(x) = y, der(x) from the differentiated constraint, x from the constraint
    solved_by = {result.unknowns[result.matching[i]]: i for i in range(3)}
    assert solved_by == {"y": 0, "x": 1, "der(x)": 2}


class TwoRigidInertias(Model):
    def build(self):
        self.i1 = Inertia(J=1.0, phi=dict(start=0.0, fixed=True), w=dict(start=1.0, fixed=True))
        self.i2 = Inertia(J=2.0)
        self.connect(self.i1.flange_b, self.i2.flange_a)


def test_two_rigid_inertias_have_two_states_and_one_velocity_constraint():
    """i1 ~ i2 rigidly: one angle; w1 = der(phi) = w2 is a hidden constraint, so Pantelides differentiates both kinematic equations."""
    _, mode = mode_of(TwoRigidInertias())
    s = mode.structure
    assert s.states == ("i1.phi", "i1.w")
    assert s.derivatives == ("der(i1.phi)", "der(i1.w)")
    # i2.phi is an alias of i1.phi, so both kinematic equations read der(i1.phi)
    assert mode.aliases.aliases["i2.phi"] == S("i1.phi")
    parents = sorted(s.equations[k].origin.text for _, k in s.differentiated)
    assert parents == ["i1.w = der(i1.phi)", "i2.w = der(i2.phi)"]
    for i, k in s.differentiated:
        assert sp.simplify(s.equations[i].residual - differentiate(s.equations[k].residual, set())) == 0
    # the constraint level has two equations, so two derivatives become dummies: the second
    # derivative of the shared angle (w1 is the state) and der(i2.w) (w2 = w1 algebraically)
    assert set(s.dummy_derivatives) == {"der(der(i1.phi))", "der(i2.w)"}
    assert len(s.equations) == len(s.unknowns)


def test_state_select_prefer_moves_the_states_to_the_preferred_inertia():
    """Inertia(stateSelect=prefer) on i2 makes i2.phi (alias representative) and i2.w the states."""

    class Preferred(Model):
        def build(self):
            self.i1 = Inertia(J=1.0, phi=dict(start=0.0, fixed=True), w=dict(start=1.0, fixed=True))
            self.i2 = Inertia(J=2.0, stateSelect=StateSelect.prefer)
            self.connect(self.i1.flange_b, self.i2.flange_a)

    translation, mode = mode_of(Preferred())
    assert mode.structure.states == ("i2.phi", "i2.w")
    assert "der(i1.w)" in mode.structure.dummy_derivatives
    # the fixed starts of i1 still initialise the model (phi = 0, w = 1 with no torque)
    result = simulate(translation, stop_time=1.0, rtol=1e-10)
    assert result.success
    np.testing.assert_allclose(result["i2.phi"], result.time, rtol=0, atol=1e-9)
    np.testing.assert_allclose(result["i2.w"], 1.0, rtol=0, atol=1e-12)


def test_first_declared_inertia_of_a_rigid_chain_keeps_its_states():
    """structure._select_dummy_derivatives promises 'the first inertia of a chain keeps its states': z before a."""

    class Chain(Model):
        def build(self):
            self.z = Inertia(J=1.0)
            self.a = Inertia(J=2.0)
            self.src = ConstantTorque(tau_constant=1.0)
            self.connect(self.z.flange_b, self.a.flange_a)
            self.connect(self.src.flange, self.z.flange_a)

    _, mode = mode_of(Chain())
    assert mode.structure.states == ("z.phi", "z.w")


J_A, J_B, RATIO, TORQUE, PHI0, W0 = 0.5, 8.0, 4.0, 3.0, 0.2, 1.5


class GearTrain(Model):
    def build(self):
        self.src = ConstantTorque(tau_constant=TORQUE)
        self.ia = Inertia(J=J_A, phi=dict(start=PHI0, fixed=True), w=dict(start=W0, fixed=True))
        self.gear = IdealGear(ratio=RATIO)
        self.ib = Inertia(J=J_B)
        self.connect(self.src.flange, self.ia.flange_a)
        self.connect(self.ia.flange_b, self.gear.flange_a)
        self.connect(self.gear.flange_b, self.ib.flange_a)


def test_ideal_gear_pair_has_two_states():
    """phi_a = r*phi_b ties the two inertias: two states, ia's phi and w (index reduction twice)."""
    _, mode = mode_of(GearTrain())
    # one angle and one speed; ties go to the first-declared inertia, so both are ia's
    assert mode.structure.states == ("ia.phi", "ia.w")
    assert {"der(ib.phi)", "der(ib.w)"} <= set(mode.structure.dummy_derivatives)
    # the gear constraint is differentiated twice (to reach accelerations)
    texts = [e.origin.text for e in mode.structure.equations]
    assert "d/dt[d/dt[gear.phi_a = gear.phi_b*gear.ratio]]" in texts


def test_ideal_gear_pair_moves_with_the_reflected_inertia():
    """Torque T on J_a geared (r) to J_b: a_a = T/(J_a + J_b/r^2), phi_a = r*phi_b, checked to 1e-8 at rtol 1e-10.

    Derivation: J_a*a_a = T - tau_g (tau_g the torque into the gear's flange_a),
    J_b*a_b = -flange_b.tau = r*tau_g (0 = r*tau_a + tau_b) and a_b = a_a/r give
    tau_g = J_b*a_a/r^2.
    """
    result = simulate(GearTrain(), stop_time=2.0, interval=0.01, rtol=1e-10)
    assert result.success
    t = result.time
    alpha = TORQUE / (J_A + J_B / RATIO**2)
    np.testing.assert_allclose(result["ia.phi"], PHI0 + W0 * t + 0.5 * alpha * t**2, rtol=0, atol=1e-8)
    np.testing.assert_allclose(result["ia.w"], W0 + alpha * t, rtol=0, atol=1e-8)
    np.testing.assert_allclose(result["ia.a"], alpha, rtol=0, atol=1e-8)
    np.testing.assert_allclose(result["ia.phi"], RATIO * result["ib.phi"], rtol=0, atol=1e-8)
    np.testing.assert_allclose(result["ib.w"], (W0 + alpha * t) / RATIO, rtol=0, atol=1e-8)
    np.testing.assert_allclose(result["ib.a"], alpha / RATIO, rtol=0, atol=1e-8)
    # torque balance of the gear: the load sees r times the torque the gear takes from J_a
    np.testing.assert_allclose(result["gear.flange_b.tau"], -RATIO * result["gear.flange_a.tau"],
                               rtol=0, atol=1e-8)
    np.testing.assert_allclose(result["gear.flange_a.tau"], J_B * alpha / RATIO**2, rtol=0, atol=1e-8)


def test_maximum_matching_of_a_long_chain_in_an_unlucky_order():
    """An augmenting path through thousands of equations (networkx's search is recursive)."""
    from acausal.compiler.structure import maximum_matching

    n = 3000
    G = [[i, i + 1] for i in range(n)] + [[0]]
    assign = maximum_matching(G, n + 1)
    assert sorted(assign) == list(range(n + 1))  # perfect
    assert all(j in G[i] for j, i in enumerate(assign))


def test_time_derivative_cancels_as_the_partial_derivatives_do():
    """d/dt[x*(y + 2) - x*y] = 2*der(x): no dependency on y may be left in the structure."""
    x, y = sp.Symbol("x", real=True), sp.Symbol("y", real=True)
    derivative = differentiate(x * (y + 2) - x * y, set())
    assert derivative == 2 * sp.Symbol("der(x)", real=True)


def test_pantelides_on_index_lists_differentiates_the_constraint_once():
    from acausal.compiler.structure import pantelides

    # variables: 0 = x, 1 = der(x), 2 = y;  e0: der(x) + y = 0, e1: x = sin(t).
    # e1 holds only x, which is not a highest derivative: e1 must be differentiated
    # once (e2: der(x) = cos(t)); then e0 takes y and e2 der(x).
    G = [[1, 2], [0]]
    A = [1, -1, -1]
    differentiated = []

    def add_derivative(j):
        A.append(-1)
        A[j] = len(A) - 1
        return A[j]

    def differentiate_equation(i):
        differentiated.append(i)
        return [A[j] if A[j] != -1 else add_derivative(j) for j in G[i]]

    B = pantelides(G, A, add_derivative, differentiate_equation)
    assert differentiated == [1]
    assert B == [-1, 2, -1]
    assert G[2] == [1]  # the derivative of e1 holds der(x)
    assert len(A) == 3  # no new variable was needed


def test_pantelides_leaves_an_index_one_system_alone():
    from acausal.compiler.structure import pantelides

    # e0: der(x) = -x, e1: y = 2x  (variables 0 = x, 1 = der(x), 2 = y)
    G = [[0, 1], [0, 2]]
    A = [1, -1, -1]
    B = pantelides(G, A, lambda j: pytest.fail("no derivative needed"),
                   lambda i: pytest.fail("no equation to differentiate"))
    assert B == [-1, -1]


def test_pantelides_stops_on_a_singular_system_instead_of_differentiating_for_ever():
    from acausal.compiler.structure import IndexTooHigh, pantelides

    # two equations that both hold only x: no number of derivatives makes this solvable
    G = [[0], [0]]
    A = [-1]

    def add_derivative(j):
        A.append(-1)
        A[j] = len(A) - 1
        return A[j]

    def differentiate_equation(i):
        return [A[j] if A[j] != -1 else add_derivative(j) for j in G[i]]

    with pytest.raises(IndexTooHigh):
        pantelides(G, A, add_derivative, differentiate_equation)
    assert len(G) < 50  # it gave up after a bounded number of differentiations
