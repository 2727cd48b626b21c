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
from ..chaos import MAPPABLE
from .options import PARAM_HELP, ROOT_HELP, START_HELP, add_out, add_workers, integer, number, out_dir, stem

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
    p.add_argument("--tol", default=None, help="Taylor tolerance (default: machine epsilon; 0 means it too)")
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
    add_workers(p, help="LocalCluster worker processes (1 thread and ~300 MB each; default 2, at most the CPUs "
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
    add_out(p, files=True, help="output directory (made absolute: Dask workers write there)")
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
        # distributed's import sets its loggers' levels from the Dask configuration: import it first, or a logger
        # it configures after this point would escape (the lost-scheduler test saw distributed.client's traceback)
        import distributed  # noqa: F401

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
    from ..chaos import MapSpec, panel_base, parse_axis
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
    from ..chaos import MAX_LEVELS

    refine = integer("refine", args.refine, minimum=0, maximum=MAX_LEVELS) if args.refine != "0" else 0
    bound = None if args.refine_bound is None else number("refine_bound", args.refine_bound)
    threshold = number("threshold", args.threshold)
    spec = MapSpec(x, y, base=base, panel=str(args.panel).lower(), root=args.root,
                   t_max=number("t_max", args.t_max, bound=1e7), tol=0.0 if args.tol is None else number("tol", args.tol, bound=1.0),
                   renorm_dt=number("renorm_dt", args.renorm_dt), tile=integer("tile", args.tile, maximum=1024),
                   refine=refine, refine_bound=bound, early_exit=bool(getattr(args, "early_exit", False)),
                   **({"refine_threshold": threshold} if refine else {}))
    if spec.early_exit and threshold > spec.exit_above:  # an exited orbit's growth exponent is a lower bound
        raise ParameterError("threshold", f"with --early-exit at most the exit level {spec.exit_above:g} (orbits "
                                          f"stop once their growth exponent passes it), got {threshold:g}")
    return spec


def _cluster_from_args(args):
    """(scheduler address or None, LocalCluster size or None), validated; nothing is contacted yet."""
    from ..store.cluster import check_workers, normalise_address, read_scheduler_file

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
    return None, check_workers(integer("workers", 2 if args.workers is None else args.workers, maximum=64))


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
    from ..core.system import as_system

    system = as_system(mc.name if mc.origin == "registry" else mc.origin, **params)[0]
    cm = mr.chaos_map(system, axes[0], axes[1], t_max=t_max, renorm_dt=renorm)
    if not cm.success:
        raise ParameterError("model", cm.message)
    from ..chaos import GROWTH_THRESHOLD

    chaotic = cm.fields["growth_exponent"] > GROWTH_THRESHOLD
    d = {k: v for k, v in cm.to_dict().items() if k != "fields"}
    d["model"] = mc.name
    d["fraction_chaotic"] = float(cm.summary()["fraction_chaotic"])
    d["files"] = [str(atomic_savez(out / f"{name}.npz", x=cm.spec.x.values(), y=cm.spec.y.values(),
                                   lyap=cm.fields["lyap"], growth_exponent=cm.fields["growth_exponent"],
                                   chaotic=chaotic)),
                  str(atomic_write_json(out / f"{name}.json", {**d, "versions": versions()}))]
    d["ok"] = True
    d["model_map"] = True
    return d


def run(args) -> dict:
    """Parse, call magrod.store.resumable.stored_map (the library holds the store's policy), draw the PNG and write
    the JSON summary of a map the library vouches for."""
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
    name = stem("stem", args.stem)
    out = out_dir("out", args.out).absolute()  # workers may run in another directory: they get the absolute path

    from ..core.io import atomic_write_json, versions
    from ..core.progress import bar
    from ..store import tiles
    from ..store.resumable import stored_map
    from . import children_immune, pause_point

    pth = tiles.paths(out, name)
    label, unit = ("chaosmap (refined)", "tile part") if spec.refine else ("chaosmap", "point")
    # the number of points to do is known once the store is opened: the bar counts up without a total until then
    with bar(None, label, not args.quiet, unit=unit) as update, quiet_distributed():
        cm = stored_map(spec, out, stem=name, workers=workers, scheduler=address, force=args.force,
                        connect_timeout=connect_timeout, worker_timeout=worker_timeout, progress=update,
                        on_round=lambda *a: pause_point("chaosmap-round"),
                        on_submitted=lambda: pause_point("chaosmap-running"), start_guard=children_immune)
    if not cm.success and "store_identity" not in cm.run:  # a task failed in a worker (magrod.store.resumable)
        return {"ok": False, "error": cm.message, "tiles": cm.run["tiles"]}
    run = dict(cm.run)
    identity = run.pop("store_identity")
    result = {"ok": True, "spec": spec.to_dict(), **cm.summary(threshold), **run, "store_identity": identity,
              "output": {k: str(v) for k, v in pth.items() if k in ("store", "png", "json")}}
    result["wall_s"] = cm.wall_s
    if not cm.success:  # never hand back a map we cannot vouch for: no PNG, no summary file
        result.update(ok=False, error=cm.message, output={"store": str(pth["store"])})
        return result
    from ..figures.chaos import draw_map

    written = []
    try:  # the picture and its summary, or neither
        written.append(draw_map(cm.fields, spec, pth["png"], indicator=args.indicator, threshold=threshold))
        written.append(atomic_write_json(pth["json"], {**result, "versions": versions()}))
    except BaseException:
        for f in written:
            Path(f).unlink(missing_ok=True)
        raise
    return result


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
