"""The one Fix(R) shooting engine: a saddle protocol, one residual-and-Jacobian function, one crossing loop and one
variational cache, shared by the multipulse searches of both saddles (magrod.orbits.multipulse,
magrod.orbits.periodic_multipulse), continuation (magrod.orbits.continuation) and the splitting's first crossing
(magrod.separatrix.splitting).

Saddles (the protocol `Saddle`).  A saddle has `params`, `H` (its chart energy Hbar), `kind` and
`launch_point(launch_distance, angle, precision)`, the body state at the launch distance and angle `angle` on its linear unstable
manifold, formed in that precision, and `at(params)`, the same kind of saddle at other parameters.
  "equilibrium"  the straight rod at mu = 2 lam (magrod.orbits.equilibrium.StraightRod).  It is fixed by the
                 rotations G_a about the body 3-axis, which act on its unstable plane as the phase: the angle is
                 a symmetry direction (`phase_independence`), and symmetric orbits are of codimension one (a
                 parameter is the second unknown; mu follows it on mu = 2 lam, `parameter_direction`).
  "periodic"     the helical relative equilibrium at mu > 2 lam (magrod.orbits.periodic.PeriodicSaddle).  The
                 phase along the G-orbit and the angle on the unstable plane are one unknown: symmetric orbits
                 are generic, the unknowns are (T, angle).
`saddle(params)` returns the one that exists at `params`.

Shooting map.  Launch at x0 = saddle.launch_point(launch_distance, angle), integrate the body-frame system to time T,
residual r = (pbar_theta, sin psi)(x(T)), zero iff x(T) lies on Fix(R) = {pbar_theta = 0, sin psi = 0} (the union
of the fixed sets of the reversors G_a R_b G_-a, derive/symmetry.py); then the orbit is reversible (symmetric)
and homoclinic.  `residual_and_jacobian` returns r and its columns
    d/dT       = grad r . f(x(T))
    d/dangle   = grad r . Phi(T) dx0/dangle                              (periodic saddles only)
    d/dq       = grad r . (Phi(T) dx0/dq + Psi(T) dpars/dq)              (each parameter direction q)
with Phi = dx(T)/dx0, Psi = dx(T)/dpars from heyoka's variational equations (systems.cached_variational, the one
variational cache), dx0/dangle and dx0/dq by central differences of the launch point in double precision
(the saddle recomputed at q +- h: the launch moves along the manifold to O(launch_distance), so these terms barely matter).

Crossings.  Zeros of sin(theta) pbar_theta (generated event ptheta_sin) along the unstable branch, in any
precision (hy.real128 and hy.real included, as the splitting needs): `crossing_events` is the one loop,
`unstable_branch` the list of `Crossing`s.  An N-pulse symmetric orbit of the straight rod has its symmetric
point at the N-th zero of pbar_theta on the branch (odd N: a maximum of theta, the middle pulse; even N: the
near-saddle minimum between pulses N/2 and N/2 + 1).

Cost: one variational integration (9 + 9 x 14 equations) per residual-and-Jacobian (~10-50 ms in double, x10 in
long double) plus two saddle constructions per parameter direction; one event integration per branch.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Protocol, runtime_checkable

import heyoka as hy
import numpy as np

from ..core import systems
from ..core.deprecation import deprecated_attribute
from ..core.deprecation import renamed_keywords
from ..core.errors import MissingStructure, ParameterError
from ..core.params import RodParams
from ..core.precision import Precision
from ..core.results import Result, jsonable
from ..core.systems import CFunc, body_functions, body_to_euler
from ..core.tolerances import FLOOR_CAP, FLOOR_FACTOR
from ..generated import scalars, symmetry
from ..generated.names import CHART, PARAMS

N = systems.dim("body")
R_DIAG = np.array(symmetry.REVERSOR_DIAG)
PULSE_FRACTION = 0.5  # a pulse is a theta maximum above this fraction of the largest one (a "large excursion")
LAUNCH_STEP = 1e-6  # relative central-difference step of the launch point in the angle and in a parameter


# --- the saddle protocol ----------------------------------------------------------------------------------------
@runtime_checkable
class Saddle(Protocol):
    """What the shooting engine needs of a saddle (implemented by StraightRod and PeriodicSaddle)."""

    params: RodParams
    H: float  # the chart energy Hbar of the saddle

    @property
    def kind(self) -> str:  # "equilibrium" or "periodic"
        ...

    precision: Precision  # the working precision of its launch points

    def launch_point(self, launch_distance: float, angle: float = 0.0, precision=None) -> np.ndarray:
        """Body state at the launch distance, angle `angle` on the linear unstable manifold, formed in `precision`
        (default the saddle's)."""
        ...

    def at(self, params: RodParams) -> "Saddle":
        """The same kind of saddle at other parameters."""
        ...


@renamed_keywords(params="system")
def saddle(system=None, *, precision=None, M: float = 1.0, T: float = 1.0):
    """The saddle of a rod model.  The paper's rod: the straight rod (an equilibrium) when mu = 2 lam, the helical
    periodic saddle when mu > 2 lam (`paper_saddle`).  Any other model: the straight twisted rod of twisting moment
    M and tension T, or the relative equilibrium next to it on its leaf (magrod.orbits.equilibria.straight_rod),
    with its spectrum on the symplectic leaf and its kind (the anisotropic and curved rods': a saddle-focus).

    Parameters
    ----------
    system : System, or what converts to one (magrod.core.system.as_system)
        The model and its parameters (a paper panel key, a RodParams, a model name or file ...).
    precision : Precision or str, optional
        The paper's rod: the working precision of the saddle's launch points (default: the system's).
    M, T : float
        Other models: the straight rod's twisting moment and tension (the leaf searched).

    Returns
    -------
    StraightRod, PeriodicSaddle or Equilibrium
        The paper's rod: result objects of the saddle protocol; other models: an Equilibrium (x, eigenvalues on
        the leaf sorted deterministically, kind, unstable eigenvalue and phase-fixed eigenvector, `.system`).

    Raises
    ------
    ParameterError
        The paper's rod: "mu" if mu < 2 lam, "m" if not hyperbolic.  Other models: "model" if no saddle is found on
        the leaf (the equilibrium is a centre or degenerate there).

    Examples
    --------
    >>> import magrod as mr
    >>> from magrod.orbits.shooting import saddle
    >>> s = saddle(mr.RodParams(m=1.7, mu=0.002, gamma=1, delta=1, lam=0.001))
    >>> s.kind, round(s.unstable_eigenvalue.real, 6)
    ('equilibrium', 0.664602)
    >>> saddle(mr.System("anisotropic", B1=1, B2=1.02, C=1.5)).kind
    'saddle-focus'

    Notes
    -----
    The paper's rod: `paper_saddle` (mu = 2 lam decided to MU_TOL; eigen-decomposition of the compiled Jacobian, or
    Gauss-Newton and one variational integration for the periodic saddle).  Other models: Gauss-Newton on
    f(x) = 0, C(x) = c from the straight twisted rod, the spectrum of the Jacobian restricted to the symplectic
    leaf, sorted by magrod.core.eigen.order and the eigenvector's phase fixed by core.eigen.fix_phase (nothing
    LAPACK decides reaches the result); < 1 ms after the model's first compile.  Paper sec. 3 and 8.
    """
    from ..core.system import as_system

    system, _ = as_system(system)
    prec = system.precision if precision is None else Precision.parse(precision)
    if system.is_paper:
        from dataclasses import replace

        return replace(paper_saddle(system.rod, precision=prec), system=system)
    from .equilibria import straight_rod

    if prec is not Precision.DOUBLE:
        raise ParameterError("precision", f"the equilibria of the model {system.model!r} are computed in double "
                                          f"precision (their evidence: the residual max|f(x)|), got {str(prec)!r}")
    eq = straight_rod(system, M=M, T=T)
    if not eq.success or eq.kind not in ("saddle-focus", "saddle", "saddle-centre"):
        raise MissingStructure(system.model, "a saddle", f"a saddle is needed, and the model {system.model!r} has none at the straight "
                                      f"rod (M, T) = ({M:g}, {T:g}): its equilibrium there is a {eq.kind} "
                                      f"({eq.message})")
    return eq


def paper_saddle(params: RodParams, *, precision=Precision.DOUBLE) -> Saddle:
    """The saddle of the rod at `params`: the straight rod (an equilibrium) when mu = 2 lam, the helical periodic
    saddle when mu > 2 lam.

    Parameters
    ----------
    params : RodParams
        Non-dimensional parameters (eq:nondim_1).
    precision : Precision or str
        The working precision of the saddle's launch points (and of the periodic saddle's chart view, computed
        there on first use); the eigen- and Floquet data are float64 in every precision.

    Returns
    -------
    StraightRod or PeriodicSaddle
        Result objects of the saddle protocol (`kind` "equilibrium" or "periodic"), with `launch_point`,
        `H`, eigen/Floquet data and `.plot()` (the spectrum).

    Raises
    ------
    ParameterError
        "mu" if mu < 2 lam (the radicand of eq:alignment_condition is negative at the straight rod: no saddle
        near it) or no relative equilibrium is found; "m" if the saddle is not hyperbolic (e.g. m >= m_c).

    Examples
    --------
    >>> import magrod as mr
    >>> from magrod.orbits.shooting import paper_saddle
    >>> paper_saddle(mr.RodParams(m=1.7, mu=0.0021, gamma=1, delta=1, lam=0.001)).kind
    'periodic'

    Notes
    -----
    mu = 2 lam is decided to MU_TOL (64 ulp: the rounding of a decimal input).  Straight rod: eigen-decomposition
    of the compiled Jacobian (hy.diff), < 1 ms.  Periodic saddle: Gauss-Newton for the relative equilibrium
    f(x) = omega xi x, then one variational integration over a period for the monodromy (~5 ms); its checks
    (closure, M = expm(T A), symplecticity) are fields of the result.  Paper sec. 3 and 8.
    """
    from .equilibrium import is_on_level, straight_rod

    if not isinstance(params, RodParams):
        raise ParameterError("params", f"must be a RodParams, got {type(params).__name__}")
    precision = Precision.parse(precision)
    if is_on_level(params):
        return straight_rod(params, precision=precision)
    gap = params.mu - scalars.straight_rod_mu(**params.to_dict())
    if gap < 0:
        raise ParameterError("mu", f"no saddle near the straight rod for mu < 2 lam (got mu - 2 lam = {gap:.3g}): "
                                   "the radicand mu - 2 lam pbar_psi of eq:alignment_condition is negative there")
    from .periodic import periodic_saddle

    return periodic_saddle(params, precision=precision)


def moved(s: Saddle, name: str, value: float) -> RodParams:
    """The parameters of `s` with `name` = value; for the straight rod mu follows on mu = 2 lam (equilibrium.on_level)."""
    if s.kind == "equilibrium":
        from .equilibrium import on_level

        return on_level(s.params, **{name: value})
    return s.params.replace(**{name: float(value)})


def parameter_direction(s: Saddle, name: str) -> np.ndarray:
    """d pars/d name (PARAMS order): the unit vector of `name`, and for the straight rod the generated
    straight_rod_mu_gradient in mu (mu follows the parameter on mu = 2 lam: d mu/d lam = 2)."""
    i = systems.par_index(name)
    d = np.zeros(len(PARAMS))
    d[i] = 1.0
    if s.kind == "equilibrium":
        d[systems.par_index("mu")] = scalars.straight_rod_mu_gradient(**s.params.to_dict())[i]
    return d


def _parameter_step(s: Saddle, name: str, h_rel: float) -> float:
    v = getattr(s.params, name)
    h = h_rel * max(1.0, abs(v))
    if s.kind == "periodic" and name in ("mu", "lam"):  # stay on the side mu > 2 lam where the saddle exists
        gap = s.params.mu - scalars.straight_rod_mu(**s.params.to_dict())
        h = min(h, 0.25 * gap / (2.0 if name == "lam" else 1.0))
    return h


def launch_derivative(s: Saddle, name: str, launch_distance: float, angle: float = 0.0, h_rel: float = LAUNCH_STEP):
    """d x0/d name of the launch point (double precision, central difference with the saddle recomputed at
    name +- h, mu following on mu = 2 lam for the straight rod)."""
    v = getattr(s.params, name)
    h = _parameter_step(s, name, h_rel)
    xp = s.at(moved(s, name, v + h)).launch_point(launch_distance, angle, Precision.DOUBLE)
    xm = s.at(moved(s, name, v - h)).launch_point(launch_distance, angle, Precision.DOUBLE)
    return (xp - xm) / (2 * h)


# --- compiled pieces ----------------------------------------------------------------------------------------------
@systems.cache
def fix_functions():
    """Compiled Fix(R) conditions (pbar_theta, sin psi) of a body state and their gradients (2 x N, hy.diff)."""
    x = systems.variables("body")
    c = symmetry.fix_conditions(*x)
    grads = [hy.diff(ci, xj) for ci in c for xj in x]
    return CFunc(c, x), CFunc(grads, x)


def fix_residual(x) -> np.ndarray:
    """(pbar_theta, sin psi) of a body state (zero on Fix(R))."""
    return fix_functions()[0](x, [])


@systems.per_thread
def crossing_integrator(precision: Precision):
    """The body-frame integrator stopping at sin(theta) pbar_theta = 0 (generated event ptheta_sin, either
    direction) in `precision`, one per thread: every crossing loop of magrod uses it.  Multiprecision (hy.real)
    is compiled in compact mode: the unrolled hy.real code took > 4 GB and minutes of LLVM time."""
    return systems.integrator("body", events=["ptheta_sin"], precision=precision,
                              compact_mode=precision is Precision.MP)


@systems.per_thread
def body_integrator(precision: Precision):
    """The plain body-frame integrator (no events) in `precision`, one per thread (compact mode for hy.real, as
    crossing_integrator)."""
    return systems.integrator("body", precision=precision,
                              compact_mode=precision is Precision.MP)


def propagate(x0, pars, T, precision=Precision.DOUBLE) -> np.ndarray:
    """x(T) from x0 at t = 0 (plain integration in `precision`), as float64."""
    prec = Precision.parse(precision)
    fp = prec.fp_type
    ta = body_integrator(prec)
    systems.reset(ta, np.asarray(x0, dtype=fp), 0.0, np.asarray(pars, dtype=fp))
    oc, *_ = ta.propagate_until(fp(T))
    if oc != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"integration stopped with outcome {oc}")
    return np.asarray(ta.state, dtype=float)


