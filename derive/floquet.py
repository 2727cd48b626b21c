"""The saddle-type sets for mu != 2 lambdabar and their linear stability (paper sec. 3 and 8).

* Rotation generator.  xi = d/da G_a at a = 0, with G_a = diag(rot3(a), rot3(a), rot3(a)) the rotations about
  the body 3-axis (derive/symmetry.py).  A relative equilibrium x(t) = G_{omega t} x0 solves f(x0) = omega xi x0;
  magrod/floquet.py computes the helical one numerically and its monodromy M = exp(T (Df(x0) - omega xi)).
* Straight rod at mu = 2 lambdabar (`floquet_straight_rod`).  The characteristic polynomial of the 9x9 Jacobian
  at m = e3 = (0, 0, 1), n = (0, 0, 1/m^2) is s^3 P(s^2) with P a cubic in sigma = s^2 (symbolic).  One root
  sigma = -w^2 < 0 is the centre pair; the other two are the quartet's s^2.  The quartet is a complex
  saddle-focus iff disc_sigma(P) < 0; the Hamiltonian-Hopf boundary (the quartet collides on the imaginary axis)
  is disc_sigma(P) = 0 with a negative double root.  At lambdabar = 0 the discriminant factors and vanishes
  at m^2 = 4 (1 + gamma), i.e. at m_c of eq:buckling_load_2 (checked symbolically).
* Reduced equilibrium (`reduced_linearisation`).  The relative equilibrium is an equilibrium (theta, 0, 0,
  pbar_psi) of the reduced canonical system, on Fix(R).  Since Hbar is even in pbar_theta and in psi, its
  Jacobian there is Hamiltonian with characteristic polynomial s^4 + b s^2 + c (b = trace term, c = det, both
  symbolic in the Hessian of Hbar); the quartet is complex iff b^2 - 4 c < 0 and c > 0 and meets the imaginary
  axis at b^2 = 4 c, b > 0 (Hamiltonian-Hopf).  magrod evaluates b, c at the numerically found equilibrium
  and compares exp(T s) with the Floquet multipliers.
* The Poisson structure J(x; lambda) (eq:noncanonical_structure) as a plain-float function, for the check
  M J M^T = J (the monodromy is a Poisson map; symplectic on the leaf)."""
from __future__ import annotations

import sympy as sp

from . import numeric_scale as ns
from . import reduction
from .codegen import HeyokaPrinter, function_source, module_source
from .model import X, psi, structure_matrix, theta
from .paper import delta, gamma, lambar, m, mu, pps, pth
from .results import DISAGREES, HOLDS, Result, fmt
from .symmetry import rot3

sigma = sp.symbols("sigma")
s = sp.symbols("s")
lam_body = sp.symbols("lam_body", real=True)
PAR = {m: "m", mu: "mu", gamma: "gamma", delta: "delta", lambar: "lam"}


def rotation_generator():
    a = sp.symbols("a", real=True)
    G = sp.diag(rot3(a), rot3(a), rot3(a))
    return sp.diff(G, a).subs(a, 0)


def straight_rod_charpoly():
    """(full characteristic polynomial in s, cubic P(sigma) with sigma = s^2, its discriminant) at mu = 2 lam."""
    f = sp.Matrix(ns.body_rhs())
    Jm = f.jacobian(X).subs(dict(zip(X, ns.straight_rod_state()))).subs(mu, 2 * lambar)
    cp = sp.factor(Jm.charpoly(s).as_expr())
    q = sp.cancel(cp / s**3)
    P = sp.Poly(sp.expand(sp.numer(sp.together(q)).subs(s, sp.sqrt(sigma))), sigma)
    lead = P.LC()
    P = sp.Poly(sp.expand(P.as_expr() / lead), sigma)
    disc = sp.factor(sp.discriminant(P.as_expr(), sigma))
    return cp, P, disc


def reduced_linearisation():
    """(b, c) of s^4 + b s^2 + c, the characteristic polynomial of the reduced Jacobian A = J Hess(Hbar) at
    (theta, psi = 0, pbar_theta = 0, pbar_psi), and the Hessian entries coupling the (theta, pbar_psi) and
    (psi, pbar_theta) blocks (zero by the evenness of Hbar in psi and pbar_theta: then the odd coefficients of
    the charpoly vanish and b = H_tt H_PtPt + H_pp H_PpPp - 2 H_tPp H_pPt, c = det Hess, since det J = 1)."""
    _, _, Hbar, _ = reduction.reduced_hamiltonians()
    at = {psi: 0, pth: 0}

    def d2(a, b_):
        return sp.diff(Hbar, a, b_).subs(at)

    mixed = [d2(theta, psi), d2(theta, pth), d2(pps, psi), d2(pps, pth)]
    Htt, HPP, HtP = d2(theta, theta), d2(pps, pps), d2(theta, pps)
    Hpp, Hqq, Hpq = d2(psi, psi), d2(pth, pth), d2(psi, pth)
    b = Htt * Hqq + Hpp * HPP - 2 * HtP * Hpq
    c = (Htt * HPP - HtP**2) * (Hpp * Hqq - Hpq**2)
    return b, c, mixed


