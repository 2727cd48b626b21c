"""The Fig 4(a) interval horseshoe by second-order enclosures in lambdabar: what they cost and how wide they reach,
measured at the critical link N12 => N13 of horseshoe_fig4a_interval.json (research/README.md).

The interval certificate's enclosures are first order in the swept hull |v| W, and N13's inverse frame multiplies a
width in a generic direction by ~8e13 (its axes are 3e-3 rad apart), so its lambdabar term grows like W
(horseshoe_interval_limit.py: 5600x the exact term at W = 2e-11).  The decomposition that takes the lambdabar motion
out of the first-order enclosures:

  P_s(c(s) + A u) = P(c) + P'(0) s + [P''] s^2 / 2                  the centre curve, second order in s
                    + ([F_u at s = 0 over the piece] + [F_us over the swept box] s) A u

needs, per piece, P'(0) from a thin C^1 flight at lambdabar_c, [P''] from a C^1 flight of the variational system
y = (x, lambdabar, u_s) (10 states) along the centre curve, and [F_us] from a C^1 flight of y = (x, lambdabar, u_th,
u_pt) (15 states) over the swept box; the D^2 F[u] blocks by forward-mode duals of fields.lam_state_field.

  cost   : the three flights timed on N12's piece beside today's 5-state box flight (adaptive steps at the
           certificate's tol, Taylor-model integrator, to the return time t_a);
  curve  : the curve term in N13's stable coordinate, y_s(s) in Ai_s (P(c) - c13) + Ai_s (P'(0) - v13) s +
           Ai_s [P''] s^2 / 2, with [P''] by implicit differentiation at the crossing (section_second_derivative);
  nodes  : the same term from thin flights at K + 1 nodes and the interpolation error [P''] h^2 / 8 between them;
  spread : the shear term Ai_s [d_s (F_u A)] u s, [F_us] by the section's mixed second derivative;
  --chain: every link of the chain at W = 2e-9, K = 4, in two processes (horseshoe_second_order_chain.json).

A measurement, not a proof (the initial tangents as balls over the hull; no guards in the 10-state flight).

    python research/horseshoe_second_order.py [--out research/horseshoe_second_order.json] [--smoke]
    python research/horseshoe_second_order.py --chain [--out research/horseshoe_second_order_chain.json]
"""
import sys
import time
from fractions import Fraction as F
from pathlib import Path

from flint import arb

from magrod.proof import ball, fields, section_return as sr, taylor, taylor_model as tm
from magrod.proof.variational import (N, d2H, extended_set, moving_column, section_second_derivative,  # noqa: F401
                                     variational_field)
from magrod.proof.kernel.schema import frac

sys.path.insert(0, str(Path(__file__).resolve().parent))
from dp_second_order_prototype import capture_box, captured, load, piece  # noqa: E402  (the same harness)

ROOT = Path(__file__).resolve().parent.parent


def timed_flight(fld, S, t_end, s):
    rec = taylor.Trajectory()
    t0 = time.process_time()
    S = tm.propagate(fld, S, t_end, order=int(s['order']), tol=float(s['tol']), record=rec)
    return time.process_time() - t0, len(rec.steps), S


