"""Fig 4(b) on h = 9/10: the float design of the covering-relation horseshoe of
magrod/proof/provers/section_horseshoe.py, with 4-D states (the excursion visits the psi = pi branch of Sigma+ at returns 12-14, which
the 2-D design of research/fig4_horseshoe_design.py cannot follow).  Numerical (float64 heyoka, reduced chart, tol
1e-15); it chooses the geometry that the prover then proves, and reports per link the linear margins of the covering
conditions at the proof's own scale.  Not a proof.

The chain is the prover's (section_horseshoe._prove): c_1 = x0 + t e_u, t = s* mu_u^-m, its k - 1 = n_exc + m images by
the float map (4-D: each centre keeps its psi branch and its pbar_psi root), c_1 shifted along e_u by float Newton
steps so that pbar_theta(c_k) = 0, the frames by section_horseshoe._frame_from (W^u pushed forward, W^s = R e_u^k pulled
back), the sizes by horseshoe_design.sizes with the given margins.  For each link N => M (N0 => N0, N0 => N1, Nj => Nj+1):

  linear   G = A_M^-1 DP(c_N) A_N, off = A_M^-1 (P(c_N) - c_M) (at the last link c_M := P(c_N): the float chain's
           end is float noise, ~3e-8 in pbar_theta at m = 3, which the prover's 128-bit Newton passes remove):
           (a') 1 - (|off_s| + |G_su| + |G_ss|) > 0,   (b) |G_uu| - |off_u| - |G_us| - 1 > 0
  hull     the same with G's entries replaced by their hull over DP at N's four corners and its centre (a proxy
           for the prover's mean-value form [DP(N)]: it misses the enclosure's own width);
  sampled  the float images of N's boundary (9 points per edge) and a 5 x 5 grid: (a') 1 - max |y_s| over image
           points with |y_u| <= 1, (b) min |y_u| - 1 over the exit edges' images (float error ~1e-15 / w_M).

    python research/fig4b_horseshoe_design.py [out.json] [--design=fig4b] [--m=4] [--qu=1.5] [--qs=1.5] [--l0=0.5]
        [--l1=0.15] [--wcap=3] [--panel=b]

--design picks the prover's named design (magrod.proof.provers.horseshoe_design.DESIGNS: fig4b, the default, or fig4a, Fig 4(a)'s
geometry, margins 3); each other flag overrides one of its fields.  Stored runs (2 cores, load ~4, ~10 s each):
fig4b_horseshoe_design.json (--design=fig4b, m = 4, the shipped certificate's geometry: every link's margins
positive, (a') >= 0.3297, (b) >= 0.4995), fig4b_horseshoe_design_m3.json (--m=3, the first certificate's geometry:
(a') >= 0.331, (b) >= 0.4999), and
fig4b_horseshoe_design_fig4a_geometry.json (--design=fig4a --m=3: N0 => N1 fails, (a') -1013, (b) -0.60; every
other link (0.62-0.69, 2.0-2.8)).
"""
from __future__ import annotations

import json
import math
import sys
import time
from fractions import Fraction
from importlib import resources

import numpy as np

from magrod.chaos.section import solve_p_psi
from magrod.proof import fields
from magrod.proof.provers import horseshoe_design, section_horseshoe
from magrod.proof.provers.horseshoe_design import R2

TH, PS, PT, PP = fields.THETA, fields.PSI, fields.PTHETA, fields.PPSI

PANELS = {  # (certificate of statement 11, s*, n_exc): the W^u point whose n_exc-th image lies on Fix(R)
    "a": ("fixed_point_fig4a.json", 2.431508147212876e-06, 8),
    "b": ("fixed_point_fig4b.json", -9.871e-7, 14),
    # research/fig4d_horseshoe_design.py: W^u (side +e_u) on Fix(R) at the 35th return from s = 1.157e-7
    # (fig4_candidates search; magrod/proof/designs/fig4d.json: 36 sets, the closest design to a proof)
    "d": ("fixed_point_fig4d.json", 1.1573e-07, 35),
}


def opt(name, default, cast=float):
    return cast(next((a.split("=", 1)[1] for a in sys.argv[1:] if a.startswith(f"--{name}=")), default))


