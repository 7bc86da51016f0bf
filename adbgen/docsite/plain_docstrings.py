"""Sphinx extension: adbgen's plain-text docstrings rendered as they are written, never as reST.

adbgen's docstrings are plain text in the style of the README: `backticks` for code, `*` and `|` as
mathematics (|J T|, a*b), indented blocks for command tables and formulas, `* ` or `- ` for bullets.
Read as reStructuredText they break (|x| is a substitution, x_ a link, an indented line a block
quote), and a documentation build with warnings as errors must not depend on every docstring of
every branch being valid reST.  So each docstring is translated before autodoc parses it
(`autodoc-process-docstring`):

    prose paragraph        -> one paragraph, every inline-markup character escaped; `code` literal
    bullet paragraph       -> a bullet list of such paragraphs (`* ` or `- ` items, continuation indented)
    anything else indented -> a literal block, as typed (tables, formulas, command lines)

`translate` is total: whatever the input, its output parses without a docutils message (a Hypothesis
test checks this), so the build's -W never fires on a docstring.
"""

from __future__ import annotations

import re

# Characters that start or end inline markup, or make a paragraph a field list or a literal-block
# marker ("::" at its end); escaped with a backslash in prose.
_ESCAPE = re.compile(r"([\\`*_|:\[\]<>])")
_CODE = re.compile(r"`([^`\n]+)`")
_BULLET = re.compile(r"^([*\-+]) (\S.*)$")


def _escape(text: str) -> str:
    return _ESCAPE.sub(r"\\\1", text)


def _inline(text: str) -> str:
    """Prose as reST: code spans become inline literals, the rest is escaped character by character."""
    out, end = [], 0
    for m in _CODE.finditer(text):
        code = m.group(1)
        out.append(_escape(text[end:m.start()]))
        # An inline literal must not start or end with a space; ". " inside one would let autosummary's
        # first-sentence split cut it in two.
        if code != code.strip() or ". " in code or "\\" in code:
            out.append(_escape(m.group(0)))
        else:
            out.append(f"\\ ``{code}``\\ ")  # escaped spaces: inline markup recognised anywhere
        end = m.end()
    out.append(_escape(text[end:]))
    # A leading escaped space keeps the paragraph from being read as a list, option list, section
    # title, comment, directive or doctest block.
    return "\\ " + "".join(out).strip()


def _paragraphs(lines: list[str]) -> list[list[str]]:
    paras, cur = [], []
    for line in lines:
        if line.strip():
            cur.append(line.rstrip())
        elif cur:
            paras.append(cur)
            cur = []
    if cur:
        paras.append(cur)
    return paras


def _bullets(para: list[str]) -> list[str] | None:
    """The items of a paragraph made of `* ` / `- ` bullets with indented continuation lines, or None."""
    items: list[list[str]] = []
    for line in para:
        m = _BULLET.match(line)
        if m and (not items or line[0] == para[0][0]):
            items.append([m.group(2)])
        elif items and line.startswith("  ") and line.strip():
            items[-1].append(line.strip())
        else:
            return None
    return [" ".join(item) for item in items]


def _literal(para: list[str]) -> list[str]:
    indent = min(len(ln) - len(ln.lstrip()) for ln in para)
    return ["::", ""] + ["    " + ln[indent:] for ln in para]


def translate(lines: list[str]) -> list[str]:
    """Docstring lines (as autodoc hands them over, dedented) -> reST lines that parse cleanly."""
    out: list[str] = []
    for para in _paragraphs([ln.expandtabs() for ln in lines]):
        items = _bullets(para)
        if items is not None:
            out += [f"* {_inline(item)}" for item in items]
        elif any(ln[:1].isspace() for ln in para):
            out += _literal(para)
        else:
            out.append(_inline(" ".join(ln.strip() for ln in para)))
        out.append("")
    return out


def _process(app, what, name, obj, options, lines: list[str]) -> None:
    lines[:] = translate(lines)


def setup(app):
    app.connect("autodoc-process-docstring", _process)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
