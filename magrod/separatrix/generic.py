"""The splitting for a > 2b, derived: the leading coefficient s1/eps^3 of D(psi) = 2 s1 sin(psi)
and one leading-order picture of W^u on Sigma for all a >= 2b, compared with the measured splitting.

Derivation (derive/generic_splitting.py; report entries generic_*):

    s1/eps^3 -> b sqrt(a - 2b) S / (V'(theta_t) (1 + cos theta_t))

with S the integral of the a = 2b case (magrod.separatrix.enclosure.enclose_S: a rigorous ball), V the potential of
eq:eq_oscillator and theta_t the turning point of the lambdabar = 0 homoclinic orbit.  In the transverse-force plane
at Sigma (chart units, nu = mu - 2 lambdabar) W^u is, to leading order, the circle

    rho e^{i psi} = lambdabar tan(theta_t/2) + i lambdabar^2 S + sqrt(nu) e^{i phi},    phi the launch phase,

which gives the a = 2b point (nu = 0), the generic term above (sqrt(nu) >> lambdabar) and, in between, the
primary symmetric orbits: sin(psi) = 0 needs sin(phi) = -lambdabar^2 S/sqrt(nu), so two primaries exist iff
nu >= nu* = lambdabar^4 S^2, their launch phases differ by pi - 2 asin(lambdabar^2 |S|/sqrt(nu)), and near
nu = 0, sin(psi) = psi_0 + A sqrt(nu) sin(phi) with psi_0 = lambdabar S/tan(theta_t/2), A = 1/(lambdabar
tan(theta_t/2)).

Status: the identities are symbolic; the expansion is formal (conditional: first order in lambdabar, uniformly as
the saddle-focus approaches the chart singularity); S and the coefficient are balls (computer-verified values of
the formal coefficient); the comparison with the measured splitting is numerical (two precisions, eps^2
extrapolation).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

from flint import arb, ctx

from ..core.errors import ParameterError
from ..core.precision import Precision
from ..core.results import Result
from ..generated import generic_splitting as _gen
from ..generated import splitting_ball as _sball
from ..core.tolerances import GENERIC_AGREEMENT
from .enclosure import DEFAULT_PREC, enclose_S, exact

# The comparison set (>= 8 parameter sets): the printed point, a/b close to 2, delta = 0, gamma = 0, and
# other (m, gamma, delta, a, b).  eps: geometric ladders on which the guard of tilted_curve passes in both precisions
# (for a/b = 2.05 the launch phases cluster on Sigma below eps ~ 4e-3).
DEFAULT_EPS = (0.02, 0.014, 0.01, 0.007, 0.005)
CASES = (
    (1.7, 1.0, 1.0, 4.0, 1.0),
    (1.7, 1.0, 1.0, 2.2, 1.0),
    (1.7, 1.0, 1.0, 2.05, 1.0),
    (1.7, 1.0, 0.0, 4.0, 1.0),
    (1.7, 0.0, 1.0, 4.0, 1.0),
    (1.2, 0.5, 2.0, 3.0, 1.0),
    (2.2, 2.0, 0.5, 2.0, 0.5),
    (1.0, 0.0, 1.0, 6.0, 2.0),
)
TOLERANCE = GENERIC_AGREEMENT  # relative: the bound asked of derived vs measured


def precisions_for(case) -> tuple:
    """The two precisions a case is measured in: double and long double, or long double and quad for a/b < 2.5,
    where float64 curves near a = 2b fail the fit guard at eps <= 0.01 (measured: residual 1e-7 at (2.05, 1),
    eps = 0.01, against 2.5e-10 at eps = 0.02 and 2.4e-13 in long double at eps = 0.005)."""
    a, b = float(case[3]), float(case[4])
    return ((Precision.LONG_DOUBLE, Precision.QUAD) if b > 0 and a / b < 2.5 else
            (Precision.DOUBLE, Precision.LONG_DOUBLE))


def _ball_dict(x: arb) -> dict:
    return {"mid": float(x.mid()), "rad": float(x.rad()), "ball": x.str(radius=True)}


@dataclass(repr=False)
class GenericTerm(Result):
    """The derived leading coefficient of the a > 2b splitting at (m, gamma, delta, a, b).

    Attributes: S (ball, enclose_S), denominator V'(theta_t)(1 + cos theta_t) (ball), coefficient s1/eps^3 (ball),
    even coefficient c1/eps = sqrt(a - 2b) (theta_u = theta_t + sqrt(nu) cos(psi) + ...), formula and
    claim_status (its kind of truth; to_dict() key "status")."""

    success: bool
    message: str
    m: str  # the rod's parameter m, as the exact rational it was read as
    gamma: str  # the rod's parameter gamma, exact rational
    delta: str  # the rod's parameter delta, exact rational
    a: str  # mu = a eps^2 (eq:condition_unperturbed_1), exact rational
    b: str  # lambdabar = b eps^2, exact rational; a > 2b
    S: arb  # the integral S of the a = 2b case, a rigorous ball (enclose_S)
    denominator: arb  # V'(theta_t) (1 + cos theta_t) at the lambdabar = 0 orbit's turning point theta_t, a ball
    coefficient: arb  # the derived leading coefficient s1/eps^3 = b sqrt(a - 2b) S / denominator, a ball
    c1_over_eps: float  # the even coefficient c1/eps = sqrt(a - 2b) (theta_u = theta_t + sqrt(nu) cos psi + ...)
    formula: str  # the formula of `coefficient`, as text
    claim_status: str  # proved / computer-verified / numerical / conditional (the result's `status` is scipy's)
    wall_time_s: float  # seconds taken

    _repr_fields = ("m", "gamma", "delta", "a", "b", "coefficient")

    def to_dict(self) -> dict:
        return {"success": self.success, "message": self.message, "m": self.m, "gamma": self.gamma,
                "delta": self.delta, "a": self.a, "b": self.b, "S": _ball_dict(self.S),
                "denominator": _ball_dict(self.denominator), "coefficient": _ball_dict(self.coefficient),
                "c1_over_eps": self.c1_over_eps, "formula": self.formula, "status": self.claim_status,
                "wall_time_s": self.wall_time_s}


def generic_coefficient(m, gamma, delta, a, b, *, prec: int = DEFAULT_PREC) -> GenericTerm:
    """The derived s1/eps^3 of the a > 2b splitting: b sqrt(a - 2b) S/(V'(theta_t)(1 + cos theta_t)).

    Parameters
    ----------
    m, gamma, delta : exact rationals (as accepted by enclosure.exact)
        0 < m < m_c, gamma >= 0, delta >= 0.
    a, b : exact rationals
        mu = a eps^2, lambdabar = b eps^2 (eq:condition_unperturbed_1); a > 2b >= 0.
    prec : int, keyword-only
        Bits of the ball arithmetic.

    Returns
    -------
    GenericTerm

    Raises
    ------
    ParameterError
        Naming m, gamma, delta, a or b.

    Examples
    --------
    >>> round(float(generic_coefficient("1.7", 1, 1, 4, 1).coefficient.mid()), 5)
    -1.6672

    Notes
    -----
    Derivation: module docstring and derive/generic_splitting.py.  Cost: one enclose_S (~0.3 s).
    """
    t0 = time.perf_counter()
    aq, bq = exact("a", a), exact("b", b)
    if bq < 0:
        raise ParameterError("b", f"must be >= 0 (lambdabar = b eps^2), got {bq}")
    if not aq > 2 * bq:
        raise ParameterError("a", f"must satisfy a > 2b (the tilted saddle-focus; a = 2b is enclose_S's psi_u = "
                                  f"lambdabar S/tan(theta_t/2)), got a = {aq}, b = {bq}")
    enc = enclose_S(m, gamma, delta, prec=prec)
    with ctx.workprec(prec):
        M, G = arb(exact("m", m)), arb(exact("gamma", gamma))
        den = _gen.denominator(M, G)
        coef = arb(bq) * (arb(aq) - 2 * arb(bq)).sqrt() * enc.S / den
    return GenericTerm(True, "derived (formal leading order; S and the coefficient enclosed in balls)", enc.m,
                       enc.gamma, enc.delta, str(aq), str(bq), enc.S, den, coef,
                       math.sqrt(float(aq) - 2 * float(bq)),
                       "s1/eps^3 = b sqrt(a - 2b) S / (V'(theta_t) (1 + cos theta_t))",
                       "conditional (formal expansion; derive/generic_splitting.py); value computer-verified",
                       time.perf_counter() - t0)


# --------------------------------------------------------------------------------------------------------------
# the measurement and the comparison
# --------------------------------------------------------------------------------------------------------------
def measured_coefficient(m, gamma, delta, a, b, eps=DEFAULT_EPS, precision=Precision.LONG_DOUBLE) -> dict:
    """s1/eps^3 measured by tilted_curve (guarded) at each eps and extrapolated in eps^2 (fit_power's C0)."""
    from .splitting import fit_power, tilted_curve

    precision = Precision.parse(precision)
    curves = [tilted_curve(m, gamma, delta, a, b, e, precision) for e in eps]
    s1 = [c.sin_coeffs[0] for c in curves]
    fit = fit_power(list(eps), s1)
    return {"precision": precision.value, "eps": list(eps), "s1_over_eps3": [v / e**3 for v, e in zip(s1, eps)],
            "C0": fit.C0, "C0_fit_max_rel_residual": fit.C0_fit_max_rel_residual, "p": fit.p,
            "max_fit_residual": max(c.fit_residual for c in curves), "max_psi_gap": max(c.psi_max_gap for c in curves),
            "guards": [c.guard for c in curves]}


@dataclass(repr=False)
class GenericComparison(Result):
    """Derived vs measured s1/eps^3 for each case, in each precision; success iff every relative difference is
    within `tolerance`."""

    success: bool
    message: str
    #: one dict per case: case (m, gamma, delta, a, b), derived (float), derived_ball, S, measured (per precision:
    #: measured_coefficient's dict, C0 the eps^2-extrapolated s1/eps^3), rel_difference (per precision)
    rows: list
    tolerance: float  # the bound asked of |measured/derived - 1|
    max_rel_difference: float  # the largest |measured/derived - 1| over cases and precisions
    precisions: tuple  # the precisions measured in ("double", "long_double", "quad")
    wall_time_s: float  # seconds taken
    notes: list = field(default_factory=list)  # remarks added by the caller (none by default)

    _repr_fields = ("max_rel_difference", "tolerance", "precisions")


def compare_generic(cases=CASES, eps=DEFAULT_EPS, precisions=None, *, tolerance: float = TOLERANCE,
                    scale: float = 1.0, progress=None) -> GenericComparison:
    """The derived coefficient (generic_coefficient) against the measured eps^2-extrapolated s1/eps^3.

    Parameters
    ----------
    cases : iterable of (m, gamma, delta, a, b)
    eps : tuple of float
        The eps ladder (>= 4 values; the guard of tilted_curve must pass at each).
    precisions : tuple of str or None
        Measured in each (splitting.PRECISIONS); None: precisions_for(case), two per case.
    tolerance : float, keyword-only
        Relative bound on |measured/derived - 1|.
    scale : float, keyword-only
        Multiplies the derived value (1 for the derivation; tests pass a wrong factor to see the check fail).
    progress : callable(int) or None

    Returns
    -------
    GenericComparison

    Raises
    ------
    ParameterError
        Bad case or eps, or a curve refused by the guard.

    Examples
    --------
    >>> r = compare_generic([(1.7, 1.0, 1.0, 4.0, 1.0)], precisions=("double",))  # doctest: +SKIP
    >>> r.success  # doctest: +SKIP
    True

    Notes
    -----
    Cost: per case and precision len(eps) tilted curves of 64 first crossings (~0.1 s double, ~0.7 s long).
    """
    t0 = time.perf_counter()
    if len(tuple(eps)) < 4:
        raise ParameterError("eps", "needs >= 4 values for the eps^2 extrapolation")
    rows, worst = [], 0.0
    for case in cases:
        g = generic_coefficient(*case)
        derived = float(g.coefficient.mid()) * scale
        row = {"case": list(case), "derived": derived, "derived_ball": g.coefficient.str(radius=True),
               "S": float(g.S.mid()), "measured": {}, "rel_difference": {}}
        for pr in (precisions or precisions_for(case)):
            pr = Precision.parse(pr)
            meas = measured_coefficient(*case, eps=eps, precision=pr)
            rel = abs(meas["C0"] / derived - 1.0)
            row["measured"][pr.value] = meas
            row["rel_difference"][pr.value] = rel
            worst = max(worst, rel)
        rows.append(row)
        if progress is not None:
            progress(1)
    ok = worst <= tolerance
    msg = (f"derived and measured s1/eps^3 agree to {worst:.2e} relative (bound {tolerance:g}) at {len(rows)} "
           "parameter sets, two precisions each" if ok else
           f"derived and measured s1/eps^3 differ by {worst:.2e} relative (> {tolerance:g})")
    used = tuple(sorted({p for row in rows for p in row["measured"]}))
    return GenericComparison(ok, msg, rows, tolerance, worst, used, time.perf_counter() - t0)


# --------------------------------------------------------------------------------------------------------------
# the circle picture: predictions for mu -> 2 lambdabar+ (the primaries to the periodic saddle)
# --------------------------------------------------------------------------------------------------------------
@dataclass(repr=False)
class CirclePrediction(Result):
    """Leading-order predictions of the circle picture at (m, gamma, delta, lambdabar) (module docstring):
    psi0 = lambdabar S/tan(theta_t/2) (sin psi at the straight rod's turning point), A = 1/(lambdabar
    tan(theta_t/2)) (sin psi = psi0 + A sqrt(nu) sin(phi)), c = lambdabar^2 |S| (spread law
    b - a - pi = -2 asin(c/sqrt(nu))), nu_merge = c^2 (the two primaries merge; none below)."""

    success: bool
    message: str
    m: float  # the rod's parameter m
    gamma: float  # the rod's parameter gamma
    delta: float  # the rod's parameter delta
    lam: float  # lambdabar (leading order in lambdabar: small)
    S: float  # the integral S of the a = 2b case (midpoint of enclose_S's ball)
    psi0: float  # lambdabar S / tan(theta_t/2): sin psi at the straight rod's turning point, at nu = 0
    A: float  # 1/(lambdabar tan(theta_t/2)): sin psi = psi0 + A sqrt(nu) sin(phi) near nu = 0
    c: float  # lambdabar^2 |S|: the spread law b - a - pi = -2 asin(c/sqrt(nu))
    nu_merge: float  # c^2: the two primaries merge at nu = mu - 2 lambdabar = nu_merge; none below

    _repr_fields = ("lam", "psi0", "A", "c", "nu_merge")

    def spread(self, nu: float) -> float:
        """b - a - pi of the two primaries' launch angles at nu = mu - 2 lambdabar (nan below nu_merge)."""
        x = self.c / math.sqrt(nu)
        return -2.0 * math.asin(x) if x <= 1 else math.nan

    def primaries_exist(self, nu: float) -> bool:
        """Whether the two primary symmetric orbits exist at nu = mu - 2 lambdabar (nu >= nu_merge)."""
        return nu >= self.nu_merge


def circle_prediction(m, gamma, delta, lam) -> CirclePrediction:
    """Predictions for the primary symmetric orbits to the periodic saddle as mu -> 2 lambdabar+ (see CirclePrediction).

    Parameters
    ----------
    m, gamma, delta : numbers (converted exactly, as in enclose_S)
    lam : float
        lambdabar > 0 (small: leading order in lambdabar).

    Returns
    -------
    CirclePrediction

    Raises
    ------
    ParameterError
        Naming the parameter.

    Examples
    --------
    >>> p = circle_prediction(1.7, 1.0, 1.0, 1e-3)
    >>> round(p.c, 10), round(p.A)
    (8.265e-07, 973)

    Notes
    -----
    Leading order in lambdabar and nu (formal); measured values: docs/errata.md and
    tests/test_generic_splitting.py.
    """
    lam = float(exact("lam", lam))
    if not lam > 0:
        raise ParameterError("lam", f"must be > 0, got {lam}")
    enc = enclose_S(m, gamma, delta)
    S = float(enc.S.mid())
    with ctx.workprec(DEFAULT_PREC):
        th = float(_sball.tan_half_turn(arb(exact("m", m)), arb(exact("gamma", gamma))).mid())
    c = lam * lam * abs(S)
    return CirclePrediction(True, "leading-order prediction (formal)", float(exact("m", m)),
                            float(exact("gamma", gamma)), float(exact("delta", delta)), lam, S, lam * S / th,
                            1.0 / (lam * th), c, c * c)
