"""Unit tests of the algebraic stage (:func:`acausal.compiler.algebraic.solve_blocks`).

Small hand-made blocks: a single equation linear in its unknown becomes an
assignment, a linear algebraic loop is torn into a small linear solve whose
matrix is free of the unknowns, a nonlinear loop becomes a Newton problem.
The steps are evaluated here with numpy (and, for the Newton problem, the
engine's :func:`~acausal.compiler.codegen.newton_solve`) and the values
checked against solutions computed by hand.
"""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from acausal.compiler.algebraic import Assign, LinearSolve, NewtonSolve, solve_blocks
from acausal.compiler.blt import sort_blt
from acausal.compiler.codegen import newton_solve
from acausal.compiler.flatten import FlatEquation, Origin
from acausal.language import real_symbol

S = real_symbol


def equation(residual, index: int) -> FlatEquation:
    return FlatEquation(residual, Origin("c", "C", "C", index, f"0 = {residual}"))


def numeric(expr, env: dict[str, float]) -> float:
    return float(sp.sympify(expr).xreplace({S(n): v for n, v in env.items()}))


def evaluate(steps, env: dict[str, float], guesses: dict[str, float] | None = None) -> dict[str, float]:
    """Run the solution steps in order on the known values ``env`` (names -> floats)."""
    env = dict(env)
    guesses = guesses or {}
    for step in steps:
        if isinstance(step, Assign):
            env[step.variable] = numeric(step.expression, env)
            continue
        if isinstance(step, LinearSolve):
            A = np.array([[numeric(e, env) for e in row] for row in step.A])
            b = np.array([numeric(e, env) for e in step.b])
            env.update(zip(step.tears, np.linalg.solve(A, b)))
            for inner in step.inner:
                env[inner.variable] = numeric(inner.expression, env)
            continue
        assert isinstance(step, NewtonSolve)

        def residual(z, step=step):
            local = {**env, **dict(zip(step.tears, z))}
            for inner in step.inner:
                local[inner.variable] = numeric(inner.expression, local)
            return [numeric(r, local) for r in step.residuals]

        z = newton_solve(residual, [guesses.get(t, 0.0) for t in step.tears], "test")
        env.update(zip(step.tears, z))
        for inner in step.inner:
            env[inner.variable] = numeric(inner.expression, env)
    return env


def test_a_chain_of_single_equations_becomes_assignments_in_blt_order():
    """J*a = tau1 + tau2 (a from known torques), v = a*h + w0: two assignments, a = (3 + 1)/2 = 2, v = 2*0.5 + 1 = 2."""
    J, a, v, tau1, tau2, h, w0 = (S(n) for n in ("J", "a", "v", "tau1", "tau2", "h", "w0"))
    equations = [equation(v - (a * h + w0), 0), equation(J * a - (tau1 + tau2), 1)]
    unknowns = ["v", "a"]
    blt = sort_blt([[0, 1], [1]], [0, 1])
    result = solve_blocks(equations, unknowns, blt, {"J": 2.0, "h": 0.5})
    assert [type(s) for s in result.steps] == [Assign, Assign]
    assert [s.variable for s in result.steps] == ["a", "v"]  # a first: v reads it
    assert (result.torn_blocks, result.linear_blocks, result.nonlinear_blocks) == (0, 0, 0)
    assert result.steps[0].origin is equations[1].origin
    assert result.steps[0].reads() == {"J", "tau1", "tau2"}
    values = evaluate(result.steps, {"J": 2.0, "h": 0.5, "tau1": 3.0, "tau2": 1.0, "w0": 1.0})
    assert values["a"] == pytest.approx(2.0, abs=1e-15)
    assert values["v"] == pytest.approx(2.0, abs=1e-15)
    # the expression solves the equation identically
    assert sp.simplify(equations[1].residual.subs(a, result.steps[0].expression)) == 0


