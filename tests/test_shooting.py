"""Shooting of symmetric homoclinic orbits (fig:multimodal1, fig:multimodal2)."""
import numpy as np
import pytest

from magrod.core.errors import ParameterError
from magrod.core.params import RodParams
from magrod.core.precision import Precision
from magrod.core.tolerances import FLOOR_CAP, FLOOR_FACTOR, LAUNCH_DISTANCE, SHOOTING_TOL
from magrod.orbits import multipulse, shooting
from magrod.orbits.equilibrium import on_level, straight_rod

EPS = np.finfo(float).eps
FIG6 = RodParams(1.7, 0.002, 1.0, 1.0, 0.001)


def test_primary_orbit_equals_closed_form():
    """lam = mu = 0: shooting (unknown T, condition pbar_theta = 0) vs the closed form of derive/homoclinic.py."""
    import heyoka as hy

    from magrod.generated import homoclinic

    p = RodParams(1.7, 0.0, 1.0, 1.0, 0.0)
    r = multipulse.shoot(p, 1, free=None)
    assert r.success and r.residual <= SHOOTING_TOL
    orb = multipulse.orbit(r)
    t, m, g = hy.make_vars("t", "m", "gamma")
    cf = hy.cfunc(homoclinic.closed_form(t, m, g), vars=[t, m, g])
    tt = orb["t"] - r.T
    win = orb["theta"] > 1e-3
    n = int(np.count_nonzero(win))
    vals = cf(np.vstack([tt[win], np.full(n, p.m), np.full(n, p.gamma)]))
    # the linear launch is off the manifold by O(eps^2); measured 3e-15 (cos) and 1.3e-13 (pbar_theta) at launch_distance=1e-7
    tol = 1e2 * r.launch_distance**2 + 1e3 * EPS
    np.testing.assert_allclose(np.cos(orb["theta"][win]), vals[0], atol=tol)
    np.testing.assert_allclose(orb["ptheta"][win], vals[1], atol=tol)
    assert np.max(np.abs(orb["H"] - r.saddle_H)) <= 64 * EPS


def test_phase_is_a_symmetry():
    # different launch phases on the unstable circle give the same reduced orbit (first crossing: double precision)
    assert shooting.phase_independence(straight_rod(FIG6), crossings=1, launch_distance=LAUNCH_DISTANCE[Precision.DOUBLE]) <= 1e-9


def test_two_pulse_orbit_reversible_and_on_level():
    res = multipulse.shoot(RodParams(1.7, 0.0025, 1.0, 1.0, 0.00125), 2)
    assert res.success and res.residual <= SHOOTING_TOL
    orb = multipulse.orbit(res)
    assert shooting.count_pulses(orb["theta"]) == 2
    assert abs(res.params.mu - 2 * res.params.lam) <= 4 * EPS * res.params.mu
    assert np.max(np.abs(orb["H"] - res.saddle_H)) <= 1e-13
    # reversibility: integrate the ODE past the symmetric point and compare with R applied to the first half
    from magrod.core import systems

    ta = systems.integrator("body")
    systems.reset(ta, res.x0, 0.0, res.params.array())
    s = np.linspace(res.T, res.T + 0.5 * res.T, 201)
    fwd = ta.propagate_grid(np.concatenate([[0.0], s]))[5][1:]
    back = multipulse.orbit(res, n=4001)
    mirrored = np.array([np.interp(s, back["t"], back["x"][:, i]) for i in range(9)]).T
    assert np.max(np.abs(fwd - mirrored)) <= 1e-6  # interpolation of the 4001-point orbit dominates (h^2 ~ 1e-4^2)


def test_eps_insensitivity():
    p = RodParams(1.7, 0.0025, 1.0, 1.0, 0.00125)
    a = multipulse.shoot(p, 2, launch_distance=1e-9)
    b = multipulse.shoot(p, 2, launch_distance=1e-8)
    assert a.success and b.success
    assert abs(a.params.lam - b.params.lam) <= 1e-9 * a.params.lam


