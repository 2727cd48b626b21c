"""Every formula *printed* in the paper that derive/ compares against, in one place.

These are comparison targets, never inputs: nothing in the numeric pipeline is built from this module
except the explicitly labelled "printed" Mel'nikov integrand and closed form, which magrod evaluates side
by side with the derived ones.  Each function is named after the paper's equation label.
"""
from __future__ import annotations

import sympy as sp

from .model import (B, B1, B2, C, J, K, Hs, e3, evec, lam, m1, m2, m3, mvec, n1, n2, n3, nvec,
                    p_phi, p_psi, p_theta, phi, psi, theta, d3)

# constants of the reduction and the non-dimensional parameters (eq:nondim_1)
C1, C2 = sp.symbols("C1 C2", real=True)
m, mu, gamma, delta, lambar = sp.symbols("m mu gamma delta lambdabar", real=True)
pth, pps = sp.symbols("pbar_theta pbar_psi", real=True)  # pbar_theta, pbar_psi
t = sp.symbols("t", real=True)
a, b, eps = sp.symbols("a b epsilon", positive=True)
psi0, psibar = sp.symbols("psi_0 psibar", real=True)

s_, c_ = sp.sin(theta), sp.cos(theta)


def eq_magnetic_ham():
    """eq:magnetic_ham with u(m) = (m1/B1, m2/B2, m3/C) and v(n) from eq:constit, eq:hyperelastic."""
    u = sp.Matrix([m1 / B1, m2 / B2, m3 / C])
    v = sp.Matrix([n1 / Hs, n2 / J, 1 + n3 / K])
    return (mvec.dot(u) + nvec.dot(v - d3)) / 2 + d3.dot(nvec)


def eq_magnetic_moment_force_vector():
    """eq:magnetic_moment, eq:magnetic_force, eq:magnetic_vector as printed: m' = m x u + n x (d3 + v),
    n' = n x u + lambda e3 x (d3 + v), e3' = e3 x u, with v the strain of eq:hyperelastic."""
    u = sp.Matrix([m1 / B1, m2 / B2, m3 / C])
    v = sp.Matrix([n1 / Hs, n2 / J, 1 + n3 / K])
    return sp.Matrix.vstack(mvec.cross(u) + nvec.cross(d3 + v), nvec.cross(u) + lam * evec.cross(d3 + v),
                            evec.cross(u))


def eq_magnetic_casimirs():
    """eq:magnetic_casimirs1-3."""
    return [nvec.dot(nvec) / 2 + lam * mvec.dot(evec), evec.dot(nvec), evec.dot(evec)]


def eq_magnetic_lagrange():
    """eq:magnetic_lagrange: I1 = B m.d3 (isotropic)."""
    return B * m3


def eq_int2():
    """eq:int2: I2 = n.m + B lambda e3.d3 (isotropic, inextensible/unshearable)."""
    return nvec.dot(mvec) + B * lam * e3


def R_printed():
    """The Euler-angle rotation matrix R printed at the start of sec. 4."""
    ct, st, cf, sf, cp, sp_ = (sp.cos(theta), sp.sin(theta), sp.cos(phi), sp.sin(phi), sp.cos(psi),
                               sp.sin(psi))
    return sp.Matrix([[ct * cf * cp - sf * sp_, ct * cf * sp_ + cp * sf, -st * cf],
                      [-ct * sf * cp - cf * sp_, -ct * sf * sp_ + cf * cp, st * sf],
                      [st * cp, st * sp_, ct]])


def eq_canonical_magnetic():
    """eq:canonical_magnetic: e3(q)."""
    return sp.Matrix([-sp.sin(theta) * sp.cos(phi), sp.sin(theta) * sp.sin(phi), sp.cos(theta)])


def L_printed():
    """The matrix L of eq:canonical_moment, m = L p."""
    st, ct, sf, cf = sp.sin(theta), sp.cos(theta), sp.sin(phi), sp.cos(phi)
    return sp.Matrix([[st * sf, -cf, ct * cf], [st * cf, sf, -ct * sf], [0, 0, st]]) / st


def eq_canonical_force():
    """eq:canonical_force: n(q, p)."""
    ct, st, cf, sf, cp, sp_ = (sp.cos(theta), sp.sin(theta), sp.cos(phi), sp.sin(phi), sp.cos(psi),
                               sp.sin(psi))
    rho = sp.sqrt(2 * C1 - C2**2 - 2 * lam * p_psi)
    return C2 * sp.Matrix([-st * cf, st * sf, ct]) + rho * sp.Matrix(
        [ct * cf * cp - sf * sp_, -ct * sf * cp - cf * sp_, st * cp])


