"""What the runtime needs of a compiled model: the contract between compiler and runtime.

Like scipy's ``OdeSolver``/``DenseOutput`` for its integrators, these
Protocols state what the runtime calls, and nothing more.  The compiler's
:class:`~acausal.compiler.translate.Translation` and its systems
(:class:`~acausal.compiler.modes.ModeSystem`,
:class:`~acausal.compiler.clusters.ComposedSystem`) satisfy them without
importing this module; the runtime imports no compiler module at import time
and generates no code: what needs the symbolic model (the discrete program,
time-event instants, clock ticks, delay times, the numpy forms of generated
functions, the system of a discrete state not visited yet) it asks of the
compiled model through the methods below.

Two kinds of member:

* **Callbacks into the compiler** (methods): :meth:`CompiledModel.system`
  compiles a discrete state on its first visit; the others turn symbolic
  expressions into numbers or functions once per run or translation.
* **Data** (attributes): :attr:`CompiledModel.data`, the names, kinds,
  relations and parameters the runtime reads, as plain values
  (:class:`~acausal.compiler.compiled.ModelData`, which pickles and loads
  without sympy); the compiled systems; bookkeeping (notes, timings).  The
  compiled functions themselves still come from the compiler's generated
  code: a compiled model saved whole and loaded without sympy (the warm
  command) is what comes next (``docs/architecture.md``).

``tests/runtime/test_contract.py`` checks that the compiler's objects
satisfy these Protocols and that importing the runtime loads neither sympy
nor networkx.
"""

from __future__ import annotations

from typing import Any, Callable, Mapping, Protocol, runtime_checkable

from ..compiler.compiled import ModelData

__all__ = ["CompiledModel", "CompiledSystem", "is_compiled_model"]


@runtime_checkable
class CompiledSystem(Protocol):
    """The continuous system of one discrete state, compiled to functions.

    ``x`` is the state vector in the order of :attr:`states`; ``t`` the time.
    """

    #: the values of the model's selectors for this discrete state
    key: tuple
    #: state names, in the order of the state vector
    states: tuple[str, ...]
    #: the algebraic unknowns :attr:`outputs` gives, in order
    unknowns: tuple[str, ...]
    #: ``(name, coefficient, source)`` of each alias: ``name = coefficient * source``
    #: (``name = coefficient`` when source is None)
    alias_plan: tuple
    #: ``derivatives(t, x)`` -> the state derivatives (a sequence of floats)
    derivatives: Callable
    #: ``crossings(t, x)`` -> ``lhs - rhs`` of every relation (and the sides)
    crossings: Callable
    #: ``outputs(t, x)`` -> the values of :attr:`unknowns`
    outputs: Callable
    #: the names of the derivatives of :attr:`states` (columns of the result)
    derivative_names: tuple[str, ...]
    #: the generated source of the system's code (a failing line is looked up in it)
    sources: tuple[str, ...]

    @property
    def description(self) -> str:
        """The discrete state in words, for messages."""

    def values(self, t: float, x) -> dict[str, float]:
        """Every state and unknown by name at ``(t, x)``."""

    #: the independent parts' own systems (a model compiled part by part), or None
    parts: tuple | None

    def crossings_for(self, relations: tuple[int, ...]) -> Callable:
        """A ``crossings`` that computes at least the values of ``relations`` (the
        model's indices): a system of parts calls only the parts that own them."""

    def vectorised(self, name: str) -> Callable | None:
        """The numpy form of ``crossings`` or ``outputs`` (``f(t, X)`` for many
        times at once, bit for bit the scalar function's values), or None."""

    # Optional (not a member here: a system of parts has none): ``relaxed``, what a
    # discrete state that constrains one motion twice left out (the run warns of it;
    # None: nothing); ``vectorised_crossings_for(relations)``, the numpy form of ``crossings``
    # giving the sides of ``relations`` only (rows 2j, 2j + 1 for ``relations[j]``), bit
    # for bit those rows of ``vectorised("crossings")``, or None.  The crossing watch
    # checks a step's samples with it (RelationEvaluator.first_flip).  Likewise
    # ``crossings_of(relations)``: the scalar ``crossings`` giving the sides of
    # ``relations`` only (``lhs, rhs`` of each in turn), bit for bit those values of
    # ``crossings``, or None; the watch decides single instants with it (a step's few
    # samples, the step's end, the trial points of the search of a flip instant).


@runtime_checkable
class CompiledModel(Protocol):
    """A model compiled for the runtime (the compiler's ``Translation``)."""

    #: names, kinds and starts of the variables, parameters and their vector, relations,
    #: clocks, delays, selectors, hints: plain values
    #: (:class:`~acausal.compiler.compiled.ModelData`)
    data: ModelData
    #: the outputs asked for (None: every variable)
    demand: frozenset[str] | None
    #: the engine's switches (:class:`~acausal.options.EngineOptions`)
    options: Any
    #: what a run should add to its result's notes
    notes: list[str]
    #: scratch space the runtime keeps per compiled model (its event evaluators)
    extras: dict
    #: the systems compiled so far, by discrete state
    systems: Mapping[tuple, CompiledSystem]
    #: the initialization systems compiled so far (each answers ``outputs`` and ``reset()``
    #: as a :class:`CompiledSystem` does)
    initial_systems: Mapping[tuple, Any]

    @property
    def translation_seconds(self) -> float:
        """Seconds spent translating and compiling so far."""

    @property
    def compiled_systems(self) -> int:
        """How many systems were compiled."""

    def system(self, key: tuple) -> CompiledSystem:
        """The system of the discrete state ``key`` (the values of ``data.selectors``),
        compiled on its first visit: the one callback that compiles."""

    def initial_system(self, key: tuple) -> Any:
        """The initialization system of the discrete state ``key``."""

    def discrete_program(self, impure_call: Callable) -> Any:
        """The compiled discrete equations, reinits, terminations and assertions
        (:class:`~acausal.compiler.discrete.DiscreteProgram`); each call site of an
        impure function calls ``impure_call(site, function class, *args)``."""

    def time_events(self) -> tuple[tuple, tuple]:
        """``(roots, held)``: ``(relation index, instant)`` of every time event of
        parameters alone, and ``(relation index, names, root)`` of those whose
        instant is ``root(*held values of names)``."""

    def clock_ticks(self) -> tuple[tuple[float, float], ...]:
        """``(start, interval)`` of every sample clock."""

    def delay_numbers(self) -> dict[int, float]:
        """Delay index -> its delay time (fixed) or its ``delayMax`` (variable)."""

    def reset_warm_starts(self) -> None:
        """Every system compiled so far forgets what its functions keep between calls (each
        Newton solve's last solution and Jacobian, its warm start): called when a run
        begins, so that every run of a compiled model gives the same numbers."""

    def part_models(self) -> tuple[tuple, str]:
        """The model's independent parts as compiled models of their own, to run each with
        a solver of its own (:mod:`acausal.runtime.part_runs`), or ``((), why not)``:
        ``"the model is one part"``, or what links the parts."""

    def start_value_relations(self, start_time: float) -> tuple[bool, ...]:
        """Each relation evaluated with the start values (the initial guess of
        the discrete state)."""


def is_compiled_model(obj: Any) -> bool:
    """Whether ``obj`` is a compiled model rather than a model to translate.

    Decided on the class's methods (``isinstance`` with a runtime-checkable
    Protocol would evaluate the properties on Python < 3.12)."""
    cls = type(obj)
    return all(callable(getattr(cls, name, None)) for name in ("system", "discrete_program", "time_events"))
