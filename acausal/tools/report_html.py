"""The teaching report as one self-contained web page.

:func:`acausal.tools.explain.explain` with ``html=DIR`` writes
``DIR/index.html`` through :func:`write_page`: the same stages as the text
(flat equations with their origin, aliases, structure, matching, BLT blocks,
generated code), plus what a simulation showed: every discrete state it
visited, named by its modes (:class:`StateNamer`), with the incidence
matrix of its system drawn as inline SVG (blocks boxed, tearing unknowns
marked), and the event timeline of the run.

Every variable name in the page links to the place that computes it in the
discrete state explained: the BLT block that solves an unknown, the alias
table for an alias, the list of states for a state, the parameter table for
a parameter, the discrete equations for a Boolean or Integer.  The anchors
are stable ids built by :func:`anchor_id` (``var-J1.w``; characters other
than letters, digits, ``.``, ``_`` and ``-`` are written ``~XX`` in hex).

The page has no external resources (no script, no style sheet, no font, no
image file), so it can be mailed or opened from a USB stick.  The pictures
are drawn by hand as SVG: a matplotlib figure per discrete state took
seconds each, the SVG takes milliseconds.

The engine has no domain knowledge, so discrete states are named
generically: an Integer selector is shown by the name of an ``int`` class
attribute of its component's class that has its value (a class defining
``Stuck = 0`` and ``Forward = 1`` makes ``0`` read ``Stuck``), a Boolean by its
name when it is true, a relation by its text when it is true.
"""

from __future__ import annotations

import hashlib
import html
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterable, Sequence

from ..arrays import array_groups
from ..compiler.algebraic import Assign, LinearSolve, NewtonSolve
from ..compiler.translate import ModeSystem, Translation
from ..fileio import atomic_write
from ..names import parse

__all__ = ["StateNamer", "anchor_id", "incidence_svg", "origin_label", "solution_kind", "state_file_stems",
           "tearing_unknowns", "write_page"]

#: File stems of pictures (and state ids) are cut to this many characters (plus a hash).
MAX_STEM = 96


# ---------------------------------------------------------------------------
# Names of things
# ---------------------------------------------------------------------------


def anchor_id(kind: str, name: str) -> str:
    """A stable element id for ``name`` (``anchor_id("var", "J1.w") == "var-J1.w"``).

    Letters, digits, ``.``, ``_`` and ``-`` are kept; every other character
    is written ``~XX`` (its code point in hex), so that different names get
    different ids and the id is usable unchanged in a URL fragment.
    """
    return f"{kind}-" + "".join(ch if (ch.isascii() and ch.isalnum()) or ch in "._-"
                                else f"~{ord(ch):02X}" for ch in name)


def solution_kind(step: Any) -> str:
    """How a BLT block is solved, in words (``explicit``, ``torn linear``, ``Newton`` ...)."""
    if isinstance(step, Assign):
        return "explicit"
    if isinstance(step, LinearSolve):
        return "torn linear"
    if isinstance(step, NewtonSolve):
        return "Newton" if len(step.tears) + len(step.inner) == 1 else "torn nonlinear (Newton)"
    return type(step).__name__


class StateNamer:
    """Names discrete states and discrete values by what they mean.

    ``namer(key)`` gives e.g. ``c1: Stuck, c2: Forward (startForward),
    time > 0.5``: per component, its Integer selectors by the names the flat
    model gives their values (:attr:`FlatVariable.labels`), its true Booleans by name (in parentheses after
    a mode), then the true relations.  Integer selectors of the key are
    ``pre(mode)`` values; while the solver integrates in a state they equal
    the modes themselves.

    Parameters
    ----------
    translation : Translation
        The translated model whose keys are named.
    """

    def __init__(self, translation: Translation) -> None:
        flat = translation.flat
        self._selectors = translation.selectors
        self._variables = flat.variable_map
        self._relation_texts = {r.symbol.name: r.text for r in translation.partitioned.relations}
        self._names: dict[tuple, str] = {}

    def owner(self, variable: str) -> str:
        """The dotted path of the component that declares ``variable`` ('' for the model)."""
        found = self._variables.get(variable)
        return found.component if found is not None else variable.rpartition(".")[0]

    def _value_name(self, variable: str, number: int) -> str | None:
        """The name the flat model gives ``number`` as a value of Integer ``variable``."""
        found = self._variables.get(variable)
        return dict(found.labels).get(number) if found is not None else None

    def value_text(self, variable: str, value: Any) -> str:
        """``value`` of discrete ``variable`` in words: a constant's name, ``true``, a number."""
        found = self._variables.get(variable)
        kind = found.kind if found is not None else ""
        if kind == "boolean" or isinstance(value, bool):
            return "true" if value else "false"
        if kind == "integer":
            number = int(value)
            name = self._value_name(variable, number)
            return f"{name} ({number})" if name else str(number)
        if isinstance(value, float):
            return f"{value:g}"
        return str(value)

    def __call__(self, key: tuple) -> str:
        if key in self._names:
            return self._names[key]
        groups: dict[str, tuple[list[tuple[str, str]], list[str]]] = {}
        conditions: list[str] = []
        for symbol, value in zip(self._selectors, key):
            name = parse(symbol.name)
            if name.kind == "relation":
                if value:
                    conditions.append(self._relation_texts.get(symbol.name, symbol.name))
                continue
            if name.kind in ("initial", "terminal", "sample"):
                if value:
                    conditions.append(name.text)
                continue
            variable = name.base
            owner = self.owner(variable)
            local = variable[len(owner) + 1:] if owner else variable
            modes, flags = groups.setdefault(owner, ([], []))
            found = self._variables.get(variable)
            kind = found.kind if found is not None else ""
            if kind == "boolean" or isinstance(value, bool):
                if value:
                    flags.append(local)
            elif kind == "integer":
                number = int(value)
                modes.append((local, self._value_name(variable, number) or str(number)))
            else:
                modes.append((local, f"{float(value):g}"))
        pieces = []
        for owner, (modes, flags) in groups.items():
            if not (modes or flags):
                continue
            if len(modes) == 1 and owner:
                body = modes[0][1]
            else:
                body = ", ".join(f"{local}={text}" for local, text in modes)
            if flags:
                body = f"{body} ({', '.join(flags)})" if body else ", ".join(flags)
            pieces.append(f"{owner}: {body}" if owner else body)
        pieces += conditions
        if pieces:
            text = ", ".join(pieces)
        else:
            text = "all conditions false" if self._selectors else "(continuous)"
        self._names[key] = text
        return text


