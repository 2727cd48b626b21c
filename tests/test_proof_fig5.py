"""Fig 5's own level (issue 27, item 4; docs/nonintegrability.md, statement 13): the saddle of the section map on the
psi = pi branch of Sigma+ at the four gammas of fig:poincare2 (kind "section_fixed_point"), and the horseshoe of
the section map (kind "section_horseshoe") where it closed.

Every tamper test changes one field of a stored certificate and requires the verifier to reject it at the check
named in the test (seen to fail: each asserts the rejection and its reason).  Complete re-verifications of more
than ~10 s and the provers' controls are behind --full (slow).
"""
from __future__ import annotations

import copy
import json
from fractions import Fraction
from importlib import resources

import pytest

from magrod.proof import fields, verify
from magrod.proof.provers import horseshoe_design, section_fixed_point, section_horseshoe
from magrod.proof.theorem import section_fixed_point_theorem, section_horseshoe_theorem
from helpers import shift_set_along_entry

PANELS = {"a": "3/20", "b": "41/200", "c": "26/125", "d": "6/25"}  # fig:poincare2's gammas 0.15 .. 0.24
FIG5 = {"m": "17/10", "mu": "4", "delta": "1/4", "lam": "2"}  # the caption: m = 1.7, delta = 0.25, lam = 2, mu = 4
HORSESHOES = ["horseshoe_fig5a.json", "horseshoe_fig5b.json", "horseshoe_fig5c.json", "horseshoe_fig5d.json",
              "horseshoe_fig5a_interval.json"]  # (a)'s sets moving with lambdabar: 2 +- 2e-11 (horseshoe_widen.widen)


def _load(name):
    return json.loads(resources.files("magrod.proof").joinpath("certificates", name).read_text())


@pytest.fixture(scope="module", params=sorted(PANELS))
def fp(request):
    return request.param, _load(f"fixed_point_fig5{request.param}.json")


def _rejected(c, *, module=fields.gen):
    res = verify.verify(c, module=module)
    assert not res.ok
    return res.reason


def test_fixed_point_certificates_are_fig5s(fp):
    """Each certificate is at Fig 5's parameters (the caption's m, mu, delta, lambdabar; the panel's gamma) on its
    level 4/5, on the psi = pi branch, and states the theorem generated for exactly that (mu = 2 lambdabar)."""
    key, c = fp
    assert c["kind"] == "section_fixed_point" and c["level"] == "4/5" and c["point"]["branch"] == "pi"
    assert {k: c["params"][k] for k in FIG5} == {k: f"{Fraction(v).numerator}/{Fraction(v).denominator}"
                                                 for k, v in FIG5.items()}
    assert Fraction(c["params"]["gamma"]) == Fraction(PANELS[key])
    assert Fraction(c["params"]["mu"]) == 2 * Fraction(c["params"]["lam"])
    assert c["theorem"] == section_fixed_point_theorem(c["params"], "4/5", "0", "pi")
    assert "(psi = pi, pbar_theta = 0)" in c["theorem"]


def test_fixed_point_branch_tamper(fp):
    """The branch relabelled psi = 0 (the theorem text regenerated to match): the level's Newton at psi = 0 is
    another point of the level and the recomputed enclosure is not the certificate's -- rejected."""
    _, c = fp
    c = copy.deepcopy(c)
    del c["point"]["branch"]
    c["theorem"] = section_fixed_point_theorem(c["params"], "4/5", "0", "0")
    reason = _rejected(c)
    assert "level" in reason, reason


def test_fixed_point_theorem_claims_psi0_rejected(fp):
    """A psi = pi certificate whose theorem says psi = 0 is rejected at the theorem check."""
    _, c = fp
    c = copy.deepcopy(c)
    c["theorem"] = section_fixed_point_theorem(c["params"], "4/5", "0", "0")
    assert "theorem" in _rejected(c)


def test_fixed_point_mutated_field_rejected(fp):
    _, c = fp
    assert "Hamiltonian form f = J grad Hbar failed" in _rejected(c, module=fields.mutated_module(0))


