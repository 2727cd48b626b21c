"""magrod.proof.taylor_model: the validated integrator with a Taylor-model (Picard-Schauder) remainder.

References: closed-form flows evaluated in ball arithmetic (x' = sin x, y' = sqrt y, z' = 1/z: every nonlinearity the
generated field uses), a heyoka real128 trajectory of the rod's chart field, and the present integrator
(taylor.py), whose enclosures must meet these wherever both apply.  Controls: a mutated field is not contained, a
step past a blow-up is not validated."""
from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from flint import arb

from magrod.proof import ball, fields, section_return, taylor, taylor_model

PREC = 128
X0 = (Fraction(1, 2), Fraction(1), Fraction(3, 4))
RAD = Fraction(1, 10**6)


def _closed_form_field(k=1):
    """(x, y, z)' = (k sin x, sqrt y, 1/z), k = 1 the field with the closed forms below (k != 1: a mutation)."""
    kb = ball.q(k)

    def rhs(x, p):
        return [kb * x[0].sin(), x[1].sqrt(), 1 / x[2]]

    def jac(x, p):
        z = arb(0) * x[0]
        return [kb * x[0].cos(), z, z, z, 1 / (2 * x[1].sqrt()), z, z, z, -1 / (x[2] * x[2])]

    return taylor.Field(rhs, jac, 3, (), "closed-form", series="newton")


def _exact(x0, t):
    """The flow and its (diagonal) derivative: tan(x/2) = tan(x0/2) e^t, y = (sqrt y0 + t/2)^2, z = sqrt(z0^2 + 2t);
    dx/dx0 = sin x / sin x0 (f(x(t)) / f(x0) for a scalar autonomous field), likewise for y and z."""
    x0 = [ball.q(v) for v in x0]
    t = ball.q(t)
    x = 2 * ((x0[0] / 2).tan() * t.exp()).atan()
    y = (x0[1].sqrt() + t / 2) ** 2
    z = (x0[2] * x0[2] + 2 * t).sqrt()
    return [x, y, z], [x.sin() / x0[0].sin(), y.sqrt() / x0[1].sqrt(), x0[2] / z]


def _fly(fld, integrator, T=Fraction(1), c1=True, **kw):
    with ball.workprec(PREC):
        S = taylor.initial_set([ball.q(v) for v in X0], radii=[RAD] * 3, c1=c1)
        return integrator.propagate(fld, S, T, order=12, tol=1e-22, **kw)


def test_closed_form_flow_and_derivative_lie_in_the_enclosure():
    """The centre's and two corners' exact flows at t = 1 lie in the C^1 set; the exact DPhi of the centre lies in
    the derivative enclosure; the present integrator's enclosure meets it component by component."""
    fld = _closed_form_field()
    S = _fly(fld, taylor_model)
    S_old = _fly(fld, taylor)
    with ball.workprec(PREC):
        hull, old, W = S.hull(), S_old.hull(), S.W()
        for d in (0, 1, -1):
            xt, dx = _exact([v + d * RAD for v in X0], 1)
            assert all(h.contains(v) for h, v in zip(hull, xt)), (d, hull, xt)
        for i in range(3):
            for j in range(3):
                assert W[i, j].contains(dx[i] if i == j else arb(0)), (i, j, W[i, j])
            assert hull[i].overlaps(old[i])
    print("\nwidths at t = 1 (box 1e-6): taylor_model", S.widths(), "taylor", S_old.widths())


def test_mutated_field_is_not_contained():
    """The control: sin x scaled by 1 + 1e-6 moves x(1) by ~1e-6 x0-widths; the enclosure then misses the exact flow."""
    S = _fly(_closed_form_field(1 + Fraction(1, 10**5)), taylor_model, c1=False)
    with ball.workprec(PREC):
        xt, _ = _exact(X0, 1)
        assert not S.hull()[0].contains(xt[0])
        assert S.hull()[1].contains(xt[1])  # the unmutated components are still contained


