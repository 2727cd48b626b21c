"""`magrod figure N`: write one figure of the paper (PNG, plus .npz data and JSON sidecars) into --out."""
from __future__ import annotations

import importlib
import inspect
from pathlib import Path

from .errors import ParameterError
from .io import ensure_writable_dir

# figure number -> (module, function).  Each function has the signature f(out_dir, quick=False, progress=True)
# and returns the list of written paths (or a dict with a "paths" entry).
FIGURES = {
    "2": ("magrod.melnikov", "figure_2", "Mel'nikov function M(psi0)/sqrt(a-2b), derived and printed integrands"),
    "3": ("magrod.homoclinic", "figure_3", "phase portraits and the homoclinic orbit (theta, pbar_theta, psi')"),
    "4": ("magrod.poincare", "figure_4", "Poincare sections, h = 0.9, lambdabar in {0.135, 0.1575, 0.175, 0.186}"),
    "5": ("magrod.poincare", "figure_5", "Poincare sections, h = 0.8, gamma in {0.15, 0.205, 0.208, 0.24}"),
    "6": ("magrod.shooting", "figure_6", "two- and four-pulse homoclinic orbits and rod shapes (lambdabar = 0.001)"),
    "7": ("magrod.shooting", "figure_7", "two- and three-pulse homoclinic orbits and rod shapes (lambdabar = 0.5)"),
    # issue 11: not a figure of the paper -- a chaos map around the Figure 4 panels and their indicators
    "chaos": ("magrod.chaos_figures", "build", "chaos map (growth exponent) in lambdabar x gamma at Figure 4's start"),
}


def add_arguments(p):
    p.add_argument("number", help="figure number: " + ", ".join(FIGURES))
    p.add_argument("--out", default="out", help="output directory")
    p.add_argument("--quick", action="store_true", help="reduced-size variant (fewer iterates/points)")


def resolve(number: str):
    number = str(number).strip()
    if number not in FIGURES:
        raise ParameterError("number", f"must be one of {', '.join(FIGURES)}, got {number!r}")
    module, func, _ = FIGURES[number]
    try:
        mod = importlib.import_module(module)
    except ImportError as exc:  # pragma: no cover - a capability that is not installed
        raise ParameterError("number", f"figure {number} needs {module}, which is unavailable: {exc}") from None
    return getattr(mod, func)


def figure_kwargs(fn, quick: bool, progress: bool) -> dict:
    """quick plus the progress switch in whichever spelling the figure function takes."""
    params = inspect.signature(fn).parameters
    kw = {"quick": bool(quick)}
    if "progress" in params or any(p.kind is p.VAR_KEYWORD for p in params.values()):
        kw["progress"] = progress
    elif "quiet" in params:
        kw["quiet"] = not progress
    return kw


def _paths(result) -> list[str]:
    if isinstance(result, dict):
        result = result.get("paths", [])
    return [str(p) for p in result]


def run(args) -> dict:
    fn = resolve(args.number)
    out = ensure_writable_dir(Path(args.out))
    res = fn(out, **figure_kwargs(fn, args.quick, progress=not args.quiet))
    return {"ok": True, "figure": args.number, "outputs": _paths(res), "quick": bool(args.quick)}


def format_text(r: dict) -> str:
    return f"figure {r['figure']}: wrote\n  " + "\n  ".join(r["outputs"])
