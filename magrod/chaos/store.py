"""Chaos maps on disk and on a Dask cluster (I/O; the numerics are in magrod.chaos.indicators).

Layout of OUT (stem "chaosmap" by default):
  OUT/<stem>.zarr        chunked zarr store, one chunk per tile, readable as an xarray Dataset (open_map)
                         with coordinates (y-parameter, x-parameter), units and provenance attributes
  OUT/<stem>.tiles/      one done-marker <iy>_<ix>.json per finished tile (written after its chunk)

A tile is done iff its marker exists (the marker is written atomically after the chunk, so a killed task leaves
no marker and is recomputed).  A resumed run checks that the store was made by the same MapSpec and skips
done tiles.  Each tile writes only its own chunk (zarr region write), so workers never touch the same file.

Dask: run_tiles starts a LocalCluster (processes, threads_per_worker=1, no dashboard) unless a scheduler
address is given.  Every tile is a pure function of (spec, tile) computed by magrod.chaos.indicators.compute_tile, so the
result is bit-identical whatever the number of workers or the order the tiles run in (on one CPU type: workers
on other machines compile heyoka for their own instruction set, e.g. with or without FMA, and may differ in the
last bits; the batch size is part of the spec, so it is the same everywhere).
"""
from __future__ import annotations

import json
import logging
import os
import time
from pathlib import Path

import numpy as np

from . import indicators as chaos, maps
from .fields import BY_NAME
from ..core.errors import ParameterError
from ..core.io import atomic_write_json

UNITS = {**{k: f.unit for k, f in BY_NAME.items()}, "status": "code"}
LONG = {**{k: f.long for k, f in BY_NAME.items()},
        "status": "0 ok; " + "; ".join(f"{c} {r}" for c, r in chaos.REASONS.items() if c)}


def paths(out: Path, stem: str) -> dict:
    out = Path(out)
    return {"store": out / f"{stem}.zarr", "tiles": out / f"{stem}.tiles", "png": out / f"{stem}.png",
            "json": out / f"{stem}.json"}


def _spec_json(spec: maps.MapSpec) -> str:
    return json.dumps(spec.as_dict(), sort_keys=True)


def create_or_open(spec: maps.MapSpec, store: Path, tiles_dir: Path, *, force=False) -> None:
    """Create the empty store (metadata + coordinates only) or check that an existing one holds this spec.
    ParameterError("out") if OUT holds a store of a different map (pass force=True to overwrite it)."""
    import zarr

    if store.exists() and not force:
        try:
            attrs = dict(zarr.open_group(str(store), mode="r").attrs)
        except Exception:  # an unreadable or half-created store: start it again
            attrs = {}
        if attrs.get("spec") == _spec_json(spec):
            tiles_dir.mkdir(exist_ok=True)
            return
        if attrs:
            raise ParameterError("out", f"{store} holds a different chaos map (other grid or options); use another "
                                        f"--out/--stem or --force to overwrite it")
    _create(spec, store)
    if tiles_dir.exists():
        for p in tiles_dir.glob("*.json"):
            p.unlink()
    tiles_dir.mkdir(exist_ok=True)


def _create(spec: maps.MapSpec, store: Path) -> None:
    import dask.array as da
    import xarray as xr

    from ..core.io import versions

    chunks = (spec.tile, spec.tile)
    dims = (spec.y.name, spec.x.name)
    data = {k: (dims, da.full(spec.shape, np.nan, chunks=chunks), {"units": UNITS[k], "long_name": LONG[k]})
            for k in maps.MAP_FIELDS}
    data["status"] = (dims, da.full(spec.shape, chaos.FAILED, dtype=np.int8, chunks=chunks),
                      {"units": UNITS["status"], "long_name": LONG["status"], "flag_values": list(chaos.REASONS),
                       "flag_meanings": " ".join(chaos.REASONS.values())})
    coords = {spec.x.name: (spec.x.name, spec.x.values(), {"units": "1", "long_name": _axis_label(spec.x.name)}),
              spec.y.name: (spec.y.name, spec.y.values(), {"units": "1", "long_name": _axis_label(spec.y.name)})}
    ds = xr.Dataset(data, coords=coords, attrs={
        "title": "magrod chaos map (Sinden & van der Heijden, spatial chaos of a conducting rod)",
        "spec": _spec_json(spec), "criterion": f"chaotic iff growth_exponent > {chaos.GROWTH_THRESHOLD:g}",
        "tolerance": "machine epsilon" if not spec.tol else repr(spec.tol),
        "formulation": "body (9-D, generated/body.py)",
        "tangent_vectors": "projected onto the level set of C1, C2, C3, H, m3 (magrod.chaos.indicators)",
        "versions": json.dumps(versions(), sort_keys=True)})
    # compute=False writes metadata and coordinates; the data chunks are written tile by tile
    ds.to_zarr(str(store), mode="w", compute=False, consolidated=False)


