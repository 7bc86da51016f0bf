"""The pinned libm of the compiled engines (adbgen/analysis/engines/fixed_libm.h, issue 23): every function it
maps onto SLEEF is declared (a missing declaration is an error, not an implicit `int` function) and gives the
function's value, within 2 ulp of glibc's, at arguments across its domain; pow(x, 2) is the one rounded
square.  (Found by `adbgen bench mutation --runtime`: a dropped declaration survived the engine tests,
whose models call no expm1.)
"""

from __future__ import annotations

import math
import re
import subprocess

import numpy as np
import pytest

from adbgen.analysis.engines.compiled import HERE, PINNED_FLAGS, PINNED_LIBS, compiler, pinned_libm

# name -> (Python's function, arguments)
FUNCTIONS = {
    "sin": (math.sin, [(0.3,), (-2.5,), (100.0,)]), "cos": (math.cos, [(0.3,), (-2.5,), (100.0,)]),
    "tan": (math.tan, [(0.3,), (-1.2,)]), "asin": (math.asin, [(0.3,), (-0.9,)]),
    "acos": (math.acos, [(0.3,), (-0.9,)]), "atan": (math.atan, [(0.3,), (-40.0,)]),
    "atan2": (math.atan2, [(0.3, -0.7), (-2.0, 0.5)]), "exp": (math.exp, [(0.3,), (-7.5,)]),
    "expm1": (math.expm1, [(1e-8,), (-0.4,)]), "log": (math.log, [(0.3,), (1e5,)]),
    "log1p": (math.log1p, [(1e-9,), (2.5,)]), "pow": (math.pow, [(0.3, 2.0), (1.7, 0.5), (2.0, -3.25)]),
    "sinh": (math.sinh, [(0.3,), (-3.0,)]), "cosh": (math.cosh, [(0.3,), (-3.0,)]),
    "tanh": (math.tanh, [(0.3,), (-3.0,)]), "cbrt": (np.cbrt, [(0.3,), (-27.5,)]),
    "hypot": (math.hypot, [(0.3, 0.4), (-3.0, 1e-3)]),
}


def test_every_mapped_function_is_tested_here():
    mapped = re.findall(r"^#define (\w+)\(", (HERE / "fixed_libm.h").read_text(), re.M)
    assert sorted(mapped) == sorted(FUNCTIONS)


def _program(functions) -> str:
    lines = ["#include <stdio.h>", "int main(void) {"]
    for name, (_, args) in functions.items():
        for a in args:
            lines.append(f'    printf("%a\\n", {name}({", ".join(repr(float(v)) for v in a)}));')
    return "\n".join(lines + ["    return 0;", "}"]) + "\n"


def _run(tmp_path, functions) -> list[float]:
    src = tmp_path / "libm.c"
    src.write_text(_program(functions))
    exe = tmp_path / "libm"
    proc = subprocess.run([compiler(), "-std=gnu99", "-O2", "-Werror=implicit-function-declaration", f"-I{HERE}",
                           *PINNED_FLAGS, str(src), "-o", str(exe), *PINNED_LIBS, "-lm"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    out = subprocess.run([str(exe)], capture_output=True, text=True, check=True).stdout.split()
    return [float.fromhex(v) for v in out]


def test_each_function_is_declared_and_gives_its_value(tmp_path):
    if not pinned_libm():
        pytest.fail("SLEEF (libsleef-dev) is not installed: the engines are not pinned")
    got = _run(tmp_path, FUNCTIONS)
    expected = [float(f(*a)) for f, args in FUNCTIONS.values() for a in args]
    assert len(got) == len(expected)
    for (name, a), g, e in zip([(n, a) for n, (_, args) in FUNCTIONS.items() for a in args], got, expected):
        assert abs(g - e) <= 2 * math.ulp(e), (name, a, g, e)
    assert got[[n for n, (_, args) in FUNCTIONS.items() for a in args].index("pow")] == 0.3 * 0.3  # x^2: x * x


def test_a_function_without_its_declaration_is_refused(tmp_path):
    """Negative control: the header with one declaration removed does not compile (rather than calling an
    implicitly declared int function)."""
    if not pinned_libm():
        pytest.fail("SLEEF (libsleef-dev) is not installed: the engines are not pinned")
    text = (HERE / "fixed_libm.h").read_text()
    broken = tmp_path / "fixed_libm.h"
    broken.write_text(text.replace("double Sleef_cinz_expm1d1_u10purec(double);\n", ""))
    src = tmp_path / "one.c"
    src.write_text('#include <stdio.h>\nint main(void) { printf("%a\\n", expm1(1e-8)); return 0; }\n')
    proc = subprocess.run([compiler(), "-std=gnu99", "-Werror=implicit-function-declaration", f"-I{tmp_path}",
                           "-include", str(broken), str(src), "-o", str(tmp_path / "one"), *PINNED_LIBS, "-lm"],
                          capture_output=True, text=True)
    assert proc.returncode != 0 and "Sleef_cinz_expm1d1_u10purec" in proc.stderr
