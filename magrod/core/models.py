"""The rod models at runtime (issue 26): the registered models' generated code (generated/models/<name>/), or a
user's model file compiled into a cache directory keyed by its content hash (never into the package).

`resolve(model)` takes None (the paper's rod, `magnetic-extensible`), a registered name, or a path to a model
file (a string ending in .py or a pathlib.Path; docs/models.md).  A model file is code that the user runs on
purpose, like a setup.py: it is executed only when its path is passed here, never found or loaded implicitly.

The returned ModelCode gives the model's names (state, parameters with meanings, ranges and defaults, the
Casimirs found, the candidates), its body-frame heyoka expressions and the exact data of the first-integral
search.  No SymPy here: compiling a user file goes through magrod.integrability.model_files (which needs the
`derive` extra).
"""
from __future__ import annotations

import hashlib
import importlib
import importlib.util
import json
import math
import os
import sys
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType

from .errors import ParameterError

DEFAULT = "magnetic-extensible"
CACHE_ENV = "MAGROD_MODEL_CACHE"


def registered() -> tuple:
    """Names of the registered models (generated/models/__init__.py)."""
    from ..generated import models

    return tuple(models.MODELS)


@dataclass(frozen=True)
class ModelCode:
    """One model's generated code: names, body (heyoka expressions), fi (exact search data), report (dict)."""

    name: str
    origin: str  # "registry" or the model file's path
    names: ModuleType
    fi: ModuleType
    report: dict
    directory: str
    body_module: str  # imported on first use of .body (it imports heyoka: `magrod check --model` never does)

    @property
    def body(self) -> ModuleType:
        """The body-frame heyoka expressions (generated body.py), imported on first use."""
        if self.body_module.endswith(".py"):
            return _import_file(f"magrod_model_{Path(self.directory).name}_body", Path(self.body_module))
        return importlib.import_module(self.body_module)

    @property
    def dim(self) -> int:
        return len(self.names.STATE)

    def parameters(self, params=None) -> list:
        """The runtime parameter vector (PARAMS order) from a dict {name: value} over the defaults; ParameterError
        naming the field for an unknown name, a non-finite value or one outside the model's open range."""
        vals = dict(zip(self.names.PARAMS, self.names.DEFAULTS))
        if params is None:
            params = {}
        if not isinstance(params, dict):
            raise ParameterError("params", f"must be a dict {{name: value}} over {', '.join(self.names.PARAMS)}")
        for k, v in params.items():
            if k not in vals:
                raise ParameterError(str(k), f"is not a parameter of the model {self.name!r} (its parameters: "
                                             f"{', '.join(self.names.PARAMS)})")
            try:
                f = float(v)
            except (TypeError, ValueError):
                raise ParameterError(k, f"must be a number, got {v!r}") from None
            lo, hi = self.names.RANGES[self.names.PARAMS.index(k)]
            lo, hi = float(lo), float(hi)
            if not math.isfinite(f) or not lo < f < hi:
                raise ParameterError(k, f"= {v!r} is outside the admissible range ({lo}, {hi}) of the model "
                                        f"{self.name!r}")
            vals[k] = f
        return [vals[k] for k in self.names.PARAMS]

    def require_s1(self, step: str) -> None:
        """A step that needs the S^1 symmetry about d3 (the Euler-angle chart of sec. 4): a clear error naming the
        model and the reason if it lacks it, and if it has it but the chart is generated only for the paper's rod."""
        if not self.names.S1_SYMMETRIC:
            raise ParameterError("model", f"{step} needs the S^1 symmetry about d3 (the Euler-angle chart), and the "
                                          f"model {self.name!r} does not have it: its H is not invariant under "
                                          "rotations of the body frame about d3 (report entry s1_symmetry)")
        if self.name != DEFAULT:
            raise ParameterError("model", f"{step}: the model {self.name!r} has the S^1 symmetry, but "
                                          + CHART_NOTES.get(self.name, "the Euler-angle reduction is generated only "
                                                            f"for the paper's rod ({DEFAULT!r})") + "; use the body frame")


