"""Splitting of the separatrix of the straight rod under the paper's scaling mu = a eps^2, lambdabar = b eps^2
(eq:condition_unperturbed_1), measured in the singularity-free body frame (docs/nonintegrability.md).

Why.  The first-order Mel'nikov function of sec. 7 vanishes identically (docs/errata.md, derive/melnikov.py:
`melnikov_vanishes`), so it cannot decide whether the stable and unstable manifolds of the saddle split.  Here
the splitting is measured directly, in several floating-point precisions, and fitted as D ~ C eps^p.

The measure.  Sigma = {pbar_theta = 0} (the first turning point of theta after leaving the saddle, where theta
is near its maximum 1.1..1.6) is invariant under the reversor R (derive/symmetry.py: (theta, psi, pbar_theta,
pbar_psi) -> (theta, -psi, -pbar_theta, pbar_psi)), and R maps the unstable manifold W^u onto the stable one
W^s.  If x_u is the first point of W^u on Sigma, R x_u is a point of W^s on Sigma, and

    d = rho sin(psi) = (e31 n2 - e32 n1)/sin(theta)      (at x_u)

is the component of the force that R flips: |x_u - R x_u| = 2 |d| in (m, n, e3) once the rotation about d3 (a
symmetry) is used to put e3 in the (d1, d3) plane.  d = 0 iff x_u lies on Fix(R) iff the orbit is a symmetric
(primary) homoclinic orbit.  We also report the chart angle psi_u; note psi = atan2(rho sin psi, rho cos psi)
is an angle around the small transverse force rho (rho = O(eps) at the turning point) and is computed from the
state with absolute error ~ ulp/rho, which is why the crossing is evaluated in the working precision.

Cases (the saddles are the orbits' own, magrod.orbits.shooting.saddle(params, precision=...), whose crossing loop
is used; the launch convention is `LAUNCH`).
  a = 2b   the saddle is the straight rod, an equilibrium (magrod.orbits.equilibrium.StraightRod, its state
           formed in the working precision); its 2-D unstable manifold is a single orbit
           modulo the rotations about d3 (the launch phase is a symmetry), so the splitting is ONE number d(eps)
           per eps.
  a > 2b   the saddle is the relative equilibrium "straight rod tilted by theta0 = O(eps) from the field" (a
           periodic orbit in the body frame -- the same relative equilibrium as magrod.orbits.periodic's
           PeriodicSaddle -- seen here as an equilibrium (theta0, psi = 0, 0, pbar_psi0) on Fix(R) of the reduced
           chart and computed by Newton in the working precision: PeriodicSaddle.chart_view, kind "periodic").  It is a saddle-focus of the chart:
           its unstable manifold is 2-D, parametrised by a genuine phase phi on the unstable eigenplane, and
           its trace on Sigma is a closed curve x_u(phi).  The splitting is the odd part of that curve:
           D(psi) = theta_u(psi) - theta_u(-psi) (W^s on Sigma is the mirror image psi -> -psi of W^u), computed
           by a Fourier fit of theta_u against psi_u; and d(phi) as above.
  a < 2b   the radicand mu - 2 lambdabar pbar_psi is negative near the straight rod (the aligned side): not a
           saddle of the chart, ParameterError.

Precisions (magrod.core.precision.Precision): double (float64), long double (x87 80-bit), quad (IEEE binary128,
hy.real128), mp (hy.real, MP_BITS bits).  Launch distance per precision (tolerances.SPLITTING_LAUNCH): the
linear launch is off the manifold by O(launch_distance^2), which is below the rounding error of each precision.  Parameters are the float64 numbers
b eps^2 and a eps^2 (mu = 2 lambdabar exactly when a = 2b) in every precision, so all precisions solve the same
problem and their difference is the numerical error.
"""
from __future__ import annotations

import math
import time
import warnings
from dataclasses import asdict, dataclass, field

import heyoka as hy
import numpy as np

from ..core import systems
from ..core.errors import MAX_MAGNITUDE, MissingStructure, ParameterError, require_finite
from ..core.params import RodParams
from ..core.precision import Precision
from ..core.results import Result
from ..core.tolerances import MU_TOL, REAL128_QUADRATURE_TOL, SPLITTING_LAUNCH
from ..generated import scalars
from ..orbits.shooting import Crossing, crossing_events
from ..orbits.shooting import paper_saddle as orbit_saddle
from ..core.deprecation import deprecated_alias, renamed_keywords

THETA_TURN_MIN = 0.3  # a zero of pbar_theta counts as the turning point only where theta exceeds this
T_MAX = 2000.0


def a_level(b) -> float:
    """The a at which the straight rod is the saddle: mu on its level (generated straight_rod_mu = 2 lam) is
    linear in lam, so along mu = a eps^2, lam = b eps^2 the condition reads a = a_level(b) = 2b."""
    return scalars.straight_rod_mu(m=1.0, mu=0.0, gamma=0.0, delta=0.0, lam=float(b))


def is_equilibrium_case(a, b) -> bool:
    """a = 2b to MU_TOL (the rule of magrod.orbits.equilibrium.is_on_level for mu = 2 lam, applied to the scaled
    parameters): then mu is put on the straight rod's level exactly (`scaled_params`) and the saddle is the
    straight rod."""
    return abs(float(a) - a_level(b)) <= MU_TOL * max(1.0, abs(float(a)))


def _check(m, gamma, delta, a, b, eps, precision):
    m, gamma, delta, a, b = (require_finite(k, v, MAX_MAGNITUDE) for k, v in
                             (("m", m), ("gamma", gamma), ("delta", delta), ("a", a), ("b", b)))
    eps = require_finite("eps", eps)
    Precision.parse(precision)
    if a < 0:
        raise ParameterError("a", f"must be >= 0 (mu = a eps^2 >= 0), got {a}")
    if b < 0:
        raise ParameterError("b", f"must be >= 0 (lambdabar = b eps^2 >= 0), got {b}")
    if a < a_level(b) and not is_equilibrium_case(a, b):
        raise ParameterError("a", f"must satisfy a >= 2b (got a = {a}, 2b = {a_level(b)}): for a < 2b the radicand "
                                  "mu - 2 lambdabar pbar_psi of eq:alignment_condition is negative at the straight rod")
    if not eps > 0:
        raise ParameterError("eps", f"must be > 0, got {eps}")
    if gamma < 0 or delta < 0:
        raise ParameterError("gamma" if gamma < 0 else "delta", "must be >= 0")
    mc = scalars.m_critical(gamma)
    if not 0 < m < mc:
        raise ParameterError("m", f"must satisfy 0 < m < m_c = 2 sqrt(1 + gamma) = {mc:.6g} (eq:buckling_load_2; "
                                  f"the straight rod is a saddle only below m_c), got {m}")
    return m, gamma, delta, a, b, eps


