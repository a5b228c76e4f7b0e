"""Tests that guard the architecture of the ``acausal`` package.

The engine is layered; dependencies point one way only::

    language  →  compiler  →  runtime  →  tools

(``acausal/language.py``, ``errors.py``, ``tables.py``, ``names.py`` … the
top-level modules form the language layer; ``acausal/compiler/``,
``acausal/runtime/`` and ``acausal/tools/`` the others.)  A module may import
from its own layer and the layers before it, never after.  Every import is
counted, including the lazy ones inside functions: a lazy import still is a
dependency, it only hides it.  The façade ``acausal/__init__.py`` and
``acausal/__main__.py`` are exempt from the direction rule.

The engine has no domain knowledge: nothing under ``acausal/`` imports the
model libraries (``acausal.library``, ``acausal.components``, which install
from the repository folders ``library/`` and ``components/``), and its
messages name no mechanical or thermal concept.

The import graph is read from the source with :mod:`ast`, nothing is
imported, so a broken module cannot hide an edge.
"""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import networkx as nx
import pytest

PACKAGE = "acausal"
PACKAGE_DIR = Path(__file__).resolve().parents[1] / PACKAGE
REPO_ROOT = PACKAGE_DIR.parent

#: The layers in dependency order: a module may import from its own layer and
#: the layers with a smaller number.  A subpackage ``acausal/<name>/`` is the
#: layer ``<name>``; the top-level modules ``acausal/<module>.py`` are
#: :data:`TOP_LEVEL_LAYER`.  A new layer is one line here.
LAYERS: dict[str, int] = {
    "language": 0,
    "compiler": 1,
    "runtime": 2,
    "tools": 3,
    # Modelica text in and out: a tool beside the others (it reads the library catalogue,
    # the command line reads FILE.mo through it)
    "modelica": 3,
}
TOP_LEVEL_LAYER = "language"

#: Modules that may import from any layer (the public API façade and ``python -m acausal``).
EXEMPT_FROM_DIRECTION = frozenset({PACKAGE, f"{PACKAGE}.__main__"})

#: The model libraries built on the engine; the engine never imports them.  The
#: bare names are the repository folders the libraries are installed from: an
#: import of those would pick up whatever ``library``/``components`` package
#: happens to be first on ``sys.path`` (a user's own, say).
DOMAIN_PACKAGES = (f"{PACKAGE}.library", f"{PACKAGE}.components", "library", "components")

#: Words of the model libraries' domains that the engine's messages must not use.
DOMAIN_WORDS = ("friction", "clutch", "inertia", "torque", "bearing", "brake", "gear", "flange",
                "rotational", "translational", "thermal", "heat")

#: Files whose strings are data, not messages: compare.py reads the Modelica
#: Association's reference results, which are named by Modelica class names.
DOMAIN_WORDS_EXEMPT_FILES = frozenset({PACKAGE_DIR / "tools" / "compare.py"})


# ---------------------------------------------------------------------------
# Reading the package
# ---------------------------------------------------------------------------

def _source_files() -> list[Path]:
    return sorted(p for p in PACKAGE_DIR.rglob("*.py") if "__pycache__" not in p.parts)


