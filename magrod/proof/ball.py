"""Exact conversions between balls (python-flint `arb`), rationals and the certificate's JSON strings.

A ball is stored as {"mid": exact decimal string, "rad": exact decimal string}: Arb's midpoint is a binary
floating-point number and its radius a 30-bit binary float, so both have finite decimal expansions and the
strings are *exact* (no rounding on the way to JSON).  Inputs are stored as exact rationals "p/q".  Bounds and
containment are decided in exact rational arithmetic (fractions.Fraction), never in floating point.

All rigorous work runs inside `workprec(bits)`, which sets Arb's working precision for the duration of a block
and restores it (python-flint keeps the precision in a process-wide context; nothing outlives the block).
"""
from __future__ import annotations

import contextlib
import math
from fractions import Fraction

from flint import arb, arb_mat, ctx, fmpq

DEFAULT_PREC = 128  # bits: rounding (~1e-38 relative) stays far below every truncation bound of the proof
SERIES_CAP = 64  # Arb truncates power series at ctx.cap terms (default 10): above every Taylor order used


@contextlib.contextmanager
def workprec(bits: int, cap: int = SERIES_CAP):
    """Arb working precision `bits` and power-series length cap `cap` inside the block (both restored
    afterwards, also on error)."""
    old, old_cap = ctx.prec, ctx.cap
    ctx.prec, ctx.cap = int(bits), int(cap)
    try:
        yield
    finally:
        ctx.prec, ctx.cap = old, old_cap


class InexactBall(ValueError):
    """A ball that should be an exact number is not: the working precision is too low for the value."""


def fraction(x) -> Fraction:
    """Exact rational of an int / Fraction / decimal or 'p/q' string / exact arb (radius 0)."""
    if isinstance(x, Fraction):
        return x
    if isinstance(x, int):
        return Fraction(x)
    if isinstance(x, str):
        return Fraction(x.strip())
    if isinstance(x, arb):
        if x.rad() != 0:
            raise InexactBall(f"not an exact ball: {x}")
        man, exp = x.mid().man_exp()
        man, exp = int(man), int(exp)
        return Fraction(man * 2**exp) if exp >= 0 else Fraction(man, 2 ** (-exp))
    if isinstance(x, float):
        return Fraction(x)  # exact binary value of the float
    raise TypeError(f"cannot convert {type(x).__name__} to an exact rational")


def q(x) -> arb:
    """arb of an exact rational (rounded outward at the working precision if not dyadic)."""
    f = fraction(x)
    return arb(fmpq(f.numerator, f.denominator))


def dyadic(x: float) -> arb:
    """The float x as an exact arb (every float is a dyadic rational)."""
    return q(Fraction(float(x)))


def mid_rad(x: arb) -> tuple[Fraction, Fraction]:
    """(midpoint, radius) of a ball as exact rationals."""
    return fraction(x.mid()), fraction(x.rad())


def bounds(x: arb) -> tuple:
    """[lo, hi] of a ball, exact (Fractions); (-inf, inf) for a non-finite ball."""
    if not x.is_finite():
        return -math.inf, math.inf
    m, r = mid_rad(x)
    return m - r, m + r


def decimal(f: Fraction) -> str:
    """Exact decimal string of a dyadic rational (denominator a power of two)."""
    n, d = f.numerator, f.denominator
    k = d.bit_length() - 1
    if d != 1 << k:
        raise ValueError(f"{f} is not dyadic")
    if k == 0:
        return str(n)
    digits = abs(n) * 5**k  # n / 2^k = n 5^k / 10^k
    s = str(digits).rjust(k + 1, "0")
    out = (s[:-k] + "." + s[-k:]).rstrip("0").rstrip(".")
    return ("-" if n < 0 else "") + out


def to_json(x: arb) -> dict:
    m, r = mid_rad(x)
    return {"mid": decimal(m), "rad": decimal(r)}


def from_json(d) -> arb:
    """The ball of a {"mid", "rad"} record (exact at the working precision if mid fits; else outward-rounded)."""
    if not isinstance(d, dict) or set(d) != {"mid", "rad"}:
        raise ValueError(f"a ball must be {{'mid': str, 'rad': str}}, got {d!r}")
    m, r = Fraction(str(d["mid"])), Fraction(str(d["rad"]))
    if r < 0:
        raise ValueError("negative radius")
    b = q(m)
    return arb(b.mid(), b.rad() + q(r).abs_upper()) if r else b


def json_bounds(d) -> tuple[Fraction, Fraction]:
    m, r = Fraction(str(d["mid"])), Fraction(str(d["rad"]))
    return m - r, m + r


def subset(inner: arb, outer) -> bool:
    """inner is contained in outer (an arb or a JSON ball), decided exactly."""
    lo, hi = bounds(inner)
    olo, ohi = json_bounds(outer) if isinstance(outer, dict) else bounds(outer)
    return olo <= lo and hi <= ohi


def positive(x: arb) -> bool:
    return bounds(x)[0] > 0


def negative(x: arb) -> bool:
    return bounds(x)[1] < 0


def excludes_zero(x: arb) -> bool:
    lo, hi = bounds(x)
    return lo > 0 or hi < 0


def pow_int(x, k: int):
    """x^k (k >= 0) by multiplications: python-flint's `**` returns nan for an arb ball containing 0."""
    out = arb(1)
    base = x
    while k:
        if k & 1:
            out = out * base
        k >>= 1
        if k:
            base = base * base
    return out


def interval(lo, hi) -> arb:
    """The smallest ball (at the working precision) containing the exact interval [lo, hi]."""
    lo, hi = fraction(lo), fraction(hi)
    if lo > hi:
        raise ValueError("empty interval")
    return q(lo).union(q(hi))


def hull(a: arb, b: arb) -> arb:
    return a.union(b)


def width(x: arb) -> float:
    return 2.0 * float(x.rad())


def vec(xs) -> arb_mat:
    """Column vector (arb_mat n x 1)."""
    xs = list(xs)
    return arb_mat(len(xs), 1, xs)


def entries(M: arb_mat) -> list:
    return [M[i, j] for i in range(M.nrows()) for j in range(M.ncols())]


def column(M: arb_mat) -> list:
    return [M[i, 0] for i in range(M.nrows())]


def exact_matrix(rows) -> arb_mat:
    """arb_mat of floats / rationals, every entry exact (floats are dyadic; other rationals are rounded outward)."""
    rows = [list(r) for r in rows]
    return arb_mat(len(rows), len(rows[0]), [q(Fraction(v) if isinstance(v, float) else v) for r in rows for v in r])


def mid_matrix(M: arb_mat) -> arb_mat:
    """The matrix of midpoints (exact, radius 0)."""
    return M.mid()


def to_floats(M: arb_mat):
    import numpy as np

    return np.array([[float(M[i, j].mid()) for j in range(M.ncols())] for i in range(M.nrows())])


def max_rad(xs) -> float:
    return max(float(x.rad()) for x in xs)


def meet_bounds(xs) -> tuple:
    """[lo, hi] of the intersection of the finite balls xs, exact (Fractions): each ball encloses one quantity (by
    different formulas), so the quantity lies in all of them.  Non-finite balls are skipped; (-inf, inf) if none is
    finite; ValueError if the intersection is empty (two enclosures of one quantity cannot be disjoint)."""
    bs = [bounds(x) for x in xs if x.is_finite()]
    if not bs:
        return -math.inf, math.inf
    lo, hi = max(b[0] for b in bs), min(b[1] for b in bs)
    if lo > hi:
        raise ValueError("disjoint enclosures of one quantity")
    return lo, hi
