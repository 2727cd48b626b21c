"""Verify many certificates: on every core, never twice.  Scheduling only, outside the verifier's trust base.

`verify_many` runs `verify.verify` on independent certificates in spawned processes (one certificate per process
at a time, the most expensive first) and returns the results in the order the certificates were given.  What a
result says does not depend on what ran it: each certificate's checks are replayed by `verify.verify` in its own
serial order (Arb is deterministic), and the results are assembled in the caller's order.

A verified certificate is remembered in a cache directory, keyed by the SHA-256 of the certificate (canonical JSON)
and of the trust base (`trust_base_digest`: the source of verify.py and of every magrod module it imports,
transitively, with python-flint's version).  A changed certificate or a changed verifier (any module of its trust
base, the generated field included) has another key and is verified again; a rejected certificate is never
cached.  This module is not imported by verify.py: a test fences the trust base."""
from __future__ import annotations

import ast
import hashlib
import importlib.util
import json
import os
from pathlib import Path

CACHE_FORMAT = "magrod-verified/1"


def _module_file(name: str) -> Path | None:
    try:
        spec = importlib.util.find_spec(name)
    except (ImportError, ValueError):
        return None
    return Path(spec.origin) if spec is not None and spec.origin and spec.origin.endswith(".py") else None


def _imports(name: str, path: Path) -> set:
    """The magrod modules `path` (module `name`) imports, anywhere in it (function-level imports included)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[:len(base) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            if mod.startswith("magrod"):
                out.add(mod)
                out |= {f"{mod}.{a.name}" for a in node.names if _module_file(f"{mod}.{a.name}")}
        elif isinstance(node, ast.Import):
            out |= {a.name for a in node.names if a.name.startswith("magrod")}
    return {m for m in out if _module_file(m)}


def trust_base_modules(root: str = "magrod.proof.verify") -> list:
    """The magrod modules the verifier runs: `root` and every magrod module it imports, transitively (sorted)."""
    seen, todo = set(), [root]
    while todo:
        m = todo.pop()
        if m in seen:
            continue
        seen.add(m)
        todo.extend(_imports(m, _module_file(m)) - seen)
    return sorted(seen)


def trust_base_digest() -> str:
    """SHA-256 over the trust base's module names and sources, and python-flint's version (Arb's rounding)."""
    import flint

    h = hashlib.sha256()
    h.update(f"python-flint {flint.__version__}\n".encode())
    for m in trust_base_modules():
        h.update(f"{m}\n".encode())
        h.update(_module_file(m).read_bytes())
    return h.hexdigest()


def certificate_digest(cert: dict) -> str:
    """SHA-256 of the certificate's canonical JSON (key order and white space do not matter)."""
    return hashlib.sha256(json.dumps(cert, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def _key(cert: dict, base: str) -> str:
    return hashlib.sha256(f"{certificate_digest(cert)}:{base}".encode()).hexdigest()


def _cached(cache_dir: Path, cert: dict, base: str):
    """The remembered VerifyResult of `cert` under trust base `base`, or None (missing, unreadable, other key)."""
    from .verify import VerifyResult

    p = cache_dir / f"{_key(cert, base)}.json"
    try:
        rec = json.loads(p.read_text())
    except (OSError, ValueError, UnicodeDecodeError):
        return None
    r = rec.get("result") if isinstance(rec, dict) else None
    if (not isinstance(r, dict) or rec.get("format") != CACHE_FORMAT or rec.get("trust_base_sha256") != base
            or rec.get("certificate_sha256") != certificate_digest(cert) or r.get("ok") is not True):
        return None
    try:
        return VerifyResult(ok=True, reason=str(r["reason"]), checks=list(r["checks"]),
                            wall_time_s=float(r["wall_time_s"]), theorem=str(r["theorem"]), slopes=dict(r["slopes"]),
                            values=dict(r["values"]))
    except (KeyError, TypeError, ValueError):
        return None


def _remember(cache_dir: Path, cert: dict, base: str, res) -> None:
    from ..core.io import atomic_write_json, record_writes

    if not res.ok:
        return
    cache_dir.mkdir(parents=True, exist_ok=True)
    with record_writes():  # a remembered verification is not an output of the figure that asked for it
        atomic_write_json(cache_dir / f"{_key(cert, base)}.json",
                          {"format": CACHE_FORMAT, "certificate_sha256": certificate_digest(cert),
                           "trust_base_sha256": base,
                           # the wall time unrounded (to_dict keeps 3 decimals): a remembered result then rounds for
                           # the sidecar exactly as the fresh one did
                           "result": {**res.to_dict(), "wall_time_s": res.wall_time_s}})


def cost(cert: dict) -> float:
    """A rough CPU cost (seconds) of verifying `cert`, to start the most expensive first (no result depends on it)."""
    kind = cert.get("kind")
    if kind == "section_horseshoe":
        return 6.0 * len(cert.get("sets") or ()) + 10.0
    if kind == "section_fixed_point":
        return 5.0
    return 12.0 * max(1, len(cert.get("crossings") or ()))


def workers_default() -> int:
    """The CPUs this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:
        return max(1, os.cpu_count() or 1)


def _child_init(parent_pid: int) -> None:
    """In each verifying process: Ctrl-C is the parent's to handle, and the process dies with its parent."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        import ctypes

        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent_pid:
        os._exit(1)


def _verify_one(cert: dict, inner_workers):
    from .kernel.pool import JOB_LOCK
    from .verify import verify

    with JOB_LOCK:  # one verification at a time per process: python-flint's precision is process-wide
        return verify(cert, workers=inner_workers)


def dask_mapper(client):
    """A mapper for verify.verify(mapper=...): a horseshoe's sets re-flown on the Dask cluster of `client`.

    Parameters
    ----------
    client : dask.distributed.Client
        A client of a cluster whose workers are other processes than this one (python-flint's working precision is
        process-wide; each worker process runs one verifier job at a time).

    Returns
    -------
    callable
        mapper(fn, jobs): one task per job (the certificate scattered once, no retries: a failing task is its check's
        failure), the results yielded in the order of the jobs; closing the iterator early (a rejection) cancels the
        tasks left.

    Raises
    ------
    ParameterError
        Naming "scheduler", if a worker runs in this process.

    Examples
    --------
    >>> from dask.distributed import Client                             # doctest: +SKIP
    >>> from magrod.proof import dask_mapper, load_certificate, verify_certificate
    >>> with Client("tcp://127.0.0.1:8786") as client:                   # doctest: +SKIP
    ...     res = verify_certificate(load_certificate("horseshoe.json"), mapper=dask_mapper(client))
    """

    import os

    here = [a for a, pid in client.run(os.getpid).items() if pid == os.getpid()]
    if here:
        from ..core.errors import ParameterError

        raise ParameterError("scheduler", f"worker {here[0]} runs in this process, whose python-flint precision "
                                          "the verifier sets: give a cluster of worker processes")

    def mapper(fn, jobs):
        jobs = list(jobs)
        if not jobs:
            return
        shared = {}  # the certificate (every job's first argument) scattered once, not sent per task

        def arg(a):
            if isinstance(a, dict):
                key = id(a)
                if key not in shared:
                    # in a list: a dict given to scatter is a mapping of keys to data, each scattered alone
                    shared[key] = client.scatter([a], hash=False)[0]
                return shared[key]
            return a

        futs = [client.submit(fn, *map(arg, job), pure=False, retries=0) for job in jobs]
        try:
            for f in futs:
                yield f.result()
        finally:
            client.cancel(futs)

    return mapper


def verify_many(certs, *, workers: int | None = None, cache_dir=None, progress=None, client=None) -> list:
    """Verify independent certificates; the VerifyResults in the order of `certs`.

    Parameters
    ----------
    certs : sequence of (name, dict)
        The certificates and the names `progress` reports them by.
    workers : int, optional
        Processes (default: the CPUs this process may use; 1: everything in this process, the horseshoes' sets
        then on every core as `verify.verify` does by default).
    cache_dir : path, optional
        Where verified certificates are remembered (None: nothing remembered, everything verified).
    progress : callable, optional
        progress(done, total, name, cached) in this process after each certificate.
    client : dask.distributed.Client, optional
        Verify on that cluster instead of `workers` local processes: each horseshoe's sets as tasks (dask_mapper),
        every other certificate as one task; the checks are replayed here in each certificate's serial order.

    Returns
    -------
    list of VerifyResult
        One per certificate, in the given order; a remembered one is the stored result (its wall_time_s is the
        time of the run that verified it).

    Notes
    -----
    CertificateError of a malformed certificate propagates as from `verify.verify`.
    """
    import concurrent.futures as cf
    import multiprocessing

    certs = list(certs)
    n = len(certs)
    workers = workers_default() if workers is None else max(1, int(workers))
    cache_dir = Path(cache_dir) if cache_dir is not None else None
    base = trust_base_digest() if cache_dir is not None else None
    results: list = [None] * n
    done = 0

    def finished(i, res, cached):
        nonlocal done
        results[i] = res
        done += 1
        if cache_dir is not None and not cached:
            _remember(cache_dir, certs[i][1], base, res)
        if progress is not None:
            progress(done, n, certs[i][0], cached)

    todo = []
    for i, (_, cert) in enumerate(certs):
        hit = _cached(cache_dir, cert, base) if cache_dir is not None else None
        if hit is not None:
            finished(i, hit, True)
        else:
            todo.append(i)
    todo.sort(key=lambda i: -cost(certs[i][1]))  # the most expensive first; ties keep the given order
    if client is not None:
        _on_cluster(client, certs, todo, finished)
        return results
    if workers == 1 or len(todo) <= 1:
        for i in sorted(todo):
            finished(i, _verify_one(certs[i][1], None if workers > 1 else 1), False)
        return results
    ex = cf.ProcessPoolExecutor(max_workers=min(workers, len(todo)), mp_context=multiprocessing.get_context("spawn"),
                                initializer=_child_init, initargs=(os.getpid(),))
    ok = False
    try:
        futs = {ex.submit(_verify_one, certs[i][1], 1): i for i in todo}
        for fut in cf.as_completed(futs):
            finished(futs[fut], fut.result(), False)
        ok = True
    finally:
        if not ok:
            for proc in list((getattr(ex, "_processes", None) or {}).values()):
                proc.kill()
        ex.shutdown(wait=ok, cancel_futures=True)
    return results


def _on_cluster(client, certs, todo, finished) -> None:
    """verify_many's certificates on a Dask cluster: every kind but the horseshoe as one task each, submitted first;
    then each horseshoe verified in this thread (one at a time: python-flint's precision is process-wide) with its
    sets mapped onto the cluster; results handed to `finished` in that order."""
    from .verify import verify

    mapper = dask_mapper(client)
    horse = [i for i in todo if certs[i][1].get("kind") == "section_horseshoe"]
    whole = [(client.submit(_verify_one, certs[i][1], 1, pure=False, retries=0), i) for i in todo if i not in horse]
    try:
        for i in horse:
            finished(i, verify(certs[i][1], mapper=mapper), False)
        for fut, i in whole:
            finished(i, fut.result(), False)
    finally:
        client.cancel([f for f, _ in whole])