def eq_full_ham():
    """eq:full_ham (isotropic: B1 = B2 = B, H = J), printed with the constant p_phi^2 term dropped."""
    g = 1 / K - 1 / J
    rho2 = 2 * C1 - C2**2 - 2 * lam * p_psi
    return (p_theta**2 / (2 * B) + ((p_psi - p_phi * c_) / s_) ** 2 / (2 * B)
            + C2 * c_ * (C2 / 2 * g * c_ + 1) + (C2 * g * c_ + 1) * s_ * sp.cos(psi) * sp.sqrt(rho2)
            + g / 2 * s_**2 * sp.cos(psi) ** 2 * rho2 - lam / J * p_psi)


def eq_constraint():
    """eq:constraint: I2 in canonical variables."""
    rho = sp.sqrt(2 * C1 - C2**2 - 2 * lam * p_psi)
    return (lam * B * c_ + C2 * p_psi
            - rho * (p_theta * sp.sin(psi) - sp.cos(psi) * (p_phi - p_psi * c_) / s_))


def eq_full_ham_nondim():
    """eq:full_ham_nondim."""
    r2 = mu - 2 * lambar * pps
    return (pth**2 / 2 + ((pps - c_) / s_) ** 2 / 2 + c_ / m**2 + gamma * c_**2 / (2 * m**2)
            + (gamma * c_ + 1) * s_ * sp.cos(psi) * sp.sqrt(r2) / m**2
            + gamma / (2 * m**2) * s_**2 * sp.cos(psi) ** 2 * r2 - delta * lambar / m**2 * pps)


def eq_constraint_nonsim():
    """eq:constraint_nonsim (label `constraint_nonsim` in the source)."""
    return (pps + lambar * c_ / m**2
            - sp.sqrt(mu - 2 * lambar * pps) * (pth * sp.sin(psi) - sp.cos(psi) * (1 - pps * c_) / s_))


def eq_extensible_ham():
    """eq:extensible_ham."""
    return pth**2 / 2 + ((pps - c_) / s_) ** 2 / 2 + c_ / m**2 + gamma * c_**2 / (2 * m**2)


def eq_equivalent_rhs():
    """eq:equivalent: (theta', pbar_theta') at pbar_psi = 1."""
    return [pth, -(1 - c_) ** 2 / s_**3 + (gamma * c_ + 1) * s_ / m**2]


def eq_eq_oscillator_V():
    """eq:eq_oscillator: V(theta)."""
    return (1 - c_) / (1 + c_) / 2 + c_ / m**2 + gamma / (2 * m**2) * c_**2


def fixed_point_cubic(u):
    """The cubic (gamma u + 1)(1 + u)^2 = m^2 printed after eq:equivalent (as lhs - rhs)."""
    return (gamma * u + 1) * (1 + u) ** 2 - m**2


def m_critical():
    """eq:buckling_load_2: m_c = 2 sqrt(1 + gamma)."""
    return 2 * sp.sqrt(1 + gamma)


def homoclinic_energy():
    """h = (1 + gamma/2)/m^2, printed after eq:eq_oscillator."""
    return (1 + gamma / 2) / m**2


def g_of_u(u):
    """g(u) printed after eq:integral_g."""
    return u**2 + 2 * u * (1 + 1 / gamma) + 1 + 2 / gamma - m**2 / gamma


def u_pm():
    """u_+, u_- printed after g(u)."""
    r = sp.sqrt(1 + gamma * m**2) / gamma
    return -(1 + 1 / gamma) + r, -(1 + 1 / gamma) - r


def k_printed(up, um):
    """k of eq:integration_2."""
    return (up - um) / (1 - um)


def eq_theta_homoclinic(up, um, k):
    """eq:theta_homoclinic: cos(theta(t)) as printed (with tan, atanh and sqrt(k^2 - 1))."""
    arg = t * (1 - um) * sp.sqrt(gamma * (k**2 - 1)) / (4 * m)
    return um + (up - um) * sp.cosh(2 * sp.atanh(sp.sqrt((k - 1) / (k + 1)) * sp.tan(arg))) ** 2


def integral_identity_printed(k, z):
    """The antiderivative printed after eq:integration_2 for 1/(1 - k cosh^2 z)."""
    return -2 / sp.sqrt(k**2 - 1) * sp.atan(sp.sqrt((k + 1) / (k - 1)) * sp.tanh(z / 2))


