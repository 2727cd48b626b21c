"""Fig 4(c) (lambdabar = 7/40, h = 9/10): the float search and the float design of a
covering-relation horseshoe around a symmetric PERIODIC orbit of the section map (P has no hyperbolic fixed point
there).  Numerical (float64 heyoka, reduced chart, tol 1e-15): it chooses the geometry a prover would prove.  Not a
proof.

  1. The orbit (horseshoe_design.float_cycle): the fig4_candidates saddle "k = 6, theta = 1.98883, psi = pi" is a
     symmetric orbit of P of period 6 (k counts returns of P: x0 = 1.98883 and x3 = 2.79951 are its two points on
     Fix(R), the table's second "k = 6" entry is x3), |mu_u(DP^6)| = 5.685 (1.336 per return on average), the
     per-return stretches of the unit frame vectors printed below.
  2. W^u(x0) of P^6 meets Fix(R) (fig4_candidates.homoclinic_point: fundamental domain s in [1e-7, 1e-7 mu_u] on
     both sides, 75 returns, 100 points): the first sign change, bisected; the W^u-W^s angle 2 atan |a / b|.
  3. The design: cycle sets N0 (symmetric, l0 = l0_frac d), N^1 .. N^(p-1) at x_1 .. x_(p-1) with
     l_(i+1) = lam_i l_i / q, w_(i+1) = q sig_i w_i (w_0 = l_0), so that N^(p-1) => N0 has the margin
     mu_u / q^(p-1) in both directions; the excursion chain C_1 = x0 + t e_u (t = s* mu_u^-m), C_(j+1) = P(C_j),
     t shifted by float Newton so that C_k lies on Fix(R), sizes by horseshoe_design.sizes (qu, qs, L = l1_frac d, cap
     w_cap L); links N0 => N^1 => ... => N^(p-1) => N0 and N^(p-1) => C_1 => ... => C_k.  Margins per link as in
     research/fig4b_horseshoe_design.py: linear, hull (DP at the four corners and the centre) and sampled.
     On the links C_j => C_(j+1) the target is centred at the float image P(C_j) itself: at the proof's scale
     (d ~ 1e-10, entry widths down to ~1e-4 d at the excursion's squeeze) the float chain cannot resolve the sets
     (its offsets A_M^-1 (P(C_j) - C_(j+1)), recomputed from a re-lifted 2-D point, are float noise of up to
     |y| ~ 3.5, recorded as float_offset); the prover's 128-bit chain puts C_(j+1) at P(C_j) to ~1e-19.

    python research/fig4c_horseshoe_design.py [out.json] [--m=2] [--q=1.2] [--qu=1.2] [--qs=1.15] [--l0=0.6]
        [--l1=0.15] [--wcap=3]

Stored run (fig4c_horseshoe_design.json, 2 cores, ~9 s): period 6, theta* = 1.98882930090, mu_u(DP^6) = 5.68499
(det DP^6 - 1 = -6.8e-9), per-return stretches of e_u 1.202, 1.397, 1.379, 0.918, 2.751, 0.972, of e_s 1.029,
0.363, 1.089, 0.725, 0.716, 0.832; return times 3.79, 3.58, 3.58, 3.58, 3.58, 3.79 (period 21.911); exit-entry
angles 34.8, 27.4, 65.2, 37.2, 65.2, 27.4 deg.  W^u (side +e_u) on Fix(R) at the 62nd return from s* = 2.679e-7
(theta = 2.79651, psi = pi, flight 226.77, W^u-W^s angle 46.5 deg; side -e_u: none within 75 returns).  The design
(m = 2: d = 8.29e-9, k = 75 chain sets, 81 sets in all): cycle q = 1.2, chain qu = 1.2, qs = 1.15, l0 = 0.6 d, l1 =
0.15 d, cap 3 l1; every link's margins positive: linear (a') >= 0.130, (b) >= 0.200; hull 0.123, 0.199; sampled
0.126, 0.199 (cycle links 0.167 / 0.200, N^5 => N0 0.562 / 1.285, N^5 => C1 0.293 / 1.472).  Entry widths down to
1.6e-12 (1.9e-4 d) at an exit-entry angle of 0.215 deg: the centre flights must resolve ~6e-15.  Loops of lengths
6 and L_B = 2 (p + k - 1) = 160: h_top >= log rho = 0.01524, x^160 = x^154 + 1.  Scratch runs: m = 1 (qs = 1.15):
N^5 => C1 (a') -0.736 (C1 too thin: the entry widths pulled back from the excursion's squeeze grow by mu_u /
qs^6 = 2.46 per cycle, one cycle short); m = 1, qs = 1.12: (a') >= 0.103 (hull), d = 4.7e-8 (sets 6x fig 4(b)'s);
m = 4, qs = 1.15: 93 sets, d = 2.6e-10; qs = 1.2 at m = 1: N^5 => C1 (a') -30.4.

The rigorous run of this design (magrod/proof/designs/fig4c.json, `magrod prove --horseshoe 1.988829300900816 --level 0.9
--m 1.7 --mu 0.4 --gamma 3 --delta 3 --lam 0.175 --design fig4c --branch pi --root smallest`) proved it:
magrod/proof/certificates/horseshoe_fig4c.json, (a') >= 0.120, (b) >= 1.199 (the rigorous margins at most 0.0102
below the linear ones above), prove 452 s (docs/nonintegrability.md, "Panel (c)").
"""
from __future__ import annotations