def propagate_variational(x0, pars, T, precision=Precision.DOUBLE) -> tuple:
    """(x(T), d x(T)/d x0, d x(T)/d pars) from x0 at t = 0 with the one variational cache."""
    prec = Precision.parse(precision)
    ft = prec.fp_type
    ta = systems.cached_variational(prec)
    systems.reset_variational(ta, np.asarray(x0, dtype=ft), np.asarray(pars, dtype=ft))
    oc, *_ = ta.propagate_until(ft(T))
    if oc != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"variational integration stopped with outcome {oc}")
    return systems.variational_blocks(ta)


# --- the one residual and Jacobian -----------------------------------------------------------------------------
@dataclass
class ShootingEvaluation:
    """One evaluation of the shooting map: residual r (2,), Jacobian J (2 x (1 [+ 1] + len(free))) with columns
    d/dT [, d/dangle for a periodic saddle], d/d(free...), the launch point x0 (float64), x(T) and the saddle
    it was launched from."""

    r: np.ndarray
    J: np.ndarray
    x0: np.ndarray
    xT: np.ndarray
    saddle: object = None


def residual_and_jacobian(s: Saddle, T: float, angle: float = 0.0, *, launch_distance: float, precision=Precision.DOUBLE,
                          free: tuple = (), h_rel: float = LAUNCH_STEP, jacobian: bool = True) -> ShootingEvaluation:
    """r = (pbar_theta, sin psi)(x(T)) from the launch point of `s` at (launch_distance, angle), integrated in `precision`,
    and its Jacobian (module docstring).  free: parameter names (PARAMS), columns after d/dT (and d/dangle for
    a periodic saddle; the straight rod's angle is a symmetry and has no column).  jacobian=False skips the
    launch-point differences (J then has the d/dT column only)."""
    prec = Precision.parse(precision)
    pars = s.params.array()
    x0 = s.launch_point(launch_distance, angle, prec)
    x, Phi, Psi = propagate_variational(x0, pars, T, prec)
    fcond, fgrad = fix_functions()
    r = fcond(x, [])
    G = fgrad(x, []).reshape(-1, x.size)
    f = body_functions()["rhs"](x, pars)
    cols = [G @ f]
    if jacobian:
        if s.kind == "periodic":
            ha = h_rel
            dxa = (s.launch_point(launch_distance, angle + ha, Precision.DOUBLE)
                   - s.launch_point(launch_distance, angle - ha, Precision.DOUBLE)) / (2 * ha)
            cols.append(G @ (Phi @ dxa))
        for name in free:
            dx0 = launch_derivative(s, name, launch_distance, angle, h_rel)
            cols.append(G @ (Phi @ dx0 + Psi @ parameter_direction(s, name)))
    return ShootingEvaluation(r, np.column_stack(cols), np.asarray(x0, dtype=float), x, s)


