"""Many orbits at once: a section portrait of one energy level, and an orbit diagram (section points
against a parameter).  Numerics only: result objects out; drawing in magrod/figures/portrait.py.

section_portrait(params, h, starts=..., iterates=1000, indicator="growth_exponent") -> SectionPortrait
grid_starts(params, h, theta0=(lo, hi, n), ptheta0=(lo, hi, n), psi0=0) -> (M, 2) starts that reach the level
orbit_diagram(parameter or params_fn, values, base="4a", iterates=500, ...) -> OrbitDiagram

Both run their orbits through `poincare_section` with many starts (SIMD lanes, magrod/chaos/batch.py), so every
orbit carries the accuracy gate of a single section (verify=True).  The portrait colours each orbit by a chaos
indicator of its start (magrod.chaos.indicators.body_indicators: the tangent growth exponent, chaotic iff > 3).
"""
from __future__ import annotations

import math
import os
import re
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

from ..core import systems
from ..core.errors import MAX_MAGNITUDE, ParameterError, require_finite, require_positive_int
from ..core.params import RodParams
from ..paper.printed import Panel, panel
from ..core.results import Result, jsonable
from ..generated.names import PARAMS
from ..core.deprecation import renamed_keywords
from ..core.system import as_system
from .indicators import GROWTH_THRESHOLD, body_indicators, model_indicators
from .section import (MAX_ORBITS, poincare_sections, resolve, resolve_start, solve_p_psi, start_table,
                      state_path)

INDICATORS = ("growth_exponent", "lyap", "fli")
DEFAULT_T_INDICATOR = 1000.0  # cost ~5 us per orbit and unit time; Fig 4(a) needs T ~ 3000 to look chaotic
COORDINATES = {"theta": 0, "psi": 1, "ptheta": 2, "ppsi": 3}


# ----------------------------------------------------------------------------------------------------------
# indicators of many starts, on all cores
# ----------------------------------------------------------------------------------------------------------
def start_indicators(orbits, *, t_max=DEFAULT_T_INDICATOR, workers=None):
    """Indicators (magrod.chaos.indicators.Indicators) of the start of every orbit (PoincareResult), computed in
    SIMD batches of the tangent system, split over `workers` threads."""
    present = [i for i, r in enumerate(orbits) if r is not None]  # None: a value without an energy root
    full = len(orbits)
    orbits = [orbits[i] for i in present]
    if not orbits:
        from .indicators import NO_ROOT

        return {**{key: np.full(full, np.nan) for key in INDICATORS}, "status": np.full(full, NO_ROOT, np.int8)}
    x0 = np.array([systems.euler_to_body(r.theta0, r.psi0, r.ptheta0, r.p_psi0, r.params.array())
                   for r in orbits]).T
    p = np.array([r.params.array() for r in orbits]).T
    b = systems.batch_width()
    n = x0.shape[1]
    k = max(1, min(int(workers or os.cpu_count() or 1), math.ceil(n / b)))
    cuts = [round(i * math.ceil(n / b) / k) * b for i in range(k + 1)]
    parts = [(lo, min(hi, n)) for lo, hi in zip(cuts[:-1], cuts[1:]) if lo < min(hi, n)]

    def one(lh):
        lo, hi = lh
        return body_indicators(x0[:, lo:hi], p[:, lo:hi], t_max=t_max)

    if len(parts) == 1:
        res = [one(parts[0])]
    else:
        with ThreadPoolExecutor(max_workers=len(parts)) as ex:
            res = list(ex.map(one, parts))
    got = {key: np.concatenate([getattr(r, key) for r in res]) for key in (*INDICATORS, "status")}
    if len(present) == full:
        return got
    from .indicators import NO_ROOT

    out = {key: np.full(full, np.nan) for key in INDICATORS}
    out["status"] = np.full(full, NO_ROOT, np.int8)
    for key, v in got.items():
        out[key][present] = v
    return out


