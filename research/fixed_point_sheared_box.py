"""What a box that follows the fixed point would buy statement 11's lambdabar interval (a measurement; not a proof).

The first shipped box (fixed_point_fig4a_interval.json as it was, W = 1e-6; here re-proved by `section_fixed_point.prove`
with the fixed box, `magrod prove --fixed-point --lam-rad 1/1000000 --box fixed`) flies Theta x {0} x {0} x N x
Lambda: the theta-box
r = 20 W, independent of lambdabar, and the level's pbar_psi box N, independent of theta.  The half-map A is enclosed
over all of it, and its entries' radii (b, c) are what limit the box (research/README.md, "Interval theorems").
Here the same flight (the certificate's exact steps, the same validated integrator) starts instead from the
parallelepiped that follows the family of fixed points: theta = theta_c + v (lambdabar - lambdabar_c) + s, s in
[-K' W, K' W], pbar_psi = p_c + (dpbar_psi/dtheta)(theta - theta_c) + (dpbar_psi/dlambdabar)(lambdabar - lambdabar_c)
+ [-1e-9, 1e-9] (the level's tangent plane; float slopes), v = dtheta*/dlambdabar = -5.23 (the 21 tiles' centres).
It prints the enclosures of b = dpbar_theta/dtheta, c = dtheta/dpbar_theta and 2 + 4bc at the crossing against the
shipped box's.  Not a certificate: the level's residual and the Newton in s are not validated here.

    python research/fixed_point_sheared_box.py [K'=2] [v=-5.2336]
"""
from __future__ import annotations

import json
import sys
from fractions import Fraction

from flint import arb

from magrod.generated import validated as gen
from magrod.proof import ball, fields, section_return as sr, taylor
from magrod.proof.provers import section_fixed_point


def main():
    p0, h0 = section_fixed_point.validate("17/10", "2/5", "3", "3", "27/200", "9/10")
    st0 = section_fixed_point.interval_settings_for(p0, h0, 0.383046, Fraction(1, 10**6))
    st0 = section_fixed_point.FixedPointSettings(lam_rad=st0.lam_rad, r=20 * st0.lam_rad, p_rad=st0.p_rad)
    c = section_fixed_point.prove(p0, h0, 0.383046, st0).certificate  # the fixed box of the first certificate
    W = Fraction(c["settings"]["lam_rad"])
    K = Fraction(sys.argv[1]) if len(sys.argv) > 1 else Fraction(2)
    v = Fraction(sys.argv[2]) if len(sys.argv) > 2 else Fraction("-5.2336")
    p, h = section_fixed_point.validate("17/10", "2/5", "3", "3", "27/200", "9/10")
    thc, pc = Fraction(c["point"]["theta_c"]), Fraction(c["point"]["p_c"])
    with ball.workprec(128):
        fld = fields.lam_state_field(p)

        def H(th, pp, lam):
            q = list(p.balls())
            q[fields.LAM] = ball.q(lam)
            return float(gen.chart_hamiltonian([ball.q(th), arb(0), arb(0), ball.q(pp)], q)[0].mid())

        e = Fraction(1, 10**7)
        Hp = (H(thc, pc + e, p.lam) - H(thc, pc - e, p.lam)) / (2 * float(e))
        Ht = (H(thc + e, pc, p.lam) - H(thc - e, pc, p.lam)) / (2 * float(e))
        Hl = (H(thc, pc, p.lam + e) - H(thc, pc, p.lam - e)) / (2 * float(e))
        dpt, dpl = -Ht / Hp, -Hl / Hp
        C = [[1.0 if i == j else 0.0 for j in range(5)] for i in range(5)]
        for j, col in {0: [1, 0, 0, dpt, 0], 4: [float(v), 0, 0, dpt * float(v) + dpl, 1]}.items():
            for i in range(5):
                C[i][j] = col[i]
        S = taylor.initial_set([ball.q(thc), arb(0), arb(0), ball.q(pc), ball.q(p.lam)], c1=True)
        S.C = ball.exact_matrix(C)
        eps = Fraction(1, 10**9)
        S.r0 = ball.vec([ball.interval(-K * W, K * W), arb(0), arb(0), ball.interval(-eps, eps),
                         ball.interval(-W, W)])
        X0 = S.hull()
        pars = fields.parameter_balls(p, W)
        g, dg, base = sr.chart_section(pars)
        first, second = sr.phase_guards(pars, fld)
        fl = c["flights"]["box"]
        S = taylor.propagate(fld, S, steps=[Fraction(x) for x in fl["steps1"]], order=20, guard=first)
        S = taylor.propagate(fld, S, steps=[Fraction(x) for x in fl["steps2"]], order=20, guard=second)
        cr = taylor.cross_section(fld, S, g, dg, Fraction(c["point"]["h_cross"]), 20, guard=base)
        q = sr.section_quantities(p, fld, cr, sr.tangents(pars, X0), gen)
        b, cc = q["dpt_theta"], q["dth_ptheta"]
        e0 = c["flights"]["box"]["enclosures"]
        out = {"W": float(W), "K'": float(K), "v": float(v),
               "sheared": {"b": [float(b.mid()), float(b.rad())], "c": [float(cc.mid()), float(cc.rad())],
                           "2+4bc": [float((2 + 4 * b * cc).mid()), float((2 + 4 * b * cc).rad())],
                           "theta hull at t=0": float(X0[0].rad())},
               "shipped box": {"b": [float(Fraction(e0["dpt_theta"]["mid"])), float(Fraction(e0["dpt_theta"]["rad"]))],
                               "c": [float(Fraction(e0["dth_ptheta"]["mid"])), float(Fraction(e0["dth_ptheta"]["rad"]))],
                               "trace": [float(Fraction(c["trace"]["mid"])), float(Fraction(c["trace"]["rad"]))]}}
        print(json.dumps(out))


if __name__ == "__main__":
    main()
