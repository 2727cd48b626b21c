"""The axial stretch v3 = dH/dn3 = ds'/ds (eq:hyperelastic): two forms (body dH/dn3, chart closed form), controls
with a known answer (straight rod: 1 + gamma + delta; inextensible rod: 1), and the finding of docs/errata.md
(the orbits of Figs 4-5 reach v3 <= 0)."""
import numpy as np
import pytest

from magrod.core import systems
from magrod.core.errors import ParameterError
from magrod.generated import scalars
from magrod.core.params import RodParams
from magrod.chaos.section import orbit_stretch, poincare_section
from magrod.core.printed import PANELS, panel_kwargs

EPS = np.finfo(float).eps


@pytest.mark.parametrize("key", ["4a", "5d"])
def test_body_and_chart_forms_agree_on_random_chart_points(key):
    p = PANELS[key]["params"]
    rng = np.random.default_rng(5)
    lo = -2.0 if p.lam > 0 else 0.0
    hi = (p.mu / (2 * p.lam)) * (1 - 1e-3)  # radicand mu - 2 lam pbar_psi > 0
    q = [(rng.uniform(0.01, 3.13), rng.uniform(-np.pi, np.pi), rng.normal(), rng.uniform(lo, hi), rng.uniform(-3, 3))
         for _ in range(50)]
    x = np.array([systems.euler_to_body(th, ps, pt, pp, p.array(), phi=ph) for th, ps, pt, pp, ph in q]).T
    vb = np.array(systems.body_stretch()(np.ascontiguousarray(x), p.array())[0])
    chart = np.ascontiguousarray(np.array([[th, ps, pt, pp] for th, ps, pt, pp, _ in q]).T)
    vc = systems.reduced_functions()["stretch"](chart, p.array())[0]
    # closed form typed here once more: 1 + (gamma + delta)(cos theta + sqrt(mu - 2 lam pbar_psi) sin theta cos psi)
    th, ps, pp = chart[0], chart[1], chart[3]
    by_hand = 1 + (p.gamma + p.delta) * (np.cos(th) + np.sqrt(p.mu - 2 * p.lam * pp) * np.sin(th) * np.cos(ps))
    np.testing.assert_allclose(vb, vc, rtol=0, atol=64 * EPS * (1 + p.gamma + p.delta))
    np.testing.assert_allclose(vc, by_hand, rtol=0, atol=64 * EPS * (1 + p.gamma + p.delta))


@pytest.mark.parametrize("gamma, delta", [(3.0, 3.0), (0.15, 0.25), (0.0, 0.0)])
def test_control_straight_rod(gamma, delta):
    # the straight rod aligned with the field carries the tension n3 = C2 = 1/m^2: v3 = 1 + (gamma + delta)
    p = RodParams(m=1.7, mu=0.4, gamma=gamma, delta=delta, lam=0.135)
    x = np.array(scalars.straight_rod_state(*p.array()), dtype=float)
    v3 = float(systems.body_stretch()(x, p.array())[0])
    assert v3 == pytest.approx(1 + gamma + delta, abs=4 * EPS * (1 + gamma + delta))
    assert scalars.straight_rod_stretch(*p.array()) == 1 + gamma + delta


def test_control_inextensible_rod_along_an_orbit():
    # gamma = delta = 0: v3 = 1 identically, along the whole orbit, in both forms
    kw = panel_kwargs("4a")
    p = kw["params"]
    kw["params"] = RodParams(m=p.m, mu=p.mu, gamma=0.0, delta=0.0, lam=p.lam)
    res = poincare_section(**kw, iterates=30, stretch_dt=0.05)
    s = res.stretch
    assert s["n_samples"] > 1000 and s["straight_rod"] == 1.0
    for k in ("min_body", "max_body", "min_chart", "min_at_section_points"):
        assert s[k] == pytest.approx(1.0, abs=1e-14), k
    assert s["fraction_compressed_body"] == 0.0 and s["fraction_compressed_chart"] == 0.0


def test_fig4a_orbit_is_compressed_past_zero_length():
    """The finding (docs/errata.md): at gamma = delta = 3 the straight rod is stretched to 7 times its length and
    the Fig 4(a) orbit reaches v3 ~ -6.8; both forms agree along the sampled orbit."""
    res = poincare_section(**panel_kwargs("4a"), iterates=200, stretch_dt=0.05)
    s = res.stretch
    assert s["max_abs_body_minus_chart"] <= 1e-12
    assert s["min_body"] < -6.0 and s["min_chart"] == pytest.approx(s["min_body"], abs=1e-12)
    assert 0.2 < s["fraction_compressed_body"] < 0.8
    assert s["straight_rod"] == 7.0
    # the global bound v3 >= 1 - (gamma + delta) sqrt(1 + mu - 2 lam pbar_psi) (|n| m^2 = sqrt(1 + radicand))
    pp_min = np.min(res.points[:, 3])
    assert s["min_at_section_points"] >= 1 - 6 * np.sqrt(1 + 0.4 - 2 * 0.135 * pp_min) - 1e-12
    assert "stretch" in res.summary() and "stretch" not in res.arrays()


