"""The covering-relation horseshoe of the section map on Fig 4(a)'s level (magrod/proof/provers/section_horseshoe.py, verify.py kind
"section_horseshoe"; docs/nonintegrability.md, statement 12).

The tamper tests change one field of the stored certificate and require the verifier to reject it, each at the check
named in the test (seen to fail: every test below asserts the rejection and its reason).  The structural checks
(links, symmetry, disjointness, cover, entropy, theorem) run before any flight, so these tests are fast; the complete
re-verification (every piece re-flown, ~45 s of CPU) is behind --full.
"""
from __future__ import annotations

import copy
import json
from fractions import Fraction
from importlib import resources
from pathlib import Path

import pytest

from magrod.proof import fields, verify
from magrod.proof.provers import horseshoe_design, horseshoe_widen, section_fixed_point, section_horseshoe
from magrod.proof.kernel import horseshoe as hs_kernel
from helpers import shift_set_along_entry, verify_cli

CERT = "horseshoe_fig4a.json"
#: a_interval: Fig 4(a)'s sets moving with lambdabar, for every lambdabar in 27/200 +- 2e-11 (horseshoe_widen.widen)
INTERVAL = "horseshoe_fig4a_interval.json"
#: c: Fig 4(c)'s horseshoe around the period-6 orbit of P (the cycle N0 => ... => N5 => N0, section_horseshoe._prove_cycle)
CYCLE = "horseshoe_fig4c.json"
#: a_wide: the same sets on 27/200 +- 43/2^32 (1.0012e-8), second order in lambdabar (kernel/horseshoe_lam2.py)
CERTS = {"a": CERT, "b": "horseshoe_fig4b.json", "a_interval": INTERVAL, "c": CYCLE,
         "a_wide": "horseshoe_fig4a_interval_wide.json"}


def _load(name):
    return json.loads(resources.files("magrod.proof").joinpath("certificates", name).read_text())


@pytest.fixture(scope="module")
def cert():
    return _load(CERT)


@pytest.fixture(scope="module", params=sorted(CERTS))
def any_cert(request):
    return _load(CERTS[request.param])


def _rejected(c, *, module=fields.gen):
    res = verify.verify(c, module=module)
    assert not res.ok
    return res.reason


def test_cover_check_exact():
    """A product grid covers the square; a missing or an overlapping piece does not (seen to fail: both)."""
    g = section_horseshoe.grid_pieces(2, 2)
    assert hs_kernel._hs_cover(g)
    assert not hs_kernel._hs_cover(g[:-1])
    assert not hs_kernel._hs_cover(g[:-1] + [(Fraction(0), Fraction(0), Fraction(1, 2), Fraction(1, 2))])


def test_separating_axis():
    sq = hs_kernel._hs_vertices([Fraction(0), Fraction(0)], [[Fraction(1), Fraction(0)], [Fraction(0), Fraction(1)]])
    far = hs_kernel._hs_vertices([Fraction(3), Fraction(0)], [[Fraction(1), Fraction(0)], [Fraction(0), Fraction(1)]])
    touch = hs_kernel._hs_vertices([Fraction(2), Fraction(0)], [[Fraction(1), Fraction(0)], [Fraction(0), Fraction(1)]])
    assert hs_kernel._hs_separated(sq, far)
    assert not hs_kernel._hs_separated(sq, touch)  # closed sets sharing an edge are not disjoint


def test_entropy_root():
    """rho_lower is below the largest root of x^L = x^(L-1) + 1 and within 1e-10 of it (L = 28: rho = 1.0947...,
    checked by numpy's roots)."""
    import numpy as np

    L = 28
    r = section_horseshoe.entropy_root_lower(L)
    assert r**L - r ** (L - 1) - 1 < 0
    roots = np.roots([1, -1] + [0] * (L - 2) + [-1])
    big = max(z.real for z in roots if abs(z.imag) < 1e-12)
    assert 0 < big - float(r) < 1e-10


def test_entropy_root_cycle():
    """The period-p bound (loops of lengths p and L: x^L = x^(L-p) + 1): p = 1 is entropy_root_lower's root exactly;
    at Fig 4(c)'s design (p = 6, L = 160) rho_lower lies below the numpy root and within 1e-10 of it (seen to fail:
    with the polynomial of p = 1 the bound at p = 6 lies above the root)."""
    import numpy as np

    for L in (28, 38):
        assert section_horseshoe.entropy_root_lower_cycle(1, L) == section_horseshoe.entropy_root_lower(L)
    p, L = 6, 160
    r = section_horseshoe.entropy_root_lower_cycle(p, L)
    assert r**L - r ** (L - p) - 1 < 0
    coef = [0] * (L + 1)
    coef[0], coef[p], coef[L] = 1, -1, -1  # x^L - x^(L-p) - 1, highest power first
    big = max(z.real for z in np.roots(coef) if abs(z.imag) < 1e-9)
    assert 0 < big - float(r) < 1e-10
    r1 = section_horseshoe.entropy_root_lower(L)
    assert r1**L - r1 ** (L - p) - 1 > 0  # the p = 1 root is larger: it would over-claim at p = 6
    with pytest.raises(ValueError):
        section_horseshoe.entropy_root_lower_cycle(L, L)


