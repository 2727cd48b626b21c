"""What is being studied: one value, `System` — a rod model, its parameter values and the precision.

Every public function takes it (or what converts to it) as its first argument, named ``system``; `as_system` is the
one converter, called once at the face, so the numerics below receive a validated value and never normalise it
again.  What converts to a System:

* a ``System`` (returned as is, with keyword overrides applied);
* a paper panel key ("4a" .. "5d") or a ``Panel``: the paper's rod with that panel's parameters (the panel is returned
  beside it, for its energy level and start);
* a ``RodParams``: the paper's rod with those non-dimensional parameters;
* a registered model name ("anisotropic", ...) or the path of a model file ("./my_rod.py"): that model at its
  file's defaults;
* ``None``: the paper's rod at Fig 4(a)'s parameters.

Keyword overrides (``lam=0.15``, ``B2=3``) replace parameter values; an unknown name is a ParameterError naming it.
Parameters are validated against the model's admissible set once, here.  The paper's rod is the registry's default
model; its runtime parameters are the non-dimensional (m, mu, gamma, delta, lam) of eq:nondim_1, validated by
RodParams.

Examples
--------
>>> import magrod as mr
>>> s = mr.System("anisotropic", B1=1, B2=2, C=1.5)
>>> s.params
{'B1': 1.0, 'B2': 2.0, 'C': 1.5}
>>> s.replace(C=2).params["C"]
2.0
>>> mr.System("4a").params["lam"]
0.135
>>> mr.System("anisotropic", B1=-1)
Traceback (most recent call last):
...
magrod.core.errors.ParameterError: B1: = -1 is outside the admissible range (0.0, inf) of the model 'anisotropic'
"""
from __future__ import annotations

from dataclasses import dataclass

from . import models
from .errors import ParameterError
from .precision import Precision

PAPER_MODEL = models.DEFAULT  # the paper's rod: the registry's default model


def _paper_names() -> tuple:
    from ..generated.names import PARAMS

    return tuple(PARAMS)


@dataclass(frozen=True, init=False, repr=False, eq=True)
class System:
    """A rod model, its parameter values and the precision: what every public function studies.

    Parameters
    ----------
    model : str, pathlib.Path, RodParams, Panel or System, optional
        A registered model name (``magrod models`` lists them), the path of a model file, a paper panel key
        ("4a" .. "5d"), a ``RodParams`` (the paper's rod), or ``None`` for the paper's rod at Fig 4(a)'s parameters.
    precision : Precision or str, optional
        The floating-point precision of the runs ("double", "long double", "quad", "mp").  Default "double".
    **params : float
        Parameter values that replace the model's defaults (or the panel's values), by the model's names.

    Attributes
    ----------
    model : str
        The model's registry name, or the resolved path of its model file.
    values : tuple of float
        The parameter values, in the order of `names`.
    names : tuple of str
        The model's parameter names (its ``hy.par[i]`` order).
    precision : Precision
        The floating-point precision.

    Raises
    ------
    ParameterError
        Naming the parameter (or ``model``) that is unknown, non-finite or outside the model's admissible set.

    Examples
    --------
    >>> import magrod as mr
    >>> mr.System("kirchhoff").model
    'kirchhoff'
    >>> mr.System(mr.RodParams(m=1.7, mu=0.4, gamma=3, delta=3, lam=0.135)).is_paper
    True
    """

    model: str
    names: tuple
    values: tuple
    precision: Precision

    def __init__(self, model=None, /, *, precision=Precision.DOUBLE, **params):
        system, _ = as_system(model, precision=precision, **params)
        for f in ("model", "names", "values", "precision"):
            object.__setattr__(self, f, getattr(system, f))

    @classmethod
    def _make(cls, model: str, names: tuple, values: tuple, precision: Precision) -> "System":
        s = object.__new__(cls)
        object.__setattr__(s, "model", model)
        object.__setattr__(s, "names", tuple(names))
        object.__setattr__(s, "values", tuple(float(v) for v in values))
        object.__setattr__(s, "precision", precision)
        return s

    # ---- views ----------------------------------------------------------------------------------------------
    @property
    def params(self) -> dict:
        """{name: value} in the model's parameter order."""
        return dict(zip(self.names, self.values))

    @property
    def is_paper(self) -> bool:
        """True for the paper's rod (the registry's default model)."""
        return self.model == PAPER_MODEL

    @property
    def code(self):
        """The model's generated code (core.models.ModelCode)."""
        return models.resolve(self.model)

    @property
    def rod(self):
        """The paper's rod's non-dimensional parameters as a RodParams; a ParameterError naming the model for any
        other model (a step written for the paper's reduced chart asks for this)."""
        if not self.is_paper:
            raise ParameterError("model", f"this step needs the paper's rod ({PAPER_MODEL!r}); the model "
                                          f"{self.model!r} is not it")
        from .params import RodParams

        return RodParams(**self.params)

    def array(self):
        """The runtime parameter vector (heyoka's hy.par[i] = names[i]) as a float64 array."""
        import numpy as np

        return np.array(self.values, dtype=float)

    def replace(self, **changes) -> "System":
        """A copy with parameter values (or ``precision=``) changed, validated again."""
        precision = changes.pop("precision", self.precision)
        system, _ = as_system(self, precision=precision, **changes)
        return system

    def to_dict(self) -> dict:
        """JSON-able: {"model", "params", "precision"}."""
        return {"model": self.model, "params": self.params, "precision": str(self.precision)}

    def __repr__(self) -> str:
        vals = ", ".join(f"{k}={v:g}" for k, v in self.params.items())
        prec = "" if self.precision is Precision.DOUBLE else f", precision={str(self.precision)!r}"
        return f"System({self.model!r}, {vals}{prec})"


