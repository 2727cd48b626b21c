"""Chaos maps: indicators over a parameter plane or a section, tile by tile.

A map is a `MapSpec` (two `Axis` objects, the base values of every other parameter and start value, tolerances);
it is cut into tiles (one Dask task and one zarr chunk each, magrod/store/tiles.py); `compute_tile` is a pure
function of (spec, tile).  Indicators and the chaos criterion come from magrod/chaos/indicators.py.
"""
from __future__ import annotations

import contextlib
import contextvars
import math
from dataclasses import asdict, dataclass, field

import numpy as np

from ..core import systems
from ..core.errors import MAX_MAGNITUDE, ParameterError, require_finite, require_positive_int
from ..core.params import RodParams
from ..core.deprecation import deprecated_alias
from ..core.results import Result
from ..core.tolerances import DRIFT_LIMIT
from ..generated.names import BODY_STATE, PARAMS
from .fields import BY_NAME, EXIT_FIELDS, MAP_EXTRA_FIELDS
from .indicators import (_KEYS, DEFAULT_RENORM_DT, EXIT_MARGIN, FAILED, GROWTH_THRESHOLD, NO_ROOT, OK, REASONS,
                         UNPHYSICAL, body_indicators, model_indicators)

# the names an Axis may vary: the paper's rod's AXIS_NAMES, or (while a model's map is specified) its parameters
_AXIS_NAMES = contextvars.ContextVar("magrod_axis_names", default=None)


@contextlib.contextmanager
def axis_names(names):
    """Axes built inside vary one of `names` (a model's parameters; None: the paper's AXIS_NAMES)."""
    token = _AXIS_NAMES.set(None if names is None else tuple(names))
    try:
        yield
    finally:
        _AXIS_NAMES.reset(token)


def model_names(model) -> tuple | None:
    """The parameter names of a map's model (None for the paper's rod: its AXIS_NAMES)."""
    if model is None:
        return None
    return tuple(_map_system(model).names)


# ----------------------------------------------------------------------------------------------------------
START = ("h", "theta0", "ptheta0", "psi0")
AXIS_NAMES = tuple(PARAMS) + START
DEFAULT_PANEL = "4a"
DEFAULT_TILE = 16


MAX_AXIS_POINTS = 4096  # 4096^2 orbits at ~5 ms each is a day on 2 cores: the largest map worth refusing later
# Bounds that make a map finish.  Cost per orbit: COST_PER_TIME per unit of T (the tangent system in
# SIMD batches, benchmarks/README.md: 5.6 us at T = 2000, batch mode) plus COST_PER_START for the energy root
# (magrod.chaos.indicators: ~1.3 ms).  A map whose estimated wall time on its workers exceeds MAX_WALL_HOURS is
# refused with the estimate; so is a renormalisation interval below T / MAX_RENORMALISATIONS (each one is a
# Python-level step per batch) or above T/2 (T/2 must be a sample time of the growth exponent).
COST_PER_TIME = 5.6e-6
COST_PER_START = 1.3e-3
MAX_WALL_HOURS = 24.0
MAX_RENORMALISATIONS = 100_000


@dataclass(frozen=True)
class Axis:
    """A grid axis: n points linspace(lo, hi, n) of one parameter (PARAMS) or start value (START).

    Validated on construction: ParameterError names the field (`name`, `lo`, `hi`, `n`) and the violated
    condition (unknown name, non-finite bound, n not an integer in [1, MAX_AXIS_POINTS], an empty range)."""

    name: str
    lo: float
    hi: float
    n: int

    def __post_init__(self):
        names = _AXIS_NAMES.get() or AXIS_NAMES
        if self.name not in names:
            raise ParameterError("name", f"unknown parameter {self.name!r}; choose from {', '.join(names)}")
        lo = require_finite("lo", self.lo, MAX_MAGNITUDE)
        hi = require_finite("hi", self.hi, MAX_MAGNITUDE)
        try:
            nf = float(self.n)
        except (TypeError, ValueError):
            raise ParameterError("n", f"number of points must be a positive integer, got {self.n!r}") from None
        if isinstance(self.n, bool) or not math.isfinite(nf) or nf != int(nf) or nf < 1:
            raise ParameterError("n", f"number of points must be a positive integer, got {self.n!r}")
        n = int(nf)
        if n > MAX_AXIS_POINTS:
            raise ParameterError("n", f"at most {MAX_AXIS_POINTS} points per axis, got {n}")
        if (n > 1 and not lo < hi) or (n == 1 and lo != hi):
            raise ParameterError("hi", f"empty range {lo:g}..{hi:g} with {n} point(s): need lo < hi (or lo = hi "
                                       f"with n = 1)")
        object.__setattr__(self, "lo", lo)
        object.__setattr__(self, "hi", hi)
        object.__setattr__(self, "n", n)

    def values(self) -> np.ndarray:
        return np.linspace(self.lo, self.hi, self.n)

    @classmethod
    def of(cls, value, option: str) -> "Axis":
        """An Axis from an Axis, a tuple (name, lo, hi, n) or the text NAME:LO:HI:N; ParameterError names
        `option` (e.g. "x" or "--x") with the field's complaint."""
        if isinstance(value, Axis):
            return value
        if isinstance(value, str):
            return parse_axis(option, value)
        try:
            name, lo, hi, n = value
        except (TypeError, ValueError):
            raise ParameterError(option, f"expected (name, lo, hi, n) or 'NAME:LO:HI:N', got {value!r}") from None
        try:
            return cls(name, lo, hi, n)
        except ParameterError as exc:
            raise ParameterError(option, exc.message) from None


def parse_axis(option: str, text: str) -> Axis:
    """NAME:LO:HI:N -> Axis; ParameterError(option, ...) on an unknown name, non-finite bounds, an empty range
    (LO >= HI with N > 1, or LO != HI with N = 1) or N not a positive integer."""
    parts = str(text).split(":")
    if len(parts) != 4:
        raise ParameterError(option, f"expected NAME:LO:HI:N (e.g. lam:0:0.3:128), got {text!r}")
    name, lo, hi, n = parts
    try:
        return Axis(name, lo, hi, n)
    except ParameterError as exc:
        raise ParameterError(option, exc.message) from None


