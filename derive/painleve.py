"""Kovalevskaya exponents and the Painleve (Ablowitz-Ramani-Segur) test for any rod model, exact.

From a model's field x' = f(x) (derive/models/pipeline.equations, the parameters given exact rational values):

  * weights w (positive integers) for which every monomial x^a of f_i has weighted degree <a, w> <= w_i + 1; the
    monomials with equality form the dominant part f^0 (weighted-homogeneous: f^0(s^w x) = s^(w+1) f^0(x)).  The
    field is weighted-homogeneous when f = f^0 (the Kirchhoff-type rods are, with w = 1 on m and 2 on n).
  * the dominant balances x = c t^(-w): the solutions c != 0 of  f^0(c) + w c = 0, decomposed into components by a
    Groebner basis (lex) split along the factors of its elements (so continuous families are kept, not dropped),
  * the Kovalevskaya matrix K(c) = Df^0(c) + diag(w) and its eigenvalues (the exponents; -1 always, eigenvector
    w c), exactly: the characteristic polynomial is reduced modulo the component's ideal; where its coefficients
    are rational numbers the exponents are the roots of a polynomial over Q, classified by factoring over Q
    (a linear factor: rational; an irreducible factor of degree >= 2: irrational or complex), never by floats;
  * the ARS compatibility conditions: the Laurent series x_i = t^(-w_i) sum_k a_ik t^k of the *full* field solved
    order by order, (K - k) a_k = P_k(a_<k); at a resonance k (an integer exponent) the condition is that P_k is in
    the range of K - k, identically in the free coefficients introduced so far (left null vectors, expanded).

Verdict per balance: "all integer, compatible" (the Painleve test is passed at this balance), "logarithmic
resonance" (a compatibility condition fails: the series needs t^k log t), "fractional (algebraic branching)",
"irrational or complex".

Yoshida's theorem (Yoshida 1983, "Necessary condition for the existence of algebraic first integrals I"): if I is
a weighted-homogeneous first integral of weighted degree M of a weighted-homogeneous field and grad I(c) != 0 at a
balance c, then K(c)^T grad I(c) = M grad I(c) (derived in `yoshida_identity`: differentiate grad I . f = 0 at c and
use Euler's relation), so M is a Kovalevskaya exponent.  Consequence (linear algebra): weighted-homogeneous
algebraic (rational degree) first integrals whose gradients are linearly independent at c number at most the
total dimension of the left eigenspaces of K(c) for rational eigenvalues (positive integers for polynomials).
This is what is *proved*; it is a statement about such integrals, not a proof of Liouville non-integrability.
A failed Painleve test alone proves nothing about integrability (evidence only)."""
from __future__ import annotations

import itertools
from dataclasses import dataclass, field

import sympy as sp

RHO = sp.Symbol("rho")


# ----------------------------------------------------------------------------------------------------------------
# weights and dominant parts
# ----------------------------------------------------------------------------------------------------------------
def _terms(f, X):
    """[(i, monomial exponent tuple, coefficient)] of the polynomial field."""
    out = []
    for i, fi in enumerate(f):
        fi = sp.expand(fi)
        if fi == 0:
            continue
        for mono, coef in sp.Poly(fi, *X).terms():
            out.append((i, tuple(int(a) for a in mono), coef))
    return out


def weight_choices(f, X, max_weight: int | None = None) -> list:
    """Weight vectors w (entries 1..max_weight) for which no monomial of f_i exceeds weighted degree w_i + 1 and the
    dominant part is maximal by inclusion among all such w (ties: the lexicographically smallest w).  Each entry is
    (w, dominant term keys).  A w making the whole field dominant (weighted-homogeneous) comes first when one
    exists, and is then the only one returned."""
    n = len(X)
    if max_weight is None:
        max_weight = 3 if n <= 6 else 2
    terms = _terms(f, X)
    valid = {}
    for w in itertools.product(range(1, max_weight + 1), repeat=n):
        dom = []
        ok = True
        for k, (i, mono, _) in enumerate(terms):
            d = sum(a * wi for a, wi in zip(mono, w))
            if d > w[i] + 1:
                ok = False
                break
            if d == w[i] + 1:
                dom.append(k)
        if ok and dom:
            key = frozenset(dom)
            if key not in valid:
                valid[key] = w
    if not valid:
        return []
    full = frozenset(range(len(terms)))
    if full in valid:
        return [(valid[full], full)]
    maximal = [k for k in valid if not any(k < other for other in valid)]
    return sorted(((valid[k], k) for k in maximal), key=lambda e: e[0])


