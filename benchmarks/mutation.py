"""`adbgen bench mutation`: how many one-line mistakes in code generation are refused before writing (issue 20).

Mutants of the Python of adbgen/codegen (cosmic-ray's operators, applied with its `mutate_code`) and of
every template (templates/**/*.j2, this module's own mutator: operator, index, constant, swapped-argument
and dropped-line mutants) are each applied to a scratch copy of the tree (never the working tree) and
followed by `adbgen regenerate --n 3 --family single-plane --skip-checks` (the rotating model with the
continuum of balanced states, the forced fixed-frame model with its oscillator extension; every target;
the lowering, self-description and every target's proof run), then classified:

- ``refused``: exit 2 with one line ``adbgen: error: <model>: ...`` (a check or a proof);
- ``crashed-as-refusal``: the same one line, naming an exception (a crash turned into the refusal);
- ``crashed``: anything else that wrote nothing (a traceback, a timeout);
- ``equivalent``: written, and every file the same as the unmutated tree's (``byte-identical``), or the
  same but for comments, docstrings and documentation (``comments only``: C/constants comments
  stripped, Python compared by its syntax tree without docstrings, README not compared);
- ``caught``: written and different, and a named test of tests/codegen fails on it (``--tests``);
- ``survived``: written and different, and not caught.

Why cosmic-ray and not mutmut: mutmut 3 runs its mutants only under pytest through trampolines in a
copy it makes itself, while the question here is what `regenerate` does with each mutant; cosmic-ray's
operators and `mutate_code(source, operator, occurrence)` give the mutated source, and this module runs
and classifies it.  The proofs themselves (codegen/passes/proof.py, compiler.py, passes/checks.py, targets/*/prove.py
and the harnesses) are not mutated: a weaker proof writes byte-identical files, which would count as
"equivalent" and say nothing.

`--runtime` (issue 33 item 5): the code that runs generated models instead, the engines' C drivers and
headers (adbgen/analysis/engines/*.c, *.h: a Butcher coefficient of dop853_tableau.h, an error-norm term,
an event bracket of event_measures.h, SUNDIALS' root functions, ...) and the orbit code (the variational
equations, a monodromy column of orbits/shooting.py, the test functions): the named mutants of `RUNTIME`
and, with ``--per-driver N``, N seeded line mutants of each driver and header.  Nothing is regenerated
for these: each is applied alone to the scratch tree and its targeted tests are run there (ENGINE_TESTS,
ORBIT_TESTS), ``caught`` when they fail, ``survived`` when they pass; the results go to the results
file's ``runtime`` key beside the codegen run, which is kept.

`SAMPLE` is the fixed set of 30 representative mutants (every one issue 20 names among them) that
tests/codegen/test_mutation_sample.py requires refused before writing, with one line, in CI.
"""

from __future__ import annotations

import ast
import difflib
import json
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from .registry import Benchmark, option

ROOT = Path(__file__).resolve().parents[1]
PYTHON_SOURCES = ("passes/ball_split.py", "passes/description.py", "emit.py", "ir/model.py", "ir/loops.py",
                  "passes/cse.py", "passes/loop_form.py", "passes/lowering.py", "printers.py",
                  "render.py", "spec.py", "targets/__init__.py", "targets/auto/__init__.py",
                  "targets/auto/dialect.py", "targets/c/__init__.py", "targets/c/dialect.py", "targets/c/printer.py",
                  "targets/cvode/__init__.py", "targets/numba/__init__.py", "targets/numba/dialect.py",
                  "targets/numba/printer.py")
# cosmic-ray's operators used (the rest are variants of these, e.g. every binary operator into every other)
OPERATORS = ("core/ReplaceBinaryOperator_Add_Sub", "core/ReplaceBinaryOperator_Sub_Add",
             "core/ReplaceBinaryOperator_Mul_Div", "core/ReplaceBinaryOperator_Div_Mul",
             "core/ReplaceBinaryOperator_Mul_Add", "core/ReplaceComparisonOperator_Lt_LtE",
             "core/ReplaceComparisonOperator_Eq_NotEq", "core/ReplaceComparisonOperator_NotEq_Eq",
             "core/ReplaceComparisonOperator_Gt_GtE", "core/NumberReplacer", "core/AddNot",
             "core/ReplaceTrueWithFalse", "core/ReplaceFalseWithTrue", "core/ReplaceAndWithOr",
             "core/ReplaceOrWithAnd", "core/ZeroIterationForLoop", "core/ReplaceContinueWithBreak",
             "core/ReplaceUnaryOperator_USub_UAdd", "core/RemoveDecorator")
REGENERATE = ("regenerate", "--n", "3", "--family", "single-plane", "--skip-checks", "--quiet")
# a mutant the loop form writes is run again in the unrolled form (the "both forms")
UNROLLED = REGENERATE + ("--form", "unrolled")
TIMEOUT = 900  # s per regenerate
PYTHON_TESTS = "tests/codegen/test_cross_target.py tests/codegen/test_c_target.py tests/codegen/test_numba_target.py"
TESTS = {  # the named tests a written mutant of a file is put through (--tests); Python: PYTHON_TESTS
    "templates/c": "tests/codegen/test_c_target.py", "templates/cvode": "tests/codegen/test_cvode.py",
    "templates/auto": "tests/codegen/test_auto.py", "templates/numba": "tests/codegen/test_numba_target.py",
}


@dataclass(frozen=True)
class Mutant:
    """A one-line change of one file: `old` (exactly once in it) replaced by `new`."""

    id: str
    file: str  # relative to the repository root
    old: str
    new: str
    kind: str  # the operator (cosmic-ray's name, or the template mutator's)
    # the regenerate run that shows it (the sample: small models, only the targets needed)
    args: tuple[str, ...] = REGENERATE
    # a mutant of the code that runs generated models (RUNTIME): the pytest arguments of its targeted tests
    tests: tuple[str, ...] = ()

    def apply(self, text: str) -> str:
        if text.count(self.old) != 1:
            raise ValueError(f"{self.id}: {self.old!r} occurs {text.count(self.old)} times in {self.file}")
        return text.replace(self.old, self.new)


def _sample(id, file, old, new, n="2", targets=(), form="loops"):
    args = ("regenerate", "--n", n, "--family", "single-plane", "--skip-checks", "--quiet", "--form", form)
    return Mutant(id, file, old, new, "sample", args + (("--targets", *targets) if targets else ()))


