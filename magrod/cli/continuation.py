"""`magrod continue`: pseudo-arclength continuation of symmetric homoclinic orbits (magrod.orbits.continuation).

Two kinds of branches:
  generic   (mu > 2 lam) orbits to the periodic saddle, unknowns (T, launch angle, --free), --pulses N
  --mu2lam  codimension-one orbits of the straight rod on mu = 2 lam: a curve in the (lam, --second) plane
Any other model (--model NAME|FILE.py [--model-params ...]): its symmetric N-pulse homoclinic orbit to the straight
twisted rod (N = 1: `mr.homoclinic_orbit`; N > 1: the first of `mr.multipulse_orbits`), or with --equilibria its
straight rod (`mr.saddle`), continued in --free (any of the model's parameters), with folds.
Writes <stem>.npz + <stem>.json (+ bifurcation diagram PNG) into --out."""
from __future__ import annotations

from ..core.errors import ParameterError
from ..generated.names import PARAMS
from .options import LIMITS, add_model, add_out, integer, is_paper_model, number, out_dir, params_from

START = dict(m=1.7, mu=0.0021, gamma=1.0, delta=1.0, lam=0.001)  # near Fig 6, generic side mu > 2 lam


def add_arguments(p):
    for k in PARAMS:
        p.add_argument(f"--{k}", default=None, help=f"{k} at the start of the branch (default {START[k]})")
    p.add_argument("--pulses", default=None, help="number of pulses N >= 1 (default 1)")
    p.add_argument("--free", default=None,
                   help=f"continuation parameter: the paper's rod's generic case {', '.join(PARAMS)} (default mu); "
                        "another model: any of its parameters (required)")
    p.add_argument("--mu2lam", action="store_true", help="continue codimension-one orbits on mu = 2 lam in (lam, --second)")
    p.add_argument("--second", default=None, choices=tuple(k for k in PARAMS if k not in ("mu", "lam")),
                   help="second parameter on mu = 2 lam (default m)")
    p.add_argument("--equilibria", action="store_true",
                   help="another model: continue its straight twisted rod (an equilibrium on its leaf) instead of "
                        "its homoclinic orbit")
    add_model(p, help="the rod model: a registered name (`magrod models`) or a model file (default: the paper's rod)")
    p.add_argument("--steps", default="40", help="continuation steps")
    p.add_argument("--ds", default="0.1", help="initial scaled arclength step, in (0, 1]")
    p.add_argument("--direction", type=int, default=1, choices=(-1, 1), help="initial direction in the parameter")
    p.add_argument("--range", nargs=2, metavar=("LO", "HI"), help="stop when the parameter leaves [LO, HI]")
    p.add_argument("--allow-boundary", action="store_true",
                   help="allow --range to cross a stability (Hamiltonian-Hopf) boundary of the saddle")
    add_out(p, files=True)


def _check_range(params, name: str, rng, mu2lam: bool):
    from ..orbits import on_level, periodic_saddle, straight_rod

    for v in rng:
        try:
            if mu2lam:
                straight_rod(on_level(params, **{name: v}))
            else:
                periodic_saddle(params.replace(**{name: v}))
        except ParameterError as exc:
            raise ParameterError("range", f"{name} = {v:g} is beyond a stability boundary of the saddle ({exc.message}); "
                                          "pass --allow-boundary to continue anyway") from None