def dominant_field(f, X, w, keys=None):
    """f^0: the monomials of f of weighted degree w_i + 1."""
    terms = _terms(f, X)
    out = [sp.Integer(0)] * len(X)
    for i, mono, coef in terms:
        if sum(a * wi for a, wi in zip(mono, w)) == w[i] + 1:
            out[i] += coef * sp.Mul(*[x**a for x, a in zip(X, mono)])
    return out


# ----------------------------------------------------------------------------------------------------------------
# balances: Groebner decomposition
# ----------------------------------------------------------------------------------------------------------------
def _split(eqs, cs):
    """Components of V(eqs): lex Groebner bases whose elements are irreducible over Q (a basis with a reducible
    element is split along its factors and each branch re-based); embedded and duplicate components removed."""
    done, stack, seen = [], [list(eqs)], set()
    while stack:
        ps = stack.pop()
        G = sp.groebner(ps, *cs, order="lex", domain="QQ")
        if list(G.exprs) == [1]:
            continue
        key = tuple(sp.srepr(g) for g in G.exprs)
        if key in seen:
            continue
        seen.add(key)
        for g in G.exprs:
            _, facs = sp.factor_list(g, *cs)
            if len(facs) > 1 or facs[0][1] > 1:
                for p, _ in facs:
                    stack.append(list(G.exprs) + [p])
                break
        else:
            done.append(G)

    def contains(Gbig, Gsmall):  # V(Gsmall) inside V(Gbig): every element of Gbig vanishes mod Gsmall
        return all(Gsmall.reduce(g)[1] == 0 for g in Gbig.exprs)

    keep = []
    for i, G in enumerate(done):
        if any(j != i and contains(H, G) and not (contains(G, H) and j > i) for j, H in enumerate(done)):
            continue
        keep.append(G)
    return keep


def _main_variables(G, cs):
    mains = set()
    for g in G.exprs:
        lm = sp.Poly(g, *cs).monoms(order="lex")[0]
        mains.add(next(c for c, a in zip(cs, lm) if a))
    return mains


def _is_origin(G, cs):
    return all(G.reduce(c)[1] == 0 for c in cs)


# ----------------------------------------------------------------------------------------------------------------
# exponents
# ----------------------------------------------------------------------------------------------------------------
def kovalevskaya_matrix(f0, X, w, c: dict):
    D = sp.Matrix(f0).jacobian(X)
    return (D + sp.diag(*w)).subs(c)


def _classify_roots(poly):
    """{'roots': [(root, multiplicity)], 'kind': ...} of a polynomial in RHO over Q, classified by factoring."""
    P = sp.Poly(poly, RHO)
    _, facs = sp.factor_list(P.as_expr(), RHO)
    roots, kinds = [], set()
    for fac, mult in facs:
        fp = sp.Poly(fac, RHO)
        if fp.degree() == 1:
            r = sp.Rational(-fp.all_coeffs()[1], fp.all_coeffs()[0])
            roots.append((r, mult))
            kinds.add("integer" if r.is_integer else "fractional")
        else:
            rs = sp.roots(fp, multiple=False)
            if sum(rs.values()) != fp.degree():  # no radical form: the real/complex roots as CRootOf
                rs = {sp.CRootOf(fp, k): 1 for k in range(fp.degree())}
            roots += [(r, m * mult) for r, m in rs.items()]
            kinds.add("irrational or complex")
    return roots, kinds


