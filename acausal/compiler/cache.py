"""What the systems of one model share: parameters, names and per-stage memos.

The discrete states of a hybrid model have most equations in common.  What a
stage derived from one equation (its specialisation, alias form, time
derivative, block solution, printed code) is kept here for the next state, so
that only the first state of a model pays full price.  Everything here is
valid for one flat model and its parameter values only, like the
:class:`~acausal.compiler.translate.Translation` that owns it.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Mapping

import sympy as sp

from ..language import parameter_symbols, real_symbol
from ..names import der_name
from .algebraic import AlgebraicMemo
from .alias import AliasMemo
from .codegen import CodegenMemo, python_identifiers
from .flatten import FlatModel
from .structure import StructureMemo

__all__ = ["ParameterTable", "SpecialiseMemo", "ModelCache"]


@dataclass(frozen=True)
class ParameterTable:
    """The numeric parameters of a flat model, in every form the stages need.

    Attributes
    ----------
    names : tuple of str
        In declaration order: the order of the generated code's ``p`` vector.
    values : mapping
        ``name -> value``.
    vector : tuple of float
        The values in the order of ``names``.
    symbols : mapping
        ``symbol -> sympy Float``, for substitution.
    zeros : mapping
        ``symbol -> 0`` for the parameters that are zero: structural zeros.
    """

    names: tuple[str, ...]
    values: Mapping[str, float]
    vector: tuple[float, ...]
    symbols: Mapping[sp.Symbol, sp.Float] = field(repr=False)
    zeros: Mapping[sp.Symbol, sp.Integer] = field(repr=False)

    @classmethod
    def of(cls, flat: FlatModel) -> "ParameterTable":
        names = tuple(p.name for p in flat.parameters)
        values = dict(flat.parameter_values)
        return cls(names, values, tuple(values[n] for n in names), parameter_symbols(values),
                   {real_symbol(n): sp.Integer(0) for n, v in values.items() if v == 0})

    def restricted(self, names) -> "ParameterTable":
        """The table of ``names`` only (in this table's order): the parameters of one cluster.

        Its cost follows ``names``, not the whole table: a model of N parts
        restricts it N times."""
        position, symbol_of = self._lookup
        kept = tuple(sorted(set(names), key=position.__getitem__))
        values = {n: self.values[n] for n in kept}
        symbols = [symbol_of[n] for n in kept]
        zeros = self.zeros
        return ParameterTable(kept, values, tuple(values[n] for n in kept),
                              {s: self.symbols[s] for s in symbols},
                              {s: zeros[s] for s in symbols if s in zeros})

    @functools.cached_property
    def _lookup(self) -> tuple[dict[str, int], dict[str, sp.Symbol]]:
        """Each name's position and symbol (made once: :meth:`restricted` is called per part)."""
        return ({n: k for k, n in enumerate(self.names)}, {s.name: s for s in self.symbols})


@dataclass(eq=False)
class SpecialiseMemo:
    """Equations specialised to values of the discrete symbols they contain."""

    used: dict = field(default_factory=dict)  #: residual -> the discrete symbols in it
    forms: dict = field(default_factory=dict)  #: (residual, their values) -> specialised residual
    #: the substitution once per shape (:func:`~acausal.compiler.canonical.substituted`)
    shapes: dict = field(default_factory=dict)


@dataclass(eq=False)
class ModelCache:
    """The work the systems of one model share (see the module docstring).

    Attributes
    ----------
    parameters : ParameterTable
    identifiers : mapping
        One Python identifier per model name, the same in every system's code:
        parameters, continuous variables and their first and second
        derivatives (which index reduction may add), named up front so the
        names do not depend on the order in which discrete states are compiled.
    specialise, alias, structure, algebraic, codegen
        The memo of each stage.
    """

    parameters: ParameterTable
    identifiers: Mapping[str, str]
    specialise: SpecialiseMemo = field(default_factory=SpecialiseMemo)
    alias: AliasMemo = field(default_factory=AliasMemo)
    structure: StructureMemo = field(default_factory=StructureMemo)
    algebraic: AlgebraicMemo = field(default_factory=AlgebraicMemo)
    codegen: CodegenMemo = field(default_factory=CodegenMemo)

    @classmethod
    def of(cls, flat: FlatModel) -> "ModelCache":
        parameters = ParameterTable.of(flat)
        continuous = [v.name for v in flat.variables if not v.is_discrete]
        # derivatives up to the order index reduction usually reaches (a third derivative in
        # a block diagram that differentiates a filter's output); generate adds higher ones
        identifiers = python_identifiers([*parameters.names, *continuous,
                                          *(der_name(n, order) for order in (1, 2, 3) for n in continuous)])
        return cls(parameters, identifiers)

    def for_cluster(self, parameter_names) -> "ModelCache":
        """The cache of one cluster's systems: its parameters, the model's identifiers and
        specialisations, its own stage memos (alias elimination's is tied to a set of
        variables, the others to a set of parameter values) but the model's work per shape
        (:mod:`~acausal.compiler.canonical`: independent of names and values, so N equal
        units compiled apart are derived once and renamed)."""
        return ModelCache(self.parameters.restricted(parameter_names), self.identifiers,
                          specialise=self.specialise, alias=AliasMemo(shapes=self.alias.shapes),
                          structure=StructureMemo(shapes=self.structure.shapes),
                          algebraic=AlgebraicMemo(shapes=self.algebraic.shapes),
                          codegen=CodegenMemo(templates=self.codegen.templates))
