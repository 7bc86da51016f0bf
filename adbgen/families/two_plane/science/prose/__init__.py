"""The long prose of the two-plane paper's reproduction sections as Markdown/jinja2 templates (package data,
`*.md.j2` beside this file; issue 33 item 6): the science modules compute and pass numbers, the words are here.

    render(name, **values) -> list of markdown lines
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

FOLDER = Path(__file__).parent


@lru_cache(maxsize=1)
def _environment():
    import jinja2

    return jinja2.Environment(loader=jinja2.FileSystemLoader(str(FOLDER)), undefined=jinja2.StrictUndefined,
                              trim_blocks=True, lstrip_blocks=True, keep_trailing_newline=False, autoescape=False)


def render(name: str, **values) -> list[str]:
    """The template `name` (without .md.j2) rendered with `values`; a paragraph is one line (the template's
    lines inside a paragraph are joined with a space, blank lines and table rows kept)."""
    text = _environment().get_template(f"{name}.md.j2").render(**values)
    out: list[str] = []
    for line in text.split("\n"):
        line = line.rstrip()
        joins = (out and out[-1] and line and not line.startswith(("|", "#", "!", "* ", "- "))
                 and not out[-1].startswith(("|", "#", "!")))
        if joins:
            out[-1] += " " + line.lstrip()
        else:
            out.append(line)
    return out


__all__ = ["render"]
