"""The persistent compile cache: hit, miss, corrupt entries, engine changes, concurrent writers.

Every test has a cache folder of its own (``ACAUSAL_CACHE_DIR``) and turns
the cache on; the in-process translation cache is emptied where a test
needs a translation to come from the disk.
"""

from __future__ import annotations

import json
import multiprocessing
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import acausal.compiler.diskcache as diskcache
import acausal.compiler.persist as persist
import acausal.compiler.translate as translate_module
from acausal import Model, simulate
from acausal.compiler.diskcache import DiskCache
from acausal.compiler.translate import translate
from examples.coupled_clutches import CoupledClutches
from examples.first import First

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def folder(tmp_path, monkeypatch):
    monkeypatch.setenv("ACAUSAL_DISK_CACHE", "on")
    monkeypatch.setenv("ACAUSAL_CACHE_DIR", str(tmp_path / "cache"))
    forget_translations()
    yield tmp_path / "cache"
    forget_translations()


def forget_translations():
    translate_module._CACHE.clear()
    translate_module._STRUCTURES.clear()


def entries(folder: Path) -> list[Path]:
    return sorted(folder.rglob("*.json")) if folder.exists() else []


def run(make, **options):
    translation = translate(make())
    return translation, simulate(translation, **options)


def assert_same(a, b):
    assert a.status == b.status == 0, (a.message, b.message)
    np.testing.assert_array_equal(a.time, b.time)
    assert sorted(a.names) == sorted(b.names)
    for name in a.names:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


def loaded(translation) -> list:
    systems = list(translation.systems.values()) + list(translation.initial_systems.values())
    systems += list(translation.parts.values()) + list(translation.initial_parts.values())
    return [s for s in systems if getattr(s, "passes", ()) and s.passes[0][0] == "load"]


def test_a_miss_compiles_and_stores_a_hit_loads_the_same_systems(folder):
    cold_translation, cold = run(CoupledClutches)
    assert not loaded(cold_translation)
    stored = entries(folder)
    assert len(stored) >= len(cold_translation.systems) + len(cold_translation.initial_systems)
    forget_translations()
    warm_translation, warm = run(CoupledClutches)
    assert warm_translation is not cold_translation
    assert loaded(warm_translation), "nothing came from the disk"
    assert all(s.structure is None for s in warm_translation.systems.values())
    assert_same(cold, warm)
    # the generated code is the same text
    for key, system in warm_translation.systems.items():
        assert system.code.source == cold_translation.systems[key].code.source


def test_a_warm_fresh_process_loads_everything_and_gets_the_same_result(folder, tmp_path):
    script = tmp_path / "run.py"
    script.write_text(
        "import sys, json, hashlib\n"
        f"sys.path.insert(0, {str(ROOT)!r})\n"
        "import numpy as np\n"
        "from acausal import simulate\n"
        "from acausal.compiler.translate import translate\n"
        "from examples.first import First\n"
        "t = translate(First())\n"
        "r = simulate(t)\n"
        "data = np.column_stack([r.time] + [r[n] for n in sorted(r.names)])\n"
        "systems = list(t.systems.values()) + list(t.initial_systems.values())\n"
        "print(json.dumps({'sha': hashlib.sha256(data.tobytes()).hexdigest(),\n"
        "                  'passes': [s.passes[0][0] for s in systems]}))\n")
    env = dict(os.environ)
    outputs = []
    for _ in range(2):
        proc = subprocess.run([sys.executable, str(script)], env=env, capture_output=True, text=True,
                              timeout=120)
        assert proc.returncode == 0, proc.stderr
        outputs.append(json.loads(proc.stdout.strip().splitlines()[-1]))
    cold, warm = outputs
    assert "load" not in cold["passes"]
    assert warm["passes"] and set(warm["passes"]) == {"load"}
    assert cold["sha"] == warm["sha"]


def test_a_corrupt_entry_is_deleted_and_compiled_anew(folder):
    _, cold = run(First)
    stored = entries(folder)
    assert stored
    stored[0].write_bytes(b"\x00garbage{")
    # valid JSON whose payload was changed after its checksum was taken
    if len(stored) > 1:
        document = json.loads(stored[1].read_text())
        document["payload"]["states"] = ["nonsense"]
        stored[1].write_text(json.dumps(document))
    forget_translations()
    translation, warm = run(First)
    disk = translation._disk_cache()
    assert disk.rejected == min(len(stored), 2)
    assert_same(cold, warm)
    # rewritten, valid again
    forget_translations()
    again, _ = run(First)
    assert again._disk_cache().rejected == 0 and again._disk_cache().hits == len(stored)


