"""Every emitted file proven before it is written (issue 20): the frame the targets' proofs run in.

`regenerate` renders a model's files in memory, then `prove_model` writes them into a temporary folder
and calls each rendered target's `Target.prove(proof)` (`targets/<name>/prove.py`): the C library is
compiled strictly and loaded, the CVODE adaptor and driver and the AUTO-07p user file are built
against harnesses, the numba module is executed, and every exported function is compared with the
model at the random states and parameters of the Python check (`checks.Reference.points`, seed 0:
angles and coordinates in [-0.1, 0.1], rates in [-1, 1], parameters 0.5x to 1.5x the defaults; away
from the start point, so AUTO's continuum term sees h != 0).  Only when every target of every model
is proven does regenerate write anything.

What a target's function is compared with (`Proof.expected`): rhs, mass and forcing with the symbolic
model (M and f lambdified, the accelerations by a dense solve: `checks.Reference`) and with the
checked programs of the intermediate form run in Python (`plain_python`; `checks.check_programs` has
shown them equal to the symbolic model, jac and jac_p to central differences of the dense solve);
jac and jac_p with those programs.  A target prints the same operations in the same order, so the
difference is rounding at most (measured: 0 for C, CVODE, AUTO-07p and numba); `TOLERANCE` leaves
room for a libm that rounds differently.

A verdict is cached (`$ADBGEN_CACHE/proofs`, default ~/.cache/adbgen) under the sha256 of the files'
texts, the intermediate form, the proofs' own source (`PROOF_SOURCES`) and the toolchain: the same
files are compiled and proven once.  Any exception while a proof runs is the
one-line refusal ``<model>: <target> files: ...`` (`ProofFailed`).
"""

from __future__ import annotations

import faulthandler
import hashlib
import os
import re
import signal
import sys
import tempfile
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Callable

import numpy as np

from .. import compiler, targets
from ...errors import AdbgenError
from ...outputs import cache_dir
from ..ir.model import KERNELS, ModelIR
from ..plain_python import compile_program
from .checks import CheckFailed, Reference, _apply, _project, _state_points

TOLERANCE = 1e-12  # a target's function against the checked programs, norm-wise relative (measured 0)
SYMBOLIC_TOLERANCE = 1e-12  # rhs, mass, forcing against the dense solve of the symbolic model (as `checks`)
SAMPLES = 12  # random points per model: those of `checks.errors_of`
SEED = 0
SENTINEL = 7.7e300  # what guard cells around an output hold (and must still hold after the call)
GUARD = 64  # guard cells on each side of an output array
ISOLATION_TIMEOUT = 120.0  # s for the compiled code of one target's proof
MESSAGE_BYTES = 4000

_PACKAGE = Path(__file__).resolve().parent


class ProofFailed(CheckFailed):
    """An emitted file does not do what the model says: the model is refused before anything is written."""


def _one_line(text: str) -> str:
    return re.sub(r"\s+", " ", str(text)).strip()


def relative(got, want) -> float:
    """max |got - want| / max(|want|, 1e-300) norm-wise (inf for a NaN, or a shape that differs)."""
    got, want = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
    if got.shape != want.shape:
        return np.inf
    if got.size == 0:
        return 0.0
    diff = float(np.max(np.abs(got - want)))
    if np.isnan(diff):
        return np.inf
    return diff / max(1e-300, float(np.max(np.abs(want))))


class Guarded:
    """A float64 output array of `size` cells between guard cells holding `SENTINEL`: a write past
    either end shows as a guard changed; the cells start as NaN, so a cell left unwritten shows too."""

    def __init__(self, size: int, fill: float = np.nan):
        self.size = size
        self.buffer = np.full(size + 2 * GUARD, SENTINEL)
        self.buffer[GUARD: GUARD + size] = fill

    @property
    def inner(self) -> np.ndarray:
        return self.buffer[GUARD: GUARD + self.size]

    def intact(self) -> bool:
        return bool(np.all(self.buffer[:GUARD] == SENTINEL) and np.all(self.buffer[GUARD + self.size:] == SENTINEL))

    def pointer(self):
        import ctypes

        return self.inner.ctypes.data_as(ctypes.POINTER(ctypes.c_double))


