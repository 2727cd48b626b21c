"""`magrod chaosmap`: a chaos map over two of (m, mu, gamma, delta, lam, h, theta0, ptheta0, psi0) -- a parameter
plane at a paper panel's start rule, or initial conditions on one panel's energy level -- computed in tiles on
Dask (a LocalCluster of --workers processes, or a running scheduler: --scheduler tcp://HOST:PORT or HOST:PORT,
--scheduler-file PATH), stored as a chunked zarr store (OUT/<stem>.zarr, an xarray Dataset), drawn as
OUT/<stem>.png with a JSON summary OUT/<stem>.json.  Re-running the same command resumes: finished tiles whose
content hash verifies are not recomputed, damaged or missing ones are (and counted); a different map into the
same store is refused (--force starts over); a second run into the same store is refused while the first runs.
--out is made absolute: Dask workers must see that path (a shared filesystem).  Everything is validated, and a
scheduler reached with a worker, before anything is created; a map with no computed point is a failure (exit 1).

Examples:  magrod chaosmap --x lam:0:0.3:128 --y gamma:0:3:128 --t-max 1000 --out DIR
           magrod chaosmap --panel 4a --x theta0:0.05:1.5:64 --y ptheta0:-1:1:64 --out DIR"""
from __future__ import annotations

import logging

from ..core.errors import ParameterError
from ..generated.names import PARAMS
from ..chaos.fields import MAPPABLE
from .options import PARAM_HELP, ROOT_HELP, START_HELP, integer, number, out_dir, stem

_OVERRIDES = (*PARAMS, "h", "theta0", "ptheta0", "psi0")


def add_arguments(p):
    p.add_argument("--x", default="lam:0.12:0.2:32", help="NAME:LO:HI:N of the horizontal axis")
    p.add_argument("--y", default="gamma:2:4:32", help="NAME:LO:HI:N of the vertical axis")
    p.add_argument("--panel", default="4a", help="paper panel whose parameters and start rule fix the other values")
    g = p.add_argument_group("overrides of the panel's values")
    for name in _OVERRIDES:
        g.add_argument(f"--{name}", default=None,
                       help=(PARAM_HELP.get(name) or START_HELP[name]) + " (not on an axis; overrides the panel's)")
    p.add_argument("--root", default="smallest", choices=["smallest", "largest"], help=ROOT_HELP)
    p.add_argument("--indicator", default="growth", choices=sorted(MAPPABLE),
                   help="field drawn in the PNG (the store holds all; chaos is classified by the growth exponent)")
    p.add_argument("--t-max", default="3000", help="integration length T per orbit")
    p.add_argument("--tol", default="0", help="Taylor tolerance (0 = machine epsilon)")
    p.add_argument("--renorm-dt", default="10", help="renormalisation interval of the tangent vector")
    p.add_argument("--threshold", default="3", help="chaotic iff growth exponent > threshold")
    p.add_argument("--tile", default="16", help="tile edge in grid points (one Dask task, one zarr chunk)")
    p.add_argument("--refine", default="0",
                   help="adaptive map: LEVELS >= 1 computes every 2^LEVELS-th point first, then only the cells whose "
                        "points disagree in class, halved round by round; the other points are inferred and "
                        "flagged (store arrays 'inferred', 'level'); 0 = every point, brute force")
    p.add_argument("--refine-bound", default=None,
                   help="with --refine: also split a cell whose growth exponents span more than this")
    p.add_argument("--early-exit", action="store_true",
                   help="stop an orbit after T/2 once its growth exponent passes the threshold with a margin (no class "
                        "changes; store array 'exit_time'); default: every orbit runs for T")
    p.add_argument("--workers", default=None,
                   help="LocalCluster worker processes (1 thread and ~300 MB each; default 2, at most the CPUs "
                        "this process may use)")
    p.add_argument("--scheduler", default=None,
                   help="a running Dask scheduler instead: tcp://HOST:PORT, HOST:PORT or tls://HOST:PORT (TLS "
                        "certificates from the Dask configuration); the workers must see --out at the same "
                        "absolute path (a shared filesystem)")
    p.add_argument("--scheduler-file", default=None,
                   help="the scheduler's address from this file (dask scheduler --scheduler-file PATH), as on HPC "
                        "systems")
    p.add_argument("--connect-timeout", default="5", help="seconds to reach the scheduler before giving up")
    p.add_argument("--worker-timeout", default="60", help="seconds to wait for a worker to join the scheduler")
    p.add_argument("--out", required=True, help="output directory (made absolute: Dask workers write there)")
    p.add_argument("--stem", default="chaosmap", help="file name stem")
    p.add_argument("--model", default=None, metavar="NAME|FILE.py",
                   help="a rod model of the family (`magrod models`) or a model file: Lyapunov estimates over two of "
                        "its parameters (--x/--y NAME:LO:HI:N name its parameters; one process, no Dask; default: "
                        "the paper's rod)")
    p.add_argument("--model-params", default=None, metavar="NAME=VALUE,...",
                   help="with --model: its other parameters")
    p.add_argument("--force", action="store_true",
                   help="start over in a store of a different map (only the store's own files are removed)")


