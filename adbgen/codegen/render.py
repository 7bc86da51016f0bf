"""Render a model's intermediate form through the jinja2 templates of every registered target.

Targets live in `targets/<name>/` (templates beside their configuration, shipped in the wheel) and are
registered in `targets.REGISTRY`; the output index (generated/__init__.py, README.md) renders from
`package_templates/`.  Files relative to the output folder, for the built-in targets::

    <model>/__init__.py             numba module            targets/numba/
    <model>/<model>.h, .c           C99 library             targets/c/
    <model>/<model>_cvode.h, .c     SUNDIALS CVODE adaptor  targets/cvode/
    <model>/<model>_cvode_main.c    CVODE driver program    targets/cvode/
    <model>/auto/<model>.c          AUTO-07p user file      targets/auto/
    <model>/auto/c.<model>          AUTO-07p constants      targets/auto/
    <model>/auto/c.<model>.2        its second stage (forced models: continuation in omega)

Rendering is pure: the same intermediate form and templates give the same bytes (sorted symbols,
fixed float formatting, no dates); the source hash in every header covers both.
"""

from __future__ import annotations

import hashlib
import math
from functools import lru_cache
from pathlib import Path

import jinja2
import sympy as sp

from .. import __version__
from ..errors import AdbgenError
from . import targets
from .emit import Dialect, Emitter, tables
from .ir import KERNELS, ModelIR, Program
from .printers import CPrinter, PythonPrinter, identifiers

PACKAGE_TEMPLATES = Path(__file__).resolve().parent / "package_templates"


def _pytuple(values) -> str:
    values = list(values)
    if not values:
        return "()"
    inner = ", ".join(repr(v) for v in values)
    return f"({inner},)" if len(values) == 1 else f"({inner})"


def _pylist(values) -> str:
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def environment() -> jinja2.Environment:
    return _environment(targets.generation())


def template_digest() -> str:
    return _template_digest(targets.generation())


@lru_cache(maxsize=4)
def _environment(generation: int) -> jinja2.Environment:
    """One environment over every registered target's templates, each under its target's name
    ("c/model.c.j2" is targets/c/templates/model.c.j2), and the output index's ("package/...")."""
    folders = {"package": PACKAGE_TEMPLATES} | {t.name: t.templates for t in targets.all_targets()}
    for name, folder in folders.items():
        if not folder.is_dir():
            raise AdbgenError(f"templates of {name!r} not found at {folder} (a broken installation?)")
    loader = jinja2.PrefixLoader({name: jinja2.FileSystemLoader(str(folder)) for name, folder in folders.items()})
    env = jinja2.Environment(loader=loader, undefined=jinja2.StrictUndefined,
                             keep_trailing_newline=True, autoescape=False)
    env.filters.update(pyrepr=repr, pytuple=_pytuple, pylist=_pylist, cfloat=_c_float)
    for target in targets.all_targets():
        env.filters.update(target.filters)
    return env


