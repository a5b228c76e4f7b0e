"""Modelica functions evaluated when a model is read (acausal.modelica.functions).

Each function is run through a model's parameter binding and the result is
checked against the same computation done in numpy or by hand.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("pymoca")

from acausal.compiler.flatten import flatten  # noqa: E402
from acausal.errors import ModelicaError  # noqa: E402
from acausal.modelica import load  # noqa: E402


def _parameter(text: str, name: str = "p", model: str | None = None):
    """The value the model ``M`` of ``text`` gives its parameter ``name``."""
    flat = flatten(load(text, name=model)())
    values = {p.name: p.value for p in flat.parameters}
    values.update(flat.structural_parameters)  # Integer parameters: evaluated, as Modelica tools do
    if name in values:
        return values[name]
    # an array parameter: its elements p[1], p[2] or p[1,1], p[1,2], ... in order
    elements = {tuple(int(i) for i in key[len(name) + 1:-1].split(",")): value
                for key, value in values.items() if key.startswith(name + "[")}
    shape = tuple(max(index[k] for index in elements) for k in range(len(next(iter(elements)))))
    array = np.empty(shape, dtype=object)
    for index, value in elements.items():
        array[tuple(i - 1 for i in index)] = value
    return array.tolist()


STRIBECK = """
package P
  function table
    input Real F_prop;
    input Real F_Coulomb;
    input Real F_Stribeck;
    input Real fexp;
    input Real v_max;
    input Integer nTable(min=2) = 100;
    output Real table[nTable, 2];
  algorithm
    for i in 1:nTable loop
      table[i, 1] := v_max*(i - 1)/(nTable - 1);
      table[i, 2] := F_Coulomb + F_prop*table[i, 1] + F_Stribeck*Modelica.Math.exp(-fexp*table[i, 1]);
    end for;
  end table;
  model M
    parameter Real p[:, 2] = table(F_prop=1, F_Coulomb=5, F_Stribeck=10, fexp=2, v_max=12, nTable=50);
    Real x(start=0, fixed=true);
  equation
    der(x) = 1;
  end M;
end P;
"""


def test_a_table_built_in_a_for_loop_with_named_arguments():
    value = np.asarray(_parameter(STRIBECK), dtype=float)
    v = 12 * np.arange(50) / 49
    assert value.shape == (50, 2)
    np.testing.assert_allclose(value[:, 0], v, rtol=1e-15)
    np.testing.assert_allclose(value[:, 1], 5 + v + 10 * np.exp(-2 * v), rtol=1e-15)


def test_a_default_input_uses_the_inputs_before_it():
    text = """
    model M
      function f
        input Real a;
        input Real b = 2*a;
        output Real y;
      algorithm
        y := a + b;
      end f;
      parameter Real p = f(3);
      parameter Real q = f(3, 1);
    end M;
    """
    assert _parameter(text, "p") == 9.0
    assert _parameter(text, "q") == 4.0


def test_while_if_break_and_integer_arithmetic():
    # the smallest n with n! > limit, by a while loop with break, and Integer results exact
    text = """
    model M
      function first_factorial_above
        input Integer limit;
        output Integer n;
      protected
        Integer fact = 1;
      algorithm
        n := 0;
        while true loop
          n := n + 1;
          fact := fact*n;
          if fact > limit then
            break;
          elseif n > 100 then
            assert(false, "no end");
          end if;
        end while;
      end first_factorial_above;
      parameter Integer p = first_factorial_above(1000000);
    end M;
    """
    expected = next(n for n in range(1, 100) if math.factorial(n) > 1_000_000)
    assert _parameter(text) == expected


def test_recursion_and_return():
    text = """
    model M
      function fib
        input Integer n;
        output Integer y;
      algorithm
        if n < 2 then
          y := n;
          return;
        end if;
        y := fib(n - 1) + fib(n - 2);
      end fib;
      parameter Integer p = fib(15);
    end M;
    """
    assert _parameter(text) == 610


def test_several_outputs_and_the_first_in_an_expression():
    text = """
    model M
      function polar
        input Real x;
        input Real y;
        output Real r;
        output Real phi;
      algorithm
        r := sqrt(x^2 + y^2);
        phi := atan2(y, x);
      end polar;
      function angle
        input Real x;
        input Real y;
        output Real phi;
      protected
        Real r;
      algorithm
        (r, phi) := polar(x, y);
      end angle;
      parameter Real p = polar(3, 4);
      parameter Real q = angle(3, 4);
    end M;
    """
    assert _parameter(text, "p") == 5.0
    assert _parameter(text, "q") == pytest.approx(math.atan2(4, 3), rel=1e-15)


def test_reals_are_doubles_and_slices_assign():
    text = """
    model M
      function f
        input Integer n;
        output Real y[n];
      algorithm
        y[1:n] := fill(1/3, n);
        y[2] := y[1]*3;
      end f;
      parameter Real p[3] = f(3);
    end M;
    """
    assert _parameter(text) == [1 / 3, 1.0, 1 / 3]


@pytest.mark.parametrize("body, call, message", [
    ("input Real a; output Real y; algorithm y := a;", "f(1, 2)", "takes 1 inputs, given 2"),
    ("input Real a; output Real y; algorithm y := a;", "f(b=1)", "has no input b"),
    ("input Real a; output Real y; algorithm y := a;", "f()", "input a is not given"),
    ("input Real a; output Real y; algorithm assert(a > 0, \"a must be positive\"); y := a;", "f(-1)",
     "a must be positive"),
    ("input Real a; output Real y; algorithm a := 1; y := a;", "f(1)", "input a is assigned"),
    ("input Real a; output Real y; output Real z; algorithm y := a;", "f(1)", "output z is not assigned"),
    ("input Real a; output Integer y; algorithm y := a/2;", "f(1)", "Integer y is given the Real value"),
    ("input Real a; output Real y; algorithm y := g(a);", "f(1)", "unsupported function g()"),
])
def test_bad_functions_and_calls_name_what_is_wrong(body, call, message):
    text = f"model M function f {body} end f; parameter Real p = {call}; end M;"
    with pytest.raises(ModelicaError, match=message):
        flatten(load(text, "M")())


def test_a_value_not_known_when_the_model_is_read_is_named():
    text = """
    model M
      function f
        input Real a;
        output Real y;
      algorithm
        if a > 0 then y := a; else y := -a; end if;
      end f;
      Real x(start=1, fixed=true);
      Real z = f(x);
    equation
      der(x) = -x;
    end M;
    """
    with pytest.raises(ModelicaError, match="not known when the model is read"):
        flatten(load(text, "M")())


def test_calling_a_model_is_refused():
    text = "model M model N end N; parameter Real p = N(); end M;"
    with pytest.raises(ModelicaError, match="not a function"):
        flatten(load(text, "M")())


RECORD_INPUT = """
package P
  record Brush
    parameter Real V = 0.5;
    parameter Real ILinear = 0.01;
  end Brush;
  function drop
    input Brush brush;
    input Real i;
    output Real v;
  algorithm
    v := if i > brush.ILinear then brush.V else brush.V*i/brush.ILinear;
  end drop;
  model M
    parameter Brush brush(V=2);
    parameter Real i = 10;
    parameter Real p = drop(brush, i);
  end M;
end P;
"""


def test_a_record_input_gives_its_fields():
    """A record given to a function: brush.V is the value the record holds (2, from its modifier)."""
    assert float(_parameter(RECORD_INPUT, model="P.M")) == pytest.approx(2.0)
