"""Separatrix splitting (magrod/splitting.py): precision agreement, independent float64 code path, integrable
controls at their rounding floor, power-law fits stable under dropping end points, CLI contract."""
import json
import math

import numpy as np
import pytest

from magrod.separatrix import splitting as S
from magrod.cli import main
from magrod.core.precision import Precision
from magrod.orbits.equilibrium import StraightRod, straight_rod
from magrod.orbits.periodic import PeriodicSaddle
from magrod.orbits.shooting import unstable_branch

M, G, DL = 1.7, 1.0, 1.0
ULP = {"double": np.finfo(float).eps, "long double": float(np.finfo(np.longdouble).eps), "quad": 2.0**-112}


@pytest.mark.parametrize("eps", [0.1, 0.01])
def test_equilibrium_two_precisions_and_independent_path(eps):
    p = S.scaled_params(M, G, DL, 2.0, 1.0, eps)
    assert p.mu == 2 * p.lam
    q = S.first_crossing(p, "quad", eps=eps)
    lo = S.first_crossing(p, "long double", eps=eps)
    # psi is the angle of the transverse force rho = O(eps^2): absolute error ~ ulp / rho
    rho = math.hypot(q.d, q.rho_cos)
    assert abs(lo.psi - q.psi) <= 1e4 * ULP["long double"] / rho
    assert abs(lo.d - q.d) <= 1e4 * ULP["long double"] * abs(q.d) / rho
    # shooting.unstable_branch: float64, other launch distance and event code, psi from float64 chart map
    c = unstable_branch(straight_rod(p), crossings=1, launch_distance=1e-7)[0]
    assert abs(c.theta - q.theta) <= 1e-12
    assert abs(c.psi - q.psi) <= 1e4 * ULP["double"] / rho
    assert abs(q.H_drift) <= 1e3 * ULP["quad"] and q.casimir_drift <= 1e3 * ULP["quad"]


def test_launch_phase_is_a_symmetry_for_the_straight_rod():
    p = S.scaled_params(M, G, DL, 2.0, 1.0, 0.05)
    a = S.first_crossing(p, "long double", phase=0.0)
    b = S.first_crossing(p, "long double", phase=2.0)
    rho = math.hypot(a.d, a.rho_cos)
    assert abs(a.psi - b.psi) <= 1e4 * ULP["long double"] / rho


@pytest.mark.parametrize("eps", [0.1, 0.01, 0.001])
def test_integrable_control_gamma_delta_zero(eps):
    """gamma = delta = 0 (inextensible, unshearable): I2 is conserved, W^u = W^s, psi_u = 0 to rounding."""
    p = S.scaled_params(M, 0.0, 0.0, 2.0, 1.0, eps)
    q = S.first_crossing(p, "quad", eps=eps)
    assert abs(q.psi) <= 1e4 * ULP["quad"] / (0.3 * eps**2)
    assert abs(q.d) <= 1e4 * ULP["quad"]
    # the non-integrable case at the same eps is many orders above that floor
    assert abs(S.first_crossing(S.scaled_params(M, G, DL, 2.0, 1.0, eps), "quad").psi) > 0.5 * eps**2


def test_equilibrium_fit_p2_stable():
    eps = [0.1, 0.03, 0.01, 0.003, 0.001]
    r = S.scan(M, G, DL, 2.0, 1.0, eps, ("long double", "quad"))
    f = r.fit_psi
    assert abs(f.p - 2) < 0.01 and abs(f.p_drop_smallest - 2) < 0.01 and abs(f.p_drop_largest - 2) < 0.01
    assert abs(r.fit_d.p - 4) < 0.01
    # C0 extrapolated in eps^2 agrees with psi/eps^2 at the smallest eps to O(eps^2)
    last = r.crossings[Precision.QUAD][-1]
    assert abs(last.psi / last.eps**2 - f.C0) <= 2 * abs(f.C0_slope) * last.eps**2 + 1e-9
    assert r.agreement_psi[Precision.LONG_DOUBLE] < 1e-6


def test_tilted_saddle_on_fix_and_hyperbolic():
    p = S.scaled_params(M, G, DL, 4.0, 1.0, 0.03)
    sd = S.splitting_saddle(p, "long double")
    assert sd.kind == "periodic" and isinstance(sd, PeriodicSaddle) and sd.chart_view.residual <= 1e3 * ULP["long double"]
    assert sd.q.dtype == np.longdouble and sd.precision is Precision.LONG_DOUBLE  # computed in the working precision
    assert float(sd.q[1]) == 0.0 and float(sd.q[2]) == 0.0  # on Fix(R)
    assert sd.chart_eigenvalue.real > 0.5 and abs(sd.chart_eigenvalue.imag) > 0.1  # saddle-focus
    # leading order tilt theta0 = eps sqrt(a - 2b)
    assert abs(float(sd.q[0]) / (0.03 * math.sqrt(2.0)) - 1) < 0.01


