"""`adbgen regenerate`: determinism, --check, atomic writes, bad input (issue: code generation)."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from adbgen.codegen.regenerate import DEFAULT_OUT, render_all

ADBGEN = [sys.executable, "-m", "adbgen.cli"]


def run(*args, env=None, timeout=600, **kw) -> subprocess.CompletedProcess:
    return subprocess.run(ADBGEN + list(args), capture_output=True, text=True, timeout=timeout,
                          env=dict(os.environ, **(env or {})), **kw)


def snapshot(folder: Path) -> dict[str, bytes]:
    return {p.relative_to(folder).as_posix(): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file() and "__pycache__" not in p.parts}


@pytest.fixture(scope="module")
def small_tree(tmp_path_factory) -> Path:
    """The n = 1 families, regenerated into a fresh folder (reduction checks on)."""
    out = tmp_path_factory.mktemp("regen") / "gen"
    r = run("regenerate", "--n", "1", "--out", str(out))
    assert r.returncode == 0, r.stderr
    # progress is shown, up to the last model ([k/k], one model per family at n = 1)
    assert "thesis_rotating_n1" in r.stderr and re.search(r"\[(\d+)/\1\]", r.stderr)
    return out


def test_committed_generated_folder_is_current():
    """`adbgen regenerate --check` with the reduction checks, as a user runs it: the committed generated/ is what
    the models and templates produce.  The README's test command runs it here, on one of the suite's workers,
    rather than as a serial step before the suite;
    a failure shows the command's own report, each stale file with its diff."""
    r = run("regenerate", "--check", "--quiet", timeout=1800)
    assert r.returncode == 0, r.stdout[-20000:] + r.stderr[-2000:]
    assert re.fullmatch(rf"{re.escape(str(DEFAULT_OUT))}: \d+ files up to date\n", r.stdout), r.stdout


def test_output_is_byte_identical_under_any_hash_seed(small_tree, tmp_path):
    for seed in ("0", "4242"):
        out = tmp_path / f"seed{seed}"
        r = run("regenerate", "--n", "1", "--out", str(out), "--skip-checks", "--quiet", env={"PYTHONHASHSEED": seed})
        assert r.returncode == 0, r.stderr
        assert snapshot(out) == snapshot(small_tree)


def test_check_names_stale_missing_and_foreign_files(small_tree, tmp_path):
    out = tmp_path / "gen"
    subprocess.run(["cp", "-r", str(small_tree), str(out)], check=True)
    r = run("regenerate", "--n", "1", "--out", str(out), "--check", "--skip-checks", "--quiet")
    assert r.returncode == 0, r.stdout + r.stderr
    c_file = out / "thesis_rotating_n1" / "thesis_rotating_n1.c"
    c_file.write_text(c_file.read_text() + "/* edited by hand */\n")
    (out / "single_plane_fixed_n1" / "single_plane_fixed_n1.h").unlink()
    (out / "thesis_rotating_n1" / "notes.txt").write_text("mine")
    (out / "thesis_rotating_n1" / "thesis_rotating_n1_cvode_main.c").write_text("")
    r = run("regenerate", "--n", "1", "--out", str(out), "--check", "--skip-checks", "--quiet")
    assert r.returncode == 1
    assert f"stale: {c_file} (differs)" in r.stdout
    assert "single_plane_fixed_n1.h (missing)" in r.stdout and "notes.txt (not generated)" in r.stdout
    # each stale file's unified diff, on disk -> regenerated
    assert f"--- {out.name}/thesis_rotating_n1/thesis_rotating_n1.c (on disk)" in r.stdout
    assert "\n-/* edited by hand */\n" in r.stdout and "\n@@ " in r.stdout
    # a missing file's diff is all additions; a long one is truncated to DIFF_LINES lines (the missing
    # header and the emptied driver; not the hand-edited file's)
    assert f"+++ {out.name}/single_plane_fixed_n1/single_plane_fixed_n1.h (regenerated)" in r.stdout
    assert r.stdout.count("more diff lines)") == 2
    r = run("regenerate", "--n", "1", "--out", str(out), "--skip-checks", "--quiet")
    assert r.returncode == 0 and snapshot(out) == snapshot(small_tree) | {"thesis_rotating_n1/notes.txt": b"mine"}


