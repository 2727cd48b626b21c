"""Splitting of the homoclinic manifold of the straight twisted rod, for the rod models that perturb the isotropic
Kirchhoff rod: the anisotropic rod [Mielke88] and the intrinsically curved rod
[Champneys97a; Leung04].

The integrable member.  The isotropic rod (B1 = B2 = B, torsion C, pre-twist k3, H = |m_perp|^2/(2B) + m3^2/(2C)
+ k3 m3 + n3 on se(3)*) has the equilibrium x* = (0, 0, M, 0, 0, T), the straight rod under tension T and twisting
moment M.  On its symplectic leaf (|n| = T, m.n = M T) it is a saddle-focus when a^2 = 4 B T - M^2 > 0 (Greenhill's
condition), eigenvalues +-kappa +- i Omega; its 2-D stable and unstable manifolds coincide (m3 = M is an integral):
the localised buckling of the twisted rod.  Closed form (derived here; proved symbolically to solve the pipeline's
own equations, generated/models/curved/report.json at k1 = 0, on the straight rod's level, and checked against the
integrated orbit: tests/test_models_splitting.py), with kappa = a / (2B), Omega = M/C + k3 - M/(2B) and the phase
phi0 of the S^1 symmetry about d3:
    n3 = T - (a^2 / (2B)) sech^2(kappa t),   m1 + i m2 = a sech(kappa t) exp(i (phi0 - Omega t)),   m3 = M,
    n1 + i n2 = (m1 + i m2) (M z + i B z') / (2 B z),   z = T - n3.
(From n3' = (n1 m2 - n2 m1)/B, |m_perp|^2 = 2B z on the level, (m_perp.n_perp) = M z: (B z')^2 = z^2 (a^2 - 2B z);
and mu = m1 + i m2 obeys mu' = -i ((M/C + k3 - M/B) mu + nu), whence arg mu = phi0 - Omega t.)

The perturbation.  Both models change only m3' (the lost integral): exactly (the pipeline's equations, checked
symbolically in the tests)
    anisotropic: m3' = (1/B2 - 1/B1) m1 m2            (B = B1),
    curved:      m3' = -k1 m2                          (uhat = (k1, 0, k3); the straight rod is the k1 = 0 member).
Mel'nikov.  The splitting of the manifolds measured by m3 on a section through the orbit's midpoint,
Delta(phi0) = m3(W^u) - m3(W^s) = int m3'(gamma_phi0(t)) dt + O(eps^2), is in closed form
    anisotropic: Delta = (1/B2 - 1/B1) 4 pi B^2 Omega / sinh(2 pi B Omega / a) sin 2 phi0
                 (limit 2 a B sin 2 phi0 at Omega = 0),
    curved:      Delta = -2 pi B k1 sech(pi B Omega / a) sin phi0,
(the Fourier transforms int sech^2(kt) cos(wt) dt = pi w / (k^2 sinh(pi w / 2k)), int sech(kt) cos(wt) dt =
(pi / k) sech(pi w / 2k)); both have simple zeros for every admissible parameter, so for small eps the manifolds
intersect transversally (Holmes & Marsden's Mel'nikov method on Lie-Poisson systems; with a saddle-focus,
Devaney's theorem then gives horseshoes: conditional on eps small enough, which the measured O(eps^2) remainder
quantifies).  `melnikov_quadrature` integrates the model's own generated m3' along the closed-form orbit (an
independent check of the closed form and of the integrand).

The measurement (numerical, floating point with error evidence).  The perturbed rod's saddle x*_eps (the
anisotropic rod keeps x*; the curved rod's is the relative equilibrium u = beta n, d3 = alpha n + beta m at the
(alpha, beta) of the straight rod's x*), its Jacobian by heyoka's derivatives of the generated right-hand side,
the unstable eigenvector v of the eigenvalue kappa + i Omega (order and phase by magrod.core.eigen: fix_phase
with m1 preferred).  n_phase starts x*_eps + delta Re(exp(i s) v), s uniform on [0, 2 pi), projected onto the
level of x*_eps (H and the Casimirs, model_chaos.project_to_level), are integrated (heyoka, tol = machine epsilon)
to the first zero of n3' (the midpoint section).  There (phi = arg(m1 + i m2), m3) is a curve; a trigonometric
least-squares fit in phi (harmonics <= FIT_HARMONICS) gives f_u(phi).
  Method A (reversibility).  R: (m2, n2, t) -> (-m2, -n2, -t) is a reversor of both models fixing x*_eps, so
  W^s = R W^u and f_s(phi) = f_u(-phi): Delta(phi) = f_u(phi) - f_u(-phi).
  Method B (direct).  The stable eigenvector, integrated backwards to the same section: Delta = f_u - f_s.
The leading harmonic's coefficient (sin 2 phi, sin phi) divided by eps is compared with the Mel'nikov
coefficient at several eps: the difference must scale like eps (first-order theory), and the measurement must not
depend on delta nor on the eigenvector's phase (the curve is parametrised by phi on the section, not by s), nor
on the precision (precision_check: the unstable manifold again in long double from the same starts).
Control: the isotropic member (eps = 0) gives |Delta| at the launch error (delta^2), not at eps.
Integrators are scalar (no MAGROD_BATCH_WIDTH dependence).  Cost: ~0.2 s per model and call, ~0.4 s with the
first compile (benchmarks/models.json, key splitting, under load 10).
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..core import systems
from ..core.errors import ParameterError
from ..core.precision import Precision
from ..core.results import Result

# the models with the straight twisted rod's homoclinic manifold, and the parameter that perturbs it
SPLITTING_MODELS = {
    "anisotropic": {"eps": "B2 = B1 (1 + eps)", "harmonic": 2, "reference": "Mielke88", "remainder_order": 1},
    # the rotation by pi about d3 maps the rod with k1 to the rod with -k1: Delta(phi; -k1) = Delta(phi + pi; k1),
    # so the sin(phi) coefficient is odd in k1 and its remainder is O(k1^3): relative difference O(eps^2)
    "curved": {"eps": "k1 = eps", "harmonic": 1, "reference": "Champneys97a, Leung04", "remainder_order": 2},
}
LAUNCH = 1e-6  # distance of the starts from the saddle along the eigenvector (launch error ~ LAUNCH^2)
FIT_HARMONICS = 6  # trigonometric fit of the section curve m3(phi)
EPS_DEFAULT = (0.04, 0.02, 0.01)
STRAIGHT = {"M": 1.0, "T": 1.0}  # the straight rod's moment and tension (4 B T - M^2 = 3 > 0 at B = 1)
T_GUARD = 400.0  # max flight time to the section (the flight is ~ ln(1/delta)/kappa ~ 20)


def _base(model: str, params: dict | None, eps: float) -> dict:
    """The model's parameters at perturbation eps (the integrable member at eps = 0)."""
    if model == "anisotropic":
        p = {"B1": 1.0, "C": 1.5}
        p.update(params or {})
        p["B2"] = p["B1"] * (1.0 + eps)
        return p
    p = {"B": 1.0, "C": 0.75, "k3": 0.2}
    p.update(params or {})
    p["k1"] = eps
    return p