def test_a_linear_two_by_two_loop_is_torn_into_a_closed_form_linear_solve():
    """2x + 3y = p, x - y = -q (p = 8, q = 1): x = 1, y = 2.

    Neither equation has a single unknown, so one unknown is torn, the other
    solved from one equation in terms of it; the last equation is linear in
    the tearing unknown: a LinearSolve whose matrix holds no unknown.
    """
    x, y, p, q = S("x"), S("y"), S("p"), S("q")
    equations = [equation(2 * x + 3 * y - p, 0), equation(x - y + q, 1)]
    blt = sort_blt([[0, 1], [0, 1]], [0, 1])
    assert [b.size for b in blt.blocks] == [2]
    result = solve_blocks(equations, ["x", "y"], blt, {"p": 8.0, "q": 1.0})
    (step,) = result.steps
    assert isinstance(step, LinearSolve)
    assert (result.torn_blocks, result.linear_blocks, result.nonlinear_blocks) == (1, 1, 0)
    assert len(step.tears) == 1 and len(step.inner) == 1
    assert set(step.defines) == {"x", "y"}
    assert all(not e.has(x, y) for row in step.A for e in row) and all(not e.has(x, y) for e in step.b)
    assert step.reads() == {"p", "q"}
    values = evaluate(result.steps, {"p": 8.0, "q": 1.0})
    assert values["x"] == pytest.approx(1.0, abs=1e-14)
    assert values["y"] == pytest.approx(2.0, abs=1e-14)
    # another right-hand side, the same step: 2x + 3y = 1, x - y = 2 gives x = 7/5, y = -3/5
    values = evaluate(result.steps, {"p": 1.0, "q": -2.0})
    assert (values["x"], values["y"]) == (pytest.approx(1.4, abs=1e-14), pytest.approx(-0.6, abs=1e-14))


def test_a_nonlinear_loop_becomes_a_newton_problem_with_the_hand_solution():
    """x^3 = y, x + y = 10: x^3 + x - 10 = 0 has the single real root x = 2, so y = 8."""
    x, y = S("x"), S("y")
    equations = [equation(x**3 - y, 0), equation(x + y - 10, 1)]
    blt = sort_blt([[0, 1], [0, 1]], [0, 1])
    result = solve_blocks(equations, ["x", "y"], blt, {})
    (step,) = result.steps
    assert isinstance(step, NewtonSolve)
    assert (result.torn_blocks, result.linear_blocks, result.nonlinear_blocks) == (1, 0, 1)
    # one tearing unknown, the other computed inside the residual function
    assert len(step.tears) == 1 and len(step.residuals) == 1 and len(step.inner) == 1
    assert set(step.defines) == {"x", "y"}
    values = evaluate(result.steps, {}, guesses={"x": 1.0, "y": 1.0})
    assert values["x"] == pytest.approx(2.0, abs=1e-9)
    assert values["y"] == pytest.approx(8.0, abs=1e-8)


def test_a_single_nonlinear_equation_is_solved_by_newton():
    """y^3 + y = 10 + u (u = 20): y = 3, not an assignment."""
    y, u = S("y"), S("u")
    equations = [equation(y**3 + y - 10 - u, 0)]
    result = solve_blocks(equations, ["y"], sort_blt([[0]], [0]), {})
    (step,) = result.steps
    assert isinstance(step, NewtonSolve) and step.tears == ("y",) and step.inner == ()
    assert (result.torn_blocks, result.nonlinear_blocks) == (0, 1)
    values = evaluate(result.steps, {"u": 20.0}, guesses={"y": 0.0})
    assert values["y"] == pytest.approx(3.0, abs=1e-9)


def test_an_equation_whose_coefficient_vanishes_for_the_parameters_is_not_divided_by():
    """(a + b)*y = x with a = 1, b = -1: linear in y, but the coefficient is zero; no assignment y = x/(a + b)."""
    x, y, a, b = S("x"), S("y"), S("a"), S("b")
    equations = [equation((a + b) * y - x, 0)]
    blt = sort_blt([[0]], [0])
    result = solve_blocks(equations, ["y"], blt, {"a": 1.0, "b": -1.0})
    (step,) = result.steps
    assert not isinstance(step, Assign)
    # with b = 1 the coefficient is 2: an assignment y = x/2
    result = solve_blocks(equations, ["y"], blt, {"a": 1.0, "b": 1.0})
    (step,) = result.steps
    assert isinstance(step, Assign)
    assert evaluate(result.steps, {"a": 1.0, "b": 1.0, "x": 3.0})["y"] == pytest.approx(1.5, abs=1e-15)


# -- tearing on index lists, and the zero-coefficient check ------------------------------


