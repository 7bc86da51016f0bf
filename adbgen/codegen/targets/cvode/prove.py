"""The CVODE files' proof (issue 20): the adaptor through a harness, the driver on a short transient.

Everything is compiled with `compiler.STRICT_CFLAGS` against the system's SUNDIALS (>= 6) and the
model's C library (rendered for the proof if the C target is not among those written).

- The adaptor (`harness.c`, over the C library): `<model>_cvode_rhs` and `<model>_cvode_jac` at the
  Python check's random points return 0 and equal `Proof.expected`'s rhs and jac, the Jacobian read
  back from the SUNDenseMatrix with SM_ELEMENT_D (its column-major layout); identical balls stay
  bitwise together.
- The adaptor over a stub library (`harness.c -DPROOF_STUB`: the model's rhs and jac copy given
  values): finite values pass through and return 0 (with NAN in the cells after ydot: an adaptor that
  reads past the end sees it); a NAN or an infinity at any one position of rhs, and a NAN at any one
  entry of the Jacobian, returns CVODE's recoverable error (> 0); a matrix of the wrong size returns < 0.
- The driver: --help (exit 0, usage on stdout), bad arguments (exit 2, one line on stderr, nothing on
  stdout), the defaults (no Y0, no P) equal to Y0 = START (or zeros) and P = DEFAULTS given, and a
  short transient from a random state at random parameters (t_end = `TRANSIENT` / the spectral radius
  of the Jacobian there) within `TRANSIENT_TOLERANCE` of SciPy's DOP853 on the model's checked rhs,
  at the output times the usage says, with the analytic Jacobian used (jac_evals > 0, no difference
  quotients: lin_rhs_evals == 0).
"""

from __future__ import annotations

import ctypes
import subprocess
from pathlib import Path

import numpy as np

from ... import compiler
from ...passes.proof import Guarded

HERE = Path(__file__).resolve().parent
TRANSIENT = 4.0  # the transient's length in units of the fastest time scale at its start
TRANSIENT_TOLERANCE = 1e-6  # CVODE (BDF) against DOP853, both at rtol 1e-10: per state, of its largest value
RTOL, ATOL = 1e-10, 1e-12
N_OUT = 4
RUN_TIMEOUT = 60  # s per driver run


def _run(exe: Path, *args) -> subprocess.CompletedProcess:
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, timeout=RUN_TIMEOUT)


class Harness:
    def __init__(self, path: Path, n: int):
        self.cdll, self.n = ctypes.CDLL(str(path)), n
        self.rhs_fn = self.cdll.proof_rhs
        self.rhs_fn.restype = ctypes.c_int
        self.rhs_fn.argtypes = [ctypes.c_double, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p]
        self.jac_fn = self.cdll.proof_jac
        self.jac_fn.restype = ctypes.c_int
        self.jac_fn.argtypes = [ctypes.c_double, ctypes.c_void_p, ctypes.c_void_p, ctypes.c_long, ctypes.c_long,
                                ctypes.c_void_p]

    def close(self):
        import _ctypes

        _ctypes.dlclose(self.cdll._handle)

    def rhs(self, t, y, p) -> tuple[int, np.ndarray, bool]:
        """(flag, ydot, the NAN cells after ydot untouched)."""
        y, p = np.array(y, dtype=float), np.array(p, dtype=float)
        buf = np.full(self.n + 8, np.nan)
        buf[: self.n] = 0.0
        flag = self.rhs_fn(float(t), y.ctypes.data, p.ctypes.data, buf.ctypes.data)
        return flag, buf[: self.n].copy(), bool(np.all(np.isnan(buf[self.n:])))

    def jac(self, t, y, p, rows=None, cols=None) -> tuple[int, np.ndarray]:
        rows, cols = rows or self.n, cols or self.n
        y, p = np.array(y, dtype=float), np.array(p, dtype=float)
        out = Guarded(rows * cols)
        flag = self.jac_fn(float(t), y.ctypes.data, p.ctypes.data, rows, cols, out.inner.ctypes.data)
        return flag, out.inner.copy()


def _adaptor(proof, h: Harness, name: str) -> None:
    for t, y, p in proof.samples():
        flag, f, after = h.rhs(t, y, p)
        proof.require(flag == 0, f"{name}_cvode_rhs returns {flag} on a finite rhs")
        proof.compare(f"{name}_cvode_rhs", f, proof.expected("rhs", t, y, p))
        flag, J = h.jac(t, y, p)
        proof.require(flag == 0, f"{name}_cvode_jac returns {flag} on a finite Jacobian")
        proof.compare(f"{name}_cvode_jac (read back with SM_ELEMENT_D)", J, proof.expected("jac", t, y, p))

    def rhs(t, y, p):
        flag, f, _ = h.rhs(t, y, p)
        proof.require(flag == 0, f"{name}_cvode_rhs returns {flag}")
        return f
    proof.exchange_bitwise(f"{name}_cvode_rhs", rhs)


