"""`magrod` command line.  Every subcommand accepts --json and then prints exactly one JSON object on stdout
(progress goes to stderr).  Exit codes: 0 success, 1 computation failed (including a result that fails its own
accuracy checks), 2 invalid input (one line naming the parameter and the violated condition), 3 environment
fault (disk full, unwritable path, closed output pipe, a resource limit; one line with the path), 128 + N for
signal N (130 Ctrl-C, 143 SIGTERM, 129 SIGHUP: one line; a signal that arrives once the result is being printed
changes nothing).  Never a
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
import threading
import warnings

from ..core.errors import EnvironmentFault, ParameterError
from .options import HelpFormatter, add_model, add_out

EXIT_OK, EXIT_FAILED, EXIT_INPUT, EXIT_ENVIRONMENT, EXIT_INTERRUPTED = 0, 1, 2, 3, 130  # 128 + signal number

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
    "spectrum": ("magrod.cli.spectrum", "Lyapunov spectrum (all exponents) and GALI indices of one orbit"),
    "prove": ("magrod.cli.prove", "computer-assisted proof of transverse homoclinic orbits (certificate, --verify)"),
    "orbitdiagram": ("magrod.cli.orbitdiagram", "orbit diagram: Poincare section points against a model parameter"),
    "explore": ("magrod.cli.explore", "interactive Poincare-section explorer in the browser (127.0.0.1)"),
    "models": ("magrod.cli.models", "the rod models (registry and model files) with their parameters"),
    "landscape": ("magrod.cli.landscape", "the integrability landscape of sec. 1 re-derived from the rod models"),
    "saddle": ("magrod.cli.saddle", "the saddle at given parameters: straight rod or helical periodic saddle"),
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


class _StoreOnce(argparse._StoreAction):
    """argparse's `store`, refusing an option given twice (argparse keeps the last silently)."""

    def __call__(self, parser, namespace, values, option_string=None):
        given = namespace.__dict__.setdefault("_given", set())
        if self.dest in given:
            parser.error(f"argument {option_string}: given twice (give each option once)")
        given.add(self.dest)
        super().__call__(parser, namespace, values, option_string)


class Parser(argparse.ArgumentParser):
    """argparse without the multi-line usage dump on error: errors raise UsageError instead; an option that takes
    a value may be given only once."""

    def __init__(self, *a, **kw):
        super().__init__(*a, **kw)
        self.register("action", None, _StoreOnce)
        self.register("action", "store", _StoreOnce)

    def error(self, message):
        raise UsageError(_param_of(message), message)


# Every command takes --model NAME|FILE.py, resolved once (magrod.core.system.as_system): an unknown name or a bad
# file is refused as such.  Each command computes for any model; where a step needs a structure the model lacks (a
# reversor, a saddle, a small parameter), the library says which by name (core.errors.MissingStructure, exit 2).
# These commands are about the paper itself (its figures, its claims, the proofs of its theorems on its validated
# fields); with another model they say so, by name, before anything runs: (what they need, why).
DEFAULT_MODEL = "magnetic-extensible"  # = magrod.core.models.DEFAULT (not imported: it would load the model code)
PAPER_ONLY = {
    "figure": ("the paper's figures", "they are figures of the paper's rod"),
    "reproduce": ("the paper's claims", "it reproduces the paper (the other models: magrod landscape)"),
    "prove": ("validated fields (generated/validated.py)",
              "the interval enclosures and certificate schema are generated for the paper's rod in this release"),
}


def routes_models(command: str) -> bool:
    """True if `command` runs any model (it is not one of PAPER_ONLY)."""
    return command not in PAPER_ONLY


