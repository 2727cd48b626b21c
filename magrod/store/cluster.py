"""The Dask cluster's lifecycle for chaos maps: a LocalCluster started and stopped, a running scheduler reached and
checked, and the machine's limits checked before either (the wing's second half; the zarr store is
magrod.store.tiles).

Nothing here touches process-wide settings: the command line owns the loggers (magrod.cli.chaosmap's
quiet_distributed) and the signals (magrod.cli.children_immune, passed in as `start_guard` by the caller)."""
from __future__ import annotations

import json
import logging
import os
import time
from pathlib import Path

from ..core.errors import EnvironmentFault, ParameterError


# ------------------------------------------------------------------------------------------------------------
# a LocalCluster
# ------------------------------------------------------------------------------------------------------------
def worker_env() -> None:
    """Single-threaded math in every worker: nothing a worker inherits may depend on how many there are."""
    for k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ[k] = "1"


def start_local_cluster(workers: int):
    """(cluster, client, worker pids) of a LocalCluster of `workers` single-threaded processes.  The workers are
    started with the terminal's signals ignored (magrod.cli.children_immune when called from the CLI), so that
    stopping them is the parent's job."""
    from dask.distributed import Client, LocalCluster

    worker_env()
    # dashboard off; the scheduler still serves its health routes over HTTP: on a free port (":0"), not 8787,
    # so that concurrent maps do not fight over it
    cluster = LocalCluster(n_workers=int(workers), threads_per_worker=1, processes=True, dashboard_address=None,
                           scheduler_kwargs={"dashboard": False, "dashboard_address": ":0"},
                           silence_logs=logging.CRITICAL)
    try:
        client = Client(cluster)
        pids = sorted(client.run(os.getpid).values())
    except BaseException:
        cluster.close()
        raise
    return cluster, client, pids


def stop_local_cluster(cluster, client, pids, *, interrupted=False) -> None:
    """Close client and cluster; after an interruption kill the worker processes first (they ignore the terminal's
    signals, and a running tile would otherwise finish first)."""
    import signal

    if interrupted:
        for pid in pids:
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:
                pass
    for closer in (client, cluster):
        if closer is None:
            continue
        try:
            closer.close(timeout=5) if interrupted else closer.close()
        except BaseException:  # noqa: BLE001 - closing after an interruption: nothing more to say
            if not interrupted:
                raise


def close_quietly(client) -> None:
    try:
        client.close(timeout=5)
    except BaseException:  # noqa: BLE001
        pass


def check_cluster(client, idle_since, worker_timeout):
    """While waiting: the scheduler must answer and have a worker at least every worker_timeout seconds."""
    try:
        n = len(client.nthreads())
    except Exception as exc:  # noqa: BLE001 - the scheduler is gone or unreachable
        raise EnvironmentFault("scheduler", f"lost the Dask scheduler ({type(exc).__name__}: "
                                            f"{' '.join(str(exc).split())[:120]})") from None
    if n:
        return None
    now = time.monotonic()
    if idle_since is None:
        return now
    if now - idle_since > worker_timeout:
        raise EnvironmentFault("scheduler", f"the Dask cluster has had no worker for {worker_timeout:g} s while tiles "
                                            f"were waiting (workers died or were stopped)")
    return idle_since


def normalise_address(text: str) -> str:
    """tcp://HOST:PORT, tls://HOST:PORT or HOST:PORT (taken as tcp://) -> the address; ParameterError("scheduler")
    for anything else (inproc:// exists only inside one Python process; other protocols are not supported)."""
    s = str(text).strip()
    if "://" in s:
        proto, rest = s.split("://", 1)
    else:
        proto, rest = "tcp", s
    if proto == "inproc":
        raise ParameterError("scheduler", f"{s!r}: inproc:// addresses exist only inside one Python process; give "
                                          "tcp://HOST:PORT (or HOST:PORT) of a running scheduler")
    if proto not in ("tcp", "tls"):
        raise ParameterError("scheduler", f"{s!r}: protocol {proto}:// is not supported; give tcp://HOST:PORT, "
                                          "HOST:PORT or tls://HOST:PORT")
    host, sep, port = rest.rpartition(":")
    host = host[1:-1] if host.startswith("[") and host.endswith("]") else host
    if not sep or not host or not port.isdigit() or not 0 < int(port) < 65536 or "/" in rest:
        raise ParameterError("scheduler", f"expected tcp://HOST:PORT or HOST:PORT (port 1-65535), got {s!r}")
    return f"{proto}://{rest}"


