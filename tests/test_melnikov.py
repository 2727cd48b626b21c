"""magrod.separatrix.melnikov: quadrature of the Mel'nikov amplitude along the homoclinic orbit (paper sec. 7,
eq:Mel_ext), its error estimate, the exact-derivative identity of the derived integrand, and bad inputs."""
import json

import heyoka as hy
import numpy as np
import pytest

from magrod.separatrix import melnikov as M
from magrod.cli import main
from magrod.core.errors import ParameterError
from magrod.core.precision import Precision
from magrod.orbits.homoclinic import homoclinic

EPS = np.finfo(float).eps


@pytest.mark.parametrize("gamma", [0.0, 1.0, 1.9, 3.0])
def test_derived_amplitude_vanishes(gamma):
    """report entry melnikov_vanishes: A_derived = 0.  float64: |A| within its estimate (~eps * Int|F|);
    real128: the truncated integral equals 2 Phi(T) (exact primitive) to ~1e-32, and |A| <= |2 Phi(T)| + tail."""
    a = M.amplitude(1.7, gamma, "derived")
    assert abs(a.A) <= a.error
    assert a.error < 1e3 * EPS
    assert abs(a.checks["real128_minus_two_phi_T"]) < 1e-30
    assert abs(a.A_reference) <= abs(a.checks["two_phi_T_real128"]) + 1e-30
    assert abs(a.A_reference) <= a.tail_bound  # |2 Phi(T)| is itself O(theta(T))


def test_primitive_identity_along_the_orbit():
    """Int_{-T}^{T} F_derived dt = 2 Phi(T) at every T (not only in the limit): an O(1) quantity matched to
    rounding, so the quadrature and the generated primitive check each other."""
    for m, g in [(1.7, 1.0), (1.2, 0.4), (1.7, 0.0)]:
        pc = M.primitive_check(m, g, n=40)
        assert pc["max_abs_2phi"] > 0.1
        assert pc["max_abs_diff"] <= 64 * EPS


@pytest.mark.parametrize("gamma", [1.0, 1.8, 2.0])
def test_printed_amplitude_nonzero_and_converged(gamma):
    """Printed integrand: float64 and real128 quadratures agree within the stated error, A is far from 0.
    Also: halving the tail cut-off (theta(T) = 1e-10 instead of 1e-20) changes A by less than the tail bound."""
    a = M.amplitude(1.7, gamma, "printed")
    assert abs(a.A - a.A_reference) <= a.error
    assert a.error < 1e3 * EPS * abs(a.A)
    assert abs(a.A) > 1e6 * a.error
    b = M.amplitude(1.7, gamma, "printed", reference=False, theta_tail=1e-10)
    assert abs(b.A - a.A) <= b.tail_bound + a.error


def test_printed_is_minus_twice_the_first_bracket_term():
    """Because the derived integrand I1 - I2 integrates to zero, the printed one -(I1 + I2) integrates to
    -2 I1 = -2 I2 (I1, I2 the two terms of the bracket of eq:Mel_ext): independent numpy quadrature of
    I2 (Simpson on a fine grid, psibar by cumulative trapezoid) reproduces A_printed/(-2)."""
    from scipy.integrate import cumulative_trapezoid, simpson

    m, g = 1.7, 1.4
    o = homoclinic(m, g)
    t = np.linspace(0.0, o.time_at_theta(1e-14), 200001)
    e = o.evaluate(t)
    ps = cumulative_trapezoid(e["psidot"], t, initial=0.0)
    i2 = 2 * simpson(e["ptheta"] * np.sin(ps) * e["sin_theta"] ** 2 * (1 + g * e["cos_theta"]) / m**2, x=t)
    a = M.amplitude(m, g, "printed", reference=False)
    assert a.A == pytest.approx(-2 * i2, rel=1e-8)  # trapezoid psibar: O(dt^2) ~ 1e-9


