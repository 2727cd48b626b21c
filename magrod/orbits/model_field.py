"""The body-frame field of any rod model, compiled once: what the orbit engines (equilibria, homoclinic orbits,
their continuation, the rod's shape) need of a model, whatever the model.

A model is x' = J(x) grad H(x) on its state (m, n[, e3]) with its Casimirs (generated body.py of the model: the
registry's generated/models/<name>/body.py, a model file's cached body.py, or, for the paper's rod, the top-level
generated/body.py at the numeric scale of derive/numeric_scale.py).  From those expressions heyoka's symbolic
differentiation (hy.diff) gives the Jacobian of the field, the gradients of H (the strains u = dH/dm, v = dH/dn of
the constitutive law) and of the Casimirs; nothing is differentiated by finite differences.

Everything here is keyed by the model (its directory, or "paper"), never by parameter values: one compiled object
serves every parameter value (hy.par[i] = System.names[i]).  Integrators are per thread (they are mutable).

(These builders belong in magrod.core.systems, the one integrator layer, once it builds integrators for any model:
`ModelField`, `field`, `integrator`, `frame_integrator`.)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core import systems
from ..core.errors import ParameterError

PAPER = "paper"


@dataclass(frozen=True)
class ModelField:
    """One model's compiled body-frame functions: state names, rhs (n,), jacobian (n*n, row-major), H (1,),
    casimirs (k,), casimir_gradients (k*n), H's gradient (n,)."""

    key: str
    name: str
    state: tuple
    params: tuple
    rhs: object
    jacobian: object
    H: object
    casimirs: object
    casimir_gradients: object
    grad_H: object
    casimir_names: tuple

    @property
    def dim(self) -> int:
        return len(self.state)

    @property
    def n_casimirs(self) -> int:
        return len(self.casimir_names)

    def index(self, name: str) -> int:
        return self.state.index(name)

    def has(self, *names) -> bool:
        return all(n in self.state for n in names)

    def jac(self, x, pars) -> np.ndarray:
        n = self.dim
        return np.asarray(self.jacobian(x, pars), float).reshape(n, n)

    def cas_grad(self, x, pars) -> np.ndarray:
        return np.asarray(self.casimir_gradients(x, pars), float).reshape(self.n_casimirs, self.dim)

    def level(self, x, pars) -> np.ndarray:
        """(H, C1, ...) at x."""
        return np.concatenate([np.atleast_1d(self.H(x, pars)), np.atleast_1d(self.casimirs(x, pars))])

    def level_scale(self, x, pars) -> np.ndarray:
        """The size of each of (H, C1, ...)'s terms at x: the sum of the absolute values of their monomials is not
        available from compiled code, so the scale used is 1 + |value| + |x|^2 (H and the Casimirs are quadratic
        in the state at most, plus linear terms): a drift test relative to the terms' size, never to a value that
        may be 0 (a Casimir m.n on its zero level)."""
        v = self.level(x, pars)
        return 1.0 + np.abs(v) + float(np.dot(x, x))


def _module(system):
    """(key, name, state, params, body module or None, expression builders) of the system's model."""
    if system.is_paper:
        from ..generated import body, names

        return PAPER, system.model, tuple(names.BODY_STATE), tuple(system.names), body
    code = system.code
    return code.directory, code.name, tuple(code.names.STATE), tuple(code.names.PARAMS), code.body


def field(system) -> ModelField:
    """The compiled field of the system's model (built once per model and process; `systems.clear_caches`
    forgets it like every compiled object)."""
    key, name, state, params, body = _module(system)
    _BODIES[key] = (name, state, params, body)
    return _field(key)


_BODIES: dict = {}  # key -> (name, state, params, body module): what the compiled builders below compile


@systems.cache
def _field(key) -> ModelField:
    import heyoka as hy

    name, state, params, body = _BODIES[key]
    x = hy.make_vars(*state)
    p = [hy.par[i] for i in range(len(params))]
    H = body.hamiltonian(*x, *p)
    f = body.rhs(*x, *p)
    cas = list(body.casimirs(*x, *p))
    return ModelField(
        key, name, tuple(state), tuple(params),
        rhs=systems.CFunc(f, x),
        jacobian=systems.CFunc([hy.diff(fi, xj) for fi in f for xj in x], x),
        H=systems.CFunc([H], x),
        casimirs=systems.CFunc(cas, x),
        casimir_gradients=systems.CFunc([hy.diff(c, xj) for c in cas for xj in x], x),
        grad_H=systems.CFunc([hy.diff(H, xj) for xj in x], x),
        casimir_names=tuple(f"C{i + 1}" for i in range(len(cas))))


def _exprs(key):
    import heyoka as hy

    _, state, params, body = _BODIES[key]
    x = hy.make_vars(*state)
    p = [hy.par[i] for i in range(len(params))]
    return x, p, body


@systems.per_thread
def _integrator(key):
    x, p, body = _exprs(key)
    sys_ = list(zip(x, body.rhs(*x, *p)))
    return systems.taylor(sys_, [0.0] * len(x), [1.0] * len(p))


def integrator(system):
    """A per-thread body-frame integrator of the system's model (tol = machine epsilon), reset before each use."""
    return _integrator(field(system).key)


@systems.per_thread
def _frame_integrator(key, st):
    import heyoka as hy

    x, p, body = _exprs(key)
    H = body.hamiltonian(*x, *p)
    u = [hy.diff(H, x[i]) for i in st[:3]]
    v = [hy.diff(H, x[i]) for i in st[3:]]
    D = hy.make_vars(*[f"D{i}{j}" for i in range(3) for j in range(3)])
    r = hy.make_vars("r1", "r2", "r3")
    hat = [[None, -u[2], u[1]], [u[2], None, -u[0]], [-u[1], u[0], None]]
    sys_ = list(zip(x, body.rhs(*x, *p)))
    # D = [d1 d2 d3] (columns: the directors in space components): d_i' = u x d_i is D' = D hat(u)
    for i in range(3):
        for j in range(3):
            sys_.append((D[3 * i + j], hy.sum([D[3 * i + k] * hat[k][j] for k in range(3) if hat[k][j] is not None])))
    # r' = sum_i v_i d_i = D v
    for i in range(3):
        sys_.append((r[i], hy.sum([D[3 * i + k] * v[k] for k in range(3)])))
    return systems.taylor(sys_, [0.0] * len(sys_), [1.0] * len(p))


def frame_integrator(system):
    """A per-thread integrator of the body state, the director frame D' = D hat(u) and the centreline r' = D v,
    u = dH/dm, v = dH/dn (hy.diff of the model's H): len(state) + 12 equations."""
    st = _strain_indices(system)
    return _frame_integrator(field(system).key, st)


M_NAMES = ("m1", "m2", "m3")
N_NAMES = ("n1", "n2", "n3")


def _strain_indices(system) -> tuple:
    """Indices of (m1, m2, m3, n1, n2, n3) in the model's state; ParameterError naming the model without them."""
    state = _module(system)[2]
    missing = [k for k in M_NAMES + N_NAMES if k not in state]
    if missing:
        raise ParameterError("model", f"the rod's shape needs the moments m and forces n in the body frame, and the "
                                      f"model {system.model!r} has none named {', '.join(missing)} (its state: "
                                      f"{', '.join(state)})")
    return tuple(state.index(k) for k in M_NAMES + N_NAMES)


def strain_indices(system) -> tuple:
    return _strain_indices(system)
