"""Mel'nikov function of the magnetically perturbed extensible rod (paper sec. 7, eq:Mel_ext, fig:Mel_ext).

Public API
----------
amplitude(m, gamma, integrand="derived", *, reference=True, theta_tail=1e-20) -> Amplitude
melnikov_function(psi0, amp)           -> M(psi0)/sqrt(a - 2b) = A sin(psi0)
primitive_check(m, gamma, n=64)        -> running quadrature vs 2 Phi(T) (derived integrand, exact derivative)
amplitude_zero(m, integrand="printed", bracket=(1.8, 2.0)) -> gamma* with A(gamma*) = 0 and its error bound
(fig:Mel_ext is drawn by magrod/figures/melnikov.py)

Convention
----------
M(psi0) = A sin(psi0) sqrt(a - 2b) with A = Int_{-inf}^{+inf} F dt along the lambdabar = 0 homoclinic orbit
(t = 0 at the turning point, psi = psibar + psi0, psibar(0) = 0), F = generated.melnikov.integrand_derived
(from the definition eq:melnikov_bracket) or integrand_printed (eq:Mel_ext as printed, prefactor -1/m^2
included).  The cos(psi0) part of the bracket is odd in t and integrates to zero (report entry
melnikov_integrand); F itself is even (pbar_theta and psibar odd, theta even), so A = 2 Int_0^inf F dt.

Quadrature and error bound
--------------------------
F(t) is evaluated on the closed form of magrod.orbits.homoclinic (t = hy.time inside a heyoka Taylor integrator of
(psibar, A_derived, A_printed)' = (psi', 2 F_derived, 2 F_printed)), from t = 0 to T where theta(T) = theta_tail.
* Tail: F = pbar_theta sin(psibar) G(theta)/m^2 with |G| <= 3 (1 + gamma) for both integrands (|cos| <= 1),
  and pbar_theta < 0 for t > 0, so |2 Int_T^inf F dt| <= 2 * 3 (1 + gamma) theta(T)/m^2 (rigorous).
* Quadrature: the float64 run (tol = eps) is compared with a real128 run (tol = 1e-32); the difference is the
  error estimate of the float64 value.  error = |A_64 - A_128| + tail bound.
For the derived integrand there is in addition an exact check: {H0, H1/omega0} = dPhi/dt along the orbit
(generated.melnikov.primitive), so Int_0^T 2 F dt = 2 Phi(T) at psi0 = pi/2 for every T (primitive_check).
Cost: float64 ~1 ms per amplitude after compilation; the real128 reference ~0.1-0.5 s.
"""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass

import heyoka as hy
import numpy as np

from ..core import systems
from ..core.errors import ParameterError
from ..core.precision import Precision
from ..generated import melnikov as gen
from ..orbits.homoclinic import homoclinic, stable_expressions
from ..core.printed import FIG2_M, FIG2_ZERO_BRACKET
from ..core.tolerances import MELNIKOV_ZERO_XTOL, REAL128_QUADRATURE_TOL
from ..core.deprecation import deprecated_alias

INTEGRANDS = ("derived", "printed")


@systems.per_thread
def _quad_integrator(precision=Precision.DOUBLE):
    """Taylor integrator of y = (psibar, A_derived(t), A_printed(t)) along the closed-form orbit; pars (m, gamma)."""
    psib, jd, jp = hy.make_vars("psibar", "A_derived", "A_printed")
    m, g = hy.par[0], hy.par[1]
    e = stable_expressions(hy.time, m, g)
    fd = gen.integrand_derived(e["theta"], e["ptheta"], psib, m, g)
    fp = gen.integrand_printed(e["theta"], e["ptheta"], psib, m, g)
    sys = [(psib, e["psidot"]), (jd, 2.0 * fd), (jp, 2.0 * fp)]
    if precision is Precision.DOUBLE:
        return systems.taylor(sys, [0.0, 0.0, 0.0], [1.0, 1.0])
    return systems.taylor(sys, [0, 0, 0], [1, 1], precision=precision, compact_mode=True,
                          tol=REAL128_QUADRATURE_TOL if precision is Precision.QUAD else 0)


