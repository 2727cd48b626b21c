"""The horseshoe certificate's checks of one set and of the branch boxes (the part of the horseshoe kernel that
both the serial replay (horseshoe.py) and the child processes (pool.py) run): its own module, below both."""
from __future__ import annotations

import dataclasses

from .. import ball, fields, taylor
from .schema import frac


def _hs_set(d):
    c = [frac(v) for v in d["c"]]
    A = [[frac(v) for v in row] for row in d["A"]]
    if len(c) != 2 or len(A) != 2 or any(len(r) != 2 for r in A):
        raise ValueError("a set is c (2) and A (2 x 2)")
    return c, A


def _hs_inv(A):
    det = A[0][0] * A[1][1] - A[0][1] * A[1][0]
    return [[A[1][1] / det, -A[0][1] / det], [-A[1][0] / det, A[0][0] / det]]


def _hs_vertices(c, A):
    return [(c[0] + A[0][0] * a + A[0][1] * b, c[1] + A[1][0] * a + A[1][1] * b)
            for a, b in ((1, 1), (1, -1), (-1, -1), (-1, 1))]


def _hs_separated(P1, P2) -> bool:
    for poly in (P1, P2):
        for i in range(4):
            (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % 4]
            n = (y2 - y1, x1 - x2)
            a = [n[0] * x + n[1] * y for x, y in P1]
            b = [n[0] * x + n[1] * y for x, y in P2]
            if max(a) < min(b) or max(b) < min(a):
                return True
    return False


def _hs_cover(pieces) -> bool:
    """The pieces (yu, ys, hu, hs) cover [-1, 1]^2: each inside it, pairwise interiors disjoint, total area 4
    (closed boxes of full total area with disjoint interiors inside the square cover it)."""
    boxes = []
    for yu, ys, hu, hs in pieces:
        if hu <= 0 or hs <= 0 or yu - hu < -1 or yu + hu > 1 or ys - hs < -1 or ys + hs > 1:
            return False
        boxes.append((yu - hu, yu + hu, ys - hs, ys + hs))
    for i in range(len(boxes)):
        for j in range(i):
            a, b = boxes[i], boxes[j]
            if a[0] < b[1] and b[0] < a[1] and a[2] < b[3] and b[2] < a[3]:
                return False
    return sum((b[1] - b[0]) * (b[3] - b[2]) for b in boxes) == 4


def _hs_lam(cert, p, module=fields.gen):
    """A lambdabar interval (settings "lam_rad" > 0; the prover's horseshoe_widen.widen): (w, pars with lambdabar's ball, the ball,
    ball - lam, [v_j] exact) -- the sets move, N_j(s) = c_j + v_j (s - lam) + A_j [-1, 1]^2; None for a point."""
    w = frac(cert["settings"].get("lam_rad", "0"))
    if w < 0:
        raise ValueError("lam_rad must be >= 0")
    if w == 0:
        if any("v" in d for d in cert["sets"]):
            raise ValueError("a point certificate's sets do not move (no 'v')")
        return None
    vs = [tuple(frac(x) for x in d["v"]) for d in cert["sets"]]
    if any(len(v) != 2 for v in vs):
        raise ValueError("a set's v has 2 entries")
    pars = fields.parameter_balls(p, w)
    lam = pars[fields.LAM]
    return w, pars, lam, lam - ball.q(p.lam), vs


def lam_order(cert) -> int:
    """How a lambdabar-interval certificate encloses the motion: 1 (absent; one flight of each piece swept over the
    interval, the image first order in lambdabar) or 2 (kernel/horseshoe_lam2.py: nodes, the centre curve's second
    derivative and the mixed one, sub-interval by sub-interval); 2 needs lam_rad > 0."""
    o = cert["settings"].get("lam_order", 1)
    if o not in (1, 2) or isinstance(o, bool):
        raise ValueError(f"lam_order must be 1 or 2, got {o!r}")
    if o == 2 and frac(cert["settings"].get("lam_rad", "0")) <= 0:
        raise ValueError("lam_order 2 needs lam_rad > 0")
    return o


def _hs_separated_moving(P1, P2, dv, w) -> bool:
    """P1 and P2 + s dv disjoint for every s in [-w, w]: a separating axis (edge normals, the normal of dv) between
    P1 and the vertices of P2 at s = -w and s = w (convex hull of the swept set)."""
    axes = []
    for poly in (P1, P2):
        for i in range(4):
            (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % 4]
            axes.append((y2 - y1, x1 - x2))
    if dv != (0, 0):
        axes.append((-dv[1], dv[0]))
    swept = [(x + t * dv[0], y + t * dv[1]) for x, y in P2 for t in (-w, w)]
    for n in axes:
        a = [n[0] * x + n[1] * y for x, y in P1]
        b = [n[0] * x + n[1] * y for x, y in swept]
        if max(a) < min(b) or max(b) < min(a):
            return True
    return False


