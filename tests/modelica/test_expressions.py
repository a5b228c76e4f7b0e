"""Modelica expressions to sympy and back (acausal.modelica.expressions).

A round trip property (random sympy expressions written by ``to_modelica``,
parsed by pymoca inside a small model and read back by ``to_sympy`` are
equal to the original), closed-form cases of the operators, arrays and
built-in functions, and the errors for what is not supported.
"""

from __future__ import annotations

import math
import random

import pytest
import sympy as sp

pytest.importorskip("pymoca")

from hypothesis import assume, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from pymoca import ast as mast  # noqa: E402
from pymoca import parser  # noqa: E402

from acausal import hybrid  # noqa: E402
from acausal.arrays import Array  # noqa: E402
from acausal.errors import ModelicaError  # noqa: E402
from acausal.language import If, StateSelect, der, initial, pre, real_symbol, time  # noqa: E402
from acausal.modelica.expressions import END, call_arguments, to_modelica, to_sympy  # noqa: E402

X, Y, Z = (real_symbol(n) for n in "xyz")


def parse(text: str):
    """The right-hand side of ``x = <text>`` in a tiny model, as pymoca reads it."""
    tree = parser.parse(f"model M\n  Real x, y, z;\nequation\n  x = {text};\nend M;\n", bypass_cache=True)
    return tree.classes["M"].equations[0].right


class Names:
    """A resolve callback: given values by name, real symbols otherwise; records the calls."""

    def __init__(self, **values) -> None:
        self.values = values
        self.calls: list[tuple[str, list]] = []

    def __call__(self, name: str, subscripts: list):
        self.calls.append((name, subscripts))
        if name in self.values:
            value = self.values[name]
            return value[tuple(subscripts[-1])] if subscripts[-1] else value
        assert not any(subscripts), f"{name}{subscripts} has no value in the test"
        return real_symbol(name)


def read(text: str, **values):
    return to_sympy(parse(text), Names(**values))


def round_trip(expr):
    return read(to_modelica(expr))


# ---------------------------------------------------------------------------
# the round trip property
# ---------------------------------------------------------------------------

SPECIAL_FLOATS = [0.1, 1e-300, -2.5e10, 2.5, 1e16, 1 / 3, 6.02214076e23, 5e-324, -0.0, 1.7976931348623157e308]

numbers = st.one_of(
    st.integers(-1000, 1000).map(sp.Integer),
    st.sampled_from(SPECIAL_FLOATS).map(sp.Float),
    st.floats(allow_nan=False, allow_infinity=False).map(sp.Float),
    st.tuples(st.integers(-20, 20), st.integers(1, 12)).map(lambda pq: sp.Rational(*pq)),
)
leaves = st.one_of(st.sampled_from([X, Y, Z, time, der(X), pre(Y)]), numbers)

UNARY = [sp.sin, sp.cos, sp.tan, sp.asin, sp.acos, sp.atan, sp.sinh, sp.cosh, sp.tanh, sp.exp, sp.log,
         lambda a: sp.log(a, 10), sp.sqrt, sp.Abs, sp.sign, sp.asinh, sp.acosh, hybrid.floor, hybrid.ceil,
         hybrid.integer, hybrid.noEvent, der, lambda a: -a]
BINARY = [lambda a, b: a + b, lambda a, b: a - b, lambda a, b: a * b, lambda a, b: a / b, sp.atan2,
          sp.Min, sp.Max, hybrid.div, hybrid.mod, hybrid.rem]
RELATIONS = [sp.Lt, sp.Le, sp.Gt, sp.Ge, sp.Eq, sp.Ne]
EXPONENTS = [sp.Integer(2), sp.Integer(3), sp.Integer(-1), sp.Integer(-2), sp.Rational(1, 2),
             sp.Rational(-1, 2), sp.Rational(1, 3), sp.Rational(-5, 3), sp.Float(2.5), sp.Float(-0.5)]


def _apply(function, *args):
    """function(*args), or nan where sympy refuses, a number is beyond a double or a power
    would be huge (the example is then rejected: sympy's numbers are unbounded, and sin(1e900)
    is slow)."""
    if any(not _double(f) for a in args if isinstance(a, sp.Basic) for f in a.atoms(sp.Float)):
        return sp.nan
    if function is sp.Pow and args[1].is_comparable and abs(args[1]) > 64:
        return sp.nan  # 1000**(1000**1000): exact, unbounded, and no double anyway
    try:
        return function(*args)
    except (TypeError, ValueError, ArithmeticError):
        return sp.nan


