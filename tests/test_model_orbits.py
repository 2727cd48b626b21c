"""Saddles, reversors, symmetric homoclinic orbits, their continuation and the rod's shape for every model: the six
registered models and a model file that is not in the registry (magrod.orbits.equilibria, magrod.orbits.reversible,
magrod.orbits.rod).  Each capability that applies is run with its accuracy evidence; where a model lacks the
structure a step needs, the named error is checked."""
from __future__ import annotations

import math

import numpy as np
import pytest

import magrod as mr
from magrod.core.tolerances import EPS
from magrod.orbits.equilibria import reversor, reversor_defect, reversors, straight_rod
from magrod.orbits.reversible import symmetric_homoclinic
from magrod.separatrix.model_splitting import homoclinic as closed_form

SIX = ("anisotropic", "curved", "kirchhoff", "extensible", "magnetic", "magnetic-extensible")
# the models whose straight twisted rod is a saddle-focus on a 4-D leaf (6-D state, 2 Casimirs)
SIX_D = {"anisotropic": dict(B1=1, B2=1.1, C=1.5), "curved": dict(B=1, C=0.75, k1=0.1, k3=0.2),
         "kirchhoff": {}, "extensible": {}}


@pytest.mark.parametrize("model", SIX)
def test_straight_rod_is_found_with_a_deterministic_spectrum(model, monkeypatch):
    """The straight twisted rod (or the relative equilibrium next to it) is an equilibrium to rounding; its leaf
    spectrum is a Hamiltonian set (w and -w both in it) whatever order and phase LAPACK returns its eigenpairs in."""
    s = mr.System(model)
    e = straight_rod(s)
    assert e.success and e.accuracy["passed"] and e.system == s
    assert e.kind in ("saddle-focus", "saddle-centre")
    w = e.eigenvalues
    assert np.max(np.abs(np.sort_complex(w) - np.sort_complex(-w))) <= 1e-10 * max(1.0, np.max(np.abs(w)))
    # LAPACK's order and the eigenvectors' phases scrambled: the same sorted spectrum and unstable vector
    rng = np.random.default_rng(7)
    eig = np.linalg.eig

    def scrambled(a):
        vals, vecs = eig(a)
        p = rng.permutation(vals.size)
        return vals[p], vecs[:, p] * np.exp(2j * np.pi * rng.uniform(size=vals.size))

    monkeypatch.setattr(np.linalg, "eig", scrambled)
    e2 = straight_rod(s)
    np.testing.assert_array_equal(e2.eigenvalues, w)
    assert np.max(np.abs(e2.unstable_vector - e.unstable_vector)) <= 1e-12


def test_anisotropic_and_curved_straight_rod_is_a_saddle_focus():
    """Greenhill: 4 B T - M^2 = 3 > 0 at B = M = T = 1: eigenvalues +-kappa +-i Omega with the closed-form rates of
    model_splitting.rates (kappa = a / 2B, Omega = M/C + k3 - M/(2B)) at the integrable member."""
    from magrod.separatrix.model_splitting import rates

    for model, kw, (B, C, k3) in (("anisotropic", dict(B1=1, B2=1, C=1.5), (1, 1.5, 0)),
                                  ("curved", dict(B=1, C=0.75, k1=0, k3=0.2), (1, 0.75, 0.2))):
        e = mr.saddle(mr.System(model, **kw))
        _, kap, om = rates(B, C, 1.0, 1.0, k3)
        assert e.kind == "saddle-focus"
        assert abs(e.unstable_eigenvalue - complex(kap, abs(om))) <= 1e-12
    # the curved rod's relative equilibrium at k1 != 0: model_splitting's closed form (u = beta n, d3 = ...)
    from magrod.separatrix.model_splitting import saddle as cf_saddle

    p = dict(B=1, C=0.75, k1=0.1, k3=0.2)
    e = mr.saddle(mr.System("curved", **p))
    assert e.kind == "saddle-focus"
    x_cf = cf_saddle("curved", p, 1.0, 1.0)
    # the closed form is a relative equilibrium on another leaf point of the family: compare on the leaf's
    # invariants (both are equilibria with the same Casimirs up to the family parameter) -- f(x_cf) = 0 exactly
    from magrod.orbits.model_field import field

    f = field(e.system)
    assert np.max(np.abs(f.rhs(x_cf, e.system.array()))) <= 1e-14


