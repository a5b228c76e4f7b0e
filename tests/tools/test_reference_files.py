"""Reference files that are not what they should be give a ReferenceDataError, never a crash or a hang.

``load_reference`` reads a CSV (or .csv.gz), ``comparisonSignals.txt`` and
``creation.txt``.  Each must be a regular file (a symbolic link to one is
fine) below a size cap, of UTF-8 text (a BOM allowed); anything else -- UTF-16,
binary content, an over-long line, a FIFO, ``/dev/zero`` -- is reported as a
ReferenceDataError (a ValueError) naming the file, and the line where there
is one, with a hint.  Cases that could hang or exhaust memory run in a
subprocess with a timeout.  The CSV's time column must also run from
creation.txt's StartTime to its StopTime.
"""

from __future__ import annotations

import gzip
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from acausal.errors import ReferenceDataError
from acausal.tools import compare
from acausal.tools.compare import bundled_reference_dir, load_reference

REPO = Path(__file__).resolve().parents[2]
SHARED = Path("/work/shared/reference/msl-4.1.0")

GOOD_CSV = '"time","a.x","a.v"\n0,0,1\n0.5,0.5,1\n0.5,0.5,2\n1,1.5,2\n'
SIGNALS = "time\na.x\na.v\n"
CREATION = "StartTime=0\nStopTime=1 // from model\nInterval=0.5\n"


def write_folder(root: Path, csv_data: bytes | str | None = GOOD_CSV, *, name: str = "Model.csv",
                 signals: bytes | str | None = SIGNALS, creation: bytes | str | None = CREATION) -> Path:
    """A reference folder of class Pkg.Model below ``root``; None leaves a file out."""
    folder = root / "Pkg.Model"
    folder.mkdir(parents=True)
    for file_name, data in ((name, csv_data), ("comparisonSignals.txt", signals),
                            ("creation.txt", creation)):
        if data is not None:
            (folder / file_name).write_bytes(data.encode() if isinstance(data, str) else data)
    return folder


def load_error(root: Path, *words: str) -> str:
    """The ReferenceDataError of loading Pkg.Model from ``root``, checked for words and a hint."""
    with pytest.raises(ReferenceDataError) as error:
        load_reference("Pkg.Model", root)
    message = str(error.value)
    assert isinstance(error.value, ValueError)
    assert error.value.hint, message
    for word in words:
        assert word in message, f"{word!r} not in {message!r}"
    return message


def load_in_subprocess(roots: list[Path], timeout: float = 60) -> list[str]:
    """Load Pkg.Model from each root in a fresh process (which a hang or a memory blow-up
    cannot take down with the test run); the ReferenceDataError message of each."""
    code = textwrap.dedent(f"""
        import resource, sys
        resource.setrlimit(resource.RLIMIT_AS, (2 * 2**30, 2 * 2**30))  # a blow-up fails fast
        from acausal.errors import ReferenceDataError
        from acausal.tools.compare import load_reference
        for root in {[str(root) for root in roots]!r}:
            try:
                load_reference("Pkg.Model", root)
            except ReferenceDataError as error:
                print(" ".join(str(error).split()))
            else:
                print("loaded")
        """)
    env = dict(os.environ)
    env["PYTHONPATH"] = str(REPO) + os.pathsep + env.get("PYTHONPATH", "")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=timeout, env=env)
    assert done.returncode == 0, done.stdout + done.stderr
    messages = done.stdout.splitlines()
    assert len(messages) == len(roots), done.stdout
    return messages


# ---------------------------------------------------------------------------
# Encodings and binary content
# ---------------------------------------------------------------------------


