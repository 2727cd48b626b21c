"""The orbits concept as a library (issue 16): the saddle protocol and the one shooting engine, the public functions
(saddle, homoclinic_orbit, multipulse_orbits, continue_branch, rod_shape) and the one orbit-file schema."""
import json
import math

import numpy as np
import pytest

from magrod.core import systems
from magrod.core.errors import ParameterError
from magrod.core.params import RodParams
from magrod.core.precision import Precision
from magrod.orbits import shooting
from magrod.orbits.continuation import continue_branch
from magrod.orbits.equilibrium import StraightRod, on_level, straight_rod_state
from magrod.orbits.homoclinic import homoclinic_orbit
from magrod.orbits.multipulse import multipulse_orbits
from magrod.orbits.periodic import PeriodicSaddle
from magrod.orbits.rod import rod_shape

EPS = np.finfo(float).eps
FIG6 = RodParams(1.7, 0.002, 1.0, 1.0, 0.001)  # fig:multimodal1, mu = 2 lam: the straight rod
GENERIC = RodParams(1.7, 0.0021, 1.0, 1.0, 0.001)  # mu > 2 lam: the periodic saddle


@pytest.fixture(scope="module")
def fig6_search():
    return multipulse_orbits(FIG6, max_pulses=2, samples=41)


@pytest.fixture(scope="module")
def generic_search():
    return multipulse_orbits(GENERIC, max_pulses=1)


# --- the saddle protocol ---------------------------------------------------------------------------------------
def test_saddle_chooses_by_parameters():
    s = shooting.saddle(FIG6)
    assert isinstance(s, StraightRod) and s.kind == "equilibrium" and isinstance(s, shooting.Saddle)
    ps = shooting.saddle(GENERIC)
    assert isinstance(ps, PeriodicSaddle) and ps.kind == "periodic" and isinstance(ps, shooting.Saddle)
    # mu = 2 lam up to the rounding of a decimal input (MU_TOL) is the straight rod
    assert shooting.saddle(FIG6.replace(mu=0.002 * (1 + 8 * EPS))).kind == "equilibrium"
    with pytest.raises(ParameterError) as e:
        shooting.saddle(FIG6.replace(mu=0.0019))
    assert e.value.name == "mu"
    with pytest.raises(ParameterError) as e:
        shooting.saddle(FIG6.replace(m=3.0))  # m >= m_c = 2 sqrt(2): not hyperbolic
    assert e.value.name == "m"


@pytest.mark.parametrize("which", ["equilibrium", "periodic"])
@pytest.mark.parametrize("precision", list(Precision))
def test_launch_point_at_distance_eps_in_every_precision(which, precision):
    """The launch point is formed in the requested precision (its number type), at distance eps from the saddle
    state, along the unstable direction at the given angle: the double launch agrees to rounding."""
    s = shooting.saddle(FIG6 if which == "equilibrium" else GENERIC)
    x_s = s.x if which == "periodic" else straight_rod_state(FIG6)
    eps, angle = 1e-9, 0.7
    x = s.launch_point(eps, angle, precision)
    x64 = s.launch_point(eps, angle)
    assert type(x.flat[0]) is type(systems.fp_array([0.0], precision.fp_type, precision.prec)[0])
    xf = np.array([float(v) for v in x])
    assert abs(np.linalg.norm(xf - x_s) / eps - 1) <= 1e-6  # |x_s| rounding (1e-16) relative to eps
    assert np.max(np.abs(xf - x64)) <= 4 * EPS
    d = np.real(np.exp(-1j * angle) * s.unstable_vector)
    assert np.allclose((xf - x_s) / eps, d / np.linalg.norm(d), atol=1e-6)