# ----------------------------------------------------------------------------------------------------------
# section portraits
# ----------------------------------------------------------------------------------------------------------
@dataclass(repr=False)
class SectionPortrait(Result):
    """Many orbits on one level Hbar = h: `orbits` (one PoincareResult each, in the order of the starts), the
    starts (N, 4) = (theta0, ptheta0, psi0, p_psi0), and per orbit the chaos indicator `values` (N,) of its
    start (NaN without one) with `chaotic` (N,) = values > threshold (growth exponent; None for other
    indicators).  success: every orbit succeeded (each passed its own accuracy gate)."""

    success: bool
    message: str
    params: RodParams
    h: float
    starts: np.ndarray
    orbits: list  # one PoincareResult per start, in the order of the starts
    indicator: str | None
    values: np.ndarray  # (N,) the chaos indicator of each start (NaN without one)
    t_indicator: float | None
    wall_s: float
    panel: str | None = None
    threshold: float = GROWTH_THRESHOLD  # growth exponent above which an orbit counts as chaotic
    system: object = None  # the System studied

    _repr_fields = ("n_orbits", "h", "indicator", "fraction_chaotic", "max_abs_dH", "wall_s")

    @property
    def n_orbits(self) -> int:
        """N, the number of orbits."""
        return len(self.orbits)

    @property
    def chaotic(self):
        """(N,) values > threshold (the growth exponent's verdict); None for another indicator."""
        if self.indicator != "growth_exponent":
            return None
        with np.errstate(invalid="ignore"):
            return np.asarray(self.values > self.threshold)

    @property
    def fraction_chaotic(self):
        """The fraction of the orbits with an indicator value that are chaotic (None without a verdict)."""
        c = self.chaotic
        ok = np.isfinite(self.values)
        return float(c[ok].mean()) if c is not None and ok.any() else None

    @property
    def max_abs_dH(self) -> float:
        """The largest max |Hbar - h| over the orbits."""
        return float(max((r.max_abs_dH for r in self.orbits), default=0.0))

    @property
    def accuracy(self) -> dict:
        """Worst max |Hbar - h| and Casimir drift over the orbits, and whether every orbit passed its gate."""
        cas = [r.casimir_drift for r in self.orbits if r.casimir_drift is not None]
        return {"max_abs_dH": self.max_abs_dH, "max_casimir_drift": max(cas) if cas else None,
                "passed": all(r.accuracy_checks()["passed"] for r in self.orbits)}

    def summary(self) -> dict:
        return jsonable({"success": self.success, "message": self.message, "panel": self.panel,
                         **({} if self.system is None or self.system.is_paper and isinstance(self.params, RodParams)
                            else {"system": self.system.to_dict()}),
                         "parameters": self.params.to_dict() if isinstance(self.params, RodParams) else
                         dict(self.params), "h": self.h, "n_orbits": self.n_orbits,
                         "iterates": [r.n_points for r in self.orbits], "indicator": self.indicator,
                         "t_indicator": self.t_indicator, "threshold": self.threshold,
                         "fraction_chaotic": self.fraction_chaotic, "accuracy": self.accuracy,
                         "wall_s": self.wall_s})

    def arrays(self) -> dict:
        """points (N, K, 4) padded with NaN to the longest orbit, dH (N, K), starts, indicator values."""
        K = max((r.n_points for r in self.orbits), default=0)
        pts = np.full((self.n_orbits, K, self.orbits[0].points.shape[1] if self.orbits else 4), np.nan)
        dH = np.full((self.n_orbits, K), np.nan)
        for i, r in enumerate(self.orbits):
            pts[i, : r.n_points] = r.points
            dH[i, : r.n_points] = r.dH
        return {"points": pts, "dH": dH, "starts": self.starts, "values": self.values}

    def to_dict(self) -> dict:
        """The summary, each orbit's outcome, and the arrays as references into arrays() (small ones inline)."""
        from ..core.results import array_refs

        return {**jsonable({**self.summary(), "orbits": [{"success": r.success, "message": r.message,
                                                           "n_points": r.n_points, "max_abs_dH": r.max_abs_dH}
                                                          for r in self.orbits]}),
                "arrays": array_refs(self.arrays())}


def _axis(name, spec):
    try:
        lo, hi, n = spec
    except (TypeError, ValueError):
        raise ParameterError(name, f"expected (lo, hi, n), got {spec!r}") from None
    lo, hi = require_finite(name, lo, MAX_MAGNITUDE), require_finite(name, hi, MAX_MAGNITUDE)
    n = require_positive_int(name, n)
    if (n > 1 and not lo < hi) or (n == 1 and lo != hi):
        raise ParameterError(name, f"empty range {lo:g}..{hi:g} with {n} point(s)")
    return np.linspace(lo, hi, n)