def _extend(children):
    relation = st.builds(_apply, st.sampled_from(RELATIONS), children, children)
    condition = st.one_of(
        relation,
        st.builds(lambda a, b: _apply(sp.And, a, b), relation, relation),
        st.builds(lambda a, b: _apply(sp.Or, a, b), relation, relation),
        st.builds(lambda a: _apply(sp.Not, a), relation),
    )
    return st.one_of(
        st.builds(_apply, st.sampled_from(BINARY), children, children),
        st.builds(lambda f, a: _apply(f, a), st.sampled_from(UNARY), children),
        st.builds(lambda b, e: _apply(sp.Pow, b, e), children, st.one_of(st.sampled_from(EXPONENTS), children)),
        st.builds(lambda c, a, b: _apply(If, c, a, b), condition, children, children),
        st.builds(lambda c1, a, c2, b, c: _apply(lambda *p: sp.Piecewise(*p), (a, c1), (b, c2), (c, True)),
                  condition, children, condition, children, children),
    )


expressions = st.recursive(leaves, _extend, max_leaves=16)


def _double(number: sp.Float) -> bool:
    """Whether a sympy Float is a finite double (not beyond its range, nor underflowing to 0)."""
    value = float(number)
    return math.isfinite(value) and (value == 0) == (number == 0)


def _writable(expr) -> bool:
    """Whether expr is a finite real expression whose numbers are doubles (what Modelica has)."""
    if not isinstance(expr, sp.Basic) or isinstance(expr, sp.logic.boolalg.BooleanAtom):
        return False
    if expr.has(sp.nan, sp.zoo, sp.oo, -sp.oo, sp.I, sp.AccumBounds) or expr.atoms(sp.AccumBounds):
        return False
    if any(max(abs(r.p), r.q).bit_length() > 200 for r in expr.atoms(sp.Rational)):
        return False  # 3**1000: exact, but no Modelica tool reads such an Integer
    return all(_double(number) for number in expr.atoms(sp.Float))


def _numeric(expr, point: dict) -> complex:
    """expr at a point, with der()/pre() as symbols and the event functions as plain mathematics."""
    try:
        plain = hybrid.without_no_event(hybrid.plain_form(expr))
        plain = plain.replace(lambda e: isinstance(e, sp.core.function.AppliedUndef),
                              lambda e: sp.Symbol(f"{e.func.__name__}_{e.args[0]}", real=True))
        value = plain.evalf(30, subs=point)
    except TypeError:  # a relation of complex values in a condition: undefined there
        return complex("nan")
    return complex(value) if value.is_number and not value.has(sp.nan, sp.zoo) else complex("nan")


def assert_same(original, back) -> None:
    """Equal structurally, or (after reordering, say) numerically at random points to 1e-12."""
    if original == back:
        return
    rng = random.Random(7)
    names = sorted(original.free_symbols | back.free_symbols, key=str) + [
        sp.Symbol(f"{f}_{a}", real=True) for f in ("der", "pre") for a in ("x", "y", "z")]
    for _ in range(4):
        point = {s: sp.Float(rng.uniform(-3, 3)) for s in names}
        a, b = _numeric(original, point), _numeric(back, point)
        if math.isnan(a.real) and math.isnan(b.real):
            continue
        assert abs(a - b) <= 1e-12 * max(1.0, abs(a), abs(b)), (original, back, point)


@settings(max_examples=300, derandomize=True, deadline=None)
@given(expressions)
def test_round_trip(expr):
    assume(_writable(expr))
    text = to_modelica(expr)
    back = read(text)
    assert_same(expr, back)
    assert to_modelica(back) == text  # written again, the same text


BOOLEAN_A, BOOLEAN_B = sp.symbols("a b")  # Boolean variables: symbols without assumptions

small_expressions = st.recursive(leaves, _extend, max_leaves=4)
booleans = st.recursive(
    st.one_of(st.sampled_from([BOOLEAN_A, BOOLEAN_B, sp.true, sp.false, hybrid.edge(BOOLEAN_A),
                               hybrid.change(BOOLEAN_B), initial() > 0]),
              st.builds(_apply, st.sampled_from(RELATIONS), small_expressions, small_expressions)),
    lambda children: st.one_of(
        st.builds(lambda p, q: _apply(sp.And, p, q), children, children),
        st.builds(lambda p, q: _apply(sp.Or, p, q), children, children),
        st.builds(lambda p: _apply(sp.Not, p), children),
        st.builds(lambda p, q: _apply(sp.Xor, p, q), children, children),
        st.builds(lambda c, p, q: _apply(sp.ITE, c, p, q), children, children, children)),
    max_leaves=8)


