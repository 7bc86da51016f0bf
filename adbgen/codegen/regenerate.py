"""`adbgen regenerate`: derive, check, render, and write atomically (or `--check` for staleness).

Everything is derived, checked and rendered in memory first; only when all of it has succeeded are
files written, into a staging folder beside the output and then moved in with os.replace.  So bad
input, a failed check or an interrupted run leave the output folder exactly as it was (a kill can
only land in the final moves, which take milliseconds; each move is atomic).
"""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable

from ..errors import AdbgenError
from ..single_plane import verify
from .models import ModelSpec, lowering_error
from .render import TARGETS, render_index, render_model, skipped_targets

DEFAULT_OUT = Path(__file__).resolve().parents[2] / "generated"
IGNORED_DIRS = {"__pycache__"}
LOWERING_TOLERANCE = 1e-12


class CheckFailed(AdbgenError):
    pass


@dataclass(frozen=True)
class Rendered:
    files: dict[str, str]  # relative path -> text
    models: tuple[str, ...]


def _checks_for(specs: Iterable[ModelSpec]) -> list[Callable[[], verify.CheckResult]]:
    """The reduction checks behind the models: rotating frame, Appendix A and steady states for the
    thesis models, the fixed-frame derivation for the fixed-frame ones (once per n)."""
    checks, seen = [], set()
    for spec in specs:
        family = spec.name.rsplit("_n", 1)[0]
        kinds = {"thesis_rotating": (verify.rotating, verify.appendix_a, verify.steady_states),
                 "single_plane_fixed": (verify.prescribed_speed,)}.get(family, ())
        for fn in kinds:
            if (fn, spec.n) not in seen:
                seen.add((fn, spec.n))
                checks.append(lambda fn=fn, n=spec.n: fn(n))
    return checks


def _check_start(ir) -> None:
    """The start point is a steady state (an equilibrium; on an oscillator extension, a point of a
    periodic orbit at rest apart from the oscillator) of the rendered rhs, to rounding: 1e-12 of the
    rhs's size at the start with its angles turned by 0.1 rad."""
    import numpy as np

    from .interpret import compile_program

    f = compile_program(ir, "rhs")
    y, p = np.array(ir.start), np.array(ir.start_parameters)
    rows = slice(0, 2 * ir.n_coordinates)  # not the oscillator's rows, if any
    turned = y.copy()
    for k, name in enumerate(ir.state_names[: ir.n_coordinates]):
        if name.startswith("phi_"):
            turned[k] += 0.1
    scale = max(1.0, float(np.max(np.abs(f(0.0, turned, p)[rows]))))
    residual = float(np.max(np.abs(f(0.0, y, p)[rows])))
    if not residual <= 1e-12 * scale:
        raise CheckFailed(f"{ir.name}: the start point ({ir.start_label}) is not at rest: |rhs| = {residual:.2e} "
                          f"(scale {scale:.2e})")


def render_all(specs: list[ModelSpec], targets=tuple(TARGETS), run_checks: bool = True,
               progress: Callable[[str], None] = lambda line: None) -> Rendered:
    """Derive, check and render every model in memory; raises CheckFailed before anything is written."""
    if run_checks:
        for check in _checks_for(specs):
            r = check()
            progress(f"check  {'ok  ' if r.passed else 'FAIL'} {r.name} [{r.reference}] ({r.seconds:.1f} s)")
            if not r.passed:
                raise CheckFailed(f"reduction check failed: {r.name} [{r.reference}]: {r.detail}")
    files: dict[str, str] = {}
    index = []
    for k, spec in enumerate(specs, 1):
        start = time.perf_counter()
        system = spec.system()
        ir = spec.build()
        err = lowering_error(ir, system)
        if not err <= LOWERING_TOLERANCE:
            raise CheckFailed(f"{spec.name}: the structured rhs differs from the closed form by {err:.2e} "
                              f"(tolerance {LOWERING_TOLERANCE:g})")
        for model in (ir, ir.autonomous_extension):
            if model is not None and model.start is not None:
                _check_start(model)
        model_files = render_model(ir, targets)
        files.update(model_files)
        index.append((ir.name, ir.title, ir.reference))
        progress(f"[{k}/{len(specs)}] {ir.name}: {ir.n_states} states, rhs {ir.rhs.count_ops()} ops, "
                 f"jac {ir.jac.count_ops()} ops, lowering error {err:.1e}, {len(model_files)} files "
                 f"({time.perf_counter() - start:.1f} s)"
                 + "".join(f"; no {t}: {why}" for t, why in skipped_targets(ir).items() if t in targets))
    files.update(render_index(index))
    return Rendered(files, tuple(name for name, _, _ in index))


def _existing(out: Path) -> dict[str, Path]:
    found = {}
    if out.is_dir():
        for path in out.rglob("*"):
            rel = path.relative_to(out)
            if path.is_file() and not (set(rel.parts) & IGNORED_DIRS) and path.suffix != ".pyc":
                found[rel.as_posix()] = path
    return found


def stale(rendered: Rendered, out: Path, extra: bool = True) -> dict[str, str]:
    """{relative path: 'differs' | 'missing' | 'not generated'} for every file out of date.

    'not generated' (a file in `out` that nothing renders) is reported only with `extra`.
    """
    have = _existing(out)
    report = {}
    for rel, text in sorted(rendered.files.items()):
        if rel not in have:
            report[rel] = "missing"
        elif have[rel].read_bytes() != text.encode():
            report[rel] = "differs"
    for rel in sorted(set(have) - set(rendered.files)) if extra else ():
        report[rel] = "not generated"
    return report


def write(rendered: Rendered, out: Path, prune: bool = True) -> list[str]:
    """Write the rendered files into `out` through a staging folder; returns the paths changed.

    With `prune`, files in `out` that were not rendered are removed (only pass it when every target
    of every model was rendered).
    """
    out.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=f".{out.name}-staging-", dir=out.parent))
    changed = []
    try:
        report = stale(rendered, out, extra=prune)
        for rel, text in rendered.files.items():
            if report.get(rel) in ("missing", "differs"):
                target = staging / rel
                target.parent.mkdir(parents=True, exist_ok=True)
                target.write_bytes(text.encode())
        for rel, status in report.items():
            if status in ("missing", "differs"):
                (out / rel).parent.mkdir(parents=True, exist_ok=True)
                os.replace(staging / rel, out / rel)
                changed.append(rel)
            elif status == "not generated" and prune:
                (out / rel).unlink()
                changed.append(rel)
        if prune:
            for path in sorted(out.rglob("*"), key=lambda p: -len(p.parts)):
                if path.is_dir() and path.name not in IGNORED_DIRS and not any(path.iterdir()):
                    path.rmdir()
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return changed
