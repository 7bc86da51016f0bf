"""Argument types and the usage error shared by every command group of the command line."""

from __future__ import annotations

import argparse
import math

from .errors import AdbgenError


class UsageError(AdbgenError):
    """Bad command-line use: reported as one line, exit status 2."""


def _whole(text: str, what: str, least: int = 1) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if value < least:
        raise argparse.ArgumentTypeError(f"{what}must be at least {least}, got {value}")
    return value


def positive_int(text: str) -> int:
    """A number of balls (--n)."""
    return _whole(text, "n ")


def count(text: str) -> int:
    """A whole number >= 1 (--workers, --max-steps, ...)."""
    return _whole(text, "")


def branch_points(text: str) -> int:
    """A number of points of a continued branch (--max-points): at least 2, its start and one more."""
    return _whole(text, "", least=2)


def finite(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return value


def model_name(text: str) -> str:
    """A model name usable as a Python module, a C prefix and a folder (`core.names`)."""
    from .core.names import name_problem

    problem = name_problem(text)
    if problem:
        raise argparse.ArgumentTypeError(f"{text!r}: {problem}")
    return text
