"""Homoclinic orbit at lambdabar = 0 (sec. 6): closed form vs 256-bit integration, ODE residual, energy, parity,
Kirchhoff limit, bad input."""
import numpy as np
import pytest

from magrod import cli
from magrod.errors import ParameterError
from magrod.homoclinic import homoclinic, phase_portrait_energy, verify

EPS = np.finfo(float).eps


@pytest.mark.parametrize("m,gamma", [(1.7, 1.0), (1.7, 0.0), (2.2, 1.0), (1.0, 3.0)])
def test_closed_form_equals_integration(m, gamma):
    o = homoclinic(m, gamma)
    v = verify(o, theta_stop=1e-8, n=61)
    # the 256-bit integration from the turning point reproduces the float64 closed form to rounding
    assert v["max_dev_theta"] <= 1e-12 and v["max_dev_ptheta"] <= 1e-12
    # ... and the closed form at 256 bits to the integration tolerance; the Kirchhoff form (gamma = 0) contains
    # sqrt(2), which the generated code carries as a float64 constant, so there only ~eps agreement is possible
    assert v["max_dev_theta_generated_hp"] <= (1e-15 if gamma == 0 else 1e-40)
    assert v["max_abs_H0_minus_h"] <= 1e-40  # H0 constant along the orbit (h = (1 + gamma/2)/m^2)
    assert v["parity_theta"] <= 1e-30 and v["parity_ptheta"] <= 1e-30 and v["parity_psi"] <= 1e-30


def test_energy_of_closed_form_in_float64():
    o = homoclinic(1.7, 1.0)
    t = np.linspace(-25, 25, 2001)
    ev = o.evaluate(t)
    E = phase_portrait_energy(ev["theta"], ev["ptheta"], 1.7, 1.0)
    h = (1 + 0.5) / 1.7**2  # eq:eq_oscillator, homoclinic level
    assert np.max(np.abs(E - h)) <= 16 * EPS


def test_ode_residual_of_closed_form():
    """theta' = pbar_theta and pbar_theta' = -V'(theta) (eq:equivalent) by central differences."""
    o = homoclinic(1.7, 1.0)
    t = np.linspace(-6, 6, 97)
    dt = 1e-4
    a, b, c = o.evaluate(t - dt), o.evaluate(t), o.evaluate(t + dt)
    dth = (c["theta"] - a["theta"]) / (2 * dt)
    assert np.max(np.abs(dth - b["ptheta"])) <= 1e-7  # O(dt^2) truncation ~ 1e-8 * |theta'''|
    th, ct, st = b["theta"], np.cos(b["theta"]), np.sin(b["theta"])
    force = -(1 - ct) ** 2 / st**3 + (ct + 1) * st / 1.7**2  # eq:equivalent with gamma = 1
    dpt = (c["ptheta"] - a["ptheta"]) / (2 * dt)
    assert np.max(np.abs(dpt - force)) <= 1e-7


def test_kirchhoff_limit():
    t = np.linspace(-10, 10, 201)
    small = homoclinic(1.7, 1e-7).evaluate(t)["theta"]
    kir = homoclinic(1.7, 0.0).evaluate(t)["theta"]
    assert np.max(np.abs(small - kir)) <= 1e-5  # O(gamma)
    assert np.max(np.abs(small - kir)) > 0


def test_parity_float64():
    o = homoclinic(1.7, 1.0)
    t = np.linspace(0.1, 10, 50)
    p, n = o.evaluate(t), o.evaluate(-t)
    assert np.allclose(p["theta"], n["theta"], rtol=0, atol=4 * EPS)
    assert np.allclose(p["ptheta"], -n["ptheta"], rtol=0, atol=4 * EPS)
    assert np.all(p["ptheta"] < 0)  # theta decreases towards the saddle for t > 0


@pytest.mark.parametrize("m,gamma,name", [(3.0, 1.0, "m"), (1.7, -0.5, "gamma"), (float("nan"), 1.0, "m"),
                                          (0.0, 1.0, "m"), (2.0, 0.0, "m")])
def test_bad_input(m, gamma, name):
    with pytest.raises(ParameterError) as e:
        homoclinic(m, gamma)
    assert e.value.name == name


def test_cli_json(capsys):
    import json

    assert cli.main(["homoclinic", "--m", "1.7", "--gamma", "1", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    for k in ("u_plus", "u_minus", "k", "theta_max", "h", "m_c", "max_deviation_theta"):
        assert k in d
    assert 0 < d["k"] < 1  # derived; the paper prints k > 1 (docs/errata.md)
    assert d["max_deviation_theta"] <= 1e-12
