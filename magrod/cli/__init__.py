"""`magrod` command line.  Every subcommand accepts --json and then prints exactly one JSON object on stdout
(progress goes to stderr).  Exit codes: 0 success, 1 computation failed (including a result that fails its own
accuracy checks), 2 invalid input (one line naming the parameter and the violated condition), 3 environment
fault (disk full, unwritable path, closed output pipe; one line with the path), 130 interrupted.  Never a
traceback (set MAGROD_DEBUG=1 to get one for an internal error); nothing is left behind by a failed run.

One module per subcommand in this package, each with add_arguments(parser), run(args) -> dict and
format_text(dict) -> str.  Subcommand modules import nothing heavy at module level (heyoka, matplotlib, SymPy are
imported inside run), so `magrod check` never loads heyoka or matplotlib."""
from __future__ import annotations

import argparse
import importlib
import json
import math
import os
import re
import signal
import sys
import warnings

from ..core.errors import EnvironmentFault, ParameterError

EXIT_OK, EXIT_FAILED, EXIT_INPUT, EXIT_ENVIRONMENT, EXIT_INTERRUPTED = 0, 1, 2, 3, 130

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
    "continue": ("magrod.cli.continuation", "pseudo-arclength continuation of symmetric homoclinic orbits"),
    "splitting": ("magrod.cli.splitting", "splitting of the separatrix along mu = a eps^2, lam = b eps^2"),
    "chaosmap": ("magrod.cli.chaosmap", "chaos map (Lyapunov/FLI indicators) over a parameter plane or a section"),
    "explore": ("magrod.cli.explore", "interactive Poincare-section explorer in the browser (127.0.0.1)"),
}


class UsageError(ParameterError):
    """An argparse error (unknown option, bad choice, missing value ...), routed through the common error path."""

    def __str__(self):
        msg = self.message.replace("argument COMMAND", "command").replace("COMMAND", "command")
        return msg if self.name in msg else f"{self.name}: {msg}"


def _param_of(message: str) -> str:
    """The option an argparse message is about (for the one-line error and the JSON `parameter`)."""
    m = re.match(r"argument (\S+?)(?:/\S+)?: ", message)
    if m:
        name = m.group(1)
        return "command" if name in ("COMMAND", "command") else name.lstrip("-").replace("-", "_")
    m = re.match(r"the following arguments are required: (\S+?)(?:,|$)", message)
    if m:
        name = m.group(1).split("/")[0]
        return "command" if name in ("COMMAND", "command") else name.lstrip("-").replace("-", "_")
    m = re.match(r"unrecognized arguments: (\S+)", message)
    if m:
        return m.group(1).split("=")[0].lstrip("-").replace("-", "_")
    return "arguments"


class Parser(argparse.ArgumentParser):
    """argparse without the multi-line usage dump on error: errors raise UsageError instead."""

    def error(self, message):
        raise UsageError(_param_of(message), message)


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="magrod", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=Parser)
    for name, (module, help_) in SUBCOMMANDS.items():
        p = sub.add_parser(name, help=help_, description=help_,
                           formatter_class=argparse.ArgumentDefaultsHelpFormatter)
        p.add_argument("--json", action="store_true", help="print exactly one JSON object on stdout")
        p.add_argument("--quiet", action="store_true", help="no progress output")
        p.set_defaults(_module=module)
        importlib.import_module(module).add_arguments(p)
    return parser


_INTERRUPTED: list = []


def _on_sigint(signum, frame):
    _INTERRUPTED.append(signum)
    raise KeyboardInterrupt


def _command_of(argv) -> str:
    return next((a for a in argv if not a.startswith("-")), "")


def main(argv=None) -> int:
    """Run one command; returns its exit code.  The process-wide settings a command line tool owns (SIGINT and
    SIGXFSZ handlers, how warnings are printed, heyoka's logger via MAGROD_QUIET_HEYOKA) are installed here and
    restored on return, so that calling main() from Python (tests, notebooks) leaves the process as it was."""
    saved = _install_process_settings()
    try:
        return _main(argv)
    finally:
        _restore_process_settings(saved)


def _install_process_settings() -> dict:
    saved = {"SIGINT": signal.getsignal(signal.SIGINT), "showwarning": warnings.showwarning,
             "env": os.environ.get(QUIET_ENV)}
    _INTERRUPTED.clear()
    signal.signal(signal.SIGINT, _on_sigint)  # from here on Ctrl-C is a KeyboardInterrupt (and remembered)
    if hasattr(signal, "SIGXFSZ"):  # a file-size limit (ulimit -f) must be an OSError, not a kill
        saved["SIGXFSZ"] = signal.getsignal(signal.SIGXFSZ)
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    # heyoka logs JIT-cache trouble to stdout, which would break --json: the library quiets it when asked to
    os.environ[QUIET_ENV] = "1"
    warnings.showwarning = _show_warning
    return saved


