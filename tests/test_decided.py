"""Integrability decided: Kovalevskaya exponents and the Painleve test (derive/painleve.py), Kovacic's algorithm
and Kimura's theorem (derive/kovacic.py), Morales-Ramis along the pendulums (derive/morales_ramis.py).  Each
control is paired with a mutation that changes its verdict (seen to fail).  The full theorem for the symmetric
anisotropic rod and the registry's stored results are behind `slow`."""
from __future__ import annotations

import json
from pathlib import Path

import pytest
import sympy as sp

from magrod.derive import kovacic, models, painleve
from magrod.derive import morales_ramis as MR
from magrod.derive.kovacic import galois, kimura, reduce_form, riemann_reduced, x

R = sp.Rational
ROOT = Path(__file__).resolve().parent.parent


# ----------------------------------------------------------------------------------------------------------------
# Kovacic's algorithm on equations with known Galois groups (textbook closed forms)
# ----------------------------------------------------------------------------------------------------------------
@pytest.mark.parametrize("name, r, case, abelian", [
    ("Airy y'' = x y: no Liouvillian solution", x, 4, False),
    ("Bessel order 1/2: sin x/sqrt x, cos x/sqrt x", reduce_form(1 / x, 1 - R(1, 4) / x**2), 1, True),
    ("Bessel order 3/2: two exponential solutions", reduce_form(1 / x, 1 - R(9, 4) / x**2), 1, True),
    ("Bessel order 0: SL(2)", reduce_form(1 / x, sp.Integer(1)), 4, False),
    ("Bessel order 1: SL(2)", reduce_form(1 / x, 1 - 1 / x**2), 4, False),
    ("Weber a = -1/2: exp(-x^2/4) and a non-elementary second solution", x**2 / 4 - R(1, 2), 1, False),
    ("Weber a = 0: SL(2)", x**2 / 4, 4, False),
    ("hypergeometric (1/2, 1/2, sqrt 2): dihedral", riemann_reduced(R(1, 2), R(1, 2), sp.sqrt(2)), 2, True),
    ("hypergeometric (1/2, 1/3, 1/3): tetrahedral", riemann_reduced(R(1, 2), R(1, 3), R(1, 3)), 3, True),
    ("hypergeometric (1/3, 1/4, 1/5): SL(2)", riemann_reduced(R(1, 3), R(1, 4), R(1, 5)), 4, False),
])
def test_kovacic_on_equations_with_known_groups(name, r, case, abelian):
    g = galois(r)
    assert (g.case, g.abelian_identity_component) == (case, abelian), (name, g.as_dict())


def test_kovacic_solution_really_solves_and_mutation_changes_the_group():
    """Case 1's answer is re-checked as a solution of the equation; Bessel of order 1/2 mutated to order 1/3
    loses its Liouvillian solutions (seen to fail)."""
    r = reduce_form(1 / x, 1 - R(1, 4) / x**2)
    for omega, P in kovacic.case1(r):
        eta = P * sp.exp(sp.integrate(omega, x))
        assert sp.simplify(sp.diff(eta, x, 2) - r * eta) == 0
    assert galois(reduce_form(1 / x, 1 - R(1, 9) / x**2)).case == 4


def test_kimura_agrees_with_kovacic_on_the_hypergeometric_table():
    """Kimura's theorem (solvable G0) and Kovacic's algorithm (case 1-3 vs 4) agree on Riemann P-equations from
    every kind of row: dihedral, reducible, not solvable (finite rows: the parametrised cases above)."""
    for d in [(R(1, 2), R(1, 2), R(2, 7)), (R(1, 2), sp.sqrt(2), sp.sqrt(2) + R(1, 2)),
              (sp.sqrt(2), sp.sqrt(3), R(1, 3))]:
        solvable = kimura(*d)["solvable"]
        assert solvable == (galois(riemann_reduced(*d)).case != 4), d


@pytest.mark.slow
@pytest.mark.parametrize("d, group", [((R(1, 2), R(1, 3), R(1, 4)), "octahedral"),
                                      ((R(2, 3), R(1, 4), R(1, 4)), "octahedral"),
                                      ((R(1, 2), R(1, 3), R(1, 5)), "icosahedral"),
                                      ((R(1, 2), R(1, 3), R(1, 7)), None)])
