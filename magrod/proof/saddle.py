"""Rigorous enclosures of the tilted saddle and of its eigen-data (Krawczyk operator, ball arithmetic).

The tilted straight rod (mu > 2 lambdabar) is an equilibrium q* = (theta0, 0, 0, pbar_psi0) of the reduced chart on
Fix(R) (magrod/splitting.py finds it in floating point).  Here:

* `krawczyk(F, DF, xhat, X)`: K(X) = xhat - C F(xhat) + (I - C DF(X)) (X - xhat), C ~ DF(xhat)^{-1} (any point
  matrix).  If K(X) lies in the interior of the box X, F has exactly one zero in X, and it lies in K(X)
  (Krawczyk 1969; Moore, Kearfott & Cloud, Introduction to Interval Analysis, SIAM 2009, Thm 8.2).  The box is
  taken symmetric in (psi, pbar_theta) about 0, so R(X) = X: R maps zeros to zeros, uniqueness gives R q* = q*,
  i.e. the enclosed saddle lies on Fix(R) exactly.
* `eigenpair(A, lam, v, k)`: the same operator in C^n for G(lam, v) = (A - lam I) v with the normalisation
  v_k = 1.  A is an interval matrix (Df over the saddle box), so the enclosure holds for the Jacobian at the
  true saddle.  An enclosure with Re lam > 0 and Im lam > 0 and one with Re < 0, Im > 0 give, with their complex
  conjugates (A is real), four distinct eigenvalues of a 4 x 4 matrix: the whole spectrum, a saddle-focus
  +-alpha +- i beta with alpha, beta != 0.
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from flint import acb, acb_mat, arb, arb_mat

from . import ball


def krawczyk(F, DF, xhat: list, X: list):
    """(K(X), inside): F(list) -> list of balls, DF(list) -> arb_mat; xhat exact points inside X."""
    n = len(xhat)
    J0 = ball.to_floats(DF(xhat).mid())
    C = ball.exact_matrix(np.linalg.inv(J0).tolist())
    Fx = ball.vec(F(xhat))
    I = arb_mat(n, n, [arb(1) if i == j else arb(0) for i in range(n) for j in range(n)])
    dX = ball.vec([x - xh for x, xh in zip(X, xhat)])
    K = ball.vec(xhat) - C * Fx + (I - C * DF(X)) * dX
    Kl = ball.column(K)
    inside = all(_interior(k, x) for k, x in zip(Kl, X))
    return Kl, inside


def _interior(a: arb, b: arb) -> bool:
    lo, hi = ball.bounds(a)
    blo, bhi = ball.bounds(b)
    return blo < lo and hi < bhi


def _interior_c(a: acb, b: acb) -> bool:
    return _interior(a.real, b.real) and _interior(a.imag, b.imag)


def _cinterval(z: complex, rad: Fraction) -> acb:
    return acb(ball.interval(Fraction(z.real) - rad, Fraction(z.real) + rad),
               ball.interval(Fraction(z.imag) - rad, Fraction(z.imag) + rad))


def eigenpair(A: arb_mat, lam: complex, v, k: int, rad=Fraction(1, 10**20)):
    """Krawczyk enclosure of the eigenpair (lam, v), v_k = 1, of every matrix in the interval matrix A.
    Returns (lam_ball (acb), v_balls (list of acb), inside (bool))."""
    n = A.nrows()
    v = np.asarray(v, complex) / complex(v[k])
    idx = [j for j in range(n) if j != k]
    zhat = [complex(lam)] + [complex(v[j]) for j in idx]
    zc = [acb(ball.dyadic(z.real), ball.dyadic(z.imag)) for z in zhat]
    Z = [_cinterval(z, rad) for z in zhat]
    Ac = acb_mat(A)

    def G(z):
        lam_, vv = z[0], _full(z[1:], k, n)
        return [sum((Ac[i, j] * vv[j] for j in range(n)), acb(0)) - lam_ * vv[i] for i in range(n)]

    def DG(z):
        lam_, vv = z[0], _full(z[1:], k, n)
        M = acb_mat(n, n)
        for i in range(n):
            M[i, 0] = -vv[i]
            for c, j in enumerate(idx, start=1):
                M[i, c] = Ac[i, j] - (lam_ if i == j else 0)
        return M

    D0 = DG(zc)
    D0f = np.array([[complex(float(D0[i, j].real.mid()), float(D0[i, j].imag.mid())) for j in range(n)]
                    for i in range(n)])
    Cf = np.linalg.inv(D0f)
    C = acb_mat(n, n, [acb(ball.dyadic(c.real), ball.dyadic(c.imag)) for c in Cf.flatten()])
    I = acb_mat(n, n, [acb(1) if i == j else acb(0) for i in range(n) for j in range(n)])
    Gz = acb_mat(n, 1, G(zc))
    dZ = acb_mat(n, 1, [z - c for z, c in zip(Z, zc)])
    K = acb_mat(n, 1, zc) - C * Gz + (I - C * DG(Z)) * dZ
    Kl = [K[i, 0] for i in range(n)]
    inside = all(_interior_c(a, b) for a, b in zip(Kl, Z))
    return Kl[0], _full(Kl[1:], k, n), inside


def _full(rest, k, n):
    out = list(rest)
    out.insert(k, acb(1))
    return out


@dataclass
class SaddleEnclosure:
    """The saddle box X (unique zero of the chart field, R-symmetric), its Krawczyk image K (contains the zero),
    the exact centre xhat, and the eigenpair enclosures (unstable: Re, Im > 0; stable: Re < 0, Im > 0)."""

    xhat: list
    X: list
    K: list
    lam_u: acb
    v_u: list
    lam_s: acb
    v_s: list
    checks: dict
    eig_inputs: list  # [(lam, v / v_k, k)] as floats: the Krawczyk boxes' centres (a verifier rebuilds them)


def refine(fld, x0, iterations=8) -> list:
    """Newton iterations on ball midpoints (non-rigorous refinement of a float guess; rigour comes later)."""
    x = [ball.dyadic(v) for v in x0]
    for _ in range(iterations):
        Fx = np.array([float(v.mid()) for v in fld.f(x)], dtype=float)
        M = fld.df(x)
        # solve in arb (midpoints): the update need not be rigorous
        d = M.mid().solve(ball.vec([v.mid() for v in fld.f(x)]))
        x = [(a - d[i, 0]).mid() for i, a in enumerate(x)]
        if np.max(np.abs(Fx)) == 0:
            break
    return x


def enclose(fld, xhat: list, radius: Fraction, symmetric=(1, 2), eig_guess=None, eig_rad=Fraction(1, 10**18)):
    """Krawczyk enclosure of the zero near xhat (exact points) in the box xhat +- radius, with the components
    in `symmetric` (psi, pbar_theta) forced to be centred at 0; then the two eigenpairs from eig_guess =
    ((lam_u, v_u), (lam_s, v_s)) (floats)."""
    xhat = [v.mid() for v in xhat]
    for i in symmetric:
        xhat[i] = arb(0)
    X = [ball.interval(ball.fraction(x) - radius, ball.fraction(x) + radius) for x in xhat]
    K, inside = krawczyk(fld.f, fld.df, xhat, X)
    checks = {"krawczyk_inside": inside,
              "box_R_symmetric": all(ball.bounds(X[i])[0] == -ball.bounds(X[i])[1] for i in symmetric)}
    A = fld.df(K)
    res, inputs = [], []
    for lam, v in eig_guess:
        k = int(np.argmax(np.abs(v)))
        lam_b, v_b, ok = eigenpair(A, lam, v, k, eig_rad)
        res.append((lam_b, v_b, ok))
        inputs.append((complex(lam), np.asarray(v, complex) / complex(v[k]), k))
    (lu, vu, oku), (ls, vs, oks) = res
    checks.update({"eig_unstable_inside": oku, "eig_stable_inside": oks,
                   "unstable_re_pos": ball.positive(lu.real), "unstable_im_pos": ball.positive(lu.imag),
                   "stable_re_neg": ball.negative(ls.real), "stable_im_pos": ball.positive(ls.imag)})
    return SaddleEnclosure(xhat, X, K, lu, vu, ls, vs, checks, inputs)
