"""Batched Poincare sections (issue 18): many starts in the SIMD lanes of heyoka's batch integrator
(magrod/chaos/batch.py), through `poincare_section` with a list of panels or a table of starts."""
import subprocess
import sys

import numpy as np
import pytest

from magrod.chaos import section
from magrod.chaos.section import MAX_ORBITS, poincare_section, poincare_sections
from magrod.core.errors import ParameterError
from magrod.paper.printed import PANELS, panel
from magrod.core.tolerances import START_LEVEL_TOL

KEYS = list(PANELS)
# conservation on every lane: the bound the scalar path meets on the paper panels (benchmarks/README.md)
DH_LANE = 1.5e-13


def _body_diff(a, b):
    return np.max(np.abs(a.body_points - b.body_points), axis=1)


@pytest.fixture(scope="module")
def eight():
    """The 8 paper panels, 100 crossings: batched, scalar (float64) and scalar long double."""
    n = 100
    return (poincare_sections(KEYS, iterates=n), [poincare_section(k, iterates=n) for k in KEYS],
            [poincare_section(k, iterates=n, precision="long double") for k in KEYS])


def test_a_lane_does_not_depend_on_its_neighbours_or_the_worker_count():
    """heyoka batch lanes step independently: an orbit's section points are bit-identical whichever lane,
    neighbours, refill order or number of threads it gets."""
    alone = poincare_sections(["4a"], iterates=300)[0]
    mixed = poincare_sections(["5d", "4b", "4a", "5a", "4c", "4d", "5b"], iterates=300, workers=2)
    many = poincare_sections(["4a"] * 9, iterates=300, workers=2)
    assert [r.panel for r in mixed] == ["5d", "4b", "4a", "5a", "4c", "4d", "5b"]  # results in input order
    np.testing.assert_array_equal(alone.body_points, mixed[2].body_points)
    np.testing.assert_array_equal(alone.times, mixed[2].times)
    for r in many:
        np.testing.assert_array_equal(alone.body_points, r.body_points)


def test_batch_agrees_with_the_scalar_path_as_well_as_two_precisions_do(eight):
    """The batch and the scalar integrator take the same Taylor steps, except that heyoka's SIMD step-size
    formula rounds differently from the scalar one in the last bit now and then (first at step 73 of Fig 4(a)),
    and event times are located to within different roundings.  Those ulps grow chaotically as any rounding
    difference does, so the reference for 'agreement' is the difference between two equally valid runs of the
    scalar path: float64 and long double.  Over the first 100 crossings of every panel the batch-scalar distance
    stays within 10x the float64-long double distance (measured ratio 0.14 .. 2.4), and before the growth takes
    over (the first 10 crossings) the two paths agree to 1e-12."""
    B, S, L = eight
    for k, b, s, ld in zip(KEYS, B, S, L):
        assert b.success and s.success and b.n_points == s.n_points == 100, k
        d_bs, d_sl = _body_diff(b, s), _body_diff(s, ld)
        assert np.max(d_bs[:10]) <= 1e-12, (k, d_bs[:10])
        assert np.max(d_bs) <= 10 * np.max(d_sl), (k, np.max(d_bs), np.max(d_sl))
        np.testing.assert_array_equal(b.roots, s.roots)  # the same start (the same root solver)
        assert b.p_psi0 == s.p_psi0


def test_every_lane_conserves_as_the_scalar_path(eight):
    B, _, _ = eight
    long = poincare_sections(KEYS, iterates=2000, workers=2)
    for r in [*B, *long]:
        assert r.success and r.max_abs_dH <= DH_LANE, (r.panel, r.max_abs_dH)
        assert r.casimir_drift <= DH_LANE
        assert r.accuracy_checks()["passed"]
        # every point is on the section, crossing in the requested direction
        assert np.max(np.abs(r.section_residual)) <= 1e-14
        assert np.all(r.psi_dot_sign * r.branch > 0)


@pytest.mark.slow
def test_the_paper_panels_full_length_in_lanes():
    """All 8 panels, 10 000 iterates each (the paper's runs) in lanes: max |Hbar - h| <= 1.5e-13 on every one."""
    res = poincare_sections(KEYS, iterates=10_000, workers=2)
    for r in res:
        assert r.success and r.n_points == 10_000 and r.max_abs_dH <= DH_LANE, (r.panel, r.max_abs_dH)


def test_lanes_are_refilled_and_a_finished_lane_does_not_stop_the_others():
    """More orbits than lanes on one thread; one orbit stops early at its t_max guard (a lane freed mid-run),
    the others carry on; a start table (N, 2) runs N orbits on one level."""
    starts = np.array([[0.1, 0.5], [0.3, 0.0], [1.0, 0.2], [0.5, -0.3], [0.2, 0.4], [0.7, 0.1], [0.4, 0.3]])
    res = poincare_sections("4a", starts=starts, iterates=60, workers=1)
    assert len(res) == 7 and all(r.success and r.n_points == 60 for r in res)
    for r, (th, pt) in zip(res, starts):
        assert (r.theta0, r.ptheta0, r.h) == (th, pt, 0.9)
        # the level is the panel's: the root solver of the scalar path gives the same start
        one = poincare_section("4a", theta0=th, ptheta0=pt, iterates=1)
        assert r.p_psi0 == one.p_psi0
    short = poincare_sections(["4a", "4b", "4c", "5a", "5b"], iterates=200, t_max=500.0, workers=1)
    assert all(not r.success and "t_max" in r.message for r in short)
    assert all(r.final_time == 500.0 and 0 < r.n_points < 200 for r in short)