def _unperturbed(model: str, p: dict) -> tuple:
    """(B, C, k3) of the isotropic member."""
    return (p["B1"], p["C"], 0.0) if model == "anisotropic" else (p["B"], p["C"], p["k3"])


def rates(B, C, M, T, k3=0.0) -> tuple:
    """(a, kappa, Omega) of the straight rod's saddle-focus (module docstring); ParameterError if 4BT <= M^2."""
    a2 = 4 * B * T - M * M
    if not a2 > 0:
        raise ParameterError("M", f"the straight rod (M, T) = ({M}, {T}) is not a saddle-focus: 4 B T - M^2 = {a2:g} "
                                  "<= 0 (Greenhill's condition)")
    a = math.sqrt(a2)
    return a, a / (2 * B), M / C + k3 - M / (2 * B)


def homoclinic(t, phi0, B, C, M, T, k3=0.0) -> np.ndarray:
    """The isotropic rod's homoclinic orbit (module docstring), shape (len(t), 6): (m1, m2, m3, n1, n2, n3)."""
    a, kap, Om = rates(B, C, M, T, k3)
    t = np.atleast_1d(np.asarray(t, float))
    s = 1 / np.cosh(kap * t)
    z = a * a / (2 * B) * s * s
    dz = -2 * kap * np.tanh(kap * t) * z
    mu = a * s * np.exp(1j * (phi0 - Om * t))
    nu = mu * (M * z + 1j * B * dz) / (2 * B * z)
    return np.stack([mu.real, mu.imag, np.full_like(t, M), nu.real, nu.imag, T - z], axis=1)


