"""A validated C^1 Taylor integrator in ball arithmetic (python-flint `arb`), with Lohner's QR wrapping control.

Problem.  x' = f(x) analytic, f given as ball-evaluable source (generated/validated.py, printed from SymPy by
derive/codegen.BallPrinter).  A *C^1 set* at time t is

    X = { xbar + B r : r in [r] },     DPhi_t(x0) in { Wbar + B E : E in [E] }   for every x0 of the initial set,

with xbar (n), B, Wbar (n x n) exact point data and [r] (n), [E] (n x n) interval data (Lohner's
parallelepiped-times-box form; the same orthogonal-ish B carries the wrapping of the state and of the
derivative, since both are pushed forward by the same Jacobians).

One step of size h (exact dyadic):
  1. Taylor coefficients x^[k](x) of the solution through x, k <= p, by Picard iteration on Arb power series
     (`arb_series`): x^(j+1)(t) = x + int_0^t f(x^(j)), each iteration fixes one more coefficient; Arb's series
     arithmetic (products, sin, cos, sqrt, division) is rigorous, so the balls contain the exact coefficients of
     every solution starting in the input ball.  Nothing here is a hand-written recurrence.  Or (Field.series
     "newton", _newton_series) by Newton's iteration on power series, doubling the correct coefficients per
     evaluation of f and Df (the same enclosure argument; ~1/3 of Picard's cost at order 20).
  2. Jacobian coefficients D_k(X) = d x^[k] / d x over the box X: Taylor coefficients of Df(x(t)) (the generated
     Jacobian on the same series) and the variational recursion D_{k+1} = (1/(k+1)) sum_j J_j D_{k-j}, D_0 = I.
  3. A priori enclosure (Nedialkov, Jackson & Pryce 2001, "high-order enclosure"): if
        sum_{k<=p} x^[k](X) [0,h]^k + x^[p+1](Y) [0,h]^{p+1}  is inside  Y,
     every solution from X exists on [0, h] and stays in Y.  The same test on the variational system
     (D_k and D_{p+1}(Y) Y_V) gives the enclosure Y_V of DPhi_s, s in [0, h].
  4. Lagrange remainders x^[p+1](Y) h^{p+1} and D_{p+1}(Y) Y_V h^{p+1}; the step's Jacobian enclosure
     A = sum_{k<=p} D_k(X) h^k + D_{p+1}(Y) Y_V h^{p+1} contains DPhi_h(x) for every x in X.
  5. Mean value form and Lohner's QR: Phi_h(x) in T_p(h, xbar) + R + A B [r]; the new B is the Q factor of
     mid(A B) with its columns ordered by their extent, so the parallelepiped follows the flow's rotation
     (the wrapping effect would otherwise blow up the saddle-focus spiral by e^(h ||A||) per step).
     DPhi_{t+h} in A Wbar + (A B) [E], re-expressed in the new B.

Section crossing (`cross_section`): the last step brackets the zero of one coordinate g = x_k (sign definite at
both ends, g' = f_k over the a-priori enclosure excludes 0 -> exactly one crossing per trajectory), an interval
Newton iteration encloses the crossing time, and the state and DPhi are evaluated on the Taylor polynomial at
that interval time.

Cost: one step of the 4-D chart at order 20 is ~10 ms (Arb series in C; Python only loops over operations).
References: R. J. Lohner, Einschliessung der Loesung gewoehnlicher Anfangs- und Randwertaufgaben (1988);
P. Zgliczynski, C^1 Lohner algorithm, Found. Comput. Math. 2 (2002) 429-465; N. S. Nedialkov, K. R. Jackson,
J. D. Pryce, Reliable Computing 7 (2001) 449-465.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
from flint import arb, arb_mat, arb_series, fmpq

from ..core.tolerances import PROOF_STEP_TOL
from . import ball

# --------------------------------------------------------------------------------------------------------------
# vector fields
# --------------------------------------------------------------------------------------------------------------


@dataclass
class Field:
    """A ball-evaluable vector field: rhs(x, p) -> n values, jacobian(x, p) -> n*n values (row-major), both
    accepting arb and arb_series entries; `pars` are the parameters as balls (exact rationals)."""

    rhs: object
    jacobian: object
    n: int
    pars: tuple = ()
    name: str = "field"
    series: str = "picard"  # how solution_series computes the Taylor coefficients: "picard" or "newton"

    def f(self, x):
        return [_ball(v) for v in self.rhs(list(x), self.pars)]

    def df(self, x) -> arb_mat:
        return arb_mat(self.n, self.n, [_ball(v) for v in self.jacobian(list(x), self.pars)])


def _ball(v):
    return v if isinstance(v, arb) else arb(v)


def linear_field(A, name="linear") -> Field:
    """x' = A x for an exact (rational) matrix A: the test problem with a closed-form flow."""
    Aq = [[ball.q(a) for a in row] for row in A]
    n = len(Aq)

    def rhs(x, p):
        return [sum((Aq[i][j] * x[j] for j in range(n) if Aq[i][j] != 0), arb(0) * x[0]) for i in range(n)]

    def jac(x, p):
        return [Aq[i][j] for i in range(n) for j in range(n)]

    return Field(rhs, jac, n, (), name)