# --- the one damped Newton ---------------------------------------------------------------------------------------
@dataclass
class NewtonRun:
    """What `newton` returns.  z: the unknowns of the returned iterate (the converged one, else the best one when
    it was accepted at the noise floor, else the last one evaluated); evaluation: what `evaluate` returned there
    (its r, J and anything the caller carries); residual: max|r| there (or `measure`); iterations: Newton steps
    taken to reach z; evaluations: calls of `evaluate`; history: [(z, residual)] per evaluation; outcome:
    "converged" (residual <= tol), "floor" (stalled, best residual within FLOOR_FACTOR x the measured noise floor
    and <= FLOOR_CAP; `noise_floor` the floor per component), or why it stopped: "max_iter", "stalled",
    "singular" (J not invertible), "non-finite", "rejected" (`evaluate` raised ParameterError: the step left
    the parameters where the problem is defined)."""

    z: np.ndarray | None
    evaluation: object
    residual: float
    iterations: int
    evaluations: int
    history: list
    outcome: str
    noise_floor: np.ndarray | None = None
    error: Exception | None = None  # the ParameterError of a "rejected" run

    @property
    def success(self) -> bool:
        return self.outcome in ("converged", "floor")


def _newton_solve(r, J, z):
    return -np.linalg.solve(J, r)


