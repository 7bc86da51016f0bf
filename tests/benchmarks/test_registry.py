"""The benchmarks' registry: every listed module declares its benchmark, the shared `adbgen bench` parser
is assembled from the declarations, and the run function a name selects is the one that runs."""

from __future__ import annotations

import json

import pytest

from benchmarks import registry
from adbgen.cli import build_parser, main


def test_every_registered_benchmark_is_declared_by_its_module():
    benchmarks = registry.all_benchmarks()
    assert [b.name for b in benchmarks] == list(registry.REGISTRY)
    assert [b.name for b in benchmarks] == ["derive", "codegen", "simulate", "sweep", "failures", "smallest",
                                             "precision", "mutation", "orbits", "auto", "rk", "ensemble", "reproduce",
                                             "trust", "design", "tolerance", "friction"]
    for b in benchmarks:
        assert b.default_out == f"benchmarks/{b.name}.json" and callable(b.run)


def test_the_parser_takes_every_declared_option_once():
    bench = next(a for a in build_parser()._subparsers._group_actions[0].choices.items() if a[0] == "bench")[1]
    flags = [f for action in bench._actions for f in action.option_strings]
    assert len(flags) == len(set(flags))
    declared = {f for b in registry.all_benchmarks() for o in b.options for f in o.flags}
    assert declared | {"-h", "--help", "--out"} == set(flags)
    helps = {a.option_strings[0]: a.help for a in bench._actions if a.option_strings}
    assert helps["--repeats"].startswith("simulate: best of N") and "sweep: each configuration" in helps["--repeats"]
    assert helps["--engines"] == "simulate, precision: only these engines (default: all)"


def test_conflicting_declarations_are_refused():
    """Negative control: two benchmarks declaring one flag differently cannot share the parser."""
    a = registry.Benchmark("a", lambda args, out: 0, (registry.option("--x", type=int, help="a's"),))
    b = registry.Benchmark("b", lambda args, out: 0, (registry.option("--x", type=float, help="b's"),))
    assert registry.merged_options([a, a])[0][1] == "a, a: a's"
    with pytest.raises(ValueError, match="--x"):
        registry.merged_options([a, b])


def test_the_named_benchmark_runs_with_its_default_results_file(tmp_path, monkeypatch, capsys):
    calls = []

    def fake_run(args, out):
        calls.append((args.what, out, args.quick))
        return 0

    from benchmarks import smallest

    monkeypatch.setattr(registry, "get", lambda name: registry.Benchmark(name, fake_run, smallest.BENCHMARK.options))
    monkeypatch.chdir(tmp_path)
    assert main(["bench", "smallest", "--quick"]) == 0
    assert calls == [("smallest", "benchmarks/smallest.json", True)]


def test_bench_sweep_rejects_zero_repeats_before_running(tmp_path, capsys):
    out = tmp_path / "s.json"
    assert main(["bench", "sweep", "--repeats", "0", "--out", str(out)]) == 2
    assert "--repeats must be >= 1" in capsys.readouterr().err and not out.exists()


def test_bench_derive_wiring(tmp_path, monkeypatch, capsys):
    from benchmarks import derive

    seen = {}

    def fake(ns, progress=None, pipeline_ns=None, pipeline_progress=None):
        seen.update(ns=ns, pipeline_ns=pipeline_ns)
        return {"benchmark": "derive", "rows": []}

    monkeypatch.setattr(derive, "bench_derive", fake)
    out = tmp_path / "d.json"
    assert main(["bench", "derive", "--out", str(out), "--n", "1", "2", "--pipeline-n", "3"]) == 0
    assert seen == {"ns": (1, 2), "pipeline_ns": (3,)}
    assert json.loads(out.read_text())["benchmark"] == "derive" and str(out) in capsys.readouterr().out
