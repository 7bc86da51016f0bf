"""The package's Markdown templates (jinja2, `*.md.j2`; issue 33 item 6: long prose out of Python string literals)
and the one way they are read: the analysis layer's reports (beside this file) and the families' science
sections (their own template folders, each a module with FOLDER, `_environment` and `render` as here).  The
modules compute and pass values (a verdict as a named boolean or string, decided where the numbers are); the
words, and the choice among them, are in the templates.

The one convention: every line of a template is a line of the document, except that a line ending in `{##}`
(an empty jinja2 comment, whose newline trim_blocks removes) goes on in the next line.  So a long paragraph or
table row is one line of the document while its template stays wrapped, and a line break the document has is
one the template has.  Block tags take their line with them (trim_blocks, lstrip_blocks); a value the template
names but the caller does not give is an error (StrictUndefined); no escaping (Markdown, not HTML).

    render(name, **values) -> list of markdown lines   (name without .md.j2)
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

FOLDER = Path(__file__).parent


def environment(folder: Path):
    """A jinja2 environment over `folder` in the convention above (`zip` among its globals)."""
    import jinja2

    env = jinja2.Environment(loader=jinja2.FileSystemLoader(str(folder)), undefined=jinja2.StrictUndefined,
                             trim_blocks=True, lstrip_blocks=True, keep_trailing_newline=True, autoescape=False)
    env.globals["zip"] = zip
    return env


def lines(text: str) -> list[str]:
    """A rendered template's lines (split at "\\n" only; a final newline ends the last line, it adds none), each
    without trailing whitespace (a document line has none: the blank a `{##}` line leaves before an empty value)."""
    out = [line.rstrip() for line in text.split("\n")]
    return out[:-1] if out[-1] == "" else out


def read(env, name: str, values: dict) -> list[str]:
    """The template `name` (without .md.j2) of `env` rendered with `values`, as `lines`."""
    return lines(env.get_template(f"{name}.md.j2").render(**values))


@lru_cache(maxsize=1)
def _environment():
    return environment(FOLDER)


def render(name: str, **values) -> list[str]:
    """The template `name` (without .md.j2) beside this module rendered with `values`, as lines."""
    return read(_environment(), name, values)


__all__ = ["environment", "lines", "read", "render"]
