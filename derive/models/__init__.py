"""The registry of rod models: one module per model, entered once (state, W or H, J, parameters with
meaning and range, source); derive/models/pipeline.py derives everything else and writes generated/models/<name>/.

The paper's rod (`magnetic-extensible`) is the default; its own pipeline (derive/model.py -> generated/) is
unchanged.  A heavy rod is not in the registry: derive/models/heavy.py shows why (gravity is not a Hamiltonian
vector field of the Lie-Poisson brackets here)."""
from __future__ import annotations

from importlib import import_module

from .spec import Model, ModelError, load_file, load_module

NAMES = ("kirchhoff", "anisotropic", "curved", "extensible", "magnetic", "magnetic-extensible")
DEFAULT = "magnetic-extensible"


def get(name: str) -> Model:
    """The registered model `name` (checked as a user file would be)."""
    if name not in NAMES:
        raise ModelError("name", f"unknown model {name!r}; registered: {', '.join(NAMES)}")
    return load_module(import_module(f".{name.replace('-', '_')}", __name__))


def all_models() -> list:
    return [get(n) for n in NAMES]


__all__ = ["NAMES", "DEFAULT", "Model", "ModelError", "get", "all_models", "load_file", "load_module"]
