"""Section portraits and orbit diagrams (issue 18; magrod.chaos.portrait, magrod poincare --starts, magrod
orbitdiagram, the reproduce figure 'orbitdiagram')."""
import json
import subprocess
import sys
import tempfile

import numpy as np
import pytest

import magrod as mr
from magrod.chaos import portrait
from magrod.chaos.indicators import GROWTH_THRESHOLD, body_indicators
from magrod.chaos.section import poincare_sections, solve_p_psi
from magrod.cli import orbitdiagram as cli_od
from magrod.core import systems
from magrod.core.errors import ParameterError
from magrod.core.printed import PANELS, panel

STARTS = [(0.1, 0.5), (0.3, 0.0), (1.0, 0.2), (0.6, -0.2), (2.0, 0.1)]


@pytest.fixture(scope="module")
def pp():
    return mr.section_portrait("4a", starts=STARTS, iterates=80, t_indicator=300)


def test_portrait_orbits_are_the_sections_of_their_starts(pp):
    assert pp.success and pp.n_orbits == len(STARTS) and pp.h == 0.9
    for r, (th, pt) in zip(pp.orbits, STARTS):
        one = poincare_sections(["4a"], theta0=th, ptheta0=pt, iterates=80)[0]
        np.testing.assert_array_equal(r.points, one.points)  # the batched section of that start
    assert pp.accuracy["passed"] and pp.max_abs_dH <= 1.5e-13
    np.testing.assert_array_equal(pp.starts[:, :2], np.array(STARTS))
    assert np.all(pp.starts[:, 3] == [r.p_psi0 for r in pp.orbits])


def test_portrait_colours_are_the_indicators_of_the_starts(pp):
    """The colour of an orbit is the growth exponent of its start, as body_indicators computes it directly."""
    x0 = np.array([systems.euler_to_body(r.theta0, r.psi0, r.ptheta0, r.p_psi0, r.params.array())
                   for r in pp.orbits]).T
    ref = body_indicators(x0, pp.params.array(), t_max=300.0)
    np.testing.assert_array_equal(pp.values, ref.growth_exponent)
    np.testing.assert_array_equal(pp.chaotic, ref.growth_exponent > GROWTH_THRESHOLD)


def test_portrait_faces(pp):
    ax = pp.plot()
    assert ax.get_xlabel() and len(ax.lines) == pp.n_orbits
    json.dumps(pp.to_dict())
    assert len(repr(pp)) < 1000
    a = pp.arrays()
    assert a["points"].shape == (pp.n_orbits, 80, 4)
    none = mr.section_portrait("4a", starts=STARTS[:2], iterates=10, indicator=None)
    assert np.all(np.isnan(none.values)) and none.chaotic is None


def test_grid_starts_keep_exactly_the_points_that_reach_the_level():
    g = portrait.grid_starts("4a", theta0=(0.1, 3.0, 5), ptheta0=(-1.0, 1.0, 5))
    P = panel("4a")
    kept = {tuple(r) for r in g}
    for th in np.linspace(0.1, 3.0, 5):
        for pt in np.linspace(-1.0, 1.0, 5):
            try:
                solve_p_psi(P.params, P.h, th, pt)
                reach = True
            except ParameterError:
                reach = False
            assert ((th, pt) in kept) == reach
    with pytest.raises(ParameterError) as e:
        portrait.grid_starts("4a", theta0=(2.9, 3.0, 2), ptheta0=(8.0, 9.0, 2))
    assert e.value.name == "starts"


@pytest.mark.parametrize("kw, name", [
    (dict(starts=[]), "starts"),
    (dict(starts=[(0.1, 0.5), (3.0, 9.0)]), "starts"),
    (dict(starts=[(0.1, 0.5)], indicator="megno"), "indicator"),
    (dict(starts=[(0.1, 0.5)], t_indicator=-1), "t_indicator"),
])
def test_portrait_bad_input(kw, name):
    with pytest.raises(ParameterError) as e:
        mr.section_portrait("4a", iterates=5, **kw)
    assert e.value.name == name


