"""One calling convention on the public face (issue 25, item 4): the system first (a RodParams, a panel name or a
Panel), model parameters overridden by keyword, the same limits and type checks as the command line, and scipy's
`status` next to `success` and `message`."""
import numpy as np
import pytest

import magrod as mr
from magrod.cli.options import LIMITS as CLI_LIMITS
from magrod.core.limits import LIMITS
from magrod.core.printed import with_overrides


def test_keyword_overrides_equal_the_explicit_rod():
    """poincare_section("4a", lam=0.15) is Fig 4(a)'s start on the rod with lambdabar = 0.15: bit for bit the run
    with that RodParams and the panel's start, and its panel says it is not the paper's."""
    P = mr.panel("4a")
    a = mr.poincare_section("4a", iterates=30, lam=0.15)
    b = mr.poincare_section(P.params.replace(lam=0.15), P.h, P.theta0, P.ptheta0, P.psi0, iterates=30)
    assert a.params == b.params and a.params.lam == 0.15
    np.testing.assert_array_equal(a.body_points, b.body_points)
    assert a.panel == "4a, lam=0.15" and a.panel != P.key
    many = mr.poincare_sections(["4a", "4b"], iterates=10, gamma=2.5)
    assert [r.params.gamma for r in many] == [2.5, 2.5]
    ly = mr.lyapunov("4a", t_max=200, lam=0.15)
    assert ly.params.lam == 0.15


def test_an_unknown_keyword_names_itself():
    with pytest.raises(mr.ParameterError) as e:
        mr.poincare_section("4a", iterates=10, lamb=0.15)
    assert e.value.name == "lamb"
    with pytest.raises(mr.ParameterError) as e:
        mr.lyapunov("4a", t_max=100, gama=1.0)
    assert e.value.name == "gama"
    with pytest.raises(mr.ParameterError) as e:
        with_overrides(3.0, {"lam": 0.1})
    assert e.value.name == "params"


@pytest.mark.parametrize("field", ["m", "mu", "gamma", "delta", "lam"])
def test_rod_parameters_must_be_numbers_not_strings(field):
    kw = dict(m=1.7, mu=0.4, gamma=3.0, delta=3.0, lam=0.135)
    kw[field] = str(kw[field])
    with pytest.raises(mr.ParameterError) as e:
        mr.RodParams(**kw)
    assert e.value.name == field and "string" in e.value.message


def test_the_library_and_the_command_line_share_their_limits():
    assert CLI_LIMITS is LIMITS
    with pytest.raises(mr.ParameterError) as e:
        mr.poincare_section("4a", iterates=LIMITS["iterates"] + 1)
    assert e.value.name == "iterates" and str(LIMITS["iterates"]) in e.value.message


def test_status_next_to_success():
    """0 on success, 1 on failure: a Newton run given no iteration does not converge."""
    from magrod.orbits import multipulse

    ok = mr.poincare_section("4a", iterates=10)
    assert ok.success and ok.status == 0
    lam = 0.00126208079543  # docs/errata.md: the Fig 6 two-pulse lam*
    bad = multipulse.shoot(mr.RodParams(1.7, 2 * lam, 1.0, 1.0, lam), 2, max_iter=0, tol=1e-300)
    assert not bad.success and bad.status == 1


def test_splitting_takes_a_rod_first_and_checks_eps_as_the_command_line_did():
    p = mr.RodParams(1.7, 0.4, 1.0, 1.0, 0.1)
    a = mr.splitting(p, a=2, b=1, eps=[0.1, 0.05])
    b = mr.splitting(1.7, 1.0, 1.0, 2, 1, eps=[0.1, 0.05])
    np.testing.assert_array_equal(a.measure, b.measure)
    for eps, words in (([1e-300], "machine epsilon"), ([0.1, 0.1], "distinct"), ([2.0], "(0, 1]"),
                       ([0.1] * 0, "non-empty"), ([1e-3 * (1 + k / 100) for k in range(65)], "at most 64")):
        with pytest.raises(mr.ParameterError) as e:
            mr.splitting(p, a=2, b=1, eps=eps)
        assert e.value.name == "eps" and words in e.value.message, (eps, e.value.message)
    with pytest.raises(mr.ParameterError) as e:
        mr.splitting(p, eps=[0.1])
    assert e.value.name == "a"


def test_chaos_map_takes_a_rod_and_checks_its_fields():
    """chaos_map(..., panel=RodParams) takes the parameters from the rod and the start values as keywords; the
    map validity check is the library's (magrod.chaos.maps.check_fields): a map of impossible starts is not a
    success, and points marked ok without finite indicators are refused."""
    from magrod.chaos import maps

    P = mr.panel("4a")
    cm = mr.chaos_map(("lam", 0.13, 0.14, 2), ("gamma", 2.9, 3.0, 2), panel=P.params, t_max=40, h=P.h,
                      theta0=P.theta0, ptheta0=P.ptheta0, psi0=P.psi0)
    ref = mr.chaos_map(("lam", 0.13, 0.14, 2), ("gamma", 2.9, 3.0, 2), panel="4a", t_max=40)
    np.testing.assert_array_equal(cm.fields["growth_exponent"], ref.fields["growth_exponent"])
    with pytest.raises(mr.ParameterError) as e:
        mr.chaos_map(("lam", 0.13, 0.14, 2), ("gamma", 2.9, 3.0, 2), panel=P.params, t_max=40)
    assert "--panel" not in e.value.message.replace("(panel= / --panel)", "")  # library wording, not the CLI's
    none = mr.chaos_map(("lam", 0.13, 0.14, 2), ("gamma", 2.9, 3.0, 2), panel="4a", t_max=40, h=-50.0)
    assert not none.success and "no point of the map could be computed" in none.message
    bad = {k: np.array(v, copy=True) for k, v in ref.fields.items()}
    bad["lyap"][0, 0] = np.nan
    assert "non-finite lyap" in maps.check_fields(bad)
    assert maps.check_fields(ref.fields) is None


