"""Issue 25, item 2 and the multipulse face: one damped Newton (magrod.orbits.shooting.newton) serves every
shooting problem; multipulse_orbits / find_orbits return Result objects; `magrod multipulse` parses, calls the
public search and prints its to_dict(), and the figure writer takes the search result."""
import json
import warnings

import numpy as np
import pytest

from magrod.core.errors import ParameterError
from magrod.core.params import RodParams
from magrod.core.results import Result
from magrod.core.tolerances import FLOOR_CAP, FLOOR_FACTOR, SHOOTING_TOL
from magrod.orbits import continuation, multipulse, periodic_multipulse, shooting
from magrod.orbits.equilibrium import on_level

FIG6_N2 = on_level(RodParams(1.7, 0.002, 1.0, 1.0, 0.001), lam=0.00126208079543)  # docs/errata.md lam*
GENERIC = RodParams(1.7, 0.0021, 1.0, 1.0, 0.001)  # mu > 2 lam: the periodic saddle


# --- the one Newton on problems whose answers are known in closed form ----------------------------------------
class _Ev:
    def __init__(self, r, J):
        self.r, self.J = np.asarray(r, float), np.asarray(J, float)


def _noisy_line(noise):
    """r(z) = (z0 - 1, z1 - 2) plus a deterministic, non-smooth noise of amplitude `noise` (the shooting residual
    near its root): Newton cannot go below it."""
    def evaluate(z):
        wiggle = noise * np.sin(1e9 * (z + np.array([0.3, 0.7])))
        return _Ev(z - np.array([1.0, 2.0]) + wiggle, np.eye(2))

    return evaluate


def test_newton_converges_to_the_root_of_a_linear_problem():
    run = shooting.newton(_noisy_line(0.0), [0.0, 0.0], tol=SHOOTING_TOL, max_evaluations=5)
    assert run.outcome == "converged" and run.success and run.iterations == 1 and run.evaluations == 2
    np.testing.assert_array_equal(run.z, [1.0, 2.0])


def test_newton_stalls_at_the_noise_floor_and_accepts_only_within_it():
    noise = 1e-9  # far above tol, below FLOOR_CAP
    kw = dict(tol=SHOOTING_TOL, max_evaluations=25, stall=4)
    plain = shooting.newton(_noisy_line(noise), [0.0, 0.0], **kw)
    assert plain.outcome == "stalled" and not plain.success and plain.evaluations < 25
    ok = shooting.newton(_noisy_line(noise), [0.0, 0.0], floor=lambda ev, z: np.full(2, noise), **kw)
    assert ok.outcome == "floor" and ok.success and ok.residual <= FLOOR_FACTOR * noise
    assert ok.residual == min(res for _, res in ok.history)  # the best iterate is the one returned
    # a floor measured too small (here 1e-3 of the noise) does not accept the stalled iterate
    low = shooting.newton(_noisy_line(noise), [0.0, 0.0], floor=lambda ev, z: np.full(2, 1e-3 * noise), **kw)
    assert low.outcome == "stalled" and not low.success
    # nor does a floor above FLOOR_CAP: a residual that large is not an orbit
    big = shooting.newton(_noisy_line(10 * FLOOR_CAP), [0.0, 0.0], floor=lambda ev, z: np.ones(2), **kw)
    assert not big.success


def test_newton_damps_and_stops_on_a_rejected_step():
    damp = shooting.limit_component(1, 0.25)
    run = shooting.newton(_noisy_line(0.0), [0.0, 0.0], tol=SHOOTING_TOL, max_evaluations=2, damp=damp)
    # the first step (1, 2) is scaled so that |d z1| = 0.25: z = (0.125, 0.25)
    np.testing.assert_allclose(run.history[1][0], [0.125, 0.25], rtol=0, atol=1e-15)

    def refuse(z):
        if z[0] > 0.5:
            raise ParameterError("lam", "no saddle here")
        return _Ev(z - 1.0, np.eye(2))

    run = shooting.newton(refuse, [0.0, 0.0], tol=SHOOTING_TOL, max_evaluations=5)
    assert run.outcome == "rejected" and run.error.name == "lam" and run.evaluations == 1


def test_the_one_newton_serves_every_shooting_problem(monkeypatch):
    """The straight rod's shooting (free parameter, noise floor), the periodic saddle's (T, angle) and the
    continuation corrector (orbits/arclength.py) all run shooting.newton; they once had their own loops."""
    calls = []
    real = shooting.newton

    def counting(evaluate, z0, **kw):
        calls.append(kw)
        return real(evaluate, z0, **kw)

    from magrod.orbits import arclength

    for mod in (shooting, multipulse, periodic_multipulse, continuation, arclength):
        if hasattr(mod, "newton"):
            monkeypatch.setattr(mod, "newton", counting)
    r = multipulse.shoot(FIG6_N2, 2)
    assert r.success and len(calls) == 1 and calls[0]["stall"] is not None and calls[0]["floor"] is not None
    ps = shooting.saddle(GENERIC)
    T, angle = periodic_multipulse.crossings(ps, 1.3, 1)[0][0], 1.3
    periodic_multipulse.shoot(GENERIC, 1, angle, T, saddle=ps)
    assert len(calls) == 2
    r2 = periodic_multipulse.find(GENERIC, 1, saddle=ps)[0]
    F, _ = continuation.periodic_problem(GENERIC, "mu", 1)
    n = len(calls)
    continuation.point_at(F, np.array([r2.T, r2.angle, GENERIC.mu]), 2, GENERIC.mu)
    assert len(calls) == n + 1