def run(args) -> dict:
    import time

    import numpy as np

    from ..core.tolerances import CONTINUATION_TOL
    from ..figures.continuation import write_branch
    from .. import continue_branch
    from ..orbits import find_multipulse, find_periodic_multipulse, fold_summary, shoot_multipulse
    from ..generated import scalars
    from ..core.params import RodParams
    from ..core.progress import bar

    steps = integer("steps", args.steps, maximum=10_000)
    ds = number("ds", args.ds)
    if not (0 < ds <= 1):
        raise ParameterError("ds", f"must be in (0, 1], got {ds}")
    if not is_paper_model(args.model):
        return _model_run(args, steps, ds)
    if args.model_params:
        raise ParameterError("model_params", "needs --model (the paper's rod takes --m --mu --gamma --delta --lam)")
    if args.equilibria:
        raise ParameterError("equilibria", "continues another model's straight rod; the paper's rod's straight rod "
                                           "(mu = 2 lam) is continued with its orbits: --mu2lam")
    N = integer("pulses", "1" if args.pulses is None else args.pulses, maximum=LIMITS["max_pulses"])
    args.free = "mu" if args.free is None else args.free
    if args.free not in PARAMS:
        raise ParameterError("free", f"must be one of {', '.join(PARAMS)}, got {args.free!r}")
    if args.second is not None and not args.mu2lam:
        raise ParameterError("second", "is the second parameter on mu = 2 lam: give --mu2lam too")
    args.second = "m" if args.second is None else args.second
    vals = params_from(args, START)
    if args.mu2lam:
        if args.mu is not None:
            raise ParameterError("mu", "--mu2lam sets mu = 2 lam: do not give --mu")
        vals["mu"] = scalars.straight_rod_mu(**vals)
    base = RodParams(**vals)
    name = args.second if args.mu2lam else args.free
    if args.range is not None:
        lo, hi = (number("range", v) for v in args.range)
        if not lo < hi:
            raise ParameterError("range", f"need LO < HI, got {lo} {hi}")
        if not args.allow_boundary:
            _check_range(base, name, (lo, hi), args.mu2lam)
    out = out_dir("out", args.out)
    t0 = time.perf_counter()
    if args.mu2lam:
        r = shoot_multipulse(base, N)
        if not r.success:  # Newton from the default guess did not converge: scan lam and bisect, as multipulse does
            found = find_multipulse(base, free="lam", max_pulses=N)
            if not found[N - 1].success:
                return {"ok": False, "error": f"no {N}-pulse orbit on mu = 2 lam near lam = {base.lam}: "
                                              f"{r.message}; scan: {found[N - 1].message} (near Figure 6 the "
                                              f"orbits on mu = 2 lam have 2 and 4 pulses: try --pulses 2)"}
            r = found[N - 1].orbit
    else:
        found = find_periodic_multipulse(base, N, samples=121)
        if not found:
            return {"ok": False, "error": f"no symmetric {N}-pulse homoclinic orbit to the periodic saddle at {base.to_dict()}"}
        r = found[0]
    # the branch itself is the library's continue_branch (the command does not rebuild it)
    with bar(steps, "continue", not args.quiet) as update:
        br = continue_branch(r.params, r, parameter=name, steps=steps, ds=ds, direction=args.direction,
                             bounds=(lo, hi) if args.range else None, progress=update)
    names = br.names
    wall = time.perf_counter() - t0
    stem = "branch_mu2lam" if args.mu2lam else f"branch_N{N}_{name}"
    folds = fold_summary(br)
    meta = {"ok": True, "kind": "mu = 2 lam (codimension one)" if args.mu2lam else "periodic saddle (mu > 2 lam)",
            "start_params": base.to_dict(), "pulses": N, "parameter": name, "names": list(names),
            "points": int(len(br.u)), "success": br.success, "message": br.message, "folds": folds,
            "max_residual": float(np.max(br.residuals)), "wall_time_s": wall, "tolerance": CONTINUATION_TOL,
            "algorithm": "pseudo-arclength (Keller), Newton + heyoka variational Jacobians",
            "first": dict(zip(names, map(float, br.u[0]))), "last": dict(zip(names, map(float, br.u[-1])))}
    meta["paths"] = write_branch(br, meta, out, stem)
    return meta


