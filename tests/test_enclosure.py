"""magrod.separatrix.enclosure: the splitting integral S at mu = 2 lambdabar in ball arithmetic (issue 20).

References: magrod's independent heyoka quadrature of the same integral in IEEE quad (magrod.splitting.
leading_coefficient: a different integrand form -- theta, pbar_theta of the closed form, Psi integrated as an ODE
-- and a different method), with its stated asymptotic tail error; the integrable control gamma = delta = 0
(S = 0 exactly: the rod is integrable for every lambdabar); a mutated integrand generated from derive/."""
import math
from fractions import Fraction

import pytest

flint = pytest.importorskip("flint")

from magrod.core.errors import ParameterError  # noqa: E402
from magrod.separatrix import enclosure as E  # noqa: E402

# the six (m, gamma, delta) of the a = 2b table of docs/nonintegrability.md
TABLE = [(1.7, 1.0, 1.0), (1.7, 1.0, 0.0), (1.7, 0.0, 1.0), (1.2, 0.5, 2.0), (2.2, 2.0, 0.5), (1.0, 0.0, 1.0)]


@pytest.fixture(scope="module")
def references():
    """real128 values of S (heyoka, tol 1e-32) and their stated tail errors, at the float parameters (the
    enclosure converts the same floats exactly, so both compute S at the same rational point)."""
    from magrod.separatrix import splitting as S

    out = {}
    for p in TABLE:
        lt = S.leading_coefficient(*p)
        out[p] = (lt.S_reference_text, lt.tail_estimate)
    return out


@pytest.mark.parametrize("p", TABLE)
def test_ball_at_the_table_points(p, references):
    r = E.enclose_S(*p)
    ref, tail = references[p]
    assert r.radius <= 1e-10
    assert r.excludes_zero and r.sign == -1
    # the real128 value lies in the ball widened by that value's own stated (asymptotic) tail error; 1e-32: the
    # real128 quadrature tolerance and its 36-digit decimal string
    assert r.contains(ref, tol=tail + 1e-32), (r, ref, tail)
    # the ball is much tighter than the comparison: the two methods agree to the real128 tail error
    assert abs(float(r.S.mid()) - float(ref)) <= tail + 1e-15
    d = r.to_dict()
    assert d["tail_bound"] > 0 and d["T"] and d["integral_0_T"]["rad"] <= 1e-10  # both parts stated


@pytest.mark.parametrize("m", ["1.7", "1", "0.5"])
def test_integrable_control_contains_zero(m):
    r = E.enclose_S(m, 0, 0)
    assert r.S.contains(0) and r.sign is None and r.radius < 1e-18


def test_exact_inputs_are_the_same_number():
    a = E.enclose_S("1.7", 1, "1")
    b = E.enclose_S(Fraction(17, 10), flint.fmpq(1), 1)
    assert a.m == b.m == "17/10" and a.S.overlaps(b.S)
    c = E.enclose_S(1.7, 1, 1)  # the float 1.7 is another rational: 1.7 + 4.4e-17 ...
    assert c.m != "17/10" and Fraction(c.m) == Fraction(1.7)


@pytest.fixture(scope="module")
def mutated_module():
    """The generated ball code with ONE sign flipped in Re G/s (the delta/m^2 term of Re G = -pbar_theta (J/sin^2
    + delta/m^2)), generated from derive/ exactly as generated/splitting_ball.py is."""
    import sympy as sp

    from magrod.derive import splitting as D
    from magrod.derive.paper import delta

    om, kp = sp.symbols("omega kappa", positive=True)
    nr, ni = D.scaled_forcing(om, kp)
    nr_mut = nr.subs(delta, -delta)  # flips exactly the sign of the delta term (nr is affine in delta)
    assert sp.simplify(nr_mut - nr) != 0 and sp.simplify(sp.diff(nr_mut + nr, delta)) == 0
    src = D.ball_module(nr=nr_mut, ni=ni, gradient=False)
    ns = {}
    exec(compile(src, "<mutated splitting_ball>", "exec"), ns)  # noqa: S102 - our own generated source
    return type("Mutated", (), {k: staticmethod(v) if callable(v) else v for k, v in ns.items()})


