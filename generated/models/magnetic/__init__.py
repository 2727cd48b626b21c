"""Machine-written by derive/models/pipeline.py (python -m derive) -- DO NOT EDIT BY HAND.

Model 'magnetic': isotropic inextensible conducting rod in a uniform magnetic field."""
