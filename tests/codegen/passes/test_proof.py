"""Every emitted file proven before it is written (issue 20): the frame (`codegen.passes.proof`) and what it refuses.

The mutants of the CI sample (test_mutation_sample.py) show each target's proof refusing real one-line
mistakes through the command line; here, in-process: the committed models' files pass, a wrong file
is refused naming its target, any exception in a proof is the one-line refusal, a target without a
proof is refused, a tool that is missing refuses rather than writing unproven files, the loop form
that cannot be had is an error naming the ball and the term, the verdict cache keys on the files,
and AUTO's constants parse as AUTO reads them.
"""

from __future__ import annotations

import dataclasses

import pytest
import sympy as sp

from adbgen import cli
from adbgen.codegen import compiler, targets
from adbgen.codegen.passes import ball_split as balls, proof as proofs
from adbgen.codegen.passes.checks import Reference
from adbgen.codegen.passes.lowering import LoopFormError
from adbgen.codegen.render import render_model
from adbgen.codegen.spec import build as build_ir
from adbgen.codegen.targets.auto.prove import parse_constants
from adbgen.families.single_plane import models

from toolchain import require_tool


@pytest.fixture(scope="module")
def thesis2():
    spec = models.thesis_rotating(2)
    system = spec.system()
    ir = build_ir(spec, system)
    return ir, Reference.of(system), render_model(ir)


@pytest.fixture(autouse=True)
def fresh_cache(tmp_path, monkeypatch):
    monkeypatch.setenv("ADBGEN_CACHE", str(tmp_path / "cache"))


def _tools():
    for what in ("gcc", "sundials", "auto"):
        why = compiler.missing(what)
        require_tool(why is None, why or what)


def test_the_files_of_a_model_are_proven_and_the_verdict_cached(thesis2):
    _tools()
    ir, ref, files = thesis2
    first = proofs.prove_model(ir, files, None, "loops", ref)
    assert first["targets"] == ("numba", "c", "cvode", "auto", "taylor", "lanes") and not first["cached"]
    assert proofs.prove_model(ir, files, None, "loops", ref)["cached"]
    # the key is the files' text: a changed file is proven again (and refused here)
    rel = f"{ir.name}/{ir.name}.c"
    wrong = dict(files, **{rel: files[rel].replace("_defaults[THESIS_ROTATING_N2_N_PARAMS] = {\n    4.0,",
                                                     "_defaults[THESIS_ROTATING_N2_N_PARAMS] = {\n    4.5,")})
    assert wrong[rel] != files[rel]
    with pytest.raises(proofs.ProofFailed, match=r"^thesis_rotating_n2: c files: thesis_rotating_n2_defaults is "):
        proofs.prove_model(ir, wrong, ("c",), "loops", ref)