def test_mutated_sign_is_detected(mutated_module, references):
    p = TABLE[0]
    ref, tail = references[p]
    good = E.enclose_S(*p)
    bad = E.enclose_S(*p, module=mutated_module)
    assert good.contains(ref, tol=tail + 1e-32)
    assert not bad.contains(ref, tol=1e-6), bad  # the mutation moves S by O(1)


@pytest.mark.parametrize("args, name", [
    (("2.9", 1, 1), "m"),          # m_c = 2 sqrt(2) = 2.828...
    ((2, 0, 1), "m"),              # m = m_c exactly (decided in exact arithmetic)
    ((0, 1, 1), "m"),
    (("1.7", -1, 1), "gamma"),
    (("1.7", 1, "-0.5"), "delta"),  # gamma + delta >= 0 and delta >= 0 (eq:nondim_1)
    ((math.nan, 1, 1), "m"),
    (("abc", 1, 1), "m"),
    ((None, 1, 1), "m"),
    ((True, 1, 1), "m"),
    ((1.7, 1, 10**7), "delta"),
])
def test_bad_input_names_the_parameter(args, name):
    with pytest.raises(ParameterError) as ei:
        E.enclose_S(*args)
    assert ei.value.name == name


def test_bad_options():
    with pytest.raises(ParameterError, match="prec"):
        E.enclose_S(1, 1, 1, prec=10)
    with pytest.raises(ParameterError, match="tail_tol"):
        E.enclose_S(1, 1, 1, tail_tol=1.0)


# --- the parameter-box theorem -------------------------------------------------------------------------------
def test_box_theorem_small_box():
    """One box around the printed point m = 1.7, gamma = delta = 1: S < 0 on all of it; the box's ball contains
    the point values at its corners (each enclosed separately)."""
    r = E.box_theorem(("1.65", "1.75"), ("0.95", "1.05"), ("0.5", "1.5"), initial=(1, 1, 1))
    assert r.success and r.signs == {"-1": len(r.decided)} and not r.zeros
    assert "computer-verified: S(m, gamma, delta) < 0" in r.statement
    for mm, gg, dd in (("1.65", "0.95", "0.5"), ("1.75", "1.05", "1.5")):
        v = E.enclose_S(mm, gg, dd, prec=64)
        box = next(b for b in r.decided if Fraction(b.m[0]) <= Fraction(mm) <= Fraction(b.m[1])
                   and Fraction(b.gamma[0]) <= Fraction(gg) <= Fraction(b.gamma[1])
                   and Fraction(b.delta[0]) <= Fraction(dd) <= Fraction(b.delta[1]))
        lo, hi = E.outward(v.S)
        assert Fraction(box.S_lo) <= Fraction(lo) and Fraction(hi) <= Fraction(box.S_hi)


def test_outward_strings_are_exact_bounds():
    """Issue 27: the stored ends are exact decimals rounded outward (a float of Arb's end point is not a bound), and
    the box's S reads as the interval it is, never Arb's "[+/- r]" (which hides the sign)."""
    from flint import arb

    x = arb(-2) / 3
    lo, hi = E.outward(x, digits=6)
    assert (lo, hi) == ("-0.666667", "-0.666666")
    assert Fraction(lo) < Fraction(-2, 3) < Fraction(hi)
    y = arb(-1.1, 0.9)  # Arb prints this as [-1e+0 +/- 0.91]; it lies in [-2, -0.2]
    lo, hi = E.outward(y, digits=3)
    assert Fraction(lo) <= Fraction(-2) and Fraction("-0.2") <= Fraction(hi) < 0
    assert E.outward(arb(0, float("inf"))) == ("-inf", "inf")
    assert E.outward(arb(5)) == ("5", "5")


def test_a_box_without_a_tail_bound_is_undecided_never_decided(monkeypatch):
    """Where no tail cut exists for a box (near m_c), its S is unknown: the box must be split or reported undecided.
    (The "unknown" ball was once arb('inf'), the point +inf, which compares > 0: such a box came out "S > 0".)"""
    def no_cut(*a, **k):
        raise E._NoCut("no cut (test)")

    monkeypatch.setattr(E, "_choose_T", no_cut)
    r = E.box_theorem(("1.65", "1.75"), ("0.95", "1.05"), ("0.5", "1.5"), initial=(1, 1, 1), min_width=0.6)
    assert r.decided == [] and len(r.undecided) >= 1 and r.zeros == []
    assert "1" not in r.signs and "-1" not in r.signs