def _truth(expr, rng: random.Random):
    """expr at a random point: Booleans true or false, Reals uniform in [-3, 3]."""
    plain = hybrid.without_no_event(hybrid.plain_form(expr))
    plain = plain.replace(lambda e: isinstance(e, sp.core.function.AppliedUndef),
                          lambda e: sp.Symbol(f"{e.func.__name__}_{e.args[0] if e.args else ''}"))
    point = {s: (sp.true if rng.random() < 0.5 else sp.false) if s.name in ("a", "b", "pre_a", "pre_b")
             else sp.Float(rng.uniform(-3, 3)) for s in sorted(plain.free_symbols, key=str)}
    try:
        return plain.subs(point)
    except TypeError:  # a relation of complex values (asin(3) < 1): undefined, on both sides
        return "undefined"


@settings(max_examples=150, derandomize=True, deadline=None)
@given(booleans)
def test_boolean_round_trip(expr):
    assume(isinstance(expr, sp.logic.boolalg.Boolean) and not isinstance(expr, sp.logic.boolalg.BooleanAtom))
    assume(not expr.has(sp.nan, sp.zoo, sp.oo, -sp.oo, sp.I)
           and all(_double(number) for number in expr.atoms(sp.Float)))
    back = read(to_modelica(expr), a=BOOLEAN_A, b=BOOLEAN_B)
    if back == expr:
        return
    for seed in range(8):  # Xor(p, q) reads back as p <> q: logically the same
        assert _truth(expr, random.Random(seed)) == _truth(back, random.Random(seed)), (expr, back)


@pytest.mark.parametrize("value", SPECIAL_FLOATS + [0.2, 123456789.125, -1e-7, 2.0 ** -1074, 9007199254740993.0])
def test_floats_read_back_to_the_same_double(value):
    text = to_modelica(sp.Float(value) * X)
    back = read(text)
    coefficient = back.as_coeff_Mul()[0] if back != 0 else sp.Float(0)
    assert float(coefficient) == value or (value == 0 and back == 0)


# ---------------------------------------------------------------------------
# writing: precedence and minimal parentheses
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("expr, text", [
    (-X**2, "-x^2"),
    ((-X)**Y, "(-x)^y"),
    (X / (Y * Z), "x/(y*z)"),
    (X * Y / Z, "x*y/z"),
    (1 / X, "1/x"),
    (X**-2, "1/x^2"),
    (X**-Y, "1/x^y"),
    (X**sp.Float(-2.5), "1/x^2.5"),
    (X**(Y + 1), "x^(y + 1)"),
    ((X**Y)**Z, "(x^y)^z"),
    (sp.Pow(2, X), "2^x"),
    (sp.Pow(-2, X), "(-2)^x"),
    (sp.Pow(sp.Rational(1, 2), X), "(1/2)^x"),
    (X**sp.Rational(1, 3), "x^(1/3)"),
    (sp.sqrt(X), "sqrt(x)"),
    (1 / sp.sqrt(X), "1/sqrt(x)"),
    (sp.Rational(1, 2), "1/2"),
    (sp.Rational(-3, 4), "-3/4"),
    (X / 2, "x/2"),
    (-2 * X / 3, "-2*x/3"),
    (X - Y, "x - y"),
    (X - 2 * Y, "x - 2*y"),
    (-X + Y, "-x + y"),
    (X * (Y + Z), "x*(y + z)"),
    (X - (Y + Z) * Z, "x - z*(y + z)"),
    (2 * X * (-Y + Z)**2, "2*x*(-y + z)^2"),
    (sp.Mul(X, -Y - 1, evaluate=False), "x*(-y - 1)"),
    (sp.Add(X, sp.Mul(-1, Y, evaluate=False), evaluate=False), "x - y"),
    (X + sp.Float(0.1), "x + 0.1"),
    (sp.Float(1.0) * X, "1.0*x"),
    (X**sp.Float(0.5), "x^0.5"),
    (X - sp.Float(2.5e10), "x - 25000000000.0"),
    (sp.Float(1e-300) * X, "1e-300*x"),
    (sp.log(X, 10), "log10(x)"),
    (2 * sp.log(X, 10), "2*log10(x)"),
    (sp.exp(X), "exp(x)"),
    (sp.E, "exp(1)"),
    (sp.pi * X, "Modelica.Constants.pi*x"),
    (sp.Abs(X), "abs(x)"),
    (sp.Min(X, Y, Z), "min(x, min(y, z))"),
    (sp.Max(X, 1), "max(1, x)"),
    (sp.atan2(Y, X), "atan2(y, x)"),
    (sp.floor(X) + sp.ceiling(Y), "ceil(y) + floor(x)"),
    (hybrid.div(X, Y) + hybrid.rem(X, 2), "div(x, y) + rem(x, 2)"),
    (der(X), "der(x)"),
    (der(X * Y), "der(x*y)"),
    (pre(X) + 1, "pre(x) + 1"),
    (time, "time"),
    (2 * time, "2*time"),
    (sp.true, "true"),
    (sp.And(X > 0, Y < 1), "x > 0 and y < 1"),
    (sp.Or(sp.And(X > 0, Y < 1), Z > 2), "z > 2 or x > 0 and y < 1"),
    (sp.And(sp.Or(X > 0, Y < 1), Z > 2), "z > 2 and (x > 0 or y < 1)"),
    (sp.Not(sp.Symbol("b")), "not b"),
    (sp.Not(sp.And(sp.Symbol("a"), sp.Symbol("b"))), "not (a and b)"),
    (sp.Eq(X, 1), "x == 1"),
    (sp.Ne(X, Y), "x <> y"),
    (sp.Gt(X + 1, -Y), "x + 1 > -y"),
    (If(X > 0, 1, If(X < 0, -1, 0)), "if x > 0 then 1 elseif x < 0 then -1 else 0"),
    (Y + If(X > 0, X, 0), "y + (if x > 0 then x else 0)"),
    (hybrid.noEvent(If(X > 0, sp.sqrt(X), 0)), "noEvent(if x > 0 then sqrt(x) else 0)"),
    (hybrid.sample(0, sp.Float(0.1)), "sample(0, 0.1)"),
    ("a \"quoted\" word\n", '"a \\"quoted\\" word\\n"'),
    (Array([1, X]), "{1, x}"),
    (Array([[1, 2], [3, X]]), "[1, 2; 3, x]"),
    (StateSelect.always, "StateSelect.always"),
    (2.5, "2.5"),
    (True, "true"),
])
def test_written_text(expr, text):
    assert to_modelica(expr) == text


