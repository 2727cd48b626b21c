"""The paper's own experiments on its panels (fig:poincare1, fig:poincare2): every panel's section at once, and
the chaos indicators of the paper's orbits.  The general numerics (magrod.chaos) know nothing of panels; the
figures and `magrod reproduce` use these."""
from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np

from ..chaos.indicators import _KEYS, REASONS, body_indicators
from ..chaos.maps import panel_base, start_point
from ..chaos.section import poincare_section
from ..core.errors import require_positive_int
from .printed import panel_kwargs


def run_panels(keys, *, iterates=10_000, workers=2, progress=None, **kw) -> dict:
    """Run several paper panels (magrod.paper.printed.PANELS) concurrently in threads (heyoka's propagate releases the
    GIL; each thread owns its integrators).  Returns {key: PoincareResult}.  progress: optional thread-safe
    callable(n_new_points) (e.g. magrod.core.progress.bar)."""
    keys = [str(k).lower() for k in keys]
    for k in keys:
        panel_kwargs(k)
    iterates = require_positive_int("iterates", iterates)

    def one(k):
        return k, poincare_section(k, iterates=iterates, progress=progress, **kw)

    with ThreadPoolExecutor(max_workers=max(1, int(workers))) as ex:
        return dict(ex.map(one, keys))


def panel_indicators(keys=("4a", "4b", "4c", "4d"), *, t_max=3000.0, tol=None, root="smallest") -> dict:
    """{panel: dict of the indicators of the paper's orbit} (one batch).  Cost ~t_max * 5 us per panel."""
    starts = [start_point(panel_base(k), root) for k in keys]
    ind = body_indicators(np.array([s[0] for s in starts]).T, np.array([s[1] for s in starts]).T, t_max=t_max,
                          tol=tol)
    return {k: {f: (float(getattr(ind, f)[i]) if f != "status" else REASONS[int(ind.status[i])]) for f in
                _KEYS + ("status",)} | {"chaotic": bool(ind.chaotic[i])} for i, k in enumerate(keys)}
