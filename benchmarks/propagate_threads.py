"""Benchmark (not a test): the bare propagate loop of the section lanes on 1 and 2 threads (issue 28, item 5).

    python benchmarks/propagate_threads.py ev       # section event: short calls (one crossing of any lane each)
    python benchmarks/propagate_threads.py noev     # no event: long calls (50 time units each)
    python benchmarks/propagate_threads.py ev 2     # only 2 threads (e.g. under `perf stat -e context-switches`)

Each thread owns a batch integrator of 4 lanes and calls propagate_until 3000 times with almost no Python in
between; printed: the wall and process CPU time, and per thread (thread CPU, thread wall).  If the two threads ran
on two cores, the process would use ~2 CPU-seconds per wall second; a process-wide lock taken once per call (the
GIL, re-acquired on every return from propagate) shows as ~1 when the calls are short."""
import sys
import threading
import time

import numpy as np
from magrod.chaos import batch
from magrod.core import systems
from magrod.chaos.portrait import grid_starts
import warnings; warnings.simplefilter("ignore")
mode = sys.argv[1]
def make():
    ta = systems.batch_integrator("body", events=[], tol=float(np.finfo(float).eps), batch_size=4) if mode=="noev" else batch.batch_section_integrator("positive", float(np.finfo(float).eps))
    return ta
# start: Fig 4a
from magrod.chaos.section import poincare_section
r = poincare_section("4a", iterates=8)
X = r.body_points[[0, 3, 5, 7]].T.copy()
def work(ta, n):
    for k in range(n):
        ta.propagate_until(np.asarray(ta.time) + 50.0)
def one(nthreads, n=3000):
    tas = []
    def mk():
        ta = make(); ta.state[:] = X; ta.pars[:] = np.repeat(r.params.array()[:, None], 4, axis=1); tas.append(ta)
    # build integrators in their threads (per_thread cache)
    res = {}
    def run(i):
        ta = make(); ta.state[:] = X; ta.pars[:] = np.repeat(r.params.array()[:, None], 4, axis=1)
        ta.set_time(0.0)
        c0 = time.thread_time(); w0 = time.perf_counter()
        work(ta, n)
        res[i] = (time.thread_time()-c0, time.perf_counter()-w0)
    th = [threading.Thread(target=run, args=(i,)) for i in range(nthreads)]
    w0 = time.perf_counter(); p0 = time.process_time()
    [t.start() for t in th]; [t.join() for t in th]
    return time.perf_counter()-w0, time.process_time()-p0, res
NT = [int(sys.argv[2])] if len(sys.argv) > 2 else (1, 2)
for rep in range(2):
    for n in NT:
        w, c, res = one(n)
        print(mode, "threads", n, f"wall {w:.2f} cpu {c:.2f}", {k: (round(a,2), round(b,2)) for k,(a,b) in res.items()}, flush=True)
