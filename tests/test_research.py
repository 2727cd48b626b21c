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


def test_horseshoe_interval_limit_scales_as_a_smooth_map_must():
    """The quad-precision images of the interval horseshoe's link N12 => N13: the linear part is the design's
    (G_ss = 1/qs = 1/3, G_su ~ 0: the design maps frame to frame), the drift off the linear motion is second order in
    W (x 25 from 2e-11 to 1e-10) and the frames' shear first order (x 5) -- the measurement's own consistency."""
    import json
    from fractions import Fraction as F

    sys.path.insert(0, str(RESEARCH))
    try:
        import horseshoe_interval_limit as hil
    finally:
        sys.path.remove(str(RESEARCH))
    c = json.loads(hil.CERT.read_text())
    p = hil.fields.ExactParams(**{k: F(v) for k, v in c["params"].items()})
    P = hil.QuadMap(p, F(c["level"]))
    n12, n13 = hil._set(c["sets"][12]), hil._set(c["sets"][13])
    a, b = hil.measure(P, n12, n13, F(1, 50_000_000_000)), hil.measure(P, n12, n13, F(1, 10_000_000_000))
    assert abs(a["G_ss"] - 1 / 3) < 1e-9 and abs(a["G_su"]) < 1e-9
    assert b["drift"] / a["drift"] == pytest.approx(25, rel=0.05)
    assert b["shear"] / a["shear"] == pytest.approx(5, rel=0.05)
    assert a["dy_s_ds"] == pytest.approx(b["dy_s_ds"], rel=1e-6)
