"""Render a model's intermediate form through the jinja2 templates of every target.

Targets (files relative to the output folder)::

    <model>/__init__.py             numba module            templates/numba/module.py.j2
    <model>/<model>.h, .c           C99 library             templates/c/
    <model>/<model>_cvode.h, .c     SUNDIALS CVODE adaptor  templates/cvode/
    <model>/<model>_cvode_main.c    CVODE driver program    templates/cvode/
    <model>/auto/<model>.c          AUTO-07p user file      templates/auto/
    <model>/auto/c.<model>          AUTO-07p constants      templates/auto/
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
from .ir import ModelIR, Program
from .printers import CPrinter, PythonPrinter, identifiers

TEMPLATES = Path(__file__).resolve().parents[2] / "templates"


def _pytuple(values) -> str:
    values = list(values)
    if not values:
        return "()"
    inner = ", ".join(repr(v) for v in values)
    return f"({inner},)" if len(values) == 1 else f"({inner})"


def _pylist(values) -> str:
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


@lru_cache(maxsize=1)
def environment() -> jinja2.Environment:
    if not TEMPLATES.is_dir():
        raise AdbgenError(f"templates folder not found at {TEMPLATES}")
    env = jinja2.Environment(loader=jinja2.FileSystemLoader(str(TEMPLATES)), undefined=jinja2.StrictUndefined,
                             keep_trailing_newline=True, autoescape=False)
    env.filters.update(pyrepr=repr, pytuple=_pytuple, pylist=_pylist, cfloat=_c_float)
    return env


def template_digest() -> str:
    """sha256 of every template file (names and bytes, sorted)."""
    h = hashlib.sha256()
    for path in sorted(TEMPLATES.rglob("*.j2")):
        h.update(path.relative_to(TEMPLATES).as_posix().encode())
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
        "shape": program.shape,
        "size": math.prod(program.shape),
    }


def _c_float(value: float) -> str:
    text = repr(float(value))
    return text if any(c in text for c in ".eEn") else text + ".0"


def context(ir: ModelIR) -> dict:
    names = identifiers(ir)
    out = {"ir": ir, "source_hash": source_hash(ir), "P": ir.name.upper(),
           "units": [p.unit for p in ir.parameters], "defaults": [p.default for p in ir.parameters],
           "coordinates": [s.name for s in ir.states[: ir.n_coordinates]], "version": __version__}
    for lang, printer in (("py", PythonPrinter(names)), ("c", CPrinter(names))):
        out[f"programs_{lang}"] = {key: _program_context(getattr(ir, key), ir, printer, names)
                                   for key in ("rhs", "jac", "jac_p", "mass", "forcing")}
    return out


# (template, output path) per target; {name} is the model's name
TARGETS = {
    "numba": [("numba/module.py.j2", "{name}/__init__.py", "py")],
    "c": [("c/model.h.j2", "{name}/{name}.h", "c"), ("c/model.c.j2", "{name}/{name}.c", "c")],
    "cvode": [("cvode/adaptor.h.j2", "{name}/{name}_cvode.h", "c"), ("cvode/adaptor.c.j2", "{name}/{name}_cvode.c", "c"),
              ("cvode/driver.c.j2", "{name}/{name}_cvode_main.c", "c")],
    "auto": [("auto/user.c.j2", "{name}/auto/{name}.c", "c"), ("auto/constants.j2", "{name}/auto/c.{name}", "c"),
             # second continuation stage: forced models only (the template is empty otherwise)
             ("auto/constants_stage2.j2", "{name}/auto/c.{name}.2", "c")],
}


def skipped_targets(ir: ModelIR) -> dict[str, str]:
    """Targets a model does not get, and why."""
    if ir.autonomous or ir.autonomous_extension is not None:
        return {}
    return {"auto": "explicit time and no autonomous extension with a known start orbit "
                     "(AUTO-07p continues autonomous systems only)"}


def render_model(ir: ModelIR, targets=tuple(TARGETS)) -> dict[str, str]:
    """{relative path: text} of every target's files for one model."""
    env = environment()
    ctx = context(ir)
    files = {}
    for target in targets:
        if target in skipped_targets(ir):
            continue
        # AUTO-07p gets a periodically forced model as its autonomous extension (oscillator)
        tctx = context(ir.autonomous_extension) if target == "auto" and not ir.autonomous else ctx
        for template, path, lang in TARGETS[target]:
            text = env.get_template(template).render(**tctx, programs=tctx[f"programs_{lang}"])
            if text.strip():
                files[path.format(name=ir.name)] = text
    return files


def render_index(models: list[tuple[str, str, str]]) -> dict[str, str]:
    """The package files of the output folder: its __init__ (the model index) and README."""
    env = environment()
    return {path: env.get_template(tpl).render(models=models, version=__version__)
            for tpl, path in (("package/__init__.py.j2", "__init__.py"), ("package/README.md.j2", "README.md"))}
