"""The Mel'nikov function of any rod model with a saddle and a small parameter, along a numerically computed
homoclinic orbit of its integrable member.

Set-up.  A model at parameter p = p0 (the integrable member) has a first integral I (one of its candidates,
generated body.candidates: m3 for the isotropic family) and the rotations G_phi about d3 (its S^1 symmetry); the
straight twisted rod is a saddle-focus whose stable and unstable manifolds coincide, a family of homoclinic orbits
gamma_phi0 = G_phi0 gamma_0 in the phase phi0.  Moving p breaks I; to first order in p - p0 the splitting of the
manifolds measured by I is

    Delta(phi0) = (p - p0) M(phi0),    M(phi0) = int grad I(gamma_phi0(t)) . d f/d p (gamma_phi0(t); p0) dt

(Holmes & Marsden's Mel'nikov method on Lie-Poisson systems).  Here gamma_0 is the symmetric homoclinic orbit of the
integrable member on Fix(R) of a reversor R that survives the perturbation (magrod.orbits.reversible), grad I and
d f/d p are compiled by hy.diff of the model's generated expressions (d/d hy.par[k]), and the integral is the
trapezoidal rule on the orbit's samples over [0, 2T] (the integrand decays like the distance from the saddle,
launch distance delta at the ends: a truncation error ~ delta / kappa).  M is fitted by a trigonometric polynomial in
phi0; its simple zeros are where the manifolds of the perturbed rod intersect transversally for small p - p0
(conditional on p - p0 small enough).  Status: numerical (floating point; the anisotropic and curved rods' closed
forms of magrod.separatrix.model_splitting are the check, tests/test_model_orbits.py).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.errors import MissingStructure, ParameterError
from ..core.results import Result

HARMONICS = 6


@dataclass(repr=False)
class MelnikovFunction(Result):
    """M(phi0) on a grid of phases (per unit change of `parameter` from `value0`), its Fourier coefficients
    (c0, a1, b1, ...), the leading harmonic and its coefficient, the fit residual, the homoclinic orbit's accuracy
    and `system` (the perturbed model)."""

    success: bool
    message: str
    system: object
    parameter: str  # the model parameter that perturbs the integrable member
    value0: float  # its value at the integrable member
    integral: str  # the candidate first integral of the member whose change along the orbit measures the splitting
    phi: np.ndarray  # the phases phi0 of the grid
    M: np.ndarray  # M(phi0) on the grid, per unit change of the parameter
    coefficients: np.ndarray  # Fourier coefficients of M: c0, a1, b1, a2, b2, ... (cos, sin of h phi0)
    harmonic: int  # the leading harmonic h (largest amplitude)
    amplitude: float  # its amplitude hypot(a_h, b_h)
    fit_residual: float  # max|Fourier fit - M| on the grid
    orbit_accuracy: dict  # the homoclinic orbit's own accuracy checks

    _repr_fields = ("system", "parameter", "harmonic", "amplitude")

    @property
    def accuracy(self) -> dict:
        """The Fourier fit's residual and the homoclinic orbit's accuracy checks."""
        return {"fit_residual": self.fit_residual, **self.orbit_accuracy}


def _rotation(names, phi: float) -> np.ndarray:
    """G_phi: the rotation about d3 of every body vector of the state (x1, x2, x3 triples)."""
    from ..orbits.equilibria import _triples

    tri = _triples(list(names))
    G = np.eye(len(names))
    c, s = np.cos(phi), np.sin(phi)
    for i1, i2, _ in tri:
        G[np.ix_([i1, i2], [i1, i2])] = [[c, -s], [s, c]]
    return G


def melnikov_along_orbit(system, parameter: str, value0: float, *, integral: str | None = None, n_phase: int = 64,
                      n: int = 4001) -> MelnikovFunction:
    """The Mel'nikov function M(phi0) of `system`'s model for `parameter` moved from `value0` (the integrable
    member), by the integral `integral` (default: the model's first candidate) -- module docstring.

    Raises
    ------
    ParameterError
        "model" if the model has no candidate integral, the candidate is not an integral at value0, the member
        has no symmetric homoclinic orbit, or no reversor of the member survives the perturbation; "parameter".
    """
    import heyoka as hy

    from ..core import systems
    from ..core.system import as_system
    from ..orbits.equilibria import reversors
    from ..orbits.model_field import field
    from ..orbits.reversible import symmetric_homoclinic

    system, _ = as_system(system)
    if system.is_paper:
        raise MissingStructure(system.model, "a non-vanishing first-order Mel'nikov function",
                               "the paper's rod's first-order Mel'nikov function vanishes identically "
                                      "(docs/errata.md): mr.splitting measures its splitting directly")
    if parameter not in system.names:
        raise ParameterError("parameter", f"must be a parameter of the model {system.model!r} "
                                          f"({', '.join(system.names)}), got {parameter!r}")
    code = system.code
    cands = tuple(code.names.CANDIDATES)
    if not cands:
        raise MissingStructure(system.model, "a candidate first integral",
                               f"the Mel'nikov function needs a first integral of the integrable member, and "
                                      f"the model {system.model!r} declares no candidate integral")
    name = cands[0] if integral is None else integral
    if name not in cands:
        raise ParameterError("integral", f"must be one of the model's candidates {cands}, got {name!r}")
    s0 = system.replace(**{parameter: value0})
    mf = field(system)
    x = hy.make_vars(*mf.state)
    p = [hy.par[i] for i in range(len(system.names))]
    I_expr = code.body.candidates(*x, *p)[cands.index(name)]
    f = code.body.rhs(*x, *p)
    k = system.names.index(parameter)
    gradI = systems.CFunc([hy.diff(I_expr, xi) for xi in x], x)
    dfdp = systems.CFunc([hy.diff(fi, p[k]) for fi in f], x)
    # I must be an integral of the member: grad I . f = 0 at seeded test points
    rng = np.random.default_rng(20260104)
    X = rng.uniform(-1, 1, size=(mf.dim, 8))
    drift = np.abs(np.sum(np.asarray(gradI(X, s0.array())) * np.asarray(mf.rhs(X, s0.array())), axis=0))
    if np.max(drift) > 1e-12:
        raise MissingStructure(system.model, "an integrable member",
                               f"{name} is not an integral of the model {system.model!r} at {parameter} = "
                                      f"{value0:g} (|dI/dt| = {np.max(drift):.2g}): no integrable member there")
    survive = [r for r in reversors(s0) if any(np.array_equal(r.matrix, q.matrix) for q in reversors(system))]
    if not survive:
        raise MissingStructure(system.model, "a reversor",
                               f"no reversor of the model {system.model!r} at {parameter} = {value0:g} "
                                      "survives the perturbation: the symmetric orbit the Mel'nikov function starts "
                                      "from is not defined")
    orb = symmetric_homoclinic(s0, reversor=survive[0])
    if not orb.success:
        raise MissingStructure(system.model, "a symmetric homoclinic orbit",
                               f"the integrable member of {system.model!r} has no symmetric homoclinic orbit "
                                      f"({orb.message})")
    smp = orb.sample(n)
    t, Xo = smp["t"], smp["x"]
    pars0 = s0.array()
    phis = 2 * np.pi * np.arange(n_phase) / n_phase
    M = np.empty(n_phase)
    for j, ph in enumerate(phis):
        Xr = np.ascontiguousarray((Xo @ _rotation(mf.state, ph).T).T)
        g = np.sum(np.asarray(gradI(Xr, pars0)) * np.asarray(dfdp(Xr, pars0)), axis=0)
        M[j] = float(np.sum((g[1:] + g[:-1]) * np.diff(t)) / 2)
    # phase of the orbit: phi0 = arg(m1 + i m2) at its symmetric point, so that M is a function of phi0
    i1, i2 = mf.index("m1"), mf.index("m2")
    phase0 = float(np.arctan2(orb.x_mid[i2], orb.x_mid[i1]))
    phi0 = (phis + phase0) % (2 * np.pi)
    cols = [np.ones_like(phi0)]
    for h in range(1, HARMONICS + 1):
        cols += [np.cos(h * phi0), np.sin(h * phi0)]
    A = np.stack(cols, axis=1)
    c, *_ = np.linalg.lstsq(A, M, rcond=None)
    res = float(np.max(np.abs(A @ c - M)))
    amps = [float(np.hypot(c[2 * h - 1], c[2 * h])) for h in range(1, HARMONICS + 1)]
    lead = int(np.argmax(amps)) + 1
    ok = bool(res <= 1e-6 * max(1.0, max(amps)) and orb.accuracy["passed"])
    msg = (f"M(phi0) of {system.model!r} in {parameter} from {value0:g}: leading harmonic sin/cos {lead} phi0, "
           f"amplitude {amps[lead - 1]:.6g} (by {name})")
    return MelnikovFunction(ok, msg, system, parameter, float(value0), name, phi0, M, c, lead, amps[lead - 1], res,
                            dict(orb.accuracy))