class Map4:
    """The float section map on (theta, pbar_theta) of a branch: psi = 0 or pi, pbar_psi the level's root nearest to
    a reference value (the chain's centre's)."""

    def __init__(self, P: horseshoe_design.FloatMap):
        self.P, self.calls = P, 0

    def lift(self, z, br, pref):
        roots = solve_p_psi(self.P.params, self.P.h, float(z[0]), float(z[1]), 0.0 if br == "0" else math.pi)
        x = np.zeros(4)
        x[TH], x[PT], x[PS] = z[0], z[1], (0.0 if br == "0" else math.pi)
        x[PP] = roots[int(np.argmin(abs(roots - pref)))]
        return x

    def step4(self, x):
        self.calls += 1
        y = self.P.full4(x)[0]
        return y, ("0" if math.cos(y[PS]) > 0 else "pi")

    def __call__(self, z, br, pref):
        y, b = self.step4(self.lift(z, br, pref))
        return np.array([y[TH], y[PT]]), b

    def jac(self, z, br, pref, eps):
        D = np.empty((2, 2))
        for j in range(2):
            dz = np.zeros(2)
            dz[j] = eps
            D[:, j] = (self(z + dz, br, pref)[0] - self(z - dz, br, pref)[0]) / (2 * eps)
        return D


def chain(M: Map4, x0_4, eu, t, n):
    """4-D centres c_1 .. c_{n+1} from c_1 = x0 + t e_u (psi = 0)."""
    z = np.array([x0_4[TH], 0.0]) + t * eu
    x = M.lift(z, "0", x0_4[PP])
    xs, brs = [x], ["0"]
    for _ in range(n):
        x, b = M.step4(x)
        xs.append(x)
        brs.append(b)
    return xs, brs


def design(M: Map4, x0_4, eu, mu, s, m, n_exc):
    k = n_exc + m + 1
    t = s / abs(mu) ** m
    # float Newton on t: pbar_theta(c_k) = 0 (the prover does this with the validated flights)
    for _ in range(4):
        xs, brs = chain(M, x0_4, eu, t, k - 1)
        f = xs[-1][PT]
        dt = t * 1e-6
        f2 = chain(M, x0_4, eu, t + dt, k - 1)[0][-1][PT]
        t -= f / ((f2 - f) / dt)
    xs, brs = chain(M, x0_4, eu, t, k - 1)
    cs = [np.array([x[TH], x[PT]]) for x in xs]
    resid = float(cs[-1][1])
    cs[-1] = np.array([cs[-1][0], 0.0])
    return t, xs, brs, cs, resid


