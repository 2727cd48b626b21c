"""Kind "section_horseshoe" (statement 12; the prover is magrod/proof/provers/section_horseshoe.py): covering relations of the
section map on Hbar = h.  The flights are section_return.piece_return driven with the certificate's exact steps (the
integrator is shared); the covering conditions, the cover by pieces, the symmetry, the disjointness, the chain's
completeness and the entropy bound are checked again here, in exact rationals where they are geometric.  Cost
(`magrod reproduce` verifies it): the Taylor coefficients by Newton's iteration on series instead of the prover's
Picard iteration (taylor._newton_series), the centres flown as C^0 sets, and the sets re-flown in child processes
(kernel/pool.py; the same checks replayed in the same order): 44-58 s of CPU instead of ~150-220 s.
"""
from __future__ import annotations

import time

from .. import ball, fields, identities
from ..theorem import section_horseshoe_theorem
# the set and branch-box checks (also run by the child processes of pool.py); the geometric helpers are named here
# too, as the tests address them through this module
from .horseshoe_sets import (_hs_branch_boxes, _hs_cover, _hs_graph, _hs_inv, _hs_lam,  # noqa: F401
                             _hs_separated, _hs_separated_moving, _hs_set, _hs_source, _hs_vertices, lam_order)
from .horseshoe_lam2 import set_source
from .schema import VerifyResult, check_structure, checked, frac, section_settings

def verify(cert, module, t0, workers=None, mapper=None) -> VerifyResult:
    def body(claim):
        p, prec, cap, order = section_settings(cert)
        with ball.workprec(prec, cap):
            return p, _horseshoe(cert, p, order, module, claim, workers, mapper)

    checks, out, failed = checked(t0, body)
    if failed:
        return failed
    p, vals = out
    return VerifyResult(True, "certificate verified: every link re-flown and every check holds", checks,
                        time.perf_counter() - t0,
                        section_horseshoe_theorem(p.as_json(), cert["level"], vals["k"], vals["L"], vals["rho"],
                                                  vals["lam_rad"], period=vals["period"]),
                        {}, {})


def _horseshoe(cert, p, order, module, claim, workers=None, mapper=None) -> dict:
    check_structure(module, claim)
    claim("field digest", cert["field_digest"] == fields.source_digest(module) == fields.source_digest(fields.gen),
          "the certificate's field is the installed derive-generated one")
    claim(identities.PSI_PERIODIC, *identities.psi_periodic(fields.source(module), fields.PARAMS))
    sets = [_hs_set(d) for d in cert["sets"]]
    brs = [d.get("branch", "0") for d in cert["sets"]]
    if any(b not in ("0", "pi") for b in brs):
        raise ValueError("a set's branch is '0' or 'pi'")
    k = len(sets) - 1
    claim("chain length", k >= 2, f"{k + 1} sets")
    per, want = _hs_graph(cert, k + 1)
    claim("links", [list(map(int, lk)) for lk in cert["links"]] == want,
          "exactly N0 => N0, N0 => N1 => ... => Nk (a complete chain)" if per == 1 else
          f"exactly the cycle N0 => N1 => ... => N{per - 1} => N0 and the chain N{per - 1} => N{per} => ... => N{k}")
    for i, (_c, A) in enumerate(sets):
        claim(f"N{i} nondegenerate", A[0][0] * A[1][1] - A[0][1] * A[1][0] != 0, "det A != 0")
    lm = _hs_lam(cert, p, module)
    if lam_order(cert) == 2:
        from .horseshoe_lam2 import lam2_settings

        lam2_settings(cert)  # W > 0 and an even K in range, before any flight
    for i in (0, k):
        c, A = sets[i]
        claim(f"N{i} symmetric", c[1] == 0 and A[0][1] == A[0][0] and A[1][1] == -A[1][0] and
              (lm is None or lm[4][i][1] == 0),
              "centre on Fix(R) and A = [a, R a], so R(N)^T = N exactly" +
              ("" if lm is None else "; it moves along Fix(R) (v's pbar_theta = 0)"))
    V0 = _hs_vertices(*sets[0])
    for j in range(1, k + 1):
        if lm is None:
            sep = _hs_separated(V0, _hs_vertices(*sets[j]))
        else:
            sep = _hs_separated_moving(V0, _hs_vertices(*sets[j]), (lm[4][j][0] - lm[4][0][0],
                                                                    lm[4][j][1] - lm[4][0][1]), lm[0])
        claim(f"N0, N{j} disjoint", brs[j] != brs[0] or sep,
              "another branch of psi, or a separating edge normal" + ("" if lm is None else " for every lambdabar"))
    for j in range(1, k):
        RV = [(x, -y) for x, y in _hs_vertices(*sets[j])]
        if lm is None:
            sep = _hs_separated(V0, RV)
        else:
            sep = _hs_separated_moving(V0, RV, (lm[4][j][0] - lm[4][0][0], -lm[4][j][1] - lm[4][0][1]), lm[0])
        claim(f"N0, R(N{j}) disjoint", brs[j] != brs[0] or sep,
              "another branch of psi (R keeps it), or a separating edge normal" +
              ("" if lm is None else " for every lambdabar"))
    L = 2 * k
    claim("loop length", int(cert["loop_length"]) == L, f"the loop N0 => ... => N{k} <= ... <= N0 has length 2k = {L}")
    rho = frac(cert["entropy"]["rho_lower"])
    # the other loop through N0 has length p (p = 1: N0 => N0): blocks 1 0^(p-1) and 1 0^(L-1), x^L = x^(L-p) + 1
    # (f(1) = -1, f increasing on [1, 2]: f(rho_lower) < 0 puts rho_lower below the largest root)
    claim("entropy bound", 1 < rho < 2 and rho**L - rho ** (L - per) - 1 < 0,
          f"rho_lower = {float(rho):.12g} is below the largest root of x^{L} = x^{L - per} + 1 (f(rho_lower) < 0)")
    w_txt = "0" if lm is None else f"{lm[0].numerator}/{lm[0].denominator}"
    text = section_horseshoe_theorem(p.as_json(), cert["level"], k, L, cert["entropy"]["rho_lower"], w_txt,
                                     period=per)
    claim("theorem", cert.get("theorem") == text, "the certificate states exactly the theorem generated here")
    fl_by_set = {int(f["set"]): f for f in cert["flights"]}
    claim("flights", sorted(fl_by_set) == list(range(k)), "one flight record per set N0 .. N(k-1)")
    pieces = {}
    for i in range(k):
        pieces[i] = [tuple(frac(v) for v in r["piece"]) for r in fl_by_set[i]["pieces"]]
        claim(f"N{i} cover", _hs_cover(pieces[i]), f"the {len(pieces[i])} pieces cover [-1, 1]^2 exactly")
    pars = p.balls()
    boxes = [B for _ok, B in _hs_branch_boxes(cert, pars, sets, brs, module, claim)]
    from . import pool  # the sets in child processes (scheduling; the checks are replayed here in the serial order)

    w = 1 if module is not fields.gen else min(pool._hs_workers(workers), k)
    if mapper is not None and module is fields.gen:
        pool._hs_sources_mapped(cert, k, mapper, claim)
    elif w <= 1:
        for i in range(k):
            set_source(cert, i, order, module, claim, boxes)
    else:
        pool._hs_sources_parallel(cert, k, w, claim)
    return {"k": k, "L": L, "rho": cert["entropy"]["rho_lower"], "lam_rad": w_txt, "period": per}
