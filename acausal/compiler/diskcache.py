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
entry leave one whole file, never a mix).

An entry holds code that is executed, so whoever can write the cache folder
could otherwise run code in every later process.  Three rules keep that out:

- **Authenticated entries.**  Every entry carries an HMAC-SHA256 of its
  content under a secret key that is kept outside the cache folder
  (:func:`cache_key`); the MAC is checked over the bytes as stored, before
  anything of the entry is parsed, and then its format, engine version,
  model key and entry name must match.  An entry that fails is deleted and
  compiled anew: the run goes on with the same result.  The key is the
  user's own (``$XDG_CONFIG_HOME/acausal/cache-key``, else
  ``~/.config/acausal/cache-key``; ``%APPDATA%\\acausal\\cache-key`` on
  Windows), created on first use, mode 0600; or a team's, from the file
  ``$ACAUSAL_CACHE_KEY_FILE`` names, which lets a team share one cache
  folder.  A key file that cannot serve turns the cache off (a warning
  says why).  Entries of the former layout (a SHA-256 anyone can compute)
  are invalid.
- **Trusted folders only.**  The cache folder and the folders below it that
  lead to an entry must not be writable by others, nor owned by another
  user (root excepted), as ssh treats its keys; else the cache neither
  reads nor writes there, with one warning per folder and process.  With a
  team key a folder may be the group's (group-writable, owned by a team
  member), never world-writable.  Without POSIX owners and modes (Windows)
  the MAC alone decides.  Folders the cache creates are private (0700; 0770
  with a team key).
- **Careful reading.**  An entry is opened only if it is a regular file
  (opened without blocking and without following a symbolic link, then
  checked with ``fstat``: a FIFO or a link to ``/dev/zero`` is refused
  unread) of at most :data:`MAX_ENTRY_BYTES`; any parse failure makes it
  invalid.  An invalid entry is unlinked (a symbolic link itself, never
  what it points to).

