"""Symmetric (reversible) multipulse homoclinic orbits of the straight rod by shooting (paper sec. 8,
fig:multimodal1, fig:multimodal2; method of van der Heijden et al. 1998, here heyoka + Newton with the
variational Jacobian), and `multipulse_orbits`, the public search for orbits to either saddle.

Codimension one.  The straight rod's unstable manifold is one orbit modulo the rotations about the body 3-axis
(the launch angle is a symmetry direction, magrod.orbits.shooting), and with the saddle's energy and Casimir levels
built in the only unknown left on the orbit is the time T: symmetric homoclinic orbits of the straight rod
generically do not exist at given parameters, and one parameter (`free`, default lambdabar with mu = 2 lambdabar
kept) is the second shooting unknown.  Newton on (T, free) for r = (pbar_theta, sin psi)(x(T)) = 0 uses the one
engine (shooting.residual_and_jacobian); converged iff max|r| <= SHOOTING_TOL (or within the measured rounding
floor, `shoot`).

The search (`find_orbits`): scan the free parameter (double precision), bracket sign changes of sin psi at the
N-th crossing, bisect (`bisect`, in the shooting precision) and finish with Newton from the bisected value.
`uncertainty` repeats it at two launch distances and two precisions.  Orbits to the periodic saddle (mu > 2 lam,
generic): magrod.orbits.periodic_multipulse.
"""
from __future__ import annotations

import math

import numpy as np

from ..core.deprecation import renamed_keywords
from ..core.errors import ParameterError, require_positive_int
from ..core.params import RodParams
from ..core.precision import Precision
from ..core.tolerances import BISECTION_RTOL, LAUNCH_DISTANCE, LAUNCH_DISTANCES, SHOOTING_TOL, STALL_ITERATIONS
from ..generated.names import PARAMS
from . import shooting
from .equilibrium import StraightRod, on_level, straight_rod
from .shooting import (MultipulseOrbit, MultipulseSearch, PulseSearch, count_pulses, fix_functions, residual_and_jacobian,
                       shooting_precision, unstable_branch)

MAX_DIGITS = 15  # significant digits a float64 value is printed with (`significant`)
# the free-parameter scan: this many intervals over value * [1 - span, 1 + span] (1.25 % of the value each at
# span 0.5), i.e. SCAN_INTERVALS + 1 samples
SCAN_INTERVALS = 80
ANGLE_SAMPLES = 121  # launch angles of the periodic saddle's scan (3 degrees apart)
# mu is not free: it follows the free parameter so that the straight rod stays on the chart's level (mu = 2 lam)
FREE_PARAMETERS = ("lam",) + tuple(p for p in PARAMS if p not in ("mu", "lam"))


