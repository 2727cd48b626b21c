"""Kovacic's algorithm (Kovacic 1986, "An algorithm for solving second order linear homogeneous differential
equations", J. Symb. Comp. 2, 3-43) and Kimura's theorem for the hypergeometric equation (Kimura 1969, Funkcial.
Ekvac. 12, 269-281), exact.

For y'' = r y with r in Q-bar(x) (poles and coefficients given exactly: rationals and square roots of them), the
differential Galois group G is a subgroup of SL(2, C) and exactly one of:
  case 1  G reducible (triangular): a solution exp(int w) with w rational;
  case 2  G imprimitive (a subgroup of the infinite dihedral group): w quadratic over C(x);
  case 3  G finite (tetrahedral, octahedral or icosahedral type): w algebraic of degree 4, 6 or 12;
  case 4  G = SL(2, C): no Liouvillian solution.
Each case is decided here, in order, from its necessary conditions and its search for a polynomial P of bounded
degree (a linear system solved exactly).  `identity_component_abelian` then decides what Morales-Ramis theory
needs: G0 is abelian in cases 2 and 3; in case 4 it is SL(2) (not abelian); in case 1 it is abelian iff there are
two independent exponential solutions (G diagonal) or the exponential solution found is algebraic (G0 unipotent),
and otherwise G0 is the whole triangular group (not abelian: see `identity_component_abelian`).

Restriction (stated, checked): the poles of r must have exact roots expressible by SymPy `roots` (so that c, [sqrt r]_c
and alpha_c are exact); otherwise ValueError."""
from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import sympy as sp

x = sp.Symbol("x")


def _canon(e):
    return sp.expand(sp.radsimp(sp.expand(e)))


def reduce_form(p, q, var=x):
    """y'' + p y' + q y = 0  ->  w'' = r w  with y = w exp(-1/2 int p):  r = p^2/4 + p'/2 - q."""
    return sp.cancel(sp.together(p**2 / 4 + sp.diff(p, var) / 2 - q))


# ----------------------------------------------------------------------------------------------------------------
# local data
# ----------------------------------------------------------------------------------------------------------------
@dataclass
class Pole:
    c: sp.Expr
    order: int


def _poles(r, var):
    s, t = sp.fraction(sp.cancel(sp.together(r)))
    s, t = sp.Poly(s, var), sp.Poly(t, var)
    lc = t.LC()
    s, t = s * (1 / lc), t * (1 / lc)  # t monic
    rts = sp.roots(t, multiple=False)
    if sum(rts.values()) != t.degree():
        raise ValueError("kovacic: the poles of r are not all expressible exactly (sympy roots)")
    poles = [Pole(sp.nsimplify(c) if c.is_number else c, int(m)) for c, m in rts.items()]
    poles.sort(key=lambda p: sp.default_sort_key(p.c))
    o_inf = t.degree() - s.degree() if not s.is_zero else sp.oo
    return s, t, poles, o_inf


def _sqrt_series(g, u, n):
    """First n+1 coefficients h_0..h_n of sqrt(g(u)) at u = 0 (g(0) != 0; principal root of g(0))."""
    gs = sp.series(g, u, 0, n + 1).removeO()
    gk = [sp.expand(gs.coeff(u, k)) for k in range(n + 1)]
    h = [sp.sqrt(gk[0])]
    for k in range(1, n + 1):
        h.append(_canon((gk[k] - sum(h[j] * h[k - j] for j in range(1, k))) / (2 * h[0])))
    return h


def _laurent_coeff(expr, var, c, power):
    """Coefficient of (var - c)^power in the Laurent expansion of expr at c."""
    u = sp.Symbol("u_")
    e = sp.cancel(sp.together(expr.subs(var, u + c)))
    lowest = -20
    ser = sp.series(e * u**(-lowest), u, 0, power - lowest + 1).removeO()
    return _canon(sp.expand(ser).coeff(u, power - lowest))


def _inf_coeff(expr, var, power):
    """Coefficient of var^power in the expansion of expr at infinity."""
    u = sp.Symbol("u_")
    e = sp.cancel(sp.together(expr.subs(var, 1 / u)))
    shift = 40
    ser = sp.series(e * u**shift, u, 0, shift - power + 1).removeO()
    return _canon(sp.expand(ser).coeff(u, shift - power))


