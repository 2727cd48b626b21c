"""`magrod multipulse`: symmetric multipulse homoclinic orbits of the straight rod by shooting (Figures 6, 7)."""
from __future__ import annotations

from .errors import ParameterError
from .params import RodParams


def add_arguments(p):
    p.add_argument("--figure", type=int, choices=(6, 7), help="parameters of fig:multimodal1 (6) / fig:multimodal2 (7)")
    for name in ("m", "mu", "gamma", "delta", "lam"):
        p.add_argument(f"--{name}", type=float, help=f"{name} (free-parameter form; overrides --figure)")
    p.add_argument("--free", default="lam", choices=("lam", "gamma", "delta", "m"),
                   help="parameter solved for together with T (lam keeps mu = 2 lam)")
    p.add_argument("--max-pulses", type=int, default=6, help="look for N-pulse orbits, N = 1..max")
    p.add_argument("--span", type=float, default=0.5, help="relative scan range of the free parameter")
    p.add_argument("--samples", type=int, default=81, help="scan samples")
    p.add_argument("--out", default="out/multipulse", help="output directory")


def run(args) -> dict:
    from . import shooting

    if args.figure is None and any(getattr(args, k) is None for k in ("m", "mu", "gamma", "delta", "lam")):
        raise ParameterError("figure", "give --figure 6|7 or all of --m --mu --gamma --delta --lam")
    base = shooting.FIGURES[args.figure]["params"].as_dict() if args.figure else {}
    for k in ("m", "mu", "gamma", "delta", "lam"):
        if getattr(args, k) is not None:
            base[k] = getattr(args, k)
    params = RodParams(**base)
    if abs(params.mu - 2 * params.lam) > 64 * 2.220446049250313e-16 * max(1.0, abs(params.mu)):
        # issue 13: mu != 2 lam, orbits to the periodic saddle (generic; nothing freed)
        from . import homoclinic_periodic

        return homoclinic_periodic.multipulse(params, args.out, max_pulses=args.max_pulses, quiet=args.quiet)
    if not (0 < args.span < 1):
        raise ParameterError("span", f"must be in (0, 1), got {args.span}")
    if args.samples < 3:
        raise ParameterError("samples", f"must be >= 3, got {args.samples}")
    summary, _ = shooting.multipulse(params, args.out, free=args.free, max_pulses=args.max_pulses, span=args.span,
                                     samples=args.samples, stem=f"figure{args.figure}" if args.figure else "multipulse",
                                     quiet=args.quiet)
    return summary


def format_text(d: dict) -> str:
    lines = [f"multipulse orbits, nominal {d['params']}, free {d['free']}:"]
    for o in d["orbits"]:
        if o["success"] and "angle" in o:  # issue 13: periodic saddle
            lines.append(f"  N={o['pulses']}: angle={o['angle']:.12g} T={o['T']:.10g} residual={o['residual']:.2e} "
                         f"|H-H_saddle|={o['energy_error']:.1e} files={o.get('paths', [])}")
        elif o["success"]:
            fv = "" if o["free_value"] is None else f"{d['free']}={o['free_value']:.12g} "
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