@dataclass
class Proof:
    """What a target's proof gets: the model, its rendered files (also written under `folder`), the
    references and the sample points; `fail` raises the one-line refusal naming the target."""

    ir: ModelIR
    files: dict[str, str]
    folder: Path
    reference: Reference
    form: str
    target: str = ""
    _memo: dict = field(default_factory=dict)

    # ------------------------------------------------------------------ files
    def path(self, rel: str) -> Path:
        return self.folder / rel

    def file(self, target: "targets.Target", template: str) -> str:
        """The relative path of `target`'s file rendered from `template` (ValueError if not rendered)."""
        for tpl, rel in target.files:
            if tpl == template:
                rel = rel.format(name=self.ir.name)
                if rel not in self.files:
                    raise ValueError(f"{rel} was not rendered")
                return rel
        raise ValueError(f"target {target.name} has no template {template}")

    def ensure(self, name: str) -> None:
        """Render target `name`'s files into the folder for the proof (not written out) if they are not
        there already (the CVODE adaptor is built over the C library even with --targets cvode)."""
        from ..render import render_model

        key = ("ensured", name)
        if key in self._memo:
            return
        for rel, text in render_model(self.ir, (name,)).items():
            path = self.folder / rel
            if rel not in self.files:
                path.parent.mkdir(parents=True, exist_ok=True)
                path.write_text(text)
            elif self.files[rel] != text:
                self.fail(f"{rel} renders differently twice")
        self._memo[key] = True

    def build_dir(self) -> Path:
        out = self.folder / ".proof"
        out.mkdir(exist_ok=True)
        return out

    def c_object(self, rel: str, include=(), defines=()) -> Path:
        """`rel` compiled with the strict flags into an object (once per proof)."""
        key = ("object", rel, tuple(include), tuple(defines))
        if key not in self._memo:
            stem = re.sub(r"[^A-Za-z0-9_]", "_", rel)
            self._memo[key] = compiler.compile_object(self.path(rel), self.build_dir() / f"{stem}.o", rel,
                                                      include=[self.path(rel).parent, *include], defines=defines)
        return self._memo[key]

    # ------------------------------------------------------------------ refusals
    def fail(self, message: str):
        raise ProofFailed(_one_line(f"{self.ir.name}: {self.target or 'proof'} files: {message}"))

    def compare(self, what: str, got, want, tolerance: float = TOLERANCE) -> float:
        err = relative(got, want)
        if not err <= tolerance:
            got, want = np.ravel(got), np.ravel(want)
            where = ""
            if got.shape == want.shape and got.size:
                k = int(np.nanargmax(np.where(np.isnan(got - want), np.inf, np.abs(got - want))))
                where = f" (entry {k}: {got[k]!r}, expected {want[k]!r})"
            self.fail(f"{what} differs from the model by {err:.2e} (tolerance {tolerance:g}){where}")
        return err

    def require(self, condition: bool, message: str) -> None:
        if not condition:
            self.fail(message)

    def isolated(self, what: str, fn: Callable[[], None], timeout: float = ISOLATION_TIMEOUT) -> None:
        """Run `fn` (which calls compiled code) in a forked child: emitted code that writes out of bounds,
        crashes or never returns is refused by name instead of taking regenerate down with it."""
        sys.stdout.flush()
        sys.stderr.flush()
        read, write = os.pipe()
        # what the child's code prints (glibc's "*** buffer overflow detected ***", a sanitizer) is kept
        # out of regenerate's output, whose stderr is the one-line refusal, and quoted in it instead
        output = tempfile.TemporaryFile()
        pid = os.fork()
        if pid == 0:  # the child: run, report on the pipe, leave without any clean-up of the parent's
            code, message = 0, ""
            try:
                os.close(read)
                os.dup2(output.fileno(), 1)
                os.dup2(output.fileno(), 2)
                faulthandler.disable()  # its dump of a crash would go to a stderr of its own; the parent reports
                fn()
            except ProofFailed as exc:
                code, message = 1, str(exc)
            except BaseException as exc:  # noqa: BLE001 - everything is reported to the parent
                code, message = 2, f"{type(exc).__name__}: {exc}"
            try:
                os.write(write, message.encode()[:MESSAGE_BYTES])
            finally:
                os._exit(code)
        os.close(write)
        deadline = time.monotonic() + timeout
        try:
            while True:
                done, status = os.waitpid(pid, os.WNOHANG)
                if done:
                    break
                if time.monotonic() > deadline:
                    os.kill(pid, signal.SIGKILL)
                    os.waitpid(pid, 0)
                    self.fail(f"{what} does not return within {timeout:g} s")
                time.sleep(0.002)
            message = os.read(read, MESSAGE_BYTES + 16).decode(errors="replace")
            output.seek(0)
            printed = [ln.strip() for ln in output.read(MESSAGE_BYTES).decode(errors="replace").splitlines() if ln.strip()]
        finally:
            os.close(read)
            output.close()
        if os.WIFSIGNALED(status):
            self.fail(f"{what} crashed ({signal.Signals(os.WTERMSIG(status)).name})"
                      + (f", printing {printed[-1][:200]!r}" if printed else ""))
        code = os.WEXITSTATUS(status)
        if code == 1:
            raise ProofFailed(message)
        if code != 0:
            self.fail(message or f"{what}: exit status {code}")

    # ------------------------------------------------------------------ references
    def model(self, target: "targets.Target") -> ModelIR:
        """The form of the model `target` renders (AUTO: a forced model's oscillator extension)."""
        return target.model_for(self.ir)

    def samples(self, model: ModelIR | None = None) -> list[tuple[float, np.ndarray, np.ndarray]]:
        """The Python check's random points (t, y, p); for an oscillator extension the forced model's
        points with the oscillator on its cycle (sin, cos)(w t) for even k and off it for odd k."""
        model = model or self.ir
        key = ("samples", id(model))
        if key not in self._memo:
            ref = self.reference
            pts = [(t, y, p) for t, y, p in ref.points(self.ir.n_states, self.ir.n_coordinates, SAMPLES, SEED)]
            if model is not self.ir:
                k_w = model.parameter_names.index(model.forcing_frequency) if model.forcing_frequency else None
                rng = np.random.default_rng(SEED + 1)
                ext = []
                for k, (t, y, p) in enumerate(pts):
                    extra = model.n_states - y.size
                    if k % 2 == 0 and k_w is not None and extra == 2:
                        osc = [np.sin(p[k_w] * t), np.cos(p[k_w] * t)]
                    else:
                        osc = rng.uniform(-1.2, 1.2, extra)
                    ext.append((t, np.concatenate([y, osc]), p))
                pts = ext
            self._memo[key] = pts
        return self._memo[key]

    def programs(self, model: ModelIR | None = None) -> dict[str, Callable]:
        model = model or self.ir
        key = ("programs", id(model))
        if key not in self._memo:
            self._memo[key] = {name: compile_program(model, name) for name in KERNELS}
        return self._memo[key]

    def expected(self, which: str, t: float, y, p, model: ModelIR | None = None) -> np.ndarray:
        """What function `which` (rhs, jac, jac_p, mass, forcing) of `model` must give, flat row-major:
        the checked program's value, itself within SYMBOLIC_TOLERANCE of the symbolic model for rhs,
        mass and forcing of the model (not of an extension, whose rows of the oscillator the symbolic
        model does not have)."""
        model = model or self.ir
        key = ("expected", id(model), which, float(t), np.asarray(y).tobytes(), np.asarray(p).tobytes())
        hit = self._memo.get(key)
        if hit is not None:
            return hit
        value = np.asarray(self.programs(model)[which](t, y, p), dtype=float).ravel()
        if model is self.ir and which in ("rhs", "mass", "forcing"):
            ref = self.reference
            symbolic = {"rhs": ref.rhs, "mass": ref.M, "forcing": ref.f}[which](t, np.asarray(y, float), p).ravel()
            err = relative(value, symbolic)
            if not err <= SYMBOLIC_TOLERANCE:
                self.fail(f"the checked program {which} differs from the symbolic model by {err:.2e}")
        self._memo[key] = value
        return value

    def expected_all(self, model: ModelIR | None = None) -> None:
        """Every `expected` value at the samples computed here (a forked proof inherits them)."""
        for t, y, p in self.samples(model):
            for which in KERNELS:
                self.expected(which, t, y, p, model)

    def symmetric_points(self, model: ModelIR | None = None, samples: int = 3):
        """(symmetry, t, y, p) at random states fixed by each identical-balls exchange the model
        declares (balls together), parameters made invariant: there rhs must be exchange-invariant
        bitwise (the printers' ball-invariant order)."""
        from ...core.description import IDENTICAL_BALLS

        base = self.ir
        if base.description is None:
            return []
        out = []
        for s in base.description.symmetries:
            if s["kind"] != IDENTICAL_BALLS:
                continue
            extra = model.n_states - base.n_states if model is not None else 0
            # on an oscillator extension the exchange leaves the oscillator's states where they are
            image = dict(s, states=tuple(s["states"]) + tuple(range(base.n_states, base.n_states + extra)),
                         signs=tuple(s["signs"]) + (1,) * extra)
            for t, y, p in _state_points(base, samples, 29):
                p = _project(p, s["params"], s["param_signs"])
                y = np.concatenate([_project(y, s["states"], s["signs"]), [np.sin(0.3), np.cos(0.3)][:extra]])
                out.append((image, t, y, p))
        return out

    def exchange_bitwise(self, what: str, rhs: Callable, model: ModelIR | None = None) -> int:
        """rhs(t, y, p) at `symmetric_points` equals its exchange bitwise; returns the points checked."""
        count = 0
        for s, t, y, p in self.symmetric_points(model):
            f = np.asarray(rhs(t, y, p), dtype=float)
            g = _apply(f, s["states"], s["signs"])
            if not np.array_equal(f, g):
                k = int(np.argmax(f != g))
                self.fail(f"{what} breaks the exchange symmetry {s['name']!r} of identical balls: at a state where "
                          f"the balls coincide, entry {k} is {f[k]!r} but its image {g[k]!r} (must be bitwise equal)")
            count += 1
        return count


