"""Run every benchmark script once on a tiny span (`--smoke`), each in its own process, and fail if one does not
run: a benchmark that no longer runs fails CI (.ci/run).  Prints each script's wall time.

    python benchmarks/smoke.py            # every script of SMOKE
    python benchmarks/smoke.py NAME ...   # only these (file names without .py)

Scripts not in SMOKE are listed in NOT_SMOKED with the reason; tests/test_benchmarks.py checks that every script
of benchmarks/ is in exactly one of the two, and that each script of SMOKE takes --smoke."""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

# script -> extra arguments of its smoke run (besides --smoke)
SMOKE = {
    "poincare_vs_peers": [],
    "chaos_vs_peers": [],
    "work_precision": [],
    "classification_precision": [],
    "batch_ratios": [],
    "batch_scaling": [],
    "batch_sections": [],
    "chaos_throughput": [],
    "early_exit": [],
    "refine_vs_brute": [],
    "propagate_threads": [],
    "first_integrals": [],
    "models": [],
    "continuation_branch": [],
    "enclosure_outward": [],
    "prove_target": [],
    "enclosure_boxes": [],
    "centre_flight_frontier": [],
    "enclosure_corner": [],
    "decided_costs": [],
    "reproduce_time": [],
    "reprove_fig4a_taylor_model": [],
    "stretch_sampler": [],
}

# script -> why it has no smoke run here (the proofs' design and search scripts are in research/, research/README.md)
NOT_SMOKED: dict = {}

TIMEOUT_S = 600


def run(names=None) -> int:
    names = list(names or SMOKE)
    bad = []
    t_all = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="magrod-smoke-") as cwd:  # a script that writes anyway writes here
        for name in names:
            t0 = time.perf_counter()
            try:
                p = subprocess.run([sys.executable, str(HERE / f"{name}.py"), "--smoke", *SMOKE[name]], cwd=cwd,
                                   capture_output=True, text=True, timeout=TIMEOUT_S,
                                   env={**os.environ, "PYTHONWARNINGS": "ignore", "MPLBACKEND": "Agg"})
                rc, tail = p.returncode, (p.stderr or p.stdout)[-2000:]
            except subprocess.TimeoutExpired:
                rc, tail = "timeout", f"no exit within {TIMEOUT_S} s"
            wall = time.perf_counter() - t0
            print(f"{name:28s} {'ok' if rc == 0 else 'FAILED'} {wall:6.1f} s", flush=True)
            if rc != 0:
                bad.append(name)
                print(tail, flush=True)
    print(f"{len(names) - len(bad)} of {len(names)} benchmark scripts ran in {time.perf_counter() - t_all:.0f} s"
          + (f"; FAILED: {', '.join(bad)}" if bad else ""))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(run(sys.argv[1:]))