# --- Results, never dicts -------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def fig6_search():
    return multipulse.multipulse_orbits(RodParams(1.7, 0.002, 1.0, 1.0, 0.001), max_pulses=2, samples=41)


def test_multipulse_orbits_and_find_orbits_return_results(fig6_search):
    s = fig6_search
    assert isinstance(s, Result) and s.status == 0 and s.success
    assert len(s.searches) == 2 and all(isinstance(p, shooting.PulseSearch) for p in s.searches)
    assert [f.pulses_target for f in s.failures] == [1] and isinstance(s.failures[0], Result)
    two = s.search(2)
    assert two.success and two.status == 0 and two.orbit is s[0] and two.accuracy["max_residual"] <= SHOOTING_TOL
    assert s.failures[0].status == 1 and s.failures[0].orbit is None
    d = json.loads(json.dumps(s.to_dict()))
    assert d["searches"][1]["free_value"] == pytest.approx(s[0].free_value, rel=0, abs=0)
    assert d["status"] == 0 and d["free"] == "lam" and d["span"] == 0.5 and d["samples"] == 41
    # find_orbits, the straight rod's search, gives the same PulseSearch results
    found = multipulse.find_orbits(s.params, max_pulses=2, samples=41, saddle=s.saddle)
    assert [type(p) for p in found] == [shooting.PulseSearch] * 2 and found[1].orbit.free_value == s[0].free_value


def test_dict_access_of_the_old_entries_warns_and_agrees(fig6_search):
    two = fig6_search.search(2)
    with pytest.warns(DeprecationWarning):
        assert two["result"] is two.orbit and two["success"] is True
    with pytest.warns(DeprecationWarning):
        assert two["residual"] == two.orbit.residual and two.get("orbit") is two.samples[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert two.row()["free_value"] == two.orbit.free_value  # the attributes do not warn


def test_periodic_saddle_refuses_straight_rod_options():
    for kw, name in (({"span": 0.3}, "span"), ({"free": "m"}, "free")):
        with pytest.raises(ParameterError) as e:
            multipulse.multipulse_orbits(GENERIC, 1, **kw)
        assert e.value.name == name
    with pytest.raises(ParameterError) as e:
        multipulse.multipulse_orbits(GENERIC, 13)  # core.limits: the command line's limit
    assert e.value.name == "max_pulses"


# --- the command is a thin client -----------------------------------------------------------------------------
def test_cli_multipulse_prints_the_public_search(monkeypatch, tmp_path, capsys, fig6_search):
    """`magrod multipulse` calls multipulse_orbits with the parsed options (it decides the saddle) and prints
    that result's to_dict() (plus the files the figure writer wrote from it)."""
    from magrod.cli import main

    seen = {}

    def fake(params, max_pulses, **kw):
        seen.update(params=params, max_pulses=max_pulses, **kw)
        return fig6_search

    monkeypatch.setattr(multipulse, "multipulse_orbits", fake)
    assert main(["multipulse", "--panel", "6", "--pulses", "2", "--samples", "41", "--json", "--quiet",
                 "--out", str(tmp_path)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert seen["params"] == fig6_search.params and seen["max_pulses"] == 2 and seen["samples"] == 41
    assert seen["free"] is None and seen["span"] is None  # not decided by the command
    expect = json.loads(json.dumps(fig6_search.to_dict()))
    assert {k: out[k] for k in expect if k != "wall_time_s"} == {k: v for k, v in expect.items() if k != "wall_time_s"}
    assert out["files"] == [[str(tmp_path / "figure6_N2.npz"), str(tmp_path / "figure6_N2.json")]]
    assert (tmp_path / "figure6_table.json").is_file()


def test_cli_and_figures_do_not_reach_into_the_search():
    """The command and the figure module use the public search and its result only: no mu = 2 lam rule of
    their own (MU_TOL, straight_rod_mu), no find_orbits/multipulse_rows internals."""
    import ast
    import inspect

    from magrod.cli import multipulse as cli
    from magrod.figures import multipulse as fig

    for mod in (cli, fig):
        names = {n.id if isinstance(n, ast.Name) else n.attr for n in ast.walk(ast.parse(inspect.getsource(mod)))
                 if isinstance(n, (ast.Name, ast.Attribute))}
        names |= {a.name for n in ast.walk(ast.parse(inspect.getsource(mod))) if isinstance(n, ast.ImportFrom)
                  for a in n.names}
        assert not names & {"MU_TOL", "straight_rod_mu", "find_orbits", "multipulse_rows", "straight_rod", "find"}, \
            (mod.__name__, names & {"MU_TOL", "straight_rod_mu", "find_orbits", "multipulse_rows", "straight_rod"})
