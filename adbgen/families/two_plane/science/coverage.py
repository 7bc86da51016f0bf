"""Which of the two-plane paper's published results (Rodrigues et al. 2011) docs/reproduction.md recomputes: a
`Coverage` row per figure or equation with a published result, naming the heading that recomputes it or saying
why it is not recomputed there (the table at the top of the document; issue 36).

    SECTION    the rows of the `two-plane` section (reproduce.py)
    ORBITS     the rows of the `two-plane-orbits` section (periodic_orbits.py, the charts of charts.CHARTS)
"""

from __future__ import annotations

from ....analysis.reproduction import Coverage
from ..charts import CHARTS

EXCHANGE = "Section 3.2.3: B and C3 exchange stability at the critical speeds"
FIG5A = "Section 3.2, Figure 5(a): the balanced state's further Hopf points"
FIG12A = "Section 4.2, Figure 12(a): brute-force diagram, anisotropic supports"
FIG12B = "Section 4.2, Figure 12(b): dynamic imbalance"
RUNUPS = "Section 6: run-ups (Figures 15, 16)"
CRITICALITY = "Criticality of the Hopf point of Fig. 14(a)"
FIG14CD = "Fig. 14(c, d): the limit cycles born there"
VERIFIED = "checked by `adbgen verify` (row {row}), not recomputed in this document"


def _paper(chapter: str, item: str, where: str = "", reason: str = "") -> Coverage:
    return Coverage("paper", chapter, item, not reason, where=where, reason=reason)


SECTION = (
    _paper("3", "Fig. 4 (the steady states B, C1-C3)", reason=VERIFIED.format(row="'steady states (28)'")
           + "; a schematic, no number"),
    _paper("3", "Fig. 5(a) (unfolding of the pitchfork in m, static imbalance)", FIG5A),
    _paper("3", "Fig. 5(b) (the same with misalignment chi = 0.001)",
           reason="not recomputed: the unfolding with chi is compared with its normal form by `adbgen verify` "
                  "(row 'Figure 9'); no number is printed for it"),
    _paper("3.1", "Fig. 6 (the symmetry group D4)", reason=VERIFIED.format(row="'D4 equivariance'")
           + "; a diagram, no number"),
    _paper("3.2.2-3.2.3", "(11), Fig. 7 (kappa, the exchange at Omega_cyl = 1 and Omega_con = 1.81)", EXCHANGE),
    _paper("3.2.3", "Fig. 8 (normal-form diagrams of (20))",
           reason=VERIFIED.format(row="'normal form (20) vs (32), (36)-(38)'") + "; the normal form's own diagrams"),
    _paper("3.3", "Fig. 9 (normal form against the full system, misalignment)",
           reason=VERIFIED.format(row="'Figure 9'")),
    _paper("4.1.2", "(42) critical speeds 0.89, 4.07",
           reason=VERIFIED.format(row="'Omega_cyl (42)', 'Omega_con (42)'") + " (0.888739, 4.071091)"),
    _paper("4.2", "(43) critical speeds 1, 1.65, 2.24, 3.79", FIG12A),
    _paper("4.2", "Fig. 12(a) (brute force, static imbalance)", FIG12A),
    _paper("4.2", "Fig. 12(b) (brute force, dynamic imbalance)", FIG12B),
    _paper("6", "Fig. 15(a) (ramp, c_b/m = 0.01: stall)", RUNUPS),
    _paper("6", "Fig. 15(b) (ramp, c_b/m = 0.1: stall and resynchronisation)", RUNUPS),
    _paper("6", "Fig. 15(b) (\"eventually this leads to balanced operation\")",
           reason="our run of the ramp ends with the two balls of each race together to the last bit (an unstable "
                  "state held by the exact symmetry, also from a start 1e-6 rad off opposite); balanced only after a "
                  "perturbation or with balls unequal to 1e-6 (" + RUNUPS + ")"),
    _paper("6", "Fig. 16(a-h) (Hill run-up (45); \"around t = 800\")", RUNUPS),
    _paper("6", "Fig. 16(d) (ABB worse than the plain rotor at the critical speeds)", RUNUPS),
)

CHAPTERS = {"10(a)": "4.1.1", "10(b)": "4.1.1", "10(c)": "4.1.2", "11": "4.2"}  # the rest: section 5

ORBITS = tuple(_paper(CHAPTERS.get(c.figure, "5"), f"Fig. {c.figure} (stability chart)", f"Fig. {c.figure}")
               for c in CHARTS) + (
    _paper("5", "Fig. 14(a) Hopf point: supercritical at eps/R + chi = 0.01, subcritical at 1e-4", CRITICALITY),
    _paper("5", "Fig. 14(c, d) (limit cycles from the Hopf point; insets (i)-(iii))", FIG14CD),
)

__all__ = ["ORBITS", "SECTION"]
