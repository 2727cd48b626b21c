"""Fig 4 (proved): the floating-point search that a horseshoe proof on h = 0.9 starts from, and a
measurement of the validated integrator on the section map.  Numerical (float64) except where stated; not a proof.

For each Fig 4 lambdabar (m = 1.7, mu = 0.4, gamma = delta = 3, Hbar = 0.9, the section sin psi = 0 crossed with
d(sin psi)/dt > 0, the paper's):
  1. a long section orbit from the panel's start (heyoka, reduced chart, tol 1e-15);
  2. near-returns |x_{i+k} - x_i| < 0.05 in (theta, pbar_theta) on the same branch (psi = 0 or pi), k = 1 .. 6,
     refined by Newton on P^k(x) - x (pbar_psi from Hbar = 0.9, root nearest the orbit's), finite differences
     (eps 1e-7); accepted if |P^k(x) - x| < 1e-10;
  3. for each periodic point: the eigenvalues of DP^k (area-preserving: mu_u mu_s = 1 is the check), the period
     (return time) and min theta along the orbit;
  4. (rigorous step, python-flint) the validated C^1 integrator of magrod/proof/taylor.py in the body frame from a
     box of radius r about the best saddle's periodic point, lifted by X(q, 0), to the next crossing of
     Gs = sin(theta) rho sin(psi) = 0: the enclosure's width there against r |DP| (the wrapping / overestimation
     factor), the Taylor steps, the wall time.

    python research/fig4_candidates.py [out.json] [--quick] [--lams=0.1575,0.175] [--saddles-only]
(--saddles-only: steps 1 and 3 of the list above only, no homoclinic search and no validated flight;
--no-flight: no validated flight)
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
from magrod.core import systems
from magrod.core.params import RodParams

OUT = next((a for a in sys.argv[1:] if not a.startswith("--")), "fig4_candidates.json")
QUICK = "--quick" in sys.argv
LAMS = ["0.135", "0.1575", "0.175", "0.186"]
# --lams 0.1575,0.175: only those panels (the runs of the four panels were made one or a few at a time)
LAMS = next((a.split("=", 1)[1].split(",") for a in sys.argv[1:] if a.startswith("--lams=")), LAMS)
H = 0.9
TH, PS, PT, PP = (systems.state_index("reduced", k) for k in ("theta", "psi", "ptheta", "ppsi"))


class SectionMap:
    """The float section map at Fig 4's parameters and lambdabar (or at `params` on the level h: Fig 5's script
    research/fig5_candidates.py uses the same search)."""

    def __init__(self, lam=None, *, params=None, h=H):
        self.params = params if params is not None else RodParams(m=1.7, mu=0.4, gamma=3.0, delta=3.0,
                                                                  lam=float(lam))
        self.h = h
        v = hy.make_vars(*systems.STATE["reduced"])
        ev = hy.t_event(hy.sin(v[PS]), direction=hy.event_direction.positive)
        self.ta = systems.taylor(systems.system("reduced"), [1.0, 0.0, 0.0, 1.0], self.params.array(),
                                 t_events=[ev], tol=1e-15)
        self.min_theta = math.inf

    def point(self, theta, ptheta, branch, near):
        roots = solve_p_psi(self.params, self.h, theta, ptheta, branch)
        x = np.empty(4)
        x[TH], x[PS], x[PT], x[PP] = theta, branch, ptheta, roots[np.argmin(abs(roots - near))]
        return x

    def step(self, x):
        ta = self.ta
        ta.time = 0.0
        ta.state[:] = x
        t_last = 0.0
        while True:
            oc, *_ = ta.propagate_until(ta.time + 200.0, c_output=False)
            self.min_theta = min(self.min_theta, float(ta.state[TH]))
            if int(oc) != -1:
                raise RuntimeError("no section crossing within t = 200")
            if ta.time - t_last > 1e-6:
                break
            t_last = ta.time
        y = ta.state.copy()
        y[PS] = math.remainder(y[PS], 2 * math.pi)
        y[PS] = 0.0 if abs(y[PS]) < 1 else math.pi
        return y, float(ta.time)

    def iterate(self, x, k):
        t = 0.0
        for _ in range(k):
            x, dt = self.step(x)
            t += dt
        return x, t


def orbit(smap, n):
    from magrod.core.printed import panel

    pnl = panel("4a")
    x = smap.point(pnl.theta0, pnl.ptheta0, 0.0, 1.0)
    pts, ts = [], []
    for _ in range(n):
        x, dt = smap.step(x)
        pts.append(x.copy())
        ts.append(dt)
    return np.array(pts), np.array(ts)


def refine(smap, x0, k):
    br, near = x0[PS], x0[PP]
    z = np.array([x0[TH], x0[PT]])

    def F(z):
        y, t = smap.iterate(smap.point(z[0], z[1], br, near), k)
        if abs(y[PS] - br) > 1:
            raise RuntimeError("branch changed")
        return np.array([y[TH], y[PT]]) - z, y, t

    for _ in range(20):
        r, y, t = F(z)
        if np.max(abs(r)) < 1e-11:
            break
        eps = 1e-7
        J = np.empty((2, 2))
        for j in range(2):
            dz = np.zeros(2)
            dz[j] = eps
            J[:, j] = (F(z + dz)[0] - F(z - dz)[0]) / (2 * eps)
        z = z - np.linalg.solve(J, r)
    r, y, t = F(z)
    eps = 1e-6
    D = np.empty((2, 2))
    for j in range(2):
        dz = np.zeros(2)
        dz[j] = eps
        D[:, j] = (F(z + dz)[0] - F(z - dz)[0]) / (2 * eps) + (np.eye(2)[:, j])
    return z, float(np.max(abs(r))), t, D, br, smap.point(z[0], z[1], br, near)


def validated_flight(lam, x, t_ret, r):
    """The C^1 Lohner set of radius r (chart coordinates, lifted) propagated to the next crossing."""
    from flint import arb

    from magrod.proof import ball, fields, taylor

    p = fields.ExactParams.from_values(m=Fraction(17, 10), mu=Fraction(2, 5), gamma=3, delta=3, lam=Fraction(lam))
    out = {"r": float(r)}
    with ball.workprec(128):
        q = [ball.interval(ball.fraction(v) - r, ball.fraction(v) + r) if i in (TH, PT) else ball.dyadic(v)
             for i, v in enumerate(x)]
        qc = [ball.dyadic(v) for v in x]
        # lift the chart box to the body frame at phi = 0 (derive/validated.py chart_body_lift), as lift_arc does
        Jl = fields.lift_jacobian(p, q, fields.gen)
        C0 = Jl.mid()
        dq = ball.vec([a - b for a, b in zip(q, qc)])
        err = ball.column((Jl - C0) * dq)
        S = taylor.initial_set([a + e for a, e in zip(fields.lift(p, qc, fields.gen), err)], c1=True)
        S.C, S.r0 = C0, dq
        fb = fields.body_field(p, fields.gen)

        def g(y):
            return fields.body_events(p, y, fields.gen)["Gs"]

        def dg(y):
            return fields.body_event_gradient(p, y, "Gs", fields.gen)

        def guard(Y):
            e = Y[fields.E33]
            return [1 - e, 1 + e, fields.body_events(p, Y, fields.gen)["rad"]]

        lead = Fraction(1, 64)
        t_a = Fraction(math.floor((t_ret - float(lead)) * 2**20), 2**20)
        tr = taylor.Trajectory()
        t0 = time.perf_counter()
        try:
            S = taylor.propagate(fb, S, t_a, order=20, tol=1e-25, guard=guard, record=tr)
            out["propagated_to"] = float(t_a)
            cr = taylor.cross_section(fb, S, g, dg, 2 * lead, 20, guard=guard)
            w = [ball.width(v) for v in cr.x]
            out.update(ok=True, crossing_width_max=max(w), crossing_widths=w)
        except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
            out.update(ok=False, error=str(err)[:300])
        out.update(n_steps=len(tr.steps), wall_s=round(time.perf_counter() - t0, 2),
                   max_width_along=max(tr.widths) if tr.widths else None)
        del arb
    return out


def symmetric_orbits(smap, branch, n_theta, jmax):
    """Symmetric periodic orbits by 1-D shooting on Fix(R) = {psi in {0, pi}, pbar_theta = 0} (the reversor
    R(theta, psi, pbar_theta, pbar_psi) = (theta, -psi, -pbar_theta, pbar_psi)): an orbit from Fix(R) that meets Fix(R)
    again at its j-th crossing is periodic with 2j crossings.  Zeros in theta of pbar_theta at crossing j (on either
    branch) by a scan and bisection."""
    out = []
    thetas = np.linspace(0.05, math.pi - 0.05, n_theta)
    for root in (0, 1):
        rows = []
        for th in thetas:
            try:
                roots = solve_p_psi(smap.params, smap.h, th, 0.0, branch)
                if len(roots) <= root:
                    rows.append(None)
                    continue
                x = np.empty(4)
                x[TH], x[PS], x[PT], x[PP] = th, branch, 0.0, roots[root]
                row = []
                for _ in range(jmax):
                    x, _t = smap.step(x)
                    row.append(x[PT])
                rows.append(row)
            except Exception:  # noqa: BLE001 - no admissible start or no crossing: a gap in the scan
                rows.append(None)
        for i in range(len(thetas) - 1):
            a, b = rows[i], rows[i + 1]
            if a is None or b is None:
                continue
            for j in range(jmax):
                if a[j] * b[j] < 0 and abs(a[j] - b[j]) < 0.5:
                    lo, hi = thetas[i], thetas[i + 1]
                    flo = a[j]
                    for _ in range(50):
                        mid = 0.5 * (lo + hi)
                        x = np.empty(4)
                        x[TH], x[PS], x[PT] = mid, branch, 0.0
                        x[PP] = solve_p_psi(smap.params, smap.h, mid, 0.0, branch)[root]
                        y, _t = smap.iterate(x, j + 1)
                        if (y[PT] > 0) == (flo > 0):
                            lo, flo = mid, y[PT]
                        else:
                            hi = mid
                    out.append({"theta": 0.5 * (lo + hi), "branch": branch, "root": root, "j": j + 1})
    return out


def monodromy(smap, f):
    """x on Fix(R), the map P^{2j} and its Jacobian in (theta, pbar_theta) by central differences (pbar_psi from
    the level, the same root), the return time, and |eigenvalues|."""
    br, root, k = f["branch"], f["root"], 2 * f["j"]

    def start(th, pt):
        x = np.empty(4)
        x[TH], x[PS], x[PT] = th, br, pt
        r = solve_p_psi(smap.params, smap.h, th, pt, br)
        x[PP] = r[min(root, len(r) - 1)]
        return x

    x0 = start(f["theta"], 0.0)
    y, t = smap.iterate(x0, k)
    eps = 1e-7
    D = np.empty((2, 2))
    for c, (dth, dpt) in enumerate(((eps, 0), (0, eps))):
        yp, _ = smap.iterate(start(f["theta"] + dth, dpt), k)
        ym, _ = smap.iterate(start(f["theta"] - dth, -dpt), k)
        D[:, c] = [(yp[TH] - ym[TH]) / (2 * eps), (yp[PT] - ym[PT]) / (2 * eps)]
    mu = np.linalg.eigvals(D)
    return {"k": k, "theta": f["theta"], "branch": "0" if br == 0 else "pi", "closure": float(np.hypot(
        y[TH] - x0[TH], y[PT] - x0[PT])), "return_time": t, "trace": float(np.trace(D)), "det": float(
        np.linalg.det(D)), "abs_eigenvalues": sorted(float(v) for v in abs(mu)),
        "hyperbolic": bool(abs(np.trace(D)) > 2 + 1e-6), "D": D.tolist()}, x0


def bisect_on_fix_r(track, lo, hi, flo, j):
    """The s in [lo, hi] where the j-th record of track(s) (pbar_theta, branch, theta, t) has pbar_theta = 0 (60
    bisections from the sign flo at lo), that record, and the tangent (dtheta/ds, dpbar_theta/ds) there by central
    differences of relative step 1e-6.  Shared with research/fig5_candidates.py."""
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        f = track(mid)[j][0]
        if (f > 0) == (flo > 0):
            lo, flo = mid, f
        else:
            hi = mid
    s = 0.5 * (lo + hi)
    e = abs(s) * 1e-6
    pa, pb = track(s - e)[j], track(s + e)[j]
    return s, track(s)[j], (pb[2] - pa[2]) / (2 * e), (pb[0] - pa[0]) / (2 * e)


def homoclinic_point(smap, rec, x0, jmax=16, n_s=120):
    """W^u of the symmetric saddle z (a periodic point of P^k on Fix(R)) until it meets Fix(R) again: points
    z + s e_u of a fundamental domain s in [s0, s0 mu_u] (e_u the float unstable eigenvector of DP^k) mapped by
    P^j, j = 1 .. jmax; a sign change of pbar_theta along s at the same j, on the same branch at both ends, is
    bisected to s*.  R maps W^u(orbit) onto W^s(orbit), so P^j(w(s*)) is a symmetric homoclinic point; it is
    transverse iff the tangent of W^u there has both components (dtheta, dpbar_theta) non-zero."""
    br = x0[PS]
    D = np.array(rec["D"])
    mu, V = np.linalg.eig(D)
    iu = int(np.argmax(abs(mu)))
    eu = np.real(V[:, iu])
    eu /= np.linalg.norm(eu)
    mu_u = float(abs(mu[iu]))
    s0 = 1e-7

    def start(sv):
        th, pt = x0[TH] + sv * eu[0], x0[PT] + sv * eu[1]
        x = np.empty(4)
        x[TH], x[PS], x[PT] = th, br, pt
        r = solve_p_psi(smap.params, smap.h, th, pt, br)
        x[PP] = r[np.argmin(abs(r - x0[PP]))]
        return x

    def track(sv):
        x, t, rows = start(sv), 0.0, []
        for _ in range(jmax):
            x, dt = smap.step(x)
            t += dt
            rows.append((x[PT], x[PS], x[TH], t))
        return rows

    found = []
    for sign in (1, -1):
        ss = sign * s0 * mu_u ** np.linspace(0, 1, n_s)
        rows = [track(v) for v in ss]
        for j in range(jmax):
            for i in range(n_s - 1):
                a, b = rows[i][j], rows[i + 1][j]
                if a[1] != b[1] or a[0] * b[0] >= 0 or abs(a[0] - b[0]) > 0.3:
                    continue
                sv, row, dth, dpt = bisect_on_fix_r(track, ss[i], ss[i + 1], a[0], j)
                found.append({"side": sign, "j": j + 1, "s_star": float(sv), "theta": float(row[2]),
                              "branch": "0" if row[1] == 0 else "pi", "flight_time": float(row[3]),
                              "tangent": [float(dth), float(dpt)],
                              "angle_to_FixR_deg": float(math.degrees(math.atan2(abs(dpt), abs(dth)))),
                              "x_start": start(sv).tolist()})
            if found:
                break
    found.sort(key=lambda f: f["flight_time"])
    return {"mu_u": mu_u, "e_u": eu.tolist(), "points": found[:4]}


def validated_homoclinic_flight(lam, hp, r):
    """The validated C^1 flight of a chart box of radius r about the start of the homoclinic excursion, to the end
    of the flight (no section stops: the body flow is continuous), then its crossing of Gs = 0."""
    x = np.array(hp["x_start"])
    return validated_flight(lam, x, hp["flight_time"], r)


def main():
    res = {"h": H, "params": {"m": 1.7, "mu": 0.4, "gamma": 3, "delta": 3}, "panels": []}
    for lam in (LAMS[:1] if QUICK and not any(a.startswith("--lams=") for a in sys.argv) else LAMS):
        t0 = time.perf_counter()
        smap = SectionMap(lam)
        cands = []
        for br in (0.0, math.pi):
            cands += symmetric_orbits(smap, br, 60 if QUICK else 90, 3)
        orbits = []
        for f in cands:
            try:
                rec, x0 = monodromy(smap, f)
            except Exception as err:  # noqa: BLE001
                print("monodromy failed:", f, err)
                continue
            if rec["closure"] < 1e-7:
                orbits.append((rec, x0))
        hyp = sorted((o for o in orbits if o[0]["hyperbolic"]), key=lambda o: (o[0]["k"], o[0]["return_time"]))
        panel = {"lam": lam, "candidates": len(cands),
                 "periodic": [{k: v for k, v in o[0].items() if k != "D"} for o in orbits], "n_hyperbolic": len(hyp)}
        best = None
        for rec, x0 in (hyp[:3] if "--saddles-only" not in sys.argv else []):
            try:
                hp = homoclinic_point(smap, rec, x0)
            except Exception as err:  # noqa: BLE001
                print("homoclinic search failed:", rec["theta"], err)
                continue
            if hp["points"]:
                best = (rec, x0, hp)
                break
        if best is not None:
            rec, x0, hp = best
            panel["saddle"] = {k: v for k, v in rec.items() if k != "D"}
            panel["homoclinic"] = hp
            p0 = hp["points"][0]
            if "--no-flight" not in sys.argv:
                panel["validated_homoclinic_flight"] = [validated_homoclinic_flight(lam, p0, Fraction(1, 10**e))
                                                        for e in ((12, 8) if QUICK else (12, 10))]
        panel["wall_s"] = round(time.perf_counter() - t0, 1)
        res["panels"].append(panel)
        print(json.dumps({k: v for k, v in panel.items() if k != "periodic"}, default=float)[:4000], flush=True)
        json.dump(res, open(OUT, "w"), indent=1, default=float)
    print("wrote", OUT)


if __name__ == "__main__":
    main()
