"""The one integrator layer: every heyoka integrator, event and compiled function magrod uses is built here,
from the expressions that derive/ wrote into generated/, with generated/names.py as the only list of names.

Formulations (paper sec. 2 and 4):
  "body"     the singularity-free 9-D system x' = J(x) grad H in (m, n, e3)        (generated/body.py)
  "reduced"  the canonical 4-D system of Hbar in (theta, psi, pbar_theta, pbar_psi) (generated/reduced.py)
Runtime parameters hy.par[i] = PARAMS[i] = (m, mu, gamma, delta, lam), so one compiled integrator serves every
parameter value: build once, then reset time/state/pars (`reset`) and reuse.  heyoka's on-disk JIT cache makes
a second process load instead of compile (~20 ms instead of ~1 s).

Builders (keyword-only options; `precision` is a core.precision.Precision or its name, `bits` the significand
width of Precision.MP runs (default MP_BITS) and nothing else.  The old spelling fp_type=/prec= (a number type and
hy.real's bit count) is still accepted by every builder for one release and is deprecated (one
vocabulary):
  taylor(sys, state, pars, ...)              any system: the one place hy.taylor_adaptive is called
  build(constructor, ...)                    every heyoka constructor goes through it (damaged JIT cache entries)
  integrator(formulation, events=...)        scalar integrator of a formulation, events by name
  batch_integrator(formulation, ...)         SIMD batch integrator (batch size: `batch_width()`, a setting:
                                             $MAGROD_BATCH_WIDTH, else hy.recommended_simd_size())
  variational_integrator(formulation, ...)   first-order variational equations (hy.var_ode_sys) w.r.t. the
                                             initial state and the parameters; `variational_blocks` splits them
  rod_frame_integrator()                     body system + director frame + centreline (magrod.orbits.rod)
Events are named (generated BODY_EVENTS, or "section", "sin_theta", "radicand" in the reduced system) and built
with a direction and an offset: event = expression - offset.

Cost: each builder compiles on first use per process (or loads from the JIT cache); the `per_thread` cache
keeps one mutable integrator per thread and configuration.
"""
from __future__ import annotations

import os
import threading
import warnings
from functools import lru_cache, wraps

import heyoka as hy
import numpy as np

from ..generated import body, names, reduced
from .errors import MagrodWarning
from .precision import MP_BITS, Precision

PARAMS = names.PARAMS
STATE = {"body": names.BODY_STATE, "reduced": names.REDUCED_STATE}
FORMULATIONS = tuple(STATE)
_GEN = {"body": body, "reduced": reduced}
# event name -> generated function, per formulation
EVENTS = {"body": {k: getattr(body, k) for k in names.BODY_EVENTS},
          "reduced": {"section": reduced.section, "sin_theta": reduced.sin_theta, "radicand": reduced.radicand}}
DIRECTIONS = {"positive": hy.event_direction.positive, "negative": hy.event_direction.negative,
              "any": hy.event_direction.any}


# --------------------------------------------------------------------------------------------------------------
# heyoka's on-disk JIT cache: never on our stdout, never a stall
# --------------------------------------------------------------------------------------------------------------
MIN_FREE_BYTES = 64 * 2**20
_cache_note: list = []


def _warn(text: str) -> None:
    """A MagrodWarning (the CLI prints it as one stderr line; a notebook shows it as Python warnings are shown)."""
    warnings.warn(" ".join(text.split()), MagrodWarning, stacklevel=3)


QUIET_ENV = "MAGROD_QUIET_HEYOKA"  # set by the CLI (and inherited by its worker processes): heyoka's logger off
_probed: list = []


def _probe_once() -> None:
    """The disk-cache probe, once per process, at the first build (never at import: importing magrod changes
    nothing in the process)."""
    if not _probed:
        _probed.append(True)
        configure_jit_cache()


def configure_jit_cache() -> str | None:
    """heyoka waits up to a minute on a locked cache database and logs cache trouble to *stdout* (which would
    break the CLI's --json).  So the disk cache is probed once per process, at the first build (creatable,
    writable, >= 64 MB free, database not locked and not damaged, each answered within ~0.5 s); if the probe fails
    the disk cache is switched off with one MagrodWarning (builds then compile, ~1 s each, instead of loading).  heyoka's logger
    is limited to critical messages only when the CLI asked for it (environment variable MAGROD_QUIET_HEYOKA): a
    library does not reconfigure its host's loggers.  Returns the reason the cache was switched off, or None."""
    if os.environ.get(QUIET_ENV):
        hy.set_logger_level_critical()
    if not hy.llvm_state.get_diskcache_enabled():
        return None
    path = str(hy.llvm_state.get_diskcache_path())
    reason = None
    try:
        os.makedirs(path, exist_ok=True)
        if not os.access(path, os.W_OK | os.X_OK):
            reason = "not writable"
        elif __import__("shutil").disk_usage(path).free < MIN_FREE_BYTES:
            reason = "less than 64 MB free"
    except OSError as exc:
        reason = exc.strerror or str(exc)
    db = os.path.join(path, "cache.db")
    if reason is None and os.path.exists(db):
        import sqlite3

        try:
            con = sqlite3.connect(db, timeout=0.5)
            try:
                con.execute("BEGIN IMMEDIATE")
                con.rollback()
                # a damaged database (found on a development machine: an index out of step with its table, cause
                # not identified) fails every lookup: heyoka then compiles each integrator and logs an error per
                # build.  integrity_check stops at the first error (~0.05 s for a healthy 140 MB cache)
                bad = con.execute("PRAGMA integrity_check(1)").fetchone()[0]
                if bad != "ok":
                    raise sqlite3.DatabaseError(f"damaged: {bad}; delete it to rebuild")
            finally:
                con.close()
        except sqlite3.Error as exc:
            reason = f"database unusable ({exc})"
    if reason is not None:
        hy.llvm_state.set_diskcache_enabled(False)
        _cache_note.append(reason)
        _warn(f"heyoka JIT cache {path!r} {reason}: running without it (integrators are compiled, not loaded)")
    return reason