# --------------------------------------------------------------------------------------------------------------
# Taylor coefficients
# --------------------------------------------------------------------------------------------------------------
def _series(v, length):
    if isinstance(v, arb_series):
        return arb_series(v, prec=length)
    return arb_series([_ball(v)], prec=length)


def _coeffs(s, length):
    c = list(s.coeffs()) if isinstance(s, arb_series) else [_ball(s)]
    c = c[:length]
    return c + [arb(0)] * (length - len(c))


def solution_series(fld: Field, x0, order: int):
    """The Taylor coefficients x^[0..order] of the solutions through every x in the ball vector x0, as n lists,
    and the solution as n arb_series of length order + 1 (for the Jacobian series).  fld.series "picard": one
    coefficient per Picard iteration (order evaluations of f, on series of length 1 .. order); "newton":
    _newton_series (4 evaluations of f and of Df at order 20, ~1/3 of the cost; other balls, as rigorous)."""
    if fld.series == "newton":
        return _newton_series(fld, x0, order)
    if fld.series != "picard":
        raise ValueError(f"series must be 'picard' or 'newton', got {fld.series!r}")
    x0 = [_ball(v) for v in x0]
    xs = [_series(v, 1) for v in x0]
    for k in range(1, order + 1):
        fk = fld.rhs(xs, fld.pars)  # xs has length k here: _series(s, k) of it would be a copy
        xs = [_series(x0[i] + _series(fk[i], k).integral(), k + 1) for i in range(fld.n)]
    return [_coeffs(s, order + 1) for s in xs], xs


def _newton_series(fld: Field, x0, order: int):
    """solution_series by Newton's iteration on power series: if x_m = x mod t^m (m coefficients correct), the
    solution is x = x_m + d, d = O(t^m), and x' = f(x) gives, exactly for every solution through a point of x0,
        d' = (f(x_m) - x_m') + Df(x_m) d + O(t^(2m)),
    so with r = f(x_m) mod t^(2m) (x_m' has degree m - 2) and J_i the coefficients of Df(x_m) mod t^m
        j d_j = r_(j-1) + sum_(i=0)^(j-1-m) J_i d_(j-1-i),   j = m .. 2m,
    i.e. x mod t^(2m+1).  Each ball operation encloses its result for every point of its operands, so the balls
    contain the exact coefficients of every solution starting in x0 (as Picard's do).  From m = 1: lengths
    1 -> 3 -> 7 -> 15 -> 31, capped at order + 1."""
    n = fld.n
    x0 = [_ball(v) for v in x0]
    cs = [[v] for v in x0]  # cs[i][j]: coefficient j of x_i, j < m
    m = 1
    while m < order + 1:
        M = min(2 * m + 1, order + 1)  # coefficients 0 .. M-1 after this pass
        xm = [arb_series(c, prec=M - 1) for c in cs]  # x_m as a series of length M - 1 (f to t^(M-2))
        fr = fld.rhs(xm, fld.pars)
        r = [_coeffs(v if isinstance(v, arb_series) else _ball(v), M - 1) for v in fr]
        nj = M - 1 - m  # J mod t^nj suffices: J_i d_(j-1-i) with j - 1 - i >= m, j <= M - 1
        if nj > 0:
            Jx = fld.jacobian([arb_series(c, prec=nj) for c in cs], fld.pars)
            Jc = [_coeffs(v if isinstance(v, arb_series) else _ball(v), nj) for v in Jx]
            J = [arb_mat(n, n, [Jc[e][i] for e in range(n * n)]) for i in range(nj)]
        d = {}
        for j in range(m, M):
            acc = arb_mat(n, 1, [r[i][j - 1] for i in range(n)])
            for i in range(0, j - m):
                acc = acc + J[i] * d[j - 1 - i]
            d[j] = acc * arb(fmpq(1, j))
        for i in range(n):
            cs[i].extend(d[j][i, 0] for j in range(m, M))
        m = M
    xs = [arb_series(c, prec=order + 1) for c in cs]
    return [list(c) for c in cs], xs