@dataclass(frozen=True)
class MapSpec:
    """Everything that determines a chaos map (the store's identity: a resumed run must match it).

    base: values of PARAMS and START for every point (a paper panel, see panel_base), overridden by the axes.
    root: which root pbar_psi of Hbar = h starts the orbit ("smallest", the poincare default, or "largest").
    tol 0 = machine epsilon.  tile: tile edge in grid points (one Dask task and one zarr chunk per tile)."""

    x: Axis  # the horizontal axis: a parameter or start value, its range and number of points
    y: Axis  # the vertical axis, likewise
    base: dict = field(default_factory=dict)
    panel: str | None = DEFAULT_PANEL
    root: str = "smallest"
    t_max: float = 3000.0  # integration time of each orbit (the growth exponent's horizon)
    tol: float = 0.0  # Taylor tolerance; 0 = machine epsilon
    renorm_dt: float = DEFAULT_RENORM_DT  # interval between renormalisations of the tangent vector
    tile: int = DEFAULT_TILE
    batch_size: int = 0  # orbits per SIMD batch; 0 = the machine's batch width (results do not depend on it)
    refine: int = 0  # 0: brute force (every point); L > 0: adaptive refinement with L levels (chaos/refine.py)
    refine_bound: float | None = None  # with refine: also split cells whose growth exponents span more than this
    refine_threshold: float = GROWTH_THRESHOLD  # with refine: the growth exponent separating regular and chaotic
    early_exit: bool = False  # stop an orbit once it is classified chaotic (its exponent then a lower bound)
    model: str | None = None  # None: the paper's rod; else a registered model or a model file (its parameters)

    def __post_init__(self):
        if self.x.name == self.y.name:
            raise ParameterError("y", f"must vary a different parameter than --x (both {self.x.name!r})")
        t = require_finite("t_max", self.t_max)
        if t <= 0:
            raise ParameterError("t_max", f"must be > 0, got {self.t_max}")
        if require_finite("tol", self.tol) < 0:
            raise ParameterError("tol", f"must be >= 0 (0 = machine epsilon), got {self.tol}")
        dt = require_finite("renorm_dt", self.renorm_dt)
        if dt <= 0:
            raise ParameterError("renorm_dt", f"must be > 0, got {self.renorm_dt}")
        if dt > t / 2:
            raise ParameterError("renorm_dt", f"must be <= t_max/2 = {t / 2:g} (T/2 is a sample time of the growth "
                                              f"exponent), got {self.renorm_dt}")
        if t / dt > MAX_RENORMALISATIONS:
            raise ParameterError("renorm_dt", f"must be >= t_max/{MAX_RENORMALISATIONS} = "
                                              f"{t / MAX_RENORMALISATIONS:.3g} (at most {MAX_RENORMALISATIONS} "
                                              f"renormalisations per orbit), got {self.renorm_dt}")
        require_positive_int("tile", self.tile)
        if self.root not in ("smallest", "largest"):
            raise ParameterError("root", f"must be 'smallest' or 'largest', got {self.root!r}")
        names = model_names(self.model) or AXIS_NAMES
        for ax, which in ((self.x, "x"), (self.y, "y")):
            if ax.name not in names:
                raise ParameterError(which, f"unknown parameter {ax.name!r}; choose from {', '.join(names)}")
        missing = [k for k in names if k not in self.base and k not in (self.x.name, self.y.name)]
        if missing:
            raise ParameterError(missing[0], "no value: give it, or a panel that sets it (panel= / --panel)")
        if self.model is None:
            _check_theta0(self)
        _check_some_point_physical(self)
        _check_refine(self)
        _check_early_exit(self)
        if not self.batch_size:
            object.__setattr__(self, "batch_size", systems.batch_width())

    @property
    def shape(self) -> tuple:
        """The map's grid shape (y points, x points)."""
        return (self.y.n, self.x.n)

    as_dict = deprecated_alias("to_dict", "as_dict")

    def to_dict(self) -> dict:
        d = asdict(self)
        d["base"] = {k: float(v) for k, v in sorted(self.base.items())}
        if not self.refine:  # a brute-force map's dict (and so its store identity) is what it was before refinement existed
            for k in REFINE_KEYS:
                d.pop(k)
        if not self.early_exit:  # likewise without early exit
            d.pop("early_exit")
        if self.model is None:  # the paper's rod: its maps' identity is what it was before any other model
            d.pop("model")
        return d

    @property
    def exit_above(self) -> float | None:
        """The growth exponent above which an orbit stops early (None: no early exit): the map's classification
        threshold (refine_threshold, GROWTH_THRESHOLD for a brute-force map) + indicators.EXIT_MARGIN."""
        if not self.early_exit:
            return None
        return (self.refine_threshold if self.refine else GROWTH_THRESHOLD) + EXIT_MARGIN

    @classmethod
    def from_dict(cls, d: dict) -> "MapSpec":
        d = dict(d)
        with axis_names(model_names(d.get("model"))):
            d["x"], d["y"] = Axis(**d["x"]), Axis(**d["y"])
        return cls(**d)

    def point(self, ix: int, iy: int) -> dict:
        v = dict(self.base)
        v[self.x.name] = float(self.x.values()[ix])
        v[self.y.name] = float(self.y.values()[iy])
        return v


REFINE_KEYS = ("refine", "refine_bound", "refine_threshold")


def _check_refine(spec: "MapSpec") -> None:
    """refine 0 (brute force) or a number of levels (magrod.chaos.refine); bound None or > 0; threshold finite."""
    from .refine import check_levels

    if spec.refine not in (0, None):
        object.__setattr__(spec, "refine", check_levels(spec.refine))
    else:
        object.__setattr__(spec, "refine", 0)
    if spec.refine_bound is not None:
        b = require_finite("refine_bound", spec.refine_bound)
        if b <= 0:
            raise ParameterError("refine_bound", f"must be > 0 (or None: refine on the class only), got {b:g}")
        object.__setattr__(spec, "refine_bound", b)
    object.__setattr__(spec, "refine_threshold", require_finite("refine_threshold", spec.refine_threshold))
    if not spec.refine and (spec.refine_bound is not None or spec.refine_threshold != GROWTH_THRESHOLD):
        raise ParameterError("refine_bound" if spec.refine_bound is not None else "refine_threshold",
                             "applies to a refined map only: give refine = a number of levels")


def _check_early_exit(spec: "MapSpec") -> None:
    """early_exit a bool; not with refine_bound (that compares growth exponents, which an exit makes lower
    bounds; the classes an exit keeps are the ones below its level, magrod.chaos.indicators)."""
    if not isinstance(spec.early_exit, (bool, np.bool_)):
        raise ParameterError("early_exit", f"must be True or False, got {spec.early_exit!r}")
    object.__setattr__(spec, "early_exit", bool(spec.early_exit))
    if spec.early_exit and spec.refine_bound is not None:
        raise ParameterError("early_exit", "not with refine_bound: an early exit leaves a chaotic orbit's growth "
                                           "exponent a lower bound, and refine_bound compares their spread")


