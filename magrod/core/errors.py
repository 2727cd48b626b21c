"""User-facing errors: the CLI prints one line naming the parameter and exits with code 2."""


class ParameterError(ValueError):
    """An input that is out of range, non-finite or inconsistent.  `name` is the offending parameter, `message`
    the violated condition; the CLI prints them as its one error line (exit 2).

    Parameters
    ----------
    name : str
        The offending parameter, as the caller spelled it (a keyword, a field, a command-line option's name).
    message : str
        The violated condition, with the value given.

    Attributes
    ----------
    name : str
        As given.
    message : str
        As given; ``str(exc)`` is ``"name: message"``.

    Examples
    --------
    >>> import magrod as mr
    >>> try:
    ...     mr.panel("9z")
    ... except mr.ParameterError as exc:
    ...     print(exc.name)
    panel
    """

    def __init__(self, name: str, message: str):
        self.name = name
        self.message = message
        super().__init__(f"{name}: {message}")

    def __reduce__(self):  # picklable, so worker processes can report it
        return (ParameterError, (self.name, self.message))


class MissingStructure(ParameterError):
    """A step needs a structure of the model (a reversor, a saddle, a small parameter, the body moments and forces
    m and n ...) that the model lacks.  `name` is "model" (the offending input), `structure` names what is missing,
    `model` the model; the message says both.

    Examples
    --------
    >>> import magrod as mr
    >>> try:
    ...     mr.splitting("kirchhoff")
    ... except mr.ParameterError as exc:
    ...     print(exc.name, "|", exc.structure)
    model | a small parameter
    """

    def __init__(self, model: str, structure: str, message: str):
        self.model = model
        self.structure = structure
        super().__init__("model", message)

    def __reduce__(self):
        return (MissingStructure, (self.model, self.structure, self.message))


class EnvironmentFault(RuntimeError):
    """The machine, not the input, stopped the run (disk full, unwritable path, locked output, JIT cache).
    `name` is the parameter whose path is involved (e.g. "out"), or None."""

    def __init__(self, name, message: str):
        self.name = name
        self.message = message
        super().__init__(message)

    def __reduce__(self):
        return (EnvironmentFault, (self.name, self.message))


class MagrodWarning(UserWarning):
    """Something the user should know that did not stop the run (e.g. the JIT cache was switched off)."""


# Inputs beyond these magnitudes are refused up front: the model's terms go up to m^4 and 1/m^4, and a float64
# integration of them with such parameters would overflow or lose every digit long before producing a NaN.
MAX_MAGNITUDE = 1e6


def require_finite(name: str, value, bound: float | None = None) -> float:
    """A finite float; subnormal numbers (|x| < 2.2e-308, x != 0) are refused, and |x| <= bound if given."""
    import math
    import sys

    if type(value).__name__ in ("bool", "bool_"):  # True is 1.0 to float(): a flag where a number belongs is a bug
        raise ParameterError(name, f"must be a number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(name, f"must be a number, got {str(value)[:40]!r}") from None
    if not math.isfinite(v):
        raise ParameterError(name, f"must be finite, got {str(value)[:40]!r}")
    if v != 0.0 and abs(v) < sys.float_info.min:
        raise ParameterError(name, f"{value!r} is below the float64 normal range (|x| >= {sys.float_info.min:.3g})")
    if bound is not None and abs(v) > bound:
        raise ParameterError(name, f"must satisfy |{name}| <= {bound:g}, got {value!r}")
    return v


def require_positive_int(name: str, value) -> int:
    try:
        v = int(value)
    except (TypeError, ValueError):
        raise ParameterError(name, f"must be an integer, got {value!r}") from None
    if v <= 0 or v != value:
        raise ParameterError(name, f"must be a positive integer, got {value!r}")
    return v
