"""Figure of sec. 7, the Mel'nikov function: fig:Mel_ext (Figure 2)."""
from __future__ import annotations

import time

import numpy as np

from ..core.io import atomic_savez, atomic_write_json, ensure_writable_dir, versions
from ..separatrix import (INTEGRANDS, melnikov_amplitude as amplitude, melnikov_amplitude_zero as amplitude_zero,
                          melnikov_function, primitive_check)
from ..paper import FIG2_GAMMAS, FIG2_M, FIG2_ZERO_BRACKET
from ..core.progress import bar
from .common import atomic_savefig, pyplot


def figure_2(out_dir, *, quick=False, progress=False) -> list[str]:
    """fig:Mel_ext at m = 1.7, gamma in {1, 1.2, 1.4, 1.6, 1.8, 2}: M(psi0)/sqrt(a - 2b) = A sin(psi0) for the
    printed integrand (left, y-range [-2, 2] as in the paper) and the derived one (middle, shown with its
    error band), and A(gamma) on gamma in [0, 3] for both (right; the paper's claimed zero interval shaded).
    Writes fig2.png, fig2.npz, fig2.json; returns the paths.  quick: coarser gamma scan for the right panel.
    Cost ~3 s (real128 references for the six paper values)."""
    plt = pyplot()
    t_start = time.perf_counter()
    out = ensure_writable_dir(out_dir)
    m = FIG2_M
    scan = np.linspace(0.0, 3.0, 31 if quick else 121)
    it = list(FIG2_GAMMAS)
    with bar(len(it) + len(scan) + 2, "fig2", progress, unit="amp") as update:
        amps = {k: [] for k in INTEGRANDS}
        for g in it:
            for k in INTEGRANDS:
                amps[k].append(amplitude(m, g, k))
            update()
        scan_a = {k: [] for k in INTEGRANDS}
        for g in scan:
            for k in INTEGRANDS:
                scan_a[k].append(amplitude(m, g, k, reference=False).A)
            update()
        zeros = {k: amplitude_zero(m, k, FIG2_ZERO_BRACKET) for k in INTEGRANDS}
        update(2)
    pc = primitive_check(m, 1.0)

    psi0 = np.linspace(0.0, 2.0 * np.pi, 361)
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8), dpi=150)
    ticks = ([0, np.pi / 2, np.pi, 3 * np.pi / 2, 2 * np.pi], ["0", r"$\pi/2$", r"$\pi$", r"$3\pi/2$", r"$2\pi$"])
    for ax, k in zip(axes[:2], ("printed", "derived")):
        for g, a in zip(it, amps[k]):
            y = melnikov_function(psi0, a)
            ax.plot(psi0, y, lw=1.2, label=f"$\\gamma$={g:g}: A={a.A:+.3g} $\\pm$ {a.error:.0e}")
            if k == "derived":
                ax.fill_between(psi0, y - a.error * np.abs(np.sin(psi0)), y + a.error * np.abs(np.sin(psi0)), alpha=0.15)
        ax.axhline(0.0, color="k", lw=0.5)
        ax.set_xticks(*ticks)
        ax.set_xlabel(r"$\psi_0$")
        ax.set_ylabel(r"$\mathcal{M}(\psi_0)/\sqrt{a-2b}$")
        ax.legend(fontsize=7, loc="upper right" if k == "printed" else "lower right")
    axes[0].set_ylim(-2, 2)
    axes[0].set_title("printed integrand (eq:Mel_ext): no zero of A for $\\gamma$ in [1.8, 2]", fontsize=9)
    axes[1].set_title("derived integrand (eq:melnikov_bracket): A = 0 to quadrature accuracy\n"
                      f"(real128: |A| < {max(abs(a.A_reference) for a in amps['derived']):.0e}; "
                      f"exact: Int F dt = [2 Phi], max|quad - 2 Phi| = {pc['max_abs_diff']:.0e})", fontsize=9)
    axes[1].ticklabel_format(axis="y", style="sci", scilimits=(0, 0))
    ax = axes[2]
    ax.plot(scan, scan_a["printed"], "C0-", label="printed")
    ax.plot(scan, scan_a["derived"], "C1-", label="derived")
    ax.axvspan(*FIG2_ZERO_BRACKET, color="0.85", label="paper: zero between 1.8 and 2")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel(r"$\gamma$")
    ax.set_ylabel("A (amplitude)")
    ax.set_title(f"A($\\gamma$) at m = {m:g}", fontsize=9)
    ax.legend(fontsize=8)
    fig.suptitle(f"Fig. 2 (fig:Mel_ext): normalised Mel'nikov function M($\\psi_0$)/$\\sqrt{{a-2b}}$ = A sin $\\psi_0$, "
                 f"m = {m:g}", fontsize=10)
    fig.tight_layout()
    paths = [str(atomic_savefig(fig, out / "fig2.png"))]
    plt.close(fig)
    arrays = {"psi0": psi0, "gammas": np.array(it), "scan_gamma": scan,
              **{f"A_{k}": np.array([a.A for a in amps[k]]) for k in INTEGRANDS},
              **{f"A_error_{k}": np.array([a.error for a in amps[k]]) for k in INTEGRANDS},
              **{f"scan_A_{k}": np.array(scan_a[k]) for k in INTEGRANDS},
              "primitive_t": pc["t"], "primitive_running_A": pc["running_A"], "primitive_two_phi": pc["two_phi"]}
    paths.append(str(atomic_savez(out / "fig2.npz", **arrays)))
    meta = {"figure": "fig:Mel_ext", "m": m, "quick": quick,
            "convention": amps["printed"][0].convention,
            "amplitudes": {k: [a.to_dict() for a in amps[k]] for k in INTEGRANDS},
            "zero_search_1.8_2.0": zeros,
            "scan_sign_changes": {k: int(np.sum(np.diff(np.sign(scan_a[k])) != 0)) for k in INTEGRANDS},
            # derived: signs are rounding noise (|A| <= error), so only the printed sign changes are meaningful
            "sign_change_in_scan": {k: bool(np.any(np.diff(np.sign(scan_a[k])) != 0)) for k in INTEGRANDS},
            "scan": {"gamma": scan, **{f"A_{k}": scan_a[k] for k in INTEGRANDS}},
            "max_abs_A_derived": max(abs(a.A) for a in amps["derived"]),
            "max_error_A_derived": max(a.error for a in amps["derived"]),
            "max_abs_A_derived_real128": max(abs(a.A_reference) for a in amps["derived"]),
            "primitive_check_gamma_1": {"max_abs_diff": pc["max_abs_diff"], "max_abs_2phi": pc["max_abs_2phi"]},
            "versions": versions(), "wall_time_s": time.perf_counter() - t_start}
    paths.append(str(atomic_write_json(out / "fig2.json", meta)))
    return paths
