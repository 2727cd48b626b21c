"""The proofs' design and search scripts (research/): each compiles and has its README entry; the cheap diagnosis
runs (--smoke).  The designs themselves are minutes each and are not run here."""
from __future__ import annotations

import py_compile
import subprocess
import sys
from pathlib import Path

import pytest

RESEARCH = Path(__file__).parents[1] / "research"
SCRIPTS = sorted(p.stem for p in RESEARCH.glob("*.py"))


def test_the_design_scripts_moved_out_of_benchmarks():
    bench = {p.stem for p in (RESEARCH.parent / "benchmarks").glob("*.py")}
    assert len(SCRIPTS) >= 10 and not bench & set(SCRIPTS), bench & set(SCRIPTS)


@pytest.mark.parametrize("name", SCRIPTS)
def test_each_script_compiles_and_has_its_readme_entry(name, tmp_path):
    py_compile.compile(str(RESEARCH / f"{name}.py"), cfile=str(tmp_path / f"{name}.pyc"), doraise=True)
    readme = (RESEARCH / "README.md").read_text()
    assert f"## `{name}.py`" in readme and f"python research/{name}.py" in readme, name


def test_horseshoe_margins_runs(tmp_path):
    p = subprocess.run([sys.executable, str(RESEARCH / "horseshoe_margins.py"), "--smoke"], cwd=tmp_path,
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    assert not list(tmp_path.iterdir())  # a smoke run writes nothing where it is run
