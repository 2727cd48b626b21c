"""`magrod landscape`: every line of the paper's sec. 1 re-derived from the rod models, with labelled evidence and
reference keys, and the anisotropic B1:B2:C scan (magrod.integrability.landscape); with --model and --grid, the same
exact scan over a parameter grid of any model, a model file included.  Imports neither heyoka nor matplotlib at
module level."""
from __future__ import annotations


def add_arguments(p):
    p.add_argument("--degree", type=str, default="4", help="degree D of the exact searches (1 <= D <= 12)")
    p.add_argument("--quick", action="store_true", help="a smaller scan grid {1/2, 1, 2, 4} and t = 500 (seconds)")
    p.add_argument("--no-scan", action="store_true", help="skip the anisotropic B1:B2:C scan")
    p.add_argument("--no-splitting", action="store_true",
                   help="skip the homoclinic splitting of the anisotropic and curved rods")
    p.add_argument("--t-max", type=str, default=None, help="length of the Lyapunov runs (default 2000, quick 500)")
    p.add_argument("--seed", type=str, default=None,
                   help="seed of the rational parameters and the starts (default 20; with --model, the model's own "
                        "parameter values unless a seed is given)")
    p.add_argument("--model", default=None, metavar="NAME|FILE.py",
                   help="scan this model (a registered name or a model file) over --grid instead of the landscape")
    p.add_argument("--grid", action="append", default=None, metavar="NAME=V1,V2,...",
                   help="with --model: one axis of the parameter grid (repeat for more axes; values integer, "
                        "decimal or p/q); every point gets the exact search to --degree")
    p.add_argument("--model-params", default=None, metavar="NAME=VALUE,...",
                   help="with --model: fixed values of parameters not on the grid (others at the model's defaults)")
    p.add_argument("--level", default=None, metavar="CASIMIR=VALUE,...",
                   help="with --model: scan on a special Casimir level, e.g. C2=0")


def run(args) -> dict:
    from ..integrability import MAX_DEGREE
    from ..integrability import rod_landscape as landscape
    from . import options

    degree = options.integer("degree", args.degree, 1, MAX_DEGREE)
    if args.model is not None or args.grid is not None:
        return _scan(args, degree)
    for opt in ("model_params", "level"):
        if getattr(args, opt) is not None:
            from ..core.errors import ParameterError

            raise ParameterError(opt.replace("_", "-"), "applies only with --model and --grid")
    seed = options.integer("seed", "20" if args.seed is None else args.seed, 0, 2**62)
    t_max = None if args.t_max is None else options.number("t_max", args.t_max)
    d = landscape(degree, quick=args.quick, scan=not args.no_scan, t_max=t_max, seed=seed,
                  splitting=not args.no_splitting).to_dict()
    d["ok"] = True
    return d


def _scan(args, degree) -> dict:
    from ..core.errors import ParameterError
    from ..core.models import resolve
    from ..integrability import stiffness_scan
    from . import options
    from .models import parse_assignments

    if args.model is None or not args.grid:
        raise ParameterError("grid" if args.model is not None else "model",
                             "the scan of a model needs both --model and at least one --grid axis")
    for opt in ("quick", "no_scan", "no_splitting"):
        if getattr(args, opt):
            raise ParameterError(opt.replace("_", "-"), "applies to the landscape, not to the scan of --model")
    if args.t_max is not None:
        raise ParameterError("t-max", "applies to the landscape, not to the scan of --model")
    mc = resolve(args.model)
    grid = {}
    for item in args.grid:
        name, sep, rest = str(item).partition("=")
        name = name.strip()
        if not sep or not rest.strip():
            raise ParameterError("grid", f"cannot read {str(item)[:40]!r}: expected NAME=V1,V2,...")
        if name in grid:
            raise ParameterError("grid", f"{name} is given twice")
        vals = [parse_assignments("grid", f"{name}={v}", mc.names.PARAMS)[name] for v in rest.split(",")]
        grid[name] = vals
    seed = None if args.seed is None else options.integer("seed", args.seed, 0, 2**62)
    values = parse_assignments("model-params", args.model_params, mc.names.PARAMS)
    level = parse_assignments("level", args.level, mc.names.CASIMIRS)
    d = stiffness_scan(mc, grid, degree, values=values, level=level or None, seed=seed)
    d.update(ok=True, kind="scan")
    return d


def _scan_text(out: dict) -> str:
    lines = [f"model {out['model']}: exact search to degree {out['degree']} at {len(out['points'])} grid point(s)"
             + (f" on the level {out['level']}" if out["level"] else "")
             + (f", fixed {out['fixed']}" if out["fixed"] else ""),
             f"    {len(out['rows'])} point(s) with an integral beyond H and the Casimirs:"]
    for r in out["rows"]:
        checks = "re-checked exactly" if all(r["verified"]) else "RE-CHECK FAILED"
        lines.append(f"    {r['values']}: {'; '.join(r['integrals'])} ({checks}"
                     + ("; the rest certified)" if r["certified"] else "; NOT certified beyond them)"))
    return "\n".join(lines)


def format_text(out: dict) -> str:
    if out.get("kind") == "scan":
        return _scan_text(out)
    from ..integrability import format_landscape as fmt

    return fmt(out)
