"""Outputs you can reuse (issue 29): to_dict() stays small (arrays by reference into arrays(), which save() writes
to .npz, as `magrod poincare --out` does), to_xarray() on the results that hold arrays, and ChaosMap's in-memory
Dataset carries the CF attributes of its zarr store (units, long_name, status flags)."""
from __future__ import annotations

import json

import numpy as np
import pytest

import magrod as mr
from magrod.core.params import RodParams
from magrod.core.results import INLINE_ARRAY_MAX

pytest.importorskip("xarray")


def _refs(d, out=None):
    out = [] if out is None else out
    if isinstance(d, dict):
        if set(d) == {"npz", "shape", "dtype"}:
            out.append(d)
        else:
            for v in d.values():
                _refs(v, out)
    elif isinstance(d, list):
        for v in d:
            _refs(v, out)
    return out


def _check_small_and_complete(res, tmp_path, limit=20_000):
    d = res.to_dict()
    text = json.dumps(d)
    assert len(text) < limit, (type(res).__name__, len(text))
    arrays = res.arrays()
    refs = _refs(d)
    assert refs, type(res).__name__  # the big arrays are referenced, not dropped
    for r in refs:
        a = np.asarray(arrays[r["npz"]])
        assert list(a.shape) == r["shape"] and str(a.dtype) == r["dtype"], r
    paths = res.save(tmp_path / type(res).__name__)
    with np.load(paths[1]) as z:
        assert set(z.files) == set(arrays)
        for k in z.files:
            assert np.array_equal(z[k], np.asarray(arrays[k]), equal_nan=True), k
    assert json.loads(open(paths[0]).read())["arrays_file"].endswith(".npz")
    ds = res.to_xarray()
    for k, a in arrays.items():
        name = k.replace(".", "_")
        if name in ds:
            assert np.array_equal(ds[name].values, np.asarray(a), equal_nan=True), k
    return d, ds


def test_rod_shape_to_dict_is_small(tmp_path):
    """Seen to fail before: RodShape.to_dict() was the whole sampled rod (1 MB of JSON at n = 3001)."""
    from magrod.orbits import multipulse

    orb = multipulse.shoot(RodParams(1.7, 0.0025, 1.0, 1.0, 0.00125), 2)
    assert orb.success
    shape = mr.rod_shape(orb, n=3001)
    d, ds = _check_small_and_complete(shape, tmp_path)
    assert {"s", "r", "D", "x"} <= set(shape.arrays())
    assert ds["r"].shape == shape.r.shape and shape.r.shape[1] == 3
    assert ds["r"].dims == ("sample", "space") and ds["s"].attrs["units"] == "B/m3" and ds["D"].attrs["long_name"]


def test_section_and_lyapunov_small(tmp_path):
    sec = mr.poincare_section("4a", iterates=300)
    d, ds = _check_small_and_complete(sec, tmp_path)
    assert d["arrays"]["points"]["shape"] == [300, 4]
    assert ds["theta"].attrs["units"] == "rad" and all(ds[v].attrs.get("long_name") for v in ds.data_vars)
    ly = mr.lyapunov("4a", t_max=200)
    json.dumps(ly.to_dict())
    assert len(json.dumps(ly.to_dict())) < 20_000
    assert ly.to_xarray() is not None


def test_small_arrays_stay_inline():
    from magrod.core.results import jsonable

    assert jsonable({"a": np.arange(INLINE_ARRAY_MAX)}, INLINE_ARRAY_MAX) == {"a": list(range(INLINE_ARRAY_MAX))}
    big = jsonable({"a": np.zeros((INLINE_ARRAY_MAX + 1,))}, INLINE_ARRAY_MAX)
    assert big == {"a": {"npz": "a", "shape": [INLINE_ARRAY_MAX + 1], "dtype": "float64"}}


def test_chaos_map_dataset_has_the_store_attributes():
    """Every field of the in-memory Dataset has units and long_name, status its flag_values/flag_meanings, the
    coordinates their long names: those the zarr store writes.  Seen to fail before (attrs {})."""
    from magrod.store import tiles as store

    cm = mr.chaos_map(("lam", 0.12, 0.2, 2), ("gamma", 2.0, 3.5, 2), panel="4a", t_max=100)
    ds = cm.to_xarray()
    for k in cm.fields:
        assert ds[k].attrs.get("units") and ds[k].attrs.get("long_name"), k
        assert ds[k].attrs == store.variable_attrs(k)
    assert ds["status"].attrs["flag_meanings"] and list(ds["status"].attrs["flag_values"]) == [0, *[
        c for c in ds["status"].attrs["flag_values"] if c]]
    assert ds["lam"].attrs["long_name"] == "lambdabar" and ds["gamma"].attrs["units"] == "1"
    assert "tolerance" in ds.attrs and "criterion" in ds.attrs
    d = cm.to_dict()
    assert len(json.dumps(d)) < 20_000
