"""Fig 4(a) on h = 9/10: the float design of a covering-relation horseshoe (Zgliczynski & Gidea
2004) along the homoclinic orbit of the saddle x0 of the section map P (statement 11).  Numerical (float64 heyoka,
reduced chart, tol 1e-15); it chooses the sets that magrod/proof/provers/section_horseshoe.py then proves, and reports the float
margins of the covering conditions per link.  Not a proof.

The sets (section coordinates (theta, pbar_theta) on Sigma+ = {sin psi = 0, d sin psi/dt > 0} of Hbar = 9/10,
pbar_psi the largest root of the level):
  N0  = x0 + l0 [e_u, R e_u] [-1, 1]^2      (R = diag(1, -1); R(N0)^T = N0 exactly)
  Nj  = c_j + [l e_u^j, w e_s^j] [-1, 1]^2, j = 1 .. k-1, c_1 = z_{-m} = P^-m(z_0), c_{j+1} = P(c_j)
  Nk  = c_k + lk [e_u^k, R e_u^k] [-1, 1]^2  (c_k on Fix(R): pbar_theta = 0; R(Nk)^T = Nk)
with z_0 = x0 + s* e_u the start of the float homoclinic excursion (W^u of x0 meets Fix(R) at P^8(z_0)),
e_u^j the tangent of W^u at c_j (DP pushed forward) and e_s^j that of W^s = R(W^u) (R e_u^k pulled back by DP^-1),
so that DP maps the frame of N_j onto that of N_{j+1} up to scalings.  c_{k-1} is moved along e_u^{k-1} so that
P(c_{k-1}) lies on Fix(R) (a one-return Newton step; the u-offset this leaves at the link k-2 -> k-1 is reported).  Sizes: the rule of
magrod.proof.provers.horseshoe_design.sizes (margins 3 in (a) and (b)).  At the scale of the proof (dist(x0, c_1) ~ 4e-10 for
m = 5) the float map cannot resolve the sets (its error ~1e-15 against widths ~1e-13): the prover recomputes the
chain with the validated flights; this script shows the geometry and the linear margins.

For each link N => M: the float images of points on N's boundary and a grid inside it, in M's coordinates
y = A_M^-1 (x - c_M): (a) max |y_s| over image points with |y_u| <= 1 (must be < 1), (b) the exit edges' images:
min y_u over the edge that must go right, max over the one that must go left (must be > 1, < -1), and the linear
part G = A_M^-1 DP(c_N) A_N.

    python research/fig4_horseshoe_design.py [out.json] [--m=2]
"""
from __future__ import annotations

import json
import sys
import time
from fractions import Fraction
from importlib import resources

import numpy as np

from magrod.proof import fields
from magrod.proof.provers import horseshoe_design
from magrod.proof.provers.horseshoe_design import R2, unit

OUT = next((a for a in sys.argv[1:] if not a.startswith("--")), "fig4_horseshoe_design.json")
M_BACK = int(next((a.split("=", 1)[1] for a in sys.argv[1:] if a.startswith("--m=")), 2))


class FloatMap(horseshoe_design.FloatMap):
    """The prover's float section map (magrod.proof.provers.horseshoe_design.FloatMap), counting its calls."""

    calls = 0

    def full(self, z):
        self.calls += 1
        return super().full(z)


def design(P: FloatMap, x0, m=2, s_star=2.431508147212876e-06, n_exc=8):
    """The chain of centres and frames (module docstring): e_u(x0) and the refined s* from the prover's
    `horseshoe_design.float_design`; here the centres are the float P^-m(z_0) and its images, with both frames."""
    fd = horseshoe_design.float_design(P, x0, 0, s_star, n_exc)
    eu, s = fd["e_u0"], fd["s_star"]
    z = x0 + s * eu
    for _ in range(m):
        z = P.inv(z)
    cs = [z]
    for _ in range(n_exc + m):
        cs.append(P(cs[-1]))
    # frames: W^u tangents forward, W^s tangents backward from R e_u^k
    Ds = [P.jac(c) for c in cs[:-1]]
    eus = [eu]
    for D in Ds:
        eus.append(unit(D @ eus[-1]))
    # the last centre on Fix(R): move c_{k-1} along e_u^{k-1}
    ck1, e = cs[-2], eus[-2]
    for _ in range(3):
        y = P(ck1)
        dy = (P(ck1 + 1e-9 * e) - P(ck1 - 1e-9 * e)) / 2e-9
        ck1 = ck1 - y[1] / dy[1] * e
    shift = float(np.dot(ck1 - cs[-2], e))
    cs[-2] = ck1
    yk = P(ck1)
    cs[-1] = np.array([yk[0], 0.0])
    Ds[-1] = P.jac(ck1)
    eus[-1] = unit(Ds[-1] @ eus[-2])
    if eus[-1][1] < 0:
        eus[-1] = -eus[-1]
    ess = [R2 @ eus[-1]]
    for D in reversed(Ds):
        ess.append(unit(np.linalg.solve(D, ess[-1])))
    ess = ess[::-1]
    return {"x0": x0, "e_u0": eu, "lam_u": fd["mu_u"], "s_star": s, "centres": cs, "e_u": eus, "e_s": ess,
            "DP": Ds, "DP0": P.jac(x0), "last_shift": shift, "pt_residual_last": float(yk[1])}


