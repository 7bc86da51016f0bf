"""The lanes target's printer: the C printer with every math function called through `adb_<name>`."""

from __future__ import annotations

from ..c.printer import CPrinter


class LanesPrinter(CPrinter):
    """C99 as the C target prints it, but sin(x) -> adb_sin(x), pow -> adb_pow, ...: the includer
    defines them on `adb_lanes` (vector math where it exists, lane by lane otherwise)."""

    _ns = "adb_"
