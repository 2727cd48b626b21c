"""One CLI vocabulary (issue 29): every parser is walked.  Every option has help, its default is stated at most
once, one name per concept in every command (--panel for a paper panel, --threads for threads, --workers only
for processes, one spelling of the indicators, one text for --root), and the old spellings still work, with one
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
    """A paper panel is --panel, threads are --threads, --workers only counts processes (chaosmap's Dask
    workers), the indicators have one spelling and --root one help text.  Seen to fail before (poincare and
    orbitdiagram took --figure PANEL and --workers meaning threads; poincare spelt growth_exponent)."""
    bad = []
    indicator_sets = {}
    for name, p in SUBS.items():
        for a in _visible(p):
            opts = set(a.option_strings)
            if a.metavar == "PANEL" and "--panel" not in opts:
                bad.append(f"{name} {opts}: a panel option not called --panel")
            if "--workers" in opts and "process" not in (a.help or "").lower():
                bad.append(f"{name} --workers does not count processes: threads are --threads")
            if "--threads" in opts and "thread" not in (a.help or "").lower():
                bad.append(f"{name} --threads does not count threads")
            if "--root" in opts and a.help not in (options.ROOT_HELP, options.ROOT_INDEX_HELP):
                bad.append(f"{name} --root: its own help text {a.help!r}")
            if "--indicator" in opts:
                choices = a.choices or set(re.findall(r"\w+", a.metavar or ""))
                indicator_sets[name] = set(choices) - {"none"}
    spellings = {frozenset(v) for v in indicator_sets.values()}
    assert len(spellings) == 1, indicator_sets
    assert spellings == {frozenset(options.INDICATORS)}, spellings
    assert not bad, bad


# (command, old argv, new argv, the dest both must set to the same value)
ALIASES = [
    ("poincare", ["--figure", "4a"], ["--panel", "4a"], "panel", "4a"),
    ("orbitdiagram", ["--parameter", "lam", "--values", "0.1:0.2:3", "--figure", "5a"],
     ["--parameter", "lam", "--values", "0.1:0.2:3", "--panel", "5a"], "panel", "5a"),
    ("poincare", ["--workers", "3"], ["--threads", "3"], "threads", "3"),
    ("orbitdiagram", ["--parameter", "lam", "--values", "0.1:0.2:3", "--workers", "2"],
     ["--parameter", "lam", "--values", "0.1:0.2:3", "--threads", "2"], "threads", "2"),
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
    assert "--panel" in text and "--threads" in text and "--figure" not in text and "--workers" not in text
    assert "growth_exponent" not in text


def test_bad_indicator_is_one_line_naming_it(capsys):
    assert cli.main(["poincare", "--panel", "4a", "--indicator", "growthh"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "indicator" in err[0], err


@pytest.mark.parametrize("name", list(SUBS))
def test_an_option_is_stored_under_its_own_name(name):
    """The namespace key of --panel is "panel" and of --threads "threads", so that an error about the value names
    the option the user typed (issue 25: poincare/orbitdiagram/spectrum stored --panel as "figure" and --threads as
    "workers", and a bad --panel said "figure: ...").  Seen to fail before the rename."""
    bad = [f"{a.option_strings[0]} -> {a.dest}" for a in _visible(SUBS[name])
           if a.option_strings and a.option_strings[0] in ("--panel", "--threads")
           and a.dest != a.option_strings[0][2:]]
    assert not bad, bad


@pytest.mark.parametrize("argv, name", [(["poincare", "--panel", "9z"], "panel"),
                                        (["orbitdiagram", "--parameter", "lam", "--values", "0.1:0.2:3", "--panel",
                                          "9z"], "panel"),
                                        (["spectrum", "--panel", "9z"], "panel"),
                                        (["orbitdiagram", "--parameter", "lam", "--values", "0.1:0.2:3",
                                          "--threads", "0"], "threads")])
def test_a_bad_value_names_the_option_typed(argv, name, capsys):
    assert cli.main([*argv, "--json"]) == 2
    import json

    assert json.loads(capsys.readouterr().out)["parameter"] == name