def eq_Kirchhoff_homoclinic():
    """eq:Kirchhoff_homoclinic: cos(theta(t)) for gamma -> 0."""
    u0 = m**2 / 2 - 1
    return u0 + (1 - u0) * sp.tanh(sp.sqrt(1 - u0) / (m * sp.sqrt(2)) * t) ** 2


def eq_psi_condition():
    """eq:psi_condition: psi' = 1/(1 + cos theta)."""
    return 1 / (1 + c_)


def melnikov_H1():
    """H1 printed in sec. 7."""
    return (gamma * c_ + 1) * s_ * sp.cos(psi) * sp.sqrt(a - 2 * b * pps) / m**2


def melnikov_omega0():
    """omega_0 printed in sec. 7."""
    return 1 / (1 + c_)


def melnikov_partials():
    """The partial derivatives printed in sec. 7, keyed by name."""
    return {
        "dH0/dtheta": s_ * (1 / (1 + c_) ** 2 - (1 + gamma * c_) / m**2),
        "dH0/dpbar_theta": pth,
        "domega0/dtheta": s_ / (1 + c_) ** 2,
        "domega0/dpbar_theta": sp.Integer(0),
        "dH1/dtheta": (c_ + gamma * sp.cos(2 * theta)) * sp.cos(psi) * sp.sqrt(a - 2 * b * pps) / m**2,
        "dH1/dpbar_theta": sp.Integer(0),
    }


def eq_Mel_ext_integrand():
    """eq:Mel_ext: M(psi0) = -sqrt(a-2b)/m^2 sin(psi0) * Integral of this integrand dt (psibar = psi - psi0)."""
    return pth * sp.sin(psibar) * ((1 + c_) * (c_ + gamma * sp.cos(2 * theta)) + s_**2 * (1 + gamma * c_))


def eq_Mel_ext_prefactor():
    return -sp.sqrt(a - 2 * b) / m**2 * sp.sin(psi0)


def djps_fortran_rhs():
    """The right-hand side of the authors' shooting code (github.com/djps/homoclinic-orbits, newton.f, USRFUN_N,
    F(1)..F(6), without the factor xT of the time scaling), transcribed as a comparison target: state (x1..x3) =
    force, (x4..x6) = moment, quaternion q1..q4; parameters xnu, xrho, xm, xgamma, xsigma, xepsilon, xlambda.  The
    field direction in body components is read off the quaternion products of F(1)-F(3).  Returns (symbols, E, F)."""
    nu, rho, mm, gF, sF, eF, lF = sp.symbols("nu_F rho_F m_F gamma_F sigma_F epsilon_F lambda_F", real=True)
    x1, x2, x3, x4, x5, x6, q1, q2, q3, q4 = sp.symbols("x1:7 q1:5", real=True)
    E = [2 * (q1 * q3 - q2 * q4), 2 * (q1 * q4 + q2 * q3), q3**2 + q4**2 - q1**2 - q2**2]
    F = [(1 + nu) * x2 * x6 - x3 * x5 + lF * 2 * (q1 * q4 + q2 * q3) + lF * eF * x3 * (1 + sF) * 2 * (q1 * q4 + q2 * q3)
         - lF * eF * x2 * (q3**2 + q4**2 - q1**2 - q2**2),
         (1 + rho) * x3 * x4 - (1 + nu) * x1 * x6 - lF * 2 * (q1 * q3 - q2 * q4)
         + lF * eF * x1 * (1 + gF) * (q3**2 + q4**2 - q1**2 - q2**2) - lF * eF * x3 * (1 + sF) * 2 * (q1 * q3 - q2 * q4),
         x1 * x5 - (1 + rho) * x2 * x4 + lF * eF * 2 * x2 * (q1 * q3 - q2 * q4) - lF * eF * (1 + gF) * x1 * 2 * (q1 * q4 + q2 * q3),
         nu * x5 * x6 + x2 * (1 + eF * gF * x3) / mm**2,
         (rho - nu) * x4 * x6 - x1 * (1 + eF * (gF - sF) * x3) / mm**2,
         -rho * x4 * x5 - eF * sF * x1 * x2 / mm**2]
    syms = dict(nu=nu, rho=rho, m=mm, gamma=gF, sigma=sF, epsilon=eF, lam=lF, x=(x1, x2, x3, x4, x5, x6),
                q=(q1, q2, q3, q4))
    return syms, E, F
