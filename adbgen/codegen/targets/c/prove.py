"""The C library's proof (issue 20): `<model>.c` compiled with the strict flags, loaded, every export compared.

`<model>.c` is compiled with `compiler.STRICT_CFLAGS` (a warning refuses it) and linked with a probe
that includes `<model>.h` first and alone (twice: the include guard) and takes every exported function's
address through a pointer of the documented type (a prototype that differs does not compile), and
records the header's macros.  Loaded with ctypes (RTLD_LOCAL), at the Python check's random points:

- rhs, jac, jac_p, mass and forcing equal `Proof.expected` (outputs between guard cells: a write
  past either end, e.g. a row stride of the rows instead of the columns, refuses; cells start as NaN,
  so one left unwritten refuses), and leave their inputs alone;
- the macros (sizes, SOURCE_HASH, HAS_START and the self-description's), the names, defaults, start
  and every array of the self-description equal the intermediate form's;
- measures, measure(k) (NAN out of range) and steady_state(k, p, y) equal the self-description's
  measures and closed forms (0 and all NAN where there is none, and out of range);
- identical balls' accelerations are bitwise equal where the balls coincide;
- the loop form requested is the form printed (the rhs loops over the balls).
"""

from __future__ import annotations

import ctypes
from pathlib import Path

import numpy as np

from ... import compiler
from ...passes.checks import _parameter_points
from ...plain_python import compile_measures, compile_steady_states
from ...passes.proof import Guarded
from ...render import param_domain, source_hash

DOUBLE_P = ctypes.c_void_p
FUNCTIONS = ("rhs", "jac", "jac_p", "mass", "forcing")


def declared_arrays(ir) -> list[tuple[str, str, tuple[str, ...]]]:
    """(symbol suffix, element type, dimensions as the header's macros) of every array the header must
    declare for this model (the self-description contract of issue 19)."""
    STR, INT, DBL = "const char *const", "const int", "const double"
    out = [("state_names", STR, ("N_STATES",)), ("param_names", STR, ("N_PARAMS",)), ("defaults", DBL, ("N_PARAMS",))]
    if ir.start is not None:
        out += [("start", DBL, ("N_STATES",)), ("start_parameters", DBL, ("N_PARAMS",))]
    d = ir.description
    if d is not None:
        out += [("state_units", STR, ("N_STATES",)), ("state_roles", STR, ("N_STATES",)),
                ("param_domains", STR, ("N_PARAMS",))]
        if d.angles:
            out.append(("angles", INT, ("N_ANGLES",)))
        if d.measure_names:
            out.append(("measure_names", STR, ("N_MEASURES",)))
        if d.symmetries:
            out += [("symmetry_names", STR, ("N_SYMMETRIES",)), ("symmetry_kinds", STR, ("N_SYMMETRIES",))]
            out += [(f"symmetry_{key}", INT, ("N_SYMMETRIES", width))
                    for key, width in (("states", "N_STATES"), ("signs", "N_STATES"), ("params", "N_PARAMS"),
                                       ("param_signs", "N_PARAMS"))]
        if d.parameter_sets:
            out += [("parameter_set_names", STR, ("N_PARAMETER_SETS",)),
                    ("parameter_sets", DBL, ("N_PARAMETER_SETS", "N_PARAMS"))]
        if d.steady_states:
            out += [("steady_state_labels", STR, ("N_STEADY_STATES",)), ("steady_state_notes", STR, ("N_STEADY_STATES",))]
    return out


def _probe(ir) -> str:
    """C source: the header alone, its macros as data, every function through a pointer of its type and
    every array through a pointer to an array of its declared type and size (an array the header does
    not declare, or declares otherwise, does not compile)."""
    P, m = ir.name.upper(), ir.name
    lines = [f'#include "{m}.h"', f'#include "{m}.h"', "",
             f"const long proof_macros[] = {{ {P}_N_STATES, {P}_N_PARAMS, {P}_N_COORDINATES, {P}_N_BALLS, "
             f"{P}_AUTONOMOUS, {P}_HAS_START }};",
             f"const char *const proof_hash = {P}_SOURCE_HASH;"]
    for fn in FUNCTIONS:
        lines.append(f"void (*const proof_fn_{fn})(double, const double *, const double *, double *) = {m}_{fn};")
    if ir.description is not None:
        lines += [f"const char *const proof_strings[] = {{ {P}_FAMILY, {P}_KIND, {P}_TIME_UNIT, {P}_FORCING_FREQUENCY }};",
                  f"const long proof_describe[] = {{ {P}_N_ANGLES, {P}_AMPLITUDE_0, {P}_AMPLITUDE_1, {P}_N_MEASURES, "
                  f"{P}_FORCING_FREQUENCY_INDEX, {P}_SCALE_ECCENTRICITY, {P}_SCALE_SPEED, {P}_N_SYMMETRIES, "
                  f"{P}_N_PARAMETER_SETS, {P}_N_STEADY_STATES }};",
                  f"void (*const proof_fn_measures)(double, const double *, const double *, double *) = {m}_measures;",
                  f"double (*const proof_fn_measure)(int, double, const double *, const double *) = {m}_measure;",
                  f"int (*const proof_fn_steady_state)(int, const double *, double *) = {m}_steady_state;"]
    for symbol, ctype, dims in declared_arrays(ir):
        shape = "".join(f"[{P}_{d}]" for d in dims)
        lines.append(f"{ctype} (*const proof_array_{symbol}){shape} = &{m}_{symbol};")
    return "\n".join(lines) + "\n"


