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
from dataclasses import dataclass, field

import numpy as np

from ..core.errors import ParameterError, require_positive_int
from ..core.params import RodParams
from ..core.precision import Precision
from ..core.results import Result, jsonable
from ..core.tolerances import BISECTION_RTOL, FLOOR_CAP, FLOOR_FACTOR, LAUNCH_DISTANCE, LAUNCH_DISTANCES, SHOOTING_TOL, STALL_ITERATIONS
from ..generated.names import PARAMS
from . import shooting
from .equilibrium import StraightRod, on_level, straight_rod
from .shooting import (MultipulseOrbit, count_pulses, fix_functions, residual_and_jacobian,
                       shooting_precision, unstable_branch)

MAX_DIGITS = 15  # significant digits a float64 value is printed with (`significant`)
# the free-parameter scan: this many intervals over value * [1 - span, 1 + span] (1.25 % of the value each at
# span 0.5), i.e. SCAN_INTERVALS + 1 samples
SCAN_INTERVALS = 80
ANGLE_SAMPLES = 121  # launch angles of the periodic saddle's scan (3 degrees apart)
# mu is not free: it follows the free parameter so that the straight rod stays on the chart's level (mu = 2 lam)
FREE_PARAMETERS = ("lam",) + tuple(p for p in PARAMS if p not in ("mu", "lam"))


# --- Newton ------------------------------------------------------------------------------------------------
def shoot(params: RodParams, crossing: int, *, free: str | None = "lam", eps: float | None = None,
          tol: float = SHOOTING_TOL, max_iter: int = 25, T_guess: float | None = None, precision=None,
          saddle: StraightRod | None = None) -> MultipulseOrbit:
    """Newton on (T, free parameter) for (pbar_theta, sin psi)(x(T)) = 0 at the `crossing`-th zero of pbar_theta.

    free=None is allowed only when the sin(psi) condition is void, i.e. lam = 0 (then mu = 0, the force is
    along the field and psi is a gauge): unknown T, condition pbar_theta = 0.  Cost: one variational
    integration (135 equations) per iteration, ~10-50 ms each (x10 in long double).  saddle: the straight rod
    at `params` if already computed.

    precision None (automatic): double for the first crossing, long double and eps = LAUNCH_DISTANCE[long double]
    (1e-9) for later crossings.  Near the saddle psi is the angle of the transverse force rho ~ sqrt(lam) theta
    (~1e-6 there), so psi after (or at) a near-saddle passage inherits the O(eps^2) error of the linear launch
    and the rounding of n divided by rho: in double precision this puts a floor of ~1e-8..1e-7 on the residual
    (measured), in long double with eps = 1e-9 it is ~1e-11 for N = 2 and grows with N (~1e-9 for N = 6: each
    near-saddle passage amplifies the rounding).

    Near the root the residual is noise, so Newton keeps its best iterate and stops after STALL_ITERATIONS
    without halving it.  If the best residual is above tol, the noise floor there is measured (`noise_floor`:
    the non-linear part of r at a few ulp of the free parameter); the result counts as converged iff the best
    residual is within FLOOR_FACTOR x that floor and below FLOOR_CAP, with `noise_floor` set and the message
    saying so (`resolution`: how far the free parameter can be from the root, through J^-1)."""
    crossing = require_positive_int("crossing", crossing)
    prec = shooting_precision(crossing, precision)
    if eps is None:
        eps = LAUNCH_DISTANCE[prec]
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
    s = saddle if saddle is not None else straight_rod(params)
    if T_guess is None:
        br = unstable_branch(s, crossings=crossing, eps=eps)
        if len(br) < crossing:
            raise ParameterError("crossing", f"the unstable branch has only {len(br)} zeros of pbar_theta before "
                                             f"t = 2000 (no homoclinic level reached)")
        T_guess = br[crossing - 1].t
    T = float(T_guess)
    history = []
    res = math.inf
    best = None  # (residual, saddle, T, x0, r, J) of the best iterate: near the root the residual is noise
    stall = 0
    x0 = s.launch_point(eps)

    def result(success, message, s_, T_, x0_, res_, iterations, **kw):
        return MultipulseOrbit(success, message, s_.params, s_, crossing, T_, x0_, res_, iterations, eps, prec,
                               free=free, history=history, **kw)

    for it in range(1, max_iter + 1):
        ev = residual_and_jacobian(s, T, eps=eps, precision=prec, free=() if free is None else (free,))
        x0, r = ev.x0, ev.r
        if void_psi:
            r = r[:1]
        res = float(np.max(np.abs(r)))
        history.append({"iteration": it, "T": T, "free_value": getattr(s.params, free) if free else None,
                        "residual": res})
        if not np.isfinite(res):
            break
        if void_psi and res <= tol:
            return result(True, f"converged in {it - 1} Newton steps", s, T, x0, res, it - 1, xT=ev.xT)
        if void_psi:
            T += -r[0] / ev.J[0, 0]
            continue
        Jm = ev.J
        if res <= tol:
            return result(True, f"converged in {it - 1} Newton steps", s, T, x0, res, it - 1,
                          resolution=_resolution(Jm, r), xT=ev.xT)
        if best is None or res < 0.5 * best[0]:
            stall = 0
        else:
            stall += 1
        if best is None or res < best[0]:
            best = (res, s, T, x0, r, Jm, ev.xT)
        if stall >= STALL_ITERATIONS:
            break
        try:
            step = -np.linalg.solve(Jm, r)
        except np.linalg.LinAlgError:
            break
        # damp steps that would leave the region where the crossing index is meaningful
        v = getattr(s.params, free)
        lim = 0.25 * max(abs(v), 1e-6)
        if abs(step[1]) > lim:
            step *= lim / abs(step[1])
        T += step[0]
        try:
            s = straight_rod(on_level(s.params, **{free: v + step[1]}))
        except ParameterError:
            break
    if best is not None and best[0] <= FLOOR_CAP:
        res_b, s_b, T_b, x0_b, r_b, J_b, xT_b = best
        floors = noise_floor(s_b, free, T_b, r_b, J_b[:, 1], eps=eps, precision=prec)
        floor = float(np.max(floors))
        if res_b <= FLOOR_FACTOR * floor:
            unc = _resolution(J_b, np.maximum(np.abs(r_b), floors))
            return result(True, f"converged to the noise floor of {prec.value} arithmetic: residual {res_b:.2e} <= "
                                f"floor {floor:.2e} (tol {tol:.1e} below it; {free} resolved to {unc:.1e})",
                          s_b, T_b, x0_b, res_b, len(history), noise_floor=floor, resolution=unc, xT=xT_b)
    return result(False, f"not converged after {len(history)} iterations (last residual {res:.3e} > tol {tol:.1e})",
                  s, T, x0, res, len(history))