def scaled_params(m, gamma, delta, a, b, eps) -> RodParams:
    """RodParams with lambdabar = b eps^2 and mu = a eps^2 (float64); mu = 2 lambdabar exactly when a = 2b
    (`is_equilibrium_case`)."""
    eps = require_finite("eps", eps)
    tiny = np.finfo(float).tiny
    if not 0 < eps <= 1:
        raise ParameterError("eps", f"must be in (0, 1], got {eps!r}")
    for coef, name in ((a, "mu = a eps^2"), (b, "lambdabar = b eps^2")):
        if float(coef) != 0 and abs(float(coef)) * eps ** 2 < tiny:
            raise ParameterError("eps", f"= {eps:g}: {name} underflows below the smallest normal double "
                                        f"({tiny:.3g}); the splitting is not computable there")
    lam = float(b) * float(eps) ** 2
    mu = scalars.straight_rod_mu(m=m, mu=0.0, gamma=gamma, delta=delta, lam=lam) if is_equilibrium_case(a, b) \
        else float(a) * float(eps) ** 2
    return RodParams(m=m, mu=mu, gamma=gamma, delta=delta, lam=lam)


# --------------------------------------------------------------------------------------------------------------
# the saddle: the orbits' saddle objects (magrod.orbits.shooting.saddle), in the working precision
# --------------------------------------------------------------------------------------------------------------
# The splitting's launch convention, per kind of saddle (explicit keywords of the saddles' launch_point):
#  - offset "double": the offset launch_distance d is formed in float64 and then converted to the working precision (the
#    eigenvector is a float64 quantity either way).  The measured splitting digits of REPORT.md (derived vs
#    measured leading term, 8.4 digits and more) were established with this rounding, which the long double runs
#    are sensitive to at their noise level (~1e-9 relative); the shooting engine forms the product in the working
#    precision instead (offset "working").
#  - frame "chart" (the periodic saddle): the launch is on the linear unstable manifold of the tilted straight rod
#    as an equilibrium of the reduced chart (PeriodicSaddle.chart_view, Newton in the working precision), at the
#    distance launch_distance theta0 relative to the tilt: its trace on Sigma is the closed curve x_u(phi) of `tilted_curve`.
LAUNCH = {"equilibrium": {"offset": "double"}, "periodic": {"offset": "double", "frame": "chart"}}


def splitting_saddle(params: RodParams, precision=Precision.DOUBLE):
    """The saddle at `params` in the working precision: magrod.orbits.shooting.saddle (the straight rod,
    StraightRod, where mu = 2 lam to MU_TOL; else the periodic saddle, PeriodicSaddle, with its chart view)."""
    return orbit_saddle(params, precision=precision)


def launch_point(sd, launch_distance: float, phase: float = 0.0, precision=None):
    """The splitting's launch point of W^u: sd.launch_point with the keywords of `LAUNCH` for its kind."""
    return sd.launch_point(launch_distance, phase, precision, **LAUNCH[sd.kind])


def working_saddle(params: RodParams, precision=Precision.DOUBLE):
    """Deprecated: the separatrix uses the orbits' saddles; call `splitting_saddle` or
    magrod.orbits.shooting.saddle(params, precision=...)."""
    warnings.warn("magrod.separatrix.splitting.working_saddle is deprecated: use magrod.orbits.shooting.saddle("
                  "params, precision=...) (the same objects: StraightRod, PeriodicSaddle)", DeprecationWarning,
                  stacklevel=2)
    return splitting_saddle(params, precision)


_DEPRECATED = {"EquilibriumSaddle": ("magrod.orbits.equilibrium", "StraightRod"),
               "TiltedSaddle": ("magrod.orbits.periodic", "PeriodicSaddle")}


def __getattr__(name):
    """The old saddle classes of the splitting, now the orbits' ones, with a DeprecationWarning."""
    if name in _DEPRECATED:
        import importlib

        mod, new = _DEPRECATED[name]
        warnings.warn(f"magrod.separatrix.splitting.{name} is deprecated: the separatrix uses {mod}.{new}",
                      DeprecationWarning, stacklevel=2)
        return getattr(importlib.import_module(mod), new)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


# --------------------------------------------------------------------------------------------------------------
# the first turning point
# --------------------------------------------------------------------------------------------------------------
@dataclass
class SplittingCrossing(Crossing):
    """The first point x_u of W^u on Sigma = {pbar_theta = 0} with theta > THETA_TURN_MIN (a Crossing, index its
    number among all zeros of sin(theta) pbar_theta) and the splitting measure there: d = rho sin psi (module
    docstring), rho_cos = rho cos psi; H_drift = Hbar(x_u) - Hbar(launch); casimir_drift = max |C_i(x_u) -
    C_i(chart)|; eps the perturbation parameter, phase the launch angle, launch_distance the launch distance (as in magrod.orbits).  Floats
    (rounded from the working precision)."""

    eps: float
    phase: float
    precision: Precision
    launch_distance: float
    d: float
    rho_cos: float
    H_drift: float
    casimir_drift: float
    wall_time_s: float


def first_crossing(params: RodParams, precision=Precision.DOUBLE, *, phase: float = 0.0, launch_distance: float | None = None,
                   sd=None, eps: float = math.nan) -> SplittingCrossing:
    """Integrate W^u from the launch point to its first turning point (a stopping event on e32 m1 - e31 m2 =
    sin(theta) pbar_theta = 0, the crossing loop of magrod.orbits.shooting) in the working precision and evaluate
    the crossing there.  sd: the saddle (`splitting_saddle`) if already computed.  Guard: T_MAX."""
    precision = Precision.parse(precision)
    fp, prec = precision.fp_type, precision.prec
    t0 = time.perf_counter()
    sd = sd or splitting_saddle(params, precision)
    launch_distance = SPLITTING_LAUNCH[precision] if launch_distance is None else launch_distance
    x0 = launch_point(sd, launch_distance, phase, precision)
    F = systems.splitting_functions(fp, prec)
    pars = params.array()
    H0 = F["H"](x0, pars)[0]
    found = None
    for index, (t, x) in enumerate(crossing_events(x0, pars, precision, t_max=T_MAX), start=1):
        ch = F["chart"](x)
        if float(ch[0]) > THETA_TURN_MIN:
            found = (index, t, x, ch)
            break
    if found is None:
        raise RuntimeError(f"no turning point of theta before t = {T_MAX}")
    index, t, x, ch = found
    fix = F["fix"](x)[0]
    # rho cos psi from psi and d: evaluated in the working precision by the chart map (atan2 of the two parts)
    H = F["H"](x, pars)[0]
    cas = F["casimirs"](x, pars)
    psi = float(ch[1])
    d = float(fix)
    return SplittingCrossing(index=index, t=float(t), theta=float(ch[0]), psi=psi, ppsi=float(ch[4]),
                             sinpsi=math.sin(psi), eps=eps, phase=phase, precision=precision, launch_distance=launch_distance, d=d,
                             rho_cos=d / math.tan(psi) if psi != 0 else math.inf, H_drift=float(H - H0),
                             casimir_drift=max(abs(float(c)) for c in cas), wall_time_s=time.perf_counter() - t0)


