"""The negative control the Markdown-template tests share (tests/analysis/test_design_report_text.py,
tests/families/two_plane/science/prose/): a module's templates read from a copy with one word changed."""

from __future__ import annotations

import shutil
from contextlib import contextmanager


@contextmanager
def changed_template(module, name: str, old: str, new: str, tmp_path, monkeypatch):
    """Inside: `module` (a template folder's reader: FOLDER, _environment) reads its templates from a copy in
    tmp_path whose `name` has its first `old` replaced by `new` (which must be there); after, its own again."""
    for p in module.FOLDER.glob("*.md.j2"):
        shutil.copy(p, tmp_path / p.name)
    text = (tmp_path / name).read_text()
    assert old in text
    (tmp_path / name).write_text(text.replace(old, new, 1))
    monkeypatch.setattr(module, "FOLDER", tmp_path)
    module._environment.cache_clear()
    try:
        yield
    finally:
        monkeypatch.undo()
        module._environment.cache_clear()
