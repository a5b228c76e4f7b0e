"""Reading Modelica text: models written in Modelica run in acausal (issue 26).

Text written here needs no Modelica Standard Library sources: library
classes are found by the Modelica names acausal's classes declare, and the
types of ``Modelica.Units`` are Reals without unit when ``Modelica/Units.mo``
is not on ``MODELICAPATH``.  The MSL examples themselves are in
``test_msl_sources.py`` (they need the sources on ``MODELICAPATH``).
"""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pymoca")

from acausal import simulate  # noqa: E402
from acausal.compiler.flatten import flatten  # noqa: E402
from acausal.errors import ModelicaError, ModelicaSyntaxError  # noqa: E402
from acausal.modelica import load  # noqa: E402

DRIVE = """
within MyLibrary.Examples;
model Drive "A torque on an inertia against air drag written in the file itself"
  import SI = Modelica.Units.SI;
  import Modelica.Mechanics.Rotational;
  model Drag "tau = k*w*|w| on a flange"
    parameter Real k(unit="N.m.s2/rad2") = 0.5;
    Rotational.Interfaces.Flange_a flange;
    Real w(unit="rad/s");
  equation
    w = der(flange.phi);
    flange.tau = k*w*abs(w);
  end Drag;
  parameter SI.Torque T = 2 "Drive torque";
  parameter SI.Inertia J = 0.5;
  parameter Real k2 = 2*J "a parameter bound to an expression of another";
  Rotational.Sources.ConstantTorque source(tau_constant=T);
  Rotational.Components.Inertia flywheel(J=J, phi(start=0, fixed=true), w(start=0, fixed=true));
  Drag drag(k=k2/4);
  Real power "power the drive puts in";
equation
  connect(source.flange, flywheel.flange_a);
  connect(flywheel.flange_b, drag.flange);
  power = T*flywheel.w;
  annotation (experiment(StopTime=5, Interval=0.01));
end Drive;
"""


def test_a_model_with_a_class_of_its_own_runs_to_its_closed_form():
    """J w' = T - k w^2 from rest: w = sqrt(T/k) tanh(t sqrt(T k)/J), k = k2/4 = 0.25."""
    model = load(DRIVE)
    assert model.modelica_class == "MyLibrary.Examples.Drive"
    assert model.experiment.stop_time == 5 and model.experiment.interval == 0.01
    result = simulate(model(), rtol=1e-10, atol=1e-10)
    assert result.success, result.message
    T, J, k = 2.0, 0.5, 0.25
    expected = np.sqrt(T / k) * np.tanh(result.time * np.sqrt(T * k) / J)
    np.testing.assert_allclose(result["flywheel.w"], expected, atol=1e-7)
    np.testing.assert_allclose(result["power"], T * result["flywheel.w"], atol=1e-12)
    assert result["drag.k"][0] == k


def test_parameters_given_at_run_time_and_as_modifiers_work_on_a_loaded_model():
    model = load(DRIVE)
    stronger = simulate(model(), parameters={"T": 8.0}, stop_time=20.0)
    assert abs(stronger["flywheel.w"][-1] - np.sqrt(8.0 / 0.25)) < 1e-3
    as_modifier = simulate(model(T=8.0), stop_time=20.0)
    np.testing.assert_array_equal(stronger["flywheel.w"], as_modifier["flywheel.w"])


HYBRID = """
model Bounce "A ball bouncing on the floor, with a for-loop and an if-equation"
  parameter Real e = 0.8 "restitution";
  parameter Integer n = 3;
  Real h(start=1, fixed=true);
  Real v(start=0, fixed=true);
  Real x[n];
  Real s;
equation
  der(h) = v;
  der(v) = -9.81;
  when h < 0 then
    reinit(v, -e*pre(v));
  end when;
  for i in 1:n loop
    x[i] = i*h;
  end for;
  if h > 0.5 then
    s = 1;
  else
    s = 0;
  end if;
  annotation (experiment(StopTime=0.5));
end Bounce;
"""


def test_when_for_and_if_equations():
    result = simulate(load(HYBRID)(), stop_time=0.45, rtol=1e-10, atol=1e-10)
    t = result.time
    np.testing.assert_allclose(result["h"], 1 - 9.81 * t ** 2 / 2, atol=1e-8)  # the bounce is at 0.4515 s
    np.testing.assert_allclose(result["x[3]"], 3 * result["h"], atol=1e-12)
    clear = np.abs(result["h"] - 0.5) > 1e-9  # at the crossing itself both values are right
    np.testing.assert_array_equal(result["s"][clear], np.where(result["h"] > 0.5, 1.0, 0.0)[clear])
    assert any(e.time == pytest.approx(np.sqrt(1 / 9.81), abs=1e-8) for e in result.events)
    bounced = simulate(load(HYBRID)(), stop_time=0.6, rtol=1e-10, atol=1e-10)
    hit = np.sqrt(2 / 9.81)
    assert any(abs(e.time - hit) < 1e-6 for e in bounced.events)
    after = bounced.time > hit + 1e-3
    np.testing.assert_allclose(bounced["v"][after], 0.8 * 9.81 * hit - 9.81 * (bounced.time[after] - hit),
                               atol=1e-6)