def test_an_engine_change_is_another_key(folder, monkeypatch):
    cold_translation, _ = run(First)
    before = set(entries(folder))
    monkeypatch.setattr(diskcache, "_ENGINE", "another engine version")
    forget_translations()
    translation, _ = run(First)
    assert not loaded(translation)
    assert translation._disk_cache().key != cold_translation._disk_cache().key
    assert set(entries(folder)) > before


def test_an_entry_of_another_engine_in_place_is_rejected(folder, monkeypatch):
    run(First)
    for path in entries(folder):
        document = json.loads(path.read_text())
        document["engine"] = "older"
        path.write_text(json.dumps(document))
    forget_translations()
    translation, _ = run(First)
    assert not loaded(translation)
    assert translation._disk_cache().rejected > 0


def test_a_changed_parameter_is_another_key(folder):
    run(First)
    forget_translations()
    translation = translate(First(), parameters={"Jload": 3.0})
    simulate(translation)
    assert not loaded(translation)


def test_off_writes_nothing(folder, monkeypatch):
    monkeypatch.setenv("ACAUSAL_DISK_CACHE", "off")
    run(First)
    assert not entries(folder)
    forget_translations()
    monkeypatch.setenv("ACAUSAL_DISK_CACHE", "on")
    translation = translate(First(), cache=False)
    simulate(translation)
    assert not entries(folder), "cache=False must not write either"


def test_an_unwritable_folder_never_stops_a_run(folder, monkeypatch, tmp_path):
    blocker = tmp_path / "a file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("ACAUSAL_CACHE_DIR", str(blocker))
    _, result = run(First)
    assert result.status == 0


def test_clustered_parts_are_cached_too(folder):
    sys.path.insert(0, str(Path(__file__).parent))
    from test_clusters import storm

    cold_translation, cold = run(lambda: storm(2), stop_time=1.0, interval=0.01)
    assert cold_translation.clustering is not None
    forget_translations()
    warm_translation, warm = run(lambda: storm(2), stop_time=1.0, interval=0.01)
    assert warm_translation.parts and all(p.passes[0][0] == "load" for p in warm_translation.parts.values())
    assert_same(cold, warm)


def _writer(folder: str, key: str, number: int, rounds: int) -> None:
    cache = DiskCache(Path(folder), key)
    for k in range(rounds):
        cache.store("the entry", {"writer": number, "round": k, "text": "x" * (1000 * (number + 1))})


def test_concurrent_writers_leave_one_whole_entry(tmp_path):
    key = "f" * 64
    context = multiprocessing.get_context("spawn")
    writers = [context.Process(target=_writer, args=(str(tmp_path), key, n, 30)) for n in range(4)]
    for w in writers:
        w.start()
    reader = DiskCache(tmp_path, key)
    seen = []
    while any(w.is_alive() for w in writers):
        payload = reader.load("the entry")
        if payload is not None:
            seen.append(payload)
    for w in writers:
        w.join(timeout=60)
        assert w.exitcode == 0
    final = reader.load("the entry")
    assert final is not None and final["round"] == 29
    assert reader.rejected == 0, "a reader saw a partial entry"
    for payload in seen + [final]:
        assert payload["text"] == "x" * (1000 * (payload["writer"] + 1))
    assert not list(tmp_path.rglob("*.tmp")), "temporary files left behind"


def test_new_parameter_values_rebind_after_a_load(folder):
    """A fresh process that loaded its systems still rebinds other parameter values
    (the loaded system is compiled once for its stages, not once per value)."""
    run(CoupledClutches)
    forget_translations()
    base, _ = run(CoupledClutches)
    assert loaded(base)
    values = [50.0, 80.0, 120.0]
    for value in values:
        translation = translate(CoupledClutches(), parameters={"clutch1.fn_max": value})
        assert translation.rebound_from is base
        result = simulate(translation)
        fresh = simulate(translate(CoupledClutches(), cache=False, parameters={"clutch1.fn_max": value}))
        assert_same(result, fresh)
        rebound = [s for s in translation.systems.values() if s.passes[0][0] == "rebind"]
        assert rebound, f"fn_max = {value}: nothing rebound"


