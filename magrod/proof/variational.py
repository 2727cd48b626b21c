"""Second-order enclosures in lambdabar for the section map's horseshoes on wide lambdabar intervals: the variational
system of the lambdabar-state field flown as a set, and the section map's second derivatives at a crossing
(the kernel's horseshoe_lam2.py checks Fig 4(a)'s horseshoe with them on 27/200 +- 43/2^32 (1.0012e-8), 500x the first-order
interval; research/horseshoe_second_order.py measured the route first; docs/nonintegrability.md, statement 12).

  variational_field(base, k)  y = (x, lambdabar, u_1 .. u_k), u_j' = DF(x) u_j, its Jacobian's D^2 F[u_j] blocks by
                              forward-mode duals (fields._Dual) of the generated Jacobian;
  extended_set(S, tangents)   a 5-state C^1 set extended by tangents given as balls over its hull;
  section_second_derivative   d^2/ds^2 or d^2/da ds of a section point, by implicit differentiation at the crossing;
  moving_column, d2H          the moving set's lambdabar column and D^2 Hbar[d1, d2] over a box.

The verifier's kernel reads them for a horseshoe certificate on a lambdabar interval to second order
(kernel/horseshoe_lam2.py), so this module is part of the verifier's trust base."""
from __future__ import annotations

from flint import arb, arb_mat, arb_series

from ..generated import validated as gen
from . import ball, fields, section_return as sr, taylor
from .fields import _Dual

N = 5  # (theta, psi, pbar_theta, pbar_psi, lambdabar)


def section_second_derivative(x, u, dus, f, Df, ua=None):
    """The second derivative of the section point (theta, pbar_theta) of the crossing of {sin psi = 0} by a family
    x(t; a, s): d^2/ds^2 (ua None: a = s) or the mixed d^2/da ds, from the crossing's x (psi = x[1]), u = d_s x, ua =
    d_a x, dus = d_s d_a x (d_s^2 x when ua is None), f = f(x) and Df = Df(x) (an arb_mat), all at the crossing
    (balls over its enclosure; x may carry lambdabar as a state with f = 0 there).  Implicit differentiation of
    sin psi(X(a, s)) = 0, X = x(tau(a, s); a, s), d_t u = Df u along the flow:
      X_s = u + f tau_s,  tau_s = -u_psi / f_psi  (and X_a, tau_a alike),
      X_as = (d_s ua + Df ua tau_s) + Df X_s tau_a + f tau_as,
      tau_as = -[cos psi (d_s ua + Df ua tau_s + Df X_s tau_a)_psi - sin psi (X_s)_psi (X_a)_psi] / (cos psi f_psi).
    Returns ((X_as's theta, X_as's pbar_theta), (tau_s, tau_as, X_s, X_as)).  Tested against a field whose section
    map has a closed form (tests/test_proof_variational.py)."""
    n = len(x)
    ua = u if ua is None else ua
    cps, sps = x[1].cos(), x[1].sin()
    tau_s, tau_a = -u[1] / f[1], -ua[1] / f[1]
    Xs = [u[i] + f[i] * tau_s for i in range(n)]
    Xa = [ua[i] + f[i] * tau_a for i in range(n)]
    Dfua = ball.column(Df * ball.vec(ua))
    DfXs = ball.column(Df * ball.vec(Xs))
    d = [dus[i] + Dfua[i] * tau_s + DfXs[i] * tau_a for i in range(n)]
    tau_as = -(cps * d[1] - sps * Xs[1] * Xa[1]) / (cps * f[1])
    Xas = [d[i] + f[i] * tau_as for i in range(n)]
    return (Xas[0], Xas[2]), (tau_s, tau_as, Xs, Xas)