def _check_model(args) -> None:
    """--model checked once before anything runs: an unknown name or a missing model file is a
    ParameterError("model") saying so; a command that needs what the model lacks says which structure, by name.
    Nothing is loaded here (a model file is code the user runs on purpose: the command that computes with it loads
    it, through as_system; a command that cannot use it never runs it)."""
    model = getattr(args, "model", None)
    if model is None or model == DEFAULT_MODEL:
        return
    from ..core import models

    if models.is_model_path(model):
        from pathlib import Path

        if not Path(model).is_file():
            models.resolve(model)  # the registry's own words for a missing file
        name = str(model)
    else:
        if model not in models.registered():
            models.resolve(model)  # ParameterError("model"): unknown model, with the registered names
        name = model
    if name == models.DEFAULT or routes_models(args.command):
        return
    structure, why = PAPER_ONLY[args.command]
    raise ParameterError("model", f"{args.command} needs {structure}, and the model {name[:80]!r} has none: {why}; "
                                  "for this model use the other commands with --model")


def build_parser() -> argparse.ArgumentParser:
    parser = Parser(prog="magrod", description=__doc__.split("\n")[0])
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND", parser_class=Parser)
    for name, (module, help_) in SUBCOMMANDS.items():
        p = sub.add_parser(name, help=help_, description=help_,
                           formatter_class=HelpFormatter)
        p.add_argument("--json", action="store_true", help="print exactly one JSON object on stdout")
        p.add_argument("--quiet", action="store_true", help="no progress output")
        p.set_defaults(_module=module)
        importlib.import_module(module).add_arguments(p)
        have = {o for a in p._actions for o in a.option_strings}
        if "--model" not in have:
            add_model(p, params=False, help="the rod model: a registered name (`magrod models`) or a model file; "
                                            f"this command needs a structure of the paper's rod ({DEFAULT_MODEL})")
        if "--out" not in have:  # one rule: --out DIR on every command; here the result is written as JSON there
            add_out(p, help=f"write the result as DIR/{name}.json")
            p.set_defaults(_result_out=name)
    return parser


# Signals that end a run: SIGINT (Ctrl-C), SIGTERM (a job queue, `timeout`, `kill`), SIGHUP (the terminal closed).
# The first one raises Interrupted (a KeyboardInterrupt, so libraries that clean up on Ctrl-C do so); later ones,
# and any that arrive once the result is being printed, are only recorded, so that cleanup is never interrupted
# and a finished run ends with its own exit code.
SIGNALS = tuple(getattr(signal, n) for n in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, n))
_STATE = {"signals": [], "armed": False}


