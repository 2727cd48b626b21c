"""Energy-level Poincare sections and a chaos indicator for any rod model of the family (issue 26), in the
body frame x' = J(x) grad H of the model (generated/models/<name>/body.py, or a model file's cache entry).

Level.  The orbits of one section share the level of H and of every Casimir found for the model
(names.CASIMIRS): starts are the model's reference state plus seeded perturbations, each projected onto the
level of the reference (or of the given `level_of` state) by Gauss-Newton least-norm steps with the generated
gradients, to |g(x) - g0| <= LEVEL_TOL.
Section.  The model's section function (names / SECTION of the model file) crossed upwards; a stopping terminal
event lands the state on it to ~1e-17 (heyoka).
Conservation.  max |H - h0| and max |C_k - C_k0| over every crossing of every orbit: `verify=True` makes
success require both <= ENERGY_TOL, CASIMIR_TOL (core/tolerances.py).
Indicator.  The maximal Lyapunov exponent by Benettin's method: the tangent system w' = Df(x) w (heyoka's own
derivatives of the generated right-hand side), w renormalised every renorm_dt; the history is kept.  A regular
orbit's estimate decays like log(t)/t, a chaotic one's levels off: `chaotic` compares the estimate with
REGULAR_BOUND = 10 log(t_max) / t_max (a regular orbit of these models stays below ~3 log t / t; stated, not
tuned to a test).

Results.  ModelSection, ModelLyapunov and ModelChaosMap are the body-frame counterparts of the paper's rod's
PoincareResult, LyapunovResult and ChaosMap: the same Result base (success, status, message, a short repr,
to_dict(), plot()), an `accuracy` property with PoincareResult.accuracy's keys (max_abs_dH, casimir_drift,
energy_tol, casimir_tol, energy_ok, casimir_ok, passed), and max_abs_dH / casimir_drift (ChaosMap:
max_casimir_drift) as read-only aliases of their energy_error / casimir_error fields (tests/test_models_results.py).
Integrators are built once per model and thread and reset (core/systems.py).  Cost: a 6-D section of 4 orbits x
200 crossings ~0.1 s after the first compile (~0.5 s, then heyoka's disk cache).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..core import systems
from ..core.errors import ParameterError
from ..core.models import resolve
from ..core.results import Result
from ..core.tolerances import CASIMIR_TOL, ENERGY_TOL, EPS, MODEL_LEVEL_TOL

LEVEL_TOL = MODEL_LEVEL_TOL  # Gauss-Newton projection of the starts onto the level (core/tolerances.py)
PERTURBATION = 0.05  # size of the seeded perturbations of the reference state


def _cfuncs(mc):
    """Compiled (H, C1, ...) and their gradients for the model (one per model and process, systems.cache)."""
    _BY_DIR[mc.directory] = mc
    return _cfuncs_dir(mc.directory)


@systems.cache
def _cfuncs_dir(directory: str):
    import heyoka as hy

    mc = resolve_dir(directory)
    xs = hy.make_vars(*mc.names.STATE)
    pars = mc.body.pars()
    return (systems.CFunc(mc.body.constraints(*xs, *pars), xs),
            systems.CFunc(mc.body.constraint_gradients(*xs, *pars), xs))


@systems.per_thread
def _integrator(directory: str, kind: str, tol=None):
    """The model's integrator: kind 'section' (stopping terminal event on the section, upwards) or 'tangent'
    (state plus one tangent vector); tol None = machine epsilon."""
    import heyoka as hy

    mc = resolve_dir(directory)
    sys_ = mc.body.system()
    n = mc.dim
    if kind == "section":
        xs = [v for v, _ in sys_]
        sec = mc.body.section(*xs, *mc.body.pars())
        ev = hy.t_event(sec, direction=hy.event_direction.positive)
        return systems.taylor(sys_, list(mc.names.REFERENCE), mc.names.DEFAULTS, t_events=[ev], tol=tol)
    ws = hy.make_vars(*[f"w{i}" for i in range(n)])
    xs = [v for v, _ in sys_]
    tang = [sum((hy.diff(f, x) * w for x, w in zip(xs, ws)), hy.expression(0.0)) for _, f in sys_]
    full = sys_ + list(zip(ws, tang))
    return systems.taylor(full, list(mc.names.REFERENCE) + [1.0] + [0.0] * (n - 1), mc.names.DEFAULTS,
                          compact_mode=True)


_BY_DIR: dict = {}


def resolve_dir(directory: str):
    return _BY_DIR[directory]


def _model(model):
    mc = resolve(model)
    _BY_DIR[mc.directory] = mc
    return mc


def project_to_level(mc, x, g0, pars, max_steps: int = 50) -> np.ndarray:
    """x moved to the level g(x) = g0 of (H, C1, ...) by least-norm Gauss-Newton steps."""
    g, dg = _cfuncs(mc)
    n = mc.dim
    x = np.array(x, dtype=float)
    for _ in range(max_steps):
        r = g(x, pars) - g0
        if np.max(np.abs(r)) <= LEVEL_TOL:
            return x
        G = dg(x, pars).reshape(len(g0), n)
        x = x - G.T @ np.linalg.solve(G @ G.T, r)
    raise ParameterError("x0", f"could not put a start on the level of H and the Casimirs of {mc.name!r} "
                               f"(residual {np.max(np.abs(g(x, pars) - g0)):.2e}); the level may be singular there")


def starts(mc, pars, n_orbits: int, seed: int, x0=None, level_of=None) -> tuple[np.ndarray, np.ndarray]:
    """(starts of shape (n_orbits, dim) on one level, the level g0 = (h, C1, ...))."""
    g, _ = _cfuncs(mc)
    ref = np.array(mc.names.REFERENCE if level_of is None else level_of, dtype=float)
    if ref.shape != (mc.dim,) or not np.all(np.isfinite(ref)):
        raise ParameterError("level_of", f"must be a finite state of {mc.dim} components {mc.names.STATE}")
    g0 = np.asarray(g(ref, pars), dtype=float)
    if x0 is not None:
        x0 = np.atleast_2d(np.asarray(x0, dtype=float))
        if x0.shape[1] != mc.dim or not np.all(np.isfinite(x0)):
            raise ParameterError("x0", f"must have shape (N, {mc.dim}) (state {mc.names.STATE}), finite")
        return np.array([project_to_level(mc, x, g0, pars) for x in x0]), g0
    rng = np.random.default_rng(seed)
    out = [project_to_level(mc, ref + PERTURBATION * rng.standard_normal(mc.dim), g0, pars) for _ in range(n_orbits)]
    return np.array(out), g0


def _conservation(energy_error, casimir_error, energy_tol, casimir_tol) -> dict:
    """The accuracy dict of the model results, with the keys of the paper's rod's (PoincareResult.accuracy, plus
    LyapunovResult's max_abs_dH and casimir_drift)."""
    e_ok = bool(np.isfinite(energy_error) and energy_error <= energy_tol)
    c_ok = bool(np.isfinite(casimir_error) and casimir_error <= casimir_tol)
    return {"max_abs_dH": float(energy_error), "casimir_drift": float(casimir_error), "energy_tol": energy_tol,
            "casimir_tol": casimir_tol, "energy_ok": e_ok, "casimir_ok": c_ok, "passed": e_ok and c_ok}


@dataclass(repr=False)
class ModelSection(Result):
    """Section crossings of N orbits on one level: points (N, iterates, dim) (NaN where an orbit stopped early at
    t_max), the level (h, C1, ...), and the conservation achieved: energy_error = max |H - h|, casimir_error =
    max_k |C_k - C_k0| over all crossings."""

    success: bool
    message: str
    model: str
    params: dict
    state_names: tuple
    level: dict
    points: np.ndarray
    counts: list
    energy_error: float
    casimir_error: float
    tol: float
    t_final: list
    notes: list = field(default_factory=list)

    _repr_fields = ("model", "counts", "energy_error", "casimir_error")

    # the paper's rod's names for the same numbers (PoincareResult): one vocabulary across the result types
    max_abs_dH = property(lambda self: self.energy_error, doc="= energy_error (PoincareResult's name)")
    casimir_drift = property(lambda self: self.casimir_error, doc="= casimir_error (PoincareResult's name)")

    @property
    def accuracy(self) -> dict:
        """max |H - h| and max |C - C0| against ENERGY_TOL and CASIMIR_TOL: PoincareResult.accuracy's keys."""
        return _conservation(self.energy_error, self.casimir_error, ENERGY_TOL, CASIMIR_TOL)

    def to_dict(self) -> dict:
        from ..core.results import jsonable

        d = {k: jsonable(getattr(self, k)) for k in ("success", "message", "model", "params", "state_names", "level",
                                                    "counts", "energy_error", "casimir_error", "tol", "t_final",
                                                    "notes")}
        d["points_shape"] = list(self.points.shape)
        return d


def model_section(model=None, *, params=None, x0=None, level_of=None, n_orbits: int = 4, iterates: int = 200,
                  seed: int = 0, tol=None, t_max=None, verify: bool = True) -> ModelSection:
    """Energy-level Poincare section of a rod model in its body frame.

    Parameters
    ----------
    model : str, path or None
        A registered model (`magrod models`), a model file's path, or None (the paper's rod).
    params : dict, keyword-only
        {parameter: value} over the model's defaults (names and ranges: `magrod models`).
    x0 : array of shape (N, dim), keyword-only
        Starts (projected onto the level); default: n_orbits seeded perturbations of the reference state.
    level_of : array of shape (dim,), keyword-only
        The state whose level of H and the Casimirs the orbits share (default: the model's reference state).
    n_orbits, iterates, seed : int, keyword-only
        Number of orbits, crossings recorded per orbit, seed of the perturbations.
    tol : float, keyword-only
        Taylor tolerance (default machine epsilon).
    t_max : float, keyword-only
        Max-time guard per orbit (default 100 x iterates).
    verify : bool, keyword-only
        success requires energy_error <= ENERGY_TOL and casimir_error <= CASIMIR_TOL.

    Returns
    -------
    ModelSection

    Raises
    ------
    ParameterError
        Naming model, a parameter, x0, level_of, n_orbits, iterates or t_max.

    Examples
    --------
    >>> sec = model_section("anisotropic", n_orbits=2, iterates=20)
    >>> sec.success, sec.points.shape
    (True, (2, 20, 6))

    Notes
    -----
    Level, section, conservation: module docstring.  The integrator is reset, never rebuilt, between orbits.
    """
    mc = _model(model)
    pars = np.array(mc.parameters(params))
    from ..core.limits import count

    # the limits and words of the paper's section and the command line (core/limits.py), whatever the path
    iterates = count("iterates", iterates)
    n_orbits = count("n_orbits", n_orbits, maximum=4096)
    t_max = 100.0 * iterates if t_max is None else t_max
    if not (isinstance(t_max, (int, float)) and math.isfinite(t_max) and t_max > 0):
        raise ParameterError("t_max", f"must be a positive finite number, got {t_max!r}")
    xs0, g0 = starts(mc, pars, n_orbits, seed, x0, level_of)
    if tol is not None and not (isinstance(tol, (int, float)) and 0 < tol < 1e-3):
        raise ParameterError("tol", f"must be a number in (0, 1e-3), got {tol!r}")
    import heyoka as hy

    ta = _integrator(mc.directory, "section", None if tol is None else float(tol))
    g, _ = _cfuncs(mc)
    pts = np.full((len(xs0), iterates, mc.dim), np.nan)
    counts, tf, eH, eC = [], [], 0.0, 0.0
    for k, x in enumerate(xs0):
        systems.reset(ta, x, 0.0, pars)
        c = 0
        while c < iterates:
            out = ta.propagate_until(float(t_max))[0]
            if out == hy.taylor_outcome.time_limit:
                break  # the max-time guard
            if out == hy.taylor_outcome.err_nf_state:
                raise ParameterError("params", f"the orbit of {mc.name!r} left the finite numbers at t = {ta.time}")
            pts[k, c] = ta.state  # stopped on the section (the only terminal event)
            c += 1
        counts.append(c)
        tf.append(float(ta.time))
        if c:
            vals = np.array([g(p, pars) for p in pts[k, :c]])
            eH = max(eH, float(np.max(np.abs(vals[:, 0] - g0[0]))))
            if vals.shape[1] > 1:
                eC = max(eC, float(np.max(np.abs(vals[:, 1:] - g0[1:]))))
    ok = (not verify) or (eH <= ENERGY_TOL and eC <= CASIMIR_TOL)
    msg = (f"{sum(counts)} crossings; max |H - h| = {eH:.1e}, max |C - C0| = {eC:.1e}" if ok else
           f"conservation check failed: max |H - h| = {eH:.1e} (<= {ENERGY_TOL:g}), max |C - C0| = {eC:.1e}")
    level = {"H": float(g0[0]), **{c: float(v) for c, v in zip(mc.names.CASIMIRS, g0[1:])}}
    return ModelSection(ok, msg, mc.name, dict(zip(mc.names.PARAMS, map(float, pars))), tuple(mc.names.STATE), level,
                        pts, counts, eH, eC, float(tol or EPS), tf)


@dataclass(repr=False)
class ModelLyapunov(Result):
    """Benettin estimate of the maximal Lyapunov exponent of one orbit: lyap (at t_max), the history (times,
    lyap_history), chaotic (lyap > REGULAR_BOUND), and the conservation of H and the Casimirs along the run."""

    success: bool
    message: str
    model: str
    params: dict
    x0: list
    lyap: float
    regular_bound: float
    chaotic: bool
    times: np.ndarray
    lyap_history: np.ndarray
    energy_error: float
    casimir_error: float

    _repr_fields = ("model", "lyap", "chaotic", "energy_error")

    max_abs_dH = property(lambda self: self.energy_error, doc="= energy_error (LyapunovResult's name)")
    casimir_drift = property(lambda self: self.casimir_error, doc="= casimir_error (LyapunovResult's name)")

    @property
    def accuracy(self) -> dict:
        """Conservation along the run against ENERGY_TOL and CASIMIR_TOL: PoincareResult.accuracy's keys."""
        return _conservation(self.energy_error, self.casimir_error, ENERGY_TOL, CASIMIR_TOL)


def model_lyapunov(model=None, *, params=None, x0=None, seed: int = 0, t_max: float = 2000.0,
                   renorm_dt: float = 1.0) -> ModelLyapunov:
    """Maximal Lyapunov exponent of one orbit of a rod model (body frame, tangent vector renormalised).

    Parameters
    ----------
    model : str, path or None
        A registered model, a model file's path, or None (the paper's rod).
    params : dict, keyword-only
        Parameter values over the defaults.
    x0 : array of shape (dim,), keyword-only
        Start (default: a seeded perturbation of the reference state, on its level).
    seed : int, keyword-only
        Seed of that perturbation.
    t_max, renorm_dt : float, keyword-only
        Length of the run, renormalisation interval.

    Returns
    -------
    ModelLyapunov

    Raises
    ------
    ParameterError
        Naming model, a parameter, x0, t_max or renorm_dt.

    Examples
    --------
    >>> ly = model_lyapunov("kirchhoff", t_max=200.0)
    >>> ly.chaotic
    False

    Notes
    -----
    Method and the bound `chaotic` uses: module docstring.
    """
    mc = _model(model)
    pars = np.array(mc.parameters(params))
    for name, v in (("t_max", t_max), ("renorm_dt", renorm_dt)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v <= 0:
            raise ParameterError(name, f"must be a positive finite number, got {v!r}")
    if renorm_dt > t_max:
        raise ParameterError("renorm_dt", f"= {renorm_dt} exceeds t_max = {t_max}")
    xs0, g0 = starts(mc, pars, 1, seed, None if x0 is None else [x0])
    n = mc.dim
    ta = _integrator(mc.directory, "tangent")
    w0 = np.random.default_rng(seed + 1).standard_normal(n)
    w0 /= np.linalg.norm(w0)
    systems.reset(ta, np.concatenate([xs0[0], w0]), 0.0, pars)
    g, _ = _cfuncs(mc)
    steps = int(round(t_max / renorm_dt))
    acc, times, hist, eH, eC = 0.0, [], [], 0.0, 0.0
    for k in range(1, steps + 1):
        ta.propagate_until(k * renorm_dt)
        w = ta.state[n:]
        nw = float(np.linalg.norm(w))
        acc += math.log(nw)
        ta.state[n:] = w / nw
        times.append(k * renorm_dt)
        hist.append(acc / (k * renorm_dt))
        gv = g(ta.state[:n].copy(), pars) - g0
        eH = max(eH, abs(float(gv[0])))
        eC = max(eC, float(np.max(np.abs(gv[1:]))) if len(gv) > 1 else 0.0)
    bound = 10.0 * math.log(t_max) / t_max
    lyap = hist[-1]
    ok = eH <= ENERGY_TOL and eC <= CASIMIR_TOL
    msg = (f"lyap = {lyap:.3g} ({'>' if lyap > bound else '<='} the regular bound {bound:.3g}); max |H - h| = "
           f"{eH:.1e}" if ok else f"conservation check failed: max |H - h| = {eH:.1e}, max |C - C0| = {eC:.1e}")
    return ModelLyapunov(ok, msg, mc.name, dict(zip(mc.names.PARAMS, map(float, pars))), xs0[0].tolist(), lyap, bound,
                         lyap > bound, np.array(times), np.array(hist), eH, eC)


def model_parameters(params, overrides: dict):
    """A model's parameters from the face's two spellings: `params` as a dict and/or keyword overrides
    (``poincare_section(model="anisotropic", B2=3)``, issue 25's calling convention)."""
    if params is None:
        return dict(overrides) or None
    if not isinstance(params, dict):
        raise ParameterError("params", f"with model= a dict of the model's parameters or keyword overrides, got "
                                       f"{type(params).__name__}")
    return {**params, **overrides}


def section_for_model(model, params, formulation, *, iterates, tol, t_max, verify, starts):
    """mr.poincare_section(model=...): the body-frame section of the model (formulation "reduced" needs the S^1
    symmetry; ModelCode.require_s1 says why not)."""
    mc = _model(model)
    if formulation == "reduced":
        mc.require_s1("the reduced (Euler-angle) formulation")
    elif formulation != "body":
        raise ParameterError("formulation", f"must be 'body' or 'reduced', got {formulation!r}")
    if params is not None and not isinstance(params, dict):
        raise ParameterError("params", f"with model= a dict of the model's parameters ({', '.join(mc.names.PARAMS)}), "
                                       f"got {type(params).__name__}")
    return model_section(mc, params=params, x0=starts, iterates=iterates, tol=tol, t_max=t_max, verify=verify)


@dataclass(repr=False)
class ModelChaosMap(Result):
    """The Lyapunov estimate over a plane of two of the model's parameters: lyap and chaotic of shape (ny, nx) for
    one start (the seeded perturbation of the reference state, on its level at each parameter point); the worst
    conservation over the map."""

    success: bool
    message: str
    model: str
    x_name: str
    x: np.ndarray
    y_name: str
    y: np.ndarray
    lyap: np.ndarray
    chaotic: np.ndarray
    t_max: float
    energy_error: float
    casimir_error: float

    _repr_fields = ("model", "x_name", "y_name", "t_max", "energy_error")

    max_abs_dH = property(lambda self: self.energy_error, doc="= energy_error (ChaosMap.accuracy's name)")
    max_casimir_drift = property(lambda self: self.casimir_error, doc="= casimir_error (ChaosMap.accuracy's name)")

    @property
    def accuracy(self) -> dict:
        """The worst conservation over the map against ENERGY_TOL and CASIMIR_TOL."""
        return _conservation(self.energy_error, self.casimir_error, ENERGY_TOL, CASIMIR_TOL)


def _axis(mc, spec, which):
    if not (isinstance(spec, tuple) and len(spec) == 4 and spec[0] in mc.names.PARAMS):
        raise ParameterError(which, f"must be (name, lo, hi, n) with name one of {', '.join(mc.names.PARAMS)}, "
                                    f"got {spec!r}")
    name, lo, hi, n = spec
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= 512:
        raise ParameterError(which, f"n must be an integer in [1, 512], got {n!r}")
    return name, np.linspace(float(lo), float(hi), n)


def model_chaos_map(model, x, y, *, t_max: float = 500.0, renorm_dt: float = 1.0, seed: int = 0,
                    params=None) -> ModelChaosMap:
    """Lyapunov estimates over a plane of two parameters of a rod model (mr.chaos_map(..., model=...)).

    Parameters
    ----------
    model : str or path
        A registered model or a model file.
    x, y : tuple
        (name, lo, hi, n): a parameter of the model and its grid (each value inside the parameter's range).
    t_max, renorm_dt : float, keyword-only
        As in model_lyapunov.
    seed : int, keyword-only
        Seed of the start (the same perturbation of the reference state at every point).
    params : dict, keyword-only
        The other parameters (defaults otherwise).

    Returns
    -------
    ModelChaosMap

    Raises
    ------
    ParameterError
        Naming x, y, model or a parameter.

    Examples
    --------
    >>> cm = model_chaos_map("anisotropic", ("B2", 1.0, 3.0, 2), ("C", 1.0, 2.0, 1), t_max=100.0)
    >>> cm.lyap.shape
    (1, 2)

    Notes
    -----
    One orbit per grid point, sequentially, on the model's tangent integrator (built once, reset per point).
    Cost ~ t_max x 25 us per point for a 6-D model.
    """
    mc = _model(model)
    xn, xs = _axis(mc, x, "x")
    yn, ys = _axis(mc, y, "y")
    if xn == yn:
        raise ParameterError("y", f"must differ from x ({xn})")
    base = dict(params or {})
    lyap = np.full((len(ys), len(xs)), np.nan)
    eH = eC = 0.0
    for i, yv in enumerate(ys):
        for j, xv in enumerate(xs):
            ly = model_lyapunov(mc, params={**base, xn: xv, yn: yv}, seed=seed, t_max=t_max, renorm_dt=renorm_dt)
            lyap[i, j] = ly.lyap
            eH, eC = max(eH, ly.energy_error), max(eC, ly.casimir_error)
    bound = 10.0 * math.log(t_max) / t_max
    ok = eH <= ENERGY_TOL and eC <= CASIMIR_TOL
    msg = (f"{lyap.size} orbits, {int(np.sum(lyap > bound))} chaotic (lyap > {bound:.3g}); max |H - h| = {eH:.1e}"
           if ok else f"conservation check failed: max |H - h| = {eH:.1e}, max |C - C0| = {eC:.1e}")
    return ModelChaosMap(ok, msg, mc.name, xn, xs, yn, ys, lyap, lyap > bound, float(t_max), eH, eC)


def magnetic_to_paper(mc, x, pars) -> tuple:
    """The `magnetic` model's state x (parameters B, C, lam) as the paper's rod at gamma = delta = 0: (RodParams,
    chart coordinates (theta, psi, phi, pbar_theta, pbar_psi), arclength scale c).

    The scaling m = m3 m~, n = (m3^2/B) n~, s = (B/m3) s~ maps the rod with B = C to the numeric scale of
    derive/numeric_scale.py (B = C = m3 = 1, lambda~ = lambda B^2/m3^3); there C2~ = e3.n~ = 1/m^2,
    lambda~ = lambdabar/m^4 and 2 C1~ = (mu + 1)/m^4.  C != B adds the uniform rotation m3 (1/C - 1/B) about d3,
    i.e. phi' only: (theta, psi, pbar_theta, pbar_psi) are those of the B = C rod."""
    from ..core.params import RodParams

    B, lam = (pars[mc.names.PARAMS.index(k)] for k in ("B", "lam"))
    i = {k: mc.names.STATE.index(k) for k in mc.names.STATE}
    m3 = x[i["m3"]]
    mv = np.array([x[i["m1"]], x[i["m2"]], m3])
    nv = np.array([x[i["n1"]], x[i["n2"]], x[i["n3"]]])
    ev = np.array([x[i["e31"]], x[i["e32"]], x[i["e33"]]])
    if not m3 > 0:
        raise ParameterError("x0", f"the chart needs m3 > 0 (p_phi = m3 is the unit of the scale), got {m3:g}")
    if abs(ev @ ev - 1.0) > 1e-12:
        raise ParameterError("x0", f"the chart needs |e3| = 1 (the field direction), got {np.sqrt(ev @ ev):.15g}")
    nt = nv * B / m3**2
    C2 = float(ev @ nt)
    if not C2 > 0:
        raise ParameterError("x0", f"the chart needs e3.n > 0 (m = m3/sqrt(B e3.n)), got e3.n = {ev @ nv:g}")
    m = C2 ** -0.5
    lt = lam * B**2 / m3**3
    C1 = 0.5 * float(nt @ nt) + lt * float((mv / m3) @ ev)
    rp = RodParams(m=float(m), mu=float(2 * C1 * m**4 - 1), gamma=0.0, delta=0.0, lam=float(lt * m**4))
    xs = np.concatenate([mv / m3, nt, ev])
    q = systems.body_to_euler(xs, rp.array())
    return rp, np.asarray(q, dtype=float), B / m3


def magnetic_chart_start(model, params, starts):
    """For mr.poincare_section(model="magnetic", formulation="reduced"): (RodParams, start keywords) of the paper's
    chart at gamma = delta = 0 (magnetic_to_paper) for the model's reference state (or starts[0]); None for every
    other model.  chaos/section.py then runs its own reduced section on them (so this module never imports it)."""
    mc = _model(model)
    if mc.name != "magnetic" or mc.origin != "registry":
        return None
    pars = np.array(mc.parameters(params))
    x0 = np.array(mc.names.REFERENCE if starts is None else np.atleast_2d(starts)[0], dtype=float)
    rp, q, _ = magnetic_to_paper(mc, x0, pars)
    ci = {k: systems.chart_index(k) for k in ("theta", "psi", "ptheta", "ppsi")}
    return rp, {"theta0": float(q[ci["theta"]]), "ptheta0": float(q[ci["ptheta"]]), "psi0": float(q[ci["psi"]]),
                "p_psi0": float(q[ci["ppsi"]])}