def _resolution(Jm, r) -> float:
    """How far the free parameter can be from the root when |residual_j| <= r_j (componentwise):
    sum_j |(J^-1)_{1j}| r_j."""
    try:
        return float(np.abs(np.linalg.inv(Jm)[1]) @ np.broadcast_to(np.abs(np.asarray(r, dtype=float)), (2,)))
    except np.linalg.LinAlgError:
        return math.nan


def noise_floor(s: StraightRod, free: str, T: float, r0, drdv, *, eps: float, precision=Precision.DOUBLE,
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
        x = shooting.propagate(q.launch_point(eps, 0.0, precision), q.params.array(), T, precision)
        worst = np.maximum(worst, np.abs(fcond(x, []) - np.asarray(r0) - k * h * np.asarray(drdv)))
    return worst


def orbit(result: MultipulseOrbit, n: int = 4001) -> dict:
    """The symmetric orbit of a converged shooting result (MultipulseOrbit.sample)."""
    return result.sample(n)


def summarize(result: MultipulseOrbit, orb: dict | None = None) -> dict:
    """pulses, residual, arclength (between the two eps-points: 2 T), H (and its deviation from the saddle's)."""
    orb = orb or orbit(result)
    return {"pulses": count_pulses(orb["theta"]), "crossing": result.pulses, "residual": result.residual,
            "noise_floor": result.noise_floor, "iterations": result.iterations, "arclength": 2 * result.T, "eps": result.eps,
            "H": float(np.mean(orb["H"])), "H_saddle": result.saddle_H,
            "max_abs_H_minus_saddle": float(np.max(np.abs(orb["H"] - result.saddle_H))),
            "theta_max": float(np.max(orb["theta"])), "free": result.free,
            "params": result.params.as_dict()}


# --- search ----------------------------------------------------------------------------------------------------
def _saddle_at(params: RodParams, free: str, value: float) -> StraightRod | None:
    """The straight rod at free = value (mu on its level), or None where there is none."""
    try:
        return straight_rod(on_level(params, **{free: value}))
    except ParameterError:
        return None


def scan(params: RodParams, free: str, values, crossings: int, eps: float = LAUNCH_DISTANCE[Precision.DOUBLE],
         progress=None):
    """sin(psi) at the first `crossings` zeros of pbar_theta along the unstable branch for each value of the
    free parameter: array (len(values), crossings) (nan where the branch has fewer crossings)."""
    out = np.full((len(values), crossings), np.nan)
    for i, v in enumerate(values):
        s = _saddle_at(params, free, v)
        for c in unstable_branch(s, crossings=crossings, eps=eps) if s is not None else []:
            out[i, c.index - 1] = c.sinpsi
        if progress is not None:
            progress(1)
    return out


def crossing_sinpsi(params: RodParams, free: str, value: float, crossing: int, *, eps: float,
                    precision=Precision.DOUBLE):
    """(sin psi, t) at the `crossing`-th zero of pbar_theta on the unstable branch at free = value (mu on the
    straight rod's level), or None if the branch does not get there (or there is no saddle)."""
    s = _saddle_at(params, free, value)
    if s is None:
        return None
    br = unstable_branch(s, crossings=crossing, eps=eps, precision=precision)
    if len(br) < crossing:
        return None
    return br[-1].sinpsi, br[-1].t


def bisect(params: RodParams, free: str, crossing: int, a: float, b: float, *, eps: float,
           precision=Precision.DOUBLE, rtol: float = BISECTION_RTOL, max_iter: int = 60) -> dict | None:
    """Bisection on g(v) = sin psi at the `crossing`-th zero of pbar_theta over a bracket [a, b] of the free
    parameter (the pbar_theta condition holds exactly at the event, so this is the 1-D form of the shooting
    problem).  Stops at relative width rtol (a few ulp: inside the noise band it just picks a point in it).
    Returns {value, T, g, width, iterations} or None if [a, b] is not a sign change in this precision and eps
    (or is a jump of psi through the chart's cut, |g(a) - g(b)| >= 1).  Cost: one crossing integration per step
    (~5-50 ms in double, x10 in long double)."""
    ga, gb = (crossing_sinpsi(params, free, v, crossing, eps=eps, precision=precision) for v in (a, b))
    if ga is None or gb is None or np.sign(ga[0]) == np.sign(gb[0]) or abs(ga[0] - gb[0]) >= 1.0:
        return None
    it = 0
    mid = (ga[0], ga[1])
    while abs(b - a) > rtol * max(abs(a), abs(b)) and it < max_iter:
        it += 1
        m = 0.5 * (a + b)
        gm = crossing_sinpsi(params, free, m, crossing, eps=eps, precision=precision)
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


def free_star(params: RodParams, free: str, crossing: int, a: float, b: float, *, eps: float, precision,
              tol: float = SHOOTING_TOL) -> MultipulseOrbit | None:
    """The orbit at the `crossing`-th zero in the bracket [a, b]: bisection (same eps and precision) then
    Newton on (T, free) from the bisected value; None if the bracket is not a sign change here.  A failed Newton
    is returned as such (success False)."""
    prec = Precision.parse(precision)
    bis = bisect(params, free, crossing, a, b, eps=eps, precision=prec)
    if bis is None:
        return None
    q = on_level(params, **{free: bis["value"]})
    return shoot(q, crossing, free=free, eps=eps, tol=tol, T_guess=bis["T"], precision=prec)


def uncertainty(params: RodParams, free: str, crossing: int, a: float, b: float, *, tol: float = SHOOTING_TOL,
                eps_values=LAUNCH_DISTANCES) -> dict:
    """The free parameter of one orbit (bracket [a, b], `crossing`) at two launch distances (eps_values) in
    double and in long double.  value: the long double run at the smaller eps; uncertainty: the larger of the
    two long double values' difference and their Newton resolutions (residual or noise floor through J^-1);
    double_check: the largest |double - value| with the double runs' resolution (the double floor after
    near-saddle passages is 1e-8..1e-6, so double only confirms the leading digits); significant: value to its
    significant digits with the uncertainty of the last digit in brackets ('0.00113526146263(9)')."""
    runs = []
    for prec in (Precision.DOUBLE, Precision.LONG_DOUBLE):
        for e in eps_values:
            r = free_star(params, free, crossing, a, b, eps=e, precision=prec, tol=tol)
            row = {"eps": e, "precision": prec.value, "success": bool(r is not None and r.success)}
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
                samples: int = SCAN_INTERVALS + 1, eps: float | None = None, tol: float = SHOOTING_TOL, progress=None,
                max_brackets: int = 8, with_uncertainty: bool = False, saddle: StraightRod | None = None) -> list[dict]:
    """For N = 1..max_pulses: scan the free parameter over value * [1 - span, 1 + span] (linearly, `samples`
    points, double precision), bracket sign changes of sin(psi) at the N-th crossing, and from the brackets
    nearest to the nominal value (at most max_brackets): bisect on sin(psi) in the shooting precision (long
    double for N >= 2, as `shoot`), then Newton on (T, free) from the bisected value; keep converged orbits
    whose counted pulses equal N.  with_uncertainty: also the free parameter at two eps and two precisions
    (`uncertainty`, ~4x the cost).  Returns one entry per N (the converged orbit closest to the nominal value,
    or a failure record listing what each bracket gave).  saddle: the straight rod at `params` if already
    computed."""
    if free not in FREE_PARAMETERS:
        raise ParameterError("free", f"must be one of {FREE_PARAMETERS}, got {free!r}")
    max_pulses = require_positive_int("max_pulses", max_pulses)
    max_brackets = require_positive_int("max_brackets", max_brackets)
    s = saddle if saddle is not None else straight_rod(params)  # ParameterError early if there is no saddle
    if params.lam == 0:
        # integrable case (psi is a gauge): only the primary orbit, unknown T alone
        r = shoot(params, 1, free=None, eps=eps, tol=tol, saddle=s)
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
    table = scan(params, free, vals, max_pulses, LAUNCH_DISTANCE[Precision.DOUBLE], progress)
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
        prec = shooting_precision(N)
        e_N = eps if eps is not None else LAUNCH_DISTANCE[prec]
        for i in idx[:max_brackets]:
            a, b = float(vals[i]), float(vals[i + 1])
            try:
                r = free_star(params, free, N, a, b, eps=e_N, precision=prec, tol=tol)
            except ParameterError as exc:
                entry["attempts"].append(f"[{a:.6g}, {b:.6g}]: {exc}")
                continue
            if r is None:
                entry["attempts"].append(f"[{a:.6g}, {b:.6g}]: no sign change in {prec.value} at eps = {e_N:g}")
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
            r.pulses_counted = summ["pulses"]
            entry = {"pulses_target": N, "success": True, "message": r.message, **summ, "bracket": [a, b],
                     "free_value": getattr(r.params, free), "noise_floor": r.noise_floor,
                     "precision": r.precision.value, "result": r, "orbit": orb}
            if with_uncertainty:
                entry["uncertainty"] = uncertainty(params, free, N, a, b, tol=tol)
                r.uncertainty = entry["uncertainty"]
            break
        if not entry["success"] and entry["attempts"]:
            entry["message"] = "; ".join(entry["attempts"])
        found.append(entry)
    return found


