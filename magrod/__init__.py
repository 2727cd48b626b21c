"""magrod: spatial chaos of an extensible, current-carrying elastic rod in a uniform magnetic field.

A SymPy -> heyoka pipeline reproducing (and correcting) Sinden & van der Heijden, "Spatial chaos of an extensible
conducting rod in a uniform magnetic field".  The public API is the flat namespace below (``import magrod as mr``);
everything else is an implementation detail.  Numerics are built from the machine-written modules in
``magrod.generated`` (written by ``magrod.derive``, the only place SymPy is used).

Importing magrod is cheap and has no process-wide side effects: heyoka, matplotlib and Dask are imported when a
function that needs them is first used (PEP 562 module ``__getattr__``).
"""
from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

__version__ = "0.1.0"


def _source_checkout() -> None:
    """Make ``magrod.generated`` and ``magrod.derive`` importable when magrod is imported from a source checkout
    without installing it (a script or notebook in the repository root finds ./magrod first): there the two
    packages are the top-level folders generated/ and derive/ beside magrod/, which an installation maps to
    magrod.generated and magrod.derive (pyproject.toml, [tool.setuptools.package-dir])."""
    here = Path(__file__).resolve().parent
    for sub in ("generated", "derive"):
        name = f"{__name__}.{sub}"
        if name in sys.modules or (here / sub).is_dir() or importlib.util.find_spec(name) is not None:
            continue
        init = here.parent / sub / "__init__.py"
        if not init.is_file():
            continue
        spec = importlib.util.spec_from_file_location(name, init, submodule_search_locations=[str(init.parent)])
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
        globals()[sub] = module  # as the import system binds a submodule on its parent


_source_checkout()

from .core.lazy import namespace  # noqa: E402  (after the checkout's generated/ is importable)

# public name -> module that defines it (relative to magrod); imported on first attribute access
_API = {
    # the model and its vocabulary
    "System": "core.system",
    "RodParams": "core.params",
    "Precision": "core.precision",
    "ParameterError": "core.errors",
    "panel": "core.printed",
    # chaos: sections, indicators, maps
    "poincare_section": "chaos.section",
    "poincare_sections": "chaos.section",
    "section_start": "chaos.section",
    "section_points": "chaos.section",
    "SectionStart": "chaos.section",
    "SectionOptions": "chaos.section",
    "section_portrait": "chaos.portrait",
    "orbit_diagram": "chaos.portrait",
    "lyapunov": "chaos.lyapunov",
    "lyapunov_spectrum": "chaos.spectrum",
    "gali": "chaos.spectrum",
    "chaos_map": "store.resumable",  # in memory (chaos.maps) or, store=DIR, resumable
    # saddles and orbits
    "saddle": "orbits.shooting",
    "homoclinic_orbit": "orbits.homoclinic",
    "multipulse_orbits": "orbits.multipulse",
    "continue_branch": "orbits.continuation",
    "rod_shape": "orbits.rod",
    # the separatrix
    "splitting": "separatrix.splitting",
    # symbolic checks
    "integrability_report": "integrability.report",
    # in the browser
    "explore": "explorer",
}

__getattr__, __dir__, __all__ = namespace(__name__, _API)
del namespace