def newton(evaluate, z0, *, tol: float, max_evaluations: int, damp=None, stall: int | None = None, floor=None,
           solve=None, measure=None, min_steps: int = 0) -> NewtonRun:
    """The one damped Newton of magrod's shooting problems (the multipulse searches of both saddles, their
    continuation corrector).

    evaluate(z) -> an object with `.r` and `.J` (ShootingEvaluation, or anything carrying them) at the unknowns z;
    a ParameterError from it ends the run ("rejected": e.g. no straight rod at the stepped parameter).
    Each evaluation: residual = measure(ev) (default max|ev.r|); non-finite -> stop; residual <= tol after at
    least `min_steps` steps -> converged; else the step dz = solve(ev.r, ev.J, z) (default -J^-1 r),
    damp(dz, z) -> dz (a limit on the components that would leave the region where the problem's crossing index
    is meaningful), z += dz.  At most `max_evaluations` evaluations.

    The noise floor (stall, floor).  Near the root the residual of a shooting problem is rounding noise amplified
    by the near-saddle passages, which Newton cannot reduce: with `stall`, the best iterate is kept and the run
    stops after `stall` consecutive evaluations that fail to halve the best residual.  If it did not converge,
    floor(best_evaluation, best_z) -> the noise floor per component of r (measured by the caller, e.g.
    multipulse.noise_floor); the best iterate is accepted ("floor") iff its residual is <= FLOOR_CAP and <=
    FLOOR_FACTOR x max(floor).  Without `stall` no best is kept and the run ends at the last evaluation."""
    solve = solve or _newton_solve
    z = np.array(z0, dtype=float)
    history = []
    best = None  # (residual, z, evaluation, iterations)
    count = 0
    last = (None, None, math.inf)
    outcome, error = "max_iter", None
    for k in range(max_evaluations):
        try:
            ev = evaluate(z)
        except ParameterError as exc:
            outcome, error = "rejected", exc
            break
        res = float(np.max(np.abs(ev.r))) if measure is None else float(measure(ev))
        history.append((z.copy(), res))
        last = (z.copy(), ev, res)
        if not np.isfinite(res):
            outcome = "non-finite"
            break
        if res <= tol and k >= min_steps:
            return NewtonRun(z.copy(), ev, res, k, k + 1, history, "converged")
        if stall is not None:
            count = 0 if best is None or res < 0.5 * best[0] else count + 1
            if best is None or res < best[0]:
                best = (res, z.copy(), ev, k)
            if count >= stall:
                outcome = "stalled"
                break
        try:
            dz = solve(ev.r, ev.J, z)
        except np.linalg.LinAlgError:
            outcome = "singular"
            break
        if damp is not None:
            dz = damp(dz, z)
        z = z + dz
    if floor is not None and best is not None and best[0] <= FLOOR_CAP:
        res_b, z_b, ev_b, k_b = best
        floors = np.asarray(floor(ev_b, z_b), dtype=float)
        if res_b <= FLOOR_FACTOR * float(np.max(floors)):
            return NewtonRun(z_b, ev_b, res_b, len(history), len(history), history, "floor", floors)
    z_l, ev_l, res_l = last
    return NewtonRun(z_l, ev_l, res_l, len(history), len(history), history, outcome, error=error)


