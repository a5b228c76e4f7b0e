"""Warnings are part of the result: a cached run says what an uncached one says.

A model with two friction elements stuck on one rigid shaft (the holding
torque's split is left open: RedundantConstraintWarning) and an angle that
no equation fixes at t = 0 (StartValueWarning).  The first run compiles
everything; a second process loads the compiled systems from the disk
cache; a second run in the same process reuses the in-memory translation.
All of them must give the same warnings and the same notes, and the long
warnings must be multi-line, naming the components on their first line.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import warnings
from pathlib import Path

from acausal import Model, simulate
from acausal.errors import RedundantConstraintWarning, StartValueWarning
from acausal.library.rotational import BearingFriction, ConstantTorque, Inertia


class TwoStuckBearings(Model):
    """A torque of 0.5 N.m below the combined static limit 1 + 2 N.m: both bearings hold."""

    def build(self):
        self.torque = ConstantTorque(tau_constant=0.5)
        self.inertia = Inertia(J=1.0, phi=dict(start=0.25), w=dict(start=0.0, fixed=True))
        self.bf1 = BearingFriction(tau_pos=[[0.0, 1.0]])
        self.bf2 = BearingFriction(tau_pos=[[0.0, 2.0]])
        self.connect(self.torque.flange, self.inertia.flange_a)
        self.connect(self.inertia.flange_b, self.bf1.flange_a)
        self.connect(self.bf1.flange_b, self.bf2.flange_a)


def said(**options) -> dict:
    """The warnings (category and text) and notes of one run, and whether it rested."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = simulate(TwoStuckBearings(), stop_time=1.0, **options)
    return {"warnings": [[w.category.__name__, str(w.message)] for w in caught
                         if issubclass(w.category, (RedundantConstraintWarning, StartValueWarning))],
            "notes": list(result.notes), "at_rest": float(abs(result["inertia.w"]).max()) < 1e-12,
            "phi0": float(result["inertia.phi"][0])}


SCRIPT = f"""
import json, sys
sys.path.insert(0, {str(Path(__file__).parent)!r})
from test_warnings_survive_the_cache import said
print(json.dumps(said()))
"""


def test_a_run_from_the_disk_cache_says_what_a_compiling_run_says(tmp_path):
    uncached = said(cache=False)
    script = tmp_path / "run.py"
    script.write_text(SCRIPT)
    env = dict(os.environ, ACAUSAL_DISK_CACHE="on", ACAUSAL_CACHE_DIR=str(tmp_path / "cache"),
               XDG_CONFIG_HOME=str(tmp_path / "config"))
    runs = []
    for _ in range(2):
        run = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env, timeout=300)
        assert run.returncode == 0, run.stderr
        runs.append(json.loads(run.stdout.splitlines()[-1]))
    assert any(tmp_path.joinpath("cache").rglob("*")), "nothing was stored on disk"
    compiled, loaded = runs
    assert compiled == uncached
    assert loaded == uncached
    categories = sorted(category for category, _ in uncached["warnings"])
    assert categories == ["RedundantConstraintWarning", "StartValueWarning"]
    # every warning is also a note of the result
    assert sorted(text for _, text in uncached["warnings"]) == sorted(uncached["notes"])
    # the physics the warnings speak of: the shaft rests, the angle is its start value
    assert uncached["at_rest"] and uncached["phi0"] == 0.25


def test_a_second_run_in_the_same_process_says_it_again():
    first = said()
    second = said()
    assert first == second
    assert len(first["warnings"]) == 2


def test_long_warnings_name_the_components_first_one_fact_per_line():
    texts = dict(said(cache=False)["warnings"])
    redundant = texts["RedundantConstraintWarning"].splitlines()
    assert redundant[0].split(":")[0] in ("bf1", "bf2")          # the components first
    assert "TwoStuckBearings" in redundant[0]
    labels = [line.strip().split(":")[0] for line in redundant[1:]]
    assert labels == ["left out", "set to 0", "discrete state", "hint"]
    assert "bf1.locked=True" in redundant[3] and "bf2.locked=True" in redundant[3]
    start = texts["StartValueWarning"].splitlines()
    # the angle is one state shared by the source, the inertia and both bearings
    assert set(start[0].split(":")[0].split(", ")) == {"torque", "inertia", "bf1", "bf2"}
    assert start[1].strip().endswith("= 0.25")
    assert start[-1].strip().startswith("hint:")
