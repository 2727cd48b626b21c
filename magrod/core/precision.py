"""One vocabulary for floating-point precision, used by every numerics module, result and command.

`Precision` names the four arithmetics heyoka integrates in on this platform; `Precision.parse` is the one place
where user input ("double", "long double", "quad", "mp", or the enum itself) becomes a precision, with a
ParameterError naming the option otherwise.  `fp_type` is the number type heyoka is built with (float,
np.longdouble, hy.real128, hy.real); `bits` the significand width (hy.real: MP_BITS unless stated).
"""
from __future__ import annotations

from enum import Enum

from .errors import ParameterError

MP_BITS = 192  # significand bits of hy.real runs (multiprecision verification runs)


class Precision(str, Enum):
    """Floating-point precision of an integration.

    A str-valued enumeration: a member equals its value, so ``"quad"`` may be passed wherever a Precision is
    taken (`parse` is the one converter, with a ParameterError naming the option otherwise).

    Attributes
    ----------
    DOUBLE : "double"
        IEEE binary64 (53 significand bits): the default of every run.
    LONG_DOUBLE : "long double"
        x87 extended precision (64 bits, ``np.longdouble``): verification runs, about 10 x slower.
    QUAD : "quad"
        IEEE binary128 (113 bits, ``hy.real128``).
    MP : "mp"
        Multiprecision (``hy.real``, MP_BITS = 192 bits unless stated).

    Examples
    --------
    >>> from magrod import Precision
    >>> Precision.parse("long double")
    <Precision.LONG_DOUBLE: 'long double'>
    >>> Precision.LONG_DOUBLE.bits
    64
    """

    DOUBLE = "double"
    LONG_DOUBLE = "long double"
    QUAD = "quad"
    MP = "mp"

    def __str__(self) -> str:
        return self.value

    # a str-valued enum member equals its value; hash it like the value too, so that {"quad": ...}[Precision.QUAD]
    # and {Precision.QUAD: ...}["quad"] both work (Enum's own __hash__ hashes the member name)
    __hash__ = str.__hash__

    @property
    def bits(self) -> int:
        """Significand bits (53, 64, 113, MP_BITS)."""
        return {"double": 53, "long double": 64, "quad": 113, "mp": MP_BITS}[self.value]

    @property
    def eps(self) -> float:
        """Unit roundoff 2^(1 - bits) as a float (the machine epsilon of the precision)."""
        return 2.0 ** (1 - self.bits)

    @property
    def fp_type(self):
        """The heyoka/numpy number type: float, np.longdouble, hy.real128 or hy.real."""
        import numpy as np

        if self is Precision.DOUBLE:
            return float
        if self is Precision.LONG_DOUBLE:
            return np.longdouble
        import heyoka as hy

        return hy.real128 if self is Precision.QUAD else hy.real

    @property
    def prec(self) -> int | None:
        """hy.real's precision argument (bits) for MP, None otherwise."""
        return MP_BITS if self is Precision.MP else None

    @classmethod
    def parse(cls, value, name: str = "precision") -> "Precision":
        """A Precision from itself or its value; ParameterError(name) for anything else."""
        if isinstance(value, cls):
            return value
        for p in cls:
            if value == p.value:
                return p
        raise ParameterError(name, f"must be one of {', '.join(repr(p.value) for p in cls)}, got {value!r}")

    @classmethod
    def of(cls, fp_type) -> "Precision":
        """The Precision of a number type (float, np.float64, np.longdouble, hy.real128, hy.real)."""
        import numpy as np

        if fp_type in (float, np.float64):
            return cls.DOUBLE
        if fp_type is np.longdouble:
            return cls.LONG_DOUBLE
        import heyoka as hy

        if fp_type is hy.real128:
            return cls.QUAD
        if fp_type is hy.real:
            return cls.MP
        raise ValueError(f"no Precision for number type {fp_type!r}")