def test_kovacic_case3_on_kimuras_finite_rows(d, group):
    """Kimura's octahedral and icosahedral rows: Kovacic's case 3 finds the finite group Kimura names (n = 6 and
    n = 12 searches, ~10 s each); (1/2, 1/3, 1/7) is in no row and Kovacic finds no Liouvillian solution."""
    g = galois(riemann_reduced(*d))
    k = kimura(*d)
    if group is None:
        assert g.case == 4 and not k["solvable"]
    else:
        assert g.case == 3 and g.group.startswith(group) and k["group"] == group


@pytest.mark.slow
def test_kirchhoff_nve_is_abelian_and_one_stiffness_changed_is_not():
    """Control: the isotropic Kirchhoff rod (integrable) has G0 abelian along its pendulum (Kovacic case 1, an
    algebraic exponential solution); the same pipeline with the stiffnesses changed to B1 = 1, B2 = C = 3 gives
    SL(2) along the second pendulum at h = 1 (seen to fail: the verdict follows the stiffnesses)."""
    m = models.get("kirchhoff")
    _, _, vals = painleve.model_field(m)
    pl = MR.invariant_planes(m, vals)[0]
    p, q, _ = MR.nve(m, vals, pl, 0)
    g = MR.galois_of(p, q)
    assert g.case == 1 and g.abelian_identity_component
    a = models.get("anisotropic")
    _, _, v3 = painleve.model_field(a, {"B1": 1, "B2": 3, "C": 3})
    p3, q3, _ = MR.nve(a, v3, MR.invariant_planes(a, v3)[1], 1)
    assert MR.galois_of(p3, q3).case == 4


# ----------------------------------------------------------------------------------------------------------------
# Kovalevskaya exponents, the Painleve test, Yoshida
# ----------------------------------------------------------------------------------------------------------------
def _aniso(b1, b2, c):
    m = models.get("anisotropic")
    return painleve.model_field(m, {"B1": b1, "B2": b2, "C": c})


def _verdicts(X, f, ars=True):
    res = painleve.analyse_field(f, X, ars=ars)
    return res, [b.verdict for ch in res["choices"] for b in ch["balances"]]


def test_kirchhoff_rod_has_integer_exponents_and_passes():
    X, f, _ = painleve.model_field(models.get("kirchhoff"))
    res, verdicts = _verdicts(X, f)
    assert res["choices"][0]["homogeneous"] and res["choices"][0]["weights"] == (1, 1, 1, 2, 2, 2)
    assert verdicts and set(verdicts) == {"all integer, compatible"}
    b = res["choices"][0]["balances"][0]
    assert sorted(r for r, _ in b.exponents) == [-1, 0, 1, 2, 3, 4]  # the Lagrange-type family: 0 from S^1


def test_kovalevskaya_rod_passes_and_the_123_rod_fails():
    X, f, _ = _aniso(1, 2, 2)  # B2 = C = 2 B1
    _, kov = _verdicts(X, f)
    assert set(kov) == {"all integer, compatible"}
    X, f, _ = _aniso(1, 2, 3)
    res, bad = _verdicts(X, f, ars=False)
    assert "irrational or complex" in bad
    kinds = [b.kinds for ch in res["choices"] for b in ch["balances"]]
    assert all(isinstance(r, sp.Basic) for ch in res["choices"] for b in ch["balances"] for r, _ in b.exponents)
    assert any("irrational or complex" in k for k in kinds)


def test_goryachev_chaplygin_exponents_are_fractional():
    """B2 = C = 4 B1: a balance with exponents 3/2 and -1/2 (algebraic branching: the weak Painleve property)."""
    X, f, _ = _aniso(1, 4, 4)
    res, verdicts = _verdicts(X, f, ars=False)
    assert "fractional (algebraic branching)" in verdicts
    exps = {r for ch in res["choices"] for b in ch["balances"] for r, _ in b.exponents}
    assert {R(3, 2), R(-1, 2)} <= exps


def test_one_coefficient_mutation_changes_the_verdict():
    """The Kovalevskaya field with the coefficient of one monomial doubled no longer passes."""
    X, f, _ = _aniso(1, 2, 2)
    m1, m2, m3, n1, n2, n3 = X
    g = list(f)
    g[0] = sp.expand(g[0] + n2)  # m1' = n2 -> 2 n2
    _, verdicts = _verdicts(X, g)
    assert set(verdicts) != {"all integer, compatible"}


def test_ars_detects_a_logarithmic_resonance_from_lower_order_terms():
    """The curved rod's dominant part is the Kirchhoff field (integer exponents); its curvature terms break the
    compatibility at a resonance.  With k1 = 0 (pure pre-twist: integrable) the condition is met."""
    m = models.get("curved")
    X, f, _ = painleve.model_field(m)
    _, verdicts = _verdicts(X, f)
    assert "logarithmic resonance" in verdicts
    X, f, _ = painleve.model_field(m, {"k1": 0})
    _, verdicts = _verdicts(X, f)
    assert set(verdicts) == {"all integer, compatible"}


