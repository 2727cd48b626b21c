"""The prover for a symmetric hyperbolic fixed point of the section map on a given level (issue 27, item 3, the
first half of the route "a hyperbolic periodic orbit of the section map plus a transverse homoclinic point").

What is proved (docs/nonintegrability.md, statement 11): at exact rational (m, mu, gamma, delta, lambdabar) and an
exact level h, the section map P of Sigma+ = {sin psi = 0, d(sin psi)/dt > 0} on {Hbar = h} (the paper's Fig 4
section) has a fixed point x0 = (theta*, psi = 0, pbar_theta = 0, pbar_psi*) on Fix(R), and DP(x0) is hyperbolic
(real eigenvalues mu, 1/mu, |mu| > 1).  Only the chart system is used: the orbit stays in theta in [0.38, 1.7]
(Fig 4(a)), far from the chart's singular set sin theta = 0, so no lift to the body frame is needed.

Method (every decision rigorous; the float search only chooses where to look):
  1. level      interval Newton in pbar_psi for Hbar(theta, 0, 0, pbar_psi) = h over the theta-box Theta =
                [theta_c - r, theta_c + r] (and at theta_c): a unique pbar_psi(theta) in the box, inside N
  2. flight     the chart box Q = Theta x {0} x {0} x N (and the thin set at theta_c) by the C^1 Lohner
                integrator (taylor.py) with exact steps, in two phases: on [0, t1] d(sin psi)/dt > 0 on every
                a priori enclosure (x0 is a positive crossing, and sin psi > 0 just after), on [t1, t_a] every
                a priori enclosure has sin psi > 0 or d(sin psi)/dt < 0 (no positive crossing); guards: theta in
                (0, pi) and the radicand mu - 2 lambdabar pbar_psi > 0 (the chart field is analytic there)
  3. crossing   sin psi = 0 crossed once in the last step, with d(sin psi)/dt < 0 (a negative crossing:
                psi = pi, the half-way point of the orbit), interval Newton for the time
  4. Fix(R)     F(theta) = pbar_theta at that crossing: interval Newton theta_c - F(theta_c)/F'(Theta) inside
                Theta, with F' = e_ptheta . (I - f grad(sin psi)^T / (grad(sin psi) . f)) W t_theta,
                t_theta = (1, 0, 0, -dHbar/dtheta / dHbar/dpbar_psi): exactly one theta* in Theta whose orbit meets
                Fix(R) at the crossing
  5. saddle     A = DQ(x0) (section coordinates (theta, pbar_theta) at both ends) over Q; reversibility gives
                DP(x0) = R A^-1 R A, R = diag(1, -1), so det DP(x0) = 1 and tr DP(x0) = 2 (ad + bc)/(ad - bc);
                |tr| > 2 on the enclosure: a saddle
Why this is a fixed point of P: x0 and x1 = Phi_tau(x0) lie on Fix(R), so the orbit is periodic with period
T = 2 tau (Devaney 1976); s(t) = sin psi(t) is odd in t along it (s(-t) = -s(t)), so its crossings at t and -t
have the same direction; there is none positive in (0, tau] (steps 2-3), hence none in (0, T), and t = T is
positive (x0 is): P(x0) = x0 with return time T.  With DQ2 = R DQ^-1 R for the second half (reversibility),
DP(x0) = R A^-1 R A.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from flint import arb, arb_mat, arb_series

from ..core.errors import ParameterError
from ..core.tolerances import FIXED_POINT_SEARCH_TOL, PROOF_STEP_TOL
from ..generated import validated as gen
from . import ball, fields, taylor
from .search import ProofFailure, ProofResult, stored, structural_tests
from .theorem import section_fixed_point_theorem

FORMAT = "magrod-proof-certificate/1"
KIND = "section_fixed_point"
TH, PS, PT, PP = fields.THETA, fields.PSI, fields.PTHETA, fields.PPSI


@dataclass
class FixedPointSettings:
    """Numerical choices (recorded; the verifier replays them).  r: half-width of the theta-box; p_rad: half-width
    of the pbar_psi box of the level's interval Newton; t1: end of the first phase (d sin psi/dt > 0); lead: the
    flight stops this long before the float crossing time, and the crossing step has length 2 lead."""

    prec: int = 128
    order: int = 20
    tol: float = PROOF_STEP_TOL
    r: Fraction = Fraction(1, 10**10)
    p_rad: Fraction = Fraction(1, 10**8)
    t1: Fraction = Fraction(1, 64)
    lead: Fraction = Fraction(1, 256)
    #: half-width of the lambdabar interval carried as a ball through every enclosure (0: the point itself)
    lam_rad: Fraction = Fraction(0)

    def as_json(self) -> dict:
        q = _q
        return {"prec": self.prec, "order": self.order, "tol": repr(self.tol), "r": q(self.r), "p_rad": q(self.p_rad),
                "t1": q(self.t1), "lead": q(self.lead), "lam_rad": q(self.lam_rad), "series_cap": ball.SERIES_CAP}


def parameter_balls(p: fields.ExactParams, lam_rad: Fraction = Fraction(0)) -> tuple:
    """The parameters as balls in generated/validated.py's order; lambdabar widened to [lam - lam_rad, lam + lam_rad]
    (every enclosure computed with it holds for every lambdabar of the interval)."""
    out = list(p.balls())
    if lam_rad:
        out[fields.PARAMS.index("lam")] = ball.interval(p.lam - lam_rad, p.lam + lam_rad)
    return tuple(out)


def interval_settings(lam_rad, base: "FixedPointSettings | None" = None) -> "FixedPointSettings":
    """Settings for a lambdabar interval of half-width lam_rad: the theta-box r = max(r, 8 lam_rad) (theta* moves by
    ~4.4 per unit lambdabar at Fig 4(a), 0.383 -> 0.283 from (a) to (b)) and the level box p_rad = max(p_rad,
    16 (r + lam_rad)) (pbar_psi moves by O(1) per unit theta or lambdabar)."""
    from dataclasses import replace

    st = base or FixedPointSettings()
    w = ball.fraction(lam_rad)
    r = max(st.r, 8 * w)
    return replace(st, lam_rad=w, r=r, p_rad=max(st.p_rad, 16 * (r + w)))


def _mu_lam(pars):
    return pars[fields.PARAMS.index("mu")], pars[fields.PARAMS.index("lam")]


def _q(x) -> str:
    f = ball.fraction(x)
    return f"{f.numerator}/{f.denominator}"


def validate(m, mu, gamma, delta, lam, h) -> tuple[fields.ExactParams, Fraction]:
    """Exact parameters and level, or ParameterError naming the field (finite; m > 0; gamma, delta >= 0; mu > 0;
    |x| <= 1e6)."""
    vals = {}
    for k, v in (("m", m), ("mu", mu), ("gamma", gamma), ("delta", delta), ("lam", lam), ("h", h)):
        try:
            f = ball.fraction(v if not isinstance(v, float) else repr(v))
        except (ValueError, ZeroDivisionError, TypeError):
            raise ParameterError(k, f"must be a finite number (decimal or p/q), got {str(v)[:40]!r}") from None
        if abs(f) > 10**6:
            raise ParameterError(k, f"must satisfy |{k}| <= 1e6, got {v}")
        vals[k] = f
    if vals["m"] <= 0:
        raise ParameterError("m", f"must be > 0, got {m}")
    for k in ("gamma", "delta", "mu"):
        if vals[k] < 0:
            raise ParameterError(k, f"must be >= 0, got {vals[k]}")
    h = vals.pop("h")
    return fields.ExactParams(**vals), h


# --------------------------------------------------------------------------------------------------------------
# float search (heyoka, chart system): the symmetric fixed point of P by 1-D shooting on Fix(R)
# --------------------------------------------------------------------------------------------------------------
def float_fixed_point(p: fields.ExactParams, h: Fraction, theta_guess: float, root: int = -1, window=0.02):
    """theta* near theta_guess (bisection of pbar_theta at the first sin psi = 0 crossing with psi ~ pi, i.e. the
    half-way point), the root index of pbar_psi, the half-return time and the float DP(x0) (central differences)."""
    import heyoka as hy

    from ..chaos.section import solve_p_psi
    from ..core import systems
    from ..core.params import RodParams

    rp = RodParams(*p.floats())
    v = hy.make_vars(*systems.STATE["reduced"])
    ta = systems.taylor(systems.system("reduced"), [1.0, 0.0, 0.0, 1.0], rp.array(),
                        t_events=[hy.t_event(hy.sin(v[PS]), direction=hy.event_direction.negative)],
                        tol=FIXED_POINT_SEARCH_TOL)

    def start(th, pt=0.0):
        roots = solve_p_psi(rp, float(h), th, pt, 0.0)
        x = np.zeros(4)
        x[TH], x[PT], x[PP] = th, pt, roots[root]
        return x

    def half(x):
        ta.time = 0.0
        ta.state[:] = x
        ta.reset_cooldowns()
        oc = ta.propagate_until(200.0)[0]
        if int(oc) != -1:  # -1: the (terminal) event, anything else: the time limit
            raise ProofFailure("search: no negative crossing of sin psi = 0 within t = 200")
        return ta.state.copy(), float(ta.time)

    def F(th):
        return half(start(th))[0][PT]

    a, b = theta_guess - window, theta_guess + window
    fa, fb = F(a), F(b)
    if fa * fb > 0:
        raise ProofFailure(f"search: pbar_theta at the half-way crossing has no sign change on [{a:.6g}, {b:.6g}]")
    for _ in range(80):
        c = 0.5 * (a + b)
        fc = F(c)
        if fc == 0.0 or b - a < 1e-16:
            break
        if (fc > 0) == (fa > 0):
            a, fa = c, fc
        else:
            b = c
    th = 0.5 * (a + b)
    x0 = start(th)
    x1, tau = half(x0)
    return th, x0, x1, tau


# --------------------------------------------------------------------------------------------------------------
# rigorous pieces (the verifier re-implements them: verify.py)
# --------------------------------------------------------------------------------------------------------------
def ham_gradient(pars, x, module=gen) -> list:
    """dHbar/dx_i over the box x (arb_series of length 2 on balls: an enclosure of the partial derivative)."""
    out = []
    for i in range(len(x)):
        y = [arb_series([v, 1 if j == i else 0], prec=2) for j, v in enumerate(x)]
        c = module.chart_hamiltonian(y, pars)[0]
        cs = c.coeffs() if isinstance(c, arb_series) else [c]
        out.append(cs[1] if len(cs) > 1 else arb(0))
    return out


def level_newton(pars, h, theta: arb, pc: Fraction, prad: Fraction, module=gen):
    """Interval Newton for Hbar(theta, 0, 0, pbar_psi) = h on P = [pc - prad, pc + prad], for every theta in the
    ball `theta`: (N, P, inside) with N = pc - (Hbar(theta, 0, 0, pc) - h) / dHbar/dpbar_psi(theta, 0, 0, P)."""
    P = ball.interval(pc - prad, pc + prad)
    Hc = module.chart_hamiltonian([theta, arb(0), arb(0), ball.q(pc)], pars)[0]
    dH = ham_gradient(pars, [theta, arb(0), arb(0), P], module)[PP]
    N = ball.q(pc) - (Hc - ball.q(h)) / dH
    lo, hi = ball.bounds(N)
    Plo, Phi = ball.bounds(P)
    return N, P, bool(ball.excludes_zero(dH) and Plo < lo and hi < Phi)


def chart_section(pars, module=gen):
    """g = sin psi (the section), its gradient, and the guards theta, pi - theta, radicand > 0."""
    def g(x):
        return x[PS].sin()

    def dg(x):  # the state may carry lambdabar as a fifth entry (fields.lam_state_field)
        return [arb(0), x[PS].cos()] + [arb(0)] * (len(x) - 2)

    mu, lam = _mu_lam(pars)

    def guard(Y):
        return [Y[TH], arb.pi() - Y[TH], mu - 2 * (Y[4] if len(Y) > 4 else lam) * Y[PP]]

    return g, dg, guard


def phase_guards(pars, fld, module=gen):
    """(first, second): guard functions of the two phases (module docstring, step 2).  first: d(sin psi)/dt =
    cos psi psi' > 0; second: sin psi > 0, or else d(sin psi)/dt < 0 (returned as a positive ball iff it holds)."""
    _, _, base = chart_section(pars, module)

    def sdot(Y):
        return Y[PS].cos() * fld.f(Y)[PS]

    def first(Y):
        return base(Y) + [sdot(Y)]

    def second(Y):
        s = Y[PS].sin()
        if ball.positive(s):
            return base(Y) + [s]
        return base(Y) + [-sdot(Y)]

    return first, second


