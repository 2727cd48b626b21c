"""Pseudo-arclength continuation (Keller 1977; e.g. Kuznetsov, Elements of Applied Bifurcation Theory, sec. 10.2)
of solution branches of F(u) = 0, F: R^{n+1} -> R^n, with fold detection -- a small layer on the Newton +
variational-Jacobian shooting maps magrod already has (no maintained Python continuation library exists).

Algorithm.  At a point u_k with unit tangent t_k (the null vector of the n x (n+1) Jacobian F_u, oriented so
that t_k . t_{k-1} > 0): predictor u* = u_k + ds t_k; corrector Newton on
    F(u) = 0,  t_k . (u - u*) = 0          (the bordered (n+1) x (n+1) system [F_u; t_k^T]),
converged when max|F| <= tol.  Step control: ds halves on failure (down to ds_min), grows by 1.5 after a quick
(<= 3 Newton steps) convergence (up to ds_max).  All arclength geometry is in scaled variables u / scale, so that
unknowns of different size (T ~ 100, lambdabar ~ 1e-3) count alike.  A fold of the parameter u[par] is a sign
change of t[par] between consecutive points; it is located by regula falsi (Illinois variant) on t[par] = 0 along
the chord between the two points, each iterate corrected onto the branch (so the fold comes out the same from
either side: tests/test_continuation.py crosses a real fold of 2-pulse orbits forward and back).

Problems (each a function returning F(u), F_u(u)):
  mu2lam_problem    symmetric N-pulse orbits of the straight rod on mu = 2 lambdabar (codimension one), u = (T,
                    lambdabar, q) with q = m, gamma or delta: a curve in the (lambdabar, q) plane
  periodic_problem  symmetric homoclinic orbits to the periodic saddle (mu > 2 lambdabar), u = (T, angle, q),
                    q = lam, mu or m
Costs: one variational integration (+ 2 per free parameter for the launch-point difference) per Newton step.
"""
from __future__ import annotations

import math


from ..core.deprecation import renamed_keywords
from ..core.errors import ParameterError, require_positive_int
from ..core.params import RodParams
from ..core.precision import Precision
from ..core.tolerances import LAUNCH_DISTANCE, SHOOTING_TOL
from .equilibrium import on_level, straight_rod
from .shooting import shooting_precision
from .periodic import periodic_saddle
from .shooting import residual_and_jacobian
from .arclength import Branch, correct, fold_summary, point_at, pseudo_arclength  # noqa: F401  (their home)


MU2LAM_FREE = ("m", "gamma", "delta")


def mu2lam_problem(base: RodParams, second: str = "m", *, launch_distance: float = LAUNCH_DISTANCE[Precision.LONG_DOUBLE],
                   precision=Precision.LONG_DOUBLE):
    """F(T, lam, q) = (pbar_theta, sin psi)(x(T)) for the straight rod's unstable manifold on mu = 2 lam, q =
    `second` (m, gamma or delta); residual and Jacobian from the one engine (shooting.residual_and_jacobian, mu
    following lam).  Returns (F, params_of(u))."""
    if second not in MU2LAM_FREE:
        raise ParameterError("second", f"must be one of {MU2LAM_FREE}, got {second!r}")
    prec = Precision.parse(precision)

    def params_of(u):
        # stay on mu = 2 lam, where the straight rod is the saddle
        return on_level(base, lam=float(u[1]), **{second: float(u[2])})

    def F(u):
        ev = residual_and_jacobian(straight_rod(params_of(u)), u[0], launch_distance=launch_distance, precision=prec, free=("lam", second))
        return ev.r, ev.J

    return F, params_of


PERIODIC_FREE = ("lam", "mu", "m", "gamma", "delta")


def periodic_problem(base: RodParams, free: str, pulses: int, *, launch_distance: float | None = None, precision=None):
    """F(T, angle, q) for symmetric homoclinic orbits to the periodic saddle (magrod.orbits.periodic_multipulse),
    q = `free`; the periodic saddle is computed once per point u.  Returns (F, params_of(u))."""
    if free not in PERIODIC_FREE:
        raise ParameterError("free", f"must be one of {PERIODIC_FREE}, got {free!r}")
    prec = shooting_precision(pulses, precision)
    launch_distance = launch_distance if launch_distance is not None else LAUNCH_DISTANCE[prec]

    def params_of(u):
        return base.replace(**{free: float(u[2])})

    def F(u):
        ev = residual_and_jacobian(periodic_saddle(params_of(u)), u[0], u[1], launch_distance=launch_distance, precision=prec, free=(free,))
        return ev.r, ev.J

    return F, params_of


