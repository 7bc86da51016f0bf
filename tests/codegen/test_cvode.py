"""The SUNDIALS CVODE target: adaptor (CVRhsFn and dense CVLsJacFn over the C library) and driver.

Built from the committed generated/ with the strict flags, against Debian's libsundials-dev (CI installs
gcc and libsundials-dev; elsewhere the tests skip when either is missing).  The driver is checked against
SciPy's DOP853 on the numba module of the same model:

* the thesis transient (issue 4): n = 2, Omega = 4, zeta = beta = delta = 0.01, mu = 0.05,
  phi(0) = (pi/2, -pi/2), all else 0, to t = 200; CVODE at rtol 1e-10, atol 1e-12; DOP853 at rtol 1e-10,
  atol 1e-12; error norm max over the output times and states of |y_cvode - y_dop853|, divided by
  max |y_dop853| over the same, must be < 1e-6 (measured: about 1e-8);
* the fixed-frame model (non-autonomous: time enters the forcing) for a short time, per state relative to
  that state's largest magnitude (the states differ in scale by 1e4).
"""

from __future__ import annotations

import subprocess
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from adbgen.codegen.regenerate import DEFAULT_OUT

# helpers of this folder (conftest.py puts it on sys.path)
from toolchain import STRICT_CFLAGS, require_tool, which


LIBS = ("-lsundials_cvode", "-lsundials_nvecserial", "-lsundials_sunmatrixdense", "-lsundials_sunlinsoldense",
        "-lm")
MODELS = ("thesis_rotating_n2", "single_plane_fixed_n2")

PROBE = r"""
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
int main(void)
{
    SUNContext ctx = NULL;
    if (SUNContext_Create(NULL, &ctx) != 0) {
        return 1;
    }
    SUNContext_Free(&ctx);
    return 0;
}
"""


