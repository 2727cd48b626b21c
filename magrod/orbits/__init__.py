"""magrod.orbits: saddles, homoclinic and multipulse orbits, their continuation, the rod's shape.

The researcher's functions are on the face (`mr.saddle`, `mr.multipulse_orbits`, `mr.continue_branch`, ...).
`__all__` below is the package's second tier: the public names the command line, the figures and the explorer use
besides the face (docs/architecture.md, the API reference; tests/test_wings.py allows these and nothing deeper).  Imported lazily."""
from ..core.lazy import namespace

_API = {
    # the saddles
    "straight_rod": "equilibrium",
    "on_level": "equilibrium",
    "periodic_saddle": "periodic",
    # the closed-form lambdabar = 0 homoclinic orbit
    "homoclinic_closed_form": ("homoclinic", "homoclinic"),
    "verify_homoclinic": ("homoclinic", "verify"),
    "validate_homoclinic": ("homoclinic", "validate"),
    "phase_portrait_energy": "homoclinic",
    # N-pulse orbits: one shot, the search, the periodic saddle's search; the plotted window
    "shoot_multipulse": ("multipulse", "shoot"),
    "find_multipulse": ("multipulse", "find_orbits"),
    "find_periodic_multipulse": ("periodic_multipulse", "find"),
    "THETA_CUT": "shooting",
    # branches with folds
    "fold_summary": "continuation",
    "periodic_problem": "continuation",
    "mu2lam_problem": "continuation",
    "point_at": "continuation",
    "pseudo_arclength": "continuation",
    # every model: equilibria on a leaf, the model's reversors, symmetric orbits, their branches
    "relative_equilibrium": "equilibria",
    "reversors": "equilibria",
    "symmetric_homoclinic": "reversible",
    "continue_equilibrium": "reversible",
    "continue_homoclinic": "reversible",
    "orbit_from_file": "reversible",
    # the rod in space
    "rod_from_orbit": ("rod", "from_orbit"),
    "reconstruct_rod": ("rod", "reconstruct"),
}

__getattr__, __dir__, __all__ = namespace(__name__, _API)
del namespace