def _restore_process_settings(saved: dict) -> None:
    warnings.showwarning = saved["showwarning"]
    if saved["env"] is None:
        os.environ.pop(QUIET_ENV, None)
    else:
        os.environ[QUIET_ENV] = saved["env"]
    if "SIGXFSZ" in saved:
        signal.signal(signal.SIGXFSZ, saved["SIGXFSZ"])
    signal.signal(signal.SIGINT, saved["SIGINT"] if saved["SIGINT"] is not None else signal.SIG_DFL)


QUIET_ENV = "MAGROD_QUIET_HEYOKA"  # = magrod.core.systems.QUIET_ENV (not imported: that would load heyoka)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """A warning is one stderr line, 'magrod: warning: ...' (never the source line Python shows by default)."""
    text = " ".join(f"magrod: warning: {message}".split())
    try:
        print(text, file=sys.stderr, flush=True)
    except (OSError, ValueError):
        pass


def _main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    want_json = "--json" in argv
    command = _command_of(argv) if _command_of(argv) in SUBCOMMANDS else ""
    try:
        from ..core import io

        io.track_created_dirs()
        args = build_parser().parse_args(argv)
        want_json = bool(args.json)
        if args.json:
            args.quiet = True
        mod = importlib.import_module(args._module)
        result = mod.run(args)
        ok = bool(result.get("ok", True))
        text = json.dumps(_clean(result), sort_keys=True, allow_nan=False) if want_json else mod.format_text(result)
        _emit(text)
        if not ok:  # a computation that failed (or failed its own accuracy checks) says so once on stderr
            _stderr(command, f"error: {result.get('error') or result.get('message') or 'computation failed'}")
        return EXIT_OK if ok else EXIT_FAILED
    except ParameterError as exc:
        return _fail(command, want_json, EXIT_INPUT, str(exc), exc.name)
    except KeyboardInterrupt:
        return _fail(command, want_json, EXIT_INTERRUPTED, "interrupted", None)
    except BrokenPipeError:
        # the reader went away (e.g. `| head -c 10`): stop writing to it, say so once on stderr
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except OSError:
            pass
        _stderr(command, "error: output pipe closed by the reader")
        return EXIT_ENVIRONMENT
    except EnvironmentFault as exc:
        return _fail(command, want_json, EXIT_ENVIRONMENT, str(exc), exc.name)
    except OSError as exc:
        path = exc.filename if exc.filename is not None else ""
        msg = f"{exc.strerror or exc}" + (f": {path!r}" if path else "")
        return _fail(command, want_json, EXIT_ENVIRONMENT, msg, "out")
    except MemoryError:
        return _fail(command, want_json, EXIT_ENVIRONMENT, "out of memory", None)
    except Exception as exc:  # an internal error: one line (MAGROD_DEBUG=1 re-raises for the traceback)
        if _INTERRUPTED:  # Ctrl-C landed inside a library (e.g. half-way through an import) and came out as this
            return _fail(command, want_json, EXIT_INTERRUPTED, "interrupted", None)
        if os.environ.get("MAGROD_DEBUG"):
            raise
        msg = " ".join(f"internal error: {type(exc).__name__}: {exc}".split())
        return _fail(command, want_json, EXIT_FAILED, msg, None)
    finally:
        _cleanup()


def _stderr(command: str, text: str) -> None:
    line = " ".join(f"magrod{' ' + command if command else ''}: {text}".split())  # exactly one line
    try:
        print(line, file=sys.stderr, flush=True)
    except (OSError, ValueError):
        pass


def _emit(text: str) -> None:
    sys.stdout.write(text + "\n")
    sys.stdout.flush()


def _cleanup() -> None:
    io = sys.modules.get(__package__.rsplit(".", 1)[0] + ".core.io")
    if io is not None:
        io.remove_empty_created_dirs()


def _fail(command, want_json, code, message, parameter) -> int:
    _cleanup()
    if want_json:
        try:
            _emit(json.dumps({"ok": False, "error": " ".join(str(message).split()), "parameter": parameter,
                              "exit_code": code}))
        except (BrokenPipeError, OSError, ValueError):
            pass
    _stderr(command, f"error: {message}")
    return code


def _clean(o):
    """JSON-able copy: numpy scalars/arrays to Python, non-finite floats to None (strict JSON has no NaN)."""
    if isinstance(o, dict):
        return {str(k): _clean(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_clean(v) for v in o]
    if isinstance(o, float):
        return o if math.isfinite(o) else None
    if isinstance(o, (str, int, bool)) or o is None:
        return o
    try:
        import numpy as np

        if isinstance(o, np.ndarray):
            return _clean(o.tolist())
        if isinstance(o, (np.floating, np.integer, np.bool_)):
            return _clean(o.item())
    except ImportError:  # pragma: no cover
        pass
    return str(o)
