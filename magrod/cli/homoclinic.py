"""`magrod homoclinic --m 1.7 --gamma 1`: the homoclinic orbit of the extensible rod at lambdabar = 0 (paper
sec. 6): roots u_pm, k, kappa, theta_max, h, m_c, and the check of the closed form against an independent
multiprecision heyoka integration of Hamilton's equations from the turning point (magrod.orbits.homoclinic.verify)."""
from __future__ import annotations

from .options import integer, number


def add_arguments(p):
    p.add_argument("--m", required=True, help="m = m3/sqrt(B C2) (0 < m < m_c = 2 sqrt(1 + gamma))")
    p.add_argument("--gamma", required=True, help="extensibility gamma >= 0 (0: inextensible Kirchhoff rod)")
    p.add_argument("--theta-stop", default=None, help="compare closed form and integration until theta = this "
                                                       "(default 1e-8)")
    p.add_argument("--n", default=None, help="grid points per time direction for the comparison (default 201)")
    p.add_argument("--no-verify", action="store_true", help="skip the multiprecision integration")


def run(args) -> dict:
    from ..core.errors import ParameterError
    from ..orbits import homoclinic_closed_form as homoclinic, verify_homoclinic as verify

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
        # the acceptance: closed form and integration agree to <= 1e-12 in theta until theta_stop
        out["ok"] = bool(v["max_dev_theta"] <= 1e-12)
    return out


def format_text(r: dict) -> str:
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
