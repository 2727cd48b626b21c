"""`magrod multipulse`: symmetric multipulse homoclinic orbits to the saddle at the given parameters (the straight
rod at mu = 2 lam, Figures 6 and 7; the periodic saddle above it), by the public search multipulse_orbits.

With --model NAME|FILE.py [--model-params ...]: the symmetric N-pulse orbits to the straight twisted rod of any
reversible model whose saddle is a saddle-focus (a launch-angle scan, --samples angles), each with its evidence and
its orbit file (<out>/multipulse_N<N>_<k>.npz + .json, which `magrod rod --from` reads).  A model without a
reversor or a saddle-focus is named with what it lacks (exit 2)."""
from __future__ import annotations

from ..core.errors import ParameterError
from ..generated.names import PARAMS
from .options import (LIMITS, add_alias, add_model, add_out, add_params, add_pulses, integer, is_paper_model, number,
                      out_dir, params_from)

FREE = ("lam",) + tuple(p for p in PARAMS if p not in ("mu", "lam"))  # = magrod.orbits.multipulse.FREE_PARAMETERS


def add_arguments(p):
    p.add_argument("--panel", type=int, choices=(6, 7), metavar="PANEL",
                   help="the paper's parameters of fig:multimodal1 (6) or fig:multimodal2 (7)")
    add_alias(p, "--figure", "--panel", "panel", type=int)
    add_params(p, help_suffix=" (free-parameter form; overrides --panel)")
    p.add_argument("--free", default=None, choices=FREE,
                   help="parameter solved for together with T (mu follows it: mu = 2 lam; default lam; mu = 2 lam "
                        "only)")
    add_pulses(p, default="6", help="look for N-pulse orbits, N = 1 .. this number", old=("--max-pulses",))
    p.add_argument("--span", default=None,
                   help="relative scan range of the free parameter, in (0, 1) (default 0.5; mu = 2 lam only)")
    p.add_argument("--samples", default="81", help="scan samples (values of --free, or launch angles)")
    add_out(p, files=True)
    add_model(p, help="the rod model: a registered name (`magrod models`) or a model file, whose symmetric N-pulse "
                      "orbits to its straight rod are searched on its reversor's Fix(R) (default: the paper's rod)")


def run(args) -> dict:
    """Parse, call the public search (magrod.orbits.multipulse.multipulse_orbits: it decides the saddle, mu = 2 lam
    to MU_TOL, and refuses --span/--free where they do not apply), write its files (figures.multipulse
    .write_search) and return its to_dict() with the paths."""
    from ..core.params import RodParams
    from ..core.printed import MULTIPULSE
    from ..core.progress import bar
    from ..figures.multipulse import write_search
    from .. import multipulse_orbits

    if not is_paper_model(args.model):
        return _model_run(args)
    if args.model_params:
        raise ParameterError("model_params", "needs --model (the paper's rod takes --m --mu --gamma --delta --lam)")
    base = MULTIPULSE[args.panel]["params"].to_dict() if args.panel else {}
    vals = params_from(args, base)
    if args.panel is None and any(k not in vals for k in PARAMS):
        raise ParameterError("panel", "give --panel 6|7 or all of " + " ".join(f"--{k}" for k in PARAMS))
    params = RodParams(**vals)
    max_pulses = integer("pulses", args.pulses, maximum=LIMITS["max_pulses"])
    span = number("span", args.span) if args.span is not None else None
    samples = integer("samples", args.samples, minimum=3)
    out = out_dir("out", args.out)
    with bar(samples, "scan", not args.quiet) as update:
        search = multipulse_orbits(params, max_pulses, free=args.free, span=span, samples=samples,
                                   with_uncertainty=True, progress=update)
    written = write_search(search, out, stem=f"figure{args.panel}" if args.panel else "multipulse")
    return {**search.to_dict(), "files": written["files"], "table": written["table"]}


