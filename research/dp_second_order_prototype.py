"""A second-order enclosure of DP, prototyped: [DP] over a horseshoe piece from a C^0 Lohner flight of the first
variational system y = (x, u1, u2), u_k = DPhi t_k (chart field + Df u by forward-mode duals; its Jacobian's D^2f[u]
block by duals of the generated chart_jacobian), so that DP's dependence on the initial point rides in the set's
exact linear part instead of accumulating as an interval (research/README.md, "dp_enclosure_width.py").  The
Taylor-model integrator with adaptive steps at the certificate's tol; the crossing and the section projection as
the verifier's.  Prints the certificate's C^1 [DP] (re-flown here with taylor.py on its steps) beside it.  A
measurement, not a proof: no guards, the initial tangents as the prover's balls over the piece's hull.

    python research/dp_second_order_prototype.py [CERT_NAME=horseshoe_fig4a] [SET=12] [--linear-tangents]

--linear-tangents: the tangents' dependence on the initial point in the set's linear part (the Hessian of Hbar over
the hull by duals of series), the rest in the remainder.
"""
import json
import sys
import time
from pathlib import Path
from flint import arb, arb_mat
from magrod.generated import validated as gen
from magrod.proof import ball, fields, section_return as sr, taylor
from magrod.proof.fields import _Dual
from magrod.proof.kernel.schema import frac
from magrod.proof.provers.section_horseshoe import piece_geometry, set_data

ROOT = Path(__file__).resolve().parent.parent


def load(name: str):
    """(certificate, settings, exact parameters) of the shipped certificate `name`."""
    c = json.loads((ROOT / 'magrod' / 'proof' / 'certificates' / f'{name}.json').read_text())
    return c, c['settings'], fields.ExactParams(**{k: frac(v) for k, v in c['params'].items()})

def ext_field(pars):
    def rhs(y, _p):
        x = list(y[:4])
        out = list(gen.chart_rhs(x, pars))
        for k in (0, 1):
            u = y[4 + 4 * k: 8 + 4 * k]
            d = gen.chart_rhs([_Dual(a, b) for a, b in zip(x, u)], pars)
            out += [v.b if isinstance(v, _Dual) else 0 * y[0] for v in d]
        return out

    def jac(y, _p):
        x = list(y[:4])
        J = list(gen.chart_jacobian(x, pars))
        z = 0 * y[0]
        M = [[z] * 12 for _ in range(12)]
        for b in range(3):
            for i in range(4):
                for j in range(4):
                    M[4 * b + i][4 * b + j] = J[4 * i + j]
        for k in (0, 1):
            u = y[4 + 4 * k: 8 + 4 * k]
            H = gen.chart_jacobian([_Dual(a, bb) for a, bb in zip(x, u)], pars)
            for i in range(4):
                for j in range(4):
                    h = H[4 * i + j]
                    M[4 + 4 * k + i][j] = h.b if isinstance(h, _Dual) else z
        return [e for row in M for e in row]

    return taylor.Field(rhs, jac, 12, pars, "chart+variational")


captured = {}  # the piece's C^1 box set, caught where piece_return hands it to first_return
_real_first_return = sr.first_return


def capture_box(n: int) -> dict:
    """Hook first_return so that the C^1 box set of n states piece_return flies is kept in `captured`."""
    def grab(pars, fld, S, t_a, lead, **kw):
        if S.Wbar is not None and S.n == n and 'box' not in captured:
            captured['box'] = S
        return _real_first_return(pars, fld, S, t_a, lead, **kw)

    sr.first_return = grab
    return captured


