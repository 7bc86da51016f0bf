"""Size of the derived forms is affine in n (the benchmark records times; this checks sizes exactly)."""

import pytest

from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane.model import derive
from adbgen.families.single_plane.reductions import first_order, rotating_frame
from adbgen.families.single_plane.verify import general_scene


@pytest.mark.parametrize("build", [
    lambda n: first_order(rotating_frame(Scene(n=n))),
    lambda n: first_order(derive(general_scene(n))),
], ids=["thesis-first-order", "general-first-order"])
def test_first_order_size_is_affine_in_n(build):
    sizes = {n: build(n).count_ops() for n in (2, 4, 8, 12)}
    per_ball = (sizes[4] - sizes[2]) / 2
    assert per_ball > 0
    for n in (8, 12):
        assert sizes[n] == sizes[2] + per_ball * (n - 2)
