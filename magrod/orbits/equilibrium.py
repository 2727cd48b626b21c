"""The saddle: the straight twisted rod aligned with the field, in the singularity-free body frame.

At the numeric scale of derive/numeric_scale.py (B = C = m3 = 1, C2 = 1/m^2, 2 C1 = (mu + 1)/m^4, lambda =
lambdabar/m^4) the straight rod m = (0, 0, 1), n = (0, 0, 1/m^2), e3 = (0, 0, 1) is an equilibrium of the 9-D
system, and it lies on the Casimir level of the Euler chart iff C1 = n3^2/2 + lambda m3, i.e. iff mu = 2 lambdabar.
There the radicand mu - 2 lambdabar pbar_psi of eq:canonical_force vanishes (pbar_psi = 1) and theta = 0: the
chart is singular exactly at the saddle, which is why everything here is done in (m, n, e3).

Spectrum (Jacobian of x' = J grad H from heyoka's symbolic differentiation, hy.diff): three zeros (Casimirs),
one centre pair +-i w and a complex quartet +-a +-i b.  The rotations about the body 3-axis (phi shifts,
derive/symmetry.py) fix the saddle, so its 2-D unstable eigenspace is a single complex line on which they act
as the phase: the unstable manifold is ONE orbit modulo this symmetry (see magrod/shooting.py).

For mu != 2 lambdabar the saddle-type set is a periodic orbit of the reduced system (paper sec. 3, "a periodic
solution in the four-dimensional system"); that case is not implemented and raises ParameterError."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.errors import ParameterError
from ..generated import scalars
from ..core.params import RodParams
from ..core.systems import body_functions, state_index

# mu = 2 lam is a condition on the input; accept the rounding of a decimal input, nothing more
MU_TOL = 64 * np.finfo(float).eps
# Re(eigenvalue) below this is not hyperbolic: the Jacobian is computed to ~eps, eigenvalues of the
# (defective at m = m_c) quartet split like sqrt(eps)
HYPERBOLIC_TOL = 1e3 * np.sqrt(np.finfo(float).eps)


_E31 = state_index("body", "e31")


def jacobian(x, pars) -> np.ndarray:
    """Jacobian (n x n) of the body-frame vector field at x (symbolic derivatives compiled by heyoka)."""
    x = np.asarray(x, float)
    return body_functions()["jacobian"](x, pars).reshape(x.size, x.size)


def straight_rod_state(params: RodParams, fp_type=float) -> np.ndarray:
    """The straight rod (generated scalars.straight_rod_state) in fp_type arithmetic."""
    return np.array(scalars.straight_rod_state(*[fp_type(v) for v in params.array()]), dtype=fp_type)


@dataclass(frozen=True)
class Saddle:
    """The straight rod: state x (9,), Jacobian (9, 9), eigenvalues (9,), the unstable eigenvalue a + i b
    (a > 0, b >= 0), its complex eigenvector (unit norm, phase fixed so that its e31 entry is real > 0), and the
    level Hbar = H_body - offset (the chart's Hbar)."""

    params: RodParams
    x: np.ndarray
    jacobian: np.ndarray
    eigenvalues: np.ndarray
    unstable_eigenvalue: complex
    unstable_vector: np.ndarray
    H: float

    def launch_point(self, eps: float, phase: float = 0.0, fp_type=float) -> np.ndarray:
        """x_eq + eps * Re(e^{-i phase} v) / |Re(...)|: a point at distance eps on the linear unstable manifold
        (the O(eps^2) error of the linearisation is the launch error; fp_type np.longdouble keeps x_eq exact
        in extended precision)."""
        d = np.real(np.exp(-1j * phase) * self.unstable_vector)
        d = (d / np.linalg.norm(d)).astype(fp_type)
        return straight_rod_state(self.params, fp_type) + fp_type(eps) * d

    def summary(self) -> dict:
        lam_u = self.unstable_eigenvalue
        return {"state": self.x.tolist(), "H": self.H,
                "eigenvalues": [[float(z.real), float(z.imag)] for z in self.eigenvalues],
                "unstable_eigenvalue": [float(lam_u.real), float(lam_u.imag)]}


def straight_rod(params: RodParams) -> Saddle:
    """The saddle at `params` (requires mu = 2 lam and a hyperbolic straight rod; ParameterError otherwise)."""
    p = params
    mu_level = scalars.straight_rod_mu(**p.as_dict())
    if abs(p.mu - mu_level) > MU_TOL * max(1.0, abs(p.mu)):
        raise ParameterError("mu", f"only mu = 2 lam is supported (got mu = {p.mu}, 2 lam = {mu_level}): for "
                                   "mu != 2 lam the straight rod aligned with the field is not on the chart's "
                                   "Casimir level and the saddle-type set is a periodic orbit of the reduced system, "
                                   "which is not implemented")
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
    k = int(np.argmax(w.real + 1e-300 * np.sign(w.imag)))
    # prefer the member of the conjugate pair with b >= 0
    cand = [i for i in range(w.size) if abs(w[i].real - w[k].real) <= 1e-12 * max(1, abs(w[k])) and w[i].imag >= 0]
    k = cand[0] if cand else k
    if w[k].real <= HYPERBOLIC_TOL:
        mc = scalars.m_critical(p.gamma) if p.gamma > -1 else float("nan")
        raise ParameterError("m", f"no saddle: the straight rod is not hyperbolic at these parameters (max Re "
                                  f"eigenvalue {w[k].real:.3g}); at lam = 0 this is m >= m_c = 2 sqrt(1 + gamma) = "
                                  f"{mc:.6g} (eq:buckling_load_2)")
    v = V[:, k] / np.linalg.norm(V[:, k])
    j = _E31 if abs(v[_E31]) > 1e-3 else int(np.argmax(np.abs(v)))
    v = v * np.exp(-1j * np.angle(v[j]))
    H = float(f["H"](x, pars)[0])
    return Saddle(p, x, Jm, w, complex(w[k]), v, H)
