"""The README's and the docs' code runs in any folder, not only in the checkout (issue 24, items 5, 6).

A user copies a snippet into a Python session in a folder of their own,
with acausal installed (``pip install -e .`` of the README, or a wheel).
So every ```python snippet of ``README.md`` and ``docs/*.md`` runs here in a
fresh ``python -c`` process whose working folder is a new temporary folder
outside the checkout, with ``PYTHONPATH`` unset and no folder of the
checkout on ``sys.path`` (the process checks): ``from examples.x import y``
fails there, ``from acausal.examples.x import y`` works.

How a document runs (the rules the README and the docs follow):

- its ```python snippets run in document order in one namespace
  (``__name__`` is ``"__main__"``), as a reader working through the page in
  one session: a snippet may use what an earlier one defined;
- a fence with more than ``python`` in its info string (```python no-run)
  is shown, not run: that is how a snippet that cannot run as written (a
  placeholder such as ``sweep(model, grid, outputs)``, a Dask scheduler's
  address) is marked;
- the ``acausal`` lines of ```sh blocks run too, in the same folder and at
  their place (a later snippet may read what a command wrote), except a
  line whose comment says ``not run`` and a line naming a ``.py`` file that
  is not in the folder (``acausal explain examples/friction.py``: a file of
  the checkout; docs/tutorial.md's own test runs those from the checkout's
  root);
- a snippet that needs the shared MSL data and does not find it (the
  reference results, ``ACAUSAL_REFERENCE_DIR``: a ``ReferenceDataError``
  "no reference results for ..."; the MSL resources, ``MODELICAPATH``: a
  ``TableError`` 'cannot resolve "modelica://...') skips the document from
  there on, with the reason.

Also here: ``import acausal.components`` from the checkout's root (where the
checkout's ``acausal/`` folder is imported instead of the installed package),
``acausal bench`` writing outside the working folder, and the layout test
passing in a checkout that commands have left folders in.
"""

from __future__ import annotations

import dataclasses
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCUMENTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

#: A whole document (several simulations, the tutorial's ``explain`` and bench commands).
TIMEOUT = 900

FENCE = re.compile(r"^```([^\n`]*)\n(.*?)^```[ \t]*$", re.M | re.S)


@dataclasses.dataclass(frozen=True)
class Step:
    kind: str  # "python", or "command": an acausal line of an sh block
    where: str  # "docs/tutorial.md:153", the line of the opening fence
    code: str = ""
    argv: tuple[str, ...] = ()


def steps_of(path: Path) -> tuple[list[Step], list[str]]:
    """The steps a document runs, and the places of the snippets it shows only."""
    return steps_of_text(path.read_text(encoding="utf-8"), path.relative_to(ROOT).as_posix())


def steps_of_text(text: str, name: str) -> tuple[list[Step], list[str]]:
    """:func:`steps_of` for the text of the document ``name``."""
    steps, shown = [], []
    for match in FENCE.finditer(text):
        info = match.group(1).split()
        where = f"{name}:{text.count(chr(10), 0, match.start()) + 1}"
        if info[:1] == ["python"]:
            if len(info) == 1:
                steps.append(Step("python", where, code=match.group(2)))
            else:
                shown.append(where)
        elif info in (["sh"], ["bash"]):
            steps += [Step("command", where, argv=tuple(argv)) for argv in _command_lines(match.group(2))]
    return steps, shown


def _command_lines(code: str) -> list[list[str]]:
    """The ``acausal`` command lines of an sh block that run in a folder of the user's."""
    lines, pending = [], ""
    for line in code.splitlines():
        if line.rstrip().endswith("\\"):
            pending += line.rstrip()[:-1] + " "
            continue
        lines.append(pending + line)
        pending = ""
    found = []
    for line in lines:
        command, _, comment = line.partition("#")
        argv = shlex.split(command)
        if argv[:1] != ["acausal"] or "not run" in comment:
            continue
        if any(arg.split(":", 1)[0].endswith(".py") for arg in argv):
            continue  # a model file of the checkout: not in the user's folder
        found.append(argv[1:])
    return found