def test_residual_and_jacobian_columns_against_differences():
    """Each Jacobian column of the one engine against a central difference of its residual: d/dT, d/dangle
    (periodic saddle) and d/dq with the saddle recomputed at q +- h (mu following lam for the straight rod: a
    column without mu's share would miss d mu/d lam = 2)."""
    s = shooting.saddle(FIG6)
    T = shooting.unstable_branch(s, crossings=1, launch_distance=1e-7)[0].t
    ev = shooting.residual_and_jacobian(s, T, launch_distance=1e-7, free=("lam", "gamma"))
    hT = 1e-6
    dT = (shooting.residual_and_jacobian(s, T + hT, launch_distance=1e-7, jacobian=False).r
          - shooting.residual_and_jacobian(s, T - hT, launch_distance=1e-7, jacobian=False).r) / (2 * hT)
    assert np.allclose(ev.J[:, 0], dT, rtol=1e-6, atol=1e-9)
    for j, (name, h) in enumerate((("lam", 1e-8), ("gamma", 1e-6)), start=1):
        v = getattr(FIG6, name)
        rp = shooting.residual_and_jacobian(s.at(on_level(FIG6, **{name: v + h})), T, launch_distance=1e-7, jacobian=False).r
        rm = shooting.residual_and_jacobian(s.at(on_level(FIG6, **{name: v - h})), T, launch_distance=1e-7, jacobian=False).r
        assert np.allclose(ev.J[:, j], (rp - rm) / (2 * h), rtol=1e-4, atol=1e-6 * np.max(np.abs(ev.J[:, j])))
    ps = shooting.saddle(GENERIC)
    T = 26.4567663389
    ev = shooting.residual_and_jacobian(ps, T, 1.2987, launch_distance=1e-7, free=("mu",))
    ha = 1e-6
    da = (shooting.residual_and_jacobian(ps, T, 1.2987 + ha, launch_distance=1e-7, jacobian=False).r
          - shooting.residual_and_jacobian(ps, T, 1.2987 - ha, launch_distance=1e-7, jacobian=False).r) / (2 * ha)
    assert np.allclose(ev.J[:, 1], da, rtol=1e-5, atol=1e-8)
    hm = 1e-9
    rp = shooting.residual_and_jacobian(ps.at(GENERIC.replace(mu=GENERIC.mu + hm)), T, 1.2987, launch_distance=1e-7,
                                        jacobian=False).r
    rm = shooting.residual_and_jacobian(ps.at(GENERIC.replace(mu=GENERIC.mu - hm)), T, 1.2987, launch_distance=1e-7,
                                        jacobian=False).r
    assert np.allclose(ev.J[:, 2], (rp - rm) / (2 * hm), rtol=1e-3)


def test_saddle_computed_once_per_parameter_point(monkeypatch):
    """Issue 16: one multipulse shot used to construct the straight rod three times at its start point."""
    from magrod.orbits import equilibrium, multipulse

    calls = []
    real = equilibrium.straight_rod

    def counting(params, **kw):
        calls.append(params)
        return real(params, **kw)

    monkeypatch.setattr(equilibrium, "straight_rod", counting)
    monkeypatch.setattr(multipulse, "straight_rod", counting)
    p = on_level(FIG6, lam=0.00126208079543)
    r = multipulse.shoot(p, 2)
    assert r.success
    assert calls.count(p) == 1, calls.count(p)


def test_one_cache_registry_cleared_by_bypass():
    """systems.clear_caches (called by bypass_disk_cache) empties every registered cache, including the shooting
    engine's compiled Fix(R) functions and its per-thread integrators, so no damaged compiled object survives."""
    f0 = shooting.fix_functions()
    i0 = shooting.crossing_integrator(Precision.DOUBLE)
    v0 = systems.cached_variational(Precision.DOUBLE)
    assert shooting.fix_functions() is f0 and systems.cached_variational("double") is v0
    systems.clear_caches()
    assert shooting.fix_functions() is not f0
    assert shooting.crossing_integrator(Precision.DOUBLE) is not i0
    assert systems.cached_variational(Precision.DOUBLE) is not v0


# --- public functions -----------------------------------------------------------------------------------------
def test_homoclinic_orbit_tolerance_is_honoured():
    """psibar(t, tol) used to ignore tol: a loose tolerance now gives a visibly different (less accurate) value,
    and the default (eps) one agrees with tol = 1e-15."""
    orb = homoclinic_orbit(RodParams(m=1.7, mu=0.0, gamma=1.0, delta=1.0, lam=0.0))
    t = np.linspace(0.0, 20.0, 9)
    exact = orb.psibar(t)
    loose = orb.psibar(t, tol=1e-4)
    assert 1e-12 < np.max(np.abs(loose - exact)) < 1e-2
    assert np.max(np.abs(orb.psibar(t, tol=1e-15) - exact)) <= 1e-13
    with pytest.raises(ParameterError) as e:
        orb.psibar(t, tol=2.0)
    assert e.value.name == "tol"
    assert orb.verify(n=11)["max_dev_theta"] <= 1e-12