def state_file_stems(names: Iterable[str]) -> list[str]:
    """File-name-safe, distinct stems for state names, in their order.

    ``"c1: Stuck, c2: Forward (startForward)"`` becomes
    ``"c1-Stuck_c2-Forward-startForward"``; a long name is cut and ends with a
    short hash of the whole name, and repeated stems get ``_2``, ``_3`` ...
    """
    stems: list[str] = []
    for name in names:
        stem = re.sub(r":\s*", "-", name)
        stem = re.sub(r"\s*\(", "-", stem)
        stem = re.sub(r"\s*>\s*", "-gt-", stem)
        stem = re.sub(r"\s*<\s*", "-lt-", stem)
        stem = re.sub(r"[^A-Za-z0-9.-]+", "_", stem).strip("_-.") or "state"
        if len(stem) > MAX_STEM:
            stem = stem[:MAX_STEM].rstrip("_-.") + "_" + hashlib.sha1(name.encode()).hexdigest()[:8]
        unique, n = stem, 1
        while unique in stems:
            n += 1
            unique = f"{stem}_{n}"
        stems.append(unique)
    return stems


# ---------------------------------------------------------------------------
# Printing, once
# ---------------------------------------------------------------------------


class _Texts:
    """Printed forms of expressions and origins, each printed once (printing sympy is slow)."""

    def __init__(self) -> None:
        self._expressions: dict[Any, str] = {}
        self._origins: dict[int, tuple[Any, str, str]] = {}

    def expression(self, expr: Any) -> str:
        try:
            return self._expressions[expr]
        except KeyError:
            text = self._expressions[expr] = str(expr)
            return text
        except TypeError:  # not hashable
            return str(expr)

    def origin(self, origin: Any) -> str:
        """``str(origin)``: where the equation comes from and its text as written."""
        return self._origin(origin)[1]

    def written(self, origin: Any) -> str:
        """The equation as written, without where it comes from."""
        return self._origin(origin)[2]

    def _origin(self, origin: Any) -> tuple[Any, str, str]:
        # keyed by identity (origins hold their unprinted source); the origin is kept
        # in the value so that its id is not reused while cached
        found = self._origins.get(id(origin))
        if found is None:
            written = getattr(origin, "text", str(origin))
            found = self._origins[id(origin)] = (origin, str(origin), written)
        return found


def origin_label(origin: Any) -> str:
    """Short form of an equation's origin, for picture rows: ``J1 eq.2`` or ``connect``."""
    component = getattr(origin, "component", "") or "model"
    declared_in = getattr(origin, "declared_in", "")
    if declared_in in ("connect", "unconnected", "binding", "relaxation"):
        return f"{component} {declared_in}"
    return f"{component} eq.{getattr(origin, 'index', 0) + 1}"


# ---------------------------------------------------------------------------
# The incidence picture
# ---------------------------------------------------------------------------

#: Outline colour of a block, by how it is solved.
KIND_COLOURS = {"explicit": "#1f77b4", "torn linear": "#ff7f0e", "Newton": "#d62728",
                "torn nonlinear (Newton)": "#d62728"}
_TEAR_COLOUR = "#c2185b"


def _steps_of(system: ModeSystem) -> list:
    steps = list(system.algebraic.steps)
    return steps if len(steps) == len(system.blt.blocks) else [None] * len(system.blt.blocks)


def tearing_unknowns(system: ModeSystem) -> set[str]:
    """The tearing unknowns of every torn block of ``system``."""
    return {name for step, block in zip(_steps_of(system), system.blt.blocks)
            if isinstance(step, (LinearSolve, NewtonSolve)) and block.size > 1 for name in step.tears}


