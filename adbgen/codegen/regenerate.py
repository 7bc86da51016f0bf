"""`adbgen regenerate`: derive, check, render, and write atomically (or `--check` for staleness).

Everything is derived, checked and rendered in memory first; only when all of it has succeeded is
the output folder replaced, as a whole (`journal`: a sibling tree swapped in by renames, with a
journal that the next run rolls forward or back).  So bad input, a failed check or a run killed at
any point leave the output folder entirely old or entirely new.
"""

from __future__ import annotations

import difflib
import logging
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable

from . import journal
from ..core.model_spec import Check, ModelSpec
from .passes.checks import CheckFailed, Reference, check_description, check_programs, check_start
from .passes.lowering import DEFAULT_FORM
from .passes.proof import prove_index, prove_model, refusal
from .render import render_index, render_model, skipped_targets
from .spec import build

_ROOT = Path(__file__).resolve().parents[2]
# generated/ of the source checkout this package runs from; an installed package has none (give --out)
DEFAULT_OUT = _ROOT / "generated"
IN_SOURCE_CHECKOUT = (_ROOT / "pyproject.toml").is_file() and (_ROOT / "adbgen").is_dir()
DIFF_LINES = 40  # lines of unified diff shown per stale file by `regenerate --check`

__all__ = ["CheckFailed", "DEFAULT_OUT", "IN_SOURCE_CHECKOUT", "MODEL_STAGES", "Rendered", "STAGES", "Stage", "StageTime",
           "stage_list",            "diff", "render_all", "stale", "write"]

_log = logging.getLogger(__name__)


@dataclass(frozen=True)
class StageTime:
    """How long one stage took: `model` is the model's name for a per-model stage, "" otherwise."""

    model: str
    stage: str
    seconds: float


@dataclass(frozen=True)
class Rendered:
    files: dict[str, str]  # relative path -> text
    models: tuple[str, ...]
    # every stage run, in order (`STAGES`, `MODEL_STAGES`); for the caller, never written to a file
    timings: tuple[StageTime, ...] = ()


@dataclass(frozen=True)
class Stage:
    """One named step of `render_all`: `run(state)` reads what earlier stages left in the state and
    adds its own result; its docstring says what it takes and what it gives."""

    name: str
    run: Callable

    @property
    def doc(self) -> str:
        """What the stage takes and gives (its function's docstring, on one line)."""
        return " ".join((self.run.__doc__ or "").split())


@dataclass
class _Model:
    """One model's state, filled by `MODEL_STAGES` in order."""

    spec: ModelSpec
    targets: object
    form: str
    system: object = None
    ir: object = None
    reference: Reference | None = None
    errors: dict | None = None
    described: dict | None = None
    files: dict[str, str] | None = None
    proven: dict | None = None


def _derive(m: _Model) -> None:
    """Takes the spec; gives `system`: the first-order system its family derives by Lagrange's equations."""
    m.system = m.spec.system()


def _lower(m: _Model) -> None:
    """Takes `system`; gives `ir`, the intermediate form (`spec.build`: the passes ball_split, loop_form
    or lowering with cse, and description)."""
    m.ir = build(m.spec, m.system, form=m.form)


def _verify(m: _Model) -> None:
    """Takes `ir` and `system`; gives `errors` and `described`: the lowered programs against the derived
    system, the self-description, the start points (`passes.checks`); raises CheckFailed."""
    m.reference = Reference.of(m.system)
    m.errors = check_programs(m.ir, m.system, m.reference)
    m.described = check_description(m.ir, m.system)
    for model in (m.ir, m.ir.autonomous_extension):
        if model is not None and model.start is not None:
            check_start(model)


def _render(m: _Model) -> None:
    """Takes `ir`; gives `files`, {path: text}: every target's templates rendered (`render.render_model`)."""
    m.files = render_model(m.ir, m.targets)


def _prove(m: _Model) -> None:
    """Takes `ir` and `files`; gives `proven`: every target's files compiled and run against the
    intermediate form (`passes.proof.prove_model`); raises ProofFailed."""
    m.proven = prove_model(m.ir, m.files, m.targets, m.form, m.reference)


# what is done to each model, in order
MODEL_STAGES = (Stage("derive", _derive), Stage("lower", _lower), Stage("verify", _verify),
                Stage("render", _render), Stage("prove", _prove))


@dataclass
class _Run:
    """The state of one `render_all`, filled by `STAGES` in order."""

    specs: list[ModelSpec]
    targets: object
    run_checks: bool
    progress: Callable[[str], None]
    full_checks: bool
    form: str
    files: dict[str, str] = field(default_factory=dict)
    index: list = field(default_factory=list)
    timings: list[StageTime] = field(default_factory=list)


