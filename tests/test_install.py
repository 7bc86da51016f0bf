"""`pip install .` (not editable) into a fresh virtual environment, then `adbgen regenerate` from any
directory (issue 8): the templates ship inside the wheel (issue 19: the top-level templates/<target>/,
mapped to the package adbgen.templates).

The wheel is built from a copy of the tracked source files (so no build/ or egg-info lands in the
checkout) with `pip wheel --no-deps --no-build-isolation`; the environment is
`python -m venv --system-site-packages` (the dependencies come from the system, nothing is
downloaded) and the wheel goes in with `--no-deps --no-index`.  PYTHONPATH is cleared, and the test
checks that the installed adbgen, not the checkout, is what runs.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import adbgen

ROOT = Path(adbgen.__file__).resolve().parents[1]


def _tracked_files() -> list[str]:
    r = subprocess.run(["git", "ls-files", "-z"], cwd=ROOT, capture_output=True, text=True)
    if r.returncode == 0 and r.stdout:
        return [f for f in r.stdout.split("\0") if f]
    return [p.relative_to(ROOT).as_posix() for top in ("adbgen", "generated", "templates") for p in (ROOT / top).rglob("*")
            if p.is_file() and "__pycache__" not in p.parts] + ["pyproject.toml", "setup.py", "README.md"]


def _run(args, cwd, env, timeout=900) -> subprocess.CompletedProcess:
    r = subprocess.run([str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)
    return r


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(venv python, venv adbgen script, clean environment) with the wheel of this checkout installed."""
    base = tmp_path_factory.mktemp("install")
    src = base / "src"
    for rel in _tracked_files():
        if rel.startswith(("adbgen/", "generated/", "templates/")) or rel in ("pyproject.toml", "setup.py", "README.md"):
            (src / rel).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / rel, src / rel)
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    r = _run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", base / "dist", src],
             base, env)
    assert r.returncode == 0, r.stdout + r.stderr
    wheels = list((base / "dist").glob("adbgen-*.whl"))
    assert len(wheels) == 1, wheels
    r = _run([sys.executable, "-m", "venv", "--system-site-packages", base / "venv"], base, env)
    assert r.returncode == 0, r.stderr
    python, script = base / "venv" / "bin" / "python", base / "venv" / "bin" / "adbgen"
    r = _run([python, "-m", "pip", "install", "--no-deps", "--no-index", "-q", wheels[0]], base, env)
    assert r.returncode == 0, r.stdout + r.stderr
    elsewhere = base / "elsewhere"
    elsewhere.mkdir()
    r = _run([python, "-c", "import adbgen, adbgen.codegen.targets.auto as a; print(adbgen.__file__); print(a.TARGET.template_folder)"],
             elsewhere, env)
    assert r.returncode == 0, r.stderr
    module, templates = r.stdout.split()
    venv = (base / "venv").resolve()
    assert Path(module).resolve().is_relative_to(venv), f"the checkout, not the wheel, was imported: {module}"
    assert Path(templates).resolve().is_relative_to(venv) and (Path(templates) / "user.c.j2").is_file()
    return python, script, env, elsewhere


def test_the_wheel_holds_the_templates_and_generated_files(installed):
    python, _, env, elsewhere = installed
    code = ("import importlib.resources as r; "
            "print(sorted(p.name for p in (r.files('adbgen') / 'templates' / 'auto').iterdir())); "
            "print((r.files('adbgen.models') / 'two_plane_rotating' / 'auto' / 'c.two_plane_rotating').is_file())")
    r = _run([python, "-c", code], elsewhere, env)
    assert r.returncode == 0, r.stderr
    assert "user.c.j2" in r.stdout and r.stdout.split()[-1] == "True"


def test_the_wheel_installs_the_models_under_adbgen_only(installed):
    """Issue 24 item 9: no top-level `generated` package in site-packages (it could collide with another
    project's); the models are `adbgen.models.<model>`, which the analysis layer loads by name."""
    python, script, env, elsewhere = installed
    code = ("import sysconfig, adbgen.models as m, adbgen.models.thesis_rotating_n2 as t; "
            "print(sysconfig.get_paths()['purelib']); print(t.NAME, t.__file__); print(len(m.names()))")
    r = _run([python, "-c", code], elsewhere, env)
    assert r.returncode == 0, r.stderr
    site, model, count = r.stdout.splitlines()
    assert (Path(site) / "adbgen").is_dir() and not (Path(site) / "generated").exists()
    name, path = model.split()
    assert name == "thesis_rotating_n2" and Path(path).resolve().is_relative_to((elsewhere.parent / "venv").resolve())
    assert int(count) == len(list((ROOT / "generated").glob("*/__init__.py")))
    r = _run([script, "stability", "thesis_rotating_n2", "--json"], elsewhere, env)
    assert r.returncode == 0 and '"classification": "stable"' in r.stdout, r.stderr[-2000:]


def test_regenerate_n5_from_another_directory(installed):
    _, script, env, elsewhere = installed
    out = elsewhere / "out_n5"
    r = _run([script, "regenerate", "--n", "5", "--out", out], elsewhere, env)
    assert r.returncode == 0, r.stderr[-3000:]
    assert "check  ok" in r.stderr  # the reduction checks ran, then the templates were found
    for name in ("thesis_rotating_n5", "single_plane_fixed_n5"):
        folder = out / name
        assert {"__init__.py", f"{name}.c", f"{name}.h", f"{name}_cvode_main.c"} <= {p.name for p in folder.iterdir()}
        assert (folder / "auto" / f"c.{name}").is_file()


def test_regenerate_scene_from_another_directory(installed):
    _, script, env, elsewhere = installed
    scene = elsewhere / "rig.toml"
    scene.write_text("n = 3\nstiffness = [1.0e4, 1.3e4]\ngravity = true\n")
    out = elsewhere / "out_scene"
    r = _run([script, "regenerate", "--scene", scene, "--name", "rig", "--out", out, "--quiet"], elsewhere, env)
    assert r.returncode == 0, r.stderr[-3000:]
    assert (out / "rig" / "rig.c").is_file() and (out / "rig" / "__init__.py").is_file()


def test_an_installed_adbgen_needs_out(installed):
    """No source checkout to hold generated/: the default output is refused in one line."""
    _, script, env, elsewhere = installed
    r = _run([script, "regenerate", "--skip-checks"], elsewhere, env)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "give --out DIR" in r.stderr, r.stderr


def test_the_wheel_holds_the_benchmarks_c_programs(installed):
    python, _, env, elsewhere = installed
    code = ("import adbgen.bench.timing as t; "
            "print(sorted(p.name for p in t.C_DIR.iterdir() if p.suffix == '.c')); print(t.C_DIR)")
    r = _run([python, "-c", code], elsewhere, env)
    assert r.returncode == 0, r.stderr
    names, folder = r.stdout.splitlines()
    shipped = sorted(p.name for p in (Path(__file__).resolve().parents[1] / "adbgen" / "bench" / "c").glob("*.c"))
    assert len(shipped) >= 3 and names == str(shipped)
    assert Path(folder).resolve().is_relative_to((elsewhere.parent / "venv").resolve())
