"""`.plot()` of the orbit results (magrod.orbits): saddles (their spectrum), the closed-form homoclinic orbit,
multipulse orbits and searches, continuation branches and rod shapes.  Each function takes the result and an
Axes (None: a new figure, plots.axes) and returns the Axes; none switches matplotlib's backend or writes a file."""
from __future__ import annotations

import numpy as np

from .plots import axes


def plot_saddle(s, ax=None, **kw):
    """The saddle's spectrum: eigenvalues of the straight rod's Jacobian in the complex plane, or the Floquet
    multipliers of the periodic saddle with the unit circle (log-polar would hide the pair at 1)."""
    ax = axes(ax)
    if s.kind == "equilibrium":
        _spectrum(ax, s.eigenvalues, s.unstable_eigenvalue, **kw)
        ax.set_title(f"straight rod (mu = 2 lam), H = {s.H:.6g}", fontsize=8)
    else:
        z = np.asarray(s.multipliers)
        phi = np.linspace(0, 2 * np.pi, 200)
        ax.plot(np.cos(phi), np.sin(phi), color="0.7", lw=0.8)
        ax.plot(z.real, z.imag, "o", mfc="none", color="k", **kw)
        u = s.unstable_multiplier
        ax.plot([u.real], [u.imag], "o", color="tab:red", label=f"|Lambda_u| = {abs(u):.4g}")
        ax.set_xscale("symlog", linthresh=1.0)
        ax.set_yscale("symlog", linthresh=1.0)
        ax.set_xlabel("Re multiplier")
        ax.set_ylabel("Im multiplier")
        ax.set_title(f"periodic saddle: period T = {s.T:.6g}, H = {s.H:.6g}", fontsize=8)
    ax.legend(fontsize=7)
    return ax


def plot_equilibrium(e, ax=None, **kw):
    """An equilibrium of any model: its spectrum on the symplectic leaf in the complex plane, the leading
    unstable eigenvalue marked."""
    ax = axes(ax)
    _spectrum(ax, e.eigenvalues, e.unstable_eigenvalue, **kw)
    ax.set_title(f"{e.kind} of {e.system!r}"[:120], fontsize=8)
    ax.legend(fontsize=7)
    return ax


def _spectrum(ax, eigenvalues, u, **kw):
    """Eigenvalues in the complex plane, the unstable one marked."""
    z = np.asarray(eigenvalues)
    ax.axvline(0.0, color="0.7", lw=0.8)
    ax.plot(z.real, z.imag, "o", mfc="none", color="k", **kw)
    ax.plot([u.real], [u.imag], "o", color="tab:red", label=f"unstable {u.real:.4g} + {u.imag:.4g}i")
    ax.set_xlabel("Re eigenvalue")
    ax.set_ylabel("Im eigenvalue")


def plot_symmetric_orbit(orbit, ax=None, n: int = 2001, **kw):
    """Every state component of a symmetric homoclinic orbit of any model against s - T (the symmetric point at 0)."""
    ax = axes(ax, figsize=(6.0, 3.0))
    smp = orbit.sample(n)
    t = smp["t"] - orbit.T
    for j, name in enumerate(orbit.reversor.names):
        ax.plot(t, smp["x"][:, j], lw=1, label=name, **kw)
    ax.set_xlabel("s - T (arclength from the symmetric point)")
    ax.set_title(f"{orbit.pulses}-pulse symmetric orbit, {orbit.reversor!r}"[:120], fontsize=8)
    ax.legend(fontsize=6, ncol=3)
    return ax


def plot_homoclinic(orb, ax=None, t_max=None, **kw):
    """theta(t) and pbar_theta(t) of the closed-form lambda = 0 homoclinic orbit (fig:angles)."""
    ax = axes(ax)
    T = t_max if t_max is not None else orb.time_at_theta(1e-3)
    t = np.linspace(-T, T, 801)
    e = orb.evaluate(t)
    ax.plot(t, e["theta"], "k-", label=r"$\theta$", **kw)
    ax.plot(t, e["ptheta"], "k--", label=r"$\bar p_\theta$")
    ax.set_xlabel("t (arclength)")
    ax.set_title(f"homoclinic orbit, m = {orb.m:g}, gamma = {orb.gamma:g}", fontsize=8)
    ax.legend(fontsize=7)
    return ax