# --- Newton ------------------------------------------------------------------------------------------------
def shoot(params: RodParams, crossing: int, *, free: str | None = "lam", launch_distance: float | None = None,
          tol: float = SHOOTING_TOL, max_iter: int = 25, T_guess: float | None = None, precision=None,
          saddle: StraightRod | None = None) -> MultipulseOrbit:
    """Newton on (T, free parameter) for (pbar_theta, sin psi)(x(T)) = 0 at the `crossing`-th zero of pbar_theta.

    free=None is allowed only when the sin(psi) condition is void, i.e. lam = 0 (then mu = 0, the force is
    along the field and psi is a gauge): unknown T, condition pbar_theta = 0.  Cost: one variational
    integration (135 equations) per iteration, ~10-50 ms each (x10 in long double).  saddle: the straight rod
    at `params` if already computed.

    precision None (automatic): double for the first crossing, long double and launch_distance = LAUNCH_DISTANCE[long double]
    (1e-9) for later crossings.  Near the saddle psi is the angle of the transverse force rho ~ sqrt(lam) theta
    (~1e-6 there), so psi after (or at) a near-saddle passage inherits the O(launch_distance^2) error of the linear launch
    and the rounding of n divided by rho: in double precision this puts a floor of ~1e-8..1e-7 on the residual
    (measured), in long double with launch_distance = 1e-9 it is ~1e-11 for N = 2 and grows with N (~1e-9 for N = 6: each
    near-saddle passage amplifies the rounding).

    Near the root the residual is noise, so Newton keeps its best iterate and stops after STALL_ITERATIONS
    without halving it.  If the best residual is above tol, the noise floor there is measured (`noise_floor`:
    the non-linear part of r at a few ulp of the free parameter); the result counts as converged iff the best
    residual is within FLOOR_FACTOR x that floor and below FLOOR_CAP, with `noise_floor` set and the message
    saying so (`resolution`: how far the free parameter can be from the root, through J^-1)."""
    crossing = require_positive_int("crossing", crossing)
    prec = shooting_precision(crossing, precision)
    if launch_distance is None:
        launch_distance = LAUNCH_DISTANCE[prec]
    if free is not None and free not in FREE_PARAMETERS:
        raise ParameterError("free", f"must be one of {FREE_PARAMETERS} or None, got {free!r}")
    void_psi = params.lam == 0.0
    if free is None and not void_psi:
        raise ParameterError("free", "symmetric homoclinic orbits of the straight rod are of codimension one "
                                     "(the launch phase is a symmetry): a free parameter is needed unless lam = 0")
    if void_psi:
        free = None
    if not (0 < launch_distance < 1e-2):
        raise ParameterError("launch_distance", f"must be in (0, 1e-2), got {launch_distance}")
    s = saddle if saddle is not None else straight_rod(params)
    if T_guess is None:
        br = unstable_branch(s, crossings=crossing, launch_distance=launch_distance)
        if len(br) < crossing:
            raise ParameterError("crossing", f"the unstable branch has only {len(br)} zeros of pbar_theta before "
                                             f"t = 2000 (no homoclinic level reached)")
        T_guess = br[crossing - 1].t
    T = float(T_guess)
    history = []
    saddles = {getattr(s.params, free) if free else None: s}

    def evaluate(z):
        # the straight rod at the free value z[1] (mu on its level); ParameterError where there is none
        v = float(z[1]) if free else None
        if v not in saddles:
            saddles.clear()
            saddles[v] = straight_rod(on_level(params, **{free: v}))
        ev = residual_and_jacobian(saddles[v], float(z[0]), launch_distance=launch_distance, precision=prec,
                                   free=() if free is None else (free,))
        if void_psi:  # the sin psi condition is void: unknown T, condition pbar_theta = 0
            ev.r, ev.J = ev.r[:1], ev.J[:1, :1]
        return ev

    def floor(ev, z):
        return noise_floor(ev.saddle, free, float(z[0]), ev.r, ev.J[:, 1], launch_distance=launch_distance, precision=prec)

    z0 = [T] if free is None else [T, getattr(s.params, free)]
    # damp steps that would leave the region where the crossing index is meaningful: |d free| <= |free| / 4
    run = shooting.newton(evaluate, z0, tol=tol, max_evaluations=max_iter,
                          damp=None if void_psi else shooting.limit_component(1, lambda z: 0.25 * max(abs(z[1]), 1e-6)),
                          stall=None if void_psi else STALL_ITERATIONS, floor=None if void_psi else floor)
    for k, (z, res) in enumerate(run.history, start=1):
        history.append({"iteration": k, "T": float(z[0]), "free_value": float(z[1]) if free else None,
                        "residual": res})
    ev = run.evaluation
    if ev is None:  # no evaluation (max_iter = 0)
        return MultipulseOrbit(False, f"not converged after 0 iterations (last residual inf > tol {tol:.1e})",
                               s.params, s, crossing, T, s.launch_point(launch_distance), math.inf, 0, launch_distance, prec, free=free,
                               history=history)
    s_, T_ = ev.saddle, float(run.z[0])

    def result(success, message, **kw):
        return MultipulseOrbit(success, message, s_.params, s_, crossing, T_, ev.x0, run.residual, run.iterations,
                               launch_distance, prec, free=free, history=history, **kw)

    if run.outcome == "converged":
        kw = {} if void_psi else {"resolution": _resolution(ev.J, ev.r)}
        return result(True, f"converged in {run.iterations} Newton steps", xT=ev.xT, **kw)
    if run.outcome == "floor":
        fl = float(np.max(run.noise_floor))
        unc = _resolution(ev.J, np.maximum(np.abs(ev.r), run.noise_floor))
        return result(True, f"converged to the noise floor of {prec.value} arithmetic: residual {run.residual:.2e} <= "
                            f"floor {fl:.2e} (tol {tol:.1e} below it; {free} resolved to {unc:.1e})",
                      noise_floor=fl, resolution=unc, xT=ev.xT)
    return result(False, f"not converged after {run.evaluations} iterations (last residual {run.residual:.3e} > "
                         f"tol {tol:.1e}; {run.outcome})")


