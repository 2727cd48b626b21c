"""The homoclinic splitting of the anisotropic and curved rods (issue 26, item 5; magrod.separatrix.model_splitting):
the closed-form homoclinic orbit against the integrated one, the Mel'nikov closed form against quadrature, the
reversor, the measured splitting against Mel'nikov with its eps scaling, the controls (integrable member, delta,
eigenvector phase, batch width), and the landscape wiring.  Each check is seen to fail under a mutation in the
test itself."""
from __future__ import annotations

import math

import numpy as np
import pytest

from magrod.core.errors import ParameterError
from magrod.separatrix import model_splitting as ms

# the integrable members (B, C, M, T, k3) of the two models' defaults, and a second straight rod
MEMBERS = [("anisotropic", {"B1": 1.0, "C": 1.5}), ("curved", {"B": 1.0, "C": 0.75, "k3": 0.2}),
           ("curved", {"B": 1.3, "C": 0.9, "k3": -0.4})]


def _integrate(model, p, x0, ts):
    """The model's generated body-frame system integrated from x0 over the grid ts (t >= 0), heyoka at tol eps."""
    from magrod.core import systems

    code = ms._code(model)
    ta = systems.taylor(code.mc.body.system(), list(x0), code.mc.parameters(p))
    return np.array(ta.propagate_grid(list(ts))[-1])


@pytest.mark.parametrize("model,params", MEMBERS)
def test_closed_form_homoclinic_orbit_is_the_integrated_orbit(model, params):
    p = ms._base(model, params, 0.0)
    B, C, k3 = ms._unperturbed(model, p)
    t0, ts = -6.0, np.linspace(0.0, 12.0, 25)
    x0 = ms.homoclinic(t0, 0.7, B, C, 1.0, 1.0, k3)[0]
    got = _integrate(model, p, x0, ts)
    want = ms.homoclinic(t0 + ts, 0.7, B, C, 1.0, 1.0, k3)
    assert np.max(np.abs(got - want)) < 1e-11
    # the mutation: the body-frame rotation rate without the pre-twist (or with M/B for M/(2B)) is not the orbit
    wrong = ms.homoclinic(t0 + ts, 0.7, B, C, 1.0, 1.0, k3 + 0.05)
    assert np.max(np.abs(got - wrong)) > 1e-2


@pytest.mark.parametrize("model,params", MEMBERS + [("anisotropic", {"B1": 1.0, "C": 2.0})])  # Omega = 0 too
def test_melnikov_closed_form_equals_quadrature_of_the_generated_integrand(model, params):
    p = ms._base(model, params, 0.01)
    closed, quad = ms.melnikov_closed_form(model, p, 1.0, 1.0), ms.melnikov_quadrature(model, p, 1.0, 1.0)
    assert abs(closed - quad) <= 1e-10 * abs(closed) and closed != 0
    # the mutation: the curved rod read with the anisotropic rod's harmonic (sin 2 phi): the quadrature at
    # phi0 = pi/4 is c sin(pi/4), not c, and the check fails
    if model == "curved":
        k = ms.SPLITTING_MODELS["curved"]["harmonic"]
        ms.SPLITTING_MODELS["curved"]["harmonic"] = 2
        try:
            assert abs(ms.melnikov_quadrature(model, p, 1.0, 1.0) - closed) > 0.2 * abs(closed)
        finally:
            ms.SPLITTING_MODELS["curved"]["harmonic"] = k


