"""Reading a reference result holds its numbers, not its text (issue 23, item 7).

A 64 KiB ``.csv.gz`` of short cells ("0,0,0,...") decompresses to some 36 MB
and used to take the process to 1.16 GiB: every cell was kept as a Python
string in a list of rows (32 times the decompressed size).  The reader now
converts the lines to numbers block by block and keeps them per column.
The peak is measured in a fresh process (``ru_maxrss``), against the same
process's size before reading.
"""

from __future__ import annotations

import gzip
import json
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _write_reference(folder: Path, rows: int, columns: int) -> int:
    """A reference of one-character cells; returns its decompressed size in bytes."""
    names = ["time"] + [f"x{k}" for k in range(1, columns)]
    line = ",".join(["0"] * (columns - 1))
    text = ",".join(f'"{n}"' for n in names) + "\n" + "".join(f"{i},{line}\n" for i in range(rows))
    folder.mkdir(parents=True)
    (folder / "Big.csv.gz").write_bytes(gzip.compress(text.encode(), mtime=0))
    (folder / "comparisonSignals.txt").write_text("time\nx1\n")
    (folder / "creation.txt").write_text(f"StartTime=0\nStopTime={rows - 1}\n")
    return len(text.encode())


def test_a_compressed_reference_of_short_cells_stays_within_four_times_its_text(tmp_path):
    size = _write_reference(tmp_path / "Pkg.Big", rows=60_000, columns=300)
    assert (tmp_path / "Pkg.Big" / "Big.csv.gz").stat().st_size < 2**20  # a small file to download
    script = textwrap.dedent(f"""
        import json, resource, sys
        sys.path.insert(0, {str(ROOT)!r})
        import numpy as np
        from acausal.tools.compare import load_reference
        before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        reference = load_reference("Pkg.Big", {str(tmp_path)!r})
        after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
        print(json.dumps({{"before": before * 1024, "after": after * 1024,
                          "rows": len(reference.time), "columns": len(reference.signals)}}))
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    found = json.loads(done.stdout.strip().splitlines()[-1])
    assert found["rows"] == 60_000 and found["columns"] == 299
    numbers = 8 * 60_000 * 300            # what the values take as float64: 4x the text here
    grown = found["after"] - found["before"]
    assert grown <= 4 * size + 64 * 2**20, (grown / 2**20, size / 2**20)
    assert grown <= 1.6 * numbers + 64 * 2**20, (grown / 2**20, numbers / 2**20)