def moving_column(pars, Q, v, module=gen):
    """The swept box's lambdabar column over the hull Q (5 balls): (gH = grad Hbar, g = -(Hbar_theta, Hbar_pt) /
    Hbar_ppsi, g_lam = -Hbar_lam / Hbar_ppsi, col = (v_theta, 0, v_pt, g . v + g_lam, 1)) -- the chart direction in
    which the piece moves with lambdabar on the level (pbar_psi's row by the implicit function theorem); module: the
    generated field's module (fields.gen, or a model's), as section_return's functions take it."""
    gH = sr.ham_gradient(pars, Q[:4], module)
    glam = -sr.ham_lam_derivative(pars, Q[:4], module) / gH[fields.PPSI]
    g = [-gH[fields.THETA] / gH[fields.PPSI], -gH[fields.PTHETA] / gH[fields.PPSI]]
    vq = [ball.q(x) for x in v]
    return gH, g, glam, [vq[0], arb(0), vq[1], g[0] * vq[0] + g[1] * vq[1] + glam, arb(1)]


def variational_field(base, k: int) -> taylor.Field:
    """y = (x5, u_1 .. u_k), u_j' = DF5(x5) u_j: the lambdabar-state field and k tangents; its Jacobian's D^2 F5[u_j]
    blocks by duals of the generated Jacobian.  Its Taylor coefficients come the way the base's do (base.series)."""
    n = N * (k + 1)

    def unwrap(v, z):
        return v.b if isinstance(v, _Dual) else z

    def rhs(y, _p):
        x = list(y[:N])
        out = list(base.rhs(x, None))
        for j in range(k):
            u = y[N * (j + 1): N * (j + 2)]
            out += [unwrap(v, 0 * y[0]) for v in base.rhs([_Dual(a, b) for a, b in zip(x, u)], None)]
        return out

    def jac(y, _p):
        x = list(y[:N])
        J = list(base.jacobian(x, None))
        z = 0 * y[0]
        M = [[z] * n for _ in range(n)]
        for b in range(k + 1):
            for i in range(N):
                for jj in range(N):
                    M[N * b + i][N * b + jj] = J[N * i + jj]
        for j in range(k):
            u = y[N * (j + 1): N * (j + 2)]
            H = base.jacobian([_Dual(a, bb) for a, bb in zip(x, u)], None)
            for i in range(N):
                for jj in range(N):
                    M[N * (j + 1) + i][jj] = unwrap(H[N * i + jj], z)
        return [e for row in M for e in row]

    return taylor.Field(rhs, jac, n, base.pars, f"lam+{k} tangents", series=base.series)


def extended_set(S5, tangents, c1: bool):
    """The set (x5 of S5, the tangents as balls) with the x5 part's Lohner form kept."""
    k = len(tangents)
    n = N * (k + 1)
    u0 = [v for t in tangents for v in t]
    center = [S5.xbar[i, 0] for i in range(N)] + [v.mid() for v in u0]
    S = taylor.initial_set(center, c1=c1)
    C = arb_mat(n, S5.C.ncols())
    for i in range(N):
        for j in range(S5.C.ncols()):
            C[i, j] = S5.C[i, j]
    S.C, S.r0 = C, S5.r0
    S.r = ball.vec(ball.column(S5.B * S5.r) + [v - v.mid() for v in u0])
    return S


def d2H(pars, x, d1, d2, module=gen):
    """D^2 Hbar[d1, d2] over the box x (4 chart balls; d1, d2 chart vectors with lambdabar as a fifth entry), by
    polarization of the univariate second derivatives along d1 + d2 and d1 - d2 (Arb series of length 3)."""
    def q(d):
        y = [arb_series([x[i], d[i]], prec=3) for i in range(4)]
        pp = list(pars)
        pp[fields.LAM] = arb_series([pars[fields.LAM], d[4]], prec=3)
        cs = module.chart_hamiltonian(y, pp)[0].coeffs()
        return 2 * cs[2] if len(cs) > 2 else arb(0)

    return (q([a + b for a, b in zip(d1, d2)]) - q([a - b for a, b in zip(d1, d2)])) / 4
