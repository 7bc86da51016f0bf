"""The two-plane orbits section's words (prose/orbits.md.j2, prose/chart.md.j2) against the committed
docs/reproduction.md: each table's cells and each computed phrase are read off the committed page and rendered
through the templates, which must give the page's lines exactly; the numbers are the page's, the words the
templates', so a changed word fails here (the negative control plants one)."""

import re
from pathlib import Path

from adbgen.families.two_plane.science import periodic_orbits as po
from adbgen.families.two_plane.science import prose
from template_checks import changed_template

ROOT = Path(__file__).resolve().parents[5]
DOC = (ROOT / "docs" / "reproduction.md").read_text().split("\n")
START = DOC.index("## Periodic orbits and stability charts of the two-plane balancer (paper sections 4, 5)")
SECTION = DOC[START:]


def _table(header):
    """The cells of the first table whose header starts with `header`."""
    i = next(k for k, line in enumerate(SECTION) if line.startswith(header)) + 2
    rows = SECTION[i:SECTION.index("", i)]
    return [[c.strip() for c in line.strip("|").split("|")] for line in rows]


def _head():
    crit = [row[:4] + [row[4].strip("*")] for row in _table("| eps/R + chi")]
    def inner(cell):  # "(3.386, 7.081, stable)" -> ("3.386", "7.081", True): the template words the verdict
        omega, period, stability = re.findall(r"\((.*)\)", cell)[0].split(", ")
        assert stability in ("stable", "unstable")
        return omega, period, stability == "stable"
    near = [{"paper": inner(r[1]), "ours": inner(r[2]), "distance": r[3]} for r in _table("| inset")]
    orbits = next(line for line in SECTION if "orbits by `continue --orbits`" in line)
    n, end = re.match(r"(\d+) orbits by `continue --orbits` \((.*)\);", orbits).groups()
    stable = next(line for line in SECTION if line.startswith(("Stable for Omega", "No stable cycles")))
    stable = re.findall(r"\[(.*)\]", stable)[0].split(", ") if stable.startswith("Stable") else None
    specials = _table("| kind | Omega | period")
    n1, n2 = re.search(r"\(grid (\d+) x (\d+),", next(x for x in SECTION if x.startswith("Each chart"))).groups()
    return prose.render("orbits", criticality=crit, n_orbits=n, end=end, near=near, stable=stable, specials=specials,
                        n1=n1, n2=n2) + [""]


def _summary(text):
    """The values of a chart's summary sentence on the page (what chart_summary computes)."""
    assert text.endswith(".")
    first, *parts = text[:-1].split("; ")
    found, size, stable = re.fullmatch(r"B found at (\d+) of (\d+) grid points, stable at (\d+)", first).groups()
    out = {"found": found, "size": size, "stable": stable, "missing": 0, "absent": 0, "rows": [], "certified": None,
           "lows": []}
    for part in parts:
        if m := re.fullmatch(r"(\d+) grid point\(s\) not computed \(a failure, drawn as x\), (\d+) where B does not "
                             r"exist", part):
            out["missing"], out["absent"] = m.groups()
        elif m := re.fullmatch(r"at the (\w+) imbalance \((.*?)\) stable for Omega in (.*)", part):
            out["rows"].append(dict(zip(("what", "imbalance", "windows"), m.groups())))
        elif m := re.fullmatch(r"certified: every stable window wider than (\S+) in Omega along a row and (\S+) in "
                               r"log10 eps/R along a column is found", part):
            out["certified"] = m.groups()
        else:
            lows = re.fullmatch(r"curves reaching the smallest imbalance at Omega = (.*)", part)
            out["lows"] = lows.group(1).split(", ")
    return out


def _chart(case):
    block = SECTION[SECTION.index(f"#### Fig. {case.figure}"):]
    block = block[:block.index(next(x for x in block if x.startswith(f"![Fig. {case.figure}]"))) + 1]
    ours = block[4]
    head = f"Ours ({case.model}{'; ' + case.note if case.note else ''}; ties: `{' '.join(case.ties)}`): "
    assert ours.startswith(head)
    curves, summary = ours[len(head):].split("; ", 1)
    extra = None
    if case.figure in po.EXTRA_CURVES:
        words = next(x for x in block if x.startswith("The chart draws"))
        changes = re.search(r"changes, (\d+) of Fig\. .*'s and (\d+) of Fig", words).groups()
        found = next(x for x in block if x.startswith(("Extra Hopf points at", "**No extra")))
        extra = {"top": f"{case.range1[1]:g}", "bottom": f"{case.range1[0]:g}", "control": po.EXTRA_CURVES[case.figure],
                 "changes_control": changes[0], "changes": changes[1],
                 "rows": [x.strip("|").strip().split(" | ") for x in block if re.match(r"\| \d", x)],
                 "extra": (re.findall(r"Extra Hopf points at (.*): the", found)[0].split(", ") if found[0] == "E"
                           else [])}
    limit = [x for x in block if x.startswith("As the imbalance vanishes")]
    limit = re.findall(r"left out\) at: (.*)\.$", limit[0])[0].split("; ") if limit else None
    if limit:  # "eps/R = 1e-06: hopf 1.00000, fold 2.00000" -> (1e-06, [("hopf", 1.0), ("fold", 2.0)])
        limit = [(float(eps), [] if points == "none" else [(k, float(v)) for k, v in
                                                             (p.split(" ") for p in points.split(", "))])
                 for eps, points in (item.removeprefix("eps/R = ").split(": ") for item in limit)]
    curves = [] if curves == "no curve" else [re.fullmatch(r"(\d+) (\w+) curve\(s\) of B's stability boundary", c)
                                              .groups() for c in curves.split(", ")]
    return prose.render("chart", figure=case.figure, text=case.text, model=case.model, note=case.note,
                        ties=case.ties, curves=curves,
                        summary=_summary(summary),
                        extra=extra, limit=limit, image=re.findall(r"@FIGURES@/(.*)\)", block[-1].replace(
                            "reproduction/", "@FIGURES@/"))[0]) + [""]


def _rendered():
    lines = _head()
    for case in po.CHARTS:
        lines += _chart(case)
    return "\n".join(lines).replace("@FIGURES@", "reproduction").split("\n")


def test_orbits_section_equals_the_committed_page():
    lines = _rendered()
    assert len(lines) > 100
    assert lines == SECTION[:len(lines)] and SECTION[len(lines):] in ([], [""])


def test_a_changed_template_word_is_caught(tmp_path, monkeypatch):
    """Negative control: one word of chart.md.j2 changed, the page's numbers no longer give the page."""
    with changed_template(prose, "chart.md.j2", "broken symmetry", "broken symmetries", tmp_path, monkeypatch):
        lines = _rendered()
        assert lines != SECTION[:len(lines)]
