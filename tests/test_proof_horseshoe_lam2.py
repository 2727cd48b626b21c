"""Fig 4(a)'s horseshoe on the lambdabar interval 27/200 +- 43/2^32 (1.0012e-8), second order in lambdabar
(horseshoe_fig4a_interval_wide.json; magrod/proof/kernel/horseshoe_lam2.py, statement 12).

The structural tampering (a deleted link, an asymmetric end set, a raised entropy bound, a missing piece, ...) is
covered for this certificate by tests/test_proof_horseshoe.py's tests over every horseshoe certificate.  Here: what
this certificate claims against the first-order interval certificate, the second-order data's own tampering
(decided before any flight, so fast), and the covering check of the critical link N12 => N13 on N12's piece
re-flown with the certificate's steps (~55 s), which holds as stored and fails when its inputs are mutated.  The
complete verification (~6 min of CPU) is CI's own step (.ci/run) and a slow test.
"""
from __future__ import annotations

import copy
import json
from fractions import Fraction
from importlib import resources

import pytest

from magrod.proof import ball, fields, verify
from magrod.proof.kernel import horseshoe_lam2 as lam2
from magrod.proof.kernel.horseshoe_sets import _hs_branch_boxes, _hs_set

WIDE = "horseshoe_fig4a_interval_wide.json"
FIRST = "horseshoe_fig4a_interval.json"


def _load(name):
    return json.loads(resources.files("magrod.proof").joinpath("certificates", name).read_text())


@pytest.fixture(scope="module")
def wide():
    return _load(WIDE)


def _rejected(c):
    res = verify.verify(c, workers=1)  # in this process: a tampered N0 is decided before any other set's flight
    assert not res.ok
    return res.reason