def bypass_disk_cache(clear: bool = False) -> None:
    """Stop using the on-disk JIT cache in this process and rebuild every integrator (used when a result fails
    its accuracy checks: a damaged cache entry must not be hit again); clear=True also empties the cache."""
    if clear:
        try:
            hy.llvm_state.clear_diskcache()
        except Exception as exc:  # best effort: the cache is off for this process either way
            _warn(f"could not clear the heyoka JIT cache: {exc}")
    hy.llvm_state.set_diskcache_enabled(False)
    hy.llvm_state.clear_memcache()
    clear_caches()


_GENERATION = [0]  # bumped by clear_caches: per-thread caches (of every thread) then build afresh
_CACHES: list = []  # every process-wide cache of compiled objects (`cache`); clear_caches empties them all


def cache(fn):
    """functools.lru_cache(maxsize=None) of fn, registered so that `clear_caches` (and `bypass_disk_cache`)
    empties it: every cache of compiled heyoka objects (cfuncs, expressions) in magrod is made with this."""
    cached = lru_cache(maxsize=None)(fn)
    _CACHES.append(cached)
    return cached


def clear_caches() -> None:
    """Forget every compiled object magrod holds: the `cache` caches of every module and the `per_thread`
    integrators of every thread (by generation: a thread's next call builds afresh)."""
    _GENERATION[0] += 1
    for c in _CACHES:
        c.cache_clear()


def build(constructor, *args, **kwargs):
    """Call a heyoka constructor (hy.taylor_adaptive, hy.taylor_adaptive_batch, hy.cfunc).  If it fails while
    the on-disk JIT cache is on, a damaged cache entry is the likely cause: it is built again with the disk cache
    off, and if that works the cache is cleared (one warning on stderr) so that the entry is not hit again."""
    _probe_once()
    try:
        return constructor(*args, **kwargs)
    except Exception:
        if not hy.llvm_state.get_diskcache_enabled():
            raise
        hy.llvm_state.set_diskcache_enabled(False)
        try:
            obj = constructor(*args, **kwargs)
        except Exception:
            hy.llvm_state.set_diskcache_enabled(True)
            raise
        try:
            hy.llvm_state.clear_diskcache()
        except Exception:  # best effort: the cache stays off for this process either way
            pass
        _warn("building a compiled integrator from the heyoka JIT cache failed; the cache was cleared and the "
              "integrator compiled afresh")
        return obj


def par_index(name: str) -> int:
    """Position of a parameter name in PARAMS (= its hy.par index)."""
    return PARAMS.index(name)


def state_index(formulation: str, name: str) -> int:
    return STATE[formulation].index(name)


def dim(formulation: str) -> int:
    return len(STATE[formulation])


def per_thread(fn):
    """Cache fn(*key) once per thread: integrators are mutable, so threads must not share them.  `clear_caches`
    invalidates every thread's entries (the key includes the cache generation)."""
    local = threading.local()

    @wraps(fn)
    def wrapper(*key):
        cache = local.__dict__.setdefault("cache", {})
        k = (_GENERATION[0], *key)
        if k not in cache:
            cache[k] = fn(*key)
        return cache[k]

    wrapper.cache_clear = lambda: local.__dict__.pop("cache", None)
    return wrapper


# --------------------------------------------------------------------------------------------------------------
# expressions
# --------------------------------------------------------------------------------------------------------------
@cache
def variables(formulation: str) -> tuple:
    return tuple(hy.make_vars(*STATE[formulation]))


def pars() -> list:
    """hy.par[i] for every name in PARAMS."""
    return body.pars()


def system(formulation: str) -> list:
    """[(variable, rhs)] of a formulation."""
    return _GEN[formulation].system()


def expression(formulation: str, fname: str):
    """A generated function of a formulation (e.g. "hamiltonian", "section") applied to its variables and pars."""
    return getattr(_GEN[formulation], fname)(*variables(formulation), *pars())


def event_expression(formulation: str, name: str):
    if name not in EVENTS[formulation]:
        raise ValueError(f"unknown {formulation} event {name!r}; known: {sorted(EVENTS[formulation])}")
    return EVENTS[formulation][name](*variables(formulation), *pars())


def arithmetic(precision=Precision.DOUBLE, bits=None, *, fp_type=None, prec=None) -> tuple:
    """(Precision, bits) of a builder call: `precision` (a Precision, its name, or for one release a number type
    float/np.longdouble/hy.real128/hy.real) with `bits` for Precision.MP (default MP_BITS; None otherwise).
    fp_type=/prec= are the deprecated spelling of the same."""
    if fp_type is not None:
        precision, bits = fp_type, prec if bits is None else bits
    if not isinstance(precision, (Precision, str)):
        precision = Precision.of(precision)
    precision = Precision.parse(precision)
    if precision is not Precision.MP:
        return precision, None
    return precision, int(bits or MP_BITS)


def number(x, precision=Precision.DOUBLE, bits=None):
    """x as a number of the precision (hy.real at `bits`; strings parsed in full precision)."""
    precision, bits = arithmetic(precision, bits)
    return _fp(precision.fp_type, x, bits)


def _fp(fp_type, x, prec=None):
    """x converted to fp_type (hy.real at `prec` bits).  The number-type form of `number`, kept for its callers."""
    if fp_type is hy.real:
        return x if isinstance(x, hy.real) else hy.real(float(x) if not isinstance(x, str) else x, prec)
    if fp_type is float:
        return float(x)
    return fp_type(x)


