"""The provers, named by what they prove; outside the trust base (the verifier, magrod/proof/verify.py and kernel/,
imports none of them; tests/test_proof_verify.py fences it).  Each searches in floating point for where to look and
then establishes every claim with ball arithmetic, writing a certificate only when all hold:

  transverse_homoclinic.py  transverse symmetric homoclinic orbits of the tilted saddle-focus (statements 5, 5a)
  section_fixed_point.py    a symmetric hyperbolic fixed point of the section map on a level (statements 11, 13)
  section_horseshoe.py      a horseshoe of the section map by covering relations (statements 12, 13)
  horseshoe_design.py       its settings, the named designs (magrod/proof/designs/*.json) and the float design
  horseshoe_widen.py        a horseshoe certificate widened to a lambdabar interval, the sets moving with lambdabar
"""
