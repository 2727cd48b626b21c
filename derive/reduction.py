"""Sec. 4 of the paper, derived: Euler-angle reduction of the 9-D non-canonical system to a canonical one,
the Poisson property of the map, the reduced Hamiltonian, I2 in canonical variables, and the
non-dimensional Hbar and I2bar (eq:nondim_1) with the cases in which I2bar is conserved."""
from __future__ import annotations

import itertools
from functools import lru_cache

import sympy as sp

from . import paper
from .model import (B, B1, B2, J, K, X, cH, cJ, cK, e3, euler_rotation, lam, mvec, nvec, p_phi,
                    p_psi, p_theta, phi, psi, strain_energy, structure_matrix, theta, u1, u2, u3)
from .paper import C1, C2, delta, gamma, lambar, m, mu, pps, pth
from .poisson import hamiltonian_compliance
from .results import CONDITIONAL, DISAGREES, HOLDS, Result, fmt

Q = [theta, psi, phi]
P = [p_theta, p_psi, p_phi]
C2p = sp.symbols("C2", positive=True)  # C2 > 0 (tension along the field) so that m = m3/sqrt(B C2) is real
m3p = sp.symbols("m_3", positive=True)  # the conserved twisting moment m3 = p_phi > 0 used as scale
rho_sym = sp.symbols("rho", positive=True)  # rho = sqrt(2 C1 - C2^2 - 2 lambda p_psi), non-alignment rho != 0

# sin/cos symbols for polynomial normal forms modulo sin^2 + cos^2 = 1
_sc = {a: sp.symbols(f"s_{a.name} c_{a.name}", real=True) for a in (theta, psi, phi)}


def trig_normal_form(expr, radicand=None):
    """Normal form of a trigonometric-algebraic expression, zero iff the expression vanishes identically.

    sin/cos -> symbols; every power radicand**(k/2) -> rho**k; then the numerator is reduced modulo
    s^2 + c^2 - 1 (theta, psi, phi) and rho^2 - radicand.  Their leading monomials (lex, rho and the sines
    first) are coprime pure powers, so the relations are a Groebner basis and the remainder is canonical."""
    rep = {}
    for a, (s, c) in _sc.items():
        rep[sp.sin(a)] = s
        rep[sp.cos(a)] = c
        rep.update({sp.tan(a): s / c, sp.cot(a): c / s, sp.sec(a): 1 / c, sp.csc(a): 1 / s})
    e = sp.expand_trig(expr)
    rels = [s**2 + c**2 - 1 for s, c in _sc.values()]
    if radicand is not None:
        rad = sp.expand(radicand)
        e = e.replace(lambda x: x.is_Pow and x.exp.is_Rational and x.exp.q == 2 and sp.expand(x.base - rad) == 0,
                      lambda x: rho_sym ** (2 * x.exp))
        rels.append(rho_sym**2 - rad)
    e = e.subs(rep)
    num = sp.numer(sp.together(e))
    gens = [rho_sym] + [v for sc in _sc.values() for v in sc]
    free = sorted((num.free_symbols | set().union(*[r.free_symbols for r in rels])) - set(gens), key=str)
    _, rem = sp.reduced(sp.expand(num), rels, *(gens + free), order="lex")
    return sp.expand(rem)


