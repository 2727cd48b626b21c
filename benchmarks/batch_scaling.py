"""Benchmark (not a test): why two threads of batched lanes gain less than 2x.

    python benchmarks/batch_scaling.py --json benchmarks/batch_scaling.json
    MAGROD_BATCH_WIDTH=8 python benchmarks/batch_scaling.py --json benchmarks/batch_scaling_w8.json

The job is the batch benchmark's ensemble: 64 orbits x 1000 section iterates on the Fig 4(a) level (the first 64 accessible
points of a 10 x 10 grid of starts), run by magrod/chaos/batch.py on 1 and on 2 threads, alternated, --repeat
times.  The machine is shared, so wall time alone says little; every run also records, per worker thread
(by wrapping batch._worker, batch.batch_section_integrator and the finish callback; batch.py is not changed):

  cpu_s          the thread's CPU time (time.thread_time): work done, whatever the load
  wall_s         the thread's wall time from its start to its last lane's end
  propagate      wall and CPU time inside heyoka's propagate_until (GIL released there) and the number of calls
  finish_s       CPU time of the finish callback (assembling a SectionResult: numpy under the GIL)
  lane_s         the sum over lanes of the time a lane carried an orbit (lane occupancy = lane_s / (b wall_s))
  tail_s         how long the thread ran after the shared queue was empty (its lanes draining, some parked)

and for the whole run: the process CPU time (time.process_time, all threads) and `uptime`.  From these:
  GIL + foreign-load wait = wall_s - cpu_s per thread (a thread that is runnable but not running: waiting for
  the GIL, or for a core another process holds), split by the in-propagate part (no GIL is held there, so wall
  minus CPU inside propagate is the foreign load alone) and the rest.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import threading
import time


from magrod.chaos import batch
from magrod.chaos.portrait import grid_starts
from magrod.chaos.section import poincare_sections as poincare_section
from magrod.core import systems


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return f"load {os.getloadavg()}"


class _Timed:
    """A batch integrator whose propagate_until is timed (wall and thread CPU); every other attribute forwards."""

    def __init__(self, ta, rec):
        object.__setattr__(self, "_ta", ta)
        object.__setattr__(self, "_rec", rec)

    def propagate_until(self, t):
        w0, c0 = time.perf_counter(), time.thread_time()
        r = self._ta.propagate_until(t)
        self._rec["prop_wall"] += time.perf_counter() - w0
        self._rec["prop_cpu"] += time.thread_time() - c0
        self._rec["calls"] += 1
        return r

    def __getattr__(self, k):
        return getattr(self._ta, k)

    def __setattr__(self, k, v):
        setattr(self._ta, k, v)


_local = threading.local()
_records: list = []
_queue_empty_at: list = []


def _instrument():
    orig_worker, orig_integrator, orig_take = batch._worker, batch.batch_section_integrator, batch._Queue.take

    def worker(queue, **kw):
        # the lanes finish their orbits themselves (section._Orbit.finish): counted where the queue hands them out;
        # finish_cpu and lane_s are no longer separable from the propagate loop and stay 0
        rec = dict(prop_wall=0.0, prop_cpu=0.0, calls=0, finish_cpu=0.0, lane_s=0.0, orbits=0,
                   start=time.perf_counter(), cpu0=time.thread_time())
        _local.rec = rec
        orig_worker(queue, **kw)
        rec["end"] = time.perf_counter()
        rec["cpu_s"] = time.thread_time() - rec.pop("cpu0")
        _records.append(rec)

    def integrator(direction, tol, width=None):
        return _Timed(orig_integrator(direction, tol, width), _local.rec)

    def take(self):
        job = orig_take(self)
        if job is not None and getattr(_local, "rec", None) is not None:
            _local.rec["orbits"] += 1
        if job is None and not _queue_empty_at:
            _queue_empty_at.append(time.perf_counter())
        return job

    batch._worker, batch.batch_section_integrator, batch._Queue.take = worker, integrator, take
    return lambda: (setattr(batch, "_worker", orig_worker), setattr(batch, "batch_section_integrator",
                    orig_integrator), setattr(batch._Queue, "take", orig_take))


def one_run(starts, iterates, workers, instrumented):
    _records.clear()
    _queue_empty_at.clear()
    undo = _instrument() if instrumented else (lambda: None)
    try:
        p0, w0 = time.process_time(), time.perf_counter()
        res = poincare_section("4a", starts=starts, iterates=iterates, workers=workers)
        wall, cpu = time.perf_counter() - w0, time.process_time() - p0
    finally:
        undo()
    out = {"workers": workers, "wall_s": wall, "process_cpu_s": cpu, "ok": all(r.success for r in res),
           "final_times": [float(r.final_time) for r in res] if hasattr(res[0], "final_time") else None}
    if instrumented:
        b = systems.batch_width()
        q = _queue_empty_at[0] if _queue_empty_at else None
        th = []
        for r in _records:
            wall_t = r["end"] - r["start"]
            th.append({"cpu_s": r["cpu_s"], "wall_s": wall_t, "propagate_wall_s": r["prop_wall"],
                       "propagate_cpu_s": r["prop_cpu"], "propagate_calls": r["calls"],
                       "finish_cpu_s": r["finish_cpu"], "orbits": r["orbits"],
                       "lane_occupancy": r["lane_s"] / (b * wall_t),
                       "tail_s": (r["end"] - q) if q is not None else None,
                       "python_cpu_s": r["cpu_s"] - r["prop_cpu"],
                       "wait_outside_propagate_s": (wall_t - r["prop_wall"]) - (r["cpu_s"] - r["prop_cpu"]),
                       "wait_inside_propagate_s": r["prop_wall"] - r["prop_cpu"]})
        out["threads"] = th
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--n", type=int, default=64)
    ap.add_argument("--iterates", type=int, default=1000)
    ap.add_argument("--json", default=None)
    ap.add_argument("--processes", action="store_true", help="only: 1 thread vs 2 threads vs 2 processes")
    ap.add_argument("--smoke", action="store_true", help="run once on a tiny span (benchmarks/smoke.py, CI): 8 "
                    "orbits x 10 iterates, once; measures nothing, writes nothing")
    a = ap.parse_args(argv)
    if a.smoke:
        a.repeat, a.n, a.iterates, a.json = 1, 8, 10, None
    if a.processes:
        rows = processes(a.n, a.iterates, a.repeat)
        if a.json:
            with open(a.json, "w") as fh:
                json.dump({"width": systems.batch_width(), "rows": rows}, fh, indent=1)
        return 0
    starts = grid_starts("4a", theta0=(0.1, 3.0, 10), ptheta0=(-1.0, 1.0, 10))[: a.n]
    poincare_section("4a", starts=starts[:8], iterates=10, workers=2)  # JIT load / compile once
    out = {"uptime_before": uptime(), "width": systems.batch_width(), "cores": os.cpu_count(), "n": len(starts),
           "iterates": a.iterates, "runs": []}
    print(out["uptime_before"], f"width {out['width']}", flush=True)
    for rep in range(a.repeat):
        for workers in (1, 2):
            for instrumented in (False, True):
                r = one_run(starts, a.iterates, workers, instrumented)
                r.update(repeat=rep, instrumented=instrumented, uptime=uptime())
                out["runs"].append(r)
                thr = "; ".join(f"cpu {t['cpu_s']:.2f} wall {t['wall_s']:.2f} prop {t['propagate_cpu_s']:.2f}/"
                                f"{t['propagate_wall_s']:.2f} calls {t['propagate_calls']} finish "
                                f"{t['finish_cpu_s']:.2f} occ {t['lane_occupancy']:.2f} tail {t['tail_s']:.2f}"
                                for t in r.get("threads", []))
                print(f"workers {workers} instr {instrumented}: wall {r['wall_s']:.2f} cpu {r['process_cpu_s']:.2f}"
                      f" | {thr} | {r['uptime'][-40:]}", flush=True)
    out["uptime_after"] = uptime()
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1)
    return 0


def _half(args):
    starts, iterates = args
    import warnings as _w

    _w.simplefilter("ignore")
    from magrod.chaos.section import poincare_sections as ps

    t0 = time.perf_counter()
    res = ps("4a", starts=starts, iterates=iterates, workers=1)
    return time.perf_counter() - t0, len(res)


def processes(n=64, iterates=1000, repeat=3):
    """The same ensemble on 1 thread, on 2 threads, and split in two halves over 2 processes (one GIL each; the
    pool is started and warmed before the timing).  A GIL hand-off per section point is what the process variant
    removes; its wall time against the 2-thread one is the gain a process-based batch.run would bring."""
    from concurrent.futures import ProcessPoolExecutor

    starts = grid_starts("4a", theta0=(0.1, 3.0, 10), ptheta0=(-1.0, 1.0, 10))[:n]
    halves = [(starts[0::2], iterates), (starts[1::2], iterates)]
    rows = []
    with ProcessPoolExecutor(2) as ex:
        list(ex.map(_half, [(starts[:4], 5)] * 2))  # start and warm both processes
        poincare_section("4a", starts=starts[:8], iterates=10, workers=2)
        for rep in range(repeat):
            row = {}
            order = ("t1", "t2", "p2") if rep % 2 == 0 else ("p2", "t2", "t1")  # alternated: the load drifts
            for what in order:
                t0, c0 = time.perf_counter(), time.process_time()
                if what == "p2":
                    inner = list(ex.map(_half, halves))
                    row["processes_inner_wall_s"] = [w for w, _ in inner]
                else:
                    poincare_section("4a", starts=starts, iterates=iterates, workers=int(what[1]))
                    row[f"threads_{what[1]}_cpu_s"] = time.process_time() - c0
                row[{"t1": "threads_1_wall_s", "t2": "threads_2_wall_s", "p2": "processes_2_wall_s"}[what]] = \
                    time.perf_counter() - t0
            row["order"] = list(order)
            row["uptime"] = uptime()
            rows.append(row)
            print(json.dumps(row), flush=True)
    return rows


if __name__ == "__main__":
    sys.exit(main())