def incidence_svg(system: ModeSystem, title: str, texts: _Texts | None = None,
                  column_links: dict[str, str] | None = None, row_links: bool = False) -> str:
    """The incidence matrix of ``system`` in BLT order, as an inline ``<svg>`` element.

    Parameters
    ----------
    system : ModeSystem
        A compiled discrete state.
    title : str
        Shown above the matrix (the state's name).
    texts : _Texts, optional
        Printed origins, shared with the rest of the page.
    column_links : dict, optional
        ``unknown -> element id``: the column labels link there.
    row_links : bool
        Rows link to ``#eq-E<i>`` (the equations listed for the explained state).

    Returns
    -------
    str
        SVG markup: rows are equations (labelled with their component and
        equation number, the whole equation as a tooltip), columns the unknowns
        they are solved for, matched pairs black on the diagonal, other
        occurrences grey, blocks outlined in the colour of how they are solved,
        tearing unknowns' columns shaded and labelled in magenta with ``†``.
    """
    texts = texts or _Texts()
    column_links = column_links or {}
    st, blt = system.structure, system.blt
    rows, cols = list(blt.equation_order), list(blt.unknown_order)
    n = len(rows)
    tears = tearing_unknowns(system)
    cell = 12.0 if n <= 80 else max(4.0, 960.0 / n)
    font = min(10.0, cell * 0.85 + 1)
    char = 0.6 * font
    row_labels = [f"E{i + 1} {origin_label(st.equations[i].origin)}" for i in rows]
    col_labels = [st.unknowns[j] + (" \u2020" if st.unknowns[j] in tears else "") for j in cols]
    left = 8 + char * max((len(t) for t in row_labels), default=4)
    top_title = 22.0
    top = top_title + 8 + char * max((len(t) for t in col_labels), default=4)
    width = left + cell * n + 10
    height = top + cell * n + 10
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" class="incidence" width="{width:.0f}" '
           f'height="{height:.0f}" viewBox="0 0 {width:.0f} {height:.0f}" role="img" '
           f'font-family="monospace" font-size="{font:.1f}">',
           f"<title>Incidence matrix in BLT order: {html.escape(title)}</title>",
           f'<text x="4" y="15" font-size="12" font-family="sans-serif">{html.escape(title)}</text>']
    if n == 0:
        out.append(f'<text x="4" y="{top_title + 14}">no unknowns to solve</text></svg>')
        return "\n".join(out)
    position = {j: k for k, j in enumerate(cols)}
    # shaded columns of the tearing unknowns, under everything else
    for k, j in enumerate(cols):
        if st.unknowns[j] in tears:
            out.append(f'<rect x="{left + k * cell:.1f}" y="{top:.1f}" width="{cell:.1f}" '
                       f'height="{cell * n:.1f}" fill="{_TEAR_COLOUR}" fill-opacity="0.12"/>')
    pad = cell * 0.15
    for r, i in enumerate(rows):
        for j in st.incidence[i]:
            colour = "#000" if j == st.matching[i] else "#999"
            out.append(f'<rect x="{left + position[j] * cell + pad:.1f}" y="{top + r * cell + pad:.1f}" '
                       f'width="{cell - 2 * pad:.1f}" height="{cell - 2 * pad:.1f}" fill="{colour}"/>')
    start = 0
    for block, step in zip(blt.blocks, _steps_of(system)):
        kind = solution_kind(step) if step is not None else "explicit"
        colour = KIND_COLOURS.get(kind, "#9467bd")
        stroke = 0.8 if block.size == 1 else 2.0
        out.append(f'<rect x="{left + start * cell:.1f}" y="{top + start * cell:.1f}" '
                   f'width="{block.size * cell:.1f}" height="{block.size * cell:.1f}" fill="none" '
                   f'stroke="{colour}" stroke-width="{stroke}"><title>{html.escape(kind)}, size '
                   f'{block.size}</title></rect>')
        start += block.size
    for r, (i, label) in enumerate(zip(rows, row_labels)):
        y = top + (r + 0.5) * cell + font * 0.35
        element = (f'<text x="{left - 4:.1f}" y="{y:.1f}" text-anchor="end">{html.escape(label)}'
                   f"<title>{html.escape(texts.origin(st.equations[i].origin))}</title></text>")
        out.append(f'<a href="#eq-E{i + 1}">{element}</a>' if row_links else element)
    for k, (j, label) in enumerate(zip(cols, col_labels)):
        x = left + (k + 0.5) * cell + font * 0.35
        name = st.unknowns[j]
        fill = f' fill="{_TEAR_COLOUR}" font-weight="bold"' if name in tears else ""
        element = (f'<text x="{x:.1f}" y="{top - 4:.1f}" transform="rotate(-90 {x:.1f} {top - 4:.1f})"'
                   f"{fill}>{html.escape(label)}</text>")
        target = column_links.get(name)
        out.append(f'<a href="#{target}">{element}</a>' if target else element)
    out.append("</svg>")
    return "\n".join(out)


# ---------------------------------------------------------------------------
# The page
# ---------------------------------------------------------------------------

