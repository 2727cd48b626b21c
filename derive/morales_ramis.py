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


def invariant_planes(model, vals: dict) -> list:
    """[(normal indices N, tangent indices T, pendulum Casimir, NVE Casimirs)] for every invariant coordinate
    3-space of the field on which exactly one Casimir is non-constant (and the field is not identically zero)."""
    from .models.pipeline import equations

    X = model.state
    f = [sp.expand(e.subs(vals)) for e in equations(model)]
    cas = _casimirs(model, vals)
    n = len(X)
    out = []
    for T in itertools.combinations(range(n), 3):
        N = [i for i in range(n) if i not in T]
        sub = {X[i]: 0 for i in N}
        if any(sp.expand(f[i].subs(sub)) != 0 for i in N):
            continue
        if all(sp.expand(f[i].subs(sub)) == 0 for i in T):
            continue
        restricted = [sp.expand(c.subs(sub)) for c in cas]
        live = [c for c in restricted if c.free_symbols]
        if len(live) != 1:
            continue
        lin = []
        for c in cas:
            g = [sp.expand(sp.diff(c, X[i]).subs(sub)) for i in range(n)]
            if all(g[i] == 0 for i in T) and any(g[i] != 0 for i in N):
                lin.append([g[i] for i in N])
        out.append((N, list(T), live[0], lin))
    return out


def _rationalise(expr, rels: dict, zt):
    """expr (rational in the tangent coordinates) as a rational function of z, using {coordinate: its square as a
    polynomial in z}; zt is the coordinate that becomes z.  None if an odd power survives."""
    num, den = sp.fraction(sp.together(sp.expand(expr)))
    others = list(rels)

    def reduce(p):
        P = sp.Poly(sp.expand(p), *others)
        tot = sp.Integer(0)
        odd = set()
        for mono, c in P.terms():
            term = c
            key = []
            for v, a in zip(others, mono):
                term *= rels[v] ** (a // 2)
                if a % 2:
                    key.append(v)
            odd.add(tuple(key))
            tot += term * sp.Mul(*key)
        return sp.expand(tot), odd

    # make the denominator even in every other coordinate by multiplying through
    for v in others:
        dn, odd = reduce(den)
        if any(v in k for k in odd):
            num, den = sp.expand(num * v), sp.expand(den * v)
    nn, oddn = reduce(num)
    dd, oddd = reduce(den)
    if oddn != {()} and nn != 0 or oddd != {()}:
        return None
    return sp.cancel(sp.together(nn.subs(zt, z) / dd.subs(zt, z)))


def nve(model, vals: dict, plane, energy=h, level=1):
    """The NVE along the pendulum of `plane` as (p, q, description): y'' + p y' + q y = 0 in z, rational, at
    energy `energy` and pendulum Casimir value `level`; None if no choice of (eliminated variable, unknown,
    independent variable) gives rational coefficients."""
    from .models.pipeline import equations

    X = model.state
    N, T, cas, lins = plane
    if not lins:
        return None
    f = [sp.expand(e.subs(vals)) for e in equations(model)]
    sub = {X[i]: 0 for i in N}
    ft = {X[i]: sp.expand(f[i].subs(sub)) for i in T}  # the restricted flow

    def dt(e):
        return sp.expand(sum(sp.diff(e, v) * ft[v] for v in ft))
    J = sp.Matrix(f).jacobian(X)
    A = J.extract(N, N).subs(sub)
    g = lins[0]
    Hr = sp.expand(model.H.subs(vals).subs(sub))
    for e_idx in range(3):  # the normal variable eliminated by the linearised Casimir (level 0)
        if g[e_idx] == 0:
            continue
        keep = [k for k in range(3) if k != e_idx]
        # xi_e = -(sum_{k != e} g_k xi_k) / g_e
        M = sp.zeros(2, 2)
        for a, ka in enumerate(keep):
            for b, kb in enumerate(keep):
                M[a, b] = sp.together(A[ka, kb] - A[ka, e_idx] * g[kb] / g[e_idx])
        for u in range(2):  # the unknown y = xi_keep[u]
            o = 1 - u
            a11, a12, a21, a22 = M[o, o], M[o, u], M[u, o], M[u, u]
            if sp.simplify(a21) == 0:
                continue
            # y' = a21 w + a22 y, w' = a11 w + a12 y  =>  y'' - P y' + Q y = 0
            da21 = sp.together(dt(sp.numer(sp.together(a21))) / sp.denom(sp.together(a21))
                               - sp.numer(sp.together(a21)) * dt(sp.denom(sp.together(a21)))
                               / sp.denom(sp.together(a21))**2)
            Pt = a11 + a22 + da21 / a21
            Qt = a11 * a22 - a12 * a21 - _dtr(a22, dt) + a22 * da21 / a21
            for zi in T:
                zt = X[zi]
                zdot = ft[zt]
                if zdot == 0:
                    continue
                zdd = dt(zdot)
                # d/dt = zdot d/dz: y_zz + (zdd - Pt zdot)/zdot^2 y_z + Qt/zdot^2 y = 0
                others = [X[i] for i in T if i != zi]
                rels = _square_relations(Hr, cas, zt, others, energy, level)
                if rels is None:
                    continue
                p = _rationalise((zdd - Pt * zdot) / zdot**2, rels, zt)
                q = _rationalise(Qt / zdot**2, rels, zt)
                if p is None or q is None:
                    continue
                return p, q, {"eliminated": str(X[N[e_idx]]), "unknown": str(X[N[keep[u]]]), "z": str(zt),
                              "normal": [str(X[i]) for i in N], "tangent": [str(X[i]) for i in T],
                              "linearised_casimir": [str(v) for v in g]}
    return None


def _dtr(e, dt):
    num, den = sp.fraction(sp.together(e))
    return sp.together((dt(num) * den - num * dt(den)) / den**2)


def _square_relations(Hr, cas, zt, others, energy, level):
    """{v: v^2 as a polynomial in zt} for the other tangent coordinates, from H = energy and the pendulum Casimir =
    level: each relation used must contain exactly one other coordinate v, and only as v^2."""
    rels = {}
    eqs = [sp.expand(Hr - energy), sp.expand(cas - level)]
    for v in others:
        for e in eqs:
            if (e.free_symbols & set(others)) != {v}:
                continue
            P = sp.Poly(e, v)
            if P.degree() != 2 or P.coeff_monomial(v) != 0:
                continue
            rels[v] = sp.expand(-P.coeff_monomial(1) / P.coeff_monomial(v**2))
            break
        else:
            return None
    return rels


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
