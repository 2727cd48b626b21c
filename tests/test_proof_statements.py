"""Every claim exactly as strong as its proof: the verdict is data (magrod/proof/statements.py), its
labels are computed from the chains, the docs and README blocks are rendered from it, and no "proved" or
"computer-verified" label is attached in README, docs or REPORT to a statement whose chain has a weak step."""
from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

from magrod.proof import statements as S
from magrod.proof.statements import Statement, Step

ROOT = Path(__file__).resolve().parents[1]


def _report_strings() -> str:
    """The prose of REPORT.md's rows: every string constant of figures/report.py (f-strings without their
    computed parts, so a label computed from the statements is not read as typed prose)."""
    tree = ast.parse((ROOT / "magrod/figures/report.py").read_text())
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.JoinedStr):
            out.append(" ".join(v.value for v in node.values if isinstance(v, ast.Constant)))
        elif isinstance(node, ast.Constant) and isinstance(node.value, str):
            out.append(node.value)
    return "\n\n".join(out)


def _texts() -> dict:
    files = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    out = {str(p.relative_to(ROOT)): p.read_text() for p in files}
    out["REPORT rows (magrod/figures/report.py)"] = _report_strings()
    return out


def test_statuses_follow_from_the_chains():
    got = {s.number: S.status(s.number) for s in S.STATEMENTS}
    # what the chains say: 3 rests on hypothesis H3, 4 and 7b on 3, 8 on theorems outside their
    # hypotheses, 10 on floating point; 7 on 5 plus the symbolic descent
    assert got == {"1": "proved", "2": "computer-verified", "3": "conditional", "4": "conditional",
                   "5": "computer-verified", "5a": "computer-verified", "6": "proved", "7": "computer-verified", "7b": "conditional",
                   "8": "heuristic", "9": "proved", "10": "numerical", "11": "computer-verified",
                   "12": "computer-verified", "13": "computer-verified"}


def test_a_weak_link_anywhere_weakens_the_statement(monkeypatch):
    extra = (Statement("90", "t", "x", (Step("a", "proved"), Step("b", ref="91"))),
             Statement("91", "t", "x", (Step("c", "computer-verified"), Step("d", ref="3"))))
    monkeypatch.setattr(S, "BY_NUMBER", {**S.BY_NUMBER, **{s.number: s for s in extra}})
    assert S.status("91") == "conditional" and S.status("90") == "conditional"
    loop = Statement("92", "t", "x", (Step("e", ref="92"),))
    monkeypatch.setattr(S, "BY_NUMBER", {**S.BY_NUMBER, "92": loop})
    with pytest.raises(ValueError, match="circular"):
        S.status("92")


@pytest.mark.parametrize("rel", sorted(S.BLOCKS))
def test_the_generated_blocks_are_fresh(rel):
    text = (ROOT / rel).read_text()
    found = S.blocks(text)
    want = {name: fn() for name, fn in S.BLOCKS[rel].items()}
    assert set(found) == set(want), f"{rel}: blocks {sorted(found)}, expected {sorted(want)}"
    for name in want:
        assert found[name] == want[name], (f"{rel}: block {name!r} is stale; run "
                                           "`python -m magrod.proof.statements --write`")


def test_no_strong_label_on_a_weak_statement_in_readme_docs_or_report():
    bad = {k: S.overclaims(v) for k, v in _texts().items()}
    bad = {k: v for k, v in bad.items() if v}
    assert not bad, bad


@pytest.mark.parametrize("sentence, flagged", [
    # the old Summary of docs/nonintegrability.md and the old enclosure verdict row
    ("**Summary.** Nonintegrability of the extensible magnetic rod is **computer-verified** at one parameter point "
     "(5, with 6 and the openness giving an open set of parameters and leaves), and near the perturbative regime "
     "it follows from a **computer-verified** non-zero coefficient (2) **conditional** on the formal expansion (3).",
     True),
    ("computer-verified: S < 0 at every case (the leading coefficient of the splitting is non-zero).", True),
    ("Statement 8 is proved by Lerman's theorem.", True),
    ("The saddle-centre picture is computer-verified.", True),
    ("Fig 4 is proved chaotic.", True),
    ("The 9-D rod is proved nonintegrable.", True),
    # ... and wording that says exactly what holds
    ("Statement 8 is heuristic; statement 5 is computer-verified.", False),
    ("Fig 4 on h = 0.9 is not proved.", False),
    ("S is computer-verified (statement 2); that it is the leading coefficient is conditional (statement 3).", False),
    ("For the 9-D rod none in involution with m3 (**computer-verified**).", False),
])
def test_the_label_check_catches_overclaims(sentence, flagged):
    assert bool(S.overclaims(sentence)) is flagged, S.overclaims(sentence)


