"""Deprecated spellings of the model family's sections, exponents and maps (kept for one release).

Every model now runs through the one engine: ``mr.poincare_section(mr.System("anisotropic"))`` (a PoincareResult),
``mr.lyapunov(...)`` (a LyapunovResult), ``mr.chaos_map(...)`` (a ChaosMap).  The names below forward to it with
a DeprecationWarning; the helpers without one (`_model`, `resolve_dir`, `_cfuncs`, `project_to_level`) serve the
splitting module until it takes a System.
"""
from __future__ import annotations

import warnings

import numpy as np

from ..core import systems
from ..core.models import resolve
from .charts import magnetic_to_paper  # noqa: F401  (its older home)

_BY_DIR: dict = {}


def _warn(old: str, new: str) -> None:
    warnings.warn(f"magrod.chaos.model_chaos.{old} is deprecated: use {new}", DeprecationWarning, stacklevel=3)


def _model(model):
    mc = resolve(model)
    _BY_DIR[mc.directory] = mc
    return mc


def resolve_dir(directory: str):
    return _BY_DIR[directory]


def _system(mc, pars=None, params=None):
    from ..core.system import as_system

    values = dict(zip(mc.names.PARAMS, map(float, pars))) if pars is not None else dict(params or {})
    return as_system(mc.name if mc.origin == "registry" else mc.origin, **values)[0]


def _cfuncs(mc):
    """(level (H, C1, ...), its gradients) compiled for the model (systems.ModelBody)."""
    mb = systems.model_body(_system(mc))
    return mb.level, mb.level_gradients


def project_to_level(mc, x, g0, pars, max_steps: int = 50) -> np.ndarray:
    from .section import project_to_level as one

    return one(_system(mc, pars), x, np.asarray(g0, float), max_steps)


def model_section(model=None, *, params=None, x0=None, level_of=None, n_orbits: int = 4, iterates: int = 200,
                  seed: int = 0, tol=None, t_max=None, verify: bool = True) -> list:
    """Deprecated: ``mr.poincare_sections(mr.System(model, **params), starts=x0 or n_orbits, ...)`` (a list of
    PoincareResult, one per orbit)."""
    from .section import poincare_sections

    _warn("model_section", "magrod.poincare_sections(System, starts=...)")
    system = _system(_model(model), params=params)
    return poincare_sections(system, starts=n_orbits if x0 is None else x0, level_of=level_of, seed=seed,
                             iterates=iterates, tol=tol, t_max=t_max, verify=verify)


def model_lyapunov(model=None, *, params=None, x0=None, seed: int = 0, t_max: float = 2000.0,
                   renorm_dt: float = 1.0):
    """Deprecated: ``mr.lyapunov(mr.System(model, **params), x0=..., t_max=...)`` (a LyapunovResult)."""
    from .lyapunov import lyapunov

    _warn("model_lyapunov", "magrod.lyapunov(System, ...)")
    return lyapunov(_system(_model(model), params=params), x0=x0, t_max=t_max, renorm_dt=renorm_dt)


def model_chaos_map(model, x, y, *, t_max: float = 500.0, renorm_dt: float = 1.0, seed: int = 0, params=None):
    """Deprecated: ``mr.chaos_map(mr.System(model, **params), x, y, t_max=...)`` (a ChaosMap)."""
    from .maps import chaos_map

    _warn("model_chaos_map", "magrod.chaos_map(System, x, y, ...)")
    return chaos_map(_system(_model(model), params=params), x, y, t_max=t_max, renorm_dt=renorm_dt)
