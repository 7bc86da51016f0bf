"""The long prose of the two-plane paper's reproduction sections as Markdown/jinja2 templates (package data,
`*.md.j2` beside this file; issue 33 item 6): the science modules compute and pass numbers, the words are here.
Read as every Markdown template of the package is (`analysis.prose`: a paragraph comes out as one line).

    render(name, **values) -> list of markdown lines
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

from .....analysis.prose import environment, paragraphs

FOLDER = Path(__file__).parent


@lru_cache(maxsize=1)
def _environment():
    return environment(FOLDER)


def render(name: str, **values) -> list[str]:
    """The template `name` (without .md.j2) rendered with `values`, a paragraph on one line (analysis.prose)."""
    return paragraphs(_environment().get_template(f"{name}.md.j2").render(**values))


__all__ = ["render"]