def test_tilted_splitting_p3_and_control_b0():
    eps = [0.05, 0.025, 0.0125, 0.00625]
    r = S.tilted_scan(M, G, DL, 4.0, 1.0, eps, ("double",), n_phases=48)
    assert abs(r.fit_s1.p - 3) < 0.02 and abs(r.fit_s1.p_drop_smallest - 3) < 0.02
    for c in r.curves:  # the first harmonic dominates and is far above the fit residual: simple zeros at 0, pi
        assert abs(c.sin_coeffs[0]) > 100 * c.fit_residual
        assert abs(c.sin_coeffs[0]) > 10 * max(abs(s) for s in c.sin_coeffs[1:])
    ctl = S.tilted_scan(M, G, DL, 1.0, 0.0, eps[:2], ("double",), n_phases=48)
    for c in ctl.curves:  # b = 0: integrable (lambdabar = 0), D(psi) = 0 up to the Fourier fit residual
        assert max(abs(s) for s in c.sin_coeffs) <= c.fit_residual


@pytest.mark.parametrize("argv,name", [(["--a", "-1"], "a"), (["--eps", "0.1,0"], "eps"), (["--m", "3"], "m"),
                                       (["--a", "1", "--b", "1"], "a")])
def test_cli_bad_input(argv, name, capsys):
    assert main(["splitting", "--json", *argv]) == 2
    out = json.loads(capsys.readouterr().out)
    assert out["ok"] is False and out["parameter"] == name


