"""Shared by the peer benchmarks: compile a JiTCODE module from any working directory.

JiTCODE's compile_C runs setuptools in the current directory, and setuptools then reads the pyproject.toml it
finds there.  Run from the repository root, that is magrod's own, whose `license = "MIT"` (PEP 639) the
setuptools in a venv may reject ("`project.license` must be valid exactly by one definition"), and the peer
benchmark crashed.  Compiling inside an empty temporary directory makes the peer independent of
where the benchmark is run from; the compiled module stays loaded after the directory is gone.
"""
from __future__ import annotations

import contextlib
import tempfile


def compile_c(ode, **kw) -> None:
    """ode.compile_C(**kw) with an empty temporary directory as the working directory."""
    with tempfile.TemporaryDirectory(prefix="magrod-peer-") as d, contextlib.chdir(d):
        ode.compile_C(**kw)
