"""Adaptive chaos maps (issue 28, item 1): magrod.chaos.refine, chaos_map(refine=L), `magrod chaosmap --refine`.

The algorithm is tested on synthetic classes with a known boundary (the expected computed set written out
independently of the code); the maps on the paper's plane against the brute-force map, bit for bit at the
computed points; the store for resumption after a kill and for a corrupted tile."""
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest

from magrod.chaos.refine import Refinement, UNKNOWN, axis_breaks

# ----------------------------------------------------------------------------------------------------------
# the algorithm on synthetic classes
# ----------------------------------------------------------------------------------------------------------


def _drive(truth, levels, value=None, bound=None):
    ref = Refinement(truth.shape, levels, bound)
    while not ref.done:
        iy, ix = ref.points()
        ref.add(iy, ix, truth[iy, ix], None if value is None else value[iy, ix])
    return ref


def test_a_straight_boundary_is_found_and_nothing_else():
    """Class 1 iff ix >= 13 on a 17 x 33 grid, coarse stride 8: the boundary lies between columns 12 and 13.  The
    points computed must be the coarse lattice plus, per level l, the rows at stride 8/2^l of the columns at that
    stride inside the interval (of the level before) that holds the boundary -- written out here by hand, not by
    the quadtree -- and the cells split are exactly the cells straddling the boundary."""
    ny, nx, c, levels = 17, 33, 13, 3
    truth = np.zeros((ny, nx), np.int16)
    truth[:, c:] = 1
    ref = _drive(truth, levels)
    expect = np.zeros((ny, nx), bool)
    expect[0::8, 0::8] = True  # round 0: the coarse lattice (17 and 33 points: 0 and the last are on it)
    a, b = 8, 16  # the coarse column interval holding the boundary 12 | 13
    for lev in range(1, levels + 1):
        s = 8 >> lev
        cols = [x for x in range(a, b + 1) if (x - a) % s == 0]
        expect[np.ix_(range(0, ny, s), cols)] = True
        m = (a + b) // 2
        a, b = (a, m) if c - 1 < m else (m, b)  # the half that still holds the boundary
    got = ref.cls != UNKNOWN
    assert np.array_equal(got, expect), np.argwhere(got != expect)[:10]
    for cells in ref.split_cells():
        for ya, yb, xa, xb in cells:
            assert xa <= c - 1 and c <= xb, (ya, yb, xa, xb)  # every split cell straddles the boundary
    # ... and every straddling cell of every round was split: after the last round no leaf straddles
    assert all(not (xa <= c - 1 and c <= xb) for ya, yb, xa, xb in ref.leaves())
    filled = ref.infer({"status": np.zeros((ny, nx), np.int8), "g": np.where(truth == 1, 10.0, 1.0)}, ["g"])
    assert np.array_equal(filled["g"] > 3, truth == 1)  # the inferred class is the truth everywhere


def test_a_disk_is_resolved_at_its_boundary_and_inferred_inside_and_outside():
    """A disk (class 1) on an irregular 45 x 61 grid (edges off the coarse lattice), coarse stride 8.  Every pair of
    neighbours of different classes is computed (the boundary resolved to the grid), every split cell held both
    classes among its true points, the inferred classes are the true ones, and far fewer than all points were
    integrated."""
    ny, nx = 45, 61
    yy, xx = np.mgrid[0:ny, 0:nx]
    truth = (((yy - 21.3) / 15.0) ** 2 + ((xx - 29.7) / 19.0) ** 2 < 1).astype(np.int16)
    ref = _drive(truth, 3)
    comp = ref.cls != UNKNOWN
    assert np.array_equal(ref.cls[comp], truth[comp])
    for dy, dx in ((0, 1), (1, 0), (1, 1)):
        a, b = truth[:ny - dy, :nx - dx], truth[dy:, dx:]
        diff = a != b
        assert comp[:ny - dy, :nx - dx][diff].all() and comp[dy:, dx:][diff].all()
    for cells in ref.split_cells():
        for ya, yb, xa, xb in cells:
            box = truth[ya:yb + 1, xa:xb + 1]
            assert box.min() != box.max(), (ya, yb, xa, xb)
    filled = ref.infer({"status": np.zeros((ny, nx), np.int8), "g": np.where(truth == 1, 10.0, 1.0)}, ["g"])
    assert np.array_equal(filled["g"] > 3, truth == 1)
    assert comp.mean() < 0.5, comp.mean()
    assert axis_breaks(ny, 8) == [0, 8, 16, 24, 32, 40, 44]