def jacobian_coefficients(fld: Field, xs, order: int) -> list:
    """[J_0, ..., J_order] (arb_mat n x n): Taylor coefficients of Df(x(t)) along the series xs (length > order)."""
    n = fld.n
    J = fld.jacobian([_series(s, order + 1) for s in xs], fld.pars)
    cs = [_coeffs(e, order + 1) for e in J]
    return [arb_mat(n, n, [cs[e][k] for e in range(n * n)]) for k in range(order + 1)]


def variational_coefficients(Js: list, V0: arb_mat, order: int) -> list:
    """[V_0 .. V_order] of V' = Df(x(t)) V, V(0) = V0, from the coefficients Js of Df(x(t)) (len >= order)."""
    V = [V0]
    for k in range(order):
        acc = Js[0] * V[k]
        for j in range(1, k + 1):
            acc = acc + Js[j] * V[k - j]
        V.append(acc * arb(fmpq(1, k + 1)))  # = ball.q(Fraction(1, k + 1)), without the Fraction
    return V


def _identity(n) -> arb_mat:
    return arb_mat(n, n, [arb(1) if i == j else arb(0) for i in range(n) for j in range(n)])


def _zero(n, m=None) -> arb_mat:
    return arb_mat(n, m or n, [arb(0)] * (n * (m or n)))


def _horner(cs, t):
    acc = cs[-1]
    for c in reversed(cs[:-1]):
        acc = acc * t + c
    return acc


def _horner_mat(Ms, t):
    acc = Ms[-1]
    for M in reversed(Ms[:-1]):
        acc = acc * t + M
    return acc


def _unit_powers(h: arb, k: int) -> arb:
    """[0, h^k] as a ball (the range of s^k over s in [0, h])."""
    hk = ball.pow_int(h, k)
    return ball.interval(0, 1) * hk


# --------------------------------------------------------------------------------------------------------------
# C^1 sets
# --------------------------------------------------------------------------------------------------------------
@dataclass
class C1Set:
    """A doubleton C^1 set (module docstring): x in xbar + C [r0] + B [r] and DPhi_t in Wbar + B [E]; t exact.
    C [r0] carries the initial set as a linear image (never re-wrapped), B [r] the accumulated local errors
    (Lohner's QR); xbar, C, B, Wbar are exact point data."""

    t: Fraction
    xbar: arb_mat  # n x 1, exact
    C: arb_mat  # n x n, exact
    r0: arb_mat  # n x 1, intervals (the initial set, in the coordinates C)
    B: arb_mat  # n x n, exact
    r: arb_mat  # n x 1, intervals
    Wbar: arb_mat | None = None  # n x n exact
    E: arb_mat | None = None  # n x n intervals

    @property
    def n(self) -> int:
        return self.xbar.nrows()

    def hull(self) -> list:
        return ball.column(self.xbar + self.C * self.r0 + self.B * self.r)

    def W(self) -> arb_mat | None:
        return None if self.Wbar is None else self.Wbar + self.B * self.E

    def widths(self) -> list[float]:
        return [ball.width(v) for v in self.hull()]


