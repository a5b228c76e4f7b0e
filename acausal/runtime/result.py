"""The simulation result: every variable by dotted name, events, status."""

from __future__ import annotations

import csv
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

import numpy as np

from ..errors import SimulationError, SimulationInterrupted

__all__ = ["Event", "SimulationResult"]


@dataclass(frozen=True)
class Event:
    """One event instant.

    Attributes
    ----------
    time : float
    kind : str
        ``'initial'`` (the event iteration after initialization), ``'time'``
        (time relations and sample clocks), ``'state'`` or ``'terminal'``.
    relations : tuple of str
        The relations whose crossing fired it (state events), or the time
        relations reached (time events).
    changes : tuple of (str, old, new)
        Discrete variables that changed, with their values before and after,
        then the states a ``reinit`` set (``reinit(v)``).
    iterations : int
        Passes of the event iteration.
    """

    time: float
    kind: str
    relations: tuple[str, ...]
    changes: tuple[tuple[str, object, object], ...]
    iterations: int = 1

    def __str__(self) -> str:
        changed = ", ".join(f"{n}: {a}->{b}" for n, a, b in self.changes) or "no discrete change"
        why = f" ({'; '.join(self.relations)})" if self.relations else ""
        return f"t={self.time:.9g} {self.kind}{why}: {changed}"


@dataclass(frozen=True)
class SimulationResult:
    """What a simulation computed.

    Like scipy's ``OdeResult`` it carries a status and a message instead of
    raising when a run stops early: everything computed up to the failure
    is kept.  Variables are read by dotted name, ``result["inertia1.w"]``.

    Attributes
    ----------
    time : ndarray
        Output times; an event time appears twice (left and right limit).
    status : int
        0 for success, 1 for a run a ``terminate()`` ended (a success, with
        the reason in ``message``), -1 for a run that stopped early (an
        error), -2 for a run interrupted (Ctrl-C).
    message : str
    events : tuple of Event
    modes : tuple of str
        Discrete states visited, in the order first visited.
    compiled_modes : int
        Systems compiled for the discrete states visited or tried during event
        iteration (states whose equations are the same share one).
    stats : dict
        Right-hand side evaluations, steps, seconds spent.
    notes : tuple of str
        Warnings, e.g. fixed start values relaxed as redundant.
    error : Exception or None
        The error that stopped the run.  A :class:`~acausal.errors.SimulationError`
        (or :class:`~acausal.errors.SimulationInterrupted`) given here is
        replaced, at construction, by a copy built with this result as its
        ``result``: ``result.error.result is result``.
    """

    time: np.ndarray
    columns: dict = field(repr=False)
    status: int = 0
    message: str = "The simulation reached the stop time."
    events: tuple = ()
    modes: tuple = ()
    compiled_modes: int = 0
    stats: dict = field(default_factory=dict)
    notes: tuple = ()
    error: BaseException | None = None
    model_name: str = ""

    def __post_init__(self) -> None:
        # the error travels with the partial result: its copy is built with it
        if isinstance(self.error, (SimulationError, SimulationInterrupted)) and self.error.result is not self:
            object.__setattr__(self, "error", self.error.with_result(self))

    @property
    def success(self) -> bool:
        """Whether the run ended as the model asked: at the stop time, or by ``terminate()``."""
        return self.status in (0, 1)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.columns)

    def __getitem__(self, name: str) -> np.ndarray:
        try:
            return self.columns[name]
        except KeyError:
            import difflib

            close = difflib.get_close_matches(name, list(self.columns), n=3)
            hint = f"; did you mean {', '.join(close)}?" if close else ""
            raise KeyError(f"{name!r} is not a variable of {self.model_name or 'this model'}{hint}") from None

    def __contains__(self, name: str) -> bool:
        return name in self.columns

    def final(self, name: str) -> float:
        return float(self[name][-1])

    def raise_for_status(self) -> "SimulationResult":
        """Raise the stored error if the run failed; return self otherwise."""
        if self.error is not None:
            raise self.error
        return self

    def to_csv(self, path: str | Path, signals: Sequence[str] | None = None) -> Path:
        """Write a CSV in the layout of the MSL reference results.

        ``"time"`` first, then dotted names as headers; Booleans as 0/1.
        """
        names = list(self.columns) if signals is None else list(signals)
        for n in names:
            self[n]  # clear KeyError for unknown names
        path = Path(path)
        with path.open("w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(["time"] + names)
            data = np.column_stack([self.time] + [np.asarray(self.columns[n], dtype=float)
                                                  for n in names])
            for row in data:
                writer.writerow([repr(float(v)) for v in row])
        return path

    def summary(self) -> str:
        lines = [f"{self.model_name}: {'ok' if self.success else 'FAILED'} — {self.message}",
                 f"  {len(self.time)} output points, {len(self.events)} events, "
                 f"{len(self.modes)} discrete states visited, {self.compiled_modes} systems compiled"]
        for key in ("steps", "rhs_evaluations", "translate_seconds", "simulate_seconds"):
            if key in self.stats:
                value = self.stats[key]
                lines.append(f"  {key}: {value:.4g}" if isinstance(value, float) else f"  {key}: {value}")
        lines += [f"  note: {n}" for n in self.notes]
        return "\n".join(lines)
