"""adbgen bench mutation: the plan's order and resuming (the mutants themselves: tests/codegen/test_mutation_sample.py)."""

import json

from adbgen.bench.mutation import Mutant, _resumed, interleaved


def _m(file, k):
    return Mutant(f"{file}:{k}", file, "a", "b", "kind")


def test_interleaved_takes_one_mutant_of_each_file_in_turn():
    plan = [_m("x.py", 0), _m("x.py", 1), _m("x.py", 2), _m("y.j2", 0), _m("z.j2", 0), _m("z.j2", 1)]
    out = interleaved(plan)
    assert [m.id for m in out] == ["x.py:0", "y.j2:0", "z.j2:0", "x.py:1", "z.j2:1", "x.py:2"]
    assert sorted(m.id for m in out) == sorted(m.id for m in plan)  # a permutation: nothing lost or doubled
    assert interleaved([]) == []


def test_a_resumed_run_keeps_what_the_file_holds(tmp_path):
    out = tmp_path / "mutation.json"
    assert _resumed(out) == []
    out.write_text(json.dumps({"results": [{"id": "x.py:0", "status": "refused"}], "seconds": 3.0}))
    assert _resumed(out) == [{"id": "x.py:0", "status": "refused"}]