@dataclass
class Balance:
    """One component of the dominant balances: its lex Groebner basis (in c1..cn), its dimension (0: finitely many
    conjugate points), a representative point (exact), the characteristic polynomial of K over Q (None if it is not
    constant along the component), the exponents with multiplicities, their kind, and the ARS result."""
    basis: list
    dimension: int
    point: dict | None
    charpoly: sp.Expr | None
    exponents: list
    kinds: set
    resonances: list = field(default_factory=list)
    compatible: bool | None = None
    conditions: list = field(default_factory=list)
    note: str = ""

    @property
    def verdict(self) -> str:
        if self.charpoly is None:
            return "exponents vary along the family"
        if "irrational or complex" in self.kinds:
            return "irrational or complex"
        if "fractional" in self.kinds:
            return "fractional (algebraic branching)"
        if self.compatible is False:
            return "logarithmic resonance"
        if self.compatible is None:
            return "all integer, compatibility not checked"
        return "all integer, compatible"

    def as_dict(self, X) -> dict:
        return {"groebner_basis": [str(g) for g in self.basis], "dimension": self.dimension,
                "point": {str(x): str(v) for x, v in (self.point or {}).items()},
                "charpoly": None if self.charpoly is None else str(sp.factor(self.charpoly)),
                "exponents": [[str(r), int(m)] for r, m in self.exponents], "kinds": sorted(self.kinds),
                "resonances": [int(k) for k in self.resonances], "compatible": self.compatible,
                "compatibility_conditions": [str(c) for c in self.conditions], "verdict": self.verdict,
                "note": self.note}


def balances(f0, X, w) -> list:
    """The components of the dominant balances c != 0, with their exponents (no ARS yet)."""
    n = len(X)
    cs = list(sp.symbols(f"c1:{n + 1}"))
    sub = dict(zip(X, cs))
    eqs = [sp.expand(f0[i].subs(sub) + w[i] * cs[i]) for i in range(n)]
    eqs = [e for e in eqs if e != 0]
    Kc = (sp.Matrix(f0).jacobian(X) + sp.diag(*w)).subs(sub)
    cp = sp.expand((Kc - RHO * sp.eye(n)).det(method="berkowitz"))
    out = []
    for G in _split(eqs, cs):
        if _is_origin(G, cs):
            continue
        free = [c for c in cs if c not in _main_variables(G, cs)]
        red = sp.Poly(cp, RHO)
        coeffs = [G.reduce(sp.expand(a))[1] for a in red.all_coeffs()]
        const = all(sp.sympify(a).free_symbols <= set() for a in coeffs)
        point = _point(G, cs, free)
        if const:
            poly = sum(a * RHO**k for k, a in enumerate(reversed(coeffs)))
            roots, kinds = _classify_roots(poly)
            b = Balance(list(G.exprs), len(free), point, sp.expand(poly), roots, kinds)
        else:
            # eliminate c: the exponents that occur anywhere on the component (a polynomial over Q in rho)
            E = sp.groebner(list(G.exprs) + [cp], *cs, RHO, order="lex", domain="QQ")
            uni = [g for g in E.exprs if g.free_symbols <= {RHO}]
            if uni and len(free) == 0:
                roots, kinds = _classify_roots(uni[-1])
                b = Balance(list(G.exprs), 0, point, None, roots, kinds,
                            note="conjugate points with different exponents; exponents listed over all of them")
                b.charpoly = None
            else:
                b = Balance(list(G.exprs), len(free), point, None, [], set(),
                            note="the characteristic polynomial of K is not constant along this family")
        out.append(b)
    return out


def _point(G, cs, free):
    """An exact point of the component: the free variables set to 1, 2, ... (first choice that gives a solution
    with c != 0), the others solved from the triangular lex basis."""
    for trial in itertools.product((1, 2, 3, -1), repeat=len(free)) if free else [()]:
        sub = dict(zip(free, (sp.Integer(t) for t in trial)))
        eqs = [sp.expand(g.subs(sub)) for g in G.exprs]
        eqs = [e for e in eqs if e != 0]
        try:
            sols = sp.solve(eqs, [c for c in cs if c not in sub], dict=True) if eqs else [{}]
        except NotImplementedError:
            continue
        for s in sols:
            pt = {**sub, **s}
            pt = {c: sp.nsimplify(pt[c]) if c in pt else sp.Integer(0) for c in cs}
            if all(sp.expand(g.subs(pt)) == 0 for g in G.exprs) and any(v != 0 for v in pt.values()):
                return pt
    return None