def cost(W=F(1, 500000000), smoke=False) -> dict:
    """CPU and steps of today's box flight and of the two variational flights on N12's piece (smoke: to t = 1/8)."""
    c, s, p = load("horseshoe_fig4a_interval")
    I = 12
    capture_box(N)
    rows = {}
    with ball.workprec(int(s['prec']), int(s['series_cap'])):
        r, cX, AX, _steps, br = piece(c, I)
        vI = tuple(frac(x) for x in c['sets'][I]['v'])
        pars = fields.parameter_balls(p, W)
        fld5 = fields.lam_state_field(p)
        mv = sr.Moving(tuple(pars), fld5, pars[fields.LAM], p.lam, vI)
        t_end = frac(r['t_a']) if not smoke else F(1, 8)
        # today's C^1 box flight of the moving piece (5 states), flown once to capture its initial set
        sr.piece_return(p.balls(), frac(c['level']), fields.chart_field(p), cX, AX, frac(r['p_c']),
                        frac(s['p_rad']), frac(r['t_a']), frac(s['lead']), t1=frac(s['t1']), order=int(s['order']),
                        tol=float(s['tol']), newton=int(s['newton']), thin_c1=False, branch=br, moving=mv,
                        integrator=tm, thin_integrator=tm)
        S5 = captured['box']
        Q = S5.hull()
        tg = sr.tangents(pars, Q)
        us = moving_column(pars, Q, vI)[3]
        cases = [("C1, 5 states: today's box flight over the swept box", fld5, S5),
                 ("C1, 10 states (x, lambdabar, u_s): the centre curve's [P'']", variational_field(fld5, 1),
                  extended_set(S5, [us], True)),
                 ("C1, 15 states (x, lambdabar, u_th, u_pt): [F_us] over the swept box", variational_field(fld5, 2),
                  extended_set(S5, [tg['th'], tg['pt']], True))]
        for name, fld, S in cases:
            S0 = taylor.C1Set(S.t, S.xbar, S.C, S.r0, S.B, S.r, S.Wbar, S.E)
            try:
                cpu, n, _ = timed_flight(fld, S0, t_end, s)
                rows[name] = {"cpu_s": round(cpu, 2), "steps": n}
            except (taylor.EnclosureError, taylor.GuardError) as e:
                rows[name] = {"failed": str(e)[:160]}
            print(name, rows[name], flush=True)
    return rows


