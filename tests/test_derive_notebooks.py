"""The derivation notebooks of derive/: each executes from a clean kernel (its asserts are the checks),
and the rendered copy committed beside each source is current (`adbgen notebooks --check`)."""

import os
import shutil

from adbgen import notebooks
from adbgen.cli import main

SOURCES = notebooks.sources()
EXPECTED = ["01_single_plane_lagrange", "02_dimensionless_and_rotating_frame", "03_steady_states_and_stability",
            "04_two_plane_model", "05_d4_normal_form", "06_generated_code_in_use"]


def test_the_six_notebooks_are_there():
    assert [p.stem for p in SOURCES] == EXPECTED


def test_rendered_copies_are_current(capsys):
    assert notebooks.stale(SOURCES) == []
    assert main(["notebooks", "--check"]) == 0


def test_check_names_a_stale_or_missing_copy(tmp_path, monkeypatch, capsys):
    """Negative control: a source edited after rendering, and a source never rendered, are reported."""
    for src in SOURCES[:2]:
        shutil.copy(src, tmp_path / src.name)
        shutil.copy(notebooks.rendered_path(src), tmp_path / notebooks.rendered_path(src).name)
    edited = tmp_path / SOURCES[0].name
    edited.write_text(edited.read_text() + "\n# an edit\n")
    (tmp_path / "07_new.py").write_text("# %%\nprint(1)\n")
    monkeypatch.setattr(notebooks, "derive_dir", lambda: tmp_path)
    assert main(["notebooks", "--check"]) == 1
    out = capsys.readouterr().out
    assert f"{SOURCES[0].stem}.ipynb: stale" in out
    assert "07_new.ipynb: missing" in out
    assert SOURCES[1].stem not in out


def test_unknown_notebook_is_one_line_error(capsys):
    assert main(["notebooks", "--check", "--only", "99"]) == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_a_failing_assertion_fails_the_run(tmp_path, monkeypatch, capsys):
    """A notebook whose check stops matching fails: exit 1, the notebook and the assertion named."""
    (tmp_path / "01_fails.py").write_text("# %%\nx = 1\n\n# %%\nassert x == 2, 'x should be 2'\n")
    monkeypatch.setattr(notebooks, "derive_dir", lambda: tmp_path)
    assert main(["notebooks", "--run"]) == 1
    err = capsys.readouterr().err
    assert "01_fails.py" in err and "x should be 2" in err
    assert not (tmp_path / "01_fails.ipynb").exists()


def test_every_notebook_executes_from_a_clean_kernel():
    """All six, two kernels at a time (as `adbgen notebooks --run`); any error or failed assertion fails."""
    failures = [f"{src.name}: {result}" for src, result, _ in notebooks.run_all(SOURCES, timeout=600, jobs=2)
                if isinstance(result, notebooks.NotebookError)]
    assert not failures, "\n".join(failures)


def test_consecutive_prints_become_one_output():
    """The kernel chunks a cell's prints by timing; the rendered copy holds them as one stream output."""
    import nbformat

    outs = [nbformat.v4.new_output("stream", name="stdout", text="a\n"),
            nbformat.v4.new_output("stream", name="stdout", text="b\n"),
            nbformat.v4.new_output("stream", name="stderr", text="w\n"),
            nbformat.v4.new_output("display_data", data={"text/plain": "x"}),
            nbformat.v4.new_output("stream", name="stdout", text="c\n")]
    merged = notebooks._coalesce_streams(outs)
    assert [(o.output_type, o.get("name"), o.get("text")) for o in merged] == [
        ("stream", "stdout", "a\nb\n"), ("stream", "stderr", "w\n"), ("display_data", None, None),
        ("stream", "stdout", "c\n")]


def test_running_a_notebook_leaves_this_process_environment_alone(tmp_path, monkeypatch):
    """The kernel gets the checkout on its PYTHONPATH; the caller's environment (inherited by later
    subprocesses, e.g. the install test's venv) is unchanged, and the kernel runs in derive/."""
    (tmp_path / "01_env.py").write_text("# %%\nimport os, sys\nprint(os.getcwd())\nprint(sys.path[:3])\n")
    monkeypatch.setattr(notebooks, "derive_dir", lambda: tmp_path)
    before = dict(os.environ)
    [(src, nb, _)] = list(notebooks.run_all(notebooks.sources(), jobs=1))
    assert dict(os.environ) == before
    out = nb.cells[0].outputs[0]["text"]
    assert str(tmp_path) in out.splitlines()[0] and str(tmp_path.parent) in out.splitlines()[1]
