"""The dimensional scale used by the numerics: B = 1, C = 1, m3 = p_phi = 1, hence (eq:nondim_1)
C2 = 1/m^2, 2 C1 = (mu + 1)/m^4, lambda = lambdabar/m^4, 1/H = 1/J = delta m^2, 1/K = (gamma + delta) m^2,
and t = s (arclength).  With this scale Hbar = H exactly up to the dropped constant, and the 9-D body-frame
system and the 4-D reduced system are two formulations of one orbit."""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from . import reduction
from .model import B, B1, B2, C, X, cH, cJ, cK, gradient, lam, p_phi, p_psi, p_theta, structure_matrix
from .paper import C1, C2, delta, gamma, lambar, m, mu, pps, pth
from .poisson import hamiltonian_compliance

BODY_SCALE = {B1: 1, B2: 1, B: 1, C: 1, cH: delta * m**2, cJ: delta * m**2, cK: (gamma + delta) * m**2,
              lam: lambar / m**4, C2: 1 / m**2, C1: (mu + 1) / (2 * m**4), p_phi: 1, p_theta: pth, p_psi: pps}
LAMBDA_BODY = lambar / m**4


def to_body_scale(expr):
    """Substitute BODY_SCALE, with sqrt(2 C1 - C2^2 - 2 lambda p_psi) -> sqrt(mu - 2 lambdabar pbar_psi)/m^2."""
    rad = sp.expand(reduction.RHO2)
    e = expr.replace(lambda x: x.is_Pow and x.exp.is_Rational and x.exp.q == 2 and sp.expand(x.base - rad) == 0,
                     lambda x: (reduction.RHO2_BAR ** sp.Rational(1, 2) / m**2) ** (2 * x.exp))
    return e.subs(BODY_SCALE)


@lru_cache(maxsize=None)
def body_hamiltonian():
    return sp.expand(hamiltonian_compliance().subs(BODY_SCALE))


@lru_cache(maxsize=None)
def body_rhs():
    return list(sp.expand(structure_matrix(LAMBDA_BODY) * gradient(body_hamiltonian())))


def casimirs_body():
    from . import paper

    return [sp.expand(c.subs(lam, LAMBDA_BODY)) for c in paper.eq_magnetic_casimirs()]


def casimir_values():
    """Values of C1, C2, C3 on every orbit of the chart at this scale."""
    return [(mu + 1) / (2 * m**4), 1 / m**2, sp.Integer(1)]


@lru_cache(maxsize=None)
def euler_to_body():
    """X(theta, psi, phi, pbar_theta, pbar_psi) at this scale (p_phi = 1)."""
    return [sp.expand(to_body_scale(x)) for x in reduction.canonical_map()]


def body_to_euler():
    """Inverse chart on sin(theta) > 0, written in body variables:
    theta = atan2(sqrt(e31^2 + e32^2), e33), phi = atan2(e32, -e31), p_theta = (e32 m1 - e31 m2)/sin(theta), p_psi = m.e3 (m3 = 1
    is p_phi), psi = atan2(n.b, n.a), where R e_1 = cos(psi) a + sin(psi) b splits the first column of R(q)
    into the body vectors a = (cos t cos f, -cos t sin f, sin t), b = (-sin f, -cos f, 0), written with
    cos f = -e31/sin t, sin f = e32/sin t; since n = C2 e3 + rho R e_1 and a, b are orthonormal and normal
    to e3, n.a = rho cos(psi), n.b = rho sin(psi).  Verified as an inverse in derive/build.py."""
    m1, m2, m3, n1, n2, n3, e1, e2, e3 = X
    st = sp.sqrt(e1**2 + e2**2)
    a = sp.Matrix([-e3 * e1 / st, -e3 * e2 / st, st])
    b = sp.Matrix([-e2 / st, e1 / st, 0])
    nv = sp.Matrix([n1, n2, n3])
    # theta = atan2(sin, cos) rather than acos(e33): full accuracy near the poles
    return {"theta": sp.atan2(st, e3), "psi": sp.atan2(nv.dot(b), nv.dot(a)), "phi": sp.atan2(e2, -e1),
            "pbar_theta": (e2 * m1 - e1 * m2) / st, "pbar_psi": m1 * e1 + m2 * e2 + m3 * e3}


def hamiltonian_offset():
    """H_body(X(q, p)) - Hbar(q, p) at this scale (a constant: the terms dropped in eq:full_ham_nondim)."""
    _, _, _, const = reduction.reduced_hamiltonians()
    return sp.simplify(const.subs({reduction.m3p: 1, C: 1, reduction.C2p: 1 / m**2}))