def test_the_same_model_written_in_python_gives_the_same_flat_model():
    from acausal import Model
    from acausal.library.rotational import ConstantTorque, Inertia

    text = """
    model Two
      Modelica.Mechanics.Rotational.Sources.ConstantTorque source(tau_constant=3);
      Modelica.Mechanics.Rotational.Components.Inertia body(J=2, w(start=1, fixed=true));
    equation
      connect(source.flange, body.flange_a);
    end Two;
    """

    class Two(Model):
        def build(self):
            self.source = ConstantTorque(tau_constant=3)
            self.body = Inertia(J=2, w=dict(start=1, fixed=True))
            self.connect(self.source.flange, self.body.flange_a)

    written, read = flatten(Two()), flatten(load(text)())
    assert sorted(str(e.residual) for e in written.equations) == sorted(str(e.residual) for e in read.equations)
    assert {v.name: (v.start, v.fixed) for v in written.variables} == \
        {v.name: (v.start, v.fixed) for v in read.variables}


# -- errors ----------------------------------------------------------------------------------


def test_a_syntax_error_names_the_line_and_what_was_expected(tmp_path):
    path = tmp_path / "broken.mo"
    path.write_text("model Broken\n  Real x\nequation\n  x = 1;\nend Broken;\n")
    with pytest.raises(ModelicaSyntaxError, match=r"broken\.mo:3(:\d+)?: .*';'") as info:
        load(path)
    assert isinstance(info.value, SyntaxError)


def test_an_undefined_class_names_the_line_and_the_close_names():
    text = DRIVE.replace("Drag drag(k=k2/4);", "Dreg drag(k=k2/4);")
    with pytest.raises(ModelicaError, match=r"<text>:\d+: undefined type name 'Dreg'") as info:
        load(text)
    assert "did you mean Drag" in info.value.hint


def test_an_msl_class_acausal_lacks_is_said_so():
    text = """
    model M
      Modelica.Fluid.Vessels.OpenTank tank;
    end M;
    """
    with pytest.raises(ModelicaError, match=r"Modelica\.Fluid\.Vessels\.OpenTank is not in acausal's library"):
        load(text)


def test_a_modifier_of_an_element_the_class_lacks_names_it():
    text = """
    model M
      Modelica.Mechanics.Rotational.Components.Inertia body(K=2);
    end M;
    """
    with pytest.raises(ModelicaError, match=r"<text>:3: body \(Modelica.Mechanics.Rotational.Components.Inertia\)"
                                            r".*no parameter or variable named 'K'"):
        simulate(load(text)())


def test_a_file_with_several_models_asks_which(tmp_path):
    path = tmp_path / "two.mo"
    path.write_text("model A Real x(start=1, fixed=true); equation der(x) = -x; end A;\n"
                    "model B Real y(start=2, fixed=true); equation der(y) = -y; end B;\n")
    with pytest.raises(ModelicaError, match="defines several models"):
        load(path)
    result = simulate(load(path, "B")(), stop_time=1.0, rtol=1e-10, atol=1e-12)
    assert result["y"][-1] == pytest.approx(2 * np.exp(-1), rel=1e-7)


CONDITIONAL = """
model M
  parameter Boolean useDamper = true;
  parameter Boolean useHeat = false;
  parameter Real d = 2;
  Modelica.Mechanics.Rotational.Components.Inertia inertia(J=1, phi(start=0, fixed=true), w(start=1, fixed=true));
  Modelica.Mechanics.Rotational.Components.Damper damper(d=d) if useDamper;
  Modelica.Mechanics.Rotational.Components.Fixed fixed;
  Real q = 2*inertia.w if useHeat "only with heat";
equation
  connect(inertia.flange_b, damper.flange_a);
  connect(damper.flange_b, fixed.flange);
end M;
"""


@pytest.mark.parametrize("use_damper", [True, False])
def test_a_conditional_component_exists_with_its_connections_only_when_enabled(use_damper):
    """MLS 4.4.5: a disabled component is not there, and its connections are removed."""
    model = load(CONDITIONAL)(useDamper=use_damper)
    result = simulate(model, stop_time=1.0, rtol=1e-10, atol=1e-12)
    expected = np.exp(-2 * result.time) if use_damper else np.ones_like(result.time)
    np.testing.assert_allclose(result["inertia.w"], expected, rtol=1e-7)
    assert ("damper.tau" in result.names) is use_damper