def read_scheduler_file(path) -> str:
    """The address in a scheduler file (`dask scheduler --scheduler-file PATH`); ParameterError("scheduler_file")
    if it is missing, unreadable or has no address."""
    p = Path(path)
    try:
        d = json.loads(p.read_text())
    except FileNotFoundError:
        raise ParameterError("scheduler_file", f"no such file: {str(p)!r}") from None
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise ParameterError("scheduler_file", f"{str(p)!r} is not a Dask scheduler file "
                                               f"({type(exc).__name__})") from None
    addr = d.get("address") if isinstance(d, dict) else None
    if not isinstance(addr, str):
        raise ParameterError("scheduler_file", f"{str(p)!r} is not a Dask scheduler file (no \"address\")")
    try:
        return normalise_address(addr)
    except ParameterError as exc:
        raise ParameterError("scheduler_file", f"{str(p)!r}: {exc.message}") from None


def _tls_security():
    """Dask's TLS settings from its configuration (distributed.comm.tls.*), or None if none are given."""
    import dask

    tls = dask.config.get("distributed.comm.tls", default={}) or {}
    client = tls.get("client") or {}
    if not (tls.get("ca-file") and client.get("cert")):
        return None
    from distributed.security import Security

    return Security()


def probe(address: str, timeout: float) -> None:
    """Fail fast and clearly if nothing Dask listens at `address`: a TCP connect and the scheduler's greeting
    (a Dask server sends its handshake first) within `timeout` seconds.  ParameterError("scheduler") naming what
    was found: nothing (refused, unreachable), a silent TCP service, an HTTP server (e.g. the dashboard port), or
    another service."""
    import socket

    proto, rest = address.split("://", 1)
    host, _, port = rest.rpartition(":")
    host = host.strip("[]")
    try:
        sock = socket.create_connection((host, int(port)), timeout=timeout)
    except socket.timeout:
        raise ParameterError("scheduler", f"no answer from {address} within {timeout:g} s (host down or port "
                                          "filtered)") from None
    except OSError as exc:
        raise ParameterError("scheduler", f"cannot connect to {address}: {exc.strerror or exc}") from None
    if proto == "tls":  # the TLS handshake is the client's to start: the connect is all we can check here
        sock.close()
        return
    try:
        sock.settimeout(timeout)
        try:
            data = sock.recv(4096)
        except socket.timeout:
            data = None
        if data is None:  # silent: perhaps an HTTP server waiting for a request
            try:
                sock.sendall(b"GET / HTTP/1.0\r\n\r\n")
                sock.settimeout(min(timeout, 2.0))
                reply = sock.recv(64)
            except OSError:
                reply = b""
            if reply.startswith(b"HTTP/"):
                raise ParameterError("scheduler", f"{address} is an HTTP server, not a Dask scheduler (the "
                                                  "dashboard's port? the scheduler listens on 8786 by default)")
            raise ParameterError("scheduler", f"{address} accepts connections but sent no Dask handshake within "
                                              f"{timeout:g} s: not a Dask scheduler (or one too busy to answer)")
        if b"compression" not in data and b"pickle-protocol" not in data:
            what = "an HTTP server" if data.startswith(b"HTTP/") else f"a service that said {data[:24]!r}"
            raise ParameterError("scheduler", f"{address} is {what}, not a Dask scheduler")
    except OSError as exc:
        raise ParameterError("scheduler", f"lost the connection to {address}: {exc.strerror or exc}") from None
    finally:
        sock.close()


def connect(address: str, *, timeout: float = 5.0, worker_timeout: float = 60.0, min_workers: int = 1):
    """A Client of the running scheduler at `address`, checked before anything is written: probe() (fails in
    `timeout` s on a dead address or a non-Dask listener), the connection, then at least `min_workers` workers
    within `worker_timeout` s.  ParameterError("scheduler") for an address that is not a usable scheduler,
    EnvironmentFault("scheduler") for a scheduler without workers."""
    from dask.distributed import Client

    address = normalise_address(address)
    security = None
    if address.startswith("tls://"):
        security = _tls_security()
        if security is None:
            raise ParameterError("scheduler", f"{address}: tls:// needs TLS certificates, and none are configured: "
                                              "set distributed.comm.tls.ca-file, .client.cert and .client.key in "
                                              "the Dask configuration (or DASK_DISTRIBUTED__COMM__TLS__* variables)")
    probe(address, timeout)
    try:
        client = Client(address, timeout=f"{timeout}s", security=security)
    except (OSError, TimeoutError) as exc:
        raise ParameterError("scheduler", f"cannot connect to {address}: "
                                          f"{' '.join(str(exc).split())[:200] or type(exc).__name__}") from None
    try:
        client.wait_for_workers(min_workers, timeout=worker_timeout)
    except (TimeoutError, OSError) as exc:
        close_quietly(client)
        if isinstance(exc, TimeoutError) or "timed out" in str(exc).lower():
            raise EnvironmentFault("scheduler", f"no Dask worker joined the scheduler at {address} within "
                                                f"{worker_timeout:g} s (start one: dask worker {address})") from None
        raise EnvironmentFault("scheduler", f"lost the scheduler at {address}: {exc}") from None
    except BaseException:
        close_quietly(client)
        raise
    return client


