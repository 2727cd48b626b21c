"""Each shipped certificate records what produced it ("provenance": the command and the design script), and the
verifier ignores it for the theorem.  The command's parameters must be the certificate's own exact values (seen to
fail: with --lam 27/200 changed to 27/201 in horseshoe_fig4a.json's provenance the second test fails)."""
from __future__ import annotations

import copy
import json
import shlex
from fractions import Fraction
from importlib import resources
from pathlib import Path

import pytest

from magrod.cli import build_parser
from magrod.cli import prove as prove_cli
from magrod.proof import verify

CERTS = resources.files("magrod.proof").joinpath("certificates")
SHIPPED = sorted(p.name for p in CERTS.iterdir() if p.name.endswith(".json"))
ROOT = Path(__file__).parents[1]


def _load(name):
    return json.loads(CERTS.joinpath(name).read_text())


def _options(command: str) -> dict:
    words = shlex.split(command)
    assert words[:2] == ["magrod", "prove"], command
    return {words[i][2:]: words[i + 1] for i in range(2, len(words), 2)}


@pytest.mark.parametrize("name", SHIPPED)
def test_each_shipped_certificate_names_what_produced_it(name):
    prov = _load(name)["provenance"]
    assert isinstance(prov, dict) and all(isinstance(v, str) for v in prov.values())
    assert prov["command"].startswith("magrod prove ") and prov["recorded"]
    if "design_script" in prov:
        script = prov["design_script"]
        assert script.startswith("research/") and (ROOT / script).is_file(), script
        assert f"`{Path(script).name}`" in (ROOT / "research" / "README.md").read_text()


@pytest.mark.parametrize("name", SHIPPED)
def test_the_recorded_command_is_the_certificates_own(name):
    c = _load(name)
    opt = _options(c["provenance"]["command"])
    if "widen" in opt:  # the point certificate it widened: the same rod, level and sets
        base = _load(opt["widen"])
        assert base["params"] == c["params"] and base["level"] == c["level"]
    else:
        assert {k: Fraction(opt[k]) for k in c["params"]} == {k: Fraction(v) for k, v in c["params"].items()}
    if "level" in opt:
        assert Fraction(opt["level"]) == Fraction(c["level"])
    assert Fraction(opt.get("lam-rad", "0")) == Fraction(c["settings"].get("lam_rad", "0"))
    if "targets" in opt:
        assert opt["targets"].split(",") == c["settings"]["targets"]


def test_the_cli_writes_the_options_that_decide_the_content():
    args = build_parser().parse_args(["prove", "--horseshoe", "0.383", "--level", "0.9", "--m", "1.7", "--mu", "0.4",
                                      "--gamma", "3", "--delta", "3", "--lam", "0.135", "--out", "/some/dir"])
    prov = prove_cli._provenance(args)
    opt = _options(prov["command"])
    assert opt["horseshoe"] == "0.383" and opt["lam"] == "0.135" and opt["design"] == "fig4a"
    assert "out" not in opt and "/some" not in prov["command"] and "targets" not in opt
    widen = build_parser().parse_args(["prove", "--widen", "/a/b/horseshoe_fig4a.json", "--lam-rad", "1/50000000000",
                                       "--out", "x"])
    assert _options(prove_cli._provenance(widen)["command"]) == {"widen": "horseshoe_fig4a.json",
                                                                 "lam-rad": "1/50000000000"}
    wide = build_parser().parse_args(["prove", "--widen", "horseshoe_fig4a.json", "--lam-rad", "1/134217728",
                                      "--lam-order", "2", "--lam-nodes", "32", "--out", "x"])
    assert _options(prove_cli._provenance(wide)["command"]) == {"widen": "horseshoe_fig4a.json",
                                                                "lam-rad": "1/134217728", "lam-order": "2",
                                                                "lam-nodes": "32"}


def test_the_verifier_ignores_provenance_but_not_its_form():
    c = copy.deepcopy(_load("fixed_point_fig4a.json"))
    c["field_digest"] = "0" * 64  # rejected at the digest (cheap), after the same checks with or without provenance
    with_prov = verify.verify(c)
    del c["provenance"]
    without = verify.verify(c)
    assert not with_prov.ok and with_prov.reason == without.reason
    assert [x["name"] for x in with_prov.checks] == [x["name"] for x in without.checks]
    c["provenance"] = ["not", "an", "object"]
    with pytest.raises(verify.CertificateError, match="provenance"):
        verify.verify(c)


def test_the_reconstruction_script_wrote_the_shipped_provenance_and_changes_nothing_else(tmp_path):
    import sys

    sys.path.insert(0, str(ROOT / "research"))
    try:
        import provenance as P
    finally:
        sys.path.remove(str(ROOT / "research"))
    for name in SHIPPED:
        c = _load(name)
        prov = c.pop("provenance")
        if prov["recorded"] == P.RECORDED:
            assert P.provenance(name, c) == prov, name
    c = _load("horseshoe_fig5b.json")
    del c["provenance"]
    path = tmp_path / "horseshoe_fig5b.json"
    path.write_text(json.dumps(c, indent=1))
    assert P.add(path) and not P.add(path)
    again = json.loads(path.read_text())
    assert again.pop("provenance") == P.provenance(path.name, c) and again == c
