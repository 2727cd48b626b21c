"""magrod: spatial chaos of an extensible conducting rod in a uniform magnetic field.

Runtime library.  Numerics are built from the machine-written modules in magrod.generated (written by
magrod.derive, the only place SymPy is used); nothing here imports SymPy.
"""
__version__ = "0.1.0"
