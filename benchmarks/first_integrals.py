"""Benchmark: wall time of the exact first-integral search with its four controls,
`first_integral_search(D)` for D = 4, 5, 6 (the CLI `magrod check --integrals --degree D` adds ~1 s of start-up and
SymPy for --subs parsing).  Prints per degree the wall time, the main regime's dimensions and whether the controls hold.
Not a test (tests/test_first_integrals.py checks the contract at D = 4)."""
import sys
import time

import _smoke  # noqa: E402  (benchmarks/: on sys.path as the script's directory)
from magrod.integrability.first_integrals import first_integral_search

_smoke.from_argv()  # --smoke: degree 2 only
for D in [int(a) for a in sys.argv[1:]] or _smoke.n((4, 5, 6), (2,)):
    t0 = time.perf_counter()
    r = first_integral_search(D)
    wall = time.perf_counter() - t0
    print(f"D = {D}: {wall:6.1f} s  ok={r.success}  main dim ker {r.main.kernel_dims} = algebra {r.main.algebra_dims}  "
          f"largest block {r.main.stats['largest_block']}  controls {r.controls_ok}", flush=True)