def test_written_text_reads_back():
    for expr in (-X**2, X / (Y * Z), X**-Y, (-X)**Y, X - (Y + Z) * Z, sp.Mul(X, -Y - 1, evaluate=False),
                 Y + If(X > 0, X, 0), sp.And(sp.Or(X > 0, Y < 1), Z > 2), sp.pi * X, sp.E):
        assert_same(expr, round_trip(expr))


def test_names_come_from_the_callback():
    a_b = real_symbol("a.b")
    assert to_modelica(a_b + time, name=lambda s: f"'{s.name}'") == "'a.b' + time"


def test_event_operators_are_written_by_their_names():
    b, n = sp.Symbol("b"), sp.Symbol("n", integer=True)
    assert to_modelica(hybrid.edge(b)) == "edge(b)"
    assert to_modelica(hybrid.change(b)) == "change(b)"
    assert to_modelica(hybrid.change(n)) == "change(n)"
    assert to_modelica(hybrid.terminal()) == "terminal()"
    assert to_modelica(initial()) == "initial()"


@pytest.mark.parametrize("expr, what", [
    (sp.oo, "oo"),
    (sp.nan, "nan"),
    (sp.I * X, "I"),
    (sp.Float("1e400") * X, "beyond the range"),
    (sp.Float("1e-400") * X, "beyond the range"),
    (sp.Function("f")(X), r"f\(x\)"),
    (sp.Integral(X, X), "Integral"),
    (sp.Derivative(sp.Function("g")(X), X), "Derivative"),
    (sp.Piecewise((X, X > 0)), "otherwise"),
    (object(), "object"),
])
def test_what_cannot_be_written(expr, what):
    with pytest.raises(ModelicaError, match=what):
        to_modelica(expr)


# ---------------------------------------------------------------------------
# reading: scalars
# ---------------------------------------------------------------------------

def test_numbers():
    assert read("1") == sp.Integer(1) and isinstance(read("1"), sp.Integer)
    assert read("1.5e-3") == sp.Float(1.5e-3) and isinstance(read("1.5e-3"), sp.Float)
    assert float(read("0.1")) == 0.1
    assert read("1/3") == sp.Rational(1, 3)  # Modelica's / of Integers is Real division


def test_precedence():
    assert read("-x^2") == -X**2
    assert read("a/(b*c)") == real_symbol("a") / (real_symbol("b") * real_symbol("c"))
    assert read("a/b*c") == real_symbol("a") * real_symbol("c") / real_symbol("b")
    assert read("x - (y - z)") == X - Y + Z
    assert read("x - y - z") == X - Y - Z
    assert read("2^(-1)") == sp.Rational(1, 2)
    assert read("x^(-1)") == 1 / X
    assert read("-2^2") == -4
    a, b, c = sp.symbols("a b c")  # Boolean variables: symbols without assumptions
    assert read("a and b or not c", a=a, b=b, c=c) == sp.Or(sp.And(a, b), sp.Not(c))
    assert read("a and (b or c)", a=a, b=b, c=c) == sp.And(a, sp.Or(b, c))
    assert read("not x > 0") == (X <= 0)


