"""The older home of the paper's printed values (now magrod.paper.printed), kept as a re-export for one release.

Importing it does not warn; the numerics and figures import magrod.paper.printed, and new code should too.
"""
from ..paper.printed import (  # noqa: F401
    FIG2_GAMMAS,
    FIG2_M,
    FIG2_ZERO_BRACKET,
    FIG3,
    MULTIPULSE,
    PANELS,
    PAPER_CLAIMS,
    POINCARE_ITERATES,
    Panel,
    panel,
    panel_kwargs,
    with_overrides,
)
