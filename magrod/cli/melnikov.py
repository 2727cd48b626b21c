"""`magrod melnikov --m 1.7 --gamma 1.2 [--integrand derived|printed|both]`: amplitude A of the Mel'nikov
function, M(psi0) = A sin(psi0) sqrt(a - 2b) (paper sec. 7, eq:Mel_ext), with its error estimate
(float64 vs real128 quadrature plus a rigorous tail bound).  --find-zero searches gamma in --bracket for
A(gamma) = 0 at the given m.

`magrod melnikov --model NAME|FILE.py [--model-params ...] --parameter P --value0 V`: the Mel'nikov function
M(phi0) of any model with a saddle and a small parameter, for P moved from its integrable member P = V, along the
member's computed symmetric homoclinic orbit (magrod.separatrix.melnikov_along_orbit): its Fourier coefficients,
leading harmonic and evidence.  A model without a candidate integral, an integrable member or a reversor that
survives the perturbation is named with what it lacks (exit 2)."""
from __future__ import annotations

from ..core.errors import ParameterError
from .options import add_model, is_paper_model, number

PAPER_OPTIONS = ("m", "gamma", "integrand", "find_zero", "bracket")  # eq:Mel_ext's, along the paper's closed form


def add_arguments(p):
    p.add_argument("--m", default=None, help="m = m3/sqrt(B C2) (0 < m < 2 sqrt(1 + gamma)); required for the paper's "
                                             "rod")
    p.add_argument("--gamma", default=None, help="extensibility gamma >= 0 (required unless --find-zero)")
    p.add_argument("--integrand", default=None, choices=["derived", "printed", "both"],
                   help="derived: from eq:melnikov_bracket; printed: eq:Mel_ext as printed (default derived)")
    p.add_argument("--find-zero", action="store_true", help="search gamma with A(gamma) = 0 in --bracket")
    p.add_argument("--bracket", nargs=2, default=None, metavar=("LO", "HI"),
                   help="gamma interval for --find-zero (the paper reports a zero between 1.8 and 2)")
    add_model(p, help="the rod model: a registered name (`magrod models`) or a model file, with a saddle and a small "
                      "parameter (default: the paper's rod)")
    p.add_argument("--parameter", default=None, help="another model: the parameter moved from its integrable member")
    p.add_argument("--value0", default=None, help="another model: the value of --parameter at the integrable member")


def run(args) -> dict:
    from ..separatrix import INTEGRANDS, melnikov_amplitude as amplitude, melnikov_amplitude_zero as amplitude_zero

    if not is_paper_model(args.model):
        return _model_run(args)
    if args.model_params:
        raise ParameterError("model_params", "needs --model (the paper's rod takes --m --gamma)")
    for name in ("parameter", "value0"):
        if getattr(args, name) is not None:
            raise ParameterError(name, "belongs to another model's Mel'nikov function along its computed orbit (give "
                                       "--model); the paper's rod's is eq:Mel_ext in --m --gamma")
    if args.m is None:
        raise ParameterError("m", "missing: the paper's rod's Mel'nikov amplitude needs --m (or give --model for "
                                  "another model)")
    args.integrand = "derived" if args.integrand is None else args.integrand
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


def _model_run(args) -> dict:
    """Another model: melnikov_along_orbit(system, parameter, value0) with its evidence."""
    from ..separatrix import melnikov_along_orbit
    from .modelrun import refuse
    from .options import system_from

    system, _ = system_from(args)
    refuse(args, PAPER_OPTIONS, system.model, "belongs to the paper's rod's eq:Mel_ext")
    if args.parameter is None:
        raise ParameterError("parameter", f"missing: the parameter moved from the integrable member, one of the "
                                          f"parameters of the model {system.model!r}: {', '.join(system.names)}")
    if args.value0 is None:
        raise ParameterError("value0", f"missing: the value of {args.parameter} at the integrable member")
    value0 = number("value0", args.value0)
    r = melnikov_along_orbit(system, args.parameter, value0)
    h = r.harmonic
    return {"ok": bool(r.success), "model": system.model, "params": system.params, "parameter": r.parameter,
            "value0": r.value0, "integral": r.integral,
            "convention": "M(phi0) = int grad I . df/dp along the integrable member's symmetric homoclinic orbit "
                          "rotated to phase phi0, per unit change of the parameter; coefficients (c0, a1, b1, ...) of "
                          "c0 + sum a_k cos(k phi0) + b_k sin(k phi0)",
            "harmonic": h, "amplitude": r.amplitude, "cos_coefficient": float(r.coefficients[2 * h - 1]),
            "sin_coefficient": float(r.coefficients[2 * h]), "coefficients": [float(c) for c in r.coefficients],
            "phi0": [float(v) for v in r.phi], "M": [float(v) for v in r.M], "accuracy": r.accuracy,
            "message": r.message, **({} if r.success else {"error": r.message})}


def format_text(r: dict) -> str:
    if r.get("model"):
        from .modelrun import checks, header

        k = r["harmonic"]
        return "\n".join([f"Mel'nikov function of {header(r)}, {r['parameter']} moved from {r['value0']:g} (integral "
                          f"{r['integral']}):",
                          f"  M(phi0) ~ {r['cos_coefficient']:+.12g} cos({k} phi0) {r['sin_coefficient']:+.12g} "
                          f"sin({k} phi0) (leading harmonic {k}, amplitude {r['amplitude']:.12g})",
                          f"  checks: {checks(r['accuracy'])}"])
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
