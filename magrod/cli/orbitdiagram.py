"""`magrod orbitdiagram`: section points sin(psi) = 0 against a model parameter -- one orbit per value, all from
the same chart start on the same level (a paper panel's, --panel, default 4a; overridable), run in SIMD lanes on
all cores.  The panels of the base figure that vary the same parameter are marked.  With --out DIR the diagram is
written as DIR/<stem>.npz, .json and .png (atomically).

Any other model (--model NAME|FILE.py [--model-params ...]): over any of its parameters, each orbit from the model's
reference state put on its own level of H and the Casimirs at each value; --coordinate any of its state components
(default its second).

Examples:  magrod orbitdiagram --parameter lam --values 0.12:0.2:200 --iterates 500 --out DIR
           magrod orbitdiagram --panel 5a --parameter gamma --values 0.15,0.205,0.208,0.24 --coordinate ptheta
           magrod orbitdiagram --model anisotropic --parameter B2 --values 1:1.5:50 --coordinate m2"""
from __future__ import annotations

from ..core.errors import ParameterError
from ..generated.names import PARAMS
from .options import (system_from, LIMITS, ROOT_HELP, add_model, add_panel, add_params, add_start, add_workers, integer,
                      is_paper_model, number, out_dir, stem)

COORDINATES = ("theta", "ptheta", "psi", "ppsi")  # checked against magrod.chaos.portrait in the tests
MAX_VALUES = 1_000_000  # = magrod.chaos.section.MAX_ORBITS (not imported: that would load heyoka)


def add_arguments(p):
    p.add_argument("--parameter", required=True, help=f"the model parameter varied: {', '.join(PARAMS)} (the paper's "
                                                       "rod), or any parameter of --model")
    p.add_argument("--values", required=True,
                   help="LO:HI:N (N values, LO to HI) or a comma-separated, strictly monotone list")
    add_panel(p, help="panel giving the rod, level and start (default 4a)")
    add_params(p, help_suffix=" (overrides the panel's)")
    g = p.add_argument_group("level and start (override the panel's)")
    add_start(g)
    p.add_argument("--iterates", default="500", help="section points per value (after --transient)")
    p.add_argument("--transient", default="0", help="section points dropped first")
    p.add_argument("--coordinate", default=None,
                   help=f"plotted against the parameter: {', '.join(COORDINATES)} (the paper's rod: theta if not given), "
                        "or a state component of --model (default its second)")
    p.add_argument("--root", default=None, choices=("smallest", "largest"), help=ROOT_HELP)
    p.add_argument("--direction", default="positive", choices=("any", "negative", "positive"),
                   help="sign of d/dt sin(psi) at recorded crossings")
    add_workers(p, help="threads (default: all cores)", old=("--threads",))
    p.add_argument("--out", default=None, help="write <stem>.npz/.json/.png into this directory")
    p.add_argument("--stem", default="orbitdiagram", help="file name stem")
    add_model(p, help="the rod model: a registered name (`magrod models`) or a model file (default: the paper's rod)")


def parse_values(text: str) -> list:
    """LO:HI:N -> N evenly spaced values; A,B,C -> the list (monotonicity is checked by the library)."""
    t = str(text).strip()
    if ":" in t:
        parts = t.split(":")
        if len(parts) != 3:
            raise ParameterError("values", f"expected LO:HI:N or a comma-separated list, got {t[:60]!r}")
        lo, hi = number("values", parts[0]), number("values", parts[1])
        n = integer("values", parts[2], maximum=MAX_VALUES)
        if n > 1 and lo == hi:
            raise ParameterError("values", f"empty range {lo:g}:{hi:g} with {n} values")
        return [lo + (hi - lo) * i / (n - 1) for i in range(n)] if n > 1 else [lo]
    items = [s for s in t.split(",") if s.strip()]
    if not items:
        raise ParameterError("values", "is empty: give LO:HI:N or a comma-separated list")
    if len(items) > MAX_VALUES:
        raise ParameterError("values", f"{len(items)} values; at most {MAX_VALUES}")
    return [number("values", s) for s in items]


def _run_options(args, values) -> tuple:
    """(iterates, transient, workers, stem, output directory) of a diagram of any model, each checked by name."""
    iterates = integer("iterates", args.iterates)
    transient = integer("transient", args.transient, minimum=0, maximum=LIMITS["iterates"])
    if len(values) * (iterates + transient) > 10 * LIMITS["iterates"]:
        raise ParameterError("values", f"{len(values)} values x {iterates + transient} iterates: at most "
                                       f"{10 * LIMITS['iterates']} section points in one command")
    workers = None if args.workers is None else integer("workers", args.workers, maximum=256)
    return iterates, transient, workers, stem("stem", args.stem), (out_dir("out", args.out) if args.out is not None
                                                                   else None)