def _module_name(path: Path) -> str:
    """``acausal/compiler/flatten.py`` → ``acausal.compiler.flatten``; a package's ``__init__`` → the package."""
    parts = list(path.relative_to(PACKAGE_DIR.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _rel(path: Path) -> str:
    return path.relative_to(REPO_ROOT).as_posix()


@dataclass(frozen=True)
class ImportSite:
    """One import statement: who imports what, where."""

    importer: str
    imported: str
    file: str
    line: int
    lazy: bool  # inside a function

    def where(self) -> str:
        return f"{self.file}:{self.line}{' (lazy, in a function)' if self.lazy else ''}"


def _lazy_import_nodes(tree: ast.AST) -> set[int]:
    """The ids of the import nodes that sit inside a function body."""
    inside: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            for sub in ast.walk(node):
                if isinstance(sub, (ast.Import, ast.ImportFrom)):
                    inside.add(id(sub))
    return inside


def _resolve(node: ast.ImportFrom | ast.Import, importer: str, is_package: bool,
             modules: set[str]) -> list[str]:
    """The module names one import statement imports (absolute, dotted)."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]

    if node.level:
        # The package the relative import counts from: the module's own package
        # (for a package's __init__, the package itself), then one up per extra dot.
        package = importer.split(".") if is_package else importer.split(".")[:-1]
        up = node.level - 1
        if up > len(package) - 1:
            raise AssertionError(f"{importer}: relative import beyond the top-level package "
                                 f"(level {node.level}) at line {node.lineno}")
        base_parts = package[: len(package) - up]
        if node.module:
            base_parts = base_parts + node.module.split(".")
        base = ".".join(base_parts)
    else:
        base = node.module or ""

    # ``from pkg import name``: a submodule if pkg.name is one, else an attribute of pkg.
    targets = []
    for alias in node.names:
        candidate = f"{base}.{alias.name}"
        if alias.name != "*" and not _is_domain(base) and (candidate in modules or _is_domain(candidate)):
            targets.append(candidate)
        else:
            targets.append(base)
    return targets


def _is_domain(name: str) -> bool:
    return any(name == p or name.startswith(p + ".") for p in DOMAIN_PACKAGES)


def _collect_imports() -> tuple[set[str], list[ImportSite]]:
    files = _source_files()
    modules = {_module_name(p) for p in files}
    sites: list[ImportSite] = []
    for path in files:
        importer = _module_name(path)
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        lazy_nodes = _lazy_import_nodes(tree)
        for node in ast.walk(tree):
            if not isinstance(node, (ast.Import, ast.ImportFrom)):
                continue
            for target in dict.fromkeys(_resolve(node, importer, path.name == "__init__.py", modules)):
                if target == PACKAGE or target.startswith(PACKAGE + ".") or _is_domain(target):
                    sites.append(ImportSite(importer, target, _rel(path), node.lineno,
                                            id(node) in lazy_nodes))
    return modules, sites


def _layer(module: str) -> str:
    """The layer of a module: its subpackage, or TOP_LEVEL_LAYER for ``acausal/<module>.py``."""
    parts = module.split(".")
    if len(parts) == 2 and not (PACKAGE_DIR / parts[1]).is_dir():
        return TOP_LEVEL_LAYER
    return parts[1]


@pytest.fixture(scope="module")
def imports():
    return _collect_imports()


@pytest.fixture(scope="module")
def graph(imports):
    modules, sites = imports
    g = nx.DiGraph()
    g.add_nodes_from(modules)
    for site in sites:
        target = site.imported
        if _is_domain(target) or target == site.importer:
            continue  # the model libraries have a test of their own
        if g.has_edge(site.importer, target):
            g.edges[site.importer, target]["sites"].append(site)
        else:
            g.add_edge(site.importer, target, sites=[site])
    return g


# ---------------------------------------------------------------------------
# Sanity of the reader itself
# ---------------------------------------------------------------------------

def test_the_reader_sees_the_package(imports, graph):
    modules, _ = imports
    for expected in ("acausal", "acausal.language", "acausal.compiler.translate",
                     "acausal.runtime.simulate", "acausal.tools.cli"):
        assert expected in modules, f"{expected} not found under {PACKAGE_DIR}"
    # known edges, one per import form: ``from ..x.y import z``, ``from .x import y``
    # in a package __init__, ``from . import y``
    assert graph.has_edge("acausal.runtime.simulate", "acausal.compiler.translate")
    assert graph.has_edge("acausal", "acausal.runtime.result")
    assert graph.has_edge("acausal", "acausal.errors")


def test_relative_imports_resolve():
    modules = {"acausal", "acausal.errors", "acausal.compiler", "acausal.compiler.flatten",
               "acausal.runtime", "acausal.runtime.events"}

    def resolve(source, importer, is_package=False):
        node = ast.parse(source).body[0]
        return _resolve(node, importer, is_package, modules)

    assert resolve("from ..compiler.flatten import INITIAL", "acausal.runtime.events") == [
        "acausal.compiler.flatten"]
    assert resolve("from ..compiler import flatten", "acausal.runtime.events") == [
        "acausal.compiler.flatten"]
    assert resolve("from ..compiler import something", "acausal.runtime.events") == ["acausal.compiler"]
    assert resolve("from . import errors", "acausal", is_package=True) == ["acausal.errors"]
    assert resolve("from .errors import X", "acausal", is_package=True) == ["acausal.errors"]
    assert resolve("from . import events", "acausal.runtime", is_package=True) == [
        "acausal.runtime.events"]
    assert resolve("from .. import __version__", "acausal.tools.cli") == ["acausal"]
    assert resolve("from ..library.rotational import X", "acausal.tools.bench") == [
        "acausal.library.rotational"]
    assert resolve("import acausal.compiler", "acausal.tools.cli") == ["acausal.compiler"]


def test_every_module_belongs_to_a_layer(imports):
    modules, _ = imports
    unknown = sorted(m for m in modules
                     if m not in EXEMPT_FROM_DIRECTION and _layer(m) not in LAYERS)
    assert not unknown, (f"modules outside every layer (add the layer to LAYERS in {Path(__file__).name}): "
                         f"{', '.join(unknown)}")


# ---------------------------------------------------------------------------
# The rules
# ---------------------------------------------------------------------------

MAX_CYCLES_SHOWN = 20


def test_no_import_cycles(graph):
    cycles = []
    for component in nx.strongly_connected_components(graph):
        if len(component) < 2:
            continue
        # every elementary cycle of the component (a few at most), each edge with its import lines
        found = sorted(nx.simple_cycles(graph.subgraph(component)), key=lambda c: (len(c), c))
        for cycle in found[:MAX_CYCLES_SHOWN]:
            start = cycle.index(min(cycle))
            cycle = cycle[start:] + cycle[:start]
            edges = zip(cycle, cycle[1:] + cycle[:1])
            lines = [f"  {a} -> {b}   [{'; '.join(s.where() for s in graph.edges[a, b]['sites'])}]"
                     for a, b in edges]
            cycles.append(" -> ".join(cycle + cycle[:1]) + ":\n" + "\n".join(lines))
        if len(found) > MAX_CYCLES_SHOWN:
            cycles.append(f"... and {len(found) - MAX_CYCLES_SHOWN} more cycles among "
                          f"{', '.join(sorted(component))}")
    if cycles:
        pytest.fail("import cycles between acausal modules:\n" + "\n".join(cycles), pytrace=False)


def test_imports_follow_the_layer_direction(graph):
    violations = []
    for importer, imported, data in sorted(graph.edges(data=True)):
        if importer in EXEMPT_FROM_DIRECTION or imported in EXEMPT_FROM_DIRECTION:
            continue
        a, b = _layer(importer), _layer(imported)
        if a in LAYERS and b in LAYERS and LAYERS[b] > LAYERS[a]:
            where = "; ".join(s.where() for s in data["sites"])
            violations.append(f"  {importer} -> {imported} (layer {a} -> layer {b})   [{where}]")
    order = " -> ".join(sorted(LAYERS, key=LAYERS.get))
    if violations:
        pytest.fail(f"imports against the layer direction ({order}; a module imports only "
                    f"from its own layer and earlier ones):\n" + "\n".join(violations), pytrace=False)


def test_the_engine_does_not_import_the_model_libraries(imports):
    _, sites = imports
    bad = sorted({f"  {s.importer} -> {s.imported}   [{s.where()}]" for s in sites
                  if _is_domain(s.imported)})
    if bad:
        pytest.fail("acausal/ imports the model libraries (the engine has no domain knowledge; "
                    f"{', '.join(DOMAIN_PACKAGES)} are built on it, not the other way round):\n"
                    + "\n".join(bad), pytrace=False)


def test_import_acausal_stays_light():
    code = ("import acausal, sys; "
            "bad = sorted(m for m in sys.modules if m.startswith(("
            "'acausal.tools', 'matplotlib', 'acausal.library', 'acausal.components'))); "
            "assert not bad, bad")
    proc = subprocess.run([sys.executable, "-c", code], cwd=REPO_ROOT, capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, f"import acausal imports modules it must not:\n{proc.stderr}"


# ---------------------------------------------------------------------------
# No domain words in the engine's messages
# ---------------------------------------------------------------------------

#: A domain word at the start of a word; words are separated by anything but a
#: letter, and by a lower→upper case change (``tau_flange``, ``ConstantTorque``).
DOMAIN_WORD_RE = re.compile(r"(?:(?<![A-Za-z])|(?<=[a-z])(?=[A-Z]))(?i:(" + "|".join(DOMAIN_WORDS) + r"))")


def _docstring_nodes(tree: ast.AST) -> set[int]:
    ids = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if (body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant)
                    and isinstance(body[0].value.value, str)):
                ids.add(id(body[0].value))
    return ids


def _domain_word_offenders() -> list[str]:
    offenders = []
    for path in _source_files():
        if path in DOMAIN_WORDS_EXEMPT_FILES:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        docstrings = _docstring_nodes(tree)
        found = []
        for node in ast.walk(tree):
            if (isinstance(node, ast.Constant) and isinstance(node.value, str)
                    and id(node) not in docstrings):
                words = sorted({m.group(1).lower() for m in DOMAIN_WORD_RE.finditer(node.value)})
                if words:
                    found.append((node.lineno, words, node.value))
        for line, words, text in sorted(found, key=lambda f: f[0]):
            shown = text if len(text) <= 160 else text[:157] + "..."
            offenders.append(f"  {_rel(path)}:{line}: [{', '.join(words)}] {shown!r}")
    return offenders


def test_domain_word_pattern():
    def hits(text):
        return [m.group(1).lower() for m in DOMAIN_WORD_RE.finditer(text)]

    assert hits("the Flange of the inertia") == ["flange", "inertia"]
    assert hits("tau_flange, ConstantTorque, gearbox, HEAT") == ["flange", "torque", "gear", "heat"]
    assert hits("overheat, sheath, cheating, torques") == ["torque"]
    assert hits("a structurally singular system") == []


def test_no_domain_words_in_engine_strings():
    offenders = _domain_word_offenders()
    if offenders:
        pytest.fail(
            f"{len(offenders)} string constant(s) in acausal/ (docstrings and tools/compare.py excepted) "
            f"use domain words ({', '.join(DOMAIN_WORDS)}); the engine's messages must speak of "
            "variables, equations and components, not of what the model libraries model:\n"
            + "\n".join(offenders), pytrace=False)


# -- the docs describe the folders as they are ------------------------------------------


def _layout_rows() -> dict[str, str]:
    """README's layout table: the first cell's paths -> the row."""
    readme = (PACKAGE_DIR.parent / "README.md").read_text()
    section = readme.split("## Layout", 1)[1].split("\n## ", 1)[0]
    rows = {}
    for line in section.splitlines():
        if line.startswith("| `"):
            first = line.split("|")[1]
            for path in re.findall(r"`([^`]+)`", first):
                rows[path.rstrip("/")] = line
    return rows


def _top_folders(repo: Path) -> list[str]:
    """The repository's top-level folders, as the layout table describes them.

    The folders of the files git tracks: what commands leave in a checkout
    (``bench-out/``, ``plots/`` of ``compare --plot``, a virtual environment,
    ``build/``), whether ``.gitignore`` lists it or not, is not the
    repository's layout, and the README's test command must pass in a
    checkout that has been used.  Outside a git checkout (an unpacked source
    archive) the folders on disk, less those ``.gitignore`` names.
    """
    try:
        top = subprocess.run(["git", "-C", str(repo), "rev-parse", "--show-toplevel"],
                             capture_output=True, text=True, timeout=60)
        files = subprocess.run(["git", "-C", str(repo), "ls-files", "-z"],
                               capture_output=True, text=True, timeout=60)
        tracked = (top.returncode == 0 and files.returncode == 0
                   and Path(top.stdout.strip()).resolve() == repo.resolve())
    except (OSError, subprocess.SubprocessError):
        tracked = False
    if tracked and files.stdout:
        names = {path.split("/", 1)[0] for path in files.stdout.split("\0") if "/" in path}
    else:
        import fnmatch

        ignore = repo / ".gitignore"
        patterns = [line.strip().strip("/") for line in
                    (ignore.read_text(encoding="utf-8").splitlines() if ignore.is_file() else [])
                    if line.strip() and not line.lstrip().startswith(("#", "!"))]
        names = {p.name for p in repo.iterdir()
                 if p.is_dir() and not any(fnmatch.fnmatch(p.name, pattern) for pattern in patterns)}
    return sorted(name for name in names if not name.startswith("."))


def test_readme_layout_names_every_layer_and_module():
    rows = _layout_rows()
    repo = PACKAGE_DIR.parent
    top = _top_folders(repo)
    missing_top = [name for name in top if not any(r == name or r.startswith(name + "/") for r in rows)]
    assert not missing_top, f"README layout misses the folders {missing_top}"
    for layer in ("compiler", "runtime", "tools"):
        row = rows.get(f"acausal/{layer}")
        assert row is not None, f"README layout has no row for acausal/{layer}/"
        modules = sorted(p.stem for p in (PACKAGE_DIR / layer).glob("*.py") if p.stem != "__init__")
        unnamed = [m for m in modules if f"`{m}`" not in row]
        assert not unnamed, f"README layout row of acausal/{layer}/ does not name {unnamed}"


def test_architecture_doc_names_every_engine_module():
    doc = (PACKAGE_DIR.parent / "docs" / "architecture.md").read_text()
    missing = [f"{layer}/{p.name}" for layer in ("compiler", "runtime")
               for p in sorted((PACKAGE_DIR / layer).glob("*.py")) if p.stem != "__init__"
               and f"{layer}/{p.name}" not in doc]
    assert not missing, f"docs/architecture.md does not mention {missing}"
