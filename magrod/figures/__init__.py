"""The figures wing: one module per paper section, each figure a builder with one signature

    build(out_dir, *, quick=False, progress=False) -> list[str]     (the paths written, atomically)

registered here.  Builders call the numerics (magrod.*), draw with matplotlib (Agg) and write
pictures (PNG, PDF or SVG: figures.common.figure_formats), .npz data and JSON sidecars through magrod.core.io.
Imported lazily: `FIGURES` lists module and function names only."""
from __future__ import annotations

import importlib

# figure number -> (module, builder, description)
FIGURES = {
    "2": ("magrod.figures.melnikov", "figure_2", "Mel'nikov function M(psi0)/sqrt(a-2b), derived and printed integrands"),
    "3": ("magrod.figures.homoclinic", "figure_3", "phase portraits and the homoclinic orbit (theta, pbar_theta, psi')"),
    "4": ("magrod.figures.poincare", "figure_4", "Poincaré sections, h = 0.9, lambdabar in {0.135, 0.1575, 0.175, 0.186}"),
    "5": ("magrod.figures.poincare", "figure_5", "Poincaré sections, h = 0.8, gamma in {0.15, 0.205, 0.208, 0.24}"),
    "6": ("magrod.figures.multipulse", "figure_6", "two- and four-pulse homoclinic orbits and rod shapes (lambdabar = 0.001)"),
    "7": ("magrod.figures.multipulse", "figure_7", "two- and three-pulse homoclinic orbits and rod shapes (lambdabar = 0.5)"),
    # beyond the paper
    "continuation": ("magrod.figures.continuation", "build",
                     "Fig 6 2-pulse orbit as a curve in (lam, m) on mu = 2 lam; primaries to the periodic saddle vs mu"),
    "chaos": ("magrod.figures.chaos", "build", "chaos map (growth exponent) in lambdabar x gamma at Figure 4's start"),
    "orbitdiagram": ("magrod.figures.portrait", "build",
                     "orbit diagram: section points vs lambdabar 0.12..0.2 at Figure 4's start, its panels marked"),
    "splitting": ("magrod.figures.splitting", "build",
                  "splitting of the separatrix vs eps (a = 2b and a > 2b) with the integrable controls"),
    "proof": ("magrod.figures.proof", "build",
              "computer-assisted proof: transverse homoclinic orbits of the tilted saddle-focus, verified certificate"),
    "landscape": ("magrod.figures.models", "build",
                  "the landscape of sec. 1 re-derived from the rod models, the anisotropic B1:B2:C scan"),
}


def builder(number: str):
    """The builder of a registered figure (ParameterError naming `number` if unknown)."""
    from ..core.errors import ParameterError

    number = str(number).strip()
    if number not in FIGURES:
        raise ParameterError("number", f"must be one of {', '.join(FIGURES)}, got {number!r}")
    module, func, _ = FIGURES[number]
    return getattr(importlib.import_module(module), func)


def build(number: str, out_dir, *, quick=False, progress=False, formats=("png",)) -> list[str]:
    """Run the builder of figure `number` into `out_dir`; its pictures in each of `formats` (png, pdf, svg).

    Returns every path written.  If the builder fails, every file it had written is removed again before the
    exception propagates, so a failed figure leaves none of its files behind (and a report cannot read the
    sidecar of a half-made figure as a result)."""
    from ..core.io import record_writes
    from .common import figure_formats

    make = builder(number)
    with figure_formats(formats), record_writes() as written:
        try:
            paths = [str(p) for p in make(out_dir, quick=quick, progress=progress)]
        except BaseException:
            for p in written:
                try:
                    p.unlink()
                except OSError:
                    pass
            raise
    return paths + [str(p) for p in dict.fromkeys(written) if str(p) not in paths]
