"""Kovalevskaya 1889, rediscovered on the anisotropic rod: for which stiffness ratios are the Kovalevskaya exponents
integers?  Derived from the model's field with (B1, B2, C) as symbols (x = B2/B1, y = C/B1 after the scaling of
derive/morales_ramis.symmetric_rod_theorem, step "scaling").

1. The balances with the moment along one body axis (found by solving the balance equations on that support, with
   the inverse stiffnesses a_i symbolic): along d2, c = (0, 2i/a2, 0, 2i/a2, 0, 2/a2), and along d1, c = (2i/a1,
   0, 0, 0, -2i/a1, 2/a1) (and conjugates).  Their characteristic polynomials factor over Q(a) as
   (rho + 1)(rho - 2)(rho - 3)(rho - 4)(rho^2 - rho - 2 D), with D = (1 - x)(1 - 2x/y) along d2 and
   D = (1 - 1/x)(1 - 2/y) along d1 (computed, then compared with these forms).
2. rho^2 - rho - 2D has integer roots iff 1 + 8D is an odd square, i.e. D = k(k+1)/2 is a triangular number T_k.
3. The pair of conditions D2 = T_k, D1 = T_k' is solved completely (`conditions`: a positivity argument gives
   k k' = 0, then three lines), cross-checked by solving the polynomial system for every pair k, k' <= K.
4. At the rational points of the lines (T_k a square: k = 1, 8, 49, 288, ...) every balance of the field is
   computed (derive/painleve.py) for the first two and their mirrors.
Found: Lagrange (x = 1, any y), Kovalevskaya 1:2:2 and its mirror 2:1:2 (every balance integer and compatible), and
1:7:2 (and 7:1:2): every exponent of every balance an integer, yet the Euler balance (n = 0) has a logarithmic
resonance, so the Painleve test fails there: integer exponents alone do not single out Kovalevskaya's case, the
compatibility conditions do.  Irrational points of the lines pass the axis balances; their other balances are not
decided here (the Groebner engine works over Q).  Goryachev-Chaplygin (1:4:4): along d1, D = 3/8, 1 + 8D = 4, exponents
3/2 and -1/2: algebraic branching (the weak Painleve property), so the Painleve test fails; its integral exists only
on m.n = 0 (derive/morales_ramis.py, step "survivors")."""
from __future__ import annotations

import sympy as sp

from . import painleve

K_MAX = 6
x, y = sp.symbols("x y", positive=True)


def axis_balances():
    """[(axis, c, characteristic polynomial factored, D)] derived with symbolic inverse stiffnesses."""
    from . import models
    from .models.pipeline import equations

    m = models.get("anisotropic")
    B1, B2, C = m.params
    a1, a2, a3 = sp.symbols("a1 a2 a3", positive=True)
    X = m.state
    f = [sp.expand(e.subs({B1: 1 / a1, B2: 1 / a2, C: 1 / a3})) for e in equations(m)]
    w = (1, 1, 1, 2, 2, 2)
    f0 = painleve.dominant_field(f, X, w)
    cs = sp.symbols("c1:7")
    eqs = [sp.expand(f0[i].subs(dict(zip(X, cs))) + w[i] * cs[i]) for i in range(6)]
    out = []
    ratio = {a1: 1, a2: 1 / x, a3: 1 / y}  # a_i = 1/B_i with B1 = 1, B2 = x, C = y
    for axis, zero in (("d1", (1, 2, 3)), ("d2", (0, 2, 4))):
        sub = {cs[i]: 0 for i in zero}
        rest = [c for c in cs if c not in sub]
        sols = [s for s in sp.solve([e.subs(sub) for e in eqs], rest, dict=True) if any(v != 0 for v in s.values())]
        s = sorted(sols, key=lambda d: sp.default_sort_key(tuple(d.values())))[0]
        cpt = {X[i]: (s.get(cs[i], sp.Integer(0)) if cs[i] not in sub else 0) for i in range(6)}
        Kc = painleve.kovalevskaya_matrix(f0, X, w, cpt)
        cp = sp.factor(sp.expand((Kc - painleve.RHO * sp.eye(6)).det()))
        quad = [fac for fac in sp.factor_list(cp, painleve.RHO)[1] if sp.degree(fac[0], painleve.RHO) == 2][0][0]
        P = sp.Poly(quad, painleve.RHO)
        lc = P.LC()
        D = sp.factor(-P.coeff_monomial(1) / lc / 2)
        out.append({"axis": axis, "c": {str(k): str(v) for k, v in cpt.items()}, "charpoly": str(cp),
                    "D": sp.factor(D.subs(ratio))})
    return out


def _in_families(xs, ys) -> bool:
    """(x, y) on the Lagrange line x = 1, the line y = 2 or the line y = 2x."""
    return any(sp.simplify(e) == 0 for e in (xs - 1, ys - 2, ys - 2 * xs))


