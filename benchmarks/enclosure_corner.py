"""Benchmark: the corner of the parameter box of benchmarks/enclosure_boxes.py left undecided by the mean value
form of box_theorem (benchmarks/enclosure_boxes.json: 3515 boxes in m in [1287/640, 11/5] x gamma in [1/4, 61/128], all
delta in [1/4, 3], next to m_c = 2 sqrt(1 + gamma)), run again with the second-order form (box_theorem(order=2)).
Covers the bounding rectangle of those boxes, then reports which share of the old undecided set is now decided.
Writes the result as JSON (argument 1, default enclosure_corner.json).  Not a test: tests/test_enclosure.py checks
small boxes.

    python benchmarks/enclosure_corner.py [out.json] [--quick] [--budget=N] [--resume=previous.json] [--smoke]
"""
import json
import sys
import time
from fractions import Fraction
from pathlib import Path

from magrod.separatrix.enclosure import BoxResult, box_theorem

HERE = Path(__file__).resolve().parent
out = next((a for a in sys.argv[1:] if not a.startswith("--")), "enclosure_corner.json")
smoke = "--smoke" in sys.argv  # a tiny span (CI runs every benchmark so): --quick's corner, a budget of 2 boxes
quick = "--quick" in sys.argv or smoke

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
print("corner (bounding rectangle of the undecided boxes):", m_rng, g_rng, d_rng)

CELLS = 4  # the bounding rectangle in 4 x 4 cells, each its own box_theorem run, recorded as it finishes
# Minimum box width, absolute: 1e-3 of the corner's span in each direction (1.9e-4 in m, 2.3e-4 in gamma).  At
# (2.2, 1/4, 1/4), S = -8.0e-5 and the second-order form needs half-widths ~4e-5 (its second-derivative bound is
# ~2.4e4 there), so boxes at the tip next to (11/5, 1/4) are given up at this width.
MIN_FRACTION = Fraction(1, 1000)
BUDGET = int(next((a.split("=")[1] for a in sys.argv if a.startswith("--budget=")), 2 if smoke else 3600))  # box evaluations in all (~0.8 s each on one core): the cells are run easiest first until it is spent
TIP_LEVELS = 2  # the cell at the tip (m_hi, gamma_lo) is split again into 4 x 4 sub-cells, TIP_LEVELS times


def split(iv, n):
    return [(iv[0] + (iv[1] - iv[0]) * i / n, iv[0] + (iv[1] - iv[0]) * (i + 1) / n) for i in range(n)]


def cells_of(mr, gr, level):
    """4 x 4 cells of mr x gr, easiest first (far from the tip (m_hi, gamma_lo), where |S| is smallest); the tip
    cell is itself split TIP_LEVELS times (so an exhausted budget leaves only the hardest small cells)."""
    cs = [(a, b) for a in split(mr, CELLS) for b in split(gr, CELLS)]
    cs.sort(key=lambda c: (-(mr[1] - c[0][1]) / (mr[1] - mr[0]) - (c[1][0] - gr[0]) / (gr[1] - gr[0]), c))
    if level < TIP_LEVELS:
        return cs[:-1] + cells_of(cs[-1][0], cs[-1][1], level + 1)
    return cs


cells = cells_of(m_rng, g_rng, 0)
min_m, min_g = (m_rng[1] - m_rng[0]) * MIN_FRACTION, (g_rng[1] - g_rng[0]) * MIN_FRACTION
t1 = time.perf_counter()
decided, undecided, zeros, runs = [], [], [], []
evaluated, wall_before = 0, 0.0
resume = next((a.split("=", 1)[1] for a in sys.argv if a.startswith("--resume=")), None)
if resume:  # continue a run: keep its decided boxes, run its undecided ones (in their order) as the cells
    prev = json.loads(Path(resume).read_text())
    decided = [BoxResult(**{**b, "m": tuple(b["m"]), "gamma": tuple(b["gamma"]), "delta": tuple(b["delta"])})
               for b in prev["decided"]]
    zeros, runs, evaluated, wall_before = prev["zeros"], prev["cells"], prev["boxes_evaluated"], prev["wall_time_s"]
    cells = [tuple((Fraction(b[k][0]), Fraction(b[k][1])) for k in ("m", "gamma")) for b in prev["undecided"]]
    BUDGET += evaluated
for i, (cm, cg) in enumerate(cells):
    if evaluated >= BUDGET:  # not attempted: the whole cell is undecided
        undecided.append(BoxResult(tuple(map(str, cm)), tuple(map(str, cg)), tuple(map(str, d_rng)), "not evaluated",
                                   None, "-inf", "inf", {}))
        runs.append({"m": [str(x) for x in cm], "gamma": [str(x) for x in cg], "statement": "not attempted (budget)"})
        continue
    # box_theorem's min_width is relative to its own box and the same in every direction: take the larger ratio
    # (a resumed box already at the minimum width may still be bisected once: min_width must be < 1)
    mw = min(float(max(min_m / (cm[1] - cm[0]), min_g / (cg[1] - cg[0]))), 0.999)
    r = box_theorem(tuple(map(str, cm)), tuple(map(str, cg)), tuple(map(str, d_rng)), initial=(1, 1, 1),
                    min_width=mw, max_boxes=BUDGET - evaluated, order=2)
    decided += r.decided
    undecided += r.undecided
    zeros += r.zeros
    evaluated += r.boxes_evaluated
    runs.append({"m": r.m, "gamma": r.gamma, "statement": r.statement, "boxes_evaluated": r.boxes_evaluated,
                 "decided": len(r.decided), "undecided": len(r.undecided), "min_width": mw,
                 "wall_time_s": r.wall_time_s})
    print(f"cell {i + 1}/{len(cells)} m {r.m} gamma {r.gamma}: {len(r.decided)} decided {r.signs}, "
          f"{len(r.undecided)} undecided, {r.boxes_evaluated} boxes, {r.wall_time_s:.0f} s "
          f"(total {evaluated} boxes, {time.perf_counter() - t1:.0f} s)", flush=True)
    with open(out + ".partial", "w") as f:  # everything so far, so an interrupted run loses nothing
        json.dump({"cells_done": runs, "decided": [b.to_dict() for b in decided],
                   "undecided": [b.to_dict() for b in undecided]}, f)
wall = time.perf_counter() - t1 + wall_before
signs = {}
for b in decided:
    signs[str(b.sign)] = signs.get(str(b.sign), 0) + 1
print(f"{len(decided)} decided {signs}, {len(undecided)} undecided, {len(zeros)} zeros, {evaluated} boxes, {wall:.0f} s")
new_und = [box(b.to_dict()) for b in undecided]
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
    "boxes_evaluated": evaluated, "decided_boxes": len(decided), "undecided_boxes": len(undecided),
    "signs": signs, "min_width_fraction_of_corner": str(MIN_FRACTION), "budget": BUDGET, "wall_time_s": wall,
    "quick": quick,  # --quick covers a sub-rectangle only: the shares above then say nothing about the corner
}
print(json.dumps(summary, indent=1))
with open(out, "w") as f:
    json.dump({"summary": summary, "m": [str(x) for x in m_rng], "gamma": [str(x) for x in g_rng],
               "delta": [str(x) for x in d_rng], "order": 2, "prec_bits": 64, "min_width_fraction_of_corner": str(MIN_FRACTION), "budget": BUDGET,
               "cells": runs, "signs": signs, "boxes_evaluated": evaluated, "wall_time_s": wall,
               "decided": [b.to_dict() for b in decided], "undecided": [b.to_dict() for b in undecided],
               "zeros": zeros}, f, indent=1)
print("wrote", out)
