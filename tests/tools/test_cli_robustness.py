"""The command line under the conditions scripts, schedulers and pipes create (issue 23).

* SIGTERM (``timeout``, systemd, SLURM, CI cancellation) stops a command as
  Ctrl-C does: ``simulate --out`` writes the rows computed up to then, status
  143 (130 for SIGINT); ``compare`` stops, 143; no traceback.
* ``--timeout`` and ``--max-steps`` on ``simulate`` and ``compare``: a run
  over budget keeps what it computed, status 1, and the message names the
  option that stopped it.
* Results (``simulate --out``, ``to_csv``, ``to_mat``, the page of ``explain
  --html``) are written whole or not at all: a failed write leaves the
  earlier file byte for byte (acausal.fileio.atomic_write).
* A model file that calls ``sys.exit()`` while imported is an error naming
  the file (status 2), not a silent status 0.
* ``read_csv``/``read_mat`` refuse a FIFO or a device at once and a file
  above their size cap, naming the file, its size and the cap.
* A reader of the output that has gone (``acausal list | head -1``) ends the
  command quietly with status 141, as SIGPIPE ends ``cat``.

Whatever could hang (a signal not handled, a FIFO read) runs in a subprocess
with a timeout of its own.
"""

from __future__ import annotations

import csv
import errno
import os
import signal
import stat
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from acausal.fileio import atomic_write, open_regular
from acausal.runtime import result as result_module
from acausal.runtime.result import MAX_CSV_BYTES, MAX_MAT_BYTES, SimulationResult, read_csv
from acausal.tools.cli import main

REPO = Path(__file__).resolve().parents[2]
FIRST = REPO / "examples" / "first.py"
TWO_MASSES = REPO / "examples" / "two_masses.py"

posix_only = pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals, FIFOs and pipes")

#: A run far longer than any test (about a minute per 1e5 s of model time), and a marker
#: file its right-hand side writes once the integration has passed t = 1000: rows exist then.
MARKED_RUN = """
    import os
    from pathlib import Path

    from sympy.utilities.lambdify import implemented_function

    from acausal import Eq, Experiment, Model, Variable, der, time


    def _mark(t):
        if t > 1000 and not os.path.exists("integrating"):
            Path("integrating").write_text("")
        return 0.0


    mark = implemented_function("mark", _mark)


    class Spin(Model):
        experiment = Experiment(stop_time=1e7, interval=100.0)
        x = Variable(start=1.0, fixed=True)
        v = Variable(start=0.0, fixed=True)

        def equations(self):
            return [Eq(der(self.x), self.v), Eq(der(self.v), -self.x + mark(time))]
    """

#: The same oscillator without the marker, for the budgets.
SPIN = """
    from acausal import Eq, Experiment, Model, Variable, der


    class Spin(Model):
        experiment = Experiment(stop_time=1e7, interval=100.0)
        x = Variable(start=1.0, fixed=True)
        v = Variable(start=0.0, fixed=True)

        def equations(self):
            return [Eq(der(self.x), self.v), Eq(der(self.v), -self.x)]
    """


def write_model(folder: Path, name: str, source: str) -> Path:
    path = folder / name
    path.write_text(textwrap.dedent(source))
    return path


def read_rows(path: Path) -> tuple[list[str], list[list[float]]]:
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return rows[0], [[float(v) for v in row] for row in rows[1:]]


def environment() -> dict[str, str]:
    env = dict(os.environ, MPLBACKEND="Agg", ACAUSAL_DISK_CACHE="off")
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def default_signals() -> None:
    """In the child: SIGINT and SIGTERM as a shell leaves them (a test runner may ignore them)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def no_traceback(err: str) -> None:
    assert "Traceback" not in err and "Exception ignored" not in err, err


@pytest.fixture
def in_tmp(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path


# ---------------------------------------------------------------------------
# 1. SIGTERM is Ctrl-C
# ---------------------------------------------------------------------------


@posix_only
@pytest.mark.parametrize("signum, status, word", [(signal.SIGTERM, 143, "SIGTERM"),
                                                  (signal.SIGINT, 130, "interrupted")],
                         ids=["SIGTERM", "SIGINT"])
def test_a_signal_during_the_run_keeps_the_rows(tmp_path, signum, status, word):
    write_model(tmp_path, "spin.py", MARKED_RUN)
    process = subprocess.Popen([sys.executable, "-m", "acausal", "simulate", "spin.py", "--out",
                                "spin.csv"], cwd=tmp_path, env=environment(), stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True, preexec_fn=default_signals)
    try:
        deadline = time.monotonic() + 60
        while not (tmp_path / "integrating").exists():
            assert process.poll() is None, process.communicate()
            assert time.monotonic() < deadline, "the run did not start integrating"
            time.sleep(0.02)
        process.send_signal(signum)
        out, err = process.communicate(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    assert process.returncode == status, err
    no_traceback(err)
    assert word in err and "spin.csv holds the result" in err, err
    assert "wrote spin.csv" in out
    header, rows = read_rows(tmp_path / "spin.csv")
    times = [row[0] for row in rows]
    assert header[:1] == ["time"] and times[0] == 0.0
    assert 900 <= times[-1] < 1e7 and times == sorted(times)  # the rows up to the signal, no more


COMPARE_TERMINATED = """
import os, signal, sys, time

