"""Building and running AUTO-07p user files the way `@r` does, and reading fort.7 (for the AUTO tests)."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import pytest

from toolchain import require_tool

AUTO_DIR = Path(os.environ.get("AUTO_DIR", "/usr/lib/auto-07p"))
BIFURCATIONS = {1: "BP", 2: "LP", 3: "HB"}  # |TY| in fort.7; 4 regular/UZ, 9 end points


def auto_header() -> Path | None:
    for folder in (AUTO_DIR / "include", Path("/usr/include")):
        if (folder / "auto_f2c.h").is_file():
            return folder
    return None


@pytest.fixture(scope="module")
def auto_toolchain():
    missing = [what for what, ok in (
        ("auto-07p (cmds/cmds.make)", (AUTO_DIR / "cmds" / "cmds.make").is_file()),
        ("auto-07p (lib/libauto_c.a)", (AUTO_DIR / "lib" / "libauto_c.a").is_file()),
        ("auto-07p (auto_f2c.h)", auto_header() is not None),
        ("gfortran", shutil.which("gfortran") is not None),
        ("gcc", shutil.which("gcc") is not None),
        ("make", shutil.which("make") is not None),
    ) if not ok]
    require_tool(not missing, ", ".join(missing) + " (Debian packages auto-07p gfortran)")
    return AUTO_DIR


# --- fort.7 ---------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Point:
    branch: int
    pt: int  # negative: stable
    ty: int  # 1 BP, 2 LP, 3 HB, 4 regular output (-4 UZ), 9 / -9 end points, 0 not printed to fort.8
    label: int
    values: dict  # column title of fort.7 (PAR(1), L2-NORM, U(1), ..., PAR(6)) -> value

    @property
    def stable(self) -> bool:
        return self.pt < 0

    @property
    def kind(self) -> str | None:
        return BIFURCATIONS.get(abs(self.ty))


def fortran_number(text: str) -> float:
    """Fortran E format; an exponent of three digits may lose its E ('1.7976+308')."""
    if not re.search(r"[eEdD]", text):
        text = re.sub(r"(?<=[0-9.])([+-]\d+)$", r"E\1", text)
    return float(text.replace("D", "E").replace("d", "e"))


def _titles(fields: list[str]) -> list[str]:
    """fort.7 column titles; periodic orbits (IPS = 2) print 'MAX U(1)', two words, joined here as 'MAX U(1)'."""
    out = []
    for field in fields:
        if out and out[-1] in ("MAX", "MIN"):
            out[-1] += " " + field
        else:
            out.append(field)
    return out


def read_fort7(path: Path) -> list[Point]:
    """Every continuation step of fort.7: lines starting with BR = 0 are headers (the last header
    before the data names its columns: 0 PT TY LAB PAR(1) L2-NORM U(1) ..., or MAX U(1) ... PERIOD
    for periodic orbits); the others are
    BR PT TY LAB followed by those columns."""
    points, titles = [], None
    for line in path.read_text().splitlines():
        fields = line.split()
        if not fields:
            continue
        if fields[0] == "0":
            if len(fields) > 4 and fields[1:4] == ["PT", "TY", "LAB"]:
                titles = _titles(fields[4:])
            continue
        assert titles is not None, f"fort.7 data before its column titles: {line!r}"
        br, pt, ty, lab = (int(v) for v in fields[:4])
        values = [fortran_number(v) for v in fields[4:]]
        assert len(values) == len(titles), line
        points.append(Point(br, pt, ty, lab, dict(zip(titles, values))))
    return points


def unlabelled_stability_changes(points: list[Point]) -> list[tuple[Point, Point]]:
    """Consecutive steps whose stability differs without a labelled bifurcation at either of them."""
    return [(a, b) for a, b in zip(points, points[1:])
            if a.branch == b.branch and a.stable != b.stable and not (a.kind or b.kind)]


# --- building and running -------------------------------------------------------------------------

def build_and_run(files: dict[str, str], name: str, workdir: Path, constants_file: str | None = None) -> str:
    """Write the user and constants files, build and run them with AUTO's make runner (reading the
    constants c.<name>, or `constants_file`); its output."""
    workdir.mkdir(parents=True, exist_ok=True)
    for filename, text in files.items():
        (workdir / filename).write_text(text)
    env = dict(os.environ, AUTO_DIR=str(AUTO_DIR))
    with open(workdir / (constants_file or f"c.{name}")) as constants:
        r = subprocess.run(["make", "-f", str(AUTO_DIR / "cmds" / "cmds.make"), f"EQUATION_NAME={name}"],
                           stdin=constants, cwd=workdir, env=env, capture_output=True, text=True, timeout=120)
    return f"--- stdout\n{r.stdout[-4000:]}\n--- stderr\n{r.stderr[-4000:]}"


def run_auto(files: dict[str, str], name: str, workdir: Path) -> list[Point]:
    """Build and run with AUTO's make runner, read fort.7."""
    log = build_and_run(files, name, workdir)
    # cmds.make is .IGNORE: a failed compile or run does not change make's exit status
    assert (workdir / f"{name}.exe").is_file(), f"AUTO build failed\n{log}"
    assert (workdir / "fort.7").is_file(), f"AUTO did not run\n{log}"
    assert "Unknown AUTO constant" not in log, log
    points = read_fort7(workdir / "fort.7")
    assert points, f"empty fort.7\n{log}"
    return points