@lru_cache(maxsize=None)
def moments_from_lagrangian():
    """m(q, p): strains u(q, q') from the Euler angles (eq:curvatures); since Wbar(q, q') = W(u(q, q')) and u is
    linear in q' = (theta', psi', phi'), p = dWbar/dq' = G^T m with G = du/dq', hence m = L p, L = G^{-T}."""
    R = euler_rotation()
    qd = sp.symbols("thetadot psidot phidot", real=True)
    d = [R.row(i).T for i in range(3)]  # space components of the directors

    def dprime(v):
        return sp.Matrix([sum(sp.diff(v[k], q) * qdot for q, qdot in zip(Q, qd)) for k in range(3)])

    dp = [dprime(v) for v in d]
    eps = sp.LeviCivita
    u = [sp.trigsimp(sp.expand(sum(eps(i, j, k) * dp[j].dot(d[k]) for j in range(3) for k in range(3)) / 2))
         for i in range(3)]
    G = sp.Matrix(3, 3, lambda i, j: sp.diff(u[i], qd[j]))
    L = sp.simplify(G.T.inv()).replace(sp.tan, lambda x: sp.sin(x) / sp.cos(x))
    m_qp = L * sp.Matrix(P)
    # cross-check: m = dW/du evaluated at u(q, q') equals L p(q, q') with p = dWbar/dq'
    Wbar = strain_energy().subs({u1: u[0], u2: u[1], u3: u[2]})
    pdef = sp.Matrix([sp.diff(Wbar, x) for x in qd])
    mom = sp.Matrix([sp.diff(strain_energy(), x).subs({u1: u[0], u2: u[1], u3: u[2]}) for x in (u1, u2, u3)])
    consistent = sp.simplify(L * pdef - mom) == sp.zeros(3, 1)
    return u, m_qp, consistent


def force_from_casimirs():
    """n(q, p) = R(q) w with w3 = e3.n = C2 (eq:magnetic_casimirs2), |w|^2 = |n|^2 = 2 C1 - 2 lambda m.e3
    (eq:magnetic_casimirs1) and m.e3 = p_psi (shown in derive_all); the transverse part of w is put along the
    fixed e_1 (the gauge of the chart: psi is measured from the transverse force)."""
    rho = sp.sqrt(2 * C1 - C2**2 - 2 * lam * p_psi)
    return euler_rotation() * sp.Matrix([rho, 0, C2])


def canonical_map():
    """The 9 functions X(q, p) = (m, n, e3)."""
    _, m_qp, _ = moments_from_lagrangian()
    n_qp = force_from_casimirs()
    e_qp = euler_rotation() * sp.Matrix([0, 0, 1])
    return sp.Matrix.vstack(m_qp, n_qp, e_qp)


def canonical_bracket(f, g, qs=Q, ps=P):
    return sum(sp.diff(f, q) * sp.diff(g, p) - sp.diff(f, p) * sp.diff(g, q) for q, p in zip(qs, ps))


def poisson_map_residuals():
    """{X_i, X_j}_can - J_ij(X(q, p)) for all 36 pairs, in normal form (sqrt -> rho, rho^2 -> its value)."""
    Xqp = canonical_map()
    Jm = structure_matrix().subs(dict(zip(X, Xqp)))
    out = {}
    for i, j in itertools.combinations(range(9), 2):
        dif = canonical_bracket(Xqp[i], Xqp[j]) - Jm[i, j]
        out[(i, j)] = trig_normal_form(dif, RHO2)
    return out


def nondim_substitution():
    """eq:nondim_1 solved for the dimensional constants, with p = m3 pbar and p_phi = m3."""
    return {B: m3p**2 / (m**2 * C2p), lam: lambar * C2p**2 / m3p, C1: C2p**2 * (mu + 1) / 2,
            cJ: delta / C2p, cH: delta / C2p, cK: (gamma + delta) / C2p, C2: C2p,
            p_theta: m3p * pth, p_psi: m3p * pps, p_phi: m3p}


RHO2 = 2 * C1 - C2**2 - 2 * lam * p_psi  # the radicand of eq:canonical_force
RHO2_BAR = mu - 2 * lambar * pps  # ... and its non-dimensional form, RHO2 = C2^2 RHO2_BAR


def to_nondim(expr):
    """Apply eq:nondim_1.  The radicand is replaced first, RHO2**(k/2) -> C2^k RHO2_BAR**(k/2) (C2 > 0), so
    SymPy never has to pull C2 out of a square root; then phi (cyclic, it must drop out) is eliminated with
    sin^2 + cos^2 = 1."""
    rad = sp.expand(RHO2)
    e = expr.replace(lambda x: x.is_Pow and x.exp.is_Rational and x.exp.q == 2 and sp.expand(x.base - rad) == 0,
                     lambda x: C2p ** (2 * x.exp) * RHO2_BAR**x.exp)
    e = e.subs(nondim_substitution())
    e = e.replace(sp.tan, lambda x: sp.sin(x) / sp.cos(x)).replace(sp.cot, lambda x: sp.cos(x) / sp.sin(x))
    return trig_reduce(e)


