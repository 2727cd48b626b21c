"""The landscape of sec. 1 (issue 26): every line against its citation, the anisotropic scan, the command, and the
examples of the model-family modules."""
from __future__ import annotations

import doctest
import json
from fractions import Fraction

import pytest

from magrod import cli


def test_every_tested_line_agrees_with_its_citation_and_a_flipped_claim_disagrees():
    from magrod.integrability.landscape import CLAIMS, landscape, line

    land = landscape(4, quick=True, scan=False, t_max=200.0)
    got = {ln["model"]: ln["agreement"] for ln in land.lines}
    assert got == {c[0]: ("not tested" if c[0] == "heavy" else "agrees") for c in CLAIMS} and land.success
    integrable = {ln["model"] for ln in land.lines if ln["verdict"] == "integrable (proved)"}
    assert integrable == {"kirchhoff", "extensible", "magnetic"}
    # the mutation: cite the anisotropic rod as integrable, and the line must disagree
    assert line("anisotropic", True, "x", "x", degree=4, t_max=200.0, seed=20)["agreement"] == "disagrees"


def test_scan_finds_lagrange_kovalevskaya_goryachev_chaplygin_and_nothing_else():
    from magrod.integrability.landscape import QUICK_GRID, anisotropic_scan, explain

    rows, ncls = anisotropic_scan(QUICK_GRID, 4)
    assert ncls == 37
    kinds = {(r["B1"], r["B2"], r["C"], r["level"]): r["explanation"].split(" (")[0] for r in rows}
    assert all(all(r["verified"]) for r in rows) and "UNEXPLAINED" not in kinds.values()
    assert kinds[("1", "2", "2", "generic")] == kinds[("2", "1", "2", "generic")] == "Kovalevskaya"
    assert kinds[("1", "4", "4", "C2=0")] == kinds[("4", "1", "4", "C2=0")] == "Goryachev-Chaplygin"
    assert ("1", "4", "4", "generic") not in kinds  # GC needs the special level
    assert {k for k, v in kinds.items() if v == "Lagrange"} == {k for k in kinds if k[0] == k[1]}
    # explain() is not a catch-all: a generic ratio has no name
    assert explain(Fraction(1), Fraction(2), Fraction(3), "generic") == ""


@pytest.mark.parametrize("argv,param", [
    (["landscape", "--degree", "0"], "degree"),
    (["landscape", "--t-max", "nan"], "t_max"),
    (["check", "--model", "kirchhoff", "--integrals", "--level", "C9=0"], "level"),
    (["check", "--model", "kirchhoff", "--integrals", "--model-params", "B=abc"], "model-params"),
    (["check", "--model", "kirchhoff", "--integrals", "--model-params", "B=-1"], "B"),
    (["check", "--model", "kirchhoff", "--level", "C2=x"], "level"),
    (["check", "--model", "nope"], "model"),
    (["check", "--level", "C2=0"], "level"),
    (["models", "--model", "nope"], "model"),
    (["chaosmap", "--model", "kirchhoff", "--out", "OUT"], "x"),
    (["chaosmap", "--model", "kirchhoff", "--x", "B:1:2:2", "--y", "C:1:2:0", "--out", "OUT"], "y"),
    (["poincare", "--model", "kirchhoff", "--model-params", "Q=1"], "model-params"),
])
def test_bad_input_of_the_model_commands(argv, param, capsys, tmp_path):
    out = tmp_path / "out"
    rc = cli.main([str(out) if a == "OUT" else a for a in argv] + ["--json"])
    cap = capsys.readouterr()
    assert rc == 2, cap
    obj = json.loads(cap.out)
    assert obj["ok"] is False and param in obj["parameter"]
    lines = [ln for ln in cap.err.splitlines() if ln.strip()]
    assert len(lines) == 1 and param in lines[0] and "Traceback" not in cap.err
    assert not out.exists() or not any(out.iterdir())  # nothing written


@pytest.mark.parametrize("module", ["magrod.integrability.model_search", "magrod.integrability.landscape",
                                    "magrod.separatrix.model_splitting"])
def test_module_examples_run(module):
    import importlib

    mod = importlib.import_module(module)
    res = doctest.testmod(mod, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    assert res.attempted > 0 and res.failed == 0
