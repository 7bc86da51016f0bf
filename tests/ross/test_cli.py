"""`adbgen scene from-ross`: a saved ROSS rotor -> a scene file, or a one-line refusal."""

from __future__ import annotations

import tomllib

import pytest

from adbgen.cli import main
from adbgen.families.two_plane.scene import TwoPlaneScene

ARGS = ["--plane", "2", "--plane", "4", "--balls", "2", "--ball-mass", "0.05", "--race-radius", "0.1"]


@pytest.fixture(scope="module")
def saved(tmp_path_factory, example, stiff):
    d = tmp_path_factory.mktemp("rotors")
    example.save(d / "example.toml")
    stiff.save(d / "stiff.json")
    return d


def test_written_scene_reads_back(saved, tmp_path, capsys):
    out = tmp_path / "scene.toml"
    assert main(["scene", "from-ross", str(saved / "stiff.json"), *ARGS, "--speed", "545",
                 "--unbalance", "2", "1e-4", "0", "--out", str(out)]) == 0
    assert "rigid is enough" in capsys.readouterr().out
    scene = TwoPlaneScene.load(out)
    data = tomllib.loads(out.read_text())
    assert scene.rotor_mass == pytest.approx(88.1818040166, rel=1e-10)
    assert scene.bearing_1.position == 0.75 and scene.bearing_1.stiffness == (1e6, 8e5)
    assert [r.z for r in scene.races] == [-0.25, 0.25] and data["speed"]["omega"] == 545.0


def test_flexible_example_is_refused_in_one_line(saved, tmp_path, capsys):
    out = tmp_path / "scene.toml"
    assert main(["scene", "from-ross", str(saved / "example.toml"), *ARGS, "--speed", "545", "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "rigid is not enough" in err and "636" in err
    assert not out.exists()


@pytest.mark.parametrize("extra, message", [(["--plane", "9"], "node 9 is not a node"),
                                             (["--plane", "2"], "must be different nodes")])
def test_bad_input(saved, tmp_path, capsys, extra, message):
    argv = ["scene", "from-ross", str(saved / "example.toml"), "--plane", "2", *extra, "--balls", "2",
            "--ball-mass", "0.05", "--race-radius", "0.1", "--speed", "100", "--no-check", "--out", str(tmp_path / "s")]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_flexible_example_writes_the_flexible_scene(saved, tmp_path, capsys):
    """--flexible: where rigid is not enough, the flexible scene at the one plane; it reads back in the
    flexible family with the unbalance at the node (m_u eps = 1e-4 kg m)."""
    from adbgen.families.flexible.scene import FlexibleScene

    out = tmp_path / "flexible.toml"
    args = ["--plane", "2", "--balls", "2", "--ball-mass", "0.05", "--race-radius", "0.1", "--speed", "545",
            "--unbalance", "2", "1e-4", "0", "--flexible", "--modes", "6", "--out", str(out)]
    assert main(["scene", "from-ross", str(saved / "example.toml"), *args]) == 0
    assert "flexible, 6 modes" in capsys.readouterr().out
    scene = FlexibleScene.load(out)
    assert scene.k == 6 and scene.n == 2 and scene.omega == 545.0
    assert scene.unbalance_mass * scene.eccentricity == pytest.approx(1e-4, rel=1e-12)
    assert not (tmp_path / "flexible.toml").read_text().count("rigid is enough")  # negative: said not enough


def test_flexible_example_with_two_planes_writes_node_2(saved, tmp_path, capsys, example):
    """--flexible with two planes (the example's disks, nodes 2 and 4): the flexible scene with [node_2], its
    shapes the bridge's at node 4 in the same k modes, the same race; the unbalance at the first plane.
    Negative control: the unbalance at the second plane is refused in one line (the family carries it at the
    first node), nothing written."""
    from adbgen.families.flexible.scene import FlexibleScene
    from adbgen.ross.flexible import scene_mapping

    out = tmp_path / "flexible.toml"
    args = ["--plane", "2", "--plane", "4", "--balls", "2", "--ball-mass", "0.05", "--race-radius", "0.1",
            "--speed", "545", "--flexible", "--modes", "6", "--out", str(out)]
    assert main(["scene", "from-ross", str(saved / "example.toml"), *args, "--unbalance", "2", "1e-4", "0"]) == 0
    assert "flexible, 6 modes, balancer nodes 2 and 4" in capsys.readouterr().out
    scene = FlexibleScene.load(out)
    assert scene.k == 6 and scene.n == 2 and scene.node_2.n == 2 and scene.node_2.race_radius == 0.1
    assert scene.unbalance_mass * scene.eccentricity == pytest.approx(1e-4, rel=1e-12)
    expected = scene_mapping(example, 2, 6, 2, 0.05, 0.1, 545.0, node_2=4)["node_2"]["node_shape"]
    assert [list(r) for r in scene.node_2.node_shape] == expected
    assert [list(r) for r in scene.node_2.node_shape] != [list(r) for r in scene.modal.node_shape]
    bad = tmp_path / "bad.toml"
    argv = ["scene", "from-ross", str(saved / "example.toml"), *args[:-1], str(bad), "--unbalance", "4", "1e-4", "0"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert "give --plane 4 first" in err and err.count("\n") == 1 and not bad.exists()
