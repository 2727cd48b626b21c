"""Kind "section_horseshoe" on a lambdabar interval to second order (settings "lam_order": 2; the prover is
provers/horseshoe_widen.py with order 2): the checks of one set as a source, sub-interval by sub-interval.

The first-order interval certificate encloses each piece's image over the whole interval by one flight of the
piece's box swept over lambdabar: its derivative enclosures grow with the swept hull |v| W, and N13's inverse frame
multiplies a width in a generic direction by ~8e13, so Fig 4(a) holds only to W ~ 3e-11 that way.  Here the image
of the piece X(s) = c_X + v s + A_X u (s = lambdabar - lam, |s| <= W, u in [-1, 1]^2) is split as

    P_s(X(s)) = gamma(s) + M(u, s) A_X u,    gamma(s) = P_s(c_X + v s)            (the centre curve)

and enclosed per sub-interval S_k = [s_k, s_k+1] of K equal ones (s_k = -W + 2 W k / K, exact; K is the piece's
"lam_nodes", else the settings'; the prover doubles it where a link needs it):
  * the curve: gamma at the K + 1 nodes by thin flights at lambdabar = lam + s_k (exact); between nodes gamma(s) =
    its linear interpolant + gamma''(xi) (s - s_k)(s - s_k+1) / 2, in [P''] [-h^2 / 8, 0] (h = 2 W / K) per
    component, [P''] over the whole curve from the C^1 flight of the 10-state variational system (x, lambdabar,
    d_s x) and the section map's second derivative by implicit differentiation (variational.py);
  * the piece: M(u, s) = the mean over [0, u] of DP_s(X(u', s)), and DP_s(X(u, s)) = DP_0(X(u, 0)) + F_us(xi) s
    with DP_0 over the piece at lambdabar = lam (the point box flight) and [F_us] = d_s DP over the swept box from
    the C^1 flight of the 15-state system (x, lambdabar, d_theta x, d_pbar_theta x) and the mixed second
    derivative, so M(u, s) A_X lies in (DP_0 + [F_us] S_k) A_X on S_k.
In N_J's moving coordinates y = A_J^-1 (P - c_J - v_J s) the interpolant minus c_J + v_J s is affine in s, so its
range over S_k is the hull of its node values.  The covering conditions (a) and (b) are then checked on every
sub-interval.  The 15-state flight's crossing encloses every point of the swept piece: its sign of cos psi, its
pbar_psi and its transversality are the branch, level and positive-return checks of the whole piece; the four
flight kinds all fly with the first return's guards (section_return.first_return), so each crossing is the first
return of P for every point and lambdabar they carry.

fly_piece is also the prover's flight (steps None: adaptive, recorded): one computation, replayed here with the
certificate's exact steps.
"""
from __future__ import annotations

import dataclasses
from fractions import Fraction

from flint import arb

from .. import ball, fields, section_return, taylor, variational
from .horseshoe_sets import _hs_graph, _hs_inv, _hs_lam, _hs_set, _hs_source, lam_order
from .schema import frac

N = variational.N
#: the flight kinds of one piece besides its K + 1 nodes, in the order flown
KINDS = ("box", "curve", "swept")


def nodes(W: Fraction, K: int) -> list:
    """The sub-intervals' end points s_k = -W + 2 W k / K, k = 0 .. K (exact)."""
    return [-W + 2 * W * k / K for k in range(K + 1)]


def lam2_settings(cert) -> tuple:
    """(W, K) of a second-order interval certificate: lam_rad > 0 dyadic (the nodes' points c_X + v s_k are then
    exact in binary) and an even number of sub-intervals K in 2 .. 64 (the middle node is the point certificate's
    centre at lambdabar = lam)."""
    s = cert["settings"]
    W = frac(s.get("lam_rad", "0"))
    if W <= 0 or W.denominator & (W.denominator - 1):
        raise ValueError(f"lam_order 2 needs lam_rad > 0 and dyadic (its nodes' points exact), got {W}")
    return W, sub_intervals(s.get("lam_nodes"))


def sub_intervals(K) -> int:
    """K, the number of sub-intervals (settings "lam_nodes", or a piece's own): an even integer in 2 .. 64."""
    if not isinstance(K, int) or isinstance(K, bool) or K < 2 or K % 2 or K > 64:
        raise ValueError(f"lam_nodes must be an even integer in 2 .. 64, got {K!r}")
    return K


