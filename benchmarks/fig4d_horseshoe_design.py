"""Issue 27 item 3 at Fig 4(d) (lambdabar = 93/500, h = 9/10, the panel the paper's indicator calls regular): the
float search for the homoclinic point of the section saddle x0 of statement 11 (fixed_point_fig4d.json, psi = 0,
|mu_u(DP)| = 1.615, return time 3.19) and the float design of the covering-relation horseshoe along it
(magrod/proof/horseshoe.py, design "fig4d").  Numerical (float64 heyoka, reduced chart, tol 1e-15); it chooses the
geometry that the prover then proves.  Not a proof.

  1. W^u(x0) meets Fix(R): benchmarks/fig4_candidates.homoclinic_point (fundamental domain s in [1e-7, 1e-7 mu_u]
     on the side +e_u, up to 45 returns, 4-D states; DP(x0) by central differences of one return, eps 1e-7): the
     first sign change of pbar_theta on one branch, bisected; its return n, end point, flight time and the tangent
     of W^u there (W^u-W^s angle = 2 atan |dtheta / dpbar_theta|: W^s = R(W^u)).
  2. The design's linear / hull / sampled margins per link (benchmarks/fig4b_horseshoe_design.py's machinery with
     panel "d" and the prover's design "fig4d"; each flag of that script overrides one field: --m, --qu, --qs,
     --l0, --l1, --wcap).

    python benchmarks/fig4d_horseshoe_design.py [out.json] [--m=0] [--qu=1.5] [--qs=1.3] [--l0=0.8] [--l1=0.1]
        [--wcap=7]

Stored run (fig4d_horseshoe_design.json, 2 cores, ~20 s): W^u on Fix(R) at return 35 from s = 1.1573e-7, theta =
1.81863 on the psi = pi branch, flight time 112.77, W^u-W^s angle 36.8 deg; the design fig4d starts 12 returns
further out (s* = 3.636e-5 = d, n_exc = 23, m = 0, k = 24 sets): every link's margins positive, (a') >= 0.231,
(b) >= 0.500 (linear, hull and sampled alike).  Scratch runs of the same homoclinic orbit (not stored): d = 4.44e-8
(s* = 1.157e-7, n_exc = 35, m = 2, k = 38): qu = qs = 1.5: (a') >= 0.292, (b) >= 0.500; qu = qs = 1.3: 0.231, 0.300;
qu = qs = 1.2: 0.167, 0.200 (its prover run failed at the crossing step near theta = pi: horseshoe.fig4d_settings,
lead); d = 3.64e-5 with qs = 1.5: (a') -0.005 at N0 => N1 (the widths reach only 0.49 d at N1).

The rigorous runs (horseshoe.prove, not a proving design: fig4d_settings is not in horseshoe.DESIGNS; 2 cores):
  1. d = 4.44e-8 (38 sets, centre flights at 1e-28, lead 1/256): chain pass 1 failed after 355 s, at the crossing
     step (length 2 lead = 1/128) of a centre flight near theta = pi ("field not evaluable on the trial enclosure":
     the orbit passes within 0.0103 of theta = pi at its 32nd / 33rd returns).
  2. d = 3.64e-5 (24 sets, tol 1e-25, lead 1/1024): one chain pass (end residual 4.5e-11), then "N0 branch box"
     failed with p_rad = 1e-6 (pbar_psi varies by ~3e-5 over N0), 164 s.
  3. the same with p_rad = 1/2000: N0 .. N17 flown, N18's box flight raised ValueError (a divisor containing 0), 258 s.
  4. the same with N18 .. N22 in 2 x 2 pieces: every piece flown, then N0 => N0 (a') failed: margin 1 - max |y_s| =
     -31.49 (float: +0.38), 613 s at load ~5.  The C^1 enclosure [DP(N0)] over a set of size 3e-5 is ~100x too wide
     for the mean-value form (its excess grows like the size squared relative to the widths): a proof needs d ~ 1e-7,
     i.e. the ~38-set chain of run 1 with lead 1/1024 (est. > 15 min: beyond the 10-minute budget; not run).
"""
from __future__ import annotations

import json
import math
import sys
import time
from fractions import Fraction
from importlib import resources

import numpy as np

import fig4_candidates as fc
import fig4b_horseshoe_design as fb

OUT = next((a for a in sys.argv[1:] if not a.startswith("--")), "fig4d_horseshoe_design.json")


def search():
    t0 = time.perf_counter()
    cert = json.loads(resources.files("magrod.proof").joinpath("certificates", "fixed_point_fig4d.json").read_text())
    smap = fc.SectionMap(str(float(Fraction(cert["params"]["lam"]))))
    th = float(Fraction(cert["point"]["theta_c"]))
    x0 = smap.point(th, 0.0, 0.0, float(Fraction(cert["point"]["p_c"])))
    eps = 1e-7
    D = np.empty((2, 2))
    for c, (a, b) in enumerate(((eps, 0.0), (0.0, eps))):
        yp, _ = smap.step(smap.point(th + a, b, 0.0, x0[fc.PP]))
        ym, _ = smap.step(smap.point(th - a, -b, 0.0, x0[fc.PP]))
        D[:, c] = [(yp[fc.TH] - ym[fc.TH]) / (2 * eps), (yp[fc.PT] - ym[fc.PT]) / (2 * eps)]
    hp = fc.homoclinic_point(smap, {"D": D.tolist()}, x0, jmax=45, n_s=120)
    for p in hp["points"]:
        a, b = p["tangent"]
        p["angle_wu_ws_deg"] = float(2 * math.degrees(math.atan(abs(a / b))))
    out = {"x0": x0.tolist(), "DP": D.tolist(), "det_DP": float(np.linalg.det(D)),
           "eigenvalues": sorted(float(v) for v in np.real(np.linalg.eigvals(D))), **hp,
           "wall_s": round(time.perf_counter() - t0, 1)}
    print(json.dumps({k: v for k, v in out.items() if k != "points"}, default=float))
    for p in hp["points"]:
        print({k: p[k] for k in ("side", "j", "s_star", "theta", "branch", "flight_time", "angle_wu_ws_deg")})
    return out


def main():
    hs = search()
    if not hs["points"]:
        raise SystemExit("no homoclinic point found")
    fb.main(panel="d", design_name="fig4d")  # writes OUT (the first non-flag argument) with its default name
    res = json.load(open(OUT))
    res["homoclinic_search"] = hs
    with open(OUT, "w") as fh:
        json.dump(res, fh, indent=1)
    print("added the homoclinic search to", OUT)


if __name__ == "__main__":
    main()
