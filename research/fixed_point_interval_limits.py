"""How wide a lambdabar box the section fixed point's proof closes (statements 11 and 13 on a lambdabar interval), and
which check fails first beyond it.

For Fig 4(a) (h = 9/10, lambdabar = 27/200, theta* = 0.3830) and Fig 5(a) (h = 4/5, lambdabar = 2, mu = 4, the
psi = pi branch) and a ladder of half-widths W: `section_fixed_point.prove` with lambdabar a fifth state variable (the theta-box
r = K W, K = 20 at 4(a), where theta* moves by ~17 W over the box, K = 2 at 5(a), where it moves by ~1.7 W), the
outcome, the first check that fails, and the enclosures that decide it (tr DP(x0), the Fix(R) Newton radius and the
entries b = dpbar_theta/dtheta, c = dtheta/dpbar_theta of the half-map A); then the complete verifier on every box that
proves.  Numerical measurements of rigorous widths; the widths behind the shipped certificates
fixed_point_fig4a_interval.json (W = 1e-6) and fixed_point_fig5a_interval.json (W = 1e-5) as first shipped (fixed boxes;
the shipped ones now move with lambdabar: research/fig4_lambda_interval.py, docs "The moving box"), which `--write DIR`
writes.

    python research/fixed_point_interval_limits.py [--out research/fixed_point_interval_limits.json] [--write DIR]
"""
from __future__ import annotations

import argparse
import json
import time
from fractions import Fraction
from pathlib import Path

#: (panel, (m, mu, gamma, delta, lambdabar, h), theta guess, root, branch, K, [(W, shipped?)])
CASES = (
    ("4a", ("17/10", "2/5", "3", "3", "27/200", "9/10"), 0.3830461903149033, -1, "0", 20,
     [("1/5000000", False), ("1/2000000", False), ("1/1000000", True), ("6/5000000", False), ("7/5000000", False)]),
    ("5a", ("17/10", "4", "3/20", "1/4", "2", "4/5"), 3.012, 0, "pi", 2,
     [("1/1000000", False), ("1/200000", False), ("1/100000", True), ("1/50000", False)]),
)


def _f(d) -> list:
    return [float(Fraction(d["mid"])), float(Fraction(d["rad"]))]


def main():
    from magrod.proof import verify
    from magrod.proof.provers import section_fixed_point

    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=None)
    ap.add_argument("--write", default=None, help="write the shipped boxes' certificates into this directory")
    args = ap.parse_args()
    rows = []
    t_all = time.perf_counter()
    for panel, pars, guess, root, branch, K, ladder in CASES:
        p, h = section_fixed_point.validate(*pars)
        for w, shipped in ladder:
            W = Fraction(w)
            st = section_fixed_point.FixedPointSettings(lam_rad=W, r=K * W, p_rad=max(Fraction(1, 10**8), 16 * (K + 1) * W))
            res = section_fixed_point.prove(p, h, guess, st, root=root, branch=branch)
            row = {"panel": panel, "lam_rad": w, "K": K, "ok": res.ok, "reason": res.reason[:200],
                   "prove_s": round(res.wall_time_s, 1)}
            if res.ok:
                c = res.certificate
                e = c["flights"]["box"]["enclosures"]
                row.update(trace=_f(c["trace"]), newton_rad=float(Fraction(c["newton"]["rad"])),
                           b=_f(e["dpt_theta"]), c=_f(e["dth_ptheta"]))
                v = verify.verify(json.loads(json.dumps(c)))
                row.update(verified=v.ok, verify_s=round(v.wall_time_s, 1))
                if shipped and args.write and v.ok:
                    Path(args.write).mkdir(parents=True, exist_ok=True)
                    (Path(args.write) / f"fixed_point_fig{panel}_interval.json").write_text(json.dumps(c, indent=1))
            rows.append(row)
            print(json.dumps(row), flush=True)
    out = {"rows": rows, "wall_s": round(time.perf_counter() - t_all, 1)}
    if args.out:
        Path(args.out).write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
