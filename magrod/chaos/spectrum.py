"""The Lyapunov spectrum and the GALI indices of one orbit: `lyapunov_spectrum`, `gali`.

Both integrate the full first-order variational system x' = f(x), Phi' = Df(x) Phi of the singularity-free body
frame (9-D, generated/body.py; built by magrod.core.systems.variational_integrator, sensitivities w.r.t. the state
only) and act on its columns every renorm_dt:

  spectrum (Benettin et al. 1980, the QR form of Shimada & Nagashima 1979)  the columns are an orthonormal frame
           Q; after each interval Phi Q = Q' R (QR with the signs fixed so diag R > 0, the same on every LAPACK),
           ln R_ii are summed and Q' is the next frame.  lambda_i(T) = (1/T) sum ln R_ii, in decreasing order.
  GALI_k   (Skokos, Bountis & Antonopoulos 2007, Physica D 231, 30)  k deviation vectors, each renormalised to unit
           length (directions kept, no orthogonalisation); GALI_k = the volume of the parallelepiped of the unit
           vectors = the product of the singular values of the n x k matrix.  Chaotic orbits: the vectors align
           with the most unstable direction and GALI_k ~ exp(-[(l1 - l2) + ... + (l1 - lk)] t).  Regular orbits:
           GALI_k stays bounded away from 0 for k up to the torus dimension and decays as a power of t beyond it.

What to expect of the rod (numerical, checked in tests/test_spectrum.py).  The body system x' = J(x) grad H is a
Lie-Poisson system with 3 Casimirs; its symplectic leaves are 6-D and carry, for the isotropic rod, the two
integrals H and m3 (the twist).  The 9 exponents are therefore (l, 0, 0, 0, 0, 0, 0, 0, -l): three zeros for the
Casimir directions (no dynamics transverse to a leaf beyond a linear shear), two each for H and m3 (the flow
direction and its conjugate, the m3-rotation and its conjugate), and one pair +-l, l the maximal exponent of
`lyapunov`.  The finite-time values converge to these as ~ln(T)/T (the zeros) and ~1/T (the pair's sum).
Integrable limits (lambdabar = 0: the Kirchhoff rod; gamma = delta = 0) have all exponents -> 0.

Cost: the 90-equation variational system in compact mode, one orbit at a time: ~0.3 ms per unit time (measured
on the AVX-512 machine: benchmarks/README.md), plus one 9 x 9 QR (or SVD) per renorm_dt.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core import systems
from ..core.errors import ParameterError
from ..core.params import RodParams
from ..core.results import Result
from ..core.tolerances import DRIFT_LIMIT
from .indicators import DEFAULT_RENORM_DT, _steps, reference_system
from .lyapunov import DEFAULT_T_MAX, body_start, check_run
from .section import DEFAULT_ROOT, level_starts, resolve, state_path

GALI_ORDERS = (2, 3, 4)
_W_SEED = 29  # the fixed generic start vectors of GALI (same on every machine)


@systems.per_thread
def _body_variational(tol):
    """The body system's variational integrator w.r.t. the state (9 + 81 equations), one per thread and tol."""
    return systems.variational_integrator("body", wrt_pars=False, tol=tol)


def _reference_variational(name: str, tol):
    import heyoka as hy

    sys_, p = reference_system(name)
    vs = hy.var_ode_sys(sys_, hy.var_args.vars, order=1)
    return systems.taylor(vs, [0.0] * len(sys_), p, tol=tol, compact_mode=True), len(sys_), p


def _qr(W):
    """QR with diag(R) > 0: the factorisation is then unique, so Q does not depend on the LAPACK kernel's signs."""
    Q, R = np.linalg.qr(W)
    s = np.sign(np.diag(R))
    s[s == 0] = 1.0
    return Q * s, (R.T * s).T


