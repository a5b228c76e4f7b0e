"""The teaching view: what each stage of the engine did to one model.

:func:`explain` runs the translation of a model and writes, stage after
stage, what came out of it, in words a student learning how an
equation-based tool works can follow:

1. the flat model and its equations, each with the component and the line it
   came from;
2. alias elimination (which trivial equations ``a = b`` vanished);
3. structural analysis: index reduction, the states chosen, dummy derivatives;
4. the matching (which unknown each equation is solved for);
5. the block lower triangular (BLT) order and how each block is solved;
6. the generated Python code;
7. for a hybrid model, the relations watched for events, the discrete
   equations and every discrete state compiled.

It also draws the incidence matrix of each compiled system in BLT order
(``incidence_<Model>.png``, or ``incidence_<Model>_<state>.png`` per
discrete state, the state named by its modes): a square per (equation,
unknown) occurrence, the matched pairs on the diagonal, the blocks outlined,
the tearing unknowns marked.  For a simulated hybrid model only the states
the simulation visited are drawn.

With ``html=DIR`` it also writes the teaching page ``DIR/index.html``
(:mod:`acausal.tools.report_html`): the same stages with every variable
linked to where it is computed, the incidence picture of every discrete state
visited, and the event timeline of the run.

Examples
--------
>>> from examples.first import First                      # doctest: +SKIP
>>> print(explain(First(), out_dir="/tmp"))                # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import re
import textwrap
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..arrays import array_groups
from ..compiler.algebraic import Assign, LinearSolve, NewtonSolve
from ..names import parse
from ..language import Component
from ..compiler.clusters import ComposedSystem
from ..compiler.translate import ModeSystem, Translation, translate
from ..errors import AcausalError
from .report_html import (StateNamer, origin_label, solution_kind, state_file_stems, tearing_unknowns,
                          write_page)

__all__ = ["Explanation", "explain", "MAX_PICTURES"]

#: At most this many incidence pictures are drawn (one per compiled discrete state).
MAX_PICTURES = 12

_RULE = "-"
_WIDTH = 96


@dataclass(frozen=True)
class Explanation:
    """What :func:`explain` produced.

    Attributes
    ----------
    model : str
        Name of the model explained.
    text : str
        The explanation, section after section.
    pictures : tuple of Path
        The incidence pictures written, one per compiled discrete state
        (at most :data:`MAX_PICTURES`).
    page : Path or None
        The teaching page written (``explain(..., html=DIR)``), else None.
    """

    model: str
    text: str
    pictures: tuple[Path, ...] = ()
    page: Path | None = None

    def __str__(self) -> str:
        return self.text


def explain(model_or_translation: Component | Translation, out_dir: str | Path | None = None,
            key: tuple | None = None, *, html: str | Path | None = None,
            pictures: bool = True) -> Explanation:
    """Explain, stage by stage, how a model is translated.

    Parameters
    ----------
    model_or_translation : Model instance or Translation
        The model, or the result of :func:`acausal.compiler.translate.translate`
        (its already compiled systems are reused).
    out_dir : str or Path, optional
        Folder for the incidence pictures (created if missing); default: the
        current directory.
    key : tuple, optional
        The discrete state (values of ``translation.selectors``) whose system
        is explained in detail.  By default a continuous model's only system;
        for a hybrid model the first discrete state the simulation visits
        (the model is simulated first if nothing has been compiled yet).
    html : str or Path, optional
        Also write the teaching page ``html/index.html`` (created if
        missing).  The page needs a run for its event timeline and its
        discrete states: the model is simulated with its experiment if
        explain did not simulate it already.
    pictures : bool
        Draw the PNG incidence pictures into ``out_dir`` (the page has its
        own, as inline SVG).

    Returns
    -------
    Explanation
        ``str(explanation)`` is the text; ``explanation.page`` the page written.

    Raises
    ------
    acausal.errors.AcausalError
        If a stage fails (e.g. a structurally singular model), as the
        translation itself would.
    """
    translation = (model_or_translation if isinstance(model_or_translation, Translation)
                   else translate(model_or_translation, cache=False))
    # the whole model's system per discrete state (a model of independent parts is
    # simulated with one system per part; its clusters are listed below)
    clustering = translation.clustering
    translation = translation.unclustered()
    partitioned = translation.partitioned
    notes: list[str] = []
    visited: tuple[str, ...] | None = None
    result = None

    if key is not None:
        main = translation.system(tuple(key))
    elif not partitioned.is_hybrid:
        from ..runtime.events import DiscreteEvaluator

        main = translation.system(DiscreteEvaluator(translation).key({}, {}, (), False))
    else:
        if not translation.systems:
            from ..runtime.simulate import simulate

            result = simulate(translation)
            visited = tuple(result.modes)
            if not result.success:
                notes.append(f"The simulation stopped early: {result.message}")
        main = _first_visited(translation, visited)
    if html is not None and result is None:
        result = _run_for_page(translation, notes)

    out = Path.cwd() if out_dir is None else Path(out_dir)
    systems = list(translation.systems.values())
    number = {system.key: n for n, system in enumerate(systems, start=1)}
    namer = StateNamer(translation)
    state_names = {system.key: namer(system.key) for system in systems}
    if visited is not None:
        # what the run went through: the pictures a student compares
        by_description = {s.description: s for s in systems}
        candidates = [main] + [by_description[d] for d in visited if d in by_description]
    else:
        # the system explained first, then the others in the order compiled
        candidates = sorted(systems, key=lambda s: (s is not main, number[s.key]))
    # one picture per compiled system: states sharing another's system have its picture
    pictured, drawn = [], set()
    for system in candidates:
        shared = system.shares if system.shares is not None else system.key
        if shared not in drawn:
            drawn.add(shared)
            pictured.append(system)
    pictured = pictured[:MAX_PICTURES] if pictures else []
    stem = _safe(translation.flat.name)
    state_stems = dict(zip([s.key for s in pictured], state_file_stems(state_names[s.key] for s in pictured)))
    names = {}
    for system in pictured:
        names[system.key] = (f"incidence_{stem}.png" if len(systems) == 1
                             else f"incidence_{stem}_{state_stems[system.key]}.png")

    writer = _Writer()
    _write_flat(writer, translation)
    writer.paragraph(_main_intro(translation, main, names.get(main.key), state_names[main.key]))
    flat_number = _flat_numbers(translation)
    _write_aliases(writer, main, flat_number)
    _write_structure(writer, main)
    _write_matching(writer, main)
    _write_blt(writer, main)
    _write_code(writer, translation, main)
    _write_passes(writer, translation, main)
    if partitioned.is_hybrid:
        _write_hybrid(writer, translation, main, visited, names, state_names)
    if clustering is not None:
        _write_parts(writer, translation, clustering, main)
    for note in notes:
        writer.note(note)
    distinct = {s.shares if s.shares is not None else s.key for s in systems}
    if pictures and visited is not None and len(drawn) < len(distinct):
        writer.note("Incidence pictures were drawn for the discrete states the simulation visited; "
                    "the states tried during event iteration only are listed, not drawn.")
    if pictures and len(pictured) < len(drawn):
        writer.note(f"{len(drawn)} distinct systems qualified for a picture; incidence pictures were "
                    f"drawn for {MAX_PICTURES} of them only (the one explained first).")

    written = []
    if pictured:
        out.mkdir(parents=True, exist_ok=True)
    for system in pictured:
        title = translation.flat.name
        if partitioned.is_hybrid:
            title += f"\n{state_names[system.key]}"
        written.append(_draw_incidence(system, out / names[system.key], title))
    text = writer.text()
    page = None
    if html is not None:
        page = write_page(translation, main, html, result=result,
                          visited=tuple(result.modes) if result is not None else None,
                          text=text, notes=notes)
    return Explanation(translation.flat.name, text, tuple(written), page)


def _run_for_page(translation: Translation, notes: list[str]):
    """The run whose events and discrete states the page shows (None if it cannot run)."""
    from ..errors import AcausalError
    from ..runtime.simulate import simulate

    try:
        result = simulate(translation)
    except AcausalError as exc:
        notes.append(f"The simulation for the event timeline failed: {exc}")
        return None
    if not result.success:
        notes.append(f"The simulation stopped early: {result.message}")
    return result


# ---------------------------------------------------------------------------
# Choosing the system to explain
# ---------------------------------------------------------------------------


def _first_visited(translation: Translation, visited) -> ModeSystem:
    systems = list(translation.systems.values())
    if visited:
        for system in systems:
            if system.description == visited[0]:
                return system
    if not systems:  # nothing compiled, nothing visited: start from the default state
        from ..runtime.events import DiscreteEvaluator

        evaluator = DiscreteEvaluator(translation)
        variables = translation.flat.variable_map
        start = {n: variables[n].start for n in translation.partitioned.discrete_variables}
        relations = tuple(False for _ in translation.partitioned.relations)
        return translation.system(evaluator.key(start, start, relations, False))
    return systems[0]


# ---------------------------------------------------------------------------
# Text
# ---------------------------------------------------------------------------


class _Writer:
    def __init__(self) -> None:
        self.lines: list[str] = []
        self.section_number = 0

    def title(self, text: str) -> None:
        self.lines += [text, "=" * len(text), ""]

    def section(self, text: str) -> None:
        self.section_number += 1
        heading = f"{self.section_number}. {text}"
        if self.lines and self.lines[-1] != "":
            self.lines.append("")
        self.lines += [heading, _RULE * len(heading)]

    def paragraph(self, text: str) -> None:
        self.lines += textwrap.wrap(text, 88) + [""]

    def line(self, text: str = "") -> None:
        self.lines.append(text)

    def items(self, prefix: str, items, indent: int | None = None, empty: str = "none") -> None:
        """``prefix`` then the items, comma separated, wrapped with a hanging indent."""
        items = [str(i) for i in items]
        if not items:
            self.lines.append(prefix + empty)
            return
        if indent is None:
            indent = len(prefix) if len(prefix) <= 32 else len(prefix) - len(prefix.lstrip()) + 4
        self.lines += textwrap.wrap(prefix + ", ".join(items), _WIDTH, subsequent_indent=" " * indent,
                                    break_long_words=False, break_on_hyphens=False)

    def note(self, text: str) -> None:
        wrapped = textwrap.wrap(text, 82)
        if self.lines and self.lines[-1] != "":
            self.lines.append("")
        self.lines += ["Note: " + wrapped[0]] + ["      " + w for w in wrapped[1:]]

    def text(self) -> str:
        while self.lines and self.lines[-1] == "":
            self.lines.pop()
        return "\n".join(self.lines) + "\n"


def _flat_numbers(translation: Translation) -> dict:
    numbers = {}
    for k, eq in enumerate(translation.flat.equations, start=1):
        numbers.setdefault(eq.origin, k)
    return numbers


def _format_value(value: Any) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def _write_flat(w: _Writer, translation: Translation) -> None:
    flat = translation.flat
    heading = f"Explanation of {flat.name}"
    if flat.modelica_class:
        heading += f" ({flat.modelica_class})"
    w.title(heading)
    w.section("Flat model")
    w.paragraph("Flattening walks the component tree: every variable gets its dotted name, "
                "every connect() becomes equations (potentials equal, flows summing to zero) "
                "and parameters get their numeric values.  Each equation remembers the "
                "component and the equation it comes from.")
    w.line(flat.summary())
    w.line()
    if flat.parameters:
        w.line(f"Parameters ({len(flat.parameters)}):")
        by_name = {p.name: p for p in flat.parameters}
        for name, shape, members in array_groups(by_name):
            p = by_name[members[0]]
            unit = f" [{p.unit}]" if p.unit else ""
            if shape is None:
                w.line(f"  {p.name} = {_format_value(p.value)}{unit}")
            else:  # an array: one line, its size and its values
                values = np.array([_format_value(by_name[m].value) for m in members], dtype=object)
                w.line(f"  {name}[{', '.join(map(str, shape))}] = "
                       f"{str(values.reshape(shape).tolist()).replace(chr(39), '')}{unit}")
        w.line()
    fixed = [v for v in flat.variables if v.fixed]
    if fixed:
        w.line("Start values with fixed=True (initial conditions):")
        by_name = {v.name: v for v in fixed}
        for name, shape, members in array_groups(by_name):
            if shape is None:
                w.line(f"  {name} = {_format_value(by_name[name].start)}")
            else:  # an array: one line, its size and its start values
                values = np.array([_format_value(by_name[m].start) for m in members], dtype=object)
                w.line(f"  {name}[{', '.join(map(str, shape))}] = "
                       f"{str(values.reshape(shape).tolist()).replace(chr(39), '')}")
        w.line()
    width = len(str(len(flat.equations)))
    w.line(f"Flat equations ({len(flat.equations)}):")
    for k, eq in enumerate(flat.equations, start=1):
        w.line(f"  [{k:>{width}}] {eq.origin}")
    if flat.initial_equations:
        w.line()
        w.line(f"Initial equations ({len(flat.initial_equations)}), used only to find the "
               f"initial values:")
        for k, eq in enumerate(flat.initial_equations, start=1):
            w.line(f"  [I{k}] {eq.origin}")
    if flat.discrete_equations:
        w.line()
        w.line(f"Discrete equations ({len(flat.discrete_equations)}), for Boolean and Integer "
               f"variables:")
        for k, eq in enumerate(flat.discrete_equations, start=1):
            w.line("  " + textwrap.shorten(f"[D{k}] {eq.origin}", _WIDTH - 2, placeholder=" ..."))
    w.line()


def _main_intro(translation: Translation, main: ModeSystem, picture: str | None, name: str) -> str:
    text = ("The next stages turn the flat equations into a system the ODE solver can "
            "integrate: x' = f(t, x), with every other variable computed from the states x.")
    if translation.partitioned.is_hybrid:
        text += (f"  This model is hybrid (section 7): its continuous equations depend on "
                 f"discrete values, so there is one such system per discrete state.  Sections "
                 f"2-6 show the system of the discrete state "
                 f"[{_key_text(translation, main.key)}], named by its modes: {name}.")
    if picture:
        text += f"  The incidence matrix of this system is drawn in {picture}."
    return text


def _write_aliases(w: _Writer, main: ModeSystem, flat_number: dict) -> None:
    aliases = main.aliases
    w.section("Alias elimination")
    w.paragraph("Connections produce many trivial equations a = b, a = -b and a = constant.  "
                "Each group of variables joined by them keeps one representative; the others "
                "become aliases, vanish from the system and are recovered for the results.")
    n_in, n_removed = len(main.equations), len(aliases.eliminated)
    w.line(f"{n_removed} of {n_in} equations removed as alias equations; "
           f"{len(aliases.equations)} remain, for {len(aliases.variables)} variables.")
    removed = [flat_number.get(eq.origin) for eq in aliases.eliminated]
    if removed and all(r is not None for r in removed):
        w.items("Removed: ", [f"[{r}]" for r in removed])
    w.line()
    if aliases.aliases:
        width = min(max(len(n) for n in aliases.aliases), 40)
        w.line(f"Alias table ({len(aliases.aliases)} variables):")
        for name, expr in aliases.aliases.items():
            w.line(f"  {name:<{width}} = {expr}")
    else:
        w.line("No aliases.")
    w.line()


def _write_structure(w: _Writer, main: ModeSystem) -> None:
    st = main.structure
    w.section("Structural analysis")
    w.paragraph("Each equation is treated as a set of the unknowns it contains (its incidence).  "
                "A variable that appears differentiated, der(x), is a candidate state: the "
                "solver integrates it, so it counts as known.  When some equations constrain "
                "states only, Pantelides' algorithm differentiates them (index reduction) and "
                "the dummy derivative method turns as many derivatives back into ordinary "
                "algebraic unknowns, so that the remaining states are independent.")
    n_original = len(st.equations) - len(st.differentiated)
    width = len(str(len(st.equations)))
    w.line(f"System equations (E1-E{n_original} after alias elimination"
           + (f", E{n_original + 1}-E{len(st.equations)} added by index reduction):"
              if st.differentiated else "):"))
    for i, eq in enumerate(st.equations):
        w.line(f"  E{i + 1:<{width}} {eq.origin}")
        w.line(f"   {'':<{width}}   0 = {eq.residual}")
    w.line()
    if st.differentiated:
        w.line(f"Index reduction: {len(st.differentiated)} equations added by differentiation:")
        for i, k in st.differentiated:
            w.line(f"  E{i + 1} = d/dt E{k + 1}")
    else:
        w.line("Index reduction: not needed (index 1 or lower); no equation differentiated.")
    w.line()
    w.items(f"States chosen ({len(st.states)}): ", st.states,
            empty="none (a purely algebraic system)")
    w.items("Their derivatives, computed by the system: ", st.derivatives, empty="-")
    w.items(f"Dummy derivatives ({len(st.dummy_derivatives)}, solved as algebraic unknowns): ",
            st.dummy_derivatives)
    w.items(f"Unknowns computed at each evaluation ({len(st.unknowns)}): ", st.unknowns)
    w.line()


def _write_matching(w: _Writer, main: ModeSystem) -> None:
    st = main.structure
    w.section("Matching")
    w.paragraph("Every equation is assigned the unknown it will be solved for, each unknown "
                "exactly once (a perfect matching of the bipartite equation-unknown graph).  "
                "This is where the equations get their causality.")
    width = len(str(len(st.equations))) + 1
    for i, j in enumerate(st.matching):
        w.line(f"  {'E' + str(i + 1):<{width}} -> {st.unknowns[j]}")
    w.line()


#: How a block is solved, in words (shared with the page).
_step_kind = solution_kind


def _write_blt(w: _Writer, main: ModeSystem) -> None:
    st, blt, alg = main.structure, main.blt, main.algebraic
    w.section("BLT: block lower triangular order")
    w.paragraph("With each equation matched, equation A must come after equation B when it "
                "uses the unknown B solves.  The strongly connected parts of that dependency "
                "graph are the blocks (algebraic loops where larger than one equation); in "
                "this order each block only needs unknowns computed before it.  A block of "
                "one equation is solved explicitly; a larger one is torn: the tearing "
                "unknowns are guessed, the other equations solved in turn, and what is left "
                "is a small linear solve or Newton's method.")
    sizes = [b.size for b in blt.blocks]
    w.line(f"{len(blt.blocks)} blocks; largest {blt.largest_block}; "
           f"{sum(s == 1 for s in sizes)} of size one; {alg.linear_blocks} torn linear, "
           f"{alg.nonlinear_blocks} nonlinear (Newton).")
    w.line()
    width = len(str(len(blt.blocks)))
    steps = alg.steps if len(alg.steps) == len(blt.blocks) else [None] * len(blt.blocks)
    for n, (block, step) in enumerate(zip(blt.blocks, steps), start=1):
        eqs = ", ".join(f"E{i + 1}" for i in block.equations)
        unknowns = [st.unknowns[j] for j in block.unknowns]
        kind = _step_kind(step) if step is not None else "?"
        label = f"  B{n:<{width}} "
        if isinstance(step, Assign):
            w.line(f"{label}{kind:<12} {eqs}: {step.variable} := {step.expression}")
            continue
        w.line(f"{label}{kind:<12} size {block.size}: {eqs}")
        pad = " " * (len(label) + 13)
        w.items(pad + "unknowns: ", unknowns)
        if isinstance(step, (LinearSolve, NewtonSolve)) and block.size > 1:
            w.items(pad + "tearing unknowns: ", step.tears)
            if step.inner:
                w.items(pad + "then solved in turn: ", [a.variable for a in step.inner])
    w.line()


def _write_code(w: _Writer, translation: Translation, main: ModeSystem) -> None:
    st = main.structure
    w.section("Generated code")
    w.paragraph("The solution steps become straight-line Python: derivatives(t, x) is what "
                "the ODE solver calls, crossings(t, x) gives the sides of the relations "
                "watched for events, outputs(t, x) every unknown for the results.  Names: "
                "xK is states[K], vK is unknowns[K], pK is parameter K:")
    for k, name in enumerate(st.states):
        w.line(f"  x{k} = {name}")
    for k, name in enumerate(st.unknowns):
        w.line(f"  v{k} = {name}")
    for k, name in enumerate(translation.parameter_names):
        w.line(f"  p{k} = {name}")
    w.line()
    w.lines += ["    " + line if line else "" for line in main.code.source.rstrip("\n").split("\n")]
    w.line()


#: At most this many independent parts are listed one by one.
MAX_PARTS_LISTED = 12


def _write_parts(w: _Writer, translation: Translation, clustering, main: ModeSystem) -> None:
    """The independent parts, each compiled for the discrete state explained."""
    w.section("Independent parts")
    w.paragraph(f"The continuous equations fall into {len(clustering.clusters)} parts that share no "
                "variable (connected components of the incidence over every discrete state; parts "
                "without discrete variables join the first one that has some).  A simulation "
                "compiles one system per part and per discrete state of that part, and puts them "
                "together: the sections above show the whole model's system, which is the same "
                "computation in one piece.  Each part in the discrete state explained:")
    # every part compiled for itself (not renamed from an equal part), so that its stages show
    parts = Translation(translation.flat, translation.partitioned, translation.flatten_seconds,
                        translation.demand, clustering=clustering, disk=False,
                        options=dataclasses.replace(translation.options, part_shapes=False))
    for cluster in clustering.clusters[:MAX_PARTS_LISTED]:
        system = parts._part(cluster, main.key)
        st, blt, alg = system.structure, system.blt, system.algebraic
        owners = list(dict.fromkeys(v.rpartition(".")[0] for v in cluster.variables))
        w.line(f"  part {cluster.index + 1}: {len(cluster.equations)} equations, "
               f"{len(cluster.variables)} variables, {len(cluster.selectors)} discrete symbols, "
               f"{len(cluster.relations)} relations")
        w.items("      components: ", owners[:10] + (["..."] if len(owners) > 10 else []))
        w.items("      states: ", st.states)
        w.line(f"      {len(blt.blocks)} BLT blocks, largest {blt.largest_block}; "
               f"{alg.linear_blocks} torn linear, {alg.nonlinear_blocks} nonlinear")
        w.items("      this state: ", system.description.split(", "))
    if len(clustering.clusters) > MAX_PARTS_LISTED:
        w.line(f"  ... and {len(clustering.clusters) - MAX_PARTS_LISTED} more parts")
    w.line()


def _write_passes(w: _Writer, translation: Translation, main: ModeSystem) -> None:
    w.section("Pass log")
    w.paragraph("Every compiled system keeps the passes that built it, in order, with the time "
                "each took (flattening and partitioning are done once for the whole model).")
    w.line(f"  {'flatten + partition (once)':<28} {1e3 * translation.flatten_seconds:9.2f} ms")
    for name, seconds in main.passes:
        w.line(f"  {name:<28} {1e3 * seconds:9.2f} ms")
    if main.shares is not None:
        twin = translation.systems[main.shares]
        w.line("  (equal equations to a state compiled before: specialising was all; that state's "
               "passes:)")
        for name, seconds in twin.passes:
            w.line(f"    {name:<26} {1e3 * seconds:9.2f} ms")
    initial = translation.initial_systems.get(main.key)
    if initial is None and not isinstance(main, ComposedSystem):
        try:  # compiled here if no run has needed it: what initialization will do is part of the story
            initial = translation.initial_system(main.key)
        except AcausalError:
            initial = None
    if initial is not None:
        w.line("  initialization problem:")
        for name, seconds in initial.passes:
            w.line(f"    {name:<26} {1e3 * seconds:9.2f} ms")
        if getattr(initial, "from_start", ()):
            # Modelica tools complete an under-determined initial problem from start values
            w.line("  states without fixed=True that start from their start values (nothing "
                   "else determines them):")
            for name, value in initial.from_start:
                w.line(f"    {name} = {_format_value(value)}")
    w.line()


def _write_hybrid(w: _Writer, translation: Translation, main: ModeSystem, visited,
                  pictures: dict, state_names: dict) -> None:
    partitioned = translation.partitioned
    w.section("Hybrid part: relations, discrete equations, discrete states")
    w.paragraph("Relations on continuous quantities become Booleans that keep their value "
                "between events; the solver watches each one's two sides for a crossing "
                "(state event), or computes in advance when it flips (time event).  At an "
                "event the discrete equations are evaluated (event iteration) and a new "
                "discrete state may select other continuous equations.")
    if partitioned.relations:
        w.line(f"Relations watched ({len(partitioned.relations)}):")
        for rel in partitioned.relations:
            kind = "time event" if rel.is_time_event else "state event"
            w.line(f"  {rel.symbol.name}: {rel.text}   ({kind})")
    else:
        w.line("Relations watched: none")
    w.line()
    if partitioned.discrete_equations:
        w.line(f"Discrete equations ({len(partitioned.discrete_equations)}), in evaluation order "
               f"($relK is relation K):")
        for eq in partitioned.discrete_equations:
            w.line(f"  {eq.variable} := {eq.rhs}")
            w.line("      " + textwrap.shorten(f"from {eq.origin}", _WIDTH - 6, placeholder=" ..."))
    else:
        w.line("Discrete equations: none")
    w.line()
    _write_when_clauses(w, translation)
    w.items("A discrete state is the values of: ",
            [_selector_text(translation, s) for s in translation.selectors], empty="(nothing)")
    if visited is not None:
        w.note("explain simulated the model first (simulate(translation) with the experiment "
               "settings), because the system of a discrete state is only built when the state "
               "is reached.  The compiled states below are those the simulation reached or "
               "tried during event iteration.")
        w.line()
        w.line(f"Discrete states visited by the simulation ({len(visited)}, named by their modes, "
               f"then as result.modes names them):")
        named = {s.description: state_names[s.key] for s in translation.systems.values()}
        for d in visited:
            if d in named:
                w.lines += textwrap.wrap(named[d], _WIDTH, initial_indent="  - ", subsequent_indent="    ")
            w.lines += textwrap.wrap(d, _WIDTH, initial_indent="    ", subsequent_indent="      ")
    w.line()
    systems = list(translation.systems.values())
    state_number = {system.key: n for n, system in enumerate(systems, start=1)}
    w.line(f"Discrete states compiled ({len(systems)}, {translation.compiled_systems} distinct "
           f"systems):")
    for n, system in enumerate(systems, start=1):
        w.line()
        marks = []
        if visited is not None:
            marks.append("visited" if system.description in visited
                         else "tried during event iteration only")
        if system is main:
            marks.append("explained in sections 2-6")
        w.items(f"  State {n}: ", [state_names[system.key]], indent=6)
        w.items("    values: ", [_key_text(translation, system.key)], indent=6)
        if marks:
            w.line(f"    ({'; '.join(marks)})")
        if system.shares is not None and system is not main:
            w.line(f"    the same equations as state {state_number[system.shares]}: its compiled "
                   f"system serves both")
            continue
        st = system.structure
        w.line(f"    {len(system.aliases.equations)} equations after alias elimination, "
               f"{len(st.differentiated)} added by index reduction")
        w.items("    states: ", st.states)
        if st.dummy_derivatives:
            w.items("    dummy derivatives: ", st.dummy_derivatives)
        if system.key in pictures:
            w.line(f"    picture: {pictures[system.key]}")
        blocks = system.blt.blocks
        w.line(f"    BLT: {len(blocks)} blocks, largest {system.blt.largest_block}"
               + ("; see section 5" if system is main else ":"))
        if system is main:
            continue
        steps = system.algebraic.steps
        if len(steps) != len(blocks):
            steps = [None] * len(blocks)
        run: list[tuple[int, str]] = []

        def flush() -> None:
            if run:
                first, last = run[0][0], run[-1][0]
                label = f"B{first}" if first == last else f"B{first}-B{last}"
                w.items(f"      {label} explicit: ", [name for _, name in run], indent=8)
                run.clear()

        for b, (block, step) in enumerate(zip(blocks, steps), start=1):
            unknowns = [st.unknowns[j] for j in block.unknowns]
            if isinstance(step, Assign):
                run.append((b, unknowns[0]))
                continue
            flush()
            kind = _step_kind(step) if step is not None else "?"
            w.items(f"      B{b} {kind}, size {block.size}: ", unknowns, indent=8)
            if isinstance(step, (LinearSolve, NewtonSolve)) and block.size > 1:
                w.items("        tearing: ", step.tears)
        flush()


def _readable(translation: Translation, expr) -> str:
    """An expression with each relation indicator $relK written as its relation."""
    import sympy as sp

    relations = {rel.symbol: sp.Symbol(f"({rel.text})") for rel in translation.partitioned.relations}
    return str(sp.sympify(expr).xreplace(relations)) if relations else str(expr)


def _write_when_clauses(w: _Writer, translation: Translation) -> None:
    """The when-clauses, reinits, sample clocks, held Reals and assertions of a hybrid model."""
    partitioned = translation.partitioned
    hybrid = translation.flat.hybrid
    clauses = [eq for eq in partitioned.discrete_equations if parse(str(eq.variable)).text.split(".")[-1]
               .startswith("$when")]
    if not (clauses or partitioned.clocks or hybrid):
        return
    w.paragraph(f"When-clauses ({len(clauses)}): each condition is a hidden Boolean $whenK; the "
                f"clause acts at the event where it becomes true (fires = $whenK and not "
                f"pre($whenK) and not initial()).  Between events the variables it assigns keep "
                f"their values; its reinits are applied after the event iteration has converged, "
                f"then the iteration runs again.")
    for eq in clauses:
        symbol = str(eq.variable)
        w.line(f"  {symbol} = {_readable(translation, eq.rhs)}")
        assigned = [str(other.variable) for other in partitioned.discrete_equations
                    if other is not eq and symbol in _names_in(other.rhs)]
        if assigned:
            w.items("      assigns: ", assigned, indent=8)
        for reinit in hybrid.reinits:
            if symbol in _names_in(reinit.fires):
                w.lines += textwrap.wrap(f"reinit({reinit.variable}, {_readable(translation, reinit.value)})",
                                         _WIDTH, initial_indent="      ", subsequent_indent="        ")
        for termination in hybrid.terminations:
            if symbol in _names_in(termination.fires):
                w.line(f"      terminate({termination.message!r})")
        w.lines += textwrap.wrap(f"from {eq.origin.component or '(model)'} "
                                 f"({eq.origin.declared_in} eq. {eq.origin.index + 1})",
                                 _WIDTH, initial_indent="      ", subsequent_indent="        ")
    if partitioned.clocks:
        w.line("Sample clocks (exact time events at start + i*interval, i = 0, 1, ...):")
        for clock in partitioned.clocks:
            w.line(f"  {clock.symbol.name} = sample({_number_or_text(clock.start)}, "
                   f"{_number_or_text(clock.interval)})")
    if partitioned.held_variables:
        w.items("Discrete Reals (held between events: der = 0, set by the event iteration): ",
                partitioned.held_variables, indent=4)
    for check in hybrid.asserts:
        when = "at events where it is active" if check.fires is not None else "after every step and event"
        w.lines += textwrap.wrap(f"assert({_readable(translation, check.condition)}, {check.message!r}, "
                                 f"level={check.level}): checked {when}",
                                 _WIDTH, initial_indent="  ", subsequent_indent="      ")
    w.line()


def _number_or_text(expr) -> str:
    return f"{float(expr):g}" if getattr(expr, "is_number", False) else str(expr)


def _names_in(expr) -> set[str]:
    """The names of the free symbols of a sympy expression (empty for numbers and None)."""
    return {str(sym) for sym in getattr(expr, "free_symbols", ())}


def _selector_text(translation: Translation, sym) -> str:
    name = parse(sym.name)
    if name.kind == "relation":
        return f"({translation.partitioned.relations[name.index].text})"
    return name.text


def _key_text(translation: Translation, key: tuple) -> str:
    """Every selector with its value, relations spelled out."""
    variables = translation.flat.variable_map
    parts = []
    for sym, value in zip(translation.selectors, key):
        name = parse(sym.name)
        var = variables.get(name.base)
        if name.kind in ("relation", "initial") or (var is not None and var.kind == "boolean"):
            value = bool(value)
        elif var is not None and var.kind == "integer":
            value = int(value)
        parts.append(f"{_selector_text(translation, sym)}={value}")
    return ", ".join(parts) or "(continuous)"


def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name) or "model"


# ---------------------------------------------------------------------------
# The picture
# ---------------------------------------------------------------------------

_KIND_COLOURS = {"explicit": "tab:blue", "torn linear": "tab:orange", "Newton": "tab:red",
                 "torn nonlinear (Newton)": "tab:red"}
_TEAR_COLOUR = "#c2185b"

#: Size of the picture's labels in points, and the width of one character in inches
#: (monospace-like estimate: the margins are computed, not measured, because
#: measuring every label for a tight bounding box doubled the drawing time).
_FONT_MAX = 8.0
_CHAR_INCHES = 0.62 / 72.0


def _draw_incidence(system: ModeSystem, path: Path, title: str) -> Path:
    """Draw the incidence matrix of ``system`` in BLT order into a PNG file.

    Rows are the equations in BLT order, labelled with the component and
    equation they come from; columns the unknowns they are matched to (so
    the matched pairs lie on the diagonal); each block is outlined in the
    colour of how it is solved; the tearing unknowns' labels are magenta
    with a dagger and their columns shaded.
    """
    # The Agg canvas draws straight to a file: no display and no change to
    # pyplot's global backend (which matplotlib.use("Agg") would make).
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Rectangle

    st, blt = system.structure, system.blt
    rows = blt.equation_order
    cols = blt.unknown_order
    n = len(rows)
    tears = tearing_unknowns(system)
    position = {j: k for k, j in enumerate(cols)}
    grid = min(max(3.0, 0.16 * n), 36.0)
    font = max(3.0, min(_FONT_MAX, 420.0 / max(n, 1)))
    row_labels = [f"E{i + 1} {origin_label(st.equations[i].origin)}" for i in rows]
    col_labels = [st.unknowns[j] + (" \u2020" if st.unknowns[j] in tears else "") for j in cols]
    wrap = max(40, int(grid * 13))
    title_lines = [part for line in title.split("\n")
                   for part in (textwrap.wrap(line, wrap, break_on_hyphens=False) or [""])]
    left = 0.25 + font * _CHAR_INCHES * max((len(t) for t in row_labels), default=4)
    top = 0.35 + font * _CHAR_INCHES * max((len(t) for t in col_labels), default=4) + 0.17 * len(title_lines)
    bottom, right = 0.45, 0.25
    width, height = left + grid + right, top + grid + bottom
    figure = Figure(figsize=(width, height))
    FigureCanvasAgg(figure)
    axes = figure.add_axes((left / width, bottom / height, grid / width, grid / height))
    figure.text(0.5, 1 - 0.08 / height, "\n".join(title_lines), ha="center", va="top", fontsize=9)
    if n == 0:
        axes.text(0.5, 0.5, "no unknowns to solve", ha="center", va="center")
        axes.set_axis_off()
    else:
        for k, j in enumerate(cols):
            if st.unknowns[j] in tears:
                axes.axvspan(k - 0.5, k + 0.5, color=_TEAR_COLOUR, alpha=0.12, linewidth=0)
        xs, ys, mx, my = [], [], [], []
        for r, i in enumerate(rows):
            for j in st.incidence[i]:
                c = position[j]
                if j == st.matching[i]:
                    mx.append(c)
                    my.append(r)
                else:
                    xs.append(c)
                    ys.append(r)
        marker = (0.6 * 72.0 * grid / n) ** 2
        axes.scatter(xs, ys, s=marker, marker="s", color="0.55", linewidths=0)
        axes.scatter(mx, my, s=marker, marker="s", color="black", linewidths=0)
        steps = system.algebraic.steps
        if len(steps) != len(blt.blocks):
            steps = [None] * len(blt.blocks)
        start = 0
        kinds_used = {}
        for block, step in zip(blt.blocks, steps):
            kind = _step_kind(step) if step is not None else "explicit"
            colour = _KIND_COLOURS.get(kind, "tab:purple")
            kinds_used.setdefault(kind, colour)
            axes.add_patch(Rectangle((start - 0.5, start - 0.5), block.size, block.size,
                                     fill=False, edgecolor=colour,
                                     linewidth=0.6 if block.size == 1 else 1.6, clip_on=False))
            start += block.size
        axes.set_xlim(-0.5, n - 0.5)
        axes.set_ylim(n - 0.5, -0.5)
        # labels as plain texts, not tick labels: matplotlib builds a Tick (two
        # lines, two texts) per tick and measures them all, which was most of the time
        axes.set_xticks([])
        axes.set_yticks([])
        for k, (label, j) in enumerate(zip(col_labels, cols)):
            torn = st.unknowns[j] in tears
            axes.text(k, -0.8, label, rotation=90, ha="center", va="bottom", fontsize=font,
                      color=_TEAR_COLOUR if torn else "black", fontweight="bold" if torn else "normal",
                      clip_on=False)
        for r, label in enumerate(row_labels):
            axes.text(-0.8, r, label, ha="right", va="center", fontsize=font, clip_on=False)
        handles = [Line2D([], [], marker="s", color="black", linestyle="", label="matched (solved for)"),
                   Line2D([], [], marker="s", color="0.55", linestyle="", label="occurs")]
        handles += [Line2D([], [], color=c, label=f"block: {k}") for k, c in kinds_used.items()]
        if tears:
            handles.append(Line2D([], [], marker="s", color=_TEAR_COLOUR, alpha=0.4, linestyle="",
                                  label="\u2020 tearing unknown"))
        axes.legend(handles=handles, loc="upper right", fontsize=7, framealpha=0.9)
        figure.text(0.5, 0.12 / height, "rows: equations in BLT order (component, equation); "
                    "columns: unknowns in the order they are solved", ha="center", va="bottom", fontsize=7)
    path = Path(path)
    figure.savefig(path, dpi=100)
    return path