def test_non_converged_returns_no_orbit():
    r = multipulse.shoot(RodParams(1.7, 0.0025, 1.0, 1.0, 0.00125), 2, max_iter=1, precision="double")
    assert not r.success and "not converged" in r.message and r.residual > SHOOTING_TOL
    with pytest.raises(ValueError):
        multipulse.orbit(r)


def test_bad_parameters():
    with pytest.raises(ParameterError) as e:
        straight_rod(RodParams(1.7, 0.5, 1.0, 1.0, 0.001))
    assert e.value.name == "mu"
    with pytest.raises(ParameterError) as e:
        straight_rod(RodParams(3.0, 0.0, 1.0, 1.0, 0.0))  # m >= m_c = 2 sqrt(2)
    assert e.value.name == "m"
    with pytest.raises(ParameterError):
        multipulse.shoot(FIG6, 2, free=None)


def test_cli_exit_codes(tmp_path):
    from magrod.cli import main

    # issue 13: mu != 2 lam is accepted (orbits to the periodic saddle); mu < 2 lam has no saddle near the rod
    assert main(["multipulse", "--panel", "6", "--mu", "0.0019", "--out", str(tmp_path / "x"), "--quiet"]) == 2
    assert not (tmp_path / "x").exists()


@pytest.mark.slow
def test_figures_full(tmp_path):
    from magrod.figures.multipulse import figure_6, figure_7

    paths6 = figure_6(tmp_path)
    paths7 = figure_7(tmp_path)
    assert any(p.endswith("figure6.png") for p in paths6) and any(p.endswith("figure7.png") for p in paths7)


def test_significant_digits_format():
    # the bracketed digit is the uncertainty of the last shown digit, rounded up
    assert multipulse.significant(0.0012620807954259, 3.3e-14) == "0.00126208079543(4)"
    assert multipulse.significant(0.40401385557147707, 2.07e-12) == "0.404013855571(3)"


def test_six_pulse_found_by_bisection_then_newton():
    """Issue 13 item 6: the Fig 6 six-pulse orbit (Newton stalled from the secant start).  Bisection on sin(psi)
    at the 6th crossing in long double, then Newton; the noise floor of long double after five near-saddle
    passages (~1e-9) is above tol, so the result is accepted at the measured floor and says so."""
    p = FIG6
    r = multipulse.free_star(p, "lam", 6, 0.001125, 0.0011375, launch_distance=LAUNCH_DISTANCE[Precision.LONG_DOUBLE], precision="long double")
    assert r is not None and r.success
    assert r.residual <= max(SHOOTING_TOL, FLOOR_FACTOR * r.noise_floor)
    assert r.residual <= FLOOR_CAP
    # the same orbit from an independent start (the one that converged by hand, issue 13) to its resolution
    r2 = multipulse.shoot(on_level(p, lam=0.0011352), 6)
    assert r2.success
    assert abs(r.params.lam - r2.params.lam) <= 2 * max(r.resolution, r2.resolution)
    assert shooting.count_pulses(multipulse.orbit(r)["theta"]) == 6


def test_branch_table_rows_read_the_sidecar(tmp_path):
    """REPORT.md branch table (figures/report.py) from a figure table sidecar: one row per orbit, lam* with its
    significant digits and uncertainty as written by shooting.uncertainty."""
    import json

    from magrod.figures import report

    u = {"success": True, "significant": "0.00126208079543(4)", "uncertainty": 3.3e-14, "eps_spread": 4.9e-16,
         "double_check": {"max_abs_difference": 5.2e-11}}
    table = {"orbits": [{"success": True, "pulses": 2, "arclength": 100.05, "residual": 7e-12, "noise_floor": 0.0,
                         "free_value": 0.0012620807954, "uncertainty": u},
                        {"success": False, "pulses_target": 1}]}
    (tmp_path / "figure6_table.json").write_text(json.dumps(table))
    (tmp_path / "continuation_mu2lam.json").write_text(json.dumps({"folds": [{"lam": 0.0013, "m": 1.65}]}))
    rows = report._branch_table(tmp_path, False)
    assert [r["label"] for r in rows] == ["branch table: Fig 6, N = 2", "branch table: folds (continuation_mu2lam)"]
    assert "0.00126208079543(4)" in rows[0]["computed"] and "lam = 0.0013" in rows[1]["computed"]