def conditions(k_max: int = K_MAX) -> dict:
    """The complete solution of "both axis balances have integer exponents" (D_d2 = T_k, D_d1 = T_k'), the rational
    cases on it with the full exponent analysis at each, and a cross-check by solving the pairs k, k' <= k_max.

    Lemma (the argument; its identities checked here): for x < 1, D_d2 > 0 forces 1 - 2x/y in (0, 1), so
    0 < D_d2 < 1 and k = 0; for x > 1, D_d1 > 0 forces y > 2, so 0 < D_d1 < 1 and k' = 0.  Hence k k' = 0 and the
    solutions are: x = 1 (Lagrange, any y); k' = 0 with y = 2, where D_d2 = (1 - x)^2, x = 1 + sqrt(T_k); k = 0 with
    y = 2x, where D_d1 = (1 - 1/x)^2, x = 1/(1 + sqrt(T_k')).  Rational ratios need T_k a square (square triangular
    numbers 1, 36, 1225, ...): x = 2, 7, 36, ... on y = 2 and their mirrors."""
    ax = axis_balances()
    D1 = next(a["D"] for a in ax if a["axis"] == "d1")
    D2 = next(a["D"] for a in ax if a["axis"] == "d2")
    ok_forms = (sp.simplify(D1 - (1 - 1 / x) * (1 - 2 / y)) == 0 and sp.simplify(D2 - (1 - x) * (1 - 2 * x / y)) == 0
                and sp.factor(D2.subs(y, 2) - (1 - x)**2) == 0 and sp.factor(D1.subs(y, 2 * x) - (1 - 1 / x)**2) == 0
                and sp.factor(D1.subs(y, 2)) == 0 and sp.factor(D2.subs(y, 2 * x)) == 0)
    # cross-check: every positive solution for k, k' <= k_max lies on the three lines
    found = []
    for k in range(k_max + 1):
        for kk in range(k_max + 1):
            e2 = sp.numer(sp.together(D2 - sp.Rational(k * (k + 1), 2)))
            e1 = sp.numer(sp.together(D1 - sp.Rational(kk * (kk + 1), 2)))
            for sol in sp.solve([e1, e2], [x, y], dict=True):
                xs, ys = sol.get(x), sol.get(y)
                if xs is None or ys is None:
                    found.append((k, kk, "x = 1" if xs == 1 else str(sol), True))
                    continue
                xs, ys = sp.radsimp(sp.simplify(xs)), sp.radsimp(sp.simplify(ys))
                if xs.is_positive and ys.is_positive:
                    found.append((k, kk, f"x = {xs}, y = {ys}", _in_families(xs, ys)))
    squares = [(k, sp.sqrt(sp.Rational(k * (k + 1), 2))) for k in range(1, 300)]
    squares = [(k, s_) for k, s_ in squares if s_.is_rational]
    from . import models

    m = models.get("anisotropic")
    cases = [{"name": "Lagrange (B1 = B2, C free)", "ratios": "x = 1, any y", "verdict": "integrable (m3)"}]
    for k, s_ in squares[:2]:
        for xv, yv, mirror in ((1 + s_, sp.Integer(2), False), (1 / (1 + s_), 2 / (1 + s_), True)):
            res = painleve.model_analysis(m, {"B1": 1, "B2": xv, "C": yv}, ars=True)
            verdicts = sorted({b["verdict"] for ch in res["choices"] for b in ch["balances"]})
            name = ("Kovalevskaya" + (" mirror (B1 = C = 2 B2)" if mirror else " (B2 = C = 2 B1)") if s_ == 1 else
                    f"integer exponents, T_{k} = {s_}^2" + (" (mirror)" if mirror else ""))
            cases.append({"name": name, "ratios": f"B1:B2:C = 1:{xv}:{yv}", "k": k,
                          "verdict": res["painleve"]["verdict"], "balance_verdicts": verdicts})
    return {"axis_balances": [{k: str(v) for k, v in a.items()} for a in ax], "forms_checked": bool(ok_forms),
            "solution": "x = 1 (any y); y = 2, x = 1 + sqrt(T_k); y = 2x, x = 1/(1 + sqrt(T_k)); T_k = k(k+1)/2",
            "rational_on_the_lines": [f"k = {k}: T_k = {s_}^2" for k, s_ in squares],
            "cross_check": {"k_max": k_max, "solutions": [f"(k, k') = ({a}, {b}): {t}" for a, b, t, _ in found],
                            "all_on_the_lines": all(f[3] for f in found)},
            "cases": cases,
            "goryachev_chaplygin": {"D_d1": str(D1.subs({x: 4, y: 4})), "D_d2": str(D2.subs({x: 4, y: 4})),
                                    "exponents_d1": "3/2, -1/2 (1 + 8D = 4)",
                                    "meaning": "algebraic branching at the d1 balance: the Painleve test fails "
                                               "(weak Painleve property); integrable only on m.n = 0"}}
