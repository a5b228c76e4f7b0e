"""How the engine works, as one value passed through :func:`translate` and :func:`simulate`.

Every field switches a way of doing the same thing: the results are the same
either way (tests compare both settings; ``parts_apart`` within the solver's
tolerance), only the work done differs.  They
exist so that a user, a test or a benchmark can see what each technique buys,
for one call, without changing a module-level flag that every other call in
the process would see.

>>> from acausal import EngineOptions
>>> EngineOptions(clusters=False)          # the whole model compiled per discrete state
EngineOptions(clusters=False, templates=True, secant=True, incremental_events=True, parts_apart=True)

The compiler's fields (:attr:`EngineOptions.compiler_fields`) are part of the
key of a translation in the in-process cache; the runtime's are read by each
run.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

from .errors import SettingError

__all__ = ["EngineOptions", "DEFAULT_OPTIONS"]


@dataclass(frozen=True)
class EngineOptions:
    """Switches of the engine's techniques; the defaults are what a user wants.

    Parameters
    ----------
    clusters : bool
        A hybrid model made of independent parts compiles one system per part
        and part mode (:mod:`acausal.compiler.clusters`) instead of one system
        of the whole model per discrete state.
    templates : bool
        Flattening and partitioning reuse the work done for one instance of a
        component's equations for the other instances (equation templates);
        False derives every instance's equations anew.
    secant : bool
        A single zero crossing in a step is located by the secant-bracketing
        method on the step's dense output; False uses the generic bisection of
        every candidate.
    incremental_events : bool
        Event iteration re-evaluates only the discrete equations downstream of
        what changed since its last pass; False evaluates every equation in
        every pass.
    parts_apart : bool
        Independent parts whose discrete part links no two of them are each
        integrated with a solver of their own (:mod:`acausal.runtime.part_runs`);
        False integrates all parts with one solver.  The results agree within
        the solver's tolerance (the step sizes differ), not bit for bit.
    part_shapes : bool
        A part equal to an earlier one up to its names takes the earlier
        part's generated code, bound to its own parameters
        (:mod:`acausal.compiler.part_shapes`); False compiles every part for
        itself.  The results are the same bit for bit.
    """

    clusters: bool = True
    templates: bool = True
    secant: bool = True
    incremental_events: bool = True
    parts_apart: bool = True
    part_shapes: bool = True

    #: the fields that change what the compiler produces (the rest only how a run goes)
    compiler_fields = ("clusters", "templates", "part_shapes")

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if not isinstance(value, bool):
                raise SettingError(f"EngineOptions.{f.name} must be True or False, not {value!r}",
                                   hint="every field switches one technique on or off")

    @property
    def compiler_key(self) -> tuple[bool, ...]:
        """The values of :attr:`compiler_fields`, for cache keys."""
        return tuple(getattr(self, name) for name in self.compiler_fields)


#: The options every call uses unless it is given others.
DEFAULT_OPTIONS = EngineOptions()