def test_cycle_graph():
    """The graph of a period-p certificate: the verifier's required links are the prover's (section_horseshoe.cycle_links);
    period 1 is the fixed-point chain; a period leaving fewer than two sets after the cycle is malformed."""
    n = 81
    c = {"settings": {"period": 6}}
    per, want = hs_kernel._hs_graph(c, n)
    assert per == 6 and want == [list(lk) for lk in section_horseshoe.cycle_links(6, n)]
    assert want[:7] == [[0, 1], [1, 2], [2, 3], [3, 4], [4, 5], [5, 0], [5, 6]] and want[-1] == [79, 80]
    assert len(want) == n  # p - 1 cycle links, the closing one, N(p-1) => Np, and n - 1 - p chain links
    assert hs_kernel._hs_graph({"settings": {}}, 5) == (1, [[0, 0], [0, 1], [1, 2], [2, 3], [3, 4]])
    for bad in (0, 1 - 2, 79):
        with pytest.raises(ValueError):
            hs_kernel._hs_graph({"settings": {"period": bad}}, n)


def test_psi_periodic_check():
    """The generated chart field is 2 pi-periodic in psi, proved by its exact evaluation with psi known only through
    sin and cos (identities.psi_periodic); a field that uses psi otherwise -- in arithmetic, or in a comparison that
    would answer silently -- fails it, and so does the horseshoe verifier's check of that name."""
    from magrod.proof import identities

    assert identities.psi_periodic(fields.source(), fields.PARAMS)[0]
    src = fields.source()
    for old, new in (("(psi).sin()", "(psi + 0).sin()"), ("    return [\n        ptheta,\n",
                                                          "    return [\n        ptheta if psi == 0 else ptheta,\n")):
        assert src.count(old) >= 1, old
        holds, how = identities.psi_periodic(src.replace(old, new, 1), fields.PARAMS)
        assert not holds and "not evaluable exactly" in how, (new, how)


def test_certificate_claims(any_cert):
    """Each stored certificate's theorem is the generated text, and its numbers are those of the chain."""
    cert = any_cert
    k = len(cert["sets"]) - 1
    assert cert["kind"] == "section_horseshoe" and cert["loop_length"] == 2 * k
    from magrod.proof.theorem import section_horseshoe_theorem

    assert cert["theorem"] == section_horseshoe_theorem(cert["params"], cert["level"], k, 2 * k,
                                                        cert["entropy"]["rho_lower"],
                                                        cert["settings"].get("lam_rad", "0"),
                                                        period=int(cert["settings"].get("period", 1)))


def test_cycle_certificate_claims():
    """Fig 4(c): the cycle of 6 sets and the chain to N80, loops 6 and 160, the polynomial x^160 = x^154 + 1."""
    c = _load(CYCLE)
    assert c["settings"]["period"] == 6 and len(c["sets"]) == 81 and c["loop_lengths"] == [6, 160]
    assert [list(lk) for lk in c["links"]] == [list(lk) for lk in section_horseshoe.cycle_links(6, 81)]
    assert "N0 => N1 => ... => N5 => N0" in c["theorem"] and "x^160 = x^154 + 1" in c["theorem"]


def test_cycle_tamper():
    """Fig 4(c)'s certificate: the cycle's closing link N5 => N0 deleted, the period set to 1 (then the links are
    not the fixed-point chain's), a rho_lower of the period-1 polynomial (above the root of x^160 = x^154 + 1), and
    the period-1 theorem text (loops 1 and 160: more entropy than verified) are each rejected."""
    base = _load(CYCLE)
    c = copy.deepcopy(base)
    c["links"].remove([5, 0])
    assert "links" in _rejected(c)
    c = copy.deepcopy(base)
    c["settings"]["period"] = 1
    assert "links" in _rejected(c)
    c = copy.deepcopy(base)
    r1 = section_horseshoe.entropy_root_lower(160)
    c["entropy"]["rho_lower"] = f"{r1.numerator}/{r1.denominator}"
    assert "entropy bound" in _rejected(c)
    from magrod.proof.theorem import section_horseshoe_theorem

    c = copy.deepcopy(base)
    c["theorem"] = section_horseshoe_theorem(c["params"], c["level"], 80, 160, c["entropy"]["rho_lower"])
    assert "theorem" in _rejected(c)


def test_default_design_is_the_fig4a_certificates(cert):
    """The default settings (design "fig4a") still give every setting the Fig 4(a) certificate records (the settings
    added for Fig 4(b) -- passes, the N0 => N1 geometry, stop_frac -- default to what that run did), and the fig4b
    design changes only the named fields (seen to fail: with the default qs = 1.5 the first assertion fails)."""
    assert horseshoe_design.DESIGNS["fig4a"]().as_json().items() >= cert["settings"].items()
    a, b = horseshoe_design.HorseshoeSettings().as_json(), horseshoe_design.DESIGNS["fig4b"]().as_json()
    changed = {k for k in a.keys() | b.keys() if a.get(k) != b.get(k)}
    assert changed == {"m_back", "n_exc", "qu", "qs", "l0_frac", "l1_frac", "w_cap", "tol_thin", "passes",
                       "stop_frac", "tol", "thin_integrator", "integrator"}  # the last three: the Taylor-model flights
    c = horseshoe_design.DESIGNS["fig4c"]().as_json()
    assert c["period"] == 6 and "period" not in a and "period" not in b  # period 1 leaves the settings as they were