def _gcc(args: list, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([which("gcc"), *args], cwd=cwd, capture_output=True, text=True, timeout=120)


# Calls the adaptor's two callbacks through N_Vector and SUNMatrix: argv = t y_0 .. y_{n-1} p_0 .. p_{m-1};
# prints dydt (one line) then J row by row, read back with SM_ELEMENT_D.
HARNESS = r"""
#include <stdio.h>
#include <stdlib.h>
#include "@NAME@_cvode.h"
int main(int argc, char **argv)
{
    const int n = @P@_N_STATES, m = @P@_N_PARAMS;
    double p[@P@_N_PARAMS];
    SUNContext ctx = NULL;
    N_Vector y, f;
    SUNMatrix J;
    int i, j, rhs_flag, jac_flag;
    if (argc != 2 + n + m || SUNContext_Create(NULL, &ctx) != 0) {
        return 2;
    }
    y = N_VNew_Serial(n, ctx);
    f = N_VNew_Serial(n, ctx);
    J = SUNDenseMatrix(n, n, ctx);
    if (y == NULL || f == NULL || J == NULL) {
        return 3;
    }
    for (i = 0; i < n; ++i) {
        NV_Ith_S(y, i) = strtod(argv[2 + i], NULL);
    }
    for (i = 0; i < m; ++i) {
        p[i] = strtod(argv[2 + n + i], NULL);
    }
    rhs_flag = @NAME@_cvode_rhs(strtod(argv[1], NULL), y, f, p);
    jac_flag = @NAME@_cvode_jac(strtod(argv[1], NULL), y, f, J, p, NULL, NULL, NULL);
    if (rhs_flag != 0 || jac_flag != 0) {
        return 4;
    }
    for (i = 0; i < n; ++i) {
        printf("%.17g%c", NV_Ith_S(f, i), i + 1 < n ? ' ' : '\n');
    }
    for (i = 0; i < n; ++i) {
        for (j = 0; j < n; ++j) {
            printf("%.17g%c", SM_ELEMENT_D(J, i, j), j + 1 < n ? ' ' : '\n');
        }
    }
    SUNMatDestroy(J);
    N_VDestroy(f);
    N_VDestroy(y);
    SUNContext_Free(&ctx);
    return 0;
}
"""


@pytest.fixture(scope="module")
def drivers(tmp_path_factory) -> dict:
    """{model: (path of the driver executable, gcc's stderr)}, built with STRICT_CFLAGS."""
    require_tool(which("gcc") is not None, "gcc")
    build = tmp_path_factory.mktemp("cvode")
    (build / "probe.c").write_text(PROBE)
    probe = _gcc([*STRICT_CFLAGS, "-o", "probe", "probe.c", *LIBS], build)
    require_tool(probe.returncode == 0 and subprocess.run([build / "probe"]).returncode == 0,
                 "SUNDIALS CVODE >= 6 (Debian: libsundials-dev) " + probe.stderr.strip()[:300])
    out = {}
    for name in MODELS:
        folder = DEFAULT_OUT / name
        sources = [folder / f"{name}_cvode_main.c", folder / f"{name}_cvode.c", folder / f"{name}.c"]
        missing = [s.name for s in sources if not s.is_file()]
        assert not missing, f"{missing} not in {folder}: run `adbgen regenerate`"
        exe = build / f"{name}_cvode_main"
        r = _gcc([*STRICT_CFLAGS, "-I", str(folder), "-o", str(exe), *map(str, sources), *LIBS], build)
        assert r.returncode == 0, f"building the CVODE driver of {name} failed:\n{r.stderr}"
        out[name] = (exe, r.stderr)
        harness = build / f"{name}_harness.c"
        harness.write_text(HARNESS.replace("@NAME@", name).replace("@P@", name.upper()))
        r = _gcc([*STRICT_CFLAGS, "-I", str(folder), "-o", str(build / f"{name}_harness"), str(harness),
                  str(folder / f"{name}_cvode.c"), str(folder / f"{name}.c"), *LIBS], build)
        assert r.returncode == 0 and r.stderr == "", f"building the adaptor harness of {name} failed:\n{r.stderr}"
    return out


def numba_module(generated_model, name: str):
    """The numba module of the committed generated/<name> (through conftest's generated_model)."""
    family, n = name.rsplit("_n", 1)
    module, _, folder = generated_model(family, int(n))
    assert folder == DEFAULT_OUT / name
    return module


def run(exe: Path, *args) -> subprocess.CompletedProcess:
    return subprocess.run([str(exe), *map(str, args)], capture_output=True, text=True, timeout=60)


def integrate(exe: Path, t_end, n_out, rtol, atol, y0=None, p=None):
    """(output rows t, y_0 .. y_{n-1}; statistics {name: count}) of one driver run."""
    args = [repr(float(t_end)), n_out, repr(rtol), repr(atol)]
    if y0 is not None:
        args += [repr(float(v)) for v in y0]
    if p is not None:
        args += ["--", *(repr(float(v)) for v in p)]
    r = run(exe, *args)
    assert r.returncode == 0, r.stderr
    rows = np.array([[float(v) for v in line.split()] for line in r.stdout.splitlines()])
    stats = dict(item.split("=") for item in r.stderr.strip().splitlines()[-1].split())
    return rows, {k: int(v) for k, v in stats.items()}


def dop853(module, rows, y0, p, atol):
    t = rows[:, 0]
    sol = solve_ivp(module.rhs, (t[0], t[-1]), np.asarray(y0, float), method="DOP853", rtol=1e-10, atol=atol,
                    t_eval=t, args=(np.asarray(p, float),))
    assert sol.success, sol.message
    return sol.y.T


@pytest.mark.parametrize("name", MODELS)
def test_builds_without_warnings(drivers, name):
    exe, stderr = drivers[name]
    assert exe.is_file()
    assert stderr == "", f"gcc printed diagnostics for {name}:\n{stderr}"


@pytest.mark.parametrize("name", MODELS)
def test_callbacks_equal_numba(drivers, generated_model, name):
    """The adaptor passes t, y, p through and lays the row-major Jacobian out column-major correctly."""
    m = numba_module(generated_model, name)
    harness = drivers[name][0].with_name(f"{name}_harness")
    rng = np.random.default_rng(4)
    n = len(m.STATE_NAMES)
    for _ in range(5):
        t = rng.uniform(0.1, 3.0)
        y = rng.uniform(-1.0, 1.0, n)
        p = m.DEFAULTS * rng.uniform(0.5, 1.5, len(m.DEFAULTS))
        r = run(harness, repr(t), *map(repr, y.tolist()), *map(repr, p.tolist()))
        assert r.returncode == 0, r.stderr
        lines = r.stdout.splitlines()
        f = np.array(lines[0].split(), float)
        J = np.array([line.split() for line in lines[1:]], float)
        f_ref, J_ref = m.rhs(t, y, p), m.jac(t, y, p)
        assert J.shape == (n, n) and not np.array_equal(J_ref, J_ref.T)
        np.testing.assert_allclose(f, f_ref, rtol=1e-13, atol=1e-13 * np.abs(f_ref).max())
        np.testing.assert_allclose(J, J_ref, rtol=1e-13, atol=1e-13 * np.abs(J_ref).max())


def test_thesis_transient_agrees_with_dop853(drivers, generated_model):
    m = numba_module(generated_model, "thesis_rotating_n2")
    assert len(m.STATE_NAMES) == N2
    p = m.params(Omega=4.0, zeta=0.01, beta=0.01, delta=0.01, mu=0.05)
    y0 = np.zeros(len(m.STATE_NAMES))
    y0[m.state_index("phi_1")] = np.pi / 2
    y0[m.state_index("phi_2")] = -np.pi / 2
    rows, stats = integrate(drivers["thesis_rotating_n2"][0], 200.0, 400, 1e-10, 1e-12, y0, p)
    assert rows.shape == (401, 1 + len(y0))
    np.testing.assert_allclose(rows[:, 0], np.linspace(0.0, 200.0, 401), rtol=0, atol=1e-12)
    assert rows[-1, 0] == 200.0
    np.testing.assert_array_equal(rows[0, 1:], y0)
    ref = dop853(m, rows, y0, p, atol=1e-12)
    err = np.abs(rows[:, 1:] - ref).max() / np.abs(ref).max()
    assert err < 1e-6, f"CVODE vs DOP853: max |difference| / max |y| = {err:.3g}"
    # the balls have moved (a transient, not a rest state) and the analytic Jacobian was used
    assert np.abs(ref[:, m.state_index("phi_1")] - np.pi / 2).max() > 0.1
    assert stats["steps"] > 0 and stats["jac_evals"] > 0
    assert stats["lin_rhs_evals"] == 0, "CVODE approximated the Jacobian by differences instead of calling jac"


def test_fixed_frame_agrees_with_dop853(drivers, generated_model):
    m = numba_module(generated_model, "single_plane_fixed_n2")
    p = m.DEFAULTS
    y0 = np.zeros(len(m.STATE_NAMES))
    y0[m.state_index("phi_1")] = 1.0
    y0[m.state_index("phi_2")] = -2.0
    rows, stats = integrate(drivers["single_plane_fixed_n2"][0], 0.5, 100, 1e-10, 1e-13, y0, p)
    ref = dop853(m, rows, y0, p, atol=1e-13)
    scale = np.abs(ref).max(axis=0)
    assert np.all(scale > 0)
    err = (np.abs(rows[:, 1:] - ref).max(axis=0) / scale).max()
    assert err < 1e-6, f"CVODE vs DOP853: max over states of max |difference| / max |y_k| = {err:.3g}"
    assert stats["jac_evals"] > 0 and stats["lin_rhs_evals"] == 0


@pytest.mark.parametrize("name", MODELS)
def test_defaults(drivers, generated_model, name):
    """Without Y0 and P the driver starts from START (or zeros) with DEFAULTS."""
    m = numba_module(generated_model, name)
    exe = drivers[name][0]
    y0 = np.zeros(len(m.STATE_NAMES)) if m.START is None else np.asarray(m.START, float)
    default = run(exe, "0.25", 5, "1e-9", "1e-12")
    explicit = run(exe, "0.25", 5, "1e-9", "1e-12", *map(repr, y0.tolist()), "--", *map(repr, m.DEFAULTS.tolist()))
    assert default.returncode == explicit.returncode == 0, default.stderr + explicit.stderr
    assert default.stdout == explicit.stdout
    assert len(default.stdout.splitlines()) == 6
    if m.START is not None and np.array_equal(m.START_PARAMETERS, m.DEFAULTS):
        rows = np.array([[float(v) for v in line.split()] for line in default.stdout.splitlines()])
        assert np.abs(rows[:, 1:] - y0).max() < 1e-9  # a steady state stays put


def test_help(drivers):
    r = run(drivers["thesis_rotating_n2"][0], "--help")
    assert r.returncode == 0 and r.stdout.startswith("usage: ") and "Omega" in r.stdout and r.stderr == ""


N2 = 8  # states of thesis_rotating_n2
BAD = {
    "no arguments": [],
    "too few": ["1", "2", "1e-8"],
    "T_END not a number": ["x", "2", "1e-8", "1e-10"],
    "T_END nan": ["nan", "2", "1e-8", "1e-10"],
    "T_END negative": ["-1", "2", "1e-8", "1e-10"],
    "N_OUT zero": ["1", "0", "1e-8", "1e-10"],
    "N_OUT not an integer": ["1", "2.5", "1e-8", "1e-10"],
    "RTOL nan": ["1", "2", "nan", "1e-10"],
    "ATOL inf": ["1", "2", "1e-8", "inf"],
    "ATOL zero": ["1", "2", "1e-8", "0"],
    "wrong number of y0": ["1", "2", "1e-8", "1e-10", "0", "0"],
    "y0 not a number": ["1", "2", "1e-8", "1e-10", *["0"] * (N2 - 1), "1e"],
    "y0 nan": ["1", "2", "1e-8", "1e-10", "NaN", *["0"] * (N2 - 1)],
    "y0 overflow": ["1", "2", "1e-8", "1e-10", "1e999", *["0"] * (N2 - 1)],
    "wrong number of p": ["1", "2", "1e-8", "1e-10", "--", "4", "0.01"],
    "no p after --": ["1", "2", "1e-8", "1e-10", "--"],
    "p nan": ["1", "2", "1e-8", "1e-10", "--", "4", "0.01", "0.01", "nan", "0.01"],
}


@pytest.mark.parametrize("args", list(BAD.values()), ids=list(BAD))
def test_bad_input(drivers, args):
    r = run(drivers["thesis_rotating_n2"][0], *args)
    assert r.returncode == 2
    assert r.stdout == ""
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and ": error: " in lines[0], r.stderr
