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
    assert "Floquet" in dr.BOUNDARY_TYPES["scope"] and "periodically forced" in dr.BOUNDARY_TYPES["scope"]
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


def test_the_scopes_floquet_statement_on_paper_b():
    """boundary_types' scope, measured: paper B of the rotating-frame model two_plane_rotating (c_b = 3e-4,
    eps = 0.001, Omega = 3.2) seen in the fixed frame (two_plane_fixed, the rotor isotropic: k_1X = k_1Y = k_1 ...)
    is a periodic orbit of period T = 2 pi / Omega (the same state returns after T) whose Floquet multipliers (the
    period map's Jacobian by central differences) are exp(lambda T), lambda B's eigenvalues: so its torus and
    fold are B's Hopf and real crossings.  Negative controls: exp(lambda T) at another period does not match, nor
    does an anisotropic rotor's period map (k_1Y = 2 k_1X: designed as a forced orbit, design_orbit)."""
    import numpy as np

    from adbgen.analysis.simulate import simulate
    from adbgen.analysis.steady import refine

    fixed, rot = load_model("two_plane_fixed"), load_model("two_plane_rotating")
    pb = rot.params({"epsilon": 0.001, "Omega": 3.2, "c_bb": 3e-4, "c_bt": 3e-4})
    values = dict(zip(rot.param_names, map(float, pb)))
    for k in ("k_1", "k_2", "c_1", "c_2"):
        values[k + "X"] = values[k + "Y"] = values[k]
    pa = fixed.params({n: values[n] for n in fixed.param_names if n in values})
    b = refine(rot, pb, rot.steady_state("B", pb), label="B")
    # the same states in the same order (the fixed frame's rotor coordinates capitalised, the balls relative)
    assert [s.lower() for s in fixed.state_names] == [s.lower() for s in rot.state_names]
    T = 2 * np.pi / values["Omega"]

    def period_map(p, y):
        return simulate(fixed, p, y, t_end=T, rtol=1e-11, atol=1e-13, keep_trajectory=False).y_end
    assert np.max(np.abs(period_map(pa, b.y) - b.y)) < 1e-10
    h, n = 1e-6, len(b.y)

    def mismatch(p, period):
        M = np.column_stack([(period_map(p, b.y + h * e) - period_map(p, b.y - h * e)) / (2 * h) for e in np.eye(n)])
        mu = np.linalg.eigvals(M)
        return max(min(abs(m - z) for m in mu) for z in np.exp(b.eigenvalues * period))
    assert mismatch(pa, T) < 1e-6
    assert mismatch(pa, T / 2) > 1e-3  # negative control: another period
    # negative control: an anisotropic rotor (the balanced rotor still at rest, but its period map another)
    aniso = fixed.params({**{n: values[n] for n in fixed.param_names if n in values}, "k_1Y": 2 * values["k_1"]})
    assert mismatch(aniso, T) > 1e-3


def test_the_figure_is_titled_by_the_scene_file_where_there_is_one(design, tmp_path):
    """A scene's model is named by a hash (scene_...): the figure of `adbgen design SCENE.toml --out` names
    the file, as `simulate --out` does; a generated model's design keeps its name (the control)."""
    files = dr.write(design, tmp_path / "scene", "adbgen design rig.toml ...", scene="examples/rig.toml")
    with Image.open(files["figure"]) as im:
        assert im.text["Title"] == "rig.toml (thesis_rotating_n3): design of beta"
    files = dr.write(design, tmp_path / "model", "adbgen design thesis_rotating_n3 ...")
    with Image.open(files["figure"]) as im:
        assert im.text["Title"] == "thesis_rotating_n3: design of beta"


@pytest.mark.parametrize("settled", [False, True])
def test_the_run_up_figure_says_when_r_has_not_settled(design, tmp_path, settled):
    """run-up.png says in its title (kept as the PNG's Title) that r has not settled by t_end, as report.md does;
    a settled run-up's title says nothing of it (the control)."""
    import dataclasses

    import numpy as np

    t = np.linspace(0.0, 50.0, 101)
    r = 0.1 * np.exp(-(0.01 if not settled else 0.3) * t)
    run = {"run_model": "thesis_rotating_n3", "design": {"beta": 0.45}, "schedule_end": 10.0, "t_end": 50.0,
           "threshold": 1e-3, "t_dec": None if not settled else float(t[np.flatnonzero(r >= 1e-3)[-1]]),
           "settled": settled, "status": "success", "trace": {"t": list(t), "r": list(r)}}
    dr.run_up_figure(dataclasses.replace(design, verification_run_up=run), tmp_path / dr.RUN_UP_FIGURE)
    with Image.open(tmp_path / dr.RUN_UP_FIGURE) as im:
        title = im.text["Title"]
    assert title.startswith("thesis_rotating_n3: run-up of the chosen design beta = 0.45")
    assert ("NOT SETTLED below the threshold by t_end = 50 (!)" in title) == (not settled)
