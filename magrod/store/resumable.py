"""A chaos map into a resumable zarr store on Dask: `stored_map(spec, out)` and the public `chaos_map(...,
store=DIR)`: the policy of a stored, resumable map lives here, so that the command line and a library caller
share it.

The policy, once, for the library and for `magrod chaosmap`:
  - everything is checked before anything is made: the store path (no symbolic link), the cost against the workers,
    the machine's limits for a LocalCluster (open files, address space), a running scheduler reached with a worker;
  - one writer per store (a flock on OUT/.<stem>.lock); the temporaries of a killed run are removed first;
  - the store is created or re-opened and verified (magrod.store.tiles.create_or_open: every done tile's content
    hash; a store of another map is refused unless force=True); what was found damaged and repaired is one
    MagrodWarning;
  - the tiles that are not done run on Dask (a LocalCluster of `workers` single-threaded processes, or the
    scheduler at `scheduler`); a refined map runs its rounds (magrod.chaos.refine);
  - the map read back is a result only if maps.check_fields vouches for it (success False otherwise);
  - after a failure or an interruption the temporaries of interrupted writes go, and a store this call created in
    which no tile finished goes too; finished tiles keep their markers, so the next call resumes.
A task that raised in a worker is a failed result (success False, the message names the tile); the machine (a
worker killed, out of memory, the scheduler lost, a full disk) is an EnvironmentFault naming "workers",
"scheduler" or "out".
"""
from __future__ import annotations

import contextlib
import inspect
import json
import time
import warnings

from ..chaos import maps
from ..core.errors import EnvironmentFault, MagrodWarning, ParameterError
from . import cluster as _cluster
from . import tiles as _tiles