def test_unary_minus_after_an_operator_is_not_modelica():
    # 2^-1, 2*-x: Modelica allows a unary minus only at the start of a sum (MLS 3.2)
    with pytest.raises(parser.ModelicaSyntaxError):
        parse("2^-1")
    assert to_modelica(sp.Pow(2, -1, evaluate=False)) == "1/2"
    assert to_modelica(sp.Pow(X, sp.Integer(-1), evaluate=False)) == "1/x"
    assert to_modelica(sp.Mul(2, -X - Y, evaluate=False)) == "2*(-x - y)"
    assert to_modelica(sp.Pow(-X, 2, evaluate=False)) == "(-x)^2"


def test_relations_and_logic():
    assert read("x < y") == sp.Lt(X, Y)
    assert read("x <= y") == sp.Le(X, Y)
    assert read("x >= 1") == sp.Ge(X, 1)
    assert read("x == 1") == sp.Eq(X, 1)
    assert read("x <> 1") == sp.Ne(X, 1)
    assert read("(x > 0) == (y > 0)") == sp.Equivalent(X > 0, Y > 0)
    assert read("(x > 0) <> (y > 0)") == sp.Xor(X > 0, Y > 0)
    a, b = sp.symbols("a b")  # Boolean variables
    assert read("a == b", a=a, b=b) == sp.Equivalent(a, b)
    assert read("not a <> b", a=a, b=b) == sp.Not(sp.Xor(a, b))
    assert read("a <> pre(a)", a=a) == hybrid.change(a)
    assert read("true and x > 0") == (X > 0)
    assert read("false") is sp.false
    assert read('"a" == "a"') is sp.true


def test_boolean_if_expressions():
    a, b = sp.symbols("a b")
    assert read("if x > 0 then a else x < 1", a=a) == sp.ITE(X > 0, a, X < 1)
    assert read("if x > 0 then true elseif y > 0 then b else false", b=b) == \
        sp.ITE(X > 0, sp.true, sp.ITE(Y > 0, b, sp.false))
    assert read("if (if x > 0 then x < 1 else y > 2) then 1 else 2") == \
        If(sp.ITE(X > 0, X < 1, Y > 2), 1, 2)
    assert to_modelica(sp.ITE(X > 0, a, X < 1)) == "if x > 0 then a else x < 1"
    assert read("if noEvent(x > 0) then noEvent(x < 1) else false") == \
        hybrid.NoEvent(sp.ITE(X > 0, X < 1, sp.false))


def test_if_expressions():
    assert read("if x > 0 then 1 elseif x < 0 then -1 else 0") == \
        sp.Piecewise((1, X > 0), (-1, X < 0), (0, True))
    assert read("if x > 0 then x else -x") == If(X > 0, X, -X)
    assert read("y + (if x > 0 then x else 0)") == Y + If(X > 0, X, 0)
    assert read('if true then "a" else "b"') == "a"
    assert read("if x > 0 then {1, 2} else {x, 3}") == Array([If(X > 0, 1, X), If(X > 0, 2, 3)])


def test_no_event_around_a_condition():
    # read as noEvent around the whole if-expression: the same where nothing else generates events
    assert read("if noEvent(x > 0) then sqrt(x) else 0") == hybrid.noEvent(If(X > 0, sp.sqrt(X), 0))
    assert read("if noEvent(x > 0 and y > 0) then x else y") == hybrid.noEvent(If(sp.And(X > 0, Y > 0), X, Y))
    assert read("if noEvent(x > 0) and noEvent(y > 0) then x else y") == \
        hybrid.noEvent(If(sp.And(X > 0, Y > 0), X, Y))
    assert read("if smooth(0, x > 0) then x else 0") == hybrid.noEvent(If(X > 0, X, 0))
    assert read("noEvent(x > 0)") == hybrid.NoEvent(X > 0)
    with pytest.raises(ModelicaError, match="other parts"):
        read("if noEvent(x > 0) then x elseif y > 0 then 1 else 0")
    with pytest.raises(ModelicaError, match="other parts"):
        read("if noEvent(x > 0) then floor(x) else 0")
    with pytest.raises(ModelicaError, match="other operands"):
        read("if noEvent(x > 0) and y > 0 then 1 else 0")


def test_time_strings_and_constants():
    assert read("time") is time
    assert read('"ab\\"c" + "d"') == 'ab"cd'
    assert read('"tab\\there"') == "tab\there"
    assert read("Modelica.Constants.pi") is sp.pi
    assert read("2*Modelica.Constants.e") == 2 * sp.E


