"""The body-frame field of any rod model as the orbit engines (equilibria, homoclinic orbits, their continuation, the
rod's shape) use it: a view of the one integrator layer's compiled model (magrod.core.systems.ModelBody), which
builds every function and integrator once per model from its generated expressions.

A model is x' = J(x) grad H(x) on its state (m, n[, e3]) with its Casimirs (generated body.py of the model: the
registry's generated/models/<name>/body.py, a model file's cached body.py, or, for the paper's rod, the top-level
generated/body.py at the numeric scale of derive/numeric_scale.py, whose H is Hbar = H - offset as everywhere in
the engine).  heyoka's symbolic differentiation (hy.diff) gives the Jacobian of the field, the gradients of H (the
strains u = dH/dm, v = dH/dn of the constitutive law) and of the Casimirs; nothing is differentiated by finite
differences.  Everything is keyed by the model, never by parameter values (hy.par[i] = System.names[i]);
integrators are per thread (they are mutable).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core import systems
from ..core.errors import MissingStructure


@dataclass(frozen=True, eq=False)
class ModelField:
    """One model's compiled body-frame functions (a view of core.systems.ModelBody): state names, `rhs(x, pars)`
    (n,), `jacobian` (n*n, row-major), `H` (1,), `casimirs` (k,), `casimir_gradients` (k*n), `grad_H` (n,); each
    evaluated on (n,) or (n, N) states."""

    body: systems.ModelBody

    @property
    def key(self) -> str:
        return self.body.key

    @property
    def name(self) -> str:
        return self.body.name

    @property
    def state(self) -> tuple:
        return self.body.state

    @property
    def params(self) -> tuple:
        return self.body.params

    @property
    def casimir_names(self) -> tuple:
        return self.body.casimir_names

    @property
    def dim(self) -> int:
        return self.body.dim

    @property
    def n_casimirs(self) -> int:
        return self.body.n_casimirs

    @property
    def rhs(self):
        return self.body.rhs

    @property
    def jacobian(self):
        return self.body.jacobian

    def H(self, x, pars) -> np.ndarray:
        return np.asarray(self.body.level(x, pars))[:1]

    def casimirs(self, x, pars) -> np.ndarray:
        return np.asarray(self.body.level(x, pars))[1:]

    def grad_H(self, x, pars) -> np.ndarray:
        return np.asarray(self.body.level_gradients(x, pars))[:self.dim]

    def casimir_gradients(self, x, pars) -> np.ndarray:
        return np.asarray(self.body.level_gradients(x, pars))[self.dim:]

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
        return np.asarray(self.body.level(x, pars), float)

    def level_scale(self, x, pars) -> np.ndarray:
        """The size of each of (H, C1, ...) at x for the orbits' drift tests: 1 + |value| + |x|^2 (H and the
        Casimirs are quadratic in the state at most, plus linear terms): relative to the terms' size, never to a
        value that may be 0 (a Casimir m.n on its zero level)."""
        v = self.level(x, pars)
        return 1.0 + np.abs(v) + float(np.dot(x, x))


def field(system) -> ModelField:
    """The compiled field of the system's model (core.systems.model_body: built once per model and process;
    `systems.clear_caches` forgets its compiled functions like every compiled object)."""
    return ModelField(systems.model_body(system))


def integrator(system):
    """A per-thread body-frame integrator of the system's model (core.systems.model_integrator, tol = machine
    epsilon), reset before each use."""
    return systems.model_integrator(system)


def frame_integrator(system):
    """A per-thread integrator of the body state, the director frame D' = D hat(u) and the centreline r' = D v,
    u = dH/dm, v = dH/dn (core.systems.model_frame_integrator): len(state) + 12 equations."""
    return systems.model_frame_integrator(system, strain_indices(system))


M_NAMES = ("m1", "m2", "m3")
N_NAMES = ("n1", "n2", "n3")


def strain_indices(system) -> tuple:
    """Indices of (m1, m2, m3, n1, n2, n3) in the model's state; MissingStructure naming the model without them."""
    state = systems.model_body(system).state
    missing = [k for k in M_NAMES + N_NAMES if k not in state]
    if missing:
        raise MissingStructure(system.model, "the body moments m and forces n",
                               f"the rod's shape needs the moments m and forces n in the body frame, and the model "
                               f"{system.model!r} has none named {', '.join(missing)} (its state: {', '.join(state)})")
    return tuple(state.index(k) for k in M_NAMES + N_NAMES)
