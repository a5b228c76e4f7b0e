"""The same model always translates to the same code and simulates to the same bits.

Checked for examples/first.py: two fresh instances in this process, and
fresh interpreters with different PYTHONHASHSEED values (set and dict
iteration orders of strings change with the seed, so any dependence of the
engine on them shows up as different code or equation order).
"""

from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from acausal import simulate
from acausal.compiler.translate import translate

ROOT = Path(__file__).resolve().parent.parent


def _simulated_first():
    """Translate a fresh First() and simulate it; the compiled systems are those the run visited."""
    from examples.first import First

    translation = translate(First())
    result = simulate(translation)
    assert result.success, result.message
    return translation, result


def _systems(translation) -> dict:
    """The structure of every compiled system (continuous and initialization), by discrete state."""
    out = {f"mode {key!r}": _structure(mode) for key, mode in sorted(translation.systems.items(), key=repr)}
    for key, init in sorted(translation.initial_systems.items(), key=repr):
        out[f"init {key!r}"] = {"source": init.code.source,
                                "equations": [f"{e.origin} | {e.residual}" for e in init.equations],
                                "unknowns": list(init.unknowns),
                                "blt_order": list(init.blt.equation_order)}
    return out


def _structure(mode) -> dict:
    """Generated source, equation order, states, unknowns and BLT order of a compiled system."""
    return {
        "source": mode.code.source,
        "equations": [f"{e.origin} | {e.residual}" for e in mode.equations],
        "structure_equations": [f"{e.origin} | {e.residual}" for e in mode.structure.equations],
        "states": list(mode.structure.states),
        "unknowns": list(mode.structure.unknowns),
        "matching": list(mode.structure.matching),
        "blt_order": list(mode.blt.equation_order),
        "aliases": sorted(f"{k} = {v}" for k, v in mode.aliases.aliases.items()),
    }


def _result_digest(result) -> dict:
    """SHA-256 of the raw bytes of every result column (bitwise identity)."""
    digest = {"time": hashlib.sha256(result.time.tobytes()).hexdigest()}
    for name in sorted(result.names):
        digest[name] = hashlib.sha256(np.ascontiguousarray(result[name]).tobytes()).hexdigest()
    return digest


def fingerprint() -> dict:
    """Everything that must not change between runs of examples/first.py."""
    translation, result = _simulated_first()
    return {"structure": _systems(translation), "result": _result_digest(result), "names": list(result.names)}


def test_two_fresh_instances_translate_identically():
    """Two First() instances give the same generated code, equation order and bitwise equal results."""
    t1, r1 = _simulated_first()
    t2, r2 = _simulated_first()
    s1, s2 = _systems(t1), _systems(t2)
    assert len(s1) >= 2  # at least one continuous system and its initialization problem
    assert list(s1) == list(s2)
    for key in s1:
        assert s1[key]["source"] == s2[key]["source"], key
        assert s1[key] == s2[key], key
    assert r1.names == r2.names
    assert r1.time.tobytes() == r2.time.tobytes()
    for name in r1.names:
        assert np.asarray(r1[name]).tobytes() == np.asarray(r2[name]).tobytes(), name


def _fingerprint_in_subprocess(seed: str) -> dict:
    env = dict(os.environ, PYTHONHASHSEED=seed, PYTHONPATH=os.pathsep.join([str(ROOT), str(ROOT / "tests")]))
    code = "import json, test_determinism as m; print(json.dumps(m.fingerprint()))"
    completed = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True,
                               text=True, timeout=300)
    assert completed.returncode == 0, completed.stderr
    return json.loads(completed.stdout.strip().splitlines()[-1])


def test_translation_and_results_do_not_depend_on_the_hash_seed():
    """Fresh interpreters with PYTHONHASHSEED 0 and 4242 reproduce this process's code, order and result bits."""
    here = json.loads(json.dumps(fingerprint()))
    for seed in ("0", "4242"):
        there = _fingerprint_in_subprocess(seed)
        assert list(there["structure"]) == list(here["structure"])
        for key in here["structure"]:
            assert there["structure"][key]["source"] == here["structure"][key]["source"], \
                f"seed {seed}: code of {key} differs"
        assert there["structure"] == here["structure"], f"seed {seed}: structure differs"
        assert there["names"] == here["names"]
        assert there["result"] == here["result"], f"seed {seed}: results differ"


def test_two_runs_of_one_translation_give_the_same_bits():
    """The generated Newton solves start each call from the last solution (a warm start); a
    new run starts them from the start values again.  Without that, the second run of the
    rectifier starts its diode's Newton solve where the first run ended and fails, and the
    resistor's first row differs in the last bits."""
    from examples.electrical_resistor import ResistorExample
    from examples.electrical_semiconductors import HeatingRectifier

    for model in (ResistorExample(), HeatingRectifier()):
        translation = translate(model, cache=False)
        first, second = simulate(translation), simulate(translation)
        assert first.success and second.success, second.message
        np.testing.assert_array_equal(second.time, first.time)
        for name in first.columns:
            np.testing.assert_array_equal(second[name], first[name])