def test_an_exception_in_a_proof_is_the_one_line_refusal(thesis2, monkeypatch, tmp_path, capsys):
    def broken(self, proof):
        raise ZeroDivisionError("float division by zero\nsecond line")

    monkeypatch.setattr(type(targets.get("numba")), "prove", broken)
    ir, ref, files = thesis2
    with pytest.raises(proofs.ProofFailed, match=r"^thesis_rotating_n2: numba files: ZeroDivisionError: float "
                                                 r"division by zero second line$"):
        proofs.prove_model(ir, files, ("numba",), "loops", ref)
    out = tmp_path / "out"
    code = cli.main(["regenerate", "--n", "2", "--family", "single-plane", "--targets", "numba", "--skip-checks",
                     "--quiet", "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and err[0].startswith("adbgen: error: thesis_rotating_n2: numba files: "
                                                             "ZeroDivisionError"), err
    assert not out.exists()


def test_a_target_without_a_proof_is_refused(thesis2):
    ir, ref, files = thesis2
    bare = targets.Target(name="bare", files=(("bare/x.j2", "{name}/x.txt"),))
    targets.register(bare)
    try:
        with pytest.raises(proofs.ProofFailed, match=r"^thesis_rotating_n2: bare files: target 'bare' has no proof of "
                           r"its files, and nothing unproven is written: give it a prove\(proof\) method "
                           r"\(adbgen/codegen/targets/bare/prove.py; .*or leave it out with --targets$"):
            proofs.prove_model(ir, files, ("bare",), "loops", ref)
    finally:
        targets.unregister("bare")


def test_a_missing_tool_refuses_instead_of_writing_unproven_files(thesis2, monkeypatch):
    ir, ref, files = thesis2
    monkeypatch.setattr(compiler, "missing", lambda what: "SUNDIALS CVODE headers not found" if what == "sundials" else None)
    with pytest.raises(proofs.ProofFailed, match=r"cvode files: cannot prove the cvode files: SUNDIALS CVODE headers "
                                                 r"not found; install it, or leave the target out \(--targets\)"):
        proofs.prove_model(ir, files, ("cvode",), "loops", ref)


def test_the_form_requested_is_the_form_produced(monkeypatch):
    """A per-ball split that fails is an error naming the ball and the term, never the unrolled form."""
    spec = models.thesis_rotating(3)
    system = spec.system()
    original = balls.split

    def third_ball_differs(coords, core, leaves, mass, f, *args):
        f = list(f)
        f[leaves[2]] = f[leaves[2]] * sp.Rational(1001, 1000)
        return original(coords, core, leaves, mass, f, *args)

    monkeypatch.setattr("adbgen.codegen.passes.lowering.split_balls", third_ball_differs)
    with pytest.raises(LoopFormError, match=r"^thesis_rotating_n3: the loop form was requested, but the balls have no "
                                            r"per-ball split: ball 3's block differs from ball 1's: "):
        build_ir(spec, system, form="loops")
    assert build_ir(spec, system, form="unrolled").form == "unrolled"
    # and the proof's own check of the form (a lowering that produced another form than asked)
    ir = build_ir(spec, system, form="unrolled")
    with pytest.raises(proofs.ProofFailed, match="the loops form was requested but the unrolled form was produced"):
        proofs.check_form(ir, "loops")


def test_auto_constants_parse_as_auto_reads_them():
    text = ("# comment, with a comma\nNDIM = 8, IPS = 1, IRS = 0, ILP = 1\nICP = [1, 6]\n"
            "UZSTOP = {1: [0.5, 6.0]}\ns = 'thesis_rotating_n2'\nSP = ['BP0']\nDS = -0.001, DSMIN = 1e-06\n")
    c = parse_constants(text)
    assert c == {"NDIM": 8, "IPS": 1, "IRS": 0, "ILP": 1, "ICP": [1, 6], "UZSTOP": {1: [0.5, 6.0]},
                 "s": "thesis_rotating_n2", "SP": ["BP0"], "DS": -0.001, "DSMIN": 1e-06}
    with pytest.raises(ValueError, match="given twice"):
        parse_constants("NDIM = 8, NDIM = 9\n")
    with pytest.raises(ValueError, match="not 'KEY = value'"):
        parse_constants("NDIM 8\n")


def test_guard_cells_see_a_write_past_the_end():
    g = proofs.Guarded(4)
    assert g.intact()
    g.buffer[proofs.GUARD + 4] = 0.0
    assert not g.intact()


def test_exchange_symmetry_is_bitwise(thesis2):
    ir, ref, files = thesis2
    import tempfile
    from pathlib import Path

    p = proofs.Proof(ir, files, Path(tempfile.gettempdir()), ref, "loops", target="test")
    rhs = p.programs()["rhs"]
    assert p.exchange_bitwise("rhs", rhs) == 3  # one identical-balls exchange for n = 2, three states each

    def nudged(t, y, q):  # one rounding's difference between the two balls
        f = rhs(t, y, q).copy()
        f[-1] = f[-1] * (1 + 2 ** -52)
        return f
    with pytest.raises(proofs.ProofFailed, match="breaks the exchange symmetry"):
        p.exchange_bitwise("rhs", nudged)


def test_a_crash_in_compiled_code_is_refused_quoting_what_it_printed(thesis2, capfd):
    """Emitted code that aborts (glibc's fortify check, say) is refused by name with the line it printed,
    and nothing reaches regenerate's own stderr, whose one line is the refusal."""
    ir, ref, files = thesis2
    import ctypes
    import tempfile
    from pathlib import Path

    p = proofs.Proof(ir, files, Path(tempfile.gettempdir()), ref, "loops", target="test")

    def aborts():
        libc = ctypes.CDLL(None)
        libc.write(2, b"*** buffer overflow detected ***: terminated\n", 45)
        libc.abort()
    with pytest.raises(proofs.ProofFailed, match=r"the library crashed \(SIGABRT\), printing "
                                                 r"'\*\*\* buffer overflow detected \*\*\*: terminated'$"):
        p.isolated("the library", aborts)
    assert capfd.readouterr() == ("", "")
    p.isolated("the library", lambda: None)  # negative control: a clean run passes, silently


def test_a_continuum_without_its_regularisation_is_refused(monkeypatch):
    """FAMILY_SIGMA = 0 writes AUTO's singular problem on thesis (3.6)'s continuum (n >= 3) while every
    value func computes still matches: the proof refuses the decision itself (a mutant once survived)."""
    _tools()
    from adbgen.codegen.targets import auto

    spec = models.thesis_rotating(3)
    system = spec.system()
    ir = build_ir(spec, system)
    ref = Reference.of(system)
    monkeypatch.setattr(auto, "FAMILY_SIGMA", 0.0)
    with pytest.raises(proofs.ProofFailed, match=r"FAMILY_SIGMA = 0\.0 must be a positive number"):
        proofs.prove_model(ir, render_model(ir), ("auto",), "loops", ref)
    monkeypatch.setattr(auto, "FAMILY_SIGMA", 1.0)  # negative control: the committed value is proven
    proofs.prove_model(ir, render_model(ir), ("auto",), "loops", ref)


def test_an_array_the_header_does_not_declare_is_refused(thesis2):
    """The library still exports it (ctypes finds it), but C code including the header cannot use it: the
    probe refers to every array of the contract through a pointer of its declared type (a mutant once
    survived dropping this declaration)."""
    _tools()
    ir, ref, files = thesis2
    header = "thesis_rotating_n2/thesis_rotating_n2.h"
    line = next(ln for ln in files[header].splitlines(keepends=True) if "_symmetry_params[" in ln)
    dropped = {**files, header: files[header].replace(line, "")}
    with pytest.raises(proofs.ProofFailed, match=r"thesis_rotating_n2: c files: .*thesis_rotating_n2_symmetry_params"):
        proofs.prove_model(ir, dropped, ("c",), "loops", ref)
    proofs.prove_model(ir, files, ("c",), "loops", ref)  # negative control: the header as rendered passes
