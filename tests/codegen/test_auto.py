"""The AUTO-07p target: user file (func with dfdu and dfdp, stpnt, pvls) and constants file.

Built and run the way AUTO's own `@r` does (Debian's `auto-07p` with `gfortran`: the classic
`make -f $AUTO_DIR/cmds/cmds.make EQUATION_NAME=<name> < c.<name>`), in a temporary folder; the
bifurcation diagram is read from fort.7 directly (AUTO's Python reader fails under numpy 2).

Shown (issue 4, "AUTO-07p"), n = 2, mu = 0.05, zeta = beta = delta = 0.01:

* continuing the balanced state (3.6) in Omega from 4 downwards (the committed
  generated/thesis_rotating_n2/auto files, unchanged) finds the Hopf point where it loses stability,
  Omega_H1 = 1.8822393..., and further down two more (1.0936..., 1.0297...); each HB agrees to 1e-5 with
  a zero of the largest real part of the eigenvalues of the numba `jac` at the steady state (brentq),
  and those eigenvalues are a complex pair there;
* every change of the stability flag (sign of PT in fort.7) sits at a labelled bifurcation (a Hopf
  point stepped over by a too large DSMAX shows up as an unlabelled change: with DSMAX = 0.01 the third
  Hopf point, where two complex pairs interact, is missed; the template uses 0.002);
* continuing the coincident state 2+ (3.9) from Omega = 0.5 upwards and from Omega = 1.5 downwards
  finds the saddle-nodes (LP) at the critical speeds of the closed form (3.16), to 1e-5;
* func's f, dfdu (column-major) and dfdp (AUTO's PAR indices) equal the numba rhs, jac and jac_p,
  and stpnt and pvls store what the file header documents;
* a periodically forced model (single_plane_fixed_n2) gets the files of its oscillator extension, a
  periodic-orbit problem (IPS = 2): func equals the forced numba model on the oscillator's cycle, stpnt
  is the exact balanced orbit at g = 0; stage 1 (c.<model>) reaches the default g on an orbit that the
  numba model, integrated by DOP853 over one period, reproduces at every mesh point (to < 1e-6 of each
  state's peak-to-peak; measured <= 1e-7), period 2 pi / omega, oscillator on its unit circle, Floquet
  multipliers = the numba monodromy matrix's eigenvalues with 1 and exp(-2 T); stage 2 (c.<model>.2)
  restarts from stage 1's label and continues in omega from 400 to 300 rad/s;
* a model with more than 10 parameters keeps PAR(11)-PAR(14) free for AUTO and builds.
"""

from __future__ import annotations


import ctypes
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from adbgen.families.single_plane import models
from adbgen.codegen.regenerate import DEFAULT_OUT
from adbgen.codegen.render import render_model, skipped_targets
from adbgen.families.single_plane.steady_states import critical_speeds
from adbgen.codegen.spec import build as build_ir

# helpers of this folder (conftest.py puts it on sys.path)
from autorun import (AUTO_DIR, Point, auto_header, auto_toolchain, build_and_run, fortran_number, read_fort7,  # noqa: F401
                     read_fort8, read_multipliers, run_auto, unlabelled_stability_changes)
from toolchain import require_tool  # noqa: F401


MU, ZETA, BETA, DELTA = 0.05, 0.01, 0.01, 0.01
TOL = 1e-5


def rendered_auto(ir) -> dict[str, str]:
    return {Path(rel).name: text for rel, text in render_model(ir, ("auto",)).items()}


def default_auto_files(spec: models.ModelSpec) -> dict[str, str]:
    """The committed generated/<model>/auto files (what users run), or the same rendered now if absent."""
    paths = [DEFAULT_OUT / spec.name / "auto" / f for f in (f"{spec.name}.c", f"c.{spec.name}")]
    if all(path.is_file() for path in paths):
        return {path.name: path.read_text() for path in paths}
    return rendered_auto(build_ir(spec))


@pytest.fixture(scope="module")
def balanced(auto_toolchain, generated_model, tmp_path_factory):
    """(numba module, fort.7 points) of the committed balanced-state continuation of n = 2."""
    module, _, _ = generated_model("thesis_rotating", 2)
    files = default_auto_files(models.thesis_rotating(2))
    return module, run_auto(files, "thesis_rotating_n2", tmp_path_factory.mktemp("auto_balanced"))