def derive_all():
    res = []
    cp, P, disc = straight_rod_charpoly()
    d0 = sp.factor(disc.subs(lambar, 0))
    mc_root = sp.simplify(d0.subs(m, 2 * sp.sqrt(1 + gamma)))
    ok = P.degree() == 3 and mc_root == 0
    res.append(Result("floquet_straight_rod", "eq:buckling_load_2, sec:numerics (saddle of Figures 6-7)",
                      "Straight rod at mu = 2 lambdabar: charpoly of the body Jacobian = s^3 P(s^2), P cubic; the "
                      "quartet is a saddle-focus iff disc_sigma(P) < 0, Hamiltonian-Hopf at disc = 0; at "
                      "lambdabar = 0 the discriminant vanishes at m = m_c = 2 sqrt(1 + gamma)",
                      HOLDS if ok else DISAGREES,
                      "symbolic: Matrix.charpoly, factor; discriminant of P in sigma; substitution m = m_c at lam = 0",
                      {"P(sigma)": fmt(P.as_expr()), "disc at lam = 0": fmt(d0)}))
    b, c, mixed = reduced_linearisation()
    odd = [sp.expand(e) for e in mixed]
    res.append(Result("reduced_linearisation", "eq:full_ham_nondim (equilibria on Fix(R))",
                      "At a reduced equilibrium (theta, 0, 0, pbar_psi) the Jacobian's charpoly is s^4 + b s^2 + c "
                      "(no odd terms): Hamiltonian-Hopf at b^2 = 4 c, b > 0",
                      HOLDS if all(o == 0 for o in odd) else DISAGREES,
                      "symbolic: the Hessian entries coupling (theta, pbar_psi) with (psi, pbar_theta) are 0 at psi = pbar_theta = 0"))
    xi = rotation_generator()
    res.append(Result("relative_equilibrium", "sec:reduction (phi cyclic), paper sec. 3 (periodic solution)",
                      "For mu != 2 lambdabar the saddle-type set on the chart level is a relative equilibrium "
                      "x(t) = G_{omega t} x0 (f(x0) = omega xi x0), periodic in the body frame with monodromy "
                      "exp(T (Df - omega xi)); computed numerically in magrod/floquet.py",
                      HOLDS, "generator xi = dG_a/da at a = 0 (symbolic); rest numeric (magrod tests)",
                      {"xi nonzero entries": [(i, j, int(xi[i, j])) for i in range(9) for j in range(9) if xi[i, j]]}))
    return res


def module():
    xi = rotation_generator()
    cp, P, disc = straight_rod_charpoly()
    b, c, _ = reduced_linearisation()
    xnames = ["m1", "m2", "m3", "n1", "n2", "n3", "e31", "e32", "e33"]
    pm = HeyokaPrinter({**PAR, **dict(zip(X, xnames)), lam_body: "lam_body", theta: "theta", pps: "ppsi"},
                       lib="math")
    Jm = structure_matrix(lam_body)
    parts = [
        function_source("structure_matrix", xnames + ["lam_body"], [Jm[i, j] for i in range(9) for j in range(9)],
                        pm, "J(x; lambda) of eq:noncanonical_structure, row-major 81 entries (lambda = lam/m^4)."),
        function_source("straight_rod_cubic", ["m", "gamma", "delta", "lam"],
                        [P.coeff_monomial(sigma**k).subs(mu, 2 * lambar) for k in (2, 1, 0)], pm,
                        "Coefficients (a2, a1, a0) of the monic cubic sigma^3 + a2 sigma^2 + a1 sigma + a0 = P(sigma), "
                        "sigma = s^2, of the straight rod's exponents at mu = 2 lam."),
        function_source("straight_rod_discriminant", ["m", "gamma", "delta", "lam"], disc, pm,
                        "disc_sigma(P): < 0 saddle-focus quartet, = 0 Hamiltonian-Hopf (mu = 2 lam)."),
        function_source("reduced_bc", ["theta", "ppsi", "m", "mu", "gamma", "delta", "lam"], [b, c], pm,
                        "(b, c) of s^4 + b s^2 + c at the reduced equilibrium (theta, psi = 0, pbar_theta = 0, ppsi)."),
    ]
    return module_source("Floquet analysis of the saddle-type sets (derive/floquet.py): rotation generator, Poisson "
                         "matrix, straight-rod cubic and its discriminant, reduced-equilibrium charpoly.",
                         "floquet.py", parts,
                         {"ROTATION_GENERATOR": tuple(float(xi[i, j]) for i in range(9) for j in range(9))},
                         lib="math")