def t_event(formulation: str, name: str, direction="any", offset=0.0, *, precision=Precision.DOUBLE, bits=None,
            batch=False, fp_type=None, prec=None):
    """A stopping terminal event `expression - offset = 0` (no callback: the integrator stops on it and the
    state lands on the event surface to ~1e-17).  direction: "positive", "negative" or "any" (sign of d/dt of
    the expression at the crossing).  precision/bits: the integrator's (fp_type/prec: deprecated spelling)."""
    precision, bits = arithmetic(precision, bits, fp_type=fp_type, prec=prec)
    fp_type = precision.fp_type
    e = event_expression(formulation, name)
    if offset:
        e = e - hy.expression(_fp(fp_type, offset, bits)) if fp_type is hy.real else e - float(offset)
    d = DIRECTIONS[direction]
    if batch:
        return hy.t_event_batch(e, direction=d)
    if fp_type is float:
        return hy.t_event(e, direction=d)
    return hy.t_event(e, direction=d, fp_type=fp_type)


# --------------------------------------------------------------------------------------------------------------
# builders
# --------------------------------------------------------------------------------------------------------------
def taylor(sys, state, pars=(), *, precision=Precision.DOUBLE, bits=None, tol=None, t_events=(), nt_events=(),
           compact_mode=False, fp_type=None, prec=None, **kw):
    """hy.taylor_adaptive for any system: state and pars converted to the precision, tol None = its machine
    epsilon (Precision.MP: of `bits` bits).  fp_type=/prec=: the deprecated spelling of precision/bits."""
    precision, bits = arithmetic(precision, bits, fp_type=fp_type, prec=prec)
    fp_type = precision.fp_type
    if fp_type is float:
        return build(hy.taylor_adaptive, sys, [float(s) for s in state], pars=[float(p) for p in pars], tol=float(tol or 0.0),
                                  t_events=list(t_events), nt_events=list(nt_events), compact_mode=compact_mode, **kw)
    return build(hy.taylor_adaptive, sys, [_fp(fp_type, s, bits) for s in state], pars=[_fp(fp_type, p, bits) for p in pars],
                              tol=_fp(fp_type, tol or 0, bits), t_events=list(t_events), nt_events=list(nt_events),
                              fp_type=fp_type, compact_mode=compact_mode, **kw)


def _events(formulation, events, precision=Precision.DOUBLE, bits=None, batch=False):
    return [t_event(formulation, *ev, precision=precision, bits=bits, batch=batch) if isinstance(ev, tuple)
            else t_event(formulation, ev, precision=precision, bits=bits, batch=batch) for ev in events]


def _unit_state(formulation):
    """A harmless placeholder state for construction (the straight rod in the body frame, theta = 1 in 4-D)."""
    return [0, 0, 1, 0, 0, 1, 0, 0, 1] if formulation == "body" else [1, 0, 0, 0]


def integrator(formulation: str = "body", *, events=(), precision=Precision.DOUBLE, bits=None, tol=None,
               compact_mode=False, fp_type=None, prec=None):
    """Scalar Taylor integrator of a formulation.  events: names, or tuples (name, direction[, offset]), in the
    order of the event indices heyoka reports (-1 - index).  State and pars are placeholders: call `reset`
    (`reset_any` for Precision.MP).  Precision.MP runs at `bits` bits.  fp_type=/prec=: deprecated spelling."""
    precision, bits = arithmetic(precision, bits, fp_type=fp_type, prec=prec)
    return taylor(system(formulation), _unit_state(formulation), [1.0] * len(PARAMS), precision=precision,
                  bits=bits, tol=tol, t_events=_events(formulation, events, precision, bits),
                  compact_mode=compact_mode)


# The batch width is a setting, not a fact of the CPU: heyoka compiles any batch size on any CPU (a width the
# vector unit does not have is split into its registers), so width 8 runs on an AVX2 machine and width 4 on an
# AVX-512 one.  Lanes step independently, so a result never depends on its neighbours; it may depend on the width
# through the vector math kernels' last bit, which is why the tests run the batch paths at widths 1, 2, 4 and 8
# (tests/test_portability.py) and a map store records the width in its identity.
BATCH_WIDTH_ENV = "MAGROD_BATCH_WIDTH"
MAX_BATCH_WIDTH = 64


def batch_width() -> int:
    """The SIMD batch width of every batch integrator: the environment variable MAGROD_BATCH_WIDTH if set (an
    integer in 1..64), else heyoka's recommended SIMD size for this CPU (4 with AVX2, 8 with AVX-512).  Read at
    each call, so a process can change it between runs; the per-thread caches key on the resolved width."""
    from .errors import ParameterError

    raw = os.environ.get(BATCH_WIDTH_ENV, "").strip()
    if not raw:
        return int(hy.recommended_simd_size())
    try:
        b = int(raw)
    except ValueError:
        raise ParameterError(BATCH_WIDTH_ENV, f"must be an integer in 1..{MAX_BATCH_WIDTH}, got {raw[:20]!r}") \
            from None
    if not 1 <= b <= MAX_BATCH_WIDTH:
        raise ParameterError(BATCH_WIDTH_ENV, f"must be an integer in 1..{MAX_BATCH_WIDTH}, got {b}")
    return b


def recommended_batch_size() -> int:
    """The batch width in use (`batch_width`); kept under its old name for its older callers."""
    return batch_width()


def batch_integrator(formulation: str = "body", *, batch_size=None, events=(), tol=None, compact_mode=False,
                     variational=False):
    """SIMD batch integrator (float64): batch_size lanes advance together (default the recommended SIMD width);
    state shape (n, batch_size), pars (len(PARAMS), batch_size).  variational=True integrates the first-order
    variational equations w.r.t. the initial state (not the parameters) as well."""
    b = int(batch_size or batch_width())
    sys_ = (hy.var_ode_sys(system(formulation), hy.var_args.vars, order=1) if variational
            else system(formulation))
    n = dim(formulation)
    st = np.repeat(np.array(_unit_state(formulation), float)[:, None], b, axis=1)
    if variational:
        st = np.vstack([st, np.zeros((n * n, b))])  # heyoka initialises the identity block itself
    return build(hy.taylor_adaptive_batch, sys_, st, pars=np.ones((len(PARAMS), b)), tol=float(tol or 0.0),
                                    t_events=_events(formulation, events, batch=True),
                                    compact_mode=compact_mode or variational)