# --------------------------------------------------------------------------------------------------------------
# eps scan (a = 2b) and power-law fit
# --------------------------------------------------------------------------------------------------------------
EPS_SCAN = tuple(float(f"{x:.3g}") for x in np.geomspace(0.3, 1e-3, 11))  # perturbation parameters eps of a scan


@dataclass
class PowerFit:
    """log|D| = log|C| + p log(eps) by least squares: p, C (with the sign of D), residuals (log), max |residual|;
    p without the smallest / largest eps; and C0 = lim D/eps^p_int by a linear fit of D/eps^p_int in eps^2 on
    the smallest half of the eps (p_int = round(p): D is a function of eps^2 through mu and lambdabar)."""

    p: float
    C: float
    residuals: list
    max_abs_residual: float
    p_drop_smallest: float
    p_drop_largest: float
    p_int: int
    C0: float
    C0_slope: float
    C0_fit_max_rel_residual: float
    n: int

    as_dict = deprecated_alias("to_dict", "as_dict")

    def to_dict(self) -> dict:
        return asdict(self)


def fit_power(eps, D) -> PowerFit:
    e = np.asarray(eps, float)
    y = np.asarray(D, float)
    if len(e) < 4 or np.any(y == 0) or np.any(np.sign(y) != np.sign(y[0])):
        raise ParameterError("eps", "a power-law fit needs >= 4 eps values with D of one sign, non-zero")
    o = np.argsort(e)
    e, y = e[o], y[o]

    def slope(ee, yy):
        A = np.column_stack([np.log(ee), np.ones_like(ee)])
        coef, *_ = np.linalg.lstsq(A, np.log(np.abs(yy)), rcond=None)
        return coef, np.log(np.abs(yy)) - A @ coef

    (p, lc), res = slope(e, y)
    p_lo = slope(e[1:], y[1:])[0][0]
    p_hi = slope(e[:-1], y[:-1])[0][0]
    pi = int(round(p))
    k = max(3, (len(e) + 1) // 2)
    z = y[:k] / e[:k] ** pi
    A = np.column_stack([np.ones(k), e[:k] ** 2])
    c, *_ = np.linalg.lstsq(A, z, rcond=None)
    rel = float(np.max(np.abs(A @ c - z)) / abs(c[0]))
    return PowerFit(float(p), float(np.sign(y[0]) * math.exp(lc)), [float(r) for r in res], float(np.max(np.abs(res))),
                    float(p_lo), float(p_hi), pi, float(c[0]), float(c[1]), rel, len(e))


@dataclass
class SplittingScan:
    """First turning points of W^u for each eps (rows) and precision (columns) at a = 2b, or for a control.
    `agreement[prec]` = max over eps of |psi_prec - psi_ref| / |psi_ref| (and of d) against the highest precision;
    fits of psi_u and of d from the reference precision (None for an integrable control, where D is zero to
    the working precision)."""

    m: float
    gamma: float
    delta: float
    a: float
    b: float
    eps: list
    precisions: list
    crossings: dict
    agreement_psi: dict
    agreement_d: dict
    fit_psi: PowerFit | None
    fit_d: PowerFit | None
    max_abs_psi: float
    max_abs_d: float
    wall_time_s: float
    notes: list = field(default_factory=list)

    def table(self, precision=None):
        """The crossings of one precision (a Precision or its value; default the reference) as dicts."""
        pr = Precision.parse(precision) if precision is not None else self.precisions[-1]
        return [asdict(c) for c in self.crossings[pr]]

    as_dict = deprecated_alias("to_dict", "as_dict")

    def to_dict(self) -> dict:
        d = asdict(self)
        return d


def scan(m, gamma, delta, a, b, eps=EPS_SCAN, precisions=(Precision.LONG_DOUBLE, Precision.QUAD), *, progress=None,
         fit: bool = True) -> SplittingScan:
    """D(eps) for the straight-rod saddle (a = 2b) in each precision; the last precision is the reference.
    Cost: ~1 ms (double), ~10 ms (long), ~0.1 s (quad) per eps; mp (hy.real) is ~100x slower than quad."""
    t0 = time.perf_counter()
    eps = [require_finite("eps", e) for e in eps]
    precisions = [Precision.parse(pr) for pr in precisions]
    for pr in precisions:
        _check(m, gamma, delta, a, b, min(eps) if eps else 1.0, pr)
    if not eps or min(eps) <= 0:
        raise ParameterError("eps", f"need a non-empty list of eps > 0, got {eps}")
    if not is_equilibrium_case(a, b):
        raise ParameterError("a", f"scan() is the a = 2b (straight-rod equilibrium) case; got a = {a}, b = {b}: use "
                                  "tilted_curve() for a > 2b")
    cr = {pr: [] for pr in precisions}
    for e in eps:
        p = scaled_params(m, gamma, delta, a, b, e)
        for pr in precisions:
            cr[pr].append(first_crossing(p, pr, eps=e))
        if progress is not None:
            progress(1)
    ref = cr[precisions[-1]]
    ag_psi, ag_d = {}, {}
    for pr in precisions[:-1]:
        ag_psi[pr] = max(abs(c.psi - r.psi) / max(abs(r.psi), 1e-300) for c, r in zip(cr[pr], ref))
        ag_d[pr] = max(abs(c.d - r.d) / max(abs(r.d), 1e-300) for c, r in zip(cr[pr], ref))
    max_psi = max(abs(c.psi) for c in ref)
    max_d = max(abs(c.d) for c in ref)
    fp = fd = None
    notes = []
    if fit and b > 0 and len(eps) >= 4:
        fp = fit_power(eps, [c.psi for c in ref])
        fd = fit_power(eps, [c.d for c in ref])
    elif fit:
        notes.append("no fit: b = 0 (lambdabar = 0)" if b <= 0 else f"no power-law fit: {len(eps)} eps (< 4)")
    return SplittingScan(m, gamma, delta, a, b, list(eps), list(precisions), cr, ag_psi, ag_d, fp, fd, max_psi,
                         max_d, time.perf_counter() - t0, notes)


# --------------------------------------------------------------------------------------------------------------
# a > 2b: the tilted saddle (saddle-focus of the chart), splitting as a function of the phase
# --------------------------------------------------------------------------------------------------------------
@dataclass
class TiltedCurve:
    """W^u on Sigma for the tilted saddle at one eps: launch phases (N,), theta_u, psi_u, d (N,); the Fourier fit
    theta_u(psi) = c0 + sum_k (ck cos k psi + sk sin k psi), k <= K (least squares on the samples, max residual
    `fit_residual`); the splitting D(psi) = theta_u(psi) - theta_u(-psi) = 2 sum_k sk sin k psi (W^s on Sigma is
    the mirror image of W^u), D_amplitude = max over psi of |D| (on a 720-point grid)."""

    eps: float
    a: float
    b: float
    precision: Precision
    theta0: float
    eigenvalue: complex
    phases: list
    theta: list
    psi: list
    d: list
    cos_coeffs: list
    sin_coeffs: list
    fit_residual: float
    D_amplitude: float
    psi_max_gap: float = math.nan  # largest gap between consecutive psi samples on the circle (coverage)
    coverage_bound: float = math.nan  # the guard's bound on psi_max_gap: pi/K
    fit_bound: float | None = None  # the guard's bound on fit_residual: FIT_REL_BOUND max_k |s_k| (None for b = 0)
    guard: str = ""  # what the guard checked, and the outcome

    as_dict = deprecated_alias("to_dict", "as_dict")

    def to_dict(self) -> dict:
        d = asdict(self)
        d["eigenvalue"] = [self.eigenvalue.real, self.eigenvalue.imag]
        return d


# Guard of tilted_curve: near a = 2b the launch phases on the saddle-focus's (very elongated, in the chart)
# unstable eigenplane map to clustered psi on Sigma, and the K-harmonic fit becomes unconstrained in the gaps
# (measured: (a, b) = (2.05, 1), eps = 1.25e-3, long double: gap 1.19 rad, residual 1e-9 > |s1| = 4e-10, and s1/eps^3
# off by 30%).  A curve is refused unless (i) no gap between consecutive psi samples exceeds pi/K (half a period of
# the highest fitted harmonic) and (ii) for b > 0 the fit residual is at most FIT_REL_BOUND times the largest sine
# coefficient (good curves: <= 3.4e-3 at eps = 0.1, where the K = 4 truncation dominates, ~1e-6 below eps = 0.01).
# For b = 0 (the integrable control) the residual is the reported bound on |D| and only (i) applies.
FIT_REL_BOUND = 1e-2


def _psi_max_gap(psi) -> float:
    ps = np.sort(np.mod(np.asarray(psi, float), 2 * np.pi))
    return float(np.max(np.diff(np.concatenate([ps, [ps[0] + 2 * np.pi]]))))


def tilted_curve(m, gamma, delta, a, b, eps, precision=Precision.DOUBLE, *, n_phases=64, harmonics=4,
                 guard: bool = True) -> TiltedCurve:
    """Trace of W^u of the tilted saddle (a > 2b) on Sigma over n_phases launch phases, and its odd part D(psi).
    guard (default True): refuse the curve, with ParameterError('eps', ...), if its psi coverage or Fourier-fit
    residual fails the stated bounds (FIT_REL_BOUND, pi/K; see the comment above); the record always carries the
    fit residual, the largest psi gap and both bounds.  Cost: n_phases first crossings (~1 ms each in double, ~10 ms
    in long)."""
    m, gamma, delta, a, b, eps = _check(m, gamma, delta, a, b, eps, precision)
    precision = Precision.parse(precision)
    if is_equilibrium_case(a, b):
        raise ParameterError("a", "a = 2b is the straight-rod equilibrium: use scan()")
    p = scaled_params(m, gamma, delta, a, b, eps)
    sd = splitting_saddle(p, precision)
    if sd.kind != "periodic":
        raise ParameterError("a", f"a - 2b = {a - a_level(b):.3g} is not resolved at eps = {eps:g}: mu - 2 lam = "
                                  f"{p.mu - 2 * p.lam:.3g} is within MU_TOL of the straight rod's level")
    ph = np.linspace(0, 2 * np.pi, int(n_phases), endpoint=False)
    cs = [first_crossing(p, precision, phase=float(x), sd=sd, eps=eps) for x in ph]
    th = np.array([c.theta for c in cs])
    ps = np.array([c.psi for c in cs])
    K = int(harmonics)
    cols = [np.ones_like(ps)] + [f(k * ps) for k in range(1, K + 1) for f in (np.cos, np.sin)]
    A = np.column_stack(cols)
    coef, *_ = np.linalg.lstsq(A, th, rcond=None)
    res = float(np.max(np.abs(A @ coef - th)))
    ck = [float(coef[0])] + [float(coef[1 + 2 * (k - 1)]) for k in range(1, K + 1)]
    sk = [float(coef[2 + 2 * (k - 1)]) for k in range(1, K + 1)]
    grid = np.linspace(-np.pi, np.pi, 720)
    D = 2 * sum(s * np.sin((k + 1) * grid) for k, s in enumerate(sk))
    gap, gap_bound = _psi_max_gap(ps), math.pi / K
    fit_bound = FIT_REL_BOUND * max(abs(v) for v in sk) if b > 0 else None
    bad = []
    if not gap <= gap_bound:
        bad.append(f"psi coverage: largest gap {gap:.3g} rad > pi/K = {gap_bound:.3g}")
    if fit_bound is not None and not res <= fit_bound:
        bad.append(f"Fourier-fit residual {res:.3g} > {FIT_REL_BOUND:g} max|s_k| = {fit_bound:.3g}")
    text = ("refused: " + "; ".join(bad)) if bad else (
        f"passed: gap {gap:.3g} <= {gap_bound:.3g}" + (f", residual {res:.3g} <= {fit_bound:.3g}" if fit_bound is not None
                                                       else ", residual not bounded (b = 0: it bounds |D|)"))
    if bad and guard:
        raise ParameterError("eps", f"the W^u curve on Sigma at eps = {eps:g} ({precision.value}) fails the fit guard: "
                                    f"{'; '.join(bad)}; use a larger eps, a higher precision or more phases")
    return TiltedCurve(eps, a, b, precision, float(sd.q[0]), sd.chart_eigenvalue, ph.tolist(), th.tolist(), ps.tolist(),
                       [c.d for c in cs], ck, sk, res, float(np.max(np.abs(D))), gap, gap_bound, fit_bound, text)


@dataclass
class TiltedScan:
    """tilted_curve for each eps (reference precision) plus a check precision; fit of the first sine coefficient
    s1(eps) (D(psi) ~ 2 s1 sin psi; simple zeros at psi = 0, pi iff s1 != 0 dominates) when b > 0."""

    m: float
    gamma: float
    delta: float
    a: float
    b: float
    eps: list
    curves: list
    check: list
    agreement_s1: float
    fit_s1: PowerFit | None
    max_abs_sin: float
    max_fit_residual: float
    wall_time_s: float

    as_dict = deprecated_alias("to_dict", "as_dict")

    def to_dict(self) -> dict:
        return {**{k: getattr(self, k) for k in ("m", "gamma", "delta", "a", "b", "eps", "agreement_s1",
                                                  "max_abs_sin", "max_fit_residual", "wall_time_s")},
                "curves": [c.to_dict() for c in self.curves], "check": [c.to_dict() for c in self.check],
                "fit_s1": self.fit_s1.to_dict() if self.fit_s1 else None}


def tilted_scan(m, gamma, delta, a, b, eps, precisions=(Precision.DOUBLE, Precision.LONG_DOUBLE), *, n_phases=64,
                harmonics=4, progress=None) -> TiltedScan:
    """The splitting at the tilted saddle-focus (a > 2b) for each perturbation parameter eps: the first-turning-point
    curve (`tilted_curve`) in the last of `precisions`, checked against the first; its leading harmonics and the
    agreement of the two precisions (TiltedScan)."""
    t0 = time.perf_counter()
    precisions = [Precision.parse(pr) for pr in precisions]
    ref, chk = [], []
    for e in eps:
        ref.append(tilted_curve(m, gamma, delta, a, b, e, precisions[-1], n_phases=n_phases, harmonics=harmonics))
        if len(precisions) > 1:
            chk.append(tilted_curve(m, gamma, delta, a, b, e, precisions[0], n_phases=n_phases, harmonics=harmonics))
        if progress is not None:
            progress(1)
    ag = max((abs(c.sin_coeffs[0] - r.sin_coeffs[0]) for c, r in zip(chk, ref)), default=0.0)
    s1 = [c.sin_coeffs[0] for c in ref]
    fit = fit_power(eps, s1) if b > 0 and len(eps) >= 4 else None
    return TiltedScan(m, gamma, delta, a, b, list(eps), ref, chk, float(ag), fit,
                      max(abs(s) for c in ref for s in c.sin_coeffs), max(c.fit_residual for c in ref),
                      time.perf_counter() - t0)


def scan_summary(res) -> dict:
    """JSON-able summary of a SplittingScan (the reference precision is the last one)."""
    ref = res.precisions[-1]
    return {"m": res.m, "gamma": res.gamma, "delta": res.delta, "a": res.a, "b": res.b, "eps": res.eps,
            "precisions": res.precisions, "rows": res.table(ref),
            "check_rows": res.table(res.precisions[0]) if len(res.precisions) > 1 else [],
            "agreement_psi": res.agreement_psi, "agreement_d": res.agreement_d,
            "fit_psi": res.fit_psi.to_dict() if res.fit_psi else None,
            "fit_d": res.fit_d.to_dict() if res.fit_d else None,
            "max_abs_psi": res.max_abs_psi, "max_abs_d": res.max_abs_d, "notes": res.notes,
            "wall_time_s": res.wall_time_s,
            "measure": "psi_u: chart angle psi at the first turning point of W^u (W^s there: -psi_u); "
                       "d = rho sin psi_u = (e31 n2 - e32 n1)/sin(theta): half the body-frame distance of W^u "
                       "from its mirror image W^s on pbar_theta = 0"}


# --------------------------------------------------------------------------------------------------------------
# a = 2b: the derived leading term (derive/splitting.py; report entries splitting_blowup,
# splitting_invariant_manifold, splitting_leading_term)
# --------------------------------------------------------------------------------------------------------------
@systems.per_thread
def _leading_integrator(fp_type=float):
    """Taylor integrator of (Psi, S(t))' = (1/(1 + cos theta), N) along the closed-form lambdabar = 0 homoclinic
    orbit (t = hy.time, t = 0 at the turning point); pars (m, gamma, delta)."""
    from ..generated import splitting as gen_split
    from ..orbits.homoclinic import stable_expressions

    Psi, S = hy.make_vars("Psi", "S")
    m, g, dl = hy.par[0], hy.par[1], hy.par[2]
    e = stable_expressions(hy.time, m, g)
    sys = [(Psi, e["psidot"]), (S, gen_split.leading_integrand(e["theta"], e["ptheta"], Psi, m, g, dl))]
    if fp_type is float:
        return systems.taylor(sys, [0.0, 0.0], [1.0, 1.0, 1.0])
    return systems.taylor(sys, [0, 0], [1, 1, 1], precision=Precision.of(fp_type), compact_mode=True,
                          tol=REAL128_QUADRATURE_TOL if fp_type is hy.real128 else 0)


def _leading_run(m, gamma, delta, T, fp_type=float):
    ta = _leading_integrator(fp_type)
    ta.time = fp_type(0)
    ta.state[:] = np.array([fp_type(0)] * 2)
    ta.pars[:] = np.array([fp_type(m), fp_type(gamma), fp_type(delta)])
    res = ta.propagate_until(fp_type(T))
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"splitting quadrature failed: {res[0]}")
    return ta.state[1]


