"""The parameters of the thesis' ch. 4 diagrams: mu = 0.05, zeta = beta = delta = 0.01 (Fig. 4.1, 4.5, 4.10)."""

CH4 = {"mu": 0.05, "zeta": 0.01, "beta": 0.01, "delta": 0.01}
