"""Options and number parsers shared by the subcommands.  Numbers arrive as strings and are parsed here, so
that a bad value is a ParameterError naming the option (exit 2, one line), never an argparse usage dump."""
from __future__ import annotations

import math

from ..errors import ParameterError, require_finite
from ..generated.names import PARAMS

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


def number(name: str, value) -> float:
    return require_finite(name, value)


def integer(name: str, value, minimum: int = 1) -> int:
    """An integer >= minimum; accepts integral floats written as '1e4'."""
    try:
        f = float(value)
    except (TypeError, ValueError):
        raise ParameterError(name, f"must be an integer, got {value!r}") from None
    if not math.isfinite(f) or f != int(f):
        raise ParameterError(name, f"must be an integer, got {value!r}")
    i = int(f)
    if i < minimum:
        raise ParameterError(name, f"must be >= {minimum}, got {value!r}")
    return i
