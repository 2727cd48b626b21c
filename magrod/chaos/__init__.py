"""magrod.chaos: Poincaré sections, chaos indicators, chaos maps.

The researcher's functions are on the face (`mr.poincare_section`, `mr.chaos_map`, ...).  `__all__` below is the
package's second tier: the public names the command line, the figures and the explorer use besides the face
(docs/architecture.md, the API reference; tests/test_wings.py allows these and nothing deeper).  Imported lazily (magrod.core.lazy)."""
from ..core.lazy import namespace

_API = {
    # what a map can show, and its status codes
    "MAPPABLE": "fields",
    "OK": "indicators",
    "GROWTH_THRESHOLD": "indicators",
    # maps: their specification, axes, tiles and the printed panels' indicators
    "MapSpec": "maps",
    "AXIS_NAMES": "maps",
    "parse_axis": "maps",
    "panel_base": "maps",
    "map_tiles": ("maps", "tiles"),
    "MAX_LEVELS": "refine",
    # sections: the level's admissible window, the start's pbar_psi, start tables, the paper's panels
    "admissible_interval": "section",
    "solve_p_psi": "section",
    "start_table": "section",
    "DEFAULT_FORMULATION": "section",
    "STRETCH_DT": "section",
    "grid_starts": "portrait",
    "start_indicators": "portrait",
    "DEFAULT_T_MAX": "lyapunov",
    # a model of the rod family (docs/models.md)
    "model_section": "model_chaos",
}

__getattr__, __dir__, __all__ = namespace(__name__, _API)
del namespace