T, C = "templates", "adbgen/codegen"
# The CI sample (issue 20 "What must be shown"): the first fourteen are the mutants the issue names.
SAMPLE: tuple[Mutant, ...] = (
    _sample("c-jacobian-transposed", f"{C}/targets/c/dialect.py", '            return f"{self.out}[{row}]"\n        if row',
            '            return f"{self.out}[{row}]"\n        row, col = col, row\n        if row', targets=("c",)),
    _sample("c-jac_p-row-stride", f"{C}/targets/c/__init__.py", "else \"out\", columns(kernel))",
            "else \"out\", kernel.shape[0])", targets=("c",)),
    _sample("cvode-nonfinite-skips-one", f"{T}/cvode/adaptor.c.j2", "for (i = 0; i < {{ P }}_N_STATES; ++i) {\n        if",
            "for (i = 1; i < {{ P }}_N_STATES; ++i) {\n        if", targets=("cvode",)),
    _sample("cvode-nonfinite-reads-past-end", f"{T}/cvode/adaptor.c.j2",
            "for (i = 0; i < {{ P }}_N_STATES; ++i) {\n        if", "for (i = 0; i <= {{ P }}_N_STATES; ++i) {\n        if",
            targets=("cvode",)),
    _sample("cvode-sunmatrix-transposed", f"{T}/cvode/adaptor.c.j2", "SM_ELEMENT_D(J, i, j) = v;",
            "SM_ELEMENT_D(J, j, i) = v;", targets=("cvode",)),
    _sample("cvode-jacobian-dropped", f"{T}/cvode/driver.c.j2", "CVodeSetJacFn(mem, {{ ir.name }}_cvode_jac)",
            "CVodeSetJacFn(mem, NULL)", targets=("cvode",)),
    _sample("auto-continuum-term-mul-div", f"{T}/auto/_family.j2",
            "f[{{ ia }}] -= FAMILY_SIGMA * sin(u[{{ ib }}] - u[{{ j }}]) / s12 * h;",
            "f[{{ ia }}] -= FAMILY_SIGMA / sin(u[{{ ib }}] - u[{{ j }}]) * s12 * h;", n="3", targets=("auto",)),
    _sample("auto-amplitude-icp-off-by-one", f"{T}/auto/constants.j2", "ICP = [{{ apar(icp0) | int + 1 }}, {{ amp + 1 }}]",
            "ICP = [{{ apar(icp0) | int + 1 }}, {{ amp + 2 }}]", targets=("auto",)),
    _sample("auto-iplt-changed", f"{C}/targets/auto/__init__.py", "\nIPLT = 0\n", "\nIPLT = 1\n", targets=("auto",)),
    _sample("auto-stpnt-copies-nothing", f"{T}/auto/user.c.j2",
            "memcpy(u, start, sizeof(doublereal) * (size_t)(ndim < NSTATES ? ndim : NSTATES));",
            "memcpy(u, start, sizeof(doublereal) * (size_t)0);", targets=("auto",)),
    _sample("numba-params-returns-defaults", f"{T}/numba/module.py.j2", "    p = DEFAULTS.copy()\n", "    p = DEFAULTS\n",
            targets=("numba",)),
    _sample("numba-jac-wrapper-out-T", f"{T}/numba/module.py.j2", "    {{ fname }}_inplace(t, y, p, out)\n",
            "    {{ fname }}_inplace(t, y, p, out.T)\n", targets=("numba",)),
    _sample("ball-split-falls-back", f"{C}/passes/ball_split.py", "if sp.expand(g.xreplace(from_ball(i)) - per_ball[i]) != 0:",
            "if sp.expand(g.xreplace(from_ball(i)) - per_ball[i]) == 0:", targets=("numba",)),
    _sample("ball-invariant-order-broken", f"{C}/printers.py", 'out = self._cls.get(expr) or "s:" + _INDEX.sub("#", expr.name)',
            'out = self._cls.get(expr) or "s:" + expr.name', targets=("c",), form="unrolled"),
    # more of every target
    _sample("c-defaults-doubled", f"{T}/c/model.c.j2", "{% for p in ir.parameters %}    {{ p.default | cfloat }},",
            "{% for p in ir.parameters %}    {{ (2 * p.default) | cfloat }},", targets=("c",)),
    _sample("c-header-n-coordinates", f"{T}/c/model.h.j2", "_N_COORDINATES {{ ir.n_coordinates }}",
            "_N_COORDINATES {{ ir.n_coordinates + 1 }}", targets=("c",)),
    _sample("c-steady-state-nan-short", f"{T}/c/model.c.j2", "for (int i = 0; i < {{ P }}_N_STATES; ++i) {\n            y[i] = NAN;",
            "for (int i = 0; i < {{ P }}_N_STATES - 1; ++i) {\n            y[i] = NAN;", targets=("c",)),
    _sample("c-measure-out-of-range", f"{T}/c/model.c.j2", "    default:\n        return NAN;", "    default:\n        return 0.0;",
            targets=("c",)),
    _sample("c-zero-one-short", f"{C}/targets/c/dialect.py", 'memset({self.out}, 0, sizeof({self.ctype}) * {size});',
            'memset({self.out}, 0, sizeof({self.ctype}) * {size - 1});', targets=("c",)),
    _sample("cvode-driver-start-ignored", f"{T}/cvode/driver.c.j2", "y0[i] = {{ ir.name }}_start[i];", "y0[i] = 0.0;",
            targets=("cvode",)),
    _sample("cvode-driver-parameters-shifted", f"{T}/cvode/driver.c.j2", "parse_number(argv[sep + 1 + i]",
            "parse_number(argv[sep + i]", targets=("cvode",)),
    _sample("cvode-driver-bad-input-status", f"{T}/cvode/driver.c.j2", "    exit(2);", "    exit(1);", targets=("cvode",)),
    _sample("cvode-adaptor-time-dropped", f"{T}/cvode/adaptor.c.j2", "{{ ir.name }}_rhs(t, yv, p, dv);",
            "{{ ir.name }}_rhs(0.0, yv, p, dv);", targets=("cvode",)),
    _sample("auto-ijac-1-returns-late", f"{T}/auto/user.c.j2", "    if (ijac == 1) {", "    if (ijac == 2) {", targets=("auto",)),
    _sample("auto-pvls-wrong-state", f"{T}/auto/user.c.j2", "u[{{ rotor[1] }}] * u[{{ rotor[1] }}]",
            "u[{{ rotor[0] }}] * u[{{ rotor[1] }}]", targets=("auto",)),
    _sample("auto-period-cell", f"{T}/auto/user.c.j2", "    par[10] = 6.283185307179586 / par[", "    par[11] = 6.283185307179586 / par[",
            targets=("auto",)),
    _sample("auto-ndim-short", f"{T}/auto/constants.j2", "NDIM = {{ ir.n_states }}, IPS = 1", "NDIM = {{ ir.n_states - 1 }}, IPS = 1",
            targets=("auto",)),
    _sample("auto-stage2-restart-label", f"{T}/auto/_forced.j2", "IPS = 2, IRS = {{ stage1_end }}, ILP = 1",
            "IPS = 2, IRS = {{ stage1_end + 1 }}, ILP = 1", targets=("auto",)),
    _sample("numba-steady-state-always", f"{T}/numba/module.py.j2", "    return out if steady_state_inplace(k, np.asarray(p, dtype=np.float64), out) else None",
            "    steady_state_inplace(k, np.asarray(p, dtype=np.float64), out)\n    return out", targets=("numba",)),
    _sample("numba-defaults-reversed", f"{T}/numba/module.py.j2", "DEFAULTS = np.array({{ defaults | pylist }})",
            "DEFAULTS = np.array({{ defaults | pylist }}[::-1])", targets=("numba",)),
)


