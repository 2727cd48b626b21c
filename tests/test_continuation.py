"""Pseudo-arclength continuation (magrod.orbits.continuation) and homoclinic orbits to the periodic saddle
(magrod.orbits.periodic_homoclinic)."""
import math

import numpy as np
import pytest

from magrod.orbits import continuation as C
from magrod.orbits import multipulse
from magrod.orbits import periodic_multipulse as hp
from magrod.orbits import shooting
from magrod.orbits.equilibrium import straight_rod
from magrod.orbits.periodic import periodic_saddle
from magrod.generated import scalars
from magrod.core.params import RodParams

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
    r = multipulse.shoot(RodParams(1.7, 2 * LAM_STAR_FIG6_N2, 1.0, 1.0, LAM_STAR_FIG6_N2), 2)
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


# --- a genuine fold: 2-pulse orbits to the periodic saddle continued in mu --------------------------------------
# At lam = 0.001, m = 1.7, gamma = delta = 1 a branch of symmetric 2-pulse orbits (launch angle ~ 20.07, i.e.
# 1.228 mod 2 pi, T ~ 42.9 at eps = 1e-9, long double) folds in mu at mu - 2 lam ~ 2.86e-3: far from the chart
# singularity at mu = 2 lam (the primaries' fold at mu - 2 lam ~ 7e-13 is not a usable test).  Newton on this branch
# reaches |F| ~ 1e-13 .. 1e-12 (long double noise), so the corrector runs at tol 2e-12.
FOLD_TOL = 2e-12
FOLD_SCALE = np.array([40.0, 1.0, 1e-4])


def _fold_problem():
    return C.periodic_problem(P, "mu", 2)


def _xT(params_of, u):
    r = hp.shoot(params_of(u), 2, u[1], u[0], tol=1.0)  # tol 1: no Newton step, just the orbit at (T, angle)
    return r, np.asarray(r.xT, float)


def _across_and_back(mu0, steps, ds):
    F, params_of = _fold_problem()
    u0, res = C.point_at(F, [42.9, 20.07, mu0], 2, mu0, scale=FOLD_SCALE, tol=FOLD_TOL)
    kw = dict(scale=FOLD_SCALE, ds=ds, ds_max=ds, steps=steps, par=2, direction=-1, tol=FOLD_TOL,
              names=("T", "angle", "mu"))
    fwd = C.pseudo_arclength(F, u0, **kw)
    # back across the fold from the last point, until it is crossed: how far each step goes depends on whether the
    # corrector meets FOLD_TOL at the full step (long double noise ~1e-13..1e-12 against 2e-12), which the rounding
    # of the CPU decides (on one Intel Xeon the back run halved its first step and stopped 5e-10 short of the fold
    # after steps + 1 points); the points it computes agree to 1e-9 on every CPU, the step sizes need not
    back = C.pseudo_arclength(F, fwd.u[-1], **{**kw, "steps": 1})
    for _ in range(3 * steps):
        if back.folds:
            break
        more = C.pseudo_arclength(F, back.u[-1], **{**kw, "steps": 1})
        back = _joined(back, more)
    return F, params_of, fwd, back


def _joined(a, b):
    """Branch a followed by branch b (b starts at a's last point; a fold of b is re-indexed)."""
    from dataclasses import replace

    n = len(a.u) - 1
    return replace(a, u=np.vstack([a.u, b.u[1:]]), tangents=np.vstack([a.tangents, b.tangents[1:]]),
                   residuals=np.r_[a.residuals, b.residuals[1:]], iterations=np.r_[a.iterations, b.iterations[1:]],
                   folds=a.folds + [{**f, "index": f["index"] + n} for f in b.folds], message=b.message)


