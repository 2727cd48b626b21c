"""`magrod chaosmap`: a chaos map over two of (m, mu, gamma, delta, lam, h, theta0, ptheta0, psi0) -- a parameter
plane at a paper panel's start rule, or initial conditions on one panel's energy level -- computed in tiles on
Dask (a LocalCluster of --workers processes, or --scheduler tcp://HOST:PORT), stored as a chunked zarr store
(OUT/<stem>.zarr, an xarray Dataset), drawn as OUT/<stem>.png with a JSON summary OUT/<stem>.json.  Re-running
the same command resumes: finished tiles are not recomputed.

Examples:  magrod chaosmap --x lam:0:0.3:128 --y gamma:0:3:128 --t-max 1000 --out DIR
           magrod chaosmap --panel 4a --x theta0:0.05:1.5:64 --y ptheta0:-1:1:64 --out DIR"""
from __future__ import annotations

from ..core.errors import ParameterError
from ..generated.names import PARAMS
from ..chaos.fields import MAPPABLE
from .options import integer, number, out_dir, stem

_OVERRIDES = (*PARAMS, "h", "theta0", "ptheta0", "psi0")


def add_arguments(p):
    p.add_argument("--x", default="lam:0.12:0.2:32", help="NAME:LO:HI:N of the horizontal axis")
    p.add_argument("--y", default="gamma:2:4:32", help="NAME:LO:HI:N of the vertical axis")
    p.add_argument("--panel", default="4a", help="paper panel whose parameters and start rule fix the other values")
    g = p.add_argument_group("overrides of the panel's values")
    for name in _OVERRIDES:
        g.add_argument(f"--{name}", default=None)
    p.add_argument("--root", default="smallest", choices=["smallest", "largest"], help="root pbar_psi of Hbar = h")
    p.add_argument("--indicator", default="growth", choices=sorted(MAPPABLE),
                   help="field drawn in the PNG (the store holds all; chaos is classified by the growth exponent)")
    p.add_argument("--t-max", default="3000", help="integration length T per orbit")
    p.add_argument("--tol", default="0", help="Taylor tolerance (0 = machine epsilon)")
    p.add_argument("--renorm-dt", default="10", help="renormalisation interval of the tangent vector")
    p.add_argument("--threshold", default="3", help="chaotic iff growth exponent > threshold")
    p.add_argument("--tile", default="16", help="tile edge in grid points (one Dask task, one zarr chunk)")
    p.add_argument("--workers", default=None, help="LocalCluster worker processes (1 thread each; default 2)")
    p.add_argument("--scheduler", default=None, help="tcp://HOST:PORT of a running Dask scheduler instead")
    p.add_argument("--out", required=True, help="output directory")
    p.add_argument("--stem", default="chaosmap", help="file name stem")
    p.add_argument("--force", action="store_true", help="overwrite a store of a different map")


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
            base[name] = number(name, v)
    _some_point_physical(x, y, base)
    return MapSpec(x, y, base=base, panel=str(args.panel).lower(), root=args.root,
                   t_max=number("t_max", args.t_max, bound=1e7), tol=number("tol", args.tol, bound=1.0),
                   renorm_dt=number("renorm_dt", args.renorm_dt), tile=integer("tile", args.tile, maximum=1024))


def _some_point_physical(x, y, base):
    """Points with unphysical parameters are marked missing, but a map with none physical is an input error.
    The constraints (m > 0, delta >= 0, gamma + delta >= 0) are linear, so the grid's corners decide."""
    from ..core.params import RodParams

    err = None
    for xv in (x.lo, x.hi):
        for yv in (y.lo, y.hi):
            v = {**base, x.name: xv, y.name: yv}
            try:
                RodParams(**{k: v[k] for k in PARAMS})
                return
            except ParameterError as exc:
                err = exc
    raise err


def _check_scheduler(s):
    if s is None:
        return None
    if not str(s).startswith(("tcp://", "tls://", "inproc://")) or ":" not in str(s).split("://", 1)[1]:
        raise ParameterError("scheduler", f"expected tcp://HOST:PORT, got {s!r}")
    return str(s)


def run(args) -> dict:
    import time

    spec = spec_from_args(args)
    workers = integer("workers", 2 if args.workers is None else args.workers, maximum=64)
    if args.scheduler is not None and args.workers is not None:  # given at all, even as "2" or "2.0"
        raise ParameterError("workers", "sizes the LocalCluster that --scheduler replaces: give one of them")
    scheduler = _check_scheduler(args.scheduler)
    threshold = number("threshold", args.threshold)
    name = stem("stem", args.stem)
    out = out_dir("out", args.out)

    from ..chaos import maps, store as chaos_store
    from ..figures.chaos import draw_map
    from ..core.io import atomic_write_json, ensure_writable_dir, versions
    from ..core.progress import bar

    out = ensure_writable_dir(out)
    pth = chaos_store.paths(out, name)
    chaos_store.create_or_open(spec, pth["store"], pth["tiles"], force=args.force)
    n_tiles = len(maps.tiles(spec))
    todo = n_tiles - len(chaos_store.done_tiles(pth["tiles"]))
    t0 = time.perf_counter()
    with bar(todo, "chaosmap", not args.quiet, unit="tile") as update:
        res = chaos_store.run_tiles(spec, pth["store"], pth["tiles"], workers=workers, scheduler=scheduler,
                                    progress=update)
    wall = time.perf_counter() - t0
    fields = chaos_store.load_fields(pth["store"])
    draw_map(fields, spec, pth["png"], indicator=args.indicator, threshold=threshold)
    summary = maps.map_summary(spec, fields, wall, threshold)
    computed = set(res["computed"])  # a set once, not per tile: a 4096^2 map has 65 536 tiles
    pts = sum(int(((t.ys.stop - t.ys.start) * (t.xs.stop - t.xs.start))) for t in maps.tiles(spec)
              if t.key in computed)
    summary.update(orbits_computed=pts, orbits_per_s=pts / wall if pts and wall > 0 else None,
                   tiles={"total": n_tiles, "computed": len(res["computed"]), "skipped": len(res["skipped"])},
                   workers=None if scheduler else workers, scheduler=scheduler or "LocalCluster",
                   task_wall_s=res["task_wall_s"])
    result = {"ok": True, "spec": spec.as_dict(), **summary,
              "output": {k: str(v) for k, v in pth.items() if k != "tiles"}}
    atomic_write_json(pth["json"], {**result, "versions": versions()})
    return result


def format_text(r: dict) -> str:
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
    for k, v in r["output"].items():
        lines.append(f"  {k}: {v}")
    return "\n".join(lines)
