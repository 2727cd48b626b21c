"""The common face of magrod's result objects: scipy's `success`/`message`, a short `repr`, `to_dict()` (JSON-able),
`.plot(ax=None)` (drawn by the figures wing, never switching matplotlib's backend) and the accuracy achieved.

A result class is a dataclass that inherits `Result` and lists the few fields its repr shows in `_repr_fields`.
"""
from __future__ import annotations

import dataclasses
import math
from enum import Enum

REPR_LIMIT = 1000  # characters: a repr is a summary, never a data dump


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


def jsonable(o):
    """A JSON-able copy: numpy arrays and scalars to Python, non-finite floats to None, complex to [re, im],
    enums to their value, dataclasses and Results to dicts."""
    import numpy as np

    if isinstance(o, Result):
        return o.to_dict()
    if isinstance(o, Enum):
        return o.value
    if dataclasses.is_dataclass(o) and not isinstance(o, type):
        return {f.name: jsonable(getattr(o, f.name)) for f in dataclasses.fields(o)}
    if isinstance(o, dict):
        return {str(k): jsonable(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [jsonable(v) for v in o]
    if isinstance(o, np.ndarray):
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
        """Every field as JSON-able data (arrays as nested lists)."""
        return {f.name: jsonable(getattr(self, f.name)) for f in dataclasses.fields(self)}

    def plot(self, ax=None, **kw):
        """Draw the result on a matplotlib Axes (a new figure's if ax is None) and return the Axes.  The backend is
        never switched: in Jupyter the figure shows inline."""
        from ..figures import plots

        return plots.plot(self, ax=ax, **kw)
