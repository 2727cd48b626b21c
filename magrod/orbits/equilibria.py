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
from dataclasses import dataclass, field as dc_field

import numpy as np

from ..core import eigen
from ..core.errors import ParameterError
from ..core.results import Result
from ..core.tolerances import EPS, HYPERBOLIC_TOL
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
    x: np.ndarray
    level: np.ndarray
    eigenvalues: np.ndarray
    kind: str
    unstable_eigenvalue: complex
    unstable_vector: np.ndarray
    residual: float
    level_residual: float
    iterations: int = 0
    extra: dict = dc_field(default_factory=dict)

    _repr_fields = ("system", "kind", "unstable_eigenvalue", "residual")

    @property
    def H(self) -> float:
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
        raise ParameterError("model", f"the straight twisted rod needs the body components m3, n3, and the model "
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
    start = straight_rod_start(system, M, T)
    if system.is_paper:
        return relative_equilibrium(system, start, tol=tol)
    return relative_equilibrium(system, start, tol=tol)


# ------------------------------------------------------------------------------------------------------------------
# the reversor
# ------------------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Reversor:
    """A linear involution R = diag(signs) with R f(x) = -f(R x), H(R x) = H(x), C(R x) = C(x): `flipped` the
    indices with sign -1 (Fix(R) = {x_j = 0, j in flipped}); `residual` the largest relative defect of the three
    identities at the test points (numeric evidence)."""

    signs: tuple
    names: tuple
    residual: float

    @property
    def flipped(self) -> tuple:
        return tuple(i for i, s in enumerate(self.signs) if s < 0)

    @property
    def matrix(self) -> np.ndarray:
        return np.diag(np.asarray(self.signs, float))

    def __repr__(self) -> str:
        return f"Reversor({', '.join('-' + self.names[i] for i in self.flipped)})"


def _test_points(mf, pars, n=8) -> np.ndarray:
    rng = np.random.default_rng(20260104)  # seeded: the same test points on every machine
    return rng.uniform(-1.0, 1.0, size=(n, mf.dim))


def reversor_defect(system, signs, points=None) -> float:
    """max over test points of |R f(x) + f(R x)| and |H(R x) - H(x)|, |C(R x) - C(x)|, relative to the terms'
    size."""
    mf = field(system)
    pars = system.array()
    X = _test_points(mf, pars) if points is None else points
    s = np.asarray(signs, float)
    Xt = np.ascontiguousarray(X.T)  # (n, points): one batched call per function
    Xr = s[:, None] * Xt
    f, fr = np.asarray(mf.rhs(Xt, pars)), np.asarray(mf.rhs(Xr, pars))
    lv = np.vstack([mf.H(Xt, pars), mf.casimirs(Xt, pars)])
    lr = np.vstack([mf.H(Xr, pars), mf.casimirs(Xr, pars)])
    scale = 1.0 + np.max(np.abs(f), axis=0) + np.max(np.abs(lv), axis=0) + np.sum(Xt * Xt, axis=0)
    return float(max(np.max(np.abs(s[:, None] * f + fr) / scale), np.max(np.abs(lv - lr) / scale)))


REVERSOR_TOL = 1e3 * EPS


def reversors(system) -> list:
    """Every diagonal-sign reversor of the model (fewest flips first, then by state order)."""
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
                out.append(Reversor(tuple(int(v) for v in signs), mf.state, d))
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
        found = [r for r in found if np.max(np.abs(np.asarray(r.signs) * x - x)) <= 1e3 * EPS * scale]
    if not found:
        where = " fixing the equilibrium" if every else ""
        raise ParameterError("model", f"symmetric (reversible) orbits need a reversor, and the model "
                                      f"{system.model!r} has none{where}: no reflection of body components R with "
                                      "R f(x) = -f(R x) preserving H and the Casimirs (checked: every diagonal sign "
                                      "matrix)")
    return found[0]