def _check_theta0(spec: "MapSpec") -> None:
    """Every start angle inside (0, pi), away from the Euler-angle singularity sin(theta) = 0 of Hbar (as
    magrod.chaos.section requires of one start): a fixed theta0 or both ends of a theta0 axis."""
    def bad(v):
        return not (0.0 < v < math.pi) or math.sin(v) < 1e-8

    for ax in (spec.x, spec.y):
        if ax.name == "theta0" and (bad(ax.lo) or bad(ax.hi)):
            which = "x" if ax is spec.x else "y"
            raise ParameterError(which, f"theta0 must lie strictly inside (0, pi) (sin(theta) = 0 is the Euler-angle "
                                        f"singularity of Hbar), got {ax.lo:g}..{ax.hi:g}")
    if "theta0" not in (spec.x.name, spec.y.name) and "theta0" in spec.base and bad(float(spec.base["theta0"])):
        raise ParameterError("theta0", f"must lie strictly inside (0, pi) (sin(theta) = 0 is the Euler-angle "
                                       f"singularity of Hbar), got {spec.base['theta0']!r}")


def _check_some_point_physical(spec: "MapSpec") -> None:
    """Points with unphysical parameters are marked missing, but a map with none physical is an input error
    (RodParams' complaint).  The constraints (m > 0, delta >= 0, gamma + delta >= 0) are linear, so the grid's
    corners decide."""
    err = None
    for xv in (spec.x.lo, spec.x.hi):
        for yv in (spec.y.lo, spec.y.hi):
            v = {**spec.base, spec.x.name: xv, spec.y.name: yv}
            try:
                if spec.model is None:
                    RodParams(**{k: v[k] for k in PARAMS})
                else:
                    _map_system(spec.model).replace(**{k: v[k] for k in _map_system(spec.model).names})
                return
            except ParameterError as exc:
                err = exc
    raise err


def estimated_cpu_s(spec: "MapSpec") -> float:
    """Estimated CPU seconds of the whole map: points x (T x COST_PER_TIME + COST_PER_START)."""
    return spec.x.n * spec.y.n * (spec.t_max * COST_PER_TIME + COST_PER_START)


def check_cost(spec: "MapSpec", workers: int = 1, name: str = "t_max") -> float:
    """Refuse (ParameterError naming `name`) a map whose estimated wall time on `workers` exceeds MAX_WALL_HOURS;
    returns the estimate in seconds."""
    cpu = estimated_cpu_s(spec)
    wall = cpu / max(1, int(workers))
    if wall > MAX_WALL_HOURS * 3600:
        raise ParameterError(name, f"the map cannot finish in {MAX_WALL_HOURS:g} h: {spec.y.n} x {spec.x.n} points x "
                                   f"(T = {spec.t_max:g} x {COST_PER_TIME * 1e6:.1f} us + "
                                   f"{COST_PER_START * 1e3:.1f} ms) = an estimated {cpu / 3600:.3g} CPU-hours, "
                                   f"{wall / 3600:.3g} h on {workers} worker(s); use fewer points, a shorter T or "
                                   f"more workers")
    return wall


def panel_base(key) -> dict:
    """PARAMS and START values of a paper panel (magrod.chaos.section.PANELS; a Panel too), or the PARAMS of a
    RodParams (its start values are then given as keywords or on an axis)."""
    from ..core.params import RodParams
    from ..paper.printed import PANELS, Panel

    if isinstance(key, RodParams):
        return key.to_dict()
    if isinstance(key, Panel):
        return {**key.params.to_dict(), **key.start()}
    if key not in PANELS:
        raise ParameterError("panel", f"unknown panel {key!r}; choose from {', '.join(PANELS)}")
    pk = PANELS[key]
    return {**pk["params"].to_dict(), "h": pk["h"], "theta0": pk["theta0"], "ptheta0": pk["ptheta0"],
            "psi0": pk["psi0"]}


def start_point(v: dict, root: str = "smallest"):
    """(x0 (9,), pars (5,), status, pbar_psi0) of one grid point: the chart start (theta0, psi0, pbar_theta0,
    pbar_psi) on Hbar = h mapped to the body frame; status NO_ROOT / UNPHYSICAL with NaNs if impossible."""
    from .section import solve_p_psi

    nan9 = np.full(len(BODY_STATE), np.nan)
    try:
        params = RodParams(*(v[k] for k in PARAMS))
    except ParameterError:
        return nan9, np.full(len(PARAMS), np.nan), UNPHYSICAL, np.nan
    p = params.array()
    try:
        roots = solve_p_psi(params, v["h"], v["theta0"], v["ptheta0"], v["psi0"])
    except ParameterError:
        return nan9, p, NO_ROOT, np.nan
    q = roots[0] if root == "smallest" else roots[-1]
    return systems.euler_to_body(v["theta0"], v["psi0"], v["ptheta0"], q, p), p, OK, float(q)


@systems.cache
def _map_system(model: str):
    """The System of a map's model at its defaults (the points' parameters are passed per orbit)."""
    from ..core.system import as_system

    return as_system(model)[0]


def model_start_point(system, v: dict):
    """(x0 (dim,), pars, status, NaN) of one grid point of a model's map: the model's reference state put on its
    own level of H and the Casimirs at the point's parameters (section.project_to_level); status UNPHYSICAL
    outside the model's admissible set, NO_ROOT where the level cannot be reached."""
    from .section import project_to_level

    mb = systems.model_body(system)
    nan = np.full(mb.dim, np.nan)
    try:
        at = system.replace(**{k: v[k] for k in mb.params})  # the model's admissible set (RodParams for the paper)
    except ParameterError:
        return nan, np.full(len(mb.params), np.nan), UNPHYSICAL, np.nan
    pars = at.array()
    ref = np.array(system.code.names.REFERENCE, float)
    try:
        x0 = project_to_level(at, ref, np.asarray(mb.level(ref, pars), float))
    except ParameterError:
        return nan, pars, NO_ROOT, np.nan
    return x0, pars, OK, np.nan


def _indicators(spec, starts, **kw):
    """The indicators of a map's starts [(x0, pars, status, p_psi0)]: the one engine for every model."""
    if spec.model is None:
        n, npar = len(BODY_STATE), len(PARAMS)
    else:
        mb = systems.model_body(_map_system(spec.model))
        n, npar = mb.dim, len(mb.params)
    x0 = np.array([s[0] for s in starts]).T.reshape(n, -1)
    p = np.array([s[1] for s in starts]).T.reshape(npar, -1)
    st0 = np.array([s[2] for s in starts], np.int8)
    common = dict(t_max=spec.t_max, tol=spec.tol or None, renorm_dt=spec.renorm_dt, batch_size=spec.batch_size,
                  valid=st0 == OK, exit_above=spec.exit_above)
    if spec.model is None:
        return body_indicators(np.nan_to_num(x0), np.nan_to_num(p, nan=1.0), **common), st0
    return model_indicators(_map_system(spec.model), np.nan_to_num(x0), pars=np.nan_to_num(p, nan=1.0),
                            **common), st0