def piece(c: dict, i: int):
    """(its record, c_X, A_X, the certificate's exact steps, the branch) of N_i's first piece."""
    cc, A = set_data(c['sets'][i])[:2]
    r = {int(f['set']): f for f in c['flights']}[i]['pieces'][0]
    cX, AX = piece_geometry(cc, A, [frac(v) for v in r['piece']])
    steps = {k: [[frac(x) for x in ph] for ph in r['steps'][k]] for k in ('thin', 'box')}
    return r, cX, AX, steps, c['sets'][i].get('branch', '0')


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    name = args[0] if args else "horseshoe_fig4a"
    I = int(args[1]) if len(args) > 1 else 12
    LINEAR_TANGENTS = '--linear-tangents' in sys.argv
    c, s, p = load(name)
    capture_box(4)
    with ball.workprec(int(s['prec']), int(s['series_cap'])):
        r, cX, AX, steps, br = piece(c, I)
        fld4 = fields.chart_field(p)
        t0 = time.perf_counter()
        f = sr.piece_return(p.balls(), frac(c['level']), fld4, cX, AX, frac(r['p_c']), frac(s['p_rad']), frac(r['t_a']),
                            frac(s['lead']), t1=frac(s['t1']), order=int(s['order']), steps=steps, newton=int(s['newton']),
                            thin_c1=False, branch=br)
        t_c1 = time.perf_counter() - t0
        S4 = captured['box']
        Q = S4.hull()
        tg = sr.tangents(p.balls(), Q)
        if LINEAR_TANGENTS:  # the tangents' last entry linear in the initial point (the Hessian of Hbar over the hull)
            from flint import arb_series
            pars = p.balls()

            def hess(xb):
                """Hessian of Hbar over the box xb (4 x 4 balls): a series in x_i (first derivative) of duals in x_k."""
                Hm = [[None] * 4 for _ in range(4)]
                for i in range(4):
                    for k in range(4):
                        y = [_Dual(arb_series([v, 1 if j == i else 0], prec=2), arb_series([1 if j == k else 0], prec=2))
                             for j, v in enumerate(xb)]
                        h = gen.chart_hamiltonian(y, pars)[0]
                        b = h.b if isinstance(h, _Dual) else arb_series([0], prec=2)
                        cs = b.coeffs() if isinstance(b, arb_series) else [b]
                        Hm[i][k] = cs[1] if len(cs) > 1 else arb(0)
                return Hm

            xc = [S4.xbar[i, 0] for i in range(4)]
            gQ = sr.ham_gradient(pars, Q)
            HQ = hess(Q)
            PPi, THi, PTi = fields.PPSI, fields.THETA, fields.PTHETA
            # t_th = (1, 0, 0, -H_th/H_pp), t_pt = (0, 0, 1, -H_pt/H_pp): the gradient of their last entry over Q
            def grad_ratio(a):
                return [-(HQ[a][k] * gQ[PPi] - gQ[a] * HQ[PPi][k]) / (gQ[PPi] * gQ[PPi]) for k in range(4)]
            G = {"th": grad_ratio(THi), "pt": grad_ratio(PTi)}
            tc = sr.tangents(pars, [ball.q(ball.fraction(v)) for v in xc])  # at the centre
            n0 = S4.C.ncols()
            C = arb_mat(12, n0)
            for i in range(4):
                for j in range(n0):
                    C[i, j] = S4.C[i, j]
            center = xc + [v.mid() for v in tc['th'] + tc['pt']]
            err = ball.column(S4.B * S4.r) + [v - v.mid() for v in tc['th'] + tc['pt']]
            for b, key in enumerate(("th", "pt")):
                row = 4 + 4 * b + PPi
                Gm = [g.mid() for g in G[key]]
                # last entry of t(x0) - t(xc) = G(xi) (x0 - xc), x0 - xc = C r0 + B r: G_mid C r0 in C, the rest in r
                for j in range(n0):
                    C[row, j] = sum((Gm[k] * S4.C[k, j] for k in range(4)), arb(0)).mid()
                Cr = ball.column(S4.C * S4.r0)
                Br = ball.column(S4.B * S4.r)
                lin = sum((C[row, j] * S4.r0[j, 0] for j in range(n0)), arb(0))
                full = sum((G[key][k] * (Cr[k] + Br[k]) for k in range(4)), arb(0))
                err[row] = err[row] + (full - lin)
            S = taylor.initial_set(center, c1=False)
            S.C, S.r0 = C, S4.r0
            S.r = ball.vec(err)
        else:
            u0 = tg['th'] + tg['pt']
            center = [S4.xbar[i, 0] for i in range(4)] + [v.mid() for v in u0]
            S = taylor.initial_set(center, c1=False)
            C = arb_mat(12, S4.C.ncols())
            for i in range(4):
                for j in range(S4.C.ncols()):
                    C[i, j] = S4.C[i, j]
            S.C, S.r0 = C, S4.r0
            err = ball.column(S4.B * S4.r) + [v - v.mid() for v in u0]
            S.r = ball.vec(err)
        print('initial tangents radii', [f"{float(S.r[i, 0].rad()):.1e}" for i in range(4, 12)])
        fld = ext_field(p.balls())
        t0 = time.perf_counter()
        allsteps = steps['box'][0] + steps['box'][1]
        from magrod.proof import taylor_model as tm
        rec = taylor.Trajectory()
        S = tm.propagate(fld, S, sum(allsteps), order=int(s["order"]), tol=float(s["tol"]), record=rec)
        print("extended flight steps", len(rec.steps), "against", len(allsteps))
        def g(y):
            return y[1].sin()
        def dg(y):
            return [arb(0), y[1].cos()] + [arb(0)] * 10
        cr = tm.cross_section(fld, S, g, dg, 2 * frac(s["lead"]), int(s["order"]))
        t_c2 = time.perf_counter() - t0
        y = cr.x
        fx = cr.fx[:4]
        gg = [arb(0), y[1].cos(), arb(0), arb(0)]
        gf = sum((a * b for a, b in zip(gg, fx)), arb(0))
        DP = []
        for k in (0, 1):
            u = y[4 + 4 * k: 8 + 4 * k]
            gu = sum((a * b for a, b in zip(gg, u)), arb(0))
            v = [ui - fi * gu / gf for ui, fi in zip(u, fx)]
            DP.append((v[0], v[2]))
        print('C1 [DP] radii', [[f"{float(x.rad()):.2e}" for x in row] for row in f['DP']], f'{t_c1:.1f} s (both flights)')
        print('C1 [DP] mids ', [[f"{float(x.mid()):.6f}" for x in row] for row in f['DP']])
        print('C0-variational [DP] radii (columns th, pt)', [[f"{float(x.rad()):.2e}" for x in col] for col in DP], f'{t_c2:.1f} s')
        print('C0-variational [DP] mids', [[f"{float(x.mid()):.6f}" for x in col] for col in DP])


if __name__ == "__main__":
    main()
