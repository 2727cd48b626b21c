"""A horseshoe certificate widened to a lambdabar interval: the point certificate's sets move with lambdabar along
the chain's float motion v_j, and every covering condition, the symmetry and the swept disjointness are checked for
all lambdabar of the interval at once, lambdabar a fifth state of the validated flights (statement 12 on a lambdabar
interval; `magrod prove --widen`)."""
from __future__ import annotations

from fractions import Fraction

import numpy as np

from ...core.errors import ParameterError
from ...generated import validated as gen
from .. import ball, fields, section_return
from ..theorem import section_horseshoe_theorem
from .horseshoe_design import FloatMap, _q, dyadic_of
from .section_horseshoe import KIND, _check_links, _hull, _mid_matrix, _vertices, grid_pieces, piece_geometry, set_data
from . import flights as flights_mod
from .transverse_homoclinic import ProofResult, run_checked, stored


def lambda_motion(p: fields.ExactParams, h, settings: dict, sets: list, DPs: list, dl: float = 1e-6) -> list:
    """The sets' motion v_j = d c_j / d lambdabar (float design; the verifier checks whatever it is): x0 moves along
    Fix(R) with v_0 = ((I - DP_0)^-1 dP/dlambdabar (x0))_theta, (0); along the chain v_{j+1} = DP_j v_j +
    dP/dlambdabar (c_j) (central differences of the float map, step dl), with v_1 = v_0 + alpha e_u^1 and alpha
    (exact linear solve: the recursion is affine in alpha) such that the end stays on Fix(R): v_k's pbar_theta = 0.
    DPs: the float DP of each N_j (j < k) about its centre.  Returns [(v_theta, v_ptheta)] as dyadic Fractions."""
    from dataclasses import replace

    k = len(sets) - 1
    maps = [FloatMap(replace(p, lam=p.lam + Fraction(s * dl)), h, settings.get("branch", "0"),
                     int(settings.get("root", -1))) for s in (1, -1)]
    cs = [np.array([float(x) for x in set_data(sd)[0]]) for sd in sets]
    dlP = [[Fraction(float(x)) for x in (maps[0](c) - maps[1](c)) / (2 * dl)] for c in cs[:k]]
    D = [[[Fraction(float(x)) for x in row] for row in M] for M in DPs]

    def mul(M, v):
        return [M[0][0] * v[0] + M[0][1] * v[1], M[1][0] * v[0] + M[1][1] * v[1]]

    I_D = [[1 - D[0][0][0], -D[0][0][1]], [-D[0][1][0], 1 - D[0][1][1]]]
    det = I_D[0][0] * I_D[1][1] - I_D[0][1] * I_D[1][0]
    v0 = [(I_D[1][1] * dlP[0][0] - I_D[0][1] * dlP[0][1]) / det, Fraction(0)]
    A1 = set_data(sets[1])[1]
    eu = [A1[0][0], A1[1][0]]

    def run(alpha):
        vs = [v0, [v0[0] + alpha * eu[0], v0[1] + alpha * eu[1]]]
        for j in range(1, k):
            w = mul(D[j], vs[-1])
            vs.append([w[0] + dlP[j][0], w[1] + dlP[j][1]])
        return vs

    a, b = run(Fraction(0))[-1][1], run(Fraction(1))[-1][1]
    vs = run(-a / (b - a))
    out = [(dyadic_of(v[0], 60), dyadic_of(v[1], 60)) for v in vs]
    out[0] = (out[0][0], Fraction(0))
    out[-1] = (out[-1][0], Fraction(0))
    return out