def grid_starts(params, h=None, *, theta0=(0.1, 3.0, 8), ptheta0=(-1.0, 1.0, 8), psi0=0.0) -> np.ndarray:
    """The points of a (theta0, ptheta0) grid on the section psi = psi0 from which the level Hbar = h is
    reached (a real root pbar_psi exists): an (M, 2) array, row-major in (theta0, ptheta0).  Grid points
    without a root are left out (a rectangle covers more than the accessible region); ParameterError names
    `starts` if none is left.  params may be a panel (then h defaults to its level)."""
    params, _, h, *_ = resolve_start(params, h, 0.5, 0.0, psi0)
    if h is None:
        raise ParameterError("h", "give the energy level h of the portrait")
    th = _axis("theta0", theta0)
    pt = _axis("ptheta0", ptheta0)
    if th.size * pt.size > MAX_ORBITS:
        raise ParameterError("starts", f"{th.size * pt.size} grid points; at most {MAX_ORBITS}")
    out = []
    for a in th:
        for b in pt:
            try:
                solve_p_psi(params, h, a, b, psi0)
            except ParameterError as exc:
                if exc.name == "h":
                    continue
                raise ParameterError("theta0", exc.message) from None
            out.append((a, b))
    if not out:
        raise ParameterError("starts", f"no point of the {th.size} x {pt.size} grid reaches the level h = {h:g}")
    return np.array(out)


@renamed_keywords(params="system")
def section_portrait(system=None, h=None, *, starts, iterates=1000, indicator="growth_exponent",
                     t_indicator=DEFAULT_T_INDICATOR, root="smallest", direction="positive", t_max=None,
                     workers=None, progress=None, model=None, level_of=None, seed=0, **overrides) -> SectionPortrait:
    """Section portrait of one energy level: the Poincare sections sin(psi) = 0 of many orbits, each coloured by a
    chaos indicator of its start.

    Parameters
    ----------
    system : System, RodParams, Panel or str
        What is studied: the paper's rod (a paper panel gives its parameters and, unless h is given, its level),
        or any model (a System, a name or a model file: its own section, from its states).
    h : float, optional
        The level Hbar = h shared by every orbit (the paper's chart).
    starts : array of shape (N, 2), (N, 3) or (N, 4), or states (N, dim), or an int
        The paper's chart: (theta0, ptheta0[, psi0[, p_psi0]]) per orbit; without p_psi0 it is solved for
        (`root`), with it the start must lie on the level (within START_LEVEL_TOL).  `grid_starts` makes a grid of
        accessible starts.  Any model: its states (N, dim), or N seeded perturbations of its reference state, put
        on the level of `level_of` (default the reference state: one level for the portrait).
    iterates : int
        Section points per orbit.
    indicator : {"growth_exponent", "lyap", "fli"} or None
        The colour of an orbit (magrod.chaos.indicators; chaotic iff growth_exponent > 3); None: no indicator.
    t_indicator : float
        Integration time of the indicator.
    root, direction, t_max, workers, progress, model, level_of, seed, **overrides
        As in `poincare_section` (workers: threads, default all cores).

    Returns
    -------
    SectionPortrait
        orbits (list of PoincareResult), starts (N, 4), values (N,), chaotic (N,), accuracy, plot().

    Raises
    ------
    ParameterError
        `starts`: empty, more than MAX_ORBITS, a start without an energy root or off the level (the message names
        the start's index); `indicator`: unknown; `t_indicator`: not > 0.

    Examples
    --------
    >>> import magrod as mr
    >>> pp = mr.section_portrait("4a", starts=[(0.1, 0.5), (0.3, 0.0), (1.0, 0.2)], iterates=50, t_indicator=200)
    >>> pp.success, pp.n_orbits, pp.values.shape
    (True, 3, (3,))

    Notes
    -----
    The orbits run in the SIMD lanes of heyoka's batch integrator (`poincare_section` with many starts: one
    section event per lane, lanes refilled as orbits end, all cores); every orbit passes the accuracy gate of a
    single section.  The indicator integrates the tangent equations from each start over t_indicator (~5 us
    per orbit and unit time in SIMD batches).  Cost: a section point costs about one SIMD batch step per lane
    of the ~57 Taylor steps between crossings; 64 orbits x 1000 iterates on the Fig 4(a) level took 6.2x less
    wall time than 64 scalar sections on a loaded 2-core machine of SIMD width 4 (benchmarks/README.md).
    """
    t0 = time.perf_counter()
    if indicator is not None and indicator not in INDICATORS:
        raise ParameterError("indicator", f"must be one of {', '.join(INDICATORS)} or None, got {indicator!r}")
    if indicator is not None and not require_finite("t_indicator", t_indicator) > 0:
        raise ParameterError("t_indicator", f"must be > 0, got {t_indicator}")
    if isinstance(system, (list, tuple)):
        raise ParameterError("system", "one rod per portrait: give a System, a RodParams or a panel, and the starts")
    sys_, params = resolve(system, model, overrides)
    if state_path(sys_, params, None, None, h, None, starts):
        return _model_portrait(sys_, starts, t0, iterates=iterates, indicator=indicator, t_indicator=t_indicator,
                               direction=direction, t_max=t_max, workers=workers, progress=progress,
                               level_of=level_of, seed=seed)
    params_r, key, h, *_ = resolve_start(params, h, 0.5, 0.0, 0.0)
    if h is None and not (np.ndim(starts) == 2 and np.shape(starts)[1] == 4):
        raise ParameterError("h", "give the energy level h of the portrait (or p_psi0 as a fourth column)")
    table = start_table(starts)
    orbits = poincare_sections(params_r, h, starts=table, iterates=iterates, root=root, direction=direction,
                              t_max=t_max, workers=workers, progress=progress)
    table[:, 3] = [r.p_psi0 for r in orbits]
    values = np.full(len(orbits), np.nan)
    if indicator is not None:
        ind = start_indicators(orbits, t_max=float(t_indicator), workers=workers)
        values = np.where(ind["status"] == 0, ind[indicator], np.nan)
    bad = [i for i, r in enumerate(orbits) if not r.success]
    msg = "ok" if not bad else f"{len(bad)} of {len(orbits)} orbits failed (first: orbit {bad[0]}: " \
                               f"{orbits[bad[0]].message})"
    return SectionPortrait(not bad, msg, params_r, float(orbits[0].h), table, orbits, indicator, values,
                           float(t_indicator) if indicator is not None else None, time.perf_counter() - t0, key,
                           system=sys_)


