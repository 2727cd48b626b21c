"""The provenance of a certificate made before `magrod prove` recorded it: the command that produces a certificate
with its content, reconstructed from the certificate's own parameters and settings (and, for the horseshoes, its
design record), and the research script whose search or design it rests on.  Adds the field "provenance" as the
first key and changes nothing else (checked: the rest parses to the same JSON); a certificate that has one is left
alone.  The verifier reads no provenance (only its form), so every certificate verifies as before.

    python research/provenance.py CERT.json [CERT.json ...]

The shipped certificates' provenance was written by this script when provenance was introduced; `magrod prove`
writes its own ("recorded": "by magrod prove").
"""
from __future__ import annotations

import json
import shlex
import sys
from fractions import Fraction
from pathlib import Path

RECORDED = ("reconstructed from the certificate's own parameters and settings and the commands in "
            "docs/nonintegrability.md when provenance was introduced (not re-run)")


def _params(c) -> list:
    return [x for k in ("m", "mu", "gamma", "delta", "lam") for x in (f"--{k}", c["params"][k])]


def provenance(name: str, c: dict) -> dict:
    """{"command", "recorded"[, "design_script"]} of the certificate `c` whose file name is `name`."""
    s = c["settings"]
    kind = c.get("kind", "homoclinic")
    w = s.get("lam_rad", "0")
    wide = Fraction(w) != 0
    script = None
    if kind == "homoclinic":
        words = ["magrod", "prove", *_params(c), "--targets", ",".join(s["targets"])]
        if wide:
            words += ["--lam-rad", w]
            script = "research/homoclinic_interval.py"
    elif kind == "section_fixed_point":
        words = ["magrod", "prove", "--fixed-point", repr(round(c["float"]["theta"], 6)), "--level", c["level"],
                 *_params(c)]
        if c["point"].get("branch", "0") == "pi":
            words += ["--branch", "pi", "--root", "0"]
        if wide:
            words += ["--lam-rad", w]
        script = ("research/fig4_lambda_interval.py" if "_lam_" in name else
                  "research/fig5_candidates.py" if "fig5" in name else "research/fig4_candidates.py")
    else:
        d = c["design"]
        if wide:
            words = ["magrod", "prove", "--widen", name.replace("_interval", ""), "--lam-rad", w]
        else:
            design = {"horseshoe_fig4b.json": "fig4b", "horseshoe_fig4c.json": "fig4c"}.get(name, "fig4a")
            words = ["magrod", "prove", "--horseshoe", repr(float(Fraction(d["x0_theta"]))), "--level", c["level"],
                     *_params(c), "--design", design]
            if s.get("branch", "0") != "0" or s.get("root") is not None:
                words += ["--branch", s.get("branch", "0"), "--root", str(s.get("root", -1))]
            words += ["--m-back", str(s["m_back"]), "--n-exc", str(s["n_exc"]), "--s-star", repr(d["s_star"])]
            if s.get("passes"):
                words += ["--passes", ",".join(s["passes"])]
        base = name.replace("_interval", "").removesuffix(".json")
        script = {"horseshoe_fig4b": "research/fig4b_horseshoe_design.py",
                  "horseshoe_fig4c": "research/fig4c_horseshoe_design.py"}.get(
            base, "research/fig5_candidates.py" if "fig5" in name else "research/fig4_horseshoe_design.py")
    out = {"command": shlex.join(words), "recorded": RECORDED}
    if script:
        out["design_script"] = script
    return out


def add(path: Path) -> bool:
    """Write the provenance into the certificate at `path` (False: it has one already)."""
    text = path.read_text()
    c = json.loads(text)
    if "provenance" in c:
        return False
    prov = provenance(path.name, c)
    new = "{\n  \"provenance\": " + json.dumps(prov, sort_keys=True) + "," + ("" if text[1] == "\n" else "\n ") + \
        text[1:]
    again = json.loads(new)
    if again.pop("provenance") != prov or again != c:
        raise RuntimeError(f"{path.name}: the certificate's content would change")
    path.write_text(new)
    return True


if __name__ == "__main__":
    for a in sys.argv[1:]:
        print(f"{a}: {'provenance added' if add(Path(a)) else 'has its provenance'}")
