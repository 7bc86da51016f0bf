"""The registry of named objects loaded by "module:attribute" (families, code-generation targets)."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from adbgen.registry import Registry, load


def test_an_entry_is_imported_when_first_asked_for_and_kept():
    entries = {"join": "os.path:join", "pi": "math:pi"}
    reg = Registry("thing", "things", entries)
    assert reg.names() == ("join", "pi") and reg.get("pi") == load("math:pi") > 3.14
    assert reg.get("join") is reg.get("join") and reg.all()[0].__name__ == "join"


def test_an_unknown_name_is_refused_naming_the_known_ones():
    reg = Registry("thing", "things", {"pi": "math:pi"})
    with pytest.raises(KeyError, match="unknown thing 'tau'; things: pi"):
        reg.get("tau")


def test_an_object_registered_at_run_time_counts_until_unregistered_and_each_change_is_counted():
    entries = {"pi": "math:pi"}
    reg = Registry("thing", "things", entries)
    toy = SimpleNamespace(name="toy")
    reg.register(toy)
    assert reg.get("toy") is toy and list(entries) == ["pi", "toy"] and reg.generation == 1
    with pytest.raises(ValueError, match="a thing named 'toy' is registered already"):  # negative control
        reg.register(SimpleNamespace(name="toy"))
    other = SimpleNamespace(name="toy")
    reg.register(other, replace=True)
    assert reg.get("toy") is other
    reg.unregister("toy")
    assert reg.names() == ("pi",) and reg.generation == 3
    with pytest.raises(KeyError):
        reg.get("toy")