# Why the S^1-symmetric models other than the paper's have no chart of their own here
CHART_NOTES = {
    "kirchhoff": "the chart about the force direction makes both Euler angles psi, phi cyclic (p_psi = m.n/|n|, "
                 "p_phi = m3): one degree of freedom in (theta, p_theta), integrable by quadrature, no section to "
                 "draw",
    "extensible": "the chart about the force direction makes both Euler angles psi, phi cyclic (p_psi = m.n/|n|, "
                  "p_phi = m3): one degree of freedom in (theta, p_theta), integrable by quadrature, no section to "
                  "draw",
    "magnetic": "its chart is the paper's reduced system at zero extensibility and shear (poincare_section(model="
                "'magnetic', formulation='reduced') runs it; magrod.chaos.model_chaos.magnetic_to_paper)",
}

_LOADED: dict = {}


def _load_registered(name: str) -> ModelCode:
    ident = name.replace("-", "_")
    pkg = f"magrod.generated.models.{ident}"
    names, fi = (importlib.import_module(f"{pkg}.{m}") for m in ("names", "first_integrals"))
    d = Path(names.__file__).parent
    return ModelCode(name, "registry", names, fi, json.loads((d / "report.json").read_text()), str(d), f"{pkg}.body")


def _import_file(modname: str, path: Path) -> ModuleType:
    if modname in sys.modules:
        return sys.modules[modname]
    spec = importlib.util.spec_from_file_location(modname, path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    sys.modules[modname] = mod
    return mod


def cache_root() -> Path:
    """$MAGROD_MODEL_CACHE, else $XDG_CACHE_HOME/magrod/models, else ~/.cache/magrod/models."""
    if os.environ.get(CACHE_ENV):
        return Path(os.environ[CACHE_ENV])
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / "magrod" / "models"


PIPELINE_SOURCES = ("models/pipeline.py", "models/spec.py", "codegen.py", "first_integrals.py", "results.py")


def content_key(path: Path) -> str:
    """sha256 of the file's bytes, magrod's version and the source of the pipeline that compiles it
    (PIPELINE_SOURCES of magrod.derive): a changed file, or a changed pipeline, compiles afresh."""
    from importlib import resources

    from .. import __version__

    h = hashlib.sha256(path.read_bytes())
    h.update(b"\0magrod " + __version__.encode())
    root = resources.files("magrod.derive")
    for rel in PIPELINE_SOURCES:
        try:
            h.update(b"\0" + root.joinpath(rel).read_bytes())
        except (FileNotFoundError, OSError):  # an installation without derive/: keyed by the version alone
            h.update(b"\0-")
    return h.hexdigest()[:24]


def is_model_path(model) -> bool:
    return isinstance(model, Path) or (isinstance(model, str) and (model.endswith(".py") or os.sep in model))


def resolve(model=None) -> ModelCode:
    """The ModelCode of `model`: None (the paper's rod), a registered name, or the path of a model file.

    Raises
    ------
    ParameterError
        Naming `model` for an unknown name, a missing file or a model file that fails a check (the check named).
    """
    if model is None:
        model = DEFAULT
    if isinstance(model, ModelCode):
        return model
    if is_model_path(model):
        path = Path(model).expanduser().resolve()
        if not path.is_file():
            raise ParameterError("model", f"no model file {str(model)[:200]!r}")
        key = content_key(path)
        if key in _LOADED:
            return _LOADED[key]
        from ..integrability.model_files import compile_file

        d, name = compile_file(path, cache_root() / key)
        names, fi = (_import_file(f"magrod_model_{key}_{m}", d / f"{m}.py") for m in ("names", "first_integrals"))
        mc = ModelCode(name, str(path), names, fi, json.loads((d / "report.json").read_text()), str(d),
                       str(d / "body.py"))
        _LOADED[key] = mc
        return mc
    if not isinstance(model, str) or model not in registered():
        raise ParameterError("model", f"unknown model {str(model)[:80]!r}; registered: {', '.join(registered())} "
                                      "(or the path of a model file, ./my_rod.py)")
    if model not in _LOADED:
        _LOADED[model] = _load_registered(model)
    return _LOADED[model]