def variational_integrator(formulation: str = "body", *, wrt_pars=True, precision=Precision.DOUBLE, tol=None,
                           events=(), fp_type=None):
    """Integrator of the state and its first-order sensitivities d x(t)/d x(0) (and d x(t)/d pars if
    wrt_pars), built with hy.var_ode_sys in compact mode (compiles in ~1 s instead of minutes).  heyoka
    initialises the sensitivities to the identity (state) and zero (pars) at construction; `reset_variational`
    does the same after a reset.  fp_type=: the deprecated spelling of precision."""
    precision, _ = arithmetic(precision, fp_type=fp_type)
    sys_ = system(formulation)
    # explicit list: every parameter gets a column, also those absent from the vector field (mu in the body frame)
    args = [v for v, _ in sys_] + (pars() if wrt_pars else [])
    vsys = hy.var_ode_sys(sys_, args, order=1)
    return taylor(vsys, _unit_state(formulation), [1.0] * len(PARAMS), precision=precision, tol=tol,
                  t_events=_events(formulation, events, precision), compact_mode=True)


def reset(ta, state=None, t=0.0, pars=None):
    """Set time, (the leading components of) the state and the parameters of an integrator; reset the event
    cooldowns (needed after editing the state by hand)."""
    ftype = type(ta.state.flat[0])
    ta.time = float(t) if ftype is np.float64 else ftype(t)
    if state is not None:
        st = np.asarray(state)
        ta.state[: st.shape[0]] = st
    if pars is not None:
        ta.pars[:] = pars
    if ta.with_events:
        ta.reset_cooldowns()


def reset_any(ta, state, pars, precision, t=0.0, bits=None):
    """`reset` for an integrator of any Precision (Precision.MP included: time, state and pars are converted at
    the integrator's bits, which a plain `reset` cannot do)."""
    precision, bits = arithmetic(precision, bits)
    ta.time = number(t, precision, bits)
    ta.state[:] = state
    ta.pars[:] = fp_array(pars, precision, bits)
    if ta.with_events:
        ta.reset_cooldowns()


def reset_variational(ta, state, pars, t=0.0):
    """Reset a variational integrator to `state` with identity state sensitivities and zero parameter ones."""
    n = ta.n_orig_sv
    ftype = type(ta.state.flat[0])
    st = np.zeros(ta.dim, dtype=ta.state.dtype) if ftype is not hy.real else np.array(
        [ftype(0, ta.state[0].prec)] * ta.dim)
    st[:n] = state
    nv = len(ta.vargs)
    for i in range(n):
        st[n + i * nv + i] = 1  # d x_i / d x0_i; the vargs list the state variables first, then the parameters
    reset(ta, st, t, pars)


def variational_blocks(ta) -> tuple:
    """(x, Phi, Psi) of a variational integrator: the state (n,), d x/d x0 (n, n) and d x/d pars (n, npars)
    in PARAMS order (empty if built with wrt_pars=False), as float64 arrays."""
    n = ta.n_orig_sv
    D = np.asarray(ta.state[ta.get_vslice(order=1)]).reshape(n, len(ta.vargs))
    return np.array(ta.state[:n]), D[:, :n].astype(float), D[:, n:].astype(float)


def rod_frame_system():
    """The body system plus the director frame D' = D hat(u) and the centreline r' = D v (21 equations), with
    the strains u = dH/dm, v = dH/dn of the constitutive law (magrod.orbits.rod): `frame_system` of the paper's
    rod, whose body state starts (m1, m2, m3, n1, n2, n3)."""
    return frame_system(variables("body"), pars(), body.hamiltonian, system("body"), tuple(range(6)))


def frame_system(x, p, hamiltonian, sys_, strains: tuple) -> list:
    """A model's body system `sys_` ([(variable, rhs)] in the variables x, parameters p) plus the director frame
    D' = D hat(u) and the centreline r' = D v: len(x) + 12 equations, the strains u = dH/dm, v = dH/dn by hy.diff
    of the generated `hamiltonian`; `strains` the indices of (m1, m2, m3, n1, n2, n3) in the state."""
    H = hamiltonian(*x, *p)
    u = [hy.diff(H, x[i]) for i in strains[:3]]
    v = [hy.diff(H, x[i]) for i in strains[3:]]
    D = hy.make_vars(*[f"D{i}{j}" for i in range(3) for j in range(3)])
    r = hy.make_vars("r1", "r2", "r3")
    hat = [[None, -u[2], u[1]], [u[2], None, -u[0]], [-u[1], u[0], None]]
    sys_ = list(sys_)
    # D = [d1 d2 d3] (columns: the directors in space components): d_i' = u x d_i is D' = D hat(u)
    for i in range(3):
        for j in range(3):
            sys_.append((D[3 * i + j], hy.sum([D[3 * i + k] * hat[k][j] for k in range(3) if hat[k][j] is not None])))
    # r' = sum_i v_i d_i = D v
    for i in range(3):
        sys_.append((r[i], hy.sum([D[3 * i + k] * v[k] for k in range(3)])))
    return sys_


@per_thread
def rod_frame_integrator():
    sys_ = rod_frame_system()
    return taylor(sys_, [0.0] * len(sys_), [1.0] * len(PARAMS))


# --------------------------------------------------------------------------------------------------------------
# compiled functions
# --------------------------------------------------------------------------------------------------------------
class CFunc:
    """A compiled heyoka function of some variables and (a prefix of) the runtime parameters PARAMS."""

    def __init__(self, exprs, variables_):
        self._cf = build(hy.cfunc, list(exprs), vars=list(variables_))

    @property
    def nparams(self) -> int:
        return self._cf.nparams

    def __call__(self, x, pars_):
        """x of shape (nvars,) or (nvars, N); pars_ of shape (len(PARAMS),) (shared) or (len(PARAMS), N)
        (one parameter set per column)."""
        x = np.ascontiguousarray(x, dtype=float)
        p = np.ascontiguousarray(np.asarray(pars_, dtype=float)[: self._cf.nparams])
        if not self._cf.nparams:
            return self._cf(x)
        if x.ndim == 1 or p.ndim == 2:
            return self._cf(x, pars=p)
        # batch mode: x of shape (nvars, N); heyoka wants pars of shape (nparams, N)
        return self._cf(x, pars=np.ascontiguousarray(np.repeat(p[:, None], x.shape[1], axis=1)))


