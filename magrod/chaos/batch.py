"""Many Poincare sections at once: the lanes of heyoka's SIMD batch integrator, refilled as orbits finish, on all
cores.  Numerics only; `magrod.chaos.section.poincare_section` is the public face (it builds the
orbits, section._Orbit: the crossing handling and the assembly every section loop shares; this module runs them
in lanes).

How the lanes run
-----------------
One batch integrator of the body-frame system (systems.batch_integrator, width systems.batch_width()) per
worker thread, with the section sin(psi) = 0 as a *stopping terminal event* in every lane (hy.t_event_batch,
direction as requested).  heyoka's batch `propagate_until(t_stop)` steps all lanes together and returns as soon
as ANY lane lands on its event (that lane's step is cut at the event, exactly as in the scalar integrator; the
other lanes have completed whole steps and simply continue on the next call), or when every lane reached its
own t_stop.  So each call yields one section point, no lane ever idles while others finish a crossing, and a
lane's step sequence is the one the scalar integrator takes from the same start: results do not depend on which
lane or which neighbours an orbit gets (tests/test_batch.py compares lanes bit for bit with the scalar path).

A lane whose orbit is done (its iterate count reached, its t_max guard hit, or a failed step) is refilled at
once with the next start from a queue shared by the worker threads; lanes left without work are parked with
t_stop equal to their own time (zero-length steps, free in SIMD).  heyoka releases the GIL in propagate, so the
threads run on all cores.  Time is reset per lane with set_dtime (the double-length time of the other lanes is
kept), event cooldowns per lane with reset_cooldowns(lane).

Cost: per section point one propagate call (~10 us of Python) plus the Taylor steps to it, of which a SIMD
batch of b lanes does b at the price of ~1.  benchmarks/README.md has the measured numbers.
"""
from __future__ import annotations

import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import heyoka as hy
import numpy as np

from ..core import systems

# outcome codes of the batch propagate: the section is terminal event 0 -> -1 - 0
_EVENT = -1
_TIME_LIMIT = int(hy.taylor_outcome.time_limit)
_SUCCESS = int(hy.taylor_outcome.success)


@systems.per_thread
def _batch_section_integrator(direction: str, tol: float, width: int):
    return systems.batch_integrator("body", events=[("section", direction)], tol=tol, batch_size=width)


def batch_section_integrator(direction: str, tol: float, width: int | None = None):
    """The body-frame batch integrator with the section event in every lane, one per thread and (direction, tol,
    batch width; default systems.batch_width())."""
    return _batch_section_integrator(direction, tol, int(width or systems.batch_width()))


class _Queue:
    """The shared list of orbits: worker threads take the next one under a lock."""

    def __init__(self, orbits):
        self._orbits = list(orbits)
        self._i = 0
        self._lock = threading.Lock()

    def take(self):
        with self._lock:
            if self._i >= len(self._orbits):
                return None
            orbit = self._orbits[self._i]
            self._i += 1
            return orbit


def _worker(queue: _Queue, *, direction, tol, key=systems.PAPER_KEY, width=None) -> None:
    ta = (batch_section_integrator(direction, float(tol), width) if key == systems.PAPER_KEY
          else systems.model_section_batch(key, direction, float(tol), width))
    b = ta.batch_size
    lanes: list = [None] * b
    t_stop = np.zeros(b)

    n_active = [0]

    def fill(j):
        orbit = queue.take()
        if lanes[j] is not None:
            n_active[0] -= 1
        if orbit is None:  # park the lane: zero-length steps from now on
            lanes[j] = None
            t_stop[j] = ta.dtime[0][j]
            return
        n_active[0] += 1
        hi, lo = (np.array(a) for a in ta.dtime)
        hi[j] = lo[j] = 0.0
        ta.set_dtime(hi, lo)  # the other lanes keep their double-length time
        ta.state[:, j] = orbit.x0
        ta.pars[:, j] = orbit.pars
        ta.reset_cooldowns(j)
        t_stop[j] = orbit.t_max
        orbit.t0_wall = time.perf_counter()
        lanes[j] = orbit

    def done(j, success, message, t_final):
        lanes[j].finish(t_final, success, message)
        fill(j)

    for j in range(b):
        fill(j)
    tv = ta.time  # a read-only view of the lanes' times (updated in place by heyoka)
    state = ta.state
    lane_ids = range(b)
    calls = 0
    while n_active[0]:
        ta.propagate_until(t_stop)
        # which lanes stopped on the section: their event cooldown has just been armed (elapsed time 0).
        # Reading the cooldowns costs ~0.5 us, propagate_res ~10 us (a list of tuples of enums): the latter is
        # read only when no lane stopped on the section and none reached its t_stop (a failed step).
        cds = ta.te_cooldowns
        hit = False
        for j in lane_ids:
            c = cds[j][0]
            if c is None or c[0] != 0.0:
                continue
            L = lanes[j]
            if L is None:
                continue
            hit = True
            x = state[:, j]
            if L.keep(x) and L.record(x, tv[j]):  # the crossing handling of every section loop (section._Orbit)
                done(j, True, "ok", tv[j])
        calls += 1
        # a lane at its t_max idles (zero-length steps) until seen here: look when no lane stopped on the
        # section (then some lane must be at its limit, or failed) and every 64 calls (a numpy test costs ~2 us)
        if not hit or not calls % 64:
            for j in lane_ids:
                L = lanes[j]
                if L is not None and tv[j] >= t_stop[j]:
                    hit = True
                    done(j, False, L.time_limit_message(), tv[j])
        if not hit:
            res = ta.propagate_res
            for j in lane_ids:
                if lanes[j] is not None and int(res[j][0]) not in (_SUCCESS, _TIME_LIMIT, _EVENT):
                    done(j, False, lanes[j].failure_message(tv[j], res[j][0]), tv[j])


