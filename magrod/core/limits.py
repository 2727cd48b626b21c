"""The largest requests magrod takes, defined once: the public functions and the command line refuse the same
values with the same words (issue 25: `poincare_section(iterates=10**9)` just ran while the CLI refused it)."""
from __future__ import annotations

LIMITS = {
    "iterates": 2_000_000,   # Poincare points: ~200 bytes and ~0.2 ms each -> 400 MB, ~7 min
    "n": 20_001,             # homoclinic comparison grid (multiprecision, ~1 ms per point)
    "max_pulses": 12,        # N-pulse search: the branch is integrated past N near-saddle passages
    "samples": 2_001,        # multipulse scan: one unstable-branch integration per sample
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
