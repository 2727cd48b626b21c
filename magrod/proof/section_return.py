"""The validated first return to the section sin psi = 0 in the reduced chart, shared by the provers of
statements 11 and 12 (provers/section_fixed_point.py, provers/section_horseshoe.py) and by the verifier (verify.py, kind section_horseshoe): the
level's pbar_psi by interval Newton, the section's guards, the C^1 flight of a set to its next crossing, the
section quantities there.  It is part of the verifier's trust base (docs/nonintegrability.md, "The verifier's trust
base"), like taylor.py: it imports only ball, fields, taylor, taylor_model and the generated fields -- never a prover's search
(provers/: transverse_homoclinic.py, section_fixed_point.py's prove, section_horseshoe.py), so a verifier that uses it does not use the prover's decisions.
Moved here from the fixed-point prover unchanged."""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from flint import arb, arb_mat, arb_series

from ..core.tolerances import PROOF_STEP_TOL
from ..generated import validated as gen
from . import ball, fields, taylor, taylor_model

#: the validated integrators a flight may use, by the name a certificate records (settings "thin_integrator" for
#: the centres, "integrator" for the sets):
#: "taylor" the a priori box's Lagrange remainder (every certificate without the field), "taylor_model" the
#: Taylor-model remainder (taylor_model.py)
INTEGRATORS = {"taylor": taylor, "taylor_model": taylor_model}


def integrator(name: str):
    """The integrator module of a certificate's name (INTEGRATORS); ValueError naming it otherwise."""
    if name not in INTEGRATORS:
        raise ValueError(f"integrator (thin_integrator) must be one of {sorted(INTEGRATORS)}, got {name!r}")
    return INTEGRATORS[name]

TH, PS, PT, PP = fields.THETA, fields.PSI, fields.PTHETA, fields.PPSI


def _mu_lam(pars):
    return pars[fields.PARAMS.index("mu")], pars[fields.PARAMS.index("lam")]


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


def initial_box(p, theta: arb, pbox: arb, lam: arb | None = None, psi: arb | None = None) -> taylor.C1Set:
    """The chart set {theta} x {psi} x {0} x pbox (x {lam} when lambdabar is a state) as a C^1 set (C = I, r0 = the
    box about its centre); psi 0 (the default) or a ball of pi (the branch psi = pi of Fix(R))."""
    x = [theta, arb(0) if psi is None else psi, arb(0), pbox] + ([] if lam is None else [lam])
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
                 tol=PROOF_STEP_TOL, steps=None, newton=4, module=gen, integrator=taylor):
    """The validated flight of the chart set S (on Sigma+ at t = 0) through one full return of P: phase 1 on
    [0, t1] with d(sin psi)/dt > 0, phase 2 on [t1, t_a] with no positive crossing (return_guards), then the one
    crossing of sin psi = 0 in (t_a, t_a + 2 lead) (taylor.cross_section; the caller checks that it is positive).
    steps: None (adaptive) or the exact (steps1, steps2) of a certificate.  integrator: the module whose propagate
    and cross_section fly it (taylor, or taylor_model: the Taylor-model remainder).  Returns (crossing, (steps1,
    steps2)).  Raises taylor.EnclosureError / GuardError / CrossingError."""
    g, dg, base = chart_section(pars, module)
    first, general = return_guards(pars, fld, module)
    tr1, tr2 = taylor.Trajectory(), taylor.Trajectory()
    if steps is None:
        S = integrator.propagate(fld, S, t1, order=order, tol=tol, guard=first, record=tr1)
        S = integrator.propagate(fld, S, t_a, order=order, tol=tol, guard=general, record=tr2)
    else:
        S = integrator.propagate(fld, S, steps=steps[0], order=order, guard=first, record=tr1)
        S = integrator.propagate(fld, S, steps=steps[1], order=order, guard=general, record=tr2)
    cr = integrator.cross_section(fld, S, g, dg, 2 * lead, order, newton=newton, guard=base)
    return cr, (tr1.steps, tr2.steps)


# --------------------------------------------------------------------------------------------------------------
# one return of a section piece (the horseshoe of provers/section_horseshoe.py; the verifier drives the same flight)
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


@dataclass(frozen=True)
class Moving:
    """A lambdabar interval for piece_return's box flight, with the piece moving along it: for every lambdabar in
    `lam` (a ball about the exact lam0) the piece is X(lambdabar) = c + v (lambdabar - lam0) + A [-1, 1]^2 (v exact,
    2 entries: (dtheta, dpbar_theta) per unit lambdabar; the sets of a horseshoe follow their chain's motion, so
    that the covering conditions hold for a lambdabar interval much wider than the sets: provers/horseshoe_widen.py).  pars: the
    parameters with `lam` in lambdabar's slot (fields.parameter_balls); fld: fields.lam_state_field (lambdabar the
    fifth state, lambdabar' = 0)."""

    pars: tuple
    fld: object
    lam: arb
    lam0: Fraction
    v: tuple


