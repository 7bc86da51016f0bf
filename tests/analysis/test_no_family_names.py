"""The analysis layer knows no family (issue 19 item 2): no family's registry key, model kind, generated
model's name or family folder's name appears anywhere in adbgen/analysis/, code, strings or comments,
nor in its data files (.json: the auto engine's table is keyed by problem, issue 33).

Citations of the references stay allowed ("thesis (3.6)", "paper (40)"): they say which equations a
generic algorithm implements and name no family, model or module.  The words are read from the
registries and from generated/, so a new family, kind or model is covered without editing this test."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

import adbgen
from adbgen import families
from adbgen.analysis.loading import available_models, load_model

ANALYSIS = Path(adbgen.__file__).parent / "analysis"


def forbidden_words() -> set[str]:
    words = set()
    for family in families.all_families():
        words |= {family.name, family.name.replace("-", "_")}  # registry key, its module spelling
        words |= set(family.kinds())
        words |= {spec.name for spec in family.models()}
    for name in available_models():
        words.add(name)
        kind = getattr(load_model(name).module, "KIND", None)
        if kind:
            words.add(kind)
    folders = Path(families.__file__).parent
    words |= {p.name for p in folders.iterdir() if p.is_dir() and (p / "__init__.py").is_file()}
    return {w for w in words if w and w != "scene"}


def occurrences(folder: Path, words: set[str]) -> list[str]:
    pattern = re.compile("|".join(sorted(map(re.escape, words), key=len, reverse=True)))
    out = []
    for path in sorted(folder.rglob("*")):
        if path.suffix not in (".py", ".c", ".h", ".j2", ".md", ".json") or "__pycache__" in path.parts:
            continue
        for k, line in enumerate(path.read_text().splitlines(), start=1):
            for m in pattern.finditer(line):
                out.append(f"{path.relative_to(folder.parent)}:{k}: {m.group(0)}")
    return out


def test_the_words_cover_every_family_kind_and_model():
    words = forbidden_words()
    assert {"single-plane", "two-plane", "single_plane", "two_plane", "thesis_rotating", "two_plane_hill",
            "thesis_rotating_n3", "single_plane_fixed"} <= words


def test_no_family_or_model_name_in_the_analysis_layer():
    assert occurrences(ANALYSIS, forbidden_words()) == []


def test_a_planted_name_is_found(tmp_path):
    """Negative control: the search finds a model name in code, in a string and in a comment."""
    (tmp_path / "analysis").mkdir()
    (tmp_path / "analysis" / "x.py").write_text('m = load("thesis_rotating_n3")  # two-plane\nkind = single_plane\n')
    (tmp_path / "analysis" / "table.json").write_text('{"by_family": {\n  "single-plane": []}}\n')
    found = occurrences(tmp_path / "analysis", forbidden_words())
    assert found == ["analysis/table.json:2: single-plane", "analysis/x.py:1: thesis_rotating_n3",
                     "analysis/x.py:1: two-plane", "analysis/x.py:2: single_plane"]