# The engines' C drivers and the orbit code (issue 33 item 5): nothing is regenerated for these; each mutant
# is applied alone and the targeted tests of what it breaks are run (pytest arguments), `caught` when they fail.
ENGINE_TESTS = ("tests/analysis/test_event_measures.py", "tests/analysis/test_fixed_libm.py",
                "tests/analysis/test_c_interface.py", "tests/analysis/test_rk_engines.py",
                "tests/analysis/test_decay_time.py", "tests/analysis/test_matlab_ode45.py")
ORBIT_TESTS = ("tests/analysis/test_orbits.py", "-k", "not auto and not command and not continue")
E, O = "adbgen/analysis/engines", "adbgen/analysis/orbits"
# the drivers and headers whose users have tests of their own beyond ENGINE_TESTS
DRIVER_TESTS = {"variational_driver.c": ORBIT_TESTS,
                "hybrid_driver.c": ENGINE_TESTS + ("tests/analysis/test_hybrid_engine.py",),
                "taylor_driver.c": ENGINE_TESTS + ("tests/analysis/test_taylor_engine.py",),
                # ENGINE_NAMES runs one method of the driver (cvode-adams); BDF (method 10: the dense linear
                # solver, the analytic Jacobian, CVodeFree) is run by the registry suite's case
                "sundials_driver.c": ENGINE_TESTS + (
                    "tests/analysis/test_engine_registry.py::test_registered_engine[reaches_the_reference[cvode-bdf]]",),
                "symmetrize.h": ENGINE_TESTS + ("tests/families/two_plane/science/test_symmetric_integration.py",)}


def _runtime(id, file, old, new, tests=ENGINE_TESTS):
    return Mutant(id, file, old, new, "runtime", (), tests)


RUNTIME: tuple[Mutant, ...] = (
    # DOP853 (rk_dop853.h over dop853_tableau.h: rk-dop853, its batch and the hybrid engine)
    _runtime("dop853-a21-last-digit", f"{E}/dop853_tableau.h", "0.0591751709536137", "0.0591751709536138"),
    _runtime("dop853-b1-rounded", f"{E}/dop853_tableau.h", "static const double dop_b[DOP_STAGES] = {0.054293734116568765",
             "static const double dop_b[DOP_STAGES] = {0.0542937341165688"),
    _runtime("dop853-e3-9-sign", f"{E}/dop853_tableau.h", "-0.4226823213237919", "0.4226823213237919"),
    _runtime("dop853-norm-e3-weight", f"{E}/rk_dop853.h", "0.01 * e3", "0.1 * e3"),
    _runtime("dop853-error-scale-old-state-only", f"{E}/rk_dop853.h", "RK_MAX(RK_ABS(y[i]), RK_ABS(ynew[i])) * rtol",
             "RK_ABS(y[i]) * rtol"),
    _runtime("dop853-safety-factor", f"{E}/rk_dop853.h", "#define DOP_SAFETY 0.9", "#define DOP_SAFETY 0.8"),
    _runtime("dop853-dense-F2-sign", f"{E}/rk_dop853.h", "h * (K[DOP_STAGES][i] + K[0][i])", "h * (K[DOP_STAGES][i] - K[0][i])"),
    # the event measures (event_measures.h: every engine's report; its search on a step's interpolant: cyrk-*, rk-dop853)
    _runtime("dense-bisect-bracket-swapped", f"{E}/event_measures.h", "if (dense_r2(h, m, ix, iy) >= H2) a = m;\n        else b = m;",
             "if (dense_r2(h, m, ix, iy) >= H2) b = m;\n        else a = m;"),
    _runtime("dense-golden-section-minimises", f"{E}/event_measures.h", "if (fc > fd) {", "if (fc < fd) {"),
    _runtime("dense-screen-margin-dropped", f"{E}/event_measures.h", "if (p >= 0.5 * H2) return 1;", "if (p >= H2) return 1;"),
    _runtime("dense-last-above-strict", f"{E}/event_measures.h", "if (v >= H2) *last = k;", "if (v > 1.01 * H2) *last = k;"),
    # SUNDIALS' root functions, the ode45 emulation's error and output, Taylor's in-step screen
    _runtime("sundials-threshold-root-squared-once", f"{E}/sundials_driver.c",
             "- d->threshold * d->threshold;", "- d->threshold;"),
    _runtime("sundials-extremum-counted-as-crossing", f"{E}/sundials_driver.c",
             "if (found[0]) adb_events_crossing(&ev, t);", "if (found[1]) adb_events_crossing(&ev, t);"),
    _runtime("ode45-error-scale-new-state-dropped", f"{E}/ode45_driver.c",
             "fabs(fe / fmax(fmax(fabs(y[i]), fabs(ynew[i])), threshold_w))", "fabs(fe / fmax(fabs(y[i]), threshold_w))"),
    _runtime("events-point-above-strict", f"{E}/event_measures.h", "if (r2 >= ev->H2) ev->t_above = t;",
             "if (r2 > 1.01 * ev->H2) ev->t_above = t;"),
    _runtime("events-report-unsettled-ignored", f"{E}/event_measures.h", "r->t_dec = r2_end >= ev->H2 ? NAN",
             "r->t_dec = r2_end >= 4.0 * ev->H2 ? NAN"),
    _runtime("taylor-in-step-screen-skipped", f"{E}/taylor_driver.c", "if (end2 < H2 && bound >= H2) {",
             "if (end2 < H2 && bound >= 4 * H2) {"),
    # the variational equations (variational_driver.c) and the shooting system (orbits/)
    _runtime("variational-phi-starts-off-identity", f"{E}/variational_driver.c", "z[ADB_NY + i * ADB_NY + i] = 1.0;",
             "z[ADB_NY + i * ADB_NY] = 1.0;", ORBIT_TESTS),
    _runtime("variational-J-Phi-column", f"{E}/variational_driver.c", "row[j] += c * src[j];", "row[j] += c * src[k];",
             ORBIT_TESTS),
    _runtime("variational-fp-transposed", f"{E}/variational_driver.c", "s += Fp[i * ADB_NP + k] * a->dp[k];",
             "s += Fp[k * ADB_NY + i] * a->dp[k];", ORBIT_TESTS),
    _runtime("monodromy-product-order", f"{O}/shooting.py", "M = P @ M", "M = M @ P", ORBIT_TESTS),
    _runtime("monodromy-arc-block-transposed", f"{O}/shooting.py", "A[r, i * N:(i + 1) * N] = Phi[i]",
             "A[r, i * N:(i + 1) * N] = Phi[i].T", ORBIT_TESTS),
    _runtime("shooting-period-column-unscaled", f"{O}/shooting.py", "A[: m * N, -1] = (fe / m).ravel()",
             "A[: m * N, -1] = fe.ravel()", ORBIT_TESTS),
    _runtime("shooting-winding-shift-sign", f"{O}/shooting.py", "nxt[-1] = X[0] + self.shift", "nxt[-1] = X[0] - self.shift",
             ORBIT_TESTS),
    _runtime("flip-test-at-plus-one", f"{O}/period_doubling.py", "return float(z.real + 1.0)", "return float(z.real - 1.0)",
             ORBIT_TESTS),
    _runtime("torus-test-conjugate-product", f"{O}/cycle.py", "prod = mu[i] * mu[j]", "prod = mu[i] * np.conj(mu[j])",
             ORBIT_TESTS),
    _runtime("multipliers-sorted-ascending", f"{O}/orbit.py", "return mu[np.lexsort((-mu.imag, -np.abs(mu)))]",
             "return mu[np.lexsort((-mu.imag, np.abs(mu)))]", ORBIT_TESTS),
)