def curve_term(W=F(1, 500000000), I=12, J=13):
    """The centre curve's image to second order in s at Fig 4(a)'s critical link N12 => N13, in N13's stable
    coordinate y_s: y_s(s) in Ai_s (P(c) - c13) + Ai_s (P'(0) - v13) s + Ai_s [P''] s^2 / 2 for s in [-W, W].

    P'(0): the thin C^1 flight at lambdabar_c (5 states), its section derivative along the curve's tangent.
    [P'']: the C^1 flight of y = (x, lambdabar, u_s) over the curve {c12 + v12 s} x {lambdabar_c + s} (10 states,
    the curve's tangent u_s and its s-derivative as balls over the curve), crossed with the 10-state field, and the
    section map's second derivative by implicit differentiation of sin psi(X(tau(s), s)) = 0:
      X' = u + f tau',  tau' = -u_psi / f_psi,
      X'' = du/ds + Df X' tau' + f tau'',  du/ds = d_s u + Df u tau',
      tau'' = -[cos psi (du/ds + Df X' tau')_psi - sin psi X'_psi^2] / (cos psi f_psi),
    P'' = (X''_theta, X''_pbar_theta), everything in balls over the crossing's enclosure.  Returns the terms."""
    from flint import arb_series

    from magrod.proof.kernel.horseshoe_sets import _hs_inv
    from magrod.proof.provers.section_horseshoe import set_data

    c, s, p = load("horseshoe_fig4a_interval")
    out = {"W": str(W)}
    with ball.workprec(int(s['prec']), int(s['series_cap'])):
        r, cX, AX, _steps, br = piece(c, I)
        vI = tuple(frac(x) for x in c['sets'][I]['v'])
        cM, AM = set_data(c['sets'][J])[:2]
        vM = [frac(x) for x in c['sets'][J]['v']]
        Ai_s = [ball.q(x) for x in _hs_inv(AM)[1]]
        pars = fields.parameter_balls(p, W)
        fld5 = fields.lam_state_field(p)
        mv = sr.Moving(tuple(pars), fld5, pars[fields.LAM], p.lam, vI)
        zero = [[F(0), F(0)], [F(0), F(0)]]
        capture_box(N)
        captured.clear()
        t0 = time.process_time()
        # the curve as a moving piece of zero extent: the thin flight at lambdabar_c gives P(c) (and, with C^1, P'(0)
        # below); the "box" is the curve's 5-state C^1 set, captured as the initial set of the 10-state flight
        f = sr.piece_return(p.balls(), frac(c['level']), fields.chart_field(p), cX, zero, frac(r['p_c']),
                            frac(s['p_rad']), frac(r['t_a']), frac(s['lead']), t1=frac(s['t1']), order=int(s['order']),
                            tol=float(s['tol']), newton=int(s['newton']), thin_c1=False, branch=br, moving=mv,
                            integrator=tm, thin_integrator=tm)
        out["cpu_5state_s"] = round(time.process_time() - t0, 2)
        S5 = captured['box']
        Q = S5.hull()
        gH, _g, _glam, us = moving_column(pars, Q, vI)
        vq = [ball.q(x) for x in vI]
        # d^2 pbar_psi / ds^2 along the curve: D^2 Hbar[x', x'] + Hbar_ppsi pbar_psi'' = 0 (x' = us)
        y = [arb_series([Q[i], us[i]], prec=3) for i in range(4)]
        q = list(pars)
        q[fields.LAM] = arb_series([pars[fields.LAM], 1], prec=3)
        Hs = fields.gen.chart_hamiltonian(y, q)[0]
        d2H = 2 * Hs.coeffs()[2] if len(Hs.coeffs()) > 2 else arb(0)
        xss = [arb(0), arb(0), arb(0), -d2H / gH[fields.PPSI], arb(0)]
        # P'(0): the centre at lambdabar_c, C^1, along the tangent at the centre
        S0 = taylor.initial_set([ball.q(cX[0]), arb(0), ball.q(cX[1]), f["ppsi_centre"], ball.q(p.lam)], c1=True)
        fl0 = fields.lam_state_field(p)
        t0 = time.process_time()
        cr0, _ = sr.first_return(p.balls(), fl0, S0, frac(r['t_a']), frac(s['lead']), t1=frac(s['t1']),
                                 order=int(s['order']), tol=float(s['tol']), newton=int(s['newton']), integrator=tm)
        Qc = [ball.q(cX[0]), arb(0), ball.q(cX[1]), f["ppsi_centre"]]
        gHc = sr.ham_gradient(p.balls(), Qc)
        glc = -sr.ham_lam_derivative(p.balls(), Qc) / gHc[fields.PPSI]
        usc = [vq[0], arb(0), vq[1], (-gHc[0] * vq[0] - gHc[2] * vq[1]) / gHc[fields.PPSI] + glc, arb(1)]
        q0 = sr.section_quantities(None, fl0, cr0, {"s": usc})
        out["cpu_thin_c1_s"] = round(time.process_time() - t0, 2)
        Pc = f["Pc"]
        dP0 = (q0["ds_theta"], q0["ds_ptheta"])
        # [P''] over the curve: the 10-state C^1 flight
        fld10 = variational_field(fld5, 1)
        S10 = extended_set(S5, [us], True)
        t0 = time.process_time()

        def g(Y):  # sin psi, the section
            return Y[1].sin()

        def dg(Y):
            return [arb(0), Y[1].cos()] + [arb(0)] * (len(Y) - 2)

        S10 = tm.propagate(fld10, S10, frac(s['t1']), order=int(s['order']), tol=float(s['tol']))
        S10 = tm.propagate(fld10, S10, frac(r['t_a']), order=int(s['order']), tol=float(s['tol']))
        cr = tm.cross_section(fld10, S10, g, dg, 2 * frac(s['lead']), int(s['order']), newton=int(s['newton']))
        out["cpu_10state_s"] = round(time.process_time() - t0, 2)
        x5, u = cr.x[:N], cr.x[N:]
        fx = cr.fx[:N]
        Df = fld5.df(x5)
        dY = ball.column(cr.W * ball.vec(us + xss))
        dus = dY[N:]
        P2 = section_second_derivative(x5, u, dus, fx, Df)[0]
        out["P2_raw"] = [v.str(20) for v in P2]
        ys0 = Ai_s[0] * (Pc[0] - ball.q(cM[0])) + Ai_s[1] * (Pc[1] - ball.q(cM[1]))
        ys1 = Ai_s[0] * (dP0[0] - ball.q(vM[0])) + Ai_s[1] * (dP0[1] - ball.q(vM[1]))
        ys2 = Ai_s[0] * P2[0] + Ai_s[1] * P2[1]
        Wq = ball.q(W)
        S_ = ball.interval(-W, W)
        bound = ys0 + ys1 * S_ + ys2 * S_ * S_ / 2  # s^2 as S_ * S_: a (loose) enclosure of [0, W^2]
        out.update({"y_s(0)": str(ys0), "y_s'(0) - v13 term": str(ys1), "[y_s'']": str(ys2),
                    "y_s'' width": float(ys2.rad()) * 2, "curve term |y_s| <=": float(ball.bounds(abs(bound))[1]),
                    "second-order term width": float((ys2 * Wq * Wq / 2).rad()) * 2})
    return out