def run(args) -> dict:
    from ..core.printed import PANELS

    if not is_paper_model(args.model):
        return _model_run(args)
    args.coordinate = "theta" if args.coordinate is None else args.coordinate
    if args.coordinate not in COORDINATES:
        raise ParameterError("coordinate", f"must be one of {', '.join(COORDINATES)}, got {args.coordinate!r}")
    args.root = "smallest" if args.root is None else args.root
    if args.parameter not in PARAMS:
        raise ParameterError("parameter", f"must be a model parameter ({', '.join(PARAMS)}), got {args.parameter!r}")
    values = parse_values(args.values)
    system, P = system_from(args, default_panel="4a")  # the rod and its panel, resolved once
    base = system.rod
    start = {k: (number(k, getattr(args, k)) if getattr(args, k) is not None else getattr(P, k))
             for k in ("h", "theta0", "ptheta0", "psi0")}
    iterates, transient, workers, name, out = _run_options(args, values)
    # the paper's panels of the same figure that vary this parameter (and share everything else)
    marks = {}
    for k, d in PANELS.items():
        var, val = d["vary"]
        if k[0] == P.key[0] and var == args.parameter and all(
                getattr(d["params"], q) == getattr(base, q) for q in PARAMS if q != var) and \
                (d["h"], d["theta0"], d["ptheta0"], d["psi0"]) == tuple(start[q] for q in ("h", "theta0", "ptheta0",
                                                                                            "psi0")):
            marks[f"{k[0]}({k[1]})"] = val

    from .. import orbit_diagram
    from ..core.progress import bar

    with bar(len(values) * (iterates + transient), "orbit diagram", not args.quiet) as update:
        res = orbit_diagram(base, args.parameter, values, iterates=iterates, transient=transient,
                            coordinate=args.coordinate, root=args.root, direction=args.direction, marks=marks,
                            workers=workers, progress=update, **start)
    res.base = P.key
    paths = {}
    if res.success and out is not None:
        from ..core.io import ensure_writable_dir
        from ..figures.portrait import save_orbit_diagram

        paths = save_orbit_diagram(res, ensure_writable_dir(out), name)
    d = {"ok": bool(res.success), **res.summary(), "output": paths}
    if not res.success:
        d["error"] = res.message + ("; nothing written" if out is not None else "")
    return d


def _model_run(args) -> dict:
    """Another model: mr.orbit_diagram(system, parameter, values, ...) from its reference state."""
    import magrod as mr

    from ..core.progress import bar
    from .modelrun import refuse

    system, _ = system_from(args)
    refuse(args, PARAMS, system.model, "is a parameter of the paper's rod (the model's: --model-params)")
    refuse(args, ("h", "theta0", "ptheta0", "psi0", "root"), system.model,
           "is a start on the paper's chart: another model's orbits start at its reference state")
    if args.parameter not in system.names:
        raise ParameterError("parameter", f"must be a parameter of the model {system.model!r} "
                                          f"({', '.join(system.names)}), got {args.parameter!r}")
    values = parse_values(args.values)
    iterates, transient, workers, name, out = _run_options(args, values)
    with bar(len(values) * (iterates + transient), "orbit diagram", not args.quiet) as update:
        res = mr.orbit_diagram(system, args.parameter, values, iterates=iterates, transient=transient,
                               coordinate=args.coordinate, direction=args.direction, workers=workers,
                               progress=update)
    paths = {}
    if res.success and out is not None:
        from ..core.io import ensure_writable_dir
        from ..figures.portrait import save_orbit_diagram

        paths = save_orbit_diagram(res, ensure_writable_dir(out), name, extra={"model": system.model,
                                                                                 "params": system.params})
    d = {"ok": bool(res.success and res.accuracy["passed"]), **res.summary(), "model": system.model,
         "params": system.params, "accuracy": res.accuracy, "output": paths}
    if not d["ok"]:
        d["error"] = res.message + ("; nothing written" if out is not None else "")
    return d


def format_text(r: dict) -> str:
    if r.get("model"):
        from .modelrun import header

        v = r["values"]
        lines = [f"Orbit diagram of {header(r)}: {r['parameter']} from {v['first']:g} to {v['last']:g} ({v['n']} "
                 f"values), from the model's reference state on its level at each value",
                 f"  {r['iterates']} iterates per value (after {r['transient']} dropped), {r['points']} points, "
                 f"coordinate {r['coordinate']}, max |H - h| = {r['max_abs_dH']:.2e}, wall {r['wall_s']:.2f} s"]
        if not r["success"]:
            lines.append(f"  FAILED: {r['message']}")
        lines += [f"  wrote {kind}: {path}" for kind, path in (r.get("output") or {}).items()]
        return "\n".join(lines)
    v = r["values"]
    lines = [f"Orbit diagram: {r['parameter']} from {v['first']:g} to {v['last']:g} ({v['n']} values), h = "
             f"{r['h']:g}, start theta0 = {r['start']['theta0']:g}, pbar_theta0 = {r['start']['ptheta0']:g}",
             f"  {r['iterates']} iterates per value (after {r['transient']} dropped), {r['points']} points, "
             f"coordinate {r['coordinate']}, max |Hbar - h| = {r['max_abs_dH']:.2e}, wall {r['wall_s']:.2f} s"]
    if r.get("marks"):
        lines.append("  marked: " + ", ".join(f"{k} = {x:g}" for k, x in r["marks"].items()))
    if not r["success"]:
        lines.append(f"  FAILED: {r['message']}")
    for kind, path in (r.get("output") or {}).items():
        lines.append(f"  wrote {kind}: {path}")
    return "\n".join(lines)
