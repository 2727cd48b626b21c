"""Morales-Ramis theory along the pendulum solutions of a rod model, exact.

Morales-Ramis theorem (Morales-Ruiz & Ramis 2001, Methods Appl. Anal. 8; for Poisson systems restricted to a
symplectic leaf as in Maciejewski & Przybylska 2005, Ann. Fac. Sci. Toulouse 14): if a Hamiltonian system is
integrable in the Liouville sense with first integrals meromorphic in a neighbourhood of a non-equilibrium phase
curve Gamma, the identity component G0 of the differential Galois group of the normal variational equation (NVE)
along Gamma is abelian.  G0 is unchanged by a finite branched covering of the independent variable (t -> z = a
coordinate along Gamma) and by the reduction y = w exp(-1/2 int p) when exp(int p) is algebraic.

Pipeline here, from the model's field (derive/models/pipeline.equations), every step exact:
  1. `invariant_planes`: coordinate subspaces V = {x_N = 0} of dimension 3 invariant under the field, on which one
     Casimir is non-constant and the others vanish (the pendulum-like motions of the top: rotation about a
     principal axis perpendicular to the force axis), with the Casimirs whose gradient has no tangential part on V
     (their linearisation is a first integral of the NVE);
  2. `nve`: the normal block of the Jacobian on V; the linearised Casimir (level 0: variations inside the
     symplectic leaf of Gamma) eliminates one normal variable; the 2x2 system becomes a second-order equation for
     another; the independent variable becomes z = a tangent coordinate (z' = dz/dt along Gamma) and the remaining
     tangent coordinates are eliminated with the energy h and the Casimir level 1 (their squares are polynomials in
     z): the result y'' + p(z) y' + q(z) y = 0 with p, q rational in z (refused if odd powers remain);
  3. at the energy of the pendulum's unstable equilibrium (the separatrix) the equation has three regular singular
     points: `riemann_data` gives the exponent differences from the indicial equations, Kimura's theorem decides
     (derive/kovacic.kimura), and Kovacic's algorithm (derive/kovacic.galois) decides at any rational parameter and
     any energy (a Heun-type equation with four singular points at a generic level).

The theorem for the symmetric rod (B2 = C = r B1) is `symmetric_rod_theorem`."""
from __future__ import annotations

import itertools

import sympy as sp

from . import kovacic

z = sp.Symbol("z")
h = sp.Symbol("h")
r = sp.Symbol("r", positive=True)


def _casimirs(model, vals):
    from .models.pipeline import casimirs

    return [sp.expand(c.subs(vals)) for c in casimirs(model)]


def _psd_sum_of_squares(c, X):
    """True if c is a nonzero sum of positive multiples of squares of coordinates (|e3|^2, |n|^2): its level 0 is
    a degenerate leaf (e3 = 0, n = 0), not one of the physical problem."""
    try:
        P = sp.Poly(c, *X)
    except sp.PolynomialError:
        return False
    if P.is_zero:
        return False
    for mono, k in P.terms():
        if sorted(mono, reverse=True)[:2] != [2, 0] or sum(mono) != 2 or k.is_positive is not True:
            return False
    return True


def _generic_rank(rows, X):
    """Rank of a matrix of polynomials at a seeded rational point (a lower bound of the generic rank, equal to it
    outside a proper algebraic set; deterministic)."""
    if not rows:
        return 0
    pt = {v: sp.Rational(3 + 2 * i, 7 + i) for i, v in enumerate(X)}
    return sp.Matrix([[sp.sympify(e).subs(pt) for e in row] for row in rows]).rank()


def invariant_planes(model, vals: dict) -> list:
    """Every invariant coordinate subspace V = {x_N = 0} of the field (any dimension) on which the restricted flow
    has one degree of freedom on a symplectic leaf: dim V minus the generic rank of the restricted Casimirs is 2
    (a curve on each energy level) and the restricted field is not zero.  V on a degenerate leaf (a sum of squares
    Casimir vanishing identically on V, e.g. e3 = 0) is skipped.  Each entry: (normal indices N, tangent indices T,
    the live restricted Casimirs (a product of them for the 6-D models is the pendulum's), the normal gradients of
    the Casimirs whose gradient has no tangential part on V, the frozen tangent coordinates)."""
    from .models.pipeline import equations

    X = model.state
    f = [sp.expand(e.subs(vals)) for e in equations(model)]
    cas = _casimirs(model, vals)
    n = len(X)
    out = []
    for k in range(2, n):
        for T in itertools.combinations(range(n), k):
            N = [i for i in range(n) if i not in T]
            sub = {X[i]: 0 for i in N}
            if any(sp.expand(f[i].subs(sub)) != 0 for i in N):
                continue
            if all(sp.expand(f[i].subs(sub)) == 0 for i in T):
                continue
            restricted = [sp.expand(c.subs(sub)) for c in cas]
            if any(c == 0 and _psd_sum_of_squares(cc, X) for c, cc in zip(restricted, cas)):
                continue
            live = [c for c in restricted if c.free_symbols]
            XT = [X[i] for i in T]
            if len(T) - _generic_rank([[sp.diff(c, v) for v in XT] for c in live], XT) != 2:
                continue
            lin = []
            for c in cas:
                g = [sp.expand(sp.diff(c, X[i]).subs(sub)) for i in range(n)]
                if all(g[i] == 0 for i in T) and any(g[i] != 0 for i in N):
                    lin.append([g[i] for i in N])
            frozen = [X[i] for i in T if sp.expand(f[i].subs(sub)) == 0]
            out.append((N, list(T), live[0] if len(live) == 1 else live, lin, frozen))
    return out