def test_cli_json(capsys):
    assert main(["splitting", "--json", "--eps", "0.1,0.05,0.02,0.01", "--precision", "long double"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert abs(out["fit_psi"]["p"] - 2) < 0.02 and len(out["rows"]) == 4


# --- the derived leading term at a = 2b (derive/splitting.py, magrod.separatrix.splitting.leading_coefficient) -----------
def test_leading_term_matches_measured_constants():
    """docs/nonintegrability.md: psi_u/eps^2 -> -0.8039252, d/eps^4 -> -0.2859876 (quad, a = 2b = 2)."""
    lt = S.leading_coefficient(M, G, DL)
    # the real128 reference and the float64 quadrature agree to a few ulp; the tail is below 1e-18
    assert lt.quad_error <= 1e3 * ULP["double"] and lt.tail_estimate <= 1e-18
    assert S.digits_agreeing(lt.C_psi, -0.8039252) >= 6.5  # the published constant has 7 digits
    assert S.digits_agreeing(lt.C_d, -0.2859876) >= 6.5


@pytest.mark.parametrize("case", [(1.7, 1.0, 1.0, 2.0, 1.0), (1.2, 0.5, 2.0, 2.0, 1.0), (2.2, 2.0, 0.5, 1.0, 0.5)])
def test_leading_term_against_scan(case):
    c = S.compare_leading(*case)
    # the measured C0 (eps^2 extrapolation, long double) is good to ~1e-8 relative
    assert c["digits_psi"] >= 6 and c["digits_d"] >= 6, c


def test_leading_term_integrable_control_zero():
    """gamma = delta = 0 (integrable for every lambdabar): the derived splitting vanishes."""
    lt = S.leading_coefficient(M, 0.0, 0.0)
    # real128: zero up to the truncated tail Int_T^inf (theta(T) = 1e-20); float64: up to rounding
    assert abs(lt.S_reference) <= lt.tail_estimate and abs(lt.S) <= 1e3 * ULP["double"]


def test_leading_term_tilted_case_rejected():
    with pytest.raises(S.ParameterError):
        S.compare_leading(M, G, DL, 4.0, 1.0)


# --- one saddle per object (issue 25) ---------------------------------------------------------------------------
def test_the_separatrix_saddle_is_the_orbits_saddle():
    """The splitting launches from magrod.orbits' saddle objects (StraightRod at a = 2b, PeriodicSaddle at
    a > 2b), in the working precision; before issue 25 it had classes of its own (EquilibriumSaddle,
    TiltedSaddle) with their own Newton."""
    from magrod.orbits import shooting

    for a, cls in ((2.0, StraightRod), (4.0, PeriodicSaddle)):
        p = S.scaled_params(M, G, DL, a, 1.0, 0.03)
        sd = S.splitting_saddle(p, "long double")
        assert type(sd) is cls and type(sd) is type(shooting.saddle(p))
        assert sd.precision is Precision.LONG_DOUBLE and sd.at(p).precision is Precision.LONG_DOUBLE
        assert S.launch_point(sd, 1e-10, 0.3).dtype == np.longdouble
    # the periodic saddle's chart view is the same relative equilibrium as its body-frame Gauss-Newton point
    ps = S.splitting_saddle(S.scaled_params(M, G, DL, 4.0, 1.0, 0.03), "double")
    chart = np.asarray(ps.chart_view.q, float)
    assert abs(chart[0] - ps.chart[0]) < 1e-12 and abs(chart[3] - ps.chart[4]) < 1e-12  # theta0, pbar_psi0
    # the old names still resolve, to the same classes, with a DeprecationWarning
    with pytest.warns(DeprecationWarning):
        assert S.TiltedSaddle is PeriodicSaddle
    with pytest.warns(DeprecationWarning):
        assert S.EquilibriumSaddle is StraightRod
    with pytest.warns(DeprecationWarning):
        assert type(S.working_saddle(p, "double")) is PeriodicSaddle


def test_mu_within_mu_tol_of_2lam_is_the_straight_rod_for_both():
    """One mu = 2 lam rule (orbits.equilibrium.is_on_level, MU_TOL): a mu a few ulp off 2 lam is the straight rod
    for the shooting engine and for the splitting alike (the splitting used to test exact equality and then ran a
    tilted-saddle Newton at a tilt of ~1e-9)."""
    from magrod.orbits import shooting

    ulp = np.finfo(float).eps
    p = S.scaled_params(M, G, DL, 2.0, 1.0, 0.05)
    q = p.replace(mu=p.mu * (1 + 8 * ulp))
    assert q.mu != 2 * q.lam
    assert shooting.saddle(q).kind == S.splitting_saddle(q, "long double").kind == "equilibrium"
    assert S.is_equilibrium_case(2.0 * (1 + 8 * ulp), 1.0) and not S.is_equilibrium_case(2.0 * (1 + 1e-9), 1.0)
    # and the scan treats such an a as a = 2b: the same crossing as a = 2b exactly
    c0 = S.first_crossing(S.scaled_params(M, G, DL, 2.0, 1.0, 0.05), "double")
    c1 = S.first_crossing(S.scaled_params(M, G, DL, 2.0 * (1 + 8 * ulp), 1.0, 0.05), "double")
    assert (c0.psi, c0.d) == (c1.psi, c1.d)


@pytest.mark.parametrize("a", [2.0, 4.0])
def test_splitting_launch_rounds_the_offset_in_double(a):
    """LAUNCH: the splitting's launch forms launch_distance d in float64 and converts it (the convention of REPORT.md's
    digits), an explicit option of the orbits' launch_point; the shooting engine's default forms it in the
    working precision.  Both are at distance launch_distance to rounding; in long double they differ in the last bits."""
    from magrod.core import systems

    p = S.scaled_params(M, G, DL, a, 1.0, 0.03)
    sd = S.splitting_saddle(p, "long double")
    launch_distance, phase = 1e-10, 0.7
    x = S.launch_point(sd, launch_distance, phase)
    if sd.kind == "equilibrium":
        d = np.real(np.exp(-1j * phase) * sd.unstable_vector)
        from magrod.orbits.equilibrium import straight_rod_state

        dist = launch_distance
        ref = straight_rod_state(p, "long double") + systems.fp_array(launch_distance * (d / np.linalg.norm(d)), np.longdouble)
        other = sd.launch_point(launch_distance, phase)  # offset "working"
    else:
        d = np.real(np.exp(-1j * phase) * sd.chart_vector)
        dist = launch_distance * float(sd.q[0])
        q = sd.q + systems.fp_array(dist * (d / np.linalg.norm(d)), np.longdouble)
        ref = systems.splitting_functions(np.longdouble)["to_body"](q, p.array())
        other = sd.launch_point(launch_distance, phase, frame="chart")
    assert np.array_equal(x, ref)
    assert not np.array_equal(x, other)  # the keyword is not a no-op in long double
    assert float(np.max(np.abs(x - other))) <= 8 * float(np.finfo(np.longdouble).eps) * max(dist, float(np.max(np.abs(x))) * 1e-3)


def test_launch_keywords_are_checked():
    from magrod.core.errors import ParameterError

    sd = S.splitting_saddle(S.scaled_params(M, G, DL, 4.0, 1.0, 0.03), "double")
    for kw, name in (({"offset": "single"}, "offset"), ({"frame": "lab"}, "frame")):
        with pytest.raises(ParameterError) as e:
            sd.launch_point(1e-8, 0.0, **kw)
        assert e.value.name == name
    # both roundings are launches at distance eps to rounding
    a, b = sd.launch_point(1e-8, 0.4, offset="double"), sd.launch_point(1e-8, 0.4)
    assert np.max(np.abs(a - b)) <= 4 * np.finfo(float).eps and abs(np.linalg.norm(a - sd.x) / 1e-8 - 1) <= 1e-7
