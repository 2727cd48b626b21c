"""Homoclinic orbit of the extensible rod at lambdabar = 0 (paper sec. 6, eq:extensible_ham, fig:angles).

Public API
----------
validate(m, gamma)                      -> (m, gamma) as floats, or ParameterError naming the parameter
homoclinic(m, gamma)                    -> HomoclinicOrbit (roots u_pm, k, kappa, h, m_c, theta_max ...)
HomoclinicOrbit.evaluate(t)             -> dict of arrays theta, ptheta, cos_theta, psidot at times t
HomoclinicOrbit.psibar(t)               -> psibar(t) = psi(t) - psi(0) (heyoka quadrature of psi' = 1/(1 + cos))
HomoclinicOrbit.time_at_theta(theta)    -> t > 0 at which the orbit reaches theta (closed form)
verify(orbit, theta_stop=1e-8, ...)     -> closed form vs an independent heyoka integration of generated.field
phase_portrait_energy(theta, ptheta, m, gamma) -> (1/2) ptheta^2 + V(theta) (eq:eq_oscillator)
(fig:angles is drawn by magrod/figures/homoclinic.py)

The closed form
---------------
derive/homoclinic.py derives (generated/homoclinic.py: closed_form; report entry theta_homoclinic_derived)
    cos theta = u_- + (u_+ - u_-)/D,   D = 1 - (1 - k) tanh^2(kappa t),
and (1 - k)(1 - u_-) = 1 - u_+ turns 1 - cos theta into (1 - u_+) sech^2(kappa t)/D, i.e.
    sin(theta/2) = A sech(kappa t)/sqrt(D),   A = sqrt((1 - u_+)/2),
    pbar_theta   = theta' = -2 k A kappa sech(kappa t) tanh(kappa t)/(D^(3/2) cos(theta/2)).
This is generated.closed_form_regular (report entry theta_homoclinic_regular): the same function as
generated.closed_form / generated.theta, with u_+, 1 - k and kappa written without any division by gamma
(generated.constants_regular), so that one compiled function also covers gamma = 0, where it reduces to
eq:Kirchhoff_homoclinic (k = 1, u_0 = m^2/2 - 1; generated.closed_form divides by gamma and is NaN there).
tests/test_homoclinic.py checks the constants against generated.roots, the orbit against generated.closed_form
evaluated in 256-bit arithmetic, and gamma = 0 against generated.closed_form_kirchhoff.  The float64 relative
accuracy of theta(t) is a few ulp times 1 + kappa |t| (the conditioning of exp(-kappa t) with respect to kappa).

Independent check (verify)
--------------------------
generated.field (Hamilton's equations eq:equivalent plus psi' = eq:psi_condition) is integrated with heyoka
from the turning point (theta = acos(u_+), pbar_theta = 0, psi = 0) forwards and backwards in time.  theta = 0
is a saddle with rate lambda = sqrt(-V''(0)) = kappa, so any error at the turning point grows like
exp(kappa t) while theta decays like exp(-kappa t): reaching theta = 1e-8 with an absolute error 1e-12 needs
an initial/round-off error below ~1e-20.  Moreover the generated field is a sum of terms ~1/sin^3(theta) that
cancel to O(theta): at theta = 1e-8 each term is ~1e24, so IEEE quad (real128, eps 1e-34) already loses the
1e-12 target (measured: 2e-11).  The check therefore runs in heyoka's multiprecision type hy.real with 256
bits (eps ~ 1e-77, ~0.3 s per direction) and compares with the generated closed form evaluated at the same
precision, and with the float64 stable form.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import heyoka as hy
import numpy as np

from ..core import systems
from ..core.precision import Precision
from ..core.errors import MAX_MAGNITUDE, ParameterError, require_finite
from ..generated import homoclinic as gen
from ..generated import scalars
from ..generated.names import CLOSED_FORM_REGULAR
from ..core.params import M_MIN
from ..core.results import Result

_PREC = 256  # bits of the multiprecision verification run (see module docstring)


def validate(m, gamma) -> tuple[float, float]:
    """(m, gamma) as floats; a homoclinic orbit of theta = 0 exists iff m > 0, gamma >= 0 and
    m^2 < 4 (1 + gamma) (eq:buckling_load_2: V''(0) = 1/4 - (1 + gamma)/m^2 < 0)."""
    m = require_finite("m", m, MAX_MAGNITUDE)
    gamma = require_finite("gamma", gamma, MAX_MAGNITUDE)
    if m <= 0:
        raise ParameterError("m", f"must be > 0, got {m}")
    if m < M_MIN:
        raise ParameterError("m", f"must be >= {M_MIN:g} (terms in m^-2 and m^-4), got {m}")
    if gamma < 0:
        raise ParameterError("gamma", f"must be >= 0 (gamma = 0 is the inextensible Kirchhoff rod), got {gamma}")
    if scalars.potential_dd0(m, gamma) >= 0:
        raise ParameterError("m", f"no homoclinic orbit: need m < m_c = {scalars.m_critical(gamma):.6g} "
                                  f"(V''(0) < 0, eq:buckling_load_2), got m = {m}")
    return m, gamma


def constant_expressions(m, gamma) -> dict:
    """u_+, 1 - k and kappa as heyoka expressions (generated constants_regular: no division by gamma, exact at
    gamma = 0 where they reduce to eq:Kirchhoff_homoclinic; report entry theta_homoclinic_regular)."""
    return dict(zip(("u_plus", "one_minus_k", "kappa"), gen.constants_regular(m, gamma)))


def stable_expressions(t, m, gamma) -> dict:
    """heyoka expressions of the homoclinic orbit in the tail-stable, gamma-regular form (generated
    closed_form_regular), keyed by CLOSED_FORM_REGULAR = (theta, ptheta, cos_theta, sin_theta, psidot).
    t, m, gamma: heyoka expressions (e.g. hy.time, hy.par[0], hy.par[1]); gamma = 0 is the Kirchhoff rod."""
    return dict(zip(_KEYS, gen.closed_form_regular(t, m, gamma)))


_KEYS = CLOSED_FORM_REGULAR


@systems.cache
def _stable_cfunc():
    t = hy.make_vars("t")
    e = stable_expressions(t, hy.par[0], hy.par[1])
    return systems.build(hy.cfunc, [e[k] for k in _KEYS], vars=[t])


@systems.cache
def _constants_cfunc():
    m, g = hy.par[0], hy.par[1]
    c0 = constant_expressions(m, g)
    return systems.build(hy.cfunc, [c0["u_plus"], c0["one_minus_k"], c0["kappa"], gen.roots(m, g)[1], gen.energy(m, g),
                     gen.m_critical(g)], vars=[])


@systems.cache
def _potential_cfunc(fp_type=float, prec=0):
    th = hy.make_vars("theta")
    kw = {"fp_type": fp_type, "prec": prec} if fp_type is hy.real else ({} if fp_type is float else
                                                                       {"fp_type": fp_type})
    return systems.build(hy.cfunc, [gen.potential(th, hy.par[0], hy.par[1])], vars=[th], **kw)


def _call(cf, x, m, gamma):
    """Evaluate a float64 cfunc of hy.par[0] = m (and hy.par[1] = gamma if it uses it) on x of shape
    (nvars, n) (heyoka wants exactly cf.nparams parameter rows)."""
    pars = np.array([[m] * x.shape[1], [gamma] * x.shape[1]], dtype=float)[: cf.nparams]
    return cf(x, pars=pars)


@dataclass(frozen=True, repr=False)
class HomoclinicOrbit(Result):
    """The homoclinic orbit of theta = 0 at lambdabar = mu = 0, pbar_psi = 1 (t = 0 at the turning point,
    pbar_theta < 0 for t > 0).  Constants from generated.homoclinic (u_minus = -inf, k = 1 for gamma = 0).
    `evaluate(t)`, `psibar(t)`, `time_at_theta`, and `verify()` (the independent multiprecision check);
    `.plot()` draws theta and pbar_theta against t."""

    m: float
    gamma: float
    u_plus: float  # cos theta at the turning point: the root u+ of the orbit's energy equation in u = cos theta
    u_minus: float  # its other root u- (-inf at gamma = 0)
    k: float  # the closed form's constant: cos theta(t) has (1 - k) tanh^2(kappa t) in its denominator (1 at gamma = 0)
    kappa: float  # = sqrt(-V''(0)), the saddle's eigenvalue (checked in tests)
    h: float  # homoclinic level V(0) = (1 + gamma/2)/m^2
    m_c: float  # 2 sqrt(1 + gamma), eq:buckling_load_2
    #: one_minus_k (1 - k without cancellation for small gamma) and, once run, verify()'s result
    extra: dict = field(default_factory=dict, compare=False)
    success: bool = True
    message: str = "closed form (derive/homoclinic.py); verify() compares an independent integration"
    system: object = field(default=None, compare=False)  # what was studied (the paper's rod at lam = mu = 0)

    _repr_fields = ("m", "gamma", "kappa", "theta_max", "h", "m_c")

    @property
    def accuracy(self) -> dict:
        """The closed form is exact (derive/homoclinic.py: proved); its numerical check against an independent
        multiprecision integration is `verify()` (~0.6 s, not run here), whose result, once run, is kept here."""
        return {"closed_form": "proved (symbolic)", "verify": self.extra.get("verify")}

    def verify(self, theta_stop: float = 1e-8, n: int = 201) -> dict:
        """The independent check of the closed form (module function `verify`: multiprecision integration of
        generated.field from the turning point), ~0.6 s."""
        out = verify(self, theta_stop=theta_stop, n=n)
        self.extra["verify"] = out
        return out

    @property
    def kirchhoff(self) -> bool:
        """True at gamma = 0 (the inextensible Kirchhoff rod's orbit)."""
        return self.gamma == 0.0

    @property
    def theta_max(self) -> float:
        """The turning point's angle, 2 asin(sqrt((1 - u_plus)/2))."""
        return float(2.0 * np.arcsin(np.sqrt((1.0 - self.u_plus) / 2.0)))

    @property
    def saddle_rate(self) -> float:
        """sqrt(-V''(0)) (generated scalars.saddle_rate; report entries fixed_points, saddle_rate)."""
        return scalars.saddle_rate(self.m, self.gamma)

    def evaluate(self, t) -> dict:
        """theta, pbar_theta, cos theta, sin theta, psi' at times t (float64, full relative accuracy in the
        tails; symmetric: theta even, pbar_theta odd).  Returns arrays of the shape of t."""
        t = np.asarray(t, dtype=float)
        flat = t.reshape(1, -1)
        out = _call(_stable_cfunc(), flat, self.m, self.gamma)
        return {k: out[i].reshape(t.shape) for i, k in enumerate(_KEYS)}

    def time_at_theta(self, theta) -> float:
        """t > 0 with theta(t) = theta (0 < theta <= theta_max): sin^2(theta/2) = A^2 y/(k + (1 - k) y) with
        y = sech^2(kappa t) solved for y."""
        s2 = np.sin(0.5 * float(theta)) ** 2
        a2 = 0.5 * (1.0 - self.u_plus)
        if not 0.0 < s2 <= a2:
            raise ParameterError("theta", f"must be in (0, theta_max = {self.theta_max:.6g}], got {theta}")
        omk = self.extra["one_minus_k"]
        y = s2 * (1.0 - omk) / (a2 - s2 * omk)
        return float(np.arccosh(1.0 / np.sqrt(min(y, 1.0))) / self.kappa)

    def psibar(self, t, tol=None) -> np.ndarray:
        """psibar(t) = int_0^t dt'/(1 + cos theta(t')) (eq:psi_condition; odd in t) by heyoka quadrature
        (Taylor integration of psibar' = psi'(t) with t = hy.time, tol = eps by default)."""
        t = np.asarray(t, dtype=float)
        grid, inv = np.unique(np.abs(t.ravel()), return_inverse=True)  # strictly increasing, psibar odd
        if tol is not None:
            tol = require_finite("tol", tol)
            if not 0 < tol < 1:
                raise ParameterError("tol", f"must be in (0, 1) (None: machine epsilon), got {tol!r}")
        ta = _psibar_integrator(tol)
        ta.time = 0.0
        ta.state[:] = 0.0
        ta.pars[:] = [self.m, self.gamma]
        if grid[0] > 0.0:  # the grid must start at ta.time
            vals = ta.propagate_grid(np.concatenate([[0.0], grid]))[-1][1:, 0]
        else:
            vals = ta.propagate_grid(grid)[-1][:, 0]
        return (np.sign(t.ravel()) * vals[inv]).reshape(t.shape)

    def summary(self) -> dict:
        # u_minus = -inf at gamma = 0 is reported as None (JSON has no infinity)
        um = self.u_minus if np.isfinite(self.u_minus) else None
        return {"m": self.m, "gamma": self.gamma, "u_plus": self.u_plus, "u_minus": um, "k": self.k,
                "kappa": self.kappa, "saddle_rate": self.saddle_rate, "theta_max": self.theta_max, "h": self.h,
                "m_c": self.m_c}


@systems.per_thread
def _psibar_integrator(tol=None):
    """psibar' = psi'(t) with t = hy.time; one per thread and tolerance (None: machine epsilon)."""
    psib = hy.make_vars("psibar")
    e = stable_expressions(hy.time, hy.par[0], hy.par[1])
    return systems.taylor([(psib, e["psidot"])], [0.0], [1.0, 1.0], tol=tol)


def homoclinic_orbit(system=None, gamma=None, *, m=None, precision=None, reversor=None, tol=None):
    """A homoclinic orbit to the saddle of a rod model.

    The paper's rod at lambdabar = mu = 0: the closed form of sec. 6 (fig:angles; below).  Any other model: a
    symmetric homoclinic orbit to its straight twisted rod, shot onto Fix(R) of the model's reversor
    (magrod.orbits.reversible.symmetric_homoclinic; a ParameterError naming the model if it has none).  The old
    spelling ``homoclinic_orbit(m, gamma)`` (the paper's rod's m and gamma) works for one release.

    Parameters
    ----------
    system : System, or what converts to one (magrod.core.system.as_system)
        The model and its parameters; the paper's rod needs lam = mu = 0 here (other parameters:
        multipulse_orbits).
    precision, tol : optional
        Other models: the shooting tolerance on ``max |x_flipped(T)|`` (default 1e-9).  precision: double only.
    reversor : Reversor, optional
        Other models: which reversor, where the model has several (magrod.orbits.equilibria.reversors).
    m, gamma : float, optional
        The old spelling: the paper's rod's m = m3/sqrt(B C2) > 0 (>= 1e-3, below the buckling value
        m_c = 2 sqrt(1 + gamma)) and extensibility gamma >= 0 (gamma = 0 is the inextensible Kirchhoff rod,
        eq:Kirchhoff_homoclinic).

    Returns
    -------
    HomoclinicOrbit or SymmetricOrbit
        Other models: a SymmetricOrbit (alpha, T, the reversor, residual, level drift, `.sample(n)`, `.system`).
        The paper's rod: the closed form, a HomoclinicOrbit with constants ``u_+``, ``u_-``, k, kappa (the
        saddle rate), h (the homoclinic level), m_c, theta_max; the orbit's `evaluate(t)` (theta, pbar_theta, cos theta, sin theta, psi'), `psibar(t)`, `time_at_theta(theta)`,
        `verify()` and `.plot()`.

    Raises
    ------
    ParameterError
        "m" if m <= 0, m < 1e-3 or m >= m_c (no homoclinic orbit: V''(0) >= 0); "gamma" if gamma < 0; either if
        not finite or beyond 1e6; "lam" for the paper's rod away from lam = mu = 0; "model" naming a model without
        a reversor fixing its saddle, or without a saddle; "precision" for another model in other than double.

    Examples
    --------
    >>> import magrod as mr
    >>> from magrod.orbits.homoclinic import homoclinic_orbit
    >>> orb = homoclinic_orbit(mr.System(m=1.7, gamma=1.0, mu=0, lam=0))
    >>> round(orb.theta_max, 12), round(orb.kappa, 12)
    (1.598491574827, 0.664862032674)
    >>> t = orb.time_at_theta(1e-3)
    >>> abs(float(orb.evaluate(t)["theta"]) - 1e-3) < 1e-15
    True
    >>> chk = orb.verify(n=21)
    >>> chk["max_dev_theta"] < 1e-12
    True

    Notes
    -----
    Method: the closed form ``cos theta = u_- + (u_+ - u_-)/D``, D = 1 - (1 - k) tanh^2(kappa t) derived by SymPy
    (derive/homoclinic.py), evaluated in a gamma-regular, tail-stable compiled form (relative accuracy a few ulp
    times ``1 + kappa |t|``).  Cost: microseconds per evaluation; psibar is a heyoka quadrature; `verify()`
    integrates generated.field in 256-bit arithmetic (~0.6 s) and compares.  Reference: Sinden & van der
    Heijden, sec. 6, eq:extensible_ham, fig:angles.
    """
    if m is not None or (isinstance(system, (int, float)) and not isinstance(system, bool)):
        import warnings

        warnings.warn("homoclinic_orbit(m, gamma) is deprecated: pass a System, e.g. homoclinic_orbit("
                      "mr.System(m=1.7, gamma=1, mu=0, lam=0))", DeprecationWarning, stacklevel=2)
        return homoclinic(system if m is None else m, gamma)
    from ..core.system import as_system

    system, _ = as_system(system)
    if system.is_paper:
        p = system.rod
        if p.lam != 0 or p.mu != 0:
            raise ParameterError("lam", f"the paper's rod's closed-form homoclinic orbit is at lam = mu = 0 (got lam = "
                                        f"{p.lam:g}, mu = {p.mu:g}); at other parameters use multipulse_orbits")
        from dataclasses import replace

        return replace(homoclinic(p.m, p.gamma), system=system)
    from ..core.precision import Precision
    from .reversible import symmetric_homoclinic

    if precision is not None and Precision.parse(precision) is not Precision.DOUBLE:
        raise ParameterError("precision", f"the symmetric homoclinic orbits of the model {system.model!r} are shot in "
                                          f"double precision only (their evidence: residual, level drift at tol = "
                                          f"eps), got {precision!r}")
    return symmetric_homoclinic(system, reversor=reversor, tol=tol)


def homoclinic(m, gamma) -> HomoclinicOrbit:
    """The homoclinic orbit at (m, gamma) (validated, see validate)."""
    m, gamma = validate(m, gamma)
    up, omk, kappa, um, h, mc = _constants_cfunc()(np.zeros(0), pars=np.array([m, gamma]))
    if gamma == 0.0:
        um = -np.inf  # generated.roots divides by gamma
    return HomoclinicOrbit(m, gamma, float(up), float(um), float(1.0 - omk), float(kappa), float(h), float(mc),
                           {"one_minus_k": float(omk)})


def phase_portrait_energy(theta, ptheta, m, gamma) -> np.ndarray:
    """(1/2) pbar_theta^2 + V(theta) (eq:eq_oscillator, generated.potential) on arrays of equal shape.
    generated.potential is a rational function of cos(theta), regular at theta = 0 (V(0) = h)."""
    theta = np.asarray(theta, dtype=float)
    ptheta = np.asarray(ptheta, dtype=float)
    flat = theta.reshape(1, -1)
    v = _call(_potential_cfunc(), flat, m, gamma)[0].reshape(theta.shape)
    return 0.5 * ptheta**2 + v


# ----------------------------------------------------------------------------------------------------------
# independent check: multiprecision integration of generated.field from the turning point


def _real(x, prec=_PREC):
    return hy.real(float(x), prec) if not isinstance(x, hy.real) else x


@systems.per_thread
def _field_integrator(prec: int):
    th, ps, pt = hy.make_vars("theta", "psi", "ptheta")
    f = gen.field(th, pt, hy.par[0], hy.par[1])
    return systems.taylor([(th, f[0]), (ps, f[1]), (pt, f[2])], [1, 0, 0], [1, 1], precision=Precision.MP, bits=prec,
                          compact_mode=True)


@systems.cache
def _closed_form_hp(prec: int, kirchhoff: bool):
    """The generated closed form (theta, pbar_theta, psi') in multiprecision (gamma = 0: theta, psi')."""
    t = hy.make_vars("t")
    if kirchhoff:
        c, psid = gen.closed_form_kirchhoff(t, hy.par[0])
        ex = [hy.acos(c), psid]
    else:
        c, pt, psid = gen.closed_form(t, hy.par[0], hy.par[1])
        ex = [hy.acos(c), pt, psid]
    return systems.build(hy.cfunc, ex, vars=[t], fp_type=hy.real, prec=prec)


@systems.cache
def _energy_hp(prec: int):
    th, pt = hy.make_vars("theta", "ptheta")
    return systems.build(hy.cfunc, [0.5 * pt**2 + gen.potential(th, hy.par[0], hy.par[1]) - gen.energy(hy.par[0], hy.par[1])],
                    vars=[th, pt], fp_type=hy.real, prec=prec)


def _hp_eval(cf, t_list, pars):
    """Evaluate a multiprecision cfunc point by point (returns an object array of shape (nout, n))."""
    return np.array([cf(np.array([x]), pars=pars) for x in t_list]).T


def verify(orbit: HomoclinicOrbit, theta_stop: float = 1e-8, n: int = 201, prec: int = _PREC) -> dict:
    """Integrate generated.field from the turning point (theta = acos(u_+), pbar_theta = psi = 0) forwards and
    backwards in hy.real(prec) to |t| = t_stop where theta(t_stop) = theta_stop, on n grid points per side, and
    compare with (i) the generated closed form at the same precision, (ii) the float64 stable form of
    HomoclinicOrbit.evaluate and psibar.  Also: energy H0 - h along the integration, parity residuals
    theta(-t) - theta(t), pbar_theta(-t) + pbar_theta(t), psi(-t) + psi(t).  Cost ~0.3 s per direction."""
    t0 = time.perf_counter()
    t_stop = orbit.time_at_theta(theta_stop)
    grid = np.linspace(0.0, t_stop, n)
    pars = np.array([_real(orbit.m, prec), _real(orbit.gamma, prec)])
    cf = _closed_form_hp(prec, orbit.kirchhoff)
    cf_pars = pars[: cf.nparams]  # closed_form_kirchhoff does not use gamma (hy.par[1])
    theta0 = cf(np.array([_real(0.0, prec)]), pars=cf_pars)[0]  # acos(u_+) at the working precision
    ta = _field_integrator(prec)
    sides = {}
    for sgn in (1.0, -1.0):
        ta.time = _real(0.0, prec)
        ta.state[:] = np.array([theta0, _real(0.0, prec), _real(0.0, prec)])
        ta.pars[:] = pars
        res = ta.propagate_grid([_real(sgn * x, prec) for x in grid])
        if res[0] != hy.taylor_outcome.time_limit:
            raise RuntimeError(f"homoclinic verification integration failed: {res[0]}")
        sides[sgn] = res[-1]  # (n, 3): theta, psi, ptheta
    fw, bw = sides[1.0], sides[-1.0]
    ref = _hp_eval(cf, [_real(x, prec) for x in grid], cf_pars)  # theta, (ptheta,) psi'
    d_theta_hp = float(np.max(np.abs(fw[:, 0] - ref[0])))
    d_ptheta_hp = None if orbit.kirchhoff else float(np.max(np.abs(fw[:, 2] - ref[1])))
    fw64 = fw.astype(float)
    st = orbit.evaluate(grid)
    psib = orbit.psibar(grid)
    en = _energy_hp(prec)
    dH = max(abs(float(en(np.array([a, b]), pars=pars)[0])) for a, b in zip(fw[:, 0], fw[:, 2]))
    out = {"theta_stop": theta_stop, "t_stop": t_stop, "n": n, "prec_bits": prec,
           "max_dev_theta": float(np.max(np.abs(fw64[:, 0] - st["theta"]))),
           "max_dev_ptheta": float(np.max(np.abs(fw64[:, 2] - st["ptheta"]))),
           "max_dev_psi": float(np.max(np.abs(fw64[:, 1] - psib))),
           "max_rel_dev_theta": float(np.max(np.abs(fw64[:, 0] - st["theta"]) / st["theta"])),
           "max_dev_theta_generated_hp": d_theta_hp, "max_dev_ptheta_generated_hp": d_ptheta_hp,
           "parity_theta": float(np.max(np.abs(bw[:, 0] - fw[:, 0]))),
           "parity_ptheta": float(np.max(np.abs(bw[:, 2] + fw[:, 2]))),
           "parity_psi": float(np.max(np.abs(bw[:, 1] + fw[:, 1]))),
           "max_abs_H0_minus_h": dH, "wall_time_s": time.perf_counter() - t0}
    out["arrays"] = {"t": grid, "theta_int": fw64[:, 0], "ptheta_int": fw64[:, 2], "psi_int": fw64[:, 1],
                     "theta_cf": st["theta"], "ptheta_cf": st["ptheta"], "psibar_cf": psib}
    return out