def melnikov_factor(model: str, p: dict, M: float, T: float) -> float:
    """F with Delta(phi0) = d F sin(k phi0) + O(d^2), d = 1/B2 - 1/B1 (anisotropic) or k1 (curved)."""
    B, C, k3 = _unperturbed(model, p)
    a, kap, Om = rates(B, C, M, T, k3)
    if model == "anisotropic":
        x = 2 * math.pi * B * Om / a
        return 2 * a * B if x == 0 else 4 * math.pi * B * B * Om / math.sinh(x)
    return -2 * math.pi * B / math.cosh(math.pi * B * Om / a)


def melnikov_closed_form(model: str, p: dict, M: float, T: float) -> float:
    """Coefficient c of Delta(phi0) = c sin(k phi0) + O(eps^2) (k = SPLITTING_MODELS[model]['harmonic'])."""
    d = 1 / p["B2"] - 1 / p["B1"] if model == "anisotropic" else p["k1"]
    return d * melnikov_factor(model, p, M, T)


def melnikov_unit(model: str, params: dict | None, M: float, T: float) -> float:
    """dc/deps at eps = 0: the Mel'nikov coefficient per unit eps (anisotropic: d = -eps/(B1 (1 + eps)))."""
    p = _base(model, params, 0.0)
    return melnikov_factor(model, p, M, T) * (-1 / p["B1"] if model == "anisotropic" else 1.0)


@dataclass(frozen=True)
class _Code:
    mc: object
    rhs: object  # cfunc of the right-hand side
    jac: object  # cfunc of its Jacobian (row-major)


def _code(model: str) -> _Code:
    from ..chaos.model_chaos import _model
    return _codes(_model(model).directory)


@systems.cache
def _codes(directory: str) -> _Code:
    import heyoka as hy

    from ..chaos.model_chaos import resolve_dir

    mc = resolve_dir(directory)
    sys_ = mc.body.system()
    xs = [v for v, _ in sys_]
    fs = [f for _, f in sys_]
    jac = [hy.diff(f, x) for f in fs for x in xs]
    return _Code(mc, systems.CFunc(fs, xs), systems.CFunc(jac, xs))


@systems.per_thread
def _integrator(directory: str, precision: str = "double"):
    """The model's integrator with a terminal event at n3' = 0 (the midpoint section; the first zero after the
    launch, either direction: forwards on W^u, backwards on W^s); precision "double" or "long double" (80-bit
    x87 where numpy's longdouble is, the precision check)."""
    import heyoka as hy

    from ..chaos.model_chaos import resolve_dir

    mc = resolve_dir(directory)
    sys_ = mc.body.system()
    if precision == "double":
        ev = hy.t_event(sys_[5][1], cooldown=1e-3)
        return systems.taylor(sys_, list(mc.names.REFERENCE), mc.names.DEFAULTS, t_events=[ev])
    ld = np.longdouble
    ev = hy.t_event(sys_[5][1], cooldown=ld(1e-3), fp_type=ld)
    return systems.taylor(sys_, list(mc.names.REFERENCE), mc.names.DEFAULTS, t_events=[ev],
                          precision=Precision.LONG_DOUBLE)


def melnikov_quadrature(model: str, p: dict, M: float, T: float, n: int = 4001) -> float:
    """The Mel'nikov coefficient by quadrature: int m3'(gamma_phi0(t)) dt at phi0 = pi/(2k) (where sin k phi0 = 1),
    m3' the model's generated right-hand side at the perturbed parameters, gamma the closed-form orbit of the
    isotropic member; trapezoidal rule on |kappa t| <= 40 (exponentially accurate for this analytic integrand)."""
    code = _code(model)
    B, C, k3 = _unperturbed(model, p)
    _, kap, _ = rates(B, C, M, T, k3)
    k = SPLITTING_MODELS[model]["harmonic"]
    t = np.linspace(-40 / kap, 40 / kap, n)
    X = homoclinic(t, math.pi / (2 * k), B, C, M, T, k3)
    pars = np.array(code.mc.parameters(p))
    f3 = np.array([code.rhs(x, pars)[2] for x in X])
    return float(np.sum(f3[1:] + f3[:-1]) * (t[1] - t[0]) / 2)