def test_a_feature_on_a_cell_edge_is_seen_by_both_cells():
    """Class 1 on the column ix = 8 for 2 <= iy <= 6 (between two coarse corners of class 0), and on the block
    ix >= 10, iy <= 8.  The right coarse cell is split (its corners disagree) and computes (4, 8), of class 1, on
    its edge with the left cell, whose corners all say 0: the left cell must then be split too (its closed box
    holds both classes), or the feature's points would be inferred wrongly."""
    truth = np.zeros((17, 17), np.int16)
    truth[2:7, 8] = 1
    truth[:9, 10:] = 1
    ref = _drive(truth, 3)
    filled = ref.infer({"status": np.zeros(truth.shape, np.int8), "g": np.where(truth == 1, 10.0, 1.0)}, ["g"])
    assert np.array_equal(filled["g"] > 3, truth == 1), np.argwhere((filled["g"] > 3) != (truth == 1))


def test_the_bound_splits_where_the_indicator_varies_more_than_it():
    """One class everywhere, indicator = ix: a cell spans xb - xa in value, so with bound 2.5 the cells of 8 and 4
    steps are split and those of 2 are not -- the computed points are exactly the lattice at stride 2."""
    ny, nx = 17, 33
    value = np.tile(np.arange(nx, dtype=float), (ny, 1))
    ref = _drive(np.zeros((ny, nx), np.int16), 3, value, bound=2.5)
    expect = np.zeros((ny, nx), bool)
    expect[0::2, 0::2] = True
    assert np.array_equal(ref.cls != UNKNOWN, expect)
    no_bound = _drive(np.zeros((ny, nx), np.int16), 3, value)
    assert (no_bound.cls != UNKNOWN).sum() == 3 * 5  # only the coarse lattice


def test_inferred_points_never_overwrite_computed_ones_and_keep_their_cells_class():
    """infer(): computed points keep their values exactly; an inferred point lies within its cell's corner range
    (so its class is its cell's); an inferred missing point has the cell's status and NaN indicators."""
    ny, nx = 17, 17
    truth = np.zeros((ny, nx), np.int16)
    truth[:, 9:] = 3  # 2 + status 1: no energy root
    ref = _drive(truth, 3)
    rng = np.random.default_rng(5)
    g = np.where(truth == 0, rng.uniform(0.5, 2.9, (ny, nx)), np.nan)
    st = np.where(truth == 0, 0, 1).astype(np.int8)
    comp = ref.cls != UNKNOWN
    fields = {"status": np.where(comp, st, 4).astype(np.int8), "g": np.where(comp, g, -7.0)}
    out = ref.infer(fields, ["g"])
    assert np.array_equal(out["g"][comp], fields["g"][comp], equal_nan=True)
    assert np.array_equal(out["status"][comp], fields["status"][comp])
    inf = ~comp
    assert inf.any()
    assert np.array_equal(out["status"][inf], st[inf])
    reg = inf & (truth == 0)
    assert np.all((out["g"][reg] >= 0.5) & (out["g"][reg] <= 2.9))
    assert np.isnan(out["g"][inf & (truth == 3)]).all()


def test_add_takes_exactly_the_rounds_points():
    ref = Refinement((9, 9), 2)
    iy, ix = ref.points()
    with pytest.raises(ValueError):
        ref.add(iy[:-1], ix[:-1], np.zeros(iy.size - 1))


# ----------------------------------------------------------------------------------------------------------
# maps on the paper's plane
# ----------------------------------------------------------------------------------------------------------
AXES = (("lam", 0.12, 0.2, 9), ("gamma", 2.0, 3.5, 9))
T = 300.0


@pytest.fixture(scope="module")
def brute():
    import magrod as mr

    return mr.chaos_map(*AXES, t_max=T, tile=4)