import acausal.runtime.simulate as runtime
from acausal.tools.cli import main


def terminated(model, **options):
    os.kill(os.getpid(), signal.SIGTERM)  # as timeout(1) or a CI runner, while the run goes on
    time.sleep(30)
    raise AssertionError("SIGTERM did not stop the run")


runtime.simulate = terminated
sys.exit(main(["compare", sys.argv[1], sys.argv[2]]))
"""


@posix_only
def test_sigterm_stops_compare(tmp_path):
    done = subprocess.run([sys.executable, "-c", COMPARE_TERMINATED, str(FIRST), str(TWO_MASSES)],
                          cwd=tmp_path, env=environment(), capture_output=True, text=True, timeout=120,
                          preexec_fn=default_signals)
    assert done.returncode == 143, done.stderr  # before: killed by the signal (-15)
    no_traceback(done.stderr)
    assert "terminated (SIGTERM) while comparing" in done.stderr
    assert "1 not compared" in done.stdout  # the second model is not started


def test_the_sigterm_handler_lasts_as_long_as_the_command(in_tmp, monkeypatch):
    from acausal.tools import catalog

    seen = []
    monkeypatch.setattr(catalog, "main_list", lambda argv: seen.append(signal.getsignal(signal.SIGTERM)) or 0)
    before = signal.getsignal(signal.SIGTERM)
    assert main(["list", "acausal.library"]) == 0
    assert seen and seen[0] not in (signal.SIG_DFL, signal.SIG_IGN, before)
    assert signal.getsignal(signal.SIGTERM) == before


# ---------------------------------------------------------------------------
# 2. Budgets on the command line
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("budget", [["--max-steps", "50", "--stop-time", "1000", "--interval", "1"],
                                    ["--timeout", "1"]], ids=["max-steps", "timeout"])
def test_simulate_over_budget_writes_what_it_computed(in_tmp, capsys, budget):
    write_model(in_tmp, "spin.py", SPIN)
    assert main(["simulate", "spin.py", "--out", "spin.csv", *budget]) == 1
    err = capsys.readouterr().err
    assert f"error: {budget[0]} {budget[1]} stopped the simulation of Spin at t = " in err, err
    assert "spin.csv holds the result up to then" in err
    _, rows = read_rows(in_tmp / "spin.csv")
    stop = 1000 if budget[0] == "--max-steps" else 1e7
    assert len(rows) > 1 and rows[-1][0] < stop


def test_compare_over_budget_fails_naming_it(in_tmp, capsys):
    assert main(["compare", str(FIRST), "--max-steps", "5", "--timeout", "60"]) == 1
    err = capsys.readouterr().err
    assert "error: --max-steps 5 stopped the simulation of First" in err, err


@pytest.mark.parametrize("option, why", [("--max-steps=0", "must be at least 1"),
                                         ("--max-steps=2.5", "not a whole number"),
                                         ("--timeout=0", "must be a positive number"),
                                         ("--timeout=nan", "must be a positive number")])
def test_budgets_must_be_positive(in_tmp, capsys, option, why):
    assert main(["compare", str(FIRST), option]) == 2
    err = capsys.readouterr().err
    assert f"argument {option.split('=')[0]}" in err and why in err, err


# ---------------------------------------------------------------------------
# 3. Outputs are written whole or not at all
# ---------------------------------------------------------------------------


def no_temporary_files(folder: Path, *expected: str) -> None:
    assert sorted(p.name for p in folder.iterdir()) == sorted(expected)


def test_a_failed_write_keeps_the_earlier_out_file(in_tmp, capsys, monkeypatch):
    out = in_tmp / "first.csv"
    assert main(["simulate", str(FIRST), "--stop-time", "0.1", "--out", str(out)]) == 0
    good = out.read_bytes()
    real_atomic_write = result_module.atomic_write

    class DiskFull:
        """A file whose disk fills up after 300 characters (the header and a few rows)."""

        def __init__(self, handle):
            self._handle, self._left = handle, 300

        def write(self, text):
            if len(text) > self._left:
                self._handle.write(text[:self._left])
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            self._left -= len(text)
            return self._handle.write(text)

    def filling(path, write, *args, **kwargs):
        return real_atomic_write(path, lambda handle: write(DiskFull(handle)), *args, **kwargs)

    monkeypatch.setattr(result_module, "atomic_write", filling)
    capsys.readouterr()
    assert main(["simulate", str(FIRST), "--stop-time", "0.2", "--out", str(out)]) == 1
    assert out.read_bytes() == good  # before: the header and three rows
    no_temporary_files(in_tmp, "first.csv")
    err = capsys.readouterr().err
    assert f"cannot write {out}: No space left on device" in err and "as it was before" in err, err


def test_to_csv_with_a_value_that_cannot_be_written(tmp_path):
    path = tmp_path / "r.csv"
    path.write_text("time,x\n0.0,1.0\n")
    bad = SimulationResult(np.array([0.0, 1.0]), {"x": np.array(["1.5", "oops"], dtype=object)})
    with pytest.raises(ValueError):
        bad.to_csv(path)
    assert path.read_text() == "time,x\n0.0,1.0\n"  # before: the header alone
    no_temporary_files(tmp_path, "r.csv")


def test_to_mat_failing_keeps_the_earlier_file(tmp_path, monkeypatch):
    import scipy.io

    path = tmp_path / "dsres.mat"
    result = SimulationResult(np.array([0.0, 1.0]), {"x": np.array([1.0, 2.0])})
    result.to_mat(path)
    good = path.read_bytes()

    def disk_full(file, *args, **kwargs):
        handle = open(file, "wb") if isinstance(file, str) else file
        handle.write(b"MATLAB")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(scipy.io, "savemat", disk_full)
    with pytest.raises(OSError, match="No space"):
        result.to_mat(path)
    assert path.read_bytes() == good
    no_temporary_files(tmp_path, "dsres.mat")


def test_explain_html_keeps_the_earlier_page(in_tmp, capsys, monkeypatch):
    page = in_tmp / "page" / "index.html"
    page.parent.mkdir()
    page.write_text("<html>the earlier page</html>")

    def disk_full(fd):  # the data reaches the disk at fsync: that is where a full disk shows
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", disk_full)
    assert main(["explain", str(FIRST), "--html", "page"]) == 1
    assert "No space left on device" in capsys.readouterr().err
    assert page.read_text() == "<html>the earlier page</html>"  # before: the new page, never synced
    no_temporary_files(page.parent, "index.html")


def test_atomic_write_keeps_modes_links_and_fifos(tmp_path):
    new = atomic_write(tmp_path / "new.txt", lambda handle: handle.write("a"))
    umask = os.umask(0o022)
    os.umask(umask)
    assert stat.S_IMODE(new.stat().st_mode) == 0o666 & ~umask  # as open() makes it, not 0o600
    new.chmod(0o640)
    atomic_write(new, lambda handle: handle.write("b"))
    assert new.read_text() == "b" and stat.S_IMODE(new.stat().st_mode) == 0o640
    link = tmp_path / "link.txt"
    link.symlink_to(new)
    atomic_write(link, lambda handle: handle.write("c"))
    assert link.is_symlink() and new.read_text() == "c"
    if hasattr(os, "mkfifo"):  # a pipe (a shell's >(...)) cannot be replaced: written to
        fifo = tmp_path / "fifo"
        os.mkfifo(fifo)
        got = []
        reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()))
        reader.start()
        atomic_write(fifo, lambda handle: handle.write(b"through"), "wb")
        reader.join(10)
        assert got == [b"through"] and stat.S_ISFIFO(fifo.stat().st_mode)
    with pytest.raises(IsADirectoryError):
        atomic_write(tmp_path, lambda handle: pytest.fail("a directory was written to"))


def test_atomic_write_interrupted(tmp_path):
    path = tmp_path / "r.csv"
    path.write_text("earlier")

    def interrupted(handle):
        handle.write("half")
        raise KeyboardInterrupt  # Ctrl-C or SIGTERM in the middle of a write

    with pytest.raises(KeyboardInterrupt):
        atomic_write(path, interrupted)
    assert path.read_text() == "earlier"
    no_temporary_files(tmp_path, "r.csv")


# ---------------------------------------------------------------------------
# 4. A model file that calls sys.exit()
# ---------------------------------------------------------------------------


def test_sys_exit_while_imported(tmp_path):
    write_model(tmp_path, "exits.py", """
        import sys

        from acausal import Model


        class Nothing(Model):
            pass


        sys.exit(0)
        """)
    done = subprocess.run([sys.executable, "-m", "acausal", "simulate", "exits.py", "--out", "x.csv"],
                          cwd=tmp_path, env=environment(), capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr  # before: 0, and nothing written
    no_traceback(done.stderr)
    assert ("acausal simulate: error: exits.py called sys.exit(0) while being imported (line 11)"
            in done.stderr), done.stderr
    assert not (tmp_path / "x.csv").exists()


def test_sys_exit_in_build(in_tmp, capsys):
    write_model(in_tmp, "quits.py", """
        import sys

        from acausal import Model


        class Quits(Model):
            def build(self):
                sys.exit(3)
        """)
    assert main(["simulate", "quits.py"]) == 2  # before: SystemExit(3) out of main()
    assert "cannot translate Quits: SystemExit: 3 (quits.py:9, in build)" in capsys.readouterr().err


# ---------------------------------------------------------------------------
# 5. Reading result files: regular files below a cap, checked without blocking
# ---------------------------------------------------------------------------


READ_ODD_FILES = """
import sys, time

