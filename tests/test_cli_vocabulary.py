"""One CLI vocabulary: every parser is walked.  Every option has help, its default is stated at most
once, one name per concept in every command (--panel for a paper panel, --model for the rod model, --workers for
parallelism, --pulses for a pulse count, --out never required, one spelling of the indicators, one text for --root), and the old spellings still work, with one
deprecation line on stderr, giving the same namespace as the new ones."""
from __future__ import annotations

import argparse
import re

import pytest

from magrod import cli
from magrod.cli import options


def _subparsers():
    parser = cli.build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return sub.choices


SUBS = _subparsers()


def _visible(p):
    return [a for a in p._actions if a.help is not argparse.SUPPRESS and not isinstance(a, argparse._HelpAction)]


@pytest.mark.parametrize("name", list(SUBS))
def test_every_option_has_help_with_its_default_once(name):
    """Seen to fail before: `check --degree` said "(default 4; ...) (default: None)" and poincare's --h,
    --theta0, --ptheta0 had no help (ArgumentDefaultsHelpFormatter, help=None)."""
    p = SUBS[name]
    fmt = p._get_formatter()
    bad = []
    for a in _visible(p):
        text = fmt._expand_help(a) if a.help else ""
        label = "/".join(a.option_strings) or a.dest
        if not text.strip():
            bad.append(f"{label}: no help")
        n = len(re.findall(r"\bdefault", text, flags=re.I))
        if n > 1:
            bad.append(f"{label}: default stated {n} times: {text!r}")
        if "(default: None)" in text or "(default: False)" in text:
            bad.append(f"{label}: {text!r}")
        # a help that states its default in words must not have an argparse default too: the docs page
        # (sphinx-argparse) adds "Default: X" for every non-None default, and the two would double
        if re.search(r"\bdefault", a.help or "", flags=re.I) and a.default not in (None, False, argparse.SUPPRESS):
            bad.append(f"{label}: help says its default and argparse has one ({a.default!r}): {a.help!r}")
    assert not bad, bad
    # the rendered help as a user sees it: no doubled default anywhere
    assert not re.search(r"\(default[^)]*\)\s*\(default", p.format_help().replace("\n", " "))


def test_one_name_per_concept():
    """A paper panel is --panel, parallelism is --workers (threads or processes, as its help says), the indicators
    have one spelling and --root one help text.  Seen to fail before (poincare and orbitdiagram took --figure PANEL
    and --threads, reproduce --jobs; poincare spelt growth_exponent)."""
    bad = []
    indicator_sets = {}
    for name, p in SUBS.items():
        for a in _visible(p):
            opts = set(a.option_strings)
            if a.metavar == "PANEL" and "--panel" not in opts:
                bad.append(f"{name} {opts}: a panel option not called --panel")
            if opts & {"--threads", "--jobs", "--max-pulses", "--figure"}:
                bad.append(f"{name} {opts}: an old name visible")
            if "--workers" in opts and not (a.help or "").lower().startswith(options.WORKERS_HELP):
                bad.append(f"{name} --workers: help does not start with {options.WORKERS_HELP!r}")
            if "--root" in opts and a.help not in (options.ROOT_HELP, options.ROOT_INDEX_HELP):
                bad.append(f"{name} --root: its own help text {a.help!r}")
            if "--indicator" in opts:
                choices = a.choices or set(re.findall(r"\w+", a.metavar or ""))
                indicator_sets[name] = set(choices) - {"none"}
    spellings = {frozenset(v) for v in indicator_sets.values()}
    assert len(spellings) == 1, indicator_sets
    assert spellings == {frozenset(options.INDICATORS)}, spellings
    assert not bad, bad


