"""The interactive section explorer: `magrod explore` on the command line, `magrod.explore` in Python.

app.py     the page (Panel widgets, Bokeh section plot, orbit list, rod view); one Explorer per browser session
worker.py  the background computations: section iterates streamed as they come, cancellable; chaos indicator
model.py   what is drawn, computed without a page: energy-level boundary, colours, input parsing, the rod
export.py  PNG + .npz/.json (the schema of `magrod poincare --out`)
server.py  address checks (loopback by default), the server, /status, shutdown on Ctrl-C
"""
from __future__ import annotations


from ..core.deprecation import renamed_keywords


@renamed_keywords(panel="system")
def explore(system="4a", *, serve=False, host="127.0.0.1", port=5006, show=True, allow_remote=False,
            iterates=1000, out_dir=None):
    """Interactive Poincare-section explorer: click on the section sin(psi) = 0 to launch an orbit.

    Parameters
    ----------
    system : System, panel key, RodParams, model name or model file
        What the page explores (magrod.core.system.as_system).  The paper's rod: a paper panel ("4a" .. "5d",
        default "4a") whose rod, energy level and start the page opens with (a System or RodParams of the paper's
        rod opens on Fig 4(a)'s level and start with its parameters).  Any other model ("anisotropic", a model file
        "./my_rod.py"): the engine's section of several orbits in the model's body frame, drawn in two state
        coordinates; launching an orbit by a click needs the paper's reduced Euler chart, and the page says so by
        name.  ``panel=`` is the deprecated spelling (one release).
    serve : bool
        False (default): return the page as an object (shown inline in Jupyter; `.show()` opens it in a browser
        tab from a script).  True: run a server at host:port until Ctrl-C (what `magrod explore` does).
    host, port : str, int
        Address of the server (serve=True); loopback (127.0.0.1) by default.
    show : bool
        Open a browser tab when serving.
    allow_remote : bool
        Allow a non-loopback host.  Anyone who can reach the port can then run computations on this machine.
    iterates : int
        Section iterates per orbit (changeable on the page).
    out_dir : path, optional
        Directory the page's "Export" button writes into (the download button works without it).

    Returns
    -------
    Explorer, ModelExplorer or dict
        The page object (serve=False; a ModelExplorer for a model other than the paper's rod: `result`, `wait()`,
        `close()`, `limited` says what it cannot do): `launch(theta0, ptheta0)`, `orbits`, `delete`, `clear`, `undo`,
        `set_input(name, value)`, `export(dir)`, `wait()`, `close()`; or, after serving, a summary dict.

    Raises
    ------
    ParameterError
        Naming `panel` (unknown panel), `model` (unknown model or a model file that does not load), `port` (outside 1..65535 or in use), `host` (not loopback without
        allow_remote), `iterates`.

    Examples
    --------
    >>> import magrod as mr
    >>> app = mr.explore("4a")             # the page object; no server is started
    >>> orbit = app.launch(0.1, 0.5)       # what a click at (theta, pbar_theta) = (0.1, 0.5) does
    >>> app.wait(timeout=120)
    True
    >>> orbit.result.n_points, bool(orbit.result.max_abs_dH < 1e-12), orbit.indicator.chaotic
    (1000, True, True)
    >>> app.launch(1.5, 1.4) is None       # outside the energy-level boundary: a message, no orbit
    True
    >>> app.close()
    >>> page = mr.explore("anisotropic", iterates=20)   # another model: the engine's section, drawn
    >>> page.wait(timeout=120), page.result.success
    (True, True)
    >>> "has none" in page.limited
    True
    >>> page.close()

    Notes
    -----
    A click solves Hbar(theta, 0, pbar_theta, pbar_psi) = h for pbar_psi (magrod.chaos.section.solve_p_psi; the
    smallest root, the paper's rule) and integrates the body-frame section loop of `poincare_section` in a
    background thread, streaming the points to the page every ~40 ms; the points equal those of
    `poincare_section` for the same start to the last bit.  The orbit is then coloured by its growth exponent
    (`lyapunov`, T = 3000) on the chaos map's scale (threshold 3).  Cost: ~0.2 ms per iterate on an idle core,
    first points ~10 ms after a click on a warm JIT cache; two worker threads per page.  Closing the page or
    Ctrl-C cancels every computation (each checks after every crossing).
    """
    from ..core.limits import integer

    what = page_system(system)
    iterates = integer("iterates", iterates)
    if serve:
        from .server import ExplorerServer

        srv = ExplorerServer(what, host=host, port=port, show=show, allow_remote=allow_remote, iterates=iterates,
                             out_dir=out_dir)
        srv.warm()
        return srv.serve_forever()
    import panel as pn

    pn.extension("plotly", notifications=False)
    return open_page(what, iterates=iterates, out_dir=out_dir)


def page_system(system):
    """(System, panel key or None): what a page opens with, resolved once (as_system).  A panel key names the
    paper panel; a paper System without one opens on the panel with its parameters, or Fig 4(a)'s level and start."""
    from ..core.printed import PANELS, panel as paper_panel
    from ..core.system import as_system

    if isinstance(system, str) and system.lower() in PANELS:
        return as_system(paper_panel(system))[0], paper_panel(system).key  # ParameterError("panel") if unknown
    resolved, pan = as_system(system)
    if pan is None and resolved.is_paper:
        pan = next((paper_panel(k) for k in PANELS if paper_panel(k).params == resolved.rod), None)
    return resolved, (pan.key if pan is not None else None)


def open_page(what, *, iterates, out_dir=None, registry=None):
    """The page of one session for (System, panel key or None) from `page_system`."""
    system, key = what
    if not system.is_paper:
        from .model_page import ModelExplorer

        return ModelExplorer(system, iterates=iterates, out_dir=out_dir, registry=registry)
    from .app import Explorer

    page = Explorer(key or "4a", iterates=iterates, out_dir=out_dir, registry=registry)
    if key is None:  # a paper rod that is no panel's: Fig 4(a)'s level and start, the rod's parameters
        for name, value in system.params.items():
            page.set_input(name, repr(value))
    return page


__all__ = ["explore"]
