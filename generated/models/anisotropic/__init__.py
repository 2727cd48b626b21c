"""Machine-written by derive/models/pipeline.py (python -m derive) -- DO NOT EDIT BY HAND.

Model 'anisotropic': anisotropic inextensible rod (B1 != B2, C free)."""
