"""Dask fails fast and clearly (issue 17, item 3), against a real `dask scheduler` + `dask worker` started on
127.0.0.1 by the tests, a port held by a plain HTTP server (the dashboard-port mistake), a TCP service that never
answers, and addresses that cannot work.  Every case asserts the exit code, one stderr line, one JSON object,
how long it took, and that no file or directory appeared."""
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest

from helpers import tree
from magrod import cli

GRID = ["--x", "lam:0.12:0.2:4", "--y", "gamma:2:4:4", "--tile", "2", "--t-max", "60"]
DASK = str(Path(sys.executable).parent / "dask")


_tree = tree

def _start_scheduler(d: Path):
    sf = d / "scheduler.json"
    p = subprocess.Popen([DASK, "scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                          "--scheduler-file", str(sf)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                         cwd=d, start_new_session=True)
    deadline = time.time() + 120
    while time.time() < deadline:
        try:
            return p, json.loads(sf.read_text())["address"], sf
        except (OSError, ValueError, KeyError):
            time.sleep(0.1)
    p.kill()
    pytest.fail("dask scheduler did not start")


def _start_worker(sf: Path, cwd: Path):
    cwd.mkdir(parents=True, exist_ok=True)
    return subprocess.Popen([DASK, "worker", "--scheduler-file", str(sf), "--nthreads", "1", "--nworkers", "1",
                             "--no-dashboard", "--local-directory", str(cwd / "dask-worker-space")],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=cwd, start_new_session=True)


def _stop(*procs):
    for p in procs:
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait(timeout=30)


def _wait_for_worker(address, n=1):
    from distributed import Client

    with Client(address, timeout="30s") as c:
        c.wait_for_workers(n, timeout=120)


@pytest.fixture(scope="module")
def real_cluster(tmp_path_factory):
    """`dask scheduler` + one `dask worker` (in its own directory, not the client's)."""
    d = tmp_path_factory.mktemp("dask")
    sched, address, sf = _start_scheduler(d)
    worker = _start_worker(sf, d / "worker-cwd")
    try:
        _wait_for_worker(address)
        yield {"address": address, "file": sf, "worker_cwd": d / "worker-cwd", "scheduler": sched, "worker": worker}
    finally:
        _stop(worker, sched)


def _main(argv, capsys):
    t0 = time.perf_counter()
    rc = cli.main(argv + ["--json"])
    wall = time.perf_counter() - t0
    cap = capsys.readouterr()
    obj = json.loads(cap.out)  # exactly one JSON object
    lines = [ln for ln in cap.err.splitlines() if ln.strip()]
    assert "Traceback" not in cap.err, cap.err
    return rc, obj, lines, wall


def test_real_cluster_host_port_and_a_relative_out(real_cluster, tmp_path, monkeypatch, capsys):
    """HOST:PORT without tcp:// is accepted; a relative --out is made absolute, so the worker (running in another
    directory that holds a store of the same relative name) writes into the client's store, and the map is right."""
    from magrod.chaos import maps
    from magrod.store import tiles as store

    monkeypatch.chdir(tmp_path)
    decoy = real_cluster["worker_cwd"] / "rel" / "chaosmap.zarr"  # the worker's own directory has such a store
    decoy.mkdir(parents=True, exist_ok=True)
    (decoy / "zarr.json").write_text("{}")
    before = _tree(real_cluster["worker_cwd"] / "rel")
    host_port = real_cluster["address"].split("://", 1)[1]
    rc, obj, lines, _ = _main(["chaosmap", *GRID, "--out", "rel", "--scheduler", host_port], capsys)
    assert rc == 0 and obj["ok"] is True and lines == [], (obj, lines)
    assert obj["output"]["store"] == str(tmp_path / "rel" / "chaosmap.zarr")
    assert obj["computed"] > 0 and obj["tiles"]["computed"] == 4
    assert _tree(real_cluster["worker_cwd"] / "rel") == before  # the decoy is untouched
    spec = maps.MapSpec.from_dict(obj["spec"])
    ref = maps.chaos_map(spec).fields
    got = store.load_fields(tmp_path / "rel" / "chaosmap.zarr")
    for k in ref:
        assert got[k].tobytes() == ref[k].astype(got[k].dtype).tobytes(), k


def test_scheduler_file(real_cluster, tmp_path, capsys):
    out = tmp_path / "o"
    rc, obj, lines, _ = _main(["chaosmap", *GRID, "--out", str(out), "--scheduler-file", str(real_cluster["file"])],
                              capsys)
    assert rc == 0 and obj["scheduler"] == real_cluster["address"] and obj["tiles"]["computed"] == 4


class _Hello(BaseHTTPRequestHandler):
    def do_GET(self):
        try:
            self.send_response(200)
            self.end_headers()
            self.wfile.write(b"dashboard")
        except OSError:  # the probe hangs up as soon as it has seen an HTTP answer: that is the point
            pass

    def log_message(self, *a):
        pass


@pytest.fixture
def http_port():
    srv = ThreadingHTTPServer(("127.0.0.1", 0), _Hello)
    th = threading.Thread(target=srv.serve_forever, daemon=True)
    th.start()
    yield srv.server_address[1]
    srv.shutdown()
    srv.server_close()


@pytest.fixture
def silent_port():
    """A TCP service that accepts and never says anything."""
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    s.listen(8)
    conns, stop = [], threading.Event()

    def accept():
        s.settimeout(0.2)
        while not stop.is_set():
            try:
                conns.append(s.accept()[0])
            except OSError:
                pass

    th = threading.Thread(target=accept, daemon=True)
    th.start()
    yield s.getsockname()[1]
    stop.set()
    th.join()
    for c in conns:
        c.close()
    s.close()


def _closed_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


# (scheduler option given, words in the error line, exit code, max seconds); PORT filled in by the fixture
FAILURES = [
    ("http", "tcp://127.0.0.1:{http}", "HTTP server", 2, 20),
    ("http-host-port", "127.0.0.1:{http}", "HTTP server", 2, 20),
    ("silent", "tcp://127.0.0.1:{silent}", "no Dask handshake", 2, 25),
    ("refused", "tcp://127.0.0.1:{closed}", "cannot connect", 2, 20),
    ("tls-without-certificates", "tls://127.0.0.1:{closed}", "TLS certificates", 2, 20),
    ("inproc", "inproc://127.0.0.1/1/2", "inproc", 2, 20),
    ("ucx", "ucx://127.0.0.1:{closed}", "not supported", 2, 20),
    ("no-port", "localhost", "HOST:PORT", 2, 20),
    ("bad-port", "localhost:99999", "HOST:PORT", 2, 20),
]


@pytest.mark.parametrize("case,addr,words,code,limit", FAILURES, ids=[f[0] for f in FAILURES])
def test_unusable_schedulers_fail_fast_and_create_nothing(case, addr, words, code, limit, http_port, silent_port,
                                                          tmp_path, capsys):
    addr = addr.format(http=http_port, silent=silent_port, closed=_closed_port())
    before = _tree(tmp_path)
    rc, obj, lines, wall = _main(["chaosmap", *GRID, "--out", str(tmp_path / "o"), "--scheduler", addr,
                                  "--connect-timeout", "2"], capsys)
    assert rc == code and obj["parameter"] == "scheduler", obj
    assert len(lines) == 1 and words in lines[0], lines
    assert wall < limit, wall
    assert _tree(tmp_path) == before


def test_a_scheduler_without_workers_is_one_line_after_the_timeout(tmp_path, capsys):
    (tmp_path / "s").mkdir()
    sched, address, _ = _start_scheduler(tmp_path / "s")
    try:
        before = _tree(tmp_path)
        rc, obj, lines, wall = _main(["chaosmap", *GRID, "--out", str(tmp_path / "o"), "--scheduler", address,
                                      "--worker-timeout", "2"], capsys)
    finally:
        _stop(sched)
    assert rc == 3 and obj["parameter"] == "scheduler", obj
    assert len(lines) == 1 and "no Dask worker joined" in lines[0] and address in lines[0], lines
    assert wall < 30
    assert _tree(tmp_path) == before


def test_scheduler_file_problems(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text("{\"nothing\": 1}")
    for f, words in ((tmp_path / "missing.json", "no such file"), (bad, "no \"address\"")):
        rc, obj, lines, _ = _main(["chaosmap", *GRID, "--out", str(tmp_path / "o"), "--scheduler-file", str(f)],
                                  capsys)
        assert rc == 2 and obj["parameter"] == "scheduler_file" and len(lines) == 1 and words in lines[0], lines
    assert not (tmp_path / "o").exists()


def _kill_mid_run(tmp_path, which):
    """A 2 x 2 map on a real `dask scheduler` + one `dask worker`; at the marker (tiles submitted) kill `which`
    ("worker" or "scheduler"), let the client go on.  Returns (returncode, stdout, stderr, OUT, seconds to exit)."""
    d = tmp_path / "c"
    d.mkdir()
    sched, address, sf = _start_scheduler(d)
    worker = _start_worker(sf, d / "w")
    marker = tmp_path / "marker"
    out = tmp_path / "o"
    p = None
    try:
        _wait_for_worker(address)
        p = subprocess.Popen([sys.executable, "-m", "magrod.cli", "chaosmap", "--x", "lam:0.12:0.2:2", "--y",
                              "gamma:2:4:2", "--tile", "1", "--t-max", "50000", "--out", str(out), "--scheduler",
                              address, "--worker-timeout", "3", "--json", "--quiet"], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True, cwd=tempfile.gettempdir(),
                             env={**os.environ, "MAGROD_TEST_PAUSE": f"chaosmap-running:{marker}"})
        deadline = time.time() + 120
        while not marker.exists() and time.time() < deadline and p.poll() is None:
            time.sleep(0.05)
        assert marker.exists(), p.communicate()
        _stop(worker if which == "worker" else sched)
        marker.unlink()  # let the client go on: it must notice what is gone
        t = time.perf_counter()
        o, e = p.communicate(timeout=180)
        waited = time.perf_counter() - t
    finally:
        if p is not None and p.poll() is None:
            p.kill()
        _stop(worker, sched)
    return p.returncode, o, e, out, waited


def _nothing_left(out):
    return not out.exists() or not any((out / "chaosmap.tiles").glob("*.json")) and not (out / "chaosmap.zarr"
                                                                                            ).exists()


def test_workers_lost_mid_run_is_one_line_not_a_hang(tmp_path):
    """The only worker is killed while the map's tiles wait: the client notices (no worker for --worker-timeout
    seconds) and says so in one line, exit 3; no tile finished, so the store it created is removed again."""
    rc, o, e, out, _ = _kill_mid_run(tmp_path, "worker")
    assert rc == 3, e
    lines = [ln for ln in e.splitlines() if ln.strip()]
    assert len(lines) == 1 and "no worker" in lines[0], lines
    assert json.loads(o)["parameter"] == "scheduler"
    assert _nothing_left(out)


def test_scheduler_lost_mid_run_is_one_line_not_a_hang(tmp_path):
    """The scheduler dies (SIGKILL) while the map's tiles run: the client must not wait forever for futures that no
    one will ever finish.  One line naming the scheduler, exit 3; no tile finished, so nothing is left behind."""
    rc, o, e, out, waited = _kill_mid_run(tmp_path, "scheduler")
    print(f"scheduler killed -> the client exited after {waited:.1f} s")
    assert rc == 3, e
    lines = [ln for ln in e.splitlines() if ln.strip()]
    assert len(lines) == 1 and "scheduler" in lines[0], lines
    assert json.loads(o)["parameter"] == "scheduler"
    assert _nothing_left(out)


def test_http_server_probe_is_fast_even_without_a_timeout_option(http_port, tmp_path, capsys):
    """The default --connect-timeout: a dashboard port fails within seconds (dask/distributed#8071 hangs)."""
    rc, obj, lines, wall = _main(["chaosmap", *GRID, "--out", str(tmp_path / "o"), "--scheduler",
                                  f"127.0.0.1:{http_port}"], capsys)
    assert rc == 2 and "HTTP server" in lines[0] and wall < 30
    shutil.rmtree(tmp_path / "o", ignore_errors=True)
