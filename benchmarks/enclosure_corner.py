"""Benchmark (issue 27, item 5): the corner of the issue-20 box left undecided by the mean value form of
box_theorem (benchmarks/enclosure_boxes.json: 3515 boxes in m in [1287/640, 11/5] x gamma in [1/4, 61/128], all
delta in [1/4, 3], next to m_c = 2 sqrt(1 + gamma)), run again with the second-order form (box_theorem(order=2)).
Covers the bounding rectangle of those boxes, then reports which share of the old undecided set is now decided.
Writes the result as JSON (argument 1, default enclosure_corner.json).  Not a test: tests/test_enclosure.py checks
small boxes.

    python benchmarks/enclosure_corner.py [out.json] [--quick]
"""
import json
import sys
import time
from fractions import Fraction
from pathlib import Path

from magrod.separatrix.enclosure import box_theorem

HERE = Path(__file__).resolve().parent
out = next((a for a in sys.argv[1:] if not a.startswith("--")), "enclosure_corner.json")
quick = "--quick" in sys.argv

old = json.loads((HERE / "enclosure_boxes.json").read_text())["undecided"]


def box(b):
    return [(Fraction(b[k][0]), Fraction(b[k][1])) for k in ("m", "gamma", "delta")]


def vol(bx):
    v = Fraction(1)
    for lo, hi in bx:
        v *= max(Fraction(0), hi - lo)
    return v


def meet(a, b):
    return [(max(x[0], y[0]), min(x[1], y[1])) for x, y in zip(a, b)]


old_boxes = [box(b) for b in old]
m_rng = (min(b[0][0] for b in old_boxes), max(b[0][1] for b in old_boxes))
g_rng = (min(b[1][0] for b in old_boxes), max(b[1][1] for b in old_boxes))
d_rng = (min(b[2][0] for b in old_boxes), max(b[2][1] for b in old_boxes))
if quick:
    m_rng, g_rng = (Fraction("2.011"), Fraction("2.05")), (Fraction("0.44"), g_rng[1])
print("corner (bounding rectangle of the issue-20 undecided boxes):", m_rng, g_rng, d_rng)

done = [0]
t1 = time.perf_counter()


def progress(n):
    done[0] += n
    if done[0] % 100 == 0:
        print(f"  {done[0]} boxes, {time.perf_counter() - t1:.0f} s", flush=True)


MIN_WIDTH = 2.5e-4  # relative: 4.7e-5 in m, 5.7e-5 in gamma (the half-width ~4e-5 that S = -8e-5 needs at (2.2, 1/4))
res = box_theorem(tuple(map(str, m_rng)), tuple(map(str, g_rng)), tuple(map(str, d_rng)), initial=(4, 4, 1),
                  min_width=MIN_WIDTH, max_boxes=6000, order=2, progress=progress)
wall = time.perf_counter() - t1
print(res)
print(res.statement)
new_und = [box(b.to_dict()) for b in res.undecided]
old_vol = sum(vol(b) for b in old_boxes)
# the old undecided set still undecided: its intersection with the new undecided boxes (the new boxes tile the
# bounding rectangle, so the intersections are disjoint)
left = sum(vol(meet(a, b)) for a in new_und for b in old_boxes
           if all(x[0] < y[1] and y[0] < x[1] for x, y in zip(a, b)))
issue_vol = Fraction("1.2") * Fraction("2.75") * Fraction("2.75")
summary = {
    "corner_m": [str(x) for x in m_rng], "corner_gamma": [str(x) for x in g_rng], "corner_delta": [str(x) for x in d_rng],
    "old_undecided_boxes": len(old_boxes), "old_undecided_volume": str(old_vol),
    "old_undecided_share_of_issue_box": float(old_vol / issue_vol),
    "still_undecided_volume": str(left), "share_of_old_undecided_now_decided": float(1 - left / old_vol),
    "issue_box_share_decided": float(1 - left / issue_vol),
    "undecided_hull": ([[str(min(b[k][0] for b in new_und)), str(max(b[k][1] for b in new_und))] for k in range(3)]
                       if new_und else None),
    "min_width_relative": MIN_WIDTH, "wall_time_s": wall,
    "quick": quick,  # --quick covers a sub-rectangle only: the shares above then say nothing about the corner
}
print(json.dumps(summary, indent=1))
with open(out, "w") as f:
    json.dump({**res.to_dict(), "wall_time_s": wall, "summary": summary}, f, indent=1)
print("wrote", out)