# ---------------------------------------------------------------------------------------------- cache


# what decides whether files are proven, besides the files and the model: the frame, the toolchain, the
# symbolic reference, and every target's proof and harness (the programs `expected` also runs are
# checked against the symbolic model in the same run, so they need not be part of the key)
PROOF_SOURCES = ("proof.py", "compiler.py", "checks.py", "targets/*/prove.py", "targets/*/harness.c")


@lru_cache(maxsize=1)
def _own_source() -> str:
    """sha256 of the proofs' own source (PROOF_SOURCES)."""
    h = hashlib.sha256()
    for path in sorted({p for pattern in PROOF_SOURCES for p in _PACKAGE.glob(pattern)}):
        h.update(path.relative_to(_PACKAGE).as_posix().encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def verdict_key(ir: ModelIR, files: dict[str, str], names, form: str) -> str:
    h = hashlib.sha256()
    for item in (ir.fingerprint(), form, tuple(sorted(names)), _own_source(), compiler.identity()):
        h.update(repr(item).encode())
    for rel, text in sorted(files.items()):
        h.update(rel.encode())
        h.update(hashlib.sha256(text.encode()).digest())
    return h.hexdigest()


def _cached(key: str) -> bool:
    return (cache_dir() / "proofs" / key).is_file()


def _remember(key: str) -> None:
    folder = cache_dir() / "proofs"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=".verdict-")
        with os.fdopen(fd, "w") as f:
            f.write("proven\n")
        os.replace(tmp, folder / key)
    except OSError:  # a read-only cache only costs the next run its proofs
        pass


