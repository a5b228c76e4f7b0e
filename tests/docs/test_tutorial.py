"""docs/tutorial.md runs as written, its shown outputs are what it prints, and its claims hold.

How the document is run (the rules the tutorial follows):

- ```python blocks are executed in document order in one namespace (``__name__`` is
  ``"__main__"``, as in a script), with a fresh folder as the working directory, so
  the files the code writes land there;
- in ```sh blocks every line starting with ``acausal`` runs through
  ``acausal.tools.cli.main`` with the repository root as the working directory (so
  ``examples/...`` resolves); the value of ``--out``, ``--html`` and ``--plot`` is
  taken relative to the folder of the python blocks, so a later python block reads
  what a command wrote, as it would for a reader working in one folder.  A line
  whose comment says ``not run`` is skipped; other lines (comments) are ignored;
- a ```text block is the printed output of the python or sh block before it: its
  lines must appear in that output as consecutive lines (trailing blanks ignored);
  a line ``...`` stands for any number of lines, also at the start or the end;
- every other fence (```python no-run, ```console, ...) is shown, not run.

The blocks run once per module (a fixture); the tests below then check the key
claims of the text against closed forms and the engine's own data.
"""

from __future__ import annotations

import contextlib
import io
import re
import shlex
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
TUTORIAL = ROOT / "docs" / "tutorial.md"

#: Command-line options whose value is a path the command writes.
OUTPUT_OPTIONS = ("--out", "--html", "--plot")

FENCE = re.compile(r"^```([^\n`]*)\n(.*?)^```\s*$", re.M | re.S)


@dataclass
class Block:
    kind: str  # "python", "sh", "text" or "other"
    code: str
    line: int  # line of the opening fence in the document
    output: str = ""  # what it printed (python, sh)
    expected: "Block | None" = None  # the text block showing its output
    exit_codes: list[int] = field(default_factory=list)


def blocks_of(text: str) -> list[Block]:
    found = []
    for match in FENCE.finditer(text):
        info = match.group(1).strip().split()
        kind = info[0] if info else ""
        if kind in ("python", "sh") and len(info) > 1:  # ```python no-run: shown only
            kind = "other"
        elif kind not in ("python", "sh", "text"):
            kind = "other"
        found.append(Block(kind, match.group(2), text.count("\n", 0, match.start()) + 1))
    last = None
    for block in found:
        if block.kind in ("python", "sh"):
            last = block
        elif block.kind == "text":
            assert last is not None and last.expected is None, \
                f"tutorial line {block.line}: a text block must follow a python or sh block"
            last.expected = block
    return found


def shows(expected: str, output: str) -> bool:
    """Whether ``output`` has the lines of ``expected`` (``...``: any lines)."""
    lines = [line.rstrip() for line in output.rstrip("\n").split("\n")]
    pattern = [line.rstrip() for line in expected.rstrip("\n").split("\n")]
    chunks: list[list[str]] = [[]]
    for line in pattern:
        if line.strip() == "...":
            chunks.append([])
        else:
            chunks[-1].append(line)
    anchored_start, anchored_end = bool(chunks[0]), bool(chunks[-1])
    chunks = [c for c in chunks if c]
    position = 0
    for k, chunk in enumerate(chunks):
        starts = [position] if (k == 0 and anchored_start) else range(position, len(lines) - len(chunk) + 1)
        for start in starts:
            if lines[start:start + len(chunk)] == chunk:
                position = start + len(chunk)
                break
        else:
            return False
    return position == len(lines) or not anchored_end


def command_lines(code: str) -> list[str]:
    """The ``acausal ...`` lines of an sh block that are run."""
    run = []
    for line in code.splitlines():
        command, _, comment = line.partition("#")
        if command.strip().startswith("acausal") and "not run" not in comment:
            run.append(command.strip())
    return run


def redirected(argv: list[str], work: Path) -> list[str]:
    """``argv`` with the paths the command writes moved under ``work``."""
    out = list(argv)
    for k, arg in enumerate(out[:-1]):
        if arg in OUTPUT_OPTIONS:
            out[k + 1] = str(work / out[k + 1])
    return out


@dataclass
class Run:
    blocks: list[Block]
    namespace: dict
    work: Path


