"""Kind "homoclinic" (statement 5; the prover is magrod/proof/provers/transverse_homoclinic.py): transverse symmetric homoclinic orbits of
the tilted saddle-focus.  The saddle's Krawczyk test, the eigenpairs, the cone conditions of the local manifold, the
lift of the boundary arc, both flights with the certificate's exact steps, the section crossings, the interval Newton
step in the phase and dtheta_u/dpsi, re-implemented here (the prover's saddle.py and manifold.py are not imported).

On a lambdabar interval (settings.lam_rad > 0) the boundary circle is centred on the moving saddle x*(lambdabar),
whose motion the certificate encloses as K0 + B (lambdabar - lam) (saddle_motion), and the flights carry lambdabar
as a tenth state (moving_arc, fields.body_lam_state_field): on a circle about the fixed saddle the homoclinic phase
moves ~2e6 times as far as lambdabar, on this one ~8 times.
"""
from __future__ import annotations

import time
from fractions import Fraction

import numpy as np
from flint import acb, acb_mat, arb, arb_mat

from .. import ball, fields, identities, taylor
from ..theorem import TARGETS, homoclinic_theorem
from .schema import CertificateError, VerifyResult, check_structure, checked, frac, inside, recomputed

def verify(cert, module, t0) -> VerifyResult:
    """The homoclinic certificate `cert` re-checked against the field `module` (started at perf_counter t0)."""
    def body(claim):
        p, st = _inputs(cert)
        with ball.workprec(st["prec"], st["series_cap"]):
            return p, _verify(cert, p, st, module, claim)

    checks, out, failed = checked(t0, body)
    if failed:
        return failed
    p, targets = out
    slopes = {c["target"]: [ball.decimal(b) for b in ball.json_bounds(c["dtheta_dpsi"])] for c in cert["crossings"]}
    return VerifyResult(True, "certificate verified: every enclosure recomputed and every check holds", checks,
                        time.perf_counter() - t0, homoclinic_theorem(p.as_json(), targets, _lam_rad_text(p)), slopes)


def _lam_rad_text(p) -> str:
    w = Fraction(getattr(p, "lam_rad", 0))
    return f"{w.numerator}/{w.denominator}"


def _inputs(cert):
    """The parameters (lambdabar an interval when the settings carry lam_rad > 0: fields.IntervalParams, so that
    every recomputed enclosure holds for every lambdabar of it) and the numerical settings."""
    p = fields.ExactParams(**{k: frac(cert["params"][k]) for k in fields.PARAMS})
    s = cert["settings"]
    w = frac(s.get("lam_rad", "0"))  # absent: a certificate at the point (the first homoclinic certificates)
    if w < 0:
        raise CertificateError("settings: lam_rad must be >= 0")
    if w:
        p = fields.IntervalParams(p.m, p.mu, p.gamma, p.delta, p.lam, lam_rad=w)
    st = {"prec": int(s["prec"]), "order": int(s["order"]), "series_cap": int(s["series_cap"]),
          "radius": frac(cert["saddle"]["radius"]), "eig_rad": frac(s["eig_rad"])}
    if not (64 <= st["prec"] <= 1024 and 4 <= st["order"] < st["series_cap"] <= 256):
        raise CertificateError("settings out of range (prec 64..1024 bits, 4 <= order < series_cap <= 256)")
    return p, st


def _stored_claims(cert, claim):
    """The theorem's inequalities on the certificate's own balls (cheap; the recomputation follows)."""
    for c in cert["crossings"]:
        tgt = c["target"]
        a = {k: ball.from_json(v) for k, v in c["arc"]["enclosures"].items()}
        phic, dphi = frac(c["phi_c"]), frac(c["dphi"])
        branch = {"0": ball.positive, "pi": ball.negative}[tgt]  # targets were checked recognised
        claim(f"psi={tgt} claims", ball.excludes_zero(a["gdot"]) and ball.excludes_zero(a["dGs"])
              and branch(a["Gc"])
              and inside(ball.from_json(c["newton"]), ball.interval(phic - dphi, phic + dphi))
              and ball.excludes_zero(ball.from_json(c["dtheta_dpsi"])),
              "the certificate's balls satisfy the claims (section transversal, branch, dGs != 0, Newton inside "
              "the arc, dtheta_u/dpsi excludes 0)")