def sheared_fixed_point_set(p, h, thc: Fraction, v: Fraction, s_rad: Fraction, lam_rad: Fraction, pc: Fraction,
                            prad: Fraction, branch="0", module=gen) -> dict:
    """The chart set of a section fixed point's box that follows the fixed point along lambdabar (statement 11 on a
    lambdabar interval): for every lambdabar in [lam - lam_rad, lam + lam_rad] (lam = p.lam, dl = lambdabar - lam)
    the points theta = thc + v dl + s, s in [-s_rad, s_rad] (s_rad 0: the line s = 0), psi on the branch,
    pbar_theta = 0, pbar_psi on the level Hbar = h, and lambdabar as the fifth state (fields.lam_state_field).

    pbar_psi: Nb by interval Newton over the hull (unique in [pc - prad, pc + prad] for every point and lambdabar),
    Nc at (thc, lam); by the mean value theorem pbar_psi(thc + v dl + s, lam + dl) - pbar_psi(thc, lam) =
    g_theta(xi) (v dl + s) + g_lam(xi) dl, g = -(dHbar/dtheta, dHbar/dlambdabar) / dHbar/dpbar_psi over the hull.
    So the set is xbar + C r0 with exact C: the s column (1, 0, 0, mid g_theta, 0), the lambdabar column (v, 0, 0,
    mid g_theta v + mid g_lam, 1), r0 = (s, psi - mid psi, 0, E, dl), E the rest.  Returns {"set": the C^1 set,
    "Q": the hull (5 balls), "level_ok", "level": Nb, "level_centre": Nc, "tangent_lam": the chart vector (v, 0, 0,
    g_theta v + g_lam, 1) that contains d/dlambdabar of the box's points at fixed s (for the section derivative
    along lambdabar: the Newton's centre theta_c + v dl moves with it)}."""
    ps = branch_psi(branch)
    pars = fields.parameter_balls(p, lam_rad)
    pars_c = fields.parameter_balls(p)
    Lam = pars[fields.LAM]
    Dl = Lam - ball.q(p.lam)
    vq, S = ball.q(v), ball.interval(-s_rad, s_rad)
    if vq.rad() != 0:
        raise ValueError("v must be a dyadic rational (exact in binary)")
    th_h = ball.q(thc) + vq * Dl + S
    Nb, _, okb = level_newton_section(pars, h, th_h, arb(0), pc, prad, module, branch)
    Nc, _, okc = level_newton_section(pars_c, h, ball.q(thc), arb(0), pc, prad, module, branch)
    out = {"level_ok": bool(okb and okc), "level": Nb, "level_centre": Nc, "Q": [th_h, ps, arb(0), Nb, Lam]}
    if not out["level_ok"]:
        return out
    Q = [th_h, ps, arb(0), Nb]
    gH = ham_gradient(pars, Q, module)
    gth = -gH[TH] / gH[PP]
    glam = -ham_lam_derivative(pars, Q, module) / gH[PP]
    gtm, glm = gth.mid(), glam.mid()
    c_s = gtm.mid()
    c_l = (gtm * vq + glm).mid()  # exact entries of C; what rounding left goes into E
    # grouped by the variable each term multiplies, so that the linear parts cancel in the ball arithmetic
    E = (Nc - Nc.mid()) + (gth - c_s) * S + (gth * vq + glam - c_l) * Dl
    n = 5
    C = arb_mat(n, n)
    for i in range(n):
        C[i, i] = 1
    C[PP, TH] = c_s
    C[TH, 4], C[PP, 4] = vq, c_l
    xbar = [ball.q(thc), ps.mid(), arb(0), Nc.mid(), ball.q(p.lam)]
    r0 = ball.vec([S, ps - ps.mid(), arb(0), E, Dl])
    Sset = taylor.initial_set(xbar, c1=True)
    Sset.C, Sset.r0 = C, r0
    out["set"] = Sset
    out["tangent_lam"] = [vq, arb(0), arb(0), gth * vq + glam, arb(1)]
    return out


def ham_lam_derivative(pars, x, module=gen) -> arb:
    """dHbar/dlambdabar over the box x and lambdabar's ball in pars (a series in the parameter, as ham_gradient)."""
    q = list(pars)
    i = fields.PARAMS.index("lam")
    q[i] = arb_series([q[i], 1], prec=2)
    c = module.chart_hamiltonian(list(x), q)[0]
    cs = c.coeffs() if isinstance(c, arb_series) else [c]
    return cs[1] if len(cs) > 1 else arb(0)