class quiet_distributed:
    """Context manager (the CLI owns the loggers, the library never touches them): Dask's loggers at CRITICAL
    while a map runs (progress is ours, and a cluster shutting down
    after an interruption would otherwise print several lines); restored afterwards."""

    NAMES = ("distributed", "tornado", "asyncio", "bokeh")

    def __enter__(self):
        # Dask's configuration gives child loggers (distributed.client, ...) levels of their own: quiet those too
        names = set(self.NAMES) | {n for n in list(logging.root.manager.loggerDict)
                                   if n.split(".")[0] in self.NAMES}
        self._old = {n: logging.getLogger(n).level for n in names}
        for n in names:
            logging.getLogger(n).setLevel(logging.CRITICAL)
        return self

    def __exit__(self, *exc):
        for n, lvl in self._old.items():
            logging.getLogger(n).setLevel(lvl)
        return False


def spec_from_args(args):
    """Validate everything and build the MapSpec; raises ParameterError before anything is written."""
    from ..chaos.maps import MapSpec, panel_base, parse_axis
    from ..core.printed import panel

    x, y = parse_axis("x", args.x), parse_axis("y", args.y)
    try:
        panel(args.panel)
    except ParameterError as exc:
        raise ParameterError("panel", exc.message) from None
    base = panel_base(str(args.panel).lower())
    for name in _OVERRIDES:
        v = getattr(args, name)
        if v is not None:
            if name in (x.name, y.name):
                axis = "x" if name == x.name else "y"
                raise ParameterError(name, f"is varied on the --{axis} axis ({name} from "
                                           f"{(x if axis == 'x' else y).lo:g} to {(x if axis == 'x' else y).hi:g}): "
                                           f"do not also fix it")
            base[name] = number(name, v)
    from ..chaos.refine import MAX_LEVELS

    refine = integer("refine", args.refine, minimum=0, maximum=MAX_LEVELS) if args.refine != "0" else 0
    bound = None if args.refine_bound is None else number("refine_bound", args.refine_bound)
    threshold = number("threshold", args.threshold)
    spec = MapSpec(x, y, base=base, panel=str(args.panel).lower(), root=args.root,
                   t_max=number("t_max", args.t_max, bound=1e7), tol=number("tol", args.tol, bound=1.0),
                   renorm_dt=number("renorm_dt", args.renorm_dt), tile=integer("tile", args.tile, maximum=1024),
                   refine=refine, refine_bound=bound, early_exit=bool(getattr(args, "early_exit", False)),
                   **({"refine_threshold": threshold} if refine else {}))
    if spec.early_exit and threshold > spec.exit_above:  # an exited orbit's growth exponent is a lower bound
        raise ParameterError("threshold", f"with --early-exit at most the exit level {spec.exit_above:g} (orbits "
                                          f"stop once their growth exponent passes it), got {threshold:g}")
    return spec