def plot_orbit(orbit, ax=None, n: int = 4001, **kw):
    """theta against the scaled arclength tau = (s - T)/L of one symmetric orbit (Figures 6, 7)."""
    ax = axes(ax, figsize=(6.0, 3.0))
    orb = orbit.sample(n)
    win = np.abs(orb["tau"]) <= 1.0
    label = f"{orbit.pulses}-pulse" + (f", {orbit.free} = {orbit.free_value:.9g}" if orbit.free else
                                       f", angle = {orbit.angle:.6g}")
    ax.plot(orb["tau"][win], orb["theta"][win], lw=1.2, label=label, **kw)
    ax.set_xlim(-1, 1)
    ax.set_ylim(bottom=0)
    ax.set_xlabel(r"$(s - s_{sym})/L$")
    ax.set_ylabel(r"$\theta$")
    ax.legend(fontsize=7)
    return ax


def plot_search(search, ax=None, **kw):
    """Every orbit of a MultipulseSearch, theta against tau (one line per orbit)."""
    ax = axes(ax, figsize=(6.0, 3.0))
    for o in search.orbits:
        plot_orbit(o, ax=ax, **kw)
    p = search.params
    ax.set_title(f"{search.kind} saddle: m={p.m:g}, mu={p.mu:g}, gamma={p.gamma:g}, delta={p.delta:g}, "
                 f"lam={p.lam:g}", fontsize=8)
    return ax


def plot_pulse_search(search, ax=None, **kw):
    """The orbits of one PulseSearch (one number of pulses), theta against tau; its message if none."""
    ax = axes(ax, figsize=(6.0, 3.0))
    for o in search.orbits:
        plot_orbit(o, ax=ax, **kw)
    ax.set_title(f"N = {search.pulses_target}: {search.message}"[:120], fontsize=8)
    return ax


def plot_branch(branch, ax=None, component: int = 0, **kw):
    """One unknown of a continuation branch (default T) against its parameter, folds circled."""
    ax = axes(ax)
    u = branch.u
    names = branch.names or tuple(f"u{i}" for i in range(u.shape[1]))
    ax.plot(u[:, -1], u[:, component], ".-", lw=1, ms=3, color="k", **kw)
    for f in branch.folds:
        if f.get("u") is not None:
            ax.plot(f["u"][-1], f["u"][component], "o", mfc="none", color="tab:red", ms=8)
    ax.set_xlabel(names[-1])
    ax.set_ylabel(names[component])
    ax.set_title(f"{len(branch.folds)} fold(s); {branch.message}", fontsize=8)
    return ax


def plot_rod_shape(rod, ax=None, radius=None, magnify: bool = True, **kw):
    """The rod as a tube along its centreline (z along the field), the tube's surface coloured by arclength.
    magnify: transverse displacements from the end-to-end chord magnified by the 1-2-5 factor of
    figures.rod.magnification (stated in the title), so that a long localised rod shows its pulses."""
    from .rod import magnification

    ax = axes(ax, projection="3d", figsize=(6.0, 5.0))
    r = rod.r
    M, u, perp = magnification(r) if magnify else (1.0, None, None)
    if M != 1.0:
        r = r[0] + np.outer((r - r[0]) @ u, u) + M * perp
    span = float(np.max(r.max(0) - r.min(0)))
    a = radius if radius is not None else 0.01 * span
    d1, d2 = rod.D[:, :, 0], rod.D[:, :, 1]
    phi = np.linspace(0, 2 * np.pi, 13)
    step = max(1, len(r) // 400)
    rr, e1, e2 = r[::step], d1[::step], d2[::step]
    X = rr[:, None, :] + a * (np.cos(phi)[None, :, None] * e1[:, None, :] + np.sin(phi)[None, :, None] * e2[:, None, :])
    import matplotlib.cm as cm

    colours = cm.viridis(np.linspace(0, 1, len(rr)))[:, None, :].repeat(len(phi), axis=1)
    ax.plot_surface(X[..., 0], X[..., 1], X[..., 2], facecolors=colours, linewidth=0, shade=True, **kw)
    c = 0.5 * (r.max(0) + r.min(0))
    h = 0.55 * span
    ax.set_xlim(c[0] - h, c[0] + h)
    ax.set_ylim(c[1] - h, c[1] + h)
    ax.set_zlim(c[2] - h, c[2] + h)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z (field)")
    ax.set_title(f"rod, length {rod.length:.4g}" + (f"; transverse x{M:g}" if M != 1.0 else ""), fontsize=8)
    return ax
