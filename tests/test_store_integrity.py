"""The chaos-map store never keeps damage and never mixes maps (issue 17, item 1).

One reference map (4 x 4 points, 4 tiles) is computed once; every case copies it, damages or changes it, re-runs
`magrod chaosmap` in-process and asserts: the exit code, the number of stderr lines, one JSON object on stdout,
which tiles were recomputed, and that the store then equals the undamaged run byte for byte -- or, for a store
that must be refused, that nothing in it changed.  The runs attach to one LocalCluster (--scheduler) so that a
case costs a connect, not a cluster start."""
import fcntl
import json
import logging
import os
import shutil
import subprocess
import sys
import warnings
from pathlib import Path

import pytest

from helpers import tree
from magrod import cli

GRID = ["--x", "lam:0.12:0.2:4", "--y", "gamma:2:4:4", "--tile", "2", "--t-max", "60"]


@pytest.fixture(scope="module")
def cluster():
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                      scheduler_kwargs={"dashboard": False, "dashboard_address": ":0"},
                      silence_logs=logging.CRITICAL) as c:
        yield c.scheduler_address


def _run(out, scheduler, *extra, capsys):
    rc = cli.main(["chaosmap", *GRID, "--out", str(out), "--scheduler", scheduler, "--json", *extra])
    cap = capsys.readouterr()
    obj = json.loads(cap.out)  # exactly one JSON object
    lines = [ln for ln in cap.err.splitlines() if ln.strip()]
    assert "Traceback" not in cap.err, cap.err
    return rc, obj, lines


@pytest.fixture(scope="module")
def reference(cluster, tmp_path_factory):
    out = tmp_path_factory.mktemp("ref") / "o"
    assert cli.main(["chaosmap", *GRID, "--out", str(out), "--scheduler", cluster, "--json", "--quiet"]) == 0
    return out


def _files(store: Path) -> dict:
    return {str(p.relative_to(store)): p.read_bytes() for p in sorted(store.rglob("*")) if p.is_file()}


def _copy(reference: Path, tmp_path: Path) -> Path:
    out = tmp_path / "o"
    shutil.copytree(reference, out, symlinks=True)
    return out