@dataclass(frozen=True)
class LeadingTerm:
    """Derived leading term of the splitting at mu = 2 lambdabar (a = 2b) for (m, gamma, delta):

        psi_u = C_psi lambdabar + O(lambdabar^2),   d = rho sin psi_u = C_d lambdabar^2 + O(lambdabar^3),

    C_psi = S/tan(theta_t/2), C_d = S/m^2 (rho of the body numeric scale = sqrt(mu - 2 lambdabar pbar_psi)/m^2,
    derive/numeric_scale.py), S = Int_0^inf N dt (generated.splitting.leading_integrand).  Along the paper's
    scaling lambdabar = b eps^2: psi_u/eps^2 -> b C_psi, d/eps^4 -> b^2 C_d."""

    m: float
    gamma: float
    delta: float
    S: float  # float64 quadrature
    S_reference: float | None  # real128 quadrature
    quad_error: float | None  # |S - S_reference|
    tail_estimate: float  # asymptotic bound of |Int_T^inf N dt| (theta -> 0 along the orbit)
    error: float | None  # quad_error + tail_estimate
    theta_turn: float
    C_psi: float
    C_d: float
    T: float
    wall_time_s: float
    S_reference_text: str | None = None  # the real128 value in full (str of hy.real128), for exact comparisons

    as_dict = deprecated_alias("to_dict", "as_dict")

    def to_dict(self) -> dict:
        return asdict(self)