def test_utf8_bom_is_allowed(tmp_path):
    bom = b"\xef\xbb\xbf"
    write_folder(tmp_path, bom + GOOD_CSV.encode(), signals=bom + SIGNALS.encode(),
                 creation=bom + CREATION.encode())
    ref = load_reference("Pkg.Model", tmp_path)
    assert ref.compared == ("a.x", "a.v")
    np.testing.assert_array_equal(ref.time, [0, 0.5, 0.5, 1])


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-le", "utf-16-be"])
def test_utf16_csv(tmp_path, encoding):
    write_folder(tmp_path, GOOD_CSV.encode(encoding))
    message = load_error(tmp_path, "Model.csv")
    assert "UTF-16" in message


@pytest.mark.parametrize("file_name", ["comparisonSignals.txt", "creation.txt"])
def test_utf16_text_files(tmp_path, file_name):
    text = {"comparisonSignals.txt": SIGNALS, "creation.txt": CREATION}[file_name]
    key = {"comparisonSignals.txt": "signals", "creation.txt": "creation"}[file_name]
    write_folder(tmp_path, **{key: text.encode("utf-16")})
    load_error(tmp_path, file_name, "UTF-16")


def test_binary_csv(tmp_path):
    png = b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\x00\x00\x01\x00"
    write_folder(tmp_path, png)
    load_error(tmp_path, "Model.csv", "line 1", "not UTF-8")


def test_latin1_byte_names_its_line(tmp_path):
    write_folder(tmp_path, GOOD_CSV.replace("0.5,0.5,2", "0.5,0.5,2 \xb0").encode("latin-1"))
    load_error(tmp_path, "Model.csv", "line 4", "not UTF-8")


def test_nul_byte_names_its_line(tmp_path):
    write_folder(tmp_path, GOOD_CSV.replace("0.5,0.5,1", "0.5,0.5\x00,1").encode())
    load_error(tmp_path, "Model.csv", "line 3", "NUL")


def test_binary_gz_content(tmp_path):
    folder = write_folder(tmp_path, gzip.compress(bytes(range(256)) * 4), name="Model.csv.gz")
    assert not (folder / "Model.csv").exists()
    load_error(tmp_path, "Model.csv.gz", "line 1")


@pytest.mark.parametrize("file_name", ["comparisonSignals.txt", "creation.txt"])
def test_binary_text_files(tmp_path, file_name):
    key = {"comparisonSignals.txt": "signals", "creation.txt": "creation"}[file_name]
    write_folder(tmp_path, **{key: b"time\na.x\n\xff\xfe\xfd\n"})
    load_error(tmp_path, file_name, "line 3", "not UTF-8")


def test_corrupt_gz(tmp_path):
    packed = bytearray(gzip.compress(GOOD_CSV.encode() * 50))
    packed[20:30] = b"\xff" * 10  # damage the deflate stream
    write_folder(tmp_path, bytes(packed), name="Model.csv.gz")
    load_error(tmp_path, "Model.csv.gz")


# ---------------------------------------------------------------------------
# Long lines and large files
# ---------------------------------------------------------------------------


def test_field_longer_than_the_csv_limit(tmp_path):
    """A value of 140 000 characters (csv's field limit is 131 072): not a raw _csv.Error."""
    write_folder(tmp_path, GOOD_CSV.replace("0.5,0.5,1", "0.5," + "1" * 140_000 + ",1"))
    load_error(tmp_path, "Model.csv", "line 3")


def test_line_longer_than_the_cap(tmp_path):
    """A line longer than the line cap (1 MiB) of short fields: refused with its line number."""
    row = ",".join(["0.5"] * 300_000)
    write_folder(tmp_path, '"time","a.x","a.v"\n0,0,1\n' + row + "\n1,1.5,2\n")
    load_error(tmp_path, "Model.csv", "line 3", "longer than")


def test_one_huge_line_in_a_small_gz(tmp_path):
    """A compressed file that decompresses to one enormous line stops at the line cap."""
    write_folder(tmp_path, gzip.compress(b"1" * (64 * 2**20)), name="Model.csv.gz")
    load_error(tmp_path, "Model.csv.gz", "line 1", "longer than")