def _resolution(Jm, r) -> float:
    """How far the free parameter can be from the root when |residual_j| <= r_j (componentwise):
    sum_j |(J^-1)_{1j}| r_j."""
    try:
        return float(np.abs(np.linalg.inv(Jm)[1]) @ np.broadcast_to(np.abs(np.asarray(r, dtype=float)), (2,)))
    except np.linalg.LinAlgError:
        return math.nan


def noise_floor(s: StraightRod, free: str, T: float, r0, drdv, *, launch_distance: float, precision=Precision.DOUBLE,
                ulps: int = 64) -> np.ndarray:
    """Rounding noise of the shooting residual at (s.params, T), per component: max over k = +-1 .. +-4 of
    |r(v + k h) - r(v) - k h dr/dv| with h = `ulps` ulp of the free value v (T fixed).  The linear part is
    ~|dr/dv| h (subtracted), so what is left is the non-smooth part: integration rounding amplified by the
    near-saddle passages, which Newton cannot reduce.  Eight integrations without variational equations."""
    fcond, _ = fix_functions()
    v = getattr(s.params, free)
    h = ulps * float(np.spacing(abs(v)))
    worst = np.zeros(2)
    for k in (-4, -3, -2, -1, 1, 2, 3, 4):
        q = straight_rod(on_level(s.params, **{free: v + k * h}))
        x = shooting.propagate(q.launch_point(launch_distance, 0.0, precision), q.params.array(), T, precision)
        worst = np.maximum(worst, np.abs(fcond(x, []) - np.asarray(r0) - k * h * np.asarray(drdv)))
    return worst


def orbit(result: MultipulseOrbit, n: int = 4001) -> dict:
    """The symmetric orbit of a converged shooting result (MultipulseOrbit.sample)."""
    return result.sample(n)


def summarize(result: MultipulseOrbit, orb: dict | None = None) -> dict:
    """pulses, residual, arclength (between the two launch_distance-points: 2 T), H (and its deviation from the saddle's)."""
    orb = orb or orbit(result)
    return {"pulses": count_pulses(orb["theta"]), "crossing": result.pulses, "residual": result.residual,
            "noise_floor": result.noise_floor, "iterations": result.iterations, "arclength": 2 * result.T, "launch_distance": result.launch_distance,
            "H": float(np.mean(orb["H"])), "H_saddle": result.saddle_H,
            "max_abs_H_minus_saddle": float(np.max(np.abs(orb["H"] - result.saddle_H))),
            "theta_max": float(np.max(orb["theta"])), "free": result.free,
            "params": result.params.to_dict()}


# --- search ----------------------------------------------------------------------------------------------------
def _saddle_at(params: RodParams, free: str, value: float) -> StraightRod | None:
    """The straight rod at free = value (mu on its level), or None where there is none."""
    try:
        return straight_rod(on_level(params, **{free: value}))
    except ParameterError:
        return None


def scan(params: RodParams, free: str, values, crossings: int, launch_distance: float = LAUNCH_DISTANCE[Precision.DOUBLE],
         progress=None):
    """sin(psi) at the first `crossings` zeros of pbar_theta along the unstable branch for each value of the
    free parameter: array (len(values), crossings) (nan where the branch has fewer crossings)."""
    out = np.full((len(values), crossings), np.nan)
    for i, v in enumerate(values):
        s = _saddle_at(params, free, v)
        for c in unstable_branch(s, crossings=crossings, launch_distance=launch_distance) if s is not None else []:
            out[i, c.index - 1] = c.sinpsi
        if progress is not None:
            progress(1)
    return out


