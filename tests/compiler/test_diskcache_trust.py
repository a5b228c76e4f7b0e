"""The persistent compile cache trusts only what its owner wrote (issue 23).

Entries are authenticated with a secret key kept outside the cache folder, a
folder others may write to is neither read nor written, and an entry that is
not a small regular file, or does not parse, is removed and compiled anew:
every run here gives the result of a run without a cache.  Runs that used to
hang (a FIFO) or to read without end (a link to ``/dev/zero``) run in a
subprocess with a timeout of its own.

Every test has a cache folder, a home and a configuration folder of its own
(``ACAUSAL_CACHE_DIR``, ``HOME``, ``XDG_CONFIG_HOME``: the key lives there),
and turns the cache on.
"""

from __future__ import annotations

import hashlib
import json
import math
import multiprocessing
import os
import stat
import subprocess
import sys
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

import acausal.compiler.diskcache as diskcache
import acausal.compiler.translate as translate_module
from acausal import Eq, Experiment, Model, Parameter, Variable, der, simulate
from acausal.compiler.diskcache import DiskCache
from acausal.compiler.translate import translate

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent


class Decay(Model):
    """der(x) = -k*x, x(0) = 1: x(1) = exp(-k).  Its generated code computes ``-k*v_x``."""

    experiment = Experiment(stop_time=1.0, interval=0.1)
    k = Parameter(2.0)
    x = Variable(start=1.0, fixed=True)

    def equations(self):
        return [Eq(der(self.x), -self.k * self.x)]


