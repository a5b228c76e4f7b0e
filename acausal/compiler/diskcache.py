"""The persistent compile cache: generated code and plain metadata on disk, by content.

A compiled system is its generated Python source plus a little metadata
(states, unknowns, the alias plan, ...).  Stored under a key that covers
everything it was computed from, a later process that translates the same
flat model loads it instead of running stages 3–9 again.

What the key covers (:func:`model_key`): the flat model — every variable with
all its attributes, every parameter value, every equation (``sympy.srepr``,
which names symbols and functions in full), discrete and initial equations,
structural parameters, hints, the data of every table — the output demand,
whether independent parts are compiled apart, and the *engine version*: a
hash of acausal's version and of the source of the modules that produce
code (:func:`engine_version`).  Any change there is another key, so an entry
can never be stale; entries of old keys are simply not read again.

Each entry is one JSON file, written to a temporary file in the same folder
and renamed into place (``os.replace`` is atomic: concurrent writers of one
entry leave one whole file, never a mix), and verified on load: its format,
engine version, key and the SHA-256 of its payload must match, else it is
deleted and compiled anew.  No pickles: nothing in the cache is executed
except generated source whose checksum matched.

Where: ``$ACAUSAL_CACHE_DIR``, else the user's cache folder
(``$XDG_CACHE_HOME/acausal`` or ``~/.cache/acausal``; ``~/Library/Caches/acausal``
on macOS; ``%LOCALAPPDATA%\\acausal\\Cache`` on Windows).  Off with
``ACAUSAL_DISK_CACHE=off`` (or ``0``, ``false``, ``no``), or per call with
``cache=False``.  Models of more than :data:`MAX_EQUATIONS` equations are not
cached (writing their key costs about as much as compiling a small model).
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import tempfile
from pathlib import Path
from typing import Any

import sympy as sp

__all__ = ["DiskCache", "MemoryCache", "cache_folder", "disk_cache_enabled", "engine_version", "model_key", "MAX_EQUATIONS"]

#: Version of the entry layout; part of every entry.
FORMAT = 1

#: Models with more continuous equations than this are not cached on disk.
MAX_EQUATIONS = 5000

_OFF = {"0", "off", "false", "no"}


def disk_cache_enabled() -> bool:
    """Whether the persistent cache is on (``ACAUSAL_DISK_CACHE``, default on)."""
    return os.environ.get("ACAUSAL_DISK_CACHE", "on").strip().lower() not in _OFF


def cache_folder() -> Path:
    """The cache's folder (see the module docstring)."""
    explicit = os.environ.get("ACAUSAL_CACHE_DIR")
    if explicit:
        return Path(explicit)
    if sys.platform == "darwin":
        return Path.home() / "Library" / "Caches" / "acausal"
    if os.name == "nt":
        base = os.environ.get("LOCALAPPDATA") or str(Path.home() / "AppData" / "Local")
        return Path(base) / "acausal" / "Cache"
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "acausal"


_ENGINE: str | None = None


def engine_version() -> str:
    """acausal's version and a hash of the source of the modules that make code.

    Computed once per process.  The whole package is hashed (its ``.py``
    files, sorted by path): a changed engine file, even without a new
    version number, makes every key new.
    """
    global _ENGINE
    if _ENGINE is None:
        try:
            from importlib.metadata import version

            __version__ = version("acausal")
        except Exception:  # not installed (run from a checkout): the sources decide alone
            __version__ = "unknown"
        root = Path(__file__).resolve().parent.parent
        digest = hashlib.sha256(f"acausal {__version__} format {FORMAT}".encode())
        for path in sorted(root.rglob("*.py")):
            digest.update(str(path.relative_to(root)).encode())
            digest.update(path.read_bytes())
        _ENGINE = digest.hexdigest()
    return _ENGINE


def _table_text(function: type) -> str:
    parts = [function.__name__]
    for attribute in ("table", "breakpoints", "values", "slopes", "kind", "data_text"):
        value = getattr(function, attribute, None)
        if value is not None:
            parts.append(f"{attribute}={_plain(value)}")
    return " ".join(parts)


def _plain(value: Any) -> str:
    if hasattr(value, "tolist"):
        return repr(value.tolist())
    return repr(value)