def _b2(r, var, c):
    return _laurent_coeff(r, var, c, -2)


# ----------------------------------------------------------------------------------------------------------------
# case 1
# ----------------------------------------------------------------------------------------------------------------
def _case1_local(r, var, poles, o_inf):
    u = sp.Symbol("u_")
    loc = []
    for p in poles:
        if p.order == 1:
            loc.append((p, sp.Integer(0), (sp.Integer(1), sp.Integer(1))))
        elif p.order == 2:
            b = _b2(r, var, p.c)
            s = sp.sqrt(1 + 4 * b)
            loc.append((p, sp.Integer(0), (_canon(sp.Rational(1, 2) + s / 2), _canon(sp.Rational(1, 2) - s / 2))))
        else:
            nu = p.order // 2
            g = sp.cancel(sp.together(r.subs(var, u + p.c) * u**(2 * nu)))
            h = _sqrt_series(g, u, nu)
            sq = sum(h[k] * (var - p.c)**(k - nu) for k in range(nu - 1))  # powers -nu .. -2
            a = h[0]
            b = _laurent_coeff(sp.expand(r - sq**2), var, p.c, -nu - 1)
            loc.append((p, sq, (_canon((b / a + nu) / 2), _canon((-b / a + nu) / 2))))
    if o_inf > 2:
        inf = (sp.Integer(0), (sp.Integer(0), sp.Integer(1)))
    elif o_inf == 2:
        b = _inf_coeff(r, var, -2)
        s = sp.sqrt(1 + 4 * b)
        inf = (sp.Integer(0), (_canon(sp.Rational(1, 2) + s / 2), _canon(sp.Rational(1, 2) - s / 2)))
    else:
        nu = -int(o_inf) // 2
        g = sp.cancel(sp.together(r.subs(var, 1 / u) * u**(2 * nu)))
        h = _sqrt_series(g, u, nu)
        sq = sum(h[k] * var**(nu - k) for k in range(nu + 1))  # powers nu .. 0
        a = h[0]
        b = _inf_coeff(sp.expand(r - sq**2), var, nu - 1)
        inf = (sq, (_canon((b / a - nu) / 2), _canon((-b / a - nu) / 2)))
    return loc, inf


def _poly_solution(d, op, var):
    """A monic polynomial P of degree d with op(P) = 0 (op linear), or None; solved as a linear system."""
    cs = sp.symbols(f"p0:{d}") if d else ()
    P = var**d + sum(c * var**k for k, c in enumerate(cs))
    expr = sp.together(op(P))
    num = sp.expand(sp.fraction(expr)[0])
    if num == 0:
        return sp.expand(P)
    eqs = [_canon(e) for e in sp.Poly(num, var).coeffs()]
    if not cs:
        return None if any(e != 0 for e in eqs) else sp.expand(P)
    sol = sp.linsolve(eqs, cs)
    if not sol:
        return None
    vals = next(iter(sol))
    vals = [v.subs({c: 0 for c in cs}) for v in vals]  # free coefficients: any choice gives a solution
    return sp.expand(P.subs(dict(zip(cs, vals))))


def case1(r, var=x):
    """All (omega, P) of Kovacic's case 1: solutions P exp(int omega) (one per sign family that succeeds)."""
    s, t, poles, o_inf = _poles(r, var)
    if any(p.order > 2 and p.order % 2 for p in poles) or not (o_inf > 2 or (o_inf % 2 == 0)):
        return []
    loc, (sq_inf, a_inf) = _case1_local(r, var, poles, o_inf)
    out = []
    for signs in itertools.product((0, 1), repeat=len(loc) + 1):
        d = _canon(a_inf[signs[-1]] - sum(al[sg] for (_, _, al), sg in zip(loc, signs)))
        if not (d.is_integer and d >= 0):
            continue
        sgn = [1 if sg == 0 else -1 for sg in signs]
        omega = sum(sgn[i] * sq + al[signs[i]] / (var - p.c) for i, (p, sq, al) in enumerate(loc))
        omega += sgn[-1] * sq_inf
        omega = sp.together(omega)

        def op(P, omega=omega):
            return sp.diff(P, var, 2) + 2 * omega * sp.diff(P, var) + (sp.diff(omega, var) + omega**2 - r) * P
        P = _poly_solution(int(d), op, var)
        if P is not None:
            out.append((omega, P))
    return out