def _hs_branch_boxes(cert, pars, sets, brs, module, claim=None) -> list:
    """[(ok, B)] per set: the level's root pbar_psi by interval Newton over the set's hull, B its Newton box (each
    claimed as it is computed when `claim` is given)."""
    from .. import section_return

    h, prad = frac(cert["level"]), frac(cert["settings"]["p_rad"])
    U = ball.interval(-1, 1)
    mv = _hs_lam(cert, fields.ExactParams(**{kk: frac(cert["params"][kk]) for kk in fields.PARAMS}), module)
    if mv is not None:
        pars = mv[1]
    out = []
    for j, (c, A) in enumerate(sets):
        U0 = ball.q(c[0]) + ball.q(A[0][0]) * U + ball.q(A[0][1]) * U
        U1 = ball.q(c[1]) + ball.q(A[1][0]) * U + ball.q(A[1][1]) * U
        if mv is not None:  # the hull swept over the lambdabar interval
            U0, U1 = U0 + ball.q(mv[4][j][0]) * mv[3], U1 + ball.q(mv[4][j][1]) * mv[3]
        _, B, ok = section_return.level_newton_section(pars, h, U0, U1, frac(cert["sets"][j]["p_c"]), prad, module,
                                                       brs[j])
        if claim is not None:
            claim(f"N{j} branch box", ok, "the level's root pbar_psi is unique in the set's branch box over its hull")
        out.append((ok, B))
    return out


def _hs_graph(cert, n: int) -> tuple:
    """(period p, the links the certificate must have) for n sets.  p = 1 (no "period" in the settings): N0 => N0,
    N0 => N1 => ... => N(n-1).  p > 1 (the prover's _prove_cycle): the cycle N0 => N1 => ... => N(p-1) => N0 and the
    chain N(p-1) => Np => ... => N(n-1) (at least two sets after the cycle, so that Np and N(n-1) differ)."""
    per = int(cert["settings"].get("period", 1))
    if per == 1:
        return 1, [[0, 0], [0, 1]] + [[j, j + 1] for j in range(1, n - 1)]
    if not 2 <= per <= n - 3:
        raise ValueError(f"period {per} out of range for {n} sets")
    return per, ([[i, i + 1] for i in range(per - 1)] + [[per - 1, 0], [per - 1, per]]
                 + [[j, j + 1] for j in range(per, n - 1)])


