"""Progress that means something: a chaos map's bar counts grid points, not tiles (a 16 x 16 map in one tile showed
one bar "0/1").  Cheap: a 2 x 3 map with T = 20 in this process.  Seen to fail before (the updates summed to the
tile count)."""
from __future__ import annotations

from magrod.chaos import maps


def test_chaos_map_progress_counts_points():
    spec = maps.MapSpec(maps.parse_axis("x", "lam:0.12:0.2:3"), maps.parse_axis("y", "gamma:2:4:2"),
                        base=maps.panel_base("4a"), panel="4a", t_max=20.0, tile=2)
    updates = []
    res = maps.compute_map(spec, progress=updates.append)
    assert res.success, res.message
    assert len(updates) == len(maps.tiles(spec)) == 2  # one update per tile: 1 x 2 tiles of a 2 x 3 grid ...
    assert sum(updates) == 6 and sorted(updates) == [2, 4]  # ... each counting its points
