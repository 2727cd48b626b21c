"""magrod.proof.taylor: the validated C^1 Taylor integrator.  Every test checks that enclosures contain a known
solution: closed forms evaluated in ball arithmetic (linear saddle-focus, harmonic oscillator), the closed-form
lambdabar = 0 homoclinic orbit of derive/homoclinic.py (50-digit mpmath), and magrod's own long-double / real128
heyoka trajectories.  Widths against time are printed (pytest -s) and bounded where the method gives a bound."""
from __future__ import annotations

from fractions import Fraction

import mpmath
import numpy as np
import pytest
from flint import arb, arb_mat

from magrod.proof import ball, fields, taylor

PREC = 128


def _table(title, rows):
    print(f"\n{title}\n  t          max width")
    for t, w in rows:
        print(f"  {float(t):<10.4g} {w:.3e}")


# --------------------------------------------------------------------------------------------------------------
# a linear saddle-focus (exact flow): A = P diag(A_u, A_s) P^-1, A_u = [[a, b], [-b, a]], A_s = [[-a, b], [-b, -a]]
A_U = (Fraction(2, 3), Fraction(1, 2))
P = [[1, 0, Fraction(1, 3), 0], [Fraction(1, 5), 1, 0, Fraction(-1, 4)], [0, Fraction(1, 2), 1, 0],
     [Fraction(-1, 7), 0, Fraction(1, 6), 1]]


def _linear_saddle_focus():
    a, b = A_U
    D = [[a, b, 0, 0], [-b, a, 0, 0], [0, 0, -a, b], [0, 0, -b, -a]]
    Pm = np.array(P, dtype=object)
    Pinv = _rational_inverse(P)
    A = (Pm @ np.array(D, dtype=object) @ Pinv).tolist()
    return A, Pinv


def _rational_inverse(M):
    n = len(M)
    aug = [[Fraction(v) for v in row] + [Fraction(int(i == j)) for j in range(n)] for i, row in enumerate(M)]
    for c in range(n):
        piv = next(r for r in range(c, n) if aug[r][c] != 0)
        aug[c], aug[piv] = aug[piv], aug[c]
        pv = aug[c][c]
        aug[c] = [v / pv for v in aug[c]]
        for r in range(n):
            if r != c and aug[r][c] != 0:
                f = aug[r][c]
                aug[r] = [x - f * y for x, y in zip(aug[r], aug[c])]
    return np.array([row[n:] for row in aug], dtype=object)


def _exact_flow(t: Fraction) -> arb_mat:
    """e^{A t} = P diag(e^{a t} R(b t), e^{-a t} R(b t)) P^-1 in ball arithmetic."""
    a, b = (ball.q(x) for x in A_U)
    tt = ball.q(t)
    c, s = (b * tt).cos(), (b * tt).sin()
    eu, es = (a * tt).exp(), (-a * tt).exp()
    z = arb(0)
    D = arb_mat(4, 4, [eu * c, eu * s, z, z, -eu * s, eu * c, z, z, z, z, es * c, es * s, z, z, -es * s, es * c])
    Pq = arb_mat(4, 4, [ball.q(v) for row in P for v in row])
    _, Pinv = _linear_saddle_focus()
    Pi = arb_mat(4, 4, [ball.q(v) for row in Pinv.tolist() for v in row])
    return Pq * D * Pi


def test_linear_saddle_focus_enclosures_contain_the_exact_flow():
    A, _ = _linear_saddle_focus()
    x0 = [Fraction(1, 3), Fraction(-1, 5), Fraction(1, 7), Fraction(2, 9)]
    delta = Fraction(1, 10**12)
    rows = []
    with ball.workprec(PREC):
        fld = taylor.linear_field(A)
        S = taylor.initial_set([ball.q(v) for v in x0], radii=[delta] * 4)
        for t in (1, 2, 4, 8):
            S = taylor.propagate(fld, S, t, order=20)
            E = _exact_flow(Fraction(t))
            exact = ball.column(E * ball.vec([ball.q(v) for v in x0]))
            assert all(h.contains(e) for h, e in zip(S.hull(), exact)), t
            W = S.W()
            assert all(W[i, j].contains(E[i, j]) for i in range(4) for j in range(4)), t
            rows.append((t, max(S.widths())))
            # the set is the exact image of the initial box: width <= ||e^{At}||_inf-row sums * 2 delta (+ rounding)
            Ef = ball.to_floats(E)
            assert max(S.widths()) <= 2 * float(delta) * np.abs(Ef).sum(axis=1).max() * (1 + 1e-6) + 1e-30
    _table("linear saddle-focus, box 2e-12", rows)


