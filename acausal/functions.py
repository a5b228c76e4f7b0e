"""Functions for equations: a signal whose time derivatives are given.

:func:`prescribed` is Modelica's ``derivative`` annotation with
``noDerivative`` for the one case models need it: a value that comes with its
time derivatives as separate signals (an input and the inputs carrying its
first and second derivatives).  Where index reduction differentiates the
value, it takes the given derivative instead of differentiating the signal.

:class:`ImpureFunction` is Modelica's ``impure function`` with a hidden state
(a random number generator): its state belongs to the simulation run, and at
an event its value is computed once per call site however often event
iteration evaluates the equation (see its docstring).
"""

from __future__ import annotations

import re

import sympy as sp

from .errors import ModelDefinitionError, SolverError, StructuralError
from .language import time as _time

__all__ = ["ImpureFunction", "impure_applications", "prescribed", "settle"]

#: (name, number of derivatives given, differentiate_last, hint) -> class; the same call
#: always gives the same class, so equations built twice compare equal.
_CLASSES: dict[tuple[str, int, bool, str | None], type] = {}

_DEFAULT_HINT = ("give the next derivative as well, or change the model so that it needs fewer "
                 "derivatives of this value")


def prescribed(value, *derivatives, time=_time, name: str, hint: str | None = None,
               differentiate_last: bool = False) -> sp.Expr:
    """``value``, whose time derivatives are the given ``derivatives``.

    The result is a sympy expression equal to ``value`` whose time derivative
    is ``derivatives[0]``, whose second time derivative is
    ``derivatives[1]``, and so on; its partial derivatives with respect to
    ``value`` and ``derivatives`` are 0 (Modelica's ``noDerivative``).  Index
    reduction therefore uses the given signals where it needs derivatives of
    ``value`` instead of differentiating it (it may be an input that cannot
    be differentiated).  The signals are meant to be consistent
    (``derivatives[0]`` the derivative of ``value``, ...), but nothing checks
    that.

    Parameters
    ----------
    value : sympy expression or number
        The value (order 0).
    *derivatives : sympy expressions or numbers
        Its first, second, ... time derivatives.  None given: the value may
        not be differentiated at all (unless ``differentiate_last``).
    time : sympy expression, keyword-only
        The independent variable, :data:`acausal.language.time` by default;
        it carries the time dependence (the derivative annotation's dummy
        input), and differentiating with respect to it moves to the next
        derivative.
    name : str, keyword-only
        Whose value this is, e.g. the dotted path of the component and its
        signal (``"drive.phi"``).  Error messages name it, and it names the
        function: dots and other characters that are not valid in a Python
        identifier become ``_`` and ``_prescribed`` is appended
        (``drive_phi_prescribed``; ``_prescribed_open`` with
        ``differentiate_last``).
    hint : str, optional
        What to do when the model needs a derivative beyond the last one
        given (the hint of the :class:`~acausal.errors.StructuralError`).
    differentiate_last : bool, default False
        What a derivative beyond the last one given is.  False: the model is
        refused (the last derivative function has no ``derivative``
        annotation of its own).  True: the last given derivative is the plain
        expression ``derivatives[-1]``, differentiated like any other (as a
        Modelica tool differentiates the body of the last derivative function
        when it needs more, e.g. for ``Move_w`` in the MSL's
        ``AngleToTorqueAdaptor``).

    Returns
    -------
    sympy expression
        An application of a :class:`sympy.Function` class to ``(0, value,
        *derivatives, time)``, the first argument being the order of the
        derivative: evaluated (in generated code, by ``_imp_``) it is
        ``value``, and its ``k``-th time derivative is the same function
        applied to ``(k, value, *derivatives, time)``, which evaluates to
        ``derivatives[k - 1]``.  The same ``name``, number of derivatives,
        ``hint`` and ``differentiate_last`` always give the same class.  With
        ``differentiate_last`` and no derivatives, ``value`` itself.

    Raises
    ------
    StructuralError
        When the model needs a time derivative of higher order than the
        derivatives given (raised while index reduction differentiates).
    ModelDefinitionError
        For an empty ``name``.

    Notes
    -----
    The partial derivatives with respect to the signals are 0, so a signal
    must not be an unknown of an algebraic loop through this function: its
    Jacobian is not defined there (as for the Modelica functions with
    ``noDerivative``).

    References
    ----------
    .. [1] Modelica Association, "Modelica Language Specification, Version
       3.6", 2023, section 12.7.1 "Using the Derivative Annotation",
       https://specification.modelica.org/maint/3.6/functions.html#using-the-derivative-annotation

    Examples
    --------
    >>> from acausal.language import real_symbol, time
    >>> p, v, a = (real_symbol(n) for n in ("p", "v", "a"))
    >>> x = prescribed(p, v, a, name="drive.p")
    >>> x
    drive_p_prescribed(0, p, v, a, time)
    >>> x.diff(time), x.diff(time, 2)
    (drive_p_prescribed(1, p, v, a, time), drive_p_prescribed(2, p, v, a, time))
    >>> x.diff(p)
    0
    >>> prescribed(p, v, name="drive.p", differentiate_last=True).diff(time)
    v
    """
    if not isinstance(name, str) or not name:
        raise ModelDefinitionError(f"prescribed(): the name must be a non-empty string, not {name!r}",
                                   hint="name the value's owner, e.g. the component path and the signal")
    if differentiate_last and not derivatives:
        return sp.sympify(value)
    return _function_class(name, len(derivatives), bool(differentiate_last), hint)(0, value, *derivatives, time)


