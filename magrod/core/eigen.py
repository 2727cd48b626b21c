"""Eigenpairs that do not depend on the machine.

LAPACK (numpy's and scipy's `eig`) returns eigenvalues in an order of its own and each eigenvector up to an
arbitrary unit factor: it scales a complex eigenvector so that its *largest* component is real, and when two
components are equal in modulus -- as the S^1 symmetry makes |e31| = |e32| at the straight rod -- the last bit
of rounding, which differs between CPUs and BLAS kernels, decides which (on an AVX-512 machine the
periodic saddle's start guess became the wrong real part and Gauss-Newton failed).  Nothing in magrod may
depend on that choice, so every eigenvector magrod uses is put through one of these rules first:

- `fix_phase(v, prefer)`: unit norm, and the first component of `prefer` (state indices in order of
  preference) whose modulus is not negligible made real and positive.  With an S^1-equivariant matrix the
  phase factor of an eigenvector is a rotation of the symmetry group, so this picks the representative on
  a slice of the group orbit (e.g. e31 real: Re v has e32 = 0).
- `fix_sign(v)`: a real vector with its first non-negligible component positive.
- `order(w, key)`: a stable, rounding-tolerant order of eigenvalues (ties within `tol` broken by the next key).

tests/test_portability.py runs the saddle, orbit and splitting computations with every `eig` result multiplied
by random unit phases and its eigenpairs permuted, and asserts the same answers.
"""
from __future__ import annotations

import numpy as np

from .tolerances import EIGEN_TIE_TOL

# a component below this fraction of the largest one is "negligible": its phase is rounding noise
NEGLIGIBLE = 1e-3


def _reference(a, prefer) -> int:
    """The first index of `prefer`, then of all indices, whose modulus is not negligible (>= NEGLIGIBLE max)."""
    floor = NEGLIGIBLE * a.max()
    for j in (*prefer, *range(a.size)):
        if a[j] >= floor:
            return j
    raise ValueError("zero vector")  # unreachable for a normalised vector


def fix_phase(v, prefer=()) -> np.ndarray:
    """v / |v| times the unit factor that makes component j real and > 0, for j the first index of `prefer`
    with |v_j| >= NEGLIGIBLE max|v| (then the remaining indices in order).  Independent of v's phase."""
    v = np.asarray(v, complex)
    v = v / np.linalg.norm(v)
    return v * np.exp(-1j * np.angle(v[_reference(np.abs(v), prefer)]))


def fix_sign(v, prefer=()) -> np.ndarray:
    """A real vector with component j > 0 (j as in `fix_phase`), unit norm."""
    v = np.asarray(v, float)
    v = v / np.linalg.norm(v)
    return v if v[_reference(np.abs(v), prefer)] > 0 else -v


def order(w, *, tol: float = EIGEN_TIE_TOL) -> np.ndarray:
    """Indices sorting eigenvalues w by decreasing real part, then decreasing imaginary part, where values that
    agree to tol (relative to max(1, |w|)) count as equal, so that rounding cannot swap members of a symmetric
    set (a conjugate pair, a quartet); exact ties keep a deterministic order by the next key."""
    w = np.asarray(w, complex)
    scale = max(1.0, float(np.max(np.abs(w)))) * tol
    re = np.round(w.real / scale)
    im = np.round(w.imag / scale)
    return np.lexsort((-im, -re))