def _check_statement(cert, p, st, claim) -> list:
    """What the certificate must contain to establish a theorem, and which theorem: returns the targets.

    Cheap, and first: a certificate with a missing, repeated or unknown target, or whose theorem text is not the
    one its content establishes, is rejected before any enclosure is recomputed."""
    targets = cert["settings"]["targets"]
    crossings = cert["crossings"]
    claim("targets recognised", isinstance(targets, list) and all(isinstance(t, str) and t in TARGETS for t in targets),
          f"every target of the settings is one of {sorted(TARGETS)} (psi = 0 or psi = pi on Fix(R)); got "
          f"{str(targets)[:80]}")
    claim("targets distinct", len(targets) > 0 and len(set(targets)) == len(targets),
          f"the settings name at least one target and none twice; got {targets}")
    got = [c["target"] if isinstance(c, dict) else None for c in crossings] if isinstance(crossings, list) else None
    claim("crossings recognised", got is not None and all(isinstance(t, str) and t in TARGETS for t in got),
          f"every crossing's target is one of {sorted(TARGETS)}; got {str(got)[:80]}")
    claim("one crossing per target", len(got) == len(set(got)) and sorted(got) == sorted(targets),
          f"the crossings' targets {got} are exactly the settings' targets {targets}, each once")
    s = cert["settings"]
    claim("settings match the data",
          frac(cert["saddle"]["radius"]) == frac(s["saddle_radius"]) and frac(cert["manifold"]["r"]) == frac(s["r"])
          and all(frac(c["h_cross"]) == 2 * frac(s["lead"]) for c in crossings)
          and all(frac(c["dphi"]) >= frac(s["dphi"]) for c in crossings),
          "the saddle box radius, the circle radius, the crossing step (2 lead) and the phase arcs (>= dphi) are "
          "the recorded settings")
    want = homoclinic_theorem(p.as_json(), targets, _lam_rad_text(p))
    stated = cert["theorem"]
    claim("theorem text", isinstance(stated, str) and stated == want,
          "the certificate's theorem is the one its verified content establishes"
          + ("" if stated == want else f" (expected: {want[:160]}...; the certificate states: {str(stated)[:160]}...)"))
    return targets


def _verify(cert, p, st, module, claim):
    targets = _check_statement(cert, p, st, claim)
    _stored_claims(cert, claim)
    check_structure(module, claim)
    # the flights run in body variables from the lift of the boundary arc: the lift's facts, as exact identities
    for name, holds, how in identities.lift_check(fields.source(module), fields.PARAMS):
        claim(name, holds, how)
    claim("field digest", cert["field_digest"] == fields.source_digest(module) == fields.source_digest(fields.gen),
          "the certificate's vector field is the installed derive-generated one (SHA-256 of generated/validated.py)")
    lam_hi = p.lam + getattr(p, "lam_rad", 0)
    claim("parameters", p.mu > 2 * lam_hi and p.m > 0 and p.m ** 2 < 4 * (1 + p.gamma) and min(p.gamma, p.delta) >= 0,
          "mu > 2 lambdabar (on the whole lambdabar interval), 0 < m < m_c = 2 sqrt(1 + gamma), gamma, delta >= 0")
    fld = fields.chart_field(p, module)
    xhat, K = _check_saddle(cert, p, st, fld, claim)
    _check_eigen(cert, fld, K, st, claim)
    V, rho_eff, L, r = _check_manifold(cert, fld, xhat, K, claim)
    if getattr(p, "lam_rad", 0):
        # on a lambdabar interval the boundary circle is centred on the moving saddle x*(lambdabar) and the flights
        # carry lambdabar as a state: the phase of the homoclinic point then moves ~7 lam_rad, not ~2e6 lam_rad
        K0, B = _check_saddle_motion(cert, p, st, module, xhat, K, claim)
        U = _norm2(ball.column(V.inv() * ball.vec([a - b for a, b in zip(K, xhat)]))[:2])
        claim("moving circle inside the block", U + r < frac(cert["manifold"]["r_block"]),
              "|u*(lambdabar)| + r < r_block: the circle about the moving saddle lies in the block, where W^u_loc is "
              "the graph of an L-Lipschitz function through the saddle")
        flight = LamStateFlight(p, module, lambda lo, hi: moving_arc(p, V, xhat, K0, B, L, r, lo, hi, module))
    else:
        flight = PointFlight(p, module, lambda lo, hi: _lift(p, V, xhat, rho_eff, L, r, lo, hi, module))
    for c in cert["crossings"]:
        _check_crossing(c, flight, st["order"], claim)
    return targets