def initial_set(center, B=None, radii=None, c1: bool = True, t=Fraction(0)) -> C1Set:
    """The set center + B [-radii, radii] (B = I by default; radii are exact numbers or balls); center may be
    balls (their radii go into the error part).  DPhi_0 = I exactly when c1."""
    center = [_ball(v) for v in center]
    n = len(center)
    C = _identity(n) if B is None else B
    xbar = ball.vec([v.mid() for v in center])
    r = _identity(n) * ball.vec([v - v.mid() for v in center])
    r0 = ball.vec([arb(0)] * n)
    if radii is not None:
        r0 = ball.vec([ball.interval(-ball.fraction(x), ball.fraction(x)) if not isinstance(x, arb) else x
                       for x in radii])
    W = E = None
    if c1:
        W, E = _identity(n), _zero(n)
    return C1Set(Fraction(t), xbar, C, r0, _identity(n), r, W, E)


@dataclass
class StepData:
    """Everything one step computed on a set (reused by the crossing): point and box coefficients, Jacobian
    coefficients over the box, the a priori enclosures and the order-(p+1) data on them."""

    h: arb
    order: int
    cx: list  # point coefficients at xbar, n lists
    cX: list  # box coefficients on the hull
    D: list  # D_0..D_p over the hull
    Y: list  # a priori enclosure of x on [0, h]
    cY: list  # x^[p+1](Y)
    YV: arb_mat | None  # a priori enclosure of DPhi_s, s in [0, h]
    DY: arb_mat | None  # D_{p+1}(Y)


class EnclosureError(RuntimeError):
    """The a priori enclosure could not be validated at this step size (the caller halves h)."""


def _inflate(xs, rel=Fraction(1, 8), abs_=Fraction(1, 10**30)):
    out = []
    for v in xs:
        m, r = ball.mid_rad(v)
        rr = r * (1 + rel) + abs_ + abs(m) * Fraction(1, 10**25)
        out.append(ball.interval(m - rr, m + rr))
    return out


def _inflate_mat(M: arb_mat, rel=Fraction(1, 8), abs_=Fraction(1, 10**30)) -> arb_mat:
    return arb_mat(M.nrows(), M.ncols(), _inflate(ball.entries(M), rel, abs_))


def _inside(a, b) -> bool:
    """every ball of a is in the interior of the corresponding ball of b (exact).  Finite balls: Arb's
    arb_contains_interior (the sign of an exact arf sum: the same decision as comparing ball.bounds in rationals,
    without building Fractions -- tests/test_proof_taylor.py compares the two); non-finite balls: ball.bounds."""
    for x, y in zip(a, b):
        if x.is_finite() and y.is_finite():
            if not y.contains_interior(x):
                return False
            continue
        lo, hi = ball.bounds(x)
        ylo, yhi = ball.bounds(y)
        if not (ylo < lo and hi < yhi):
            return False
    return True


