"""Poincare sections sin(psi) = 0 of the reduced system (paper sec. 8, fig:poincare1, fig:poincare2).

Public API
----------
solve_p_psi(params, h, theta0, ptheta0, psi0=0)  -> every real root pbar_psi of Hbar(theta0, psi0, ptheta0, .) = h
poincare_section(params, h, theta0, ptheta0, psi0=0, *, iterates=10_000, root="smallest", direction="positive",
             branch="any", formulation="body", ...) -> PoincareResult
poincare_sections([panels...] | params, h, starts=(N, 2..4) array, ...) -> [PoincareResult] (many orbits: SIMD
             lanes of heyoka's batch integrator, magrod/chaos/batch.py)
section_start(params, h, theta0, ptheta0, psi0, *, p_psi0, root) -> SectionStart (the one resolver of a start)
SectionOptions(iterates, t_max, direction, branch, formulation, precision, tol, ...) (validated on construction)
section_points(start, options, *, cancel=None) -> SectionPoints: the one section loop as a stream of SectionChunk;
             .result is the PoincareResult (poincare_section drains it; the explorer draws it as it comes).  The
             lanes of batch.py hand their crossings to the same _Orbit (branch filter, buffer, messages, assembly)
run_panels(keys, ...)                   -> {panel: PoincareResult} for paper panels (magrod.paper.printed.PANELS), threads
orbit_stretch(res, dt=0.05)             -> the axial stretch v3 along the orbit (min, fraction <= 0; two forms)
(figures: magrod/figures/poincare.py; files: PoincareResult.arrays()/summary())

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
the 8 paper panels (80 000 iterates) take ~8-12 s wall on 2 cores with a warm JIT cache (benchmarks/).  The first
process compiles each integrator (~1 s), later processes load it from heyoka's on-disk cache.  Many starts run in
the SIMD lanes of heyoka's batch integrator (magrod/chaos/batch.py): the 8 panels 2.7-3.0x faster than with
`run_panels` in the same run (benchmarks/README.md).
"""
from __future__ import annotations

import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace

import heyoka as hy
import numpy as np
from scipy.optimize import brentq

from ..core import systems
from ..core.errors import ParameterError, require_finite, require_positive_int
from ..generated import scalars
from ..core.params import RodParams
from ..core.precision import Precision
from ..core.limits import LIMITS
from ..paper.printed import Panel, panel, with_overrides
from ..core.results import Result
from ..core.deprecation import renamed_keywords
from ..core.system import as_system
from ..core.tolerances import CASIMIR_TOL, ENERGY_TOL, MODEL_LEVEL_TOL, ROOT_XTOL, START_LEVEL_TOL

DIRECTIONS = systems.DIRECTIONS
BRANCHES = ("any", "0", "pi")
FORMULATIONS = ("reduced", "body")
FRAME_REDUCED, FRAME_BODY = 0, 1
# The body frame is the default: singularity-free, ~3x faster than the 4-D chart (polynomial vector field) and
# Hbar conserved to ~1e-13 on every paper panel; "reduced" (the paper's 4-D system, body-frame patches near the
# chart singularities) agrees with it to ~1e-11 over the first 50 crossings and conserves Hbar to < 1e-12.
DEFAULT_FORMULATION = "body"
DEFAULT_ROOT = "smallest"  # see the module docstring for the evidence
# A result checks itself against ENERGY_TOL and CASIMIR_TOL (magrod.core.tolerances: why these values)

# ----------------------------------------------------------------------------------------------------------
# initial data
# ----------------------------------------------------------------------------------------------------------
def admissible_interval(params: RodParams) -> tuple:
    """Open interval (lo, hi) of pbar_psi where the radicand mu - 2 lam pbar_psi of Hbar is > 0
    (eq:alignment_condition); ParameterError("mu") if it is empty (lam = 0 and mu <= 0)."""
    p = params.to_dict()
    slope = scalars.radicand_slope_ppsi(**p)
    if slope < 0:
        return -np.inf, scalars.radicand_root_ppsi(**p)
    if slope > 0:
        return scalars.radicand_root_ppsi(**p), np.inf
    if params.mu <= 0:
        raise ParameterError("mu", f"with lam = 0 the square root sqrt(mu - 2 lam pbar_psi) = sqrt(mu) of Hbar is "
                                   f"imaginary or zero for every pbar_psi (mu = {params.mu}); need mu > 0")
    return -np.inf, np.inf


_admissible_interval = admissible_interval  # the name its callers inside the package use


def _radicand(params: RodParams, ppsi) -> float:
    """mu - 2 lam pbar_psi (generated reduced.radicand, evaluated through the compiled function)."""
    return float(systems.reduced_functions()["radicand"]([0.0, 0.0, 0.0, ppsi], params.array())[0])


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
    cf = systems.reduced_functions()["H"]._cf
    p = np.ascontiguousarray(params.array()[: cf.nparams])
    lo, hi = _admissible_interval(params)
    fixed = (theta0, psi0, ptheta0)  # the chart state (theta, psi, pbar_theta, pbar_psi) with pbar_psi = q

    def f(q):
        # the compiled Hbar on columns (theta0, psi0, pbar_theta0, q) with the parameters in every column:
        # the same inputs as CFunc.__call__ builds with vstack/repeat, filled in place (3x cheaper)
        q = np.atleast_1d(np.asarray(q, dtype=float))
        x = np.empty((len(fixed) + 1, q.size))
        for i, v in enumerate(fixed):
            x[i] = v
        x[len(fixed)] = q
        P = np.empty((p.size, q.size))
        P[:] = p[:, None]
        return cf(x, pars=P)[0] - h

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
        r = brentq(lambda s: f(s)[0], q[i], q[i + 1], xtol=ROOT_XTOL, rtol=4 * np.finfo(float).eps, maxiter=200)
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
@systems.per_thread
def _integrators(formulation, direction, pole_switch, radicand_switch, precision, tol):
    """(reduced, body) integrators with their events; the reduced one is None for formulation="body".
    Event 0 is the section in both; the others switch between the frames near the chart singularities
    (entering: sin(theta) < pole_switch[0] or radicand < radicand_switch[0]; leaving: both above [1])."""
    body_events = [("section", direction)]
    if formulation == "reduced":
        body_events += [("sin2_theta", "positive", pole_switch[1] ** 2), ("radicand", "positive", radicand_switch[1])]
    ta_b = systems.integrator("body", events=body_events, precision=precision, tol=tol)
    ta_r = None
    if formulation == "reduced":
        ta_r = systems.integrator("reduced", tol=tol, precision=precision,
                                  events=[("section", direction), ("sin_theta", "negative", pole_switch[0]),
                                          ("radicand", "negative", radicand_switch[0])])
    return ta_r, ta_b


_set = systems.reset
_CHART_PSI = systems.chart_index("psi")
_SECTION = systems.names.BODY_EVENTS.index("section")
_PSI = systems.state_index("reduced", "psi")
_CHART4 = [systems.chart_index(k) for k in systems.STATE["reduced"]]  # chart coordinates of the 4-D state
NBODY = systems.dim("body")


def _wrap(a):
    return a - 2 * np.pi * np.round(a / (2 * np.pi))