def _model_run(args) -> dict:
    """Another model: mr.multipulse_orbits(system, N, samples=...), each orbit's evidence and orbit file."""
    import magrod as mr

    from ..core.io import ensure_writable_dir, write_model_orbit
    from .modelrun import equilibrium_dict, orbit_dict, refuse
    from .options import system_from

    system, _ = system_from(args)
    refuse(args, ("panel", *PARAMS), system.model, "is of the paper's rod")
    refuse(args, ("free", "span"), system.model, "shapes the paper's codimension-one scan on mu = 2 lam (another "
                                                 "model's orbits to its saddle-focus are generic: a launch-angle scan)")
    max_pulses = integer("pulses", args.pulses, maximum=LIMITS["max_pulses"])
    samples = integer("samples", args.samples, minimum=3, maximum=4096)
    out = out_dir("out", args.out)
    found = mr.multipulse_orbits(system, max_pulses, samples=samples)
    orbits = [orbit_dict(o) for o in found]
    passed = all(o["accuracy"]["passed"] for o in orbits)
    res = {"ok": bool(found.success and passed), "model": system.model, "params": system.params,
           "max_pulses": max_pulses, "samples": samples, "saddle": equilibrium_dict(found.saddle),
           "pulses": found.pulses, "orbits": orbits, "accuracy": {**found.accuracy, "passed": passed},
           "message": found.message, "wall_time_s": found.wall_time_s}
    if not res["ok"]:
        res["error"] = found.message if not found.success else "an orbit failed its accuracy checks"
        return res
    dest = ensure_writable_dir(out, "out")
    count = {}
    for o, row in zip(found, orbits):
        k = count[o.pulses] = count.get(o.pulses, -1) + 1
        row["orbit_files"] = write_model_orbit(dest, f"multipulse_N{o.pulses}_{k}", o,
                                               meta={"max_pulses": max_pulses, "samples": samples})
    return res


def _model_text(d: dict) -> str:
    from .modelrun import checks, header

    lines = [f"symmetric multipulse orbits of {header(d)} to its {d['saddle']['kind']} (N <= {d['max_pulses']}, "
             f"{d['samples']} launch angles): pulses {d['pulses']}"]
    for o in d["orbits"]:
        lines.append(f"  N={o['pulses']}: alpha={o['alpha']:.12g} T={o['T']:.10g} {checks(o['accuracy'])}")
        lines += [f"    wrote {p}" for p in o.get("orbit_files", [])]
    lines.append(f"  {d['message']}")
    return "\n".join(lines)


def format_text(d: dict) -> str:
    if d.get("model"):
        return _model_text(d)
    lines = [f"multipulse orbits to the {d['kind']} saddle, nominal {d['params']}, free {d['free']}:"]
    by_n = {}
    for o, files in zip(d["orbits"], d["files"]):
        by_n.setdefault(o["pulses"], []).append((o, files))
    for row in d["searches"]:
        N = row["pulses_target"]
        if not row["success"]:
            extra = (f" (iterations {row['iterations']}, last residual {row['residual']:.2e})"
                     if row.get("iterations") is not None else "")
            lines.append(f"  N={N}: no orbit: {row['message']}{extra}")
        elif d["kind"] == "periodic":  # generic orbits at the given parameters, several per N
            for o, files in by_n.get(N, []):
                lines.append(f"  N={N}: angle={o['angle']:.12g} T={o['T']:.10g} residual={o['residual']:.2e} "
                             f"|H-H_saddle|={o['energy_error']:.1e} files={files}")
        else:
            files = [f for _, f in by_n.get(N, [])]
            u = row.get("uncertainty") or {}
            fv = "" if row["free_value"] is None else (
                f"{d['free']}*={u['significant']} (+-{u['uncertainty']:.1e}; double agrees to "
                f"{u['double_check']['max_abs_difference']:.1e}) " if u.get("success") and "double_check" in u
                else f"{d['free']}={row['free_value']:.12g} ")
            lines.append(f"  N={N}: {fv}residual={row['residual']:.2e} arclength={row['arclength']:.6g} "
                         f"(launch distance {row['launch_distance']:g}) H={row['H']:.15g} |H-H_saddle|={row['max_abs_H_minus_saddle']:.1e} "
                         f"files={files[0] if files else []}")
    lines.append(f"  {d['message']}")
    if d.get("table"):
        lines.append(f"  table: {d['table']}")
    return "\n".join(lines)
