"""`magrod` command line.  Every subcommand accepts --json and then prints exactly one JSON object on stdout
(progress goes to stderr).  Exit codes: 0 success, 1 computation failed, 2 invalid input (one line naming
the parameter and the violated condition, no traceback)."""
from __future__ import annotations

import argparse
import importlib
import importlib.util
import json
import sys

from .errors import ParameterError

# subcommand -> module; each module defines add_arguments(parser), run(args) -> dict, format_text(dict) -> str.
# Imported lazily so that `magrod check` does not pay for heyoka/matplotlib imports it does not need.
SUBCOMMANDS = {
    "check": ("magrod.check", "integrability report (Casimirs, involution tables, reduction, I2bar cases)"),
}


def register(name: str, module: str, help_: str) -> None:
    SUBCOMMANDS[name] = (module, help_)


def _optional_subcommands():
    # capabilities that live in their own modules; listed here so `magrod --help` shows them all
    for name, module, help_ in [
        ("poincare", "magrod.poincare_cli", "Poincare sections sin(psi) = 0 (Figures 4, 5)"),
        ("homoclinic", "magrod.homoclinic_cli", "homoclinic orbit of the extensible rod at lambdabar = 0"),
        ("melnikov", "magrod.melnikov_cli", "Mel'nikov function amplitude (eq:Mel_ext)"),
        ("figure", "magrod.figures_cli", "write a figure of the paper (2, 3, 4, 5, 6, 7)"),
        ("multipulse", "magrod.multipulse_cli", "multipulse homoclinic orbits by shooting (Figures 6, 7)"),
        ("rod", "magrod.rod_cli", "3-D rod shape from a computed solution"),
        ("reproduce", "magrod.reproduce", "reproduce every figure and claim of the paper"),
        ("chaosmap", "magrod.chaosmap_cli", "chaos maps (FLI, Lyapunov) over parameter planes and sections"),
    ]:
        if importlib.util.find_spec(module) is not None:
            SUBCOMMANDS.setdefault(name, (module, help_))


def build_parser() -> argparse.ArgumentParser:
    _optional_subcommands()
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


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