def main(panel="b", design_name="fig4b"):
    """The run of the module docstring; research/fig4d_horseshoe_design.py calls it with panel "d", design
    "fig4d" as its defaults (flags override both)."""
    t0 = time.perf_counter()
    panel = opt("panel", panel, str)
    name, s_guess, n_exc = PANELS[panel]
    dname = opt("design", design_name, str)  # a named design (magrod/proof/designs/NAME.json; fig4d: not proving)
    st = horseshoe_design.design(dname)  # the prover's named design; each flag overrides one field
    m_back = opt("m", st.m_back, int)
    qu, qs = opt("qu", st.qu), opt("qs", st.qs)
    l0_frac, l1_frac, w_cap = opt("l0", st.l0_frac), opt("l1", st.l1_frac), opt("wcap", st.w_cap)
    out_path = next((a for a in sys.argv[1:] if not a.startswith("--")), f"fig4{panel}_horseshoe_design.json")
    cert = json.loads(resources.files("magrod.proof").joinpath("certificates", name).read_text())
    ep = fields.ExactParams(*(Fraction(cert["params"][k]) for k in ("m", "mu", "gamma", "delta", "lam")))
    h = Fraction(cert["level"])
    P = horseshoe_design.FloatMap(ep, h)
    M = Map4(P)
    th0 = float(Fraction(cert["point"]["theta_c"]))
    x0 = np.array([th0, 0.0])
    x0_4 = P.lift(x0)
    fd = horseshoe_design.float_design(P, x0, 0, s_guess, n_exc)
    eu, mu, s = fd["e_u0"], fd["mu_u"], fd["s_star"]
    t, xs, brs, cs, resid = design(M, x0_4, eu, mu, s, m_back, n_exc)
    k = len(cs)
    d = float(np.hypot(cs[0][0] - x0[0], cs[0][1]))
    eps = opt("eps", 1e-9)  # central differences: float error ~1e-15 / eps, curvature ~eps^2
    DPs = [M.jac(c, b, x[PP], eps) for c, b, x in zip(cs[:-1], brs[:-1], xs[:-1])]
    eus, ess, lam, sig = section_horseshoe._frame_from(DPs, eu)
    L = d * l1_frac
    ls, ws = horseshoe_design.sizes(lam, sig, L, qu, qs, w_cap * L)
    l0 = d * l0_frac
    sets = [(x0, np.column_stack([l0 * eu, l0 * (R2 @ eu)]), "0", x0_4[PP])]
    for j in range(k - 1):
        sets.append((cs[j], np.column_stack([ls[j] * eus[j], ws[j] * ess[j]]), brs[j], xs[j][PP]))
    ek = eus[-1]
    sets.append((cs[-1], np.column_stack([ls[-1] * ek, ls[-1] * (R2 @ ek)]), brs[-1], xs[-1][PP]))
    links = [(0, 0), (0, 1)] + [(j, j + 1) for j in range(1, k)]
    rows = []
    for i, j in links:
        cN, AN, bN, pN = sets[i]
        cM, AM, _, _ = sets[j]
        Ai = np.linalg.inv(AM)
        Pc = M(cN, bN, pN)[0]
        if j == k:  # the float chain's end is noise (~3e-8 at m = 3): the prover's 128-bit Newton zeroes it
            cM = Pc.copy()
        off = Ai @ (Pc - cM)
        Dc = M.jac(cN, bN, pN, eps)
        G = Ai @ Dc @ AN
        lin_a = 1 - (abs(off[1]) + abs(G[1, 0]) + abs(G[1, 1]))
        lin_b = abs(G[0, 0]) - abs(off[0]) - abs(G[0, 1]) - 1
        Gs = [G]
        for a, b in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
            corner = cN + AN @ np.array([a, b], float)
            Gs.append(Ai @ M.jac(corner, bN, pN, eps) @ AN)
        Gh = np.max(np.abs(np.array(Gs)), axis=0)
        Gl = np.min(np.abs(np.array(Gs)), axis=0)
        hull_a = 1 - (abs(off[1]) + Gh[1, 0] + Gh[1, 1])
        hull_b = Gl[0, 0] - abs(off[0]) - Gh[0, 1] - 1

        def img(y, cN=cN, AN=AN, bN=bN, pN=pN, Ai=Ai, cM=cM):
            return Ai @ (M(cN + AN @ np.asarray(y, float), bN, pN)[0] - cM)

        ts = np.linspace(-1, 1, 9)
        right = np.array([img((1.0, v)) for v in ts])
        left = np.array([img((-1.0, v)) for v in ts])
        other = np.array([img((v, sgn)) for v in ts for sgn in (-1.0, 1.0)]
                         + [img((a, b)) for a in np.linspace(-1, 1, 5) for b in np.linspace(-1, 1, 5)])
        pts = np.vstack([right, left, other])
        inside = pts[np.abs(pts[:, 0]) <= 1]
        o = 1.0 if right[:, 0].mean() > left[:, 0].mean() else -1.0
        smp_a = 1 - (float(np.max(np.abs(inside[:, 1]))) if len(inside) else 0.0)
        smp_b = min(float(np.min(o * right[:, 0])), float(np.min(-o * left[:, 0]))) - 1
        r = {"link": f"N{i} => N{j}", "orientation": o, "lin_a": lin_a, "lin_b": lin_b, "hull_a": hull_a,
             "hull_b": hull_b, "smp_a": smp_a, "smp_b": smp_b, "off": off.tolist(), "G": G.tolist()}
        rows.append(r)
        print(json.dumps({kk: (round(v, 4) if isinstance(v, float) else v) for kk, v in r.items() if kk not in
                          ("G", "off")}), flush=True)
    angles = [float(np.degrees(np.arccos(min(1.0, abs(float(np.dot(u, e))))))) for u, e in zip(eus, ess)]
    out = {"panel": panel, "params": {kk: str(v) for kk, v in cert["params"].items()}, "h": str(h),
           "m_back": m_back, "n_exc": n_exc, "k": k, "qu": qu, "qs": qs, "l0_frac": l0_frac, "l1_frac": l1_frac,
           "w_cap": w_cap, "x0": x0.tolist(), "mu_u": mu, "e_u0": eu.tolist(), "s_star": s, "t": t, "d": d,
           "end_residual": resid, "branches": brs, "l0": l0, "l": ls, "w": ws, "stretch_u": lam, "stretch_s": sig,
           "angle_us_deg": angles, "centres": [c.tolist() for c in cs], "links": rows,
           "min_margins": {kk: min(r[kk] for r in rows) for kk in
                           ("lin_a", "lin_b", "hull_a", "hull_b", "smp_a", "smp_b")},
           "float_map_calls": M.calls, "wall_s": round(time.perf_counter() - t0, 1)}
    with open(out_path, "w") as fh:
        json.dump(out, fh, indent=1)
    print("k =", k, "d =", f"{d:.3g}", "mu_u", round(mu, 4), "branches", "".join("p" if b == "pi" else "0" for b in brs))
    print("stretch_u", [round(v, 3) for v in lam])
    print("stretch_s", [round(v, 3) for v in sig])
    print("angles", [round(a, 3) for a in angles])
    print("l/d", [f"{v / d:.3g}" for v in ls])
    print("w/d", [f"{v / d:.3g}" for v in ws])
    print("min margins", {kk: round(v, 4) for kk, v in out["min_margins"].items()})
    print("wrote", out_path, out["wall_s"], "s")


if __name__ == "__main__":
    main()
