"""The scene reference docs/scenes.md (issue 24 item 8) is generated from the scene definitions, is
current, and says what the validators enforce: every documented domain is probed against the scene
format's own from_mapping, and every field of a scene is documented."""

from __future__ import annotations

import copy
import dataclasses

import pytest

from adbgen.errors import SceneError
from adbgen.families import all_families
from adbgen.families.scene_reference import DEFAULT_OUT, markdown, scene_module


def test_the_committed_reference_is_current():
    assert DEFAULT_OUT.read_text() == markdown(), "run `adbgen scenes --out docs/scenes.md`"


def _base(family) -> dict:
    module = scene_module(family)
    return copy.deepcopy(module._preset(module.DEFAULT_PRESET)) if hasattr(module, "_preset") else {}


def _with(family, key, value) -> tuple[dict, str]:
    """A scene mapping with `key` set to `value` (in its context), and the field an error must name."""
    data = _base(family)
    for section, entries in (key.context or {}).items():
        data[section] = dict(entries) if isinstance(entries, dict) else entries  # a table: that law's keys only
    parts = key.path.split(".")
    where, field = data, []
    for part in parts[:-1]:
        if part.endswith("[]"):
            where = where[part[:-2]][0]
            field.append(part[:-2] + "[0]")
        else:
            where = where.setdefault(part, {})
            field.append(part)
    leaf = parts[-1]
    if leaf.endswith("[]"):
        raise AssertionError(key.path)
    list_valued = isinstance(where.get(leaf), list) and key.path.endswith("masses")
    where[leaf] = [value, value] if list_valued else value
    return data, ".".join(field + [leaf + ("[0]" if list_valued else "")])


CASES = [(f, k) for f in all_families() for k in getattr(scene_module(f), "KEYS", ()) if k.domain != "other"]


@pytest.mark.parametrize("family, key", CASES, ids=[f"{f.name}:{k.path}" for f, k in CASES])
def test_each_documented_domain_is_what_the_validator_enforces(family, key):
    load = family.scene_type.from_mapping
    bad, good = {"positive": (0.0, 0.5), "nonnegative": (-1.0, 0.0), "real": (None, -1.0)}[key.domain]
    data, field = _with(family, key, good)
    load(data)  # accepted at the edge of the domain
    if bad is not None:
        data, field = _with(family, key, bad)
        with pytest.raises(SceneError) as err:
            load(data)
        assert err.value.field == field, (err.value, field)


@pytest.mark.parametrize("family", all_families(), ids=lambda f: f.name)
def test_every_field_of_a_scene_is_documented(family):
    documented = {k.path.split(".")[0].removesuffix("[]") for k in scene_module(family).KEYS}
    fields = {f.name for f in dataclasses.fields(family.scene_type)}
    assert fields <= documented, fields - documented
    assert all(family.scene_type.from_mapping(_base(family)) for _ in (0,))


def test_a_wrong_domain_would_be_caught():
    """Negative control: documenting ball_mass as non-negative is refuted by the validator (0 refused)."""
    family = next(f for f in all_families() if f.name == "single-plane")
    key = next(k for k in scene_module(family).KEYS if k.path == "ball_mass")
    wrong = dataclasses.replace(key, domain="nonnegative")
    with pytest.raises(SceneError):
        family.scene_type.from_mapping(_with(family, wrong, 0.0)[0])