def settle(expr: sp.Expr) -> sp.Expr:
    """``expr`` with every application of a function that only carries given
    derivatives replaced by the expression it evaluates to.

    A function with given derivatives (:func:`prescribed`, Modelica's
    ``derivative`` annotation with ``noDerivative``) matters to index
    reduction only: differentiating it takes the next given signal.  Its
    *value* depends on one argument alone (``prescribed(p, u1, u2)`` is
    ``p``), so once the equations have been differentiated as far as index
    reduction needs, the engine settles them: matching, sorting and code see
    what the value really depends on (matching ``u2`` to the equation of its
    order-0 value would be structurally wrong, as a Modelica tool that
    inlines the function never does).

    The protocol is generic: any :class:`sympy.Function` subclass with a
    method ``settled()`` is replaced by what that method returns.
    """
    if not isinstance(expr, sp.Basic) or not any(hasattr(type(f), "settled") for f in expr.atoms(sp.Function)):
        return expr
    return expr.replace(lambda e: isinstance(e, sp.Function) and hasattr(type(e), "settled"),
                        lambda e: e.settled())


class _Prescribed(sp.Function):
    """A value given with ``given`` time derivatives (made by :func:`prescribed`).

    Arguments ``(order, value, derivative_1, ..., derivative_given, time)``:
    the application is the time derivative of order ``order`` (an integer),
    so its value is the argument of that order; its time derivative is the
    same function at ``order + 1``.  One class serves every order, so that
    the functions the generated code calls (the derivatives index reduction
    makes) are all in the flat model's equations, which is where the engine
    finds them when it loads compiled code from its disk cache.
    """

    owner: str = ""
    given: int = 0
    differentiate_last: bool = False
    advice: str | None = None

    @classmethod
    def eval(cls, order, *args):
        if isinstance(order, sp.Integer) and all(isinstance(a, sp.Number) for a in args):
            return args[int(order)]
        return None

    def fdiff(self, argindex: int = 1):
        if argindex != len(self.args):  # the order or a signal: never differentiated (noDerivative)
            return sp.Integer(0)
        order, signals = int(self.args[0]), self.args[1:-1]
        following = order + 1
        if self.differentiate_last and following == self.given:
            return signals[following]
        if following > self.given:
            given = (f"only derivatives up to order {self.given} are given" if self.given
                     else "no derivative of it is given")
            raise StructuralError(f"{self.owner}: the model needs the time derivative of order "
                                  f"{following} of this value, but {given}",
                                  hint=self.advice or _DEFAULT_HINT)
        return self.func(following, *self.args[1:])

    def _eval_evalf(self, prec):
        return self.args[1 + int(self.args[0])].evalf(prec)

    def settled(self) -> sp.Expr:
        """The signal this application evaluates to (see :func:`settle`)."""
        return self.args[1 + int(self.args[0])]

    def _eval_is_real(self):
        return self.args[1 + int(self.args[0])].is_real

    def __reduce_ex__(self, protocol):
        return _apply, (self.owner, self.given, self.differentiate_last, self.advice, self.args)


