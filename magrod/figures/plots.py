"""`.plot(ax=None)` of every result object: one drawing function per result class, registered in PLOTTERS.

Result.plot (magrod/core/results.py) lands here, so the numerics never import matplotlib.  Every function takes
the result and an Axes (None: a new figure via pyplot, so that it shows inline in Jupyter) and returns the
Axes; none switches matplotlib's backend or writes a file.
"""
from __future__ import annotations

import importlib

# result class name -> "module:function" (module relative to magrod.figures), imported on first use
PLOTTERS: dict[str, str] = {
    "PoincareResult": "poincare:plot_section",
    "LyapunovResult": "chaos:plot_lyapunov",
    "ChaosMap": "chaos:plot_map",
    "LyapunovSpectrum": "chaos:plot_spectrum",
    "GaliResult": "chaos:plot_gali",
    "IntegrabilityReport": "integrability:plot_involution",
    "RegimeSearch": "integrability:plot_regime_search",
    "FirstIntegralSearch": "integrability:plot_first_integrals",
    "Splitting": "splitting:plot_splitting",
    "MelnikovFunction": "splitting:plot_melnikov_function",
    # orbits (magrod/figures/orbits.py)
    "StraightRod": "orbits:plot_saddle",
    "PeriodicSaddle": "orbits:plot_saddle",
    "HomoclinicOrbit": "orbits:plot_homoclinic",
    "MultipulseOrbit": "orbits:plot_orbit",
    "MultipulseSearch": "orbits:plot_search",
    "PulseSearch": "orbits:plot_pulse_search",
    "Branch": "orbits:plot_branch",
    "RodShape": "orbits:plot_rod_shape",
    "Equilibrium": "orbits:plot_equilibrium",
    "SymmetricOrbit": "orbits:plot_symmetric_orbit",
    # many orbits (magrod/figures/portrait.py)
    "SectionPortrait": "portrait:plot_portrait",
    "OrbitDiagram": "portrait:plot_orbit_diagram",
    "GenericTerm": "splitting:plot_generic_term",
    "GenericComparison": "splitting:plot_generic_comparison",
    "CirclePrediction": "splitting:plot_circle",
    # the rod family (magrod/figures/models.py)
    "ModelSection": "models:plot_model_section",
    "ModelLyapunov": "models:plot_model_lyapunov",
    "ModelSearch": "models:plot_model_search",
    "Landscape": "models:plot_landscape",
    "ModelChaosMap": "models:plot_model_chaos_map",
    "ModelSplitting": "models:plot_model_splitting",
    "MelnikovScan": "models:plot_model_splitting",
}


def axes(ax=None, *, projection=None, figsize=(5.0, 4.0)):
    """ax, or a new Axes of a new pyplot figure (pyplot's current backend: inline in Jupyter, Agg headless)."""
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=figsize, layout="constrained")
    return fig.add_subplot(projection=projection)


def plot(result, ax=None, **kw):
    """Draw `result` with its registered plotter and return the Axes."""
    name = type(result).__name__
    if name not in PLOTTERS:
        raise TypeError(f"{name} has no plot; plottable results: {', '.join(sorted(PLOTTERS))}")
    module, func = PLOTTERS[name].split(":")
    return getattr(importlib.import_module(f"{__package__}.{module}"), func)(result, ax=ax, **kw)
