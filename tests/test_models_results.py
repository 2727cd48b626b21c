"""The model family's result types share the paper's rod's face (issues 25, 26): the Result base (success, status,
message, short repr, to_dict, plot), an `accuracy` property, and the paper types' names for the conservation
numbers (max_abs_dH, casimir_drift) as aliases of the model types' fields."""
from __future__ import annotations

import dataclasses
import json

import pytest

from magrod.core.results import Result
from magrod.core.tolerances import CASIMIR_TOL, ENERGY_TOL

# the keys of PoincareResult.accuracy (magrod/chaos/section.py, accuracy_checks) and LyapunovResult.accuracy's
# conservation names (magrod/chaos/lyapunov.py)
POINCARE_KEYS = {"energy_tol", "casimir_tol", "energy_ok", "casimir_ok", "passed"}
LYAPUNOV_KEYS = {"max_abs_dH", "casimir_drift", "passed"}


@pytest.fixture(scope="module")
def results():
    from magrod.chaos.model_chaos import model_chaos_map, model_lyapunov, model_section
    from magrod.integrability.model_search import model_search

    return {"section": model_section("anisotropic", n_orbits=2, iterates=20),
            "lyapunov": model_lyapunov("kirchhoff", t_max=100.0),
            "map": model_chaos_map("anisotropic", ("B2", 1.0, 3.0, 2), ("C", 1.0, 2.0, 1), t_max=50.0),
            "search": model_search("kirchhoff", 2)}


def test_one_face(results):
    for name, r in results.items():
        assert isinstance(r, Result), name
        assert r.success and r.status == 0 and isinstance(r.message, str), name
        assert repr(r).startswith(type(r).__name__ + "(success=True"), name
        json.dumps(r.to_dict())
        assert r.accuracy["passed"] is True, name


@pytest.mark.parametrize("name", ["section", "lyapunov", "map"])
def test_conservation_under_the_paper_types_names_and_a_failing_one(results, name):
    r = results[name]
    acc = r.accuracy
    assert POINCARE_KEYS | LYAPUNOV_KEYS <= set(acc)
    assert acc["energy_tol"] == ENERGY_TOL and acc["casimir_tol"] == CASIMIR_TOL
    assert r.max_abs_dH == r.energy_error == acc["max_abs_dH"]
    assert (r.max_casimir_drift if name == "map" else r.casimir_drift) == r.casimir_error == acc["casimir_drift"]
    # the mutation: an energy error beyond the gate fails the accuracy check, a NaN too
    for bad in (10 * ENERGY_TOL, float("nan")):
        assert dataclasses.replace(r, energy_error=bad).accuracy["passed"] is False
    assert "max_abs_dH" not in r.to_dict()  # an alias, not a new field: the data files are unchanged


def test_exact_search_accuracy(results):
    acc = results["search"].accuracy
    assert acc["exact"] and acc["certified"] and acc["passed"]
    assert dataclasses.replace(results["search"], certified=False).accuracy["passed"] is False
