"""magrod.separatrix: the splitting of the separatrix, the Mel'nikov integral, the rigorous enclosure of S.

The researcher's function is on the face (`mr.splitting`).  `__all__` below is the package's second tier: the
public names the command line and the figures use besides the face (docs/architecture.md, the API reference; tests/test_wings.py allows these
and nothing deeper).  Imported lazily."""
from ..core.lazy import namespace

_API = {
    # the splitting: scans in the perturbation parameter eps, their summary, the leading coefficient
    "EPS_SCAN": "splitting",
    "SplittingScan": "splitting",
    "splitting_scan": ("splitting", "scan"),
    "tilted_scan": "splitting",
    "tilted_curve": "splitting",
    "scan_summary": "splitting",
    "leading_coefficient": "splitting",
    "compare_leading": "splitting",
    # the generic (a > 2b) leading term
    "GENERIC_CASES": ("generic", "CASES"),
    "compare_generic": "generic",
    "circle_prediction": "generic",
    # S in ball arithmetic and the parameter-box theorem
    "enclose_S": "enclosure",
    "box_theorem": "enclosure",
    # the Mel'nikov integral
    "INTEGRANDS": "melnikov",
    "melnikov_amplitude": ("melnikov", "amplitude"),
    "melnikov_amplitude_zero": ("melnikov", "amplitude_zero"),
    "melnikov_function": "melnikov",
    "primitive_check": "melnikov",
    # any model with a saddle and a small parameter: M(phi0) along its integrable member's homoclinic orbit
    "melnikov_along_orbit": "melnikov_orbit",
}

__getattr__, __dir__, __all__ = namespace(__name__, _API)
del namespace