def test_designs_are_data_and_give_the_shipped_certificates_settings():
    """The prover's named designs are data files (magrod/proof/designs/NAME.json: settings and why): each proving
    design gives exactly the settings its shipped certificate records, and a name that is no design is refused
    naming `design`.  Seen to fail with fig4c.json's qs changed from 1.15 to 1.2."""
    import json

    from magrod.core.errors import ParameterError

    assert set(horseshoe_design.DESIGNS) == {"fig4a", "fig4b", "fig4c", "fig4d"}
    assert horseshoe_design.design_names(proving_only=False) == ["fig4a", "fig4b", "fig4c", "fig4d"]
    for name in ("fig4b", "fig4c", "fig4d"):
        cert = json.loads(resources.files("magrod.proof").joinpath("certificates", f"horseshoe_{name}.json")
                          .read_text())
        want = {k: v for k, v in cert["settings"].items()}
        assert horseshoe_design.DESIGNS[name]().as_json() == want, name
        doc = json.loads(resources.files("magrod.proof").joinpath("designs", f"{name}.json").read_text())
        assert doc["proving"] and len(doc["why"]) > 200, name
    with pytest.raises(ParameterError, match="design"):
        horseshoe_design.design("fig9z")

def test_tamper_deleted_link(any_cert):
    c = copy.deepcopy(any_cert)
    del c["links"][3]
    assert "links" in _rejected(c)


def test_tamper_set_not_symmetric(any_cert):
    c = copy.deepcopy(any_cert)
    A = c["sets"][-1]["A"]
    A[1][1] = str(Fraction(A[1][1]) * Fraction(1001, 1000))
    assert f"N{len(c['sets']) - 1} symmetric" in _rejected(c)


def test_tamper_N0_off_FixR(any_cert):
    c = copy.deepcopy(any_cert)
    c["sets"][0]["c"][1] = "1/10000000000000"
    assert "N0 symmetric" in _rejected(c)


def test_tamper_entropy(any_cert):
    """An entropy bound above the root is rejected; so is a theorem text claiming more."""
    c = copy.deepcopy(any_cert)
    c["entropy"]["rho_lower"] = "11/10"
    assert "entropy bound" in _rejected(c)
    c = copy.deepcopy(any_cert)
    c["theorem"] = c["theorem"].replace("h_top(P|Lambda) >= log rho", "h_top(P|Lambda) >= 2 log rho")
    assert "theorem" in _rejected(c)


def test_tamper_missing_piece(any_cert):
    c = copy.deepcopy(any_cert)
    fl = c["flights"][2]
    fl["pieces"][0]["piece"] = ["-1/2", "0", "1/2", "1"]  # only half of the square
    assert "N2 cover" in _rejected(c)


def test_tamper_disjointness(any_cert):
    """N1 moved onto N0 (its centre at x0's): N0 and N1 are no longer disjoint."""
    c = copy.deepcopy(any_cert)
    c["sets"][1]["c"] = list(c["sets"][0]["c"])
    assert "N0, N1 disjoint" in _rejected(c)


def test_mutated_field_rejected(any_cert):
    """A mutated generated field (control): rejected by the identity it breaks (one sign flipped in chart_rhs:
    f is no longer J grad Hbar), checked on its source before its digest."""
    assert "Hamiltonian form f = J grad Hbar failed" in _rejected(any_cert, module=fields.mutated_module(0))


def test_parallel_workers_replay_the_serial_checks(cert):
    """The sets' checks in child processes (workers=2, hs_kernel._hs_sources_parallel) are replayed in the serial order:
    a certificate whose N0 steps do not sum to t_a is rejected at the same check with the same check list as in
    one process, and a missing field of N0's piece is the same malformed-certificate error (both before any flight,
    so fast; the full equality of the 212 checks is test_certificate_verifies)."""
    c = copy.deepcopy(cert)
    c["flights"][0]["pieces"][0]["steps"]["thin"][1][0] = "1/2"
    r1, r2 = verify.verify(c, workers=1), verify.verify(c, workers=2)
    assert not r1.ok and "N0 piece 0 thin steps" in r1.reason
    assert (r2.ok, r2.reason, r2.checks) == (r1.ok, r1.reason, r1.checks)
    c = copy.deepcopy(cert)
    del c["flights"][0]["pieces"][0]["t_a"]
    msgs = []
    for w in (1, 2):
        with pytest.raises(verify.CertificateError) as e:
            verify.verify(c, workers=w)
        msgs.append(str(e.value))
    assert msgs[0] == msgs[1] and "KeyError" in msgs[0]