# --- eigenvalues of the numba Jacobian ------------------------------------------------------------

def steady_state(module, y0, p):
    y = np.array(y0, float)
    for _ in range(50):
        f = module.rhs(0.0, y, p)
        if np.max(np.abs(f)) < 1e-14:
            break
        y = y - np.linalg.solve(module.jac(0.0, y, p), f)
    assert np.max(np.abs(module.rhs(0.0, y, p))) < 1e-12
    return y


def leading_eigenvalue(module, y0, omega: float) -> complex:
    p = module.params(Omega=omega, mu=MU, zeta=ZETA, beta=BETA, delta=DELTA)
    ev = np.linalg.eigvals(module.jac(0.0, steady_state(module, y0, p), p))
    return complex(ev[np.argmax(ev.real)])


def eigenvalue_crossings(module, y0, lo: float, hi: float, step: float = 0.005) -> list[float]:
    """Omega in (lo, hi) where the largest real part of the eigenvalues changes sign (brentq)."""
    g = lambda w: leading_eigenvalue(module, y0, w).real  # noqa: E731
    grid = np.arange(hi, lo, -step)
    values = [g(w) for w in grid]
    return [brentq(g, b, a, xtol=1e-13, rtol=1e-13)
            for a, b, ga, gb in zip(grid, grid[1:], values, values[1:]) if ga * gb < 0]


# --- tests ----------------------------------------------------------------------------------------

def test_balanced_state_loses_stability_at_a_hopf_point(balanced):
    module, points = balanced
    omega = [p.values["PAR(1)"] for p in points]
    start = points[0]
    assert start.values["PAR(1)"] == pytest.approx(4.0) and start.stable, start
    assert np.allclose(module.START_PARAMETERS, [4.0, BETA, DELTA, MU, ZETA])  # Omega, beta, delta, mu, zeta
    assert all(b <= a for a, b in zip(omega, omega[1:])), "the balanced branch is continued downwards"
    assert min(omega) == pytest.approx(0.5), "stops at UZSTOP Omega = 0.5"

    assert unlabelled_stability_changes(points) == [], "a stability change without a labelled bifurcation"
    special = [p for p in points if p.kind]
    assert {p.kind for p in special} == {"HB"}, special
    hopf = [p.values["PAR(1)"] for p in special]

    # the Hopf point where the balanced state loses stability: the first bifurcation from Omega = 4,
    # stable on every step before it, unstable after
    first = points.index(special[0])
    assert all(p.stable for p in points[: first + 1]) and not points[first + 1].stable
    crossings = eigenvalue_crossings(module, module.START, 0.5, 4.0)
    assert len(crossings) == len(hopf), (crossings, hopf)
    for w_auto, w_eig in zip(hopf, crossings):
        assert abs(w_auto - w_eig) < TOL, (w_auto, w_eig)
        assert abs(leading_eigenvalue(module, module.START, w_eig).imag) > 1e-3, "a complex pair crosses"
    # regression value: H1 as this project's linearisation locates it (verify's chapter-4 check and the
    # README's stability table, 1.8822393490); the independent comparison is the crossing check above
    assert hopf[0] == pytest.approx(1.88224, abs=1e-5)
    print(f"\nAUTO HB: {hopf}; eigenvalue crossings (numba jac): {crossings}; "
          f"differences {[a - b for a, b in zip(hopf, crossings)]}")


def test_a_large_dsmax_steps_over_a_hopf_point_and_the_cross_check_sees_it(balanced, tmp_path):
    """Why the stability flag is cross-checked (issue 4): DSMAX = 0.01 misses the third Hopf point."""
    _, points = balanced
    name = "thesis_rotating_n2"
    files = default_auto_files(models.thesis_rotating(2))
    files[f"c.{name}"] = re.sub(r"DSMAX = [0-9.e+-]+", "DSMAX = 0.01", files[f"c.{name}"])
    coarse = run_auto(files, name, tmp_path)
    assert len([p for p in coarse if p.kind == "HB"]) < len([p for p in points if p.kind == "HB"])
    assert unlabelled_stability_changes(coarse), "the missed Hopf point shows as an unlabelled stability change"


