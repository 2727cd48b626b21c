"""The explorer's background computations: one orbit's section iterates streamed as they are computed, cancellable.

`stream_section` draws on the public streaming form of the section, `magrod.section_points`: the section loop of
`magrod.poincare_section` itself (the same integrator, the same propagate calls), so its points are those of
`poincare_section` for the same start to the last bit (tests/test_explorer.py checks it).  What a browser needs
is in the stream's options: a chunk after the first FIRST_CHUNK points, then every EMIT_INTERVAL seconds, and a
`cancel` event checked before every step to the next crossing (~0.2 ms apart), so a closed page or Ctrl-C stops
it at once.  The finished (or cancelled) run is the stream's genuine `PoincareResult`, which the export writes
with the files of `magrod poincare --out` (magrod/figures/poincare.py save_result).

`Worker` runs orbit jobs on a small thread pool (heyoka's propagate releases the GIL, so the server's event
loop stays responsive); each job has its own cancel event and `cancel_all` stops every job of a session.
"""
from __future__ import annotations

import threading
import time
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field

import numpy as np

import magrod as mr

from ..core.errors import ParameterError
from ..core.params import RodParams

FIRST_CHUNK = 8  # the first points go out after this many crossings (~2 ms): first light fast
EMIT_INTERVAL = 0.04  # then at most every 40 ms (the page polls at 50 ms; more often only costs transfers)

Start = mr.SectionStart  # a launch point on the section and the energy root chosen for it (magrod.section_start)


def solve_start(params: RodParams, h: float, theta0: float, ptheta0: float, psi0: float = 0.0,
                root="smallest") -> Start:
    """The start of an orbit by the section's rule (magrod.section_start: every root pbar_psi of Hbar = h, the
    chosen one by `root`).  Raises ParameterError ("h": no root on the admissible range, "mu": the square
    root of Hbar is imaginary for every pbar_psi, "theta0": outside (0, pi))."""
    return mr.section_start(params, h, theta0, ptheta0, psi0, root=root)


@dataclass
class Chunk:
    """Points found since the last chunk: theta (k,), pbar_theta (k,), the running max |Hbar - h| and count, and
    pbar_psi (k,) for the (theta, pbar_psi) and (pbar_theta, pbar_psi) projections of the page."""

    theta: np.ndarray
    ptheta: np.ndarray
    n_total: int
    max_abs_dH: float
    ppsi: np.ndarray | None = None
    psi: np.ndarray | None = None  # the branch of each point: psi = 0 or psi = pi (model.branch_of)


def stream_section(start: Start, iterates: int, *, direction="positive", cancel: threading.Event | None = None,
                   emit=None, t_max=None):
    """Iterate the section from `start`, handing Chunks to emit(chunk) as they come; returns the PoincareResult
    of what was computed (success=False with message "cancelled ..." if `cancel` was set first, or with the
    reason if the accuracy check failed)."""
    options = mr.SectionOptions(iterates=iterates, direction=direction, t_max=t_max)
    stream = mr.section_points(start, options, cancel=cancel, first=FIRST_CHUNK, every=EMIT_INTERVAL)
    max_dH = 0.0
    for c in stream:
        if emit is None or not c.points.shape[0]:
            continue
        max_dH = max(max_dH, float(np.max(np.abs(c.dH))))
        p = c.points
        emit(Chunk(p[:, 0].copy(), p[:, 2].copy(), c.n_total, max_dH, p[:, 3].copy(), p[:, 1].copy()))
    return stream.result


def growth_indicator(start: Start, t_max: float | None = None):
    """The chaos indicator of the orbit from `start` (magrod.lyapunov at the chosen root): a LyapunovResult."""
    from .. import lyapunov
    from ..chaos import DEFAULT_T_MAX

    return lyapunov(start.params, theta0=start.theta0, ptheta0=start.ptheta0, psi0=start.psi0, p_psi0=start.p_psi0,
                    t_max=DEFAULT_T_MAX if t_max is None else t_max)


# ----------------------------------------------------------------------------------------------------------
# jobs
# ----------------------------------------------------------------------------------------------------------
@dataclass
class Job:
    """One orbit computation: its cancel event, its future, and what it has produced so far."""

    id: int
    start: Start
    iterates: int
    direction: str
    cancel: threading.Event = field(default_factory=threading.Event)
    future: Future | None = None  # the section
    tail: Future | None = None  # the indicator, after the section
    submitted: float = field(default_factory=time.perf_counter)
    first_points_s: float | None = None  # seconds from submission to the first emitted chunk
    finished: threading.Event = field(default_factory=threading.Event)  # on_done has been called (or never will)