@pytest.mark.parametrize("model", SIX)
def test_reversor_of_every_registered_model(model):
    """(m2, n2[, e32]) -> -(...) is a reversor of every registered model (fixing the straight rod); a mutated
    candidate (one more flip) is not."""
    s = mr.System(model)
    e = straight_rod(s)
    names = [r.names[i] for r in reversors(s) for i in r.flipped]
    R = reversor(s, fixing=e.x)
    assert R.residual <= 1e3 * EPS
    assert {"m2", "n2"} <= {R.names[i] for i in R.flipped} or {"m1", "n1"} <= {R.names[i] for i in R.flipped}
    assert "m2" in names
    bad = np.array(R.signs, float)
    bad[R.names.index("m3")] *= -1
    assert reversor_defect(s, bad) > 1e-3


@pytest.mark.parametrize("model", sorted(SIX_D))
def test_symmetric_homoclinic_orbit_with_its_accuracy(model):
    """Any 6-D reversible model: x(T) on Fix(R) to 1e-9, H and the Casimirs conserved to 1e-12 at tol = eps, the
    launch level within O(delta^2), and the second half R-symmetric (sample: x(2T - t) = R x(t))."""
    s = mr.System(model, **SIX_D[model])
    o = mr.homoclinic_orbit(s)
    assert o.success and o.system == s, o.message
    acc = o.accuracy
    assert acc["passed"] and acc["level_drift"] <= 1e-12 and acc["launch_level_gap"] <= 1e-11
    # reversibility checked by the flow itself: integrated on past T, the orbit is R x(2T - t) (the deviation
    # grows from the residual like exp(kappa s): ~1e-9 e^(4 kappa) here); with another sign pattern it is not
    from magrod.orbits.reversible import _flow

    sg = np.asarray(o.reversor.signs, float)
    tt = np.linspace(o.T - 4.0, o.T + 4.0, 81)
    X = _flow(s, o.x0, None, np.concatenate([[0.0], tt]))[1:]
    dev = np.max(np.abs(X[::-1] - o.reversor.apply(X)))
    assert dev <= 1e-6, dev
    wrong = -sg
    wrong[o.equilibrium.x != 0] = 1.0
    assert np.max(np.abs(X[::-1] - wrong * X)) > 1e-2
    # a homoclinic orbit: both ends at the saddle, the middle far from it
    smp = o.sample(201)
    x = smp["x"]
    assert np.max(np.abs(x[0] - o.equilibrium.x)) <= 2 * o.launch_distance
    assert np.max(np.abs(x[-1] - o.equilibrium.x)) <= 2 * o.launch_distance
    assert np.max(np.abs(x[100] - o.equilibrium.x)) > 0.5


@pytest.mark.parametrize("model, kw, B, C, k3, harmonic", [
    ("anisotropic", dict(B1=1, B2=1, C=1.5), 1.0, 1.5, 0.0, 2),
    ("curved", dict(B=1, C=0.75, k1=0, k3=0.2), 1.0, 0.75, 0.2, 1)])
