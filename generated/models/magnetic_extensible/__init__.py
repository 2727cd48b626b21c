"""Machine-written by derive/models/pipeline.py (python -m derive) -- DO NOT EDIT BY HAND.

Model 'magnetic-extensible': the paper's rod: isotropic, extensible, shearable, conducting, in a uniform magnetic field."""