import json
import math
import sys
import time
from fractions import Fraction

import numpy as np

import fig4_candidates as fc
from magrod.proof import fields
from magrod.proof.provers import horseshoe_design, section_horseshoe
from magrod.proof.provers.horseshoe_design import R2

TH, PS, PT, PP = fields.THETA, fields.PSI, fields.PTHETA, fields.PPSI
PARAMS = fields.ExactParams.from_values(m=Fraction(17, 10), mu=Fraction(2, 5), gamma=3, delta=3, lam=Fraction(7, 40))
H = Fraction(9, 10)
THETA_GUESS, PERIOD = 1.98883, 6


def opt(name, default, cast=float):
    return cast(next((a.split("=", 1)[1] for a in sys.argv[1:] if a.startswith(f"--{name}=")), default))


def search(cyc):
    """W^u(x0) of P^p meets Fix(R) (fig4_candidates.homoclinic_point on fc's own float map)."""
    smap = fc.SectionMap("0.175")
    x0 = smap.point(cyc["theta"], 0.0, math.pi, float(cyc["xs"][0][PP]))
    hp = fc.homoclinic_point(smap, {"D": cyc["DPp"].tolist()}, x0, jmax=75, n_s=100)
    for p in hp["points"]:
        a, b = p["tangent"]
        p["angle_wu_ws_deg"] = float(2 * math.degrees(math.atan(abs(a / b))))
    return hp


def chain(M, x0_4, eu, t, n):
    z = np.array([x0_4[TH], 0.0]) + t * eu
    x = M.lift(z, "pi", x0_4[PP])
    xs, brs = [x], ["pi"]
    for _ in range(n):
        x, b, _ = M.step4(x)
        xs.append(x)
        brs.append(b)
    return xs, brs


