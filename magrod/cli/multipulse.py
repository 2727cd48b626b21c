"""`magrod multipulse`: symmetric multipulse homoclinic orbits of the straight rod by shooting (Figures 6, 7)."""
from __future__ import annotations

from ..core.errors import ParameterError
from ..generated.names import PARAMS
from .options import add_params, integer, number, out_dir, params_from

FREE = ("lam",) + tuple(p for p in PARAMS if p not in ("mu", "lam"))  # = magrod.orbits.multipulse.FREE_PARAMETERS


def add_arguments(p):
    p.add_argument("--figure", type=int, choices=(6, 7), help="parameters of fig:multimodal1 (6) / fig:multimodal2 (7)")
    add_params(p, help_suffix=" (free-parameter form; overrides --figure)")
    p.add_argument("--free", default=None, choices=FREE,
                   help="parameter solved for together with T (mu follows it: mu = 2 lam; default lam; mu = 2 lam "
                        "only)")
    p.add_argument("--max-pulses", default="6", help="look for N-pulse orbits, N = 1..max")
    p.add_argument("--span", default=None,
                   help="relative scan range of the free parameter, in (0, 1) (default 0.5; mu = 2 lam only)")
    p.add_argument("--samples", default="81", help="scan samples")
    p.add_argument("--out", default="out/multipulse", help="output directory")


def run(args) -> dict:
    from ..figures.multipulse import multipulse
    from ..generated import scalars
    from ..core.params import RodParams
    from ..core.printed import MULTIPULSE
    from ..core.tolerances import MU_TOL

    base = MULTIPULSE[args.figure]["params"].as_dict() if args.figure else {}
    vals = params_from(args, base)
    if args.figure is None and any(k not in vals for k in PARAMS):
        raise ParameterError("figure", "give --figure 6|7 or all of " + " ".join(f"--{k}" for k in PARAMS))
    params = RodParams(**vals)
    max_pulses = integer("max_pulses", args.max_pulses)
    span = number("span", args.span if args.span is not None else "0.5")  # validated whenever given
    if not (0 < span < 1):
        raise ParameterError("span", f"must be in (0, 1) (a relative range around the nominal value), got {span}")
    if abs(params.mu - scalars.straight_rod_mu(**vals)) > MU_TOL * max(1.0, abs(params.mu)):
        for opt in ("span", "free"):  # these shape the mu = 2 lam scan only: given here they would be ignored
            if getattr(args, opt) is not None:
                raise ParameterError(opt, f"applies to mu = 2 lam only (a scan of the free parameter); at mu = "
                                          f"{params.mu:g} != 2 lam = {2 * params.lam:g} the orbits to the periodic "
                                          f"saddle are found at the given parameters: drop --{opt}")
        # mu != 2 lam: orbits to the periodic saddle (helical rod) are generic, found at the given parameters
        from ..figures.multipulse import periodic_multipulse

        samples = integer("samples", args.samples, minimum=3)
        out_dir("out", args.out)
        return periodic_multipulse(params, args.out, max_pulses=max_pulses, samples=samples,
                                         progress=not args.quiet)
    samples = integer("samples", args.samples, minimum=3)
    out_dir("out", args.out)
    summary, _ = multipulse(params, args.out, free=args.free or "lam", max_pulses=max_pulses, span=span, samples=samples,
                            stem=f"figure{args.figure}" if args.figure else "multipulse", progress=not args.quiet)
    return summary


def format_text(d: dict) -> str:
    lines = [f"multipulse orbits, nominal {d['params']}, free {d['free']}:"]
    for o in d["orbits"]:
        if o["success"] and "angle" in o:  # periodic saddle (mu != 2 lam)
            lines.append(f"  N={o['pulses']}: angle={o['angle']:.12g} T={o['T']:.10g} residual={o['residual']:.2e} "
                         f"|H-H_saddle|={o['energy_error']:.1e} files={o.get('paths', [])}")
        elif o["success"]:
            u = o.get("uncertainty") or {}
            fv = "" if o["free_value"] is None else (
                f"{d['free']}*={u['significant']} (+-{u['uncertainty']:.1e}; double agrees to "
                f"{u['double_check']['max_abs_difference']:.1e}) " if u.get("success") and "double_check" in u
                else f"{d['free']}={o['free_value']:.12g} ")
            lines.append(f"  N={o['pulses']}: {fv}residual={o['residual']:.2e} "
                         f"arclength={o['arclength']:.6g} (eps={o['eps']:g}) H={o['H']:.15g} "
                         f"|H-H_saddle|={o['max_abs_H_minus_saddle']:.1e} files={o.get('paths', [])}")
        else:
            extra = f" (iterations {o['iterations']}, last residual {o['residual']:.2e})" if "iterations" in o else ""
            lines.append(f"  N={o['pulses_target']}: no orbit: {o['message']}{extra}")
    lines.append(f"  {d['note']}")
    if "table" in d:
        lines.append(f"  table: {d['table']}")
    return "\n".join(lines)
