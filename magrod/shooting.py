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
import time
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import heyoka as hy
import numpy as np

from .errors import ParameterError, require_positive_int
from .generated import body, symmetry
from .params import RodParams
from .saddle import Saddle, straight_rod
from .systems import CFunc, body_functions, body_integrator, body_to_euler, body_vars

FREE_PARAMETERS = ("lam", "gamma", "delta", "m")
EXTENDED_EPS = 1e-9  # ... in extended precision (even crossings, see shoot)
DEFAULT_EPS = 1e-7  # distance of the launch point from the saddle (documented; results checked insensitive)
DEFAULT_TOL = 1e-10
PULSE_FRACTION = 0.5  # a pulse is a theta maximum above this fraction of the largest one (a "large excursion")
R_DIAG = np.array(symmetry.REVERSOR_DIAG)


# --- compiled pieces (built once per process) --------------------------------------------------------
@lru_cache(maxsize=None)
def _fix_functions():
    x = body_vars()
    c = symmetry.fix_conditions(*x)
    grads = [hy.diff(ci, xj) for ci in c for xj in x]
    return CFunc(c, x), CFunc(grads, x)


@lru_cache(maxsize=None)
def _rhs_function():
    x = body_vars()
    return CFunc(body.rhs(*x, *body.pars()), x)


@lru_cache(maxsize=None)
def _crossing_integrator():
    """Body-frame integrator with a stopping event at m1 e32 - m2 e31 = 0 (i.e. pbar_theta sin(theta) = 0)."""
    m1, m2, _, _, _, _, e1, e2, _ = body_vars()
    return body_integrator(np.zeros(9), np.ones(5), t_events=[hy.t_event(m1 * e2 - m2 * e1)])


@lru_cache(maxsize=None)
def _variational_integrator(fp_type=float):
    """Body system + first-order variational equations w.r.t. the 9 initial values and the 5 parameters
    (fp_type float or np.longdouble)."""
    sys_ = body.system()
    xs = [v for v, _ in sys_]
    vsys = hy.var_ode_sys(sys_, xs + [hy.par[i] for i in range(5)], order=1)
    if fp_type is float:
        return hy.taylor_adaptive(vsys, [0.0] * 9, pars=[1.0] * 5, compact_mode=True, tol=0.0)
    return hy.taylor_adaptive(vsys, [fp_type(0)] * 9, pars=[fp_type(1)] * 5, compact_mode=True,
                              tol=fp_type(0), fp_type=fp_type)


def fix_residual(x) -> np.ndarray:
    """(pbar_theta, sin psi) of a body state (zero on Fix(R))."""
    return _fix_functions()[0](x, [])


def _free_direction(free: str) -> np.ndarray:
    """d(pars)/d(free): lam moves mu = 2 lam along with it (the saddle needs mu = 2 lam)."""
    d = np.zeros(5)
    if free == "lam":
        d[4], d[1] = 1.0, 2.0
    else:
        d[("m", "mu", "gamma", "delta", "lam").index(free)] = 1.0
    return d


def _with_free(params: RodParams, free: str | None, value: float) -> RodParams:
    if free is None:
        return params
    kw = params.as_dict()
    kw[free] = value
    if free == "lam":
        kw["mu"] = 2 * value
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
    ta.time = 0.0
    ta.state[:] = s.launch_point(eps, phase)
    ta.pars[:] = pars
    ta.reset_cooldowns()
    out = []
    while len(out) < crossings:
        oc, *_ = ta.propagate_until(t_max)
        if int(oc) != -1:
            break
        x = ta.state.copy()
        th, ps, _, _, pp = body_to_euler(x, pars)
        c = fix_residual(x)
        out.append(Crossing(len(out) + 1, float(ta.time), float(th), float(ps), float(pp), float(c[1])))
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
        return np.zeros(9)
    v0 = getattr(params, free)
    h = 1e-6 * max(1.0, abs(v0))
    xp = _launch(_with_free(params, free, v0 + h), eps)[1]
    xm = _launch(_with_free(params, free, v0 - h), eps)[1]
    return (xp - xm) / (2 * h)


