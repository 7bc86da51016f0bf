"""adbgen.outputs: output paths checked before work, files written whole (issue 24 item 5)."""

from __future__ import annotations

import os

import pytest

from adbgen.cli_types import UsageError
from adbgen.outputs import output_file, output_folder, write_text, writing


def test_output_folder(tmp_path):
    assert output_folder(tmp_path / "new" / "deeper") == tmp_path / "new" / "deeper"  # need not exist
    assert not (tmp_path / "new").exists()  # checking creates nothing
    (tmp_path / "afile").write_text("x")
    for bad, message in ((tmp_path / "afile", "is a file, not a folder"), (tmp_path / "afile" / "sub", "is a file"),
                         ("/sys/adbgen-x", "cannot write in /sys"), (tmp_path / ("n" * 300), "longer than"),
                         ("", "empty path")):
        with pytest.raises(UsageError, match=message):
            output_folder(bad)


def test_output_file(tmp_path):
    assert output_file(tmp_path / "a.json") == tmp_path / "a.json"
    with pytest.raises(UsageError, match="is a folder, not a file"):
        output_file(tmp_path)


def test_a_failed_write_leaves_the_old_file(tmp_path):
    target = tmp_path / "result.csv"
    target.write_text("old and good\n")
    with pytest.raises(RuntimeError):
        with writing(target) as fh:
            fh.write("half of the new")
            raise RuntimeError("killed half-way")
    assert target.read_text() == "old and good\n" and os.listdir(tmp_path) == ["result.csv"]
    write_text(target, "new\n")
    assert target.read_text() == "new\n" and os.listdir(tmp_path) == ["result.csv"]
