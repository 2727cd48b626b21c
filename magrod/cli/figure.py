"""`magrod figure N`: write one figure of the paper (PNG, PDF or SVG, plus .npz data and JSON sidecars) into --out."""
from __future__ import annotations


def add_arguments(p):
    from ..figures import FIGURES
    from .options import add_format

    p.add_argument("number", help="figure number: " + ", ".join(FIGURES))
    from .options import add_out

    add_out(p, files=True, help="output directory")
    p.add_argument("--quick", action="store_true", help="reduced-size variant (fewer iterates/points)")
    add_format(p)


def run(args) -> dict:
    from ..figures import build, builder
    from ..core.io import check_out_path, ensure_writable_dir

    from .options import formats_from

    builder(args.number)  # an unknown figure (or format) fails before the output directory is created
    formats = formats_from(args)
    out = ensure_writable_dir(check_out_path(args.out))
    paths = build(args.number, out, quick=args.quick, progress=not args.quiet, formats=formats)
    return {"ok": True, "figure": str(args.number).strip(), "outputs": paths, "quick": bool(args.quick),
            "formats": list(formats)}


def format_text(r: dict) -> str:
    return f"figure {r['figure']}: wrote\n  " + "\n  ".join(r["outputs"])
