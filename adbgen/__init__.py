"""adbgen: equations of motion of automatic dynamic balancers, derived, checked, emitted.

Data flows one way: scene -> symbolic model -> Lagrange -> reductions (checked) -> intermediate form.
"""

__version__ = "0.1.0"

from .errors import AdbgenError, ReductionError, SceneError  # noqa: E402
from .scene import Scene, SpeedLaw  # noqa: E402

__all__ = ["AdbgenError", "ReductionError", "Scene", "SceneError", "SpeedLaw", "__version__"]