def test_homoclinic_at_eps_0_is_the_closed_form_and_continues_in_eps(model, kw, B, C, k3, harmonic):
    """At eps = 0 the homoclinic orbits are a family in phi0; the one on Fix(R) of the reversor that survives the
    perturbation ((m2, n2) -> -(m2, n2)) has sin phi0 = 0, a Mel'nikov zero (sin 2 phi0 = 0 anisotropic, sin phi0 = 0
    curved), and matches model_splitting's closed form along the orbit.  It then continues in eps."""
    s0 = mr.System(model, **kw)
    s1 = s0.replace(**({"B2": 1.05} if model == "anisotropic" else {"k1": 0.05}))
    # a reversor of the perturbed rod (the curved rod's only one; the anisotropic rod keeps (m1, n1) too)
    survive = [r for r in reversors(s1) if {r.names[i] for i in r.flipped} == {"m2", "n2"}]
    assert len(survive) == 1
    R = survive[0]
    o = symmetric_homoclinic(s0, reversor=R)
    assert o.success, o.message
    xm = o.x_mid
    phi0 = math.atan2(xm[1], xm[0])
    assert abs(math.sin(harmonic * phi0)) <= 1e-9
    smp = o.sample(2001)
    t = smp["t"] - o.T
    win = np.abs(t) <= 8.0
    ref = closed_form(t[win], phi0, B, C, 1.0, 1.0, k3)
    err = float(np.max(np.abs(smp["x"][win] - ref)))
    # the launch error O(delta^2) = 1e-12 and the Fix(R) residual: measured 2.6e-12 (anisotropic), 3.8e-13 (curved)
    assert err <= 1e-10, err
    # mutation: the closed form at the other phase of the family is far
    assert np.max(np.abs(smp["x"][win] - closed_form(t[win], phi0 + 0.1, B, C, 1.0, 1.0, k3))) > 1e-2
    # continuation in eps from the reversible orbit
    par = "B2" if model == "anisotropic" else "k1"
    br = mr.continue_branch(s0, o, parameter=par, steps=2, ds=0.02)
    assert br.success and br.points == 3 and br.max_residual <= 1e-9, br.message
    assert br.u[-1, 2] != br.u[0, 2] and br.system == s0
    with pytest.raises(mr.ParameterError) as exc:  # the orbit belongs to its own system
        mr.continue_branch(s1, o, parameter=par, steps=1)
    assert exc.value.name == "system"


def test_continuation_of_equilibria_and_its_folds():
    """The curved rod's relative equilibria on the straight rod's leaf continued in k1: every point an equilibrium
    to rounding, on the start's leaf; the branch's folds are the points where the tangent's k1 component changes
    sign (none or located ones, each with a residual)."""
    s = mr.System("curved", B=1, C=0.75, k1=0.0, k3=0.2)
    e = straight_rod(s)
    br = mr.continue_branch(s, e, parameter="k1", steps=4, ds=0.1)
    assert br.success and br.points == 5, br.message
    assert br.max_residual <= 1e-12
    from magrod.orbits.model_field import field

    f = field(s)
    for u in br.u:
        ss = s.replace(k1=u[-1])
        assert np.max(np.abs(f.rhs(u[:-1], ss.array()))) <= 1e-12
        np.testing.assert_allclose(f.casimirs(u[:-1], ss.array()), f.casimirs(e.x, s.array()), atol=1e-12)
    for fold in br.folds:
        assert fold["u"] is not None


@pytest.mark.parametrize("model", SIX)
def test_rod_shape_of_every_model(model):
    """d_i' = u x d_i, r' = sum v_i d_i with u = dH/dm, v = dH/dn (hy.diff): the frame orthonormal and the field (or
    the force in space) conserved to 1e-12 along the equilibrium's helix; the helix's body state constant."""
    s = mr.System(model)
    e = straight_rod(s)
    rod = mr.rod_shape(s, e, n=200)
    assert rod.success and rod.system == s
    assert rod.orthonormality <= 1e-12 and rod.det <= 1e-12 and rod.field_consistency <= 1e-12
    # the helix is a saddle: rounding grows like exp(kappa s) along it
    assert rod.deviation_from_symmetric_orbit <= 1e-14 * max(1.0, math.exp(e.unstable_eigenvalue.real * rod.length))
    # the centreline of a uniform helix has constant speed |r'| = |v|
    speed = np.linalg.norm(np.diff(rod.r, axis=0), axis=1)
    assert np.ptp(speed) <= 1e-9 * np.max(speed)


