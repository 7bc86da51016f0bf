# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 6. From the first-order form to code, and the code in use
#
# Part 1 lowers the thesis' first-order system (Appendix A) to the intermediate form that every target
# (numba, C, CVODE, AUTO-07p) is rendered from, and checks it.  Part 2 does what a user does: describe a
# scene (five unequal balls), generate its smallest exact model into a folder, load it with the analysis
# layer (`adbgen.analysis`: numpy, numba and the compiled engines, no SymPy), simulate a transient, call
# the emitted C library directly, and find Hopf points by continuation on the generated code and by
# AUTO-07p on the emitted files.

# %%
import contextlib
import ctypes
import io
import subprocess
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import sympy as sp

from adbgen.analysis import auto07p, equilibrium_scan, steady
from adbgen.analysis.loading import load_model
from adbgen.analysis.simulate import amplitude, simulate
from adbgen.cli import main as adbgen
from adbgen.codegen.plain_python import compile_program
from adbgen.codegen.render import render_model, source_hash
from adbgen.codegen.spec import build
from adbgen.families.single_plane import models
from adbgen.notebooks import show

# %% [markdown]
# ## Part 1: the intermediate form
# ### The model and its mass-matrix structure
# Two rotor coordinates (x, y) form the Schur core; each ball's row couples only to them, so the ball
# block of M is diagonal.  The intermediate form records the pattern.

# %%
spec = models.thesis_rotating(2)
system = spec.system()
ir = build(spec)
print("states:", ir.state_names)
print("parameters:", ir.parameter_names)
print("core:", ir.core, " leaves:", ir.leaves)
print("nonzero M entries:", ir.mass_pattern)
balls = [ir.state_names.index(name) for name in ir.leaves]
assert all((i, j) not in ir.mass_pattern for i in balls for j in balls if i != j)

# %% [markdown]
# ### The rhs, in the loop form every target prints
# Each ball's block (its row of M and of the forcing: B_i, C_i, D_i, f_i) is kept once, with the ball's
# angle, rate and parameters as loop inputs (`codegen/balls.py` takes ball 1's block and checks
# symbolically that it equals every ball's).  The Schur complement S of the rotor core and its right-hand
# side g are accumulated over the balls in one loop, the 2 x 2 core is solved by an unrolled LU, and a
# second loop back-substitutes the ball accelerations (A.6).  No inverse of M is ever formed.  This is the
# function the numba target prints (the C, CVODE and AUTO-07p targets print the same kernel in C):

# %%
from adbgen.codegen.plain_python import python_source

print(python_source(ir, "rhs", "rhs"))

# %% [markdown]
# The same model unrolled (one block of statements per ball, `adbgen regenerate --form unrolled`), as
# mathematics: the statements after the common subexpressions.

# %%
for lhs, rhs in ir.as_unrolled().rhs.assignments:
    if not lhs.name.startswith("w_"):
        show(str(lhs), rhs, "", lhs=sp.latex(lhs))

# %% [markdown]
# ### It equals the closed form
# Cramer's rule on the whole system (what (A.7)-(A.8) write out) is independent of the structured
# lowering; both agree to rounding at random points.

# %%
closed = sp.lambdify((list(system.states), [p.symbol for p in system.parameters]), system.rhs(), modules="math")
program = compile_program(ir, "rhs")
rng = np.random.default_rng(0)
worst = 0.0
for _ in range(20):
    y = rng.uniform(-1, 1, ir.n_states)
    p = np.array([q.default for q in ir.parameters]) * rng.uniform(0.5, 2, len(ir.parameters))
    a, b = np.asarray(program(0.0, y, p)), np.asarray(closed(y, p))
    assert np.allclose(a, b, rtol=1e-12, atol=1e-14)
    worst = max(worst, np.max(np.abs(a - b)) / np.max(np.abs(b)))
print(f"rhs program = closed form at 20 random points (largest difference {worst:.1e} of max |rhs|)")

# %% [markdown]
# ### The printed code does not grow with n; the operations executed grow linearly
# The loop form prints the per-ball block once, so its operation count (a loop body counted once) is the
# same for every n >= 2 (with one ball the common-subexpression elimination pairs a few terms differently).  Unrolled, one more ball adds about the same number of operations (common-subexpression
# elimination makes the increments differ by a few): what the loops execute, nothing grows like n^2.