class _TableUnit(Model):
    """Sine -> torque -> inertia on a bearing with a two-row friction table (a table function)."""

    def build(self):
        from acausal.library.blocks import Sine
        from acausal.library.rotational import BearingFriction, Inertia, Torque

        rest = dict(start=0.0, fixed=True)
        self.s = Sine(amplitude=2.0, f=1.0)
        self.t = Torque()
        self.j = Inertia(J=1.0, phi=rest, w=rest)
        self.f = BearingFriction(tau_pos=[[0.0, 0.5], [1.0, 1.0]], peak=1.2)
        self.connect(self.s.y, self.t.tau)
        self.connect(self.t.flange, self.j.flange_a)
        self.connect(self.j.flange_b, self.f.flange_a)


def test_systems_rebound_for_other_values_are_not_stored(folder):
    """Only what was compiled for a key is stored under it: a rebound system (printed by
    another translation, with numeric choices made for other values) is not."""
    run(_TableUnit, stop_time=1.0)
    rebound = translate(_TableUnit(), parameters={"j.J": 0.5})
    assert rebound.rebound_from is not None
    stored = set(entries(folder))
    rebound_result = simulate(rebound, stop_time=1.0)
    assert set(entries(folder)) == stored
    forget_translations()
    fresh = translate(_TableUnit(), parameters={"j.J": 0.5})
    result = simulate(fresh, stop_time=1.0)
    assert not loaded(fresh) and fresh._disk_cache().hits == 0
    assert result.status == 0
    np.testing.assert_allclose(result["j.w"], rebound_result["j.w"], rtol=0, atol=1e-9)
    # its own compilation is stored, and loads with its table function
    forget_translations()
    again = translate(_TableUnit(), parameters={"j.J": 0.5})
    assert_same(simulate(again, stop_time=1.0), result)
    assert loaded(again)


def test_an_entry_that_calls_a_table_it_does_not_name_is_not_used(folder):
    cold_translation, cold = run(_TableUnit, stop_time=1.0)
    disk = cold_translation._disk_cache()
    tampered = 0
    for path in entries(folder):
        document = json.loads(path.read_text())
        payload = document["payload"]
        if payload["functions"]:
            payload["functions"] = {}
            disk.store(document["entry"], payload)  # a valid checksum over a wrong payload
            tampered += 1
    assert tampered
    forget_translations()
    translation, warm = run(_TableUnit, stop_time=1.0)
    assert_same(cold, warm)
    calls_a_table = persist._CALLED_TABLE.search
    assert not [s for s in loaded(translation) if calls_a_table(s.code.source)]


def test_the_command_line_can_turn_the_disk_cache_off(folder, tmp_path):
    from acausal.tools.cli import main

    out = tmp_path / "first.csv"
    assert main(["simulate", "examples/first.py", "--no-disk-cache", "--out", str(out)]) == 0
    assert not entries(folder)
    assert os.environ["ACAUSAL_DISK_CACHE"] == "on"  # as it was
    forget_translations()
    assert main(["simulate", "examples/first.py", "--out", str(out)]) == 0
    assert entries(folder)


def test_table_models_load_their_code_from_the_cache_and_travel_in_bundles(folder):
    """A model of table blocks (time table with its held next event, 1-D and 2-D tables): the
    second translation loads every system from the cache, a bundle rebuilds the translation in
    a pickled round trip, and all three runs give the same result."""
    import pickle

    from acausal.compiler.translate import Translation
    from examples.tables_combi_table_2ds import Test1 as Table2D
    from examples.tables_combi_time_table import Test1 as PeriodicJumps

    for make in (PeriodicJumps, Table2D):
        cold_translation, cold = run(make)
        assert entries(folder)
        forget_translations()
        warm_translation, warm = run(make)
        assert all(s.passes[0][0] == "load" for s in warm_translation.systems.values())
        assert_same(cold, warm)
        bundle = pickle.loads(pickle.dumps(cold_translation.export()))
        travelled = simulate(Translation.from_bundle(bundle))
        assert_same(cold, travelled)