def sets_of(d, l0, ls, ws):
    """[(centre, A)] for N0, N1..N_{k-1}, N_k (module docstring); ls, ws: the sizes of N1 .. Nk."""
    x0, eu = d["x0"], d["e_u0"]
    out = [(x0, np.column_stack([l0 * eu, l0 * (R2 @ eu)]))]
    for c, u, s, l, w in zip(d["centres"][:-1], d["e_u"][:-1], d["e_s"][:-1], ls, ws):
        out.append((c, np.column_stack([l * u, w * s])))
    ek = d["e_u"][-1]
    out.append((d["centres"][-1], np.column_stack([ls[-1] * ek, ls[-1] * (R2 @ ek)])))
    return out


def link_margins(P: FloatMap, N, M, n_edge=9, n_in=5):
    """Float images of N's boundary and interior grid in M's coordinates: margins of (a) and (b)."""
    cN, AN = N
    cM, AM = M
    AMi = np.linalg.inv(AM)

    def img(y):
        return AMi @ (P(cN + AN @ np.asarray(y)) - cM)

    ts = np.linspace(-1, 1, n_edge)
    right = np.array([img((1.0, t)) for t in ts])
    left = np.array([img((-1.0, t)) for t in ts])
    top = np.array([img((t, 1.0)) for t in ts])
    bot = np.array([img((t, -1.0)) for t in ts])
    grid = np.array([img((a, b)) for a in np.linspace(-1, 1, n_in) for b in np.linspace(-1, 1, n_in)])
    pts = np.vstack([right, left, top, bot, grid])
    inside = pts[np.abs(pts[:, 0]) <= 1]
    amax = float(np.max(np.abs(inside[:, 1]))) if len(inside) else 0.0
    sign = 1.0 if right[:, 0].mean() > left[:, 0].mean() else -1.0
    b_right = float(np.min(sign * right[:, 0]))
    b_left = float(np.min(-sign * left[:, 0]))
    G = AMi @ P.jac(cN) @ AN
    return {"a_max_abs_ys": amax, "b_exit_plus": b_right, "b_exit_minus": b_left, "orientation": sign,
            "offset": (AMi @ (P(cN) - cM)).tolist(), "G": G.tolist()}


def main():
    t0 = time.perf_counter()
    cert = json.loads(resources.files("magrod.proof").joinpath("certificates", "fixed_point_fig4a.json").read_text())
    pr = {k: float(Fraction(cert["params"][k])) for k in ("m", "mu", "gamma", "delta", "lam")}
    h = float(Fraction(cert["level"]))
    P = FloatMap(fields.ExactParams(*(Fraction(cert["params"][k]) for k in ("m", "mu", "gamma", "delta", "lam"))),
                 Fraction(cert["level"]))
    x0 = np.array([float(Fraction(cert["point"]["theta_c"])), 0.0])
    d = design(P, x0, m=M_BACK)
    dist = float(np.linalg.norm(d["centres"][0] - x0))
    l0 = dist / 3
    lam = [float(np.linalg.norm(D @ u)) for D, u in zip(d["DP"], d["e_u"][:-1])]
    sig = [float(np.linalg.norm(D @ s)) for D, s in zip(d["DP"], d["e_s"][:-1])]
    ls, ws = horseshoe_design.sizes(lam, sig, dist / 6, 3.0, 3.0)
    l, w, lk = ls, ws, ls[-1]
    sets = sets_of(d, l0, ls, ws)
    k = len(sets) - 1
    links = [(0, 0), (0, 1)] + [(j, j + 1) for j in range(1, k)]
    rows = []
    for i, j in links:
        r = link_margins(P, sets[i], sets[j])
        r.update(link=f"N{i} => N{j}")
        rows.append(r)
        print(json.dumps({kk: (round(v, 4) if isinstance(v, float) else v) for kk, v in r.items() if kk != "G"}),
              flush=True)
    angles = [float(np.degrees(np.arccos(abs(np.dot(u, s))))) for u, s in zip(d["e_u"], d["e_s"])]
    out = {"params": pr, "h": h, "m_back": M_BACK, "k": k, "x0": x0.tolist(), "lam_u": d["lam_u"],
           "e_u0": d["e_u0"].tolist(), "s_star": d["s_star"], "dist_N1": dist, "l0": l0, "l": l, "w": w, "lk": lk,
           "last_shift": d["last_shift"], "last_shift_over_l": d["last_shift"] / ls[-2],
           "pt_residual_last": d["pt_residual_last"],
           "centres": [c.tolist() for c in d["centres"]], "e_u": [e.tolist() for e in d["e_u"]],
           "e_s": [e.tolist() for e in d["e_s"]], "angle_us_deg": angles,
           "stretch": lam, "stretch_s": sig,
           "DP_norm": [float(np.linalg.norm(D, 2)) for D in d["DP"]],
           "links": rows, "float_map_calls": P.calls, "wall_s": round(time.perf_counter() - t0, 1)}
    json.dump(out, open(OUT, "w"), indent=1)
    print("k =", k, "angles", [round(a, 3) for a in angles], "stretch", [round(s, 2) for s in out["stretch"]])
    print("wrote", OUT, out["wall_s"], "s")


if __name__ == "__main__":
    main()