# ------------------------------------------------------------------------------------------------ orbit diagram
def test_orbit_diagram_points_are_the_sections_of_each_value():
    vals = [0.135, 0.16, 0.186]
    od = mr.orbit_diagram("lam", vals, iterates=50, transient=10, marks={"4(a)": 0.135})
    assert od.success and od.points.shape == (150, 4) and od.n_values == 3
    for i, lam in enumerate(vals):
        P = panel("4a")
        r = poincare_sections([P.params.replace(lam=lam)], h=P.h, theta0=P.theta0, ptheta0=P.ptheta0,
                             iterates=60)[0]
        np.testing.assert_array_equal(od.points[od.value_index == i], r.points[10:])
    assert np.all(od.coordinate_values("ptheta") == od.points[:, 2])
    ax = od.plot()
    assert ax.get_xlabel()
    json.dumps(od.to_dict())
    # a params_fn gives the same diagram as the parameter name
    od2 = mr.orbit_diagram(lambda x: panel("4a").params.replace(lam=x), vals, iterates=50, transient=10)
    np.testing.assert_array_equal(od2.points, od.points)
    # decreasing values are fine too
    od3 = mr.orbit_diagram("lam", vals[::-1], iterates=5)
    assert od3.values[0] == 0.186


@pytest.mark.parametrize("args, kw, name, words", [
    (("foo", [0.1, 0.2]), {}, "parameter", "model parameter"),
    (("lam", [0.15, 0.14, 0.16]), {}, "values", "monotone"),
    (("lam", [0.15, 0.15]), {}, "values", "monotone"),
    (("lam", []), {}, "values", "non-empty"),
    (("lam", [0.15, np.inf]), {}, "values", "finite"),
    (("delta", [-2.0, 1.0]), {}, "values", "value 0"),  # an unphysical rod
    (("lam", [0.15]), {"coordinate": "phi"}, "coordinate", ""),
])
def test_orbit_diagram_bad_input(args, kw, name, words):
    with pytest.raises(ParameterError) as e:
        mr.orbit_diagram(*args, iterates=5, **kw)
    assert e.value.name == name and words in e.value.message, (e.value.name, e.value.message)


def test_orbit_diagram_refuses_more_than_max_orbits(monkeypatch):
    monkeypatch.setattr(portrait, "MAX_ORBITS", 3)
    with pytest.raises(ParameterError) as e:
        mr.orbit_diagram("lam", [0.14, 0.15, 0.16, 0.17], iterates=5)
    assert e.value.name == "values"


def test_reproduce_figure_marks_the_panels_and_the_inaccessible_band(tmp_path):
    from magrod.figures import FIGURES, build
    from magrod.figures.portrait import accessible_threshold
    from magrod.figures.report import _orbit_diagram

    assert "orbitdiagram" in FIGURES
    lam_min = accessible_threshold("4a", "lam", 0.12, 0.2)
    P = panel("4a")
    solve_p_psi(P.params.replace(lam=lam_min), P.h, P.theta0, P.ptheta0)  # reached at the threshold
    with pytest.raises(ParameterError):
        solve_p_psi(P.params.replace(lam=lam_min - 2e-6), P.h, P.theta0, P.ptheta0)  # and not just below
    paths = build("orbitdiagram", tmp_path, quick=True)
    d = json.loads((tmp_path / "orbitdiagram.json").read_text())
    assert set(d["marks"]) == {"4(a)", "4(b)", "4(c)", "4(d)"}
    assert d["marks"]["4(a)"] == PANELS["4a"]["vary"][1]
    assert d["accessible_from"] == lam_min and d["values"]["first"] >= lam_min
    assert any(p.endswith(".png") for p in paths)
    row = _orbit_diagram(tmp_path, True)[0]
    assert row["verdict"] == "reproduced (by the indicator)", row