class Library:
    """The model's C library loaded with ctypes; `call(fn, t, y, p, size)` on guarded outputs."""

    def __init__(self, proof, path: Path, ir):
        self.proof, self.ir, self.name = proof, ir, ir.name
        self.cdll = ctypes.CDLL(str(path))

    def close(self) -> None:
        import _ctypes

        _ctypes.dlclose(self.cdll._handle)

    def fn(self, suffix: str, restype=None, argtypes=(ctypes.c_double, DOUBLE_P, DOUBLE_P, DOUBLE_P)):
        f = getattr(self.cdll, f"{self.name}_{suffix}")
        f.restype, f.argtypes = restype, list(argtypes)
        return f

    def array(self, symbol: str, ctype, *shape):
        total = int(np.prod(shape))
        raw = list((ctype * total).in_dll(self.cdll, symbol))
        if ctype is ctypes.c_char_p:
            raw = [b.decode() if b is not None else None for b in raw]
        return raw

    def call(self, suffix: str, t: float, y, p, size: int) -> np.ndarray:
        y, p = np.array(y, dtype=float), np.array(p, dtype=float)
        y0, p0 = y.copy(), p.copy()
        out = Guarded(size)
        self.fn(suffix)(float(t), y.ctypes.data, p.ctypes.data, out.inner.ctypes.data)
        self.proof.require(out.intact(), f"{self.name}_{suffix} writes outside its {size} output values")
        self.proof.require(np.array_equal(y, y0) and np.array_equal(p, p0), f"{self.name}_{suffix} changes its inputs")
        return out.inner.copy()


def _metadata(proof, lib: Library, ir) -> None:
    S, P = ir.n_states, len(ir.parameters)
    macros = lib.array("proof_macros", ctypes.c_long, 6)
    want = [S, P, ir.n_coordinates, ir.n_balls, int(ir.autonomous), int(ir.start is not None)]
    proof.require(macros == want, f"the header's N_STATES, N_PARAMS, N_COORDINATES, N_BALLS, AUTONOMOUS, "
                                  f"HAS_START are {macros}, the model's {want}")
    got = ctypes.c_char_p.in_dll(lib.cdll, "proof_hash").value.decode()
    proof.require(got == source_hash(ir), f"SOURCE_HASH is {got!r}, not {source_hash(ir)!r}")
    m = ir.name
    checks = [("state_names", ctypes.c_char_p, S, list(ir.state_names)),
              ("param_names", ctypes.c_char_p, P, list(ir.parameter_names)),
              ("defaults", ctypes.c_double, P, [q.default for q in ir.parameters])]
    if ir.start is not None:
        checks += [("start", ctypes.c_double, S, list(ir.start)),
                   ("start_parameters", ctypes.c_double, P, list(ir.start_parameters))]
    d = ir.description
    if d is not None:
        names, params = ir.state_names, ir.parameter_names
        strings = lib.array("proof_strings", ctypes.c_char_p, 4)
        want_s = [d.family, d.kind, d.time_unit, d.forcing_frequency]
        proof.require(strings == want_s, f"FAMILY, KIND, TIME_UNIT, FORCING_FREQUENCY are {strings}, not {want_s}")
        scales = dict(d.scales)
        want_d = [len(d.angles), *([names.index(a) for a in d.amplitude] if d.amplitude else [-1, -1]),
                  len(d.measure_names), params.index(d.forcing_frequency) if d.forcing_frequency else -1,
                  params.index(scales["eccentricity"]) if "eccentricity" in scales else -1,
                  params.index(scales["speed"]) if "speed" in scales else -1,
                  len(d.symmetries), len(d.parameter_sets), len(d.steady_states)]
        got_d = lib.array("proof_describe", ctypes.c_long, 10)
        proof.require(got_d == want_d, f"the self-description's macros are {got_d}, the model's {want_d}")
        checks += [("state_units", ctypes.c_char_p, S, list(d.state_units)),
                   ("state_roles", ctypes.c_char_p, S, list(d.roles)),
                   ("param_domains", ctypes.c_char_p, P, [param_domain(q.symbol) for q in ir.parameters])]
        if d.angles:
            checks.append(("angles", ctypes.c_int, len(d.angles), [names.index(a) for a in d.angles]))
        if d.measure_names:
            checks.append(("measure_names", ctypes.c_char_p, len(d.measure_names), list(d.measure_names)))
        ns = len(d.symmetries)
        if ns:
            checks += [("symmetry_names", ctypes.c_char_p, ns, [s["name"] for s in d.symmetries]),
                       ("symmetry_kinds", ctypes.c_char_p, ns, [s["kind"] for s in d.symmetries])]
            for key, width in (("states", S), ("signs", S), ("params", P), ("param_signs", P)):
                checks.append((f"symmetry_{key}", ctypes.c_int, ns * width,
                               [int(v) for s in d.symmetries for v in s[key]]))
        if d.parameter_sets:
            defaults = [q.default for q in ir.parameters]
            vectors = []
            for _, values in d.parameter_sets:
                full = list(defaults)
                for k, v in values:
                    full[params.index(k)] = v
                vectors += full
            checks += [("parameter_set_names", ctypes.c_char_p, len(d.parameter_sets), [n for n, _ in d.parameter_sets]),
                       ("parameter_sets", ctypes.c_double, len(vectors), vectors)]
        if d.steady_states:
            checks += [("steady_state_labels", ctypes.c_char_p, len(d.steady_states), list(d.labels)),
                       ("steady_state_notes", ctypes.c_char_p, len(d.steady_states),
                        [note for _, note, _, _ in d.steady_states])]
    for symbol, ctype, size, want in checks:
        got = lib.array(f"{m}_{symbol}", ctype, size)
        proof.require(got == want, f"{m}_{symbol} is {got}, the model's is {want}")


