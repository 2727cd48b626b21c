"""The Lyapunov spectrum and GALI (issue 28, item 4): magrod.chaos.spectrum, `magrod spectrum`.

Controls: Lorenz (a published value and a closed-form sum), Henon-Heiles (Hamiltonian pairing), the rod's 4(a)
orbit (pairing, the seven zero exponents of its Casimirs, H and m3, the maximal exponent of `lyapunov`), the rod's
integrable limits (every exponent zero), GALI on 4(a) (exponential) and 4(d) (power law).

"Zero" at a finite T: a direction that grows linearly (the shear along a conserved quantity) has the finite-time
exponent ln(T)/T; an exponent is called zero when |lambda| <= ZERO_FACTOR ln(T)/T (a factor 2 for the constant of
the linear growth), and a positive exponent must exceed that bound."""
import json
import math
from dataclasses import replace

import numpy as np
import pytest

import magrod as mr
from magrod.chaos import indicators
from magrod.chaos.spectrum import lyapunov_spectrum

ZERO_FACTOR = 2.0
EPS = np.finfo(float).eps


def zero_bound(T):
    return ZERO_FACTOR * math.log(T) / T


# ----------------------------------------------------------------------------------------------------------
# textbook controls
# ----------------------------------------------------------------------------------------------------------
def test_lorenz_matches_the_published_spectrum_and_its_closed_form_sum():
    """Lorenz (10, 28, 8/3): lambda = (0.9056, 0, -14.5723) (Sprott, Chaos and Time-Series Analysis, 2003, table
    A.1).  The sum is -(sigma + 1 + b) exactly (the trace of the Jacobian is constant), so it is checked to
    rounding; lambda_1 to 0.03 (a finite-T estimate at T = 500: the spread of L(T)/T over starts is ~0.01).  The
    same run without re-orthonormalisation must fail: every column aligns with the unstable direction."""
    x0 = [1.0, 1.0, 20.0]
    sp = lyapunov_spectrum(x0, system="lorenz", t_max=500, renorm_dt=0.1)
    assert sp.success, sp.message
    assert abs(sp.exponents.sum() + (10 + 1 + 8 / 3)) <= 1e-9 * (10 + 1 + 8 / 3)
    assert abs(sp.exponents[0] - 0.9056) < 0.03, sp.exponents
    assert abs(sp.exponents[1]) < 0.03, sp.exponents
    assert abs(sp.exponents[2] + 14.5723) < 0.05, sp.exponents
    bad = lyapunov_spectrum(x0, system="lorenz", t_max=500, renorm_dt=0.1, _reorthonormalise=False)
    assert abs(bad.exponents[2] + 14.5723) > 10, bad.exponents  # the control fails without QR


def test_henon_heiles_exponents_pair_and_the_energy_pair_is_zero():
    """Henon-Heiles at E = 1/6, a start in the chaotic sea (x = 0, y = -0.193, py = 0): a canonical 2-degree-of-
    freedom flow, so lambda_1 + lambda_4 = 0 and lambda_2 = lambda_3 = 0 (the flow direction and energy)."""
    x0 = indicators.henon_heiles_start(1 / 6, np.array([-0.193]))[:, 0]
    T = 2000.0
    sp = lyapunov_spectrum(x0, system="henon_heiles", t_max=T, renorm_dt=1.0)
    z = zero_bound(T)
    assert sp.exponents[0] > 5 * z, sp.exponents
    assert abs(sp.exponents[0] + sp.exponents[3]) <= z and abs(sp.exponents[1]) <= z and abs(sp.exponents[2]) <= z
    assert abs(sp.exponents.sum()) <= 1e-12  # divergence-free: ln|det Phi| = 0


# ----------------------------------------------------------------------------------------------------------
# the rod
# ----------------------------------------------------------------------------------------------------------
T_4A = 4000.0  # 4(a) is sticky: its exponent ~0.007 separates from the zero bound 0.004 only from T ~ 3000 on


@pytest.fixture(scope="module")
def spectrum_4a():
    return lyapunov_spectrum("4a", t_max=T_4A)


def test_the_body_flow_is_divergence_free_so_the_exponents_sum_to_zero(spectrum_4a):
    """trace Df = 0 at random points of the body frame (the Lie-Poisson structure of se(3)*-like J is unimodular),
    so sum lambda_i = ln|det Phi(T)|/T = 0 up to rounding in every renormalisation."""
    from magrod.core import systems

    rng = np.random.default_rng(3)
    jac = systems.body_functions()["jacobian"]
    p = mr.panel("4a").params.array()
    for _ in range(20):
        x = rng.standard_normal(9)
        J = np.asarray(jac(x, p)).reshape(9, 9)
        assert abs(np.trace(J)) <= 100 * EPS * np.abs(J).sum()
    nsteps = T_4A / spectrum_4a.renorm_dt
    assert abs(spectrum_4a.exponents.sum()) <= 10 * nsteps * EPS * 9 / T_4A


