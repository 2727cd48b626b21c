"""Pseudo-arclength continuation (magrod.continuation) and homoclinic orbits to the periodic saddle
(magrod.homoclinic_periodic)."""
import math

import numpy as np
import pytest

from magrod import continuation as C
from magrod import homoclinic_periodic as hp
from magrod import shooting
from magrod.params import RodParams

EPS = np.finfo(float).eps
LAM_STAR_FIG6_N2 = 0.00126208079543  # docs/errata.md table: long double, eps = 1e-9, +-3.3e-14 (two eps, two precisions)


def _circle(u):
    return np.array([u[0] ** 2 + u[1] ** 2 - 1.0]), np.array([[2 * u[0], 2 * u[1]]])


def test_folds_of_a_circle_located_and_reproduced_back_and_forth():
    b = C.pseudo_arclength(_circle, [0.6, 0.8], ds=0.1, steps=40, par=0, ds_max=0.2)
    assert b.success and len(b.folds) >= 2
    for f in b.folds[:2]:
        assert abs(abs(f["u"][0]) - 1) <= 1e-12 and abs(f["u"][1]) <= 1e-5
    # across the fold at x = 1 and back (retracing: direction +1 at the last point, after the fold)
    fwd = C.pseudo_arclength(_circle, [0.9, math.sqrt(0.19)], ds=0.05, steps=6, par=0, direction=1)
    assert len(fwd.folds) == 1 and fwd.u[-1][1] < 0
    back = C.pseudo_arclength(_circle, fwd.u[-1], ds=0.07, steps=6, par=0, direction=1)
    assert len(back.folds) == 1
    for u in fwd.u:
        near = back.u[np.argmin(np.linalg.norm(back.u - u, axis=1))]
        v, _ = C.point_at(_circle, near, 0, u[0], scale=[1.0, 1.0])
        assert np.max(np.abs(v - u)) <= 1e-9


@pytest.fixture(scope="module")
def fig6_n2():
    r = shooting.shoot(RodParams(1.7, 2 * LAM_STAR_FIG6_N2, 1.0, 1.0, LAM_STAR_FIG6_N2), 2)
    assert r.success
    return r


def test_mu2lam_continuation_in_m_passes_through_fig6_two_pulse(fig6_n2):
    base = fig6_n2.params
    F, _ = C.mu2lam_problem(base, "m")
    scale = [fig6_n2.T, 1e-3, 1.0]
    u, _ = C.point_at(F, [fig6_n2.T, fig6_n2.params.lam, 1.69], 2, 1.69, scale=scale)
    br = C.pseudo_arclength(F, u, scale=scale, ds=0.01, ds_max=0.02, steps=5, par=2)
    assert br.success and br.u[-1, 2] > 1.7 and np.all(br.residuals <= 1e-10)
    i = int(np.argmin(np.abs(br.u[:, 2] - 1.7)))
    u17, res = C.point_at(F, br.u[i], 2, 1.7, scale=scale)
    assert res <= 1e-10
    assert abs(u17[1] / LAM_STAR_FIG6_N2 - 1) <= 1e-9
    # and back: the reversed run from the last point reproduces the branch points to 1e-9
    back = C.pseudo_arclength(F, br.u[-1], scale=scale, ds=0.01, ds_max=0.02, steps=5, par=2, direction=-1)
    for u_ in br.u[1:-1]:
        v, _ = C.point_at(F, back.u[np.argmin(np.abs(back.u[:, 2] - u_[2]))], 2, u_[2], scale=scale)
        assert np.max(np.abs((v - u_) / np.asarray(scale))) <= 1e-9


P = RodParams(1.7, 0.0021, 1.0, 1.0, 0.001)


@pytest.fixture(scope="module")
def primaries():
    return hp.find(P, 1, samples=91)


def test_primary_orbits_to_the_periodic_saddle(primaries):
    assert len(primaries) == 2
    for r in primaries:
        assert r.success and r.residual <= 1e-10 and r.energy_error <= 1e-13
        orb = hp.orbit(r)
        assert hp.count_pulses(r) == 1
        assert np.max(np.abs(orb["H"] - r.saddle.H)) <= 1e-13
        # generic: found at the printed lam = 0.001 with mu != 2 lam (no parameter freed)
        assert r.params == P


def test_periodic_branch_in_mu_reversible(primaries):
    r = primaries[0]
    F, _ = C.periodic_problem(P, "mu", 1)
    scale = [r.T, 1.0, 1e-4]
    fwd = C.pseudo_arclength(F, [r.T, r.angle, P.mu], scale=scale, ds=0.2, ds_max=0.3, steps=3, par=2)
    assert fwd.success and np.all(fwd.residuals <= 1e-10)
    back = C.pseudo_arclength(F, fwd.u[-1], scale=scale, ds=0.2, ds_max=0.3, steps=3, par=2, direction=-1)
    u_end, _ = C.point_at(F, back.u[np.argmin(np.abs(back.u[:, 2] - P.mu))], 2, P.mu, scale=scale)
    assert abs(u_end[0] - fwd.u[0][0]) <= 1e-9 * fwd.u[0][0]
    assert abs(math.remainder(u_end[1] - fwd.u[0][1], 2 * math.pi)) <= 1e-9


def test_mu2lam_continuation_in_gamma_from_fig6_two_pulse(fig6_n2):
    """Issue 13 item 3: the codimension-one Fig 6 two-pulse orbit continued on mu = 2 lam in gamma (the second
    parameter) from gamma = 1 a little way: the first corrected point is the orbit itself (lam* to 1e-9), the
    branch stays converged, and the reversed run reproduces its points to 1e-9 (scaled)."""
    F, params_of = C.mu2lam_problem(fig6_n2.params, "gamma")
    scale = [fig6_n2.T, 1e-3, 1.0]
    u0, res = C.point_at(F, [fig6_n2.T, fig6_n2.params.lam, 1.0], 2, 1.0, scale=scale)
    assert res <= 1e-10 and abs(u0[1] / fig6_n2.params.lam - 1) <= 1e-9
    br = C.pseudo_arclength(F, u0, scale=scale, ds=0.01, ds_max=0.02, steps=3, par=2)
    assert br.success and br.u[-1, 2] > 1.0 and np.all(br.residuals <= 1e-10)
    assert params_of(br.u[-1]).mu == pytest.approx(2 * br.u[-1, 1], rel=4 * EPS)  # stayed on mu = 2 lam
    back = C.pseudo_arclength(F, br.u[-1], scale=scale, ds=0.01, ds_max=0.02, steps=3, par=2, direction=-1)
    for u_ in br.u[1:-1]:
        v, _ = C.point_at(F, back.u[np.argmin(np.abs(back.u[:, 2] - u_[2]))], 2, u_[2], scale=scale)
        assert np.max(np.abs((v - u_) / np.asarray(scale))) <= 1e-9
