"""The integrator layer (magrod.core.systems) and generated/ as the single source of the model's names."""
import dataclasses

import heyoka as hy
import numpy as np
import pytest

from magrod.core import systems
from magrod.generated import body, names, reduced, scalars
from magrod.core.params import RodParams

EPS = np.finfo(float).eps
P4A = RodParams(m=1.7, mu=0.4, gamma=3.0, delta=3.0, lam=0.135)


def test_rodparams_fields_are_generated_params():
    """RodParams is written by hand (validation, docs); its fields must be PARAMS in order."""
    assert tuple(f.name for f in dataclasses.fields(RodParams)) == names.PARAMS
    assert RodParams.from_array(P4A.array()) == P4A


def test_generated_modules_share_the_names():
    assert body.STATE == names.BODY_STATE and reduced.STATE == names.REDUCED_STATE
    assert len(body.pars()) == len(names.PARAMS) == len(systems.pars())
    assert [str(v) for v in systems.variables("body")] == list(names.BODY_STATE)
    assert tuple(systems.EVENTS["body"]) == names.BODY_EVENTS


def test_variational_blocks_match_finite_differences():
    """d x(T)/d x0 and d x(T)/d pars from hy.var_ode_sys against central differences of the plain integrator
    (step 1e-6: truncation ~1e-12, rounding ~eps/1e-6 ~ 1e-10 relative)."""
    x0 = systems.euler_to_body(0.7, 0.3, 0.2, 1.1, P4A.array())
    T = 2.0
    v = systems.variational_integrator("body")
    systems.reset_variational(v, x0, P4A.array())
    v.propagate_until(T)
    x, Phi, Psi = systems.variational_blocks(v)
    assert Phi.shape == (9, 9) and Psi.shape == (9, len(names.PARAMS))
    ta = systems.integrator("body")

    def flow(x_, p_):
        systems.reset(ta, x_, 0.0, p_)
        ta.propagate_until(T)
        return np.array(ta.state)

    np.testing.assert_allclose(x, flow(x0, P4A.array()), rtol=0, atol=1e-14)
    h = 1e-6
    for j in (0, 4, 8):
        e = np.zeros(9)
        e[j] = h
        fd = (flow(x0 + e, P4A.array()) - flow(x0 - e, P4A.array())) / (2 * h)
        np.testing.assert_allclose(Phi[:, j], fd, rtol=0, atol=1e-8 * max(1, np.max(np.abs(fd))))
    for name in names.PARAMS:
        k = systems.par_index(name)
        e = np.zeros(len(names.PARAMS))
        e[k] = h
        fd = (flow(x0, P4A.array() + e) - flow(x0, P4A.array() - e)) / (2 * h)
        np.testing.assert_allclose(Psi[:, k], fd, rtol=0, atol=1e-8 * max(1, np.max(np.abs(fd))))
    assert np.all(Psi[:, systems.par_index("mu")] == 0)  # mu enters only through the Casimir level, not the field


def test_batch_integrator_lanes_equal_scalar_runs():
    """Each SIMD lane of the batch integrator reproduces the scalar integrator to a few ulp of the state."""
    b = systems.recommended_batch_size()
    ta_b = systems.batch_integrator("body", batch_size=b)
    lams = np.linspace(0.1, 0.2, b)
    pars = np.array([P4A.replace(lam=lam).array() for lam in lams]).T
    x0 = np.array([systems.euler_to_body(0.5, 0.0, 0.3, 0.9, pars[:, i]) for i in range(b)]).T
    ta_b.set_time(0.0)
    ta_b.state[:] = x0
    ta_b.pars[:] = pars
    ta_b.propagate_until(5.0)
    ta = systems.integrator("body")
    for i in range(b):
        systems.reset(ta, x0[:, i], 0.0, pars[:, i])
        ta.propagate_until(5.0)
        np.testing.assert_allclose(ta_b.state[:, i], ta.state, rtol=0, atol=1e-13)


def test_named_events_land_on_their_surface():
    """A stopping section event puts the state on e31 n2 - e32 n1 = 0 to rounding, with the requested direction."""
    ta = systems.integrator("body", events=[("section", "positive")])
    x0 = systems.euler_to_body(0.5, 0.3, 0.3, 0.9, P4A.array())
    systems.reset(ta, x0, 0.0, P4A.array())
    f = systems.body_functions()
    k = names.BODY_EVENTS.index("section")
    for _ in range(5):
        oc = ta.propagate_until(1e4)[0]
        assert int(oc) == -1
        x = np.array(ta.state)
        assert abs(f["events"](x, P4A.array())[k]) <= 64 * EPS
        # direction "positive": d/dt of the event function > 0 at the crossing (central difference along f)
        fx = f["rhs"](x, P4A.array())
        h = 1e-6
        gdot = (f["events"](x + h * fx, P4A.array())[k] - f["events"](x - h * fx, P4A.array())[k]) / (2 * h)
        assert gdot > 0
        e = systems.body_to_euler(x, P4A.array())
        assert abs(np.sin(e[systems.chart_index("psi")])) <= 1e-12