def _axis_label(name: str) -> str:
    return {"lam": "lambdabar", "mu": "mu", "gamma": "gamma", "delta": "delta", "m": "m", "h": "h (energy)",
            "theta0": "theta at the start", "ptheta0": "pbar_theta at the start", "psi0": "psi at the start"}[name]


def done_tiles(tiles_dir: Path) -> set:
    return {p.stem for p in Path(tiles_dir).glob("*.json")}


def write_tile(store: Path, tiles_dir: Path, tile: maps.Tile, fields: dict, wall_s: float) -> str:
    """Region write of one tile's chunk, then its done-marker (atomically)."""
    import zarr

    g = zarr.open_group(str(store), mode="r+")
    for k, v in fields.items():
        g[k][tile.ys, tile.xs] = v
    atomic_write_json(Path(tiles_dir) / f"{tile.key}.json", {"tile": tile.key, "wall_s": wall_s,
                                                             "points": int(np.asarray(fields["status"]).size)})
    return tile.key


def tile_task(spec_dict: dict, tile_key: str, store: str, tiles_dir: str) -> tuple:
    """The Dask task: compute one tile and write it.  Takes plain data (picklable, no shared state)."""
    spec = maps.MapSpec.from_dict(spec_dict)
    tile = maps.tile_of(spec, tile_key)
    t0 = time.perf_counter()
    fields = maps.compute_tile(spec, tile)
    wall = time.perf_counter() - t0
    write_tile(Path(store), Path(tiles_dir), tile, fields, wall)
    return tile_key, wall


def _worker_env() -> None:
    """Single-threaded math in every worker: nothing a worker inherits may depend on how many there are."""
    for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[k] = "1"


def run_tiles(spec: maps.MapSpec, store: Path, tiles_dir: Path, *, workers=2, scheduler=None, progress=None,
              max_tiles=None) -> dict:
    """Compute the tiles that are not done, on Dask.  workers: LocalCluster size (ignored with scheduler, a
    tcp://HOST:PORT address of a running cluster).  max_tiles limits this call (tests: a 'killed' run).
    Returns {"computed": [...], "skipped": [...], "task_wall_s": total seconds inside tasks}."""
    from dask.distributed import Client, LocalCluster, as_completed

    all_tiles = maps.tiles(spec)
    done = done_tiles(tiles_dir)
    todo = [t.key for t in all_tiles if t.key not in done][:max_tiles]
    res = {"computed": [], "skipped": sorted(done), "task_wall_s": 0.0}
    if not todo:
        return res
    _worker_env()
    logging.getLogger("distributed").setLevel(logging.ERROR)  # progress is ours; the cluster's INFO is noise
    cluster = None
    if scheduler is None:
        # dashboard off; the scheduler still serves its health routes over HTTP: on a free port (":0"), not 8787,
        # so that concurrent maps do not fight over it
        cluster = LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True,
                               dashboard_address=None, scheduler_kwargs={"dashboard": False, "dashboard_address": ":0"},
                               silence_logs=logging.ERROR)
        client = Client(cluster)
    else:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise ParameterError("scheduler", f"cannot connect to {scheduler}: {exc}") from None
    try:
        client.run(_worker_env)
        sd = spec.as_dict()
        futs = [client.submit(tile_task, sd, k, str(store), str(tiles_dir), pure=False)
                for k in todo]
        for fut in as_completed(futs):
            key, wall = fut.result()
            res["computed"].append(key)
            res["task_wall_s"] += wall
            if progress is not None:
                progress(1)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return res


def open_map(store: Path):
    """The store as an xarray Dataset (lazy, dask-backed)."""
    import xarray as xr

    return xr.open_zarr(str(store), consolidated=False)


def load_fields(store: Path) -> dict:
    ds = open_map(store)
    return {k: ds[k].values for k in list(maps.MAP_FIELDS) + ["status"]}
