"""Figure and data files of the separatrix splitting (magrod/splitting.py, docs/nonintegrability.md).

write(result, out_dir)  one scan (SplittingScan or TiltedScan) as JSON + npz + PNG
build(out_dir, quick=False, progress=False)  the verdict figure: (a) a = 2b: |psi_u| and |d| vs eps with fitted
slopes, and the integrable control gamma = delta = 0 at its rounding floor; (b) a > 2b: |s1| vs eps with slope and
the b = 0 control; (c) C(psi) = D(psi)/eps^3 for several eps (collapse, simple zeros at psi = 0, pi)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core.precision import Precision
from ..separatrix import (EPS_SCAN, SplittingScan, compare_leading, leading_coefficient, scan_summary,
                          splitting_scan, tilted_scan)
from ..core.io import atomic_savez, atomic_write_json, ensure_writable_dir, versions
from .common import atomic_savefig, pyplot


def write(res, out_dir, stem: str = "splitting") -> list[str]:
    out = ensure_writable_dir(out_dir)
    d = res.to_dict() if not isinstance(res, SplittingScan) else scan_summary(res)
    paths = [str(atomic_write_json(out / f"{stem}.json", {**d, "versions": versions()}))]
    if isinstance(res, SplittingScan):
        ref = res.crossings[res.precisions[-1]]
        arrays = {"eps": np.array(res.eps), "psi": np.array([c.psi for c in ref]), "d": np.array([c.d for c in ref]),
                  "theta": np.array([c.theta for c in ref])}
    else:
        arrays = {"eps": np.array(res.eps), "s1": np.array([c.sin_coeffs[0] for c in res.curves]),
                  "sin_coeffs": np.array([c.sin_coeffs for c in res.curves])}
    paths.append(str(atomic_savez(out / f"{stem}.npz", **arrays)))
    paths.append(plot(res, out, stem))
    return paths


def plot_control(ax, eps, values, measured, label):
    """An integrable control's values on a log axis without stretching it: a value far below the measured ones
    (zero, or at the rounding level) is drawn at a floor three decades under the smallest measured value, as a
    downward triangle, and the label says "<= floor".  (Drawn at max(|v|, 1e-40), one control point pulled the
    axis down to 1e-40 and squeezed the measurements into its top sixth.)  Returns the floor."""
    v = np.abs(np.asarray(values, float))
    m = np.abs(np.asarray(measured, float))
    m = m[np.isfinite(m) & (m > 0)]
    floor = 1e-3 * float(m.min()) if len(m) else 1e-16
    low = ~(v > floor)
    if (~low).any():
        ax.loglog(np.asarray(eps)[~low], v[~low], "x", label=label)
    if low.any():
        ax.loglog(np.asarray(eps)[low], np.full(int(low.sum()), floor), "v", mfc="none",
                  label=f"{label} $\\leq$ {floor:.0e}")
    return floor


def _loglog(ax, eps, y, fit, label, marker):
    e = np.asarray(eps)
    ax.loglog(e, np.abs(y), marker, label=label)
    if fit is not None:
        ax.loglog(e, abs(fit.C0) * e ** fit.p_int, "k:", lw=0.8)
        ax.annotate(f"p = {fit.p:.3f}", (e[len(e) // 2], abs(y[len(e) // 2])), fontsize=7,
                    textcoords="offset points", xytext=(5, -12))


def plot(res, out_dir, stem: str = "splitting") -> str:
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5, 3.6))
    if isinstance(res, SplittingScan):
        ref = res.crossings[res.precisions[-1]]
        _loglog(ax, res.eps, np.array([c.psi for c in ref]), res.fit_psi, r"$|\psi_u|$", "o-")
        _loglog(ax, res.eps, np.array([c.d for c in ref]), res.fit_d, r"$|d| = |\rho\sin\psi_u|$", "s-")
    else:
        _loglog(ax, res.eps, np.array([c.sin_coeffs[0] for c in res.curves]), res.fit_s1, r"$|s_1|$", "o-")
    ax.set_xlabel(r"$\varepsilon$")
    ax.set_title(f"m={res.m:g}, $\\gamma$={res.gamma:g}, $\\delta$={res.delta:g}, a={res.a:g}, b={res.b:g}", fontsize=8)
    ax.legend(fontsize=7)
    fig.tight_layout()
    p = str(atomic_savefig(fig, Path(out_dir) / f"{stem}.png", dpi=150))
    plt.close(fig)
    return p


FIGURE = {"m": 1.7, "gamma": 1.0, "delta": 1.0}
# (m, gamma, delta, a, b) where the derived leading term (derive/splitting.py) is compared with the measurement
LEADING_CASES = [(1.7, 1.0, 1.0, 2.0, 1.0), (1.7, 1.0, 0.0, 2.0, 1.0), (1.7, 0.0, 1.0, 2.0, 1.0),
                 (1.2, 0.5, 2.0, 2.0, 1.0), (2.2, 2.0, 0.5, 1.0, 0.5), (1.0, 0.0, 1.0, 2.0, 1.0)]


def build(out_dir, *, quick: bool = False, progress: bool = False) -> list[str]:
    plt = pyplot()
    out = ensure_writable_dir(out_dir)
    eps = EPS_SCAN[::2] if quick else EPS_SCAN
    eps_t = [0.1, 0.03, 0.01] if quick else [0.1, 0.0541, 0.0292, 0.0158, 0.00855, 0.00462, 0.0025]
    prec = (Precision.DOUBLE, Precision.LONG_DOUBLE) if quick else (Precision.LONG_DOUBLE, Precision.QUAD)
    eq = splitting_scan(**FIGURE, a=2.0, b=1.0, eps=eps, precisions=prec)
    ctl = splitting_scan(1.7, 0.0, 0.0, 2.0, 1.0, eps, prec, fit=False)
    ti = tilted_scan(**FIGURE, a=4.0, b=1.0, eps=eps_t)
    ti0 = tilted_scan(**FIGURE, a=1.0, b=0.0, eps=eps_t[:3])
    lead = [compare_leading(*c) for c in (LEADING_CASES[:2] if quick else LEADING_CASES)]
    control = leading_coefficient(1.7, 0.0, 0.0)
    paths = [str(atomic_write_json(out / "splitting_leading.json",
                                   {"cases": lead, "control_gamma_delta_0": control.to_dict(),
                                    "versions": versions()}))]
    paths += _enclosure_and_generic(out, quick)
    for r, stem in ((eq, "splitting_a2b"), (ctl, "splitting_a2b_control"), (ti, "splitting_tilted"),
                    (ti0, "splitting_tilted_control")):
        paths += write(r, out, stem)
    fig, axs = plt.subplots(1, 3, figsize=(13, 3.8))
    ax = axs[0]
    ref = eq.crossings[eq.precisions[-1]]
    _loglog(ax, eq.eps, np.array([c.psi for c in ref]), eq.fit_psi, r"$|\psi_u|$", "o-")
    _loglog(ax, eq.eps, np.array([c.d for c in ref]), eq.fit_d, r"$|d|$", "s-")
    ee = np.array([min(eq.eps), max(eq.eps)])
    ax.loglog(ee, np.abs(lead[0]["derived_psi"]) * ee**2, "k--", lw=0.8,
              label=rf"derived $|\psi_u| \approx {abs(lead[0]['derived_psi']):.6f}\,\varepsilon^2$")
    cr = ctl.crossings[ctl.precisions[-1]]
    plot_control(ax, ctl.eps, [c.psi for c in cr], [c.d for c in ref], r"control $\gamma=\delta=0$: $|\psi_u|$")
    ax.set_title(f"(a) a = 2b = 2 (straight rod), {eq.precisions[-1]}", fontsize=8)
    ax.set_xlabel(r"$\varepsilon$")
    ax.legend(fontsize=7)
    ax = axs[1]
    _loglog(ax, ti.eps, np.array([c.sin_coeffs[0] for c in ti.curves]), ti.fit_s1, r"$|s_1|$, a=4, b=1", "o-")
    plot_control(ax, ti0.eps, [c.sin_coeffs[0] for c in ti0.curves], [c.sin_coeffs[0] for c in ti.curves],
                 r"control $b = 0$: $|s_1|$")
    ax.loglog(ti0.eps, [c.fit_residual for c in ti0.curves], "k--", lw=0.6, label="control: Fourier fit residual")
    ax.set_title("(b) a > 2b (tilted saddle-focus)", fontsize=8)
    ax.set_xlabel(r"$\varepsilon$")
    ax.legend(fontsize=7)
    ax = axs[2]
    grid = np.linspace(-np.pi, np.pi, 361)
    for c in ti.curves:
        D = 2 * sum(s * np.sin((k + 1) * grid) for k, s in enumerate(c.sin_coeffs))
        ax.plot(grid, D / c.eps**3, lw=0.9, label=f"$\\varepsilon$ = {c.eps:g}")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel(r"$\psi$ on $\bar p_\theta = 0$")
    ax.set_ylabel(r"$C(\psi) = D(\psi)/\varepsilon^3$")
    ax.set_title(r"(c) a = 4, b = 1: $D = \theta_u(\psi) - \theta_u(-\psi)$", fontsize=8)
    ax.legend(fontsize=6)
    fig.suptitle(f"Separatrix splitting, $m = {FIGURE['m']}$, $\\gamma = {FIGURE['gamma']}$, "
                 f"$\\delta = {FIGURE['delta']}$", fontsize=9)
    fig.tight_layout()
    paths.append(str(atomic_savefig(fig, out / "splitting.png", dpi=150)))
    plt.close(fig)
    return paths


def _enclosure_and_generic(out, quick: bool) -> list[str]:
    """Sidecars of the rigorous splitting: S in ball arithmetic at the six a = 2b cases and the integrable control
    (splitting_enclosure.json), and the derived a > 2b coefficient against the measurement (splitting_generic.json)."""
    from ..separatrix import GENERIC_CASES, box_theorem, circle_prediction, compare_generic, enclose_S

    enc = [enclose_S(repr(m), repr(g), repr(d)).to_dict() for m, g, d, _, _ in LEADING_CASES]  # decimal = exact
    ctl = enclose_S(1.7, 0, 0).to_dict()
    box = box_theorem(("1.65", "1.75"), ("0.95", "1.05"), ("0.25", "3"), initial=(1, 1, 1))
    paths = [str(atomic_write_json(out / "splitting_enclosure.json",
                                   {"cases": enc, "control_gamma_delta_0": ctl, "box": box.to_dict(),
                                    "versions": versions()}))]
    cmp_ = compare_generic(GENERIC_CASES[:2] if quick else GENERIC_CASES)
    circle = circle_prediction(1.7, 1.0, 1.0, 1e-3).to_dict()
    paths.append(str(atomic_write_json(out / "splitting_generic.json",
                                       {**cmp_.to_dict(), "circle_lam_1e-3": circle, "versions": versions()})))
    return paths


def plot_generic_term(g, ax=None, **kw):
    """GenericTerm.plot: the derived odd part D(psi)/eps^3 = 2 (s1/eps^3) sin(psi) of the a > 2b splitting, with its
    zeros at psi = 0, pi (the two primary symmetric orbits)."""
    from .plots import axes

    ax = axes(ax)
    psi = np.linspace(-np.pi, np.pi, 361)
    c = float(g.coefficient.mid())
    ax.plot(psi, 2 * c * np.sin(psi), **kw)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel(r"$\psi$")
    ax.set_ylabel(r"$D/\varepsilon^3$")
    ax.set_title(f"derived, $(m, \\gamma, \\delta, a, b)$ = ({g.m}, {g.gamma}, {g.delta}, {g.a}, {g.b})", fontsize=8)
    return ax


def plot_generic_comparison(r, ax=None, **kw):
    """GenericComparison.plot: measured / derived - 1 per case and precision (the bound as a band)."""
    from .plots import axes

    ax = axes(ax)
    for i, row in enumerate(r.rows):
        for k, (pr, rel) in enumerate(row["rel_difference"].items()):
            ax.semilogy([i], [max(rel, 1e-12)], "os"[k % 2], label=pr if i == 0 else None, **kw)
    ax.axhline(r.tolerance, color="r", lw=0.8, label=f"bound {r.tolerance:g}")
    ax.set_xticks(range(len(r.rows)), [str(tuple(row["case"])) for row in r.rows], rotation=60, ha="right",
                  fontsize=6)
    ax.set_ylabel("|measured/derived - 1|")
    ax.legend(fontsize=7)
    return ax


def plot_circle(p, ax=None, nu=None, **kw):
    """CirclePrediction.plot: W^u on Sigma in the transverse-force plane (chart units): the circle of radius
    sqrt(nu) about lambdabar tan(theta_t/2) + i lambdabar^2 S; symmetric orbits where it meets Im = 0."""
    from .plots import axes

    ax = axes(ax)
    nu = 4 * p.nu_merge if nu is None else nu
    x0 = p.lam * p.lam * p.S / p.psi0  # = lambdabar tan(theta_t/2)
    y0 = p.lam * p.lam * p.S
    ph = np.linspace(0, 2 * np.pi, 361)
    ax.plot(x0 + np.sqrt(nu) * np.cos(ph), y0 + np.sqrt(nu) * np.sin(ph), **kw)
    ax.plot([x0], [y0], "k+")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel(r"$\rho\cos\psi$")
    ax.set_ylabel(r"$\rho\sin\psi$")
    ax.set_title(rf"$\bar\lambda$ = {p.lam:g}, $\nu$ = {nu:.2g} ($\nu^*$ = {p.nu_merge:.2g})", fontsize=8)
    ax.set_aspect("equal", adjustable="datalim")
    return ax
def plot_splitting(res, ax=None, **kw):
    """Splitting.plot: |measure| against eps (log-log) in the reference precision, the power-law fit and, at
    a = 2b, the derived leading term b C_psi eps^2."""
    from .plots import axes

    if res.kind == "melnikov":  # another model's splitting: its measurement against the Mel'nikov coefficient
        from .models import plot_model_splitting

        return plot_model_splitting(res.scan.to_dict(), ax=ax, **kw)
    ax = axes(ax)
    e = np.asarray(res.eps, float)
    ax.loglog(e, np.abs(res.measure), "ko", ms=4, label=("|psi_u|" if res.kind == "equilibrium" else "|s1|")
              + f" ({res.precisions[-1]})", **kw)
    grid = np.geomspace(e.min(), e.max(), 50)
    if res.fit is not None:
        ax.loglog(grid, abs(res.fit["C"]) * grid ** res.fit["p"], "k:", lw=1, label=f"fit $\\varepsilon^{{{res.fit['p']:.3f}}}$")
    if res.leading is not None:
        ax.loglog(grid, abs(res.leading["derived_psi_over_eps2"]) * grid**2, "C3-", lw=1,
                  label=f"derived $b\\,C_\\psi\\,\\varepsilon^2$ ({res.leading['digits']:.1f} digits)")
    ax.set_xlabel(r"$\varepsilon$")
    ax.set_ylabel("splitting")
    ax.set_title(f"m={res.m:g}, $\\gamma$={res.gamma:g}, $\\delta$={res.delta:g}, a={res.a:g}, b={res.b:g} "
                 f"({res.kind})", fontsize=8)
    ax.legend(fontsize=7)
    return ax


def plot_melnikov_function(res, ax=None, **kw):
    """MelnikovFunction.plot: M(phi0) (dots) and its trigonometric fit (line) against the phase phi0."""
    from .plots import axes

    ax = axes(ax)
    order = np.argsort(res.phi)
    ax.plot(res.phi[order], res.M[order], "ko", ms=3, **kw)
    grid = np.linspace(0, 2 * np.pi, 400)
    c = res.coefficients
    fit = c[0] + sum(c[2 * h - 1] * np.cos(h * grid) + c[2 * h] * np.sin(h * grid) for h in range(1, (c.size - 1) // 2 + 1))
    ax.plot(grid, fit, "C3-", lw=1)
    ax.axhline(0.0, color="0.7", lw=0.8)
    ax.set_xlabel(r"$\phi_0$")
    ax.set_ylabel(f"M (per unit {res.parameter})")
    ax.set_title(res.message[:110], fontsize=7)
    return ax