def step_data(fld: Field, S: C1Set, h: arb, order: int, c1: bool = True, cx=None) -> StepData:
    """Steps 1-4 of the module docstring for the set S and step h; EnclosureError if the a priori enclosure
    fails (5 refinements)."""
    n = fld.n
    X = S.hull()
    if cx is None:
        cx, _ = solution_series(fld, ball.column(S.xbar), order)
    cX, xsX = solution_series(fld, X, order)
    JX = jacobian_coefficients(fld, xsX, order - 1)
    D = variational_coefficients(JX, _identity(n), order)
    u01 = ball.interval(0, 1)
    up = [None] + [u01 * ball.pow_int(h, k) for k in range(1, order + 2)]  # _unit_powers(h, k), once per step
    P = [sum((cX[i][k] * up[k] for k in range(1, order + 1)), cX[i][0]) for i in range(n)]
    PV = D[0]
    for k in range(1, order + 1):
        PV = PV + D[k] * up[k]
    hp = up[order + 1]
    Y = _inflate(P, Fraction(1, 2), Fraction(1, 10**20))
    YV = _inflate_mat(PV, Fraction(1, 2), Fraction(1, 10**20)) if c1 else None
    for _ in range(6):
        try:
            cY_all, xsY = solution_series(fld, Y, order + 1)
        except (ValueError, ZeroDivisionError) as err:  # e.g. a divisor (sin theta) that contains 0 on Y
            raise EnclosureError(f"field not evaluable on the trial enclosure: {err}") from None
        cY = [c[order + 1] for c in cY_all]
        cand = [P[i] + cY[i] * hp for i in range(n)]
        DY = candV = None
        okV = True
        if c1:
            try:
                JY = jacobian_coefficients(fld, xsY, order)
            except (ValueError, ZeroDivisionError) as err:
                raise EnclosureError(f"Jacobian not evaluable on the trial enclosure: {err}") from None
            DY = variational_coefficients(JY, _identity(n), order + 1)[order + 1]
            candV = PV + DY * YV * hp
            okV = _inside(ball.entries(candV), ball.entries(YV))
        if _inside(cand, Y) and okV:
            # the candidate is itself an enclosure: x(s) = sum_k x^[k] s^k + x^[p+1](x(xi)) s^(p+1), x(xi) in Y
            return StepData(h, order, cx, cX, D, cand, cY, candV if c1 else None, DY)
        Y = _inflate([a.union(b) for a, b in zip(cand, Y)], Fraction(1, 4), Fraction(1, 10**20))
        if c1:
            YV = _inflate_mat(arb_mat(n, n, [a.union(b) for a, b in zip(ball.entries(candV), ball.entries(YV))]),
                              Fraction(1, 4), Fraction(1, 10**20))
    raise EnclosureError("a priori enclosure not validated")


def _step_matrix(sd: StepData, t: arb, c1: bool) -> arb_mat:
    """sum_k D_k t^k (+ D_{p+1}(Y) Y_V t^{p+1} when c1): DT_p, resp. DPhi_t, for t in [0, h] (t a ball)."""
    A = _horner_mat(sd.D, t)
    if c1:
        A = A + sd.DY * sd.YV * ball.pow_int(t, sd.order + 1)
    return A


def _point_value(sd: StepData, t: arb) -> list:
    """T_p(t, xbar) + x^[p+1](Y) t^{p+1}: the centre trajectory at time t in [0, h]."""
    tp = ball.pow_int(t, sd.order + 1)
    return [_horner(c, t) + sd.cY[i] * tp for i, c in enumerate(sd.cx)]


def _qr_basis(M: np.ndarray, extents: np.ndarray) -> np.ndarray:
    """Lohner's choice: Q of the QR factorisation of M with columns sorted by decreasing extent |M_j| w_j."""
    ext = np.linalg.norm(M, axis=0) * extents
    order = np.argsort(-ext, kind="stable")
    Q, R = np.linalg.qr(M[:, order])
    Q = Q * np.sign(np.where(np.diag(R) == 0, 1.0, np.diag(R)))
    return Q


def apply_step(S: C1Set, sd: StepData, t: arb | None = None, c1: bool | None = None, new_t=None) -> C1Set:
    """Step 5: the set at time S.t + t (t = h by default) in Lohner form."""
    c1 = (S.Wbar is not None) if c1 is None else c1
    t = sd.h if t is None else t
    n = S.n
    z = _point_value(sd, t)
    A = _step_matrix(sd, t, False)  # DT_p: the remainder is in z
    AC = A * S.C
    Cn = AC.mid()
    AB = A * S.B
    xbar = ball.vec([v.mid() for v in z])
    ext = np.array([max(ball.width(S.r[i, 0]), 1e-300) for i in range(n)])
    Q = _qr_basis(ball.to_floats(AB.mid()), ext)
    Bn = ball.exact_matrix(Q.tolist())
    Bi = Bn.inv()
    r = Bi * (ball.vec([v - v.mid() for v in z]) + (AC - Cn) * S.r0) + (Bi * AB) * S.r
    W = E = None
    if c1 and S.Wbar is not None:
        Af = _step_matrix(sd, t, True)  # contains DPhi_t(x) for every x of the hull
        AW = Af * S.Wbar
        W = AW.mid()
        E = Bi * (AW - W) + (Bi * (Af * S.B)) * S.E
    tt = S.t + (ball.fraction(t) if new_t is None else new_t)
    return C1Set(tt, xbar, Cn, S.r0, Bn, r, W, E)


