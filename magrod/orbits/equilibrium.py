"""The saddle: the straight twisted rod aligned with the field, in the singularity-free body frame.

At the numeric scale of derive/numeric_scale.py (B = C = m3 = 1, C2 = 1/m^2, 2 C1 = (mu + 1)/m^4, lambda =
lambdabar/m^4) the straight rod m = (0, 0, 1), n = (0, 0, 1/m^2), e3 = (0, 0, 1) is an equilibrium of the 9-D
system, and it lies on the Casimir level of the Euler chart iff C1 = n3^2/2 + lambda m3, i.e. iff mu = 2 lambdabar.
There the radicand mu - 2 lambdabar pbar_psi of eq:canonical_force vanishes (pbar_psi = 1) and theta = 0: the
chart is singular exactly at the saddle, which is why everything here is done in (m, n, e3).

Spectrum (Jacobian of x' = J grad H from heyoka's symbolic differentiation, hy.diff): three zeros (Casimirs),
one centre pair +-i w and a complex quartet +-a +-i b.  The rotations about the body 3-axis (phi shifts,
derive/symmetry.py) fix the saddle, so its 2-D unstable eigenspace is a single complex line on which they act
as the phase: the unstable manifold is ONE orbit modulo this symmetry (see magrod.orbits.shooting).

For mu != 2 lambdabar the straight rod is off the chart's level and the saddle-type set is a periodic orbit of
the body frame (a uniform helix, paper sec. 3): magrod.orbits.periodic.  Both implement the saddle protocol of
magrod.orbits.shooting (params, H, kind, launch_point, at), which the one shooting engine uses."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core import eigen, systems
from ..core.errors import ParameterError
from ..core.params import RodParams
from ..core.precision import Precision
from ..core.results import Result
from ..core.systems import body_functions, state_index
from ..core.tolerances import HYPERBOLIC_TOL, MU_TOL
from ..generated import scalars


_E31 = state_index("body", "e31")


def jacobian(x, pars) -> np.ndarray:
    """Jacobian (n x n) of the body-frame vector field at x (symbolic derivatives compiled by heyoka)."""
    x = np.asarray(x, float)
    return body_functions()["jacobian"](x, pars).reshape(x.size, x.size)


def straight_rod_state(params: RodParams, precision=Precision.DOUBLE) -> np.ndarray:
    """The straight rod (generated scalars.straight_rod_state) computed in `precision` arithmetic (1/m^2 is
    rounded there, not in double)."""
    precision = Precision.parse(precision)
    fp, bits = precision.fp_type, precision.prec
    return systems.fp_array(scalars.straight_rod_state(*systems.fp_array(params.array(), fp, bits)), fp, bits)


def is_on_level(params: RodParams) -> bool:
    """True iff mu = 2 lam (generated straight_rod_mu) to MU_TOL (64 ulp, relative above 1: the rounding of a
    decimal input): the one test of which saddle exists, used by `straight_rod`, magrod.orbits.shooting.saddle,
    magrod.orbits.periodic and the splitting of the separatrix alike."""
    gap = params.mu - scalars.straight_rod_mu(**params.to_dict())
    return abs(gap) <= MU_TOL * max(1.0, abs(params.mu))


OFFSETS = ("working", "double")  # how a launch offset launch_distance d is rounded (StraightRod.launch_point)


def launch_offset(d, launch_distance, precision: Precision, offset: str = "working") -> np.ndarray:
    """launch_distance d (d a float64 unit vector) in `precision`: offset "working" forms the product there (launch_distance and d
    converted first), "double" forms it in float64 and converts the result.  The eigenvector is a float64
    quantity either way, so both are launches at the launch distance to rounding; the splitting of the separatrix
    (magrod.separatrix.splitting) uses "double", the convention its REPORT.md digits were measured with (the long
    double runs see the difference at their noise level, ~1e-9 relative), everything else "working"."""
    if offset not in OFFSETS:
        raise ParameterError("offset", f"must be one of {OFFSETS}, got {offset!r}")
    fp, bits = precision.fp_type, precision.prec
    if offset == "double":
        return systems.fp_array(launch_distance * d, fp, bits)
    if precision in (Precision.DOUBLE, Precision.LONG_DOUBLE):
        return fp(launch_distance) * d.astype(fp)
    return systems._fp(fp, launch_distance, bits) * systems.fp_array(d, fp, bits)


def on_level(params: RodParams, **changes) -> RodParams:
    """params with `changes` and mu on the straight rod's level (generated straight_rod_mu: mu = 2 lam), where the
    straight rod is the saddle: the one helper that moves a parameter with mu following it."""
    kw = {**params.to_dict(), **{k: float(v) for k, v in changes.items()}}
    kw["mu"] = scalars.straight_rod_mu(**kw)
    return RodParams(**kw)


@dataclass(frozen=True, repr=False)
class StraightRod(Result):
    """The straight rod as the saddle (mu = 2 lam): state x (9,), Jacobian (9, 9), eigenvalues (9,), the unstable
    eigenvalue a + i b (a > 0, b >= 0), its complex eigenvector (unit norm, phase fixed so that its e31 entry is
    real > 0), and the level H = H_body - offset (the chart's Hbar); `precision`: the working precision of its
    launch points (the state is computed there, `straight_rod_state`; the eigen-data are float64 in every
    precision).  Implements the saddle protocol of magrod.orbits.shooting (kind "equilibrium": the launch angle
    is a symmetry direction); the one straight-rod saddle of magrod, the separatrix's included."""

    params: RodParams
    x: np.ndarray  # the straight rod state, shape (9,)
    jacobian: np.ndarray  # the Jacobian of the body field there, shape (9, 9)
    eigenvalues: np.ndarray  # its eigenvalues, shape (9,)
    unstable_eigenvalue: complex  # a + i b, a > 0, b >= 0
    unstable_vector: np.ndarray  # its complex eigenvector (unit norm, phase fixed: the e31 entry real > 0)
    H: float  # the level H = H_body - offset (the chart's Hbar)
    success: bool = True
    message: str = "straight rod: a hyperbolic equilibrium on the chart's level (mu = 2 lam)"
    precision: Precision = Precision.DOUBLE
    system: object = field(default=None, compare=False)  # what was studied (set by magrod.orbits.shooting.saddle)

    kind = "equilibrium"
    _repr_fields = ("kind", "params", "unstable_eigenvalue", "H")

    def launch_point(self, launch_distance: float, angle: float = 0.0, precision=None, *, offset: str = "working") -> np.ndarray:
        """x_eq + launch_distance Re(e^{-i angle} v)/|Re(e^{-i angle} v)|: a point at the launch distance on the linear unstable
        manifold, formed in `precision` (default: the saddle's; x_eq computed there too, so that it is exact in
        that arithmetic; the O(launch_distance^2) error of the linearisation is the launch error).  The angle is a symmetry
        direction: the rotations about the body 3-axis act on the unstable plane as this phase.  offset: how launch_distance d
        is rounded ("working" or "double", `launch_offset`)."""
        pr = self.precision if precision is None else Precision.parse(precision)
        d = np.real(np.exp(-1j * angle) * self.unstable_vector)
        d = d / np.linalg.norm(d)
        return straight_rod_state(self.params, pr) + launch_offset(d, launch_distance, pr, offset)

    def at(self, params: RodParams) -> "StraightRod":
        """The straight-rod saddle at other parameters, in the same precision (ParameterError where there is
        none)."""
        return straight_rod(params, precision=self.precision)

    @property
    def accuracy(self) -> dict:
        """The accuracy achieved (nothing is integrated): the eigenpair residual |J v - lambda v| of the unstable
        eigenvector (unit norm; passed: <= 1e3 eps |J|, the backward error of a LAPACK eigenpair)."""
        v, lam = self.unstable_vector, self.unstable_eigenvalue
        res = float(np.max(np.abs(self.jacobian @ v - lam * v)))
        return {"eigen_residual": res,
                "passed": bool(res <= 1e3 * np.finfo(float).eps * max(1.0, float(np.linalg.norm(self.jacobian, 2))))}

    def summary(self) -> dict:
        lam_u = self.unstable_eigenvalue
        return {"state": self.x.tolist(), "H": self.H,
                "eigenvalues": [[float(z.real), float(z.imag)] for z in self.eigenvalues],
                "unstable_eigenvalue": [float(lam_u.real), float(lam_u.imag)]}


def straight_rod(params: RodParams, *, precision=Precision.DOUBLE) -> StraightRod:
    """The saddle at `params` (requires mu = 2 lam to MU_TOL, `is_on_level`, and a hyperbolic straight rod;
    ParameterError otherwise), its launch points formed in `precision` by default."""
    p = params
    precision = Precision.parse(precision)
    mu_level = scalars.straight_rod_mu(**p.to_dict())
    if not is_on_level(p):
        raise ParameterError("mu", f"the straight rod is the saddle only at mu = 2 lam (got mu = {p.mu}, 2 lam = "
                                   f"{mu_level}): for mu > 2 lam the saddle is the periodic (helical) one, "
                                   "magrod.orbits.periodic.periodic_saddle (or magrod.orbits.shooting.saddle, which "
                                   "chooses)")
    pars = p.array()
    x = straight_rod_state(p)
    # equilibrium and Casimir level, to rounding
    f = body_functions()
    scale = max(1.0, 1.0 / p.m**4)
    cas = f["casimirs"](x, pars) - f["casimir_values"]([], pars)
    if np.max(np.abs(cas)) > 64 * np.finfo(float).eps * scale * (1 + abs(p.lam)):
        raise ParameterError("mu", f"straight rod is not on the chart's Casimir level (residuals {cas})")
    Jm = jacobian(x, pars)
    w, V = np.linalg.eig(Jm)
    o = eigen.order(w)  # largest real part first, then b >= 0 before the conjugate: no eigen-solver decides
    w, V = w[o], V[:, o]
    k = 0
    if w[k].real <= HYPERBOLIC_TOL:
        mc = scalars.m_critical(p.gamma) if p.gamma > -1 else float("nan")
        raise ParameterError("m", f"no saddle: the straight rod is not hyperbolic at these parameters (max Re "
                                  f"eigenvalue {w[k].real:.3g}); at lam = 0 this is m >= m_c = 2 sqrt(1 + gamma) = "
                                  f"{mc:.6g} (eq:buckling_load_2)")
    # the eigenvector of the simple eigenvalue a + ib is one of the rotation generator xi too, so its phase is
    # a rotation G_a of the symmetry: e31 real > 0 picks the representative (core.eigen.fix_phase)
    v = eigen.fix_phase(V[:, k], prefer=(_E31,))
    H = float(f["H"](x, pars)[0])
    return StraightRod(p, x, Jm, w, complex(w[k]), v, H, precision=precision)
