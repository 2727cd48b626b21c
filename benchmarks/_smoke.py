"""`--smoke`: a benchmark script runs once on a tiny span, measures nothing and writes nothing (benchmarks/smoke.py
runs every script so; CI fails when one no longer runs).  A script calls `enable()` when given --smoke (or
`from_argv()` if it has no argument parser) and sizes its runs with `n(full, tiny)`."""
from __future__ import annotations

import sys

FLAG = "--smoke"
HELP = "run once on a tiny span (benchmarks/smoke.py, CI): measures nothing, writes nothing"
ON = False


def enable(on: bool = True) -> bool:
    global ON
    ON = bool(on)
    return ON


def from_argv() -> bool:
    """enable() if --smoke is among the script's arguments, and remove it from sys.argv."""
    if FLAG in sys.argv[1:]:
        sys.argv[:] = [a for a in sys.argv if a != FLAG]
        return enable()
    return ON


def n(full, tiny):
    """`tiny` in a smoke run, else `full`."""
    return tiny if ON else full
