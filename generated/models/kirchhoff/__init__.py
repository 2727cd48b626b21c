"""Machine-written by derive/models/pipeline.py (python -m derive) -- DO NOT EDIT BY HAND.

Model 'kirchhoff': isotropic, inextensible Kirchhoff rod."""
