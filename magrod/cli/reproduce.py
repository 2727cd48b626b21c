"""`magrod reproduce`: every figure and claim of the paper in one command, with a claim-by-claim REPORT.md.

Nothing symbolic is re-derived (generated/ is used as is).  Figures run as independent tasks in worker
processes (--workers), each task writing its files atomically; a task whose stamp (same quick flag, same
package versions, every file present with its recorded content hash) is found in OUT/.state/ is skipped, so an
interrupted run resumes.  Ctrl-C (exit 130), SIGTERM (143) and SIGHUP (129) stop the workers at once (they
ignore the terminal's signals: stopping them is the parent's job), keep the stamps of finished figures, remove
the temporaries of half-written files and print one line; workers die with their parent even on kill -9 (and
the next run removes what they left); a second run into the same directory is refused while the first holds its
lock.

The proof figure verifies every shipped certificate (--quick: one of each kind but the horseshoe) with the
complete verifier, independent certificates in processes on every core, and remembers each verified certificate
in OUT/.state/verified/ under the SHA-256 of the certificate and of the verifier's trust base
(magrod.proof.schedule): a second run does not verify it again, a changed certificate or verifier does, --force
forgets.  While it verifies, the bar shows how many certificates are done."""
from __future__ import annotations

import json
import time
from pathlib import Path

from ..core.errors import EnvironmentFault, ParameterError
from ..figures import FIGURES
from .options import add_format, add_out, add_workers, formats_from, integer

TASKS = list(FIGURES)
# CPU seconds of each figure in --quick (measured one figure per process, this machine, 2026-12): the workers take the
# longest first, so that no long figure starts last and runs alone (the order decides nothing in the results)
QUICK_CPU_S = {"splitting": 25, "continuation": 19, "proof": 17, "5": 8, "3": 8, "6": 7, "4": 7, "7": 6,
               "landscape": 5, "2": 4, "chaos": 4, "orbitdiagram": 4}
# and in the full reproduction, where the proof figure verifies every shipped certificate
FULL_FIRST = ("proof",)


# the measured wall time of `reproduce --quick` (benchmarks/reproduce_time.py writes it; present in a source
# checkout): the help quotes it from there, so that it cannot go stale silently
TIMING = Path(__file__).resolve().parents[2] / "benchmarks" / "reproduce_time.json"


def quick_time_text(path=None) -> str:
    """What the help says of the quick run's time: the benchmark's measured minimum with its machine, or, without
    the benchmark's file (an installed package), where to measure it."""
    import json

    try:
        t = json.loads(Path(path or TIMING).read_text())
        wall, cores = float(t["min_wall_s"]), int(t["cores"])
        load = max(float(r["load_before"][0]) for r in t["runs"] if r["wall_s"] == t["min_wall_s"])
    except (OSError, ValueError, KeyError, TypeError, IndexError):
        return "time: measure it with benchmarks/reproduce_time.py"
    return f"measured {wall:.0f} s on {cores} cores at load {load:.1f} (benchmarks/reproduce_time.json)"


def add_arguments(p):
    add_out(p, files=True, help="output directory for PNGs, data, sidecars and REPORT.md")
    p.add_argument("--quick", action="store_true",
                   help=f"reduced sizes (fewer Poincaré iterates etc.); {quick_time_text()}")
    add_workers(p, default="2", help="worker processes (figures run in parallel)", old=("--jobs",))
    p.add_argument("--only", default=",".join(TASKS), help="comma-separated figure numbers to run")
    p.add_argument("--force", action="store_true", help="ignore finished-task stamps and remembered verifications; recompute everything")
    add_format(p)


def _stamp_path(out: Path, task: str) -> Path:
    return out / ".state" / f"figure_{task}.json"


def _sha256(path: Path) -> str:
    import hashlib

    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _stamp_ok(out: Path, task: str, quick: bool, formats=("png",)) -> dict | None:
    """The stamp of a finished task if it is valid for this run: a JSON object written by this code, same quick
    flag and package versions, and every file it lists present with the content hash it recorded.  Anything
    else (missing, unreadable, truncated, wrong type, a changed file) means: recompute."""
    from ..core.io import versions

    p = _stamp_path(out, task)
    try:
        st = json.loads(p.read_text())
    except (OSError, ValueError, UnicodeDecodeError):
        return None
    files = st.get("files") if isinstance(st, dict) else None
    if (not isinstance(files, dict) or not files or st.get("quick") is not quick or st.get("versions") != versions()
            or not isinstance(st.get("paths"), list) or st.get("formats", ["png"]) != list(formats)):
        return None
    for name, digest in files.items():
        f = out / str(name)
        if not isinstance(digest, str) or Path(name).name != name or not f.is_file():
            return None
        try:
            if _sha256(f) != digest:
                return None
        except OSError:
            return None
    return st