# ----------------------------------------------------------------------------------------------------------------
# ARS: the Laurent series order by order
# ----------------------------------------------------------------------------------------------------------------
def _canon(e):
    """A canonical form for expressions over Q(sqrt's, i)[free coefficients]: denominators rationalised, expanded
    (a zero test that is exact for the algebraic numbers the balances produce: square roots of rationals)."""
    e = sp.expand(sp.radsimp(sp.together(sp.expand(e))))
    return sp.expand(sp.nsimplify(e)) if e.free_symbols == set() and not e.is_Rational else e


def ars_check(f, X, w, c_point: dict, kmax: int):
    """Solve the Laurent series of the full field up to order kmax at the balance point c (dict c_i -> value, in
    the order of X).  Returns (compatible, [(k, condition)], free coefficient symbols).  The coefficient of
    t^(k - w_i - 1) of x_i' - f_i(x) is linear in a_k: (k I - K) a_k = rhs; at a resonance the left null vectors of
    K - k give the conditions, which must expand to 0 identically in the free coefficients."""
    n = len(X)
    tt = sp.Symbol("t")
    cvals = list(c_point.values())
    a = [[cvals[i]] for i in range(n)]
    conds, free = [], []
    ok = True
    for k in range(1, kmax + 1):
        ak = sp.symbols(f"a{k}_1:{n + 1}")
        xs = [tt**(-w[i]) * sum(a[i][j] * tt**j for j in range(k)) + ak[i] * tt**(k - w[i]) for i in range(n)]
        sub = dict(zip(X, xs))
        eqs = []
        for i in range(n):
            # coefficient of t^(k - w_i - 1) in x_i' - f_i(x); multiply by t^(w_i + 1) first: a polynomial in t
            expr = sp.expand((sp.diff(xs[i], tt) - f[i].subs(sub)) * tt**(w[i] + 1))
            eqs.append(sp.expand(expr).coeff(tt, k) if k else expr.subs(tt, 0))
        A, rhs = sp.linear_eq_to_matrix(eqs, ak)
        M = A.applyfunc(_canon)  # = k I - K
        rhs = rhs.applyfunc(_canon)
        if _canon(M.det(method="berkowitz")) != 0:
            sol = M.LUsolve(rhs)
            for i in range(n):
                a[i].append(_canon(sol[i]))
            continue
        # resonance: conditions from the left null space of M
        for v in M.T.nullspace(simplify=_canon):
            cond = _canon((v.T * rhs)[0, 0])
            conds.append((k, cond))
            if cond != 0:
                ok = False
        if not ok:
            break
        # a particular solution plus the kernel (free coefficients)
        params = sp.symbols(f"b{k}_1:{n + 1}")
        sol, pars = M.gauss_jordan_solve(rhs)
        renamed = dict(zip(pars, params[:len(pars)]))
        free.extend(renamed.values())
        for i in range(n):
            a[i].append(_canon(sol[i].subs(renamed)))
    return ok, conds, free


def analyse_field(f, X, *, max_weight=None, ars: bool = True, kmax_limit: int = 8) -> dict:
    """The whole analysis of a polynomial field: weights, dominant part, balances, exponents, ARS, Yoshida data.
    Returns {"choices": [{"weights", "homogeneous", "balances": [Balance]}]}."""
    out = []
    for w, _keys in weight_choices(f, X, max_weight):
        f0 = dominant_field(f, X, w)
        homog = all(sp.expand(a - b) == 0 for a, b in zip(f, f0))
        bals = balances(f0, X, w)
        for b in bals:
            ints = sorted({int(r) for r, _ in b.exponents if r.is_integer and r > 0})
            b.resonances = ints
            if ars and b.point is not None and b.charpoly is not None and not (b.kinds - {"integer"}):
                kmax = max(ints, default=0)
                if kmax > kmax_limit:
                    b.note += f"; resonances above {kmax_limit} not checked"
                    kmax = kmax_limit
                ok, conds, _ = ars_check(f, X, w, b.point, kmax)
                b.compatible = ok
                b.conditions = [c for _, c in conds if c != 0]
        out.append({"weights": tuple(w), "homogeneous": homog, "dominant": f0, "balances": bals})
    return {"state": list(X), "choices": out}