class PointFlight:
    """The flights of a certificate at one lambdabar: the body field, its events and their gradients, and the lift
    of a boundary arc (lo, hi) -> (C^1 set, body tangent box)."""

    def __init__(self, p, module, lift):
        self.field, self.lift = fields.body_field(p, module), lift
        self.events = lambda x: fields.body_events(p, x, module)
        self.gradient = lambda x, name: fields.body_event_gradient(p, x, name, module)


class LamStateFlight(PointFlight):
    """The flights on a lambdabar interval: the body field with lambdabar as its tenth state
    (fields.body_lam_state_field), the events evaluated at the state's own lambdabar."""

    def __init__(self, p, module, lift):
        self.field, self.lift = fields.body_lam_state_field(p, module), lift
        self.events = lambda x: fields.lam_state_events(p, x, module)
        self.gradient = lambda x, name: fields.lam_state_event_gradient(p, x, name, module)


def krawczyk(fld, xhat, X) -> list:
    """K(X) = xhat - C F(xhat) + (I - C DF(X)) (X - xhat), C a float inverse of DF(xhat): inside the interior of X
    means exactly one zero of fld in X, and it lies in K(X)."""
    n = fld.n
    Cf = np.linalg.inv(ball.to_floats(fld.df(xhat).mid()))
    C = arb_mat(n, n, [ball.dyadic(v) for v in Cf.flatten()])
    I = arb_mat(n, n, [arb(int(i == j)) for i in range(n) for j in range(n)])
    return ball.column(ball.vec(xhat) - C * ball.vec(fld.f(xhat))
                       + (I - C * fld.df(X)) * ball.vec([a - b for a, b in zip(X, xhat)]))


def saddle_motion(p, module, xhat, K, rad0):
    """The saddle as an affine function of lambdabar: (K0, B, ok) with x*(lambdabar) in K0 + B (lambdabar - lam)
    for every lambdabar of p's interval.  K0: the Krawczyk image at the centre lam (ok: inside the box xhat +-
    rad0, so x*(lam) in K0); B = -DF^-1 dF/dlambdabar over K x [interval] (Arb's solve encloses the solution for
    every matrix of the ball), which holds dx*/dlambdabar at every lambdabar of the interval since x* stays in K;
    the mean value theorem, coordinate by coordinate, gives the affine enclosure."""
    pc = p.centre()
    X0 = [ball.interval(ball.fraction(v) - rad0, ball.fraction(v) + rad0) for v in xhat]
    K0 = krawczyk(fields.chart_field(pc, module), xhat, X0)
    ok = all(inside(k, x) for k, x in zip(K0, X0))
    n = len(xhat)
    J = fields.lam_state_field(p, module).df(list(K) + [p.balls()[fields.LAM]])
    A = arb_mat(n, n, [J[i, j] for i in range(n) for j in range(n)])
    c = arb_mat(n, 1, [J[i, n] for i in range(n)])
    try:
        B = ball.column(-A.solve(c))
    except ZeroDivisionError:  # DF over the box not provably invertible
        B, ok = [ball.interval(-1, 1) * 10**30] * n, False
    return K0, B, ok


