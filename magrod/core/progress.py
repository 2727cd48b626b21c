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
    one error line.  update.set_total(n) sets a total learnt only once the work is planned (a stored map knows its
    tiles to do once its store is verified); update.note(text) shows a short text beside the bar."""
    if not enabled:
        def nothing(n=1):
            return None

        nothing.set_total = lambda n: None
        nothing.note = lambda text: None
        yield nothing
        return
    from tqdm import tqdm

    bars = []
    lock = threading.Lock()

    def update(n=1):
        with lock:
            if not bars:
                bars.append(tqdm(total=total, desc=desc, unit=unit, leave=False, smoothing=0.05, file=sys.stderr))
            bars[0].update(n)

    def set_total(n):
        nonlocal total
        with lock:
            total = n
            if bars:
                bars[0].total = n
                bars[0].refresh()

    def note(text):
        """A short text beside the bar (what a running part reports; the work has started, so the bar appears)."""
        with lock:
            if not bars:
                bars.append(tqdm(total=total, desc=desc, unit=unit, leave=False, smoothing=0.05, file=sys.stderr))
            bars[0].set_postfix_str(text[:120])

    update.set_total = set_total
    update.note = note
    try:
        yield update
    finally:
        for t in bars:
            t.close()