def saddle(model: str, p: dict, M: float, T: float) -> np.ndarray:
    """The perturbed rod's equilibrium next to the straight rod (M, T) (module docstring)."""
    if model == "anisotropic":
        return np.array([0.0, 0.0, M, 0.0, 0.0, T])
    B, C, k1, k3 = p["B"], p["C"], p["k1"], p["k3"]
    beta = (M / C + k3) / T
    alpha = (1 - beta * M) / T
    # u = beta n, d3 = alpha n + beta m, m2 = n2 = 0 (the relative equilibria of the pre-curved rod)
    n1 = k1 / (beta + alpha / (beta * B))
    n3 = (1 / (beta * C) + k3) / (beta + alpha / (beta * C))
    return np.array([-(alpha / beta) * n1, 0.0, (1 - alpha * n3) / beta, n1, 0.0, n3])


def _eig(code: _Code, x, pars, unstable: bool):
    from ..core.eigen import fix_phase, order

    Jm = np.asarray(code.jac(x, pars)).reshape(6, 6)
    w, V = np.linalg.eig(Jm)
    idx = order(w)
    j = idx[0] if unstable else idx[-1]  # kappa + i Omega first, -kappa - i Omega last (order: Re, then Im)
    return w[j], fix_phase(V[:, j], prefer=(0, 1, 3, 4))


def section_curve(model: str, p: dict, M: float, T: float, *, stable: bool = False, delta: float = LAUNCH,
                  n_phase: int = 32, phase: float = 0.0, precision: str = "double") -> dict:
    """The unstable (stable: backwards) manifold's trace on the midpoint section: arrays phi, m3 (n_phase points),
    the eigenvalue, the level error and the flight times.  `phase` multiplies the eigenvector by exp(i phase)
    (a control: the curve must not depend on it)."""
    import heyoka as hy

    from ..chaos.model_chaos import _cfuncs, project_to_level

    code = _code(model)
    mc = code.mc
    pars = np.array(mc.parameters(p))
    xs = saddle(model, p, M, T)
    res = np.max(np.abs(np.asarray(code.rhs(xs, pars))))
    lam, v = _eig(code, xs, pars, unstable=not stable)
    v = v * np.exp(1j * phase)
    g, _ = _cfuncs(mc)
    g0 = np.asarray(g(xs, pars), float)
    ta = _integrator(mc.directory, precision)
    fp = np.longdouble if precision != "double" else float
    phis, m3s, times, lev = [], [], [], 0.0
    B, C, k3 = _unperturbed(model, p)
    a, _, _ = rates(B, C, M, T, k3)
    zmid = a * a / (4 * B)  # half the straight rod's excursion T - min n3 = a^2 / (2B)
    sign = -1.0 if stable else 1.0
    # the stable manifold's starts sit half a step off the unstable ones' mirror images, so that method B's curve
    # is sampled at other points than R of method A's (not a bitwise mirror of the same computation)
    for s in 2 * np.pi * (np.arange(n_phase) + (0.5 if stable else 0.0)) / n_phase:
        x0 = project_to_level(mc, xs + delta * np.real(np.exp(1j * s) * v), g0, pars)
        systems.reset(ta, np.asarray(x0, dtype=fp), 0.0, np.asarray(pars, dtype=fp))
        while True:  # the first zero of n3' beyond half the excursion (near x* n3' is O(delta) for the curved rod)
            out = ta.propagate_until(fp(sign * T_GUARD))[0]
            if out != hy.taylor_outcome(-1):
                raise ParameterError("eps", f"{model}: a {'stable' if stable else 'unstable'} manifold orbit did not "
                                            f"reach the midpoint section by |t| = {T_GUARD:g} ({out})")
            x = np.array(ta.state, dtype=float)
            if xs[5] - x[5] > zmid:
                break
        lev = max(lev, float(np.max(np.abs(np.asarray(g(x, pars)) - g0))))
        phis.append(math.atan2(x[1], x[0]))
        m3s.append(x[2])
        times.append(abs(float(ta.time)))
    return {"phi": np.array(phis), "m3": np.array(m3s), "eigenvalue": complex(lam), "saddle_residual": float(res),
            "level_error": lev, "flight_time": (min(times), max(times)), "saddle": xs}


