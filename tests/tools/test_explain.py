"""Tests of acausal.tools.explain: the stage-by-stage teaching view."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from acausal import Experiment, Model, simulate, translate
from acausal.tools.explain import MAX_PICTURES, Explanation, explain
from examples.first import First
from examples.two_masses import TwoMasses
from acausal.library.rotational import Inertia
from acausal.library.rotational.sources import TorqueStep

PNG = b"\x89PNG\r\n\x1a\n"


class StepDrive(Model):
    """An inertia driven by a torque step: a time event, two discrete states."""

    experiment = Experiment(stop_time=1.0, interval=0.01)

    def build(self):
        self.step = TorqueStep(stepTorque=1.0, offsetTorque=0.0, startTime=0.5)
        self.inertia = Inertia(J=1, phi=dict(start=0, fixed=True), w=dict(start=0, fixed=True))
        self.connect(self.step.flange, self.inertia.flange_a)


def section(text: str, number: int) -> str:
    """The body of section ``number`` ("3. Structural analysis" up to the next one)."""
    match = re.search(rf"^{number}\. .*?(?=^\d+\. |\Z)", text, flags=re.S | re.M)
    assert match, f"no section {number}"
    return match.group(0)


@pytest.fixture(scope="module")
def first(tmp_path_factory) -> tuple[Explanation, Path]:
    out = tmp_path_factory.mktemp("first")
    return explain(First(), out_dir=out), out


def test_sections_in_order(first):
    explanation, _ = first
    text = str(explanation)
    assert text == explanation.text
    headings = re.findall(r"^\d+\. (.*)$", text, flags=re.M)
    assert headings[:7] == ["Flat model", "Alias elimination", "Structural analysis", "Matching",
                            "BLT: block lower triangular order", "Generated code", "Pass log"]
    # First's Sine has `time < startTime`: a relation, so the model is hybrid
    assert headings[7].startswith("Hybrid part")


def test_pass_log_lists_the_pipeline_in_order(first):
    explanation, _ = first
    section = explanation.text.split("Pass log", 1)[1].split("Hybrid part", 1)[0]
    mode = re.findall(r"^ {2}([a-z][a-z ]+?)\s+\d+\.\d+ ms$", section, flags=re.M)
    initial = re.findall(r"^ {4}([a-z][a-z ]+?)\s+\d+\.\d+ ms$", section, flags=re.M)
    # the pipeline's order, as the mode compiler and the initialization stage run it
    assert mode == ["specialise", "alias", "structure", "blt", "algebraic", "codegen"]
    assert initial == ["initial equations", "matching", "blt", "algebraic", "codegen"]


def test_flat_equations_numbered_with_origin(first):
    explanation, _ = first
    flat = translate(First()).flat
    body = section(explanation.text, 1)
    assert flat.summary() in body
    for k, eq in enumerate(flat.equations, start=1):
        assert re.search(rf"^\s*\[\s*{k}\] {re.escape(str(eq.origin))}$", body, flags=re.M)


def test_stage_outputs_match_the_translation(first):
    explanation, _ = first
    text = explanation.text
    translation = translate(First())
    simulate(translation)
    (system,) = translation.systems.values()
    aliases = section(text, 2)
    n_removed = len(system.aliases.eliminated)
    assert f"{n_removed} of {len(system.equations)} equations removed" in aliases
    for name, expr in system.aliases.aliases.items():
        assert re.search(rf"^\s+{re.escape(name)}\s+= {re.escape(str(expr))}$", aliases, flags=re.M)

    structure = section(text, 3)
    states = ", ".join(system.structure.states)
    assert f"States chosen ({len(system.structure.states)}): {states}" in structure
    for i, k in system.structure.differentiated:
        assert f"E{i + 1} = d/dt E{k + 1}" in structure
    flat_dummies = " ".join(section(text, 3).split())
    for name in system.structure.dummy_derivatives:
        assert name in flat_dummies

    matching = section(text, 4)
    pairs = re.findall(r"^\s+E(\d+)\s+-> (\S+)$", matching, flags=re.M)
    assert [(int(i) - 1, u) for i, u in pairs] == [
        (i, system.structure.unknowns[j]) for i, j in enumerate(system.structure.matching)]

    blt = section(text, 5)
    assert re.findall(r"^\s+B(\d+)\s", blt, flags=re.M) == [
        str(n) for n in range(1, len(system.blt.blocks) + 1)]
    assert "torn linear" in blt and "tearing unknowns" in blt

    code = section(text, 6)
    assert "def derivatives(t, x):" in code
    assert f"x0 = {system.structure.states[0]}" in code


def test_hybrid_section(first):
    explanation, _ = first
    hybrid = section(explanation.text, 8)
    assert "sine.startTime > time" in hybrid and "time event" in hybrid
    assert "simulated the model first" in hybrid
    assert "State 1:" in hybrid and "visited" in hybrid


def test_picture(first):
    explanation, out = first
    assert explanation.pictures == (out / "incidence_First.png",)
    assert explanation.pictures[0].read_bytes()[:8] == PNG


def test_deterministic(tmp_path):
    a = explain(First(), out_dir=tmp_path / "a")
    b = explain(First(), out_dir=tmp_path / "b")
    # everything but the measured seconds of the pass log: the same pass names, in the same order
    seconds = re.compile(r"\s*\d+\.\d\d ms$", flags=re.M)
    assert seconds.sub("ms", a.text) == seconds.sub("ms", b.text)
    assert len(seconds.findall(a.text)) >= 6
    assert [p.name for p in a.pictures] == [p.name for p in b.pictures]


def test_continuous_model(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    explanation = explain(TwoMasses())  # default out_dir: the current directory
    text = explanation.text
    assert "Hybrid part" not in text and "simulated" not in text
    assert "Initial equations (1)" in text
    assert "Explanation of TwoMasses (Modelica.Thermal.HeatTransfer.Examples.TwoMasses)" in text
    assert explanation.pictures == (tmp_path / "incidence_TwoMasses.png",)
    assert explanation.pictures[0].read_bytes()[:8] == PNG


def test_hybrid_model_with_several_states(tmp_path):
    explanation = explain(StepDrive(), out_dir=tmp_path)
    text = explanation.text
    assert "(step.startTime > time)=True" in text and "(step.startTime > time)=False" in text
    assert "Discrete states compiled (2, 2 distinct systems)" in text
    # each picture's file says which discrete state it shows (a relation true, or none)
    assert sorted(p.name for p in explanation.pictures) == [
        "incidence_StepDrive_all_conditions_false.png", "incidence_StepDrive_step.startTime-gt-time.png"]
    for picture in explanation.pictures:
        assert picture.read_bytes()[:8] == PNG


def test_explicit_key_and_translation_reuse(tmp_path):
    translation = translate(StepDrive())
    explanation = explain(translation, out_dir=tmp_path, key=(True,))
    text = explanation.text
    assert "Sections 2-6 show the system of the discrete state [(step.startTime > time)=True]" \
        in " ".join(text.split())
    assert "simulated the model first" not in text  # a key given: nothing simulated
    assert list(translation.systems) == [(True,)]
    assert [p.name for p in explanation.pictures] == ["incidence_StepDrive.png"]


def test_already_simulated_translation_is_not_simulated_again(tmp_path):
    translation = translate(StepDrive())
    simulate(translation)
    compiled = list(translation.systems)
    explanation = explain(translation, out_dir=tmp_path)
    assert list(translation.systems) == compiled
    assert "simulated the model first" not in explanation.text
    assert len(explanation.pictures) == len(compiled) <= MAX_PICTURES


def test_independent_parts_are_listed_with_their_systems(tmp_path):
    """A model of independent units: explain lists each part with its states and BLT."""
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "compiler"))
    from test_clusters import storm

    text = str(explain(storm(3), out_dir=tmp_path))
    section = text[text.index("Independent parts"):]
    assert "3 parts that share no variable" in section
    for k in range(3):
        assert f"part {k + 1}:" in section
        assert f"states: j{k}.phi, j{k}.w" in section