def initial_box(p, theta: arb, pbox: arb, lam: arb | None = None) -> taylor.C1Set:
    """The chart set {theta} x {0} x {0} x pbox (x {lam} when lambdabar is a state) as a C^1 set (C = I, r0 = the
    box about its centre)."""
    x = [theta, arb(0), arb(0), pbox] + ([] if lam is None else [lam])
    xc = [v.mid() for v in x]
    S = taylor.initial_set(xc, c1=True)
    S.r0 = ball.vec([a - b for a, b in zip(x, xc)])
    return S


def section_quantities(p, fld, cr: taylor.CrossingEnclosure, tangents, module=gen) -> dict:
    """At the crossing x1: pbar_theta, theta, cos psi, d(sin psi)/dt, and for each tangent t (a chart vector) the
    section derivative v = (I - f grad g^T/(grad g . f)) W t in (theta, pbar_theta)."""
    g_grad = [arb(0), cr.x[PS].cos()] + [arb(0)] * (len(cr.x) - 2)
    gf = sum((a * b for a, b in zip(g_grad, cr.fx)), arb(0))
    out = {"ptheta": cr.x[PT], "theta": cr.x[TH], "cospsi": cr.x[PS].cos(), "gdot": cr.gdot, "tau": cr.tau}
    if cr.W is not None:
        for name, t in tangents.items():
            u = ball.column(cr.W * ball.vec(t))
            gu = sum((a * b for a, b in zip(g_grad, u)), arb(0))
            v = [ui - fi * gu / gf for ui, fi in zip(u, cr.fx)]
            out[f"d{name}_theta"] = v[TH]
            out[f"d{name}_ptheta"] = v[PT]
    return out