def _known_integrals(model, vals):
    """{name: I} of the model's candidate integrals that Poisson-commute with H at `vals` (checked), Casimirs not
    included."""
    from .models.pipeline import bracket

    H = model.H
    out = {}
    for k, (e, _) in model.candidates.items():
        I = sp.expand(sp.sympify(e, strict=True))
        if sp.expand(bracket(model, I, H).subs(vals)) == 0:
            out[k] = sp.expand(I.subs(vals))
    return out


def normal_block(model, vals: dict, plane):
    """The normal variational equation along the 1-DOF flow on `plane`, cut down to its last quotient:
    xi' = A xi on the normal coordinates; the linearised Casimirs and known integrals whose gradient has no tangential
    part are first integrals of it (their level 0: variations inside the leaf and the integral's level set) and
    eliminate one coordinate each; the Hamiltonian vector field X_I = J grad I of a known integral I whose tangential
    part vanishes is a solution (the flows of H and I commute), and the quotient by it is taken (the Galois group of
    a quotient system is a quotient of the group, so a non-abelian G0 there proves a non-abelian G0 of the NVE).
    Returns (M (d x d, rational in the tangent coordinates), the names of the remaining normal coordinates, the
    substitutions {frozen coordinate: value}, a description) or (None, reason)."""
    from .models.pipeline import equations

    X = model.state
    N, T, _live, _lins, frozen = plane
    f = [sp.expand(e.subs(vals)) for e in equations(model)]
    sub = {X[i]: 0 for i in N}
    fix = {v: sp.Integer(1) for v in frozen}  # a frozen coordinate on its unit level (e.g. e31 = 1)
    J = sp.Matrix(f).jacobian(X)
    A = J.extract(N, N).subs(sub).subs(fix)
    cas = _casimirs(model, vals)
    ints = _known_integrals(model, vals)
    desc = {"constraints": [], "quotient_by": []}
    names = [X[i] for i in N]
    ft = {X[i]: sp.expand(f[i].subs(sub).subs(fix)) for i in T if X[i] not in fix}

    def dt(e):
        num, den = sp.fraction(sp.together(e))
        d = lambda u: sp.expand(sum(sp.diff(u, v) * ft[v] for v in ft))  # noqa: E731
        return sp.cancel((d(num) * den - num * d(den)) / den**2)
    st = {"keep": list(range(len(N))), "L": sp.eye(len(N)), "M": A}

    def constrain(name, g):
        """Restrict to g . xi = 0 (a first integral of the NVE): eliminate one kept coordinate."""
        keep, L = st["keep"], st["L"]
        gk = [sp.expand(sum(g[a] * L[a, b] for a in range(len(N)))) for b in range(len(keep))]
        if all(sp.simplify(e) == 0 for e in gk):
            return False
        piv = sorted((b for b in range(len(keep)) if gk[b] != 0),
                     key=lambda b: (not gk[b].is_number, sp.count_ops(gk[b])))[0]
        cols = [b for b in range(len(keep)) if b != piv]
        E = sp.zeros(len(keep), len(keep) - 1)
        for j, b in enumerate(cols):  # xi_keep[piv] = -sum_{b != piv} gk_b xi_keep[b] / gk_piv
            E[b, j] = 1
            E[piv, j] = sp.cancel(-gk[b] / gk[piv])
        st["L"] = (L * E).applyfunc(sp.cancel)
        desc["constraints"].append(f"{name} (eliminates d{names[keep[piv]]}): "
                                   + " + ".join(f"({g[a]}) d{names[a]}" for a in range(len(N)) if g[a] != 0))
        st["keep"] = [keep[b] for b in cols]
        st["M"] = (A * st["L"]).extract(st["keep"], list(range(len(cols)))).applyfunc(sp.cancel)
        return True

    def quotient(name, v):
        """Quotient by a known solution v of the NVE: eta = P xi with P = 1 - v e_k^T / v_k solves
        eta' = (P' + P M) eta and eta_k = 0."""
        keep, M = st["keep"], st["M"]
        vk = sp.Matrix([v[a] for a in keep])
        cand = sorted((b for b in range(len(keep)) if sp.simplify(vk[b]) != 0),
                      key=lambda b: (not vk[b].is_number, sp.count_ops(vk[b])))
        if not cand:
            return
        k = cand[0]
        P = sp.eye(len(keep)) - vk * sp.Matrix([[1 if b == k else 0 for b in range(len(keep))]]) / vk[k]
        Mq = (P.applyfunc(dt) + P * M).applyfunc(sp.cancel)
        rest = [b for b in range(len(keep)) if b != k]
        st["M"] = Mq.extract(rest, rest)
        st["keep"] = [keep[b] for b in rest]
        st["quotiented"] = True
        desc["quotient_by"].append(f"X_{name} = (" + ", ".join(str(v[a]) for a in range(len(N))) + f"), "
                                   f"eliminates d{names[keep[k]]}")

    def grad_normal(c):
        g = [sp.expand(sp.diff(c, X[i]).subs(sub).subs(fix)) for i in range(len(X))]
        return [g[i] for i in N] if all(g[i] == 0 for i in T) and any(g[i] != 0 for i in N) else None
    # the linearised Casimirs (variations inside the leaf), then per known integral I: its level (dI = 0) and the
    # quotient by X_I (the symplectic reduction by the symmetry I generates), while more than 2 dimensions remain
    for i, c in enumerate(cas):
        g = grad_normal(c)
        if g is not None and len(st["keep"]) > 2:
            constrain(f"Casimir {i + 1}", g)
    for name, I in ints.items():
        if len(st["keep"]) <= 2 or st.get("quotiented"):
            break  # (a constraint after a quotient would need the quotient's coordinates: not attempted)
        g = grad_normal(I)
        if g is None or not constrain(name, g) or len(st["keep"]) <= 2:
            continue
        v = (model.J.subs(vals) * sp.Matrix([sp.diff(I, x_) for x_ in X])).subs(sub).subs(fix)
        if all(sp.expand(v[i]) == 0 for i in T):
            quotient(name, [sp.expand(v[i]) for i in N])
    keep, M = st["keep"], st["M"]
    return M, [names[a] for a in keep], fix, desc


