"""Serving the explorer: address checks (loopback unless allowed), the Panel/Bokeh server, /status, shutdown.

Bad input is refused before anything is bound (ParameterError naming the option: the CLI's exit 2).  The server
runs in the calling thread; Ctrl-C (KeyboardInterrupt) or `stop()` cancels every session's computations, stops
the server and joins the worker threads (each checks its cancel event after every section crossing, ~0.2 ms).
"""
from __future__ import annotations

import errno
import ipaddress
import signal
import socket
import sys
import threading
import time

from ..core.errors import ParameterError

DEFAULT_HOST, DEFAULT_PORT = "127.0.0.1", 5006
SWITCH_INTERVAL = 2e-4  # s: the GIL hand-over interval while serving (see serve_forever)


def is_loopback(host: str) -> bool:
    """True if every address `host` resolves to is a loopback address (127.0.0.0/8, ::1)."""
    try:
        infos = socket.getaddrinfo(host, None)
    except (socket.gaierror, UnicodeError):
        raise ParameterError("host", f"cannot resolve {host!r}") from None
    addrs = {i[4][0] for i in infos}
    return bool(addrs) and all(ipaddress.ip_address(a.split("%")[0]).is_loopback for a in addrs)


def check_address(host, port, allow_remote: bool = False) -> tuple[str, int]:
    """(host, port) validated: port an integer in 1..65535 that is free on host; host loopback unless
    allow_remote.  ParameterError("port" | "host") otherwise; nothing stays bound."""
    try:
        p = int(str(port).strip())
    except ValueError:
        raise ParameterError("port", f"must be an integer in 1..65535, got {str(port)[:40]!r}") from None
    if not 1 <= p <= 65535:
        raise ParameterError("port", f"must be in 1..65535, got {p}")
    host = str(host).strip()
    if not host:
        raise ParameterError("host", "must not be empty")
    if not allow_remote and not is_loopback(host):
        raise ParameterError("host", f"{host!r} is not a loopback address: the explorer serves 127.0.0.1 unless "
                                     f"--allow-remote is given (anyone who can reach the port can use it)")
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    s = socket.socket(family, socket.SOCK_STREAM)
    try:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # as tornado binds: TIME_WAIT is not "in use"
        s.bind((host, p))
    except OSError as exc:
        if exc.errno == errno.EADDRINUSE:
            raise ParameterError("port", f"{host}:{p} is already in use; choose another --port") from None
        if exc.errno in (errno.EACCES, errno.EPERM):
            raise ParameterError("port", f"{host}:{p}: permission denied (ports below 1024 need privileges)") from None
        raise ParameterError("host", f"cannot bind {host}:{p}: {exc.strerror}") from None
    finally:
        s.close()
    return host, p


class ExplorerServer:
    """A running explorer server (Panel on Bokeh/tornado) with its registry of sessions."""

    def __init__(self, system="4a", *, host=DEFAULT_HOST, port=DEFAULT_PORT, show=True, allow_remote=False,
                 iterates=1000, out_dir=None, log=None):
        from . import page_system

        # a panel key, a System (any model) or (System, panel key): ParameterError("panel"/"model") first, nothing
        # started yet
        self.what = system if isinstance(system, tuple) else page_system(system)
        self.system, self.panel = self.what
        self.host, self.port = check_address(host, port, allow_remote)
        self.show, self.iterates, self.out_dir = bool(show), int(iterates), out_dir
        self.log = log or (lambda text: print(f"magrod explore: {text}", file=sys.stderr, flush=True))
        self._server = None

    @property
    def url(self) -> str:
        h = f"[{self.host}]" if ":" in self.host else self.host
        return f"http://{h}:{self.port}/"

    def _build(self):
        import panel as pn
        from tornado.web import RequestHandler

        from . import open_page
        from .app import Registry, status_json

        pn.extension("plotly", notifications=False)
        self.registry = registry = Registry()

        class Status(RequestHandler):
            def get(self):
                self.set_header("Content-Type", "application/json")
                self.write(status_json(registry))

        def factory():
            return open_page(self.what, iterates=self.iterates, out_dir=self.out_dir, registry=registry)

        origins = [f"{self.host}:{self.port}", f"localhost:{self.port}", f"127.0.0.1:{self.port}"]
        # panel's get_server installs a SIGINT handler that only stops the event loop (the process then exits 0
        # after a clean-looking shutdown): keep the caller's handler instead (the CLI's raises KeyboardInterrupt,
        # which stops the computations and exits 130)
        in_main = threading.current_thread() is threading.main_thread()
        saved = signal.getsignal(signal.SIGINT) if in_main else None
        try:
            self._server = pn.serve({"/": factory}, address=self.host, port=self.port, show=False, start=False,
                                    title="magrod explore", websocket_origin=origins, threaded=False,
                                    verbose=False, extra_patterns=[(r"/status", Status)],
                                    check_unused_sessions=1000, unused_session_lifetime=2000)
        except OSError as exc:  # lost the race for the port after check_address
            raise ParameterError("port", f"{self.host}:{self.port}: {exc.strerror or exc}") from None
        finally:
            if in_main and saved is not None:
                signal.signal(signal.SIGINT, saved)
        return self._server

    def warm(self) -> None:
        """Compile or load the integrators and compiled functions a click needs (so the first click is fast)."""
        from ..core.printed import panel as paper_panel
        from .worker import solve_start, stream_section

        if not self.system.is_paper:
            from .model_page import model_section

            model_section(self.system, 2)
            return
        P = paper_panel(self.panel or "4a")
        st = solve_start(P.params, P.h, P.theta0, P.ptheta0, P.psi0)
        stream_section(st, 2)
        from .model import energy_boundary

        energy_boundary(P.params, P.h)

    def serve_forever(self) -> dict:
        """Serve until Ctrl-C or stop(); returns what happened (the CLI's result dict)."""
        t0 = time.perf_counter()
        # The section loop takes the GIL back after every crossing (~0.2 ms of heyoka without it); while the event
        # loop runs Python (serialising a stream to the page) a thread waits up to the switch interval (5 ms by
        # default) for it, which made 1000 iterates take 5 s instead of 0.5 s.  The server owns its process
        # while it runs; the interval is restored on return.
        switch = sys.getswitchinterval()
        sys.setswitchinterval(SWITCH_INTERVAL)
        server = self._build()
        server.start()
        self.log(f"serving {self.url} ({self._what_text()}); Ctrl-C stops")
        if self.show:
            server.io_loop.add_callback(server.show, "/")
        try:
            server.io_loop.start()
        finally:
            sys.setswitchinterval(switch)
            t = time.perf_counter()
            self.stop()
            self.log(f"stopped: every computation cancelled, worker threads joined in {time.perf_counter() - t:.3f} s")
        return {"ok": True, "url": self.url, "panel": self.panel, "model": self.system.model, "served_s": time.perf_counter() - t0,
                "first_points_s": list(self.registry.latencies)}

    def _what_text(self) -> str:
        if not self.system.is_paper:
            return f"model {self.system.model}"
        return f"panel {self.panel}" if self.panel else repr(self.system)

    def stop(self) -> None:
        """Cancel every computation, close every session, stop the server."""
        reg = getattr(self, "registry", None)
        if reg is not None:
            reg.close_all()
        if self._server is not None:
            try:
                self._server.stop()
                self._server.io_loop.stop()
            except Exception:
                pass
