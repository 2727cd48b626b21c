"""magrod.integrability: the symbolic integrability report, the exact search for first integrals, the rod family.

The researcher's function is on the face (`mr.integrability_report`).  `__all__` below is the package's second
tier: the public names the command line and the figures use besides the face (docs/architecture.md, the API reference; tests/test_wings.py
allows these and nothing deeper).  Imported lazily: `magrod check` loads neither heyoka nor matplotlib."""
from ..core.lazy import namespace

_API = {
    # the report read from generated/report.json
    "load_report": ("report", "load_report"),
    "report_summary": ("report", "summary"),
    "format_report": ("report", "format_text"),
    "custom_involution": "report",
    "model_report": "report",
    "report_row_details": ("report", "row_details"),
    # the exact/modular search for polynomial first integrals
    "first_integral_search": "first_integrals",
    "format_integrals": ("first_integrals", "format_text"),
    "MAX_DEGREE": "exact",
    "DEFAULT_SEED": "exact",
    "search_model": ("model_search", "model_search"),
    # the landscape of sec. 1
    "rod_landscape": ("landscape", "landscape"),
    "format_landscape": ("landscape", "format_text"),
    "stiffness_scan": "landscape",
    # the decided results: Kovalevskaya exponents, Morales-Ramis, the symmetric-rod theorem
    "decided_theorem": ("decided", "theorem"),
}

__getattr__, __dir__, __all__ = namespace(__name__, _API)
del namespace