_STYLE = """
body { font-family: sans-serif; margin: 1.5em auto; max-width: 80em; padding: 0 1em; line-height: 1.4; }
code, pre, td.eq { font-family: monospace; }
pre { background: #f6f6f6; padding: 0.8em; overflow-x: auto; }
table { border-collapse: collapse; margin: 0.5em 0 1em; }
th, td { border-bottom: 1px solid #ddd; padding: 0.15em 0.6em; text-align: left; vertical-align: top; }
th { background: #eee; }
a { color: #0645ad; text-decoration: none; }
a:hover { text-decoration: underline; }
:target { background: #fff3a0; }
.tear { color: #c2185b; font-weight: bold; }
.note { border-left: 4px solid #f0ad4e; padding-left: 0.8em; }
.muted { color: #666; }
.picture { overflow-x: auto; }
nav li { display: inline; margin-right: 1em; }
section.state { border-top: 2px solid #ccc; margin-top: 1.5em; }
"""


@dataclass
class _Context:
    translation: Translation
    main: ModeSystem
    texts: _Texts
    namer: StateNamer
    targets: dict[str, str]  # variable name -> id of the place that computes it (explained state)


class _Page:
    """Collects the page's markup; knows which ids were written."""

    def __init__(self) -> None:
        self.parts: list[str] = []
        self.ids: set[str] = set()

    def add(self, markup: str) -> None:
        self.parts.append(markup)

    def id_attr(self, element_id: str | None) -> str:
        """`` id="..."`` the first time an id is asked for, else nothing (ids stay unique)."""
        if not element_id or element_id in self.ids:
            return ""
        self.ids.add(element_id)
        return f' id="{element_id}"'

    def text(self) -> str:
        return "\n".join(self.parts)


def _esc(text: Any) -> str:
    return html.escape(str(text), quote=True)


class _Linker:
    """Escapes text and turns every known variable name in it into a link."""

    def __init__(self, targets: dict[str, str]) -> None:
        self.targets = targets
        names = sorted(targets, key=len, reverse=True)
        # longest first, so that der(J1.w) wins over J1.w; a name is not part of a longer name
        self._pattern = (re.compile(r"(?<![\w.$])(" + "|".join(re.escape(n) for n in names)
                                    + r")(?![\w$(\[])(?!\.\w)") if names else None)

    def __call__(self, text: str) -> str:
        if self._pattern is None:
            return _esc(text)
        out, last = [], 0
        for match in self._pattern.finditer(text):
            out.append(_esc(text[last:match.start()]))
            name = match.group(1)
            out.append(f'<a href="#{self.targets[name]}">{_esc(name)}</a>')
            last = match.end()
        out.append(_esc(text[last:]))
        return "".join(out)

    def name(self, name: str, css: str = "") -> str:
        """One variable name, linked if it has a target."""
        attr = f' class="{css}"' if css else ""
        target = self.targets.get(name)
        if target is None:
            return f"<code{attr}>{_esc(name)}</code>"
        return f'<a href="#{target}"{attr}><code>{_esc(name)}</code></a>'


def _main_targets(translation: Translation, main: ModeSystem) -> dict[str, str]:
    """Where each variable is computed in the explained state (the ids the page writes)."""
    targets: dict[str, str] = {}
    for p in translation.flat.parameters:
        targets[p.name] = anchor_id("var", p.name)
    for name in main.aliases.aliases:
        targets[name] = anchor_id("var", name)
    for name in (*main.structure.states, *main.structure.unknowns):
        targets[name] = anchor_id("var", name)
    for eq in translation.partitioned.discrete_equations:
        targets.setdefault(str(eq.variable), anchor_id("var", str(eq.variable)))
    for rel in translation.partitioned.relations:
        targets[rel.symbol.name] = anchor_id("rel", str(rel.index))
    return targets