def test_orbit_diagram_marks_values_without_an_energy_root():
    """At lambdabar = 0.12 Fig 4(a)'s start is not on the level h = 0.9 (the figure's grey band): the value is
    marked no_root, nothing computed there, and the other values are the run without it, bit for bit."""
    od = mr.orbit_diagram("lam", [0.12, 0.135, 0.15], iterates=20)
    ref = mr.orbit_diagram("lam", [0.135, 0.15], iterates=20)
    assert od.success and od.no_root.tolist() == [True, False, False] and "no energy root" in od.message
    assert od.orbits[0] is None and od.n_points[0] == 0 and not od.orbit_success[0]
    np.testing.assert_array_equal(od.points, ref.points)
    np.testing.assert_array_equal(od.value_index, ref.value_index + 1)
    assert od.to_dict()["no_root_values"] == [0.12]
    none = mr.orbit_diagram("lam", [0.11, 0.12], iterates=20)
    assert not none.success and none.points.shape == (0, 4)


def test_one_return_type_per_function():
    """poincare_section returns one result; poincare_sections a list, always (one orbit too).  The list form of
    poincare_section still works for one release, with a DeprecationWarning naming the plural."""
    one = mr.poincare_section("4a", iterates=10)
    many = mr.poincare_sections("4a", iterates=10)
    assert not isinstance(one, list) and isinstance(many, list) and len(many) == 1
    np.testing.assert_array_equal(many[0].body_points, mr.poincare_sections(["4a"], iterates=10)[0].body_points)
    with pytest.warns(DeprecationWarning, match="poincare_sections"):
        old = mr.poincare_section(["4a", "4b"], iterates=10)
    new = mr.poincare_sections(["4a", "4b"], iterates=10)
    for a, b in zip(old, new):
        np.testing.assert_array_equal(a.body_points, b.body_points)


def test_accuracy_on_every_result_that_integrates_or_solves():
    """Every result that integrates or solves carries the accuracy it achieved (issue 25)."""
    ps = mr.saddle(mr.RodParams(1.7, 0.4, 3.0, 3.0, 0.135))
    assert ps.accuracy["passed"] and ps.accuracy["re_residual"] <= 1e-13 and ps.accuracy["closure"] < 1e-9
    sr = mr.saddle(mr.RodParams(1.7, 0.27, 3.0, 3.0, 0.135))  # mu = 2 lam: the straight rod
    assert sr.accuracy["passed"]
    ho = mr.homoclinic_orbit(1.7, 1.0)
    assert ho.accuracy["verify"] is None
    ho.verify(n=21)
    assert ho.accuracy["verify"] is not None


def test_the_continue_command_is_the_library_branch(tmp_path, capsys):
    """`magrod continue` parses, calls continue_branch and prints (issue 25: it rebuilt the branch with its own
    scale): its first and last points are the library's, bit for bit."""
    import json

    from magrod import cli
    from magrod.orbits import periodic_multipulse as pm
    from magrod.orbits.continuation import continue_branch

    assert cli.main(["continue", "--pulses", "1", "--steps", "2", "--out", str(tmp_path / "o"), "--json",
                     "--quiet"]) == 0
    d = json.loads(capsys.readouterr().out)
    r = pm.find(mr.RodParams(1.7, 0.0021, 1.0, 1.0, 0.001), 1, samples=121)[0]
    br = continue_branch(r, "mu", 2, ds=0.1)
    assert list(d["first"].values()) == br.u[0].tolist() and list(d["last"].values()) == br.u[-1].tolist()


def test_one_name_per_quantity():
    """The launch distance is `launch_distance` everywhere; `eps` is the perturbation parameter (magrod.separatrix)
    and never a launch distance; machine epsilon is Precision.eps / np.finfo(...).eps, never a parameter.  Read
    from the source: no function of magrod.orbits (where every eps was a launch distance) takes `eps`, and no
    function anywhere takes `eta`.  Seen to fail on the tree before issue 25's rename (24 functions)."""
    import ast
    from pathlib import Path

    import magrod

    root = Path(magrod.__file__).parent
    bad = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                names = {a.arg for a in node.args.args + node.args.kwonlyargs + node.args.posonlyargs}
                rel = path.relative_to(root).as_posix()
                if "eta" in names or ("eps" in names and rel.startswith("orbits/")):
                    bad.append(f"{rel}:{node.lineno} {node.name}")
    assert not bad, bad


def test_integrability_report_takes_the_system_first():
    """integrability_report(system): the model of any System (or what converts to one) gives that model's report;
    the paper's rod the paper's; the old first argument (a substitution) and model= still work, with one
    DeprecationWarning each, and give the same report."""
    import warnings

    s = mr.System("magnetic")
    new = mr.integrability_report(s)
    assert new.source.endswith("magnetic/report.json")
    assert mr.integrability_report("4a").source == mr.integrability_report().source == "generated/report.json"
    with pytest.warns(DeprecationWarning, match="system"):
        old = mr.integrability_report(model="magnetic")
    assert old.rows == new.rows
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        sub = mr.integrability_report({"lambda": 0})
    assert len(w) == 1 and "subs=" in str(w[0].message)
    assert sub.substitution == mr.integrability_report(subs={"lambda": 0}).substitution
    with pytest.raises(mr.ParameterError) as e:
        mr.integrability_report("nosuch")
    assert e.value.name == "model"
