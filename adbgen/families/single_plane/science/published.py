"""Numbers the thesis prints for its transients (ch. 5), as printed: the one table the reproduction, the
`demo` command and the tests read.

Every run starts with x, y and their rates at 0 and the balls at rest in the rotating frame (unless a
row gives rates), parameters (5.1) (Omega = 4, zeta = beta = delta = 0.01, mu = 0.05) but for the row's
changes.  The thesis integrated with MATLAB's ode45 at its defaults (ch. 5; no tolerance is stated) and
took t_dec as the time after which r < 1e-3 ("if we consider that the balance is achieved when
r < 10^-3").
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

PI = math.pi


@dataclass(frozen=True)
class Transient:
    """One published run: where it is printed, the start, and its printed r_max and t_dec (None: not
    printed)."""

    figure: str
    n: int
    phi0: tuple[float, ...]
    phi0_text: str
    r_max: float | None
    t_dec: float | None
    params: dict = field(default_factory=dict)
    source: str = ""  # the section whose text prints the numbers


_S = "5.1.2"
_D = "5.2.2"
_O = "5.2.1"
EQUIDISTANT = {2: ((PI / 2, -PI / 2), "(pi/2, -pi/2)"),  # (5.3)-(5.5): section 5.2's starts
               3: ((PI / 3, -PI / 3, PI), "(pi/3, -pi/3, pi)"),
               4: ((PI / 2, -PI / 2, PI, 0.0), "(pi/2, -pi/2, pi, 0)")}

TRANSIENTS = (
    Transient("5.4(a)", 2, (PI / 2, -PI / 2), "(pi/2, -pi/2)", 0.0483, 462.42, source=_S),
    Transient("5.4(c)", 2, (3 * PI / 4, -3 * PI / 4), "(3pi/4, -3pi/4)", 0.2878, 745.02, source=_S),
    Transient("5.4(d)", 2, (0.0, PI), "(0, pi)", 0.0478, 549.93, source=_S),
    Transient("5.6(a)", 3, (PI / 2, -PI / 2, PI), "(pi/2, -pi/2, pi)", 0.1806, 1090.40, source=_S),
    Transient("5.6(b)", 3, (PI / 4, -PI / 4, PI), "(pi/4, -pi/4, pi)", 0.1285, 714.47, source=_S),
    Transient("5.6(c)", 3, (3 * PI / 4, -3 * PI / 4, 0.0), "(3pi/4, -3pi/4, 0)", 0.0450, 901.88, source=_S),
    Transient("5.6(d)", 3, (0.0, PI, PI / 2), "(0, pi, pi/2)", 0.2278, 1330.20, source=_S),
    Transient("5.8(a)", 4, (PI / 2, -PI / 2, PI, 0.0), "(pi/2, -pi/2, pi, 0)", 0.0444, 495.87, source=_S),
    Transient("5.8(b)", 4, (PI / 4, -PI / 4, PI, PI), "(pi/4, -pi/4, pi, pi)", 0.0810, 567.48, source=_S),
    Transient("5.8(c)", 4, (3 * PI / 4, -3 * PI / 4, 0.0, 0.0), "(3pi/4, -3pi/4, 0, 0)", 0.1768, 708.36, source=_S),
    Transient("5.8(d)", 4, (PI / 4, -PI / 4, 3 * PI / 4, -3 * PI / 4), "(pi/4, -pi/4, 3pi/4, -3pi/4)", 0.0444,
              485.04, source=_S),
    *(Transient(f"5.{11 + n - 1}(c)", n, *EQUIDISTANT[n], r, t, {"Omega": 20.0}, _O)
      for n, r, t in ((2, 0.1940, 567.89), (3, 0.1903, 722.13), (4, 0.1855, 603.44))),
    *(Transient(f"5.{15 + n - 2}(b)", n, *EQUIDISTANT[n], r, t, {"beta": 0.25}, _D)
      for n, r, t in ((2, 0.0447, 406.21), (3, 0.0421, 421.82), (4, 0.0429, 437.60))),
    *(Transient(f"5.{15 + n - 2}(c)", n, *EQUIDISTANT[n], r, t, {"zeta": 0.25, "beta": 0.25}, _D)
      for n, r, t in ((2, 0.0315, 15.76), (3, 0.0325, 32.47), (4, 0.0323, 41.42))),
)

# Fig. 5.4 as `adbgen demo` shows it: panel -> (phi(0), (r_max, t_dec))
FIGURE_5_4 = {t.figure[4]: (t.phi0, (t.r_max, t.t_dec)) for t in TRANSIENTS if t.figure.startswith("5.4")}


def printed_half_unit(value: float) -> float:
    """Half a unit in the last printed digit of a number printed with two decimals or four significant
    digits (the thesis prints t_dec as 462.42, r_max as 0.0483): the tolerance "to the printed digits"."""
    text = f"{value:.2f}" if value >= 1 else f"{value:.4f}"
    decimals = len(text.split(".")[1])
    return 0.5 * 10.0 ** -decimals
