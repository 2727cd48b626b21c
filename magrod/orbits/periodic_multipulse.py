"""Symmetric homoclinic orbits to the periodic saddle (mu > 2 lambdabar): shooting from the linear unstable
manifold of the helical relative equilibrium (magrod.orbits.periodic) to Fix(R) (derive/symmetry.py).

Unknowns.  The periodic orbit is a G-orbit (rotations about the body 3-axis), so a launch at phase s along it
is the G_{omega s}-image of a launch at phase 0 with the unstable-plane coordinate multiplied by
exp(-s (a + i b)) (d Phi_s = G_{omega s} exp(s A), magrod.orbits.periodic).  Fix(R) = {pbar_theta = 0, sin psi = 0} is
G-invariant, so the phase along the periodic orbit and the launch angle on the unstable plane are one unknown:
we launch at phase 0, launch distance, angle `angle` (x_L = x_p + launch_distance Re(e^{-i angle} v)/|.|, v the monodromy's
unstable eigenvector) -- the phase along the periodic orbit s corresponds to angle = b s at distance
launch_distance e^{a s}.  With the time T to the symmetric point this gives two unknowns for the two conditions
r = (pbar_theta, sin psi)(x(T)) = 0: symmetric homoclinic orbits to the periodic saddle are generic (isolated
at fixed parameters, in one-parameter branches), unlike those of the straight rod at mu = 2 lambdabar
(magrod.orbits.multipulse), which are of codimension one.

Newton on (T, angle) with the one engine (magrod.orbits.shooting.residual_and_jacobian: dr/dT = grad r . f(x(T)),
dr/d angle = grad r . Phi(T) dx_L/d angle; dr/d par for continuation, magrod.orbits.continuation).  Precision:
double for the first crossing; long double from the second on, as for the straight rod (after a passage near
the saddle psi inherits the launch error divided by the small transverse force); the launch point is formed in
that precision (PeriodicSaddle.launch_point).
"""
from __future__ import annotations

import math

import numpy as np

from ..core import systems
from ..core.errors import require_positive_int
from ..core.params import RodParams
from ..core.precision import Precision
from ..core.tolerances import LAUNCH_DISTANCE, SHOOTING_TOL
from .periodic import PeriodicSaddle, periodic_saddle
from .shooting import (MultipulseOrbit, crossing_events, fix_residual, limit_component, newton, residual_and_jacobian,
                       shooting_precision, symmetric_orbit)

THETA_GATE = 0.3  # a zero of pbar_theta with theta above this is a pulse maximum; below it, a near-saddle one


def crossings(saddle: PeriodicSaddle, angle: float, pulses: int, *, launch_distance: float = LAUNCH_DISTANCE[Precision.DOUBLE],
              t_max: float = 3000.0, gate: float = THETA_GATE, max_events: int = 400):
    """Candidate symmetric points for a `pulses`-pulse orbit on the unstable branch launched at `angle`: list of
    (t, sin psi) at zeros of pbar_theta sin(theta).  Odd pulses = 2j - 1: the j-th zero with theta > gate (the
    middle pulse's maximum).  Even pulses = 2j: every zero with theta < gate between the j-th and (j+1)-th pulse
    maxima (the near-saddle passage spirals around the periodic orbit, so there are several; each gives its own
    family of orbits).  Empty if the branch does not get there before t_max.  Double precision (the crossing
    loop of magrod.orbits.shooting)."""
    pars = saddle.params.array()
    j = (pulses + 1) // 2
    big, out = 0, []
    for t, x in crossing_events(saddle.launch_point(launch_distance, angle, Precision.DOUBLE), pars, t_max=t_max, max_events=max_events):
        th = float(systems.body_to_euler(x, pars)[0])
        if th > gate:
            big += 1
            if pulses % 2 == 1 and big == j:
                return [(float(t), float(fix_residual(x)[1]))]
            if pulses % 2 == 0 and big > j:
                return out
        elif pulses % 2 == 0 and big == j:
            out.append((float(t), float(fix_residual(x)[1])))
    return [] if pulses % 2 == 1 else out


def shoot(params: RodParams, pulses: int, angle: float, T: float, *, launch_distance: float | None = None,
          tol: float = SHOOTING_TOL, max_iter: int = 20, precision=None,
          saddle: PeriodicSaddle | None = None) -> MultipulseOrbit:
    """Newton on (T, angle) at fixed parameters from the guess (angle, T) of a `pulses`-pulse orbit (precision
    None: double for one pulse, long double from two on; launch_distance None: LAUNCH_DISTANCE of that precision).  saddle:
    the periodic saddle at `params` if already computed."""
    crossing = require_positive_int("pulses", pulses)
    prec = shooting_precision(crossing, precision)
    launch_distance = launch_distance if launch_distance is not None else LAUNCH_DISTANCE[prec]
    s = saddle if saddle is not None else periodic_saddle(params)

    def evaluate(z):
        return residual_and_jacobian(s, float(z[0]), float(z[1]), launch_distance=launch_distance, precision=prec)

    # the one damped Newton (magrod.orbits.shooting.newton): |d angle| <= 0.5 (a wrong crossing index otherwise);
    # the periodic searches converge to tol at their launch distance, so no stall/noise-floor acceptance here
    run = newton(evaluate, [T, angle], tol=tol, max_evaluations=max_iter + 1, damp=limit_component(1, 0.5))
    hist = [{"iteration": k, "T": float(z[0]), "angle": float(z[1]), "residual": res}
            for k, (z, res) in enumerate(run.history)]
    ev = run.evaluation
    T, angle = float(run.z[0]), float(run.z[1])
    if run.success:
        H = float(systems.body_functions()["H"](ev.xT, params.array())[0])
        return MultipulseOrbit(True, f"converged in {run.iterations} Newton steps", params, s, crossing, T, ev.x0,
                               run.residual, run.iterations, launch_distance, prec, angle=angle, history=hist, xT=ev.xT,
                               energy_error=abs(H - s.H))
    x0, xT = (ev.x0, ev.xT) if ev is not None else (np.full(systems.dim("body"), np.nan),) * 2
    return MultipulseOrbit(False, f"not converged after {len(hist)} evaluations (last residual {run.residual:.3e} > "
                                  f"tol {tol:.1e}; {run.outcome})", params, s, crossing, T, x0, run.residual,
                           len(hist), launch_distance, prec, angle=angle, history=hist, xT=xT)


