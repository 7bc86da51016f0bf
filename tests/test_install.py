"""`pip install .` (not editable) into a fresh virtual environment, then `adbgen regenerate` from any
directory (issue 8): the templates ship inside the wheel (issue 19: the top-level templates/<target>/,
mapped to the package adbgen.templates).

The wheel is built from a copy of the tracked source files (so no build/ or egg-info lands in the
checkout) with `pip wheel --no-deps --no-build-isolation`; the environment is
`python -m venv --system-site-packages` and sees the running interpreter's site-packages too
(`_see_site_packages`: inside a virtual environment the "system" of a new venv is the base Python,
which need not have numba; issue 33), so the dependencies are the ones the tests run with and nothing
is downloaded; the wheel goes in with `--no-deps --no-index`.  PYTHONPATH is cleared, and the test
checks that the installed adbgen, not the checkout, is what runs.
"""

from __future__ import annotations

import os
import shutil
import site
import subprocess
import sys
import zipfile
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


def _see_site_packages(python: Path, env: dict) -> Path:
    """A .pth file in the venv of `python` listing this interpreter's site-packages (plain paths: their
    own .pth hooks, such as an editable install of this checkout, are not run), so that a venv made from
    inside a virtual environment sees that environment's packages, not only the base Python's."""
    r = _run([python, "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], python.parent, env)
    assert r.returncode == 0, r.stderr
    pth = Path(r.stdout.strip()) / "adbgen-test-dependencies.pth"
    pth.write_text("".join(f"{p}\n" for p in site.getsitepackages() if Path(p).is_dir()))
    return pth


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(venv python, venv adbgen script, clean environment, a folder outside the checkout, the wheel) with
    the wheel of this checkout installed."""
    base = tmp_path_factory.mktemp("install")
    src = base / "src"
    for rel in _tracked_files():
        # benchmarks/' code too (not its results), so that its absence from the wheel is a finding
        if rel.startswith(("adbgen/", "generated/", "templates/")) or rel in ("pyproject.toml", "setup.py", "README.md") \
                or (rel.startswith("benchmarks/") and rel.endswith((".py", ".c"))):
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
    _see_site_packages(python, env)
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
    return python, script, env, elsewhere, wheels[0]


def test_the_wheel_holds_the_templates_and_generated_files(installed):
    python, _, env, elsewhere, _ = installed
    code = ("import importlib.resources as r; "
            "print(sorted(p.name for p in (r.files('adbgen') / 'templates' / 'auto').iterdir())); "
            "print((r.files('adbgen.models') / 'two_plane_rotating' / 'auto' / 'c.two_plane_rotating').is_file())")
    r = _run([python, "-c", code], elsewhere, env)
    assert r.returncode == 0, r.stderr
    assert "user.c.j2" in r.stdout and r.stdout.split()[-1] == "True"


def test_the_wheel_installs_the_models_under_adbgen_only(installed):
    """Issue 24 item 9: no top-level `generated` package in site-packages (it could collide with another
    project's); the models are `adbgen.models.<model>`, which the analysis layer loads by name."""
    python, script, env, elsewhere, _ = installed
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
    _, script, env, elsewhere, _ = installed
    out = elsewhere / "out_n5"
    r = _run([script, "regenerate", "--n", "5", "--out", out], elsewhere, env)
    assert r.returncode == 0, r.stderr[-3000:]
    assert "check  ok" in r.stderr  # the reduction checks ran, then the templates were found
    for name in ("thesis_rotating_n5", "single_plane_fixed_n5"):
        folder = out / name
        assert {"__init__.py", f"{name}.c", f"{name}.h", f"{name}_cvode_main.c"} <= {p.name for p in folder.iterdir()}
        assert (folder / "auto" / f"c.{name}").is_file()


def test_regenerate_scene_from_another_directory(installed):
    _, script, env, elsewhere, _ = installed
    scene = elsewhere / "rig.toml"
    scene.write_text("n = 3\nstiffness = [1.0e4, 1.3e4]\ngravity = true\n")
    out = elsewhere / "out_scene"
    r = _run([script, "regenerate", "--scene", scene, "--name", "rig", "--out", out, "--quiet"], elsewhere, env)
    assert r.returncode == 0, r.stderr[-3000:]
    assert (out / "rig" / "rig.c").is_file() and (out / "rig" / "__init__.py").is_file()


def test_an_installed_adbgen_needs_out(installed):
    """No source checkout to hold generated/: the default output is refused in one line."""
    _, script, env, elsewhere, _ = installed
    r = _run([script, "regenerate", "--skip-checks"], elsewhere, env)
    assert r.returncode == 2 and r.stderr.count("\n") == 1 and "give --out DIR" in r.stderr, r.stderr


def test_the_wheel_ships_no_benchmarks(installed):
    """Issue 33 item 6: the benchmarks (benchmarks/, their C programs, the mutation tool) stay in the
    checkout; the installed `adbgen bench` says in one line that they need one (exit 2)."""
    _, script, env, elsewhere, wheel = installed
    names = zipfile.ZipFile(wheel).namelist()
    assert any(n.startswith("adbgen/cli/") for n in names)  # the listing is the wheel's
    assert [n for n in names if n.startswith(("benchmarks/", "adbgen/bench/"))] == []
    for args in (["bench", "simulate", "--quick"], ["bench"]):
        r = _run([script, *args], elsewhere, env)
        assert r.returncode == 2 and r.stderr.count("\n") == 1, r.stderr
        assert "the benchmarks need a source checkout" in r.stderr, r.stderr
    r = _run([script, "bench", "--help"], elsewhere, env)
    assert r.returncode == 0 and "need a source checkout" in " ".join(r.stdout.split()), r.stdout


def test_a_venv_sees_the_tests_site_packages(tmp_path):
    """The installed venv's dependencies are those of the interpreter running the tests, also when that
    is a virtual environment (issue 33).  Negative control: a venv without the .pth file cannot import
    numba (no site-packages but its own); with it, numba comes from this interpreter's site-packages."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    bare = tmp_path / "bare"
    assert _run([sys.executable, "-m", "venv", "--without-pip", bare], tmp_path, env).returncode == 0
    python = bare / "bin" / "python"
    code = "import numba; print(numba.__file__)"
    assert _run([python, "-c", code], tmp_path, env).returncode != 0
    _see_site_packages(python, env)
    r = _run([python, "-c", code], tmp_path, env)
    assert r.returncode == 0, r.stderr
    ours = [Path(p).resolve() for p in site.getsitepackages() if Path(p).is_dir()]
    assert any(Path(r.stdout.strip()).resolve().is_relative_to(p) for p in ours), (r.stdout, ours)