class Growth(Decay):
    """Another model (another key) of the same kind."""

    k = Parameter(-1.0)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("ACAUSAL_DISK_CACHE", "on")
    monkeypatch.setenv("ACAUSAL_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "config"))
    monkeypatch.delenv("ACAUSAL_CACHE_KEY_FILE", raising=False)
    monkeypatch.setattr(diskcache, "_WARNED", set(), raising=False)  # warnings once per process: per test here
    forget_translations()
    yield tmp_path / "cache"
    forget_translations()


def forget_translations():
    translate_module._CACHE.clear()
    translate_module._STRUCTURES.clear()


def entries(folder: Path) -> list[Path]:
    return sorted(folder.rglob("*.json")) if folder.exists() else []


def run(make=Decay):
    translation = translate(make())
    return translation, simulate(translation)


def loaded(translation) -> list:
    systems = list(translation.systems.values()) + list(translation.initial_systems.values())
    return [s for s in systems if s.passes and s.passes[0][0] == "load"]


def assert_same(a, b):
    assert a.status == b.status == 0, (a.message, b.message)
    np.testing.assert_array_equal(a.time, b.time)
    for name in a.names:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


def assert_decays(result):
    assert result.status == 0, result.message
    assert result["x"][-1] == pytest.approx(math.exp(-2.0), rel=1e-4)


def write_key(path: Path, mode: int, text: str = "0123456789abcdef" * 4) -> Path:
    path.write_text(text + "\n")
    path.chmod(mode)
    return path


def cache_warnings(caught, subject) -> list[str]:
    return [str(w.message) for w in caught
            if issubclass(w.category, UserWarning) and str(subject) in str(w.message)]


# -- authentication ----------------------------------------------------------------


def test_a_tampered_entry_does_not_run(cache, tmp_path):
    """The attack of issue 23: ``-k*v_x`` edited to ``k*v_x`` (x(1) = 7.389 instead of
    0.135), with a line that creates a file, and every checksum that needs no secret
    recomputed.  The code does not run, the result is the untampered one, and the entries
    are written again, valid."""
    _, cold = run()
    assert_decays(cold)
    marker = tmp_path / "the tampered code ran"
    tampered = 0
    for path in entries(cache):
        document = json.loads(path.read_text())
        payload = document["payload"]
        assert "-k*v_x" in payload["source"]
        payload["source"] = payload["source"].replace("-k*v_x", "k*v_x").replace(
            "def make(p):\n", f"__import__('pathlib').Path({str(marker)!r}).touch()\ndef make(p):\n", 1)
        if "sha256" in document:  # the checksum of the former layout: anyone can compute it
            document["sha256"] = hashlib.sha256(json.dumps(payload, sort_keys=True).encode()).hexdigest()
        path.write_text(json.dumps(document))
        tampered += 1
    assert tampered == 2  # the mode and the initialization
    forget_translations()
    translation, warm = run()
    assert not marker.exists(), "the tampered code ran"
    assert_decays(warm)
    assert_same(cold, warm)
    assert not loaded(translation) and translation._disk_cache().rejected == tampered
    forget_translations()
    again, _ = run()
    assert len(loaded(again)) == tampered and again._disk_cache().rejected == 0


def test_the_key_is_made_private_outside_the_cache_and_reused(cache, tmp_path, monkeypatch):
    """The key file is made 0600 in a 0700 folder of the configuration folder, never in the
    cache, and read again by the next run; the cache's folders are private even under
    umask 002 (else the next run would not trust them)."""
    umask = os.umask(0o002)
    try:
        run()
    finally:
        os.umask(umask)
    key = tmp_path / "config" / "acausal" / "cache-key"
    assert stat.S_IMODE(key.stat().st_mode) == 0o600
    assert stat.S_IMODE(key.parent.stat().st_mode) == 0o700
    secret = key.read_bytes().strip()
    assert len(secret) == 64 and int(secret, 16) >= 0  # 32 random bytes, in hexadecimal
    stored = entries(cache)
    assert stored and not any(secret in path.read_bytes() for path in stored)
    assert all(stat.S_IMODE(path.stat().st_mode) == 0o600 for path in stored)
    assert stat.S_IMODE(cache.stat().st_mode) == 0o700  # made private whatever the umask
    forget_translations()
    translation, _ = run()
    assert len(loaded(translation)) == len(stored)
    assert key.read_bytes().strip() == secret
    # without XDG_CONFIG_HOME the key is in ~/.config: another key, so the entries are invalid
    monkeypatch.delenv("XDG_CONFIG_HOME")
    forget_translations()
    translation, _ = run()
    assert (tmp_path / "home" / ".config" / "acausal" / "cache-key").is_file()
    assert not loaded(translation) and translation._disk_cache().rejected == len(stored)


def _key_of(folder: str, barrier, keys) -> None:
    import secrets
    import time

    def slow_token(n):  # every process makes a key of its own before any is in place
        time.sleep(0.5)
        return secrets.token_hex(n)

    diskcache.secrets = SimpleNamespace(token_hex=slow_token)
    barrier.wait()
    keys.put(diskcache.cache_key(Path(folder)))


def test_processes_starting_together_agree_on_the_key(cache, tmp_path):
    """Four processes create the key at once, each with a key of its own: ``os.link`` never
    replaces a file, so the first key in place is everyone's."""
    context = multiprocessing.get_context("spawn")
    barrier, keys = context.Barrier(4), context.Queue()
    processes = [context.Process(target=_key_of, args=(str(cache), barrier, keys)) for _ in range(4)]
    for process in processes:
        process.start()
    found = [keys.get(timeout=60) for _ in processes]
    for process in processes:
        process.join(timeout=60)
        assert process.exitcode == 0
    folder = tmp_path / "config" / "acausal"
    assert found[0] is not None and all(key == found[0] for key in found)
    assert found[0][0] == (folder / "cache-key").read_bytes().strip()
    assert sorted(p.name for p in folder.iterdir()) == ["cache-key"], "temporary files left behind"


def test_a_team_key_shares_entries_and_another_key_invalidates_them(cache, tmp_path, monkeypatch):
    """Two users with the team's key file share entries; a third with another key finds
    them invalid, removes them and compiles anew, with the same result.  The folders and
    entries of a team are its group's (0770, 0640), so a user without the team key does
    not trust them."""
    monkeypatch.setenv("ACAUSAL_CACHE_KEY_FILE", str(write_key(tmp_path / "team-key", 0o640)))
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "alice"))
    _, cold = run()
    stored = {path: path.read_bytes() for path in entries(cache)}
    assert stored and all(stat.S_IMODE(path.stat().st_mode) == 0o640 for path in stored)
    assert stat.S_IMODE(cache.stat().st_mode) == 0o770
    assert not (tmp_path / "alice").exists(), "with a team key no key of one's own is made"
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "bob"))
    forget_translations()
    translation, warm = run()
    assert len(loaded(translation)) == len(stored) and translation._disk_cache().rejected == 0
    assert_same(cold, warm)
    other = "fedcba9876543210" * 4
    monkeypatch.setenv("ACAUSAL_CACHE_KEY_FILE", str(write_key(tmp_path / "carol-key", 0o600, other)))
    forget_translations()
    translation, carol = run()
    assert not loaded(translation) and translation._disk_cache().rejected == len(stored)
    assert_same(cold, carol)
    assert all(path.read_bytes() != raw for path, raw in stored.items()), "not written again with her key"
    monkeypatch.delenv("ACAUSAL_CACHE_KEY_FILE")
    forget_translations()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        translation, own = run()
    assert cache_warnings(caught, cache) and not loaded(translation)
    assert_same(cold, own)


@pytest.mark.parametrize("problem", ["own key others can read", "team key anyone can read", "no team key file",
                                     "team key too short", "key inside the cache folder"])
