"""Rod shape: straight rod centreline (closed form) and frame orthonormality on a computed orbit."""
import numpy as np
import pytest

from magrod.orbits import rod
from magrod.core.params import RodParams
from magrod.orbits.equilibrium import straight_rod_state

EPS = np.finfo(float).eps


@pytest.mark.parametrize("gamma,delta", [(1.0, 1.0), (0.01, 0.01), (0.0, 0.0)])
def test_straight_rod_centreline(gamma, delta):
    p = RodParams(m=1.7, mu=0.002, gamma=gamma, delta=delta, lam=0.001)
    s = np.linspace(0.0, 20.0, 41)
    r = rod.reconstruct(straight_rod_state(p), p.array(), s, D0=np.eye(3))
    # v3 = 1 + n3/K with n3 = 1/m^2 and 1/K = (gamma + delta) m^2 at this scale: r(s) = (0, 0, (1 + gamma + delta) s)
    v3 = 1 + gamma + delta
    np.testing.assert_allclose(r["r"][:, 2], v3 * s, rtol=0, atol=64 * EPS * v3 * s[-1])
    assert np.max(np.abs(r["r"][:, :2])) == 0.0
    assert r["orthonormality"] <= 16 * EPS


def test_frame_orthonormal_on_multipulse_orbit(tmp_path):
    from magrod.orbits import multipulse

    p = RodParams(1.7, 0.0025, 1.0, 1.0, 0.00125)
    res = multipulse.shoot(p, 2)
    assert res.success
    s = np.linspace(0.0, 2 * res.T, 2001)
    r = rod.reconstruct(res.x0, res.params.array(), s)
    assert r["orthonormality"] <= 1e-12
    assert r["det"] <= 1e-12
    # the frame's third row is e3 in body components (integrated independently by the state equations)
    assert r["field_consistency"] <= 1e-12
    # |r'| = |v|: the centreline is longer than s by the axial strain (extensible rod)
    assert r["r"][-1, 2] > 0


def test_rod_cli_bad_file(tmp_path):
    from magrod.cli import main

    assert main(["rod", "--from", str(tmp_path / "missing.npz")]) == 2


def test_magnification_of_a_localised_bump():
    """A straight segment of length 100 along z with a transverse bump of height 0.3: the chord is z, the
    transverse part is the bump, and the 1-2-5 factor is the largest one <= 100 / (4 * 0.3) = 83.3, i.e. 50."""
    from magrod.figures.rod import magnification

    z = np.linspace(0.0, 100.0, 2001)
    r = np.column_stack([0.3 * np.exp(-((z - 50.0) / 5.0) ** 2), np.zeros_like(z), z])
    M, u, perp = magnification(r)
    assert M == 50.0
    assert np.allclose(u, [0.0, 0.0, 1.0], atol=1e-12)
    assert abs(np.max(np.linalg.norm(perp, axis=1)) - 0.3) <= 1e-3  # exp(-(z-50)^2/25) at the nearest grid point
    assert magnification(np.column_stack([np.zeros(3), np.zeros(3), [0.0, 1.0, 2.0]]))[0] == 1.0
