"""Fig 4(d) (lambdabar = 93/500, h = 9/10, the panel the paper's indicator calls regular): the
float search for the homoclinic point of the section saddle x0 of statement 11 (fixed_point_fig4d.json, psi = 0,
|mu_u(DP)| = 1.615, return time 3.19) and the float design of the covering-relation horseshoe along it
(magrod/proof/provers/section_horseshoe.py, design "fig4d").  Numerical (float64 heyoka, reduced chart, tol 1e-15); it chooses the
geometry that the prover then proves.  Not a proof.

  1. W^u(x0) meets Fix(R): research/fig4_candidates.homoclinic_point (fundamental domain s in [1e-7, 1e-7 mu_u]
     on the side +e_u, up to 45 returns, 4-D states; DP(x0) by central differences of one return, eps 1e-7): the
     first sign change of pbar_theta on one branch, bisected; its return n, end point, flight time and the tangent
     of W^u there (W^u-W^s angle = 2 atan |dtheta / dpbar_theta|: W^s = R(W^u)).
  2. The design's linear / hull / sampled margins per link (research/fig4b_horseshoe_design.py's machinery with
     panel "d" and the prover's design "fig4d"; each flag of that script overrides one field: --m, --qu, --qs,
     --l0, --l1, --wcap).

    python research/fig4d_horseshoe_design.py [out.json] [--m=0] [--qu=1.5] [--qs=1.3] [--l0=0.8] [--l1=0.1]
        [--wcap=7]

Stored run (fig4d_horseshoe_design.json, 2 cores, ~20 s): W^u on Fix(R) at return 35 from s = 1.1573e-7, theta =
1.81863 on the psi = pi branch, flight time 112.77, W^u-W^s angle 36.8 deg; the design fig4d starts there
(s* = 1.157e-7 = d, n_exc = 35, m = 0, k = 36 sets): every link's margins positive, (a') >= 0.231 (0.231 at
N31 => N32, where the rigorous run 8 below fails), (b) >= 0.500 (linear, hull and sampled alike).  Until
2026-12-03 the design started 12 returns further out (s* = 3.636e-5, n_exc = 23, k = 24: the same float margins;
runs 2-4 below).  Scratch runs of the same homoclinic orbit (not stored): d = 4.44e-8
(s* = 1.157e-7, n_exc = 35, m = 2, k = 38): qu = qs = 1.5: (a') >= 0.292, (b) >= 0.500; qu = qs = 1.3: 0.231, 0.300;
qu = qs = 1.2: 0.167, 0.200 (its prover run failed at the crossing step near theta = pi: magrod/proof/designs/fig4d.json,
lead); d = 3.64e-5 with qs = 1.5: (a') -0.005 at N0 => N1 (the widths reach only 0.49 d at N1).

The rigorous runs (horseshoe.prove, not a proving design: fig4d.json says "proving": false; 2 cores):
  1. d = 4.44e-8 (38 sets, centre flights at 1e-28, lead 1/256): chain pass 1 failed after 355 s, at the crossing
     step (length 2 lead = 1/128) of a centre flight near theta = pi ("field not evaluable on the trial enclosure":
     the orbit passes within 0.0103 of theta = pi at its 32nd / 33rd returns).
  2. d = 3.64e-5 (24 sets, tol 1e-25, lead 1/1024): one chain pass (end residual 4.5e-11), then "N0 branch box"
     failed with p_rad = 1e-6 (pbar_psi varies by ~3e-5 over N0), 164 s.
  3. the same with p_rad = 1/2000: N0 .. N17 flown, N18's box flight raised ValueError (a divisor containing 0), 258 s.
  4. the same with N18 .. N22 in 2 x 2 pieces: every piece flown, then N0 => N0 (a') failed: margin 1 - max |y_s| =
     -31.49 (float: +0.38), 613 s at load ~5.  The C^1 enclosure [DP(N0)] over a set of size 3e-5 is ~100x too wide
     for the mean-value form (its excess grows like the size squared relative to the widths): a proof needs d ~ 1e-7,
     i.e. the ~38-set chain of run 1 with lead 1/1024.
  5. (2026-12-03, idle 2 cores unless stated) d = 1.27e-6 (31 sets, s* = 1.157e-7 mu_u^5, n_exc = 30, p_rad
     1/20000, one piece per set): N0 => N0 (a') -0.52, 182 s at load 2.  d = 4.9e-7 (33 sets, N0 in 2 x 2 pieces):
     N0 => N0 (a') 0.274, N0 => N1 0.17, then N1 => N2 (b) failed (the exit edges' images straddle), 353 s at load 3.
  6. d = 1.157e-7 (36 sets, n_exc = 35, the design fig4d.json with one piece per set): every link up to
     N29 => N30 closed ((a') >= 0.157, (b) >= 1.38), N30 => N31 (a') -1.165 (the pass near theta = pi), 540 s at
     load 3.
  7. the same with N30, N31 in 4 x 4 pieces, N32 .. N34 in 2 x 2, p_rad 1/20000: N30 => N31 (a') -0.461, the
     pieces' centres (pbar_psi solved about their set's p_c in the wide Newton box) enclosed to +-1.2 of N31's width.
  8. p_rad 1e-6 (fig4d.json as stored): N30 => N31 (a') 0.122, N31 => N32 (a') -0.113 (centre offset +-0.069
     in y_s); prove 651 s idle (chain passes 194 s, 76 pieces' flights 455 s): over the 10-minute budget before the
     last links.  Not shipped: no horseshoe is claimed at (d).
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
