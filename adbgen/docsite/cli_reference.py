"""The CLI reference's sources: the parser as sphinx-argparse should read it, and a Sphinx extension
for the `adbgen bench WHAT` part, one section per benchmark.

sphinx-argparse renders a parser with every nested subcommand and reads its help texts, descriptions
and epilogs as reST.  adbgen's are plain text (|TO - FROM| is a substitution to reST, an indented
line a block quote), so `reference_parser()` is `adbgen.cli.build_parser()` with each of those
translated as the docstrings are (`plain_docstrings`): the page shows them as written and no command's
wording can fail the -W build.

The benchmarks are values of one positional argument (`benchmarks/registry.py`), not argparse subcommands, and
share one merged option list.  The directive

    ```{adbgen-benchmarks}
    ```

renders, for each benchmark of `benchmarks.registry.all_benchmarks()` in registry order, a section with
the id ``adbgen-bench-<name>``: its usage (formatted by argparse from the options it declares), the
first paragraph of its module's docstring, its results file and its options with its own help.  A
benchmark added to the registry appears with no edit here.
"""

from __future__ import annotations

import argparse
import inspect

from docutils import nodes
from docutils.statemachine import StringList
from sphinx.util.docutils import SphinxDirective
from sphinx.util.nodes import nested_parse_with_titles

from .plain_docstrings import _inline, _paragraphs, translate

SECTION_ID = "adbgen-bench-{}"


def _parsers(parser: argparse.ArgumentParser):
    yield parser
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for sub in action.choices.values():
                yield from _parsers(sub)


def _text(text: str, prog: str) -> str:
    """A description, epilog or group description as reST (argparse's %(prog)s filled in)."""
    return "\n".join(translate(text.replace("%(prog)s", prog).splitlines()))


def reference_parser() -> argparse.ArgumentParser:
    """`adbgen.cli.build_parser()` with its texts made reST that shows them as written (the CLI page's
    `:func:`).  Help strings are expanded by argparse here (%(default)s ...) and their other percent
    signs doubled, since sphinx-argparse %-formats them again."""
    from adbgen.cli import build_parser

    root = build_parser()
    for parser in _parsers(root):
        formatter = parser._get_formatter()
        for attr in ("description", "epilog"):
            if getattr(parser, attr):
                setattr(parser, attr, _text(getattr(parser, attr), parser.prog))
        for group in parser._action_groups:
            if group.description:
                group.description = _text(group.description, parser.prog)
        for action in parser._actions:
            if action.help and action.help is not argparse.SUPPRESS:
                action.help = _inline(formatter._expand_help(action)).replace("%", "%%")
            if isinstance(action, argparse._SubParsersAction):
                for choice in action._choices_actions:  # each subcommand's one-line help
                    if choice.help:
                        choice.help = _inline(choice.help.replace("%(prog)s", parser.prog))
    return root


def _usage(benchmark) -> str:
    parser = argparse.ArgumentParser(prog=f"adbgen bench {benchmark.name}", add_help=False)
    parser.add_argument("--out", metavar="FILE")
    for opt in benchmark.options:
        kwargs = {k: v for k, v in opt.kwargs.items() if k != "action" or isinstance(v, str)}
        parser.add_argument(*opt.flags, **kwargs)
    return parser.format_usage().removeprefix("usage: ").rstrip()


def _option_line(opt) -> str:
    kw = opt.kwargs
    flags = ", ".join(opt.flags)
    if kw.get("action") not in ("store_true", "store_false"):
        metavar = opt.dest.upper()
        flags += f" {metavar} [{metavar} ...]" if kw.get("nargs") == "+" else f" {metavar}"
    return flags


def benchmark_rst(benchmark) -> list[str]:
    """reST lines of one benchmark's section."""
    name = benchmark.name
    title = f"bench {name}"
    doc = inspect.getdoc(inspect.getmodule(benchmark.run)) or ""
    summary = _paragraphs(doc.splitlines())[:1]
    lines = [f".. _{SECTION_ID.format(name)}:", "", title, "-" * len(title), "", "::", ""]
    lines += ["    " + ln for ln in _usage(benchmark).splitlines()] + [""]
    lines += translate(summary[0]) if summary else []
    lines += [_inline(f"Results: `{benchmark.default_out}` (or --out FILE)."), ""]
    for opt in benchmark.options:
        choices = opt.kwargs.get("choices")
        help_ = opt.help + (f" (choices: {', '.join(map(str, choices))})" if choices else "")
        lines += [f"``{_option_line(opt)}``", "    " + (_inline(help_) if help_.strip() else "\\ -"), ""]
    return lines


class BenchmarksDirective(SphinxDirective):
    has_content = False

    def run(self) -> list[nodes.Node]:
        from adbgen.cli.bench import registry  # the checkout's benchmarks (the site is built from one)

        lines: list[str] = []
        for benchmark in registry().all_benchmarks():
            lines += benchmark_rst(benchmark)
        container = nodes.section()
        container.document = self.state.document
        nested_parse_with_titles(self.state, StringList(lines, source="benchmarks.registry"), container)
        return container.children


def setup(app):
    app.add_directive("adbgen-benchmarks", BenchmarksDirective)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
