"""The prover for a symmetric hyperbolic fixed point of the section map on a given level (the
first half of the route "a hyperbolic periodic orbit of the section map plus a transverse homoclinic point").

What is proved (docs/nonintegrability.md, statement 11): at exact rational (m, mu, gamma, delta, lambdabar) and an
exact level h, the section map P of Sigma+ = {sin psi = 0, d(sin psi)/dt > 0} on {Hbar = h} (the paper's Fig 4
section) has a fixed point x0 = (theta*, psi = 0, pbar_theta = 0, pbar_psi*) on Fix(R), and DP(x0) is hyperbolic
(`branch="pi"`: x0 at psi = pi instead, Fig 5's saddle, statement 13; steps 1-5 unchanged, the half-way crossing at psi = 0)
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
                and det A = 1 (Hamilton's flow preserves dtheta ^ dpbar_theta + dpsi ^ dpbar_psi; the transition
                between the sections psi = 0 and psi = pi, read on the level's tangents t_theta, t_ptheta, whose
                psi-components vanish and whose form is 1, preserves it: the flow direction adds nothing, since
                omega(f, v) = dHbar(v) = 0 on the level), so also tr DP(x0) = 2 + 4 bc = 4 ad - 2 (the narrowest
                enclosure over a wide box: trace_DP); |tr| > 2 on the enclosure: a saddle
Why this is a fixed point of P: x0 and x1 = Phi_tau(x0) lie on Fix(R), so the orbit is periodic with period
T = 2 tau (Devaney 1976); s(t) = sin psi(t) is odd in t along it (s(-t) = -s(t)), so its crossings at t and -t
have the same direction; there is none positive in (0, tau] (steps 2-3), hence none in (0, T), and t = T is
positive (x0 is): P(x0) = x0 with return time T.  With DQ2 = R DQ^-1 R for the second half (reversibility),
DP(x0) = R A^-1 R A.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from flint import arb

from ...core.errors import ParameterError
from ...core.tolerances import FIXED_POINT_SEARCH_TOL, PROOF_STEP_TOL
from ...generated import validated as gen
from .. import ball, fields, taylor
from .transverse_homoclinic import ProofFailure, ProofResult, run_checked, stored, structural_tests
from ..theorem import section_fixed_point_theorem
from ..section_return import (_mu_lam, branch_psi, chart_section, first_return, ham_gradient, initial_box, level_newton, level_newton_section, phase_guards, piece_return, return_guards, section_quantities, section_set, sheared_fixed_point_set, tangents)  # noqa: F401  (re-exported: the provers' names)

FORMAT = "magrod-proof-certificate/1"
KIND = "section_fixed_point"
TH, PS, PT, PP = fields.THETA, fields.PSI, fields.PTHETA, fields.PPSI


@dataclass
class FixedPointSettings:
    """Numerical choices (recorded; the verifier replays them).  r: half-width of the theta-box; p_rad: half-width
    of the pbar_psi box of the level's interval Newton; t1: end of the first phase (d sin psi/dt > 0); lead: the
    flight stops this long before the float crossing time, and the crossing step has length 2 lead."""

    prec: int = 128  # working precision in bits
    order: int = 20  # Taylor order of the validated steps
    tol: float = PROOF_STEP_TOL  # step-size control of the validated integrator
    r: Fraction = Fraction(1, 10**10)
    p_rad: Fraction = Fraction(1, 10**8)
    t1: Fraction = Fraction(1, 64)
    lead: Fraction = Fraction(1, 256)
    #: half-width of the lambdabar interval carried as a ball through every enclosure (0: the point itself)
    lam_rad: Fraction = Fraction(0)
    #: on an interval: the box moves with lambdabar, theta = theta_c + v (lambdabar - lam) + [-r, r] (v exact dyadic,
    #: ~dtheta*/dlambdabar; section_return.sheared_fixed_point_set); None: the box theta_c +- r for every lambdabar
    v: Fraction | None = None

    def as_json(self) -> dict:
        q = _q
        return {"prec": self.prec, "order": self.order, "tol": repr(self.tol), "r": q(self.r), "p_rad": q(self.p_rad),
                "t1": q(self.t1), "lead": q(self.lead), "lam_rad": q(self.lam_rad), "series_cap": ball.SERIES_CAP,
                **({} if self.v is None else {"v": q(self.v)})}


parameter_balls = fields.parameter_balls  # moved to fields (the verifier uses it and must not import periodic)


def interval_settings(lam_rad, base: "FixedPointSettings | None" = None) -> "FixedPointSettings":
    """Settings for a lambdabar interval of half-width lam_rad: the theta-box r = max(r, 8 lam_rad) (theta* moves by
    ~4.4 per unit lambdabar at Fig 4(a), 0.383 -> 0.283 from (a) to (b)) and the level box p_rad = max(p_rad,
    16 (r + lam_rad)) (pbar_psi moves by O(1) per unit theta or lambdabar)."""
    from dataclasses import replace

    st = base or FixedPointSettings()
    w = ball.fraction(lam_rad)
    r = max(st.r, 8 * w)
    return replace(st, lam_rad=w, r=r, p_rad=max(st.p_rad, 16 * (r + w)))


def interval_settings_for(p: fields.ExactParams, h: Fraction, theta_guess: float, lam_rad, *, root: int = -1,
                          branch: str = "0", base: "FixedPointSettings | None" = None,
                          moving=None) -> "FixedPointSettings":
    """interval_settings with the theta-box sized by theta*'s measured motion: v = dtheta*/dlambdabar by central
    differences of the float search at lambdabar +- lam_rad, and r = max(4 |v| lam_rad, 2 lam_rad) (the interval
    Newton image is ~3.3 |v| lam_rad wide at Fig 4(a): 17.2 lam_rad against |v| = 5.2;
    research/fixed_point_interval_limits.py), p_rad = 16 (r + lam_rad).  What `magrod prove --fixed-point
    --lam-rad W` uses; a float design choice only (the proof checks the box).  moving K': the box moves with
    lambdabar along the measured slope v (signed, rounded to 16 bits) and has half-width r = K' lam_rad about the
    moving point (FixedPointSettings.v)."""
    from dataclasses import replace

    st = base or FixedPointSettings()
    w = ball.fraction(lam_rad)
    if w <= 0:
        return replace(st, lam_rad=Fraction(0))
    ths = []
    for s in (-1, 1):
        q = fields.ExactParams(p.m, p.mu, p.gamma, p.delta, p.lam + s * w)
        ths.append(float_fixed_point(q, h, theta_guess, root, branch=branch)[0])
    v = abs(ths[1] - ths[0]) / (2 * float(w))
    if moving:  # the box follows theta*: its slope (signed, 16 bits), and a box of K' w about the moving point
        vs = Fraction(round((ths[1] - ths[0]) / (2 * float(w)) * 2**16), 2**16)
        return moving_box(replace(st, lam_rad=w, v=vs), moving)
    r = max(4 * ball.fraction(v) * w, 2 * w, st.r)
    r = Fraction(math.ceil(r / w * 8), 8) * w  # a short rational: K w with K a multiple of 1/8
    return replace(st, lam_rad=w, r=r, p_rad=max(st.p_rad, 16 * (r + w)))


def moving_box(st: "FixedPointSettings", k) -> "FixedPointSettings":
    """st (a moving box: lam_rad and v set) with the half-width r = K' lam_rad about the moving point, and the level's
    Newton box p_rad that holds pbar_psi's motion over it."""
    from dataclasses import replace

    base = FixedPointSettings()
    r = max(Fraction(k) * st.lam_rad, base.r)
    return replace(st, r=r, p_rad=max(base.p_rad, 16 * (r + (abs(st.v) + 1) * st.lam_rad)))


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
def float_fixed_point(p: fields.ExactParams, h: Fraction, theta_guess: float, root: int = -1, window=0.02,
                      branch: str = "0"):
    """theta* near theta_guess (bisection of pbar_theta at the first negative crossing of sin psi = 0, the half-way
    point: psi ~ pi from the branch "0", psi ~ 0 from "pi"), x0 (psi = 0 or pi: `branch`; pbar_psi the root of index
    `root`), the half-way state and the half-return time."""
    import heyoka as hy

    from ...chaos.section import solve_p_psi
    from ...core import systems
    from ...core.params import RodParams

    rp = RodParams(*p.floats())
    v = hy.make_vars(*systems.STATE["reduced"])
    ta = systems.taylor(systems.system("reduced"), [1.0, 0.0, 0.0, 1.0], rp.array(),
                        t_events=[hy.t_event(hy.sin(v[PS]), direction=hy.event_direction.negative)],
                        tol=FIXED_POINT_SEARCH_TOL)

    psi0 = {"0": 0.0, "pi": math.pi}[branch]

    def start(th, pt=0.0):
        roots = solve_p_psi(rp, float(h), th, pt, psi0)
        x = np.zeros(4)
        x[TH], x[PS], x[PT], x[PP] = th, psi0, pt, roots[root]
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