def _non_finite(proof, stub: Harness, name: str) -> None:
    n = stub.n
    values = (ctypes.c_double * n).in_dll(stub.cdll, "proof_stub_rhs")
    jac = (ctypes.c_double * (n * n)).in_dll(stub.cdll, "proof_stub_jac")
    finite = 1.0 + np.arange(n, dtype=float) / 8
    zeros = np.zeros(n)
    values[:] = finite.tolist()
    flag, f, after = stub.rhs(0.0, zeros, zeros)
    proof.require(flag == 0, f"{name}_cvode_rhs returns {flag} on finite values")
    proof.require(after, f"{name}_cvode_rhs writes past the end of ydot")
    proof.require(np.array_equal(f, finite), f"{name}_cvode_rhs does not pass rhs's values through")
    for k in range(n):
        for bad in (np.nan, np.inf, -np.inf):
            v = finite.copy()
            v[k] = bad
            values[:] = v.tolist()
            flag, _, _ = stub.rhs(0.0, zeros, zeros)
            proof.require(flag > 0, f"{name}_cvode_rhs returns {flag}, not CVODE's recoverable error (> 0), "
                                    f"when dydt[{k}] is {bad}")
    entries = 1.0 + np.arange(n * n, dtype=float) / (4 * n * n)
    jac[:] = entries.tolist()
    flag, J = stub.jac(0.0, zeros, zeros)
    proof.require(flag == 0, f"{name}_cvode_jac returns {flag} on finite values")
    proof.require(np.array_equal(J, entries), f"{name}_cvode_jac stores the row-major Jacobian in the wrong places")
    for k in range(n * n):
        v = entries.copy()
        v[k] = np.nan
        jac[:] = v.tolist()
        flag, _ = stub.jac(0.0, zeros, zeros)
        proof.require(flag > 0, f"{name}_cvode_jac returns {flag}, not CVODE's recoverable error (> 0), "
                                f"when entry ({k // n}, {k % n}) is nan")
    jac[:] = entries.tolist()
    for rows, cols in ((n, n + 1), (n + 1, n)):
        flag, _ = stub.jac(0.0, zeros, zeros, rows, cols)
        proof.require(flag < 0, f"{name}_cvode_jac returns {flag} for a {rows} x {cols} matrix, not an error (< 0)")


def _rows(proof, r: subprocess.CompletedProcess, what: str) -> np.ndarray:
    proof.require(r.returncode == 0, f"the driver exits {r.returncode} ({what}): {r.stderr.strip()[:200]}")
    try:
        return np.array([[float(v) for v in line.split()] for line in r.stdout.splitlines()])
    except ValueError:
        proof.fail(f"the driver prints something not numbers ({what})")


def _stats(proof, r: subprocess.CompletedProcess) -> dict:
    try:
        last = r.stderr.strip().splitlines()[-1]
        return {k: int(v) for k, v in (item.split("=") for item in last.split())}
    except (IndexError, ValueError):
        proof.fail(f"the driver prints no statistics line on stderr: {r.stderr.strip()[:200]!r}")