# --- event functions and the straight rod, in body variables --------------------------------------------------
def events_body():
    """Event functions of the body-frame integrators, written in (m, n, e3) (each checked on the chart in
    events_on_chart):
      section    = e31 n2 - e32 n1          = sin(theta) rho sin(psi)   (Poincare section sin(psi) = 0 with
                                                                         the crossing direction of sin(psi))
      sin2_theta = e31^2 + e32^2            = sin(theta)^2              (distance from the chart's poles)
      radicand   = mu - 2 lambdabar m.e3    = mu - 2 lambdabar pbar_psi (eq:alignment_condition)
      ptheta_sin = e32 m1 - e31 m2          = sin(theta) pbar_theta     (turning points of theta)
    with rho = sqrt(mu - 2 lambdabar pbar_psi)/m^2 > 0 and sin(theta) > 0 on the chart."""
    m1, m2, m3, n1, n2, n3, e1, e2, e3 = X
    return {"section": e1 * n2 - e2 * n1, "sin2_theta": e1**2 + e2**2,
            "radicand": mu - 2 * lambar * (m1 * e1 + m2 * e2 + m3 * e3), "ptheta_sin": e2 * m1 - e1 * m2}


def events_on_chart():
    """Each body event pulled back through euler_to_body minus its chart expression (zero iff the identity
    holds), as trig normal forms modulo sin^2 + cos^2 = 1 and rho^2 = mu - 2 lambdabar pbar_psi."""
    from .model import psi, theta

    sub = dict(zip(X, euler_to_body()))
    rho = sp.sqrt(reduction.RHO2_BAR) / m**2
    chart = {"section": sp.sin(theta) * rho * sp.sin(psi), "sin2_theta": sp.sin(theta) ** 2,
             "radicand": reduction.RHO2_BAR, "ptheta_sin": sp.sin(theta) * pth}
    return {k: reduction.trig_normal_form(sp.expand(e.subs(sub, simultaneous=True) - chart[k]), reduction.RHO2_BAR)
            for k, e in events_body().items()}


def straight_rod_state():
    """The straight rod aligned with the field: m, n, e3 all along the body 3-axis, m3 = p_phi = 1 and
    n3 = C2 = e3.n = 1/m^2 (the chart's Casimir C2).  Returned as the 9-vector of X."""
    return [sp.Integer(0), sp.Integer(0), sp.Integer(1), sp.Integer(0), sp.Integer(0), 1 / m**2,
            sp.Integer(0), sp.Integer(0), sp.Integer(1)]


def straight_rod_analysis():
    """(rhs at the straight rod, C1 defect = C1(x_eq) - chart value, mu solving defect = 0).  The rhs vanishes
    identically (an equilibrium for all parameters); the rod lies on the chart's Casimir level iff the defect
    vanishes, i.e. iff mu = 2 lambdabar (the radicand then vanishes at pbar_psi = m.e3 = 1: the chart is
    singular exactly there)."""
    sub = dict(zip(X, straight_rod_state()))
    rhs = [sp.simplify(f.subs(sub)) for f in body_rhs()]
    defect = sp.simplify(casimirs_body()[0].subs(sub) - casimir_values()[0])
    mu_sol = sp.solve(defect, mu)
    return rhs, defect, mu_sol


# --- the axial stretch v3 (eq:hyperelastic) -----------------------------------------------------------------
def stretch_chart():
    """v3 on the Euler chart, written by hand from the chart (eq:canonical_force) and eq:nondim_1, to be checked
    against the body-frame v3 = dH/dn3 pulled back (stretch_analysis):
    n3 = n.d3 = C2 cos(theta) + rho sin(theta) cos(psi) with C2 = 1/m^2, rho = sqrt(mu - 2 lambdabar pbar_psi)/m^2,
    and 1/K = (gamma + delta)/C2 = (gamma + delta) m^2, so
    v3 = 1 + n3/K = 1 + (gamma + delta) (cos(theta) + sqrt(mu - 2 lambdabar pbar_psi) sin(theta) cos(psi)).
    Independent of pbar_theta and of phi."""
    from .model import psi, theta

    return 1 + (gamma + delta) * (sp.cos(theta) + sp.sqrt(reduction.RHO2_BAR) * sp.sin(theta) * sp.cos(psi))


