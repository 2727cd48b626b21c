"""One table of limits (magrod/core/limits.py), one wording, whatever the path: the functions behind the face check
their inputs as the face and the command line do.  Each probe below returned a result or raised a bare Python
error before the check was added (seen to fail: body_indicators(t_max=-1) returned an Indicators, renorm_dt=0 a
ZeroDivisionError, scaled_params(eps=1e-300) a RodParams with mu = lambdabar = 0, periodic_multipulse.find with
samples=0 an empty list)."""
from __future__ import annotations

import numpy as np
import pytest

import magrod as mr
from magrod.core.limits import LIMITS, integer, positive


def _start():
    from magrod.chaos.section import section_start
    from magrod.core import systems

    st = section_start("4a")
    pars = st.params.array()
    return systems.euler_to_body(st.theta0, st.psi0, st.ptheta0, st.p_psi0, pars), pars


@pytest.mark.parametrize("kw, name", [({"t_max": -1.0}, "t_max"), ({"t_max": 0.0}, "t_max"),
                                      ({"t_max": float("nan")}, "t_max"), ({"t_max": 10.0, "renorm_dt": 0.0},
                                                                          "renorm_dt"),
                                      ({"t_max": 10.0, "renorm_dt": -1.0}, "renorm_dt")])
def test_body_indicators_checks_its_times(kw, name):
    from magrod.chaos.indicators import body_indicators

    x0, pars = _start()
    with pytest.raises(mr.ParameterError) as e:
        body_indicators(x0, pars, **kw)
    assert e.value.name == name and "> 0" in e.value.message


def test_body_indicators_still_runs_with_good_times():
    from magrod.chaos.indicators import body_indicators

    x0, pars = _start()
    ind = body_indicators(x0, pars, t_max=20.0)
    assert np.all(np.isfinite(ind.fli))


@pytest.mark.parametrize("eps, words", [(1e-300, "underflows"), (1e-160, "underflows"), (0.0, "(0, 1]"),
                                        (float("nan"), "finite"), (2.0, "(0, 1]")])
def test_scaled_params_refuses_an_eps_whose_parameters_underflow(eps, words):
    from magrod.separatrix.splitting import scaled_params

    with pytest.raises(mr.ParameterError) as e:
        scaled_params(1.7, 1.0, 1.0, 4.0, 1.0, eps)
    assert e.value.name == "eps" and words in e.value.message, e.value.message
    p = scaled_params(1.7, 1.0, 1.0, 4.0, 1.0, 1e-3)  # a small eps that is representable: as before
    assert p.lam == 1e-3 ** 2 and p.mu == 4.0 * 1e-3 ** 2


@pytest.mark.parametrize("samples", [0, 2, -5, 2.5, LIMITS["samples"] + 1])
def test_periodic_multipulse_find_checks_samples_as_the_face_does(samples):
    """The same limit and wording as multipulse_orbits(samples=...) and `magrod multipulse --samples`."""
    from magrod.orbits import periodic_multipulse as pm

    with pytest.raises(mr.ParameterError) as e:
        pm.find(mr.RodParams(1.7, 0.0021, 1.0, 1.0, 0.001), 1, samples=samples)
    with pytest.raises(mr.ParameterError) as f:
        integer("samples", samples, minimum=3)
    assert e.value.name == "samples" and str(e.value) == str(f.value)


def test_positive_uses_the_table_and_one_wording():
    assert positive("t_max", "3e3") == 3000.0
    with pytest.raises(mr.ParameterError) as e:
        positive("renorm_dt", "abc")
    assert e.value.name == "renorm_dt" and "number" in e.value.message
    with pytest.raises(mr.ParameterError) as e:
        positive("iterates", LIMITS["iterates"] + 1)
    assert e.value.name == "iterates" and f"{LIMITS['iterates']:g}" in e.value.message


@pytest.mark.parametrize("iterates", [LIMITS["iterates"] + 1, 0, "100", 2.5, True])
def test_iterates_one_limit_one_wording_on_every_path(iterates):
    """poincare_section(iterates=...) said "<= 2000000 (the limit of what a run can finish ...)" for the paper's rod
    and, with model=, accepted up to 1e7 with "an integer in [1, 1e7]"; now the same check on both paths, the
    command line's."""
    errors = []
    for call in (lambda: mr.poincare_section("4a", iterates=iterates),
                 lambda: mr.poincare_section(model="anisotropic", iterates=iterates)):
        with pytest.raises(mr.ParameterError) as e:
            call()
        errors.append(str(e.value))
    assert errors[0] == errors[1] and errors[0].startswith("iterates:"), errors
    if iterates == LIMITS["iterates"] + 1:
        with pytest.raises(mr.ParameterError) as e:
            integer("iterates", str(iterates))
        assert errors[0].replace(repr(iterates), "X") == str(e.value).replace(repr(str(iterates)), "X")
