"""Statement 11 (issue 27): a symmetric hyperbolic fixed point of the section map sin psi = 0 on Fig 4's level
h = 9/10 (magrod/proof/provers/section_fixed_point.py), its certificate kind "section_fixed_point" and the complete verifier's checks of
it (verify.py).  The shipped certificates verify; every tampering is rejected, most of them before any flight is
replayed (< 1 s); the shifted-box and mutated-field controls fail; the docs quote the certificates' intervals.

Each rejection test was seen to fail once with the check it names removed from the verifier's _fixed_point
(magrod/proof/kernel/fixed_point.py; the tampered certificate then verified or failed elsewhere)."""
from __future__ import annotations

import copy
import json
import re
from fractions import Fraction
from importlib import resources
from pathlib import Path

import numpy as np
import pytest

from helpers import assert_rejected, verify_cli

from magrod.cli import main
from magrod.proof import fields, theorem, tiling, verify
from magrod.proof.provers import section_fixed_point

ROOT = Path(__file__).resolve().parents[1]
FIG4A = ["--m", "17/10", "--mu", "2/5", "--gamma", "3", "--delta", "3", "--lam", "27/200"]
SHIPPED = {"a": "27/200", "b": "63/400", "d": "93/500", "a_interval": "27/200"}


def _shipped(panel):
    return json.loads(resources.files("magrod.proof").joinpath("certificates", f"fixed_point_fig4{panel}.json")
                      .read_text())


@pytest.fixture(scope="module")
def cert():
    return _shipped("a")


@pytest.mark.parametrize("panel", sorted(SHIPPED))
def test_shipped_certificates_state_their_theorem(panel):
    c = _shipped(panel)
    assert c["kind"] == "section_fixed_point" and c["level"] == "9/10"
    assert c["params"] == {"m": "17/10", "mu": "2/5", "gamma": "3/1", "delta": "3/1", "lam": SHIPPED[panel]}
    assert c["theorem"] == theorem.section_fixed_point_theorem(c["params"], "9/10", c["settings"].get("lam_rad", "0"),
                                                               moving="v" in c["settings"])