def _cluster_from_args(args):
    """(scheduler address or None, LocalCluster size or None), validated; nothing is contacted yet."""
    from ..chaos.store import normalise_address, read_scheduler_file

    given = [o for o, v in (("scheduler", args.scheduler), ("scheduler_file", args.scheduler_file)) if v is not None]
    if len(given) == 2:
        raise ParameterError("scheduler_file", "give --scheduler or --scheduler-file, not both")
    if given and args.workers is not None:  # given at all, even as "2" or "2.0"
        raise ParameterError("workers", f"sizes the LocalCluster that --{given[0].replace('_', '-')} replaces: give "
                                        f"one of them")
    if args.scheduler is not None:
        return normalise_address(args.scheduler), None
    if args.scheduler_file is not None:
        return read_scheduler_file(args.scheduler_file), None
    return None, _check_workers(2 if args.workers is None else args.workers)


WORKER_MB = 300  # RSS of a LocalCluster worker after a tile (heyoka + LLVM + dask): 253 MB measured, rounded up


def _check_workers(value) -> int:
    """At most the CPUs this process may use (one single-threaded process each: more only cost memory) and what
    the available memory holds at WORKER_MB each."""
    import os

    cpus = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    n = integer("workers", value, maximum=64)
    if n > cpus:
        raise ParameterError("workers", f"must be <= {cpus}, the CPUs this process may use (each worker is one "
                                        f"single-threaded process of ~{WORKER_MB} MB; more only cost memory), got "
                                        f"{value!r}")
    avail = _available_mb()
    if avail is not None and n * WORKER_MB > avail:
        raise ParameterError("workers", f"{n} workers need ~{n * WORKER_MB} MB ({WORKER_MB} MB each) but only "
                                        f"{avail:.0f} MB are available: use fewer")
    return n


def _available_mb():
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return None


def _run_model(args) -> dict:
    """`chaosmap --model NAME|FILE`: magrod.chaos.model_chaos.model_chaos_map; files <stem>.npz/.json in --out."""
    import magrod as mr

    from ..core.io import atomic_savez, atomic_write_json, versions
    from ..core.models import resolve
    from .models import parse_assignments

    mc = resolve(args.model)
    axes = []
    for opt in ("x", "y"):
        parts = str(getattr(args, opt)).split(":")
        if len(parts) != 4 or parts[0] not in mc.names.PARAMS:
            raise ParameterError(opt, f"must be NAME:LO:HI:N with NAME one of {', '.join(mc.names.PARAMS)} (the "
                                      f"parameters of {mc.name!r}), got {getattr(args, opt)!r}")
        axes.append((parts[0], number(opt, parts[1]), number(opt, parts[2]), integer(opt, parts[3], 1, 512)))
    params = {k: float(v) for k, v in parse_assignments("model-params", args.model_params, mc.names.PARAMS).items()}
    t_max = number("t_max", args.t_max)
    renorm = number("renorm_dt", args.renorm_dt)
    name = stem("stem", args.stem)
    out = out_dir("out", args.out)
    cm = mr.chaos_map(axes[0], axes[1], model=mc, t_max=t_max, renorm_dt=renorm, **params)
    if not cm.success:
        raise ParameterError("model", cm.message)
    d = {k: v for k, v in cm.to_dict().items() if k not in ("lyap", "chaotic")}
    d["fraction_chaotic"] = float(cm.chaotic.mean())
    d["files"] = [str(atomic_savez(out / f"{name}.npz", x=cm.x, y=cm.y, lyap=cm.lyap, chaotic=cm.chaotic)),
                  str(atomic_write_json(out / f"{name}.json", {**d, "versions": versions()}))]
    d["ok"] = True
    d["model_map"] = True
    return d