@pytest.mark.slow
def test_shifted_set_fails_covering(any_cert):
    """N2 shifted by 3 of its half-widths along its entry direction: the image of N1 lies at y_s ~ -3 in N2's
    coordinates and (a') fails at N1 => N2, seen after re-flying N0 and N1 (~30 s), at panels (a) and (b).  (A shift along the exit
    direction by 3 half-lengths is absorbed by N1 => N2, whose images of the exit edges reach y_u = -3 +- 5.75, and
    would fail only at N2 => N3.)"""
    reason = _rejected(shift_set_along_entry(any_cert, 2))
    assert "N1 => N2 piece 0 (a)" in reason, reason


@pytest.mark.slow
def test_certificate_verifies(any_cert):
    """The complete verifier re-flies every piece and accepts each stored certificate (~45 s of CPU for (a), issue
    27), in one process and in two with the same checks in the same order (bit-identical balls: Arb is
    deterministic)."""
    cert = any_cert
    res = verify.verify(cert, workers=2)
    assert res.ok, res.reason
    assert "h_top(P|Lambda) >= log rho" in res.theorem
    serial = verify.verify(cert, workers=1)
    assert serial.ok and serial.checks == res.checks and serial.theorem == res.theorem


@pytest.mark.slow
@pytest.mark.parametrize("lam, theta, design", [("27/200", 0.383, "fig4a"), ("63/400", 0.283, "fig4b"),
                                                ("7/40", 1.988829300900816, "fig4c")])
def test_mutated_field_control_fails_to_prove(lam, theta, design):
    """Control: with the sign of term 0 of the generated chart field flipped, the prover fails (at the first centre
    flight of the chain, or of the cycle at (c): no crossing where the float map of the true field has one; ~15 s)
    and issues nothing, at panels (a), (b) and (c) with their designs."""
    from magrod.proof.provers import horseshoe_design, section_horseshoe

    p, h = section_fixed_point.validate("17/10", "2/5", "3", "3", lam, "9/10")
    res = section_horseshoe.prove(p, h, theta, horseshoe_design.DESIGNS[design](), module=fields.mutated_module(0))
    assert not res.ok and res.certificate is None
    assert "flight not validated" in res.reason or "not established" in res.reason, res.reason


@pytest.mark.slow
@pytest.mark.parametrize("theta, design", [(0.383, "fig4a"), (0.283, "fig4b")])
def test_lambda_zero_control_proves_nothing(theta, design):
    """lambdabar = 0 (the integrable extensible rod), otherwise panel (a)'s / (b)'s rod, level and design: the prover
    proves nothing and issues no certificate.  Not a rigorous control of transversality (docs: on h = 9/10 at
    lambdabar = 0 there is no admissible point near the saddles, so the search fails before any set is built); it
    shows that the certificates are not an artefact of the chain's construction."""
    from magrod.proof.provers import horseshoe_design, section_horseshoe

    p, h = section_fixed_point.validate("17/10", "2/5", "3", "3", "0", "9/10")
    res = section_horseshoe.prove(p, h, theta, horseshoe_design.DESIGNS[design]())
    assert not res.ok and res.certificate is None and "no real root pbar_psi" in res.reason, res.reason


def test_lambda_zero_control_cycle():
    """lambdabar = 0 with Fig 4(c)'s rod, level and design: there is no symmetric period-6 orbit near theta =
    1.98883 (pbar_theta at the 3rd return has no sign change on the window), so the prover proves nothing and issues
    no certificate (~2 s; not a rigorous control, as at (a), (b))."""
    from magrod.proof.provers import horseshoe_design, section_horseshoe

    p, h = section_fixed_point.validate("17/10", "2/5", "3", "3", "0", "9/10")
    res = section_horseshoe.prove(p, h, 1.988829300900816, horseshoe_design.DESIGNS["fig4c"]())
    assert not res.ok and res.certificate is None
    assert "no sign change of pbar_theta at return 3" in res.reason, res.reason


def test_text_output_of_a_horseshoe_result():
    """`magrod prove --horseshoe` without --json prints the entropy bound (seen to fail: the Fig 4(b) run's text
    output raised KeyError 'crossings' after its certificate was written)."""
    from magrod.cli import prove as cli

    d = {"ok": True, "params": {}, "level": "9/10", "wall_time_s": 1.0, "checks": [{}] * 3, "reason": "",
         "certificate": "out/certificate.json", "entropy": {"rho_lower": "295848435455/274877906944",
                                                            "log_rho_lower": 0.0735}}
    text = cli.format_text(d)
    assert text.startswith("proved: 3 checks") and "log rho > 0.0735" in text


# --------------------------------------------------------------------------------------------------------------
# the lambdabar interval (horseshoe_widen.widen; statement 12): the sets move with lambdabar
# --------------------------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def interval_cert():
    return _load(INTERVAL)


