"""Computer-assisted proof of transverse homoclinic orbits of the magnetic rod (issue 21).

Layers (each tested on its own, tests/test_proof_*.py):
  ball.py      exact rationals <-> Arb balls <-> the certificate's decimal strings; the working precision
  taylor.py    the validated C^1 Taylor integrator (Picard on arb_series, high-order enclosure, doubleton Lohner/QR)
  fields.py    the rod's ball-arithmetic fields (generated/validated.py, from derive/validated.py)
  saddle.py    Krawczyk enclosures of the tilted saddle and its eigenpairs
  manifold.py  the local unstable manifold by cone/slab conditions; its boundary circle with C^1 bounds
  search.py    the prover: floating-point search + the rigorous steps -> certificate
  verify.py    the independent checker of a certificate (imports neither search.py nor saddle.py/manifold.py)
"""