def _functions(proof, lib: Library, ir) -> None:
    S, P, N = ir.n_states, len(ir.parameters), ir.n_coordinates
    sizes = {"rhs": S, "jac": S * S, "jac_p": S * P, "mass": N * N, "forcing": N}
    for t, y, p in proof.samples():
        for fn in FUNCTIONS:
            proof.compare(f"{ir.name}_{fn}", lib.call(fn, t, y, p, sizes[fn]), proof.expected(fn, t, y, p))
    proof.exchange_bitwise(f"{ir.name}_rhs", lambda t, y, p: lib.call("rhs", t, y, p, S))


def _description(proof, lib: Library, ir) -> None:
    d = ir.description
    if d is None:
        return
    m, S, M = ir.name, ir.n_states, len(d.measure_names)
    measure = lib.fn("measure", ctypes.c_double, (ctypes.c_int, ctypes.c_double, DOUBLE_P, DOUBLE_P))
    if M:
        measures = compile_measures(ir)
        for t, y, p in proof.samples():
            want = measures(t, y, p)
            proof.compare(f"{m}_measures", lib.call("measures", t, y, p, M), want)
            y, p = np.array(y, float), np.array(p, float)
            got = [measure(k, float(t), y.ctypes.data, p.ctypes.data) for k in range(M)]
            proof.compare(f"{m}_measure", got, want)
    t, y, p = proof.samples()[0]
    y, p = np.array(y, float), np.array(p, float)
    for k in (-1, M):
        value = measure(k, float(t), y.ctypes.data, p.ctypes.data)
        proof.require(np.isnan(value), f"{m}_measure({k}) is {value!r} out of range, not NAN")
    steady = lib.fn("steady_state", ctypes.c_int, (ctypes.c_int, DOUBLE_P, DOUBLE_P))
    solvers = compile_steady_states(ir)
    points = list(_parameter_points(ir, 8, 14))
    for p in points:
        p = np.array(p, float)
        for k, label in [(-1, None), *enumerate(d.labels), (len(d.labels), None)]:
            out = Guarded(S, fill=0.0)
            found = steady(k, p.ctypes.data, out.inner.ctypes.data)
            proof.require(out.intact(), f"{m}_steady_state({k}) writes outside its {S} values")
            want = solvers[label](p) if label is not None else None
            if want is None:
                proof.require(found == 0 and bool(np.all(np.isnan(out.inner))),
                              f"{m}_steady_state({k}) gives a state (returns {found}) where there is none")
            else:
                proof.require(found == 1, f"{m}_steady_state({k}) ({label}) returns {found} where the state exists")
                proof.compare(f"{m}_steady_state({k}) ({label})", out.inner, want)


def prove(target, proof) -> None:
    compiler.require("gcc", "c")
    ir = proof.model(target)
    rel_c = proof.file(target, "c/model.c.j2")
    proof.file(target, "c/model.h.j2")
    obj = proof.c_object(rel_c)
    build = proof.build_dir()
    (build / "probe.c").write_text(_probe(ir))
    probe = compiler.compile_object(build / "probe.c", build / "probe.o", f"{ir.name}.h (included alone)",
                                    include=[proof.path(rel_c).parent])
    so = compiler.link([obj, probe], build / f"lib{ir.name}.so", f"the library of {rel_c}", shared=True)
    proof.expected_all()

    def run():
        lib = Library(proof, so, ir)
        _metadata(proof, lib, ir)
        _functions(proof, lib, ir)
        _description(proof, lib, ir)
    proof.isolated(f"the library of {rel_c}", run)
    if proof.form == "loops":
        text = proof.files[rel_c]
        body = text.split(f"void {ir.name}_rhs(", 1)[1].split("\n}\n", 1)[0]
        proof.require(f"for (int i = 0; i < {ir.n_balls}; ++i) {{" in body,
                      f"{ir.name}_rhs is not in the loop form requested")
