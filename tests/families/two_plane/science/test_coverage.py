"""The two-plane paper's coverage rows (issue 36): every covered row names a heading its section writes, every
paper chart has its row, the rows not covered say why."""

import re
from pathlib import Path

from adbgen.families.two_plane.charts import CHARTS
from adbgen.families.two_plane.science import coverage, periodic_orbits, reproduce

SCIENCE = Path(reproduce.__file__).parent


def _headings() -> set[str]:
    """The headings the two sections write: literal '### ...' lines of the sources and templates, and the
    charts' '#### Fig. X' (one per CHARTS entry)."""
    text = "\n".join(p.read_text() for p in [*SCIENCE.glob("*.py"), *SCIENCE.glob("prose/*.md.j2")])
    found = {m.group(1) for m in re.finditer(r'#{3,4} ([^"\n]+?)(?:", ""|$)', text, re.M)}
    return found | {f"Fig. {c.figure}" for c in CHARTS}


def test_every_covered_row_names_a_heading_of_its_section():
    headings = _headings()
    rows = coverage.SECTION + coverage.ORBITS
    assert all(r.where in headings for r in rows if r.covered)
    assert all(r.reason for r in rows if not r.covered)
    # negative control: a planted heading that no section writes is not found
    assert "Section 9: a heading nobody writes" not in headings


def test_the_sections_carry_their_rows_and_every_chart_is_listed():
    assert reproduce.REPRODUCTION.coverage == coverage.SECTION
    assert periodic_orbits.REPRODUCTION.coverage == coverage.ORBITS
    charts = {r.item.split(" (")[0] for r in coverage.ORBITS}
    assert {f"Fig. {c.figure}" for c in CHARTS} <= charts
    assert {"Fig. 10(b)", "Fig. 10(c)"} <= charts
    balanced = [r for r in coverage.SECTION if "balanced operation" in r.item]
    assert len(balanced) == 1 and not balanced[0].covered