def _truncate(p: Path):
    p.write_bytes(p.read_bytes()[: len(p.read_bytes()) // 2])


def _corrupt(p: Path):
    b = bytearray(p.read_bytes())
    for i in range(len(b) // 3, len(b) // 3 + 8):
        b[i] ^= 0xFF
    p.write_bytes(bytes(b))


def _edit_json(p: Path, f):
    d = json.loads(p.read_text())
    f(d)
    p.write_text(json.dumps(d))


S, T = "chaosmap.zarr", "chaosmap.tiles"
# (case, damage(out), tiles recomputed as damaged, metadata files rewritten).  Tile 1_0 has no energy root: its
# indicator chunks equal the fill value (NaN) and zarr does not write them; status 0 (ok) is the fill of status.
DAMAGE = [
    ("delete-chunk", lambda o: (o / S / "lyap/c/0/1").unlink(), ["0_1"], 0),
    ("truncate-chunk", lambda o: _truncate(o / S / "fli/c/1/1"), ["1_1"], 0),
    ("corrupt-chunk-zstd", lambda o: _corrupt(o / S / "growth_exponent/c/1/1"), ["1_1"], 0),
    ("delete-status-chunk", lambda o: (o / S / "status/c/1/0").unlink(), ["1_0"], 0),  # NO_ROOT read as 0 = OK
    ("edit-marker-hash", lambda o: _edit_json(o / T / "0_0.json", lambda d: d.update(sha256="0" * 64)), ["0_0"], 0),
    ("marker-of-another-map", lambda o: _edit_json(o / T / "1_1.json", lambda d: d.update(identity="x")), ["1_1"], 0),
    ("edit-root-metadata", lambda o: _edit_json(o / S / "zarr.json",
                                                lambda d: d["attributes"].update(title="edited")), [], 1),
    ("edit-array-metadata", lambda o: _edit_json(o / S / "lyap/zarr.json", lambda d: d.update(fill_value=0.0)), [], 1),
    ("delete-coordinate", lambda o: shutil.rmtree(o / S / "lam"), [], 2),
    # the record's spec edited by hand, its identity not (issue 24): nothing it vouches for is trusted
    ("edit-record-spec", lambda o: _edit_json(o / T / "store.record", lambda d: d["spec"].update(t_max=300.0)),
     ["0_0", "0_1", "1_0", "1_1"], 1),
    ("delete-store", lambda o: shutil.rmtree(o / S), ["0_0", "0_1", "1_0", "1_1"], None),
]


@pytest.mark.parametrize("case,damage,repaired,rewritten", DAMAGE, ids=[d[0] for d in DAMAGE])
def test_damage_is_found_recomputed_and_counted(case, damage, repaired, rewritten, reference, cluster, tmp_path,
                                                capsys):
    out = _copy(reference, tmp_path)
    ref = _files(reference / S)
    damage(out)
    rc, obj, lines = _run(out, cluster, capsys=capsys)
    assert rc == 0 and obj["ok"] is True, (obj, lines)
    assert obj["repaired_tiles"] == repaired and obj["tiles"]["repaired"] == len(repaired)
    assert obj["tiles"]["computed"] == len(repaired) and obj["tiles"]["skipped"] == 4 - len(repaired)
    if rewritten is None:  # every file the creation wrote
        rewritten = len(json.loads((reference / T / "store.record").read_text())["skeleton"])
    assert len(obj["metadata_rewritten"]) == rewritten, obj["metadata_rewritten"]
    if repaired or rewritten:  # said once on stderr
        assert len(lines) == 1 and "damaged" in lines[0], lines
    else:
        assert lines == []
    assert _files(out / S) == ref  # exactly the undamaged run's store, byte for byte


def test_deleting_one_chunk_recomputes_exactly_that_tile(reference, cluster, tmp_path, capsys):
    """The issue's acceptance case: one chunk file deleted -> that tile, and only it, is recomputed; the marker
    times of the other tiles are unchanged and the store equals the undamaged one bit for bit."""
    out = _copy(reference, tmp_path)
    (out / S / "max_abs_dH/c/0/1").unlink()
    before = {p.name: p.stat().st_mtime_ns for p in (out / T).glob("*.json")}
    rc, obj, lines = _run(out, cluster, capsys=capsys)
    assert rc == 0 and obj["repaired_tiles"] == ["0_1"] and obj["tiles"]["computed"] == 1
    after = {p.name: p.stat().st_mtime_ns for p in (out / T).glob("*.json")}
    assert {k for k in after if after[k] != before.get(k)} == {"0_1.json"}
    assert _files(out / S) == _files(reference / S)
    # and the next run trusts it again: nothing recomputed, nothing said
    rc, obj, lines = _run(out, cluster, capsys=capsys)
    assert rc == 0 and obj["tiles"]["computed"] == 0 and obj["tiles"]["repaired"] == 0 and lines == []


def test_a_deleted_marker_is_checked_against_the_final_record(reference, cluster, tmp_path, capsys):
    out = _copy(reference, tmp_path)
    (out / T / "0_1.json").unlink()  # the chunk is fine and store.record lists its hash: nothing to recompute
    rc, obj, lines = _run(out, cluster, capsys=capsys)
    assert rc == 0 and obj["tiles"]["computed"] == 0 and lines == []
    (out / T / "1_1.json").unlink()
    (out / S / "lyap/c/1/1").unlink()  # ... but a tile with neither a good chunk nor a marker is damage
    rc, obj, lines = _run(out, cluster, capsys=capsys)
    assert rc == 0 and obj["repaired_tiles"] == ["1_1"] and len(lines) == 1
    assert _files(out / S) == _files(reference / S)


def test_a_lost_record_starts_this_map_again(reference, cluster, tmp_path, capsys):
    """store.record gone, the store's identity attribute says it is this map: nothing can be verified, so every
    tile is recomputed (never trusted) and the result is the same store."""
    out = _copy(reference, tmp_path)
    (out / T / "store.record").unlink()
    rc, obj, lines = _run(out, cluster, capsys=capsys)
    assert rc == 0 and obj["tiles"]["computed"] == 4 and obj["tiles"]["skipped"] == 0
    assert _files(out / S) == _files(reference / S)


# ------------------------------------------------------------------------------------------------------------
# refused: other maps, foreign stores, links, files, concurrent runs
# ------------------------------------------------------------------------------------------------------------
def _snapshot(root: Path) -> dict:
    return {str(p.relative_to(root)): (p.read_bytes() if p.is_file() and not p.is_symlink() else None)
            for p in sorted(root.rglob("*"))}


REFUSED = [
    # (case, prepare(out), extra argv, exit code, parameter, words in the line)
    ("other-grid", None, ["--x", "lam:0.12:0.2:5"], 2, "out", "different chaos map"),
    ("other-t-max", None, ["--t-max", "61"], 2, "out", "different chaos map"),
    ("other-panel-value", None, ["--mu", "0.41"], 2, "out", "different chaos map"),
    ("old-format-store", lambda o: (o / T / "store.record").unlink() or _edit_json(
        o / S / "zarr.json", lambda d: d["attributes"].pop("identity")), [], 2, "out", "integrity record"),
    ("foreign-directory", lambda o: (shutil.rmtree(o / S), shutil.rmtree(o / T), (o / S).mkdir(),
                                     (o / S / "data.bin").write_bytes(b"x")), [], 2, "out", "not a magrod"),
    ("store-is-a-file", lambda o: (shutil.rmtree(o / S), (o / S).write_text("x")), [], 2, "out", "not a directory"),
    ("store-is-a-symlink", lambda o: (os.rename(o / S, o / "elsewhere.zarr"), os.symlink(o / "elsewhere.zarr", o / S)),
     [], 2, "out", "symbolic link"),
    ("tiles-is-a-symlink", lambda o: (os.rename(o / T, o / "t2"), os.symlink(o / "t2", o / T)), [], 2, "out",
     "symbolic link"),
    # a directory where a file belongs (issue 24: exit 3 after a warning line, naming zarr's temporary)
    ("chunk-is-a-directory", lambda o: ((o / S / "lyap/c/0/1").unlink(), (o / S / "lyap/c/0/1").mkdir()), [], 2,
     "out", "lyap/c/0/1' is a directory where"),
    ("metadata-is-a-directory", lambda o: ((o / S / "fli/zarr.json").unlink(), (o / S / "fli/zarr.json").mkdir()),
     [], 2, "out", "fli/zarr.json' is a directory where"),
]


@pytest.mark.parametrize("case,prepare,extra,code,param,words", REFUSED, ids=[r[0] for r in REFUSED])
def test_refused_and_untouched(case, prepare, extra, code, param, words, reference, cluster, tmp_path, capsys):
    out = _copy(reference, tmp_path)
    if prepare:
        prepare(out)
    before = _snapshot(out)
    argv = list(GRID)
    for i in range(0, len(extra), 2):  # an option of GRID given again replaces it (no duplicate options)
        if extra[i] in argv:
            argv[argv.index(extra[i]) + 1] = extra[i + 1]
        else:
            argv += extra[i:i + 2]
    rc = cli.main(["chaosmap", *argv, "--out", str(out), "--scheduler", cluster, "--json"])
    cap = capsys.readouterr()
    obj = json.loads(cap.out)
    lines = [ln for ln in cap.err.splitlines() if ln.strip()]
    assert rc == code and obj["parameter"] == param, (obj, lines)
    assert len(lines) == 1 and words in lines[0] and "Traceback" not in cap.err, lines
    if "symlink" in case or case == "store-is-a-file":
        assert str(out / (S if "store" in case else T)) in lines[0]  # the path is named
    assert _snapshot(out) == before  # nothing written, nothing deleted, no lock file left


def test_force_starts_over_and_keeps_what_magrod_did_not_write(reference, cluster, tmp_path, capsys):
    out = _copy(reference, tmp_path)
    (out / S / "notes.txt").write_text("mine")
    (out / S / "lyap" / "README").write_text("mine too")
    (out / T / "todo.txt").write_text("and this")
    argv = [a if a != "60" else "61" for a in GRID]  # another T
    rc = cli.main(["chaosmap", *argv, "--out", str(out), "--scheduler", cluster, "--json", "--force"])
    obj = json.loads(capsys.readouterr().out)
    assert rc == 0 and obj["spec"]["t_max"] == 61.0 and obj["tiles"]["computed"] == 4
    assert (out / S / "notes.txt").read_text() == "mine" and (out / S / "lyap" / "README").read_text() == "mine too"
    assert (out / T / "todo.txt").read_text() == "and this"
    # a plain re-run of the new map trusts it; the old map's command is now refused
    rc, obj, lines = _run(out, cluster, capsys=capsys)
    assert rc == 2 and "different chaos map" in lines[0]


def test_unrelated_files_survive_a_rerun(reference, cluster, tmp_path, capsys):
    out = _copy(reference, tmp_path)
    (out / S / "notes.txt").write_text("mine")
    rc, obj, lines = _run(out, cluster, capsys=capsys)
    assert rc == 0 and (out / S / "notes.txt").read_text() == "mine"


def test_concurrent_run_is_refused(reference, cluster, tmp_path, capsys):
    out = _copy(reference, tmp_path)
    before = _snapshot(out)
    with open(out / ".chaosmap.lock", "a+") as fh:  # another run holds the lock
        fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        rc = cli.main(["chaosmap", *GRID, "--out", str(out), "--scheduler", cluster, "--json"])
    cap = capsys.readouterr()
    assert rc == 3 and json.loads(cap.out)["parameter"] == "out"
    lines = [ln for ln in cap.err.splitlines() if ln.strip()]
    assert len(lines) == 1 and "another magrod chaosmap" in lines[0]
    (out / ".chaosmap.lock").unlink()
    assert _snapshot(out) == before


def test_stale_temporaries_are_removed_live_ones_kept(reference, cluster, tmp_path, capsys):
    out = _copy(reference, tmp_path)
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                          text=True).stdout.strip()
    live = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        stale = [out / f".chaosmap.json.{dead}.abcd1234.tmp", out / T / f".0_0.json.{dead}.zz99yy88.tmp",
                 out / S / "lyap/c/0" / ("0." + "ab" * 16 + ".partial")]
        kept = [out / f".chaosmap.png.{live.pid}.abcd1234.tmp", out / S / "unrelated.partial"]
        for p in stale + kept:
            p.write_bytes(b"half")
        rc, obj, lines = _run(out, cluster, capsys=capsys)
        assert rc == 0 and lines == []
        assert not any(p.exists() for p in stale) and all(p.exists() for p in kept)
    finally:
        live.kill()
        live.wait()


def test_consolidated_metadata_opens_without_a_warning(reference):
    import xarray as xr

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        ds = xr.open_zarr(str(reference / S))  # plain: consolidated=None tries and must find it
    assert ds["growth_exponent"].dims == ("gamma", "lam") and len(ds.attrs["identity"]) == 64


def test_the_record_is_written_last(reference):
    rec = json.loads((reference / T / "store.record").read_text())
    markers = {p.stem: json.loads(p.read_text())["sha256"] for p in (reference / T).glob("*.json")}
    assert rec["complete"] is True and rec["tiles"] == markers and len(markers) == 4
    assert (reference / T / "store.record").stat().st_mtime_ns >= max(p.stat().st_mtime_ns for p in
                                                                       (reference / T).glob("*.json"))


def test_a_worker_that_writes_elsewhere_is_caught(reference, tmp_path, monkeypatch):
    """The client reads every tile back: a worker writing into another store of the same map (another machine's
    filesystem at the same path) is an EnvironmentFault naming the path, not a map of NaNs."""
    from distributed import Client, LocalCluster

    from magrod.chaos import maps
    from magrod.store import tiles as store
    from magrod.core.errors import EnvironmentFault

    out = _copy(reference, tmp_path)
    other = _copy(reference, tmp_path / "other")
    for d in (out, other):
        (d / S / "lyap/c/0/0").unlink()
    spec = maps.MapSpec.from_dict(json.loads((reference / T / "store.record").read_text())["spec"])
    real = store.tile_task
    monkeypatch.setattr(store, "tile_task", lambda sd, k, s, t, i: real(sd, k, str(other / S), str(other / T), i))
    state = store.create_or_open(spec, out / S, out / T)
    assert state.repaired == ["0_0"]
    with LocalCluster(n_workers=1, processes=False, dashboard_address=None, threads_per_worker=1,
                      scheduler_kwargs={"dashboard": False, "dashboard_address": ":0"}) as lc, Client(lc) as client:
        with pytest.raises(EnvironmentFault, match="does not read back") as e:
            store.run_tiles(spec, out / S, out / T, client=client, state=state)
    assert str(out / S) in e.value.message


def test_a_worker_refuses_a_store_of_another_map(reference, tmp_path):
    from magrod.chaos import maps
    from magrod.store import tiles as store
    from magrod.core.errors import EnvironmentFault

    out = _copy(reference, tmp_path)
    spec = maps.MapSpec.from_dict(json.loads((reference / T / "store.record").read_text())["spec"])
    tile = maps.tile_of(spec, "0_0")
    fields = store.read_tile(out / S, tile)
    with pytest.raises(EnvironmentFault, match="another map"):
        store.write_tile(out / S, out / T, tile, fields, 0.0, "f" * 64)
    with pytest.raises(EnvironmentFault, match="no chaos map store"):
        store.write_tile(tmp_path / "nowhere.zarr", out / T, tile, fields, 0.0, "f" * 64)


def test_a_worker_out_of_memory_is_not_called_another_filesystem(reference, tmp_path, monkeypatch):
    """Only a store that is not there means "the workers need a shared filesystem"; a worker that runs out of memory
    opening it must say so, not send the user looking for a filesystem problem."""
    import zarr

    from magrod.chaos import maps
    from magrod.store import tiles as store

    out = _copy(reference, tmp_path)
    spec = maps.MapSpec.from_dict(json.loads((reference / T / "store.record").read_text())["spec"])
    tile = maps.tile_of(spec, "0_0")
    fields = store.read_tile(out / S, tile)

    def no_memory(*a, **k):
        raise MemoryError("cannot allocate")

    monkeypatch.setattr(zarr, "open_group", no_memory)
    with pytest.raises(MemoryError):
        store.write_tile(out / S, out / T, tile, fields, 0.0, "f" * 64)


# ------------------------------------------------------------------------------------------------------------
# a full disk (ENOSPC), simulated in-process: a tmpfs or loop device would need mount privileges the tests do not
# assume.  The writers are the real ones with one system call replaced.
# ------------------------------------------------------------------------------------------------------------
def _enospc(*a, **k):
    import errno

    raise OSError(errno.ENOSPC, "No space left on device")


def test_full_disk_while_creating_the_store(cluster, tmp_path, monkeypatch, capsys):
    import zarr.storage._local as local

    monkeypatch.setattr(local, "_put", _enospc)
    before = _tree(tmp_path)
    rc, obj, lines = _run(tmp_path / "o", cluster, capsys=capsys)
    assert rc == 3 and obj["parameter"] == "out" and len(lines) == 1, (obj, lines)
    assert "no space left" in lines[0] and str(tmp_path / "o" / S) in lines[0]
    assert _tree(tmp_path) == before  # nothing partial: no store, no temporary, no OUT


def test_full_disk_while_writing_the_summary(reference, cluster, tmp_path, monkeypatch, capsys):
    """The map is complete, the summary cannot be written: exit 3 naming the file, no half file, no temporary,
    no picture without its summary; the store's finished tiles stay and the next run only writes the summary."""
    import magrod.core.io as io

    out = _copy(reference, tmp_path)
    for f in ("chaosmap.json", "chaosmap.png"):
        (out / f).unlink()
    real = os.fsync

    def fsync(fd):
        if os.readlink(f"/proc/self/fd/{fd}").split("/")[-1].startswith(".chaosmap.json."):
            _enospc()
        return real(fd)

    monkeypatch.setattr(io.os, "fsync", fsync)
    rc, obj, lines = _run(out, cluster, capsys=capsys)
    assert rc == 3 and len(lines) == 1 and "chaosmap.json" in lines[0] and "No space left" in lines[0], lines
    assert not (out / "chaosmap.json").exists() and not (out / "chaosmap.png").exists()
    assert not list(out.rglob("*.tmp"))
    monkeypatch.setattr(io.os, "fsync", real)
    rc, obj, lines = _run(out, cluster, capsys=capsys)
    assert rc == 0 and obj["tiles"]["computed"] == 0 and (out / "chaosmap.json").exists()


_tree = tree

def test_a_map_with_no_computed_point_is_a_failure(cluster, tmp_path, capsys):
    """Every start impossible (no energy root anywhere at h = -50): exit 1, one line, ok false, no picture and no
    summary -- never an ok map of NaNs.  The store itself is complete and says the same on a re-run."""
    out = tmp_path / "o"
    for _ in range(2):
        rc, obj, lines = _run(out, cluster, "--h", "-50", capsys=capsys)
        assert rc == 1 and obj["ok"] is False and "no point of the map could be computed" in obj["error"], obj
        assert len(lines) == 1 and "no_energy_root" in lines[0], lines
        assert not (out / "chaosmap.png").exists() and not (out / "chaosmap.json").exists()


def test_a_full_disk_in_a_worker_names_the_store():
    """A worker's ENOSPC from zarr's chunk write carries no file name: the one line names the store (issue 24:
    'no space left on the device (2 of 16 tiles finished and kept; re-run to resume)' named nothing)."""
    import errno

    from magrod.store.tiles import TileFailure
    from magrod.store.resumable import tile_failure
    from magrod.core.errors import EnvironmentFault

    exc = TileFailure("0_1", OSError(errno.ENOSPC, "No space left on device"))
    with pytest.raises(EnvironmentFault) as e:
        tile_failure(exc, None, 2, 16, Path("/data/o/chaosmap.zarr"))
    assert "/data/o/chaosmap.zarr" in e.value.message and "2 of 16 tiles finished and kept" in e.value.message
