"""The CLI contract under bad input and faults (issue 17; grouped by what they test in issue 25).

Every case asserts: the exit code (2 bad input, 3 environment fault, 1 failed computation, 130 interrupted),
exactly one non-empty stderr line naming the parameter, no traceback, exactly one JSON object on stdout under
--json, and that no file or directory appeared.  The table-driven battery runs in-process (cli.main); the
fault cases that need a real process (closed pipe, file-size limit, kill -9, Ctrl-C, JIT cache trouble) run as
subprocesses."""
import json
import os
import resource
import signal
import sqlite3
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

from helpers import one_line, run_cli, tree
from magrod import cli

P4 = ["--mu", "0.4", "--gamma", "3", "--delta", "3", "--lam", "0.135", "--h", "0.9", "--theta0", "0.1",
      "--ptheta0", "0.5", "--iterates", "10"]
M6 = ["--m", "1.7", "--gamma", "1", "--delta", "1", "--lam", "0.001", "--mu", "0.002"]


def _write_orbit_file(path: Path, kind: str) -> str:
    """Damaged orbit files for `magrod rod --from`."""
    if kind == "empty":
        path.write_bytes(b"")
    elif kind == "text":
        path.write_text("not an npz\n")
    else:
        n = 50
        t = np.linspace(0.0, 10.0, n)
        d = {"x0": np.zeros(9), "T": np.array(5.0), "pars": np.array([1.7, 0.002, 1.0, 1.0, 0.001]), "t": t,
             "tau": np.linspace(-2, 2, n), "x": np.zeros((n, 9))}
        if kind == "nan":
            d["x"][:] = np.nan
        if kind == "missing":
            d.pop("tau")
        if kind == "pars":
            d["pars"] = np.array([-1.7, 0.002, 1.0, 1.0, 0.001])
        np.savez(path, **d)
        if kind == "truncated":
            data = path.read_bytes()
            path.write_bytes(data[: len(data) // 2])
    return str(path)


# (argv, parameter named in the error, exit code); "{tmp}" is replaced by the case's temporary directory,
# "{orbit:KIND}" by a damaged orbit file made there before the run.
BATTERY = [
    # --- check: the substitution grammar (no code execution) and option conflicts
    (["check", "--subs", 'B1=__import__("os").system("id")'], "subs", 2),
    (["check", "--subs", "c_H=open('/etc/hostname').read().__len__()"], "subs", 2),
    (["check", "--subs", "B1=9**9**9"], "subs", 2),
    (["check", "--subs", "x=1"], "subs", 2),
    (["check", "--subs", ""], "subs", 2),
    (["check", "--subs", "B1="], "subs", 2),
    (["check", "--subs", "B1=1/0"], "subs", 2),
    (["check", "--subs", "B1=(lambda: 1)()"], "subs", 2),
    (["check", "--subs", "B1=B2.__class__"], "subs", 2),
    (["check", "--subs", "B1=[1]*10**9"], "subs", 2),
    (["check", "--subs", "B2=B1", "--rederive"], "subs", 2),
    (["check", "--bogus"], "bogus", 2),
    (["check", "extra"], "extra", 2),
    # --- argparse errors on the common path
    (["nosuch"], "command", 2),
    ([], "command", 2),
    (["poincare", "--panel", "4a", "--direction", "up"], "direction", 2),
    (["poincare", "--panel", "4a", "--branch", "2"], "branch", 2),
    (["poincare", "--panel", "4a", "--formulation", "x"], "formulation", 2),
    (["poincare", "--panel", "4a", "--m"], "m", 2),
    (["melnikov", "--m", "1.7", "--gamma", "1", "--integrand", "x"], "integrand", 2),
    (["multipulse", "--panel", "8"], "panel", 2),
    (["multipulse", "--panel", "x"], "panel", 2),
    (["multipulse", "--panel", "6", "--free", "mu"], "free", 2),
    (["homoclinic"], "m", 2),
    (["rod"], "from", 2),
    (["figure"], "number", 2),
    # --- poincare: numbers, ranges, counts, paths
    (["poincare", "--m", "nan", *P4], "m", 2),
    (["poincare", "--m", "-1.7", *P4], "m", 2),
    (["poincare", "--m", "1e-320", *P4], "m", 2),
    (["poincare", "--m", "1e-4", *P4], "m", 2),
    (["poincare", "--panel", "4a", "--gamma", "1e308"], "gamma", 2),
    (["poincare", "--panel", "4a", "--lam", "inf"], "lam", 2),
    (["poincare", "--panel", "4a", "--mu", "abc"], "mu", 2),
    (["poincare", "--panel", "4a", "--h", "-50"], "h", 2),
    (["poincare", "--panel", "4a", "--theta0", "0"], "theta0", 2),
    (["poincare", "--panel", "4a", "--theta0", "4"], "theta0", 2),
    (["poincare", "--panel", "4a", "--delta", "-4"], "delta", 2),
    (["poincare", "--panel", "4a", "--iterates", "0"], "iterates", 2),
    (["poincare", "--panel", "4a", "--iterates", "-5"], "iterates", 2),
    (["poincare", "--panel", "4a", "--iterates", "2.5"], "iterates", 2),
    (["poincare", "--panel", "4a", "--iterates", "1e12"], "iterates", 2),
    (["poincare", "--panel", "4a", "--iterates", "abc"], "iterates", 2),
    (["poincare", "--panel", "4a", "--t-max", "0"], "t_max", 2),
    (["poincare", "--panel", "4a", "--t-max", "-1"], "t_max", 2),
    (["poincare", "--panel", "4a", "--t-max", "1e300"], "t_max", 2),
    (["poincare", "--panel", "4a", "--root", "5"], "root", 2),
    (["poincare", "--panel", "4a", "--root", "abc"], "root", 2),
    (["poincare", "--panel", "4a", "--ppsi0", "1.0", "--h", "0.9"], "ppsi0", 2),
    (["poincare", "--panel", "4a", "--ppsi0", "100"], "ppsi0", 2),
    (["poincare", "--panel", "9z"], "panel", 2),
    (["poincare", "--panel", "4a", "--stem", "../x", "--out", "{tmp}/o"], "stem", 2),
    (["poincare", "--panel", "4a", "--stem", "a/b", "--out", "{tmp}/o"], "stem", 2),
    (["poincare", "--panel", "4a", "--stem", ".hidden", "--out", "{tmp}/o"], "stem", 2),
    (["poincare", "--panel", "4a", "--stem", "x" * 300, "--out", "{tmp}/o"], "stem", 2),
    (["poincare", "--panel", "4a", "--stem", "x"], "stem", 2),
    (["poincare", "--panel", "4a", "--out", ""], "out", 2),
    (["poincare", "--panel", "4a", "--out", "/proc/magrod-test"], "out", 2),
    (["poincare", "--panel", "4a", "--out", "{tmp}/file"], "out", 2),
    (["poincare", "--panel", "4a", "--out", "{tmp}/" + "d" * 300], "out", 2),
    # without --panel the paper's Fig 4(a) gives what is not given (one default panel for every command)
    (["poincare", "--m", "1.7", "--mu", "0.4", "--gamma", "3", "--delta", "3", "--lam", "0.135", "--h", "0.9",
      "--theta0", "nan"], "theta0", 2),
    (["poincare", "--model", "nosuch"], "model", 2),
    (["saddle", "--model", "nosuch"], "model", 2),
    (["explore", "--model", "nosuch"], "model", 2),
    (["explore", "--model", "kirchhoff", "--panel", "4a"], "panel", 2),
    (["figure", "2", "--model", "kirchhoff"], "model", 2),  # the paper's own figures
    (["continue", "--model", "kirchhoff"], "free", 2),  # another model: its continuation parameter is required
    (["continue", "--model", "kirchhoff", "--free", "B", "--mu2lam"], "mu2lam", 2),
    (["splitting", "--model", "kirchhoff"], "model", 2),  # no small parameter: named
    (["homoclinic", "--model", "kirchhoff", "--m", "1.7"], "m", 2),
    (["orbitdiagram", "--model", "kirchhoff", "--parameter", "lam", "--values", "1,2"], "parameter", 2),
    (["rod", "--from", "x.npz", "--model", "kirchhoff"], "from", 2),
    # --- homoclinic
    (["homoclinic", "--m", "3", "--gamma", "1"], "m", 2),
    (["homoclinic", "--m", "1.7", "--gamma", "-1"], "gamma", 2),
    (["homoclinic", "--m", "inf", "--gamma", "1"], "m", 2),
    (["homoclinic", "--m", "1.7", "--gamma", "1", "--n", "2.5"], "n", 2),
    (["homoclinic", "--m", "1.7", "--gamma", "1", "--n", "1e12"], "n", 2),
    (["homoclinic", "--m", "1.7", "--gamma", "1", "--n", "1"], "n", 2),
    (["homoclinic", "--m", "1.7", "--gamma", "1", "--theta-stop", "0"], "theta_stop", 2),
    (["homoclinic", "--m", "1.7", "--gamma", "1", "--theta-stop", "5"], "theta_stop", 2),
    (["homoclinic", "--m", "1.7", "--gamma", "1", "--no-verify", "--n", "10"], "no_verify", 2),
    (["homoclinic", "--m", "1e-320", "--gamma", "1"], "m", 2),
    (["homoclinic", "--m", "1.7", "--gamma", "1e308"], "gamma", 2),
    # --- melnikov
    (["melnikov", "--m", "1.7", "--gamma", "nan"], "gamma", 2),
    (["melnikov", "--m", "5", "--gamma", "1"], "m", 2),
    (["melnikov", "--m", "1.7", "--gamma", "1", "--find-zero"], "gamma", 2),
    (["melnikov", "--m", "1.7", "--find-zero", "--bracket", "2", "1"], "bracket", 2),
    (["melnikov", "--m", "1.7", "--gamma", "1", "--bracket", "1", "2"], "bracket", 2),
    (["melnikov", "--m", "1.7", "--gamma", "1e308"], "gamma", 2),
    (["melnikov", "--m", "1.7"], "gamma", 2),
    # --- figure
    (["figure", "9"], "number", 2),
    (["figure", ""], "number", 2),
    (["figure", "2", "--out", "/proc/magrod-test"], "out", 2),
    (["figure", "2", "--out", ""], "out", 2),
    # --- multipulse
    (["multipulse", "--m", "3", "--gamma", "1", "--delta", "1", "--lam", "0.001", "--mu", "0.002",
      "--out", "{tmp}/o"], "m", 2),
    (["multipulse", "--panel", "6", "--pulses", "0", "--out", "{tmp}/o"], "pulses", 2),
    (["multipulse", "--panel", "6", "--pulses", "1e12", "--out", "{tmp}/o"], "pulses", 2),
    (["multipulse", "--panel", "6", "--samples", "1e12", "--out", "{tmp}/o"], "samples", 2),
    (["multipulse", "--panel", "6", "--samples", "2", "--out", "{tmp}/o"], "samples", 2),
    (["multipulse", "--panel", "6", "--span", "1.5", "--out", "{tmp}/o"], "span", 2),
    (["multipulse", "--panel", "6", "--span", "nan", "--out", "{tmp}/o"], "span", 2),
    (["multipulse", "--out", "{tmp}/o"], "panel", 2),
    (["multipulse", "--panel", "6", "--mu", "0.0019", "--out", "{tmp}/o"], "mu", 2),  # mu < 2 lam: no saddle
    (["multipulse", *M6, "--out", "/proc/magrod-test"], "out", 2),
    # --- rod: damaged input files
    (["rod", "--from", "{tmp}/missing.npz"], "from", 2),
    (["rod", "--from", "{orbit:empty}"], "from", 2),
    (["rod", "--from", "{orbit:text}"], "from", 2),
    (["rod", "--from", "{orbit:truncated}"], "from", 2),
    (["rod", "--from", "{orbit:nan}"], "from", 2),
    (["rod", "--from", "{orbit:missing}"], "from", 2),
    (["rod", "--from", "{orbit:pars}"], "from", 2),
    (["rod", "--from", "{orbit:good}", "--points", "1e12"], "points", 2),
    (["rod", "--from", "{orbit:good}", "--points", "1"], "points", 2),
    (["rod", "--from", "{orbit:good}", "--out", "/proc/magrod-test"], "out", 2),
    # --- reproduce
    (["reproduce", "--workers", "0", "--out", "{tmp}/o"], "workers", 2),
    (["reproduce", "--workers", "1e6", "--out", "{tmp}/o"], "workers", 2),
    (["reproduce", "--workers", "x", "--out", "{tmp}/o"], "workers", 2),
    (["reproduce", "--only", "", "--out", "{tmp}/o"], "only", 2),
    (["reproduce", "--only", "3,3", "--out", "{tmp}/o"], "only", 2),
    (["reproduce", "--only", "9", "--out", "{tmp}/o"], "only", 2),
    (["reproduce", "--out", ""], "out", 2),
    (["reproduce", "--out", "/proc/magrod-test"], "out", 2),
    # --- continue
    (["continue", "--pulses", "0", "--out", "{tmp}/o"], "pulses", 2),
    (["continue", "--pulses", "1e12", "--out", "{tmp}/o"], "pulses", 2),
    (["continue", "--steps", "1e12", "--out", "{tmp}/o"], "steps", 2),
    (["continue", "--ds", "2", "--out", "{tmp}/o"], "ds", 2),
    (["continue", "--range", "1", "0", "--out", "{tmp}/o"], "range", 2),
    (["continue", "--m", "3", "--out", "{tmp}/o"], "m", 2),
    (["continue", "--mu", "0.0019", "--out", "{tmp}/o"], "mu", 2),
    (["continue", "--mu2lam", "--mu", "0.002", "--out", "{tmp}/o"], "mu", 2),
    (["continue", "--free", "x", "--out", "{tmp}/o"], "free", 2),
    (["continue", "--out", "/proc/magrod-test"], "out", 2),
    # --- splitting
    (["splitting", "--a", "-1"], "a", 2),
    (["splitting", "--b", "-1"], "b", 2),
    (["splitting", "--a", "1", "--b", "1"], "a", 2),
    (["splitting", "--eps", "0"], "eps", 2),
    (["splitting", "--eps", ""], "eps", 2),
    (["splitting", "--eps", "0.1,nan"], "eps", 2),
    (["splitting", "--m", "3"], "m", 2),
    (["splitting", "--precision", "foo"], "precision", 2),
    (["splitting", "--precision", "long"], "precision", 2),  # the Precision values: "long double"
    (["splitting", "--a", "4", "--phases", "1e12"], "phases", 2),
    (["splitting", "--out", "/proc/magrod-test"], "out", 2),
    # --- chaosmap
    (["chaosmap", "--x", "bad", "--out", "{tmp}/o"], "x", 2),
    (["chaosmap", "--x", "lam:0:0.3:0", "--out", "{tmp}/o"], "x", 2),
    (["chaosmap", "--x", "lam:nan:1:4", "--out", "{tmp}/o"], "x", 2),
    (["chaosmap", "--y", "foo:0:1:4", "--out", "{tmp}/o"], "y", 2),
    (["chaosmap", "--x", "lam:0.3:0:4", "--out", "{tmp}/o"], "x", 2),
    (["chaosmap", "--x", "lam:0:1:1e6", "--out", "{tmp}/o"], "x", 2),
    (["chaosmap", "--t-max", "0", "--out", "{tmp}/o"], "t_max", 2),
    (["chaosmap", "--t-max", "-1", "--out", "{tmp}/o"], "t_max", 2),
    (["chaosmap", "--workers", "0", "--out", "{tmp}/o"], "workers", 2),
    (["chaosmap", "--scheduler", "nonsense", "--out", "{tmp}/o"], "scheduler", 2),
    (["chaosmap", "--panel", "9z", "--out", "{tmp}/o"], "panel", 2),
    (["chaosmap", "--stem", "../x", "--out", "{tmp}/o"], "stem", 2),
    (["chaosmap", "--out", "/proc/magrod-test"], "out", 2),
    (["chaosmap", "--out", "{tmp}/file"], "out", 2),  # --out is optional (default ./out), checked when given
    # --- chaosmap (issue 17): duplicate and conflicting options, impossible starts, what cannot finish, clusters
    (["chaosmap", "--x", "lam:0:1:4", "--x", "lam:0:1:5", "--out", "{tmp}/o"], "x", 2),
    (["chaosmap", "--stem", "a", "--stem", "b", "--out", "{tmp}/o"], "stem", 2),
    (["chaosmap", "--out", "{tmp}/o", "--out", "{tmp}/p"], "out", 2),
    (["chaosmap", "--t-max", "100", "--t-max", "200", "--out", "{tmp}/o"], "t_max", 2),
    (["chaosmap", "--lam", "0.5", "--x", "lam:0.1:0.2:4", "--out", "{tmp}/o"], "lam", 2),
    (["chaosmap", "--gamma", "3", "--out", "{tmp}/o"], "gamma", 2),  # the default --y varies gamma
    (["chaosmap", "--theta0", "0", "--out", "{tmp}/o"], "theta0", 2),
    (["chaosmap", "--theta0", "3.14159265358979", "--out", "{tmp}/o"], "theta0", 2),
    (["chaosmap", "--x", "theta0:0:1.5:4", "--out", "{tmp}/o"], "x", 2),
    (["chaosmap", "--y", "theta0:0.1:3.5:4", "--out", "{tmp}/o"], "y", 2),
    (["chaosmap", "--x", "delta:-3:-1:4", "--out", "{tmp}/o"], "delta", 2),
    (["chaosmap", "--renorm-dt", "1e-9", "--out", "{tmp}/o"], "renorm_dt", 2),
    (["chaosmap", "--renorm-dt", "2.3e-308", "--out", "{tmp}/o"], "renorm_dt", 2),
    (["chaosmap", "--renorm-dt", "2000", "--out", "{tmp}/o"], "renorm_dt", 2),
    (["chaosmap", "--renorm-dt", "0", "--out", "{tmp}/o"], "renorm_dt", 2),
    (["chaosmap", "--renorm-dt", "nan", "--out", "{tmp}/o"], "renorm_dt", 2),
    (["chaosmap", "--x", "lam:0:0.3:4096", "--y", "gamma:0:3:4096", "--out", "{tmp}/o"], "t_max", 2),
    (["chaosmap", "--x", "lam:0:0.3:1024", "--y", "gamma:0:3:1024", "--t-max", "1e5", "--out", "{tmp}/o"],
     "t_max", 2),
    (["chaosmap", "--workers", "64", "--out", "{tmp}/o"], "workers", 2),
    (["chaosmap", "--workers", str(len(os.sched_getaffinity(0)) + 1), "--out", "{tmp}/o"], "workers", 2),
    (["chaosmap", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1", "--out", "{tmp}/o"], "workers", 2),
    (["chaosmap", "--workers", "1", "--scheduler-file", "{tmp}/file", "--out", "{tmp}/o"], "workers", 2),
    (["chaosmap", "--scheduler", "127.0.0.1:1", "--scheduler-file", "{tmp}/file", "--out", "{tmp}/o"],
     "scheduler_file", 2),
    (["chaosmap", "--scheduler-file", "{tmp}/missing.json", "--out", "{tmp}/o"], "scheduler_file", 2),
    (["chaosmap", "--scheduler-file", "{tmp}/file", "--out", "{tmp}/o"], "scheduler_file", 2),  # not JSON
    (["chaosmap", "--scheduler", "inproc://x/1/2", "--out", "{tmp}/o"], "scheduler", 2),
    (["chaosmap", "--scheduler", "tls://127.0.0.1:1", "--out", "{tmp}/o"], "scheduler", 2),
    (["chaosmap", "--scheduler", "127.0.0.1:0", "--out", "{tmp}/o"], "scheduler", 2),
    (["chaosmap", "--scheduler", "tcp://127.0.0.1:1", "--out", "{tmp}/o"], "scheduler", 2),  # refused
    (["chaosmap", "--connect-timeout", "0", "--out", "{tmp}/o"], "connect_timeout", 2),
    (["chaosmap", "--worker-timeout", "-1", "--out", "{tmp}/o"], "worker_timeout", 2),
    (["chaosmap", "--out", "{tmp}/file/sub"], "out", 2),
]


def _expand(argv, tmp: Path):
    out = []
    for a in argv:
        if a.startswith("{orbit:"):
            kind = a[len("{orbit:"):-1]
            a = _write_orbit_file(tmp / f"orbit_{kind}.npz", kind)
        out.append(a.replace("{tmp}", str(tmp)))
    return out


_tree = tree

@pytest.mark.parametrize("argv,param,code", BATTERY,
                         ids=[f"{i:03d}-" + " ".join(a[:4])[:60] for i, (a, _, _) in enumerate(BATTERY)])
def test_battery(argv, param, code, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)  # default output directories ("out") would appear here
    (tmp_path / "file").write_text("occupied")
    args = _expand(argv, tmp_path)
    before = _tree(tmp_path)
    rc = cli.main(args + ["--json"])
    cap = capsys.readouterr()
    assert rc == code, cap
    obj = json.loads(cap.out)  # exactly one JSON object (json.loads refuses trailing data)
    assert obj["ok"] is False and param in str(obj["parameter"]), obj
    lines = [ln for ln in cap.err.splitlines() if ln.strip()]
    assert len(lines) == 1 and param.split("_")[0] in lines[0] and "Traceback" not in cap.err, cap.err
    assert _tree(tmp_path) == before  # no file, no directory


def test_battery_size():
    assert len(BATTERY) >= 80


def test_text_mode_errors_are_one_line_too(capsys):
    assert cli.main(["poincare", "--panel", "4a", "--direction", "up"]) == 2
    cap = capsys.readouterr()
    assert cap.out == "" and len(cap.err.strip().splitlines()) == 1 and "direction" in cap.err


# --------------------------------------------------------------------------------------------------------------
# the substitution grammar
@pytest.mark.parametrize("text", ["B2=B1,c_J=c_H", "B2=B1,c_J=c_H,lambda=0", "B2=B1,c_J=0,c_H=0,c_K=0",
                                  "B2=B1, c_J=c_H, lambda=0", "lambda=1/3", "B1=2.5*B2-(C+1)^2",
                                  "c_K=-0.25e0" if False else "c_K=-0.25", "B1=B2**2/B", "B1=B2,"])
def test_subs_accepts_the_documented_forms(text):
    from magrod.derive import poisson

    sub = poisson.parse_substitution(text)
    assert sub and all(str(k) in poisson.MODEL_SYMBOLS for k in sub)


def test_subs_values_are_exact():
    import sympy as sp

    from magrod.derive import poisson

    sub = poisson.parse_substitution("lambda=1/3, B1=2.5*B2 - (C+1)^2")
    S = poisson.MODEL_SYMBOLS
    assert sub[S["lambda"]] == sp.Rational(1, 3)
    assert sp.expand(sub[S["B1"]] - (sp.Rational(5, 2) * S["B2"] - (S["C"] + 1) ** 2)) == 0


@pytest.mark.parametrize("text", ['B1=__import__("os").system("id")', "B1=eval('1')", "B1=exec", "B1=1;B2=2",
                                  "B1=9**9**9", "B1=(B2+1)**100", "B1=B2**-9", "B1=1e5", "B1=0x10", "B1=1j",
                                  "B1=" + "(" * 40 + "1" + ")" * 40, "B1=" + "9" * 100, "B1=" + "B2*" * 20 + "B2",
                                  "B1=1/(B2-B2)", "B1", "=1", "B1==1", "B1=B2 B2", "B1=\u00b2", "B1=1" + " " * 2000])
def test_subs_refuses_code_and_unbounded_input(text):
    from magrod.derive import poisson
    from magrod.derive.substitution import SubstitutionError

    t0 = time.perf_counter()
    with pytest.raises(SubstitutionError):
        poisson.parse_substitution(text)
    assert time.perf_counter() - t0 < 1.0  # refused at once, never evaluated


def test_subs_injection_does_not_run(tmp_path, monkeypatch, capsys):
    marker = tmp_path / "pwned"
    monkeypatch.chdir(tmp_path)
    rc = cli.main(["check", "--json", "--subs", f'B1=__import__("os").system("touch {marker}")'])
    assert rc == 2 and not marker.exists()
    assert json.loads(capsys.readouterr().out)["parameter"] == "subs"


# --------------------------------------------------------------------------------------------------------------
# faults that need a real process
def magrod(*argv, env=None, preexec_fn=None, timeout=600, stdout=subprocess.PIPE, cwd=None):
    return run_cli(*argv, env=env, preexec_fn=preexec_fn, timeout=timeout, stdout=stdout, cwd=cwd)

_one_line = one_line

def test_closed_pipe_is_one_line():
    r_fd, w_fd = os.pipe()
    os.close(r_fd)  # the reader is gone before magrod writes
    try:
        r = magrod("check", "--json", stdout=w_fd)
    finally:
        os.close(w_fd)
    assert r.returncode == 3
    assert "pipe" in _one_line(r.stderr)[0]


def test_file_size_limit_is_an_environment_fault(tmp_path):
    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (2000, 2000))  # like `ulimit -f` (and a full disk: ENOSPC)

    out = tmp_path / "o"
    r = magrod("poincare", "--panel", "4a", "--iterates", "200", "--out", str(out), "--json", preexec_fn=limit)
    assert r.returncode == 3, r.stderr
    assert json.loads(r.stdout)["ok"] is False
    assert str(out) in _one_line(r.stderr)[0]
    assert not out.exists() or not [p for p in out.iterdir()]  # no partial file, no temporary left behind


def test_output_files_respect_the_umask(tmp_path):
    from magrod.core import io

    old = os.umask(0o022)
    try:
        p = io.atomic_write_text(tmp_path / "a.txt", "x")
    finally:
        os.umask(old)
    assert (p.stat().st_mode & 0o777) == 0o644


def test_unwritable_jit_cache_keeps_stdout_clean():
    r = magrod("poincare", "--panel", "4a", "--iterates", "5", "--json",
               env={"HEYOKA_CACHE_DIR": "/proc/magrod-no-cache"})
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout)["n_points"] == 5  # one JSON object, no heyoka warning mixed in
    assert "cache" in _one_line(r.stderr)[0]


def test_locked_jit_cache_does_not_stall(tmp_path):
    cache = tmp_path / "cache"
    assert magrod("poincare", "--panel", "4a", "--iterates", "2", "--json",
                  env={"HEYOKA_CACHE_DIR": str(cache)}).returncode == 0
    con = sqlite3.connect(cache / "cache.db", timeout=1)
    con.execute("BEGIN EXCLUSIVE")  # another process holds the database
    try:
        t0 = time.perf_counter()
        r = magrod("poincare", "--panel", "4a", "--iterates", "2", "--json", env={"HEYOKA_CACHE_DIR": str(cache)},
                   timeout=120)
        wall = time.perf_counter() - t0
    finally:
        con.rollback()
        con.close()
    assert r.returncode == 0 and json.loads(r.stdout)["n_points"] == 2
    assert "cache" in _one_line(r.stderr)[0]
    assert wall < 40  # heyoka alone would wait ~60 s for the lock


def test_damaged_jit_cache_is_switched_off_with_one_line(tmp_path):
    """A cache database whose index is out of step with its table (found on a machine whose cache was restored
    while its write-ahead log was open): heyoka would fail every lookup and compile each integrator; the probe
    finds it by sqlite's integrity check and runs without the cache, one stderr line naming it, stdout clean."""
    cache = tmp_path / "cache"
    assert magrod("poincare", "--panel", "4a", "--iterates", "2", "--json",
                  env={"HEYOKA_CACHE_DIR": str(cache)}).returncode == 0
    con = sqlite3.connect(cache / "cache.db")
    con.execute("PRAGMA writable_schema = ON")  # the index now claims another column than it holds
    con.execute("UPDATE sqlite_master SET sql = 'CREATE INDEX idx_last_access ON cache(size)' "
                "WHERE name = 'idx_last_access'")
    con.commit()
    con.close()
    r = magrod("poincare", "--panel", "4a", "--iterates", "2", "--json", env={"HEYOKA_CACHE_DIR": str(cache)})
    assert r.returncode == 0 and json.loads(r.stdout)["n_points"] == 2
    line = _one_line(r.stderr)[0]
    assert "cache" in line and "damaged" in line


def test_failed_accuracy_check_is_an_error_and_writes_nothing(tmp_path):
    """A result that does not meet its own accuracy checks (here: a tolerance no run can meet, standing in for a
    damaged integrator) is refused: exit 1, one line, ok false, no files; the run was repeated without the JIT
    cache first."""
    code = ("import sys; from magrod.chaos import section; section.ENERGY_TOL = 1e-300\n"
            "from magrod.cli import main; sys.exit(main(sys.argv[1:]))")
    out = tmp_path / "o"
    r = subprocess.run([sys.executable, "-c", code, "poincare", "--panel", "4a", "--iterates", "20", "--out",
                        str(out), "--json"], capture_output=True, text=True, cwd=tempfile.gettempdir(), timeout=600)
    assert r.returncode == 1, r.stderr
    obj = json.loads(r.stdout)
    assert obj["ok"] is False and obj["retried_without_jit_cache"] is True and "accuracy" in obj["error"]
    assert "accuracy" in _one_line(r.stderr)[0]
    assert not out.exists()


# --------------------------------------------------------------------------------------------------------------
# reproduce under faults
def _children(pid: int) -> list:
    try:
        out = subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True).stdout
    except FileNotFoundError:  # pragma: no cover - procps missing
        pytest.skip("pgrep not available")
    return [int(x) for x in out.split()]


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as fh:
            return fh.read().split()[2] != "Z"
    except OSError:
        return False


def _start_reproduce(out: Path, *extra):
    return subprocess.Popen([sys.executable, "-m", "magrod.cli", "reproduce", "--quick", "--out", str(out),
                             "--quiet", *extra], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=tempfile.gettempdir(), start_new_session=True)


def test_workers_die_with_their_parent(tmp_path):
    p = _start_reproduce(tmp_path / "o", "--only", "4,5", "--workers", "2", "--force")
    workers = []
    for _ in range(300):
        workers = [c for c in _children(p.pid) if _alive(c)]
        if len(workers) >= 2:
            break
        time.sleep(0.1)
    assert workers, "no worker processes appeared"
    os.kill(p.pid, signal.SIGKILL)
    p.wait(timeout=30)
    deadline = time.time() + 15
    while time.time() < deadline and any(_alive(w) for w in workers):
        time.sleep(0.2)
    assert not any(_alive(w) for w in workers)


def _start_paused(out: Path, marker: Path, point: str, *extra):
    """reproduce with the test hook MAGROD_TEST_PAUSE: it writes `marker` on reaching `point` and waits there."""
    return subprocess.Popen([sys.executable, "-m", "magrod.cli", "reproduce", "--quick", "--out", str(out),
                             "--quiet", *extra], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            cwd=tempfile.gettempdir(), start_new_session=True,
                            env={**os.environ, "MAGROD_TEST_PAUSE": f"{point}:{marker}"})


def _wait_for(marker: Path, p, timeout=300):
    deadline = time.time() + timeout
    while not marker.exists() and time.time() < deadline and p.poll() is None:
        time.sleep(0.02)
    assert marker.exists(), p.communicate()


@pytest.mark.parametrize("sig,code", [(signal.SIGINT, 130), (signal.SIGTERM, 143), (signal.SIGHUP, 129)],
                         ids=["SIGINT", "SIGTERM", "SIGHUP"])
def test_ctrl_c_exits_130_with_one_line(tmp_path, sig, code):
    """Deterministic: the signal is sent while both workers are running figures (the test hook says when), to the
    whole process group as a terminal does.  One line, exit 128 + signum, workers gone, no temporary left."""
    marker = tmp_path / "running"
    p = _start_paused(tmp_path / "o", marker, "reproduce-running", "--only", "4,5", "--workers", "2", "--force")
    _wait_for(marker, p)
    workers = [c for c in _children(p.pid) if _alive(c)]
    os.killpg(p.pid, sig)
    t0 = time.time()
    out, err = p.communicate(timeout=60)
    assert p.returncode == code, err
    assert time.time() - t0 < 20
    assert "interrupted" in _one_line(err)[0] and signal.Signals(sig).name in err
    deadline = time.time() + 15
    while time.time() < deadline and any(_alive(w) for w in workers):
        time.sleep(0.1)
    assert workers and not any(_alive(w) for w in workers)
    leftovers = [q for q in (tmp_path / "o").rglob("*.tmp")] if (tmp_path / "o").exists() else []
    assert not leftovers


# the resume, stamp, lock and signal tests run the cheapest paper figure (Fig 2, ~7 s quick; Fig 3 took ~11 s and
# is recomputed by nine of these tests): what they test is the reproduce machinery, the same for every figure
FIG = "2"


@pytest.fixture(scope="module")
def fig_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("repro")
    assert cli.main(["reproduce", "--quick", "--only", FIG, "--out", str(out), "--quiet"]) == 0
    return out


def _skipped(out, capsys) -> bool:
    assert cli.main(["reproduce", "--quick", "--only", FIG, "--out", str(out), "--json"]) == 0
    return json.loads(capsys.readouterr().out)["figures"][FIG]["skipped"]


def test_resume_verifies_content_hashes(fig_run, capsys):
    out = fig_run
    assert _skipped(out, capsys) is True
    npz = out / "fig2.npz"
    npz.write_bytes(npz.read_bytes()[:100])  # truncated, stamp still there
    assert _skipped(out, capsys) is False  # recomputed
    assert _skipped(out, capsys) is True


@pytest.mark.parametrize("content", ["[]", "null", "{}", "{\"files\": 3}", "not json", ""])
def test_bad_stamps_are_recomputed_not_tracebacks(fig_run, capsys, content):
    stamp = fig_run / ".state" / "figure_2.json"
    stamp.write_text(content)
    assert _skipped(fig_run, capsys) is False
    assert json.loads(stamp.read_text())["files"]  # a good stamp again


def test_concurrent_run_into_one_directory_is_refused(fig_run, capsys):
    import fcntl

    with open(fig_run / ".state" / "lock", "a+") as fh:
        fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
        rc = cli.main(["reproduce", "--quick", "--only", FIG, "--out", str(fig_run), "--json"])
    cap = capsys.readouterr()
    assert rc == 3 and json.loads(cap.out)["parameter"] == "out"
    assert "another magrod reproduce" in _one_line(cap.err)[0]


def test_signal_after_the_result_was_printed_changes_nothing(fig_run, tmp_path):
    """Ctrl-C (or SIGTERM) just after the result was printed: the process ends quietly with the result's own exit
    code (0 here), the JSON on stdout is whole, nothing on stderr, no KeyboardInterrupt at shutdown."""
    for sig in (signal.SIGINT, signal.SIGTERM):
        marker = tmp_path / f"printed-{sig}"
        p = subprocess.Popen([sys.executable, "-m", "magrod.cli", "reproduce", "--quick", "--only", FIG, "--workers",
                              "2", "--out", str(fig_run), "--json"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, cwd=tempfile.gettempdir(), start_new_session=True,
                             env={**os.environ, "MAGROD_TEST_PAUSE": f"printed:{marker}"})
        _wait_for(marker, p)
        os.killpg(p.pid, sig)
        out, err = p.communicate(timeout=60)
        assert p.returncode == 0 and err.strip() == "", err
        assert json.loads(out)["ok"] is True


def test_a_killed_run_leaves_no_temporary_behind(fig_run):
    """kill -9 cannot clean up: the temporary a killed writer left (its pid is dead) is removed by the next run,
    a live writer's is not."""
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                          text=True).stdout.strip()
    live = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])
    try:
        stale = fig_run / f".fig2.npz.{dead}.k9k9k9k9.tmp"
        kept = fig_run / f".fig2.png.{live.pid}.abcdefgh.tmp"
        stale.write_bytes(b"half")
        kept.write_bytes(b"being written")
        assert cli.main(["reproduce", "--quick", "--only", FIG, "--out", str(fig_run), "--quiet"]) == 0
        assert not stale.exists() and kept.exists()
    finally:
        live.kill()
        live.wait()
        kept.unlink(missing_ok=True)


