"""Symmetric homoclinic orbits to the periodic saddle (mu > 2 lambdabar): shooting from the linear unstable
manifold of the helical relative equilibrium (magrod/floquet.py) to Fix(R) (derive/symmetry.py).

Unknowns.  The periodic orbit is a G-orbit (rotations about the body 3-axis), so a launch at phase s along it
is the G_{omega s}-image of a launch at phase 0 with the unstable-plane coordinate multiplied by
exp(-s (a + i b)) (d Phi_s = G_{omega s} exp(s A), floquet.py).  Fix(R) = {pbar_theta = 0, sin psi = 0} is
G-invariant, so the phase along the periodic orbit and the launch angle on the unstable plane are one unknown:
we launch at phase 0, distance eps, angle `angle` (x_L = x_p + eps Re(e^{-i angle} v)/|.|, v the monodromy's
unstable eigenvector) -- the phase along the periodic orbit s corresponds to angle = b s at distance
eps e^{a s}.  With the time T to the symmetric point this gives two unknowns for the two conditions
r = (pbar_theta, sin psi)(x(T)) = 0: symmetric homoclinic orbits to the periodic saddle are generic (isolated
at fixed parameters, in one-parameter branches), unlike those of the straight rod at mu = 2 lambdabar
(magrod/shooting.py), which are of codimension one.

Newton on (T, angle): dr/dT = grad r . f(x(T)), dr/d angle = grad r . Phi(T) dx_L/d angle (heyoka variational
equations, systems.cached_variational; d x_L/d angle by a central difference of the closed-form launch).
dr/d par (for continuation, magrod/continuation.py) = grad r . (Phi dx_L/dpar + Psi e_par), dx_L/dpar by a
central difference of the periodic saddle (relative equilibrium + monodromy eigenvector) at par +- h.
Precision: double for the first crossing; long double from the second on, as in magrod/shooting.py (after a
passage near the saddle psi inherits the launch error divided by the small transverse force).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import heyoka as hy
import numpy as np

from ..core import systems
from ..core.errors import ParameterError, require_positive_int
from .periodic import PeriodicSaddle, periodic_saddle
from ..generated import scalars
from ..core.params import RodParams

DEFAULT_EPS = 1e-7
EXTENDED_EPS = 1e-9
DEFAULT_TOL = 1e-10
PAR_NAMES = ("m", "mu", "gamma", "delta", "lam")


@dataclass
class PeriodicHomoclinic:
    """A symmetric homoclinic orbit to the periodic saddle: launch angle, time T to the symmetric point,
    crossing = the number of pulses it was shot for, residual, energy error |H(x(T)) - H_saddle|."""

    success: bool
    message: str
    params: RodParams
    crossing: int
    angle: float
    T: float
    eps: float
    residual: float
    energy_error: float
    x0: np.ndarray
    xT: np.ndarray
    saddle: PeriodicSaddle
    iterations: int
    precision: str
    history: list = field(default_factory=list)

    def as_dict(self) -> dict:
        return {"success": self.success, "message": self.message, "params": self.params.as_dict(),
                "crossing": self.crossing, "angle": self.angle, "T": self.T, "eps": self.eps,
                "residual": self.residual, "energy_error": self.energy_error, "iterations": self.iterations,
                "precision": self.precision, "saddle_H": self.saddle.H, "saddle_T": self.saddle.T}


# --- compiled pieces -----------------------------------------------------------------------------------------
def _fix():
    """The Fix(R) conditions and their gradients, shared with the straight-rod shooting."""
    from .shooting import fix_functions

    return fix_functions()


@systems.per_thread
def _crossing_integrator():
    return systems.integrator("body", events=[("ptheta_sin", "any")])


def _precision(crossing: int, precision: str) -> str:
    if precision not in ("auto", "double", "long double"):
        raise ParameterError("precision", f"must be auto, double or 'long double', got {precision!r}")
    if precision == "auto":
        return "double" if crossing == 1 else "long double"
    return precision


THETA_GATE = 0.3  # a zero of pbar_theta with theta above this is a pulse maximum; below it, a near-saddle one


def crossings(saddle: PeriodicSaddle, angle: float, pulses: int, *, eps: float = DEFAULT_EPS, t_max: float = 3000.0,
              gate: float = THETA_GATE, max_events: int = 400):
    """Candidate symmetric points for a `pulses`-pulse orbit on the unstable branch launched at `angle`: list of
    (t, sin psi) at zeros of pbar_theta sin(theta).  Odd pulses = 2j - 1: the j-th zero with theta > gate (the
    middle pulse's maximum).  Even pulses = 2j: every zero with theta < gate between the j-th and (j+1)-th pulse
    maxima (the near-saddle passage spirals around the periodic orbit, so there are several; each gives its own
    family of orbits).  Empty if the branch does not get there before t_max.  Reuses the event integrator."""
    ta = _crossing_integrator()
    pars = saddle.params.array()
    systems.reset(ta, saddle.launch_point(eps, angle), 0.0, pars)
    fcond, _ = _fix()
    j = (pulses + 1) // 2
    big, out = 0, []
    for _ in range(max_events):
        oc, *_ = ta.propagate_until(t_max)
        if int(oc) != -1:
            break
        x = ta.state.copy()
        th = float(systems.body_to_euler(x, pars)[0])
        if th > gate:
            big += 1
            if pulses % 2 == 1 and big == j:
                return [(float(ta.time), float(fcond(x, [])[1]))]
            if pulses % 2 == 0 and big > j:
                return out
        elif pulses % 2 == 0 and big == j:
            out.append((float(ta.time), float(fcond(x, [])[1])))
    return [] if pulses % 2 == 1 else out


def _propagate(x0, pars, T, precision):
    ta = systems.cached_variational(precision)
    ft = systems.PRECISIONS[precision]
    systems.reset_variational(ta, np.asarray(x0, dtype=ft), np.asarray(pars, dtype=ft))
    oc, *_ = ta.propagate_until(ft(T))
    if oc != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"variational integration stopped with outcome {oc}")
    return systems.variational_blocks(ta)


def _with(params: RodParams, name: str, value: float) -> RodParams:
    kw = params.as_dict()
    kw[name] = float(value)
    return RodParams(**kw)


def residual_and_jacobian(params: RodParams, crossing_T: float, angle: float, *, eps: float, precision: str,
                          free: tuple = (), saddle: PeriodicSaddle | None = None, h_rel: float = 1e-6):
    """r = (pbar_theta, sin psi)(x(T)) and its Jacobian w.r.t. (T, angle, *free) (2 x (2 + len(free))).
    Also returns the saddle, x0 and x(T).  free: parameter names (PARAMS)."""
    s = saddle or periodic_saddle(params)
    pars = params.array()
    x0 = s.launch_point(eps, angle)
    x, Phi, Psi = _propagate(x0, pars, crossing_T, precision)
    fcond, fgrad = _fix()
    r = fcond(x, [])
    G = fgrad(x, []).reshape(-1, x.size)
    f = systems.body_functions()["rhs"](x, pars)
    ha = 1e-6
    dxa = (s.launch_point(eps, angle + ha) - s.launch_point(eps, angle - ha)) / (2 * ha)
    cols = [G @ f, G @ (Phi @ dxa)]
    for name in free:
        v = getattr(params, name)
        h = h_rel * max(1.0, abs(v))
        if name in ("mu", "lam"):  # stay on the side mu > 2 lam where the periodic saddle exists
            gap = params.mu - scalars.straight_rod_mu(**params.as_dict())
            h = min(h, 0.25 * gap / (2.0 if name == "lam" else 1.0))
        xp = periodic_saddle(_with(params, name, v + h)).launch_point(eps, angle)
        xm = periodic_saddle(_with(params, name, v - h)).launch_point(eps, angle)
        cols.append(G @ (Phi @ ((xp - xm) / (2 * h)) + Psi[:, systems.par_index(name)]))
    return r, np.column_stack(cols), s, x0, x


def shoot(params: RodParams, pulses: int, angle: float, T: float, *, eps: float | None = None,
          tol: float = DEFAULT_TOL, max_iter: int = 20, precision: str = "auto") -> PeriodicHomoclinic:
    """Newton on (T, angle) at fixed parameters from the guess (angle, T) of a `pulses`-pulse orbit."""
    crossing = require_positive_int("pulses", pulses)
    prec = _precision(crossing, precision)
    eps = eps if eps is not None else (DEFAULT_EPS if prec == "double" else EXTENDED_EPS)
    s = periodic_saddle(params)
    hist = []
    res = math.inf
    x0 = xT = np.full(9, np.nan)
    for it in range(max_iter + 1):
        r, J, _, x0, xT = residual_and_jacobian(params, T, angle, eps=eps, precision=prec, saddle=s)
        res = float(np.max(np.abs(r)))
        hist.append({"iteration": it, "T": T, "angle": angle, "residual": res})
        if not np.isfinite(res):
            break
        if res <= tol:
            H = float(systems.body_functions()["H"](xT, params.array())[0])
            return PeriodicHomoclinic(True, f"converged in {it} Newton steps", params, crossing, angle, T, eps, res,
                                      abs(H - s.H), x0, xT, s, it, prec, hist)
        try:
            step = -np.linalg.solve(J, r)
        except np.linalg.LinAlgError:
            break
        lim = 0.5
        if abs(step[1]) > lim:  # damp angle jumps (a wrong crossing index otherwise)
            step *= lim / abs(step[1])
        T, angle = T + step[0], angle + step[1]
    return PeriodicHomoclinic(False, f"not converged after {len(hist)} evaluations (last residual {res:.3e} > "
                                     f"tol {tol:.1e})", params, crossing, angle, T, eps, res, math.nan, x0, xT, s,
                              len(hist), prec, hist)


def scan_angles(params: RodParams, pulses: int, samples: int = 181, *, eps: float = DEFAULT_EPS, k: int = 1):
    """sin psi at the candidate symmetric point (the k-th near-saddle zero for even pulses) for launch angles on
    [0, 2 pi): (angles, t, sinpsi), nan where the branch has no such point."""
    s = periodic_saddle(params)
    ang = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)
    t = np.full(samples, np.nan)
    sp_ = np.full(samples, np.nan)
    for i, a in enumerate(ang):
        c = crossings(s, a, pulses, eps=eps)
        if len(c) >= k:
            t[i], sp_[i] = c[k - 1]
    return ang, t, sp_


def bisect_angle(saddle: PeriodicSaddle, pulses: int, a: float, b: float, *, eps: float, k: int = 1,
                 width: float = 1e-12, max_iter: int = 60):
    """Bisection on g(angle) = sin psi at the candidate symmetric point (`crossings`, k-th one for even pulses) over
    a sign change [a, b] of the launch angle: the 1-D form of the shooting problem (pbar_theta = 0 holds exactly at
    the event).  Returns (angle, t) or None if the bracket is not a transversal zero: the branch loses the crossing,
    or sin psi or the crossing time jumps (|d sin psi| >= 1 or |dt| > 2: through the chart's cut, or to the
    neighbouring symmetric point after one more turn near the saddle).  Cost: one double-precision event
    integration per halving (a few ms)."""
    def g(angle):
        c = crossings(saddle, angle, pulses, eps=eps)
        return c[k - 1] if len(c) >= k else None

    ga, gb = g(a), g(b)
    if ga is None or gb is None or np.sign(ga[1]) == np.sign(gb[1]):
        return None
    for _ in range(max_iter):
        if abs(b - a) <= width or abs(ga[1] - gb[1]) >= 1.0 or abs(ga[0] - gb[0]) > 2.0:
            break
        m = 0.5 * (a + b)
        gm = g(m)
        if gm is None:
            return None
        if np.sign(gm[1]) == np.sign(ga[1]):
            a, ga = m, gm
        else:
            b, gb = m, gm
    if abs(ga[1] - gb[1]) >= 1.0 or abs(ga[0] - gb[0]) > 2.0:
        return None
    w = ga[1] / (ga[1] - gb[1]) if ga[1] != gb[1] else 0.5
    return a + w * (b - a), ga[0] + w * (gb[0] - ga[0])


def find(params: RodParams, pulses: int, *, samples: int = 181, eps: float | None = None, k: int = 1,
         tol: float = DEFAULT_TOL, max_orbits: int | None = None, precision: str = "auto") -> list[PeriodicHomoclinic]:
    """Symmetric homoclinic orbits with `pulses` pulses (symmetric point chosen as in `crossings`, k-th
    near-saddle zero for even pulses) from sign changes of sin psi over a launch-angle scan, each narrowed by
    bisection (`bisect_angle`) and refined by Newton on (T, angle) in `precision` (auto: long double from 2 pulses
    on); duplicates removed.  The scan, the bisection and Newton use the same launch distance eps: a different eps
    is a different launch phase (angle shift b ln(eps'/eps)/a, T shift ln(eps'/eps)/a ~ 6.93 for 1e-7 -> 1e-9),
    and a Newton started from the other eps's angle slides to a neighbouring symmetric point (it used to: 3-pulse
    searches ended on 2-pulse orbits)."""
    pulses = require_positive_int("pulses", pulses)
    prec = _precision(pulses, precision)
    eps = eps if eps is not None else (DEFAULT_EPS if prec == "double" else EXTENDED_EPS)
    s = periodic_saddle(params)
    ang, t, sp_ = scan_angles(params, pulses, samples, k=k, eps=eps)
    out = []
    n = len(ang)
    for i in range(n):
        j = (i + 1) % n
        if not (np.isfinite(sp_[i]) and np.isfinite(sp_[j])) or np.sign(sp_[i]) == np.sign(sp_[j]):
            continue
        if abs(sp_[i] - sp_[j]) > 1.0 or abs(t[i] - t[j]) > 2.0:
            continue  # a jump through the chart's cut or to another zero, not a transversal zero
        a_i = ang[i]
        a_j = ang[j] if j > i else ang[j] + 2 * math.pi
        start = bisect_angle(s, pulses, a_i, a_j, eps=eps, k=k)
        if start is None:
            continue
        r = shoot(params, pulses, start[0], start[1], eps=eps, tol=tol, precision=prec)
        if r.success and count_pulses(r) != pulses:
            continue  # Newton slid to a neighbouring symmetric point
        if r.success and not any(abs(math.remainder(r.angle - o.angle, 2 * math.pi)) < 1e-6 for o in out):
            out.append(r)
            if max_orbits and len(out) >= max_orbits:
                break
    return out


def count_pulses(res: PeriodicHomoclinic) -> int:
    """Pulses of the converged orbit: local maxima of theta above THETA_GATE."""
    th = orbit(res, 2001)["theta"]
    inner = (th[1:-1] > th[:-2]) & (th[1:-1] >= th[2:]) & (th[1:-1] > THETA_GATE)
    return int(np.count_nonzero(inner))


def orbit(res: PeriodicHomoclinic, n: int = 4001) -> dict:
    """The symmetric orbit on [0, 2T] (magrod.orbits.shooting.symmetric_orbit): body states, reduced coordinates, Hbar."""
    from .shooting import symmetric_orbit

    return symmetric_orbit(res.x0, res.T, res.params.array(), n)


def multipulse_rows(params: RodParams, *, max_pulses: int = 3, samples: int = 121) -> tuple:
    """Symmetric N-pulse orbits to the periodic saddle at the given parameters (mu != 2 lam: generic, no parameter
    freed), N = 1..max_pulses.  Returns (summary dict with one row per orbit or failure, [(row, result)])."""
    import time

    max_pulses = require_positive_int("max_pulses", max_pulses)
    s = periodic_saddle(params)  # ParameterError before anything is computed
    t0 = time.perf_counter()
    rows, found_all = [], []
    for N in range(1, max_pulses + 1):
        found = find(params, N, samples=samples)
        if not found:
            rows.append({"pulses_target": N, "success": False, "message": "no sign change of sin psi over the "
                         f"launch-angle scan ({samples} angles) converged to a {N}-pulse orbit"})
        for k, r in enumerate(found):
            row = {"pulses_target": N, "pulses": N, "index": k, **r.as_dict()}
            rows.append(row)
            found_all.append((row, r))
    return {"ok": True, "params": params.as_dict(), "free": None, "saddle": "periodic (helical relative equilibrium)",
            "saddle_T": s.T, "quartet_abs": [abs(z) for z in s.quartet], "orbits": rows,
            "wall_time_s": time.perf_counter() - t0,
            "note": "mu != 2 lam: homoclinic orbits to the periodic saddle are generic (unknowns T and the launch "
                    "angle), found at the given parameters"}, found_all