# ----------------------------------------------------------------------------------------------------------------
# Yoshida's theorem
# ----------------------------------------------------------------------------------------------------------------
def weighted_degree(I, X, w):
    """The weighted degree M of a weighted-homogeneous polynomial I (None if I is not weighted-homogeneous)."""
    P = sp.Poly(sp.expand(I), *X)
    degs = {sum(a * wi for a, wi in zip(m, w)) for m in P.monoms()}
    return degs.pop() if len(degs) == 1 else None


def yoshida_identity(I, f0, X, w, c: dict):
    """K(c)^T grad I(c) - M grad I(c) (zero vector when I is a weighted-homogeneous integral of f0 of degree M):
    the identity behind Yoshida's theorem, evaluated exactly."""
    M = weighted_degree(I, X, w)
    g = sp.Matrix([sp.diff(I, x) for x in X]).subs(c)
    K = kovalevskaya_matrix(f0, X, w, c)
    return M, sp.expand(K.T * g - M * g), g


def rational_left_eigenspace_dim(K, exponents, positive_integers_only=False) -> int:
    """Sum over the rational eigenvalues r (positive integers only if asked) of dim ker (K^T - r)."""
    tot = 0
    for r, _m in exponents:
        if r.is_rational and (not positive_integers_only or (r.is_integer and r > 0)):
            tot += len((K.T - r * sp.eye(K.rows)).nullspace())
    return tot


def model_field(model, values: dict | None = None):
    """(state, field) of a derive.models Model with the parameters at `values` (default: the model's defaults),
    every value exact."""
    from .models.pipeline import equations

    vals = {p: sp.nsimplify(sp.sympify(v[2], strict=True)) for p, v in model.parameters.items()}
    for k, v in (values or {}).items():
        key = next((p for p in model.parameters if str(p) == str(k)), None)
        if key is None:
            raise ValueError(f"values: {k} is not a parameter of {model.name}")
        vals[key] = sp.nsimplify(v)
    f = [sp.expand(e.subs(vals)) for e in equations(model)]
    return list(model.state), f, vals


PAINLEVE_PASSED = "Painleve test passed at every balance found"
PAINLEVE_FAILED = "Painleve test failed"
EVIDENCE = "evidence"
PROVED = "proved"


def model_analysis(model, values: dict | None = None, *, ars: bool = True) -> dict:
    """The Kovalevskaya-Painleve analysis of a rod model (derive.models Model) at exact parameter values, as a
    JSON-able dict: per weight choice the balances (c, exponents, verdict), the Painleve verdict (evidence), and
    where the whole field is weighted-homogeneous Yoshida's theorem applied to H and the Casimirs found (proved)."""
    from .models.pipeline import casimirs

    X, f, vals = model_field(model, values)
    res = analyse_field(f, X, ars=ars)
    known = {"H": sp.expand(model.H.subs(vals))}
    for i, c in enumerate(casimirs(model), 1):
        known[f"C{i}"] = sp.expand(c.subs(vals))
    choices = []
    all_pass, any_bal = True, False
    for ch in res["choices"]:
        w, f0 = ch["weights"], ch["dominant"]
        entry = {"weights": {str(x): int(wi) for x, wi in zip(X, w)}, "homogeneous": ch["homogeneous"],
                 "dominant_part": [str(e) for e in f0], "balances": []}
        for b in ch["balances"]:
            any_bal = True
            d = b.as_dict(X)
            if d["verdict"] != "all integer, compatible":
                all_pass = False
            if ch["homogeneous"] and b.point is not None:
                d["yoshida"] = yoshida_at(known, f0, X, w, b)
            entry["balances"].append(d)
        choices.append(entry)
    out = {"parameters": {str(k): str(v) for k, v in vals.items()}, "choices": choices,
           "homogeneous": any(c["homogeneous"] for c in choices)}
    if not any_bal:
        out["painleve"] = {"verdict": "no dominant balance found", "label": EVIDENCE}
    else:
        out["painleve"] = {"verdict": PAINLEVE_PASSED if all_pass else PAINLEVE_FAILED, "label": EVIDENCE,
                           "meaning": "every balance found (weights <= 3, resonances <= 8) has integer exponents and compatible "
                           "resonances: necessary for the Painleve property, not a proof of integrability" if
                           all_pass else "some balance has non-integer exponents or a logarithmic resonance: the "
                           "general solution is not single-valued (evidence of non-integrability, not a proof)"}
    out["yoshida"] = yoshida_summary(choices, len(X), len(known) - 1)
    return out