#: Runs the steps (JSON on stdin) in the working folder; prints "@@step WHERE" before each.
DRIVER = r'''
import json, os, subprocess, sys, traceback

job = json.load(sys.stdin)
root = os.path.realpath(job["root"])
prefixes = {os.path.realpath(p) for p in (sys.prefix, sys.base_prefix)}
for entry in sys.path:
    real = os.path.realpath(entry or os.curdir)
    inside = real == root or real.startswith(root + os.sep)
    installed = any(real == p or real.startswith(p + os.sep) for p in prefixes)  # a venv in the checkout
    if inside and not installed:
        print(f"@@checkout-on-path {entry!r}", flush=True)
        sys.exit(4)


def missing_shared_data(exc):
    """Why a snippet cannot run here: shared MSL data not found, or None."""
    try:
        from acausal.errors import ReferenceDataError, TableError
    except ImportError:
        return None
    text = str(exc)
    if isinstance(exc, ReferenceDataError) and text.startswith("no reference results for"):
        return "needs the MSL reference results (ACAUSAL_REFERENCE_DIR): " + text
    if isinstance(exc, TableError) and text.startswith('cannot resolve "modelica://'):
        return "needs the MSL resources (MODELICAPATH): " + text
    return None


namespace = {"__name__": "__main__"}
for step in job["steps"]:
    print(f"@@step {step['where']}", flush=True)
    if step["kind"] == "command":
        status = subprocess.run([sys.executable, "-m", "acausal", *step["argv"]]).returncode
        if status != 0:
            print(f"@@failed {step['where']}: acausal {' '.join(step['argv'])} exited {status}", flush=True)
            sys.exit(1)
        continue
    try:
        exec(compile(step["code"], step["where"], "exec"), namespace)
    except BaseException as exc:
        reason = missing_shared_data(exc)
        if reason:
            print(f"@@skip {step['where']}: {reason}", flush=True)
            sys.exit(3)
        traceback.print_exc()
        sys.stdout.flush()
        print(f"@@failed {step['where']}: {type(exc).__name__}: {exc}", flush=True)
        sys.exit(1)
print("@@done", flush=True)
'''


def _environment() -> dict[str, str]:
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)  # nothing of the checkout's on the path
    env["MPLBACKEND"] = "Agg"
    return env


RUNNABLE = [path for path in DOCUMENTS if any(s.kind == "python" for s in steps_of(path)[0])]


def test_the_documents_have_snippets_to_run_and_the_marks_are_read():
    readme, _ = steps_of(ROOT / "README.md")
    assert sum(s.kind == "python" for s in readme) >= 2
    assert ROOT / "docs" / "tutorial.md" in RUNNABLE
    text = "```python\nprint(1)\n```\n\n```python no-run\nsweep(model, grid)\n```\n\n" \
           "```sh\nacausal list blocks\nacausal show \\\n    blocks.Gain   # shown\n" \
           "acausal explain examples/first.py --out x\nacausal bench  # not run\npip install acausal\n```\n"
    steps, shown = steps_of_text(text, "docs/probe.md")
    assert [(s.kind, s.code, s.argv) for s in steps] == [
        ("python", "print(1)\n", ()), ("command", "", ("list", "blocks")), ("command", "", ("show", "blocks.Gain"))]
    assert shown == ["docs/probe.md:5"]


