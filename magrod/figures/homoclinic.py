"""Figure of sec. 6, the homoclinic orbit of the extensible rod at lambdabar = 0: fig:angles (Figure 3)."""
from __future__ import annotations

import time

import numpy as np

from ..generated import scalars
from ..orbits import homoclinic_closed_form as homoclinic, phase_portrait_energy, verify_homoclinic as verify
from ..core.io import atomic_savez, atomic_write_json, ensure_writable_dir, versions
from ..paper import FIG3
from ..core.progress import bar
from .common import atomic_savefig, pyplot, rect


def _portrait(ax, m, gamma, xr, yr, title, paper_box=None, n=601):
    th = np.linspace(xr[0], xr[1], n)
    pt = np.linspace(yr[0], yr[1], n)
    TH, PT = np.meshgrid(th, pt)
    E = phase_portrait_energy(TH, PT, m, gamma)
    h = scalars.homoclinic_energy(m, gamma)
    levels = np.quantile(E, np.linspace(0.0, 0.6, 25))
    ax.contour(TH, PT, E, levels=np.unique(levels), colors="0.55", linewidths=0.6)
    ax.contour(TH, PT, E, levels=[h], colors="C3", linewidths=1.6)
    if paper_box is not None:
        rect(ax, paper_box, label="paper's axes")
    # every contour says what it is (an unexplained line is a question for the reader)
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color="0.55", lw=0.6, label=r"level sets of $\bar H$ (the phase portrait)"),
               Line2D([], [], color="C3", lw=1.6, label=r"$\bar H = h$: the homoclinic level (separatrix)")]
    if paper_box is not None:
        handles.append(Line2D([], [], color="k", ls=":", lw=0.8, label="the paper's axis ranges"))
    ax.legend(handles=handles, fontsize=6, loc="upper right")
    ax.set_xlabel(r"$\theta$")
    ax.set_ylabel(r"$\bar p_\theta$")
    ax.set_title(title, fontsize=9)
    return E


def figure_3_data(n_t=1201) -> dict:
    """Arrays and checks of fig:angles: orbits at m = 1.7 for gamma = 1 and gamma = 0 (t in [-T, T] with
    theta(T) = 1e-3 theta_max), their verification against the multiprecision integration, and the values at the
    paper's window edge t = +-1."""
    out = {}
    for key, g in (("ext", FIG3["gamma"]), ("kir", 0.0)):
        o = homoclinic(FIG3["m"], g)
        T = o.time_at_theta(1e-3 * o.theta_max)
        t = np.linspace(-T, T, n_t)
        ev = o.evaluate(t)
        v = verify(o, theta_stop=1e-8, n=101)
        v.pop("arrays")
        at1 = o.evaluate(np.array([1.0]))
        out[key] = {"orbit": o, "t": t, "theta": ev["theta"], "ptheta": ev["ptheta"], "psidot": ev["psidot"],
                    "verify": v, "at_t1": {k: float(at1[k][0]) for k in ("theta", "ptheta", "psidot")},
                    "max_abs_ptheta": float(np.max(np.abs(ev["ptheta"]))), "psidot_max": float(np.max(ev["psidot"])),
                    "t_half_width_theta_1e-2": o.time_at_theta(1e-2)}
    return out


def figure_3(out_dir, *, quick=False, progress=False) -> list[str]:
    """fig:angles: (a) phase portrait gamma = 1, m = 1.7; (b) m = 2.2 (printed as '> m_c', but m_c =
    2 sqrt(2) at gamma = 1); (b*) m = 3 > m_c for comparison; (c, d, e) theta, pbar_theta, psi' against t for
    gamma = 1 (solid) and gamma = 0 (dashed) at m = 1.7, on the orbit's full width with the paper's window
    t in [-1, 1] (and y-range) marked.  Writes fig3.png, fig3.npz, fig3.json; returns the paths.
    quick: coarser contour grids.  Cost ~5 s (two multiprecision verifications)."""
    plt = pyplot()
    t_start = time.perf_counter()
    out = ensure_writable_dir(out_dir)
    n = 201 if quick else 601
    with bar(5, "figure 3", progress, unit="step") as update:  # two verified orbits, then three portraits
        d = figure_3_data(401 if quick else 1201)
        update(2)
        fig, axes, ob = _figure_3_portraits(plt, d, n, update)
    return _figure_3_rest(plt, fig, axes, ob, d, out, quick, t_start)


