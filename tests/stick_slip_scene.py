"""The one stick/slip scene the tests generate: a braked free rotor (law = "torque", tau = tau0 < 0) with two
balls, rolling resistance and stiction.  A friction model with stiction takes minutes to generate, and every
value in the scene is a parameter of the model (eps, D, tau0, kappa, mu_r, mu_s ...), so the tests that need
such a model load this one, from the scene cache (`load_model(scene=...)`, the same bytes: generated once per
machine and generator), and set their own values with `model.params({...})`."""

from __future__ import annotations

from adbgen.analysis.loading import load_model

MU_R, MU_S, R, MASS = 0.02, 0.05, 0.05, 0.01
I_Z, TAU0 = 1e-3, -0.01
TORQUE_SCENE = f"""n = 2
rotor_mass = 1.0
eccentricity = 0.0
polar_inertia = {I_Z}
race_radius = {R}
ball_mass = {MASS}
ball_damping = 0.0
stiffness = 1000.0
damping = 1.0
rolling_resistance = {MU_R}
static_friction = {MU_S}
[speed]
law = "torque"
tau0 = {TAU0}
motor_slope = 0.0
"""


def braked_model(tmp_path_factory):
    """The scene's model (numba, C and AUTO-07p targets: the scene cache's), for a module-scoped fixture."""
    path = tmp_path_factory.mktemp("braked") / "braked.toml"
    path.write_text(TORQUE_SCENE)
    return load_model(scene=path)