@pytest.mark.parametrize("omega0, which", [(0.5, 0), (1.5, 1)], ids=["from-below", "from-above"])
def test_coincident_states_fold_at_the_critical_speeds(auto_toolchain, generated_model, tmp_path, omega0, which):
    module, _, _ = generated_model("thesis_rotating", 2)
    spec = models.ModelSpec(f"coincident_n2_{which}", "thesis n = 2 from the coincident state 2+", 2,
                            models.thesis_rotating(2).system,
                            lambda s: models.balanced_start(s, 2, "coincident", Omega=omega0),
                            continuation=models.steady_continuation("Omega", stop=(0.5, 6.0)))
    ir = build_ir(spec)
    assert "coincident" in ir.start_label and ir.start_parameters[0] == omega0
    points = run_auto(rendered_auto(ir), spec.name, tmp_path)
    assert points[0].values["PAR(1)"] == pytest.approx(omega0)
    assert unlabelled_stability_changes(points) == []
    folds = [p for p in points if p.kind == "LP"]
    first = next(p for p in points if p.kind)
    assert first.kind == "LP" and len(folds) == 1, [(p.kind, p.values["PAR(1)"]) for p in points if p.kind]
    expected = critical_speeds(2, 2, MU, ZETA, DELTA)[which]
    omega_lp = folds[0].values["PAR(1)"]
    assert abs(omega_lp - expected) < TOL, (omega_lp, expected)
    # the branch exists on the start's side only: 2+ turns into 2- at the fold
    sides = {np.sign(p.values["PAR(1)"] - expected) for p in points if abs(p.values["PAR(1)"] - expected) > 1e-9}
    assert sides == {-1.0 if which == 0 else 1.0}
    print(f"\nLP from Omega = {omega0}: AUTO {omega_lp!r}, (3.16) {expected!r}, difference {omega_lp - expected:.2e}")


HARNESS = r"""
#include "{name}.c"

void h_func(const double *u, const double *par, double *f, double *dfdu, double *dfdp)
{{
    func({ndim}, u, 0, par, 2, f, dfdu, dfdp);
}}

void h_stpnt(double *u, double *par) {{ stpnt({ndim}, 0.0, u, par); }}

void h_stpnt_at(double t, double *u, double *par) {{ stpnt({ndim}, t, u, par); }}

void h_pvls(const double *u, double *par) {{ pvls({ndim}, u, par); }}
"""


def _harness(user_file: str, name: str, ndim: int, tmp_path: Path):
    """The user file's func, stpnt and pvls in a shared library (they are static: include the file)."""
    (tmp_path / f"{name}.c").write_text(user_file)
    (tmp_path / "harness.c").write_text(HARNESS.format(name=name, ndim=ndim))
    lib = tmp_path / "harness.so"
    r = subprocess.run(["gcc", "-std=gnu99", "-O1", "-Wall", "-Wextra", "-Werror", "-fPIC", "-shared",
                        "-I", str(auto_header()), "-o", str(lib), "harness.c", "-lm"],
                       cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return ctypes.CDLL(str(lib))


def _ptr(a: np.ndarray):
    return a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))


def test_func_dfdu_dfdp_stpnt_pvls_equal_the_numba_module(auto_toolchain, generated_model, tmp_path):
    module, _, _ = generated_model("thesis_rotating", 2)
    name, ndim, npar = "thesis_rotating_n2", module.N_STATES, 36
    lib = _harness(default_auto_files(models.thesis_rotating(2))[f"{name}.c"], name, ndim, tmp_path)
    rng = np.random.default_rng(4)
    for _ in range(20):
        y = rng.uniform(-1, 1, ndim)
        p = module.DEFAULTS * rng.uniform(0.5, 2.0, module.DEFAULTS.size)
        par = np.zeros(npar)
        par[: p.size] = p  # fewer than 10 parameters: PAR(k+1) = parameter k
        f, dfdu, dfdp = np.zeros(ndim), np.full(ndim * ndim, np.nan), np.full(ndim * npar, np.nan)
        lib.h_func(_ptr(y), _ptr(par), _ptr(f), _ptr(dfdu), _ptr(dfdp))
        scale = lambda a: max(1.0, float(np.max(np.abs(a))))  # noqa: E731
        assert np.max(np.abs(f - module.rhs(0.0, y, p))) <= 1e-13 * scale(f)
        J = dfdu.reshape(ndim, ndim).T  # column-major: dfdu[i + j*ndim] = dF_i/dU_j
        assert np.max(np.abs(J - module.jac(0.0, y, p))) <= 1e-13 * scale(J)
        Jp = dfdp.reshape(npar, ndim).T[:, : p.size]
        assert np.max(np.abs(Jp - module.jac_p(0.0, y, p))) <= 1e-13 * scale(Jp)
    u, par = np.zeros(ndim), np.zeros(npar)
    lib.h_stpnt(_ptr(u), _ptr(par))
    assert np.array_equal(u, module.START) and np.array_equal(par[:5], module.START_PARAMETERS)
    u = rng.uniform(-1, 1, ndim)
    lib.h_pvls(_ptr(u), _ptr(par))
    assert par[5] == pytest.approx(np.hypot(u[0], u[1]), rel=1e-15)  # PAR(6): sqrt(x^2 + y^2)


