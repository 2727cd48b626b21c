"""Where a horseshoe certificate's covering margin (a') goes (Fig 5(b)'s thin N8 => N9 margin).

For every link N_i => N_j and piece X of N_i, the image in N_j's coordinates is enclosed by the mean-value form
(section_horseshoe.image_in)
    y_s in off_s + G_su [-1, 1] + G_ss [-1, 1],      1 - max |y_s| = (a') margin,
with off = A_j^-1 (P(c_X) - c_j) the centre's offset, G = A_j^-1 [DP(X)] A_X.  The design maps frame to frame, so
mid(G_su) ~ 0 and G_ss ~ 1 / qs; what is left of (a') after the linear part 1 - |G_ss| is spent on |off_s| and on
the radii, chiefly rad(G_su) ~ rad([DP]) * l_X / w_j: the width of the C^1 enclosure times the aspect ratio of the
exit half-length of X to the entry half-width of N_j.  This script reads the PROVER's stored enclosures
(flights[].pieces[].enclosures: P(c_X), [DP(X)]); the verifier recomputes its own, of the same size.  Float
output, a diagnosis, not part of any proof.

    python research/horseshoe_margins.py [CERT.json] [out.json]

An interval certificate (settings.lam_rad = W, sets moving along v_j) has one more term, the verifier's
A_j^-1 (dP/ds - v_j) [-W, W] ("lambdabar"): at Fig 4(a)'s W = 2e-11 it is 0.278 of N12 => N13's 0.29 margin, all
of it from the radius of the box's dP/ds enclosure (2.2e-4, 1.5e-4; the mismatch of its midpoint with v_13 gives
3.7e-5 of y_s), which is what stops the interval (research/README.md, "dp_enclosure_width.py").

Stored run (horseshoe_margins.json, Fig 5(b), < 1 s; the sums reproduce the certificate's own link_margins to
<= 7e-4, conservatively): (a') = 0.016 at N8 => N9 is 1 - 0.333 (|G_ss|, the design's 1/qs) - 0.012 (its radius)
- 0.639 (G_su) - 8.5e-5 (off_s).  On the saddle's returns (N0 .. N9, 634-644 steps) rad([DP]) is proportional to the
set's size, ~1.3e7 l (4.8e-2 at N0's l = 3.8e-9, 1.9-2.4e-2 at l = 1.9e-9), against 2e4 l - 5e5 l on the excursion's
N10 .. N13 (why the saddle's returns are so much wider was not isolated; x0 lies at theta = 3.023, near the
chart's theta = pi).  Along N3 .. N10 the entry half-widths shrink by 2.2 per link (w9 = 1.56e-11 against l8 =
1.90e-9: aspect ratio 122), so G_su ~ rad([DP]) l / w grows from 0.005 (N2 => N3) to 0.639 (N8 => N9); at
N9 => N10 the ratio is 302 but rad([DP]) is 3.6x smaller (0.136).  Cutting N7 .. N9 into pieces along the exit
direction divides G_su by the number of pieces (as at Fig 4(b)'s N16); not needed: 0.016 is a strict inequality in
ball arithmetic, re-checked by the verifier's own enclosures.
"""
from __future__ import annotations

import json
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
from flint import arb

from magrod.proof.provers import section_horseshoe

ROOT = Path(__file__).resolve().parent.parent
DEFAULT = ROOT / "magrod" / "proof" / "certificates" / "horseshoe_fig5b.json"


def _ball(d: dict) -> arb:
    q = Fraction(d["mid"])
    return arb(q.numerator) / arb(q.denominator) + arb(0, float(Fraction(d["rad"])))


def _set(s: dict):
    return [Fraction(x) for x in s["c"]], [[Fraction(x) for x in r] for r in s["A"]]


def _abs_hi(x: arb) -> float:
    return float(abs(x.mid()) + x.rad())


def decompose(cert: dict) -> list[dict]:
    """One row per (link, piece): the parts of (a') as floats (see the module docstring)."""
    sets = [_set(s) for s in cert["sets"]]
    w = Fraction(cert["settings"].get("lam_rad", "0"))  # an interval certificate's sets move with lambdabar
    rows = []
    for fl in cert["flights"]:
        i = int(fl["set"])
        for src, j in cert["links"]:
            if src != i:
                continue
            for n, pr in enumerate(fl["pieces"]):
                e = pr["enclosures"]
                f = {"Pc": [_ball(x) for x in e["Pc"]], "DP": [[_ball(x) for x in r] for r in e["DP"]]}
                piece = [Fraction(x) for x in pr["piece"]]
                _, AX = section_horseshoe.piece_geometry(*sets[i], piece)
                off, G = section_horseshoe.image_in(sets[j], f, AX)
                lam_s = 0.0
                if w and "dPds" in e:  # a lambdabar interval: + A_j^-1 (dP/ds - v_j) [-w, w] (the verifier's term)
                    vj = [Fraction(x) for x in cert["sets"][j]["v"]]
                    d = [(_ball(e["dPds"][a]) - arb(vj[a].numerator) / arb(vj[a].denominator))
                         * arb(0, float(w)) for a in range(2)]
                    Ai = np.linalg.inv(np.array(sets[j][1], float))
                    lam_s = float(abs(Ai[1][0]) * _abs_hi(d[0]) + abs(Ai[1][1]) * _abs_hi(d[1]))
                DP = [x for r in f["DP"] for x in r]
                AXf, Aj = np.array(AX, float), np.array(sets[j][1], float)
                gss = G[1][1]
                rows.append({"link": f"N{i} => N{j}", "piece": n, "n_steps": int(pr["n_steps"]),
                             "dp_rad": max(float(x.rad()) for x in DP),
                             "dp_rel_rad": max(float(x.rad()) for x in DP) / max(abs(float(x.mid())) for x in DP),
                             "aspect_lX_over_wj": float(np.linalg.norm(AXf[:, 0]) / np.linalg.norm(Aj[:, 1])),
                             "off_s": _abs_hi(off[1]), "G_su": _abs_hi(G[1][0]), "G_ss_mid": float(abs(gss.mid())),
                             "G_ss_rad": float(gss.rad()), "lam_s": lam_s,
                             "a_margin": 1 - _abs_hi(off[1]) - _abs_hi(G[1][0]) - _abs_hi(gss) - lam_s})
    return rows


def main(argv: list[str]) -> None:
    smoke = "--smoke" in argv  # benchmarks/smoke.py: the same diagnosis, written into a temporary directory
    argv = [a for a in argv if a != "--smoke"]
    path = Path(argv[0]) if argv else DEFAULT
    out = Path(argv[1]) if len(argv) > 1 else Path(__file__).with_suffix(".json")
    if smoke:
        import tempfile

        out = Path(tempfile.mkdtemp(prefix="magrod-smoke-")) / out.name
    cert = json.loads(path.read_text())
    rows = decompose(cert)
    for r in rows:
        print(f"{r['link']:>10} piece {r['piece']}: (a') {r['a_margin']:.4f} = 1 - |G_ss| {r['G_ss_mid']:.3f} "
              f"- rad {r['G_ss_rad']:.3f} - G_su {r['G_su']:.3f} - off_s {r['off_s']:.1e}"
              + (f" - lambdabar {r['lam_s']:.3f}" if r["lam_s"] else "") + "   "
              f"rad[DP] {r['dp_rad']:.1e} (/|DP| {r['dp_rel_rad']:.1e}), l_X/w_j {r['aspect_lX_over_wj']:.1f}, {r['n_steps']} steps")
    out.write_text(json.dumps({"certificate": path.name, "rows": rows}, indent=1) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:])
