"""A validated integrator whose step remainder is a Taylor model in time (Makino-Berz), not a box evaluation.

The present integrator (taylor.py) encloses the truncation error of a step by the Lagrange remainder
x^[p+1](Y) h^(p+1) on the a priori box Y, the box that holds every trajectory of the set over the whole step
(radius ~1e-2 on the rod's flights): Arb's series recursion over Y inflates that coefficient ~1e11-fold
(benchmarks/centre_flight_frontier.py), and the centres' flights pay for it with ~2.3x the steps.  Here the
remainder is a Taylor model in time instead.  On a step [0, h] from the set X (hull of the C^0/C^1 set):

  P_c(t) = sum_{k<=p} c_k t^k        the Taylor polynomial of the solution through x0, c = c(x0) in the balls
                                     c^X = x^[k](X) (the solution series on X, as in taylor.py);
  M      = { y in C([0, h]) : y(t) - P_c(t) in I for every t }     (I: a vector of intervals, the remainder);
  Phi(y)(t) = x0 + int_0^t f(y(s)) ds                               (the Picard operator).

For y in M write y = P_c + e.  Since P_c agrees with the solution to order p, x0 + int_0^t T_{p-1}[f o P_c] = P_c(t)
exactly, so

  Phi(y)(t) - P_c(t) = int_0^t (f o P_c - T_{p-1}[f o P_c])(s) ds  +  int_0^t (f(P_c + e) - f(P_c))(s) ds.

The remainder is carried with a weight, M = { y : y(t) - P_c(t) in (t/h)^q I }, q = p + 1 (the order at which the
truncation error starts): then int_0^t Df(Y) (s/h)^q I ds lies in (t/h)^q [0, h/(q+1)] Df(Y) I, so the Lipschitz
term contracts by h |Df| / (p + 2) instead of h |Df| (without the weight the step would be capped at h < 1/|Df|,
~0.04 on the rod's flights), and every term of the tail, of degree k + 1 >= q in t, carries the weight too:

  Phi(y)(t) - P_c(t)  in  (t/h)^q (Tail + [0, h/(p+2)] Df(Y) I),      Y = P^X([0, h]) + I (holds every y in M),

  Tail = sum_{k=p}^{L-1} G_k [0, h^(k+1)] / (k+1)  +  G_L([0, h]) [0, h^(L+1)] / (L+1),

with G_k the Taylor coefficients of f o P_c at s = 0 (series arithmetic on the point-like balls c^X: sharp) and
G_L([0, h]) the coefficient L of f o P_c expanded about every point of [0, h] (the Lagrange form of the tail; the
series of P_c shifted to the ball [0, h], one field evaluation, no recursion).  If Tail + [0, h] Df(Y) I lies in
the interior of I, Phi maps the closed convex set M into itself; Phi is compact (f is continuous on the box Y,
which Arb evaluated finitely), so Schauder's theorem gives a fixed point in M: the solution through x0 exists on
[0, h] and stays in P_c(t) + (t/h)^q I, inside P_c(t) + I (it is unique since f is analytic on Y).  The remainder
is of the size of the tail: the true truncation error at G_p (= (p+1) x^[p+1]), the box-like Lagrange coefficient
only at order L, where h^(L+1) makes its inflation harmless.

The derivative DPhi_t(x0) (C^1 sets) solves V' = Df(x(t)) V, V(0) = Id: the same argument on the Taylor model
V_poly(t) = sum_k D_k(X) t^k + I_V (D_k the variational coefficients over X, as in taylor.py), with
A(s) = Df(x(s)) in Df(P_c(s)) + dDf(Y)[I] (the mean value form: one Jacobian series of length 2 on Y + I eps):

  V(t) - V_poly(t) in (t/h)^q (TailV + [0, h/(p+2)] (dDf(Y)[I] V_poly([0, h]) + Df(Y) I_V)),

TailV the tail of (Df o P_c) V_poly beyond degree p - 1, bounded as Tail.

The step's result is handed to taylor.apply_step in taylor's StepData form (Lohner's mean value form with QR,
unchanged): for x0 in X, Phi_h(x0) = P_c(x0)(h) + e with e in I, and P_c(x0)(h) = T_p(h, x0) in
T_p(h, xbar) + DT_p(h, X)(x0 - xbar); StepData's order-(p+1) slots carry I / h^(p+1) (resp. I_V / h^(p+1) with
Y_V = Id), which reproduce I (I_V) at t = h.  Inside a step (the section crossing) the remainder I holds for every
t in [0, h]: cross_section here uses it directly.

Cost per step: the solution and Jacobian series on X (as taylor.py), two field evaluations on series of length
L + 1 (at 0 and shifted) and one Jacobian on Y for C^0; for C^1 the Jacobian series at 0 to length L + 1 (instead of
p), the shifted one and one of length 2 on Y + I eps.  No series on the a priori box.  Measured
(benchmarks/centre_flight_frontier.py, README): a C^0 step costs about what taylor.py's does, a C^1 step ~1.2x, and
the remainder is ~1x the last Taylor term instead of ~1e9-1e11x, so a flight needs ~0.4-0.7x the steps for the same
enclosure.

References: K. Makino, M. Berz, Verified integration of ODEs and flows using differential algebraic methods on
high-order Taylor models, Reliable Computing 4 (1998) 361-369; K. Makino, M. Berz, Suppression of the wrapping
effect by Taylor model-based verified integrators, Int. J. Diff. Eq. Appl. 10 (2005); the Lohner step as in
taylor.py.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from math import comb

from flint import arb, arb_mat, arb_series, fmpq

from ..core.tolerances import PROOF_STEP_TOL
from . import ball, taylor


@lru_cache(maxsize=64)
def _shift_matrix_cached(L: int, m: int, prec: int) -> arb_mat:
    """B (L x m): B[k, j] = binom(j, k) [0, 1] (j > k), 1 (j = k), 0 (j < k).  With coefficients scaled by h^j, row
    k of B times the scaled coefficients, divided by h^k, encloses the coefficient k of P(xi + sigma) for every xi in
    [0, h]: sum_j binom(j, k) c_j xi^(j-k), each xi^(j-k) in [0, h^(j-k)]."""
    u01 = U01
    B = arb_mat(L, m)
    for k in range(L):
        for j in range(k, m):
            B[k, j] = arb(comb(j, k)) * (u01 if j > k else 1)
    return B


def _shift_matrix(L: int, m: int) -> arb_mat:
    from flint import ctx

    return _shift_matrix_cached(L, m, ctx.prec)


def shifted(cols: list, h: arb, L: int) -> list:
    """For polynomials given by their coefficient lists (each of length m), the coefficients 0..L-1 of
    P(xi + sigma) in sigma, enclosed for every xi in [0, h] (one ball list per polynomial)."""
    m = len(cols[0])
    hp = [arb(1)]
    for _ in range(max(m, L)):
        hp.append(hp[-1] * h)
    C = arb_mat(m, len(cols), [cols[i][j] * hp[j] for j in range(m) for i in range(len(cols))])
    S = _shift_matrix(L, m) * C
    inv = [arb(1)]
    hi = 1 / h
    for _ in range(L):
        inv.append(inv[-1] * hi)
    return [[S[k, i] * inv[k] for k in range(L)] for i in range(len(cols))]


def _coeffs(v, length):
    return taylor._coeffs(v, length)


#: [0, 1] (as a ball; Arb's radius is rounded up, so it may hold a little more, which is safe)
U01 = ball.interval(0, 1)
#: the seed of a remainder (2^-200: far below every tail, keeps a zero tail's remainder a proper interval)
TINY = arb(0, arb(2) ** -200)


def _tail_weights(h, p, L) -> list:
    """w[k] = [0, h^(k+1)] / (k+1) for k = p .. L (index k - p)."""
    hk = ball.pow_int(h, p + 1)
    out = []
    for k in range(p, L + 1):
        out.append(U01 * hk * arb(fmpq(1, k + 1)))
        hk = hk * h
    return out


def _finite(xs) -> bool:
    return all(x.is_finite() for x in xs)


class EnclosureError(taylor.EnclosureError):
    """The Taylor-model remainder could not be validated at this step size (the caller halves h)."""


@dataclass
class TMStepData(taylor.StepData):
    """taylor.StepData (cY = I / h^(p+1), DY = I_V / h^(p+1), YV = Id, Y the box of the Taylor model over the
    step), with the remainders themselves: I (n balls) and I_V (arb_mat), valid for every t in [0, h]."""

    I: list | None = None
    IV: arb_mat | None = None


def _tail(G0: list, GL: list, w: list, p: int, L: int) -> list:
    """Tail of int_0^t (g - T_{p-1} g) over t in [0, h]: G0 the coefficients of g at 0 (k = p .. L-1 used), GL its
    coefficient L over [0, h] (Lagrange); w = _tail_weights(h, p, L)."""
    out = []
    for i in range(len(G0)):
        acc = GL[i] * w[L - p]
        for k in range(p, L):
            acc = acc + G0[i][k] * w[k - p]
        out.append(acc)
    return out


def _weighted(h: arb, p: int) -> arb:
    """[0, h / (p + 2)]: int_0^t (s/h)^(p+1) ds = (t/h)^(p+1) t / (p + 2), t in [0, h] (module docstring: the
    remainder is carried with the weight (t/h)^(p+1))."""
    return U01 * h * arb(fmpq(1, p + 2))


def _sym(x: arb, grow: arb) -> arb:
    """[-R, R] with R >= grow * max |x| (an interval symmetric about 0 holding x when grow >= 1): Arb's upper bound
    of |grow x|, a ball of midpoint 0 (Arb rounds a radius up)."""
    return arb(0, (x * grow).abs_upper())


def _inside(a, b) -> bool:
    return taylor._inside(a, b)


def step_data(fld: taylor.Field, S: taylor.C1Set, h: arb, order: int, c1: bool = True, cx=None,
              extra: int = 10) -> TMStepData:
    """The step's Taylor coefficients (as taylor.step_data), and the Taylor-model remainders I (and I_V when c1)
    validated by the Picard-Schauder test of the module docstring.  extra: L = order + extra (point coefficients
    of the tail, the Lagrange coefficient at L).  EnclosureError if the test fails (the caller halves h)."""
    n = fld.n
    p = order
    L = order + extra
    X = S.hull()
    if cx is None:
        cx, _ = taylor.solution_series(fld, ball.column(S.xbar), p)
    try:
        cX, xsX = taylor.solution_series(fld, X, p)
        # Df o P_c: to p - 1 for D_k; for C^1 steps to L at once (the variational tail's point coefficients)
        J0 = taylor.jacobian_coefficients(fld, [arb_series(c, prec=L + 1) for c in cX] if c1 else xsX,
                                          L if c1 else p - 1)
        JX = J0[:p]
    except (ValueError, ZeroDivisionError) as err:
        raise EnclosureError(f"field not evaluable on the set: {err}") from None
    D = taylor.variational_coefficients(JX, taylor._identity(n), p)
    # f o P_c at s = 0 (coefficients p .. L-1) and about every s in [0, h] (coefficient L)
    Ppt = [arb_series(cX[i], prec=L + 1) for i in range(n)]
    sh = shifted(cX, h, L + 1)
    Psh = [arb_series(sh[i], prec=L + 1) for i in range(n)]
    try:
        G0 = [_coeffs(v, L + 1) for v in fld.rhs(Ppt, fld.pars)]
        GL = [_coeffs(v, L + 1)[L] for v in fld.rhs(Psh, fld.pars)]
    except (ValueError, ZeroDivisionError) as err:
        raise EnclosureError(f"field not evaluable over the step: {err}") from None
    if not (_finite(GL) and all(_finite(g) for g in G0)):
        raise EnclosureError("field not finite over the step")
    w = _tail_weights(h, p, L)
    tail = _tail(G0, GL, w, p, L)
    rng = [s[0] for s in sh]  # P^X([0, h])
    hh = _weighted(h, p)
    I = [_sym(t, arb(2)) + TINY for t in tail]
    ok = False
    for _ in range(6):
        Y = [a + b for a, b in zip(rng, I)]
        try:
            DfY = fld.df(Y)
        except (ValueError, ZeroDivisionError) as err:
            raise EnclosureError(f"Jacobian not evaluable on the step's box: {err}") from None
        if not _finite(ball.entries(DfY)) or not _finite(fld.f(Y)):
            raise EnclosureError("field not finite on the step's box")
        K = [t + hh * v for t, v in zip(tail, ball.column(DfY * ball.vec(I)))]
        if _inside(K, I):
            ok = True
            break
        I = [_sym(k.union(i), arb(1.5)) for k, i in zip(K, I)]
    if not ok:
        raise EnclosureError("Taylor-model remainder not validated")
    Y = [a + b for a, b in zip(rng, I)]  # every solution from X over [0, h]
    hp = ball.pow_int(h, p + 1)
    cY = [v / hp for v in I]
    IV = DY = YV = None
    if c1:
        IV = _variational_remainder(fld, J0, D, sh, I, Y, DfY, h, p, L)
        DY = IV * (1 / hp)
        YV = taylor._identity(n)
    return TMStepData(h, p, cx, cX, D, Y, cY, YV, DY, I, IV)


def _variational_remainder(fld, J0, D, sh, I, Y, DfY, h, p, L) -> arb_mat:
    """I_V of the module docstring: V(t) - sum_k D_k t^k in I_V for t in [0, h] (J0: the coefficients 0 .. L of
    Df o P_c at s = 0)."""
    n = fld.n
    try:
        Jsh = taylor.jacobian_coefficients(fld, [arb_series(c, prec=L + 1) for c in sh], L)
        dJ = fld.jacobian([arb_series([y, e], prec=2) for y, e in zip(Y, I)], fld.pars)
    except (ValueError, ZeroDivisionError) as err:
        raise EnclosureError(f"Jacobian not evaluable over the step: {err}") from None
    dA = arb_mat(n, n, [_coeffs(v, 2)[1] for v in dJ])  # contains Df(y + e) - Df(y), y, y + e in Y, e in I
    # (Df o P_c) V_poly at 0, coefficients p .. L-1; about [0, h], coefficient L (V_poly shifted like P_c)
    Dsh_cols = shifted([[D[k][a, b] for k in range(p + 1)] for a in range(n) for b in range(n)], h, L + 1)
    Dsh = [arb_mat(n, n, [Dsh_cols[e][k] for e in range(n * n)]) for k in range(L + 1)]
    zero = taylor._zero(n)

    def coeff(J, V, k):
        acc = zero
        for j in range(max(0, k - len(V) + 1), k + 1):
            acc = acc + J[j] * V[k - j]
        return acc

    w = _tail_weights(h, p, L)
    tail = coeff(Jsh, Dsh, L) * w[L - p]
    for k in range(p, L):
        tail = tail + coeff(J0, D, k) * w[k - p]
    Vr = taylor._horner_mat(D, U01 * h)  # V_poly([0, h])
    hh = _weighted(h, p)
    base = tail + (dA * Vr) * hh
    IV = arb_mat(n, n, [_sym(v, arb(2)) + TINY for v in ball.entries(base)])
    for _ in range(6):
        K = base + (DfY * IV) * hh
        if _inside(ball.entries(K), ball.entries(IV)):
            return IV
        IV = arb_mat(n, n, [_sym(k.union(i), arb(1.5)) for k, i in zip(ball.entries(K), ball.entries(IV))])
    raise EnclosureError("variational Taylor-model remainder not validated")


# --------------------------------------------------------------------------------------------------------------
# stepping and propagation (taylor.py's Lohner step on this step's data)
# --------------------------------------------------------------------------------------------------------------
def step(fld, S, h, order: int, guard=None, record=None, extra: int = 10):
    """One validated step of exact size h (taylor.step with the Taylor-model remainder)."""
    hq = ball.fraction(h)
    sd = step_data(fld, S, ball.q(hq), order, S.Wbar is not None, extra=extra)
    taylor._check_guard(guard, sd, S.t)
    S2 = taylor.apply_step(S, sd)
    if record is not None:
        record.note(S2, hq, sd, guard)
    return S2


def propagate(fld, S, t_end=None, *, order: int = 20, tol: float = PROOF_STEP_TOL, h_max: float = 1.0, steps=None,
              guard=None, record=None, extra: int = 10, rem_factor: float = 1e3):
    """taylor.propagate with the Taylor-model remainder: to the exact dyadic t_end with adaptive dyadic steps, or
    by the given exact `steps`.  Adaptive steps are also halved while the validated remainder exceeds rem_factor *
    tol (a valid but loose remainder, e.g. a step near a singularity of f o P_c in complex time: step control
    only, the remainder is rigorous either way; the replay of given steps does not use it)."""
    c1 = S.Wbar is not None
    if steps is not None:
        for h in steps:
            S = step(fld, S, h, order, guard, record, extra)
        return S
    t_end = ball.fraction(t_end)
    if t_end.denominator & (t_end.denominator - 1):
        raise ValueError(f"t_end must be a dyadic rational (exact in binary), got {t_end}")
    while S.t < t_end:
        cx, _ = taylor.solution_series(fld, ball.column(S.xbar), order)
        h = taylor.dyadic_floor(taylor.step_size(cx, order, tol, h_max))
        if S.t + h > t_end:
            h = t_end - S.t
        for _ in range(30):
            try:
                sd = step_data(fld, S, ball.q(h), order, c1, cx=cx, extra=extra)
                if max(float(v.rad()) for v in sd.I) > rem_factor * tol:
                    raise EnclosureError("remainder above rem_factor * tol")
                taylor._check_guard(guard, sd, S.t)
                break
            except (taylor.EnclosureError, taylor.GuardError):
                h = h / 2
        else:
            raise EnclosureError(f"no step validated at t = {float(S.t)}")
        S = taylor.apply_step(S, sd)
        if record is not None:
            record.note(S, h, sd, guard)
    return S


def _value(S, sd: TMStepData, t: arb) -> list:
    """Phi_t(S) for a ball time t in [0, h]: T_p(t, xbar) + I + DT_p(t) (C r0 + B r)."""
    z = [taylor._horner(c, t) + e for c, e in zip(sd.cx, sd.I)]
    A = taylor._horner_mat(sd.D, t)
    return [a + b for a, b in zip(z, ball.column((A * S.C) * S.r0 + (A * S.B) * S.r))]


def cross_section(fld, S, g, dg, h, order: int, newton: int = 4, guard=None, extra: int = 10):
    """taylor.cross_section with the Taylor-model remainder (the same checks: opposite definite signs of g on the
    set and after the step, grad g . f excluding 0 over the step's box, interval Newton for the time)."""
    c1 = S.Wbar is not None
    hf = ball.fraction(h)
    sd = step_data(fld, S, ball.q(hf), order, c1, extra=extra)
    taylor._check_guard(guard, sd, S.t)
    g0 = g(S.hull())
    if not ball.excludes_zero(g0):
        raise taylor.CrossingError(f"g on the set at t = {float(S.t):.6g} contains 0 ({g0})")
    gdot = sum((a * b for a, b in zip(dg(sd.Y), fld.f(sd.Y))), arb(0))
    if not ball.excludes_zero(gdot):
        raise taylor.CrossingError(f"g' over the crossing step contains 0 ({gdot}): the crossing is not transversal")
    g1 = g(_value(S, sd, ball.q(hf)))
    positive0 = ball.positive(g0)
    if not (ball.negative(g1) if positive0 else ball.positive(g1)):
        raise taylor.CrossingError(f"g does not change sign over the step ({g0} -> {g1})")
    T = ball.interval(0, hf)
    for _ in range(newton):
        sm = T.mid()
        N = sm - g(_value(S, sd, sm)) / gdot
        T = taylor._intersect(T, N)
        if T is None:
            raise taylor.CrossingError("interval Newton for the crossing time returned an empty set")
    x = _value(S, sd, T)
    W = None
    if c1:
        A = taylor._horner_mat(sd.D, T) + sd.IV
        W = A * S.Wbar + (A * S.B) * S.E
    return taylor.CrossingEnclosure(S.t, hf, T, x, W, fld.f(x), gdot)