def test_mutated_linear_field_is_not_contained():
    """The containment check can fail: integrate x' = (1 + 1e-9) A x against the exact flow of A."""
    A, _ = _linear_saddle_focus()
    Am = [[v * (1 + Fraction(1, 10**9)) for v in row] for row in A]
    x0 = [Fraction(1, 3), Fraction(-1, 5), Fraction(1, 7), Fraction(2, 9)]
    with ball.workprec(PREC):
        S = taylor.initial_set([ball.q(v) for v in x0], radii=[Fraction(1, 10**15)] * 4)
        S = taylor.propagate(taylor.linear_field(Am), S, 4, order=20)
        exact = ball.column(_exact_flow(Fraction(4)) * ball.vec([ball.q(v) for v in x0]))
        assert not all(h.contains(e) for h, e in zip(S.hull(), exact))


@pytest.mark.parametrize("T", [200, pytest.param(2000, marks=pytest.mark.slow)])
def test_harmonic_oscillator_over_long_times(T):
    """x'' = -x from (1, 0) +- delta: the exact flow is a rotation, so the hull of the rotated box is at most
    sqrt(2) times the box; Lohner's QR keeps the enclosure at that size over hundreds of periods."""
    delta = Fraction(1, 10**12)
    rows = []
    with ball.workprec(PREC):
        fld = taylor.linear_field([[0, 1], [-1, 0]])
        S = taylor.initial_set([ball.q(1), ball.q(0)], radii=[delta, delta])
        for t in np.linspace(T / 5, T, 5):
            t = Fraction(int(t))
            S = taylor.propagate(fld, S, t, order=20)
            tt = ball.q(t)
            assert S.hull()[0].contains(tt.cos()) and S.hull()[1].contains(-tt.sin())
            W = S.W()
            assert W[0, 0].contains(tt.cos()) and W[0, 1].contains(tt.sin())
            rows.append((t, max(S.widths())))
            assert max(S.widths()) <= 2 * float(delta) * 2**0.5 * (1 + 1e-6) + 1e-30
    _table(f"harmonic oscillator to t = {T}, box 2e-12", rows)


def test_a_priori_enclosure_fails_for_a_too_long_step():
    with ball.workprec(PREC):
        fld = taylor.linear_field([[0, 1], [-1, 0]])
        S = taylor.initial_set([ball.q(1), ball.q(0)])
        with pytest.raises(taylor.EnclosureError):
            taylor.step(fld, S, 64, 8)


# --------------------------------------------------------------------------------------------------------------
# the lambdabar = 0 homoclinic orbit (closed form, derive/homoclinic.py) in the body frame
def _closed_form(m, gamma, ts):
    import sympy as sp

    from magrod.derive import homoclinic as H
    from magrod.derive.paper import gamma as G
    from magrod.derive.paper import m as M

    up, omk, kap = H.regular_constants(M, G)
    f = sp.lambdify([H.t, M, G], H.regular_closed_form(H.t, up, omk, kap), "mpmath")
    with mpmath.workdps(50):
        mm = mpmath.mpf(m.numerator) / m.denominator
        gg = mpmath.mpf(gamma.numerator) / gamma.denominator
        return [[mpmath.mpf(v) for v in f(mpmath.mpf(t), mm, gg)] for t in ts]


def _lift_mp(q, pars):
    import sympy as sp

    from magrod.derive import numeric_scale as ns
    from magrod.derive.model import phi, psi, theta
    from magrod.derive.paper import delta, gamma, lambar, m, mu, pps, pth

    f = sp.lambdify([theta, psi, phi, pth, pps, m, mu, gamma, delta, lambar], ns.euler_to_body(), "mpmath")
    with mpmath.workdps(50):
        return f(*q, *pars)