@pytest.fixture(scope="module")
def tutorial(tmp_path_factory) -> Run:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from acausal.tools.cli import main

    work = tmp_path_factory.mktemp("tutorial")
    blocks = blocks_of(TUTORIAL.read_text(encoding="utf-8"))
    namespace: dict = {"__name__": "__main__"}
    with pytest.MonkeyPatch.context() as patch:
        # the references bundled with acausal, as the tutorial says
        patch.delenv("ACAUSAL_REFERENCE_DIR", raising=False)
        for block in blocks:
            if block.kind == "python":
                patch.chdir(work)
                printed = io.StringIO()
                with contextlib.redirect_stdout(printed), warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # what the blocks print is what is checked
                    try:
                        exec(compile(block.code, f"{TUTORIAL}:{block.line + 1}", "exec"), namespace)
                    except Exception as exc:
                        raise AssertionError(f"tutorial line {block.line}: the python block raised "
                                             f"{type(exc).__name__}: {exc}") from exc
                block.output = printed.getvalue()
            elif block.kind == "sh":
                patch.chdir(ROOT)
                printed = io.StringIO()
                for line in command_lines(block.code):
                    with contextlib.redirect_stdout(printed):
                        code = main(redirected(shlex.split(line)[1:], work))
                    block.exit_codes.append(code)
                    assert code == 0, f"tutorial line {block.line}: `{line}` exited with {code}"
                block.output = printed.getvalue()
    plt.close("all")
    return Run(blocks, namespace, work)


def test_the_document_has_the_sections_in_the_order_of_the_course():
    headings = re.findall(r"^## (.+)$", TUTORIAL.read_text(encoding="utf-8"), flags=re.M)
    words = ["Writing a component", "library parts", "parameters", "Simulating", "Changing parameters",
             "engine", "Modelica reference", "work-precision"]
    positions = [next(k for k, h in enumerate(headings) if word.lower() in h.lower()) for word in words]
    assert positions == sorted(positions), headings


def test_every_block_runs_and_every_command_exits_0(tutorial):
    python = [b for b in tutorial.blocks if b.kind == "python"]
    sh = [b for b in tutorial.blocks if b.kind == "sh"]
    assert len(python) >= 10 and len(sh) >= 5
    assert all(b.exit_codes and set(b.exit_codes) == {0} for b in sh)
    # the commands the tutorial promises are all among those run
    run = " | ".join(line for b in sh for line in command_lines(b.code))
    for command in ("acausal show library.rotational.Clutch", "acausal list library.rotational",
                    "acausal explain examples/friction.py", "acausal check", "acausal compare examples/friction.py",
                    "acausal bench"):
        assert command in run, command


def test_shown_outputs_are_what_the_blocks_print(tutorial):
    checked = 0
    for block in tutorial.blocks:
        if block.expected is not None:
            assert shows(block.expected.code, block.output), (
                f"tutorial line {block.expected.line}: the output shown is not what the block at line "
                f"{block.line} prints:\n{block.output}")
            checked += 1
    assert checked >= 10


def test_the_matcher():
    assert shows("a\nb", "a\nb\n")
    assert not shows("a", "a\nb")  # no trailing ...: the output ends there
    assert not shows("b", "a\nb")  # no leading ...: the output starts there
    assert shows("...\nb\n...", "a\nb\nc")
    assert shows("a\n...\nc", "a\nb\nc")
    assert not shows("a\nc", "a\nb\nc")


def test_breakaway_times_match_the_closed_form(tutorial):
    ns = tutorial.namespace
    result = ns["result"]
    r, j1, j2, t_b, t_c = 10.0, 1.0, 1.0, 5.0, 0.5 * 40.0
    t1 = t_b / r
    t2 = (t_b + (t_c - t_b) * (j1 + j2) / j2) / r
    assert (t1, t2) == (0.5, 3.5)
    assert ns["unlocks"](result, "bearing") == pytest.approx(t1, abs=1e-8)
    assert ns["unlocks"](result, "clutch") == pytest.approx(t2, abs=1e-8)
    # the motion in between: w = r (t - t1)^2 / (2 (J1 + J2)), then J2 at (T_c - T_b)/J2
    t = result.time
    together = (t > t1 + 1e-3) & (t < t2 - 1e-3)
    assert np.allclose(result["J1.w"][together], r * (t[together] - t1) ** 2 / (2 * (j1 + j2)), atol=1e-6)
    assert result.final("J2.w") == pytest.approx(22.5 + (t_c - t_b) / j2 * (5.0 - t2), abs=1e-6)
    assert result.final("J1.w") == pytest.approx(56.25, abs=1e-6)


def test_the_two_parameter_routes_give_identical_arrays(tutorial):
    ns = tutorial.namespace
    a, b = ns["weak_model"], ns["weak_run"]
    assert a.names == b.names
    assert np.array_equal(a.time, b.time)
    for name in a.names:
        assert np.array_equal(a[name], b[name]), name
    assert ns["unlocks"](b, "clutch") == pytest.approx((5.0 + 10.0 * 2) / 10.0, abs=1e-8)
    # a numeric parameter: no new translation (the result's notes would say so)
    assert b.notes == ()


