"""Chaos maps on disk: the resumable zarr store of a map and its tiles run on Dask (I/O; the numerics are in
magrod.chaos.maps and .indicators, the cluster's lifecycle in magrod.store.cluster, a whole stored map in
magrod.store.resumable).

Layout of OUT (stem "chaosmap" by default):
  OUT/<stem>.zarr          chunked zarr store (consolidated metadata: a plain xr.open_zarr opens it without a
                           warning), one chunk per tile, an xarray Dataset with coordinates (y-parameter,
                           x-parameter), units and provenance attributes, among them `spec` and `identity`
  OUT/<stem>.tiles/        the store's record and one done-marker per finished tile:
    store.record           identity (sha256 of the spec, the store format and the versions of magrod, heyoka and
                           numpy), the sha256 of every file the creation wrote (metadata and coordinates), and,
                           once a run has finished every tile, the content hash of every tile (written last,
                           atomically)
    <iy>_<ix>.json         {tile, identity, sha256, wall_s, points}: written atomically after the tile's chunk
  OUT/.<stem>.lock         held (flock) for the whole run: a second run into the same store fails at once

Integrity.  A tile is done iff a record of it (its marker, or the final list in store.record) carries this store's
identity and the sha256 of its content (every field's dtype, shape and bytes, read back from the store) equals
the recorded one.  A re-run verifies every done tile before trusting it: a deleted, truncated or corrupted chunk,
an edited marker, a missing store, are found, recomputed and counted ("repaired").  Damaged metadata (the files
the creation wrote) is rewritten from the spec when the rewrite reproduces the recorded hashes (the chunks are
then verified as usual); otherwise the store is rebuilt.  A store of another map (other grid, parameters,
tolerances, code version) is refused (ParameterError "out"; force=True starts over).  Nothing is deleted that
magrod did not write: starting over removes the files of the store layout (metadata, chunk files, zarr's
half-written `.partial` files, our markers and temporaries) and leaves anything else where it is.  A store path
that is a symbolic link is refused.

Dask.  run_tiles starts a LocalCluster (processes, threads_per_worker=1, no dashboard) unless a client (connect()
to a running scheduler) is given.  Every tile is a pure function of (spec, tile) computed by
magrod.chaos.maps.compute_tile, so the result is bit-identical whatever the number of workers or the order the
tiles run in (on one CPU type: workers on other machines compile heyoka for their own instruction set, e.g. with
or without FMA, and may differ in the last bits; the batch size is part of the spec, so it is the same
everywhere).  Workers write into the store at the absolute path they are given, so they need that same path (a
shared filesystem); a worker refuses to write into a store whose identity is not the map's, and the client reads
every tile back and checks its hash, so a worker writing elsewhere is an error, never a silent NaN map.
"""
from __future__ import annotations

import hashlib
import json
import os
import re
import time
import warnings
from concurrent.futures import CancelledError
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..chaos import indicators as chaos, maps
from ..core.errors import EnvironmentFault, ParameterError
from ..core.io import atomic_write_json
from .cluster import check_cluster, close_quietly, connect, start_local_cluster, stop_local_cluster, worker_env

STORE_FORMAT = 2  # 1: markers without hashes
FIELDS = tuple(maps.MAP_FIELDS) + ("status",)  # the order of the content hash
_REFINED = FIELDS + maps.REFINE_FIELDS  # the arrays of a refined store
# every array a store may hold (what starting over may remove), in the order of the content hash
ALL_FIELDS = _REFINED + maps.EARLY_EXIT_FIELDS


def names_of(spec: maps.MapSpec) -> tuple:
    """The arrays of this map's store, in the order of the content hash: FIELDS, for a refined map
    "inferred" and "level" after them, for a map with early exit "exit_time" (a brute-force store without early
    exit is what it was before)."""
    return FIELDS + (maps.REFINE_FIELDS if spec.refine else ()) + (maps.EARLY_EXIT_FIELDS if spec.early_exit else ())


# the CF attributes (units, long names, status flags) are defined once, in maps.py (ChaosMap.to_xarray uses them)
from ..chaos.maps import LONG, UNITS, _axis_label, coord_attrs, dataset_attrs, variable_attrs  # noqa: E402,F401


def paths(out: Path, stem: str) -> dict:
    out = Path(out)
    return {"store": out / f"{stem}.zarr", "tiles": out / f"{stem}.tiles", "png": out / f"{stem}.png",
            "json": out / f"{stem}.json", "lock": out / f".{stem}.lock"}


# ------------------------------------------------------------------------------------------------------------
# identity and content hashes
# ------------------------------------------------------------------------------------------------------------
def _spec_json(spec: maps.MapSpec) -> str:
    return json.dumps(spec.to_dict(), sort_keys=True)


def code_versions() -> dict:
    """The versions whose change can change a map's numbers (part of the identity: tiles of two are not mixed)."""
    from importlib.metadata import version

    from .. import __version__

    return {"magrod": __version__, "heyoka": version("heyoka"), "numpy": version("numpy")}


def identity(spec: maps.MapSpec) -> str:
    """sha256 of what a map is: spec (grid, parameters, tolerances, tile, batch size), store format, code."""
    doc = {"spec": spec.to_dict(), "format": STORE_FORMAT, "code": code_versions()}
    return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()


