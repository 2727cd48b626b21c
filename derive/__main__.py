"""python -m derive            regenerate generated/
python -m derive --check    regenerate into a temporary directory and fail (exit 1) with a diff if generated/
                            is stale."""
from __future__ import annotations

import argparse
import difflib
import sys
import tempfile
from pathlib import Path

from .build import build

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


def check(target: Path) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        fresh = build(Path(tmp), verbose=True)
    stale = stale_files(fresh, target)
    if stale:
        print(f"\nderive --check: generated/ is stale ({', '.join(stale)}). Run `python -m derive` and commit.")
        return 1
    print("derive --check: generated/ is up to date")
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m derive", description=__doc__)
    ap.add_argument("--check", action="store_true", help="fail with a diff if generated/ is stale")
    ap.add_argument("--out", type=Path, default=GENERATED, help="output directory")
    a = ap.parse_args(argv)
    if a.check:
        return check(a.out)
    build(a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