class Interrupted(KeyboardInterrupt):
    """The run was stopped by a signal; exit code 128 + signum (130 SIGINT, 143 SIGTERM, 129 SIGHUP)."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


def _on_signal(signum, frame):
    _STATE["signals"].append(signum)
    if _STATE["armed"] and _STATE.get("deferred"):  # inside signals_deferred: raised when it ends
        _STATE.setdefault("pending", signum)
        return
    if _STATE["armed"]:
        _STATE["armed"] = False  # one exception per run
        _STATE["unhandled"] = signum  # cleared when the Interrupted reaches _main: a library may swallow it
        raise Interrupted(signum)


def _after_exit(signum, frame):
    """Installed by console_main around main(): a signal while the interpreter shuts down changes nothing."""
    _STATE["signals"].append(signum)


def _interrupt_code() -> int:
    return 128 + (_STATE["signals"][0] if _STATE["signals"] else signal.SIGINT)


def _interrupt_message() -> str:
    signum = _STATE["signals"][0] if _STATE["signals"] else signal.SIGINT
    try:
        return f"interrupted ({signal.Signals(signum).name})"
    except ValueError:  # pragma: no cover
        return "interrupted"


PAUSE_ENV = "MAGROD_TEST_PAUSE"
STARTED_ENV = "MAGROD_TEST_STARTED"  # console_main writes this file first thing (tests sweep signals from there)


def pause_point(point: str) -> None:
    """Test hook: with MAGROD_TEST_PAUSE=POINT:MARKER in the environment, reaching POINT writes the file MARKER and
    waits (at most 60 s) until a signal arrives or the test removes MARKER, so that tests act at a known moment
    rather than after a sleep.  Without the variable (always, outside the tests) it does nothing."""
    spec = os.environ.get(PAUSE_ENV, "")
    want, _, marker = spec.partition(":")
    if not marker or want != point:
        return
    import time

    n = len(_STATE["signals"])
    with open(marker, "w") as fh:
        fh.write(str(os.getpid()))
    deadline = time.monotonic() + 60.0
    while time.monotonic() < deadline and len(_STATE["signals"]) == n and os.path.exists(marker):
        time.sleep(0.005)  # an armed signal raises Interrupted out of this sleep


def _command_of(argv) -> str:
    return next((a for a in argv if not a.startswith("-")), "")


def main(argv=None) -> int:
    """Run one command; returns its exit code.  The process-wide settings a command line tool owns (SIGINT,
    SIGTERM, SIGHUP and SIGXFSZ handlers, how warnings are printed, heyoka's logger via MAGROD_QUIET_HEYOKA) are
    installed here and restored on return, so that calling main() from Python (tests, notebooks) leaves the
    process as it was."""
    saved = _install_process_settings()
    try:
        try:
            return _main(argv)
        except KeyboardInterrupt:  # a signal that hit an error path before it disarmed: still one line
            _STATE["armed"] = False
            argv_ = list(sys.argv[1:] if argv is None else argv)
            command = _command_of(argv_) if _command_of(argv_) in SUBCOMMANDS else ""
            return _fail(command, "--json" in argv_, _interrupt_code(), _interrupt_message(), None)
    finally:
        _STATE["armed"] = False
        _restore_process_settings(saved)


def console_main() -> None:
    """The `magrod` script and `python -m magrod.cli`: main(), and the process ends with its exit code even if a
    signal arrives while the interpreter shuts down (no KeyboardInterrupt reaches interpreter shutdown).

    Once main() has returned, the signals are *ignored* (SIG_IGN), not recorded: at shutdown CPython resets every
    signal with a Python handler to SIG_DFL (_PySignal_Fini), and a Ctrl-C in the milliseconds after the result
    was printed then killed the process (exit -2, no line).  A signal handled as SIG_IGN stays ignored."""
    for s in SIGNALS:
        signal.signal(s, _after_exit)
    _STATE["early"] = True  # a signal between here and main()'s handlers is kept, and ends the run at once
    started = os.environ.get(STARTED_ENV)
    if started:  # test hook: the moment magrod's own code runs (before it, the interpreter's start-up owns SIGINT)
        with open(started, "w") as fh:
            fh.write(str(os.getpid()))
    code = main()
    for s in SIGNALS:
        signal.signal(s, signal.SIG_IGN)
    if _STATE["signals"]:
        # The run ended on a signal and said so in its one line.  What libraries log while the interpreter tears
        # down what the signal cut short is not news, and broke that one line: asyncio's "Task was destroyed but
        # it is pending!" for a Dask client's task, logged when the task is collected at shutdown, a coroutine's
        # "never awaited" warning, or the "Exception ignored in: <module 'threading'>" traceback of a process
        # pool's exit handler writing to the wake-up pipe of a pool the signal already tore down.
        import logging

        logging.disable(logging.CRITICAL)
        warnings.simplefilter("ignore")
        sys.unraisablehook = _ignore_unraisable
    sys.exit(code)


def _ignore_unraisable(unraisable) -> None:
    """sys.unraisablehook once a run has ended on a signal and said so (console_main): nothing more is printed."""


def _install_process_settings() -> dict:
    saved = {"signals": {s: signal.getsignal(s) for s in SIGNALS}, "showwarning": warnings.showwarning,
             "env": os.environ.get(QUIET_ENV), "thread_start": threading.Thread.start}
    if not _STATE.pop("early", False):
        _STATE["signals"].clear()
    for k in ("unhandled", "pending", "deferred"):
        _STATE.pop(k, None)
    _STATE["armed"] = True
    for s in SIGNALS:  # from here on a signal is an Interrupted exception (and remembered)
        signal.signal(s, _on_signal)
    # Every thread started during the run blocks the signals: a process-directed signal is then delivered to the
    # main thread, which interrupts its blocking call and runs the handler, and never to a library's thread
    # (zarr's I/O loop, Dask's event loop, asyncio executors).  Worker processes spawned from those threads
    # inherit the blocked mask, so a terminal's Ctrl-C to the process group is the parent's alone to handle.
    threading.Thread.start = _start_blocking_signals
    if hasattr(signal, "SIGXFSZ"):  # a file-size limit (ulimit -f) must be an OSError, not a kill
        saved["SIGXFSZ"] = signal.getsignal(signal.SIGXFSZ)
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    # heyoka logs JIT-cache trouble to stdout, which would break --json: the library quiets it when asked to
    os.environ[QUIET_ENV] = "1"
    warnings.showwarning = _show_warning
    return saved


_THREAD_START = threading.Thread.start


def _start_blocking_signals(self, *a, **kw):
    """threading.Thread.start with SIGNALS blocked in the new thread (a thread inherits its creator's mask)."""
    if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - not POSIX
        return _THREAD_START(self, *a, **kw)
    old = signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS)
    try:
        return _THREAD_START(self, *a, **kw)
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _restore_process_settings(saved: dict) -> None:
    threading.Thread.start = saved["thread_start"]
    warnings.showwarning = saved["showwarning"]
    if saved["env"] is None:
        os.environ.pop(QUIET_ENV, None)
    else:
        os.environ[QUIET_ENV] = saved["env"]
    if "SIGXFSZ" in saved:
        signal.signal(signal.SIGXFSZ, saved["SIGXFSZ"])
    for s, h in saved["signals"].items():
        signal.signal(s, h if h is not None else signal.SIG_DFL)


class signals_deferred:
    """Context manager: a signal that arrives meanwhile is recorded, and its Interrupted raised on exit (never
    lost, never raised inside the code of the block).  The deferral is at the Python level, because a signal may
    be delivered to any thread that does not block it (OpenBLAS's and TBB's threads are not Python's), and
    CPython then runs the handler in the main thread whatever the main thread's mask; the signals are blocked in
    the calling thread as well, so that processes started in the block inherit the blocked mask."""

    def __enter__(self):
        self._mask = signal.pthread_sigmask(signal.SIG_BLOCK, SIGNALS) if hasattr(signal, "pthread_sigmask") else None
        self._outer = _STATE.get("deferred", False)
        _STATE["deferred"] = True
        return self

    def __exit__(self, *exc):
        _STATE["deferred"] = self._outer
        if self._mask is not None:
            signal.pthread_sigmask(signal.SIG_SETMASK, self._mask)  # a signal pending in this thread arrives here
        if not self._outer and _STATE.get("pending") is not None:
            signum = _STATE.pop("pending")
            if _STATE["armed"]:
                _STATE["armed"] = False
                _STATE["unhandled"] = signum
                raise Interrupted(signum)
        return False


# Commands that never load heyoka (`magrod check` must stay light); every other command imports it up front with
# the signals deferred: heyoka's extension module imports SymPy inside a C++ try/catch, which swallows the
# KeyboardInterrupt of a Ctrl-C that lands during that import, and the run then went on to its end.
LIGHT_COMMANDS = {"check"}


class children_immune(signals_deferred):
    """Context manager around starting worker processes (a Dask LocalCluster, a process pool): the signals of
    SIGNALS are blocked in the calling thread while the children are created.  A child inherits the blocked mask
    across fork and exec (as it does from the threads main() starts, `_start_blocking_signals`), so a Ctrl-C in
    the terminal, which reaches the whole process group, or a closed terminal's SIGHUP, is the parent's alone to
    handle: the parent stops its workers.  A signal that arrives meanwhile stays pending and is delivered to the
    parent's handler on exit.

    The dispositions are left alone.  Once they were set to SIG_IGN here as well; a signal delivered to
    one of the library threads that did not block it (zarr's, asyncio's) was then discarded, and a Ctrl-C 2-3 s
    after `magrod chaosmap` started (the LocalCluster's start-up) was lost."""


QUIET_ENV = "MAGROD_QUIET_HEYOKA"  # = magrod.core.systems.QUIET_ENV (not imported: that would load heyoka)


def _show_warning(message, category, filename, lineno, file=None, line=None):
    """A warning is one stderr line, 'magrod: warning: ...' (never the source line Python shows by default).  Once
    a signal has ended the run, warnings are dropped: the interrupted run says one line, and what a library thread
    warns while it is torn down (zarr's consolidated-metadata warning, escaping the filter of an interrupted write,
    seen by the start-up signal sweep) is not news."""
    if _STATE["signals"]:
        return
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
        if _STATE["signals"]:  # arrived while the process started (console_main): honoured before anything runs
            _STATE["armed"] = False
            raise Interrupted(_STATE["signals"][0])
        args = build_parser().parse_args(argv)
        want_json = bool(args.json)
        if args.json:
            args.quiet = True
        _check_model(args)
        if getattr(args, "_result_out", None) and args.out is not None:
            from ..core.io import check_out_path

            check_out_path(args.out, "out")  # refused before the run: a bad --out writes nothing
        mod = importlib.import_module(args._module)
        if args.command not in LIGHT_COMMANDS and "heyoka" not in sys.modules:
            with signals_deferred():
                importlib.import_module("heyoka")
        result = mod.run(args)
        if _STATE.get("unhandled") is not None:
            # the signal's Interrupted was raised inside a library that swallowed it (a __del__, a callback, an
            # `except BaseException: pass`), and the run went on to its end: the signal is still honoured
            raise Interrupted(_STATE["unhandled"])
        ok = bool(result.get("ok", True))
        if getattr(args, "_result_out", None) and args.out is not None:
            from ..core.io import atomic_write_text, ensure_writable_dir

            out = ensure_writable_dir(args.out, "out")
            result = {**result, "files": [str(atomic_write_text(out / f"{args._result_out}.json",
                                                                 json.dumps(_clean(result), sort_keys=True,
                                                                            allow_nan=False, indent=1) + "\n"))]}
        text = json.dumps(_clean(result), sort_keys=True, allow_nan=False) if want_json else mod.format_text(result)
        _STATE["armed"] = False  # from here on the run is finished: a signal ends it quietly with this exit code
        _emit(text)
        if not ok:  # a computation that failed (or failed its own accuracy checks) says so once on stderr
            _stderr(command, f"error: {result.get('error') or result.get('message') or 'computation failed'}")
        pause_point("printed")
        return EXIT_OK if ok else EXIT_FAILED
    except ParameterError as exc:
        # a structure the model lacks (core.errors.MissingStructure) is named in the JSON object as well
        return _fail(command, want_json, EXIT_INPUT, str(exc), exc.name, structure=getattr(exc, "structure", None))
    except KeyboardInterrupt:
        _STATE["armed"] = False
        _STATE.pop("unhandled", None)
        return _fail(command, want_json, _interrupt_code(), _interrupt_message(), None)
    except BrokenPipeError:
        _STATE["armed"] = False
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
        if _STATE["signals"]:  # a signal landed inside a library (e.g. half-way through an import) and came out as this
            _STATE["armed"] = False
            return _fail(command, want_json, _interrupt_code(), _interrupt_message(), None)
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


def _fail(command, want_json, code, message, parameter, structure=None) -> int:
    _STATE["armed"] = False  # the run is over: a further signal must not interrupt the error report
    _cleanup()
    if want_json:
        obj = {"ok": False, "error": " ".join(str(message).split()), "parameter": parameter, "exit_code": code}
        if structure is not None:
            obj["structure"] = structure
        try:
            _emit(json.dumps(obj))
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