def test_tear_solves_a_chain_causally_without_tearing():
    from acausal.compiler.algebraic import tear

    # e0: u0 = f(u1), e1: u1 = g(u2), e2: u2 = c  ->  solved e2, e1, e0; nothing torn
    incidence = [{0, 1}, {1, 2}, {2}]
    plan = tear(incidence, 3, lambda i, j: True)
    assert plan == ([(2, 2), (1, 1), (0, 0)], [], [])


def test_tear_tears_the_unknown_in_most_equations_and_leaves_one_residual_per_tear():
    from acausal.compiler.algebraic import tear

    # a 3-cycle e0(u0,u1), e1(u1,u2), e2(u2,u0): no equation has a single unknown;
    # all unknowns occur twice, so the first (u0) is torn, then e0 gives u1, e1 gives u2,
    # and e2 is the residual
    incidence = [{0, 1}, {1, 2}, {2, 0}]
    solved, tears, residuals = tear(incidence, 3, lambda i, j: True)
    assert tears == [0] and residuals == [2] and solved == [(0, 1), (1, 2)]


def test_tear_never_solves_what_the_callback_refuses():
    from acausal.compiler.algebraic import tear

    # e0 cannot be solved for u0 (e.g. u0 appears nonlinearly): u0 must be torn
    incidence = [{0}, {0, 1}]
    solved, tears, residuals = tear(incidence, 2, lambda i, j: (i, j) != (0, 0))
    assert (0, 0) not in solved and tears == [0] and residuals == [0] and solved == [(1, 1)]


def test_a_float_zero_parameter_coefficient_is_never_divided_by():
    from acausal.compiler.algebraic import Assign
    from acausal.compiler.blt import sort_blt
    from acausal.compiler.flatten import FlatEquation, Origin
    from acausal.language import real_symbol

    eq = FlatEquation(real_symbol("p") * real_symbol("y") - real_symbol("x"),
                      Origin("c", "C", "C", 0, "p*y = x"))
    steps = solve_blocks([eq], ["y"], sort_blt([[0]], [0]), {"p": 0.0}).steps
    assert not any(isinstance(s, Assign) for s in steps)


@pytest.mark.parametrize("v_in_source, expected", [(-1.001, -15.0), (1.001, 15.0), (-0.5, None)])
def test_newton_past_the_end_of_a_branch_finds_the_root_by_bracketing(v_in_source, expected):
    """A Schmitt trigger's loop v = clip(V0*(a*u + b*v), -15, 15), a = 15/16, b = 1/16, V0 = 15000.

    From the guess v = 15 (the upper branch, which ends at u = -1), Newton alone
    cycles across the kink; the roots are found in closed form: for u = -1.001
    only v = -15 is left, for u = +1.001 only v = +15. Inside the hysteresis band
    (u = -0.5) the root nearest to the guess, +15, is kept.
    """
    V0, a, b = 15000.0, 15 / 16, 1 / 16

    def residual(z):
        gained = V0 * (a * v_in_source + b * z[0])
        return [z[0] - min(15.0, max(-15.0, gained))]

    guess = -15.0 if v_in_source > 0 else 15.0
    z = newton_solve(residual, [guess], "test")
    assert z[0] == pytest.approx(expected if expected is not None else guess, abs=1e-8)
    assert abs(residual(z)[0]) <= 1e-10 * (1 + abs(z[0]))


def test_newton_without_a_root_still_fails_with_the_reason():
    """v**2 + 1 = 0 has no real root: neither Newton nor the bracket search invents one."""
    from acausal.errors import SolverError

    with pytest.raises(SolverError, match="did not converge"):
        newton_solve(lambda z: [z[0] ** 2 + 1.0], [0.3], "test")


def test_newton_judges_a_small_residual_by_its_step_too():
    """i = v/Roff with Roff = 1 MOhm: a guess 1 mV off leaves a residual of 1e-9 A, within
    Newton's residual tolerance, yet the voltage the current i = 30 uA gives is v = 30 V exactly.
    With the block's Jacobian kept between calls (``memo``), the next call iterates to it."""
    r_off, current = 1e6, 30e-6

    def residual(z):
        return [current - z[0] / r_off]

    memo: dict = {}
    first = newton_solve(residual, [0.0], "test", memo=memo)  # from afar: iterates, keeps J
    assert first[0] == pytest.approx(30.0, abs=1e-6)
    again = newton_solve(residual, [30.001], "test", memo=memo)  # residual 1e-9 A: small
    assert abs(again[0] - 30.0) <= 1e-8