def test_symmetric_homoclinic_orbit_of_the_magnetic_rod():
    """9-D, 3 Casimirs, Fix(R) of codimension 3 on the 6-D leaf: consistent through the S^1 symmetry's integral; the
    orbit conserves H and the Casimirs to 1e-12, its rod's frame stays orthonormal with D^T z = e3, and it continues
    in lam."""
    s = mr.System("magnetic")
    o = mr.homoclinic_orbit(s)
    assert o.success and o.accuracy["passed"] and o.reversor.codim == 3, o.message
    rod = mr.rod_shape(s, o, n=300)
    assert rod.orthonormality <= 1e-12 and rod.field_consistency <= 1e-12
    # three Fix(R) conditions of rank 2 continued by projection: every point's full residual is reported
    br = mr.continue_branch(s, o, parameter="lam", steps=2, ds=0.05)
    assert br.success and br.points == 3 and br.max_residual <= 1e-9 and br.u[-1, 2] != 0.25, br.message


def test_rod_shape_of_a_homoclinic_orbit():
    s = mr.System("anisotropic", **SIX_D["anisotropic"])
    o = mr.homoclinic_orbit(s)
    rod = mr.rod_shape(s, o, n=400)
    assert rod.orthonormality <= 1e-12 and rod.field_consistency <= 1e-12
    assert rod.deviation_first_half <= 1e-9  # the integrated states are the orbit's own samples
    # the old spelling rod_shape(orbit) takes the orbit's system
    rod2 = mr.rod_shape(o, 400)
    np.testing.assert_array_equal(rod2.r, rod.r)


def test_multipulse_orbits_of_a_reversible_model():
    """The anisotropic rod (non-integrable) has 2-pulse symmetric orbits; the integrable Kirchhoff rod, whose
    manifolds coincide, has only its primary (a search that passed x* at the launch's level error would find
    spurious 2-pulse orbits there)."""
    s = mr.System("anisotropic", B1=1, B2=1.2, C=1.5)
    found = mr.multipulse_orbits(s, 2, samples=48)
    assert found.success and found.system == s
    assert set(found.pulses) == {1, 2}
    for o in found:
        assert o.accuracy["passed"]
    assert set(mr.multipulse_orbits("kirchhoff", 2, samples=32).pulses) == {1}


def test_paper_rod_paths_unchanged():
    """The paper's rod: saddle, the closed form at lam = mu = 0, and the named errors of the face."""
    p = mr.RodParams(m=1.7, mu=0.002, gamma=1, delta=1, lam=0.001)
    from magrod.orbits.shooting import paper_saddle

    a, b = mr.saddle(p), paper_saddle(p)
    np.testing.assert_array_equal(a.x, b.x)
    np.testing.assert_array_equal(a.unstable_vector, b.unstable_vector)
    # the generic engine on the paper's rod: the same straight rod, its leaf spectrum the nonzero eigenvalues of the
    # paper's 9 x 9 Jacobian (three zeros: the Casimirs)
    g = straight_rod(mr.System(p))
    np.testing.assert_array_equal(g.x, b.x)
    assert abs(g.unstable_eigenvalue - b.unstable_eigenvalue) <= 1e-14
    nonzero = b.eigenvalues[np.abs(b.eigenvalues) > 1e-12]
    np.testing.assert_allclose(np.sort_complex(g.eigenvalues), np.sort_complex(nonzero), atol=1e-13)
    o = mr.homoclinic_orbit(mr.System(m=1.7, gamma=1.0, mu=0, lam=0))
    with pytest.warns(DeprecationWarning):
        o2 = mr.homoclinic_orbit(1.7, 1.0)
    assert (o.kappa, o.h) == (o2.kappa, o2.h)
    with pytest.raises(mr.ParameterError) as exc:
        mr.homoclinic_orbit("4a")
    assert exc.value.name == "lam"
    with pytest.warns(DeprecationWarning, match="system"):  # the old keyword of the first argument
        c = mr.saddle(params=p)
    np.testing.assert_array_equal(c.x, b.x)