def tile_hash(fields: dict, names=FIELDS) -> str:
    """sha256 of one tile's content: every field (`names` order) as name, dtype, shape and C-order bytes."""
    h = hashlib.sha256()
    for k in names:
        a = np.ascontiguousarray(fields[k])
        h.update(f"{k}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()


_INT8 = ("status",) + maps.REFINE_FIELDS


def _store_dtypes(fields: dict) -> dict:
    return {k: np.asarray(v, dtype=np.int8 if k in _INT8 else np.float64) for k, v in fields.items()}


def read_tile(store: Path, tile: maps.Tile, group=None, names=FIELDS) -> dict:
    """One tile's fields as stored (raises on an unreadable chunk or metadata)."""
    import zarr

    g = group if group is not None else zarr.open_group(str(store), mode="r")
    return {k: np.asarray(g[k][tile.ys, tile.xs]) for k in names}


def _hash_of_stored(store: Path, tile: maps.Tile, group=None, names=FIELDS) -> str | None:
    try:
        return tile_hash(read_tile(store, tile, group, names), names)
    except Exception:  # noqa: BLE001 - a missing, truncated or corrupt chunk (zstd error, ...) is damage
        return None


def _file_sha(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _skeleton_hashes(root: Path) -> dict:
    """{relative path: sha256} of every file under root (the files a store's creation writes)."""
    return {str(p.relative_to(root)): _file_sha(p) for p in sorted(root.rglob("*")) if p.is_file()}


# ------------------------------------------------------------------------------------------------------------
# what magrod writes, and nothing else, may be removed
# ------------------------------------------------------------------------------------------------------------
_CHUNK = re.compile(r"^\d+$")
_PARTIAL = re.compile(r"^\d+\.[0-9a-f]{32}\.partial$")  # zarr's LocalStore temporary of a chunk write
_MARKER = re.compile(r"^\d+_\d+\.json$")
_ROUND_MARKER = re.compile(r"^r\d+_\d+_\d+\.json$")  # a refinement round's part of one tile


def _refuse_symlink(p: Path) -> None:
    if p.is_symlink():
        raise ParameterError("out", f"{str(p)!r} is a symbolic link: refusing to write through it (give --out a real "
                                    f"directory, or remove the link)")


def check_paths(pth: dict) -> None:
    """ParameterError("out") if the store, its tile directory, the record or the lock is a symbolic link or the
    store/tile path exists and is not a directory."""
    for k in ("store", "tiles", "lock"):
        _refuse_symlink(pth[k])
    _refuse_symlink(pth["tiles"] / "store.record")
    for k in ("store", "tiles"):
        if pth[k].exists() and not pth[k].is_dir():
            raise ParameterError("out", f"{str(pth[k])!r} exists and is not a directory")


def _remove_store_files(store: Path, names) -> None:
    """Remove the files of the store layout (root zarr.json; per variable in `names` its zarr.json, chunk files
    c/I[/J] and zarr's .partial temporaries) and the directories left empty; keep anything else."""
    if not store.is_dir() or store.is_symlink():
        return
    _unlink(store / "zarr.json")
    for v in names:
        d = store / v
        if not d.is_dir() or d.is_symlink():
            continue
        _unlink(d / "zarr.json")
        c = d / "c"
        if c.is_dir() and not c.is_symlink():
            for p in sorted(c.rglob("*"), key=lambda q: -len(q.parts)):
                if p.is_symlink():
                    continue
                if p.is_file() and (_CHUNK.match(p.name) or _PARTIAL.match(p.name)):
                    _unlink(p)
                elif p.is_dir():
                    _rmdir(p)
            _rmdir(c)
        _rmdir(d)
    _rmdir(store)


def _remove_markers(tiles_dir: Path) -> None:
    if tiles_dir.is_dir() and not tiles_dir.is_symlink():
        for p in tiles_dir.iterdir():
            if (_MARKER.match(p.name) or _ROUND_MARKER.match(p.name)) and p.is_file() and not p.is_symlink():
                _unlink(p)
        _unlink(tiles_dir / "store.record")


def _unlink(p: Path) -> None:
    try:
        if p.is_file() and not p.is_symlink():
            p.unlink()
    except OSError:
        pass


def _rmdir(p: Path) -> None:
    try:
        p.rmdir()
    except OSError:  # not empty (something we did not write is in it) or gone
        pass


def remove_temporaries(pth: dict, pids=()) -> None:
    """Temporaries of interrupted writes: our atomic-write temporaries (OUT, the tile directory) and zarr's
    `.partial` chunk files in the store (only called while the lock is held and no worker of ours runs)."""
    from ..core.io import remove_stale_temporaries

    remove_stale_temporaries(pth["store"].parent, pids)
    remove_stale_temporaries(pth["tiles"], pids)
    store = pth["store"]
    if store.is_dir() and not store.is_symlink():
        for v in ALL_FIELDS:
            c = store / v / "c"
            if c.is_dir() and not c.is_symlink():
                for p in c.rglob("*.partial"):
                    if _PARTIAL.match(p.name) and p.is_file() and not p.is_symlink():
                        _unlink(p)


# ------------------------------------------------------------------------------------------------------------
# creating, opening and verifying a store
# ------------------------------------------------------------------------------------------------------------
@dataclass
class StoreState:
    """What a run found in the store: `done` tiles verified, `repaired` tiles that were recorded as done but failed
    verification (to be recomputed), `created` if this run made the store."""

    store: Path
    tiles_dir: Path
    identity: str
    done: set = field(default_factory=set)
    repaired: list = field(default_factory=list)
    created: bool = False
    metadata_rewritten: list = field(default_factory=list)


def _read_json(p: Path):
    try:
        return json.loads(Path(p).read_text())
    except (OSError, ValueError, UnicodeDecodeError):
        return None


def _write_skeleton(spec: maps.MapSpec, ident: str, target: Path) -> None:
    """Metadata, coordinates and attributes of an empty store, written (consolidated) into the new directory
    `target`; the data chunks are written tile by tile."""
    import dask.array as da
    import xarray as xr

    from ..core.io import versions

    chunks = (spec.tile, spec.tile)
    dims = (spec.y.name, spec.x.name)
    data = {k: (dims, da.full(spec.shape, np.nan, chunks=chunks), variable_attrs(k)) for k in maps.MAP_FIELDS}
    data["status"] = (dims, da.full(spec.shape, chaos.FAILED, dtype=np.int8, chunks=chunks), variable_attrs("status"))
    if spec.refine:  # which points were computed, and in which round
        data["inferred"] = (dims, da.full(spec.shape, 0, dtype=np.int8, chunks=chunks), variable_attrs("inferred"))
        data["level"] = (dims, da.full(spec.shape, -1, dtype=np.int8, chunks=chunks), variable_attrs("level"))
    for k in maps.EARLY_EXIT_FIELDS if spec.early_exit else ():  # the time an orbit stopped
        data[k] = (dims, da.full(spec.shape, np.nan, chunks=chunks), variable_attrs(k))
    coords = {spec.x.name: (spec.x.name, spec.x.values(), coord_attrs(spec.x.name)),
              spec.y.name: (spec.y.name, spec.y.values(), coord_attrs(spec.y.name))}
    ds = xr.Dataset(data, coords=coords, attrs={
        **dataset_attrs(spec), "spec": _spec_json(spec), "identity": ident, "store_format": STORE_FORMAT,
        "versions": json.dumps(versions(), sort_keys=True)})
    with warnings.catch_warnings():  # "consolidated metadata is not part of the zarr v3 spec": we know
        warnings.simplefilter("ignore")
        # compute=False writes metadata and coordinates; the data chunks are written tile by tile
        ds.to_zarr(str(target), mode="w-", compute=False, consolidated=True)


def _fresh_skeleton(spec, ident, store: Path) -> tuple[Path, dict]:
    """A complete skeleton in a temporary sibling directory of the store, and its file hashes."""
    import tempfile

    tmp = Path(tempfile.mkdtemp(dir=store.parent, prefix=f".{store.name}.{os.getpid()}.", suffix=".new"))
    target = tmp / "s.zarr"
    try:
        _write_skeleton(spec, ident, target)
    except BaseException:
        _remove_tree_we_made(tmp)
        raise
    return tmp, _skeleton_hashes(target)


def _remove_tree_we_made(tmp: Path) -> None:
    import shutil

    if tmp.is_dir() and not tmp.is_symlink():
        shutil.rmtree(tmp, ignore_errors=True)


def _install_skeleton(tmp: Path, store: Path, only=None) -> None:
    """Move the skeleton's files into the store (all, or the relative paths in `only`), each by rename."""
    src = tmp / "s.zarr"
    if only is None and not store.exists():
        os.rename(src, store)  # a new store appears whole
        return
    for p in sorted(src.rglob("*")):
        rel = str(p.relative_to(src))
        if p.is_file() and (only is None or rel in only):
            dst = store / rel
            dst.parent.mkdir(parents=True, exist_ok=True)
            os.replace(p, dst)


def create_or_open(spec: maps.MapSpec, store: Path, tiles_dir: Path, *, force=False) -> StoreState:
    """Create the empty store, or open and verify an existing one that holds this map.

    Raises ParameterError("out") if the store holds a different map (other grid, parameters, tolerances or
    code version), was not written by this version of magrod's store code, or a path is a symbolic link (pass
    force=True to start over: only the files of the store layout are removed).  Returns the StoreState: the
    verified done tiles and the damaged ones (recorded as done, failed verification), which are recomputed."""
    store, tiles_dir = Path(store), Path(tiles_dir)
    pth = {"store": store, "tiles": tiles_dir, "lock": store.parent / f".{store.stem}.lock"}
    check_paths(pth)
    ident = identity(spec)
    rec = _read_json(tiles_dir / "store.record")
    rec = rec if isinstance(rec, dict) and isinstance(rec.get("skeleton"), dict) else None
    inconsistent = rec is not None and rec.get("identity") == ident and not _record_is_consistent(rec)
    names = list(ALL_FIELDS) + [spec.x.name, spec.y.name]
    has_store = store.exists() and any(store.iterdir())
    if rec is not None and rec.get("identity") != ident and not force:
        other = rec.get("spec")
        raise ParameterError("out", f"{str(store)!r} holds a different chaos map (other grid, parameters, tolerances or "
                                    f"code version{'' if other is None else ': ' + _spec_diff(other, spec)}); use "
                                    f"another --out/--stem or --force to overwrite it")
    if rec is None and has_store and not force:
        attrs = _read_json(store / "zarr.json")
        attrs = (attrs.get("attributes") or {}) if isinstance(attrs, dict) else {}
        if attrs.get("identity") != ident:  # this very map's store with its record gone is started again below
            raise ParameterError("out", f"{str(store)!r} " + (
                "is a chaos map store without an integrity record (written before store format 2, or by another "
                f"map; its record {str(tiles_dir / 'store.record')!r} is missing)" if "spec" in attrs else
                "exists and is not a magrod chaos map store")
                + "; use another --out/--stem or --force to start over (only the files of a magrod store are "
                  "removed)")
    if inconsistent and not force:
        # this map's identity over an edited spec: nothing the record vouches for can be trusted; start again,
        # and say so (every recorded tile is recomputed)
        recorded = sorted(_recorded_tiles(spec, ident, tiles_dir, rec))
        _remove_store_files(store, set(names))
        _remove_markers(tiles_dir)
        st = _create(spec, ident, store, tiles_dir)
        st.repaired = recorded
        st.metadata_rewritten = ["store.record"]
        return st
    if force or rec is None or rec.get("identity") != ident:
        if rec is not None:
            names += [a["name"] for a in (rec.get("spec") or {}).values() if isinstance(a, dict) and "name" in a
                      and isinstance(a["name"], str) and "/" not in a["name"]]
        _remove_store_files(store, set(names))
        _remove_markers(tiles_dir)
        return _create(spec, ident, store, tiles_dir)
    return _open(spec, ident, store, tiles_dir, rec)


def _spec_diff(other: dict, spec: maps.MapSpec) -> str:
    mine = spec.to_dict()
    keys = [k for k in sorted(set(mine) | set(other)) if mine.get(k) != other.get(k)]
    return "differs in " + ", ".join(keys) if keys else "same spec, other code version"


def _create(spec, ident, store: Path, tiles_dir: Path) -> StoreState:
    from ..core.io import resource_fault

    store.parent.mkdir(parents=True, exist_ok=True)
    try:
        tmp, skel = _fresh_skeleton(spec, ident, store)
    except OSError as exc:  # disk full, file-size limit ...: name the store, not our temporary
        raise resource_fault(exc, "out", store) from None
    try:
        tiles_dir.mkdir(exist_ok=True)
        _install_skeleton(tmp, store)
    finally:
        _remove_tree_we_made(tmp)
    _write_record(spec, ident, tiles_dir, skel, tiles=None)
    return StoreState(store, tiles_dir, ident, created=True)


def _write_record(spec, ident, tiles_dir: Path, skeleton: dict, tiles: dict | None) -> None:
    atomic_write_json(tiles_dir / "store.record", {
        "identity": ident, "format": STORE_FORMAT, "spec": spec.to_dict(), "code": code_versions(),
        "skeleton": skeleton, "complete": tiles is not None, "tiles": tiles or {}})


def _record_is_consistent(rec: dict) -> bool:
    """The integrity record agrees with itself: its spec, format and code hash to its identity (`identity`).  A
    record whose spec was edited by hand (t_max 200 -> 300) but whose identity was not would otherwise be taken
    for this map's, and its tiles reused as if computed with the edited spec."""
    try:
        doc = {"spec": rec["spec"], "format": rec["format"], "code": rec["code"]}
        return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest() == rec.get("identity")
    except (KeyError, TypeError, ValueError):
        return False


def _refuse_directories_at_files(spec, store: Path, skel: dict) -> None:
    """A directory where the store keeps a file (a metadata file of the skeleton, a chunk c/I/J) is not magrod's
    to remove: refuse with one line naming it (zarr's write would fail on it, naming its own temporary,
    after a warning line)."""
    if not store.is_dir():
        return
    for rel in skel:
        if (store / rel).is_dir():
            raise ParameterError("out", f"{str(store / rel)!r} is a directory where the chaos map store keeps a "
                                        "file; remove it, or use --force to start over")
    ndim = {**{k: 2 for k in names_of(spec)}, spec.x.name: 1, spec.y.name: 1}
    for name, n in ndim.items():
        c = store / name / "c"
        if not c.is_dir() or c.is_symlink():
            continue
        for q in c.rglob("*"):
            parts = q.relative_to(c).parts
            if len(parts) == n and q.is_dir() and all(_CHUNK.match(x) for x in parts):
                raise ParameterError("out", f"{str(q)!r} is a directory where the chaos map store keeps a chunk "
                                            "file; remove it, or use --force to start over")


def _open(spec, ident, store: Path, tiles_dir: Path, rec: dict) -> StoreState:
    state = StoreState(store, tiles_dir, ident)
    skel = rec["skeleton"]
    _refuse_directories_at_files(spec, store, skel)
    have = _skeleton_hashes(store) if store.is_dir() else {}
    bad = sorted(k for k, v in skel.items() if have.get(k) != v)
    if bad:  # metadata or coordinates damaged or missing: rewrite them from the spec if that reproduces them
        tmp, fresh = _fresh_skeleton(spec, ident, store)
        try:
            if fresh == skel:
                store.mkdir(exist_ok=True)
                _install_skeleton(tmp, store, only=set(bad))
                state.metadata_rewritten = bad
            else:  # this environment writes other metadata bytes: rebuild the store from scratch
                recorded = _recorded_tiles(spec, ident, tiles_dir, rec)
                _remove_store_files(store, set(ALL_FIELDS) | {spec.x.name, spec.y.name})
                _remove_markers(tiles_dir)
                st = _create(spec, ident, store, tiles_dir)
                st.repaired = sorted(recorded)
                return st
        finally:
            _remove_tree_we_made(tmp)
    tiles_dir.mkdir(exist_ok=True)
    recorded = _recorded_tiles(spec, ident, tiles_dir, rec)
    import zarr

    try:
        group = zarr.open_group(str(store), mode="r")
    except Exception:  # noqa: BLE001 - unreadable although the skeleton matched: every tile is suspect
        group = None
    for key, digest in sorted(recorded.items()):
        tile = maps.tile_of(spec, key)
        if digest is not None and group is not None and _hash_of_stored(store, tile, group,
                                                                         names_of(spec)) == digest:
            state.done.add(key)
        else:
            state.repaired.append(key)
            _unlink(tiles_dir / f"{key}.json")
    return state


def _recorded_tiles(spec, ident, tiles_dir: Path, rec: dict) -> dict:
    """{tile key: recorded sha256, or None if its records disagree or are malformed} over markers and the final
    list of store.record."""
    n_y, n_x = -(-spec.y.n // spec.tile), -(-spec.x.n // spec.tile)
    out: dict = {}

    def note(key, digest):
        try:
            iy, ix = (int(v) for v in str(key).split("_"))
        except ValueError:
            return
        if not (0 <= iy < n_y and 0 <= ix < n_x) or str(key) != f"{iy}_{ix}":
            return
        ok = isinstance(digest, str) and len(digest) == 64
        if key in out and out[key] != digest:
            ok = False
        out[key] = digest if ok and out.get(key, digest) is not None else None

    for key, digest in (rec.get("tiles") or {}).items() if isinstance(rec.get("tiles"), dict) else ():
        note(key, digest)
    if tiles_dir.is_dir():
        for p in tiles_dir.iterdir():
            if not _MARKER.match(p.name):
                continue
            m = _read_json(p) if p.is_file() and not p.is_symlink() else None
            good = isinstance(m, dict) and m.get("identity") == ident and m.get("tile") == p.stem
            note(p.stem, m.get("sha256") if good else None)
    return out


def done_tiles(tiles_dir: Path) -> set:
    """Tiles with a marker, or a refinement round's marker (unverified: use create_or_open for the verified set)."""
    return {p.stem for p in Path(tiles_dir).glob("*.json") if _MARKER.match(p.name) or _ROUND_MARKER.match(p.name)}


def finish(spec: maps.MapSpec, state: StoreState) -> None:
    """Record every tile's hash in store.record (written last and atomically): the store is complete."""
    rec = _read_json(state.tiles_dir / "store.record") or {}
    tiles = {}
    for t in maps.tiles(spec):
        m = _read_json(state.tiles_dir / f"{t.key}.json")
        if not isinstance(m, dict) or m.get("identity") != state.identity:
            return  # not complete (or damaged since): nothing to record
        tiles[t.key] = m["sha256"]
    _write_record(spec, state.identity, state.tiles_dir, rec.get("skeleton") or {}, tiles)


# ------------------------------------------------------------------------------------------------------------
# the work: one tile per task
# ------------------------------------------------------------------------------------------------------------
def write_tile(store: Path, tiles_dir: Path, tile: maps.Tile, fields: dict, wall_s: float, ident: str | None = None,
               marker: bool = True) -> str:
    """Region write of one tile's chunk, then its done-marker with the content hash (atomically).  Refuses (an
    EnvironmentFault naming "out") a store at this path whose identity is not `ident`: a worker that sees another
    filesystem than the client must not fill some other store.  Returns the content hash."""
    import zarr

    try:
        g = zarr.open_group(str(store), mode="r+")
        found = g.attrs.get("identity")
    except Exception as exc:  # noqa: BLE001 - only "not there" means another filesystem; anything else (out of
        if not (isinstance(exc, FileNotFoundError) or "NotFound" in type(exc).__name__):  # memory ...) is itself
            raise
        raise EnvironmentFault("out", f"no chaos map store at {str(store)!r} on this worker "
                                      f"({type(exc).__name__}): the workers need the same --out path as the client "
                                      f"(a shared filesystem)") from None
    if ident is not None and found != ident:
        raise EnvironmentFault("out", f"the store at {str(store)!r} on this worker is another map: the workers need "
                                      f"the same --out path as the client (a shared filesystem)")
    fields = _store_dtypes(fields)
    names = tuple(k for k in ALL_FIELDS if k in fields)  # = names_of(spec): the fields a tile of this map has
    for k in names:
        g[k][tile.ys, tile.xs] = fields[k]
    digest = tile_hash(fields, names)
    if marker:  # a refinement round writes its own marker (refine_task): the tile is not done yet
        atomic_write_json(Path(tiles_dir) / f"{tile.key}.json", {
            "tile": tile.key, "identity": found, "sha256": digest, "wall_s": wall_s,
            "points": int(np.asarray(fields["status"]).size)})
    return digest


def tile_task(spec_dict: dict, tile_key: str, store: str, tiles_dir: str, ident: str | None = None) -> tuple:
    """The Dask task: compute one tile and write it.  Takes plain data (picklable, no shared state).  Returns
    (key, wall seconds, content hash)."""
    spec = maps.MapSpec.from_dict(spec_dict)
    tile = maps.tile_of(spec, tile_key)
    t0 = time.perf_counter()
    fields = maps.compute_tile(spec, tile)
    wall = time.perf_counter() - t0
    digest = write_tile(Path(store), Path(tiles_dir), tile, fields, wall, ident)
    return tile_key, wall, digest


# ------------------------------------------------------------------------------------------------------------
# a refined map: rounds of points, each round one task per tile
# ------------------------------------------------------------------------------------------------------------
def _round_marker(tiles_dir: Path, rnd: int, key: str) -> Path:
    return Path(tiles_dir) / f"r{rnd}_{key}.json"


def points_hash(values: dict, iy, ix, names) -> str:
    """sha256 of some points of a map: their global indices, then every field (`names` order) at them as name,
    dtype and bytes.  A round's marker records it: later rounds write into the same tile, so the tile's hash
    changes, while the values of the points a round computed never do."""
    h = hashlib.sha256()
    h.update(np.ascontiguousarray(np.asarray(iy, np.int64)).tobytes())
    h.update(np.ascontiguousarray(np.asarray(ix, np.int64)).tobytes())
    for k in names:
        a = np.ascontiguousarray(values[k])
        h.update(f"{k}|{a.dtype.str}|{a.shape}|".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def _empty_tile(spec: maps.MapSpec, tile: maps.Tile) -> dict:
    shape = (tile.ys.stop - tile.ys.start, tile.xs.stop - tile.xs.start)
    f = {k: np.full(shape, np.nan) for k in maps.MAP_FIELDS}
    f["status"] = np.full(shape, chaos.FAILED, np.int8)
    f["inferred"] = np.zeros(shape, np.int8)
    f["level"] = np.full(shape, -1, np.int8)
    return f


def refine_task(spec_dict: dict, rnd: int, parts: list, store: str, tiles_dir: str, ident: str | None = None
                ) -> list:
    """The Dask task of some tiles' parts in one refinement round (maps.round_tasks): compute the points of every
    part [(tile key, iy, ix), ...] in one run (full SIMD batches), then per tile write them into its chunk (read,
    update those points, write back: no other task of the round touches this chunk) and the round's marker with
    the points' hash.  An unreadable chunk starts from the empty tile (the points of earlier rounds it held are
    found missing when their round is verified, and recomputed).  Returns [(key, wall seconds, content hash of the
    whole tile as written), ...]."""
    spec = maps.MapSpec.from_dict(spec_dict)
    t0 = time.perf_counter()
    allv = maps.compute_points(spec, [y for _, iy, _ in parts for y in iy], [x for _, _, ix in parts for x in ix])
    wall = (time.perf_counter() - t0) / max(1, len(parts))
    out, at = [], 0
    for key, iy, ix in parts:
        vals = {k: v[at:at + len(iy)] for k, v in allv.items()}
        at += len(iy)
        out.append(_write_part(spec, rnd, key, iy, ix, vals, wall, store, tiles_dir, ident))
    return out


def _write_part(spec, rnd, tile_key, iy, ix, vals, wall, store, tiles_dir, ident) -> tuple:
    import zarr

    tile = maps.tile_of(spec, tile_key)
    try:
        g = zarr.open_group(str(store), mode="r")
        cur = {k: np.array(g[k][tile.ys, tile.xs]) for k in _REFINED}
    except Exception:  # noqa: BLE001 - a damaged chunk: write_tile below says so if the store itself is missing
        cur = _empty_tile(spec, tile)
    ly, lx = np.asarray(iy) - tile.ys.start, np.asarray(ix) - tile.xs.start
    for k, v in vals.items():
        cur[k][ly, lx] = v
    cur["level"][ly, lx] = rnd
    cur["inferred"][ly, lx] = 0
    digest = write_tile(Path(store), Path(tiles_dir), tile, cur, wall, ident, marker=False)
    pts = _store_dtypes({k: cur[k][ly, lx] for k in _REFINED})
    atomic_write_json(_round_marker(tiles_dir, rnd, tile_key), {
        "tile": tile_key, "round": rnd, "identity": ident, "points": len(iy),
        "sha256": points_hash(pts, iy, ix, _REFINED), "wall_s": wall})
    return tile_key, wall, digest


def _load_tolerant(spec: maps.MapSpec, store: Path) -> dict:
    """Every array of a refined store in memory; a tile whose chunk cannot be read is the empty tile there."""
    import zarr

    out = {}
    try:
        g = zarr.open_group(str(store), mode="r")
    except Exception:  # noqa: BLE001 - nothing readable: every round is recomputed
        g = None
    for k in _REFINED:
        try:
            out[k] = np.array(g[k][...])
            continue
        except Exception:  # noqa: BLE001 - some chunk is damaged: read tile by tile
            pass
        out[k] = np.full(spec.shape, np.nan) if k in maps.MAP_FIELDS else np.full(
            spec.shape, {"status": chaos.FAILED, "inferred": 0, "level": -1}[k], np.int8)
        for t in maps.tiles(spec):
            try:
                out[k][t.ys, t.xs] = np.asarray(g[k][t.ys, t.xs])
            except Exception:  # noqa: BLE001 - the damaged chunk stays empty
                pass
    return out


def run_refined(spec: maps.MapSpec, store: Path, tiles_dir: Path, *, workers=2, scheduler=None, progress=None,
                client=None, state: StoreState | None = None, on_round=None, max_rounds=None,
                worker_timeout: float = 60.0) -> dict:
    """A refined map into the store (magrod.chaos.refine), resumable.

    The rounds are replayed from what the store holds: a round's points are a function of the earlier rounds'
    values, so for each round the points are found again, every tile's part of the round is verified against its
    round marker (r<round>_<iy>_<ix>.json: identity and the points' hash) and only the missing or damaged parts
    are computed (one Dask task per tile: refine_task).  After the last round the never-computed points are
    inferred and every tile is written whole with its final marker (the tile's hash over names_of(spec)), as in a
    brute-force store; store.record then lists them (finish).  A store whose tiles are all done is not touched.
    on_round(round, points, computed_tiles) after each round; max_rounds stops early (tests: a killed run).
    Returns {"computed": tile parts computed, "skipped": verified ones, "repaired": damaged parts and tiles,
    "rounds": [points per round], "points_computed": points this call computed, "task_wall_s"}."""
    from ..chaos.refine import Refinement, point_class

    store, tiles_dir = Path(store).absolute(), Path(tiles_dir).absolute()
    if state is None:
        state = create_or_open(spec, store, tiles_dir)
    all_tiles = maps.tiles(spec)
    res = {"computed": [], "skipped": [], "repaired": list(state.repaired), "rounds": [], "points_computed": 0,
           "task_wall_s": 0.0}
    if all(t.key in state.done for t in all_tiles):
        res["skipped"] = sorted(state.done)
        return res
    fields = _load_tolerant(spec, store)
    ref = Refinement(spec.shape, spec.refine, spec.refine_bound)
    cluster, pids, own = None, [], client is None
    interrupted = False
    sd = spec.to_dict()
    try:
        while not ref.done:
            if max_rounds is not None and ref.round >= max_rounds:
                return res
            rnd = ref.round
            iy, ix = ref.points()
            groups = maps.round_tiles(spec, iy, ix)
            todo = []
            for key, (gy, gx) in groups.items():
                m = _read_json(_round_marker(tiles_dir, rnd, key))
                ok = (isinstance(m, dict) and m.get("identity") == state.identity and m.get("tile") == key
                      and m.get("round") == rnd and m.get("sha256") == points_hash(
                          _store_dtypes({k: fields[k][gy, gx] for k in _REFINED}), gy, gx, _REFINED))
                if ok:
                    res["skipped"].append(f"r{rnd}_{key}")
                    continue
                if m is not None:
                    res["repaired"].append(f"r{rnd}_{key}")
                    _unlink(_round_marker(tiles_dir, rnd, key))
                todo.append(key)
            if todo:
                if client is None:
                    if scheduler is not None:
                        client = connect(scheduler)
                    else:
                        cluster, client, pids = start_local_cluster(workers)
                    client.run(worker_env)
                tasks = maps.round_tasks(spec, {k: groups[k] for k in todo})
                futs = {client.submit(refine_task, sd, rnd, [(k, groups[k][0].tolist(), groups[k][1].tolist())
                                                             for k in ks], str(store), str(tiles_dir),
                                      state.identity, pure=False): ks for ks in tasks}
                part = {"computed": [], "task_wall_s": 0.0}
                _collect(client, futs, spec, state, part, progress, worker_timeout, mark_done=False)
                import zarr

                g = zarr.open_group(str(store), mode="r")
                for key in part["computed"]:
                    t = maps.tile_of(spec, key)
                    for k in _REFINED:
                        fields[k][t.ys, t.xs] = np.asarray(g[k][t.ys, t.xs])
                    res["points_computed"] += int(groups[key][0].size)
                res["computed"] += [f"r{rnd}_{k}" for k in part["computed"]]
                res["task_wall_s"] += part["task_wall_s"]
            ref.add(iy, ix, point_class(fields["status"][iy, ix], fields["growth_exponent"][iy, ix],
                                        spec.refine_threshold), fields["growth_exponent"][iy, ix])
            res["rounds"].append(int(iy.size))
            if on_round is not None:
                on_round(rnd, int(iy.size), len(todo))
        final = maps.finish_refined(ref, {k: fields[k] for k in FIELDS})
        for t in all_tiles:  # the inferred points, and each tile's final marker (client side: I/O only)
            if t.key not in state.done:
                write_tile(store, tiles_dir, t, {k: final[k][t.ys, t.xs] for k in _REFINED}, 0.0, state.identity)
                state.done.add(t.key)
    except BaseException:
        interrupted = True
        raise
    finally:
        if own and client is not None:
            if cluster is None:
                close_quietly(client)
            else:
                stop_local_cluster(cluster, client, pids, interrupted=interrupted)
        if interrupted:
            remove_temporaries({"store": store, "tiles": tiles_dir}, pids)
    return res


def run_tiles(spec: maps.MapSpec, store: Path, tiles_dir: Path, *, workers=2, scheduler=None, progress=None,
              max_tiles=None, client=None, state: StoreState | None = None, on_submitted=None,
              worker_timeout: float = 60.0) -> dict:
    """Compute the tiles that are not done, on Dask, and verify each as it arrives.

    workers: LocalCluster size (ignored with `client`, a Client of a running cluster, or `scheduler`, its address).
    max_tiles limits this call (tests: a 'killed' run).  `state` is create_or_open's (verified) StoreState; without
    it the store is opened and verified here.  on_submitted() is called once every task is submitted.  Returns {"computed": [...], "skipped": [...], "repaired": [...],
    "task_wall_s": total seconds inside tasks}.  Raises EnvironmentFault("out") if a tile the workers wrote does
    not read back with its hash (the workers see another filesystem)."""
    store, tiles_dir = Path(store).absolute(), Path(tiles_dir).absolute()
    if state is None:
        state = create_or_open(spec, store, tiles_dir)
    done = state.done
    todo = [t.key for t in maps.tiles(spec) if t.key not in done][:max_tiles]
    res = {"computed": [], "skipped": sorted(done), "repaired": list(state.repaired), "task_wall_s": 0.0}
    if not todo:
        return res
    cluster, pids, own = None, [], client is None
    if client is None and scheduler is not None:
        client = connect(scheduler)
    elif client is None:
        cluster, client, pids = start_local_cluster(workers)
    interrupted = False
    try:
        client.run(worker_env)
        sd = spec.to_dict()
        futs = {client.submit(tile_task, sd, k, str(store), str(tiles_dir), state.identity, pure=False): k
                for k in todo}
        if on_submitted is not None:
            on_submitted()
        _collect(client, futs, spec, state, res, progress, worker_timeout)
    except BaseException:
        interrupted = True
        raise
    finally:
        if own:
            if cluster is None:
                close_quietly(client)
            else:
                stop_local_cluster(cluster, client, pids, interrupted=interrupted)
        if interrupted:
            remove_temporaries({"store": store, "tiles": tiles_dir}, pids)
    return res


POLL_S = 2.0  # how often a waiting client asks the scheduler whether it still has workers


def _collect(client, futs, spec, state: StoreState, res: dict, progress, worker_timeout: float = 60.0,
             mark_done: bool = True) -> None:
    """Wait for the tasks ({future: tile key}); verify each tile the workers wrote by reading it back here.  A
    cluster left without workers for worker_timeout seconds, or a scheduler that stops answering, is an
    EnvironmentFault("scheduler"), not an endless wait."""
    import zarr
    from dask.distributed import wait

    group = None
    pending = set(futs)
    idle_since = None
    try:
        while pending:
            try:
                finished, pending = wait(list(pending), timeout=POLL_S, return_when="FIRST_COMPLETED")
            except TimeoutError:
                idle_since = check_cluster(client, idle_since, worker_timeout)
                continue
            except CancelledError as exc:  # distributed cancels every future when it loses the scheduler
                why = "the connection was lost" if "connection-lost" in str(exc) else type(exc).__name__
                raise EnvironmentFault("scheduler", f"lost the Dask scheduler while tiles were running ({why}): "
                                                    f"finished tiles are kept; re-run the command to resume") from None
            for fut in finished:
                try:
                    got = fut.result()
                except (ParameterError, EnvironmentFault):
                    raise
                except Exception as exc:  # noqa: BLE001 - a task or the cluster failed: one line saying which
                    raise TileFailure(futs.get(fut), exc) from None
                for key, wall, digest in (got if isinstance(got, list) else [got]):  # a refinement task: parts
                    if group is None:
                        group = zarr.open_group(str(state.store), mode="r")
                    here = _hash_of_stored(state.store, maps.tile_of(spec, key), group, names_of(spec))
                    if here != digest:
                        raise EnvironmentFault("out", f"tile {key} written by a worker does not read back here from "
                                                      f"{str(state.store)!r} (content hash differs): the workers need "
                                                      f"the same --out path as the client (a shared filesystem)")
                    if mark_done:
                        state.done.add(key)
                    res["computed"].append(key)
                    res["task_wall_s"] += wall
                    if progress is not None:  # points of a tile (a refinement's part counts 1)
                        progress(maps.tile_of(spec, key).n_points if mark_done else 1)
    except BaseException:
        try:
            client.cancel(list(futs))
        except BaseException:  # noqa: BLE001
            pass
        raise


class TileFailure(RuntimeError):
    """A Dask task failed (an exception in the worker, a worker that died, the scheduler lost)."""

    def __init__(self, key, exc):
        self.key = key
        self.exc = exc
        kind = type(exc).__name__
        text = " ".join(str(exc).split())[:300]
        super().__init__(f"{kind}: {text}" if text else kind)


# ------------------------------------------------------------------------------------------------------------
# reading
# ------------------------------------------------------------------------------------------------------------
def open_map(store: Path):
    """The store as an xarray Dataset (lazy, dask-backed; consolidated metadata)."""
    import xarray as xr

    return xr.open_zarr(str(store), consolidated=True)


def load_fields(store: Path) -> dict:
    """Every field as a numpy array.  Read directly (chunks=None), not through dask: with a Client alive, dask would
    ship a few kB of chunks through the cluster (1.2 s for a 32 x 32 map, against 0.05 s)."""
    import xarray as xr

    ds = xr.open_zarr(str(store), consolidated=True, chunks=None)
    return {k: np.asarray(ds[k].values) for k in ALL_FIELDS if k in FIELDS or k in ds}