def _worker_init(parent_pid: int) -> None:
    """Runs in each worker: Ctrl-C is the parent's to handle, and a worker never outlives its parent (Linux:
    the kernel kills it when the parent dies, even by kill -9; elsewhere a watchdog thread notices)."""
    import os
    import signal
    import threading

    for name in ("SIGINT", "SIGTERM", "SIGHUP"):  # the terminal's signals reach the whole group: ours to handle
        if hasattr(signal, name):
            signal.signal(getattr(signal, name), signal.SIG_IGN)
    try:
        import ctypes

        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent_pid:  # the parent died before prctl took effect
        os._exit(1)

    def watchdog():
        while True:
            time.sleep(1.0)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watchdog, daemon=True).start()


def _progress_path(out: Path, task: str) -> Path:
    return out / ".state" / f"progress_{task}.txt"


def _run_task(task: str, out: str, quick: bool, formats=("png",)) -> dict:
    """Worker: one figure.  Runs in a separate process; returns paths, their content hashes and wall time.  A
    figure that fails removes the files it wrote (figures.build), so its stamp and its claims are both absent.
    The proof figure reports each verified certificate in OUT/.state/progress_proof.txt ("done/total name"),
    which the parent shows beside its bar."""
    from ..figures import build

    t0 = time.perf_counter()
    progress = False
    if task == "proof":
        ppath = _progress_path(Path(out), task)

        def progress(done, total, name, cached):
            from ..core.io import atomic_write_text, record_writes

            with record_writes():  # not an output of the figure
                atomic_write_text(ppath, f"{done}/{total} {name}{' (remembered)' if cached else ''}\n")
    paths = build(task, Path(out), quick=quick, progress=progress, formats=formats)
    files = {Path(p).name: _sha256(Path(p)) for p in paths}
    return {"task": task, "paths": paths, "files": files, "wall_s": time.perf_counter() - t0}


def _tasks(only: str) -> list:
    tasks = [t.strip() for t in str(only).split(",")]
    if not any(tasks):
        raise ParameterError("only", f"give at least one figure number ({', '.join(TASKS)})")
    for t in tasks:
        if t not in FIGURES:
            raise ParameterError("only", f"unknown figure {t!r}; choose from {', '.join(TASKS)}")
    dup = sorted({t for t in tasks if tasks.count(t) > 1})
    if dup:
        raise ParameterError("only", f"figure(s) {', '.join(dup)} listed twice")
    return tasks


def _lock(out: Path):
    """An exclusive lock on OUT/.state/lock for the whole run: a second `magrod reproduce` into the same
    directory fails at once instead of computing everything again."""
    from ..core.io import DirectoryLock

    return DirectoryLock(out / ".state" / "lock", "out", f"another magrod reproduce is writing into {str(out)!r}; "
                         "wait for it to finish (finished figures are then reused) or choose another --out").acquire()


