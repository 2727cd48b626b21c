"""The leading term of the splitting of the separatrix of the straight rod at mu = 2 lambdabar (a = 2b in
eq:condition_unperturbed_1), derived (issue 12, item 3; docs/nonintegrability.md).

Idea.  On mu = 2 lambdabar the radicand of eq:full_ham_nondim is mu - 2 lambdabar pbar_psi = 2 lambdabar (1 - pbar_psi),
so 1 - pbar_psi is an action whose angle is psi, and the transverse force rho = sqrt(2 lambdabar (1 - pbar_psi)) is
O(lambdabar) on the unstable manifold of the straight rod.  Blowing up with 1 - pbar_psi = lambdabar J and
Cartesian coordinates (x, y) = sqrt(2 J) (cos psi, sin psi) = (rho cos psi, rho sin psi)/lambdabar gives EXACTLY

    Hbar = H0(theta, pbar_theta) + lambdabar K1(theta, x, y) + lambdabar^2 K2(theta, x, y),   {x, y} = 1/lambdabar,

(H0 = eq:extensible_ham at pbar_psi = 1), i.e. theta' = pbar_theta, pbar_theta' = -d_theta Hbar,
x' = d_y (K1 + lambdabar K2), y' = -d_x (K1 + lambdabar K2).  In the shifted variables
xi = x - tan(theta/2), eta = y + pbar_theta, with omega = 1/(1 + cos theta) (= psi' of eq:psi_condition),

    xi'  = -omega eta + lambdabar d_y K2,
    eta' =  omega xi  - lambdabar (d_x K2 + d_theta K1) - lambdabar^2 d_theta K2        (exact identities),

so at lambdabar = 0 the set xi = eta = 0 is invariant: the unperturbed unstable manifold carries the transverse
force (x, y) = (tan(theta0/2), -pbar_theta0) along the homoclinic orbit theta0(t) of derive/homoclinic.py.  At
first order zeta = xi + i eta = lambdabar zeta1 + O(lambdabar^2) solves zeta1' = i omega zeta1 + G(t) with
G = d_y K2 - i (d_x K2 + d_theta K1) on that orbit, and zeta1 -> 0 as t -> -infinity (W^u of the straight rod), so

    zeta1(t) = exp(i Psi(t)) Int_{-inf}^t exp(-i Psi(s)) G(s) ds,    Psi(t) = Int_0^t omega.

On Sigma = {pbar_theta = 0} y = eta exactly, and the turning point moves by O(lambdabar), hence

    psi_u = lambdabar S / tan(theta_t/2) + O(lambdabar^2),   S = eta1(0) = Int_{-inf}^0 N dt,
    N = cos(Psi) Im G - sin(Psi) Re G                                                     (the integrand below),

theta_t = theta0(0) the turning point (cos theta_t = u_+).  N is even in t, so S = Int_0^inf N dt =
(1/2) Int_R N dt: a second-order Mel'nikov integral (the first order vanishes, melnikov_vanishes).  The force
component that R flips is rho sin psi_u = lambdabar^2 S + O(lambdabar^3) in chart units.
What is symbolic: the blow-up identity, the bracket, the (xi, eta) identities, the parity of N.  The expansion
in lambdabar is formal (regular perturbation on t <= 0 at a hyperbolic-elliptic rest point); its value is checked
against the measurement in magrod (magrod.splitting.leading_coefficient, tests/test_splitting.py)."""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from .codegen import HeyokaPrinter, function_source, module_source
from .model import psi, theta
from .paper import delta, gamma, lambar, m, mu, pps, pth
from .reduction import reduced_hamiltonians, trig_normal_form
from .results import HOLDS, DISAGREES, Result, fmt

x, y = sp.symbols("x y", real=True)
r = sp.symbols("r", positive=True)  # sqrt(2 J) = |(x, y)|
lp = sp.symbols("lambdabar_p", positive=True)
Psi = sp.symbols("Psi", real=True)  # Int_0^t omega dt along the unperturbed orbit
_CP, _SP = sp.symbols("cos_Psi sin_Psi", real=True)
_c, _s = sp.cos(theta), sp.sin(theta)


def _half_powers(e):
    """Every radicand**(k/2) with the radicand factored (so sqrt(lambdabar^2 r^2) = lambdabar r)."""
    return e.replace(lambda z: z.is_Pow and z.exp.is_Rational and z.exp.q == 2,
                     lambda z: sp.sqrt(sp.factor(sp.expand(z.base))) ** (2 * z.exp))