def leading_coefficient(m, gamma, delta, *, reference=True, theta_tail=1e-20) -> LeadingTerm:
    """The derived coefficients C_psi, C_d of the a = 2b splitting (see LeadingTerm) by heyoka quadrature of the
    generated integrand on the closed-form homoclinic orbit, float64 (tol = eps) and, if reference, real128
    (tol = 1e-32) for the error estimate.
    Tail: as theta -> 0 on the orbit, x = tan(theta/2) ~ theta/2, |pbar_theta| ~ kappa theta, J/sin^2 -> q0 =
    (1/4 + kappa^2)/2, so |N| <~ theta [kappa (q0 + delta/m^2) + (q0 + (1 + gamma + delta)/m^2)/2] and
    Int_T^inf theta dt ~ theta(T)/kappa; tail_estimate is twice that (asymptotic, not rigorous; 1e-19 at the
    default theta_tail).  Cost: ~ms (float64) + ~0.3 s (real128)."""
    from ..orbits.homoclinic import homoclinic

    t0 = time.perf_counter()
    delta = require_finite("delta", delta, MAX_MAGNITUDE)
    if delta < 0:
        raise ParameterError("delta", f"must be >= 0, got {delta}")
    orbit = homoclinic(m, gamma)
    T = orbit.time_at_theta(theta_tail)
    s64 = float(_leading_run(orbit.m, orbit.gamma, delta, T))
    sref = qerr = err = sref_text = None
    if reference:
        s128 = _leading_run(orbit.m, orbit.gamma, delta, T, hy.real128)
        sref, sref_text = float(s128), str(s128)
        qerr = abs(s64 - sref)
    k = orbit.saddle_rate
    q0 = (0.25 + k * k) / 2
    m2 = orbit.m**2
    tail = 2.0 * theta_tail / k * (k * (q0 + delta / m2) + 0.5 * (q0 + (1 + orbit.gamma + delta) / m2))
    if reference:
        err = qerr + tail
    s = sref if reference else s64
    tan_half = math.sqrt((1.0 - orbit.u_plus) / (1.0 + orbit.u_plus))
    return LeadingTerm(orbit.m, orbit.gamma, delta, s64, sref, qerr, tail, err, orbit.theta_max, s / tan_half,
                       s / m2, T, time.perf_counter() - t0, sref_text)