def crossing_sinpsi(params: RodParams, free: str, value: float, crossing: int, *, launch_distance: float,
                    precision=Precision.DOUBLE):
    """(sin psi, t) at the `crossing`-th zero of pbar_theta on the unstable branch at free = value (mu on the
    straight rod's level), or None if the branch does not get there (or there is no saddle)."""
    s = _saddle_at(params, free, value)
    if s is None:
        return None
    br = unstable_branch(s, crossings=crossing, launch_distance=launch_distance, precision=precision)
    if len(br) < crossing:
        return None
    return br[-1].sinpsi, br[-1].t


def bisect(params: RodParams, free: str, crossing: int, a: float, b: float, *, launch_distance: float,
           precision=Precision.DOUBLE, rtol: float = BISECTION_RTOL, max_iter: int = 60) -> dict | None:
    """Bisection on g(v) = sin psi at the `crossing`-th zero of pbar_theta over a bracket [a, b] of the free
    parameter (the pbar_theta condition holds exactly at the event, so this is the 1-D form of the shooting
    problem).  Stops at relative width rtol (a few ulp: inside the noise band it just picks a point in it).
    Returns {value, T, g, width, iterations} or None if [a, b] is not a sign change in this precision and launch_distance
    (or is a jump of psi through the chart's cut, |g(a) - g(b)| >= 1).  Cost: one crossing integration per step
    (~5-50 ms in double, x10 in long double)."""
    ga, gb = (crossing_sinpsi(params, free, v, crossing, launch_distance=launch_distance, precision=precision) for v in (a, b))
    if ga is None or gb is None or np.sign(ga[0]) == np.sign(gb[0]) or abs(ga[0] - gb[0]) >= 1.0:
        return None
    it = 0
    mid = (ga[0], ga[1])
    while abs(b - a) > rtol * max(abs(a), abs(b)) and it < max_iter:
        it += 1
        m = 0.5 * (a + b)
        gm = crossing_sinpsi(params, free, m, crossing, launch_distance=launch_distance, precision=precision)
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


def free_star(params: RodParams, free: str, crossing: int, a: float, b: float, *, launch_distance: float, precision,
              tol: float = SHOOTING_TOL) -> MultipulseOrbit | None:
    """The orbit at the `crossing`-th zero in the bracket [a, b]: bisection (same launch_distance and precision) then
    Newton on (T, free) from the bisected value; None if the bracket is not a sign change here.  A failed Newton
    is returned as such (success False)."""
    prec = Precision.parse(precision)
    bis = bisect(params, free, crossing, a, b, launch_distance=launch_distance, precision=prec)
    if bis is None:
        return None
    q = on_level(params, **{free: bis["value"]})
    return shoot(q, crossing, free=free, launch_distance=launch_distance, tol=tol, T_guess=bis["T"], precision=prec)


def uncertainty(params: RodParams, free: str, crossing: int, a: float, b: float, *, tol: float = SHOOTING_TOL,
                eps_values=LAUNCH_DISTANCES) -> dict:
    """The free parameter of one orbit (bracket [a, b], `crossing`) at two launch distances (eps_values) in
    double and in long double.  value: the long double run at the smaller launch_distance; uncertainty: the larger of the
    two long double values' difference and their Newton resolutions (residual or noise floor through J^-1);
    double_check: the largest |double - value| with the double runs' resolution (the double floor after
    near-saddle passages is 1e-8..1e-6, so double only confirms the leading digits); significant: value to its
    significant digits with the uncertainty of the last digit in brackets ('0.00113526146263(9)')."""
    runs = []
    for prec in (Precision.DOUBLE, Precision.LONG_DOUBLE):
        for e in eps_values:
            r = free_star(params, free, crossing, a, b, launch_distance=e, precision=prec, tol=tol)
            row = {"launch_distance": e, "precision": prec.value, "success": bool(r is not None and r.success)}
            if r is not None:
                row.update({"value": getattr(r.params, free), "residual": r.residual, "T": r.T,
                            "noise_floor": r.noise_floor, "resolution": r.resolution, "message": r.message})
            runs.append(row)
    ld = [row for row in runs if row["success"] and row["precision"] == Precision.LONG_DOUBLE.value]
    dbl = [row for row in runs if row["success"] and row["precision"] == Precision.DOUBLE.value]
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
    last_digit = lead - (MAX_DIGITS - 1)
    last = last_digit if uncertainty <= 0 else max(math.floor(math.log10(uncertainty)), last_digit)
    decimals = max(0, -last)
    u = max(1, math.ceil(uncertainty / 10.0**last - 1e-9)) if uncertainty > 0 else 1
    if u >= 10:  # 9.6 rounds up a decade
        last, u = last + 1, 1
        decimals = max(0, -last)
    return f"{value:.{decimals}f}({u})"