def tangents(pars, Q, module=gen) -> dict:
    """t_theta, t_ptheta: the tangents of the level's section at Q in chart coordinates (pbar_psi from Hbar = h)."""
    gH = ham_gradient(pars, Q[:4], module)
    z = [arb(0)] * (len(Q) - 4)  # lambdabar (a state) is fixed along the section's tangents
    return {"th": [arb(1), arb(0), arb(0), -gH[TH] / gH[PP]] + z, "pt": [arb(0), arb(0), arb(1), -gH[PT] / gH[PP]] + z}


def trace_DP(a, b, c, d):
    """tr DP(x0) = tr(R A^-1 R A) = 2 (ad + bc) / (ad - bc) for A = [[a, b], [c, d]], R = diag(1, -1)."""
    return 2 * (a * d + b * c) / (a * d - b * c)


def return_guards(pars, fld, module=gen):
    """(first, general): guards of a full return of P from Sigma+.  first: d(sin psi)/dt > 0 (leaving Sigma+);
    general: sin psi excludes 0, or else d(sin psi)/dt < 0 (no positive crossing; the negative one at psi = pi is
    allowed).  Each returns balls that are positive iff its condition holds, with the base guards (theta in
    (0, pi), radicand > 0)."""
    _, _, base = chart_section(pars, module)
    first, _ = phase_guards(pars, fld, module)

    def general(Y):
        s = Y[PS].sin()
        if ball.excludes_zero(s):
            return base(Y) + [arb(1)]
        return base(Y) + [-(Y[PS].cos() * fld.f(Y)[PS])]

    return first, general