def test_event_offset_and_unknown_event():
    ta = systems.integrator("body", events=[("sin2_theta", "negative", 0.25)])
    x0 = systems.euler_to_body(1.2, 0.0, -0.8, 0.9, P4A.array())
    systems.reset(ta, x0, 0.0, P4A.array())
    oc = ta.propagate_until(1e3)[0]
    assert int(oc) == -1  # theta decreases from 1.2 through asin(1/2): sin(theta)^2 = 0.25 from above, t ~ 1.26
    st = np.array(ta.state)
    i1, i2 = systems.state_index("body", "e31"), systems.state_index("body", "e32")
    assert abs(st[i1] ** 2 + st[i2] ** 2 - 0.25) <= 64 * EPS
    with pytest.raises(ValueError):
        systems.integrator("body", events=["no_such_event"])


def test_scalars_agree_with_heyoka_expressions():
    """The plain-float scalars (generated/scalars.py) equal the heyoka-expression versions of generated/."""
    from magrod.generated import homoclinic as gh

    m, g = 1.7, 1.3
    cf = hy.cfunc([gh.energy(hy.par[0], hy.par[1]), gh.m_critical(hy.par[1])], vars=[])
    h, mc = cf(np.zeros(0), pars=np.array([m, g]))
    assert scalars.homoclinic_energy(m, g) == pytest.approx(h, rel=4 * EPS)
    assert scalars.m_critical(g) == pytest.approx(mc, rel=4 * EPS)
    assert scalars.potential_dd0(m, g) < 0 < scalars.potential_dd0(1.01 * mc, g)
    x = np.array(scalars.straight_rod_state(*P4A.array()))
    p = P4A.replace(mu=scalars.straight_rod_mu(**P4A.to_dict()))
    f = systems.body_functions()
    assert np.all(f["rhs"](x, p.array()) == 0)  # an equilibrium
    cas = f["casimirs"](x, p.array()) - np.array(scalars.casimir_values(*p.array()))
    assert np.max(np.abs(cas)) <= 4 * EPS  # on the chart's level at mu = straight_rod_mu
    assert scalars.straight_rod_level_defect(*p.array()) == 0.0


def test_long_double_straight_rod_is_exact_in_extended_precision():
    from magrod.core.precision import Precision
    from magrod.orbits.equilibrium import straight_rod_state

    p = RodParams(m=1.7, mu=0.002, gamma=1.0, delta=1.0, lam=0.001)
    x = straight_rod_state(p, Precision.LONG_DOUBLE)
    assert x.dtype == np.longdouble and x[5] == np.longdouble(1) / np.longdouble(1.7) ** 2


def test_build_bypasses_a_failing_jit_cache(monkeypatch, capsys):
    """A constructor that fails while the disk cache is on (as with a damaged cache entry) is built again with the
    cache off, the cache is cleared (here: recorded, not done) and one MagrodWarning is issued (the CLI prints it
    as one stderr line)."""
    from magrod.core.errors import MagrodWarning

    cleared = []
    monkeypatch.setattr(hy.llvm_state, "clear_diskcache", lambda: cleared.append(True))
    was_on = hy.llvm_state.get_diskcache_enabled()
    hy.llvm_state.set_diskcache_enabled(True)
    try:
        def constructor(x):
            if hy.llvm_state.get_diskcache_enabled():
                raise RuntimeError("corrupted object code")
            return 2 * x

        with pytest.warns(MagrodWarning) as rec:
            assert systems.build(constructor, 21) == 42
        assert cleared == [True] and not hy.llvm_state.get_diskcache_enabled()
        assert len(rec) == 1 and "cache" in str(rec[0].message)

        def always_fails():
            raise ValueError("bad arguments")

        hy.llvm_state.set_diskcache_enabled(True)
        with pytest.raises(ValueError):
            systems.build(always_fails)
        assert hy.llvm_state.get_diskcache_enabled()  # not a cache problem: the cache stays on
    finally:
        hy.llvm_state.set_diskcache_enabled(was_on)