def _figure_3_portraits(plt, d, n, update):
    ax_p = FIG3["paper_axes"]
    fig, axes = plt.subplots(2, 3, figsize=(14, 8), dpi=150)
    m, g = FIG3["m"], FIG3["gamma"]
    mc = scalars.m_critical(g)
    th_max = d["ext"]["orbit"].theta_max
    _portrait(axes[0, 0], m, g, (-1.8, 1.8), (-0.6, 0.6),
              f"(a) $\\gamma$={g:g}, m={m:g} < $m_c$={mc:.3f}; homoclinic level h (red),\n"
              f"$\\theta_{{max}}$={th_max:.3f} exceeds the paper's $|\\theta|\\leq 1.5$", ax_p["a"], n)
    update(1)
    ob = homoclinic(FIG3["m_b"], g)
    _portrait(axes[0, 1], FIG3["m_b"], g, (-1.5, 1.5), (-0.8, 0.8),
              f"(b) $\\gamma$={g:g}, m={FIG3['m_b']:g}: printed as '> $m_c$', but $m_c$={mc:.3f};\n"
              f"theta = 0 is still a saddle (homoclinic level red, $\\theta_{{max}}$={ob.theta_max:.3f})",
              ax_p["b"], n)
    update(1)
    _portrait(axes[0, 2], FIG3["m_super"], g, (-1.5, 1.5), (-0.8, 0.8),
              f"(b*) not in the paper: $\\gamma$={g:g}, m={FIG3['m_super']:g} > $m_c$ (theta = 0 a centre;\n"
              "no homoclinic orbit)", None, n)
    update(1)
    return fig, axes, ob


def _figure_3_rest(plt, fig, axes, ob, d, out, quick, t_start):
    ax_p = FIG3["paper_axes"]
    m, g = FIG3["m"], FIG3["gamma"]
    for ax, key, lab in ((axes[1, 0], "theta", r"$\theta$"), (axes[1, 1], "ptheta", r"$\bar p_\theta$"),
                         (axes[1, 2], "psidot", r"$\dot\psi = 1/(1+\cos\theta)$")):
        for which, style, name in (("ext", "-", f"extensible $\\gamma$={g:g}"), ("kir", "--", "inextensible $\\gamma$=0")):
            ax.plot(d[which]["t"], d[which][key], style, color="C0" if which == "ext" else "C1", lw=1.2, label=name)
        pk = {"theta": "c", "ptheta": "d", "psidot": "e"}[key]
        rect(ax, ax_p[pk], label="paper's axes")
        ax.set_xlabel("t (scaled arclength, t = s, eq:nondim_1)")
        ax.set_ylabel(lab)
        ax.set_title(f"({pk}) m={m:g}", fontsize=9)
        ax.legend(fontsize=7, loc="best")
    ver = {k: d[k]["verify"] for k in ("ext", "kir")}
    fig.suptitle("Fig. 3 (fig:angles): closed-form homoclinic orbits; vs 256-bit integration from the turning point: "
                 f"max|d$\\theta$| = {ver['ext']['max_dev_theta']:.1e} ($\\gamma$=1), "
                 f"{ver['kir']['max_dev_theta']:.1e} ($\\gamma$=0) until $\\theta$ = 1e-8", fontsize=10)
    fig.tight_layout()
    paths = [str(atomic_savefig(fig, out / "fig3.png"))]
    plt.close(fig)
    arrays = {f"{k}_{v}": d[k][v] for k in ("ext", "kir") for v in ("t", "theta", "ptheta", "psidot")}
    paths.append(str(atomic_savez(out / "fig3.npz", **arrays)))
    meta = {"figure": "fig:angles", "quick": quick, "params": FIG3,
            "orbits": {k: {**d[k]["orbit"].summary(), "verify": d[k]["verify"], "at_t=1": d[k]["at_t1"],
                           "max_abs_ptheta": d[k]["max_abs_ptheta"], "psidot_max": d[k]["psidot_max"],
                           "t_where_theta=1e-2": d[k]["t_half_width_theta_1e-2"]} for k in ("ext", "kir")},
            "panel_b_orbit": ob.summary(),
            "versions": versions(), "wall_time_s": time.perf_counter() - t_start}
    paths.append(str(atomic_write_json(out / "fig3.json", meta)))
    return paths