def test_a_step_past_a_blow_up_is_not_validated():
    """x' = 1 + x^2 from 0 is tan t (blow-up at pi/2): a step of 2 must fail; a step of 1/4 validates and
    contains tan(1/4)."""
    def rhs(x, p):
        return [1 + x[0] * x[0]]

    def jac(x, p):
        return [2 * x[0]]

    fld = taylor.Field(rhs, jac, 1, (), "tan", series="newton")
    with ball.workprec(PREC):
        S = taylor.initial_set([arb(0)])
        with pytest.raises(taylor.EnclosureError):
            taylor_model.step(fld, S, Fraction(2), 12)
        S1 = taylor_model.step(fld, S, Fraction(1, 4), 12)
        assert S1.hull()[0].contains(ball.q(Fraction(1, 4)).tan())
        assert S1.W()[0, 0].contains(1 + ball.q(Fraction(1, 4)).tan() ** 2)
        # extra = 0: the whole tail is the Lagrange coefficient over [0, h] (order 4, h = 1/2: ~1e-3 of tan)
        S2 = taylor_model.step(fld, S, Fraction(1, 2), 4, extra=0)
        assert S2.hull()[0].contains(ball.q(Fraction(1, 2)).tan())
        assert S2.W()[0, 0].contains(1 + ball.q(Fraction(1, 2)).tan() ** 2)


def test_heyoka_quad_trajectory_lies_in_the_chart_enclosure():
    """The rod's chart field at the target parameters: a box of radius 1e-25 about an exact dyadic start flown
    by the Taylor-model integrator; heyoka's real128 trajectory from its centre lies inside at every step."""
    import heyoka as hy

    from magrod.core import systems

    p = fields.ExactParams.from_values(m="1.7", mu="0.04", gamma=1, delta=1, lam="0.01")
    fp = hy.real128
    q0 = [0.1433, 0.0004, -0.0002, 0.99]
    pars = [fp(Fraction(v).numerator) / fp(Fraction(v).denominator) for v in p.as_json().values()]
    ta = systems.taylor(systems.system("reduced"), np.array([fp(v) for v in q0]), np.array(pars), fp_type=fp)
    rec = taylor.Trajectory()
    fld = fields.chart_field(p)
    fld.series = "newton"
    with ball.workprec(PREC):
        S = taylor.initial_set([ball.dyadic(v) for v in q0], radii=[Fraction(1, 10**25)] * 4, c1=False)
        S = taylor_model.propagate(fld, S, 2, order=20, tol=1e-28, record=rec)
    grid = np.array([fp(0)] + [fp(float(t)) for t in rec.times])
    states = ta.propagate_grid(grid)[-1][1:]
    with ball.workprec(PREC):
        S = taylor.initial_set([ball.dyadic(v) for v in q0], radii=[Fraction(1, 10**25)] * 4, c1=False)
        for h, row in zip(rec.steps, states):
            S = taylor_model.step(fld, S, h, 20)
            for v, hv in zip(S.hull(), row):
                assert v.contains(ball.q(Fraction(str(hv)))), (float(S.t), v, hv)
    print(f"\nchart, heyoka quad inside: {len(rec.steps)} steps, widths at t = 2 {S.widths()}")


def test_fig4b_centre_return_agrees_with_the_present_integrator():
    """One return of Fig 4(b)'s saddle x0 (the benchmark's flight), both integrators at tol 1e-25 with the
    certificate's x0 (fixed_point_fig4b.json): the enclosures of P(x0) meet, and the Taylor-model one is the
    narrower (benchmarks/centre_flight_frontier.py: ~1e4 x at this tolerance)."""
    import json
    from importlib import resources

    from magrod.proof.provers.horseshoe_design import dyadic
    from magrod.proof.provers.section_horseshoe import t_approach

    c = json.loads(resources.files("magrod.proof").joinpath("certificates", "fixed_point_fig4b.json").read_text())
    p = fields.ExactParams(**{k: Fraction(v) for k, v in c["params"].items()})
    th = Fraction(c["newton"]["mid"])
    pc = dyadic(float(Fraction(c["point"]["level_newton"]["centre"]["mid"])), 60)
    t_a = t_approach(c["float"]["half_time"] * 2, Fraction(1, 256))
    out = {}
    with ball.workprec(PREC):
        fld = fields.chart_field(p)
        fld.series = "newton"
        for integ in (taylor, taylor_model):
            out[integ.__name__] = section_return.piece_return(
                fld.pars, Fraction(c["level"]), fld, [th, Fraction(0)], [[0, 0], [0, 0]], pc, Fraction(1, 10**8),
                t_a, Fraction(1, 256), order=20, tol=1e-25, box=False, thin_c1=False, integrator=integ)["Pc"]
        new, old = out["magrod.proof.taylor_model"], out["magrod.proof.taylor"]
        assert all(a.overlaps(b) for a, b in zip(new, old))
        assert max(float(v.rad()) for v in new) < max(float(v.rad()) for v in old)
    print("\nP(x0) radii at tol 1e-25: taylor_model", [float(v.rad()) for v in new],
          "taylor", [float(v.rad()) for v in old])


