"""Render a model's intermediate form through the jinja2 templates of every registered target.

Targets are registered in `targets.REGISTRY`, their Python side in `targets/<name>/`, their templates
in the top-level `templates/<name>/` (shipped in the wheel); the output index (generated/__init__.py,
README.md) renders from `templates/package/`.  Files relative to the output folder, for the built-in
targets::

    <model>/__init__.py             numba module            targets/numba/, templates/numba/
    <model>/<model>.h, .c           C99 library             targets/c/, templates/c/
    <model>/<model>_cvode.h, .c     SUNDIALS CVODE adaptor  targets/cvode/, templates/cvode/
    <model>/<model>_cvode_main.c    CVODE driver program    targets/cvode/, templates/cvode/
    <model>/auto/<model>.c          AUTO-07p user file      targets/auto/, templates/auto/
    <model>/auto/c.<model>          AUTO-07p constants      targets/auto/, templates/auto/
    <model>/auto/c.<model>.2        its second stage (forced models: continuation in omega)

Rendering is pure: the same intermediate form and templates give the same bytes (sorted symbols,
fixed float formatting, no dates); the source hash in every header covers both.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
from functools import lru_cache

import jinja2
import sympy as sp

from .. import __version__
from ..errors import AdbgenError
from . import targets
from .emit import Emitter, tables
from .ir.model import ModelIR, Program
from .printers import identifiers


def package_templates():
    """The output index's templates (generated/__init__.py, README.md): templates/package/."""
    return targets.template_root() / "package"


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
    folders = {"package": package_templates()} | {t.name: t.template_folder for t in targets.all_targets()}
    for name, folder in folders.items():
        if not folder.is_dir():
            raise AdbgenError(f"templates of {name!r} not found at {folder} (a broken installation?)")
    loader = jinja2.PrefixLoader({name: jinja2.FileSystemLoader(str(folder)) for name, folder in folders.items()})
    env = jinja2.Environment(loader=loader, undefined=jinja2.StrictUndefined,
                             keep_trailing_newline=True, autoescape=False)
    env.filters.update(pyrepr=repr, pytuple=_pytuple, pylist=_pylist, cfloat=_c_float, cstr=_c_string)
    for target in targets.all_targets():
        env.filters.update(target.filters)
    return env


@lru_cache(maxsize=4)
def _template_digest(generation: int) -> str:
    """sha256 of every registered target's templates (names as the templates see them, and bytes, sorted)."""
    h = hashlib.sha256()
    files = sorted((f"{t.name}/{p.relative_to(t.template_folder).as_posix()}", p)
                   for t in targets.all_targets() for p in t.template_folder.rglob("*.j2"))
    package = package_templates()
    files += sorted((f"package/{p.relative_to(package).as_posix()}", p) for p in package.rglob("*.j2"))
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
    printer.set_program(program.assignments)
    outputs = [(i, printer.doprint(e)) for i, e in program.outputs]
    return {
        "states": states,
        "params": params,
        "uses_t": ir.time in used,
        "assignments": [(printer.doprint(lhs), printer.doprint(rhs)) for lhs, rhs in program.assignments],
        "outputs": outputs,
    }


def _c_string(text: str) -> str:
    """A C string literal."""
    return '"' + str(text).replace("\\", "\\\\").replace('"', '\\"') + '"'


def _c_float(value: float) -> str:
    text = repr(float(value))
    return text if any(c in text for c in ".eEn") else text + ".0"


def param_domain(symbol: sp.Symbol) -> str:
    """What values a parameter's symbol admits, from its assumptions (the derivation relies on them)."""
    return "positive" if symbol.is_positive else "nonnegative" if symbol.is_nonnegative else "real"


