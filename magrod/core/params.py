"""Non-dimensional parameters of the reduced system (eq:nondim_1), validated on construction."""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from .errors import MAX_MAGNITUDE, ParameterError, require_finite
from ..generated.names import PARAMS
from .deprecation import deprecated_alias


M_MIN = 1e-3


@dataclass(frozen=True)
class RodParams:
    """m = m3/sqrt(B C2), mu = (2 C1 - C2^2)/C2^2, gamma = C2 (1/K - 1/J), delta = C2/J,
    lam = lambdabar = lambda m3 / C2^2   (eq:nondim_1).

    Physical ranges: m > 0 (m3 > 0, C2 > 0); delta >= 0 (J > 0); gamma + delta >= 0 (K > 0); mu is
    constrained only through the radicand mu - 2 lam pbar_psi > 0 along an orbit (eq:alignment_condition),
    which the integrators check.  Numerical range: ``|value|`` <= MAX_MAGNITUDE = 1e6 and m >= M_MIN = 1e-3 (the
    vector field has terms in m^-4: beyond these a float64 run is meaningless).

    Parameters
    ----------
    m : float
        m = m3/sqrt(B C2): the axial twisting moment m3 scaled by the bending stiffness B and the Casimir C2;
        m > 0 (and m >= M_MIN).
    mu : float
        mu = (2 C1 - C2^2)/C2^2, from the Casimirs C1 and C2 (eq:magnetic_casimirs1, eq:magnetic_casimirs2).
    gamma : float
        gamma = C2 (1/K - 1/J), K the axial and J the transverse shear stiffness; gamma + delta >= 0.
    delta : float
        delta = C2/J; delta >= 0.
    lam : float
        lambdabar = lambda m3 / C2^2, with lambda = I B the current times the magnetic field (lam = 0: no field).

    Raises
    ------
    ParameterError
        Naming the field that is not a finite number or violates its range.

    Examples
    --------
    >>> import magrod as mr
    >>> p = mr.RodParams(m=1.7, mu=0.4, gamma=3, delta=3, lam=0.135)
    >>> p.replace(lam=0.15).lam
    0.15
    >>> mr.RodParams(m=1.7, mu=0.4, gamma=3, delta=-1, lam=0.135)
    Traceback (most recent call last):
    ...
    magrod.core.errors.ParameterError: delta: must be >= 0 (delta = C2/J with shear stiffness J > 0), got -1.0
    """

    m: float
    mu: float
    gamma: float
    delta: float
    lam: float

    def __post_init__(self):
        for f in PARAMS:
            v = getattr(self, f)
            if isinstance(v, (str, bytes)):  # a number where a number belongs: "1.7" is the caller's bug
                raise ParameterError(f, f"must be a number, got the string {str(v)[:40]!r}")
            object.__setattr__(self, f, require_finite(f, v, MAX_MAGNITUDE))
        if self.m <= 0:
            raise ParameterError("m", f"must be > 0 (m = m3/sqrt(B C2)), got {self.m}")
        if self.m < M_MIN:
            raise ParameterError("m", f"must be >= {M_MIN:g} (terms in m^-4), got {self.m}")
        if self.delta < 0:
            raise ParameterError("delta", f"must be >= 0 (delta = C2/J with shear stiffness J > 0), got {self.delta}")
        if self.gamma + self.delta < 0:
            raise ParameterError("gamma", f"must satisfy gamma + delta >= 0 (axial stiffness K > 0), got "
                                          f"gamma = {self.gamma}, delta = {self.delta}")

    def array(self) -> np.ndarray:
        """heyoka runtime parameters hy.par[i] = PARAMS[i] (generated/names.py)."""
        return np.array([getattr(self, f) for f in PARAMS], dtype=float)

    def replace(self, **changes) -> "RodParams":
        """A copy with some fields changed (validated again)."""
        return RodParams(**{**self.to_dict(), **changes})

    @classmethod
    def from_array(cls, values) -> "RodParams":
        return cls(**dict(zip(PARAMS, map(float, values))))

    as_dict = deprecated_alias("to_dict", "as_dict")

    def to_dict(self) -> dict:
        return asdict(self)