Where: ``$ACAUSAL_CACHE_DIR``, else the user's cache folder
(``$XDG_CACHE_HOME/acausal`` or ``~/.cache/acausal``; ``~/Library/Caches/acausal``
on macOS; ``%LOCALAPPDATA%\\acausal\\Cache`` on Windows).  Off with
``ACAUSAL_DISK_CACHE=off`` (or ``0``, ``false``, ``no``), or per call with
``cache=False``.  Models of more than :data:`MAX_EQUATIONS` equations are not
cached (writing their key costs about as much as compiling a small model).
"""

from __future__ import annotations

import errno
import hashlib
import hmac
import json
import os
import secrets
import stat
import sys
import tempfile
import warnings
from pathlib import Path
from typing import Any


__all__ = ["DiskCache", "MemoryCache", "cache_folder", "cache_key", "disk_cache_enabled", "engine_version",
           "key_file", "model_key", "MAX_ENTRY_BYTES", "MAX_EQUATIONS"]

#: Version of the entry layout; part of every entry.
FORMAT = 2

#: Models with more continuous equations than this are not cached on disk.
MAX_EQUATIONS = 5000

#: The largest entry read or written.  An entry of a model at :data:`MAX_EQUATIONS`
#: (``drive_train_model(151)`` of ``examples/benchmarks.py``) is 0.8 MB, and even
#: ``drive_train_model(200)``, too large to be cached, makes payloads of 1.5 MB: 8 MiB
#: leaves five times that, and bounds what a bad entry can make a process read.
MAX_ENTRY_BYTES = 8 * 2**20

#: Random bytes of a key the cache creates (written as 64 hexadecimal digits).
KEY_BYTES = 32

#: The shortest key accepted from a key file, in bytes (surrounding white space aside).
MIN_KEY_LENGTH = 32

#: Keys are small: a key file longer than this is not one.
_MAX_KEY_FILE_BYTES = 4096

_OFF = {"0", "off", "false", "no"}

#: What an entry starts with: the MAC comes first, at a fixed place, so that it is
#: checked over the bytes as stored before anything of the entry is parsed.
_MAC_FIELD = b'{"hmac": "'
_MAC_LENGTH = 64  # hexadecimal digits of an HMAC-SHA256
_MAC_END = b'", '

#: Folders (and key files) a warning was given for in this process.
_WARNED: set[str] = set()


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


# -- the secret key --------------------------------------------------------------


def key_file() -> tuple[Path, bool]:
    """The file of the cache's secret key, and whether it is a team's key.

    A team's key is the file ``$ACAUSAL_CACHE_KEY_FILE`` names: every user
    who sets it reads the entries the others write.  Else the key is the
    user's own, in the user's configuration folder — never in the cache
    folder, whose contents must not give it away:
    ``$XDG_CONFIG_HOME/acausal/cache-key``, else ``~/.config/acausal/cache-key``
    (``%APPDATA%\\acausal\\cache-key`` on Windows).

    Returns
    -------
    path : Path
        The key file.
    shared : bool
        True for a team's key (``ACAUSAL_CACHE_KEY_FILE``).
    """
    team = os.environ.get("ACAUSAL_CACHE_KEY_FILE")
    if team:
        return Path(team).expanduser(), True
    if os.name == "nt":
        base = os.environ.get("APPDATA") or str(Path.home() / "AppData" / "Roaming")
        return Path(base) / "acausal" / "cache-key", False
    base = os.environ.get("XDG_CONFIG_HOME") or str(Path.home() / ".config")
    return Path(base) / "acausal" / "cache-key", False


def cache_key(folder: Path) -> tuple[bytes, bool] | None:
    """The secret key entries in ``folder`` are authenticated with, or None if there is none.

    The user's own key (:func:`key_file`) is created on first use: 32 random
    bytes, written as 64 hexadecimal digits to a file of mode 0600 in a
    folder of mode 0700.  A key file that cannot serve — a team key file that
    is missing, a file others may read or change (a team's may be its
    group's), a key inside ``folder``, fewer than :data:`MIN_KEY_LENGTH`
    bytes — turns the cache off, with one warning per process: entries that
    nobody else can forge are the point of the key.

    Parameters
    ----------
    folder : Path
        The cache folder.

    Returns
    -------
    tuple of (bytes, bool) or None
        The key (the file's bytes, white space around them aside) and whether
        it is a team's key.
    """
    path, shared = key_file()
    try:
        if _inside(path, Path(folder)):
            raise _Unusable("is inside the cache folder, whose contents must not give the key away",
                            "move the cache folder (ACAUSAL_CACHE_DIR) or the key (XDG_CONFIG_HOME, "
                            "ACAUSAL_CACHE_KEY_FILE) apart")
        if not shared and not os.path.lexists(path):
            _create_key(path)
        raw, info = _read_regular(path, _MAX_KEY_FILE_BYTES, follow=True)
        _check_key_file(path, info, shared)
        secret = raw.strip()
        if len(secret) < MIN_KEY_LENGTH:
            raise _Unusable(f"holds {len(secret)} bytes, fewer than the {MIN_KEY_LENGTH} of a key",
                            'write 64 random hexadecimal digits into it (python -c "import secrets; '
                            'print(secrets.token_hex(32))")')
    except _Unusable as problem:
        _warn_once(str(path), f"acausal's compile cache is off: its key file {path} {problem}; "
                              f"{problem.hint}")
        return None
    except OSError as error:
        hint = ("unset ACAUSAL_CACHE_KEY_FILE, or have it name the team's key file" if shared
                else f"check that {path.parent} can be written, or set ACAUSAL_CACHE_KEY_FILE to a key file")
        _warn_once(str(path), f"acausal's compile cache is off: its key file {path} cannot be used "
                              f"({error.strerror or error}); {hint}")
        return None
    return secret, shared


class _Unusable(Exception):
    """A key file the cache does not use: why (the message, read after the file's name), and a hint."""

    def __init__(self, why: str, hint: str) -> None:
        super().__init__(why)
        self.hint = hint


def _create_key(path: Path) -> None:
    """Create the user's key file at ``path``, unless another process does it first.

    The key is written whole to a temporary file (mode 0600), which is then
    linked to its name: ``os.link`` never replaces a file, so of processes
    starting together the first one's key is everyone's, and none reads a
    key half written.
    """
    _make_folders(path.parent, 0o700)
    handle = tempfile.NamedTemporaryFile("w", dir=path.parent, prefix=".cache-key-", suffix=".tmp",
                                         delete=False, encoding="ascii")
    try:
        with handle:
            handle.write(secrets.token_hex(KEY_BYTES) + "\n")
        try:
            os.link(handle.name, path)
        except FileExistsError:
            pass
    finally:
        os.unlink(handle.name)


def _check_key_file(path: Path, info: os.stat_result, shared: bool) -> None:
    """Raise :class:`_Unusable` if others than the key file's owner (and, for a team's key,
    its group) may read or change it.  Without POSIX owners and modes, nothing to check."""
    if not hasattr(os, "getuid"):
        return
    mode = stat.S_IMODE(info.st_mode)
    described = f"(mode {mode:#o} {stat.filemode(info.st_mode)}, owner {_owner(info.st_uid)})"
    if shared and mode & 0o007:
        raise _Unusable(f"may be read or changed by anyone {described}", f"chmod o-rwx {path}")
    if not shared and info.st_uid != os.getuid():
        raise _Unusable(f"belongs to another user {described}", "remove it: the next run makes a new key")
    if not shared and mode & 0o077:
        raise _Unusable(f"may be read or changed by others {described}", f"chmod 600 {path}")


def _inside(path: Path, folder: Path) -> bool:
    """Whether ``path`` is in ``folder`` (symbolic links resolved)."""
    return Path(os.path.realpath(path)).is_relative_to(os.path.realpath(folder))


# -- keys of models ---------------------------------------------------------------


_ENGINE: str | None = None


def engine_version() -> str:
    """acausal's version and a hash of the source of the modules that make code.

    Computed once per process.  The whole package is hashed (its ``.py``
    files, sorted by path): a changed engine file, even without a new
    version number, makes every key new.
    """
    global _ENGINE
    if _ENGINE is None:
        from .. import __version__  # the package's own (importlib.metadata costs a warm command 15 ms)

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
    import sympy as sp  # here only: loading an entry needs no sympy (acausal.compiler.saved)
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


# -- the stores ------------------------------------------------------------------


class DiskCache:
    """The entries of one model key in the cache folder.

    Entries are read and written only with the cache's key (:func:`cache_key`)
    and in trusted folders (see the module docstring); else every load is a
    miss and every store does nothing.

    Parameters
    ----------
    folder : Path
        The cache folder.
    key : str
        The model's key (:func:`model_key`).
    """

    def __init__(self, folder: Path, key: str) -> None:
        self.root = Path(folder)
        self.folder = self.root / key[:2] / key
        self.key = key
        self.hits = 0
        self.misses = 0
        self.rejected = 0  #: entries found but not valid (deleted)
        self._secret: tuple[bytes, bool] | None = None
        self._looked_up = False  # the key is read once, at the first load or store

    def _path(self, entry: str) -> Path:
        name = hashlib.sha256(entry.encode()).hexdigest()[:40]
        return self.folder / f"{name}.json"

    def load(self, entry: str) -> dict | None:
        """The payload stored for ``entry``, or None (missing, or invalid and deleted)."""
        secret = self._access(write=False)
        if secret is None:
            self.misses += 1
            return None
        path = self._path(entry)
        try:
            raw, _ = _read_regular(path, MAX_ENTRY_BYTES, follow=False)
        except FileNotFoundError:
            self.misses += 1
            return None
        except OSError:  # a symbolic link, a FIFO, a device, a folder, too long, unreadable: no entry
            raw = None
        document = _unseal(raw, secret) if raw is not None else None
        valid = (document is not None and document.get("format") == FORMAT
                 and document.get("engine") == engine_version() and document.get("model") == self.key
                 and document.get("entry") == entry and isinstance(document.get("payload"), dict))
        if not valid:
            self.rejected += 1
            self.misses += 1
            try:
                os.unlink(path)  # a symbolic link itself, never what it points to
            except OSError:
                pass
            return None
        self.hits += 1
        return document["payload"]

    def store(self, entry: str, payload: dict) -> bool:
        """Write ``payload`` for ``entry`` atomically; False if it could not be written
        (a cache that cannot write never stops a translation)."""
        document = {"format": FORMAT, "engine": engine_version(), "model": self.key, "entry": entry,
                    "payload": payload}
        try:
            body = json.dumps(document).encode()
            if len(_MAC_FIELD) + _MAC_LENGTH + len(body) > MAX_ENTRY_BYTES:
                return False  # it would never be read
            secret = self._access(write=True)
            if secret is None:
                return False
            handle = tempfile.NamedTemporaryFile("wb", dir=self.folder, suffix=".tmp", delete=False)
            try:
                with handle:
                    handle.write(_seal(body, secret))
                if self._secret[1]:
                    os.chmod(handle.name, 0o640)  # a team's entry: its group reads it
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

    def _access(self, write: bool) -> bytes | None:
        """The key to read (or write) this model's entries with, or None: there is no key, or a
        folder on the way to them is not trusted (a warning names it, once per process).

        To write, the folders missing are created (private: 0700, 0770 with a team's key) and
        examined again (one made meanwhile by someone else is not trusted either).
        """
        if not self._looked_up:
            self._looked_up = True
            self._secret = cache_key(self.root)
        if self._secret is None:
            return None
        secret, shared = self._secret
        if not self._trusted(shared):
            return None
        if write:
            _make_folders(self.folder, 0o770 if shared else 0o700)
            if not self._trusted(shared):
                return None
        return secret

    def _trusted(self, shared: bool) -> bool:
        """Whether the cache folder and the folders below it that lead to the entries are trusted."""
        for folder in (self.root, self.folder.parent, self.folder):
            try:
                problem = _distrust(folder, shared)
            except FileNotFoundError:
                return True  # neither it nor those below exist: nothing to read, a store makes them
            except OSError:
                return False  # not a folder, or it cannot be examined: no cache here
            if problem is not None:
                _warn_once(str(folder), problem)
                return False
        return True


class MemoryCache:
    """Payloads held in memory, read as :class:`DiskCache` entries are: how a
    process that did not translate a model gets its compiled systems
    (:meth:`~acausal.compiler.translate.Translation.from_bundle`).

    A system compiled where this store is used (a discrete state the payloads
    do not hold) is kept here too, for the next translation of the process
    (:attr:`compiled` counts them).

    Payloads here carry no MAC: a bundle travels inside one process tree (a
    pool's workers, a Dask cluster the user runs) and holds a pickle besides,
    so whoever could change it in transit could run code anyway.

    Parameters
    ----------
    payloads : mapping
        ``entry -> payload``, as :meth:`DiskCache.store` takes them.
    """

    def __init__(self, payloads) -> None:
        self.payloads = dict(payloads)
        #: ``entry -> (GeneratedCode, make)``: the source is loaded once, then every translation binds it
        self.codes: dict = {}
        #: ``entry -> the parameters its aliases read`` and ``(entry, their values) -> alias plan``
        #: (:func:`acausal.compiler.persist._bundle_plan`)
        self.plans: dict = {}
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
        # the plans made from the entry's previous payload go with it
        self.plans = {key: plan for key, plan in self.plans.items()
                      if (key if isinstance(key, str) else key[0]) != entry}
        return True


# -- entries on disk ---------------------------------------------------------------


def _seal(body: bytes, secret: bytes) -> bytes:
    """An entry's bytes: the JSON object ``body`` with the MAC of ``body`` as its first field.

    The result is still one JSON object (``{"hmac": "...", "format": ...}``).
    """
    return _MAC_FIELD + _mac(body, secret) + _MAC_END + body[1:]


def _unseal(raw: bytes, secret: bytes) -> dict | None:
    """The document of an entry's bytes, or None: not authenticated by ``secret``, or not a JSON object.

    The MAC is checked first, over the bytes as they are stored: nothing an
    attacker wrote is parsed.
    """
    start = len(_MAC_FIELD)
    end = start + _MAC_LENGTH
    if not raw.startswith(_MAC_FIELD) or raw[end:end + len(_MAC_END)] != _MAC_END:
        return None
    body = b"{" + raw[end + len(_MAC_END):]
    if not hmac.compare_digest(raw[start:end], _mac(body, secret)):
        return None
    try:
        document = json.loads(body)
    except Exception:  # RecursionError, MemoryError, ValueError (UnicodeDecodeError), ...: not an entry
        return None
    return document if isinstance(document, dict) else None


def _mac(body: bytes, secret: bytes) -> bytes:
    return hmac.new(secret, body, hashlib.sha256).hexdigest().encode()


def _read_regular(path: Path, limit: int, follow: bool) -> tuple[bytes, os.stat_result]:
    """The bytes of ``path`` and its status, if it is a regular file of at most ``limit`` bytes.

    Opened without blocking (a FIFO would wait for a writer for ever) and,
    unless ``follow``, without following a symbolic link (a link to
    ``/dev/zero`` reads without end); then examined with ``fstat``, which
    describes the file opened, not one put in its place meanwhile.

    Raises
    ------
    OSError
        If it cannot be opened (FileNotFoundError: it does not exist), is a
        symbolic link and ``follow`` is false, is not a regular file, or is
        longer than ``limit``.
    """
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0)
    if not follow:
        if not hasattr(os, "O_NOFOLLOW") and os.path.islink(path):
            raise OSError(errno.ELOOP, "a symbolic link", str(path))
        flags |= getattr(os, "O_NOFOLLOW", 0)
    fd = os.open(path, flags)
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise OSError(errno.EINVAL, "not a regular file", str(path))
        if info.st_size > limit:
            raise OSError(errno.EFBIG, f"longer than {limit} bytes", str(path))
        chunks: list[bytes] = []
        size = 0
        while size <= limit:  # a file growing meanwhile is read no further than the limit
            chunk = os.read(fd, limit + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
    finally:
        os.close(fd)
    if size > limit:
        raise OSError(errno.EFBIG, f"longer than {limit} bytes", str(path))
    return b"".join(chunks), info


# -- trusted folders -------------------------------------------------------------


def _distrust(folder: Path, shared: bool) -> str | None:
    """Why the cache must not use ``folder`` (a warning's text), or None if it may.

    Not trusted: a folder others may write to, or one owned by another user
    than the user and root — except that with a team's key (``shared``) the
    group may write to it and a team member may own it.  Without POSIX
    owners and modes (Windows) every folder is trusted: the MAC decides.

    Raises
    ------
    OSError
        If it cannot be examined (FileNotFoundError: it does not exist) or is not a folder.
    """
    info = os.stat(folder)
    if not stat.S_ISDIR(info.st_mode):
        raise NotADirectoryError(errno.ENOTDIR, "not a folder", str(folder))
    if not hasattr(os, "getuid"):
        return None
    mode = stat.S_IMODE(info.st_mode)
    if mode & 0o002:
        why, hint = "anyone may write to it", f"chmod o-w {folder}" if shared else f"chmod go-w {folder}"
    elif mode & 0o020 and not shared:
        why, hint = "its group may write to it", (f"chmod go-w {folder} (a team sharing it sets "
                                                  "ACAUSAL_CACHE_KEY_FILE to the team's key file)")
    elif info.st_uid not in (os.getuid(), 0) and not shared:
        why, hint = "it belongs to another user", "use a folder of your own"
    else:
        return None
    return (f"acausal's compile cache neither reads nor writes {folder}: {why} (mode {mode:#o} "
            f"{stat.filemode(info.st_mode)}, owner {_owner(info.st_uid)}), and whoever can change the "
            f"cache can change the code it runs; {hint}, or set ACAUSAL_CACHE_DIR to a private folder")


def _make_folders(folder: Path, mode: int) -> None:
    """Create ``folder`` and its missing parents with ``mode``, whatever the umask (under
    umask 002 they would be group-writable, and not trusted).  A set-group-ID bit a new
    folder inherits (a team's folder) is kept."""
    missing = []
    while not os.path.isdir(folder) and folder.parent != folder:
        missing.append(folder)
        folder = folder.parent
    for folder in reversed(missing):
        try:
            os.mkdir(folder, mode)
        except FileExistsError:
            continue  # made meanwhile by another process: examined as any folder is
        os.chmod(folder, mode | (os.stat(folder).st_mode & stat.S_ISGID))


def _owner(uid: int) -> str:
    try:
        import pwd

        return f"{pwd.getpwuid(uid).pw_name} (uid {uid})"
    except (ImportError, KeyError):
        return f"uid {uid}"


def _warn_once(subject: str, text: str) -> None:
    """Warn ``text`` unless this process warned about ``subject`` (a folder, a key file) already."""
    if subject not in _WARNED:
        _WARNED.add(subject)
        warnings.warn(text, UserWarning, stacklevel=2)
