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
        emit(Chunk(p[:, 0].copy(), p[:, 2].copy(), c.n_total, max_dH, p[:, 3].copy()))
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
    future: Future | None = None
    submitted: float = field(default_factory=time.perf_counter)
    first_points_s: float | None = None  # seconds from submission to the first emitted chunk


class Worker:
    """A thread pool for one explorer session.  `submit(job, on_chunk, on_done)` runs the section (chunks to
    on_chunk(job, chunk)), then the chaos indicator, then on_done(job, result, indicator or exception).
    Callbacks run on the worker thread: they must only hand data over (queues), never touch the page."""

    def __init__(self, max_workers: int = 2, name: str = "magrod-explore"):
        self._pool = ThreadPoolExecutor(max_workers=max_workers, thread_name_prefix=name)
        self._jobs: dict[int, Job] = {}
        self._lock = threading.Lock()
        self._closed = False

    @property
    def running(self) -> int:
        """Jobs submitted and not finished (queued or computing)."""
        with self._lock:
            return sum(1 for j in self._jobs.values() if j.future is not None and not j.future.done())

    def submit(self, job: Job, on_chunk=None, on_done=None, indicator_t_max=None) -> Job:
        if self._closed:
            raise RuntimeError("worker is shut down")

        def emit(chunk):
            if job.first_points_s is None:
                job.first_points_s = time.perf_counter() - job.submitted
            if on_chunk is not None:
                on_chunk(job, chunk)

        def run():
            try:
                res = stream_section(job.start, job.iterates, direction=job.direction, cancel=job.cancel, emit=emit)
                ind = None
                if not job.cancel.is_set() and res.n_points:
                    try:
                        ind = growth_indicator(job.start, indicator_t_max)
                    except (ParameterError, RuntimeError) as exc:
                        ind = exc
                if on_done is not None:
                    on_done(job, res, ind)
                return res
            except BaseException as exc:  # never a silent dead job: the page is told
                if on_done is not None:
                    on_done(job, None, exc)
                raise

        with self._lock:
            self._jobs[job.id] = job
            job.future = self._pool.submit(run)
        return job

    def call(self, fn, on_done) -> Future:
        """Run fn() on a worker thread (e.g. the rod of the selected orbit); on_done(value or exception)."""

        def run():
            try:
                out = fn()
            except Exception as exc:  # reported to the page, never raised into the pool
                out = exc
            on_done(out)

        return self._pool.submit(run)

    def warm(self, start: Start, direction: str = "positive") -> threading.Event:
        """Build, in every worker thread, the integrators a click needs (they are cached per thread): the section
        integrator, the indicator's tangent integrator and the rod's frame integrator.  From heyoka's disk cache
        this takes ~0.1 s per thread; afterwards the first points of a click come within milliseconds."""
        done = threading.Event()
        barrier = threading.Barrier(self._pool._max_workers, action=done.set, timeout=60)

        def one():
            from ..core.systems import rod_frame_integrator

            stream_section(start, 2, direction=direction)  # builds (or loads) the section integrator
            growth_indicator(start, 20.0)
            rod_frame_integrator()
            try:
                barrier.wait()  # hold this thread until every thread has warmed: each gets its own copy
            except threading.BrokenBarrierError:
                pass

        for _ in range(self._pool._max_workers):
            self._pool.submit(one)
        return done

    def cancel(self, job_id: int) -> None:
        with self._lock:
            job = self._jobs.get(job_id)
        if job is not None:
            job.cancel.set()
            if job.future is not None:
                job.future.cancel()

    def cancel_all(self) -> int:
        """Cancel every job; returns how many were still running."""
        with self._lock:
            jobs = list(self._jobs.values())
        n = 0
        for j in jobs:
            if j.future is not None and not j.future.done():
                n += 1
            j.cancel.set()
            if j.future is not None:
                j.future.cancel()
        return n

    def shutdown(self, timeout: float = 1.0) -> bool:
        """Cancel everything and wait (at most `timeout` s) for the threads; True if they all stopped."""
        self._closed = True
        self.cancel_all()
        self._pool.shutdown(wait=False, cancel_futures=True)
        deadline = time.perf_counter() + timeout
        for t in list(getattr(self._pool, "_threads", ())):
            t.join(max(0.0, deadline - time.perf_counter()))
        return not any(t.is_alive() for t in getattr(self._pool, "_threads", ()))
