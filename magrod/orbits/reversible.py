"""Symmetric homoclinic orbits of any reversible rod model, and the continuation of these orbits and of equilibria in
any of the model's parameters (pseudo-arclength, with folds).

Shooting onto Fix(R).  The model's reversor R = diag(signs) (magrod.orbits.equilibria.reversor: R f(x) = -f(R x),
H and the Casimirs preserved) fixes the equilibrium x*.  An orbit of W^u(x*) that meets Fix(R) = {x_j = 0, j
flipped} at t = T is homoclinic: its image under R is the same orbit run backwards, on W^s(x*).  For a saddle-focus
the unstable manifold near x* is a disc; its points at the launch distance delta from x* are
x*(alpha) = x* + delta Re(e^{-i alpha} v)/|Re(e^{-i alpha} v)| (v the unit unstable eigenvector, phase fixed by
core.eigen.fix_phase), so the unknowns are (alpha, T) and the residual r = (x_j(T))_{j flipped}: two unknowns and,
on a 4-D leaf (6-D models with 2 Casimirs), two equations (dim Fix(R) = half the leaf: a symmetric homoclinic orbit
of a saddle-focus is generic, a branch in every parameter).  A start is chosen by scanning alpha on the launch
circle (the point of the first excursion closest to Fix(R)); Newton then uses d r/d T = f_flipped(x(T)) exactly and
d r/d alpha by a central difference.  The second half is R x(2T - t).  Accuracy evidence: the residual (distance
from Fix(R)), the drift of H and the Casimirs along the integrated half (tol = machine epsilon), the level gap of the
launch point (O(delta^2)), and the reversor's own defect.

Continuation.  Homoclinic orbits: F(alpha, T, p) = r, the equilibrium and its eigenvector recomputed at each p on the
leaf of the start (its Casimir values held); equilibria: F(x, p) = (Q0^T f(x), C(x) - c), Q0 a basis of the leaf's
tangent space at the start.  Both are continued by magrod.orbits.continuation.pseudo_arclength (Keller's method,
folds located by regula falsi on the tangent's parameter component).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field as dc_field

import numpy as np

from ..core.errors import MissingStructure, ParameterError
from ..core.results import Result
from ..core.tolerances import EPS, ORBIT_FILE_TOL, SYMMETRIC_ORBIT_TOL
from . import model_field
from .equilibria import Equilibrium, leaf_basis, relative_equilibrium, spectrum
from .equilibria import reversor as _reversor

LAUNCH = 1e-6  # launch distance: launch error ~ delta^2 = 1e-12, rounding amplified along W^u ~ eps / delta ~ 1e-10
N_ALPHA = 48  # launch-circle samples of the start scan
RESIDUAL_TOL = SYMMETRIC_ORBIT_TOL  # Newton converged: max |x_flipped(T)| (core/tolerances.py)
FD_STEP = 1e-6


def _flow(system, x0, T, grid=None):
    ta = model_field.integrator(system)
    ta.time = 0.0
    ta.state[:] = x0
    ta.pars[:] = system.array()
    if grid is not None:
        return np.array(ta.propagate_grid(np.asarray(grid, float))[-1])
    out = ta.propagate_until(float(T))
    if out[0] != _ok():
        raise ParameterError("T", f"the integration stopped at t = {ta.time:.6g} ({out[0]})")
    return np.array(ta.state)


def _ok():
    import heyoka as hy

    return hy.taylor_outcome.time_limit


def launch(eq: Equilibrium, alpha: float, delta: float = LAUNCH) -> np.ndarray:
    """x* + delta d(alpha): the launch point on the linear unstable manifold (module docstring)."""
    v = eq.unstable_vector
    d = np.real(np.exp(-1j * alpha) * v) if np.iscomplexobj(v) else np.real(v)
    return eq.x + delta * d / np.linalg.norm(d)


def _require_saddle(eq: Equilibrium, step: str):
    if not eq.success or eq.kind not in ("saddle-focus", "saddle", "saddle-centre"):
        raise MissingStructure(eq.system.model, "a saddle", f"{step} needs a saddle, and the equilibrium of the model "
                                      f"{eq.system.model!r} found is a {eq.kind} ({eq.message})")


def _scan(system, eq, R, delta, n_alpha):
    """(alpha, T) of the launch-circle point whose first excursion passes closest to Fix(R)."""
    kappa = eq.unstable_eigenvalue.real
    t_end = (2 * math.log(1 / delta) + 16) / kappa
    grid = np.linspace(0, t_end, 801)
    best = (np.inf, 0.0, 0.0)
    complex_ = abs(eq.unstable_eigenvalue.imag) > 0
    alphas = 2 * np.pi * np.arange(n_alpha) / n_alpha if complex_ else np.array([0.0, np.pi])
    for a in alphas:
        X = _flow(system, launch(eq, a, delta), None, grid)
        dist = np.max(np.abs(X - eq.x), axis=1)
        if not np.all(np.isfinite(dist)):
            continue
        # the first excursion: the first block where the distance from x* exceeds 0.3 of its largest value
        above = dist >= 0.3 * float(np.max(dist))
        lo = int(np.argmax(above))
        hi = lo
        while hi < dist.size - 1 and above[hi + 1]:
            hi += 1
        score = np.max(np.abs(R.project(X[lo:hi + 1])), axis=1)
        j = lo + int(np.argmin(score))
        if score[j - lo] < best[0]:
            best = (float(score[j - lo]), float(a), float(grid[j]))
    return best[1], best[2]


def _residual(system, eq, R, alpha, T, delta):
    x = _flow(system, launch(eq, alpha, delta), T)
    return R.project(x), x


def _newton(system, eq, R, alpha, T, delta, tol, max_iter=25):
    mf = model_field.field(system)
    pars = system.array()
    complex_ = abs(eq.unstable_eigenvalue.imag) > 0
    best = (np.inf, alpha, T)
    for _ in range(max_iter):
        r, x = _residual(system, eq, R, alpha, T, delta)
        err = float(np.max(np.abs(r)))
        if err < best[0]:
            best = (err, alpha, T)
        elif err > 4 * best[0] and best[0] < 1e-6:
            break
        if err <= tol:
            break
        cols = [R.project(np.asarray(mf.rhs(x, pars), float))]
        if complex_:
            rp, _ = _residual(system, eq, R, alpha + FD_STEP, T, delta)
            rm, _ = _residual(system, eq, R, alpha - FD_STEP, T, delta)
            cols.insert(0, (rp - rm) / (2 * FD_STEP))
        Jm = np.stack(cols, axis=1)
        step = np.linalg.lstsq(Jm, -r, rcond=None)[0]
        # damped: T stays on the first excursion (x* itself lies on Fix(R): an undamped step can fall back to it)
        step *= min(1.0, 0.25 * T / max(abs(float(step[-1])), 1e-300), 0.5 / max(float(np.max(np.abs(step[:-1])))
                                                                                 if complex_ else 0.0, 1e-300))
        if complex_:
            alpha, T = alpha + float(step[0]), T + float(step[1])
        else:
            T = T + float(step[0])
    return best


@dataclass(repr=False)
class SymmetricOrbit(Result):
    """A symmetric (reversible) homoclinic orbit of any model: launch angle alpha and half-time T (x(T) on Fix(R)),
    launch distance, the equilibrium, the reversor, the residual max|x_flipped(T)|, the drift of (H, C) along the
    half orbit, the launch level gap; `system`; `sample(n)` gives the whole orbit on [0, 2T]."""

    success: bool
    message: str
    system: object
    equilibrium: Equilibrium  # the saddle (an Equilibrium) the orbit is homoclinic to
    reversor: object  # the reversor R whose fixed set Fix(R) the orbit crosses at its midpoint
    alpha: float  # the launch angle on the circle of radius launch_distance in the unstable plane
    T: float  # the half-time: x(T) lies on Fix(R)
    launch_distance: float  # distance of the launch point from the saddle
    x0: np.ndarray  # the launch point, shape (n,)
    x_mid: np.ndarray  # the midpoint x(T), on Fix(R)
    residual: float  # max|x_flipped(T)|: the distance of x(T) from Fix(R)
    level_drift: float  # drift of H and the Casimirs along the half orbit, relative to their terms
    launch_level_gap: float  # level difference between the launch point and the saddle (O(delta^2))
    extra: dict = dc_field(default_factory=dict)  # method-specific details (a plain dict)
    pulses: int = 1  # excursions from the saddle along the whole orbit
    noise_floor: float = 0.0  # the residual reachable in floating point at this launch distance

    _repr_fields = ("system", "pulses", "alpha", "T", "residual", "level_drift")
    kind = "equilibrium"

    @property
    def accuracy(self) -> dict:
        """residual (distance of x(T) from Fix(R)), level drift (H, Casimirs along the integration, relative to the
        terms' size), the launch level gap (O(delta^2)) and the reversor defect."""
        return {"residual": self.residual, "level_drift": self.level_drift, "launch_level_gap": self.launch_level_gap,
                "reversor_defect": self.reversor.residual,
                "passed": bool(self.residual <= RESIDUAL_TOL and self.level_drift <= 1e-12)}

    def sample(self, n: int = 2001) -> dict:
        """t (n,) on [0, 2T] and x (n, dim): the first half integrated, the second its image x(2T - t) under R."""
        n = max(3, int(n)) | 1
        h = (n + 1) // 2
        t1 = np.linspace(0.0, self.T, h)
        X1 = _flow(self.system, self.x0, None, t1)
        X2 = self.reversor.apply(X1[::-1])[1:]
        return {"t": np.concatenate([t1, 2 * self.T - t1[::-1][1:]]), "x": np.vstack([X1, X2])}

    def params_array(self) -> np.ndarray:
        return self.system.array()


def symmetric_homoclinic(system, *, equilibrium: Equilibrium | None = None, reversor=None, alpha=None, T=None,
                         delta: float = LAUNCH, tol: float | None = None, n_alpha: int = N_ALPHA) -> SymmetricOrbit:
    """A symmetric homoclinic orbit to the system's saddle (default: the straight twisted rod,
    magrod.orbits.equilibria.straight_rod) by shooting onto Fix(R) of the model's reversor (module docstring).
    `reversor`: which one, where the model has several (default: the first of equilibria.reversors fixing the
    equilibrium) -- at an integrable member, the one that survives the perturbation to be continued.

    Raises
    ------
    ParameterError
        "model" naming the model if it has no reversor fixing the equilibrium, or the equilibrium is no saddle.
    """
    from .equilibria import straight_rod

    eq = straight_rod(system) if equilibrium is None else equilibrium
    _require_saddle(eq, "a homoclinic orbit")
    R = _reversor(system, fixing=eq.x) if reversor is None else reversor
    tol = RESIDUAL_TOL if tol is None else float(tol)
    if alpha is None or T is None:
        a0, T0 = _scan(system, eq, R, delta, n_alpha)
        alpha = a0 if alpha is None else alpha
        T = T0 if T is None else T
    err, alpha, T = _newton(system, eq, R, float(alpha), float(T), delta, tol)
    return _orbit(system, eq, R, alpha, T, delta, tol)


def orbit_from_file(system, data: dict) -> SymmetricOrbit:
    """The symmetric orbit an orbit file records (magrod.core.io.load_model_orbit_file: the model, its parameters,
    alpha, T, the launch distance and the reversor), re-shot for `system`: the equilibrium, the reversor and the
    orbit are computed again, and the launch point must reproduce the file's to rounding.

    Raises
    ------
    ParameterError
        "model" if the file is another model's; the parameter's name if the file was computed at another value of
        it; "from" if its state or reversor is not the model's, or the orbit no longer reproduces (an edited model
        file).
    """
    from .equilibria import reversors, straight_rod

    if data["model"] != system.model:
        raise ParameterError("model", f"the orbit file is of the model {data['model']!r}, not {system.model!r}")
    file_params = dict(zip(data["param_names"], (float(v) for v in data["pars"])))
    if tuple(data["param_names"]) != tuple(system.names):
        raise ParameterError("from", f"the orbit file's parameters ({', '.join(data['param_names'])}) are not those of "
                                     f"the model {system.model!r} ({', '.join(system.names)})")
    for k, v in system.params.items():
        if file_params[k] != v:
            raise ParameterError(k, f"the orbit file was computed at {k} = {file_params[k]!r}, not {v!r}")
    mf = model_field.field(system)
    if tuple(data["state"]) != mf.state:
        raise ParameterError("from", f"the orbit file's state ({', '.join(data['state'])}) is not the model's "
                                     f"({', '.join(mf.state)})")
    eq = straight_rod(system)
    _require_saddle(eq, "the orbit file's orbit")
    match = [r for r in reversors(system) if np.allclose(r.matrix, data["reversor"], rtol=0, atol=ORBIT_FILE_TOL)]
    if not match:
        raise ParameterError("from", f"the orbit file's reversor is not one of the model {system.model!r}'s")
    o = _orbit(system, eq, match[0], data["alpha"], data["T"], data["launch_distance"], RESIDUAL_TOL)
    o.pulses = int(data["pulses"])
    x0 = np.asarray(data["x0"], float)
    gap = float(np.max(np.abs(o.x0 - x0)))
    if gap > ORBIT_FILE_TOL * (1.0 + float(np.max(np.abs(x0)))):
        raise ParameterError("from", f"the orbit file's launch point is not reproduced by the model {system.model!r} "
                                     f"(|dx0| = {gap:.2g}): the model changed since the file was written")
    o.extra["from_file"] = {"launch_point_gap": gap}
    return o


def _orbit(system, eq, R, alpha, T, delta, tol) -> SymmetricOrbit:
    mf = model_field.field(system)
    pars = system.array()
    x0 = launch(eq, alpha, delta)
    grid = np.linspace(0.0, T, 401)
    X = _flow(system, x0, None, grid)
    lv = np.array([mf.level(x, pars) for x in X])
    scale = mf.level_scale(x0, pars)
    drift = float(np.max(np.abs(lv - lv[0]) / scale))
    gap = float(np.max(np.abs(mf.level(x0, pars) - eq.level) / scale))
    xm = X[-1]
    res = float(np.max(np.abs(R.project(xm))))
    ok = res <= tol and drift <= 1e-12
    msg = (f"symmetric homoclinic orbit of the model {system.model!r}: x(T) on Fix(R), R = {R!r}, to {res:.2g}" if ok else
           f"no symmetric homoclinic orbit converged (residual {res:.3g}, drift {drift:.2g})")
    return SymmetricOrbit(bool(ok), msg, system, eq, R, float(alpha) % (2 * np.pi), float(T), float(delta), x0, xm,
                          res, drift, gap)


# ------------------------------------------------------------------------------------------------------------------
# continuation
# ------------------------------------------------------------------------------------------------------------------
def _index(system, parameter: str) -> int:
    if parameter not in system.names:
        raise ParameterError("parameter", f"must be a parameter of the model {system.model!r} "
                                          f"({', '.join(system.names)}), got {parameter!r}")
    return system.names.index(parameter)


def _at(system, parameter, value):
    """The system at parameter = value; a ParameterError (naming the parameter) outside the model's range."""
    return system.replace(**{parameter: float(value)})


def equilibrium_problem(system, eq: Equilibrium, parameter: str):
    """F(x, p) = (Q0^T f(x), C(x) - c) and its Jacobian ((n - k + k) x (n + 1)) for pseudo_arclength."""
    _index(system, parameter)
    mf = model_field.field(system)
    c = np.asarray(mf.casimirs(eq.x, system.array()), float)
    Q0 = leaf_basis(mf.cas_grad(eq.x, system.array()))
    n = mf.dim

    def F(u):
        x, p = u[:n], u[n]
        s = _at(system, parameter, p)
        pars = s.array()
        r = np.concatenate([Q0.T @ np.asarray(mf.rhs(x, pars), float), np.asarray(mf.casimirs(x, pars), float) - c])
        Jx = np.vstack([Q0.T @ mf.jac(x, pars), mf.cas_grad(x, pars)])
        h = 1e-7 * max(1.0, abs(p))
        sp, sm = _at(system, parameter, p + h).array(), _at(system, parameter, p - h).array()
        fp = np.concatenate([Q0.T @ np.asarray(mf.rhs(x, sp), float), np.asarray(mf.casimirs(x, sp), float)])
        fm = np.concatenate([Q0.T @ np.asarray(mf.rhs(x, sm), float), np.asarray(mf.casimirs(x, sm), float)])
        return r, np.column_stack([Jx, (fp - fm) / (2 * h)])

    return F


def homoclinic_problem(system, orbit: SymmetricOrbit, parameter: str):
    """F(alpha, T, p) = x_flipped(T) with the equilibrium recomputed at p on the start's leaf; Jacobian by the exact
    d/dT and central differences in alpha and p."""
    _index(system, parameter)
    mf = model_field.field(system)
    R = orbit.reversor
    eq0 = orbit.equilibrium
    c = np.asarray(mf.casimirs(eq0.x, system.array()), float)
    delta = orbit.launch_distance
    memo = {}

    def eq_at(p):
        if p not in memo:
            s = _at(system, parameter, p)
            e = relative_equilibrium(s, eq0.x, levels=c)
            if not e.success:
                raise ParameterError(parameter, f"no equilibrium on the start's leaf at {parameter} = {p:g}")
            memo[p] = e
        return memo[p]

    def res(a, T, p):
        e = eq_at(p)
        x = _flow(e.system, launch(e, a, delta), T)
        return R.project(x), x, e

    def F(u):
        a, T, p = (float(v) for v in u)
        r, x, e = res(a, T, p)
        dT = R.project(np.asarray(mf.rhs(x, e.system.array()), float))
        da = (res(a + FD_STEP, T, p)[0] - res(a - FD_STEP, T, p)[0]) / (2 * FD_STEP)
        h = 1e-6 * max(1.0, abs(p))
        dp = (res(a, T, p + h)[0] - res(a, T, p - h)[0]) / (2 * h)
        return r, np.column_stack([da, dT, dp])

    return F


def continue_equilibrium(system, eq: Equilibrium, parameter: str, *, steps: int = 20, ds: float = 0.05,
                         direction: int = 1, bounds=None, tol: float | None = None):
    """A branch of equilibria (on the start's leaf) in `parameter`, with folds (Branch: u = (x, p))."""
    from .arclength import pseudo_arclength

    k = _index(system, parameter)
    n = eq.x.size
    F = equilibrium_problem(system, eq, parameter)
    u0 = np.concatenate([eq.x, [system.values[k]]])
    tol = 1e3 * EPS * (1 + float(np.max(np.abs(eq.x)))) ** 2 if tol is None else tol
    bd = None if bounds is None else {n: tuple(float(b) for b in bounds)}
    br = pseudo_arclength(F, u0, scale=np.ones(n + 1), ds=ds, ds_max=max(ds, 0.2), steps=steps, par=n,
                          direction=direction, bounds=bd, names=(*model_field.field(system).state, parameter), tol=tol)
    br.kind, br.parameter = "equilibrium branch", parameter
    br.system = system
    return br


def continue_homoclinic(system, orbit: SymmetricOrbit, parameter: str, *, steps: int = 10, ds: float = 0.05,
                        direction: int = 1, bounds=None, tol: float | None = None):
    """A branch of symmetric homoclinic orbits in `parameter`, with folds (Branch: u = (alpha, T, p)).

    Fix(R) of codimension k > 2 (the 9-D rods: (m2, n2, e32) on a 6-D leaf) is consistent only through a further
    integral (the S^1 symmetry's), so the k conditions have rank 2 along the branch: they are continued as their
    projection U0^T r onto the two leading left singular vectors of their Jacobian at the start (for k = 2 an
    orthogonal change of basis), and every point's full residual max|P x(T)| is recomputed and reported in
    `residuals` (the evidence that the projection lost nothing)."""
    from .arclength import pseudo_arclength

    k = _index(system, parameter)
    if abs(orbit.equilibrium.unstable_eigenvalue.imag) == 0:
        raise MissingStructure(system.model, "a saddle-focus", f"continuing symmetric homoclinic orbits needs a saddle-focus (the launch "
                                      f"angle an unknown), and the model {system.model!r}'s saddle has a real "
                                      "unstable eigenvalue")
    F = homoclinic_problem(system, orbit, parameter)
    u0 = np.array([orbit.alpha, orbit.T, system.values[k]])
    _, J0 = F(u0)
    U, sv, _ = np.linalg.svd(J0)
    if sv.size < 2 or sv[1] <= 1e-8 * sv[0]:
        raise MissingStructure(system.model, "Fix(R) conditions of rank 2", f"the Fix(R) conditions of the model {system.model!r} have rank < 2 at the "
                                      "start: the branch is not a curve in (alpha, T, parameter)")
    U0 = U[:, :2]

    def F2(u):
        r, J = F(u)
        return U0.T @ r, U0.T @ J

    bd = None if bounds is None else {2: tuple(float(b) for b in bounds)}
    tol = RESIDUAL_TOL if tol is None else float(tol)
    br = pseudo_arclength(F2, u0, scale=np.array([1.0, 10.0, 1.0]), ds=ds, ds_max=max(ds, 0.2), steps=steps,
                          par=2, direction=direction, bounds=bd, names=("alpha", "T", parameter), tol=tol)
    full = np.array([float(np.max(np.abs(F(u)[0]))) for u in br.u])
    br.residuals = full
    if np.any(full > tol) and br.success:
        br.success = False
        br.message += f"; full Fix(R) residual {float(np.max(full)):.3g} > {tol:g} (the projection lost a condition)"
    br.kind, br.parameter = "symmetric homoclinic branch", parameter
    br.system = system
    return br


def spectrum_at(system, x):
    """Leaf spectrum of the system at x (a convenience for branches)."""
    return spectrum(system, x)[0]


# ------------------------------------------------------------------------------------------------------------------
# N-pulse orbits
# ------------------------------------------------------------------------------------------------------------------
EXCURSION = 0.3  # an excursion: the distance from x* above this fraction of the primary's largest distance


def _blocks(dist, thr) -> list:
    """[(lo, hi)] index ranges where dist >= thr."""
    above = dist >= thr
    out, i = [], 0
    while i < dist.size:
        if above[i]:
            j = i
            while j + 1 < dist.size and above[j + 1]:
                j += 1
            out.append((i, j))
            i = j + 1
        else:
            i += 1
    return out


def count_pulses(orbit: SymmetricOrbit, thr: float) -> tuple:
    """(excursions above thr, the closest passage to x* between two excursions: inf for one pulse)."""
    smp = orbit.sample(4001)
    dist = np.max(np.abs(smp["x"] - orbit.equilibrium.x), axis=1)
    b = _blocks(dist, thr)
    gaps = [float(np.min(dist[b[i][1]:b[i + 1][0] + 1])) for i in range(len(b) - 1)]
    return len(b), min(gaps, default=math.inf)


# a passage between pulses closer to x* than this many launch distances is the launch's level error (O(delta^2) in
# H and the Casimirs: orbits on that level pass x* at ~delta), not a multipulse orbit (the integrable rods'
# artefacts pass at ~1e-8; the anisotropic rod's 2-pulse orbits at eps = 0.02 at 6e-3)
PASSAGE_FLOOR = 1e3


def multipulse(system, max_pulses: int = 3, *, samples=None, delta: float = LAUNCH, tol=None):
    """Symmetric N-pulse homoclinic orbits (N = 1..max_pulses) to the straight twisted rod of a reversible model:
    a scan of the launch angle for the approach to Fix(R) at the orbit's middle (inside excursion (N + 1)/2 for
    odd N, between excursions N/2 and N/2 + 1 for even N), Newton from each local minimum over the angle, and
    the pulses of each converged orbit counted (excursions above EXCURSION of the primary's size).  Returns a
    MultipulseSearch (orbits: SymmetricOrbit, `.pulses`)."""
    import time

    from .equilibria import straight_rod
    from .shooting import MultipulseSearch

    t0 = time.perf_counter()
    eq = straight_rod(system)
    _require_saddle(eq, "multipulse orbits")
    if abs(eq.unstable_eigenvalue.imag) == 0:
        raise MissingStructure(system.model, "a saddle-focus", f"the multipulse search needs a saddle-focus, a complex unstable eigenvalue (the unstable "
                                      f"manifold a disc, the launch angle the unknown), and the model "
                                      f"{system.model!r}'s straight rod has a real one")
    R = _reversor(system, fixing=eq.x)
    tol = RESIDUAL_TOL if tol is None else float(tol)
    samples = 96 if samples is None else int(samples)
    kappa = eq.unstable_eigenvalue.real
    leg = (2 * math.log(1 / delta) + 16) / kappa
    alphas = 2 * np.pi * np.arange(samples) / samples
    grid = np.linspace(0, (max_pulses + 1) * leg, 400 * (max_pulses + 1) + 1)
    runs = []
    for a in alphas:
        X = _flow(system, launch(eq, a, delta), None, grid)
        dist = np.max(np.abs(X - eq.x), axis=1)
        runs.append((X, dist))
    ok = [d for _, d in runs if np.all(np.isfinite(d))]
    peak = float(np.median([np.max(d) for d in ok]))
    thr = EXCURSION * peak
    orbits, seen = [], []
    for N in range(1, max_pulses + 1):
        scores = np.full(samples, np.inf)
        times = np.zeros(samples)
        for i, (X, dist) in enumerate(runs):
            if not np.all(np.isfinite(dist)):
                continue
            b = _blocks(dist, thr)
            k = (N + 1) // 2
            if N % 2:
                if len(b) < k:
                    continue
                lo, hi = b[k - 1]
            else:
                if len(b) < k + 1:
                    continue
                lo, hi = b[k - 1][1], b[k][0]
            sc = np.max(np.abs(R.project(X[lo:hi + 1])), axis=1)
            j = int(np.argmin(sc))
            scores[i], times[i] = sc[j], grid[lo + j]
        # Newton from each local minimum of the score over the launch circle (the best 6)
        mins = [i for i in range(samples) if np.isfinite(scores[i]) and scores[i] <= scores[i - 1]
                and scores[i] <= scores[(i + 1) % samples]]
        mins = sorted(mins, key=lambda i: scores[i])[:6]
        for i in mins:
            err, a, T = _newton(system, eq, R, float(alphas[i]), float(times[i]), delta, tol)
            if not err <= tol:
                continue
            o = _orbit(system, eq, R, a, T, delta, tol)
            if not o.success:
                continue
            o.pulses, passage = count_pulses(o, thr)
            o.extra["closest_passage"] = passage
            if passage < PASSAGE_FLOOR * delta:
                continue
            key = (o.pulses, round(o.T, 6), round(o.alpha, 6))
            if o.pulses != N or any(abs(o.T - s_[1]) < 1e-6 and abs(math.remainder(o.alpha - s_[2], 2 * math.pi))
                                    < 1e-6 for s_ in seen):
                continue
            seen.append(key)
            orbits.append(o)
    orbits.sort(key=lambda o: (o.pulses, o.T))
    n = len(orbits)
    found = sorted({o.pulses for o in orbits})
    msg = (f"{n} symmetric orbit(s) to the straight rod of the model {system.model!r}, pulses {found}, for "
           f"N <= {max_pulses}")
    return MultipulseSearch(n > 0, msg, None, eq, orbits, [], max_pulses, None, time.perf_counter() - t0, [], None,
                            samples, False, system)