def test_the_plot_was_written(tutorial):
    assert (tutorial.work / "breakaway.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_explain_wrote_the_page_and_the_text_says_what_the_tutorial_does(tutorial):
    ns = tutorial.namespace
    explanation = ns["explanation"]
    assert (tutorial.work / "out" / "breakaway" / "index.html").is_file()
    # one picture per distinct system the run visited: both stuck, bearing sliding, both sliding
    assert len(explanation.pictures) == 3
    assert all((tutorial.work / p).read_bytes()[:4] == b"\x89PNG" for p in explanation.pictures)
    # the state explained in detail is the first one visited
    assert ("named by its modes: bearing: Stuck (locked), clutch: Stuck (locked)."
            in " ".join(explanation.text.split()))
    assert "clutch.sa := J1.J*J1.a - motor.tau" in explanation.text
    assert "bearing.sa := -J2.J*J2.a - clutch.sa" in explanation.text
    assert (tutorial.work / "out" / "friction" / "index.html").is_file()  # acausal explain --html


def test_one_system_per_mode_as_described(tutorial):
    ns = tutorial.namespace
    translation, run = ns["translation"], ns["run"]
    system_of = ns["system_of"]
    visited = [system_of[d] for d in run.modes]
    assert len(visited) == 5
    # the same states in every mode
    assert {s.structure.states for s in visited} == {("J1.phi", "J1.w", "clutch.phi_rel", "clutch.w_rel")}
    loops = [[b for b in s.blt.blocks if b.size > 1] for s in visited]
    # both stuck and both sliding: explicit; bearing sliding with the clutch stuck: one loop with clutch.sa
    assert loops[0] == [] and loops[3] == [] and loops[4] == []
    for system, found in ((visited[1], loops[1]), (visited[2], loops[2])):
        (block,) = found
        assert "clutch.sa" in [system.structure.unknowns[j] for j in block.unknowns]
    # states 2 and 3, and 4 and 5, share a compiled system
    assert visited[2].shares == visited[1].key and visited[4].shares == visited[3].key
    assert visited[1].shares is None and visited[3].shares is None
    assert translation.flat.summary().startswith("Breakaway: 50 continuous")


def test_the_start_value_warning_names_the_open_states(tutorial):
    from acausal.errors import StartValueWarning

    caught = tutorial.namespace["caught"]
    assert [type(w.message) for w in caught] == [StartValueWarning]
    assert "J1.phi" in str(caught[0].message) and "clutch.phi_rel" in str(caught[0].message)


def test_the_unit_check_finds_the_forgotten_time(tutorial):
    ns = tutorial.namespace
    report = ns["check_model"](ns["Broken"]())
    assert report.ok and report.unit_findings == 1
    assert not ns["check_model"](ns["Broken"](), strict=True).ok
    assert ns["check_model"](ns["Breakaway"]()).unit_findings == 0
    # "the model still runs"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert ns["simulate"](ns["Broken"](), stop_time=1.0).success


def test_the_comparison_and_the_tube(tutorial):
    ns = tutorial.namespace
    comparison, reference = ns["comparison"], ns["reference"]
    assert comparison.passed
    y = np.asarray(reference.signals["inertia3.w"])
    span = reference.time[-1] - reference.time[0]
    assert (ns["dx"], ns["dy"]) == pytest.approx(
        (2e-3 * span, 2e-3 * max(y.max() - y.min(), abs(y.min()), 1e-3)))
    # the text: 3 s, and the speed from -5.8 to 102.5 rad/s
    assert span == pytest.approx(3.0)
    assert (round(y.min(), 1), round(y.max(), 1), round(y.max() - y.min(), 1)) == (-5.8, 102.5, 108.3)
    mode = ns["mode"]
    assert mode.discrete and mode.passed and not mode.unmatched_changes
    # a discrete signal: judged by its change times, each within dx of the reference's
    for t_ref, t_res in zip(mode.reference_changes, mode.result_changes):
        assert abs(t_ref - t_res) <= ns["dx"]


def test_the_bench_wrote_its_diagram_and_the_cheapest_run_is_found(tutorial):
    out = tutorial.work / "bench-out"
    for name in ("bench.md", "bench.csv", "work_precision.png"):
        assert (out / name).is_file(), name
    ns = tutorial.namespace
    accurate, cheapest = ns["accurate"], ns["cheapest"]
    assert set(ns["runs"]["method"]) == {"RK45", "Radau"}
    assert cheapest["error"] <= 1.0 and cheapest["sim_seconds"] == accurate["sim_seconds"].min()
    # the full run's diagram the page shows is in the repository
    assert (ROOT / "docs" / "bench" / "work_precision.png").is_file()


def test_links_resolve():
    text = TUTORIAL.read_text(encoding="utf-8")
    targets = re.findall(r"\]\(([^)#]+)\)", text)
    assert targets
    for target in targets:
        assert (TUTORIAL.parent / target).exists(), target
