"""Modelica's hybrid language: when-clauses, reinit, edge, change, sample, noEvent.

Modelica 3.6, chapter 8 (equations and events) and section 3.7 (built-in
operators), spelt so that a Modelica model reads almost line by line::

    Modelica                                   acausal
    when h <= 0 then                           When(self.h <= 0,
      reinit(v, -e*pre(v));                         reinit(self.v, -self.e*pre(self.v)))
    end when;
    when {sample(0, 0.1), initial()} then      When([sample(0, 0.1), initial()],
      y = u;                                        Eq(self.y, self.u))
    elsewhen c then ... end when;              When(...).elsewhen(c, ...)

The objects here are *declarations* returned from a component's
``equations()`` among its ordinary equations; flattening turns them into
discrete equations (``v = if <fires> then expr else pre(v)``), the
reinitializations of states, the assertions and the terminations that
:mod:`acausal.runtime.events` executes.  ``docs/hybrid.md`` gives the
semantics and the whole table Modelica ↔ acausal.

The event-generating functions (:func:`floor`, :func:`ceil`, :func:`integer`,
:func:`div`, :func:`mod`, :func:`rem`) are sympy functions that flattening
replaces by a value held between events and the two relations that end it;
inside :func:`noEvent` they are the plain mathematical functions.  As in
Modelica, ``abs``, ``sign``, ``min`` and ``max`` (sympy's ``Abs``, ``sign``,
``Min``, ``Max``) generate no events (Modelica 3.6, 3.7.1: they expand into
``noEvent(...)``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Sequence

import sympy as sp
from sympy.core.function import AppliedUndef, UndefinedFunction
from sympy.logic.boolalg import Boolean as SympyBoolean

from .errors import EquationError

__all__ = [
    "When",
    "Reinit",
    "Assert",
    "Terminate",
    "reinit",
    "terminate",
    "edge",
    "change",
    "sample",
    "terminal",
    "noEvent",
    "smooth",
    "Homotopy",
    "homotopy",
    "floor",
    "ceil",
    "integer",
    "div",
    "mod",
    "rem",
    "delay",
    "Delay",
    "EVENT_FUNCTIONS",
]


def _uncached_new(cls, *args):
    # Function.__new__ is cached by argument; building the object directly keeps
    # a Boolean application from being confused with a cached non-Boolean one.
    return sp.Basic.__new__(cls, *map(sp.sympify, args))


def _boolean_function(name: str, doc: str) -> type:
    """A sympy undefined function whose applications are Booleans (usable in And/Or/Not)."""
    function = UndefinedFunction(name, bases=(AppliedUndef, SympyBoolean),
                                 __dict__={"__new__": _uncached_new})
    function.__module__ = __name__
    function.__doc__ = doc
    return function


#: ``sample(start, interval)``: true at the instants ``start + i*interval``
#: (i = 0, 1, ...), each a time event hit exactly; false otherwise.
_Sample = _boolean_function("sample", "sample(start, interval): true at start + i*interval, else false.")

#: ``terminal()``: true in the event iteration at the end of a successful run.
_Terminal = _boolean_function("terminal", "terminal(): true at the end of a successful run.")


class NoEvent(sp.Function):
    """``noEvent(expr)``: relations inside are evaluated literally, no event is generated."""

    nargs = 1

    def fdiff(self, argindex: int = 1):  # d noEvent(u)/du = 1: the chain rule sees through it
        return sp.Integer(1)

    def _eval_is_real(self):
        return self.args[0].is_real


class _EventFunction(sp.Function):
    """An event-generating function: flattening holds its value between events."""

    #: the plain function used under noEvent and to compute the value at events
    plain: Any = None

    def fdiff(self, argindex: int = 1):  # piecewise constant (or linear in the held part)
        return sp.Integer(0)


class floor(_EventFunction):  # noqa: N801 - Modelica's name
    """``floor(x)``: the largest integer not greater than x; an event where it jumps."""

    nargs = 1


class ceil(_EventFunction):  # noqa: N801
    """``ceil(x)``: the smallest integer not less than x; an event where it jumps."""

    nargs = 1


class integer(_EventFunction):  # noqa: N801
    """``integer(x)``: the largest integer not greater than x (an Integer); an event where it jumps."""

    nargs = 1


class div(_EventFunction):  # noqa: N801
    """``div(x, y)``: x/y truncated toward zero; an event where it jumps."""

    nargs = 2


class mod(_EventFunction):  # noqa: N801
    """``mod(x, y) = x - floor(x/y)*y``; an event where it jumps."""

    nargs = 2


class rem(_EventFunction):  # noqa: N801
    """``rem(x, y) = x - div(x, y)*y``; an event where it jumps."""

    nargs = 2

    def fdiff(self, argindex: int = 1):
        return sp.Integer(1) if argindex == 1 else sp.Integer(0)


mod.fdiff = rem.fdiff  # d/dx (x - held*y) = 1

#: The event-generating functions, by class.
EVENT_FUNCTIONS = (floor, ceil, integer, div, mod, rem)


def plain_form(expr: sp.Basic) -> sp.Basic:
    """``expr`` with the event-generating functions as plain mathematics (what noEvent means)."""
    if not isinstance(expr, sp.Basic) or not expr.has(*EVENT_FUNCTIONS):
        return expr
    replacements = {}
    for node in sp.preorder_traversal(expr):
        if isinstance(node, _EventFunction):
            replacements[node] = _plain(node.func, [plain_form(a) for a in node.args])
    return expr.xreplace(replacements)


def without_no_event(expr: sp.Basic) -> sp.Basic:
    """``expr`` with every ``noEvent(u)`` replaced by ``u`` (for code evaluated at events only)."""
    if not isinstance(expr, sp.Basic) or not expr.has(NoEvent):
        return expr
    return expr.replace(lambda node: isinstance(node, NoEvent), lambda node: node.args[0])


def _plain(func: type, args: Sequence[sp.Basic]) -> sp.Basic:
    if func in (floor, integer):
        return sp.floor(args[0])
    if func is ceil:
        return sp.ceiling(args[0])
    x, y = args
    q = x / y
    truncated = sp.Piecewise((sp.floor(q), q >= 0), (sp.ceiling(q), True))
    if func is div:
        return truncated
    if func is mod:
        return x - sp.floor(q) * y
    return x - truncated * y


# -- operators on discrete values ---------------------------------------------------


def _check_symbol(what: str, value: Any) -> sp.Symbol:
    if not isinstance(value, sp.Symbol):
        raise EquationError(f"{what}() takes a variable, not {value!r}",
                            hint=f"write {what}(self.b) with a Boolean, Integer or discrete Real "
                                 f"variable; for an expression, give it a variable of its own")
    return value


def edge(b: sp.Symbol) -> SympyBoolean:
    """``edge(b)``: true at the event where Boolean ``b`` becomes true (``b and not pre(b)``)."""
    from .language import pre  # the language's pre, as a Boolean application
    b = _check_symbol("edge", b)
    return sp.And(b, sp.Not(_boolean_pre(pre, b)))


def change(v: sp.Symbol) -> SympyBoolean:
    """``change(v)``: true at the event where the discrete variable ``v`` changes (``v <> pre(v)``)."""
    from .language import pre
    v = _check_symbol("change", v)
    if v.is_integer or v.is_real:
        return sp.Ne(v, pre(v), evaluate=False)
    return sp.Xor(v, _boolean_pre(pre, v))


_PRE_BOOLEAN: dict = {}


def _boolean_pre(pre, b: sp.Symbol) -> SympyBoolean:
    """``pre(b)`` as a sympy Boolean (And/Or/Not reject plain function applications)."""
    value = pre(b)
    if isinstance(value, SympyBoolean):
        return value
    twin = _PRE_BOOLEAN.get(pre)
    if twin is None:
        twin = _PRE_BOOLEAN[pre] = UndefinedFunction(pre.__name__, bases=(AppliedUndef, SympyBoolean),
                                                     __dict__={"__new__": _uncached_new},
                                                     **dict(pre._kwargs))
    return twin(b)


def sample(start: Any, interval: Any) -> SympyBoolean:
    """``sample(start, interval)``: true at ``start + i*interval`` (i = 0, 1, ...), else false.

    Each instant is a time event computed as ``start + i*interval`` (never by
    adding up intervals), so the instants are exact to round-off however many
    periods pass.  ``start`` and ``interval`` are parameter expressions.
    """
    return _Sample(sp.sympify(start), sp.sympify(interval))


def terminal() -> SympyBoolean:
    """``terminal()``: true in the event iteration at the end of a successful run."""
    return _Terminal()


def noEvent(expr: Any) -> sp.Basic:  # noqa: N802 - Modelica's name
    """``noEvent(expr)``: relations in ``expr`` are evaluated literally, without events.

    Use it where the expression is continuous anyway or must never be
    evaluated outside a domain (``noEvent(if x > 0 then sqrt(x) else 0)``).
    The integrator then steps over the switch, so its error control sees it.
    """
    return NoEvent(sp.sympify(expr))


def smooth(order: int, expr: Any) -> sp.Basic:
    """``smooth(order, expr)``: ``expr`` is ``order`` times continuously differentiable.

    As Modelica allows, a non-negative order means no events are generated
    for the relations inside (the same as :func:`noEvent`); a negative order
    keeps them.
    """
    if int(order) < 0:
        return sp.sympify(expr)
    return NoEvent(sp.sympify(expr))


class Homotopy(sp.Function):
    """``homotopy(actual, simplified)`` as written in an equation (made by :func:`homotopy`).

    Flattening turns it into ``if $homotopy then simplified else actual``
    with a hidden Boolean ``$homotopy`` that only initialization sets (see
    :func:`homotopy`); it never reaches the structural analysis.
    """

    nargs = 2

    def _eval_is_real(self):
        return self.args[0].is_real


def homotopy(actual: Any, simplified: Any) -> sp.Basic:
    """Modelica's ``homotopy(actual, simplified)`` (MLS 3.7.4.4).

    Simulation uses ``actual``. Initialization first solves the problem with
    ``simplified`` in its place, which decides the discrete state (which
    branch of a limiter, which side of a switch), then solves it again with
    ``actual`` from that state: a homotopy path taken in one step, from its
    start (lambda = 0) to its end (lambda = 1). That is how an amplifier with
    positive feedback, whose ``simplified`` expression is its lower limit,
    starts saturated instead of on its unstable equilibrium, as Dymola and
    OpenModelica start it. Where the simplified problem cannot be solved,
    initialization uses ``actual`` alone, which the specification also
    allows.
    """
    actual, simplified = sp.sympify(actual), sp.sympify(simplified)
    if actual == simplified:
        return actual
    return Homotopy(actual, simplified)


# -- delay ----------------------------------------------------------------------------


class Delay(sp.Function):
    """``delay(expr, delayTime[, delayMax])`` as written in an equation (made by :func:`delay`).

    Flattening replaces every application by the value the runtime reads from
    the recorded solution (:mod:`acausal.compiler.delays`).
    """

    nargs = (2, 3)

    def _eval_is_real(self):
        return self.args[0].is_real


def delay(expr: Any, delayTime: Any = None, delayMax: Any = None) -> sp.Basic:  # noqa: N803 - Modelica's names
    """``delay(expr, delayTime)`` or ``delay(expr, delayTime, delayMax)``: ``expr`` delayed.

    The value of ``expr`` at ``time - delayTime``; while ``time - delayTime``
    lies at or before the start time, the value of ``expr`` at the start time
    (Modelica 3.6, 3.7.4.1).

    Parameters
    ----------
    expr : sympy expression
        A Real expression of the model's continuous variables and time.
    delayTime : sympy expression or number
        ``>= 0``.  An expression of parameters is a *fixed* delay; one that
        reads variables (or time) is a *variable* delay and needs ``delayMax``.
    delayMax : sympy expression or number, optional
        An expression of parameters with ``0 <= delayTime <= delayMax`` at
        all times (checked while simulating).

    Raises
    ------
    EquationError
        For a missing ``delayTime``, a negative number as ``delayTime`` or
        ``delayMax``, or ``delayMax`` smaller than a numeric ``delayTime``.
        A variable ``delayTime`` without ``delayMax`` is refused when the model
        is flattened (only then is it known what is a parameter).
    """
    if delayTime is None:
        raise EquationError("delay() needs a delay time: delay(expr, delayTime) or "
                            "delay(expr, delayTime, delayMax)",
                            hint="give the delay time, e.g. delay(self.u, self.T) with a parameter T")
    args = [sp.sympify(expr), sp.sympify(delayTime)]
    if delayMax is not None:
        args.append(sp.sympify(delayMax))
    for what, value in zip(("delayTime", "delayMax"), args[1:]):
        if value.is_number and (not value.is_real or value < 0):
            raise EquationError(f"delay(): {what} = {value} must be a real number >= 0",
                                hint="a delay looks into the past: the delay time is not negative")
    if len(args) == 3 and args[1].is_number and args[2].is_number and args[1] > args[2]:
        raise EquationError(f"delay(): delayTime = {args[1]} exceeds delayMax = {args[2]}",
                            hint="delayMax bounds the delay time from above")
    return Delay(*args)


# -- declarations inside equations() ------------------------------------------------


@dataclass(frozen=True)
class Reinit:
    """``reinit(x, value)``: at the event where its when-clause fires, the state ``x`` becomes ``value``."""

    variable: sp.Symbol
    value: sp.Basic


def reinit(variable: sp.Symbol, value: Any) -> Reinit:
    """``reinit(x, value)`` inside a :class:`When`: set the state ``x`` to ``value`` at the event."""
    if not isinstance(variable, sp.Symbol):
        raise EquationError(f"reinit() takes a variable, not {variable!r}",
                            hint="write reinit(self.v, expression) with a continuous state")
    return Reinit(variable, sp.sympify(value))


@dataclass(frozen=True)
class Terminate:
    """``terminate(message)`` inside a :class:`When`: end the run successfully, giving the reason."""

    message: str


def terminate(message: str) -> Terminate:
    """``terminate(message)`` inside a :class:`When`: end the run successfully with ``message``."""
    return Terminate(str(message))


#: Modelica's AssertionLevel.
ASSERTION_LEVELS = ("error", "warning")


@dataclass(frozen=True)
class Assert:
    """``assert(condition, message, level)``: checked while the model is simulated.

    ``level="error"`` ends the run (keeping what was computed) the first time
    the condition is false; ``level="warning"`` records the message once in the
    result's notes and goes on.  The condition is evaluated without events
    (as Modelica does).
    """

    condition: Any
    message: str
    level: str = "error"

    def __post_init__(self) -> None:
        if self.level not in ASSERTION_LEVELS:
            raise EquationError(f"Assert level {self.level!r} is not one of {ASSERTION_LEVELS}",
                                hint='use level="error" (the default) or level="warning"')


class When:
    """``when condition then equations [elsewhen condition then equations] end when``.

    Parameters
    ----------
    condition : Boolean expression, or a list of them
        The clause fires at the event where the condition *becomes* true; a
        list (Modelica's ``when {c1, c2}``) fires where any of its elements
        becomes true.  ``initial()`` in the list fires during initialization.
    *equations
        ``Eq(v, expr)`` with a discrete variable ``v`` (a Real assigned here is
        a discrete Real: it keeps its value between events), ``reinit(x, expr)``,
        ``terminate(message)`` or ``Assert(...)``; lists are flattened.

    Between events the variables assigned keep their values (``v = pre(v)``).
    A variable may be assigned in one when-clause only.
    """

    def __init__(self, condition: Any, *equations: Any) -> None:
        self.branches: list[tuple[Any, tuple]] = []
        self.elsewhen(condition, *equations)

    def elsewhen(self, condition: Any, *equations: Any) -> "When":
        """Add an ``elsewhen`` branch (it fires only if no earlier branch does); returns self."""
        items: list = []
        stack = list(reversed(equations))
        while stack:
            item = stack.pop()
            if isinstance(item, (list, tuple)):
                stack.extend(reversed(item))
            elif isinstance(item, When):
                raise EquationError("a when-clause inside a when-clause",
                                    hint="Modelica does not nest when-clauses; combine the "
                                         "conditions (And) or use elsewhen")
            else:
                items.append(item)
        conditions = list(condition) if isinstance(condition, (list, tuple)) else [condition]
        if not conditions:
            raise EquationError("a when-clause without a condition")
        for c in conditions:
            if isinstance(c, bool) or not isinstance(c, (sp.Basic, SympyBoolean)):
                raise EquationError(f"when-condition {c!r} is not a Boolean expression",
                                    hint="write a relation (self.h <= 0), a Boolean variable, "
                                         "sample(start, interval) or initial()")
        self.branches.append((tuple(conditions), tuple(items)))
        return self

    def _sympy_(self):
        # sympify(When(...)): the clause was put inside an expression, e.g. an if-branch
        raise EquationError("a when-clause inside an expression (an if-branch of an equation?)",
                            hint="Modelica allows when-clauses only at the top of equations(); "
                                 "put the condition into the when-condition instead: "
                                 "When(sp.And(c, cond), ...)")

    def __repr__(self) -> str:
        parts = [f"{'when' if k == 0 else 'elsewhen'} {list(c) if len(c) > 1 else c[0]}: {list(items)}"
                 for k, (c, items) in enumerate(self.branches)]
        return f"When({'; '.join(parts)})"