@pytest.mark.slow
@pytest.mark.parametrize("key", sorted(PANELS))
def test_fixed_point_fig5_verifies(key):
    """The complete verifier accepts each panel's saddle (6 s at load ~3, 12-13 s at load ~6) and generates the
    psi = pi theorem."""
    res = verify.verify(_load(f"fixed_point_fig5{key}.json"))
    assert res.ok, res.reason
    assert "(psi = pi, pbar_theta = 0)" in res.theorem


def test_interval_certificate_states_its_theorem():
    """fixed_point_fig5a_interval.json: every lambdabar in 2 +- 1e-4 (mu = 4 fixed; the box moving with lambdabar),
    psi = pi, its generated theorem; a wider interval in the theorem text is rejected (seen to fail: the theorem
    check)."""
    c = _load("fixed_point_fig5a_interval.json")
    assert c["settings"]["lam_rad"] == "1/10000" and c["point"]["branch"] == "pi"
    assert c["theorem"] == section_fixed_point_theorem(c["params"], "4/5", "1/10000", "pi", moving=True)
    bad = copy.deepcopy(c)
    bad["theorem"] = section_fixed_point_theorem(c["params"], "4/5", "1/5000", "pi", moving=True)
    assert "theorem" in _rejected(bad)


@pytest.mark.slow
def test_interval_certificate_verifies():
    res = verify.verify(_load("fixed_point_fig5a_interval.json"))
    assert res.ok, res.reason


@pytest.mark.slow
def test_lambda_zero_control_has_no_saddle():
    """lambdabar = 0 (the integrable extensible rod, otherwise Fig 5(a)'s rod and level): the float search finds
    symmetric fixed points of P near theta = 3.1076 (psi = pi) but DP there is parabolic (tr ~ 2, as on a resonant
    torus of an integrable twist map) and the prover fails at "hyperbolic" (tr DP in [2.00 +/- 3.3e-3]); no
    sign change within 0.02 of Fig 5(a)'s theta* = 3.012.  Seen to fail (i.e. to prove nothing) in both places;
    ~25 s."""
    p, h = section_fixed_point.validate("17/10", "4", "3/20", "1/4", "0", "4/5")
    res = section_fixed_point.prove(p, h, 3.1076291042978577, root=0, branch="pi")
    assert not res.ok and res.certificate is None and "hyperbolic not established" in res.reason, res.reason
    res = section_fixed_point.prove(p, h, 3.0119924258452446, root=0, branch="pi")
    assert not res.ok and "no sign change" in res.reason, res.reason


# --------------------------------------------------------------------------------------------------------------
# the horseshoe
# --------------------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module", params=HORSESHOES)
def hs(request):
    return _load(request.param)


def test_horseshoe_certificate_claims(hs):
    """At Fig 5's parameters on h = 4/5, N0 on the psi = pi branch, the generated theorem, the entropy bound."""
    k = len(hs["sets"]) - 1
    assert hs["kind"] == "section_horseshoe" and hs["level"] == "4/5" and hs["loop_length"] == 2 * k
    assert hs["sets"][0]["branch"] == "pi" and hs["settings"]["branch"] == "pi"
    assert Fraction(hs["params"]["mu"]) == 2 * Fraction(hs["params"]["lam"]) == 4
    assert hs["theorem"] == section_horseshoe_theorem(hs["params"], hs["level"], k, 2 * k, hs["entropy"]["rho_lower"],
                                                      hs["settings"].get("lam_rad", "0"))
    rho = Fraction(hs["entropy"]["rho_lower"])
    assert rho ** (2 * k) - rho ** (2 * k - 1) - 1 < 0


def test_horseshoe_mutated_field_rejected(hs):
    assert "Hamiltonian form f = J grad Hbar failed" in _rejected(hs, module=fields.mutated_module(0))


def test_horseshoe_tamper_N0_branch(hs):
    """N0 relabelled psi = 0: its branch box (the level's root over N0 at psi = 0) does not hold, or the
    disjointness/branch claims fail -- rejected before any flight of N1 ..."""
    c = copy.deepcopy(hs)
    c["sets"][0]["branch"] = "0"
    reason = _rejected(c)
    assert "N0" in reason, reason


def test_horseshoe_tamper_N0_off_FixR(hs):
    c = copy.deepcopy(hs)
    c["sets"][0]["c"][1] = "1/10000000000000"
    assert "N0 symmetric" in _rejected(c)


