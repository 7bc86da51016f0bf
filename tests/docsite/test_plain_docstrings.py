"""adbgen's plain-text docstrings translated for autodoc: always valid reST, content as written."""

from __future__ import annotations

import importlib
import inspect
import io
import pkgutil

import pytest
import site_helpers
import toolchain
from hypothesis import given, settings
from hypothesis import strategies as st

import adbgen
from adbgen.docsite.plain_docstrings import translate


def parse(text: str, stream=None):
    toolchain.require_module("docutils", "the docs extra, with Sphinx")  # fails under CI when missing
    from docutils.core import publish_doctree

    return publish_doctree(text, settings_overrides={"report_level": 2, "halt_level": 5,
                                                     "warning_stream": stream or io.StringIO()})


def messages(text: str) -> list[str]:
    """docutils' warnings and errors for `text` (what Sphinx reports as WARNING/ERROR), parser and
    transforms (an undefined substitution, an unknown target) alike."""
    stream = io.StringIO()
    parse(text, stream)
    return stream.getvalue().splitlines()


# Text made of the characters that are markup in reST, with line breaks, indentation and blank lines.
MARKUP_TEXT = st.text(alphabet=st.sampled_from(list("ab1 .:*_|`[]<>\\-+#=()'\"\n\t/~^{}!$&@,;?")), max_size=160)


@settings(max_examples=400, deadline=None)
@given(MARKUP_TEXT)
def test_any_text_translates_to_rest_without_a_message(text):
    out = "\n".join(translate(text.splitlines()))
    assert messages(out) == [], (text, out)


@pytest.mark.parametrize("text", ["|J T| <= 1e-8 |J|", "a_ reference", "*emphasis without end",
                                  "line\n    indented block\nunindent", "ends in a marker::"])
def test_the_same_text_as_rest_gives_messages(text):
    """Negative control: what the translation is for; each of these, read as reST, is a warning."""
    assert messages(text) != []
    assert messages("\n".join(translate(text.splitlines()))) == []


def test_every_docstring_of_the_package_translates_cleanly():
    """The package's own docstrings (modules, classes, functions), the input the site renders."""
    site_helpers.require_docs_extra()  # adbgen.docsite's Sphinx extensions import Sphinx
    bad = []
    for info in pkgutil.walk_packages(adbgen.__path__, "adbgen."):
        if info.name.rpartition(".")[2].startswith("_"):  # private, or a __main__ that would run
            continue
        module = importlib.import_module(info.name)
        objects = [module] + [v for _, v in vars(module).items()
                              if (inspect.isfunction(v) or inspect.isclass(v)) and v.__module__ == module.__name__]
        for obj in objects:
            doc = inspect.getdoc(obj)
            if doc and messages("\n".join(translate(doc.splitlines()))):
                bad.append(f"{module.__name__}:{getattr(obj, '__qualname__', '')}")
    assert not bad, bad


def test_indented_blocks_stay_as_typed_and_code_becomes_literal():
    from docutils import nodes

    doc = ("Sweeps: `run_sweep(spec, out)`, see |J T|.\n\n"
           "    spec = SweepSpec(model=\"m\",\n"
           "                     t_end=2000)          -> {\"points\"}\n\n"
           "* first item with `code`\n"
           "  continued\n"
           "* second item")
    tree = parse("\n".join(translate(doc.splitlines())))
    paragraph = next(iter(tree.findall(nodes.paragraph)))
    assert paragraph.astext() == "Sweeps: run_sweep(spec, out), see |J T|."
    assert [lit.astext() for lit in paragraph.findall(nodes.literal)] == ["run_sweep(spec, out)"]
    [block] = tree.findall(nodes.literal_block)
    assert block.astext() == 'spec = SweepSpec(model="m",\n                 t_end=2000)          -> {"points"}'
    [items] = tree.findall(nodes.bullet_list)
    assert [item.astext() for item in items.children] == ["first item with code continued", "second item"]