def _fields(p, s, module):
    """The chart field at lam and the lambdabar-state field, their Taylor coefficients by Newton's iteration on
    series whenever a Taylor-model integrator flies them (as the prover's, provers/flights.prover_field)."""
    f0, fl = fields.chart_field(p, module), fields.lam_state_field(p, module)
    if "taylor_model" in (s.get("integrator"), s.get("thin_integrator")):
        f0, fl = (dataclasses.replace(f, series="newton") for f in (f0, fl))
    return f0, fl


def fly_piece(p, h, s, cX, AX, v, W, K, p_c, nodes_pc, t_a, branch, module=fields.gen, steps=None,
              node_tol=None) -> dict:
    """The flights of one piece X(s) = c_X + v s + A_X [-1, 1]^2 over |s| <= W (module docstring) and the enclosures
    the checks read, at the working precision.  p: the exact parameters at lam; s: the certificate's settings; p_c:
    the level's Newton centre over the piece, nodes_pc[k] at node k; steps: None (adaptive at the settings'
    tolerances; the prover) or {"nodes": [[phase 1, phase 2]] * (K + 1), "box", "curve", "swept": [phase 1, phase 2]}
    (exact steps; the verifier); node_tol: the adaptive step tolerance of the nodes other than the middle one
    (default the settings' tol_thin; the prover passes tol: their images need ~1e-20, not the centre's ~1e-25).
    Returns {"nodes": [{"Pc", "gdot", "cospsi", "ppsi", "level_ok"}], "box": {"DP", "gdot",
    "cospsi", "level_ok"}, "curve": {"P2", "gdot", "ppsi_hull", "level_ok"}, "swept": {"Fas", "gdot", "cospsi", "ppsi",
    "ppsi_hull", "level_ok"}, "steps"}; a flight whose level fails stops there ("level_ok" False).  Raises taylor's
    errors when a flight fails."""
    prad, t1, lead = (frac(s[kk]) for kk in ("p_rad", "t1", "lead"))
    order, newton = int(s["order"]), int(s["newton"])
    tol = float(s["tol"])
    tol_thin = float(s.get("tol_thin", s["tol"]))
    integ = section_return.integrator(s.get("integrator", "taylor"))
    thin_integ = section_return.integrator(s.get("thin_integrator", "taylor"))
    zero = [[Fraction(0), Fraction(0)], [Fraction(0), Fraction(0)]]
    sk = nodes(W, K)
    out = {"nodes": [], "steps": {"nodes": []}}
    st = steps or {}

    def fail(where):
        out[where] = {"level_ok": False}
        return out

    # the nodes: thin flights at lambdabar = lam + s_k from c_X + v s_k; the middle one with the point piece's box
    for k, sv in enumerate(sk):
        pk = dataclasses.replace(p, lam=p.lam + sv)
        fk = _fields(pk, s, module)[0]
        mid = k == K // 2
        want = None if steps is None else {"thin": st["nodes"][k], **({"box": st["box"]} if mid else {})}
        f = section_return.piece_return(
            pk.balls(), h, fk, [cX[0] + v[0] * sv, cX[1] + v[1] * sv], AX if mid else zero, nodes_pc[k], prad, t_a,
            lead, t1=t1, order=order, tol=tol, tol_thin=tol_thin if mid or node_tol is None else node_tol,
            steps=want, newton=newton, box=mid,
            thin_c1=False, branch=branch, module=module, integrator=integ, thin_integrator=thin_integ)
        if not f["level_ok"]:
            out["nodes"].append({"level_ok": False})
            return out
        out["nodes"].append({"Pc": f["Pc"], "gdot": f["gdot_thin"], "cospsi": f["cospsi_thin"],
                             "ppsi": f["ppsi_centre"], "level_ok": True})
        out["steps"]["nodes"].append(f["steps"]["thin"])
        if mid:
            out["box"] = {"DP": f["DP"], "gdot": f["gdot_box"], "cospsi": f["cospsi_box"], "ppsi": f["ppsi_box"],
                          "level_ok": True}
            out["steps"]["box"] = f["steps"]["box"]
    pars0 = p.balls()
    parsW = fields.parameter_balls(p, W)
    f0, fL = _fields(p, s, module)
    mv = section_return.Moving(tuple(parsW), fL, parsW[fields.LAM], p.lam, tuple(v))

    def fly(kind, fld, S):
        cr, used = section_return.first_return(parsW, fld, S, t_a, lead, t1=t1, order=order, tol=tol,
                                               steps=st.get(kind), newton=newton, module=module, integrator=integ)
        out["steps"][kind] = used
        x5 = cr.x[:N]
        return cr, x5, cr.fx[:N], fL.df(x5)

    # the centre curve c_X + v s, s in [-W, W]: the 10-state flight (x, lambdabar, u_s = d_s x) for [P'']
    ps = section_return.piece_sets(pars0, h, f0, cX, zero, p_c, prad, branch=branch, moving=mv, module=module)
    if not ps["level_ok"]:
        return fail("curve")
    Q = ps["Q"]
    gH, _g, _gl, us = variational.moving_column(parsW, Q, v, module)
    # d_s^2 of the initial point: only pbar_psi's (theta, pbar_theta, lambdabar are affine in s), from
    # D^2 Hbar[x', x'] + Hbar_ppsi pbar_psi'' = 0 on the level
    xss = [arb(0), arb(0), arb(0), -variational.d2H(parsW, Q[:4], us, us, module) / gH[fields.PPSI], arb(0)]
    cr, x5, fx, Df = fly("curve", variational.variational_field(fL, 1),
                         variational.extended_set(ps["box_set"], [us], True))
    dY = ball.column(cr.W * ball.vec(us + xss))
    P2 = variational.section_second_derivative(x5, cr.x[N:], dY[N:], fx, Df)[0]
    out["curve"] = {"P2": P2, "gdot": cr.gdot, "ppsi_hull": ps["ppsi_hull"], "level_ok": True}
    # the piece swept over [-W, W]: the 15-state flight (x, lambdabar, u_theta, u_pbar_theta) for [F_us]
    ps = section_return.piece_sets(pars0, h, f0, cX, AX, p_c, prad, branch=branch, moving=mv, module=module)
    if not ps["level_ok"]:
        return fail("swept")
    Q = ps["Q"]
    gH, _g, _gl, col = variational.moving_column(parsW, Q, v, module)
    Hp = gH[fields.PPSI]
    tg = section_return.tangents(parsW, Q, module)
    e_pp = [arb(0), arb(0), arb(0), arb(1), arb(0)]
    dts = []
    for a, ea in ((fields.THETA, [arb(1), arb(0), arb(0), arb(0), arb(0)]),
                  (fields.PTHETA, [arb(0), arb(0), arb(1), arb(0), arb(0)])):
        # the tangent t_a = e_a + g_a e_ppsi (g_a = -Hbar_a / Hbar_ppsi) moves with s: d_s g_a by the quotient rule
        dg = -(variational.d2H(parsW, Q[:4], ea, col, module) * Hp
               - gH[a] * variational.d2H(parsW, Q[:4], e_pp, col, module)) / (Hp * Hp)
        dts.append([arb(0), arb(0), arb(0), dg, arb(0)])
    cr, x5, fx, Df = fly("swept", variational.variational_field(fL, 2),
                         variational.extended_set(ps["box_set"], [tg["th"], tg["pt"]], True))
    dY = ball.column(cr.W * ball.vec(col + dts[0] + dts[1]))
    Fas = [variational.section_second_derivative(x5, dY[:N], dY[N * (a + 1): N * (a + 2)], fx, Df,
                                                 ua=cr.x[N * (a + 1): N * (a + 2)])[0] for a in (0, 1)]
    out["swept"] = {"Fas": Fas, "gdot": cr.gdot, "cospsi": x5[fields.PSI].cos(), "ppsi": x5[fields.PPSI],
                    "ppsi_hull": ps["ppsi_hull"], "level_ok": True}
    return out