def _timed(stage: Stage, state, timings: list[StageTime], model: str = "") -> None:
    start = time.perf_counter()
    stage.run(state)
    seconds = time.perf_counter() - start
    timings.append(StageTime(model, stage.name, seconds))
    _log.debug("stage %s%s: %.3f s", f"{model} " if model else "", stage.name, seconds)


def _distinct_names(run: _Run) -> None:
    """Takes the specs; gives nothing: refuses two models of one name before any is derived."""
    names = [spec.name for spec in run.specs]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise CheckFailed(f"two models named {', '.join(twice)}")


def _reduction_checks(run: _Run) -> None:
    """Takes the specs; gives progress lines: the families' reduction checks (`Check`), each once,
    proportionate forms unless `full_checks`; raises CheckFailed."""
    if not run.run_checks:
        return
    for check in _checks_for(run.specs):
        scaled = check.scaled is not None and not run.full_checks
        with refusal(f"check {check.key}"):
            r = (check.scaled if scaled else check.run)()
        run.progress(f"check  {'ok  ' if r.passed else 'FAIL'} {r.name} [{r.reference}] ({r.seconds:.1f} s)"
                     + (" (proportionate form; --full-checks runs the exact one)" if scaled else ""))
        if not r.passed:
            raise CheckFailed(f"reduction check failed: {r.name} [{r.reference}]: {r.detail}")


def _models(run: _Run) -> None:
    """Takes the specs; gives `files` and the index entries: `MODEL_STAGES` for every model, each timed,
    with one progress line per model."""
    for k, spec in enumerate(run.specs, 1):
        start = time.perf_counter()
        m = _Model(spec, run.targets, run.form)
        with refusal(spec.name):
            for stage in MODEL_STAGES:
                _timed(stage, m, run.timings, spec.name)
        ir, errors, described, proven = m.ir, m.errors, m.described, m.proven
        run.files.update(m.files)
        run.index.append((ir.name, ir.title, ir.reference))
        run.progress(f"[{k}/{len(run.specs)}] {ir.name}: {ir.n_states} states, {ir.form}, rhs {ir.count_ops('rhs')} ops, "
                     f"jac {ir.count_ops('jac')} ops, lowering error {errors['rhs']:.1e} (jac {errors['jac']:.1e}), "
                     + (f"self-description checked ({len(ir.description.labels)} steady states"
                        + (f"; {', '.join(described['unexercised'])} given at no sampled parameters" if described
                           and described["unexercised"] else "") + "), " if described else "")
                     + f"{len(m.files)} files, proven: {' '.join(proven['targets'])}"
                     + (" (cached)" if proven["cached"] else f" ({proven['seconds']:.1f} s)")
                     + f" ({time.perf_counter() - start:.1f} s)"
                     + "".join(f"; no {t}: {why}" for t, why in skipped_targets(ir, run.targets).items()))


def _index(run: _Run) -> None:
    """Takes the index entries; gives the output folder's own files (__init__.py, README.md), proven."""
    with refusal("the output's index"):
        package = render_index(run.index)
        prove_index(package, run.index)
    run.files.update(package)


# what `render_all` does, in order (the "models" stage runs `MODEL_STAGES` for each model)
STAGES = (Stage("names", _distinct_names), Stage("reduction checks", _reduction_checks),
          Stage("models", _models), Stage("index", _index))


def stage_list() -> list[str]:
    """What `render_all` does, a line a stage in order ("models: ..." followed by its per-model stages):
    `python3 -c "from adbgen.codegen.regenerate import stage_list; print(*stage_list(), sep=chr(10))"`."""
    out = []
    for stage in STAGES:
        out.append(f"{stage.name}: {stage.doc}")
        if stage.run is _models:
            out += [f"  {s.name}: {s.doc}" for s in MODEL_STAGES]
    return out


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

    Runs `STAGES` in order, each timed (`Rendered.timings`, and a debug log line per stage).
    `targets`: names of the targets to render (default: every registered one).  Checks with a
    proportionate form (`Check.scaled`) run in that form unless `full_checks`; the progress lines
    say which form ran.  `form`: the lowering's form (`lowering.FORMS`)."""
    run = _Run(specs, targets, run_checks, progress, full_checks, form)
    for stage in STAGES:
        _timed(stage, run, run.timings)
    return Rendered(run.files, tuple(name for name, _, _ in run.index), tuple(run.timings))


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
