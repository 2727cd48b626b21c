"""The largest requests magrod takes, defined once: the public functions and the command line refuse the same
values with the same words (issue 25: `poincare_section(iterates=10**9)` just ran while the CLI refused it)."""
from __future__ import annotations

LIMITS = {
    "iterates": 2_000_000,   # Poincare points: ~200 bytes and ~0.2 ms each -> 400 MB, ~7 min
    "n": 20_001,             # homoclinic comparison grid (multiprecision, ~1 ms per point)
    "max_pulses": 12,        # N-pulse search: the branch is integrated past N near-saddle passages
    "samples": 2_001,        # multipulse scan: one unstable-branch integration per sample
    "points": 1_000_000,     # rod samples
    "jobs": 64,              # reproduce worker processes
}