def digits_agreeing(x, ref) -> float:
    """-log10 |x/ref - 1| (inf if equal): the number of significant digits x shares with ref."""
    rel = abs(x / ref - 1.0)
    return math.inf if rel == 0 else -math.log10(rel)


def compare_leading(m, gamma, delta, a, b, eps=(0.02, 0.014, 0.01, 0.007, 0.005, 0.0035),
                    precisions=(Precision.DOUBLE, Precision.LONG_DOUBLE)) -> dict:
    """Derived leading term (leading_coefficient) against the measured one (scan: C0 of the eps^2 extrapolation
    of psi_u/eps^2 and d/eps^4) at a = 2b.  Cost ~0.5 s."""
    if not is_equilibrium_case(a, b):
        raise ParameterError("a", f"the derived leading term is the a = 2b case; got a = {a}, b = {b}")
    lt = leading_coefficient(m, gamma, delta)
    sc = scan(m, gamma, delta, a, b, list(eps), precisions)
    dp, dd = b * lt.C_psi, b * b * lt.C_d
    return {"m": m, "gamma": gamma, "delta": delta, "a": a, "b": b, "eps": list(eps), "precisions": list(precisions),
            "derived_psi": dp, "measured_psi": sc.fit_psi.C0, "digits_psi": digits_agreeing(sc.fit_psi.C0, dp),
            "derived_d": dd, "measured_d": sc.fit_d.C0, "digits_d": digits_agreeing(sc.fit_d.C0, dd),
            "measured_fit_rel_residual": sc.fit_psi.C0_fit_max_rel_residual, "leading": lt.to_dict()}