def test_csv_over_the_size_cap(tmp_path, monkeypatch):
    monkeypatch.setattr(compare, "_MAX_CSV_BYTES", 40)
    write_folder(tmp_path, GOOD_CSV + "# padding\n" * 10)
    load_error(tmp_path, "Model.csv", "at most 40 bytes")


def test_gz_decompressed_size_is_capped(tmp_path, monkeypatch):
    """The cap counts the decompressed bytes: a small .gz that inflates past it is refused."""
    monkeypatch.setattr(compare, "_MAX_CSV_BYTES", 5_000)
    rows = "".join(f"{t / 1000!r},0,0\n" for t in range(1001))
    packed = gzip.compress(('"time","a.x","a.v"\n' + rows).encode())
    assert len(packed) < 5_000 < len(rows)
    write_folder(tmp_path, packed, name="Model.csv.gz")
    load_error(tmp_path, "Model.csv.gz", "decompressed")


@pytest.mark.parametrize("file_name", ["comparisonSignals.txt", "creation.txt"])
def test_text_file_over_the_size_cap(tmp_path, file_name):
    key = {"comparisonSignals.txt": "signals", "creation.txt": "creation"}[file_name]
    text = {"comparisonSignals.txt": SIGNALS, "creation.txt": CREATION}[file_name]
    write_folder(tmp_path, **{key: text + "// padding\n" * 200_000})  # 2.2 MB
    load_error(tmp_path, file_name, "MiB")


# ---------------------------------------------------------------------------
# Not regular files (these could hang or exhaust memory: run in a subprocess)
# ---------------------------------------------------------------------------


needs_posix = pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs and /dev/zero")


KEYS = {"Model.csv": "csv_data", "Model.csv.gz": "csv_data", "comparisonSignals.txt": "signals",
        "creation.txt": "creation"}


@needs_posix
def test_fifo_does_not_hang(tmp_path):
    names = ["Model.csv", "comparisonSignals.txt", "creation.txt"]
    for name in names:
        folder = write_folder(tmp_path / name, **{KEYS[name]: None})
        os.mkfifo(folder / name)
    messages = load_in_subprocess([tmp_path / name for name in names])
    for name, message in zip(names, messages):
        assert name in message and "FIFO" in message and "hint:" in message, message


@needs_posix
def test_symlink_to_dev_zero(tmp_path):
    names = ["Model.csv", "Model.csv.gz", "comparisonSignals.txt", "creation.txt"]
    for name in names:
        folder = write_folder(tmp_path / name, **{KEYS[name]: None})
        os.symlink("/dev/zero", folder / name)
    messages = load_in_subprocess([tmp_path / name for name in names])
    for name, message in zip(names, messages):
        assert name in message and "/dev/zero" in message and "not a regular file" in message, message


def test_directory_instead_of_a_file(tmp_path):
    folder = write_folder(tmp_path, signals=None)
    (folder / "comparisonSignals.txt").mkdir()
    load_error(tmp_path, "comparisonSignals.txt", "a directory")


def test_symlink_to_a_regular_file_is_fine(tmp_path):
    elsewhere = tmp_path / "data"
    elsewhere.mkdir()
    (elsewhere / "Model.csv").write_text(GOOD_CSV)
    folder = write_folder(tmp_path / "refs", None)
    (folder / "Model.csv").symlink_to(elsewhere / "Model.csv")
    ref = load_reference("Pkg.Model", tmp_path / "refs")
    np.testing.assert_array_equal(ref.signals["a.v"], [1, 1, 2, 2])


# ---------------------------------------------------------------------------
# Other layouts that still load
# ---------------------------------------------------------------------------


def test_carriage_return_line_ends_still_load(tmp_path):
    write_folder(tmp_path, GOOD_CSV.replace("\n", "\r"))
    np.testing.assert_array_equal(load_reference("Pkg.Model", tmp_path).time, [0, 0.5, 0.5, 1])
    for other in ("crlf", "lf-only"):
        root = tmp_path / other
        write_folder(root, GOOD_CSV.replace("\n", "\r\n") if other == "crlf" else GOOD_CSV)
        np.testing.assert_array_equal(load_reference("Pkg.Model", root).time, [0, 0.5, 0.5, 1])


