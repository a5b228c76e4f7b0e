"""Other parameter values with the compiled systems of a translation: rebinding.

The generated code reads its parameters from a vector, so a system compiled
for one set of values serves another, given its vector
(:meth:`Rebinding.rebound`).  What the values decided while translating must
still hold: the parameters relations were decided from keep their values, a
solution that divides by an expression of parameters stays away from zero
(:attr:`~acausal.compiler.algebraic.AlgebraicResult.nonzero`), and Newton's
guesses taken from start values are those of the new values; otherwise the
system is compiled anew.

:class:`Rebinding` is the part of :class:`~acausal.compiler.translate.Translation`
that does this; it reads the translation's ``flat``, ``partitioned``,
``cache``, ``continuous`` and ``rebound_from``, and adds to ``notes``.
"""

from __future__ import annotations

import dataclasses
import time as _time

import sympy as sp

from .algebraic import NewtonSolve
from .clusters import ComposedSystem
from .flatten import FlatModel
from .initial import InitialSystem, StartValues, bind_start_values, check_fixed_constants, newton_guesses
from .modes import ModeSystem, alias_plan

__all__ = ["Rebinding"]


class Rebinding:
    """Serving other parameter values with compiled systems (see the module docstring)."""

    def rebound(self, flat: FlatModel, flatten_seconds: float = 0.0) -> "Rebinding | None":
        """A translation (of this translation's class) of ``flat`` (this model's structure with other numeric
        parameter values) that reuses this one's compiled systems, or None.

        The generated code reads its parameters from a vector, so a compiled
        system serves other values as they are, given its new vector.  What
        the values decided while translating must still hold: parameters of
        relations decided from the parameters alone keep their values (else
        None: translate anew), and a system whose solution divides by an
        expression of parameters that is zero for the new values is compiled
        anew (:attr:`AlgebraicResult.nonzero`).
        """
        old = self.parameter_values
        new = flat.parameter_values
        if any(old[n] != new[n] for n in self.partitioned.evaluated_parameters):
            return None
        partitioned = dataclasses.replace(self.partitioned, flat=flat)
        translation = type(self)(flat, partitioned, flatten_seconds, self.demand,
                                  clusters=self.clustering is not None, clustering=self.clustering,
                                  redundant_constraints=self.redundant_constraints, options=self.options)
        translation.rebound_from = self
        return translation

    def _rebind(self, key: tuple) -> ModeSystem | None:
        """The system of ``key`` compiled by :attr:`rebound_from`, bound to this one's parameters."""
        if self.rebound_from is None:
            return None
        # compiled by the first translation of the structure, with its memos (its values
        # decide nothing the structure does not, but which coefficients are non-zero)
        base = self.rebound_from
        source = base.system(key)
        if isinstance(source, ComposedSystem):  # the other translation compiles by parts
            return None
        if source.structure is None:
            # loaded from disk: rebinding needs its stages (compiled once, then every value rebinds)
            source = base._build_whole(key)
            base._store(base.systems, key, source)
        if not self._guards_hold(source.algebraic) or not self._guesses_hold(source):
            return None
        return _bind_mode(source, self.cache.parameters)

    def _guards_hold(self, algebraic) -> bool:
        if algebraic is None:  # a system loaded from the persistent cache: no guards known
            return False
        symbols = self.cache.parameters.symbols
        return all(not sp.sympify(g).xreplace(symbols).is_zero for g in algebraic.nonzero)

    def _guesses_hold(self, source: ModeSystem) -> bool:
        """Whether the first guesses of ``source``'s Newton iterations, start values its code
        holds as numbers, are this translation's (else it is compiled anew, with a note)."""
        if not self._other_starts() or not any(isinstance(step, NewtonSolve) for step in source.algebraic.steps):
            return True
        starts = StartValues(source.aliases.aliases, source.aliases.variables, self.continuous,
                             self.cache.parameters.symbols)
        for name, expression, value in newton_guesses(source.algebraic, starts):
            if value != source.aliases.variables[name].start:
                self._note_guess(name, expression, self._where("the system", source.description))
                return False
        return True

    def _other_starts(self) -> bool:
        """Whether this translation's tunable start values differ from :attr:`rebound_from`'s
        (computed once: a sweep over parameters alone never looks at Newton guesses)."""
        found = self.extras.get("other starts")
        if found is None:
            base = self.rebound_from.flat.variable_map
            found = self.extras["other starts"] = any(
                base[n].start != self.continuous[n].start for n in self.flat.tunable_starts)
        return found

    def _where(self, what: str, description: str) -> str:
        """``what`` ('the system', ...) of the discrete state ``description``, in words."""
        return f"{what} of discrete state {description}" if self.partitioned.is_hybrid else what

    def _note_guess(self, name: str, expression: sp.Expr, where: str) -> None:
        """Note that a start value given at run time made a system be compiled anew."""
        given = ", ".join(sorted(s.name for s in expression.free_symbols))
        self.notes.append(f"{given} is the first guess of a Newton iteration for {name} in {where}, which "
                          f"its code holds as a number: that system was compiled anew for this start value")

    def _bound_initial(self, source: InitialSystem, mode: ModeSystem, parameters) -> InitialSystem | None:
        """``source`` bound to ``parameters`` (None: its Newton guesses are other start values, noted)."""
        bound = _bind_initial(source, mode, parameters)
        if bound is None:
            name, expression, _ = next(g for g in source.starts.guesses
                                       if float(g[1].xreplace(parameters.symbols)) != g[2])
            self._note_guess(name, expression, self._where("the initialization problem", mode.description))
        return bound


def _bind_mode(source: ModeSystem, parameters) -> ModeSystem:
    """``source``'s compiled system bound to the values of ``parameters`` (a ParameterTable)."""
    t0 = _time.perf_counter()
    derivatives, crossings, outputs = source.code.make(parameters.vector)
    plan = alias_plan(source.aliases, parameters.symbols)
    return dataclasses.replace(source, derivatives=derivatives, crossings=crossings, outputs=outputs,
                               alias_plan=plan, passes=(("rebind", _time.perf_counter() - t0),))


def _bind_initial(source: InitialSystem, mode: ModeSystem, parameters) -> InitialSystem | None:
    """``source``'s initialization problem bound to ``parameters`` (start values included), its
    fixed constants checked; None when its code holds other start values as Newton guesses."""
    t0 = _time.perf_counter()
    check_fixed_constants(mode.aliases, parameters.symbols)
    bound = bind_start_values(source, parameters.symbols)
    if bound is None:
        return None
    _, _, outputs = source.code.make(parameters.vector)
    return dataclasses.replace(bound, outputs=outputs, passes=(("rebind", _time.perf_counter() - t0),))


