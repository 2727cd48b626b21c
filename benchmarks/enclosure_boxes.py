"""Benchmark: the parameter-box theorem for S on the box m in [1, 2.2], gamma in [0.25, 3],
delta in [0.25, 3] (inside the saddle range: m_c = 2 sqrt(1.25) = 2.236 at gamma = 0.25), and the cost of one
enclosure.  Prints the decided/undecided boxes, the statement proved, the wall time; writes the result as JSON
(argument 1, default enclosure_boxes.json).  Not a test: tests/test_enclosure.py checks small boxes.

    python benchmarks/enclosure_boxes.py [out.json] [--quick]
"""
import json
import sys
import time
from fractions import Fraction

from magrod.separatrix.enclosure import box_theorem, enclose_S

out = next((a for a in sys.argv[1:] if not a.startswith("--")), "enclosure_boxes.json")
quick = "--quick" in sys.argv
# --smoke (benchmarks/smoke.py): one enclosure and the quick box undivided, written into a temporary directory
smoke = "--smoke" in sys.argv
if smoke:
    import tempfile
    from pathlib import Path

    out = str(Path(tempfile.mkdtemp(prefix="magrod-smoke-")) / "enclosure_boxes.json")

t0 = time.perf_counter()
for p in [("1.7", 1, 1)] if smoke else [("1.7", 1, 1), ("1.0", 0, 1), ("2.2", "0.25", "0.25")]:
    r = enclose_S(*p)
    print(f"enclose_S{p}: {r.S.str(radius=True)}  T = {r.T}  tail <= {r.tail_bound:.1e}  "
          f"{r.evaluations} evaluations  {r.wall_time_s:.2f} s")
print(f"three enclosures: {time.perf_counter() - t0:.2f} s")

done = [0]


def progress(n):
    done[0] += n
    if done[0] % 50 == 0:
        print(f"  {done[0]} boxes, {time.perf_counter() - t1:.0f} s", flush=True)


t1 = time.perf_counter()
box = (("1.6", "1.8"), ("0.9", "1.1"), ("0.25", "3")) if quick or smoke else (("1.0", "2.2"), ("0.25", "3"), ("0.25", "3"))
res = box_theorem(*box, initial=(1, 1, 1) if smoke else (12, 11, 1), min_width=0.5 if smoke else 2e-3,
                  progress=progress)
wall = time.perf_counter() - t1
print(res)
print(res.statement)
print(f"boxes evaluated {res.boxes_evaluated}, decided {len(res.decided)}, undecided {len(res.undecided)}, zeros "
      f"{len(res.zeros)}; wall {wall:.0f} s ({wall / max(1, res.boxes_evaluated):.2f} s per box)")
if res.undecided:
    print("undecided:", [(b.m, b.gamma, b.delta, b.S) for b in res.undecided[:20]])
if res.decided:
    smallest = min((float(Fraction(b.m[1]) - Fraction(b.m[0])), b.m, b.gamma) for b in res.decided)
    print("smallest decided box (width in m, m, gamma):", smallest)
with open(out, "w") as f:
    json.dump({**res.to_dict(), "wall_time_s": wall}, f, indent=1)
print("wrote", out)
