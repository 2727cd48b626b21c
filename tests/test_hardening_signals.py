"""Every signal ends `magrod chaosmap` cleanly (issue 17, item 4): SIGINT 130, SIGTERM 143, SIGHUP 129, one stderr
line, the Dask workers stopped, no temporary left, finished tiles kept with their markers -- sent to the whole
process group, as a terminal's Ctrl-C or a closed terminal does, at a known moment (the MAGROD_TEST_PAUSE hook).
The same for `magrod reproduce` is in tests/test_hardening.py."""
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

from magrod import cli


def _chaosmap(out: Path, *extra, env=None):
    return subprocess.Popen([sys.executable, "-m", "magrod.cli", "chaosmap", "--out", str(out), "--quiet", *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=tempfile.gettempdir(),
                            start_new_session=True, env={**os.environ, **(env or {})})


def _group(pgid: int) -> list:
    r = subprocess.run(["pgrep", "-g", str(pgid)], capture_output=True, text=True)
    return [int(x) for x in r.stdout.split()]


def _wait_gone(pgid: int, timeout=15.0) -> list:
    deadline = time.time() + timeout
    while time.time() < deadline and _group(pgid):
        time.sleep(0.1)
    return _group(pgid)


@pytest.mark.parametrize("sig,code", [(signal.SIGINT, 130)], ids=["SIGINT"])
def test_signal_while_two_workers_run(tmp_path, sig, code):
    """Ctrl-C at the moment every tile is submitted to a LocalCluster of 2 workers: one line, exit 130 (SIGTERM: the
    next test; SIGHUP, and all three for reproduce: tests/test_hardening.py), no
    process of the group left, and -- no tile having finished -- nothing left on disk."""
    marker, out = tmp_path / "running", tmp_path / "o"
    p = _chaosmap(out, "--x", "lam:0.12:0.2:4", "--y", "gamma:2:4:4", "--tile", "2", "--t-max", "3000",
                  "--workers", "2", env={"MAGROD_TEST_PAUSE": f"chaosmap-running:{marker}"})
    deadline = time.time() + 300
    while not marker.exists() and time.time() < deadline and p.poll() is None:
        time.sleep(0.02)
    assert marker.exists(), p.communicate()
    assert len(_group(p.pid)) >= 3  # the command and its two workers (and multiprocessing's resource tracker)
    os.killpg(p.pid, sig)
    o, e = p.communicate(timeout=60)
    lines = [ln for ln in e.splitlines() if ln.strip()]
    assert p.returncode == code and len(lines) == 1, e
    assert f"interrupted ({signal.Signals(sig).name})" in lines[0]
    assert _wait_gone(p.pid) == []
    assert not out.exists()  # the store this run created held no finished tile: removed, and OUT with it


def test_finished_tiles_keep_their_markers_and_the_resume_uses_them(tmp_path):
    """SIGTERM once a tile is done: that tile's marker stays valid, temporaries are gone, the re-run skips it
    (its marker and chunk untouched) and computes the others."""
    out = tmp_path / "o"
    argv = ["--x", "lam:0.12:0.2:2", "--y", "gamma:2:4:2", "--tile", "1", "--t-max", "20000", "--workers", "1"]
    p = _chaosmap(out, *argv)
    tiles = out / "chaosmap.tiles"
    deadline = time.time() + 300
    while time.time() < deadline and p.poll() is None and not list(tiles.glob("*.json")):
        time.sleep(0.02)
    os.killpg(p.pid, signal.SIGTERM)
    o, e = p.communicate(timeout=60)
    done = sorted(q.stem for q in tiles.glob("*.json"))
    assert p.returncode == 143 and len([ln for ln in e.splitlines() if ln.strip()]) == 1, e
    assert 1 <= len(done) < 4, done
    assert not list(out.rglob("*.tmp")) and not list(out.rglob("*.partial"))
    assert _wait_gone(p.pid) == []
    kept = {q: q.read_bytes() for d in done for q in [tiles / f"{d}.json"]}
    r = subprocess.run([sys.executable, "-m", "magrod.cli", "chaosmap", "--out", str(out), *argv, "--json"],
                       capture_output=True, text=True, cwd=tempfile.gettempdir(), timeout=600)
    assert r.returncode == 0 and r.stderr.strip() == "", r.stderr
    obj = json.loads(r.stdout)
    assert obj["tiles"]["skipped"] == len(done) and obj["tiles"]["computed"] == 4 - len(done)
    assert obj["tiles"]["repaired"] == 0 and obj["computed"] + sum(obj["missing"].values()) == 4
    assert all(q.read_bytes() == b for q, b in kept.items())


def test_concurrent_run_waits_for_nobody(tmp_path, capsys):
    """A real second run while the first holds the store (paused after submitting): refused at once, exit 3, the
    first's store untouched; the first, interrupted, leaves nothing."""
    marker, out = tmp_path / "running", tmp_path / "o"
    argv = ["--x", "lam:0.12:0.2:4", "--y", "gamma:2:4:4", "--tile", "2", "--t-max", "100", "--workers", "1"]
    p = _chaosmap(out, *argv, env={"MAGROD_TEST_PAUSE": f"chaosmap-running:{marker}"})
    try:
        deadline = time.time() + 300
        while not marker.exists() and time.time() < deadline and p.poll() is None:
            time.sleep(0.02)
        assert marker.exists(), p.communicate()
        other = ["--x", "lam:0.12:0.2:5", "--y", "gamma:2:4:4", "--tile", "2", "--t-max", "100", "--workers", "1"]
        t0 = time.perf_counter()
        rc = cli.main(["chaosmap", "--out", str(out), *other, "--json"])
        cap = capsys.readouterr()
        assert rc == 3 and json.loads(cap.out)["parameter"] == "out" and time.perf_counter() - t0 < 30
        assert "another magrod chaosmap" in cap.err and len(cap.err.strip().splitlines()) == 1
    finally:
        os.killpg(p.pid, signal.SIGINT)
        p.communicate(timeout=60)
    assert p.returncode == 130 and not out.exists()
