"""Machine-written by derive/build.py (python -m derive) -- DO NOT EDIT BY HAND.

The registered rod models (derive/models/), one package each."""

MODELS = ('kirchhoff', 'anisotropic', 'curved', 'extensible', 'magnetic', 'magnetic-extensible')
DEFAULT = 'magnetic-extensible'
