"""The a > 2b splitting coefficient, derived (derive/generic_splitting.py, magrod.separatrix.generic; issue 20).

References: the measured splitting (magrod.separatrix.splitting.tilted_curve in two precisions, eps^2
extrapolation: an independent computation, 9-D body-frame integration of W^u of the tilted saddle-focus); the
primary orbits to the periodic saddle as mu -> 2 lambdabar+ (magrod.orbits.periodic_homoclinic, the branches of
docs/errata.md / tests/test_continuation.py, re-shot here); an independent quadrature of the transverse integrand."""
import math

import numpy as np
import pytest

pytest.importorskip("flint")

from flint import arb, ctx  # noqa: E402

from magrod.core.errors import ParameterError  # noqa: E402
from magrod.separatrix import generic as G  # noqa: E402
from magrod.separatrix import splitting as SPL  # noqa: E402

QUICK = [(1.7, 1.0, 1.0, 4.0, 1.0), (1.7, 0.0, 1.0, 4.0, 1.0)]  # all eight cases: test_all_eight_cases (slow)


@pytest.fixture(scope="module")
def quick_comparison():
    return G.compare_generic(QUICK, precisions=("double", "long double"))


def test_derived_matches_measured(quick_comparison):
    r = quick_comparison
    assert r.success, r.message
    assert r.max_rel_difference <= G.TOLERANCE
    for row in r.rows:
        assert set(row["measured"]) == {"double", "long double"}
        for meas in row["measured"].values():
            assert all(g.startswith("passed") for g in meas["guards"])  # every curve passed the fit guard


@pytest.mark.parametrize("wrong, why", [(2.0, "a factor of 2 too many"), (0.5, "a dropped factor of 2"),
                                        (-1.0, "the sign"), (math.sqrt(4.0 / 2.0), "sqrt(a) instead of sqrt(a - 2b)")])
def test_a_wrong_guess_fails(quick_comparison, wrong, why):
    """The same measurement against a wrong coefficient: the check fails (relative difference >> 1e-4)."""
    row = quick_comparison.rows[0]  # a = 4, b = 1: sqrt(a)/sqrt(a - 2b) = sqrt(2)
    rel = abs(row["measured"]["long double"]["C0"] / (row["derived"] * wrong) - 1.0)
    assert rel > 100 * G.TOLERANCE, why


def test_transverse_integral_is_minus_2_m2_S():
    """Int_R W_y dt = -2 m^2 S (symbolic, report entry generic_exact_derivative): checked by an independent
    Gauss-Legendre quadrature of the generated W_y (float64 on [0, 40] in tau = kappa t) against enclose_S."""
    from magrod.generated import generic_splitting as gen
    from magrod.separatrix.enclosure import enclose_S

    x, w = np.polynomial.legendre.leggauss(80)
    for m, g, d in [(1.7, 1.0, 1.0), (1.2, 0.5, 2.0), (1.7, 0.0, 1.0)]:
        tot = 0.0
        with ctx.workprec(64):
            M, Gm, Dl = arb(m), arb(g), arb(d)
            for a, b in zip(np.arange(0, 40, 2.0), np.arange(2.0, 42, 2.0)):
                tau = 0.5 * (b - a) * x + 0.5 * (a + b)
                tot += 0.5 * (b - a) * sum(wi * float(gen.transverse_integrand(arb(float(t)), M, Gm, Dl).mid())
                                           for wi, t in zip(w, tau))
        S = float(enclose_S(m, g, d, prec=64).S.mid())
        assert abs(2 * tot + 2 * m * m * S) <= 1e-10 * max(1.0, abs(S)), (m, g, d, 2 * tot, -2 * m * m * S)