def blowup_parts():
    """H0 (pbar_psi = 1), K1, K2 in (theta, pbar_theta, x, y); J = (x^2 + y^2)/2 (the ansatz checked in derive_all)."""
    J = (x**2 + y**2) / 2
    H0 = pth**2 / 2 + ((1 - _c) / _s) ** 2 / 2 + _c / m**2 + gamma * _c**2 / (2 * m**2)
    K1 = -J / (1 + _c) + (1 + gamma * _c) * _s * x / m**2 - delta / m**2
    K2 = J**2 / (2 * _s**2) + gamma * _s**2 * x**2 / (2 * m**2) + delta * J / m**2
    return H0, K1, K2


@lru_cache(maxsize=None)
def blowup_difference():
    """Hbar(mu = 2 lambdabar, pbar_psi = 1 - lambdabar r^2/2) - (H0 + lambdabar K1 + lambdabar^2 K2)(x = r cos psi,
    y = r sin psi), in trig normal form (zero iff the blow-up is exact)."""
    _, _, Hbar, _ = reduced_hamiltonians()
    Hc = _half_powers(Hbar.subs(mu, 2 * lambar).subs(lambar, lp).subs(pps, 1 - lp * r**2 / 2))
    H0, K1, K2 = blowup_parts()
    Hb = (H0 + lp * K1 + lp**2 * K2).subs({x: r * sp.cos(psi), y: r * sp.sin(psi)})
    return trig_normal_form(sp.expand(Hc - Hb))


def xy_bracket():
    """{x, y} in the canonical pair (psi, pbar_psi) with x, y = sqrt(2 (1 - pbar_psi)/lambdabar) (cos psi, sin psi)."""
    R = sp.sqrt(2 * (1 - pps) / lp)
    X, Y = R * sp.cos(psi), R * sp.sin(psi)
    return sp.simplify(sp.diff(X, psi) * sp.diff(Y, pps) - sp.diff(X, pps) * sp.diff(Y, psi))


def vector_field():
    """(theta', pbar_theta', x', y') of the blown-up system (exact)."""
    H0, K1, K2 = blowup_parts()
    H = H0 + lp * K1 + lp**2 * K2
    K = K1 + lp * K2
    return sp.diff(H, pth), -sp.diff(H, theta), sp.diff(K, y), -sp.diff(K, x)


def shifted_identities():
    """Residuals of xi' = -omega eta + lambdabar K2_y and eta' = omega xi - lambdabar (K2_x + K1_theta)
    - lambdabar^2 K2_theta along the exact vector field (both zero iff the identities hold)."""
    _, K1, K2 = blowup_parts()
    th_d, pth_d, x_d, y_d = vector_field()
    om = 1 / (1 + _c)
    half_tan = _s / (1 + _c)  # tan(theta/2)
    xi, eta = x - half_tan, y + pth
    xi_d = x_d - sp.diff(half_tan, theta) * th_d
    eta_d = y_d + pth_d
    r1 = xi_d - (-om * eta + lp * sp.diff(K2, y))
    r2 = eta_d - (om * xi - lp * (sp.diff(K2, x) + sp.diff(K1, theta)) - lp**2 * sp.diff(K2, theta))
    return trig_normal_form(sp.expand(r1)), trig_normal_form(sp.expand(r2))


def forcing():
    """G = (Re G, Im G) = (K2_y, -(K2_x + K1_theta)) on the unperturbed manifold x = tan(theta/2), y = -pbar_theta,
    written with tan(theta/2) = sin/(1 + cos)."""
    _, K1, K2 = blowup_parts()
    on = {x: _s / (1 + _c), y: -pth}
    gr = sp.diff(K2, y).subs(on)
    gi = (-(sp.diff(K2, x) + sp.diff(K1, theta))).subs(on)
    return gr, gi


def integrand():
    """N(theta, pbar_theta, Psi) = cos(Psi) Im G - sin(Psi) Re G: psi_u = lambdabar Int_{-inf}^0 N dt / tan(theta_t/2)."""
    gr, gi = forcing()
    return sp.cos(Psi) * gi - sp.sin(Psi) * gr


def integrand_grouped():
    """N in a grouped form for code generation (checked equal to integrand()): with q = J/sin^2,
    J = (tan^2(theta/2) + pbar_theta^2)/2, X = tan(theta/2)."""
    X = _s / (1 + _c)
    q = (X**2 + pth**2) / (2 * _s**2)
    gr = -pth * (q + delta / m**2)
    gi = -(X * (q + gamma * _s**2 / m**2 + delta / m**2 + (_c + gamma * sp.cos(2 * theta)) / m**2)
           - q * _s**3 / (1 + _c) ** 2)
    return sp.cos(Psi) * gi - sp.sin(Psi) * gr