def test_splitting_of_a_model_with_a_small_parameter():
    """mr.splitting dispatches the curved rod to its Mel'nikov measurement, which carries the system."""
    s = mr.System("curved", B=1, C=0.75, k3=0.2)
    r = mr.splitting(s, eps=(0.02, 0.01))
    assert type(r).__name__ == "Splitting" and r.kind == "melnikov"
    assert r.success and r.system == s and abs(r.leading["melnikov_unit"] + 1.884) < 1e-3
    assert r.leading["digits"] >= 2 and r.accuracy["passed"] and r.agreement <= 1e-6
    import json

    json.dumps(r.to_dict())


@pytest.mark.parametrize("model", ("kirchhoff", "extensible", "magnetic"))
def test_splitting_needs_a_small_parameter(model):
    with pytest.raises(mr.ParameterError) as exc:
        mr.splitting(model)
    assert exc.value.name == "model" and repr(model) in str(exc.value) and "small parameter" in str(exc.value)


SKEW_ROD = '''
import sympy as sp
m1, m2, m3, n1, n2, n3 = sp.symbols("m1 m2 m3 n1 n2 n3", real=True)
u1, u2, u3 = sp.symbols("u1 u2 u3", real=True)
v1, v2, v3 = sp.symbols("v1 v2 v3", real=True)
A1, A2, C = sp.symbols("A1 A2 C", positive=True)
k1, k2 = sp.symbols("k1 k2", real=True)

def hat(a):
    return sp.Matrix([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])

m, n = sp.Matrix([m1, m2, m3]), sp.Matrix([n1, n2, n3])
NAME = "skew-rod"
STATE = [m1, m2, m3, n1, n2, n3]
PARAMETERS = {A1: ("bending stiffness about d1", (0, sp.oo), 1), A2: ("bending stiffness about d2", (0, sp.oo), 2),
              C: ("torsional stiffness", (0, sp.oo), sp.Rational(3, 2)),
              k1: ("intrinsic curvature about d1", (-sp.oo, sp.oo), sp.Rational(1, 4)),
              k2: ("intrinsic curvature about d2", (-sp.oo, sp.oo), sp.Rational(1, 8))}
J = sp.Matrix.vstack(sp.Matrix.hstack(hat(m), hat(n)), sp.Matrix.hstack(hat(n), sp.zeros(3, 3)))
W = (A1 * (u1 - k1)**2 + A2 * (u2 - k2)**2 + C * u3**2) / 2
STRAINS = [(u1, m1), (u2, m2), (u3, m3), (v1, n1), (v2, n2), (v3, n3)]
FIXED = {v1: 0, v2: 0, v3: 1}
'''


@pytest.fixture(scope="module")
def skew_rod(tmp_path_factory):
    """A model file outside the registry: an anisotropic rod curved about both principal axes (no reflection of
    body components is a reversor: each flips the sign of k1 or k2).  Compiled once (~20 s)."""
    import os

    from magrod.core import models

    d = tmp_path_factory.mktemp("skew")
    old = os.environ.get("MAGROD_MODEL_CACHE")
    os.environ["MAGROD_MODEL_CACHE"] = str(d / "cache")
    f = d / "skew_rod.py"
    f.write_text(SKEW_ROD)
    try:
        yield mr.System(str(f))
    finally:
        if old is None:
            os.environ.pop("MAGROD_MODEL_CACHE", None)
        else:
            os.environ["MAGROD_MODEL_CACHE"] = old
        models._LOADED.clear()


def test_a_model_file_outside_the_registry(skew_rod):
    """Saddle, its helix, equilibrium continuation and the rod's shape work; the reversible steps name the model and
    the missing reversor; the splitting names the missing small parameter."""
    s = skew_rod
    e = mr.saddle(s)
    assert e.success and e.kind == "saddle-focus" and e.system == s
    rod = mr.rod_shape(s, e, n=100)
    assert rod.orthonormality <= 1e-12 and rod.field_consistency <= 1e-12
    br = mr.continue_branch(s, e, parameter="k2", steps=2, ds=0.05)
    assert br.success and br.max_residual <= 1e-12
    assert reversors(s) == []
    for step in (lambda: mr.homoclinic_orbit(s), lambda: mr.multipulse_orbits(s, 1)):
        with pytest.raises(mr.ParameterError) as exc:
            step()
        assert exc.value.name == "model" and "reversor" in str(exc.value) and "skew_rod.py" in str(exc.value)
    with pytest.raises(mr.ParameterError) as exc:
        mr.splitting(s)
    assert exc.value.name == "model" and "small parameter" in str(exc.value)


