"""Repeated structure compiled once per shape (:mod:`acausal.compiler.canonical`).

A model of N equal units has N copies of each equation and solution step
that differ only in the names of their symbols.  Substitution (alias
elimination, specialisation), solving, differentiation and code printing
are done once per shape and renamed for the other copies.  These tests hold
the renamed results to what the work done copy by copy gives: the same
sympy expressions and the same generated text, character for character;
copies that differ in a number, an equation or the order of their names get
shapes of their own.
"""

from __future__ import annotations

import random

import networkx as nx
import pytest
import sympy as sp

import acausal.compiler.algebraic as algebraic
import acausal.compiler.canonical as canonical
import acausal.compiler.codegen as codegen
import acausal.compiler.structure as structure
from acausal import Experiment, Model
from acausal.compiler.blt import Block, BLTResult, sort_blt
from acausal.compiler.translate import translate
from acausal.language import real_symbol, time
from acausal.runtime.simulate import simulate

S = real_symbol


def unit_residual(k: int, c: float = 2.0):
    """One unit's equation: k's torque from its neighbours (names as a library's)."""
    return (S(f"spring{k}.tau") - S(f"spring{k - 1}.tau") + c * S(f"inertia{k}.J") * S(f"inertia{k}.a")
            - sp.sin(S(f"inertia{k}.phi")) * S(f"bearing{k}.tau0") / S(f"bearing{k}.unitTorque"))


def same(a, b) -> bool:
    return a == b and sp.srepr(a) == sp.srepr(b)


# -- shapes -------------------------------------------------------------------------


def test_copies_share_a_shape_and_differences_do_not():
    key2, order2, _ = canonical.shape((unit_residual(2),))
    key3, order3, _ = canonical.shape((unit_residual(3),))
    assert key2 == key3 and order2 != order3
    # another number: another shape
    assert canonical.shape((unit_residual(3, c=3.0),))[0] != key2
    # names that sort otherwise (spring9 < spring10 is false as text): another shape
    assert canonical.shape((unit_residual(10),))[0] != key2
    # another equation: another shape
    assert canonical.shape((unit_residual(3) + S("inertia3.w"),))[0] != key2


def test_symbols_that_cannot_be_renamed_have_no_shape():
    assert canonical.shape((sp.Dummy("d") + S("x"),)) is None
    # two symbols of one name (other assumptions)
    assert canonical.shape((sp.Symbol("x") + S("x"),)) is None


# -- substitution, solving, differentiation --------------------------------------------


def test_substitution_renamed_is_the_substitution_itself():
    memo: dict = {}
    for k in (2, 3, 4, 9, 10, 11, 99, 100):
        expr = unit_residual(k)
        substitution = {S(f"spring{k - 1}.tau"): -S(f"torque{k}.tau"), S(f"inertia{k}.J"): sp.Float(0.5),
                        S(f"inertia{k}.a"): S(f"der(inertia{k}.w)")}
        assert same(canonical.substituted(expr, substitution, memo), expr.xreplace(substitution))
    # the copies shared their work: fewer shapes than copies (9/10 and 99/100 sort otherwise)
    assert len(memo) < 8


def test_solutions_renamed_and_a_zero_coefficient_decided_per_copy():
    shapes: dict = {}
    values = {S(f"inertia{k}.J"): sp.Float(1.0 + k) for k in range(2, 6)}
    values[S("inertia4.J")] = sp.Float(0.0)  # one unit differs in a parameter value
    for k in range(2, 6):
        residual, var = unit_residual(k), S(f"inertia{k}.a")
        found = algebraic._solved(residual, var, values, shapes)
        expected = algebraic._solve_with_guard(residual, var, values)
        assert (found[0] is None) == (expected[0] is None)
        if expected[0] is not None:
            assert same(found[0], expected[0]) and same(found[1], expected[1])
    assert algebraic._solved(unit_residual(4), S("inertia4.a"), values, shapes) == (None, None)
    assert len(shapes) == 1


def test_derivative_without_sympy_machinery_is_sympy_diff():
    x, y, z, k = (S(n) for n in ("x", "y", "z", "k"))
    exprs = [x + y, k * (x - y) / z, -k * (x - z * sp.sign(y)) / y + 3 * x, 2 * (x + y) * k,
             sp.Integer(2) * (k + y) * (x - 1), x * (y + 2) - x * y]
    for expr in exprs:
        for var in (x, y):
            found = algebraic._derivative(expr, var)
            if found is not None:
                assert same(found, sp.diff(expr, var)), (expr, var)


def test_differentiation_renamed_is_the_derivative_itself():
    shapes: dict = {}
    parameters = {f"inertia{k}.J" for k in range(2, 12)} | {f"bearing{k}.tau0" for k in range(2, 12)} \
        | {f"bearing{k}.unitTorque" for k in range(2, 12)}
    for k in range(2, 12):
        expr = unit_residual(k) + sp.sin(time) * S(f"inertia{k}.phi")
        assert same(structure._differentiated(expr, parameters, shapes),
                    structure.differentiate(expr, parameters))
    assert len(shapes) < 10


