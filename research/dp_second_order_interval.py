"""[DP] and [dP/ds] of a moving horseshoe piece (a lambdabar interval) by the C^0 Lohner flight of the variational system
of the lambdabar-state field: y = (x5, u_th, u_pt, u_s), x5 = (x, lambdabar), u' = DF5 u, u_s starting on the
piece's moving column (v, ..., 1); the D^2 F5[u] blocks by nested forward-mode duals of fields.lam_state_field.
Beside it the C^1 box flight (Taylor model, adaptive steps) that the interval certificates use.  A measurement, not
a proof (no guards; the initial tangents as balls over the box's hull).

    python research/dp_second_order_interval.py [CERT_NAME=horseshoe_fig4a_interval] [SET=12] [W=1/50000000000]
"""
import sys
import time
from fractions import Fraction as F
from pathlib import Path
from flint import arb, arb_mat
from magrod.proof import ball, fields, section_return as sr, taylor, taylor_model as tm
from magrod.proof.kernel.schema import frac

sys.path.insert(0, str(Path(__file__).resolve().parent))
from dp_second_order_prototype import capture_box, captured, load, piece  # noqa: E402  (the same harness)
from magrod.proof.variational import moving_column, variational_field  # noqa: E402

name = sys.argv[1] if len(sys.argv) > 1 else 'horseshoe_fig4a_interval'
I = int(sys.argv[2]) if len(sys.argv) > 2 else 12
W = F(sys.argv[3]) if len(sys.argv) > 3 else F(1, 50000000000)
c, s, p = load(name)
N = 5


capture_box(5)
with ball.workprec(int(s['prec']), int(s['series_cap'])):
    r, cX, AX, steps, br = piece(c, I)
    vI = tuple(frac(x) for x in c['sets'][I]['v'])
    pars = fields.parameter_balls(p, W)
    lamb = pars[fields.LAM]
    fld5 = fields.lam_state_field(p)
    mv = sr.Moving(tuple(pars), fld5, lamb, p.lam, vI)
    t0 = time.perf_counter()
    try:
        f = sr.piece_return(p.balls(), frac(c['level']), fields.chart_field(p), cX, AX, frac(r['p_c']), frac(s['p_rad']),
                            frac(r['t_a']), frac(s['lead']), t1=frac(s['t1']), order=int(s['order']), steps=None,
                            tol=float(s['tol']), newton=int(s['newton']), thin_c1=False, branch=br, moving=mv,
                            integrator=tm, thin_integrator=tm)
        print('C1 (taylor_model, adaptive) [DP] radii', [[f"{float(x.rad()):.2e}" for x in row] for row in f['DP']],
              '[dPds] radii', [f"{float(x.rad()):.2e}" for x in f['dPds']], f"{time.perf_counter() - t0:.1f} s")
    except Exception as e:
        print('C1 flight failed:', str(e)[:120])
    S5 = captured['box']
    Q = S5.hull()
    tg = sr.tangents(pars, Q)
    us = moving_column(pars, Q, vI)[3]
    u0 = tg['th'] + tg['pt'] + us
    center = [S5.xbar[i, 0] for i in range(N)] + [v.mid() for v in u0]
    S = taylor.initial_set(center, c1=False)
    C = arb_mat(4 * N, S5.C.ncols())
    for i in range(N):
        for j in range(S5.C.ncols()):
            C[i, j] = S5.C[i, j]
    S.C, S.r0 = C, S5.r0
    S.r = ball.vec(ball.column(S5.B * S5.r) + [v - v.mid() for v in u0])
    fld = variational_field(fld5, 3)  # (x5, u_th, u_pt, u_s)
    t0 = time.perf_counter()
    t_end = frac(r['t_a'])
    rec = taylor.Trajectory()
    S = tm.propagate(fld, S, t_end, order=int(s['order']), tol=float(s['tol']), record=rec)
    cr = tm.cross_section(fld, S, lambda y: y[1].sin(), lambda y: [arb(0), y[1].cos()] + [arb(0)] * (4 * N - 2),
                          2 * frac(s['lead']), int(s['order']))
    y = cr.x
    fx = cr.fx[:N]
    gg = [arb(0), y[1].cos(), arb(0), arb(0), arb(0)]
    gf = sum((a * b for a, b in zip(gg, fx)), arb(0))
    out = []
    for k in range(3):
        u = y[N + N * k: 2 * N + N * k]
        gu = sum((a * b for a, b in zip(gg, u)), arb(0))
        v = [ui - fi * gu / gf for ui, fi in zip(u, fx)]
        out.append((v[0], v[2]))
    print('second order: [DP] radii (cols th, pt)', [[f"{float(x.rad()):.2e}" for x in col] for col in out[:2]],
          '[dPds] radii', [f"{float(x.rad()):.2e}" for x in out[2]], f"{time.perf_counter() - t0:.1f} s, {len(rec.steps)} steps")
    print('  dPds mid', [f"{float(x.mid()):.8f}" for x in out[2]], 'v_next', c['sets'][I + 1]['v'] if I + 1 < len(c['sets']) else None)