def test_a_model_file_with_a_rotated_reversor(skew_rod):
    """The same file at A1 = A2: an isotropic rod curved in the direction at atan(k2/k1) from d1.  Its reversor is the
    reflection of the body frame through the plane of d3 and the curvature (no diagonal one): found to rounding, and
    the symmetric homoclinic orbit to its straight rod shot onto its Fix(R) and continued in k2."""
    s = skew_rod.replace(A1=1, A2=1, k1=0.1, k2=0.05)
    (R,) = reversors(s)
    assert R.signs is None and R.residual <= 1e3 * EPS and R.codim == 2
    ang = math.atan2(0.05, 0.1)
    Rm = R.matrix
    assert abs(Rm[0, 0] - math.cos(2 * ang)) <= 1e-12 and abs(Rm[0, 1] - math.sin(2 * ang)) <= 1e-12
    o = mr.homoclinic_orbit(s)
    assert o.success and o.accuracy["passed"], o.message
    br = mr.continue_branch(s, o, parameter="k2", steps=1, ds=0.02)
    assert br.success and br.max_residual <= 1e-9


@pytest.mark.parametrize("model, kw, parameter, value0, harmonic", [
    ("anisotropic", dict(B1=1, B2=1.05, C=1.5), "B2", 1.0, 2),
    ("curved", dict(B=1, C=0.75, k1=0.05, k3=0.2), "k1", 0.0, 1)])
def test_melnikov_function_along_the_computed_orbit_is_the_closed_form(model, kw, parameter, value0, harmonic):
    """M(phi0) = int grad I . df/dp along the integrable member's computed homoclinic orbit family (hy.diff of the
    generated expressions, trapezoidal rule) has the closed form of model_splitting: c sin(k phi0), c the Mel'nikov
    coefficient per unit eps (B2 = B1 (1 + eps) with B1 = 1, k1 = eps)."""
    from magrod.separatrix import melnikov_along_orbit
    from magrod.separatrix.model_splitting import melnikov_unit

    s = mr.System(model, **kw)
    r = melnikov_along_orbit(s, parameter, value0)
    assert r.success and r.system == s and r.harmonic == harmonic, r.message
    rest = {k: v for k, v in kw.items() if k != parameter}
    c = melnikov_unit(model, rest, 1.0, 1.0)
    b = r.coefficients[2 * harmonic]  # the sin(k phi0) coefficient
    # measured 1.4e-12 (anisotropic: the integrand is O(delta^2) at the orbit's ends), 5.1e-7 (curved: O(delta),
    # the truncation delta / kappa)
    assert abs(b - c) <= 2e-6 * abs(c), (b, c)
    others = np.delete(r.coefficients, 2 * harmonic)
    assert np.max(np.abs(others)) <= 1e-6 * abs(c)
    assert abs(b - 1.01 * c) > 1e-3  # mutation: a 1 % error would be seen


def test_melnikov_function_names_what_is_missing():
    from magrod.separatrix import melnikov_along_orbit

    # the integrable control: the Kirchhoff rod's m3 survives every change of C, M vanishes to rounding
    r = melnikov_along_orbit(mr.System("kirchhoff", C=0.8), "C", 0.75)
    assert np.max(np.abs(r.M)) <= 1e-12

    with pytest.raises(mr.ParameterError) as exc:  # B2 = 1.5 != B1: m3 is no integral there
        melnikov_along_orbit(mr.System("anisotropic", B1=1, B2=1.6, C=1.5), "B2", 1.5)
    assert exc.value.name == "model" and "not an integral" in str(exc.value)
    with pytest.raises(mr.ParameterError) as exc:
        melnikov_along_orbit("4a", "lam", 0.0)
    assert exc.value.name == "model"