def write_page(translation: Translation, main: ModeSystem, out_dir: str | Path, *,
               result: Any = None, visited: Sequence[str] | None = None, text: str | None = None,
               notes: Sequence[str] = ()) -> Path:
    """Write the teaching page ``out_dir/index.html`` and return its path.

    Parameters
    ----------
    translation : Translation
        The model's (unclustered) translation, with the systems compiled so far.
    main : ModeSystem
        The discrete state explained stage by stage.
    out_dir : str or Path
        Folder of the page (created if missing).
    result : SimulationResult, optional
        The run whose event timeline is shown.
    visited : sequence of str, optional
        Descriptions (``translation.describe(key)``) of the discrete states the
        run visited, in order; by default every compiled state.
    text : str, optional
        The plain-text explanation, appended in a folded section.
    notes : sequence of str
        Remarks shown at the top (e.g. that the run stopped early).

    Returns
    -------
    Path
        The page written (whole or not at all: a failed write leaves an
        earlier page as it was).
    """
    texts = _Texts()
    context = _Context(translation, main, texts, StateNamer(translation), _main_targets(translation, main))
    link = _Linker(context.targets)
    page = _Page()
    flat = translation.flat
    hybrid = translation.partitioned.is_hybrid

    systems = list(translation.systems.values()) or [main]
    by_description = {s.description: s for s in systems}
    if visited:
        shown = [by_description[d] for d in dict.fromkeys(visited) if d in by_description]
    else:
        shown = systems
    if main not in shown:
        shown.insert(0, main)
    names = {s.key: context.namer(s.key) for s in systems}
    stems = dict(zip([s.key for s in shown], state_file_stems(names[s.key] for s in shown)))
    state_ids = {key: f"state-{stem}" for key, stem in stems.items()}

    sections = [("flat", "Flat model"), ("aliases", "Alias elimination"),
                ("structure", "Structural analysis"), ("matching", "Matching"),
                ("blt", "BLT blocks"), ("code", "Generated code")]
    if hybrid:
        sections.append(("hybrid", "Relations and discrete equations"))
    sections += [("states", "Discrete states visited"), ("events", "Event timeline")]
    if text:
        sections.append(("text", "The text explanation"))

    title = f"How {flat.name} is translated"
    page.add(f'<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
             f"<title>{_esc(title)}</title>\n<style>{_STYLE}</style>\n</head>\n<body>")
    page.add(f'<h1{page.id_attr("top")}>{_esc(title)}</h1>')
    if flat.modelica_class:
        page.add(f'<p class="muted">{_esc(flat.modelica_class)}</p>')
    page.add(f"<p>{_esc(flat.summary())}</p>")
    page.add("<nav><ul>" + "".join(f'<li><a href="#{sid}">{k}. {_esc(label)}</a></li>'
                                    for k, (sid, label) in enumerate(sections, start=1)) + "</ul></nav>")
    page.add("<p>Every variable name links to where it is computed in the discrete state explained "
             f'(<a href="#{state_ids[main.key]}">{_esc(names[main.key])}</a>): the BLT block that '
             "solves it, the alias table, the list of states or the parameters.  Tearing unknowns "
             'are marked <span class="tear">\u2020</span>.</p>')
    for note in notes:
        page.add(f'<p class="note">{_esc(note)}</p>')

    _flat_section(page, context, link)
    _alias_section(page, context, link)
    _structure_section(page, context, link)
    _matching_section(page, context, link)
    _blt_section(page, context, link, names[main.key])
    _code_section(page, context)
    if hybrid:
        _hybrid_section(page, context, link)
    _states_section(page, context, link, shown, names, state_ids, visited is not None)
    _events_section(page, context, link, result)
    if text:
        page.add(f'<h2{page.id_attr("text")}>The text explanation</h2>')
        page.add(f"<details><summary>what <code>acausal explain</code> prints</summary>"
                 f"<pre>{_esc(text)}</pre></details>")
    page.add("</body>\n</html>\n")

    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    # whole or not at all: a page that cannot be written leaves the earlier one as it was
    markup = page.text()
    return atomic_write(out / "index.html", lambda handle: handle.write(markup), "w", encoding="utf-8")


def _flat_section(page: _Page, c: _Context, link: _Linker) -> None:
    flat = c.translation.flat
    page.add(f'<h2{page.id_attr("flat")}>1. Flat model</h2>')
    page.add("<p>Flattening walks the component tree: every variable gets its dotted name, every "
             "connect() becomes equations (potentials equal, flows summing to zero) and parameters "
             "get their numeric values.  Each equation remembers the component and the equation it "
             "comes from.</p>")
    if flat.parameters:
        page.add(f"<h3>Parameters ({len(flat.parameters)})</h3><table><tr><th>name</th><th>value</th>"
                 "<th>unit</th></tr>")
        by_name = {p.name: p for p in flat.parameters}

        def row(p) -> str:
            value = f"{p.value:g}" if isinstance(p.value, float) else p.value
            return (f'<tr{page.id_attr(c.targets.get(p.name))}><td><code>{_esc(p.name)}</code></td>'
                    f"<td>{_esc(value)}</td><td>{_esc(p.unit or '')}</td></tr>")

        for name, shape, members in array_groups(by_name):
            if shape is None:
                page.add(row(by_name[name]))
                continue
            # an array: one row with its size, its elements in a nested table that opens
            inner = "".join(row(by_name[m]) for m in members)
            page.add(f"<tr><td colspan=\"3\"><details><summary><code>{_esc(name)}"
                     f"[{', '.join(map(str, shape))}]</code> ({len(members)} elements)</summary>"
                     f"<table>{inner}</table></details></td></tr>")
        page.add("</table>")
    fixed = [v for v in flat.variables if v.fixed]
    if fixed:
        page.add("<h3>Start values with fixed=true (initial conditions)</h3><ul>")
        by_name = {v.name: v for v in fixed}

        def item(v) -> str:
            start = f"{v.start:g}" if isinstance(v.start, float) else v.start
            return f"<li>{link.name(v.name)} = {_esc(start)}</li>"

        for name, shape, members in array_groups(by_name):
            if shape is None:
                page.add(item(by_name[name]))
            else:  # an array: one entry with its size, its elements when opened
                page.add(f"<li><details><summary><code>{_esc(name)}[{', '.join(map(str, shape))}]</code> "
                         f"({len(members)} elements)</summary><ul>"
                         + "".join(item(by_name[m]) for m in members) + "</ul></details></li>")
        page.add("</ul>")
    page.add(f"<h3>Flat equations ({len(flat.equations)})</h3>")
    page.add("<table><tr><th>#</th><th>component</th><th>from</th><th>equation as written</th></tr>")
    for k, eq in enumerate(flat.equations, start=1):
        origin = eq.origin
        page.add(f'<tr{page.id_attr(f"flat-{k}")}><td>[{k}]</td>'
                 f"<td>{_esc(origin.component or '(model)')}</td>"
                 f"<td>{_esc(_declared(origin))}</td>"
                 f'<td class="eq">{link(c.texts.written(origin))}</td></tr>')
    page.add("</table>")
    for label, prefix, equations in (("Initial equations, used only to find the initial values", "I",
                                      flat.initial_equations),
                                     ("Discrete equations, for Boolean and Integer variables", "D",
                                      flat.discrete_equations)):
        if not equations:
            continue
        page.add(f"<h3>{label} ({len(equations)})</h3><table>")
        for k, eq in enumerate(equations, start=1):
            page.add(f"<tr><td>[{prefix}{k}]</td><td>{_esc(eq.origin.component or '(model)')}</td>"
                     f'<td class="eq">{link(c.texts.written(eq.origin))}</td></tr>')
        page.add("</table>")


