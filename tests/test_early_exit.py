"""The optional early exit of a chaos map (issue 28): a chaotic orbit stops after T/2 once its growth exponent so
far passes the exit level, the field exit_time records when, and nothing else changes.

The references are independent computations: the unchanged batch path (exit_above=None) and its per-sample
history ln|w(t_k)| (history=True), from which the exit rule is re-derived by hand."""
from __future__ import annotations

import math

import numpy as np
import pytest

from magrod.chaos import indicators, maps

T = 600.0
AXES = (("lam", 0.1, 0.2, 6), ("gamma", 2.0, 3.5, 6))  # regular, chaotic and no-root points (36, 27 computed)


@pytest.fixture(scope="module")
def starts():
    spec = maps.MapSpec(maps.Axis(*AXES[0]), maps.Axis(*AXES[1]), base=maps.panel_base("4a"), t_max=T)
    pts = [maps.start_point(spec.point(ix, iy)) for iy in range(spec.y.n) for ix in range(spec.x.n)]
    x0 = np.nan_to_num(np.array([q[0] for q in pts]).T)
    p = np.nan_to_num(np.array([q[1] for q in pts]).T, nan=1.0)
    return x0, p, np.array([q[2] == indicators.OK for q in pts])


@pytest.fixture(scope="module")
def full(starts):
    x0, p, v = starts
    return indicators.body_indicators(x0, p, t_max=T, valid=v, history=True)


def test_the_lane_loop_without_an_exit_is_the_batch_path_bit_for_bit(starts, full):
    """exit_above = inf runs the refilled-lane loop with no orbit exiting: every field equals the unchanged batch
    path's bit for bit (own lane, own time from 0, the same start normalisation and renormalisations)."""
    x0, p, v = starts
    lanes = indicators.body_indicators(x0, p, t_max=T, valid=v, exit_above=np.inf)
    for k in indicators._KEYS + ("status",):
        assert np.array_equal(getattr(lanes, k), getattr(full, k), equal_nan=True), k
    assert np.array_equal(lanes.exit_time[v], np.full(v.sum(), T)) and np.isnan(lanes.exit_time[~v]).all()
    assert full.exit_time is None


def test_a_chaotic_orbit_exits_early_with_its_exit_time_and_a_regular_one_does_not(starts, full):
    """Against the history of the full run: an orbit exits exactly at the first sample t_k >= T/2 where
    (max_{j<=k} L_j - FLI(T/2))/ln 2 > exit level, with lyap = L_k/t_k, fli = max_{j<=k} L_j and the full run's
    fli_half; an orbit that never passes it runs to T with the full run's numbers.  Both kinds occur here."""
    x0, p, v = starts
    level = indicators.GROWTH_THRESHOLD + indicators.EXIT_MARGIN
    ee = indicators.body_indicators(x0, p, t_max=T, valid=v, exit_above=level)
    K = full.log_growth.shape[1]
    exited = 0
    for i in np.flatnonzero(v):
        Lk = full.log_growth[i]
        fli = np.maximum.accumulate(Lk)
        half = fli[K // 2 - 1]
        g = (fli - half) / math.log(2.0)
        over = [k for k in range(K // 2, K + 1) if g[k - 1] > level and k < K]
        if over:  # exits at the first such sample
            k = over[0]
            t_e = k * full.renorm_dt
            assert ee.exit_time[i] == t_e < T, i
            assert ee.lyap[i] == Lk[k - 1] / t_e and ee.fli[i] == fli[k - 1] and ee.fli_half[i] == half, i
            assert level < ee.growth_exponent[i] <= full.growth_exponent[i], i  # a lower bound, above the level
            assert full.chaotic[i] and ee.chaotic[i], i
            exited += 1
        else:
            assert ee.exit_time[i] == T, i
            for key in indicators._KEYS:
                assert getattr(ee, key)[i] == getattr(full, key)[i], (i, key)
    assert 0 < exited < v.sum() and (~full.chaotic[v]).any()


@pytest.fixture(scope="module")
def maps_pair():
    import magrod as mr

    return mr.chaos_map(*AXES, t_max=T, tile=4), mr.chaos_map(*AXES, t_max=T, tile=4, early_exit=True)


def test_a_map_with_early_exit_classifies_every_point_as_the_full_map(maps_pair):
    """Same status and class at every point; the points that did not exit carry the full map's numbers bit for
    bit; exit_time is T there, earlier at some chaotic points, NaN where nothing was computed; the summary says
    how many orbits exited and what share of the time was integrated."""
    a, b = maps_pair
    assert "exit_time" not in a.fields and "early_exit" not in a.summary()
    assert np.array_equal(a.fields["status"], b.fields["status"])
    ok = a.fields["status"] == indicators.OK
    ca = a.fields["growth_exponent"][ok] > indicators.GROWTH_THRESHOLD
    cb = b.fields["growth_exponent"][ok] > indicators.GROWTH_THRESHOLD
    assert np.array_equal(ca, cb)
    te = b.fields["exit_time"]
    assert np.isnan(te[~ok]).all()
    stayed = ok & (te == T)
    assert stayed.sum() < ok.sum() and (te[ok] < T).sum() == b.summary()["early_exit"]["orbits_exited"] > 0
    for k in maps.MAP_FIELDS:
        assert np.array_equal(a.fields[k][stayed], b.fields[k][stayed]), k
    s = b.summary()["early_exit"]
    assert s["exit_above"] == b.spec.exit_above and s["time_fraction"] == pytest.approx(te[ok].mean() / T)
    assert s["time_fraction"] < 1
    ds = b.to_xarray()
    assert "exit_time" in ds and "T/2" in ds["exit_time"].attrs["long_name"] and "early_exit" in ds.attrs


def test_early_exit_off_keeps_the_spec_dict_and_the_fields_of_today(maps_pair):
    """early_exit=False: the spec's dict (the store identity) has no early_exit key and the fields are the
    brute-force tiles', bit for bit; on, the key is there (another map, another store)."""
    a, b = maps_pair
    assert "early_exit" not in a.spec.to_dict() and b.spec.to_dict()["early_exit"] is True
    assert maps.MapSpec.from_dict(b.spec.to_dict()) == b.spec
    for t in maps.tiles(a.spec):
        ref = maps.compute_tile(a.spec, t)
        assert set(ref) == set(maps.MAP_FIELDS) | {"status"}
        for k, v in ref.items():
            assert np.array_equal(a.fields[k][t.ys, t.xs], v, equal_nan=True), (t.key, k)


def test_bad_early_exit_values_name_the_field():
    import magrod as mr
    from magrod.core.errors import ParameterError

    with pytest.raises(ParameterError) as e:
        mr.chaos_map(*AXES, t_max=T, early_exit="yes")
    assert e.value.name == "early_exit"
    with pytest.raises(ParameterError) as e:
        mr.chaos_map(*AXES, t_max=T, refine=1, refine_bound=2.0, early_exit=True)
    assert e.value.name == "early_exit"


def test_cli_refuses_a_threshold_above_the_exit_level(tmp_path, capsys):
    import json

    from magrod import cli

    rc = cli.main(["chaosmap", "--x", "lam:0.1:0.2:2", "--y", "gamma:2:3:2", "--t-max", "100", "--early-exit",
                   "--threshold", "9", "--out", str(tmp_path / "o"), "--json"])
    cap = capsys.readouterr()
    assert rc == 2 and json.loads(cap.out)["parameter"] == "threshold"
    assert len([ln for ln in cap.err.splitlines() if ln.strip()]) == 1
    assert not (tmp_path / "o").exists()
