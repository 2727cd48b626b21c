"""The paper's conjecture (sec. 9): the floating-point search that a horseshoe proof on Fig 5's
own level starts from.  Numerical (float64 heyoka, reduced chart, tol 1e-15); it only chooses where the provers
look.  Not a proof.

Fig 5 (fig:poincare2): m = 1.7, delta = 0.25, lambdabar = 2, mu = 4, gamma in {0.15, 0.205, 0.208, 0.24}, the level
Hbar = 0.8, the section sin psi = 0 crossed with d(sin psi)/dt > 0 (Sigma+: psi = 0 with psi' > 0 and psi = pi with
psi' < 0 -- the paper plots both branches in one (theta, pbar_theta) panel).  mu = 2 lambdabar exactly: the saddle of
the system is the straight rod (magrod.orbits.equilibrium, MU_TOL), a point of the chart's singular set sin theta = 0
(the radicand mu - 2 lambdabar pbar_psi vanishes at pbar_psi = 1 = its pbar_psi), so the route of statements 10 / 12
through the helical saddle does not exist here; what the section carries instead are periodic orbits of P.

For each gamma:
  1. symmetric fixed points of P: starts on Fix(R) = {pbar_theta = 0, psi in {0, pi}} on both branches and every
     root pbar_psi of the level, flown to the first NEGATIVE crossing of sin psi = 0 (the half-way point of a
     symmetric periodic orbit with one positive crossing per period); sign changes of pbar_theta there in theta
     (a scan of 400 points) are refined by section_fixed_point.float_fixed_point (the prover's own search);
  2. DP(x0) (the prover's FloatMap.jac, central differences 1e-7), trace, det (area preservation: det = 1), the
     return time, and the range of theta along the orbit (the chart is singular at theta = 0, pi);
  3. for each hyperbolic one: the homoclinic points of W^u(x0) on Fix(R): points x0 + s e_u of two fundamental
     domains (s in +-[s0, s0 mu_u], s0 = 1e-7), mapped by P (4-D states, so the excursion may switch branch) j =
     1 .. 16 times; a sign change of pbar_theta at the same j on the same branch is bisected to s*.  R maps W^u onto
     W^s, so P^j(x0 + s* e_u) on Fix(R) is a symmetric homoclinic point (transverse iff W^u's tangent there is not
     along Fix(R): the angle is reported); the range of theta along the excursion.

    python research/fig5_candidates.py [out.json] [--gammas=0.15,0.24]
"""
from __future__ import annotations

import json
import math
import sys
import time
from fractions import Fraction

import heyoka as hy
import numpy as np

from magrod.chaos.section import solve_p_psi
from magrod.core import printed, systems
from magrod.proof import fields
from magrod.proof.provers import section_fixed_point
from magrod.proof.provers.horseshoe_design import FloatMap, unit

from fig4_candidates import bisect_on_fix_r  # research/ is the script's directory (sys.path[0])

OUT = next((a for a in sys.argv[1:] if not a.startswith("--")), "fig5_candidates.json")
GAMMAS = [f"{printed.panel(k).params.gamma:g}" for k in ("5a", "5b", "5c", "5d")]
GAMMAS = next((a.split("=", 1)[1].split(",") for a in sys.argv[1:] if a.startswith("--gammas=")), GAMMAS)
H = Fraction(printed.panel("5a").h).limit_denominator(10)  # 4/5
TH, PS, PT, PP = fields.THETA, fields.PSI, fields.PTHETA, fields.PPSI


def exact(gamma) -> fields.ExactParams:
    f = printed.panel("5a").params
    q = {k: Fraction(repr(getattr(f, k))) for k in ("m", "mu", "delta", "lam")}
    return fields.ExactParams(m=q["m"], mu=q["mu"], gamma=Fraction(gamma), delta=q["delta"], lam=q["lam"])


class Tracker:
    """theta's range along a flight of the reduced chart (a dense grid of 400 points): the chart's singular set
    is sin theta = 0."""

    def __init__(self, rp):
        self.ta = systems.taylor(systems.system("reduced"), [1.0, 0.0, 0.0, 1.0], rp.array(), tol=1e-15)

    def theta_range(self, x, T):
        ta = self.ta
        ta.time = 0.0
        ta.state[:] = x
        out = ta.propagate_grid(np.linspace(0.0, T, 400))[-1]
        return float(out[:, TH].min()), float(out[:, TH].max())


def fixed_point_brackets(p, rp):
    """(branch, root, theta_lo, theta_hi) where pbar_theta at the first negative crossing changes sign."""
    v = hy.make_vars(*systems.STATE["reduced"])
    ta = systems.taylor(systems.system("reduced"), [1.0, 0.0, 0.0, 1.0], rp.array(),
                        t_events=[hy.t_event(hy.sin(v[PS]), direction=hy.event_direction.negative)], tol=1e-15)
    out = []
    thetas = np.linspace(0.02, math.pi - 0.02, 400)
    for br, psi in (("0", 0.0), ("pi", math.pi)):
        roots = []
        for th in thetas:
            try:
                roots.append(solve_p_psi(rp, float(H), th, 0.0, psi))
            except Exception:  # noqa: BLE001 - no admissible pbar_psi: a gap in the scan
                roots.append(np.array([]))
        for ri in range(max(len(r) for r in roots)):
            prev = None
            for th, r in zip(thetas, roots):
                if len(r) <= ri:
                    prev = None
                    continue
                x = np.zeros(4)
                x[TH], x[PS], x[PP] = th, psi, r[ri]
                ta.time = 0.0
                ta.state[:] = x
                ta.reset_cooldowns()
                if int(ta.propagate_until(200.0)[0]) != -1:
                    prev = None
                    continue
                cur = (th, float(ta.state[PT]), float(ta.time), len(r))
                if (prev and prev[1] * cur[1] < 0 and abs(prev[1] - cur[1]) < 0.5 and abs(prev[2] - cur[2]) < 1
                        and prev[3] == cur[3]):
                    out.append((br, ri, prev[0], th))
                prev = cur
    return out