def test_a_key_that_cannot_serve_turns_the_cache_off_with_a_warning(cache, tmp_path, monkeypatch, problem):
    if problem == "own key others can read":
        (tmp_path / "config" / "acausal").mkdir(parents=True)
        key = write_key(tmp_path / "config" / "acausal" / "cache-key", 0o644)
    elif problem == "team key anyone can read":
        key = write_key(tmp_path / "team-key", 0o644)
    elif problem == "no team key file":
        key = tmp_path / "no such key"
    elif problem == "team key too short":
        key = write_key(tmp_path / "team-key", 0o600, "secret")
    else:
        monkeypatch.setenv("XDG_CONFIG_HOME", str(cache / "config"))
        key = cache / "config" / "acausal" / "cache-key"
    if problem.startswith(("team", "no team")):
        monkeypatch.setenv("ACAUSAL_CACHE_KEY_FILE", str(key))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        _, result = run()
        forget_translations()
        run(Growth)
    assert_decays(result)
    assert len(cache_warnings(caught, key)) == 1, [str(w.message) for w in caught]
    assert not entries(cache)
    if problem == "key inside the cache folder":
        assert not key.exists()


# -- trusted folders -------------------------------------------------------------------


def test_a_group_writable_cache_folder_is_neither_read_nor_written_and_says_so_once(cache):
    _, cold = run()
    stored = entries(cache)
    stored[0].write_bytes(b"garbage")  # read, it would be removed
    before = {path: path.read_bytes() for path in stored}
    cache.chmod(0o775)  # a folder made under umask 002
    forget_translations()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        translation, warm = run()
        forget_translations()
        run(Growth)
    assert_same(cold, warm)
    assert not loaded(translation) and translation._disk_cache().rejected == 0
    assert {path: path.read_bytes() for path in entries(cache)} == before, "entries read or written"
    messages = cache_warnings(caught, cache)
    assert len(messages) == 1, messages
    text = messages[0]
    assert "0o775" in text and "drwxrwxr-x" in text and "owner" in text
    assert f"chmod go-w {cache}" in text and "ACAUSAL_CACHE_DIR" in text


def test_a_writable_folder_below_the_cache_folder_is_not_trusted_either(cache):
    translation, _ = run()
    folder = translation._disk_cache().folder
    folder.chmod(0o777)
    forget_translations()
    with pytest.warns(UserWarning, match="anyone may write to it") as caught:
        translation, _ = run()
    assert not loaded(translation)
    assert len(cache_warnings(caught, folder)) == 1


def test_a_team_may_share_a_group_writable_folder_but_not_a_world_writable_one(cache, tmp_path, monkeypatch):
    monkeypatch.setenv("ACAUSAL_CACHE_KEY_FILE", str(write_key(tmp_path / "team-key", 0o640)))
    _, cold = run()
    cache.chmod(0o2775)
    forget_translations()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        translation, warm = run()
    assert loaded(translation) and not cache_warnings(caught, cache)
    assert_same(cold, warm)
    cache.chmod(0o777)
    forget_translations()
    with pytest.warns(UserWarning, match=f"chmod o-w {cache}"):
        translation, _ = run()
    assert not loaded(translation)


@pytest.mark.skipif(not hasattr(os, "getuid") or os.getuid() != 0,
                    reason="giving a folder to another user needs root")
def test_a_cache_folder_of_another_user_is_not_trusted(cache):
    run()
    os.chown(cache, 65534, -1)
    forget_translations()
    with pytest.warns(UserWarning, match="belongs to another user") as caught:
        translation, result = run()
    assert_decays(result)
    assert not loaded(translation)
    assert "uid 65534" in cache_warnings(caught, cache)[0]


# -- careful reading ---------------------------------------------------------------------


