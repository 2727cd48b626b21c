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

from . import systems
from .errors import ParameterError, require_positive_int
from .generated import scalars, symmetry
from .generated.names import CHART, PARAMS
from .params import RodParams
from .saddle import Saddle, straight_rod
from .systems import CFunc, body_functions, body_to_euler

# mu is not free: it follows the free parameter so that the straight rod stays on the chart's level (mu = 2 lam)
FREE_PARAMETERS = ("lam",) + tuple(p for p in PARAMS if p not in ("mu", "lam"))
EXTENDED_EPS = 1e-9  # ... in extended precision (even crossings, see shoot)
DEFAULT_EPS = 1e-7  # distance of the launch point from the saddle (documented; results checked insensitive)
DEFAULT_TOL = 1e-10
PULSE_FRACTION = 0.5  # a pulse is a theta maximum above this fraction of the largest one (a "large excursion")
R_DIAG = np.array(symmetry.REVERSOR_DIAG)


# --- compiled pieces (built once per process) --------------------------------------------------------
@lru_cache(maxsize=None)
def _fix_functions():
    x = systems.variables("body")
    c = symmetry.fix_conditions(*x)
    grads = [hy.diff(ci, xj) for ci in c for xj in x]
    return CFunc(c, x), CFunc(grads, x)


@systems.per_thread
def _crossing_integrator():
    """Body-frame integrator stopping at sin(theta) pbar_theta = 0 (generated event ptheta_sin)."""
    return systems.integrator("body", events=["ptheta_sin"])


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
    return _fix_functions()[0](x, [])


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
                    t_max: float = 2000.0, saddle: Saddle | None = None) -> list[Crossing]:
    """Integrate the unstable manifold from the saddle and return its first `crossings` zeros of pbar_theta.
    Mutates (reuses) the cached crossing integrator.  Stops early if t_max is reached."""
    s = saddle or straight_rod(params)
    pars = params.array()
    ta = _crossing_integrator()
    systems.reset(ta, s.launch_point(eps, phase), 0.0, pars)
    out = []
    while len(out) < crossings:
        oc, *_ = ta.propagate_until(t_max)
        if int(oc) != -1:
            break
        x = ta.state.copy()
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

    def as_dict(self) -> dict:
        return {"success": self.success, "message": self.message, "iterations": self.iterations,
                "residual": self.residual, "crossing": self.crossing, "free": self.free,
                "params": self.params.as_dict(), "T": self.T, "eps": self.eps}


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
    ~1e-8..1e-7 on the residual (measured), in extended precision with eps = 1e-9 it is ~1e-11."""
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
    fcond, fgrad = _fix_functions()
    history = []
    res = math.inf
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
        if res <= tol:
            return ShootingResult(True, f"converged in {it - 1} Newton steps", it - 1, res, crossing, free, p, T,
                                  eps, x0, s.H, history)
        G = fgrad(x, []).reshape(-1, x.size)
        f = body_functions()["rhs"](x, pars)
        if void_psi:
            dT = -r[0] / (G[0] @ f)
            T += dT
            continue
        dxdp = Phi @ _launch_derivative(p, free, eps) + Psi @ _free_direction(p, free)
        Jm = np.column_stack([G @ f, G @ dxdp])
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
    return ShootingResult(False, f"not converged after {len(history)} iterations (last residual {res:.3e} > "
                                 f"tol {tol:.1e})", len(history), res, crossing, free, p, T, eps, x0, math.nan,
                          history)


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


def find_orbits(params: RodParams, *, free: str = "lam", max_pulses: int = 6, span: float = 0.5,
                samples: int = 81, eps: float | None = None, tol: float = DEFAULT_TOL, progress=None) -> list[dict]:
    """For N = 1..max_pulses: scan the free parameter over value * [1 - span, 1 + span] (linearly, `samples`
    points), bracket sign changes of sin(psi) at the N-th crossing, Newton from the bracket nearest to the
    nominal value, and keep converged orbits whose counted pulses equal N.  Returns one entry per N (the
    converged orbit closest to the nominal value, or a failure record)."""
    if free not in FREE_PARAMETERS:
        raise ParameterError("free", f"must be one of {FREE_PARAMETERS}, got {free!r}")
    max_pulses = require_positive_int("max_pulses", max_pulses)
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
    table = scan(params, free, vals, max_pulses, eps or DEFAULT_EPS, progress)
    found = []
    for N in range(1, max_pulses + 1):
        col = table[:, N - 1]
        idx = [i for i in range(samples - 1) if np.isfinite(col[i]) and np.isfinite(col[i + 1])
               and np.sign(col[i]) != np.sign(col[i + 1])
               # a jump of psi across +-pi/2 through the chart's cut is a sign change of sin psi through +-1: skip
               and abs(col[i] - col[i + 1]) < 1.0]
        idx.sort(key=lambda i: abs(0.5 * (vals[i] + vals[i + 1]) - v0))
        entry = {"pulses_target": N, "success": False, "message": "no sign change of sin(psi) at crossing "
                 f"{N} for {free} in [{vals[0]:.6g}, {vals[-1]:.6g}]", "brackets": len(idx)}
        for i in idx[:4]:
            # secant start inside the bracket
            a, b = vals[i], vals[i + 1]
            va = a - col[i] * (b - a) / (col[i + 1] - col[i])
            q = _with_free(params, free, va)
            try:
                r = shoot(q, N, free=free, eps=eps, tol=tol)
            except ParameterError as exc:
                entry["message"] = f"bracket [{a:.6g}, {b:.6g}]: {exc}"
                continue
            if not r.success:
                entry["message"] = f"bracket [{a:.6g}, {b:.6g}]: {r.message}"
                entry.update({"iterations": r.iterations, "residual": r.residual})
                continue
            orb = orbit(r)
            summ = summarize(r, orb)
            if summ["pulses"] != N:
                entry["message"] = f"bracket [{a:.6g}, {b:.6g}]: converged orbit has {summ['pulses']} pulses"
                continue
            entry = {"pulses_target": N, "success": True, "message": r.message, **summ,
                     "free_value": getattr(r.params, free), "result": r, "orbit": orb}
            break
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
