"""Long Markdown of the analysis layer's reports as jinja2 templates (package data, `*.md.j2` beside this file;
issue 33 item 6): the modules compute and pass values, the words are here.  `environment(folder)` and
`paragraphs(text)` are the one way the package's Markdown templates of this form are read (the families'
science reads its prose with them too).

    render(name, **values) -> list of markdown lines
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

FOLDER = Path(__file__).parent


def environment(folder: Path):
    """A jinja2 environment over `folder`: a value the template names but the caller does not give is an
    error (StrictUndefined), block tags take their line with them, no escaping (Markdown, not HTML)."""
    import jinja2

    return jinja2.Environment(loader=jinja2.FileSystemLoader(str(folder)), undefined=jinja2.StrictUndefined,
                              trim_blocks=True, lstrip_blocks=True, keep_trailing_newline=False, autoescape=False)


def paragraphs(text: str) -> list[str]:
    """The rendered template's lines with each paragraph on one line: a line is joined to the one before it with
    a space unless either is blank or a table row, heading or image, or it starts a list item."""
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


@lru_cache(maxsize=1)
def _environment():
    return environment(FOLDER)


def render(name: str, **values) -> list[str]:
    """The template `name` (without .md.j2) rendered with `values`, as `paragraphs`."""
    return paragraphs(_environment().get_template(f"{name}.md.j2").render(**values))


__all__ = ["environment", "paragraphs", "render"]
