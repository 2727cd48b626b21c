"""The structure the proofs use, checked by the verifier at run time (magrod/proof/identities.py): reversibility
under R = diag(1, -1, -1, 1), the Hamiltonian form f = J grad Hbar (det DP = 1), and chart_jacobian = Df, each an
exact rational-function identity on the generated field's source.

Controls: a sign flipped in chart_rhs, chart_hamiltonian or chart_jacobian (fields.mutated_module), and a field made
non-reversible by hand, must each fail the identity they break, by name, and a shipped certificate verified against
such a field must be rejected at that identity (before its digest and before any flight: < 1 s each).  Seen to fail:
with identities.REVERSOR = (1, 1, -1, 1) the installed field fails reversibility and the first test fails."""
from __future__ import annotations

import copy
import json
import types
from importlib import resources

import pytest

from magrod.proof import fields, identities, verify


def _shipped(name):
    return json.loads(resources.files("magrod.proof").joinpath("certificates", name).read_text())


def _check(module=fields.gen) -> dict:
    return {name: (holds, how) for name, holds, how in identities.check(fields.source(module), fields.PARAMS)}


def _module(old: str, new: str):
    """A copy of the generated module with `old` replaced by `new` once (a control, as fields.mutated_module)."""
    src = fields.source()
    assert src.count(old) >= 1, old
    mod = types.ModuleType("magrod.generated.validated_control")
    mod.SOURCE = src.replace(old, new, 1)
    exec(compile(mod.SOURCE, "<control>", "exec"), mod.__dict__)  # noqa: S102 - the package's own source
    return mod


def test_the_installed_field_has_the_structure_the_proofs_use():
    got = _check()
    assert list(got) == list(identities.NAMES)
    assert all(holds for holds, _ in got.values()), {k: v[1] for k, v in got.items() if not v[0]}
    assert "exact identity" in got[identities.HAMILTONIAN][1]


@pytest.mark.parametrize("function, broken", [
    ("chart_rhs", {identities.HAMILTONIAN, identities.VARIATIONAL}),
    ("chart_hamiltonian", {identities.HAMILTONIAN}),
    ("chart_jacobian", {identities.VARIATIONAL}),
])
def test_a_flipped_sign_breaks_the_identity_it_touches(function, broken):
    # term 1: the first ' + ' of the function's code (term 0 of chart_jacobian is in its docstring)
    got = _check(fields.mutated_module(1, function))
    assert {k for k, (holds, _) in got.items() if not holds} == broken, got
    assert all("nonzero in component" in got[k][1] for k in broken)


def test_a_field_that_is_not_reversible_fails_reversibility():
    # theta' = pbar_theta + pbar_psi: odd and even parts mixed (f_theta(R x) != f_theta(x))
    got = _check(_module("    return [\n        ptheta,\n", "    return [\n        ptheta + ppsi,\n"))
    assert not got[identities.REVERSIBLE][0] and "['theta']" in got[identities.REVERSIBLE][1]
    assert got[identities.LEVEL_SYMMETRIC][0]


def test_what_the_exact_evaluation_cannot_represent_fails_every_identity_by_name():
    # another radical: the check cannot cover it and says so
    got = _check(_module("_c12 = ((((-_c11)).sqrt()))", "_c12 = ((((-_c11 + ppsi)).sqrt()))"))
    assert not any(holds for holds, _ in got.values())
    assert all("a square root of other than mu - 2 lambdabar pbar_psi" in how for _, how in got.values())
    # an angle used other than through sin and cos
    got = _check(_module("_c2 = (theta).sin()", "_c2 = (theta * 2).sin()"))
    assert not any(holds for holds, _ in got.values()) and "not evaluable exactly" in got[identities.REVERSIBLE][1]


@pytest.mark.parametrize("name", ["fixed_point_fig4a.json", "horseshoe_fig4a.json", "homoclinic_target.json"])
def test_the_verifier_rejects_a_mutated_field_at_the_identity(name):
    cert = _shipped(name)
    bad = verify.verify(cert, module=fields.mutated_module(1, "chart_jacobian"))
    assert not bad.ok and bad.reason.startswith(f"certificate rejected: {identities.VARIATIONAL} failed"), bad.reason
    rev = verify.verify(cert, module=_module("    return [\n        ptheta,\n", "    return [\n        ptheta + ppsi,\n"))
    assert not rev.ok and f"{identities.REVERSIBLE} failed" in rev.reason, rev.reason


