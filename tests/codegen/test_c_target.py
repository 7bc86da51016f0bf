"""The C target: strict compilation, the library (ctypes) against numba, and sanitizers (issue 4).

* Every default model's `<model>.c` compiles with exactly STRICT_CFLAGS (and with `-fPIC -shared` for the
  library) without a single line on gcc's stderr.
* Loaded with ctypes, `_rhs`, `_jac`, `_jac_p`, `_mass` and `_forcing` equal the numba module's `rhs`, `jac`,
  `jac_p`, `mass_matrix` and `forcing` norm-wise: max_k |c_k - numba_k| <= 1e-13 max_k |numba_k| for every
  function at each of 1000 random inputs per model (the default set, and n = 1, 5, 6 of both families
  rendered from the templates; for those, jac_p, mass_matrix and forcing run as py_func, see
  numba_functions).  Outputs are pre-filled with NaN, so an entry left unwritten fails.  Measured: the
  difference is exactly 0 everywhere (gcc -O2 and numba evaluate the same operations in the same order).
  The metadata arrays and the header's macros agree with the numba module.
* `c_harness.c`, compiled with the model (the default set and n = 1) under -fsanitize=address,undefined
  -fno-sanitize-recover=all, calls all five functions on heap blocks of exactly their size, on ordinary
  random inputs and on extreme but finite ones (states to 1e3, angles to 1e4 rad, parameters from 1e-6x
  to 1e6x the defaults, t to 1e4; outputs reach 1e29): exit 0, nothing on stderr, and the outputs equal
  numba's to 1e-13 (measured: 0, at the extreme inputs too).  A harness with a Jacobian block one entry
  short and a signed overflow must both be caught, so the sanitizers are known to be active.
Tests needing gcc fail in CI and skip elsewhere when it is missing (toolchain.require_tool).
"""

from __future__ import annotations

import ctypes
import os
import re
import subprocess
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

from adbgen.codegen.regenerate import DEFAULT_OUT

# helpers of this folder (conftest.py puts it on sys.path)
from sampling import random_inputs
from toolchain import STRICT_CFLAGS, require_tool, which

HERE = Path(__file__).parent


RTOL = 1e-13
EXTREME_RTOL = 1e-13  # measured: C and numba are bit-identical at the extreme inputs too
SAMPLES = 1000
FAMILIES = ("thesis_rotating", "single_plane_fixed")
DEFAULT_SET = [(f, n) for f in FAMILIES for n in (2, 3, 4)]
RENDERED = [(f, n) for f in FAMILIES for n in (1, 5, 6)]
SANITIZE = ("-fsanitize=address,undefined", "-fno-sanitize-recover=all", "-g", "-O1")  # after STRICT: -O1 wins
SANITIZER_ENV = {"ASAN_OPTIONS": "detect_leaks=1:halt_on_error=1:detect_stack_use_after_return=1",
                 "UBSAN_OPTIONS": "print_stacktrace=1:halt_on_error=1"}
FUNCTIONS = ("rhs", "jac", "jac_p", "mass", "forcing")


def _ids(models):
    return [f"{f}_n{n}" for f, n in models]


