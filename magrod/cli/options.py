"""Options and number parsers shared by the subcommands.  Numbers arrive as strings and are parsed here, so
that a bad value is a ParameterError naming the option (exit 2, one line), never an argparse usage dump."""
from __future__ import annotations

import argparse
import sys

from ..core.errors import MAX_MAGNITUDE, require_finite
from ..core.limits import LIMITS, integer  # noqa: F401  (integer: the count parser, defined with the limits)
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


def stem(name: str, value) -> str:
    """A file-name stem (core.io.check_stem: one path component, printable, at most 200 bytes)."""
    from ..core.io import check_stem

    return check_stem(value, name)


def out_dir(name: str, value):
    """Validate an output directory without creating it (io.check_out_path)."""
    from ..core.io import check_out_path

    return check_out_path(value, name)


FORMAT_HELP = ("picture format(s) of the figures: png, pdf or svg, or several separated by commas (pdf,svg); "
               "the .npz data and .json sidecars are the same whatever the format")


def add_format(p):
    """--format png|pdf|svg[,...] (magrod figure, magrod reproduce), parsed by `formats_from`."""
    p.add_argument("--format", default="png", metavar="FMT[,FMT]", help=FORMAT_HELP)


def formats_from(args) -> tuple:
    """The --format value as a tuple of picture formats (ParameterError naming 'format')."""
    from ..figures.common import parse_formats

    return parse_formats(getattr(args, "format", "png"))


# ---- one vocabulary: one option name per concept in every command (issue 29) ---------------------------------
# the level and the start of an orbit, wherever a command takes them
START_HELP = {"h": "the level Hbar = h of the orbit",
              "theta0": "start theta0 in (0, pi), exact: the decimal you type is the double used",
              "ptheta0": "start pbar_theta0, exact as typed",
              "psi0": "start psi0 (0 if not given)"}
ROOT_HELP = "which root pbar_psi of Hbar = h at the start: smallest or largest"
ROOT_INDEX_HELP = (ROOT_HELP + ", or an integer index into the ascending roots (0 = smallest, -1 = largest; "
                   "a single orbit only)")
# the chaos indicators by their one spelling (magrod.chaos.fields MAPPABLE short names), and the old ones
INDICATORS = {"growth": "growth_exponent", "fli": "fli", "lyap": "lyap"}


def warn_deprecated(old: str, new: str) -> None:
    """One line on stderr for an old spelling that still works (the CLI's own output: never a traceback)."""
    print(f"magrod: warning: {old} is deprecated, use {new}", file=sys.stderr)


class _Deprecated(argparse.Action):
    """The old name of an option: stores into the new option's dest, refuses being given with it (or twice), and
    prints one deprecation line.  Hidden from --help (the new name is documented)."""

    def __init__(self, option_strings, dest, new=None, **kw):
        self.new = new
        super().__init__(option_strings, dest, **kw)

    def __call__(self, parser, namespace, values, option_string=None):
        given = namespace.__dict__.setdefault("_given", set())
        if self.dest in given:
            parser.error(f"argument {self.new}: given twice (give each option once; {option_string} is its old name)")
        given.add(self.dest)
        warn_deprecated(option_string, self.new)
        setattr(namespace, self.dest, values)


def add_alias(p, old: str, new: str, dest: str, type=None):
    """`old` keeps working as a deprecated spelling of `new` (the same dest)."""
    p.add_argument(old, dest=dest, action=_Deprecated, new=new, default=argparse.SUPPRESS, help=argparse.SUPPRESS,
                   type=type)


def add_panel(p, *, dest="panel", default=None, help="a panel of the paper"):
    """--panel PANEL (a paper panel such as 4a) in every command that takes one; --figure is its old name there
    (`magrod multipulse --figure 6` is a whole figure and keeps its name)."""
    from ..core.printed import PANELS

    p.add_argument("--panel", dest=dest, default=default, metavar="PANEL", help=f"{help}: {', '.join(PANELS)}")
    add_alias(p, "--figure", "--panel", dest)


def add_threads(p, *, help="threads (default: all cores)"):
    """--threads N where a command runs threads; --workers is kept for processes (chaosmap's Dask workers) and is
    the deprecated old name here."""
    p.add_argument("--threads", dest="threads", default=None, metavar="N", help=help)
    add_alias(p, "--workers", "--threads", "threads")


def indicator(value: str) -> str:
    """--indicator growth|fli|lyap|none -> the field name the numerics use (growth -> growth_exponent); the old
    spelling growth_exponent still works, with one deprecation line."""
    v = str(value).strip()
    if v == "growth_exponent":
        warn_deprecated("--indicator growth_exponent", "--indicator growth")
        v = "growth"
    if v == "none":
        return v
    if v not in INDICATORS:
        raise argparse.ArgumentTypeError(f"invalid choice: {value!r} (choose from {', '.join([*INDICATORS, 'none'])})")
    return INDICATORS[v]


def add_start(g, names=("h", "theta0", "ptheta0", "psi0"), *, suffix=""):
    """The level and start options (--h, --theta0, --ptheta0, --psi0), each with its help."""
    for name in names:
        g.add_argument(f"--{name}", type=str, default=None, help=START_HELP[name] + suffix)


class HelpFormatter(argparse.HelpFormatter):
    """Each option's default stated once: appended as "(default: X)" only when the help does not already say
    its default and there is one to state (not None, not a flag's False)."""

    def _get_help_string(self, action):
        text = action.help or ""
        if action.default in (None, False, argparse.SUPPRESS) or "default" in text.lower() or not text:
            return text
        if action.option_strings or action.nargs in (argparse.OPTIONAL, argparse.ZERO_OR_MORE):
            return text + " (default: %(default)s)"
        return text