def test_every_kind_checks_the_identities_before_the_digest():
    """A certificate whose digest is tampered is rejected at the digest, after the four identities held."""
    for name in ("fixed_point_fig4a.json", "horseshoe_fig4a.json", "homoclinic_target.json"):
        cert = copy.deepcopy(_shipped(name))
        cert["field_digest"] = "0" * 64
        res = verify.verify(cert)
        assert not res.ok and "field digest failed" in res.reason, (name, res.reason)
        held = [c["name"] for c in res.checks if c["holds"]]
        assert set(identities.NAMES) <= set(held), (name, held)


def test_the_identity_check_imports_nothing_of_magrod():
    """It is in the verifier's trust base: its arithmetic is python-flint's, its input the field's source text."""
    import ast
    from pathlib import Path

    tree = ast.parse(Path(identities.__file__).read_text())
    mods = {n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)} | \
        {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    assert mods == {"__future__", "hashlib", "fractions", "flint"}, mods


def test_a_constant_component_is_evaluated_not_refused():
    # theta' = 0: a constant component has derivative 0 (seen to fail when a non-dual value was refused as
    # "not evaluable"); R-reversible still, but no longer Hamilton's equations of Hbar, nor chart_jacobian's field
    got = _check(_module("    return [\n        ptheta,\n", "    return [\n        _Q(0, 1),\n"))
    assert got[identities.REVERSIBLE][0] and got[identities.LEVEL_SYMMETRIC][0]
    assert not got[identities.HAMILTONIAN][0] and "['theta']" in got[identities.HAMILTONIAN][1]
    assert not got[identities.VARIATIONAL][0] and "[0, 2]" in got[identities.VARIATIONAL][1]


def _lift(module=fields.gen) -> dict:
    return {name: (holds, how) for name, holds, how in identities.lift_check(fields.source(module), fields.PARAMS)}


def test_the_installed_lift_has_what_the_homoclinic_flights_rest_on():
    """f_body(X(q)) = DX f_chart + Omega G X, the body field commuting with the rotation about d3, the events
    invariant and equal to their chart forms, and the body and lift Jacobians the derivatives they stand for: each an
    exact identity on the installed module (they replace the derivation's report entry chart_body_lift)."""
    got = _lift()
    assert list(got) == list(identities.LIFT_NAMES)
    assert all(holds for holds, _ in got.values()), {k: v[1] for k, v in got.items() if not v[0]}


@pytest.mark.parametrize("function, term, broken", [
    ("body_rhs", 0, {identities.LIFT_INTERTWINES, identities.BODY_EQUIVARIANT, identities.BODY_DERIVATIVES}),
    ("lift", 0, {identities.LIFT_INTERTWINES, identities.EVENTS_ON_CHART, identities.BODY_DERIVATIVES}),
    ("body_events", 3, {identities.EVENTS_ON_CHART, identities.BODY_DERIVATIVES}),
    ("body_jacobian", 0, {identities.BODY_DERIVATIVES}),
    ("lift_jacobian", 0, {identities.BODY_DERIVATIVES}),
])
def test_a_flipped_sign_in_the_body_module_breaks_the_lift_identity_it_touches(function, term, broken):
    got = _lift(fields.mutated_module(term, function))
    assert {k for k, (holds, _) in got.items() if not holds} == broken, {k: v[1][-80:] for k, v in got.items()}
    assert all("nonzero in" in got[k][1] for k in broken)


def test_the_homoclinic_verifier_rejects_a_wrong_lift_at_its_identity():
    """The chart field untouched (its four identities hold), the body field's sign flipped: the homoclinic
    certificate is rejected at the lift, before its digest and any flight."""
    res = verify.verify(_shipped("homoclinic_target.json"), module=fields.mutated_module(0, "body_rhs"))
    assert not res.ok and res.reason.startswith(f"certificate rejected: {identities.LIFT_INTERTWINES} failed"), \
        res.reason
    held = [c["name"] for c in res.checks if c["holds"]]
    assert set(identities.NAMES) <= set(held)
