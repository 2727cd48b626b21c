"""The periodic saddle for mu != 2 lambdabar: the helical relative equilibrium, its monodromy matrix and Floquet
multipliers (paper sec. 3: "a periodic solution in the four-dimensional system").

Geometry (derive/floquet.py, report entries `relative_equilibrium`, `floquet_straight_rod`).  The rotations G_a
about the body 3-axis (phi -> phi - a, derive/symmetry.py) commute with the flow.  For mu != 2 lambdabar the
straight rod is off the chart's Casimir level; the saddle-type set on the level is a *relative equilibrium*
x(t) = G_{omega t} x0 -- a uniform helix, periodic in the body frame with period T = 2 pi/|omega| and an
equilibrium (theta_eq, psi = 0, pbar_theta = 0, pbar_psi_eq) of the reduced 4-D system, on Fix(R).  Near the
straight rod it exists for mu > 2 lambdabar only (theta_eq^2 ~ mu - 2 lambdabar; the branch is born from the
straight rod's centre pair +-i w, omega -> -w as mu -> 2 lambdabar).

It is computed by Gauss-Newton on (x0, omega) for
    f(x0) - omega xi x0 = 0,  C_i(x0) = chart values,  m3 = 1 (= p_phi),  e32 = 0 (phase on the G-orbit),
with xi the generator of G_a (14 equations, 10 unknowns, consistent), started on the straight rod's centre
eigenvector and, if needed, continued in mu from mu = 2 lambdabar.

Monodromy.  M = d x(T)/d x(0) from heyoka's variational equations (systems.cached_variational).  Because
Phi_t(x0) = G_{omega t} x0, d Phi_t(x0) = G_{omega t} exp(t A) with A = Df(x0) - omega xi (the Jacobian in the
co-rotating frame), so M = exp(T A): an independent check (`exp_check`).  Multipliers on the 6-D symplectic
leaf: 1, 1 (the G-direction = flow direction and the conserved m3), and a quartet Lambda, 1/Lambda, conj (a
saddle-focus, |Lambda| = exp(a T)) while the reduced equilibrium is hyperbolic; the three Casimir directions
give three more multipliers 1.  M is a Poisson map: M J(x0) M^T = J(x0) (`symplectic_defect`).  The quartet
meets the unit circle at the Hamiltonian-Hopf boundary (at mu = 2 lambdabar in closed form, derive/floquet.py).

Cost: one Gauss-Newton solve (~10 evaluations of compiled functions) and one variational integration over one
period (~5 ms).  Nothing here mutates anything but the per-thread cached integrator.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field

import numpy as np

from ..core import eigen, systems
from ..core.errors import ParameterError
from ..core.params import RodParams
from ..core.precision import Precision
from ..core.results import Result
from ..core.tolerances import HYPERBOLIC_TOL, RELATIVE_EQUILIBRIUM_TOL
from ..generated import floquet as gfl
from ..generated import scalars
from .equilibrium import is_on_level, launch_offset

N = systems.dim("body")
NC = systems.n_casimirs()  # the Casimirs C1, C2, C3 (systems.body_casimir_gradients: NC x N)
XI = np.array(gfl.ROTATION_GENERATOR, dtype=float).reshape(N, N)
# the relative-equilibrium equations: f(x) - omega xi x (N), Casimirs (NC), m3 = 1, e32 = 0; unknowns (x, omega)
N_EQUATIONS, N_UNKNOWNS = N + NC + 2, N + 1


def _poisson_matrix(x, lam_body):
    """J(x; lambda) of eq:noncanonical_structure (structure matrix of derive/model.py), from the generated
    function, for the symplecticity check."""
    return np.asarray(gfl.structure_matrix(*x, lam_body), dtype=float).reshape(N, N)


def _re_equations(z, pars, cv):
    F = systems.body_functions()
    x, w = z[:N], z[N]
    i_m3, i_e32 = systems.state_index("body", "m3"), systems.state_index("body", "e32")
    r = np.r_[F["rhs"](x, pars) - w * XI @ x, F["casimirs"](x, pars) - cv, x[i_m3] - 1.0, x[i_e32]]
    J = np.zeros((N_EQUATIONS, N_UNKNOWNS))
    J[:N, :N] = F["jacobian"](x, pars).reshape(N, N) - w * XI
    J[:N, N] = -XI @ x
    J[N:N + NC, :N] = systems.body_casimir_gradients()(x, pars).reshape(NC, N)
    J[N + NC, i_m3] = 1.0
    J[N + NC + 1, i_e32] = 1.0
    return r, J


def _gauss_newton(z, pars, max_iter=40):
    cv = systems.body_functions()["casimir_values"]([], pars)
    res = math.inf
    for _ in range(max_iter):
        r, J = _re_equations(z, pars, cv)
        res = float(np.max(np.abs(r)))
        if not np.isfinite(res):
            break
        dz = np.linalg.lstsq(J, -r, rcond=None)[0]
        z = z + dz
        if np.max(np.abs(dz)) <= 4 * np.finfo(float).eps * max(1.0, np.max(np.abs(z))):
            r, _ = _re_equations(z, pars, cv)
            return z, float(np.max(np.abs(r)))
    return z, res


def _straight_rod_centre(params: RodParams):
    """Straight rod state, its centre frequency w > 0 and the real part of the centre eigenvector, on the
    phase slice of the relative equilibrium (e32 = 0, e31 > 0).

    The straight rod is fixed by the rotations G_a, and its Jacobian commutes with their generator xi, so the
    eigenvector of the simple eigenvalue +i w is an eigenvector of xi as well: multiplying it by e^{i a} is the
    rotation G_{+-a}.  LAPACK returns it with an arbitrary such factor (its largest component real; here |e31|
    = |e32| by the symmetry, so rounding picks one: BLAS kernels differ).  Making the e31 component real and positive
    (core.eigen.fix_phase) picks the representative whose real part has e32 = 0: the slice Gauss-Newton
    imposes.  The real part of any other phase is a rotated guess, up to a useless one (e31 = 0) at a = pi/2."""
    pars = params.array()
    x = np.array(scalars.straight_rod_state(*pars))
    Jm = systems.body_functions()["jacobian"](x, pars).reshape(N, N)
    w, V = np.linalg.eig(Jm)
    k = int(np.argmax(np.where(np.abs(w.real) < 1e-8, w.imag, -np.inf)))
    v = eigen.fix_phase(V[:, k], prefer=(systems.state_index("body", "e31"), systems.state_index("body", "m1"),
                                         systems.state_index("body", "n1")))
    d = np.real(v)
    return x, float(w[k].imag), d / np.linalg.norm(d)


def relative_equilibrium(params: RodParams, *, tol: float = RELATIVE_EQUILIBRIUM_TOL):
    """(x0 (9,), omega, residual): the helical relative equilibrium f(x0) = omega xi x0 on the chart's Casimir
    level, phase fixed by e32 = 0, e31 <= 0 (phi = 0).  Raises ParameterError if none is found near the
    straight rod (mu < 2 lambdabar, or too far from it)."""
    p = params
    pars = p.array()
    mu_level = scalars.straight_rod_mu(**p.to_dict())  # mu = 2 lam: the straight rod on the chart's level
    delta_mu = p.mu - mu_level
    if delta_mu <= 0 or is_on_level(p):
        raise ParameterError("mu", f"no periodic saddle near the straight rod for mu <= 2 lam (got mu - 2 lam = "
                                   f"{delta_mu:.3g}); at mu = 2 lam the saddle is the straight rod itself "
                                   "(magrod.orbits.equilibrium)")
    x_eq, w, d = _straight_rod_centre(p)
    best = (None, math.inf)
    for sgn in (-1.0, 1.0):
        z0 = np.r_[x_eq + sgn * math.sqrt(delta_mu) * d, -w]
        z, res = _gauss_newton(z0, pars)
        if res <= tol:
            best = (z, res)
            break
        if res < best[1]:
            best = (z, res)
    if best[1] > tol:
        # homotopy in mu from just above 2 lam
        z = None
        for s in np.linspace(0.05, 1.0, 20):
            q = p.replace(mu=mu_level + s * delta_mu)
            z0 = z if z is not None else np.r_[x_eq - math.sqrt(s * delta_mu) * d, -w]
            z, res = _gauss_newton(z0, q.array())
            if res > tol:
                break
        best = (z, res)
    z, res = best
    if z is None or res > tol:
        raise ParameterError("mu", f"no periodic saddle (helical relative equilibrium) found at {p.to_dict()} "
                                   f"(Gauss-Newton residual {res:.2e})")
    x0 = z[:N].copy()
    if x0[systems.state_index("body", "e31")] > 0:  # G_pi: the same orbit, the phi = 0 representative
        x0 = _rotation_by_pi() @ x0
    return x0, float(z[N]), res


@dataclass(frozen=True)
class ChartEquilibrium:
    """The periodic saddle seen in the reduced chart: q = (theta0, psi = 0, pbar_theta = 0, pbar_psi0) on Fix(R),
    an equilibrium of the chart's vector field, in a working precision (`precision`); `residual` = max |chart
    field| at q; the unstable eigenvalue (largest real part, Im >= 0) and unit eigenvector (theta entry real > 0,
    core.eigen.fix_phase) of the chart Jacobian, float64 in every precision.  It is a saddle-focus of the chart: its
    unstable manifold is 2-D, parametrised by the phase on the unstable eigenplane (the separatrix's launch)."""

    q: np.ndarray
    precision: Precision
    residual: float
    eigenvalue: complex
    vector: np.ndarray


CHART_NEWTON_ITERATIONS = 60  # the chart Newton converges quadratically from the leading-order tilt in < 10


def chart_equilibrium(params: RodParams, precision=Precision.DOUBLE) -> ChartEquilibrium:
    """The tilted straight rod (the helical relative equilibrium, mu > 2 lam) as an equilibrium of the reduced
    chart, computed by Newton in `precision` on (theta, pbar_psi) for psi' = pbar_theta' = 0 at psi = pbar_theta = 0
    (there theta' = pbar_psi' = 0 by the reversibility), from the leading-order tilt theta0 = sqrt(mu - 2 lam).
    Newton stops at a zero residual or a step below 1e-3 ulp of the precision (relative to 1 + theta0).
    ParameterError("mu") if mu is not above 2 lam (`is_on_level`), ("m") if the equilibrium is not hyperbolic."""
    precision = Precision.parse(precision)
    fp, bits = precision.fp_type, precision.prec
    F = systems.splitting_functions(fp, bits)
    pars = params.array()
    mu_level = scalars.straight_rod_mu(**params.to_dict())  # mu = 2 lam
    if params.mu - mu_level <= 0 or is_on_level(params):
        raise ParameterError("mu", f"the tilted straight rod exists for mu > 2 lam only (got mu - 2 lam = "
                                   f"{params.mu - mu_level:.3g}); at mu = 2 lam the saddle is the straight rod")
    th0 = math.sqrt(params.mu - mu_level)  # leading order: the tilt of the force from the field
    q = systems.fp_array([th0, 0.0, 0.0, math.cos(th0)], fp, bits)
    nq = systems.dim("reduced")
    for _ in range(CHART_NEWTON_ITERATIONS):
        r = F["reduced_rhs"](q, pars)
        Jm = F["reduced_jacobian"](q, pars).reshape(nq, nq)
        A = np.array([[float(Jm[i, j]) for j in (0, 3)] for i in (1, 2)])
        rr = np.array([float(r[1]), float(r[2])])
        res = float(np.max(np.abs(rr)))
        step = np.linalg.solve(A, -rr)
        q[0] += systems.fp_array([step[0]], fp, bits)[0]
        q[3] += systems.fp_array([step[1]], fp, bits)[0]
        if res == 0.0 or np.max(np.abs(step)) < 1e-3 * 2.0 ** -(113 if bits is None else bits) * (1 + th0):
            break
    r = F["reduced_rhs"](q, pars)
    res = float(max(abs(float(v)) for v in r))
    Jm = np.array([float(v) for v in F["reduced_jacobian"](q, pars)]).reshape(nq, nq)
    w, V = np.linalg.eig(Jm)
    k = int(eigen.order(w)[0])  # largest real part, then Im >= 0: no eigen-solver decides
    if w[k].real <= HYPERBOLIC_TOL:
        raise ParameterError("m", f"the tilted straight rod is not hyperbolic (eigenvalues {w})")
    v = eigen.fix_phase(V[:, k], prefer=(0,))  # theta entry real > 0, whatever LAPACK's phase
    return ChartEquilibrium(q, precision, res, complex(w[k]), v)


def _rotation_by_pi() -> np.ndarray:
    """G_pi = expm(pi xi) (the rotation by pi about the body 3-axis, acting on every body vector of the state):
    diag(-1, -1, 1) on each of m, n, e3, from the generated generator (exact up to rounding, then rounded)."""
    from scipy.linalg import expm

    return np.round(expm(math.pi * XI))


@dataclass(frozen=True, repr=False)
class PeriodicSaddle(Result):
    """The helical relative equilibrium and its Floquet data; implements the saddle protocol of
    magrod.orbits.shooting (kind "periodic": the launch angle on the unstable plane is a genuine unknown).

    x (9,): point of the periodic orbit with e32 = 0 (phi = 0); omega: rotation rate (x(t) = G_{omega t} x);
    period T = 2 pi/|omega|; monodromy (9, 9) = d x(T)/d x(0); multipliers (9,) (eigenvalues of the monodromy);
    exponents (9,): eigenvalues of the co-rotating Jacobian A = Df(x) - omega xi; unstable_multiplier Lambda
    (|Lambda| > 1, Im >= 0) and its unit eigenvector (phase fixed: the largest |component| of the first
    eigenvector real > 0... see `_phase_fix`); chart = (theta, psi, phi, pbar_theta, pbar_psi) of x;
    H = H_body - offset (the chart's Hbar); closure = |x(T) - x|; exp_check = |M - expm(T A)|/|M|;
    symplectic_defect = |M J M^T - J|/(|M|^2 |J|); reciprocal_defect = max over the quartet of
    |Lambda_i Lambda_j - 1| for its reciprocal partners.  precision: the working precision of its launch points
    and of its chart view (`chart`: the same relative equilibrium as an equilibrium q of the reduced chart,
    computed in that precision: `chart_view`, `q`, `chart_eigenvalue`, `chart_vector`).  The one tilted/periodic saddle of
    magrod: the separatrix's a > 2b splitting launches from its chart view (frame="chart")."""

    params: RodParams
    x: np.ndarray  # point of the periodic orbit with e32 = 0 (phi = 0), shape (9,)
    omega: float  # rotation rate: x(t) = G_{omega t} x
    T: float  # period 2 pi/|omega|
    monodromy: np.ndarray  # d x(T)/d x(0), shape (9, 9)
    multipliers: np.ndarray  # eigenvalues of the monodromy, shape (9,)
    exponents: np.ndarray  # eigenvalues of the co-rotating Jacobian Df(x) - omega xi, shape (9,)
    unstable_multiplier: complex  # Lambda, |Lambda| > 1, Im >= 0
    unstable_vector: np.ndarray  # its unit eigenvector, phase fixed
    chart: np.ndarray  # (theta, psi, phi, pbar_theta, pbar_psi) of x
    H: float  # H_body - offset: the chart's Hbar
    re_residual: float  # Gauss-Newton residual of the relative-equilibrium equations
    closure: float  # |x(T) - x|
    exp_check: float  # |M - expm(T A)|/|M|: the monodromy against the co-rotating exponential
    symplectic_defect: float  # |M J M^T - J|/(|M|^2 |J|)
    reciprocal_defect: float  # max |Lambda_i Lambda_j - 1| over the quartet's reciprocal partners
    hyperbolic: bool  # max Re of the exponents > HYPERBOLIC_TOL: multipliers off the unit circle
    success: bool = True
    message: str = "periodic saddle: the helical relative equilibrium (mu > 2 lam)"
    precision: Precision = Precision.DOUBLE
    system: object = field(default=None, compare=False)  # what was studied (set by magrod.orbits.shooting.saddle)

    kind = "periodic"
    _repr_fields = ("kind", "params", "T", "unstable_multiplier", "H", "hyperbolic")

    @property
    def quartet(self) -> np.ndarray:
        """The four nontrivial multipliers (largest |log|Lambda|| first)."""
        return _quartet(self.multipliers)

    @property
    def accuracy(self) -> dict:
        """The accuracy achieved: the Gauss-Newton residual of the relative equilibrium (passed: <=
        RELATIVE_EQUILIBRIUM_TOL), the closure |x(T) - x| of the integrated period, the monodromy against
        expm(T A), its symplectic defect and the reciprocal pairing of the quartet."""
        return {"re_residual": self.re_residual, "closure": self.closure, "exp_check": self.exp_check,
                "symplectic_defect": self.symplectic_defect, "reciprocal_defect": self.reciprocal_defect,
                "passed": bool(self.re_residual <= RELATIVE_EQUILIBRIUM_TOL)}

    @functools.cached_property
    def chart_view(self) -> ChartEquilibrium:
        """The chart view in the saddle's precision (`chart_equilibrium`; computed once, on first use)."""
        return chart_equilibrium(self.params, self.precision)

    @property
    def q(self) -> np.ndarray:
        """The chart equilibrium (theta0, 0, 0, pbar_psi0) in the saddle's precision."""
        return self.chart_view.q

    @property
    def chart_eigenvalue(self) -> complex:
        """The unstable eigenvalue of the same relative equilibrium as an equilibrium of the reduced chart."""
        return self.chart_view.eigenvalue

    @property
    def chart_vector(self) -> np.ndarray:
        """Its eigenvector in the reduced chart."""
        return self.chart_view.vector

    def launch_point(self, launch_distance: float, angle: float = 0.0, precision=None, *, offset: str = "working",
                     frame: str = "body") -> np.ndarray:
        """A point on the linear unstable manifold at launch distance and angle `angle`, formed in `precision`
        (default: the saddle's; the O(launch_distance^2) error of the linearisation is the launch error).

        frame "body": x + launch_distance Re(e^{-i angle} v)/|.| on the unstable fibre of the periodic orbit at phase 0 (v the
        monodromy's eigenvector; x the double-precision relative equilibrium, exact in every wider type).  The
        angle is a genuine unknown of the shooting problem (module docstring of magrod.orbits.shooting).
        frame "chart": the body state of q + launch_distance theta0 Re(e^{-i angle} v_c)/|.| (q the chart equilibrium in
        `precision`, v_c its unstable eigenvector; the distance is relative to the tilt theta0), on the chart's
        linear unstable manifold: the launch of the separatrix's splitting.
        offset: how the offset is rounded ("working" or "double", magrod.orbits.equilibrium.launch_offset)."""
        pr = self.precision if precision is None else Precision.parse(precision)
        fp, bits = pr.fp_type, pr.prec
        if frame == "chart":
            ch = self.chart_view if pr is self.precision else chart_equilibrium(self.params, pr)
            d = np.real(np.exp(-1j * angle) * ch.vector)
            q = ch.q + launch_offset(d / np.linalg.norm(d), launch_distance * float(ch.q[0]), pr, offset)
            return systems.splitting_functions(fp, bits)["to_body"](q, self.params.array())
        if frame != "body":
            raise ParameterError("frame", f"must be 'body' or 'chart', got {frame!r}")
        d = np.real(np.exp(-1j * angle) * self.unstable_vector)
        if pr is Precision.DOUBLE and offset == "working":
            return self.x + launch_distance * d / np.linalg.norm(d)
        return systems.fp_array(self.x, fp, bits) + launch_offset(d / np.linalg.norm(d), launch_distance, pr, offset)

    def at(self, params: RodParams) -> "PeriodicSaddle":
        """The periodic saddle at other parameters, in the same precision (ParameterError where there is none)."""
        return periodic_saddle(params, precision=self.precision)

    def summary(self) -> dict:
        q = self.quartet
        return {"params": self.params.to_dict(), "x": self.x.tolist(), "omega": self.omega, "T": self.T,
                "chart": dict(zip(("theta", "psi", "phi", "ptheta", "ppsi"), self.chart.tolist())), "H": self.H,
                "multipliers": [[float(z.real), float(z.imag)] for z in self.multipliers],
                "quartet_abs": [float(abs(z)) for z in q],
                "unstable_multiplier": [self.unstable_multiplier.real, self.unstable_multiplier.imag],
                "re_residual": self.re_residual, "closure": self.closure, "exp_check": self.exp_check,
                "symplectic_defect": self.symplectic_defect, "reciprocal_defect": self.reciprocal_defect,
                "hyperbolic": self.hyperbolic}


def _quartet(mult) -> np.ndarray:
    """The four multipliers off the unit circle, in an order no eigen-solver decides: largest |log|Lambda||
    first (the quartet shares it), then |Lambda| > 1 before its reciprocal, then Im >= 0 before the conjugate."""
    mult = np.asarray(mult, complex)
    g = np.log(np.abs(mult))
    top = np.argsort(-np.abs(g), kind="stable")[:4]
    q = mult[top]
    return q[eigen.order(np.log(q))]


def _phase_fix(v):
    """Unit norm, e31 component real > 0 (as magrod.orbits.equilibrium does for the straight rod), so that the
    launch angle varies smoothly with the parameters and never with LAPACK's phase (core.eigen.fix_phase; the
    next non-negligible component if e31 vanishes)."""
    return eigen.fix_phase(v, prefer=(systems.state_index("body", "e31"),))


def monodromy(x0, pars, T, precision=Precision.DOUBLE, as_float: bool = True):
    """d x(T)/d x(0) along the orbit of x0 (heyoka variational equations, tol = eps of the precision); returns
    (x(T), M) (float64 unless as_float=False)."""
    precision = Precision.parse(precision)
    ta = systems.cached_variational(precision)
    ftype = precision.fp_type
    systems.reset_variational(ta, np.asarray(x0, dtype=ftype), np.asarray(pars, dtype=ftype))
    ta.propagate_until(ftype(T))
    if not as_float:
        n = ta.n_orig_sv
        D = np.asarray(ta.state[ta.get_vslice(order=1)]).reshape(n, len(ta.vargs))
        return np.array(ta.state[:n]), D[:, :n].copy()
    x, Phi, _ = systems.variational_blocks(ta)
    return x.astype(float), Phi


def reciprocal_defect_backward(ps: "PeriodicSaddle", precision=Precision.LONG_DOUBLE) -> float:
    """Reciprocal pairing checked with the backward monodromy M_b = d x(-T)/d x(0) = M^{-1}, integrated
    independently: spec(M) is closed under z -> 1/z iff the dominant (unstable) multipliers of M and M_b
    coincide.  Returns max |Lambda_i(M)/Lambda_i(M_b) - 1| over the two unstable members of the quartet
    (eigenvalues of dominant modulus are computed to ~eps relative; the small ones of M directly are not: their
    absolute error ~ eps |M| makes the product test of `reciprocal_defect` ~ eps |Lambda|^2).  Measured: exactly
    0 -- the backward integration of this reversible system returns R M R to the last bit, so this checks the
    reversing symmetry of the computed monodromy rather than the eigen-solver."""
    pars = ps.params.array()
    _, M = monodromy(ps.x, pars, ps.T, precision=precision)
    _, Mb = monodromy(ps.x, pars, -ps.T, precision=precision)

    def top2(A):
        ev = np.linalg.eigvals(A)
        ev = ev[np.argsort(-np.abs(ev))][:2]
        return ev[np.argsort(ev.imag)]

    a, b = top2(M), top2(Mb)
    return float(np.max(np.abs(a / b - 1.0)))


def periodic_saddle(params: RodParams, *, require_hyperbolic: bool = True, precision=Precision.DOUBLE) -> PeriodicSaddle:
    """The periodic saddle at `params` (mu > 2 lambdabar) with its monodromy and Floquet multipliers (float64),
    its launch points and chart view formed in `precision` by default.
    ParameterError if there is no relative equilibrium near the straight rod, or (require_hyperbolic) if its
    nontrivial multipliers lie on the unit circle (beyond the Hamiltonian-Hopf boundary, e.g. m >= m_c)."""
    from scipy.linalg import expm

    p = params
    precision = Precision.parse(precision)
    pars = p.array()
    x0, omega, res = relative_equilibrium(p)
    T = 2 * math.pi / abs(omega)
    xT, M = monodromy(x0, pars, T)
    A = systems.body_functions()["jacobian"](x0, pars).reshape(N, N) - omega * XI
    expo = np.linalg.eigvals(A)
    expo = expo[eigen.order(expo)]
    mult, V = np.linalg.eig(M)
    o = eigen.order(mult)  # a stored order no eigen-solver decides
    mult, V = mult[o], V[:, o]
    k = int(np.argmax(np.abs(mult) + 1e-300 * np.sign(mult.imag)))
    cand = [i for i in range(N) if abs(abs(mult[i]) - abs(mult[k])) <= 1e-9 * abs(mult[k]) and mult[i].imag >= 0]
    k = cand[0] if cand else k
    hyper = bool(np.max(expo.real) > HYPERBOLIC_TOL)
    if require_hyperbolic and not hyper:
        mc = scalars.m_critical(p.gamma) if p.gamma > -1 else float("nan")
        raise ParameterError("m", f"no saddle: the periodic orbit is not hyperbolic at these parameters (max "
                                  f"Re exponent {np.max(expo.real):.3g}); beyond the Hamiltonian-Hopf boundary "
                                  f"(at lam = 0: m >= m_c = {mc:.6g})")
    Jx = _poisson_matrix(x0, p.lam / p.m**4)
    nM = np.linalg.norm(M, 2)
    sym = float(np.linalg.norm(M @ Jx @ M.T - Jx, 2) / (nM**2 * np.linalg.norm(Jx, 2)))
    # reciprocal partners within the quartet (the multipliers off the unit circle)
    q = _quartet(mult)
    rec = max(float(np.min(np.abs(q * qi - 1.0))) for qi in q) if hyper else float(
        max(np.min(np.abs(mult * mi - 1.0)) for mi in mult))
    chart = systems.body_to_euler(x0, pars)
    H = float(systems.body_functions()["H"](x0, pars)[0])
    return PeriodicSaddle(p, x0, omega, T, M, mult, expo, complex(mult[k]), _phase_fix(V[:, k]), np.asarray(chart),
                          H, res, float(np.max(np.abs(xT - x0))),
                          float(np.linalg.norm(M - expm(T * A), 2) / nM), sym, rec, hyper, precision=precision)


def hamiltonian_hopf_scan(params: RodParams, name: str, values) -> dict:
    """max Re of the co-rotating exponents (= log|Lambda|/T) along `values` of one parameter: the quartet meets
    the imaginary axis where it drops to 0 (Hamiltonian-Hopf).  Returns arrays values, growth (nan where no
    relative equilibrium was found)."""
    out = np.full(len(values), np.nan)
    for i, v in enumerate(values):
        try:
            q = params.replace(**{name: float(v)})
            x0, omega, _ = relative_equilibrium(q)
        except ParameterError:
            continue
        A = systems.body_functions()["jacobian"](x0, q.array()).reshape(N, N) - omega * XI
        out[i] = float(np.max(np.linalg.eigvals(A).real))
    return {"values": np.asarray(values, float), "growth": out}