def piece_data(cert, i, n) -> dict:
    """Piece n of set N_i as fly_piece reads it from a second-order certificate: its frame (c_X, A_X), its number
    of sub-intervals K (the piece's "lam_nodes", else the settings'), p_c, the nodes' p_c, t_a, and the exact
    steps."""
    c, A = _hs_set(cert["sets"][i])
    r = {int(f["set"]): f for f in cert["flights"]}[i]["pieces"][n]
    yu, ys, hu, hs = (frac(x) for x in r["piece"])
    cX = [c[0] + A[0][0] * yu + A[0][1] * ys, c[1] + A[1][0] * yu + A[1][1] * ys]
    AX = [[A[0][0] * hu, A[0][1] * hs], [A[1][0] * hu, A[1][1] * hs]]
    st = r["steps"]
    steps = {"nodes": [[[frac(x) for x in ph] for ph in nd] for nd in st["nodes"]],
             **{kk: [[frac(x) for x in ph] for ph in st[kk]] for kk in KINDS}}
    return {"piece": (yu, ys, hu, hs), "cX": cX, "AX": AX, "p_c": frac(r["p_c"]),
            "K": sub_intervals(r.get("lam_nodes", cert["settings"].get("lam_nodes"))),
            "nodes_pc": [frac(x) for x in r["nodes_p_c"]], "t_a": frac(r["t_a"]), "steps": steps}


