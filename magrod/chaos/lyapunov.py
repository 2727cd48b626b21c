"""The maximal Lyapunov exponent of one orbit, with its history and the chaos verdict (`magrod.lyapunov`).

One call from a start (a paper panel, or parameters and a chart start on an energy level) to the indicators of
magrod/chaos/indicators.py: the root pbar_psi of Hbar = h (the section's root rule), the body-frame start, one
tangent vector renormalised every renorm_dt, projected onto the invariant level set of the first integrals.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.errors import ParameterError, require_finite
from ..core.params import RodParams
from ..core.deprecation import renamed_keywords
from ..core.precision import Precision
from ..core.results import Result
from ..core.tolerances import DRIFT_LIMIT
from .indicators import DEFAULT_RENORM_DT, GROWTH_THRESHOLD, OK, REASONS, body_indicators, model_indicators
from .section import DEFAULT_ROOT, level_starts, resolve, section_start, state_path

DEFAULT_T_MAX = 3000.0  # the Fig 4 orbits are sticky: T <= 2000 is marginal for the verdict (indicators.py)


@dataclass(repr=False)
class LyapunovResult(Result):
    """Chaos indicators of one orbit.

    lyap = L(T)/T (finite-time maximal Lyapunov exponent, per unit scaled arclength), fli = max L(t_k), fli_half
    the same over [0, T/2], growth_exponent = (fli - fli_half)/ln 2, chaotic = growth_exponent > threshold.
    times (K,) and log_growth (K,) = L(t_k) = ln |w(t_k)|: the history; lyap_history = log_growth/times.
    max_abs_dH, casimir_drift: conservation along the orbit; min_stretch: the smallest axial stretch v3."""

    success: bool
    message: str
    params: RodParams
    panel: str | None
    h: float
    theta0: float
    ptheta0: float
    psi0: float
    p_psi0: float
    t_max: float  # the scaled arclength T of the run
    renorm_dt: float  # the tangent vector is renormalised every renorm_dt
    lyap: float  # L(T)/T: the finite-time maximal Lyapunov exponent, per unit scaled arclength
    fli: float  # max L(t_k) over [0, T]: the fast Lyapunov indicator
    fli_half: float  # the same over [0, T/2]
    growth_exponent: float  # (fli - fli_half)/ln 2: about 1 on a regular orbit (linear growth), large on a chaotic one
    chaotic: bool  # growth_exponent > threshold
    threshold: float  # the growth exponent above which an orbit is called chaotic
    times: np.ndarray  # (K,) the renormalisation times t_k
    log_growth: np.ndarray  # (K,) L(t_k) = ln |w(t_k)|, the tangent vector's log growth
    max_abs_dH: float  # max |Hbar - h| along the orbit
    casimir_drift: float  # max drift of the Casimirs along the orbit
    min_stretch: float  # the smallest axial stretch v3 along the orbit
    system: object = None  # the System studied (core.system.System)

    _repr_fields = ("panel", "lyap", "growth_exponent", "chaotic", "t_max", "max_abs_dH", "casimir_drift")

    # older names (the model family's result, kept one release): the conservation as energy_error/casimir_error
    energy_error = property(lambda self: self.max_abs_dH, doc="Deprecated spelling of max_abs_dH.")
    casimir_error = property(lambda self: self.casimir_drift, doc="Deprecated spelling of casimir_drift.")

    @property
    def regular_bound(self) -> float:
        """10 ln T / T: the older verdict's bound on lyap (a regular orbit's estimate decays like ln t / t)."""
        return 10.0 * np.log(self.t_max) / self.t_max

    @property
    def lyap_history(self) -> np.ndarray:
        """L(t_k)/t_k: the finite-time exponent as it converges (K,)."""
        return self.log_growth / self.times

    @property
    def accuracy(self) -> dict:
        """Conservation along the orbit against DRIFT_LIMIT (the indicator is trusted only within it)."""
        ok = bool(np.isfinite(self.max_abs_dH) and self.max_abs_dH <= DRIFT_LIMIT
                  and np.isfinite(self.casimir_drift) and self.casimir_drift <= DRIFT_LIMIT)
        return {"max_abs_dH": self.max_abs_dH, "casimir_drift": self.casimir_drift, "limit": DRIFT_LIMIT,
                "passed": ok}

    def to_dict(self) -> dict:
        d = super().to_dict()
        d["system"] = None if self.system is None else self.system.to_dict()
        if not isinstance(self.params, RodParams):
            d["params"] = dict(self.params)
        return d

    def criterion(self) -> str:
        return f"chaotic iff growth_exponent = (FLI(T) - FLI(T/2))/ln 2 > {self.threshold:g}"


def check_run(t_max, renorm_dt) -> tuple:
    """(t_max, renorm_dt) of a tangent-vector run, validated: t_max > 0, 0 < renorm_dt <= t_max/2, at most 1e7
    renormalisations; ParameterError names the argument."""
    t_max = require_finite("t_max", t_max)
    if t_max <= 0:
        raise ParameterError("t_max", f"must be > 0, got {t_max}")
    renorm_dt = require_finite("renorm_dt", renorm_dt)
    if not 0 < renorm_dt <= t_max / 2:
        raise ParameterError("renorm_dt", f"must satisfy 0 < renorm_dt <= t_max/2 = {t_max / 2:g}, got {renorm_dt}")
    if t_max / renorm_dt > 1e7:
        raise ParameterError("renorm_dt", f"t_max/renorm_dt = {t_max / renorm_dt:.3g} renormalisations: at most 1e7")
    return t_max, renorm_dt


def body_start(params, h=None, theta0=None, ptheta0=None, psi0=None, p_psi0=None, root=DEFAULT_ROOT) -> tuple:
    """(params, panel key, h, theta0, ptheta0, psi0, p_psi0, x0 (9,), pars (5,)) of one orbit's start: a paper panel
    or RodParams with a chart start, pbar_psi0 the root of Hbar = h chosen by `root` (or given, h then computed),
    mapped to the body frame.  Shared by lyapunov, lyapunov_spectrum and gali.  The start is the sections' own
    (section_start: the same validation and error words; a given p_psi0 defines the level)."""
    s = section_start(params, None if p_psi0 is not None else h, theta0, ptheta0, psi0, p_psi0=p_psi0, root=root)
    params, key, h, theta0, ptheta0, psi0, p_psi0 = s.params, s.panel, s.h, s.theta0, s.ptheta0, s.psi0, s.p_psi0
    pars = params.array()
    x0 = s.body_state()
    return params, key, h, theta0, ptheta0, psi0, p_psi0, x0, pars


@renamed_keywords(params="system")
def lyapunov(system=None, h=None, theta0=None, ptheta0=None, psi0=None, *, p_psi0=None, root=DEFAULT_ROOT,
             t_max=DEFAULT_T_MAX, renorm_dt=DEFAULT_RENORM_DT, tol=None, project=True, model=None, x0=None,
             level_of=None, seed=0, precision=None, **overrides) -> LyapunovResult:
    """Maximal Lyapunov exponent, Fast Lyapunov Indicator and growth exponent of one orbit, with the history.

    Parameters
    ----------
    system : System, RodParams, Panel or str
        What is studied (magrod.System or what converts to it): a paper panel ("4a" .. "5d") whose parameters and
        start fill in what is not given, a RodParams, or any model (a name or a model file: its body frame, start
        `x0`); None: the paper's rod at Fig 4(a).
    h, theta0, ptheta0, psi0, p_psi0, root
        The start, as in `poincare_section` (pbar_psi0 solves Hbar = h; `root` picks the root).
    t_max : float
        Length of the run in scaled arclength (default 3000: the Fig 4 orbits are sticky).
    renorm_dt : float
        Renormalisation interval of the tangent vector (and sampling step of the history).
    tol : float, optional
        Taylor tolerance (default machine epsilon).
    project : bool
        Project the tangent vector onto the invariant level set of C1, C2, C3, H and m3 (removes the linear shear
        between neighbouring leaves, which is not the orbit's own instability).
    **overrides : float
        Model parameters replacing those of `params`: ``lyapunov("4a", lam=0.15)``.
    model : str or path, keyword-only
        The model when `system` is a dict of its parameter values.
    x0 : array, keyword-only
        Any model but the paper's: the start (dim,), put on the level of `level_of` (default its own); default the
        model's reference state.
    level_of : array, keyword-only
        Any model: the state whose level of H and the Casimirs the start is put on.
    seed : int, keyword-only
        Unused for a given start (kept for the older spelling of the model path).
    precision : Precision or str, keyword-only
        "double" only (the tangent integrator is a float64 SIMD batch).

    Returns
    -------
    LyapunovResult
        lyap, fli, growth_exponent, chaotic, the history (times, log_growth, lyap_history) and conservation.

    Raises
    ------
    ParameterError
        Naming the argument (no energy root, theta0 outside (0, pi), t_max or renorm_dt not positive, ...).

    Examples
    --------
    >>> import magrod as mr
    >>> ly = mr.lyapunov("4a", t_max=1000)
    >>> ly.success, ly.times.shape, bool(ly.lyap > 0)
    (True, (100,), True)
    >>> bool(mr.lyapunov("kirchhoff", t_max=200).chaotic)   # the integrable Kirchhoff rod
    False

    Notes
    -----
    Criterion (magrod.chaos.indicators): chaotic iff growth_exponent > 3.  An orbit with exponent lyap is seen as
    chaotic once lyap T/(2 ln 2) > 3.  Cost: ~5 us per unit time in a SIMD batch (one lane used here; for many
    orbits use `chaos_map`).  References: Benettin et al. 1980; Froeschle, Lega & Gonczi 1997.
    """
    system, params = resolve(system, model, overrides, precision)
    if system is None:
        raise ParameterError("system", "one System, panel or RodParams (many orbits: chaos_map)")
    if system.precision is not Precision.DOUBLE:
        raise ParameterError("precision", f"must be 'double' for Lyapunov exponents (a float64 SIMD tangent "
                                          f"integrator), got {system.precision.value!r}")
    t_max, renorm_dt = check_run(t_max, renorm_dt)
    if not system.is_paper or x0 is not None or state_path(system, params, theta0, ptheta0, h, p_psi0):
        return _model_lyapunov(system, x0, level_of, t_max=t_max, renorm_dt=renorm_dt, tol=tol, project=project)
    params, key, h, theta0, ptheta0, psi0, p_psi0, x0, pars = body_start(params, h, theta0, ptheta0, psi0, p_psi0,
                                                                         root)
    ind = body_indicators(x0[:, None], pars, t_max=t_max, tol=tol, renorm_dt=renorm_dt, project=project,
                          history=True)
    status = int(ind.status[0])
    ok = status == OK
    message = "ok" if ok else f"indicator not computed: {REASONS[status]}"
    return LyapunovResult(ok, message, params, key, float(h), float(theta0), float(ptheta0), float(psi0),
                          float(p_psi0), float(t_max), float(ind.renorm_dt), float(ind.lyap[0]), float(ind.fli[0]),
                          float(ind.fli_half[0]), float(ind.growth_exponent[0]), bool(ind.chaotic[0]),
                          GROWTH_THRESHOLD, ind.times, ind.log_growth[0], float(ind.max_abs_dH[0]),
                          float(ind.casimir_drift[0]), float(ind.min_stretch[0]), system)


def _model_lyapunov(system, x0, level_of, *, t_max, renorm_dt, tol, project) -> LyapunovResult:
    """`lyapunov` of any model but the paper's: its start on its level (section.level_starts), the one indicator
    engine (indicators.model_indicators), conservation relative to the size of H's and the Casimirs' terms."""
    start = level_starts(system, None if x0 is None else [x0], level_of=level_of, name="x0")[0]
    ind = model_indicators(system, start.x0[:, None], t_max=t_max, tol=tol, renorm_dt=renorm_dt, project=project,
                           history=True)
    status = int(ind.status[0])
    ok = status == OK
    message = "ok" if ok else f"indicator not computed: {REASONS[status]}"
    nan = float("nan")
    return LyapunovResult(ok, message, dict(system.params), None, start.h, nan, nan, nan, nan, float(t_max),
                          float(ind.renorm_dt), float(ind.lyap[0]), float(ind.fli[0]), float(ind.fli_half[0]),
                          float(ind.growth_exponent[0]), bool(ind.chaotic[0]), GROWTH_THRESHOLD, ind.times,
                          ind.log_growth[0], float(ind.max_abs_dH[0]), float(ind.casimir_drift[0]), nan, system)