def _check_fold_and_points(F, fwd, back):
    assert fwd.success and back.success
    assert np.all(fwd.residuals <= FOLD_TOL) and np.all(back.residuals <= FOLD_TOL)
    assert len(fwd.folds) == 1 and len(back.folds) == 1
    ff, fb = fwd.folds[0]["u"], back.folds[0]["u"]
    # a fold of mu: the branch lies on one side, both arms on it were visited
    assert np.all(fwd.u[:, 2] >= ff[2]) and fwd.u[0, 0] < ff[0] < fwd.u[-1, 0]
    assert abs(fb[2] / ff[2] - 1) <= 1e-9 and abs(fb[0] / ff[0] - 1) <= 1e-9 and abs(fb[1] - ff[1]) <= 1e-9
    # every forward point is reproduced by the backward run: correct the nearest backward point onto the forward
    # point's pseudo-arclength hyperplane (well conditioned also at the fold)
    out = []
    for u, t in zip(fwd.u, fwd.tangents):
        near = back.u[np.argmin(np.linalg.norm((back.u - u) / FOLD_SCALE, axis=1))]
        tt = t * FOLD_SCALE / np.linalg.norm(t * FOLD_SCALE)
        v, res, *_ = C.correct(F, u, tt, scale=FOLD_SCALE, tol=FOLD_TOL, start=near)
        assert abs(v[0] / u[0] - 1) <= 1e-9 and abs(v[1] - u[1]) <= 1e-9 and abs(v[2] / u[2] - 1) <= 1e-9
        out.append(v)
    return ff, np.array(out)


def test_two_pulse_branch_folds_in_mu_and_steps_across_it_reproduce_the_orbits():
    """Must hold (issue 13): continuation steps back and forth across a fold reproduce the same orbits to 1e-9 --
    on a real branch: forward across the fold, back across it from the last point; the fold located from either
    side and every forward point agree to 1e-9 (T and mu relative, launch angle absolute)."""
    F, _, fwd, back = _across_and_back(4.8625e-3, 3, 0.05)
    ff, _ = _check_fold_and_points(F, fwd, back)
    assert 4.8e-3 < ff[2] < 4.9e-3  # mu - 2 lam ~ 2.86e-3: far from the chart singularity at mu = 2 lam


@pytest.mark.slow
def test_two_pulse_fold_back_and_forth_states_at_matched_mu():
    """Full version: a longer excursion over the fold; at each forward point's mu the backward branch gives the same
    (T, angle) and the same state x(T) at the symmetric point to 1e-9, and both arms are 2-pulse orbits."""
    F, params_of, fwd, back = _across_and_back(4.87e-3, 6, 0.1)
    ff, matched = _check_fold_and_points(F, fwd, back)
    for u, v in zip(fwd.u, matched):
        w, res = C.point_at(F, v, 2, u[2], scale=FOLD_SCALE, tol=FOLD_TOL)  # same mu, from the backward run
        assert res <= FOLD_TOL and abs(w[0] / u[0] - 1) <= 1e-9 and abs(w[1] - u[1]) <= 1e-9
        ru, xu = _xT(params_of, u)
        _, xw = _xT(params_of, w)
        assert np.max(np.abs(xw - xu)) <= 1e-9
        assert hp.count_pulses(ru) == 2