def test_closed_form_homoclinic_orbit_lies_in_the_body_enclosures():
    """At mu = lambdabar = 0 the chart state of the homoclinic orbit is (theta(t), psi, pbar_theta(t), 1) in
    closed form; in the body frame e33 = cos theta and e32 m1 - e31 m2 = sin(theta) pbar_theta (report entry
    events_body), independent of the angles psi, phi.  Start at the turning point (t = 0) and integrate."""
    m, gamma = Fraction(17, 10), Fraction(1)
    p = fields.ExactParams(m, Fraction(0), gamma, Fraction(1), Fraction(0))
    ts = [Fraction(k, 2) for k in range(1, 13)]
    ref = _closed_form(m, gamma, [0] + [float(t) for t in ts])  # t = k/2: exact floats
    th0, pt0 = ref[0][0], ref[0][1]
    with mpmath.workdps(50):
        x0 = _lift_mp([th0, mpmath.mpf(0), mpmath.mpf(0), pt0, mpmath.mpf(1)],
                      [mpmath.mpf(17) / 10, 0, 1, 1, 0])
    rows = []
    with ball.workprec(PREC):
        x0b = [ball.q(Fraction(mpmath.nstr(v, 45))) for v in x0]
        S = taylor.initial_set(x0b, radii=[Fraction(1, 10**40)] * len(x0b))
        fld = fields.body_field(p)
        for t, r in zip(ts, ref[1:]):
            S = taylor.propagate(fld, S, t, order=20)
            ev = fields.body_events(p, S.hull())
            with mpmath.workdps(50):  # (the product too: mpmath's default is 53 bits)
                cos_t = ball.q(Fraction(mpmath.nstr(r[2], 45)))
                g = ball.q(Fraction(mpmath.nstr(r[3] * r[1], 45)))
            # the references are 45-digit decimals: widen by 1e-44
            tol = ball.interval(Fraction(-1, 10**44), Fraction(1, 10**44))
            # the exact value lies in the enclosure and within 1e-44 of the reference: the two must meet
            assert ev["e33"].overlaps(cos_t + tol), (t, ev["e33"], cos_t)
            assert ev["g"].overlaps(g + tol), (t, ev["g"], g)
            rows.append((t, max(S.widths())))
    _table("lambdabar = 0 homoclinic orbit (body frame), box 2e-40", rows)


# --------------------------------------------------------------------------------------------------------------
# magrod's own heyoka trajectories (long double, real128) inside the enclosures
T_HEYOKA = 5