# ----------------------------------------------------------------------------------------------------------------
# case 2
# ----------------------------------------------------------------------------------------------------------------
def _E2(b):
    s = sp.sqrt(1 + 4 * b)
    return sorted({e for e in (_canon(2 + k * s) for k in (0, 2, -2)) if e.is_integer}, key=sp.default_sort_key)


def case2(r, var=x):
    """(theta, P) of Kovacic's case 2, or None."""
    s, t, poles, o_inf = _poles(r, var)
    if not any(p.order == 2 or (p.order > 2 and p.order % 2) for p in poles):
        return None
    Es = []
    for p in poles:
        if p.order == 1:
            Es.append([sp.Integer(4)])
        elif p.order == 2:
            Es.append(_E2(_b2(r, var, p.c)))
        else:
            Es.append([sp.Integer(p.order)])
    if o_inf > 2:
        Einf = [sp.Integer(0), sp.Integer(2), sp.Integer(4)]
    elif o_inf == 2:
        Einf = _E2(_inf_coeff(r, var, -2))
    else:
        Einf = [sp.Integer(o_inf)]
    for e_inf in Einf:
        for es in itertools.product(*Es):
            d = sp.Rational(e_inf - sum(es), 2)
            if not (d.is_integer and d >= 0):
                continue
            theta = sp.together(sum(sp.Rational(e, 2) / (var - p.c) for e, p in zip(es, poles)))

            def op(P, th=theta):
                D = lambda f, k=1: sp.diff(f, var, k)  # noqa: E731
                return (D(P, 3) + 3 * th * D(P, 2) + (3 * th**2 + 3 * D(th) - 4 * r) * D(P)
                        + (D(th, 2) + 3 * th * D(th) + th**3 - 4 * r * th - 2 * D(r)) * P)
            P = _poly_solution(int(d), op, var)
            if P is not None:
                return theta, P
    return None