def _relations(eqs, zt, others, linear=True):
    """{v: ("=", poly in zt) or ("^2", poly in zt)} for the other tangent coordinates from the level equations
    eqs (= 0), solved one at a time: an equation that (after the values known so far) contains one unknown
    coordinate v, linearly (v = ...) or only as v^2 (v^2 = ...).  None if some coordinate is not reached."""
    rels = {}
    eqs = list(eqs)
    progress = True
    while progress and len(rels) < len(others):
        progress = False
        for e in eqs:
            e2 = _apply(e, rels)
            if e2 is None:
                continue
            unk = e2.free_symbols & (set(others) - set(rels))
            if len(unk) != 1 or (e2.free_symbols & set(others)) - unk:
                continue
            v = unk.pop()
            P = sp.Poly(e2, v)
            if P.degree() == 1 and linear:
                rels[v] = ("=", sp.expand(-P.coeff_monomial(1) / P.coeff_monomial(v)))
            elif P.degree() == 2 and P.coeff_monomial(v) == 0:
                rels[v] = ("^2", sp.expand(-P.coeff_monomial(1) / P.coeff_monomial(v**2)))
            else:
                continue
            progress = True
    return rels if len(rels) == len(others) else None


def _apply(e, rels):
    """e with the known coordinates replaced: v -> poly (linear relations), v^2 -> poly (square relations; None if
    an odd power of such a v remains)."""
    e = sp.expand(e.subs({v: r for v, (k, r) in rels.items() if k == "="}))
    sq = [v for v, (k, _) in rels.items() if k == "^2" and v in e.free_symbols]
    if not sq:
        return e
    P = sp.Poly(e, *sq)
    tot = sp.Integer(0)
    for mono, c in P.terms():
        if any(a % 2 for a in mono):
            return None
        term = c
        for v, a in zip(sq, mono):
            term *= rels[v][1] ** (a // 2)
        tot += term
    return sp.expand(tot)


def _rationalise(expr, rels: dict, zt):
    """expr (rational in the tangent coordinates) as a rational function of z, using the relations of
    `_relations` ({coordinate: ("=", poly) or ("^2", poly)} in zt); zt becomes z.  None if an odd power of a
    square-known coordinate survives."""
    lin = {v: r for v, (k, r) in rels.items() if k == "="}
    num, den = sp.fraction(sp.together(sp.expand(expr).subs(lin)))
    num, den = sp.expand(num), sp.expand(den)
    sq = {v: r for v, (k, r) in rels.items() if k == "^2"}
    for v in sq:  # make the denominator even in v: multiply by its conjugate E - v O (den = E + v O)
        if v not in den.free_symbols:
            continue
        P = sp.Poly(den, v)
        E = sum((c * v**m[0] for m, c in P.terms() if m[0] % 2 == 0), sp.Integer(0))
        O = sp.expand(den - E)
        if O != 0:
            num, den = sp.expand(num * (E - O)), sp.expand(E**2 - O**2)
    nn = _apply(num, {v: ("^2", r) for v, r in sq.items()})
    dd = _apply(den, {v: ("^2", r) for v, r in sq.items()})
    if nn is None or dd is None or dd == 0:
        return None
    return sp.cancel(sp.together(nn.subs(zt, z) / dd.subs(zt, z)))


def nve(model, vals: dict, plane, energy=h, level=1):
    """The NVE along the pendulum of `plane` as (p, q, description): y'' + p y' + q y = 0 in z, rational, at
    energy `energy` and level `level` of the live Casimirs; None if the normal block does not reduce to 2 x 2 or no
    choice of (unknown, independent variable) gives rational coefficients (`nve_reason` says which)."""
    res = nve_reason(model, vals, plane, energy, level)
    return None if isinstance(res, str) else res


def nve_reason(model, vals: dict, plane, energy=h, level=1):
    """`nve`, or the reason (a sentence) why none was found."""
    X = model.state
    N, T, _live, _lins, frozen = plane
    M, names, fix, desc = normal_block(model, vals, plane)
    if M.shape != (2, 2):
        return (f"the normal variational equation is {M.shape[0]}-dimensional after the linearised Casimirs and "
                "integrals and the symmetry quotients: not a second-order equation")
    from .models.pipeline import equations

    f = [sp.expand(e.subs(vals)) for e in equations(model)]
    sub = {X[i]: 0 for i in N}
    ft = {X[i]: sp.expand(f[i].subs(sub).subs(fix)) for i in T if X[i] not in fix}

    def dt(e):
        return sp.expand(sum(sp.diff(e, v) * ft[v] for v in ft))
    Hr = sp.expand(model.H.subs(vals).subs(sub).subs(fix))
    live = [c for c in (sp.expand(c.subs(sub).subs(fix)) for c in _casimirs(model, vals)) if c.free_symbols]
    # square relations only first (a Riemann P-equation in n3 at the separatrix of a top's pendulum), then linear
    for u, linear in itertools.product(range(2), (False, True)):  # the unknown y = the u-th remaining coordinate
        o = 1 - u
        a11, a12, a21, a22 = M[o, o], M[o, u], M[u, o], M[u, u]
        if sp.simplify(a21) == 0:
            continue
        # y' = a21 w + a22 y, w' = a11 w + a12 y  =>  y'' - P y' + Q y = 0
        da21 = _dtr(a21, dt)
        Pt = a11 + a22 + da21 / a21
        Qt = a11 * a22 - a12 * a21 - _dtr(a22, dt) + a22 * da21 / a21
        for zt in ft:
            zdot = ft[zt]
            if zdot == 0:
                continue
            zdd = dt(zdot)
            others = [v for v in ft if v != zt]
            eqs = [Hr - energy] + [c - level for c in live]
            rels = _relations(eqs, zt, others, linear)
            if rels is None and linear and len(eqs) > 1:  # combinations of the levels (a lex Groebner basis)
                try:
                    gb = list(sp.groebner(eqs, *others, zt, order="lex"))
                except (sp.PolificationFailed, sp.GeneratorsError, sp.DomainError):
                    gb = []
                rels = _relations(eqs + gb, zt, others, linear) if gb else None
            if rels is None:
                continue
            p = _rationalise((zdd - Pt * zdot) / zdot**2, rels, zt)
            q = _rationalise(Qt / zdot**2, rels, zt)
            if p is None or q is None:
                continue
            return p, q, {**desc, "unknown": str(names[u]), "z": str(zt), "normal": [str(X[i]) for i in N],
                          "tangent": [str(X[i]) for i in T], "frozen": {str(k): str(v) for k, v in fix.items()},
                          "relations": {str(k): f"{k}{'' if kind == '=' else '^2'} = {r}"
                                        for k, (kind, r) in rels.items()}}
    return (f"the normal variational equation reduces to d({', '.join(str(v) for v in names)})/dt = M ({', '.join(str(v) for v in names)}) with "
            f"M = {[[str(sp.factor(M[i, j])) for j in range(2)] for i in range(2)]} along the solution, but on the energy and Casimir levels no tangent coordinate "
            "determines the others linearly or through their squares (the solution lies on a curve not rationally "
            "parametrised by one coordinate, or odd powers of a coordinate known only through its square remain): "
            "no rational second-order equation")


def _dtr(e, dt):
    num, den = sp.fraction(sp.together(e))
    return sp.together((dt(num) * den - num * dt(den)) / den**2)


def irrational_singular_points(p, q) -> list:
    """The irreducible factors of degree > 1 over Q of the denominators of p and q (as strings): singular points
    that are not rational."""
    dens = sp.denom(sp.together(p)) * sp.denom(sp.together(q))
    return [str(f.as_expr()) for f, _ in sp.factor_list(sp.Poly(dens, z))[1] if f.degree() > 1]


def singular_points(p, q):
    """Finite singular points of y'' + p y' + q y = 0 (poles of p or q)."""
    dens = sp.denom(sp.together(p)) * sp.denom(sp.together(q))
    return sorted(set(sp.roots(sp.Poly(dens, z)).keys()), key=sp.default_sort_key)


def exponent_difference(p, q, c):
    """The difference of the roots of the indicial equation at c (c = sp.oo for infinity), a regular singular
    point: rho (rho - 1) + p0 rho + q0 = 0."""
    if c == sp.oo:
        u = sp.Symbol("u_")
        # z = 1/u: y_zz + p y_z + q y -> u^4 y_uu + (2 u^3 - u^2 p(1/u)) y_u + q(1/u) y
        P = sp.cancel((2 * u**3 - u**2 * p.subs(z, 1 / u)) / u**4)
        Q = sp.cancel(q.subs(z, 1 / u) / u**4)
        return exponent_difference(P.subs(u, z), Q.subs(u, z), 0)
    p0 = sp.limit(sp.cancel(p * (z - c)), z, c)
    q0 = sp.limit(sp.cancel(q * (z - c) ** 2), z, c)
    if p0.has(sp.oo, sp.zoo) or q0.has(sp.oo, sp.zoo):
        raise ValueError(f"irregular singular point at {c}")
    disc = sp.expand((1 - p0) ** 2 - 4 * q0)
    return sp.sqrt(sp.factor(disc))


def riemann_data(p, q) -> dict:
    """{singular point: exponent difference} including infinity (three points: a Riemann P-equation)."""
    pts = singular_points(p, q) + [sp.oo]
    return {c: exponent_difference(p, q, c) for c in pts}


def galois_of(p, q) -> kovacic.GaloisResult:
    """Kovacic's algorithm on y'' + p y' + q y = 0 (exact rational coefficients)."""
    return kovacic.galois(kovacic.reduce_form(p.subs(z, kovacic.x), q.subs(z, kovacic.x)))


# ----------------------------------------------------------------------------------------------------------------
# the theorem for the symmetric anisotropic rod B2 = C = r B1
# ----------------------------------------------------------------------------------------------------------------
EXCEPTIONAL = (sp.Integer(1), sp.Integer(2), sp.Integer(4))
HALF_ROWS = [(e2, e3) for (e1, e2, e3), _, _ in kovacic.KIMURA_TABLE if e1 == sp.Rational(1, 2)]


def _symmetric_rod():
    from . import models

    m = models.get("anisotropic")
    B1, B2, C = m.params
    return m, {B1: 1, B2: r, C: r}


def pendulum_nves(model, vals, energy=h):
    """[(plane, p, q, description)] for every invariant plane of the model (NVE at `energy`)."""
    out = []
    for pl in invariant_planes(model, vals):
        res = nve(model, vals, pl, energy)
        if res is not None:
            out.append((pl, *res))
    return out


def _mod1(v):
    return v - sp.floor(v)


def _table_impossible_gamma1():
    """Kimura rows 2-15 for (1/2, s, 3/2 - 2 s^2): lambda = 1/2 must sit in a '1/2' slot (no other entry is 1/2 mod 1
    up to sign), so s and nu are rational with denominators 3, 4 or 5; nu mod 1 depends on s = p/d only through
    p mod d^2: enumerate."""
    entries = {e for row, _, _ in kovacic.KIMURA_TABLE for e in row}
    assert all(_mod1(e) != sp.Rational(1, 2) and _mod1(-e) != sp.Rational(1, 2) for e in entries - {sp.Rational(1, 2)})
    for e2, e3 in HALF_ROWS:
        for es, en in ((e2, e3), (e3, e2)):
            d = sp.denom(es)
            for p in range(1, d**2 + 1):
                s = sp.Rational(p, d)
                if _mod1(s) not in (_mod1(es), _mod1(-es)):
                    continue
                nu = sp.Rational(3, 2) - 2 * s**2
                if _mod1(nu) in (_mod1(en), _mod1(-en)):
                    return False
    return True


def _table_impossible_gamma2():
    """Kimura rows 2-15 for (1/2, a, b), b^2 = (8 a^2 - 7)/4: a = p/d, and b rational means 8 p^2 - 7 d^2 = m^2,
    b = m/(2d); b = +-e' mod 1 fixes m mod 2d.  Impossible modulo 8 for every row (enumerated)."""
    for e2, e3 in HALF_ROWS:
        for ea, eb in ((e2, e3), (e3, e2)):
            d = sp.denom(ea)
            M = 8
            for p in range(0, 2 * d * M):
                a = sp.Rational(p, d)
                if _mod1(a) not in (_mod1(ea), _mod1(-ea)):
                    continue
                for mm in range(0, 2 * d * M):
                    b = sp.Rational(mm, 2 * d)
                    if _mod1(b) not in (_mod1(eb), _mod1(-eb)):
                        continue
                    if (mm**2 - (8 * p**2 - 7 * d**2)) % M == 0:
                        return False
    return True


def symmetric_rod_theorem() -> dict:
    """Non-integrability of the symmetric anisotropic rod B2 = C = r B1 (and its mirror B1 = C = r B2) on the
    symplectic leaf m.n = 0 for every r > 0 outside {1, 2, 4}: every step computed and checked here (see the
    `steps`).  Returns a JSON-able dict with the theorem text, the steps (each with ok: True/False) and the
    explanation of each exceptional r."""
    from .models.pipeline import bracket, equations

    model, vals = _symmetric_rod()
    X = model.state
    m1, m2, m3, n1, n2, n3 = X
    s, q, k, j = sp.symbols("s q k j", positive=True)
    steps = []

    def step(name, ok, text):
        steps.append({"step": name, "ok": bool(ok), "text": text})

    # 0. the normalisation B1 = 1 and the mirror
    B1, B2, C = model.params
    t = sp.Symbol("t_", positive=True)
    f = equations(model)
    f_t = [e.subs({B1: t * B1, B2: t * B2, C: t * C}, simultaneous=True).subs({x_: t * x_ for x_ in X},
                                                                              simultaneous=True) for e in f]
    scal = all(sp.simplify(a - t * b) == 0 for a, b in zip(f_t, f))
    step("scaling", scal, "the field of stiffnesses t B at t x is t times the field of B at x (symbolic): a linear "
         "change of variables, so only r = B2/B1 = C/B1 matters; B1 = 1")
    phi = {m1: m2, m2: -m1, m3: m3, n1: n2, n2: -n1, n3: n3}
    Hm = model.H.subs(phi, simultaneous=True)
    Jphi = sp.Matrix(6, 6, lambda i, jj: sp.diff(X[i].subs(phi, simultaneous=True), X[jj]))
    mirror = (sp.expand(Hm - model.H.subs({B1: B2, B2: B1}, simultaneous=True)) == 0 and
              sp.expand(Jphi * model.J * Jphi.T - model.J.subs(phi, simultaneous=True)) == sp.zeros(6, 6))
    step("mirror", mirror, "the quarter turn about d3 (m1, m2, n1, n2) -> (m2, -m1, n2, -n1) is a Poisson map of "
         "e(3)* taking H(B1, B2, C) to H(B2, B1, C): the mirror family B1 = C = r B2 is the same system")
    # 1. the pendulums and their NVEs
    nves = pendulum_nves(model, vals)
    step("pendulums", len(nves) == 2, "two invariant planes with a pendulum flow found: " + "; ".join(
        f"{d['normal']} = 0 (z = {d['z']})" for _, _, _, d in nves))
    data = []
    for _pl, p, qq, d in nves:
        p1, q1 = sp.cancel(p.subs(h, 1)), sp.cancel(qq.subs(h, 1))
        rd = riemann_data(p1, q1)
        data.append({"plane": d, "p": str(sp.factor(p)), "q": str(sp.factor(qq)),
                     "separatrix_exponent_differences": {str(c): str(v) for c, v in rd.items()}, "_rd": rd,
                     "_pq": (p, qq)})
    sq = [sorted((sp.factor(v**2) for v in g["_rd"].values()), key=sp.default_sort_key) for g in data]
    want1 = sorted([sp.Rational(1, 4), 1 / r, sp.factor((3 * r - 4)**2 / (4 * r**2))], key=sp.default_sort_key)
    want2 = sorted([sp.Rational(1, 4), r, sp.factor((8 * r - 7) / 4)], key=sp.default_sort_key)
    ok1 = len(sq) == 2 and all(sp.simplify(a - b) == 0 for a, b in zip(sq[0], want1))
    ok2 = len(sq) == 2 and all(sp.simplify(a - b) == 0 for a, b in zip(sq[1], want2))
    step("riemann", ok1 and ok2, "on the separatrix level h = 1 both NVEs are Riemann P-equations (singular points "
         "-1, 1, oo) with exponent differences Gamma1: (1/2, 1/sqrt(r), (3r - 4)/(2r)), Gamma2: (1/2, sqrt(r), "
         "sqrt(8r - 7)/2)")
    # 2. Gamma1 in s = 1/sqrt(r): (1/2, s, 3/2 - 2 s^2)
    half = sp.Rational(1, 2)
    lam, mu, nu = half, s, sp.Rational(3, 2) - 2 * s**2
    X1, Y1 = 2 * s**2 - s, 2 * s**2 + s
    sums = [lam + mu + nu, -lam + mu + nu, lam - mu + nu, lam + mu - nu]
    ok = [sp.expand(a - b) for a, b in zip(sums, [2 - X1, 1 - X1, 2 - Y1, Y1 - 1])] == [0] * 4
    step("gamma1_A", ok, "Gamma1, Kimura (A): the four sums are 2 - X, 1 - X, 2 - Y, Y - 1 with X = 2s^2 - s, Y = "
         "2s^2 + s; one is odd iff X or Y is an integer")
    step("gamma1_B1", True, "Gamma1, Kimura (B) case 1 (two of the differences in 1/2 + Z; lambda = 1/2 is one): "
         "s in 1/2 + Z, or 3/2 - 2s^2 in 1/2 + Z, i.e. 2s^2 in Z")
    step("gamma1_B2-15", _table_impossible_gamma1(), "Gamma1, Kimura (B) cases 2-15 impossible: enumerated s = p/d, "
         "d in {3, 4, 5}, p mod d^2")
    # 3. Gamma2 in a = sqrt(r): (1/2, a, b), 4 b^2 = 8 a^2 - 7
    a = sp.Symbol("a", positive=True)
    ident = sp.expand((q / 2 - a)**2 - (8 * a**2 - 7) / 4 + (a**2 + q * a - (q**2 + 7) / 4))
    step("gamma2_A", ident == 0, "Gamma2, Kimura (A): as for Gamma1 the condition is a + b or b - a in 1/2 + Z (b "
         "real: 8a^2 >= 7), i.e. b^2 = (q/2 - a)^2 for an odd integer q, i.e. a^2 + q a - (q^2 + 7)/4 = 0: a = "
         "(-q + sqrt(2q^2 + 7))/2 (the other root is negative)")
    rj = sp.expand(((2 * j + 1)**2 + 7) / 8 - (1 + j * (j + 1) / 2))
    step("gamma2_B1", rj == 0, "Gamma2, Kimura (B) case 1: a in 1/2 + Z (r = (2k+1)^2/4), or b in 1/2 + Z: "
         "8r - 7 = (2j+1)^2, r = 1 + j(j+1)/2")
    step("gamma2_B2-15", _table_impossible_gamma2(), "Gamma2, Kimura (B) cases 2-15 impossible: a = p/d, "
         "b = m/(2d) with m^2 = 8p^2 - 7d^2 has no solution modulo 8 in any row (enumerated)")
    # 4. intersections
    kk = sp.Symbol("kk", integer=True)
    ineq = sp.expand((2 * kk + 1)**2 - (8 + 2 * (2 * kk + 1)))
    small = [kv for kv in range(0, 2) for sg in (1, -1)
             if sp.Rational(8 + sg * 2 * (2 * kv + 1), (2 * kv + 1)**2).is_integer]
    step("meet_i", ineq == 4 * kk**2 - 9 and small == [0, 0], "a = (2k+1)/2, s = 2/(2k+1): s in 1/2 + Z would need "
         "(2k+1)(2i+1) = 4 (odd = even); 2s^2 = 8/(2k+1)^2 in Z only for k = 0; 2s^2 +- s = (8 +- 2(2k+1))/(2k+1)^2 "
         "is not an integer for k >= 2 (0 < |numerator| < (2k+1)^2 since (2k+1)^2 - 8 - 2(2k+1) = 4k^2 - 9 > 0) nor "
         "k = 1 (checked): only r = 1/4")
    jj = [jv for jv in range(0, 3) if sp.Rational(4, jv**2 + jv + 2).is_integer]
    step("meet_ii", jj == [0, 1], "r = 1 + j(j+1)/2, s^2 = 2/(j^2 + j + 2): 2s^2 in Z iff j in {0, 1} (r = 1, 2); "
         "s in 1/2 + Z iff (2i+1)^2 (j^2+j+2) = 8, i.e. j = 2 (r = 4); 2s^2 +- s in Z needs s rational, r = R^2, "
         "(2 +- R)/R^2 in Z, R | 2: r in {1, 4}")
    sols = sp.solve(q**2 - 8 * q + 7, q) + sp.solve(q**2 + 8 * q + 7, q)
    D = 2 * q**2 + 7
    s_of_q = 2 * (q + sp.sqrt(D)) / (q**2 + 7)
    ident_s = sp.simplify(s_of_q - 2 / (-q + sp.sqrt(D)))
    seven = []
    for qv in (7, -7):
        sv = s_of_q.subs(q, qv)
        seven += [sp.nsimplify(sp.radsimp(sp.expand(2 * sv**2 + sg * sv))) for sg in (1, -1)]
    rational_seven = [v for v in seven if v.is_rational]
    step("meet_iii", ident_s == 0 and sorted(set(abs(v) for v in sols)) == [1, 7] and
         all(not v.is_integer for v in rational_seven) and len(rational_seven) == 2,
         "a = (-q + sqrt(D))/2, D = 2q^2 + 7, q odd: if D is a square, a is an integer and s = 1/a meets Gamma1's "
         "conditions only for a in {1, 2} (r = 1, 4); otherwise s = 2(q + sqrt D)/(q^2 + 7) is irrational, 2s^2 is "
         "irrational, and 2s^2 +- s is rational only if q^2 +- 8q + 7 = 0 (q = +-1: D = 9 a square; q = +-7: "
         f"2s^2 +- s = {', '.join(str(v) for v in rational_seven)}, not integers)")
    # 5. r = 1/4: the separatrix does not decide; a generic level does (Kovacic on the Heun-type NVE)
    p2, q2 = nves[1][1], nves[1][2]
    quarter = galois_of(sp.cancel(p2.subs({h: 0, r: sp.Rational(1, 4)})), sp.cancel(q2.subs({h: 0, r: sp.Rational(1, 4)})))
    step("r=1/4", quarter.case == 4, "r = 1/4 survives both separatrix NVEs (Gamma1 dihedral, Gamma2 dihedral); on "
         "the level h = 0 the NVE along Gamma2 (four singular points -1, 0, 1, oo) has no Liouvillian solution by "
         f"Kovacic's algorithm (all three cases fail: {quarter.group}), so G0 is not abelian")
    # 6. the survivors
    Hr2 = model.H.subs({B1: 1, B2: 2, C: 2})
    K = ((m3 / 2)**2 - (m2 / 2)**2 - n3)**2 + (m2 * m3 / 2 - n2)**2
    import copy
    mk = copy.copy(model)
    mk.H = Hr2
    kov = bracket(mk, K, Hr2) == 0
    mg = copy.copy(model)
    mg.H = model.H.subs({B1: 1, B2: 4, C: 4})
    G = m1 * (m2**2 + m3**2) - 4 * m3 * n1
    gc = sp.expand(bracket(mg, G, mg.H) - (m1 * n1 + m2 * n2 + m3 * n3) * m2) == 0
    mi = copy.copy(model)
    mi.H = model.H.subs({B1: 1, B2: 1, C: 1})
    iso = bracket(mi, m3, mi.H) == 0
    step("survivors", kov and gc and iso, "r = 1: B1 = B2 = C, m3 is an integral (Lagrange's case B1 = B2); r = 2: Kovalevskaya's integral K = ((m3/2)^2 - (m2/2)^2 - n3)^2 + (m2 m3/2 - n2)^2, {K, H} = 0; "
         "r = 4: G = m1 (m2^2 + m3^2) - 4 m3 n1 with {G, H} = (m.n) m2 (Goryachev-Chaplygin: an integral on m.n = 0, "
         "the leaf of both pendulums)")
    # 7. the scope: the pendulums' leaf.  m.n vanishes identically on both pendulum planes, and the search over
    # every invariant coordinate subspace (r symbolic) finds no one-degree-of-freedom flow on which m.n is live.
    mn = m1 * n1 + m2 * n2 + m3 * n3
    on_leaf = all(sp.expand(mn.subs({X[i]: 0 for i in pl[0]})) == 0 for pl, *_ in nves)
    planes = invariant_planes(model, vals)
    generic = [pl for pl in planes if sp.expand(mn.subs({X[i]: 0 for i in pl[0]})) != 0]
    step("leaf", on_leaf and not generic and len(planes) == 2,
         "m.n = 0 identically on both pendulum planes; among all invariant coordinate subspaces (r symbolic) none "
         "carries a one-degree-of-freedom flow on a leaf m.n = l != 0: no particular solution of this kind on a "
         "generic leaf, so the Heun-type NVE there is not reached")
    proved = all(st["ok"] for st in steps)
    for g in data:
        g.pop("_rd")
        g.pop("_pq")
    return {
        "theorem": ("For every r > 0 with r not in {1, 2, 4}, the anisotropic rod with B2 = C = r B1 (and its mirror "
                    "B1 = C = r B2), restricted to a symplectic leaf L = {m.n = 0, |n| = gamma > 0}, has no "
                    "meromorphic first integral functionally independent of H|L in a connected neighbourhood of the "
                    "pendulum solutions in L (Morales-Ramis: the identity component of the Galois group of the "
                    "normal variational equation along one of the two pendulums is not abelian). For the full "
                    "Poisson system on e(3)* this means: if F is a meromorphic first integral near a pendulum and "
                    "F|L is defined, then F|L is functionally dependent on H|L there; so the rod is not Liouville "
                    "integrable with meromorphic integrals (H, F and the Casimirs) that stay independent on L. An "
                    "integral independent on the generic leaves m.n = l != 0 whose restriction to L depends on H is "
                    "not excluded: the pendulums lie on m.n = 0 only. At r = 1 (isotropic), 2 (Kovalevskaya) and 4 "
                    "(Goryachev-Chaplygin, integrable on m.n = 0) the rod is integrable on L."),
        "status": "proved" if proved else "not proved (a step failed)",
        "exceptional_set": [str(v) for v in EXCEPTIONAL],
        "explanations": {"1": "isotropic (B1 = B2 = C): Lagrange's case", "2": "Kovalevskaya (B2 = C = 2 B1)",
                         "4": "Goryachev-Chaplygin (B2 = C = 4 B1): integrable on m.n = 0, the pendulums' leaf"},
        "removed_by_a_generic_level": {"1/4": quarter.as_dict()},
        "hypotheses": {"Hamiltonian on a symplectic leaf": "checked: x' = J grad H with J Lie-Poisson (Jacobi identity, "
                                                           "derivation report); the leaf m.n = 0, |n| = 1 (scaling)",
                       "non-equilibrium particular solution": "the pendulums (restricted field not zero)",
                       "change of variable z = n3": "finite branched covering: G0 unchanged (Morales-Ruiz 1999)",
                       "reduction to normal form": "exp(int p) algebraic (p has rational residues): G0 unchanged"},
        "not_proved": ("non-integrability on the generic leaves m.n != 0 (the pendulums lie on m.n = 0 only, and no "
                       "invariant coordinate subspace gives a particular solution on m.n = l != 0); an integral "
                       "independent on those leaves but dependent on H on m.n = 0; integrals that are not "
                       "meromorphic near the pendulums"),
        "pendulums": data, "steps": steps}
