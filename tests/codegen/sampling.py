"""Random inputs for comparing generated code with its references (numba, C, symbolic)."""

import numpy as np


def random_inputs(module, n_samples: int, seed: int):
    """Random states (angles on the whole circle) and parameters (0.5x to 2x the defaults)."""
    rng = np.random.default_rng(seed)
    nq = module.N_STATES // 2
    y = np.empty((n_samples, module.N_STATES))
    y[:, :nq] = rng.uniform(-0.5, 0.5, (n_samples, nq))
    for k, name in enumerate(module.STATE_NAMES[:nq]):
        if name.startswith("phi_"):
            y[:, k] = rng.uniform(-np.pi, np.pi, n_samples)
    y[:, nq:] = rng.uniform(-1.0, 1.0, (n_samples, nq))
    p = module.DEFAULTS * rng.uniform(0.5, 2.0, (n_samples, module.DEFAULTS.size))
    t = rng.uniform(0.0, 10.0, n_samples)
    return t, y, p
