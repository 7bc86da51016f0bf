"""adbgen: equations of motion of automatic dynamic balancers, derived, checked, emitted.

Data flows one way: scene -> symbolic model -> Lagrange -> reductions (checked) -> intermediate form
-> targets -> generated files.  `core` holds what every family shares, `families` the machines
(single-plane, two-plane; one registry), `codegen` the intermediate form, its lowering and the
targets (one registry), `cli` the command line assembled from both registries.
"""

__version__ = "0.1.0"

from .errors import AdbgenError, ReductionError, SceneError  # noqa: E402


def __getattr__(name: str):
    # the single-plane scene, as `adbgen.Scene` before the families had folders; loaded on first use
    if name in ("Scene", "SpeedLaw"):
        from .families.single_plane import scene

        return getattr(scene, name)
    raise AttributeError(f"module 'adbgen' has no attribute {name!r}")


__all__ = ["AdbgenError", "ReductionError", "Scene", "SceneError", "SpeedLaw", "__version__"]
