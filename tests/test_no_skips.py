"""No silent skips (issue 13, item 5): the skips of this run, listed, and a failure under CI if any.

tests/conftest.py records every skipped test and moves this test to the end of the run.  Outside
CI the list is printed (`pytest -rs` shows it too) and the test passes.
"""

from __future__ import annotations

import pytest
from toolchain import SKIPS_SEEN, in_ci, require_module, require_tool


def test_no_test_was_skipped_under_ci():
    listing = "\n".join(f"  {node}: {reason}" for node, reason in SKIPS_SEEN)
    if SKIPS_SEEN:
        print(f"\n{len(SKIPS_SEEN)} skipped:\n{listing}")
    assert not (in_ci() and SKIPS_SEEN), f"{len(SKIPS_SEEN)} test(s) skipped under CI:\n{listing}"


@pytest.mark.parametrize("value,truthy", [("true", True), ("1", True), ("True", True), ("yes", True),
                                          ("", False), ("0", False), ("false", False), ("no", False)])
def test_ci_is_any_truthy_value(monkeypatch, value, truthy):
    monkeypatch.setenv("CI", value)
    assert in_ci() is truthy


def test_a_missing_tool_or_package_fails_under_ci_and_skips_elsewhere(monkeypatch):
    monkeypatch.setenv("CI", "1")
    with pytest.raises(pytest.fail.Exception, match="required in CI"):
        require_tool(False, "frobnicator")
    with pytest.raises(pytest.fail.Exception, match="no_such_package_adbgen"):
        require_module("no_such_package_adbgen", "nothing")
    monkeypatch.delenv("CI")
    with pytest.raises(pytest.skip.Exception, match="frobnicator not available"):
        require_tool(False, "frobnicator")
    assert require_module("math", "stdlib").sqrt(4.0) == 2.0