def test_primaries_tend_to_the_mu_2lam_limits():
    """Must hold (issue 13): what the generic-case branches do as mu -> 2 lam.  The two primary orbits at lam =
    0.001 (eps = 1e-7) followed down mu - 2 lam = 1e-4 .. 1e-10 (natural continuation, Newton from the previous
    decade):
      * T tends to T0, the time from the straight rod (launched at the same eps on mu = 2 lam) to its first turning
        point (an independent computation: magrod.orbits.shooting.unstable_branch), |T - T0| <= 2e-6 below 1e-8;
      * the launch angles stay symmetric about a fixed midpoint (2.870125) and spread apart from pi as
        b - a - pi = -2 asin(c / sqrt(mu - 2 lam)): sin psi at the turning point is psi0 + A sqrt(gap) cos(angle -
        angle0) to leading order, psi0 = psi at the straight rod's turning point, c = |psi0| / A.  The two
        primaries merge at the midpoint when sqrt(gap) = c (the fold reported in docs/errata.md)."""
    mu0 = scalars.straight_rod_mu(**P.to_dict())
    turn = shooting.unstable_branch(straight_rod(P.replace(mu=mu0)), crossings=1, launch_distance=1e-7)[0]
    prim = [(26.4567663389, 1.298695337565), (26.4567330589, 4.440084038851)]  # docs/errata.md table, gap 1e-4
    rows = {}
    for gap in (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10):
        p = P.replace(mu=mu0 + gap)
        rs = [hp.shoot(p, 1, a, T, launch_distance=1e-7) for T, a in prim]
        assert all(r.success and r.residual <= 1e-10 and hp.count_pulses(r) == 1 for r in rs)
        prim = [(r.T, r.angle) for r in rs]
        rows[gap] = prim
    dT = {g: max(abs(T - turn.t) for T, _ in v) for g, v in rows.items()}
    assert dT[1e-4] > dT[1e-5] > dT[1e-6] > dT[1e-7] and dT[1e-4] < 2e-3
    assert all(dT[g] <= 2e-6 for g in (1e-8, 1e-9, 1e-10))
    mid = {g: (v[0][1] + v[1][1]) / 2 for g, v in rows.items()}
    assert all(abs(mid[g] - mid[1e-10]) <= 1e-5 for g in (1e-6, 1e-7, 1e-8, 1e-9))
    spread = {g: v[1][1] - v[0][1] - math.pi for g, v in rows.items()}
    c = {g: math.sin(-spread[g] / 2) * math.sqrt(g) for g in (1e-7, 1e-8, 1e-9, 1e-10)}
    assert all(abs(c[g] / c[1e-9] - 1) <= 1e-2 for g in c)  # the sqrt(gap) law, c = 8.30e-7
    # c = |psi0| / A with A from the range of sin psi over a launch-angle scan at gap = 1e-8 (half-width / sqrt(gap))
    _, _, sp = hp.scan_angles(periodic_saddle(P.replace(mu=mu0 + 1e-8)), 1, 61, launch_distance=1e-7)
    A = (np.nanmax(sp) - np.nanmin(sp)) / 2 / math.sqrt(1e-8)
    assert abs(c[1e-9] * A / abs(turn.psi) - 1) <= 2e-2


def test_three_pulse_orbits_to_the_periodic_saddle():
    """Issue 13: genuine 3-pulse orbits (symmetric point at the middle pulse's maximum).  find() scans, bisects and
    runs Newton at one launch distance (eps = 1e-9, long double); it used to scan at 1e-7 and shoot at 1e-9 and slid
    onto 2-pulse orbits.  Check against the launch-distance law: the same orbit launched at eps = 1e-7 (double)
    reaches its symmetric point ln(100)/a earlier, a = ln|Lambda_u| / T_periodic (the Floquet exponent)."""
    found = hp.find(P, 3, samples=181)
    assert len(found) == 2
    for r in found:
        assert r.success and r.residual <= 1e-10 and r.energy_error <= 1e-13 and r.launch_distance == 1e-9
        assert hp.count_pulses(r) == 3
        a = math.log(abs(r.saddle.unstable_multiplier)) / r.saddle.T
        shift = math.log(100.0) / a  # 6.929
        b = math.atan2(r.saddle.unstable_multiplier.imag, r.saddle.unstable_multiplier.real) / r.saddle.T
        r7 = hp.shoot(P, 3, r.angle - math.remainder(b * shift, math.pi), r.T - shift, launch_distance=1e-7, precision="double",
                      saddle=r.saddle)
        assert r7.success and hp.count_pulses(r7) == 3
        assert abs((r.T - r7.T) / shift - 1) <= 1e-3  # O(eps) corrections to the linear launch
