"""Fig 4(a) on h = 9/10: how far the validated flight gets towards a transverse homoclinic point of the
section map's saddle x0 (statement 11).  Measurements, not a proof.

1. DP over a box N = x0 + T([-rho, rho]^2) (T = [e_u, e_s], the float eigenvectors of DP(x0) from the certificate's
   A): the C^1 flight of N for one full return (the phases of magrod/proof/provers/section_fixed_point.py, then the positive crossing),
   M = T^-1 DP T over N, and the cone slope L for which Zgliczynski's cone condition Q(Mv) > Q(v),
   Q(u, s) = u^2 - s^2/L^2, holds for every M in the enclosure (the smallest of a ladder of L).
2. The thickness budget of the homoclinic arc: a W^u point at distance u from x0 is known to within L u in s.

    python research/fig4_homoclinic_budget.py [out.json]
"""
from __future__ import annotations

import json
import math
import sys
import time
from fractions import Fraction
from importlib import resources

import numpy as np
from flint import arb

from magrod.proof import ball, fields, taylor
from magrod.proof.provers import section_fixed_point

OUT = next((a for a in sys.argv[1:] if not a.startswith("--")), "fig4_homoclinic_budget.json")
TH, PS, PT, PP = fields.THETA, fields.PSI, fields.PTHETA, fields.PPSI


def full_return(p, h, fld, Q, t_a, lead, module=fields.gen):
    """C^1 flight of the chart box Q through one return of P (positive crossing at the end): (crossing, tangents)."""
    g, dg, base = section_fixed_point.chart_section(p, module)
    first, _ = section_fixed_point.phase_guards(p, fld, module)

    def general(Y):  # no positive crossing: sin psi excludes 0, or d(sin psi)/dt < 0
        s = Y[PS].sin()
        if ball.excludes_zero(s):
            return base(Y) + [arb(1)]
        return base(Y) + [-(Y[PS].cos() * fld.f(Y)[PS])]

    S = section_fixed_point.initial_box(p, Q[TH], Q[PP])
    S.r0 = ball.vec([a - a.mid() for a in Q])
    S.xbar = ball.vec([a.mid() for a in Q])
    tr = taylor.Trajectory()
    S = taylor.propagate(fld, S, Fraction(1, 64), order=20, guard=first, record=tr)
    S = taylor.propagate(fld, S, t_a, order=20, guard=general, record=tr)
    cr = taylor.cross_section(fld, S, g, dg, 2 * lead, 20, guard=base)
    return cr, tr


def main():
    cert = json.loads(resources.files("magrod.proof").joinpath("certificates", "fixed_point_fig4a.json").read_text())
    p, h = section_fixed_point.validate(*(cert["params"][k] for k in ("m", "mu", "gamma", "delta", "lam")), cert["level"])
    fld = fields.chart_field(p)
    enc = {k: float(Fraction(v["mid"])) for k, v in cert["flights"]["box"]["enclosures"].items()}
    A = np.array([[enc["dth_theta"], enc["dpt_theta"]], [enc["dth_ptheta"], enc["dpt_ptheta"]]])
    R = np.diag([1.0, -1.0])
    DP = R @ np.linalg.inv(A) @ R @ A
    w, V = np.linalg.eig(DP)
    o = np.argsort(-abs(w))
    w, V = w[o].real, V[:, o].real
    V = V / np.linalg.norm(V, axis=0)
    out = {"DP_float": DP.tolist(), "eigenvalues": w.tolist(), "T": V.tolist(), "rows": []}
    thc = Fraction(cert["point"]["theta_c"])
    pc = Fraction(cert["point"]["p_c"])
    T_ret = 2 * float(Fraction(cert["point"]["t_a"])) + 2 * float(Fraction(cert["flights"]["box"]["enclosures"]["tau"]["mid"]))
    lead = Fraction(1, 256)
    t_a = Fraction(math.floor((T_ret - float(lead)) * 2**20), 2**20)
    Tm = ball.exact_matrix(V.tolist())
    Ti = Tm.inv()
    with ball.workprec(128):
        for rho in (Fraction(1, 10**6), Fraction(1, 10**5), Fraction(1, 10**4)):
            t0 = time.perf_counter()
            U = ball.interval(-rho, rho)
            d = ball.column(Tm * ball.vec([U, U]))
            th = ball.q(thc) + d[0]
            pt = d[1]
            # pbar_psi over the box by interval Newton (Hbar(theta, 0, pt, .) = h)
            P0 = ball.interval(pc - 1000 * rho, pc + 1000 * rho)
            Hc = fields.gen.chart_hamiltonian([th, arb(0), pt, ball.q(pc)], p.balls())[0]
            dH = section_fixed_point.ham_gradient(p, [th, arb(0), pt, P0])[PP]
            N = ball.q(pc) - (Hc - ball.q(h)) / dH
            row = {"rho": float(rho), "level_newton_inside": ball.subset(N, P0)}
            Q = [th, arb(0), pt, N]
            try:
                cr, tr = full_return(p, h, fld, Q, t_a, lead)
            except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
                row.update(ok=False, error=str(err)[:200])
                out["rows"].append(row)
                print(row, flush=True)
                continue
            q = section_fixed_point.section_quantities(p, fld, cr, section_fixed_point.tangents(p, Q))
            DPb = arb_mat2([[q["dth_theta"], q["dpt_theta"]], [q["dth_ptheta"], q["dpt_ptheta"]]])
            M = Ti * DPb * Tm
            Mf = [[(float(M[i, j].mid()), float(M[i, j].rad())) for j in range(2)] for i in range(2)]
            # the smallest L of a ladder with the cone condition: M'^T Q M' - Q positive definite, M' = S M S^-1,
            # S = diag(1, 1/L), Q = diag(1, -1)
            Lbest = None
            for e in np.arange(-8, 1, 0.25):
                L = ball.q(Fraction(10.0 ** e))
                Mp = [[M[0, 0], M[0, 1] * L], [M[1, 0] / L, M[1, 1]]]
                a11 = Mp[0][0] * Mp[0][0] - Mp[1][0] * Mp[1][0] - 1
                a22 = Mp[0][1] * Mp[0][1] - Mp[1][1] * Mp[1][1] + 1
                a12 = Mp[0][0] * Mp[0][1] - Mp[1][0] * Mp[1][1]
                if ball.positive(a11) and ball.positive(a22) and ball.positive(a11 * a22 - a12 * a12):
                    Lbest = float(10.0 ** e)
                    break
            row.update(ok=True, steps=len(tr.steps), wall_s=round(time.perf_counter() - t0, 1),
                       crossing_width=max(ball.width(v) for v in cr.x), M=Mf, cone_L=Lbest,
                       gdot=str(cr.gdot))
            out["rows"].append(row)
            print(json.dumps(row), flush=True)
    json.dump(out, open(OUT, "w"), indent=1)
    print("wrote", OUT)


def arb_mat2(rows):
    from flint import arb_mat

    return arb_mat(2, 2, [rows[0][0], rows[0][1], rows[1][0], rows[1][1]])


if __name__ == "__main__":
    main()
