"""What the orbit commands share when they run a model other than the paper's rod (`--model NAME|FILE.py`): the
refusal of the paper's chart options, and the plain data of an equilibrium and of a symmetric orbit with their
accuracy evidence.  (Not a subcommand: cli.SUBCOMMANDS does not list it.)"""
from __future__ import annotations

from ..core.errors import ParameterError


def refuse(args, options, model: str, why: str) -> None:
    """A ParameterError naming the first of `options` given on the command line (not None, not False): an option
    of the paper's chart, meaningless for `model`."""
    for opt in options:
        v = getattr(args, opt, None)
        if v is not None and v is not False:
            raise ParameterError(opt, f"--{opt.replace('_', '-')} {why}; it is not an option for the model "
                                      f"{str(model)[:80]!r}")


def complex_pair(z) -> list:
    return [float(complex(z).real), float(complex(z).imag)]


def equilibrium_dict(eq) -> dict:
    """An Equilibrium (magrod.orbits.equilibria) as plain data, with its accuracy."""
    return {"kind": eq.kind, "H": float(eq.H), "x": [float(v) for v in eq.x],
            "unstable_eigenvalue": complex_pair(eq.unstable_eigenvalue), "accuracy": eq.accuracy,
            "message": eq.message}


def orbit_dict(o) -> dict:
    """A SymmetricOrbit (magrod.orbits.reversible) as plain data, with its accuracy."""
    return {"success": bool(o.success), "pulses": int(o.pulses), "alpha": float(o.alpha), "T": float(o.T),
            "launch_distance": float(o.launch_distance), "reversor": o.reversor.label,
            "x_mid": [float(v) for v in o.x_mid], "accuracy": o.accuracy, "message": o.message}


def header(d: dict) -> str:
    p = ", ".join(f"{k} = {v:g}" for k, v in d["params"].items())
    return f"the model {d['model']} at {p}"


def checks(acc: dict) -> str:
    return ", ".join(f"{k} {v:.1e}" if isinstance(v, float) else f"{k} {v}" for k, v in acc.items())