def _sabotaged_run(tmp_path: Path, sabotage: str) -> dict:
    """Run Decay in a fresh process (under a 4 GiB address-space limit) after ``sabotage``
    (Python, with ``path``) replaced every stored entry; what the second run gave."""
    script = tmp_path / "sabotaged.py"
    script.write_text(
        "import json, os, resource, stat, sys\n"
        "from pathlib import Path\n"
        "resource.setrlimit(resource.RLIMIT_AS, (4 * 2**30, 4 * 2**30))\n"
        f"sys.path[:0] = [{str(ROOT)!r}, {str(HERE)!r}]\n"
        "from test_diskcache_trust import Decay, forget_translations, entries\n"
        "from acausal import simulate\n"
        "from acausal.compiler.translate import translate\n"
        "simulate(translate(Decay()))\n"
        "paths = entries(Path(os.environ['ACAUSAL_CACHE_DIR']))\n"
        "for path in paths:\n"
        "    path.unlink()\n"
        f"    {sabotage}\n"
        "forget_translations()\n"
        "t = translate(Decay())\n"
        "r = simulate(t)\n"
        "print(json.dumps({'status': r.status, 'x': float(r['x'][-1]), 'entries': len(paths),\n"
        "                  'rejected': t._disk_cache().rejected,\n"
        "                  'regular': sum(stat.S_ISREG(os.lstat(p).st_mode) for p in paths)}))\n")
    try:
        proc = subprocess.run([sys.executable, str(script)], env=dict(os.environ), capture_output=True,
                              text=True, timeout=60)
    except subprocess.TimeoutExpired:
        pytest.fail(f"the run hung after `{sabotage}`")
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs here")
def test_an_entry_that_is_a_fifo_does_not_block(cache, tmp_path):
    out = _sabotaged_run(tmp_path, "os.mkfifo(path)")
    assert out["status"] == 0 and out["x"] == pytest.approx(math.exp(-2.0), rel=1e-4)
    assert out["rejected"] == out["entries"] == 2
    assert out["regular"] == 2, "the FIFOs were not replaced by entries"


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="no /dev/zero here")
def test_an_entry_that_links_to_dev_zero_is_not_read(cache, tmp_path):
    out = _sabotaged_run(tmp_path, "os.symlink('/dev/zero', path)")
    assert out["status"] == 0 and out["x"] == pytest.approx(math.exp(-2.0), rel=1e-4)
    assert out["rejected"] == out["entries"] == 2
    assert out["regular"] == 2, "the links were not replaced by entries"


def test_a_link_to_a_valid_entry_is_removed_and_its_target_kept(cache, tmp_path):
    """A symbolic link is not followed, even to a valid entry, and removing it leaves its target."""
    _, cold = run()
    targets = []
    for number, path in enumerate(entries(cache)):
        target = tmp_path / f"target {number}.json"
        target.write_bytes(path.read_bytes())
        path.unlink()
        path.symlink_to(target)
        targets.append((path, target, target.read_bytes()))
    forget_translations()
    translation, warm = run()
    assert_same(cold, warm)
    assert not loaded(translation) and translation._disk_cache().rejected == len(targets)
    for path, target, raw in targets:
        assert not path.is_symlink() and path.is_file()
        assert target.read_bytes() == raw


def test_deeply_nested_brackets_make_an_entry_invalid(cache):
    _, cold = run()
    stored = entries(cache)
    for path in stored:
        path.write_bytes(b"[" * 100_000)
    forget_translations()
    translation, warm = run()
    assert_same(cold, warm)
    assert translation._disk_cache().rejected == len(stored)
    forget_translations()
    assert len(loaded(run()[0])) == len(stored), "not written again"


def test_an_authentic_entry_that_does_not_parse_is_invalid(cache):
    """Parse failures are caught even behind a valid MAC (a RecursionError, invalid UTF-8)."""
    _, cold = run()
    secret, _ = diskcache.cache_key(cache)
    stored = entries(cache)
    bodies = [b'{"format": 2, "payload": ' + b"[" * 100_000 + b"}", b'{"format": "\xff\xfe"}']
    for path, body in zip(stored, bodies):
        path.write_bytes(diskcache._seal(body, secret))
    forget_translations()
    translation, warm = run()
    assert_same(cold, warm)
    assert translation._disk_cache().rejected == len(stored)


def test_an_entry_longer_than_the_cap_is_not_read_nor_written(cache, monkeypatch):
    """Even authentic, an entry longer than MAX_ENTRY_BYTES is refused unread; an entry
    that long is not written (it would never be read)."""
    assert 4 * 2**20 <= diskcache.MAX_ENTRY_BYTES <= 64 * 2**20
    _, cold = run()
    secret, _ = diskcache.cache_key(cache)
    stored = entries(cache)
    for path in stored:
        document = json.loads(path.read_bytes())
        del document["hmac"]
        document["padding"] = " " * diskcache.MAX_ENTRY_BYTES
        path.write_bytes(diskcache._seal(json.dumps(document).encode(), secret))
    forget_translations()
    translation, warm = run()
    assert_same(cold, warm)
    assert not loaded(translation) and translation._disk_cache().rejected == len(stored)
    assert all(path.stat().st_size < 2**20 for path in stored), "not written again"
    monkeypatch.setattr(diskcache, "MAX_ENTRY_BYTES", 2000)
    disk = DiskCache(cache, "e" * 64)
    assert not disk.store("large", {"text": "x" * 3000})
    assert disk.store("small", {"text": "x"}) and disk.load("small") == {"text": "x"}
    assert disk.load("large") is None and len(entries(disk.folder)) == 1
