"""Options and number parsers shared by the subcommands.  Numbers arrive as strings and are parsed here, so
that a bad value is a ParameterError naming the option (exit 2, one line), never an argparse usage dump."""
from __future__ import annotations

import math

import os

from ..core.errors import MAX_MAGNITUDE, ParameterError, require_finite
from ..core.limits import LIMITS
from ..generated.names import PARAMS

# Counts are bounded by what memory and time allow on a workstation; the messages state the limit (one table
# for the library and the command line: magrod/core/limits.py).

PARAM_HELP = {"m": "m = m3/sqrt(B C2) > 0", "mu": "mu = (2 C1 - C2^2)/C2^2", "gamma": "extensibility gamma",
              "delta": "shearability delta >= 0", "lam": "lambdabar = lambda m3/C2^2 (field strength x current)"}


def add_params(p, *, required=False, help_suffix=""):
    """--m --mu --gamma --delta --lam (PARAMS order), as strings parsed later by `params_from`."""
    g = p.add_argument_group("parameters (eq:nondim_1)")
    for name in PARAMS:
        g.add_argument(f"--{name}", type=str, default=None, required=required,
                       help=PARAM_HELP.get(name, name) + help_suffix)
    return g


def params_from(args, base: dict | None = None) -> dict:
    """{name: float} for the PARAMS given on the command line, over `base` (e.g. a paper figure's values)."""
    vals = dict(base or {})
    for name in PARAMS:
        v = getattr(args, name, None)
        if v is not None:
            vals[name] = require_finite(name, v)
    return vals


def number(name: str, value, bound: float = MAX_MAGNITUDE) -> float:
    """A finite, normal float with |x| <= bound."""
    return require_finite(name, value, bound)


def integer(name: str, value, minimum: int = 1, maximum: int | None = None) -> int:
    """An integer in [minimum, maximum] (maximum defaults to LIMITS[name]); accepts integral floats ('1e4')."""
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


def stem(name: str, value) -> str:
    """A file-name stem: one path component (no '/', no '..'), printable, at most 200 bytes (suffixes follow)."""
    v = str(value)
    if not v or v in (".", "..") or "/" in v or "\\" in v or "\x00" in v or v.startswith("."):
        raise ParameterError(name, f"must be a plain file name (no directories, not hidden), got {v[:60]!r}")
    if not v.isprintable() or len(os.fsencode(v)) > 200:
        raise ParameterError(name, "must be printable and at most 200 bytes")
    return v


def out_dir(name: str, value):
    """Validate an output directory without creating it (io.check_out_path)."""
    from ..core.io import check_out_path

    return check_out_path(value, name)
