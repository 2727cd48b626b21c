"""Lazy public namespaces (PEP 562): a package lists its public names and the module that defines each; a name is
imported on first access, so `import magrod` and `from magrod.chaos import MAPPABLE` stay light (no heyoka, no
matplotlib until a function that needs them runs).

The face (`magrod`) and the numerics packages' second tier (`magrod.chaos`, `.orbits`, `.separatrix`,
`.integrability`, `.proof`: the names the command line, the figures and the explorer may use; docs/architecture.md) are
both built here, so the two cannot drift apart in how they resolve a name."""
from __future__ import annotations

import importlib


def namespace(package: str, api: dict):
    """(__getattr__, __dir__, __all__) for `package`, given api = {public name: "module"} or
    {public name: ("module", "attribute")} (module relative to `package`; the tuple form when the defining module
    spells it differently, e.g. `verify_certificate` is `verify.verify`).  A public name may not be the name of a
    submodule: once that submodule is imported, the import system binds the module under that name and
    `from package import name` would return the module (tests/test_wings.py checks it)."""
    table = {k: (v, k) if isinstance(v, str) else tuple(v) for k, v in api.items()}

    def __getattr__(name: str):
        if name in table:
            mod, attr = table[name]
            # not cached in the package: the namespace is a view of the defining modules, so a name patched there
            # (a test's monkeypatch) is seen through the face and is never frozen into it (~1 us per lookup)
            return getattr(importlib.import_module(f"{package}.{mod}"), attr)
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():
        return sorted(set(globals_of(package)) | set(table))

    return __getattr__, __dir__, sorted(table)


def globals_of(package: str) -> dict:
    import sys

    return vars(sys.modules[package])