def trace_DP(a, b, c, d):
    """tr DP(x0) = tr(R A^-1 R A) = 2 (ad + bc) / (ad - bc) for A = [[a, b], [c, d]], R = diag(1, -1); and, since
    det A = ad - bc = 1 (step 5 of the module docstring: the transition from psi = 0 to psi = pi preserves
    dtheta ^ dpbar_theta), also 2 + 4 bc and 4 ad - 2.  Each of the three encloses tr DP at every point of the box the
    entries were enclosed on; the returned ball is their intersection (2 + 4 bc is the narrowest: ~6x at Fig 4(a),
    since the quotient's numerator and denominator vary together)."""
    general = 2 * (a * d + b * c) / (a * d - b * c)
    lo, hi = ball.meet_bounds([general, 2 + 4 * b * c, 4 * a * d - 2])
    return general if not math.isfinite(lo) else ball.interval(lo, hi)


def fly(fld, S, steps1, steps2, h_cross, order, guards, cross_guard, g, dg):
    S = taylor.propagate(fld, S, steps=steps1, order=order, guard=guards[0])
    S = taylor.propagate(fld, S, steps=steps2, order=order, guard=guards[1])
    return taylor.cross_section(fld, S, g, dg, h_cross, order, guard=cross_guard)


# --------------------------------------------------------------------------------------------------------------
# the prover
# --------------------------------------------------------------------------------------------------------------
def prove(params: fields.ExactParams, h: Fraction, theta_guess: float, settings: FixedPointSettings | None = None,
          *, root: int = -1, branch: str = "0", module=gen, progress=None) -> ProofResult:
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
        Which root pbar_psi of Hbar(theta, psi, 0, .) = h (index into the ascending roots; -1: the largest).
    branch : {"0", "pi"}
        x0's branch of Sigma+: psi = 0 (psi' > 0; Fig 4) or psi = pi (psi' < 0; Fig 5's saddle).  From psi = pi
        the half-way (negative) crossing is at psi = 0; the argument is the same (Fix(R) holds both branches).
    module : module, optional
        The generated field module; a mutated copy for controls (no certificate is issued for it).
    progress : callable, optional

    Returns
    -------
    ProofResult
        As transverse_homoclinic.prove: ok, certificate (kind "section_fixed_point"), reason, checks, wall_time_s.

    Notes
    -----
    Method: module docstring.  Cost at Fig 4(a): about 10 s (two chart flights of ~3 time units).
    """
    st = settings or FixedPointSettings()
    if st.lam_rad < 0:
        raise ParameterError("lam_rad", f"must be >= 0, got {st.lam_rad}")
    return run_checked(st.prec, lambda check: _prove(params, h, theta_guess, root, st, module, check, progress,
                                                     branch))


#: the moving box's half-widths K' lam_rad tried by prove_moving, smallest first (a smaller box gives a tighter
#: trace; the Newton image must fit: ~1.5 lam_rad at Fig 4(a) for lam_rad = 1e-5, 0.12 lam_rad at Fig 5(a), 1e-4)
MOVING_BOXES = (Fraction(1, 4), Fraction(1), Fraction(2), Fraction(4))


def prove_moving(params: fields.ExactParams, h: Fraction, theta_guess: float, lam_rad, *, root: int = -1,
                 branch: str = "0", module=gen, progress=None) -> ProofResult:
    """prove() for every lambdabar in [lam - lam_rad, lam + lam_rad] with the theta-box following the fixed point
    (interval_settings_for(moving=K')), trying the box half-widths K' lam_rad of MOVING_BOXES in turn: the first
    that proves, or the last failure.  What `magrod prove --fixed-point --lam-rad W` runs (--box moving).

    Examples
    --------
    >>> from fractions import Fraction
    >>> from magrod.proof.provers import section_fixed_point as sfp
    >>> p, h = sfp.validate("17/10", "2/5", "3", "3", "27/200", "9/10")
    >>> res = sfp.prove_moving(p, h, 0.383046, Fraction(1, 10**5))  # doctest: +SKIP
    >>> res.ok, res.certificate["settings"]["v"]  # doctest: +SKIP
    (True, '-85747/16384')
    """
    res = None
    st0 = interval_settings_for(params, h, theta_guess, lam_rad, root=root, branch=branch, moving=MOVING_BOXES[0])
    for k in MOVING_BOXES:  # the float slope once; only the box's half-width changes
        st = moving_box(st0, k)
        res = prove(params, h, theta_guess, st, root=root, branch=branch, module=module, progress=progress)
        if res.ok:
            return res
    return res


def _prove(p, h, theta_guess, root, st, module, check, progress, branch="0") -> dict:
    say = progress or (lambda s: None)
    say("float search")
    psi0 = branch_psi(branch)
    th_f, x0, x1, tau_f = float_fixed_point(p, h, theta_guess, root, branch=branch)
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
    sheared = {}
    if st.v is not None:
        if not st.lam_rad:
            raise ParameterError("v", "a moving box needs a lambdabar interval (lam_rad > 0)")
        sheared = sheared_fixed_point_set(p, h, thc, st.v, st.r, st.lam_rad, pc, st.p_rad, branch, module)
        check("level Newton (box)", sheared["level_ok"],
              f"pbar_psi unique over the moving box and the interval, inside {sheared['level']}")
        N, Nc = sheared["level"], sheared["level_centre"]
        ok = okc = True
    elif branch == "0":
        N, _, ok = level_newton(pars, h, Theta, pc, st.p_rad, module)
        Nc, _, okc = level_newton(pars, h, ball.q(thc), pc, st.p_rad, module)
    else:
        N, _, ok = level_newton_section(pars, h, Theta, arb(0), pc, st.p_rad, module, branch)
        Nc, _, okc = level_newton_section(pars, h, ball.q(thc), arb(0), pc, st.p_rad, module, branch)
    if not sheared:
        check("level Newton (box)", ok, f"pbar_psi(theta) unique in the box about {float(pc):.12g}, inside N = {N}")
        check("level Newton (centre)", okc, f"pbar_psi(theta_c) inside {Nc}")
    t_a = Fraction(math.floor((tau_f - float(st.lead)) * 2**20), 2**20)
    g, dg, base = chart_section(pars, module)
    guards = phase_guards(pars, fld, module)
    vals, record = {}, {}
    for kind, theta, pbox in (("thin", ball.q(thc), Nc), ("box", Theta, N)):
        say(f"flight ({kind})")
        if sheared and kind == "box":
            S = sheared["set"]
        else:  # moving: the thin set is the point (theta_c, lam), lambdabar a state at lam
            S = initial_box(p, theta, pbox, ball.q(p.lam) if sheared else Lam, psi0)
        steps = []
        try:
            tr1, tr2 = taylor.Trajectory(), taylor.Trajectory()
            S = taylor.propagate(fld, S, st.t1, order=st.order, tol=st.tol, guard=guards[0], record=tr1)
            S = taylor.propagate(fld, S, t_a, order=st.order, tol=st.tol, guard=guards[1], record=tr2)
            cr = taylor.cross_section(fld, S, g, dg, 2 * st.lead, st.order, guard=base)
        except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
            raise ProofFailure(f"flight ({kind}) not validated: {err}") from None
        steps = [tr1.steps, tr2.steps]
        if sheared and kind == "box":
            Q = sheared["Q"]
        else:
            Q = [theta, psi0, arb(0), pbox] + ([ball.q(p.lam)] if sheared else [] if Lam is None else [Lam])
        tg = tangents(pars, Q, module)
        if sheared and kind == "box":  # the section derivative along lambdabar, the box moving with it
            tg["l"] = sheared["tangent_lam"]
        q = section_quantities(p, fld, cr, tg, module)
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
    Fc = thin["ptheta"]
    if sheared:  # pbar_theta on the line theta_c + v dl: the point's and the derivative along it (mean value)
        Fc = Fc + bx["dl_ptheta"] * ball.interval(-st.lam_rad, st.lam_rad)
    newton = ball.q(thc) - Fc / bx["dth_ptheta"]
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
        "theorem": section_fixed_point_theorem(params, _q(h), _q(st.lam_rad), branch, st.v is not None),
        "params": params, "level": _q(h), "settings": st.as_json(), "field_digest": digest,
        "point": {"theta_c": _q(thc), "p_c": _q(pc), "t_a": _q(t_a), "h_cross": _q(2 * st.lead),
                  "level_newton": {"box": stored(N), "centre": stored(Nc)},
                  **({} if branch == "0" else {"branch": branch})},
        "flights": record, "newton": stored(newton), "trace": stored(tr), "mu_u": stored(lam_u),
        "hypotheses_symbolic": ["reversor_reduced", "validated_fields", "full_ham_nondim"],
        "float": {"theta": float(th_f), "half_time": tau_f, "x0": x0.tolist(), "x_half": x1.tolist()},
    }


def _mu_u(tr: arb) -> arb:
    """The eigenvalue of modulus > 1: mu + 1/mu = tr, mu = (tr + sign(tr) sqrt(tr^2 - 4)) / 2, on the ball tr; and,
    since mu is increasing in tr on |tr| > 2, the hull of its values at tr's two end points (the ball formula's
    tr * tr loses the lower bound once tr's radius is comparable to its distance from 2: tr in [2.1, 12.1] gives
    a radicand ball containing negatives).  The intersection of the two."""
    s = (tr * tr - 4).sqrt()
    pos = ball.positive(tr)
    ball_form = (tr + s) / 2 if pos else (tr - s) / 2
    lo, hi = ball.bounds(tr)
    if not (math.isfinite(lo) and (lo > 2 or hi < -2)):
        return ball_form
    ends = []
    for t in (ball.q(lo), ball.q(hi)):
        r = (t * t - 4).sqrt()
        ends.append((t + r) / 2 if pos else (t - r) / 2)
    mlo, mhi = ball.meet_bounds([ball_form, ends[0].union(ends[1])])
    return ball.interval(mlo, mhi)