def moving_arc(p, V, xhat, K0, B, L, r, lo, hi, module):
    """The arc phi in [lo, hi] of the circle of radius r about the moving saddle on W^u_loc(x*(lambdabar)), for
    every lambdabar of p's interval, lifted to the body frame with lambdabar as a tenth state.

    In the chart y = V^-1 (x - xhat): y*(lambdabar) in y0 + b dl (y0 = V^-1 (K0 - xhat), b = V^-1 B, dl =
    lambdabar - lam), the point is y*(lambdabar) + (r cos phi, r sin phi, s) with |s| <= L r (W^u_loc is the graph
    of an L-Lipschitz function through the saddle).  By the mean value theorem over the chart box Q and the
    interval, X(q, lambdabar) - X(q_c, lam) lies in (DX V)(y - y_c) + dX/dlambdabar dl, whose parts linear in the
    circle's offsets and in dl form the set's C r0 (exact C), the rest its error ball.  Returns the C^1 set (10
    states, r0 = the four chart offsets and dl) and the tangent d/dphi at fixed lambdabar (10 balls, last 0)."""
    W = p.lam_rad
    Vi = V.inv()
    dl = ball.interval(-W, W)
    y0 = ball.column(Vi * ball.vec([a - b for a, b in zip(K0, xhat)]))
    b = ball.column(Vi * ball.vec(B))
    Phi = ball.interval(lo, hi)
    rq, lr = ball.q(r), L * r
    circ = [rq * Phi.cos(), rq * Phi.sin(), ball.interval(-lr, lr), ball.interval(-lr, lr)]
    dy = [-rq * Phi.sin(), rq * Phi.cos(), ball.interval(-lr, lr), ball.interval(-lr, lr)]
    cc = [c.mid() for c in circ]
    yc = [a.mid() + c for a, c in zip(y0, cc)]
    Q = ball.column(ball.vec(xhat) + V * ball.vec([a + bb * dl + c for a, bb, c in zip(y0, b, circ)]))
    qc = ball.column(ball.vec(xhat) + V * ball.vec(yc))
    JV = fields.lift_jacobian(p, Q, module) * V
    Jl = ball.vec(fields.lift_lam_derivative(p, Q, module))
    C0 = JV.mid()
    cl = (C0 * ball.vec([v.mid() for v in b]) + Jl.mid()).mid()
    dyb = ball.vec([y - c for y, c in zip(circ, cc)])
    err = ball.column((JV - C0) * dyb + (JV * ball.vec(b) + Jl - cl) * dl
                      + JV * ball.vec([a - a.mid() for a in y0]))
    pc = p.centre()
    n = JV.nrows()
    S = taylor.initial_set([a + e for a, e in zip(fields.lift(pc, qc, module), err)] + [ball.q(p.lam)], c1=True)
    S.C = arb_mat(n + 1, 5, [C0[i, j] if j < 4 else cl[i, 0] for i in range(n) for j in range(5)]
                  + [arb(0)] * 4 + [arb(1)])
    S.r0 = ball.vec(ball.column(dyb) + [dl])
    return S, ball.vec(ball.column(JV * ball.vec(dy)) + [arb(0)])


def _check_saddle(cert, p, st, fld, claim):
    xhat = [ball.q(frac(v)) for v in cert["saddle"]["xhat"]]
    rad = st["radius"]
    sym = (fields.PSI, fields.PTHETA)
    claim("saddle box R-symmetric", all(ball.fraction(xhat[i]) == 0 for i in sym),
          "the box centre has psi = pbar_theta = 0, so R(box) = box and the unique zero lies on Fix(R)")
    X = [ball.interval(ball.fraction(v) - rad, ball.fraction(v) + rad) for v in xhat]
    K = krawczyk(fld, xhat, X)
    claim("saddle Krawczyk", all(inside(k, x) for k, x in zip(K, X)),
          "K(X) lies in the interior of the box X: exactly one zero of the chart field in X")
    for i, (k, s) in enumerate(zip(K, cert["saddle"]["K"])):
        recomputed(claim, f"saddle K[{i}]", k, s)
    return xhat, K