def test_interval_certificate_is_the_point_one_moving(cert, interval_cert):
    """The interval certificate has the point certificate's sets (plus their motion v), chain and entropy, and
    claims the interval [lam - w, lam + w] of its settings; its end sets move along Fix(R)."""
    ic = interval_cert
    w = Fraction(ic["settings"]["lam_rad"])
    assert w > 0 and f"every lambdabar in [{Fraction(ic['params']['lam']) - w}" in ic["theorem"]
    assert [{k: v for k, v in d.items() if k != "v"} for d in ic["sets"]] == cert["sets"]
    assert ic["entropy"] == cert["entropy"] and ic["links"] == cert["links"]
    assert Fraction(ic["sets"][0]["v"][1]) == 0 == Fraction(ic["sets"][-1]["v"][1])
    assert {k: v for k, v in ic["settings"].items() if k != "lam_rad"} == cert["settings"]


def test_interval_tamper_end_set_leaves_FixR(interval_cert):
    """N0 moving off Fix(R) (v's pbar_theta != 0) is no longer symmetric for lambdabar != lam: rejected."""
    c = copy.deepcopy(interval_cert)
    c["sets"][0]["v"][1] = "1/1000"
    assert "N0 symmetric" in _rejected(c)


def test_interval_tamper_wider_theorem(interval_cert):
    """A theorem text claiming a wider interval than settings.lam_rad is rejected; a missing motion is malformed,
    and a point certificate with a motion too."""
    c = copy.deepcopy(interval_cert)
    w = Fraction(c["settings"]["lam_rad"])
    lam = Fraction(c["params"]["lam"])
    c["theorem"] = c["theorem"].replace(f"[{lam - w}, {lam + w}]", f"[{lam - 2 * w}, {lam + 2 * w}]")
    assert c["theorem"] != interval_cert["theorem"]
    assert "theorem" in _rejected(c)
    c = copy.deepcopy(interval_cert)
    del c["sets"][3]["v"]
    with pytest.raises(verify.CertificateError):
        verify.verify(c)
    c = copy.deepcopy(interval_cert)
    c["settings"]["lam_rad"] = "0/1"
    with pytest.raises(verify.CertificateError):
        verify.verify(c)


@pytest.mark.parametrize("fn", ["prover", "verifier"])
def test_swept_disjointness(fn):
    """Two unit squares 1/2 apart: disjoint while the second moves by s dv, |s| <= w, with |dv| w < 1/2, not when it
    can reach the first (prover's and verifier's copies; exact rationals)."""
    f = horseshoe_widen.disjoint_moving if fn == "prover" else hs_kernel._hs_separated_moving
    sq = [(Fraction(x), Fraction(y)) for x, y in ((1, 1), (1, -1), (-1, -1), (-1, 1))]
    other = [(x + Fraction(5, 2), y) for x, y in sq]
    assert f(sq, other, (0, 0), Fraction(1))
    assert f(sq, other, (Fraction(1), Fraction(0)), Fraction(2, 5))
    assert not f(sq, other, (Fraction(1), Fraction(0)), Fraction(3, 5))
    assert f(sq, other, (Fraction(0), Fraction(1)), Fraction(100))  # moving along the gap never closes it


@pytest.mark.slow
def test_interval_needs_the_motion(interval_cert):
    """Control: the same sets held fixed (v = 0) over the same interval are rejected -- the chain moves by ~87 per
    unit lambdabar per return, against entry widths down to 1.4e-13 (docs/nonintegrability.md, statement 12) -- and
    the moving sets over the wider interval w = 1e-10 are rejected at N12 => N13, where the 5-D box's derivative
    enclosures grow with its lambdabar extent (measured: (a') margin 0.54 at w = 1e-11, 0.27 at 2e-11, -5.2 at
    1e-10)."""
    c = copy.deepcopy(interval_cert)
    for d in c["sets"]:
        d["v"] = ["0", "0"]
    reason = _rejected(c)
    assert "(a)" in reason or "(b)" in reason, reason
    c = copy.deepcopy(interval_cert)
    w = Fraction(c["settings"]["lam_rad"])
    lam = Fraction(c["params"]["lam"])
    wide = Fraction(1, 10**10)
    c["settings"]["lam_rad"] = str(wide)
    c["theorem"] = c["theorem"].replace(f"[{lam - w}, {lam + w}]", f"[{lam - wide}, {lam + wide}]")
    reason = _rejected(c)
    assert "N12 => N13" in reason, reason


@pytest.mark.parametrize("name", [CERT, "homoclinic_target.json"])
def test_a_certificate_whose_precision_is_too_low_fails_a_check(name, tmp_path, capsys):
    """A lowered working precision (64 bits: in range, too low for the stored exact values) is a certificate that
    fails a check, exit 1 naming "working precision", not a malformed one (exit 2).  Seen to fail (exit 2,
    "malformed certificate (ValueError: not an exact ball ...)") before the verifier told the two apart.  Decided
    on reading the sets / the saddle (< 2 s each)."""
    from helpers import assert_rejected

    c = copy.deepcopy(_load(name))
    c["settings"]["prec"] = 64
    assert_rejected(c, tmp_path, capsys, "working precision")


def test_a_failing_check_says_that_it_failed(cert, tmp_path, capsys):
    """A raised entropy bound: the line names the check, says it failed and what it requires (it used to print the
    requirement as if it held: "rho_lower = ... is below the largest root")."""
    from helpers import verify_cli

    c = copy.deepcopy(cert)
    c["entropy"]["rho_lower"] = "19/10"
    code, _, err = verify_cli(c, tmp_path, capsys)
    assert code == 1 and len(err) == 1, (code, err)
    assert "entropy bound failed (the check requires: rho_lower = 1.9 is below" in err[0], err


