"""Deprecated spellings kept for one release (issue 25).  Imports nothing from magrod: any module may use it."""
from __future__ import annotations


def deprecated_alias(new: str, old: str):
    """A method `old` that warns (DeprecationWarning) and calls `new`: a renamed method keeps its old name for one
    release (issue 25: one serialisation verb, to_dict(), where as_dict() and summary() were spelt too)."""
    def alias(self, *args, **kw):
        import warnings

        warnings.warn(f"{type(self).__name__}.{old}() is deprecated: use {new}()", DeprecationWarning, stacklevel=2)
        return getattr(self, new)(*args, **kw)

    alias.__name__ = old
    alias.__doc__ = f"Deprecated spelling of {new}() (kept for one release)."
    return alias


def deprecated_attribute(new: str, old: str):
    """A read-only property `old` that warns (DeprecationWarning) and returns attribute `new`: a renamed field keeps
    its old name for one release (issue 25: the launch distance was `eps`, the name of the perturbation parameter
    and of machine epsilon too)."""
    def getter(self):
        import warnings

        warnings.warn(f"{type(self).__name__}.{old} is deprecated: use .{new}", DeprecationWarning, stacklevel=2)
        return getattr(self, new)

    return property(getter, doc=f"Deprecated spelling of .{new} (kept for one release).")
