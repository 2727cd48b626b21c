"""The leading term of the splitting of the separatrix of the straight rod at mu = 2 lambdabar (a = 2b in
eq:condition_unperturbed_1), derived (docs/nonintegrability.md).

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

import random
from functools import lru_cache

import mpmath
import sympy as sp

from . import homoclinic
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
    ok_ph, det_ph = phase_checks()
    res.append(Result(
        "splitting_phase_closed_form", "eq:psi_condition, eq:theta_homoclinic (regular form)",
        "The phase of S in closed form: Psi(t) = Int_0^t dt/(1 + cos theta0) = t/2 + B atan(rho tanh(kappa t)), "
        "B = A^2/(2 kappa sqrt(P q)), rho = sqrt(q/P), P = (1 + u_+)/2, q = A^2 - (1 - k) > 0; regular at gamma = 0",
        HOLDS if ok_ph else DISAGREES,
        "symbolic: Psi' - 1/(1 + cos theta0) is 0 as a rational function of tanh(kappa t) (P, q, kappa free "
        "positive); q identity for m, gamma > 0; constants at gamma = 0 equal the Kirchhoff ones (no 1/gamma)",
        det_ph))
    ok_s, det_s = s_form_checks()
    res.append(Result(
        "splitting_integrand_ball", "eq:condition_unperturbed_1 (a = 2b), ball code of S",
        "The integrand of S without cancellation: N = s (cos Psi Im G/s - sin Psi Re G/s), s = sin(theta0/2); "
        "N is affine in delta; s decreases for t > 0 and Int_T^inf s dt <= 2 A atan(exp(-kappa T))/(kappa "
        "sqrt(1 - omega)) (the tail bound of the enclosure)",
        HOLDS if ok_s else DISAGREES,
        "symbolic: Re G, Im G of forcing() equal s Re G/s, s Im G/s after sin = 2 s c, cos = 1 - 2 s^2, pbar_theta = "
        f"s Ptil (cancelled); affinity, monotonicity, tail integral; numeric: {det_s['points']} seeded points, 50 "
        f"digits, max relative difference from integrand_grouped {det_s['numeric vs integrand_grouped (relative, 50 digits)']:.1e}",
        det_s))
    return res


def module() -> str:
    names = {theta: "theta", pth: "ptheta", Psi: "Psi", m: "m", gamma: "gamma", delta: "delta"}
    pr = HeyokaPrinter(names)
    parts = [function_source(
        "leading_integrand", ["theta", "ptheta", "Psi", "m", "gamma", "delta"], integrand_grouped(), pr,
        "N with psi_u = lambdabar Int_0^inf N dt / tan(theta_t/2) + O(lambdabar^2) at mu = 2 lambdabar, along the "
        "lambdabar = 0 homoclinic orbit (Psi' = 1/(1 + cos theta), Psi(0) = 0 at the turning point).")]
    return module_source("Leading term of the separatrix splitting at mu = 2 lambdabar.", "splitting.py",
                         parts)


# ==============================================================================================================
# S rigorously.  The phase in closed form, the integrand in a form without cancellation, ball code.
# ==============================================================================================================
# Along the regular closed form (derive/homoclinic.py, regular_closed_form) put
#     s = sin(theta0/2) = A sech(kappa t)/sqrt(D),  c = cos(theta0/2) = sqrt(1 - s^2),  TH = tanh(kappa t),
#     D = 1 - omega TH^2  (omega = 1 - k),  A^2 = (1 - u_+)/2.
# Then sin(theta0) = 2 s c, cos(theta0) = 1 - 2 s^2, tan(theta0/2) = s/c and pbar_theta0 = s Ptil with
# Ptil = -2 (1 - omega) kappa TH/(D c): every piece of G is s times a function that stays bounded as t -> inf,
# so Re G/s, Im G/s need no cancellation, and a tail bound follows from s <= A sech(kappa t)/sqrt(1 - omega).
# The phase Psi = Int_0^t dt/(1 + cos theta0) = Int dt/(2 c^2) is elementary: with P = 1 - A^2 = (1 + u_+)/2
# and q = A^2 - omega (> 0), partial fractions in TH give
#     Psi(t) = t/2 + B atan(rho TH),   B = A^2/(2 kappa sqrt(P q)),   rho = sqrt(q/P).
s_, c_, TH_, D_ = sp.symbols("s c TH D", positive=True)
t_ = sp.symbols("t", real=True)
_Pp, _qp, _kp = sp.symbols("P q kappa", positive=True)


def orbit_constants():
    """(u_+, omega = 1 - k, kappa, A, B, rho, P, q) in (m, gamma), without division by gamma (regular_constants;
    q in the factored form q = (1 - u_+)(1 + r)/(2 w), r = sqrt(1 + gamma m^2), w = 1 + 2 gamma + r, checked
    equal to A^2 - omega in phase_checks)."""
    up, omk, kap = homoclinic.regular_constants()
    r_ = sp.sqrt(1 + gamma * m**2)
    w = 1 + 2 * gamma + r_
    A2 = (1 - up) / 2
    P = (1 + up) / 2
    q = (1 - up) * (1 + r_) / (2 * w)
    return up, omk, kap, sp.sqrt(A2), A2 / (2 * kap * sp.sqrt(P * q)), sp.sqrt(q / P), P, q


def phase_closed_form(t=t_):
    """Psi(t) = t/2 + B atan(rho tanh(kappa t)) in (t, m, gamma)."""
    _, _, kap, _, B, rho, _, _ = orbit_constants()
    return t / 2 + B * sp.atan(rho * sp.tanh(kap * t))


def phase_checks():
    """(ok, details).  Symbolic: (i) Psi' = 1/(1 + cos theta0) along regular_closed_form, as a rational identity in
    TH = tanh(kappa t) with P, q, kappa free positive symbols (u_+ = 2P - 1, omega = 1 - P - q); (ii) q of
    orbit_constants equals A^2 - omega = (1 - u_+)/2 - omega for m, gamma > 0; (iii) at gamma = 0 the constants
    are finite with no division by gamma: omega = 0, P = m^2/4, q = 1 - m^2/4, B = 1 (the Kirchhoff phase
    Psi = t/2 + atan(rho tanh(kappa t))); Psi(0) = 0 and Psi is odd."""
    A2 = 1 - _Pp
    B = A2 / (2 * _kp * sp.sqrt(_Pp) * sp.sqrt(_qp))
    Ps = t_ / 2 + B * sp.atan(sp.sqrt(_qp) / sp.sqrt(_Pp) * sp.tanh(_kp * t_))
    reg = homoclinic.regular_closed_form(t_, 2 * _Pp - 1, 1 - _Pp - _qp, _kp)
    T = sp.symbols("T", real=True)
    d = (sp.diff(Ps, t_) - 1 / (1 + reg[2])).subs(sp.tanh(_kp * t_), T).subs(sp.cosh(_kp * t_), 1 / sp.sqrt(1 - T**2))
    ident = sp.cancel(sp.together(d))
    up, omk, kap, A, Bc, rho, P, q = orbit_constants()
    mp_, gp_ = sp.symbols("m_p gamma_p", positive=True)
    dq = sp.simplify((q - ((1 - up) / 2 - omk)).subs({m: mp_, gamma: gp_}))
    at0 = {k: sp.simplify(v.subs(gamma, 0).subs(m, mp_)).subs(mp_, m) for k, v in (("omega", omk), ("P", P), ("q", q), ("kappa", kap),
                                                         ("B", Bc), ("rho", rho))}
    kir = {"omega": 0, "P": m**2 / 4, "q": 1 - m**2 / 4, "B": 1}
    d0 = [sp.simplify(at0[k] - v) for k, v in kir.items()]
    Psi_full = phase_closed_form()
    odd = sp.simplify(Psi_full + Psi_full.subs(t_, -t_)) == 0 and Psi_full.subs(t_, 0) == 0
    ok = ident == 0 and dq == 0 and all(x == 0 for x in d0) and odd
    return ok, {"Psi' - 1/(1 + cos theta0) (rational in tanh)": fmt(ident), "q - (A^2 - omega)": fmt(dq),
                "gamma = 0 constants": {k: fmt(v) for k, v in at0.items()},
                "gamma = 0 minus Kirchhoff values": [fmt(x) for x in d0], "Psi odd, Psi(0) = 0": odd,
                "formula": "Psi(t) = t/2 + B atan(rho tanh(kappa t)), B = A^2/(2 kappa sqrt(P q)), rho = sqrt(q/P), "
                           "P = (1 + u_+)/2, q = (1 - u_+)(1 + r)/(2 w)"}


def scaled_forcing(omega=None, kappa=None):
    """(Re G/s, Im G/s) in (s, c, TH, D, m, gamma, delta, omega, kappa): G of forcing() on the closed form, with
    the factor s = sin(theta0/2) taken out (module comment above).  Both stay bounded as t -> inf."""
    om = sp.Symbol("omega", positive=True) if omega is None else omega
    kp = sp.Symbol("kappa", positive=True) if kappa is None else kappa
    Pt = -2 * (1 - om) * kp * TH_ / (D_ * c_)
    Q = (1 / c_**2 + Pt**2) / (8 * c_**2)  # J/sin^2(theta) = (tan^2(theta/2) + pbar_theta^2)/(2 sin^2)
    cth = 1 - 2 * s_**2
    nr = -Pt * (Q + delta / m**2)
    ni = -(Q * cth + 4 * gamma * s_**2 * c_**2 / m**2 + delta / m**2 + (cth + gamma * (2 * cth**2 - 1)) / m**2) / c_
    return nr, ni


def orbit_point(t=t_):
    """(s, c, TH, D, Psi) at time t in (t, m, gamma) (closed forms above)."""
    _, omk, kap, A, _, _, _, _ = orbit_constants()
    TH = sp.tanh(kap * t)
    D = 1 - omk * TH**2
    s = A / sp.cosh(kap * t) / sp.sqrt(D)
    return s, sp.sqrt(1 - s**2), TH, D, phase_closed_form(t)


def integrand_ball_form(nr=None, ni=None):
    """N(t; m, gamma, delta) = s (cos(Psi) Im G/s - sin(Psi) Re G/s) along the closed form: the integrand of S in
    the form that is emitted as ball code (`nr`, `ni` override Re G/s, Im G/s: tests mutate them)."""
    _, omk, kap, _, _, _, _, _ = orbit_constants()
    if nr is None or ni is None:
        nr0, ni0 = scaled_forcing(omk, kap)
        nr = nr0 if nr is None else nr
        ni = ni0 if ni is None else ni
    s, c, TH, D, Ps = orbit_point()
    sub = {s_: s, c_: c, TH_: TH, D_: D}
    return s * (sp.cos(Ps) * ni.subs(sub) - sp.sin(Ps) * nr.subs(sub))


def branch_arguments(expr, var=t_):
    """The arguments of every square root (kind 'sqrt': analytic where Re > 0) and atan (kind 'atan': analytic
    where |Im| < 1) in expr that depend on `var`, in a stable order: what acb.integral must check (the `analytic`
    flag) before it may use an evaluation on a complex ball.  Sufficient conditions, read off the tree."""
    out = []
    for node in sp.preorder_traversal(expr):
        if var not in node.free_symbols:
            continue
        if node.is_Pow and node.exp.is_Rational and node.exp.q == 2:
            item = ("sqrt", node.base)
        elif isinstance(node, sp.atan):
            item = ("atan", node.args[0])
        elif isinstance(node, sp.Function) and not isinstance(node, (sp.sin, sp.cos, sp.tanh, sp.cosh, sp.sinh,
                                                                       sp.exp)):
            raise TypeError(f"no analyticity rule for {type(node).__name__}")
        else:
            continue
        if item not in out:
            out.append(item)
    return sorted(out, key=lambda kv: (kv[0], sp.default_sort_key(kv[1])))


def s_form_checks(n=60, seed=20):
    """(ok, details).  Symbolic: (i) s Re G/s, s Im G/s of scaled_forcing equal forcing() after sin theta = 2 s c,
    cos theta = 1 - 2 s^2, pbar_theta = s Ptil, c = sqrt(1 - s^2); (ii) pbar_theta of regular_closed_form equals
    s Ptil with s = sin(theta/2) there; (iii) N is affine in delta (d^2 N/d delta^2 = 0; the orbit and Psi do not
    depend on delta); (iv) s^2 = A^2 (1 - TH^2)/(1 - omega TH^2) decreases in TH^2 (derivative -A^2 (1 - omega)/D^2),
    so s(t) <= s(T) for t >= T; (v) d/dT [(2/kappa) atan(exp(-kappa T))] = -sech(kappa T) (the tail integral of
    the majorant).  Numeric: N of integrand_ball_form equals integrand_grouped on regular_closed_form at n seeded
    points (t, m, gamma, delta), 50 digits."""
    gr, gi = forcing()
    om, kp = sp.symbols("omega kappa", positive=True)
    nr, ni = scaled_forcing(om, kp)
    Pt = -2 * (1 - om) * kp * TH_ / (D_ * c_)
    sub = {sp.sin(theta): 2 * s_ * c_, sp.cos(theta): 1 - 2 * s_**2, pth: s_ * Pt}
    cs = {c_: sp.sqrt(1 - s_**2)}
    d1 = sp.cancel(sp.together((sp.expand_trig(gr).subs(sub) - s_ * nr).subs(cs)))
    d2 = sp.cancel(sp.together((sp.expand_trig(gi).subs(sub) - s_ * ni).subs(cs)))
    # (ii) with free constants
    upx, omx, kx, tt = sp.symbols("u_x omega_x kappa_x tt", positive=True)
    reg = homoclinic.regular_closed_form(tt, upx, omx, kx)
    s_reg = sp.sin(reg[0] / 2)
    c_reg = sp.sqrt(1 - s_reg**2)
    th = sp.tanh(kx * tt)
    Dx = 1 - omx * th**2
    d3 = sp.simplify(reg[1] - s_reg * (-2 * (1 - omx) * kx * th / (Dx * c_reg)))
    N = integrand_ball_form()
    aff = sp.simplify(sp.diff(N, delta, 2)) == 0
    A2, TT = sp.symbols("A2 TT", positive=True)
    s2 = A2 * (1 - TT) / (1 - om * TT)
    d4 = sp.factor(sp.diff(s2, TT))
    mono = sp.simplify(d4 + A2 * (1 - om) / (1 - om * TT) ** 2) == 0
    Tt = sp.symbols("T_t", positive=True)
    d5 = sp.simplify((sp.diff(2 / kp * sp.atan(sp.exp(-kp * Tt)), Tt) + 1 / sp.cosh(kp * Tt)).rewrite(sp.exp))
    # numeric: against the leading-term integrand on the regular closed form
    up, omk, kap = homoclinic.regular_constants()
    th0, pt0 = homoclinic.regular_closed_form(t_, up, omk, kap)[:2]
    Psi_q = sp.Symbol("Psi_q")
    old = integrand_grouped().subs(Psi, Psi_q).subs({theta: th0, pth: pt0}).subs(Psi_q, phase_closed_form())
    f_new = sp.lambdify([t_, m, gamma, delta], N, "mpmath")
    f_old = sp.lambdify([t_, m, gamma, delta], old, "mpmath")
    rng = random.Random(seed)
    worst = 0.0
    with mpmath.workdps(50):
        for i in range(n):
            g = mpmath.mpf(0) if i % 6 == 0 else mpmath.mpf(rng.uniform(0, 4))
            mv = mpmath.mpf(rng.uniform(0.3, 0.97)) * 2 * mpmath.sqrt(1 + g)
            tv = mpmath.mpf(rng.uniform(-25, 25))
            dv = mpmath.mpf(rng.uniform(0, 3))
            a, b = f_new(tv, mv, g, dv), f_old(tv, mv, g, dv)
            worst = max(worst, float(abs(a - b) / max(1, abs(b))))
    ok = d1 == 0 and d2 == 0 and d3 == 0 and aff and mono and d5 == 0 and worst < 1e-40
    return ok, {"Re G - s Re G/s": fmt(d1), "Im G - s Im G/s": fmt(d2), "pbar_theta - s Ptil": fmt(d3),
                "N affine in delta": aff, "d(s^2)/d(TH^2)": fmt(d4), "s decreasing for t > 0": mono,
                "tail integral of sech": fmt(d5), "numeric vs integrand_grouped (relative, 50 digits)": worst,
                "points": n, "branch arguments": [[k, fmt(v)] for k, v in branch_arguments(N)]}


tau_ = sp.symbols("tau", nonnegative=True)


def integrand_tau(nr=None, ni=None):
    """The integrand of S in the variable tau = kappa t: S = Int_0^inf N(tau/kappa)/kappa dtau.  In tau the decay
    rate is 1 for every (m, gamma), so ball-valued parameters widen only the constants, never exp(-kappa t) (the
    form used by the enclosure and the parameter-box theorem)."""
    _, _, kap, _, _, _, _, _ = orbit_constants()
    e = integrand_ball_form(nr, ni).subs(t_, tau_ / kap) / kap
    if t_ in e.free_symbols:
        raise AssertionError("t left in the tau form")
    return e


TAU_T = sp.Symbol("tau_T", positive=True)


def tail_quantities(tT=TAU_T):
    """Bounds on the tail tau >= tau_T > 0 (t >= T = tau_T/kappa), valid for every parameter in the balls they are
    evaluated on: (s_up, c_lo, tanh(tau_T), 1 - omega, D_up, majorant) with s <= s_up = A sech(tau_T)/sqrt(1 -
    omega) (s decreasing, D >= 1 - omega), c >= c_lo = sqrt(1 - s_up^2), TH in [tanh(tau_T), 1], D in [1 - omega,
    D_up], D_up = 1 - omega tanh^2(tau_T) (D decreasing), and Int_T^inf s dt <= majorant = 2 A atan(exp(-tau_T))/
    (kappa sqrt(1 - omega)) (s_form_checks (iv), (v)).  The ranges are kept narrow on purpose: a ball of large
    relative width loses its sign under squaring (mid-radius arithmetic)."""
    _, omk, kap, A, _, _, _, _ = orbit_constants()
    s_up = A / sp.cosh(tT) / sp.sqrt(1 - omk)
    return [s_up, sp.sqrt(1 - s_up**2), sp.tanh(tT), 1 - omk, 1 - omk * sp.tanh(tT) ** 2,
            2 * A * sp.atan(sp.exp(-tT)) / (kap * sp.sqrt(1 - omk))]


BALL_ARGS = ["tau", "m", "gamma", "delta"]


def ball_module(nr=None, ni=None, gradient=True) -> str:
    """generated/splitting_ball.py (python-flint balls; BallPrinter, exact rationals only).  `nr`, `ni` replace
    Re G/s, Im G/s in (s, c, TH, D, m, gamma, delta, omega, kappa) (tests generate mutated modules this way);
    gradient=False leaves out integrand_gradient (only the box theorem needs it; saves ~5 s)."""
    from .codegen import BallPrinter, cse_function_source

    om, kp = sp.symbols("omega kappa", positive=True)
    nr0, ni0 = scaled_forcing(om, kp)
    nr = nr0 if nr is None else nr
    ni = ni0 if ni is None else ni
    up, omk, kap, A, Bc, rho, P, q = orbit_constants()
    N = integrand_tau(nr.subs({om: omk, kp: kap}), ni.subs({om: omk, kp: kap}))
    grad = [sp.diff(N, v) for v in (m, gamma, delta)] if gradient else None
    branches = branch_arguments(N, tau_)
    Tsym = TAU_T
    names = {t_: "t", tau_: "tau", m: "m", gamma: "gamma", delta: "delta", s_: "s", c_: "c", TH_: "TH", D_: "D",
             Tsym: "tau_T"}
    pr = BallPrinter(names)
    tail_nr, tail_ni = nr.subs({om: omk, kp: kap}), ni.subs({om: omk, kp: kap})
    parts = [
        cse_function_source("orbit_constants", ["m", "gamma"], [up, omk, kap, A, Bc, rho, P, q], pr,
                            "(u_+, omega = 1 - k, kappa, A, B, rho, P, q) of the lambdabar = 0 homoclinic orbit "
                            "(derive/splitting.py orbit_constants; no division by gamma)."),
        cse_function_source("phase", ["t", "m", "gamma"], phase_closed_form(), pr,
                            "Psi(t) = t/2 + B atan(rho tanh(kappa t)) = Int_0^t dt/(1 + cos theta0) (report entry "
                            "splitting_phase_closed_form)."),
        cse_function_source("integrand", BALL_ARGS, N, pr,
                            "N(tau/kappa)/kappa: S = Int_0^inf of it dtau, tau = kappa t (report entries "
                            "splitting_leading_term, splitting_integrand_ball).  Same source for arb and acb; with "
                            "acb, check branch_arguments first."),
        *([cse_function_source("integrand_gradient", BALL_ARGS, grad, pr,
                               "d/d(m, gamma, delta) of integrand at fixed tau (for the parameter-box theorem).")]
          if gradient else []),
        cse_function_source("branch_arguments", ["tau", "m", "gamma"], [e for _, e in branches], pr,
                            "Arguments of the t-dependent sqrt/atan of integrand, kinds in BRANCH_KINDS: N is "
                            "analytic on a complex ball where every 'sqrt' argument has Re > 0 and every 'atan' "
                            "argument |Im| < 1."),
        cse_function_source("tail_factors", ["s", "c", "TH", "D", "m", "gamma", "delta"], [tail_nr, tail_ni], pr,
                            "(Re G/s, Im G/s): |N| <= s (|Re G/s| + |Im G/s|) (evaluate on the tail's ranges)."),
        cse_function_source("tail_quantities", ["tau_T", "m", "gamma"], tail_quantities(Tsym), pr,
                            "(s_up, c_lo, tanh(tau_T), 1 - omega, D_up, majorant of Int_T^inf s dt) on tau >= tau_T "
                            "(derive/splitting.py tail_quantities)."),
        cse_function_source("tan_half_turn", ["m", "gamma"], sp.sqrt((1 - up) / (1 + up)), pr,
                            "tan(theta_t/2) at the turning point (psi_u = lambdabar S/tan(theta_t/2))."),
    ]
    return module_source("Ball-arithmetic (python-flint arb/acb) code for the splitting integral S at mu = 2 "
                         "lambdabar.", "splitting.py", parts,
                         {"BRANCH_KINDS": tuple(k for k, _ in branches)}, lib="arb")