# ------------------------------------------------------------------------------------------ mutants


def python_mutants(root: Path, per_file: int, seed: int) -> list[Mutant]:
    """Up to `per_file` cosmic-ray mutants of each of PYTHON_SOURCES (a seeded sample of every position of
    every operator of OPERATORS), each as the one changed line."""
    import cosmic_ray.plugins
    from cosmic_ray.ast import ast_nodes, get_ast
    from cosmic_ray.mutating import mutate_code

    rng = random.Random(seed)
    out = []
    for rel in PYTHON_SOURCES:
        path = root / "adbgen" / "codegen" / rel
        source = path.read_text()
        tree = get_ast(source)
        candidates = []
        for name in OPERATORS:
            operator = cosmic_ray.plugins.get_operator(name)()
            count = sum(1 for node in ast_nodes(tree) for _ in operator.mutation_positions(node))
            candidates += [(name, k) for k in range(count)]
        rng.shuffle(candidates)
        taken = 0
        for name, k in candidates:
            if taken >= per_file:
                break
            mutated = mutate_code(source, cosmic_ray.plugins.get_operator(name)(), k)
            if mutated is None or mutated == source:
                continue
            change = _one_change(source, mutated)
            if change is None:
                continue
            old, new = change
            out.append(Mutant(f"py:{rel}:{name.split('/')[-1]}:{k}", f"adbgen/codegen/{rel}", old, new, name))
            taken += 1
    return out


def _one_change(a: str, b: str) -> tuple[str, str] | None:
    """(old, new): the smallest run of whole lines that differs, made unique in `a` by context lines."""
    la, lb = a.splitlines(keepends=True), b.splitlines(keepends=True)
    sm = difflib.SequenceMatcher(a=la, b=lb, autojunk=False)
    ops = [op for op in sm.get_opcodes() if op[0] != "equal"]
    if len(ops) != 1:
        return None
    _, i1, i2, j1, j2 = ops[0]
    for pad in range(0, 6):
        lo, hi = max(0, i1 - pad), min(len(la), i2 + pad)
        old = "".join(la[lo:hi])
        if old and a.count(old) == 1:
            new = "".join(la[lo:i1] + lb[j1:j2] + la[i2:hi])
            return old, new
    return None


_SWAPS = ((" + ", " - "), (" - ", " + "), (" * ", " / "), (" / ", " * "), (" < ", " <= "), (" <= ", " < "),
          (" >= ", " > "), (" == ", " != "), (" != ", " == "), (" and ", " or "), (" && ", " || "))
_COMMENT = re.compile(r"^\s*(/\*|\*|#|\{#|//)")


def _line_mutants(line: str):
    """(kind, new line) for one template line."""
    for a, b in _SWAPS:
        if a in line:
            yield "operator", line.replace(a, b, 1)
    for m in re.finditer(r"\[(\d+|[a-z])\]", line):
        yield "index", line[: m.start()] + f"[{m.group(1)} + 1]" + line[m.end():]
    for m in re.finditer(r"(?<![\w.])(\d+\.\d+|\d+)(?![\w.])", line):
        value = m.group(1)
        repl = str(float(value) * 2 if "." in value else int(value) + 1)
        yield "constant", line[: m.start()] + repl + line[m.end():]
    for m in re.finditer(r"\w\(([^(),]+), ([^(),]+)([,)])", line):
        a, b = m.group(1), m.group(2)
        if a != b:
            yield "swapped-argument", line[: m.start(1)] + b + ", " + a + line[m.end(2):]
    if line.strip():
        yield "dropped-line", ""


