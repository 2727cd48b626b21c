"""The horseshoe verifier's sets, checked in child processes: scheduling only.  Each set's checks
(horseshoe_lam2.set_source) are recorded in a fresh interpreter and replayed through the parent's `claim` in the serial
order, so the checks, the first rejection and its reason are the serial verifier's whatever ran them.
"""
from __future__ import annotations

import json
import threading
from pathlib import Path

from ...core.errors import ParameterError
from .. import ball, fields
from .horseshoe_lam2 import set_source
from .horseshoe_sets import _hs_branch_boxes, _hs_set
from .schema import CertificateError, frac


def _hs_workers(workers) -> int:
    """The number of processes for the horseshoe's sets: `workers`, or None: the CPUs this process may use."""
    if workers is not None:
        return max(1, int(workers))
    import os

    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


#: serialises the verifier's jobs within a process (python-flint's precision context is process-wide, not per thread)
JOB_LOCK = threading.Lock()


class _Stop(Exception):
    """A worker's recorded check failed: stop there (the parent raises the rejection when it replays it)."""


_MALFORMED = (KeyError, TypeError, ValueError, IndexError, ZeroDivisionError, AttributeError)


def _hs_record(cert, i, boxes: list) -> dict:
    """One set's checks (set_source, with the branch boxes of every set), recorded: {"i", "recs": [(name, holds,
    how)], "err": None or [type name, message, malformed?]}; the recording stops at the first check that fails (as
    the serial verifier does)."""
    recs = []

    def rec(name, holds, how):
        recs.append((name, bool(holds), how))
        if not holds:
            raise _Stop

    err = None
    try:
        s = cert["settings"]
        with ball.workprec(int(s["prec"]), int(s["series_cap"])):
            set_source(cert, i, int(s["order"]), fields.gen, rec, boxes)
    except _Stop:
        pass
    except Exception as e:  # noqa: BLE001 - handed to the parent, which raises it where the serial run would
        err = [type(e).__name__, str(e)[:120], isinstance(e, _MALFORMED) and not isinstance(e, (ParameterError,
                                                                                                ball.InexactBall))]
    return {"i": i, "recs": recs, "err": err}


def _hs_worker_boxes(cert) -> tuple:
    """The branch boxes of every set, once per worker process (they depend on the certificate only), or the error
    that each of the worker's sets then reports."""
    try:
        s = cert["settings"]
        p = fields.ExactParams(**{kk: frac(cert["params"][kk]) for kk in fields.PARAMS})
        with ball.workprec(int(s["prec"]), int(s["series_cap"])):
            sets = [_hs_set(d) for d in cert["sets"]]
            brs = [d.get("branch", "0") for d in cert["sets"]]
            return [B for _ok, B in _hs_branch_boxes(cert, p.balls(), sets, brs, fields.gen)], None
    except Exception as e:  # noqa: BLE001 - handed to the parent, which raises it where the serial run would
        return None, [type(e).__name__, str(e)[:120], isinstance(e, _MALFORMED) and not isinstance(e, (ParameterError,
                                                                                                       ball.InexactBall))]


def _hs_worker_main() -> None:
    """A worker process of _hs_sources_parallel: the certificate and its set indices on stdin (one JSON document),
    one JSON line per set on stdout, in the order of the indices."""
    import sys

    job = json.loads(sys.stdin.read())
    boxes, err = _hs_worker_boxes(job["cert"])
    for i in job["sets"]:
        r = {"i": int(i), "recs": [], "err": err} if err is not None else _hs_record(job["cert"], int(i), boxes)
        sys.stdout.write(json.dumps(r) + "\n")
        sys.stdout.flush()


def _hs_record_job(cert, i) -> dict:
    """One set's recorded checks from the certificate alone (the branch boxes recomputed: ~0.02 s): a job a mapper
    (a Dask cluster, magrod.proof.schedule.dask_mapper) runs anywhere; its record is replayed by _hs_sources_mapped.
    One job at a time per process: python-flint's working precision is process-wide, so two threads of a worker
    computing at once could each run at the other's precision (seen: a fixed-point enclosure 100x too wide)."""
    with JOB_LOCK:
        boxes, err = _hs_worker_boxes(cert)
        if err is not None:
            return {"i": int(i), "recs": [], "err": err}
        return _hs_record(cert, int(i), boxes)


def _hs_sources_mapped(cert, k, mapper, claim) -> None:
    """_hs_source for i = 0 .. k-1 run by `mapper(fn, jobs)` (an iterator of fn(*job) in the order of jobs, wherever
    it runs them: scheduling outside this kernel), the records replayed through `claim` in the order of i; on a
    rejection the iterator is closed (the mapper cancels what is left)."""
    results = mapper(_hs_record_job, [(cert, i) for i in range(k)])
    try:
        for i, r in enumerate(results):
            _replay(r, i, claim)
    finally:
        close = getattr(results, "close", None)
        if close is not None:
            close()


def _replay(r, i, claim) -> None:
    """A set's record, replayed as the serial verifier would have made its checks (the same rejection and reason)."""
    if r["i"] != i:
        raise RuntimeError(f"worker result for N{r['i']} where N{i} was expected")
    for name, holds, how in r["recs"]:
        claim(name, holds, how)
    if r["err"] is not None:
        kind, msg, malformed = r["err"]
        if kind == "InexactBall":
            raise ball.InexactBall(msg)
        if malformed:
            raise CertificateError(f"malformed certificate ({kind}: {msg})")
        raise RuntimeError(f"horseshoe verifier worker, N{i}: {kind}: {msg}")


def _hs_sources_parallel(cert, k, workers, claim) -> None:
    """_hs_source for i = 0 .. k-1 in `workers` child processes (fresh interpreters running _hs_worker_main on
    sets i = w, w + workers, ...: no multiprocessing, so nothing of the caller's __main__ is re-run and no
    process-wide state is changed), their records replayed through `claim` in the order of i, so the checks, the
    first rejection and its reason are the serial verifier's; on a rejection the workers are stopped."""
    import os
    import subprocess
    import sys

    root = str(Path(__file__).resolve().parents[3])  # the magrod the caller runs, for the children too
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([root] + [v for v in [os.environ.get("PYTHONPATH")] if v]))
    # one thread each (the QR of Lohner's step is 4 x 4): BLAS threads of two workers would compete for the cores
    env.update(OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    code = "from magrod.proof.kernel.pool import _hs_worker_main; _hs_worker_main()"
    procs = []
    try:
        for w in range(workers):
            pr = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                  env=env, text=True)
            procs.append(pr)
            pr.stdin.write(json.dumps({"cert": cert, "sets": list(range(w, k, workers))}))
            pr.stdin.close()
        for i in range(k):
            line = procs[i % workers].stdout.readline()
            if not line:
                raise RuntimeError(f"the horseshoe verifier's worker for N{i} ended without a result "
                                   f"(exit status {procs[i % workers].wait()})")
            _replay(json.loads(line), i, claim)
    finally:
        for pr in procs:
            if pr.poll() is None:
                pr.kill()
            pr.wait()
            pr.stdout.close()
