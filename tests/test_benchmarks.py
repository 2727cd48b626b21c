"""Every benchmark script runs (benchmarks/smoke.py, a step of .ci/run): each script is either smoke-run with
--smoke or listed with the reason it is not, and the cheapest smoke runs are run here."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).parents[1] / "benchmarks"
sys.path.insert(0, str(BENCH))
import smoke  # noqa: E402  (benchmarks/smoke.py)

SCRIPTS = sorted(p.stem for p in BENCH.glob("*.py") if not p.stem.startswith("_") and p.stem != "smoke")


def test_every_script_is_smoke_run_or_says_why_not():
    listed = set(smoke.SMOKE) | set(smoke.NOT_SMOKED)
    assert not set(smoke.SMOKE) & set(smoke.NOT_SMOKED)
    assert sorted(listed) == SCRIPTS, (sorted(set(SCRIPTS) - listed), sorted(listed - set(SCRIPTS)))
    for name in smoke.SMOKE:
        text = (BENCH / f"{name}.py").read_text()
        assert "--smoke" in text or "_smoke" in text, name


def test_ci_runs_the_smoke_step():
    assert "benchmarks/smoke.py" in (BENCH.parent / ".ci" / "run").read_text()


@pytest.mark.parametrize("name", ["first_integrals", "enclosure_outward", "prove_target"])
def test_the_cheapest_benchmarks_run(name, tmp_path):
    p = subprocess.run([sys.executable, str(BENCH / f"{name}.py"), "--smoke"], cwd=tmp_path, capture_output=True,
                       text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    assert not list(tmp_path.iterdir())  # a smoke run writes nothing where it is run