# ------------------------------------------------------------------------------------------------------ CLI
def magrod(*argv):
    return subprocess.run([sys.executable, "-m", "magrod.cli", *argv], capture_output=True, text=True,
                          cwd=tempfile.gettempdir(), timeout=300)


def test_cli_choices_match_the_library():
    assert set(cli_od.COORDINATES) == set(portrait.COORDINATES)
    from magrod.chaos.section import MAX_ORBITS

    assert cli_od.MAX_VALUES == MAX_ORBITS


def test_cli_orbitdiagram_and_portrait_write_their_files(tmp_path):
    r = magrod("orbitdiagram", "--parameter", "lam", "--values", "0.14:0.18:3", "--iterates", "30", "--out",
               str(tmp_path), "--json", "--quiet")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["ok"] and d["points"] == 90 and set(d["marks"]) == {"4(a)", "4(b)", "4(c)", "4(d)"}
    assert all((tmp_path / f"orbitdiagram.{e}").exists() for e in ("npz", "json", "png"))
    f = tmp_path / "starts.txt"
    f.write_text("# theta0 ptheta0\n0.1 0.5\n0.3, 0.0\n")
    r = magrod("poincare", "--figure", "4a", "--starts", str(f), "--iterates", "20", "--t-indicator", "100",
               "--out", str(tmp_path), "--json", "--quiet")
    assert r.returncode == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["ok"] and d["n_orbits"] == 2 and d["iterates"] == [20, 20]
    r = magrod("poincare", "--figure", "4a", "--starts", "theta0:0.1:3:3,ptheta0:-1:1:3", "--iterates", "10",
               "--indicator", "none", "--json", "--quiet")
    d = json.loads(r.stdout)
    assert r.returncode == 0 and d["n_orbits"] == len(portrait.grid_starts("4a", theta0=(0.1, 3, 3),
                                                                            ptheta0=(-1, 1, 3)))


@pytest.mark.parametrize("argv, name", [
    (["orbitdiagram", "--parameter", "foo", "--values", "0.1:0.2:3"], "parameter"),
    (["orbitdiagram", "--parameter", "lam", "--values", "0.15,0.14,0.16"], "values"),
    (["orbitdiagram", "--parameter", "lam", "--values", ","], "values"),
    (["orbitdiagram", "--parameter", "lam", "--values", "0.1:0.2:2000000"], "values"),
    (["poincare", "--figure", "4a", "--starts", "EMPTY"], "starts"),
    (["poincare", "--figure", "4a", "--starts", "BADROOT"], "starts"),
    (["poincare", "--figure", "4a", "--starts", "OFFLEVEL"], "starts"),
    (["poincare", "--figure", "4a", "--starts", "/nonexistent/starts.txt"], "starts"),
    (["poincare", "--figure", "4a", "--starts", "theta0:0.1:3:3"], "starts"),
    (["poincare", "--figure", "4a", "--starts", "theta0:2.9:3:2,ptheta0:8:9:2"], "starts"),
    (["poincare", "--figure", "4a", "--starts", "theta0:0.1:3:3,ptheta0:-1:1:3", "--theta0", "0.2"], "theta0"),
])
def test_cli_bad_input_exit_2_one_line_nothing_written(argv, name, tmp_path, capsys):
    files = {"EMPTY": "", "BADROOT": "0.1 0.5\n3.0 9.0\n", "OFFLEVEL": "0.1 0.5 0 0.9\n"}
    argv = list(argv)
    for i, a in enumerate(argv):
        if a in files:
            p = tmp_path / f"{a}.txt"
            p.write_text(files[a])
            argv[i] = str(p)
    out = tmp_path / "out"
    from magrod import cli

    rc = cli.main([*argv, "--iterates", "5", "--out", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert rc == 2, (rc, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and f"{name}:" in lines[0] and "Traceback" not in err, err
    assert not out.exists()
