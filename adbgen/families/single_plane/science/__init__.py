"""The single-plane family's science: what the thesis published and its recomputation on the generated
models.  These modules run generated code through the analysis layer (`adbgen.analysis`); the family's
derivation modules (one folder up) never import them.

    published   published numbers the commands compare with (thesis Fig. 5.4)
    reproduce   the thesis' chapters 4 and 5 in docs/reproduction.md (`REPRODUCTION`)
    commands    `adbgen demo` (thesis Fig. 5.4 recomputed and plotted)
"""
