"""Atomic file output: data as .npz plus a JSON sidecar with parameters, tolerances, versions and timings.

Every file is written to a temporary name in the target directory (".NAME.PID.XXXXXXXX.tmp", PID = the writing
process) and renamed into place, so an interrupted run never leaves a half-written file; a temporary left by a
killed process is recognised by its name and removed by the next run (remove_stale_temporaries).  Files get the
permissions of the umask (like any file the user creates).
A write that fails because of the machine (disk full, file-size limit, read-only filesystem) raises
EnvironmentFault naming the path.  Directories created by a command are tracked so that a failed run removes
the ones it left empty."""
from __future__ import annotations

import contextlib
import contextvars
import errno
import io as _io
import json
import os
import platform
import re
import tempfile
from pathlib import Path

import numpy as np

from .errors import EnvironmentFault, ParameterError

_created: list | None = None  # directories made by ensure_writable_dir since track_created_dirs()
# the files written by atomic_write_bytes inside record_writes() (a list), so that a failed figure can remove them
_written: contextvars.ContextVar = contextvars.ContextVar("magrod_written", default=None)


@contextlib.contextmanager
def record_writes():
    """Collect the paths of the files written in this context (in this thread) into the list it yields."""
    paths: list = []
    token = _written.set(paths)
    try:
        yield paths
    finally:
        _written.reset(token)


def track_created_dirs() -> None:
    global _created
    _created = []


def remove_empty_created_dirs() -> None:
    """Remove the directories this command created that are still empty (deepest first)."""
    global _created
    for d in reversed(_created or []):
        try:
            d.rmdir()
        except OSError:
            pass
    _created = [] if _created is not None else None


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def versions() -> dict:
    """Versions of magrod and the packages its numbers depend on (from the installed metadata: nothing imported)."""
    from importlib.metadata import PackageNotFoundError, version

    from .. import __version__

    out = {"magrod": __version__}
    for pkg in ("heyoka", "numpy", "scipy", "matplotlib"):
        try:
            out[pkg] = version(pkg)
        except PackageNotFoundError:  # pragma: no cover - every one is a dependency
            out[pkg] = None
    out["python"] = platform.python_version()
    return out


def check_stem(value, name: str = "stem") -> str:
    """A file-name stem: one path component (no '/', no '..'), printable, at most 200 bytes (suffixes follow)."""
    v = str(value)
    if not v or v in (".", "..") or "/" in v or "\\" in v or "\x00" in v or v.startswith("."):
        raise ParameterError(name, f"must be a plain file name (no directories, not hidden), got {v[:60]!r}")
    if not v.isprintable() or len(os.fsencode(v)) > 200:
        raise ParameterError(name, "must be printable and at most 200 bytes")
    return v


def check_out_path(path, name: str = "out") -> Path:
    """Validate an output directory argument without creating anything: non-empty, no NUL, not an existing
    non-directory, and its nearest existing ancestor is a writable directory."""
    if path is None or str(path).strip() == "":
        raise ParameterError(name, "must be a non-empty directory path")
    if "\x00" in str(path):
        raise ParameterError(name, "must not contain a NUL character")
    p = Path(path)
    if len(os.fsencode(str(p))) > 4000 or any(len(os.fsencode(c)) > 255 for c in p.parts):
        raise ParameterError(name, "path too long")
    if p.exists() and not p.is_dir():
        raise ParameterError(name, f"{str(p)!r} exists and is not a directory")
    q = p.absolute()
    while not q.exists():
        q = q.parent
    if not q.is_dir():
        raise ParameterError(name, f"{str(q)!r} is not a directory")
    if not os.access(q, os.W_OK | os.X_OK) or str(q).startswith(("/proc", "/sys")):
        raise ParameterError(name, f"cannot create or write {str(p)!r}: {str(q)!r} is not writable")
    return p


