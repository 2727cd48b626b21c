"""The proof checker's kernel: the certificate schema (schema.py) and one module per certificate kind
(homoclinic.py, fixed_point.py, horseshoe.py; pool.py runs the horseshoe's sets in child processes).  The entry is
magrod/proof/verify.py; what the kernel may import is fenced by tests/test_proof_verify.py (never a prover)."""
