"""analysis.design_report: every output of a design states which boundary types it certifies (issue 39 item 2):
design.json's boundary_types (with its scope), the report's lines and the figure, drawn under it and kept in
the PNG's Description.  Negative control: a PNG saved without the statement has no Description to read."""

from __future__ import annotations

import json

import pytest
from PIL import Image

from adbgen.analysis import design_report as dr
from adbgen.analysis.design import Axis, Design, Problem, assess
from adbgen.analysis.loading import load_model


@pytest.fixture(scope="module")
def design():
    m = load_model("thesis_rotating_n3")
    pr = Problem(m, m.params({"zeta": 0.3}), [Axis("Omega", 4.0, 4.0)], [Axis("beta", 0.3, 0.6)])
    vs = [assess(pr, [b]) for b in (0.3, 0.45, 0.6)]
    return Design(pr, "interval", vs[1], verdicts=vs)


def test_every_output_says_which_boundaries_are_certified(design, tmp_path):
    files = dr.write(design, tmp_path, "adbgen design ...")
    data = json.loads((tmp_path / "design.json").read_text())
    assert data["boundary_types"] == dr.BOUNDARY_TYPES and set(dr.BOUNDARY_TYPES) == {"certified", "not_certified",
                                                                                        "scope"}
    assert "Floquet" in dr.BOUNDARY_TYPES["scope"] and "forced models are refused" in dr.BOUNDARY_TYPES["scope"]
    report = (tmp_path / "report.md").read_text().splitlines()
    assert "Scope: " + dr.BOUNDARY_TYPES["scope"] in report
    assert any(line.startswith("Boundaries the chart certifies: capacity limit") for line in report)
    with Image.open(files["figure"]) as im:
        assert im.text["Description"] == dr.BOUNDARY_NOTE
    for kind in ("Hopf", "real eigenvalue", "capacity limit", "basin boundary"):
        assert kind in dr.BOUNDARY_NOTE
    # negative control: a figure saved without the statement carries none
    from adbgen.analysis.figure_style import pyplot

    plt = pyplot()
    fig, _ = plt.subplots()
    fig.savefig(tmp_path / "plain.png")
    plt.close(fig)
    with Image.open(tmp_path / "plain.png") as im:
        assert "Description" not in im.text