@cache
def reduced_functions() -> dict:
    """Compiled Hbar, I2bar, radicand, section, the vector field and the axial stretch v3 (chart form) of the
    reduced system."""
    x = variables("reduced")
    p = pars()
    return {"H": CFunc([reduced.hamiltonian(*x, *p)], x), "I2": CFunc([reduced.i2bar(*x, *p)], x),
            "radicand": CFunc([reduced.radicand(*x, *p)], x), "section": CFunc([reduced.section(*x, *p)], x),
            "rhs": CFunc(reduced.rhs(*x, *p), x), "stretch": CFunc([reduced.stretch(*x, *p)], x)}


@cache
def body_functions() -> dict:
    """Compiled body-frame H - offset (= Hbar on the chart), Casimirs, the vector field, its Jacobian (hy.diff)
    and the two chart maps."""
    x = variables("body")
    p = pars()
    q = hy.make_vars(*names.CHART)
    f = body.rhs(*x, *p)
    return {"H": CFunc([body.hamiltonian(*x, *p) - body.hamiltonian_offset(*p)], x),
            "casimirs": CFunc(body.casimirs(*x, *p), x),
            "casimir_values": CFunc(body.casimir_values(*p), []),
            "rhs": CFunc(f, x),
            "events": CFunc([e(*x, *p) for e in EVENTS["body"].values()], x),
            "jacobian": CFunc([hy.diff(fi, xj) for fi in f for xj in x], x),
            "to_body": CFunc(body.euler_to_body(*q, *p), q),
            "to_euler": CFunc(body.body_to_euler(*x, *p), x)}


def euler_to_body(theta, psi, ptheta, ppsi, pars_, phi=0.0) -> np.ndarray:
    """(m, n, e3) of a reduced state; phi (the cyclic twist angle) is free and defaults to 0."""
    chart = dict(theta=theta, psi=psi, phi=phi, ptheta=ptheta, ppsi=ppsi)
    return body_functions()["to_body"]([chart[k] for k in names.CHART], pars_)


def body_to_euler(x, pars_) -> np.ndarray:
    """CHART coordinates (theta, psi, phi, pbar_theta, pbar_psi) of a body state (x of shape (9,) or (9, N));
    sin(theta) > 0."""
    return body_functions()["to_euler"](x, pars_)


def n_casimirs() -> int:
    """Number of Casimirs of the body system (generated body.casimir_values)."""
    return len(body.casimir_values(*[1.0] * len(PARAMS)))


def chart_index(name: str) -> int:
    return names.CHART.index(name)


# --------------------------------------------------------------------------------------------------------------
# periodic saddle, homoclinic orbits to it, continuation: cached builders
# --------------------------------------------------------------------------------------------------------------
def cached_variational(precision=Precision.DOUBLE):
    """The one body-frame variational integrator (w.r.t. the 9 initial values and the 5 parameters, tol = eps of
    the precision) per thread and Precision (DOUBLE or LONG_DOUBLE; a value of Precision is accepted); reset with
    `reset_variational`, never rebuilt per orbit.  Every Newton and monodromy computation of magrod.orbits uses it."""
    return _cached_variational(Precision.parse(precision))


@per_thread
def _cached_variational(precision):
    return variational_integrator("body", wrt_pars=True, precision=precision)


@cache
def body_casimir_gradients() -> CFunc:
    """Gradients of the Casimirs C1, C2, C3 (3 x 9, row-major) by hy.diff of the generated expressions."""
    x = variables("body")
    return CFunc([hy.diff(c, xi) for c in body.casimirs(*x, *pars()) for xi in x], x)


# --------------------------------------------------------------------------------------------------------------
# compiled functions in any precision (magrod/splitting.py)
# --------------------------------------------------------------------------------------------------------------
def fp_array(values, precision=Precision.DOUBLE, bits=None) -> np.ndarray:
    """values as a numpy array of the precision (Precision.MP at `bits`); strings are parsed in full precision.
    A number type in place of `precision` (float, np.longdouble, hy.real128, hy.real) is the deprecated spelling."""
    precision, bits = arithmetic(precision, bits)
    fp_type = precision.fp_type
    if fp_type is hy.real:
        return np.array([v if isinstance(v, hy.real) else hy.real(v if isinstance(v, str) else float(v), bits)
                         for v in values])
    if fp_type is float:
        return np.array([float(v) for v in values], dtype=float)
    return np.array([fp_type(v) for v in values])


class PrecisionCFunc:
    """A compiled heyoka function in a Precision (Precision.MP at `bits`) of some variables and the runtime
    parameters PARAMS (only those it uses are passed).  A number type in place of `precision` is deprecated."""

    def __init__(self, exprs, variables_, precision=Precision.DOUBLE, bits=None):
        self.precision, self.bits = arithmetic(precision, bits)
        fp_type = self.precision.fp_type
        kw = {"fp_type": fp_type} if fp_type is not float else {}
        if fp_type is hy.real:
            kw["prec"] = self.bits
        self._cf = build(hy.cfunc, list(exprs), vars=list(variables_), **kw)

    @property
    def fp_type(self):
        """The number type (deprecated: use `precision`)."""
        return self.precision.fp_type

    def __call__(self, x, pars_=()):
        x = fp_array(x, self.precision, self.bits)
        if self._cf.nparams:
            return self._cf(x, pars=fp_array(list(pars_)[: self._cf.nparams], self.precision, self.bits))
        return self._cf(x)


def splitting_functions(precision=Precision.DOUBLE, bits=None) -> dict:
    """`_splitting_functions` cached per (Precision, bits); a number type in place of `precision` is deprecated."""
    return _splitting_functions(*arithmetic(precision, bits))


