"""Kind "section_fixed_point" (statement 11; the prover is magrod/proof/provers/section_fixed_point.py, everything here re-implemented
from its module docstring): a symmetric hyperbolic fixed point of the section map sin psi = 0 on Hbar = h -- the
level's interval Newton, the two phase guards, the section derivatives, the Fix(R) Newton step and the monodromy
trace (det DP = 1 from the Hamiltonian form, which schema.check_structure checks).
"""
from __future__ import annotations

import time

from flint import arb

from .. import ball, fields, taylor
from ..section_return import sheared_fixed_point_set
from ..theorem import section_fixed_point_theorem
from .schema import (VerifyResult, check_structure, checked, frac, inside, recomputed, recomputed_meet,
                     section_settings)


def verify(cert, module, t0) -> VerifyResult:
    def body(claim):
        p, prec, cap, order = section_settings(cert)
        with ball.workprec(prec, cap):
            return p, _fixed_point(cert, p, order, module, claim)

    checks, out, failed = checked(t0, body)
    if failed:
        return failed
    p, vals = out
    return VerifyResult(True, "certificate verified: every enclosure recomputed and every check holds", checks,
                        time.perf_counter() - t0,
                        section_fixed_point_theorem(p.as_json(), cert["level"], cert["settings"].get("lam_rad", "0"),
                                                    cert["point"].get("branch", "0"),  # the branch _fixed_point flew
                                                    "v" in cert["settings"]),
                        {}, vals)


def _fp_hamgrad(pars, x, module):
    from flint import arb_series

    out = []
    for i in range(len(x)):
        y = [arb_series([v, 1 if j == i else 0], prec=2) for j, v in enumerate(x)]
        c = module.chart_hamiltonian(y, pars)[0]
        cs = c.coeffs() if isinstance(c, arb_series) else [c]
        out.append(cs[1] if len(cs) > 1 else arb(0))
    return out