def test_a_killed_regeneration_leaves_the_folder_as_it_was(small_tree, tmp_path):
    out = tmp_path / "gen"
    subprocess.run(["cp", "-r", str(small_tree), str(out)], check=True)
    stale_file = out / "thesis_rotating_n1" / "__init__.py"
    stale_file.write_text("# an old version\n")
    before = snapshot(out)
    proc = subprocess.Popen(ADBGEN + ["regenerate", "--n", "1", "--out", str(out)], stderr=subprocess.PIPE, text=True)
    for line in proc.stderr:  # kill it half-way: after the first model is rendered, before the others
        if line.startswith("[1/"):
            proc.send_signal(signal.SIGKILL)
            break
    proc.wait(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    assert snapshot(out) == before
    assert not list(tmp_path.glob(".gen-staging-*"))


@pytest.mark.parametrize("scene_text, message", [
    ("n = 2\nrotor_mass = -1.0\n", "scene.rotor_mass: must be positive"),
    ("n = 0\n", "scene.n"),
    ("n = 2\neccentricity = nan\n", "scene.eccentricity: must be finite"),
    ("n = 2\nflux = 3\n", "scene"),
])
def test_bad_scene_exits_with_one_line_and_writes_nothing(small_tree, tmp_path, scene_text, message):
    out = tmp_path / "gen"
    subprocess.run(["cp", "-r", str(small_tree), str(out)], check=True)
    before = snapshot(out)
    scene = tmp_path / "bad.toml"
    scene.write_text(scene_text)
    r = run("regenerate", "--scene", str(scene), "--out", str(out))
    assert r.returncode == 2
    assert r.stderr.count("\n") == 1 and r.stderr.startswith("adbgen: error: ") and message in r.stderr
    assert snapshot(out) == before


@pytest.mark.parametrize("args, message", [
    (["--n", "0", "--out", "x"], "n must be at least 1"),
    (["--n", "2"], "give --out DIR"),
    (["--frobnicate"], "unrecognized arguments"),
    (["--targets", "fortran"], "invalid choice"),
    (["--scene", "s.toml", "--name", "1bad", "--out", "x"], "not a C identifier"),
])
def test_bad_options_exit_with_one_line(args, message):
    r = run("regenerate", *args)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and message in r.stderr, r.stderr


def test_a_scene_gets_its_smallest_model(tmp_path):
    scene = tmp_path / "unequal.toml"
    scene.write_text("n = 3\nball_mass = [0.05, 0.04, 0.03]\n")
    out = tmp_path / "gen"
    r = run("regenerate", "--scene", str(scene), "--name", "unequal_n3", "--out", str(out), "--targets", "numba", "c")
    assert r.returncode == 0, r.stderr
    # the checks its spec carries, the family's for n = 3 (the name no longer decides: issue 8); the
    # dimensional rotating frame of unequal balls is not (2.25)-(2.27), so not those checks
    for check in ("fixed frame, n=3", "prescribed speed, n=3"):
        assert f"check  ok   {check} [" in r.stderr, (check, r.stderr)
    assert "rotating frame, n=3" not in r.stderr
    text = (out / "unequal_n3" / "__init__.py").read_text()
    assert "STATE_NAMES = ('x', 'y', 'phi_1', 'phi_2', 'phi_3'," in text  # rotating frame: autonomous
    assert "AUTONOMOUS = True" in text and "'m_3'" in text
    assert sorted(p.name for p in (out / "unequal_n3").iterdir()) == ["__init__.py", "program.json", "unequal_n3.c", "unequal_n3.h"]


@pytest.mark.parametrize("name, why", [
    ("class", "Python keyword"), ("match", "Python keyword"), ("int", "C keyword"), ("len", "Python builtin"), ("os", "standard-library"),
    ("json", "standard-library"), ("generated", "reserved"), ("double", "C keyword"), ("1bad", "C identifier"),
    ("a-b", "C identifier"), ("mod\u00e8le", "C identifier"), ("__init__", "dunder"), ("__x", "dunder"),
])
def test_model_names_that_cannot_be_a_module_and_a_c_prefix_are_refused(name, why):
    from adbgen.codegen.names import ModelNameError, name_problem, validate_name

    assert why in name_problem(name)
    with pytest.raises(ModelNameError, match="model name"):
        validate_name(name)


def test_good_model_names_pass():
    from adbgen.codegen.names import name_problem

    for name in ("thesis_rotating_n2", "two_plane_hill", "rig_A", "_private"):
        assert name_problem(name) is None, name


@pytest.mark.parametrize("name", ["class", "int", "generated", "os"])
def test_a_bad_name_on_the_command_line_is_one_line_and_writes_nothing(tmp_path, name):
    scene = tmp_path / "s.toml"
    scene.write_text("n = 2\n")
    r = run("regenerate", "--scene", str(scene), "--name", name, "--out", str(tmp_path / "gen"))
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and f"'{name}'" in r.stderr, r.stderr
    assert not (tmp_path / "gen").exists()


def test_a_scene_file_finds_its_family(tmp_path):
    """--scene reads the file with each registered family's scene format; the one that accepts it
    makes the model, with that family's checks (here the two-plane fixed frame: (2)-(4), (40))."""
    scene = tmp_path / "rig.toml"
    scene.write_text('preset = "paper-43"\n')
    out = tmp_path / "gen"
    r = run("regenerate", "--scene", str(scene), "--name", "rig43", "--out", str(out), "--targets", "numba")
    assert r.returncode == 0, r.stderr
    assert "check  ok   fixed frame, torque drive [paper (2)-(4)" in r.stderr and "autonomous extension [paper (40)]" in r.stderr
    text = (out / "rig43" / "__init__.py").read_text()
    assert "STATE_NAMES = ('X', 'Y', 'phi_X', 'phi_Y', 'alpha_1'," in text and "AUTONOMOUS = False" in text
    r = run("regenerate", "--scene", str(tmp_path / "missing.toml"), "--out", str(out))
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "no scene file at" in r.stderr


@pytest.mark.parametrize("full", [False, True], ids=["proportionate", "full"])
def test_regenerate_says_which_form_of_each_check_ran(tmp_path, monkeypatch, capsys, full):
    """Above FULL_CHECKS_MAX_N the slow checks run in their proportionate form (issue 10), and the
    progress line says so; --full-checks runs the exact ones (the limit lowered here to keep it fast)."""
    from adbgen.cli import main
    from adbgen.families.single_plane import verify

    monkeypatch.setattr(verify, "FULL_CHECKS_MAX_N", 1)
    out = tmp_path / "gen"
    args = ["regenerate", "--n", "2", "--family", "single-plane", "--targets", "numba", "--out", str(out)]
    assert main(args + (["--full-checks"] if full else [])) == 0
    err = capsys.readouterr().err
    numeric = "check  ok   steady states (numeric, 50 digits), n=2 [thesis (3.6), (3.9), (3.10)]"
    assert (numeric in err) != full and ("check  ok   steady states, n=2 [" in err) == full, err
    assert ("(proportionate form; --full-checks runs the exact one)" in err) != full
    assert "thesis_rotating_n2: 8 states, loops," in err
    assert "for i in range(2):" in (out / "thesis_rotating_n2" / "__init__.py").read_text()


def test_the_unrolled_form_is_one_switch_away(tmp_path):
    out = tmp_path / "gen"
    r = run("regenerate", "--n", "2", "--family", "single-plane", "--targets", "numba", "--skip-checks",
            "--form", "unrolled", "--out", str(out))
    assert r.returncode == 0, r.stderr
    assert "thesis_rotating_n2: 8 states, unrolled," in r.stderr
    assert "for i in range" not in (out / "thesis_rotating_n2" / "__init__.py").read_text()


def test_the_source_hash_covers_every_templates_name_and_bytes(tmp_path, monkeypatch):
    """A generated file's SOURCE_HASH changes with any template: its bytes, its name, a new template (so
    `regenerate --check` sees a template edit even where the rendered text happens not to change)."""
    from types import SimpleNamespace

    from adbgen.codegen import render

    toy, package = tmp_path / "toy", tmp_path / "package"
    toy.mkdir(), package.mkdir()
    (toy / "a.j2").write_text("{{ x }}\n")
    (package / "index.j2").write_text("index\n")
    monkeypatch.setattr(render.targets, "all_targets", lambda: [SimpleNamespace(name="toy", template_folder=toy)])
    monkeypatch.setattr(render, "package_templates", lambda: package)
    digest = render._template_digest.__wrapped__  # past the cache: each call reads the folders again

    first = digest(0)
    assert digest(0) == first
    (toy / "a.j2").write_text("{{ x }} \n")
    edited = digest(0)
    (toy / "a.j2").rename(toy / "b.j2")
    renamed = digest(0)
    (package / "extra.j2").write_text("")
    added = digest(0)
    assert len({first, edited, renamed, added}) == 4


def test_render_all_runs_its_named_stages_in_order_and_times_each(caplog):
    """`render_all` is `STAGES` in order, the "models" stage `MODEL_STAGES` per model (issue 33 item 4);
    each stage's time is in `Rendered.timings` and a debug log line, not in the files."""
    import logging

    from adbgen.codegen.regenerate import MODEL_STAGES, STAGES
    from adbgen.families.single_plane import models

    spec = models.thesis_rotating(1)
    with caplog.at_level(logging.DEBUG, logger="adbgen.codegen.regenerate"):
        rendered = render_all([spec], ("numba",), run_checks=False)
    per_model = [(spec.name, s.name) for s in MODEL_STAGES]
    assert [(t.model, t.stage) for t in rendered.timings] == \
        [("", "names"), ("", "reduction checks")] + per_model + [("", "models"), ("", "index")]
    assert [s.name for s in STAGES] == ["names", "reduction checks", "models", "index"]
    assert all(t.seconds >= 0 for t in rendered.timings)
    # the models stage holds its model's stages (the clock is monotonic)
    models_time = next(t.seconds for t in rendered.timings if t.stage == "models")
    assert sum(t.seconds for t in rendered.timings if t.model) <= models_time
    lines = [r.getMessage() for r in caplog.records if r.name == "adbgen.codegen.regenerate"]
    assert len(lines) == len(rendered.timings) and f"stage {spec.name} lower: " in "\n".join(lines)
    assert not any("stage " in text or "seconds" in text for text in rendered.files.values())


def test_every_stage_says_what_it_takes_and_gives_and_the_list_prints_them_in_order():
    """`stage_list` is the stages in the order `render_all` runs them, each with its docstring (issue 33);
    a stage without one would print an empty description."""
    from adbgen.codegen.regenerate import MODEL_STAGES, STAGES, stage_list

    lines = stage_list()
    names = [line.split(":", 1)[0] for line in lines]
    assert names == ["names", "reduction checks", "models"] + [f"  {s.name}" for s in MODEL_STAGES] + ["index"]
    for stage in (*STAGES, *MODEL_STAGES):
        assert stage.doc.startswith("Takes ") and "gives" in stage.doc, stage.name


def test_a_failing_stage_stops_the_run_before_the_later_stages(monkeypatch):
    """Negative control: a planted failing stage raises (named for its model) and no later stage runs;
    two models of one name are refused by the first stage, before any model is derived."""
    from adbgen.codegen import regenerate
    from adbgen.codegen.regenerate import CheckFailed, MODEL_STAGES, Stage
    from adbgen.families.single_plane import models

    ran = []

    def record(stage):
        return Stage(stage.name, lambda m: (ran.append(stage.name), stage.run(m)))

    def broken(m):
        raise ValueError("planted")

    staged = [record(s) for s in MODEL_STAGES]
    monkeypatch.setattr(regenerate, "MODEL_STAGES", (*staged[:2], Stage("broken", broken), *staged[2:]))
    spec = models.thesis_rotating(1)
    with pytest.raises(CheckFailed, match=f"{spec.name}: ValueError: planted"):
        render_all([spec], ("numba",), run_checks=False)
    assert ran == ["derive", "lower"]
    ran.clear()
    with pytest.raises(CheckFailed, match="two models named"):
        render_all([spec, spec], ("numba",), run_checks=False)
    assert ran == []
