"""Machine-written by derive/ (python -m derive) -- DO NOT EDIT BY HAND.

Modules: body, first_integrals, floquet, generic_splitting, homoclinic, integrals, melnikov, names, reduced, scalars, splitting, splitting_ball, symmetry, validated; report.json / report.md: the derivation report."""