def _check_saddle_motion(cert, p, st, module, xhat, K, claim):
    sd = cert["saddle"]
    K0, B, ok = saddle_motion(p, module, xhat, K, frac(sd["radius0"]))
    claim("saddle Krawczyk at the centre", ok,
          "K(X0) lies in the interior of the box X0 = xhat +- radius0 at lambdabar = lam (the zero x*(lam) in K0), "
          "and DF is invertible over the saddle box and the interval (the slope B of x*(lambdabar))")
    for i, (k, s) in enumerate(zip(K0, sd["K0"])):
        recomputed(claim, f"saddle K0[{i}]", k, s)
    for i, (b, s) in enumerate(zip(B, sd["slope"])):
        recomputed(claim, f"saddle slope[{i}]", b, s)
    return [ball.from_json(s) for s in sd["K0"]], [ball.from_json(s) for s in sd["slope"]]


def _check_eigen(cert, fld, K, st, claim):
    A = acb_mat(fld.df(K))
    n = fld.n
    for key, want in (("u", (1, 1)), ("s", (-1, 1))):
        inp = cert["saddle"][f"eig_input_{key}"]
        lam0 = complex(float(frac(inp["lam"][0])), float(frac(inp["lam"][1])))
        k = int(inp["k"])
        v0 = [complex(float(frac(a)), float(frac(b))) for a, b in inp["v"]]
        zc = [acb(ball.q(frac(inp["lam"][0])), ball.q(frac(inp["lam"][1])))] + \
             [acb(ball.q(frac(a)), ball.q(frac(b))) for j, (a, b) in enumerate(inp["v"]) if j != k]
        rad = st["eig_rad"]
        Z = [acb(ball.interval(ball.fraction(z.real.mid()) - rad, ball.fraction(z.real.mid()) + rad),
                 ball.interval(ball.fraction(z.imag.mid()) - rad, ball.fraction(z.imag.mid()) + rad)) for z in zc]
        G, DG = _eigen_system(A, n, k)
        D0 = DG(zc)
        Cf = np.linalg.inv(np.array([[complex(float(D0[i, j].real.mid()), float(D0[i, j].imag.mid()))
                                      for j in range(n)] for i in range(n)]))
        C = acb_mat(n, n, [acb(ball.dyadic(c.real), ball.dyadic(c.imag)) for c in Cf.flatten()])
        I = acb_mat(n, n, [acb(int(i == j)) for i in range(n) for j in range(n)])
        Kz = acb_mat(n, 1, zc) - C * acb_mat(n, 1, G(zc)) + (I - C * DG(Z)) * acb_mat(n, 1, [a - b for a, b in zip(Z, zc)])
        Kl = [Kz[i, 0] for i in range(n)]
        claim(f"eigenpair {key} Krawczyk", all(inside(a.real, b.real) and inside(a.imag, b.imag) for a, b in zip(Kl, Z)),
              f"Krawczyk image inside the box around (lambda_{key}, v_{key}), v_k = 1, k = {k}")
        lam = Kl[0]
        ok = (ball.positive(lam.real) if want[0] > 0 else ball.negative(lam.real)) and ball.positive(lam.imag)
        claim(f"eigenvalue {key}", ok, f"lambda_{key} = {lam}: Re {'>' if want[0] > 0 else '<'} 0, Im > 0")
        stored = cert["saddle"][f"lam_{key}"]
        recomputed(claim, f"lambda_{key} (re)", lam.real, stored["re"])
        recomputed(claim, f"lambda_{key} (im)", lam.imag, stored["im"])
        del lam0, v0


def _eigen_system(A, n, k):
    """G(lam, v) = (A - lam I) v with v_k = 1 (unknowns: lam and the other n - 1 entries of v), and DG."""
    idx = [j for j in range(n) if j != k]

    def full(z):
        v = list(z[1:])
        v.insert(k, acb(1))
        return z[0], v

    def G(z):
        lam, v = full(z)
        return [sum((A[i, j] * v[j] for j in range(n)), acb(0)) - lam * v[i] for i in range(n)]

    def DG(z):
        lam, v = full(z)
        M = acb_mat(n, n)
        for i in range(n):
            M[i, 0] = -v[i]
            for c, j in enumerate(idx, start=1):
                M[i, c] = A[i, j] - (lam if i == j else 0)
        return M

    return G, DG