class Worker:
    """Two thread pools for one explorer session.  `submit(job, on_chunk, on_done)` runs the section (chunks to
    on_chunk(job, chunk)) on the section pool, then the chaos indicator on the second ("tail") pool, then
    on_done(job, result, indicator or exception); `call` (the rod of the selected orbit) runs on the tail pool too.
    Why two: a click's first points need one section thread, not a thread after every earlier orbit's indicator
    and rod (0.4 s and more each).  With one pool the latency of the k-th quick click grew with k (2.5 s for the
    first, 9 s for the 30th at load ~3, tests/test_explorer_browser.py); now the sections never queue behind the
    indicators.  Callbacks run on the worker threads: they must only hand data over (queues), never touch the page."""

    def __init__(self, max_workers: int = 2, name: str = "magrod-explore"):
        self._pool = ThreadPoolExecutor(max_workers=max_workers, thread_name_prefix=name)
        self._tail = ThreadPoolExecutor(max_workers=max_workers, thread_name_prefix=f"{name}-tail")
        self._jobs: dict[int, Job] = {}
        self._lock = threading.Lock()
        self._closed = False

    @property
    def running(self) -> int:
        """Jobs submitted and not finished (queued, computing their section or their indicator)."""
        with self._lock:
            return sum(1 for j in self._jobs.values() if j.future is not None and not j.finished.is_set())

    def submit(self, job: Job, on_chunk=None, on_done=None, indicator_t_max=None) -> Job:
        if self._closed:
            raise RuntimeError("worker is shut down")

        def emit(chunk):
            if job.first_points_s is None:
                job.first_points_s = time.perf_counter() - job.submitted
            if on_chunk is not None:
                on_chunk(job, chunk)

        def done(res, ind):
            try:
                if on_done is not None:
                    on_done(job, res, ind)
            finally:
                job.finished.set()

        def tail(res):
            try:
                ind = growth_indicator(job.start, indicator_t_max) if not job.cancel.is_set() else None
            except (ParameterError, RuntimeError) as exc:
                ind = exc
            except BaseException as exc:  # never a silent dead job: the page is told
                done(None, exc)
                raise
            done(res, ind)

        def run():
            try:
                res = stream_section(job.start, job.iterates, direction=job.direction, cancel=job.cancel, emit=emit)
            except BaseException as exc:  # never a silent dead job: the page is told
                done(None, exc)
                raise
            if job.cancel.is_set() or not res.n_points:
                done(res, None)
                return res
            try:
                job.tail = self._tail.submit(tail, res)
            except RuntimeError:  # shut down meanwhile: no indicator
                done(res, None)
            return res

        with self._lock:
            self._jobs[job.id] = job
            job.future = self._pool.submit(run)
        return job

    def call(self, fn, on_done) -> Future:
        """Run fn() on a tail thread (e.g. the rod of the selected orbit); on_done(value or exception)."""

        def run():
            try:
                out = fn()
            except Exception as exc:  # reported to the page, never raised into the pool
                out = exc
            on_done(out)

        return self._tail.submit(run)

    def warm(self, start: Start, direction: str = "positive") -> threading.Event:
        """Build, in every worker thread, the integrators it needs (they are cached per thread): the section
        integrator in the section threads, the indicator's tangent integrator and the rod's frame integrator in
        the tail threads.  From heyoka's disk cache this takes ~0.1 s per thread; afterwards the first points of a
        click come within milliseconds."""
        done = threading.Event()
        pools = (self._pool, self._tail)
        left = [len(pools)]
        lock = threading.Lock()

        def one_pool_done():
            with lock:
                left[0] -= 1
                if left[0] == 0:
                    done.set()

        def warm_section():
            stream_section(start, 2, direction=direction)  # builds (or loads) the section integrator

        def warm_tail():
            from ..core.systems import rod_frame_integrator

            growth_indicator(start, 20.0)
            rod_frame_integrator()

        for pool, fn in zip(pools, (warm_section, warm_tail)):
            barrier = threading.Barrier(pool._max_workers, action=one_pool_done, timeout=60)

            def one(fn=fn, barrier=barrier):
                fn()
                try:
                    barrier.wait()  # hold this thread until every thread has warmed: each gets its own copy
                except threading.BrokenBarrierError:
                    pass

            for _ in range(pool._max_workers):
                pool.submit(one)
        return done

    def cancel(self, job_id: int) -> None:
        with self._lock:
            job = self._jobs.get(job_id)
        if job is not None:
            self._cancel(job)

    @staticmethod
    def _cancel(job: Job) -> None:
        job.cancel.set()
        for f in (job.future, job.tail):
            if f is not None and f.cancel():  # never started: on_done will not be called
                job.finished.set()

    def cancel_all(self) -> int:
        """Cancel every job; returns how many were still running."""
        with self._lock:
            jobs = list(self._jobs.values())
        n = 0
        for j in jobs:
            if j.future is not None and not j.finished.is_set():
                n += 1
            self._cancel(j)
        return n

    def shutdown(self, timeout: float = 1.0) -> bool:
        """Cancel everything and wait (at most `timeout` s) for the threads; True if they all stopped."""
        self._closed = True
        self.cancel_all()
        for pool in (self._pool, self._tail):
            pool.shutdown(wait=False, cancel_futures=True)
        deadline = time.perf_counter() + timeout
        threads = [*getattr(self._pool, "_threads", ()), *getattr(self._tail, "_threads", ())]
        for t in threads:
            t.join(max(0.0, deadline - time.perf_counter()))
        with self._lock:  # a job cancelled with its pool before it started will never call on_done
            for j in self._jobs.values():
                if (j.future is not None and j.future.cancelled()) or (j.tail is not None and j.tail.cancelled()):
                    j.finished.set()
        return not any(t.is_alive() for t in threads)
