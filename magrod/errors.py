"""User-facing errors: the CLI prints one line naming the parameter and exits with code 2."""


class ParameterError(ValueError):
    """An input that is out of range, non-finite or inconsistent.  `name` is the offending parameter."""

    def __init__(self, name: str, message: str):
        self.name = name
        self.message = message
        super().__init__(f"{name}: {message}")

    def __reduce__(self):  # picklable, so worker processes can report it
        return (ParameterError, (self.name, self.message))


def require_finite(name: str, value) -> float:
    import math

    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, f"must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise ParameterError(name, f"must be finite, got {value!r}")
    return v


def require_positive_int(name: str, value) -> int:
    try:
        v = int(value)
    except (TypeError, ValueError):
        raise ParameterError(name, f"must be an integer, got {value!r}") from None
    if v <= 0 or v != value:
        raise ParameterError(name, f"must be a positive integer, got {value!r}")
    return v