def run(args) -> dict:
    import math
    import time
    from pathlib import Path

    if args.model is not None:
        return _run_model(args)
    if args.model_params is not None:
        raise ParameterError("model-params", "applies only with --model")

    spec = spec_from_args(args)
    address, workers = _cluster_from_args(args)
    connect_timeout = number("connect_timeout", args.connect_timeout, bound=3600)
    worker_timeout = number("worker_timeout", args.worker_timeout, bound=86400)
    for k, v in (("connect_timeout", connect_timeout), ("worker_timeout", worker_timeout)):
        if v <= 0:
            raise ParameterError(k, f"must be > 0 seconds, got {v:g}")
    threshold = number("threshold", args.threshold)
    if not math.isfinite(threshold):  # pragma: no cover - number() refuses it
        raise ParameterError("threshold", "must be finite")
    name = stem("stem", args.stem)
    out = out_dir("out", args.out).absolute()  # workers may run in another directory: they get the absolute path

    from ..chaos import maps, store as chaos_store
    from ..core.io import DirectoryLock, atomic_write_json, ensure_writable_dir, versions
    from ..core.progress import bar
    from . import children_immune, pause_point

    pth = chaos_store.paths(out, name)
    chaos_store.check_paths(pth)  # a symbolic link for the store: refused before anything is made
    if workers is not None:
        maps.check_cost(spec, workers)
        _check_open_files(workers)
        _check_address_space()
    client = cluster = None
    pids: list = []
    state = None
    ok_exit = False
    try:
        if address is not None:  # reach the scheduler and a worker before anything is created
            with quiet_distributed():
                client = chaos_store.connect(address, timeout=connect_timeout, worker_timeout=worker_timeout)
            maps.check_cost(spec, max(1, len(client.scheduler_info().get("workers", {}))))
        out = ensure_writable_dir(out)
        busy = (f"another magrod chaosmap is writing {str(pth['store'])!r}; wait for it to finish (its tiles are then "
                f"reused) or choose another --out/--stem")
        with DirectoryLock(pth["lock"], "out", busy):
            chaos_store.remove_temporaries(pth)  # what a killed run left (we hold the lock: no writer is alive)
            state = chaos_store.create_or_open(spec, pth["store"], pth["tiles"], force=args.force)
            if state.repaired or state.metadata_rewritten:  # one line: what was found damaged and is repaired
                import warnings

                from ..core.errors import MagrodWarning

                what = [f"{len(state.repaired)} damaged or missing tile(s) failed their content hash and are "
                        f"recomputed"] if state.repaired else []
                if state.metadata_rewritten:
                    what.append(f"{len(state.metadata_rewritten)} damaged metadata file(s) rewritten from the spec")
                warnings.warn(f"{str(pth['store'])!r}: {'; '.join(what)}", MagrodWarning, stacklevel=1)
            n_tiles = len(maps.tiles(spec))
            todo = n_tiles - len(state.done)
            t0 = time.perf_counter()
            if todo and client is None:
                with quiet_distributed(), children_immune():
                    try:
                        cluster, client, pids = chaos_store.start_local_cluster(workers)
                    except (RuntimeError, OSError, TimeoutError) as exc:
                        raise _start_failure(exc, workers) from None
            try:
                if spec.refine:  # rounds of tile parts: their number is known round by round only
                    with bar(None, "chaosmap (refined)", not args.quiet, unit="tile part") as update, \
                            quiet_distributed():
                        res = chaos_store.run_refined(spec, pth["store"], pth["tiles"], client=client, state=state,
                                                      progress=update, worker_timeout=worker_timeout,
                                                      on_round=lambda *a: pause_point("chaosmap-round"))
                else:
                    with bar(todo, "chaosmap", not args.quiet, unit="tile") as update, quiet_distributed():
                        res = chaos_store.run_tiles(spec, pth["store"], pth["tiles"], client=client, state=state,
                                                    progress=update,
                                                    on_submitted=lambda: pause_point("chaosmap-running"),
                                                    worker_timeout=worker_timeout)
            except chaos_store.TileFailure as exc:  # finished tiles keep their markers for the next run
                return _tile_failure(exc, address, len(state.done), n_tiles, pth["store"])
            chaos_store.finish(spec, state)
            wall = time.perf_counter() - t0
            fields = chaos_store.load_fields(pth["store"])
            summary = maps.map_summary(spec, fields, wall, threshold)
            computed = set(res["computed"])  # a set once, not per tile: a 4096^2 map has 65 536 tiles
            if spec.refine:
                pts = res["points_computed"]
            else:
                pts = sum(int(((t.ys.stop - t.ys.start) * (t.xs.stop - t.xs.start))) for t in maps.tiles(spec)
                          if t.key in computed)
            summary.update(orbits_computed=pts, orbits_per_s=pts / wall if pts and wall > 0 else None,
                           tiles={"total": n_tiles, "computed": len(res["computed"]), "skipped": len(res["skipped"]),
                                  "repaired": len(res["repaired"])},
                           repaired_tiles=res["repaired"], metadata_rewritten=state.metadata_rewritten,
                           workers=workers, scheduler=address or "LocalCluster",
                           task_wall_s=res["task_wall_s"])
            if spec.refine:  # tile parts (one per tile and round) rather than tiles
                summary["tiles"].update(parts_computed=len(res["computed"]), parts_skipped=len(res["skipped"]),
                                        rounds=res["rounds"])
            result = {"ok": True, "spec": spec.as_dict(), **summary, "store_identity": state.identity,
                      "output": {k: str(v) for k, v in pth.items() if k in ("store", "png", "json")}}
            problem = maps.check_fields(fields)
            if problem:  # never hand back a map we cannot vouch for: no PNG, no summary file
                result.update(ok=False, error=problem, output={"store": str(pth["store"])})
            else:
                from ..figures.chaos import draw_map

                written = []
                try:  # the picture and its summary, or neither
                    written.append(draw_map(fields, spec, pth["png"], indicator=args.indicator, threshold=threshold))
                    written.append(atomic_write_json(pth["json"], {**result, "versions": versions()}))
                except BaseException:
                    for f in written:
                        Path(f).unlink(missing_ok=True)
                    raise
            ok_exit = True
            return result
    except OSError as exc:  # the machine (disk full, file-size limit, ...): one line with the path
        from ..core.io import resource_fault

        raise resource_fault(exc, "out", exc.filename if exc.filename is not None else pth["store"]) from None
    finally:
        interrupted = not ok_exit
        with quiet_distributed():  # a client whose scheduler is gone logs its reconnection attempts
            if cluster is not None:
                chaos_store.stop_local_cluster(cluster, client, pids, interrupted=interrupted)
            elif client is not None:
                chaos_store._close_quietly(client)
        if interrupted and state is not None:
            _clean_after_failure(chaos_store, pth, state, pids)


