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


@pytest.mark.parametrize("mixed", [False, True])
def test_section_second_derivative_against_a_closed_form(mixed):
    """research/horseshoe_second_order.py's second derivative of a section point, d^2/ds^2 and the mixed d^2/da ds,
    by implicit differentiation at the crossing, on a field whose flow has a closed form and whose crossing time
    moves with both parameters: theta' = lam theta, psi' = 1 + theta^2, pbar_theta' = theta, pbar_psi' = 0,
    lam' = 0, started at (a0 + a + s, 0.1, b + 2 a, 0, l + s); the section psi = 2 pi.  Reference: the crossing time
    by findroot and P(a, s) differentiated by mpmath at 40 digits (a second, independent method)."""
    import mpmath as mp
    from flint import arb, arb_mat

    sys.path.insert(0, str(RESEARCH))
    try:
        import horseshoe_second_order as hso
    finally:
        sys.path.remove(str(RESEARCH))
    mp.mp.dps = 40
    a0, b, l = mp.mpf("0.3"), mp.mpf("-0.2"), mp.mpf("0.7")

    def flow(t, a, s):
        th0, lam = a0 + a + s, l + s
        e = mp.exp(lam * t)
        return [th0 * e, mp.mpf("0.1") + t + th0**2 * (e**2 - 1) / (2 * lam), b + 2 * a + th0 * (e - 1) / lam, 0, lam]

    def P(a, s):
        t = mp.findroot(lambda t: flow(t, a, s)[1] - 2 * mp.pi, 5)
        x = flow(t, a, s)
        return [x[0], x[2]]

    t0 = mp.findroot(lambda t: flow(t, 0, 0)[1] - 2 * mp.pi, 5)
    x = flow(t0, 0, 0)
    u = [mp.diff(lambda s, i=i: flow(t0, 0, s)[i], 0) for i in range(5)]
    ua = [mp.diff(lambda a, i=i: flow(t0, a, 0)[i], 0) for i in range(5)] if mixed else None
    if mixed:
        dus = [mp.diff(lambda a, s, i=i: flow(t0, a, s)[i], (0, 0), (1, 1)) for i in range(5)]
        want = [mp.diff(lambda a, s, k=k: P(a, s)[k], (0, 0), (1, 1)) for k in (0, 1)]
    else:
        dus = [mp.diff(lambda s, i=i: flow(t0, 0, s)[i], 0, 2) for i in range(5)]
        want = [mp.diff(lambda s, k=k: P(0, s)[k], 0, 2) for k in (0, 1)]
    f = [x[4] * x[0], 1 + x[0] ** 2, x[0], 0, 0]
    Df = [[x[4], 0, 0, 0, x[0]], [2 * x[0], 0, 0, 0, 0], [1, 0, 0, 0, 0], [0] * 5, [0] * 5]

    def ar(v):
        return arb(mp.nstr(v, 40))

    P2, _ = hso.section_second_derivative([ar(v) for v in x], [ar(v) for v in u], [ar(v) for v in dus],
                                          [ar(v) for v in f], arb_mat([[ar(v) for v in row] for row in Df]),
                                          ua=None if ua is None else [ar(v) for v in ua])
    for got, w in zip(P2, want):
        assert abs(float(got.mid()) - float(w)) <= 1e-12 * abs(float(w)) and abs(float(w)) > 1e-2
