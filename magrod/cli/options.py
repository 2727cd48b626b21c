"""Options and number parsers shared by the subcommands.  Numbers arrive as strings and are parsed here, so
that a bad value is a ParameterError naming the option (exit 2, one line), never an argparse usage dump."""
from __future__ import annotations

import argparse
import sys

from ..core.errors import MAX_MAGNITUDE, ParameterError, require_finite
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


# ---- one vocabulary: one option name per concept in every command -------------------------------------------
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


# ---- one CLI vocabulary: the same option name for the same concept in every command ----------------------------
# parallelism: --workers N everywhere (threads or processes, as the command's help says; the library's workers=);
#   --threads (poincare, orbitdiagram) and --jobs (reproduce) are its old names, one deprecation line each
# output: --out DIR on every command, never required; files are written only there; the commands whose product
#   is files (figure, reproduce, chaosmap, continue, multipulse, rod) write into ./out when it is not given, the
#   others write only when it is given
# a pulse count: --pulses N (multipulse's --max-pulses is its old name)
# what is studied: --panel (a paper panel) and --model NAME|FILE.py (a registered model or a model file), each
#   resolved once by magrod.core.system.as_system (`system_from`); --precision where the library takes it
WORKERS_HELP = "parallel workers"
OUT_DEFAULT = "out"
OUT_HELP = "output directory (files are written only there)"
PRECISIONS = ("double", "long double", "quad", "mp")


def add_workers(p, *, default=None, help="parallel workers", old=()):
    """--workers N (the library's workers=); each name in `old` is a deprecated spelling of it."""
    text = help if help.lower().startswith(WORKERS_HELP) else f"{WORKERS_HELP}: {help}"
    p.add_argument("--workers", dest="workers", default=default, metavar="N", help=text)
    for o in old:
        add_alias(p, o, "--workers", "workers")


def add_threads(p, *, help="threads (default: all cores)"):
    """Deprecated name of add_workers(old=("--threads",)), kept for one release."""
    add_workers(p, help=help, old=("--threads",))


def add_out(p, *, files=False, help=None):
    """--out DIR: `files=True` for a command whose product is files (default ./out), else written only if given."""
    if files:
        p.add_argument("--out", default=OUT_DEFAULT, metavar="DIR", help=help or OUT_HELP)
    else:
        p.add_argument("--out", default=None, metavar="DIR",
                       help=(help or OUT_HELP) + " (default: nothing is written)")


def add_pulses(p, *, default, help, old=()):
    """--pulses N, the one name of a pulse count; `old` are deprecated spellings."""
    p.add_argument("--pulses", dest="pulses", default=default, metavar="N", help=help)
    for o in old:
        add_alias(p, o, "--pulses", "pulses")


def add_precision(p, *, default="double", choices=PRECISIONS, help="floating-point precision of the run"):
    """--precision NAME (magrod.core.precision.Precision's names)."""
    p.add_argument("--precision", default=default, choices=tuple(choices), help=help)


def add_model(p, *, help="the rod model: a registered name (`magrod models`) or a model file (default: the "
                         "paper's rod)", params=True):
    """--model NAME|FILE.py and, with `params`, --model-params NAME=VALUE,... (the model's parameters)."""
    p.add_argument("--model", default=None, metavar="NAME|FILE.py", help=help)
    if params:
        p.add_argument("--model-params", default=None, metavar="NAME=VALUE,...",
                       help="with --model: the model's parameters (the others at the model's defaults)")


def model_params(args) -> dict:
    """--model-params NAME=VALUE,... as {name: float} (ParameterError("model_params") on a bad item)."""
    text = getattr(args, "model_params", None)
    out = {}
    if not text:
        return out
    for item in str(text).split(","):
        if not item.strip():
            continue
        name, eq, value = item.partition("=")
        name = name.strip()
        if not eq or not name:
            raise ParameterError("model_params", f"expected NAME=VALUE,..., got {item.strip()[:60]!r}")
        if name in out:
            raise ParameterError("model_params", f"{name} given twice")
        out[name] = require_finite(name, value.strip())
    return out


def is_paper_model(model) -> bool:
    from ..core.models import DEFAULT

    return model is None or model == DEFAULT


def system_from(args, *, overrides=None, default_panel=None):
    """(System, Panel or None): what the command studies, resolved ONCE by as_system from --model (with
    --model-params) or from --panel (default `default_panel`) and the paper's parameter options (--m --mu ...).
    A panel with --model is refused: a paper panel is of the paper's rod."""
    from ..core.system import as_system

    model = getattr(args, "model", None)
    key = getattr(args, "panel", None)
    if not is_paper_model(model):
        if key is not None:
            raise ParameterError("panel", f"a paper panel is of the paper's rod, not the model {str(model)[:80]!r}: "
                                          "give the model's parameters by --model-params")
        given = [n for n in PARAMS if getattr(args, n, None) is not None]
        if given and not hasattr(args, "model_params"):
            raise ParameterError(given[0], f"--{given[0]} is a parameter of the paper's rod, not of the model "
                                           f"{str(model)[:80]!r}")
        return as_system(model, **model_params(args))
    if getattr(args, "model_params", None):
        raise ParameterError("model_params", "needs --model (the paper's rod takes --m --mu --gamma --delta --lam)")
    vals = params_from(args) if overrides is None else overrides
    key = key if key is not None else default_panel
    if key is not None:
        from ..core.printed import panel

        key = panel(key)  # ParameterError("panel") for an unknown panel
    return as_system(key, **vals)


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

