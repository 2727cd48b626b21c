"""How wide a λ̄ interval the Fig 4(a) horseshoe's critical link N12 => N13 could take with exact enclosures: the
limit of the interval certificate's *form* (sets moving affinely with λ̄, fixed frames), apart from its enclosures.

The interval certificate (horseshoe_fig4a_interval.json, W = 2e-11) moves every set along v_j: N_j(s) = c_j + v_j s +
A_j [-1, 1]^2, s = λ̄ - λ̄_c.  Its (a') check at N12 => N13 bounds the stable coordinate y_s of the image in N13's
coordinates, A_13^-1 (P(c_12 + v_12 s + A_12 r, λ̄_c + s) - c_13 - v_13 s), over the whole moving set.  What limits it
today is the enclosure (the box's [dP/ds], research/horseshoe_margins.py); this script measures what the form itself
allows, in quad precision (heyoka real128, tol 1e-32; the level by Newton in 256-bit balls), at the link's exact
images, for several W:

  * drift: the centre's image off N13's linear motion, y_s(s) - y_s(0) - s y_s'(0) over s in [-W, W] (second order
    in s: the sets' nonlinear motion), y_s' by a central difference at s = +-W / 8;
  * shear: the change over s in [-W, W] of the image's linear part G(s) = A_13^-1 DP(c_12(s), s) A_12 (DP by central
    differences at +-1e-3 of the set's half-axes), its stable row (G_su, G_ss): the frames' rotation with λ̄;
  * budget: the point certificate's margin at this link, 1 - |y_s| of the centre's image at s = 0 minus the linear
    part's |G_su| + |G_ss| (what the drift and the shear may take).

Float (quad) measurement, not part of any proof.

    python research/horseshoe_interval_limit.py [--out research/horseshoe_interval_limit.json]
"""
from __future__ import annotations

import argparse
import json
import time
from fractions import Fraction as F
from pathlib import Path

import heyoka as hy
import mpmath as mp
from flint import arb

from magrod.core import systems
from magrod.core.params import RodParams
from magrod.proof import ball, fields

ROOT = Path(__file__).resolve().parent.parent
CERT = ROOT / "magrod" / "proof" / "certificates" / "horseshoe_fig4a_interval.json"
WIDTHS = ("2e-11", "1e-10", "1e-9", "1e-8")
mp.mp.dps = 40


def q128(x) -> hy.real128:
    return hy.real128(mp.nstr(_mpf(x) if isinstance(x, F) else mp.mpf(x), 36))


class QuadMap:
    """P(z, s) on (theta, pbar_theta), branch psi = 0, pbar_psi the level's largest root, at lambdabar = lam_c + s."""

    def __init__(self, p: fields.ExactParams, h: F):
        self.p, self.h = p, h
        v = hy.make_vars(*systems.STATE["reduced"])
        ev = hy.t_event(hy.sin(v[fields.PSI]), direction=hy.event_direction.positive, fp_type=hy.real128)
        self.ta = hy.taylor_adaptive(systems.system("reduced"), [q128(F(1)), q128(F(0)), q128(F(0)), q128(F(1))],
                                     pars=[q128(getattr(p, k)) for k in fields.PARAMS], tol=hy.real128("1e-32"),
                                     t_events=[ev], fp_type=hy.real128)

    def lift(self, z, ps: fields.ExactParams) -> list:
        """(theta, 0, pbar_theta, pbar_psi) with Hbar = h by Newton in 256-bit balls (psi' = dHbar/dpbar_psi)."""
        from magrod.chaos.section import solve_p_psi

        guess = solve_p_psi(RodParams(*ps.floats()), float(self.h), float(z[0]), float(z[1]), 0.0)[-1]
        with ball.workprec(256):
            x = [arb(mp.nstr(z[0], 60)), arb(0), arb(mp.nstr(z[1], 60)), arb(float(guess))]
            fld = fields.chart_field(ps)
            for _ in range(8):
                x[3] = (x[3] - (fields.hamiltonian(ps, x) - ball.q(self.h)) / fld.f(x)[fields.PSI]).mid()
            return [mp.mpf(v.mid().str(70, radius=False)) for v in x]

    def __call__(self, z, s: F) -> list:
        ps = fields.ExactParams(self.p.m, self.p.mu, self.p.gamma, self.p.delta, self.p.lam + s)
        x = self.lift(z, ps)
        ta = self.ta
        ta.time = hy.real128(0)
        ta.state[:] = [q128(v) for v in x]
        ta.pars[:] = [q128(getattr(ps, k)) for k in fields.PARAMS]
        ta.reset_cooldowns()
        while True:
            oc = ta.propagate_until(ta.time + hy.real128(100))[0]
            if int(oc) != -1:
                raise RuntimeError("no return of the section map within t = 100")
            if float(ta.time) > 1e-3:
                break
        return [mp.mpf(str(ta.state[fields.THETA])), mp.mpf(str(ta.state[fields.PTHETA]))]