@cache
def _splitting_functions(precision, bits) -> dict:
    """Body-frame functions evaluated in the working precision at a section crossing, and the reduced chart's
    vector field, its Jacobian (hy.diff) and the chart -> body map, all compiled for fp_type:
      "chart"     body_to_euler (theta, psi, phi, pbar_theta, pbar_psi)
      "fix"       (e31 n2 - e32 n1)/sin(theta) = rho sin(psi): the component of the force that the reversor
                  flips, i.e. the distance of a state with pbar_theta = 0 from Fix(R) (modulo rotations)
      "H", "casimirs", "casimir_values", "reduced_rhs", "reduced_jacobian", "to_body" (phi = 0)."""
    fp_type = precision.fp_type
    x = variables("body")
    p = pars()
    q = variables("reduced")
    e31, e32 = x[state_index("body", "e31")], x[state_index("body", "e32")]
    fr = reduced.rhs(*q, *p)
    phi0 = hy.expression(0.0) if fp_type is not hy.real else hy.expression(hy.real(0, bits))
    to_body = body.euler_to_body(q[0], q[1], phi0, q[2], q[3], *p)

    def cf(exprs, vs):
        return PrecisionCFunc(exprs, vs, precision, bits)

    return {"chart": cf(body.body_to_euler(*x, *p), x),
            "fix": cf([body.section(*x, *p) / hy.sqrt(e31**2 + e32**2)], x),
            "H": cf([body.hamiltonian(*x, *p) - body.hamiltonian_offset(*p)], x),
            "casimirs": cf([c - v for c, v in zip(body.casimirs(*x, *p), body.casimir_values(*p))], x),
            "reduced_rhs": cf(fr, q),
            "reduced_jacobian": cf([hy.diff(fi, qj) for fi in fr for qj in q], q),
            "to_body": cf(to_body, q)}


# --------------------------------------------------------------------------------------------------------------
# tangent-vector integrators for chaos indicators (magrod.chaos.indicators)
# --------------------------------------------------------------------------------------------------------------
def tangent_system(sys_, npars: int):
    """x' = f(x), w' = Df(x) w: the first-order variational equations along ONE tangent vector w.

    Built with hy.var_ode_sys w.r.t. a parameter hy.par[npars] that f does not contain: its sensitivity
    w = dx/dp obeys w' = Df(x) w + df/dp = Df(x) w exactly, and its initial value is ours to set (heyoka starts
    it at 0; `magrod.chaos.indicators` writes the tangent vector there).  n + n equations instead of the n + n^2 of the
    full matrix Phi: ~14x cheaper for the 9-D body system (benchmarks/README.md)."""
    return hy.var_ode_sys(sys_, [hy.par[int(npars)]], order=1)


def tangent_batch(sys_, npars: int, *, batch_size=None, tol=None):
    """SIMD batch integrator of `tangent_system(sys_, npars)`, float64, non-compact mode (compiled once, then
    loaded from the JIT cache; compact mode is ~2x slower to run).  State shape (2n, batch_size): rows
    [0, n) the state, rows [n, 2n) the tangent vector; pars (npars, batch_size)."""
    b = int(batch_size or batch_width())
    vs = tangent_system(sys_, npars)
    return build(hy.taylor_adaptive_batch, vs, np.ones((2 * len(sys_), b)), pars=np.ones((int(npars), b)),
                                    tol=float(tol or 0.0))


@per_thread
def _body_tangent_batch(batch_size, tol):
    return tangent_batch(system("body"), len(PARAMS), batch_size=batch_size, tol=tol)


def body_tangent_batch(batch_size=None, tol=None):
    """`tangent_batch` of the body system, cached per thread and (resolved batch width, tol)."""
    return _body_tangent_batch(int(batch_size or batch_width()), tol)


@cache
def body_neutral_gradients() -> CFunc:
    """Gradients of the body system's first integrals, stacked row-wise (k x 9 outputs): the Casimirs C1..C3,
    H, and every state component whose generated right-hand side is identically 0 (m3 = I1, the twist, for
    the isotropic rod).  Their kernel is the tangent space of the invariant level set through x."""
    x = variables("body")
    p = pars()
    f = [r for _, r in system("body")]
    integrals = list(body.casimirs(*x, *p)) + [body.hamiltonian(*x, *p)]
    integrals += [x[i] for i, fi in enumerate(f) if fi == hy.expression(0.0)]
    return CFunc([hy.diff(g, xj) for g in integrals for xj in x], x)


@cache
def body_renorm_functions() -> CFunc:
    """One compiled function with everything a chaos indicator evaluates at a renormalisation (one call instead
    of four): rows [H - offset, C1, C2, C3, v3 = dH/dn3, then the k x 9 gradients of body_neutral_gradients].
    Each output is the same expression as in body_functions / body_stretch / body_neutral_gradients, compiled
    together: the values are bit-identical to those of the separate functions (tests/test_chaos_speed.py)."""
    x = variables("body")
    p = pars()
    H = body.hamiltonian(*x, *p)
    f = [r for _, r in system("body")]
    integrals = list(body.casimirs(*x, *p)) + [H]
    integrals += [x[i] for i, fi in enumerate(f) if fi == hy.expression(0.0)]
    return CFunc([H - body.hamiltonian_offset(*p), *body.casimirs(*x, *p),
                  hy.diff(H, x[state_index("body", "n3")]), *[hy.diff(g, xj) for g in integrals for xj in x]], x)


@cache
def body_stretch() -> CFunc:
    """The axial stretch v3 = dH/dn3 of the constitutive law (eq:hyperelastic); a physical rod has v3 > 0."""
    x = variables("body")
    return CFunc([hy.diff(body.hamiltonian(*x, *pars()), x[state_index("body", "n3")])], x)


# --------------------------------------------------------------------------------------------------------------
# any model of the registry or a model file: its body-frame field x' = J(x) grad H (generated body.py of the model)
# --------------------------------------------------------------------------------------------------------------
PAPER_KEY = "paper"  # the paper's rod: the top-level generated tree (generated/body.py), at its numeric scale


