"""magrod.paper: what belongs to the paper (Sinden & van der Heijden, spatial chaos of a conducting rod) alone: its
printed values and panels (fig:poincare1, fig:poincare2), the experiments run on them (every panel's section,
the indicators of the panels' orbits), and its epsilon scans and generic cases of the splitting.  The figures and
`magrod reproduce` use it; the general numerics (magrod.chaos, magrod.orbits, ...) know nothing of panels.

Imported lazily: `import magrod.paper` loads nothing numerical until a name is used.
"""
from __future__ import annotations

from ..core.lazy import namespace

_API = {
    # printed values and panels
    **{k: "printed" for k in ("PANELS", "Panel", "panel", "panel_kwargs", "with_overrides", "PAPER_CLAIMS",
                              "POINCARE_ITERATES", "MULTIPULSE", "FIG2_M", "FIG2_GAMMAS", "FIG2_ZERO_BRACKET",
                              "FIG3")},
    # experiments on the panels
    "run_panels": "panels",
    "panel_indicators": "panels",
    # the epsilon scans of the splitting and its generic cases (numerics: the splitting engine)
    **{k: "splitting" for k in ("eps_scan", "tilted_scan", "EPS_SCAN", "GENERIC_CASES", "compare_generic")},
}

__getattr__, __dir__, __all__ = namespace(__name__, _API)
del namespace
