"""How the lanes target writes statements: the C dialect on `adb_lanes` vectors."""

from __future__ import annotations

import re
from dataclasses import dataclass

from ..c.dialect import CDialect

_STORE = re.compile(r"^(\w+\[[^\]]*\]) = (.*)$")


@dataclass(frozen=True)
class LanesDialect(CDialect):
    """CDialect with ctype adb_lanes.  GCC's vector types take a scalar in arithmetic (broadcast) but not
    in an initialisation or a plain store, so every defined value and every output store goes through
    adb_splat (x - 0: exact for every x, -0 included, and folded away on vectors)."""

    ctype: str = "adb_lanes"

    def let(self, name: str, value: str, mutable: bool = False) -> str:
        return super().let(name, f"adb_splat({value})", mutable)

    def stmt(self, text: str) -> str:
        m = _STORE.match(text)
        if m and m.group(1).startswith(self.out + "["):
            text = f"{m.group(1)} = adb_splat({m.group(2)})"
        return super().stmt(text)