@pytest.mark.parametrize("model", ["anisotropic", "curved"])
def test_the_reversor_of_both_models_and_a_wrong_one(model):
    """R (m2, n2, t) -> (-m2, -n2, -t): f(R x) = -R f(x); R' (m1, n1) also works for the anisotropic rod only."""
    code = ms._code(model)
    p = ms._base(model, None, 0.3)
    pars = np.array(code.mc.parameters(p))
    rng = np.random.default_rng(1)
    R2, R1 = np.diag([1, -1, 1, 1, -1, 1.0]), np.diag([-1, 1, 1, -1, 1, 1.0])
    for x in rng.standard_normal((5, 6)):
        f = np.asarray(code.rhs(x, pars))
        assert np.allclose(np.asarray(code.rhs(R2 @ x, pars)), -R2 @ f, rtol=0, atol=1e-14)
        r1 = np.max(np.abs(np.asarray(code.rhs(R1 @ x, pars)) + R1 @ f))
        assert (r1 < 1e-14) if model == "anisotropic" else (r1 > 1e-3)  # the k1 m1 term breaks R1
    xs = ms.saddle(model, p, 1.0, 1.0)
    assert np.allclose(R2 @ xs, xs) and np.max(np.abs(np.asarray(code.rhs(xs, pars)))) < 1e-15


@pytest.mark.parametrize("model", ["anisotropic", "curved"])
def test_measured_splitting_converges_to_melnikov_and_the_controls_hold(model):
    r = ms.model_splitting(model, eps=(0.02, 0.01), n_phase=24)
    assert r.success, r.message
    for row in r.rows:
        # first-order theory: relative remainder O(eps) (anisotropic) or O(eps^2) (curved, by the k1 -> -k1 symmetry)
        assert row["relative_difference"] < (2 * row["eps"] if model == "anisotropic" else 2 * row["eps"] ** 2)
        assert row["A_minus_B"] < 1e-6 and row["level_error"] < 1e-13
    assert abs(r.scaling_order - ms.SPLITTING_MODELS[model]["remainder_order"]) < 0.3
    assert r.control < 1e-12 and r.delta_change < 1e-6 and r.phase_change < 1e-6
    assert r.accuracy["passed"] and r.accuracy["A_minus_B"] < 1e-6 and r.status == 0
    # the integrable control detects a splitting when there is one (mutation: eps != 0 at "eps = 0")
    c = ms.measure(model, 0.01, n_phase=24, direct=False)
    assert abs(c["A"]) > 1e-3 and c["max_abs_delta"] > 1e-3
    # the scaling check fails on a wrong Mel'nikov coefficient (mutation: 1 % off)
    wrong = [abs(x["A"] - 1.01 * x["melnikov"]) / abs(1.01 * x["melnikov"]) for x in r.rows]
    assert abs(math.log(wrong[0] / wrong[1]) / math.log(2) - ms.SPLITTING_MODELS[model]["remainder_order"]) > 0.3


def test_double_and_long_double_agree():
    """The integration error: the unstable manifold from the same starts in long double (x87 80-bit)."""
    if np.finfo(np.longdouble).eps >= np.finfo(float).eps:
        pytest.skip("numpy's longdouble is double on this platform")
    a = ms.measure("curved", 0.01, n_phase=24, direct=False)["A"]
    b = ms.measure("curved", 0.01, n_phase=24, direct=False, precision="long double")["A"]
    assert abs(a - b) <= 1e-12 * abs(a)
    # the mutation: the check resolves a change of eps by one part in 1e8 (and the launch distance does not
    # matter: an off-manifold start error lies in the stable directions, which contract on the way)
    c = ms.measure("curved", 0.01 * (1 + 1e-8), n_phase=24, direct=False)["A"]
    assert abs(c - a) > 1e-12 * abs(a)


def test_measurement_independent_of_batch_width_and_eigenvector_phase(monkeypatch):
    a = ms.measure("anisotropic", 0.02, n_phase=24, direct=False)["A"]
    monkeypatch.setenv("MAGROD_BATCH_WIDTH", "8")
    b = ms.measure("anisotropic", 0.02, n_phase=24, direct=False)["A"]
    c = ms.measure("anisotropic", 0.02, n_phase=24, direct=False, phase=2.1)["A"]
    assert a == b and abs(c - a) < 1e-8 * abs(a)
    # the launch grid in s is not the measured quantity: the raw m3 at a fixed sample index moves with the phase
    u0 = ms.section_curve("anisotropic", ms._base("anisotropic", None, 0.02), 1.0, 1.0, n_phase=24)
    u1 = ms.section_curve("anisotropic", ms._base("anisotropic", None, 0.02), 1.0, 1.0, n_phase=24, phase=2.1)
    assert np.max(np.abs(u0["m3"] - u1["m3"])) > 1e-3


