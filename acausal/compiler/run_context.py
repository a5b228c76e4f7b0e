"""The run in progress, as generated code sees it: the history its delayed values read.

Generated code evaluates ``delay(u, T)`` by asking the history of the run in
progress (:mod:`acausal.compiler.delays`); the runtime says which history that
is (``with activate(history):``).  This module is that meeting point and
imports nothing but the errors, so that the runtime and a saved run can use
it without loading the compiler (see :mod:`acausal.runtime.contract`);
:func:`delayed_value` is what generated code calls for a delayed value.
"""

from __future__ import annotations

import threading

from ..errors import SolverError

__all__ = ["activate", "active_history", "delayed_value"]

_ACTIVE = threading.local()


def active_history():
    """The history the delayed values of this thread read (None: no run in progress)."""
    return getattr(_ACTIVE, "history", None)


class activate:  # noqa: N801 - a context manager used like a function
    """``with activate(history):`` the generated code of this thread reads ``history``."""

    def __init__(self, history) -> None:
        self.history = history

    def __enter__(self):
        self.previous = active_history()
        _ACTIVE.history = self.history
        return self.history

    def __exit__(self, *exc) -> None:
        _ACTIVE.history = self.previous


def delayed_value(k, t, delay_time, delay_max):
    """What generated code calls for ``delay(u, T, Tmax)`` number ``k`` at time ``t``: the
    value of the run in progress's history (:class:`~acausal.compiler.delays.DelayedValue`)."""
    history = active_history()
    if history is None:
        raise SolverError("delay(): a delayed value was asked for outside a simulation run",
                          hint="delayed values come from the recorded solution of a run: simulate the model")
    return history.value(int(k), t, delay_time, delay_max)