def test_refine_off_is_todays_map_and_todays_identity(brute):
    """refine=0 goes through the brute-force path: the fields are compute_tile's, tile by tile, bit for bit, and the
    spec's dict (the store identity) has exactly the keys it had before issue 28 (so existing stores still open)."""
    from magrod.chaos import maps

    spec = brute.spec
    assert spec.refine == 0 and "inferred" not in brute.fields
    assert set(spec.to_dict()) == {"x", "y", "base", "panel", "root", "t_max", "tol", "renorm_dt", "tile",
                                   "batch_size"}
    for t in maps.tiles(spec):
        ref = maps.compute_tile(spec, t)
        for k, v in ref.items():
            assert np.array_equal(brute.fields[k][t.ys, t.xs], v, equal_nan=True), (t.key, k)


def test_a_refined_map_computes_the_brute_force_numbers(brute):
    """Every point a refined map computes has the brute-force map's values bit for bit (its own lane, the same
    start tangent), the inferred points are flagged and take their cell's class, and on this plane the refined
    classification agrees with the brute-force one on nearly every point."""
    import magrod as mr
    from magrod.chaos import maps
    from magrod.chaos.refine import point_class

    r = mr.chaos_map(*AXES, t_max=T, tile=4, refine=2)
    comp = r.fields["inferred"] == 0
    assert 0 < comp.sum() < comp.size
    for k in maps.MAP_FIELDS + ("status",):
        assert np.array_equal(r.fields[k][comp], brute.fields[k][comp], equal_nan=True), k
    assert np.array_equal(r.fields["level"] >= 0, comp)
    cr = point_class(r.fields["status"], r.fields["growth_exponent"])
    cb = point_class(brute.fields["status"], brute.fields["growth_exponent"])
    assert (cr == cb).mean() >= 0.95, (cr == cb).mean()
    ds = r.to_xarray()
    assert "inferred" in ds and ds["inferred"].dims == ("gamma", "lam")
    s = r.summary()["refine"]
    assert s["points_computed"] + s["points_inferred"] == 81 and sum(s["points_per_round"]) == s["points_computed"]


def test_bad_refine_values_name_the_field():
    import magrod as mr
    from magrod.core.errors import ParameterError

    for kw, field in (({"refine": 1.5}, "refine"), ({"refine": 99}, "refine"), ({"refine": -1}, "refine"),
                      ({"refine": 2, "refine_bound": 0}, "refine_bound"), ({"refine_bound": 1.0}, "refine_bound")):
        with pytest.raises(ParameterError) as e:
            mr.chaos_map(*AXES, t_max=T, **kw)
        assert e.value.name == field, (kw, e.value.name)


# ----------------------------------------------------------------------------------------------------------
# the store: resume after a kill, a corrupted tile
# ----------------------------------------------------------------------------------------------------------
GRID = ["--x", "lam:0.12:0.2:9", "--y", "gamma:2:3.5:9", "--tile", "4", "--t-max", "300", "--refine", "2"]


@pytest.fixture(scope="module")
def cluster():
    import logging

    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                      scheduler_kwargs={"dashboard": False, "dashboard_address": ":0"},
                      silence_logs=logging.CRITICAL) as c:
        yield c.scheduler_address


def _run(out, scheduler, capsys):
    from magrod import cli

    rc = cli.main(["chaosmap", *GRID, "--out", str(out), "--scheduler", scheduler, "--json", "--quiet"])
    cap = capsys.readouterr()
    assert "Traceback" not in cap.err, cap.err
    return rc, json.loads(cap.out), [ln for ln in cap.err.splitlines() if ln.strip()]


def _stored(out):
    from magrod.store import tiles as store

    return store.load_fields(Path(out) / "chaosmap.zarr")


@pytest.fixture(scope="module")
def reference(cluster, tmp_path_factory):
    from magrod import cli

    out = tmp_path_factory.mktemp("refined") / "o"
    assert cli.main(["chaosmap", *GRID, "--out", str(out), "--scheduler", cluster, "--json", "--quiet"]) == 0
    return out


def test_the_refined_store_is_the_in_memory_map(reference, brute):
    import magrod as mr

    r = mr.chaos_map(*AXES, t_max=T, tile=4, refine=2)
    f = _stored(reference)
    for k, v in r.fields.items():
        assert np.array_equal(f[k], v, equal_nan=True), k
    assert json.loads((reference / "chaosmap.tiles" / "store.record").read_text())["complete"]


