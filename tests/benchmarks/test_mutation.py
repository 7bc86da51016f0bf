"""adbgen bench mutation: the plan's order and resuming (the mutants themselves: tests/codegen/test_mutation_sample.py)."""

import json

from benchmarks.mutation import Mutant, _resumed, blank_hashes, files_of, interleaved


def _m(file, k):
    return Mutant(f"{file}:{k}", file, "a", "b", "kind")


def test_interleaved_takes_one_mutant_of_each_file_in_turn():
    plan = [_m("x.py", 0), _m("x.py", 1), _m("x.py", 2), _m("y.j2", 0), _m("z.j2", 0), _m("z.j2", 1)]
    out = interleaved(plan)
    assert [m.id for m in out] == ["x.py:0", "y.j2:0", "z.j2:0", "x.py:1", "z.j2:1", "x.py:2"]
    assert sorted(m.id for m in out) == sorted(m.id for m in plan)  # a permutation: nothing lost or doubled
    assert interleaved([]) == []


def test_a_resumed_run_keeps_what_the_file_holds_but_survivors_and_crashes(tmp_path):
    out = tmp_path / "mutation.json"
    assert _resumed(out) == []
    results = [{"id": "x.py:0", "status": "refused"}, {"id": "x.py:1", "status": "survived"},
               {"id": "x.py:2", "status": "crashed"}, {"id": "y.j2:0", "status": "equivalent"}]
    out.write_text(json.dumps({"results": results, "seconds": 3.0}))
    assert [r["id"] for r in _resumed(out)] == ["x.py:0", "y.j2:0"]


def test_the_source_hash_is_blanked_and_nothing_else(tmp_path):
    (tmp_path / "m").mkdir()
    (tmp_path / "m" / "m.h").write_text('#define M_SOURCE_HASH "0123456789abcdef"\n#define M_N 0123456789abcdef\n')
    (tmp_path / "m" / "__init__.py").write_text("SOURCE_HASH = '0123456789abcdef'\n")
    files = blank_hashes(files_of(tmp_path))
    assert files_of(tmp_path)["m/__init__.py"] == "SOURCE_HASH = '0123456789abcdef'\n"  # raw unless blanked
    assert files == {"m/m.h": '#define M_SOURCE_HASH "<hash>"\n#define M_N 0123456789abcdef\n',
                     "m/__init__.py": "SOURCE_HASH = '<hash>'\n"}


def test_every_runtime_mutant_changes_its_file_once_and_names_existing_tests():
    """The mutants of the engines and the orbit code (issue 33) apply to the tree as it is: each `old` occurs
    once in its file (Mutant.apply refuses otherwise), and each names test files that exist."""
    from pathlib import Path

    from benchmarks.mutation import DRIVER_TESTS, ROOT, RUNTIME, driver_mutants

    files = set()
    for m in RUNTIME:
        text = (ROOT / m.file).read_text()
        assert m.apply(text) != text, m.id
        files.add(m.file)
        assert all((ROOT / a).is_file() for a in m.tests if a.startswith("tests/")), m.id
    # the four: a Butcher coefficient, an error-norm term, an event bracket, a monodromy column
    assert {"adbgen/analysis/engines/dop853_tableau.h", "adbgen/analysis/engines/rk_dop853.h",
            "adbgen/analysis/engines/event_measures.h", "adbgen/analysis/orbits/shooting.py"} <= files
    assert len({m.id for m in RUNTIME}) == len(RUNTIME)
    sampled = driver_mutants(ROOT, 1, 20)
    assert [m.id for m in sampled] == [m.id for m in driver_mutants(ROOT, 1, 20)]  # seeded: the same plan
    assert {Path(m.file).suffix for m in sampled} == {".c", ".h"} and all(m.tests for m in sampled)
    assert all((ROOT / a.split("::")[0]).is_file() for t in DRIVER_TESTS.values() for a in t if a.startswith("tests/"))


def _toy_scratch(tmp_path):
    """A scratch copy of a tiny tree: adbgen/toy.py (double, unused) and tests/test_toy.py (double's test)."""
    from benchmarks.mutation import Scratch

    src = tmp_path / "src"
    (src / "adbgen").mkdir(parents=True)
    (src / "tests").mkdir()
    (src / "adbgen" / "__init__.py").write_text("")
    (src / "adbgen" / "toy.py").write_text("def double(x):\n    return 2 * x\n\n\ndef unused(x):\n    return x + 1\n")
    (src / "tests" / "test_toy.py").write_text("from adbgen.toy import double\n\n\ndef test_double():\n"
                                               "    assert double(3) == 6\n")
    return src, Scratch(root=src, folder=tmp_path / "scratch")


def test_a_runtime_mutant_is_caught_by_a_failing_test_and_survives_a_passing_one(tmp_path):
    """classify_runtime on a tiny tree: the mutant a test sees is caught (naming the test), the one no test
    sees survives (the negative control of the classification)."""
    from benchmarks.mutation import classify_runtime

    src, scratch = _toy_scratch(tmp_path)
    seen = Mutant("seen", "adbgen/toy.py", "return 2 * x", "return 3 * x", "runtime", (), ("tests/test_toy.py",))
    unseen = Mutant("unseen", "adbgen/toy.py", "return x + 1", "return x - 1", "runtime", (), ("tests/test_toy.py",))
    caught = classify_runtime(scratch, seen)
    assert caught["status"] == "caught" and caught["test"] == "tests/test_toy.py::test_double"
    assert classify_runtime(scratch, unseen)["status"] == "survived"
    assert (tmp_path / "scratch" / "adbgen" / "toy.py").read_text() == (src / "adbgen" / "toy.py").read_text()


def test_a_runtime_mutant_whose_tests_die_of_a_signal_is_caught_naming_the_test(tmp_path):
    """A mutant that kills the test process (as a driver's segmentation fault does: sundials_driver.c's
    ERKStepFree on CVODE's memory) fails the suite: caught, naming the test faulthandler reports and the signal."""
    from benchmarks.mutation import classify_runtime

    _, scratch = _toy_scratch(tmp_path)
    dies = Mutant("dies", "adbgen/toy.py", "return 2 * x", "__import__('os').abort()", "runtime", (),
                  ("tests/test_toy.py",))
    caught = classify_runtime(scratch, dies)
    assert caught["status"] == "caught"
    assert caught["test"] == "tests/test_toy.py::test_double (the test process died of SIGABRT)"
