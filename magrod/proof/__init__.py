"""Computer-assisted proof of transverse homoclinic orbits of the magnetic rod.

Layers (each tested on its own, tests/test_proof_*.py):
  ball.py      exact rationals <-> Arb balls <-> the certificate's decimal strings; the working precision
  taylor.py    the validated C^1 Taylor integrator (Picard on arb_series, high-order enclosure, doubleton Lohner/QR)
  fields.py    the rod's ball-arithmetic fields (generated/validated.py, from derive/validated.py)
  identities.py  the field's reversibility, Hamiltonian form and Jacobian as exact identities (checked by the verifier)
  saddle.py    Krawczyk enclosures of the tilted saddle and its eigenpairs
  manifold.py  the local unstable manifold by cone/slab conditions; its boundary circle with C^1 bounds
  search.py    the prover: floating-point search + the rigorous steps -> certificate
  verify.py    the independent checker of a certificate (imports neither search.py nor saddle.py/manifold.py): its
               entry, and kernel/ (schema.py, one module per kind: homoclinic.py, fixed_point.py, horseshoe.py; pool.py)
  schedule.py  verifies many certificates in processes and remembers verified ones (outside the trust base)
  tiling.py    the lambdabar interval a chain of interval certificates covers, exactly (a gap is an error)

The names below are the package's public tier (docs/architecture.md, the API reference; tests/test_wings.py allows these and nothing deeper
for the command line and the figures), imported lazily.
"""
from ..core.lazy import namespace

_API = {
    # the generated ball-arithmetic fields, and the mutated control
    "validated_fields": ("fields", "gen"),
    "mutated_fields": ("fields", "mutated_module"),
    # the prover of transverse homoclinic orbits to the tilted saddle
    "ProofSettings": ("search", "ProofSettings"),
    "TARGET_ANGLES": ("search", "TARGETS"),
    "validate_proof_params": ("search", "validate_params"),
    "prove_homoclinic": ("search", "prove"),
    # the same proof for every lambdabar of an interval (lambdabar a ball in every enclosure; statement 5)
    "interval_proof_params": ("search", "interval_params"),
    "interval_proof_settings": ("search", "interval_proof_settings"),
    # the prover of the section map's fixed point (statement 11)
    "FixedPointSettings": ("periodic", "FixedPointSettings"),
    "interval_settings": ("periodic", "interval_settings"),
    "interval_settings_for": ("periodic", "interval_settings_for"),
    "validate_fixed_point": ("periodic", "validate"),
    "prove_fixed_point": ("periodic", "prove"),
    # the prover of the section map's horseshoe by covering relations (statement 12)
    "HorseshoeSettings": ("horseshoe", "HorseshoeSettings"),
    "prove_horseshoe": ("horseshoe", "prove"),
    # the same horseshoe for every lambdabar of an interval, its sets moving with lambdabar (statement 12)
    "widen_horseshoe": ("horseshoe", "widen"),
    "HORSESHOE_DESIGNS": ("horseshoe", "DESIGNS"),
    # the independent checker, and the statements' verdicts
    "load_certificate": ("verify", "load"),
    "verify_certificate": ("verify", "verify"),
    # many certificates: in processes on every core, each verified one remembered (scheduling, not the trust base)
    "verify_certificates": ("schedule", "verify_many"),
    # a verify_certificate(mapper=...) that re-flies a horseshoe's sets on a Dask cluster
    "dask_mapper": ("schedule", "dask_mapper"),
    "statement_status": ("statements", "status"),
}

__getattr__, __dir__, __all__ = namespace(__name__, _API)
del namespace