def test_a_corrupted_refined_tile_is_found_recomputed_and_counted(reference, cluster, tmp_path, capsys):
    """Overwrite one chunk of the growth exponent with garbage: the re-run finds that tile (its final hash fails),
    replays the rounds, recomputes exactly the damaged tile's parts, and the store equals the undamaged one."""
    out = tmp_path / "o"
    shutil.copytree(reference, out)
    chunk = out / "chaosmap.zarr" / "growth_exponent" / "c" / "1" / "1"
    assert chunk.is_file()
    chunk.write_bytes(b"\x00garbage" * 8)
    rc, obj, lines = _run(out, cluster, capsys)
    assert rc == 0, obj
    assert obj["tiles"]["repaired"] >= 1 and obj["tiles"]["total"] == 9, obj["tiles"]
    assert len(lines) == 1 and "failed their content hash" in lines[0], lines
    parts = set(obj["repaired_tiles"])
    assert "1_1" in parts and all(p.endswith("_1_1") for p in parts if p.startswith("r")), parts
    assert obj["tiles"]["parts_computed"] >= 1 and obj["tiles"]["parts_skipped"] >= 1
    ref, got = _stored(reference), _stored(out)
    for k in ref:
        assert np.array_equal(ref[k], got[k], equal_nan=True), k


def test_a_refined_map_resumes_after_a_kill(reference, cluster, tmp_path, capsys):
    """Kill (SIGKILL) `magrod chaosmap --refine` once its first round is written; the re-run keeps that round
    (verified, not recomputed) and ends with the uninterrupted map, byte for byte in every field."""
    out = tmp_path / "o"
    marker = tmp_path / "marker"
    p = subprocess.Popen([sys.executable, "-m", "magrod.cli", "chaosmap", *GRID, "--out", str(out), "--scheduler",
                          cluster, "--json", "--quiet"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         cwd=tempfile.gettempdir(), env={**os.environ, "MAGROD_TEST_PAUSE": f"chaosmap-round:{marker}"})
    try:
        deadline = time.time() + 180
        while not marker.exists() and time.time() < deadline and p.poll() is None:
            time.sleep(0.05)
        assert marker.exists(), p.communicate()
        os.kill(p.pid, signal.SIGKILL)
        p.wait(timeout=30)
    finally:
        if p.poll() is None:
            p.kill()
    assert any((out / "chaosmap.tiles").glob("r0_*.json")) and not any((out / "chaosmap.tiles").glob("r1_*.json"))
    rc, obj, lines = _run(out, cluster, capsys)
    assert rc == 0, obj
    assert obj["tiles"]["parts_skipped"] == 9 and obj["tiles"]["repaired"] == 0, obj["tiles"]  # round 0: 9 tiles
    ref, got = _stored(reference), _stored(out)
    for k in ref:
        assert np.array_equal(ref[k], got[k], equal_nan=True), k


def test_cli_refuses_a_bad_refine_in_one_line(tmp_path, capsys):
    from magrod import cli

    rc = cli.main(["chaosmap", *GRID[:-2], "--refine", "x", "--out", str(tmp_path / "o"), "--json"])
    cap = capsys.readouterr()
    assert rc == 2 and json.loads(cap.out)["parameter"] == "refine"
    assert len([ln for ln in cap.err.splitlines() if ln.strip()]) == 1
    assert not (tmp_path / "o").exists()


def test_a_refined_map_is_the_same_at_another_simd_width(brute):
    """Batch width 4 (2 if the default is 4) against the default: the points computed and their classes agree (a point whose growth
    exponent sits at the threshold could flip between two valid roundings and refine one more cell; none does
    on this plane, and the classification is required to agree on at least 99 % of the points)."""
    import magrod as mr
    from magrod.chaos import maps
    from magrod.chaos.refine import point_class

    a = mr.chaos_map(*AXES, t_max=T, tile=4, refine=2)
    other = 4 if a.spec.batch_size != 4 else 2
    spec = maps.MapSpec(**{**{k: getattr(a.spec, k) for k in ("x", "y", "base", "panel", "root", "t_max", "tol",
                                                                "renorm_dt", "tile", "refine")}, "batch_size": other})
    b = mr.chaos_map(spec)
    assert b.spec.batch_size == other != a.spec.batch_size
    ca = point_class(a.fields["status"], a.fields["growth_exponent"])
    cb = point_class(b.fields["status"], b.fields["growth_exponent"])
    assert (ca == cb).mean() >= 0.99
    assert (a.fields["inferred"] == b.fields["inferred"]).mean() >= 0.95