def derive_all():
    res = []
    d_blow = blowup_difference()
    br = xy_bracket()
    res.append(Result(
        "splitting_blowup", "eq:full_ham_nondim, eq:condition_unperturbed_1 (a = 2b)",
        "On mu = 2 lambdabar, with 1 - pbar_psi = lambdabar (x^2 + y^2)/2 and (x, y) = (rho cos psi, rho sin psi)/"
        "lambdabar: Hbar = H0 + lambdabar K1 + lambdabar^2 K2 exactly, {x, y} = 1/lambdabar",
        HOLDS if d_blow == 0 and sp.simplify(br - 1 / lp) == 0 else DISAGREES,
        "symbolic: trig normal form of the difference is 0 (rho = lambdabar r for lambdabar > 0); bracket in (psi, "
        "pbar_psi) simplified",
        {"H0": fmt(blowup_parts()[0]), "K1": fmt(blowup_parts()[1]), "K2": fmt(blowup_parts()[2]),
         "difference": fmt(d_blow), "{x, y}": fmt(br)}))

    r1, r2 = shifted_identities()
    res.append(Result(
        "splitting_invariant_manifold", "eq:psi_condition, eq:theta_homoclinic (a = 2b)",
        "xi = x - tan(theta/2), eta = y + pbar_theta obey xi' = -omega eta + lambdabar K2_y, eta' = omega xi - "
        "lambdabar (K2_x + K1_theta) - lambdabar^2 K2_theta (omega = 1/(1 + cos theta)): at lambdabar = 0 the "
        "unstable manifold of the straight rod carries (x, y) = (tan(theta0/2), -pbar_theta0)",
        HOLDS if r1 == 0 and r2 == 0 else DISAGREES,
        "symbolic: residuals along the exact blown-up vector field have zero trig normal form",
        {"residual xi'": fmt(r1), "residual eta'": fmt(r2)}))

    def nf(e):  # cos(Psi), sin(Psi) enter linearly: plain symbols
        return trig_normal_form(sp.expand(e).subs({sp.cos(Psi): _CP, sp.sin(Psi): _SP}))

    N = integrand()
    same = nf(N - integrand_grouped()) == 0
    even = nf(N - N.subs({pth: -pth, Psi: -Psi}, simultaneous=True)) == 0
    gr, gi = forcing()
    res.append(Result(
        "splitting_leading_term", "eq:condition_unperturbed_1 (a = 2b), eq:Mel_ext (second order)",
        "Leading term of the splitting at mu = 2 lambdabar: psi_u = lambdabar S/tan(theta_t/2) + O(lambdabar^2), "
        "rho sin psi_u = lambdabar^2 S + O(lambdabar^3), S = Int_0^inf N dt along the lambdabar = 0 homoclinic "
        "orbit (Psi' = 1/(1 + cos theta), Psi(0) = 0)",
        HOLDS if same and even else DISAGREES,
        "symbolic: N from the first-order equation of zeta = xi + i eta (variation of constants, zeta -> 0 at "
        "t -> -inf), parity N(theta, -pbar_theta, -Psi) = N; formal expansion in lambdabar, value compared with "
        "the measured splitting in magrod (magrod.splitting.leading_coefficient)",
        {"Re G": fmt(sp.simplify(gr)), "Im G": fmt(sp.simplify(gi)), "N even in t": even,
         "grouped form equals N": same,
         "formula": "psi_u = lambdabar * S / tan(theta_t/2) + O(lambdabar^2); S = Int_{-inf}^0 N dt = "
                    "Int_0^inf N dt; N = cos(Psi) Im G - sin(Psi) Re G; at mu = a eps^2, lambdabar = b eps^2 "
                    "(a = 2b): psi_u/eps^2 -> b S/tan(theta_t/2)"}))
    return res


def module() -> str:
    names = {theta: "theta", pth: "ptheta", Psi: "Psi", m: "m", gamma: "gamma", delta: "delta"}
    pr = HeyokaPrinter(names)
    parts = [function_source(
        "leading_integrand", ["theta", "ptheta", "Psi", "m", "gamma", "delta"], integrand_grouped(), pr,
        "N with psi_u = lambdabar Int_0^inf N dt / tan(theta_t/2) + O(lambdabar^2) at mu = 2 lambdabar, along the "
        "lambdabar = 0 homoclinic orbit (Psi' = 1/(1 + cos theta), Psi(0) = 0 at the turning point).")]
    return module_source("Leading term of the separatrix splitting at mu = 2 lambdabar (issue 12).", "splitting.py",
                         parts)