def _fit(phi, y, K=FIT_HARMONICS):
    """Least-squares coefficients (c0, a1, b1, ..., aK, bK) of y = c0 + sum a_k cos k phi + b_k sin k phi."""
    cols = [np.ones_like(phi)]
    for k in range(1, K + 1):
        cols += [np.cos(k * phi), np.sin(k * phi)]
    A = np.stack(cols, axis=1)
    c, *_ = np.linalg.lstsq(A, y, rcond=None)
    return c, float(np.max(np.abs(A @ c - y)))


def measure(model: str, eps: float, *, params=None, delta: float = LAUNCH, n_phase: int = 32, phase: float = 0.0,
            direct: bool = True, M: float = STRAIGHT["M"], T: float = STRAIGHT["T"], precision: str = "double") -> dict:
    """The splitting Delta(phi) at one eps: the leading odd harmonic's coefficient by method A (reversor) and, with
    `direct`, method B (the stable manifold integrated backwards), the other odd harmonics' size, and the
    Mel'nikov coefficient (closed form) times 1 -- Delta's prediction to first order."""
    k = SPLITTING_MODELS[model]["harmonic"]
    p = _base(model, params, eps)
    u = section_curve(model, p, M, T, delta=delta, n_phase=n_phase, phase=phase, precision=precision)
    cu, fit_u = _fit(u["phi"], u["m3"])
    # Delta_A(phi) = f_u(phi) - f_u(-phi) = 2 sum b_j sin j phi
    A = 2 * cu[2 * k]
    odd_rest = max(abs(2 * cu[2 * j]) for j in range(1, FIT_HARMONICS + 1) if j != k)
    out = {"eps": eps, "params": p, "A": float(A), "other_odd_harmonics": float(odd_rest), "fit_residual_u": fit_u,
           "melnikov": melnikov_closed_form(model, p, M, T), "eigenvalue": [u["eigenvalue"].real, u["eigenvalue"].imag],
           "level_error": u["level_error"], "saddle_residual": u["saddle_residual"],
           "flight_time": list(u["flight_time"]), "max_abs_delta": float(np.max(np.abs(u["m3"] - u["saddle"][2])))}
    if direct:
        s = section_curve(model, p, M, T, stable=True, delta=delta, n_phase=n_phase, phase=phase,
                          precision=precision)
        cs, fit_s = _fit(s["phi"], s["m3"])
        out["B"] = float(cu[2 * k] - cs[2 * k])
        out["B_even_part"] = float(max(abs(cu[2 * j - 1] - cs[2 * j - 1]) for j in range(1, FIT_HARMONICS + 1)))
        out["fit_residual_s"] = fit_s
        out["level_error"] = max(out["level_error"], s["level_error"])
    return out


