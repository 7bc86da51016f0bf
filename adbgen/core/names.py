"""Model names: one name is a Python module (`generated.<name>`), a C prefix (`<name>_rhs`), a folder and
AUTO-07p's equation name, so it must be valid, and harmless, as all of them at once."""

from __future__ import annotations

import builtins
import keyword
import re
import sys

from ..errors import AdbgenError

# C99 keywords (and the few C11 ones a compiler may treat as such)
C_KEYWORDS = frozenset("""
auto break case char const continue default do double else enum extern float for goto if inline int long
register restrict return short signed sizeof static struct switch typedef union unsigned void volatile while
_Bool _Complex _Imaginary _Alignas _Alignof _Atomic _Generic _Noreturn _Static_assert _Thread_local
""".split())
# the output package itself, and names the generated files already use for themselves
RESERVED_NAMES = frozenset({"generated", "auto"})
_C_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


class ModelNameError(AdbgenError, ValueError):
    pass


def name_problem(name: str) -> str | None:
    """Why `name` cannot name a model, or None when it can."""
    if not isinstance(name, str) or not _C_IDENTIFIER.match(name):
        return "not a C identifier and Python module name (ASCII letters, digits and _, not starting with a digit)"
    if keyword.iskeyword(name) or keyword.issoftkeyword(name):
        return "a Python keyword"
    if name in C_KEYWORDS:
        return "a C keyword"
    if name in dir(builtins):
        return "a Python builtin"
    if name in sys.stdlib_module_names or name in sys.builtin_module_names:
        return "a Python standard-library module name"
    if name in RESERVED_NAMES:
        return "reserved (the output package or its AUTO-07p folder)"
    if name.startswith("__"):
        return "reserved (dunder names belong to Python)"
    return None


def validate_name(name: str) -> str:
    """`name`, or ModelNameError saying why it cannot name a model."""
    problem = name_problem(name)
    if problem is not None:
        raise ModelNameError(f"model name {name!r}: {problem}")
    return name