def section_set(pars, theta: arb, ptheta: arb, ppsi: arb, C2=None) -> taylor.C1Set:
    """The chart C^1 set of a section piece: C2 None: the box theta x {0} x ptheta x ppsi (C = I, r0 the box about
    its midpoint); else C2 = (xbar, C, r0), an exact parallelepiped xbar + C r0 in the chart (the caller encloses
    the piece in it)."""
    if C2 is None:
        S = initial_box(None, theta, ppsi)
        x = [theta, arb(0), ptheta, ppsi]
        S.xbar = ball.vec([v.mid() for v in x])
        S.r0 = ball.vec([a - a.mid() for a in x])
        return S
    xbar, C, r0 = C2
    S = taylor.initial_set([ball.q(v) for v in xbar], c1=True)
    S.C, S.r0 = C, r0
    return S


def first_return(pars, fld, S: taylor.C1Set, t_a: Fraction, lead: Fraction, *, t1=Fraction(1, 64), order=20,
                 tol=PROOF_STEP_TOL, steps=None, newton=4, module=gen):
    """The validated flight of the chart set S (on Sigma+ at t = 0) through one full return of P: phase 1 on
    [0, t1] with d(sin psi)/dt > 0, phase 2 on [t1, t_a] with no positive crossing (return_guards), then the one
    crossing of sin psi = 0 in (t_a, t_a + 2 lead) (taylor.cross_section; the caller checks that it is positive).
    steps: None (adaptive) or the exact (steps1, steps2) of a certificate.  Returns (crossing, (steps1, steps2)).
    Raises taylor.EnclosureError / GuardError / CrossingError."""
    g, dg, base = chart_section(pars, module)
    first, general = return_guards(pars, fld, module)
    tr1, tr2 = taylor.Trajectory(), taylor.Trajectory()
    if steps is None:
        S = taylor.propagate(fld, S, t1, order=order, tol=tol, guard=first, record=tr1)
        S = taylor.propagate(fld, S, t_a, order=order, tol=tol, guard=general, record=tr2)
    else:
        S = taylor.propagate(fld, S, steps=steps[0], order=order, guard=first, record=tr1)
        S = taylor.propagate(fld, S, steps=steps[1], order=order, guard=general, record=tr2)
    cr = taylor.cross_section(fld, S, g, dg, 2 * lead, order, newton=newton, guard=base)
    return cr, (tr1.steps, tr2.steps)


