"""The store wing (magrod/store/, issue 25): a resumable, store-backed chaos map from the library itself,
`mr.chaos_map(..., store=DIR)`, with the integrity rules `magrod chaosmap` has (it calls the same function), and the
wing's place in the layout (the numerics never import it)."""
from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import magrod as mr
from magrod.core.errors import ParameterError

AXES = (("lam", 0.12, 0.2, 4), ("gamma", 2.0, 4.0, 4))
KW = {"t_max": 200.0, "tile": 2}


def _same_fields(a: dict, b: dict) -> None:
    assert set(a) == set(b)
    for k in a:
        np.testing.assert_array_equal(np.asarray(a[k]), np.asarray(b[k]), err_msg=k)


def test_a_stored_map_is_the_in_memory_map_and_resumes(tmp_path):
    """The same bits as the in-memory map (every tile is the same pure function); a second call verifies every tile
    by its content hash and computes nothing; a damaged tile is found and recomputed."""
    ref = mr.chaos_map(*AXES, **KW)
    cm = mr.chaos_map(*AXES, **KW, store=tmp_path, workers=1)
    assert cm.success, cm.message
    _same_fields(cm.fields, ref.fields)
    assert cm.store == str(tmp_path.absolute() / "chaosmap.zarr")
    assert cm.run["tiles"] == {"total": 4, "computed": 4, "skipped": 0, "repaired": 0}
    assert cm.run["orbits_computed"] == 16 and cm.to_dict()["run"]["tiles"]["total"] == 4
    again = mr.chaos_map(*AXES, **KW, store=tmp_path, workers=1)
    assert again.run["tiles"] == {"total": 4, "computed": 0, "skipped": 4, "repaired": 0}
    _same_fields(again.fields, ref.fields)
    chunk = next(p for p in sorted((tmp_path / "chaosmap.zarr" / "lyap").rglob("*")) if p.is_file()
                 and p.name[0].isdigit())
    chunk.write_bytes(b"\0" * len(chunk.read_bytes()))  # a corrupted chunk: its tile fails its content hash
    from magrod.core.errors import MagrodWarning

    with pytest.warns(MagrodWarning, match="content hash"):
        fixed = mr.chaos_map(*AXES, **KW, store=tmp_path, workers=1)
    assert fixed.run["tiles"]["computed"] == 1 and fixed.run["tiles"]["repaired"] == 1
    _same_fields(fixed.fields, ref.fields)


def test_a_stored_map_refuses_another_map_in_its_store(tmp_path):
    mr.chaos_map(*AXES, **KW, store=tmp_path, workers=1)
    other = (("lam", 0.12, 0.2, 4), ("gamma", 2.0, 3.0, 4))
    with pytest.raises(ParameterError) as e:
        mr.chaos_map(*other, **KW, store=tmp_path, workers=1)
    assert e.value.name == "out" and "force" in e.value.message
    forced = mr.chaos_map(*other, **KW, store=tmp_path, workers=1, force=True)
    assert forced.success and forced.run["tiles"]["computed"] == 4


@pytest.mark.parametrize("kw, name", [({"workers": 1}, "workers"), ({"force": True}, "force"),
                                      ({"stem": "x"}, "stem"), ({"scheduler": "tcp://127.0.0.1:1"}, "scheduler")])
def test_store_options_need_a_store(kw, name):
    with pytest.raises(ParameterError) as e:
        mr.chaos_map(*AXES, **KW, **kw)
    assert e.value.name == name


@pytest.mark.parametrize("kw, name", [({"stem": "../up"}, "stem"), ({"stem": ".hidden"}, "stem"),
                                      ({"workers": 0}, "workers"), ({"workers": 10 ** 4}, "workers"),
                                      ({"workers": 1, "scheduler": "tcp://127.0.0.1:1"}, "scheduler"),
                                      ({"scheduler": "inproc://x"}, "scheduler")])
def test_stored_map_bad_options_name_themselves_and_write_nothing(tmp_path, kw, name):
    out = tmp_path / "o"
    with pytest.raises(ParameterError) as e:
        mr.chaos_map(*AXES, **KW, store=out, **kw)
    assert e.value.name == name
    assert not out.exists()


def test_the_public_chaos_map_documents_and_signs_its_store_options():
    import inspect

    sig = inspect.signature(mr.chaos_map)
    for name in ("store", "stem", "workers", "scheduler", "force", "panel", "t_max", "refine"):
        assert name in sig.parameters, name
    assert "\n    store : str or Path, optional" in mr.chaos_map.__doc__


# ----------------------------------------------------------------------------------------------------------------
# the layout: the store wing sits above the numerics
def store_imports(root: Path) -> list:
    """(module, line) of every import of the store wing inside the numerics subpackages of `root` (a magrod tree)."""
    bad = []
    for sub in ("core", "orbits", "chaos", "separatrix", "integrability", "proof"):
        for path in sorted((root / sub).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text())):
                if isinstance(node, ast.ImportFrom):
                    mod = node.module or ""
                    hit = (node.level >= 2 and (mod == "store" or mod.startswith("store."))) or \
                        mod.startswith("magrod.store") or (node.level >= 2 and not mod and
                                                           any(a.name == "store" for a in node.names))
                elif isinstance(node, ast.Import):
                    hit = any(a.name.startswith("magrod.store") for a in node.names)
                else:
                    continue
                if hit:
                    bad.append((str(path.relative_to(root)), node.lineno))
    return bad


def test_the_numerics_never_import_the_store_wing():
    assert store_imports(Path(mr.__file__).parent) == []


def test_the_store_rule_finds_a_violation(tmp_path):
    """The rule above, seen to fail: a numerics module that imports the wing is found, in each spelling."""
    for sub in ("chaos", "core", "orbits", "separatrix", "integrability", "proof"):
        (tmp_path / sub).mkdir()
    (tmp_path / "chaos" / "a.py").write_text("from ..store import tiles\n")
    (tmp_path / "chaos" / "b.py").write_text("def f():\n    from ..store.resumable import stored_map\n")
    (tmp_path / "core" / "c.py").write_text("import magrod.store.cluster\n")
    (tmp_path / "orbits" / "d.py").write_text("from .. import store\n")
    assert sorted(m for m, _ in store_imports(tmp_path)) == ["chaos/a.py", "chaos/b.py", "core/c.py", "orbits/d.py"]


def test_a_stored_map_keeps_its_exit_times(tmp_path):
    """Early exit in a store (issue 28): the store holds exit_time, equal to the in-memory map's bit for bit, and a
    second call verifies it in each tile's content hash (computes nothing).  Seen to fail before the store knew the
    field (exit_time was silently not written)."""
    axes = (("lam", 0.1, 0.2, 4), ("gamma", 2.0, 3.5, 4))
    kw = {"t_max": 600.0, "tile": 2, "early_exit": True}
    ref = mr.chaos_map(*axes, **kw)
    cm = mr.chaos_map(*axes, **kw, store=tmp_path, workers=1)
    assert cm.success and "exit_time" in cm.fields
    _same_fields(cm.fields, ref.fields)
    assert (tmp_path / "chaosmap.zarr" / "exit_time").is_dir()
    again = mr.chaos_map(*axes, **kw, store=tmp_path, workers=1)
    assert again.run["tiles"]["computed"] == 0
    _same_fields(again.fields, ref.fields)
    with pytest.raises(ParameterError) as e:
        mr.chaos_map(*axes, **kw, refine=1, store=tmp_path / "r", workers=1)
    assert e.value.name == "early_exit"