def template_mutants(root: Path, per_file: int, seed: int) -> list[Mutant]:
    """Up to `per_file` mutants of each template (a seeded sample over its lines and the five kinds;
    comment lines are left alone: dropping one changes nothing that runs)."""
    rng = random.Random(seed)
    out = []
    for path in sorted((root / "templates").rglob("*.j2")):
        rel = path.relative_to(root).as_posix()
        out += [Mutant(f"tpl:{rel[len('templates/'):]}:{m.id}", rel, m.old, m.new, m.kind)
                for m in _sampled_lines(path, rel, per_file, rng)]
    return out


def _sampled_lines(path: Path, rel: str, per_file: int, rng: random.Random) -> list[Mutant]:
    """Up to `per_file` distinct line mutants of one file drawn with `rng` (ids "LINE:KIND")."""
    text = path.read_text()
    lines = text.splitlines(keepends=True)
    candidates = []
    for k, line in enumerate(lines):
        if _COMMENT.match(line):
            continue
        for kind, new in _line_mutants(line.rstrip("\n")):
            new_line = new + "\n" if new or not line.endswith("\n") else ""
            candidates.append((k, kind, new_line if kind != "dropped-line" else ""))
    rng.shuffle(candidates)
    seen, out = set(), []
    for k, kind, new_line in candidates:
        if len(seen) >= per_file:
            break
        mutated = "".join(lines[:k] + [new_line] + lines[k + 1:])
        change = _one_change(text, mutated) if mutated != text else None
        if change is None or change in seen:
            continue
        seen.add(change)
        out.append(Mutant(f"{k + 1}:{kind}", rel, change[0], change[1], kind))
    return out


def driver_mutants(root: Path, per_file: int, seed: int) -> list[Mutant]:
    """Up to `per_file` line mutants (the templates' mutator: operator, index, constant, swapped-argument,
    dropped-line) of each C driver and header of the engines, a seeded sample, each through ENGINE_TESTS
    and the tests of its own users (DRIVER_TESTS; variational_driver.c: ORBIT_TESTS, the orbit code is
    its one user)."""
    rng = random.Random(seed)
    out = []
    for path in sorted((root / E).glob("*.[ch]")):
        rel = path.relative_to(root).as_posix()
        tests = DRIVER_TESTS.get(path.name, ENGINE_TESTS)
        out += [Mutant(f"c:{path.name}:{m.id}", rel, m.old, m.new, m.kind, (), tests)
                for m in _sampled_lines(path, rel, per_file, rng)]
    return out


# ------------------------------------------------------------------------------------------ running