def _model_portrait(system, starts, t0, *, iterates, indicator, t_indicator, direction, t_max, workers, progress,
                    level_of, seed) -> SectionPortrait:
    """A portrait from body-frame states (any model): one level (that of `level_of`, default the reference
    state's), the one section engine, the one indicator engine on the starts."""
    if level_of is None:
        level_of = np.asarray(system.code.names.REFERENCE, float)
    orbits = poincare_sections(system, starts=starts, level_of=level_of, seed=seed, iterates=iterates,
                               direction=direction, t_max=t_max, workers=workers, progress=progress)
    x0 = np.array([_start_state(r) for r in orbits])
    values = np.full(len(orbits), np.nan)
    if indicator is not None:
        ind = model_indicators(system, x0.T, t_max=float(t_indicator))
        values = np.where(ind.status == 0, getattr(ind, indicator), np.nan)
    bad = [i for i, r in enumerate(orbits) if not r.success]
    msg = "ok" if not bad else f"{len(bad)} of {len(orbits)} orbits failed (first: orbit {bad[0]}: " \
                               f"{orbits[bad[0]].message})"
    return SectionPortrait(not bad, msg, dict(system.params), float(orbits[0].h), x0, orbits, indicator, values,
                           float(t_indicator) if indicator is not None else None, time.perf_counter() - t0, None,
                           system=system)


def _start_state(r) -> np.ndarray:
    """The start of a model's section orbit (its StateStart's x0, kept in the result's extra)."""
    return np.asarray(r.extra["x0"], float)