def _run(ta, n, x0, pars, *, t_max, renorm_dt, W0, mode, check=None, reorthonormalise=True):
    """Integrate x and the columns W0 (n, k) of the tangent flow; every interval: "spectrum" -> QR (running sums of
    ln R_ii), "gali" -> unit columns and GALI_k for k in GALI_ORDERS.  Returns (times (K,), history (K, k or 3),
    drift (2,) or None, failure message or None)."""
    import heyoka as hy

    nsteps, dt = _steps(float(t_max), renorm_dt)
    k = W0.shape[1]
    ta.time = 0.0
    ta.state[:n] = x0
    if len(pars):
        ta.pars[:] = pars
    D = np.zeros((n, n))
    D[:, :k] = W0
    ta.state[n:n + n * n] = D.ravel()
    times = dt * np.arange(1, nsteps + 1)
    hist = np.full((nsteps, k if mode == "spectrum" else len(GALI_ORDERS)), np.nan)
    sums = np.zeros(k)
    drift = np.zeros(2)
    for j in range(nsteps):
        oc = ta.propagate_until(float(times[j]))[0]
        if oc != hy.taylor_outcome.time_limit:
            return times, hist, drift, f"integration stopped at t = {ta.time:g} ({oc})"
        W = np.array(ta.state[n:n + n * n]).reshape(n, n)[:, :k]
        if not np.all(np.isfinite(W)):
            return times, hist, drift, f"tangent vectors not finite at t = {ta.time:g}"
        if mode == "spectrum":
            if reorthonormalise:
                Q, R = _qr(W)
                sums += np.log(np.diag(R))
            else:  # the control of tests/test_spectrum.py: columns only rescaled, never orthogonalised
                norms = np.linalg.norm(W, axis=0)
                Q, sums = W / norms, sums + np.log(norms)
            hist[j] = sums / times[j]
        else:
            Q = W / np.linalg.norm(W, axis=0)
            # GALI_m of the first m unit vectors: the product of the singular values of those m columns
            hist[j] = [float(np.prod(np.linalg.svd(Q[:, :m], compute_uv=False))) for m in GALI_ORDERS]
        D[:, :k] = Q
        ta.state[n:n + n * n] = D.ravel()
        if check is not None:
            drift = np.maximum(drift, check(np.array(ta.state[:n])))
    return times, hist, drift, None


def _body_check(x0, pars):
    f = systems.body_functions()
    H0, C0 = f["H"](x0, pars)[0], f["casimirs"](x0, pars)

    def check(x):
        return np.array([abs(float(f["H"](x, pars)[0] - H0)), float(np.max(np.abs(f["casimirs"](x, pars) - C0)))])
    return check