def test_yoshida_identity_and_bound():
    """K(c)^T grad I(c) = M grad I(c) for H and the Casimirs at every balance (a mutated H breaks it), and the
    (1, 2, 3) rod's bound equals the rank of H and the Casimirs: Yoshida's obstruction, labelled proved."""
    res = painleve.model_analysis(models.get("anisotropic"), {"B1": 1, "B2": 2, "C": 3}, ars=False)
    y = res["yoshida"]
    assert y["applies"] and y["obstruction"] and y["label"] == "proved" and y["bound_polynomial"] == 3
    X, f, vals = _aniso(1, 2, 3)
    w = (1, 1, 1, 2, 2, 2)
    f0 = painleve.dominant_field(f, X, w)
    b = painleve.balances(f0, X, w)[1]
    c = dict(zip(X, b.point.values()))
    H = models.get("anisotropic").H.subs(vals)
    M, resid, _ = painleve.yoshida_identity(H, f0, X, w, c)
    assert M == 2 and all(painleve._canon(v) == 0 for v in resid)
    _, resid, _ = painleve.yoshida_identity(H + X[1] ** 2 / 3, f0, X, w, c)  # not an integral
    assert any(painleve._canon(v) != 0 for v in resid)
    ok = painleve.model_analysis(models.get("anisotropic"), {"B1": 1, "B2": 2, "C": 2}, ars=False)["yoshida"]
    assert ok["obstruction"] is False and ok["label"] == "no conclusion"


def test_nonhomogeneous_model_gets_no_yoshida_theorem():
    res = painleve.model_analysis(models.get("extensible"), ars=False)
    assert res["yoshida"]["applies"] is False and res["yoshida"]["label"] == "not applicable"


# ----------------------------------------------------------------------------------------------------------------
# Morales-Ramis along the pendulums
# ----------------------------------------------------------------------------------------------------------------
def test_pendulum_nves_of_the_symmetric_rod_are_riemann_equations():
    """Both NVEs derived from the field; at h = 1 their exponent differences are (1/2, 1/sqrt r, (3r-4)/(2r)) and
    (1/2, sqrt r, sqrt(8r-7)/2) (derived by hand independently; squared, to be sign-free)."""
    model, vals = MR._symmetric_rod()
    nves = MR.pendulum_nves(model, vals)
    assert len(nves) == 2
    r = MR.r
    want = [{R(1, 4), 1 / r, sp.factor((3 * r - 4) ** 2 / (4 * r**2))}, {R(1, 4), r, sp.factor((8 * r - 7) / 4)}]
    for (_, p, q, _), w in zip(nves, want):
        rd = MR.riemann_data(sp.cancel(p.subs(MR.h, 1)), sp.cancel(q.subs(MR.h, 1)))
        got = {sp.factor(v**2) for v in rd.values()}
        assert all(any(sp.simplify(g - ww) == 0 for g in got) for ww in w)


def test_kimura_and_kovacic_decide_the_same_along_a_pendulum():
    """r = 3: Gamma2 at h = 1 is not solvable by Kimura and Kovacic finds no Liouvillian solution; r = 2
    (Kovalevskaya): dihedral by both.  The two methods are independent."""
    model, vals = MR._symmetric_rod()
    _, p, q, _ = MR.pendulum_nves(model, vals)[1]
    for rv, solvable in ((3, False), (2, True)):
        pp, qq = sp.cancel(p.subs({MR.h: 1, MR.r: rv})), sp.cancel(q.subs({MR.h: 1, MR.r: rv}))
        d = list(MR.riemann_data(pp, qq).values())
        assert kimura(*d)["solvable"] is solvable
        assert (MR.galois_of(pp, qq).case != 4) is solvable


@pytest.mark.slow
def test_symmetric_rod_theorem_every_step_holds():
    t = MR.symmetric_rod_theorem()
    assert t["status"] == "proved", [s for s in t["steps"] if not s["ok"]]
    assert t["exceptional_set"] == ["1", "2", "4"]


@pytest.mark.slow
def test_stored_decided_results_are_fresh():
    from magrod.derive import decided

    stored = json.loads((ROOT / "generated" / "decided" / "registry.json").read_text())
    assert stored == json.loads(json.dumps(decided.registry_results(), sort_keys=True, default=str))