def curve_nodes_term(W=F(1, 500000000), K=4, P2=None, I=12, J=13):
    """The centre curve's term with K sub-intervals: y_s at the nodes s_k = -W + 2 W k / K from thin flights at
    lambdabar_c + s_k (the curve's point c12 + v12 s_k), and between nodes the linear interpolant's error
    P''(xi) (s - s_k)(s - s_k+1) / 2, bounded by [y_s''] h^2 / 8 (h = 2 W / K; [y_s''] over the whole curve from
    curve_term, or P2 given).  Returns the bound of |y_s| over the curve and its parts."""
    from dataclasses import replace

    from magrod.proof.kernel.horseshoe_sets import _hs_inv
    from magrod.proof.provers.section_horseshoe import set_data

    if P2 is None:
        P2 = curve_term(W, I, J)["[y_s'']"]
    c, s, p = load("horseshoe_fig4a_interval")
    with ball.workprec(int(s['prec']), int(s['series_cap'])):
        r, cX, AX, _steps, br = piece(c, I)
        vI = [frac(x) for x in c['sets'][I]['v']]
        cM, AM = set_data(c['sets'][J])[:2]
        vM = [frac(x) for x in c['sets'][J]['v']]
        Ai_s = [ball.q(x) for x in _hs_inv(AM)[1]]
        zero = [[F(0), F(0)], [F(0), F(0)]]
        ys, cpu, raw = [], 0.0, []
        for k in range(K + 1):
            sk = -W + 2 * W * k / K
            pk = replace(p, lam=p.lam + sk)
            # the curve's point, rounded to a dyadic (the flights start from exact binary data; ~1e-40 off the curve)
            ck = [ball.fraction(ball.q(cX[m] + vI[m] * sk).mid()) for m in (0, 1)]
            pc = frac(r['p_c'])  # the level's root at the node, to the working precision (Newton from the centre's)
            for _ in range(3):
                pc = ball.fraction(sr.level_newton_section(pk.balls(), frac(c['level']), ball.q(ck[0]), ball.q(ck[1]),
                                                           pc, frac(s['p_rad']), branch=br)[0].mid())
            t0 = time.process_time()
            f = sr.piece_return(pk.balls(), frac(c['level']), fields.chart_field(pk), ck, zero, pc,
                                frac(s['p_rad']), frac(r['t_a']), frac(s['lead']), t1=frac(s['t1']),
                                order=int(s['order']), tol=float(s['tol']), newton=int(s['newton']), box=False,
                                thin_c1=False, branch=br, integrator=tm, thin_integrator=tm)
            cpu += time.process_time() - t0
            d = [f["Pc"][m] - ball.q(cM[m]) - ball.q(vM[m] * sk) for m in (0, 1)]
            ys.append(Ai_s[0] * d[0] + Ai_s[1] * d[1])
            raw.append([v.str(40) for v in f["Pc"]])
        h = 2 * W / K
        err = abs(arb(P2)) * ball.q(h * h / 8)
        node = max(float(ball.bounds(abs(y))[1]) for y in ys)
    return {"W": str(W), "K": K, "nodes_raw": raw, "nodes |y_s| <=": node, "interpolation error <=": float(ball.bounds(err)[1]),
            "curve term |y_s| <=": node + float(ball.bounds(err)[1]), "cpu_nodes_s": round(cpu, 2),
            "y_s at nodes": [str(y) for y in ys]}