def fly(fld, S, steps1, steps2, h_cross, order, guards, cross_guard, g, dg):
    S = taylor.propagate(fld, S, steps=steps1, order=order, guard=guards[0])
    S = taylor.propagate(fld, S, steps=steps2, order=order, guard=guards[1])
    return taylor.cross_section(fld, S, g, dg, h_cross, order, guard=cross_guard)


# --------------------------------------------------------------------------------------------------------------
# the prover
# --------------------------------------------------------------------------------------------------------------
def prove(params: fields.ExactParams, h: Fraction, theta_guess: float, settings: FixedPointSettings | None = None,
          *, root: int = -1, module=gen, progress=None) -> ProofResult:
    """Prove (or fail to prove) a symmetric hyperbolic fixed point of the section map sin psi = 0 on Hbar = h.

    Parameters
    ----------
    params : ExactParams
        Exact (m, mu, gamma, delta, lambdabar).
    h : Fraction
        The level Hbar = h (exact).
    theta_guess : float
        Where the float search looks (within 0.02) for theta* on Fix(R).
    settings : FixedPointSettings, optional
        With lam_rad > 0 the statement is for every lambdabar in [lam - lam_rad, lam + lam_rad]: lambdabar is a
        ball in every enclosure (the box Theta must then hold theta*(lambdabar) for all of them: r >~ 4.4 lam_rad at
        Fig 4(a); `interval_settings` picks r and p_rad).
    root : int
        Which root pbar_psi of Hbar(theta, 0, 0, .) = h (index into the ascending roots; -1: the largest).
    module : module, optional
        The generated field module; a mutated copy for controls (no certificate is issued for it).
    progress : callable, optional

    Returns
    -------
    ProofResult
        As search.prove: ok, certificate (kind "section_fixed_point"), reason, checks, wall_time_s.

    Notes
    -----
    Method: module docstring.  Cost at Fig 4(a): about 10 s (two chart flights of ~3 time units).
    """
    st = settings or FixedPointSettings()
    if st.lam_rad < 0:
        raise ParameterError("lam_rad", f"must be >= 0, got {st.lam_rad}")
    t0 = time.perf_counter()
    checks: list = []

    def check(name, holds, how):
        checks.append({"name": name, "holds": bool(holds), "how": how})
        if not holds:
            raise ProofFailure(f"{name} not established: {how}", checks)

    try:
        with ball.workprec(st.prec):
            cert = _prove(params, h, theta_guess, root, st, module, check, progress)
    except ProofFailure as err:
        return ProofResult(False, None, err.reason, checks, time.perf_counter() - t0)
    except (ArithmeticError, ValueError, np.linalg.LinAlgError, ParameterError) as err:
        reason = f"numerical failure ({type(err).__name__}: {' '.join(str(err).split())[:160]})"
        return ProofResult(False, None, reason, checks, time.perf_counter() - t0)
    cert["checks"] = checks
    cert["wall_time_s"] = round(time.perf_counter() - t0, 3)
    return ProofResult(True, cert, "all checks hold", checks, time.perf_counter() - t0)


