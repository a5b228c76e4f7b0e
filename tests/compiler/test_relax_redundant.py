"""relax_redundant: a square, structurally singular system made solvable by
leaving out a redundant selected equation and zeroing an open flow."""

import sympy as sp

from acausal.compiler.flatten import FlatEquation, Origin
from acausal.compiler.structure import _incidence, maximum_matching, relax_redundant
from acausal.language import real_symbol

a, f1, f2 = (real_symbol(n) for n in ("s.a", "e1.f", "e2.f"))
T = 3.0


def equation(residual, component, index):
    return FlatEquation(residual, Origin(component, "Element", "Element", index, f"0 = {residual}"))


def system():
    """Two elements each lock the acceleration a (a = 0 twice); their forces hold T together."""
    return [equation(a, "e1", 0), equation(a, "e2", 0), equation(f1 + f2 - T, "s", 0)]


def incidence(equations):
    return [_incidence(e.residual, {}) for e in equations]


FAMILIES = ["s.a", "e1.f", "e2.f"]


def test_a_doubled_constraint_is_left_out_and_one_share_set_to_zero():
    equations = system()
    found = relax_redundant(equations, incidence(equations), FAMILIES, droppable=[0, 1],
                            flows=["e1.f", "e2.f"])
    assert found is not None
    relaxed, relaxation = found
    assert len(relaxation.dropped) == 1 and relaxation.dropped[0] in equations[:2]
    assert relaxation.zeroed in (("e1.f",), ("e2.f",))
    # the relaxed system has a perfect matching, and its solution holds T with the other share
    column = {f: j for j, f in enumerate(FAMILIES)}
    G = [sorted(column[n] for n in names) for names in incidence(relaxed)]
    assert -1 not in maximum_matching(G, len(FAMILIES))
    solution = sp.solve([e.residual for e in relaxed], [a, f1, f2], dict=True)
    assert len(solution) == 1
    values = solution[0]
    assert float(values[a]) == 0 and float(values[f1] + values[f2]) == T
    assert float(values[real_symbol(relaxation.zeroed[0])]) == 0
    assert "left out e" in str(relaxation) and "= 0" in str(relaxation)


def test_the_same_choice_every_time():
    runs = {str(relax_redundant(system(), incidence(system()), FAMILIES, [0, 1], ["e1.f", "e2.f"])[1])
            for _ in range(5)}
    assert len(runs) == 1


def test_not_of_this_kind():
    equations = system()
    inc = incidence(equations)
    # no equation the discrete state selected: nothing may be left out
    assert relax_redundant(equations, inc, FAMILIES, droppable=[2], flows=["e1.f", "e2.f"]) is None
    # no flow left open
    assert relax_redundant(equations, inc, FAMILIES, droppable=[0, 1], flows=[]) is None
    # not square
    assert relax_redundant(equations[:2], inc[:2], FAMILIES, [0, 1], ["e1.f"]) is None
    # already solvable
    fine = [equation(a, "e1", 0), equation(f1 - 1, "e1", 1), equation(f1 + f2 - T, "s", 0)]
    assert relax_redundant(fine, incidence(fine), FAMILIES, [0], ["e1.f", "e2.f"]) is None
