"""The Markdown of the thesis' reproduction sections, as jinja2 templates (issue 33 item 6: long prose out of
Python string literals).  `render(name, **values)`: the template filled; numbers are formatted in the
templates, computed by the science modules.

A line of a template that ends in `{##}` (an empty jinja2 comment, whose newline trim_blocks removes) goes on
in the next line: the document's long paragraphs and table cells are one line each, the templates wrapped."""

from __future__ import annotations

from functools import lru_cache


@lru_cache(maxsize=None)
def _environment():
    import jinja2

    env = jinja2.Environment(loader=jinja2.PackageLoader("adbgen.families.single_plane.science", "templates"),
                             undefined=jinja2.StrictUndefined, keep_trailing_newline=True, trim_blocks=True,
                             lstrip_blocks=True)
    env.globals["zip"] = zip
    return env


def render(name: str, **values) -> str:
    return _environment().get_template(name).render(**values)