def test_box_theorem_cannot_decide_where_S_vanishes():
    """A box touching the integrable corner gamma = delta = 0 (S = 0 there) must stay undecided."""
    r = E.box_theorem(("1.6", "1.7"), ("0", "0.05"), ("0", "0.05"), initial=(1, 1, 1), min_width=0.3)
    assert not r.success and r.undecided and "partial" in r.statement


class _DeltaFlipped:
    """The true ball code evaluated at -delta: S_flip(m, gamma, delta) = S(m, gamma, -delta) (N is affine in delta and
    delta enters only through Re G/s, Im G/s), so S_flip has a zero delta* = S(., 0)/(S(., 1) - S(., 0)) > 0."""

    from magrod.generated import splitting_ball as _g

    BRANCH_KINDS = _g.BRANCH_KINDS
    orbit_constants = staticmethod(_g.orbit_constants)
    branch_arguments = staticmethod(_g.branch_arguments)
    tail_quantities = staticmethod(_g.tail_quantities)
    tan_half_turn = staticmethod(_g.tan_half_turn)

    @staticmethod
    def integrand(t, m, g, d):
        return _DeltaFlipped._g.integrand(t, m, g, -d)

    @staticmethod
    def integrand_gradient(t, m, g, d):
        a, b, c = _DeltaFlipped._g.integrand_gradient(t, m, g, -d)
        return [a, b, -c]

    @staticmethod
    def tail_factors(s, c, TH, D, m, g, d):
        return _DeltaFlipped._g.tail_factors(s, c, TH, D, m, g, -d)


def test_box_theorem_locates_a_zero():
    r = E.box_theorem(("1.699", "1.701"), ("0.999", "1.001"), ("0.3", "0.45"), initial=(1, 1, 1), min_width=0.5,
                      module=_DeltaFlipped)
    assert r.zeros and not r.success
    s0 = E.enclose_S("1.7", 1, 0, prec=64).S
    s1 = E.enclose_S("1.7", 1, 1, prec=64).S
    dstar = float((s0 / (s1 - s0)).mid())  # S_flip(delta) = s0 - delta (s1 - s0): zero at s0/(s1 - s0)
    assert 0.3 < dstar < 0.45
    # the located ball (for (m, gamma) in the rectangle) contains the zero at its centre
    z = r.zeros[0]
    assert abs(z["delta_star_mid"] - dstar) <= z["delta_star_rad"] + 1e-12


@pytest.mark.parametrize("kw, name", [
    ({"m": ("1.8", "1.7")}, "m"),             # inverted
    ({"m": ("1.7", "1.7")}, "m"),             # empty
    ({"gamma": ("1", "0.5")}, "gamma"),
    ({"delta": ("-0.1", "1")}, "delta"),
    ({"gamma": ("-0.5", "1")}, "gamma"),
    ({"m": ("2", "2.3"), "gamma": ("0.25", "1")}, "m"),   # m_hi = 2.3 > 2 sqrt(1.25) = 2.236
    ({"m": "1.7"}, "m"),
    ({"initial": (0, 1, 1)}, "initial"),
])
def test_box_theorem_bad_input(kw, name):
    with pytest.raises(ParameterError) as ei:
        E.box_theorem(**kw)
    assert ei.value.name == name


@pytest.mark.slow
def test_box_theorem_slice():
    """A slice of the issue's box (the full coverage is benchmarks/enclosure_boxes.py)."""
    r = E.box_theorem(("1.0", "1.4"), ("0.25", "1.25"), ("0.25", "3"), initial=(2, 4, 1))
    assert r.success and r.signs == {"-1": len(r.decided)}


# --- the second-order form (issue 27: the corner next to m_c) --------------------------------------------------
# A rectangle inside the corner the mean value form left undecided (benchmarks/enclosure_boxes.json: every box with
# m in [1287/640, 11/5], gamma in [1/4, 61/128]), where S(2.15, 0.3, 1/4) ~ -7e-3 and the mean value form's spread
# is ~2e-2 even after one bisection (test_first_order_form_cannot_decide_the_corner_box).
CORNER_BOX = (("2.15", "2.152"), ("0.3", "0.302"), ("0.25", "3"))