def wrap_angle(a: float) -> float:
    return math.remainder(a, 2 * math.pi) % (2 * math.pi)


@renamed_keywords(params="system")
def continue_branch(system=None, orbit=None, parameter: str = "mu", steps: int = 50, *, ds: float = 0.1,
                    direction: int = 1, bounds: tuple | None = None, tol: float | None = None,
                    progress=None) -> Branch:
    """Follow a symmetric homoclinic orbit, or an equilibrium, through parameter space by pseudo-arclength
    continuation, with its folds.

    Parameters
    ----------
    system : System, or what converts to one (magrod.core.system.as_system)
        The model and its parameters at the start.  The old spelling ``continue_branch(orbit, parameter, steps)``
        (the orbit first) works for one release.
    orbit : MultipulseOrbit, SymmetricOrbit or Equilibrium
        Any model: a symmetric homoclinic orbit (homoclinic_orbit; unknowns u = (alpha, T, parameter), the
        equilibrium recomputed on the start's leaf at each point) or an equilibrium (saddle; u = (x, parameter)).
        The paper's rod: a converged orbit (from multipulse_orbits).  Straight rod (mu = 2 lam, codimension one): the branch is a
        curve in the (lam, parameter) plane, unknowns u = (T, lam, parameter), mu = 2 lam kept.  Periodic saddle
        (mu > 2 lam, generic): u = (T, launch angle, parameter).
    parameter : str
        The continuation parameter: lam, mu, m, gamma or delta for the periodic saddle; m, gamma or delta for
        the straight rod (lam is already an unknown there and mu follows it).
    steps : int
        Points after the first (>= 1).
    ds : float
        Initial scaled arclength step, in (0, 1] (grows to 0.5 after quick corrector convergence).
    direction : int
        +1 or -1: initial direction in the parameter.
    bounds : (lo, hi), optional
        Stop when the parameter leaves [lo, hi].
    tol : float
        Corrector tolerance on max ``|(pbar_theta, sin psi)(x(T))|``.
    progress : callable, optional
        progress(1) after each point.

    Returns
    -------
    Branch
        Points u, unit tangents, residuals, Newton iterations, folds of the parameter (located by regula falsi),
        names, success/message; `.plot()`.

    Raises
    ------
    ParameterError
        "orbit" if not a converged MultipulseOrbit; "parameter" if not a continuation parameter of this kind of
        orbit; "steps", "ds", "direction" or "bounds" if out of range.

    Examples
    --------
    >>> import magrod as mr
    >>> from magrod.orbits.continuation import continue_branch
    >>> from magrod.orbits.multipulse import multipulse_orbits
    >>> primaries = multipulse_orbits(mr.RodParams(m=1.7, mu=0.0021, gamma=1, delta=1, lam=0.001), max_pulses=1)
    >>> br = continue_branch(primaries[0].params, primaries[0], parameter="mu", steps=3, ds=0.2)
    >>> br.success, br.points, br.names
    (True, 4, ('T', 'angle', 'mu'))
    >>> br.max_residual <= 1e-10
    True

    Notes
    -----
    Method: pseudo-arclength continuation (Keller 1977; Kuznetsov, Elements of Applied Bifurcation Theory,
    sec. 10.2) of F(u) = (pbar_theta, sin psi)(x(T)) = 0 with the one shooting engine's Jacobian (variational
    equations; launch-point differences with the saddle recomputed at each point); folds are sign changes of the
    tangent's parameter component, located by Illinois regula falsi.  The orbit's launch distance and precision
    are kept (T depends on launch_distance).  Cost: one variational integration and two saddle constructions per parameter
    direction per Newton step (~0.05-0.5 s per point).  Accuracy: every point has max|F| <= tol.
    """
    from ..core.system import as_system
    from .equilibria import Equilibrium
    from .reversible import SymmetricOrbit, continue_equilibrium, continue_homoclinic
    from .shooting import MultipulseOrbit

    if orbit is None or isinstance(orbit, str):
        # the old call continue_branch(orbit, parameter, steps): the orbit first
        import warnings

        warnings.warn("continue_branch(orbit, parameter, ...) is deprecated: call continue_branch(system, orbit, "
                      "parameter=...)", DeprecationWarning, stacklevel=3)
        if isinstance(orbit, str):
            if isinstance(parameter, int) and not isinstance(parameter, bool):
                steps = parameter
            parameter = orbit
        orbit, system = system, None
    if system is None:
        system = getattr(orbit, "system", None) or getattr(orbit, "params", None)
    system, _ = as_system(system)
    if isinstance(orbit, (SymmetricOrbit, Equilibrium)):
        if not orbit.success:
            raise ParameterError("orbit", "must be a converged orbit or equilibrium")
        if orbit.system != system:
            raise ParameterError("system", f"the orbit was computed for {orbit.system!r}, not {system!r}: pass its "
                                           "own system (orbit.system) to start the branch from it")
        steps = require_positive_int("steps", steps)
        if not (0 < float(ds) <= 1):
            raise ParameterError("ds", f"must be in (0, 1], got {ds}")
        if direction not in (-1, 1):
            raise ParameterError("direction", f"must be +1 or -1, got {direction!r}")
        go = continue_homoclinic if isinstance(orbit, SymmetricOrbit) else continue_equilibrium
        return go(system, orbit, parameter, steps=steps, ds=float(ds), direction=direction, bounds=bounds, tol=tol)
    tol = SHOOTING_TOL if tol is None else float(tol)
    if not isinstance(orbit, MultipulseOrbit) or not orbit.success:
        raise ParameterError("orbit", "must be a converged MultipulseOrbit (magrod.orbits.multipulse.multipulse_orbits)")
    steps = require_positive_int("steps", steps)
    if not (0 < float(ds) <= 1):
        raise ParameterError("ds", f"must be in (0, 1], got {ds}")
    if direction not in (-1, 1):
        raise ParameterError("direction", f"must be +1 or -1, got {direction!r}")
    p = orbit.params
    if orbit.kind == "equilibrium":
        if parameter not in MU2LAM_FREE:
            raise ParameterError("parameter", f"an orbit of the straight rod (mu = 2 lam) is continued in one of "
                                              f"{MU2LAM_FREE} (lam is an unknown and mu follows it), got {parameter!r}")
        F, _ = mu2lam_problem(p, parameter, launch_distance=orbit.launch_distance, precision=orbit.precision)
        v = getattr(p, parameter)
        u0, names = [orbit.T, p.lam, v], ("T", "lam", parameter)
        scale = [orbit.T, abs(p.lam) or 1e-3, max(1.0, abs(v))]
    else:
        if parameter not in PERIODIC_FREE:
            raise ParameterError("parameter", f"must be one of {PERIODIC_FREE}, got {parameter!r}")
        F, _ = periodic_problem(p, parameter, orbit.pulses, launch_distance=orbit.launch_distance, precision=orbit.precision)
        v = getattr(p, parameter)
        u0, names = [orbit.T, orbit.angle, v], ("T", "angle", parameter)
        gap = p.mu - 2 * p.lam
        scale = [10.0, 1.0, gap if parameter in ("mu", "lam") else max(abs(v), 1e-3) * 0.1]
    bd = None
    if bounds is not None:
        try:
            lo, hi = (float(b) for b in bounds)
        except (TypeError, ValueError):
            raise ParameterError("bounds", f"must be a pair (lo, hi), got {bounds!r}") from None
        if not lo < hi:
            raise ParameterError("bounds", f"need lo < hi, got {bounds!r}")
        bd = {2: (lo, hi)}
    br = pseudo_arclength(F, u0, scale=scale, ds=float(ds), ds_max=max(float(ds), 0.5), steps=steps, par=2,
                          direction=direction, bounds=bd, names=names, tol=tol, progress=progress)
    br.kind, br.parameter, br.pulses, br.start = orbit.kind, parameter, orbit.pulses, p
    br.system = as_system(p, precision=system.precision)[0]  # the branch's start: the orbit's own parameters
    return br