def test_branch_and_direction_filters_in_lanes():
    r0, rpi = poincare_sections(["4a", "4a"], iterates=40, branch="0"), poincare_sections(["4a"], iterates=40,
                                                                                         branch="pi")
    assert all(np.all(r.branch == 1) for r in r0) and np.all(rpi[0].branch == -1)
    neg = poincare_sections(["5a"], iterates=40, direction="negative")[0]
    assert np.all(neg.psi_dot_sign * neg.branch < 0)
    scalar = poincare_section("4a", iterates=40, branch="0")
    assert np.max(_body_diff(r0[0], scalar)[:5]) <= 1e-12


def test_configurations_without_a_batch_kernel_run_the_scalar_path_per_start():
    """The 4-D formulation, long double and stretch sampling have no batch kernel: they run the scalar path on
    threads, bit-identical to one call per start."""
    red = poincare_sections(["4a", "4d"], iterates=30, formulation="reduced")
    assert [r.formulation for r in red] == ["reduced", "reduced"]
    np.testing.assert_array_equal(red[1].points, poincare_section("4d", iterates=30, formulation="reduced").points)
    st = poincare_sections(["5a"], iterates=20, stretch_dt=0.05)[0]
    assert st.stretch is not None


def test_starts_with_pbar_psi0_on_and_off_the_level():
    s = poincare_section("4a", iterates=5)
    good = [[s.theta0, s.ptheta0, s.psi0, s.p_psi0]]
    r = poincare_sections(s.params, 0.9, starts=good, iterates=50)[0]
    assert r.success and r.p_psi0 == s.p_psi0 and r.roots.tolist() == [s.p_psi0]
    np.testing.assert_array_equal(r.points[:5], poincare_sections(["4a"], iterates=5)[0].points)
    off = [[s.theta0, s.ptheta0, s.psi0, s.p_psi0 + 1e-6]]
    with pytest.raises(ParameterError) as e:
        poincare_sections(s.params, 0.9, starts=off, iterates=5)
    assert e.value.name == "starts" and "off the level" in e.value.message and "start 0" in e.value.message
    assert START_LEVEL_TOL == section.ENERGY_TOL


@pytest.mark.parametrize("kw, name, words", [
    (dict(params=[]), "params", "empty"),
    (dict(params="4a", starts=np.zeros((0, 2))), "starts", "empty"),
    (dict(params="4a", starts=[[0.1, 0.5], [3.0, 9.0]]), "starts", "start 1"),  # no energy root
    (dict(params="4a", starts=[[0.1, 0.5], [0.0, 0.5]]), "starts", "start 1"),  # theta0 on the pole
    (dict(params="4a", starts=[[0.1, np.nan]]), "starts", "non-finite"),
    (dict(params="4a", starts=np.zeros((3, 5))), "starts", "shape"),
    (dict(params=["4a", "9z"]), "params", "entry 1"),
    (dict(params="4a", theta0=[0.1, 0.2], ptheta0=[0.5, 0.5, 0.5]), "theta0", "broadcast"),
])
def test_bad_many_start_input_names_the_option(kw, name, words):
    with pytest.raises(ParameterError) as e:
        poincare_sections(kw.pop("params"), iterates=5, **kw)
    assert e.value.name == name and words in e.value.message, (e.value.name, e.value.message)


def test_more_than_max_orbits_is_refused_before_any_work():
    with pytest.raises(ParameterError) as e:
        poincare_sections("4a", starts=np.full((MAX_ORBITS + 1, 2), 0.5), iterates=5)
    assert e.value.name == "starts" and str(MAX_ORBITS) in e.value.message


def test_the_accuracy_gate_refuses_every_lane_that_fails_it():
    """verify=True in lanes as in the scalar path: with an impossible energy tolerance every orbit is re-run once
    with freshly compiled code and then refused (success False, the reason in the message).  In a subprocess:
    the retry switches off heyoka's disk cache for the process."""
    code = ("from magrod.chaos import section; section.ENERGY_TOL = 1e-300\n"
            "rs = section.poincare_sections(['4a', '5a'], iterates=20)\n"
            "assert all(not r.success and 'accuracy check failed' in r.message and r.retried_without_jit_cache "
            "for r in rs), [(r.success, r.message) for r in rs]\n"
            "ok = section.poincare_sections(['4a', '5a'], iterates=20, verify=False)\n"
            "assert all(r.success for r in ok)\nprint('ok')\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0 and r.stdout.strip().endswith("ok"), r.stderr[-2000:]


def test_panel_objects_and_rodparams_lists():
    P = panel("5b")
    a = poincare_sections([P, "5b"], iterates=30)
    np.testing.assert_array_equal(a[0].points, a[1].points)
    p2 = P.params.replace(gamma=0.21)
    b = poincare_sections([P.params, p2], h=P.h, theta0=P.theta0, ptheta0=P.ptheta0, iterates=30)
    np.testing.assert_array_equal(b[0].points, a[0].points)
    assert b[1].params.gamma == 0.21 and b[1].success


def test_a_model_of_the_family_runs_on_two_processes(monkeypatch):
    """Another rod's lanes on two worker processes (batch width forced to 2, so that 6 starts make two processes on
    every machine; at the machine's own width 8 they were one and the path untested): each worker registers the
    model's body before its lanes look it up (a fresh process knew only the paper's rod: KeyError on the model's
    key).  The points are those of one worker."""
    from magrod.core import systems

    monkeypatch.setenv(systems.BATCH_WIDTH_ENV, "2")
    two = poincare_sections("kirchhoff", starts=6, iterates=15, workers=2)
    one = poincare_sections("kirchhoff", starts=6, iterates=15, workers=1)
    assert len(two) == len(one) == 6
    for a, b in zip(two, one):
        assert a.success and b.success
        assert np.array_equal(a.body_points, b.body_points)