def test_component_references_go_to_resolve():
    names = Names(x=Array([X, Y, Z]), a=None, StateSelect=None)
    names.values["a.b"] = Array([[1, 2], [3, 4]])
    names.values["StateSelect.always"] = StateSelect.always
    assert to_sympy(parse("StateSelect.always"), names) is StateSelect.always
    assert to_sympy(parse("x"), names) == Array([X, Y, Z])
    to_sympy(parse("x[2]"), names)
    to_sympy(parse("x[2:3]"), names)
    to_sympy(parse("x[1:2:3]"), names)
    to_sympy(parse("x[{1, 3}]"), names)
    to_sympy(parse("x[end - 1]"), names.__class__(x=_EndArray([X, Y, Z])))
    calls = names.calls
    assert calls[0] == ("StateSelect.always", [[], []])
    assert calls[1] == ("x", [[]])
    assert calls[2] == ("x", [[2]]) and isinstance(calls[2][1][0][0], int)
    assert calls[3] == ("x", [[slice(2, 3)]])
    assert calls[4] == ("x", [[slice(1, 3, 2)]])
    assert calls[5] == ("x", [[[1, 3]]])


class _EndArray(Array):
    """An array that substitutes END as a resolver would."""

    def __getitem__(self, key):
        return super().__getitem__(tuple(int(k.subs(END, len(self))) if isinstance(k, sp.Basic) else k
                                         for k in key))


def test_subscripts_of_every_part_and_end():
    names = Names()
    names.values["a.b"] = Array([[1, 2], [3, 4]])
    names.values["c"] = _EndArray([X, Y, Z])
    assert to_sympy(parse("c[end]"), names) == Z
    assert to_sympy(parse("c[end - 1]"), names) == Y
    seen = []
    to_sympy(parse("a[1].b[2, :]"), lambda name, subscripts: seen.append((name, subscripts)) or 0)
    to_sympy(parse("p.q[2:end]"), lambda name, subscripts: seen.append((name, subscripts)) or 0)
    assert seen == [("a.b", [[1], [2, slice(None)]]), ("p.q", [[], [slice(2, END)]])]


# ---------------------------------------------------------------------------
# reading: built-in operators and functions
# ---------------------------------------------------------------------------

def test_event_and_derivative_operators():
    b = sp.Symbol("b")
    n = sp.Symbol("n", integer=True)
    names = Names(b=b, n=n)
    assert read("der(x)") == der(X)
    assert read("der(x*y)") == der(X * Y)
    assert read("pre(x)") == pre(X)
    assert read("initial()") == initial()
    assert read("terminal()") == hybrid.terminal()
    assert read("sample(0, 0.1)") == hybrid.sample(0, sp.Float(0.1))
    assert to_sympy(parse("edge(b)"), names) == hybrid.edge(b)
    assert to_sympy(parse("change(n)"), names) == hybrid.change(n)
    assert to_sympy(parse("change(b)"), names) == hybrid.change(b)
    assert read("noEvent(x)") == hybrid.noEvent(X)
    assert read("smooth(1, x)") == hybrid.noEvent(X)
    assert read("smooth(-1, x)") == X
    assert read("homotopy(x, y)") == hybrid.Homotopy(X, Y)
    assert read("homotopy(actual=x, simplified=y)") == hybrid.Homotopy(X, Y)
    assert read("homotopy(simplified=y, actual=x)") == hybrid.Homotopy(X, Y)
    assert read("homotopy(x, x)") == X


def test_boolean_operators_take_pre_and_initial():
    b = sp.Symbol("b")
    names = Names(b=b)
    value = to_sympy(parse("b and not pre(b)"), names)
    assert value == hybrid.edge(b)
    assert to_modelica(value) == "edge(b)"
    assert to_modelica(to_sympy(parse("if initial() then 1 else x"), names)) == "if initial() then 1 else x"
    assert to_modelica(to_sympy(parse("initial() or b"), names)) in ("initial() or b", "b or initial()")


def test_numeric_and_elementary_functions():
    assert read("abs(x) + sign(y) + sqrt(z)") == sp.Abs(X) + sp.sign(Y) + sp.sqrt(Z)
    for name in ("sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh", "tanh", "exp", "log"):
        assert read(f"{name}(x)") == getattr(sp, name)(X)
    assert read("log10(x)") == sp.log(X) / sp.log(10)
    assert read("atan2(y, x)") == sp.atan2(Y, X)
    assert read("min(x, y)") == sp.Min(X, Y)
    assert read("max(x, 2)") == sp.Max(X, 2)
    assert read("floor(x) + ceil(x) + integer(x)") == hybrid.floor(X) + hybrid.ceil(X) + hybrid.integer(X)
    assert read("div(x, y) + mod(x, y) + rem(x, y)") == hybrid.div(X, Y) + hybrid.mod(X, Y) + hybrid.rem(X, Y)