def limit_component(i: int, bound) -> callable:
    """A `damp` for `newton`: scale the whole step so that |dz_i| <= bound(z) (a float or a function of z)."""
    def damp(dz, z):
        lim = bound(z) if callable(bound) else bound
        return dz * (lim / abs(dz[i])) if abs(dz[i]) > lim else dz

    return damp


# --- the one crossing loop ----------------------------------------------------------------------------------------
@dataclass
class Crossing:
    """A zero of sin(theta) pbar_theta on an orbit (index from 1): time t, chart angles theta, psi, pbar_psi,
    and sin psi = the second Fix(R) condition (zero at a symmetric point).  Floats (rounded from the working
    precision)."""

    index: int
    t: float
    theta: float
    psi: float
    ppsi: float
    sinpsi: float


def crossing_events(x0, pars, precision=Precision.DOUBLE, *, t_max: float = 2000.0, max_events: int | None = None):
    """Yield (t, x) at each zero of sin(theta) pbar_theta along the orbit of x0 (a state in `precision`), x the
    state in that precision (a copy), until t_max or max_events.  The one crossing loop: it reuses the
    per-thread crossing integrator, so consume it before starting another."""
    prec = Precision.parse(precision)
    ta = crossing_integrator(prec)
    systems.reset_any(ta, x0, pars, prec)
    t_end = systems._fp(prec.fp_type, t_max, prec.prec)
    n = 0
    while max_events is None or n < max_events:
        oc, *_ = ta.propagate_until(t_end)
        if int(oc) != -1:
            return
        n += 1
        yield ta.time, ta.state.copy()


def crossing_at(index: int, t, x, pars) -> Crossing:
    """The Crossing record of an event state x (any precision) at time t."""
    xf = np.asarray(x, dtype=float)
    e = dict(zip(CHART, body_to_euler(xf, pars)))
    c = fix_residual(xf)
    return Crossing(index, float(t), float(e["theta"]), float(e["psi"]), float(e["ppsi"]), float(c[1]))


def unstable_branch(s: Saddle, *, crossings: int = 6, launch_distance: float, angle: float = 0.0, t_max: float = 2000.0,
                    precision=Precision.DOUBLE) -> list[Crossing]:
    """The first `crossings` zeros of pbar_theta on the unstable branch of `s` launched at (launch_distance, angle) in
    `precision` (fewer if t_max is reached first)."""
    pars = s.params.array()
    out = []
    for t, x in crossing_events(s.launch_point(launch_distance, angle, precision), pars, precision, t_max=t_max,
                                max_events=crossings):
        out.append(crossing_at(len(out) + 1, t, x, pars))
    return out


def phase_independence(s: Saddle, phases=(0.0, 1.0, 2.5), *, launch_distance: float, crossings: int = 3) -> float:
    """Max difference of (t, theta, psi) at the first crossings between launch angles of the straight rod:
    ~ integration error, i.e. the angle is a symmetry direction (module docstring)."""
    ref = unstable_branch(s, crossings=crossings, launch_distance=launch_distance, angle=phases[0])
    worst = 0.0
    for ph in phases[1:]:
        other = unstable_branch(s, crossings=crossings, launch_distance=launch_distance, angle=ph)
        for a, b in zip(ref, other):
            worst = max(worst, abs(a.t - b.t), abs(a.theta - b.theta), abs(math.sin(a.psi - b.psi)))
    return worst


