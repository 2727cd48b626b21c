"""The rod models at runtime: the registered models' generated code (generated/models/<name>/; the default model,
the paper's rod, is the paper's own tree at generated/ top level: names.py, body.py, integrals.py,
model_report.json), or a user's model
file compiled into a cache directory keyed by the evaluated model -- its SymPy expressions, so an edited helper
module that the file imports counts and an edited comment does not -- never into the package.  `resolve(path,
cache=False)` or MAGROD_NO_MODEL_CACHE=1 bypasses the cache (a fresh compile into a temporary directory).

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
NO_CACHE_ENV = "MAGROD_NO_MODEL_CACHE"


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
        self.check_regular({k: vals[k] for k in params}, vals)
        return [vals[k] for k in self.names.PARAMS]

    def check_regular(self, given: dict, values: dict) -> None:
        """ParameterError naming a parameter of `given` where the model itself is singular at `values` (every
        parameter, exact or float): a coefficient of H, J, a Casimir or a candidate divides by zero there, or a
        Casimir vanishes identically.  (The Casimirs are generated with polynomial coefficients, kappa m^2 + n^2,
        so they are defined wherever the model is.)"""
        from fractions import Fraction

        exact = {k: v if isinstance(v, Fraction) else Fraction(float(v)) for k, v in values.items()}
        bad = self._singular(exact)
        if bad is None:
            return
        culprit = next((k for k in given if self._singular({**dict(zip(self.names.PARAMS, map(
            Fraction, self.names.DEFAULTS))), k: exact[k]}) is not None), next(iter(given), self.names.PARAMS[0]))
        raise ParameterError(culprit, f"= {values[culprit]!r}: the model {self.name!r} is singular there ({bad}); "
                                      "choose another value")

    def _singular(self, exact: dict):
        args = [exact[k] for k in self.fi.PARAMETERS]
        for name in (*self.fi.POLYNOMIALS, "structure"):
            try:
                coefs = getattr(self.fi, name)(*args)
            except ZeroDivisionError:
                what = "its structure matrix J" if name == "structure" else name
                return f"a coefficient of {what} divides by zero"
            if name in self.names.CASIMIRS and not any(c != 0 for c in coefs):
                return f"its Casimir {name} vanishes identically"
        return None

    def conservation_scales(self, states, params=None):
        """(N, 1 + k) array: for each state, the sum of the absolute values of the terms of H and of each Casimir
        (CASIMIRS order) at that state.  The size a conservation error is measured against: |C - C0| <= tol * scale
        is independent of how the model normalises C (kappa m^2 + n^2 or m^2 + n^2/kappa) and stays meaningful on
        a level where C itself is 0 (m.n = 0)."""
        import numpy as np

        p = dict(zip(self.names.PARAMS, self.parameters(params)))
        x = np.abs(np.atleast_2d(np.asarray(states, dtype=float)))
        if x.shape[1] != self.dim:
            raise ParameterError("states", f"must have {self.dim} columns ({', '.join(self.names.STATE)})")
        out = np.empty((x.shape[0], 1 + len(self.names.CASIMIRS)))
        for j, name in enumerate(("H", *self.names.CASIMIRS)):
            monos = np.array(getattr(self.fi, f"{name}_MONOMIALS"), dtype=float).reshape(-1, self.dim)
            coefs = np.abs(np.array([float(c) for c in getattr(self.fi, name)(*(p[k] for k in self.fi.PARAMETERS))]))
            out[:, j] = (np.prod(x[:, None, :] ** monos[None, :, :], axis=2) * coefs[None, :]).sum(axis=1)
        return out

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
    if name == DEFAULT:  # the paper's rod: the paper's own tree at generated/ top level, generated once
        names, fi = (importlib.import_module(f"magrod.generated.{m}") for m in ("names", "integrals"))
        d = Path(names.__file__).parent
        return ModelCode(name, "registry", names, fi, json.loads((d / "model_report.json").read_text()), str(d),
                         "magrod.generated.body")
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


def content_key(model) -> str:
    """sha256 of the evaluated model (derive.models.spec.Model: the srepr of its SymPy expressions and its data),
    magrod's version and the source of the pipeline that compiles it (PIPELINE_SOURCES of magrod.derive): a model
    whose expressions changed -- in the file or in a helper module it imports -- or a changed pipeline compiles
    afresh; an edited comment does not."""
    from importlib import resources

    from .. import __version__

    h = hashlib.sha256(model.fingerprint().encode())
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


def _stamp(files) -> tuple:
    out = []
    for f in files:
        try:
            st = os.stat(f)
            out.append((str(f), st.st_mtime_ns, st.st_size))
        except OSError:
            out.append((str(f), None, None))
    return tuple(out)


_TEMP: list = []  # temporary directories of uncached compiles (removed when the process ends)


def _resolve_file(model, cache) -> ModelCode:
    path = Path(model).expanduser().resolve()
    if not path.is_file():
        raise ParameterError("model", f"no model file {str(model)[:200]!r}")
    use_cache = (not os.environ.get(NO_CACHE_ENV)) if cache is None else bool(cache)
    memo = ("file", str(path))  # -> (stamp of the file and the helper modules it imported, ModelCode)
    if use_cache and memo in _LOADED:
        stamp, mc = _LOADED[memo]
        if _stamp(s[0] for s in stamp) == stamp:
            return mc
    from ..integrability.model_files import check_file, compile_model

    checked = check_file(path)  # executes the file (and its helpers, afresh) and checks it; nothing written yet
    key = content_key(checked)
    if use_cache:
        target = cache_root() / key
    else:
        import tempfile

        tmp = tempfile.TemporaryDirectory(prefix="magrod-model-")
        _TEMP.append(tmp)
        target = Path(tmp.name) / key
    d, name = compile_model(checked, target, cached=use_cache)
    tag = key if use_cache else f"{key}_{len(_TEMP)}"
    names, fi = (_import_file(f"magrod_model_{tag}_{m}", d / f"{m}.py") for m in ("names", "first_integrals"))
    mc = ModelCode(name, str(path), names, fi, json.loads((d / "report.json").read_text()), str(d),
                   str(d / "body.py"))
    if use_cache:
        _LOADED[memo] = (_stamp([path, *checked.helpers]), mc)
    return mc


def resolve(model=None, *, cache=None) -> ModelCode:
    """The ModelCode of `model`: None (the paper's rod), a registered name, or the path of a model file.

    A model file is executed (with the helper modules it imports) at every call in a new process and whenever it
    or one of its helpers changed on disk; its compiled code is reused from the cache when the evaluated model is
    the same.  `cache=False` (or the environment variable MAGROD_NO_MODEL_CACHE=1) compiles it afresh into a
    temporary directory, the cache untouched.

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
        return _resolve_file(model, cache)
    if not isinstance(model, str) or model not in registered():
        raise ParameterError("model", f"unknown model {str(model)[:80]!r}; registered: {', '.join(registered())} "
                                      "(or the path of a model file, ./my_rod.py)")
    if model not in _LOADED:
        _LOADED[model] = _load_registered(model)
    return _LOADED[model]