def test_modelica_math_aliases():
    assert read("Modelica.Math.sin(x)") == sp.sin(X)
    assert read("Math.cos(x)") == sp.cos(X)
    assert read(".Modelica.Math.exp(x)") == sp.exp(X)
    assert read("Modelica.Math.log10(x)") == sp.log(X, 10)
    assert read("Modelica.Math.asinh(x) + Modelica.Math.acosh(y)") == sp.asinh(X) + sp.acosh(Y)
    assert read("Modelica.Math.atan2(y, x)") == sp.atan2(Y, X)
    assert read("Modelica.Math.atan2(u1=y, u2=x)") == sp.atan2(Y, X)
    assert read("Modelica.Math.atan2(y, u2=x)") == sp.atan2(Y, X)
    assert read("Modelica.Math.tanh(u=x)") == sp.tanh(X)
    assert to_modelica(sp.asinh(X)) == "Modelica.Math.asinh(x)"


# ---------------------------------------------------------------------------
# reading: arrays
# ---------------------------------------------------------------------------

A = Array([[1, 2], [3, 4]])
V = Array([real_symbol("v1"), real_symbol("v2")])
V1, V2 = V.flat


def test_matrix_products():
    assert read("A*v", A=A, v=V) == Array([V1 + 2 * V2, 3 * V1 + 4 * V2])
    assert read("v*A", A=A, v=V) == Array([V1 + 3 * V2, 2 * V1 + 4 * V2])
    assert read("v*v", v=V) == V1**2 + V2**2
    assert read("A*A", A=A) == Array([[7, 10], [15, 22]])
    assert read("A^2", A=A) == Array([[7, 10], [15, 22]])
    assert read("A^0", A=A) == Array([[1, 0], [0, 1]])
    assert read("2*A - A", A=A) == A
    assert read("A/2", A=A) == Array([[sp.Rational(1, 2), 1], [sp.Rational(3, 2), 2]])
    assert read("-v", v=V) == Array([-V1, -V2])


def test_elementwise_operators():
    assert read("{1, 2} .* {3, 4}") == Array([3, 8])
    assert read("{1, 2} .+ 1") == Array([2, 3])
    assert read("1 .- {1, 2}") == Array([0, -1])
    assert read("2 ./ {1, 4}") == Array([2, sp.Rational(1, 2)])
    assert read("2 .^ {1, 3}") == Array([2, 8])
    assert read("{x, y} .^ 2") == Array([X**2, Y**2])
    assert read("{1, 2} + {3, 4}") == Array([4, 6])
    assert read("sin({x, y})") == Array([sp.sin(X), sp.sin(Y)])
    assert read("der(v)", v=V) == Array([der(V1), der(V2)])
    assert read("atan2({1, 2}, x)") == Array([sp.atan2(1, X), sp.atan2(2, X)])


def test_constructors_and_concatenation():
    assert read("{1, 2, 3}").shape == (3,)
    assert read("{{1, 2}, {3, 4}}") == Array([[1, 2], [3, 4]])
    assert read("[1, 2; 3, 4]") == Array([[1, 2], [3, 4]])
    assert read("[1, 2]") == Array([[1, 2]])  # a 1 x 2 matrix, not a vector
    assert read("[1; 2]") == Array([[1], [2]])
    assert read("[x]") == Array([[X]])
    assert read("[v, v]", v=V) == Array([[V1, V1], [V2, V2]])
    assert read("[A, A]", A=A) == Array([[1, 2, 1, 2], [3, 4, 3, 4]])
    assert read("[A; [5, 6]]", A=A) == Array([[1, 2], [3, 4], [5, 6]])
    assert read("{i^2 for i in 1:3}") == Array([1, 4, 9])
    assert read("{i - j for i in 1:2, j in 1:3}") == Array([[0, 1], [-1, 0], [-2, -1]])  # MLS 10.4.1.2
    assert read("{x*i for i in {2, 5}}") == Array([2 * X, 5 * X])


def test_array_functions():
    assert read("sum({1, 2, 3})") == 6
    assert read("product({2, 3, 4})") == 24
    assert read("sum(v)", v=V) == V1 + V2
    assert read("sum(v[i]^2 for i in 1:2)", v=V) == V1**2 + V2**2
    assert read("max({1, x})") == sp.Max(1, X)
    assert read("min(A)", A=A) == 1
    assert read("size(A)", A=A) == Array([2, 2])
    assert read("size(A, 2)", A=A) == 2
    assert read("ndims(A)", A=A) == 2
    assert read("fill(x, 2, 3)") == Array([[X] * 3] * 2)
    assert read("fill({1, 2}, 2)") == Array([[1, 2], [1, 2]])
    assert read("zeros(2)") == Array([0, 0])
    assert read("ones(1, 2)") == Array([[1, 1]])
    assert read("identity(2)") == Array([[1, 0], [0, 1]])
    assert read("transpose(A)", A=A) == Array([[1, 3], [2, 4]])
    assert read("cat(1, {1}, {2, 3})") == Array([1, 2, 3])
    assert read("cat(2, A, A)", A=A) == Array([[1, 2, 1, 2], [3, 4, 3, 4]])
    assert read("scalar({{x}})") == X
    assert read("vector([1; 2])") == Array([1, 2])


