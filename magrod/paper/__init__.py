"""magrod.paper: what belongs to the paper (Sinden & van der Heijden, spatial chaos of a conducting rod) alone: its
printed values and panels (fig:poincare1, fig:poincare2), the experiments run on them (every panel's section,
the indicators of the panels' orbits), and its epsilon scans and generic cases of the splitting.  The figures and
`magrod reproduce` use it; the general numerics (magrod.chaos, magrod.orbits, ...) know nothing of panels.

Imported lazily: `import magrod.paper` loads nothing numerical until a name is used.
"""
from __future__ import annotations

import importlib

_API = {
    # printed values and panels
    "PANELS": "magrod.paper.printed",
    "Panel": "magrod.paper.printed",
    "panel": "magrod.paper.printed",
    "panel_kwargs": "magrod.paper.printed",
    "with_overrides": "magrod.paper.printed",
    "PAPER_CLAIMS": "magrod.paper.printed",
    "POINCARE_ITERATES": "magrod.paper.printed",
    "MULTIPULSE": "magrod.paper.printed",
    "FIG2_M": "magrod.paper.printed",
    "FIG2_GAMMAS": "magrod.paper.printed",
    "FIG3": "magrod.paper.printed",
    # experiments on the panels
    "run_panels": "magrod.paper.panels",
    "panel_indicators": "magrod.paper.panels",
    # the epsilon scans of the splitting and its generic cases (defined with the splitting engine)
    "eps_scan": ("magrod.separatrix.splitting", "scan"),
    "tilted_scan": ("magrod.separatrix.splitting", "tilted_scan"),
    "EPS_SCAN": ("magrod.separatrix.splitting", "EPS_SCAN"),
    "GENERIC_CASES": ("magrod.separatrix.generic", "CASES"),
    "compare_generic": ("magrod.separatrix.generic", "compare_generic"),
}
__all__ = sorted(_API)


def __getattr__(name: str):
    if name in _API:
        mod, attr = (_API[name], name) if isinstance(_API[name], str) else _API[name]
        return getattr(importlib.import_module(mod), attr)
    raise AttributeError(f"module 'magrod.paper' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_API))