@pytest.mark.parametrize("kw,param", [({"model": "kirchhoff"}, "model"), ({"eps": (0.01, 0.02)}, "eps"),
                                      ({"eps": (0.3, 0.1)}, "eps"), ({"eps": "ab"}, "eps"), ({"eps": (0.1,)}, "eps"),
                                      ({"n_phase": 8}, "n_phase"), ({"n_phase": True}, "n_phase"),
                                      ({"delta": 1e-2}, "delta")])
def test_bad_input_names_the_parameter(kw, param):
    args = {"model": "curved", **kw}
    with pytest.raises(ParameterError) as e:
        ms.model_splitting(args.pop("model"), **args)
    assert param in str(e.value)


def test_greenhill_condition():
    with pytest.raises(ParameterError, match="M"):
        ms.rates(1.0, 1.0, 2.0, 1.0)  # 4 B T = M^2: no saddle-focus


def test_landscape_lines_carry_the_splitting_and_a_failed_one_disagrees(monkeypatch):
    from magrod.integrability import landscape as ls

    got = ls.line("curved", False, "Champneys97a, Leung04", "x", degree=2, t_max=50.0, seed=20, splitting=True,
                  quick=True)
    assert got["agreement"] == "agrees" and got["splitting"]["success"]
    labels = [e["label"] for e in got["evidence"]]
    assert "numerical (floating point with error evidence)" in labels and any(lb.startswith("derived") for lb in labels)
    # the mutation: a splitting measurement that fails its checks makes the line disagree
    real = ms.model_splitting

    def failing(*a, **k):
        r = real(*a, **k)
        r.success = False
        return r

    monkeypatch.setattr(ms, "model_splitting", failing)
    bad = ls.line("curved", False, "x", "x", degree=2, t_max=50.0, seed=20, splitting=True, quick=True)
    assert bad["agreement"] == "disagrees"


def test_report_rows_of_the_splitting():
    from magrod.figures import report
    from magrod.integrability import landscape as ls

    ln = ls.line("anisotropic", False, "Mielke88", "anisotropy destroys integrability", degree=2, t_max=50.0,
                 seed=20, splitting=True, quick=True)
    d = {"lines": [ln], "scan": [], "scan_grid": [], "scan_classes": 0, "degree": 2}
    import json
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as tmp:
        Path(tmp, "landscape.json").write_text(json.dumps(d))
        rows = report._landscape(Path(tmp), True)
    split = [r for r in rows if r["label"] == "sec:intro [Mielke88] (splitting)"]
    assert len(split) == 1 and split[0]["verdict"].startswith("new result") and "-3.26172" in split[0]["computed"]