def _files_needed(workers: int) -> int:
    """Open files the parent needs for a LocalCluster: ~31 + 10 per worker measured (sockets, pipes, the JIT
    cache, zarr), with a margin."""
    return 40 + 12 * workers


def _check_open_files(workers: int) -> None:
    import resource

    from ..core.errors import EnvironmentFault

    soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
    need = _files_needed(workers)
    if soft != resource.RLIM_INFINITY and soft < need:
        raise EnvironmentFault("workers", f"the open-file limit (ulimit -n) is {soft}; a LocalCluster of {workers} "
                                          f"worker(s) needs about {need} open files: raise it (e.g. ulimit -n 1024)")


WORKER_VM_MB = 1800  # virtual memory of a LocalCluster worker: VmPeak 904 MB measured after a tile, x 2 margin


def _check_address_space() -> None:
    """Under an address-space limit (ulimit -v) too small for a worker, the worker dies at start-up and prints its
    own traceback: refuse before that, in one line."""
    import resource

    from ..core.errors import EnvironmentFault

    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft != resource.RLIM_INFINITY and soft < WORKER_VM_MB * 2 ** 20:
        raise EnvironmentFault("workers", f"the address-space limit (ulimit -v) is {soft // 2 ** 20} MB; a LocalCluster "
                                          f"worker needs about {WORKER_VM_MB} MB of virtual memory (heyoka's JIT): "
                                          f"raise it or remove it (ulimit -v unlimited)")


