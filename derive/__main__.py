"""python -m derive            regenerate generated/ (the paper's model and generated/models/<name>/ per model)
python -m derive --check    regenerate into a temporary directory and fail (exit 1) with a diff if generated/
                            is stale (an orphan file, in generated/ or under generated/models/, counts as stale)
python -m derive --model NAME [--check]   only that model's generated/models/<name>/ (the default model,
                            the paper's rod, is the top-level tree: the whole build)"""
from __future__ import annotations

import argparse
import difflib
import sys
import tempfile
from pathlib import Path

from .build import build, models_files, write_files

# derive/ and generated/ are siblings both in the source tree and when installed (magrod/derive, magrod/generated)
GENERATED = Path(__file__).resolve().parent.parent / "generated"


def checked_in(target: Path) -> set:
    """Every file of generated/ (compiled bytecode aside): a file the derivation does not write is an orphan."""
    return {p.name for p in target.glob("*") if p.is_file() and p.suffix != ".pyc"}


def stale_files(fresh: dict, target: Path) -> list:
    """Names whose checked-in text differs from the fresh build, is missing, or is not written by it (orphans);
    prints a diff of each."""
    stale = []
    for name in sorted(set(fresh) | checked_in(target)):
        new = fresh.get(name)
        old_path = target / name
        old = old_path.read_text() if old_path.exists() else None
        if new != old:
            stale.append(name)
            diff = difflib.unified_diff((old or "").splitlines(True), (new or "").splitlines(True),
                                        f"generated/{name} (checked in)", f"generated/{name} (fresh)", n=2)
            sys.stdout.writelines(list(diff)[:200])
            if new is None:
                print(f"generated/{name}: not written by the derivation (an orphan): delete it")
    return stale


def stale_model_files(fresh: dict, target: Path, only: str | None = None) -> list:
    """Like stale_files for generated/models/ (paths relative to generated/, recursive): every file under
    generated/models/ (or only under generated/models/<only>/) that differs, is missing or is an orphan."""
    base = target / "models" / only if only else target / "models"
    have = {str(p.relative_to(target)) for p in base.rglob("*") if p.is_file() and p.suffix != ".pyc"
            and "__pycache__" not in p.parts} if base.exists() else set()
    stale = []
    for rel in sorted(set(fresh) | have):
        new = fresh.get(rel)
        old = (target / rel).read_text() if (target / rel).exists() else None
        if new != old:
            stale.append(rel)
            diff = difflib.unified_diff((old or "").splitlines(True), (new or "").splitlines(True),
                                        f"generated/{rel} (checked in)", f"generated/{rel} (fresh)", n=2)
            sys.stdout.writelines(list(diff)[:200])
            if new is None:
                print(f"generated/{rel}: not written by the derivation (an orphan): delete it")
    return stale


def start_decided():
    """(pool, future) of derive.decided.files() in a spawned process, so that it overlaps the paper's build; (None,
    None) where no process can be started (then it runs here)."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from .decided import files

    try:
        pool = ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"))
        return pool, pool.submit(files)
    except (OSError, ValueError):
        return None, None


def decided_files(started=(None, None)) -> dict:
    """generated/decided/: Kovalevskaya exponents, Yoshida, Morales-Ramis per registered model (derive/decided.py),
    from the process `started` by start_decided() or computed here."""
    import time
    from concurrent.futures.process import BrokenProcessPool

    from .decided import files

    t0 = time.perf_counter()
    pool, fut = started
    out = None
    if fut is not None:
        try:
            with pool:
                out = fut.result()
        except BrokenProcessPool:  # the child could not start: do it here
            out = None
    if out is None:
        out = files()
    print(f"derive: integrability decided (exponents, Morales-Ramis): {time.perf_counter() - t0:.1f} s more")
    return out


def stale_decided(target: Path, started=(None, None)) -> list:
    """Like stale_model_files for generated/decided/ (every file there must be written by the derivation)."""
    fresh = decided_files(started)
    have = {str(p.relative_to(target)) for p in (target / "decided").rglob("*") if p.is_file()} \
        if (target / "decided").exists() else set()
    stale = []
    for rel in sorted(set(fresh) | have):
        old = (target / rel).read_text() if (target / rel).exists() else None
        if fresh.get(rel) != old:
            stale.append(rel)
            diff = difflib.unified_diff((old or "").splitlines(True), (fresh.get(rel) or "").splitlines(True),
                                        f"generated/{rel} (checked in)", f"generated/{rel} (fresh)", n=2)
            sys.stdout.writelines(list(diff)[:200])
    return stale


def check(target: Path, model: str | None = None) -> int:
    if model is not None:
        from .models import get

        stale = stale_model_files(models_files([model]), target, get(model).ident)
        print(f"derive --check: generated/models/{get(model).ident}/ is "
              + (f"stale ({', '.join(stale)})" if stale else "up to date"))
        return 1 if stale else 0
    started = start_decided()
    with tempfile.TemporaryDirectory() as tmp:
        fresh = build(Path(tmp), verbose=True)
    stale = stale_files(fresh, target) + stale_model_files(models_files(verbose=True), target)
    stale += stale_decided(target, started)
    if stale:
        print(f"\nderive --check: generated/ is stale ({', '.join(stale)}). Run `python -m derive` and commit.")
        return 1
    print("derive --check: generated/ is up to date")
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m derive", description=__doc__)
    ap.add_argument("--check", action="store_true", help="fail with a diff if generated/ is stale")
    ap.add_argument("--out", type=Path, default=GENERATED, help="output directory")
    ap.add_argument("--model", default=None, help="only this registered model (generated/models/<name>/)")
    a = ap.parse_args(argv)
    if a.model is not None:
        from .models import NAMES

        if a.model not in NAMES:
            ap.error(f"--model: unknown model {a.model!r}; registered: {', '.join(NAMES)}")
        from .models import DEFAULT

        if a.model == DEFAULT:  # the paper's rod is the paper's tree at generated/ top level: the whole build
            a.model = None
    if a.check:
        return check(a.out, a.model)
    if a.model is None:
        started = start_decided()
        build(a.out)
        write_files(a.out, decided_files(started))
    write_files(a.out, models_files(None if a.model is None else [a.model], verbose=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
