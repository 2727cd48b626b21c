"""Poincare sections sin(psi) = 0 of the reduced system (paper sec. 8, fig:poincare1, fig:poincare2).

Public API
----------
solve_p_psi(params, h, theta0, ptheta0, psi0=0)  -> every real root pbar_psi of Hbar(theta0, psi0, ptheta0, .) = h
poincare_map(params, h, theta0, ptheta0, psi0=0, *, iterates=10_000, root="smallest", direction="positive",
             branch="any", formulation="body", ...) -> PoincareResult
run_panels(keys, ...), figure_4(out_dir, quick=False), figure_5(out_dir, quick=False), save_result(...)

What is integrated
------------------
* formulation="body": the singularity-free 9-D body-frame system in (m, n, e3) (generated/body.py) for the
  whole run.  The section sin(psi) = 0 is written in body variables through the chart of
  derive/numeric_scale.py: with b = (-e32, e31, 0)/sin(theta) one has n.b = rho sin(psi), so
  g = e31 n2 - e32 n1 = sin(theta) rho sin(psi) has the zeros *and the crossing direction* of sin(psi)
  (sin(theta) > 0, rho = sqrt(mu - 2 lam pbar_psi)/m^2 > 0).
* formulation="reduced": the paper's canonical 4-D system in (theta, psi, pbar_theta, pbar_psi)
  (eq:full_ham_nondim) wherever the Euler-angle chart is well conditioned.  Hbar has 1/sin(theta)^2 and
  sqrt(mu - 2 lam pbar_psi) terms; the paper's orbits pass within sin(theta) ~ 1e-4 of the poles and within
  1e-7 of the radicand zero, where the 4-D vector field is nearly singular and Hbar cannot even be
  *evaluated* to better than eps/sin(theta)^2.  Terminal events detect sin(theta) < pole_switch[0] or
  radicand < radicand_switch[0]; the orbit is then continued in the body frame and handed back to the 4-D
  system once sin(theta) > pole_switch[1] and radicand > radicand_switch[1] (hysteresis).  Each point records
  the frame it was computed in.

Section points are landed by heyoka stopping terminal events (t_event without callback) in a loop, so each
point lies on sin(psi) = 0 to ~1e-16.  psi grows without bound in the 4-D system; it is reduced by 2 pi at
every stop (heyoka switches to relative error control on large state components, which would cost accuracy).
Integrators are cached per thread and reused (state/time reset, never recompiled); several panels run in
threads (heyoka's propagate releases the GIL).

The section direction is the sign of d/dt sin(psi) = cos(psi) psi' at the crossing ("positive",
"negative", "any"); branch selects psi = 0 (cos psi > 0) or psi = pi crossings ("0", "pi", "any").
Defaults: direction="positive", branch="any", root="smallest".  The paper states none of them; the evidence
(benchmarks/README.md): it reports 10 000 iterates for runs "up to t = 84 000" (fig:poincare1).  Counting every
crossing gives ~4 time units per iterate, a one-directional section ~6-9.  On the Fig 4 start Hbar = h has two
roots pbar_psi; the smaller one gives final times 69.9k, 72.0k, 85.9k, 81.5k for panels (a)-(d) (max ~84k as
printed) and a monotone break-up of a closed curve (d) into a chaotic sea (a) as lam decreases, which is what
the text describes; the larger root gives 57.7k-76.4k and regular islands in (b)-(d).

Cost (float64, tol = eps, one core): ~0.2 ms per iterate in the body frame, ~0.5 ms with formulation="reduced";
the 8 paper panels (80 000 iterates) take ~8-12 s wall on 2 cores with a warm JIT cache (benchmarks/).  The first process compiles each integrator (~1 s), later
processes load it from heyoka's on-disk cache.
"""
from __future__ import annotations

import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import heyoka as hy
import numpy as np
from scipy.optimize import brentq

from . import systems
from .errors import ParameterError, require_finite, require_positive_int
from .params import RodParams

DIRECTIONS = {"positive": hy.event_direction.positive, "negative": hy.event_direction.negative,
              "any": hy.event_direction.any}
