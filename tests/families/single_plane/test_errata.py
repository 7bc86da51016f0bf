"""The thesis' textual errata (docs/errata.md), read off its transcription (adbgen.references.thesis, from
../shared/references/, which a checkout elsewhere does not have): the captions of Figs. 5.20-5.22 label the
n = 4 panel "(d)" while the figures and the text have (a)-(c)."""

import re
from pathlib import Path

import pytest

from adbgen.references import thesis

REFERENCE = Path(__file__).resolve().parents[3] / ".." / "shared" / "references" / "thesis-multi-ball-adb-2005.txt"


def _caption_panels(text: str, figure: str) -> list[str]:
    """The panel letters a caption names, in order."""
    caption = next(line for line in text.splitlines() if line.startswith(f"Figure {figure}:"))
    return re.findall(r"balls \(([a-z])\)", caption)


@pytest.fixture(scope="module")
def text():
    """The reference text where the checkout sits beside it, else the transcription of the lines read."""
    if REFERENCE.exists():
        return REFERENCE.read_text()
    return "\n".join([*(f"Figure {f}: (caption) {thesis.PANELS_CAPTION_5_20_22}" for f in ("5.20", "5.21", "5.22")),
                      thesis.N4_PANEL_SENTENCE_5_20])


def test_the_transcription_is_the_reference_text_where_it_is_at_hand():
    if REFERENCE.exists():  # beside the checkout (this project's machines): the transcription is verbatim
        ref = REFERENCE.read_text()
        assert thesis.PANELS_CAPTION_5_20_22 in ref and thesis.N4_PANEL_SENTENCE_5_20 in ref
    assert thesis.PANELS_CAPTION_5_20_22.endswith("four balls (d).")


@pytest.mark.parametrize("figure", ["5.20", "5.21", "5.22"])
def test_the_n4_panel_is_captioned_d(text, figure):
    assert _caption_panels(text, figure) == ["a", "b", "d"]


def test_the_text_calls_the_n4_panel_c(text):
    assert "In panel (c) we can see that for four balls" in text


def test_a_caption_with_its_panels_in_order_is_not_flagged():
    """Negative control: a correct caption gives (a), (b), (c)."""
    fine = "Figure 5.20: x for the ADB system with two balls (a); three balls (b); four balls (c). End."
    assert _caption_panels(fine, "5.20") == ["a", "b", "c"]