# ------------------------------------------------------------------------------------------------------------
# the machine's limits, checked before a LocalCluster is started (here, not in the CLI: a library caller gets them too)
# ------------------------------------------------------------------------------------------------------------
WORKER_MB = 300  # RSS of a LocalCluster worker after a tile (heyoka + LLVM + dask): 253 MB measured, rounded up
WORKER_VM_MB = 1800  # virtual memory of a LocalCluster worker: VmPeak 904 MB measured after a tile, x 2 margin


def usable_cpus() -> int:
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)


def check_workers(n: int, name: str = "workers") -> int:
    """At most the CPUs this process may use (one single-threaded process each: more only cost memory) and what
    the available memory holds at WORKER_MB each; ParameterError(name) otherwise."""
    cpus = usable_cpus()
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ParameterError(name, f"must be an integer >= 1, got {n!r}")
    if n > cpus:
        raise ParameterError(name, f"must be <= {cpus}, the CPUs this process may use (each worker is one "
                                   f"single-threaded process of ~{WORKER_MB} MB; more only cost memory), got {n!r}")
    avail = available_mb()
    if avail is not None and n * WORKER_MB > avail:
        raise ParameterError(name, f"{n} workers need ~{n * WORKER_MB} MB ({WORKER_MB} MB each) but only "
                                   f"{avail:.0f} MB are available: use fewer")
    return n


def available_mb():
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) / 1024
    except OSError:
        pass
    return None


def files_needed(workers: int) -> int:
    """Open files the parent needs for a LocalCluster: ~31 + 10 per worker measured (sockets, pipes, the JIT
    cache, zarr), with a margin."""
    return 40 + 12 * workers


def check_open_files(workers: int) -> None:
    import resource

    soft, _ = resource.getrlimit(resource.RLIMIT_NOFILE)
    need = files_needed(workers)
    if soft != resource.RLIM_INFINITY and soft < need:
        raise EnvironmentFault("workers", f"the open-file limit (ulimit -n) is {soft}; a LocalCluster of {workers} "
                                          f"worker(s) needs about {need} open files: raise it (e.g. ulimit -n 1024)")


def check_address_space() -> None:
    """Under an address-space limit (ulimit -v) too small for a worker, the worker dies at start-up and prints its
    own traceback: refuse before that, in one line."""
    import resource

    soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    if soft != resource.RLIM_INFINITY and soft < WORKER_VM_MB * 2 ** 20:
        raise EnvironmentFault("workers", f"the address-space limit (ulimit -v) is {soft // 2 ** 20} MB; a LocalCluster "
                                          f"worker needs about {WORKER_VM_MB} MB of virtual memory (heyoka's JIT): "
                                          f"raise it or remove it (ulimit -v unlimited)")


def start_failure(exc, workers: int) -> EnvironmentFault:
    """The LocalCluster did not start: the machine's limits (memory, processes, files) say why, in one line."""
    import resource

    limits = []
    for name, rl, unit in (("ulimit -v", "RLIMIT_AS", "kB"), ("ulimit -u", "RLIMIT_NPROC", ""),
                           ("ulimit -n", "RLIMIT_NOFILE", "")):
        soft = resource.getrlimit(getattr(resource, rl))[0]
        if soft != resource.RLIM_INFINITY:
            limits.append(f"{name} {soft // 1024 if unit else soft}")
    why = " ".join(f"{type(exc).__name__}: {exc}".split())[:120]
    return EnvironmentFault("workers", f"cannot start a LocalCluster of {workers} worker(s) ({why}): not enough "
                                       f"memory, processes or open files? limits in force: "
                                       f"{', '.join(limits) or 'none'}")