def scan_angles(saddle: PeriodicSaddle, pulses: int, samples: int = 181, *,
                launch_distance: float = LAUNCH_DISTANCE[Precision.DOUBLE], k: int = 1):
    """sin psi at the candidate symmetric point (the k-th near-saddle zero for even pulses) for launch angles on
    [0, 2 pi): (angles, t, sinpsi), nan where the branch has no such point."""
    s = saddle
    ang = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)
    t = np.full(samples, np.nan)
    sp_ = np.full(samples, np.nan)
    for i, a in enumerate(ang):
        c = crossings(s, a, pulses, launch_distance=launch_distance)
        if len(c) >= k:
            t[i], sp_[i] = c[k - 1]
    return ang, t, sp_


def bisect_angle(saddle: PeriodicSaddle, pulses: int, a: float, b: float, *, launch_distance: float, k: int = 1,
                 width: float = 1e-12, max_iter: int = 60):
    """Bisection on g(angle) = sin psi at the candidate symmetric point (`crossings`, k-th one for even pulses) over
    a sign change [a, b] of the launch angle: the 1-D form of the shooting problem (pbar_theta = 0 holds exactly at
    the event).  Returns (angle, t) or None if the bracket is not a transversal zero: the branch loses the crossing,
    or sin psi or the crossing time jumps (|d sin psi| >= 1 or |dt| > 2: through the chart's cut, or to the
    neighbouring symmetric point after one more turn near the saddle).  Cost: one double-precision event
    integration per halving (a few ms)."""
    def g(angle):
        c = crossings(saddle, angle, pulses, launch_distance=launch_distance)
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


def find(params: RodParams, pulses: int, *, samples: int = 181, launch_distance: float | None = None, k: int = 1,
         tol: float = SHOOTING_TOL, max_orbits: int | None = None, precision=None,
         saddle: PeriodicSaddle | None = None) -> list[MultipulseOrbit]:
    """Symmetric homoclinic orbits with `pulses` pulses (symmetric point chosen as in `crossings`, k-th
    near-saddle zero for even pulses) from sign changes of sin psi over a launch-angle scan, each narrowed by
    bisection (`bisect_angle`) and refined by Newton on (T, angle) in `precision` (auto: long double from 2 pulses
    on); duplicates removed.  The scan, the bisection and Newton use the same launch distance: a different launch_distance
    is a different launch phase (angle shift b ln(launch_distance'/launch_distance)/a, T shift ln(launch_distance'/launch_distance)/a ~ 6.93 for 1e-7 -> 1e-9),
    and a Newton started from the other launch_distance's angle slides to a neighbouring symmetric point (it used to: 3-pulse
    searches ended on 2-pulse orbits)."""
    from ..core.limits import integer

    pulses = require_positive_int("pulses", pulses)
    samples = integer("samples", samples, minimum=3)  # the limit and words of multipulse_orbits and the CLI
    prec = shooting_precision(pulses, precision)
    launch_distance = launch_distance if launch_distance is not None else LAUNCH_DISTANCE[prec]
    s = saddle if saddle is not None else periodic_saddle(params)
    ang, t, sp_ = scan_angles(s, pulses, samples, k=k, launch_distance=launch_distance)
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
        start = bisect_angle(s, pulses, a_i, a_j, launch_distance=launch_distance, k=k)
        if start is None:
            continue
        r = shoot(params, pulses, start[0], start[1], launch_distance=launch_distance, tol=tol, precision=prec, saddle=s)
        if r.success:
            r.pulses_counted = count_pulses(r)
        if r.success and r.pulses_counted != pulses:
            continue  # Newton slid to a neighbouring symmetric point
        if r.success and not any(abs(math.remainder(r.angle - o.angle, 2 * math.pi)) < 1e-6 for o in out):
            out.append(r)
            if max_orbits and len(out) >= max_orbits:
                break
    return out


def count_pulses(res: MultipulseOrbit) -> int:
    """Pulses of the orbit: local maxima of theta above THETA_GATE (on 2001 samples)."""
    from .shooting import count_pulses as count

    return count(orbit(res, 2001)["theta"], THETA_GATE)


def orbit(res: MultipulseOrbit, n: int = 4001) -> dict:
    """The symmetric orbit on [0, 2T] (magrod.orbits.shooting.symmetric_orbit): body states, reduced coordinates,
    Hbar (also for an unconverged result: it is the orbit at its (T, angle))."""
    return symmetric_orbit(res.x0, res.T, res.params.array(), n)