# --- periodically forced models: periodic orbits of the oscillator extension (IPS = 2) -------------

FORCED = "single_plane_fixed_n2"


def forced_auto_files(ir) -> dict[str, str]:
    """c.<model>, <model>.c and c.<model>.2 of a forced model: the committed generated/ files if
    present, else rendered now."""
    name = ir.name
    folder = DEFAULT_OUT / name / "auto"
    names = (f"{name}.c", f"c.{name}", f"c.{name}.2")
    if all((folder / f).is_file() for f in names):
        return {f: (folder / f).read_text() for f in names}
    return rendered_auto(ir)


@pytest.fixture(scope="module")
def forced(auto_toolchain, generated_model, tmp_path_factory):
    """Both stages for single_plane_fixed_n2, as the file headers say: stage 1 (c.<model>), its
    fort.8 kept as s.<model>, stage 2 (c.<model>.2, naming s.<model> itself).  Returns
    (numba module, ir, {stage: (fort.7 points, fort.8 orbits, multipliers at the last point)})."""
    module, _, _ = generated_model("single_plane_fixed", 2)
    ir = build_ir(models.single_plane_fixed(2))
    workdir = tmp_path_factory.mktemp("auto_forced")
    files = forced_auto_files(ir)
    ndim = ir.autonomous_extension.n_states
    stages = {}
    points = run_auto(files, FORCED, workdir)
    stages[1] = (points, read_fort8(workdir / "fort.8"), read_multipliers(workdir / "fort.9", ndim))
    shutil.copy(workdir / "fort.8", workdir / f"s.{FORCED}")
    log = build_and_run({}, FORCED, workdir, f"c.{FORCED}.2")
    assert "Unknown AUTO constant" not in log, log
    stages[2] = (read_fort7(workdir / "fort.7"), read_fort8(workdir / "fort.8"), read_multipliers(workdir / "fort.9", ndim))
    assert stages[2][0], f"stage 2 wrote no fort.7\n{log}"
    return module, ir, stages


def _param(module, name: str) -> int:
    return list(module.PARAM_NAMES).index(name)


def _auto_par(k: int) -> int:
    """0-based index into AUTO's PAR array of model parameter k."""
    return k if k < 10 else k + 4


def _model_parameters(module, par: np.ndarray) -> np.ndarray:
    return np.array([par[_auto_par(k)] for k in range(len(module.PARAM_NAMES))])


