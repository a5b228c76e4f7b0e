"""What a run loads: an explicit method needs neither scipy nor pandas nor matplotlib (issue 29).

Each check runs in a new interpreter, since this test process has long imported them.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _loaded_after(code: str) -> set[str]:
    script = f"import sys\n{code}\nprint(' '.join(sorted({{m.split('.')[0] for m in sys.modules}})))"
    done = subprocess.run([sys.executable, "-c", script], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return set(done.stdout.split())


def test_importing_acausal_loads_no_scipy_pandas_or_matplotlib():
    loaded = _loaded_after("import acausal")
    assert not loaded & {"scipy", "pandas", "matplotlib"}


@pytest.mark.parametrize("method", ["RK45", "DOP853", "Euler"])
def test_a_run_with_an_explicit_method_loads_no_scipy(method):
    loaded = _loaded_after(
        "import acausal\n"
        "sys.path.insert(0, '.')\n"
        "from examples.first import First\n"
        f"result = acausal.simulate(First(), method={method!r})\n"
        "assert result.success, result.message")
    assert not loaded & {"scipy", "pandas", "matplotlib"}


def test_an_implicit_method_loads_scipy_when_asked():
    loaded = _loaded_after(
        "import acausal\n"
        "sys.path.insert(0, '.')\n"
        "from examples.first import First\n"
        "assert acausal.simulate(First(), method='BDF').success")
    assert "scipy" in loaded