def test_ranges():
    assert read("1:3") == [1, 2, 3] and all(type(i) is int for i in read("1:3"))
    assert read("1:2:6") == [1, 3, 5]
    assert read("5:-1:1") == [5, 4, 3, 2, 1]
    assert read("1:2:5") == [1, 3, 5]
    assert read("3:1") == []
    assert read("1.0:0.5:2.0") == [1.0, 1.5, 2.0]
    assert read("2.7:6.8") == [sp.Float(v) for v in (2.7, 3.7, 4.7, 5.7, 6.7)]  # MLS 10.4.3
    assert read("false:true") == [sp.false, sp.true]
    assert read("sum(1:4)") == 10


def test_parser_repairs():
    # pymoca 0.12 swaps step and stop and drops named arguments, iterators and [...]: repaired
    node = parse("1:2:5")
    assert (node.start.value, node.step.value, node.stop.value) == (1, 2, 5)
    call = parse("f(1, b=2)")
    assert len(call.operands) == 2 and call.operands[1].operator == "="
    assert parse("{i for i in 1:3}").operator == "for"
    assert parse("sum(i for i in 1:3)").operands[0].operator == "for"
    assert parse("[1, 2]").operator == "[]"
    assert isinstance(parse("{1, 2}"), mast.Array)


def test_call_arguments_of_an_equation_level_call():
    tree = parser.parse('model M Real x; equation assert(x > 0, "negative", level=AssertionLevel.warning); '
                        'end M;', bypass_cache=True)
    call = tree.classes["M"].equations[0]
    positional, named = call_arguments(call.arguments, call.name)
    assert len(positional) == 2 and list(named) == ["level"]
    assert str(named["level"]) == "AssertionLevel.warning"


# ---------------------------------------------------------------------------
# errors
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("text, what", [
    ("foo(x)", "unsupported function foo"),
    ("delay(x, 1)", "unsupported function delay"),
    ("semiLinear(x, 1, 2)", "semiLinear"),
    ("Modelica.Math.Vectors.norm({1, 2})", "Modelica.Math.Vectors.norm"),
    ("Modelica.Math.wrapAngle(x)", "Modelica.Math.wrapAngle"),
    ("sin(x, y)", r"sin\(\) takes 1 argument, given 2"),
    ("atan2(x)", r"atan2\(\) takes 2 arguments"),
    ("sin(u=x)", "named arguments"),
    ("Modelica.Math.sin(v=x)", "no argument v"),
    ("homotopy(x)", "homotopy"),
    ("{1, 2} + 1", r"a scalar and an array in \+"),
    ("{1, 2} / {1, 2}", "division by an array"),
    ("{1, 2} .* {1, 2, 3}", r"sizes \[2\] and \[3\]"),
    ("{1, 2} * {{1, 2, 3}}", "matrix product|columns"),
    ("2 ^ {1, 2}", "array exponent"),
    ("{1, 2} ^ 2", "square matrix"),
    ("{1, 2} < {3, 4}", "relation < of arrays"),
    ('"a" * 2', "a string in arithmetic"),
    ("sin(\"a\")", "string"),
    ("x[1.5]", "not an Integer"),
    ("1:n", "not known numbers"),
    ("1:0:3", "step 0"),
    ("end + 1", "'end' outside subscripts"),
    ("(x, y)", "parenthesised list"),
    ("{1, {2, 3}}", "elements of sizes"),
    ("[{1, 2}, {1, 2, 3}]", "do not fit"),
    ("if x then 1 else 2", "not a Boolean"),
    ("if x > 0 then {1, 2} else 3", "branches of sizes"),
    ("noEvent(x > 0) + 1", "used as a value"),
    ("smooth(n, x)", "constant Integer"),
    ("fill(1, n)", "constant Integer"),
    ("size(x, 1)", "scalar|size"),
    ("sum(x)", "sum\\(\\) of the scalar"),
    ("min({1}, 2)", "min\\(a, b\\) of arrays"),
])
def test_unsupported_constructs(text, what):
    with pytest.raises(ModelicaError, match=what):
        read(text, x=X, n=sp.Symbol("n", integer=True))


def test_errors_carry_a_hint():
    with pytest.raises(ModelicaError) as error:
        read("{1, 2} + 1")
    assert ".+" in error.value.hint
    assert isinstance(error.value, ValueError)