def test_circle_predicts_the_primaries_as_mu_to_2lam():
    """The two primary orbits to the periodic saddle at lambdabar = 1e-3, m = 1.7, gamma = delta = 1 (the branches of
    docs/errata.md, re-shot here at nu = mu - 2 lambdabar = 1e-8 and 1e-9 from the errata's converged angles):
    their launch angles differ by pi - 2 asin(lambdabar^2 |S|/sqrt(nu)).  Measured 0.27 % above the leading order
    (an O(lambdabar) correction is expected); the bound 1 % is 4x that."""
    from magrod.core.params import RodParams
    from magrod.generated import scalars
    from magrod.orbits import periodic_multipulse as hp
    from magrod.orbits.periodic import periodic_saddle

    P = RodParams(1.7, 0.0021, 1.0, 1.0, 0.001)
    mu0 = scalars.straight_rod_mu(**P.to_dict())
    pred = G.circle_prediction(1.7, 1.0, 1.0, 0.001)
    T0 = 26.458268971  # errata: time to the straight rod's first turning point (mu = 2 lambdabar)
    starts = {1e-8: [(T0 - 1.17e-6, 1.307617), (T0 - 1.50e-6, 4.432634)],
              1e-9: [(T0 - 1.15e-6, 1.325540), (T0 - 1.25e-6, 4.414711)]}
    for nu, prim in starts.items():
        rs = [hp.shoot(P.replace(mu=mu0 + nu), 1, a, T, launch_distance=1e-7) for T, a in prim]
        assert all(r.success and r.residual <= 1e-10 for r in rs)
        spread = rs[1].angle - rs[0].angle - math.pi
        assert abs(spread / pred.spread(nu) - 1) <= 1e-2, (nu, spread, pred.spread(nu))
    assert pred.primaries_exist(1e-12) and not pred.primaries_exist(1e-13)  # merge at nu* = 6.8e-13
    # sin(psi) over the launch angle: psi0 + A sqrt(nu) sin(phi + const); least-squares first harmonic of a scan
    ang, _, sp = hp.scan_angles(periodic_saddle(P.replace(mu=mu0 + 1e-8)), 1, 61, launch_distance=1e-7)
    ok = np.isfinite(sp)
    cols = np.column_stack([np.ones(ok.sum()), np.cos(ang[ok]), np.sin(ang[ok])])
    (p0, p1, p2), *_ = np.linalg.lstsq(cols, sp[ok], rcond=None)
    A = math.hypot(p1, p2) / math.sqrt(1e-8)
    assert abs(A / pred.A - 1) <= 2e-2, (A, pred.A)
    assert abs(p0 / pred.psi0 - 1) <= 2e-2, (p0, pred.psi0)


def test_guard_refuses_a_clustered_curve_and_reports_fit_and_coverage():
    """The curve the audit found wrong: (a, b) = (2.05, 1), eps = 1.25e-3, long double (clustered psi, residual 1e-9
    > |s1|).  With guard=False it is returned, marked refused, with both numbers stated."""
    with pytest.raises(ParameterError) as ei:
        SPL.tilted_curve(1.7, 1, 1, 2.05, 1, 1.25e-3, "long double")
    assert ei.value.name == "eps" and "guard" in str(ei.value)
    raw = SPL.tilted_curve(1.7, 1, 1, 2.05, 1, 1.25e-3, "long double", guard=False)
    assert raw.guard.startswith("refused") and raw.psi_max_gap > raw.coverage_bound
    ok = SPL.tilted_curve(1.7, 1, 1, 4, 1, 0.01, "double")
    assert ok.guard.startswith("passed") and ok.psi_max_gap <= ok.coverage_bound and ok.fit_residual <= ok.fit_bound
    d = ok.to_dict()
    assert {"fit_residual", "psi_max_gap", "coverage_bound", "fit_bound", "guard"} <= set(d)


@pytest.mark.parametrize("args, name", [((1.7, 1, 1, 2, 1), "a"), ((1.7, 1, 1, 1, 1), "a"), ((1.7, 1, 1, 4, -1), "b"),
                                        ((3.0, 1, 1, 4, 1), "m"), ((1.7, -1, 1, 4, 1), "gamma")])
def test_bad_input_names_the_parameter(args, name):
    with pytest.raises(ParameterError) as ei:
        G.generic_coefficient(*args)
    assert ei.value.name == name


@pytest.mark.slow
def test_all_eight_cases():
    r = G.compare_generic()
    assert len(r.rows) >= 8 and r.success, r.message