def _mpf(x) -> mp.mpf:
    """An exact rational (Fraction or "p/q") as an mpf."""
    x = F(x)
    return mp.mpf(x.numerator) / x.denominator


def _set(s):
    return [_mpf(v) for v in s["c"]], mp.matrix([[_mpf(v) for v in r] for r in s["A"]]), [_mpf(x) for x in s["v"]]


def measure(P: QuadMap, n12, n13, W: F) -> dict:
    c12, A12, v12 = n12
    c13, A13, v13 = n13
    Ai = A13 ** -1

    def y(s: F):  # the centre's image in N13's coordinates at s
        sf = _mpf(s)
        z = [c12[i] + v12[i] * sf for i in range(2)]
        img = P(z, s)
        return Ai * mp.matrix([img[i] - c13[i] - v13[i] * sf for i in range(2)])

    def G(s: F):  # A13^-1 DP A12 at the moving centre, central differences along A12's columns
        sf = _mpf(s)
        z0 = [c12[i] + v12[i] * sf for i in range(2)]
        cols = []
        for k in range(2):
            e = [A12[i, k] * mp.mpf("1e-3") for i in range(2)]
            a = P([z0[i] + e[i] for i in range(2)], s)
            b = P([z0[i] - e[i] for i in range(2)], s)
            cols.append(Ai * mp.matrix([(a[i] - b[i]) / mp.mpf("2e-3") for i in range(2)]))
        return mp.matrix([[cols[0][0], cols[1][0]], [cols[0][1], cols[1][1]]])

    y0, yp, ym = y(F(0)), y(W), y(-W)
    h8 = W / 8
    dy = (y(h8) - y(-h8)) / (2 * _mpf(h8))
    wf = _mpf(W)
    drift = max(abs(yp[1] - y0[1] - wf * dy[1]), abs(ym[1] - y0[1] + wf * dy[1]))
    G0, Gp, Gm = G(F(0)), G(W), G(-W)
    shear = max(abs(Gp[1, 0] - G0[1, 0]) + abs(Gp[1, 1] - G0[1, 1]), abs(Gm[1, 0] - G0[1, 0]) + abs(Gm[1, 1] - G0[1, 1]))
    budget = 1 - abs(y0[1]) - abs(G0[1, 0]) - abs(G0[1, 1])
    return {"W": str(W), "y_s0": float(y0[1]), "dy_s_ds": float(dy[1]), "drift": float(drift), "shear": float(shear),
            "G_su": float(G0[1, 0]), "G_ss": float(G0[1, 1]), "budget": float(budget),
            "left": float(budget - drift - shear)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    c = json.loads(CERT.read_text())
    p = fields.ExactParams(**{k: F(v) for k, v in c["params"].items()})
    P = QuadMap(p, F(c["level"]))
    n12, n13 = _set(c["sets"][12]), _set(c["sets"][13])
    t0 = time.perf_counter()
    rows = []
    for w in WIDTHS:
        r = measure(P, n12, n13, F(w))
        rows.append(r)
        print(r, flush=True)
    out = {"certificate": CERT.name, "link": "N12 => N13", "rows": rows, "wall_s": round(time.perf_counter() - t0, 1),
           "date": time.strftime("%Y-%m-%d")}
    if a.out:
        Path(a.out).write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    main()