def test_forced_model_renders_a_periodic_orbit_problem():
    """The forced model's AUTO files are those of its oscillator extension: IPS = 2, two stages."""
    from adbgen.codegen.render import skipped_targets

    ir = build_ir(models.single_plane_fixed(2))
    assert not ir.autonomous and "auto" not in skipped_targets(ir)
    ext = ir.autonomous_extension
    assert ext.autonomous and ext.forcing_frequency == "omega" and ext.state_names[-2:] == ("osc_sin", "osc_cos")
    files = forced_auto_files(ir)
    c1, c2, user = files[f"c.{FORCED}"], files[f"c.{FORCED}.2"], files[f"{FORCED}.c"]
    g, omega = 7, 15  # PAR indices: g is parameter 6, omega parameter 10 (-> PAR(15))
    assert re.search(r"^NDIM = 10, IPS = 2, IRS = 0,", c1, re.M) and re.search(rf"^ICP = \[{g}, 11, 16\]$", c1, re.M)
    assert re.search(rf"^UZSTOP = \{{{g}: 9\.80665\}}$", c1, re.M) and re.search(r"^NTST = 40, NCOL = 4,", c1, re.M) and "JAC = 1" in c1
    assert re.search(r"^s = 'single_plane_fixed_n2'$", c2, re.M) and re.search(r"^NDIM = 10, IPS = 2, IRS = 2,", c2, re.M)
    assert re.search(rf"^ICP = \[{omega}, 11, 16\]$", c2, re.M) and re.search(rf"^UZSTOP = \{{{omega}: \[300\.0, 500\.0\]\}}$", c2, re.M)
    assert "u[8] = sin(6.283185307179586 * t);" in user and "par[10] = 6.283185307179586 / par[14];" in user
    # autonomous models have one stage: the stage-2 template renders nothing for them
    from adbgen.codegen import targets
    from adbgen.codegen.render import context, environment
    thesis = build_ir(models.thesis_rotating(2))
    ctx = context(thesis, targets.get("auto"))
    assert environment().get_template("auto/constants_stage2.j2").render(**ctx) == ""
    one_stage = render_model(thesis, ("auto",))
    assert "thesis_rotating_n2/auto/c.thesis_rotating_n2.2" not in one_stage
    # ... but they do get their one stage: an autonomous model with a start is never skipped
    assert "auto" not in skipped_targets(thesis)
    assert {"thesis_rotating_n2/auto/c.thesis_rotating_n2", "thesis_rotating_n2/auto/thesis_rotating_n2.c"} <= set(one_stage)


def test_forced_func_and_stpnt_equal_the_forced_numba_model_on_the_cycle(auto_toolchain, generated_model, tmp_path):
    """On the oscillator's cycle (osc = (sin, cos)(omega t)) the extension's F, dF/dU and dF/dPAR are the
    forced model's rhs, jac and jac_p at time t (but d/d omega, which the oscillator carries), and its
    own rows are the cycle's derivative; stpnt is the exact orbit at AUTO's time t."""
    module, _, _ = generated_model("single_plane_fixed", 2)
    ir = build_ir(models.single_plane_fixed(2))
    ndim, npar, n = ir.autonomous_extension.n_states, 36, module.N_STATES
    lib = _harness(forced_auto_files(ir)[f"{FORCED}.c"], FORCED, ndim, tmp_path)
    lib.h_stpnt_at.argtypes = [ctypes.c_double, ctypes.POINTER(ctypes.c_double), ctypes.POINTER(ctypes.c_double)]
    rng = np.random.default_rng(40)
    k_omega = _param(module, "omega")
    for _ in range(20):
        p = module.DEFAULTS * rng.uniform(0.5, 2.0, module.DEFAULTS.size)
        t = rng.uniform(0, 0.1)
        w = p[k_omega]
        y = rng.uniform(-1, 1, n) * np.r_[np.full(2, 1e-3), np.ones(n - 2)]
        u = np.r_[y, np.sin(w * t), np.cos(w * t)]
        par = np.zeros(npar)
        for k, v in enumerate(p):
            par[_auto_par(k)] = v
        f, dfdu, dfdp = np.zeros(ndim), np.full(ndim * ndim, np.nan), np.full(ndim * npar, np.nan)
        lib.h_func(_ptr(u), _ptr(par), _ptr(f), _ptr(dfdu), _ptr(dfdp))
        scale = lambda a: max(1.0, float(np.max(np.abs(a))))  # noqa: E731
        rhs = module.rhs(t, y, p)
        assert np.max(np.abs(f[:n] - rhs)) <= 1e-12 * scale(rhs)
        assert np.allclose(f[n:], [w * np.cos(w * t), -w * np.sin(w * t)], rtol=1e-13, atol=1e-13 * w)
        J = dfdu.reshape(ndim, ndim).T
        jac = module.jac(t, y, p)
        assert np.max(np.abs(J[:n, :n] - jac)) <= 1e-12 * scale(jac)
        Jp = dfdp.reshape(npar, ndim).T
        jac_p = module.jac_p(t, y, p)
        others = [k for k in range(p.size) if k != k_omega]
        assert np.max(np.abs(Jp[:n, [_auto_par(k) for k in others]] - jac_p[:, others])) <= 1e-12 * scale(jac_p)
    for t in (0.0, 0.25, 0.3, 1.0):
        u, par = np.full(ndim, np.nan), np.zeros(npar)
        lib.h_stpnt_at(t, _ptr(u), _ptr(par))
        assert np.array_equal(u[:n], ir.autonomous_extension.start[:n])
        assert u[n:] == pytest.approx([np.sin(2 * np.pi * t), np.cos(2 * np.pi * t)], abs=1e-15)
        start_p = np.array(ir.autonomous_extension.start_parameters)
        assert np.array_equal(_model_parameters(module, par), start_p) and start_p[_param(module, "g")] == 0.0
        assert par[10] == pytest.approx(2 * np.pi / start_p[k_omega], rel=1e-15)
    # the start is an exact periodic orbit of the forced model: zero rhs at g = 0 (rounding only, against
    # terms of the order of the unbalance's eps omega^2 = 80 m/s^2)
    start_p = np.array(ir.autonomous_extension.start_parameters)
    scale = start_p[_param(module, "eps")] * start_p[k_omega] ** 2
    for t in (0.0, 0.3, 1e-3):
        assert np.max(np.abs(module.rhs(t, np.array(ir.autonomous_extension.start[:n]), start_p))) < 1e-13 * scale


