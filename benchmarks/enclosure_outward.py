"""Rewrite benchmarks/enclosure_boxes.json (the first run of enclosure_boxes.py) with outward-rounded exact end points.

That run stored S as Arb's string (4691 of the 4694 decided boxes read "[+/- x]", as if the ball contained
0) and S_lo / S_hi as floats of Arb's end points, which are not bounds.  A float of an exact end point is within one
ulp of it under any faithful rounding, so the float widened by two ulps outward *is* a bound; rounded outward to 12
significant digits it is stored as an exact decimal string, and S becomes "[S_lo, S_hi]".  The decided signs come
from the finite balls of the run (magrod.separatrix.enclosure._decide) and are unchanged; a box whose widened
interval did not keep its sign would be reported (none does).  New runs store outward strings directly
(enclosure.outward).

    python benchmarks/enclosure_outward.py [enclosure_boxes.json]
"""
import json
import math
import sys
from fractions import Fraction

args = [a for a in sys.argv[1:] if a != "--smoke"]
path = args[0] if args else "enclosure_boxes.json"
if "--smoke" in sys.argv:  # benchmarks/smoke.py: convert a copy of the shipped run, in a temporary directory
    import shutil
    import tempfile
    from pathlib import Path

    src = Path(__file__).with_name("enclosure_boxes.json")
    path = str(Path(tempfile.mkdtemp(prefix="magrod-smoke-")) / src.name)
    shutil.copy(src, path)
d = json.load(open(path))


def dec(f: Fraction, up: bool, digits=12) -> str:
    k = digits - 1 - math.floor(math.log10(abs(float(f))))
    n = math.ceil(f * Fraction(10) ** k) if up else math.floor(f * Fraction(10) ** k)
    q = Fraction(n) / Fraction(10) ** k
    assert (q >= f) if up else (q <= f)
    s = f"{abs(q.numerator) * 10**max(k, 0) // q.denominator}".rjust(max(k, 0) + 1, "0")
    ip, fp = s[: len(s) - max(k, 0)], s[len(s) - max(k, 0):].rstrip("0")
    return ("-" if q < 0 else "") + ip + (f".{fp}" if fp else "")


flipped = 0
for kind in ("decided", "undecided"):
    for b in d[kind]:
        lo, hi = b["S_lo"], b["S_hi"]
        if isinstance(lo, str):  # already converted
            continue
        if not (math.isfinite(lo) and math.isfinite(hi)):
            b["S_lo"], b["S_hi"] = "-inf", "inf"
        else:
            lo2 = math.nextafter(math.nextafter(lo, -math.inf), -math.inf)
            hi2 = math.nextafter(math.nextafter(hi, math.inf), math.inf)
            b["S_lo"], b["S_hi"] = dec(Fraction(lo2), False), dec(Fraction(hi2), True)
        b["S"] = f"[{b['S_lo']}, {b['S_hi']}]"
        if kind == "decided" and not ((b["sign"] < 0 and Fraction(b["S_hi"]) < 0)
                                      or (b["sign"] > 0 and Fraction(b["S_lo"]) > 0)):
            flipped += 1
d.setdefault("notes", []).append(
    "S_lo, S_hi are exact decimal strings, the run's floats widened by two ulps outward and rounded outward "
    "to 12 significant digits; S = [S_lo, S_hi] (was Arb's string, e.g. '[+/- 2.02]' for a ball in [-2.01, -0.23])")
json.dump(d, open(path, "w"), indent=1)
print(f"{path}: {len(d['decided'])} decided, {len(d['undecided'])} undecided converted; decided boxes whose widened "
      f"interval lost its sign: {flipped}")
