"""The contract between compiler and runtime (acausal/runtime/contract.py).

The runtime depends on the compiled model only through the Protocols of
``acausal.runtime.contract``: importing it loads neither sympy nor networkx,
it generates no code, and the compiler's objects satisfy the Protocols.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

from acausal import simulate, translate
from acausal.compiler.clusters import ComposedSystem
from acausal.compiler.modes import ModeSystem
from acausal.runtime.contract import CompiledModel, CompiledSystem, is_compiled_model
from examples.coupled_clutches import CoupledClutches
from tests.compiler.test_clusters import storm

RUNTIME = Path(__file__).resolve().parents[2] / "acausal" / "runtime"
RUNTIME_MODULES = sorted(f"acausal.runtime.{p.stem}" for p in RUNTIME.glob("*.py") if p.stem != "__init__")


def test_every_runtime_module_imports_without_sympy_or_networkx():
    # sympy and networkx made unimportable: an import of either anywhere in the runtime fails
    code = ("import sys\n"
            "sys.modules['sympy'] = None\nsys.modules['networkx'] = None\n"
            f"for name in {RUNTIME_MODULES!r}:\n"
            "    __import__(name)\n"
            "import acausal\n"
            "print(sorted(m for m in ('scipy', 'pandas', 'matplotlib') if m in sys.modules))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                          cwd=RUNTIME.parents[1])
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_the_runtime_generates_no_code():
    """No exec, eval, compile or lambdify in the runtime: code comes from the compiler."""
    found = []
    for path in sorted(RUNTIME.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call):
                name = getattr(node.func, "id", None) or getattr(node.func, "attr", None)
                if getattr(getattr(node.func, "value", None), "id", None) == "re":
                    continue  # re.compile: a pattern, not code
                if name in ("exec", "eval", "compile", "lambdify", "compile_functions"):
                    found.append(f"{path.name}:{node.lineno} {name}")
    assert not found


def test_a_translation_and_its_systems_satisfy_the_contract():
    translation = translate(CoupledClutches())
    assert isinstance(translation, CompiledModel) and is_compiled_model(translation)
    assert not is_compiled_model(CoupledClutches())
    simulate(translation)
    assert translation.systems
    for system in translation.systems.values():
        assert isinstance(system, ModeSystem) and isinstance(system, CompiledSystem)


def test_a_composed_system_satisfies_the_contract():
    from acausal import EngineOptions

    translation = translate(storm(2), cache=False)
    simulate(translation, stop_time=0.5, options=EngineOptions(parts_apart=False))  # composed systems
    composed = [s for s in translation.systems.values() if isinstance(s, ComposedSystem)]
    assert composed
    assert all(isinstance(s, CompiledSystem) for s in composed)
    # its numpy form is the parts', laid end to end: equal to the scalar function
    import numpy as np

    system = composed[0]
    many = system.vectorised("crossings")
    assert many is not None
    X = np.zeros((len(system.states), 3))
    t = np.array([0.0, 0.1, 0.2])
    got = many(t, X)
    for j in range(3):
        np.testing.assert_array_equal(got[:, j], np.asarray(system.crossings(t[j], X[:, j]), dtype=float))


@pytest.mark.parametrize("what", ["time_events", "clock_ticks", "delay_numbers"])
def test_the_numbers_the_runtime_asks_for_are_plain_numbers(what):
    translation = translate(CoupledClutches())
    answer = getattr(translation, what)()
    flat = []

    def walk(value):
        if isinstance(value, (tuple, list)):
            for v in value:
                walk(v)
        elif isinstance(value, dict):
            walk(list(value.items()))
        else:
            flat.append(value)

    walk(answer if what != "time_events" else answer[0])
    assert all(isinstance(v, (int, float)) for v in flat), flat


def test_the_runtime_reads_the_model_through_its_data_only():
    """No runtime module reaches for the compiler's flat or partitioned model or its cache."""
    found = []
    for path in sorted(RUNTIME.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Attribute) and node.attr in ("flat", "partitioned", "cache", "continuous"):
                found.append(f"{path.name}:{node.lineno} .{node.attr}")
    assert not found


def test_the_model_data_loads_where_sympy_cannot_be_imported(tmp_path):
    import pickle

    translation = translate(CoupledClutches())
    data = translation.data
    path = tmp_path / "data.pickle"
    path.write_bytes(pickle.dumps(data))
    code = ("import pickle, sys\n"
            "sys.modules['sympy'] = None\nsys.modules['networkx'] = None\n"
            f"data = pickle.loads(open({str(path)!r}, 'rb').read())\n"
            "print(data.name, len(data.relations), len(data.variables), data.selectors[:1])\n"
            "print([r.holds(1.0) for r in data.relations[:3]])\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                          cwd=RUNTIME.parents[1])
    assert done.returncode == 0, done.stderr
    first, second = done.stdout.splitlines()
    assert first == f"{data.name} {len(data.relations)} {len(data.variables)} {data.selectors[:1]}"
    assert second == str([r.holds(1.0) for r in data.relations[:3]])
    # the data is the translation's: every relation decided as the compiler's own
    for mine, theirs in zip(data.relations, translation.partitioned.relations):
        assert (mine.index, mine.name, mine.op, mine.text) == (theirs.index, theirs.symbol.name, theirs.op,
                                                              theirs.text)
        for g in (-1.0, 0.0, 1e-12, 1.0):
            assert mine.holds_with_hysteresis(g, True, 1e-10) == theirs.holds_with_hysteresis(g, True, 1e-10)


def test_the_runtime_does_not_tell_system_kinds_apart_by_probing():
    """Whole-model and composed systems answer the same contract: no getattr probing of
    ``parts`` or ``crossings_for`` in the runtime."""
    found = []
    for path in sorted(RUNTIME.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if (isinstance(node, ast.Call) and getattr(node.func, "id", None) in ("getattr", "hasattr")
                    and len(node.args) >= 2 and isinstance(node.args[1], ast.Constant)
                    and node.args[1].value in ("parts", "crossings_for", "vectorised")):
                found.append(f"{path.name}:{node.lineno}")
    assert not found