def test_rewrite_replaces_only_the_block():
    a, b = S._markers("summary")
    text = f"before\n{a}\nold text\n{b}\nafter\n"
    new = S.rewrite(text, {"summary": lambda: "NEW"})
    assert new == f"before\n{a}\nNEW\n{b}\nafter\n" and S.blocks(new) == {"summary": "NEW"}
    with pytest.raises(ValueError, match="not found"):
        S.rewrite("no markers", {"summary": lambda: "x"})


# the statements' data is Unicode (what a terminal shows); what README and docs render is mathematics
_UNICODE_MATH = re.compile(r"[" + S._GREEK + "̄" + "".join(S._SUP) + r"≠∈≤≥≪≲≈⇒⇐→]|\b\w\^\w|\b[A-Za-z]_[a-z]\b")


@pytest.mark.parametrize("rel", sorted(S.BLOCKS))
def test_the_blocks_carry_their_mathematics_as_mathematics(rel):
    """README and the docs render the statements with myst's dollar math: no Greek letter, barred symbol,
    superscript, relation or ASCII exponent (W^u) is left as text outside $...$ and code.  Seen to fail before
    `markdown` (492 such places, W^u, λ̄ and H̄ among them)."""
    for name, block in S.blocks((ROOT / rel).read_text()).items():
        assert block.count("$") % 2 == 0, (rel, name)
        prose = re.sub(r"\$[^$\n]+\$", " ", re.sub(r"`[^`]*`", " ", block))
        left = [prose[max(0, m.start() - 30):m.end() + 10] for m in _UNICODE_MATH.finditer(prose)]
        assert not left, (rel, name, left[:10])
        assert re.search(r"\$W\^u\$", block) or name != "verdict"


@pytest.mark.parametrize("unicode, latex", [
    ("W^u and W^s", "$W^u$ and $W^s$"),
    ("independent of H̄ at λ̄ = 27/200", r"independent of $\bar H$ at $\bar\lambda = 27/200$"),
    ("(m, μ, γ, δ) = (17/10, 2/5, 3, 3)", r"$(m, \mu, \gamma, \delta) = (17/10, 2/5, 3, 3)$"),
    ("for every λ̄ in 1/100 ± 10⁻¹³", r"for every $\bar\lambda$ in 1/100 ± $10^{-13}$"),
    ("T ∈ [5.1, 5.2] (a)", r"$T \in [5.1, 5.2]$ (a)"),
    ("N0 ⇒ N1 ⇒ … ⇒ Nk", r"$N_{0} \Rightarrow N_{1} \Rightarrow \dots \Rightarrow N_{k}$"),
    ("at `magrod prove --lam 0.135` (λ̄)", r"at `magrod prove --lam 0.135` ($\bar\lambda$)"),
])
def test_markdown_writes_mathematics(unicode, latex):
    assert S.markdown(unicode) == latex


@pytest.mark.parametrize("sentence, flagged", [
    ("For ε small the splitting is proved.", True),
    ("For the 9-D rod none in involution with m3 (**computer-verified**).", False),
])
def test_the_label_check_reads_rendered_mathematics(sentence, flagged):
    """The phrases that name a statement ("ε small", "in involution with m3") are found in dollar math too, so the
    label check judges a rendered block ($\\varepsilon$, $m_3$) exactly as its Unicode."""
    assert S.markdown(sentence) != sentence
    assert bool(S.overclaims(S.markdown(sentence))) is bool(S.overclaims(sentence)) is flagged