# ----------------------------------------------------------------------------------------------------------
# orbit diagrams
# ----------------------------------------------------------------------------------------------------------
@dataclass(repr=False)
class OrbitDiagram(Result):
    """Section points against a parameter: for every value (M,) one orbit from the same chart start on the same
    level; flattened point arrays value_index (K,), points (K, 4) (theta, psi, pbar_theta, pbar_psi), and per
    value n_points, max_abs_dH, final_time, success (M,).  `orbits` keeps the PoincareResults."""

    success: bool
    message: str
    parameter: str
    values: np.ndarray
    value_index: np.ndarray  # (K,) the index into values of each point
    points: np.ndarray  # (K, 4) the section points (theta, psi, pbar_theta, pbar_psi) of every value
    n_points: np.ndarray  # (M,) points recorded per value
    max_abs_dH: np.ndarray  # (M,) max |Hbar - h| per value's orbit
    final_time: np.ndarray  # (M,) the arclength where each value's run stopped
    orbit_success: np.ndarray  # False also where the value has no energy root (no_root)
    h: float
    theta0: float
    ptheta0: float
    psi0: float
    iterates: int
    transient: int  # section points dropped at the start of each orbit
    coordinate: str
    wall_s: float
    marks: dict = field(default_factory=dict)
    orbits: list = field(default_factory=list)  # one PoincareResult per value; None where no_root
    base: str | None = None  # the paper's panel whose start the diagram uses (None for another model)
    no_root: np.ndarray | None = None  # (M,) bool: the start is not on the level at this value (nothing computed)
    system: object = None  # the System whose parameter is varied (its base values)

    _repr_fields = ("parameter", "n_values", "iterates", "coordinate", "worst_dH", "wall_s")

    @property
    def n_values(self) -> int:
        """M, the number of parameter values."""
        return int(self.values.size)

    @property
    def worst_dH(self) -> float:
        """The largest max |Hbar - h| over the values' orbits."""
        d = self.max_abs_dH[np.isfinite(self.max_abs_dH)]
        return float(np.max(d)) if d.size else 0.0

    @property
    def accuracy(self) -> dict:
        """{"max_abs_dH": worst_dH, "passed": every orbit passed its own accuracy checks}."""
        return {"max_abs_dH": self.worst_dH,
                "passed": all(r.accuracy_checks()["passed"] for r in self.orbits if r is not None)}

    def coordinate_values(self, coordinate=None) -> np.ndarray:
        """The plotted coordinate of every point (K,)."""
        c = coordinate or self.coordinate
        if self.points.shape[1] == 4 and c in COORDINATES:
            return self.points[:, COORDINATES[c]]
        return self.points[:, systems.model_body(self.system).state.index(c)]

    def summary(self) -> dict:
        return jsonable({"success": self.success, "message": self.message, "parameter": self.parameter,
                         "values": {"first": float(self.values[0]), "last": float(self.values[-1]),
                                    "n": self.n_values},
                         "h": self.h, "start": {"theta0": self.theta0, "ptheta0": self.ptheta0, "psi0": self.psi0},
                         "iterates": self.iterates, "transient": self.transient, "coordinate": self.coordinate,
                         "points": int(self.points.shape[0]), "max_abs_dH": self.worst_dH,
                         "failed_values": [float(v) for v, ok in zip(self.values, self.orbit_success) if not ok],
                         "no_root_values": [] if self.no_root is None else
                         [float(v) for v, nr in zip(self.values, self.no_root) if nr],
                         "marks": self.marks, "base": self.base, "wall_s": self.wall_s})

    def arrays(self) -> dict:
        return {"values": self.values, "value_index": self.value_index, "points": self.points,
                "n_points": self.n_points, "max_abs_dH": self.max_abs_dH, "final_time": self.final_time,
                "orbit_success": self.orbit_success}

    def to_dict(self) -> dict:
        """The summary and the arrays as references into arrays() (small ones inline)."""
        from ..core.results import array_refs

        return {**jsonable(self.summary()), "arrays": array_refs(self.arrays())}


def _monotone_values(values) -> np.ndarray:
    try:
        v = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError("values", "must be a list of numbers") from None
    if v.ndim == 0:
        v = v[None]
    if v.ndim != 1 or v.size == 0:
        raise ParameterError("values", f"must be a non-empty 1-D list of numbers, got shape {v.shape}")
    if v.size > MAX_ORBITS:
        raise ParameterError("values", f"{v.size} values; at most {MAX_ORBITS} orbits (MAX_ORBITS)")
    if not np.all(np.isfinite(v)):
        raise ParameterError("values", "must be finite")
    d = np.diff(v)
    if v.size > 1 and not (np.all(d > 0) or np.all(d < 0)):
        i = int(np.argmax(d <= 0) if d[0] > 0 else np.argmax(d >= 0))
        raise ParameterError("values", f"must be strictly monotone (increasing or decreasing); values {i} and {i + 1} "
                                       f"are {v[i]:g}, {v[i + 1]:g}")
    return v


_UNSET = object()