# ----------------------------------------------------------------------------------------------------------------
# Kovalevskaya 1889 on the anisotropic rod, with the stiffnesses as symbols
# ----------------------------------------------------------------------------------------------------------------
def test_ratio_conditions_find_lagrange_and_kovalevskaya():
    """The axis balances' exponents rho^2 - rho - 2D with D derived symbolically; the integrality conditions solved
    completely (three lines), cross-checked for k, k' <= 1; on the lines, Kovalevskaya 1:2:2 and its mirror pass
    and 1:7:2 (integer exponents everywhere) fails by a logarithmic resonance.  Goryachev-Chaplygin's d1 balance
    has D = 3/8 (exponents 3/2, -1/2): mutating 4:4 to 4:5 changes it."""
    from magrod.derive import kovalevskaya1889 as K

    res = K.conditions(k_max=1)
    assert res["forms_checked"] and res["cross_check"]["all_on_the_lines"]
    by = {c["name"]: c for c in res["cases"]}
    assert by["Kovalevskaya (B2 = C = 2 B1)"]["verdict"].startswith("Painleve test passed")
    assert by["Kovalevskaya mirror (B1 = C = 2 B2)"]["verdict"].startswith("Painleve test passed")
    seven = by["integer exponents, T_8 = 6^2"]
    assert seven["ratios"] == "B1:B2:C = 1:7:2" and "logarithmic resonance" in seven["balance_verdicts"]
    D1 = (1 - 1 / K.x) * (1 - 2 / K.y)
    assert D1.subs({K.x: 4, K.y: 4}) == R(3, 8) and res["goryachev_chaplygin"]["D_d1"] == "3/8"
    assert D1.subs({K.x: 4, K.y: 5}) != R(3, 8)


# ----------------------------------------------------------------------------------------------------------------
# what the runtime reads (generated/decided/registry.json) and shows
# ----------------------------------------------------------------------------------------------------------------
def test_stored_results_reach_the_report_and_the_landscape():
    from magrod.integrability import decided

    t = decided.theorem()
    assert t["status"] == "proved" and t["exceptional_set"] == ["1", "2", "4"]
    assert all(s["ok"] for s in t["steps"])
    # the scope on the full Poisson system is stated, and checked: no particular solution on a leaf m.n != 0
    assert "F|L is functionally dependent on H|L" in t["theorem"] and "generic leaves" in t["not_proved"]
    assert [s["step"] for s in t["steps"]][-1] == "leaf"
    st = decided.stored()["models"]
    assert st["anisotropic"]["strongest"]["label"] == "proved"
    assert st["kirchhoff"]["morales_ramis"]["label"] == "no conclusion"  # control: abelian along both pendulums
    assert st["kirchhoff"]["painleve"]["verdict"].startswith("Painleve test passed")
    import magrod as mr

    rep = mr.integrability_report(model="anisotropic")
    assert rep.row("morales_ramis")["status"] == "proved"
    assert "exponents" in "\n".join(rep.row("kovalevskaya_exponents")["details"]["balances"])
    assert "[proved] Morales-Ramis" in rep.text()
    ev, strongest = decided.landscape_evidence("anisotropic")
    assert "proved" in strongest and any("r > 0 outside {1, 2, 4}" in e["detail"] for e in ev)
    import tempfile

    from magrod.figures import report

    with tempfile.TemporaryDirectory() as tmp:  # the REPORT.md row, from a landscape sidecar with no lines
        Path(tmp, "landscape.json").write_text(json.dumps({"lines": [], "scan": [], "scan_grid": [],
                                                           "scan_classes": 0, "degree": 2}))
        rows = report._landscape(Path(tmp), True)
    mr_row = [r for r in rows if r["label"] == "sec:intro [Mielke88] (Morales-Ramis)"]
    assert len(mr_row) == 1 and "r not in {1, 2, 4}" in mr_row[0]["computed"]
    assert mr_row[0]["verdict"].startswith("proved (symbolic") and report.verdict_word(mr_row[0]["verdict"]) == "proved"


def test_check_fast_applies_only_with_a_model():
    import subprocess
    import sys

    p = subprocess.run([sys.executable, "-m", "magrod.cli", "check", "--fast"], capture_output=True, text=True)
    assert p.returncode == 2 and "fast" in p.stderr


