"""The splitting for a > 2b (mu > 2 lambdabar: the tilted saddle-focus) and one leading-order picture of W^u on
Sigma for all a >= 2b, derived (docs/nonintegrability.md).

Result.  With nu = mu - 2 lambdabar (= (a - 2b) eps^2 along eq:condition_unperturbed_1) and S the integral of
derive/splitting.py (report entry splitting_leading_term):

    D(psi) = theta_u(psi) - theta_u(-psi) = 2 s1 sin(psi) + ...,
    s1 = sqrt(nu) lambdabar S / (V'(theta_t) (1 + cos theta_t)),  i.e.  s1/eps^3 -> b sqrt(a - 2b) S/(V'(theta_t)(1 + u_+)),

V the potential of eq:eq_oscillator, theta_t the turning point (cos theta_t = u_+).  The same S governs a = 2b
(psi_u = lambdabar S/tan(theta_t/2)).

Route 1 (Mel'nikov for the second integral, body frame).  In the body frame, along x' = J(lambda) grad H,
    d(n.m)/dt = lambda m.(e3 x v) = lambda e3.(v x m),   v = grad_n H          (lorentz_identity, exact)
and n.m is the integral of the lambda = 0 rod (eq:int2 at lambda = 0).  Take as unperturbed system lambda = 0 with
the force tilted from the field by alpha0, tan(alpha0) = sqrt(nu) (the tilt of the saddle: the radicand
mu - 2 lambdabar pbar_psi at the saddle), and lambda = lambdabar/m^4 as the perturbation.  Then, to first order,
Delta(n.m) = lambda E . Int W dt with E the (fixed) field direction and W = R^T (v x m) the spatial vector along
the unperturbed homoclinic orbit.  Its component along the force vanishes (n.(v x m) = d/dt |m|^2/2,
lorentz_identity), so Delta(n.m) = lambda sin(alpha0) e_perp . Int W dt: a first harmonic of the launch phase, of
order lambdabar sqrt(nu) = O(eps^3).  At leading order W is evaluated along the vertical orbit (mu = lambdabar = 0,
transverse_integrand: independent of the twist angle phi for the isotropic rod); Int W_x = 0 by parity, and
    W_y + m^2 N = d/dt [A(theta) sin Psi - m^2 pbar_theta cos Psi]    on the energy level (exact_derivative),
A = -(1 - cos)(gamma cos (1 + cos) + 2 cos + 2 m^2)/(2 sin), and F -> 0 at both ends: Int_R W_y dt = -2 m^2 S.
Finally Delta(n.m) = (dI/dtheta) D on Sigma with dI/dtheta = -V'(theta_t)(1 + cos theta_t)/m^2
(turning_point_derivative), and the chart angle psi on Sigma is the orbit's azimuth relative to the field's
(psi = chi - beta - pi at leading order): D(psi) = 2 s1 sin(psi) with s1 above.

Route 2 (the blow-up of derive/splitting.py with the tilt; one picture for all a >= 2b).  Put
mu = 2 lambdabar + lambdabar^2 nut, pbar_psi = 1 + lambdabar nut/2 - lambdabar J: then exactly
Hbar = H0 + lambdabar (K1 + nut omega/2) + lambdabar^2 K2' (blowup_with_tilt), so the transverse-force equation
zeta' = i omega zeta + lambdabar G of derive/splitting.py is unchanged at first order, and the tilted saddle adds
the homogeneous solutions (sqrt(nu)/lambdabar) e^{i(Psi + phi)} (phi: the launch phase).  At Sigma (Psi = 0),
in chart units (transverse force rho e^{i psi}):
    rho sin(psi) = lambdabar^2 S + sqrt(nu) sin(phi),    rho cos(psi) = lambdabar tan(theta_t/2) + sqrt(nu) cos(phi),
and the energy fixes theta (V'(theta) = tan(theta/2)/(1 + cos) - (1 + gamma cos) sin/m^2, potential_slope):
    theta_u = theta_t + sqrt(nu) cos(phi) + sqrt(nu) lambdabar S sin(phi)/(V'(theta_t)(1 + cos theta_t)).
So W^u on Sigma is a circle of radius sqrt(nu) about the a = 2b point in the transverse-force plane.  For
sqrt(nu) >> lambdabar, psi -> phi and the odd part of theta_u(psi) is Route 1's D (the two routes agree).
Symmetric (primary) homoclinic orbits are the points with sin(psi) = 0: sin(phi) = -lambdabar^2 S/sqrt(nu), so
they exist iff sqrt(nu) >= lambdabar^2 |S|, come in pairs whose launch phases differ by
pi - 2 asin(lambdabar^2 |S|/sqrt(nu)), and merge at nu* = lambdabar^4 S^2; for sqrt(nu) << lambdabar,
sin(psi) = psi_0 + (sqrt(nu)/(lambdabar tan(theta_t/2))) sin(phi), psi_0 = lambdabar S/tan(theta_t/2).

What is symbolic: every identity named above (derive_all).  What is formal: the first-order expansions (Mel'nikov
in lambda; the blow-up at first order in lambdabar with nut = nu/lambdabar^2 fixed) and the leading-order geometry
(psi = chi - beta - pi); checked against the measured splitting in magrod (magrod/separatrix/generic.py)."""
from __future__ import annotations