def ensure_writable_dir(path, name: str = "out") -> Path:
    p = check_out_path(path, name)
    missing = []
    q = p.absolute()
    while not q.exists():
        missing.append(q)
        q = q.parent
    try:
        p.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ParameterError(name, f"cannot create output directory {str(p)!r}: {exc.strerror}") from None
    if _created is not None:
        _created.extend(reversed(missing))
    if not os.access(p, os.W_OK | os.X_OK):
        raise ParameterError(name, f"output directory {str(p)!r} is not writable")
    return p


def atomic_write_bytes(path, data: bytes) -> Path:
    path = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name[:200]}.{os.getpid()}.", suffix=".tmp")
    except OSError as exc:
        raise EnvironmentFault("out", f"cannot write in {str(path.parent)!r}: {exc.strerror}") from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600; a result file is as readable as any other
        os.replace(tmp, path)
        rec = _written.get()
        if rec is not None:
            rec.append(path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        if isinstance(exc, OSError):
            raise EnvironmentFault("out", f"cannot write {str(path)!r}: {exc.strerror or exc}") from None
        raise
    return path


_TEMP = re.compile(r"^\.(?P<name>.+)\.(?P<pid>\d+)\.[A-Za-z0-9_]{8}\.tmp$")


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True


def remove_stale_temporaries(directory, pids=()) -> list:
    """Remove the temporaries of atomic_write_bytes in `directory` (not recursive) whose writer is `pids`, this
    process, or no longer alive: what an interrupted or killed run left behind.  A live writer's temporary
    (another magrod command writing there now) is kept.  Returns the removed paths."""
    removed = []
    own = {os.getpid(), *map(int, pids)}
    try:
        entries = list(os.scandir(directory))
    except OSError:
        return removed
    for e in entries:
        m = _TEMP.match(e.name)
        if not m or not e.is_file(follow_symlinks=False):
            continue
        pid = int(m.group("pid"))
        if pid in own or not _alive(pid):
            try:
                os.unlink(e.path)
                removed.append(e.path)
            except OSError:
                pass
    return removed


class DirectoryLock:
    """An exclusive advisory lock (flock) on the file `path` for the duration of a run, so that a second run into
    the same output fails at once (EnvironmentFault naming `name`) instead of mixing its files with the first's.
    The lock file is removed on release; a holder checks after locking that the path still names the file it
    locked (a run that removed it in between would otherwise leave two holders)."""

    def __init__(self, path, name: str, busy: str):
        self.path, self.name, self.busy = Path(path), name, busy
        self.fh = None

    def acquire(self) -> "DirectoryLock":
        import fcntl

        for _ in range(20):
            try:
                fh = open(self.path, "a+")
            except OSError as exc:
                raise EnvironmentFault(self.name, f"cannot create the lock {str(self.path)!r}: "
                                                  f"{exc.strerror or exc}") from None
            try:
                fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                fh.close()
                raise EnvironmentFault(self.name, self.busy) from None
            try:
                same = os.stat(self.path).st_ino == os.fstat(fh.fileno()).st_ino
            except FileNotFoundError:
                same = False
            if same:
                self.fh = fh
                return self
            fh.close()  # removed by a holder that just finished: lock the new file instead
        raise EnvironmentFault(self.name, self.busy)

    def release(self) -> None:
        if self.fh is None:
            return
        try:
            os.unlink(self.path)
        except OSError:
            pass
        self.fh.close()
        self.fh = None

    def __enter__(self):
        return self.acquire()

    def __exit__(self, *exc):
        self.release()
        return False


# errno values that mean "the machine is out of something", not "the input is wrong"
RESOURCE_ERRNOS = {errno.ENOSPC: "no space left on the device", errno.EDQUOT: "disk quota exceeded",
                   errno.EFBIG: "file too large (file-size limit, ulimit -f)",
                   errno.EMFILE: "too many open files (ulimit -n)", errno.ENFILE: "too many open files in the system",
                   errno.ENOMEM: "out of memory", errno.EROFS: "read-only file system"}


def resource_fault(exc: OSError, name: str = "out", path=None) -> EnvironmentFault:
    """The EnvironmentFault (exit 3, one line with the path) for an OSError raised by the machine."""
    what = RESOURCE_ERRNOS.get(exc.errno) or exc.strerror or str(exc)
    where = path if path is not None else (exc.filename if exc.filename is not None else None)
    return EnvironmentFault(name, f"{what}" + (f": {str(where)!r}" if where is not None else ""))


def atomic_write_text(path, text: str) -> Path:
    return atomic_write_bytes(path, text.encode("utf-8"))


def atomic_write_json(path, obj) -> Path:
    return atomic_write_text(path, json.dumps(obj, indent=2, sort_keys=True, default=_jsonable) + "\n")


def atomic_savez(path, **arrays) -> Path:
    buf = _io.BytesIO()
    np.savez(buf, **arrays)
    return atomic_write_bytes(path, buf.getvalue())


def atomic_savefig(fig, path, **kw) -> Path:
    """Write `fig` atomically as `path` (format from the suffix), with reproducible bytes: no creation date in
    PNG, PDF or SVG.  The figures wing calls it through magrod.figures.common.atomic_savefig (formats chosen
    per build, SVG ids from a fixed salt)."""
    path = Path(path)
    buf = _io.BytesIO()
    fmt = path.suffix.lstrip(".") or "png"
    meta = {"png": {"Software": None}, "svg": {"Date": None}}.get(fmt, {"CreationDate": None})
    fig.savefig(buf, format=fmt, metadata=meta, **kw)
    return atomic_write_bytes(path, buf.getvalue())


# The one orbit-file schema (every orbit file magrod writes, `write_orbit`; `magrod rod --from` reads them all):
# arrays of the sampled symmetric orbit, t in [0, 2T] (n,), body states x (n, N), chart coordinates, Hbar, the
# scaled arclength tau of the plotted window, and what reproduces it: launch point x0, time T to the symmetric
# point, launch distance ("eps" in older files; not read back), angle, parameters pars (PARAMS order) and the reversor at the symmetric point.
ORBIT_ARRAYS = ("t", "x", "theta", "psi", "ptheta", "ppsi", "H", "tau", "x0", "T", "launch_distance", "pars", "reversor",
                "angle")
ORBIT_KEYS = ("x0", "T", "pars", "t", "tau", "x")  # what load_orbit_file requires (and validates)
ORBIT_SCALE = "B = C = m3 = 1 (derive/numeric_scale.py): t = s, lengths in units of B/m3"


def write_orbit(out_dir, stem: str, orbit, *, samples: dict | None = None, meta: dict | None = None) -> list[str]:
    """The one orbit-file writer: `orbit` (a converged magrod.orbits.shooting.MultipulseOrbit, to either saddle)
    as <stem>.npz (ORBIT_ARRAYS) and <stem>.json (meta, the orbit's scalar fields under "shooting", its Newton
    history, versions), atomically.  samples: orbit.sample() if already computed.  Returns the two paths."""
    orb = samples if samples is not None else orbit.sample()
    if "tau" not in orb:
        raise ValueError("samples must contain the scaled arclength tau (MultipulseOrbit.sample)")
    out = Path(out_dir)
    arrays = {"t": orb["t"], "x": orb["x"], "theta": orb["theta"], "psi": orb["psi"], "ptheta": orb["ptheta"],
              "ppsi": orb["ppsi"], "H": orb["H"], "tau": orb["tau"], "x0": orbit.x0, "T": orbit.T,
              "launch_distance": orbit.launch_distance, "pars": orbit.params.array(), "reversor": orb["reversor"]}
    if orbit.kind != "equilibrium":  # the straight rod's angle is a symmetry (always 0): its files omit it
        arrays["angle"] = orbit.angle
    npz = atomic_savez(out / f"{stem}.npz", **arrays)
    side = {**(meta or {}), "shooting": orbit.to_dict(arrays=False), "history": orbit.history, "versions": versions(),
            "scale": ORBIT_SCALE, "arrays": sorted(arrays)}
    js = atomic_write_json(out / f"{stem}.json", side)
    return [str(npz), str(js)]


def _orbit_arrays(path: Path, keys, bad: str) -> dict:
    """{key: array} of an orbit .npz (never unpickled); ParameterError naming `from` if the file is missing or is
    not one (`bad` says what it should have been)."""
    import zipfile

    if not path.is_file():
        raise ParameterError("from", f"no such file: {str(path)!r}")
    try:
        with np.load(path, allow_pickle=False) as d:
            return {k: np.asarray(d[k]) for k in keys}
    except (KeyError, ValueError, OSError, EOFError, zipfile.BadZipFile) as exc:
        raise ParameterError("from", f"{bad} ({type(exc).__name__}: {' '.join(str(exc).split())[:120]})") from None


def load_orbit_file(path) -> dict:
    """The arrays of an orbit .npz written by magrod (`write_orbit`: `magrod multipulse` for either saddle, the
    figures), validated: ParameterError naming `from` if the file is missing, empty, truncated, not such a file,
    or holds non-finite or inconsistent data.  Never unpickles (allow_pickle=False)."""
    path = Path(path)
    bad = f"{str(path)!r} is not a magrod orbit file (magrod multipulse)"
    out = _orbit_arrays(path, ORBIT_KEYS, bad)
    from ..generated.names import BODY_STATE, PARAMS

    n = len(BODY_STATE)
    shapes_ok = (out["x0"].shape == (n,) and out["T"].shape == () and out["pars"].shape == (len(PARAMS),)
                 and out["t"].ndim == 1 and out["t"].size >= 3 and out["tau"].shape == out["t"].shape
                 and out["x"].shape == (out["t"].size, n))
    if not shapes_ok:
        raise ParameterError("from", f"{bad} (arrays of the wrong shape)")
    if not all(out[k].dtype.kind == "f" and np.all(np.isfinite(out[k])) for k in ORBIT_KEYS):
        raise ParameterError("from", f"{bad} (non-numeric or non-finite values)")
    if not (np.all(np.diff(out["t"]) > 0) and np.count_nonzero(np.abs(out["tau"]) <= 1.0) >= 2):
        raise ParameterError("from", f"{bad} (arclength not increasing or no plotted window)")
    from .params import RodParams

    try:
        RodParams.from_array(out["pars"])
    except ParameterError as exc:
        raise ParameterError("from", f"{bad} (its parameters: {exc})") from None
    return out


# An orbit file of any other model (a symmetric homoclinic or N-pulse orbit, magrod.orbits.reversible.SymmetricOrbit,
# written by `magrod homoclinic --model` and `magrod multipulse --model`): the model and its parameters are recorded,
# so that `magrod rod --from` studies the orbit of the model it was computed for, and the orbit's own unknowns
# (alpha, T, launch distance, reversor), so that it is re-shot (not trusted) when read.
MODEL_ORBIT_KEYS = ("model", "param_names", "pars", "state", "x0", "T", "alpha", "launch_distance", "equilibrium",
                    "reversor", "pulses", "t", "x")


def write_model_orbit(out_dir, stem: str, orbit, *, meta: dict | None = None, samples: int = 2001) -> list[str]:
    """A converged symmetric orbit of any model other than the paper's rod as <stem>.npz (MODEL_ORBIT_KEYS, the
    model's name or file path and its parameters among them) and <stem>.json (meta, the model, its parameters, the
    orbit's accuracy, versions), atomically.  Returns the two paths."""
    system = orbit.system
    smp = orbit.sample(samples)
    arrays = {"model": np.array(str(system.model)), "param_names": np.array(list(system.names)),
              "pars": system.array(), "state": np.array(list(orbit.reversor.names)), "x0": np.asarray(orbit.x0, float),
              "T": np.float64(orbit.T), "alpha": np.float64(orbit.alpha),
              "launch_distance": np.float64(orbit.launch_distance), "equilibrium": np.asarray(orbit.equilibrium.x, float),
              "reversor": np.asarray(orbit.reversor.matrix, float), "pulses": np.int64(orbit.pulses),
              "t": smp["t"], "x": smp["x"]}
    out = Path(out_dir)
    npz = atomic_savez(out / f"{stem}.npz", **arrays)
    side = {**(meta or {}), "model": system.model, "params": system.params, "pulses": int(orbit.pulses),
            "alpha": float(orbit.alpha), "T": float(orbit.T), "launch_distance": float(orbit.launch_distance),
            "reversor": repr(orbit.reversor), "accuracy": orbit.accuracy, "message": orbit.message,
            "versions": versions(), "arrays": sorted(arrays)}
    js = atomic_write_json(out / f"{stem}.json", side)
    return [str(npz), str(js)]


def is_model_orbit_file(path) -> bool:
    """True if `path` is an .npz that records a model (an orbit file of `write_model_orbit`); False for anything
    else (the paper's orbit files, other files, a missing file: `load_orbit_file` then says what is wrong)."""
    import zipfile

    try:
        with np.load(Path(path), allow_pickle=False) as d:
            return "model" in d.files
    except (ValueError, OSError, EOFError, zipfile.BadZipFile, AttributeError):
        return False


def load_model_orbit_file(path) -> dict:
    """The arrays of a model's orbit file (`write_model_orbit`), validated: ParameterError naming `from` if the file
    is not such a file or holds inconsistent or non-finite data.  "model", "param_names" and "state" come back as
    str and tuples of str, the scalars as Python numbers.  Never unpickles."""
    path = Path(path)
    bad = f"{str(path)!r} is not a magrod orbit file of a model (magrod homoclinic/multipulse --model)"
    out = _orbit_arrays(path, MODEL_ORBIT_KEYS, bad)
    text = ("model", "param_names", "state")
    if not all(out[k].dtype.kind == "U" for k in text) or out["model"].shape != ():
        raise ParameterError("from", f"{bad} (no model recorded)")
    n = out["state"].size
    shapes_ok = (out["param_names"].ndim == 1 and out["pars"].shape == out["param_names"].shape
                 and out["state"].ndim == 1 and out["x0"].shape == (n,) and out["equilibrium"].shape == (n,)
                 and out["reversor"].shape == (n, n) and out["t"].ndim == 1 and out["t"].size >= 3
                 and out["x"].shape == (out["t"].size, n)
                 and all(out[k].shape == () for k in ("T", "alpha", "launch_distance", "pulses")))
    if not shapes_ok:
        raise ParameterError("from", f"{bad} (arrays of the wrong shape)")
    numeric = [k for k in MODEL_ORBIT_KEYS if k not in text]
    if not all(out[k].dtype.kind in "fi" and np.all(np.isfinite(out[k])) for k in numeric):
        raise ParameterError("from", f"{bad} (non-numeric or non-finite values)")
    if not (out["T"] > 0 and out["launch_distance"] > 0 and out["pulses"] >= 1):
        raise ParameterError("from", f"{bad} (T, launch distance and pulses must be positive)")
    res = {k: out[k] for k in numeric}
    res.update(model=str(out["model"]), param_names=tuple(str(v) for v in out["param_names"]),
               state=tuple(str(v) for v in out["state"]))
    for k in ("T", "alpha", "launch_distance"):
        res[k] = float(out[k])
    res["pulses"] = int(out["pulses"])
    return res


def _jsonable(o):
    from enum import Enum

    if isinstance(o, Enum):
        return o.value
    if isinstance(o, (np.floating, np.integer)):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"not JSON serialisable: {type(o)}")