def piece_sets(pars, h, fld, c, A, pc: Fraction, prad: Fraction, *, box=True, thin_c1=True, branch="0",
               moving: Moving | None = None, module=gen) -> dict:
    """The initial sets of piece_return's two flights, without flying them (the arguments as piece_return's): the
    level's Newton results ("level_ok", "ppsi_centre", "ppsi_hull"); when the level holds also the centre's chart
    set "thin_set", the piece's exact parallelepiped "box_set" (None for box False), its hull "Q" (5 balls with
    lambdabar when moving), the parameters and field of the box flight ("pars_b", "fld_b"), grad pbar_psi over the
    hull ("grad", with "glam" = d pbar_psi / d lambdabar when moving), and the box's exact lambdabar column
    "col_s" (None unless moving).  Also the set a flight of the piece's variational system starts from
    (kernel/horseshoe_lam2.py)."""
    out = {}
    glam = vq = None
    cq = [ball.q(v) for v in c]
    ps = branch_psi(branch)
    Nc, _, okc = level_newton_section(pars, h, cq[0], cq[1], pc, prad, module, branch)
    A00, A01, A10, A11 = (ball.q(A[i][j]) for i in range(2) for j in range(2))
    U = ball.interval(-1, 1)
    th_h = cq[0] + A00 * U + A01 * U
    pt_h = cq[1] + A10 * U + A11 * U
    pars_b, fld_b, xl = pars, fld, []
    if moving is not None:  # the hull over lambdabar: the piece moves by v (lambdabar - lam0)
        Dl = moving.lam - ball.q(moving.lam0)
        vq = [ball.q(x) for x in moving.v]
        th_h, pt_h = th_h + vq[0] * Dl, pt_h + vq[1] * Dl
        pars_b, fld_b, xl = moving.pars, moving.fld, [moving.lam]
    Nb, _, okb = level_newton_section(pars_b, h, th_h, pt_h, pc, prad, module, branch)
    out["level_ok"] = bool(okc and okb)
    out["ppsi_centre"], out["ppsi_hull"] = Nc, Nb
    if not out["level_ok"]:
        return out
    Q = [th_h, ps, pt_h, Nb]
    gH = ham_gradient(pars_b, Q, module)
    grad = [-gH[TH] / gH[PP], -gH[PT] / gH[PP]]
    gm = [v.mid() for v in grad]
    col = [(A00, A10), (A01, A11)]
    E = (Nc - Nc.mid()) + sum(((grad[0] - gm[0]) * a + (grad[1] - gm[1]) * b) * U for a, b in col)
    n = 4 + len(xl)
    C = arb_mat(n, n)
    for i, row in enumerate([[A00, A01, 0, 0], [0, 0, 1, 0], [A10, A11, 0, 0],
                             [gm[0] * A00 + gm[1] * A10, gm[0] * A01 + gm[1] * A11, 0, 1]]):
        for j, x in enumerate(row):
            C[i, j] = x
    col_s = None
    if moving is not None:
        # pbar_psi(c + A u + v D, lam0 + D) - pbar_psi(c, lam0) = grad(xi) . (A u + v D) + g_lam(xi) D (mean value;
        # the root is unique in the Newton box over the hull): the lambdabar column (v, gm . v + g_lam_mid, 1)
        glam = -ham_lam_derivative(pars_b, Q, module) / gH[PP]
        glm = glam.mid()
        col_s = [vq[0], arb(0), vq[1], gm[0] * vq[0] + gm[1] * vq[1] + glm, arb(1)]
        for i, x in enumerate(col_s):
            C[i, 4] = x
        C[4, 4] = 1
        E = E + ((grad[0] - gm[0]) * vq[0] + (grad[1] - gm[1]) * vq[1] + (glam - glm)) * Dl
    if any(C[i, j].rad() != 0 for i in range(n) for j in range(n)):  # exact: g A rounded to a point matrix
        Cm = C.mid()
        E = E + sum(((gm[0] * a + gm[1] * b) - Cm[3, j]) * U for j, (a, b) in enumerate(col))
        if moving is not None:
            E = E + (C[3, 4] - Cm[3, 4]) * Dl
        C = Cm
    xbar = [ball.fraction(cq[0]), ball.fraction(ps.mid()), ball.fraction(cq[1]), ball.fraction(Nc.mid())]
    r0 = [U, U, ps - ps.mid(), E]  # psi = pi: the ball of pi about its exact midpoint (C's psi row e_psi)
    if moving is not None:
        xbar, r0 = xbar + [moving.lam0], r0 + [Dl]
    r0 = ball.vec(r0)
    thin_set = taylor.initial_set([cq[0], ps, cq[1], Nc], c1=thin_c1)
    box_set = section_set(pars_b, None, None, None, C2=(xbar, C, r0)) if box else None
    out.update(cq=cq, psi=ps, Nc=Nc, Q=Q + xl, pars_b=pars_b, fld_b=fld_b, grad=grad, glam=glam, vq=vq,
               col_s=col_s, thin_set=thin_set, box_set=box_set)
    return out