# %%
ns = (1, 2, 3, 4, 6)
built = {n: build(models.thesis_rotating(n)) for n in ns}
printed = {n: built[n].count_ops("rhs") for n in ns}
ops = {n: built[n].as_unrolled().rhs.count_ops() for n in ns}
slope, intercept = np.polyfit(ns, [ops[n] for n in ns], 1)
deviation = max(abs(ops[n] - (intercept + slope * n)) / ops[n] for n in ns)
print("loop form, printed rhs operations:", printed)
print("unrolled rhs operations:", ops)
print(f"unrolled ops ~ {intercept:.0f} + {slope:.1f} n, largest deviation from the line {100 * deviation:.1f} %")
assert len({printed[n] for n in ns if n >= 2}) == 1 and all(built[n].form == "loops" for n in ns)
assert deviation < 0.05
fig, ax = plt.subplots(figsize=(4.5, 3))
ax.plot(ns, [ops[n] for n in ns], "ko", label="unrolled")
ax.plot(ns, intercept + slope * np.array(ns), "C0-", lw=0.8, label=f"{intercept:.0f} + {slope:.1f} n")
ax.plot(ns, [printed[n] for n in ns], "s", color="C1", label="loop form (printed)")
ax.set_xlabel("balls n")
ax.set_ylabel("operations in rhs")
ax.legend(fontsize=8)
fig.tight_layout()
plt.show()

# %% [markdown]
# ### The Jacobian by the same structure, and rendering
# Differentiating M q'' = f at fixed accelerations gives M d(q'')/dy = d(f - M q'')/dy: sparse derivative
# expressions, each column solved with the factorised Schur complement.  It equals central differences of
# the rhs.  Every target's files come from the same programs; the source hash in each header covers the
# intermediate form and the templates.

# %%
jac = compile_program(ir, "jac")
y = rng.uniform(-1, 1, ir.n_states)
p = np.array([q.default for q in ir.parameters])
J = np.asarray(jac(0.0, y, p)).reshape(ir.n_states, ir.n_states)
h = 1e-6
fd = np.column_stack([(np.asarray(program(0.0, y + h * e, p)) - np.asarray(program(0.0, y - h * e, p))) / (2 * h)
                      for e in np.eye(ir.n_states)])
err = np.max(np.abs(J - fd)) / np.max(np.abs(J))
print(f"jac = central differences of rhs to {err:.1e}")
assert err < 1e-6
files = render_model(ir)
print(sorted(files))
assert all(source_hash(ir) in text for text in files.values())

# %% [markdown]
# ## Part 2: a scene, its generated model, and the analysis layer
# ### Regenerate a model for a scene
# Five unequal balls (50, 45, 40, 35, 30 g) on the thesis' rotor (M = 1 kg, k = 1e4 N/m, R = 5 cm,
# eps = 0.5 mm, omega = 400 rad/s).  The scene is isotropic, at constant speed, without gravity, so its
# smallest exact model is the autonomous rotating frame with dimensional parameters (unequal balls rule
# out the thesis' scaling (2.14)).  `adbgen regenerate --scene` derives it, runs the family's reduction
# checks, and writes every target into a temporary folder.

# %%
work = Path(tempfile.mkdtemp(prefix="adbgen-nb06-"))
scene_file = work / "five_balls.toml"
scene_file.write_text('n = 5\nball_mass = [0.05, 0.045, 0.04, 0.035, 0.03]\n')
with contextlib.redirect_stdout(io.StringIO()):  # its summary names the temporary folder
    assert adbgen(["regenerate", "--scene", str(scene_file), "--name", "five_balls", "--out", str(work / "gen"), "--quiet"]) == 0
print(sorted(f.name for f in (work / "gen" / "five_balls").iterdir() if f.is_file()))
model = load_model(work / "gen" / "five_balls")
print(model.name, "| states:", model.state_names)
print("parameters:", {k: float(v) for k, v in zip(model.param_names, model.params())})
print("reference:", model.module.REFERENCE)

# %% [markdown]
# ### A transient
# The balls start spread round the race; the default engine (CyRK's DOP853 on the emitted C library)
# integrates 5 s.  The rotor's whirl r = sqrt(x^2 + y^2) grows through the transient and decays as the
# balls find the balancing positions.  The first second again by SciPy's DOP853 on the numba module (a
# different integrator on the other target, a Python call per step) ends at the same state.

