"""`magrod melnikov --m 1.7 --gamma 1.2 [--integrand derived|printed|both]`: amplitude A of the Mel'nikov
function, M(psi0) = A sin(psi0) sqrt(a - 2b) (paper sec. 7, eq:Mel_ext), with its error estimate
(float64 vs real128 quadrature plus a rigorous tail bound).  --find-zero searches gamma in --bracket for
A(gamma) = 0 at the given m."""
from __future__ import annotations

from ..core.errors import ParameterError
from .options import number


def add_arguments(p):
    p.add_argument("--m", required=True, help="m = m3/sqrt(B C2) (0 < m < 2 sqrt(1 + gamma))")
    p.add_argument("--gamma", default=None, help="extensibility gamma >= 0 (required unless --find-zero)")
    p.add_argument("--integrand", default="derived", choices=["derived", "printed", "both"],
                   help="derived: from eq:melnikov_bracket; printed: eq:Mel_ext as printed")
    p.add_argument("--find-zero", action="store_true", help="search gamma with A(gamma) = 0 in --bracket")
    p.add_argument("--bracket", nargs=2, default=None, metavar=("LO", "HI"),
                   help="gamma interval for --find-zero (the paper reports a zero between 1.8 and 2)")


def run(args) -> dict:
    from ..separatrix import INTEGRANDS, melnikov_amplitude as amplitude, melnikov_amplitude_zero as amplitude_zero

    which = list(INTEGRANDS) if args.integrand == "both" else [args.integrand]
    out = {"ok": True, "convention": "M(psi0) = A * sin(psi0) * sqrt(a - 2b), A = Int F dt along the "
                                     "lambdabar = 0 homoclinic orbit; error = |A_float64 - A_real128| + tail bound"}
    m = number("m", args.m)
    if args.find_zero and args.gamma is not None:
        raise ParameterError("gamma", "--find-zero searches gamma in --bracket: do not give --gamma as well")
    if not args.find_zero and args.bracket is not None:
        raise ParameterError("bracket", "is the search interval of --find-zero: give --find-zero too")
    if args.find_zero:
        lo, hi = (number("bracket", b) for b in (args.bracket or ("1.8", "2.0")))
        if not 0.0 <= lo < hi:
            raise ParameterError("bracket", f"need 0 <= LO < HI, got {lo}, {hi}")
        from ..orbits import validate_homoclinic as validate

        validate(m, lo)
        out["zeros"] = {k: amplitude_zero(m, k, (lo, hi)) for k in which}
        return out
    if args.gamma is None:
        raise ParameterError("gamma", "missing: give --gamma (or --find-zero)")
    gamma = number("gamma", args.gamma)
    out["amplitudes"] = {k: amplitude(m, gamma, k).to_dict() for k in which}
    return out


def format_text(r: dict) -> str:
    lines = [r["convention"]]
    for k, a in r.get("amplitudes", {}).items():
        lines.append(f"  {k:8s} m = {a['m']:g}, gamma = {a['gamma']:g}:  A = {a['A']:+.16e}  +- {a['error']:.2e}  "
                     f"(real128: {a['A_reference']:+.3e}; quadrature {a['quad_error']:.1e}, tail {a['tail_bound']:.1e}; "
                     f"|t| <= {a['T']:.4g})")
    for k, z in r.get("zeros", {}).items():
        if z["found"]:
            lines.append(f"  {k:8s} A(gamma) = 0 at gamma = {z['gamma_zero']:.15g} +- {z['error_bound']:.1e} "
                         f"(m = {z['m']:g}; sign change confirmed in real128: {z['sign_change_confirmed_real128']})")
        elif z.get("zero_within_bound_at_ends"):
            lines.append(f"  {k:8s} A is zero within its error bound ({z['A_at_ends'][0]:+.1e} +- "
                         f"{z['A_error_at_ends'][0]:.1e}, {z['A_at_ends'][1]:+.1e} +- {z['A_error_at_ends'][1]:.1e} at "
                         f"gamma = {z['bracket']}): no isolated zero to search for")
        else:
            lines.append(f"  {k:8s} no sign change of A on gamma in {z['bracket']} at m = {z['m']:g}: "
                         f"A = {z['A_at_ends'][0]:+.6e}, {z['A_at_ends'][1]:+.6e} at the ends")
    return "\n".join(lines)