# ---------------------------------------------------------------------------------------------- driver


def _overrides_prove(target: "targets.Target") -> bool:
    return type(target).prove is not targets.Target.prove or targets.proof_module(target) is not None


def check_form(ir: ModelIR, form: str) -> None:
    """The form produced is the form requested (the lowering raises where the per-ball split fails)."""
    if ir.form != form:
        raise ProofFailed(f"{ir.name}: the {form} form was requested but the {ir.form} form was produced")
    if ir.autonomous_extension is not None and ir.autonomous_extension.form != form:
        raise ProofFailed(f"{ir.name}: the {form} form was requested but its oscillator extension has the "
                          f"{ir.autonomous_extension.form} form")


def prove_model(ir: ModelIR, files: dict[str, str], names=None, form: str | None = None,
                reference: Reference | None = None, system=None) -> dict:
    """Prove every file of one model rendered by the targets `names` (default: all registered): raises
    ProofFailed (one line) or returns {"targets": (...), "seconds": s, "cached": bool}."""
    start = time.perf_counter()
    form = form or ir.form
    check_form(ir, form)
    chosen = [t for t in targets.all_targets() if (names is None or t.name in names) and not t.skip_reason(ir)]
    proven = tuple(t.name for t in chosen)
    key = verdict_key(ir, files, proven, form)
    if _cached(key):
        return {"targets": proven, "seconds": time.perf_counter() - start, "cached": True}
    if reference is None:
        reference = Reference.of(system)
    with tempfile.TemporaryDirectory(prefix=f"adbgen-proof-{ir.name}-") as tmp:
        folder = Path(tmp)
        for rel, text in files.items():
            path = folder / rel
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
        proof = Proof(ir, files, folder, reference, form)
        for target in chosen:
            proof.target = target.name
            if not _overrides_prove(target):
                proof.fail(f"target {target.name!r} has no proof of its files, and nothing unproven is written: "
                           f"give it a prove(proof) method (adbgen/codegen/targets/{target.name}/prove.py; "
                           "docs/proofs.md says what a proof compares), or leave it out with --targets")
            try:
                target.prove(proof)
            except ProofFailed:
                raise
            except AdbgenError as exc:
                proof.fail(str(exc))
            except Exception as exc:  # noqa: BLE001 - any failure of a proof is the refusal
                proof.fail(f"{type(exc).__name__}: {exc}")
    _remember(key)
    return {"targets": proven, "seconds": time.perf_counter() - start, "cached": False}