# %%
y0 = {f"phi_{i + 1}": a for i, a in enumerate([0.3, 1.5, 2.9, 4.2, 5.5])}
run = simulate(model, None, y0, t_end=5.0, rtol=1e-10, atol=1e-12)
print(f"{run.engine}: status {run.status}, r_max = {run.r_max:.4e} m, t_dec = {run.t_dec:.4f} s "
      f"(r below the thesis' threshold {run.threshold:g} from then on), {run.n_rhs} rhs evaluations")
assert run.ok and run.t_dec is not None and run.t_dec < 5.0
first = simulate(model, None, y0, t_end=1.0, rtol=1e-10, atol=1e-12, samples=11)
ref = simulate(model, None, y0, t_end=1.0, rtol=1e-10, atol=1e-12, engine="scipy-dop853", samples=11)
diff = np.max(np.abs(first.y_end - ref.y_end) / np.maximum(1.0, np.abs(ref.y_end)))
print(f"state at t = 1 s, {first.engine} vs {ref.engine}: largest difference {diff:.1e}")
assert diff < 1e-6
masses = np.array([model.params()[model.param_names.index(f"m_{i + 1}")] for i in range(5)])

fig, axes = plt.subplots(1, 2, figsize=(10, 3.2))
axes[0].semilogy(run.t, amplitude(model, run.y), "k-", lw=0.8)
axes[0].axhline(run.threshold, color="C3", lw=0.6)
axes[0].set_xlabel("t (s)")
axes[0].set_ylabel("r (m)")
axes[0].set_title(f"rotor whirl; t_dec = {run.t_dec:.3f} s", fontsize=9)
for i in range(5):
    axes[1].plot(run.t, np.unwrap(run.y[model.index(f"phi_{i + 1}")]), lw=0.8, label=f"$\\phi_{i + 1}$, m = {masses[i] * 1e3:.0f} g")
axes[1].set_xlabel("t (s)")
axes[1].set_ylabel("ball angle (rad)")
axes[1].legend(fontsize=7, ncol=2)
fig.tight_layout()
plt.show()

# %% [markdown]
# ### Its stability
# Newton on the generated rhs/jac from the end state, then the eigenvalues of the generated Jacobian.  The
# balanced states of five balls form a 3-dimensional continuum (two conditions on five angles): three
# eigenvalues are zero along it (reported apart), the transverse spectrum decides.

# %%
state = steady.refine(model, model.params(), run.y_end)
print(f"classification: {state.classification}, family dimension {state.to_json()['family_dimension']}")
print("neutral eigenvalues (along the family):", np.array2string(state.neutral, precision=1))
print("transverse eigenvalues:", np.array2string(state.transverse, precision=4))
assert len(state.neutral) == 3 and np.max(np.abs(state.neutral)) < 1e-6 and np.all(state.transverse.real < 0)
assert state.classification == "stable" and state.to_json()["family_dimension"] == 3
# It balances the rotor: x = y = 0 and sum m_i R e^{i phi_i} = -M eps (the mass-weighted (3.6)).
par = dict(zip(model.param_names, model.params()))
phis = np.array([state.y[model.index(f"phi_{i + 1}")] for i in range(5)])
moment = np.sum(masses * par["R"] * np.exp(1j * phis)) + par["M"] * par["eps"]
print(f"x, y = {state.y[0]:.1e}, {state.y[1]:.1e} m; |sum m_i R e^(i phi_i) + M eps| = {abs(moment):.1e} kg m "
      f"(M eps = {par['M'] * par['eps']:.1e})")
assert abs(moment) < 1e-9 * par["M"] * par["eps"] and max(abs(state.y[0]), abs(state.y[1])) < 1e-12

# %% [markdown]
# ### Calling the C library directly
# The emitted `five_balls.c` is plain C99 with no dependencies: compiled here by gcc into a shared library
# and called through ctypes, its rhs and Jacobian equal the numba module's at random states.

# %%
lib_path = work / "libfive_balls.so"
subprocess.run(["gcc", "-std=c99", "-O2", "-shared", "-fPIC", "-o", str(lib_path), str(model.c_source())], check=True)
lib = ctypes.CDLL(str(lib_path))
vec = ctypes.POINTER(ctypes.c_double)
for fn in (lib.five_balls_rhs, lib.five_balls_jac):
    fn.argtypes = [ctypes.c_double, vec, vec, vec]
    fn.restype = None


