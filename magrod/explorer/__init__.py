"""The interactive section explorer (issue 19): `magrod explore` on the command line, `magrod.explore` in Python.

app.py     the page (Panel widgets, Bokeh section plot, orbit list, rod view); one Explorer per browser session
worker.py  the background computations: section iterates streamed as they come, cancellable; chaos indicator
model.py   what is drawn, computed without a page: energy-level boundary, colours, input parsing, the rod
export.py  PNG + .npz/.json (the schema of `magrod poincare --out`)
server.py  address checks (loopback by default), the server, /status, shutdown on Ctrl-C
"""
from __future__ import annotations


def explore(panel="4a", *, serve=False, host="127.0.0.1", port=5006, show=True, allow_remote=False,
            iterates=1000, out_dir=None):
    """Interactive Poincare-section explorer: click on the section sin(psi) = 0 to launch an orbit.

    Parameters
    ----------
    panel : str
        Paper panel ("4a" .. "5d") whose rod, energy level and start the page opens with.
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
    Explorer or dict
        The page object (serve=False): `launch(theta0, ptheta0)`, `orbits`, `delete`, `clear`, `undo`,
        `set_input(name, value)`, `export(dir)`, `wait()`, `close()`; or, after serving, a summary dict.

    Raises
    ------
    ParameterError
        Naming `panel` (unknown), `port` (outside 1..65535 or in use), `host` (not loopback without
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
    from ..core.printed import panel as paper_panel
    from ..core.limits import integer

    key = paper_panel(panel).key
    iterates = integer("iterates", iterates)
    if serve:
        from .server import ExplorerServer

        srv = ExplorerServer(key, host=host, port=port, show=show, allow_remote=allow_remote, iterates=iterates,
                             out_dir=out_dir)
        srv.warm()
        return srv.serve_forever()
    import panel as pn

    from .app import Explorer

    pn.extension("plotly", notifications=False)
    return Explorer(key, iterates=iterates, out_dir=out_dir)


__all__ = ["explore"]
