"""Every error acausal raises on purpose.

Each exception subclasses the built-in a Python user would expect
(``ValueError`` for bad models and parameters, ``RuntimeError`` for failures
during simulation), so ``except ValueError`` keeps working.  Messages name the
component, the variable or the equation concerned and end with a hint.

An error keeps its parts as fields: :attr:`AcausalError.message`,
:attr:`AcausalError.hint` and :attr:`AcausalError.components` (the dotted
paths of the components concerned); ``str(error)`` joins message and hint.
The engine has no domain knowledge: where a component knows more about what
went wrong, it says so in its ``hints`` (see :class:`acausal.language.Component`),
and the engine adds that hint to an error that concerns the component.
"""

from __future__ import annotations

__all__ = [
    "AcausalError",
    "ModelDefinitionError",
    "EquationError",
    "ModifierError",
    "ConnectorError",
    "ConnectionError_",
    "ArraySizeError",
    "ArrayIndexError",
    "ModelicaError",
    "ModelicaSyntaxError",
    "ParameterError",
    "TableError",
    "StructuralError",
    "OverDeterminedError",
    "UnderDeterminedError",
    "StructurallySingularError",
    "InitializationError",
    "SimulationError",
    "EventIterationError",
    "ChatteringError",
    "ZenoError",
    "AssertionViolation",
    "SolverError",
    "SettingError",
    "SimulationInterrupted",
    "ReferenceDataError",
    "RedundantConstraintWarning",
    "UnitError",
    "UnitWarning",
    "StartValueWarning",
]


class AcausalError(Exception):
    """Base class of every error acausal raises deliberately.

    Parameters
    ----------
    message : str
        What is wrong, naming the component, variable or equation.
    hint : str, optional
        What the user can do about it.
    components : sequence of str, optional
        Dotted paths of the components concerned (for hints they declare).
    """

    def __init__(self, message: str, hint: str | None = None, components: tuple[str, ...] = ()) -> None:
        self.message = message
        self.hint = hint
        self.components = tuple(components)
        super().__init__(message if hint is None else f"{message}\n  hint: {hint}")

    def with_hint(self, hint: str | None) -> "AcausalError":
        """The same error (type, message, components, cause) with another hint."""
        return self._copy(hint=hint)

    def _copy(self, **changes) -> "AcausalError":
        fields = {"message": self.message, "hint": self.hint, "components": self.components, **changes}
        new = type(self).__new__(type(self))
        AcausalError.__init__(new, fields.pop("message"), fields.pop("hint"), fields.pop("components"))
        for name, value in vars(self).items():
            if name not in ("message", "hint", "components"):
                setattr(new, name, value)
        for name, value in fields.items():
            setattr(new, name, value)
        _same_chain(new, self)
        return new


def _same_chain(new: BaseException, old: BaseException) -> None:
    """``new`` tells the same story as ``old``: cause, context and traceback."""
    new.__cause__, new.__context__ = old.__cause__, old.__context__
    new.__suppress_context__ = old.__suppress_context__
    new.__traceback__ = old.__traceback__


class ModelDefinitionError(AcausalError, ValueError):
    """A model or component is written wrongly (declarations, build)."""


class EquationError(ModelDefinitionError):
    """An equation is not an equation (e.g. a Python bool from ``==``)."""


class ModifierError(ModelDefinitionError, TypeError):
    """A modifier names something the component does not declare."""


class ArraySizeError(ModelDefinitionError):
    """Arrays of different sizes meet: in an equation, a connect(), a modifier or a product.

    The message names both sizes.
    """


class ArrayIndexError(ModelDefinitionError, IndexError):
    """An array is indexed outside its size (Modelica's indices count from 1), or with a non-integer."""


class ModelicaError(AcausalError, ValueError):
    """Modelica text that acausal cannot read or write: an unknown name, an unsupported
    construct, a class acausal's library lacks.  The message names the file and line."""


class ModelicaSyntaxError(ModelicaError, SyntaxError):
    """Modelica text that does not parse: the file, the line, the column and what was expected."""

    def __str__(self) -> str:  # SyntaxError's own __str__ shows only its fields
        return self.args[0] if self.args else ""


class ConnectorError(ModelDefinitionError):
    """A connect() joins incompatible or disabled connectors, or an input is left unconnected.

    Not called ``ConnectionError``, so that it does not shadow the built-in
    (which is about sockets).
    """