@contextmanager
def refusal(model: str):
    """Any exception while a model is derived, checked, rendered or proven becomes the one-line refusal
    ``<model>: ...`` (CheckFailed; the command line prints ``adbgen: error: <model>: ...``)."""
    try:
        yield
    except CheckFailed as exc:
        text = _one_line(str(exc))
        raise type(exc)(text if text.startswith(f"{model}:") else f"{model}: {text}") from exc
    except AdbgenError:
        raise
    except Exception as exc:  # noqa: BLE001 - the refusal names what failed, the traceback is chained
        raise CheckFailed(_one_line(f"{model}: {type(exc).__name__}: {exc}")) from exc


def prove_index(files: dict[str, str], models: list[tuple[str, str, str]]) -> None:
    """The output folder's package files: __init__.py executed, MODELS = {name: title} of every model,
    and README.md's table naming each model with its title."""
    text = files.get("__init__.py")
    scope: dict = {}
    try:
        exec(compile(text, "__init__.py", "exec"), scope)  # noqa: S102 - the file just rendered
    except Exception as exc:  # noqa: BLE001
        raise ProofFailed(_one_line(f"the output's __init__.py does not run: {type(exc).__name__}: {exc}")) from exc
    want = {name: title for name, title, _ in models}
    if scope.get("MODELS") != want:
        raise ProofFailed(_one_line(f"the output's __init__.py lists {scope.get('MODELS')!r}, not {want!r}"))
    readme = files.get("README.md", "")
    for name, title, reference in models:
        if f"| `{name}` | {title} | {reference} |" not in readme:
            raise ProofFailed(_one_line(f"the output's README.md does not list {name}"))