def _start_failure(exc, workers: int):
    """The LocalCluster did not start: the machine's limits (memory, processes, files) say why, in one line."""
    import resource

    from ..core.errors import EnvironmentFault

    limits = []
    for name, rl, unit in (("ulimit -v", "RLIMIT_AS", "kB"), ("ulimit -u", "RLIMIT_NPROC", ""),
                           ("ulimit -n", "RLIMIT_NOFILE", "")):
        soft = resource.getrlimit(getattr(resource, rl))[0]
        if soft != resource.RLIM_INFINITY:
            limits.append(f"{name} {soft // 1024 if unit else soft}")
    why = " ".join(f"{type(exc).__name__}: {exc}".split())[:120]
    return EnvironmentFault("workers", f"cannot start a LocalCluster of {workers} worker(s) ({why}): not enough "
                                       f"memory, processes or open files? limits in force: "
                                       f"{', '.join(limits) or 'none'}")


def _tile_failure(exc, address, done: int, total: int, store=None) -> dict:
    """A failed task as one line: the machine (a worker killed, out of memory, the scheduler lost, a full disk)
    is an EnvironmentFault (exit 3); an exception raised by the computation is a failed run (exit 1)."""
    from ..core.errors import EnvironmentFault
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
    return {"ok": False, "error": f"tile task failed in a worker: {exc} ({kept})", "tiles": {"total": total,
                                                                                           "done": done}}


def _clean_after_failure(chaos_store, pth, state, pids) -> None:
    """After a failure or a signal: temporaries of interrupted writes go; a store this run created in which no tile
    finished goes too (nothing partial is left); finished tiles keep their markers for the next run."""
    chaos_store.remove_temporaries(pth, pids)
    if state.created and not state.done and not chaos_store.done_tiles(pth["tiles"]):  # a marker not yet verified
        # here is kept too: the next run verifies it
        chaos_store._remove_store_files(pth["store"], set(chaos_store.ALL_FIELDS) | _axis_names(state))
        chaos_store._remove_markers(pth["tiles"])
        try:
            pth["tiles"].rmdir()
        except OSError:
            pass


def _axis_names(state) -> set:
    import json

    try:
        rec = json.loads((state.tiles_dir / "store.record").read_text())
        return {rec["spec"]["x"]["name"], rec["spec"]["y"]["name"]}
    except (OSError, ValueError, KeyError, TypeError):
        from ..chaos.maps import AXIS_NAMES

        return set(AXIS_NAMES)


def format_text(r: dict) -> str:
    if r.get("model_map"):
        return (f"model {r['model']}: Lyapunov map over {r['x_name']} x {r['y_name']}, t = {r['t_max']:g}: "
                f"{100 * r['fraction_chaotic']:.0f}% chaotic; max |H - h| = {r['energy_error']:.1e}"
                + "".join(f"\n  wrote {f}" for f in r["files"]))
    if "grid" not in r:  # a failed run: the error line says it
        return f"chaos map: FAILED ({r.get('error')})"
    g = r["grid"]
    lines = [f"chaos map {g['x']['name']} [{g['x']['lo']:g}, {g['x']['hi']:g}] x {g['y']['name']} "
             f"[{g['y']['lo']:g}, {g['y']['hi']:g}], {g['x']['n']} x {g['y']['n']} points, T = {r['t_max']:g}",
             f"  {r['computed']} computed, missing: {r['missing'] or 'none'}; tiles: {r['tiles']}",
             f"  {r['criterion']}: fraction chaotic "
             + (f"{r['fraction_chaotic']:.3f}" if r["fraction_chaotic"] is not None else "n/a"),
             f"  wall {r['wall_s']:.1f} s, {r['orbits_computed']} orbits this run"
             + (f" ({r['orbits_per_s']:.0f} orbits/s)" if r["orbits_per_s"] else "")
             + (f"; max |dH| {r['max_abs_dH']:.1e}, Casimir drift {r['max_casimir_drift']:.1e}"
                if r["max_abs_dH"] is not None else "")]
    if r.get("refine"):
        f = r["refine"]
        lines.append(f"  refined (L = {f['levels']}): {f['points_computed']} points computed, {f['points_inferred']} "
                     f"inferred from their cells; points per round {f['points_per_round']}")
    for k, v in r["output"].items():
        lines.append(f"  {k}: {v}")
    return "\n".join(lines)
