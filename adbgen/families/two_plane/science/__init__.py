"""The two-plane family's science: the paper's results (Rodrigues et al. 2011) recomputed on the generated
models through the analysis layer (`adbgen.analysis`); the family's derivation modules (one folder up)
never import these.

    exchange    section 3.2.3: the B/C3 stability exchange at the critical speeds
    runs        Figure 12(a) and the run-ups of section 6 (Figures 15, 16); the vibration measure A
    reproduce   the paper's sections of docs/reproduction.md (`REPRODUCTION`)
    stick_slip_energy  the energy balance over a run with stick and slip (a check of `adbgen verify`)
"""