def _abs_up(x) -> arb:
    return ball.q(max(abs(v) for v in ball.bounds(x)))


def _norm2(entries) -> Fraction:
    return ball.bounds(sum((_abs_up(e) * _abs_up(e) for e in entries), arb(0)).sqrt())[1]


def _sym2(M):
    a, d = M[0][0], M[1][1]
    b = (M[0][1] + M[1][0]) / 2
    mean = (a + d) / 2
    rad = (_abs_up((a - d) / 2) * _abs_up((a - d) / 2) + _abs_up(b) * _abs_up(b)).sqrt()
    return ball.bounds(mean - rad)[0], ball.bounds(mean + rad)[1]


def _check_manifold(cert, fld, xhat, K, claim):
    m = cert["manifold"]
    n = fld.n
    V = arb_mat(n, n, [ball.q(frac(v)) for row in m["V"] for v in row])
    rb, rho, L, r = (frac(m[k]) for k in ("r_block", "rho", "L", "r"))
    Vi = V.inv()
    ybox = [ball.interval(-rb, rb)] * 2 + [ball.interval(-rho, rho)] * 2
    G = Vi * fld.df(ball.column(ball.vec(xhat) + V * ball.vec(ybox))) * V
    blk = {(a, b): [[G[i, j] for j in b] for i in a] for a in ((0, 1), (2, 3)) for b in ((0, 1), (2, 3))}
    u, s = (0, 1), (2, 3)
    m_u = _sym2(blk[u, u])[0]
    M_s = _sym2(blk[s, s])[1]
    c_us = _norm2([e for row in blk[u, s] for e in row])
    c_su = _norm2([e for row in blk[s, u] for e in row])
    N_uu = _norm2([e for row in blk[u, u] for e in row])
    N_ss = _norm2([e for row in blk[s, s] for e in row])
    y = ball.column(Vi * ball.vec([a - b for a, b in zip(K, xhat)]))
    U, S = _norm2(y[:2]), _norm2(y[2:])
    claim("manifold outflow", m_u * rb > N_uu * U + c_us * (rho + S), "u . u' > 0 on |u| = r_block")
    claim("manifold inflow", -M_s * rho > c_su * (rb + U) + N_ss * S, "s . s' < 0 on |s| = rho")
    claim("manifold cone", L * (m_u - M_s) > c_su + L * L * c_us, "the cone |ds| <= L |du| is forward invariant")
    claim("manifold growth", M_s + c_su / L < 0 and m_u - c_us * L > 0,
          "outside the cone |ds| grows backwards, inside |du| shrinks backwards")
    claim("manifold saddle inside", U < rb and S < rho and 0 < r < rb, "the saddle and the circle lie inside the block")
    rho_eff = min(rho, S + L * (r + U))
    claim("manifold rho_eff", frac(m["rho_eff"]) >= rho_eff,
          "the certificate's C^0 bound of the boundary circle is at least the recomputed min(rho, S + L (r + U))")
    return V, frac(m["rho_eff"]), L, r


def _lift(p, V, xhat, rho_eff, L, r, lo, hi, module):
    Phi = ball.interval(lo, hi)
    rq = ball.q(r)
    ybox = [rq * Phi.cos(), rq * Phi.sin(), ball.interval(-rho_eff, rho_eff), ball.interval(-rho_eff, rho_eff)]
    lr = L * r
    dy = [-rq * Phi.sin(), rq * Phi.cos(), ball.interval(-lr, lr), ball.interval(-lr, lr)]
    yc = [y.mid() for y in ybox]
    Q = ball.column(ball.vec(xhat) + V * ball.vec(ybox))
    qc = ball.column(ball.vec(xhat) + V * ball.vec(yc))
    JV = fields.lift_jacobian(p, Q, module) * V
    C0 = JV.mid()
    dyb = ball.vec([y - c for y, c in zip(ybox, yc)])
    err = ball.column((JV - C0) * dyb)
    S = taylor.initial_set([a + e for a, e in zip(fields.lift(p, qc, module), err)], c1=True)
    S.C, S.r0 = C0, dyb
    return S, JV * ball.vec(dy)


