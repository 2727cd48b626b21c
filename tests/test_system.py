"""The one value of what is studied (magrod.core.system): model, parameters validated once, precision."""
from __future__ import annotations

import pytest

import magrod as mr
from magrod.core.system import as_system


def test_paper_panel_and_rodparams_give_the_same_system():
    a = mr.System("4a")
    b = mr.System(mr.panel("4a").params)
    assert a == b and hash(a) == hash(b) and a.is_paper
    assert a.rod == mr.panel("4a").params


def test_overrides_validated_and_panel_relabelled():
    s, pan = as_system("5a", gamma=0.2)
    assert s.params["gamma"] == 0.2
    assert pan.key == "5a, gamma=0.2" and pan.params.gamma == 0.2  # never claims to be the paper's panel
    with pytest.raises(mr.ParameterError) as e:
        mr.System("4a", delta=-1)
    assert e.value.name == "delta"


def test_registry_model_defaults_and_ranges():
    s = mr.System("anisotropic")
    code = s.code
    assert s.names == tuple(code.names.PARAMS)
    assert s.values == tuple(float(v) for v in code.names.DEFAULTS)
    assert s.replace(C=2.5).params["C"] == 2.5
    with pytest.raises(mr.ParameterError) as e:
        s.replace(B1=0)
    assert e.value.name == "B1"
    with pytest.raises(mr.ParameterError) as e:
        s.rod  # the paper's chart asked of another model: named
    assert e.value.name == "model"


@pytest.mark.parametrize("bad, name", [(3, "system"), ("nosuch", "model"), ("./missing_rod.py", "model")])
def test_what_does_not_convert_is_named(bad, name):
    with pytest.raises(mr.ParameterError) as e:
        mr.System(bad)
    assert e.value.name == name


def test_precision_and_dict_round_trip():
    s = mr.System("kirchhoff", precision="quad")
    assert s.precision is mr.Precision.QUAD
    d = s.to_dict()
    t, _ = as_system(d["params"], model=d["model"], precision=d["precision"])
    assert t == s
    assert len(repr(s)) < 200