def spread_term(W=F(1, 500000000), I=12, J=13):
    """The piece's own extent, second order: the shear term Ai_s [d_s (F_u A)] u s of N12's piece in N13's stable
    coordinate, [F_us] from the C^1 flight of y = (x, lambdabar, u_th, u_pt) (15 states) over the swept box and the
    mixed second derivative of the section map (section_second_derivative with ua).  The tangents t_a = e_a + g_a
    e_ppsi (g_a = -Hbar_a / Hbar_ppsi) as balls over the hull, their s-derivative d_s g_a along the box's lambdabar
    column by D^2 Hbar.  Returns its bound beside the exact shear (horseshoe_interval_limit.py: ~3e5 W)."""
    from magrod.proof.kernel.horseshoe_sets import _hs_inv
    from magrod.proof.provers.section_horseshoe import set_data

    c, s, p = load("horseshoe_fig4a_interval")
    out = {"W": str(W)}
    capture_box(N)
    captured.clear()
    with ball.workprec(int(s['prec']), int(s['series_cap'])):
        r, cX, AX, _steps, br = piece(c, I)
        vI = tuple(frac(x) for x in c['sets'][I]['v'])
        AM = set_data(c['sets'][J])[1]
        Ai_s = [ball.q(x) for x in _hs_inv(AM)[1]]
        pars = fields.parameter_balls(p, W)
        fld5 = fields.lam_state_field(p)
        mv = sr.Moving(tuple(pars), fld5, pars[fields.LAM], p.lam, vI)
        sr.piece_return(p.balls(), frac(c['level']), fields.chart_field(p), cX, AX, frac(r['p_c']), frac(s['p_rad']),
                        frac(r['t_a']), frac(s['lead']), t1=frac(s['t1']), order=int(s['order']), tol=float(s['tol']),
                        newton=int(s['newton']), thin_c1=False, branch=br, moving=mv, integrator=tm,
                        thin_integrator=tm)
        S5 = captured['box']
        Q = S5.hull()
        gH, _g, _glam, col = moving_column(pars, Q, vI)
        Hp = gH[fields.PPSI]
        tg = sr.tangents(pars, Q)
        e_pp = [arb(0), arb(0), arb(0), arb(1), arb(0)]
        dts = []
        for a, ea in ((fields.THETA, [arb(1), arb(0), arb(0), arb(0), arb(0)]),
                      (fields.PTHETA, [arb(0), arb(0), arb(1), arb(0), arb(0)])):
            # d_s g_a = -(D^2H[e_a, col] Hp - H_a D^2H[e_ppsi, col]) / Hp^2
            dg = -(d2H(pars, Q[:4], ea, col) * Hp - gH[a] * d2H(pars, Q[:4], e_pp, col)) / (Hp * Hp)
            dts.append([arb(0), arb(0), arb(0), dg, arb(0)])
        fld15 = variational_field(fld5, 2)
        S15 = extended_set(S5, [tg['th'], tg['pt']], True)
        t0 = time.process_time()
        S15 = tm.propagate(fld15, S15, frac(s['t1']), order=int(s['order']), tol=float(s['tol']))
        S15 = tm.propagate(fld15, S15, frac(r['t_a']), order=int(s['order']), tol=float(s['tol']))

        def gsec(Y):  # sin psi, the section
            return Y[1].sin()

        def dgsec(Y):
            return [arb(0), Y[1].cos()] + [arb(0)] * (len(Y) - 2)

        cr = tm.cross_section(fld15, S15, gsec, dgsec, 2 * frac(s['lead']), int(s['order']), newton=int(s['newton']))
        out["cpu_15state_s"] = round(time.process_time() - t0, 2)
        x5, fx = cr.x[:N], cr.fx[:N]
        Df = fld5.df(x5)
        dY = ball.column(cr.W * ball.vec(col + dts[0] + dts[1]))
        us, w = dY[:N], (dY[N:2 * N], dY[2 * N:])
        ua = (cr.x[N:2 * N], cr.x[2 * N:])
        Fas = [section_second_derivative(x5, us, w[k], fx, Df, ua=ua[k])[0] for k in (0, 1)]  # (d theta', d pt')
        out["Fas_raw"] = [[v.str(20) for v in Fa] for Fa in Fas]
        out["swept"] = {"gdot": cr.gdot.str(10), "cospsi": x5[1].cos().str(10)}
        # d_s of F_u A's columns (A = the piece's frame in (theta, pbar_theta)), in N13's stable coordinate
        shear = arb(0)
        rows = []
        for j in (0, 1):
            a0, a1 = ball.q(AX[0][j]), ball.q(AX[1][j])
            v = [a0 * Fas[0][m] + a1 * Fas[1][m] for m in (0, 1)]
            ys = Ai_s[0] * v[0] + Ai_s[1] * v[1]
            rows.append(str(ys))
            shear = shear + abs(ys)
        Wq = ball.q(W)
        out.update({"d_s G_s-row (y_s per unit s)": rows, "shear term |y_s| <=": float(ball.bounds(shear * Wq)[1]),
                    "exact shear (quad, ~3e5 W)": 3e5 * float(W)})
    return out