def step_size(cx, order: int, tol: float, h_max: float) -> float:
    """Jorba-Zou style: h = min_k (tol / max_i |x_i^[k]|)^(1/k) over the last two orders, times 0.8."""
    hs = [h_max]
    for k in (order - 1, order):
        a = max(abs(float(c[k].mid())) + float(c[k].rad()) for c in cx)
        if a > 0:
            hs.append((tol / a) ** (1.0 / k))
    return 0.8 * min(hs)


def dyadic_floor(h: float, bits: int = 20) -> Fraction:
    """h rounded down to a dyadic rational with `bits` significant bits (exact step sizes for certificates)."""
    e = math.floor(math.log2(h)) - bits + 1
    return Fraction(math.floor(h / 2.0**e)) * Fraction(2) ** e


@dataclass
class Trajectory:
    """Validated propagation record: exact step sizes, times, the max width of the state enclosure after each
    step, and the smallest lower bound of each guard over the a priori enclosures."""

    steps: list = field(default_factory=list)  # Fractions
    times: list = field(default_factory=list)
    widths: list = field(default_factory=list)
    guard_min: list | None = None

    def note(self, S: C1Set, h: Fraction, sd: StepData, guard):
        self.steps.append(h)
        self.times.append(S.t)
        self.widths.append(max(S.widths()))
        if guard is not None:
            lows = [ball.bounds(v)[0] for v in guard(sd.Y)]
            self.guard_min = lows if self.guard_min is None else [min(a, b) for a, b in zip(self.guard_min, lows)]


class GuardError(RuntimeError):
    """A guard (a quantity that must stay positive along the trajectory, e.g. sin^2 theta) is not positive on
    the a priori enclosure of a step."""


def _check_guard(guard, sd: StepData, t):
    if guard is None:
        return
    for i, v in enumerate(guard(sd.Y)):
        if not ball.positive(v):
            raise GuardError(f"guard {i} not positive over the step at t = {float(t):.6g}: {v}")


def step(fld: Field, S: C1Set, h, order: int, guard=None, record: Trajectory | None = None) -> C1Set:
    """One validated step of exact size h; EnclosureError if the a priori enclosure fails, GuardError if a
    guard is not positive on it."""
    hq = ball.fraction(h)
    sd = step_data(fld, S, ball.q(hq), order, S.Wbar is not None)
    _check_guard(guard, sd, S.t)
    S2 = apply_step(S, sd)
    if record is not None:
        record.note(S2, hq, sd, guard)
    return S2


def propagate(fld: Field, S: C1Set, t_end=None, *, order: int = 20, tol: float = PROOF_STEP_TOL, h_max: float = 1.0,
              steps=None, guard=None, record: Trajectory | None = None) -> C1Set:
    """Propagate S to the exact dyadic time t_end with adaptive dyadic steps, or by the given exact `steps`
    (how a verifier replays a certificate).  `guard(Y)` -> balls that must be > 0 on every a priori enclosure.
    The steps taken go to `record`."""
    c1 = S.Wbar is not None
    if steps is not None:
        for h in steps:
            S = step(fld, S, h, order, guard, record)
        return S
    t_end = ball.fraction(t_end)
    if t_end.denominator & (t_end.denominator - 1):
        raise ValueError(f"t_end must be a dyadic rational (exact in binary), got {t_end}")
    while S.t < t_end:
        cx, _ = solution_series(fld, ball.column(S.xbar), order)
        h = dyadic_floor(step_size(cx, order, tol, h_max))
        if S.t + h > t_end:
            h = t_end - S.t
        for _ in range(30):
            try:
                sd = step_data(fld, S, ball.q(h), order, c1, cx=cx)
                _check_guard(guard, sd, S.t)
                break
            except (EnclosureError, GuardError):
                h = h / 2
        else:
            raise EnclosureError(f"no step validated at t = {float(S.t)}")
        S = apply_step(S, sd)
        if record is not None:
            record.note(S, h, sd, guard)
    return S


