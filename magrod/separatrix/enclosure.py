"""The splitting integral S of the straight rod at mu = 2 lambdabar, enclosed rigorously in ball arithmetic
(docs/nonintegrability.md, statement 2).

What S is.  At mu = 2 lambdabar (a = 2b of eq:condition_unperturbed_1) the unstable manifold of the straight rod
meets Sigma = {pbar_theta = 0} at the chart angle psi_u = lambdabar S/tan(theta_t/2) + O(lambdabar^2), with

    S = Int_0^inf N dt,   N = s (cos Psi Im G/s - sin Psi Re G/s)

along the lambdabar = 0 homoclinic orbit (derive/splitting.py: report entries splitting_leading_term,
splitting_phase_closed_form, splitting_integrand_ball).  Everything in N is a closed form: s = sin(theta0/2) =
A sech(kappa t)/sqrt(1 - omega tanh^2(kappa t)) and the phase Psi(t) = t/2 + B atan(rho tanh(kappa t)), so S is a
single integral of an explicit analytic function.

Method.  S = I + R with I = Int_0^T N dt and the tail R = Int_T^inf N dt.
  * I: python-flint's acb.integral (Petras' adaptive Gauss-Legendre with rigorous error bounds; Arb, Johansson
    2018) of the generated ball code generated/splitting_ball.py (BallPrinter: exact rationals only).  acb.integral
    needs the integrand to be analytic on the complex balls it evaluates: before each such evaluation the
    generated `branch_arguments` (every t-dependent sqrt and atan argument, read off the SymPy tree) are checked
    (Re > 0 for sqrt, |Im| < 1 for atan) and a non-finite ball is returned otherwise; poles of tanh and 1/cosh give
    non-finite balls by themselves.
  * R: for t >= T, |N| <= s (|Re G/s| + |Im G/s|), and on t >= T (symbolic facts of splitting_integrand_ball):
    s in [0, s(T)], c in [c(T), 1], tanh in [tanh(kappa T), 1], D in [1 - omega, 1], so M = the ball value of
    |Re G/s| + |Im G/s| on these ranges bounds the bracket, and Int_T^inf s dt <= 2 A atan(exp(-kappa T))/(kappa
    sqrt(1 - omega)).  |R| <= M times that.  T is increased until this bound is below `tail_tol`.
Every rounding is in Arb's balls; the inputs are exact rationals (`exact`), so the ball contains the exact S of the
stated (m, gamma, delta): a computer-verified statement.

The parameter-box theorem (`box_theorem`).  For a box B = [m] x [gamma] x [delta]:
  * N is affine in delta (symbolic, splitting_integrand_ball), so S(m, gamma, .) is affine and its range over
    [delta] is the hull of its values at the two delta end points;
  * at a fixed delta, mean value form over the (m, gamma) rectangle with centre p0: for every p in it,
    Int_0^T N(t, p) dt is in I(p0) + sum_k [-w_k, w_k] G_k, where w_k is the half width and G_k >= Int_0^T
    sup_B |dN/dp_k| dt is a Riemann upper sum of the generated gradient evaluated on (t-interval x parameter
    balls); the tail is bounded with ball-valued parameters (the same bound, valid for all p in B).
A box is decided when the resulting ball excludes 0; otherwise it is bisected (the direction that contributes the
most width) down to `min_width`, and what is left is reported as undecided.  Where S changes sign along delta at
the centre of an undecided box, the zero delta*(m0, gamma0) is located (affine: one ball division) and reported.

The second-order form (`box_theorem(order=2)`).  Next to m_c, |S| ~ 1e-4 is a small remainder of an
oscillating integrand while Int |dN/dp| ~ 70, so the mean value form needs half-widths ~1e-6.  Instead, on each
rectangle and delta end: I(p0 + h) = I(p0) + grad I(p0).h + (1/2) h^T Hess I(p0 + xi h) h (I cut at a tau_T fixed
for the rectangle), with I(p0) and grad I(p0) point values by acb.integral of the integrand and of the generated
gradient (so the cancellation is kept), and the remainder bounded by Riemann upper sums of the second derivatives
of the integrand (arb_series Taylor arithmetic on tau-cells x the rectangle).  The remainder bound is still one of
Int |d^2 f| (~1e4 times the true |S''| at (2.199, 1/4, 1/4)), but it enters multiplied by w^2.

Cost: enclose_S ~0.1-0.3 s (96 bits; more where kappa is small, i.e. m near m_c); box_theorem ~0.3-1 s per box
(order=2: ~0.7 s).
References: F. Johansson, "Numerical integration in arbitrary-precision ball arithmetic", ICMS 2018
(acb_calc_integrate); python-flint acb.integral.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from fractions import Fraction

from flint import acb, arb, arb_series, ctx, fmpq

from ..core.errors import ParameterError
from ..core.tolerances import BOX_CENTRE_ABS_TOL, BOX_TAIL_TOL, ENCLOSURE_TAIL_TOL
from ..generated import splitting_ball as _gen

DEFAULT_PREC = 96  # bits; radius ~1e-25 at the six table points, far below the 1e-10 asked for
DEFAULT_TAIL_TOL = ENCLOSURE_TAIL_TOL  # the public default (core/tolerances.py says why)
MAX_ABS = 10**6  # inputs beyond this are refused (the model's terms go up to m^4 and 1/m^4)


# --------------------------------------------------------------------------------------------------------------
# exact inputs
# --------------------------------------------------------------------------------------------------------------
def exact(name: str, value) -> fmpq:
    """An exact rational (python-flint fmpq) from int, fractions.Fraction, flint.fmpq, a decimal/fraction string
    ('1.7', '17/10', '1e-3') or a float (converted exactly: 1.7 becomes 7656119366529843/4503599627370496).
    Raises ParameterError(name, ...) for anything else, non-finite values and |value| > 1e6."""
    if isinstance(value, bool):
        raise ParameterError(name, f"must be a number, got {value!r}")
    try:
        if isinstance(value, fmpq):
            fr = Fraction(int(value.p), int(value.q))
        elif isinstance(value, (int, Fraction)):
            fr = Fraction(value)
        elif isinstance(value, float):
            if not math.isfinite(value):
                raise ParameterError(name, f"must be finite, got {value!r}")
            fr = Fraction(value)
        elif isinstance(value, str):
            if len(value) > 200:
                raise ParameterError(name, "must be a number of at most 200 characters")
            fr = Fraction(value.strip())
        else:
            raise ParameterError(name, f"must be an int, Fraction, fmpq, decimal string or float, got "
                                       f"{type(value).__name__}")
    except (ValueError, ZeroDivisionError, OverflowError):
        raise ParameterError(name, f"must be a number, got {str(value)[:40]!r}") from None
    if abs(fr) > MAX_ABS:
        raise ParameterError(name, f"must satisfy |{name}| <= {MAX_ABS}, got {str(value)[:40]}")
    return fmpq(fr.numerator, fr.denominator)


def _check_point(m: fmpq, gamma: fmpq, delta: fmpq):
    if not m > 0:
        raise ParameterError("m", f"must be > 0, got {m}")
    if gamma < 0:
        raise ParameterError("gamma", f"must be >= 0 (gamma = 0 is the inextensible rod), got {gamma}")
    if delta < 0:
        raise ParameterError("delta", f"must be >= 0 (delta = C2/J, gamma + delta = C2/K >= 0), got {delta}")
    # m < m_c = 2 sqrt(1 + gamma) (eq:buckling_load_2), decided exactly: m^2 < 4 (1 + gamma)
    if not m * m < 4 * (1 + gamma):
        raise ParameterError("m", f"must satisfy m < m_c = 2 sqrt(1 + gamma) (m^2 < 4 (1 + gamma), "
                                  f"eq:buckling_load_2: the straight rod is a saddle only below m_c), got m = {m}, "
                                  f"gamma = {gamma}")


def _s(q: fmpq) -> str:
    return str(q)


# --------------------------------------------------------------------------------------------------------------
# ball helpers
# --------------------------------------------------------------------------------------------------------------
_NAN = None


def _nan():
    return acb(arb("nan"))


def _UNKNOWN() -> arb:
    """A ball containing every real number."""
    return arb(0, math.inf)


def _hull(a, b):
    return arb(a).union(arb(b))


def _upper(x: arb) -> float:
    """A float >= every point of the ball x (outward rounded)."""
    u = x.upper()
    return math.nextafter(float(u.mid()) + float(u.rad()), math.inf)


def _ball_to_dict(x: arb) -> dict:
    return {"mid": float(x.mid()), "rad": _upper(x.rad()), "lower": float(x.lower().mid()) if x.is_finite() else None,
            "upper": float(x.upper().mid()) if x.is_finite() else None, "ball": x.str(20, radius=True)}


def _exact(x: arb) -> Fraction:
    m, e = x.mid().man_exp()
    m, e = int(m), int(e)
    return Fraction(m * 2**e) if e >= 0 else Fraction(m, 2**-e)


def outward(x: arb, digits: int = 12) -> tuple[str, str]:
    """(lo, hi) exact decimal strings with lo <= every point of the ball x <= hi, rounded outward to `digits`
    significant digits (a float of the mid-point of x.lower() is round-to-nearest, not a bound)."""
    if not x.is_finite():
        return "-inf", "inf"
    lo, hi = _exact(x.lower()), _exact(x.upper())  # Arb rounds these outward at the working precision

    def dec(f: Fraction, up: bool) -> str:
        if f == 0:
            return "0"
        k = digits - 1 - math.floor(math.log10(abs(float(f))))
        scaled = f * Fraction(10) ** k
        n = math.ceil(scaled) if up else math.floor(scaled)
        q = Fraction(n) / Fraction(10) ** k
        assert (q >= f) if up else (q <= f)
        if q.denominator == 1:
            return str(q.numerator)
        sign, a = ("-" if q < 0 else ""), abs(q)
        ip, fp = divmod(a.numerator, a.denominator)
        places = max(k, 0)
        frac = str(fp * 10**places // a.denominator).rjust(places, "0").rstrip("0")
        return f"{sign}{ip}.{frac}" if frac else f"{sign}{ip}"

    return dec(lo, False), dec(hi, True)


def _integrand_fn(mod, m, g, d, counter, k: int = -1):
    """The integrand for acb.integral (k = -1; k >= 0: the k-th component of the generated gradient, `_component_fn`)
    with the analyticity checks: where acb.integral asks for analyticity, every t-dependent sqrt argument has a
    positive real part and every atan argument |Im| < 1 on the ball, else the value is non-finite."""
    kinds = mod.BRANCH_KINDS

    def f(t, analytic):
        counter[0] += 1
        if analytic:
            for kind, a in zip(kinds, mod.branch_arguments(t, m, g)):
                if not (a.real > 0 if kind == "sqrt" else abs(a.imag) < 1):
                    return _nan()
        return mod.integrand(t, m, g, d) if k < 0 else mod.integrand_gradient(t, m, g, d)[k]

    return f


def _tail_bound(mod, tT: fmpq, m, g, d) -> arb:
    """Ball whose upper end bounds |Int_{tau_T}^inf integrand dtau| = |Int_T^inf N dt| (m, g, d may be balls: the
    bound then holds for every point in them)."""
    s_up, c_lo, thT, one_m_om, d_up, maj = mod.tail_quantities(arb(tT), m, g)
    if not all(x.is_finite() for x in (s_up, c_lo, thT, one_m_om, d_up, maj)) or not one_m_om > 0 or not s_up < 1:
        return arb("inf")
    # narrow ranges (tail_quantities): s in [0, s_up], c in [c_lo, 1], tanh in [tanh(tau_T), 1], D in [1 - omega, D_up]
    nr, ni = mod.tail_factors(_hull(0, s_up.upper()), _hull(c_lo.lower(), 1), _hull(thT.lower(), 1),
                              _hull(one_m_om.lower(), d_up.upper()), m, g, d)
    return (abs(nr) + abs(ni)) * maj


def _choose_T(mod, m, g, d, tail_tol: float) -> tuple[fmpq, arb]:
    """The smallest tau_T = kappa T on a ladder (step 1/2 from log(1/tol)) with tail bound <= tail_tol."""
    tT = max(1.0, math.log(1.0 / tail_tol))
    for _ in range(400):
        tq = fmpq(math.ceil(tT * 2), 2)
        E = _tail_bound(mod, tq, m, g, d)
        if E.is_finite() and _upper(E) <= tail_tol:
            return tq, E
        tT += 0.5
    raise _NoCut(f"no cut with tail bound <= {tail_tol} up to tau_T = {tT:.3g} (m too close to m_c?)")


class _NoCut(ArithmeticError):
    """The tail bound cannot be met (parameter balls too wide, or kappa ~ 0): a box is then split, a point refused."""


# --------------------------------------------------------------------------------------------------------------
# S at one point
# --------------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SEnclosure:
    """Rigorous enclosure of S(m, gamma, delta) = Int_0^inf N dt (module docstring).

    Attributes
    ----------
    m, gamma, delta : str
        The exact rationals used (fmpq as 'p/q').
    S : arb
        Ball containing S: integral + [-tail_bound, tail_bound].
    integral : arb
        Ball containing Int_0^T (N/kappa) dtau = Int_0^(T/kappa) N dt (acb.integral; the imaginary part is checked to
        contain 0 and discarded).
    tail_bound : float
        Upper bound of |Int_T^inf N dt| (rigorous, outward rounded).
    T : str
        The cut in tau = kappa t (exact rational; the integral runs over 0 <= tau <= T).
    psi_coefficient : arb
        Ball containing C_psi = S/tan(theta_t/2) (psi_u = lambdabar C_psi + O(lambdabar^2)).
    sign : int or None
        -1 or +1 if the ball excludes 0, else None.
    prec, evaluations, wall_time_s
        Working precision (bits), integrand evaluations, wall time.
    """

    m: str
    gamma: str
    delta: str
    S: arb
    integral: arb
    tail_bound: float
    T: str
    psi_coefficient: arb
    sign: int | None
    prec: int
    evaluations: int
    wall_time_s: float

    @property
    def radius(self) -> float:
        return _upper(self.S.rad())

    @property
    def excludes_zero(self) -> bool:
        return self.sign is not None

    def contains(self, value, tol: float = 0.0) -> bool:
        """True if `value` (str/float/arb; strings are read exactly) lies in S widened by tol."""
        with ctx.workprec(max(self.prec, 128)):  # a decimal string is read at this precision, not at 53 bits
            v = arb(value) if not isinstance(value, arb) else value
            return (self.S + arb(0, tol)).contains(v) if tol else self.S.contains(v)

    def to_dict(self) -> dict:
        return {"m": self.m, "gamma": self.gamma, "delta": self.delta, "S": _ball_to_dict(self.S),
                "integral_0_T": _ball_to_dict(self.integral), "tail_bound": self.tail_bound, "T": self.T,
                "psi_coefficient": _ball_to_dict(self.psi_coefficient), "sign": self.sign,
                "excludes_zero": self.excludes_zero, "prec_bits": self.prec, "evaluations": self.evaluations,
                "wall_time_s": self.wall_time_s, "status": "computer-verified (ball arithmetic, all roundings and "
                                                            "the tail bounded)"}

    def __repr__(self) -> str:
        return (f"SEnclosure(m={self.m}, gamma={self.gamma}, delta={self.delta}, S={self.S.str(radius=True)}, "
                f"T={self.T}, tail<={self.tail_bound:.2e}, sign={self.sign})")


def enclose_S(m, gamma, delta, *, prec: int = DEFAULT_PREC, tail_tol: float = DEFAULT_TAIL_TOL,
              module=None) -> SEnclosure:
    """Rigorous enclosure of the splitting integral S(m, gamma, delta) of the straight rod at mu = 2 lambdabar.

    Parameters
    ----------
    m, gamma, delta : int, Fraction, fmpq, str or float
        Exact rationals (floats are converted exactly); 0 < m < m_c = 2 sqrt(1 + gamma), gamma >= 0, delta >= 0.
    prec : int, keyword-only
        Working precision in bits (53 ... 4096).
    tail_tol : float, keyword-only
        The cut T is chosen so that the rigorous tail bound is <= tail_tol (1e-30 ... 1e-3).
    module : keyword-only
        The ball code to use (default generated.splitting_ball); tests pass a mutated one.

    Returns
    -------
    SEnclosure
        The ball S = integral on [0, T] + [-tail_bound, tail_bound], both parts stated.

    Raises
    ------
    ParameterError
        Naming m, gamma, delta, prec or tail_tol.

    Examples
    --------
    >>> r = enclose_S("1.7", 1, 1)
    >>> r.sign, r.radius < 1e-10
    (-1, True)
    >>> enclose_S(2, 0, 0).sign is None   # gamma = delta = 0: integrable, S = 0
    True

    Notes
    -----
    Method: module docstring (acb.integral on [0, T] with analyticity checks; tail bound from s <= A sech/sqrt(1 -
    omega)).  Accuracy: the radius is ~2^-prec |S| plus tail_tol.  Cost ~0.1-0.3 s at 96 bits.
    """
    t0 = time.perf_counter()
    mq, gq, dq = exact("m", m), exact("gamma", gamma), exact("delta", delta)
    _check_point(mq, gq, dq)
    if isinstance(prec, bool) or not isinstance(prec, int) or not 53 <= prec <= 4096:
        raise ParameterError("prec", f"must be an integer in [53, 4096] (bits), got {prec!r}")
    try:
        tol = float(tail_tol)
    except (TypeError, ValueError):
        raise ParameterError("tail_tol", f"must be a number, got {tail_tol!r}") from None
    if not 1e-30 <= tol <= 1e-3:
        raise ParameterError("tail_tol", f"must be in [1e-30, 1e-3], got {tail_tol!r}")
    mod = _gen if module is None else module
    counter = [0]
    with ctx.workprec(prec):
        M, G, Dl = arb(mq), arb(gq), arb(dq)
        try:
            T, E = _choose_T(mod, M, G, Dl, tol)
        except _NoCut as exc:
            raise ParameterError("m", str(exc)) from None
        res = acb.integral(_integrand_fn(mod, M, G, Dl, counter), 0, arb(T))
        if not res.imag.contains(0):  # the integrand is real on the real axis: a sanity check of the code
            raise RuntimeError(f"imaginary part {res.imag} of a real integral")
        integral = res.real
        e_up = _upper(E)
        Sb = integral + arb(0, e_up)
        tan_half = mod.tan_half_turn(M, G)
        cpsi = Sb / tan_half
    sign = -1 if Sb < 0 else (1 if Sb > 0 else None)
    return SEnclosure(_s(mq), _s(gq), _s(dq), Sb, integral, e_up, _s(T), cpsi, sign, prec, counter[0],
                      time.perf_counter() - t0)


# --------------------------------------------------------------------------------------------------------------
# the parameter-box theorem
# --------------------------------------------------------------------------------------------------------------
def _interval(name: str, value) -> tuple[fmpq, fmpq]:
    try:
        lo, hi = value
    except (TypeError, ValueError):
        raise ParameterError(name, f"must be a pair (lo, hi), got {str(value)[:60]!r}") from None
    lo, hi = exact(name, lo), exact(name, hi)
    if not lo < hi:
        raise ParameterError(name, f"must be a non-empty interval lo < hi, got ({lo}, {hi})"
                                   + (" (inverted)" if lo > hi else " (empty)"))
    return lo, hi


def _check_box(mb, gb, db):
    if not mb[0] > 0:
        raise ParameterError("m", f"the box must have m > 0, got m_lo = {mb[0]}")
    if gb[0] < 0:
        raise ParameterError("gamma", f"the box must have gamma >= 0, got gamma_lo = {gb[0]}")
    if db[0] < 0:
        raise ParameterError("delta", f"the box must have delta >= 0 (gamma + delta >= 0), got delta_lo = {db[0]}")
    if not mb[1] * mb[1] < 4 * (1 + gb[0]):
        raise ParameterError("m", f"the box must lie in the saddle range m < m_c = 2 sqrt(1 + gamma): m_hi = {mb[1]} "
                                  f"but 2 sqrt(1 + gamma_lo) = {2 * math.sqrt(1 + float(gb[0])):.6g}")


def _ball(lo: fmpq, hi: fmpq) -> arb:
    return _hull(arb(lo), arb(hi))


def _tgrid(T: fmpq) -> list:
    """Cut points of [0, T] (in tau) for the Riemann upper sums (finer where the integrand is large)."""
    pts, t = [fmpq(0)], fmpq(0)
    while t < T:
        h = fmpq(1, 8) if t < 4 else (fmpq(1, 4) if t < 12 else fmpq(1, 2))
        t = min(t + h, T)
        pts.append(t)
    return pts


@dataclass
class BoxResult:
    """One box: bounds (exact, as strings), the ball of S over it, the sign if decided, and the parts."""

    m: tuple
    gamma: tuple
    delta: tuple
    S: str  # "[S_lo, S_hi]": both ends outward-rounded exact decimals (never Arb's "[+/- r]", which hides the sign)
    sign: int | None
    S_lo: str  # an exact decimal <= every value of S on the box ("-inf" if unknown)
    S_hi: str  # an exact decimal >= every value of S on the box ("inf" if unknown)
    widths: dict

    def to_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass
class BoxTheorem:
    """Result of box_theorem: decided boxes (S != 0 with its sign on each: computer-verified), undecided boxes,
    zeros located in undecided boxes, and the totals.  `statement` says what was proved."""

    m: tuple
    gamma: tuple
    delta: tuple
    decided: list
    undecided: list
    zeros: list
    signs: dict
    statement: str
    prec: int
    boxes_evaluated: int
    wall_time_s: float
    notes: list = field(default_factory=list)

    @property
    def success(self) -> bool:
        return not self.undecided

    def to_dict(self) -> dict:
        return {"m": self.m, "gamma": self.gamma, "delta": self.delta, "success": self.success,
                "statement": self.statement, "decided": [b.to_dict() for b in self.decided],
                "undecided": [b.to_dict() for b in self.undecided], "zeros": self.zeros, "signs": self.signs,
                "prec_bits": self.prec, "boxes_evaluated": self.boxes_evaluated, "wall_time_s": self.wall_time_s,
                "notes": self.notes}

    def __repr__(self) -> str:
        return (f"BoxTheorem(m={self.m}, gamma={self.gamma}, delta={self.delta}: {len(self.decided)} decided "
                f"{self.signs}, {len(self.undecided)} undecided, {len(self.zeros)} zeros, {self.wall_time_s:.1f} s)")


def _enclose_rect(mod, mb, gb, dv: fmpq, tail_tol: float, counter) -> tuple[arb, dict]:
    """Ball containing S(m, gamma, dv) for every (m, gamma) in the rectangle mb x gb (mean value form)."""
    m0, g0 = (mb[0] + mb[1]) / 2, (gb[0] + gb[1]) / 2
    wm, wg = (mb[1] - mb[0]) / 2, (gb[1] - gb[0]) / 2
    Mb, Gb, Dv = _ball(*mb), _ball(*gb), arb(dv)
    try:
        T, E = _choose_T(mod, Mb, Gb, Dv, tail_tol)
    except _NoCut:  # too wide a box for the tail bound (near m_c): undecided, split it
        # the whole real line, [+/- inf]: NOT arb("inf"), which is the point +inf and compares > 0 (a box once
        # came out "decided, S > 0" that way)
        return _UNKNOWN(), {"m": math.inf, "gamma": math.inf, "tail": math.inf, "quad": math.inf, "T": "none"}
    M0, G0 = arb(m0), arb(g0)

    # the centre value needs only a few digits more than the mean value terms it is combined with
    res = acb.integral(_integrand_fn(mod, M0, G0, Dv, counter), 0, arb(T), rel_tol=2.0**-40, abs_tol=tail_tol)
    I0 = res.real
    # Riemann upper sums of sup |dN/dm|, sup |dN/dgamma| over (t-interval x rectangle)
    pts = _tgrid(T)
    Gm, Gg = arb(0), arb(0)
    for a, b in zip(pts[:-1], pts[1:]):
        tb = _ball(a, b)
        dm, dg, _ = mod.integrand_gradient(tb, Mb, Gb, Dv)
        counter[0] += 1
        h = arb(b - a)
        Gm += h * abs(dm)
        Gg += h * abs(dg)
    wm_up, wg_up = arb(wm) * Gm, arb(wg) * Gg
    # the radius summed in Arb (rounded outward), not in floats (round-to-nearest could lose an ulp)
    ball = I0 + arb(0, _upper(arb(_upper(wm_up)) + arb(_upper(wg_up)) + arb(_upper(E))))
    return ball, {"m": _upper(wm_up), "gamma": _upper(wg_up), "tail": _upper(E), "quad": _upper(I0.rad()),
                  "T": str(T)}


# --------------------------------------------------------------------------------------------------------------
# the second-order (Taylor) form of a rectangle (for the corner next to m_c)
# --------------------------------------------------------------------------------------------------------------
def _tight_ball(lo: fmpq, hi: fmpq) -> arb:
    """A ball containing [lo, hi] with mid-point (lo + hi)/2 and radius (hi - lo)/2 rounded up (_ball's arb union is
    up to twice as wide; in the second-order remainder the width enters squared)."""
    return arb((lo + hi) / 2) + arb(0, _upper(arb((hi - lo) / 2)))


def _component_fn(mod, m, g, d, k, counter):
    """The integrand (k = -1) or the k-th component of the generated gradient d/d(m, gamma, delta) at fixed tau, with
    the analyticity checks of `_integrand_fn`.  The gradient is the derivative of the same expression tree: its
    t-dependent sqrt and atan arguments are those of `branch_arguments` (the sqrt of 1 - tanh^2 (..) gamma and of
    1 - (1/2 - ..)/(.. cosh^2), the atan of tanh sqrt(..)), and every division by a ball containing 0 is non-finite,
    so a finite value on a checked ball is a value of an analytic function there."""
    return _integrand_fn(mod, m, g, d, counter, k)


def _tgrid2(T: fmpq) -> list:
    """Cut points of [0, T] (in tau) for the Riemann upper sum of the second-order remainder: 1/32 where the integrand
    is large (tau < 8: its envelope is ~ sech tau), 1/8 beyond."""
    pts, t = [fmpq(0)], fmpq(0)
    while t < T:
        t = min(t + (fmpq(1, 32) if t < 8 else fmpq(1, 8)), T)
        pts.append(t)
    return pts


def _second_order_remainder(mod, mb, gb, dv, T: fmpq, counter) -> tuple[arb, arb, arb]:
    """(R_mm, R_mg, R_gg), balls whose upper ends bound Int_0^T sup |c| dtau for c = f_mm/2, f_mg/2, f_gg/2, the sup
    over (tau-cell x rectangle), f the integrand (tau coordinates, T fixed for the rectangle).

    Taylor's theorem on the segment p0 -> p0 + h (h = (h_m, h_g), |h_m| <= w_m, |h_g| <= w_g) gives I(p0 + h) =
    I(p0) + grad I(p0).h + (1/2) h^T Hess I(p0 + xi h) h, and |(1/2) h^T Hess f h| <= |f_mm/2| w_m^2 + 2 |f_mg/2| w_m
    w_g + |f_gg/2| w_g^2 at every point of the rectangle, so |remainder| <= R_mm w_m^2 + 2 R_mg w_m w_g + R_gg w_g^2.
    The second derivatives are the x^2 coefficients of python-flint arb_series (Taylor arithmetic, rigorous for
    ball coefficients) along the point directions (1, 0), (0, 1) and (1, 1): f_uu/2 = f_mm/2 + f_mg + f_gg/2 gives
    f_mg/2 = (c_uu - c_mm - c_gg)/2 pointwise, hence as balls.  Directions are points, not balls: a ball direction
    [-w, w] would lose every cancellation between the intermediate derivatives (measured: 1e3 w instead of 1.4e2 w
    for the first-order term at (2.199, 1/4, 1/4))."""
    Mb, Gb, Dv = _tight_ball(*mb), _tight_ball(*gb), arb(dv)
    sm, sg = arb_series([Mb, 1], prec=3), arb_series([Gb, 1], prec=3)
    pts = _tgrid2(T)
    r_mm, r_mg, r_gg = arb(0), arb(0), arb(0)
    for a, b in zip(pts[:-1], pts[1:]):
        tb = _tight_ball(a, b)
        c = []
        for mm, gg in ((sm, Gb), (Mb, sg), (sm, sg)):
            try:
                co = mod.integrand(tb, mm, gg, Dv).coeffs()
            except ValueError:  # arb_series division by a series whose leading ball contains 0: no bound here
                return _UNKNOWN(), _UNKNOWN(), _UNKNOWN()
            c.append(co[2] if len(co) > 2 else arb(0))  # arb_series drops trailing zero coefficients
        counter[0] += 3
        cmm, cgg, cuu = c
        cmg = (cuu - cmm - cgg) / 2
        h = arb(b - a)
        r_mm += h * abs(cmm)
        r_mg += h * abs(cmg)
        r_gg += h * abs(cgg)
    return r_mm, r_mg, r_gg


def _centre_terms(mod, M0, G0, Dv, T: fmpq, counter) -> tuple[arb, arb, arb]:
    """Balls containing I(p0) = Int_0^T f dtau, dI/dm(p0) and dI/dgamma(p0) at a point p0 (T fixed: the derivatives
    are those of the integral cut at tau = T, which is what the second-order form expands), each by acb.integral
    with the analyticity checks (point values, so the oscillation's cancellation is kept: |dS/dm| ~ 1e-2 at
    (2.199, 1/4, 1/4) against Int |df/dm| dtau ~ 73)."""
    # the centre terms need an absolute accuracy small against |S| >= 1e-5 on the corner (tolerances.py)
    vals = [acb.integral(_component_fn(mod, M0, G0, Dv, k, counter), 0, arb(T), rel_tol=2.0**-40,
                         abs_tol=BOX_CENTRE_ABS_TOL)
            for k in (-1, 0, 1)]
    for v in vals:
        if not v.imag.contains(0):  # real integrands on the real axis: a sanity check of the code
            raise RuntimeError(f"imaginary part {v.imag} of a real integral")
    return tuple(v.real for v in vals)


def _enclose_rect2(mod, mb, gb, dv: fmpq, tail_tol: float, counter) -> tuple[arb, dict]:
    """Ball containing S(m, gamma, dv) for every (m, gamma) in mb x gb: the second-order form
    I(p0) + [-1, 1] (|dI/dm(p0)| w_m + |dI/dgamma(p0)| w_g) + [-R2, R2] + [-tail, tail], with I(p0) and grad I(p0)
    by acb.integral at the centre (point values: the oscillation's cancellation is kept) and R2 from
    `_second_order_remainder`."""
    m0, g0 = (mb[0] + mb[1]) / 2, (gb[0] + gb[1]) / 2
    wm, wg = (mb[1] - mb[0]) / 2, (gb[1] - gb[0]) / 2
    try:
        T, E = _choose_T(mod, _tight_ball(*mb), _tight_ball(*gb), arb(dv), tail_tol)
    except _NoCut:  # as in _enclose_rect: unknown, [+/- inf], never arb("inf")
        return _UNKNOWN(), {"m": math.inf, "gamma": math.inf, "tail": math.inf, "quad": math.inf, "T": "none"}
    I0, dIm, dIg = _centre_terms(mod, arb(m0), arb(g0), arb(dv), T, counter)
    r_mm, r_mg, r_gg = _second_order_remainder(mod, mb, gb, dv, T, counter)
    Wm, Wg = arb(wm), arb(wg)
    lin_m, lin_g = abs(dIm) * Wm, abs(dIg) * Wg
    q_m, q_g, q_x = r_mm * Wm * Wm, r_gg * Wg * Wg, 2 * r_mg * Wm * Wg
    if not all(x.is_finite() for x in (I0, lin_m, lin_g, q_m, q_g, q_x)):
        return _UNKNOWN(), {"m": math.inf, "gamma": math.inf, "tail": _upper(E), "quad": math.inf, "T": str(T)}
    w_m = _upper(lin_m + q_m + q_x / 2)  # the cross term is charged half to each direction (for the bisection)
    w_g = _upper(lin_g + q_g + q_x / 2)
    ball = I0 + arb(0, _upper(arb(w_m) + arb(w_g) + arb(_upper(E))))  # summed in Arb, rounded outward
    return ball, {"m": w_m, "gamma": w_g, "tail": _upper(E), "quad": _upper(I0.rad()), "T": str(T),
                  "linear": _upper(lin_m) + _upper(lin_g), "second_order": _upper(q_m + q_g + q_x)}


def _decide(mod, mb, gb, db, tail_tol, counter, order: int = 1):
    """S over the box: hull of the rectangle enclosures at the two delta end points (S affine in delta)."""
    rect = _enclose_rect if order == 1 else _enclose_rect2
    lo_ball, w_lo = rect(mod, mb, gb, db[0], tail_tol, counter)
    hi_ball, w_hi = rect(mod, mb, gb, db[1], tail_tol, counter)
    hull = lo_ball.union(hi_ball)
    # a sign only from a finite ball: an infinite end point is no information, whatever the comparison says
    sign = None if not hull.is_finite() else (-1 if hull < 0 else (1 if hull > 0 else None))
    widths = {k: max(w_lo[k], w_hi[k]) for k in ("m", "gamma", "tail", "quad")}
    return hull, sign, widths, lo_ball, hi_ball


def box_theorem(m=("1.0", "2.2"), gamma=("0.25", "3"), delta=("0.25", "3"), *, initial=(4, 4, 1),
                min_width=1e-3, max_boxes: int = 20000, prec: int = 64, tail_tol: float = BOX_TAIL_TOL,
                progress=None, module=None, order: int = 1) -> BoxTheorem:
    """Prove S(m, gamma, delta) != 0, with its sign, on a parameter box by interval subdivision.

    Parameters
    ----------
    m, gamma, delta : pairs (lo, hi) of exact rationals (as accepted by `exact`)
        The box; it must lie in the saddle range (m_hi^2 < 4 (1 + gamma_lo)), gamma_lo >= 0, delta_lo >= 0.
    initial : (int, int, int), keyword-only
        Initial subdivision in (m, gamma, delta).
    min_width : float
        Boxes narrower than this (relative to the initial box, in every direction that still needs splitting) are
        reported as undecided instead of being bisected.
    max_boxes : int
        Guard on the number of boxes evaluated.
    prec, tail_tol
        Working precision (bits) and the tail tolerance per rectangle.
    progress : callable(int) or None
        Called with 1 per evaluated box.
    module
        The ball code (default generated.splitting_ball; tests pass a mutated one).
    order : 1 or 2, keyword-only
        1: the mean value form (Riemann upper sums of |dN/dp| on the rectangle).  2: the second-order form of
        `_enclose_rect2` (value and gradient at the centre by acb.integral, second derivatives bounded on the
        rectangle): needed next to m_c, where |S| ~ 1e-4 is a small remainder of an oscillating integrand and the
        mean value form would need ~1e10 boxes (docs/nonintegrability.md, "Why the corner resists"); ~4x the cost
        per box elsewhere.

    Returns
    -------
    BoxTheorem
        decided boxes with the sign of S on each, undecided boxes, zeros located, and the statement proved.

    Raises
    ------
    ParameterError
        Naming m, gamma or delta for empty, inverted or out-of-range boxes, or the option at fault.

    Examples
    --------
    >>> r = box_theorem(("1.6", "1.7"), ("1", "1.1"), ("1", "1.1"), initial=(1, 1, 1))
    >>> r.success, r.signs
    (True, {'-1': 1})

    Notes
    -----
    Method: module docstring (affinity in delta; mean value form in (m, gamma) with Riemann upper sums of the
    generated gradient on ball-valued parameters; rigorous tail with ball-valued parameters).  A decided box is a
    computer-verified statement "S < 0 (or > 0) for every (m, gamma, delta) in it" for the leading coefficient
    S; that it is the leading coefficient of the splitting is the formal expansion (statement 3 of
    docs/nonintegrability.md).  Cost ~0.3-1 s per box at 64 bits.
    """
    t0 = time.perf_counter()
    mb, gb, db = _interval("m", m), _interval("gamma", gamma), _interval("delta", delta)
    _check_box(mb, gb, db)
    try:
        n0 = [int(x) for x in initial]
    except (TypeError, ValueError):
        raise ParameterError("initial", f"must be three positive integers, got {initial!r}") from None
    if len(n0) != 3 or min(n0) < 1 or max(n0) > 1000:
        raise ParameterError("initial", f"must be three integers in [1, 1000], got {initial!r}")
    if isinstance(prec, bool) or not isinstance(prec, int) or not 53 <= prec <= 1024:
        raise ParameterError("prec", f"must be an integer in [53, 1024], got {prec!r}")
    if isinstance(order, bool) or order not in (1, 2):
        raise ParameterError("order", f"must be 1 (mean value form) or 2 (second-order form), got {order!r}")
    if not (isinstance(max_boxes, int) and max_boxes >= 1):
        raise ParameterError("max_boxes", f"must be a positive integer, got {max_boxes!r}")
    try:
        mw = float(min_width)
        tol = float(tail_tol)
    except (TypeError, ValueError):
        raise ParameterError("min_width", "min_width and tail_tol must be numbers") from None
    if not 0 < mw < 1:
        raise ParameterError("min_width", f"must be in (0, 1), got {min_width!r}")
    if not 1e-30 <= tol <= 1e-3:
        raise ParameterError("tail_tol", f"must be in [1e-30, 1e-3], got {tail_tol!r}")

    spans = [mb[1] - mb[0], gb[1] - gb[0], db[1] - db[0]]
    mod = _gen if module is None else module

    def split(iv, n):
        return [(iv[0] + (iv[1] - iv[0]) * i / n, iv[0] + (iv[1] - iv[0]) * (i + 1) / n) for i in range(n)]

    queue = [(a, b, c) for a in split(mb, n0[0]) for b in split(gb, n0[1]) for c in split(db, n0[2])]
    decided, undecided, zeros = [], [], []
    counter = [0]
    evaluated = 0
    with ctx.workprec(prec):
        while queue:
            if evaluated >= max_boxes:
                undecided.extend(BoxResult(tuple(map(str, a)), tuple(map(str, b)), tuple(map(str, c)), "not evaluated",
                                           None, "-inf", "inf", {}) for a, b, c in queue)
                break
            bm, bg, bd = queue.pop()
            hull, sign, widths, lo_ball, hi_ball = _decide(mod, bm, bg, bd, tol, counter, order)
            evaluated += 1
            if progress is not None:
                progress(1)
            lo_s, hi_s = outward(hull)
            rec = BoxResult(tuple(map(str, bm)), tuple(map(str, bg)), tuple(map(str, bd)), f"[{lo_s}, {hi_s}]",
                            sign, lo_s, hi_s, widths)
            if sign is not None:
                decided.append(rec)
                continue
            # S changes sign along delta at the box centre?  (affine: locate delta*)
            if (lo_ball > 0 and hi_ball < 0) or (lo_ball < 0 and hi_ball > 0):  # delta* at every (m, gamma)
                slope = (hi_ball - lo_ball) / arb(bd[1] - bd[0])
                dstar = arb(bd[0]) - lo_ball / slope
                zeros.append({"m": rec.m, "gamma": rec.gamma, "delta_star": dstar.str(radius=True),
                              "delta_star_mid": float(dstar.mid()), "delta_star_rad": _upper(dstar.rad()),
                              "note": "S changes sign along delta on this (m, gamma) rectangle: for every (m, gamma) "
                                      "in it S has a zero delta* in the ball (S affine in delta)"})
            rel = [float((bm[1] - bm[0]) / spans[0]), float((bg[1] - bg[0]) / spans[1]),
                   float((bd[1] - bd[0]) / spans[2])]
            # bisect where the width comes from: delta if both end values are decided with opposite signs (a zero
            # lies between: narrow it down), otherwise m or gamma (the mean value terms), the larger first
            opposite = (lo_ball > 0 and hi_ball < 0) or (lo_ball < 0 and hi_ball > 0)
            split_order = [2] if opposite else sorted((0, 1), key=lambda k: -[widths["m"], widths["gamma"]][k])
            k = next((k for k in split_order if rel[k] > mw), None)
            if k is None:
                undecided.append(rec)
                continue
            box = [bm, bg, bd]
            lo, hi = box[k]
            mid = (lo + hi) / 2
            for part in ((lo, mid), (mid, hi)):
                nb = list(box)
                nb[k] = part
                queue.append(tuple(nb))
    signs = {}
    for b in decided:
        signs[str(b.sign)] = signs.get(str(b.sign), 0) + 1
    region = f"m in [{mb[0]}, {mb[1]}], gamma in [{gb[0]}, {gb[1]}], delta in [{db[0]}, {db[1]}]"
    if not undecided and len(signs) == 1:
        sgn = "< 0" if "-1" in signs else "> 0"
        statement = (f"computer-verified: S(m, gamma, delta) {sgn} for every (m, gamma, delta) with {region} "
                     f"({len(decided)} boxes, ball arithmetic at {prec} bits, tails bounded"
                     + (", second-order form)" if order == 2 else ")"))
    else:
        statement = (f"partial: {len(decided)} boxes decided {signs}, {len(undecided)} undecided in {region}"
                     + (f"; {len(zeros)} rectangles with a located zero in delta" if zeros else ""))
    return BoxTheorem(tuple(map(str, mb)), tuple(map(str, gb)), tuple(map(str, db)), decided, undecided, zeros,
                      signs, statement, prec, evaluated, time.perf_counter() - t0)