def source_enclosures(args) -> dict:
    """Every enclosure the second-order check of N_I's piece reads, at W with K nodes (strings of balls):
    the node images P(c(s_k), s_k), [P''] over the curve, DP over the piece at lambdabar_c (the point box flight)
    and [F_as] over the swept box (a = theta, pbar_theta)."""
    W, K, I = args
    c, s, p = load("horseshoe_fig4a_interval")
    J = I + 1 if I + 1 < len(c["sets"]) else 0  # any target: only the raw enclosures are kept
    cv = curve_term(W, I, J)
    nd = curve_nodes_term(W, K, cv["[y_s'']"], I, J)
    sp = spread_term(W, I, J)
    with ball.workprec(int(s['prec']), int(s['series_cap'])):
        r, cX, AX, _steps, br = piece(c, I)
        t0 = time.process_time()
        f = sr.piece_return(p.balls(), frac(c['level']), fields.chart_field(p), cX, AX, frac(r['p_c']),
                            frac(s['p_rad']), frac(r['t_a']), frac(s['lead']), t1=frac(s['t1']), order=int(s['order']),
                            tol=float(s['tol']), newton=int(s['newton']), thin_c1=False, branch=br, integrator=tm,
                            thin_integrator=tm)
        cpu_box = time.process_time() - t0
        DP = [[v.str(20) for v in row] for row in f["DP"]]
    return {"set": I, "nodes": nd["nodes_raw"], "P2": cv["P2_raw"], "DP": DP, "Fas": sp["Fas_raw"],
            "cpu_s": round(cv["cpu_10state_s"] + nd["cpu_nodes_s"] + sp["cpu_15state_s"] + cpu_box, 1)}


