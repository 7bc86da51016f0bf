"""Every registered check can fail: each declares a deliberately wrong variant (a flipped term, a
dropped factor, the misprinted form, a printed value moved by a few units of its last digit) and
must reject it (issue 13, item 2).  Also: every check says what it compares (its kind)."""

from __future__ import annotations

import pytest

from adbgen import families
from adbgen.core.checks import KINDS

# n = 1 for the single-plane checks that take a number of balls (the cheapest; the correct variants
# run for n = 1..6 in the family tests)
CHECKS = [(family.name, check) for family in families.all_families() for check in family.checks((1,))]


@pytest.mark.parametrize("family,check", CHECKS, ids=[f"{f}:{c.name}" for f, c in CHECKS])
def test_every_check_rejects_its_wrong_variant(family, check):
    assert check.kind in KINDS and check.wrong
    results = check.results(wrong=True)
    assert results, f"{family}: {check.name} ran nothing"
    passed = [r.name for r in results if r.passed]
    assert not passed, f"{family}: {check.name} accepted its wrong variant ({check.wrong}): {passed}"
    assert all(r.kind in KINDS for r in results)


def test_every_family_registers_checks_and_the_listed_ones_have_controls():
    names = {f: {c.name for f2, c in CHECKS if f2 == f} for f in families.names()}
    # the ten that had no negative control before issue 13
    assert {"prescribed speed", "rotating frame", "two routes"} <= names["single-plane"]
    assert {"prescribed run-up (ramp)", "balanced condition", "B solves (9)", "single-plane limit (torque)",
            "critical speeds, symbolic", "C3 relation (31)", "stability exchange (35)",
            "autonomous extension (40)"} <= names["two-plane"]