def disjoint_moving(P1, P2, dv, w) -> bool:
    """P1 and P2 + s dv are disjoint for every s in [-w, w] (convex polygons, exact): some axis (an edge normal of
    P1 or P2, or the normal of dv) separates P1 from the swept P2 (P2's vertices at s = +-w)."""
    axes = []
    for poly in (P1, P2):
        n = len(poly)
        for i in range(n):
            (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
            axes.append((y2 - y1, x1 - x2))
    if dv[0] or dv[1]:
        axes.append((-dv[1], dv[0]))
    swept = [(x + s * dv[0], y + s * dv[1]) for x, y in P2 for s in (-w, w)]
    for nx, ny in axes:
        a = [nx * x + ny * y for x, y in P1]
        b = [nx * x + ny * y for x, y in swept]
        if max(a) < min(b) or max(b) < min(a):
            return True
    return False


def widen(cert: dict, lam_rad, *, module=gen, progress=None, workers: int | None = None, mapper=None,
          order: int = 1, nodes: int = 8) -> ProofResult:
    """The point certificate's horseshoe for every lambdabar in [lam - lam_rad, lam + lam_rad] (statement 12 over
    an interval): each set moves with lambdabar, N_j(lambdabar) = c_j + v_j (lambdabar - lam) + A_j [-1, 1]^2
    (v_j: lambda_motion), so that it follows its chain; each piece's box is re-flown over the interval with
    lambdabar the fifth state (section_return.Moving), its centre at lam on the certificate's own steps, and the
    covering conditions hold for every lambdabar with P_s(X(s)) in P(c_X) + DP A_X [-1, 1]^2 + (dPds - v_M)
    (s - lam) in M's moving coordinates.  N0 and Nk stay symmetric (v_0, v_k on Fix(R)), the disjointness is
    checked for the swept sets.  Why the sets must move: fixed sets hold for |lambdabar - lam| < ~1e-16 only (the
    chain moves by ~87 per unit lambdabar per return against entry widths of 1.4e-13; measured at Fig 4(a)); moving,
    the limit is the growth of the 5-D box's derivative enclosures with its lambdabar extent |v| lam_rad
    (docs/nonintegrability.md, statement 12).

    The pieces' flights run in `workers` fresh processes (None, the default: the CPUs this process may use; 1: here)
    or by `mapper` (a Dask cluster), as section_horseshoe.prove's: the certificate is the same for every value.

    order 2 (settings "lam_order": 2, "lam_nodes": nodes): the second-order enclosures of kernel/horseshoe_lam2.py
    instead, sub-interval by sub-interval (`nodes` equal sub-intervals, an even number): each piece's centre curve
    by thin flights at the nodes and its second derivative, the piece's extent by DP at lam and the mixed second
    derivative over the swept box; a set whose link keeps an (a') margin below REFINE_MARGIN is flown again with
    twice the sub-intervals, up to 64.  That reaches ~500x wider intervals (Fig 4(a): 1.0012e-8 against 2e-11; 8
    sub-intervals, 16 at N10 and N11, 64 at N12) at 25-75 s of CPU per piece.

    Returns a ProofResult whose certificate has settings["lam_rad"] and a "v" per set.  Point certificates of
    period 1 only (lambda_motion follows x0 as a fixed point; a cycle certificate raises ParameterError)."""
    if int(cert.get("settings", {}).get("period", 1)) != 1:
        raise ParameterError("cert", "a certificate around a periodic orbit (period > 1) cannot be widened here")
    say = progress or (lambda s: None)
    w = ball.fraction(lam_rad)
    if w <= 0:
        raise ParameterError("lam_rad", f"must be > 0, got {lam_rad}")
    if cert.get("kind") != KIND or Fraction(cert["settings"].get("lam_rad", "0")) != 0:
        raise ParameterError("cert", "must be a point certificate of kind section_horseshoe")
    if order not in (1, 2):
        raise ParameterError("lam_order", f"must be 1 or 2, got {order}")
    if order == 2 and w.denominator & (w.denominator - 1):
        raise ParameterError("lam_rad", f"--lam-order 2 needs a dyadic radius (p/2^n: its nodes exact), got {w}")
    if order == 2 and (isinstance(nodes, bool) or not isinstance(nodes, int) or nodes < 2 or nodes % 2 or nodes > 64):
        raise ParameterError("lam_nodes", f"must be an even integer in 2 .. 64, got {nodes}")
    mapper = flights_mod.mapper_for(workers, mapper, module)
    return run_checked(int(cert["settings"]["prec"]),
                       lambda check: _widen(cert, w, module, check, say, mapper, order, nodes), flights=True)


def _widen(cert, w, module, check, say, mapper=None, order=1, nodes=8) -> dict:
    import copy

    s = cert["settings"]
    p = fields.ExactParams(**{kk: Fraction(cert["params"][kk]) for kk in fields.PARAMS})
    h = Fraction(cert["level"])
    sets = copy.deepcopy(cert["sets"])
    k = len(sets) - 1
    fl_by = {int(f["set"]): f for f in cert["flights"]}
    DPs = [np.mean([_mid_matrix([[ball.from_json(x) for x in row] for row in r["enclosures"]["DP"]])
                    for r in fl_by[i]["pieces"]], axis=0) for i in range(k)]
    say("the sets' motion (float)")
    vs = lambda_motion(p, h, s, sets, DPs)
    for sd, v in zip(sets, vs):
        sd["v"] = [_q(x) for x in v]
    brs = [sd.get("branch", "0") for sd in sets]
    for name, idx in (("N0", 0), (f"N{k}", k)):
        check(f"{name} moves on Fix(R)", vs[idx][1] == 0, "v's pbar_theta = 0: the set stays symmetric")
    parsL = fields.parameter_balls(p, w)
    Lam = parsL[fields.LAM]
    Dl = Lam - ball.q(p.lam)
    prad = Fraction(s["p_rad"])
    branch = {}
    for i, sd in enumerate(sets):
        c, A = set_data(sd)
        th, pt = _hull(c, A)
        th, pt = th + ball.q(vs[i][0]) * Dl, pt + ball.q(vs[i][1]) * Dl
        _, B, ok = section_return.level_newton_section(parsL, h, th, pt, Fraction(sd["p_c"]), prad, module, brs[i])
        check(f"N{i} branch box", ok, "pbar_psi unique in the branch box over the set's hull swept over lambdabar")
        branch[i] = B
    links = [(0, 0), (0, 1)] + [(j, j + 1) for j in range(1, k)]
    grids, plan = {}, []
    for i in range(k):
        grids[i] = tuple(fl_by[i]["grid"])
        for n, (pc, r) in enumerate(zip(grid_pieces(*grids[i]), fl_by[i]["pieces"])):
            plan.append((i, n, pc, r))
    if order == 2:
        flights, link_rec = _fly_second_order(cert, sets, brs, branch, plan, grids, w, nodes, links, module, check,
                                              say, mapper)
    else:
        flights, link_rec = _fly_first_order(cert, sets, brs, branch, plan, grids, Dl, links, module, check, say,
                                             mapper, w)
    for name, idx in (("N0", 0), (f"N{k}", k)):
        c, A = set_data(sets[idx])
        check(f"{name} symmetric", c[1] == 0 and A[0][1] == A[0][0] and A[1][1] == -A[1][0],
              "centre on Fix(R) and A = [a, R a]: R(N)^T = N")
    polys = [_vertices(*set_data(sd)) for sd in sets]
    for j in range(1, k + 1):
        dv = (vs[j][0] - vs[0][0], vs[j][1] - vs[0][1])
        check(f"N0, N{j} disjoint", brs[j] != brs[0] or disjoint_moving(polys[0], polys[j], dv, w),
              "another branch of psi, or a separating axis for every lambdabar (exact)")
    for j in range(1, k):
        dv = (vs[j][0] - vs[0][0], -vs[j][1] - vs[0][1])
        check(f"N0, R(N{j}) disjoint", brs[j] != brs[0] or
              disjoint_moving(polys[0], [(x, -y) for x, y in polys[j]], dv, w),
              "another branch of psi (R keeps it), or a separating axis for every lambdabar (exact)")
    digest = fields.source_digest(module)
    check("field_is_derived", digest == fields.source_digest(gen),
          "the vector field is the derive-generated generated/validated.py (SHA-256 of its source)")
    L = int(cert["loop_length"])
    out = {kk: cert[kk] for kk in ("format", "kind", "params", "level", "field_digest", "links", "loop_length",
                                    "entropy", "hypotheses_symbolic")}
    out["field_digest"] = digest
    out["theorem"] = section_horseshoe_theorem(cert["params"], cert["level"], k, L, cert["entropy"]["rho_lower"],
                                               _q(w))
    out["settings"] = {**s, "lam_rad": _q(w), **({"lam_order": 2, "lam_nodes": nodes} if order == 2 else {})}
    out["sets"], out["flights"], out["link_margins"] = sets, flights, link_rec
    out["design"] = {**cert["design"], "v": [[float(x) for x in v] for v in vs]}
    return out


def _fly_first_order(cert, sets, brs, branch, plan, grids, Dl, links, module, check, say, mapper, w):
    """Each piece's box re-flown over the interval (section_return.Moving), the links checked on
    P(c_X) + DP A_X [-1, 1]^2 + (dPds - v_M)(s - lam) in M's moving coordinates: (flight records, link records)."""
    s = cert["settings"]
    fl_by = {int(f["set"]): f for f in cert["flights"]}
    vs = [[Fraction(x) for x in sd["v"]] for sd in sets]
    images, flights = {}, []
    jobs = []
    for i, _n, pc, r in plan:
        cX, AX = piece_geometry(*set_data(sets[i]), pc)
        jobs.append({"params": cert["params"], "h": cert["level"], "settings": s, "lam_rad": _q(w),
                     "c": [_q(x) for x in cX], "A": [[_q(x) for x in row] for row in AX], "pc": r["p_c"],
                     "t_a": r["t_a"], "thin_steps": r["steps"]["thin"], "branch": brs[i], "v": sets[i]["v"]})
    if mapper is None:  # here, through the same exact JSON form as from another process (flights.normalised)
        results = (flights_mod.normalised(flights_mod.widen_flight(job, module)) for job in jobs)
    else:
        results = flights_mod.decoded(mapper(flights_mod.widen_job, jobs))
    recs = []
    try:
        for (i, n, pc, r), fl in zip(plan, results):
            check(f"N{i} piece {n} geometry", [Fraction(x) for x in r["piece"]] == list(pc), "the grid's piece")
            say(f"set N{i}: piece {n + 1}/{len(fl_by[i]['pieces'])} over lambdabar")
            AX = piece_geometry(*set_data(sets[i]), pc)[1]
            check(f"N{i} piece {n} level", fl["level_ok"] and ball.subset(fl["ppsi_hull"], branch[i]),
                  "pbar_psi unique in its Newton box over the moving piece, inside the set's branch box")
            check(f"N{i} piece {n} positive return", ball.positive(fl["gdot_thin"]) and ball.positive(fl["gdot_box"]),
                  f"d(sin psi)/dt = {fl['gdot_box']} > 0 at the crossing")
            recs.append({"piece": r["piece"], "p_c": r["p_c"], "t_a": r["t_a"],
                         "steps": {kk: [[ball.decimal(x) for x in ph] for ph in vv] for kk, vv in fl["steps"].items()},
                         "n_steps": sum(len(ph) for vv in fl["steps"].values() for ph in vv),
                         "enclosures": {"Pc": [stored(v) for v in fl["Pc"]],
                                        "DP": [[stored(v) for v in row] for row in fl["DP"]],
                                        "dPds": [stored(v) for v in fl["dPds"]],
                                        "ppsi_box": stored(fl["ppsi_box"])}})
            images[(i, n)] = (pc, AX, fl)
            if n == len(fl_by[i]["pieces"]) - 1:
                flights.append({"set": i, "grid": list(grids[i]), "pieces": recs})
                recs = []
    finally:
        flights_mod.close(results)  # after a failed check: the flights not yet taken are cancelled

    def shift(i, j, fl):  # P_s(c_X(s)) - c_M(s) = P(c_X) - c_M + (dPds - v_M)(s - lam)
        vM = [ball.q(x) for x in vs[j]]
        return {**fl, "Pc": tuple(fl["Pc"][a] + (fl["dPds"][a] - vM[a]) * Dl for a in range(2))}

    link_rec = _check_links([{**sd, "branch": b} for sd, b in zip(sets, brs)], links, grids, images, branch, check,
                            say, shift)
    return flights, link_rec


def _fly_second_order(cert, sets, brs, branch, plan, grids, w, K0, links, module, check, say, mapper):
    """Each piece's second-order flights (kernel/horseshoe_lam2.fly_piece, adaptive, with the nodes' Newton
    centres: flights.widen2_flight) and the kernel's own checks of the pieces and of every link, sub-interval by
    sub-interval: (flight records, link records).  Each piece starts with K0 sub-intervals; where a link's (a')
    margin is below REFINE_MARGIN (or a condition fails) its source's pieces are flown again with twice as many,
    up to 64, so that the nodes (about half of a piece's cost at K = 32) are spent where the curve needs them."""
    from ..kernel import horseshoe_lam2 as lam2

    s = cert["settings"]
    fl_by = {int(f["set"]): f for f in cert["flights"]}
    W = Fraction(w)

    def job(i, pc, r, K):
        cX, AX = piece_geometry(*set_data(sets[i]), pc)
        return {"params": cert["params"], "h": cert["level"], "settings": s, "lam_rad": _q(w), "lam_nodes": K,
                "c": [_q(x) for x in cX], "A": [[_q(x) for x in row] for row in AX], "pc": r["p_c"],
                "t_a": r["t_a"], "branch": brs[i], "v": sets[i]["v"]}

    def fly(todo):  # [(plan index, K)] -> {plan index: flight}, in the order given, wherever the mapper runs them
        jobs = [job(plan[x][0], plan[x][2], plan[x][3], K) for x, K in todo]
        if mapper is None:  # here, through the same exact JSON form as from another process (flights.normalised)
            results = (flights_mod.normalised(flights_mod.widen2_flight(jb, module)) for jb in jobs)
        else:
            results = flights_mod.decoded(mapper(flights_mod.widen2_job, jobs))
        out = {}
        try:
            for m, ((x, K), fl) in enumerate(zip(todo, results)):
                out[x] = fl
                say(f"set N{plan[x][0]}: piece {plan[x][1] + 1} over lambdabar, {K} sub-intervals "
                    f"({m + 1}/{len(todo)})")
            return out
        finally:
            flights_mod.close(results)

    Ks = {x: K0 for x in range(len(plan))}
    flown = fly(list(Ks.items()))
    sources = {i: [x for x, (ii, *_rest) in enumerate(plan) if ii == i] for i in {row[0] for row in plan}}
    while True:
        refine = set()
        for i, j in links:
            imgs = [(plan[x][2], piece_geometry(*set_data(sets[i]), plan[x][2])[1], flown[x], Ks[x])
                    for x in sources[i]]
            bad = []
            rec = lam2.link_checks(i, j, imgs, set_data(sets[j])[:2], [Fraction(x) for x in sets[j]["v"]], W,
                                   brs[j], branch[j],
                                   lambda name, holds, how, bad=bad: bad.append(name) if not holds else None)
            if (bad or rec["a_margin"] < REFINE_MARGIN) and all(Ks[x] < 64 for x in sources[i]):
                refine |= set(sources[i])
        if not refine:
            break
        for x in refine:
            Ks[x] *= 2
        say(f"sets {sorted({plan[x][0] for x in refine})}: {sorted({Ks[x] for x in refine})} sub-intervals")
        flown.update(fly(sorted((x, Ks[x]) for x in refine)))
    images, flights, recs = {}, [], []
    for x, (i, n, pc, r) in enumerate(plan):
        fl = flown[x]
        check(f"N{i} piece {n} geometry", [Fraction(v) for v in r["piece"]] == list(pc), "the grid's piece")
        AX = piece_geometry(*set_data(sets[i]), pc)[1]
        lam2.check_piece(i, n, fl, branch, check)
        st = fl["steps"]
        recs.append({"piece": r["piece"], "p_c": r["p_c"], "t_a": r["t_a"], "lam_nodes": Ks[x],
                     "nodes_p_c": [_q(v) for v in fl["nodes_p_c"]],
                     "steps": {"nodes": [[[ball.decimal(v) for v in ph] for ph in nd] for nd in st["nodes"]],
                               **{kk: [[ball.decimal(v) for v in ph] for ph in st[kk]] for kk in lam2.KINDS}},
                     "n_steps": sum(len(ph) for nd in st["nodes"] for ph in nd)
                     + sum(len(ph) for kk in lam2.KINDS for ph in st[kk]),
                     "enclosures": {"nodes_Pc": [[stored(v) for v in nd["Pc"]] for nd in fl["nodes"]],
                                    "DP": [[stored(v) for v in row] for row in fl["box"]["DP"]],
                                    "P2": [stored(v) for v in fl["curve"]["P2"]],
                                    "Fas": [[stored(v) for v in row] for row in fl["swept"]["Fas"]]}})
        images[x] = (pc, AX, fl, Ks[x])
        if n == len(fl_by[i]["pieces"]) - 1:
            flights.append({"set": i, "grid": list(grids[i]), "pieces": recs})
            recs = []
    link_rec = []
    for i, j in links:
        rec = lam2.link_checks(i, j, [images[x] for x in sources[i]], set_data(sets[j])[:2],
                               [Fraction(v) for v in sets[j]["v"]], W, brs[j], branch[j], check)
        link_rec.append(rec)
        say(f"N{i} => N{j}: (a) margin {rec['a_margin']:.3g}, (b) min |y_u| {rec['b_min_abs_yu']:.3g} "
            f"with {sorted({Ks[x] for x in sources[i]})} sub-intervals")
    return flights, link_rec


#: a link whose (a') margin on the prover's flights is below this has its source's pieces flown again with twice the
#: sub-intervals (horseshoe_widen._fly_second_order)
REFINE_MARGIN = 0.25
