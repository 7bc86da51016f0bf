"""adbgen.ross.rotor: the rigid body, the bearings and the imbalance read from a ROSS rotor."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from adbgen.ross.rotor import (RotorError, Unbalance, check_rigid_body, imbalance, load_rotor, rigid_body,
                               supports)


def test_rigid_body_is_rosss_element_sums(example):
    body = rigid_body(example)
    assert body.mass == pytest.approx(example.m, rel=1e-12)
    assert body.z_cg == pytest.approx(0.75, rel=1e-12)  # the example is symmetric about its middle
    assert body.polar_inertia == pytest.approx(example.Ip, rel=1e-12)
    assert body.transverse_inertia == pytest.approx(example.It, rel=1e-12)  # ROSS's own rigid tilt about CG
    # the element sums by hand: shaft elements' m and the disks' m, Id + m d^2
    disks = sum(d.Id + d.m * (example.nodes_pos[d.n] - body.z_cg) ** 2 for d in example.disk_elements)
    assert disks < body.transverse_inertia  # the shaft adds its own


def test_a_wrong_rigid_body_property_is_refused(example):
    body = rigid_body(example)
    for wrong in (replace(body, mass=body.mass * 1.001), replace(body, z_cg=body.z_cg + 1e-3),
                  replace(body, polar_inertia=body.polar_inertia * 1.001)):
        with pytest.raises(RotorError, match="rigid-body"):
            check_rigid_body(example, wrong)
    check_rigid_body(example, body)


def test_bearings_at_speed(example):
    b1, b2 = supports(example, 300.0)
    assert (b1.node, b1.z, b1.k, b1.c) == (6, 1.5, (1e6, 0.8e6), (0.0, 0.0))
    assert (b2.node, b2.z) == (0, 0.0)


def test_cross_coupled_and_extra_bearings_are_refused(ross, example):
    b = lambda n, **kw: ross.BearingElement(n, kxx=1e6, cxx=0, **kw)  # noqa: E731
    plain = ross.Rotor(example.shaft_elements, example.disk_elements, [b(0, kyy=1e6), b(6, kyy=1e6)])
    assert supports(plain, 100.0)[0].k == (1e6, 1e6)  # the control: the same rotor without kxy passes
    coupled = ross.Rotor(example.shaft_elements, example.disk_elements, [b(0, kyy=1e6, kxy=2e5), b(6)])
    with pytest.raises(RotorError, match="cross-coupled stiffness"):
        supports(coupled, 100.0)
    three = ross.Rotor(example.shaft_elements, example.disk_elements,
                       [b(0), b(3), b(6)])
    with pytest.raises(RotorError, match="two bearings; this rotor has 3"):
        supports(three, 100.0)


def test_imbalance_static_and_couple(example):
    body = rigid_body(example)
    # one unbalance in the plane of G: static only
    still = imbalance(example, body, [Unbalance(3, 2e-4, 0.5)])
    assert still["eccentricity"] == pytest.approx(2e-4 / body.mass) and still["misalignment"] == 0
    assert still["imbalance_phase"] == pytest.approx(0.5)
    # equal and opposite at nodes 2 and 4 (z - z_G = -0.25, +0.25): a pure couple, 2 u 0.25 kg m^2
    pure = imbalance(example, body, [Unbalance(2, 1e-4, 0.0), Unbalance(4, 1e-4, math.pi)])
    assert pure["eccentricity"] == pytest.approx(0, abs=1e-18)
    dJ = body.transverse_inertia - body.polar_inertia
    chi = pure["misalignment"]
    assert dJ * math.sin(chi) * math.cos(chi) == pytest.approx(2 * 1e-4 * 0.25, rel=1e-12)
    # negative control: the couple of unbalances on one side differs from the pure couple
    assert imbalance(example, body, [Unbalance(2, 1e-4, 0.0)])["misalignment"] != pytest.approx(chi)


def test_bad_sources(tmp_path, ross):
    with pytest.raises(RotorError, match="no ROSS rotor file"):
        load_rotor(tmp_path / "none.toml")
    (tmp_path / "x.txt").write_text("x")
    with pytest.raises(RotorError, match="the .toml or .json"):
        load_rotor(tmp_path / "x.txt")
    (tmp_path / "bad.toml").write_text("[[x]]\n")
    with pytest.raises(RotorError, match="ROSS cannot load it"):
        load_rotor(tmp_path / "bad.toml")


def test_projection_is_diagonal(example):
    p = rigid_body(example).projection
    assert np.max(np.abs(p - np.diag(np.diag(p)))) < 1e-9 * np.max(np.diag(p))