def trig_reduce(expr):
    """Expand, then rewrite positive powers sin(a)^n, n >= 2, as sin(a)^(n mod 2) (1 - cos(a)^2)^(n // 2)
    for a in (theta, psi, phi) and expand again: a canonical polynomial form in which constants separate."""
    def rw(x):
        n = int(x.exp)
        return x.base ** (n % 2) * (1 - sp.cos(x.base.args[0]) ** 2) ** (n // 2)

    e = sp.expand(expr)
    e = e.replace(lambda x: x.is_Pow and isinstance(x.base, sp.sin) and x.exp.is_Integer and x.exp >= 2, rw)
    return sp.expand(e)


@lru_cache(maxsize=None)
def reduced_hamiltonians():
    """H(q, p) for general stiffnesses (eq:ham_canon), the isotropic one (compare eq:full_ham), and the
    non-dimensional one split as Hbar_full = Hbar + const (compare eq:full_ham_nondim)."""
    Xqp = canonical_map()
    Hqp = hamiltonian_compliance().subs(dict(zip(X, Xqp)))
    Hiso = Hqp.subs({B1: B, B2: B, cJ: cH})
    Hbar_full = to_nondim(Hiso * B / p_phi**2)
    state = {theta, psi, pth, pps}
    const = sp.Add(*[t for t in Hbar_full.args if not (t.free_symbols & state)])
    Hbar = sp.expand(Hbar_full - const)
    return Hqp, Hiso, Hbar, const


def hbar_compact():
    """Hbar written in the grouped form of eq:full_ham_nondim (after checking it equals the derived one)."""
    return paper.eq_full_ham_nondim()


@lru_cache(maxsize=None)
def i2_canonical():
    """I2 = n.m + B lambda e3.d3 (eq:int2) pulled back to (q, p), and I2bar = I2/(C2 m3)."""
    Xqp = canonical_map()
    I2 = (nvec.dot(mvec) + B * lam * e3).subs(dict(zip(X, Xqp)))
    I2bar = to_nondim(I2 / (C2 * p_phi))
    return I2, I2bar


def s1_descent() -> Result:
    """The S^1-descent of integrals in involution with m3 (docs/nonintegrability.md, statement 7).

    Shown here, symbolically: (a) m3 pulled back by X is p_phi; (b) the phi-flow of the chart is the flow of m3,
    dX/dphi = J(X) grad m3 (all 9 components, trig normal form with rho^2 reduced); (c) the isotropic H pulled back
    does not depend on phi.  With poisson_map ({G o X, K o X}_can = {G, K} o X) these give, for every G on the 9-D
    space: {G o X, p_phi}_can = dG o X / dphi = {G, m3} o X.  So an integral G with {G, m3} = 0 has G o X
    independent of phi: it descends to the chart (theta, psi, p_theta, p_psi) at fixed p_phi = m3 and Casimirs, and
    {G o X, H o X}_4 = {G, H} o X = 0 there (both phi-independent, so the (phi, p_phi) term of the 6-D bracket
    vanishes): a first integral of the reduced system on every leaf."""
    Xqp = canonical_map()
    _, m_qp, _ = moments_from_lagrangian()
    a = sp.simplify(m_qp[2] - p_phi)
    Jm = structure_matrix().subs(dict(zip(X, Xqp)))
    k = list(X).index(mvec[2])
    b = [trig_normal_form(sp.diff(Xqp[i], phi) - Jm[i, k], RHO2) for i in range(9)]
    Hqp = hamiltonian_compliance().subs(dict(zip(X, Xqp))).subs({B1: B, B2: B, cJ: cH})
    c = trig_normal_form(sp.diff(Hqp, phi), RHO2)
    ok = a == 0 and all(v == 0 for v in b) and c == 0
    return Result("s1_descent", "sec:reduction",
                  "m3 o X = p_phi and dX/dphi = J(X) grad m3 (the phi-flow is the flow of m3), and the isotropic H o X "
                  "is phi-independent: with poisson_map, an integral in involution with m3 descends to an integral "
                  "of the reduced chart system on every leaf",
                  HOLDS if ok else DISAGREES,
                  "symbolic: differences simplified / reduced modulo sin^2+cos^2=1 and rho^2 = 2C1 - C2^2 - 2 lambda "
                  "p_psi, all zero",
                  {"m3 o X - p_phi": fmt(a), "dX/dphi - J(X) grad m3": [fmt(v) for v in b],
                   "d(H_iso o X)/dphi": fmt(c),
                   "consequence": "{G o X, p_phi}_can = d(G o X)/dphi = {G, m3} o X for every G (with poisson_map)",
                   "domain": "the chart: sin(theta) != 0, rho != 0 (the assumptions of poisson_map)"})


def bracket4(f, g):
    return canonical_bracket(f, g, [theta, psi], [pth, pps])


def derive_all():
    res = []
    R = euler_rotation()
    dR = sp.simplify(R - paper.R_printed())
    res.append(Result("euler_rotation", "sec:reduction (matrix R)",
                      "R = R_z(phi) R_y(theta) R_z(psi) equals the printed R",
                      HOLDS if dR == sp.zeros(3, 3) else DISAGREES, "symbolic: simplified difference is 0"))
    e_qp = R * sp.Matrix([0, 0, 1])
    de = sp.simplify(e_qp - paper.eq_canonical_magnetic())
    res.append(Result("e3_of_q", "eq:canonical_magnetic", "e3(q) = R(q) k",
                      HOLDS if de == sp.zeros(3, 1) else DISAGREES, "symbolic"))

    u, m_qp, consistent = moments_from_lagrangian()
    dm = sp.simplify(m_qp - paper.L_printed() * sp.Matrix(P))
    res.append(Result("moments", "eq:canonical_moment",
                      "u from eq:curvatures, m = dW/du, p = dWbar/dq' solved for q' gives m = L p",
                      HOLDS if dm == sp.zeros(3, 1) and consistent else DISAGREES,
                      "symbolic: simplified difference is 0",
                      {"u(q, q')": [fmt(x) for x in u], "L p(q, q') == dW/du": consistent}))
    me3 = sp.simplify(m_qp.dot(e_qp))
    res.append(Result("m_dot_e3", "sec:reduction", "m.e3 = p_psi (used to express |n|^2 by C1)",
                      HOLDS if sp.simplify(me3 - p_psi) == 0 else DISAGREES, "symbolic", {"m.e3": fmt(me3)}))

    n_qp = force_from_casimirs()
    dn = sp.simplify(n_qp - paper.eq_canonical_force())
    casi = [sp.simplify(sp.expand(c.subs(dict(zip(X, canonical_map()))))) for c in paper.eq_magnetic_casimirs()]
    res.append(Result("force", "eq:canonical_force",
                      "n = R(q) (rho, 0, C2) from the Casimirs; Casimirs evaluate to C1, C2, 1 on the chart",
                      HOLDS if dn == sp.zeros(3, 1) and casi == [C1, C2, 1] else DISAGREES,
                      "symbolic", {"casimirs on chart": [fmt(c) for c in casi]}))

    resid = poisson_map_residuals()
    bad = {f"{X[i]},{X[j]}": fmt(r) for (i, j), r in resid.items() if r != 0}
    res.append(Result("poisson_map", "eq:alignment_condition",
                      "The map (q, p) -> (m, n, e3) is Poisson: canonical brackets of the 9 pulled-back functions "
                      "reproduce J(m, n, e3; lambda) for all 36 pairs",
                      CONDITIONAL if not bad else DISAGREES,
                      "symbolic: numerators reduced modulo sin^2+cos^2=1 and rho^2 = 2C1 - C2^2 - 2 lambda p_psi",
                      {"assumption": "rho = sqrt(2 C1 - C2^2 - 2 lambda p_psi) != 0 (eq:alignment_condition) and "
                                     "sin(theta) != 0 (chart)", "nonzero_pairs": bad}))

    res.append(s1_descent())

    Hqp, Hiso, Hbar, const = reduced_hamiltonians()
    d_full = sp.expand(Hiso - paper.eq_full_ham().subs({J: 1 / cH, K: 1 / cK}))
    vars6 = [theta, psi, p_theta, p_psi]
    dvars = [trig_normal_form(sp.diff(d_full, v), RHO2) for v in vars6]
    dconst = sp.factor(trig_reduce(d_full).subs({cK: 1 / K, cH: 1 / J}))
    res.append(Result("full_ham", "eq:ham_canon, eq:full_ham",
                      "Isotropic reduced Hamiltonian equals the printed one up to an additive constant",
                      HOLDS if all(x == 0 for x in dvars) else DISAGREES,
                      "symbolic: d/d(theta, psi, p_theta, p_psi) of the difference has zero normal form",
                      {"constant difference (derived - printed)": fmt(dconst)}))

    d_nd = trig_normal_form(Hbar - paper.eq_full_ham_nondim(), RHO2_BAR)
    res.append(Result("full_ham_nondim", "eq:nondim_1, eq:full_ham_nondim",
                      "Hbar = H B/m3^2 with eq:nondim_1 equals the printed Hbar (constants dropped)",
                      HOLDS if d_nd == 0 else DISAGREES, "symbolic: normal form of the difference is 0",
                      {"dropped constant": fmt(const), "assumptions": "C2 > 0, m3 > 0"}))

    I2, I2bar = i2_canonical()
    dI2 = trig_normal_form(sp.expand(I2) - sp.expand(paper.eq_constraint()), RHO2)
    res.append(Result("constraint", "eq:constraint", "I2 of eq:int2 pulled back to canonical variables",
                      HOLDS if dI2 == 0 else DISAGREES, "symbolic: normal form of the difference is 0"))
    dI2b = trig_normal_form(I2bar - paper.eq_constraint_nonsim(), RHO2_BAR)
    res.append(Result("constraint_nonsim", "constraint_nonsim", "I2bar = I2/(C2 m3)",
                      HOLDS if dI2b == 0 else DISAGREES, "symbolic: normal form of the difference is 0"))

    # conservation of I2bar by Hbar
    def nf(e):
        return trig_normal_form(e, mu - 2 * lambar * pps)

    br = bracket4(I2bar, Hbar)
    cases = {
        "gamma = delta = 0": {gamma: 0, delta: 0},
        "lambdabar = 0": {lambar: 0},
        "gamma = 0, delta != 0": {gamma: 0},
        "delta = 0, gamma != 0": {delta: 0},
        "general": {},
    }
    table = {}
    for name, sub in cases.items():
        if lambar in sub:  # the square root changes its argument; recompute the bracket in the case
            e = bracket4(I2bar.subs(sub), Hbar.subs(sub))
            e = trig_normal_form(e, mu)
        else:
            e = nf(br.subs(sub))
        table[name] = "0" if e == 0 else fmt(sp.factor(e))
    # a numeric witness that the general bracket is non-zero
    witness = {theta: sp.Rational(7, 10), psi: sp.Rational(3, 10), pth: sp.Rational(1, 2), pps: sp.Rational(1, 10),
               m: sp.Rational(17, 10), mu: sp.Rational(2, 5), gamma: 3, delta: 3, lambar: sp.Rational(3, 20)}
    wval = sp.N(br.subs(witness), 30)
    ok = table["gamma = delta = 0"] == "0" and table["lambdabar = 0"] == "0" and table["general"] != "0"
    res.append(Result("I2bar_conservation", "constraint_nonsim, rem (sec:reduction)",
                      "{I2bar, Hbar} in the reduced canonical system",
                      CONDITIONAL if ok else DISAGREES,
                      "symbolic: normal form of the canonical bracket in (theta, psi, pbar_theta, pbar_psi)",
                      {"cases": table,
                       "witness point (fig:poincare1a parameters)": {str(k): str(v) for k, v in witness.items()},
                       "bracket at witness": str(wval)}))
    return res
