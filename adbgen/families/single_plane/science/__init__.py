"""The single-plane family's science: what the thesis published and its recomputation on the generated
models.  These modules run generated code through the analysis layer (`adbgen.analysis`); the family's
derivation modules (one folder up) never import them.

    published        published numbers the commands compare with (thesis Fig. 5.4)
    reproduce        the thesis' chapters 4 and 5 in docs/reproduction.md (`REPRODUCTION`)
    coverage         the thesis' published results, ch. 3-5, and where the document recomputes each
    chapter3         ch. 3's critical speeds and balanced positions from the generated models
    starts           Figs. 5.1-5.3 (random rotor starts) and the named starts of Figs. 5.7, 5.9 explained
    plain            Figs. 5.12-5.14's rotor without balls beside the runs
    sweeps           the chapter-5 sweeps (Figs. 5.5-5.11, 5.19-5.25)
    sensitivity      the outcomes that hang on the tolerance (Fig. 5.10, every transient)
    periodic_orbits  the thesis' periodic orbits (`REPRODUCTION` "thesis-orbits")
    balanced         the balanced state's stability (one member and the n = 3 family)
    lyapunov         the largest Lyapunov exponent (Figs. 5.12-5.14 (b))
    templates        every section's Markdown as jinja2 templates (package data); the modules compute
    commands         `adbgen demo` (thesis Fig. 5.4 recomputed and plotted)
    stick_slip_energy  the energy balance over a run with stick and slip (a check of `adbgen verify`)
"""