# the commands whose product is files: --out defaults to ./out there; elsewhere nothing is written without --out
FILE_COMMANDS = {"figure", "reproduce", "chaosmap", "continue", "multipulse", "rod"}
# the commands that study the paper's rod at a paper panel
PANEL_COMMANDS = {"poincare", "orbitdiagram", "spectrum", "chaosmap", "explore", "saddle", "multipulse"}
# a command -> the public function it calls: where the function takes precision=, the command takes --precision
FUNCTION_OF = {"poincare": "poincare_section", "saddle": "saddle", "spectrum": "lyapunov_spectrum",
               "chaosmap": "chaos_map", "orbitdiagram": "orbit_diagram", "multipulse": "multipulse_orbits",
               "continue": "continue_branch", "splitting": "splitting", "explore": "explore",
               "check": "integrability_report"}
PARALLELISM_WORDS = ("thread", "worker", "process", "core")
# options that are about parallelism without being a count of workers (where to find them, how long to wait)
NOT_A_COUNT = {"--scheduler", "--scheduler-file", "--worker-timeout"}


def _options(p):
    return {o: a for a in _visible(p) for o in a.option_strings}


@pytest.mark.parametrize("name", list(SUBS))
def test_one_vocabulary_walking_every_parser(name):
    """The parser walk of the one CLI vocabulary: --out on every command and never required (./out for commands
    whose product is files, nothing written by default elsewhere); --model on every command; --panel wherever a
    paper panel applies; --precision wherever the library function behind the command takes precision=; a
    parallelism option is --workers and a pulse count --pulses.  Seen to fail before: chaosmap required --out,
    landscape refused it, poincare had no --precision, reproduce took --jobs, multipulse --max-pulses and
    --figure."""
    import inspect

    import magrod as mr

    p = SUBS[name]
    opts = _options(p)
    bad = []
    out = opts.get("--out")
    if out is None:
        bad.append("no --out")
    elif out.required:
        bad.append("--out is required")
    elif (out.default == options.OUT_DEFAULT) != (name in FILE_COMMANDS):
        bad.append(f"--out default {out.default!r}: the rule is {options.OUT_DEFAULT!r} exactly for "
                   f"{sorted(FILE_COMMANDS)}")
    if "--model" not in opts:
        bad.append("no --model")
    if name in PANEL_COMMANDS and "--panel" not in opts:
        bad.append("no --panel")
    fn = FUNCTION_OF.get(name)
    if fn is not None and "precision" in inspect.signature(getattr(mr, fn)).parameters and "--precision" not in opts:
        bad.append(f"no --precision although {fn}() takes precision=")
    for o, a in opts.items():
        if o not in NOT_A_COUNT and o != "--workers" and (o.startswith(("--thread", "--job", "--core", "--proc"))
                                                           or "worker" in o):
            bad.append(f"{o}: parallelism is --workers")
        if o != "--pulses" and "pulse" in o:
            bad.append(f"{o}: a pulse count is --pulses")
        if o == "--workers" and not any(w in (a.help or "").lower() for w in PARALLELISM_WORDS):
            bad.append("--workers: its help does not say what runs in parallel")
    assert not bad, bad


def test_the_walk_names_real_commands():
    """The lists above name real commands (a renamed command must not silently leave the walk)."""
    assert FILE_COMMANDS <= set(SUBS) and PANEL_COMMANDS <= set(SUBS) and set(FUNCTION_OF) <= set(SUBS)