def describe_data(ir: ModelIR) -> dict:
    """The self-description as template data (names resolved to indices where a C array wants them);
    empty where the model declares none."""
    d = ir.description
    names, params = ir.state_names, ir.parameter_names
    if d is None:
        return {"present": False, "family": "", "kind": "", "time_unit": "", "state_units": [""] * ir.n_states,
                "roles": [""] * ir.n_states, "angles": [], "angle_indices": [], "amplitude": [],
                "amplitude_indices": [], "measures": [], "residual": "", "forcing_frequency": "", "forcing_index": -1,
                "symmetries": [], "parameter_sets": [], "scales": [], "labels": [], "forms": [], "max_args": 0,
                "steady_state_names": [], "equilibria": None}
    defaults = [q.default for q in ir.parameters]
    sets = []
    for name, values in d.parameter_sets:
        full = list(defaults)
        for k, v in values:
            full[params.index(k)] = v
        sets.append({"name": name, "values": dict(values), "vector": full})
    return {
        "present": True, "family": d.family, "kind": d.kind, "time_unit": d.time_unit, "state_units": list(d.state_units),
        "roles": list(d.roles), "angles": list(d.angles), "angle_indices": [names.index(a) for a in d.angles],
        "amplitude": list(d.amplitude), "amplitude_indices": [names.index(a) for a in d.amplitude],
        "measures": list(d.measure_names), "residual": d.residual, "forcing_frequency": d.forcing_frequency,
        "forcing_index": params.index(d.forcing_frequency) if d.forcing_frequency else -1,
        "symmetries": list(d.symmetries), "parameter_sets": sets,
        "scales": [{"key": k, "name": v, "index": params.index(v)} for k, v in d.scales],
        "labels": [{"label": label, "note": note, "form": form, "arguments": list(args)
                    + [0.0] * (max(1, d.max_arguments) - len(args))} for label, note, form, args in d.steady_states],
        "forms": [{"name": f.name, "candidates": len(f.candidates), "arguments": [a.name for a in f.arguments]}
                  for f in d.closed_forms],
        "max_args": max(1, d.max_arguments),
        "steady_state_names": list(d.steady_state_names),
        "equilibria": None if d.equilibria is None else dict(zip(("name", "zero", "constraints"), d.equilibria)),
    }


def _base_context(ir: ModelIR) -> dict:
    return {"ir": ir, "source_hash": source_hash(ir), "P": ir.name.upper(),
            "units": [p.unit for p in ir.parameters], "defaults": [p.default for p in ir.parameters],
            "param_domains": [param_domain(p.symbol) for p in ir.parameters],
            "coordinates": [s.name for s in ir.states[: ir.n_coordinates]], "version": __version__,
            "describe": describe_data(ir)}


def _programs(ir: ModelIR, target: "targets.Target") -> dict:
    """The target's functions printed by its printer in its dialect (`code`, and for the unrolled form
    the statements one by one), with the ball-slot tables the loop form reads."""
    out = {"tables": tables(ir.loops.split) if ir.loops is not None else [], "form": ir.form}
    if target.printer is None:
        return out
    names = identifiers(ir)
    printer = target.printer(names)
    kernels = ir.kernels()
    split = ir.loops.split if ir.loops is not None else None
    states, params = [s.symbol for s in ir.states], [q.symbol for q in ir.parameters]
    for key in target.functions:
        kernel = kernels[key]
        code = Emitter(kernel, target.dialect(key, kernel), printer, names, split, ir.n_coordinates, states,
                       params).emit(target.depth)
        ctx = {"shape": kernel.shape, "size": math.prod(kernel.shape), "code": code}
        program = getattr(ir, key)
        if program is not None:
            ctx.update(_program_context(program, ir, printer, names))
        out[key] = ctx
    if target.describe and ir.description is not None:
        out.update(_described(ir, target, printer, names, split, states, params))
    return out


def _described(ir: ModelIR, target, printer, names, split, states, params) -> dict:
    """The self-description's functions printed by the target: every measure, each measure alone,
    each closed form's candidates (reading their arguments from an array a, no time argument) and the
    gradients of the manifold of equilibria's constraints (no time argument)."""
    d = ir.description

    def code(kernel, which):
        return Emitter(kernel, target.dialect(which, kernel), printer, names, split, ir.n_coordinates, states,
                       params).emit(target.depth)

    def closed(kernel, form):
        dia = dataclasses.replace(target.dialect("closed_form", kernel), states="a", time=False)
        return Emitter(kernel, dia, printer, names, split, ir.n_coordinates, list(form.arguments),
                       params).emit(target.depth)

    out = {"measures": {"size": len(d.measure_names), "code": code(d.measures, "measures")},
           "measure_each": [code(k, "measure") for k in d.measure_kernels],
           "closed_forms": [[closed(k, f) for k in f.candidates] for f in d.closed_forms]}
    if d.equilibria_gradient is not None:  # (no time argument: a manifold of equilibria is autonomous)
        kernel = d.equilibria_gradient
        out["equilibria_gradient"] = Emitter(kernel, dataclasses.replace(target.dialect("equilibria", kernel), time=False),
                                             printer, names, split, ir.n_coordinates, states, params).emit(target.depth)
    return out


def context(ir: ModelIR, target: "targets.Target", _memo: dict | None = None) -> dict:
    """Everything one target's templates see for one model: the common data, the functions printed by
    the target's printer, and the target's own decisions (under the target's name).  `_memo` shares
    the common parts between the targets of one model."""
    memo = _memo if _memo is not None else {}
    if ("base", id(ir)) not in memo:
        memo[("base", id(ir))] = _base_context(ir)
    return {**memo[("base", id(ir))], "programs": _programs(ir, target), target.name: target.context(ir)}


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