def test_forced_stage1_reaches_the_default_gravity_on_the_forced_models_orbit(forced):
    """Stage 1 converges from the exact orbit at g = 0 and ends on label 2 (UZ) at the default g; that
    orbit, integrated as the forced numba model (DOP853) from its point at AUTO time 0, returns the
    AUTO orbit at every mesh point; period 2 pi / omega; the oscillator on its unit circle; Floquet
    multipliers: 1, exp(-2 T) (the oscillator) and the forced model's monodromy eigenvalues."""
    from scipy.integrate import solve_ivp

    module, ir, stages = forced
    points, orbits, multipliers = stages[1]
    kg, kw = _param(module, "g"), _param(module, "omega")
    g_default, omega = module.DEFAULTS[kg], module.DEFAULTS[kw]
    assert points[0].values["PAR(7)"] == 0.0 and abs(points[0].ty) == 9 and points[0].label == 1
    end = points[-1]
    assert end.ty == -4 and end.label == 2, "stage 1 ends on the UZSTOP label 2"
    assert end.values["PAR(7)"] == pytest.approx(g_default, abs=1e-6)
    assert all(p.stable for p in points), "the balanced orbit stays stable from g = 0 to the default"
    assert all(abs(p.values["PERIOD"] - 2 * np.pi / omega) < 1e-10 for p in points)

    orbit = next(o for o in orbits if o.label == 2)
    n = module.N_STATES
    p = _model_parameters(module, orbit.par)
    assert p[kg] == pytest.approx(g_default, abs=1e-6) and p[kw] == omega
    T = orbit.par[10]
    assert abs(T - 2 * np.pi / omega) < 1e-10
    s, c = orbit.u[:, n], orbit.u[:, n + 1]
    assert np.max(np.abs(s**2 + c**2 - 1)) < 1e-8
    t0 = np.arctan2(s[0], c[0]) / omega  # the oscillator's phase at AUTO time 0, as forced-model time
    times = t0 + T * orbit.t
    assert np.max(np.abs(s - np.sin(omega * times))) < 1e-7 and np.max(np.abs(c - np.cos(omega * times))) < 1e-7
    sol = solve_ivp(lambda t, y: module.rhs(t, y, p), (times[0], times[-1]), orbit.u[0, :n], method="DOP853",
                    rtol=1e-10, atol=1e-14, t_eval=times)
    assert sol.success
    amplitude = np.ptp(orbit.u[:, :n], axis=0)
    assert np.all(amplitude > 0), "every state moves at the default g"
    rel = np.max(np.abs(sol.y.T - orbit.u[:, :n]), axis=0) / amplitude
    assert np.max(rel) < 1e-6, dict(zip(module.STATE_NAMES, rel))

    # Floquet multipliers (fort.9): the forced model's monodromy matrix over one period (variational
    # equations along the numba orbit), plus the extension's 1 (phase) and exp(-2 T) (oscillator)
    def variational(t, z):
        y, phi = z[:n], z[n:].reshape(n, n)
        return np.r_[module.rhs(t, y, p), (module.jac(t, y, p) @ phi).ravel()]
    mono = solve_ivp(variational, (times[0], times[-1]), np.r_[orbit.u[0, :n], np.eye(n).ravel()], method="DOP853",
                     rtol=1e-10, atol=1e-12).y[n:, -1].reshape(n, n)
    expected = list(np.linalg.eigvals(mono)) + [1.0, np.exp(-2 * T)]
    remaining = list(multipliers)
    worst = 0.0
    for mu in expected:
        k = int(np.argmin([abs(mu - m) for m in remaining]))
        worst = max(worst, abs(mu - remaining.pop(k)))
    assert worst < 1e-4, (multipliers, expected)
    assert np.max(np.abs(np.linalg.eigvals(mono))) < 1, "stable: every multiplier of the forced model inside the unit circle"
    print(f"\nstage 1: {len(points)} steps to g = {end.values['PAR(7)']!r}; orbit vs numba DOP853, max |diff|/ptp "
          f"per state {np.array2string(rel, precision=1)}; |T - 2 pi/omega| = {abs(T - 2 * np.pi / omega):.1e}; "
          f"max |s^2 + c^2 - 1| = {np.max(np.abs(s**2 + c**2 - 1)):.1e}; multipliers {np.round(multipliers, 5)} "
          f"(max |AUTO - monodromy| {worst:.1e})")