def find_orbits(params: RodParams, *, free: str = "lam", max_pulses: int = 6, span: float = 0.5,
                samples: int = SCAN_INTERVALS + 1, launch_distance: float | None = None, tol: float = SHOOTING_TOL, progress=None,
                max_brackets: int = 8, with_uncertainty: bool = False,
                saddle: StraightRod | None = None) -> list[PulseSearch]:
    """For N = 1..max_pulses: scan the free parameter over value * [1 - span, 1 + span] (linearly, `samples`
    points, double precision), bracket sign changes of sin(psi) at the N-th crossing, and from the brackets
    nearest to the nominal value (at most max_brackets): bisect on sin(psi) in the shooting precision (long
    double for N >= 2, as `shoot`), then Newton on (T, free) from the bisected value; keep converged orbits
    whose counted pulses equal N.  with_uncertainty: also the free parameter at two launch_distance and two precisions
    (`uncertainty`, ~4x the cost).  Returns one PulseSearch per N (success: the converged orbit closest to the
    nominal value, its samples and summary row; failure: what each bracket gave).  saddle: the straight rod at
    `params` if already computed."""
    if free not in FREE_PARAMETERS:
        raise ParameterError("free", f"must be one of {FREE_PARAMETERS}, got {free!r}")
    max_pulses = require_positive_int("max_pulses", max_pulses)
    max_brackets = require_positive_int("max_brackets", max_brackets)
    s = saddle if saddle is not None else straight_rod(params)  # ParameterError early if there is no saddle
    if params.lam == 0:
        # integrable case (psi is a gauge): only the primary orbit, unknown T alone
        r = shoot(params, 1, free=None, launch_distance=launch_distance, tol=tol, saddle=s)
        if not r.success:
            return [PulseSearch(False, r.message, 1, iterations=r.iterations, residual=r.residual)]
        orb = orbit(r)
        return [PulseSearch(True, r.message, 1, [r], [orb], {**summarize(r, orb), "free_value": None},
                            residual=r.residual)]
    v0 = getattr(params, free)
    if v0 == 0:
        raise ParameterError(free, "the free parameter must be non-zero to scan around it")
    vals = np.linspace(v0 * (1 - span), v0 * (1 + span), samples)
    table = scan(params, free, vals, max_pulses, LAUNCH_DISTANCE[Precision.DOUBLE], progress)
    found = []
    for N in range(1, max_pulses + 1):
        col = table[:, N - 1]
        idx = [i for i in range(samples - 1) if np.isfinite(col[i]) and np.isfinite(col[i + 1])
               and np.sign(col[i]) != np.sign(col[i + 1])
               # a jump of psi across +-pi/2 through the chart's cut is a sign change of sin psi through +-1: skip
               and abs(col[i] - col[i + 1]) < 1.0]
        idx.sort(key=lambda i: abs(0.5 * (vals[i] + vals[i + 1]) - v0))
        entry = PulseSearch(False, f"no sign change of sin(psi) at crossing {N} for {free} in [{vals[0]:.6g}, "
                                   f"{vals[-1]:.6g}]", N, brackets=len(idx), attempts=[])
        prec = shooting_precision(N)
        e_N = launch_distance if launch_distance is not None else LAUNCH_DISTANCE[prec]
        for i in idx[:max_brackets]:
            a, b = float(vals[i]), float(vals[i + 1])
            try:
                r = free_star(params, free, N, a, b, launch_distance=e_N, precision=prec, tol=tol)
            except ParameterError as exc:
                entry.attempts.append(f"[{a:.6g}, {b:.6g}]: {exc}")
                continue
            if r is None:
                entry.attempts.append(f"[{a:.6g}, {b:.6g}]: no sign change in {prec.value} at launch_distance = {e_N:g}")
                continue
            if not r.success:
                entry.attempts.append(f"[{a:.6g}, {b:.6g}]: {r.message}")
                entry.iterations, entry.residual = r.iterations, r.residual
                continue
            orb = orbit(r)
            summ = summarize(r, orb)
            if summ["pulses"] != N:
                entry.attempts.append(f"[{a:.6g}, {b:.6g}]: converged orbit has {summ['pulses']} pulses")
                continue
            r.pulses_counted = summ["pulses"]
            summ.update({"bracket": [a, b], "free_value": getattr(r.params, free), "noise_floor": r.noise_floor,
                         "precision": r.precision.value})
            if with_uncertainty:
                summ["uncertainty"] = uncertainty(params, free, N, a, b, tol=tol)
                r.uncertainty = summ["uncertainty"]
            entry = PulseSearch(True, r.message, N, [r], [orb], summ, residual=r.residual)
            break
        if not entry.success and entry.attempts:
            entry.message = "; ".join(entry.attempts)
        found.append(entry)
    return found