@dataclass(repr=False)
class MelnikovScan(Result):
    """The splitting of the straight twisted rod's homoclinic manifold for one model: per eps the measured leading
    coefficient (methods A and B), the Mel'nikov coefficient (closed form and quadrature), their relative
    difference and its scaling with eps, the delta and eigenvector-phase controls and the integrable control."""

    success: bool
    message: str
    model: str  # the model's name
    reference: str  # the literature whose claim the scan checks (e.g. Mielke88)
    perturbation: str  # what eps changes, e.g. "B2 = B1 (1 + eps)"
    harmonic: int  # the Mel'nikov function's harmonic in the phase phi0 (sin 2 phi0: 2; sin phi0: 1)
    rows: list  # one dict per eps: the measured coefficients A and B, the Mel'nikov prediction, their difference
    melnikov_unit: float  # Mel'nikov coefficient per unit eps at eps = 0 (closed form)
    quadrature_error: float  # |closed form - quadrature| / |closed form| at the smallest eps
    scaling_order: float  # log2 of the ratio of successive relative differences / log2 of the eps ratio
    delta_change: float  # relative change of A at the smallest eps when delta is divided by 10
    phase_change: float  # relative change of A under a random eigenvector phase
    control: float  # max |Delta| at eps = 0 (the integrable member)
    precision_change: float = float("nan")  # relative change of A at the smallest eps in long double (precision_check)
    status_label: str = "numerical (floating point with error evidence)"  # the claim's status
    wall_time_s: float = 0.0  # wall time of the scan
    notes: list = field(default_factory=list)  # the scan's checks, one line each: pass or FAIL

    _repr_fields = ("model", "melnikov_unit", "scaling_order", "control")

    @property
    def accuracy(self) -> dict:
        """The error evidence: A-B agreement, the remainder's order, the delta, phase and integrable controls."""
        return {"A_minus_B": max(r.get("A_minus_B", 0.0) for r in self.rows),
                "relative_difference": [r.get("relative_difference") for r in self.rows],
                "scaling_order": self.scaling_order, "quadrature_error": self.quadrature_error,
                "delta_change": self.delta_change, "phase_change": self.phase_change, "control": self.control,
                "precision_change": self.precision_change,
                "level_error": max(r["level_error"] for r in self.rows), "passed": bool(self.success)}


# the measurement's record was called ModelSplitting; mr.splitting returns the one Splitting result for every model,
# with this record as its `scan` (the old name kept for one release)
ModelSplitting = MelnikovScan


