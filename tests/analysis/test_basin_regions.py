"""Provable basin regions by the nonlinear Lyapunov decrease condition (adbgen/analysis/basin_regions.py)."""

from __future__ import annotations

import math

import numpy as np

from adbgen.analysis import attractors, basin_regions
from adbgen.analysis.loading import load_model
from adbgen.analysis.simulate import simulate


def _vdot(model, p, centre, R, E):
    """dV/dt at the rows of E: grad V . f, V = e'Pe + T(e, e, e)."""
    out = []
    for e in E:
        grad = 2.0 * R.P @ e + (3.0 * np.einsum("ijk,j,k->i", R.T, e, e) if R.T is not None else 0.0)
        out.append(grad @ model.module.rhs(0.0, centre + e, p))
    return np.array(out)


def _ball(P, rho2, n, rng, shell=False):
    """n random points of the ball e'Pe <= rho2 (or of its sphere)."""
    u = rng.standard_normal((n, len(P)))
    u /= np.linalg.norm(u, axis=1)[:, None]
    radius = np.ones(n) if shell else rng.uniform(0, 1, n) ** (1.0 / len(P))
    return (u * radius[:, None] * math.sqrt(rho2)) @ np.linalg.inv(np.linalg.cholesky(P))


def _values(R, E):
    q = np.einsum("ni,ij,nj->n", E, R.P, E)
    return q, q + (np.einsum("ijk,ni,nj,nk->n", R.T, E, E, E) if R.T is not None else 0.0)


def test_lyapunov_region_at_5_1_decreases_v_and_is_larger_than_contraction():
    model = load_model("thesis_rotating_n2")
    p = model.params()
    y = attractors.newton(model, np.array(model.module.START, float), p)
    R = basin_regions.lyapunov_region(model, y, p)
    assert 0.004 < R.rate < 0.006  # the slowest mode at (5.1)
    small = attractors.stop_region(model, y, p, method="contraction")
    quadratic = basin_regions.lyapunov_region(model, y, p, cubic=False)
    # sizes along the slowest mode (weighted 1 in every metric): cubic > quadratic > contraction
    assert math.sqrt(R.rho2) > 5 * math.sqrt(quadratic.rho2) and math.sqrt(quadratic.rho2) > 3 * math.sqrt(small.c)
    # an independent sample (other seed) of the region: V > 0 and dV/dt < 0 everywhere
    rng = np.random.default_rng(11)
    E = _ball(R.P, R.rho2, 6000, rng)
    q, v = _values(R, E)
    E = E[v <= R.c]
    assert len(E) > 1000 and np.all(_values(R, E)[1] > 0) and np.all(_vdot(model, p, y, R, E) < 0)
    # the region never reaches the ball's sphere: V > c there
    assert np.all(_values(R, _ball(R.P, R.rho2, 4000, rng, shell=True))[1] > R.c)
    # negative controls: without the cubic term the same ball has points where V grows, and so has the
    # ball 5 times larger with it
    flat = basin_regions.Region(R.P, None, R.rho2, R.rho2, R.rate)
    assert np.any(_vdot(model, p, y, flat, _ball(R.P, R.rho2, 4000, rng, shell=True)) > 0)
    assert np.any(_vdot(model, p, y, R, _ball(R.P, 25 * R.rho2, 4000, rng, shell=True)) > 0)


def test_a_trajectory_from_the_boundary_stays_inside_and_converges():
    model = load_model("thesis_rotating_n2")
    p = model.params()
    region = next(r for r in attractors.classifier(model, p).regions if r.label == "balanced 1")
    rng = np.random.default_rng(3)
    E = _ball(region.P, region.rho2, 400, rng)
    q, v = region.value(model, region.centre + E)
    for e in E[np.argsort(np.abs(v - 0.99 * region.c))[:3]]:  # three points near the boundary V = c
        sim = simulate(model, p, region.centre + e, t_end=400.0)
        q, V = region.value(model, sim.y.T)
        assert np.all(region.contains(model, sim.y.T)) and V[-1] < 0.3 * V[0]
        assert np.all(np.diff(V) < 0)


def test_unstable_and_non_hyperbolic_states_get_no_region():
    model = load_model("thesis_rotating_n2")
    p = model.params()
    coincident = attractors.newton(model, np.array([0.1, 0.0, 3.0, 3.0, 0, 0, 0, 0]), p)
    assert attractors.name_steady_state(model, coincident, p).startswith("coincident")
    assert basin_regions.lyapunov_region(model, coincident, p) is None
    n3 = load_model("thesis_rotating_n3")
    y3 = attractors.newton(n3, np.array(n3.module.START, float), n3.params())
    assert basin_regions.lyapunov_region(n3, y3, n3.params()) is None  # the balanced family: a continuum


def test_modal_groups_pair_conjugates_slowest_first():
    lam = np.array([-0.1 + 2j, -0.01 + 0.5j, -0.1 - 2j, -0.3, -0.01 - 0.5j])
    groups = basin_regions.modal_groups(lam)
    assert [sorted(g.tolist()) for g in groups] == [[1, 4], [0, 2], [3]]