def test_out_on_a_command_without_files_writes_the_json_result(tmp_path, capsys):
    """A command without files of its own writes its result as DIR/<command>.json under --out (landscape refused
    --out before); a bad --out is refused before the run, writing nothing."""
    import json

    assert cli.main(["models", "--out", str(tmp_path / "o"), "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    written = json.loads((tmp_path / "o" / "models.json").read_text())
    assert d["files"] == [str(tmp_path / "o" / "models.json")]
    assert {k: v for k, v in written.items() if k != "files"} == {k: v for k, v in d.items() if k != "files"}
    (tmp_path / "f").write_text("")
    assert cli.main(["models", "--out", str(tmp_path / "f" / "x"), "--json"]) == 2
    assert json.loads(capsys.readouterr().out)["parameter"] == "out"


# (command, old argv, new argv, the dest both must set to the same value)
ALIASES = [
    ("poincare", ["--figure", "4a"], ["--panel", "4a"], "panel", "4a"),
    ("orbitdiagram", ["--parameter", "lam", "--values", "0.1:0.2:3", "--figure", "5a"],
     ["--parameter", "lam", "--values", "0.1:0.2:3", "--panel", "5a"], "panel", "5a"),
    ("poincare", ["--threads", "3"], ["--workers", "3"], "workers", "3"),
    ("orbitdiagram", ["--parameter", "lam", "--values", "0.1:0.2:3", "--threads", "2"],
     ["--parameter", "lam", "--values", "0.1:0.2:3", "--workers", "2"], "workers", "2"),
    ("reproduce", ["--jobs", "3"], ["--workers", "3"], "workers", "3"),
    ("multipulse", ["--max-pulses", "3"], ["--pulses", "3"], "pulses", "3"),
    ("multipulse", ["--figure", "7"], ["--panel", "7"], "panel", 7),
    ("poincare", ["--indicator", "growth_exponent"], ["--indicator", "growth"], "indicator", "growth_exponent"),
]



@pytest.mark.parametrize("command, old, new, dest, value", ALIASES)
def test_old_spellings_work_with_one_deprecation_line(command, old, new, dest, value, capsys):
    parser = cli.build_parser()
    a_new = parser.parse_args([command, *new])
    assert capsys.readouterr().err == ""
    a_old = parser.parse_args([command, *old])
    err = capsys.readouterr().err
    assert getattr(a_old, dest) == getattr(a_new, dest) == value
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "deprecated" in lines[0] and new[-2] in lines[0], err
    # the same namespace, apart from the bookkeeping of which options were given
    strip = {k: v for k, v in vars(a_old).items() if k != "_given"}
    assert strip == {k: v for k, v in vars(a_new).items() if k != "_given"}


def test_old_and_new_spelling_together_is_an_error(capsys):
    with pytest.raises(cli.UsageError, match="given twice"):
        cli.build_parser().parse_args(["poincare", "--panel", "4a", "--figure", "4b"])


def test_old_spellings_are_hidden_from_help():
    text = SUBS["poincare"].format_help()
    assert "--panel" in text and "--workers" in text and "--figure" not in text and "--threads" not in text
    assert "growth_exponent" not in text


def test_bad_indicator_is_one_line_naming_it(capsys):
    assert cli.main(["poincare", "--panel", "4a", "--indicator", "growthh"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "indicator" in err[0], err


@pytest.mark.parametrize("name", list(SUBS))
def test_an_option_is_stored_under_its_own_name(name):
    """The namespace key of --panel is "panel" and of --workers "workers", so that an error about the value names
    the option the user typed (issue 25: poincare/orbitdiagram/spectrum stored --panel as "figure" and --threads as
    "workers", and a bad --panel said "figure: ...").  Seen to fail before the rename."""
    bad = [f"{a.option_strings[0]} -> {a.dest}" for a in _visible(SUBS[name])
           if a.option_strings and a.option_strings[0] in ("--panel", "--workers", "--pulses")
           and a.dest != a.option_strings[0][2:]]
    assert not bad, bad


@pytest.mark.parametrize("argv, name", [(["poincare", "--panel", "9z"], "panel"),
                                        (["orbitdiagram", "--parameter", "lam", "--values", "0.1:0.2:3", "--panel",
                                          "9z"], "panel"),
                                        (["spectrum", "--panel", "9z"], "panel"),
                                        (["orbitdiagram", "--parameter", "lam", "--values", "0.1:0.2:3",
                                          "--workers", "0"], "workers")])
def test_a_bad_value_names_the_option_typed(argv, name, capsys):
    assert cli.main([*argv, "--json"]) == 2
    import json

    assert json.loads(capsys.readouterr().out)["parameter"] == name