def test_thin_integrator_is_a_recorded_setting_and_an_unknown_one_is_malformed(cert):
    """The centres' (and the sets') integrator is recorded only when it is not taylor.py (every shipped certificate's settings stay
    as they were), and a certificate naming an integrator the verifier does not have is malformed (exit 2), not
    re-flown with another (seen to fail: with the name unchecked, "bogus" verifies by taylor.py)."""
    st = horseshoe_design.HorseshoeSettings(thin_integrator="taylor_model")
    assert st.as_json()["thin_integrator"] == "taylor_model"
    assert "thin_integrator" not in horseshoe_design.HorseshoeSettings().as_json()
    for key in ("thin_integrator", "integrator"):
        c = copy.deepcopy(cert)
        c["settings"][key] = "bogus"
        with pytest.raises(verify.CertificateError, match="integrator"):
            verify.verify(c, workers=1)


def _tm_cert():
    """The Fig 4(a) horseshoe re-proved with the centres flown by the Taylor-model integrator
    (benchmarks/reprove_fig4a_taylor_model.py; not shipped: measured beside the shipped certificate)."""
    import pathlib

    path = pathlib.Path(__file__).resolve().parents[1] / "benchmarks" / "horseshoe_fig4a_taylor_model.json"
    return json.loads(path.read_text())


def test_taylor_model_certificate_states_the_shipped_theorem(cert):
    """The benchmark's re-proved certificate (centres by the Taylor-model integrator, sets by taylor.py) records
    its centres' integrator and tolerance and states the shipped theorem (same chain, same entropy bound); the
    shipped certificate flies centres and sets by the Taylor-model integrator, on 1695 centre and 1180 set steps
    where the taylor.py certificate it replaced took 3925 and 1695 (research/reprove_taylor_model_fig4a.json, the
    side-by-side verification that compared them)."""
    c = _tm_cert()
    assert c["settings"]["thin_integrator"] == "taylor_model" and c["settings"]["tol_thin"] == "1e-25"
    assert c["theorem"] == cert["theorem"] and c["links"] == cert["links"] and c["entropy"] == cert["entropy"]
    assert cert["settings"]["thin_integrator"] == cert["settings"]["integrator"] == "taylor_model"

    def steps(x, kind):
        return sum(len(ph) for f in x["flights"] for r in f["pieces"] for ph in r["steps"][kind])

    rec = json.loads((Path(__file__).parents[1] / "research" / "reprove_taylor_model_fig4a.json").read_text())
    assert rec["same_theorem"] and rec["steps"]["shipped"] == {"thin": 3925, "box": 1695}
    assert rec["steps"]["taylor_model"] == {"thin": steps(cert, "thin"), "box": steps(cert, "box")} == \
        {"thin": 1695, "box": 1180}
    assert steps(c, "thin") == 1695


@pytest.mark.slow
def test_taylor_model_certificate_verifies_and_needs_its_integrator(cert):
    """It verifies with the shipped theorem; replayed by taylor.py (its thin_integrator deleted) the same steps
    enclose the centres too loosely and it is rejected (the control)."""
    c = _tm_cert()
    res = verify.verify(c)
    assert res.ok and res.theorem == cert["theorem"], res.reason
    del c["settings"]["thin_integrator"]
    assert not verify.verify(c).ok


def test_mapped_sets_replay_the_serial_checks_on_dask(cert, tmp_path, capsys):
    """verify(mapper=...) runs the sets wherever the mapper does -- here a Dask cluster (schedule.dask_mapper) --
    and replays their records in the serial order: a certificate whose N1 steps do not sum
    to t_a is rejected at the same check, with the same check list, as by workers=1 (N0 re-flown first: the
    records of an accepted set are replayed too), here and through `magrod prove --verify --scheduler`.
    verify_many(client=...) gives verify_many(workers=1)'s results, in the given order."""
    import logging

    from distributed import Client, LocalCluster

    from magrod.proof import schedule

    c = copy.deepcopy(cert)
    c["flights"][1]["pieces"][0]["steps"]["thin"][1][0] = "1/2"
    r1 = verify.verify(c, workers=1)
    assert not r1.ok and "N1 piece 0 thin steps" in r1.reason
    fp = json.loads(resources.files("magrod.proof").joinpath("certificates", "fixed_point_fig4a.json").read_text())
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=True, host="127.0.0.1", dashboard_address=None,
                      scheduler_kwargs={"dashboard": False, "dashboard_address": ":0"},
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        rd = verify.verify(c, mapper=schedule.dask_mapper(client))
        c0 = copy.deepcopy(cert)
        c0["flights"][0]["pieces"][0]["steps"]["thin"][1][0] = "1/2"  # rejected before any flight
        many = schedule.verify_many([("tampered", c0), ("fixed point", fp)], client=client)
        code, out, err = verify_cli(c, tmp_path, capsys, "--scheduler", cluster.scheduler_address, "--json")
    assert code == 1 and json.loads(out)["reason"] == r1.reason and len(err) == 1, (code, err)
    assert (rd.ok, rd.reason, rd.checks) == (r1.ok, r1.reason, r1.checks)
    # a worker in this process would share the verifier's python-flint precision (process-wide): refused
    from magrod.core.errors import ParameterError

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None,
                      silence_logs=logging.ERROR) as cluster, Client(cluster) as client:
        with pytest.raises(ParameterError, match="scheduler"):
            schedule.dask_mapper(client)
    ref = schedule.verify_many([("tampered", c0), ("fixed point", fp)], workers=1)
    assert [(r.ok, r.reason, len(r.checks)) for r in many] == [(r.ok, r.reason, len(r.checks)) for r in ref]
    assert [r.ok for r in many] == [False, True]