def _declared(origin: Any) -> str:
    declared_in = getattr(origin, "declared_in", "")
    if declared_in in ("connect", "unconnected", "binding", "relaxation"):
        return declared_in
    return f"{declared_in} eq. {getattr(origin, 'index', 0) + 1}"


def _alias_section(page: _Page, c: _Context, link: _Linker) -> None:
    aliases = c.main.aliases
    flat_number: dict[int, int] = {}
    for k, eq in enumerate(c.translation.flat.equations, start=1):
        flat_number.setdefault(id(eq.origin), k)
    page.add(f'<h2{page.id_attr("aliases")}>2. Alias elimination</h2>')
    page.add("<p>Connections produce many trivial equations a = b, a = -b and a = constant.  Each "
             "group of variables joined by them keeps one representative; the others become "
             "aliases, vanish from the system and are recovered for the results.</p>")
    page.add(f"<p>{len(aliases.eliminated)} of {len(c.main.equations)} equations removed as alias "
             f"equations; {len(aliases.equations)} remain, for {len(aliases.variables)} variables.</p>")
    removed = [flat_number.get(id(eq.origin)) for eq in aliases.eliminated]
    if removed and all(r is not None for r in removed):
        page.add("<p>Removed: " + ", ".join(f'<a href="#flat-{r}">[{r}]</a>' for r in removed) + "</p>")
    if not aliases.aliases:
        page.add("<p>No aliases.</p>")
        return
    page.add(f"<table><tr><th>alias ({len(aliases.aliases)})</th><th>is</th></tr>")
    for name, expr in aliases.aliases.items():
        page.add(f'<tr{page.id_attr(c.targets.get(name))}><td><code>{_esc(name)}</code></td>'
                 f'<td class="eq">{link(c.texts.expression(expr))}</td></tr>')
    page.add("</table>")


def _structure_section(page: _Page, c: _Context, link: _Linker) -> None:
    st = c.main.structure
    page.add(f'<h2{page.id_attr("structure")}>3. Structural analysis</h2>')
    page.add("<p>Each equation is treated as the set of unknowns it contains (its incidence).  A "
             "variable that appears differentiated, der(x), is a candidate state: the solver "
             "integrates it.  When equations constrain states only, Pantelides' algorithm "
             "differentiates them (index reduction) and the dummy derivative method turns as many "
             "derivatives back into algebraic unknowns.</p>")
    added = dict(st.differentiated)
    page.add("<table><tr><th>equation</th><th>from</th><th>0 =</th></tr>")
    for i, eq in enumerate(st.equations):
        where = (f"d/dt E{added[i] + 1}" if i in added else "") or c.texts.origin(eq.origin)
        page.add(f'<tr{page.id_attr(f"eq-E{i + 1}")}><td>E{i + 1}</td><td>{link(where)}</td>'
                 f'<td class="eq">{link(c.texts.expression(eq.residual))}</td></tr>')
    page.add("</table>")
    if st.differentiated:
        page.add("<p>Index reduction: " + ", ".join(
            f'<a href="#eq-E{i + 1}">E{i + 1}</a> = d/dt <a href="#eq-E{k + 1}">E{k + 1}</a>'
            for i, k in st.differentiated) + "</p>")
    else:
        page.add("<p>Index reduction: not needed (index 1 or lower).</p>")
    page.add(f"<h3>States ({len(st.states)}), integrated by the ODE solver</h3><ul>")
    for state, derivative in zip(st.states, st.derivatives):
        page.add(f"<li{page.id_attr(c.targets.get(state))}><code>{_esc(state)}</code>, from its "
                 f"derivative {link.name(str(derivative))}</li>")
    page.add("</ul>")
    if st.dummy_derivatives:
        page.add("<p>Dummy derivatives (solved as algebraic unknowns): "
                 + ", ".join(link.name(n) for n in st.dummy_derivatives) + "</p>")


def _matching_section(page: _Page, c: _Context, link: _Linker) -> None:
    st = c.main.structure
    page.add(f'<h2{page.id_attr("matching")}>4. Matching</h2>')
    page.add("<p>Every equation is assigned the unknown it will be solved for, each unknown exactly "
             "once (a perfect matching of the bipartite equation-unknown graph).  This is where the "
             "equations get their causality.</p>")
    page.add("<table><tr><th>equation</th><th>solved for</th><th>from</th></tr>")
    for i, j in enumerate(st.matching):
        page.add(f'<tr><td><a href="#eq-E{i + 1}">E{i + 1}</a></td><td>{link.name(st.unknowns[j])}</td>'
                 f"<td>{_esc(origin_label(st.equations[i].origin))}</td></tr>")
    page.add("</table>")


