"""The paper's splitting experiments (sec. 7): the epsilon scans of the splitting distance against Mel'nikov and the
generic cases of the splitting coefficient.  Their numerics are the splitting engine's (magrod.separatrix); this
is the paper package's door to them (the figures and `magrod reproduce` take them from here)."""
from __future__ import annotations

from ..separatrix.generic import CASES as GENERIC_CASES  # noqa: F401
from ..separatrix.generic import compare_generic  # noqa: F401
from ..separatrix.splitting import EPS_SCAN, tilted_scan  # noqa: F401
from ..separatrix.splitting import scan as eps_scan  # noqa: F401