def test_horseshoe_tamper_entropy(hs):
    """rho_lower = 6/5, above the largest root of x^L = x^(L-1) + 1 for L = 24 and 30 (1.1036, 1.0876; 11/10
    is not: it lies below the root for L = 24, and the rejection came from the theorem text instead)."""
    c = copy.deepcopy(hs)
    c["entropy"]["rho_lower"] = "6/5"
    assert "entropy bound" in _rejected(c)


@pytest.mark.slow
def test_horseshoe_shifted_set_fails_covering(hs):
    """N2 shifted by 3 of its half-widths along its entry direction: (a') fails at N1 => N2 (the image of N1 lies
    at y_s ~ -3 in N2's coordinates), after N0 and N1 are re-flown."""
    reason = _rejected(shift_set_along_entry(hs, 2))
    assert "N1 => N2 piece 0 (a)" in reason, reason


@pytest.mark.slow
def test_horseshoe_certificate_verifies(hs):
    res = verify.verify(hs)
    assert res.ok, res.reason


@pytest.mark.slow
def test_horseshoe_mutated_field_control_fails_to_prove():
    """Control: the sign of term 0 of the generated chart field flipped; the prover fails and issues nothing."""
    p, h = section_fixed_point.validate("17/10", "4", "3/20", "1/4", "2", "4/5")
    st = horseshoe_design.HorseshoeSettings(branch="pi", root=0, m_back=3, n_exc=12, s_star=1.1709116837165307e-07)
    res = section_horseshoe.prove(p, h, 3.0119924258452446, st, module=fields.mutated_module(0))
    assert not res.ok and res.certificate is None, res.reason


# --------------------------------------------------------------------------------------------------------------
# the command line and the docs
# --------------------------------------------------------------------------------------------------------------
FIG5A = ["--m", "1.7", "--mu", "4", "--gamma", "0.15", "--delta", "0.25", "--lam", "2"]


@pytest.mark.parametrize("args, name", [(["--fixed-point", "3.012", "--level", "0.8", "--root", "x"], "root"),
                                        (["--fixed-point", "3.012", "--level", "0.8", "--root", "9"], "root"),
                                        (["--horseshoe", "3.012", "--level", "0.8", "--passes", "tol,fast"],
                                         "passes"),
                                        (["--horseshoe", "3.012", "--level", "0.8", "--s-star", "2"], "s_star"),
                                        (["--horseshoe", "3.012", "--level", "0.8", "--m-back", "-1"], "m_back"),
                                        (["--horseshoe", "3.012", "--level", "0.8", "--n-exc", "0"], "n_exc")])
def test_bad_section_options_are_exit_2_naming_the_parameter(args, name, tmp_path, capsys):
    """Every new option is checked before anything is computed or written (seen to fail: each case)."""
    from magrod.cli import main

    out = tmp_path / "never"
    code = main(["prove", *FIG5A, *args, "--branch", "pi", "--out", str(out), "--quiet", "--json"])
    cap = capsys.readouterr()
    assert code == 2 and json.loads(cap.out)["parameter"] == name, cap.out
    assert not out.exists()


def test_statement_13_quotes_the_certificates_traces():
    """Statement 13's text quotes tr DP(x0) per panel: each quoted interval contains the certificate's ball
    (outward rounding), and it quotes the horseshoe's entropy bound at most as strong as the certificate's."""
    import re

    from magrod.proof import statements

    text = statements.BY_NUMBER["13"].text.replace("−", "-")
    for key in PANELS:
        c = _load(f"fixed_point_fig5{key}.json")
        mid, rad = Fraction(c["trace"]["mid"]), Fraction(c["trace"]["rad"])
        quoted = [(Fraction(a), Fraction(b)) for a, b in re.findall(r"\[(-[0-9.]+), (-[0-9.]+)\] \(" + key + r"\)",
                                                                       text)]
        assert any(a <= mid - rad and mid + rad <= b for a, b in quoted), (key, quoted)
    for name in HORSESHOES:
        c = _load(name)
        key = name[len("horseshoe_fig5"):][0]
        q = re.search(r"> ([0-9.]+) \(" + key + r"\)", text)
        assert q and Fraction(q.group(1)) < Fraction(repr(c["entropy"]["log_rho_lower"])), (key, q)
