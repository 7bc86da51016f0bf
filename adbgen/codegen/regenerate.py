"""`adbgen regenerate`: derive, check, render, and write atomically (or `--check` for staleness).

Everything is derived, checked and rendered in memory first; only when all of it has succeeded is
the output folder replaced, as a whole (`journal`: a sibling tree swapped in by renames, with a
journal that the next run rolls forward or back).  So bad input, a failed check or a run killed at
any point leave the output folder entirely old or entirely new.
"""

from __future__ import annotations

import difflib
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable

from . import journal
from .checks import CheckFailed, Reference, check_description, check_programs, check_start
from .proof import prove_index, prove_model, refusal
from .render import render_index, render_model, skipped_targets
from .lowering import DEFAULT_FORM
from ..core.model_spec import Check, ModelSpec
from .spec import build

_ROOT = Path(__file__).resolve().parents[2]
# generated/ of the source checkout this package runs from; an installed package has none (give --out)
DEFAULT_OUT = _ROOT / "generated"
IN_SOURCE_CHECKOUT = (_ROOT / "pyproject.toml").is_file() and (_ROOT / "adbgen").is_dir()
DIFF_LINES = 40  # lines of unified diff shown per stale file by `regenerate --check`

__all__ = ["CheckFailed", "DEFAULT_OUT", "IN_SOURCE_CHECKOUT", "Rendered", "diff", "render_all", "stale", "write"]


@dataclass(frozen=True)
class Rendered:
    files: dict[str, str]  # relative path -> text
    models: tuple[str, ...]


def _checks_for(specs: Iterable[ModelSpec]) -> list[Check]:
    """The reduction checks the model specs carry, each once (models of one family share them)."""
    out, seen = [], set()
    for spec in specs:
        for check in spec.checks:
            if check.key not in seen:
                seen.add(check.key)
                out.append(check)
    return out


def render_all(specs: list[ModelSpec], targets=None, run_checks: bool = True,
               progress: Callable[[str], None] = lambda line: None, full_checks: bool = False,
               form: str = DEFAULT_FORM) -> Rendered:
    """Derive, check and render every model in memory; raises CheckFailed before anything is written.

    `targets`: names of the targets to render (default: every registered one).  Checks with a
    proportionate form (`Check.scaled`) run in that form unless `full_checks`; the progress lines
    say which form ran.  `form`: the lowering's form (`lowering.FORMS`)."""
    names = [spec.name for spec in specs]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise CheckFailed(f"two models named {', '.join(twice)}")
    if run_checks:
        for check in _checks_for(specs):
            scaled = check.scaled is not None and not full_checks
            with refusal(f"check {check.key}"):
                r = (check.scaled if scaled else check.run)()
            progress(f"check  {'ok  ' if r.passed else 'FAIL'} {r.name} [{r.reference}] ({r.seconds:.1f} s)"
                     + (" (proportionate form; --full-checks runs the exact one)" if scaled else ""))
            if not r.passed:
                raise CheckFailed(f"reduction check failed: {r.name} [{r.reference}]: {r.detail}")
    files: dict[str, str] = {}
    index = []
    for k, spec in enumerate(specs, 1):
        start = time.perf_counter()
        with refusal(spec.name):
            system = spec.system()
            ir = build(spec, system, form=form)
            reference = Reference.of(system)
            errors = check_programs(ir, system, reference)
            described = check_description(ir, system)
            for model in (ir, ir.autonomous_extension):
                if model is not None and model.start is not None:
                    check_start(model)
            model_files = render_model(ir, targets)
            proven = prove_model(ir, model_files, targets, form, reference)
        files.update(model_files)
        index.append((ir.name, ir.title, ir.reference))
        progress(f"[{k}/{len(specs)}] {ir.name}: {ir.n_states} states, {ir.form}, rhs {ir.count_ops('rhs')} ops, "
                 f"jac {ir.count_ops('jac')} ops, lowering error {errors['rhs']:.1e} (jac {errors['jac']:.1e}), "
                 + (f"self-description checked ({len(ir.description.labels)} steady states"
                    + (f"; {', '.join(described['unexercised'])} given at no sampled parameters" if described
                       and described["unexercised"] else "") + "), " if described else "")
                 + f"{len(model_files)} files, proven: {' '.join(proven['targets'])}"
                 + (" (cached)" if proven["cached"] else f" ({proven['seconds']:.1f} s)")
                 + f" ({time.perf_counter() - start:.1f} s)"
                 + "".join(f"; no {t}: {why}" for t, why in skipped_targets(ir, targets).items()))
    with refusal("the output's index"):
        package = render_index(index)
        prove_index(package, index)
    files.update(package)
    return Rendered(files, tuple(name for name, _, _ in index))


def stale(rendered: Rendered, out: Path, extra: bool = True) -> dict[str, str]:
    """{relative path: 'differs' | 'missing' | 'not generated'} for every file out of date.

    'not generated' (a file in `out` that nothing renders) is reported only with `extra`.
    """
    return journal.changes(rendered.files, out, prune=extra)


def diff(rendered: Rendered, out: Path, rel: str, lines: int = DIFF_LINES) -> str:
    """Unified diff of one stale file (what is in `out` -> what would be written), at most `lines` lines."""
    path = out / rel
    old = path.read_text(errors="replace").splitlines(keepends=True) if path.is_file() else []
    new = rendered.files.get(rel, "").splitlines(keepends=True)
    text = list(difflib.unified_diff(old, new, f"{out.name}/{rel} (on disk)", f"{out.name}/{rel} (regenerated)", n=2))
    shown = "".join(line if line.endswith("\n") else line + "\n" for line in text[:lines])
    if len(text) > lines:
        shown += f"... ({len(text) - lines} more diff lines)\n"
    return shown


def write(rendered: Rendered, out: Path, prune: bool = True) -> list[str]:
    """Replace `out` by the rendered tree, all at once (`journal.write`); returns the paths changed.

    With `prune`, files in `out` that were not rendered are dropped (only pass it when every target
    of every model was rendered); otherwise they are kept.
    """
    return journal.write(rendered.files, out, prune)
