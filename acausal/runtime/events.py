"""Stage 11: the discrete part at events — Modelica's event iteration.

At an event instant, with the ``pre()`` values held fixed, the continuous
equations (of the discrete state the current guess selects) and the
discrete equations are solved together by fixed-point iteration; then, if a
discrete variable differs from its ``pre()`` value, ``pre`` takes the new
values and the whole is repeated until nothing changes (Otter, Elmqvist &
Mattsson 1999; Dymola and OpenModelica do the same).

Relations are evaluated with the continuous values at the event, with a
small hysteresis against their value before it (see
:meth:`acausal.compiler.partition.Relation.shifted`).

References
----------
.. [1] M. Otter, H. Elmqvist and S. E. Mattsson, "Hybrid modeling in Modelica
   based on the synchronous data flow principle", Proc. CACSD'99, 1999.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from ..compiler.codegen import compile_functions
from ..errors import EventIterationError, SimulationError
from ..names import INITIAL_NAME, is_relation, parse, pre_name, relation_name
from ..compiler.translate import ModeSystem, Translation

__all__ = ["DiscreteEvaluator", "EventOutcome", "evaluator_for", "mode_values"]


#: From this many watched relations on, they are checked with numpy at once.
_VECTORISE_FROM = 48


def mode_values(system: ModeSystem, t: float, x) -> dict[str, float]:
    """All continuous variables at ``(t, x)``: unknowns, states and aliases."""
    values = system.values(t, x)
    for name, coeff, source in system.alias_plan:
        if source is None:
            values[name] = coeff
        elif source in values:  # with an output demand, some are not computed
            values[name] = coeff * values[source]
    return values


def evaluator_for(translation: Translation, relation_epsilon: float = 1e-10,
                  max_iterations: int = 20) -> "DiscreteEvaluator":
    """The discrete-part evaluator of ``translation``, built once per setting and kept
    with the translation (compiling the discrete equations is a few milliseconds)."""
    cache = translation.extras.setdefault("evaluators", {})
    key = (relation_epsilon, max_iterations)
    if key not in cache:
        cache[key] = DiscreteEvaluator(translation, relation_epsilon, max_iterations)
    return cache[key]


@dataclass(frozen=True)
class EventOutcome:
    """The fixed point reached by event iteration."""

    discrete: dict
    relations: tuple[bool, ...]
    system: ModeSystem
    values: dict
    iterations: int
    changes: tuple


class DiscreteEvaluator:
    """Evaluates relations and discrete equations of a translated model."""

    def __init__(self, translation: Translation, relation_epsilon: float = 1e-10,
                 max_iterations: int = 20) -> None:
        self.translation = translation
        self.partitioned = translation.partitioned
        self.relations = self.partitioned.relations
        self.epsilon = relation_epsilon
        self.max_iterations = max_iterations
        variables = translation.flat.variable_map
        self.kinds = {n: variables[n].kind for n in self.partitioned.discrete_variables}
        equations = self.partitioned.discrete_equations
        arguments = [sorted(s.name for s in eq.rhs.free_symbols) for eq in equations]
        functions = compile_functions(arguments, [eq.rhs for eq in equations],
                                      f"the discrete equations of {translation.flat.name}")
        self.equations = [(eq.variable, args, fn, eq.origin)
                          for eq, args, fn in zip(equations, arguments, functions)]
        self._downstream = self._downstream_equations()
        self._selector_names = tuple(parse(s.name) for s in translation.selectors)
        self._vector_plan = None

    def _downstream_equations(self) -> dict[int, list[int]]:
        """For each relation, the discrete equations (in order) its value can reach."""
        readers: dict[str, list[int]] = {}
        for i, (_variable, args, _fn, _origin) in enumerate(self.equations):
            for a in args:
                readers.setdefault(a, []).append(i)
        out = {}
        for k, rel in enumerate(self.relations):
            reached, frontier = set(), [rel.symbol.name]
            while frontier:
                name = frontier.pop()
                for i in readers.get(name, ()):
                    if i not in reached:
                        reached.add(i)
                        frontier.append(self.equations[i][0])
            out[k] = sorted(reached)
        return out

    # -- keys -----------------------------------------------------------------

    def key(self, discrete: Mapping, pre: Mapping, relations, initial: bool) -> tuple:
        out = []
        for name in self._selector_names:
            if name.kind == "relation":
                out.append(bool(relations[name.index]))
            elif name.kind == "initial":
                out.append(bool(initial))
            elif name.kind == "pre":
                out.append(pre[name.base])
            else:
                out.append(discrete[name.text])
        return tuple(out)

    # -- relations --------------------------------------------------------------

    def relation_values(self, system: ModeSystem, t: float, x, previous, exact: bool = False,
                        fired: frozenset = frozenset()):
        """Relation values at ``(t, x)``; with hysteresis against ``previous``.

        Relations in ``fired`` (those whose crossing caused the event) are
        evaluated exactly: their margin has done its job, and in another
        discrete state their arguments may have other units (``sa`` is a
        torque while locked and an acceleration while sliding), so a margin
        in the units of one would wrongly undo the crossing in the other.
        """
        if not self.relations:
            return ()
        raw = system.crossings(t, x)
        out = []
        for k, rel in enumerate(self.relations):
            lhs, rhs = raw[2 * k], raw[2 * k + 1]
            g = lhs - rhs
            if exact or k in fired:
                out.append(rel.holds(g))
            else:
                eps = self.epsilon * max(1.0, abs(lhs), abs(rhs))
                out.append(rel.holds_with_hysteresis(g, previous[k], eps))
        return tuple(out)

    def flipped_relations(self, system: ModeSystem, t: float, x, relations,
                          watched: tuple[int, ...]) -> tuple[int, ...]:
        """The watched relations whose value at ``(t, x)`` differs from ``relations``.

        The hot path of event detection: only the watched relations are
        evaluated (with hysteresis against their current values).
        """
        if not watched:
            return ()
        raw = system.crossings(t, x)
        if len(watched) >= _VECTORISE_FROM:
            return self._flipped_vectorised(raw, relations, watched)
        out = []
        epsilon = self.epsilon
        for k in watched:
            lhs, rhs = raw[2 * k], raw[2 * k + 1]
            eps = epsilon * max(1.0, abs(lhs), abs(rhs))
            if self.relations[k].holds_with_hysteresis(lhs - rhs, relations[k], eps) != relations[k]:
                out.append(k)
        return tuple(out)

    def _flipped_vectorised(self, raw, relations, watched) -> tuple[int, ...]:
        """:meth:`flipped_relations` for many relations at once, with numpy.

        The same arithmetic as :meth:`Relation.holds_with_hysteresis`, written
        so that every operation rounds the same way: ``d * (g ± eps)`` with
        ``d = ±1`` compared with 0 (``>`` for strict relations, ``>=`` not).
        """
        plan = self._vector_plan
        if plan is None or plan[0] is not watched or plan[1] is not relations:
            w = np.array(watched, dtype=int)
            rels = [self.relations[k] for k in watched]
            previous = np.array([relations[k] for k in watched], dtype=bool)
            direction = np.array([1.0 if r.op in (">", ">=") else -1.0 for r in rels])
            strict = np.array([r.op in (">", "<") for r in rels], dtype=bool)
            timed = np.array([r.is_time_event for r in rels], dtype=bool)
            # the margin keeps the previous value: towards it on the side of d
            toward = np.where(previous, direction, -direction)
            plan = self._vector_plan = (watched, relations, w, previous, direction, strict, timed, toward)
        _, _, w, previous, direction, strict, timed, toward = plan
        values = np.asarray(raw, dtype=float)
        lhs, rhs = values[2 * w], values[2 * w + 1]
        with np.errstate(invalid="ignore", over="ignore"):  # inf/NaN sides decide as in Python
            eps = self.epsilon * np.maximum(1.0, np.maximum(np.abs(lhs), np.abs(rhs)))
            eps = np.where(timed, 0.0, eps)
            v = direction * ((lhs - rhs) + toward * eps)
            holds = np.where(strict, v > 0, v >= 0)
        return tuple(w[holds != previous].tolist())

    # -- discrete equations -------------------------------------------------------

    def evaluate_discrete(self, discrete: Mapping, pre: Mapping, relations, initial: bool,
                          relation_free: bool = False) -> dict:
        """One pass over the discrete equations in dependency order.

        With ``relation_free`` only the equations that read no relation are
        evaluated; the others keep their values.
        """
        current = dict(discrete)
        env = dict(current)
        for k, value in enumerate(relations):
            env[relation_name(k)] = value
        env[INITIAL_NAME] = initial
        for name, value in pre.items():
            env[pre_name(name)] = value
        for variable, args, fn, origin in self.equations:
            if relation_free and any(is_relation(a) for a in args):
                continue
            value = fn(*[env[a] for a in args])
            value = bool(value) if self.kinds[variable] == "boolean" else int(value)
            current[variable] = env[variable] = value
        return current

    def relevant_relations(self, discrete: Mapping, relations) -> tuple[int, ...]:
        """State relations whose flip could change something in this discrete state.

        A relation that only matters in another mode (``sa > tau0_max`` while
        sliding) need not be watched: flipping it alone leaves every discrete
        variable as it is.  Relations that select continuous equations are
        always watched.  At the next event all relations are re-evaluated.
        """
        selector_names = {s.name for s in self.translation.selectors}
        # the values every flip is tried against: relations as they are, pre = current
        env = {relation_name(j): value for j, value in enumerate(relations)}
        env[INITIAL_NAME] = False
        for name, value in discrete.items():
            env[pre_name(name)] = value
        env.update(discrete)
        out = []
        for k, rel in enumerate(self.relations):
            if rel.is_time_event:
                continue
            if rel.symbol.name in selector_names:
                out.append(k)
                continue
            if self._flip_changes(k, env, discrete, relations):
                out.append(k)
        return tuple(out)

    def _flip_changes(self, k: int, env: Mapping, discrete: Mapping, relations) -> bool:
        """Whether flipping relation k alone changes a discrete variable (pre = current).

        Only the equations downstream of the relation are evaluated; they see
        ``env`` with the relation flipped.  (A variable they recompute keeps
        its value, or the answer is already yes.)
        """
        flipped = relation_name(k)
        for i in self._downstream[k]:
            variable, args, fn, _origin = self.equations[i]
            value = fn(*[(not relations[k]) if a == flipped else env[a] for a in args])
            value = bool(value) if self.kinds[variable] == "boolean" else int(value)
            if value != discrete[variable]:
                return True
        return False

    # -- event iteration ------------------------------------------------------------

    def iterate(self, t: float, values: Mapping[str, float], pre: Mapping, relations_before,
                initial: bool = False, fired: frozenset = frozenset()) -> EventOutcome:
        """Modelica event iteration at time ``t``.

        Parameters
        ----------
        values : mapping
            Continuous values (states at least) at the event.
        pre : mapping
            Discrete values before the event.
        relations_before : sequence of bool
            Relation values before the event (the hysteresis reference).
        fired : frozenset of int
            Indices of the relations whose crossing caused the event.
        """
        pre = dict(pre)
        first_pre = dict(pre)
        discrete = dict(pre)
        relations = tuple(relations_before)
        history = []
        passes = 0
        for _outer in range(self.max_iterations):
            seen = []
            for _inner in range(self.max_iterations):
                passes += 1
                new_discrete, new_relations = self._pass(t, values, discrete, pre, relations,
                                                         relations_before, initial, fired)
                if new_discrete == discrete and new_relations == relations:
                    break
                state = (tuple(sorted(new_discrete.items())), new_relations)
                if state in seen:
                    # The fixed-point iteration cycles: search for a consistent
                    # assignment instead (as OpenModelica's mixed-system solver does).
                    found = self._search(t, values, pre, new_relations, relations_before, initial, fired,
                                         seen, new_discrete)
                    if found is None:
                        self._fail(t, [dict(d) for d, _ in seen], "the mixed continuous/discrete system")
                    new_discrete, new_relations = found
                seen.append(state)
                discrete, relations = new_discrete, new_relations
            else:
                self._fail(t, history + [discrete], "the mixed continuous/discrete system")
            history.append(dict(discrete))
            if discrete == pre:
                system = self.translation.system(self.key(discrete, pre, relations, initial))
                x = [values[s] for s in system.states]
                full = mode_values(system, t, x)
                changes = tuple((n, first_pre[n], discrete[n]) for n in discrete
                                if discrete[n] != first_pre[n])
                return EventOutcome(discrete, relations, system, full, passes, changes)
            pre = dict(discrete)
            # The new pre values first act on the discrete equations that read no
            # relation: relation values still describe the previous discrete
            # state (sa is an acceleration while sliding, a torque while locked)
            # and must be recomputed before they decide anything.  So a friction
            # element that has just stopped (pre(mode) = Stuck) is tried locked
            # first, and static friction holds a load it can hold.
            discrete = self.evaluate_discrete(discrete, pre, relations, initial, relation_free=True)
        self._fail(t, history, "event iteration")

    def _pass(self, t, values, discrete, pre, relations, relations_before, initial, fired):
        """Solve the continuous part for a guess, then re-evaluate the discrete part."""
        system = self.translation.system(self.key(discrete, pre, relations, initial))
        x = [values[s] for s in system.states]
        new_relations = self.relation_values(system, t, x, relations_before, fired=fired)
        return self.evaluate_discrete(discrete, pre, new_relations, initial), new_relations

    def _search(self, t, values, pre, relations, relations_before, initial, fired, cycle, current):
        """The first consistent assignment with fewest flips from the pre values.

        Only discrete variables that select continuous equations are searched,
        and only those of the components whose variables were cycling; the
        others follow from the discrete equations.
        """
        cycling = {n for (a, _), (b, _) in zip(cycle, cycle[1:] + cycle[:1])
                   for (n, va), (_, vb) in zip(a, b) if va != vb}
        owners = {n.rpartition(".")[0] for n in cycling}
        selectors = [s.name for s in self.translation.selectors
                     if s.name in self.kinds and s.name.rpartition(".")[0] in owners]
        booleans = [n for n in selectors if self.kinds[n] == "boolean"]
        if not booleans:  # nothing continuous to choose: a purely discrete loop
            return None
        base = {**current, **{n: pre[n] for n in booleans}}
        for flips in range(len(booleans) + 1):
            for chosen in itertools.combinations(booleans, flips):
                candidate = dict(base)
                for n in chosen:
                    candidate[n] = not candidate[n]
                try:
                    result, rels = self._pass(t, values, candidate, pre, relations,
                                              relations_before, initial, fired)
                except SimulationError:
                    continue  # e.g. a singular system in an impossible configuration
                if all(result[n] == candidate[n] for n in selectors):
                    return result, rels
        return None

    def _fail(self, t: float, history, what: str):
        changing = sorted({n for a, b in zip(history, history[1:]) for n in a if a[n] != b[n]})
        owners = tuple(dict.fromkeys(n.rpartition(".")[0] for n in changing))
        hint = "the discrete variables named may flip each other back and forth; check the " \
               "conditions that set them"
        own = self.translation.flat.hints_for("event_iteration", owners)
        raise EventIterationError(
            f"{what} at t = {t:.12g} did not converge in {self.max_iterations} iterations; "
            f"still changing: {', '.join(changing) or 'unknown'}",
            hint="; ".join((hint, *own)), components=owners)