# --------------------------------------------------------------------------------------------------------------
# the public face
# --------------------------------------------------------------------------------------------------------------
@dataclass(repr=False)
class Splitting(Result):
    """The splitting of the separatrix along mu = a eps^2, lambdabar = b eps^2 (what `splitting` returns).

    kind "equilibrium" (a = 2b: the straight rod; `measure` = psi_u, the chart angle of W^u at its first turning
    point, `d` = rho sin psi_u) or "tilted" (a > 2b: the tilted saddle-focus; `measure` = s1, the first sine
    coefficient of D(psi) = theta_u(psi) - theta_u(-psi), `d` = max_psi |D|), one value per eps, in the reference
    (last) precision.  agreement: max relative difference of `measure` between the precisions (the numerical
    error evidence).  fit: power law measure ~ C eps^p (>= 4 eps).  leading (a = 2b): the derived second-order
    Mel'nikov coefficient b C_psi against the measured eps^2-extrapolation, with the digits they share.

    kind "melnikov" (any other model with a saddle and a small parameter: the anisotropic rod, B2 = B1 (1 + eps), the
    curved rod, k1 = eps): `measure` = c / eps, the measured leading coefficient of Delta(phi0) = c sin(k phi0) per
    unit eps, `d` = c; agreement: max relative difference of c between the two methods (reversor, stable manifold);
    fit: power law c ~ C eps^p; leading: the Mel'nikov coefficient per unit eps (closed form) with the digits the
    smallest eps's c / eps shares with it; m, gamma, delta, a, b are NaN (the paper's rod's); `scan` the measurement
    (magrod.separatrix.model_splitting.MelnikovScan: rows, controls, quadrature); `system` what was studied."""

    success: bool
    message: str
    kind: str  # "equilibrium" (a = 2b), "tilted" (a > 2b) or "melnikov" (another model)
    m: float  # the paper's rod's m, gamma, delta (NaN for another model)
    gamma: float  # likewise
    delta: float  # likewise
    a: float
    b: float
    eps: np.ndarray
    precisions: list
    measure: np.ndarray  # per eps: psi_u ("equilibrium"), s1 ("tilted") or c / eps ("melnikov")
    d: np.ndarray  # per eps: the splitting (rho sin psi_u, max |D|, or c)
    agreement: float
    fit: dict | None
    leading: dict | None
    wall_s: float
    scan: object = field(default=None, repr=False)  # the underlying SplittingScan (every precision's rows)
    system: object = None  # what was studied (the paper's rod at its m, gamma, delta)

    _repr_fields = ("kind", "eps", "measure", "agreement", "fit_exponent", "leading_digits")

    @property
    def fit_exponent(self):
        """p of the power law measure ~ C eps^p (None without a fit)."""
        return None if self.fit is None else self.fit["p"]

    @property
    def leading_digits(self):
        """The digits the measured leading coefficient shares with the derived one (None without one)."""
        return None if self.leading is None else self.leading["digits"]

    @property
    def accuracy(self) -> dict:
        """The agreement of the measure between the precisions (kind "melnikov": the scan's accuracy)."""
        if self.kind == "melnikov":
            return self.scan.accuracy
        return {"agreement_between_precisions": self.agreement, "precisions": self.precisions}

    def to_dict(self) -> dict:
        from ..core.results import jsonable

        d = {k: getattr(self, k) for k in ("success", "message", "kind", "m", "gamma", "delta", "a", "b", "eps",
                                           "precisions", "measure", "d", "agreement", "fit", "leading", "wall_s")}
        d["system"] = self.system.to_dict() if self.system is not None else None
        if self.kind == "melnikov":
            d["scan"] = self.scan.to_dict()
        return jsonable(d)


MAX_EPS_VALUES = 64  # a scan of more perturbation parameters than this is a mistake, not a measurement


def check_eps(eps, precision) -> list:
    """The perturbation parameters of a scan: 1..64 distinct values in (0, 1] (eps is the expansion parameter),
    each resolvable in the working `precision`: the splitting d scales like eps^4 at a = 2b (d/eps^4 -> b^2 S/m^2,
    docs/nonintegrability.md; psi_u ~ eps^2) and no faster in the tilted case, so an eps whose eps^4 is below the
    precision's machine epsilon measures nothing but rounding (e.g. eps = 1e-300, where b eps^2 underflows).
    ParameterError("eps") otherwise."""
    vals = [require_finite("eps", e) for e in (eps if not np.isscalar(eps) else [eps])]
    if not vals:
        raise ParameterError("eps", "need a non-empty list of eps > 0")
    if len(vals) > MAX_EPS_VALUES:
        raise ParameterError("eps", f"at most {MAX_EPS_VALUES} values, got {len(vals)}")
    for v in vals:
        if not 0 < v <= 1:
            raise ParameterError("eps", f"must be in (0, 1] (the expansion parameter), got {v}")
    if len(set(vals)) != len(vals):
        raise ParameterError("eps", "values must be distinct")
    prec = Precision.parse(precision)
    lo = prec.eps ** 0.25
    small = [e for e in vals if e < lo]
    if small:
        raise ParameterError("eps", f"must be >= {lo:.2g} in {prec.value} precision (eps^4 >= its machine epsilon "
                                    f"2^-{prec.bits - 1}: the splitting ~ eps^4 is below rounding otherwise), got "
                                    f"{min(small):g}")
    return vals


