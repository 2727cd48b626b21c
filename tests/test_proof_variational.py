"""magrod.proof.variational: the section map's second derivatives against a closed form, and the variational
system's flight against the 5-state C^1 flight it extends (two methods, one enclosure)."""
import pytest

@pytest.mark.parametrize("mixed", [False, True])
def test_section_second_derivative_against_a_closed_form(mixed):
    """magrod.proof.variational's second derivative of a section point, d^2/ds^2 and the mixed d^2/da ds,
    by implicit differentiation at the crossing, on a field whose flow has a closed form and whose crossing time
    moves with both parameters: theta' = lam theta, psi' = 1 + theta^2, pbar_theta' = theta, pbar_psi' = 0,
    lam' = 0, started at (a0 + a + s, 0.1, b + 2 a, 0, l + s); the section psi = 2 pi.  Reference: the crossing time
    by findroot and P(a, s) differentiated by mpmath at 40 digits (a second, independent method)."""
    import mpmath as mp
    from flint import arb, arb_mat

    from magrod.proof import variational as hso
    mp.mp.dps = 40
    a0, b, l = mp.mpf("0.3"), mp.mpf("-0.2"), mp.mpf("0.7")

    def flow(t, a, s):
        th0, lam = a0 + a + s, l + s
        e = mp.exp(lam * t)
        return [th0 * e, mp.mpf("0.1") + t + th0**2 * (e**2 - 1) / (2 * lam), b + 2 * a + th0 * (e - 1) / lam, 0, lam]

    def P(a, s):
        t = mp.findroot(lambda t: flow(t, a, s)[1] - 2 * mp.pi, 5)
        x = flow(t, a, s)
        return [x[0], x[2]]

    t0 = mp.findroot(lambda t: flow(t, 0, 0)[1] - 2 * mp.pi, 5)
    x = flow(t0, 0, 0)
    u = [mp.diff(lambda s, i=i: flow(t0, 0, s)[i], 0) for i in range(5)]
    ua = [mp.diff(lambda a, i=i: flow(t0, a, 0)[i], 0) for i in range(5)] if mixed else None
    if mixed:
        dus = [mp.diff(lambda a, s, i=i: flow(t0, a, s)[i], (0, 0), (1, 1)) for i in range(5)]
        want = [mp.diff(lambda a, s, k=k: P(a, s)[k], (0, 0), (1, 1)) for k in (0, 1)]
    else:
        dus = [mp.diff(lambda s, i=i: flow(t0, 0, s)[i], 0, 2) for i in range(5)]
        want = [mp.diff(lambda s, k=k: P(0, s)[k], 0, 2) for k in (0, 1)]
    f = [x[4] * x[0], 1 + x[0] ** 2, x[0], 0, 0]
    Df = [[x[4], 0, 0, 0, x[0]], [2 * x[0], 0, 0, 0, 0], [1, 0, 0, 0, 0], [0] * 5, [0] * 5]

    def ar(v):
        return arb(mp.nstr(v, 40))

    P2, _ = hso.section_second_derivative([ar(v) for v in x], [ar(v) for v in u], [ar(v) for v in dus],
                                          [ar(v) for v in f], arb_mat([[ar(v) for v in row] for row in Df]),
                                          ua=None if ua is None else [ar(v) for v in ua])
    for got, w in zip(P2, want):
        assert abs(float(got.mid()) - float(w)) <= 1e-12 * abs(float(w)) and abs(float(w)) > 1e-2


def test_variational_flight_contains_the_c1_flights_derivative():
    """The 10-state set (x, lambdabar, u) flown by the Taylor-model integrator carries u = DPhi col; the 5-state C^1
    flight of the same set gives W col.  Both enclose the same derivative, so they overlap in every component; and
    the 10-state enclosure contains u flown from each corner of the set (thin flights, a second method).  With the
    duals' D^2 F[u] block replaced by 0 the set's u loses its dependence on the initial point and misses corners."""
    import itertools
    from fractions import Fraction as F

    from flint import arb

    from magrod.proof import ball, fields, taylor, taylor_model as tm
    from magrod.proof import variational as var

    p = fields.ExactParams(m=F(17, 10), mu=F(2, 5), gamma=F(3), delta=F(3), lam=F(27, 200))
    r = F(1, 10**5)
    with ball.workprec(128, 64):
        x0 = [F(3, 4), F(0), F(1, 2), F(11, 10), p.lam]
        S5 = taylor.initial_set([ball.q(v) for v in x0], radii=[r, 0, r, 0, r], c1=True)
        col = [ball.q(F(-4)), arb(0), ball.q(F(3)), ball.q(F(1, 2)), arb(1)]
        fld5 = fields.lam_state_field(p)
        fld10 = var.variational_field(fld5, 1)
        T = F(1)
        u5 = ball.column(tm.propagate(fld5, S5, T, order=16, tol=1e-20).W() * ball.vec(col))
        u10 = tm.propagate(fld10, var.extended_set(S5, [col], False), T, order=16, tol=1e-20).hull()[var.N:]
        for a, b in zip(u5, u10):
            assert a.overlaps(b), (a, b)
        for sg in itertools.product((-1, 1), repeat=3):
            xc = list(x0)
            xc[0], xc[2], xc[4] = x0[0] + sg[0] * r, x0[2] + sg[1] * r, x0[4] + sg[2] * r
            Sc = taylor.initial_set([ball.q(v) for v in xc] + list(col), c1=False)
            uc = tm.propagate(fld10, Sc, T, order=16, tol=1e-20).hull()[var.N:]
            assert all(b.contains(c.mid()) for b, c in zip(u10, uc)), sg
