"""Tests of the teaching page: ``explain(..., html=DIR)`` writes a self-contained DIR/index.html.

The page is read back with :mod:`html.parser` (well-formed, ids unique,
every in-page link resolves, nothing loaded from outside), and compared with
what the translation and a simulation of the same model say: the discrete
states visited named by their modes, the generated code, the event times,
the tearing unknowns.  A last test opens the page in a real headless
browser when one is installed.
"""

from __future__ import annotations

import html
import re
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import pytest

from acausal import simulate, translate
from acausal.compiler.algebraic import LinearSolve, NewtonSolve
from acausal.tools.explain import explain
from acausal.tools.report_html import StateNamer, anchor_id, state_file_stems
from examples.coupled_clutches import CoupledClutches
from examples.two_masses import TwoMasses

#: The sections every page has (element ids), in order.
SECTIONS = ("flat", "aliases", "structure", "matching", "blt", "code", "states", "events")

#: Elements that have no end tag in HTML.
VOID = frozenset({"meta", "br", "hr", "img", "input", "link", "wbr"})


class PageReader(HTMLParser):
    """Collects ids, in-page links, external references and nesting errors of a page."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.ids: list[str] = []
        self.links: list[str] = []
        self.external: list[str] = []
        self.tags: list[str] = []
        self.open: list[str] = []
        self.errors: list[str] = []

    def _attributes(self, tag: str, attrs) -> None:
        self.tags.append(tag)
        values = dict(attrs)
        if "id" in values:
            self.ids.append(values["id"])
        href = values.get("href")
        if href is not None:
            (self.links.append(href[1:]) if href.startswith("#") else self.external.append(href))
        if "src" in values:
            self.external.append(values["src"])

    def handle_starttag(self, tag, attrs):
        self._attributes(tag, attrs)
        if tag not in VOID:
            self.open.append(tag)

    def handle_startendtag(self, tag, attrs):  # <rect .../> in the SVG
        self._attributes(tag, attrs)

    def handle_endtag(self, tag):
        if not self.open or self.open[-1] != tag:
            self.errors.append(f"</{tag}> closes <{self.open[-1] if self.open else 'nothing'}>")
        else:
            self.open.pop()


def read_page(text: str) -> PageReader:
    reader = PageReader()
    reader.feed(text)
    reader.close()
    return reader


@pytest.fixture(scope="module")
def clutches(tmp_path_factory):
    """CoupledClutches explained with its page and pictures, and a run of the same model."""
    out = tmp_path_factory.mktemp("clutches")
    translation = translate(CoupledClutches(), cache=False)  # its own: no states visited by other tests
    explanation = explain(translation, out_dir=out / "pictures", html=out / "page")
    return explanation, translation, simulate(CoupledClutches())


@pytest.fixture(scope="module")
def page_text(clutches) -> str:
    explanation, _, _ = clutches
    return explanation.page.read_text(encoding="utf-8")


def main_system(clutches):
    """The system explained in sections 2-6: the first state the run visits."""
    _, translation, result = clutches
    return next(s for s in translation.systems.values() if s.description == result.modes[0])


def test_page_is_written_well_formed_and_self_contained(clutches, page_text):
    explanation, _, _ = clutches
    assert explanation.page.name == "index.html" and explanation.page.is_file()
    assert page_text.startswith("<!DOCTYPE html>")
    reader = read_page(page_text)
    assert not reader.errors, reader.errors[:5]
    assert not reader.open, f"elements left open: {reader.open}"
    assert len(reader.ids) == len(set(reader.ids)), "ids repeat"
    unresolved = sorted(set(reader.links) - set(reader.ids))
    assert not unresolved, f"links to no element: {unresolved[:10]}"
    # nothing fetched from elsewhere: no script, style sheet, image file or link out
    assert not reader.external, reader.external[:5]
    assert not {"script", "link", "img", "iframe"} & set(reader.tags)
    assert "svg" in reader.tags
    positions = [reader.ids.index(section) for section in SECTIONS]
    assert positions == sorted(positions)


def test_every_variable_has_an_anchor_where_it_is_computed(clutches, page_text):
    explanation, translation, _ = clutches
    ids = set(read_page(page_text).ids)
    assert 'id="var-J1.w"' in page_text  # a state: listed with the derivative it comes from
    assert anchor_id("var", "der(J1.w)") == "var-der~28J1.w~29"
    system = main_system(clutches)
    for name in (*system.structure.unknowns, *system.structure.states, *system.aliases.aliases):
        assert anchor_id("var", name) in ids, name
    for parameter in translation.flat.parameters:
        assert anchor_id("var", parameter.name) in ids
    # an unknown's anchor sits in the BLT block that solves it
    blt = page_text[page_text.index('id="blt"'):page_text.index('id="code"')]
    for name in system.structure.unknowns:
        assert f'id="{anchor_id("var", name)}"' in blt


def test_visited_states_are_named_by_their_modes(clutches, page_text):
    _, translation, result = clutches
    states = page_text[page_text.index('id="states"'):page_text.index('id="events"')]
    heading = r'<section class="state" id="[^"]+"><h3>([^<]+)</h3>'
    titles = [html.unescape(t) for t in re.findall(heading, states)]
    assert len(titles) == len(set(result.modes)) == len(set(titles))
    mode = re.compile(r"clutch[123]: (Stuck|Forward|Backward|Free|Unknown)")
    for title in titles:
        assert [m.group(0)[:7] for m in mode.finditer(title)] == ["clutch1", "clutch2", "clutch3"], title
        assert "=" not in title and "pre(" not in title  # no raw discrete-state tuple
    # clutch 1 frees at 1.25 s while clutches 2 and 3 are locked: the last state of the run
    assert titles[-1] == "clutch1: Free (free), clutch2: Stuck (locked), clutch3: Stuck (locked)"
    # the raw values stay one click away
    assert html.escape(result.modes[0]) in states


def test_pictures_are_named_by_their_discrete_state(clutches):
    explanation, _, result = clutches
    names = [p.name for p in explanation.pictures]
    assert names and all(re.fullmatch(r"incidence_CoupledClutches_clutch1-\S+\.png", n) for n in names)
    assert not any(re.search(r"_\d+\.png$", n) for n in names)
    last = "clutch1-Free-free_clutch2-Stuck-locked_clutch3-Stuck-locked"
    assert f"incidence_CoupledClutches_{last}.png" in names
    assert len(names) <= len(set(result.modes))


def test_generated_code_is_on_the_page(clutches, page_text):
    explanation, translation, _ = clutches
    code = page_text[page_text.index('id="code"'):]
    source = main_system(clutches).code.source
    assert html.escape(source, quote=True) in code
    assert "def derivatives(t, x):" in html.unescape(code)


def test_event_timeline_has_the_events_of_the_run(clutches, page_text):
    _, _, result = clutches
    timeline = page_text[page_text.index('id="events"'):]
    times = [float(t) for t in re.findall(r'<tr class="event" data-time="([^"]+)"', timeline)]
    assert times == pytest.approx([float(e.time) for e in result.events], rel=1e-9, abs=1e-12)
    # what changed, with the modes by name: clutch 2 starts sliding backward at 0.4 s
    row = next(r for r in timeline.split("<tr")[1:] if 'data-time="0.4"' in r)
    assert "clutch2.mode</code></a>: Free (2) \u2192 Backward (-1)" in row
    assert "clutch2.free</code></a>: true \u2192 false" in row


def torn_blocks(system):
    return [step for block, step in zip(system.blt.blocks, system.algebraic.steps)
            if isinstance(step, (LinearSolve, NewtonSolve)) and block.size > 1]


def test_tearing_unknowns_are_marked(clutches, page_text):
    _, translation, result = clutches
    by_description = {s.description: s for s in translation.systems.values()}
    sections = page_text.split('<section class="state"')[1:]
    checked = 0
    for description in dict.fromkeys(result.modes):
        system = by_description[description]
        section = next(s for s in sections if html.escape(description) in s)
        prefix = re.match(r' id="([^"]+)"', section).group(1) + "-"  # the state's own anchors
        if system is main_system(clutches):  # its blocks are in the BLT section
            section = page_text[page_text.index('id="blt"'):page_text.index('id="code"')]
            prefix = ""
        elif "its compiled system serves both" in section:
            continue
        for step in torn_blocks(system):
            for name in step.tears:
                assert (f'<code id="{prefix}{anchor_id("var", name)}" class="tear" '
                        f'title="tearing unknown">') in section
                assert f"{html.escape(name)} \u2020</text>" in section  # the picture's column label
                checked += 1
    assert checked, "CoupledClutches should have torn blocks in the states it visits"


def test_continuous_model_page(tmp_path):
    explanation = explain(TwoMasses(), html=tmp_path / "page", pictures=False)
    assert explanation.pictures == () and not list(tmp_path.glob("*.png"))
    text = explanation.page.read_text(encoding="utf-8")
    reader = read_page(text)
    assert not reader.errors and not set(reader.links) - set(reader.ids)
    assert set(SECTIONS) <= set(reader.ids) and "hybrid" not in reader.ids
    assert "(continuous)" in text


def test_state_names_are_generic(clutches):
    _, translation, _ = clutches
    namer = StateNamer(translation)
    key = next(iter(translation.systems))
    assert namer(key) == namer(key)
    assert namer.value_text("clutch1.mode", 0) == "Stuck (0)"
    assert namer.value_text("clutch1.mode", 7) == "7"  # no constant of that value
    assert namer.value_text("clutch1.locked", True) == "true"
    stems = state_file_stems(["a: Stuck, b: Free (free)", "a: Stuck, b: Free (free)", "x" * 300])
    assert stems[0] == "a-Stuck_b-Free-free" and stems[1] == "a-Stuck_b-Free-free_2"
    assert len(stems[2]) < 120 and len(set(stems)) == 3


BROWSERS = ("chromium", "chromium-browser", "google-chrome")


def test_page_renders_in_a_headless_browser(clutches):
    browser = next((found for name in BROWSERS if (found := shutil.which(name))), None)
    if browser is None:
        pytest.skip("no headless browser installed (apt install chromium)")
    explanation, _, _ = clutches
    done = subprocess.run([browser, "--headless", "--disable-gpu", "--no-sandbox", "--dump-dom",
                           Path(explanation.page).resolve().as_uri()],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    dom = read_page(done.stdout)
    assert set(SECTIONS) <= set(dom.ids), "sections missing from the rendered page"
    assert dom.links and not set(dom.links) - set(dom.ids), "links that do not resolve in the browser"
    assert "svg" in dom.tags


def test_the_command_line_writes_the_page(tmp_path, capsys):
    from pathlib import Path

    from acausal.tools.cli import main

    first = Path(__file__).resolve().parents[2] / "examples" / "first.py"
    page_dir = tmp_path / "page"
    assert main(["explain", str(first), "--html", str(page_dir)]) == 0
    out = capsys.readouterr().out
    assert f"wrote {page_dir / 'index.html'}" in out
    assert (page_dir / "index.html").read_text().lstrip().lower().startswith("<!doctype html")
    assert not list(tmp_path.glob("*.png"))  # --html alone: the pictures are in the page
