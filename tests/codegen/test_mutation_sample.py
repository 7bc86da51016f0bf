"""The CI sample of issue 20: 30 representative one-line mutants of code generation (every one the issue
names among them: the C Jacobian transposed, the C jac_p row stride, the CVODE adaptor's non-finite check
skipping an element or reading past the end, its SUNMatrix store transposed, the analytic Jacobian
dropped, the AUTO continuum term with * and / swapped, the amplitude ICP off by one, IPLT changed,
stpnt copying nothing, numba's params() returning DEFAULTS, its jac wrapper passing out.T, a broken
per-ball split, the ball-invariant print order broken), each applied to a scratch copy of the tree
(`benchmarks.mutation.Scratch`), must be refused by `adbgen regenerate` before writing: exit 2, one
line `adbgen: error: <model>: ...`, no output folder.  Small models (n = 2, n = 3 for the continuum),
only the target each mutant is in, reduction checks skipped (the lowering check and the proofs run).

The unmutated scratch tree regenerates the same runs (the negative control: the refusals are the
mutants'), `adbgen bench mutation --sample` runs the same set as a benchmark.
"""

from __future__ import annotations

import pytest

from benchmarks.mutation import SAMPLE, Scratch
from adbgen.codegen import compiler

from toolchain import require_tool

NAMED = 14  # the first fourteen of SAMPLE are the mutants issue 20 names


@pytest.fixture(scope="module")
def scratch():
    for what in ("gcc", "sundials", "auto"):
        why = compiler.missing(what)
        require_tool(why is None, why or what)
    s = Scratch()
    yield s
    s.close()


def test_the_sample_is_thirty_distinct_mutants_of_the_tree():
    assert len(SAMPLE) == 30 and len({m.id for m in SAMPLE}) == 30
    assert {m.file.split("/")[0] for m in SAMPLE} == {"adbgen", "templates"}
    for m in SAMPLE:  # each applies to the tree as it is (exactly one occurrence)
        from benchmarks.mutation import ROOT

        assert m.apply((ROOT / m.file).read_text()) != (ROOT / m.file).read_text()


@pytest.mark.parametrize("args", sorted({m.args for m in SAMPLE}), ids=lambda a: " ".join(a[1:]))
def test_the_unmutated_tree_regenerates(scratch, args):
    out = scratch.root / f".ok-{abs(hash(args))}"
    r = scratch.regenerate(args, out)
    assert r.returncode == 0, r.stderr
    assert any(out.rglob("*.py"))


@pytest.mark.parametrize("mutant", SAMPLE, ids=[m.id for m in SAMPLE])
def test_the_mutant_is_refused_before_writing(scratch, mutant):
    out = scratch.root / f".out-{mutant.id}"
    with scratch.applied(mutant):
        r = scratch.regenerate(mutant.args, out)
    lines = r.stderr.strip().splitlines()
    assert r.returncode == 2, f"{mutant.id}: exit {r.returncode}\n{r.stderr[-2000:]}"
    assert len(lines) == 1 and lines[0].startswith("adbgen: error: "), r.stderr[-2000:]
    assert not out.exists(), f"{mutant.id}: something was written"
    print(f"{mutant.id}: {lines[0]}")