def test_the_fig4a_certificate_verifies_and_prints_the_generated_theorem(cert, tmp_path, capsys):
    p = tmp_path / "c.json"
    p.write_text(json.dumps(cert))
    assert main(["prove", "--verify", str(p), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["ok"] and out["theorem"] == theorem.section_fixed_point_theorem(cert["params"], "9/10")
    # the float benchmark's saddle (research/fig4_candidates.json, panel 0.135: theta 0.3830461903149033,
    # |eigenvalues of DP^2| 33.0405 = mu_u^2, return time of P^2 11.4109 = 2 T) lies in the verified balls
    vals = {k: [float(Fraction(v)) for v in b] for k, b in out["values"].items()}
    assert vals["theta*"][0] - 1e-12 <= 0.3830461903149033 <= vals["theta*"][1] + 1e-12
    mu = 33.04052256946038 ** 0.5
    assert vals["mu_u"][0] <= mu * (1 + 1e-6) and vals["mu_u"][1] >= mu * (1 - 1e-6)
    assert vals["return time T"][0] - 1e-6 <= 11.410932152563042 / 2 <= vals["return time T"][1] + 1e-6
    FIG4A_VALUES.update(out["values"])


FIG4A_VALUES: dict = {}


@pytest.mark.slow
@pytest.mark.parametrize("panel", ["b", "d"])
def test_the_other_shipped_certificates_verify(panel):
    res = verify.verify(_shipped(panel))
    assert res.ok, res.reason


def test_a_theorem_text_that_claims_more_is_rejected(cert, tmp_path, capsys):
    bad = copy.deepcopy(cert)
    bad["theorem"] = bad["theorem"].replace("(a saddle of P;", "(a saddle of P with a transverse homoclinic point;")
    assert_rejected(bad, tmp_path, capsys, "theorem text")


def test_a_missing_flight_is_rejected(cert, tmp_path, capsys):
    bad = copy.deepcopy(cert)
    del bad["flights"]["box"]
    assert_rejected(bad, tmp_path, capsys, "flights present")


def test_a_trace_ball_inside_the_unit_band_is_rejected(cert, tmp_path, capsys):
    bad = copy.deepcopy(cert)
    bad["trace"] = {"mid": "1.5", "rad": "0.001"}
    assert_rejected(bad, tmp_path, capsys, "claims on the certificate's balls")


def test_another_level_is_rejected(cert, tmp_path, capsys):
    """The level changed consistently (theorem text too): the level's interval Newton no longer holds."""
    bad = copy.deepcopy(cert)
    bad["level"] = "1/1"
    bad["theorem"] = theorem.section_fixed_point_theorem(bad["params"], "1/1")
    assert_rejected(bad, tmp_path, capsys, "level Newton (box)")


@pytest.mark.parametrize("shift, check", [(10, "claims on the certificate's balls"), (Fraction(1, 2), "level (box) recomputed")])
def test_the_shifted_box_control_is_rejected(cert, tmp_path, capsys, shift, check):
    """theta_c moved by 10 r: the stored Newton ball is no longer inside the box (rejected before any
    recomputation); by r/2: every stored claim still holds, and the first recomputed enclosure (the level's Newton
    ball over the shifted box) is outside the certificate's ball."""
    bad = copy.deepcopy(cert)
    bad["point"]["theta_c"] = str(Fraction(bad["point"]["theta_c"]) + shift * Fraction(bad["settings"]["r"]))
    assert_rejected(bad, tmp_path, capsys, check)


def test_a_dropped_step_is_rejected(cert, tmp_path, capsys):
    bad = copy.deepcopy(cert)
    bad["flights"]["thin"]["steps2"] = bad["flights"]["thin"]["steps2"][:-1]
    assert_rejected(bad, tmp_path, capsys, "thin steps")


def test_an_unknown_kind_is_bad_input(cert, tmp_path, capsys):
    bad = copy.deepcopy(cert)
    bad["kind"] = "horseshoe"
    code, _, err = verify_cli(bad, tmp_path, capsys)
    assert code == 2 and len(err) == 1 and "unknown certificate kind" in err[0]


def test_the_mutated_field_control_fails_to_prove():
    p, h = section_fixed_point.validate("17/10", "2/5", "3", "3", "27/200", "9/10")
    res = section_fixed_point.prove(p, h, 0.3830461903149033, module=fields.mutated_module(0))
    assert not res.ok and res.certificate is None and "not established" in res.reason


def test_the_monodromy_formula():
    """DP = R A^-1 R A (reversibility) has trace 2 (ad + bc)/(ad - bc) and determinant 1, for any invertible A; for
    det A = 1 (the half-map of Hamilton's flow between psi = 0 and psi = pi) its trace is also 2 + 4bc = 4ad - 2,
    and trace_DP intersects the three (seen to fail: with a random A of det != 1 the enclosures are disjoint)."""
    from flint import arb

    from magrod.proof import ball

    rng = np.random.default_rng(3)
    R = np.diag([1.0, -1.0])
    for _ in range(5):
        a = float(2.0 ** rng.integers(-2, 3) * rng.choice([-1, 1]))
        b, c = rng.normal(size=2)
        with ball.workprec(256):  # exact: d = (1 + bc)/a with a a power of two, so det A = 1 exactly
            ab = [arb(a), arb(b), arb(c), (1 + arb(b) * arb(c)) / a]
            tr = section_fixed_point.trace_DP(*ab)
        A = np.array([[a, b], [c, float(ab[3].mid())]])
        M = R @ np.linalg.inv(A) @ R @ A
        assert abs(float(tr.mid()) - np.trace(M)) < 1e-9 * (1 + abs(np.trace(M)))
        assert abs(np.linalg.det(M) - 1) < 1e-9
    with pytest.raises(ValueError, match="disjoint"):
        section_fixed_point.trace_DP(*(arb(v) for v in (2.0, 0.5, 0.25, 1.0)))  # det 15/8: not a half-map of the flow


@pytest.mark.parametrize("name", ["fixed_point_fig4a.json", "fixed_point_fig4b.json", "fixed_point_fig4d.json",
                                  "fixed_point_fig5a.json", "fixed_point_fig4a_interval.json"])
def test_the_half_map_is_area_preserving(name):
    """det A = ad - bc = 1, which tr = 2 + 4bc rests on (Hamilton's flow preserves dtheta ^ dpbar_theta between the
    sections psi = 0 and psi = pi): the certificates' own box enclosures of a, b, c, d, computed without using it,
    give ad - bc within 1e-6 of 1 at the points and contain 1 on the interval boxes."""
    from flint import arb

    from magrod.proof import ball

    c = json.loads(resources.files("magrod.proof").joinpath("certificates", name).read_text())
    e = {k: ball.from_json(v) for k, v in c["flights"]["box"]["enclosures"].items()}
    det = e["dth_theta"] * e["dpt_ptheta"] - e["dpt_theta"] * e["dth_ptheta"]
    assert (det - 1).contains(arb(0)) or abs(float(det.mid()) - 1) < 1e-6, det


CERTS = Path(__file__).resolve().parents[1] / "magrod" / "proof" / "certificates"


@pytest.mark.parametrize("args, name", [(["--fixed-point", "4", "--level", "0.9"], "fixed_point"),
                                        (["--fixed-point", "0.383"], "level"),
                                        (["--fixed-point", "x", "--level", "0.9"], "fixed_point"),
                                        (["--fixed-point", "0.383", "--level", "0.9", "--lam-rad", "-1"], "lam_rad"),
                                        # --horseshoe shares the input handling (cli/prove.py _section_inputs)
                                        (["--horseshoe", "4", "--level", "0.9"], "horseshoe"),
                                        (["--horseshoe", "0.383"], "level"),
                                        (["--horseshoe", "0.383", "--level", "0.9", "--mutate", "x"], "mutate"),
                                        (["--horseshoe", "0.383", "--level", "0.9", "--design", "fig4z"], "design"),
                                        # a cycle design fixes its orbit's branch and root
                                        (["--horseshoe", "1.98883", "--level", "0.9", "--design", "fig4c"], "branch"),
                                        (["--horseshoe", "0.383", "--level", "0.9", "--lam-rad", "-1"], "lam_rad"),
                                        # --widen: a point horseshoe certificate and W > 0
                                        (["--widen", str(CERTS / "horseshoe_fig4a.json")], "lam_rad"),
                                        (["--widen", str(CERTS / "fixed_point_fig4a.json"), "--lam-rad", "1e-11"],
                                         "widen"),
                                        (["--widen", str(CERTS / "horseshoe_fig4a_interval.json"), "--lam-rad",
                                          "1e-11"], "widen"),
                                        # second order: an order 1 or 2, an even K in 2 .. 64, a dyadic radius
                                        (["--widen", str(CERTS / "horseshoe_fig4a.json"), "--lam-rad", "1/134217728",
                                          "--lam-order", "3"], "lam_order"),
                                        (["--widen", str(CERTS / "horseshoe_fig4a.json"), "--lam-rad", "1/134217728",
                                          "--lam-order", "2", "--lam-nodes", "7"], "lam_nodes"),
                                        (["--widen", str(CERTS / "horseshoe_fig4a.json"), "--lam-rad", "1/134217728",
                                          "--lam-nodes", "x"], "lam_nodes"),
                                        (["--widen", str(CERTS / "horseshoe_fig4a.json"), "--lam-rad", "1/100000000",
                                          "--lam-order", "2"], "lam_rad"),
                                        (["--fixed-point", "0.383", "--level", "0.9", "--lam-order", "2"],
                                         "lam_order")])
def test_bad_input_is_exit_2_naming_the_parameter(args, name, tmp_path, capsys):
    out = tmp_path / "never"
    code = main(["prove", *FIG4A, *args, "--out", str(out), "--quiet", "--json"])
    cap = capsys.readouterr()
    assert code == 2 and len(cap.err.strip().splitlines()) == 1 and json.loads(cap.out)["parameter"] == name
    assert not out.exists()


def test_the_docs_quote_the_certificates_intervals():
    """Statement 11's text (rendered into docs/nonintegrability.md) quotes tr DP, mu_u and T per panel: each quoted
    interval contains the certificate's (outward rounding)."""
    from magrod.proof import statements

    text = statements.BY_NUMBER["11"].text
    for panel in "abd":
        c = _shipped(panel)
        tr = [Fraction(c["trace"]["mid"]) - Fraction(c["trace"]["rad"]),
              Fraction(c["trace"]["mid"]) + Fraction(c["trace"]["rad"])]
        quoted = [(Fraction(a), Fraction(b)) for a, b in re.findall(r"\[([0-9.]+), ([0-9.]+)\] \(" + panel + r"\)",
                                                                       text.replace("−", "-"))]
        assert any(a <= tr[0] and tr[1] <= b for a, b in quoted), (panel, tr, quoted)
    if FIG4A_VALUES:  # the verified return time of (a) (from the verification test above)
        T = [Fraction(v) for v in FIG4A_VALUES["return time T"]]
        assert any(a <= T[0] and T[1] <= b for a, b in
                   [(Fraction(a), Fraction(b)) for a, b in re.findall(r"\[([0-9.]+), ([0-9.]+)\] \(a\)", text)]), T


def test_the_lambda_column_of_the_state_field_is_the_derivative():
    """fields.lam_state_field: the Jacobian's lambdabar column (forward-mode _Dual) and the generated columns agree
    with central differences of the field (float, step 1e-7: truncation ~1e-14 |f'''|, rounding ~1e-9)."""
    from flint import arb

    p = fields.ExactParams.from_values(m=Fraction(17, 10), mu=Fraction(2, 5), gamma=3, delta=3, lam=Fraction(27, 200))
    F = fields.lam_state_field(p)
    x0 = np.array([0.5, 0.3, 0.1, 1.1, 0.135])
    J = F.jacobian([arb(v) for v in x0], None)

    def f(x):
        return np.array([float(v.mid()) for v in F.rhs([arb(float(v)) for v in x], None)])

    for j in range(5):
        d = np.zeros(5)
        d[j] = 1e-7
        fd = (f(x0 + d) - f(x0 - d)) / 2e-7
        assert np.allclose([float(J[5 * i + j].mid()) for i in range(5)], fd, atol=1e-7), j


def test_the_interval_certificate_states_its_theorem_and_rejects_a_wider_interval(tmp_path, capsys):
    """The shipped box moves with lambdabar (settings.v): its theorem says so, and without v (the fixed box's
    reading of the same data) the text is another theorem.  Twice the interval, consistently claimed: the level's
    Newton ball over the moving box is recomputed wider."""
    c = _shipped("a_interval")
    assert c["settings"]["lam_rad"] == "1/100000" and c["params"]["lam"] == "27/200" and "v" in c["settings"]
    want = theorem.section_fixed_point_theorem(c["params"], "9/10", "1/100000", moving=True)
    assert c["theorem"] == want and "every lambdabar in [13499/100000, 13501/100000]" in want
    assert "moves with lambdabar along the certificate's v" in want and "theta - v (lambdabar - lam)" in want
    bad = copy.deepcopy(c)
    bad["settings"]["lam_rad"] = "2/100000"
    bad["theorem"] = theorem.section_fixed_point_theorem(c["params"], "9/10", "2/100000", moving=True)
    assert_rejected(bad, tmp_path, capsys, "level (box) recomputed")
    bad = copy.deepcopy(c)
    del bad["settings"]["v"]  # the fixed box's theorem would be claimed from the moving box's data
    assert_rejected(bad, tmp_path, capsys, "theorem text")


def test_the_moving_box_is_checked_where_it_moves(tmp_path, capsys):
    """Controls of the moving box: its slope v moved by 1/64 (0.3 %; the theorem text does not name v) is
    rejected, the section derivative along the moving box recomputed elsewhere (by 1/1024 it verifies, and
    rightly: every enclosure recomputed for that box still lies in its stored ball, so the theorem holds for it
    too); a moving box claimed at a point (lam_rad 0) is rejected by the settings check."""
    c = _shipped("a_interval")
    bad = copy.deepcopy(c)
    v = Fraction(c["settings"]["v"]) + Fraction(1, 64)
    bad["settings"]["v"] = f"{v.numerator}/{v.denominator}"
    assert_rejected(bad, tmp_path, capsys, "box dl_theta recomputed")
    bad = copy.deepcopy(c)
    bad["settings"]["lam_rad"] = "0"
    bad["theorem"] = theorem.section_fixed_point_theorem(c["params"], "9/10", "0", moving=True)
    assert_rejected(bad, tmp_path, capsys, "settings match the data")


def _widened(c, frac):
    """c claiming lam_rad (1 + frac) with its theorem text regenerated for it (a consistent tampering)."""
    w = Fraction(c["settings"]["lam_rad"]) * (1 + frac)
    bad = copy.deepcopy(c)
    bad["settings"]["lam_rad"] = f"{w.numerator}/{w.denominator}"
    bad["theorem"] = theorem.section_fixed_point_theorem(c["params"], c["level"], bad["settings"]["lam_rad"],
                                                         c["point"].get("branch", "0"), "v" in c["settings"])
    return bad


@pytest.mark.parametrize("name", ["fixed_point_fig4a_interval.json", "fixed_point_fig5a_interval.json"])
def test_an_interval_widened_beyond_its_balls_slack_is_rejected(name, tmp_path, capsys):
    """The smallest widening the certificate's balls do not absorb is rejected: its radius times 1 + 2^-10 (the
    stored balls are the prover's enclosures widened by 2^-10 of their radius, search.stored, so that another
    python-flint build's last-bit rounding still verifies); for the moving boxes a flight's recomputed enclosure
    is the first to leave its ball (their level balls over the box have the slack to hold it).  A widening by one
    ulp of the radius (float64: 1 + 2^-52; Arb's radius: 1 + 2^-30) verifies, and rightly: the verifier recomputes
    every enclosure on the widened interval and each still lies in its stored ball, so the wider theorem is what
    it checked (research/README.md, "Section fixed points on a lambdabar box")."""
    c = json.loads(resources.files("magrod.proof").joinpath("certificates", name).read_text())
    assert_rejected(_widened(c, Fraction(1, 2**10)), tmp_path, capsys, "recomputed")


@pytest.mark.slow
def test_the_interval_certificate_verifies():
    res = verify.verify(_shipped("a_interval"))
    assert res.ok, res.reason


def test_interval_settings_size_the_theta_box_by_the_measured_motion():
    """The fixed theta-box (`magrod prove --fixed-point --lam-rad W --box fixed`) is sized from theta*'s float motion
    (4 |dtheta*/dlambdabar| W): at Fig 4(a), W = 1e-6, r = 21 W, which holds the interval Newton image of that box
    (radius 17.2 W: research/fixed_point_interval_limits.json, K = 20) and is the first interval certificate's
    r = 20 W within 5 %; interval_settings' fixed r = 8 W does not hold it.  The moving box is sized by K' W about
    the fixed point moving with the measured slope v (signed, on a 2^-16 grid: exact in binary)."""
    p, h = section_fixed_point.validate("17/10", "2/5", "3", "3", "27/200", "9/10")
    w = Fraction(1, 10**6)
    rows = json.loads((ROOT / "research" / "fixed_point_interval_limits.json").read_text())["rows"]
    newton = Fraction(next(r for r in rows if r["panel"] == "4a" and r["lam_rad"] == "1/1000000")["newton_rad"])
    st = section_fixed_point.interval_settings_for(p, h, 0.383, w)
    assert st.lam_rad == w and st.v is None and newton < st.r <= Fraction(21, 20) * 20 * w
    assert section_fixed_point.interval_settings(w).r < newton
    mv = section_fixed_point.interval_settings_for(p, h, 0.383, w, moving=2)
    assert mv.r == 2 * w and abs(float(mv.v) + 5.2336) < 1e-3 and (mv.v * 2**16).denominator == 1


@pytest.mark.slow
def test_the_cli_proves_the_shipped_box_and_it_verifies(tmp_path, capsys):
    assert main(["prove", "--fixed-point", "0.383", "--level", "0.9", *FIG4A, "--lam-rad", "1/100000", "--out",
                 str(tmp_path), "--json", "--quiet"]) == 0
    out = json.loads(capsys.readouterr().out)
    c = json.loads(Path(out["certificate"]).read_text())
    assert c["theorem"] == _shipped("a_interval")["theorem"]
    assert verify.verify(c).ok


def _tiles():
    d = resources.files("magrod.proof").joinpath("certificates", "fig4a_interval")
    return [json.loads(f.read_text()) for f in sorted(d.iterdir(), key=lambda f: f.name) if f.name.endswith(".json")]


def test_the_interval_tiles_cover_their_union_exactly():
    """research/fig4_lambda_interval.py's 21 certificates: adjacent lambdabar boxes [c - w, c + w] whose union is
    [13479/100000, 13521/100000] = 27/200 +- 2.1e-4 with no gap (tiling.chain_interval, exact rationals), each
    stating the theorem for its box (moving with lambdabar)."""
    tiles = _tiles()
    for c in tiles:
        assert c["kind"] == "section_fixed_point" and Fraction(c["settings"]["lam_rad"]) == Fraction(1, 10**5)
        assert c["theorem"] == theorem.section_fixed_point_theorem(c["params"], c["level"], c["settings"]["lam_rad"],
                                                                   moving=True)
    assert len(tiles) == 21
    assert tiling.chain_interval(tiles) == (Fraction(13479, 100000), Fraction(13521, 100000))


def test_a_tile_dropped_from_the_chain_is_rejected():
    """Without its middle box the chain covers no interval: rejected, naming the gap (seen to fail: with the gap
    check removed from tiling.chain_interval the union was reported whole); an end box dropped leaves a shorter
    interval, not the stated one; another level's box is another theorem."""
    tiles = sorted(_tiles(), key=lambda c: Fraction(c["params"]["lam"]))
    with pytest.raises(tiling.ChainError, match=r"gap in lambdabar between 13499/100000 and 13501/100000"):
        tiling.chain_interval(tiles[:10] + tiles[11:])
    assert tiling.chain_interval(tiles[1:]) == (Fraction(13481, 100000), Fraction(13521, 100000))
    other = copy.deepcopy(tiles[0])
    other["level"] = "8/10"
    with pytest.raises(tiling.ChainError, match="different theorems"):
        tiling.chain_interval(tiles[1:] + [other])
    point = copy.deepcopy(tiles[0])
    point["settings"]["lam_rad"] = "0"
    with pytest.raises(tiling.ChainError, match="point certificate"):
        tiling.chain_interval(tiles[1:] + [point])


@pytest.mark.slow
def test_every_interval_tile_verifies():
    assert tiling.chain_interval(_tiles(), verify=True) == (Fraction(13479, 100000), Fraction(13521, 100000))


def test_the_fixed_box_still_proves_and_verifies(tmp_path, capsys):
    """`--box fixed` (the first interval certificates' theta_c +- r for every lambdabar, no settings.v): proves at
    W = 1e-7 and verifies with the theorem that does not say the box moves; the same interval with the moving box
    states that it moves."""
    args = ["prove", "--fixed-point", "0.383046", "--level", "9/10", *FIG4A, "--lam-rad", "1/10000000", "--json",
            "--quiet"]
    assert main([*args, "--box", "fixed", "--out", str(tmp_path / "f")]) == 0
    c = json.loads(Path(json.loads(capsys.readouterr().out)["certificate"]).read_text())
    assert "v" not in c["settings"] and "--box fixed" in c["provenance"]["command"]
    res = verify.verify(c)
    assert res.ok and res.theorem == theorem.section_fixed_point_theorem(c["params"], "9/10", "1/10000000")
    assert "moves with lambdabar" not in res.theorem
    assert main([*args, "--out", str(tmp_path / "m")]) == 0
    m = json.loads(Path(json.loads(capsys.readouterr().out)["certificate"]).read_text())
    assert "v" in m["settings"] and "moves with lambdabar" in m["theorem"]
