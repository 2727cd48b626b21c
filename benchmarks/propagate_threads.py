"""Benchmark (not a test): the bare propagate loop of the section lanes on 1 and 2 threads.

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
import warnings

import numpy as np

import _smoke  # noqa: E402  (benchmarks/: on sys.path as the script's directory)
from magrod.chaos import batch
from magrod.chaos.section import poincare_section
from magrod.core import systems


def make(mode):
    eps = float(np.finfo(float).eps)
    if mode == "noev":
        return systems.batch_integrator("body", events=[], tol=eps, batch_size=4)
    return batch.batch_section_integrator("positive", eps, 4)


def one(mode, nthreads, X, pars, n=3000):
    """nthreads threads, each with its own 4-lane integrator (lanes at four different crossings of Fig 4(a), so
    that a section call stops at the first of four phases) and n calls."""
    res = {}

    def run(i):
        ta = make(mode)
        ta.state[:] = X
        ta.pars[:] = pars
        ta.set_time(0.0)
        c0, w0 = time.thread_time(), time.perf_counter()
        for _ in range(n):
            ta.propagate_until(np.asarray(ta.time) + 50.0)
        res[i] = (time.thread_time() - c0, time.perf_counter() - w0)

    th = [threading.Thread(target=run, args=(i,)) for i in range(nthreads)]
    w0, p0 = time.perf_counter(), time.process_time()
    for t in th:
        t.start()
    for t in th:
        t.join()
    return time.perf_counter() - w0, time.process_time() - p0, res


def main():
    warnings.simplefilter("ignore")
    _smoke.from_argv()  # --smoke: 30 calls per thread, one round
    mode = sys.argv[1] if len(sys.argv) > 1 else "ev"
    counts = [int(sys.argv[2])] if len(sys.argv) > 2 else (1, 2)
    r = poincare_section("4a", iterates=8)
    X = r.body_points[[0, 3, 5, 7]].T.copy()
    pars = np.repeat(r.params.array()[:, None], 4, axis=1)
    for _ in range(_smoke.n(2, 1)):
        for n in counts:
            w, c, res = one(mode, n, X, pars, _smoke.n(3000, 30))
            print(mode, "threads", n, f"wall {w:.2f} cpu {c:.2f}",
                  {k: (round(a, 2), round(b, 2)) for k, (a, b) in res.items()}, flush=True)


if __name__ == "__main__":
    main()
