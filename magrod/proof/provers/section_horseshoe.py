"""The prover of a horseshoe of the section map on Fig 4's level: covering relations
(Zgliczynski & Gidea 2004) along the homoclinic orbit of the saddle x0 of statement 11, one return per flight.

What is proved (docs/nonintegrability.md, statement 12): at exact (m, mu, gamma, delta, lambdabar) and level h, the
section map P of Sigma+ = {sin psi = 0, d sin psi/dt > 0} on {Hbar = h}, in the section coordinates
(theta, pbar_theta) (psi = 0 or pi: each set's branch; pbar_psi the root of the level in the set's Newton box), has
h-sets (parallelograms
N = c + A [-1, 1]^2, first column of A the exit, second the entry direction) with
    N0 =>_P N0,   N0 =>_P N1 =>_P N2 => ... =>_P Nk,
N0 and Nk symmetric (centre on Fix(R) = {pbar_theta = 0}, A = [a, R a], R = diag(1, -1): R(N)^T = N), N0 disjoint
from N1 .. Nk and from R(N1) .. R(N_{k-1}).  Reversibility (R P R = P^-1) turns the chain into back-coverings
    Nk = R(Nk)^T <=_P R(N_{k-1})^T <=_P ... <=_P R(N1)^T <=_P R(N0)^T = N0
(lemma: N =>_P M implies R(M)^T <=_P R(N)^T), so N0 has two closed chains, of lengths 1 and L = 2k, and the
covering-chain theorem gives, for every sequence of these loops, an orbit realising it; coding the visits to N0 gives
a semiconjugacy onto the shift of concatenations of the blocks "1" and "1 0^(L-1)": h_top(P) >= log rho,
rho the largest root of x^L = x^(L-1) + 1.

The covering N =>_P M (dimension 2, one exit direction) is checked by the sufficient conditions of Zgliczynski &
Gidea (their theorem for u = 1 with the straight-line homotopy): in M's coordinates y = A_M^-1 (x - c_M), (a) the
image of N meets {|y_u| <= 1} only inside {|y_s| < 1}, (b) the images of N's exit edges {y_u = -1}, {y_u = +1} lie in
{y_u < -1} and {y_u > 1} (or the reverse), P continuous on N.  N is cut into pieces X = c_X + A_X [-1, 1]^2
(a product grid in N's coordinates); each is flown ONE return (section_return.piece_return: the centre and the piece,
validated C^1 Lohner flights with the phases of statement 11 and the crossing enclosed), and its image is enclosed by
the mean-value form P(X) in P(c_X) + [DP(X)] A_X [-1, 1]^2.

Method of the design (float, heyoka; only chooses where to look): the W^u point z_0 = x0 + s* e_u whose 8th image lies
on Fix(R), pulled back m times along the local W^u (c_1 = x0 + s* mu_u^-m e_u, to second order); the chain c_{j+1} = P(c_j) is then recomputed with the validated
thin flights (their midpoints: 128 bits), c_1 shifted along e_u by one Newton step so that P^(k-1)(c_1) lies on
Fix(R); frames: e_u^j (W^u tangents, pushed forward by DP) and e_s^j (W^s tangents, R e_u^k pulled back), so that DP
maps frame to frame; sizes by the rule of `sizes`.

Over a lambdabar interval (`widen`): the point certificate's sets move with lambdabar along the chain's motion v_j,
every condition checked for all lambdabar of the interval at once (statement 12 on a lambdabar interval).
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np

from ...generated import validated as gen
from .. import ball, fields, section_return
from ..theorem import section_horseshoe_theorem
from . import section_fixed_point
from .horseshoe_design import (R2, FloatMap, HorseshoeSettings, _float_s_star, _q, dyadic, dyadic_of, float_cycle,
                               float_design, sizes, unit, unstable_eigen)
from .flights import close as flights_close
from .flights import prover_field
from .transverse_homoclinic import ProofResult, run_checked, stored

FORMAT = "magrod-proof-certificate/1"
KIND = "section_horseshoe"


# --------------------------------------------------------------------------------------------------------------
# h-sets and pieces (exact data)
# --------------------------------------------------------------------------------------------------------------
def hset(c, A) -> dict:
    return {"c": [_q(v) for v in c], "A": [[_q(v) for v in row] for row in A]}


def set_data(s) -> tuple:
    c = [Fraction(v) for v in s["c"]]
    A = [[Fraction(v) for v in row] for row in s["A"]]
    return c, A


def grid_pieces(nu: int, ns: int) -> list:
    """The product grid of nu x ns pieces of [-1, 1]^2: [(yu, ys, hu, hs)] (centres and half sizes, dyadic if nu, ns
    are powers of two)."""
    out = []
    for i in range(nu):
        for j in range(ns):
            out.append((Fraction(2 * i + 1, nu) - 1, Fraction(2 * j + 1, ns) - 1, Fraction(1, nu), Fraction(1, ns)))
    return out


def piece_geometry(c, A, piece):
    """(c_X, A_X) of the piece (yu, ys, hu, hs) of N = c + A [-1, 1]^2: c_X = c + A (yu, ys), A_X = A diag(hu, hs)."""
    yu, ys, hu, hs = piece
    cX = [c[0] + A[0][0] * yu + A[0][1] * ys, c[1] + A[1][0] * yu + A[1][1] * ys]
    AX = [[A[0][0] * hu, A[0][1] * hs], [A[1][0] * hu, A[1][1] * hs]]
    return cX, AX


def t_approach(T: float, lead: Fraction) -> Fraction:
    return Fraction(math.floor((T - float(lead)) * 2**20), 2**20)


# --------------------------------------------------------------------------------------------------------------
# the covering conditions on a piece's image (the verifier has its own copy: kernel/horseshoe.py)
# --------------------------------------------------------------------------------------------------------------
def image_in(M, fl, AX):
    """y = A_M^-1 (P(c_X) - c_M) + A_M^-1 [DP(X)] A_X v, v in [-1, 1]^2: (off, G) as balls (off 2, G 2 x 2)."""
    cM, AM = M
    det = AM[0][0] * AM[1][1] - AM[0][1] * AM[1][0]
    Ai = [[AM[1][1] / det, -AM[0][1] / det], [-AM[1][0] / det, AM[0][0] / det]]
    Aib = [[ball.q(v) for v in row] for row in Ai]
    d = [fl["Pc"][0] - ball.q(cM[0]), fl["Pc"][1] - ball.q(cM[1])]
    off = [Aib[i][0] * d[0] + Aib[i][1] * d[1] for i in range(2)]
    DP = fl["DP"]
    DA = [[DP[i][0] * ball.q(AX[0][j]) + DP[i][1] * ball.q(AX[1][j]) for j in range(2)] for i in range(2)]
    G = [[Aib[i][0] * DA[0][j] + Aib[i][1] * DA[1][j] for j in range(2)] for i in range(2)]
    return off, G


def piece_checks(off, G, piece):
    """(a_ok, a_margin, edge images): (a') the piece's image lies in {|y_s| < 1} (stronger than (a): then the
    straight-line homotopy to (a y_u, 0) never meets M's entry edges);
    the images of the piece's parts of N's exit edges (y_u(N) = -1 and +1) as y_u balls."""
    U = ball.interval(-1, 1)
    yu = off[0] + G[0][0] * U + G[0][1] * U
    ys = off[1] + G[1][0] * U + G[1][1] * U
    lo_u, hi_u = ball.bounds(yu)
    lo_s, hi_s = ball.bounds(ys)
    del lo_u, hi_u
    inside = -1 < lo_s and hi_s < 1
    margin = float(1 - max(abs(lo_s), abs(hi_s)))
    edges = {}
    pu, _, hu, _ = piece
    if pu - hu == -1:
        edges[-1] = off[0] - G[0][0] + G[0][1] * U
    if pu + hu == 1:
        edges[1] = off[0] + G[0][0] + G[0][1] * U
    return bool(inside), margin, edges


# --------------------------------------------------------------------------------------------------------------
# the prover
# --------------------------------------------------------------------------------------------------------------
def prove(params: fields.ExactParams, h: Fraction, x0_theta: Fraction, settings: HorseshoeSettings | None = None, *,
          module=gen, progress=None, workers: int | None = None, mapper=None) -> ProofResult:
    """Prove (or fail to prove) the covering-relation horseshoe of the section map (module docstring).

    Parameters
    ----------
    params, h : the exact parameters and level.
    x0_theta : float or Fraction
        Where the float search (section_fixed_point.float_fixed_point, within 0.02) looks for the symmetric saddle
        x0 = (theta*, psi, pbar_theta = 0) of P (statement 11; psi = 0, or pi with settings.branch = "pi": Fig 5,
        statement 13); N0 is centred at the float theta*.
    settings : HorseshoeSettings, optional
    module : the generated field module (a mutated copy for controls: its flights stay in this process).
    progress : callable, optional
        progress(message) at each stage and after each piece's flight.
    workers : int or None, optional
        The pieces' flights (one return of each piece of each set, independent of one another) in this many fresh
        processes on this machine (None, the default: the CPUs this process may use; 1: in this process).  The chain's
        centre flights are sequential and stay here.  The certificate is the same for every value: the flights are
        the same Arb computations wherever they run, and their checks are made here in the serial order.
    mapper : callable, optional
        mapper(fn, jobs) running the pieces' flights elsewhere (a Dask cluster: magrod.proof.schedule.dask_mapper),
        instead of `workers`.

    Returns
    -------
    ProofResult
        ok, certificate (kind "section_horseshoe"), reason, checks, wall_time_s.
    """
    st = settings or HorseshoeSettings()
    run = _prove if st.period == 1 else _prove_cycle
    from . import flights

    mapper = flights.mapper_for(workers, mapper, module)
    return run_checked(st.prec, lambda check: run(params, h, x0_theta, st, module, check,
                                                  progress or (lambda s: None), mapper), flights=True)


def _frame_from(DPs, e_u1):
    """W^u tangents pushed forward and W^s tangents (R e_u^k) pulled back along float DP's; the stretches."""
    eus = [unit(e_u1)]
    for D in DPs:
        eus.append(unit(D @ eus[-1]))
    if eus[-1][1] < 0:
        eus[-1] = -eus[-1]
    ess = [R2 @ eus[-1]]
    for D in reversed(DPs):
        ess.append(unit(np.linalg.solve(D, ess[-1])))
    ess = ess[::-1]
    lam = [float(np.linalg.norm(D @ u)) for D, u in zip(DPs, eus[:-1])]
    sig = [float(np.linalg.norm(D @ s)) for D, s in zip(DPs, ess[:-1])]
    return eus, ess, lam, sig


def _mid_matrix(DP):
    return np.array([[float(v.mid()) for v in row] for row in DP])


def _chain_passes(fly_chain, c1, e_u1, x0, n_flights, st, say):
    """The chain by the validated centre flights fly_chain(c1, tol) -> (centres, pbar_psi, branches, flights), one
    pass per st.passes; after each pass but the last a Newton step along e_u^1 moves c_1 so that the chain's end
    lies on Fix(R) (with st.stop_frac, the passes stop once it is within stop_frac of the end set's width).
    Returns the last pass's chain, its frames (e_u, e_s, stretches) and the end residual of every pass."""
    passes = []
    sched = [st.tol if kind == "tol" else st.tol_thin for kind in st.passes]
    for n_pass, tl in enumerate(sched):
        say(f"chain pass {n_pass + 1} ({n_flights} centre flights, tol {tl:g})")
        cs, pcs, brs, fls = fly_chain(c1, tl)
        DPs = [_mid_matrix(f["DPc"]) for f in fls]
        eus, ess, lam, sig = _frame_from(DPs, e_u1)
        delta = float(fls[-1]["Pc"][1].mid())
        passes.append(delta)
        if n_pass == len(sched) - 1:
            break
        if st.stop_frac and len(set(sched[n_pass:])) == 1:
            d_ = float(np.hypot(float(cs[0][0]) - x0[0], float(cs[0][1])))
            w_end = sizes(lam, sig, d_ * st.l1_frac, st.qu, st.qs, st.w_cap * d_ * st.l1_frac)[1][-1]
            if abs(delta) < st.stop_frac * w_end:
                say(f"  pbar_theta at the end {delta:.3g} < {st.stop_frac:g} w_k: the chain passes stop")
                break
        v = eus[0]
        for D in DPs:
            v = D @ v
        shift = -delta / v[1]
        say(f"  pbar_theta at the end {delta:.3g}: shift {shift:.3g} along e_u")
        c1 = [dyadic_of(c1[0] + Fraction(shift) * Fraction(eus[0][0])),
              dyadic_of(c1[1] + Fraction(shift) * Fraction(eus[0][1]))]
    return cs, pcs, brs, fls, (eus, ess, lam, sig), passes


def _branch_boxes(pars, h, sets, p_rad, module, check) -> dict:
    """{i: B}: the level's root pbar_psi unique in B = [p_c - p_rad, p_c + p_rad] over each set's hull."""
    branch = {}
    for i, sd in enumerate(sets):
        c, A = set_data(sd)
        _, B, ok = section_return.level_newton_section(pars, h, *_hull(c, A), Fraction(sd["p_c"]), p_rad, module,
                                                 sd["branch"])
        check(f"N{i} branch box", ok, "pbar_psi unique in the branch box over the set's hull")
        branch[i] = B
    return branch


def _fly_sets(sets, n_src, grids, fly_many, thin_of, branch, check, say):
    """Every piece of the sources N_0 .. N_(n_src - 1) flown one return (fly_many: section_return.piece_return with
    the prover's settings, for a list of pieces, in this process or in others; thin_of[i], when given, is N_i's
    centre flight already taken, reused for a one-piece set), its level and positive return checked in the order of
    the sets and pieces (the serial order, wherever the flights ran).  Returns the certificate's flight records and
    images[(i, n)] = (piece, A_X, flight) for _check_links."""
    plan = []
    for i in range(n_src):
        cN, AN = set_data(sets[i])
        pieces = grid_pieces(*grids[i])
        for n, pc in enumerate(pieces):
            cX, AX = piece_geometry(cN, AN, pc)
            plan.append((i, n, len(pieces), pc, cX, AX))
    results = fly_many([(cX, AX, Fraction(sets[i]["p_c"]), sets[i]["branch"], thin_of.get(i) if m == 1 else None)
                        for i, n, m, pc, cX, AX in plan])
    flights, images, recs = [], {}, []
    try:
        for (i, n, m, pc, _cX, AX), fl in zip(plan, results):
            say(f"set N{i}: piece {n + 1}/{m}")
            ppc = Fraction(sets[i]["p_c"])
            check(f"N{i} piece {n} level", fl["level_ok"] and ball.subset(fl["ppsi_hull"], branch[i]),
                  "pbar_psi unique in its Newton box over the piece, inside the set's branch box")
            check(f"N{i} piece {n} positive return", ball.positive(fl["gdot_thin"]) and ball.positive(fl["gdot_box"]),
                  f"d(sin psi)/dt = {fl['gdot_box']} > 0 at the crossing")
            recs.append({"piece": [_q(v) for v in pc], "p_c": _q(ppc), "t_a": _q(fl["t_a"]),
                         "steps": {kk: [[ball.decimal(s) for s in ph] for ph in vv] for kk, vv in fl["steps"].items()},
                         "n_steps": sum(len(ph) for vv in fl["steps"].values() for ph in vv),
                         "enclosures": {"Pc": [stored(v) for v in fl["Pc"]],
                                        "DP": [[stored(v) for v in row] for row in fl["DP"]],
                                        "ppsi_box": stored(fl["ppsi_box"])}})
            images[(i, n)] = (pc, AX, fl)
            if n == m - 1:
                flights.append({"set": i, "grid": list(grids[i]), "pieces": recs})
                recs = []
    finally:
        flights_close(results)  # after a failed check: the flights not yet taken are cancelled
    return flights, images


def _symmetric_and_disjoint(sets, check) -> None:
    """N0 and the end set N_last symmetric (R(N)^T = N), N0 disjoint from every other set and from the reversed
    copies R(N_j) of the inner ones (exact rationals: the coding by visits to N0 is then well defined), every A
    nondegenerate."""
    last = len(sets) - 1
    for idx in (0, last):
        c, A = set_data(sets[idx])
        check(f"N{idx} symmetric", c[1] == 0 and A[0][1] == A[0][0] and A[1][1] == -A[1][0],
              "centre on Fix(R) and A = [a, R a]: R(N)^T = N")
    polys = [_vertices(*set_data(s)) for s in sets]
    for j in range(1, last + 1):
        other = sets[j]["branch"] != sets[0]["branch"]
        check(f"N0, N{j} disjoint", other or _disjoint(polys[0], polys[j]), "another branch of psi, or a separating "
              "axis (exact rationals)")
    for j in range(1, last):
        other = sets[j]["branch"] != sets[0]["branch"]
        check(f"N0, R(N{j}) disjoint", other or _disjoint(polys[0], [(x, -y) for x, y in polys[j]]),
              "another branch of psi (R keeps it), or a separating axis (exact)")
    for i, s in enumerate(sets):
        c, A = set_data(s)
        check(f"N{i} nondegenerate", A[0][0] * A[1][1] - A[0][1] * A[1][0] != 0, "det A != 0")


def _fliers(P: FloatMap, pars, h, fld, st: HorseshoeSettings, module, check, mapper=None, params=None):
    """The provers' validated flights with the settings st: fly(c, A, pc, branch, ...) one return of the set
    c + A [-1, 1]^2 (section_return.piece_return, t_a from the float return time), fly_many(items) the same for a
    list of (c, A, pc, branch, thin) (by `mapper` in other processes when given: provers/flights.py), pc_of(c) the
    float level root at c, orbit(c1, pc1, n, tol_thin, name) the centres, pbar_psi, branches ("0": cos psi > 0, "pi":
    cos psi < 0) and flights of n validated returns from c1 (the centres: the flights' 128-bit midpoints)."""
    zero = [[Fraction(0), Fraction(0)], [Fraction(0), Fraction(0)]]

    def t_approach_of(c, pc, br):
        x4 = np.zeros(4)
        x4[fields.THETA], x4[fields.PTHETA], x4[fields.PPSI] = float(c[0]), float(c[1]), float(pc)
        x4[fields.PSI] = 0.0 if br == "0" else math.pi
        return t_approach(P.full4(x4)[1], st.lead)

    def fly(c, A, pc, br, steps=None, box=True, tol_thin=None, thin=None):
        t_a = t_approach_of(c, pc, br)
        fl = section_return.piece_return(pars, h, fld, c, A, pc, st.p_rad, t_a, st.lead, t1=st.t1, order=st.order,
                                   tol=st.tol, tol_thin=tol_thin or st.tol_thin, steps=steps, newton=st.newton,
                                   box=box, thin=thin, branch=br, module=module,
                                   integrator=section_return.integrator(st.integrator),
                                   thin_integrator=section_return.integrator(st.thin_integrator))
        fl["t_a"] = t_a
        return fl

    def fly_many(items):
        from . import flights as fj

        if mapper is None:
            # the same balls as from another process: each flight's result (and a reused centre flight) passes
            # through its exact JSON form, whose decoding rounds a radius up by one unit in its last place
            # (provers/flights.py), so that the certificate does not depend on where the flights ran
            return (fj.normalised(fly(c, A, pc, br, thin=None if thin is None else fj.normalised(thin)))
                    for c, A, pc, br, thin in items)

        sj = fj.settings_json(st)
        jobs, t_as = [], []
        for c, A, pc, br, thin in items:
            t_as.append(t_approach_of(c, pc, br))
            jobs.append({"params": params.as_json(), "h": _q(h), "settings": sj, "c": [_q(v) for v in c],
                         "A": [[_q(v) for v in row] for row in A], "pc": _q(pc), "branch": br, "t_a": _q(t_as[-1]),
                         "thin": None if thin is None else fj.encode(thin)})
        return fj.decoded(mapper(fj.piece_job, jobs), t_as)

    def pc_of(c):
        return dyadic(float(P.lift([float(c[0]), float(c[1])])[fields.PPSI]), 50)

    def orbit(c1, pc1, n, tol_thin, name):
        cs, pcs, brs, fls = [c1], [pc1], [st.branch], []
        for j in range(n):
            fl = fly(cs[-1], zero, pcs[-1], brs[-1], box=False, tol_thin=tol_thin)
            check(f"{name} flight {j + 1}", fl["level_ok"], "the level's Newton at the centre")
            cp = fl["cospsi_thin"]
            check(f"{name} flight {j + 1} branch", ball.excludes_zero(cp), f"cos psi = {cp} at the crossing")
            fls.append(fl)
            cs.append([dyadic_of(fl["Pc"][0].mid()), dyadic_of(fl["Pc"][1].mid())])
            pcs.append(dyadic_of(fl["ppsi_thin"].mid(), 60))
            brs.append("0" if ball.positive(cp) else "pi")
        return cs, pcs, brs, fls

    return fly, fly_many, pc_of, orbit


def _chain_sets(cs, pcs, brs, eus, ess, ls, ws) -> list:
    """The chain's h-sets (exact dyadic data): N_j = c_j + [l_j e_u^j, w_j e_s^j] [-1, 1]^2 for the inner centres,
    the last one symmetric, c + l [e_u, R e_u] (its centre is on Fix(R))."""
    out = []
    for j in range(len(cs) - 1):
        u, s = eus[j], ess[j]
        out.append(hset(cs[j], [[dyadic(ls[j] * u[0]), dyadic(ws[j] * s[0])],
                                [dyadic(ls[j] * u[1]), dyadic(ws[j] * s[1])]]))
        out[-1]["p_c"], out[-1]["branch"] = _q(pcs[j]), brs[j]
    ak = [dyadic(ls[-1] * eus[-1][0]), dyadic(ls[-1] * eus[-1][1])]
    out.append(hset(cs[-1], [[ak[0], ak[0]], [ak[1], -ak[1]]]))
    out[-1]["p_c"], out[-1]["branch"] = _q(pcs[-1]), brs[-1]
    return out


def _prove(p, h, x0_theta, st, module, check, say, mapper=None) -> dict:
    pars = p.balls()
    fld = prover_field(p, module, st)
    P = FloatMap(p, h, st.branch, st.root)
    say("float search for x0")
    th_f = section_fixed_point.float_fixed_point(p, h, float(x0_theta), root=st.root, branch=st.branch)[0]
    x0_theta = dyadic(float(th_f), 53)
    x0 = np.array([float(x0_theta), 0.0])
    say("float design")
    fd = float_design(P, x0, st.m_back, st.s_star, st.n_exc)
    k = st.n_exc + st.m_back + 1  # N_1 at z_-m .. N_k at z_n_exc

    fly, fly_many, pc_of, orbit = _fliers(P, pars, h, fld, st, module, check, mapper, p)

    def chain(c1, tol_thin):
        return orbit(c1, pc_of(c1), k - 1, tol_thin, "chain")

    c1 = [x0_theta + Fraction(fd["t"]) * Fraction(fd["e_u0"][0]), Fraction(fd["t"]) * Fraction(fd["e_u0"][1])]
    c1 = [dyadic_of(v) for v in c1]
    # the chain by the validated centre flights; Newton steps along e_u^1 put P^(k-1)(c_1) on Fix(R): two passes
    # at the design tolerance, the last at tol_thin (its flights are the certificate's centre flights)
    cs, pcs, brs, fls, (eus, ess, lam, sig), passes = _chain_passes(chain, c1, fd["e_u0"], x0, k - 1, st, say)
    resid = passes[-1]
    cs[-1] = [dyadic_of(fls[-1]["Pc"][0].mid()), Fraction(0)]
    dist = float(np.hypot(float(cs[0][0]) - x0[0], float(cs[0][1])))
    L = dist * st.l1_frac
    ls, ws = sizes(lam, sig, L, st.qu, st.qs, st.w_cap * L)
    check("end on Fix(R)", abs(resid) < ws[-1] / 4,
          f"pbar_theta(P^(k-1)(c_1)) = {resid:.3g} after the Newton shift, against the size {ws[-1]:.3g} of Nk")
    # the sets (exact dyadic data)
    a0 = [dyadic(dist * st.l0_frac * fd["e_u0"][0]), dyadic(dist * st.l0_frac * fd["e_u0"][1])]
    sets = [hset([dyadic_of(x0_theta, 62), Fraction(0)], [[a0[0], a0[0]], [a0[1], -a0[1]]])]
    sets[0]["p_c"], sets[0]["branch"] = _q(pc_of([x0_theta, Fraction(0)])), st.branch
    sets += _chain_sets(cs, pcs, brs, eus, ess, ls, ws)
    # the branch boxes: the level's root unique in [p_c - p_rad, p_c + p_rad] over each set's hull
    branch = _branch_boxes(pars, h, sets, st.p_rad, module, check)
    # links, pieces, flights
    links = [(0, 0), (0, 1)] + [(j, j + 1) for j in range(1, k)]
    grids = {i: (1, 1) for i in range(k)}
    grids.update(st.pieces or {})
    # the chain's flight from c_i is N_i's centre flight (one piece: c_X = c_i)
    flights, images = _fly_sets(sets, k, grids, fly_many, {i: fls[i - 1] for i in range(1, k)}, branch, check,
                                 say)
    link_rec = _check_links(sets, links, grids, images, branch, check, say)
    # symmetry, disjointness, entropy
    _symmetric_and_disjoint(sets, check)
    Lloop = 2 * k
    rho = entropy_root_lower(Lloop)
    digest = fields.source_digest(module)
    check("field_is_derived", digest == fields.source_digest(gen),
          "the vector field is the derive-generated generated/validated.py (SHA-256 of its source)")
    pj = p.as_json()
    return {
        "format": FORMAT, "kind": KIND,
        "theorem": section_horseshoe_theorem(pj, _q(h), k, Lloop, _q(rho)),
        "params": pj, "level": _q(h), "settings": st.as_json(), "field_digest": digest,
        "sets": sets, "links": [[i, j] for i, j in links], "flights": flights, "link_margins": link_rec,
        "loop_length": Lloop, "entropy": {"rho_lower": _q(rho), "log_rho_lower": math.log(float(rho))},
        "hypotheses_symbolic": ["reversor_reduced", "validated_fields", "full_ham_nondim"],
        "design": {"x0_theta": _q(x0_theta), "s_star": fd["s_star"], "m_back": st.m_back, "dist_c1": dist,
                   "L": L, "l": ls, "w": ws, "stretch_u": lam, "stretch_s": sig, "end_residual": resid, "end_residual_passes": passes,
                   "angles_deg": [float(np.degrees(np.arccos(min(1.0, abs(float(np.dot(u, s))))))) for u, s in
                                  zip(eus, ess)]},
    }


def _prove_cycle(p, h, x0_theta, st, module, check, say, mapper=None) -> dict:
    """The horseshoe around a symmetric period-p orbit of P (st.period = p > 1; module docstring of
    research/fig4c_horseshoe_design.py for the design).  Sets (certificate order): N0 (symmetric, at x0), the
    cycle sets N1 .. N(p-1) at x_1 .. x_(p-1), the excursion sets N(p) .. N(n-1) (C_1 .. C_k, C_1 on W^u(x0) at
    distance d, C_(j+1) = P(C_j), C_k symmetric).  Links: N_i => N_(i+1) (i < p - 1), N(p-1) => N0,
    N(p-1) => N(p), N_j => N_(j+1) (p <= j < n - 1).  Loops through N0: the cycle (length p) and, closed by the
    reversed chain, L = 2 (n - 1) = 2 (p + k - 1); the coding of the visits to N0 gives the blocks 1 0^(p-1) and
    1 0^(L-1): h_top >= log rho, x^L = x^(L-p) + 1."""
    per = st.period
    pars = p.balls()
    fld = prover_field(p, module, st)
    P = FloatMap(p, h, st.branch, st.root)
    say(f"float search for the period-{per} orbit")
    cyc = float_cycle(P, float(x0_theta), per)
    x0_theta = dyadic(cyc["theta"], 53)
    x0 = np.array([float(x0_theta), 0.0])

    fly, fly_many, pc_of, orbit = _fliers(P, pars, h, fld, st, module, check, mapper, p)

    # the cycle: x_0 .. x_(p-1) by validated returns from x0 (x_p = P^p(x0) closes on x0 up to the float theta*)
    say(f"cycle: {per} centre flights (tol {st.tol_thin:g})")
    ccs, cpcs, cbrs, cfls = orbit([dyadic_of(x0_theta, 62), Fraction(0)], pc_of([x0_theta, Fraction(0)]), per,
                                  st.tol_thin, "cycle")
    close = float(np.hypot(float(ccs[-1][0]) - x0[0], float(ccs[-1][1])))
    check("cycle closes", close < 1e-12 and cbrs[-1] == st.branch,
          f"|P^{per}(x0) - x0| = {close:.3g} (float theta*) on x0's branch")
    ccs, cpcs, cbrs = ccs[:per], cpcs[:per], cbrs[:per]
    CD = [_mid_matrix(f["DPc"]) for f in cfls]
    Dp = np.eye(2)
    for D in CD:
        Dp = D @ Dp
    mu, eu = unstable_eigen(Dp)
    ceu = [eu]
    for D in CD[:-1]:
        ceu.append(unit(D @ ceu[-1]))
    ces = [R2 @ eu]
    for D in reversed(CD[1:]):
        ces.append(unit(np.linalg.solve(D, ces[-1])))
    ces = [ces[0]] + ces[1:][::-1]
    clam = [float(np.linalg.norm(D @ u)) for D, u in zip(CD, ceu)]
    csig = [float(np.linalg.norm(D @ s)) for D, s in zip(CD, ces)]
    say(f"  mu_u(DP^{per}) = {mu:.6g}, stretches {[round(v, 3) for v in clam]}")
    check("cycle hyperbolic (design)", abs(mu) > st.q_cycle ** per,
          f"|mu_u(DP^p)| = {abs(mu):.4g} > q_cycle^p (the float design's margins around the cycle)")
    # the excursion chain C_1 .. C_k from C_1 = x0 + t e_u, t = s* mu_u^-m (m pull-backs by P^p)
    k = st.n_exc + per * st.m_back + 1
    s_star = _float_s_star(P, x0, eu, st.s_star, st.n_exc)
    t = s_star / abs(mu) ** st.m_back
    c1 = [dyadic_of(x0_theta + Fraction(t) * Fraction(eu[0])), dyadic_of(Fraction(t) * Fraction(eu[1]))]
    cs, pcs, brs, fls, (eus, ess, lam, sig), passes = _chain_passes(
        lambda c, tl: orbit(c, pc_of(c), k - 1, tl, "chain"), c1, eu, x0, k - 1, st, say)
    resid = passes[-1]
    cs[-1] = [dyadic_of(fls[-1]["Pc"][0].mid()), Fraction(0)]
    dist = float(np.hypot(float(cs[0][0]) - x0[0], float(cs[0][1])))
    L = dist * st.l1_frac
    ls, ws = sizes(lam, sig, L, st.qu, st.qs, st.w_cap * L)
    check("end on Fix(R)", abs(resid) < ws[-1] / 4,
          f"pbar_theta(P^(k-1)(C_1)) = {resid:.3g} after the Newton shift, against the size {ws[-1]:.3g} of C_k")
    # the cycle's sizes: l_(i+1) = lam_i l_i / q, w_(i+1) = q sig_i w_i from l_0 = w_0 = l0_frac d
    l0 = dist * st.l0_frac
    lc, wc = [l0], [l0]
    for i in range(per - 1):
        lc.append(clam[i] * lc[-1] / st.q_cycle)
        wc.append(st.q_cycle * csig[i] * wc[-1])
    a0 = [dyadic(l0 * eu[0]), dyadic(l0 * eu[1])]
    sets = [hset(ccs[0], [[a0[0], a0[0]], [a0[1], -a0[1]]])]
    sets[0]["p_c"], sets[0]["branch"] = _q(cpcs[0]), cbrs[0]
    for i in range(1, per):
        u, s = ceu[i], ces[i]
        sets.append(hset(ccs[i], [[dyadic(lc[i] * u[0]), dyadic(wc[i] * s[0])],
                                  [dyadic(lc[i] * u[1]), dyadic(wc[i] * s[1])]]))
        sets[-1]["p_c"], sets[-1]["branch"] = _q(cpcs[i]), cbrs[i]
    sets += _chain_sets(cs, pcs, brs, eus, ess, ls, ws)
    n = len(sets)
    branch = _branch_boxes(pars, h, sets, st.p_rad, module, check)
    links = cycle_links(per, n)
    grids = {i: (1, 1) for i in range(n - 1)}
    grids.update(st.pieces or {})
    thin_of = {i: cfls[i] for i in range(per)}
    thin_of.update({per + j: fls[j] for j in range(k - 1)})  # C_(j+1)'s centre flight is the chain's j-th
    flights, images = _fly_sets(sets, n - 1, grids, fly_many, thin_of, branch, check, say)
    link_rec = _check_links(sets, links, grids, images, branch, check, say)
    _symmetric_and_disjoint(sets, check)
    Lloop = 2 * (n - 1)
    rho = entropy_root_lower_cycle(per, Lloop)
    digest = fields.source_digest(module)
    check("field_is_derived", digest == fields.source_digest(gen),
          "the vector field is the derive-generated generated/validated.py (SHA-256 of its source)")
    pj = p.as_json()
    return {
        "format": FORMAT, "kind": KIND,
        "theorem": section_horseshoe_theorem(pj, _q(h), n - 1, Lloop, _q(rho), period=per),
        "params": pj, "level": _q(h), "settings": st.as_json(), "field_digest": digest,
        "sets": sets, "links": [[i, j] for i, j in links], "flights": flights, "link_margins": link_rec,
        "loop_length": Lloop, "loop_lengths": [per, Lloop],
        "entropy": {"rho_lower": _q(rho), "log_rho_lower": math.log(float(rho))},
        "hypotheses_symbolic": ["reversor_reduced", "validated_fields", "full_ham_nondim"],
        "design": {"x0_theta": _q(x0_theta), "period": per, "mu_u_cycle": mu, "cycle_closure": close,
                   "cycle_stretch_u": clam, "cycle_stretch_s": csig, "l_cycle": lc, "w_cycle": wc,
                   "s_star": s_star, "m_back": st.m_back, "dist_c1": dist, "L": L, "l": ls, "w": ws,
                   "stretch_u": lam, "stretch_s": sig, "end_residual": resid, "end_residual_passes": passes,
                   "angles_deg": [float(np.degrees(np.arccos(min(1.0, abs(float(np.dot(u, s))))))) for u, s in
                                  zip(ceu + eus, ces + ess)]},
    }


def cycle_links(period: int, n: int) -> list:
    """The links of the period-p graph on n sets (_prove_cycle; the verifier requires exactly these): the cycle
    N0 => N1 => ... => N(p-1) => N0, then N(p-1) => N(p) => ... => N(n-1)."""
    return ([(i, i + 1) for i in range(period - 1)] + [(period - 1, 0), (period - 1, period)]
            + [(j, j + 1) for j in range(period, n - 1)])


def _check_links(sets, links, grids, images, branch, check, say, shift=None) -> list:
    """The covering conditions (a'), (b), the image's psi branch and pbar_psi branch of every link i => j from the
    pieces' flights images[(i, n)] = (piece, A_X, flight); shift(i, j, fl): the flight with its "Pc" replaced by the
    enclosure to use against M = N_j (a lambdabar interval: widen).  Returns the link records."""
    link_rec = []
    for i, j in links:
        cM, AM = set_data(sets[j])
        amin, right, left = math.inf, [], []
        for n, pc in enumerate(grid_pieces(*grids[i])):
            _, AX, fl = images[(i, n)]
            off, G = image_in((cM, AM), fl if shift is None else shift(i, j, fl), AX)
            a_ok, margin, edges = piece_checks(off, G, pc)
            cps = [fl["cospsi_box"], fl["cospsi_thin"]]
            check(f"N{i} => N{j} piece {n} psi branch", all(ball.positive(v) if sets[j]["branch"] == "0" else
                                                             ball.negative(v) for v in cps),
                  f"cos psi = {cps[0]} at the crossing: the image lies on M's branch psi = {sets[j]['branch']} mod 2 pi")
            check(f"N{i} => N{j} piece {n} (a)", a_ok, f"image in M's coordinates: y_u = {off[0]} + ..., y_s ="
                  f" {off[1]} + G ...: stays in |y_s| < 1 (margin 1 - max |y_s| = {margin:.4g})")
            amin = min(amin, margin)
            if -1 in edges:
                left.append(edges[-1])
            if 1 in edges:
                right.append(edges[1])
            # the branch of pbar_psi: where the image lands in M it is M's root
            check(f"N{i} => N{j} piece {n} branch", ball.subset(fl["ppsi_box"], branch[j]),
                  f"pbar_psi of the image {fl['ppsi_box']} inside M's branch box {branch[j]} (unique root there)")
        o = 1 if ball.bounds(right[0])[0] > 1 else -1
        okb = all((ball.bounds(e)[0] > 1) if o == 1 else (ball.bounds(e)[1] < -1) for e in right) and \
            all((ball.bounds(e)[1] < -1) if o == 1 else (ball.bounds(e)[0] > 1) for e in left)
        bmin = min(min(abs(float(ball.bounds(e)[0 if o == 1 else 1])) for e in right),
                   min(abs(float(ball.bounds(e)[1 if o == 1 else 0])) for e in left))
        check(f"N{i} => N{j} (b)", okb, f"the exit edges' images beyond M's exit edges (orientation {o}), "
              f"min |y_u| = {bmin:.4g}")
        link_rec.append({"from": i, "to": j, "orientation": o, "a_margin": amin, "b_min_abs_yu": bmin})
        say(f"N{i} => N{j}: (a) margin {amin:.3g}, (b) min |y_u| {bmin:.3g}")
    return link_rec


def _hull(c, A):
    U = ball.interval(-1, 1)
    return (ball.q(c[0]) + ball.q(A[0][0]) * U + ball.q(A[0][1]) * U,
            ball.q(c[1]) + ball.q(A[1][0]) * U + ball.q(A[1][1]) * U)


def _vertices(c, A):
    return [(c[0] + A[0][0] * a + A[0][1] * b, c[1] + A[1][0] * a + A[1][1] * b) for a, b in
            ((1, 1), (1, -1), (-1, -1), (-1, 1))]


def _disjoint(P1, P2) -> bool:
    """Two convex polygons (exact vertices, in order) are disjoint iff some edge normal separates them strictly."""
    for poly in (P1, P2):
        n = len(poly)
        for i in range(n):
            (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
            nx, ny = y2 - y1, x1 - x2
            a = [nx * x + ny * y for x, y in P1]
            b = [nx * x + ny * y for x, y in P2]
            if max(a) < min(b) or max(b) < min(a):
                return True
    return False


def entropy_root_lower(L: int, digits: int = 12) -> Fraction:
    """A rational rho_lo < rho, the largest root of x^L = x^(L-1) + 1 (f(rho_lo) < 0 for f = x^L - x^(L-1) - 1,
    f(2) > 0, f increasing on [1, 2] beyond its one critical point (L-1)/L < 1): by bisection on [1, 2]."""
    lo, hi = Fraction(1), Fraction(2)
    for _ in range(int(digits * 3.33) + 2):
        mid = (lo + hi) / 2
        if mid**L - mid ** (L - 1) - 1 < 0:
            lo = mid
        else:
            hi = mid
    return lo


def entropy_root_lower_cycle(p: int, L: int, digits: int = 12) -> Fraction:
    """A rational rho_lo < rho, the largest root of x^L = x^(L-p) + 1 (p < L: the blocks "1 0^(p-1)" and
    "1 0^(L-1)"; p = 1 is entropy_root_lower's polynomial): f = x^L - x^(L-p) - 1 has f(1) = -1 < 0, f(2) > 0 and
    f' = x^(L-p-1) (L x^p - (L-p)) > 0 for x >= 1, so one root in (1, 2): bisection, f(rho_lo) < 0 exactly."""
    if not 1 <= p < L:
        raise ValueError("need 1 <= p < L")
    lo, hi = Fraction(1), Fraction(2)
    for _ in range(int(digits * 3.33) + 2):
        mid = (lo + hi) / 2
        if mid**L - mid ** (L - p) - 1 < 0:
            lo = mid
        else:
            hi = mid
    return lo