def _check_crossing(c, flight, order, claim):
    tgt = c["target"]
    phic, dphi, t_a, h = (frac(c[k]) for k in ("phi_c", "dphi", "t_a", "h_cross"))
    e33 = fields.E33

    def g(x):
        return flight.events(x)["g"]

    def dg(x):
        return flight.gradient(x, "g")

    def guard(Y):
        return [1 - Y[e33], 1 + Y[e33], flight.events(Y)["rad"]]

    vals = {}
    for kind, lo, hi in (("thin", phic, phic), ("arc", phic - dphi, phic + dphi)):
        steps = [frac(s) for s in c[kind]["steps"]]
        claim(f"psi={tgt} {kind} steps", sum(steps) == t_a and all(s > 0 for s in steps),
              f"the {len(steps)} exact step sizes add up to t_a = {float(t_a):.9g}")
        S, tangent = flight.lift(lo, hi)
        try:
            S = taylor.propagate(flight.field, S, steps=steps, order=order, guard=guard)
            cr = taylor.cross_section(flight.field, S, g, dg, h, order, guard=guard)
        except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
            claim(f"psi={tgt} {kind} flight", False, str(err))
        ev = flight.events(cr.x)
        q = {"Gs": ev["Gs"], "Gc": ev["Gc"], "s2": ev["s2"], "gdot": cr.gdot, "tau": cr.tau}
        u = ball.column(cr.W * tangent)
        grad = dg(cr.x)
        gu = sum((a * b for a, b in zip(grad, u)), arb(0))
        gf = sum((a * b for a, b in zip(grad, cr.fx)), arb(0))
        v = [ui - fi * gu / gf for ui, fi in zip(u, cr.fx)]
        q["dGs"] = sum((a * b for a, b in zip(flight.gradient(cr.x, "Gs"), v)), arb(0))
        q["de33"] = v[e33]
        stored = c[kind]["enclosures"]
        for k, val in q.items():
            recomputed(claim, f"psi={tgt} {kind} {k}", val, stored[k])
        vals[kind] = q
    thin, arc = vals["thin"], vals["arc"]
    # the claims are made on the certificate's balls (each contains its recomputation, checked above)
    sarc = {k: ball.from_json(v) for k, v in c["arc"]["enclosures"].items()}
    claim(f"psi={tgt} section transversal", ball.excludes_zero(sarc["gdot"]),
          "d/dt (sin theta pbar_theta) excludes 0 over the crossing step")
    claim(f"psi={tgt} branch", {"0": ball.positive, "pi": ball.negative}[tgt](sarc["Gc"]),
          f"sin(theta) rho cos(psi) {'>' if tgt == '0' else '<'} 0 at the crossing")
    claim(f"psi={tgt} dGs/dphi", ball.excludes_zero(sarc["dGs"]), "dGs/dphi excludes 0 over the arc")
    N = ball.q(phic) - thin["Gs"] / arc["dGs"]
    recomputed(claim, f"psi={tgt} Newton", N, c["newton"])
    claim(f"psi={tgt} unique zero", inside(ball.from_json(c["newton"]), ball.interval(phic - dphi, phic + dphi)),
          "the interval Newton image lies inside the phase arc: one phi* with psi = "
          + ("0" if tgt == "0" else "pi"))
    dtdp = -arc["de33"] * arc["Gc"] / (arc["s2"].sqrt() * arc["dGs"])
    recomputed(claim, f"psi={tgt} dtheta/dpsi", dtdp, c["dtheta_dpsi"])
    claim(f"psi={tgt} transversality", ball.excludes_zero(ball.from_json(c["dtheta_dpsi"])),
          "dtheta_u/dpsi excludes 0 (transverse intersection of W^u and W^s)")
