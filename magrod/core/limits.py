"""The largest requests magrod takes, defined once: the public functions, the functions behind them and the command
line refuse the same values with the same words (`integer` for counts, `positive` for lengths and intervals of
time), whatever the path that reaches them."""
from __future__ import annotations

LIMITS = {
    "iterates": 2_000_000,   # Poincare points: ~200 bytes and ~0.2 ms each -> 400 MB, ~7 min
    "n": 20_001,             # homoclinic comparison grid (multiprecision, ~1 ms per point)
    "max_pulses": 12,        # N-pulse search: the branch is integrated past N near-saddle passages
    "samples": 2_001,        # multipulse scan: one unstable-branch integration per sample (at least 3: a sign
                             # change of the scanned function needs two neighbours of a sample)
    "points": 1_000_000,     # rod samples
    "workers": 64,           # worker processes or threads of one command
}


def integer(name: str, value, minimum: int = 1, maximum: int | None = None) -> int:
    """An integer in [minimum, maximum] (maximum defaults to LIMITS[name]); accepts integral floats and their
    strings ('1e4').  The one count parser of the command line and the explorer; ParameterError(name)."""
    import math

    from .errors import ParameterError

    try:
        f = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(name, f"must be an integer, got {str(value)[:40]!r}") from None
    if not math.isfinite(f) or f != int(f):
        raise ParameterError(name, f"must be an integer, got {str(value)[:40]!r}")
    i = int(f)
    if i < minimum:
        raise ParameterError(name, f"must be >= {minimum}, got {value!r}")
    maximum = LIMITS.get(name) if maximum is None else maximum
    if maximum is not None and i > maximum:
        raise ParameterError(name, f"must be <= {maximum} (the limit of what this command can finish), got {value!r}")
    return i


def count(name: str, value, minimum: int = 1, maximum: int | None = None) -> int:
    """`integer` for the library: a number, never a string (a string is the command line's, parsed there);
    the same limits and words.  ParameterError(name)."""
    from .errors import ParameterError

    if isinstance(value, (str, bytes, bool)):
        raise ParameterError(name, f"must be an integer, got {str(value)[:40]!r}")
    return integer(name, value, minimum, maximum)


def positive(name: str, value, maximum: float | None = None) -> float:
    """A finite number in (0, maximum] (maximum defaults to LIMITS[name], if any): an integration time t_max, a
    renormalisation interval renorm_dt.  The one check of such a value, by the library's functions and the ones
    behind them; ParameterError(name)."""
    import math

    from .errors import ParameterError

    try:
        f = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(name, f"must be a number, got {str(value)[:40]!r}") from None
    if not math.isfinite(f) or f <= 0:
        raise ParameterError(name, f"must be a finite number > 0, got {value!r}")
    maximum = LIMITS.get(name) if maximum is None else maximum
    if maximum is not None and f > maximum:
        raise ParameterError(name, f"must be <= {maximum:g} (the limit of what this command can finish), got {value!r}")
    return f
