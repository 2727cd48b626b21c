"""Machine-written by derive/models/pipeline.py (python -m derive) -- DO NOT EDIT BY HAND.

Model 'curved': isotropic inextensible rod with intrinsic curvature (k1, 0, k3)."""
