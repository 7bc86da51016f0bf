"""The measures' pre-write check on a model with a time law (adbgen/codegen/passes/checks.py `measure_errors`): where time
enters a measure, the bound is the rounding its evaluation may carry (2 n eps times `magnitudes`, the sum of the
magnitudes it combines, sin and cos with their argument's), not LOWERING_TOLERANCE alone, which a schedule's stick
force exceeded by rounding (1.2e-12 against 1e-12, docs/friction.md).  The model: a single-plane scene whose
spin follows the `schedule` law (ramp, hold, reduction, plateau, recovery: core/speed_schedule.py), its measures
spin_angle and spin_rate the law itself (Piecewise in t; the angle of order omega t).

Negative control: one term of the time law with its sign flipped (in the emitted measure only: what a printing or
lowering error would do) is refused, by orders of magnitude beyond the derived bound."""

from __future__ import annotations

import numpy as np
import pytest
import sympy as sp

from adbgen.codegen.passes import description as describe_module
from adbgen.codegen.passes.checks import CheckFailed, check_description, magnitudes, measure_errors
from adbgen.codegen.spec import build as build_ir
from adbgen.families.single_plane import models
from adbgen.families.single_plane.scene import Scene

SCHEDULE = {"law": "schedule", "omega": 100.0, "ramp_time": 1.0, "hold_time": 0.5, "reduction_depth": 0.5,
            "reduction_rate": 200.0, "plateau_time": 0.5, "recovery_rate": 200.0}


@pytest.fixture(scope="module")
def schedule():
    spec = models.for_scene(Scene.from_mapping({"n": 2, "speed": SCHEDULE}), "schedule_n2")
    system = spec.system()
    return spec, system


def _ir(spec, system):
    return build_ir(spec, system)


def test_magnitudes_bound_the_terms_and_the_trig_arguments():
    x, y, t, w = sp.symbols("x y t w", real=True)
    bound = sp.lambdify((x, y, t, w), magnitudes(x - y + w * t * sp.sin(w * t)))
    # |x| + |y| + |w t| (1 + |w t|): cancellation of x - y does not shrink it, sin's argument enters
    assert bound(3.0, 3.0, 10.0, 100.0) == pytest.approx(3 + 3 + 1000 * 1001)


def test_the_time_law_measures_pass_within_their_derived_bound(schedule):
    spec, system = schedule
    ir = _ir(spec, system)
    assert {"spin_angle", "spin_rate"} <= set(ir.description.measure_names)
    rows = [row for row in measure_errors(ir, system) if row[0] in ("spin_angle", "spin_rate")]
    assert rows and all(err <= bound for _, _, _, err, bound in rows)
    check_description(ir, system)  # the whole check passes


def test_a_flipped_term_of_the_time_law_is_refused_by_orders_of_magnitude(schedule, monkeypatch):
    spec, system = schedule
    t = system.solve.eom.time
    measures = describe_module._measures

    def flip_one_term(expr):
        """One term of the law's last sum in t (the innermost Piecewise branch: the phase after the recovery,
        where most of the check's random times t in [0, 10] s fall) with its sign flipped."""
        sums = [sub for sub in sp.preorder_traversal(expr) if sub.is_Add and t in sub.free_symbols]
        assert sums, "no sum in t to plant a wrong term in"
        return expr.xreplace({sums[-1]: sums[-1] - 2 * sums[-1].args[0]})

    def planted(names, exprs):
        return measures(names, [flip_one_term(e) if n == "spin_angle" else e for n, e in zip(names, exprs)])

    monkeypatch.setattr(describe_module, "_measures", planted)
    ir = _ir(spec, system)
    rows = [row for row in measure_errors(ir, system) if row[0] == "spin_angle"]
    worst = max(err / bound for _, _, _, err, bound in rows)
    assert worst > 1e3, worst
    with pytest.raises(CheckFailed, match="measure spin_angle") as info:
        check_description(ir, system)
    assert "\n" not in str(info.value) and "bound" in str(info.value)
