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