@pytest.mark.parametrize("use_heat", [True, False])
def test_a_conditional_variable_and_its_binding(use_heat):
    result = simulate(load(CONDITIONAL)(useHeat=use_heat), stop_time=1.0, rtol=1e-10, atol=1e-12)
    assert ("q" in result.names) is use_heat
    if use_heat:
        np.testing.assert_allclose(result["q"], 2 * np.exp(-2 * result.time), rtol=1e-7)


def test_a_condition_must_be_known_when_the_model_is_built():
    text = """
    model M
      Real x(start=1, fixed=true);
      Real q if x > 0;
    equation
      der(x) = -x;
    end M;
    """
    with pytest.raises(ModelicaError, match=r"<text>:4: the condition of q is .*not a Boolean known"):
        flatten(load(text)())




def test_parses_are_kept_in_the_disk_cache(tmp_path, monkeypatch):
    """A text parsed once is read back from acausal's authenticated disk cache (not parsed
    again), and a damaged entry is parsed anew, to the same model."""
    from acausal.modelica import read as reader

    monkeypatch.setenv("ACAUSAL_DISK_CACHE", "on")
    monkeypatch.setenv("ACAUSAL_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "config"))
    text = "model Decay Real x(start=1, fixed=true); equation der(x) = -x; end Decay; // cached"
    parses = []
    parser = reader._pymoca_parser()
    plain = parser.parse
    monkeypatch.setattr(parser, "parse", lambda *args, **kw: parses.append(1) or plain(*args, **kw))
    reader._parsed.cache_clear()
    first = simulate(load(text)(), stop_time=1.0)
    assert len(parses) == 1
    reader._parsed.cache_clear()  # a new process, as far as the parse is concerned
    second = simulate(load(text)(), stop_time=1.0)
    assert len(parses) == 1
    np.testing.assert_array_equal(first["x"], second["x"])
    for entry in (tmp_path / "cache").rglob("*.json"):  # damage the entry: it fails its MAC
        raw = bytearray(entry.read_bytes())
        if b'"pickle": "' not in raw:
            continue  # a compiled system's entry
        at = raw.index(b'"pickle": "') + 20
        raw[at] = ord("A") if raw[at] != ord("A") else ord("B")
        entry.write_bytes(bytes(raw))
    reader._parsed.cache_clear()
    third = simulate(load(text)(), stop_time=1.0)
    assert len(parses) == 2
    np.testing.assert_array_equal(first["x"], third["x"])
    reader._parsed.cache_clear()


COEFFICIENTS = """
model Coefficients "sizes written as expressions, a function with two outputs, Evaluate"
  function twoPowers
    input Real T;
    input Integer n;
    output Real b[n] "T^1 ... T^n";
    output Real a[n + 1] "1, T ... T^n";
  algorithm
    a[1] := 1;
    for i in 1:n loop
      b[i] := T^i;
      a[i + 1] := b[i];
    end for;
  end twoPowers;
  parameter Real T = 2;
  parameter Integer n = 2;
  parameter Integer m = n "bound to another structural parameter";
  parameter Real k = 3 annotation(Evaluate=true);
  Real b[m];
  Real a[m + 1];
equation
  (b, a) = twoPowers(T, m);
end Coefficients;
"""


def test_sizes_as_expressions_and_an_equation_of_several_function_outputs():
    model = load(COEFFICIENTS)
    flat = flatten(model())
    residuals = sorted(str(e.residual) for e in flat.equations)
    assert residuals == ["a[1] - 1.0", "a[2] - 2.0", "a[3] - 4.0", "b[1] - 2.0", "b[2] - 4.0"]
    # T is passed to a function, which acausal evaluates when it reads the model: T is
    # structural (used by value), as is k, which its annotation asks to evaluate
    assert {p.name for p in flat.parameters} == set()


def test_a_structural_parameter_given_a_variable_keeps_it():
    """Show.IntegerValue's ``number`` is a time-varying input the library declares structural:
    a modifier giving it another block's output is kept as that variable (MSL IntegerNetwork1)."""
    model = load("""
model ShowIt
  Modelica.Blocks.Sources.IntegerConstant c(k=3);
  Modelica.Blocks.Interaction.Show.IntegerValue show(use_numberPort=false, number=c.y);
end ShowIt;
""")
    flat = flatten(model())
    assert {(e.variable, str(e.rhs)) for e in flat.discrete_equations} >= {("show.showNumber", "c.y")}


def test_a_record_of_parameters_and_the_import_forms():
    """A record's elements are parameters of a parameter record (MLS 4.5); qualified, single,
    wildcard and renaming imports (MLS 13.2) name the same library classes."""
    text = """
    package P
      record Data
        Real k = 2;
        Real T = 0.5;
      end Data;
      model M
        import Modelica.Mechanics.Rotational.Components.Inertia;
        import R = Modelica.Mechanics.Rotational;
        import Modelica.Mechanics.Rotational.Sources.*;
        import Modelica.Mechanics.Rotational;
        parameter Data data(k=3);
        Real x(start=0, fixed=true);
        Inertia J(J=1, phi(start=0, fixed=true), w(start=0, fixed=true));
        ConstantTorque source(tau_constant=2);
        R.Components.Fixed fixed;
        Rotational.Components.Damper damper(d=1);
      equation
        data.T*der(x) = data.k - x;
        connect(source.flange, J.flange_a);
        connect(J.flange_b, damper.flange_a);
        connect(damper.flange_b, fixed.flange);
      end M;
    end P;
    """
    result = simulate(load(text, "P.M")(), stop_time=1.0, rtol=1e-10, atol=1e-12)
    t = result.time
    np.testing.assert_allclose(result["x"], 3 * (1 - np.exp(-t / 0.5)), rtol=1e-7, atol=1e-9)
    # J dw/dt = 2 - w: w = 2 (1 - exp(-t))
    np.testing.assert_allclose(result["J.w"], 2 * (1 - np.exp(-t)), rtol=1e-7, atol=1e-9)


def test_a_redeclared_simple_type_changes_that_instance_only():
    """redeclare type T = Real(...) (MLS 7.3) gives the declarations of that type in the one
    instance the new attributes: here a start value and a unit."""
    text = """
    model M
      model Decay
        replaceable type T = Real(start=1);
        T x(fixed=true);
      equation
        der(x) = -x;
      end Decay;
      Decay plain;
      Decay redeclared(redeclare type T = Real(unit="m", start=2));
    end M;
    """
    model = load(text)
    result = simulate(model(), stop_time=1.0, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(result["plain.x"], np.exp(-result.time), rtol=1e-7)
    np.testing.assert_allclose(result["redeclared.x"], 2 * np.exp(-result.time), rtol=1e-7)
    units = {v.name: v.unit for v in flatten(model()).variables}
    assert units["redeclared.x"] == "m" and units["plain.x"] == ""


def test_redeclare_of_a_component_is_refused_clearly():
    text = """
    model M
      model A Real x = 1; end A;
      model B Real x = 2; end B;
      model Holder replaceable A a; end Holder;
      Holder h(redeclare B a);
    end M;
    """
    with pytest.raises(ModelicaError, match="redeclare of a component or a class is not supported"):
        flatten(load(text)())


SELF_READING = """
model SelfReading "a modifier that reads the component it modifies, and a connector restated"
  parameter Real f = 10;
  Modelica.Electrical.Analog.Sources.TrapezoidVoltage vIn(V=1, rising=0.2/f, width=0.3/f, falling=0.2/f,
    period=1/f, startTime=-(vIn.rising + vIn.width/2));
  Modelica.Electrical.Analog.Basic.Resistor r(R=1, p(i(start=0, fixed=false)));
  Modelica.Electrical.Analog.Basic.Ground ground;
equation
  connect(vIn.p, r.p);
  connect(vIn.n, r.n);
  connect(r.n, ground.p);
end SelfReading;
"""


def test_a_modifier_reads_the_component_it_modifies_in_the_enclosing_class():
    """MLS 7.2: vIn.rising in vIn's own modification is the value that modification gives rising;
    a connector modifier that restates its variables' attributes changes nothing."""
    flat = flatten(load(SELF_READING)())
    values = {p.name: p.value for p in flat.parameters}
    assert values["vIn.startTime"] == pytest.approx(-(0.02 + 0.03 / 2), rel=1e-15)


def test_a_connector_modifier_that_changes_an_attribute_is_refused():
    with pytest.raises(ModelicaError, match="connector"):
        flatten(load(SELF_READING.replace("r(R=1, p(i(start=0, fixed=false)))", "r(R=1, p(i(start=1)))"))())


RECORDS = """
model Records "a record given whole as a modifier binds each of its parameters"
  record Data
    parameter Real R = 2;
  end Data;
  model Load
    parameter Real R = 1;
    Modelica.Electrical.Analog.Basic.Resistor r(R=R);
  end Load;
  parameter Data data(R=3);
  Load load(R=data.R);
end Records;
"""


def test_a_record_component_s_parameters_are_read_by_modifiers():
    flat = flatten(load(RECORDS)())
    values = {p.name: p.value for p in flat.parameters}
    assert values["load.R"] == pytest.approx(3.0) and values["data.R"] == pytest.approx(3.0)