def _propagate_var(x0, pars, T, fp_type=float):
    ta = _variational_integrator(fp_type)
    ta.time = fp_type(0)
    st = np.zeros(ta.dim, dtype=fp_type)
    st[:9] = x0
    # d x_i / d x0_j = delta_ij, d x_i / d par_k = 0: layout x_i block of 14 entries after the 9 states
    for i in range(9):
        st[9 + 14 * i + i] = 1.0
    ta.state[:] = st
    ta.pars[:] = np.asarray(pars, dtype=fp_type)
    oc, *_ = ta.propagate_until(fp_type(T))
    if oc != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"variational integration stopped with outcome {oc}")
    s = ta.state
    x = s[:9].copy()
    D = s[9:].reshape(9, 14).astype(float)
    return x, D[:, :9].copy(), D[:, 9:].copy()


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
        G = fgrad(x, []).reshape(2, 9)
        f = _rhs_function()(x, pars)
        if void_psi:
            dT = -r[0] / (G[0] @ f)
            T += dT
            continue
        dxdp = Phi @ _launch_derivative(p, free, eps) + Psi @ _free_direction(free)
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
def reversor_at(x_sym) -> np.ndarray:
    """The reversor G_a R_b G_-a (9x9) whose fixed set contains the symmetric point x_sym: a is the direction
    of e_perp there (derive/symmetry.py)."""
    a = math.atan2(x_sym[7], x_sym[6])
    c, s_ = math.cos(a), math.sin(a)
    G3 = np.array([[c, -s_, 0], [s_, c, 0], [0, 0, 1]])
    G = np.kron(np.eye(3), G3)
    return G @ np.diag(R_DIAG) @ G.T


def orbit(result: ShootingResult, n: int = 4001) -> dict:
    """The symmetric orbit sampled on t in [0, 2T] (t = arclength s from the launch point): first half
    integrated, second half its image under the reversor (x(T + s) = R x(T - s)).  Returns body states
    (n, 9), reduced (theta, psi, pbar_theta, pbar_psi), Hbar along the orbit."""
    if not result.success:
        raise ValueError("no orbit: shooting did not converge")
    p = result.params
    pars = p.array()
    half = (n + 1) // 2
    tg = np.linspace(0.0, result.T, half)
    ta = body_integrator(result.x0, pars)
    xs = ta.propagate_grid(tg)[5]
    R = reversor_at(xs[-1])
    second = (R @ xs[-2::-1].T).T
    X = np.vstack([xs, second])
    t = np.concatenate([tg, 2 * result.T - tg[-2::-1]])
    Xc = np.ascontiguousarray(X.T)
    th, ps, _, pt, pp = body_to_euler(Xc, pars)
    H = body_functions()["H"](Xc, pars)[0]
    return {"t": t, "x": X, "theta": th, "psi": ps, "ptheta": pt, "ppsi": pp, "H": H, "reversor": R}


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
            progress.update(1)
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


# --- Figures 6 and 7 -----------------------------------------------------------------------------------------
FIGURES = {
    6: {"params": RodParams(m=1.7, mu=0.002, gamma=1.0, delta=1.0, lam=0.001), "show": (2, 4),
        "label": "fig:multimodal1", "caption": "two-pulse (solid) and four-pulse (dashed)"},
    7: {"params": RodParams(m=1.7, mu=1.0, gamma=0.01, delta=0.01, lam=0.5), "show": (2, 3),
        "label": "fig:multimodal2", "caption": "two-pulse (solid) and three-pulse (dashed)"},
}
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


def write_orbit(entry: dict, out_dir, stem: str, extra: dict | None = None):
    """Orbit data as .npz (t, body states, reduced coordinates, launch point, pars) + JSON sidecar."""
    from .io import atomic_savez, atomic_write_json, versions

    orb, r = entry["orbit"], entry["result"]
    tau, _ = scaled_arclength(orb)
    npz = atomic_savez(Path(out_dir) / f"{stem}.npz", t=orb["t"], x=orb["x"], theta=orb["theta"], psi=orb["psi"],
                       ptheta=orb["ptheta"], ppsi=orb["ppsi"], H=orb["H"], tau=tau, x0=r.x0, T=r.T, eps=r.eps,
                       pars=r.params.array(), reversor=orb["reversor"])
    meta = {k: v for k, v in entry.items() if k not in ("result", "orbit")}
    meta.update({"shooting": r.as_dict(), "history": r.history, "versions": versions(),
                 "scale": "B = C = m3 = 1 (derive/numeric_scale.py): t = s, lengths in units of B/m3",
                 "tau": f"(s - T)/L, L = T - s(theta first >= {THETA_CUT})", **(extra or {})})
    js = atomic_write_json(Path(out_dir) / f"{stem}.json", meta)
    return [str(npz), str(js)]