def stored_map(spec: maps.MapSpec, out, *, stem: str = "chaosmap", workers: int | None = None,
               scheduler: str | None = None, client=None, force: bool = False, connect_timeout: float = 5.0,
               worker_timeout: float = 60.0, progress=None, on_round=None, on_submitted=None,
               start_guard=None) -> maps.ChaosMap:
    """Compute `spec` into the store OUT/<stem>.zarr (resumable), return the map read back from it.

    Parameters
    ----------
    spec : MapSpec
        The map (maps.map_spec builds one from axes and a panel).
    out : str or Path
        Output directory (made absolute: Dask workers write there, so they need the same path).
    stem : str
        File name stem: OUT/<stem>.zarr, OUT/<stem>.tiles/, OUT/.<stem>.lock.
    workers : int, optional
        LocalCluster size (default 2, at most the CPUs this process may use); not with `scheduler` or `client`.
    scheduler : str, optional
        Address of a running Dask scheduler (tcp://HOST:PORT, HOST:PORT, tls://HOST:PORT).
    client : dask.distributed.Client, optional
        A client of a running cluster (the caller keeps it open).
    force : bool
        Start over in a store of a different map (only the store's own files are removed).
    connect_timeout, worker_timeout : float
        Seconds to reach the scheduler, and to wait for a worker.
    progress : callable, optional
        progress(n) as tiles finish, n their grid points (refined: n = 1 per tile part); if it has `set_total`,
        set_total(points to do) is called first for a brute-force map (magrod.core.progress.bar's update has it).
    on_round, on_submitted : callable, optional
        Called after each refinement round / once every brute-force task is submitted.
    start_guard : callable, optional
        A context-manager factory entered around the LocalCluster's start (the CLI passes its children_immune, so
        that the workers ignore the terminal's signals); None: nothing.

    Returns
    -------
    ChaosMap
        With `store` (the zarr store's path) and `run`: tiles computed/skipped/repaired, orbits computed this
        call and per second, damaged metadata rewritten, workers/scheduler, the store's identity.
    """
    for k, v in (("connect_timeout", connect_timeout), ("worker_timeout", worker_timeout)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not v > 0:
            raise ParameterError(k, f"must be > 0 seconds, got {v!r}")
    if sum(x is not None for x in (workers, scheduler, client)) > 1:
        given = [n for n, x in (("workers", workers), ("scheduler", scheduler), ("client", client)) if x is not None]
        raise ParameterError(given[-1], f"give one of workers, scheduler and client, not {' and '.join(given)}")
    from ..core.io import DirectoryLock, check_out_path, check_stem, ensure_writable_dir

    name = check_stem(stem)
    if spec.refine and spec.early_exit:
        raise ParameterError("early_exit", "a refined map in a store does not keep exit times yet: give refine or "
                                           "early_exit, not both (in memory both work)")
    out = check_out_path(out, "out").absolute()  # workers may run elsewhere: they get the absolute path

    pth = _tiles.paths(out, name)
    _tiles.check_paths(pth)  # a symbolic link for the store: refused before anything is made
    if scheduler is not None:
        scheduler = _cluster.normalise_address(scheduler)
    if scheduler is None and client is None:
        workers = _cluster.check_workers(2 if workers is None else workers)
        maps.check_cost(spec, workers)
        _cluster.check_open_files(workers)
        _cluster.check_address_space()
    guard = start_guard or contextlib.nullcontext
    cluster = None
    own_client = client is None
    pids: list = []
    state = None
    ok_exit = False
    try:
        if scheduler is not None:  # reach the scheduler and a worker before anything is created
            client = _cluster.connect(scheduler, timeout=connect_timeout, worker_timeout=worker_timeout)
        if client is not None:
            maps.check_cost(spec, max(1, len(client.scheduler_info().get("workers", {}))))
        out = ensure_writable_dir(out)
        busy = (f"another magrod chaosmap is writing {str(pth['store'])!r}; wait for it to finish (its tiles are then "
                f"reused) or choose another --out/--stem")
        with DirectoryLock(pth["lock"], "out", busy):
            _tiles.remove_temporaries(pth)  # what a killed run left (we hold the lock: no writer is alive)
            state = _tiles.create_or_open(spec, pth["store"], pth["tiles"], force=force)
            if state.repaired or state.metadata_rewritten:  # one warning: what was found damaged and is repaired
                what = [f"{len(state.repaired)} damaged or missing tile(s) failed their content hash and are "
                        f"recomputed"] if state.repaired else []
                if state.metadata_rewritten:
                    what.append(f"{len(state.metadata_rewritten)} damaged metadata file(s) rewritten from the spec")
                warnings.warn(f"{str(pth['store'])!r}: {'; '.join(what)}", MagrodWarning, stacklevel=2)
            n_tiles = len(maps.tiles(spec))
            todo = n_tiles - len(state.done)
            t0 = time.perf_counter()
            if not spec.refine and getattr(progress, "set_total", None) is not None:  # points, not tiles
                progress.set_total(sum(t.n_points for t in maps.tiles(spec) if t.key not in state.done))
            if todo and client is None:
                with guard():
                    try:
                        cluster, client, pids = _cluster.start_local_cluster(workers)
                    except (RuntimeError, OSError, TimeoutError) as exc:
                        raise _cluster.start_failure(exc, workers) from None
            try:
                if spec.refine:
                    res = _tiles.run_refined(spec, pth["store"], pth["tiles"], client=client, state=state,
                                             progress=progress, worker_timeout=worker_timeout, on_round=on_round)
                else:
                    res = _tiles.run_tiles(spec, pth["store"], pth["tiles"], client=client, state=state,
                                           progress=progress, on_submitted=on_submitted,
                                           worker_timeout=worker_timeout)
            except _tiles.TileFailure as exc:  # finished tiles keep their markers for the next run
                return _failed(spec, exc, scheduler, len(state.done), n_tiles, pth, time.perf_counter() - t0)
            _tiles.finish(spec, state)
            wall = time.perf_counter() - t0
            fields = _tiles.load_fields(pth["store"])
            computed = set(res["computed"])  # a set once, not per tile: a 4096^2 map has 65 536 tiles
            if spec.refine:
                pts = res["points_computed"]
            else:
                pts = sum(int((t.ys.stop - t.ys.start) * (t.xs.stop - t.xs.start)) for t in maps.tiles(spec)
                          if t.key in computed)
            run = {"orbits_computed": pts, "orbits_per_s": pts / wall if pts and wall > 0 else None,
                   "tiles": {"total": n_tiles, "computed": len(res["computed"]), "skipped": len(res["skipped"]),
                             "repaired": len(res["repaired"])},
                   "repaired_tiles": res["repaired"], "metadata_rewritten": state.metadata_rewritten,
                   "workers": workers, "scheduler": scheduler or ("LocalCluster" if own_client else "client"),
                   "task_wall_s": res["task_wall_s"], "store_identity": state.identity}
            if spec.refine:  # tile parts (one per tile and round) rather than tiles
                run["tiles"].update(parts_computed=len(res["computed"]), parts_skipped=len(res["skipped"]),
                                    rounds=res["rounds"])
            problem = maps.check_fields(fields)  # never hand back a map we cannot vouch for
            ok_exit = True
            return maps.ChaosMap(problem is None, problem or "ok", spec, fields, wall, str(pth["store"]), run=run)
    except OSError as exc:  # the machine (disk full, file-size limit, ...): one line with the path
        from ..core.io import resource_fault

        raise resource_fault(exc, "out", exc.filename if exc.filename is not None else pth["store"]) from None
    finally:
        interrupted = not ok_exit
        if cluster is not None:
            _cluster.stop_local_cluster(cluster, client, pids, interrupted=interrupted)
        elif client is not None and own_client:
            _cluster.close_quietly(client)
        if interrupted and state is not None:
            clean_after_failure(pth, state, pids)


def tile_failure(exc: _tiles.TileFailure, address, done: int, total: int, store=None) -> str:
    """A failed task as one line: the machine (a worker killed, out of memory, the scheduler lost, a full disk)
    raises an EnvironmentFault (exit 3 in the CLI); an exception raised by the computation is returned as the
    message of a failed map (exit 1)."""
    from ..core.io import resource_fault

    inner = exc.exc
    kept = f"{done} of {total} tiles finished" + (" and kept; re-run to resume" if done else "")
    where = f"the scheduler at {address}" if address else "the LocalCluster"
    kind = type(inner).__name__
    if isinstance(inner, OSError) and inner.errno is not None:
        # a worker's OSError often carries no file name (zarr's chunk write): name the store it was writing
        f = resource_fault(inner, "out", inner.filename if inner.filename is not None else store)
        raise EnvironmentFault("out", f"{f.message} ({kept})") from None
    text = str(inner)
    if isinstance(inner, MemoryError) or "bad_alloc" in text or "can't start new thread" in text \
            or "Cannot allocate memory" in text:
        raise EnvironmentFault("workers", f"a worker ran out of memory or threads on tile {exc.key} ({kind}: "
                                          f"{' '.join(text.split())[:80]}; a memory limit such as ulimit -v?); {kept}"
                               ) from None
    if kind in ("KilledWorker", "CommClosedError", "FutureCancelledError", "CancelledError", "TimeoutError") \
            or isinstance(inner, (OSError, TimeoutError)):
        raise EnvironmentFault("scheduler", f"lost a worker or {where} ({kind}: "
                                            f"{' '.join(str(inner).split())[:160]}; {kept})") from None
    return f"tile task failed in a worker: {exc} ({kept})"


def _failed(spec, exc, address, done, total, pth, wall) -> maps.ChaosMap:
    msg = tile_failure(exc, address, done, total, pth["store"])
    return maps.ChaosMap(False, msg, spec, maps.empty_fields(spec), wall, str(pth["store"]),
                         run={"tiles": {"total": total, "done": done}})


def clean_after_failure(pth: dict, state, pids) -> None:
    """After a failure or a signal: temporaries of interrupted writes go; a store this run created in which no tile
    finished goes too (nothing partial is left); finished tiles keep their markers for the next run."""
    _tiles.remove_temporaries(pth, pids)
    if state.created and not state.done and not _tiles.done_tiles(pth["tiles"]):  # a marker not yet verified
        # here is kept too: the next run verifies it
        _tiles._remove_store_files(pth["store"], set(_tiles.ALL_FIELDS) | _axis_names(state))
        _tiles._remove_markers(pth["tiles"])
        try:
            pth["tiles"].rmdir()
        except OSError:
            pass


def _axis_names(state) -> set:
    try:
        rec = json.loads((state.tiles_dir / "store.record").read_text())
        return {rec["spec"]["x"]["name"], rec["spec"]["y"]["name"]}
    except (OSError, ValueError, KeyError, TypeError):
        return set(maps.AXIS_NAMES)


# ----------------------------------------------------------------------------------------------------------------
# the public chaos_map: in memory (magrod.chaos.maps.chaos_map) or, with store=DIR, resumable on disk
# ----------------------------------------------------------------------------------------------------------------
_STORE_DOC = """
    store : str or Path, optional
        A directory: the map goes into the resumable zarr store STORE/<stem>.zarr (magrod.store.resumable:
        re-running resumes, finished tiles whose content hash verifies are not recomputed, damaged ones are; a
        different map there is refused unless force=True; one writer at a time).  The returned map's `store` is
        the store's path and `run` says what this call computed.  Not with `model`.
    stem, workers, scheduler, force
        With `store`: the file stem ("chaosmap"), the LocalCluster size (default 2), a running scheduler's
        address instead (tcp://HOST:PORT), and starting over in a store of another map.
"""


def chaos_map(system=None, x=None, y=None, *, store=None, stem: str = "chaosmap", workers: int | None = None,
              scheduler: str | None = None, force: bool = False, **kw) -> maps.ChaosMap:
    if store is None:
        for k, v in (("stem", stem != "chaosmap"), ("workers", workers is not None),
                     ("scheduler", scheduler is not None), ("force", force)):
            if v:
                raise ParameterError(k, "applies only with store=DIR (an in-memory map runs in this process, or on "
                                        "the Dask `client` given)")
        return maps.chaos_map(system, x, y, **kw)
    client, progress = kw.pop("client", None), kw.pop("progress", None)
    spec = maps.map_spec(system, x, y, **kw)
    return stored_map(spec, store, stem=stem, workers=workers, scheduler=scheduler, client=client, force=force,
                      progress=progress)


def _public_signature():
    base = inspect.signature(maps.chaos_map)
    params = [p for p in base.parameters.values() if p.kind is not p.VAR_KEYWORD]
    extra = [inspect.Parameter(n, inspect.Parameter.KEYWORD_ONLY, default=d)
             for n, d in (("store", None), ("stem", "chaosmap"), ("workers", None), ("scheduler", None),
                          ("force", False))]
    var = [p for p in base.parameters.values() if p.kind is p.VAR_KEYWORD]
    return base.replace(parameters=params + extra + var)


def _public_doc() -> str:
    doc = maps.chaos_map.__doc__
    anchor = "\n    Returns\n    -------"
    return doc.replace(anchor, _STORE_DOC.rstrip("\n") + "\n" + anchor, 1) if anchor in doc else doc


chaos_map.__signature__ = _public_signature()
chaos_map.__doc__ = _public_doc()
