"""Many Poincare sections at once: the lanes of heyoka's SIMD batch integrator, refilled as orbits finish, on all
cores (issue 18).  Numerics only; `magrod.chaos.section.poincare_section` is the public face (it builds the jobs,
this module runs them).

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
from dataclasses import dataclass, field

import heyoka as hy
import numpy as np

from ..core import systems
from ..core.params import RodParams

NBODY = systems.dim("body")
_CHART_PSI = systems.chart_index("psi")
# outcome codes of the batch propagate: the section is terminal event 0 -> -1 - 0
_EVENT = -1
_TIME_LIMIT = int(hy.taylor_outcome.time_limit)
_SUCCESS = int(hy.taylor_outcome.success)
_CHUNK = 1024  # initial per-orbit point buffer (grown by doubling)


@dataclass
class Job:
    """One orbit of a batched section run: its rod, level, chart start, the chosen root and the body start."""

    index: int
    params: RodParams
    h: float
    theta0: float
    ptheta0: float
    psi0: float
    p_psi0: float
    roots: np.ndarray
    root_index: int
    x0: np.ndarray
    key: str | None = None
    pars: np.ndarray = field(init=False)

    def __post_init__(self):
        self.pars = self.params.array()


@systems.per_thread
def _batch_section_integrator(direction: str, tol: float, width: int):
    return systems.batch_integrator("body", events=[("section", direction)], tol=tol, batch_size=width)


def batch_section_integrator(direction: str, tol: float, width: int | None = None):
    """The body-frame batch integrator with the section event in every lane, one per thread and (direction, tol,
    batch width; default systems.batch_width())."""
    return _batch_section_integrator(direction, tol, int(width or systems.batch_width()))


class _Lane:
    __slots__ = ("job", "raw", "times", "n", "reported", "t0_wall")

    def __init__(self, job: Job, cap: int):
        self.job = job
        self.raw = np.empty((cap, NBODY))
        self.times = np.empty(cap)
        self.n = 0
        self.reported = 0
        self.t0_wall = time.perf_counter()

    def record(self, x, t, iterates) -> None:
        if self.n == self.raw.shape[0]:
            cap = min(iterates, 2 * self.n)
            self.raw = np.vstack([self.raw, np.empty((cap - self.n, NBODY))])
            self.times = np.concatenate([self.times, np.empty(cap - self.n)])
        self.raw[self.n] = x
        self.times[self.n] = t
        self.n += 1


class _Queue:
    """The shared list of jobs: worker threads take the next one under a lock."""

    def __init__(self, jobs):
        self._jobs = list(jobs)
        self._i = 0
        self._lock = threading.Lock()

    def take(self):
        with self._lock:
            if self._i >= len(self._jobs):
                return None
            job = self._jobs[self._i]
            self._i += 1
            return job


def _keep(x, pars, branch) -> bool:
    if branch == "any":
        return True
    c = np.cos(systems.body_to_euler(np.ascontiguousarray(x), pars)[_CHART_PSI])
    return bool((c > 0) == (branch == "0"))


def _worker(queue: _Queue, finish, *, iterates, t_max, direction, branch, tol, progress) -> None:
    ta = batch_section_integrator(direction, float(tol))
    b = ta.batch_size
    lanes: list[_Lane | None] = [None] * b
    t_stop = np.zeros(b)
    cap = min(iterates, _CHUNK)

    n_active = [0]

    def fill(j):
        job = queue.take()
        if lanes[j] is not None:
            n_active[0] -= 1
        if job is None:  # park the lane: zero-length steps from now on
            lanes[j] = None
            t_stop[j] = ta.dtime[0][j]
            return
        n_active[0] += 1
        hi, lo = (np.array(a) for a in ta.dtime)
        hi[j] = lo[j] = 0.0
        ta.set_dtime(hi, lo)  # the other lanes keep their double-length time
        ta.state[:, j] = job.x0
        ta.pars[:, j] = job.pars
        ta.reset_cooldowns(j)
        t_stop[j] = t_max(job)
        lanes[j] = _Lane(job, cap)

    def done(j, success, message, t_final):
        L = lanes[j]
        if progress is not None and L.n > L.reported:
            progress(L.n - L.reported)
        finish(L.job, L.raw[: L.n], L.times[: L.n], float(t_final), success, message,
               time.perf_counter() - L.t0_wall)
        fill(j)

    for j in range(b):
        fill(j)
    tv = ta.time  # a read-only view of the lanes' times (updated in place by heyoka)
    state = ta.state
    lane_ids = range(b)
    any_branch = branch == "any"
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
            if any_branch or _keep(state[:, j], L.job.pars, branch):
                L.record(state[:, j], tv[j], iterates)
                if L.n == iterates:
                    done(j, True, "ok", tv[j])
                elif progress is not None and L.n - L.reported >= 200:
                    progress(L.n - L.reported)
                    L.reported = L.n
        calls += 1
        # a lane at its t_max idles (zero-length steps) until seen here: look when no lane stopped on the
        # section (then some lane must be at its limit, or failed) and every 64 calls (a numpy test costs ~2 us)
        if not hit or not calls % 64:
            for j in lane_ids:
                L = lanes[j]
                if L is not None and tv[j] >= t_stop[j]:
                    hit = True
                    done(j, False, f"t_max = {t_stop[j]:g} reached after {L.n} of {iterates} iterates (max-time "
                                   f"guard; raise t_max or check that the orbit crosses sin(psi) = 0)", tv[j])
        if not hit:
            res = ta.propagate_res
            for j in lane_ids:
                if lanes[j] is not None and int(res[j][0]) not in (_SUCCESS, _TIME_LIMIT, _EVENT):
                    done(j, False, f"integration failed at t = {tv[j]:g} ({res[j][0]}) after {lanes[j].n} "
                                   f"iterates", tv[j])


def run(jobs, finish, *, iterates, t_max, direction="positive", branch="any", tol=None, workers=None,
        progress=None) -> None:
    """Integrate every job's orbit in SIMD lanes on `workers` threads (default: all cores, at most one per
    batch of jobs); finish(job, raw (n, 9) body points, times (n,), final_time, success, message, wall_s) is
    called once per job as its orbit ends (from the worker threads).  t_max: callable job -> time limit."""
    jobs = list(jobs)
    if not jobs:
        return
    b = systems.batch_width()
    n_threads = max(1, min(int(workers or os.cpu_count() or 1), -(-len(jobs) // b)))
    tol = float(tol) if tol else float(np.finfo(float).eps)
    queue = _Queue(jobs)
    kw = dict(iterates=iterates, t_max=t_max, direction=direction, branch=branch, tol=tol, progress=progress)
    if n_threads == 1:
        _worker(queue, finish, **kw)
        return
    with ThreadPoolExecutor(max_workers=n_threads) as ex:
        for f in [ex.submit(_worker, queue, finish, **kw) for _ in range(n_threads)]:
            f.result()
