"""heyoka building blocks from generated/: Taylor integrators and compiled functions for the reduced 4-D
canonical system and the 9-D body-frame system.  One set of runtime parameters hy.par[0..4] =
(m, mu, gamma, delta, lam) serves every parameter value, so each integrator is compiled once per process
(and loaded from heyoka's on-disk JIT cache in later processes); callers reset time/state/pars and reuse it."""
from __future__ import annotations

from functools import lru_cache

import heyoka as hy
import numpy as np

from .generated import body, reduced

REDUCED_STATE = reduced.STATE  # ('theta', 'psi', 'ptheta', 'ppsi')
BODY_STATE = body.STATE  # ('m1', 'm2', 'm3', 'n1', 'n2', 'n3', 'e31', 'e32', 'e33')


class CFunc:
    """A compiled heyoka function of some state variables and (a prefix of) the 5 runtime parameters."""

    def __init__(self, exprs, variables):
        self._cf = hy.cfunc(list(exprs), vars=list(variables))

    def __call__(self, x, pars):
        x = np.ascontiguousarray(x, dtype=float)
        p = np.ascontiguousarray(np.asarray(pars, dtype=float)[: self._cf.nparams])
        if x.ndim == 1:
            return self._cf(x, pars=p) if self._cf.nparams else self._cf(x)
        # batch mode: x of shape (nvars, N); heyoka wants pars of shape (nparams, N)
        pp = np.repeat(p[:, None], x.shape[1], axis=1)
        return self._cf(x, pars=pp) if self._cf.nparams else self._cf(x)


@lru_cache(maxsize=None)
def reduced_vars():
    return hy.make_vars(*REDUCED_STATE)


@lru_cache(maxsize=None)
def body_vars():
    return hy.make_vars(*BODY_STATE)


@lru_cache(maxsize=None)
def reduced_functions() -> dict:
    """Compiled Hbar, I2bar, radicand and the vector field of the reduced system."""
    x = reduced_vars()
    p = reduced.pars()
    return {"H": CFunc([reduced.hamiltonian(*x, *p)], x), "I2": CFunc([reduced.i2bar(*x, *p)], x),
            "radicand": CFunc([reduced.radicand(*x, *p)], x), "rhs": CFunc(reduced.rhs(*x, *p), x)}


@lru_cache(maxsize=None)
def body_functions() -> dict:
    """Compiled body-frame H - offset (= Hbar on the chart), Casimirs, and the two chart maps."""
    x = body_vars()
    p = body.pars()
    q = hy.make_vars("theta", "psi", "phi", "ptheta", "ppsi")
    return {"H": CFunc([body.hamiltonian(*x, *p) - body.hamiltonian_offset(*p)], x),
            "casimirs": CFunc(body.casimirs(*x, *p), x),
            "casimir_values": CFunc(body.casimir_values(*p), []),
            "to_body": CFunc(body.euler_to_body(*q, *p), q),
            "to_euler": CFunc(body.body_to_euler(*x, *p), x)}


def _integrator(sys, state, pars, tol, t_events, nt_events, fp_type, **kw):
    if fp_type is float:
        return hy.taylor_adaptive(sys, list(map(float, state)), pars=list(map(float, pars)), tol=tol or 0.0,
                                  t_events=list(t_events), nt_events=list(nt_events), **kw)
    return hy.taylor_adaptive(sys, [fp_type(s) for s in state], pars=[fp_type(p) for p in pars],
                              tol=fp_type(tol or 0.0), t_events=list(t_events), nt_events=list(nt_events),
                              fp_type=fp_type, **kw)


def reduced_integrator(state, pars, *, tol=None, t_events=(), nt_events=(), fp_type=float, **kw):
    """A Taylor integrator of the reduced 4-D system (eq:full_ham_nondim).  tol defaults to machine epsilon
    of fp_type."""
    return _integrator(reduced.system(), state, pars, tol, t_events, nt_events, fp_type, **kw)


def body_integrator(state, pars, *, tol=None, t_events=(), nt_events=(), fp_type=float, **kw):
    """A Taylor integrator of the 9-D body-frame system x' = J grad H (singularity-free)."""
    return _integrator(body.system(), state, pars, tol, t_events, nt_events, fp_type, **kw)


def euler_to_body(theta, psi, ptheta, ppsi, pars, phi=0.0) -> np.ndarray:
    """(m, n, e3) of a reduced state; phi (the cyclic twist angle) is free and defaults to 0."""
    return body_functions()["to_body"]([theta, psi, phi, ptheta, ppsi], pars)


def body_to_euler(x, pars) -> np.ndarray:
    """(theta, psi, phi, pbar_theta, pbar_psi) of a body state (x of shape (9,) or (9, N)); sin(theta) > 0."""
    return body_functions()["to_euler"](x, pars)