def _diagram_args(system, parameter, values, base):
    """(system, parameter, values) from orbit_diagram(system, parameter, values) or the older forms
    orbit_diagram(parameter, values, base=...) and base= (deprecated, one warning)."""
    import warnings

    if values is None and parameter is not None and not isinstance(parameter, str) and not callable(parameter):
        warnings.warn("orbit_diagram(parameter, values, base=...) is deprecated: call orbit_diagram(system, "
                      "parameter, values)", DeprecationWarning, stacklevel=3)
        system, parameter, values = (None if base is _UNSET else base), system, parameter
        return ("4a" if system is None else system), parameter, values
    if base is not _UNSET:
        if system is not None:
            raise TypeError("orbit_diagram() got both a system and base= (deprecated)")
        warnings.warn("orbit_diagram(base=...) is deprecated: the argument is now called system",
                      DeprecationWarning, stacklevel=3)
        system = base
    return ("4a" if system is None else system), parameter, values


def orbit_diagram(system=None, parameter=None, values=None, *, base=_UNSET, h=None, theta0=None, ptheta0=None,
                  psi0=None, iterates=500, transient=0, coordinate=None, root="smallest", direction="positive",
                  t_max=None, marks=None, workers=None, progress=None, model=None, x0=None) -> OrbitDiagram:
    """Orbit diagram: the section points sin(psi) = 0 of one orbit per parameter value, against the parameter.

    Parameters
    ----------
    system : System, str, Panel or RodParams
        What is studied, and the values the parameter is varied from: a paper panel (its rod, level and start;
        default Figure 4(a): h = 0.9, theta0 = 0.1, pbar_theta0 = 0.5), a RodParams (give h, theta0, ptheta0), or
        any model (a System, a name or a model file): its section from `x0` (default its reference state), put on
        its own level of H and the Casimirs at each value.  (The older form orbit_diagram(parameter, values,
        base=...) is deprecated.)
    parameter : str or callable
        A parameter of the model varied from `system`'s values (the paper's rod: m, mu, gamma, delta, lam), or,
        for the paper's rod, params_fn(value) -> RodParams (or a Panel, which then also gives the level and start).
    values : array of shape (M,)
        Strictly monotone parameter values.
    model, x0
        Any model: the model when `system` is a dict of its values; the start state (dim,).
    h, theta0, ptheta0, psi0 : float, optional
        Override the base's level and start (needed when base is a RodParams).
    iterates : int
        Section points per value, after dropping the first `transient`.
    coordinate : {"theta", "ptheta", "psi", "ppsi"} or a state name
        The coordinate plotted against the parameter (default theta; any other model: its second state
        component).
    marks : dict, optional
        {label: value} drawn as vertical lines (e.g. the paper's panels).
    root, direction, t_max, workers, progress
        As in `poincare_section`.

    Returns
    -------
    OrbitDiagram
        values (M,), value_index (K,), points (K, 4), per-value accuracy and success, plot().

    Raises
    ------
    ParameterError
        `parameter`: not a model parameter (nor callable); `values`: empty, non-finite, not strictly monotone,
        more than MAX_ORBITS, or a value giving an invalid rod (named by index); a value whose start has no energy
        root is not an error: it is marked in `no_root` (nothing computed there, `orbits[i]` is None);
        `coordinate`, `transient`.

    Examples
    --------
    >>> import magrod as mr
    >>> od = mr.orbit_diagram("4a", "lam", [0.135, 0.16, 0.186], iterates=40)
    >>> od.success, od.values.size, od.points.shape
    (True, 3, (120, 4))

    Notes
    -----
    Every orbit starts from the same chart point on the same level (the base's); pbar_psi0 is solved per value
    (`root`).  The orbits run in SIMD lanes on all cores (`poincare_section` with many starts) and each passes the
    accuracy gate of a single section.  Cost: as many section points in lanes (benchmarks/README.md: 200 values x
    500 iterates), plus one energy-root solve per value (~1-8 ms each) before the lanes start.
    """
    t0 = time.perf_counter()
    system, parameter, values = _diagram_args(system, parameter, values, base)
    v = _monotone_values(values)
    if not callable(parameter):
        sys_, base = resolve(system, model)
        if not sys_.is_paper or x0 is not None or (isinstance(base, RodParams) and h is None and theta0 is None
                                                   and ptheta0 is None):
            return _model_diagram(sys_, parameter, v, x0, t0, iterates=iterates, transient=transient,
                                  coordinate=coordinate, direction=direction, t_max=t_max, marks=marks,
                                  workers=workers, progress=progress)
    else:
        base = system
    coordinate = "theta" if coordinate is None else coordinate
    if coordinate not in COORDINATES:
        raise ParameterError("coordinate", f"must be one of {', '.join(COORDINATES)}, got {coordinate!r}")
    iterates = require_positive_int("iterates", iterates)
    transient = int(transient)
    if transient < 0 or transient != float(transient):
        raise ParameterError("transient", f"must be an integer >= 0, got {transient!r}")
    if isinstance(base, (str, Panel)) or (base is not None and not isinstance(base, RodParams)
                                          and getattr(base, "key", None)):
        P = panel(base)
        base_params, base_key = P.params, P.key
        h = P.h if h is None else h
        theta0 = P.theta0 if theta0 is None else theta0
        ptheta0 = P.ptheta0 if ptheta0 is None else ptheta0
        psi0 = P.psi0 if psi0 is None else psi0
    elif isinstance(base, RodParams):
        base_params, base_key = base, None
    else:
        raise ParameterError("base", f"must be a panel name, a Panel or a RodParams, got {type(base).__name__}")
    psi0 = 0.0 if psi0 is None else psi0
    if callable(parameter):
        name = getattr(parameter, "__name__", "parameter")
        make = parameter
    elif isinstance(parameter, str) and parameter in PARAMS:
        name = parameter

        def make(x):
            return base_params.replace(**{parameter: float(x)})
    else:
        raise ParameterError("parameter", f"must be a model parameter ({', '.join(PARAMS)}) or a callable "
                                          f"value -> RodParams, got {parameter!r}")
    items = []
    for i, x in enumerate(v):
        try:
            p = make(float(x))
        except ParameterError as exc:
            raise ParameterError("values", f"value {i} = {x:g}: {exc.name}: {exc.message}") from None
        if isinstance(p, Panel):
            items.append(Panel(p.key, p.label, p.params, p.h if h is None else h,
                               p.theta0 if theta0 is None else theta0, p.ptheta0 if ptheta0 is None else ptheta0,
                               p.psi0 if psi0 is None else psi0, p.vary))
        elif isinstance(p, RodParams):
            if h is None or theta0 is None or ptheta0 is None:
                raise ParameterError("base", "give h, theta0 and ptheta0 (or a panel as base)")
            items.append(Panel(f"{name}={x:g}", "", p, float(h), float(theta0), float(ptheta0), float(psi0),
                               (name, float(x))))
        else:
            raise ParameterError("parameter", f"params_fn must return a RodParams or a Panel, got {type(p).__name__}")
    # a value whose start is not on the level (no energy root) is marked, not raised: the package's own
    # figure draws those values as a grey band, and a scan through them is what a researcher asks for
    def has_no_root(P) -> bool:
        try:
            return solve_p_psi(P.params, P.h, P.theta0, P.ptheta0, P.psi0).size == 0
        except ParameterError as exc:
            if exc.name == "h":  # "Hbar(...) = h has no real root pbar_psi on the admissible range"
                return True
            raise

    no_root = np.array([has_no_root(P) for P in items])
    run = [P for P, nr in zip(items, no_root) if not nr]
    got = []
    if run:
        try:
            got = poincare_sections(run, iterates=iterates + transient, root=root, direction=direction,
                                   t_max=t_max, workers=workers, progress=progress)
        except ParameterError as exc:
            m = re.match(r"entry (\d+) ", exc.message)
            if exc.name == "params" and m:
                i = int(np.flatnonzero(~no_root)[int(m.group(1))])
                raise ParameterError("values", f"value {i} = {v[i]:g}: {exc.message[m.end():]}") from None
            raise
    orbits, idx, pts, ok, failed, parts = _gathered(got, no_root, v, transient, 4,
                                                    "have no energy root at the start (marked no_root; first "
                                                    f"{v[int(np.argmax(no_root))]:g})")
    if no_root.all():
        parts.append("nothing computed")
    msg = "; ".join(parts) or "ok"
    nan = float("nan")
    P0 = items[0]
    return OrbitDiagram(not failed and not no_root.all(), msg, name, v, np.concatenate(idx), np.concatenate(pts),
                        np.array([0 if r is None else r.n_points for r in orbits]),
                        np.array([nan if r is None else r.max_abs_dH for r in orbits]),
                        np.array([nan if r is None else r.final_time for r in orbits]), ok, float(P0.h),
                        float(P0.theta0), float(P0.ptheta0), float(P0.psi0), iterates, transient, coordinate,
                        time.perf_counter() - t0, dict(marks or {}), orbits, base_key, no_root,
                        as_system(base_params)[0])


