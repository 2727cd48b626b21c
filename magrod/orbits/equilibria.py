"""Equilibria and relative equilibria of any rod model, their stability, and the model's reversor.

An equilibrium of the body-frame system x' = J(x) grad H (a rod whose strains u = dH/dm, v = dH/dn are constant
along its length: a uniform helix, the straight twisted rod its special case -- a relative equilibrium of the rod in
space) is a critical point of H on a symplectic leaf {C = c}.  On a leaf equilibria are isolated, so the leaf is
named by its Casimir values c and the equilibrium is found by Gauss-Newton on the consistent, overdetermined system

    f(x) = 0,   C(x) = c          (n + k equations, n unknowns; Jacobian [Df; grad C] of full rank n at a
                                    non-degenerate equilibrium)

with Df and grad C compiled from the model's generated expressions by hy.diff (magrod.orbits.model_field).

Stability on the leaf.  The Casimir gradients are left null vectors of Df at an equilibrium (grad C . f = 0 for all
x), so the range of Df lies in the tangent space T of the leaf and T is invariant: with Q an orthonormal basis of T,
the spectrum on the leaf is that of Q^T Df Q (basis-independent, similar matrices).  Eigenvalues are sorted by
magrod.core.eigen.order (decreasing real, then imaginary part, rounding-tolerant), eigenvectors phase-fixed by
core.eigen.fix_phase: nothing LAPACK decides reaches a result.  The classification: a complex quartet
+-a +-ib (a, b > 0) is a saddle-focus (the straight twisted rod under tension below Greenhill's load), a real pair
a saddle, an imaginary pair a centre; a zero eigenvalue on the leaf is a degenerate equilibrium (a fold).

The reversor.  A linear involution R with R f(x) = -f(R x) that preserves H and the Casimirs maps orbits to
orbits run backwards; a homoclinic orbit that meets Fix(R) is symmetric (magrod.orbits.model_homoclinic).  The
model's reversor is found among the diagonal sign matrices (the reflections of body components that rod models
have: (m2, n2, e32) -> -(m2, n2, e32) for the paper's rod and the isotropic family), checked at seeded random states
(numeric: 8 points, residual <= 1e3 eps times the terms' size) -- the fewest sign flips first, ties broken by the
state order, and one fixing the given equilibrium preferred.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field as dc_field

import numpy as np

from ..core import eigen
from ..core.errors import MissingStructure, ParameterError
from ..core.results import Result
from ..core.tolerances import EPS, HYPERBOLIC_TOL, REVERSOR_MATCH_TOL
from .model_field import field

MAX_ITER = 60


@dataclass(repr=False)
class Equilibrium(Result):
    """An equilibrium of the body-frame system (a relative equilibrium of the rod): state x (n,), its level
    (H, C1, ...), the spectrum on the symplectic leaf (n - k,), sorted (core.eigen.order), its kind
    ("saddle-focus", "saddle", "saddle-centre", "centre", "degenerate"), the leading unstable eigenvalue and its
    eigenvector in the state space (unit norm, phase fixed: core.eigen.fix_phase), the Newton residual
    max|f(x)| and the level residual; `system` (what was studied)."""

    success: bool
    message: str
    system: object
    x: np.ndarray  # the equilibrium state, shape (n,)
    level: np.ndarray  # (H, C1, ...) at x: the energy and the Casimirs
    eigenvalues: np.ndarray  # the spectrum on the symplectic leaf, shape (n - k,), sorted (core.eigen.order)
    kind: str  # "saddle-focus", "saddle", "saddle-centre", "centre" or "degenerate"
    unstable_eigenvalue: complex  # the leading unstable eigenvalue
    unstable_vector: np.ndarray  # its eigenvector in the state space (unit norm, phase fixed: core.eigen.fix_phase)
    residual: float  # the Newton residual max|f(x)|
    level_residual: float  # max|C(x) - C0|: the Casimirs at x against the leaf asked for
    iterations: int = 0  # Newton iterations taken
    extra: dict = dc_field(default_factory=dict)  # method-specific details (a plain dict)

    _repr_fields = ("system", "kind", "unstable_eigenvalue", "residual")

    @property
    def H(self) -> float:
        """The energy H at x (the level's first entry)."""
        return float(self.level[0])

    @property
    def accuracy(self) -> dict:
        """max|f(x)| (an equilibrium to rounding: <= 1e3 eps times the state's size) and the level residual."""
        scale = 1.0 + float(np.max(np.abs(self.x)))
        return {"residual": self.residual, "level_residual": self.level_residual,
                "passed": bool(self.residual <= 1e3 * EPS * scale * scale)}


def leaf_basis(G: np.ndarray) -> np.ndarray:
    """An orthonormal basis (n, n - rank) of the null space of the Casimir gradients G (k, n) (the tangent space
    of the symplectic leaf); the basis is arbitrary, only its span is used (spectra of Q^T A Q)."""
    n = G.shape[1]
    if G.size == 0:
        return np.eye(n)
    _, s, Vt = np.linalg.svd(G)
    rank = int(np.sum(s > 1e-12 * max(1.0, s[0])))
    return Vt[rank:].T


def classify(w: np.ndarray, tol: float = HYPERBOLIC_TOL) -> str:
    """The kind of an equilibrium from its spectrum on the leaf."""
    scale = max(1.0, float(np.max(np.abs(w)))) if w.size else 1.0
    re, im = np.abs(w.real) > tol * scale, np.abs(w.imag) > tol * scale
    if np.any(~re & ~im):
        return "degenerate"
    focus, real, imag = int(np.sum(re & im)), int(np.sum(re & ~im)), int(np.sum(~re & im))
    if focus and not imag:
        return "saddle-focus"
    if real and not imag and not focus:
        return "saddle"
    if (real or focus) and imag:
        return "saddle-centre"
    return "centre"


def spectrum(system, x, pars=None) -> tuple:
    """(leaf eigenvalues sorted, full Jacobian, leading eigenvalue, its phase-fixed eigenvector) at x."""
    mf = field(system)
    pars = system.array() if pars is None else pars
    A = mf.jac(x, pars)
    Q = leaf_basis(mf.cas_grad(x, pars))
    w = np.linalg.eigvals(Q.T @ A @ Q)
    w = w[eigen.order(w)]
    wf, V = np.linalg.eig(A)
    o = eigen.order(wf)
    lam = complex(wf[o[0]])
    v = eigen.fix_phase(V[:, o[0]], prefer=_prefer(mf))
    return w, A, lam, v


def _prefer(mf) -> tuple:
    """Components whose phase is fixed first (m1, then m2, n1, n2): e.g. m1 real > 0 on the unstable vector."""
    return tuple(mf.index(k) for k in ("m1", "m2", "n1", "n2") if k in mf.state)


def relative_equilibrium(system, start, *, levels=None, tol=None, max_iter: int = MAX_ITER) -> Equilibrium:
    """The equilibrium of the system's body-frame field near `start` on the leaf of Casimir values `levels`
    (default: those of `start`), by Gauss-Newton on f(x) = 0, C(x) = c (module docstring).

    Raises
    ------
    ParameterError
        "start" if it has the wrong length or is not finite.
    """
    mf = field(system)
    x = np.array(start, dtype=float)
    if x.shape != (mf.dim,) or not np.all(np.isfinite(x)):
        raise ParameterError("start", f"must be {mf.dim} finite numbers (the state {', '.join(mf.state)}) of the "
                                      f"model {system.model!r}")
    pars = system.array()
    c = np.asarray(mf.casimirs(x, pars), float) if levels is None else np.asarray(levels, float)
    tol = 1e3 * EPS if tol is None else float(tol)
    it, best = 0, np.inf
    for it in range(1, max_iter + 1):
        F = np.concatenate([np.asarray(mf.rhs(x, pars), float), np.asarray(mf.casimirs(x, pars), float) - c])
        err = float(np.max(np.abs(F)))
        scale = 1.0 + float(np.max(np.abs(x)))
        if err <= tol * scale * scale or (err >= best and it > 8):
            break
        best = min(best, err)
        Jm = np.vstack([mf.jac(x, pars), mf.cas_grad(x, pars)])
        dx = np.linalg.lstsq(Jm, -F, rcond=None)[0]
        x = x + dx
        if not np.all(np.isfinite(x)):
            break
    res = float(np.max(np.abs(np.asarray(mf.rhs(x, pars), float)))) if np.all(np.isfinite(x)) else np.inf
    lev_res = float(np.max(np.abs(np.asarray(mf.casimirs(x, pars), float) - c))) if np.isfinite(res) else np.inf
    if not np.isfinite(res):
        return Equilibrium(False, "Gauss-Newton diverged", system, x, np.full(mf.n_casimirs + 1, np.nan),
                           np.array([]), "unknown", complex(np.nan), np.full(mf.dim, np.nan), res, lev_res, it)
    w, A, lam, v = spectrum(system, x, pars)
    kind = classify(w)
    scale = 1.0 + float(np.max(np.abs(x)))
    ok = res <= 1e4 * EPS * scale * scale and lev_res <= 1e4 * EPS * scale * scale
    msg = (f"{kind} of the model {system.model!r} at |f| = {res:.2g}" if ok else
           f"no equilibrium found near the start (|f| = {res:.3g} after {it} Gauss-Newton steps)")
    return Equilibrium(bool(ok), msg, system, x, mf.level(x, pars), w, kind, lam, v, res, lev_res, it)


def straight_rod_start(system, M: float = 1.0, T: float = 1.0) -> np.ndarray:
    """The straight twisted rod as a start: m = (0, 0, M), n = (0, 0, T) (twisting moment M, tension T), e3 along
    d3 where the model has the field direction e3."""
    mf = field(system)
    if system.is_paper:
        from .equilibrium import straight_rod_state

        return straight_rod_state(system.rod)
    x = np.zeros(mf.dim)
    missing = [k for k in ("m3", "n3") if k not in mf.state]
    if missing:
        raise MissingStructure(system.model, "the body components m3, n3",
                               f"the straight twisted rod needs the body components m3, n3, and the model "
                                      f"{system.model!r} has none named {', '.join(missing)}")
    x[mf.index("m3")], x[mf.index("n3")] = M, T
    if "e33" in mf.state:
        x[mf.index("e33")] = 1.0
    return x


def straight_rod(system, *, M: float = 1.0, T: float = 1.0, tol=None) -> Equilibrium:
    """The straight twisted rod of moment M and tension T of any model, or the relative equilibrium next to it on
    the same leaf (the curved rod's uniform helix: its straight rod is the k1 = 0 member), with its stability.

    Examples
    --------
    >>> import magrod as mr
    >>> from magrod.orbits.equilibria import straight_rod
    >>> e = straight_rod(mr.System("anisotropic", B1=1, B2=1.02, C=1.5))
    >>> e.kind, e.success
    ('saddle-focus', True)
    """
    return relative_equilibrium(system, straight_rod_start(system, M, T), tol=tol)


# ------------------------------------------------------------------------------------------------------------------
# the reversor
# ------------------------------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Reversor:
    """A linear involution R with R f(x) = -f(R x), H(R x) = H(x), C(R x) = C(x) (`matrix`, n x n): a reflection of
    body components (diagonal: `signs`, `flipped` the indices with sign -1) or a reflection of the body frame
    through a plane containing d3 at angle `angle` from d1 (the same 3 x 3 reflection on every body vector).
    Fix(R) = {P x = 0}, P (`fix_rows`, k x n) an orthonormal basis of the range of I - R; `residual` the largest
    relative defect of the three identities at the test points (numeric evidence)."""

    matrix: np.ndarray
    names: tuple
    residual: float
    label: str

    @property
    def signs(self) -> tuple | None:
        """The diagonal of a diagonal reversor (None for a rotated reflection)."""
        R = self.matrix
        if np.any(R - np.diag(np.diag(R))):
            return None
        return tuple(int(v) for v in np.diag(R))

    @property
    def flipped(self) -> tuple:
        """The indices a diagonal reversor negates (empty for a rotated one)."""
        sg = self.signs
        return () if sg is None else tuple(i for i, v in enumerate(sg) if v < 0)

    @property
    def fix_rows(self) -> np.ndarray:
        A = (np.eye(len(self.names)) - self.matrix) / 2
        U, sv, _ = np.linalg.svd(A)
        P = U[:, sv > 0.5].T
        # a deterministic basis: each row's largest entry positive (core.eigen.fix_sign)
        return np.array([eigen.fix_sign(r) for r in P])

    @property
    def codim(self) -> int:
        return int(round(np.trace((np.eye(len(self.names)) - self.matrix) / 2)))

    def project(self, x) -> np.ndarray:
        """P x (x of shape (n,) or (N, n)): zero on Fix(R)."""
        return np.asarray(x, float) @ self.fix_rows.T

    def apply(self, x) -> np.ndarray:
        return np.asarray(x, float) @ self.matrix.T

    def __repr__(self) -> str:
        return f"Reversor({self.label})"


def _diagonal(signs, names, residual) -> Reversor:
    flipped = [names[i] for i, v in enumerate(signs) if v < 0]
    return Reversor(np.diag(np.asarray(signs, float)), tuple(names), residual, ", ".join("-" + k for k in flipped))


def _triples(names) -> list:
    """[(i1, i2, i3)] of the state's body vectors (x1, x2, x3 named alike: m, n, e3 ...)."""
    out = []
    for i, k in enumerate(names):
        if k.endswith("1") and k[:-1] + "2" in names and k[:-1] + "3" in names:
            out.append((i, names.index(k[:-1] + "2"), names.index(k[:-1] + "3")))
    return out


def _frame_reflection(names, angle: float) -> np.ndarray | None:
    """The reflection of every body vector through the plane containing d3 at `angle` from d1 (None if the state is
    not made of body vectors)."""
    tri = _triples(names)
    if sum(len(t) for t in tri) != len(names):
        return None
    c, s_ = np.cos(2 * angle), np.sin(2 * angle)
    Rm = np.eye(len(names))
    for i1, i2, _ in tri:
        Rm[np.ix_([i1, i2], [i1, i2])] = [[c, s_], [s_, -c]]
    return Rm


def _test_points(mf, pars, n=8) -> np.ndarray:
    rng = np.random.default_rng(20260104)  # seeded: the same test points on every machine
    return rng.uniform(-1.0, 1.0, size=(n, mf.dim))


def reversor_defect(system, signs, points=None) -> float:
    """max over test points of |R f(x) + f(R x)| and |H(R x) - H(x)|, |C(R x) - C(x)|, relative to the terms'
    size; `signs` the diagonal of R (n,) or R itself (n, n)."""
    mf = field(system)
    pars = system.array()
    X = _test_points(mf, pars) if points is None else points
    s = np.asarray(signs, float)
    Rm = np.diag(s) if s.ndim == 1 else s
    Xt = np.ascontiguousarray(X.T)  # (n, points): one batched call per function
    Xr = np.ascontiguousarray(Rm @ Xt)
    f, fr = np.asarray(mf.rhs(Xt, pars)), np.asarray(mf.rhs(Xr, pars))
    lv = np.vstack([mf.H(Xt, pars), mf.casimirs(Xt, pars)])
    lr = np.vstack([mf.H(Xr, pars), mf.casimirs(Xr, pars)])
    scale = 1.0 + np.max(np.abs(f), axis=0) + np.max(np.abs(lv), axis=0) + np.sum(Xt * Xt, axis=0)
    return float(max(np.max(np.abs(Rm @ f + fr) / scale), np.max(np.abs(lv - lr) / scale)))


REVERSOR_TOL = 1e3 * EPS


_REVERSORS: dict = {}


def reversors(system) -> list:
    """The model's reversors at the system's parameter values (`find_reversors`, cached per model and values)."""
    key = (field(system).key, system.values)
    if key not in _REVERSORS:
        _REVERSORS[key] = find_reversors(system)
    return list(_REVERSORS[key])


def find_reversors(system) -> list:
    """Every reversor of the model among the reflections of body components (diagonal sign matrices: fewest flips
    first, then by state order) and, where the state is made of body vectors and no diagonal one exists, the
    reflections of the body frame through a plane containing d3 (the angle located by a scan and golden-section
    refinement of the defect: an isotropic rod curved in a direction other than d1's)."""
    mf = field(system)
    pars = system.array()
    X = _test_points(mf, pars)
    out = []
    for k in range(1, mf.dim + 1):
        for flip in itertools.combinations(range(mf.dim), k):
            signs = np.ones(mf.dim)
            signs[list(flip)] = -1
            d = reversor_defect(system, signs, X)
            if d <= REVERSOR_TOL:
                out.append(_diagonal(signs, mf.state, d))
    if out or _frame_reflection(mf.state, 0.0) is None:
        return out
    grid = np.pi * np.arange(90) / 90
    vals = [reversor_defect(system, _frame_reflection(mf.state, a), X) for a in grid]
    for j in np.argsort(vals)[:2]:
        lo, hi = grid[j] - np.pi / 90, grid[j] + np.pi / 90
        g = (math.sqrt(5) - 1) / 2
        for _ in range(60):  # golden section on the defect (smooth, minimum 0 at a reversor): 4e-15 rad
            a, b = hi - g * (hi - lo), lo + g * (hi - lo)
            if reversor_defect(system, _frame_reflection(mf.state, a), X) < \
                    reversor_defect(system, _frame_reflection(mf.state, b), X):
                hi = b
            else:
                lo = a
        ang = 0.5 * (lo + hi) % np.pi
        Rm = _frame_reflection(mf.state, ang)
        d = reversor_defect(system, Rm, X)
        if d <= REVERSOR_TOL and not any(np.allclose(Rm, r.matrix, atol=REVERSOR_MATCH_TOL) for r in out):
            out.append(Reversor(Rm, mf.state, d, f"reflection of the body frame through the plane of d3 at "
                                                 f"{math.degrees(ang):.6g} deg from d1"))
    return out


def reversor(system, fixing=None) -> Reversor:
    """The model's reversor: the first of `reversors` (fixing the state `fixing` if given).

    Raises
    ------
    ParameterError
        "model", naming the model, if it has no reversor (fixing that state).
    """
    found = every = reversors(system)
    if fixing is not None:
        x = np.asarray(fixing, float)
        scale = 1.0 + float(np.max(np.abs(x)))
        found = [r for r in found if np.max(np.abs(r.apply(x) - x)) <= 1e3 * EPS * scale]
    if not found:
        where = " fixing the equilibrium" if every else ""
        raise MissingStructure(system.model, "a reversor", f"symmetric (reversible) orbits need a reversor, and the model "
                                      f"{system.model!r} has none{where}: no reflection of body components R with "
                                      "R f(x) = -f(R x) preserving H and the Casimirs (checked: every diagonal sign "
                                      "matrix, and every reflection of the body frame through a plane containing "
                                      "d3)")
    return found[0]