def set_source(cert, i, order, module, claim, branch) -> None:
    """The checks of set N_i as a source, whatever the certificate: second order in lambdabar (source, here) or not
    (horseshoe_sets._hs_source); the serial verifier and the child processes of pool.py both call this."""
    if lam_order(cert) == 2:
        return source(cert, i, module, claim, branch)
    return _hs_source(cert, i, order, module, claim, branch)


def source(cert, i, module, claim, branch) -> None:
    """The checks of set N_i as a source on a second-order certificate, in the verifier's order: its pieces re-flown
    with the certificate's steps (steps, level, positive return), then every link N_i => N_j (link_checks)."""
    s = cert["settings"]
    W, _K = lam2_settings(cert)
    h = frac(cert["level"])
    t1 = frac(s["t1"])
    p = fields.ExactParams(**{kk: frac(cert["params"][kk]) for kk in fields.PARAMS})
    sets = [_hs_set(d) for d in cert["sets"]]
    brs = [d.get("branch", "0") for d in cert["sets"]]
    v = _hs_lam(cert, p, module)[4][i]
    fl = {int(f["set"]): f for f in cert["flights"]}[i]
    images = []
    for n in range(len(fl["pieces"])):
        d = piece_data(cert, i, n)
        st, t_a, K = d["steps"], d["t_a"], d["K"]
        claim(f"N{i} piece {n} nodes", len(st["nodes"]) == K + 1 == len(d["nodes_pc"]) and
              d["nodes_pc"][K // 2] == d["p_c"], f"K + 1 = {K + 1} nodes (K = {K} sub-intervals), the middle one at "
              "the piece's p_c")
        for kk, phs in [(f"node {k}", ph) for k, ph in enumerate(st["nodes"])] + [(kk, st[kk]) for kk in KINDS]:
            claim(f"N{i} piece {n} {kk} steps", len(phs) == 2 and sum(phs[0]) == t1 and sum(phs[0]) + sum(phs[1])
                  == t_a and all(x > 0 for ph in phs for x in ph),
                  "phase 1 on [0, t1], phase 2 on [t1, t_a], positive exact steps")
        try:
            f = fly_piece(p, h, s, d["cX"], d["AX"], v, W, K, d["p_c"], d["nodes_pc"], t_a, brs[i], module, st)
        except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
            claim(f"N{i} piece {n} flight", False, str(err)[:200])
        check_piece(i, n, f, branch, claim)
        images.append((d["piece"], d["AX"], f, K))
    for src, j in _hs_graph(cert, len(sets))[1]:
        if src == i:
            link_checks(i, j, images, sets[j], _hs_lam(cert, p, module)[4][j], W, brs[j], branch[j], claim)


def check_piece(i, n, f, branch, claim) -> None:
    """A piece's flights: the level's root unique (every flight), the swept piece's pbar_psi inside its set's branch
    box, every crossing a positive first return."""
    kinds = [f"node {k}" for k in range(len(f["nodes"]))] + [kk for kk in KINDS if kk in f]
    recs = list(f["nodes"]) + [f[kk] for kk in KINDS if kk in f]
    done = all(kk in f for kk in KINDS) and all(r["level_ok"] for r in recs)
    claim(f"N{i} piece {n} level", done and all(ball.subset(r["ppsi"], branch[i]) for r in f["nodes"]) and
          all(ball.subset(f[kk]["ppsi_hull"], branch[i]) for kk in ("curve", "swept")),
          "the level's root pbar_psi unique in its Newton box at every node, over the curve and over the swept "
          "piece, each inside the set's branch box")
    bad = [kk for kk, r in zip(kinds, recs) if not ball.positive(r["gdot"])]
    claim(f"N{i} piece {n} positive return", not bad,
          "every flight's first return is a transversal positive crossing" + (f" (not: {', '.join(bad)})" if bad
                                                                                else ""))


def link_checks(i, j, images, setM, vM, W, brM, branchM, claim) -> dict:
    """The covering conditions of N_i => N_j for every lambdabar in [lam - W, lam + W] (module docstring), on each of
    the K sub-intervals of each piece, in N_j's moving coordinates.  images: [(piece (yu, ys, hu, hs), A_X,
    fly_piece's result, K)].
    Returns the smallest (a) margin 1 - |y_s| and the smallest |y_u| of the exit edges' images."""
    cM, AM = setM
    Ai = [[ball.q(x) for x in row] for row in _hs_inv(AM)]
    U = ball.interval(-1, 1)
    vq = [ball.q(x) for x in vM]
    a_min, b_min = None, None
    right, left = [], []  # the exit edges' y_u, per piece and sub-interval
    for n, (pc, AX, f, K) in enumerate(images):
        sk, h = nodes(W, K), 2 * W / K
        ok_psi = all((ball.positive(r["cospsi"]) if brM == "0" else ball.negative(r["cospsi"]))
                     for r in f["nodes"] + [f["box"], f["swept"]])
        claim(f"N{i} => N{j} piece {n} psi branch", ok_psi,
              f"the image is on M's branch psi = {brM} mod 2 pi (the sign of cos psi at every crossing)")
        ends = []  # A_M^-1 (gamma(s_k) - c_M - v_M s_k)
        for Pk, sv in zip((r["Pc"] for r in f["nodes"]), sk):
            d = [Pk[a] - ball.q(cM[a]) - vq[a] * ball.q(sv) for a in (0, 1)]
            ends.append([Ai[b][0] * d[0] + Ai[b][1] * d[1] for b in (0, 1)])
        e = [x * ball.interval(-h * h / 8, 0) for x in f["curve"]["P2"]]
        Ae = [Ai[b][0] * e[0] + Ai[b][1] * e[1] for b in (0, 1)]
        DP, Fas = f["box"]["DP"], f["swept"]["Fas"]
        a_ok, lands = True, False
        for k in range(K):
            off = [ball.hull(ends[k][b], ends[k + 1][b]) + Ae[b] for b in (0, 1)]
            S = ball.interval(sk[k], sk[k + 1])
            Mx = [[DP[a][t] + Fas[t][a] * S for t in (0, 1)] for a in (0, 1)]  # d P_a / d x_t over the piece
            DA = [[Mx[a][0] * ball.q(AX[0][c]) + Mx[a][1] * ball.q(AX[1][c]) for c in (0, 1)] for a in (0, 1)]
            G = [[Ai[b][0] * DA[0][c] + Ai[b][1] * DA[1][c] for c in (0, 1)] for b in (0, 1)]
            lo, hi = ball.bounds(off[1] + G[1][0] * U + G[1][1] * U)
            m = 1 - max(abs(lo), abs(hi))
            a_min = m if a_min is None else min(a_min, m)
            a_ok = a_ok and -1 < lo and hi < 1
            ulo, uhi = ball.bounds(off[0] + G[0][0] * U + G[0][1] * U)
            lands = lands or (ulo <= 1 and uhi >= -1)
            if pc[0] + pc[2] == 1:
                right.append(off[0] + G[0][0] + G[0][1] * U)
            if pc[0] - pc[2] == -1:
                left.append(off[0] - G[0][0] + G[0][1] * U)
        claim(f"N{i} => N{j} piece {n} (a)", a_ok,
              f"on each of its {K} sub-intervals the image lies in |y_s| < 1, so it never meets M's entry edges and "
              f"the straight-line homotopy to (a y_u, 0) keeps |y_s| < 1")
        if lands:
            # where the image can land in M, its pbar_psi is M's root: inside M's branch box
            claim(f"N{i} => N{j} piece {n} branch", ball.subset(f["swept"]["ppsi"], branchM),
                  "the image's pbar_psi lies in M's branch box (the level's root unique there over M)")
    claim(f"N{i} => N{j} exit edges", bool(right) and bool(left), "pieces on both exit edges")
    if not (right and left):  # (a claim that does not stop: the prover's trial of its sub-intervals)
        return {"from": i, "to": j, "a_margin": float(a_min), "b_min_abs_yu": 0.0}
    o = 1 if ball.bounds(right[0])[0] > 1 else -1
    okb = all(ball.bounds(e)[0] > 1 if o == 1 else ball.bounds(e)[1] < -1 for e in right) and \
        all(ball.bounds(e)[1] < -1 if o == 1 else ball.bounds(e)[0] > 1 for e in left)
    b_min = min(min(abs(x) for x in ball.bounds(e)) for e in right + left)
    claim(f"N{i} => N{j} (b)", okb, "on each sub-interval the images of the exit edges lie beyond M's "
          "exit edges, on opposite sides")
    return {"from": i, "to": j, "a_margin": float(a_min), "b_min_abs_yu": float(b_min)}
