"""Benchmark: wall time of a 200-point pseudo-arclength branch of the Fig 6 two-pulse orbit on
mu = 2 lam, continued in m (long double variational shooting, eps = 1e-9).  Prints points, wall time, max
residual and folds.  Not a test."""
import time

import numpy as np

import _smoke  # noqa: E402  (benchmarks/: on sys.path as the script's directory)
from magrod.orbits import continuation as C
from magrod.orbits import multipulse
from magrod.core.params import RodParams

_smoke.from_argv()  # --smoke: 3 points of the branch
LAM = 0.00126208079536
r = multipulse.shoot(RodParams(1.7, 2 * LAM, 1.0, 1.0, LAM), 2)
F, _ = C.mu2lam_problem(r.params, "m")
t0 = time.perf_counter()
b = C.pseudo_arclength(F, [r.T, r.params.lam, 1.7], scale=[r.T, 1e-3, 1.0], ds=0.01, ds_max=0.02, steps=_smoke.n(199, 2), par=2,
                       names=("T", "lam", "m"))
wall = time.perf_counter() - t0
print(f"points {len(b.u)}  wall {wall:.1f} s  ({wall / len(b.u) * 1e3:.0f} ms/point)  max residual "
      f"{np.max(b.residuals):.1e}  m range [{b.u[:, 2].min():.4f}, {b.u[:, 2].max():.4f}]  lam range "
      f"[{b.u[:, 1].min():.6g}, {b.u[:, 1].max():.6g}]  folds {C.fold_summary(b)}  {b.message}")
