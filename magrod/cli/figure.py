"""`magrod figure N`: write one figure of the paper (PNG, plus .npz data and JSON sidecars) into --out."""
from __future__ import annotations


def add_arguments(p):
    from ..figures import FIGURES

    p.add_argument("number", help="figure number: " + ", ".join(FIGURES))
    p.add_argument("--out", default="out", help="output directory")
    p.add_argument("--quick", action="store_true", help="reduced-size variant (fewer iterates/points)")


def run(args) -> dict:
    from ..figures import build, builder
    from ..core.io import check_out_path, ensure_writable_dir

    builder(args.number)  # an unknown figure fails before the output directory is created
    out = ensure_writable_dir(check_out_path(args.out))
    paths = build(args.number, out, quick=args.quick, progress=not args.quiet)
    return {"ok": True, "figure": str(args.number).strip(), "outputs": paths, "quick": bool(args.quick)}


def format_text(r: dict) -> str:
    return f"figure {r['figure']}: wrote\n  " + "\n  ".join(r["outputs"])
