"""The benchmarks' part of the CLI reference: one section per registered benchmark, its own options."""

from __future__ import annotations

import io

import toolchain

from adbgen.bench import registry
from adbgen.docsite.cli_reference import SECTION_ID, _usage, benchmark_rst


def documents(text: str, flag: str) -> bool:
    return f"``{flag}``" in text or f"``{flag} " in text


def test_every_benchmark_has_a_section_with_its_options():
    for bm in registry.all_benchmarks():
        text = "\n".join(benchmark_rst(bm))
        assert f".. _{SECTION_ID.format(bm.name)}:" in text
        usage = _usage(bm)
        assert usage.startswith(f"adbgen bench {bm.name} [--out FILE]")
        for opt in bm.options:
            assert opt.flags[0] in usage and documents(text, opt.flags[0]), (bm.name, opt.flags)
        others = {o.flags[0] for b in registry.all_benchmarks() for o in b.options} - {o.flags[0] for o in bm.options}
        assert not [flag for flag in others if documents(text, flag)], bm.name  # only its own options


def test_the_sections_are_valid_rest():
    toolchain.require_module("docutils", "the docs extra, with Sphinx")
    from docutils.core import publish_doctree

    for bm in registry.all_benchmarks():
        # the label directive is Sphinx's; docutils alone knows it as a hyperlink target too
        stream = io.StringIO()
        publish_doctree("\n".join(benchmark_rst(bm)), settings_overrides={"report_level": 2, "warning_stream": stream})
        assert stream.getvalue() == "", (bm.name, stream.getvalue())