def _driver(proof, exe: Path, ir) -> None:
    from scipy.integrate import solve_ivp

    S, P = ir.n_states, len(ir.parameters)
    r = _run(exe, "--help")
    proof.require(r.returncode == 0 and r.stdout.startswith("usage: ") and r.stderr == "",
                  f"--help exits {r.returncode} without the usage on stdout")
    bad = {"no arguments": [], "T_END not a number": ["x", 2, 1e-8, 1e-10], "N_OUT zero": [1, 0, 1e-8, 1e-10],
           "RTOL nan": [1, 2, "nan", 1e-10], "ATOL zero": [1, 2, 1e-8, 0], "one y0": [1, 2, 1e-8, 1e-10, 0],
           "p short": [1, 2, 1e-8, 1e-10, "--", 1], "y0 nan": [1, 2, 1e-8, 1e-10, "nan", *[0] * (S - 1)],
           "p inf": [1, 2, 1e-8, 1e-10, "--", "inf", *[1] * (P - 1)]}
    for what, args in bad.items():
        r = _run(exe, *args)
        lines = r.stderr.splitlines()
        proof.require(r.returncode == 2 and r.stdout == "" and len(lines) == 1 and ": error: " in lines[0],
                      f"bad arguments ({what}): exit {r.returncode}, stderr {r.stderr.strip()[:120]!r} "
                      "(must be 2, one line '...: error: ...', nothing on stdout)")
    prog = proof.programs()
    t0, y0, p = proof.samples()[1]
    rho = float(np.max(np.abs(np.linalg.eigvals(prog["jac"](0.0, y0, p).reshape(S, S)))))
    t_end = TRANSIENT / max(rho, 1e-12)
    start = np.array(ir.start if ir.start is not None else np.zeros(S), dtype=float)
    defaults = np.array([q.default for q in ir.parameters], dtype=float)
    implicit = _run(exe, repr(t_end), 2, 1e-9, 1e-12)
    explicit = _run(exe, repr(t_end), 2, 1e-9, 1e-12, *map(repr, start.tolist()), "--", *map(repr, defaults.tolist()))
    _rows(proof, implicit, "defaults")
    proof.require(implicit.stdout == explicit.stdout, "the default Y0 and P differ from START (or zeros) and DEFAULTS")

    r = _run(exe, repr(t_end), N_OUT, RTOL, ATOL, *map(repr, y0.tolist()), "--", *map(repr, p.tolist()))
    rows = _rows(proof, r, "a transient")
    proof.require(rows.shape == (N_OUT + 1, S + 1), f"the driver prints {rows.shape} numbers, not {(N_OUT + 1, S + 1)}")
    times = t_end * np.arange(N_OUT + 1) / N_OUT
    proof.require(np.allclose(rows[:, 0], times, rtol=1e-14, atol=0) and rows[-1, 0] == t_end,
                  f"the output times are {rows[:, 0].tolist()}, not k T_END / N_OUT")
    proof.require(np.array_equal(rows[0, 1:], y0), "the first row is not Y0")
    sol = solve_ivp(lambda t, y: prog["rhs"](t, y, p), (0.0, t_end), y0, method="DOP853", rtol=RTOL, atol=ATOL,
                    t_eval=times)
    proof.require(sol.success, f"DOP853 failed on the reference transient: {sol.message}")
    ref = sol.y.T
    scale = np.maximum(np.abs(ref).max(axis=0), 1e-12 * np.abs(ref).max())
    err = float((np.abs(rows[:, 1:] - ref).max(axis=0) / scale).max())
    proof.require(err <= TRANSIENT_TOLERANCE, f"the driver's transient differs from DOP853 on the model by {err:.2e} "
                                              f"(tolerance {TRANSIENT_TOLERANCE:g})")
    stats = _stats(proof, r)
    proof.require(stats.get("steps", 0) > 0 and stats.get("jac_evals", 0) > 0 and stats.get("lin_rhs_evals", 1) == 0,
                  f"the driver does not use the analytic Jacobian (statistics {stats})")


def prove(target, proof) -> None:
    compiler.require("sundials", "cvode")
    ir = proof.model(target)
    name, up = ir.name, ir.name.upper()
    proof.ensure("c")
    folder = proof.path(proof.file(target, "cvode/adaptor.c.j2")).parent
    proof.file(target, "cvode/adaptor.h.j2")
    model = proof.c_object(f"{name}/{name}.c")
    adaptor = proof.c_object(proof.file(target, "cvode/adaptor.c.j2"))
    build = proof.build_dir()
    defines = [f"MODEL={name}", f"MODEL_UPPER={up}", f'MODEL_CVODE_HEADER="{name}_cvode.h"']
    libs = compiler.SUNDIALS_LIBS
    h_o = compiler.compile_object(HERE / "harness.c", build / "cvode_harness.o", "the CVODE proof harness",
                                  include=[folder], defines=defines)
    s_o = compiler.compile_object(HERE / "harness.c", build / "cvode_stub.o", "the CVODE proof harness (stub)",
                                  include=[folder], defines=[*defines, "PROOF_STUB"])
    real = compiler.link([h_o, adaptor, model], build / "libcvode_proof.so", f"{name}_cvode.c with {name}.c",
                         shared=True, libs=libs)
    stub = compiler.link([s_o, adaptor], build / "libcvode_stub.so", f"{name}_cvode.c alone", shared=True, libs=libs)
    driver = proof.c_object(proof.file(target, "cvode/driver.c.j2"))
    exe = compiler.link([driver, adaptor, model], build / f"{name}_cvode_main", f"{name}_cvode_main.c",
                        shared=False, libs=libs)
    proof.expected_all()
    for path, check, what in ((real, _adaptor, f"{name}_cvode.c over {name}.c"), (stub, _non_finite, f"{name}_cvode.c")):
        proof.isolated(what, lambda path=path, check=check: check(proof, Harness(path, ir.n_states), name))
    _driver(proof, exe, ir)