@renamed_keywords(params="system")
def splitting(system=None, gamma=None, delta=None, a=None, b=None, eps=EPS_SCAN, *, m=None, precisions=None,
              n_phases=64, harmonics=4, progress=None):
    """The splitting of the stable and unstable manifolds of a rod model's saddle under its small parameter.

    The paper's rod: under mu = a eps^2, lambdabar = b eps^2 (the paper's scaling eq:condition_unperturbed_1),
    measured in two precisions (below).  The anisotropic rod (B2 = B1 (1 + eps)) and the curved rod (k1 = eps):
    the splitting of the straight twisted rod's homoclinic manifold against its Mel'nikov function
    (magrod.separatrix.model_splitting).  Other models: a ParameterError naming the model and what it lacks.

    Parameters
    ----------
    system : System, or what converts to one (magrod.core.system.as_system)
        The paper's rod (0 < m < m_c = 2 sqrt(1 + gamma), gamma, delta >= 0; its mu and lambdabar are what the
        scaling varies, so they are not used), or a model with a splitting measurement: its other parameters are
        the unperturbed member's.  The old spellings ``splitting(m, gamma, delta, a, b)`` and ``m=`` work for one
        release.
    a, b : float
        mu = a eps^2, lambdabar = b eps^2, a >= 2b; a = 2b is the straight-rod saddle (an equilibrium), a > 2b the
        tilted saddle-focus.
    eps : sequence of float
        The perturbation parameters (> 0); >= 4 values give a power-law fit.
    precisions : sequence of Precision or str, optional
        The last one is the reference; default ("long double", "quad") for a = 2b, ("double", "long double")
        for a > 2b.
    n_phases, harmonics : int
        a > 2b: launch phases on the unstable eigenplane and Fourier harmonics of the fit of theta_u(psi).
    progress : callable, optional
        progress(n_eps_done).

    Returns
    -------
    Splitting
        measure (psi_u or s1) and d per eps, agreement between precisions, fit, derived leading term (a = 2b).

    Raises
    ------
    ParameterError
        Naming the argument: m >= m_c, a < 2b, eps <= 0 or empty, an unknown precision.

    Examples
    --------
    >>> import magrod as mr
    >>> spl = mr.splitting(mr.System(m=1.7, gamma=1, delta=1), a=2, b=1, eps=[0.1, 0.03, 0.01])
    >>> spl.kind, bool(spl.agreement < 1e-8), bool(all(spl.measure < 0))
    ('equilibrium', True, True)

    Notes
    -----
    The first-order Mel'nikov function vanishes identically (docs/errata.md), so the splitting is measured
    directly: the first turning point of W^u on Sigma = {pbar_theta = 0}, integrated in the body frame in each
    precision (docs/nonintegrability.md).  At a = 2b the leading term psi_u ~ b C_psi eps^2 is derived as a
    second-order Mel'nikov integral (leading_coefficient) and agrees with the measurement to 8-9 digits.  Status:
    numerical (floating point, two precisions); the rigorous statements are in docs/nonintegrability.md.  Cost:
    ~0.1 s per eps in quad (a = 2b); n_phases first crossings per eps for a > 2b.
    """
    t0 = time.perf_counter()
    sysv = None
    if m is not None or (isinstance(system, (int, float)) and not isinstance(system, bool)):
        warnings.warn("splitting(m, gamma, delta, ...) is deprecated: pass a System first, e.g. splitting(mr.System("
                      "m=1.7, gamma=1, delta=1), a=2, b=1)", DeprecationWarning, stacklevel=3)
        m = system if m is None else m
    else:
        from ..core.system import as_system

        sysv, _ = as_system(system)
        if not sysv.is_paper:
            return _model_splitting(sysv, eps, progress)
        rod = sysv.rod
        m, gamma, delta = rod.m, rod.gamma if gamma is None else gamma, rod.delta if delta is None else delta
    for name, v in (("gamma", gamma), ("delta", delta), ("a", a), ("b", b)):
        if v is None:
            raise ParameterError(name, "missing: splitting(m, gamma, delta, a, b, eps) or splitting(RodParams, a=, b=)")
    a, b = require_finite("a", a, MAX_MAGNITUDE), require_finite("b", b, MAX_MAGNITUDE)
    equilibrium = is_equilibrium_case(a, b)
    if precisions is None:
        precisions = (Precision.LONG_DOUBLE, Precision.QUAD) if equilibrium else (Precision.DOUBLE,
                                                                                   Precision.LONG_DOUBLE)
    precisions = [Precision.parse(p) for p in precisions]
    if not precisions:
        raise ParameterError("precisions", "need at least one precision (the last is the reference)")
    eps = check_eps(eps, precisions[-1])
    m, gamma, delta, a, b, _ = _check(m, gamma, delta, a, b, min(eps), precisions[-1].value)
    notes = []
    if equilibrium:
        sc = scan(m, gamma, delta, a, b, eps, precisions, progress=progress)
        ref = sc.crossings[precisions[-1]]
        measure = np.array([c.psi for c in ref])
        d = np.array([c.d for c in ref])
        agreement = max(sc.agreement_psi.values(), default=0.0)
        fit = sc.fit_psi.to_dict() if sc.fit_psi else None
        leading = None
        if sc.fit_psi is not None and b > 0:
            lt = leading_coefficient(m, gamma, delta)
            derived = b * lt.C_psi
            leading = {"derived_psi_over_eps2": derived, "measured_psi_over_eps2": sc.fit_psi.C0,
                       "digits": digits_agreeing(sc.fit_psi.C0, derived), "S": lt.S_reference, "S_error": lt.error}
        notes += sc.notes
    else:
        sc = tilted_scan(m, gamma, delta, a, b, eps, precisions, n_phases=n_phases, harmonics=harmonics,
                         progress=progress)
        measure = np.array([c.sin_coeffs[0] for c in sc.curves])
        d = np.array([c.D_amplitude for c in sc.curves])
        agreement = sc.agreement_s1 / max(float(np.max(np.abs(measure))), 1e-300)
        fit = sc.fit_s1.to_dict() if sc.fit_s1 else None
        leading = None
    if not equilibrium and fit is None:
        notes.append("no power-law fit: b = 0 or fewer than 4 eps")
    if b == 0 or (gamma == 0 and delta == 0):
        notes.append("integrable control: the splitting vanishes to the working precision")
    return Splitting(True, "; ".join(notes) or "ok", "equilibrium" if equilibrium else "tilted", float(m),
                     float(gamma), float(delta), float(a), float(b), np.asarray(eps, float),
                     [p.value for p in precisions], measure, d, float(agreement), fit, leading,
                     time.perf_counter() - t0, sc, sysv)


# why a model has no splitting measurement: what it lacks
NO_SPLITTING = {
    "kirchhoff": "it has no small parameter: the isotropic rod is integrable (m3 is an integral) and its straight "
                 "rod's stable and unstable manifolds coincide for every parameter value",
    "extensible": "it has no small parameter: the isotropic extensible rod is integrable (m3 is an integral) and its "
                  "straight rod's stable and unstable manifolds coincide for every parameter value",
    "magnetic": "it has no small parameter: the inextensible rod in a field is integrable (I2 = n.m + B lam e3.d3, "
                "eq:int2), so its straight rod's stable and unstable manifolds coincide; its extensible perturbation "
                "is the paper's rod (magnetic-extensible), whose splitting this function measures",
}


def _model_splitting(system, eps, progress=None):
    """The splitting of a non-paper model (model_splitting), or the named error."""
    from .model_splitting import EPS_DEFAULT, SPLITTING_MODELS, model_splitting

    name = system.code.name if system.code.origin == "registry" else system.model
    if name not in SPLITTING_MODELS:
        why = NO_SPLITTING.get(name, "it is not a perturbation, by a named small parameter, of an integrable rod "
                                     "whose saddle has a homoclinic manifold in closed form (the anisotropic rod "
                                     "B2 = B1 (1 + eps) and the curved rod k1 = eps are)")
        raise MissingStructure(system.model, "a small parameter",
                               f"the splitting of the separatrix needs a saddle and a small parameter, and "
                                      f"the model {system.model!r} has none: {why}")
    t0 = time.perf_counter()
    eps = EPS_DEFAULT if eps is EPS_SCAN else eps
    small = "B2" if name == "anisotropic" else "k1"
    params = {k: v for k, v in system.params.items() if k != small}
    r = model_splitting(name, eps=eps, params=params)
    e = np.array([row["eps"] for row in r.rows], float)
    c = np.array([row["A"] for row in r.rows], float)
    fit = None
    if e.size >= 2 and np.all(c != 0):
        p, logC = np.polyfit(np.log(e), np.log(np.abs(c)), 1)
        fit = {"C": float(math.copysign(math.exp(logC), c[-1])), "p": float(p)}
    leading = {"melnikov_unit": r.melnikov_unit, "measured_unit": float(c[-1] / e[-1]),
               "digits": digits_agreeing(float(c[-1] / e[-1]), r.melnikov_unit),
               "remainder_order": r.scaling_order, "quadrature_error": r.quadrature_error}
    nan = float("nan")
    return Splitting(r.success, r.message, "melnikov", nan, nan, nan, nan, nan, e, ["double"], c / e, c,
                     float(r.accuracy["A_minus_B"]), fit, leading, time.perf_counter() - t0, r, system)