def _symbolic_residuals(k3_in_omega: bool = True):
    """Residuals of the closed-form homoclinic orbit in the curved rod's generated equations at k1 = 0 (the pipeline's
    report.json, derived from J and W), with E = exp(kappa t), c + i s = exp(i theta): rational in (E, c, s), reduced
    modulo c^2 + s^2 - 1; and its Casimirs |n|^2 - T^2, m.n - M T."""
    import json
    from importlib import resources

    sp = pytest.importorskip("sympy")
    rep = json.loads(resources.files("magrod.generated").joinpath("models/curved/report.json").read_text())
    eqs = {r["key"]: r for r in rep["results"]}["equations"]["details"]
    B, C, M, a = sp.symbols("B C M a", positive=True)
    k3, k1, E, c, s = sp.symbols("k3 k1 E c s", real=True)
    st = sp.symbols("m1 m2 m3 n1 n2 n3", real=True)
    loc = {x.name: x for x in (B, C, k3, k1, *st)}
    kap = a / (2 * B)
    Om = M / C + (k3 if k3_in_omega else 0) - M / (2 * B)
    S, Th = 2 * E / (E**2 + 1), (E**2 - 1) / (E**2 + 1)  # sech, tanh of kappa t
    T = (a**2 + M**2) / (4 * B)  # a^2 = 4 B T - M^2
    X = [a * S * c, a * S * s, M, a * S * (M / (2 * B) * c + kap * Th * s), a * S * (M / (2 * B) * s - kap * Th * c),
         T - a**2 / (2 * B) * S**2]

    def ddt(x):  # E' = kappa E, theta = phi0 - Omega t: c' = Omega s, s' = -Omega c
        return sp.diff(x, E) * kap * E + sp.diff(x, c) * Om * s - sp.diff(x, s) * Om * c

    def reduce(e):
        num = sp.expand(sp.numer(sp.cancel(sp.together(e))))
        return sp.expand(sp.rem(num, c**2 + s**2 - 1, s)) if num != 0 else sp.Integer(0)

    sub = {**dict(zip(st, X)), k1: 0}
    res = [reduce(ddt(x) - sp.sympify(eqs[n], locals=loc).subs(sub)) for n, x in zip([v.name for v in st], X)]
    cas = [reduce(X[3]**2 + X[4]**2 + X[5]**2 - T**2), reduce(X[0] * X[3] + X[1] * X[4] + X[2] * X[5] - M * T)]
    return res, cas, {n: sp.sympify(eqs[n], locals=loc) for n in eqs}, (k1, st)


def test_closed_form_homoclinic_orbit_symbolic():
    """Proved (symbolic): the closed form solves the pipeline's own equations of the straight isotropic rod (curved
    at k1 = 0, any pre-twist k3) on the level of the straight rod; and m3' = -k1 m2 exactly (the integrand of the
    Mel'nikov function).  The mutation: Omega without the pre-twist leaves a residual."""
    res, cas, eqs, (k1, st) = _symbolic_residuals()
    assert all(r == 0 for r in res) and all(c == 0 for c in cas)
    assert eqs["m3"] == -k1 * st[1]
    import json
    from importlib import resources

    import sympy as sp

    rep = json.loads(resources.files("magrod.generated").joinpath("models/anisotropic/report.json").read_text())
    m3dot = {r["key"]: r for r in rep["results"]}["equations"]["details"]["m3"]
    B1, B2 = sp.symbols("B1 B2", positive=True)
    m1, m2 = sp.symbols("m1 m2", real=True)
    assert sp.simplify(sp.sympify(m3dot, locals={"B1": B1, "B2": B2, "m1": m1, "m2": m2})
                       - (1 / B2 - 1 / B1) * m1 * m2) == 0
    bad, _, _, _ = _symbolic_residuals(k3_in_omega=False)
    assert any(r != 0 for r in bad)


def test_landscape_command_passes_no_splitting(monkeypatch, capsys):
    """`magrod landscape --no-splitting` reaches the library as splitting=False (default True); a stub stands in for
    the landscape itself (its content: the tests above)."""
    import json

    from magrod import cli
    from magrod.integrability import landscape as ls

    seen = []

    def stub(degree, **kw):
        seen.append(kw["splitting"])
        return ls.Landscape(True, "stub", degree, 1.0, [], [], 0, [], 0.0)

    monkeypatch.setattr(ls, "landscape", stub)
    for extra in ([], ["--no-splitting"]):
        assert cli.main(["landscape", "--quick", "--json", *extra]) == 0
        assert json.loads(capsys.readouterr().out)["message"] == "stub"
    assert seen == [True, False]