# resource limits: exit 3, one line naming the limit or the path, nothing left behind
CHAOS_SMALL = ["chaosmap", "--x", "lam:0.12:0.2:4", "--y", "gamma:2:4:4", "--tile", "2", "--t-max", "50",
               "--workers", "1", "--json", "--quiet"]


def _rlimit(which, value):
    def f():
        resource.setrlimit(which, (value, value))
    return f


@pytest.mark.parametrize("case,limit,words", [
    ("ulimit -n 24", _rlimit(resource.RLIMIT_NOFILE, 24), "open-file limit"),
    ("ulimit -f 2", _rlimit(resource.RLIMIT_FSIZE, 2048), "file too large"),
    ("ulimit -v 1 GB", _rlimit(resource.RLIMIT_AS, 1 << 30), "memory"),
], ids=["nofile", "fsize", "address-space"])
def test_chaosmap_under_resource_limits(tmp_path, case, limit, words):
    out = tmp_path / "o"
    r = magrod(*CHAOS_SMALL, "--out", str(out), preexec_fn=limit, timeout=300)
    assert r.returncode == 3, r.stderr
    assert json.loads(r.stdout)["ok"] is False
    line = _one_line(r.stderr)[0]
    assert words in line, line
    if case == "ulimit -f 2":
        assert str(out) in line  # the path
    if case == "ulimit -v 1 GB":  # refused before any worker starts (and prints its own start-up traceback)
        assert "ulimit -v" in line and "1024 MB" in line, line
    assert not out.exists()  # nothing partial: no tile finished, so the store this run made is gone with OUT


def test_report_on_a_full_disk_is_one_line(fig_run):
    def limit():
        resource.setrlimit(resource.RLIMIT_FSIZE, (500, 500))  # REPORT.md is larger than this

    r = magrod("reproduce", "--quick", "--only", FIG, "--out", str(fig_run), "--json", preexec_fn=limit)
    assert r.returncode == 3, r.stderr
    assert "REPORT.md" in _one_line(r.stderr)[0]
    assert not list(fig_run.glob(".*.tmp"))