def test_time_column_spelled_Time(tmp_path):
    """Newer Dymola versions write "Time" (MAP-LIB's Rotational.Examples.EddyCurrentBrake)."""
    write_folder(tmp_path, GOOD_CSV.replace('"time"', '"Time"'))
    ref = load_reference("Pkg.Model", tmp_path)
    np.testing.assert_array_equal(ref.time, [0, 0.5, 0.5, 1])
    assert set(ref.signals) == {"a.x", "a.v"}


# ---------------------------------------------------------------------------
# StartTime and StopTime against the time column
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("csv_text, words", [
    (GOOD_CSV.replace("1,1.5,2\n", ""), ["0.5", "1.0"]),                        # truncated
    (GOOD_CSV.replace("0,0,1\n", ""), ["0.5", "StartTime = 0.0"]),              # starts late
    (GOOD_CSV.replace("1,1.5,2", "2,1.5,2"), ["2.0", "StopTime = 1.0"]),        # another run
    (GOOD_CSV.replace("1,1.5,2", "1.00001,1.5,2"), ["1.00001"]),                # 1e-5 off
], ids=["truncated", "starts-late", "another-run", "1e-5-off"])
def test_time_column_must_match_creation(tmp_path, csv_text, words):
    write_folder(tmp_path, csv_text)
    message = load_error(tmp_path, "Model.csv", "creation.txt", "StartTime", "StopTime", *words)
    assert "time column runs from" in message


def test_time_within_the_tolerance_passes(tmp_path):
    """Within 1e-6 of the span: a stop time printed with 7 significant digits still matches."""
    write_folder(tmp_path, GOOD_CSV.replace("1,1.5,2", "0.9999996,1.5,2"))
    assert load_reference("Pkg.Model", tmp_path).stop_time == 1.0


def test_tolerance_is_relative(tmp_path):
    csv_text = '"time","a.x","a.v"\n1000,0,1\n1500,1,1\n2000.0005,1,2\n'
    write_folder(tmp_path / "ok", csv_text, creation="StartTime=1000\nStopTime=2000\n")
    assert load_reference("Pkg.Model", tmp_path / "ok").time[-1] == 2000.0005
    write_folder(tmp_path / "off", csv_text.replace("2000.0005", "2000.01"),
                 creation="StartTime=1000\nStopTime=2000\n")
    load_error(tmp_path / "off", "2000.01", "StopTime = 2000.0")


@pytest.mark.parametrize("creation, words", [
    ("StartTime=1\nStopTime=1\n", ["creation.txt", "not after StartTime"]),
    ("StartTime=0\nStopTime=nan\n", ["creation.txt", "line 2", "not a finite number"]),
    ("StartTime=-inf\nStopTime=1\n", ["creation.txt", "line 1", "not a finite number"]),
], ids=["empty-span", "nan", "inf"])
def test_creation_times_must_make_sense(tmp_path, creation, words):
    write_folder(tmp_path, creation=creation)
    load_error(tmp_path, *words)


@pytest.mark.parametrize("root", [
    bundled_reference_dir(),
    pytest.param(SHARED, marks=pytest.mark.skipif(not SHARED.is_dir(), reason=f"{SHARED} is absent")),
], ids=["bundled", "shared"])
def test_every_known_reference_passes_the_checks(root):
    """The five bundled references and the team's full copy load, times matching creation.txt."""
    classes = sorted(p.name for p in root.iterdir() if p.is_dir())
    assert len(classes) >= 5
    for modelica_class in classes:
        ref = load_reference(modelica_class, root)
        assert ref.time[0] == ref.start_time and ref.time[-1] == ref.stop_time, modelica_class