def test_multipulse_orbits_to_either_saddle(fig6_search, generic_search):
    assert fig6_search.success and fig6_search.kind == "equilibrium" and fig6_search.pulses == [2]
    o = fig6_search[0]
    # lam* of the Fig 6 2-pulse orbit, docs/errata.md table (long double, eps = 1e-9): 0.00126208079543(4)
    assert abs(o.free_value - 0.00126208079543) <= 4e-14
    assert o.residual <= 1e-10 and o.pulses_counted == 2 and abs(o.params.mu - 2 * o.params.lam) <= 4 * EPS
    orb = o.sample(2001)
    assert shooting.count_pulses(orb["theta"]) == 2 and np.max(np.abs(orb["H"] - o.saddle.H)) <= 1e-13
    assert generic_search.kind == "periodic" and len(generic_search) == 2
    for g in generic_search:  # generic: at the given parameters, no parameter freed
        assert g.params == GENERIC and g.free is None and g.residual <= 1e-10 and g.energy_error <= 1e-13
    for res in (fig6_search, o, generic_search, generic_search[0]):
        assert len(repr(res)) < 1000
        json.dumps(res.to_dict())


@pytest.mark.parametrize("kw,name", [({"max_pulses": 0}, "max_pulses"), ({"samples": 2}, "samples"),
                                     ({"span": 1.5}, "span"), ({"free": "mu"}, "free")])
def test_multipulse_orbits_bad_input(kw, name):
    with pytest.raises(ParameterError) as e:
        multipulse_orbits(FIG6, **kw)
    assert e.value.name == name


def test_continue_branch_both_kinds(fig6_search, generic_search):
    br = continue_branch(GENERIC, generic_search[0], parameter="mu", steps=2, ds=0.2)
    assert br.success and br.points == 3 and br.names == ("T", "angle", "mu") and br.max_residual <= 1e-10
    assert br.kind == "periodic" and len(repr(br)) < 1000
    json.dumps(br.to_dict())
    b2 = continue_branch(FIG6, fig6_search[0], parameter="m", steps=2, ds=0.01)
    assert b2.success and b2.names == ("T", "lam", "m") and b2.max_residual <= 1e-10
    # the first point is the orbit itself: lam* at m = 1.7
    assert abs(b2.u[0, 1] / fig6_search[0].free_value - 1) <= 1e-9
    with pytest.raises(ParameterError) as e:
        continue_branch(FIG6, fig6_search[0], parameter="mu")  # mu follows lam on the straight rod's level
    assert e.value.name == "parameter"
    with pytest.raises(ParameterError) as e:
        continue_branch(FIG6, fig6_search, parameter="mu")
    assert e.value.name == "orbit"


def test_rod_shape_of_an_orbit_and_of_its_file(fig6_search, tmp_path):
    from magrod.core.io import write_orbit

    o = fig6_search[0]
    rod = rod_shape(o, n=1001)
    assert rod.orthonormality <= 1e-12 and rod.det <= 1e-12 and rod.field_consistency <= 1e-12
    paths = write_orbit(tmp_path, "fig6_N2", o)
    again = rod_shape(paths[0], n=1001)
    assert np.array_equal(again.r, rod.r)


# --- one orbit-file schema ----------------------------------------------------------------------------------------
def test_every_orbit_file_reads_back_with_magrod_rod(tmp_path, capsys):
    """Both kinds of orbit file `magrod multipulse` writes (straight rod and periodic saddle) are read by
    `magrod rod --from` (the periodic ones used to lack T, pars and tau and were rejected)."""
    from magrod.cli import main
    from magrod.core.io import ORBIT_ARRAYS, load_orbit_file

    straight, periodic = tmp_path / "straight", tmp_path / "periodic"
    assert main(["multipulse", "--panel", "6", "--pulses", "2", "--samples", "21", "--quiet", "--out",
                 str(straight)]) == 0
    assert main(["multipulse", "--m", "1.7", "--mu", "0.0021", "--gamma", "1", "--delta", "1", "--lam", "0.001",
                 "--pulses", "1", "--samples", "61", "--quiet", "--out", str(periodic)]) == 0
    capsys.readouterr()
    files = sorted(straight.glob("*_N*.npz")) + sorted(periodic.glob("*_N*.npz"))
    kinds = {"straight": 0, "periodic": 0}
    for f in files:
        d = load_orbit_file(f)
        with np.load(f) as z:
            assert set(ORBIT_ARRAYS) - {"angle"} <= set(z.files)
        kinds[f.parent.name] += 1
        assert main(["rod", "--from", str(f), "--json", "--points", "501", "--out", str(tmp_path / "rod")]) == 0
        out = json.loads(capsys.readouterr().out)
        assert out["ok"] and out["orthonormality"] <= 1e-12
        assert math.isfinite(float(d["T"]))
    assert kinds["straight"] >= 1 and kinds["periodic"] >= 1