def test_blt_sort_is_networkx_order():
    random.seed(7)
    for _ in range(300):
        n = random.randint(1, 25)
        matching = list(range(n))
        random.shuffle(matching)
        incidence = [sorted({matching[i]} | {j for j in range(n) if random.random() < 0.12})
                     for i in range(n)]
        solver_of = {j: i for i, j in enumerate(matching)}
        graph = nx.DiGraph()
        graph.add_nodes_from(range(n))
        graph.add_edges_from((solver_of[j], i) for i, row in enumerate(incidence) for j in row
                             if solver_of[j] != i)
        condensed = nx.condensation(graph)
        expected = []
        for c in nx.lexicographical_topological_sort(condensed, key=lambda c: min(condensed.nodes[c]["members"])):
            members = tuple(sorted(condensed.nodes[c]["members"]))
            expected.append(Block(members, tuple(matching[i] for i in members)))
        assert sort_blt(incidence, matching) == BLTResult(tuple(expected))


# -- whole models ---------------------------------------------------------------------------


def drive_train(n: int, odd_unit: int | None = None, odd_equation: bool = False) -> Model:
    """``n`` units Inertia–BearingFriction–SpringDamper in series (as the scaling bench's);
    ``odd_unit`` has another inertia (a parameter value), or with ``odd_equation`` a
    damper without its spring (another equation)."""

    class Train(Model):
        experiment = Experiment(start_time=0.0, stop_time=0.05, interval=0.01)

        def build(self):
            from acausal.library.blocks import Sine
            from acausal.library.rotational import BearingFriction, Damper, Inertia, SpringDamper, Torque

            self.sine = Sine(amplitude=20.0, f=2.0)
            self.torque = Torque()
            self.connect(self.sine.y, self.torque.tau)
            previous = self.torque.flange
            for i in range(1, n + 1):
                inertia = Inertia(J=2.5 if i == odd_unit and not odd_equation else 1.0,
                                  phi=dict(start=0, fixed=True), w=dict(start=10.0, fixed=True))
                bearing = BearingFriction(tau_pos=[[0.0, 0.5]], peak=1.1)
                setattr(self, f"inertia{i}", inertia)
                setattr(self, f"bearing{i}", bearing)
                self.connect(previous, inertia.flange_a)
                self.connect(inertia.flange_b, bearing.flange_a)
                if i < n:
                    spring = (Damper(d=5.0) if i == odd_unit and odd_equation
                              else SpringDamper(c=1e3, d=5.0))
                    setattr(self, f"spring{i}", spring)
                    self.connect(bearing.flange_b, spring.flange_a)
                    previous = spring.flange_b

    Train.__name__ = Train.__qualname__ = f"Train{n}_{odd_unit}_{odd_equation}"
    return Train()


def _copy_by_copy(monkeypatch) -> None:
    """Every shape refused: each equation and step done on its own (the path before shapes)."""
    for module in (canonical, codegen, algebraic, structure):
        monkeypatch.setattr(module, "shape", lambda *args, **kwargs: None)


def _sources(translation) -> list[str]:
    systems = [translation.systems[k] for k in sorted(translation.systems, key=repr)]
    initial = [translation.initial_systems[k] for k in sorted(translation.initial_systems, key=repr)]
    return [s.code.source for s in systems] + [s.code.source for s in initial]


@pytest.mark.parametrize("odd", [dict(), dict(odd_unit=5), dict(odd_unit=5, odd_equation=True)],
                         ids=["equal units", "one parameter value", "one equation"])
def test_code_per_shape_is_the_code_copy_by_copy(monkeypatch, odd):
    """12 units (names crossing 9/10): the systems compiled with shapes have the source
    compiled copy by copy, character for character, and simulate to the same numbers."""
    shared = translate(drive_train(12, **odd), cache=False)
    with_shapes = simulate(shared)
    codegen_memo = shared.cache.codegen
    assert 0 < sum(t is not None for t in codegen_memo.templates.values()) < len(codegen_memo.steps) / 3
    with monkeypatch.context() as patch:
        _copy_by_copy(patch)
        alone = translate(drive_train(12, **odd), cache=False)
        copy_by_copy = simulate(alone)
        assert not alone.cache.codegen.templates
    assert _sources(shared) == _sources(alone)
    assert with_shapes.names == copy_by_copy.names
    for name in ("inertia1.w", "inertia5.w", "inertia12.phi", "bearing5.tau"):
        assert (with_shapes[name] == copy_by_copy[name]).all(), name


def test_equal_parts_compiled_apart_share_the_work_per_shape(monkeypatch):
    """Independent parts have caches of their own but the model's work per shape: the units of
    a storm are derived once and renamed, and the generated code is what each part's own
    derivation gives, character for character."""
    from acausal.compiler.cache import ModelCache
    from acausal.tools.bench import suite

    def sources():
        translation = translate(suite().storm_model(4), cache=False)
        simulate(translation, stop_time=0.5)
        return translation, sorted((repr(k), s.code.source) for k, s in translation.parts.items())

    shared, with_sharing = sources()
    assert len(shared.parts) > 4
    # the parts' solutions and printed steps landed in the model's memos per shape
    assert shared.cache.algebraic.shapes and shared.cache.codegen.templates

    def own_memos(self, parameter_names):  # each part derives everything itself
        return ModelCache(self.parameters.restricted(parameter_names), self.identifiers,
                          specialise=self.specialise)

    monkeypatch.setattr(ModelCache, "for_cluster", own_memos)
    apart, without_sharing = sources()
    assert not apart.cache.algebraic.shapes
    assert with_sharing == without_sharing