def piece_return(pars, h, fld, c, A, pc: Fraction, prad: Fraction, t_a: Fraction, lead: Fraction, *,
                 t1=Fraction(1, 64), order=20, tol=PROOF_STEP_TOL, tol_thin=None, steps=None, newton=12, box=True,
                 thin=None, thin_c1=True, branch="0", moving: Moving | None = None, module=gen,
                 integrator=taylor, thin_integrator=None) -> dict:
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
    1e-32: 5e-20, 2.3x the steps).  thin_c1 False: the centre flies as a C^0 set (no "DPc"; the verifier, which
    reads DP from the box only): the same state enclosures whenever the C^1 flight's a priori enclosure validates at
    its first trial (taylor.step_data; the C^0 test is a subset of the C^1 one), at ~3/4 of the cost.  moving (a
    Moving): the box flies over every lambdabar of moving.lam with the piece moving along v (its chart set xbar +
    C r0 gains the column (v, grad pbar_psi . (v, 1), 1) and the row lambdabar; the centre flies at lam0, with pars
    and fld, as without it), and the result has "dPds": the derivative of s -> P_s(c + v (s - lam0)) over the box
    (the section derivative along that column), so that P_s(X(s)) lies in Pc + DP A [-1, 1]^2 + dPds (s - lam0)
    for every s in lam.  integrator: taylor (default) or taylor_model, for both flights (first_return);
    thin_integrator: the centre's, if other.  Flight failures raise taylor's errors; the caller checks the signs."""
    out = piece_sets(pars, h, fld, c, A, pc, prad, box=box, thin_c1=thin_c1, branch=branch, moving=moving,
                     module=module)
    if not out["level_ok"]:
        return out
    ps_ = out
    out = {"level_ok": True, "ppsi_centre": ps_["ppsi_centre"], "ppsi_hull": ps_["ppsi_hull"]}
    cq, ps, Nc, Qx, pars_b, fld_b = (ps_[k] for k in ("cq", "psi", "Nc", "Q", "pars_b", "fld_b"))
    grad, glam, vq, col_s = ps_["grad"], ps_["glam"], ps_["vq"], ps_["col_s"]
    thin_set, box_set = ps_["thin_set"], ps_["box_set"]
    steps_out = {}
    if thin is not None:
        for key in ("Pc", "ppsi_thin", "DPc", "gdot_thin", "cospsi_thin"):
            if key in thin:
                out[key] = thin[key]
        steps_out["thin"] = thin["steps"]["thin"]
    todo = ([] if thin is not None else [("thin", thin_set)]) + ([("box", box_set)] if box else [])
    for kind, S in todo:
        st = None if steps is None else steps.get(kind)  # a kind missing: its steps adaptive
        tk = (tol_thin or tol) if kind == "thin" else tol
        pk, fk = (pars, fld) if kind == "thin" else (pars_b, fld_b)
        cr, used = first_return(pk, fk, S, t_a, lead, t1=t1, order=order, tol=tk, steps=st, newton=newton,
                                module=module,
                                integrator=(thin_integrator or integrator) if kind == "thin" else integrator)
        steps_out[kind] = used
        Qk = [cq[0], ps, cq[1], Nc] if kind == "thin" else Qx
        tg = tangents(pk, Qk, module)
        if kind == "box" and col_s is not None:
            # the exact column of C along lambdabar, with pbar_psi's row the enclosure of its derivative
            tg["s"] = col_s[:3] + [grad[0] * vq[0] + grad[1] * vq[1] + glam, arb(1)]
        q = section_quantities(None, fk, cr, tg, module)
        out[f"gdot_{kind}"], out[f"cospsi_{kind}"] = q["gdot"], q["cospsi"]
        if kind == "thin":
            out["Pc"] = (q["theta"], q["ptheta"])
            out["ppsi_thin"] = cr.x[PP]
            if cr.W is not None:
                out["DPc"] = [[q["dth_theta"], q["dpt_theta"]], [q["dth_ptheta"], q["dpt_ptheta"]]]
        else:
            out["DP"] = [[q["dth_theta"], q["dpt_theta"]], [q["dth_ptheta"], q["dpt_ptheta"]]]
            out["ppsi_box"] = cr.x[PP]
            out["tau_box"] = cr.tau
            if col_s is not None:
                out["dPds"] = (q["ds_theta"], q["ds_ptheta"])
    out["steps"] = steps_out
    return out