def run(args) -> dict:
    import concurrent.futures as cf
    import multiprocessing
    import os

    from ..figures.report import claims, mark_failed, report_markdown, tally
    from ..core.io import atomic_write_json, atomic_write_text, ensure_writable_dir, remove_stale_temporaries, versions
    from ..core.progress import bar
    from . import children_immune, pause_point
    from .options import out_dir

    jobs = integer("workers", args.workers)
    tasks = _tasks(args.only)
    formats = formats_from(args)
    out = ensure_writable_dir(out_dir("out", args.out))
    try:
        (out / ".state").mkdir(exist_ok=True)
    except OSError as exc:
        raise EnvironmentFault("out", f"cannot create {str(out / '.state')!r}: {exc.strerror}") from None
    lock = _lock(out)
    remove_stale_temporaries(out)  # what a killed run left behind (its writer is dead; we hold the lock)
    remove_stale_temporaries(out / ".state")
    remove_stale_temporaries(out / ".state" / "verified")
    t0 = time.perf_counter()
    done, todo = {}, []
    for t in tasks:
        st = None if args.force else _stamp_ok(out, t, args.quick, formats)
        if st:
            done[t] = {**st, "skipped": True}
        else:
            todo.append(t)
    # the longest figures first (see QUICK_CPU_S): the order of the work, never of the results
    cost = {**QUICK_CPU_S, **({t: 10_000 for t in FULL_FIRST} if not args.quick else {})}
    todo.sort(key=lambda t: -cost.get(t, 0))
    if args.force and "proof" in todo:  # recompute everything: the proof figure's remembered verifications too
        import shutil

        shutil.rmtree(out / ".state" / "verified", ignore_errors=True)
    for t in todo:
        _progress_path(out, t).unlink(missing_ok=True)
    failures = {}
    # spawn, not fork: workers build their own LLVM/heyoka state (the on-disk JIT cache makes this cheap)
    # multiprocessing's resource tracker starts with the pool's first queue: it too must not die of the terminal's
    # SIGHUP (it ignores only SIGINT and SIGTERM itself)
    with children_immune():
        ex = cf.ProcessPoolExecutor(max_workers=min(jobs, max(1, len(todo))),
                                    mp_context=multiprocessing.get_context("spawn"), initializer=_worker_init,
                                    initargs=(os.getpid(),))
    interrupted = False
    pids = set()
    try:
        with bar(len(todo), "reproduce", not args.quiet, unit="figure") as update:
            with children_immune():  # the workers are started by submit: they inherit SIG_IGN
                futs = {ex.submit(_run_task, t, str(out), args.quick, formats): t for t in todo}
            pids = set(getattr(ex, "_processes", {}) or {})
            pause_point("reproduce-running")
            for fut in _completed(futs, out, update):
                t = futs[fut]
                try:
                    r = fut.result()
                except Exception as exc:  # a failed figure is reported, the others still finish
                    failures[t] = " ".join(f"{type(exc).__name__}: {exc}".split())
                else:
                    st = {"task": t, "quick": args.quick, "formats": list(formats), "versions": versions(),
                          "paths": r["paths"],
                          "files": r["files"], "wall_s": r["wall_s"]}
                    atomic_write_json(_stamp_path(out, t), st)
                    done[t] = {**st, "skipped": False}
                update(1)
    except BaseException:
        interrupted = True
        procs = list((getattr(ex, "_processes", None) or {}).values())
        for proc in procs:  # stop now, not after the running figures
            pids.add(proc.pid)
            proc.kill()
        for proc in procs:
            proc.join(5)
        raise
    finally:
        ex.shutdown(wait=not interrupted, cancel_futures=True)
        for t in todo:
            _progress_path(out, t).unlink(missing_ok=True)
        if interrupted:  # a worker killed mid-write leaves its temporary: remove it (stamps of finished figures stay)
            remove_stale_temporaries(out, pids)
            remove_stale_temporaries(out / ".state", pids)
            remove_stale_temporaries(out / ".state" / "verified", pids)
        lock.release()
    report_path = out / "REPORT.md"
    rows = claims(out, args.quick)
    counts = tally(mark_failed(rows, failures))
    atomic_write_text(report_path, report_markdown(rows, done, failures, args.quick, time.perf_counter() - t0))
    res = {"ok": not failures, "out": str(out), "report": str(report_path), "quick": args.quick,
           "figures": {t: {"paths": d["paths"], "skipped": d["skipped"], "wall_s": d.get("wall_s")}
                       for t, d in sorted(done.items())},
           "failures": failures, "claims": rows, "tally": counts, "wall_s": time.perf_counter() - t0}
    if failures:
        res["error"] = "figure(s) failed: " + "; ".join(f"{t}: {m}" for t, m in sorted(failures.items()))
    return res


def _completed(futs, out: Path, update):
    """The futures as they complete; meanwhile the progress a running figure reports (the proof figure: each
    certificate verified) is shown beside the bar."""
    import concurrent.futures as cf

    pending, shown = set(futs), None
    while pending:
        finished, pending = cf.wait(pending, timeout=1.0, return_when=cf.FIRST_COMPLETED)
        notes = []
        for t in sorted({futs[f] for f in pending}):
            try:
                notes.append(f"{t}: {_progress_path(out, t).read_text().strip()}")
            except OSError:
                pass
        note = "; ".join(notes)
        if note != shown:
            update.note(note)
            shown = note
        yield from finished


def format_text(r: dict) -> str:
    from ..figures.report import tally_text

    lines = [f"reproduce: {'ok' if r['ok'] else 'with failures'} in {r['wall_s']:.1f} s -> {r['report']}"]
    if r.get("tally"):
        lines.append(f"  {sum(r['tally'].values())} claims: {tally_text(r['tally'])}")
    for t, d in r["figures"].items():
        lines.append(f"  figure {t}: {len(d['paths'])} files" + (" (skipped: already done)" if d["skipped"] else ""))
    for t, msg in r["failures"].items():
        lines.append(f"  figure {t}: FAILED {msg}")
    return "\n".join(lines)
