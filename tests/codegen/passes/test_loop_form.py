"""The loop form (issue 10): the per-ball block kept once and verified against every ball, kernels
equal to the unrolled programs, and printed source whose size does not grow with n."""

from __future__ import annotations

import dataclasses
import re
import subprocess

import numpy as np
import pytest
import sympy as sp

from adbgen.codegen.passes.ball_split import NoBallStructure, split
from adbgen.codegen.plain_python import compile_program
from adbgen.codegen.ir.model import KERNELS
from adbgen.codegen.passes.lowering import _blocks
from adbgen.codegen.render import render_model
from adbgen.families.single_plane import models
from adbgen.families.single_plane.scene import Scene
from adbgen.families.two_plane import models as two_plane
from adbgen.codegen.spec import build as build_ir

from toolchain import STRICT_CFLAGS, require_tool
from toolchain import which as find_tool


def _both(spec):
    system = spec.system()
    return system, build_ir(spec, system), build_ir(spec, system, form="unrolled")


CASES = {
    "thesis_n3": lambda: models.thesis_rotating(3),
    "unequal_balls": lambda: models.for_scene(Scene.from_mapping(
        {"n": 3, "ball_mass": [0.05, 0.04, 0.03], "ball_damping": [1e-4, 2e-4, 3e-4]}), "unequal_n3"),
    "two_plane_races": two_plane.two_plane_fixed,
    "two_plane_rotating": two_plane.two_plane_rotating,
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_the_loop_form_equals_the_unrolled_form(case):
    """Every function of the loop form against the unrolled program, at random points (unequal balls and
    the two-plane races read their own parameters through the slot tables)."""
    system, loops, unrolled = _both(CASES[case]())
    assert loops.form == "loops" and unrolled.form == "unrolled"
    rng = np.random.default_rng(3)
    p0 = np.array([p.default for p in system.parameters])
    for which in KERNELS:
        a, b = compile_program(loops, which), compile_program(unrolled, which)
        for _ in range(5):
            y = rng.uniform(-1, 1, loops.n_states) * 0.1
            p = p0 * rng.uniform(0.5, 1.5, p0.size)
            got, want = a(rng.uniform(0, 5), y, p), b(0.0, y, p) if loops.autonomous else None
            if want is None:
                t = rng.uniform(0, 5)
                got, want = a(t, y, p), b(t, y, p)
            assert np.max(np.abs(got - want)) <= 1e-11 * max(1.0, np.max(np.abs(want))), (case, which)


def test_the_ball_block_is_verified_against_every_ball():
    """A model whose third ball differs from the first (its forcing row scaled) has no loop form: the
    check that the generic block is every ball's can fail, and the lowering falls back to unrolled."""
    spec = models.thesis_rotating(3)
    system = spec.system()
    blocks, _ = _blocks(system, False)
    ok = split(blocks.coordinates, blocks.core, blocks.leaves, blocks.mass, blocks.f, system.parameters)
    assert ok.n == 3 and ok.first == 2
    f = list(blocks.f)
    f[blocks.leaves[2]] = f[blocks.leaves[2]] * sp.Rational(1001, 1000)
    with pytest.raises(NoBallStructure, match="ball 3's block differs"):
        split(blocks.coordinates, blocks.core, blocks.leaves, blocks.mass, f, system.parameters)
    # a race parameter not declared as a ball's own: ball 3's block names R_b where ball 1's has R_t
    sc = two_plane.scene("paper-43")
    fixed = two_plane.two_plane_fixed()
    sys2 = fixed.system()
    b2, _ = _blocks(sys2, False)
    with pytest.raises(NoBallStructure):
        split(b2.coordinates, b2.core, b2.leaves, b2.mass, b2.f, sys2.parameters)
    assert len(split(b2.coordinates, b2.core, b2.leaves, b2.mass, b2.f, sys2.parameters,
                     two_plane.race_slots(sc)(sys2)).slots) == 4


def test_a_term_coupling_two_balls_is_refused():
    spec = models.thesis_rotating(2)
    system = spec.system()
    blocks, _ = _blocks(system, False)
    c1, c2 = (blocks.coordinates[k] for k in blocks.leaves)
    f = list(blocks.f)
    f[blocks.core[0]] += sp.sin(c1.q - c2.q)
    with pytest.raises(NoBallStructure, match="couples balls"):
        split(blocks.coordinates, blocks.core, blocks.leaves, blocks.mass, f, system.parameters)


def _sizes(n: int) -> dict[str, int]:
    ir = build_ir(models.thesis_rotating(n))
    files = render_model(ir, ("numba", "c"))
    name = ir.name
    out = {}
    for rel, text in files.items():
        if rel.endswith(".json"):  # program.json is the rhs unrolled as data for the peers, not emitted code
            continue
        body = text[text.index("def rhs_inplace" if rel.endswith(".py") else f"void {name}_rhs"):]
        # KNOWN GAP (issue 33): the manifold's gradient (thesis (3.6), 2 n entries) is still emitted unrolled, 82
        # characters a ball; it is left out here until it is emitted in loop form, and only it
        body = re.sub(r"\ndef equilibria_gradient_inplace\(.*?(?=\n\S)", "", body, flags=re.S)
        out[rel.replace(name, "M")] = re.sub(r"\d+", "#", body.replace(name, "M"))
    return out


def test_the_source_does_not_grow_with_n():
    """The functions of the numba module and the C file (everything after the metadata) are the same
    size for n = 2 and n = 12 but for the numbers (indices, counts, n as a coefficient) and the order
    of terms (the print order follows the statements' definitions, numbers included); the closed-form
    steady states (issue 19) simplify a little further for n = 2 (their A = -delta/mu is known to be
    negative there), a few lines, so lines are compared to 1 % too.  The kernels (rhs ... forcing) are
    compared line for line in test_the_kernels_do_not_grow_with_n."""
    small, large = _sizes(2), _sizes(12)
    assert small.keys() == large.keys()
    for rel in small:
        assert abs(len(small[rel]) - len(large[rel])) <= 0.01 * len(small[rel]), rel
        lines = len(small[rel].splitlines())
        assert sorted(small[rel].split()) != [] and abs(lines - len(large[rel].splitlines())) <= 0.01 * lines, rel


def test_the_kernels_do_not_grow_with_n():
    """rhs, jac, jac_p, mass_matrix, forcing: the same number of lines for n = 2 and n = 12."""
    small, large = _sizes(2), _sizes(12)
    for rel in small:
        cut = "def measures_inplace" if rel.endswith(".py") else "M_measure"  # (the header: prototypes only)
        a, b = small[rel].partition(cut)[0], large[rel].partition(cut)[0]
        assert len(a.splitlines()) == len(b.splitlines()), rel


def test_balls_started_together_stay_equal_bit_for_bit():
    """Ball i's loop body is ball j's: equal ball states give bitwise equal accelerations and rows."""
    ir = build_ir(models.thesis_rotating(4))
    f, J = compile_program(ir, "rhs"), compile_program(ir, "jac")
    y = np.array([0.01, -0.02, 1.0, 1.0, 2.5, 1.0, 0.3, -0.1, 0.2, 0.2, -0.4, 0.2])
    p = np.array([q.default for q in ir.parameters])
    a = f(0.0, y, p)
    assert a[2] == a[3] == a[5] and a[8] == a[9] == a[11]
    Jm = J(0.0, y, p).reshape(12, 12)
    others = [0, 1, 4, 5, 6, 7, 10, 11]  # not balls 1 and 2's own columns
    assert np.array_equal(Jm[8, others], Jm[9, others]) and np.array_equal(Jm[2:6, 8:12], np.eye(4))


def test_a_ball_parameter_with_a_coefficient_is_read_through_its_table(tmp_path):
    """Ball 2's mass declared as 2 m_1 (a slot value c * p[k] with c != 1, as the symmetric two-plane
    set-up's -z): the loop form reads it through the coefficient table and equals the unrolled form."""
    from adbgen.codegen.passes.lowering import build
    from adbgen.core.first_order import first_order

    system = models.for_scene(Scene.from_mapping({"n": 2, "ball_mass": [0.05, 0.04]}), "u2").system()
    eom = system.solve.eom
    names = {p.name: p.symbol for p in system.parameters}
    tied = {names["m_2"]: 2 * names["m_1"]}
    eom2 = dataclasses.replace(eom.map(lambda e: sp.sympify(e).xreplace(tied)),
                               parameters=tuple(p for p in eom.parameters if p.name != "m_2"))
    system2 = first_order(eom2, tuple(eom.coordinates[k].name for k in system.solve.core))
    slots = [{"m": names["m_1"], "D": names["D_1"]}, {"m": 2 * names["m_1"], "D": names["D_2"]}]
    loops = build("tied", system2, title="tied", n_balls=2, balls=slots)
    unrolled = build("tied", system2, title="tied", n_balls=2, form="unrolled")
    assert loops.form == "loops"
    m = {sl.name: sl for sl in loops.loops.split.slots}["m"]
    assert m.coefficients == (1.0, 2.0) and not m.unit_coefficients
    rng = np.random.default_rng(8)
    p0 = np.array([p.default for p in system2.parameters])
    for which in KERNELS:
        a, b = compile_program(loops, which), compile_program(unrolled, which)
        for _ in range(3):
            t, y, p = rng.uniform(0, 5), rng.uniform(-0.1, 0.1, loops.n_states), p0 * rng.uniform(0.5, 1.5, p0.size)
            want = b(t, y, p)
            assert np.max(np.abs(a(t, y, p) - want)) <= 1e-11 * max(1.0, np.max(np.abs(want))), which
    files = render_model(loops, ("numba", "c"))
    assert "ball_slot_m_coef = np.array([1.0, 2.0]" in files["tied/__init__.py"]
    assert "static const double ball_slot_m_coef[2] = { 1.0, 2.0 };" in files["tied/tied.c"]
    gcc = find_tool("gcc")
    require_tool(gcc is not None, "gcc")
    (tmp_path / "tied.c").write_text(files["tied/tied.c"])
    (tmp_path / "tied.h").write_text(files["tied/tied.h"])
    r = subprocess.run([gcc, *STRICT_CFLAGS, "-fsyntax-only", "tied.c"], cwd=tmp_path, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