def test_prove_workers_and_scheduler_apply_to_the_horseshoe_only(cert, tmp_path, capsys):
    """--workers and --scheduler size or place a horseshoe's set flights (the verifier's, and the horseshoe prover's
    pieces): given together, or to another prover, exit 2 naming the option, one line, nothing written."""
    from magrod.cli import main

    code, _, err = verify_cli(cert, tmp_path, capsys, "--workers", "2", "--scheduler", "127.0.0.1:1")
    assert code == 2 and len(err) == 1 and "workers" in err[0], err
    code = main(["prove", "--fixed-point", "0.383", "--level", "9/10", "--workers", "2", "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "workers" in err[0] and not (tmp_path / "o").exists(), err
    for extra in (["--workers", "0"], ["--workers", "2", "--scheduler", "127.0.0.1:1"]):
        code = main(["prove", "--horseshoe", "0.383", "--level", "9/10", *extra, "--out", str(tmp_path / "o")])
        err = capsys.readouterr().err.strip().splitlines()
        assert code == 2 and len(err) == 1 and "workers" in err[0] and not (tmp_path / "o").exists(), err
    code, _, err = verify_cli(cert, tmp_path, capsys, "--workers", "0")
    assert code == 2 and len(err) == 1 and "workers" in err[0], err


def _fig4d():
    cert = json.loads(resources.files("magrod.proof").joinpath("certificates", "horseshoe_fig4d.json").read_text())
    rec = json.loads((Path(__file__).parents[1] / "research" / "horseshoe_fig4d_verified.json").read_text())
    return cert, rec


def test_fig4d_certificate_is_the_one_the_verifier_accepted():
    """The shipped Fig 4(d) horseshoe is a well-formed certificate of Fig 4(d)'s rod and level, issued by `magrod
    prove --design fig4d`, with the theorem and the number of checks of the verification recorded in research/ (of
    the same certificate issued by research/fig4d_taylor_model.py: field for field equal but its provenance and wall
    time); a copy with N0's steps tampered is rejected at that check (before any flight).  Its full verification
    (~400 s of CPU) is the slow test below and a step of CI's own (.ci/run)."""
    cert, rec = _fig4d()
    assert cert["params"]["lam"] == "93/500" and cert["level"] == "9/10" and rec["ok"] and rec["n_checks"] == 1131
    assert cert["theorem"] == rec["theorem"] and "x^72 = x^71 + 1" in rec["theorem"]
    assert "--design fig4d" in cert["provenance"]["command"]
    assert horseshoe_design.DESIGNS["fig4d"]().as_json() == cert["settings"]
    c = copy.deepcopy(cert)
    c["flights"][0]["pieces"][0]["steps"]["thin"][1][0] = "1/2"
    assert "N0 piece 0 thin steps" in _rejected(c)


@pytest.mark.slow
def test_fig4d_certificate_verifies():
    """The independent verifier accepts it and prints the recorded theorem (~400 s of CPU)."""
    cert, rec = _fig4d()
    res = verify.verify(cert)
    assert res.ok and res.theorem == rec["theorem"] and len(res.checks) == rec["n_checks"], res.reason


def _piece_jobs(cert, sets=(0, 1)):
    """The prover's flight jobs for the one-piece sets `sets` of a certificate (its own t_a), and the settings."""
    from magrod.proof.provers import flights, horseshoe_design
    from magrod.proof.provers.section_horseshoe import _q, set_data

    st = horseshoe_design.DESIGNS["fig4a"]()
    jobs = []
    for i in sets:
        c, A = set_data(cert["sets"][i])
        jobs.append({"params": cert["params"], "h": cert["level"], "settings": flights.settings_json(st),
                     "c": [_q(v) for v in c], "A": [[_q(v) for v in row] for row in A], "pc": cert["sets"][i]["p_c"],
                     "branch": cert["sets"][i].get("branch", "0"), "t_a": cert["flights"][i]["pieces"][0]["t_a"],
                     "thin": None})
    return st, jobs


def test_the_provers_piece_flights_are_the_same_in_other_processes(cert):
    """The horseshoe prover's pieces flown by local_mapper (two fresh interpreters, results in the order of the jobs)
    give the same balls, bit for bit, as in this process through the same exact JSON form (flights.normalised): the
    certificate does not depend on --workers.  The steps are the shipped certificate's (Fig 4(a), N0 and N1, each
    worker one; their balls differ, so the order is checked too), and a flight error travels by name."""
    from magrod.proof import ball, section_return
    from magrod.proof.provers import flights

    st, jobs = _piece_jobs(cert)
    results = list(flights.local_mapper(2)(flights.piece_job, jobs))
    p = fields.ExactParams(**{k: Fraction(v) for k, v in cert["params"].items()})

    def flat(fl):
        balls = [*fl["Pc"], *fl["DP"][0], *fl["DP"][1], fl["ppsi_box"], fl["gdot_box"], fl["gdot_thin"]]
        return [ball.mid_rad(x) for x in balls]

    with ball.workprec(st.prec):  # a ball decodes at the working precision: the flights'
        got = [flights.decode(r["flight"]) for r in results]
        job = jobs[0]
        here = flights.normalised(section_return.piece_return(
            p.balls(), Fraction(cert["level"]), flights.prover_field(p, fields.gen, st), [Fraction(v) for v in job["c"]],
            [[Fraction(v) for v in row] for row in job["A"]], Fraction(job["pc"]), st.p_rad, Fraction(job["t_a"]),
            st.lead, t1=st.t1, order=st.order, tol=st.tol, tol_thin=st.tol_thin, newton=st.newton,
            module=fields.gen, integrator=section_return.integrator(st.integrator),
            thin_integrator=section_return.integrator(st.thin_integrator)))
        assert flat(here) == flat(got[0]) and here["steps"] == got[0]["steps"]
        assert flat(got[0]) != flat(got[1])
        for i, there in enumerate(got):
            shipped = cert["flights"][i]["pieces"][0]["steps"]
            assert [[ball.decimal(s) for s in ph] for ph in there["steps"]["box"]] == shipped["box"], i
    broken = dict(jobs[0], t_a="1/1024")  # far too early: the return is not reached by then
    r = flights.piece_job(broken)
    assert "err" in r and r["err"][0] in flights.ERRORS
    with pytest.raises(flights.ERRORS[r["err"][0]]):
        flights.raise_error(r["err"])


@pytest.mark.slow
def test_prover_gives_the_same_certificate_for_every_number_of_workers():
    """Fig 4(a)'s horseshoe proved with its pieces flown in this process and in two others: the same certificate but
    for its wall time (~60 s each), whose theorem is the shipped one's."""
    from magrod.proof.provers import horseshoe_design, section_fixed_point, section_horseshoe

    old = _load(CERT)
    p, h = section_fixed_point.validate(*(old["params"][k] for k in ("m", "mu", "gamma", "delta", "lam")), old["level"])
    got = []
    for w in (1, 2):
        r = section_horseshoe.prove(p, h, Fraction(old["design"]["x0_theta"]), horseshoe_design.DESIGNS["fig4a"](),
                                    workers=w)
        assert r.ok, r.reason
        got.append({k: v for k, v in r.certificate.items() if k != "wall_time_s"})
    assert got[0] == got[1] and got[0]["theorem"] == old["theorem"]


def test_the_widening_flights_are_the_same_in_other_processes(interval_cert):
    """The lambdabar-interval flights of horseshoe_widen (flights.widen_flight: a piece moving with lambdabar,
    lambdabar the fifth state) flown by local_mapper give the same balls, bit for bit, as here through flights.normalised, and the shipped
    interval certificate's own steps (Fig 4(a), N0 and N1 over 27/200 +- 2e-11)."""
    from magrod.proof import ball
    from magrod.proof.provers import flights
    from magrod.proof.provers.section_horseshoe import _q, grid_pieces, piece_geometry, set_data

    c = interval_cert
    jobs = []
    for i in (0, 1):
        sd, r = c["sets"][i], c["flights"][i]["pieces"][0]
        cX, AX = piece_geometry(*set_data(sd), grid_pieces(1, 1)[0])
        jobs.append({"params": c["params"], "h": c["level"], "settings": c["settings"],
                     "lam_rad": c["settings"]["lam_rad"], "c": [_q(x) for x in cX],
                     "A": [[_q(x) for x in row] for row in AX], "pc": r["p_c"], "t_a": r["t_a"],
                     "thin_steps": r["steps"]["thin"], "branch": sd.get("branch", "0"), "v": sd["v"]})
    results = list(flights.local_mapper(2)(flights.widen_job, jobs))

    def flat(fl):
        return [ball.mid_rad(x) for x in [*fl["Pc"], *fl["DP"][0], *fl["DP"][1], *fl["dPds"], fl["ppsi_box"]]]

    with ball.workprec(int(c["settings"]["prec"])):  # a ball decodes at the working precision: the flights'
        got = [flights.decode(r["flight"]) for r in results]
        here = flights.normalised(flights.widen_flight(jobs[0]))
        assert flat(here) == flat(got[0]) and here["steps"] == got[0]["steps"] and flat(got[0]) != flat(got[1])
        for i, there in enumerate(got):
            assert [[ball.decimal(s) for s in ph] for ph in there["steps"]["box"]] == \
                c["flights"][i]["pieces"][0]["steps"]["box"], i
