"""derive.codegen.BallPrinter: SymPy -> python-flint ball code (the printer every rigorous enclosure is generated
with).  References: the same expression evaluated by SymPy at 40 digits."""
import pytest
import sympy as sp

flint = pytest.importorskip("flint")

from magrod.derive.codegen import BallPrinter, function_source, module_source  # noqa: E402

x, m = sp.symbols("x m")
EXPR = (sp.Rational(1, 3) * sp.sin(x) ** 2 / (1 + sp.cos(x)) - sp.sqrt(m) * sp.atan(sp.Rational(2, 5) * sp.tanh(x))
        + x / 2 + sp.pi * m**-2 - 3 * x * m + sp.exp(-x) * sp.cosh(m) / m ** sp.Rational(3, 2))


def _compile(expr):
    src = module_source("test", "test_ballcode.py", [function_source("f", ["x", "m"], expr,
                                                                     BallPrinter({x: "x", m: "m"}), "f")], lib="arb")
    ns = {}
    exec(src, ns)  # noqa: S102 - our own generated source, as generated/ modules are imported
    return ns["f"]


@pytest.mark.parametrize("xv, mv", [(sp.Rational(3, 10), sp.Integer(2)), (sp.Rational(-7, 4), sp.Rational(1, 9))])
def test_ball_contains_the_exact_value(xv, mv):
    f = _compile(EXPR)
    ref = sp.N(EXPR.subs({x: xv, m: mv}), 40)
    ball = f(flint.arb(flint.fmpq(int(xv.p), int(xv.q))), flint.arb(flint.fmpq(int(mv.p), int(mv.q))))
    assert ball.contains(flint.arb(str(ref)))
    assert ball.rad() < 64 * 2.0**-53 * max(1.0, abs(float(ball.mid())))  # a few ulp at 53 bits
    # the same source evaluates complex balls (acb), as acb.integral needs
    cb = f(flint.acb(flint.fmpq(int(xv.p), int(xv.q))), flint.acb(flint.fmpq(int(mv.p), int(mv.q))))
    assert cb.real.contains(flint.arb(str(ref)))


def test_mutated_expression_is_not_contained():
    f = _compile(EXPR + sp.Rational(1, 10**12))
    ref = sp.N(EXPR.subs({x: sp.Rational(3, 10), m: 2}), 40)
    assert not f(flint.arb(flint.fmpq(3, 10)), flint.arb(2)).contains(flint.arb(str(ref)))


def test_rounded_constants_are_refused():
    with pytest.raises(TypeError, match="exact numbers only"):
        BallPrinter({x: "x"})(sp.Float(0.1) * x)


def test_integer_powers_of_a_ball_around_zero_are_finite():
    """Arb's `x ** k` goes through exp(k log x): nan for any ball containing 0 (rigorous, but it makes an enclosure
    undecidable wherever, e.g., sin(theta)**2 is evaluated near theta = 0).  The printer writes products instead."""
    assert not flint.arb(0, 0.1) ** 2 == flint.arb(0, 0.1) ** 2  # nan: the reason for the product form
    expr = sp.sin(x) ** 2 + x ** 3 * m ** -2 + sp.sqrt(1 + x) ** 3
    f = _compile(expr)
    ball = f(flint.arb(0, flint.arb("1e-3").mid()), flint.arb(2))
    assert ball.is_finite() and ball.contains(1) and ball.rad() < 1e-2
    exact = f(flint.arb(flint.fmpq(3, 10)), flint.arb(flint.fmpq(1, 2)))
    assert exact.contains(flint.arb(str(sp.N(expr.subs({x: sp.Rational(3, 10), m: sp.Rational(1, 2)}), 40))))