class Scratch:
    """A copy of the tree (adbgen/, templates/, tests/, generated/, pyproject.toml) in a temporary folder;
    mutants are applied there and undone after each run."""

    def __init__(self, root: Path = ROOT, folder: Path | None = None):
        self.tmp = None
        if folder is None:
            self.tmp = tempfile.TemporaryDirectory(prefix="adbgen-mutation-")
            folder = Path(self.tmp.name)
        self.root = folder
        ignore = shutil.ignore_patterns("__pycache__", "*.pyc", ".pytest_cache")
        for name in ("adbgen", "templates", "tests", "generated"):
            if (root / name).is_dir() and not (folder / name).exists():
                shutil.copytree(root / name, folder / name, ignore=ignore)
        for name in ("pyproject.toml", "setup.py"):
            if (root / name).is_file():
                shutil.copy2(root / name, folder / name)
        self.cache = folder / ".cache"

    def close(self):
        if self.tmp is not None:
            self.tmp.cleanup()

    def env(self) -> dict:
        return {**os.environ, "PYTHONPATH": str(self.root), "ADBGEN_CACHE": str(self.cache),
                "NUMBA_CACHE_DIR": str(self.root / ".numba"), "PYTHONDONTWRITEBYTECODE": "1"}

    def regenerate(self, args, out: Path, timeout: int = TIMEOUT) -> subprocess.CompletedProcess:
        shutil.rmtree(out, ignore_errors=True)
        try:
            return subprocess.run([sys.executable, "-m", "adbgen.cli", *args, "--out", str(out)], cwd=self.root,
                                  env=self.env(), capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return subprocess.CompletedProcess(args, -9, "", f"timeout after {timeout} s")

    def applied(self, mutant: Mutant):
        scratch = self

        class _Applied:
            def __enter__(self):
                self.path = scratch.root / mutant.file
                self.text = self.path.read_text()
                self.path.write_text(mutant.apply(self.text))

            def __exit__(self, *exc):
                self.path.write_text(self.text)
        return _Applied()


_SOURCE_HASH = re.compile(r"(SOURCE_HASH\W{1,5})[0-9a-f]{16}\b")


def files_of(out: Path) -> dict[str, str]:
    return {p.relative_to(out).as_posix(): p.read_text(errors="replace") for p in sorted(out.rglob("*")) if p.is_file()}


def blank_hashes(files: dict[str, str]) -> dict[str, str]:
    """The files with each model's SOURCE_HASH blanked: it hashes the templates, so every template mutant
    changes it by design (a Python mutant's outputs are compared with their hashes: render.py computes them)."""
    return {rel: _SOURCE_HASH.sub(r"\1<hash>", text) for rel, text in files.items()}


def _strip_c(text: str) -> str:
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    return " ".join(text.split())


def _python_code(text: str) -> str:
    tree = ast.parse(text)
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if isinstance(body, list) and body and isinstance(body[0], ast.Expr) and isinstance(
                getattr(body[0], "value", None), ast.Constant) and isinstance(body[0].value.value, str):
            body.pop(0)
    return ast.dump(tree)


def same_but_comments(a: dict[str, str], b: dict[str, str]) -> bool:
    if set(a) != set(b):
        return False
    for rel in a:
        if a[rel] == b[rel] or rel.endswith(".md"):
            continue
        try:
            if rel.endswith(".py"):
                same = _python_code(a[rel]) == _python_code(b[rel])
            elif rel.endswith((".c", ".h")):
                same = _strip_c(a[rel]) == _strip_c(b[rel])
            else:  # AUTO constants: '#' comments
                same = [ln.split("#")[0].strip() for ln in a[rel].splitlines()] == \
                       [ln.split("#")[0].strip() for ln in b[rel].splitlines()]
        except SyntaxError:
            return False
        if not same:
            return False
    return True


_EXCEPTION = re.compile(r": (?:[A-Z]\w*(?:Error|Exception)|KeyError|StopIteration|RecursionError|NotImplementedError)\b")


def _outcome(scratch: Scratch, args, baseline: dict[str, str], template: bool = False) -> dict:
    """One regenerate run of the applied mutant, classified (without the tests); `template`: a template
    mutant, whose outputs are compared with the SOURCE_HASH blanked."""
    out = scratch.root / ".out"
    r = scratch.regenerate(args, out)
    lines = r.stderr.strip().splitlines()
    written = files_of(out) if out.is_dir() else {}
    if template:
        written, baseline = blank_hashes(written), blank_hashes(baseline)
    if r.returncode == 0:
        if written == baseline:
            return {"status": "equivalent", "reason": "byte-identical output"}
        if same_but_comments(written, baseline):
            return {"status": "equivalent", "reason": "the output differs in comments, docstrings or README only"}
        return {"status": "survived", "changed": sorted(k for k in set(written) | set(baseline)
                                                        if written.get(k) != baseline.get(k))}
    if written:
        return {"status": "crashed", "message": "wrote files and failed: " + (lines[-1] if lines else "")}
    if r.returncode == 2 and len(lines) == 1 and lines[0].startswith("adbgen: error: "):
        return {"status": "crashed-as-refusal" if _EXCEPTION.search(lines[0]) else "refused", "message": lines[0]}
    return {"status": "crashed", "message": (lines[-1] if lines else f"exit {r.returncode}")[:300]}


# Written mutants read and judged equivalent (same values for every input; the reason says why).
REVIEWED_EQUIVALENTS = {
    "py:emit.py:ReplaceAndWithOr:0": "parenthesises every atom of the C text, (x) instead of x: the same "
                                     "expression trees, the same values",
    "py:passes/lowering.py:NumberReplacer:27": "writes the oscillator extension's zero Jacobian entries explicitly (`!= 0` "
                                        "-> `!= -1`): every jac kernel sets all its entries (the numba one writes "
                                        "each, the C ones memset first), so the same values",
    "tpl:auto/user.c.j2:105:operator": "stpnt's copy length `ndim < NSTATES ? ndim : NSTATES` -> `<=`: the two differ "
                                       "only where ndim == NSTATES, and there both give NSTATES",
    "tpl:auto/constants_stage2.j2:5:constant": "forced_constants(2) -> (3) in the stage-2 file: the macro tests "
                                               "`stage == 1` only, so every constant takes the same (restart) branch; "
                                               "the one difference is the comment line 'stage 3 of 2'",
}


def classify(scratch: Scratch, mutant: Mutant, baselines: dict, run_tests: bool) -> dict:
    """The mutant's class: its loop-form run, and where that writes, its unrolled-form run too (refused
    in either form is refused; equivalent only if both are)."""
    start = time.perf_counter()
    result = {"id": mutant.id, "file": mutant.file, "kind": mutant.kind, "old": mutant.old, "new": mutant.new}
    with scratch.applied(mutant):
        template = mutant.file.startswith("templates/")
        first = _outcome(scratch, mutant.args, baselines[mutant.args], template)
        outcome = dict(first, form="loops")
        if first["status"] in ("equivalent", "survived") and mutant.args == REGENERATE:
            second = _outcome(scratch, UNROLLED, baselines[UNROLLED], template)
            if second["status"] != "equivalent":
                outcome = dict(second, form="unrolled") if second["status"] != "survived" or first["status"] != "survived" \
                    else dict(first, form="both")
        result.update(outcome)
        if result["status"] == "survived" and mutant.id in REVIEWED_EQUIVALENTS:
            result.update(status="equivalent", reason="reviewed: " + REVIEWED_EQUIVALENTS[mutant.id])
        if result["status"] == "survived" and run_tests:
            test = _named_test(mutant)
            if test is not None:
                caught, name = _run_test(scratch, test)
                if caught:
                    result.update(status="caught", test=name)
    result["seconds"] = round(time.perf_counter() - start, 1)
    return result


def _named_test(mutant: Mutant) -> str:
    for prefix, test in TESTS.items():
        if mutant.file.startswith(prefix):
            return test
    return PYTHON_TESTS


def _run_test(scratch: Scratch, test: str) -> tuple[bool, str]:
    """The scratch generated/ regenerated with the mutant applied (the default set: what the tests read),
    then the named tests run there; (failed, the first failing test)."""
    generated = scratch.root / "generated"
    try:
        r = subprocess.run([sys.executable, "-m", "adbgen.cli", "regenerate", "--skip-checks", "--quiet"],
                           cwd=scratch.root, env=scratch.env(), capture_output=True, text=True, timeout=2 * TIMEOUT)
        if r.returncode != 0:
            return True, "adbgen regenerate (the default set refuses it): " + r.stderr.strip()[-200:]
        r = subprocess.run([sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", *test.split()],
                           cwd=scratch.root, env={**scratch.env(), "CI": "true"}, capture_output=True, text=True,
                           timeout=4 * TIMEOUT)
        failed = re.findall(r"^FAILED (\S+)", r.stdout, re.M)
        return r.returncode not in (0, 5), failed[0] if failed else test
    finally:
        shutil.rmtree(generated)
        shutil.copytree(ROOT / "generated", generated, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))


# Runtime mutants that survive their tests and were read and judged equivalent (the reason says why).
REVIEWED_RUNTIME_EQUIVALENTS = {
    "c:hybrid_driver.c:93:operator": "locate()'s stop test `m <= a` -> `m < a`: at adjacent doubles the midpoint "
                                     "rounds to a, g(a) >= 0 keeps `a = m` a no-op, and the same b is returned after "
                                     "the 200 iterations (only the early exit is lost)",
    "c:lanes.h:95:swapped-argument": "adb_lanes_max's fmax(a, c) -> fmax(c, a): fmax is symmetric but for the sign "
                                     "of a zero result, and its one user takes the max of two fabs (never -0)",
    "c:variational_driver.c:121:operator": "arc()'s last row `ry + (m - 1) * n` -> `ry + (m - 1) / n`: the arc is solved "
                                           "with t_eval = {t1}, and CyRK stores only the t_eval points (not the start: "
                                           "cysolver.cpp), so m = 1 on success and both are ry; m = 0 (failure) is "
                                           "refused by `m < 1` before `end` is read.  Checked: `abort()` when "
                                           "success and m != 1 passes ORBIT_TESTS, when m == 1 aborts",
    "c:cyrk_driver.c:149:operator": "the no-store path's (keep = 0, measures = 0) Y[0] <- row n - 3 read from "
                                    "`ry - (n - 3) * ADB_NY`: Y[0]'s state is never read afterwards (the next segment, "
                                    "the target test and y_end read Y[K - 1], K = 3; h and t_last read T) unless the "
                                    "scan finds a nonfinite row before the last two: CyRK accepts a step only at error "
                                    "norm < 1 (never NaN), so that needs a state overflowing past 1.8e308 and two more "
                                    "steps accepted after it, which a state feeding the right-hand side (sin, cos of "
                                    "inf: NaN) refuses.  The read itself is out of the solution's buffer (undefined "
                                    "behaviour), which no test sees short of a sanitizer",
}


def classify_runtime(scratch: Scratch, mutant: Mutant) -> dict:
    """A mutant of the engines or the orbit code: applied alone in the scratch tree, its targeted tests run
    there (CI=true: a missing tool fails); ``caught`` when they fail (or do not collect, or their process
    dies of a signal: a driver's segmentation fault fails the suite as a failing test does), ``survived`` when
    they pass (``equivalent`` when REVIEWED_RUNTIME_EQUIVALENTS says why), ``crashed`` on a timeout.  (The compiled engines are rebuilt by their sources' digest.)"""
    start = time.perf_counter()
    result = {"id": mutant.id, "file": mutant.file, "kind": mutant.kind, "old": mutant.old, "new": mutant.new,
              "tested": " ".join(mutant.tests)}
    with scratch.applied(mutant):
        result.update(_runtime_outcome(scratch, mutant.tests))
    if result["status"] == "survived" and mutant.id in REVIEWED_RUNTIME_EQUIVALENTS:
        result.update(status="equivalent", reason="reviewed: " + REVIEWED_RUNTIME_EQUIVALENTS[mutant.id])
    result["seconds"] = round(time.perf_counter() - start, 1)
    return result


def _runtime_outcome(scratch: Scratch, tests: tuple[str, ...]) -> dict:
    try:
        r = subprocess.run([sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", *tests],
                           cwd=scratch.root, env={**scratch.env(), "CI": "true"}, capture_output=True, text=True,
                           timeout=2 * TIMEOUT)
    except subprocess.TimeoutExpired:
        return {"status": "crashed", "message": f"timeout after {2 * TIMEOUT} s"}
    if r.returncode == 0:
        return {"status": "survived"}
    if r.returncode in (1, 2):  # tests failed, or the mutated module did not import (a collection error)
        failed = re.findall(r"^(?:FAILED|ERROR) (\S+)", r.stdout, re.M)
        return {"status": "caught", "test": failed[0] if failed else " ".join(tests)}
    if r.returncode < 0:  # killed by a signal (a segmentation fault in a driver): pytest's faulthandler names the test
        frames = re.findall(r'File "[^"]*?/(tests/[^"]+\.py)", line \d+ in (test_\w+)', r.stdout + r.stderr)
        died = f"{frames[0][0]}::{frames[0][1]}" if frames else " ".join(tests)
        return {"status": "caught", "test": f"{died} (the test process died of {signal.Signals(-r.returncode).name})"}
    return {"status": "crashed", "message": (r.stdout + r.stderr).strip()[-300:]}


def run_runtime(args, out) -> int:
    """The RUNTIME mutants (and --per-driver sampled ones) through their targeted tests; the results go to
    the results file's ``runtime`` key (its codegen run is kept as it is)."""
    from .report import load_average, machine, utc_now, write

    started = time.time()
    scratch = Scratch()
    path = Path(out)
    data = json.loads(path.read_text()) if path.is_file() else {"benchmark": "mutation"}
    mutants = list(RUNTIME) + (driver_mutants(scratch.root, args.per_driver, args.seed) if args.per_driver else [])
    # --resume: the earlier run's results kept but for its survivors and crashes (run again: a test may
    # have been added since), and its commands listed
    earlier = data.get("runtime", {}) if args.resume else {}
    results: list[dict] = [r for r in earlier.get("results", []) if r["status"] not in ("survived", "crashed")]
    done = {r["id"] for r in results}
    commands = earlier.get("commands", [earlier["command"]] if "command" in earlier else [])
    commands.append(" ".join(["adbgen", "bench", "mutation", *sys.argv[3:]]))
    started -= earlier.get("seconds", 0) if results else 0

    def section() -> dict:
        return {"date": utc_now(), "machine": machine(), "load_average": load_average(),
                "seconds": round(time.time() - started), "complete": len(results) == len(mutants),
                "planned": len(mutants), "command": commands[-1], "commands": commands,
                "tests": {"engines": " ".join(ENGINE_TESTS), "orbits": " ".join(ORBIT_TESTS)},
                "sources": sorted({m.file for m in mutants}), "summary": summarize(results), "results": results,
                "survivors": [r for r in results if r["status"] in ("survived", "crashed")]}
    try:
        todo = [m for m in mutants if m.id not in done]
        for tests in dict.fromkeys(m.tests for m in todo):  # the unmutated tree must pass them
            base = _runtime_outcome(scratch, tests)
            if base["status"] != "survived":
                print(f"the unmutated tree fails {' '.join(tests)}: {base}", file=sys.stderr)
                return 1
        for k, mutant in enumerate(todo, 1):
            res = classify_runtime(scratch, mutant)
            results.append(res)
            print(f"[{k}/{len(todo)}] {res['status']:10} {mutant.id} ({res['seconds']} s)", file=sys.stderr,
                  flush=True)
            write({**data, "runtime": section()}, path)  # a run cut short keeps what it did
    finally:
        scratch.close()
    summary = summarize(results)
    write({**data, "runtime": section()}, path)
    print(f"{path}: runtime: {summary['mutants']} mutants, {summary['counts']}; caught "
          f"{summary['score_refused_or_caught']:.1%} of the non-equivalent")
    return 0


def summarize(results: list[dict]) -> dict:
    counts: dict[str, int] = {}
    for r in results:
        counts[r["status"]] = counts.get(r["status"], 0) + 1
    non_equivalent = len(results) - counts.get("equivalent", 0)
    before = counts.get("refused", 0) + counts.get("crashed-as-refusal", 0)
    return {"mutants": len(results), "counts": counts, "non_equivalent": non_equivalent,
            "refused_before_writing": before,
            "score_refused_or_caught": (before + counts.get("caught", 0)) / non_equivalent if non_equivalent else None,
            "score_refused": before / non_equivalent if non_equivalent else None}


def _report(results: list[dict], started: float, planned: int) -> dict:
    from .report import load_average, machine, utc_now, versions

    return {"benchmark": "mutation", "date": utc_now(), "machine": machine(), "versions": versions(),
            "load_average": load_average(), "seconds": round(time.time() - started),
            "complete": len(results) == planned, "planned": planned,
            "command": " ".join(["adbgen", "bench", "mutation", *sys.argv[3:]]),
            "regenerate": [" ".join(REGENERATE), " ".join(UNROLLED) + " (where the loop form writes)"],
            "sources": {"python": [f"adbgen/codegen/{p}" for p in PYTHON_SOURCES], "operators": list(OPERATORS),
                        "templates": "templates/**/*.j2"},
            "summary": summarize(results), "results": results,
            "survivors": [r for r in results if r["status"] in ("survived", "crashed")],
            "equivalents": [{"id": r["id"], "reason": r["reason"]} for r in results if r["status"] == "equivalent"]}


def retest(path: str) -> int:
    """Put the survivors of a results file through their named tests (the --tests step of a run that
    was made without it); rewrites the file."""
    from .report import write

    data = json.loads(Path(path).read_text())
    results, started = data["results"], time.time() - data["seconds"]
    scratch = Scratch()
    try:
        for res in results:
            if res["status"] != "survived":
                continue
            mutant = Mutant(res["id"], res["file"], res["old"], res["new"], res["kind"])
            t0 = time.perf_counter()
            with scratch.applied(mutant):
                caught, name = _run_test(scratch, _named_test(mutant))
            res.update(tested=_named_test(mutant), test_seconds=round(time.perf_counter() - t0, 1))
            if caught:
                res.update(status="caught", test=name)
            print(f"{res['status']:10} {res['id']} ({res['test_seconds']} s)", file=sys.stderr, flush=True)
            write(_report(results, started, data["planned"]), path)
    finally:
        scratch.close()
    summary = summarize(results)
    print(f"{path}: {summary['counts']}")
    return 0


def interleaved(mutants: list[Mutant]) -> list[Mutant]:
    """Round-robin over the mutated files (each file's own order kept), so that a run cut short has
    sampled every file and template alike instead of the first files only."""
    by_file: dict[str, list[Mutant]] = {}
    for m in mutants:
        by_file.setdefault(m.file, []).append(m)
    queues = list(by_file.values())
    return [q[k] for k in range(max(map(len, queues), default=0)) for q in queues if k < len(q)]


def _resumed(out) -> list[dict]:
    """The results an earlier run of the same plan wrote to `out` (none when there is no such file), but
    for the survivors and crashes: those are run again (the classification may have been refined since)."""
    path = Path(out)
    results = json.loads(path.read_text())["results"] if path.is_file() else []
    return [r for r in results if r["status"] not in ("survived", "crashed")]


def run(args, out) -> int:
    from .report import write

    if args.retest:
        return retest(out)
    if args.runtime:
        return run_runtime(args, out)
    started = time.time()
    scratch = Scratch()
    try:
        if args.sample:
            mutants = list(SAMPLE)
        else:
            mutants = interleaved(python_mutants(scratch.root, args.per_file, args.seed)
                                  + template_mutants(scratch.root, args.per_template, args.seed))
        baselines: dict[tuple, dict] = {}
        results = _resumed(out) if args.resume else []
        done = {r["id"] for r in results}
        if done:
            started -= json.loads(Path(out).read_text())["seconds"]
        for k, mutant in enumerate(mutants, 1):
            if mutant.id in done:
                continue
            for runs in {mutant.args, UNROLLED} - set(baselines):
                r = scratch.regenerate(runs, scratch.root / ".out")
                if r.returncode != 0:
                    print(f"the unmutated tree does not regenerate: {r.stderr.strip()[-300:]}", file=sys.stderr)
                    return 1
                baselines[runs] = files_of(scratch.root / ".out")
            res = classify(scratch, mutant, baselines, args.tests)
            results.append(res)
            print(f"[{k}/{len(mutants)}] {res['status']:18} {mutant.id} ({res['seconds']} s)", file=sys.stderr, flush=True)
            path = write(_report(results, started, len(mutants)), out)  # a run cut short keeps what it did
    finally:
        scratch.close()
    summary = summarize(results)
    path = write(_report(results, started, len(mutants)), out)
    print(f"{path}: {summary['mutants']} mutants, {summary['counts']}; refused or caught "
          f"{summary['score_refused_or_caught']:.1%}, refused before writing {summary['score_refused']:.1%} "
          "of the non-equivalent")
    return 0


BENCHMARK = Benchmark("mutation", run, (
    option("--per-file", type=int, default=8, help="cosmic-ray mutants per Python file of adbgen/codegen"),
    option("--per-template", type=int, default=8, help="mutants per template"),
    option("--seed", type=int, default=20, help="the sample's seed"),
    option("--sample", action="store_true", help="only the CI sample of 30 mutants"),
    option("--tests", action="store_true", help="put written mutants through the named tests of their target"),
    option("--retest", action="store_true", help="only put the survivors of the results file (--out) through their tests"),
    option("--resume", action="store_true", help="keep the results already in --out and run only the mutants not in it"),
    option("--runtime", action="store_true", help="the mutants of the engines' C drivers and the orbit code (RUNTIME, "
           "and --per-driver sampled ones), each through its targeted tests; into the results file's 'runtime' key"),
    option("--per-driver", type=int, default=0, help="with --runtime: sampled line mutants per C driver or header"),
))

__all__ = ["BENCHMARK", "Mutant", "RUNTIME", "SAMPLE", "Scratch", "classify", "classify_runtime", "driver_mutants",
           "interleaved", "python_mutants", "template_mutants"]

if __name__ == "__main__":  # pragma: no cover
    raise SystemExit("run: adbgen bench mutation")