# --- the symmetric orbit -----------------------------------------------------------------------------------------
_E31, _E32 = systems.state_index("body", "e31"), systems.state_index("body", "e32")


def reversor_at(x_sym) -> np.ndarray:
    """The reversor G_a R_b G_-a (N x N) whose fixed set contains the symmetric point x_sym: a is the direction
    of e_perp there (derive/symmetry.py)."""
    a = math.atan2(x_sym[_E32], x_sym[_E31])
    c, s_ = math.cos(a), math.sin(a)
    G3 = np.array([[c, -s_, 0], [s_, c, 0], [0, 0, 1]])
    G = np.kron(np.eye(N // 3), G3)  # the state is three body vectors (m, n, e3), each rotated by G3
    return G @ np.diag(R_DIAG) @ G.T


def symmetric_orbit(x0, T, pars, n: int = 4001) -> dict:
    """A reversible orbit sampled on t in [0, 2T] (t = arclength s from the launch point x0, the symmetric point
    at t = T): first half integrated, second half its image under the reversor (x(T + s) = R x(T - s)).
    Returns body states (n, N), reduced (theta, psi, pbar_theta, pbar_psi), Hbar along the orbit."""
    half = (n + 1) // 2
    tg = np.linspace(0.0, T, half)
    ta = body_integrator(Precision.DOUBLE)
    systems.reset(ta, x0, 0.0, pars)
    xs = ta.propagate_grid(tg)[-1]
    R = reversor_at(xs[-1])
    second = (R @ xs[-2::-1].T).T
    X = np.vstack([xs, second])
    t = np.concatenate([tg, 2 * T - tg[-2::-1]])
    Xc = np.ascontiguousarray(X.T)
    e = dict(zip(CHART, body_to_euler(Xc, pars)))
    H = body_functions()["H"](Xc, pars)[0]
    return {"t": t, "x": X, "theta": e["theta"], "psi": e["psi"], "ptheta": e["ptheta"], "ppsi": e["ppsi"], "H": H,
            "reversor": R}


def count_pulses(theta: np.ndarray, threshold: float | None = None) -> int:
    """Number of local maxima of theta above `threshold` (default PULSE_FRACTION x max(theta): large theta
    excursions)."""
    th = np.asarray(theta)
    if th.size < 3:
        return 0
    level = PULSE_FRACTION * th.max() if threshold is None else threshold
    interior = (th[1:-1] > th[:-2]) & (th[1:-1] >= th[2:]) & (th[1:-1] > level)
    return int(np.count_nonzero(interior))


THETA_CUT = 1e-3  # the plotted window: where theta first exceeds this (tails are straight rod to O(THETA_CUT))


def scaled_arclength(orb: dict, theta_cut: float = THETA_CUT):
    """Scaled arclength (s - s_sym)/L in [-1, 1], s_sym = T the symmetric point and L = T - s_cut with s_cut the
    first s where theta >= theta_cut; returns (tau, mask of the window)."""
    t, th = orb["t"], orb["theta"]
    T = 0.5 * (t[0] + t[-1])
    s_cut = t[np.argmax(th >= theta_cut)]
    L = T - s_cut
    tau = (t - T) / L
    return tau, np.abs(tau) <= 1.0


# --- the one orbit result ----------------------------------------------------------------------------------------
@dataclass(repr=False)
class MultipulseOrbit(Result):
    """A symmetric (reversible) homoclinic orbit to a saddle, shot onto Fix(R): the one result type of both
    multipulse searches (straight rod and periodic saddle), of continuation starts and of orbit files.

    success is True only if max|residual| <= tol (or, for the straight rod's later crossings, within the measured
    rounding floor: noise_floor > 0, message says so).  pulses: the number of pulses it was shot for (the
    crossing index for the straight rod); T: time (= arclength s) from the launch point x0 to the symmetric point;
    angle: launch angle (a symmetry direction for the straight rod, an unknown for the periodic saddle); free: the
    parameter solved for with T (straight rod; None for the periodic saddle, where the orbit is generic);
    resolution: |free - free*| bound implied by max(residual, noise_floor) through J^-1; energy_error:
    |Hbar(x(T)) - H_saddle|.  `sample(n)` gives the orbit on [0, 2T]."""

    success: bool
    message: str
    params: RodParams
    saddle: object  # the saddle the orbit is homoclinic to (StraightRod or PeriodicSaddle)
    pulses: int
    T: float
    x0: np.ndarray  # the launch point
    residual: float  # max|residual| of the symmetry condition at the last Newton step
    iterations: int  # Newton iterations taken
    launch_distance: float  # distance of the launch point from the saddle
    precision: Precision
    angle: float = 0.0
    free: str | None = None
    history: list = field(default_factory=list)  # one dict per Newton iteration: iteration, T, free_value, residual
    noise_floor: float = 0.0  # the measured rounding floor of the residual (0 where not measured)
    resolution: float = math.nan
    xT: np.ndarray | None = None  # the state at the symmetric point x(T)
    energy_error: float = math.nan
    pulses_counted: int | None = None  # pulses counted along the sampled orbit (None until counted)
    #: the free parameter's spread over launch distances and precisions (with_uncertainty only)
    uncertainty: dict | None = None

    _repr_fields = ("pulses", "kind", "T", "angle", "free_value", "residual", "launch_distance", "precision")

    @property
    def kind(self) -> str:
        """The saddle's kind: "equilibrium" (straight rod) or "periodic"."""
        return self.saddle.kind

    @property
    def saddle_H(self) -> float:
        """The saddle's level H (Hbar on the chart)."""
        return self.saddle.H

    @property
    def free_value(self):
        """The value of the free parameter (None if no parameter was freed)."""
        return None if self.free is None else getattr(self.params, self.free)

    def sample(self, n: int = 4001) -> dict:
        """The orbit on t in [0, 2T] (symmetric_orbit: n body states, chart coordinates, Hbar, the reversor) and
        the scaled arclength tau of the plotted window."""
        if not self.success:
            raise ValueError("no orbit: shooting did not converge")
        orb = symmetric_orbit(self.x0, self.T, self.params.array(), n)
        orb["tau"] = scaled_arclength(orb)[0]
        return orb

    @property
    def accuracy(self) -> dict:
        """The accuracy achieved: residual (|r| at the symmetric point), the rounding floor it reached (0 if tol was
        met), resolution of the free parameter, energy error at x(T), launch distance (launch error O(launch_distance^2))."""
        return {"residual": self.residual, "noise_floor": self.noise_floor, "resolution": self.resolution,
                "energy_error": self.energy_error, "launch_distance": self.launch_distance, "precision": self.precision.value}

    def to_dict(self, arrays: bool = True) -> dict:
        """The result as a dict: its scalar fields, and with `arrays` (default) also x0, the Newton history, the
        uncertainty and the pulses counted (JSON-able).  arrays=False: the scalar fields only, as they are."""
        d = {"success": self.success, "message": self.message, "kind": self.kind, "iterations": self.iterations,
             "residual": self.residual, "pulses": self.pulses, "free": self.free, "free_value": self.free_value,
             "params": self.params.to_dict(), "T": self.T, "angle": self.angle, "launch_distance": self.launch_distance,
             "noise_floor": self.noise_floor, "precision": self.precision.value, "resolution": self.resolution,
             "energy_error": self.energy_error, "saddle_H": self.saddle.H}
        if not arrays:
            return d
        d = jsonable(d)
        d.update({"x0": jsonable(self.x0), "history": jsonable(self.history),
                  "uncertainty": jsonable(self.uncertainty), "pulses_counted": self.pulses_counted})
        return d

    eps = deprecated_attribute("launch_distance", "eps")  # renamed: one name per quantity

    def as_dict(self) -> dict:
        """Deprecated spelling of to_dict(arrays=False) (kept for one release)."""
        import warnings

        warnings.warn("MultipulseOrbit.as_dict() is deprecated: use to_dict(arrays=False)", DeprecationWarning,
                      stacklevel=2)
        return self.to_dict(arrays=False)


@dataclass(repr=False)
class PulseSearch(Result):
    """The search for the symmetric orbits with one number of pulses (`pulses_target` = N) to one saddle: what
    magrod.orbits.multipulse.find_orbits returns per N, and MultipulseSearch.searches holds.

    orbits: the converged MultipulseOrbit(s) kept (straight rod: at most one, the one nearest the nominal value
    of the free parameter; periodic saddle: every distinct one found); samples: the sampled orbit of each
    (MultipulseOrbit.sample, the straight rod's, as its files are written from them); summary: the straight
    rod's row (pulses counted, arclength 2T, H and its deviation from the saddle's, theta_max, bracket, the free
    value, its uncertainty ...; `row()`); brackets: sign changes found by the scan; attempts: what each bracket
    gave when none was kept; iterations, residual: of the last failed Newton (nan if none ran).

    Dict access (search["result"], search["orbit"], search["residual"], ...) is the older (dict) return of
    find_orbits, kept for one release with a DeprecationWarning: use the attributes, `row()` or `to_dict()`."""

    success: bool
    message: str
    pulses_target: int  # N: the number of pulses searched for
    orbits: list = field(default_factory=list)
    samples: list = field(default_factory=list)
    summary: dict = field(default_factory=dict)
    brackets: int | None = None
    attempts: list | None = None
    iterations: int | None = None  # Newton iterations of the last failed attempt (None if none ran)
    residual: float = math.nan

    _repr_fields = ("pulses_target", "n_orbits", "residual")

    @property
    def n_orbits(self) -> int:
        """The number of orbits kept."""
        return len(self.orbits)

    @property
    def orbit(self):
        """The (first) orbit found, or None."""
        return self.orbits[0] if self.orbits else None

    @property
    def uncertainty(self):
        """The free parameter's uncertainty of the orbit kept (the summary's; None unless searched with it)."""
        return self.summary.get("uncertainty")

    @property
    def accuracy(self) -> dict:
        """The accuracy achieved: the orbits' residuals and noise floors (each orbit's `accuracy` has the rest)."""
        return {"max_residual": max((o.residual for o in self.orbits), default=self.residual),
                "max_noise_floor": max((o.noise_floor for o in self.orbits), default=0.0)}

    def row(self) -> dict:
        """The search as one flat record (the table row of `magrod multipulse` and the figures): pulses_target,
        success, message, then the straight rod's summary, or brackets, attempts (and the last failed Newton's
        iterations and residual) for a failure."""
        out = {"pulses_target": self.pulses_target, "success": self.success, "message": self.message}
        if self.success:
            out.update(self.summary)
            return out
        if self.brackets is not None:
            out["brackets"] = self.brackets
        if self.attempts is not None:
            out["attempts"] = self.attempts
        if self.iterations is not None:
            out.update({"iterations": self.iterations, "residual": self.residual})
        return out

    def to_dict(self) -> dict:
        return jsonable(self.row())

    def _legacy(self) -> dict:
        d = self.row()
        if self.success and self.orbits and self.samples:
            d.update({"result": self.orbits[0], "orbit": self.samples[0]})
        return d

    def _warn(self):
        import warnings

        warnings.warn("find_orbits' entries are PulseSearch results: dict access is deprecated and goes "
                      "in the next release; use the attributes (orbit, samples, summary), row() or to_dict()",
                      DeprecationWarning, stacklevel=3)

    def __getitem__(self, key):
        self._warn()
        return self._legacy()[key]

    def get(self, key, default=None):
        self._warn()
        return self._legacy().get(key, default)

    def __contains__(self, key) -> bool:
        self._warn()
        return key in self._legacy()

    def keys(self):
        self._warn()
        return self._legacy().keys()

    def items(self):
        self._warn()
        return self._legacy().items()


def shooting_precision(crossing: int, precision=None) -> Precision:
    """The precision of a shot at the `crossing`-th zero: `precision` if given (a Precision or its value), else
    double for the first crossing (no passage near the saddle before it) and long double from the second on
    (after a near-saddle passage psi inherits the launch error divided by the small transverse force)."""
    if precision is None:
        return Precision.DOUBLE if crossing == 1 else Precision.LONG_DOUBLE
    return Precision.parse(precision)


@dataclass(repr=False)
class MultipulseSearch(Result):
    """The symmetric multipulse homoclinic orbits found at (or, for the straight rod, near) `params`: `orbits`
    (MultipulseOrbit, ordered by pulses; indexable: search[0]), `searches` (one PulseSearch per N = 1..max_pulses,
    with the straight rod's sampled orbits and summary rows), `failures` (the PulseSearch of each N without an
    orbit), the saddle, and the search settings (free, span, samples: None where they do not apply)."""

    success: bool
    message: str
    params: RodParams
    saddle: object  # the saddle the orbits are homoclinic to (StraightRod, PeriodicSaddle or Equilibrium)
    orbits: list  # the orbits found (MultipulseOrbit; SymmetricOrbit for other models), ordered by pulses
    failures: list = field(default_factory=list)  # the PulseSearch of each N without an orbit
    max_pulses: int = 0
    free: str | None = None
    wall_time_s: float = 0.0  # wall time of the search
    searches: list = field(default_factory=list)  # one PulseSearch per N = 1..max_pulses
    span: float | None = None
    samples: int | None = None
    with_uncertainty: bool = False
    system: object = None  # what was studied

    _repr_fields = ("kind", "params", "pulses", "failures")

    @property
    def kind(self) -> str:
        """The saddle's kind."""
        return self.saddle.kind

    @property
    def pulses(self) -> list:
        """The pulse numbers of the orbits found."""
        return [o.pulses for o in self.orbits]

    def __len__(self) -> int:
        return len(self.orbits)

    @property
    def accuracy(self) -> dict:
        """The accuracy achieved: the largest residual and noise floor over the orbits found (each orbit's own
        `accuracy` has the rest)."""
        return {"max_residual": max((o.residual for o in self.orbits), default=math.nan),
                "max_noise_floor": max((o.noise_floor for o in self.orbits), default=0.0)}

    def __getitem__(self, i) -> MultipulseOrbit:
        return self.orbits[i]

    def __iter__(self):
        return iter(self.orbits)

    def search(self, pulses: int) -> PulseSearch:
        """The PulseSearch of `pulses` pulses."""
        for ps in self.searches:
            if ps.pulses_target == pulses:
                return ps
        raise ParameterError("pulses", f"not searched: N = 1..{self.max_pulses}, got {pulses!r}")

    def to_dict(self) -> dict:
        return {"success": self.success, "status": self.status, "message": self.message, "kind": self.kind,
                "params": self.params.to_dict(), "saddle_H": self.saddle.H, "max_pulses": self.max_pulses,
                "free": self.free, "span": self.span, "samples": self.samples,
                "with_uncertainty": self.with_uncertainty, "orbits": [o.to_dict() for o in self.orbits],
                "searches": [ps.to_dict() for ps in self.searches],
                "failures": [f.to_dict() for f in self.failures], "accuracy": jsonable(self.accuracy),
                "wall_time_s": self.wall_time_s}