def test_the_wide_certificate_is_the_interval_one_500_times_wider(wide):
    """The same sets and motions as the first-order interval certificate, its interval 43/2^32 >= 1e-8, 500x wider (the
    first order reaches 2e-11 at Fig 4(a): tests/test_proof_horseshoe.py, test_interval_needs_the_motion), every
    piece with its K + 1 nodes whose middle one is the point piece's centre (K = 8, doubled by the prover where a
    link's margin stayed below 1/4: N10, N11 16, N12 64), and every link's recorded margins positive."""
    first = _load(FIRST)
    W, K = lam2.lam2_settings(wide)
    assert W == Fraction(43, 2**32) and K == 8 and wide["settings"]["lam_order"] == 2 and W > Fraction(1, 10**8)
    assert W / Fraction(first["settings"]["lam_rad"]) > 500
    assert wide["sets"] == first["sets"] and wide["links"] == first["links"] and wide["entropy"] == first["entropy"]
    lam = Fraction(wide["params"]["lam"])
    assert f"every lambdabar in [{lam - W}, {lam + W}]" in wide["theorem"]
    Ks = {}
    for fl in wide["flights"]:
        for r in fl["pieces"]:
            Kr = r["lam_nodes"]
            assert len(r["steps"]["nodes"]) == Kr + 1 == len(r["nodes_p_c"]) and r["nodes_p_c"][Kr // 2] == r["p_c"]
            Ks[fl["set"]] = Kr
    assert Ks == {**{i: 8 for i in range(14)}, 10: 16, 11: 16, 12: 64}
    assert len(wide["link_margins"]) == len(wide["links"])
    assert all(m["a_margin"] > 0.17 and m["b_min_abs_yu"] > 2.9 for m in wide["link_margins"])


def test_a_dropped_node_is_rejected(wide):
    """A node dropped from N0's piece (its steps and its Newton centre), the middle node's centre not the piece's,
    or the piece claiming more sub-intervals than it has nodes: rejected at the piece's nodes, before the piece
    flies; a piece's odd K is malformed.  Seen to fail: with the check's K + 1 count removed the flights ran."""
    c = copy.deepcopy(wide)
    r = c["flights"][0]["pieces"][0]
    del r["steps"]["nodes"][3], r["nodes_p_c"][3]
    assert "N0 piece 0 nodes" in _rejected(c)
    c = copy.deepcopy(wide)
    mid = wide["settings"]["lam_nodes"] // 2
    r = c["flights"][0]["pieces"][0]
    r["nodes_p_c"][mid] = r["nodes_p_c"][mid - 1]
    assert "N0 piece 0 nodes" in _rejected(c)  # the middle node is the point piece's own centre
    c = copy.deepcopy(wide)
    c["flights"][0]["pieces"][0]["lam_nodes"] = 16  # more sub-intervals than its nodes
    assert "N0 piece 0 nodes" in _rejected(c)
    c = copy.deepcopy(wide)
    c["flights"][0]["pieces"][0]["lam_nodes"] = 7
    with pytest.raises(verify.CertificateError, match="lam_nodes"):
        verify.verify(c, workers=1)


def test_a_node_step_not_summing_to_t_a_is_rejected(wide):
    c = copy.deepcopy(wide)
    c["flights"][0]["pieces"][0]["steps"]["nodes"][2][1][0] = "1/2"
    assert "N0 piece 0 node 2 steps" in _rejected(c)
    c = copy.deepcopy(wide)
    c["flights"][0]["pieces"][0]["steps"]["swept"][0][0] = "1/3"
    assert "N0 piece 0 swept steps" in _rejected(c)


@pytest.mark.parametrize("key, value", [("lam_nodes", 7), ("lam_nodes", 0), ("lam_nodes", "8"), ("lam_order", 3),
                                        ("lam_order", True)])
def test_second_order_settings_out_of_range_are_malformed(wide, key, value):
    c = copy.deepcopy(wide)
    c["settings"][key] = value
    with pytest.raises(verify.CertificateError, match=key):
        verify.verify(c, workers=1)


def test_a_theorem_on_a_wider_interval_is_rejected(wide):
    """The theorem text claiming twice the interval the settings name: rejected at the theorem, and the settings'
    lam_rad doubled with it: the covering check fails (test_the_critical_link_check_is_live: W doubled)."""
    c = copy.deepcopy(wide)
    W, lam = Fraction(c["settings"]["lam_rad"]), Fraction(c["params"]["lam"])
    c["theorem"] = c["theorem"].replace(f"[{lam - W}, {lam + W}]", f"[{lam - 2 * W}, {lam + 2 * W}]")
    assert c["theorem"] != wide["theorem"]
    assert "theorem" in _rejected(c)


@pytest.fixture(scope="module")
def n12(wide):
    """N12's piece re-flown with the certificate's exact steps (as the verifier does), its data, the sets and the
    branch boxes."""
    c = wide
    s = c["settings"]
    with ball.workprec(int(s["prec"]), int(s["series_cap"])):
        p = fields.ExactParams(**{k: Fraction(c["params"][k]) for k in fields.PARAMS})
        sets = [_hs_set(d) for d in c["sets"]]
        brs = [d.get("branch", "0") for d in c["sets"]]
        boxes = [B for _ok, B in _hs_branch_boxes(c, p.balls(), sets, brs, fields.gen)]
        d = lam2.piece_data(c, 12, 0)
        W, K = lam2.lam2_settings(c)[0], d["K"]
        fl = lam2.fly_piece(p, Fraction(c["level"]), s, d["cX"], d["AX"], [Fraction(x) for x in c["sets"][12]["v"]],
                            W, K, d["p_c"], d["nodes_pc"], d["t_a"], brs[12], fields.gen, d["steps"])
    return {"fl": fl, "d": d, "sets": sets, "brs": brs, "boxes": boxes, "W": W, "K": K, "prec": int(s["prec"]),
            "cap": int(s["series_cap"])}


def _link(n12, wide, *, fl=None, W=None, K=None, v=None):
    failed = []

    def claim(name, holds, how):
        if not holds:
            failed.append(name)

    with ball.workprec(n12["prec"], n12["cap"]):
        out = lam2.link_checks(12, 13, [(n12["d"]["piece"], n12["d"]["AX"], fl or n12["fl"], K or n12["K"])],
                               n12["sets"][13], v or [Fraction(x) for x in wide["sets"][13]["v"]], W or n12["W"],
                               n12["brs"][13], n12["boxes"][13], claim)
    return failed, out


def test_the_critical_link_check_is_live(n12, wide):
    """N12 => N13, the link that limits the first-order certificate: with the re-flown enclosures every condition
    holds on each of its 64 sub-intervals, with the margins the certificate records; each mutation of its inputs
    fails it at (a): the same flights claimed for twice the interval, the 64 sub-intervals read as 16 (every fourth node: the
    interpolation error's h^2 grows 16x), the curve's second derivative [P''] taken 8x or the mixed one [F_us]
    10x (at 2^-27 they took the margin 0.33 to -0.28 and -0.34), N13's motion v off by a relative 1e-6 (the moving frame
    then misses the image by ~2x N13's entry width)."""
    failed, out = _link(n12, wide)
    assert failed == [], failed
    rec = next(m for m in wide["link_margins"] if (m["from"], m["to"]) == (12, 13))
    assert abs(out["a_margin"] - rec["a_margin"]) < 1e-6 and abs(out["b_min_abs_yu"] - rec["b_min_abs_yu"]) < 1e-3
    fl = n12["fl"]
    assert "N12 => N13 piece 0 (a)" in _link(n12, wide, W=2 * n12["W"])[0]
    assert "N12 => N13 piece 0 (a)" in _link(n12, wide, K=n12["K"] // 4, fl={**fl, "nodes": fl["nodes"][::4]})[0]
    with ball.workprec(n12["prec"], n12["cap"]):
        P2x8 = {**fl, "curve": {**fl["curve"], "P2": [8 * x for x in fl["curve"]["P2"]]}}
        Fas10 = {**fl, "swept": {**fl["swept"], "Fas": [[10 * x for x in r] for r in fl["swept"]["Fas"]]}}
    assert "N12 => N13 piece 0 (a)" in _link(n12, wide, fl=P2x8)[0]
    assert "N12 => N13 piece 0 (a)" in _link(n12, wide, fl=Fas10)[0]
    v = [Fraction(x) * (1 + Fraction(1, 10**6)) for x in wide["sets"][13]["v"]]
    assert "N12 => N13 piece 0 (a)" in _link(n12, wide, v=v)[0]


def test_the_replayed_flights_are_positive_returns_on_the_branch(n12):
    """The replayed piece passes its own checks: the level's root in the branch box at every node, over the curve and
    over the swept piece, and every crossing a positive first return."""
    failed = []
    with ball.workprec(n12["prec"], n12["cap"]):
        lam2.check_piece(12, 0, n12["fl"], n12["boxes"], lambda name, holds, how: failed.append(name) if not holds
                         else None)
    assert failed == []


@pytest.mark.slow
def test_the_wide_certificate_verifies(wide):
    """The complete verifier accepts it (~6 min of CPU; CI runs `magrod prove --verify` on it in a step of its own)."""
    res = verify.verify(wide, workers=2)
    assert res.ok, res.reason
    assert res.theorem == wide["theorem"]
