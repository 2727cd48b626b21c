"""What the paper printed: the parameters of every figure and the numbers it claims, in one place.

Used by the figures, `magrod reproduce` (claim rows) and the benchmarks alike.  These are *comparison targets
and inputs of the paper's experiments*, never formulas (printed formulas live in derive/paper.py).  Each entry
names the paper label it comes from.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..core.params import RodParams

# --- sec. 7, fig:Mel_ext -----------------------------------------------------------------------------------------
FIG2_M = 1.7
FIG2_GAMMAS = (1.0, 1.2, 1.4, 1.6, 1.8, 2.0)
FIG2_ZERO_BRACKET = (1.8, 2.0)  # "the amplitude is identically zero for a gamma between 1.8 and 2"

# --- sec. 6, fig:angles ------------------------------------------------------------------------------------------
# m = 1.7, gamma = 1 (panels a, c-e); panel (b) printed as m = 2.2 "> m_c"; m_super = 3 is our own comparison panel.
# paper_axes: the axis ranges read off the LaTeX picture labels of fig:angles.
FIG3 = {"m": 1.7, "gamma": 1.0, "m_b": 2.2, "m_super": 3.0,
        "paper_axes": {"a": ((-1.5, 1.5), (-0.5, 0.5)), "b": ((-1.5, 1.5), (-0.8, 0.8)),
                       "c": ((-1, 1), (0, 1.2)), "d": ((-1, 1), (-0.3, 0.3)), "e": ((-1, 1), (0.45, 0.75))}}

# --- sec. 8, fig:poincare1 and fig:poincare2 ---------------------------------------------------------------------
# fig:poincare1: one orbit per panel from theta = 0.1, pbar_theta = 0.5, psi = 0 at h = 0.9;
# fig:poincare2: from theta = 0.1, pbar_theta = 1, psi = 0 at h = 0.8.
_F4 = dict(m=1.7, mu=0.4, gamma=3.0, delta=3.0)
_F5 = dict(m=1.7, mu=4.0, delta=0.25, lam=2.0)
PANELS = {
    **{f"4{k}": dict(params=RodParams(**_F4, lam=lam), h=0.9, theta0=0.1, ptheta0=0.5, psi0=0.0,
                     label=f"fig:poincare1{k}", vary=("lam", lam))
       for k, lam in zip("abcd", (0.135, 0.1575, 0.175, 0.186))},
    **{f"5{k}": dict(params=RodParams(**_F5, gamma=g), h=0.8, theta0=0.1, ptheta0=1.0, psi0=0.0,
                     label=f"fig:poincare2{k}", vary=("gamma", g))
       for k, g in zip("abcd", (0.15, 0.205, 0.208, 0.24))},
}
POINCARE_ITERATES = 10_000  # "10000 iterates" per panel (fig:poincare1)
# "runs up to t = 84000" (fig:poincare1) and "t = 81000" (fig:poincare2), Hbar preserved to 3.6e-9 / 3.9e-9
PAPER_CLAIMS = {"4": dict(t_final=84000.0, max_abs_dH=3.6e-9, label="fig:poincare1"),
                "5": dict(t_final=81000.0, max_abs_dH=3.9e-9, label="fig:poincare2")}

# --- sec. 8, fig:multimodal1 and fig:multimodal2 -----------------------------------------------------------------
MULTIPULSE = {
    6: {"params": RodParams(m=1.7, mu=0.002, gamma=1.0, delta=1.0, lam=0.001), "show": (2, 4),
        "label": "fig:multimodal1", "caption": "two-pulse (solid) and four-pulse (dashed)"},
    7: {"params": RodParams(m=1.7, mu=1.0, gamma=0.01, delta=0.01, lam=0.5), "show": (2, 3),
        "label": "fig:multimodal2", "caption": "two-pulse (solid) and three-pulse (dashed)"},
}


@dataclass(frozen=True)
class Panel:
    """A Poincare panel of the paper: its rod, energy level and start on the chart (theta0, pbar_theta0, psi0),
    the figure label and which parameter the figure varies across its panels."""

    key: str  # "4a" .. "5d"
    label: str  # the paper's figure label with the panel letter ("fig:poincare1a")
    params: RodParams
    h: float
    theta0: float  # the start on the chart
    ptheta0: float  # pbar_theta0 of the start
    psi0: float  # psi0 of the start
    vary: tuple  # (parameter, value): what the figure varies across its panels, lam (Fig 4) or gamma (Fig 5)

    def start(self) -> dict:
        """{h, theta0, ptheta0, psi0}."""
        return {"h": self.h, "theta0": self.theta0, "ptheta0": self.ptheta0, "psi0": self.psi0}


def panel(key) -> Panel:
    """A Poincare panel of the paper, by its key: "4a" to "4d" (fig:poincare1), "5a" to "5d" (fig:poincare2).

    Parameters
    ----------
    key : str
        Figure number and panel letter, case-insensitive.

    Returns
    -------
    Panel
        params (RodParams), h, theta0, ptheta0, psi0, label (the paper's figure label), vary.

    Raises
    ------
    ParameterError
        Naming `panel` if the key is unknown.

    Examples
    --------
    >>> import magrod as mr
    >>> p = mr.panel("4a")
    >>> p.params.lam, p.h, p.label
    (0.135, 0.9, 'fig:poincare1a')

    Notes
    -----
    The start values are those printed with fig:poincare1 (theta = 0.1, pbar_theta = 0.5, psi = 0 at h = 0.9)
    and fig:poincare2 (theta = 0.1, pbar_theta = 1, psi = 0 at h = 0.8); the panels differ in lambdabar
    (Fig 4) or gamma (Fig 5), named by `vary`.
    """
    from ..core.errors import ParameterError

    if isinstance(key, Panel):
        return key
    k = str(key).lower()
    if k not in PANELS:
        raise ParameterError("panel", f"unknown panel {key!r}; choose one of {', '.join(PANELS)}")
    P = PANELS[k]
    return Panel(k, P["label"], P["params"], P["h"], P["theta0"], P["ptheta0"], P["psi0"], tuple(P["vary"]))


def panel_kwargs(key: str) -> dict:
    """Keyword arguments (params, h, theta0, ptheta0, psi0) of a paper panel."""
    P = panel(key)
    return dict(params=P.params, h=P.h, theta0=P.theta0, ptheta0=P.ptheta0, psi0=P.psi0)


def with_overrides(system, overrides: dict):
    """The system (a RodParams, a Panel, a panel key, or a list of them) with model parameters replaced by keyword
    overrides: `poincare_section("4a", lam=0.15)` is Fig 4(a)'s start on the rod with lambdabar = 0.15 (one
    calling convention, as `chaos_map(..., lam=...)`).  A panel keeps its start and gets the key
    "4a, lam=0.15", so a result never claims to be the paper's panel when it is not.  ParameterError names an
    override that is not a model parameter."""
    from dataclasses import replace

    from ..generated.names import PARAMS
    from ..core.errors import ParameterError

    if not overrides:
        return system
    for k in overrides:
        if k not in PARAMS:
            raise ParameterError(k, f"unknown keyword: neither an option of this function nor a model parameter "
                                    f"({', '.join(PARAMS)})")
    if isinstance(system, (list, tuple)):
        return [with_overrides(s, overrides) for s in system]
    if isinstance(system, RodParams):
        return system.replace(**overrides)
    if isinstance(system, (str, Panel)):
        P = panel(system)
        tag = ", ".join(f"{k}={float(v):g}" for k, v in overrides.items())
        return replace(P, key=f"{P.key}, {tag}", params=P.params.replace(**overrides))
    raise ParameterError("params", f"must be a RodParams, a Panel or a panel name, got {type(system).__name__}")
