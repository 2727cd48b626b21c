"""Every model's results are the paper's rod's result types (one type per concept): PoincareResult, LyapunovResult,
ChaosMap, with the Result face (success, status, message, short repr, to_dict with the System, plot) and an
`accuracy` that a bad number fails.  The older Model* names are gone; model_chaos's functions only forward, with
a DeprecationWarning."""
from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

import magrod as mr
from magrod.chaos.lyapunov import LyapunovResult
from magrod.chaos.maps import ChaosMap
from magrod.chaos.section import PoincareResult
from magrod.core.results import Result


@pytest.fixture(scope="module")
def results():
    from magrod.integrability.model_search import model_search

    return {"section": mr.poincare_section("anisotropic", iterates=20),
            "lyapunov": mr.lyapunov("kirchhoff", t_max=100.0),
            "map": mr.chaos_map("anisotropic", ("B2", 1.0, 3.0, 2), ("C", 1.5, 1.5, 1), t_max=50.0),
            "search": model_search("kirchhoff", 2)}


def test_one_face(results):
    for name, r in results.items():
        assert isinstance(r, Result), name
        assert r.success and r.status == 0 and isinstance(r.message, str), name
        assert repr(r).startswith(type(r).__name__ + "(success=True"), name
        json.dumps(r.to_dict())
        assert r.accuracy["passed"] is not False, name
    assert type(results["section"]) is PoincareResult and type(results["lyapunov"]) is LyapunovResult
    assert type(results["map"]) is ChaosMap
    for name in ("section", "lyapunov"):
        assert results[name].to_dict()["system"]["model"] == results[name].system.model


def test_accuracy_fails_on_a_bad_number(results):
    sec = results["section"]
    assert sec.accuracy["passed"]
    for bad in (1e-6, float("nan")):
        assert dataclasses.replace(sec, max_abs_dH=bad).accuracy["passed"] is False
        assert dataclasses.replace(sec, casimir_drift=bad).accuracy["passed"] is False
    ly = results["lyapunov"]
    assert dataclasses.replace(ly, max_abs_dH=1.0).accuracy["passed"] is False


def test_no_model_twins_and_the_old_names_forward():
    from magrod.chaos import model_chaos

    for name in ("ModelSection", "ModelLyapunov", "ModelChaosMap"):
        assert not hasattr(model_chaos, name)
    with pytest.warns(DeprecationWarning, match="poincare_sections"):
        secs = model_chaos.model_section("anisotropic", n_orbits=2, iterates=10)
    assert [type(r) for r in secs] == [PoincareResult] * 2
    with pytest.warns(DeprecationWarning, match="lyapunov"):
        ly = model_chaos.model_lyapunov("kirchhoff", t_max=50.0)
    assert type(ly) is LyapunovResult and np.isfinite(ly.lyap)