def _validated(model: str, values: dict) -> tuple:
    """(names, values) of `model` with `values` (over the defaults) checked against the model's admissible set."""
    if model == PAPER_MODEL:
        from .params import RodParams

        names = _paper_names()
        unknown = [k for k in values if k not in names]
        if unknown:
            raise ParameterError(str(unknown[0]), f"is not a parameter of the model {model!r} (its parameters: "
                                                  f"{', '.join(names)})")
        missing = [k for k in names if k not in values]
        if missing:
            from .printed import panel

            values = {**panel("4a").params.to_dict(), **values}
        p = RodParams(**{k: values[k] for k in names})
        return names, tuple(getattr(p, k) for k in names)
    code = models.resolve(model)
    return tuple(code.names.PARAMS), tuple(code.parameters(dict(values)))


def as_system(x=None, *, model=None, precision=None, **overrides):
    """(System, Panel or None) from anything that converts to a System (module docstring); the one place where a
    first argument becomes a System.  `model=` names the model when `x` is a dict of parameter values or None.

    Raises
    ------
    ParameterError
        Naming ``system`` for a value that is none of these, ``model`` for an unknown model, or the parameter.
    """
    from .params import RodParams
    from .printed import PANELS, Panel, panel

    prec = None if precision is None else Precision.parse(precision)
    pan = None
    if isinstance(x, System):
        if model is not None and models.resolve(model).name != models.resolve(x.model).name:
            raise ParameterError("model", f"the system is the model {x.model!r}, not {model!r}")
        name, base = x.model, x.params
        prec = prec or x.precision
    elif isinstance(x, Panel) or (isinstance(x, str) and x.lower() in PANELS):
        pan = panel(x)
        name, base = PAPER_MODEL, pan.params.to_dict()
    elif isinstance(x, RodParams):
        name, base = PAPER_MODEL, x.to_dict()
    elif isinstance(x, dict):
        name, base = (PAPER_MODEL if model is None else model), dict(x)
    elif x is None:
        name, base = (PAPER_MODEL if model is None else model), {}
    elif isinstance(x, str) or models.is_model_path(x):
        name, base = x, {}
    else:
        raise ParameterError("system", "must be a System, a model name or file, a paper panel key ('4a' .. '5d'), a "
                                       f"RodParams or a dict of parameter values, got {type(x).__name__}")
    if not isinstance(name, str) or name != PAPER_MODEL:
        code = models.resolve(name)  # ParameterError("model") for an unknown name or a bad file
        name = code.name if code.origin == "registry" else code.origin
    names, values = _validated(name, {**base, **overrides})
    if pan is not None and overrides:
        from dataclasses import replace

        tag = ", ".join(f"{k}={float(v):g}" for k, v in overrides.items())
        pan = replace(pan, key=f"{pan.key}, {tag}", params=RodParams(**dict(zip(names, values))))
    return System._make(name, names, values, prec or Precision.DOUBLE), pan
