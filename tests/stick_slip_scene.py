"""The one stick/slip scene the tests generate: a braked free rotor (law = "torque", tau = tau0 < 0) with two
balls, rolling resistance and stiction.  A friction model with stiction takes a while to generate (36 s on the
shared machine), and every value in the scene is a parameter of the model (eps, D, tau0, kappa, mu_r, mu_s ...),
so the tests that need such a model load this one (the scene of `adbgen verify`'s stick/slip energy balance,
science/stick_slip_energy.py), from the scene cache (`load_model(scene=...)`, the same bytes: generated once per
machine and generator), and set their own values with `model.params({...})`."""

from __future__ import annotations

from adbgen.analysis.loading import load_model
from adbgen.families.single_plane.science.stick_slip_energy import I_Z, MASS, MU_R, MU_S, R, TAU0  # noqa: F401
from adbgen.families.single_plane.science.stick_slip_energy import SCENE as TORQUE_SCENE


def braked_model(tmp_path_factory):
    """The scene's model (numba, C and AUTO-07p targets: the scene cache's), for a module-scoped fixture."""
    path = tmp_path_factory.mktemp("braked") / "braked.toml"
    path.write_text(TORQUE_SCENE)
    return load_model(scene=path)
