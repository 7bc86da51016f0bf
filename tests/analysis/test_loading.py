"""Model loading and values by name (adbgen/analysis/loading.py)."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from adbgen.analysis.loading import AnalysisError, load_model, parse_assignments, parse_value


@pytest.mark.parametrize("text, value", [("0.05", 0.05), ("pi", math.pi), ("3*pi/4", 3 * math.pi / 4),
                                         ("-pi/2", -math.pi / 2), ("2*pi/3 + 0.1", 2 * math.pi / 3 + 0.1),
                                         ("1e-3", 1e-3), ("(1+2)**2", 9.0)])
def test_values(text, value):
    assert parse_value(text) == pytest.approx(value, rel=1e-15)


@pytest.mark.parametrize("text", ["nan", "inf", "1e400", "", "pi*", "__import__('os')", "x", "2**1000",
                                  "1/0", "True"])
def test_bad_values(text):
    with pytest.raises(AnalysisError):
        parse_value(text)


def test_assignments():
    assert parse_assignments(["mu=0.1", "Omega = 2*pi"], "--set") == {"mu": 0.1, "Omega": 2 * math.pi}
    for bad in (["mu"], ["=1"], ["mu=1", "mu=2"]):
        with pytest.raises(AnalysisError):
            parse_assignments(bad, "--set")


def test_by_name(thesis):
    m = thesis[3]
    assert m.name == "thesis_rotating_n3" and m.n_states == 10
    p = m.params({"Omega": 2.5})
    assert p[m.param_names.index("Omega")] == 2.5 and p[m.param_names.index("mu")] == 0.05
    y = m.state({"phi_2": 1.0})
    assert y[m.index("phi_2")] == 1.0 and np.count_nonzero(y) == 1
    assert m.amplitude_indices == (0, 1, 5, 6)
    assert [m.state_names[i] for i in m.angle_indices] == ["phi_1", "phi_2", "phi_3"]
    for bad in (lambda: m.params({"Omeg": 1.0}), lambda: m.state({"psi": 1.0}),
                lambda: m.params({"mu": float("nan")}), lambda: m.state({"x": float("inf")}),
                lambda: m.check_vector(np.zeros(3), "state"), lambda: load_model("nosuch"),
                lambda: load_model("not a name"), lambda: load_model("/nonexistent/dir"),
                lambda: load_model(None)):
        with pytest.raises(AnalysisError):
            bad()


def test_scene_and_folder(tmp_path, monkeypatch):
    """A scene file gets its smallest exact model generated once into the cache; the folder loads too."""
    monkeypatch.setenv("ADBGEN_CACHE", str(tmp_path / "cache"))
    scene = tmp_path / "rotor.toml"
    scene.write_text('n = 2\nball_mass = 0.05\n[speed]\nlaw = "constant"\nomega = 400.0\n')
    m = load_model(scene=scene)
    assert m.name.startswith("scene_") and m.module.N_BALLS == 2 and m.autonomous
    again = load_model(scene=scene)
    assert again.folder == m.folder
    assert load_model(str(m.folder.parent)).name == m.name  # the --out folder holding one model
    bad = tmp_path / "bad.toml"
    bad.write_text("n = 0\n")
    with pytest.raises(AnalysisError, match="scene.n"):
        load_model(scene=bad)
    assert not (tmp_path / "cache" / "scenes").joinpath("x").exists()
    with pytest.raises(AnalysisError, match="not both"):
        load_model("thesis_rotating_n2", scene=scene)


def test_no_sympy_in_the_analysis_layer():
    """The analysis layer runs on generated code only: importing and simulating never imports SymPy."""
    code = ("import sys, math; from adbgen.analysis.loading import load_model; "
            "from adbgen.analysis.simulate import simulate; import adbgen.cli.simulate; "
            "m = load_model('thesis_rotating_n2'); simulate(m, None, {'phi_1': 1.0}, t_end=10.0); "
            "print('sympy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_a_numba_cache_written_under_the_generated_name_loads_in_adbgen(tmp_path):
    """numba keys its cache by the file and rebuilds an entry's environment by importing the name it was
    compiled under: the README's example (`import generated.thesis_rotating_n2`, from the checkout's root)
    wrote entries that crashed a later `adbgen` run elsewhere ("No module named 'generated'").  Both
    processes share a fresh cache folder here; the second runs from another folder, as the CLI does."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    import adbgen

    root = Path(adbgen.__file__).resolve().parents[1]
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    env.pop("PYTHONPATH", None)
    call = "import numpy as np; y = np.zeros(len(m.STATE_NAMES)); print(float(np.sum(m.rhs(0.0, y, m.DEFAULTS))))"
    first = subprocess.run([sys.executable, "-c", f"import generated.thesis_rotating_n2 as m; {call}"], cwd=root,
                           env=env, capture_output=True, text=True, timeout=600)
    assert first.returncode == 0, first.stderr[-800:]
    second = subprocess.run([sys.executable, "-c", "from adbgen.analysis.loading import load_model; "
                             f"m = load_model('thesis_rotating_n2').module; {call}"], cwd=tmp_path, env=env,
                            capture_output=True, text=True, timeout=600)
    assert second.returncode == 0, second.stderr[-800:]
    assert first.stdout == second.stdout
    assert any((tmp_path / "numba").rglob("*.nbi"))  # the first process did write the cache the second read