def margins(M, sets, i, j, eps, end):
    cN, AN, bN, pN = sets[i]
    cM, AM, _, _ = sets[j]
    Ai = np.linalg.inv(AM)
    Pc = M(cN, bN, pN)[0]
    noise = (Ai @ (Pc - cM)).tolist()
    if end:  # C_(j+1) = P(C_j) of the float chain: the offset is float noise (see the module docstring)
        cM = Pc.copy()
    off = Ai @ (Pc - cM)
    G = Ai @ M.jac(cN, bN, pN, eps) @ AN
    lin_a = 1 - (abs(off[1]) + abs(G[1, 0]) + abs(G[1, 1]))
    lin_b = abs(G[0, 0]) - abs(off[0]) - abs(G[0, 1]) - 1
    Gs = [G] + [Ai @ M.jac(cN + AN @ np.array([a, b], float), bN, pN, eps) @ AN
                for a, b in ((1, 1), (1, -1), (-1, 1), (-1, -1))]
    Gh, Gl = np.max(np.abs(np.array(Gs)), axis=0), np.min(np.abs(np.array(Gs)), axis=0)
    hull_a = 1 - (abs(off[1]) + Gh[1, 0] + Gh[1, 1])
    hull_b = Gl[0, 0] - abs(off[0]) - Gh[0, 1] - 1

    def img(y):
        return Ai @ (M(cN + AN @ np.asarray(y, float), bN, pN)[0] - cM)

    ts = np.linspace(-1, 1, 9)
    right, left = np.array([img((1.0, v)) for v in ts]), np.array([img((-1.0, v)) for v in ts])
    other = np.array([img((v, s)) for v in ts for s in (-1.0, 1.0)]
                     + [img((a, b)) for a in np.linspace(-1, 1, 5) for b in np.linspace(-1, 1, 5)])
    pts = np.vstack([right, left, other])
    inside = pts[np.abs(pts[:, 0]) <= 1]
    o = 1.0 if right[:, 0].mean() > left[:, 0].mean() else -1.0
    smp_a = 1 - (float(np.max(np.abs(inside[:, 1]))) if len(inside) else 0.0)
    smp_b = min(float(np.min(o * right[:, 0])), float(np.min(-o * left[:, 0]))) - 1
    return {"float_offset": noise, "orientation": o, "lin_a": lin_a, "lin_b": lin_b, "hull_a": hull_a, "hull_b": hull_b, "smp_a": smp_a,
            "smp_b": smp_b, "off": off.tolist(), "G": G.tolist()}


