"""Atomic file output: data as .npz plus a JSON sidecar with parameters, tolerances, versions and timings.

Every file is written to a temporary name in the target directory and renamed into place, so an interrupted
run never leaves a half-written file."""
from __future__ import annotations

import io as _io
import json
import os
import platform
import tempfile
from pathlib import Path

import numpy as np

from .errors import ParameterError


def versions() -> dict:
    import heyoka
    import matplotlib
    import scipy

    from . import __version__

    return {"magrod": __version__, "heyoka": heyoka.__version__, "numpy": np.__version__,
            "scipy": scipy.__version__, "matplotlib": matplotlib.__version__,
            "python": platform.python_version()}


def ensure_writable_dir(path) -> Path:
    p = Path(path)
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ParameterError("out", f"cannot create output directory {str(p)!r}: {exc.strerror}") from None
    if not os.access(p, os.W_OK | os.X_OK):
        raise ParameterError("out", f"output directory {str(p)!r} is not writable")
    return p


def atomic_write_bytes(path, data: bytes) -> Path:
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        raise
    return path


def atomic_write_text(path, text: str) -> Path:
    return atomic_write_bytes(path, text.encode("utf-8"))


def atomic_write_json(path, obj) -> Path:
    return atomic_write_text(path, json.dumps(obj, indent=2, sort_keys=True, default=_jsonable) + "\n")


def atomic_savez(path, **arrays) -> Path:
    buf = _io.BytesIO()
    np.savez(buf, **arrays)
    return atomic_write_bytes(path, buf.getvalue())


def atomic_savefig(fig, path, **kw) -> Path:
    path = Path(path)
    buf = _io.BytesIO()
    fmt = path.suffix.lstrip(".") or "png"
    # a fixed creation date keeps PNG/PDF bytes reproducible
    meta = {"Software": None} if fmt == "png" else {"CreationDate": None}
    fig.savefig(buf, format=fmt, metadata=meta, **kw)
    return atomic_write_bytes(path, buf.getvalue())


ORBIT_KEYS = ("x0", "T", "pars", "t", "tau", "x")


def load_orbit_file(path) -> dict:
    """The arrays of an orbit .npz written by `magrod multipulse` (ParameterError naming `from` if the file is
    missing or is not such a file).  Never unpickles: allow_pickle=False."""
    path = Path(path)
    if not path.is_file():
        raise ParameterError("from", f"no such file: {str(path)!r}")
    try:
        with np.load(path, allow_pickle=False) as d:
            return {k: d[k] for k in ORBIT_KEYS}
    except (KeyError, ValueError, OSError) as exc:
        raise ParameterError("from", f"{str(path)!r} is not an orbit file of magrod multipulse ({exc})") from None


def _jsonable(o):
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"not JSON serialisable: {type(o)}")