# --- the public search -------------------------------------------------------------------------------------------
def _count(name: str, value, minimum: int = 1) -> int:
    """A count in [minimum, LIMITS[name]] (core.limits: the command line's limits, in its words)."""
    from ..core.limits import LIMITS

    v = require_positive_int(name, value)
    if v < minimum:
        raise ParameterError(name, f"must be >= {minimum}, got {value!r}")
    if name in LIMITS and v > LIMITS[name]:
        raise ParameterError(name, f"must be <= {LIMITS[name]} (the limit of what this command can finish), got "
                                   f"{value!r}")
    return v


@renamed_keywords(params="system")
def multipulse_orbits(system=None, max_pulses: int = 4, *, free: str | None = None, span: float | None = None,
                      samples: int | None = None, with_uncertainty: bool = False, progress=None) -> MultipulseSearch:
    """Symmetric N-pulse homoclinic orbits, N = 1..max_pulses, to the saddle that exists at `params`.

    Parameters
    ----------
    system : System, or what converts to one (magrod.core.system.as_system)
        The model and its parameters.  Other models than the paper's rod: symmetric N-pulse homoclinic orbits to
        the straight twisted rod of a reversible model (magrod.orbits.reversible.multipulse; a ParameterError
        naming the model if it has no reversor or no saddle-focus).  The paper's rod:
        mu = 2 lam (within MU_TOL): the saddle is the straight rod and symmetric orbits are of codimension one --
        each exists at its own value of `free`, searched within value * [1 - span, 1 + span]; mu > 2 lam: the
        saddle is the helical periodic one and orbits are generic, found at `params` (launch-angle scan).
    max_pulses : int
        Largest N (>= 1).
    free : str, optional
        Straight rod only: the parameter solved for with T (lam, m, gamma or delta; mu follows on mu = 2 lam;
        default lam).  Given for the periodic saddle it is refused (it would be ignored).
    span : float, optional
        Straight rod only: relative scan range of `free`, in (0, 1) (default 0.5); refused for the periodic
        saddle.
    samples : int, optional
        Scan samples: values of `free` (straight rod, default 81) or launch angles (periodic saddle, default 121).
    with_uncertainty : bool
        Straight rod: also the free parameter at two launch distances and two precisions (~4x the cost;
        MultipulseOrbit.uncertainty with its significant digits).  No effect for the periodic saddle (its orbits
        are generic: no parameter is solved for).
    progress : callable, optional
        progress(k) after each scan sample (straight rod).

    Returns
    -------
    MultipulseSearch
        Indexable collection of MultipulseOrbit (pulses, T, x0, residual, params, saddle, `.sample(n)`,
        `.accuracy`, `.plot()`), one PulseSearch per N in `searches` and those that gave no orbit in `failures`;
        success iff at least one orbit.

    Raises
    ------
    ParameterError
        "mu" if mu < 2 lam (no saddle near the straight rod); "m" if the saddle is not hyperbolic; "max_pulses",
        "samples", "span" or "free" if out of range (the command line's limits, core.limits) or given for the
        periodic saddle; "lam" ("free") if the free parameter is zero.

    Examples
    --------
    >>> import magrod as mr
    >>> from magrod.orbits.multipulse import multipulse_orbits
    >>> fig6 = mr.RodParams(m=1.7, mu=0.002, gamma=1, delta=1, lam=0.001)    # fig:multimodal1, mu = 2 lam
    >>> found = multipulse_orbits(fig6, max_pulses=2, samples=41)
    >>> [(o.pulses, round(o.free_value, 9)) for o in found]    # lam* of the 2-pulse orbit (docs/errata.md)
    [(2, 0.001262081)]
    >>> found[0].residual < 1e-10, [f.pulses_target for f in found.failures]
    (True, [1])

    Notes
    -----
    Method: shooting onto Fix(R) with the one engine (magrod.orbits.shooting): a scan (sin psi at the N-th zero of
    pbar_theta over the free parameter, or over the launch angle), bisection on the sign changes, Newton with the
    variational Jacobian; an orbit is kept only if its counted pulses equal N.  Precision: double for N = 1, long
    double and launch distance 1e-9 from N = 2 (tolerances.LAUNCH_DISTANCE).  Accuracy: residual <= 1e-10
    (SHOOTING_TOL) or within the measured rounding floor (straight rod, N >= 3: noise_floor and resolution
    say how far the free parameter can be from the root).  Cost: ~1-3 s per N in long double (bisection and
    Newton), ~4x with_uncertainty.  References: paper sec. 8 (fig:multimodal1, fig:multimodal2); van der Heijden,
    Champneys and Thompson 1998 (shooting for reversible homoclinic orbits); docs/errata.md (lam* table).
    """
    import time

    from ..core.system import as_system
    from .shooting import paper_saddle as saddle_of

    sysv, _ = as_system(system)
    if not sysv.is_paper:
        from .reversible import multipulse

        return multipulse(sysv, _count("max_pulses", max_pulses), samples=samples)
    params = sysv.rod
    max_pulses = _count("max_pulses", max_pulses)
    if samples is not None:
        samples = _count("samples", samples, minimum=3)
    t0 = time.perf_counter()
    s = saddle_of(params)  # the one mu = 2 lam rule (MU_TOL) decides the saddle
    orbits, searches = [], []
    if s.kind == "equilibrium":
        free = "lam" if free is None else free
        span = 0.5 if span is None else span
        try:
            ok = 0 < float(span) < 1
        except (TypeError, ValueError):
            ok = False
        if not ok:
            raise ParameterError("span", f"must be in (0, 1) (a relative range around the nominal value), got {span}")
        span, samples = float(span), samples or SCAN_INTERVALS + 1
        searches = find_orbits(params, free=free, max_pulses=max_pulses, span=span, samples=samples,
                               with_uncertainty=with_uncertainty, progress=progress, saddle=s)
        orbits = [o for ps in searches for o in ps.orbits]
    else:
        for name, v in (("span", span), ("free", free)):  # they shape the mu = 2 lam scan only
            if v is not None:
                raise ParameterError(name, f"applies to mu = 2 lam only (a scan of the free parameter); at mu = "
                                           f"{params.mu:g} != 2 lam = {2 * params.lam:g} the orbits to the periodic "
                                           f"saddle are found at the given parameters: drop {name}")
        from . import periodic_multipulse as pm

        samples = samples or ANGLE_SAMPLES
        for N in range(1, max_pulses + 1):
            got = pm.find(params, N, samples=samples, saddle=s)
            msg = (f"{len(got)} symmetric {N}-pulse orbit(s) to the periodic saddle" if got else
                   f"no sign change of sin psi over the launch-angle scan ({samples} angles) converged to a "
                   f"{N}-pulse orbit")
            searches.append(PulseSearch(bool(got), msg, N, list(got), residual=max((o.residual for o in got),
                                                                                 default=math.nan)))
            orbits += got
    failures = [ps for ps in searches if not ps.success]
    n = len(orbits)
    msg = (f"{n} symmetric orbit(s) to the {'straight rod' if s.kind == 'equilibrium' else 'periodic saddle'} "
           f"for N <= {max_pulses}" + (f"; none for N = {[f.pulses_target for f in failures]}" if failures else ""))
    return MultipulseSearch(n > 0, msg, params, s, orbits, failures, max_pulses,
                            free if s.kind == "equilibrium" else None, time.perf_counter() - t0, searches,
                            span if s.kind == "equilibrium" else None, samples, bool(with_uncertainty), sysv)
