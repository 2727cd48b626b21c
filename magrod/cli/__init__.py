"""`magrod` command line.  Every subcommand accepts --json and then prints exactly one JSON object on stdout
(progress goes to stderr).  Exit codes: 0 success, 1 computation failed, 2 invalid input (one line naming
the parameter and the violated condition, no traceback).

One module per subcommand in this package, each with add_arguments(parser), run(args) -> dict and
format_text(dict) -> str.  Subcommand modules import nothing heavy at module level (heyoka, matplotlib, SymPy are
imported inside run), so `magrod check` never loads heyoka or matplotlib."""
from __future__ import annotations

import argparse
import importlib
import json
import sys

from ..errors import ParameterError

# subcommand -> (module, help)
SUBCOMMANDS = {
    "check": ("magrod.cli.check", "integrability report (Casimirs, involution tables, reduction, I2bar cases)"),
    "poincare": ("magrod.cli.poincare", "Poincare sections sin(psi) = 0 (Figures 4, 5)"),
    "homoclinic": ("magrod.cli.homoclinic", "homoclinic orbit of the extensible rod at lambdabar = 0"),
    "melnikov": ("magrod.cli.melnikov", "Mel'nikov function amplitude (eq:Mel_ext)"),
    "figure": ("magrod.cli.figure", "write a figure of the paper (2, 3, 4, 5, 6, 7)"),
    "multipulse": ("magrod.cli.multipulse", "multipulse homoclinic orbits by shooting (Figures 6, 7)"),
    "rod": ("magrod.cli.rod", "3-D rod shape from a computed solution"),
    "reproduce": ("magrod.cli.reproduce", "reproduce every figure and claim of the paper"),
}


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="magrod", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, (module, help_) in SUBCOMMANDS.items():
        p = sub.add_parser(name, help=help_, description=help_,
                           formatter_class=argparse.ArgumentDefaultsHelpFormatter)
        p.add_argument("--json", action="store_true", help="print exactly one JSON object on stdout")
        p.add_argument("--quiet", action="store_true", help="no progress output")
        p.set_defaults(_module=module)
        importlib.import_module(module).add_arguments(p)
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.json:
        args.quiet = True
    mod = importlib.import_module(args._module)
    try:
        result = mod.run(args)
    except ParameterError as exc:
        if args.json:
            print(json.dumps({"ok": False, "error": str(exc), "parameter": exc.name}))
        print(f"magrod {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"magrod {args.command}: interrupted", file=sys.stderr)
        return 130
    ok = bool(result.get("ok", True))
    if args.json:
        print(json.dumps(result, sort_keys=True, default=_default))
    else:
        print(mod.format_text(result))
    return 0 if ok else 1


def _default(o):
    try:
        import numpy as np

        if isinstance(o, (np.floating, np.integer)):
            return o.item()
        if isinstance(o, np.ndarray):
            return o.tolist()
    except ImportError:  # pragma: no cover
        pass
    return str(o)