def _start(spec, v):
    if spec.model is None:
        return start_point(v, spec.root)
    return model_start_point(_map_system(spec.model), v)


@dataclass(frozen=True)
class Tile:
    iy: int
    ix: int
    ys: slice
    xs: slice

    @property
    def key(self) -> str:
        return f"{self.iy}_{self.ix}"

    @property
    def n_points(self) -> int:
        """The grid points of the tile (what a progress bar counts: points, not tiles)."""
        return (self.ys.stop - self.ys.start) * (self.xs.stop - self.xs.start)


def tiles(spec: MapSpec) -> list[Tile]:
    """The grid cut into tile x tile blocks, row-major; the same on every machine and for any worker count."""
    t = spec.tile
    return [tile_of(spec, f"{iy}_{ix}") for iy in range(math.ceil(spec.y.n / t)) for ix in range(math.ceil(spec.x.n / t))]


def tile_of(spec: MapSpec, key: str) -> Tile:
    """The tile with this key ("iy_ix"), built directly (O(1): a task must not list every tile of a 4096^2 map)."""
    try:
        iy, ix = (int(v) for v in str(key).split("_"))
    except ValueError:
        raise ParameterError("tile", f"not a tile key: {key!r}") from None
    t = spec.tile
    if not (0 <= iy < math.ceil(spec.y.n / t) and 0 <= ix < math.ceil(spec.x.n / t)):
        raise ParameterError("tile", f"tile {key!r} is outside the {spec.y.n} x {spec.x.n} grid")
    return Tile(iy, ix, slice(iy * t, min((iy + 1) * t, spec.y.n)), slice(ix * t, min((ix + 1) * t, spec.x.n)))


MAP_FIELDS = _KEYS + tuple(f.name for f in MAP_EXTRA_FIELDS)
EARLY_EXIT_FIELDS = tuple(f.name for f in EXIT_FIELDS)  # what a map with early exit adds ("exit_time")


def compute_tile(spec: MapSpec, tile: Tile) -> dict:
    """Indicators of every grid point of one tile: {field: (ny_t, nx_t) float64 array, "status": int8 array}.
    Pure function of (spec, tile): the unit of work of a Dask task and of a zarr chunk."""
    iys = range(tile.ys.start, tile.ys.stop)
    ixs = range(tile.xs.start, tile.xs.stop)
    pts = [spec.point(ix, iy) for iy in iys for ix in ixs]
    starts = [_start(spec, v) for v in pts]
    ind, st0 = _indicators(spec, starts)
    shape = (len(iys), len(ixs))
    out = {k: getattr(ind, k).reshape(shape) for k in _KEYS}
    out["p_psi0"] = np.array([s[3] for s in starts]).reshape(shape)
    out["status"] = np.where(st0 == OK, ind.status, st0).astype(np.int8).reshape(shape)
    if spec.early_exit:
        out["exit_time"] = ind.exit_time.reshape(shape)
    return out


REFINE_FIELDS = ("inferred", "level")  # what a refined map adds per grid point (magrod.chaos.refine)


def compute_points(spec: MapSpec, iy, ix) -> dict:
    """Indicators of the grid points (iy[k], ix[k]) (1-D index arrays): {field: (k,) array, "status": int8}.  The
    same numbers as compute_tile gives at those points (each orbit has its own batch lane and the same start
    tangent vector), so a refined map's computed points are the brute-force map's."""
    iy, ix = np.asarray(iy, int), np.asarray(ix, int)
    starts = [_start(spec, spec.point(int(x), int(y))) for y, x in zip(iy, ix)]
    ind, st0 = _indicators(spec, starts)
    out = {k: np.asarray(getattr(ind, k), float) for k in _KEYS}
    out["p_psi0"] = np.array([s[3] for s in starts], float)
    out["status"] = np.where(st0 == OK, ind.status, st0).astype(np.int8)
    if spec.early_exit:
        out["exit_time"] = np.asarray(ind.exit_time, float)
    return out