def test_forced_stage2_restarts_and_continues_in_omega(forced):
    """Stage 2 restarts from stage 1's label 2 (read from s.<model>) and continues in omega (PAR(15))
    from 400 down to UZSTOP 300 rad/s, the period following 2 pi / omega, g staying at its default."""
    module, ir, stages = forced
    points, orbits, multipliers = stages[2]
    kg = _param(module, "g")
    omega = [p.values["PAR(15)"] for p in points]
    assert omega[0] == pytest.approx(module.DEFAULTS[_param(module, "omega")], abs=1e-9)
    assert all(b < a for a, b in zip(omega, omega[1:])), "omega decreases along the branch"
    assert points[-1].ty == -4 and points[-1].values["PAR(15)"] == pytest.approx(300.0, abs=1e-6)
    assert len(points) > 10
    for p in points:
        assert abs(p.values["PERIOD"] - 2 * np.pi / p.values["PAR(15)"]) < 1e-10, p
    end = next(o for o in orbits if o.label == points[-1].label)
    assert end.par[_auto_par(kg)] == pytest.approx(module.DEFAULTS[kg], abs=1e-6)
    assert abs(end.par[10] - 2 * np.pi / 300.0) < 1e-10
    assert all(p.stable for p in points), "the balanced orbit stays stable between 400 and 300 rad/s"
    print(f"\nstage 2: {len(points)} steps, omega {omega[0]!r} -> {omega[-1]!r}, period {float(end.par[10])!r}, "
          f"max |T - 2 pi/omega| {max(abs(p.values['PERIOD'] - 2 * np.pi / p.values['PAR(15)']) for p in points):.1e}; "
          f"multipliers at 300 rad/s {np.round(multipliers, 5)}")


def test_more_than_ten_parameters_skip_autos_own_par_slots(auto_toolchain, tmp_path):
    """Unequal balls keep the dimensional rotating-frame model (12 parameters for n = 3):
    parameters 10 and 11 go to PAR(15), PAR(16); PAR(11)-PAR(14) stay AUTO's; it builds."""
    from adbgen.families.single_plane.scene import Scene

    spec = models.for_scene(Scene.from_mapping({"n": 3, "ball_mass": [0.05, 0.04, 0.03]}), "unequal_n3")
    ir = build_ir(spec)
    assert ir.autonomous and len(ir.parameters) == 12
    # issue 24: a scene's unequal balls get the balanced state weighted by their masses as START
    assert ir.start is not None and "masses" in ir.start_label and "auto" not in skipped_targets(ir)
    files = rendered_auto(ir)
    user = files["unequal_n3.c"]
    name10, name11 = ir.parameter_names[10], ir.parameter_names[11]
    assert re.search(rf"PAR\(15\)\s+par\[14\]\s+{name10}", user) and re.search(rf"PAR\(16\)\s+par\[15\]\s+{name11}", user)
    assert not re.search(r"par\[1[0-3]\]", user)
    log = build_and_run(files, "unequal_n3", tmp_path)
    assert (tmp_path / "unequal_n3.exe").is_file(), log
