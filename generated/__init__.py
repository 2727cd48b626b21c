"""Machine-written by derive/ (python -m derive) -- DO NOT EDIT BY HAND.

Modules: body, reduced; report.json / report.md: the derivation report."""