def homoclinic_points(P: FloatMap, x0, D, jmax=16, n_s=160):
    """W^u(x0) on Fix(R) (module docstring, step 3)."""
    w, V = np.linalg.eig(D)
    iu = int(np.argmax(abs(w)))
    eu = unit(np.real(V[:, iu]))
    eu = -eu if eu[0] < 0 else eu  # the sign rule of horseshoe.float_design
    mu_u = float(abs(w[iu]))
    s0 = 1e-7

    def track(s):
        x, t, rows = P.lift(x0 + s * eu), 0.0, []
        for _ in range(jmax):
            x, dt = P.full4(x)
            t += dt
            rows.append((float(x[PT]), "0" if math.cos(x[PS]) > 0 else "pi", float(x[TH]), t))
        return rows

    found = []
    for sign in (1, -1):
        ss = sign * s0 * mu_u ** np.linspace(0, 1, n_s)
        rows = []
        for s in ss:
            try:
                rows.append(track(s))
            except Exception:  # noqa: BLE001 - no return within t = 100: a gap
                rows.append(None)
        for j in range(jmax):
            for i in range(n_s - 1):
                a, b = rows[i], rows[i + 1]
                if a is None or b is None:
                    continue
                a, b = a[j], b[j]
                if a[1] != b[1] or a[0] * b[0] >= 0 or abs(a[0] - b[0]) > 0.3:
                    continue
                s, row, dth, dpt = bisect_on_fix_r(track, ss[i], ss[i + 1], a[0], j)
                found.append({"side": sign, "n_exc": j + 1, "s_star": float(s), "theta": row[2], "branch": row[1],
                              "flight_time": row[3], "tangent": [float(dth), float(dpt)],
                              "angle_to_FixR_deg": float(math.degrees(math.atan2(abs(dpt), abs(dth)))),
                              "branches_along": [r[1] for r in track(s)[: j + 1]]})
            if len(found) >= 2:
                break
    found.sort(key=lambda f: (f["n_exc"], f["flight_time"]))
    return {"mu_u": mu_u, "e_u": eu.tolist(), "points": found[:6]}


def main():
    res = {"figure": "fig:poincare2", "h": f"{H}", "params": {"m": 1.7, "mu": 4, "delta": 0.25, "lam": 2},
           "panels": []}
    for g in GAMMAS:
        t0 = time.perf_counter()
        p = exact(g)
        rp = FloatMap(p, H).params
        trk = Tracker(rp)
        panel = {"gamma": g, "fixed_points": []}
        seen = set()
        for br, ri, lo, hi in fixed_point_brackets(p, rp):
            try:
                th, x0, x1, tau = section_fixed_point.float_fixed_point(p, H, 0.5 * (lo + hi), root=ri, window=0.5 * (hi - lo),
                                                             branch=br)
            except Exception as err:  # noqa: BLE001
                print("refine failed", br, ri, lo, err)
                continue
            key = (br, round(th, 8))
            if key in seen:
                continue
            seen.add(key)
            P = FloatMap(p, H, branch=br, root=ri)
            D = P.jac(np.array([th, 0.0]))
            tr = float(np.trace(D))
            th_lo, th_hi = trk.theta_range(x0, 2 * tau)
            rec = {"branch": br, "root": ri, "theta": th, "ppsi": float(x0[PP]), "half_time": tau,
                   "return_time": 2 * tau, "trace": tr, "det": float(np.linalg.det(D)), "hyperbolic": abs(tr) > 2.01,
                   "mu_u": (abs(tr) + math.sqrt(tr * tr - 4)) / 2 if abs(tr) > 2 else None,
                   "theta_range": [th_lo, th_hi], "dist_to_pi": math.pi - th_hi, "D": D.tolist()}
            if rec["hyperbolic"]:
                hp = homoclinic_points(P, np.array([th, 0.0]), D)
                for q in hp["points"]:
                    x = P.lift(np.array([th, 0.0]) + q["s_star"] * np.array(hp["e_u"]))
                    q["theta_range"] = list(trk.theta_range(x, q["flight_time"]))
                rec["homoclinic"] = hp
            panel["fixed_points"].append(rec)
            print(json.dumps({k: v for k, v in rec.items() if k not in ("D",)}, default=float)[:1500], flush=True)
        panel["wall_s"] = round(time.perf_counter() - t0, 1)
        res["panels"].append(panel)
        json.dump(res, open(OUT, "w"), indent=1, default=float)
    print("wrote", OUT)


if __name__ == "__main__":
    main()