def model_splitting(model: str, *, eps=EPS_DEFAULT, params=None, n_phase: int = 32, delta: float = LAUNCH,
                    controls: bool = True, precision_check: bool = False, seed: int = 20) -> MelnikovScan:
    """Measure the splitting of the straight twisted rod's homoclinic manifold of `model` ('anisotropic' or
    'curved') at the perturbations `eps`, against the Mel'nikov prediction (module docstring).

    Parameters
    ----------
    model : str
        'anisotropic' (B2 = B1 (1 + eps)) or 'curved' (k1 = eps).
    eps : sequence of float, keyword-only
        At least two perturbation sizes, decreasing, each in (0, 0.2].
    params : dict, keyword-only
        The other parameters (anisotropic: B1, C; curved: B, C, k3) over the defaults (1, 3/2; 1, 3/4, 1/5).
    n_phase : int, keyword-only
        Starts on the launch circle (>= 4 FIT_HARMONICS).
    delta : float, keyword-only
        Launch distance (1e-9 ... 1e-3).
    controls : bool, keyword-only
        Run the delta/10, eigenvector-phase and integrable (eps = 0) controls.
    precision_check : bool, keyword-only
        Repeat the smallest eps's unstable manifold in long double (the integration error; ~1-2 s more for the
        compile).
    seed : int, keyword-only
        Seed of the random eigenvector phase of the phase control.

    Returns
    -------
    MelnikovScan
        success: every eps's methods A and B agree to 1e-6 relative, the relative difference from Mel'nikov
        decreases like eps^r (r = SPLITTING_MODELS[model]['remainder_order'] within 0.3), the controls are
        below 1e-6 (delta, phase) and 1e-9 (eps = 0).

    Raises
    ------
    ParameterError
        Naming model, eps, n_phase or delta.

    Examples
    --------
    >>> r = model_splitting("curved", eps=(0.02, 0.01), n_phase=24, controls=False)
    >>> r.success, round(r.melnikov_unit, 3)
    (True, -1.884)
    """
    t0 = time.perf_counter()
    if model not in SPLITTING_MODELS:
        raise ParameterError("model", f"the splitting measurement is for {', '.join(SPLITTING_MODELS)} (the models "
                                      f"that perturb the straight twisted rod's homoclinic orbit), got {model!r}")
    try:
        eps = [float(e) for e in eps]
    except (TypeError, ValueError):
        raise ParameterError("eps", f"must be a sequence of numbers, got {eps!r}") from None
    if len(eps) < 2 or not all(0 < e <= 0.2 for e in eps) or sorted(eps, reverse=True) != eps or len(set(eps)) < len(eps):
        raise ParameterError("eps", f"must be >= 2 distinct decreasing values in (0, 0.2], got {eps!r}")
    if isinstance(n_phase, bool) or not isinstance(n_phase, int) or not 4 * FIT_HARMONICS <= n_phase <= 4096:
        raise ParameterError("n_phase", f"must be an integer in [{4 * FIT_HARMONICS}, 4096], got {n_phase!r}")
    if not isinstance(delta, (int, float)) or isinstance(delta, bool) or not 1e-9 <= delta <= 1e-3:
        raise ParameterError("delta", f"must be a number in [1e-9, 1e-3], got {delta!r}")
    info = SPLITTING_MODELS[model]
    M, T = STRAIGHT["M"], STRAIGHT["T"]
    rows = [measure(model, e, params=params, delta=delta, n_phase=n_phase) for e in eps]
    for r in rows:
        r["relative_difference"] = abs(r["A"] - r["melnikov"]) / abs(r["melnikov"])
        r["A_minus_B"] = abs(r["A"] - r["B"]) / abs(r["A"])
    d = [r["relative_difference"] for r in rows]
    orders = [math.log(d[i] / d[i + 1]) / math.log(eps[i] / eps[i + 1]) for i in range(len(d) - 1)
              if d[i + 1] > 0 and d[i] > 0]
    order_ = float(min(orders)) if orders else float("nan")
    p_small = _base(model, params, eps[-1])
    mel = melnikov_closed_form(model, p_small, M, T)
    quad = melnikov_quadrature(model, p_small, M, T)
    qerr = abs(quad - mel) / abs(mel)
    dchange = pchange = control = float("nan")
    if controls:
        a = rows[-1]["A"]
        a2 = measure(model, eps[-1], params=params, delta=delta / 10, n_phase=n_phase, direct=False)["A"]
        dchange = abs(a2 - a) / abs(a)
        ph = float(np.random.default_rng(seed).uniform(0, 2 * np.pi))
        a3 = measure(model, eps[-1], params=params, delta=delta, n_phase=n_phase, phase=ph, direct=False)["A"]
        pchange = abs(a3 - a) / abs(a)
        c = measure(model, 0.0, params=params, delta=delta, n_phase=n_phase)
        control = max(abs(c["A"]), abs(c["B"]), c["max_abs_delta"])
    prec = float("nan")
    if precision_check:
        a4 = measure(model, eps[-1], params=params, delta=delta, n_phase=n_phase, direct=False,
                     precision="long double")["A"]
        prec = abs(a4 - rows[-1]["A"]) / abs(rows[-1]["A"])
    checks = {
        "methods A and B agree": all(r["A_minus_B"] <= 1e-6 for r in rows),
        "Mel'nikov closed form = quadrature": qerr <= 1e-9,
        f"difference from Mel'nikov is O(eps^{info['remainder_order']})":
            abs(order_ - info["remainder_order"]) <= 0.3,
    }
    if controls:
        checks.update({"independent of delta": dchange <= 1e-6, "independent of the eigenvector phase": pchange <= 1e-6,
                       "integrable member: no splitting": control <= 1e-9})
    if precision_check:
        checks["double = long double"] = prec <= 1e-10
    bad = [k for k, ok in checks.items() if not ok]
    unit = melnikov_unit(model, params, M, T)
    msg = (f"{model}: Delta(phi) = c sin({info['harmonic']} phi), dc/deps = {unit:.6g} at eps = 0 (Mel'nikov); "
           "measured c/eps = "
           + ", ".join(f"{r['A'] / r['eps']:.6g}" for r in rows) + f" at eps = {eps}; "
           + ("all checks pass" if not bad else f"FAILED: {bad}"))
    return MelnikovScan(not bad, msg, model, info["reference"], info["eps"], info["harmonic"], rows, float(unit),
                          float(qerr), order_, float(dchange), float(pchange), float(control), prec,
                          wall_time_s=time.perf_counter() - t0, notes=[f"check {k}: {'pass' if v else 'FAIL'}"
                                                                       for k, v in checks.items()])
