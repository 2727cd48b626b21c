"""The periodic saddle for mu != 2 lam (magrod.orbits.periodic, derive/floquet.py): relative equilibrium, monodromy,
Floquet multipliers, Hamiltonian-Hopf boundary."""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from magrod.orbits import periodic as floquet
from magrod.core.errors import ParameterError
from magrod.generated import floquet as gfl
from magrod.core.params import RodParams
from magrod.orbits.equilibrium import straight_rod

EPS = np.finfo(float).eps
P = RodParams(1.7, 0.0021, 1.0, 1.0, 0.001)


@pytest.fixture(scope="module")
def ps():
    return floquet.periodic_saddle(P)


def test_relative_equilibrium_on_level_and_periodic(ps):
    assert ps.re_residual <= 64 * EPS
    assert ps.closure <= 1e3 * EPS  # x(T) = x: the orbit closes after T = 2 pi/|omega|
    th, psi, _, pth, _ = ps.chart
    assert th > 0 and abs(math.sin(psi)) <= 1e-12 and abs(pth) <= 1e-12  # an equilibrium of the chart on Fix(R)


def test_monodromy_is_exp_of_corotating_jacobian(ps):
    # independent: M = exp(T (Df - omega xi)) because Phi_t(x0) = G_{omega t} x0
    assert ps.exp_check <= 1e3 * EPS


def test_multipliers_reciprocal_and_symplectic(ps):
    assert ps.hyperbolic
    q = ps.quartet
    assert abs(q[0]) > 1
    # double-precision monodromy: the small multipliers carry a relative error ~ eps |Lambda|^2 (= 9.5e-13 here).
    # That floor is the bound: the product test sits at it on every BLAS kernel (8.1e-13 with OpenBLAS's Haswell
    # kernel, 1.05e-12 with Sandybridge's; issue 24), so a fixed 1e-12 was a statement about one kernel's rounding.
    # The kernel-independent check of the pairing is the backward monodromy below.
    assert ps.reciprocal_defect <= 16 * EPS * abs(q[0]) ** 2
    # the backward monodromy M^-1 (integrated independently) has the same spectrum (= R M R by reversibility)
    assert floquet.reciprocal_defect_backward(ps) <= 64 * EPS
    # five multipliers 1: three Casimirs, the G-direction (= flow direction) and the conserved m3
    ones = np.sort(np.abs(ps.multipliers - 1))[:5]
    assert np.all(ones <= 1e-8)  # a Jordan block at 1 splits like sqrt(eps)
    assert ps.symplectic_defect <= 64 * EPS  # M J M^T = J: a Poisson map, symplectic on the leaf


def test_exponents_match_derived_reduced_linearisation(ps):
    b, c = gfl.reduced_bc(ps.chart[0], ps.chart[4], *P.array())
    s_derived = np.sqrt(np.roots([1, b, c]).astype(complex))
    num = ps.exponents[np.argsort(-np.abs(ps.exponents.real))][:4]
    # the chart is nearly singular at theta_eq ~ 0.01: b, c cancel 1/sin^4 terms, error ~ eps/theta^4
    tol = 16 * EPS / ps.chart[0] ** 4
    for z in s_derived:
        assert np.min(np.abs(num - z)) <= tol * abs(z)
    # multipliers are exp(T * exponents)
    for z in s_derived:
        mu_ = np.exp(ps.T * z)
        assert np.min(np.abs(ps.multipliers - mu_)) <= ps.T * tol * abs(z) * abs(mu_)


def test_limit_mu_to_2lam_is_the_straight_rod():
    p0 = RodParams(1.7, 0.002, 1.0, 1.0, 0.001)
    s = straight_rod(p0)
    ps = floquet.periodic_saddle(RodParams(1.7, 0.002 + 1e-10, 1.0, 1.0, 0.001))
    w = np.max(s.eigenvalues.imag[np.abs(s.eigenvalues.real) < 1e-8])
    assert abs(abs(ps.omega) - w) <= 1e-6
    a = s.unstable_eigenvalue
    # co-rotating exponents: a +- i (b - w) (the quartet has G-weight 1); same multipliers, since T w = 2 pi
    assert np.min(np.abs(ps.exponents - complex(a.real, a.imag - w))) <= 1e-6
    assert np.min(np.abs(ps.multipliers - np.exp(ps.T * a))) <= 1e-5 * abs(np.exp(ps.T * a))
    assert ps.chart[0] <= 2e-5  # theta_eq ~ sqrt(mu - 2 lam)


def test_straight_rod_cubic_matches_jacobian():
    p = RodParams(1.7, 0.002, 1.0, 1.0, 0.001)
    sig = np.roots([1, *gfl.straight_rod_cubic(p.m, p.gamma, p.delta, p.lam)])
    ev = straight_rod(p).eigenvalues
    for z in np.sqrt(sig.astype(complex)):
        assert np.min(np.abs(ev - z)) <= 1e-10
    assert gfl.straight_rod_discriminant(p.m, p.gamma, p.delta, p.lam) < 0  # saddle-focus


def test_hamiltonian_hopf_boundary_derived_vs_numerics():
    g, d, lam = 1.0, 1.0, 0.001
    disc = lambda m: gfl.straight_rod_discriminant(m, g, d, lam)  # noqa: E731
    m_hh = brentq(disc, 2.0, 3.5, xtol=1e-14)
    # lam -> 0: the boundary is m_c = 2 sqrt(1 + gamma) (eq:buckling_load_2)
    assert abs(brentq(lambda m: gfl.straight_rod_discriminant(m, g, d, 1e-9), 2.5, 3.2) - 2 * math.sqrt(2)) <= 1e-6
    # numerics: the straight rod is a saddle-focus just below m_hh and not hyperbolic just above
    assert straight_rod(RodParams(m_hh - 1e-3, 2 * lam, g, d, lam)).unstable_eigenvalue.real > 1e-3
    with pytest.raises(ParameterError):
        straight_rod(RodParams(m_hh + 1e-3, 2 * lam, g, d, lam))
    # the periodic saddle close to mu = 2 lam follows the same boundary
    scan = floquet.hamiltonian_hopf_scan(RodParams(1.7, 2 * lam + 1e-8, g, d, lam), "m",
                                         [m_hh - 2e-3, m_hh + 2e-3])
    assert scan["growth"][0] > 1e-3 and scan["growth"][1] <= floquet.HYPERBOLIC_TOL


def test_bad_input():
    with pytest.raises(ParameterError, match="mu"):
        floquet.periodic_saddle(RodParams(1.7, 0.0019, 1.0, 1.0, 0.001))
    with pytest.raises(ParameterError, match="m"):
        floquet.periodic_saddle(RodParams(3.0, 0.0021, 1.0, 1.0, 0.001))
