"""Model names (`core.names`: the rules live with the model specs, below code generation and the
command line, which both check names)."""

from ..core.names import C_KEYWORDS, RESERVED_NAMES, ModelNameError, name_problem, validate_name

__all__ = ["C_KEYWORDS", "RESERVED_NAMES", "ModelNameError", "name_problem", "validate_name"]
