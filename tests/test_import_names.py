"""The model libraries live inside the acausal package, not under generic top-level names.

``components/`` and ``library/`` of the repository install as
``acausal.components`` and ``acausal.library``.  A user whose working folder
has packages of their own called ``components`` or ``library`` must still be
able to run the README's worked example (``examples/flywheel.py``) there, both
as a script and through the command line, and acausal must not pick up the
user's packages.

The user's packages here define names that look like the library's
(``library.rotational.Inertia = None``) and leave a marker file when they are
imported, so that an accidental import shows even when it does not break.
"""

from __future__ import annotations

import csv
import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[1]
FLYWHEEL = REPO_ROOT / "examples" / "flywheel.py"

#: The flywheel's numbers (examples/flywheel.py): constant torque T, drag k, inertia J.
T, K, J = 2.0, 0.02, 0.5
TERMINAL_SPEED = math.sqrt(T / K)  # 10 rad/s

TIMEOUT = 300


def _user_package(folder: Path, name: str, modules: dict[str, str]) -> None:
    """A package ``name`` of the user's own that leaves ``<name>_was_imported`` behind when imported."""
    package = folder / name
    package.mkdir()
    (package / "__init__.py").write_text(
        f'"""The user\'s own {name} package: nothing to do with acausal."""\n'
        "from pathlib import Path\n\n"
        f"(Path(__file__).resolve().parents[1] / {name + '_was_imported'!r}).touch()\n\n"
        "SHOPPING_LIST = ['bread', 'milk']\n\n\n"
        "def greet():\n"
        "    return 'hello'\n",
        encoding="utf-8")
    for module, text in modules.items():
        (package / f"{module}.py").write_text(text, encoding="utf-8")


@pytest.fixture
def user_folder(tmp_path: Path) -> Path:
    """A working folder with the user's own ``components`` and ``library`` and a copy of the flywheel."""
    _user_package(tmp_path, "library", {"rotational": "Inertia = None\nConstantTorque = None\n"})
    _user_package(tmp_path, "components", {"rotational": "Flange_a = None\n"})
    shutil.copy(FLYWHEEL, tmp_path / "flywheel.py")
    return tmp_path


def _run(args: list[str], cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, *args], cwd=cwd, capture_output=True, text=True,
                          timeout=TIMEOUT)


def _details(proc: subprocess.CompletedProcess) -> str:
    return f"exit {proc.returncode}\n--- stdout ---\n{proc.stdout}\n--- stderr ---\n{proc.stderr}"


def _assert_user_packages_untouched(folder: Path) -> None:
    imported = sorted(p.name for p in folder.glob("*_was_imported"))
    assert not imported, f"the user's own packages were imported: {imported}"


def test_flywheel_script_runs_beside_user_packages(user_folder: Path):
    proc = _run(["flywheel.py"], user_folder)
    assert proc.returncode == 0, _details(proc)
    # the script prints "flywheel.w(20) = 9.999998 rad/s, terminal speed 10.000000; ..."
    match = re.search(r"flywheel\.w\(20\) = ([-+0-9.eE]+) rad/s", proc.stdout)
    assert match, f"the flywheel's final speed is not in its output\n{_details(proc)}"
    w_final = float(match.group(1))
    assert abs(w_final - TERMINAL_SPEED) < 1e-4, (
        f"flywheel.w(20) = {w_final}, expected sqrt(T/k) = {TERMINAL_SPEED} within 1e-4")
    _assert_user_packages_untouched(user_folder)


def test_flywheel_command_line_beside_user_packages(user_folder: Path):
    proc = _run(["-m", "acausal", "simulate", "flywheel.py", "--stop-time", "2", "--out", "out.csv"],
                user_folder)
    assert proc.returncode == 0, _details(proc)
    out = user_folder / "out.csv"
    assert out.is_file(), f"out.csv was not written\n{_details(proc)}"
    with out.open(newline="") as f:
        rows = list(csv.DictReader(f))
    assert rows and float(rows[-1]["time"]) == pytest.approx(2.0)
    exact = TERMINAL_SPEED * math.tanh(2.0 * math.sqrt(T * K) / J)
    assert float(rows[-1]["flywheel.w"]) == pytest.approx(exact, abs=1e-4)
    _assert_user_packages_untouched(user_folder)


def test_acausal_library_does_not_import_user_library(user_folder: Path):
    code = ("import sys\n"
            "import acausal.library.rotational as rot\n"
            "assert rot.Inertia is not None, 'acausal.library.rotational.Inertia is the user\\'s None'\n"
            "leaked = sorted(m for m in sys.modules if m.split('.')[0] in ('library', 'components'))\n"
            "assert not leaked, f'user packages imported: {leaked}'\n"
            "print(rot.__file__)\n")
    proc = _run(["-c", code], user_folder)
    assert proc.returncode == 0, _details(proc)
    assert Path(proc.stdout.strip()).resolve().is_relative_to(REPO_ROOT / "library"), proc.stdout
    _assert_user_packages_untouched(user_folder)
