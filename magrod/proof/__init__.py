"""Computer-assisted proof of transverse homoclinic orbits of the magnetic rod.

Layers (each tested on its own, tests/test_proof_*.py):
  ball.py      exact rationals <-> Arb balls <-> the certificate's decimal strings; the working precision
  taylor.py    the validated C^1 Taylor integrator (Picard on arb_series, high-order enclosure, doubleton Lohner/QR)
  fields.py    the rod's ball-arithmetic fields (generated/validated.py, from derive/validated.py)
  identities.py  the field's reversibility, Hamiltonian form and Jacobian as exact identities (checked by the verifier)
  saddle.py    Krawczyk enclosures of the tilted saddle and its eigenpairs
  manifold.py  the local unstable manifold by cone/slab conditions; its boundary circle with C^1 bounds
  provers/     the provers, named by what they prove (floating-point search + the rigorous steps -> certificate):
               transverse_homoclinic.py (statement 5), section_fixed_point.py (11, 13), section_horseshoe.py (12, 13),
               with the horseshoe's design (horseshoe_design.py; the named designs are data, designs/*.json) and its
               widening to a lambdabar interval (horseshoe_widen.py)
  verify.py    the independent checker of a certificate (imports neither provers/ nor saddle.py/manifold.py): its
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
    "ProofSettings": ("provers.transverse_homoclinic", "ProofSettings"),
    "TARGET_ANGLES": ("provers.transverse_homoclinic", "TARGETS"),
    "validate_proof_params": ("provers.transverse_homoclinic", "validate_params"),
    "prove_homoclinic": ("provers.transverse_homoclinic", "prove"),
    # the same proof for every lambdabar of an interval (the circle about the moving saddle; statement 5)
    "interval_proof_params": ("provers.transverse_homoclinic", "interval_params"),
    "interval_proof_settings": ("provers.transverse_homoclinic", "interval_proof_settings"),
    # the prover of the section map's fixed point (statement 11)
    "FixedPointSettings": ("provers.section_fixed_point", "FixedPointSettings"),
    "interval_settings": ("provers.section_fixed_point", "interval_settings"),
    "interval_settings_for": ("provers.section_fixed_point", "interval_settings_for"),
    "validate_fixed_point": ("provers.section_fixed_point", "validate"),
    "prove_fixed_point": ("provers.section_fixed_point", "prove"),
    # the same for every lambdabar of an interval, the theta-box moving with the fixed point (statements 11, 13)
    "prove_fixed_point_moving": ("provers.section_fixed_point", "prove_moving"),
    # the prover of the section map's horseshoe by covering relations (statement 12)
    "HorseshoeSettings": ("provers.horseshoe_design", "HorseshoeSettings"),
    "prove_horseshoe": ("provers.section_horseshoe", "prove"),
    # the same horseshoe for every lambdabar of an interval, its sets moving with lambdabar (statement 12)
    "widen_horseshoe": ("provers.horseshoe_widen", "widen"),
    "HORSESHOE_DESIGNS": ("provers.horseshoe_design", "DESIGNS"),
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
