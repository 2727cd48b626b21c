"""Deprecated spellings kept for one release.  Imports nothing from magrod: any module may use it."""
from __future__ import annotations


def deprecated_alias(new: str, old: str):
    """A method `old` that warns (DeprecationWarning) and calls `new`: a renamed method keeps its old name for one
    release (one serialisation verb, to_dict(), where as_dict() and summary() were spelt too)."""
    def alias(self, *args, **kw):
        import warnings

        warnings.warn(f"{type(self).__name__}.{old}() is deprecated: use {new}()", DeprecationWarning, stacklevel=2)
        return getattr(self, new)(*args, **kw)

    alias.__name__ = old
    alias.__doc__ = f"Deprecated spelling of {new}() (kept for one release)."
    return alias


def deprecated_attribute(new: str, old: str):
    """A read-only property `old` that warns (DeprecationWarning) and returns attribute `new`: a renamed field keeps
    its old name for one release (the launch distance was `eps`, the name of the perturbation parameter
    and of machine epsilon too)."""
    def getter(self):
        import warnings

        warnings.warn(f"{type(self).__name__}.{old} is deprecated: use .{new}", DeprecationWarning, stacklevel=2)
        return getattr(self, new)

    return property(getter, doc=f"Deprecated spelling of .{new} (kept for one release).")


def renamed_keywords(**old_to_new):
    """A decorator: keyword arguments spelt the old way (``params=``, ``m=``, ``panel=`` for the first argument, now
    ``system``; ``fp_type=`` now ``precision=``) keep working for one release with one DeprecationWarning naming the
    new spelling.  Both spellings at once is a TypeError, as Python gives for a repeated argument.

    >>> @renamed_keywords(params="system")
    ... def f(system=None):
    ...     return system
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     f(params=3), str(w[0].message)
    (3, 'f(params=...) is deprecated: the argument is now called system')
    """
    import functools

    def wrap(fn):
        @functools.wraps(fn)
        def inner(*args, **kw):
            import warnings

            for old, new in old_to_new.items():
                if old in kw:
                    if new in kw:
                        raise TypeError(f"{fn.__name__}() got both {old}= (deprecated) and {new}=")
                    warnings.warn(f"{fn.__name__}({old}=...) is deprecated: the argument is now called {new}",
                                  DeprecationWarning, stacklevel=2)
                    kw[new] = kw.pop(old)
            return fn(*args, **kw)

        inner.__deprecated_keywords__ = dict(old_to_new)
        return inner

    return wrap