def link_check(enc: dict, J: int, W, K: int) -> dict:
    """The covering conditions of N_I => N_J for every lambdabar in [lam_c - W, lam_c + W], from the source's
    enclosures (source_enclosures), sub-interval by sub-interval, in N_J's moving coordinates y = A_J^-1 (P - c_J -
    v_J s): on [s_k, s_k+1] the centre curve is the linear interpolant of the node images plus [P''] [-h^2/8, 0]
    (affine in s, so its range is the hull at the two nodes), the piece adds (DP_0 + [F_us] [s_k, s_k+1]) A_X U.
    (a): |y_s| < 1 over the piece; (b): the exit edges' y_u beyond +-1 on opposite sides.  Returns the smallest
    (a) margin and (b) |y_u| over the sub-intervals."""
    from magrod.proof.kernel.horseshoe_sets import _hs_inv
    from magrod.proof.provers.section_horseshoe import set_data

    c, s, p = load("horseshoe_fig4a_interval")
    I = enc["set"]
    with ball.workprec(int(s['prec']), int(s['series_cap'])):
        _r, _cX, AX, _steps, _br = piece(c, I)
        cM, AM = set_data(c['sets'][J])[:2]
        vM = [frac(x) for x in c['sets'][J]['v']]
        Ai = [[ball.q(x) for x in row] for row in _hs_inv(AM)]
        nodes = [[arb(v) for v in P] for P in enc["nodes"]]
        P2 = [arb(v) for v in enc["P2"]]
        DP = [[arb(v) for v in row] for row in enc["DP"]]
        Fas = [[arb(v) for v in Fa] for Fa in enc["Fas"]]
        U = ball.interval(-1, 1)
        h = 2 * W / K
        a_min, b_min = 2.0, float("inf")
        for k in range(K):
            sk = [-W + 2 * W * m / K for m in (k, k + 1)]
            ends = []
            for m, sv in zip((k, k + 1), sk):
                d = [nodes[m][a] - ball.q(cM[a]) - ball.q(vM[a] * sv) for a in (0, 1)]
                ends.append([Ai[b][0] * d[0] + Ai[b][1] * d[1] for b in (0, 1)])
            e = [x * ball.interval(-h * h / 8, 0) for x in P2]
            Ae = [Ai[b][0] * e[0] + Ai[b][1] * e[1] for b in (0, 1)]
            off = [ball.hull(ends[0][b], ends[1][b]) + Ae[b] for b in (0, 1)]
            S = ball.interval(sk[0], sk[1])
            # F_u over the piece for s in the sub-interval, applied to A_X's columns, in N_J's coordinates
            M = [[DP[a][t] + (Fas[t][a]) * S for t in (0, 1)] for a in (0, 1)]  # M[a][t] = d P_a / d x_t
            DA = [[M[a][0] * ball.q(AX[0][col]) + M[a][1] * ball.q(AX[1][col]) for col in (0, 1)] for a in (0, 1)]
            G = [[Ai[b][0] * DA[0][col] + Ai[b][1] * DA[1][col] for col in (0, 1)] for b in (0, 1)]
            ys = off[1] + G[1][0] * U + G[1][1] * U
            lo, hi = ball.bounds(ys)
            a_min = min(a_min, 1 - max(abs(lo), abs(hi)))
            right = off[0] + G[0][0] + G[0][1] * U
            left = off[0] - G[0][0] + G[0][1] * U
            rl, rh = ball.bounds(right)
            ll, lh = ball.bounds(left)
            if rl > 1 and lh < -1:
                b_min = min(b_min, rl, -lh)
            elif rh < -1 and ll > 1:
                b_min = min(b_min, -rh, ll)
            else:
                b_min = min(b_min, 0.0)
    return {"link": f"N{I} => N{J}", "a_margin": round(float(a_min), 4), "b_min_abs_yu": round(float(b_min), 3)}


def chain_check(W=F(1, 2**29), K=4, workers=2) -> list:
    """source_enclosures for every set (in spawned processes), then link_check for every link of the chain."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    c, _s, _p = load("horseshoe_fig4a_interval")
    links = [(int(a), int(b)) for a, b in c["links"]]
    sources = sorted({a for a, _ in links})
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn")) as ex:
        encs = {e["set"]: e for e in ex.map(source_enclosures, [(W, K, i) for i in sources])}
    rows = []
    for a, b in links:
        row = link_check(encs[a], b, W, K)
        row["cpu_s"] = encs[a]["cpu_s"]
        rows.append(row)
        print(row, flush=True)
    return rows


def link_estimate(args) -> dict:
    """One link N_I => N_J of the chain at W with K nodes: the curve term (nodes + interpolation), the shear term,
    and the point certificate's (a') margin there; the estimated interval margin is the point margin minus what
    the curve term adds to the centre's offset (its bound less |y_s(0)|) minus the shear term."""
    W, K, I, J = args
    import json as _json

    point = _json.loads((ROOT / "magrod" / "proof" / "certificates" / "horseshoe_fig4a.json").read_text())
    pm = [m for m in point["link_margins"] if (m["from"], m["to"]) == (I, J)][0]["a_margin"]
    cv = curve_term(W, I, J)
    nd = curve_nodes_term(W, K, cv["[y_s'']"], I, J)
    sp = spread_term(W, I, J)
    y0 = float(ball.bounds(abs(arb(cv["y_s(0)"])))[1])
    est = pm - (nd["curve term |y_s| <="] - y0) - sp["shear term |y_s| <="]
    return {"link": f"N{I} => N{J}", "point a_margin": round(pm, 4), "curve term": nd["curve term |y_s| <="],
            "shear term": sp["shear term |y_s| <="], "estimated a_margin": round(est, 4),
            "cpu_s": round(cv["cpu_5state_s"] + cv["cpu_thin_c1_s"] + cv["cpu_10state_s"] + nd["cpu_nodes_s"]
                           + sp["cpu_15state_s"], 1)}