def c_call(fn, y, p, size):
    out = np.zeros(size)
    fn(0.0, y.ctypes.data_as(vec), p.ctypes.data_as(vec), out.ctypes.data_as(vec))
    return out


N = model.n_states
worst = 0.0
for _ in range(200):
    y = np.concatenate([rng.normal(0, 1e-3, 2), rng.uniform(-np.pi, np.pi, 5), rng.normal(0, 1, N - 7)])
    p = model.params() * rng.uniform(0.5, 2.0, model.n_params)
    for fn, py, size in ((lib.five_balls_rhs, model.module.rhs, N), (lib.five_balls_jac, model.module.jac, N * N)):
        c_out, nb_out = c_call(fn, y, p, size), np.ravel(py(0.0, y, p))
        worst = max(worst, np.max(np.abs(c_out - nb_out)) / np.max(np.abs(nb_out)))
print(f"C (ctypes) vs numba, rhs and jac at 200 random points: largest relative difference {worst:.1e}")
assert worst <= 1e-13

# %% [markdown]
# ### Hopf points: continuation on the generated code, and AUTO-07p on the emitted files
# The thesis model with three balls (`generated/thesis_rotating_n3`, parameters (5.1)), its balanced
# state 1 followed in Omega from 4 down to 1.5.  First by the analysis layer's pseudo-arclength
# continuation on the generated rhs/jac (stability from the transverse spectrum, each change located by
# root finding); then by AUTO-07p, built from the model's emitted `auto/` files with gfortran and run
# with AUTO's own make runner.  The thesis (Fig. 4.6(a)): with three balls state 1 is stable only above
# the first Hopf point H1.

# %%
thesis3 = load_model("thesis_rotating_n3")
p0 = np.array(thesis3.module.START_PARAMETERS, float)
y_start = np.array(thesis3.module.START, float)
scan = equilibrium_scan.scan(thesis3, p0, y_start, "Omega", 4.0, 1.5)
for b in scan.points:
    print(f"{b.kind} at Omega = {b.value:.10f}, frequency {b.frequency:.7f}, {b.direction}")
print("stable for Omega in", [tuple(round(v, 7) for v in iv) for iv in scan.stable_intervals])
hopf = [b.value for b in scan.points if b.kind == "hopf"]
assert np.allclose(hopf, [1.8753674503, 1.7124468663, 1.6127672512], atol=1e-8)  # the README's table

assert not auto07p.missing_tools(), auto07p.missing_tools()
run_auto = auto07p.continue_one(thesis3, "Omega", to=1.5)
labelled = [(pt.type, pt.values["PAR(1)"] if "PAR(1)" in pt.values else None) for pt in run_auto.points if pt.label]
print("AUTO-07p labelled points:", labelled)
hb = sorted((v for kind, v in labelled if kind == "HB"), reverse=True)
print("HB - scan:", [f"{a - b:.1e}" for a, b in zip(hb, hopf)])
assert len(hb) == 3 and np.allclose(hb, hopf, atol=1e-7)

# The transverse spectrum along the branch: its largest real parts cross zero at the Hopf points.
branch_Om = np.array([b.lam for b in scan.branch])
real_parts = np.array([np.sort(b.spectrum.real)[::-1][:6] for b in scan.branch])
fig, ax = plt.subplots(figsize=(7, 3.2))
ax.plot(branch_Om, real_parts, "k-", lw=0.7)
ax.axhline(0, color="0.5", lw=0.6)
ax.plot(hopf, np.zeros(3), "o", mfc="none", color="C0", ms=9, label="Hopf (continuation)")
ax.plot(hb, np.zeros(3), "x", color="C3", ms=7, label="HB (AUTO-07p)")
ax.set_ylim(-0.03, 0.02)
ax.set_xlabel(r"$\Omega$")
ax.set_ylabel(r"Re $\lambda$ (six largest)")
ax.set_title("state 1 of the thesis model, n = 3, (5.1): transverse spectrum along Omega", fontsize=9)
ax.legend(fontsize=7)
fig.tight_layout()
plt.show()
