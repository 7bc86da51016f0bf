"""The symbols every family shares: time, and symbols with the assumptions a derivation relies on.

One time symbol for every model, so that forms of different families (the two-plane rotor's
single-plane limit against the single-plane model) compare term by term.
"""

from __future__ import annotations

import sympy as sp

t = sp.Symbol("t", real=True)


def positive(name: str) -> sp.Symbol:
    return sp.Symbol(name, positive=True)


def nonnegative(name: str) -> sp.Symbol:
    return sp.Symbol(name, nonnegative=True)