def test_zero_search():
    """Printed integrand at m = 1.7: no sign change on [1.8, 2] (the paper reports one); A is positive and
    increasing on [0, 3].  Derived: zero within its bound at both ends (no isolated zero)."""
    zp = M.amplitude_zero(1.7, "printed", (1.8, 2.0))
    assert zp["found"] is False and min(zp["A_at_ends"]) > 1.0
    zd = M.amplitude_zero(1.7, "derived", (1.8, 2.0))
    assert zd["found"] is False and zd["zero_within_bound_at_ends"] is True
    a = [M.amplitude(1.7, g, "printed", reference=False).A for g in np.linspace(0, 3, 13)]
    assert np.all(np.diff(a) > 0) and a[0] > 0


def test_zero_search_finds_a_constructed_zero(monkeypatch):
    """The root finder itself on an amplitude with a known zero: A(gamma) replaced by A_printed(gamma) - A_printed(1.9)."""
    shift = M.amplitude(1.7, 1.9, "printed").A
    real = M.amplitude

    def fake(m, g, integrand="derived", **kw):
        a = real(m, g, integrand, **kw)
        ref = None if a.A_reference is None else a.A_reference - shift
        return M.Amplitude(a.m, a.gamma, a.integrand, a.A - shift, ref, a.quad_error, a.tail_bound, a.error,
                           a.T, a.theta_tail, a.wall_time_s, a.checks)

    monkeypatch.setattr(M, "amplitude", fake)
    z = M.amplitude_zero(1.7, "printed", (1.8, 2.0))
    assert z["found"] and abs(z["gamma_zero"] - 1.9) <= z["error_bound"] and z["error_bound"] < 1e-10
    assert z["sign_change_confirmed_real128"]


def test_melnikov_function_shape():
    a = M.amplitude(1.7, 1.2, "printed", reference=False)
    psi0 = np.linspace(0, 2 * np.pi, 9)
    assert np.allclose(M.melnikov_function(psi0, a), a.A * np.sin(psi0), rtol=0, atol=4 * EPS)


def test_quadrature_uses_heyoka_time():
    """The quadrature integrator is compiled once and reused (state/time/pars reset)."""
    assert M._quad_integrator() is M._quad_integrator()
    assert M._quad_integrator(Precision.QUAD) is M._quad_integrator(Precision.QUAD)
    assert M._quad_integrator(Precision.QUAD).state.dtype == np.dtype(hy.real128)


@pytest.mark.parametrize("m,gamma,integrand,name", [(3.0, 1.0, "derived", "m"), (1.7, -1.0, "printed", "gamma"),
                                                    (1.7, float("nan"), "derived", "gamma"), (0.0, 1.0, "derived", "m"),
                                                    (1.7, 1.0, "other", "integrand")])
def test_bad_inputs(m, gamma, integrand, name):
    with pytest.raises(ParameterError) as e:
        M.amplitude(m, gamma, integrand)
    assert e.value.name == name


def test_cli(capsys):
    assert main(["melnikov", "--m", "1.7", "--gamma", "1.2", "--integrand", "both", "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert "sin(psi0)" in r["convention"]
    p = r["amplitudes"]["printed"]
    assert abs(p["A"]) > 1 and p["error"] < 1e-12
    assert abs(r["amplitudes"]["derived"]["A"]) <= r["amplitudes"]["derived"]["error"]
    for argv in (["--m", "3", "--gamma", "1"], ["--m", "1.7", "--gamma", "-1"], ["--m", "inf", "--gamma", "1"],
                 ["--m", "1.7"], ["--m", "1.7", "--find-zero", "--bracket", "2", "1"]):
        assert main(["melnikov", *argv]) == 2
        assert "error" in capsys.readouterr().err


def test_figure_2(tmp_path):
    from magrod.figures.melnikov import figure_2

    paths = figure_2(tmp_path, quick=True)
    assert {p.rsplit(".", 1)[1] for p in paths} == {"png", "npz", "json"}
    meta = json.loads((tmp_path / "fig2.json").read_text())
    assert meta["scan_sign_changes"]["printed"] == 0
    d = np.load(tmp_path / "fig2.npz")
    assert np.all(np.abs(d["A_derived"]) <= d["A_error_derived"])
