"""The lanes target (the rhs over a vector of trajectories, for the ensemble engine): its header is proven
before it is written, a wrong one is refused, and a model whose rhs branches is skipped with the reason."""

from __future__ import annotations

import pytest

from adbgen.codegen import compiler, targets
from adbgen.codegen.passes import proof as proofs
from adbgen.codegen.passes.checks import Reference
from adbgen.codegen.render import render_model
from adbgen.codegen.spec import build as build_ir
from adbgen.families.single_plane import models

from toolchain import require_tool


@pytest.fixture(autouse=True)
def fresh_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("ADBGEN_CACHE", str(tmp_path / "cache"))


def test_the_lanes_header_is_proven_and_a_wrong_one_refused():
    why = compiler.missing("gcc")
    require_tool(why is None, why or "gcc")
    spec = models.thesis_rotating(2)
    system = spec.system()
    ir = build_ir(spec, system)
    ref = Reference.of(system)
    files = render_model(ir, ("lanes",))
    rel = f"{ir.name}/{ir.name}_lanes.h"
    assert list(files) == [rel] and "adb_sin(ball_q)" in files[rel]
    assert proofs.prove_model(ir, files, ("lanes",), "loops", ref)["targets"] == ("lanes",)
    # negative control: a sign flipped in one statement of the rhs
    wrong = dict(files, **{rel: files[rel].replace("const adb_lanes ball_c_0 = adb_splat(-wb_6);",
                                                   "const adb_lanes ball_c_0 = adb_splat(wb_6);")})
    assert wrong[rel] != files[rel]
    with pytest.raises(proofs.ProofFailed, match=r"^thesis_rotating_n2: lanes files: thesis_rotating_n2_rhs_lanes "):
        proofs.prove_model(ir, wrong, ("lanes",), "loops", ref)


def test_a_branching_rhs_is_skipped_with_the_reason():
    from adbgen.families.two_plane import models as two_plane

    lanes = targets.get("lanes")
    hill = two_plane.two_plane_hill()
    assert "Piecewise" in lanes.skip_reason(build_ir(hill, hill.system()))
    thesis = models.thesis_rotating(2)
    assert lanes.skip_reason(build_ir(thesis, thesis.system())) is None