from functools import lru_cache

import sympy as sp

from . import homoclinic
from . import numeric_scale as ns
from .codegen import BallPrinter, cse_function_source, module_source
from .model import X, euler_rotation, gradient, phi, psi, structure_matrix, theta
from .paper import delta, gamma, lambar, m, mu, pps, pth
from .reduction import reduced_hamiltonians, trig_normal_form
from .results import DISAGREES, HOLDS, Result, fmt
from .splitting import _half_powers, blowup_parts, integrand_grouped, lp, r as r_blow
from .splitting import Psi as PsiS

lam_b = sp.Symbol("lambda_b", real=True)  # the body lambda (= lambdabar/m^4 at the numeric scale)
nut = sp.Symbol("nut", positive=True)  # nu/lambdabar^2


def _body(lam_value):
    H = ns.body_hamiltonian()
    rhs = list(sp.expand(structure_matrix(lam_value) * gradient(H)))
    return H, rhs


def lorentz_identity():
    """(d(n.m)/dt - lambda m.(e3 x v), d(|m|^2/2)/dt - n.(v x m)) along x' = J(lambda) grad H: both 0."""
    H, rhs = _body(lam_b)
    mv, nv, ev = sp.Matrix(X[0:3]), sp.Matrix(X[3:6]), sp.Matrix(X[6:9])
    v = sp.Matrix([sp.diff(H, x) for x in X[3:6]])
    dI = sum(sp.diff(nv.dot(mv), x) * f for x, f in zip(X, rhs))
    dm2 = sum(sp.diff(mv.dot(mv) / 2, x) * f for x, f in zip(X, rhs))
    return sp.expand(dI - lam_b * mv.dot(ev.cross(v))), sp.expand(dm2 - nv.dot(v.cross(mv)))


@lru_cache(maxsize=None)
def transverse_integrand(twist=phi):
    """W = R(theta, psi, twist)^T (v x m) (spatial components) on the chart at mu = lambdabar = 0, pbar_psi = 1."""
    sub0 = {mu: 0, lambar: 0, pps: 1, phi: twist}
    xs = [e.subs(sub0) for e in ns.euler_to_body()]
    H = ns.body_hamiltonian()
    mv = sp.Matrix(xs[0:3])
    v = sp.Matrix([sp.diff(H, x) for x in X[3:6]]).subs(dict(zip(X, xs)))
    return sp.Matrix([sp.simplify(w) for w in euler_rotation(theta, psi, twist).T * v.cross(mv)])


