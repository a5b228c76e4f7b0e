"""Plots of a simulation result: one panel per signal (or group), with units,
event lines and the names of an Integer mode's values.

Values are drawn in each signal's display unit (``Variable(display_unit="rpm")``)
or in the unit asked for, ``plot(result, "J1.w", units={"J1.w": "rpm"})``.

Importing this module registers :func:`plot` as the plotter of
:meth:`acausal.SimulationResult.plot` (the runtime does not import the
tools layer, so it cannot find it on its own)::

    import acausal.tools.plotting
    figure = result.plot(["inertia1.w", "clutch.mode"])

matplotlib is imported when a plot is made, not with this module.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Mapping, Sequence

import numpy as np

from ..runtime.result import ColumnInfo, SimulationResult, register_plotter

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["plot", "event_times"]

#: How many signals :func:`plot` shows when none are named.
DEFAULT_SIGNALS = 4


def event_times(result: SimulationResult, initial: bool = False) -> list[float]:
    """The distinct event instants of ``result``, in time order.

    From :attr:`~acausal.SimulationResult.events` (the initial event only
    with ``initial``), else, for a result read from a file, the times that
    appear more than once in its time column (the left and right limits).
    """
    if result.events:
        times = {float(e.time) for e in result.events if initial or e.kind != "initial"}
    else:
        time = np.asarray(result.time, dtype=float)
        times = set(time[1:][time[1:] == time[:-1]].tolist())
    return sorted(times)


def _groups(result: SimulationResult, names) -> list[list[str]]:
    """``names`` as panels: a str is one panel, a sequence of str one panel with all of them."""
    if names is None:
        chosen = [n for n in result.names if result.info(n).kind != "parameter"
                  and not n.startswith("der(")][:DEFAULT_SIGNALS]
        return [[n] for n in chosen]
    if isinstance(names, str):
        names = [names]
    groups = [[entry] if isinstance(entry, str) else list(entry) for entry in names]
    for group in groups:
        for name in group:
            result.info(name)  # a KeyError with the close names for an unknown one
    # an array name (cell.T) is one panel of its elements
    return [[element for name in group for element in result.elements(name)] for group in groups]


def _label(info: ColumnInfo, unit: str | None = None) -> str:
    """``name [unit]``: the unit the values are drawn in (default: the declared one)."""
    unit = info.unit if unit is None else unit
    return f"{info.name} [{unit}]" if unit else info.name


def _panel(ax: "Axes", result: SimulationResult, group: list[str], events: list[float],
           shown: Mapping[str, str]) -> None:
    infos = [result.info(n) for n in group]
    time = np.asarray(result.time, dtype=float)
    for info in infos:
        unit = shown.get(info.name, info.unit)
        if info.is_discrete or unit == info.unit:
            values = np.asarray(result.columns[info.name], dtype=float)
        else:
            values = np.asarray(result.in_unit(info.name, unit), dtype=float)
        # discrete values hold between events: a step, not a ramp
        style = "steps-post" if info.kind in ("boolean", "integer", "discrete") else "default"
        ax.plot(time, values, drawstyle=style, label=_label(info, unit))
    for t in events:
        ax.axvline(t, color="0.6", linewidth=0.8, linestyle=":", zorder=0)
    units = {shown.get(i.name, i.unit) for i in infos}
    if len(infos) == 1:
        ax.set_ylabel(_label(infos[0], shown.get(infos[0].name)))
    else:
        ax.set_ylabel(f"[{units.pop()}]" if len(units) == 1 and "" not in units else "")
        ax.legend(loc="best", fontsize="small")
    labels = infos[0].labels if len({i.labels for i in infos}) == 1 else ()
    if all(i.kind == "boolean" for i in infos):
        ax.set_yticks([0, 1], ["false", "true"])
    elif labels and all(i.kind == "integer" for i in infos):
        values = [v for v, _ in labels]
        ax.set_yticks(values, [f"{n} ({v})" for v, n in labels])
        ax.set_ylim(min(values) - 0.5, max(values) + 0.5)
    ax.grid(True, alpha=0.3)


def plot(result: SimulationResult, names: str | Sequence[str | Sequence[str]] | None = None, *,
         events: bool = True, figure: "Figure | None" = None, title: str | None = None,
         panel_height: float = 2.2, width: float = 8.0, units: Mapping[str, str] | None = None,
         display_units: bool = True) -> "Figure":
    """A figure with one panel per signal (or group of signals) against time.

    Parameters
    ----------
    result : SimulationResult
    names : str, or sequence of str or of sequences of str, optional
        The signals: each entry one panel; an entry that is a sequence of
        names puts them in one panel with a legend.  Default: the first
        :data:`DEFAULT_SIGNALS` signals that are not parameters.
    events : bool
        Draw a dotted vertical line at each event instant (the initial event
        excepted).
    figure : matplotlib Figure, optional
        Draw into this figure (cleared first); default: a new one from
        ``matplotlib.pyplot`` (so that it shows in notebooks and with
        ``plt.show()``).
    title : str, optional
        Default: the model name and the run's status.
    panel_height, width : float
        Size of a new figure, in inches.
    units : mapping of str to str, optional
        Units to draw signals in, ``{"J1.w": "rpm", "T": "degC"}`` (Modelica
        unit syntax, or ``rpm``, ``°C``; see
        :func:`~acausal.runtime.result.convert_unit`).  Every name must be a
        column of the result; names not drawn are ignored, so one mapping
        can serve several plots.
    display_units : bool
        Draw the other signals in their declared display unit (True, the
        default) or in their declared unit (False).

    Returns
    -------
    matplotlib.figure.Figure
        The y axes are labelled ``name [unit]`` (the unit drawn in); Booleans
        and Integers are drawn as steps, Booleans with false/true ticks and
        Integers whose values have names
        (:attr:`~acausal.runtime.result.ColumnInfo.labels`) with those names
        as ticks.

    Raises
    ------
    KeyError
        For a name (in ``names`` or ``units``) that is not a column.
    ValueError
        For a unit a signal cannot be drawn in, naming both units (before
        anything is drawn).
    """
    groups = _groups(result, names)
    if not groups:
        raise ValueError("nothing to plot: the result has no signals")
    drawn = [name for group in groups for name in group]
    shown = result.shown_units(drawn, display_units)
    if units:
        # every name must be a column (a KeyError names the close ones), and each unit must fit;
        # the names not drawn are let be, so that one mapping can serve several plots
        given = result.shown_units(list(units), dict(units))
        shown.update({name: unit for name, unit in given.items() if name in shown})
    if figure is None:
        import matplotlib.pyplot as plt  # lazily: only a plot needs matplotlib

        figure = plt.figure(figsize=(width, max(2.5, panel_height * len(groups) + 0.8)))
    else:
        figure.clear()
    axes = figure.subplots(len(groups), 1, sharex=True, squeeze=False)[:, 0]
    instants = event_times(result) if events else []
    for ax, group in zip(axes, groups):
        _panel(ax, result, group, instants, shown)
    axes[-1].set_xlabel("time [s]")
    if title is None:
        title = f"{result.model_name or 'result'}" + ("" if result.success else f" ({result.message})")
    figure.suptitle(title)
    figure.tight_layout()
    return figure


register_plotter(plot)
