"""Every capability of the section and chaos engine for every model: the six registered models and a model file
that is not in the registry (tests/model_files/gyro_rod.py), through one engine and one result type per concept.

Accuracy evidence per model at tol = machine epsilon: H and every Casimir conserved to <= 1e-12 along sections,
Lyapunov runs, maps, spectra and GALI runs, relative to the size of their terms (core.systems.term_scale: a
Casimir may be 0 at the state, or huge); where a capability needs a structure the model lacks, the named error.
Kept cheap: short runs (tens of crossings, T <= 100)."""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

import magrod as mr
from magrod.chaos.section import PoincareResult
from magrod.core import models, systems

BOUND = 1e-12  # H and the Casimirs at tol = eps, relative to the size of their terms
MODEL_FILE = Path(__file__).parent / "model_files" / "gyro_rod.py"
REGISTERED = ("kirchhoff", "anisotropic", "curved", "extensible", "magnetic", "magnetic-extensible")


@pytest.fixture(scope="module")
def gyro(tmp_path_factory):
    """The model file, copied and compiled into a private cache (never into the package)."""
    d = tmp_path_factory.mktemp("gyro")
    mp = pytest.MonkeyPatch()
    mp.setenv(models.CACHE_ENV, str(d / "cache"))
    f = d / "gyro_rod.py"
    shutil.copy(MODEL_FILE, f)
    yield mr.System(str(f))
    mp.undo()


@pytest.fixture(params=REGISTERED + ("file",))
def system(request, gyro):
    return gyro if request.param == "file" else mr.System(request.param)


def _rel(r):
    return r.max_abs_dH / r.extra["energy_scale"]


def test_sections(system):
    """The one section loop (SIMD lanes) on the model's own section: on the level and on the section."""
    secs = mr.poincare_sections(system, starts=2, iterates=20)
    assert [r.n_points for r in secs] == [20, 20] and all(r.success for r in secs)
    assert all(type(r) is PoincareResult and r.system == system for r in secs)
    assert max(_rel(r) for r in secs) <= BOUND and max(r.casimir_drift for r in secs) <= BOUND
    assert max(float(np.max(np.abs(r.section_residual))) for r in secs) <= BOUND
    assert all(r.psi_dot_sign.tolist() == [1] * 20 for r in secs)  # crossed upwards
    one = mr.poincare_section(system, iterates=5)  # the reference state's orbit
    assert one.success and one.points.shape == (5, systems.model_body(system).dim)


def test_lyapunov_and_spectrum_and_gali(system):
    ly = mr.lyapunov(system, t_max=60.0, renorm_dt=1.0)
    assert ly.success and ly.system == system and ly.times.shape == (60,)
    assert ly.max_abs_dH <= BOUND and ly.casimir_drift <= BOUND
    sp = mr.lyapunov_spectrum(system, t_max=40.0, renorm_dt=2.0)
    n = systems.model_body(system).dim
    assert sp.success and sp.exponents.shape == (n,) and sp.max_abs_dH <= BOUND and sp.casimir_drift <= BOUND
    # a Lie-Poisson field of se(3)* (or its extension) is divergence-free: the exponents sum to 0
    assert abs(float(np.sum(sp.exponents))) <= 1e-8
    g = mr.gali(system, t_max=40.0, renorm_dt=2.0)
    assert g.success and g.gali.shape == (20, 3) and g.max_abs_dH <= BOUND and g.casimir_drift <= BOUND


def test_chaos_map_portrait_and_orbit_diagram(system):
    p, q = system.names[0], system.names[1]
    v, w = system.params[p], system.params[q]
    cm = mr.chaos_map(system, (p, v, 1.2 * v, 2), (q, w, w, 1), t_max=40.0, renorm_dt=2.0)
    assert cm.success and cm.shape == (1, 2) and np.all(cm.fields["status"] == 0)
    assert float(np.max(cm.fields["max_abs_dH"])) <= BOUND and float(np.max(cm.fields["casimir_drift"])) <= BOUND
    pp = mr.section_portrait(system, starts=2, iterates=10, t_indicator=40.0)
    assert pp.success and pp.n_orbits == 2 and np.all(np.isfinite(pp.values)) and pp.accuracy["passed"]
    od = mr.orbit_diagram(system, p, [v, 1.1 * v], iterates=8)
    assert od.success and od.points.shape[0] == 16 and od.accuracy["passed"]
    assert od.coordinate_values().shape == (16,)


def test_structures_the_model_lacks_are_named(system):
    """The Euler-angle chart (formulation "reduced", the branch filter) belongs to the paper's rod (and the
    magnetic rod through it): any other model gets an error naming itself and the structure."""
    if system.is_paper:
        pytest.skip("the paper's rod has its chart")
    if system.model == "magnetic":
        assert mr.poincare_section(system, formulation="reduced", iterates=3).success  # through the paper's chart
    else:
        with pytest.raises(mr.ParameterError) as e:
            mr.poincare_section(system, formulation="reduced", iterates=3)
        assert e.value.name == "model" and "S^1" in e.value.message
    with pytest.raises(mr.ParameterError) as e:
        mr.poincare_sections(system, starts=1, branch="0", iterates=3)
    assert e.value.name == "branch" and repr(system.model) in e.value.message


def test_a_loose_tolerance_fails_the_bound():
    """The check can fail: tol = 1e-6 breaks the 1e-12 conservation of the same sections."""
    loose = mr.poincare_sections("anisotropic", starts=2, iterates=20, tol=1e-6, verify=False)
    assert max(max(_rel(r), r.casimir_drift) for r in loose) > BOUND


def test_term_scale_is_the_sum_of_the_terms():
    """term_scale(C) = sum of |terms|: for C2 = m.n of the anisotropic rod at (1, 0, 0, -1, 0, 0) the value is -1
    and the scale 1; at m = n = 0 both are 0 (a drift relative to the value would divide by 0)."""
    s = mr.System("anisotropic")
    x = np.array([[1.0, 0.0], [0.0, 0.0], [0.0, 0.0], [-1.0, 0.0], [0.0, 0.0], [0.0, 0.0]])
    c = systems.term_scale(s, "casimirs", x)
    assert c.tolist() == [[1.0, 0.0], [1.0, 0.0]]
    x2 = np.array([1.0, 2.0, 3.0, -1.0, 1.0, 0.5])
    assert systems.term_scale(s, "casimirs", x2)[1] == pytest.approx(1.0 + 2.0 + 1.5)


def test_the_papers_rod_keeps_its_chart_path_bit_for_bit():
    """The paper's rod from a panel runs its chart path (the numbers of REPORT.md); from body states it runs the
    same compiled body system in the model path: the same crossings from the same body start."""
    a = mr.poincare_section("4a", iterates=30)
    x0 = a.body_points[0]  # a crossing, in the body frame (the paper's formulation "body")
    b = mr.poincare_sections(mr.System("4a"), starts=[x0], iterates=5, level_of=x0)[0]
    # a start landed on the section (to ~1e-17) is the start, not a crossing: then the paper's next crossings
    assert b.success and np.max(np.abs(b.points - a.body_points[1:6])) < 1e-12
    assert np.max(np.abs(b.times + a.times[0] - a.times[1:6])) < 1e-9
