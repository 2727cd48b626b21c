"""Symmetric (reversible) multipulse homoclinic orbits of the straight rod by shooting (paper sec. 8,
fig:multimodal1, fig:multimodal2; method of van der Heijden et al. 1998, here heyoka + Newton with the
variational Jacobian).

Geometry (derive/symmetry.py, magrod/saddle.py).  The straight rod is a fixed point of the rotations G_a about
the body 3-axis, and its 2-D unstable eigenspace is one complex line on which G_a acts as the phase.  Hence
the unstable manifold is a single orbit modulo G_a: the "phase on the unstable circle" is a symmetry direction,
not a shooting unknown (checked: `phase_independence`).  Symmetric orbits hit Fix(R) = {pbar_theta = 0,
sin psi = 0} (the union of the fixed sets of the reversors G_a R_b G_-a): two conditions.  With the saddle's
energy and Casimir levels built in, the only unknown left on the orbit is the time T, so symmetric homoclinic
orbits of the straight rod are of codimension one: at given parameters they generically do not exist, and
one parameter (`free`, default lambdabar with mu = 2 lambdabar kept) is the second shooting unknown.

Shooting map: launch at x0(p) = x_eq + eps Re(v)/|Re(v)| (v the unstable eigenvector), integrate the body
frame system to time T, residual r = (pbar_theta, sin psi)(x(T)).  Newton on (T, p) with
dr/dT = grad r . f(x(T)), dr/dp = grad r . (Phi dx0/dp + dx/dpar dpar/dp), Phi and dx/dpar from heyoka's
variational equations, dx0/dp by a central difference of the launch point (the launch point only moves along
the unstable manifold to O(eps), so this term barely matters).  Converged iff max|r| <= tol (1e-10).

An N-pulse symmetric orbit has its symmetric point at the N-th zero of pbar_theta on the unstable branch
(odd N: a maximum of theta, the middle pulse; even N: the near-saddle minimum between pulses N/2 and N/2 + 1).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import heyoka as hy
import numpy as np

from ..core import systems
from ..core.errors import ParameterError, require_positive_int
from ..generated import scalars, symmetry
from ..generated.names import CHART, PARAMS
from ..core.params import RodParams
from .equilibrium import Saddle, straight_rod
from ..core.systems import CFunc, body_functions, body_to_euler

# mu is not free: it follows the free parameter so that the straight rod stays on the chart's level (mu = 2 lam)
FREE_PARAMETERS = ("lam",) + tuple(p for p in PARAMS if p not in ("mu", "lam"))
EXTENDED_EPS = 1e-9  # ... in extended precision (even crossings, see shoot)
DEFAULT_EPS = 1e-7  # distance of the launch point from the saddle (documented; results checked insensitive)
DEFAULT_TOL = 1e-10
# Newton stops after this many iterations without halving the best residual (it is then sampling rounding noise)
STALL_ITERATIONS = 4
# ... and "within the floor" means best residual <= FLOOR_FACTOR x the measured floor: the floor is a max over 8
# samples of noise about a smooth fit through the best iterate, which itself carries noise of the same size
FLOOR_FACTOR = 2.0
# a stalled Newton counts as converged if its best residual is within the measured noise floor (shoot) and below
# this cap: the double-precision floor after near-saddle passages is 1e-8..1e-7 (docstring of shoot); 1e-6 rad
# from Fix(R) is far below any feature of the orbit, and the uncertainty it leaves in the free parameter is reported
FLOOR_CAP = 1e-6
PULSE_FRACTION = 0.5  # a pulse is a theta maximum above this fraction of the largest one (a "large excursion")
R_DIAG = np.array(symmetry.REVERSOR_DIAG)


# --- compiled pieces (built once per process) --------------------------------------------------------
@lru_cache(maxsize=None)
def fix_functions():
    """Compiled Fix(R) conditions (pbar_theta, sin psi) of a body state and their gradients (2 x 9, hy.diff)."""
    x = systems.variables("body")
    c = symmetry.fix_conditions(*x)
    grads = [hy.diff(ci, xj) for ci in c for xj in x]
    return CFunc(c, x), CFunc(grads, x)


@systems.per_thread
def _crossing_integrator(fp_type=float):
    """Body-frame integrator stopping at sin(theta) pbar_theta = 0 (generated event ptheta_sin), in fp_type
    (float or np.longdouble)."""
    return systems.integrator("body", events=["ptheta_sin"], fp_type=fp_type)


@systems.per_thread
def _variational_integrator(fp_type=float):
    """Body system + first-order variational equations w.r.t. the initial state and all PARAMS (fp_type float or
    np.longdouble), built once per thread and reset for every Newton step."""
    return systems.variational_integrator("body", fp_type=fp_type, tol=0)


@systems.per_thread
def _orbit_integrator():
    return systems.integrator("body")


def fix_residual(x) -> np.ndarray:
    """(pbar_theta, sin psi) of a body state (zero on Fix(R))."""
    return fix_functions()[0](x, [])


_MU = systems.par_index("mu")


def _free_direction(params: RodParams, free: str) -> np.ndarray:
    """d(pars)/d(free): mu follows the free parameter along the straight rod's level (generated
    straight_rod_mu_gradient: d mu/d lam = 2, the saddle needs mu = 2 lam)."""
    i = systems.par_index(free)
    d = np.zeros(len(PARAMS))
    d[i] = 1.0
    d[_MU] = scalars.straight_rod_mu_gradient(**params.as_dict())[i]
    return d


def _with_free(params: RodParams, free: str | None, value: float) -> RodParams:
    if free is None:
        return params
    kw = {**params.as_dict(), free: value}
    kw["mu"] = scalars.straight_rod_mu(**kw)
    return RodParams(**kw)


# --- the unstable branch ---------------------------------------------------------------------------------
@dataclass
class Crossing:
    """A zero of pbar_theta on the unstable branch (index from 1)."""

    index: int
    t: float
    theta: float
    psi: float
    ppsi: float
    sinpsi: float


def unstable_branch(params: RodParams, *, crossings: int = 6, eps: float = DEFAULT_EPS, phase: float = 0.0,
                    t_max: float = 2000.0, saddle: Saddle | None = None, fp_type=float) -> list[Crossing]:
    """Integrate the unstable manifold from the saddle and return its first `crossings` zeros of pbar_theta.
    Mutates (reuses) the cached crossing integrator of precision fp_type (float or np.longdouble; the launch
    point is formed in the same precision).  Stops early if t_max is reached."""
    s = saddle or straight_rod(params)
    pars = params.array()
    ta = _crossing_integrator(fp_type)
    systems.reset(ta, s.launch_point(eps, phase, fp_type=fp_type), 0.0, np.asarray(pars, dtype=fp_type))
    out = []
    while len(out) < crossings:
        oc, *_ = ta.propagate_until(fp_type(t_max))
        if int(oc) != -1:
            break
        x = np.asarray(ta.state, dtype=float)
        e = dict(zip(CHART, body_to_euler(x, pars)))
        c = fix_residual(x)
        out.append(Crossing(len(out) + 1, float(ta.time), float(e["theta"]), float(e["psi"]), float(e["ppsi"]),
                            float(c[1])))
    return out


def phase_independence(params: RodParams, phases=(0.0, 1.0, 2.5), eps: float = DEFAULT_EPS, crossings: int = 3):
    """Max difference of (t, theta, psi) at the first crossings between launch phases: ~ integration error,
    i.e. the phase is a symmetry direction (module docstring)."""
    ref = unstable_branch(params, crossings=crossings, eps=eps, phase=phases[0])
    worst = 0.0
    for ph in phases[1:]:
        other = unstable_branch(params, crossings=crossings, eps=eps, phase=ph)
        for a, b in zip(ref, other):
            worst = max(worst, abs(a.t - b.t), abs(a.theta - b.theta), abs(math.sin(a.psi - b.psi)))
    return worst


# --- Newton ------------------------------------------------------------------------------------------------
@dataclass
class ShootingResult:
    """Outcome of `shoot`.  success is True only if max|residual| <= tol; then `params` holds the converged
    parameters, T the time from the launch point to the symmetric point, and `orbit()` gives the full orbit."""

    success: bool
    message: str
    iterations: int
    residual: float
    crossing: int
    free: str | None
    params: RodParams
    T: float
    eps: float
    x0: np.ndarray
    saddle_H: float
    history: list = field(default_factory=list)
    noise_floor: float = 0.0  # > 0 when converged to the measured rounding floor instead of tol (see shoot)
    precision: str = "double"
    resolution: float = math.nan  # |free - free*| bound implied by max(residual, noise_floor) and the Jacobian

    def as_dict(self) -> dict:
        return {"success": self.success, "message": self.message, "iterations": self.iterations,
                "residual": self.residual, "crossing": self.crossing, "free": self.free,
                "params": self.params.as_dict(), "T": self.T, "eps": self.eps, "noise_floor": self.noise_floor,
                "precision": self.precision, "resolution": self.resolution}


def _launch(params: RodParams, eps: float, fp_type=float):
    s = straight_rod(params)
    return s, s.launch_point(eps, fp_type=fp_type)


def _launch_derivative(params, free, eps):
    if free is None:
        return np.zeros(systems.dim("body"))
    v0 = getattr(params, free)
    h = 1e-6 * max(1.0, abs(v0))
    xp = _launch(_with_free(params, free, v0 + h), eps)[1]
    xm = _launch(_with_free(params, free, v0 - h), eps)[1]
    return (xp - xm) / (2 * h)


def _propagate_var(x0, pars, T, fp_type=float):
    """(x(T), d x(T)/d x0, d x(T)/d pars) from x0 at t = 0."""
    ta = _variational_integrator(fp_type)
    systems.reset_variational(ta, np.asarray(x0, dtype=fp_type), np.asarray(pars, dtype=fp_type))
    oc, *_ = ta.propagate_until(fp_type(T))
    if oc != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"variational integration stopped with outcome {oc}")
    return systems.variational_blocks(ta)


def shoot(params: RodParams, crossing: int, *, free: str | None = "lam", eps: float | None = None,
          tol: float = DEFAULT_TOL, max_iter: int = 25, T_guess: float | None = None,
          precision: str = "auto") -> ShootingResult:
    """Newton on (T, free parameter) for (pbar_theta, sin psi)(x(T)) = 0 at the `crossing`-th zero of pbar_theta.

    free=None is allowed only when the sin(psi) condition is void, i.e. lam = 0 (then mu = 0, the force is
    along the field and psi is a gauge): unknown T, condition pbar_theta = 0.  Cost: one variational
    integration (135 equations) per iteration, ~10-50 ms each (x10 in extended precision).

    precision "auto": double for the first crossing (no passage near the saddle before it); extended
    (np.longdouble) and eps = 1e-9 for later crossings.  Near the saddle psi is the angle of the transverse
    force rho ~ sqrt(lam) theta (~1e-6 there), so psi after (or at) a near-saddle passage inherits the O(eps^2)
    error of the linear launch and the rounding of n divided by rho: in double precision this puts a floor of
    ~1e-8..1e-7 on the residual (measured), in extended precision with eps = 1e-9 it is ~1e-11 for N = 2 and
    grows with N (~1e-9 for N = 6: each near-saddle passage amplifies the rounding).

    Near the root the residual is noise, so Newton keeps its best iterate and stops after STALL_ITERATIONS
    without halving it.  If the best residual is above tol, the noise floor there is measured (`noise_floor`:
    the non-linear part of r at a few ulp of the free parameter); the result counts as converged iff the best
    residual is within FLOOR_FACTOR x that floor and below FLOOR_CAP, with `noise_floor` set and the message
    saying so (`resolution`: how far the free parameter can be from the root, through J^-1)."""
    if precision not in ("auto", "double", "extended"):
        raise ParameterError("precision", f"must be auto, double or extended, got {precision!r}")
    ext = precision == "extended" or (precision == "auto" and crossing >= 2)
    fp = np.longdouble if ext else float
    if eps is None:
        eps = EXTENDED_EPS if ext else DEFAULT_EPS
    crossing = require_positive_int("crossing", crossing)
    if free is not None and free not in FREE_PARAMETERS:
        raise ParameterError("free", f"must be one of {FREE_PARAMETERS} or None, got {free!r}")
    void_psi = params.lam == 0.0
    if free is None and not void_psi:
        raise ParameterError("free", "symmetric homoclinic orbits of the straight rod are of codimension one "
                                     "(the launch phase is a symmetry): a free parameter is needed unless lam = 0")
    if void_psi:
        free = None
    if not (0 < eps < 1e-2):
        raise ParameterError("eps", f"must be in (0, 1e-2), got {eps}")
    p = params
    s, x0 = _launch(p, eps)
    if T_guess is None:
        br = unstable_branch(p, crossings=crossing, eps=eps, saddle=s)
        if len(br) < crossing:
            raise ParameterError("crossing", f"the unstable branch has only {len(br)} zeros of pbar_theta before "
                                             f"t = 2000 (no homoclinic level reached)")
        T_guess = br[crossing - 1].t
    T = float(T_guess)
    fcond, fgrad = fix_functions()
    history = []
    res = math.inf
    best = None  # (residual, p, T, x0, H, r, dr/dfree) of the best iterate: near the root the residual is noise
    stall = 0
    for it in range(1, max_iter + 1):
        pars = p.array()
        s, x0 = _launch(p, eps, fp)
        x, Phi, Psi = _propagate_var(x0, pars, T, fp)
        x0 = x0.astype(float)
        r = fcond(x, [])
        if void_psi:
            r = r[:1]
        res = float(np.max(np.abs(r)))
        history.append({"iteration": it, "T": T, "free_value": getattr(p, free) if free else None, "residual": res})
        if not np.isfinite(res):
            break
        if void_psi and res <= tol:
            return ShootingResult(True, f"converged in {it - 1} Newton steps", it - 1, res, crossing, free, p, T,
                                  eps, x0, s.H, history, precision="long double" if ext else "double")
        G = fgrad(x, []).reshape(-1, x.size)
        f = body_functions()["rhs"](x, pars)
        if void_psi:
            dT = -r[0] / (G[0] @ f)
            T += dT
            continue
        dxdp = Phi @ _launch_derivative(p, free, eps) + Psi @ _free_direction(p, free)
        Jm = np.column_stack([G @ f, G @ dxdp])
        if res <= tol:
            return ShootingResult(True, f"converged in {it - 1} Newton steps", it - 1, res, crossing, free, p, T,
                                  eps, x0, s.H, history, precision="long double" if ext else "double",
                                  resolution=_resolution(Jm, r))
        if best is None or res < 0.5 * best[0]:
            stall = 0
        else:
            stall += 1
        if best is None or res < best[0]:
            best = (res, p, T, x0, s.H, r, Jm)
        if stall >= STALL_ITERATIONS:
            break
        try:
            step = -np.linalg.solve(Jm, r)
        except np.linalg.LinAlgError:
            break
        # damp steps that would leave the region where the crossing index is meaningful
        v = getattr(p, free)
        lim = 0.25 * max(abs(v), 1e-6)
        if abs(step[1]) > lim:
            step *= lim / abs(step[1])
        T += step[0]
        try:
            p = _with_free(p, free, v + step[1])
        except ParameterError:
            break
    if best is not None and best[0] <= FLOOR_CAP:
        res_b, p_b, T_b, x0_b, H_b, r_b, J_b = best
        floors = noise_floor(p_b, free, crossing, T_b, r_b, J_b[:, 1], eps=eps, fp=fp)
        floor = float(np.max(floors))
        if res_b <= FLOOR_FACTOR * floor:
            unc = _resolution(J_b, np.maximum(np.abs(r_b), floors))
            return ShootingResult(True, f"converged to the noise floor of {'long double' if ext else 'double'} "
                                        f"arithmetic: residual {res_b:.2e} <= floor {floor:.2e} (tol {tol:.1e} "
                                        f"below it; {free} resolved to {unc:.1e})", len(history), res_b, crossing,
                                  free, p_b, T_b, eps, x0_b, H_b, history, noise_floor=floor,
                                  precision="long double" if ext else "double", resolution=unc)
    return ShootingResult(False, f"not converged after {len(history)} iterations (last residual {res:.3e} > "
                                 f"tol {tol:.1e})", len(history), res, crossing, free, p, T, eps, x0, math.nan,
                          history, precision="long double" if ext else "double")


def _resolution(Jm, r) -> float:
    """How far the free parameter can be from the root when |residual_j| <= r_j (componentwise):
    sum_j |(J^-1)_{1j}| r_j."""
    try:
        return float(np.abs(np.linalg.inv(Jm)[1]) @ np.broadcast_to(np.abs(np.asarray(r, dtype=float)), (2,)))
    except np.linalg.LinAlgError:
        return math.nan


def noise_floor(params: RodParams, free: str, crossing: int, T: float, r0, drdv, *, eps: float, fp=float,
                ulps: int = 64) -> np.ndarray:
    """Rounding noise of the shooting residual at (params, T), per component: max over k = +-1 .. +-4 of
    |r(v + k h) - r(v) - k h dr/dv| with h = `ulps` ulp of the free value v (T fixed).  The linear part is
    ~|dr/dv| h (subtracted), so what is left is the non-smooth part: integration rounding amplified by the
    near-saddle passages, which Newton cannot reduce.  Eight integrations without variational equations."""
    fcond, _ = fix_functions()
    v = getattr(params, free)
    h = ulps * float(np.spacing(abs(v)))
    worst = np.zeros(2)
    for k in (-4, -3, -2, -1, 1, 2, 3, 4):
        q = _with_free(params, free, v + k * h)
        x = _propagate_plain(_launch(q, eps, fp)[1], q.array(), T, fp)
        worst = np.maximum(worst, np.abs(fcond(x, []) - np.asarray(r0) - k * h * np.asarray(drdv)))
    return worst


@systems.per_thread
def _plain_integrator(fp_type=float):
    return systems.integrator("body", fp_type=fp_type)


def _propagate_plain(x0, pars, T, fp=float):
    ta = _plain_integrator(fp)
    systems.reset(ta, np.asarray(x0, dtype=fp), 0.0, np.asarray(pars, dtype=fp))
    oc, *_ = ta.propagate_until(fp(T))
    if oc != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"integration stopped with outcome {oc}")
    return np.asarray(ta.state, dtype=float)


# --- the full symmetric orbit --------------------------------------------------------------------------------
_E31, _E32 = systems.state_index("body", "e31"), systems.state_index("body", "e32")


def reversor_at(x_sym) -> np.ndarray:
    """The reversor G_a R_b G_-a (9x9) whose fixed set contains the symmetric point x_sym: a is the direction
    of e_perp there (derive/symmetry.py)."""
    a = math.atan2(x_sym[_E32], x_sym[_E31])
    c, s_ = math.cos(a), math.sin(a)
    G3 = np.array([[c, -s_, 0], [s_, c, 0], [0, 0, 1]])
    G = np.kron(np.eye(3), G3)  # the state is three body vectors (m, n, e3), each rotated by G3
    return G @ np.diag(R_DIAG) @ G.T


def orbit(result: ShootingResult, n: int = 4001) -> dict:
    """The symmetric orbit of a converged shooting result (symmetric_orbit)."""
    if not result.success:
        raise ValueError("no orbit: shooting did not converge")
    return symmetric_orbit(result.x0, result.T, result.params.array(), n)


def symmetric_orbit(x0, T, pars, n: int = 4001) -> dict:
    """A reversible orbit sampled on t in [0, 2T] (t = arclength s from the launch point x0, the symmetric point
    at t = T): first half integrated, second half its image under the reversor (x(T + s) = R x(T - s)).
    Returns body states (n, 9), reduced (theta, psi, pbar_theta, pbar_psi), Hbar along the orbit."""
    half = (n + 1) // 2
    tg = np.linspace(0.0, T, half)
    ta = _orbit_integrator()
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


def count_pulses(theta: np.ndarray) -> int:
    """Number of local maxima of theta above PULSE_FRACTION x max(theta) (large theta excursions)."""
    th = np.asarray(theta)
    if th.size < 3:
        return 0
    interior = (th[1:-1] > th[:-2]) & (th[1:-1] >= th[2:]) & (th[1:-1] > PULSE_FRACTION * th.max())
    return int(np.count_nonzero(interior))


def summarize(result: ShootingResult, orb: dict | None = None) -> dict:
    """pulses, residual, arclength (between the two eps-points: 2 T), H (and its deviation from the saddle's)."""
    orb = orb or orbit(result)
    return {"pulses": count_pulses(orb["theta"]), "crossing": result.crossing, "residual": result.residual,
            "iterations": result.iterations, "arclength": 2 * result.T, "eps": result.eps,
            "H": float(np.mean(orb["H"])), "H_saddle": result.saddle_H,
            "max_abs_H_minus_saddle": float(np.max(np.abs(orb["H"] - result.saddle_H))),
            "theta_max": float(np.max(orb["theta"])), "free": result.free,
            "params": result.params.as_dict()}


# --- search ----------------------------------------------------------------------------------------------------
def scan(params: RodParams, free: str, values, crossings: int, eps: float = DEFAULT_EPS, progress=None):
    """sin(psi) at the first `crossings` zeros of pbar_theta along the unstable branch for each value of the
    free parameter: array (len(values), crossings) (nan where the branch has fewer crossings)."""
    out = np.full((len(values), crossings), np.nan)
    for i, v in enumerate(values):
        try:
            q = _with_free(params, free, v)
            br = unstable_branch(q, crossings=crossings, eps=eps)
        except ParameterError:
            br = []
        for c in br:
            out[i, c.index - 1] = c.sinpsi
        if progress is not None:
            progress(1)
    return out


def crossing_sinpsi(params: RodParams, free: str, value: float, crossing: int, *, eps: float, fp_type=float):
    """(sin psi, t) at the `crossing`-th zero of pbar_theta on the unstable branch at free = value (mu on the
    straight rod's level), or None if the branch does not get there (or there is no saddle)."""
    try:
        br = unstable_branch(_with_free(params, free, value), crossings=crossing, eps=eps, fp_type=fp_type)
    except ParameterError:
        return None
    if len(br) < crossing:
        return None
    return br[-1].sinpsi, br[-1].t


def bisect(params: RodParams, free: str, crossing: int, a: float, b: float, *, eps: float, fp_type=float,
           rtol: float = 1e-15, max_iter: int = 60) -> dict | None:
    """Bisection on g(v) = sin psi at the `crossing`-th zero of pbar_theta over a bracket [a, b] of the free
    parameter (the pbar_theta condition holds exactly at the event, so this is the 1-D form of the shooting
    problem).  Stops at relative width rtol (a few ulp: inside the noise band it just picks a point in it).  Returns {value, T, g, width, iterations} or None if [a, b] is not
    a sign change in this precision and eps (or is a jump of psi through the chart's cut, |g(a) - g(b)| >= 1).
    Cost: one crossing integration per step (~5-50 ms in double, x10 in long double)."""
    ga, gb = (crossing_sinpsi(params, free, v, crossing, eps=eps, fp_type=fp_type) for v in (a, b))
    if ga is None or gb is None or np.sign(ga[0]) == np.sign(gb[0]) or abs(ga[0] - gb[0]) >= 1.0:
        return None
    it = 0
    mid = (ga[0], ga[1])
    while abs(b - a) > rtol * max(abs(a), abs(b)) and it < max_iter:
        it += 1
        m = 0.5 * (a + b)
        gm = crossing_sinpsi(params, free, m, crossing, eps=eps, fp_type=fp_type)
        if gm is None or abs(gm[0] - ga[0]) >= 1.0 and abs(gm[0] - gb[0]) >= 1.0:
            return None
        mid = gm
        if gm[0] == 0.0:
            a = b = m
            break
        if np.sign(gm[0]) == np.sign(ga[0]):
            a, ga = m, gm
        else:
            b, gb = m, gm
    v = 0.5 * (a + b)
    return {"value": v, "T": mid[1], "g": mid[0], "width": abs(b - a), "iterations": it}


PRECISION_FP = {"double": float, "long double": np.longdouble}
LAUNCH_DISTANCES = (1e-7, 1e-9)  # the two eps of the uncertainty estimate (errata: lam* insensitive to eps)


def free_star(params: RodParams, free: str, crossing: int, a: float, b: float, *, eps: float, precision: str,
              tol: float = DEFAULT_TOL) -> ShootingResult | None:
    """The orbit at the `crossing`-th zero in the bracket [a, b]: bisection (same eps and precision) then
    Newton on (T, free) from the bisected value; None if the bracket is not a sign change here.  A failed Newton
    is returned as such (success False)."""
    fp = PRECISION_FP[precision]
    bis = bisect(params, free, crossing, a, b, eps=eps, fp_type=fp)
    if bis is None:
        return None
    return shoot(_with_free(params, free, bis["value"]), crossing, free=free, eps=eps, tol=tol, T_guess=bis["T"],
                 precision="extended" if fp is np.longdouble else "double")


def uncertainty(params: RodParams, free: str, crossing: int, a: float, b: float, *, tol: float = DEFAULT_TOL,
                eps_values=LAUNCH_DISTANCES) -> dict:
    """The free parameter of one orbit (bracket [a, b], `crossing`) at two launch distances (eps_values) in
    double and in long double.  value: the long double run at the smaller eps; uncertainty: the larger of the
    two long double values' difference and their Newton resolutions (residual or noise floor through J^-1);
    double_check: the largest |double - value| with the double runs' resolution (the double floor after
    near-saddle passages is 1e-8..1e-6, so double only confirms the leading digits); significant: value to its
    significant digits with the uncertainty of the last digit in brackets ('0.00113526146263(9)')."""
    runs = []
    for prec in ("double", "long double"):
        for e in eps_values:
            r = free_star(params, free, crossing, a, b, eps=e, precision=prec, tol=tol)
            row = {"eps": e, "precision": prec, "success": bool(r is not None and r.success)}
            if r is not None:
                row.update({"value": getattr(r.params, free), "residual": r.residual, "T": r.T,
                            "noise_floor": r.noise_floor, "resolution": r.resolution, "message": r.message})
            runs.append(row)
    ld = [row for row in runs if row["success"] and row["precision"] == "long double"]
    dbl = [row for row in runs if row["success"] and row["precision"] == "double"]
    if len(ld) < len(eps_values):
        return {"runs": runs, "success": False}
    vals = [row["value"] for row in ld]
    value = ld[-1]["value"]
    unc = max(max(vals) - min(vals), *(row["resolution"] for row in ld))
    out = {"runs": runs, "success": True, "value": value, "uncertainty": float(unc),
           "eps_spread": float(max(vals) - min(vals)), "significant": significant(value, unc)}
    if dbl:
        out["double_check"] = {"max_abs_difference": float(max(abs(row["value"] - value) for row in dbl)),
                               "max_resolution": float(max(row["resolution"] for row in dbl))}
    return out


def significant(value: float, uncertainty: float) -> str:
    """value rounded at the decimal of its uncertainty's leading digit, that digit's uncertainty in brackets:
    (0.00113526146263, 8.7e-15) -> '0.00113526146263(9)' (i.e. +-9e-14 ... the last shown digit).  At most
    15 significant digits."""
    if value == 0 or not math.isfinite(uncertainty):
        return repr(value)
    lead = math.floor(math.log10(abs(value)))
    last = lead - 14 if uncertainty <= 0 else max(math.floor(math.log10(uncertainty)), lead - 14)
    decimals = max(0, -last)
    u = max(1, math.ceil(uncertainty / 10.0**last - 1e-9)) if uncertainty > 0 else 1
    if u >= 10:  # 9.6 rounds up a decade
        last, u = last + 1, 1
        decimals = max(0, -last)
    return f"{value:.{decimals}f}({u})"


def find_orbits(params: RodParams, *, free: str = "lam", max_pulses: int = 6, span: float = 0.5,
                samples: int = 81, eps: float | None = None, tol: float = DEFAULT_TOL, progress=None,
                max_brackets: int = 8, with_uncertainty: bool = False) -> list[dict]:
    """For N = 1..max_pulses: scan the free parameter over value * [1 - span, 1 + span] (linearly, `samples`
    points, double precision), bracket sign changes of sin(psi) at the N-th crossing, and from the brackets
    nearest to the nominal value (at most max_brackets): bisect on sin(psi) in the shooting precision (long
    double for N >= 2, as `shoot`), then Newton on (T, free) from the bisected value; keep converged orbits
    whose counted pulses equal N.  with_uncertainty: also the free parameter at two eps and two precisions
    (`uncertainty`, ~4x the cost).  Returns one entry per N (the converged orbit closest to the nominal value,
    or a failure record listing what each bracket gave)."""
    if free not in FREE_PARAMETERS:
        raise ParameterError("free", f"must be one of {FREE_PARAMETERS}, got {free!r}")
    max_pulses = require_positive_int("max_pulses", max_pulses)
    max_brackets = require_positive_int("max_brackets", max_brackets)
    straight_rod(params)  # ParameterError early if there is no saddle
    if params.lam == 0:
        # integrable case (psi is a gauge): only the primary orbit, unknown T alone
        r = shoot(params, 1, free=None, eps=eps, tol=tol)
        if not r.success:
            return [{"pulses_target": 1, "success": False, "message": r.message, "iterations": r.iterations,
                     "residual": r.residual}]
        orb = orbit(r)
        return [{"pulses_target": 1, "success": True, "message": r.message, **summarize(r, orb),
                 "free_value": None, "result": r, "orbit": orb}]
    v0 = getattr(params, free)
    if v0 == 0:
        raise ParameterError(free, "the free parameter must be non-zero to scan around it")
    vals = np.linspace(v0 * (1 - span), v0 * (1 + span), samples)
    table = scan(params, free, vals, max_pulses, DEFAULT_EPS, progress)
    found = []
    for N in range(1, max_pulses + 1):
        col = table[:, N - 1]
        idx = [i for i in range(samples - 1) if np.isfinite(col[i]) and np.isfinite(col[i + 1])
               and np.sign(col[i]) != np.sign(col[i + 1])
               # a jump of psi across +-pi/2 through the chart's cut is a sign change of sin psi through +-1: skip
               and abs(col[i] - col[i + 1]) < 1.0]
        idx.sort(key=lambda i: abs(0.5 * (vals[i] + vals[i + 1]) - v0))
        entry = {"pulses_target": N, "success": False, "message": "no sign change of sin(psi) at crossing "
                 f"{N} for {free} in [{vals[0]:.6g}, {vals[-1]:.6g}]", "brackets": len(idx), "attempts": []}
        prec = "long double" if N >= 2 else "double"
        e_N = eps if eps is not None else (EXTENDED_EPS if N >= 2 else DEFAULT_EPS)
        for i in idx[:max_brackets]:
            a, b = float(vals[i]), float(vals[i + 1])
            try:
                r = free_star(params, free, N, a, b, eps=e_N, precision=prec, tol=tol)
            except ParameterError as exc:
                entry["attempts"].append(f"[{a:.6g}, {b:.6g}]: {exc}")
                continue
            if r is None:
                entry["attempts"].append(f"[{a:.6g}, {b:.6g}]: no sign change in {prec} at eps = {e_N:g}")
                continue
            if not r.success:
                entry["attempts"].append(f"[{a:.6g}, {b:.6g}]: {r.message}")
                entry.update({"iterations": r.iterations, "residual": r.residual})
                continue
            orb = orbit(r)
            summ = summarize(r, orb)
            if summ["pulses"] != N:
                entry["attempts"].append(f"[{a:.6g}, {b:.6g}]: converged orbit has {summ['pulses']} pulses")
                continue
            entry = {"pulses_target": N, "success": True, "message": r.message, **summ, "bracket": [a, b],
                     "free_value": getattr(r.params, free), "noise_floor": r.noise_floor,
                     "precision": r.precision, "result": r, "orbit": orb}
            if with_uncertainty:
                entry["uncertainty"] = uncertainty(params, free, N, a, b, tol=tol)
            break
        if not entry["success"] and entry["attempts"]:
            entry["message"] = "; ".join(entry["attempts"])
        found.append(entry)
    return found


# --- the plotted window of Figures 6 and 7 ------------------------------------------------------------------
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