# ----------------------------------------------------------------------------------------------------------
# results
# ----------------------------------------------------------------------------------------------------------
@dataclass(repr=False)
class LyapunovSpectrum(Result):
    """The finite-time Lyapunov spectrum of one orbit.

    exponents (n,): lambda_1 >= ... >= lambda_n at T (per unit scaled arclength); times (K,) and history (K, n):
    the running exponents at the renormalisation times.  `pairing` (n//2,): lambda_i + lambda_{n+1-i} (0 for a
    Hamiltonian flow); `accuracy`: pairing, the sum (the mean divergence, 0 here), conservation."""

    success: bool
    message: str
    control: str  # "body" (a rod model in its body frame) or the control system ("lorenz", "henon_heiles")
    params: RodParams | dict | None
    panel: str | None
    x0: np.ndarray
    t_max: float
    renorm_dt: float
    exponents: np.ndarray
    times: np.ndarray  # (K,) the renormalisation times
    history: np.ndarray
    max_abs_dH: float
    casimir_drift: float
    system: object = None  # the System studied (None for a control system)

    _repr_fields = ("control", "panel", "exponents", "t_max", "max_abs_dH")

    @property
    def pairing(self) -> np.ndarray:
        """(n//2,) lambda_i + lambda_{n+1-i}: 0 for a Hamiltonian flow (the spectrum's own check)."""
        e = self.exponents
        n = e.size
        return np.array([e[i] + e[n - 1 - i] for i in range(n // 2)])

    @property
    def max_exponent(self) -> float:
        """lambda_1, the maximal exponent."""
        return float(self.exponents[0])

    @property
    def accuracy(self) -> dict:
        """The largest |pairing|, the sum of the exponents (the mean divergence: 0 for a Hamiltonian flow), the
        conservation against DRIFT_LIMIT and whether it passed."""
        ok = bool(self.control != "body" or (self.max_abs_dH <= DRIFT_LIMIT and self.casimir_drift <= DRIFT_LIMIT))
        return {"max_pairing": float(np.max(np.abs(self.pairing))) if self.pairing.size else 0.0,
                "sum": float(np.sum(self.exponents)), "max_abs_dH": self.max_abs_dH,
                "casimir_drift": self.casimir_drift, "limit": DRIFT_LIMIT, "passed": ok}


@dataclass(repr=False)
class GaliResult(Result):
    """GALI_k (k = 2, 3, 4) of one orbit: times (K,), gali (K, 3) in the order of `orders`.  `decay()` fits the
    late half of each curve both ways: an exponential rate (d ln GALI/dt) and a power (d ln GALI/d ln t)."""

    success: bool
    message: str
    control: str  # "body" (a rod model in its body frame) or the control system ("lorenz", "henon_heiles")
    params: RodParams | dict | None
    panel: str | None
    x0: np.ndarray
    t_max: float
    renorm_dt: float
    orders: tuple  # the orders k of the columns of gali: (2, 3, 4)
    times: np.ndarray  # (K,) the renormalisation times
    gali: np.ndarray  # (K, 3) GALI_k at those times, one column per order
    max_abs_dH: float
    casimir_drift: float
    system: object = None  # the System studied (None for a control system)

    _repr_fields = ("control", "panel", "final", "t_max")

    @property
    def final(self) -> dict:
        """{"GALI_k": its value at the end of the run}."""
        return {f"GALI_{k}": float(self.gali[-1, i]) for i, k in enumerate(self.orders)}

    def decay(self, floor: float = 1e-14) -> dict:
        """{k: {"rate": slope of ln GALI_k against t, "power": slope against ln t}} over the second half of the run
        (or up to where GALI_k first falls below `floor`, the end of its meaningful range in double precision)."""
        out = {}
        for i, k in enumerate(self.orders):
            g = self.gali[:, i]
            stop = int(np.argmax(g < floor)) if np.any(g < floor) else g.size
            lo = stop // 2
            t, lg = self.times[lo:stop], np.log(np.maximum(g[lo:stop], 1e-300))
            if t.size < 2:
                out[k] = {"rate": math.nan, "power": math.nan, "until": float(self.times[max(stop - 1, 0)])}
                continue
            out[k] = {"rate": float(np.polyfit(t, lg, 1)[0]), "power": float(np.polyfit(np.log(t), lg, 1)[0]),
                      "until": float(t[-1])}
        return out

    @property
    def accuracy(self) -> dict:
        """The conservation (max |Hbar - h|, Casimir drift) against DRIFT_LIMIT and whether it passed."""
        ok = bool(self.control != "body" or (self.max_abs_dH <= DRIFT_LIMIT and self.casimir_drift <= DRIFT_LIMIT))
        return {"max_abs_dH": self.max_abs_dH, "casimir_drift": self.casimir_drift, "limit": DRIFT_LIMIT,
                "passed": ok}


def _to_dict(self) -> dict:
    """Every field as JSON-able data (as Result.to_dict), the System studied as its own dict."""
    d = Result.to_dict(self)
    d["system"] = None if self.system is None else self.system.to_dict()
    if isinstance(self.params, dict):
        d["params"] = dict(self.params)
    return d


LyapunovSpectrum.to_dict = _to_dict
GaliResult.to_dict = _to_dict
LyapunovSpectrum.formulation = GaliResult.formulation = property(
    lambda self: self.control, doc="Deprecated spelling of control (the field was called system).")


# ----------------------------------------------------------------------------------------------------------
# the public functions
# ----------------------------------------------------------------------------------------------------------
CONTROLS = ("lorenz", "henon_heiles")


def _control_keyword(fn):
    """The older spelling system="lorenz" (the control system; `system` is now the first argument, what is
    studied) keeps working for one release as control=, with one DeprecationWarning."""
    import functools
    import warnings

    @functools.wraps(fn)
    def inner(*args, **kw):
        if isinstance(kw.get("system"), str) and (args or "params" in kw):
            warnings.warn(f"{fn.__name__}(system={kw['system']!r}) is deprecated: the control system is now "
                          f"control=; system is what is studied", DeprecationWarning, stacklevel=2)
            kw["control"] = kw.pop("system")
        if "params" in kw:
            warnings.warn(f"{fn.__name__}(params=...) is deprecated: the argument is now called system",
                          DeprecationWarning, stacklevel=2)
            kw["system"] = kw.pop("params")
        return fn(*args, **kw)

    inner.__deprecated_keywords__ = {"params": "system"}
    return inner


def _model_check(system, x0):
    """The conservation of a model along a run, relative to the size of its H's and Casimirs' terms at x0."""
    from .indicators import _ModelCheck

    chk = _ModelCheck(system, np.asarray(x0, float)[:, None], system.array()[:, None])

    def check(x):
        _, d = chk(np.asarray(x, float)[:, None], system.array()[:, None])
        return d[:2, 0]
    return check


def _prepare(system, h, theta0, ptheta0, psi0, p_psi0, root, t_max, renorm_dt, tol, control, model, x0, level_of,
             overrides):
    t_max, renorm_dt = check_run(t_max, renorm_dt)
    if control in (None, "body"):
        sys_, params = resolve(system, model, overrides)
        if sys_ is None:
            raise ParameterError("system", "one System, panel or RodParams")
        if not sys_.is_paper or x0 is not None or state_path(sys_, params, theta0, ptheta0, h, p_psi0):
            start = level_starts(sys_, None if x0 is None else [x0], level_of=level_of, name="x0")[0]
            return (systems.model_variational(sys_, tol), len(start.x0), start.x0, sys_.array(),
                    dict(sys_.params), None, _model_check(sys_, start.x0), t_max, renorm_dt, sys_)
        params, key, *_, x0_, pars = body_start(params, h, theta0, ptheta0, psi0, p_psi0, root)
        return (_body_variational(tol), systems.dim("body"), x0_, pars, params, key,
                _body_check(x0_, pars), t_max, renorm_dt, sys_)
    if control not in CONTROLS:
        raise ParameterError("system", f"unknown control system {control!r}; choose body (a rod), lorenz or "
                                       "henon_heiles")
    ta, n, p = _reference_variational(control, tol)
    start = np.asarray(system if x0 is None else x0, float)
    if start.shape != (n,) or not np.all(np.isfinite(start)):
        raise ParameterError("x0", f"the start of {control} must be {n} finite numbers, got {system!r}")
    return ta, n, start, np.asarray(p, float), None, None, None, t_max, renorm_dt, None


@_control_keyword
def lyapunov_spectrum(system=None, h=None, theta0=None, ptheta0=None, psi0=None, *, p_psi0=None, root=DEFAULT_ROOT,
                      t_max=DEFAULT_T_MAX, renorm_dt=DEFAULT_RENORM_DT, tol=None, control=None, model=None, x0=None,
                      level_of=None, _reorthonormalise=True, **overrides) -> LyapunovSpectrum:
    """The Lyapunov spectrum of one orbit: all n finite-time exponents by QR re-orthonormalisation (Benettin).

    Parameters
    ----------
    system : System, RodParams, Panel or str, or a start (n,)
        What is studied: a paper panel ("4a" .. "5d") whose parameters and start fill in what is not given, a
        RodParams, or any model (a System, a name or a model file: its body frame, from `x0` or its reference
        state on its level); with `control` "lorenz" or "henon_heiles", the start state.
    h, theta0, ptheta0, psi0, p_psi0, root
        The start, as in `lyapunov`.
    t_max : float
        Length of the run (scaled arclength; default 3000).
    renorm_dt : float
        Interval between QR re-orthonormalisations (default 10: the rod's exponents are ~0.02, so a frame grows
        by ~e^0.2 in between; a stiff contraction, e.g. Lorenz's -14.6, needs renorm_dt ~ 0.1).
    tol : float, optional
        Taylor tolerance (default machine epsilon).
    control : str, optional
        None (the system given), "lorenz" (sigma, r, b = 10, 28, 8/3) or "henon_heiles": a control system of
        textbook values (the older spelling system="lorenz" is deprecated).
    model, x0, level_of, **overrides
        As in `lyapunov`.

    Returns
    -------
    LyapunovSpectrum
        exponents (n,) decreasing, the running history, `pairing`, `accuracy` (pairing, sum, conservation).

    Raises
    ------
    ParameterError
        Naming the argument (no energy root, t_max or renorm_dt out of range, an unknown system, a bad start).

    Examples
    --------
    >>> import magrod as mr
    >>> sp = mr.lyapunov_spectrum("4a", t_max=200)
    >>> sp.success, sp.exponents.shape, bool(abs(sp.exponents.sum()) < 1e-6)
    (True, (9,), True)

    Notes
    -----
    Expected for the rod: (l, 0 x 7, -l) (module magrod.chaos.spectrum), l the maximal exponent of `lyapunov`.
    Controls (tests/test_spectrum.py): Lorenz lambda_1 = 0.9056 and the sum -(sigma + 1 + b) (Sprott 2003);
    Henon-Heiles pairing.  References: Benettin, Galgani, Giorgilli & Strelcyn, Meccanica 15 (1980) 9 and 21;
    Skokos, Lect. Notes Phys. 790 (2010) 63.  Cost ~0.3 ms per unit time of the 90-equation system.
    """
    ta, n, x0, pars, params, key, check, t_max, renorm_dt, sys_ = _prepare(
        system, h, theta0, ptheta0, psi0, p_psi0, root, t_max, renorm_dt, tol, control, model, x0, level_of, overrides)
    control = "body" if control is None else control
    times, hist, drift, fail = _run(ta, n, x0, pars, t_max=t_max, renorm_dt=renorm_dt, W0=np.eye(n),
                                    mode="spectrum", check=check, reorthonormalise=_reorthonormalise)
    ex = hist[-1].copy() if fail is None else np.full(n, np.nan)
    if fail is None:
        order = np.argsort(-ex, kind="stable")  # QR keeps them ordered in the limit; sorted for a finite T
        ex, hist = ex[order], hist[:, order]
    ok = bool(fail is None and (control != "body" or max(drift) <= DRIFT_LIMIT))
    msg = "ok" if ok else (fail or f"conservation beyond DRIFT_LIMIT (|dH| {drift[0]:.1e}, Casimirs {drift[1]:.1e})")
    return LyapunovSpectrum(ok, msg, control, params, key, np.asarray(x0, float), float(t_max), float(times[0]), ex,
                            times, hist, float(drift[0]) if control == "body" else math.nan,
                            float(drift[1]) if control == "body" else math.nan, sys_)


@_control_keyword
def gali(system=None, h=None, theta0=None, ptheta0=None, psi0=None, *, p_psi0=None, root=DEFAULT_ROOT,
         t_max=DEFAULT_T_MAX, renorm_dt=DEFAULT_RENORM_DT, tol=None, control=None, model=None, x0=None, level_of=None,
         **overrides) -> GaliResult:
    """The Generalized Alignment Indices GALI_2, GALI_3, GALI_4 of one orbit (Skokos, Bountis & Antonopoulos 2007).

    Parameters
    ----------
    system : System, RodParams, Panel or str, or a start (n,)
        As in `lyapunov_spectrum`.
    h, theta0, ptheta0, psi0, p_psi0, root
        The start, as in `lyapunov`.
    t_max : float
        Length of the run (default 3000).
    renorm_dt : float
        Interval at which the deviation vectors are rescaled to unit length and GALI_k is sampled.
    tol : float, optional
        Taylor tolerance (default machine epsilon).
    control, model, x0, level_of, **overrides
        As in `lyapunov_spectrum`.

    Returns
    -------
    GaliResult
        times (K,), gali (K, 3) for k = 2, 3, 4, `decay()` (exponential rate and power of each), `final`.

    Raises
    ------
    ParameterError
        Naming the argument, as in `lyapunov_spectrum`.

    Examples
    --------
    >>> import magrod as mr
    >>> g = mr.gali("4a", t_max=200)
    >>> g.success, g.gali.shape
    (True, (20, 3))

    Notes
    -----
    GALI_k = product of the singular values of the k unit deviation vectors (the volume they span).  Chaotic:
    exponential decay, rate (l1 - l2) + ... + (l1 - lk) -- for the rod (l2 = ... = 0) (k - 1) l1.  Regular: a
    power law (Skokos et al. 2007: constant up to the torus dimension, then t^(-2(k - N)) in a canonical system of
    N degrees of freedom).  Start vectors: k fixed seeded Gaussian directions.  Values below ~1e-15 are rounding.
    """
    ta, n, x0, pars, params, key, check, t_max, renorm_dt, sys_ = _prepare(
        system, h, theta0, ptheta0, psi0, p_psi0, root, t_max, renorm_dt, tol, control, model, x0, level_of, overrides)
    control = "body" if control is None else control
    k = max(GALI_ORDERS)
    if n < k:
        raise ParameterError("system", f"GALI_{k} needs at least {k} dimensions, {control} has {n}")
    W0 = np.random.default_rng(_W_SEED).standard_normal((n, k))
    W0 /= np.linalg.norm(W0, axis=0)
    times, hist, drift, fail = _run(ta, n, x0, pars, t_max=t_max, renorm_dt=renorm_dt, W0=W0, mode="gali",
                                    check=check)
    ok = bool(fail is None and (control != "body" or max(drift) <= DRIFT_LIMIT))
    msg = "ok" if ok else (fail or f"conservation beyond DRIFT_LIMIT (|dH| {drift[0]:.1e}, Casimirs {drift[1]:.1e})")
    return GaliResult(ok, msg, control, params, key, np.asarray(x0, float), float(t_max), float(times[0]),
                      GALI_ORDERS, times, hist, float(drift[0]) if control == "body" else math.nan,
                      float(drift[1]) if control == "body" else math.nan, sys_)