# ----------------------------------------------------------------------------------------------------------------
# case 3
# ----------------------------------------------------------------------------------------------------------------
def case3(r, var=x):
    """(n, theta, P) of Kovacic's case 3 (n = 4, 6, 12), or None."""
    s, t, poles, o_inf = _poles(r, var)
    if any(p.order > 2 for p in poles) or o_inf < 2:
        return None
    S = sp.Mul(*[(var - p.c) for p in poles]) if poles else sp.Integer(1)
    for n in (4, 6, 12):
        def E(b, n=n):
            sq = sp.sqrt(1 + 4 * b)
            vals = {_canon(6 + sp.Rational(12 * k, n) * sq) for k in range(-n // 2, n // 2 + 1)}
            return sorted((e for e in vals if e.is_integer), key=sp.default_sort_key)
        Es = [[sp.Integer(12)] if p.order == 1 else E(_b2(r, var, p.c)) for p in poles]
        Einf = E(_inf_coeff(r, var, -2) if o_inf == 2 else sp.Integer(0))
        for e_inf in Einf:
            for es in itertools.product(*Es):
                d = sp.Rational(n, 12) * (e_inf - sum(es))
                if not (d.is_integer and d >= 0):
                    continue
                theta = sp.Rational(n, 12) * sum(sp.Integer(e) / (var - p.c) for e, p in zip(es, poles))
                d = int(d)
                cs = sp.symbols(f"q0:{d}") if d else ()
                # poles of order <= 2: S theta and S^2 r are polynomials, so every P_i is (exact Poly arithmetic)
                gens = (var, *cs)
                A = sp.Poly(sp.cancel(S * theta), *gens)
                Rr = sp.Poly(sp.cancel(S**2 * r), *gens)
                Sp, dS = sp.Poly(S, *gens), sp.Poly(sp.diff(S, var), *gens)
                P = sp.Poly(var**d + sum(c * var**k for k, c in enumerate(cs)), *gens)
                Pi = {n: -P, n + 1: sp.Poly(0, *gens)}
                for i in range(n, -1, -1):
                    Pi[i - 1] = (-Sp * Pi[i].diff(var) + ((n - i) * dS - A) * Pi[i]
                                 - (n - i) * (i + 1) * Rr * Pi[i + 1])
                last = Pi[-1]
                if last.is_zero:
                    return n, theta, P.as_expr()
                coeffs = sp.Poly(last.as_expr(), var).coeffs()
                eqs = [_canon(e) for e in coeffs]
                sol = sp.linsolve(eqs, cs) if cs else (None if any(e != 0 for e in eqs) else {()})
                if sol:
                    vals = [v.subs({c: 0 for c in cs}) for v in next(iter(sol))]
                    return n, theta, sp.expand(P.as_expr().subs(dict(zip(cs, vals))))
    return None


# ----------------------------------------------------------------------------------------------------------------
# the decision
# ----------------------------------------------------------------------------------------------------------------
@dataclass
class GaloisResult:
    case: int  # 1, 2, 3 or 4 (no Liouvillian solution)
    group: str
    abelian_identity_component: bool
    reason: str
    data: dict = field(default_factory=dict)

    def as_dict(self):
        return {"case": self.case, "group": self.group, "abelian_identity_component": self.abelian_identity_component,
                "reason": self.reason, "data": {k: str(v) for k, v in self.data.items()}}


def _is_algebraic_exp(omega, var):
    """exp(int omega) algebraic over C(x): omega has only simple poles with rational residues and no polynomial
    part (then exp(int omega) = prod (x - c)^res)."""
    num, den = sp.fraction(sp.together(omega))
    q, rem = sp.div(sp.Poly(num, var), sp.Poly(den, var))
    if not q.is_zero:
        return False
    for c, m in sp.roots(sp.Poly(den, var), multiple=False).items():
        if any(_laurent_coeff(omega, var, c, -k) != 0 for k in range(2, m + 1)):
            return False
        res = _laurent_coeff(omega, var, c, -1)
        if not sp.nsimplify(res).is_rational:
            return False
    return True


def galois(r, var=x) -> GaloisResult:
    """Kovacic's algorithm, all three cases in order, and the identity component G0 of the Galois group of
    y'' = r y: abelian or not (what Morales-Ramis theory asks)."""
    r = sp.cancel(sp.together(r))
    sols = case1(r, var)
    if sols:
        # independent exponential solutions: distinct logarithmic derivatives omega + P'/P
        logd = []
        for om, P in sols:
            ld = sp.cancel(sp.together(om + sp.diff(P, var) / P))
            if all(sp.cancel(sp.together(ld - other)) != 0 for other in logd):
                logd.append(ld)
        if len(logd) >= 2:
            return GaloisResult(1, "reducible, diagonal (two exponential solutions)", True,
                                "case 1 found two independent solutions exp(int w1), exp(int w2): G is a subgroup of "
                                "the diagonal torus", {"w1": logd[0], "w2": logd[1]})
        if _is_algebraic_exp(logd[0], var):
            return GaloisResult(1, "reducible, G0 unipotent (the exponential solution is algebraic)", True,
                                "case 1: the solution exp(int w) is algebraic, so G acts on it through a finite group "
                                "and G0 lies in the unipotent group (abelian)", {"w": logd[0]})
        return GaloisResult(1, "reducible, G0 the triangular group", False,
                            "case 1: one transcendental exponential solution exp(int w) and no second one: G0 maps "
                            "onto C* and is not a torus (a torus would give a second invariant line, i.e. a second "
                            "rational w), so G0 is the whole triangular group (not abelian)", {"w": logd[0]})
    c2 = case2(r, var)
    if c2 is not None:
        return GaloisResult(2, "imprimitive (dihedral type)", True, "case 2: G is a subgroup of the infinite dihedral "
                            "group, G0 lies in the diagonal torus", {"theta": c2[0], "P": c2[1]})
    c3 = case3(r, var)
    if c3 is not None:
        return GaloisResult(3, {4: "tetrahedral", 6: "octahedral", 12: "icosahedral"}[c3[0]] + " (finite)", True,
                            "case 3: G finite, G0 trivial", {"n": c3[0], "theta": c3[1], "P": c3[2]})
    return GaloisResult(4, "SL(2, C)", False, "no case of Kovacic's algorithm holds: no Liouvillian solution, "
                        "G = SL(2, C), G0 not abelian (not even solvable)")


# ----------------------------------------------------------------------------------------------------------------
# Kimura's theorem for the Riemann P (hypergeometric) equation
# ----------------------------------------------------------------------------------------------------------------
KIMURA_TABLE = (  # (entries, parity condition l+m+q even needed, group); case 1 (dihedral) is handled apart
    ((sp.Rational(1, 2), sp.Rational(1, 3), sp.Rational(1, 3)), False, "tetrahedral"),
    ((sp.Rational(2, 3), sp.Rational(1, 3), sp.Rational(1, 3)), True, "tetrahedral"),
    ((sp.Rational(1, 2), sp.Rational(1, 3), sp.Rational(1, 4)), False, "octahedral"),
    ((sp.Rational(2, 3), sp.Rational(1, 4), sp.Rational(1, 4)), True, "octahedral"),
    ((sp.Rational(1, 2), sp.Rational(1, 3), sp.Rational(1, 5)), False, "icosahedral"),
    ((sp.Rational(2, 5), sp.Rational(1, 3), sp.Rational(1, 3)), True, "icosahedral"),
    ((sp.Rational(2, 3), sp.Rational(1, 5), sp.Rational(1, 5)), True, "icosahedral"),
    ((sp.Rational(1, 2), sp.Rational(2, 5), sp.Rational(1, 5)), False, "icosahedral"),
    ((sp.Rational(3, 5), sp.Rational(1, 3), sp.Rational(1, 5)), True, "icosahedral"),
    ((sp.Rational(2, 5), sp.Rational(2, 5), sp.Rational(2, 5)), True, "icosahedral"),
    ((sp.Rational(2, 3), sp.Rational(1, 3), sp.Rational(1, 5)), True, "icosahedral"),
    ((sp.Rational(4, 5), sp.Rational(1, 5), sp.Rational(1, 5)), True, "icosahedral"),
    ((sp.Rational(1, 2), sp.Rational(2, 5), sp.Rational(1, 3)), False, "icosahedral"),
    ((sp.Rational(3, 5), sp.Rational(2, 5), sp.Rational(1, 3)), True, "icosahedral"),
)


def _is_int(e):
    e = _canon(e)
    return bool(e.is_integer)


def kimura(lam, mu, nu) -> dict:
    """Kimura's theorem for exponent differences (lam, mu, nu) (exact): G0 solvable iff (A) one of lam+mu+nu,
    -lam+mu+nu, lam-mu+nu, lam+mu-nu is an odd integer (reducible), or (B) +-lam, +-mu, +-nu are, in some order, in
    one of the fifteen families of Kimura's table (case 1: dihedral; 2-15: finite).  Returns {'solvable', 'case',
    'group'}."""
    ds = [_canon(v) for v in (lam, mu, nu)]
    for sl, sm, sn in ((1, 1, 1), (-1, 1, 1), (1, -1, 1), (1, 1, -1)):
        v = _canon(sl * ds[0] + sm * ds[1] + sn * ds[2])
        if v.is_integer and v % 2 == 1:
            return {"solvable": True, "case": "A", "group": "reducible (triangular)"}
    half = [_is_int(v - sp.Rational(1, 2)) for v in ds]
    if sum(half) >= 2:
        return {"solvable": True, "case": "B1", "group": "dihedral (G0 in a torus)"}
    for entries, parity, grp in KIMURA_TABLE:
        for perm in itertools.permutations(range(3)):
            for signs in itertools.product((1, -1), repeat=3):
                shifts = [_canon(signs[k] * ds[perm[k]] - entries[k]) for k in range(3)]
                if all(s.is_integer for s in shifts) and (not parity or sum(shifts) % 2 == 0):
                    return {"solvable": True, "case": f"B ({entries[0]}, {entries[1]}, {entries[2]})", "group": grp}
    return {"solvable": False, "case": "none", "group": "SL(2, C) (G0 not solvable)"}


def riemann_reduced(lam, mu, nu, var=x):
    """r of the reduced Riemann P-equation w'' = r w with singular points 0, 1, oo and exponent differences
    lam, mu, nu (the normal form Kimura's theorem is about)."""
    return sp.together((lam**2 - 1) / (4 * var**2) + (mu**2 - 1) / (4 * (var - 1)**2)
                       - (lam**2 + mu**2 - nu**2 - 1) / (4 * var * (var - 1)))