def _blocks_table(page: _Page, system: ModeSystem, link: _Linker, targets: dict[str, str],
                  texts: _Texts, equation_links: bool) -> None:
    """One row per BLT block: how it is solved, its equations, its unknowns (with their ids)."""
    st = system.structure
    page.add("<table><tr><th>block</th><th>solved</th><th>equations</th><th>unknowns</th>"
             "<th>solution</th></tr>")
    for n, (block, step) in enumerate(zip(system.blt.blocks, _steps_of(system)), start=1):
        kind = solution_kind(step) if step is not None else "?"
        tears = set(step.tears) if isinstance(step, (LinearSolve, NewtonSolve)) and block.size > 1 else set()
        equations = ", ".join(
            (f'<a href="#eq-E{i + 1}">E{i + 1}</a>' if equation_links
             else f'<span title="{_esc(texts.origin(st.equations[i].origin))}">E{i + 1}</span>')
            for i in block.equations)
        unknowns = []
        for j in block.unknowns:
            name = st.unknowns[j]
            mark = ' class="tear" title="tearing unknown"' if name in tears else ""
            unknowns.append(f"<code{page.id_attr(targets.get(name))}{mark}>{_esc(name)}"
                            f"{' &#8224;' if name in tears else ''}</code>")
        if isinstance(step, Assign):
            solution = f"{link.name(step.variable)} := {link(texts.expression(step.expression))}"
        elif tears:
            solution = ("tearing unknowns " + ", ".join(link.name(t, "tear") for t in step.tears)
                        + (", then in turn " + ", ".join(link.name(a.variable) for a in step.inner)
                           if step.inner else ""))
        else:
            solution = ""
        page.add(f"<tr><td>B{n}</td><td>{_esc(kind)}, size {block.size}</td><td>{equations}</td>"
                 f"<td>{', '.join(unknowns)}</td><td class=\"eq\">{solution}</td></tr>")
    page.add("</table>")


def _legend() -> str:
    kinds = ", ".join(f'<span style="color:{colour}">\u25a1 {_esc(kind)}</span>'
                      for kind, colour in KIND_COLOURS.items() if kind != "Newton")
    return (f'<p class="muted">Picture: rows are equations in BLT order, columns the unknowns they '
            f"are solved for; black: matched (solved for), grey: occurs; blocks outlined: {kinds}; "
            f'<span class="tear">\u2020</span> tearing unknown (its column shaded).  Hover a row for '
            f"its equation; click a label to go to it.</p>")


def _blt_section(page: _Page, c: _Context, link: _Linker, state_name: str) -> None:
    blt, alg = c.main.blt, c.main.algebraic
    page.add(f'<h2{page.id_attr("blt")}>5. BLT: block lower triangular order</h2>')
    page.add("<p>With each equation matched, an equation must come after the one that solves an "
             "unknown it uses.  The strongly connected parts of that dependency graph are the "
             "blocks; in this order each block only needs unknowns computed before it.  A block of "
             "one equation is solved explicitly; a larger one is torn: the tearing unknowns are "
             "guessed, the other equations solved in turn, and what is left is a small linear "
             "solve or Newton's method.</p>")
    sizes = [b.size for b in blt.blocks]
    page.add(f"<p>{len(blt.blocks)} blocks; largest {blt.largest_block}; {sum(s == 1 for s in sizes)} "
             f"of size one; {alg.linear_blocks} torn linear, {alg.nonlinear_blocks} nonlinear.</p>")
    page.add(_legend())
    page.add('<div class="picture">' + incidence_svg(c.main, state_name, c.texts, c.targets, row_links=True)
             + "</div>")
    _blocks_table(page, c.main, link, c.targets, c.texts, equation_links=True)


def _code_section(page: _Page, c: _Context) -> None:
    page.add(f'<h2{page.id_attr("code")}>6. Generated code</h2>')
    page.add("<p>The solution steps become straight-line Python: <code>derivatives(t, x)</code> is "
             "what the ODE solver calls, <code>crossings(t, x)</code> gives the sides of the "
             "relations watched for events, <code>outputs(t, x)</code> every unknown for the "
             "results.</p>")
    page.add(f'<pre class="code"><code>{_esc(c.main.code.source)}</code></pre>')