# ----------------------------------------------------------------------------------------------------------------
# Morales-Ramis on the 9-D models and the curved rod: particular solutions found, NVEs derived, or why not
# ----------------------------------------------------------------------------------------------------------------
def test_paper_rod_planar_solution_and_its_reduced_nve():
    """The paper's rod has the planar solutions perpendicular to the field (m2 = m3 = n1 = e32 = e33 = 0, e31 = 1:
    the rod bends in the plane normal to the field, the Lorentz force stays in that plane); the leaf e3 = 0 is
    skipped (|e3|^2 = 0).  The NVE cut down by e3.n (Casimir), m3 (integral) and the quotient by X_m3 is, by hand,
    y'' = ((1 + gamma m^2 n3) n3 - m1^2) y for y = de33; the pipeline derives the same 2 x 2 block.  At gamma != 0
    (m1, n3) lie on a conic, and the stored row says that no rational second-order equation was formed."""
    m = models.get("magnetic-extensible")
    _, _, vals = painleve.model_field(m)
    planes = MR.invariant_planes(m, vals)
    normals = [[str(m.state[i]) for i in pl[0]] for pl in planes]
    assert normals == [["m2", "m3", "n1", "e32", "e33"], ["m1", "m3", "n2", "e31", "e33"]]
    M, names, fix, _ = MR.normal_block(m, vals, planes[0])
    m1, n3 = m.state[0], m.state[5]
    par = {str(k): v for k, v in vals.items()}
    gm2 = par["gamma"] * par["m"] ** 2
    want = (1 + gm2 * n3) * n3 - m1**2
    assert [str(v) for v in names] == ["m2", "e33"] and M[0, 0] == 0 and M[1, 1] == 0 and M[1, 0] == 1
    assert sp.expand(M[0, 1] - want) == 0
    assert sp.expand(M[0, 1] - (1 - gm2 * n3) * n3 + m1**2) != 0  # a mutated coefficient is told apart
    # at gamma = 0 (K = J) n3 is a polynomial in m1 on the levels (a combination of H and C1, from a Groebner
    # basis) and the NVE becomes rational in z = m1, with n2^2 a quartic
    _, _, v0 = painleve.model_field(m, {"gamma": 0})
    res = MR.nve_reason(m, v0, MR.invariant_planes(m, v0)[0], MR.h, sp.Symbol("c1"))
    assert not isinstance(res, str) and res[2]["z"] == "m1" and res[2]["relations"]["n3"].startswith("n3 = ")


def test_curved_rod_has_a_pendulum_only_without_pretwist():
    """Intrinsic curvature k1 with pre-twist k3 != 0 leaves no invariant coordinate subspace; at k3 = 0 the planar
    bending about d1 is one, and its NVE is rational."""
    m = models.get("curved")
    _, _, vals = painleve.model_field(m)
    assert MR.invariant_planes(m, vals) == []
    _, _, vals0 = painleve.model_field(m, {"k3": 0})
    planes = MR.invariant_planes(m, vals0)
    assert len(planes) == 1 and [str(m.state[i]) for i in planes[0][0]] == ["m2", "m3", "n1"]
    assert not isinstance(MR.nve_reason(m, vals0, planes[0], 0), str)


def test_stored_rows_say_why_morales_ramis_does_not_decide():
    from magrod.integrability import decided

    st = decided.stored()["models"]
    assert "no invariant coordinate subspace" in st["curved"]["morales_ramis"]["verdict"]
    me = st["magnetic-extensible"]["morales_ramis"]
    assert me["label"] == "no conclusion" and len(me["pendulums"]) == 2
    assert all(r["nve"].startswith("not reduced") and r["frozen"] == [f] for r, f in zip(me["pendulums"], ["e31", "e32"]))
    ext = st["extensible"]["morales_ramis"]  # control: integrable (Stump00); moved to a level with rational poles
    assert ext["verdict"].startswith("G0 abelian") and all(r["energy"] != "0" for r in ext["pendulums"])
    mag = st["magnetic"]["morales_ramis"]
    assert all("not_run" in r["galois"] for r in mag["pendulums"])  # singular points: roots of z^4 + 2z - 4


def test_paper_report_carries_the_default_models_decided_rows():
    """`magrod check` without --model is the paper's rod, the registry's default: its report carries the same
    decided rows as `--model magnetic-extensible`."""
    from magrod.integrability import decided
    from magrod.integrability.report import format_text, summary

    out = summary()
    keys = [r["key"] for r in out["results"]]
    assert {"kovalevskaya_exponents", "yoshida", "morales_ramis"} <= set(keys)
    mine = [r for r in out["results"] if r["key"] == "morales_ramis"][0]
    assert mine == decided.rows(decided.stored()["models"]["magnetic-extensible"])[-1]
    assert "particular solution m2, m3, n1, e32, e33 = 0 (e31 = 1)" in format_text(out)
