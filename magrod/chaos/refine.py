"""Adaptive chaos maps: a coarse grid first, then only the cells whose corners disagree.

Most of a chaos map is plain regular or missing area (measured: 11.6 % of a 128^2 map chaotic, 34 % without an
energy root), and a brute-force map integrates every point for the full T.  A refined map with `levels` = L
computes

  round 0   the coarse lattice: every 2^L-th index on each axis (and the last index), i.e. cells of 2^L x 2^L
            grid steps whose corners are grid points;
  round r   every leaf cell (a cell not split so far) that is *mixed* -- the computed points in its closed box do
            not all have one class, or (with `bound`) their growth exponents span more than `bound` -- is split
            into its 2 x 2 (or 1 x 2 at an odd edge) halves, and the corners of the halves that are not computed
            yet are the points of round r.  Cells of one grid step are never split (all their points are
            computed).  Rounds end when no leaf is mixed.

The class of a point is its status if it is missing (no energy root, unphysical, left the range, failed: one
class each), else regular (growth exponent <= threshold) or chaotic.  A leaf that stays uniform has every
computed point in its box of one class; its never-computed points are *inferred*: they get that class, and their
indicator fields the bilinear interpolation of the leaf's four corners, clipped to the corners' range (so an
inferred point's class is its cell's: a convex combination of values on one side of the threshold stays on that
side); fields of an inferred missing point are NaN.  A computed point is never overwritten by an inferred one.
Checking the whole closed box (not only the corners) matters at a T-junction: a large uniform leaf next to a
refined one sees the points its neighbour computed on their shared edge, and is split if they disagree.

What a refined map can miss (conditional): a region of another class that lies strictly inside one coarse cell
without touching its corners (an island smaller than 2^L grid steps), or a thin filament crossing a cell edge
between two corners of the same class.  `bound` (refine where the growth exponent varies more than the bound)
catches some of those near a boundary; a smaller L catches more.  benchmarks/refine_vs_brute.py measures the
agreement with the brute-force map on the paper's map.

Determinism.  The rounds are a pure function of the computed values (leaves are visited in a fixed order), and a
point's values are those of the brute-force map at that point, bit for bit (heyoka's batch lanes step
independently, and every orbit starts with the same tangent vector: magrod.chaos.indicators), so a refined map is
the same for any worker count, tile order and resumption; tests/test_refine.py checks the computed points
against the brute-force map.

This module is the pure algorithm (no heyoka, no I/O): `Refinement` takes classes and values and says which
points to compute next; magrod.chaos.maps (in memory, on Dask) and magrod.store.tiles (a resumable zarr store)
drive it.
"""
from __future__ import annotations

import math

import numpy as np

from .indicators import GROWTH_THRESHOLD, OK

MAX_LEVELS = 12  # a coarse stride of 4096 grid steps: the largest axis (maps.MAX_AXIS_POINTS) in one cell
UNKNOWN = -1    # class of a point not computed


def point_class(status, growth, threshold=GROWTH_THRESHOLD) -> np.ndarray:
    """The class of computed points: 0 regular, 1 chaotic (status OK, growth exponent <= / > threshold), and
    2 + status for a missing point (one class per reason, magrod.chaos.indicators.REASONS)."""
    status = np.asarray(status).astype(np.int16)
    g = np.asarray(growth, float)
    with np.errstate(invalid="ignore"):
        chaotic = (g > threshold).astype(np.int16)
    return np.where(status == OK, chaotic, 2 + status).astype(np.int16)


def axis_breaks(n: int, stride: int) -> list:
    """Coarse lattice indices of one axis of n points: 0, stride, 2 stride, ..., and n - 1."""
    idx = list(range(0, n, stride))
    if idx[-1] != n - 1:
        idx.append(n - 1)
    return idx


def _intervals(n: int, stride: int) -> list:
    b = axis_breaks(n, stride)
    return list(zip(b[:-1], b[1:])) if len(b) > 1 else [(0, 0)]


def _halves(a: int, b: int) -> list:
    if b - a <= 1:
        return [(a, b)]
    m = (a + b) // 2
    return [(a, m), (m, b)]