def _apply(owner: str, given: int, differentiate_last: bool, advice: str | None, args: tuple) -> sp.Expr:
    """The function applied to ``args`` (how an application is unpickled)."""
    return _function_class(owner, given, differentiate_last, advice)(*args)


def _function_class(owner: str, given: int, differentiate_last: bool, advice: str | None) -> type:
    key = (owner, given, differentiate_last, advice)
    cls = _CLASSES.get(key)
    if cls is None:
        ident = re.sub(r"[^0-9A-Za-z_]", "_", owner)
        suffix = "_open" if differentiate_last else ""

        def value_of(order, *signals):  # evaluated in generated code: the signal of this order
            return signals[order]

        cls = _CLASSES[key] = type(f"{ident}_prescribed{suffix}", (_Prescribed,), {
            "__module__": __name__,
            "__doc__": f"{owner} and its time derivatives (made by prescribed()).",
            "nargs": given + 3,
            "owner": owner,
            "given": given,
            "differentiate_last": differentiate_last,
            "advice": advice,
            "_imp_": staticmethod(value_of),
        })
    return cls


class ImpureFunction(sp.Function):
    """A function of the equations with a side effect on a state the run owns
    (Modelica's ``impure function`` with a hidden state, e.g. a random number generator).

    A subclass names its state, :attr:`stream` (the functions that share one
    generator name the same one), and computes its value in
    :meth:`_impure_` from that state, which it may change: a ``dict``, empty
    when the run starts, that the subclass fills on its first call.

    The runtime gives these functions Modelica's semantics of a call in a
    when-clause:

    * **one value per event and call site.**  Each application in the
      discrete equations is a call site (one per distinct application in an
      equation; sympy merges identical ones within an expression).  The first
      evaluation at an event iteration (the initialization's, or one event's)
      computes the value and changes the state; every later evaluation of the
      same site in that iteration (its passes, its searches) returns that value,
      so the state advances once per firing, in the order in which the events
      happen.  What the site's arguments are at later evaluations of the same
      iteration does not matter.
    * **the state belongs to the run.**  Each run starts from empty states
      (``DiscreteEvaluator.start_run``, called when initialization begins), so
      two runs of one model give the same values.
    * **outside event iteration** (asking whether a relation could change the
      discrete state) the value is computed from a copy of the state: the value
      the next event would give, with no side effect.

    An impure function is meant for when-clauses (its value is held between
    events); in a continuous equation it is refused when evaluated.  Applied
    to numbers it stays a call: it is never evaluated while the model is
    translated.
    """

    #: the name of the state this function reads and changes (one per generator)
    stream: str = ""

    @classmethod
    def _impure_(cls, state: dict, *args):
        """The value for ``args``; may change ``state`` (override)."""
        raise NotImplementedError(f"{cls.__name__} does not define its value")

    @staticmethod
    def _imp_(*args):
        # reached only by code that is not event iteration (a continuous equation): refused
        raise SolverError("an impure function is evaluated at events only",
                          hint="call it in a when-clause, whose value is held between events")

    def _eval_evalf(self, prec):
        return None  # never a number while translating: a call has a side effect

    def _eval_is_real(self):
        return True

    def fdiff(self, argindex: int = 1):
        raise TypeError(f"{type(self).__name__} has no derivative: it is evaluated at events only")


def impure_applications(expr: sp.Basic) -> list[sp.Expr]:
    """The distinct applications of :class:`ImpureFunction` subclasses in ``expr``,
    inner ones before the calls that take them as arguments (postorder: the order
    the runtime numbers their call sites in)."""
    if not isinstance(expr, sp.Basic):
        return []
    seen: dict[sp.Expr, None] = {}
    for node in sp.postorder_traversal(expr):
        if isinstance(node, ImpureFunction):
            seen.setdefault(node, None)
    return list(seen)
