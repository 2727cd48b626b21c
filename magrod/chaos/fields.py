"""What a chaos indicator run returns per orbit, described once: name, unit, meaning, and the short name the
CLI and the figures use.  Light (no heyoka, no numpy): the CLI reads it to offer `--indicator` choices, the
store to label its arrays, the figures to label colour bars.  Adding an indicator = a row here + its
computation in magrod/chaos/indicators.py (+ a test): docs/architecture.md walks through it."""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Field:
    name: str      # array name in Indicators, ChaosMap.fields and the zarr store
    unit: str
    long: str      # long_name attribute of the stored array
    short: str | None = None  # name for `magrod chaosmap --indicator` and ChaosMap.plot(indicator=...), if mappable
    label: str = ""  # colour-bar label


# Per-orbit outputs of indicators._run_batch, in this order (the order of Indicators' arrays).
INDICATOR_FIELDS = (
    Field("lyap", "1/length (scaled arclength of eq:nondim_1)", "finite-time maximal Lyapunov exponent L(T)/T",
          "lyap", "finite-time Lyapunov exponent L(T)/T"),
    Field("fli", "1 (ln |w|)", "Fast Lyapunov Indicator max_{t<=T} ln|w(t)|", "fli", "FLI = max ln|w(t)|, t <= T"),
    Field("fli_half", "1 (ln |w|)", "FLI at T/2"),
    Field("growth_exponent", "1", "(FLI(T) - FLI(T/2))/ln 2: power of tangent growth over [T/2, T]", "growth",
          "growth exponent (FLI(T) - FLI(T/2))/ln 2"),
    Field("max_abs_dH", "1", "max |H - H(0)| along the orbit"),
    Field("casimir_drift", "1", "max |C - C(0)| (Casimirs)"),
    Field("min_stretch", "1", "min axial stretch v3 = dH/dn3 at the sample times"),
)
# ... and what a map adds per grid point
MAP_EXTRA_FIELDS = (Field("p_psi0", "1", "start pbar_psi (root of Hbar = h)"),)

# ... and what a map with early exit adds per grid point (magrod.chaos.indicators.tangent_indicators)
EXIT_FIELDS = (Field("exit_time", "1/length (scaled arclength of eq:nondim_1)",
                     "time the orbit's integration stopped: T, or the first sample time t_e >= T/2 at which "
                     "(FLI(t_e) - FLI(T/2))/ln 2 exceeded the exit level (then lyap = L(t_e)/t_e, fli and the "
                     "conservation maxima are over t <= t_e, growth_exponent is a lower bound of its value at T); "
                     "NaN where not computed"),)

KEYS = tuple(f.name for f in INDICATOR_FIELDS)
BY_NAME = {f.name: f for f in INDICATOR_FIELDS + MAP_EXTRA_FIELDS + EXIT_FIELDS}
MAPPABLE = {f.short: f for f in INDICATOR_FIELDS if f.short}  # short name -> Field