def exact_derivative():
    """Residual of d/dt[A sin Psi - m^2 pbar_theta cos Psi] - (W_y + m^2 N) along theta' = pbar_theta,
    pbar_theta' = -V'(theta), Psi' = 1/(1 + cos theta) with pbar_theta^2 = 2 (h - V) (zero iff the identity holds),
    and A."""
    W = transverse_integrand(sp.Integer(0))
    Wy = W[1]
    N = integrand_grouped().subs(PsiS, psi)
    V = homoclinic.potential()
    h = homoclinic.roots_and_k()[0]
    c, s = sp.cos(theta), sp.sin(theta)
    A = -(1 - c) * (gamma * c * (1 + c) + 2 * c + 2 * m**2) / (2 * s)
    F = A * sp.sin(psi) - m**2 * pth * sp.cos(psi)
    dF = sp.diff(F, theta) * pth + sp.diff(F, pth) * (-sp.diff(V, theta)) + sp.diff(F, psi) / (1 + c)
    res = sp.expand(dF - Wy - m**2 * N)
    P = sp.Poly(res, pth)
    red = sum(cf * (2 * (h - V)) ** (k // 2) * pth ** (k % 2) for (k,), cf in P.terms())
    return trig_normal_form(sp.expand(red)), A


def parity_checks():
    """W_x odd and W_y even in t (theta even, pbar_theta and Psi odd): Int W_x = 0; W independent of the twist."""
    W = transverse_integrand(phi)
    W0 = transverse_integrand(sp.Integer(0))
    indep = all(sp.simplify(a - b) == 0 for a, b in zip(W, W0))
    Wx, Wy = W0[0], W0[1]
    flip = {pth: -pth, psi: -psi}
    odd = trig_normal_form(sp.expand(Wx + Wx.subs(flip, simultaneous=True))) == 0
    even = trig_normal_form(sp.expand(Wy - Wy.subs(flip, simultaneous=True))) == 0
    return indep, odd, even


def turning_point_derivative():
    """d(n.m)/dtheta on Sigma = {pbar_theta = 0} at fixed psi and Hbar, at mu = lambdabar = 0, pbar_psi = 1, minus
    -V'(theta)(1 + cos theta)/m^2 (zero iff the identity holds); and n.m on the chart at mu = lambdabar = 0."""
    xs = ns.euler_to_body()
    I = sp.Matrix(xs[0:3]).dot(sp.Matrix(xs[3:6]))
    _, _, Hbar, _ = reduced_hamiltonians()
    at = {mu: 0, lambar: 0, pth: 0, pps: 1}
    I0 = sp.simplify(I.subs(at))
    dI = sp.diff(I, theta) - sp.diff(I, pps) * sp.diff(Hbar, theta) / sp.diff(Hbar, pps)
    dI = dI.subs(at)
    V = homoclinic.potential()
    target = -sp.diff(V, theta) * (1 + sp.cos(theta)) / m**2
    return trig_normal_form(sp.expand(sp.together(dI - target))), I0


def potential_slope():
    """V'(theta) - [tan(theta/2)/(1 + cos theta) - (1 + gamma cos theta) sin(theta)/m^2] (zero)."""
    V = homoclinic.potential()
    c, s = sp.cos(theta), sp.sin(theta)
    return trig_normal_form(sp.expand(sp.diff(V, theta) - (s / (1 + c) / (1 + c) - (1 + gamma * c) * s / m**2)))


def blowup_with_tilt():
    """Hbar(mu = 2 lambdabar + lambdabar^2 nut, pbar_psi = 1 + lambdabar nut/2 - lambdabar r^2/2) minus
    (H0 + lambdabar (K1 + nut omega/2) + lambdabar^2 K2') with K2' = K2 with J -> J - nut/2 in the J terms
    (trig normal form; zero iff exact)."""
    _, _, Hbar, _ = reduced_hamiltonians()
    Hc = _half_powers(Hbar.subs(mu, 2 * lambar + lambar**2 * nut).subs(lambar, lp)
                      .subs(pps, 1 + lp * nut / 2 - lp * r_blow**2 / 2))
    x, y = sp.symbols("x y", real=True)
    H0, K1, _ = blowup_parts()
    J = (x**2 + y**2) / 2
    c, s = sp.cos(theta), sp.sin(theta)
    K2p = (J - nut / 2) ** 2 / (2 * s**2) + gamma * s**2 * x**2 / (2 * m**2) + delta * (J - nut / 2) / m**2
    Hb = (H0 + lp * (K1 + nut / (2 * (1 + c))) + lp**2 * K2p).subs({x: r_blow * sp.cos(psi), y: r_blow * sp.sin(psi)})
    return trig_normal_form(sp.expand(Hc - Hb))


def denominator():
    """V'(theta_t) (1 + cos theta_t) in (m, gamma) (cos theta_t = u_+, sin theta_t = sqrt(1 - u_+^2) > 0)."""
    up, _, _ = homoclinic.regular_constants()
    V = homoclinic.potential()
    e = (sp.diff(V, theta) * (1 + sp.cos(theta)))
    e = sp.expand_trig(e).subs({sp.sin(theta): sp.sqrt(1 - up**2), sp.cos(theta): up})
    return e


def derive_all():
    res = []
    d1, d2 = lorentz_identity()
    res.append(Result(
        "generic_lorentz_identity", "eq:magnetic_force (the lambda e3 x v term), eq:int2 at lambda = 0",
        "Along x' = J(lambda) grad H: d(n.m)/dt = lambda m.(e3 x v) and d(|m|^2/2)/dt = n.(v x m) (v = grad_n H)",
        HOLDS if d1 == 0 and d2 == 0 else DISAGREES, "symbolic: expanded differences are 0 (body frame, numeric scale)",
        {"residual d(n.m)/dt": fmt(d1), "residual d|m|^2/2/dt": fmt(d2)}))
    indep, odd, even = parity_checks()
    res.append(Result(
        "generic_transverse_integrand", "sec:homoclinic (the lambdabar = 0 orbit), eq:canonical_magnetic",
        "W = R^T (v x m) along the vertical homoclinic orbit: independent of the twist angle (isotropic rod), W_x odd "
        "and W_y even in t, so Int W_x dt = 0",
        HOLDS if indep and odd and even else DISAGREES, "symbolic: trig normal forms of the differences",
        {"W": [fmt(w) for w in transverse_integrand(sp.Integer(0))], "independent of phi": indep, "W_x odd": odd,
         "W_y even": even}))
    r, A = exact_derivative()
    res.append(Result(
        "generic_exact_derivative", "eq:condition_unperturbed_1 (a > 2b): the same integral S",
        "W_y + m^2 N = d/dt [A(theta) sin Psi - m^2 pbar_theta cos Psi] on the homoclinic level, A = -(1 - cos)"
        "(gamma cos (1 + cos) + 2 cos + 2 m^2)/(2 sin) -> 0 at theta = 0: Int_R W_y dt = -2 m^2 S",
        HOLDS if r == 0 else DISAGREES,
        "symbolic: d/dt along theta' = pbar_theta, pbar_theta' = -V', Psi' = 1/(1 + cos), pbar_theta^2 = 2 (h - V); "
        "trig normal form of the residual is 0",
        {"residual": fmt(r), "A": fmt(A)}))
    dI, I0 = turning_point_derivative()
    res.append(Result(
        "generic_turning_point", "eq:eq_oscillator (the turning point), Sigma = {pbar_theta = 0}",
        "On Sigma at fixed psi and energy, d(n.m)/dtheta = -V'(theta)(1 + cos theta)/m^2 at mu = lambdabar = 0 "
        "(n.m = pbar_psi/m^2 = 1/m^2 there)",
        HOLDS if dI == 0 and sp.simplify(I0 - 1 / m**2) == 0 else DISAGREES,
        "symbolic: implicit derivative along Hbar = h, trig normal form of the difference is 0",
        {"residual": fmt(dI), "n.m on the chart": fmt(I0)}))
    dV = potential_slope()
    dB = blowup_with_tilt()
    res.append(Result(
        "generic_blowup_with_tilt", "eq:full_ham_nondim, eq:condition_unperturbed_1 (a >= 2b)",
        "With mu = 2 lambdabar + lambdabar^2 nut, pbar_psi = 1 + lambdabar nut/2 - lambdabar J: Hbar = H0 + "
        "lambdabar (K1 + nut/(2(1 + cos))) + lambdabar^2 K2' exactly (the tilt enters the first-order transverse-force "
        "equation only as a homogeneous solution); V'(theta) = tan(theta/2)/(1 + cos) - (1 + gamma cos) sin/m^2",
        HOLDS if dB == 0 and dV == 0 else DISAGREES, "symbolic: trig normal forms of the differences are 0",
        {"blow-up difference": fmt(dB), "V' difference": fmt(dV)}))
    res.append(Result(
        "generic_leading_term", "eq:condition_unperturbed_1 (a > 2b), eq:Mel_ext (second order)",
        "Leading term of the splitting for a > 2b: D(psi) = 2 s1 sin(psi), s1/eps^3 -> b sqrt(a - 2b) S/(V'(theta_t)"
        "(1 + cos theta_t)); one circle picture on Sigma for all a >= 2b (module docstring)",
        HOLDS if all(x == 0 for x in (d1, d2, r, dI, dB, dV)) and indep and odd and even else DISAGREES,
        "symbolic: the identities generic_*; formal: first-order expansions; value compared with the measured "
        "splitting in magrod (magrod.separatrix.generic)",
        {"formula": "s1/eps^3 -> b sqrt(a - 2b) S / (V'(theta_t) (1 + u_+)); S as in splitting_leading_term",
         "circle": "rho e^{i psi} = lambdabar tan(theta_t/2) + i lambdabar^2 S + sqrt(nu) e^{i phi} on Sigma, nu = "
                   "mu - 2 lambdabar; primaries iff sqrt(nu) >= lambdabar^2 |S|, merging at nu* = lambdabar^4 S^2",
         "denominator V'(theta_t)(1 + cos theta_t)": "V'(theta) (1 + cos theta) at cos theta = u_+ (generated "
                                                      "generic_splitting.denominator)"}))
    return res


def ball_module() -> str:
    """generated/generic_splitting.py: the denominator and the transverse integrand W_y (in tau = kappa t) as ball
    code, for the derived coefficient and an independent enclosure of Int W_y = -2 m^2 S."""
    from . import splitting as S

    up, omk, kap, *_ = S.orbit_constants()
    Wy = (transverse_integrand(sp.Integer(0))[1])
    s, c, TH, D, Ps = S.orbit_point(S.t_)
    # W_y in the s-form: sin theta = 2 s c, cos theta = 1 - 2 s^2, pbar_theta = s Ptil (splitting.s_form_checks),
    # cancelled in the symbols s, c first so that no 1 - cos theta is formed (it would lose all digits as s -> 0)
    sy, cy, Ty, Dy, Py = S.s_, S.c_, S.TH_, S.D_, sp.Symbol("Psi_y")
    Pt = -2 * (1 - omk) * kap * Ty / (Dy * cy)
    e = sp.expand_trig(Wy).subs({sp.sin(theta): 2 * sy * cy, sp.cos(theta): 1 - 2 * sy**2, pth: sy * Pt, psi: Py})
    e = sp.expand(e)
    e = sp.cos(Py) * sp.factor(sp.cancel(e.coeff(sp.cos(Py)))) + sp.sin(Py) * sp.factor(sp.cancel(e.coeff(sp.sin(Py))))
    e = e.subs({sy: s, cy: c, Ty: TH, Dy: D, Py: Ps})
    e = e.subs(S.t_, S.tau_ / kap) / kap
    pr = BallPrinter({S.tau_: "tau", m: "m", gamma: "gamma", delta: "delta"})
    parts = [
        cse_function_source("denominator", ["m", "gamma"], denominator(), pr,
                            "V'(theta_t) (1 + cos theta_t) (report entry generic_leading_term)."),
        cse_function_source("transverse_integrand", ["tau", "m", "gamma", "delta"], e, pr,
                            "W_y(tau/kappa)/kappa: Int_R W_y dt = -2 m^2 S (report entry generic_exact_derivative); "
                            "real arguments only (no analyticity guard)."),
    ]
    return module_source("Ball code for the a > 2b splitting coefficient.", "generic_splitting.py", parts,
                         lib="arb")
