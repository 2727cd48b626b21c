"""Benchmark (not a test): the wall time of `magrod reproduce --quick`, the time its help text quotes.

    python benchmarks/reproduce_time.py --json benchmarks/reproduce_time.json

Runs the command as a user would (a fresh output directory, --quiet), --repeat times, and records each wall time
with the machine's core count and load average before and after (a shared machine's wall time is pessimistic: say
so, never hide it).  `magrod reproduce --help` reads the minimum from benchmarks/reproduce_time.json when the file
is present (a source checkout), so the help cannot quote a time nobody measured."""
from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--json", default="benchmarks/reproduce_time.json")
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--smoke", action="store_true", help="a tiny span: one figure (--only 2) once, nothing written "
                    "(CI runs every benchmark so)")
    a = ap.parse_args()
    if a.smoke:
        with tempfile.TemporaryDirectory(prefix="magrod-reproduce-time-") as d:
            t = time.perf_counter()
            r = subprocess.run([sys.executable, "-m", "magrod.cli", "reproduce", "--quick", "--quiet", "--only", "2",
                                "--out", d], capture_output=True, text=True)
            print({"command": "magrod reproduce --quick --only 2", "wall_s": round(time.perf_counter() - t, 1),
                   "returncode": r.returncode})
            if r.returncode:
                raise SystemExit(f"reproduce_time --smoke: exit {r.returncode}: {r.stderr.strip()[-300:]}")
        return
    runs = []
    for _ in range(a.repeat):
        with tempfile.TemporaryDirectory(prefix="magrod-reproduce-time-") as d:
            load0 = os.getloadavg()
            t = time.perf_counter()
            r = subprocess.run([sys.executable, "-m", "magrod.cli", "reproduce", "--quick", "--quiet", "--out", d],
                               capture_output=True, text=True)
            wall = time.perf_counter() - t
            runs.append({"wall_s": round(wall, 1), "returncode": r.returncode, "load_before": load0,
                         "load_after": os.getloadavg()})
    import magrod

    out = {"command": "magrod reproduce --quick", "runs": runs, "min_wall_s": min(x["wall_s"] for x in runs),
           "cores": os.cpu_count(), "machine": platform.machine(), "python": platform.python_version(),
           "magrod": magrod.__version__, "date": time.strftime("%Y-%m-%d")}
    with open(a.json, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