def chain(W=F(1, 500000000), K=4, workers=2) -> list:
    """link_estimate for every link of the Fig 4(a) chain (N0 => N0, N0 => N1, ..., N13 => N14), in processes."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    c, _s, _p = load("horseshoe_fig4a_interval")
    links = [(int(a), int(b)) for a, b in c["links"]]
    # spawned, not forked (as magrod's own pools): a forked child shares the parent's open libraries' state
    with ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn")) as ex:
        return list(ex.map(link_estimate, [(W, K, a, b) for a, b in links]))


def main(argv=None):
    import argparse
    import json

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    ap.add_argument("--smoke", action="store_true", help="the flights' cost to t = 1/8 only (seconds)")
    ap.add_argument("--chain", action="store_true", help="every link of the chain at W = 2e-9, K = 4 (~5 min)")
    ap.add_argument("--check", action="store_true", help="the covering conditions of every link at --W, --K, sub-interval"
                    " by sub-interval (~5 min)")
    ap.add_argument("--W", default="1/536870912", help="the interval's radius for --check (dyadic; default 2^-29)")
    ap.add_argument("--K", type=int, default=4, help="the number of sub-intervals for --check (default 4)")
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    if a.check:
        rows = chain_check(F(a.W), a.K)
        out = {"certificate": "horseshoe_fig4a_interval.json", "W": a.W, "K": a.K, "links": rows,
               "wall_s": round(time.perf_counter() - t0, 1), "date": time.strftime("%Y-%m-%d")}
        if a.out:
            Path(a.out).write_text(json.dumps(out, indent=1) + "\n")
        return out
    if a.chain:
        rows = chain()
        for row in rows:
            print(row, flush=True)
        out = {"certificate": "horseshoe_fig4a_interval.json", "W": "1/500000000", "K": 4, "links": rows,
               "wall_s": round(time.perf_counter() - t0, 1), "date": time.strftime("%Y-%m-%d")}
        if a.out:
            Path(a.out).write_text(json.dumps(out, indent=1) + "\n")
        return out
    out = {"certificate": "horseshoe_fig4a_interval.json", "link": "N12 => N13", "cost_W": "1/500000000",
           "cost": cost(smoke=a.smoke)}
    if not a.smoke:
        out["curve"] = [curve_term(F(w)) for w in ("1/2000000000", "1/1000000000", "1/500000000")]
        for row in out["curve"]:
            print({k: row[k] for k in ("W", "[y_s'']", "curve term |y_s| <=")}, flush=True)
        out["curve_nodes"] = [curve_nodes_term(F(1, 500000000), K, out["curve"][-1]["[y_s'']"]) for K in (4, 8)]
        for row in out["curve_nodes"]:
            print({k: v for k, v in row.items() if k != "y_s at nodes"}, flush=True)
        out["spread"] = [spread_term(F(w)) for w in ("1/2000000000", "1/500000000")]
        for row in out["spread"]:
            print(row, flush=True)
    out["wall_s"] = round(time.perf_counter() - t0, 1)
    out["date"] = time.strftime("%Y-%m-%d")
    if a.out:
        Path(a.out).write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    main()
