"""Chaos indicators from the tangent (variational) equations, and chaos maps over parameter planes and sections
Numerics only: result objects out, no plotting, no files.

Public API
----------
tangent_indicators(ta, x0, w0, pars, *, t_max, renorm_dt=10.0, project=None, check=None) -> Indicators
body_indicators(x0, pars, *, t_max, tol=None, renorm_dt=10.0, project=True, batch_size=None) -> Indicators
reference_indicators(name, x0, pars, *, t_max, ...) -> Indicators        name in REFERENCE_SYSTEMS
(the paper's orbits: magrod.paper.panel_indicators)
Axis, MapSpec, parse_axis(option, text), tiles(spec), compute_tile(spec, iy, ix) -> dict, chaos_map(spec) -> MapResult

Indicators (Froeschle, Lega & Gonczi 1997; Benettin et al. 1980; Cincotta & Simo 2000)
----------------------------------------------------------------------------------------
One tangent vector w(t) = Phi(t) w0, |w0| = 1, is integrated with the orbit (systems.tangent_system: heyoka's
var_ode_sys, n + n equations) and renormalised every renorm_dt; the logarithms of the norms are summed, so
L(t_k) = ln |w(t_k)| exactly at the sample times t_k = k dt.
  lyap            = L(T)/T                   finite-time maximal Lyapunov exponent
  fli             = max_{t_k <= T} L(t_k)     Fast Lyapunov Indicator (sampled at the t_k)
  fli_half        = max_{t_k <= T/2} L(t_k)
  growth_exponent = (fli - fli_half)/ln 2   the power p of |w| ~ t^p over [T/2, T]: a discrete MEGNO.
Criterion (stated once, used everywhere): an orbit is *chaotic* iff growth_exponent > GROWTH_THRESHOLD = 3.
Tangent vectors of regular orbits grow at most linearly (shear between tori: p ~ 1), those of chaotic ones
exponentially (p ~ lyap T/(2 ln 2), e.g. 8 for lyap = 0.011 at T = 1000); the threshold leaves room for the
intermittent, separatrix-crossing growth of regular orbits near a homoclinic loop.
Resolution: an orbit with exponent lyap is seen as chaotic once lyap T/(2 ln 2) > 3, i.e. T > 4.2/lyap.  The
Figure 4 orbits have lyap ~ 0.01 and are sticky (Fig 4(a): growth exponent 2.9, 3.8, 2.3, 3.3, 11.9 at
T = 1000, 1200, 1500, 2000, 3000), so T <= 2000 is marginal for this rod and the default is T = 3000.
MEGNO proper is not computed: it needs the integral of t d ln|w| between samples (and a 0/0 at t = 0 in the
Taylor recursion); the growth exponent is its discrete analogue with the same limits (~1 regular, ~lyap t).

Neutral directions (body frame)
-------------------------------
The body system has first integrals C1, C2, C3 (Casimirs), H and m3 (I1; its right-hand side is identically 0).
Their level set through x0 is invariant, so its tangent space T = ker G(x), G = the stacked gradients, is
carried into itself by Phi.  A tangent vector with a component across T measures how *neighbouring leaves*
(other Casimir values, energies, twists: other rods) drift apart -- a linear shear that adds a c log t bias to
the FLI and nothing to lyap.  We remove it: w0 and, after every renormalisation, w are projected orthogonally
onto ker G(x(t)) (w - G^T (G G^T)^{-1} G w), so the indicators describe the orbit's own leaf.  By invariance
the projection removes only round-off after the first one (tests/test_chaos.py checks both facts).

Cost: ~4.4 us per orbit per unit time at tol = eps in SIMD batches of systems.batch_width() lanes
(~24 us scalar), plus ~1.3 ms per start point for the energy root; see benchmarks/README.md.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import heyoka as hy
import numpy as np

from ..core import systems
from ..core.tolerances import DRIFT_LIMIT
from .fields import KEYS

GROWTH_THRESHOLD = 3.0
# Early exit: an orbit stops at the first sample time t_k >= T/2 at which its growth exponent so far,
# (max_{t_j <= t_k} L(t_j) - FLI(T/2))/ln 2, exceeds the classification threshold by EXIT_MARGIN.  The margin is
# not what makes the class safe (the running maximum never decreases, so the full-T growth exponent is at least the
# value at the exit: chaotic stays chaotic for any threshold up to the exit level); it makes the exited orbit's
# recorded growth exponent, a lower bound, chaotic by a visible margin rather than by round-off.
EXIT_MARGIN = 1.0
DEFAULT_RENORM_DT = 10.0
# status codes of a grid point; NaN indicators carry one of these reasons
OK, NO_ROOT, UNPHYSICAL, LEFT_RANGE, FAILED = 0, 1, 2, 3, 4
REASONS = {OK: "ok", NO_ROOT: "no_energy_root", UNPHYSICAL: "unphysical_parameters",
           LEFT_RANGE: "left_physical_range", FAILED: "integration_failed"}
# An orbit whose first integrals drift by more than DRIFT_LIMIT (magrod.core.tolerances) has left its invariant set
_KEYS = KEYS  # the per-orbit outputs, described in magrod/chaos/fields.py
_W0_SEED = 11  # the fixed generic direction of w0 (before projection): same on every worker and machine


# ----------------------------------------------------------------------------------------------------------
# results
# ----------------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Indicators:
    """Per-orbit chaos indicators, arrays of shape (N,); NaN where status != OK."""

    lyap: np.ndarray
    fli: np.ndarray
    fli_half: np.ndarray
    growth_exponent: np.ndarray
    max_abs_dH: np.ndarray
    casimir_drift: np.ndarray
    min_stretch: np.ndarray
    status: np.ndarray
    t_max: float
    renorm_dt: float
    # with history=True: ln |w(t_k)| (N, K) at the renormalisation times t_k = k renorm_dt, k = 1..K
    log_growth: np.ndarray | None = None
    # with exit_above (early exit): the time each orbit stopped, t_max or an earlier sample time (NaN
    # where status != OK); see tangent_indicators
    exit_time: np.ndarray | None = None

    @property
    def times(self) -> np.ndarray:
        """The sample times t_k = k renorm_dt (K,) of log_growth."""
        K = 0 if self.log_growth is None else self.log_growth.shape[1]
        return self.renorm_dt * np.arange(1, K + 1)

    @property
    def chaotic(self) -> np.ndarray:
        """growth_exponent > GROWTH_THRESHOLD (False where missing)."""
        with np.errstate(invalid="ignore"):
            return np.asarray(self.growth_exponent > GROWTH_THRESHOLD)

    def arrays(self) -> dict:
        return {k: v for k, v in asdict(self).items() if isinstance(v, np.ndarray)}


# ----------------------------------------------------------------------------------------------------------
# the core: one tangent vector, renormalised
# ----------------------------------------------------------------------------------------------------------
def _steps(t_max, renorm_dt):
    """An even number of renormalisation intervals (so T/2 is a sample time) of length <= renorm_dt."""
    k = max(2, 2 * math.ceil(t_max / (2 * renorm_dt)))
    return k, t_max / k


def tangent_indicators(ta, x0, w0, pars, *, t_max, renorm_dt=DEFAULT_RENORM_DT, project=None, check=None,
                       valid=None, history=False, exit_above=None) -> Indicators:
    """Indicators of N orbits with a batch tangent integrator (systems.tangent_batch).

    x0 (n, N) starts, w0 (n, N) tangent vectors (normalised here), pars (npars, N); project(x, w, p) -> w
    maps tangent vectors onto the neutral-free subspace (None: identity); check is a factory: check(x0, p) is
    called once per batch with that batch's (padded) lanes' starts and returns the lane checker
    checker(x, p) -> (ok (b,), diag (3, b)), which flags lanes that left the physical range and reports (|dH|,
    Casimir drift, -stretch), whose maxima are kept (`body_check` is the body system's); valid (N,) bool skips
    points; history=True also returns ln |w(t_k)| at every renormalisation time.
    Lanes are filled in order, padded with a copy of a valid lane: a lane's result does not depend on its
    neighbours (heyoka batch lanes step independently), and the fixed order makes results reproducible.  The
    checker is built on the padded lanes, so N may be smaller than the batch width (any width: 1, 2, 4, 8, ...).
    Cost: N/batch_size batch propagations of t_max plus ~t_max/renorm_dt Python-level renormalisations each.

    exit_above (a growth exponent, e.g. GROWTH_THRESHOLD + EXIT_MARGIN; None: off, the default): early exit.  The
    lanes are then refilled as orbits end (`_run_lanes`), and an orbit ends at T, or when it fails or leaves the
    physical range (its numbers are NaN either way), or at the first sample time t_e >= T/2 at which
    (fli(t_e) - fli_half)/ln 2 > exit_above.  An exited orbit reports lyap = L(t_e)/t_e, fli = max_{t_k <= t_e}
    L(t_k), fli_half as usual, growth_exponent = (fli(t_e) - fli_half)/ln 2 (a lower bound of its full-T value:
    the running maximum never decreases, so its class at any threshold <= exit_above is the full run's), the
    conservation maxima over [0, t_e], and exit_time = t_e; every other orbit's numbers are bit for bit those of
    exit_above=None (each orbit has its own lane, time and start tangent vector; tests/test_early_exit.py)."""
    t_max = float(t_max)
    x0, w0, pars = (np.atleast_2d(np.asarray(a, float)) for a in (x0, w0, pars))
    n, N = x0.shape
    b = ta.batch_size
    valid = np.ones(N, bool) if valid is None else np.asarray(valid, bool).copy()
    out = {k: np.full(N, np.nan) for k in _KEYS}
    status = np.where(valid, OK, FAILED).astype(np.int8)
    nsteps, dt = _steps(t_max, renorm_dt)
    if exit_above is not None:
        if history:
            raise ValueError("history is not recorded with an early exit (orbits end at different times)")
        t_exit = np.full(N, np.nan)
        _run_lanes(ta, x0, w0, pars, valid, nsteps, dt, project, check, float(exit_above), out, status, t_exit)
        bad = status != OK
        for key in out:
            out[key][bad] = np.nan
        t_exit[bad] = np.nan
        return Indicators(**out, status=status, t_max=t_max, renorm_dt=dt, exit_time=t_exit)
    hist = np.full((N, nsteps), np.nan) if history else None
    for s in range(0, N, b):
        idx = np.arange(s, min(s + b, N))
        good = idx[valid[idx]]
        if good.size == 0:
            continue
        lanes = np.concatenate([good, np.full(b - good.size, good[-1])])
        chk = None if check is None else check(x0[:, lanes], pars[:, lanes])
        res = _run_batch(ta, x0[:, lanes], w0[:, lanes], pars[:, lanes], nsteps, dt, project, chk, history)
        k = good.size
        for key in out:
            out[key][good] = res[key][:k]
        status[good] = res["status"][:k]
        if history:
            hist[good] = res["history"][:, :k].T
    bad = status != OK
    for key in out:
        out[key][bad] = np.nan
    if history:
        hist[bad] = np.nan
    return Indicators(**out, status=status, t_max=t_max, renorm_dt=dt, log_growth=hist)


def _normalise(x, w, p, project):
    if project is not None:
        w = project(x, w, p)
    nrm = np.linalg.norm(w, axis=0)
    return w / nrm, nrm


def _run_batch(ta, x, w, p, nsteps, dt, project, check, history=False) -> dict:
    n = x.shape[0]
    b = ta.batch_size
    ta.set_time(0.0)
    ta.pars[:] = p
    w, _ = _normalise(x, w, p, project)
    ta.state[:n] = x
    ta.state[n:] = w
    L = np.zeros(b)
    fli = np.zeros(b)
    fli_half = np.zeros(b)
    status = np.zeros(b, np.int8)
    drift = np.full((3, b), -np.inf)
    hist = np.empty((nsteps, b)) if history else None
    # the body system's check and projection from ONE compiled call per renormalisation (values bit-identical
    # to the separate functions: systems.body_renorm_functions); other systems call check and project
    fused = isinstance(check, _BodyCheck) and project is project_neutral  # check: this batch's checker
    tv = ta.time  # read-only view: a lane reached k dt exactly iff its propagation did not fail
    for k in range(1, nsteps + 1):
        t_k = k * dt
        ta.propagate_until(t_k)
        st = np.array(ta.state)
        failed = (tv != t_k) | ~np.all(np.isfinite(st), axis=0)
        xs, ws = st[:n], st[n:]
        if failed.any():  # restart dead lanes from their start so the batch keeps going; results discarded
            xs[:, failed], ws[:, failed] = x[:, failed], w[:, failed]
            ta.state[:] = st
        if fused:
            vals = systems.body_renorm_functions()(xs, p)
            in_range, d = check.judge(vals[0], vals[1:4], vals[4])
            drift = np.maximum(drift, d)
            status[(status == OK) & ~in_range] = LEFT_RANGE
            wk = _project(vals[5:], xs, ws)
            nrm = np.linalg.norm(wk, axis=0)
            wk = wk / nrm
        else:
            if check is not None:
                in_range, d = check(xs, p)
                drift = np.maximum(drift, d)
                status[(status == OK) & ~in_range] = LEFT_RANGE
            wk, nrm = _normalise(xs, ws, p, project)
        status[(status == OK) & failed] = FAILED
        ta.state[n:] = wk
        L += np.log(nrm)
        if history:
            hist[k - 1] = L
        fli = np.maximum(fli, L)
        if 2 * k == nsteps:
            fli_half = fli.copy()
    T = nsteps * dt
    if check is None:  # nothing monitored: NaN, not the -inf of an empty maximum
        drift[:] = np.nan
    return {"lyap": L / T, "fli": fli, "fli_half": fli_half, "growth_exponent": (fli - fli_half) / math.log(2.0),
            "max_abs_dH": drift[0], "casimir_drift": drift[1], "min_stretch": -drift[2], "status": status,
            "history": hist}


def _run_lanes(ta, x0, w0, pars, valid, nsteps, dt, project, check, exit_above, out, status, t_exit) -> None:
    """The early-exit loop of tangent_indicators: the valid orbits in order through the b lanes, a lane refilled
    as soon as its orbit ends (at T, failed, out of range, or exited); fills out, status and t_exit in place.

    Each propagate call moves every busy lane by one renormalisation interval of its own (time reset per lane with
    set_dtime, targets k dt as in _run_batch); parked lanes (no work left) sit at time 0 with target 0.  Per lane,
    the arithmetic is _run_batch's: the same start normalisation, compiled calls and projection over the b lanes'
    columns (a column's value does not depend on its neighbours), the same order of the status updates."""
    n, N = x0.shape
    b = ta.batch_size
    todo = [int(i) for i in np.flatnonzero(valid)]
    if not todo:
        return
    jobs = np.full(b, -1)              # the orbit in each lane (-1: parked)
    k = np.zeros(b, np.int64)          # renormalisations done in the lane
    xs0 = np.repeat(x0[:, todo[:1]], b, axis=1)   # each lane's start (a parked lane keeps a valid one)
    ws0 = np.repeat(w0[:, todo[:1]], b, axis=1)
    p = np.repeat(pars[:, todo[:1]], b, axis=1)
    L, fli, fli_half = np.zeros(b), np.zeros(b), np.zeros(b)
    st_l = np.zeros(b, np.int8)
    drift = np.full((3, b), -np.inf)
    target = np.zeros(b)
    nxt = 0
    T = nsteps * dt

    def start(lanes):
        """Put the next orbits into `lanes` (or park them): start values, normalised w0, time 0, checker."""
        nonlocal nxt, chk, wn0
        for j in lanes:
            if nxt < len(todo):
                i = todo[nxt]
                nxt += 1
                jobs[j] = i
                xs0[:, j], ws0[:, j], p[:, j] = x0[:, i], w0[:, i], pars[:, i]
            else:
                jobs[j] = -1
            k[j] = 0
            L[j] = fli[j] = fli_half[j] = 0.0
            st_l[j] = OK
            drift[:, j] = -np.inf
        wn0, _ = _normalise(xs0, ws0, p, project)  # over all b columns, as _run_batch does per batch
        chk = None if check is None else check(xs0, p)
        hi, lo = (np.array(a) for a in ta.dtime)
        hi[lanes] = lo[lanes] = 0.0
        ta.set_dtime(hi, lo)
        ta.pars[:] = p
        st = np.array(ta.state)
        st[:n, lanes], st[n:, lanes] = xs0[:, lanes], wn0[:, lanes]
        ta.state[:] = st

    chk = wn0 = None
    start(list(range(b)))
    fused = isinstance(chk, _BodyCheck) and project is project_neutral  # as in _run_batch
    tv = ta.time
    while (jobs >= 0).any():
        busy = jobs >= 0
        target[:] = np.where(busy, (k + 1) * dt, 0.0)
        ta.propagate_until(target)
        k[busy] += 1
        st = np.array(ta.state)
        failed = busy & ((tv != target) | ~np.all(np.isfinite(st), axis=0))
        xs, ws = st[:n], st[n:]
        if failed.any():  # back to the start, so the batched numpy below sees finite numbers; results discarded
            xs[:, failed], ws[:, failed] = xs0[:, failed], wn0[:, failed]
        if fused:
            vals = systems.body_renorm_functions()(xs, p)
            in_range, d = chk.judge(vals[0], vals[1:4], vals[4])
            drift = np.maximum(drift, d)
            st_l[(st_l == OK) & ~in_range] = LEFT_RANGE
            wk = _project(vals[5:], xs, ws)
            nrm = np.linalg.norm(wk, axis=0)
            wk = wk / nrm
        else:
            if chk is not None:
                in_range, d = chk(xs, p)
                drift = np.maximum(drift, d)
                st_l[(st_l == OK) & ~in_range] = LEFT_RANGE
            wk, nrm = _normalise(xs, ws, p, project)
        st_l[(st_l == OK) & failed] = FAILED
        st[n:] = wk
        ta.state[:] = st
        L[busy] += np.log(nrm[busy])
        fli[busy] = np.maximum(fli[busy], L[busy])
        half = busy & (2 * k == nsteps)
        fli_half[half] = fli[half]
        with np.errstate(invalid="ignore"):
            growth = (fli - fli_half) / math.log(2.0)
        ended = busy & ((k == nsteps) | (st_l != OK) | ((2 * k >= nsteps) & (growth > exit_above)))
        if not ended.any():
            continue
        lanes = [int(j) for j in np.flatnonzero(ended)]
        for j in lanes:
            i = jobs[j]
            full = k[j] == nsteps
            t_e = T if full else k[j] * dt
            out["lyap"][i] = L[j] / T if full else L[j] / t_e
            out["fli"][i], out["fli_half"][i], out["growth_exponent"][i] = fli[j], fli_half[j], growth[j]
            if check is None:
                out["max_abs_dH"][i] = out["casimir_drift"][i] = out["min_stretch"][i] = np.nan
            else:
                out["max_abs_dH"][i], out["casimir_drift"][i], out["min_stretch"][i] = drift[0, j], drift[1, j], \
                    -drift[2, j]
            status[i] = st_l[j]
            t_exit[i] = t_e
        start(lanes)


def generic_w0(n: int, N: int) -> np.ndarray:
    """The fixed generic start direction (seeded Gaussian, unit norm), repeated for N orbits: (n, N)."""
    v = np.random.default_rng(_W0_SEED).standard_normal(n)
    return np.repeat((v / np.linalg.norm(v))[:, None], N, axis=1)


# ----------------------------------------------------------------------------------------------------------
# the rod in the body frame
# ----------------------------------------------------------------------------------------------------------
def project_neutral(x, w, p) -> np.ndarray:
    """Orthogonal projection of the columns of w onto ker G(x): the tangent space of the level set of the first
    integrals (C1, C2, C3, H, m3) through x (see the module docstring)."""
    return _project(systems.body_neutral_gradients()(x, p), x, w)


def _project(G, x, w) -> np.ndarray:
    """project_neutral with the stacked gradients G (k*9, N) already evaluated at x."""
    n = x.shape[0]
    G = G.reshape(-1, n, x.shape[1]).transpose(2, 0, 1)  # (N, k, n)
    Gw = np.einsum("bkn,nb->bk", G, w)
    coef = np.linalg.solve(G @ G.transpose(0, 2, 1), Gw[..., None])[..., 0]
    return w - np.einsum("bkn,bk->nb", G, coef)


def neutral_components(x, w, p) -> np.ndarray:
    """|G(x) w| / |w| per column: how much of w lies across the invariant level set (0 = none)."""
    G = systems.body_neutral_gradients()(x, p)
    n = x.shape[0]
    G = G.reshape(-1, n, x.shape[1]).transpose(2, 0, 1)
    Gn = G / np.linalg.norm(G, axis=2, keepdims=True)
    return np.linalg.norm(np.einsum("bkn,nb->bk", Gn, w), axis=1) / np.linalg.norm(w, axis=0)


@dataclass
class _BodyCheck:
    """Physical range and conservation budget along an orbit, evaluated at the sample times.

    Range: the first integrals stay within DRIFT_LIMIT of their start values (otherwise the orbit has left its
    invariant set and nothing computed on it can be trusted).  The axial stretch v3 = dH/dn3 (eq:hyperelastic) is
    recorded as min_stretch but does not mark a point missing: the paper's own Fig 4 orbits reach v3 < 0 (the
    rod compressed through zero length, unphysical for a real rod but a valid orbit of the Hamiltonian system)."""

    H0: np.ndarray
    C0: np.ndarray

    @classmethod
    def at(cls, x0, p):
        f = systems.body_functions()
        return cls(f["H"](x0, p)[0], f["casimirs"](x0, p))

    def __call__(self, x, p):
        f = systems.body_functions()
        return self.judge(f["H"](x, p)[0], f["casimirs"](x, p), systems.body_stretch()(x, p)[0])

    def judge(self, H, C, v3):
        """(in range (N,), [|H - H0|, Casimir drift, -v3] (3, N)) from H, the Casimirs (3, N) and v3 at x."""
        dH = np.abs(H - self.H0)
        dC = np.max(np.abs(C - self.C0), axis=0)
        ok = (dH <= DRIFT_LIMIT) & (dC <= DRIFT_LIMIT)
        return ok, np.vstack([dH, dC, -v3])


def body_check(x0, p) -> _BodyCheck:
    """The body system's lane checker factory for `tangent_indicators` (start values of H and the Casimirs of
    the batch's lanes); with project_neutral it takes the fused path (one compiled call per renormalisation)."""
    return _BodyCheck.at(x0, p)


def body_indicators(x0, pars, *, t_max, tol=None, renorm_dt=DEFAULT_RENORM_DT, project=True, batch_size=None,
                    w0=None, valid=None, history=False, exit_above=None) -> Indicators:
    """Indicators of body-frame orbits x0 (9, N) with parameters pars (5, N) in PARAMS order.

    Defaults: tol None = machine epsilon, renorm_dt 10, project onto the invariant level set (module docstring),
    batch size systems.batch_width() ($MAGROD_BATCH_WIDTH or the CPU's SIMD size), w0 the fixed generic direction.  Max |H - H0| and Casimir drift are
    returned per orbit; an orbit with v3 <= 0 or drift > DRIFT_LIMIT is LEFT_RANGE.
    Cost: ~4.4 us per orbit per unit time (tol = eps, AVX-512 batch of 8)."""
    from ..core.limits import positive

    t_max, renorm_dt = positive("t_max", t_max), positive("renorm_dt", renorm_dt)
    x0 = np.atleast_2d(np.asarray(x0, float).T).T if np.ndim(x0) == 1 else np.asarray(x0, float)
    pars = np.asarray(pars, float)
    if pars.ndim == 1:
        pars = np.repeat(pars[:, None], x0.shape[1], axis=1)
    n, N = x0.shape
    valid = np.ones(N, bool) if valid is None else np.asarray(valid, bool)
    ta = systems.body_tangent_batch(batch_size, tol)
    w0 = generic_w0(n, N) if w0 is None else np.asarray(w0, float).reshape(n, -1)
    # each batch's checker holds its own (padded) lanes' start values of H and the Casimirs (tangent_indicators)
    return tangent_indicators(ta, x0, w0, pars, t_max=t_max, renorm_dt=renorm_dt,
                              project=project_neutral if project else None, check=body_check, valid=valid,
                              history=history, exit_above=exit_above)


# ----------------------------------------------------------------------------------------------------------
# reference systems nobody here wrote: controls for the machinery
# ----------------------------------------------------------------------------------------------------------
def reference_system(name: str):
    """(sys, pars, integrals) of a textbook system, pars as hy.par[i]:
    "lorenz"        x' = s (y - x), y' = x (r - z) - y, z' = x y - b z; classic pars (10, 28, 8/3),
                    lambda_max = 0.9056 (Sprott, Chaos and Time-Series Analysis, 2003, table A.1).
    "henon_heiles"  H = (px^2 + py^2)/2 + (x^2 + y^2)/2 + x^2 y - y^3/3 (no parameters); E = 1/6 mostly
                    chaotic, E = 1/12 mostly regular (Henon & Heiles 1964)."""
    if name == "lorenz":
        x, y, z = hy.make_vars("x", "y", "z")
        s, r, b = hy.par[0], hy.par[1], hy.par[2]
        return [(x, s * (y - x)), (y, x * (r - z) - y), (z, x * y - b * z)], [10.0, 28.0, 8.0 / 3.0]
    if name == "henon_heiles":
        x, y, px, py = hy.make_vars("x", "y", "px", "py")
        H = (px * px + py * py) / 2.0 + (x * x + y * y) / 2.0 + x * x * y - y * y * y / 3.0
        return hy.hamiltonian(H, [x, y], [px, py]), []
    raise ValueError(f"unknown reference system {name!r}; known: lorenz, henon_heiles")


def henon_heiles_start(E, y0, x0=0.0, py0=0.0) -> np.ndarray:
    """(x, y, px, py) on the level H = E with px >= 0 solved for; NaN where the level is not reached."""
    y0 = np.asarray(y0, float)
    V = (x0 ** 2 + y0 ** 2) / 2 + x0 ** 2 * y0 - y0 ** 3 / 3
    with np.errstate(invalid="ignore"):
        px = np.sqrt(2 * (E - V) - py0 ** 2)
    return np.vstack([np.full_like(y0, x0), y0, px, np.full_like(y0, py0)])


def reference_indicators(name, x0, pars=None, *, t_max, tol=None, renorm_dt=1.0, batch_size=None) -> Indicators:
    """Indicators of a reference system (no projection: for Henon-Heiles the energy direction's shear is
    linear and cannot make a regular orbit look chaotic).  x0 (n, N); pars default the classic ones."""
    sys_, p0 = reference_system(name)
    x0 = np.asarray(x0, float)
    N = x0.shape[1]
    p = np.repeat(np.asarray(p0 if pars is None else pars, float).reshape(-1, 1), N, axis=1) if len(p0) else \
        np.zeros((0, N))
    ta = systems.tangent_batch(sys_, len(p0), batch_size=batch_size, tol=tol)
    start = np.all(np.isfinite(x0), axis=0)
    ind = tangent_indicators(ta, np.nan_to_num(x0), generic_w0(x0.shape[0], N), p, t_max=t_max,
                             renorm_dt=renorm_dt, valid=start)
    ind.status[~start] = NO_ROOT  # e.g. a Henon-Heiles start whose energy level is not reached
    return ind


# ----------------------------------------------------------------------------------------------------------
# any model in its body frame (the same engine: tangent_indicators with the model's tangent integrator)
# ----------------------------------------------------------------------------------------------------------
class _ModelCheck:
    """A model's conservation budget along an orbit: |H - H0| and max_k |C_k - C_k0|, each relative to the size
    of its terms at the start (systems.term_scale, at least 1); an orbit beyond DRIFT_LIMIT has left its invariant
    set (LEFT_RANGE).  A model has no axial-stretch convention of the paper's: min_stretch is NaN."""

    def __init__(self, system, x0, p):
        self.system = system
        self.mb = systems.model_body(system)
        self.g0 = self.mb.level(x0, p)
        self.scale = np.maximum(1.0, np.concatenate([systems.term_scale(system, "H", x0, p),
                                                     systems.term_scale(system, "casimirs", x0, p)]))

    def __call__(self, x, p):
        d = np.abs(self.mb.level(x, p) - self.g0) / self.scale
        dH = d[0]
        dC = np.max(d[1:], axis=0) if d.shape[0] > 1 else np.zeros_like(dH)
        ok = (dH <= DRIFT_LIMIT) & (dC <= DRIFT_LIMIT)
        # row 3 is -v3 (min_stretch = -max): -NaN here so that min_stretch is the canonical +NaN (a zarr chunk of
        # the fill value reads back bit for bit)
        return ok, np.vstack([dH, dC, np.full_like(dH, -np.nan)])


def model_project(system):
    """project(x, w, p) onto the tangent space of the level set of every first integral the model states (H, the
    Casimirs, state components with zero right-hand side: systems.ModelBody.neutral_gradients)."""
    G = systems.model_body(system).neutral_gradients
    return lambda x, w, p: _project(G(x, p), x, w)


def model_indicators(system, x0, *, t_max, tol=None, renorm_dt=DEFAULT_RENORM_DT, project=True, batch_size=None,
                     w0=None, valid=None, history=False, exit_above=None, pars=None) -> Indicators:
    """`body_indicators` for any System: orbits x0 (dim, N) of its model, parameters pars (npars, N) (default the
    System's values for every orbit).  The paper's rod is `body_indicators` itself (the same compiled code)."""
    x0 = np.asarray(x0, float)
    x0 = x0[:, None] if x0.ndim == 1 else x0
    n, N = x0.shape
    p = system.array() if pars is None else np.asarray(pars, float)
    p = np.repeat(p[:, None], N, axis=1) if p.ndim == 1 else p
    if system.is_paper:
        return body_indicators(x0, p, t_max=t_max, tol=tol, renorm_dt=renorm_dt, project=project,
                               batch_size=batch_size, w0=w0, valid=valid, history=history, exit_above=exit_above)
    ta = systems.model_tangent_batch(system, batch_size, tol)
    w0 = generic_w0(n, N) if w0 is None else np.asarray(w0, float).reshape(n, -1)
    return tangent_indicators(ta, x0, w0, p, t_max=t_max, renorm_dt=renorm_dt,
                              project=model_project(system) if project else None,
                              check=lambda xs, ps: _ModelCheck(system, xs, ps), valid=valid, history=history,
                              exit_above=exit_above)