def run(orbits, *, direction="positive", tol=None, workers=None, key=systems.PAPER_KEY, processes=True) -> None:
    """Integrate every orbit in SIMD lanes on `workers` threads (default: all cores, at most one per batch of
    orbits).  An orbit is a `magrod.chaos.section._Orbit` (the crossing handling every section loop shares): a lane
    starts it from `orbit.x0`, `orbit.pars` with the guard `orbit.t_max`, hands it each crossing
    (`keep(x)`, then `record(x, t)`, True once its iterates are reached) and ends it with
    `finish(t, success, message)`, which assembles `orbit.result` (called from the worker threads)."""
    orbits = list(orbits)
    # key: the model (systems.model_key) whose body field and section event the lanes integrate
    if not orbits:
        return
    b = systems.batch_width()
    n_threads = max(1, min(int(workers or os.cpu_count() or 1), -(-len(orbits) // b)))
    tol = float(tol) if tol else float(np.finfo(float).eps)
    queue = _Queue(orbits)
    kw = dict(direction=direction, tol=tol, key=key, width=b)
    if n_threads == 1:
        _worker(queue, **kw)
        return
    if processes and _processes_ok() and _picklable(orbits[0]):
        _run_processes(orbits, n_threads, b, kw)
        return
    with ThreadPoolExecutor(max_workers=n_threads) as ex:
        for f in [ex.submit(_worker, queue, **kw) for _ in range(n_threads)]:
            f.result()


# --------------------------------------------------------------------------------------------------------------
# two or more workers: processes.  heyoka's propagate releases the GIL, but every crossing costs ~10 us of Python
# in the lane loop, and with two threads that Python is serialised: measured 1.1-1.5x for 2 threads against
# 1.5-2.1x for 2 processes (benchmarks/batch_ratios.py).  Each process runs the same lane loop on a contiguous
# share of the orbits; a lane's steps do not depend on its neighbours, so the points are those of one thread.
# --------------------------------------------------------------------------------------------------------------
# One pool per call, shut down (its processes joined) before the call returns: a pool kept for the process would be
# a process-wide side effect of a library call, and a kept pool inside a worker of another pool (a figure of
# `magrod reproduce` running its panels on two workers) hung that worker's exit, and with it the outer pool's
# shutdown.  The spawn costs ~1 s per call (heyoka's disk cache spares the JIT compilation).
def _pool(n: int):
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor

    # spawn, never fork: a forked child of a process running heyoka's (LLVM's) threads may deadlock
    return ProcessPoolExecutor(max_workers=n, mp_context=mp.get_context("spawn"))


def _processes_ok() -> bool:
    """Spawned workers re-import the main module: only when that is harmless (no main file, or one that guards
    its top level with `if __name__ == "__main__"`), and only while heyoka's disk cache is on (a run repeated
    with freshly compiled code, systems.bypass_disk_cache, stays in this process)."""
    import sys

    if not hy.llvm_state.get_diskcache_enabled():
        return False
    main = sys.modules.get("__main__")
    path = getattr(main, "__file__", None)
    if not path:
        return True
    try:
        with open(path, encoding="utf-8", errors="replace") as fh:
            text = fh.read()
    except OSError:
        return False
    return "__main__" in text


def _picklable(orbit) -> bool:
    import pickle

    try:
        pickle.dumps((orbit.start, orbit.options))
        return True
    except Exception:  # noqa: BLE001 - an unpicklable start (a user's object): the threads instead
        return False


def _process_task(orbit_type, starts, options, kw) -> list:
    """In a worker process: the orbits of `starts` (section._Orbit, passed as `orbit_type`: this module does not
    import the section module) through the lane loop; their results."""
    orbits = [orbit_type(s, options) for s in starts]
    # a model other than the paper's rod is known to this process only once its body is registered (model_body):
    # the parent registered it, a fresh worker has not (the lanes look the body up by key)
    system = getattr(starts[0], "system", None) if starts else None
    if system is not None and kw.get("key") != systems.PAPER_KEY:
        systems.model_body(system)
    _worker(_Queue(orbits), **kw)
    return [o.result for o in orbits]


def _run_processes(orbits, n: int, b: int, kw) -> None:
    """The orbits in contiguous shares of about equal size (a whole number of SIMD batches where possible) on n
    processes; each orbit's result, progress and wall time handed back to it here."""
    N = len(orbits)
    cuts = [round(i * N / n) for i in range(n + 1)]
    if N >= n * b:
        cuts = [min(N, round(i * -(-N // b) / n) * b) for i in range(n + 1)]
        cuts[-1] = N
    parts = [(lo, hi) for lo, hi in zip(cuts[:-1], cuts[1:]) if hi > lo]
    with _pool(n) as ex:
        futs = [(lo, hi, ex.submit(_process_task, type(orbits[lo]), [o.start for o in orbits[lo:hi]],
                                   orbits[lo].options, kw))
                for lo, hi in parts]
        for lo, hi, f in futs:
            for o, res in zip(orbits[lo:hi], f.result()):
                o.result = res
                o.n = res.n_points
                if o.progress is not None and res.n_points > o.reported:
                    o.progress(res.n_points - o.reported)
                    o.reported = res.n_points