def _hs_source(cert, i, order, module, claim, branch) -> None:
    """The checks of set N_i as a source (a point or first-order interval certificate; horseshoe_lam2.set_source
    chooses), in the verifier's order: its pieces re-flown (steps, flight, level,
    positive return), then every link N_i => N_j of the chain.  Depends only on the certificate, i and the branch
    boxes, so the sets can be checked in separate processes (_hs_sources_parallel) with the same checks."""
    from .. import section_return

    s = cert["settings"]
    h = frac(cert["level"])
    prad, t1, lead = (frac(s[kk]) for kk in ("p_rad", "t1", "lead"))
    newton = int(s["newton"])
    p = fields.ExactParams(**{kk: frac(cert["params"][kk]) for kk in fields.PARAMS})
    sets = [_hs_set(d) for d in cert["sets"]]
    brs = [d.get("branch", "0") for d in cert["sets"]]
    want = _hs_graph(cert, len(sets))[1]
    fl = {int(f["set"]): f for f in cert["flights"]}[i]
    pieces = [tuple(frac(v) for v in r["piece"]) for r in fl["pieces"]]
    pars = p.balls()
    # the flights' Taylor coefficients by Newton's iteration on series (taylor._newton_series: as rigorous as the
    # prover's Picard iteration, other balls, ~1/4 of the cost), the centres as C^0 sets (their DP is not read here)
    fld = dataclasses.replace(fields.chart_field(p, module), series="newton")
    lm = _hs_lam(cert, p, module)
    mv = None if lm is None else section_return.Moving(
        tuple(lm[1]), dataclasses.replace(fields.lam_state_field(p, module), series="newton"), lm[2], p.lam, lm[4][i])
    U = ball.interval(-1, 1)
    c, A = sets[i]
    images = []
    for n, (r, pc) in enumerate(zip(fl["pieces"], pieces)):
        yu, ys, hu, hs = pc
        cX = [c[0] + A[0][0] * yu + A[0][1] * ys, c[1] + A[1][0] * yu + A[1][1] * ys]
        AX = [[A[0][0] * hu, A[0][1] * hs], [A[1][0] * hu, A[1][1] * hs]]
        steps = {kk: [[frac(x) for x in ph] for ph in r["steps"][kk]] for kk in ("thin", "box")}
        t_a = frac(r["t_a"])
        for kk in ("thin", "box"):
            claim(f"N{i} piece {n} {kk} steps", len(steps[kk]) == 2 and sum(steps[kk][0]) == t1 and
                  sum(steps[kk][0]) + sum(steps[kk][1]) == t_a and all(x > 0 for ph in steps[kk] for x in ph),
                  "phase 1 on [0, t1], phase 2 on [t1, t_a], positive exact steps")
        try:
            f = section_return.piece_return(pars, h, fld, cX, AX, frac(r["p_c"]), prad, t_a, lead, t1=t1,
                                            order=order, steps=steps, newton=newton, thin_c1=False, branch=brs[i],
                                            integrator=section_return.integrator(s.get("integrator", "taylor")),
                                            thin_integrator=section_return.integrator(s.get("thin_integrator",
                                                                                            "taylor")),
                                            moving=mv, module=module)
        except (taylor.EnclosureError, taylor.GuardError, taylor.CrossingError) as err:
            claim(f"N{i} piece {n} flight", False, str(err)[:200])
        claim(f"N{i} piece {n} level", f["level_ok"] and ball.subset(f["ppsi_hull"], branch[i]),
              "the piece's pbar_psi: unique in its Newton box over the piece, inside the set's branch box")
        claim(f"N{i} piece {n} positive return", all(ball.positive(f[x]) for x in ("gdot_thin", "gdot_box")),
              "the first return is a transversal positive crossing")
        images.append((pc, AX, f))
    for src, j in want:
        if src != i:
            continue
        cM, AM = sets[j]
        Ai = [[ball.q(v) for v in row] for row in _hs_inv(AM)]
        right, left = [], []
        for n, (pc, AX, f) in enumerate(images):
            d = [f["Pc"][0] - ball.q(cM[0]), f["Pc"][1] - ball.q(cM[1])]
            if lm is not None:  # in M's moving coordinates: + (dP/ds - v_M)(s - lam), s in the interval
                d = [d[a] + (f["dPds"][a] - ball.q(lm[4][j][a])) * lm[3] for a in range(2)]
            off = [Ai[a][0] * d[0] + Ai[a][1] * d[1] for a in range(2)]
            DA = [[f["DP"][a][0] * ball.q(AX[0][b]) + f["DP"][a][1] * ball.q(AX[1][b]) for b in range(2)]
                  for a in range(2)]
            G = [[Ai[a][0] * DA[0][b] + Ai[a][1] * DA[1][b] for b in range(2)] for a in range(2)]
            yu = off[0] + G[0][0] * U + G[0][1] * U
            ys = off[1] + G[1][0] * U + G[1][1] * U
            lu, hu_ = ball.bounds(yu)
            ls_, hs_ = ball.bounds(ys)
            claim(f"N{i} => N{j} piece {n} psi branch", all((ball.positive(f[x]) if brs[j] == "0" else
                                                              ball.negative(f[x])) for x in ("cospsi_thin",
                                                                                              "cospsi_box")),
                  f"the image is on M's branch psi = {brs[j]} mod 2 pi (the sign of cos psi at the crossing)")
            claim(f"N{i} => N{j} piece {n} (a)", -1 < ls_ and hs_ < 1,
                  f"the image lies in |y_s| < 1 (y_s {ys}), so it never meets M's entry edges and the straight-line "
                  f"homotopy to (a y_u, 0) keeps |y_s| < 1")
            if lu <= 1 and hu_ >= -1:
                # where the image can land in M, its pbar_psi is M's root: inside M's branch box
                claim(f"N{i} => N{j} piece {n} branch", ball.subset(f["ppsi_box"], branch[j]),
                      "the image's pbar_psi lies in M's branch box (the level's root unique there over M)")
            if pc[0] - pc[2] == -1:
                left.append(off[0] - G[0][0] + G[0][1] * U)
            if pc[0] + pc[2] == 1:
                right.append(off[0] + G[0][0] + G[0][1] * U)
        claim(f"N{i} => N{j} exit edges", bool(right) and bool(left), "pieces on both exit edges")
        o = 1 if ball.bounds(right[0])[0] > 1 else -1
        okb = all(ball.bounds(e)[0] > 1 if o == 1 else ball.bounds(e)[1] < -1 for e in right) and \
            all(ball.bounds(e)[1] < -1 if o == 1 else ball.bounds(e)[0] > 1 for e in left)
        claim(f"N{i} => N{j} (b)", okb, "the images of the exit edges lie beyond M's exit edges, on opposite sides")