def _hybrid_section(page: _Page, c: _Context, link: _Linker) -> None:
    partitioned = c.translation.partitioned
    page.add(f'<h2{page.id_attr("hybrid")}>7. Relations and discrete equations</h2>')
    page.add("<p>Relations on continuous quantities become Booleans that keep their value between "
             "events; the solver watches each one for a crossing (state event) or computes when it "
             "flips (time event).  At an event the discrete equations are evaluated until nothing "
             "changes (event iteration), and a new discrete state may select other equations.</p>")
    if partitioned.relations:
        page.add("<table><tr><th>relation</th><th>watched</th><th>kind</th></tr>")
        for rel in partitioned.relations:
            kind = "time event" if rel.is_time_event else "state event"
            page.add(f'<tr{page.id_attr(anchor_id("rel", str(rel.index)))}><td><code>'
                     f"{_esc(rel.symbol.name)}</code></td><td class=\"eq\">{link(rel.text)}</td>"
                     f"<td>{kind}</td></tr>")
        page.add("</table>")
    if partitioned.discrete_equations:
        page.add(f"<h3>Discrete equations ({len(partitioned.discrete_equations)}), in evaluation "
                 f"order</h3><table>")
        for eq in partitioned.discrete_equations:
            variable = str(eq.variable)
            page.add(f'<tr{page.id_attr(c.targets.get(variable))}><td><code>{_esc(variable)}</code> '
                     f':=</td><td class="eq">{link(c.texts.expression(eq.rhs))}</td>'
                     f"<td>{_esc(eq.origin.component or '(model)')}</td></tr>")
        page.add("</table>")


def _states_section(page: _Page, c: _Context, link: _Linker, shown: list[ModeSystem],
                    names: dict[tuple, str], state_ids: dict[tuple, str], from_run: bool) -> None:
    page.add(f'<h2{page.id_attr("states")}>Discrete states {"visited" if from_run else "compiled"} '
             f"({len(shown)})</h2>")
    if c.translation.partitioned.is_hybrid:
        page.add("<p>A discrete state is the values of the discrete symbols the continuous equations "
                 "depend on; each one has its own system.  The states are named by their modes (the "
                 "names of the owning class's integer constants), the Booleans that are true and "
                 "the relations that are true.</p>")
    page.add(_legend())
    pictured: dict[tuple, tuple] = {}  # system shared -> the state whose picture shows it
    pictured[c.main.shares if c.main.shares is not None else c.main.key] = c.main.key
    for system in shown:
        sid = state_ids[system.key]
        page.add(f'<section class="state"{page.id_attr(sid)}><h3>{_esc(names[system.key])}</h3>')
        page.add(f'<details><summary class="muted">the values of every discrete symbol</summary>'
                 f"<p><code>{_esc(system.description)}</code></p></details>")
        if system is c.main:
            page.add('<p>This is the state explained in sections <a href="#aliases">2</a>-'
                     '<a href="#code">6</a>; its picture and blocks are in <a href="#blt">section 5</a>.</p>')
            page.add("</section>")
            continue
        twin = system.shares if system.shares is not None else system.key
        if twin in pictured:
            other = pictured[twin]
            page.add(f'<p>The same equations as <a href="#{state_ids[other]}">{_esc(names[other])}</a>: '
                     f"its compiled system serves both.</p></section>")
            continue
        pictured[twin] = system.key
        st = system.structure
        prefix = sid + "-"
        targets = {name: prefix + anchor_id("var", name) for name in st.unknowns}
        page.add(f"<p>{len(system.aliases.equations)} equations after alias elimination, "
                 f"{len(st.differentiated)} added by index reduction; {len(system.blt.blocks)} "
                 f"blocks, largest {system.blt.largest_block}.  States: "
                 + ", ".join(link.name(s) for s in st.states) + ".</p>")
        page.add('<div class="picture">' + incidence_svg(system, names[system.key], c.texts, targets)
                 + "</div>")
        _blocks_table(page, system, link, targets, c.texts, equation_links=False)
        page.add("</section>")


def _events_section(page: _Page, c: _Context, link: _Linker, result: Any) -> None:
    page.add(f'<h2{page.id_attr("events")}>Event timeline</h2>')
    if result is None:
        page.add("<p>No simulation was run.</p>")
        return
    events = list(getattr(result, "events", ()))
    page.add(f"<p>{len(events)} events in the run from {result.time[0]:g} to {result.time[-1]:g}"
             f"{'' if result.success else ' (stopped early: ' + _esc(result.message) + ')'}.  "
             "Kind: <code>initial</code> after initialization, <code>time</code> when a time "
             "relation or clock is reached, <code>state</code> when a watched relation crosses.</p>")
    if not events:
        return
    page.add('<table class="events"><tr><th>time</th><th>kind</th><th>triggered by</th>'
             "<th>what changed</th><th>iterations</th></tr>")
    for event in events:
        changes = []
        for name, old, new in event.changes:
            if name.startswith("reinit("):
                changes.append(f"{_esc(name)}: {_esc(f'{old:g}')} \u2192 {_esc(f'{new:g}')}"
                               if isinstance(old, float) and isinstance(new, float)
                               else f"{_esc(name)}: {_esc(old)} \u2192 {_esc(new)}")
                continue
            changes.append(f"{link.name(name)}: {_esc(c.namer.value_text(name, old))} \u2192 "
                           f"{_esc(c.namer.value_text(name, new))}")
        triggers = ", ".join(link(r) for r in event.relations)
        time = float(event.time)
        page.add(f'<tr class="event" data-time="{time!r}"><td>{time:.10g}</td><td>{_esc(event.kind)}</td>'
                 f'<td class="eq">{triggers}</td><td>{"<br>".join(changes) or "-"}</td>'
                 f"<td>{event.iterations}</td></tr>")
    page.add("</table>")
