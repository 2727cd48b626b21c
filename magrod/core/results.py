"""The common face of magrod's result objects: scipy's `success`/`message`, a short `repr`, `to_dict()` (JSON-able),
`.plot(ax=None)` (drawn by the figures wing, never switching matplotlib's backend) and the accuracy achieved.

A result class is a dataclass that inherits `Result` and lists the few fields its repr shows in `_repr_fields`.
"""
from __future__ import annotations

import dataclasses
import math
from enum import Enum

from .deprecation import deprecated_alias  # noqa: F401  (re-exported: results use it)

REPR_LIMIT = 1000  # characters: a repr is a summary, never a data dump
# to_dict() stays small: an array of more elements than this is written as a reference {"npz": key, "shape",
# "dtype"} to the key of `arrays()` (what `save()` writes to <stem>.npz, as magrod poincare --out does)
INLINE_ARRAY_MAX = 64


def _short(v) -> str:
    import numpy as np

    if isinstance(v, Enum):
        return repr(v.value)
    if isinstance(v, np.ndarray):
        return f"<array {'x'.join(map(str, v.shape)) or 'scalar'} {v.dtype}>"
    if isinstance(v, (float, np.floating)):
        return f"{float(v):.6g}"
    if isinstance(v, (list, tuple)) and len(v) > 4:
        return f"<{type(v).__name__} of {len(v)}>"
    if isinstance(v, dict) and len(repr(v)) > 120:
        return f"<dict of {len(v)}>"
    if isinstance(v, str) and len(v) > 100:
        return repr(v[:97] + "...")
    if dataclasses.is_dataclass(v) and not isinstance(v, type):
        inner = ", ".join(f"{f.name}={_short(getattr(v, f.name))}" for f in dataclasses.fields(v)
                          if f.repr)
        return f"{type(v).__name__}({inner})" if len(inner) < 160 else f"<{type(v).__name__}>"
    return repr(v)


def jsonable(o, inline: int | None = None, _key: str = ""):
    """A JSON-able copy: numpy arrays and scalars to Python, non-finite floats to None, complex to [re, im],
    enums to their value, dataclasses and Results to dicts.  With `inline`, an array of more than `inline`
    elements becomes {"npz": key, "shape": [...], "dtype": ...}, key its dotted path (see Result.arrays)."""
    import numpy as np

    def sub(v, k):
        return jsonable(v, inline, f"{_key}.{k}" if _key else str(k))

    if isinstance(o, Result):
        return o.to_dict()
    if type(o).__name__ == "System" and hasattr(o, "to_dict"):  # core.system.System: {"model", "params", "precision"}
        return o.to_dict()
    if isinstance(o, Enum):
        return o.value
    if dataclasses.is_dataclass(o) and not isinstance(o, type):
        return {f.name: sub(getattr(o, f.name), f.name) for f in dataclasses.fields(o)}
    if isinstance(o, dict):
        return {str(k): sub(v, k) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [sub(v, i) for i, v in enumerate(o)]
    if isinstance(o, np.ndarray):
        if inline is not None and o.size > inline:
            return {"npz": _key, "shape": list(o.shape), "dtype": str(o.dtype)}
        return jsonable(o.tolist())
    if isinstance(o, (complex, np.complexfloating)):
        return [jsonable(float(o.real)), jsonable(float(o.imag))]
    if isinstance(o, (np.floating, float)):
        f = float(o)
        return f if math.isfinite(f) else None
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, (np.bool_,)):
        return bool(o)
    if isinstance(o, (str, int, bool)) or o is None:
        return o
    return str(o)


def array_refs(arrays: dict) -> dict:
    """{key: array} -> {key: the array as a list if small, else {"npz": key, "shape", "dtype"}} (for to_dict()
    of results whose arrays() are their own per-point arrays)."""
    return {k: jsonable(v, INLINE_ARRAY_MAX, k) for k, v in arrays.items()}