def stretch_analysis():
    """The axial stretch v3 = d3.r' = ds'/ds (deformed over reference length) four ways.

    Returns a dict of residuals that vanish iff each identity holds, plus the closed forms:
      legendre   dH/dn3 - v3(n) where v3(n) inverts n3 = dW/dv3 of eq:hyperelastic (dimensional: 1 + n3/K)
      compliance 1/K from eq:nondim_1 (gamma = C2 (1/K - 1/J), delta = C2/J) minus (gamma + delta)/C2
      body       dH/dn3 at the numeric scale minus 1 + (gamma + delta) m^2 n3
      chart      the body v3 pulled back through euler_to_body minus stretch_chart() (trig normal form)
      straight   v3 at the straight rod (n3 = C2 = 1/m^2): 1 + gamma + delta
      inext      v3 at gamma = delta = 0: 1 (the inextensible rod)."""
    from .model import K as Kst, n3, v3
    from .poisson import hamiltonian

    Ham, sol = hamiltonian()
    v3_dim = sp.diff(Ham, n3)
    Kp, Jp = sp.symbols("K_s J_s", positive=True)
    ck_sol = sp.solve([gamma - C2 * (1 / Kp - 1 / Jp), delta - C2 / Jp], [Kp, Jp], dict=True)[0]
    v3_body = sp.expand(sp.diff(body_hamiltonian(), n3))
    sub = dict(zip(X, euler_to_body()))
    chart = stretch_chart()
    pulled = reduction.trig_normal_form(sp.expand(v3_body.subs(sub, simultaneous=True) - chart), reduction.RHO2_BAR)
    straight = sp.simplify(v3_body.subs(dict(zip(X, straight_rod_state()))))
    return {"v3_dimensional": v3_dim, "v3_body": v3_body, "v3_chart": chart, "v3_straight_rod": straight,
            "legendre": sp.expand(v3_dim - sol[v3]), "legendre_closed": sp.expand(v3_dim - (1 + n3 / Kst)),
            "compliance": sp.simplify(1 / ck_sol[Kp] - (gamma + delta) / C2),
            "body": sp.expand(v3_body - (1 + (gamma + delta) * m**2 * X[5])),
            "chart": pulled, "straight": sp.simplify(straight - (1 + gamma + delta)),
            "inext": sp.expand(v3_body.subs({gamma: 0, delta: 0}) - 1)}


def derive_all():
    """Results of this module for the derivation report."""
    from .results import DISAGREES, HOLDS, Result, fmt

    res = []
    ev = events_on_chart()
    res.append(Result("events_body", "eq:canonical_force, eq:alignment_condition (sec:numerics sections)",
                      "Body-frame event functions: e31 n2 - e32 n1 = sin(theta) rho sin(psi), e31^2 + e32^2 = "
                      "sin(theta)^2, mu - 2 lambdabar m.e3 = the radicand, e32 m1 - e31 m2 = sin(theta) pbar_theta",
                      HOLDS if all(v == 0 for v in ev.values()) else DISAGREES,
                      "symbolic: pulled back through the chart, trig normal form of each difference is 0",
                      {k: fmt(v) for k, v in ev.items()}))
    rhs, defect, mu_sol = straight_rod_analysis()
    ok = all(r == 0 for r in rhs) and len(mu_sol) == 1 and sp.simplify(mu_sol[0] - 2 * lambar) == 0
    res.append(Result("straight_rod", "sec:homoclinic (the straight rod), eq:alignment_condition",
                      "The straight rod m = e3 = (0, 0, 1), n = (0, 0, 1/m^2) is an equilibrium of the body system for "
                      "all parameters; it lies on the chart's Casimir level iff mu = 2 lambdabar",
                      HOLDS if ok else DISAGREES,
                      "symbolic: rhs at the state simplifies to 0; C1(x_eq) - (mu + 1)/(2 m^4) solved for mu",
                      {"C1 defect": fmt(defect), "mu on the level": [fmt(s) for s in mu_sol]}))
    st = stretch_analysis()
    keys = ("legendre", "legendre_closed", "compliance", "body", "chart", "straight", "inext")
    res.append(Result("axial_stretch", "eq:hyperelastic, eq:nondim_1 (v3 > 0, sec. 2)",
                      "The axial stretch v3 = dH/dn3 = 1 + n3/K = 1 + (gamma + delta) m^2 n3 = 1 + (gamma + delta) "
                      "(cos(theta) + sqrt(mu - 2 lambdabar pbar_psi) sin(theta) cos(psi)); 1 + gamma + delta on the "
                      "straight rod, 1 for gamma = delta = 0; v3 <= 0 (unphysical) iff n3 <= -K",
                      HOLDS if all(st[k] == 0 for k in keys) else DISAGREES,
                      "symbolic: dH/dn3 of the Legendre transform minus the inverted constitutive law; 1/K solved from "
                      "eq:nondim_1; body v3 pulled back through the chart, trig normal form of the difference is 0",
                      {**{k: fmt(st[k]) for k in keys},
                       **{k: fmt(st[k]) for k in ("v3_dimensional", "v3_body", "v3_chart", "v3_straight_rod")}}))
    return res