def _gathered(run, no_root, v, transient, dim, no_root_text):
    """The orbits of a diagram in value order (None where a value has no start), the kept points with their value
    index, the success mask, the failed values and the message parts: the one bookkeeping of every model's diagram."""
    it = iter(run)
    orbits = [None if nr else next(it) for nr in no_root]
    idx, pts = [np.zeros(0, np.int32)], [np.zeros((0, dim))]
    for i, r in enumerate(orbits):
        if r is not None:
            keep = r.points[transient:]
            idx.append(np.full(keep.shape[0], i, dtype=np.int32))
            pts.append(keep)
    ok = np.array([r is not None and r.success for r in orbits])
    failed = [i for i, r in enumerate(orbits) if r is not None and not r.success]
    parts = []
    if failed:
        parts.append(f"{len(failed)} of {len(orbits)} orbits failed (first: value {v[failed[0]]:g}: "
                     f"{orbits[failed[0]].message})")
    if no_root.any():
        sep = "" if no_root_text.startswith(":") else " "
        parts.append(f"{int(no_root.sum())} of {no_root.size} values{sep}{no_root_text}")
    return orbits, idx, pts, ok, failed, parts


def _model_diagram(system, parameter, v, x0, t0, *, iterates, transient, coordinate, direction, t_max, marks,
                   workers, progress) -> OrbitDiagram:
    """An orbit diagram of any model over one of its parameters: per value the model's start (x0, default its
    reference state) on its own level there (section.level_starts), all values in the SIMD lanes of the one
    section engine."""
    from .section import SectionOptions, StateStart, _check_model_options, _refuse, _run_lanes, project_to_level

    mb = systems.model_body(system)
    if not isinstance(parameter, str) or parameter not in mb.params:
        raise ParameterError("parameter", f"must be a parameter of the model {system.model!r} "
                                          f"({', '.join(mb.params)}), got {parameter!r}")
    coordinate = mb.state[1] if coordinate is None else coordinate
    if coordinate not in mb.state:
        raise ParameterError("coordinate", f"must be a state variable of {system.model!r} ({', '.join(mb.state)}), "
                                           f"got {coordinate!r}")
    iterates = require_positive_int("iterates", iterates)
    transient = int(transient)
    if transient < 0:
        raise ParameterError("transient", f"must be an integer >= 0, got {transient!r}")
    start = np.asarray(system.code.names.REFERENCE if x0 is None else x0, float)
    if start.shape != (mb.dim,) or not np.all(np.isfinite(start)):
        raise ParameterError("x0", f"must be a finite state of {mb.dim} components {mb.state}")
    opts = SectionOptions(iterates=iterates + transient, t_max=t_max, direction=direction)
    _check_model_options(system, opts)
    starts, no_root = [], np.zeros(v.size, bool)
    for i, x in enumerate(v):
        try:
            si = system.replace(**{parameter: float(x)})
        except ParameterError as exc:
            raise ParameterError("values", f"value {i} = {x:g}: {exc.name}: {exc.message}") from None
        g0 = np.asarray(mb.level(start, si.array()), float)
        try:
            starts.append(StateStart(si, project_to_level(si, start, g0), g0, f"{parameter}={x:g}"))
        except ParameterError:
            no_root[i] = True
    orbits_run = _run_lanes(starts, opts, workers, progress) if starts else []
    for r in orbits_run:
        if r.success and not r.accuracy_checks()["passed"]:
            _refuse(r)
    orbits, idx, pts, ok, failed, parts = _gathered(orbits_run, no_root, v, transient, mb.dim,
                                                    ": the start cannot be put on its level (marked no_root)")
    nan = float("nan")
    return OrbitDiagram(not failed and not no_root.all(), "; ".join(parts) or "ok", parameter, v,
                        np.concatenate(idx), np.concatenate(pts),
                        np.array([0 if r is None else r.n_points for r in orbits]),
                        np.array([nan if r is None else r.max_abs_dH for r in orbits]),
                        np.array([nan if r is None else r.final_time for r in orbits]), ok,
                        float(orbits_run[0].h) if orbits_run else nan, nan, nan, nan, iterates, transient, coordinate,
                        time.perf_counter() - t0, dict(marks or {}), orbits, None, no_root, system)
