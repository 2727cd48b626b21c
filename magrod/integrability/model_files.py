"""Bring your own rod: a user's model file is checked and put through the symbolic pipeline (derive/models/
pipeline.py, live SymPy), and its generated code is written into a cache directory keyed by the evaluated model
(magrod.core.models.content_key, under cache_root), never into the installed package.

Every check runs before anything is written (derive/models/spec.py: import, missing names, name clash, J skew,
Jacobi identity, W polynomial and convex, parameters); a failure is a ParameterError naming `model` and the check.
The cache entry is written into a temporary sibling directory and renamed into place, so an interrupted compile
never leaves a half entry."""
from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

from ..core.errors import EnvironmentFault, ParameterError


def check_file(path: Path):
    """The checked Model of a file (derive.models.spec.Model); ParameterError('model', '<check>: ...')."""
    try:
        from ..derive.models import spec
    except ImportError as exc:
        raise EnvironmentFault("model", f"a model file needs SymPy (pip install 'magrod[derive]'): {exc}") from None
    try:
        model = spec.load_file(path)
    except spec.ModelError as exc:
        raise ParameterError("model", f"{path.name}: {exc}") from None
    from ..derive.models import NAMES

    if model.name in NAMES:
        raise ParameterError("model", f"{path.name}: name clash: NAME {model.name!r} is a registered model; choose "
                                      "another name")
    return model


def compile_model(model, target: Path, *, cached: bool = True) -> tuple[Path, str]:
    """(directory with names.py, body.py, first_integrals.py, report.json, report.md; the model's NAME) of a checked
    model.  Reuses a complete entry at `target`; otherwise derives, writes to a temporary directory, renames."""
    marker = target / "report.json"
    if marker.is_file():
        import json

        return target, json.loads(marker.read_text())["model"]
    from ..derive.models import pipeline

    files = pipeline.model_files(model, cached=cached)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=".tmp-", dir=target.parent))
        try:
            for name, text in files.items():
                (tmp / name).write_text(text)
            os.replace(tmp, target)
        except OSError:
            shutil.rmtree(tmp, ignore_errors=True)
            if not marker.is_file():  # a concurrent compile of the same content won the rename: fine
                raise
    except OSError as exc:
        raise EnvironmentFault("model", f"cannot write the model cache {target.parent}: {exc.strerror or exc}") from None
    return target, model.name


def compile_file(path: Path, target: Path) -> tuple[Path, str]:
    """compile_model of the checked file."""
    return compile_model(check_file(path), target)