def _prove(p, h, theta_guess, root, st, module, check, progress) -> dict:
    say = progress or (lambda s: None)
    say("float search")
    th_f, x0, x1, tau_f = float_fixed_point(p, h, theta_guess, root)
    thc = ball.fraction(float(th_f))
    pc = ball.fraction(float(x0[PP]))
    pars = parameter_balls(p, st.lam_rad)
    Lam = pars[fields.LAM] if st.lam_rad else None
    # a lambdabar interval rides in the state (its Lohner linear part), a point in the parameters
    fld = fields.lam_state_field(p, module) if st.lam_rad else fields.chart_field(p, module)
    say("structure")
    pts = [[ball.dyadic(v) for v in x0], [ball.dyadic(v) for v in x1]]
    for name, holds, how in structural_tests(p, module, pts):
        check(name, holds, how)
    say("level")
    Theta = ball.interval(thc - st.r, thc + st.r)
    N, _, ok = level_newton(pars, h, Theta, pc, st.p_rad, module)
    check("level Newton (box)", ok, f"pbar_psi(theta) unique in the box about {float(pc):.12g}, inside N = {N}")
    Nc, _, okc = level_newton(pars, h, ball.q(thc), pc, st.p_rad, module)
    check("level Newton (centre)", okc, f"pbar_psi(theta_c) inside {Nc}")
    t_a = Fraction(math.floor((tau_f - float(st.lead)) * 2**20), 2**20)
    g, dg, base = chart_section(pars, module)
    guards = phase_guards(pars, fld, module)
    vals, record = {}, {}
    for kind, theta, pbox in (("thin", ball.q(thc), Nc), ("box", Theta, N)):
        say(f"flight ({kind})")
        S = initial_box(p, theta, pbox, Lam)
        steps = []
        try:
            tr1, tr2 = taylor.Trajectory(), taylor.Trajectory()
            S = taylor.propagate(fld, S, st.t1, order=st.order, tol=st.tol, guard=guards[0], record=tr1)
            S = taylor.propagate(fld, S, t_a, order=st.order, tol=st.tol, guard=guards[1], record=tr2)
            cr = taylor.cross_section(fld, S, g, dg, 2 * st.lead, st.order, guard=base)
        except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
            raise ProofFailure(f"flight ({kind}) not validated: {err}") from None
        steps = [tr1.steps, tr2.steps]
        Q = [theta, arb(0), arb(0), pbox] + ([] if Lam is None else [Lam])
        q = section_quantities(p, fld, cr, tangents(pars, Q, module), module)
        bad = [k for k, v in q.items() if not v.is_finite()]
        check(f"{kind} enclosures finite", not bad, f"the {kind} flight's crossing quantities are finite balls"
              + (f" (not: {', '.join(bad)})" if bad else ""))
        vals[kind] = q
        record[kind] = {"steps1": [ball.decimal(s) for s in steps[0]], "steps2": [ball.decimal(s) for s in steps[1]],
                        "n_steps": len(steps[0]) + len(steps[1]), "max_width": max(tr1.widths + tr2.widths),
                        "enclosures": {k: stored(v) for k, v in q.items()}}
    thin, bx = vals["thin"], vals["box"]
    check("negative crossing", ball.negative(bx["gdot"]),
          f"d(sin psi)/dt over the crossing step = {bx['gdot']} < 0 (the half-way point, not a return to Sigma+)")
    newton = ball.q(thc) - thin["ptheta"] / bx["dth_ptheta"]
    lo, hi = ball.bounds(newton)
    check("Fix(R) Newton", ball.excludes_zero(bx["dth_ptheta"]) and thc - st.r < lo and hi < thc + st.r,
          f"theta_c - pbar_theta(theta_c)/F'(Theta) = {newton} inside Theta: one theta* whose orbit meets Fix(R)")
    tr = trace_DP(bx["dth_theta"], bx["dpt_theta"], bx["dth_ptheta"], bx["dpt_ptheta"])
    check("hyperbolic", ball.bounds(abs(tr))[0] > 2 if tr.is_finite() else False,
          f"tr DP(x0) = {tr}: |tr| > 2, det = 1 (a saddle)")
    digest = fields.source_digest(module)
    check("field_is_derived", digest == fields.source_digest(gen),
          "the vector field is the derive-generated generated/validated.py (SHA-256 of its source)")
    params = p.as_json()
    lam_u = _mu_u(ball.from_json(stored(tr)))  # from the stored trace ball, as the verifier recomputes it
    return {
        "format": FORMAT, "kind": KIND,
        "theorem": section_fixed_point_theorem(params, _q(h), _q(st.lam_rad)),
        "params": params, "level": _q(h), "settings": st.as_json(), "field_digest": digest,
        "point": {"theta_c": _q(thc), "p_c": _q(pc), "t_a": _q(t_a), "h_cross": _q(2 * st.lead),
                  "level_newton": {"box": stored(N), "centre": stored(Nc)}},
        "flights": record, "newton": stored(newton), "trace": stored(tr), "mu_u": stored(lam_u),
        "hypotheses_symbolic": ["reversor_reduced", "validated_fields", "full_ham_nondim"],
        "float": {"theta": float(th_f), "half_time": tau_f, "x0": x0.tolist(), "x_half": x1.tolist()},
    }