def _run(m, gamma, t_grid, precision=Precision.DOUBLE) -> np.ndarray:
    """(len(t_grid), 3) array of (psibar, A_derived, A_printed) running integrals at t_grid (increasing, >= 0)."""
    precision = Precision.parse(precision)
    fp_type = precision.fp_type
    ta = _quad_integrator(precision)
    ta.time = fp_type(0)
    ta.state[:] = np.array([fp_type(0)] * 3)
    ta.pars[:] = np.array([fp_type(m), fp_type(gamma)])
    res = ta.propagate_grid(np.array([fp_type(0)] + [fp_type(x) for x in t_grid]))  # grid starts at ta.time
    if res[0] != hy.taylor_outcome.time_limit:
        raise RuntimeError(f"Mel'nikov quadrature failed: {res[0]}")
    return res[-1][1:]


@dataclass(frozen=True)
class Amplitude:
    """A with M(psi0) = A sin(psi0) sqrt(a - 2b); error = quad_error + tail_bound."""

    m: float
    gamma: float
    integrand: str
    A: float  # float64 quadrature
    A_reference: float | None  # real128 quadrature (None if reference=False)
    quad_error: float | None  # |A - A_reference|
    tail_bound: float  # rigorous bound of the truncated tails
    error: float | None
    T: float  # quadrature over [-T, T]
    theta_tail: float
    wall_time_s: float
    checks: dict  # derived integrand: 2 Phi(T) (exact truncated integral) and the real128 quadrature minus it
    convention: str = "M(psi0) = A * sin(psi0) * sqrt(a - 2b), A = Int F dt over the homoclinic orbit"

    as_dict = deprecated_alias("to_dict", "as_dict")

    def to_dict(self) -> dict:
        return asdict(self)


def _check_integrand(integrand):
    if integrand not in INTEGRANDS:
        raise ParameterError("integrand", f"must be one of {INTEGRANDS}, got {integrand!r}")


def tail_bound(m, gamma, theta_T) -> float:
    """|2 Int_T^inf F dt| <= 6 (1 + gamma) theta(T)/m^2 (see module docstring)."""
    return 6.0 * (1.0 + gamma) * theta_T / m**2


def amplitude(m, gamma, integrand="derived", *, reference=True, theta_tail=1e-20) -> Amplitude:
    """Amplitude A of M(psi0)/sqrt(a - 2b) = A sin(psi0) for `integrand` ("derived" | "printed") at (m, gamma).
    reference=True adds a real128 run for the quadrature error estimate (~0.1-0.5 s)."""
    _check_integrand(integrand)
    t0 = time.perf_counter()
    orbit = homoclinic(m, gamma)
    T = orbit.time_at_theta(theta_tail)
    col = 1 + INTEGRANDS.index(integrand)
    a64 = float(_run(orbit.m, orbit.gamma, [T])[-1, col])
    aref = qerr = err = None
    extra = {}
    if reference:
        yref = _run(orbit.m, orbit.gamma, [T], Precision.QUAD)[-1]
        aref = float(yref[col])
        qerr = abs(a64 - aref)
        if integrand == "derived":
            # exact value of the truncated integral: Int_{-T}^{T} F dt = 2 Phi(T) (psi0 = pi/2)
            q = hy.real128
            two_phi = _two_phi_cfunc(q)(np.array([q(T), yref[0]]), pars=np.array([q(orbit.m), q(orbit.gamma)]))[0]
            extra = {"two_phi_T_real128": float(two_phi), "real128_minus_two_phi_T": float(yref[col] - two_phi)}
    tb = tail_bound(orbit.m, orbit.gamma, theta_tail)
    if reference:
        err = qerr + tb
    return Amplitude(orbit.m, orbit.gamma, integrand, a64, aref, qerr, tb, err, T, theta_tail,
                     time.perf_counter() - t0, extra)


def amplitudes(m, gammas, *, reference=True, theta_tail=1e-20) -> dict:
    """{integrand: [Amplitude for each gamma]} for both integrands (one quadrature run per gamma)."""
    out = {k: [] for k in INTEGRANDS}
    for g in gammas:
        for k in INTEGRANDS:
            out[k].append(amplitude(m, g, k, reference=reference, theta_tail=theta_tail))
    return out


def melnikov_function(psi0, amp) -> np.ndarray:
    """M(psi0)/sqrt(a - 2b) = A sin(psi0) (amp: an Amplitude or the number A)."""
    a = amp.A if isinstance(amp, Amplitude) else float(amp)
    return a * np.sin(np.asarray(psi0, dtype=float))