def _fixed_point(cert, p, order, module, claim) -> dict:
    TH, PS, PT, PP = fields.THETA, fields.PSI, fields.PTHETA, fields.PPSI
    s, pt = cert["settings"], cert["point"]
    h = frac(cert["level"])
    r, prad, t1, lead = (frac(s[k]) for k in ("r", "p_rad", "t1", "lead"))
    thc, pc, t_a, hc = (frac(pt[k]) for k in ("theta_c", "p_c", "t_a", "h_cross"))
    # what the certificate must contain, and which theorem (cheap, first)
    lam_rad = frac(s.get("lam_rad", "0"))  # absent: a certificate at the point (the first section certificates)
    branch = pt.get("branch", "0")  # absent: psi = 0 (the Fig 4 certificates)
    if branch not in ("0", "pi"):
        raise ValueError("the point's branch is '0' or 'pi'")
    psi0 = arb(0) if branch == "0" else arb.pi()
    moving = "v" in s  # the box follows the fixed point along lambdabar: theta = theta_c + v (lambdabar - lam) + s
    want = section_fixed_point_theorem(p.as_json(), cert["level"], s.get("lam_rad", "0"), branch, moving)
    claim("theorem text", cert["theorem"] == want,
          "the certificate's theorem is the one its verified content establishes"
          + ("" if cert["theorem"] == want else f" (expected: {want[:120]}...; states: {str(cert['theorem'])[:120]}...)"))
    claim("settings match the data", hc == 2 * lead and r > 0 and prad > 0 and 0 < t1 < t_a and thc > 0
          and lam_rad >= 0 and (lam_rad > 0 or not moving),
          "the crossing step is 2 lead; r, p_rad > 0; 0 < t1 < t_a; theta_c > 0; lam_rad >= 0; a moving box (v) only "
          "on a lambdabar interval")
    fl = cert["flights"]
    claim("flights present", isinstance(fl, dict) and set(fl) == {"thin", "box"},
          f"exactly the thin flight (theta_c) and the box flight (Theta); got {sorted(fl) if isinstance(fl, dict) else fl}")
    sb = {k: ball.from_json(v) for k, v in fl["box"]["enclosures"].items()}
    tr_s = ball.from_json(cert["trace"])
    claim("claims on the certificate's balls", ball.negative(sb["gdot"]) and ball.excludes_zero(sb["dth_ptheta"])
          and inside(ball.from_json(cert["newton"]), ball.interval(thc - r, thc + r))
          and ball.bounds(abs(tr_s))[0] > 2,
          "negative crossing, F' excludes 0, Newton inside Theta, |tr DP| > 2")
    check_structure(module, claim)
    claim("field digest", cert["field_digest"] == fields.source_digest(module) == fields.source_digest(fields.gen),
          "the certificate's vector field is the installed derive-generated one (SHA-256 of generated/validated.py)")
    claim("parameters", p.m > 0 and min(p.gamma, p.delta, p.mu) >= 0, "m > 0; gamma, delta, mu >= 0")
    pars = list(p.balls())
    ilam, imu = fields.PARAMS.index("lam"), fields.PARAMS.index("mu")
    if lam_rad:  # lambdabar as the ball [lam - lam_rad, lam + lam_rad]: every enclosure holds on the interval
        pars[ilam] = ball.interval(p.lam - lam_rad, p.lam + lam_rad)
    pars = tuple(pars)
    # a lambdabar interval rides in the state (fields.lam_state_field: lambdabar' = 0), a point in the parameters
    fld = fields.lam_state_field(p, module) if lam_rad else fields.chart_field(p, module)
    Lam = [pars[ilam]] if lam_rad else []

    def H(x):
        return module.chart_hamiltonian(x, pars)[0]

    # 1. the level: pbar_psi(theta) by interval Newton, on the box and at the centre
    Theta = ball.interval(thc - r, thc + r)
    Pb = ball.interval(pc - prad, pc + prad)
    levels = {}
    sheared = {}
    if moving:  # the box's points theta_c + v dl + s as an exact parallelepiped (section_return)
        sheared = sheared_fixed_point_set(p, h, thc, frac(s["v"]), r, lam_rad, pc, prad, branch, module)
        claim("level Newton (box)", sheared["level_ok"],
              f"a unique pbar_psi with Hbar = h for every point of the moving box and every lambdabar, inside "
              f"{sheared['level']}, and at (theta_c, lam), inside {sheared['level_centre']}")
        recomputed(claim, "level (box)", sheared["level"], pt["level_newton"]["box"])
        recomputed(claim, "level (centre)", sheared["level_centre"], pt["level_newton"]["centre"])
        levels["centre"] = sheared["level_centre"]
    for key, th in () if moving else (("box", Theta), ("centre", ball.q(thc))):
        dH = _fp_hamgrad(pars, [th, psi0, arb(0), Pb], module)[PP]
        N = ball.q(pc) - (H([th, psi0, arb(0), ball.q(pc)]) - ball.q(h)) / dH
        claim(f"level Newton ({key})", ball.excludes_zero(dH) and inside(N, Pb),
              f"a unique pbar_psi(theta) with Hbar(theta, {branch}, 0, pbar_psi) = h in the box, inside {N}")
        recomputed(claim, f"level ({key})", N, pt["level_newton"][key])
        levels[key] = N

    # 2-3. the flights (exact steps), two phases, one negative crossing of sin psi = 0
    def base(Y):
        return [Y[TH], arb.pi() - Y[TH], pars[imu] - 2 * (Y[4] if len(Y) > 4 else pars[ilam]) * Y[PP]]

    def sdot(Y):
        return Y[PS].cos() * fld.f(Y)[PS]

    def first(Y):
        return base(Y) + [sdot(Y)]

    def second(Y):
        sn = Y[PS].sin()
        return base(Y) + [sn if ball.positive(sn) else -sdot(Y)]

    def g(x):
        return x[PS].sin()

    def dg(x):
        return [arb(0), x[PS].cos()] + [arb(0)] * (len(x) - 2)

    got = {}
    for kind in ("thin", "box"):
        st1 = [frac(v) for v in fl[kind]["steps1"]]
        st2 = [frac(v) for v in fl[kind]["steps2"]]
        claim(f"{kind} steps", sum(st1) == t1 and sum(st1) + sum(st2) == t_a and all(v > 0 for v in st1 + st2),
              f"the exact steps add up to t1 = {float(t1):.6g} (phase 1) and t_a = {float(t_a):.9g} (both phases)")
        if moving and kind == "box":
            x, S = sheared["Q"], sheared["set"]
        else:  # moving: the thin set is the point (theta_c, lam), lambdabar a state at lam
            th, pbox = (ball.q(thc), levels["centre"]) if kind == "thin" else (Theta, levels["box"])
            x = [th, psi0, arb(0), pbox] + ([ball.q(p.lam)] if moving else Lam)
            xc = [v.mid() for v in x]
            S = taylor.initial_set(xc, c1=True)
            S.r0 = ball.vec([a - b for a, b in zip(x, xc)])
        try:
            S = taylor.propagate(fld, S, steps=st1, order=order, guard=first)
            S = taylor.propagate(fld, S, steps=st2, order=order, guard=second)
            cr = taylor.cross_section(fld, S, g, dg, hc, order, guard=base)
        except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
            claim(f"{kind} flight", False, str(err))
        gH = _fp_hamgrad(pars, x[:4], module)
        z = [arb(0)] * len(Lam)
        tang = {"th": [arb(1), arb(0), arb(0), -gH[TH] / gH[PP]] + z,
                "pt": [arb(0), arb(0), arb(1), -gH[PT] / gH[PP]] + z}
        if moving and kind == "box":  # along lambdabar with the box (theta_c + v dl + s, s fixed)
            tang["l"] = sheared["tangent_lam"]
        gg = dg(cr.x)
        gf = sum((a * b for a, b in zip(gg, cr.fx)), arb(0))
        q = {"ptheta": cr.x[PT], "theta": cr.x[TH], "cospsi": cr.x[PS].cos(), "gdot": cr.gdot, "tau": cr.tau}
        for name, t in tang.items():
            u = ball.column(cr.W * ball.vec(t))
            gu = sum((a * b for a, b in zip(gg, u)), arb(0))
            v = [ui - fi * gu / gf for ui, fi in zip(u, cr.fx)]
            q[f"d{name}_theta"], q[f"d{name}_ptheta"] = v[TH], v[PT]
        for k, val in q.items():
            recomputed(claim, f"{kind} {k}", val, fl[kind]["enclosures"][k])
        got[kind] = q
    thin, bx = got["thin"], got["box"]
    claim("negative crossing", ball.negative(sb["gdot"]),
          "d(sin psi)/dt < 0 over the crossing step: the half-way point on Fix(R), not a return to Sigma+")
    # 4. Fix(R): one theta* in Theta whose orbit meets pbar_theta = 0 at the crossing (moving: for each lambdabar,
    # in theta_c + v dl + [-r, r], the Newton step taken in s about the line's point: the same formula shifted by v dl)
    if moving:  # pbar_theta(theta_c + v dl, lam + dl) = pbar_theta(theta_c, lam) + (d/dl along the box) dl
        Fc = thin["ptheta"] + bx["dl_ptheta"] * ball.interval(-lam_rad, lam_rad)
    else:
        Fc = thin["ptheta"]
    N = ball.q(thc) - Fc / bx["dth_ptheta"]
    recomputed(claim, "Fix(R) Newton", N, cert["newton"])
    claim("unique theta*", ball.excludes_zero(sb["dth_ptheta"]) and inside(ball.from_json(cert["newton"]), Theta),
          "the interval Newton image lies inside Theta: exactly one theta* in Theta, its orbit meets Fix(R)"
          + (" (Theta and the image moving with lambdabar by v (lambdabar - lam))" if moving else ""))
    # 5. hyperbolicity: DP(x0) = R A^-1 R A, tr = 2 (ad + bc) / (ad - bc); det A = 1 (Hamilton's flow: the transition
    # psi = 0 -> pi preserves dtheta ^ dpbar_theta on the level's tangents), so also tr = 2 + 4 bc = 4 ad - 2: the
    # recomputed enclosure is the intersection of the three, decided exactly
    a, b, c, d = bx["dth_theta"], bx["dpt_theta"], bx["dth_ptheta"], bx["dpt_ptheta"]
    recomputed_meet(claim, "tr DP(x0)", [2 * (a * d + b * c) / (a * d - b * c), 2 + 4 * b * c, 4 * a * d - 2],
                    cert["trace"])
    claim("hyperbolic", ball.bounds(abs(tr_s))[0] > 2, f"|tr DP(x0)| > 2 on the certificate's ball {tr_s}: a saddle")
    sq = (tr_s * tr_s - 4).sqrt()
    sgn = 1 if ball.positive(tr_s) else -1
    mus = [(tr_s + sgn * sq) / 2]
    lo, hi = ball.bounds(tr_s)
    if lo > 2 or hi < -2:  # mu_u is increasing in tr on |tr| > 2: its values at the two end points bound it
        ends = [(t + sgn * (t * t - 4).sqrt()) / 2 for t in (ball.q(lo), ball.q(hi))]
        mus.append(ends[0].union(ends[1]))
    recomputed_meet(claim, "mu_u", mus, cert["mu_u"])
    T = ball.q(2 * t_a) + 2 * ball.from_json(fl["box"]["enclosures"]["tau"])
    theta_star = cert["newton"]
    if moving:  # theta*(lambdabar) over the interval: the Newton ball moved by v dl
        theta_star = ball.to_json(ball.from_json(cert["newton"]) + ball.q(frac(s["v"])) * ball.interval(-lam_rad, lam_rad))
    return {k: [ball.decimal(v) for v in ball.json_bounds(x)]
            for k, x in (("theta*", theta_star), ("tr DP(x0)", cert["trace"]), ("mu_u", cert["mu_u"]),
                         ("return time T", ball.to_json(T)))}
