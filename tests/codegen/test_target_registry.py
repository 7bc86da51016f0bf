"""One suite for the target registry (adbgen/codegen/targets/__init__.py: REGISTRY, register; issue 33 item
5): every registered target is put through every check, so a new target is tested by registering it.  A
toy target registered from the test (tests/plugins/pylist, the registry's own `register`) runs the
whole suite, and the same toy with a dialect that transposes the Jacobian fails it (the negative
control).  What each target's files compute is the target's own proof (codegen/passes/proof.py); here the
suite runs it on the thesis model n = 2, with every check below the proof's frame.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from adbgen.codegen import compiler, targets
from adbgen.codegen.ir.model import KERNELS
from adbgen.codegen.passes import proof as proofs
from adbgen.codegen.passes.checks import Reference
from adbgen.codegen.render import render_model
from adbgen.codegen.spec import build as build_ir
from adbgen.families.single_plane import models

from toolchain import require_tool

PYLIST = Path(__file__).parents[1] / "plugins" / "pylist" / "target.py"


@pytest.fixture(scope="module")
def thesis2():
    spec = models.thesis_rotating(2)
    system = spec.system()
    ir = build_ir(spec, system)
    return ir, Reference.of(system)


@pytest.fixture(autouse=True)
def fresh_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("ADBGEN_CACHE", str(tmp_path / "cache"))  # no verdict cached from another run


def _tools():
    for what in ("gcc", "sundials", "auto"):
        why = compiler.missing(what)
        require_tool(why is None, why or what)


# ------------------------------------------------------------------ the checks


def check_declares_its_files(name, thesis2):
    """Its templates exist in its folder, its output paths are its own (no two targets write one path),
    and a target with a printer prints kernels the intermediate form has."""
    target = targets.get(name)
    assert target.name == name and target.files, name
    for template, output in target.files:
        assert (target.template_folder / Path(template).relative_to(Path(template).parts[0])).is_file(), \
            (name, template)
        assert "{name}" in output, (name, output)
    mine = {out for _, out in target.files}
    for other in targets.names():
        if other != name:
            assert not mine & {out for _, out in targets.get(other).files}, (name, other)
    if target.printer is not None:
        assert target.functions and set(target.functions) <= set(KERNELS), (name, target.functions)


def check_renders_deterministically(name, thesis2):
    """It renders every file it declares for the model (none when it says why it skips it), twice the
    same bytes."""
    ir, _ = thesis2
    files = render_model(ir, (name,))
    target = targets.get(name)
    if target.skip_reason(ir):
        assert files == {}
        return
    expected = {out.format(name=target.model_for(ir).name) for _, out in target.files}
    assert set(files) <= expected and files, (name, sorted(files), sorted(expected))
    assert all(text.strip() for text in files.values()), name  # a blank render writes no file
    assert render_model(ir, (name,)) == files


def check_files_are_proven(name, thesis2):
    """Its own proof passes on its files (what they compute against the symbolic model)."""
    _tools()
    ir, ref = thesis2
    files = render_model(ir, (name,))
    out = proofs.prove_model(ir, files, (name,), "loops", ref)
    assert out["targets"] == ((name,) if not targets.get(name).skip_reason(ir) else ())


SUITE = (check_declares_its_files, check_renders_deterministically, check_files_are_proven)


@pytest.mark.parametrize("name, check", [pytest.param(n, c, id=f"{c.__name__[len('check_'):]}[{n}]")
                                         for c in SUITE for n in targets.names()])
def test_registered_target(name, check, thesis2):
    check(name, thesis2)


# ------------------------------------------------------------------ a toy target through the whole suite


def _pylist():
    spec = importlib.util.spec_from_file_location("_adbgen_registry_pylist", PYLIST)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def toy():
    module = _pylist()
    targets.register(module.TARGET)
    yield module
    targets.unregister(module.TARGET.name)


def test_a_toy_target_registered_from_a_test_runs_the_whole_suite(toy, thesis2):
    assert "pylist" in targets.names() and targets.get("pylist") is toy.TARGET
    for check in SUITE:
        check("pylist", thesis2)
    assert "thesis_rotating_n2/thesis_rotating_n2_pylist.py" in render_model(thesis2[0], ("pylist",))


def test_a_broken_toy_target_fails_the_suite(toy, thesis2, monkeypatch):
    """Negative control: the toy's dialect writing jac entries transposed renders, but its proof refuses."""
    entry = toy.ListDialect.entry
    monkeypatch.setattr(toy.ListDialect, "entry",
                        lambda self, row, col: entry(self, row, col) if col is None else entry(self, col, row))
    check_declares_its_files("pylist", thesis2)
    with pytest.raises(proofs.ProofFailed, match="pylist jac differs"):
        check_files_are_proven("pylist", thesis2)


def test_the_suite_ran_on_every_registered_target_and_no_toy_is_left():
    assert targets.names() == tuple(targets.REGISTRY) and "pylist" not in targets.names()
    assert {"numba", "c", "cvode", "auto", "taylor", "lanes"} <= set(targets.names())
