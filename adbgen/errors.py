"""Errors raised for bad input: each carries a one-line message naming what is wrong."""


class AdbgenError(Exception):
    """Base class of every error adbgen reports to a user."""


class SceneError(AdbgenError, ValueError):
    """An impossible or malformed scene; ``field`` names the offending entry."""

    def __init__(self, field: str, message: str):
        self.field = field
        super().__init__(f"scene.{field}: {message}")


class ReductionError(AdbgenError):
    """A reduction was asked of a model it does not apply to (e.g. rotating frame with anisotropy)."""
