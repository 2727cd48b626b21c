"""`magrod explore`: the interactive Poincare-section explorer in the browser (Panel + Bokeh), on 127.0.0.1 by
default.  Click on the section to launch an orbit; Ctrl-C stops the server and every computation.  Bad input
(an unknown panel, a port outside 1..65535 or in use, a non-loopback --host without --allow-remote) exits 2
before anything is bound.  --model NAME|FILE.py opens any other rod model: the engine's section of several orbits
in the model's body frame (an unknown model is refused, naming it)."""
from __future__ import annotations

from .options import add_model, add_out, add_panel, integer, system_from


def add_arguments(p):
    add_panel(p, help="paper panel whose rod and level to start with (default 4a)")
    add_model(p, help="the rod model: a registered name (`magrod models`) or a model file; another model than the "
                      "paper's rod opens the engine's section of several orbits (default: the paper's rod)")
    p.add_argument("--host", default="127.0.0.1", help="address to bind (loopback unless --allow-remote)")
    p.add_argument("--port", default="5006", help="TCP port, 1..65535")
    p.add_argument("--no-browser", action="store_true", help="do not open a browser tab")
    p.add_argument("--allow-remote", action="store_true",
                   help="allow a non-loopback --host (anyone who can reach it can run computations)")
    p.add_argument("--iterates", default="1000", help="iterates per orbit (changeable on the page)")
    add_out(p, help="directory the page's 'Export' button writes into")


def run(args) -> dict:
    from .options import out_dir

    system, pan = system_from(args, default_panel="4a")  # ParameterError("panel"/"model") before anything starts
    iterates = integer("iterates", args.iterates)
    out = out_dir("out", args.out) if args.out is not None else None
    from ..explorer.server import ExplorerServer

    srv = ExplorerServer((system, pan.key if pan is not None else None), host=args.host, port=args.port,
                         show=not args.no_browser,
                         allow_remote=args.allow_remote, iterates=iterates, out_dir=out,
                         log=(lambda text: None) if args.quiet else None)
    srv.warm()
    return srv.serve_forever()


def format_text(r: dict) -> str:
    lat = r.get("first_points_s") or []
    extra = f"; click to first points: median {sorted(lat)[len(lat) // 2]:.3f} s over {len(lat)} click(s)" if lat \
        else ""
    return f"served {r['url']} for {r['served_s']:.1f} s{extra}"