BRANCHES = ("any", "0", "pi")
FORMULATIONS = ("reduced", "body")
FRAME_REDUCED, FRAME_BODY = 0, 1
# The body frame is the default: singularity-free, ~3x faster than the 4-D chart (polynomial vector field) and
# Hbar conserved to ~1e-13 on every paper panel; "reduced" (the paper's 4-D system, body-frame patches near the
# chart singularities) agrees with it to ~1e-11 over the first 50 crossings and conserves Hbar to < 1e-12.
DEFAULT_FORMULATION = "body"
DEFAULT_ROOT = "smallest"  # see the module docstring for the evidence

# The paper's panels (sec. 8).  fig:poincare1: one orbit per panel from theta = 0.1, pbar_theta = 0.5, psi = 0 at
# h = 0.9; fig:poincare2: from theta = 0.1, pbar_theta = 1, psi = 0 at h = 0.8.
_F4 = dict(m=1.7, mu=0.4, gamma=3.0, delta=3.0)
_F5 = dict(m=1.7, mu=4.0, delta=0.25, lam=2.0)
PANELS = {
    **{f"4{k}": dict(params=RodParams(**_F4, lam=lam), h=0.9, theta0=0.1, ptheta0=0.5, psi0=0.0,
                     label=f"fig:poincare1{k}", vary=("lam", lam))
       for k, lam in zip("abcd", (0.135, 0.1575, 0.175, 0.186))},
    **{f"5{k}": dict(params=RodParams(**_F5, gamma=g), h=0.8, theta0=0.1, ptheta0=1.0, psi0=0.0,
                     label=f"fig:poincare2{k}", vary=("gamma", g))
       for k, g in zip("abcd", (0.15, 0.205, 0.208, 0.24))},
}
# paper: "runs up to t = 84000" (fig:poincare1) and "t = 81000" (fig:poincare2), Hbar preserved to 3.6e-9 / 3.9e-9
PAPER_CLAIMS = {"4": dict(t_final=84000.0, max_abs_dH=3.6e-9), "5": dict(t_final=81000.0, max_abs_dH=3.9e-9)}


# ----------------------------------------------------------------------------------------------------------
# initial data
# ----------------------------------------------------------------------------------------------------------
def _admissible_interval(params: RodParams):
    """Open interval of pbar_psi where the radicand mu - 2 lam pbar_psi of Hbar is > 0 (eq:alignment_condition)."""
    if params.lam > 0:
        return -np.inf, params.mu / (2 * params.lam)
    if params.lam < 0:
        return params.mu / (2 * params.lam), np.inf
    if params.mu <= 0:
        raise ParameterError("mu", f"with lam = 0 the square root sqrt(mu - 2 lam pbar_psi) = sqrt(mu) of Hbar is "
                                   f"imaginary or zero for every pbar_psi (mu = {params.mu}); need mu > 0")
    return -np.inf, np.inf


def _check_start(theta0, ptheta0, psi0, h=None):
    theta0 = require_finite("theta0", theta0)
    ptheta0 = require_finite("ptheta0", ptheta0)
    psi0 = require_finite("psi0", psi0)
    if h is not None:
        h = require_finite("h", h)
    if not (0.0 < theta0 < np.pi) or np.sin(theta0) < 1e-8:
        raise ParameterError("theta0", f"must lie strictly inside (0, pi), away from the Euler-angle singularity "
                                       f"sin(theta) = 0 of Hbar, got {theta0!r}")
    return theta0, ptheta0, psi0, h


