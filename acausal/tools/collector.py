"""The garbage collector's settings in a short command process.

Shared by the command line (:mod:`acausal.tools.cli`) and the benchmarks
(:mod:`acausal.tools.bench`), which time commands as the command line runs
them.
"""

from __future__ import annotations

__all__ = ["GC_THRESHOLD"]

#: The collector's thresholds in a command; the default is (700, 10, 10).  A
#: command's sympy expressions and compiled systems live until it ends, so
#: the cyclic collector finds little to free and runs less often here.
GC_THRESHOLD = (100_000, 50, 100)