def _collect_arrays(o, key: str = "", out: dict | None = None) -> dict:
    """Every numpy array of more than INLINE_ARRAY_MAX elements inside o, by the dotted key jsonable gives it."""
    import numpy as np

    out = {} if out is None else out
    if isinstance(o, Result):
        return out
    if isinstance(o, np.ndarray):
        if o.size > INLINE_ARRAY_MAX:
            out[key] = o
    elif dataclasses.is_dataclass(o) and not isinstance(o, type):
        for f in dataclasses.fields(o):
            _collect_arrays(getattr(o, f.name), f"{key}.{f.name}" if key else f.name, out)
    elif isinstance(o, dict):
        for k, v in o.items():
            _collect_arrays(v, f"{key}.{k}" if key else str(k), out)
    elif isinstance(o, (list, tuple)):
        for i, v in enumerate(o):
            _collect_arrays(v, f"{key}.{i}" if key else str(i), out)
    return out


class Result:
    """Mixin for result dataclasses (fields `success: bool` and `message: str` required)."""

    _repr_fields: tuple = ()

    def __repr__(self) -> str:
        parts = [f"success={self.success!r}", f"message={_short(self.message)}"]
        for name in self._repr_fields:
            v = getattr(self, name)
            parts.append(f"{name}={_short(v() if callable(v) else v)}")
        text = f"{type(self).__name__}({', '.join(parts)})"
        return text if len(text) <= REPR_LIMIT else text[: REPR_LIMIT - 4] + "...)"

    def __str__(self) -> str:
        return repr(self)

    def _get_status(self):
        return self.__dict__.get("_status", 0 if self.success else 1)

    def _set_status(self, value):  # a result class with a `status` field of its own stores it here
        self.__dict__["_status"] = value

    status = property(_get_status, _set_status, doc="scipy's termination code next to `success` and `message`: 0 "
                      "success, 1 failure (a result class with finer codes, or a `status` field, overrides it).")

    def to_dict(self) -> dict:
        """Every field as JSON-able data, small: arrays of up to INLINE_ARRAY_MAX elements as lists, larger ones
        as references {"npz": key, "shape", "dtype"} into `arrays()` (`save()` writes both)."""
        return {f.name: jsonable(getattr(self, f.name), INLINE_ARRAY_MAX, f.name) for f in dataclasses.fields(self)}

    def arrays(self) -> dict:
        """The arrays that to_dict() refers to, by key (dotted paths into the fields: "x", "extra.r")."""
        return _collect_arrays({f.name: getattr(self, f.name) for f in dataclasses.fields(self)})

    def save(self, stem) -> list:
        """Write <stem>.json (to_dict()) and <stem>.npz (arrays()) atomically; returns the two paths."""
        from pathlib import Path

        import numpy as np

        from .io import atomic_savez, atomic_write_json

        stem = Path(stem)
        arrays = {k: np.asarray(v) for k, v in self.arrays().items()}
        npz = atomic_savez(stem.with_suffix(".npz"), **arrays)
        side = atomic_write_json(stem.with_suffix(".json"), {**self.to_dict(), "arrays_file": npz.name})
        return [str(side), str(npz)]

    def to_xarray(self):
        """The arrays as an xarray.Dataset: one variable per array of `arrays()` (dims named `<key>_<axis>`, or
        the class's `_xarray_dims`), CF attributes from `_cf` ({key: (units, long_name)}), and the JSON of
        to_dict() as the attribute "summary"."""
        import json

        import numpy as np
        import xarray as xr

        dims = getattr(self, "_xarray_dims", {})
        cf = getattr(self, "_cf", {})
        data = {}
        for k, v in self.arrays().items():
            a = np.asarray(v)
            name = k.replace(".", "_")
            d = dims.get(k) or tuple(f"{name}_{i}" for i in range(a.ndim))
            attrs = {"units": cf[k][0], "long_name": cf[k][1]} if k in cf else {}
            data[name] = (d, a, attrs)
        return xr.Dataset(data, attrs={"title": f"magrod {type(self).__name__}",
                                       "summary": json.dumps(self.to_dict(), sort_keys=True)})

    def plot(self, ax=None, **kw):
        """Draw the result on a matplotlib Axes (a new figure's if ax is None) and return the Axes.  The backend is
        never switched: in Jupyter the figure shows inline."""
        from ..figures import plots

        return plots.plot(self, ax=ax, **kw)