def test_4a_has_one_pair_and_seven_zeros_and_its_maximal_exponent_is_lyapunovs(spectrum_4a):
    """(l, 0 x 7, -l): pairing lambda_i + lambda_{10-i} within the zero bound, exactly two exponents beyond it
    (the pair), and lambda_1 equal to `lyapunov`'s L(T)/T on the same orbit within 10 % (one tangent vector,
    projected onto the level set, against the first QR column: the same limit, O(1/T) apart)."""
    sp = spectrum_4a
    assert sp.success, sp.message
    z = zero_bound(T_4A)
    e = sp.exponents
    assert np.all(np.abs(sp.pairing) <= z), (sp.pairing, z)
    assert (np.abs(e) > z).sum() == 2 and e[0] > z and e[-1] < -z, (e, z)
    ly = mr.lyapunov("4a", t_max=T_4A)
    assert abs(e[0] - ly.lyap) <= 0.1 * ly.lyap, (e[0], ly.lyap)
    assert sp.accuracy["passed"] and sp.max_abs_dH < 1e-10


@pytest.mark.parametrize("change, h", [({"lam": 0.0}, 1.2), ({"gamma": 0.0, "delta": 0.0}, None)],
                         ids=["lambdabar=0", "gamma=delta=0"])
def test_every_exponent_is_zero_in_an_integrable_limit(change, h):
    """lambdabar = 0 (no magnetic field: the Kirchhoff rod) and gamma = delta = 0 (inextensible, unshearable):
    integrable, so all nine exponents are zero at T.  (h = 1.2 at lambdabar = 0: 4(a)'s h = 0.9 is below that
    level's minimum.)"""
    P = mr.panel("4a")
    T = 1000.0
    sp = lyapunov_spectrum(replace(P.params, **change), h=P.h if h is None else h, theta0=P.theta0,
                           ptheta0=P.ptheta0, t_max=T)
    assert sp.success, sp.message
    assert np.all(np.abs(sp.exponents) <= zero_bound(T)), (sp.exponents, zero_bound(T))


def test_gali_decays_exponentially_on_4a_and_as_a_power_on_4d(spectrum_4a):
    """Skokos, Bountis & Antonopoulos 2007: chaotic -> GALI_2 ~ exp(-(l1 - l2) t) = exp(-l1 t) here (l2 = 0);
    regular -> bounded or a power of t.  On 4(d) (regular) GALI_2 and GALI_3 stay of order one (power within 0.5 of
    0) and GALI_4 falls as ~t^-1 (the orbit fills a 3-torus of the 9-D body frame: its reduced 2-torus times the
    m3 rotation; one extra vector needs one O(1/t) component), while on 4(a) GALI_2 falls below 1e-5 at a rate
    within 35 % of l1 from the spectrum."""
    T = 3000.0
    ga, gd = mr.gali("4a", t_max=T), mr.gali("4d", t_max=T)
    assert ga.success and gd.success
    assert np.all(ga.gali <= 1 + 1e-12) and np.all(gd.gali <= 1 + 1e-12)  # volumes of unit vectors
    da, dd = ga.decay(), gd.decay()
    l1 = spectrum_4a.exponents[0]
    assert ga.final["GALI_2"] < 1e-5 and abs(da[2]["rate"] + l1) <= 0.35 * l1, (da, l1)
    assert abs(dd[2]["power"]) < 0.5 and abs(dd[3]["power"]) < 0.5, dd
    assert -2.0 < dd[4]["power"] < -0.5 and gd.final["GALI_4"] > 1e-8, dd
    assert ga.final["GALI_2"] < 1e-3 * gd.final["GALI_2"]


def test_results_share_the_face_and_plot():
    import matplotlib

    matplotlib.use("Agg", force=False)
    sp = mr.lyapunov_spectrum("4d", t_max=100)
    g = mr.gali("4d", t_max=100)
    for r in (sp, g):
        assert len(repr(r)) < 1000
        json.dumps(r.to_dict())
        assert r.plot() is not None


def test_bad_input_names_the_field():
    for kw, name in (({"t_max": -1}, "t_max"), ({"renorm_dt": 0}, "renorm_dt"), ({"system": "x"}, "system")):
        with pytest.raises(mr.ParameterError) as e:
            mr.lyapunov_spectrum("4a", **kw)
        assert e.value.name == name
    with pytest.raises(mr.ParameterError) as e:
        mr.gali([1.0, 2.0, 3.0], system="lorenz")
    assert e.value.name == "system"  # GALI_4 needs 4 dimensions


# ----------------------------------------------------------------------------------------------------------
# the command
# ----------------------------------------------------------------------------------------------------------
def test_spectrum_command(tmp_path, capsys):
    from magrod import cli

    rc = cli.main(["spectrum", "--panel", "4d", "--t-max", "200", "--gali", "--out", str(tmp_path / "o"), "--json",
                   "--quiet"])
    cap = capsys.readouterr()
    assert rc == 0, cap.err
    d = json.loads(cap.out)
    assert len(d["exponents"]) == 9 and set(d["gali"]["final"]) == {"GALI_2", "GALI_3", "GALI_4"}
    assert (tmp_path / "o" / "spectrum.png").is_file() and (tmp_path / "o" / "spectrum.json").is_file()
    rc = cli.main(["spectrum", "--t-max", "-5", "--out", str(tmp_path / "p"), "--json"])
    cap = capsys.readouterr()
    assert rc == 2 and json.loads(cap.out)["parameter"] == "t_max"
    assert len([ln for ln in cap.err.splitlines() if ln.strip()]) == 1 and not (tmp_path / "p").exists()
