"""The lanes header's proof (issue 20): `<model>_lanes.h` compiled inside a harness that defines its
contract (a 2-lane GCC vector type, adb_splat, and every math function lane by lane with libm: the
header's own includer, analysis/engines/lanes.h, maps sin/cos to libmvec), with -Wall -Wextra -Werror,
loaded, and at the Python check's random points, two different points per call (one per lane, each
with its own time and parameters), each lane's rhs equals `Proof.expected`; identical balls'
accelerations are bitwise equal where the balls coincide."""

from __future__ import annotations

import ctypes

import numpy as np

from ... import compiler
from ...passes.proof import Guarded

FLAGS = ("-std=gnu99", "-O2", "-Wall", "-Wextra", "-Werror")
LANES = 2  # SSE2: a vector every x86-64 passes in registers (no ABI note under -Werror)
FUNCTIONS = ("sin", "cos", "tan", "exp", "log", "sqrt", "atan", "fabs", "tanh", "cbrt")


def _harness(ir, header: str) -> str:
    m, S, P = ir.name, ir.n_states, len(ir.parameters)
    lines = ["#include <math.h>", "#include <string.h>",
             f"typedef double adb_lanes __attribute__((vector_size({LANES * 8})));",
             "#define adb_splat(x) ((x) - (adb_lanes){0})"]
    for fn in FUNCTIONS:
        lines += [f"static inline adb_lanes adb_{fn}_(adb_lanes x) {{ adb_lanes r; "
                  f"for (int b = 0; b < {LANES}; ++b) r[b] = {fn}(x[b]); return r; }}",
                  f"#define adb_{fn}(x) adb_{fn}_(adb_splat(x))"]
    lines += [f"static inline adb_lanes adb_pow_(adb_lanes a, adb_lanes e) {{ adb_lanes r; "
              f"for (int b = 0; b < {LANES}; ++b) r[b] = pow(a[b], e[b]); return r; }}",
              "#define adb_pow(a, e) adb_pow_(adb_splat(a), adb_splat(e))",
              f'#include "{header}"', f'#include "{header}"',  # twice: the include guard
              "/* T: LANES times; Y: LANES x states, P: LANES x parameters, F: LANES x states (row-major) */",
              "void proof_rhs(const double *T, const double *Y, const double *P, double *F)",
              "{",
              f"    adb_lanes t, y[{S}], p[{P}], f[{S}];",
              f"    for (int b = 0; b < {LANES}; ++b) {{",
              "        t[b] = T[b];",
              f"        for (int i = 0; i < {S}; ++i) y[i][b] = Y[b * {S} + i];",
              f"        for (int i = 0; i < {P}; ++i) p[i][b] = P[b * {P} + i];",
              "    }",
              f"    {m}_rhs_lanes(t, y, p, f);",
              f"    for (int b = 0; b < {LANES}; ++b)",
              f"        for (int i = 0; i < {S}; ++i) F[b * {S} + i] = f[i][b];",
              "}",
              f"const long proof_sizes[] = {{ {m.upper()}_LANES_N_STATES, {m.upper()}_LANES_N_PARAMS }};"]
    return "\n".join(lines) + "\n"


def prove(target, proof) -> None:
    compiler.require("gcc", "lanes")
    ir = proof.model(target)
    rel = proof.file(target, "lanes/model_lanes.h.j2")
    build = proof.build_dir()
    (build / "lanes_harness.c").write_text(_harness(ir, proof.path(rel).name))
    obj = compiler.compile_object(build / "lanes_harness.c", build / "lanes_harness.o", f"{rel} (in its harness)",
                                  include=[proof.path(rel).parent], flags=FLAGS)
    so = compiler.link([obj], build / f"lib{ir.name}_lanes.so", f"the harness of {rel}", shared=True)
    proof.expected_all()
    S, P = ir.n_states, len(ir.parameters)

    def run():
        lib = ctypes.CDLL(str(so))
        sizes = list((ctypes.c_long * 2).in_dll(lib, "proof_sizes"))
        proof.require(sizes == [S, P], f"{rel}'s N_STATES, N_PARAMS are {sizes}, the model's {[S, P]}")
        fn = lib.proof_rhs
        fn.restype, fn.argtypes = None, [ctypes.c_void_p] * 4

        def lanes(points):
            T = np.array([t for t, _, _ in points], float)
            Y = np.array([y for _, y, _ in points], float)
            Pm = np.array([p for _, _, p in points], float)
            out = Guarded(LANES * S)
            fn(T.ctypes.data, Y.ctypes.data, Pm.ctypes.data, out.inner.ctypes.data)
            proof.require(out.intact(), f"{ir.name}_rhs_lanes writes outside its {S} states x {LANES} lanes")
            return out.inner.reshape(LANES, S)

        points = proof.samples()
        for k in range(len(points)):
            pair = [points[k], points[(k + 1) % len(points)]]
            got = lanes(pair)
            for b, (t, y, p) in enumerate(pair):
                proof.compare(f"{ir.name}_rhs_lanes (lane {b})", got[b], proof.expected("rhs", t, y, p))
        proof.exchange_bitwise(f"{ir.name}_rhs_lanes", lambda t, y, p: lanes([(t, y, p)] * LANES)[1])
    proof.isolated(f"the harness of {rel}", run)
