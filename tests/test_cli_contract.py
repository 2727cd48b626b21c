"""CLI contract for every subcommand: --help, and the bad-input battery (exit code 2, one line on stderr naming
the parameter, no traceback, no file written).  Good-path --json shapes are tested in each capability's tests."""
import json
import os
import stat

import pytest

from helpers import run_cli
from magrod import cli

SUBCOMMANDS = list(cli.SUBCOMMANDS)  # every registered command, new ones included


def magrod(*argv, timeout=300):
    return run_cli(*argv, timeout=timeout, quiet_warnings=True)

@pytest.mark.parametrize("sub", SUBCOMMANDS)
def test_help(sub, capsys):
    with pytest.raises(SystemExit) as e:
        cli.main([sub, "--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    assert "--json" in out and "--quiet" in out
    # a default is stated where an option has one (the parser decides: a new command needs no entry here)
    import argparse

    sp = next(a for a in cli.build_parser()._actions if isinstance(a, argparse._SubParsersAction)).choices[sub]
    has_default = any(a.default not in (None, False, argparse.SUPPRESS) and a.help is not argparse.SUPPRESS
                      for a in sp._actions if a.option_strings and not isinstance(a, argparse._HelpAction))
    assert "default" in out.lower() or not has_default, sub


# (argv, the parameter the one-line error must name)
BAD = [
    (["poincare", "--m", "nan", "--mu", "0.4", "--gamma", "3", "--delta", "3", "--lam", "0.135", "--h", "0.9",
      "--theta0", "0.1", "--ptheta0", "0.5", "--iterates", "10"], "m"),
    (["poincare", "--m", "-1.7", "--mu", "0.4", "--gamma", "3", "--delta", "3", "--lam", "0.135", "--h", "0.9",
      "--theta0", "0.1", "--ptheta0", "0.5", "--iterates", "10"], "m"),
    (["poincare", "--panel", "4a", "--iterates", "0"], "iterates"),
    (["poincare", "--panel", "4a", "--iterates", "-5"], "iterates"),
    (["poincare", "--m", "1.7", "--mu", "0.4", "--gamma", "3", "--delta", "3", "--lam", "0.135", "--h", "-50",
      "--theta0", "0.1", "--ptheta0", "0.5", "--iterates", "10"], "h"),  # impossible energy level
    (["poincare", "--m", "1.7", "--mu", "0.4", "--gamma", "3", "--delta", "3", "--lam", "0.135", "--h", "0.9",
      "--theta0", "0", "--ptheta0", "0.5", "--iterates", "10"], "theta0"),  # singular start
    (["poincare", "--m", "1.7", "--mu", "0.4", "--gamma", "3", "--delta", "-4", "--lam", "0.135", "--h", "0.9",
      "--theta0", "0.1", "--ptheta0", "0.5", "--iterates", "10"], "delta"),  # unphysical
    (["homoclinic", "--m", "3", "--gamma", "1"], "m"),  # m >= m_c: no homoclinic orbit
    (["homoclinic", "--m", "1.7", "--gamma", "-1"], "gamma"),
    (["homoclinic", "--m", "inf", "--gamma", "1"], "m"),
    (["melnikov", "--m", "1.7", "--gamma", "nan"], "gamma"),
    (["melnikov", "--m", "5", "--gamma", "1"], "m"),
    (["figure", "9"], "number"),
    (["multipulse", "--m", "3", "--gamma", "1", "--delta", "1", "--lam", "0.001", "--mu", "0.002"], "m"),
    (["multipulse", "--panel", "6", "--pulses", "0"], "pulses"),
    (["rod", "--from", "/nonexistent/orbit.npz"], "from"),
    (["reproduce", "--workers", "0"], "workers"),
    (["check", "--subs", "x=1"], "subs"),
]


@pytest.mark.parametrize("argv,param", BAD, ids=[" ".join(a[:3]) + f" [{p}]" for a, p in BAD])
def test_bad_input(argv, param, tmp_path, capsys):
    out_dir = tmp_path / "out"
    extra = ["--out", str(out_dir)] if argv[0] in ("poincare", "figure", "multipulse", "rod", "reproduce") else []
    rc = cli.main(argv + extra + ["--json"])
    cap = capsys.readouterr()
    assert rc == 2, cap
    obj = json.loads(cap.out)  # exactly one JSON object even on error
    assert obj["ok"] is False and param in obj["parameter"]
    lines = [ln for ln in cap.err.splitlines() if ln.strip()]
    assert len(lines) == 1 and param in lines[0] and "Traceback" not in cap.err
    assert not out_dir.exists() or not any(out_dir.iterdir())  # no file written


@pytest.mark.skipif(os.geteuid() == 0, reason="root can write anywhere")
def test_unwritable_output_directory(tmp_path):  # pragma: no cover - CI runs as root here
    d = tmp_path / "ro"
    d.mkdir()
    d.chmod(stat.S_IRUSR | stat.S_IXUSR)
    r = magrod("poincare", "--panel", "4a", "--iterates", "5", "--out", str(d / "sub"))
    assert r.returncode == 2 and "out" in r.stderr


def test_output_path_is_a_file(tmp_path):
    """An --out that exists as a regular file cannot be used as a directory (works even as root)."""
    f = tmp_path / "occupied"
    f.write_text("x")
    r = magrod("poincare", "--panel", "4a", "--iterates", "5", "--out", str(f), "--json")
    assert r.returncode == 2, r.stderr
    assert json.loads(r.stdout)["parameter"] == "out"
    assert "Traceback" not in r.stderr


def test_json_mode_prints_one_object_and_progress_only_on_stderr():
    r = magrod("poincare", "--panel", "5a", "--iterates", "20", "--json")
    assert r.returncode == 0, r.stderr
    obj = json.loads(r.stdout)
    assert obj["n_points"] == 20 and "max_abs_dH" in obj
