"""What limits statement 5's lambdabar interval: the homoclinic crossing phase phi* moves with lambdabar.

The proof encloses W^u of the saddle-focus by a boundary circle x = x* + V_u r (cos phi, sin phi) around the point's
saddle x*(1/100) and finds, by interval Newton in phi over an arc [phi_c - dphi, phi_c + dphi], the one phi* whose
orbit crosses Fix(R) at psi = 0 (and at psi = pi).  On a lambdabar interval the Newton image must hold phi*(lambdabar)
for every lambdabar of it, so its radius is at least |dphi*/dlambdabar| W, whatever the integrator.  Measured here
in float64 (heyoka, the prover's own float search transverse_homoclinic._FloatFlow; central differences at lambdabar = 1/100 +- d):

  fixed circle    the circle about x*(1/100) (what the certificate does: its saddle box holds x*(lambdabar));
  moving circle   the circle about x*(lambdabar) (the saddle re-found at each lambdabar; V, r unchanged).

Against it: the rigorous Newton radius of research/homoclinic_interval.json (1.9e8 W) and the widest phase arc that
still proves (3.2e-5, where the arc's dtheta_u/dpsi ball is already +-0.0014 about -0.0025).  Numerical
(floating-point) measurements of a derivative; two step sizes d as the convergence evidence.

    python research/homoclinic_phase_motion.py [--out research/homoclinic_phase_motion.json]
"""
from __future__ import annotations

import argparse
import json
import time
from fractions import Fraction

import numpy as np


def phases(lam: Fraction, centre=None):
    from magrod.proof import ball, fields, saddle
    from magrod.proof.provers import transverse_homoclinic

    p = transverse_homoclinic.validate_params("1.7", "0.04", "1", "1", lam)
    fld = fields.chart_field(p)
    sd = transverse_homoclinic._float_saddle(p)
    xhat = saddle.refine(fld, [float(v) for v in sd.q])
    J = ball.to_floats(fld.df(xhat).mid())
    w, Vc = np.linalg.eig(J)
    iu = [i for i in range(len(w)) if w[i].real > 0 and w[i].imag > 0]
    is_ = [i for i in range(len(w)) if w[i].real < 0 and w[i].imag > 0]
    Vf = np.column_stack(transverse_homoclinic._real_basis(Vc[:, iu[0]]) + transverse_homoclinic._real_basis(Vc[:, is_[0]]))
    return p, xhat, Vf


def main(argv=None):
    from magrod.proof import ball
    from magrod.proof.provers import transverse_homoclinic

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    st = transverse_homoclinic.ProofSettings()
    lam0 = Fraction(1, 100)
    _, x0, V0 = phases(lam0)
    V = ball.exact_matrix(V0.tolist())
    rows = []
    for d in (Fraction(1, 10**8), Fraction(1, 10**7)):
        out = {"d": float(d)}
        for mode in ("fixed", "moving"):
            phi = {}
            for tgt, val in (("0", 0.0), ("pi", np.pi)):
                vals = []
                for s in (-1, 1):
                    p, xs, _ = phases(lam0 + s * d)
                    centre = x0 if mode == "fixed" else xs
                    vals.append(transverse_homoclinic._FloatFlow(p, centre, V, st.r).phase(val)[0])
                phi[tgt] = (vals[1] - vals[0]) / (2 * float(d))
            out[mode] = phi
        rows.append(out)
        print(json.dumps(out), flush=True)
    res = {"r": float(st.r), "rows": rows, "wall_s": round(time.perf_counter() - t0, 1)}
    if a.out:
        with open(a.out, "w") as fh:
            json.dump(res, fh, indent=1)


if __name__ == "__main__":
    main()
