"""`magrod reproduce`: every figure and claim of the paper in one command, with a claim-by-claim REPORT.md.

Nothing symbolic is re-derived (generated/ is used as is).  Figures run as independent tasks in worker
processes (--jobs), each task writing its files atomically; a task whose stamp (same quick flag, same
package versions, all files present) is found in OUT/.state/ is skipped, so an interrupted run resumes.
Ctrl-C stops the workers, leaves no half-written file and exits non-zero (130)."""
from __future__ import annotations

import json
import sys
import time
from pathlib import Path

from ..errors import ParameterError
from ..figures import FIGURES
from .options import integer

TASKS = list(FIGURES)


def add_arguments(p):
    p.add_argument("--out", default="out", help="output directory for PNGs, data, sidecars and REPORT.md")
    p.add_argument("--quick", action="store_true", help="reduced sizes (fewer Poincare iterates etc.), ~1 min")
    p.add_argument("--jobs", default="2", help="worker processes (figures run in parallel)")
    p.add_argument("--only", default=",".join(TASKS), help="comma-separated figure numbers to run")
    p.add_argument("--force", action="store_true", help="ignore finished-task stamps and recompute everything")


def _stamp_path(out: Path, task: str) -> Path:
    return out / ".state" / f"figure_{task}.json"


def _stamp_ok(out: Path, task: str, quick: bool) -> dict | None:
    from ..io import versions

    p = _stamp_path(out, task)
    if not p.exists():
        return None
    try:
        st = json.loads(p.read_text())
    except (OSError, ValueError):
        return None
    if st.get("quick") != quick or st.get("versions") != versions():
        return None
    if not all(Path(x).exists() for x in st.get("paths", [])):
        return None
    return st


def _run_task(task: str, out: str, quick: bool) -> dict:
    """Worker: one figure.  Runs in a separate process; returns paths and wall time."""
    from ..figures import build

    t0 = time.perf_counter()
    paths = build(task, Path(out), quick=quick, progress=False)
    return {"task": task, "paths": paths, "wall_s": time.perf_counter() - t0}


def run(args) -> dict:
    import concurrent.futures as cf

    from ..figures.report import claims, report_markdown
    from ..io import atomic_write_json, atomic_write_text, ensure_writable_dir, versions

    jobs = integer("jobs", args.jobs)
    tasks = [t.strip() for t in args.only.split(",") if t.strip()]
    for t in tasks:
        if t not in FIGURES:
            raise ParameterError("only", f"unknown figure {t!r}; choose from {', '.join(TASKS)}")
    out = ensure_writable_dir(Path(args.out))
    (out / ".state").mkdir(exist_ok=True)
    t0 = time.perf_counter()
    done, todo = {}, []
    for t in tasks:
        st = None if args.force else _stamp_ok(out, t, args.quick)
        if st:
            done[t] = {**st, "skipped": True}
        else:
            todo.append(t)
    progress = None
    if not args.quiet:
        from tqdm import tqdm

        progress = tqdm(total=len(tasks), initial=len(done), desc="reproduce", unit="figure", file=sys.stderr)
    failures = {}
    import multiprocessing

    # spawn, not fork: workers build their own LLVM/heyoka state (the on-disk JIT cache makes this cheap)
    ex = cf.ProcessPoolExecutor(max_workers=min(jobs, max(1, len(todo))),
                                mp_context=multiprocessing.get_context("spawn"))
    try:
        futs = {ex.submit(_run_task, t, str(out), args.quick): t for t in todo}
        for fut in cf.as_completed(futs):
            t = futs[fut]
            try:
                r = fut.result()
            except Exception as exc:  # a failed figure is reported, the others still finish
                failures[t] = f"{type(exc).__name__}: {exc}"
            else:
                st = {"task": t, "quick": args.quick, "versions": versions(), "paths": r["paths"],
                      "wall_s": r["wall_s"]}
                atomic_write_json(_stamp_path(out, t), st)
                done[t] = {**st, "skipped": False}
            if progress:
                progress.update(1)
    except KeyboardInterrupt:
        for f in futs:
            f.cancel()
        ex.shutdown(wait=False, cancel_futures=True)
        raise
    finally:
        ex.shutdown(wait=True, cancel_futures=True)
        if progress:
            progress.close()
    report_path = out / "REPORT.md"
    rows = claims(out, args.quick)
    atomic_write_text(report_path, report_markdown(rows, done, failures, args.quick, time.perf_counter() - t0))
    return {"ok": not failures, "out": str(out), "report": str(report_path), "quick": args.quick,
            "figures": {t: {"paths": d["paths"], "skipped": d["skipped"], "wall_s": d.get("wall_s")}
                        for t, d in sorted(done.items())},
            "failures": failures, "claims": rows, "wall_s": time.perf_counter() - t0}


def format_text(r: dict) -> str:
    lines = [f"reproduce: {'ok' if r['ok'] else 'with failures'} in {r['wall_s']:.1f} s -> {r['report']}"]
    for t, d in r["figures"].items():
        lines.append(f"  figure {t}: {len(d['paths'])} files" + (" (skipped: already done)" if d["skipped"] else ""))
    for t, msg in r["failures"].items():
        lines.append(f"  figure {t}: FAILED {msg}")
    return "\n".join(lines)