@pytest.mark.parametrize("precision", ["long double", "quad"])
def test_heyoka_trajectories_lie_inside_the_chart_enclosures(precision):
    """W^u-like chart trajectory of the tilted saddle at the target (m, gamma, delta, mu, lam) = (1.7, 1, 1, 0.04,
    0.01): a box of radius 1e-15 (long double) / 1e-25 (quad) around an exact dyadic start, the heyoka trajectory
    from its centre in that precision must lie inside the enclosure at every step time."""
    import heyoka as hy

    from magrod.core import systems

    p = fields.ExactParams.from_values(m="1.7", mu="0.04", gamma=1, delta=1, lam="0.01")
    fp = {"long double": np.longdouble, "quad": hy.real128}[precision]
    rad = {"long double": Fraction(1, 10**15), "quad": Fraction(1, 10**25)}[precision]
    q0 = [0.1433, 0.0004, -0.0002, 0.99]
    pars = [fp(Fraction(v).numerator) / fp(Fraction(v).denominator) for v in p.as_json().values()]
    ta = systems.taylor(systems.system("reduced"), np.array([fp(v) for v in q0]), np.array(pars), fp_type=fp)
    rec = taylor.Trajectory()
    rows = []
    with ball.workprec(PREC):
        S = taylor.initial_set([ball.dyadic(v) for v in q0], radii=[rad] * 4)
        S = taylor.propagate(fields.chart_field(p), S, T_HEYOKA, order=20, record=rec)
    assert all(Fraction(float(t)) == t for t in rec.times)  # dyadic step times: exact in both precisions
    grid = np.array([fp(0)] + [fp(float(t)) for t in rec.times])
    states = ta.propagate_grid(grid)[-1][1:]
    with ball.workprec(PREC):
        S = taylor.initial_set([ball.dyadic(v) for v in q0], radii=[rad] * 4)
        for h, row in zip(rec.steps, states):
            S = taylor.step(fields.chart_field(p), S, h, 20)
            for v, hv in zip(S.hull(), row):
                # exact value of the long double; real128 printed with 36 digits (error 1e-36 << the widths)
                hq = ball.q(Fraction(str(hv)) if precision == "quad" else Fraction(*hv.as_integer_ratio()))
                assert v.contains(hq), (float(S.t), v, hv)
            rows.append((S.t, max(S.widths())))
    _table(f"chart, heyoka {precision} inside, box {float(rad):.0e}", rows[:: max(1, len(rows) // 8)])


def test_heyoka_variational_matrix_lies_inside_the_c1_enclosure():
    """The C^1 part in the body frame: DPhi_t from heyoka's variational equations in long double (from the centre
    of a 1e-15 box at the lifted target state) lies inside the enclosure Wbar + B E at t = 3."""
    from magrod.core import systems

    p = fields.ExactParams.from_values(m="1.7", mu="0.04", gamma=1, delta=1, lam="0.01")
    q0 = [0.1433, 0.0004, -0.0002, 0.99]
    with ball.workprec(PREC):
        x0 = [v.mid() for v in fields.lift(p, [ball.dyadic(v) for v in q0])]
        x0 = [ball.dyadic(float(v)) for v in x0]  # an exact double start, shared with heyoka
        S = taylor.initial_set(x0, radii=[Fraction(1, 10**15)] * len(x0))
        S = taylor.propagate(fields.body_field(p), S, 3, order=20)
        W = S.W()
    pars = np.array([np.longdouble(Fraction(v).numerator) / Fraction(v).denominator for v in p.as_json().values()])
    ta = systems.variational_integrator("body", wrt_pars=False, fp_type=np.longdouble)
    systems.reset_variational(ta, np.array([np.longdouble(float(v)) for v in x0]), pars)
    ta.propagate_until(np.longdouble(3))
    _, D, _ = systems.variational_blocks(ta)
    n = len(x0)
    # variational_blocks reads the long-double matrix out as float64: allow that rounding, 2^-52 max |D|
    tol = Fraction(2.0**-52 * float(np.abs(D).max()))
    inside = [[W[i, j].overlaps(ball.dyadic(float(D[i, j])) + ball.interval(-tol, tol)) for j in range(n)]
              for i in range(n)]
    assert all(all(r) for r in inside), inside
    # the check can fail: heyoka's DPhi at lambdabar (1 + 1e-6) is not inside
    lam = list(fields.PARAMS).index("lam")
    pm = pars.copy()
    pm[lam] *= np.longdouble(1 + 1e-6)
    systems.reset_variational(ta, np.array([np.longdouble(float(v)) for v in x0]), pm)
    ta.propagate_until(np.longdouble(3))
    Dm = systems.variational_blocks(ta)[1]
    assert not all(W[i, j].overlaps(ball.dyadic(float(Dm[i, j])) + ball.interval(-tol, tol))
                   for i in range(n) for j in range(n))
    print(f"\nbody DPhi(3): enclosure width {max(ball.width(v) for v in ball.entries(W)):.2e}, "
          f"max |DPhi| {float(np.abs(D).max()):.2e}, read-out tolerance {float(tol):.1e}")


# --------------------------------------------------------------------------------------------------------------
# Newton's iteration on power series (taylor._newton_series; the horseshoe's verifier flies with it, issue 27)
def _newton(fld):
    import dataclasses

    return dataclasses.replace(fld, series="newton")


def test_newton_series_contains_the_exact_linear_flow():
    """The linear saddle-focus flown with Newton's series: the enclosures contain the exact flow e^{At} x0 and
    e^{At}; the control (the field x' = (1 + 1e-9) A x) is not contained (seen to fail)."""
    A, _ = _linear_saddle_focus()
    x0 = [Fraction(1, 3), Fraction(-1, 5), Fraction(1, 7), Fraction(2, 9)]
    with ball.workprec(PREC):
        for Am, ok in ((A, True), ([[v * (1 + Fraction(1, 10**9)) for v in row] for row in A], False)):
            S = taylor.initial_set([ball.q(v) for v in x0], radii=[Fraction(1, 10**15)] * 4)
            S = taylor.propagate(_newton(taylor.linear_field(Am)), S, 4, order=20)
            E = _exact_flow(Fraction(4))
            exact = ball.column(E * ball.vec([ball.q(v) for v in x0]))
            assert all(h.contains(e) for h, e in zip(S.hull(), exact)) is ok
            if ok:
                W = S.W()
                assert all(W[i, j].contains(E[i, j]) for i in range(4) for j in range(4))


def test_newton_series_matches_picard_on_the_chart_field():
    """On the rod's chart field (Fig 4(a), a point and a 1e-8 box near the horseshoe's N0) Newton's coefficients
    overlap Picard's at every order and are no wider (max ratio 1 + 3e-9 measured, issue 27); a wrong Jacobian
    (zero) in Newton's correction gives coefficients disjoint from Picard's (the control: seen to fail)."""
    import dataclasses

    p = fields.ExactParams.from_values(m="17/10", mu="2/5", gamma="3", delta="3", lam="27/200")
    with ball.workprec(PREC):
        fld = fields.chart_field(p)
        zero = dataclasses.replace(fld, jacobian=lambda x, pars: [arb(0)] * 16)
        for r in ("0", "1e-8"):
            x0 = [arb(f"0.383 +/- {r}"), arb(f"0.001 +/- {r}"), arb(f"0.1 +/- {r}"), arb(f"1.1 +/- {r}")]
            for order in (20, 21):
                a, _ = taylor.solution_series(fld, x0, order)
                b, xs = taylor.solution_series(_newton(fld), x0, order)
                assert len(xs) == 4 and all(len(c) == order + 1 for c in b)
                for i in range(4):
                    for k in range(order + 1):
                        assert a[i][k].overlaps(b[i][k]), (i, k)
                        assert float(b[i][k].rad()) <= float(a[i][k].rad()) * (1 + 1e-6) + 1e-60, (i, k)
                c, _ = taylor.solution_series(_newton(zero), x0, order)
                assert not all(a[i][k].overlaps(c[i][k]) for i in range(4) for k in range(order + 1))


def test_interior_test_is_the_exact_rational_one():
    """taylor._inside (Arb's arb_contains_interior for finite balls) decides exactly as the rational comparison of
    ball.bounds, on random balls, equal balls, shared and touching endpoints, and non-finite balls."""
    import random

    def rational(a, b):
        for x, y in zip(a, b):
            lo, hi = ball.bounds(x)
            ylo, yhi = ball.bounds(y)
            if not (ylo < lo and hi < yhi):
                return False
        return True

    rng = random.Random(1)
    with ball.workprec(PREC):
        for _ in range(4000):
            m = rng.choice([0.0, 1.0, -1.0, rng.random()])
            r = rng.choice([0.0, 1e-30, rng.random() * 1e-3, 1.0])
            y = arb(m, r) if r else arb(m)
            lo, hi = ball.bounds(y)
            xs = [arb(m, r) if r else arb(m), arb(m + rng.random() * r * 0.5, r * 0.5) if r else arb(m), y.mid(),
                  ball.q(lo).mid() if lo == lo else y, ball.q(hi).mid(), ball.interval(lo, (lo + hi) / 2),
                  arb(rng.random(), rng.random() * 1e-3), arb("nan"), arb(0, float("inf"))]
            for x in xs:
                for a, b in ((x, y), (y, x)):
                    assert taylor._inside([a], [b]) == rational([a], [b]), (a, b)
