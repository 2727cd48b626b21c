"""Progress bars for long runs: tqdm on stderr, off under --quiet/--json.  Numerics take a plain callable
`progress(n_done_since_last_call)`; the callers (figures, CLI) own the bar."""
from __future__ import annotations

import sys
import threading
from contextlib import contextmanager


@contextmanager
def bar(total: int, desc: str, enabled: bool = True, unit: str = "it"):
    """Yields a thread-safe callable update(n) (a no-op when disabled); the bar is closed on exit.  The bar
    appears at the first update, so that a run refused on its input (before any work) prints nothing but its
    one error line."""
    if not enabled:
        yield lambda n=1: None
        return
    from tqdm import tqdm

    bars = []
    lock = threading.Lock()

    def update(n=1):
        with lock:
            if not bars:
                bars.append(tqdm(total=total, desc=desc, unit=unit, leave=False, smoothing=0.05, file=sys.stderr))
            bars[0].update(n)

    try:
        yield update
    finally:
        for t in bars:
            t.close()
