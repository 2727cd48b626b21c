"""Chaos maps: indicators over a parameter plane or a section, tile by tile (issue 11).

A map is a `MapSpec` (two `Axis` objects, the base values of every other parameter and start value, tolerances);
it is cut into tiles (one Dask task and one zarr chunk each, magrod/chaos/store.py); `compute_tile` is a pure
function of (spec, tile).  Indicators and the chaos criterion come from magrod/chaos/indicators.py.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from ..core import systems
from ..core.errors import MAX_MAGNITUDE, ParameterError, require_finite, require_positive_int
from ..core.params import RodParams
from ..generated.names import BODY_STATE, PARAMS
from .indicators import (_KEYS, DEFAULT_RENORM_DT, FAILED, GROWTH_THRESHOLD, NO_ROOT, OK, REASONS, UNPHYSICAL,
                         body_indicators)


# ----------------------------------------------------------------------------------------------------------
START = ("h", "theta0", "ptheta0", "psi0")
AXIS_NAMES = tuple(PARAMS) + START
DEFAULT_PANEL = "4a"
DEFAULT_TILE = 16


@dataclass(frozen=True)
class Axis:
    """A grid axis: n points linspace(lo, hi, n) of one parameter (PARAMS) or start value (START)."""

    name: str
    lo: float
    hi: float
    n: int

    def values(self) -> np.ndarray:
        return np.linspace(self.lo, self.hi, self.n)


MAX_AXIS_POINTS = 4096  # 4096^2 orbits at ~5 ms each is a day on 2 cores: the largest map worth refusing later


def parse_axis(option: str, text: str) -> Axis:
    """NAME:LO:HI:N -> Axis; ParameterError(option, ...) on an unknown name, non-finite bounds, an empty range
    (LO >= HI with N > 1, or LO != HI with N = 1) or N not a positive integer."""
    parts = str(text).split(":")
    if len(parts) != 4:
        raise ParameterError(option, f"expected NAME:LO:HI:N (e.g. lam:0:0.3:128), got {text!r}")
    name, lo, hi, n = parts
    if name not in AXIS_NAMES:
        raise ParameterError(option, f"unknown parameter {name!r}; choose from {', '.join(AXIS_NAMES)}")
    lo, hi = require_finite(option, lo, MAX_MAGNITUDE), require_finite(option, hi, MAX_MAGNITUDE)
    try:
        nf = float(n)
    except ValueError:
        raise ParameterError(option, f"number of points must be a positive integer, got {n!r}") from None
    if not math.isfinite(nf) or nf != int(nf) or nf < 1:
        raise ParameterError(option, f"number of points must be a positive integer, got {n!r}")
    n = int(nf)
    if n > MAX_AXIS_POINTS:
        raise ParameterError(option, f"at most {MAX_AXIS_POINTS} points per axis, got {n}")
    if (n > 1 and not lo < hi) or (n == 1 and lo != hi):
        raise ParameterError(option, f"empty range {lo:g}..{hi:g} with {n} point(s): need LO < HI (or LO = HI "
                                     f"with N = 1)")
    return Axis(name, lo, hi, n)


@dataclass(frozen=True)
class MapSpec:
    """Everything that determines a chaos map (the store's identity: a resumed run must match it).

    base: values of PARAMS and START for every point (a paper panel, see panel_base), overridden by the axes.
    root: which root pbar_psi of Hbar = h starts the orbit ("smallest", the poincare default, or "largest").
    tol 0 = machine epsilon.  tile: tile edge in grid points (one Dask task and one zarr chunk per tile)."""

    x: Axis
    y: Axis
    base: dict = field(default_factory=dict)
    panel: str | None = DEFAULT_PANEL
    root: str = "smallest"
    t_max: float = 3000.0
    tol: float = 0.0
    renorm_dt: float = DEFAULT_RENORM_DT
    tile: int = DEFAULT_TILE
    batch_size: int = 0

    def __post_init__(self):
        if self.x.name == self.y.name:
            raise ParameterError("y", f"must vary a different parameter than --x (both {self.x.name!r})")
        t = require_finite("t_max", self.t_max)
        if t <= 0:
            raise ParameterError("t_max", f"must be > 0, got {self.t_max}")
        if require_finite("tol", self.tol) < 0:
            raise ParameterError("tol", f"must be >= 0 (0 = machine epsilon), got {self.tol}")
        if require_finite("renorm_dt", self.renorm_dt) <= 0:
            raise ParameterError("renorm_dt", f"must be > 0, got {self.renorm_dt}")
        require_positive_int("tile", self.tile)
        if self.root not in ("smallest", "largest"):
            raise ParameterError("root", f"must be 'smallest' or 'largest', got {self.root!r}")
        missing = [k for k in AXIS_NAMES if k not in self.base and k not in (self.x.name, self.y.name)]
        if missing:
            raise ParameterError(missing[0], "no value: give it or choose a --panel")
        if not self.batch_size:
            object.__setattr__(self, "batch_size", systems.recommended_batch_size())

    @property
    def shape(self) -> tuple:
        return (self.y.n, self.x.n)

    def as_dict(self) -> dict:
        d = asdict(self)
        d["base"] = {k: float(v) for k, v in sorted(self.base.items())}
        return d

    @classmethod
    def from_dict(cls, d: dict) -> "MapSpec":
        d = dict(d)
        d["x"], d["y"] = Axis(**d["x"]), Axis(**d["y"])
        return cls(**d)

    def point(self, ix: int, iy: int) -> dict:
        v = dict(self.base)
        v[self.x.name] = float(self.x.values()[ix])
        v[self.y.name] = float(self.y.values()[iy])
        return v


def panel_base(key: str) -> dict:
    """PARAMS and START values of a paper panel (magrod.chaos.section.PANELS)."""
    from ..core.printed import PANELS

    if key not in PANELS:
        raise ParameterError("panel", f"unknown panel {key!r}; choose from {', '.join(PANELS)}")
    pk = PANELS[key]
    return {**pk["params"].as_dict(), "h": pk["h"], "theta0": pk["theta0"], "ptheta0": pk["ptheta0"],
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


@dataclass(frozen=True)
class Tile:
    iy: int
    ix: int
    ys: slice
    xs: slice

    @property
    def key(self) -> str:
        return f"{self.iy}_{self.ix}"


def tiles(spec: MapSpec) -> list[Tile]:
    """The grid cut into tile x tile blocks, row-major; the same on every machine and for any worker count."""
    t = spec.tile
    return [Tile(iy, ix, slice(iy * t, min((iy + 1) * t, spec.y.n)), slice(ix * t, min((ix + 1) * t, spec.x.n)))
            for iy in range(math.ceil(spec.y.n / t)) for ix in range(math.ceil(spec.x.n / t))]


MAP_FIELDS = _KEYS + ("p_psi0",)


def compute_tile(spec: MapSpec, tile: Tile) -> dict:
    """Indicators of every grid point of one tile: {field: (ny_t, nx_t) float64 array, "status": int8 array}.
    Pure function of (spec, tile): the unit of work of a Dask task and of a zarr chunk."""
    iys = range(tile.ys.start, tile.ys.stop)
    ixs = range(tile.xs.start, tile.xs.stop)
    pts = [spec.point(ix, iy) for iy in iys for ix in ixs]
    starts = [start_point(v, spec.root) for v in pts]
    x0 = np.array([s[0] for s in starts]).T
    p = np.array([s[1] for s in starts]).T
    st0 = np.array([s[2] for s in starts], np.int8)
    ind = body_indicators(np.nan_to_num(x0), np.nan_to_num(p, nan=1.0), t_max=spec.t_max, tol=spec.tol or None,
                          renorm_dt=spec.renorm_dt, batch_size=spec.batch_size, valid=st0 == OK)
    shape = (len(iys), len(ixs))
    out = {k: getattr(ind, k).reshape(shape) for k in _KEYS}
    out["p_psi0"] = np.array([s[3] for s in starts]).reshape(shape)
    out["status"] = np.where(st0 == OK, ind.status, st0).astype(np.int8).reshape(shape)
    return out


@dataclass(frozen=True)
class MapResult:
    """A whole map in memory: fields (ny, nx) as in compute_tile, plus the spec and wall time."""

    spec: MapSpec
    fields: dict
    wall_s: float

    def summary(self, threshold=GROWTH_THRESHOLD) -> dict:
        return map_summary(self.spec, self.fields, self.wall_s, threshold)


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
            "t_max": spec.t_max, "wall_s": wall_s, "orbits_per_s": st.size / wall_s if wall_s > 0 else None}


def empty_fields(spec: MapSpec) -> dict:
    f = {k: np.full(spec.shape, np.nan) for k in MAP_FIELDS}
    f["status"] = np.full(spec.shape, FAILED, np.int8)
    return f


def chaos_map(spec: MapSpec, *, progress=None) -> MapResult:
    """The whole map in this process (tests, the figure builder, small maps); the CLI spreads the same tiles
    over Dask workers and a zarr store instead (magrod.chaos.store).  progress(n) is called per tile."""
    import time

    t0 = time.perf_counter()
    fields = empty_fields(spec)
    for tile in tiles(spec):
        res = compute_tile(spec, tile)
        for k, v in res.items():
            fields[k][tile.ys, tile.xs] = v
        if progress is not None:
            progress(1)
    return MapResult(spec, fields, time.perf_counter() - t0)


def panel_indicators(keys=("4a", "4b", "4c", "4d"), *, t_max=3000.0, tol=None, root="smallest") -> dict:
    """{panel: dict of the indicators of the paper's orbit} (one batch).  Cost ~t_max * 5 us per panel."""
    starts = [start_point(panel_base(k), root) for k in keys]
    ind = body_indicators(np.array([s[0] for s in starts]).T, np.array([s[1] for s in starts]).T, t_max=t_max,
                          tol=tol)
    return {k: {f: (float(getattr(ind, f)[i]) if f != "status" else REASONS[int(ind.status[i])]) for f in
                _KEYS + ("status",)} | {"chaotic": bool(ind.chaotic[i])} for i, k in enumerate(keys)}
