"""Writing Modelica text: every example written with ``dump`` reads back to the same model (issue 26).

The round trip is checked on the flat model (the same equations, variables
and start values: what the engine computes from) for every model of
``examples/``, and on the simulated arrays for models of each kind: library
components only, a component class of the user's own, when-clauses and
reinit, arrays of components.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pymoca")

from acausal import Model, simulate  # noqa: E402
from acausal.compiler.flatten import flatten  # noqa: E402
from acausal.modelica import dump, load  # noqa: E402
from acausal.tools.modelfile import _import_file, _models_defined  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def _example_models() -> list[tuple[str, type]]:
    found = []
    for path in sorted((ROOT / "examples").glob("*.py")):
        if path.name in ("__init__.py", "benchmarks.py"):
            continue
        module = _import_file(path, str(path))
        found += [(f"{path.stem}:{klass.__name__}", klass) for klass in _models_defined(module)]
    return found


EXAMPLES = _example_models()


def _flat_form(model):
    flat = flatten(model)
    return (sorted(str(e.residual) for e in flat.equations),
            sorted(str(e.residual) for e in flat.initial_equations),
            {v.name: (v.start, v.fixed, v.kind) for v in flat.variables},
            {p.name: repr(p.value) for p in flat.parameters})


@pytest.mark.parametrize("spec, klass", EXAMPLES, ids=[s for s, _ in EXAMPLES])
def test_every_example_reads_back_to_the_same_flat_model(spec, klass):
    text = dump(klass())
    assert text.startswith(f"model {klass.__name__}") and text.rstrip().endswith(f"end {klass.__name__};")
    assert _flat_form(load(text)()) == _flat_form(klass())


@pytest.mark.parametrize("spec", ["first:First", "flywheel:Flywheel", "bouncing_ball:BouncingBall",
                                  "coupled_clutches:CoupledClutches", "sampled_speed_control:SampledSpeedControl"])
def test_the_written_model_gives_the_same_arrays(spec):
    klass = dict(EXAMPLES)[spec]
    written = simulate(klass())
    read = simulate(load(dump(klass()))())
    assert written.success and read.success, (written.message, read.message)
    assert written.names == read.names
    for name in written.names:
        np.testing.assert_array_equal(written[name], read[name], err_msg=name)


def test_library_components_are_written_as_their_msl_classes_with_their_modifiers():
    from acausal.examples.first import First

    text = dump(First())
    assert "Modelica.Mechanics.Rotational.Components.Inertia inertia1(J=Jmotor);" in text
    assert "Modelica.Mechanics.Rotational.Components.Inertia inertia2(J=2, phi(start=0, fixed=true), " \
           "w(start=0, fixed=true));" in text
    assert "connect(inertia1.flange_b, idealGear.flange_a);" in text
    assert "annotation(experiment(StartTime=0.0, StopTime=1.0, Interval=0.001), " \
           "__acausal(modelicaClass=\"Modelica.Mechanics.Rotational.Examples.First\"));" in text
    assert load(text).modelica_class == "Modelica.Mechanics.Rotational.Examples.First"


def test_a_class_of_the_user_s_own_is_written_with_its_equations():
    from acausal.examples.flywheel import Flywheel

    text = dump(Flywheel())
    own = [line.strip() for line in text.splitlines()]
    assert any(line.startswith("model QuadraticDrag") for line in own)
    assert "tau = k*w*abs(w);" in own and "w = der(flange.phi);" in own    # its equations, as written


def test_an_array_of_components_with_a_value_per_element():
    from acausal.examples.heat_rod import HeatRod

    model = HeatRod(n=4)
    text = dump(model)
    assert "cell[4](" in text
    assert _flat_form(load(text)()) == _flat_form(HeatRod(n=4))


def test_the_command_line_writes_a_file_that_simulates(tmp_path):
    out = tmp_path / "First.mo"
    run = subprocess.run([sys.executable, "-m", "acausal", "export", str(ROOT / "examples" / "first.py"),
                          "--modelica", str(out)], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    csv = tmp_path / "first.csv"
    run = subprocess.run([sys.executable, "-m", "acausal", "simulate", str(out), "--out", str(csv),
                          "--signals", "inertia3.w"], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    from acausal.examples.first import First

    columns = np.genfromtxt(csv, delimiter=",", names=True)
    np.testing.assert_allclose(columns["inertia3w"], simulate(First())["inertia3.w"], rtol=0, atol=1e-12)


def test_arrays_are_modified_and_declared_whole():
    """Modelica names a component without subscripts in a modification (MLS 7.2): the
    elements of an array a component holds one by one are written as one array."""
    from acausal.examples.blocks_pade_delay import PadeDelay1
    from acausal.library.blocks import Constant
    from acausal.library.blocks.continuous import StateSpace, TransferFunction

    class Arrays(Model):
        def build(self):
            self.tf = TransferFunction(a=[1.0, 2.0], b=[1.0])
            self.ss = StateSpace(A=[[1.0, 0.0], [0.0, 1.0]], B=[[1.0], [1.0]], C=[[1.0, 1.0]],
                                 x=dict(start=[1.0, 2.0], fixed=True))
            self.one = Constant(k=1.0)
            self.connect(self.one.y, self.tf.u)
            self.connect(self.one.y, self.ss.u[1])

    text = dump(Arrays())
    assert "tf(a={1.0, 2.0}, b={1.0}" in text and "A=[1.0, 0.0; 0.0, 1.0]" in text
    assert "x(start={1.0, 2.0}, fixed={true, true})" in text
    assert _flat_form(load(text)()) == _flat_form(Arrays())
    own = dump(PadeDelay1())
    assert 'Real x[10] "State of transfer function' in own and "Real x[1] " not in own
    # a structural Real parameter is marked so that it reads back structural (MLS 18.3)
    assert 'parameter Real delayTime(unit="s") = 0.2 "Delay time of output with respect to input signal" ' \
           'annotation(Evaluate=true);' in own