def test_thin_coarse_flight_contains_the_exact_flow():
    """A point (no box to hide in) flown at a coarse tolerance (order 8, tol 1e-10): the truncation error is the
    whole width, and the exact flow at t = 2 still lies inside; the enclosure is at most ~1e3 x the tolerance."""
    fld = _closed_form_field()
    with ball.workprec(PREC):
        S = taylor.initial_set([ball.q(v) for v in X0], c1=False)
        S = taylor_model.propagate(fld, S, 2, order=8, tol=1e-10)
        xt, _ = _exact(X0, 2)
        assert all(h.contains(v) for h, v in zip(S.hull(), xt)), (S.hull(), xt)
        assert 0 < max(S.widths()) < 1e-7


def test_rod_c1_enclosures_meet_the_present_integrators():
    """The rod's chart field (Fig 4(a)'s parameters), a box of radius 1e-10 flown C^1 to t = 1/2 by both
    integrators with the same exact steps: the state and DPhi enclosures meet entry by entry (both are rigorous, so
    a disjoint pair would expose a bug in one of them), and the Taylor-model DPhi is no wider than twice today's."""
    p = fields.ExactParams.from_values(m="1.7", mu="0.4", gamma=3, delta=3, lam="0.135")
    fld = fields.chart_field(p)
    fld.series = "newton"
    x0 = [ball.q(v) for v in (Fraction(383, 1000), Fraction(1, 64), Fraction(1, 100), Fraction(1117, 1000))]
    rec = taylor.Trajectory()
    with ball.workprec(PREC):
        S0 = taylor.initial_set(x0, radii=[Fraction(1, 10**10)] * 4)
        old = taylor.propagate(fld, S0, Fraction(1, 2), order=20, tol=1e-25, record=rec)
        new = taylor_model.propagate(fld, S0, steps=rec.steps, order=20)
        assert all(a.overlaps(b) for a, b in zip(new.hull(), old.hull()))
        Wn, Wo = ball.entries(new.W()), ball.entries(old.W())
        assert all(a.overlaps(b) for a, b in zip(Wn, Wo))
        assert max(float(v.rad()) for v in Wn) <= 2 * max(float(v.rad()) for v in Wo)
    print(f"\nrod C^1 to t = 1/2, {len(rec.steps)} steps: DPhi radius taylor_model "
          f"{max(float(v.rad()) for v in Wn):.3e}, taylor {max(float(v.rad()) for v in Wo):.3e}")


def test_taylor_model_and_section_return_import_no_prover():
    """The trust base's fence (docs/nonintegrability.md, "The verifier's trust base"): taylor_model imports from
    magrod only ball, taylor and the tolerances; section_return, which the verifier flies through, adds fields,
    taylor_model and the generated fields, never a prover (seen to fail: with `from .provers import section_horseshoe` added to
    taylor_model the first assertion fails)."""
    import ast
    from pathlib import Path

    def relative_imports(mod):
        got = set()
        for node in ast.walk(ast.parse(Path(mod.__file__).read_text())):
            if isinstance(node, ast.ImportFrom) and node.level > 0:
                got |= {f"{node.module}.{a.name}".strip(".") if node.module else a.name for a in node.names}
        return got

    assert relative_imports(taylor_model) == {"ball", "taylor", "core.tolerances.PROOF_STEP_TOL"}
    allowed = {"ball", "fields", "taylor", "taylor_model", "generated.validated", "core.tolerances.PROOF_STEP_TOL"}
    assert relative_imports(section_return) <= allowed, relative_imports(section_return)
