"""The thesis sections' prose in templates (templates/*.md.j2, issue 33 item 6): each rendered from the inputs
that produced the committed docs/reproduction.md gives its lines exactly, so a change of a template's words
fails here; a planted wrong input is caught (negative control)."""

from pathlib import Path

from adbgen.families.single_plane.science import reproduce

ROOT = Path("docs")


def _basin(panel, zeta, balanced, counts, **more):
    return {"panel": panel, "zeta": zeta, "balanced": balanced, "counts": counts,
            "figure": ROOT / "reproduction" / f"fig5_{'18' if 'inline_share' in more else '19'}{panel}.png", **more}


FIG_5_18 = [_basin("a", 0.01, 0.946, {"balanced 1": 1514, "coincident 2-": 37, "limit cycle": 49}, inline_share=0.4),
            _basin("b", 0.1, 0.627, {"balanced 1": 1004, "coincident 2-": 21, "limit cycle": 575}, inline_share=0.6),
            _basin("c", 0.2, 0.146, {"balanced 1": 234, "coincident 2-": 4, "limit cycle": 1362}, inline_share=1.0),
            _basin("d", 0.25, 0.130, {"balanced 1": 208, "limit cycle": 1392}, inline_share=1.0)]


def _n4(panel, zeta, balanced, counts, **more):
    return _basin(panel, zeta, balanced / 256, counts, size=16, diagonal=1.0, **more)


FIG_5_19 = [_n4("a", 0.01, 256, {"balanced 1": 256}),
            _n4("b", 0.1, 255, {"balanced 1": 255, "undecided": 1}),
            _n4("c", 0.2, 47, {"balanced 1": 47, "limit cycle": 174, "desynchronised": 35}, off_diagonal_balanced=31,
                off_diagonal_near_centres=22, near_share_of_grid=0.12, off_diagonal_on_shifted=15),
            _n4("d", 0.25, 39, {"balanced 1": 39, "limit cycle": 206, "desynchronised": 11})]


def test_the_basin_sections_render_the_published_lines(published_section):
    """Figs. 5.18, 5.19 (templates/basins_n2.md.j2, basins_n4.md.j2).  Control: (b)'s balanced fraction of Fig.
    5.18 raised above (a)'s is said, the fraction "does not decrease monotonically"; a count changed changes
    the line."""
    assert reproduce._basin_section(FIG_5_18, ROOT) == published_section(
        "## Thesis, Fig. 5.18: basins of attraction of the balanced state, n = 2")
    assert reproduce._basin_n4_section(FIG_5_19, ROOT) == published_section(
        "## Thesis, Fig. 5.19: basins of attraction of the balanced state, n = 4")
    wrong = [FIG_5_18[0], dict(FIG_5_18[1], balanced=0.95), *FIG_5_18[2:]]
    text = "\n".join(reproduce._basin_section(wrong, ROOT))
    assert "does not decrease monotonically" in text and "95.0 %" in text
    wrong = [FIG_5_19[0], dict(FIG_5_19[1], balanced=250 / 256), *FIG_5_19[2:]]
    assert reproduce._basin_n4_section(wrong, ROOT) != published_section(
        "## Thesis, Fig. 5.19: basins of attraction of the balanced state, n = 4")
    assert reproduce._basin_section([], ROOT) == reproduce._basin_n4_section([], ROOT) == []


def _chapter4_inputs():
    """The values behind the committed section, to the digits it prints."""
    import numpy as np

    zeta = iter([(3.6e-05, 0.018288), (0.00014, 0.09446), (1.1e-05, 0.020588), (3.3e-05, 0.1036), (0.0009, 0.4923),
                 (0.235352, 0.00025, 0.00027), (0.04883, 0.00016, 0.00016)])
    statements = [(st, next(zeta)) for st in reproduce.STATEMENTS]
    for st in reproduce.LINES:
        bad = [(float(o), float(b)) for o in (2.5, 2.6) for b in np.linspace(0.005, 0.5, 20)[10:18]] \
            if st.n == 4 else []
        statements.append((st, {"points": 1520, "unstable": bad, "planes": tuple(st.line),
                                "ranges": tuple(st.line.values())}))
    pitchfork = {"damped": {n: [1.0079598, 1.338096] for n in (2, 3, 4)},
                 "limit": {n: [1.0075981, 1.3389774] for n in (2, 3, 4)},
                 "tip": [-6.9e-16 + 0j, -3.4e-15 + 0j, -0.0085 + 0j, 0.02 + 0j],
                 "past": [-0.0041 + 0.0165j, -0.0041 - 0.0165j]}
    maps = [(reproduce.map_caption(n, plane, figure),
             ROOT / "reproduction" / f"fig4_n{n}_{'omega_mu' if 'Omega' in plane else 'zeta_beta'}.png")
            for n, plane, _, figure in reproduce.MAPS]
    return statements, maps, pitchfork


def test_the_balanced_states_chapter_4_section_renders_the_published_lines(published_section):
    """Ch. 4's limits, lines, (4.1)-(4.2) and maps (templates/chapter4_balanced.md.j2).  Controls: an upper
    limit moved changes its row; without the pitchfork-Hopf points their paragraph goes; a statement along a
    line that holds is said to hold."""
    statements, maps, pitchfork = _chapter4_inputs()
    published = published_section("## Thesis, chapter 4: stability of the balanced state")
    assert reproduce._chapter4(statements, maps, ROOT, pitchfork) == published
    moved = [(statements[0][0], (3.6e-05, 0.0185)), *statements[1:]]
    assert reproduce._chapter4(moved, maps, ROOT, pitchfork) != published
    without = reproduce._chapter4(statements, maps, ROOT)
    i = next(k for k, line in enumerate(published) if line.startswith("**(4.1)-(4.2)"))
    j = next(k for k, line in enumerate(published) if line.startswith("Maps ("))
    assert without == published[:i - 1] + published[j - 1:]
    holds = [(st, dict(v, unstable=[])) if st.kind == "line" else (st, v) for st, v in statements]
    assert sum("— (the statement holds on the grid)" in line
               for line in reproduce._chapter4(holds, maps, ROOT, pitchfork)) == 4