# --------------------------------------------------------------------------------------------------------------
# crossing a section {g = 0}
# --------------------------------------------------------------------------------------------------------------
@dataclass
class CrossingEnclosure:
    """The crossing of {g = 0} by every trajectory of a set, enclosed (the rigorous counterpart of
    magrod.orbits.shooting.Crossing, the one floating-point crossing record): time enclosure tau relative to the
    set's time t0, state enclosure x (n balls), DPhi enclosure W (arb_mat; None for a C^0 set), f at x, and
    gdot = grad g . f over the step's a priori enclosure (excludes 0)."""

    t0: Fraction
    h: Fraction
    tau: arb
    x: list
    W: arb_mat | None
    fx: list
    gdot: arb


class CrossingError(RuntimeError):
    pass


def cross_section(fld: Field, S: C1Set, g, dg, h, order: int, newton: int = 4, guard=None) -> CrossingEnclosure:
    """Every trajectory of S crosses {g = 0} exactly once in (0, h), with g(x) -> ball, dg(x) -> gradient (n
    balls).  Checked: g on the set and at S.t + h of opposite definite signs, and grad g . f over the step's a
    priori enclosure excludes 0 (so g is strictly monotone along each trajectory: one transversal crossing).  The
    crossing time by interval Newton (tau = s - G(s)/G'(xi), G' in gdot); the state and DPhi on the Taylor
    polynomial at that interval time."""
    c1 = S.Wbar is not None
    hf = ball.fraction(h)
    sd = step_data(fld, S, ball.q(hf), order, c1)
    _check_guard(guard, sd, S.t)
    g0 = g(S.hull())
    if not ball.excludes_zero(g0):
        raise CrossingError(f"g on the set at t = {float(S.t):.6g} contains 0 ({g0})")
    gdot = sum((a * b for a, b in zip(dg(sd.Y), fld.f(sd.Y))), arb(0))
    if not ball.excludes_zero(gdot):
        raise CrossingError(f"g' over the crossing step contains 0 ({gdot}): the crossing is not transversal")
    g1 = g(apply_step(S, sd, c1=False).hull())
    positive0 = ball.positive(g0)
    if not (ball.negative(g1) if positive0 else ball.positive(g1)):
        raise CrossingError(f"g does not change sign over the step ({g0} -> {g1})")
    T = ball.interval(0, hf)
    for _ in range(newton):
        sm = T.mid()
        N = sm - g(_lohner_value(S, sd, sm)) / gdot
        T = _intersect(T, N)
        if T is None:
            raise CrossingError("interval Newton for the crossing time returned an empty set")
    x = _lohner_value(S, sd, T)
    W = None
    if c1:
        A = _step_matrix(sd, T, True)
        W = A * S.Wbar + (A * S.B) * S.E
    return CrossingEnclosure(S.t, hf, T, x, W, fld.f(x), gdot)
def _lohner_value(S: C1Set, sd: StepData, t: arb) -> list:
    """Enclosure of Phi_t(S) for a (ball) time t in [0, h], as n balls: T_p(t, xbar) + R + DT_p(t) B [r]."""
    z = _point_value(sd, t)
    A = _step_matrix(sd, t, False)
    return [a + b for a, b in zip(z, ball.column((A * S.C) * S.r0 + (A * S.B) * S.r))]


def _intersect(a: arb, b: arb):
    alo, ahi = ball.bounds(a)
    blo, bhi = ball.bounds(b)
    lo, hi = max(alo, blo), min(ahi, bhi)
    if lo > hi:
        return None
    return ball.interval(lo, hi)