def _mu_u(tr: arb) -> arb:
    """The eigenvalue of modulus > 1: mu + 1/mu = tr, mu = (tr + sign(tr) sqrt(tr^2 - 4)) / 2."""
    s = (tr * tr - 4).sqrt()
    return (tr + s) / 2 if ball.positive(tr) else (tr - s) / 2



# --------------------------------------------------------------------------------------------------------------
# one return of a section piece (the horseshoe of horseshoe.py; the verifier drives the same flight)
# --------------------------------------------------------------------------------------------------------------
def branch_psi(branch: str) -> arb:
    """psi on the section's branch: "0" -> 0, "pi" -> pi (a ball)."""
    if branch not in ("0", "pi"):
        raise ValueError(f"branch must be '0' or 'pi', got {branch!r}")
    return arb(0) if branch == "0" else arb.pi()


def level_newton_section(pars, h, theta: arb, ptheta: arb, pc: Fraction, prad: Fraction, module=gen, branch="0"):
    """Interval Newton for Hbar(theta, psi_b, ptheta, pbar_psi) = h (psi_b = 0 or pi: `branch`) on
    P = [pc - prad, pc + prad] for every (theta, ptheta) in the balls: (N, P, inside) as level_newton."""
    ps = branch_psi(branch)
    P = ball.interval(pc - prad, pc + prad)
    Hc = module.chart_hamiltonian([theta, ps, ptheta, ball.q(pc)], pars)[0]
    dH = ham_gradient(pars, [theta, ps, ptheta, P], module)[PP]
    N = ball.q(pc) - (Hc - ball.q(h)) / dH
    lo, hi = ball.bounds(N)
    Plo, Phi = ball.bounds(P)
    return N, P, bool(ball.excludes_zero(dH) and Plo < lo and hi < Phi)


