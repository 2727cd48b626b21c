"""`magrod continue`: pseudo-arclength continuation of symmetric homoclinic orbits (magrod.orbits.continuation).

Two kinds of branches:
  generic   (mu > 2 lam) orbits to the periodic saddle, unknowns (T, launch angle, --free), --pulses N
  --mu2lam  codimension-one orbits of the straight rod on mu = 2 lam: a curve in the (lam, --second) plane
Writes branch.npz + branch.json (+ bifurcation diagram PNG) into --out."""
from __future__ import annotations

from ..core.errors import ParameterError
from ..generated.names import PARAMS
from .options import LIMITS, add_out, integer, number, out_dir, params_from

START = dict(m=1.7, mu=0.0021, gamma=1.0, delta=1.0, lam=0.001)  # near Fig 6, generic side mu > 2 lam


def add_arguments(p):
    for k in PARAMS:
        p.add_argument(f"--{k}", default=None, help=f"{k} at the start of the branch (default {START[k]})")
    p.add_argument("--pulses", default="1", help="number of pulses N >= 1")
    p.add_argument("--free", default="mu", choices=PARAMS, help="continuation parameter (generic case)")
    p.add_argument("--mu2lam", action="store_true", help="continue codimension-one orbits on mu = 2 lam in (lam, --second)")
    p.add_argument("--second", default="m", choices=tuple(k for k in PARAMS if k not in ("mu", "lam")),
                   help="second parameter on mu = 2 lam")
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

    N = integer("pulses", args.pulses, maximum=LIMITS["max_pulses"])
    steps = integer("steps", args.steps, maximum=10_000)
    ds = number("ds", args.ds)
    if not (0 < ds <= 1):
        raise ParameterError("ds", f"must be in (0, 1], got {ds}")
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
    # the branch itself is the library's continue_branch (issue 25: the command no longer rebuilds it)
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


def format_text(d: dict) -> str:
    if not d.get("ok", True):
        return f"continue: {d['error']}"
    lines = [f"continuation ({d['kind']}, N = {d['pulses']}) in {d['parameter']}: {d['points']} points, "
             f"max residual {d['max_residual']:.1e}, {d['wall_time_s']:.1f} s; {d['message']}",
             f"  first {d['first']}", f"  last  {d['last']}"]
    for f in d["folds"]:
        lines.append(f"  fold: {f}")
    lines.append(f"  files: {d['paths']}")
    return "\n".join(lines)