from acausal.runtime.result import read_csv, read_mat

for reader, path in ((read_csv, sys.argv[1]), (read_mat, sys.argv[1]), (read_csv, "/dev/zero"),
                     (read_csv, sys.argv[2]), (read_mat, sys.argv[3])):
    start = time.monotonic()
    try:
        reader(path)
        print("read", path)
    except OSError as exc:
        print(f"{time.monotonic() - start:.3f} {exc}")
"""


@posix_only
def test_fifos_devices_and_huge_files_are_refused_at_once(tmp_path):
    fifo = tmp_path / "result.csv"
    os.mkfifo(fifo)
    huge_csv, huge_mat = tmp_path / "huge.csv", tmp_path / "huge.mat"
    for path, cap in ((huge_csv, MAX_CSV_BYTES), (huge_mat, MAX_MAT_BYTES)):
        with open(path, "wb") as handle:
            handle.truncate(cap + 1)  # sparse: no disk space used
    done = subprocess.run([sys.executable, "-c", READ_ODD_FILES, str(fifo), str(huge_csv), str(huge_mat)],
                          env=environment(), capture_output=True, text=True, timeout=60)
    lines = done.stdout.splitlines()
    assert len(lines) == 5, done.stdout + done.stderr  # before: blocked on the FIFO, until the timeout
    for line in lines:
        assert float(line.split()[0]) < 1.0, line
    assert all(f"{fifo} is a FIFO (named pipe), not a regular file" in line for line in lines[:2])
    assert "/dev/zero is a character device" in lines[2]
    assert f"{huge_csv} is 512 MiB ({MAX_CSV_BYTES + 1} bytes), more than the 512 MiB" in lines[3]
    assert f"{huge_mat} is 2 GiB ({MAX_MAT_BYTES + 1} bytes), more than the 2 GiB" in lines[4]


def test_a_cap_of_ones_own(tmp_path):
    path = SimulationResult(np.linspace(0, 1, 50), {"x": np.ones(50)}).to_csv(tmp_path / "r.csv")
    size = path.stat().st_size
    assert 1024 < size < 2048
    with pytest.raises(OSError, match=rf"r.csv is 1.\d+ KiB \({size} bytes\), more than the 100 bytes "
                                      rf"this reader accepts; read_csv\(path, max_bytes=...\)") as info:
        read_csv(path, max_bytes=100)
    assert info.value.errno == errno.EFBIG
    assert len(read_csv(path, max_bytes=None).time) == 50


def test_a_file_that_grows_while_read(tmp_path):
    path = tmp_path / "growing.csv"
    path.write_bytes(b"x" * 50)
    with open_regular(path, 100) as handle:
        with open(path, "ab") as more:
            more.write(b"y" * 100)
        with pytest.raises(OSError, match="holds more than 100 bytes"):
            handle.read()


def test_a_directory_is_not_a_result(tmp_path):
    with pytest.raises(IsADirectoryError, match="is a directory"):
        read_csv(tmp_path)


# ---------------------------------------------------------------------------
# 6. A reader of the output that has gone
# ---------------------------------------------------------------------------


def run_into_a_closed_pipe(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    """The command with its standard output a pipe whose reader has gone (``| head -1`` done)."""
    read_end, write_end = os.pipe()
    os.close(read_end)
    try:
        return subprocess.run([sys.executable, "-m", "acausal", *args], cwd=cwd, env=environment(),
                              stdout=write_end, stderr=subprocess.PIPE, text=True, timeout=120)
    finally:
        os.close(write_end)


@posix_only
@pytest.mark.parametrize("command", [["list", "acausal.library"],
                                     ["simulate", str(FIRST), "--stop-time", "0.1", "--out", "x.csv"]],
                         ids=["list", "simulate"])
def test_a_closed_pipe_ends_quietly(tmp_path, command):
    done = run_into_a_closed_pipe(*command, cwd=tmp_path)
    assert done.returncode == 141, done.stderr  # before: 1, with a BrokenPipeError traceback
    assert done.stderr == ""
    if command[0] == "simulate":
        _, rows = read_rows(tmp_path / "x.csv")  # written before the summary is printed
        assert rows[-1][0] == pytest.approx(0.1)