class ModelBody:
    """One model's body-frame field, compiled once per model and process (never per parameter value: the model's
    parameters are the runtime parameters hy.par[i] = names[i]).  Built by `model_body(system)`.

    state, params, casimir_names: the model's names; `expr(name)` the generated expressions of
    "H" (for the paper's rod H - offset = Hbar on the chart), "casimirs", "section", "rhs"; compiled functions
    (CFunc, evaluated on (n,) or (n, N) states): `level` = (H, C1, ...), `level_gradients` ((1 + k) x n, row-major),
    `level_scale` (the size of each of (H, C1, ...)'s terms at the state: `term_scale`), `rhs`, `jacobian`,
    `neutral_gradients` (the gradients of every first integral the model states: H, the Casimirs and each state
    component whose right-hand side is identically 0), `section`.  Integrators: `integrator`, `batch_integrator`,
    `tangent_batch`, `variational_integrator` (per thread, reset before use)."""

    def __init__(self, key, name, state, params, module, is_paper):
        self.key, self.name, self.is_paper = key, name, is_paper
        self.state, self.params, self.module = tuple(state), tuple(params), module
        x = self.variables
        p = self.pars
        self.casimir_names = tuple(f"C{i + 1}" for i in range(len(module.casimirs(*x, *p))))

    @property
    def dim(self) -> int:
        return len(self.state)

    @property
    def n_casimirs(self) -> int:
        return len(self.casimir_names)

    @property
    def variables(self) -> tuple:
        return _model_variables(self.state)

    @property
    def pars(self) -> list:
        return [hy.par[i] for i in range(len(self.params))]

    def system(self) -> list:
        """[(variable, rhs)]."""
        return self.module.system() if self.is_paper else list(zip(self.variables, self.expr("rhs")))

    def expr(self, what: str):
        x, p, m = self.variables, self.pars, self.module
        if what == "H":
            H = m.hamiltonian(*x, *p)
            return H - m.hamiltonian_offset(*p) if self.is_paper else H
        if what == "casimirs":
            return list(m.casimirs(*x, *p))
        if what == "section":
            return m.section(*x, *p)
        if what == "rhs":
            return [r for _, r in m.system()] if self.is_paper else list(m.rhs(*x, *p))
        raise ValueError(f"unknown expression {what!r}")

    def integrals(self) -> list:
        """H, the Casimirs, and each state component whose right-hand side is identically 0 (e.g. the twist m3
        of an isotropic rod): every first integral the model states, whose gradients span the directions across
        the orbit's invariant level set."""
        x = self.variables
        zero = [x[i] for i, f in enumerate(self.expr("rhs")) if f == hy.expression(0.0)]
        return [self.expr("H"), *self.expr("casimirs"), *zero]

    def __getattr__(self, name):  # the compiled functions, built on first use and kept
        if name not in _MODEL_CFUNCS:
            raise AttributeError(name)
        return _model_cfunc(self.key, name)

    def __repr__(self) -> str:
        return f"ModelBody({self.name!r}, state={self.state}, params={self.params})"


_MODEL_CFUNCS = ("level", "level_gradients", "rhs", "jacobian", "neutral_gradients", "section")
_MODEL_BODIES: dict = {}  # key -> ModelBody (the model's expressions; the compiled objects are in `cache`s)


@lru_cache(maxsize=None)
def _model_variables(state: tuple) -> tuple:
    return tuple(hy.make_vars(*state))


def model_key(system) -> str:
    """The key of a System's model in every per-model cache: PAPER_KEY for the paper's rod, else the directory of
    its generated code (a registry package, or a model file's content-keyed cache entry)."""
    return PAPER_KEY if system.is_paper else system.code.directory


def model_body(system) -> ModelBody:
    """The ModelBody of a System's model (core.system.System; built once per model and process)."""
    key = model_key(system)
    mb = _MODEL_BODIES.get(key)
    if mb is None:
        if system.is_paper:
            mb = ModelBody(key, system.model, names.BODY_STATE, PARAMS, body, True)
        else:
            code = system.code
            mb = ModelBody(key, code.name, code.names.STATE, code.names.PARAMS, code.body, False)
        _MODEL_BODIES[key] = mb
    return mb


def body_of(key: str) -> ModelBody:
    """The ModelBody registered under a model key (what the per-thread builders compile)."""
    return _MODEL_BODIES[key]


@cache
def _model_cfunc(key: str, what: str) -> CFunc:
    mb = body_of(key)
    x = mb.variables
    if what == "level":
        return CFunc([mb.expr("H"), *mb.expr("casimirs")], x)
    if what == "level_gradients":
        return CFunc([hy.diff(g, xj) for g in [mb.expr("H"), *mb.expr("casimirs")] for xj in x], x)
    if what == "rhs":
        return CFunc(mb.expr("rhs"), x)
    if what == "jacobian":
        return CFunc([hy.diff(fi, xj) for fi in mb.expr("rhs") for xj in x], x)
    if what == "neutral_gradients":
        return CFunc([hy.diff(g, xj) for g in mb.integrals() for xj in x], x)
    if what == "section":
        return CFunc([mb.expr("section")], x)
    raise ValueError(what)


class _Terms:
    """A number and the sum of the absolute values of the terms it is made of, carried through + - * / ** (the
    generated expressions are sums of products of state variables and parameters): `term_scale`."""

    __slots__ = ("v", "s")

    def __init__(self, v, s):
        self.v, self.s = v, s

    @staticmethod
    def of(a):
        return a if isinstance(a, _Terms) else _Terms(a, np.abs(a))

    def __add__(self, o):
        o = _Terms.of(o)
        return _Terms(self.v + o.v, self.s + o.s)

    __radd__ = __add__

    def __sub__(self, o):
        o = _Terms.of(o)
        return _Terms(self.v - o.v, self.s + o.s)

    def __rsub__(self, o):
        return _Terms.of(o) - self

    def __neg__(self):
        return _Terms(-self.v, self.s)

    def __mul__(self, o):
        o = _Terms.of(o)
        return _Terms(self.v * o.v, self.s * o.s)

    __rmul__ = __mul__

    def __truediv__(self, o):
        o = _Terms.of(o)
        return _Terms(self.v / o.v, self.s / np.abs(o.v))

    def __rtruediv__(self, o):
        return _Terms.of(o) / self

    def __pow__(self, k):
        return _Terms(self.v ** k, self.s ** k)