def multipulse(params: RodParams, out_dir=None, *, free: str = "lam", max_pulses: int = 6, span: float = 0.5,
               samples: int = 81, stem: str = "multipulse", quiet: bool = True) -> dict:
    """find_orbits + files: one .npz/.json per orbit found and a table (JSON) of all N <= max_pulses."""
    from tqdm import tqdm

    from .io import atomic_write_json, ensure_writable_dir, versions

    straight_rod(params)  # bad input fails before any file is written
    if out_dir is not None:
        ensure_writable_dir(out_dir)
    t0 = time.perf_counter()
    with tqdm(total=samples, desc=f"scan {free}", disable=quiet, file=__import__("sys").stderr) as bar:
        found = find_orbits(params, free=free, max_pulses=max_pulses, span=span, samples=samples, progress=bar)
    rows = []
    for e in found:
        row = {k: v for k, v in e.items() if k not in ("result", "orbit")}
        if e["success"] and out_dir is not None:
            row["paths"] = write_orbit(e, out_dir, f"{stem}_N{e['pulses']}",
                                       {"nominal_params": params.as_dict(), "free": free})
        rows.append(row)
    out = {"ok": True, "params": params.as_dict(), "free": free, "span": span, "samples": samples,
           "orbits": rows, "wall_time_s": time.perf_counter() - t0,
           "note": "symmetric homoclinic orbits of the straight rod are of codimension one (the launch phase is a "
                   f"symmetry): each orbit exists at its own value of {free}, found by Newton on (T, {free})"}
    if out_dir is not None:
        out["table"] = str(atomic_write_json(Path(out_dir) / f"{stem}_table.json", {**out, "versions": versions()}))
    return out, found


def _figure(number: int, out_dir, quick: bool = False, quiet: bool = True) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .io import atomic_savefig, ensure_writable_dir

    spec = FIGURES[number]
    out_dir = ensure_writable_dir(out_dir)
    max_pulses = max(spec["show"]) if quick else 6
    summary, found = multipulse(spec["params"], out_dir, max_pulses=max_pulses, samples=41 if quick else 81,
                                stem=f"figure{number}", quiet=quiet)
    paths = [summary["table"]]
    for row in summary["orbits"]:
        paths += row.get("paths", [])
    fig, ax = plt.subplots(figsize=(7, 3.2))
    for N, style in zip(spec["show"], ("-", "--")):
        e = found[N - 1]
        if not e["success"]:
            continue
        tau, win = scaled_arclength(e["orbit"])
        ax.plot(tau[win], e["orbit"]["theta"][win], style, color="k", lw=1.2,
                label=f"{N}-pulse, lam = {e['free_value']:.6g}, residual {e['residual']:.1e}")
    p = spec["params"]
    ax.set_xlim(-1, 1)
    ax.set_ylim(bottom=0)
    ax.set_xlabel(r"$(s - s_{sym})/L$")
    ax.set_ylabel(r"$\theta$")
    ax.set_title(f"Fig. {number} ({spec['label']}): m={p.m}, gamma={p.gamma}, delta={p.delta}, mu = 2 lam "
                 f"(paper lam={p.lam})", fontsize=9)
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    paths.append(str(atomic_savefig(fig, Path(out_dir) / f"figure{number}.png", dpi=150)))
    plt.close(fig)
    # 3-D rod shapes of the orbits shown (directors + extensible centreline, magrod.rod)
    from . import rod as rodmod

    for N in spec["show"]:
        e = found[N - 1]
        if not e["success"]:
            continue
        stem = f"figure{number}_N{N}"
        r = rodmod.from_orbit_file(Path(out_dir) / f"{stem}.npz")
        paths += rodmod.plot_rod(r, out_dir, stem, title=f"Fig. {number}: {N}-pulse rod, lam = {e['free_value']:.6g}, "
                                                         f"orthonormality {r['orthonormality']:.1e}")
    return paths


def figure_6(out_dir, quick: bool = False, quiet: bool = True) -> list[str]:
    """fig:multimodal1: two- and four-pulse orbits near lam = 0.001 (mu = 2 lam), plus N <= 6 table."""
    return _figure(6, out_dir, quick, quiet)


def figure_7(out_dir, quick: bool = False, quiet: bool = True) -> list[str]:
    """fig:multimodal2: two- and three-pulse orbits near lam = 0.5 (mu = 2 lam), plus N <= 6 table."""
    return _figure(7, out_dir, quick, quiet)