def test_two_callers_of_a_new_scene_generate_it_once(tmp_path, monkeypatch):
    """Two processes (pytest's workers, two sweeps) asking for one new scene at once: the lock on its cache
    entry makes the second wait and find the model, not generate it again into the same folder.  Negative
    control: without the lock both generate."""
    import time
    import types
    from concurrent.futures import ThreadPoolExecutor

    from adbgen.analysis import loading

    scene = tmp_path / "s.toml"
    scene.write_text("n = 2\n")

    def callers(cache):
        monkeypatch.setenv("ADBGEN_CACHE", str(tmp_path / cache))
        calls = []

        def generate(path, name, out, on_line):
            calls.append(name)
            time.sleep(0.5)
            (out / name).mkdir(parents=True, exist_ok=True)
            (out / name / "__init__.py").write_text("")

        monkeypatch.setattr(loading, "_generate", generate)
        with ThreadPoolExecutor(2) as pool:
            folders = list(pool.map(lambda _: loading._scene_model(scene), range(2)))
        assert folders[0] == folders[1] and (folders[0] / "__init__.py").is_file()
        return len(calls)

    assert callers("locked") == 1
    monkeypatch.setattr(loading, "fcntl", types.SimpleNamespace(flock=lambda *_: None, LOCK_EX=0))
    assert callers("unlocked") == 2


def test_a_model_folder_loads_from_its_numba_cache_after_a_copy_or_a_move(tmp_path):
    """A copied ADBGEN_CACHE (a CI cache, a Docker layer, a colleague's folder) or a moved model folder loads
    and runs from numba's cache in a fresh process: the module's name no longer depends on the folder's
    path (it did: "No module named '_adbgen_model_...'").  Entries compiled under another name (an adbgen
    that named the module by its path, or another importer) are dropped and rebuilt, not crashed on."""
    import os
    import shutil
    from pathlib import Path

    import adbgen

    root = Path(adbgen.__file__).resolve().parents[1]
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}  # numba's cache in the folder
    env.update(PYTHONPATH=str(root), NUMBA_DEBUG_CACHE="1")  # numba says "[cache] data loaded" on a hit
    shutil.copytree(root / "generated" / "thesis_rotating_n2", tmp_path / "a" / "thesis_rotating_n2",
                    ignore=shutil.ignore_patterns("__pycache__"))
    call = ("import numpy as np; y = np.linspace(0.1, 0.8, len(m.STATE_NAMES)); "
            "print(repr(float(np.sum(m.rhs(0.0, y, m.DEFAULTS)))))")

    def run(code):
        out = subprocess.run([sys.executable, "-c", code + "; " + call], cwd=tmp_path, env=env, capture_output=True,
                             text=True, timeout=300)
        assert out.returncode == 0, out.stderr[-800:]
        lines = out.stdout.splitlines()
        return lines[-1], any(line.startswith("[cache] data loaded") for line in lines)

    load = "from adbgen.analysis.loading import load_model; m = load_model({!r}).module"
    # compiled under another module name first (what an older adbgen or another importer leaves behind)
    other, _ = run("from pathlib import Path; from adbgen.codegen.render_and_import import import_numba; "
                f"m = import_numba(Path({str(tmp_path / 'a' / 'thesis_rotating_n2')!r}), '_another_name')")
    assert run(load.format(str(tmp_path / "a"))) == (other, False)  # dropped and compiled again
    shutil.copytree(tmp_path / "a", tmp_path / "copy")
    (tmp_path / "a").rename(tmp_path / "moved")
    for folder in ("copy", "moved"):
        assert run(load.format(str(tmp_path / folder))) == (other, True)  # from the cache the copy carried


def test_a_model_folder_given_relative_to_the_working_folder_compiles(tmp_path, monkeypatch):
    """`adbgen simulate gen/MODEL` (docs/flexible.md): the compiled engine is built from the model's C file
    in a folder of its own; a relative path failed there ('gen/.../MODEL.c: No such file or directory')."""
    import shutil

    from adbgen.analysis.simulate import simulate

    thesis = load_model("thesis_rotating_n2")
    shutil.copytree(thesis.folder, tmp_path / "gen" / thesis.name, ignore=shutil.ignore_patterns("__pycache__"))
    monkeypatch.setenv("ADBGEN_CACHE", str(tmp_path / "cache"))  # a fresh build, not a cached library
    monkeypatch.chdir(tmp_path)
    m = load_model(f"gen/{thesis.name}")
    assert m.folder == tmp_path / "gen" / thesis.name
    sim = simulate(m, m.params(), {"phi_1": 1.0}, t_end=1.0, engine="cyrk-dop853")
    assert sim.status == "success"