def model_key(flat, demand, clustered: bool, redundant_constraints: str = "relax") -> str | None:
    """The key of a flat model's compiled systems, or None when it is not cached.

    Returns None for models of more than :data:`MAX_EQUATIONS` equations.
    """
    if len(flat.equations) > MAX_EQUATIONS:
        return None
    digest = hashlib.sha256()

    def add(text: str) -> None:
        digest.update(text.encode())
        digest.update(b"\n")

    add(engine_version())
    add(f"model {flat.name} {flat.modelica_class} {flat.experiment!r}")
    add(f"demand {sorted(demand) if demand is not None else None} clustered {clustered} "
        f"redundant {redundant_constraints}")
    add(f"structural {sorted(flat.structural_parameters.items(), key=lambda kv: kv[0])!r}")
    for v in flat.variables:
        add(f"variable {v!r}")
    for p in flat.parameters:
        add(f"parameter {p.name} {p.value!r}")
    tables: dict[str, str] = {}
    for group, equations in (("equation", flat.equations), ("initial", flat.initial_equations)):
        for eq in equations:
            o = eq.origin
            add(f"{group} {sp.srepr(eq.residual)} @ {o.component} {o.component_class} {o.declared_in} {o.index}")
            for f in eq.residual.atoms(sp.Function):
                if getattr(type(f), "_imp_", None) is not None:
                    tables.setdefault(type(f).__name__, _table_text(type(f)))
    for eq in flat.discrete_equations:
        o = eq.origin
        add(f"discrete {eq.variable} {sp.srepr(eq.rhs)} @ {o.component} {o.component_class} {o.index}")
    for name in sorted(tables):
        add(f"table {tables[name]}")
    add(f"hints {sorted((k, repr(v)) for k, v in flat.hints.items())!r}")
    return digest.hexdigest()


class DiskCache:
    """The entries of one model key in the cache folder.

    Parameters
    ----------
    folder : Path
        The cache folder.
    key : str
        The model's key (:func:`model_key`).
    """

    def __init__(self, folder: Path, key: str) -> None:
        self.folder = Path(folder) / key[:2] / key
        self.key = key
        self.hits = 0
        self.misses = 0
        self.rejected = 0  #: entries found but not valid (deleted)

    def _path(self, entry: str) -> Path:
        name = hashlib.sha256(entry.encode()).hexdigest()[:40]
        return self.folder / f"{name}.json"

    def load(self, entry: str) -> dict | None:
        """The payload stored for ``entry``, or None (missing, or invalid and deleted)."""
        path = self._path(entry)
        try:
            with open(path, "rb") as handle:
                raw = handle.read()
        except OSError:
            self.misses += 1
            return None
        try:
            document = json.loads(raw)
            payload = document["payload"]
            valid = (document.get("format") == FORMAT and document.get("engine") == engine_version()
                     and document.get("model") == self.key and document.get("entry") == entry
                     and document.get("sha256") == _checksum(payload))
        except (ValueError, KeyError, TypeError, AttributeError):
            valid = False
        if not valid:
            self.rejected += 1
            self.misses += 1
            try:
                path.unlink()
            except OSError:
                pass
            return None
        self.hits += 1
        return payload

    def store(self, entry: str, payload: dict) -> bool:
        """Write ``payload`` for ``entry`` atomically; False if it could not be written
        (a cache that cannot write never stops a translation)."""
        document = {"format": FORMAT, "engine": engine_version(), "model": self.key, "entry": entry,
                    "sha256": _checksum(payload), "payload": payload}
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            handle = tempfile.NamedTemporaryFile("w", dir=self.folder, suffix=".tmp", delete=False,
                                                 encoding="utf-8")
            try:
                with handle:
                    json.dump(document, handle)
                os.replace(handle.name, self._path(entry))
            except BaseException:
                try:
                    os.unlink(handle.name)
                except OSError:
                    pass
                raise
        except (OSError, TypeError, ValueError):
            return False
        return True


class MemoryCache:
    """Payloads held in memory, read as :class:`DiskCache` entries are: how a
    process that did not translate a model gets its compiled systems
    (:meth:`~acausal.compiler.translate.Translation.from_bundle`).

    A system compiled where this store is used (a discrete state the payloads
    do not hold) is kept here too, for the next translation of the process
    (:attr:`compiled` counts them).

    Parameters
    ----------
    payloads : mapping
        ``entry -> payload``, as :meth:`DiskCache.store` takes them.
    """

    def __init__(self, payloads) -> None:
        self.payloads = dict(payloads)
        #: ``entry -> (GeneratedCode, make)``: the source is loaded once, then every translation binds it
        self.codes: dict = {}
        self.hits = 0
        self.misses = 0
        self.compiled = 0  #: systems compiled because no payload served them

    def load(self, entry: str) -> dict | None:
        """The payload of ``entry``, or None."""
        payload = self.payloads.get(entry)
        if payload is None:
            self.misses += 1
        else:
            self.hits += 1
        return payload

    def store(self, entry: str, payload: dict) -> bool:
        """Keep the payload of a system compiled here."""
        self.compiled += 1
        self.payloads[entry] = payload
        self.codes.pop(entry, None)
        return True


def _checksum(payload) -> str:
    return hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()
