"""One calling convention on the public face (issue 25, item 4): the system first (a RodParams, a panel name or a
Panel), model parameters overridden by keyword, the same limits and type checks as the command line, and scipy's
`status` next to `success` and `message`."""
import numpy as np
import pytest

import magrod as mr
from magrod.cli.options import LIMITS as CLI_LIMITS
from magrod.core.limits import LIMITS
from magrod.core.printed import with_overrides


def test_keyword_overrides_equal_the_explicit_rod():
    """poincare_section("4a", lam=0.15) is Fig 4(a)'s start on the rod with lambdabar = 0.15: bit for bit the run
    with that RodParams and the panel's start, and its panel says it is not the paper's."""
    P = mr.panel("4a")
    a = mr.poincare_section("4a", iterates=30, lam=0.15)
    b = mr.poincare_section(P.params.replace(lam=0.15), P.h, P.theta0, P.ptheta0, P.psi0, iterates=30)
    assert a.params == b.params and a.params.lam == 0.15
    np.testing.assert_array_equal(a.body_points, b.body_points)
    assert a.panel == "4a, lam=0.15" and a.panel != P.key
    many = mr.poincare_section(["4a", "4b"], iterates=10, gamma=2.5)
    assert [r.params.gamma for r in many] == [2.5, 2.5]
    ly = mr.lyapunov("4a", t_max=200, lam=0.15)
    assert ly.params.lam == 0.15


def test_an_unknown_keyword_names_itself():
    with pytest.raises(mr.ParameterError) as e:
        mr.poincare_section("4a", iterates=10, lamb=0.15)
    assert e.value.name == "lamb"
    with pytest.raises(mr.ParameterError) as e:
        mr.lyapunov("4a", t_max=100, gama=1.0)
    assert e.value.name == "gama"
    with pytest.raises(mr.ParameterError) as e:
        with_overrides(3.0, {"lam": 0.1})
    assert e.value.name == "params"


@pytest.mark.parametrize("field", ["m", "mu", "gamma", "delta", "lam"])
def test_rod_parameters_must_be_numbers_not_strings(field):
    kw = dict(m=1.7, mu=0.4, gamma=3.0, delta=3.0, lam=0.135)
    kw[field] = str(kw[field])
    with pytest.raises(mr.ParameterError) as e:
        mr.RodParams(**kw)
    assert e.value.name == field and "string" in e.value.message


def test_the_library_and_the_command_line_share_their_limits():
    assert CLI_LIMITS is LIMITS
    with pytest.raises(mr.ParameterError) as e:
        mr.poincare_section("4a", iterates=LIMITS["iterates"] + 1)
    assert e.value.name == "iterates" and str(LIMITS["iterates"]) in e.value.message


def test_status_next_to_success():
    """0 on success, 1 on failure: a Newton run given no iteration does not converge."""
    from magrod.orbits import multipulse

    ok = mr.poincare_section("4a", iterates=10)
    assert ok.success and ok.status == 0
    lam = 0.00126208079543  # docs/errata.md: the Fig 6 two-pulse lam*
    bad = multipulse.shoot(mr.RodParams(1.7, 2 * lam, 1.0, 1.0, lam), 2, max_iter=0, tol=1e-300)
    assert not bad.success and bad.status == 1