class Refinement:
    """The refinement of an (ny, nx) grid with a coarse stride 2^levels (module docstring).

    Drive it with `points()` (the (iy, ix) index arrays of the current round, row-major), then `add(iy, ix, cls,
    value)` with the classes (point_class) and the values compared against `bound` (the growth exponent) of exactly
    those points, until `done`.  Then `inferred()` gives the mask of the points that were never computed and
    `infer(fields)` fills them.  `level` holds, per point, the round it was computed in (-1: not computed)."""

    def __init__(self, shape, levels: int, bound: float | None = None):
        ny, nx = (int(v) for v in shape)
        self.shape = (ny, nx)
        self.levels = int(levels)
        self.stride = 2 ** self.levels
        self.bound = None if bound is None else float(bound)
        self.cls = np.full(self.shape, UNKNOWN, np.int16)
        self.value = np.full(self.shape, np.nan)
        self.level = np.full(self.shape, -1, np.int8)
        self.round = 0
        ys, xs = _intervals(ny, self.stride), _intervals(nx, self.stride)
        # leaves that may still split (more than one grid step on some side), as (ya, yb, xa, xb), row-major
        self._leaves = [(ya, yb, xa, xb) for ya, yb in ys for xa, xb in xs]
        self._final = []  # leaves that cannot split (all their points are corners: computed)
        by, bx = axis_breaks(ny, self.stride), axis_breaks(nx, self.stride)
        mask = np.zeros(self.shape, bool)
        mask[np.ix_(by, bx)] = True
        self._pending = mask
        self._split_log = []  # per round: the leaves split after it (for tests and the benchmark)

    # -- the rounds -------------------------------------------------------------------------------------
    @property
    def done(self) -> bool:
        return not self._pending.any()

    def points(self) -> tuple:
        """(iy, ix) of the points of the current round (row-major); empty when done."""
        return np.nonzero(self._pending)

    def add(self, iy, ix, cls, value=None) -> None:
        """Record the current round's results (exactly the points() of this round) and plan the next round."""
        iy, ix = np.asarray(iy, int), np.asarray(ix, int)
        want = self._pending.copy()
        got = np.zeros(self.shape, bool)
        got[iy, ix] = True
        if iy.size != int(want.sum()) or not np.array_equal(got, want):
            raise ValueError("add() takes exactly the points of the current round")
        self.cls[iy, ix] = np.asarray(cls, np.int16)
        if value is not None:
            self.value[iy, ix] = np.asarray(value, float)
        self.level[iy, ix] = min(self.round, np.iinfo(np.int8).max)
        self._pending[:] = False
        self._plan()
        self.round += 1

    def _mixed(self, leaf) -> bool:
        ya, yb, xa, xb = leaf
        box = self.cls[ya:yb + 1, xa:xb + 1]
        c = box[box != UNKNOWN]
        if c.size and c.min() != c.max():
            return True
        if self.bound is not None and c.size and c[0] in (0, 1):
            v = self.value[ya:yb + 1, xa:xb + 1][box != UNKNOWN]
            v = v[np.isfinite(v)]
            if v.size and float(v.max() - v.min()) > self.bound:
                return True
        return False

    def _plan(self) -> None:
        keep, split = [], []
        for leaf in self._leaves:
            if self._mixed(leaf):
                split.append(leaf)
                ya, yb, xa, xb = leaf
                for cy in _halves(ya, yb):
                    for cx in _halves(xa, xb):
                        child = (cy[0], cy[1], cx[0], cx[1])
                        for y in cy:
                            for x in cx:
                                if self.cls[y, x] == UNKNOWN:
                                    self._pending[y, x] = True
                        (keep if (cy[1] - cy[0] > 1 or cx[1] - cx[0] > 1) else self._final).append(child)
            else:
                keep.append(leaf)
        keep.sort()  # a fixed order whatever the history
        self._leaves = keep
        self._split_log.append(split)

    # -- after the last round -----------------------------------------------------------------------------
    def leaves(self) -> list:
        """Every leaf (ya, yb, xa, xb), inclusive index bounds, that may contain inferred points."""
        return list(self._leaves)

    def split_cells(self) -> list:
        """Per round, the leaves split after it (the cells found to be mixed)."""
        return [list(s) for s in self._split_log]

    def inferred(self) -> np.ndarray:
        """Mask of the points never computed (the refinement must be done)."""
        return self.cls == UNKNOWN

    def infer(self, fields: dict, float_keys) -> dict:
        """Fill the never-computed points of `fields` ({name: (ny, nx) array}, "status" int8) from their leaf:
        status from the leaf's class, the float fields `float_keys` by bilinear interpolation of the leaf's four
        corners clipped to their range (NaN for a missing class).  Computed points are left as they are.  Leaves
        are filled largest first, so that a point on the edge of two leaves takes the finer one's interpolation."""
        if not self.done:
            raise ValueError("the refinement is not finished")
        out = {k: np.array(v, copy=True) for k, v in fields.items()}
        unknown = self.cls == UNKNOWN
        order = sorted(self._leaves, key=lambda lf: (-(lf[1] - lf[0]) * (lf[3] - lf[2]), lf))
        for ya, yb, xa, xb in order:
            sub = unknown[ya:yb + 1, xa:xb + 1]
            if not sub.any():
                continue
            corners = [(ya, xa), (ya, xb), (yb, xa), (yb, xb)]
            c = int(self.cls[ya, xa])
            jy, jx = np.nonzero(sub)
            gy, gx = jy + ya, jx + xa
            out["status"][gy, gx] = OK if c in (0, 1) else c - 2
            ty = (gy - ya) / (yb - ya) if yb > ya else np.zeros(gy.size)
            tx = (gx - xa) / (xb - xa) if xb > xa else np.zeros(gx.size)
            for k in float_keys:
                if c not in (0, 1):
                    out[k][gy, gx] = np.nan
                    continue
                f00, f01, f10, f11 = (float(fields[k][y, x]) for y, x in corners)
                v = (1 - ty) * ((1 - tx) * f00 + tx * f01) + ty * ((1 - tx) * f10 + tx * f11)
                lo, hi = min(f00, f01, f10, f11), max(f00, f01, f10, f11)
                out[k][gy, gx] = np.clip(v, lo, hi)
        return out


def check_levels(levels, shape=None) -> int:
    """`refine` as a number of levels: an integer in [1, MAX_LEVELS]; ParameterError("refine") otherwise."""
    from ..core.errors import ParameterError

    try:
        f = float(levels)
    except (TypeError, ValueError):
        raise ParameterError("refine", f"must be an integer number of levels in 1..{MAX_LEVELS}, got {levels!r}"
                             ) from None
    if isinstance(levels, bool) or not math.isfinite(f) or f != int(f) or not 1 <= f <= MAX_LEVELS:
        raise ParameterError("refine", f"must be an integer number of levels in 1..{MAX_LEVELS}, got {levels!r}")
    return int(f)