def gcc(args, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([which("gcc"), *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=120)


def numba_functions(m, folder: Path) -> tuple:
    """The numba module's counterparts of FUNCTIONS.  For a model rendered into a temporary folder (no numba
    cache) only rhs and jac are JIT-compiled (test_numba_target compiles them in the same session);
    jac_p, mass_matrix and forcing run as their py_func, the same source under CPython, which spares ~7 s
    of compilation per model (the default set checks the compiled ones)."""
    if folder == DEFAULT_OUT / m.NAME:
        return m.rhs, m.jac, m.jac_p, m.mass_matrix, m.forcing
    n, n_p = len(m.STATE_NAMES), len(m.PARAM_NAMES)

    def jac_p(t, y, p):
        out = np.empty((n, n_p))
        m.jac_p_inplace.py_func(t, y, p, out)
        return out

    return m.rhs, m.jac, jac_p, m.mass_matrix.py_func, m.forcing.py_func


def numba_outputs(functions, t, y, p) -> tuple:
    """The outputs of `functions` (numba_functions), flattened row-major."""
    return tuple(np.ravel(f(t, y, p)) for f in functions)


def sizes(m) -> tuple:
    """Output lengths of FUNCTIONS for numba module `m`."""
    n, n_p = len(m.STATE_NAMES), len(m.PARAM_NAMES)
    return n, n * n, n * n_p, (n // 2) ** 2, n // 2


def relative_error(a: np.ndarray, b: np.ndarray) -> float:
    """max |a - b| / max |b| (0 if equal; inf if b is 0 and a is not, or if a has a NaN)."""
    diff = np.abs(a - b).max()
    if np.isnan(diff):
        return np.inf
    scale = np.abs(b).max()
    return diff / scale if scale > 0 else (0.0 if diff == 0 else np.inf)


def header_macros(folder: Path, name: str) -> dict:
    """{suffix: value} of the `#define <NAME>_<suffix> <value>` lines of `<name>.h`."""
    text = (folder / f"{name}.h").read_text()
    return dict(re.findall(rf"^#define {name.upper()}_(\w+) (.+)$", text, re.M))


# ---------------------------------------------------------------------------------------------------- library


class Library:
    """The C library of one model, loaded with ctypes, with the five functions callable on numpy arrays."""

    def __init__(self, path: Path, name: str, module):
        self.cdll, self.name, self.module = ctypes.CDLL(str(path)), name, module
        vec = np.ctypeslib.ndpointer(dtype=np.float64, flags="C_CONTIGUOUS")
        self.functions = []
        for suffix in FUNCTIONS:
            f = getattr(self.cdll, f"{name}_{suffix}")
            f.argtypes, f.restype = [ctypes.c_double, vec, vec, vec], None
            self.functions.append(f)
        self.sizes = sizes(module)

    def outputs(self, t, y, p) -> tuple:
        y, p = np.ascontiguousarray(y, float), np.ascontiguousarray(p, float)
        outs = []
        for f, size in zip(self.functions, self.sizes):
            out = np.full(size, np.nan)
            f(float(t), y, p, out)
            outs.append(out)
        return tuple(outs)

    def array(self, symbol: str, ctype, length: int):
        return list((ctype * length).in_dll(self.cdll, f"{self.name}_{symbol}"))


_libraries: dict = {}


@pytest.fixture(scope="module")
def library(generated_model, tmp_path_factory):
    """library(family, n) -> (Library, gcc's stderr, folder with the sources), built with STRICT_CFLAGS."""
    require_tool(which("gcc") is not None, "gcc")

    def get(family: str, n: int):
        key = (family, n)
        if key not in _libraries:
            module, _, folder = generated_model(family, n)
            name = module.NAME
            build = tmp_path_factory.mktemp(f"c_{name}")
            so = build / f"lib{name}.so"
            r = gcc([*STRICT_CFLAGS, "-fPIC", "-shared", "-o", so, folder / f"{name}.c", "-lm"], build)
            assert r.returncode == 0, f"building the library of {name} failed:\n{r.stderr}"
            _libraries[key] = (Library(so, name, module), r.stderr, folder)
        return _libraries[key]
    return get


@pytest.mark.parametrize("family, n", DEFAULT_SET, ids=_ids(DEFAULT_SET))
def test_compiles_without_diagnostics(library, family, n, tmp_path):
    lib, library_stderr, folder = library(family, n)
    assert folder == DEFAULT_OUT / lib.name, "the default set must come from the committed generated/"
    r = gcc([*STRICT_CFLAGS, "-c", "-o", tmp_path / f"{lib.name}.o", folder / f"{lib.name}.c"], tmp_path)
    assert r.returncode == 0 and r.stderr == "", f"gcc {' '.join(STRICT_CFLAGS)} on {lib.name}.c:\n{r.stderr}"
    assert library_stderr == "", f"gcc -fPIC -shared on {lib.name}.c:\n{library_stderr}"


@pytest.mark.parametrize("family, n", DEFAULT_SET + RENDERED, ids=_ids(DEFAULT_SET + RENDERED))
def test_library_equals_numba(library, family, n):
    lib, _, folder = library(family, n)
    m = lib.module
    reference = numba_functions(m, folder)
    t, y, p = random_inputs(m, SAMPLES, seed=1300 + 10 * n + FAMILIES.index(family))
    worst = dict.fromkeys(FUNCTIONS, 0.0)
    for k in range(SAMPLES):
        for name, c, ref in zip(FUNCTIONS, lib.outputs(t[k], y[k], p[k]), numba_outputs(reference, t[k], y[k], p[k])):
            assert np.all(np.isfinite(c)), f"{lib.name}_{name}: entry not written or not finite at sample {k}"
            worst[name] = max(worst[name], relative_error(c, ref))
    print(f"{lib.name}: max norm-wise relative difference C vs numba", worst)
    bad = {name: e for name, e in worst.items() if not e <= RTOL}
    assert not bad, f"{lib.name}: C differs from numba beyond {RTOL:g}: {bad}"


@pytest.mark.parametrize("family, n", DEFAULT_SET + RENDERED, ids=_ids(DEFAULT_SET + RENDERED))
def test_metadata_equals_numba(library, family, n):
    lib, _, folder = library(family, n)
    m = lib.module
    n_states, n_params = len(m.STATE_NAMES), len(m.PARAM_NAMES)
    assert [s.decode() for s in lib.array("state_names", ctypes.c_char_p, n_states)] == list(m.STATE_NAMES)
    assert [s.decode() for s in lib.array("param_names", ctypes.c_char_p, n_params)] == list(m.PARAM_NAMES)
    assert lib.array("defaults", ctypes.c_double, n_params) == m.DEFAULTS.tolist()
    macros = header_macros(folder, lib.name)
    assert macros["SOURCE_HASH"] == f'"{m.SOURCE_HASH}"'
    assert (int(macros["N_STATES"]), int(macros["N_PARAMS"]), int(macros["N_COORDINATES"])) == \
        (n_states, n_params, n_states // 2) == (m.N_STATES, n_params, n_states // 2)
    assert int(macros["N_BALLS"]) == m.N_BALLS == n
    assert macros["HAS_START"] == ("0" if m.START is None else "1")
    if m.START is not None:
        assert lib.array("start", ctypes.c_double, n_states) == m.START.tolist()
        assert lib.array("start_parameters", ctypes.c_double, n_params) == m.START_PARAMETERS.tolist()


# ------------------------------------------------------------------------------------------------- sanitizers


def build_harness(module, folder: Path, build: Path, *defines: str) -> tuple[Path, str]:
    """c_harness.c with the model's .c under the sanitizers and STRICT_CFLAGS: (executable, gcc's stderr)."""
    name = module.NAME
    exe = build / ("_".join([name, "harness", *(d.lower() for d in defines)]))
    r = gcc([*STRICT_CFLAGS, *SANITIZE, "-I", folder, f'-DMODEL_HEADER="{name}.h"', f"-DMODEL={name}",
             f"-DMODEL_UPPER={name.upper()}", *(f"-D{d}" for d in defines), "-o", exe, HERE / "c_harness.c",
             folder / f"{name}.c", "-lm"], build)
    assert r.returncode == 0, f"building the sanitized harness of {name} failed:\n{r.stderr}"
    return exe, r.stderr


def run_sanitized(exe: Path, stdin: str) -> subprocess.CompletedProcess:
    r = subprocess.run([str(exe)], input=stdin, capture_output=True, text=True, timeout=120,
                       env={**os.environ, **SANITIZER_ENV})
    if "LeakSanitizer has encountered a fatal error" in r.stderr:  # LSan needs ptrace; keep ASan and UBSan
        env = {**os.environ, **SANITIZER_ENV, "ASAN_OPTIONS": SANITIZER_ENV["ASAN_OPTIONS"] + ":detect_leaks=0"}
        r = subprocess.run([str(exe)], input=stdin, capture_output=True, text=True, timeout=120, env=env)
    return r


def harness_input(t, y, p) -> str:
    records = [" ".join(map(repr, [float(t[k]), *map(float, y[k]), *map(float, p[k])])) for k in range(len(t))]
    return f"{len(t)}\n" + "\n".join(records) + "\n"


def parse_harness(stdout: str, m) -> tuple[dict, list]:
    """({label: [words]} of the metadata lines, [(rhs, jac, jac_p, mass, forcing) per record])."""
    meta, results = {}, []
    bounds = np.cumsum((0, *sizes(m)))
    for line in stdout.splitlines():
        label, *words = line.split()
        if label == "out":
            values = np.array(words, float)
            assert values.size == bounds[-1], f"harness printed {values.size} numbers, expected {bounds[-1]}"
            results.append(tuple(values[a:b] for a, b in zip(bounds[:-1], bounds[1:])))
        else:
            meta[label] = words
    return meta, results


def extreme_inputs(m, n_samples: int, seed: int):
    """Finite but far from the ordinary: coordinates and rates to +-1e3, angles to +-1e4 rad, every parameter
    scaled by 10^U(-6, 6) independently, t to 1e4; plus the all-zero state at t = 0."""
    rng = np.random.default_rng(seed)
    n = len(m.STATE_NAMES)
    y = rng.choice([-1.0, 1.0], (n_samples, n)) * 10.0 ** rng.uniform(-3.0, 3.0, (n_samples, n))
    for k, name in enumerate(m.STATE_NAMES[: n // 2]):
        if name.startswith("phi_"):
            y[:, k] = rng.uniform(-1e4, 1e4, n_samples)
    p = m.DEFAULTS * 10.0 ** rng.uniform(-6.0, 6.0, (n_samples, m.DEFAULTS.size))
    t = 10.0 ** rng.uniform(-3.0, 4.0, n_samples)
    y[0], t[0] = 0.0, 0.0
    return t, y, p


SANITIZED = DEFAULT_SET + [("thesis_rotating", 1), ("single_plane_fixed", 1)]


@pytest.fixture(scope="module")
def harnesses(generated_model, tmp_path_factory) -> dict:
    """{(family, n): (executable, gcc's stderr)}, built in parallel."""
    require_tool(which("gcc") is not None, "gcc")
    build = tmp_path_factory.mktemp("c_harness")
    models = {key: generated_model(*key) for key in SANITIZED}
    with ThreadPoolExecutor(max_workers=max(2, os.cpu_count() or 1)) as pool:
        futures = {key: pool.submit(build_harness, m, folder, build) for key, (m, _, folder) in models.items()}
        return {key: f.result() for key, f in futures.items()}


@pytest.mark.parametrize("family, n", SANITIZED, ids=_ids(SANITIZED))
def test_sanitized_harness_runs_clean(harnesses, generated_model, family, n):
    exe, build_stderr = harnesses[(family, n)]
    assert build_stderr == "", f"gcc printed diagnostics building the sanitized harness:\n{build_stderr}"
    m, _, folder = generated_model(family, n)
    reference = numba_functions(m, folder)
    seed = 4100 + 10 * n + FAMILIES.index(family)
    ordinary, extreme = random_inputs(m, 200, seed), extreme_inputs(m, 200, seed + 1)
    inputs = [np.concatenate(parts) for parts in zip(ordinary, extreme)]
    r = run_sanitized(exe, harness_input(*inputs))
    assert r.returncode == 0 and r.stderr == "", f"sanitized harness of {m.NAME}: exit {r.returncode}\n{r.stderr}"
    meta, results = parse_harness(r.stdout, m)
    assert len(results) == len(inputs[0])

    # metadata as compiled: the hash macro, the sizes, names, defaults and start
    assert meta["hash"] == [m.SOURCE_HASH]
    assert meta["sizes"] == [str(m.N_STATES), str(len(m.PARAM_NAMES)), str(m.N_STATES // 2)]
    assert meta["states"] == list(m.STATE_NAMES) and meta["params"] == list(m.PARAM_NAMES)
    assert np.array_equal(np.array(meta["defaults"], float), m.DEFAULTS)
    assert ("start" in meta) == (m.START is not None)
    if m.START is not None:
        assert np.array_equal(np.array(meta["start"], float), m.START)
        assert np.array_equal(np.array(meta["start_parameters"], float), m.START_PARAMETERS)

    worst = {"ordinary": dict.fromkeys(FUNCTIONS, 0.0), "extreme": dict.fromkeys(FUNCTIONS, 0.0)}
    for k, outputs in enumerate(results):
        kind = "ordinary" if k < len(ordinary[0]) else "extreme"
        refs = numba_outputs(reference, inputs[0][k], inputs[1][k], inputs[2][k])
        for name, c, ref in zip(FUNCTIONS, outputs, refs):
            # C and numba agree on which entries overflow (inf or nan) at extreme inputs
            assert np.array_equal(np.isfinite(c), np.isfinite(ref)), f"{m.NAME}_{name}, {kind} sample {k}"
            if kind == "ordinary":
                assert np.all(np.isfinite(c))
            finite = np.isfinite(ref)
            if finite.any():
                worst[kind][name] = max(worst[kind][name], relative_error(c[finite], ref[finite]))
    print(f"{m.NAME} sanitized harness vs numba: max norm-wise relative difference", worst)
    assert all(e <= RTOL for e in worst["ordinary"].values()), worst["ordinary"]
    assert all(e <= EXTREME_RTOL for e in worst["extreme"].values()), worst["extreme"]


def test_sanitizers_are_active(generated_model, tmp_path):
    """The harness with a Jacobian block one entry short must be stopped by AddressSanitizer, and a signed
    overflow by UndefinedBehaviorSanitizer: a clean run above means something."""
    require_tool(which("gcc") is not None, "gcc")
    m, _, folder = generated_model("thesis_rotating", 2)
    exe, _ = build_harness(m, folder, tmp_path, "HARNESS_SHORT_JAC")
    r = run_sanitized(exe, harness_input(*random_inputs(m, 1, seed=5)))
    assert r.returncode != 0 and "AddressSanitizer: heap-buffer-overflow" in r.stderr, r.stderr
    assert f"{m.NAME}_jac" in r.stderr  # the write past the block is in the generated Jacobian
    (tmp_path / "ub.c").write_text("#include <limits.h>\n#include <stdio.h>\n"
                                   "int main(void)\n{\n    volatile int one = 1;\n    int big = INT_MAX;\n"
                                   "    big += one;\n    printf(\"%d\\n\", big);\n    return 0;\n}\n")
    b = gcc([*STRICT_CFLAGS, *SANITIZE, "-o", tmp_path / "ub", tmp_path / "ub.c"], tmp_path)
    assert b.returncode == 0, b.stderr
    r = run_sanitized(tmp_path / "ub", "")
    assert r.returncode != 0 and "signed integer overflow" in r.stderr, r.stderr
