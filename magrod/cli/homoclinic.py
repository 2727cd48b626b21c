"""`magrod homoclinic --m 1.7 --gamma 1`: the homoclinic orbit of the extensible rod at lambdabar = 0 (paper
sec. 6): roots u_pm, k, kappa, theta_max, h, m_c, and the check of the closed form against an independent
multiprecision heyoka integration of Hamilton's equations from the turning point (magrod.orbits.homoclinic.verify).

`magrod homoclinic --model NAME|FILE.py [--model-params ...]`: the symmetric homoclinic orbit to the straight twisted
rod of any reversible model (`mr.homoclinic_orbit`), with its evidence (Fix(R) residual, H and Casimir drift, launch
level gap, reversor defect); with --out DIR also its orbit file DIR/homoclinic_orbit.npz (+ .json), which
`magrod rod --from` reads.  A model without a saddle or a reversor is named with what it lacks (exit 2)."""
from __future__ import annotations

from .options import add_model, integer, is_paper_model, number

PAPER_OPTIONS = ("m", "gamma", "theta_stop", "n", "no_verify")  # the closed form's, on the paper's chart


def add_arguments(p):
    p.add_argument("--m", default=None, help="m = m3/sqrt(B C2) (0 < m < m_c = 2 sqrt(1 + gamma)); required for the "
                                             "paper's rod")
    p.add_argument("--gamma", default=None, help="extensibility gamma >= 0 (0: inextensible Kirchhoff rod); required "
                                                 "for the paper's rod")
    add_model(p, help="the rod model: a registered name (`magrod models`) or a model file, whose symmetric "
                      "homoclinic orbit to its straight rod is shot onto Fix(R) of its reversor (default: the "
                      "paper's rod, its closed form at lambdabar = 0)")
    p.add_argument("--theta-stop", default=None, help="compare closed form and integration until theta = this "
                                                       "(default 1e-8)")
    p.add_argument("--n", default=None, help="grid points per time direction for the comparison (default 201)")
    p.add_argument("--no-verify", action="store_true", help="skip the multiprecision integration")


def run(args) -> dict:
    from ..core.errors import ParameterError
    from ..orbits import homoclinic_closed_form as homoclinic, verify_homoclinic as verify

    if not is_paper_model(args.model):
        return _model_run(args)
    if args.model_params:
        raise ParameterError("model_params", "needs --model (the paper's rod takes --m --gamma)")
    for name in ("m", "gamma"):
        if getattr(args, name) is None:
            raise ParameterError(name, "missing: the paper's rod's closed form needs --m and --gamma (or give "
                                       "--model for another model)")
    if args.no_verify and (args.theta_stop is not None or args.n is not None):
        raise ParameterError("no_verify", "--theta-stop and --n set up the verification that --no-verify skips")
    orbit = homoclinic(number("m", args.m), number("gamma", args.gamma))
    out = {"ok": True, **orbit.summary(), "kirchhoff": orbit.kirchhoff}
    if not args.no_verify:
        theta_stop = number("theta_stop", "1e-8" if args.theta_stop is None else args.theta_stop)
        if not 1e-30 <= theta_stop < orbit.theta_max:
            raise ParameterError("theta_stop", f"must be in [1e-30, theta_max = {orbit.theta_max:.6g}), got {theta_stop}")
        n = integer("n", "201" if args.n is None else args.n, minimum=2)
        v = verify(orbit, theta_stop=theta_stop, n=n)
        v.pop("arrays")
        out["verify"] = v
        out["max_deviation_theta"] = v["max_dev_theta"]
        # the acceptance bound: closed form and integration agree to <= 1e-12 in theta until theta_stop
        out["ok"] = bool(v["max_dev_theta"] <= 1e-12)
    return out


def _model_run(args) -> dict:
    """Another model: mr.homoclinic_orbit(system), its evidence, and (--out) its orbit file."""
    import magrod as mr

    from .modelrun import equilibrium_dict, orbit_dict, refuse
    from .options import system_from

    system, _ = system_from(args)
    refuse(args, PAPER_OPTIONS, system.model, "belongs to the paper's rod's closed form at lambdabar = 0")
    o = mr.homoclinic_orbit(system)
    res = {"ok": bool(o.success and o.accuracy["passed"]), "model": system.model, "params": system.params,
           "saddle": equilibrium_dict(o.equilibrium), **orbit_dict(o)}
    if not res["ok"]:
        res["error"] = o.message
    elif args.out is not None:
        from ..core.io import ensure_writable_dir, write_model_orbit

        res["orbit_files"] = write_model_orbit(ensure_writable_dir(args.out, "out"), "homoclinic_orbit", o)
    return res


def _model_text(r: dict) -> str:
    from .modelrun import checks, header

    s = r["saddle"]
    lines = [f"symmetric homoclinic orbit of {header(r)}",
             f"  to the {s['kind']} at H = {s['H']:.12g} (unstable eigenvalue {s['unstable_eigenvalue'][0]:.10g} "
             f"{s['unstable_eigenvalue'][1]:+.10g}i)",
             f"  reversor {r['reversor']}: launch angle {r['alpha']:.12g}, half time T = {r['T']:.12g}, launch "
             f"distance {r['launch_distance']:g}",
             f"  checks: {checks(r['accuracy'])}"]
    lines += [f"  wrote {p}" for p in r.get("orbit_files", [])]
    return "\n".join(lines)


def format_text(r: dict) -> str:
    if r.get("model"):
        return _model_text(r)
    lines = [f"homoclinic orbit at m = {r['m']:g}, gamma = {r['gamma']:g} (lambdabar = 0, pbar_psi = 1)"
             + ("  [Kirchhoff limit]" if r["kirchhoff"] else ""),
             f"  u_+ = {r['u_plus']:.16g}   u_- = {r['u_minus'] if r['u_minus'] is not None else '-inf (gamma = 0)'}",
             f"  k = {r['k']:.16g}   kappa = {r['kappa']:.16g}   (sqrt(-V''(0)) = {r['saddle_rate']:.16g})",
             f"  theta_max = {r['theta_max']:.16g}   h = {r['h']:.16g}   m_c = {r['m_c']:.16g}"]
    v = r.get("verify")
    if v:
        lines += [f"  closed form vs hy.real({v['prec_bits']}-bit) integration from the turning point, |t| <= "
                  f"{v['t_stop']:.6g} (theta >= {v['theta_stop']:g}), {v['n']} points per side:",
                  f"    max |dtheta| = {v['max_dev_theta']:.3e}   max |dpbar_theta| = {v['max_dev_ptheta']:.3e}   "
                  f"max |dpsi| = {v['max_dev_psi']:.3e}",
                  f"    generated closed form at the same precision: max |dtheta| = "
                  f"{v['max_dev_theta_generated_hp']:.3e}",
                  f"    max |H0 - h| = {v['max_abs_H0_minus_h']:.3e}   parity residuals (theta, pbar_theta, psi): "
                  f"{v['parity_theta']:.1e}, {v['parity_ptheta']:.1e}, {v['parity_psi']:.1e}",
                  f"    wall time {v['wall_time_s']:.2f} s"]
    return "\n".join(lines)
