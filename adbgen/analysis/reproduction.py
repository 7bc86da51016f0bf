"""A reproduction document: published results recomputed, one section per reproduction, written as
markdown with its figures beside it (`adbgen reproduce`).

The sections come from the families' science packages (each family lists its own; this layer knows
none of them).  A `Reproduction` computes its results (`compute(fig_dir, progress)`) and turns them into
markdown lines (`lines(results, root)`, figure links relative to the document's folder `root`).  A
section not chosen this run is named with a line saying so.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

from .prose import render

TITLE = "# Reproduction of the published results"

# The document must come out byte-identical on any x86-64 machine (issue 23).  The compiled engines pin
# their own elementary functions (engines/fixed_libm.h); everything else picks its code by the processor
# when the process starts, and the variants differ in the last bit:
# * glibc's libm (CyRK's step-size control calls its pow, numba's code its sin and cos) picks FMA/AVX2
#   variants by ifunc; with these hardware capabilities masked every x86-64 processor runs the SSE2/AVX ones;
# * OpenBLAS (numpy's and scipy's, built DYNAMIC_ARCH: eigenvalues, Newton's solves, numba's dot) picks its
#   kernels by the processor (Haswell, SkylakeX, Zen, ...): forced to the Prescott kernels (SSE3, every
#   x86-64 processor of this kind has them), one thread (the split of a product must not follow the cores);
# * numpy's own SIMD loops (exp, log1p, arctan, tanh, power, ...) dispatch X86_V4 (AVX-512) / X86_V3 (AVX2,
#   FMA) / baseline: the first two disabled (both the numpy >= 2.3 names and the older ones; unknown names
#   are ignored).
# numba's LLVM code contracts no multiply-add and reorders no sum without fastmath, which nothing here asks.
PINNED_HWCAPS = ("-AVX2", "-FMA", "-FMA4")
PINNED_VARIABLES = {"OPENBLAS_CORETYPE": "Prescott", "OPENBLAS_NUM_THREADS": "1"}
PINNED_NUMPY_FEATURES = ("X86_V4", "X86_V3", "AVX512F", "AVX512CD", "AVX512_KNL", "AVX512_KNM", "AVX512_SKX",
                         "AVX512_CLX", "AVX512_CNL", "AVX512_ICL", "AVX512_SPR", "AVX2", "FMA3", "F16C", "AVX")


def _hwcaps(tunables: str) -> list[str]:
    for item in tunables.split(":"):
        key, _, value = item.partition("=")
        if key == "glibc.cpu.hwcaps":
            return [v for v in value.split(",") if v]
    return []


def environment_pinned(env=None) -> bool:
    """Does this process run pinned: glibc's per-processor libm variants masked (`PINNED_HWCAPS`), OpenBLAS's
    kernels and threads fixed (`PINNED_VARIABLES`), numpy's AVX loops off (`PINNED_NUMPY_FEATURES`)?"""
    env = os.environ if env is None else env
    return (set(PINNED_HWCAPS) <= set(_hwcaps(env.get("GLIBC_TUNABLES", "")))
            and all(env.get(k) == v for k, v in PINNED_VARIABLES.items())
            and set(PINNED_NUMPY_FEATURES) <= set(env.get("NPY_DISABLE_CPU_FEATURES", "").replace(",", " ").split()))


def pinned_environment(env=None) -> dict:
    """`env` (default os.environ) pinned: PINNED_HWCAPS added to GLIBC_TUNABLES (other tunables and masked
    capabilities kept: a machine emulated by masking more stays emulated), PINNED_VARIABLES set (a user's own
    OPENBLAS_CORETYPE replaced), PINNED_NUMPY_FEATURES added to NPY_DISABLE_CPU_FEATURES."""
    env = dict(os.environ if env is None else env)
    items = [i for i in env.get("GLIBC_TUNABLES", "").split(":") if i and not i.startswith("glibc.cpu.hwcaps=")]
    caps = _hwcaps(env.get("GLIBC_TUNABLES", ""))
    caps += [c for c in PINNED_HWCAPS if c not in caps]
    env["GLIBC_TUNABLES"] = ":".join(items + ["glibc.cpu.hwcaps=" + ",".join(caps)])
    env.update(PINNED_VARIABLES)
    features = env.get("NPY_DISABLE_CPU_FEATURES", "").replace(",", " ").split()
    env["NPY_DISABLE_CPU_FEATURES"] = " ".join(features + [f for f in PINNED_NUMPY_FEATURES if f not in features])
    return env


