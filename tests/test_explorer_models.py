"""The explorer for every model: `explore(system)` opens the paper's click-to-launch page for the paper's rod and,
for any other model, the engine's section in the model's body frame, saying by name what it cannot do; an unknown
model is refused as unknown (before: `magrod explore --model nosuch` said the same as `--model kirchhoff`)."""
from __future__ import annotations

import json

import pytest

import magrod as mr
from magrod import cli


def test_another_model_opens_its_section():
    page = mr.explore("anisotropic", iterates=20)
    try:
        assert page.wait(timeout=300)
        r = page.result
        assert r.success and r.points.shape[1] == 20
        # the accuracy evidence of the drawn section: H and the Casimirs conserved at tol = eps
        assert r.energy_error <= 1e-12 and r.casimir_error <= 1e-12
        assert "'anisotropic' has none" in page.limited and "Euler chart" in page.limited
        assert "max |H - h|" in page.status.object
        assert sum(len(src.data["x"]) for src in page.sources) > 0  # the points are drawn
    finally:
        page.close()


def test_the_paper_page_for_a_panel_and_for_a_system():
    a = mr.explore("4b", iterates=10)
    b = mr.explore(mr.System("4a", lam=0.15), iterates=10)
    try:
        assert type(a).__name__ == "Explorer" and a.panel_key == "4b"
        assert b.params.lam == 0.15  # a paper rod that is no panel's: its parameters on Fig 4(a)'s level
    finally:
        a.close()
        b.close()


def test_unknown_model_is_named_as_unknown(capsys):
    with pytest.raises(mr.ParameterError) as e:
        mr.explore("nosuch")
    assert e.value.name == "model" and "unknown model" in e.value.message
    assert cli.main(["explore", "--model", "nosuch", "--json"]) == 2
    d = json.loads(capsys.readouterr().out)
    assert d["parameter"] == "model" and "unknown model 'nosuch'" in d["error"]
    # a real model is not refused by the CLI's model check (the server would start): only the panel, which is the
    # paper's, is
    assert cli.main(["explore", "--model", "kirchhoff", "--panel", "4a", "--json"]) == 2
    assert json.loads(capsys.readouterr().out)["parameter"] == "panel"


def test_old_keyword_panel_still_works_with_a_warning():
    with pytest.warns(DeprecationWarning, match="system"):
        page = mr.explore(panel="4c", iterates=10)
    assert page.panel_key == "4c"
    page.close()


def test_the_page_draws_the_coordinates_that_vary():
    """The section fixes one coordinate (a plot of it against another is a line at 0): the page opens on the two
    coordinates that vary most over the section."""
    import numpy as np

    page = mr.explore("kirchhoff", iterates=30)
    try:
        assert page.wait(timeout=300) and page.result.success
        names = list(page.x_select.options)
        pts = page.result.points
        spread = [float(np.nanmax(pts[..., i]) - np.nanmin(pts[..., i])) for i in range(len(names))]
        shown = {names.index(page.x_select.value), names.index(page.y_select.value)}
        assert len(shown) == 2 and min(spread[i] for i in shown) >= sorted(spread)[-2]
        assert min(spread) < 1e-8  # one coordinate is fixed by the section, and it is not drawn
    finally:
        page.close()


def test_a_model_file_opens_too(tmp_path, monkeypatch):
    """`explore("./my_rod.py")`: a user's model file (not in the registry) opens its section like a registered model
    (the file is code the user runs on purpose; it is compiled into a cache keyed by its content)."""
    from test_models_files import GOOD

    from magrod.core import models

    monkeypatch.setenv("MAGROD_MODEL_CACHE", str(tmp_path / "cache"))
    models._LOADED.clear()
    f = tmp_path / "my_rod.py"
    f.write_text(GOOD)
    page = mr.explore(str(f), iterates=20)
    try:
        assert page.wait(timeout=300) and page.result.success
        assert page.result.energy_error <= 1e-12 and page.result.casimir_error <= 1e-12
        assert "has none" in page.limited and page.system.params == {"A": 1.0, "C": 2.0}  # the file's defaults
    finally:
        page.close()
        models._LOADED.clear()