@lru_cache(maxsize=4)
def _template_digest(generation: int) -> str:
    """sha256 of every registered target's templates (names as the templates see them, and bytes, sorted)."""
    h = hashlib.sha256()
    files = sorted((f"{t.name}/{p.relative_to(t.templates).as_posix()}", p)
                   for t in targets.all_targets() for p in t.templates.rglob("*.j2"))
    files += sorted((f"package/{p.relative_to(PACKAGE_TEMPLATES).as_posix()}", p) for p in PACKAGE_TEMPLATES.rglob("*.j2"))
    for name, path in sorted(files):
        h.update(name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def source_hash(ir: ModelIR) -> str:
    """Identifies what a generated file was made from: the model's intermediate form and the templates."""
    h = hashlib.sha256()
    h.update(ir.fingerprint().encode())
    h.update(template_digest().encode())
    h.update(__version__.encode())
    return h.hexdigest()[:16]


def _program_context(program: Program, ir: ModelIR, printer, names: dict) -> dict:
    """The unrolled program's statements and stores, printed (for targets that print them one by one)."""
    used: set = set()
    for _, e in program.assignments:
        used |= e.free_symbols
    for _, e in program.outputs:
        used |= sp.sympify(e).free_symbols
    states = [{"ident": names[s.symbol], "index": k} for k, s in enumerate(ir.states) if s.symbol in used]
    params = [{"ident": names[p.symbol], "index": k} for k, p in enumerate(ir.parameters) if p.symbol in used]
    ncol = program.shape[1] if len(program.shape) == 2 else 1
    printer.set_program(program.assignments)
    outputs = [(i, printer.doprint(e)) for i, e in program.outputs]
    return {
        "states": states,
        "params": params,
        "uses_t": any(s.name == "t" for s in used),
        "assignments": [(printer.doprint(lhs), printer.doprint(rhs)) for lhs, rhs in program.assignments],
        "outputs": outputs,
        "outputs2": [(i // ncol, i % ncol, e) for i, e in outputs],
    }


# (states, parameters, output) array names of each function, per dialect: the C library's and
# numba's functions take (t, y, p, out), AUTO-07p's func (u, par) and writes f, dfdu, dfdp
_ARRAYS = {"py": {}, "c": {"rhs": ("y", "p", "dydt")}, "auto": {}}
_AUTO_OUT = {"rhs": "f", "jac": "dfdu", "jac_p": "dfdp"}
NUMBA_SCRATCH = "_scratch({size})"  # targets/numba/templates/module.py.j2 defines _scratch (on the stack)


def _code(ir: ModelIR, which: str, kernel, dialect: str, printer, names: dict) -> str:
    ncol = kernel.shape[1] if len(kernel.shape) == 2 else 0
    if dialect == "auto":
        d = Dialect("c", "u", "par", _AUTO_OUT[which], ncol, auto=True, auto_columns=which == "jac_p",
                    indent="    ")
    else:
        y, p, out = _ARRAYS[dialect].get(which, ("y", "p", "out"))
        d = Dialect(dialect, y, p, out, ncol, scratch=NUMBA_SCRATCH if dialect == "py" else "")
    split = ir.loops.split if ir.loops is not None else None
    return Emitter(kernel, d, printer, names, split, ir.n_coordinates, [s.symbol for s in ir.states],
                   [q.symbol for q in ir.parameters]).emit(2 if dialect == "auto" else 1)


def _c_float(value: float) -> str:
    text = repr(float(value))
    return text if any(c in text for c in ".eEn") else text + ".0"


_PRINTERS = {"py": PythonPrinter, "c": CPrinter}


def _base_context(ir: ModelIR) -> dict:
    return {"ir": ir, "source_hash": source_hash(ir), "P": ir.name.upper(),
            "units": [p.unit for p in ir.parameters], "defaults": [p.default for p in ir.parameters],
            "coordinates": [s.name for s in ir.states[: ir.n_coordinates]], "version": __version__}


def _programs(ir: ModelIR, language: str) -> dict:
    names = identifiers(ir)
    printer = _PRINTERS[language](names)
    kernels = ir.kernels()
    out = {}
    for key in KERNELS:
        kernel = kernels[key]
        ctx = {"shape": kernel.shape, "size": math.prod(kernel.shape),
               "code": _code(ir, key, kernel, language, printer, names)}
        if language == "c" and key in _AUTO_OUT:
            ctx["auto"] = _code(ir, key, kernel, "auto", printer, names)
        program = getattr(ir, key)
        if program is not None:
            ctx.update(_program_context(program, ir, printer, names))
        out[key] = ctx
    out["tables"] = tables(ir.loops.split) if ir.loops is not None else []
    out["form"] = ir.form
    return out


def context(ir: ModelIR, target: "targets.Target", _memo: dict | None = None) -> dict:
    """Everything one target's templates see for one model: the common data, the programs printed in
    the target's language, and the target's own decisions (under the target's name).  `_memo` shares
    the common parts between the targets of one model."""
    memo = _memo if _memo is not None else {}
    if ("base", id(ir)) not in memo:
        memo[("base", id(ir))] = _base_context(ir)
    if (target.language, id(ir)) not in memo:
        memo[(target.language, id(ir))] = _programs(ir, target.language)
    return {**memo[("base", id(ir))], "programs": memo[(target.language, id(ir))], target.name: target.context(ir)}


def skipped_targets(ir: ModelIR, names=None) -> dict[str, str]:
    """Targets a model does not get, and why."""
    out = {}
    for target in targets.all_targets():
        if names is None or target.name in names:
            why = target.skip_reason(ir)
            if why:
                out[target.name] = why
    return out


def render_model(ir: ModelIR, names=None) -> dict[str, str]:
    """{relative path: text} of the files of the given targets (default: every registered one) for one model."""
    env = environment()
    files, memo = {}, {}
    for target in targets.all_targets():
        if (names is not None and target.name not in names) or target.skip_reason(ir):
            continue
        model = target.model_for(ir)
        if not target.loops:
            model = model.as_unrolled()
        memo.setdefault(("model", id(model)), model)  # keeps it alive: the memo is keyed by id
        ctx = context(model, target, memo)
        for template, path in target.files:
            text = env.get_template(template).render(**ctx)
            if text.strip():
                files[path.format(name=ir.name)] = text
    return files


def render_index(models: list[tuple[str, str, str]]) -> dict[str, str]:
    """The package files of the output folder: its __init__ (the model index) and README."""
    env = environment()
    return {path: env.get_template(tpl).render(models=models, version=__version__)
            for tpl, path in (("package/__init__.py.j2", "__init__.py"), ("package/README.md.j2", "README.md"))}