@dataclass(frozen=True)
class Coverage:
    """One published result (a figure, table or equation of a source document) and whether this document
    recomputes it: `source` names the document ("thesis", "paper"), `chapter` its chapter or section, `item`
    the figure or equation ("Fig. 5.11"), `where` the heading of this document that recomputes it (empty
    when not covered) and `reason` why it is not covered (empty when covered)."""

    source: str
    chapter: str
    item: str
    covered: bool
    where: str = ""
    reason: str = ""

    def __post_init__(self):
        if self.covered == bool(self.reason) or (self.covered and not self.where):
            raise ValueError(f"{self.item}: a covered result names where it is; one not covered says why")


@dataclass(frozen=True)
class Reproduction:
    """One section of the document: `key` chooses it (``adbgen reproduce --only KEY``), `title` names it
    where it is not computed; `coverage` lists the published results the section is responsible for (the
    table at the top of the document, written whether or not the section is computed this run)."""

    key: str
    title: str
    compute: Callable[[Path, Callable[[str], None] | None], Any]
    lines: Callable[[Any, Path], list[str]]
    coverage: tuple[Coverage, ...] = ()


_DOCS = Path(__file__).resolve().parents[2] / "docs"  # the repository's docs/, beside the package


def markdown_section(key: str, title: str, section: Callable[[Path, Callable[[str], None]], str],
                     coverage: tuple[Coverage, ...] = ()) -> Reproduction:
    """A section whose markdown `section(fig_dir, progress)` writes with two placeholders, @FIGURES@ (the
    figure folder) and @DOCS@ (the repository's docs/), made relative to the document's folder."""
    def compute(fig_dir: Path, progress=None) -> dict:
        return {"text": section(fig_dir, progress or (lambda *_: None)), "figures": Path(fig_dir)}

    def lines(results: dict, root: Path) -> list[str]:
        figures = Path(os.path.relpath(results["figures"], root)).as_posix()
        docs = Path(os.path.relpath(_DOCS, root)).as_posix()
        return results["text"].replace("@FIGURES@", figures).replace("@DOCS@", docs).splitlines()

    return Reproduction(key, title, compute, lines, coverage)


def document(sections: list[Reproduction], results: dict[str, Any], root: Path, command: str) -> list[str]:
    """The whole document: its opening and the table of published results covered (prose/reproduction.md.j2),
    then each section's lines in order; those without results (not chosen) named (prose/not_computed.md.j2)."""
    every = all(s.key in results for s in sections)
    lines = render("reproduction", title=TITLE, command=command, every=every,
                   rows=[c for s in sections for c in s.coverage])
    for section in sections:
        if lines[-1] != "":
            lines.append("")
        if section.key in results:
            lines += section.lines(results[section.key], root)
        else:
            lines += render("not_computed", title=section.title, command=command)
    return lines


def write(path: Path, lines: list[str]) -> Path:
    """The document through a temporary file (an interrupted run leaves the old one)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(".md.tmp")
    tmp.write_text("\n".join(lines) + "\n")
    tmp.replace(path)
    return path


def build(sections: list[Reproduction], chosen: tuple[str, ...], out_md: Path, fig_dir: Path, command: str,
          progress: Callable[[str], None] | None = print) -> Path:
    """Compute the chosen sections (in the order given), draw their figures into fig_dir, write out_md."""
    fig_dir.mkdir(parents=True, exist_ok=True)
    results = {s.key: s.compute(fig_dir, progress) for s in sections if s.key in chosen}
    return write(out_md, document(sections, results, out_md.parent, command))


__all__ = ["PINNED_HWCAPS", "PINNED_NUMPY_FEATURES", "PINNED_VARIABLES", "Coverage", "Reproduction", "TITLE",
           "build", "document", "environment_pinned", "markdown_section", "pinned_environment",
           "write"]