#: The earlier name of :class:`ConnectorError`, kept so that ``except ConnectionError_``
#: and ``pytest.raises(ConnectionError_)`` keep working: the same class, not a subclass.
ConnectionError_ = ConnectorError


class ParameterError(ModelDefinitionError):
    """A parameter value is out of its allowed range or malformed."""


class TableError(ParameterError):
    """An interpolation table that cannot be used: a missing file or matrix, a
    wrong shape, abscissae that do not increase where the options need it,
    non-finite entries, an unknown option.  The message names the file (if
    any), the table and the row concerned."""


class StructuralError(AcausalError, ValueError):
    """The equation system is not solvable as posed.

    Attributes
    ----------
    undetermined : tuple of str
        The variables of the under-determined part, when known.
    """

    def __init__(self, message: str, hint: str | None = None, components: tuple[str, ...] = (),
                 undetermined: tuple[str, ...] = ()) -> None:
        super().__init__(message, hint, components)
        self.undetermined = tuple(undetermined)


class OverDeterminedError(StructuralError):
    """More equations than unknowns (in the whole model or one part of it)."""


class UnderDeterminedError(StructuralError):
    """More unknowns than equations."""


class StructurallySingularError(StructuralError):
    """Balanced in count, but some equations cannot be matched to unknowns."""


class InitializationError(AcausalError, ValueError):
    """Initial values are missing, conflicting or cannot be solved."""


class SimulationError(AcausalError, RuntimeError):
    """A simulation stopped before its end; the partial result is attached.

    Attributes
    ----------
    result : acausal.runtime.result.SimulationResult or None
        Everything computed up to the failure.
    """

    def __init__(self, message: str, hint: str | None = None, result=None,
                 components: tuple[str, ...] = ()) -> None:
        super().__init__(message, hint, components)
        self.result = result

    def with_result(self, result) -> "SimulationError":
        """The same error carrying the partial ``result`` of the run it stopped."""
        return self._copy(result=result)


class EventIterationError(SimulationError):
    """Event iteration did not reach a fixed point of the discrete variables."""


class ChatteringError(SimulationError):
    """Too many events in a vanishing window of time."""


class ZenoError(ChatteringError):
    """Events of one relation accumulate at a finite time (Zeno behaviour)."""


class AssertionViolation(SimulationError):
    """An ``Assert`` of level ``"error"`` is violated."""


class SolverError(SimulationError):
    """The numerical integrator or an algebraic solve failed."""


class SettingError(AcausalError, ValueError):
    """A setting of a run (times, interval, tolerances, budgets) is out of range."""


class SimulationInterrupted(KeyboardInterrupt):
    """Ctrl-C during a simulation: the run stopped, and what it computed is kept.

    A :class:`KeyboardInterrupt` (so it still ends a loop of runs and is not
    caught by ``except Exception``) that carries the partial result: status
    -2, everything computed up to the interrupt.

    Attributes
    ----------
    message : str
    hint : str or None
    result : acausal.runtime.result.SimulationResult or None
    """

    def __init__(self, message: str, hint: str | None = None, result=None) -> None:
        self.message = message
        self.hint = hint
        self.components: tuple[str, ...] = ()
        self.result = result
        super().__init__(message)

    def with_result(self, result) -> "SimulationInterrupted":
        """The same interrupt carrying the partial ``result``."""
        new = SimulationInterrupted(self.message, self.hint, result)
        _same_chain(new, self)
        return new


class ReferenceDataError(AcausalError, ValueError):
    """Reference result files are missing or malformed."""


class UnitError(ModelDefinitionError):
    """An equation whose terms have inconsistent units (raised by the strict unit check)."""


class UnitWarning(UserWarning):
    """An equation whose terms have inconsistent units (the unit check's default)."""


class StartValueWarning(UserWarning):
    """States without ``fixed=True`` were initialised from their start values.

    When the initial problem is under-determined, acausal does what Modelica
    tools do: the remaining states take their start values, and this warning
    lists them.
    """


class RedundantConstraintWarning(UserWarning):
    """A discrete state whose equations constrain one motion twice was made solvable.

    Two stuck elements that lock the same motion leave the split of the
    holding force between them open; acausal then leaves one of the two
    constraints out and sets one element's share to zero, as Modelica tools
    pick a split (see :func:`acausal.compiler.structure.relax_redundant`).
    The warning names the equation left out and the variable set to zero.
    """