@systems.cache
def _primitive_cfunc():
    th, pt, ps = hy.make_vars("theta", "ptheta", "psi")
    return systems.build(hy.cfunc, [gen.primitive(th, pt, ps, hy.par[0], hy.par[1])], vars=[th, pt, ps])


@systems.cache
def _two_phi_cfunc(fp_type):
    """2 Phi(t) at psi0 = pi/2 on the closed-form orbit, as a function of (t, psibar(t))."""
    t, psib = hy.make_vars("t", "psibar")
    e = stable_expressions(t, hy.par[0], hy.par[1])
    half_pi = hy.acos(hy.expression(fp_type(0)))  # pi/2 at the working precision
    phi = gen.primitive(e["theta"], e["ptheta"], psib + half_pi, hy.par[0], hy.par[1])
    return systems.build(hy.cfunc, [2.0 * phi], vars=[t, psib], fp_type=fp_type)


def primitive_check(m, gamma, n=64, theta_tail=1e-20) -> dict:
    """For the derived integrand: the running quadrature 2 Int_0^T F dt against 2 Phi(T)|_(psi0 = pi/2) at n
    times T in (0, T_tail] (exact identity since the full integrand is dPhi/dt and Phi is odd in t at
    psi0 = pi/2).  Returns the max difference, the largest |2 Phi| on the grid, and the arrays."""
    orbit = homoclinic(m, gamma)
    T = orbit.time_at_theta(theta_tail)
    grid = np.linspace(T / n, T, n)
    run = _run(orbit.m, orbit.gamma, grid)
    st = orbit.evaluate(grid)
    x = np.vstack([st["theta"], st["ptheta"], run[:, 0] + np.pi / 2])
    cf = _primitive_cfunc()
    phi = cf(x, pars=np.array([[orbit.m] * n, [orbit.gamma] * n])[: cf.nparams])[0]
    diff = run[:, 1] - 2.0 * phi
    return {"max_abs_diff": float(np.max(np.abs(diff))), "max_abs_2phi": float(np.max(np.abs(2 * phi))),
            "t": grid, "running_A": run[:, 1], "two_phi": 2.0 * phi}


def amplitude_zero(m=FIG2_M, integrand="printed", bracket=FIG2_ZERO_BRACKET, xtol=MELNIKOV_ZERO_XTOL) -> dict:
    """gamma* in `bracket` with A(gamma*) = 0 by Brent's method on the float64 amplitude.  Error bound:
    |gamma* - gamma_found| <= xtol + eps_A/|dA/dgamma| with eps_A the amplitude error estimate at gamma_found
    (real128 reference + tail bound) and dA/dgamma by a central difference; the sign of the real128 amplitude
    is checked at gamma_found -/+ 2 * bound."""
    from scipy.optimize import brentq

    _check_integrand(integrand)
    a, b = bracket
    f = lambda g: amplitude(m, g, integrand, reference=False).A  # noqa: E731
    ends = [amplitude(m, a, integrand), amplitude(m, b, integrand)]
    fa, fb = ends[0].A, ends[1].A
    base = {"m": m, "integrand": integrand, "bracket": [a, b], "A_at_ends": [fa, fb],
            "A_error_at_ends": [e.error for e in ends]}
    if any(abs(e.A) <= e.error for e in ends):
        # a sign change of rounding noise is not a zero: A is zero within its bound at an end of the bracket
        # (the derived amplitude vanishes identically, report entry melnikov_vanishes)
        return {**base, "found": False, "zero_within_bound_at_ends": True}
    if not np.sign(fa) * np.sign(fb) < 0:
        return {**base, "found": False, "zero_within_bound_at_ends": False}
    g0 = brentq(f, a, b, xtol=xtol, rtol=4 * np.finfo(float).eps)
    amp = amplitude(m, g0, integrand)
    dg = 1e-4
    slope = (f(g0 + dg) - f(g0 - dg)) / (2 * dg)
    bound = xtol + amp.error / abs(slope)
    lo = amplitude(m, g0 - 2 * bound, integrand).A_reference
    hi = amplitude(m, g0 + 2 * bound, integrand).A_reference
    return {**base, "found": True, "gamma_zero": g0, "error_bound": bound,
            "A_at_zero": amp.A, "A_error": amp.error, "dA_dgamma": slope,
            "sign_change_confirmed_real128": bool(np.sign(lo) * np.sign(hi) < 0),
            "A_real128_at_zero_minus_2bound": lo, "A_real128_at_zero_plus_2bound": hi}