def term_scale(system, what: str, x, pars_=None) -> np.ndarray:
    """The size of the terms of H ("H") or of each Casimir ("casimirs") at the states x ((n,) or (n, N)): the sum
    of the absolute values of the terms of the generated expression (for a polynomial in expanded form, of its
    monomials).  A drift test relative to it is scaled by what the Casimir is made of, never by its value, which
    may be 0 (m.n on its zero level) or huge (m^2 + n^2/kappa at small kappa).  Evaluated by running the generated
    Python function on numbers that carry their terms' sizes (no SymPy, no compilation)."""
    import types

    mb = model_body(system)
    fn = {"H": mb.module.hamiltonian, "casimirs": mb.module.casimirs}[what]
    g = types.FunctionType(fn.__code__, {**fn.__globals__, "_E": lambda v: v})
    x = np.asarray(x, dtype=float)
    p = system.array() if pars_ is None else np.asarray(pars_, dtype=float)
    out = g(*[_Terms(xi, np.abs(xi)) for xi in x], *[_Terms(pi, np.abs(pi)) for pi in p])
    out = out if isinstance(out, list) else [out]
    return np.array([np.broadcast_to(_Terms.of(o).s, x.shape[1:]) for o in out], dtype=float)


def _model_events(mb: ModelBody, events, precision, bits, batch):
    out = []
    for ev in events:
        name, direction, *offset = ev if isinstance(ev, tuple) else (ev, "any")
        if name != "section":
            raise ValueError(f"unknown model event {name!r}; known: ['section']")
        e = mb.expr("section")
        if offset and offset[0]:
            e = e - float(offset[0])
        d = DIRECTIONS[direction]
        if batch:
            out.append(hy.t_event_batch(e, direction=d))
        elif precision.fp_type is float:
            out.append(hy.t_event(e, direction=d))
        else:
            out.append(hy.t_event(e, direction=d, fp_type=precision.fp_type))
    return out


@per_thread
def _model_integrator(key, events, precision, tol):
    mb = body_of(key)
    return taylor(mb.system(), [0.0] * mb.dim, [1.0] * len(mb.params), precision=precision, tol=tol,
                  t_events=_model_events(mb, events, precision, None, False))


def model_integrator(system, *, events=(), precision=Precision.DOUBLE, tol=None):
    """A per-thread scalar integrator of the System's model (for the paper's rod: `integrator("body", ...)`, the
    same compiled code), events by name ("section", or (name, direction[, offset])); reset before use."""
    precision = Precision.parse(precision)
    if system.is_paper:
        return _paper_integrator(tuple(events), precision, tol)
    model_body(system)
    return _model_integrator(model_key(system), tuple(events), precision, tol)


@per_thread
def _paper_integrator(events, precision, tol):
    return integrator("body", events=events, precision=precision, tol=tol)


@per_thread
def _model_batch(key, direction, tol, width):
    mb = body_of(key)
    st = np.ones((mb.dim, width))
    return build(hy.taylor_adaptive_batch, mb.system(), st, pars=np.ones((len(mb.params), width)),
                 tol=float(tol or 0.0), t_events=_model_events(mb, [("section", direction)], Precision.DOUBLE,
                                                              None, True))


def model_section_batch(key: str, direction: str, tol: float, width: int | None = None):
    """The batch integrator of a model (by `model_key`) with its section event in every lane: the paper's rod's
    is `batch_integrator("body", events=[("section", direction)])`; per thread and (direction, tol, width)."""
    width = int(width or batch_width())
    if key == PAPER_KEY:
        return _paper_section_batch(direction, tol, width)
    return _model_batch(key, direction, tol, width)


@per_thread
def _paper_section_batch(direction, tol, width):
    return batch_integrator("body", events=[("section", direction)], tol=tol, batch_size=width)


@per_thread
def _model_tangent(key, batch_size, tol):
    mb = body_of(key)
    return tangent_batch(mb.system(), len(mb.params), batch_size=batch_size, tol=tol)


def model_tangent_batch(system, batch_size=None, tol=None):
    """`tangent_batch` of the System's model (for the paper's rod: `body_tangent_batch`), per thread."""
    if system.is_paper:
        return body_tangent_batch(batch_size, tol)
    model_body(system)
    return _model_tangent(model_key(system), int(batch_size or batch_width()), tol)


@per_thread
def _model_variational(key, tol):
    mb = body_of(key)
    vsys = hy.var_ode_sys(mb.system(), list(mb.variables), order=1)
    return taylor(vsys, [0.0] * mb.dim, [1.0] * len(mb.params), tol=tol, compact_mode=True)


def model_variational(system, tol=None):
    """Integrator of the model's state and d x(t)/d x(0) (hy.var_ode_sys, compact mode), per thread; reset with
    `reset_variational`."""
    model_body(system)
    return _model_variational(model_key(system), tol)


@per_thread
def _model_frame(key, strains):
    mb = body_of(key)
    sys_ = frame_system(mb.variables, mb.pars, mb.module.hamiltonian, mb.system(), strains)
    return taylor(sys_, [0.0] * len(sys_), [1.0] * len(mb.params))


def model_frame_integrator(system, strains: tuple):
    """A per-thread integrator of the System's model's body state, its director frame and centreline
    (`frame_system`; `strains` the indices of m1, m2, m3, n1, n2, n3 in the state), tol = machine epsilon."""
    model_body(system)
    return _model_frame(model_key(system), tuple(int(i) for i in strains))