# --- the public search -------------------------------------------------------------------------------------------
@dataclass(repr=False)
class MultipulseSearch(Result):
    """The symmetric multipulse homoclinic orbits found at (or, for the straight rod, near) `params`: `orbits`
    (MultipulseOrbit, ordered by pulses; indexable: search[0]), `failures` (one dict per N without an orbit:
    pulses_target, message), the saddle, and the search settings."""

    success: bool
    message: str
    params: RodParams
    saddle: object
    orbits: list
    failures: list = field(default_factory=list)
    max_pulses: int = 0
    free: str | None = None
    wall_time_s: float = 0.0

    _repr_fields = ("kind", "params", "pulses", "failures")

    @property
    def kind(self) -> str:
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

    def to_dict(self) -> dict:
        return {"success": self.success, "message": self.message, "kind": self.kind,
                "params": self.params.as_dict(), "saddle_H": self.saddle.H, "max_pulses": self.max_pulses,
                "free": self.free, "orbits": [o.to_dict() for o in self.orbits], "failures": jsonable(self.failures),
                "wall_time_s": self.wall_time_s}


def multipulse_orbits(params: RodParams, max_pulses: int = 4, *, free: str = "lam", span: float = 0.5,
                      samples: int | None = None, with_uncertainty: bool = False, progress=None) -> MultipulseSearch:
    """Symmetric N-pulse homoclinic orbits, N = 1..max_pulses, to the saddle that exists at `params`.

    Parameters
    ----------
    params : RodParams
        mu = 2 lam (within MU_TOL): the saddle is the straight rod and symmetric orbits are of codimension one --
        each exists at its own value of `free`, searched within value * [1 - span, 1 + span]; mu > 2 lam: the
        saddle is the helical periodic one and orbits are generic, found at `params` (launch-angle scan).
    max_pulses : int
        Largest N (>= 1).
    free : str
        Straight rod only: the parameter solved for with T (lam, m, gamma or delta; mu follows on mu = 2 lam).
    span : float
        Straight rod only: relative scan range of `free`, in (0, 1).
    samples : int, optional
        Scan samples: values of `free` (straight rod, default 81) or launch angles (periodic saddle, default 121).
    with_uncertainty : bool
        Straight rod only: also the free parameter at two launch distances and two precisions (~4x the cost;
        MultipulseOrbit.uncertainty with its significant digits).
    progress : callable, optional
        progress(k) after each scan sample (straight rod).

    Returns
    -------
    MultipulseSearch
        Indexable collection of MultipulseOrbit (pulses, T, x0, residual, params, saddle, `.sample(n)`,
        `.accuracy`, `.plot()`), with the N that gave no orbit in `failures`; success iff at least one orbit.

    Raises
    ------
    ParameterError
        "mu" if mu < 2 lam (no saddle near the straight rod); "m" if the saddle is not hyperbolic; "max_pulses",
        "samples", "span" or "free" if out of range; "lam" ("free") if the free parameter is zero.

    Examples
    --------
    >>> import magrod as mr
    >>> from magrod.orbits.multipulse import multipulse_orbits
    >>> fig6 = mr.RodParams(m=1.7, mu=0.002, gamma=1, delta=1, lam=0.001)    # fig:multimodal1, mu = 2 lam
    >>> found = multipulse_orbits(fig6, max_pulses=2, samples=41)
    >>> [(o.pulses, round(o.free_value, 9)) for o in found]    # lam* of the 2-pulse orbit (docs/errata.md)
    [(2, 0.001262081)]
    >>> found[0].residual < 1e-10, [f["pulses_target"] for f in found.failures]
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

    from .shooting import saddle as saddle_of

    if not isinstance(params, RodParams):
        raise ParameterError("params", f"must be a RodParams, got {type(params).__name__}")
    max_pulses = require_positive_int("max_pulses", max_pulses)
    if samples is not None:
        samples = require_positive_int("samples", samples)
        if samples < 3:
            raise ParameterError("samples", f"must be >= 3, got {samples}")
    t0 = time.perf_counter()
    s = saddle_of(params)
    orbits, failures = [], []
    if s.kind == "equilibrium":
        if not (0 < float(span) < 1):
            raise ParameterError("span", f"must be in (0, 1), got {span}")
        found = find_orbits(params, free=free, max_pulses=max_pulses, span=float(span), samples=samples or SCAN_INTERVALS + 1,
                            with_uncertainty=with_uncertainty, progress=progress, saddle=s)
        for e in found:
            if e["success"]:
                orbits.append(e["result"])
            else:
                failures.append({"pulses_target": e["pulses_target"], "message": e["message"]})
        free_used = free
    else:
        from . import periodic_multipulse as pm

        for N in range(1, max_pulses + 1):
            got = pm.find(params, N, samples=samples or ANGLE_SAMPLES, saddle=s)
            if not got:
                failures.append({"pulses_target": N, "message": "no sign change of sin psi over the launch-angle "
                                 "scan converged to a symmetric orbit with this many pulses"})
            orbits += got
        free_used = None
    n = len(orbits)
    msg = (f"{n} symmetric orbit(s) to the {'straight rod' if s.kind == 'equilibrium' else 'periodic saddle'} "
           f"for N <= {max_pulses}" + (f"; none for N = {[f['pulses_target'] for f in failures]}" if failures else ""))
    return MultipulseSearch(n > 0, msg, params, s, orbits, failures, max_pulses, free_used,
                            time.perf_counter() - t0)