def test_second_order_box_contains_point_values():
    """box_theorem(order=2) decides a corner box, and its ball contains S at sample points (vertices, the centre and
    an off-centre interior point), each enclosed separately by enclose_S (acb.integral at the point, 96 bits)."""
    r = E.box_theorem(*CORNER_BOX, initial=(1, 1, 1), min_width=0.6, order=2)
    assert r.success and r.signs == {"-1": 1} and "second-order form" in r.statement
    (b,) = r.decided
    lo, hi = Fraction(b.S_lo), Fraction(b.S_hi)
    assert hi < 0
    pts = [("2.15", "0.3", "0.25"), ("2.152", "0.302", "3"), ("2.15", "0.302", "0.25"),
           ("2.151", "0.301", "1"), ("2.1517", "0.3003", "2.5")]
    for p in pts:
        v = E.enclose_S(*p)
        vlo, vhi = E.outward(v.S)
        assert lo <= Fraction(vlo) and Fraction(vhi) <= hi, (p, v.S, b.S)


class _GradientScaled(_DeltaFlipped):
    """The true ball code with dI/dm scaled by 1.01 (a 1 % error in the m component of the gradient)."""

    @staticmethod
    def integrand(t, m, g, d):
        return _DeltaFlipped._g.integrand(t, m, g, d)

    @staticmethod
    def integrand_gradient(t, m, g, d):
        a, b, c = _DeltaFlipped._g.integrand_gradient(t, m, g, d)
        return [a * flint.arb("1.01"), b, c]

    @staticmethod
    def tail_factors(s, c, TH, D, m, g, d):
        return _DeltaFlipped._g.tail_factors(s, c, TH, D, m, g, d)


@pytest.mark.parametrize("module, agrees", [(None, True), (_GradientScaled, False)])
def test_centre_gradient_matches_finite_differences(module, agrees):
    """The centre gradient (acb.integral of the generated gradient) against central differences of the integral
    itself (acb.integral of the integrand at p0 +- eps, the same cut T): independent of the gradient code.  The
    difference error is eps^2 I'''/6 + O(eps^4), so with the true gradient it falls by ~4 when eps halves; a wrong
    gradient leaves a constant error (ratio ~1).  The mutated module (dI/dm off by 1 %) must fail."""
    from flint import arb, ctx

    mod = E._gen if module is None else module
    m0, g0, d0 = E.exact("m", "2.1"), E.exact("gamma", "0.3"), E.exact("delta", "0.25")
    T = E.fmpq(20)
    c = [0]
    with ctx.workprec(64):
        _, dIm, dIg = E._centre_terms(mod, arb(m0), arb(g0), arb(d0), T, c)

        def integral(m, g):
            return E._centre_terms(E._gen, arb(m), arb(g), arb(d0), T, c)[0]

        ratios = []
        for k, d in ((0, dIm), (1, dIg)):
            errs = []
            for eps in (E.fmpq(1, 500), E.fmpq(1, 1000)):
                e = (eps, 0) if k == 0 else (0, eps)
                fd = (integral(m0 + e[0], g0 + e[1]) - integral(m0 - e[0], g0 - e[1])) / (2 * arb(eps))
                errs.append(abs(float((fd - d).mid())))
            ratios.append(errs[0] / errs[1])
    ok = all(3 < q < 5 for q in ratios)  # eps^2 convergence: 4 up to the O(eps^4) term
    assert ok is agrees, ratios


@pytest.mark.parametrize("order", [0, 3, True, "2"])
def test_box_theorem_bad_order(order):
    with pytest.raises(ParameterError) as ei:
        E.box_theorem(("1.6", "1.7"), ("1", "1.1"), ("1", "1.1"), order=order)
    assert ei.value.name == "order"


def test_first_order_form_cannot_decide_the_corner_box(monkeypatch):
    """The reason for order=2: on the same box, bisected once in m and gamma, the mean value form's spread
    (~ Int sup |dN/dp| w per direction) still exceeds |S| (~7e-3 at delta = 1/4): every quarter stays undecided.
    Also a regression test: the bisection once reused the name `order`, so sub-boxes silently got the other form."""
    calls = []
    real = E._enclose_rect2
    monkeypatch.setattr(E, "_enclose_rect2", lambda *a: calls.append(a) or real(*a))
    r = E.box_theorem(*CORNER_BOX, initial=(1, 1, 1), min_width=0.6, order=1)
    assert not r.success and r.decided == [] and len(r.undecided) == 4
    assert calls == []  # the mean value form only
