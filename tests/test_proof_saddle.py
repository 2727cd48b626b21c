"""magrod.proof.saddle (Krawczyk enclosures of the tilted saddle and its eigenpairs) and magrod.proof.manifold
(cone/slab conditions for the local unstable manifold).  References: magrod's own float64 / long-double saddle
(magrod.separatrix.splitting.splitting_saddle), numpy's eigenvalues, and heyoka long-double points of W^u."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from magrod.core.params import RodParams
from magrod.proof import ball, fields, manifold, saddle
from magrod.proof.provers import transverse_homoclinic
from magrod.separatrix import splitting

TARGET = dict(m="1.7", mu="0.04", gamma=1, delta=1, lam="0.01")
PREC = 128


@pytest.fixture(scope="module")
def setup():
    p = fields.ExactParams.from_values(**TARGET)
    out = {"p": p}
    out["float"] = {pr: splitting.splitting_saddle(RodParams(*p.floats()), pr) for pr in ("double", "long double")}
    with ball.workprec(PREC):
        fld = fields.chart_field(p)
        xhat = saddle.refine(fld, [float(v) for v in out["float"]["long double"].q])
        J = ball.to_floats(fld.df(xhat).mid())
        w, Vc = np.linalg.eig(J)
        iu = next(i for i in range(len(w)) if w[i].real > 0 and w[i].imag > 0)
        is_ = next(i for i in range(len(w)) if w[i].real < 0 and w[i].imag > 0)
        guess = [(w[iu], Vc[:, iu]), (w[is_], Vc[:, is_])]
        E = saddle.enclose(fld, xhat, Fraction(1, 10**12), eig_guess=guess, eig_rad=Fraction(1, 10**12))
        Vf = np.column_stack(transverse_homoclinic._real_basis(Vc[:, iu]) + transverse_homoclinic._real_basis(Vc[:, is_]))
        out.update(fld=fld, E=E, w=w, Vf=Vf, V=ball.exact_matrix(Vf.tolist()))
    return out


def test_krawczyk_box_contains_the_float_saddle(setup):
    E = setup["E"]
    assert all(E.checks.values()), E.checks
    for pr, sd in setup["float"].items():
        q = [Fraction(*v.as_integer_ratio()) for v in sd.q]  # exact values of the floats
        assert all(ball.bounds(X)[0] <= v <= ball.bounds(X)[1] for X, v in zip(E.X, q)), pr
        # and the (much tighter) Krawczyk image is within the float's own error (|q| ~ 1, a few ulp)
        ulp = {"double": Fraction(1, 2**52), "long double": Fraction(1, 2**63)}[pr]
        for K, v in zip(E.K, q):
            assert abs(ball.fraction(K.mid()) - v) <= 64 * ulp, pr
    # psi = pbar_theta = 0 exactly is inside K (the saddle lies on Fix(R))
    assert E.K[fields.PSI].contains(0) and E.K[fields.PTHETA].contains(0)


def test_eigenpair_boxes_contain_numpy_and_the_spectrum_is_a_saddle_focus(setup):
    E, w = setup["E"], setup["w"]
    lu = next(z for z in w if z.real > 0 and z.imag > 0)
    ls = next(z for z in w if z.real < 0 and z.imag > 0)
    for ball_, z in ((E.lam_u, lu), (E.lam_s, ls)):
        assert abs(float(ball_.real.mid()) - z.real) < 1e-12 and abs(float(ball_.imag.mid()) - z.imag) < 1e-12
    # the printed values: +-0.670 +- 0.486 i at the target
    assert round(float(E.lam_u.real.mid()), 3) == 0.670 and round(float(E.lam_u.imag.mid()), 3) == 0.486
    # Hamiltonian spectrum: lambda_s = -conj(lambda_u), and the enclosures say so
    assert (E.lam_u.real + E.lam_s.real).contains(0) and (E.lam_u.imag - E.lam_s.imag).contains(0)


def test_krawczyk_rejects_a_box_without_the_zero(setup):
    """The check can fail: a box of the same size shifted off the saddle by 1e-6 in theta."""
    fld, E = setup["fld"], setup["E"]
    with ball.workprec(PREC):
        xs = list(E.xhat)
        xs[fields.THETA] = (xs[fields.THETA] + ball.q(Fraction(1, 10**6))).mid()
        X = [ball.interval(ball.fraction(x) - Fraction(1, 10**12), ball.fraction(x) + Fraction(1, 10**12)) for x in xs]
        _, inside = saddle.krawczyk(fld.f, fld.df, xs, X)
    assert not inside


def test_enclosure_does_not_contain_the_saddle_of_a_mutated_parameter(setup):
    sd = splitting.splitting_saddle(RodParams(1.7, 0.0401, 1.0, 1.0, 0.01), "long double")
    E = setup["E"]
    assert not E.K[fields.THETA].contains(ball.q(Fraction(*sd.q[0].as_integer_ratio())))


# --------------------------------------------------------------------------------------------------------------
def test_cone_conditions_hold_at_the_circle_radius_and_fail_when_too_large(setup):
    fld, E, V = setup["fld"], setup["E"], setup["V"]
    with ball.workprec(PREC):
        man = manifold.choose(fld, E.xhat, V, E.K, Fraction(1, 10**5))
        assert man.ok, man.checks
        # slope and slab are O(r) and O(r^2): L ~ c_su/alpha, rho ~ c_su r/alpha
        assert man.L < Fraction(1, 1000) and man.rho_eff < Fraction(1, 10**8)
        big = manifold.choose(fld, E.xhat, V, E.K, Fraction(1, 10))
        assert not big.ok  # r = 0.1 is comparable to theta0 = 0.14: the nonlinearity breaks the cone
    print(f"\nr = 1e-5: rho = {float(man.rho):.3e}, rho_eff = {float(man.rho_eff):.3e}, L = {float(man.L):.3e}")


def test_float_points_of_the_unstable_manifold_lie_in_the_slab(setup):
    """heyoka long double from the linear manifold at |u| = 1e-12 (off W^u by O(1e-24)) forward to |u| ~ r: the
    stable coordinate s of each point must obey |s| <= S + L (|u| + U) (the graph bound through the saddle); a
    point moved off W^u by 10 rho_eff does not."""
    import heyoka as hy  # noqa: F401

    from magrod.core import systems

    fld, E, V, Vf = setup["fld"], setup["E"], setup["V"], setup["Vf"]
    p = setup["p"]
    with ball.workprec(PREC):
        man = manifold.choose(fld, E.xhat, V, E.K, Fraction(1, 10**5))
    xh = np.array([np.longdouble(ball.fraction(v).numerator) / np.longdouble(ball.fraction(v).denominator)
                   for v in E.xhat])
    Vl = Vf.astype(np.longdouble)
    Vi = np.linalg.inv(Vf)
    pars = np.array([np.longdouble(Fraction(v).numerator) / Fraction(v).denominator for v in p.as_json().values()])
    ta = systems.taylor(systems.system("reduced"), xh, pars, fp_type=np.longdouble)
    b = man.bounds
    worst = 0.0
    for phi in np.linspace(0, 2 * np.pi, 7)[:-1]:
        ta.time = np.longdouble(0)
        ta.state[:] = xh + Vl[:, :2] @ (np.longdouble(1e-12) * np.array([np.cos(phi), np.sin(phi)], dtype=np.longdouble))
        for _ in range(200):
            ta.step()
            y = Vi @ (ta.state - xh).astype(float)
            if np.hypot(*y[:2]) > 0.9 * float(man.r):
                break
            if ta.time > 60:
                raise AssertionError("never reached the circle")
        u, s = np.hypot(*y[:2]), np.hypot(*y[2:])
        bound = float(b["S"] + man.L * (Fraction(u) + b["U"]))
        # float error of y: |xh| ulp (long double) times ||V^-1||
        err = 1e-18 * np.linalg.norm(Vi, 2)
        assert s <= bound + err, (phi, u, s, bound)
        assert not np.hypot(*(y[2:] + 10 * float(man.rho_eff))) <= bound  # the check can fail
        worst = max(worst, s / bound)
    print(f"\nW^u points: max |s| / (S + L |u|) = {worst:.3g} (must be <= 1)")
