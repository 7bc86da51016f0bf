"""The benchmarks' part of the CLI reference: one section per registered benchmark, its own options."""

from __future__ import annotations

import io

import toolchain

from benchmarks import registry
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


def _texts(parser) -> list[str]:
    """Every text of a parser tree that sphinx-argparse reads as reST (help strings %-formatted)."""
    import argparse

    from adbgen.docsite.cli_reference import _parsers

    out = []
    for p in _parsers(parser):
        out += [t for t in (p.description, p.epilog) if t]
        out += [g.description for g in p._action_groups if g.description]
        for a in p._actions:
            if a.help and a.help is not argparse.SUPPRESS:
                out.append(a.help % {**vars(a), "prog": p.prog, "default": a.default})
            if isinstance(a, argparse._SubParsersAction):
                out += [c.help for c in a._choices_actions if c.help]
    return out


def _messages(text: str) -> str:
    from docutils.core import publish_doctree

    stream = io.StringIO()
    publish_doctree(text, settings_overrides={"report_level": 2, "halt_level": 5, "warning_stream": stream})
    return stream.getvalue()


def test_the_reference_parser_is_the_parser_with_texts_that_parse_cleanly():
    """sphinx-argparse reads help texts as reST; adbgen's are plain text.  The reference's copy of the
    parser has the same commands and options, and every text parses without a message; the parser's
    own texts do not all (negative control: the translation is needed)."""
    toolchain.require_module("docutils", "the docs extra, with Sphinx")
    from site_helpers import all_parsers, command_paths

    from adbgen.cli import build_parser
    from adbgen.docsite.cli_reference import reference_parser

    plain, reference = build_parser(), reference_parser()
    assert command_paths(plain) == command_paths(reference)
    assert [[a.option_strings for a in p._actions] for p in all_parsers(plain)] == \
           [[a.option_strings for a in p._actions] for p in all_parsers(reference)]
    bad = [(text, msg) for text in _texts(reference) if (msg := _messages(text))]
    assert not bad, bad[:3]


def test_texts_that_are_not_rest_are_translated(monkeypatch):
    """Negative control on a toy parser: its texts, read as reST, give messages; the reference's don't,
    and argparse's %(default)s is filled in before the % signs are doubled for sphinx-argparse."""
    import argparse

    toolchain.require_module("docutils", "the docs extra, with Sphinx")
    import adbgen.cli
    from adbgen.docsite.cli_reference import reference_parser

    def toy():
        p = argparse.ArgumentParser(prog="adbgen", description="runs *everything", epilog="exit status:\n  0 done\nend")
        sub = p.add_subparsers(dest="command")
        s = sub.add_parser("scan", help="a scan_ of |x|", description="steps of |TO - FROM|")
        s.add_argument("--ds", default=0.5, help="step (default %(default)s, |TO - FROM| / 350, 5 %%)")
        return p

    monkeypatch.setattr(adbgen.cli, "build_parser", toy)
    nasty = [text for text in _texts(toy()) if any(c in text for c in "|*\n")]
    assert len(nasty) == 5 and all(_messages(text) for text in nasty)
    reference = reference_parser()
    assert [_messages(text) for text in _texts(reference)] == [""] * len(_texts(reference))
    [scan] = [a for a in reference._actions if isinstance(a, argparse._SubParsersAction)][0].choices.values()
    assert "default 0.5," in [a for a in scan._actions if a.dest == "ds"][0].help % {}