def _model_run(args, steps: int, ds: float) -> dict:
    """Another model: its symmetric N-pulse orbit (or, --equilibria, its straight rod) continued in --free by
    mr.continue_branch, the branch's evidence, and its files."""
    import time

    import numpy as np

    import magrod as mr

    from ..figures.continuation import write_branch
    from ..orbits import fold_summary
    from .modelrun import refuse
    from .options import system_from

    system, _ = system_from(args)
    refuse(args, PARAMS, system.model, "is a parameter of the paper's rod (the model's: --model-params)")
    refuse(args, ("mu2lam", "second", "allow_boundary"), system.model, "belongs to the paper's rod's branches")
    if args.free is None:
        raise ParameterError("free", f"missing: the continuation parameter, one of the parameters of the model "
                                     f"{system.model!r}: {', '.join(system.names)}")
    if args.free not in system.names:
        raise ParameterError("free", f"must be a parameter of the model {system.model!r} ({', '.join(system.names)}), "
                                     f"got {args.free!r}")
    if args.equilibria and args.pulses is not None:
        raise ParameterError("pulses", "counts the pulses of a homoclinic orbit: --equilibria continues the straight "
                                       "rod")
    N = integer("pulses", "1" if args.pulses is None else args.pulses, maximum=LIMITS["max_pulses"])
    bounds = None
    if args.range is not None:
        lo, hi = (number("range", v) for v in args.range)
        if not lo < hi:
            raise ParameterError("range", f"need LO < HI, got {lo} {hi}")
        bounds = (lo, hi)
    out = out_dir("out", args.out)
    t0 = time.perf_counter()
    if args.equilibria:
        start = mr.saddle(system)
    elif N == 1:
        start = mr.homoclinic_orbit(system)
    else:
        found = [o for o in mr.multipulse_orbits(system, N) if o.pulses == N]
        if not found:
            return {"ok": False, "model": system.model, "params": system.params,
                    "error": f"no symmetric {N}-pulse homoclinic orbit of the model {system.model!r} at "
                             f"{system.params} to start the branch from"}
        start = found[0]
    if not start.success:
        return {"ok": False, "model": system.model, "params": system.params,
                "error": f"the branch's start did not converge: {start.message}"}
    br = mr.continue_branch(system, start, parameter=args.free, steps=steps, ds=ds, direction=args.direction,
                            bounds=bounds)
    stem = f"branch_equilibria_{args.free}" if args.equilibria else f"branch_N{N}_{args.free}"
    meta = {"ok": bool(br.success), "kind": br.kind, "model": system.model, "start_params": system.params,
            "params": system.params, "pulses": None if args.equilibria else N, "parameter": args.free,
            "names": list(br.names), "points": int(br.points), "success": bool(br.success), "message": br.message,
            "folds": fold_summary(br), "max_residual": br.max_residual, "accuracy": br.accuracy,
            "start_accuracy": start.accuracy, "wall_time_s": time.perf_counter() - t0,
            "algorithm": "pseudo-arclength (Keller), Newton; the equilibrium recomputed on the start's leaf",
            "first": dict(zip(br.names, map(float, br.u[0]))), "last": dict(zip(br.names, map(float, br.u[-1])))}
    if not br.success:
        meta["error"] = br.message
    meta["max_residual"] = float(np.max(br.residuals))
    meta["paths"] = write_branch(br, meta, out, stem)
    return meta


def format_text(d: dict) -> str:
    if not d.get("ok", True) and "points" not in d:
        return f"continue: {d['error']}"
    if d.get("model"):
        from .modelrun import header

        what = "straight rod" if d["pulses"] is None else f"{d['pulses']}-pulse symmetric homoclinic orbit"
        lines = [f"continuation of the {what} of {header(d)} in {d['parameter']}: {d['points']} points, max "
                 f"residual {d['max_residual']:.1e}, {d['wall_time_s']:.1f} s; {d['message']}",
                 f"  first {d['first']}", f"  last  {d['last']}"]
        lines += [f"  fold: {f}" for f in d["folds"]]
        lines.append(f"  files: {d['paths']}")
        return "\n".join(lines)
    lines = [f"continuation ({d['kind']}, N = {d['pulses']}) in {d['parameter']}: {d['points']} points, "
             f"max residual {d['max_residual']:.1e}, {d['wall_time_s']:.1f} s; {d['message']}",
             f"  first {d['first']}", f"  last  {d['last']}"]
    for f in d["folds"]:
        lines.append(f"  fold: {f}")
    lines.append(f"  files: {d['paths']}")
    return "\n".join(lines)