def main():
    t0 = time.perf_counter()
    out_path = next((a for a in sys.argv[1:] if not a.startswith("--")), "fig4c_horseshoe_design.json")
    m_back, q = opt("m", 2, int), opt("q", 1.2)
    qu, qs = opt("qu", 1.2), opt("qs", 1.15)
    l0_frac, l1_frac, w_cap = opt("l0", 0.6), opt("l1", 0.15), opt("wcap", 3.0)
    eps = opt("eps", 1e-9)
    P = horseshoe_design.FloatMap(PARAMS, H, "pi", 0)
    M = horseshoe_design.NearMap(P)
    cyc = horseshoe_design.float_cycle(P, THETA_GUESS, PERIOD)
    p, mu = PERIOD, cyc["mu_u"]
    print("cycle: theta", cyc["theta"], "mu_u(DP^p)", mu, "det - 1", cyc["det"] - 1, "closure", cyc["closure"])
    print("  lam", [round(v, 4) for v in cyc["lam"]], "sig", [round(v, 4) for v in cyc["sig"]])
    print("  angles", [round(v, 2) for v in cyc["angles_deg"]], "return times", [round(v, 4) for v in cyc["times"]])
    hp = search(cyc)
    for pt in hp["points"]:
        print("  W^u on Fix(R):", {k: pt[k] for k in ("side", "j", "s_star", "theta", "branch", "flight_time",
                                                      "angle_wu_ws_deg")})
    best = min((pt for pt in hp["points"] if pt["side"] == 1), key=lambda pt: pt["flight_time"])
    s_star, n_exc = best["s_star"], best["j"]
    eu = cyc["e_u"][0]
    if float(np.dot(eu, hp["e_u"])) < 0:
        raise SystemExit("e_u conventions differ")
    x0_4 = cyc["xs"][0]
    k = n_exc + p * m_back + 1
    t = s_star / mu**m_back
    for _ in range(4):  # float Newton on t: pbar_theta(C_k) = 0
        xs, brs = chain(M, x0_4, eu, t, k - 1)
        f = xs[-1][PT]
        dt = t * 1e-6
        t -= f / ((chain(M, x0_4, eu, t + dt, k - 1)[0][-1][PT] - f) / dt)
    xs, brs = chain(M, x0_4, eu, t, k - 1)
    cs = [np.array([x[TH], x[PT]]) for x in xs]
    resid = float(cs[-1][1])
    cs[-1] = np.array([cs[-1][0], 0.0])
    d = t
    DPs = [M.jac(c, b, x[PP], eps) for c, b, x in zip(cs[:-1], brs[:-1], xs[:-1])]
    eus, ess, lam, sig = section_horseshoe._frame_from(DPs, eu)
    L = d * l1_frac
    ls, ws = horseshoe_design.sizes(lam, sig, L, qu, qs, w_cap * L)
    # the cycle sets
    l0 = d * l0_frac
    lc, wc = [l0], [l0]
    for i in range(p - 1):
        lc.append(cyc["lam"][i] * lc[-1] / q)
        wc.append(q * cyc["sig"][i] * wc[-1])
    sets = [(cyc["zs"][0], np.column_stack([l0 * eu, l0 * (R2 @ eu)]), "pi", x0_4[PP])]
    for i in range(1, p):
        sets.append((cyc["zs"][i], np.column_stack([lc[i] * cyc["e_u"][i], wc[i] * cyc["e_s"][i]]),
                     cyc["branches"][i], cyc["xs"][i][PP]))
    for j in range(k - 1):
        sets.append((cs[j], np.column_stack([ls[j] * eus[j], ws[j] * ess[j]]), brs[j], xs[j][PP]))
    sets.append((cs[-1], np.column_stack([ls[-1] * eus[-1], ls[-1] * (R2 @ eus[-1])]), brs[-1], xs[-1][PP]))
    links = [(i, i + 1) for i in range(p - 1)] + [(p - 1, 0), (p - 1, p)] + [(p + j, p + j + 1) for j in range(k - 1)]
    names = ["N0"] + [f"N0^{i}" for i in range(1, p)] + [f"C{j}" for j in range(1, k + 1)]
    rows = []
    for i, j in links:
        r = {"link": f"{names[i]} => {names[j]}", **margins(M, sets, i, j, eps, i >= p)}
        rows.append(r)
        print(json.dumps({kk: (round(v, 4) if isinstance(v, float) else v) for kk, v in r.items()
                          if kk not in ("G", "off", "float_offset")}), flush=True)
    mm = {kk: min(r[kk] for r in rows) for kk in ("lin_a", "lin_b", "hull_a", "hull_b", "smp_a", "smp_b")}
    L_B = 2 * (p + k - 1)
    rho = float(section_horseshoe.entropy_root_lower_cycle(p, L_B))
    out = {"params": {"m": "17/10", "mu": "2/5", "gamma": "3", "delta": "3", "lam": "7/40"}, "h": "9/10",
           "cycle": {kk: (v.tolist() if isinstance(v, np.ndarray) else
                          [x.tolist() if isinstance(x, np.ndarray) else x for x in v] if isinstance(v, list) else v)
                     for kk, v in cyc.items()},
           "homoclinic_search": hp, "m_back": m_back, "n_exc": n_exc, "k": k, "q": q, "qu": qu, "qs": qs,
           "l0_frac": l0_frac, "l1_frac": l1_frac, "w_cap": w_cap, "s_star": s_star, "t": t, "d": d,
           "end_residual": resid, "branches": brs, "l_cycle": lc, "w_cycle": wc, "l": ls, "w": ws,
           "stretch_u": lam, "stretch_s": sig,
           "angle_us_deg": [float(np.degrees(np.arccos(min(1.0, abs(float(np.dot(u, e))))))) for u, e in
                            zip(eus, ess)],
           "centres": [c.tolist() for c in cs], "links": rows, "min_margins": mm,
           "loops": {"A": p, "B": L_B}, "entropy_rho_lower": rho, "log_rho_lower": math.log(rho),
           "wall_s": round(time.perf_counter() - t0, 1)}
    with open(out_path, "w") as fh:
        json.dump(out, fh, indent=1)
    print("k =", k, "sets", len(sets), "d =", f"{d:.3g}", "end residual", f"{resid:.3g}")
    print("stretch_u", [round(v, 3) for v in lam])
    print("angles", [round(a, 2) for a in out["angle_us_deg"]])
    print("l/d", [f"{v / d:.3g}" for v in ls])
    print("w/d", [f"{v / d:.3g}" for v in ws])
    print("cycle l/d", [f"{v / d:.3g}" for v in lc], "w/d", [f"{v / d:.3g}" for v in wc])
    print("min margins", {kk: round(v, 4) for kk, v in mm.items()})
    print("loops", p, L_B, "h_top >=", math.log(rho))
    print("wrote", out_path, out["wall_s"], "s")


if __name__ == "__main__":
    main()