def round_tiles(spec: MapSpec, iy, ix) -> dict:
    """{tile key: (iy, ix) of the round's points in that tile, row-major}: a refinement round cut into tasks."""
    iy, ix = np.asarray(iy, int), np.asarray(ix, int)
    t = spec.tile
    keys = (iy // t) * (-(-spec.x.n // t)) + ix // t
    order = np.lexsort((ix, iy, keys))
    out = {}
    ks = keys[order]
    for k in np.unique(ks):
        sel = order[ks == k]
        out[f"{int(k) // (-(-spec.x.n // t))}_{int(k) % (-(-spec.x.n // t))}"] = (iy[sel], ix[sel])
    return out


TASK_BATCHES = 8  # a refinement task integrates at least this many full SIMD batches (when the round has them)


def round_tasks(spec: MapSpec, groups: dict) -> list:
    """A round's tile parts ({key: (iy, ix)}, row-major) grouped into tasks: consecutive parts until a task holds
    TASK_BATCHES x batch_size points.  A round touches few points per tile (the coarse lattice of a 256^2 map with
    L = 3: ~4 per tile), and a task per tile part would leave most SIMD lanes of its batches empty.  The grouping
    changes no number (every orbit has its own lane), only how full the batches are."""
    want = TASK_BATCHES * spec.batch_size
    tasks, cur, n = [], [], 0
    for k, (gy, _) in groups.items():
        cur.append(k)
        n += int(gy.size)
        if n >= want:
            tasks.append(cur)
            cur, n = [], 0
    if cur:
        tasks.append(cur)
    return tasks


def compute_refined(spec: MapSpec, *, progress=None, client=None, on_round=None) -> "ChaosMap":
    """A refined map in memory (magrod.chaos.refine): round by round, each round's points cut into tiles, in this
    process or as one Dask task per tile.  on_round(round, n_points) after each round (tests, progress)."""
    import time

    from .refine import Refinement, point_class

    t0 = time.perf_counter()
    fields = empty_fields(spec)
    ref = Refinement(spec.shape, spec.refine, spec.refine_bound)
    sd = spec.to_dict()
    n_computed = 0
    while not ref.done:
        iy, ix = ref.points()
        groups = round_tiles(spec, iy, ix)
        tasks = round_tasks(spec, groups)
        pts = [(np.concatenate([groups[k][0] for k in ks]), np.concatenate([groups[k][1] for k in ks]))
               for ks in tasks]
        if client is None:
            done = ((j, compute_points(spec, *pts[j])) for j in range(len(tasks)))
        else:
            from dask.distributed import as_completed

            futs = {client.submit(_points_task, sd, gy.tolist(), gx.tolist(), pure=False): j
                    for j, (gy, gx) in enumerate(pts)}
            done = ((futs[f], f.result()) for f in as_completed(futs))
        for j, res in done:
            gy, gx = pts[j]
            for name, v in res.items():
                fields[name][gy, gx] = v
            if progress is not None:
                progress(1)
        ref.add(iy, ix, point_class(fields["status"][iy, ix], fields["growth_exponent"][iy, ix],
                                    spec.refine_threshold), fields["growth_exponent"][iy, ix])
        n_computed += iy.size
        if on_round is not None:
            on_round(ref.round - 1, int(iy.size))
    fields = finish_refined(ref, fields)
    n_ok = int(((fields["status"] == OK) & (fields["inferred"] == 0)).sum())
    msg = "ok" if n_ok else "no point of the map could be computed (see the status field)"
    return ChaosMap(n_ok > 0, msg, spec, fields, time.perf_counter() - t0)


def finish_refined(ref, fields: dict) -> dict:
    """The finished refinement's fields: inferred points filled (refine.Refinement.infer), plus "inferred" (int8:
    1 never computed, class from its cell) and "level" (int8: the round a point was computed in, -1 inferred)."""
    out = ref.infer(fields, MAP_FIELDS)
    out["inferred"] = ref.inferred().astype(np.int8)
    out["level"] = ref.level.copy()
    return out


def _points_task(spec_dict: dict, iy: list, ix: list) -> dict:
    """Some points of one tile from plain data (a Dask task of a refinement round)."""
    return compute_points(MapSpec.from_dict(spec_dict), iy, ix)


@dataclass(repr=False)
class ChaosMap(Result):
    """A chaos map: fields (ny, nx) as in compute_tile ("status" int8, NaN indicators where status != OK), the
    spec, wall time.  success: at least one point computed; `summary()` adds the fraction chaotic."""

    success: bool
    message: str
    spec: MapSpec  # what was mapped: the axes, the base system, the level and the indicators' settings
    fields: dict  # {name: (ny, nx) array}: the indicators (lyap, fli, growth_exponent, ...), the conservation, status
    wall_s: float
    store: str | None = None  # the store directory of a resumable map (None: computed in memory)
    run: dict | None = None  # a stored map (magrod.store.resumable): what this call computed, skipped, repaired

    _repr_fields = ("shape", "fraction_chaotic", "wall_s", "store")

    @property
    def shape(self) -> tuple:
        """(ny, nx), the map's grid."""
        return self.spec.shape

    @property
    def chaotic(self) -> np.ndarray:
        """growth_exponent > GROWTH_THRESHOLD per point (ny, nx) (False where missing)."""
        with np.errstate(invalid="ignore"):
            return np.asarray(self.fields["growth_exponent"]) > GROWTH_THRESHOLD

    @property
    def system(self):
        """The System whose parameters the map varies around (its base values; the paper's rod for a panel map)."""
        from ..core.system import as_system

        if self.spec.model is not None:
            return as_system(self.spec.model, **self.spec.base)[0]
        return as_system({k: self.spec.base[k] for k in PARAMS if k in self.spec.base} if all(
            k in self.spec.base for k in PARAMS) else None)[0]

    @property
    def fraction_chaotic(self):
        """The fraction of the computed points that are chaotic (growth exponent above GROWTH_THRESHOLD)."""
        return self.summary()["fraction_chaotic"]

    @property
    def accuracy(self) -> dict:
        """Worst conservation over the computed points against DRIFT_LIMIT (points beyond it are LEFT_RANGE)."""
        s = self.summary()
        worst = [v for v in (s["max_abs_dH"], s["max_casimir_drift"]) if v is not None]
        return {"max_abs_dH": s["max_abs_dH"], "max_casimir_drift": s["max_casimir_drift"], "limit": DRIFT_LIMIT,
                "passed": bool(worst) and all(np.isfinite(v) and v <= DRIFT_LIMIT for v in worst)}

    def summary(self, threshold=GROWTH_THRESHOLD) -> dict:
        return map_summary(self.spec, self.fields, self.wall_s, threshold)

    def to_dict(self) -> dict:
        from ..core.results import INLINE_ARRAY_MAX, jsonable

        # the fields as references {"npz": "fields.<name>", ...} into arrays() (small maps inline)
        return {**jsonable({"success": self.success, "message": self.message, "spec": self.spec.to_dict(),
                            "summary": self.summary(), "store": self.store,
                            **({"run": self.run} if self.run is not None else {})}),
                "fields": jsonable(self.fields, INLINE_ARRAY_MAX, "fields")}

    def to_xarray(self):
        """An xarray.Dataset with coordinates (y-parameter, x-parameter) and one variable per field."""
        import json

        import xarray as xr

        from ..core.results import jsonable

        sx, sy = self.spec.x, self.spec.y
        dims = (sy.name, sx.name)
        # the CF attributes of the zarr store (units, long_name, the status flags): one definition, store.py
        ds = xr.Dataset({k: (dims, np.asarray(v), variable_attrs(k)) for k, v in self.fields.items()},
                        coords={sx.name: (sx.name, sx.values(), coord_attrs(sx.name)),
                                sy.name: (sy.name, sy.values(), coord_attrs(sy.name))})
        ds.attrs.update({**dataset_attrs(self.spec), "spec": json.dumps(self.spec.to_dict()),
                         "criterion": self.summary()["criterion"], "summary": json.dumps(jsonable(self.summary()))})
        return ds


def map_summary(spec: MapSpec, fields: dict, wall_s: float, threshold=GROWTH_THRESHOLD) -> dict:
    """Grid, fraction chaotic (growth_exponent > threshold, among computed points), missing points by reason,
    wall time and orbits per second."""
    st = np.asarray(fields["status"])
    ok = st == OK
    g = np.asarray(fields["growth_exponent"])
    n_ok = int(ok.sum())
    return {"grid": {"x": asdict(spec.x), "y": asdict(spec.y)}, "points": int(st.size), "computed": n_ok,
            "missing": {REASONS[c]: int((st == c).sum()) for c in REASONS if c != OK and (st == c).any()},
            "criterion": f"chaotic iff growth_exponent = (FLI(T) - FLI(T/2))/ln 2 > {threshold:g}",
            "threshold": threshold,
            "fraction_chaotic": float((g[ok] > threshold).mean()) if n_ok else None,
            "max_growth_exponent": float(np.max(g[ok])) if n_ok else None,
            "max_lyap": float(np.nanmax(np.asarray(fields["lyap"])[ok])) if n_ok else None,
            "max_abs_dH": float(np.max(np.asarray(fields["max_abs_dH"])[ok])) if n_ok else None,
            "max_casimir_drift": float(np.max(np.asarray(fields["casimir_drift"])[ok])) if n_ok else None,
            "fraction_compressed": float((np.asarray(fields["min_stretch"])[ok] <= 0).mean()) if n_ok else None,
            "t_max": spec.t_max, "wall_s": wall_s, "orbits_per_s": st.size / wall_s if wall_s > 0 else None,
            **_refined_summary(spec, fields, wall_s), **_exit_summary(spec, fields)}


def _exit_summary(spec: MapSpec, fields: dict) -> dict:
    """What an early-exit map adds to its summary: the exit level, how many orbits stopped before T, and the
    integrated time as a fraction of the full T per computed orbit (nothing without early exit)."""
    if "exit_time" not in fields:
        return {}
    te = np.asarray(fields["exit_time"])
    run = np.isfinite(te)
    return {"early_exit": {"exit_above": spec.exit_above, "orbits_exited": int((te[run] < spec.t_max).sum()),
                           "orbits_run": int(run.sum()),
                           "time_fraction": float(te[run].sum() / (run.sum() * spec.t_max)) if run.any() else None}}


def _refined_summary(spec: MapSpec, fields: dict, wall_s: float) -> dict:
    """What a refined map adds to its summary (nothing for a brute-force map): how many points were computed
    and inferred, per round, and the requested grid points per second."""
    if "inferred" not in fields:
        return {}
    inf = np.asarray(fields["inferred"]) != 0
    lev = np.asarray(fields["level"])
    rounds = [int((lev == r).sum()) for r in range(int(lev.max()) + 1)] if (lev >= 0).any() else []
    return {"refine": {"levels": spec.refine, "bound": spec.refine_bound, "threshold": spec.refine_threshold,
                       "points_computed": int((~inf).sum()), "points_inferred": int(inf.sum()),
                       "fraction_computed": float((~inf).mean()), "points_per_round": rounds,
                       "grid_points_per_s": inf.size / wall_s if wall_s > 0 else None}}


def empty_fields(spec: MapSpec) -> dict:
    f = {k: np.full(spec.shape, np.nan) for k in MAP_FIELDS + (EARLY_EXIT_FIELDS if spec.early_exit else ())}
    f["status"] = np.full(spec.shape, FAILED, np.int8)
    return f


def compute_map(spec: MapSpec, *, progress=None, client=None) -> ChaosMap:
    """The whole map in memory: tile by tile in this process, or as one task per tile on a Dask `client`."""
    import time

    if spec.refine:
        return compute_refined(spec, progress=progress, client=client)
    t0 = time.perf_counter()
    fields = empty_fields(spec)
    all_tiles = tiles(spec)
    if client is None:
        done = ((t, compute_tile(spec, t)) for t in all_tiles)
    else:
        from dask.distributed import as_completed

        sd = spec.to_dict()
        futs = {client.submit(_tile_task, sd, t.key, pure=False): t for t in all_tiles}
        done = ((futs[f], f.result()) for f in as_completed(futs))
    for tile, res in done:
        for k, v in res.items():
            fields[k][tile.ys, tile.xs] = v
        if progress is not None:
            progress(tile.n_points)
    problem = check_fields(fields)
    return ChaosMap(problem is None, problem or "ok", spec, fields, time.perf_counter() - t0)


def check_fields(fields) -> str | None:
    """Why a map's fields are not a result (None if they are): no point computed, or points marked ok without
    finite indicators (what the workers wrote is inconsistent).  The one validity check of every map, in memory or
    from a store."""
    status = np.asarray(fields["status"])
    ok = status == OK
    if not ok.any():
        counts = {REASONS[int(c)]: int((status == c).sum()) for c in np.unique(status)}
        why = ", ".join(f"{v} {k}" for k, v in counts.items()) or "none"
        return f"no point of the map could be computed (status of the {status.size} points: {why})"
    for k in ("lyap", "fli", "growth_exponent", "max_abs_dH"):
        if not np.all(np.isfinite(np.asarray(fields[k])[ok])):
            return f"points marked ok have non-finite {k}: the store's content is inconsistent"
    return None


def _tile_task(spec_dict: dict, tile_key: str) -> dict:
    """One tile from plain data (a Dask task: picklable, no shared state)."""
    spec = MapSpec.from_dict(spec_dict)
    return compute_tile(spec, tile_of(spec, tile_key))


def _is_axis(v) -> bool:
    """An axis (or a MapSpec) rather than a System: the older calling form chaos_map(x, y, panel=...)."""
    return isinstance(v, (Axis, MapSpec)) or (isinstance(v, str) and ":" in v) or (
        isinstance(v, (tuple, list)) and len(v) == 4 and isinstance(v[0], str))


_UNSET = object()
_NO_BASE = object()


def _map_args(system, x, y, panel, model, values):
    """(x, y, base system or panel for map_spec, model name or None) from the calling forms: chaos_map(system, x,
    y) (the convention), chaos_map(x, y, panel=...) (older, deprecated) and model=/panel= (deprecated)."""
    import warnings

    if system is _NO_BASE:  # chaos_map's older panel=None: no base values, all given
        return x, y, None, None
    if isinstance(system, MapSpec):
        return system, x, None, None
    if _is_axis(system):  # the older form: the axes first
        if y is not None:
            raise ParameterError("y", "three axes given: call chaos_map(system, x, y)")
        x, y, system = system, x, None
        warnings.warn("chaos_map(x, y, panel=...) is deprecated: call chaos_map(system, x, y) (system: a panel key, "
                      "a System, a model name or file)", DeprecationWarning, stacklevel=3)
    if panel is not _UNSET:
        if system is not None:
            raise TypeError("chaos_map() got both a system and panel= (deprecated)")
        warnings.warn("chaos_map(panel=...) is deprecated: the argument is now called system", DeprecationWarning,
                      stacklevel=3)
        system = panel
        if panel is None:
            return x, y, None, None
        if isinstance(panel, str) and panel.lower() not in _panels():
            raise ParameterError("panel", f"unknown panel {panel!r}; choose from {', '.join(_panels())}")
    from ..paper.printed import Panel

    if model is None and (system is None or isinstance(system, (RodParams, Panel)) or (
            isinstance(system, str) and system.lower() in _panels())):
        return x, y, DEFAULT_PANEL if system is None else system, None
    from ..core.system import System, as_system

    sys_ = system if isinstance(system, System) and model is None else as_system(system, model=model)[0]
    # a System (of any model, the paper's rod included) has no chart start: its orbits start from the model's
    # reference state on its level at each point (model_start_point); a panel or RodParams keeps the chart's
    return x, y, sys_, sys_.model


def _panels():
    from ..paper.printed import PANELS

    return PANELS


def chaos_map(system=None, x=None, y=None, *, t_max=3000.0, tol=None, renorm_dt=DEFAULT_RENORM_DT,
              root="smallest", tile=DEFAULT_TILE, refine=0, refine_bound=None, early_exit=False, client=None,
              progress=None, model=None, panel=_UNSET, **values) -> ChaosMap:
    """Chaos indicators over a plane of two parameters or start values of a system.

    Parameters
    ----------
    system : System, str, Panel, RodParams or MapSpec
        What is studied: a paper panel ("4a" .. "5d"), whose parameters and start fill in every value not on an
        axis; a RodParams (the parameters only: the start values then come as keywords or on an axis); any other
        model (a System, a registered name or a model file), whose reference state, put on its own level of H
        and the Casimirs at each point's parameters, starts every orbit; None: panel 4a.  A MapSpec alone is
        computed as it is.  (The older form chaos_map(x, y, panel=...) is deprecated.)
    x, y : tuple, str or Axis
        The axes: (name, lo, hi, n), "name:lo:hi:n" or Axis; name is a parameter (m, mu, gamma, delta, lam) or a
        start value (h, theta0, ptheta0, psi0).  A MapSpec may be given as `x` alone.
    t_max, tol, renorm_dt, root
        As in `lyapunov` (tol None = machine epsilon, the default: see Notes for the evidence).
    tile : int
        Tile edge (one task per tile; in a refined map, one task per tile and round).
    refine : int
        0 (default): brute force, every grid point integrated.  L >= 1: adaptive (magrod.chaos.refine): the
        lattice of every 2^L-th point first, then only the cells whose computed points disagree in class
        (regular, chaotic, or the reason a point is missing), halved round by round down to the grid; the other
        points are inferred from their cell and flagged in the fields "inferred" (1) and "level" (-1).
    refine_bound : float, optional
        With `refine`: also split a cell of regular or chaotic points whose growth exponents span more than this.
    early_exit : bool
        False (default): every orbit runs for T.  True: an orbit stops at the first sample time t_e >= T/2 at
        which its growth exponent so far exceeds the classification threshold + EXIT_MARGIN (MapSpec.exit_above),
        and the field "exit_time" records t_e (T for an orbit that ran to the end).  No class changes (see Notes);
        an exited orbit's growth_exponent is a lower bound, its lyap L(t_e)/t_e.  Not with refine_bound.
    client : dask.distributed.Client, optional
        Run the tiles on this cluster (the workers need magrod installed); None: in this process.
    progress : callable, optional
        progress(n_points_done) as each tile finishes (a brute-force map; a refined map counts its tile parts).
    **values
        Values overriding the panel's (e.g. lam=0.15, h=0.9).

    model : str or path, keyword-only
        The model when `system` is a dict of its parameter values (older spelling: chaos_map(x, y, model=...)).
    panel : deprecated
        The older name of `system`.

    Returns
    -------
    ChaosMap
        fields (ny, nx) of lyap, fli, fli_half, growth_exponent, max_abs_dH, casimir_drift, min_stretch, p_psi0,
        status (and, refined, inferred and level; with early_exit, exit_time); `summary()`, `to_xarray()`,
        `plot()`.

    Raises
    ------
    ParameterError
        Naming x, y or the value: unknown name, empty range, the same name on both axes, a value both on an
        axis and given explicitly, bad t_max/tol/renorm_dt/tile, renorm_dt outside [t_max/MAX_RENORMALISATIONS,
        t_max/2], a start angle theta0 outside (0, pi), a map estimated to take longer than MAX_WALL_HOURS
        (named t_max, with the estimate).

    Examples
    --------
    >>> import magrod as mr
    >>> cm = mr.chaos_map("4a", ("lam", 0.12, 0.2, 2), ("gamma", 2.0, 3.5, 2), t_max=200)
    >>> cm.success, cm.shape, cm.to_xarray()["growth_exponent"].dims
    (True, (2, 2), ('gamma', 'lam'))
    >>> rm = mr.chaos_map("4a", ("lam", 0.12, 0.2, 5), ("gamma", 2.0, 3.5, 5), t_max=200, refine=2)
    >>> rm.fields["inferred"].shape, int(rm.fields["inferred"].sum()) <= 25 - 4
    ((5, 5), True)

    Notes
    -----
    Criterion: chaotic iff growth_exponent > 3 (magrod.chaos.indicators).  Cost ~5 us per orbit per unit time in
    SIMD batches, plus the energy root per point.  Results are bit-identical for any tile order and worker
    count.  For maps too large for memory, or resumable runs, give store=DIR (a zarr store on Dask,
    magrod.store.resumable; `magrod chaosmap --out DIR` is that).

    The default tolerance stays machine epsilon, by the work-precision study of the classification
    (benchmarks/classification_precision.py, benchmarks/README.md "Chaos maps at scale"; numerical evidence, two machines, the
    map lam x gamma = [0, 0.3] x [0, 3] at Figure 4's start rule):

    * 128 x 128, T = 1000, against the brute-force tol = eps map: the brute-force maps at 1e-12 and 1e-10 have the
      same class and status at all 10857 physical points, the one at 1e-8 misclassifies none of the 10813 it
      keeps and loses 44 (0.4 %); refined maps (L = 3, whose computed points are the
      brute-force map's bit for bit and sit at the class boundaries) at 1e-12 and 1e-10 misclassify none of their
      1606 computed points; 1e-8 misclassifies none but loses 42 of 2172 (1.9 %) to left_physical_range: its
      energy error exceeds the conservation budget DRIFT_LIMIT = 1e-8, the check that makes a point trustworthy.
    * 128 x 128, T = 3000, against the brute-force tol = eps map: brute force at 1e-12 changes nothing, at 1e-10
      one point of 10857 crosses the threshold (0.009 %, a sticky orbit at the boundary), at 1e-8 none of the 6055
      points it keeps does, but it loses 4802 (44 %) to the conservation budget.
    * 64 x 64 brute force, T = 1000 and 3000: 1e-12 and 1e-10 misclassify none of 2700 points; 1e-8 loses 0.3 %
      (T = 1000) and 45 % (T = 3000) of them.

    So a looser tolerance barely changes the answer (1e-12: not at all here), its gain is bounded by the
    integration's share of a point's cost (an orbit at 1e-10 / 1e-12 costs ~0.3-0.4x the one at eps, in-process),
    and 1e-8 breaks the conservation budget.  The default keeps every existing store's identity and REPORT.md's
    map; tol = 1e-10 is a sound choice for a large exploratory map (measured: 0 and 1 points of 10857 classified
    differently at T = 1000 and 3000).

    A refined map (`refine` = L) computes each point it computes exactly as the brute-force map does (the same
    bits), in rounds (one Dask wave each); what it can miss is an island of another class inside one coarse cell
    that touches none of the cell's computed points (magrod.chaos.refine).  benchmarks/refine_vs_brute.py measures
    its agreement with and its cost against the brute-force map.

    Early exit (`early_exit=True`) stops an orbit only after T/2, once (FLI(t_e) - FLI(T/2))/ln 2 exceeds the exit
    level; FLI(t) is a running maximum and never decreases, so the orbit's growth exponent at T is at least that
    value, and its class at any threshold up to the exit level is the one the full run gives (by the definition,
    not by a numerical comparison).  The lanes of the SIMD batch are refilled as orbits end, so the time saved is
    real: at most half of each chaotic orbit's T, nothing on regular ones (benchmarks/README.md, "early exit").
    Every orbit that does not exit has the brute-force map's numbers bit for bit (tests/test_early_exit.py).
    """
    x, y, base, model = _map_args(system, x, y, panel, model, values)
    base = _NO_BASE if base is None and model is None else base
    if isinstance(x, MapSpec):
        if y is not None or values:
            raise ParameterError("y", "give a MapSpec alone, or two axes")
        check_cost(x, _n_workers(client))
        return compute_map(x, progress=progress, client=client)
    spec = map_spec(base, x, y, t_max=t_max, tol=tol, renorm_dt=renorm_dt, root=root, tile=tile,
                    refine=refine, refine_bound=refine_bound, early_exit=early_exit, model=model, **values)
    check_cost(spec, _n_workers(client))
    return compute_map(spec, progress=progress, client=client)


def map_spec(system=None, x=None, y=None, *, t_max=3000.0, tol=None, renorm_dt=DEFAULT_RENORM_DT,
             root="smallest", tile=DEFAULT_TILE, refine=0, refine_bound=None, early_exit=False, model=None,
             panel=_UNSET, **values) -> MapSpec:
    """The MapSpec `chaos_map` computes (same arguments, validated the same way; a MapSpec given alone is
    returned as it is): for a stored map (magrod.store.resumable) or to inspect a map's grid and cost first."""
    x, y, base_sys, model = _map_args(system, x, y, panel, model, values)
    if isinstance(x, MapSpec):
        if y is not None or values:
            raise ParameterError("y", "give a MapSpec alone, or two axes")
        return x
    if y is None:
        raise ParameterError("y", "missing: give two axes (name, lo, hi, n)")
    names = model_names(model)
    with axis_names(names):
        ax, ay = Axis.of(x, "x"), Axis.of(y, "y")
    tol = 0.0 if tol is None else tol  # 0 = machine epsilon in a spec (the store identity of every existing map)
    if model is not None:
        base = dict(base_sys.params)
    else:
        base = panel_base(base_sys) if base_sys is not None else {}
    names = names or AXIS_NAMES
    for k, v in values.items():
        if k not in names:
            raise ParameterError(k, f"not a parameter or start value; choose from {', '.join(names)}")
        if k in (ax.name, ay.name):
            raise ParameterError(k, f"is varied on the {'x' if k == ax.name else 'y'} axis: do not also fix it")
        base[k] = require_finite(k, v, MAX_MAGNITUDE)
    pan = None if model is not None else base_sys
    return MapSpec(ax, ay, base=base, panel=pan, root=root, t_max=t_max, tol=tol, renorm_dt=renorm_dt, tile=tile,
                   refine=refine, refine_bound=refine_bound, early_exit=early_exit, model=model)


def _n_workers(client) -> int:
    if client is None:
        return 1
    try:
        return max(1, len(client.scheduler_info().get("workers", {})))
    except Exception:  # noqa: BLE001 - not a Client: compute_map says so when it uses it
        return 1


# ---- the CF attributes of a map: its zarr store (store.py) and ChaosMap.to_xarray() ----------------------------
UNITS = {**{k: f.unit for k, f in BY_NAME.items()}, "status": "code", "inferred": "flag", "level": "round"}
LONG = {**{k: f.long for k, f in BY_NAME.items()},
        "status": "0 ok; " + "; ".join(f"{c} {r}" for c, r in REASONS.items() if c),
        "inferred": "1: never computed, class (status, growth exponent) inferred from its refinement cell and the "
                    "indicators interpolated from the cell's corners; 0: computed",
        "level": "refinement round in which the point was computed (0 the coarse lattice); -1 inferred"}


def variable_attrs(name: str) -> dict:
    """The CF attributes of a map field (units, long_name; flag_values/flag_meanings for status): the store's and
    ChaosMap.to_xarray()'s, defined once here."""
    attrs = {"units": UNITS[name], "long_name": LONG[name]}
    if name == "status":
        attrs.update({"flag_values": list(REASONS), "flag_meanings": " ".join(REASONS.values())})
    if name == "inferred":  # a refined map's
        attrs.update({"flag_values": [0, 1], "flag_meanings": "computed inferred"})
    return attrs


def coord_attrs(name: str) -> dict:
    return {"units": "1", "long_name": _axis_label(name)}


def dataset_attrs(spec) -> dict:
    """The global attributes that describe a map (not its store's identity or the versions that wrote it)."""
    return {**({"early_exit": f"orbits stop at the first sample time t_e >= T/2 with (FLI(t_e) - FLI(T/2))/ln 2 > "
                              f"{spec.exit_above:g} (exit_time): their lyap is L(t_e)/t_e, fli, max_abs_dH, "
                              f"casimir_drift and min_stretch are over t <= t_e, growth_exponent is a lower bound "
                              f"of its value at T (classes at thresholds <= {spec.exit_above:g} unchanged)"}
               if getattr(spec, "early_exit", False) else {}),
            "title": "magrod chaos map (Sinden & van der Heijden, spatial chaos of a conducting rod)",
            "criterion": f"chaotic iff growth_exponent > {GROWTH_THRESHOLD:g}",
            "tolerance": "machine epsilon" if not spec.tol else repr(spec.tol),
            **({"formulation": "body (9-D, generated/body.py)",
                "tangent_vectors": "projected onto the level set of C1, C2, C3, H, m3 (magrod.chaos.indicators)"}
               if getattr(spec, "model", None) is None else
               {"model": str(spec.model), "formulation": "the model's body frame (its generated body.py)",
                "tangent_vectors": "projected onto the level set of H, the Casimirs and the integrals with zero "
                                   "right-hand side (magrod.chaos.indicators.model_project)"})}


def _axis_label(name: str) -> str:
    return {"lam": "lambdabar", "mu": "mu", "gamma": "gamma", "delta": "delta", "m": "m", "h": "h (energy)",
            "theta0": "theta at the start", "ptheta0": "pbar_theta at the start",
            "psi0": "psi at the start"}.get(name, f"model parameter {name}")