def solve_p_psi(params: RodParams, h, theta0, ptheta0, psi0=0.0) -> np.ndarray:
    """All real roots pbar_psi of Hbar(theta0, psi0, pbar_theta0, pbar_psi) = h, ascending.

    Hbar is smooth on the admissible half-line mu - 2 lam pbar_psi > 0 and grows like
    (pbar_psi - cos theta)^2 / (2 sin^2 theta) at infinity, so its level set is bounded: the scan interval is
    widened by doubling until Hbar > h and increasing outwards, then sign changes on a dense grid (uniform, plus
    geometric towards the radicand zero where Hbar has a square-root edge) are polished with brentq
    (xtol = 1e-15) and the best of the three neighbouring doubles is kept, so |Hbar - h| is at the rounding
    level of Hbar.
    Raises ParameterError("h") if there is no root, ParameterError("mu") if no pbar_psi is admissible."""
    theta0, ptheta0, psi0, h = _check_start(theta0, ptheta0, psi0, h)
    H = systems.reduced_functions()["H"]
    pars = params.array()
    lo, hi = _admissible_interval(params)

    def f(q):
        q = np.atleast_1d(np.asarray(q, dtype=float))
        x = np.ascontiguousarray(np.vstack([np.full_like(q, theta0), np.full_like(q, psi0),
                                            np.full_like(q, ptheta0), q]))
        return H(x, pars)[0] - h

    # bracket [a, b] of the level set: on each unbounded side walk outwards (doubling) until Hbar > h and
    # still increasing outwards, beyond which the quadratic term keeps it increasing
    anchor = hi if np.isfinite(hi) else (lo if np.isfinite(lo) else np.cos(theta0))
    ends = {}
    for side, edge in ((-1, lo), (+1, hi)):
        if np.isfinite(edge):
            ends[side] = edge
            continue
        w = 1.0
        for _ in range(80):
            e = anchor + side * w
            if f(e)[0] > 0 and f(e + side * w)[0] > f(e)[0]:
                break
            w *= 2.0
        ends[side] = anchor + side * 2 * w
    a, b = ends[-1], ends[+1]
    grids = [np.linspace(a, b, 20001)]
    for edge, sgn in ((lo, +1), (hi, -1)):
        if np.isfinite(edge):  # geometric grid towards the square-root edge
            grids.append(edge + sgn * np.geomspace(1e-15 * max(1.0, abs(edge)), b - a, 4000))
    q = np.unique(np.concatenate(grids))
    q = q[(q > lo) & (q < hi) & (q >= a) & (q <= b)]
    v = f(q)
    ok = np.isfinite(v)
    q, v = q[ok], v[ok]
    roots = []
    for i in np.nonzero(v == 0.0)[0]:
        roots.append(q[i])
    for i in np.nonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0)[0]:
        r = brentq(lambda s: f(s)[0], q[i], q[i + 1], xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
        # the last ulp: pick the neighbour with the smaller residual
        cand = np.array([np.nextafter(r, -np.inf), r, np.nextafter(r, np.inf)])
        roots.append(cand[np.argmin(np.abs(f(cand)))])
    roots = np.unique(np.array(roots, dtype=float))
    if roots.size == 0:
        vmin = float(np.min(v)) + h if v.size else np.nan
        raise ParameterError("h", f"Hbar(theta0={theta0}, psi0={psi0}, pbar_theta0={ptheta0}, pbar_psi) = h has no "
                                  f"real root pbar_psi on the admissible range mu - 2 lam pbar_psi > 0 "
                                  f"(min Hbar found there ~ {vmin:.6g} > h = {h})")
    return roots


def choose_root(roots, root="smallest") -> int:
    """Index into `roots` for root = "largest" | "smallest" | int (negative ints count from the end)."""
    n = len(roots)
    if root == "largest":
        return n - 1
    if root in ("smallest", None):
        return 0
    try:
        i = int(root)
    except (TypeError, ValueError):
        raise ParameterError("root", f"must be 'largest', 'smallest' or an integer index, got {root!r}") from None
    if not -n <= i < n:
        raise ParameterError("root", f"index {i} out of range: {n} root(s) {np.array2string(np.asarray(roots))}")
    return i % n


# ----------------------------------------------------------------------------------------------------------
# integrators (built once per thread and configuration, reused by resetting time/state/pars)
# ----------------------------------------------------------------------------------------------------------
_local = threading.local()


def _integrators(formulation, direction, pole_switch, radicand_switch, fp_type, tol):
    cache = _local.__dict__.setdefault("cache", {})
    key = (formulation, direction, pole_switch, radicand_switch, fp_type, tol)
    if key in cache:
        return cache[key]
    d = DIRECTIONS[direction]
    ev = (lambda g, dr: hy.t_event(g, direction=dr)) if fp_type is float else \
        (lambda g, dr: hy.t_event(g, direction=dr, fp_type=fp_type))
    m1, m2, m3, n1, n2, n3, e31, e32, e33 = systems.body_vars()
    p = [hy.par[i] for i in range(5)]
    # chart (euler_to_body): e3 = (-sin th cos phi, sin th sin phi, cos th), pbar_psi = m.e3
    body_events = [ev(e31 * n2 - e32 * n1, d)]
    if formulation == "reduced":
        sin2 = e31 ** 2 + e32 ** 2
        rad = p[1] - 2.0 * p[4] * (m1 * e31 + m2 * e32 + m3 * e33)
        body_events += [ev(sin2 - pole_switch[1] ** 2, hy.event_direction.positive),
                        ev(rad - radicand_switch[1], hy.event_direction.positive)]
    x9 = np.zeros(9)
    x9[2] = x9[8] = 1.0
    ta_b = systems.body_integrator(x9, np.ones(5), tol=tol, t_events=body_events, fp_type=fp_type)
    ta_r = None
    if formulation == "reduced":
        th, psi, pth, pps = systems.reduced_vars()
        red_events = [hy.t_event(hy.sin(psi), direction=d),
                      hy.t_event(hy.sin(th) - pole_switch[0], direction=hy.event_direction.negative),
                      hy.t_event(p[1] - 2.0 * p[4] * pps - radicand_switch[0], direction=hy.event_direction.negative)]
        ta_r = systems.reduced_integrator([1.0, 0.0, 0.0, 0.0], np.ones(5), tol=tol, t_events=red_events,
                                         fp_type=fp_type)
    cache[key] = (ta_r, ta_b)
    return ta_r, ta_b


def _set(ta, state, t, pars):
    ftype = type(ta.state[0])
    ta.state[:] = state
    ta.time = ftype(t) if ftype is not np.float64 else float(t)
    ta.pars[:] = pars
    ta.reset_cooldowns()


def _wrap(a):
    return a - 2 * np.pi * np.round(a / (2 * np.pi))


# ----------------------------------------------------------------------------------------------------------
# the map
# ----------------------------------------------------------------------------------------------------------
@dataclass
class PoincareResult:
    """One orbit's section points.  Arrays have length N = number of recorded iterates (N = iterates on success).

    points: (N, 4) Euler-chart coordinates (theta, psi, pbar_theta, pbar_psi), psi wrapped to (-pi, pi];
    times: (N,) arclength of each crossing; branch: (N,) +1 where psi = 0 (cos psi > 0), -1 where psi = pi;
    psi_dot_sign: (N,) sign of psi' at the crossing; frame: (N,) 0 = computed by the 4-D system,
    1 = by the body-frame system; dH: (N,) Hbar - h at each point (Hbar evaluated in the frame of the point:
    eq:full_ham_nondim for 4-D points, H_body - offset for body points, which is well conditioned at the poles);
    body_points: (N, 9) body state of body-frame points (NaN for 4-D points); section_residual: (N,) the event
    function at the point in its frame (sin(psi) for 4-D points, e31 n2 - e32 n1 for body points)."""

    success: bool
    message: str
    params: RodParams
    h: float
    theta0: float
    ptheta0: float
    psi0: float
    p_psi0: float
    roots: np.ndarray
    root_index: int
    formulation: str
    direction: str
    branch_filter: str
    tol: float
    iterates: int
    t_max: float
    points: np.ndarray
    times: np.ndarray
    branch: np.ndarray
    psi_dot_sign: np.ndarray
    frame: np.ndarray
    dH: np.ndarray
    body_points: np.ndarray
    section_residual: np.ndarray
    max_abs_dH: float
    casimir_drift: float | None
    final_time: float
    n_frame_switches: int
    wall_s: float
    fp_type: str = "float64"
    extra: dict = field(default_factory=dict)

    @property
    def n_points(self) -> int:
        return int(self.points.shape[0])

    def summary(self) -> dict:
        """JSON-able metadata (everything except the per-point arrays)."""
        return {"success": self.success, "message": self.message, "parameters": self.params.as_dict(),
                "h": self.h, "theta0": self.theta0, "ptheta0": self.ptheta0, "psi0": self.psi0,
                "p_psi0": self.p_psi0, "roots": [float(r) for r in self.roots], "root_index": self.root_index,
                "formulation": self.formulation, "direction": self.direction, "branch": self.branch_filter,
                "tol": self.tol, "iterates_requested": self.iterates, "n_points": self.n_points,
                "t_max": self.t_max, "final_time": self.final_time, "max_abs_dH": self.max_abs_dH,
                "casimir_drift": self.casimir_drift, "n_frame_switches": self.n_frame_switches,
                "fraction_body_frame_points": float(np.mean(self.frame == FRAME_BODY)) if self.n_points else 0.0,
                "max_abs_section_residual": float(np.max(np.abs(self.section_residual))) if self.n_points else 0.0,
                "wall_s": self.wall_s, "fp_type": self.fp_type, **self.extra}

    def arrays(self) -> dict:
        return {"points": self.points, "times": self.times, "branch": self.branch,
                "psi_dot_sign": self.psi_dot_sign, "frame": self.frame, "dH": self.dH,
                "body_points": self.body_points, "section_residual": self.section_residual, "roots": self.roots}


def _validate_options(iterates, root, direction, branch, formulation, pole_switch, radicand_switch):
    iterates = require_positive_int("iterates", iterates)
    if direction not in DIRECTIONS:
        raise ParameterError("direction", f"must be one of {sorted(DIRECTIONS)}, got {direction!r}")
    if branch not in BRANCHES:
        raise ParameterError("branch", f"must be one of {list(BRANCHES)}, got {branch!r}")
    if formulation not in FORMULATIONS:
        raise ParameterError("formulation", f"must be one of {list(FORMULATIONS)}, got {formulation!r}")
    if not (0 < pole_switch[0] < pole_switch[1] < 1):
        raise ParameterError("pole_switch", f"need 0 < enter < leave < 1, got {pole_switch}")
    if not (0 < radicand_switch[0] < radicand_switch[1]):
        raise ParameterError("radicand_switch", f"need 0 < enter < leave, got {radicand_switch}")
    return iterates


def poincare_map(params: RodParams, h=None, theta0=0.1, ptheta0=0.5, psi0=0.0, *, p_psi0=None, iterates=10_000,
                 root=DEFAULT_ROOT, direction="positive", branch="any", formulation=DEFAULT_FORMULATION, tol=None,
                 t_max=None, pole_switch=(0.05, 0.1), radicand_switch=(1e-3, 2e-3), fp_type=float,
                 progress=None) -> PoincareResult:
    """Iterate the Poincare map of sin(psi) = 0 for the orbit through (theta0, psi0, pbar_theta0, pbar_psi0).

    Either h (then pbar_psi0 solves Hbar = h, all roots reported, `root` picks one: "smallest" (default, see
    the module docstring), "largest" or an index) or p_psi0 directly (then h = Hbar at the start).
    Stops after `iterates` recorded
    crossings or at t_max (default 100 * iterates, about 12x the paper's time per iterate), whichever first;
    success is False (with a message) if t_max or a non-finite state stopped it.  tol defaults to machine
    epsilon of fp_type.  fp_type=np.longdouble is supported for formulation="body" (verification runs).
    progress: optional callable(n_new_points) for progress bars.  The integrators are per-thread and reused;
    the function does not mutate anything visible to the caller."""
    t_start = time.perf_counter()
    if not isinstance(params, RodParams):
        raise TypeError("params must be a RodParams")
    iterates = _validate_options(iterates, root, direction, branch, formulation, pole_switch, radicand_switch)
    pars = params.array()
    if p_psi0 is not None and h is not None:
        raise ParameterError("p_psi0", "give either an energy level h or p_psi0, not both")
    if p_psi0 is not None:
        theta0, ptheta0, psi0, _ = _check_start(theta0, ptheta0, psi0)
        p_psi0 = require_finite("p_psi0", p_psi0)
        lo, hi = _admissible_interval(params)
        if not lo < p_psi0 < hi:
            raise ParameterError("p_psi0", f"the square root sqrt(mu - 2 lam pbar_psi) of Hbar is imaginary or zero "
                                           f"at the start: mu - 2 lam pbar_psi0 = {params.mu - 2 * params.lam * p_psi0:.6g}")
        roots, ridx = np.array([p_psi0]), 0
        h = float(systems.reduced_functions()["H"]([theta0, psi0, ptheta0, p_psi0], pars)[0])
    else:
        if h is None:
            raise ParameterError("h", "give an energy level h (or p_psi0)")
        roots = solve_p_psi(params, h, theta0, ptheta0, psi0)
        h = float(h)
        ridx = choose_root(roots, root)
        p_psi0 = float(roots[ridx])
    if fp_type is not float and formulation != "body":
        raise ValueError("extended precision is supported for formulation='body' only")
    t_max = float(100.0 * iterates if t_max is None else require_finite("t_max", t_max))
    eps = float(np.finfo(fp_type).eps)
    tol_eff = float(tol) if tol else eps

    # the tolerance is fixed at construction, so it is part of the integrator cache key
    ta_r, ta_b = _integrators(formulation, direction, tuple(pole_switch), tuple(radicand_switch), fp_type, tol_eff)

    start4 = np.array([theta0, psi0, ptheta0, p_psi0])

    def chart_ok_4d(th, pps, leave):
        i = 1 if leave else 0
        return np.sin(th) > pole_switch[i] and params.mu - 2 * params.lam * pps > radicand_switch[i]

    if formulation == "reduced" and chart_ok_4d(theta0, p_psi0, False):
        mode = FRAME_REDUCED
        _set(ta_r, start4, 0.0, pars)
    else:
        mode = FRAME_BODY
        x0 = systems.euler_to_body(theta0, psi0, ptheta0, p_psi0, pars)
        _set(ta_b, [fp_type(v) for v in x0] if fp_type is not float else x0, 0.0, pars)

    cap = min(iterates, 4096)  # grown by doubling: iterates may be huge when t_max is the real limit
    raw = np.full((cap, 9), np.nan)
    times = np.zeros(cap)
    frame = np.zeros(cap, dtype=np.int8)
    n = switches = 0
    success, message = True, "ok"
    t_limit = hy.taylor_outcome.time_limit
    t_stop = t_max if fp_type is float else fp_type(t_max)
    last_report = 0
    while n < iterates:
        ta = ta_r if mode == FRAME_REDUCED else ta_b
        oc = ta.propagate_until(t_stop)[0]
        if oc == t_limit:
            success, message = False, (f"t_max = {t_max:g} reached after {n} of {iterates} iterates (max-time guard; "
                                       f"raise t_max or check that the orbit crosses sin(psi) = 0)")
            break
        code = int(oc)
        if code >= 0 or not np.all(np.isfinite(ta.state)):
            success, message = False, f"integration failed at t = {float(ta.time):g} ({oc}) after {n} iterates"
            break
        ev = -code - 1
        if ev == 0:  # section crossing; branch filter applied here (the event direction filtered already)
            st = np.array(ta.state, dtype=float)
            if mode == FRAME_REDUCED:
                c = np.cos(st[1])
                ta.state[1] = _wrap(st[1])  # keep psi bounded (see module docstring)
            else:
                c = None
            keep = branch == "any" or c is None or (c > 0) == (branch == "0")
            if c is None and branch != "any":
                c = np.cos(systems.body_to_euler(np.ascontiguousarray(st), pars)[1])
                keep = (c > 0) == (branch == "0")
            if keep:
                if n == raw.shape[0]:
                    cap = min(iterates, 2 * cap)
                    raw = np.vstack([raw, np.full((cap - n, 9), np.nan)])
                    times = np.concatenate([times, np.zeros(cap - n)])
                    frame = np.concatenate([frame, np.zeros(cap - n, dtype=np.int8)])
                raw[n, : st.size] = st
                times[n] = float(ta.time)
                frame[n] = mode
                n += 1
                if progress is not None and n - last_report >= 200:
                    progress(n - last_report)
                    last_report = n
        elif mode == FRAME_REDUCED:  # entering the neighbourhood of a chart singularity
            st = np.array(ta.state, dtype=float)
            xb = systems.euler_to_body(st[0], st[1], st[2], st[3], pars)
            _set(ta_b, xb, ta.time, pars)
            mode = FRAME_BODY
            switches += 1
        else:  # leaving it: back to the 4-D chart only if both chart conditions hold with margin
            e = systems.body_to_euler(np.ascontiguousarray(np.array(ta.state, dtype=float)), pars)
            if chart_ok_4d(e[0], e[4], True) or (np.sin(e[0]) >= pole_switch[1] * (1 - 1e-9)
                                                  and params.mu - 2 * params.lam * e[4]
                                                  >= radicand_switch[1] * (1 - 1e-9)):
                _set(ta_r, [e[0], e[1], e[3], e[4]], ta.time, pars)
                mode = FRAME_REDUCED
                switches += 1
    if progress is not None and n > last_report:
        progress(n - last_report)
    final_time = float((ta_r if mode == FRAME_REDUCED else ta_b).time)
    res = _assemble(params, pars, h, theta0, ptheta0, psi0, p_psi0, roots, ridx, formulation, direction, branch,
                    tol_eff, iterates, t_max, raw[:n], times[:n], frame[:n], final_time, switches, success,
                    message, fp_type)
    res.wall_s = time.perf_counter() - t_start
    return res


def _assemble(params, pars, h, theta0, ptheta0, psi0, p_psi0, roots, ridx, formulation, direction, branch, tol,
              iterates, t_max, raw, times, frame, final_time, switches, success, message, fp_type):
    F = systems.reduced_functions()
    B = systems.body_functions()
    n = raw.shape[0]
    points = np.zeros((n, 4))
    dH = np.zeros(n)
    body_points = np.full((n, 9), np.nan)
    casimir = None
    r = frame == FRAME_REDUCED
    # value of the section's event function in the frame that landed the point (how well it is on the section)
    section_residual = np.where(r, np.sin(raw[:, 1]), raw[:, 6] * raw[:, 4] - raw[:, 7] * raw[:, 3])
    if r.any():
        x = np.ascontiguousarray(raw[r, :4].T)
        points[r] = x.T
        dH[r] = F["H"](x, pars)[0] - h
    b = ~r
    if b.any():
        x = np.ascontiguousarray(raw[b].T)
        body_points[b] = raw[b]
        e = B["to_euler"](x, pars)
        points[b] = e[[0, 1, 3, 4]].T
        dH[b] = B["H"](x, pars)[0] - h
        cv = np.asarray(B["casimir_values"](np.zeros(0), pars))
        casimir = float(np.max(np.abs(B["casimirs"](x, pars) - cv[:, None])))
    points[:, 1] = _wrap(points[:, 1])
    branch_flag = np.where(np.cos(points[:, 1]) > 0, 1, -1).astype(np.int8)
    psi_dot = F["rhs"](np.ascontiguousarray(points.T), pars)[1] if n else np.zeros(0)
    return PoincareResult(
        success=success, message=message, params=params, h=float(h), theta0=float(theta0), ptheta0=float(ptheta0),
        psi0=float(psi0), p_psi0=float(p_psi0), roots=np.asarray(roots, dtype=float), root_index=int(ridx),
        formulation=formulation, direction=direction, branch_filter=branch, tol=float(tol), iterates=iterates,
        t_max=t_max, points=points, times=times, branch=branch_flag, psi_dot_sign=np.sign(psi_dot).astype(np.int8),
        frame=frame, dH=dH, body_points=body_points, section_residual=section_residual, max_abs_dH=float(np.max(np.abs(dH))) if n else 0.0,
        casimir_drift=casimir, final_time=final_time, n_frame_switches=int(switches), wall_s=0.0,
        fp_type=np.dtype(fp_type).name)


# ----------------------------------------------------------------------------------------------------------
# panels, files and figures
# ----------------------------------------------------------------------------------------------------------
def panel_kwargs(key: str) -> dict:
    """poincare_map keyword arguments of a paper panel '4a'..'4d', '5a'..'5d'."""
    key = str(key).lower()
    if key not in PANELS:
        raise ParameterError("figure", f"unknown panel {key!r}; choose one of {', '.join(PANELS)}")
    P = PANELS[key]
    return dict(params=P["params"], h=P["h"], theta0=P["theta0"], ptheta0=P["ptheta0"], psi0=P["psi0"])


def panel_title(key: str | None, res: PoincareResult) -> str:
    p = res.params
    pars = (f"m={p.m:g}, $\\mu$={p.mu:g}, $\\gamma$={p.gamma:g}, $\\delta$={p.delta:g}, $\\bar\\lambda$={p.lam:g}, "
            f"h={res.h:g}")
    head = f"Fig. {key[0]}({key[1]})  " if key else ""
    return f"{head}{pars}\n{res.n_points} iterates, max|$\\bar H$-h| = {res.max_abs_dH:.1e}"


def plot_points(ax, res: PoincareResult, title=None):
    """theta on the horizontal axis, pbar_theta on the vertical one: the two coordinates of the section
    sin(psi) = 0 that are free at fixed h (pbar_psi follows from Hbar = h, psi is 0 or pi).  The paper's
    panels are not labelled in the source; theta-pbar_theta is the natural choice for this section."""
    ax.plot(res.points[:, 0], res.points[:, 2], ",", color="k", rasterized=True)
    ax.set_xlim(0.0, np.pi)
    ax.set_xlabel(r"$\theta$")
    ax.set_ylabel(r"$\bar p_\theta$")
    if title:
        ax.set_title(title, fontsize=8)


def save_result(res: PoincareResult, out_dir, stem: str, *, key: str | None = None, label: str | None = None,
                formats=("png",)) -> dict:
    """Write <stem>.npz (arrays), <stem>.json (metadata, versions) and <stem>.png atomically; returns the paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .io import atomic_savefig, atomic_savez, atomic_write_json, ensure_writable_dir, versions

    out = ensure_writable_dir(out_dir)
    paths = {"npz": str(atomic_savez(out / f"{stem}.npz", **res.arrays()))}
    meta = {"panel": key, "label": label, **res.summary(), "versions": versions(),
            "axes": "theta (horizontal) vs pbar_theta (vertical)",
            "section": "sin(psi) = 0, direction = sign of d/dt sin(psi) at the crossing"}
    for fmt in formats:
        fig, ax = plt.subplots(figsize=(5.0, 4.2), dpi=150)
        plot_points(ax, res, panel_title(key, res))
        fig.tight_layout()
        paths[fmt] = str(atomic_savefig(fig, out / f"{stem}.{fmt}"))
        plt.close(fig)
    meta["files"] = dict(paths)
    paths["json"] = str(atomic_write_json(out / f"{stem}.json", meta))
    return paths


def run_panels(keys, *, iterates=10_000, workers=2, progress=True, **kw) -> dict:
    """Run several paper panels concurrently (threads: heyoka's propagate releases the GIL; each thread owns
    its integrators).  Returns {key: PoincareResult}.  progress: show one tqdm bar (stderr) over all iterates."""
    keys = [str(k).lower() for k in keys]
    for k in keys:
        panel_kwargs(k)
    iterates = require_positive_int("iterates", iterates)
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=iterates * len(keys), desc="poincare", unit="it", leave=False, smoothing=0.05)
    lock = threading.Lock()

    def tick(k):
        if bar is not None:
            with lock:
                bar.update(k)

    def one(k):
        return k, poincare_map(**panel_kwargs(k), iterates=iterates, progress=tick, **kw)

    try:
        with ThreadPoolExecutor(max_workers=max(1, int(workers))) as ex:
            return dict(ex.map(one, keys))
    finally:
        if bar is not None:
            bar.close()


def _figure(fig_no: str, out_dir, quick=False, iterates=None, workers=2, progress=True,
            formulation=DEFAULT_FORMULATION,
            **kw) -> list[str]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .io import atomic_savefig, ensure_writable_dir

    out = ensure_writable_dir(out_dir)
    n = iterates or (500 if quick else 10_000)
    keys = [f"{fig_no}{c}" for c in "abcd"]
    results = run_panels(keys, iterates=n, workers=workers, progress=progress, formulation=formulation, **kw)
    written = []
    for k in keys:
        written += list(save_result(results[k], out, f"fig{k}", key=k, label=PANELS[k]["label"]).values())
    fig, axes = plt.subplots(2, 2, figsize=(10, 8.4), dpi=150)
    for ax, k in zip(axes.flat, keys):
        var, val = PANELS[k]["vary"]
        sym = {"lam": r"$\bar\lambda$", "gamma": r"$\gamma$"}[var]
        plot_points(ax, results[k], f"({k[1]}) {sym} = {val:g}   [max|$\\bar H$-h| = {results[k].max_abs_dH:.1e}]")
    p = results[keys[0]].params
    common = (f"m={p.m:g}, $\\mu$={p.mu:g}, $\\gamma$={p.gamma:g}, $\\delta$={p.delta:g}" if fig_no == "4"
              else f"m={p.m:g}, $\\delta$={p.delta:g}, $\\bar\\lambda$={p.lam:g}, $\\mu$={p.mu:g}")
    fig.suptitle(f"Fig. {fig_no}: Poincare sections sin$\\psi$ = 0 at h = {results[keys[0]].h:g} ({common}), "
                 f"{n} iterates each", fontsize=10)
    fig.tight_layout()
    written.append(str(atomic_savefig(fig, out / f"fig{fig_no}.png")))
    plt.close(fig)
    return written


def figure_4(out_dir, quick=False, **kw) -> list[str]:
    """fig:poincare1: four panels (lam = 0.135, 0.1575, 0.175, 0.186), per-panel .png/.npz/.json and fig4.png.
    quick=True uses 500 iterates per panel instead of the paper's 10 000."""
    return _figure("4", out_dir, quick, **kw)


def figure_5(out_dir, quick=False, **kw) -> list[str]:
    """fig:poincare2: four panels (gamma = 0.15, 0.205, 0.208, 0.24), per-panel files and fig5.png."""
    return _figure("5", out_dir, quick, **kw)