def piece_return(pars, h, fld, c, A, pc: Fraction, prad: Fraction, t_a: Fraction, lead: Fraction, *,
                 t1=Fraction(1, 64), order=20, tol=PROOF_STEP_TOL, tol_thin=None, steps=None, newton=12, box=True,
                 thin=None, branch="0", module=gen) -> dict:
    """One return of P for the section piece X = c + A [-1, 1]^2 (c exact (theta, pbar_theta), A exact 2 x 2) on
    the level Hbar = h, pbar_psi the root in [pc - prad, pc + prad].

    Two validated flights (first_return): the centre c (its pbar_psi by interval Newton at c) and the piece as the
    chart parallelepiped xbar + C r0, C = [[A, 0], [g A, e_ppsi]] in the rows (theta, psi, pbar_theta, pbar_psi),
    r0 = ([-1, 1], [-1, 1], 0, E): g = mid of grad pbar_psi(theta, pbar_theta) = -(dHbar/dtheta, dHbar/dpbar_theta)
    / dHbar/dpbar_psi over the hull, E the mean-value remainder (the root is unique in the Newton box over the hull,
    so pbar_psi(c + A v) = pbar_psi(c) + grad(xi) A v).  Returns the balls: "Pc" = (theta, pbar_theta) of P(c),
    "DP" = [[dtheta'/dtheta, dtheta'/dpbar_theta], [dpbar_theta'/dtheta, dpbar_theta'/dpbar_theta]] over X, the
    crossings' "gdot" and "cospsi" (thin and box), "ppsi_box" (pbar_psi at the box crossing), the Newton results
    ("level_ok"), and the steps taken (box False: the centre's flight only, with "DPc" its DP; thin: a previous
    result of this function at the same centre and p_c whose centre flight is reused).  tol_thin: the step
    tolerance of the centre's flight (default tol): the centre's enclosure must resolve sets of ~1e-13, and the
    Lagrange remainders on the a priori enclosures dominate it (1e-25: widths 1e-14 .. 2e-13 after one return;
    1e-32: 5e-20, 2.3x the steps).  Flight failures raise taylor's errors; the caller checks the signs."""
    out = {}
    cq = [ball.q(v) for v in c]
    ps = branch_psi(branch)
    Nc, _, okc = level_newton_section(pars, h, cq[0], cq[1], pc, prad, module, branch)
    A00, A01, A10, A11 = (ball.q(A[i][j]) for i in range(2) for j in range(2))
    U = ball.interval(-1, 1)
    th_h = cq[0] + A00 * U + A01 * U
    pt_h = cq[1] + A10 * U + A11 * U
    Nb, _, okb = level_newton_section(pars, h, th_h, pt_h, pc, prad, module, branch)
    out["level_ok"] = bool(okc and okb)
    out["ppsi_centre"], out["ppsi_hull"] = Nc, Nb
    if not out["level_ok"]:
        return out
    Q = [th_h, ps, pt_h, Nb]
    gH = ham_gradient(pars, Q, module)
    grad = [-gH[TH] / gH[PP], -gH[PT] / gH[PP]]
    gm = [v.mid() for v in grad]
    col = [(A00, A10), (A01, A11)]
    E = (Nc - Nc.mid()) + sum(((grad[0] - gm[0]) * a + (grad[1] - gm[1]) * b) * U for a, b in col)
    C = arb_mat(4, 4, [A00, A01, 0, 0,
                       0, 0, 1, 0,
                       A10, A11, 0, 0,
                       gm[0] * A00 + gm[1] * A10, gm[0] * A01 + gm[1] * A11, 0, 1])
    if any(C[i, j].rad() != 0 for i in range(4) for j in range(4)):  # exact: g A rounded to a point matrix
        C = C.mid()
        E = E + sum(((gm[0] * a + gm[1] * b) - C[3, j]) * U for j, (a, b) in enumerate(col))
    xbar = [ball.fraction(cq[0]), ball.fraction(ps.mid()), ball.fraction(cq[1]), ball.fraction(Nc.mid())]
    r0 = ball.vec([U, U, ps - ps.mid(), E])  # psi = pi: the ball of pi about its exact midpoint (C's psi row e_psi)
    thin_set = taylor.initial_set([cq[0], ps, cq[1], Nc], c1=True)
    box_set = section_set(pars, None, None, None, C2=(xbar, C, r0)) if box else None
    steps_out = {}
    if thin is not None:
        for key in ("Pc", "ppsi_thin", "DPc", "gdot_thin", "cospsi_thin"):
            out[key] = thin[key]
        steps_out["thin"] = thin["steps"]["thin"]
    todo = ([] if thin is not None else [("thin", thin_set)]) + ([("box", box_set)] if box else [])
    for kind, S in todo:
        st = None if steps is None else steps[kind]
        tk = (tol_thin or tol) if kind == "thin" else tol
        cr, used = first_return(pars, fld, S, t_a, lead, t1=t1, order=order, tol=tk, steps=st, newton=newton,
                                module=module)
        steps_out[kind] = used
        Qk = [cq[0], ps, cq[1], Nc] if kind == "thin" else Q
        q = section_quantities(None, fld, cr, tangents(pars, Qk, module), module)
        out[f"gdot_{kind}"], out[f"cospsi_{kind}"] = q["gdot"], q["cospsi"]
        if kind == "thin":
            out["Pc"] = (q["theta"], q["ptheta"])
            out["ppsi_thin"] = cr.x[PP]
            out["DPc"] = [[q["dth_theta"], q["dpt_theta"]], [q["dth_ptheta"], q["dpt_ptheta"]]]
        else:
            out["DP"] = [[q["dth_theta"], q["dpt_theta"]], [q["dth_ptheta"], q["dpt_ptheta"]]]
            out["ppsi_box"] = cr.x[PP]
            out["tau_box"] = cr.tau
    out["steps"] = steps_out
    return out