@pytest.mark.parametrize("document", RUNNABLE, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_the_snippets_run_in_a_folder_outside_the_checkout(document, tmp_path):
    assert not tmp_path.resolve().is_relative_to(ROOT.resolve())
    steps, _ = steps_of(document)
    job = {"root": str(ROOT), "steps": [dataclasses.asdict(s) for s in steps]}
    proc = subprocess.run([sys.executable, "-c", DRIVER], input=json.dumps(job), cwd=tmp_path,
                          env=_environment(), capture_output=True, text=True, timeout=TIMEOUT)
    out = proc.stdout
    details = f"exit {proc.returncode}\n--- stdout (last lines) ---\n{_tail(out)}\n--- stderr ---\n{_tail(proc.stderr)}"
    assert "@@checkout-on-path" not in out, details
    if proc.returncode == 3:
        pytest.skip(re.search(r"^@@skip (.*)$", out, re.M).group(1))
    failed = re.search(r"^@@failed (.*)$", out, re.M)
    assert proc.returncode == 0 and not failed, (
        f"{failed.group(1) if failed else 'the snippets did not finish'}\n{details}")
    ran = re.findall(r"^@@step (\S+)$", out, re.M)
    assert ran == [s.where for s in steps] and out.rstrip().endswith("@@done"), details


def _tail(text: str, lines: int = 60) -> str:
    return "\n".join(text.rstrip().splitlines()[-lines:])


# --------------------------------------------------------------------------
# import acausal.components from the checkout's root


#: Imports as a wheel-installed acausal, or none, would: without the editable install's finder.
WITHOUT_EDITABLE_FINDER = (
    "import sys\n"
    "sys.meta_path[:] = [f for f in sys.meta_path\n"
    "                    if not getattr(f, '__module__', '').startswith('__editable__')]\n")

IMPORTS = (
    "import acausal, acausal.components, acausal.components.rotational\n"
    "import acausal.library.rotational, acausal.examples.first\n"
    "from acausal.library.rotational import Flange_a\n"
    "assert acausal.components.rotational.Flange_a is Flange_a\n"
    "for module in (acausal, acausal.components, acausal.library, acausal.examples.first):\n"
    "    print(module.__file__)\n")


@pytest.mark.parametrize("install", ["as installed", "without the editable install's finder"])
def test_import_acausal_components_from_the_checkout_root(install):
    code = IMPORTS if install == "as installed" else WITHOUT_EDITABLE_FINDER + IMPORTS
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=_environment(), capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    files = [Path(line).resolve() for line in proc.stdout.split()]
    # the checkout's acausal/ folder is the package here (the working folder comes first on sys.path)
    assert files == [ROOT / "acausal" / "__init__.py", ROOT / "components" / "__init__.py",
                     ROOT / "library" / "__init__.py", ROOT / "examples" / "first.py"]


# --------------------------------------------------------------------------
# acausal bench writes outside the working folder


def test_bench_writes_into_the_users_cache_folder_and_says_so(tmp_path, monkeypatch, capsys):
    from acausal.tools import bench

    work, cache, home = tmp_path / "work", tmp_path / "cache", tmp_path / "home"
    for folder in (work, cache, home):
        folder.mkdir()
    monkeypatch.chdir(work)
    monkeypatch.setenv("XDG_CACHE_HOME", str(cache))
    monkeypatch.setenv("LOCALAPPDATA", str(cache))
    monkeypatch.setenv("HOME", str(home))
    out = bench.default_out()
    assert out.is_relative_to(tmp_path) and not out.is_relative_to(work)
    assert bench.main(["--only", "soak", "--soak-runs", "2"]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["soak.csv", "soak.md", "soak.png"]
    assert list(work.iterdir()) == [], "acausal bench wrote into the working folder"
    printed = capsys.readouterr().out
    assert f"writing into {out}" in printed and f"wrote {out / 'soak.md'}" in printed


# --------------------------------------------------------------------------
# the README's test command passes in a checkout that has been used


def _git(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run(["git", *args], cwd=cwd, capture_output=True, text=True, timeout=300)


def test_the_layout_test_ignores_what_commands_leave_in_a_checkout(tmp_path):
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("needs git and a git checkout")
    clone = tmp_path / "clone"
    cloned = _git("clone", "--quiet", "--depth", "1", ROOT.as_uri(), str(clone), cwd=tmp_path)
    assert cloned.returncode == 0, cloned.stderr
    # this checkout's architecture test, in a copy of the committed repository
    shutil.copy(ROOT / "tests" / "test_architecture.py", clone / "tests" / "test_architecture.py")
    (clone / "bench-out").mkdir()  # ignored (.gitignore)
    (clone / "bench-out" / "bench.csv").write_text("case\n")
    (clone / "plots").mkdir()  # neither tracked nor ignored: acausal compare --plot plots/
    (clone / "plots" / "First.png").write_bytes(b"")

    def layout_test() -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                               "tests/test_architecture.py", "-k", "readme_layout"],
                              cwd=clone, env=_environment(), capture_output=True, text=True, timeout=300)

    used = layout_test()
    assert used.returncode == 0, used.stdout + used.stderr
    # and it still reads the layout: the README without its examples/ row fails
    readme = clone / "README.md"
    rows = readme.read_text(encoding="utf-8").splitlines(keepends=True)
    readme.write_text("".join(r for r in rows if not r.startswith("| `examples/`")), encoding="utf-8")
    missing = layout_test()
    assert missing.returncode != 0 and "examples" in missing.stdout, missing.stdout
