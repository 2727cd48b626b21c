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


def check(target: Path) -> int:
    with tempfile.TemporaryDirectory() as tmp:
        fresh = build(Path(tmp), verbose=True)
    stale = []
    names = sorted(set(fresh) | {p.name for p in target.glob("*") if p.is_file() and p.suffix in (".py", ".json", ".md")})
    for name in names:
        new = fresh.get(name)
        old_path = target / name
        old = old_path.read_text() if old_path.exists() else None
        if new != old:
            stale.append(name)
            diff = difflib.unified_diff((old or "").splitlines(True), (new or "").splitlines(True),
                                        f"generated/{name} (checked in)", f"generated/{name} (fresh)", n=2)
            sys.stdout.writelines(list(diff)[:200])
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