def yoshida_at(known: dict, f0, X, w, b: Balance) -> dict:
    """At a balance point c: the weighted degree of each known integral, whether its gradient vanishes at c, and
    Yoshida's identity K^T grad I(c) = M grad I(c) checked exactly; the bound on the number of weighted-homogeneous
    polynomial (and algebraic) integrals with gradients independent at c; the rank of the known gradients."""
    cpt = dict(zip(X, b.point.values()))
    K = kovalevskaya_matrix(f0, X, w, cpt).applyfunc(_canon)
    rows, grads = {}, []
    for k, I in known.items():
        M = weighted_degree(I, X, w)
        if M is None:
            rows[k] = {"weighted_degree": None}
            continue
        _, resid, g = yoshida_identity(I, f0, X, w, cpt)
        g = g.applyfunc(_canon)
        nz = any(v != 0 for v in g)
        if nz:
            grads.append(g.T)
        rows[k] = {"weighted_degree": int(M), "gradient_nonzero_at_c": nz,
                   "identity_holds": all(_canon(v) == 0 for v in resid),
                   "degree_is_exponent": any(r == M for r, _ in b.exponents)}
    rank = sp.Matrix.vstack(*grads).rank(simplify=_canon) if grads else 0
    return {"integrals": rows, "rank_of_known_gradients_at_c": int(rank),
            "bound_polynomial": rational_left_eigenspace_dim(K, b.exponents, positive_integers_only=True),
            "bound_algebraic": rational_left_eigenspace_dim(K, b.exponents)}


def yoshida_summary(choices, n: int, n_casimirs: int) -> dict:
    """Yoshida's theorem where the whole field is weighted-homogeneous (hypotheses checked), else not applicable."""
    need = n_casimirs + (n - n_casimirs) // 2  # Casimirs + half the leaf dimension: Liouville on the generic leaf
    hom = [c for c in choices if c["homogeneous"]]
    if not hom:
        return {"applies": False, "label": "not applicable",
                "reason": "the field is not weighted-homogeneous for any positive integer weights (only its "
                          "dominant part is): Yoshida's theorem needs the whole field homogeneous"}
    best = None
    for b in hom[0]["balances"]:
        y = b.get("yoshida")
        if not y:
            continue
        ok = all(r.get("identity_holds", True) for r in y["integrals"].values())
        if not ok:
            return {"applies": True, "label": "disagrees", "reason": "Yoshida's identity fails at a balance: the "
                    "field or the integrals are wrong"}
        if y["bound_polynomial"] <= y["rank_of_known_gradients_at_c"] and (best is None or y["bound_polynomial"] <
                                                                              best["bound_polynomial"]):
            best = {"balance_point": b["point"], **y}
    if best is None:
        return {"applies": True, "label": "no conclusion", "obstruction": False,
                "statement": "Yoshida's theorem gives no obstruction: at every balance the positive-integer exponents "
                             "leave room for weighted-homogeneous polynomial integrals beyond H and the Casimirs",
                "needed_for_liouville": need}
    return {"applies": True, "label": PROVED, "obstruction": True, "needed_for_liouville": need,
            "balance_point": best["balance_point"], "bound_polynomial": best["bound_polynomial"],
            "statement": (f"Yoshida (1983), hypotheses checked (field weighted-homogeneous, balance c exact, "
                          f"K^T grad I = M grad I verified for H and the Casimirs): at the balance c every "
                          f"weighted-homogeneous polynomial first integral has its gradient at c in the span of the "
                          f"left eigenvectors of K(c) for positive integer exponents, a space of dimension "
                          f"{best['bound_polynomial']} already spanned by the gradients of H and the Casimirs. "
                          f"Hence there is no weighted-homogeneous polynomial first integral whose gradient at c is "
                          f"independent of theirs (Liouville integrability on the generic leaf needs {need} "
                          "independent integrals with the Casimirs). Not proved: non-existence of integrals whose "
                          "gradients happen to be dependent at c, or of non-polynomial ones.")}
