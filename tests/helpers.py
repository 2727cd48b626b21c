"""What many test modules need, written once (issue 25: the subprocess runner of the CLI was written five times,
`_free_port` and `_tree` twice each).  Imported as `from helpers import ...` (pytest puts tests/ on sys.path)."""
from __future__ import annotations

import os
import socket
import subprocess
import sys
import tempfile
from pathlib import Path


def run_cli(*argv, timeout: float = 600, env: dict | None = None, quiet_warnings: bool = False, cwd=None,
            **kw) -> subprocess.CompletedProcess:
    """`python -m magrod.cli ARGV` in a subprocess, text mode, stdout and stderr captured (unless `stdout`/`stderr`
    are given), in a directory outside the repository (the checkout's magrod/ would shadow the installed package).
    env: added to the environment; quiet_warnings: PYTHONWARNINGS=ignore (for tests that count stderr lines of a
    command whose libraries may warn); other keywords go to subprocess.run (preexec_fn, ...)."""
    full_env = {**os.environ, **(env or {})}
    if quiet_warnings:
        full_env["PYTHONWARNINGS"] = "ignore"
    if "stdout" not in kw and "stderr" not in kw:
        kw["capture_output"] = True
    elif "stderr" not in kw:
        kw["stderr"] = subprocess.PIPE
    return subprocess.run([sys.executable, "-m", "magrod.cli", *argv], text=True, timeout=timeout,
                          cwd=cwd or tempfile.gettempdir(), env=full_env, **kw)


def free_port() -> int:
    """A TCP port free on the loopback interface now (bound and released: the tests talk only to 127.0.0.1)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def tree(root: Path) -> set:
    """Every path under root, relative: what a refused command must leave unchanged."""
    return {str(p.relative_to(root)) for p in Path(root).rglob("*")}


def one_line(err: str) -> list:
    """The non-empty lines of stderr, asserted to be exactly one and no traceback."""
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines


def shift_set_along_entry(cert: dict, i: int, k: int = 3) -> dict:
    """A copy of a horseshoe certificate with the centre of N_i moved by k of its entry half-widths (the second
    column of its A): the shifted-set control of the section provers (tests/test_proof_horseshoe.py, _fig5.py)."""
    import copy
    from fractions import Fraction

    c = copy.deepcopy(cert)
    cN = [Fraction(v) for v in c["sets"][i]["c"]]
    A = [[Fraction(v) for v in r] for r in c["sets"][i]["A"]]
    c["sets"][i]["c"] = [str(cN[0] + k * A[0][1]), str(cN[1] + k * A[1][1])]
    return c


def verify_cli(cert: dict, tmp_path, capsys, *extra) -> tuple:
    """`magrod prove --verify` on the certificate dict (written to tmp_path/c.json): (exit code, stdout, stderr
    lines)."""
    import json

    from magrod.cli import main

    p = Path(tmp_path) / "c.json"
    p.write_text(json.dumps(cert))
    code = main(["prove", "--verify", str(p), *extra])
    cap = capsys.readouterr()
    return code, cap.out, cap.err.strip().splitlines()


def assert_rejected(cert: dict, tmp_path, capsys, check: str) -> None:
    """The verifier rejects the certificate: exit 1, one stderr line "certificate rejected: ..." naming `check`."""
    code, _, err = verify_cli(cert, tmp_path, capsys)
    assert code == 1 and len(err) == 1 and "certificate rejected" in err[0] and check in err[0], (code, err)