def test_orbit_stretch_long_double_agrees_before_divergence():
    res = poincare_section(**panel_kwargs("4d"), iterates=20)
    a = orbit_stretch(res, t_final=60.0)
    b = orbit_stretch(res, t_final=60.0, precision="long double")
    assert b["fp_type"] != "float64"
    assert abs(a["min_body"] - b["min_body"]) <= 1e-9
    assert a["fraction_compressed_body"] == b["fraction_compressed_body"]


def test_stretch_along_the_run_equals_the_reintegration():
    """poincare_section(stretch_dt=...) samples v3 on the dense output of the run itself; orbit_stretch
    re-integrates independently with propagate_grid.  On the regular Fig 4(d) orbit over 20 iterates (no
    divergence yet) both give the same samples: minimum to 1e-10 and the same count of compressed samples."""
    res = poincare_section("4d", iterates=20, stretch_dt=0.05)
    a, b = res.stretch, orbit_stretch(res, dt=0.05)
    assert a["sampled"].startswith("along the run") and b["sampled"].startswith("re-integrated")
    assert a["n_samples"] == b["n_samples"] > 1000
    assert abs(a["min_body"] - b["min_body"]) <= 1e-10 and abs(a["t_min_body"] - b["t_min_body"]) <= 0.05
    assert abs(a["fraction_compressed_body"] - b["fraction_compressed_body"]) <= 2 / a["n_samples"]


def test_orbit_stretch_bad_input():
    res = poincare_section(**panel_kwargs("4a"), iterates=3)
    with pytest.raises(ParameterError):
        orbit_stretch(res, dt=0.0)
    with pytest.raises(ParameterError):
        orbit_stretch(res, dt=float("nan"))


@pytest.mark.parametrize("t_start", [0.0, 7.0e4])
def test_taylor_steps_equal_heyokas_continuous_output(t_start):
    """The sampler evaluates the steps' Taylor polynomials itself (heyoka's continuous output costs ~1.2 ms per
    propagate call); on the same steps of the body-frame integrator, the samples equal the continuous output's to a
    few ulps -- also at t ~ 7e4, the length of a Fig 4 run, where h = t - t_start must come from the integrator's
    double-length time -- and a run that ends on a section event (a truncated last step) is covered to its end."""
    import heyoka as hy

    from magrod.chaos.section import _StretchSampler

    p = panel_kwargs("4a")["params"]
    pars = p.array()
    x0 = systems.euler_to_body(0.1, 0.0, 0.5, 0.9860764939894979, pars)
    ev = hy.t_event(hy.time - (t_start + 30.3))  # a terminal event: the call ends inside a step
    ta = hy.taylor_adaptive(systems.system("body"), list(x0), time=t_start, pars=list(pars), t_events=[ev])
    s = _StretchSampler(0.05, pars)
    r = ta.propagate_until(t_start + 40.0, callback=s.step, write_tc=True, c_output=True)
    assert int(r[0]) < 0 and len(s._steps) == r[3] > 20  # stopped by the event, every step recorded
    co = r[4]
    hi = np.array([a for a, _, _, _ in s._steps])
    lo = np.array([b for _, b, _, _ in s._steps])
    lh = np.array([c for _, _, c, _ in s._steps])
    from magrod.chaos.section import _TaylorSteps

    steps = _TaylorSteps(hi, lo, lh, np.stack([d for *_, d in s._steps]), co.bounds)
    t = np.linspace(*co.bounds, 2001)
    ours, theirs = steps(t), np.array([np.array(co(tt)) for tt in t])  # co returns its own buffer
    scale = np.max(np.abs(theirs), axis=0)
    assert np.max(np.abs(ours - theirs) / scale) <= 64 * EPS
    # the coefficients are the step's at its start: the last (truncated) step's polynomial at h = last_h is the
    # event's state (at t ~ 7e4 the end time hi + lo is not a double, so this is checked at h, not at t)
    tc = s._steps[-1][3]
    end = sum(tc[:, k] * lh[-1] ** k for k in range(tc.shape[1]))
    assert np.max(np.abs(end - np.asarray(ta.state)) / scale) <= 64 * EPS