# ----------------------------------------------------------------------------------------------------------
# the map
# ----------------------------------------------------------------------------------------------------------
@dataclass(repr=False)
class PoincareResult(Result):
    """One orbit's section points (what `poincare_section` returns).  Arrays have length N = number of recorded iterates (N = iterates on success).

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
    roots: np.ndarray  # every real root pbar_psi of Hbar = h at the start, increasing
    root_index: int  # which root is the start's pbar_psi0 (p_psi0 = roots[root_index])
    formulation: str
    direction: str
    branch_filter: str  # the branch option: which crossings are recorded ("any", "0", "pi")
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
    max_abs_dH: float  # max |Hbar - h| over the recorded points (the conservation check)
    casimir_drift: float | None  # max drift of the Casimirs along the body-frame run (None: no body-frame points)
    final_time: float  # the arclength where the run stopped
    n_frame_switches: int  # switches between the 4-D chart and the body frame (formulation "reduced")
    wall_s: float
    precision: Precision = Precision.DOUBLE  # the arithmetic of the integration (one Precision, all the way down)
    extra: dict = field(default_factory=dict)  # a model's run: its start x0 and the energy scale of dH
    stretch: dict | None = None  # the axial stretch sampled along the run (stretch_dt); summary only, not arrays()
    retried_without_jit_cache: bool = False  # verify=True repeated the run with freshly compiled code
    panel: str | None = None
    system: object = None  # the System studied (core.system.System)

    _repr_fields = ("panel", "n_points", "h", "p_psi0", "final_time", "max_abs_dH", "casimir_drift", "wall_s")

    @property
    def fp_type(self) -> str:
        """Deprecated (goes away in the next release): the numpy name of the precision's number type
        ("float64", "longdouble"); use `precision`."""
        import warnings

        warnings.warn("PoincareResult.fp_type is deprecated: use PoincareResult.precision (a magrod.Precision)",
                      DeprecationWarning, stacklevel=2)
        return self._fp_name

    @property
    def _fp_name(self) -> str:
        return np.dtype(self.precision.fp_type).name

    @property
    def accuracy(self) -> dict:
        """max |Hbar - h| and the Casimir drift against ENERGY_TOL and CASIMIR_TOL (`accuracy_checks()`)."""
        return self.accuracy_checks()

    def to_dict(self) -> dict:
        """The summary plus the per-point arrays: small ones as lists, the others as references into arrays()
        ({"npz": key, "shape", "dtype"}; `save()` or magrod poincare --out writes them to .npz)."""
        from ..core.results import array_refs, jsonable

        d = {**jsonable(self.summary()), "arrays": array_refs(self.arrays())}
        if self.system is not None:
            d["system"] = self.system.to_dict()
        return d

    def to_xarray(self):
        """The section points as an xarray.Dataset over the iterate index (attributes: the summary)."""
        import json

        import xarray as xr

        from ..core.results import jsonable

        coords = {"iterate": np.arange(self.n_points)}
        cf = {"theta": ("rad", "Euler angle theta at the crossing"), "psi": ("rad", "Euler angle psi (0 or pi)"),
              "ptheta": ("1", "pbar_theta (eq:nondim_1)"), "ppsi": ("1", "pbar_psi (eq:nondim_1)"),
              "t": ("1", "scaled arclength t = s of the crossing (eq:nondim_1)"), "dH": ("1", "Hbar - h"),
              "frame": ("1", "0: crossing computed by the 4-D system, 1: by the 9-D body frame")}
        cols = {"theta": self.points[:, 0], "psi": self.points[:, 1], "ptheta": self.points[:, 2],
                "ppsi": self.points[:, 3], "t": self.times, "dH": self.dH, "frame": self.frame}
        data = {k: ("iterate", v, {"units": cf[k][0], "long_name": cf[k][1]}) for k, v in cols.items()}
        return xr.Dataset(data, coords=coords, attrs={"summary": json.dumps(jsonable(self.summary()))})

    @property
    def n_points(self) -> int:
        """N, the number of recorded section points."""
        return int(self.points.shape[0])

    def accuracy_checks(self, energy_tol=None, casimir_tol=None) -> dict:
        """max |Hbar - h| and the Casimir drift against their tolerances (default ENERGY_TOL, CASIMIR_TOL);
        `passed` is both (and finite)."""
        energy_tol = ENERGY_TOL if energy_tol is None else energy_tol
        casimir_tol = CASIMIR_TOL if casimir_tol is None else casimir_tol
        # a model's level is checked relative to the size of H's terms at the start (at least 1)
        e_scale = self.extra.get("energy_scale", 1.0) if isinstance(self.extra, dict) else 1.0
        e_ok = bool(np.isfinite(self.max_abs_dH) and self.max_abs_dH <= energy_tol * e_scale)
        c = self.casimir_drift
        c_ok = c is None or bool(np.isfinite(c) and c <= casimir_tol)
        return {"energy_tol": energy_tol, "casimir_tol": casimir_tol, "energy_ok": e_ok, "casimir_ok": c_ok,
                "passed": e_ok and c_ok}

    def summary(self) -> dict:
        """JSON-able metadata (everything except the per-point arrays)."""
        model = {} if isinstance(self.params, RodParams) else {"model": self.system.model,
                                                                "state_names": list(systems.model_body(self.system).state)}
        return {"success": self.success, "message": self.message, "panel": self.panel, **model,
                "parameters": self.params.to_dict() if isinstance(self.params, RodParams) else dict(self.params),
                "h": self.h, "theta0": self.theta0, "ptheta0": self.ptheta0, "psi0": self.psi0,
                "p_psi0": self.p_psi0, "roots": [float(r) for r in self.roots], "root_index": self.root_index,
                "formulation": self.formulation, "direction": self.direction, "branch": self.branch_filter,
                "tol": self.tol, "iterates_requested": self.iterates, "n_points": self.n_points,
                "t_max": self.t_max, "final_time": self.final_time, "max_abs_dH": self.max_abs_dH,
                "casimir_drift": self.casimir_drift, "n_frame_switches": self.n_frame_switches,
                "fraction_body_frame_points": float(np.mean(self.frame == FRAME_BODY)) if self.n_points else 0.0,
                "max_abs_section_residual": float(np.max(np.abs(self.section_residual))) if self.n_points else 0.0,
                "wall_s": self.wall_s, "fp_type": self._fp_name, "accuracy": self.accuracy_checks(),
                "retried_without_jit_cache": self.retried_without_jit_cache,
                **({"stretch": self.stretch} if self.stretch is not None else {}), **self.extra}

    def arrays(self) -> dict:
        return {"points": self.points, "times": self.times, "branch": self.branch,
                "psi_dot_sign": self.psi_dot_sign, "frame": self.frame, "dH": self.dH,
                "body_points": self.body_points, "section_residual": self.section_residual, "roots": self.roots}


def resolve_start(params, h=None, theta0=None, ptheta0=None, psi0=None, p_psi0=None) -> tuple:
    """(params, panel key, h, theta0, ptheta0, psi0) from a RodParams and a start, or from a paper panel (a
    Panel or its key) whose start values fill in what is not given.  ParameterError names what is missing."""
    if isinstance(params, (str, Panel)):
        P = panel(params)
        params, key = P.params, P.key
        if p_psi0 is None and h is None:
            h = P.h
        theta0 = P.theta0 if theta0 is None else theta0
        ptheta0 = P.ptheta0 if ptheta0 is None else ptheta0
        psi0 = P.psi0 if psi0 is None else psi0
    else:
        key = None
        if not isinstance(params, RodParams):
            raise ParameterError("params", f"must be a RodParams, a Panel or a panel name, got {type(params).__name__}")
        for name, v in (("theta0", theta0), ("ptheta0", ptheta0)):
            if v is None:
                raise ParameterError(name, "missing: give the start (theta0, ptheta0) or a paper panel")
    return params, key, h, theta0, ptheta0, 0.0 if psi0 is None else psi0


# ----------------------------------------------------------------------------------------------------------
# a start and the options of a run: the values the one section loop consumes
# ----------------------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class SectionStart:
    """A launch point on the section sin(psi) = 0, validated: the rod, the level Hbar = h, the chart start
    (theta0, pbar_theta0, psi0) and every real root pbar_psi of Hbar(theta0, psi0, pbar_theta0, .) = h with the
    one chosen (`p_psi0 = roots[root_index]`).  Built by `section_start`; consumed by the scalar path, the SIMD
    lanes (magrod/chaos/batch.py) and the explorer's stream (`section_points`).  `panel` labels the result.

    Parameters
    ----------
    params : RodParams
        The paper's rod's non-dimensional parameters.
    h : float
        The energy level Hbar = h of the orbit.
    theta0, ptheta0, psi0 : float
        The start on the chart: theta0 in (0, pi), pbar_theta0, psi0 (0 or pi on the section).
    roots : ndarray of shape (k,)
        Every real root pbar_psi of Hbar(theta0, psi0, pbar_theta0, pbar_psi) = h, increasing.
    root_index : int
        Which root is the start's pbar_psi0 (the paper's rule: the smallest, index 0).
    panel : str, optional
        The paper's panel key the start is, if any ("4a", or "4a, lam=0.15" with a parameter changed).

    Examples
    --------
    >>> import magrod as mr
    >>> s = mr.section_start("4a", root="largest")
    >>> s.root_index, bool(s.p_psi0 == s.roots[-1])
    (1, True)
    """

    params: RodParams
    h: float
    theta0: float
    ptheta0: float
    psi0: float
    roots: np.ndarray
    root_index: int
    panel: str | None = None

    @property
    def p_psi0(self) -> float:
        """pbar_psi0: the chosen root."""
        return float(self.roots[self.root_index])

    def body_state(self, fp_type=float) -> np.ndarray:
        """The start as the 9-D body-frame state (systems.euler_to_body), in fp_type."""
        x0 = systems.euler_to_body(self.theta0, self.psi0, self.ptheta0, self.p_psi0, self.params.array())
        return x0 if fp_type is float else [fp_type(v) for v in x0]

    def describe(self) -> str:
        """One sentence: the roots and which one is used (the paper's rule: the smaller, fig:poincare1)."""
        rs = ", ".join(f"{r:.6g}" for r in self.roots)
        which = {0: "smallest"}.get(self.root_index, "largest" if self.root_index == len(self.roots) - 1 else
                                    f"index {self.root_index}")
        return (f"Hbar = {self.h:g} has {len(self.roots)} root(s) pbar_psi = [{rs}] at theta0 = {self.theta0:.4f}, "
                f"pbar_theta0 = {self.ptheta0:.4f}: using the {which}, {self.p_psi0:.10g} (the paper's rule, "
                f"fig:poincare1: the smaller root)")


@dataclass(frozen=True, eq=False)
class StateStart:
    """A launch point of a section of any model in its body frame: the System, the state x0 (dim,) and the level
    g0 = (H, C1, ...) the orbit lies on (`level_starts` builds them: the starts projected onto one level).  The
    paper's rod's chart starts are `SectionStart`s; both feed the one section loop (`_Orbit`)."""

    system: object
    x0: np.ndarray
    level: np.ndarray
    panel: str | None = None

    @property
    def h(self) -> float:
        return float(self.level[0])

    def body_state(self, fp_type=float) -> np.ndarray:
        return self.x0 if fp_type is float else [fp_type(v) for v in self.x0]


LEVEL_TOL = MODEL_LEVEL_TOL  # Gauss-Newton projection of a start onto the level (core/tolerances.py)
PERTURBATION = 0.05  # size of the seeded perturbations of a model's reference state (default starts)


def project_to_level(system, x, g0, max_steps: int = 50) -> np.ndarray:
    """x moved onto the level g(x) = g0 of (H, C1, ...) of the System's model by least-norm Gauss-Newton steps
    with the generated gradients, to |g(x) - g0| <= LEVEL_TOL (relative to the size of the terms of g at x when
    they are large).  ParameterError("x0") if it does not converge (a singular level)."""
    mb = systems.model_body(system)
    pars = system.array()
    n = mb.dim
    x = np.array(x, dtype=float)
    for _ in range(max_steps):
        r = mb.level(x, pars) - g0
        if np.max(np.abs(r) / np.maximum(1.0, _level_scale(system, x))) <= LEVEL_TOL:
            return x
        G = mb.level_gradients(x, pars).reshape(len(g0), n)
        try:
            x = x - G.T @ np.linalg.solve(G @ G.T, r)
        except np.linalg.LinAlgError:
            break
    res = float(np.max(np.abs(mb.level(x, pars) - g0)))
    raise ParameterError("x0", f"could not put a start on the level of H and the Casimirs of {mb.name!r} (residual "
                               f"{res:.2e}); the level may be singular there")


def _level_scale(system, x) -> np.ndarray:
    """The size of the terms of (H, C1, ...) at x (systems.term_scale): what a level residual is relative to."""
    return np.concatenate([systems.term_scale(system, "H", x), systems.term_scale(system, "casimirs", x)])


def level_starts(system, starts=None, *, level_of=None, seed: int = 0, name: str = "starts") -> list:
    """StateStarts of a model's section on one level of H and the Casimirs.

    starts: None (the model's reference state), an int N (N seeded perturbations of size PERTURBATION of the
    reference state, `seed`), or states of shape (dim,) or (N, dim); each is projected onto the level of
    `level_of` (default: the reference state for generated starts, else each start's own level).
    ParameterError naming `name` or level_of on a wrong shape or non-finite values."""
    mb = systems.model_body(system)
    ref = np.array(system.code.names.REFERENCE if level_of is None else level_of, dtype=float)
    if ref.shape != (mb.dim,) or not np.all(np.isfinite(ref)):
        raise ParameterError("level_of", f"must be a finite state of {mb.dim} components {mb.state}")
    pars = system.array()
    if starts is None or (isinstance(starts, (int, np.integer)) and not isinstance(starts, bool)):
        n = 1 if starts is None else int(starts)
        if not 1 <= n <= MAX_ORBITS:
            raise ParameterError(name, f"must be a number of orbits in [1, {MAX_ORBITS}] or states, got {n}")
        g0 = np.asarray(mb.level(ref, pars), dtype=float)
        if starts is None:
            xs = [project_to_level(system, ref, g0)]
        else:
            rng = np.random.default_rng(seed)
            xs = [project_to_level(system, ref + PERTURBATION * rng.standard_normal(mb.dim), g0) for _ in range(n)]
        return [StateStart(system, x, g0) for x in xs]
    try:
        a = np.asarray(starts, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(name, f"must be states of shape (N, {mb.dim}) ({', '.join(mb.state)})") from None
    a = np.atleast_2d(a)
    if a.ndim != 2 or a.shape[1] != mb.dim or not np.all(np.isfinite(a)):
        raise ParameterError(name, f"must be finite states of shape (N, {mb.dim}) ({', '.join(mb.state)}), got "
                                   f"shape {a.shape}")
    _count_check(a.shape[0], name)
    out = []
    for x in a:
        g0 = np.asarray(mb.level(ref if level_of is not None else x, pars), dtype=float)
        out.append(StateStart(system, project_to_level(system, x, g0), g0))
    return out


@renamed_keywords(params="system")
def section_start(system=None, h=None, theta0=None, ptheta0=None, psi0=None, *, p_psi0=None, root=DEFAULT_ROOT,
                  model=None, x0=None, level_of=None, **overrides) -> SectionStart:
    """The validated start of a Poincare section: the one resolver of `poincare_section`, `poincare_sections`
    and the explorer.

    Parameters
    ----------
    system : System, RodParams, Panel or str
        The rod, or a paper panel whose level and start fill in what is not given; any other model (a System, a
        name or a model file): its start `x0` (default its reference state) on the level of `level_of` (default
        its own), a StateStart.
    h : float, optional
        Energy level; pbar_psi0 is solved for (`root` picks one of the real roots).
    theta0, ptheta0, psi0 : float
        Start on the chart; 0 < theta0 < pi, psi0 defaults to 0.
    p_psi0 : float, optional
        pbar_psi0 directly: then h is Hbar at the start, or, if h is given as well, the start must lie on the
        level within START_LEVEL_TOL.
    root : {"smallest", "largest"} or int
        Which root of Hbar = h.
    **overrides : float
        Model parameters replacing those of `params` (``section_start("4a", lam=0.15)``).

    Returns
    -------
    SectionStart

    Raises
    ------
    ParameterError
        Naming the field: theta0 outside (0, pi), "h" (no root, or the start off the level), "p_psi0" (the
        square root of Hbar imaginary at the start), "mu", "root", a missing theta0/ptheta0.

    Examples
    --------
    >>> import magrod as mr
    >>> s = mr.section_start("4a")
    >>> len(s.roots), s.root_index, s.panel
    (2, 0, '4a')

    Notes
    -----
    The roots are those of `solve_p_psi` (a dense scan polished by brentq to the last ulp of Hbar).
    """
    sys_, params = resolve(system, model, overrides)
    if sys_ is not None and (x0 is not None or state_path(sys_, params, theta0, ptheta0, h, p_psi0)):
        return level_starts(sys_, None if x0 is None else [x0], level_of=level_of, name="x0")[0]
    params, key, h, theta0, ptheta0, psi0 = resolve_start(params, h, theta0, ptheta0, psi0, p_psi0)
    theta0, ptheta0, psi0, _ = _check_start(theta0, ptheta0, psi0)
    if p_psi0 is not None:
        p_psi0 = require_finite("p_psi0", p_psi0)
        lo, hi = _admissible_interval(params)
        if not lo < p_psi0 < hi:
            raise ParameterError("p_psi0", f"the square root sqrt(mu - 2 lam pbar_psi) of Hbar is imaginary or zero "
                                           f"at the start: mu - 2 lam pbar_psi0 = {_radicand(params, p_psi0):.6g}")
        h_start = float(systems.reduced_functions()["H"]([theta0, psi0, ptheta0, p_psi0], params.array())[0])
        if h is not None and not abs(h_start - require_finite("h", h)) <= START_LEVEL_TOL:
            raise ParameterError("h", f"the start is off the level: Hbar(start) - h = {h_start - float(h):.3g} "
                                      f"(tolerance {START_LEVEL_TOL:g})")
        roots, ridx, h = np.array([p_psi0]), 0, h_start if h is None else float(h)
    else:
        if h is None:
            raise ParameterError("h", "give an energy level h (or p_psi0)")
        h = require_finite("h", h)
        roots = solve_p_psi(params, h, theta0, ptheta0, psi0)
        ridx = choose_root(roots, root)
    return SectionStart(params=params, h=float(h), theta0=float(theta0), ptheta0=float(ptheta0), psi0=float(psi0),
                        roots=np.asarray(roots, dtype=float), root_index=int(ridx), panel=key)


@dataclass(frozen=True)
class SectionOptions:
    """How a section is integrated and which crossings it records; validated on construction (ParameterError
    naming the option).  t_max None is the max-time guard 100 x iterates; tol None the precision's machine
    epsilon; pole_switch / radicand_switch the (enter, leave) thresholds of the body-frame patches of the
    formulation "reduced"; stretch_dt samples the axial stretch along the run.

    Parameters
    ----------
    iterates : int
        Number of recorded section crossings (at most LIMITS["iterates"]).  Default 10 000.
    t_max : float, optional
        The max-time guard; None: 100 x iterates.
    direction : {"positive", "negative", "any"}
        Sign of d/dt sin(psi) at recorded crossings.  Default "positive".
    branch : {"any", "0", "pi"}
        psi = 0 crossings, psi = pi crossings, or both.  Default "any".
    formulation : {"body", "reduced"}
        The singularity-free 9-D body-frame system (default) or the paper's 4-D chart with body-frame patches.
    precision : Precision or str
        "double" (default) or "long double" (body formulation only).
    tol : float, optional
        Taylor tolerance; None: the precision's machine epsilon.
    pole_switch : (float, float)
        (enter, leave) thresholds in sin(theta) of the reduced formulation's body-frame patch at the poles,
        0 < enter < leave < 1.  Default (0.05, 0.1).
    radicand_switch : (float, float)
        (enter, leave) thresholds of the radicand mu - 2 lam pbar_psi of its second patch, 0 < enter < leave.
        Default (1e-3, 2e-3).
    stretch_dt : float, optional
        Sample the axial stretch v3 every stretch_dt along the run (the result's ``stretch``).

    Raises
    ------
    ParameterError
        Naming the option that is out of range.

    Examples
    --------
    >>> import magrod as mr
    >>> o = mr.SectionOptions(iterates=500, precision="long double")
    >>> o.precision, o.time_limit
    (<Precision.LONG_DOUBLE: 'long double'>, 50000.0)
    """

    iterates: int = 10_000
    t_max: float | None = None
    direction: str = "positive"
    branch: str = "any"
    formulation: str = DEFAULT_FORMULATION
    precision: Precision = Precision.DOUBLE
    tol: float | None = None
    pole_switch: tuple = (0.05, 0.1)
    radicand_switch: tuple = (1e-3, 2e-3)
    stretch_dt: float | None = None

    def __post_init__(self):
        put = object.__setattr__
        from ..core.limits import count

        # the one limit and wording of iterates, whatever the path (core/limits.py)
        put(self, "iterates", count("iterates", self.iterates, maximum=LIMITS["iterates"]))
        if self.direction not in DIRECTIONS:
            raise ParameterError("direction", f"must be one of {sorted(DIRECTIONS)}, got {self.direction!r}")
        if self.branch not in BRANCHES:
            raise ParameterError("branch", f"must be one of {list(BRANCHES)}, got {self.branch!r}")
        if self.formulation not in FORMULATIONS:
            raise ParameterError("formulation", f"must be one of {list(FORMULATIONS)}, got {self.formulation!r}")
        pole, rad = tuple(self.pole_switch), tuple(self.radicand_switch)
        if not (0 < pole[0] < pole[1] < 1):
            raise ParameterError("pole_switch", f"need 0 < enter < leave < 1, got {self.pole_switch}")
        if not (0 < rad[0] < rad[1]):
            raise ParameterError("radicand_switch", f"need 0 < enter < leave, got {self.radicand_switch}")
        put(self, "pole_switch", pole)
        put(self, "radicand_switch", rad)
        precision = Precision.parse(self.precision)
        if precision not in (Precision.DOUBLE, Precision.LONG_DOUBLE):
            raise ParameterError("precision", f"must be 'double' or 'long double' for sections, got "
                                              f"{precision.value!r}")
        if precision is not Precision.DOUBLE and self.formulation != "body":
            raise ParameterError("precision", "extended precision is supported for formulation='body' only")
        put(self, "precision", precision)
        if self.t_max is not None and not require_finite("t_max", self.t_max) > 0:
            raise ParameterError("t_max", f"must be > 0, got {self.t_max}")
        if self.stretch_dt is not None and not require_finite("stretch_dt", self.stretch_dt) > 0:
            raise ParameterError("stretch_dt", f"must be > 0, got {self.stretch_dt}")

    @property
    def time_limit(self) -> float:
        """The max-time guard: t_max, default 100 x iterates."""
        return float(100.0 * self.iterates if self.t_max is None else self.t_max)

    @property
    def taylor_tol(self) -> float:
        """The Taylor tolerance: tol, default the precision's machine epsilon."""
        return float(self.tol) if self.tol else float(np.finfo(self.precision.fp_type).eps)

    @property
    def batchable(self) -> bool:
        """Whether the SIMD lanes of magrod/chaos/batch.py integrate this configuration (body frame, double
        precision, no stretch sampling); otherwise many starts run the scalar path per start."""
        return self.formulation == "body" and self.precision is Precision.DOUBLE and self.stretch_dt is None


def resolve(system, model=None, overrides=None, precision=None) -> tuple:
    """(System, what the paper's chart path takes or None): the one conversion of a public function's first
    argument (core.system.as_system), at its entry.  For the paper's rod the second item is the Panel (its level
    and start fill in what is not given, its key labels the result) or the RodParams, with the keyword overrides
    applied as before; a list of them (many orbits) is returned as the second item with System None.  For any
    other model the second item is None."""
    from ..paper.printed import PANELS
    from ..core.system import System

    overrides = dict(overrides or {})
    if isinstance(system, (list, tuple)):
        return None, with_overrides(system, overrides)
    paperish = system is None or isinstance(system, (RodParams, Panel)) or (
        isinstance(system, str) and system.lower() in PANELS)
    if model is None and paperish:
        legacy = with_overrides("4a" if system is None else system, overrides)
        return as_system(legacy, precision=precision)[0], legacy
    if isinstance(system, dict) and model is None:
        raise ParameterError("system", "a dict of parameter values needs model= (the model they belong to)")
    sys_, pan = as_system(system, model=model, precision=precision, **overrides)
    if not sys_.is_paper:
        return sys_, None
    if pan is None and isinstance(system, System):
        return sys_, sys_.rod
    return sys_, pan if pan is not None else sys_.rod


def state_path(system, params, theta0=None, ptheta0=None, h=None, p_psi0=None, starts=None) -> bool:
    """Whether a call runs from body-frame states (`level_starts`: any model, the paper's rod included) rather than
    from the paper's chart start (theta0, pbar_theta0, h): every model but the paper's; for the paper's rod, when
    `starts` are its body states (N, 9) or a number of orbits, or when a RodParams comes without any chart start."""
    if not system.is_paper:
        return True
    if isinstance(starts, (int, np.integer)) and not isinstance(starts, bool):
        return True
    if starts is not None:
        return np.ndim(starts) in (1, 2) and np.shape(starts)[-1] == NBODY
    return isinstance(params, RodParams) and theta0 is None and ptheta0 is None and h is None and p_psi0 is None


@renamed_keywords(params="system")
def poincare_section(system=None, h=None, theta0=None, ptheta0=None, psi0=None, *, p_psi0=None, iterates=10_000,
                     root=DEFAULT_ROOT, direction="positive", branch="any", formulation=DEFAULT_FORMULATION,
                     precision=None, tol=None, t_max=None, verify=True, pole_switch=(0.05, 0.1),
                     radicand_switch=(1e-3, 2e-3), progress=None, stretch_dt=None, starts=None, workers=None,
                     model=None, level_of=None, seed=0, **overrides):
    """Poincare section sin(psi) = 0 of one orbit of the reduced system (paper sec. 8, fig:poincare1/2), or of
    many orbits at once in the SIMD lanes of heyoka's batch integrator.

    Parameters
    ----------
    system : System, RodParams, Panel, str, or a list of them
        What is studied (magrod.System, or what converts to it): a paper panel ("4a" .. "5d", or
        `magrod.panel("4a")`), whose parameters and start are used unless h, theta0, ptheta0, psi0 are given; a
        RodParams; a registered model name or a model file (its section in its body frame: `starts` are then its
        states, see below); None: the paper's rod at Fig 4(a).  A list (of panels, or of RodParams sharing the start
        given) runs one orbit per entry and returns a list of results (deprecated: `poincare_sections`).
    h : float, optional
        Energy level Hbar = h; pbar_psi0 is solved for (all real roots are reported, `root` picks one).
    theta0, ptheta0, psi0 : float or array of shape (N,)
        Start on the chart; 0 < theta0 < pi, psi0 defaults to 0.  Arrays give N orbits (broadcast together).
    p_psi0 : float, optional
        Give pbar_psi0 directly instead of h (then h = Hbar at the start).
    starts : array of shape (N, 2), (N, 3) or (N, 4), optional
        N starts (theta0, ptheta0[, psi0[, p_psi0]]) sharing params and h; with a p_psi0 column each start must
        lie on the level Hbar = h (within START_LEVEL_TOL) or, without h, defines its own level.  Returns a list.
    workers : int, optional
        Threads for many orbits (default: all cores).
    **overrides : float
        Model parameters replacing those of `params` (m, mu, gamma, delta, lam): ``poincare_section("4a",
        lam=0.15)`` is Fig 4(a)'s start on the rod with lambdabar = 0.15 (its result's panel is "4a, lam=0.15").
    iterates : int
        Number of recorded section crossings (the paper: 10 000; at most LIMITS["iterates"] = 2 000 000, as on
        the command line).
    root : {"smallest", "largest"} or int
        Which root pbar_psi of Hbar = h ("smallest" reproduces the paper's final times, see Notes).
    direction : {"positive", "negative", "any"}
        Sign of d/dt sin(psi) at recorded crossings.
    branch : {"any", "0", "pi"}
        psi = 0 crossings, psi = pi crossings, or both.
    formulation : {"body", "reduced"}
        Integrate the singularity-free 9-D body-frame system (default) or the paper's 4-D chart (with body-frame
        patches near its singularities).
    precision : Precision or str
        "double" (default) or "long double" (body formulation only; verification runs).
    tol : float, optional
        Taylor tolerance (default: the precision's machine epsilon).
    t_max : float, optional
        Max-time guard (default 100 x iterates).
    verify : bool
        Check the result's own accuracy (max ``|Hbar - h|`` <= ENERGY_TOL, Casimir drift <= CASIMIR_TOL); if the check
        fails, repeat the run once with freshly compiled integrators (a damaged JIT-cache entry is the likely
        cause) and, if it still fails, return success=False with the reason.
    progress : callable, optional
        progress(n_new_points), e.g. a tqdm update.
    stretch_dt : float, optional
        Sample the axial stretch v3 every stretch_dt along the same integration (result.stretch).

    model : str or path, optional
        The model when `system` is a dict of its parameter values (the older spelling ``poincare_section(model=
        "anisotropic", B2=3)`` is ``poincare_section(mr.System("anisotropic", B2=3))``).  For any model but the
        paper's rod the section is its own section function crossed upwards (generated body.py, or SECTION of a
        model file), in its body frame: `starts` are its states (dim,) or (N, dim), or an int N (N seeded
        perturbations of its reference state), projected onto the level of H and the Casimirs of `level_of`
        (default: the reference state, or each start's own); points are the states at the crossings.
        formulation="reduced" needs the model's S^1 chart, branch the Euler-angle chart: an error names the model
        and the reason otherwise.
    level_of : array of shape (dim,), optional
        Any model: the state whose level of H and the Casimirs the starts are put on.
    seed : int
        Any model: the seed of the generated starts (starts=N).

    Returns
    -------
    PoincareResult
        (For many starts the list form is deprecated: use `poincare_sections`, which always returns a list.)
        points (N, 4) in (theta, psi, pbar_theta, pbar_psi), times (N,), dH (N,), accuracy, success/message.

    Raises
    ------
    ParameterError
        Naming the argument: no energy root, theta0 outside (0, pi), an imaginary square root at the start, ...;
        for many starts `starts` (or `params`) with the index of the offending start: an empty list, more than
        MAX_ORBITS orbits, a start without an energy root or off the level.

    Examples
    --------
    >>> import magrod as mr
    >>> sec = mr.poincare_section("4a", iterates=200)
    >>> sec.success, sec.points.shape, bool(sec.max_abs_dH < 1e-12)
    (True, (200, 4), True)
    >>> sec = mr.poincare_section("4a", iterates=100, lam=0.15)  # the panel's start on another rod
    >>> sec.panel, sec.params.lam
    ('4a, lam=0.15', 0.15)
    >>> bool(mr.poincare_section("anisotropic", iterates=20).max_abs_dH < 1e-12)   # another rod model
    True

    Many orbits: `poincare_sections` (a list, always).

    Notes
    -----
    Section points are landed by heyoka stopping terminal events, so each lies on sin(psi) = 0 to ~1e-16.
    On the Fig 4 start Hbar = h has two roots; the smaller one gives the final times the paper prints (module
    docstring).  Cost: ~0.2 ms per iterate (body frame, float64, tol = eps, one core); max ``|Hbar - h|`` ~ 1e-13
    over 10 000 iterates.  Integrators are cached per thread and reused; nothing visible to the caller is
    mutated (verify=True may switch off heyoka's disk cache for the process after a failed check).

    Many starts (body formulation, double precision, no stretch sampling) run in the lanes of heyoka's SIMD
    batch integrator (magrod/chaos/batch.py): one section event per lane, a lane refilled with the next start as
    soon as its orbit ends, one batch integrator per core.  Each lane takes the scalar integrator's steps, so a
    batched orbit equals its scalar run (tests/test_batch.py: to round-off over the first crossings, until
    chaotic divergence).  Other configurations run the scalar path per start on `workers` threads.
    """
    system, params = resolve(system, model, overrides, precision)
    if precision is None:
        precision = Precision.DOUBLE if system is None else system.precision
    if system is not None and state_path(system, params, theta0, ptheta0, h, p_psi0, starts):
        if formulation == "reduced":
            from .charts import magnetic_chart_start

            chart = magnetic_chart_start(system, starts)
            if chart is not None:  # the magnetic rod's Euler chart is the paper's at gamma = delta = 0
                return poincare_section(chart[0], **chart[1], iterates=iterates, formulation="reduced", tol=tol,
                                        t_max=t_max, verify=verify)
        options = SectionOptions(iterates=iterates, t_max=t_max, direction=direction, branch=branch,
                                 formulation=formulation, precision=precision, tol=tol, stretch_dt=stretch_dt)
        _check_model_options(system, options)
        many = starts is not None and (np.ndim(starts) == 2 and np.shape(starts)[0] > 1
                                       or isinstance(starts, (int, np.integer)) and int(starts) > 1)
        out = _model_sections(system, starts, options, level_of=level_of, seed=seed, workers=workers,
                              progress=progress, verify=verify)
        if many:
            import warnings

            warnings.warn("poincare_section with many orbits returns a list: call magrod.poincare_sections instead "
                          "(this form of poincare_section goes away in the next release)", DeprecationWarning,
                          stacklevel=2)
            return out
        return out[0]
    if _is_many(params, theta0, ptheta0, psi0, starts):
        import warnings

        # one return type per function: many orbits are poincare_sections' (a list, always)
        warnings.warn("poincare_section with many orbits (a list of systems, arrays of starts or `starts`) returns "
                      "a list: call magrod.poincare_sections instead (this form of poincare_section goes away in "
                      "the next release)", DeprecationWarning, stacklevel=2)
        return _many_sections(params, h, theta0, ptheta0, psi0, starts=starts, p_psi0=p_psi0, iterates=iterates,
                              root=root, direction=direction, branch=branch, formulation=formulation,
                              precision=precision, tol=tol, t_max=t_max, verify=verify, pole_switch=pole_switch,
                              radicand_switch=radicand_switch, progress=progress, stretch_dt=stretch_dt,
                              workers=workers)
    options = SectionOptions(iterates=iterates, t_max=t_max, direction=direction, branch=branch,
                             formulation=formulation, precision=precision, tol=tol, pole_switch=pole_switch,
                             radicand_switch=radicand_switch, stretch_dt=stretch_dt)
    return _verified(section_start(params, h, theta0, ptheta0, psi0, p_psi0=p_psi0, root=root), options, progress,
                     verify)


def _verified(start: SectionStart, options: SectionOptions, progress, verify: bool) -> PoincareResult:
    """The scalar section of one start, gated on its own accuracy (verify): a failed check repeats the run once
    with freshly compiled integrators, and refuses the result if it still fails."""
    res = _iterate(start, options, progress)
    if verify and res.success and not res.accuracy_checks()["passed"]:
        # the integrator did not conserve what it must: do not trust the compiled code from the disk cache
        systems.bypass_disk_cache()
        res = _iterate(start, options)
        res.retried_without_jit_cache = True
        if res.accuracy_checks()["passed"]:
            systems.bypass_disk_cache(clear=True)
            systems._warn("the on-disk JIT cache gave an integrator that failed its accuracy checks; the cache was "
                          "cleared and the run repeated with freshly compiled code")
    if verify and res.success and not res.accuracy_checks()["passed"]:
        _refuse(res)
    return res


@renamed_keywords(systems="system", params="system")
def poincare_sections(system=None, h=None, theta0=None, ptheta0=None, psi0=None, *, p_psi0=None, iterates=10_000,
                      root=DEFAULT_ROOT, direction="positive", branch="any", formulation=DEFAULT_FORMULATION,
                      precision=None, tol=None, t_max=None, verify=True, pole_switch=(0.05, 0.1),
                      radicand_switch=(1e-3, 2e-3), progress=None, stretch_dt=None, starts=None, workers=None,
                      model=None, level_of=None, seed=0, **overrides) -> list:
    """Poincare sections sin(psi) = 0 of many orbits at once (the SIMD lanes of heyoka's batch integrator): always
    a list of PoincareResult, one per orbit, in the order given.

    Parameters
    ----------
    system : System, RodParams, Panel or str, or a list of them
        One rod or panel with many starts (`starts`, or arrays theta0/ptheta0/psi0), or a list of rods/panels
        (one orbit each, each with the start given or its panel's); or any model (a System, a model name or
        file) with `starts` its states (N, dim) or an int N.
    h, theta0, ptheta0, psi0, p_psi0, starts, iterates, root, direction, branch, formulation, precision, tol,
    t_max, verify, pole_switch, radicand_switch, progress, stretch_dt, workers, model, level_of, seed, **overrides
        As in `poincare_section`.

    Returns
    -------
    list of PoincareResult
        One per orbit (a failed orbit has success False and says why; it does not stop the others).

    Raises
    ------
    ParameterError
        Naming the argument, and the entry for a bad start ("entry i: ...").

    Examples
    --------
    >>> import magrod as mr
    >>> secs = mr.poincare_sections(["4a", "4b", "5a"], iterates=100)
    >>> [s.panel for s in secs], all(s.success for s in secs)
    (['4a', '4b', '5a'], True)

    Notes
    -----
    The batch path (body formulation, double precision, no stretch sampling) runs one section event per lane, a
    lane refilled with the next start as its orbit ends, one batch integrator per core; each lane takes the scalar
    integrator's steps (tests/test_batch.py).  Other configurations run the scalar path per start on `workers`
    threads.  Cost: the 8 paper panels x 10 000 iterates take ~2 s on 2 cores (benchmarks/README.md).
    """
    sys_, systems_ = resolve(system, model, overrides, precision)
    if precision is None:
        precision = Precision.DOUBLE if sys_ is None else sys_.precision
    if sys_ is not None and state_path(sys_, systems_, theta0, ptheta0, h, p_psi0, starts):
        options = SectionOptions(iterates=iterates, t_max=t_max, direction=direction, branch=branch,
                                 formulation=formulation, precision=precision, tol=tol, stretch_dt=stretch_dt)
        _check_model_options(sys_, options)
        return _model_sections(sys_, starts, options, level_of=level_of, seed=seed, workers=workers,
                               progress=progress, verify=verify)
    if not _is_many(systems_, theta0, ptheta0, psi0, starts):
        systems_ = [systems_]
    return _many_sections(systems_, h, theta0, ptheta0, psi0, starts=starts, p_psi0=p_psi0, iterates=iterates,
                          root=root, direction=direction, branch=branch, formulation=formulation,
                          precision=precision, tol=tol, t_max=t_max, verify=verify, pole_switch=pole_switch,
                          radicand_switch=radicand_switch, progress=progress, stretch_dt=stretch_dt, workers=workers)


# ----------------------------------------------------------------------------------------------------------
# many starts: SIMD lanes (magrod/chaos/batch.py)
# ----------------------------------------------------------------------------------------------------------
MAX_ORBITS = 1_000_000  # a million orbits of 1000 iterates is ~10 h on 2 cores: the largest request worth taking


def _is_many(params, theta0, ptheta0, psi0, starts) -> bool:
    return (isinstance(params, (list, tuple)) or starts is not None
            or any(v is not None and np.ndim(v) > 0 for v in (theta0, ptheta0, psi0)))


def _count_check(n: int, name: str) -> None:
    if n == 0:
        raise ParameterError(name, "is empty: give at least one start")
    if n > MAX_ORBITS:
        raise ParameterError(name, f"{n} orbits requested; at most {MAX_ORBITS} (MAX_ORBITS) in one call")


def start_table(starts, name="starts") -> np.ndarray:
    """starts as a float array (N, 4) of (theta0, ptheta0, psi0, p_psi0) with NaN where p_psi0 is to be solved
    for; from an (N, 2), (N, 3) or (N, 4) array-like.  ParameterError(name) on a wrong shape, non-finite values
    (NaN only in the p_psi0 column), an empty table or more than MAX_ORBITS rows."""
    try:
        a = np.asarray(starts, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(name, "must be an array of numbers of shape (N, 2), (N, 3) or (N, 4)") from None
    if a.ndim == 1 and a.size in (2, 3, 4):
        a = a[None, :]
    if a.ndim != 2 or a.shape[1] not in (2, 3, 4):
        raise ParameterError(name, f"must have shape (N, 2), (N, 3) or (N, 4) = (theta0, ptheta0[, psi0[, "
                                   f"p_psi0]]), got shape {a.shape}")
    _count_check(a.shape[0], name)
    fin = np.isfinite(a)
    if a.shape[1] == 4:
        fin[:, 3] |= np.isnan(a[:, 3])  # NaN p_psi0: solve for it
    if not np.all(fin):
        i = int(np.nonzero(~np.all(fin, axis=1))[0][0])
        raise ParameterError(name, f"start {i} has a non-finite value: {a[i].tolist()}")
    out = np.full((a.shape[0], 4), np.nan)
    out[:, 2] = 0.0
    out[:, : a.shape[1]] = a
    return out


def _job_specs(params, h, theta0, ptheta0, psi0, starts, p_psi0):
    """[(name for errors, index, params, key, h, theta0, ptheta0, psi0, p_psi0 or None)] of a many-start call."""
    if isinstance(params, (list, tuple)):
        if starts is not None:
            raise ParameterError("starts", "give either a list of panels/params or starts, not both")
        _count_check(len(params), "params")
        specs = []
        for i, item in enumerate(params):
            try:
                pr, key, hh, th, pt, ps = resolve_start(item, h, theta0, ptheta0, psi0, p_psi0)
            except ParameterError as exc:
                raise ParameterError("params", f"entry {i}: {exc.name}: {exc.message}") from None
            specs.append(("params", i, pr, key, hh, th, pt, ps, p_psi0))
        return specs
    if starts is None:  # theta0 / ptheta0 / psi0 arrays, broadcast together
        if theta0 is None or ptheta0 is None:
            pr, key, hh, th, pt, ps = resolve_start(params, h, theta0, ptheta0, psi0, p_psi0)
        else:
            th, pt, ps = theta0, ptheta0, 0.0 if psi0 is None else psi0
        try:
            cols = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (th, pt, ps)))
        except ValueError:
            raise ParameterError("theta0", "theta0, ptheta0 and psi0 must broadcast to one shape (N,)") from None
        table = start_table(np.column_stack([c.ravel() for c in cols]), "theta0")
        name = "theta0"
    else:
        if any(v is not None and np.ndim(v) > 0 for v in (theta0, ptheta0, psi0)):
            raise ParameterError("starts", "give the starts either as `starts` or as theta0/ptheta0 arrays")
        table = start_table(starts)
        name = "starts"
    if p_psi0 is not None:
        raise ParameterError("p_psi0", "with many starts give p_psi0 as the fourth column of `starts`")
    pr, key, hh, *_ = resolve_start(params, h, 0.5, 0.0, 0.0)  # the rod and level (a panel fills in h)
    return [(name, i, pr, key, hh, row[0], row[1], row[2], None if np.isnan(row[3]) else float(row[3]))
            for i, row in enumerate(table)]


def _start_of(spec, root) -> SectionStart:
    """The SectionStart of one spec of a many-start call (section_start), errors naming the entry or start."""
    name, i, params, key, h, theta0, ptheta0, psi0, p_psi0 = spec
    try:
        start = section_start(params, h, theta0, ptheta0, psi0, p_psi0=p_psi0, root=root)
    except ParameterError as exc:
        if exc.name == "root":
            raise
        what = f"entry {i}" if name == "params" else f"start {i}"
        raise ParameterError(name, f"{what} (theta0={float(theta0)!r}, ptheta0={float(ptheta0)!r}, "
                                   f"psi0={float(psi0)!r}): {exc.name}: {exc.message}") from None
    return replace(start, panel=key)


def _run_lanes(starts, options: SectionOptions, workers, progress) -> list:
    """Many starts in the SIMD lanes of magrod/chaos/batch.py: one _Orbit each (the shared crossing handling)."""
    from . import batch

    orbits = [_Orbit(s, options, index=k, progress=progress) for k, s in enumerate(starts)]
    key = systems.model_key(starts[0].system) if starts and isinstance(starts[0], StateStart) else systems.PAPER_KEY
    batch.run(orbits, direction=options.direction, tol=options.taylor_tol, workers=workers, key=key)
    return [o.result for o in orbits]


def _many_sections(params, h, theta0, ptheta0, psi0, *, starts, p_psi0, iterates, root, direction, branch,
                   formulation, precision, tol, t_max, verify, pole_switch, radicand_switch, progress, stretch_dt,
                   workers) -> list:
    options = SectionOptions(iterates=iterates, t_max=t_max, direction=direction, branch=branch,
                             formulation=formulation, precision=precision, tol=tol, pole_switch=pole_switch,
                             radicand_switch=radicand_switch, stretch_dt=stretch_dt)
    if workers is not None:
        workers = require_positive_int("workers", workers)
    starts = [_start_of(s, root) for s in _job_specs(params, h, theta0, ptheta0, psi0, starts, p_psi0)]
    if not options.batchable:
        # no batch kernel for this configuration: the scalar path per start, on `workers` threads
        with ThreadPoolExecutor(max_workers=workers or os.cpu_count() or 1) as ex:
            return list(ex.map(lambda s: _verified(s, options, progress, verify), starts))
    out = _run_lanes(starts, options, workers, progress)
    if verify:
        bad = [k for k, r in enumerate(out) if r.success and not r.accuracy_checks()["passed"]]
        if bad:  # as in the scalar path: do not trust the compiled code from the disk cache, run those again
            systems.bypass_disk_cache()
            again = _run_lanes([starts[k] for k in bad], options, workers, None)
            for k, r in zip(bad, again):
                r.retried_without_jit_cache = True
                out[k] = r
            if all(r.accuracy_checks()["passed"] for r in again):
                systems.bypass_disk_cache(clear=True)
                systems._warn("the on-disk JIT cache gave an integrator that failed its accuracy checks; the cache "
                              "was cleared and the run repeated with freshly compiled code")
        for r in out:
            if r.success and not r.accuracy_checks()["passed"]:
                _refuse(r)
    return out


def _model_sections(system, starts, options: SectionOptions, *, level_of=None, seed=0, workers=None, progress=None,
                    verify=True) -> list:
    """Sections of any model (not the paper's chart): its starts on one level (`level_starts`), then the one
    section loop, in the SIMD lanes for double precision (batch.py) or scalar per start (`SectionPoints`)."""
    if workers is not None:
        workers = require_positive_int("workers", workers)
    todo = level_starts(system, starts, level_of=level_of, seed=seed)
    if options.precision is Precision.DOUBLE:
        out = _run_lanes(todo, options, workers, progress)
    else:
        out = [SectionPoints(s, options, progress=progress).run() for s in todo]
    if verify:
        for r in out:
            if r.success and not r.accuracy_checks()["passed"]:
                _refuse(r)
    return out


def _refuse(res) -> None:
    acc = res.accuracy_checks()
    res.success = False
    res.message = (f"accuracy check failed: max |Hbar - h| = {res.max_abs_dH:.3g} (tol {acc['energy_tol']:g}), "
                   f"Casimir drift {res.casimir_drift if res.casimir_drift is not None else 0:.3g} "
                   f"(tol {acc['casimir_tol']:g})")


# ----------------------------------------------------------------------------------------------------------
# the one section loop: an orbit's crossings recorded (shared by the scalar loop and the SIMD lanes), and the
# scalar loop itself as a stream of chunks (poincare_section drains it, the explorer draws it as it comes)
# ----------------------------------------------------------------------------------------------------------
PROGRESS_EVERY = 200  # section points between two progress(n) calls
START_CROSSING_T = 1e-12  # a model's event this close to t = 0 is its start lying on the section (not recorded)


class _Orbit:
    """One orbit's section points as they are found: the crossing handling every section loop shares (the
    branch filter, the point buffer, the iterate count, the progress reports, the stop messages) and the
    assembly of its PoincareResult.  The scalar loop (`SectionPoints`) and the lanes of magrod/chaos/batch.py
    drive it; `x0`, `pars` and `t_max` are what a lane needs to start the orbit."""

    __slots__ = ("start", "options", "index", "pars", "x0", "t_max", "raw", "times", "frame", "n", "reported",
                 "progress", "t0_wall", "result")

    def __init__(self, start: SectionStart, options: SectionOptions, *, index=None, progress=None):
        self.start, self.options, self.index, self.progress = start, options, index, progress
        model = isinstance(start, StateStart)
        self.pars = start.system.array() if model else start.params.array()
        self.x0 = start.body_state(options.precision.fp_type)
        self.t_max = options.time_limit
        # the point buffer is made by the first record (a million queued lane orbits hold none) and grown by
        # doubling: iterates may be huge when t_max is the real limit
        self.raw = np.full((0, len(self.x0) if model else NBODY), np.nan)
        self.times = np.zeros(0)
        self.frame = np.zeros(0, dtype=np.int8)
        self.n = self.reported = 0
        self.t0_wall = time.perf_counter()
        self.result = None

    def keep(self, state, cos_psi=None) -> bool:
        """The branch filter (the event has filtered the direction already): psi = 0 (cos psi > 0) or psi = pi.
        cos_psi is given by the 4-D chart; body-frame points are mapped to the chart first."""
        branch = self.options.branch
        if branch == "any":
            return True
        if cos_psi is None:
            cos_psi = np.cos(systems.body_to_euler(np.ascontiguousarray(state), self.pars)[_CHART_PSI])
        return bool((cos_psi > 0) == (branch == "0"))

    def record(self, state, t: float, frame: int = FRAME_BODY) -> bool:
        """Record a kept crossing (a 4-D chart state for frame 0, a body state for frame 1); True once the
        requested number of iterates is reached."""
        n = self.n
        if n == 0 and t <= START_CROSSING_T and isinstance(self.start, StateStart):
            # a start landed on the section (a crossing of another run) meets its event at t ~ 1e-17 or not,
            # by the sign of its residual: it is the start, never a crossing, so every start gives the same points
            return False
        if n == self.raw.shape[0]:
            cap = min(self.options.iterates, max(4096, 2 * n))
            self.raw = np.vstack([self.raw, np.full((cap - n, self.raw.shape[1]), np.nan)])
            self.times = np.concatenate([self.times, np.zeros(cap - n)])
            self.frame = np.concatenate([self.frame, np.zeros(cap - n, dtype=np.int8)])
        self.raw[n, : len(state)] = state
        self.times[n] = t
        self.frame[n] = frame
        self.n = n = n + 1
        if self.progress is not None and n - self.reported >= PROGRESS_EVERY:
            self.progress(n - self.reported)
            self.reported = n
        return n >= self.options.iterates

    def time_limit_message(self) -> str:
        what = "its section" if isinstance(self.start, StateStart) else "sin(psi) = 0"
        return (f"t_max = {self.t_max:g} reached after {self.n} of {self.options.iterates} iterates (max-time guard; "
                f"raise t_max or check that the orbit crosses {what})")

    def failure_message(self, t, outcome) -> str:
        return f"integration failed at t = {float(t):g} ({outcome}) after {self.n} iterates"

    def finish(self, final_time, success: bool, message: str, switches: int = 0) -> PoincareResult:
        """The orbit is over: report the last progress and assemble its PoincareResult (self.result)."""
        if self.progress is not None and self.n > self.reported:
            self.progress(self.n - self.reported)
            self.reported = self.n
        n = self.n
        assemble = _assemble_model if isinstance(self.start, StateStart) else _assemble
        res = assemble(self.start, self.options, self.pars, self.raw[:n], self.times[:n], self.frame[:n],
                       float(final_time), switches, success, message)
        res.wall_s = time.perf_counter() - self.t0_wall
        self.result = res
        return res


@dataclass(frozen=True)
class SectionChunk:
    """Section points found since the previous chunk of a `section_points` stream (k of them): `points` (k, 4)
    chart coordinates (theta, psi, pbar_theta, pbar_psi; psi wrapped), `times` (k,), `frame` (k,), `dH` (k,)
    Hbar - h, and `n_total`, the points of the orbit so far.  times and frame are the result's to the bit; points
    and dH come from the same compiled functions as the result's, evaluated on the chunk's columns only, so they
    agree with the result's to rounding (heyoka's cfunc runs SIMD blocks and a scalar remainder)."""

    points: np.ndarray
    times: np.ndarray
    frame: np.ndarray
    dH: np.ndarray
    n_total: int


_IN_USE: set = set()  # ids of the per-thread integrators a running (possibly suspended) stream holds
_IN_USE_LOCK = threading.Lock()


class SectionPoints:
    """The section loop of one orbit as an iterator of `SectionChunk` (`section_points` builds it).  After the
    iteration `result` is the PoincareResult of every point computed, with success/message (a cancelled stream:
    success False, message "cancelled after ...")."""

    def __init__(self, start: SectionStart, options: SectionOptions, *, cancel=None, progress=None, first=None,
                 every=None, verify=False):
        if not isinstance(start, (SectionStart, StateStart)):
            raise ParameterError("start", f"must be a SectionStart (magrod.section_start), got "
                                          f"{type(start).__name__}")
        if isinstance(start, StateStart):
            _check_model_options(start.system, options)
        if not isinstance(options, SectionOptions):
            raise ParameterError("options", f"must be a SectionOptions, got {type(options).__name__}")
        self.start, self.options = start, options
        self._cancel, self._first, self._every, self._verify = cancel, first, every, verify
        self._orbit = _Orbit(start, options, progress=progress)
        self._started = False

    @property
    def result(self) -> PoincareResult | None:
        """The PoincareResult once the stream is exhausted (None before)."""
        return self._orbit.result

    def run(self) -> PoincareResult:
        """Drain the stream; the result."""
        for _ in self:
            pass
        return self.result

    def _chunk(self, lo: int, hi: int) -> SectionChunk:
        o = self._orbit
        if isinstance(self.start, StateStart):
            points = o.raw[lo:hi].copy()
            dH = systems.model_body(self.start.system).level(np.ascontiguousarray(points.T), o.pars)[0] - \
                self.start.h if hi > lo else np.zeros(0)
            return SectionChunk(points, o.times[lo:hi], o.frame[lo:hi], dH, hi)
        points, dH, *_ = _chart_points(o.raw[lo:hi], o.frame[lo:hi], o.pars, self.start.h, casimirs=False)
        return SectionChunk(points, o.times[lo:hi], o.frame[lo:hi], dH, hi)

    def __iter__(self):
        if self._started:
            raise RuntimeError("a section stream runs once; build another with section_points")
        self._started = True
        opts = self.options
        # the tolerance is fixed at construction, so it is part of the integrator cache key
        key = (opts.formulation, opts.direction, opts.pole_switch, opts.radicand_switch, opts.precision,
               opts.taylor_tol)
        if isinstance(self.start, StateStart):  # any model: its body frame, its section event
            key = (systems.model_key(self.start.system), opts.direction, opts.precision, opts.taylor_tol)
            systems.model_body(self.start.system)
            ta_r, ta_b = None, _model_section_integrator(*key)
            builder = _model_section_integrator
        else:
            ta_r, ta_b = _integrators(*key)
            builder = _integrators
        with _IN_USE_LOCK:
            own = id(ta_b) in _IN_USE
            if not own:
                _IN_USE.add(id(ta_b))
        if own:  # another stream is suspended on this thread's integrators (zip of two streams): build a pair
            pair = builder.__wrapped__(*key)
            ta_r, ta_b = pair if builder is _integrators else (None, pair)
        try:
            yield from self._loop(ta_r, ta_b)
        finally:
            if not own:
                with _IN_USE_LOCK:
                    _IN_USE.discard(id(ta_b))

    def _loop(self, ta_r, ta_b):
        start, opts, o = self.start, self.options, self._orbit
        formulation, iterates = opts.formulation, opts.iterates
        pole_switch, radicand_switch = opts.pole_switch, opts.radicand_switch
        fp_type = opts.precision.fp_type
        params, pars = getattr(start, "params", None), o.pars

        def chart_ok_4d(th, pps, leave):
            i = 1 if leave else 0
            return np.sin(th) > pole_switch[i] and _radicand(params, pps) > radicand_switch[i]

        if formulation == "reduced" and chart_ok_4d(start.theta0, start.p_psi0, False):
            mode = FRAME_REDUCED
            _set(ta_r, np.array([start.theta0, start.psi0, start.ptheta0, start.p_psi0]), 0.0, pars)
        else:
            mode = FRAME_BODY
            _set(ta_b, o.x0, 0.0, pars)
        switches = 0
        success, message = True, "ok"
        t_limit = hy.taylor_outcome.time_limit
        t_stop = o.t_max if fp_type is float else fp_type(o.t_max)
        sampler = None if opts.stretch_dt is None else _StretchSampler(float(opts.stretch_dt), pars)
        cancel, first, every = self._cancel, self._first, self._every
        sent, last = 0, time.perf_counter()
        while o.n < iterates:
            if cancel is not None and cancel.is_set():
                success, message = False, f"cancelled after {o.n} of {iterates} iterates"
                break
            ta = ta_r if mode == FRAME_REDUCED else ta_b
            if sampler is None:
                oc = ta.propagate_until(t_stop)[0]
            else:  # the Taylor polynomials of the same steps: the stretch is sampled on the trajectory of the points
                oc = ta.propagate_until(t_stop, callback=sampler.step, write_tc=True)[0]
                sampler.flush(mode)
            if oc == t_limit:
                success, message = False, o.time_limit_message()
                break
            code = int(oc)
            if code >= 0 or not np.all(np.isfinite(ta.state)):
                success, message = False, o.failure_message(ta.time, oc)
                break
            ev = -code - 1
            if ev == 0:  # section crossing; branch filter applied here (the event direction filtered already)
                st = np.array(ta.state, dtype=float)
                c = None
                if mode == FRAME_REDUCED:
                    c = np.cos(st[_PSI])
                    ta.state[_PSI] = _wrap(st[_PSI])  # keep psi bounded (see module docstring)
                if o.keep(st, c):
                    o.record(st, float(ta.time), mode)
                    if first is not None and (o.n == first or time.perf_counter() - last > every):
                        yield self._chunk(sent, o.n)
                        sent, last = o.n, time.perf_counter()
            elif mode == FRAME_REDUCED:  # entering the neighbourhood of a chart singularity
                st = np.array(ta.state, dtype=float)
                xb = systems.euler_to_body(*st, pars)
                _set(ta_b, xb, ta.time, pars)
                mode = FRAME_BODY
                switches += 1
            else:  # leaving it: back to the 4-D chart only if both chart conditions hold with margin
                e = systems.body_to_euler(np.ascontiguousarray(np.array(ta.state, dtype=float)), pars)[_CHART4]
                th, pps = e[0], e[-1]
                if chart_ok_4d(th, pps, True) or (np.sin(th) >= pole_switch[1] * (1 - 1e-9)
                                                  and _radicand(params, pps) >= radicand_switch[1] * (1 - 1e-9)):
                    _set(ta_r, e, ta.time, pars)
                    mode = FRAME_REDUCED
                    switches += 1
        final_time = float((ta_r if mode == FRAME_REDUCED else ta_b).time)
        res = o.finish(final_time, success, message, switches)
        res.panel = start.panel
        if sampler is not None and res.n_points:
            res.stretch = sampler.result(res, np.dtype(fp_type).name)
        if self._verify and res.success and not res.accuracy_checks()["passed"]:
            _refuse(res)
        if o.n > sent:
            yield self._chunk(sent, o.n)


@renamed_keywords(start="system")
def section_points(system, options=None, *, cancel=None, progress=None, first=8, every=0.04,
                   verify=True) -> SectionPoints:
    """The Poincare section of one orbit as a stream: chunks of points as they are computed (the explorer's form
    of `poincare_section`; the same loop, the same integrator, hence the same points to the last bit).

    Parameters
    ----------
    system : SectionStart, StateStart, or what `section_start` takes
        The start (`section_start`'s result), or a system whose start `section_start` resolves.
    options : SectionOptions, optional
        Default SectionOptions() (10 000 iterates, body frame, double precision).
    cancel : threading.Event, optional
        Checked before every step to the next crossing (~0.2 ms apart): once set, the stream ends with
        success False and the message "cancelled after n of N iterates".
    progress : callable, optional
        progress(n_new_points), every 200 points and at the end.
    first, every : int, float
        A chunk is yielded after the first `first` points, then whenever `every` seconds have passed since the
        last one, and at the end (first=None: one chunk at the end).
    verify : bool
        Gate the result on ENERGY_TOL and CASIMIR_TOL (success False with the reason).  A stream is not
        repeated with freshly compiled code, as `poincare_section(verify=True)` is: its points have been handed
        out already.

    Returns
    -------
    SectionPoints
        An iterator of SectionChunk; `.result` is the PoincareResult once it is exhausted.

    Raises
    ------
    ParameterError
        "start" or "options" of the wrong type.

    Examples
    --------
    >>> import magrod as mr
    >>> stream = mr.section_points(mr.section_start("4a"), mr.SectionOptions(iterates=50))
    >>> sum(c.points.shape[0] for c in stream), stream.result.n_points
    (50, 50)

    Notes
    -----
    ChaosTools.jl's `poincare_cross!` drives both `poincaresos` and `orbitdiagram`; here `_Orbit` (the crossing
    handling and the assembly) serves this loop and the SIMD lanes alike, and `poincare_section` drains this
    stream.
    """
    start = system if isinstance(system, (SectionStart, StateStart)) else section_start(system)
    return SectionPoints(start, SectionOptions() if options is None else options, cancel=cancel,
                         progress=progress, first=first, every=every, verify=verify)


def _iterate(start: SectionStart, options: SectionOptions, progress=None) -> PoincareResult:
    """The section iteration itself (no accuracy gate; `poincare_section` is the public face)."""
    return SectionPoints(start, options, progress=progress).run()


def _chart_points(raw, frame, pars, h, casimirs=True):
    """Chart points, Hbar - h, body points, section residuals and the Casimir drift of recorded crossings
    (raw rows: 4-D chart states for frame 0, body states for frame 1)."""
    F = systems.reduced_functions()
    B = systems.body_functions()
    n = raw.shape[0]
    points = np.zeros((n, 4))
    dH = np.zeros(n)
    body_points = np.full((n, NBODY), np.nan)
    casimir = None
    r = frame == FRAME_REDUCED
    # value of the section's event function in the frame that landed the point (how well it is on the section)
    section_residual = np.zeros(n)
    if r.any():
        x = np.ascontiguousarray(raw[r, :4].T)
        section_residual[r] = F["section"](x, pars)[0]
        points[r] = x.T
        dH[r] = F["H"](x, pars)[0] - h
    b = ~r
    if b.any():
        x = np.ascontiguousarray(raw[b].T)
        body_points[b] = raw[b]
        section_residual[b] = B["events"](x, pars)[_SECTION]
        e = B["to_euler"](x, pars)
        points[b] = e[_CHART4].T
        dH[b] = B["H"](x, pars)[0] - h
        if casimirs:
            cv = np.asarray(B["casimir_values"](np.zeros(0), pars))
            casimir = float(np.max(np.abs(B["casimirs"](x, pars) - cv[:, None])))
    points[:, _PSI] = _wrap(points[:, _PSI])
    return points, dH, body_points, section_residual, casimir


def _assemble(start: SectionStart, options: SectionOptions, pars, raw, times, frame, final_time, switches, success,
              message) -> PoincareResult:
    n = raw.shape[0]
    points, dH, body_points, section_residual, casimir = _chart_points(raw, frame, pars, start.h)
    F = systems.reduced_functions()
    branch_flag = np.where(np.cos(points[:, _PSI]) > 0, 1, -1).astype(np.int8)
    psi_dot = F["rhs"](np.ascontiguousarray(points.T), pars)[_PSI] if n else np.zeros(0)
    return PoincareResult(
        success=success, message=message, params=start.params, h=float(start.h), theta0=float(start.theta0),
        ptheta0=float(start.ptheta0), psi0=float(start.psi0), p_psi0=float(start.p_psi0),
        roots=np.asarray(start.roots, dtype=float), root_index=int(start.root_index),
        formulation=options.formulation, direction=options.direction, branch_filter=options.branch,
        tol=options.taylor_tol, iterates=options.iterates, t_max=options.time_limit, points=points, times=times,
        branch=branch_flag, psi_dot_sign=np.sign(psi_dot).astype(np.int8), frame=frame, dH=dH,
        body_points=body_points, section_residual=section_residual,
        max_abs_dH=float(np.max(np.abs(dH))) if n else 0.0, casimir_drift=casimir, final_time=final_time,
        n_frame_switches=int(switches), wall_s=0.0, precision=options.precision, panel=start.panel,
        system=as_system(start.params, precision=options.precision)[0])


def _assemble_model(start: StateStart, options: SectionOptions, pars, raw, times, frame, final_time, switches,
                    success, message) -> PoincareResult:
    """The PoincareResult of a model's orbit: points are the model's states at the crossings (N, dim); dH = H - h;
    casimir_drift = max_k max |C_k - C_k0| / (the size of C_k's terms, systems.term_scale; at least 1): a drift
    relative to what the Casimir is made of, never to its value (which may be 0, or huge)."""
    system = start.system
    mb = systems.model_body(system)
    n = raw.shape[0]
    x = np.ascontiguousarray(raw.T)
    nan = float("nan")
    if n:
        g = mb.level(x, pars)
        dH = g[0] - start.level[0]
        scale = np.maximum(1.0, _level_scale(system, x))
        casimir = float(np.max(np.abs(g[1:] - start.level[1:, None]) / scale[1:])) if mb.n_casimirs else 0.0
        residual = mb.section(x, pars)[0]
        # the sign of d/dt of the section function at the crossing: grad(section) . f
        J = mb.rhs(x, pars)
        G = _section_gradient(system)(x, pars)
        sdot = np.sign(np.sum(G * J, axis=0)).astype(np.int8)
    else:
        dH, casimir, residual, sdot = np.zeros(0), None, np.zeros(0), np.zeros(0, np.int8)
    h_scale = max(1.0, float(systems.term_scale(system, "H", start.x0)[0]))
    extra = {"energy_scale": h_scale, "x0": [float(v) for v in start.x0]}
    return PoincareResult(
        success=success, message=message, params=dict(system.params), h=float(start.h), theta0=nan, ptheta0=nan,
        psi0=nan, p_psi0=nan, roots=np.zeros(0), root_index=-1, formulation="body", direction=options.direction,
        branch_filter=options.branch, tol=options.taylor_tol, iterates=options.iterates, t_max=options.time_limit,
        points=raw.copy(), times=times, branch=np.ones(n, np.int8), psi_dot_sign=sdot, frame=frame, dH=dH,
        body_points=raw.copy(), section_residual=residual, max_abs_dH=float(np.max(np.abs(dH))) if n else 0.0,
        casimir_drift=casimir, final_time=final_time, n_frame_switches=0, wall_s=0.0, precision=options.precision,
        extra=extra, panel=start.panel, system=system)


@systems.cache
def _section_gradient_key(key: str):
    import heyoka as hy

    mb = systems.body_of(key)
    return systems.CFunc([hy.diff(mb.expr("section"), xj) for xj in mb.variables], mb.variables)


def _section_gradient(system):
    systems.model_body(system)
    return _section_gradient_key(systems.model_key(system))


@systems.per_thread
def _model_section_integrator(key, direction, precision, tol):
    """A model's scalar integrator with its section as a stopping terminal event (one per thread and key)."""
    return systems._model_integrator.__wrapped__(key, (("section", direction),), precision, tol)


def _check_model_options(system, options: SectionOptions) -> None:
    """What a model's section can do: its body frame, every crossing of its section (the branch filter and the
    stretch sampling are the paper's chart's)."""
    if options.formulation != "body":
        system.code.require_s1("the reduced (Euler-angle) formulation")
    if options.branch != "any":
        raise ParameterError("branch", f"the branch filter needs the Euler-angle chart (psi = 0 or pi), and the "
                                       f"model {system.model!r} has none: its section is its own section function")
    if options.stretch_dt is not None:
        raise ParameterError("stretch_dt", f"the axial stretch sampler is the paper's rod's v3 = dH/dn3 in its "
                                           f"chart; the model {system.model!r} has none")


# ----------------------------------------------------------------------------------------------------------
# the axial stretch along an orbit (eq:hyperelastic; docs/errata.md)
# ----------------------------------------------------------------------------------------------------------
STRETCH_DT = 0.05  # sampling step in arclength; from 0.05 to 0.01 (panel 4d, 1000 iterates) min v3 moves by 3e-4
# and the fraction with v3 <= 0 by 5e-5
_STRETCH_CHUNK = 8192  # grid points per propagate_grid call (memory stays ~1 MB per chunk)


@systems.per_thread
def _stretch_integrator(precision):
    return systems.integrator("body", precision=precision)


class _TaylorSteps:
    """The dense output of consecutive Taylor steps: step i ends at hi[i] + lo[i] (heyoka's double-length time),
    has signed size lh[i] and Taylor coefficients tc[i] (n x (order + 1), at the step's start).  Called at an
    array of times in `bounds`, returns the states (len(t) x n) by Horner's scheme in h = t - t_start."""

    def __init__(self, hi, lo, lh, tc, bounds):
        self.hi, self.lo, self.lh, self.tc, self.bounds = hi, lo, lh, tc, bounds

    def __call__(self, t):
        t = np.atleast_1d(np.asarray(t, dtype=float))
        # the step of each time: the first whose end is >= t (forward runs: ends increase)
        i = np.minimum(np.searchsorted(self.hi + self.lo, t, side="left"), len(self.hi) - 1)
        # h = t - (hi + lo - lh): t - hi is exact (t and hi within a step of each other), then the small terms
        h = ((t - self.hi[i]) - self.lo[i]) + self.lh[i]
        c = self.tc[i]  # len(t) x n x (order + 1)
        x = c[:, :, -1].copy()
        for k in range(c.shape[2] - 2, -1, -1):
            x *= h[:, None]
            x += c[:, :, k]
        return x


class _StretchSampler:
    """The axial stretch v3 at t = k dt along a section run, from the Taylor polynomials of the integrator's steps
    (the same steps that land the section points).  Body-frame segments: v3 = dH/dn3 of the body Hamiltonian and
    the chart form at the chart coordinates of the sample; 4-D segments: the chart form, and the body form at the
    body image of the sample (systems.euler_to_body).

    Why not heyoka's continuous output (propagate_until(..., c_output=True)): building it costs ~1.2 ms per call, and
    the section loop calls propagate_until once per crossing -- a Fig 4 panel took 16.9 CPU-s, 3.4 now
    (benchmarks/stretch_sampler.py).  Instead `step`
    (propagate_until's step callback, write_tc=True) keeps each step's Taylor coefficients and `flush` evaluates
    them at the sample times after the call, as the continuous output would: Horner's scheme in h = t - t_start,
    with t_start from the integrator's double-length time (ta.dtime), so that h is exact at t ~ 1e5 too.  The
    samples agree with the continuous output's to a few ulps (tests/test_stretch.py)."""

    def __init__(self, dt: float, pars):
        self.dt, self.pars, self.k = dt, pars, 0
        self.acc = {"n": 0, "neg_b": 0, "neg_c": 0, "min_b": np.inf, "t_min_b": 0.0, "min_c": np.inf,
                    "max_diff": 0.0, "max_b": -np.inf}
        self.v3b, self.v3c = systems.body_stretch(), systems.reduced_functions()["stretch"]
        self.B = systems.body_functions()
        self._steps = []

    def step(self, ta) -> bool:
        """propagate_until's step callback: the step's end time (hi, lo), signed size and Taylor coefficients."""
        hi, lo = ta.dtime
        self._steps.append((hi, lo, ta.last_h, np.array(ta.tc, dtype=float)))
        return True

    def flush(self, mode) -> None:
        """The samples t = k dt on the steps recorded since the last flush (they cover [t0, t1] contiguously)."""
        steps, self._steps = self._steps, []
        if not steps:
            return
        hi = np.array([s[0] for s in steps])
        lo = np.array([s[1] for s in steps])
        lh = np.array([s[2] for s in steps])
        ends = hi + lo
        t0, t1 = float(ends[0] - lh[0]), float(ends[-1])
        self.add(_TaylorSteps(hi, lo, lh, np.stack([s[3] for s in steps]), (t0, t1)), mode)

    def add(self, c_out, mode) -> None:
        """The samples on c_out (a dense output: .bounds and a call at an array of times)."""
        t0, t1 = (float(b) for b in c_out.bounds)
        k1 = int(np.floor(t1 / self.dt))
        if k1 < self.k:
            return
        while self.k <= k1:  # in chunks of _STRETCH_CHUNK samples (memory)
            kk = np.arange(self.k, min(k1 + 1, self.k + _STRETCH_CHUNK))
            t = kk * self.dt
            t = np.clip(t, t0, t1)  # t = k dt lies in [t0, t1] up to the rounding of k dt
            X = np.asarray(c_out(t), dtype=float)
            X = X[None, :] if X.ndim == 1 else X
            if mode == FRAME_REDUCED:
                q = np.ascontiguousarray(X.T)
                vc = self.v3c(q, self.pars)[0]
                chart = np.vstack([q[0], q[1], np.zeros(q.shape[1]), q[2], q[3]])
                xb = self.B["to_body"](np.ascontiguousarray(chart), self.pars)
                vb = np.asarray(self.v3b(np.ascontiguousarray(xb), self.pars)[0])
            else:
                xb = np.ascontiguousarray(X.T)
                vb = np.asarray(self.v3b(xb, self.pars)[0])
                e = self.B["to_euler"](xb, self.pars)[_CHART4]
                vc = self.v3c(np.ascontiguousarray(e), self.pars)[0]
            self._accumulate(t, vb, vc)
            self.k = int(kk[-1]) + 1

    def _accumulate(self, t, vb, vc) -> None:
        a = self.acc
        if not (np.all(np.isfinite(vb)) and np.all(np.isfinite(vc))):
            raise RuntimeError(f"axial stretch not finite near t = {float(t[-1]):g}")
        i = int(np.argmin(vb))
        if vb[i] < a["min_b"]:
            a["min_b"], a["t_min_b"] = float(vb[i]), float(t[i])
        a["min_c"] = min(a["min_c"], float(np.min(vc)))
        a["max_b"] = max(a["max_b"], float(np.max(vb)))
        a["max_diff"] = max(a["max_diff"], float(np.max(np.abs(vb - vc))))
        a["neg_b"] += int(np.sum(vb <= 0))
        a["neg_c"] += int(np.sum(vc <= 0))
        a["n"] += t.size

    def result(self, res, fp_name: str) -> dict:
        return _stretch_summary(self.acc, self.dt, res.final_time, fp_name, res, self.pars)


def _stretch_summary(acc, dt, T, fp_name, res, pars) -> dict:
    sec = systems.reduced_functions()["stretch"](np.ascontiguousarray(res.points.T), pars)[0] if res.n_points \
        else np.zeros(0)
    n = max(acc["n"], 1)
    return {"dt": dt, "t_final": T, "n_samples": acc["n"], "fp_type": fp_name,
            "min_body": acc["min_b"], "t_min_body": acc["t_min_b"], "max_body": acc["max_b"],
            "min_chart": acc["min_c"], "max_abs_body_minus_chart": acc["max_diff"],
            "fraction_compressed_body": acc["neg_b"] / n, "fraction_compressed_chart": acc["neg_c"] / n,
            "min_at_section_points": float(np.min(sec)) if sec.size else None,
            "fraction_compressed_at_section_points": float(np.mean(sec <= 0)) if sec.size else None,
            "straight_rod": float(scalars.straight_rod_stretch(*pars)), "sampled": "along the run (dense output)"}


def orbit_stretch(res: PoincareResult, *, dt=STRETCH_DT, precision=Precision.DOUBLE, t_final=None) -> dict:
    """The axial stretch v3 = d3.r' = ds'/ds along the orbit of `res`, from an independent re-integration.

    `poincare_section(..., stretch_dt=dt)` samples v3 along the run itself (its dense output): that is the
    stretch of the trajectory whose points are reported.  This function re-integrates the orbit in the body frame
    from the start of `res` over [0, t_final] (default res.final_time) in `precision` and samples it every dt, as a
    cross-check: the two agree to round-off until a chaotic orbit's two integrations diverge
    (tests/test_stretch.py).  At every sample v3 is evaluated twice: dH/dn3 of the generated body Hamiltonian
    (systems.body_stretch, = 1 + (gamma+delta) m^2 n3) and the closed chart form 1 + (gamma+delta)(cos theta +
    sqrt(mu - 2 lam pbar_psi) sin theta cos psi) (generated reduced.stretch).  v3 <= 0 means the linearly elastic
    rod is compressed through zero length (paper sec. 2: v3 > 0).  Returns a JSON-able dict (min_*, fraction of
    samples with v3 <= 0, ...)."""
    dt = float(require_finite("dt", dt))
    if dt <= 0:
        raise ParameterError("dt", f"must be > 0, got {dt}")
    precision = Precision.parse(precision)
    fp_type = precision.fp_type
    T = float(res.final_time if t_final is None else require_finite("t_final", t_final))
    pars = res.params.array()
    ta = _stretch_integrator(precision)
    x0 = systems.euler_to_body(res.theta0, res.psi0, res.ptheta0, res.p_psi0, pars)
    systems.reset(ta, [fp_type(v) for v in x0] if fp_type is not float else x0, 0.0, pars)
    sampler = _StretchSampler(dt, pars)
    n_total = int(np.floor(T / dt)) + 1
    k = 0
    while k < n_total:
        k1 = min(n_total, k + _STRETCH_CHUNK)
        k0 = max(k - 1, 0)  # heyoka wants the grid to start at the current time: repeat the last point, drop it
        grid = np.arange(k0, k1, dtype=float) * dt
        if fp_type is not float:
            grid = np.array([fp_type(i) * fp_type(dt) for i in range(k0, k1)])
        out = np.asarray(ta.propagate_grid(grid)[-1], dtype=float)[k - k0:]
        grid = np.asarray(grid[k - k0:], dtype=float)
        if out.shape[0] != k1 - k or not np.all(np.isfinite(out)):
            raise RuntimeError(f"orbit_stretch: integration stopped near t = {float(ta.time):g}")
        x = np.ascontiguousarray(out.T)
        vb = np.array(sampler.v3b(x, pars)[0])
        e = sampler.B["to_euler"](x, pars)[_CHART4]
        sampler._accumulate(grid, vb, sampler.v3c(np.ascontiguousarray(e), pars)[0])
        k = k1
    out = _stretch_summary(sampler.acc, dt, T, np.dtype(fp_type).name, res, pars)
    out["sampled"] = "re-integrated (orbit_stretch)"
    return out
