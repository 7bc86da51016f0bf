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
# # 2. Dimensionless form, rotating frame, first-order form, Jacobi integral
#
# Thesis ch. 2.2-2.3 and Appendix A.  From the fixed-frame equations of notebook 1 (equal balls,
# constant speed (2.14), isotropic support (2.18)): the scalings (2.15)-(2.19) give (2.20)-(2.22); the
# rotating axes (2.23)-(2.24) give the autonomous system (2.25)-(2.27); Appendix A writes it in first
# order without ever inverting the mass matrix.  Two errata of the thesis are shown on the way (each
# asserted both ways: the corrected form is an identity, the printed one is not).

# %%
import matplotlib.pyplot as plt
import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from adbgen.core.numeric import NumericFirstOrder
from adbgen.families.single_plane import verify
from adbgen.families.single_plane.jacobi import rotating_lagrangian
from adbgen.families.single_plane.reductions import first_order, nondimensionalise, rotating_frame, scaling
from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane.symbols import G, Omega, beta, delta, mu, t, zeta
from adbgen.notebooks import check, compare, latex, show
from adbgen.references import thesis

# %% [markdown]
# ## The scalings (2.15)-(2.19)
# X = R Xbar, t = tbar / omega_n (2.15), (2.17): k = M omega_n^2; mu = m/M, Omega = omega/omega_n,
# delta = eps/R, G = g/(eps omega_n^2) (2.16); zeta = c/(2 sqrt(k M)), beta = D/(m R^2 omega_n) (2.19).
# The substitution the library applies (each dimensional symbol in terms of the dimensionless ones;
# after it no dimensional symbol is left, which `nondimensionalise` checks):

# %%
scene = Scene(n=2, gravity=True)
sub, rows = scaling(scene)
for old, new in sub.items():
    if not old.name.endswith("dot"):
        show(f"{old}", new, "thesis (2.15)-(2.19)", lhs=latex(old))

# %% [markdown]
# ## Non-dimensional fixed frame (2.20)-(2.22), and the erratum in (2.21)
# Each derived row (divided by M R omega_n^2 for X, Y and by m R^2 omega_n^2 for the balls) against the
# thesis.  With gravity the printed (2.21) has -G(1 + n mu); the scalings give -delta G (1 + n mu)
# (as (2.22) has delta G).

# %%
nondim = nondimensionalise(scene)
right = thesis.nondimensional(2, mu, Omega, zeta, beta, delta, G, t)
misprinted = thesis.nondimensional(2, mu, Omega, zeta, beta, delta, G, t, printed=True)
numbers = {"X": "(2.20)", "Y": "(2.21), corrected", "phi_1": "(2.22), i = 1", "phi_2": "(2.22), i = 2"}
for name, reference in right.items():
    compare(f"row {name}", nondim.residual(nondim.index(name)), reference, f"thesis {numbers[name]}")
compare("row Y against (2.21) as printed", nondim.residual(nondim.index("Y")), misprinted["Y"],
        "thesis (2.21), printed", identical=False)

# %% [markdown]
# ## Rotating frame (2.23)-(2.27)
# X = x cos(Omega t) - y sin(Omega t), Y = x sin(Omega t) + y cos(Omega t); the rotor rows projected on the
# rotating axes.  With G = 0 no explicit t is left: the system is autonomous (checked).

# %%
rot = rotating_frame(Scene(n=2))
printed = thesis.rotating_frame(2, mu, Omega, zeta, beta, delta)
numbers = {"x": "(2.25), first row", "y": "(2.25), second row", "phi_1": "(2.26), i = 1", "phi_2": "(2.26), i = 2"}
for name, reference in printed.items():
    compare(f"row {name}", rot.residual(rot.index(name)), reference, f"thesis {numbers[name]}, K of (2.27)")
assert all(t not in f.free_symbols for f in rot.forcing)
for n in (3, 4):
    check(verify.rotating(n))
    check(verify.nondimensional(n))

# %% [markdown]
# A second route: transform the *Lagrangian* (psi = omega t, the scalings, the rotating axes) and apply
# Lagrange's equations anew.  It gives the same equations (ball rows up to the factor mu): the reductions
# commute with Lagrange's equations.

# %%
check(verify.two_routes(2))
check(verify.two_routes(3))

# %% [markdown]
# ## First-order form, Appendix A, and the erratum in (A.12)-(A.13)
# States (A.1)-(A.2): the thesis' u, v, theta_i are x', y', phi_i' here.  The ball rows (2.26) give each
# phi_i'' in terms of x'', y'' (A.6); substituting into (2.25) leaves a 2 x 2 system
# [[a, b], [b, c]] (x'', y'') = (f, g), the Schur complement of the diagonal ball block, solved by
# (A.7)-(A.8).  The printed (A.12)-(A.13) break a line so that two terms of f appear on g's line; read
# literally, f is wrong.

# %%
fo = first_order(rot)
A = thesis.appendix_a(2, mu, Omega, zeta, beta, delta)
literal = thesis.appendix_a(2, mu, Omega, zeta, beta, delta, printed=True)
S, rhs = fo.solve.schur, fo.solve.rhs
show("Schur complement", S, "thesis (A.9)-(A.11)", lhs=r"\begin{pmatrix} a & b \\ b & c \end{pmatrix}")
for label, mine, ref, number in (("a", S[0, 0], A["a"], "(A.9)"), ("b", S[0, 1], A["b"], "(A.10)"),
                                 ("c", S[1, 1], A["c"], "(A.11)"), ("f", rhs[0], A["f"], "(A.12), corrected"),
                                 ("g", rhs[1], A["g"], "(A.13), corrected")):
    compare(label, mine - ref, 0, f"thesis {number}")
compare("f against (A.12) read line by line as printed", rhs[0], literal["f"], "thesis (A.12), printed",
        identical=False)
for i, accel in enumerate(fo.solve.leaf_accel):
    compare(f"G_{3 + i} (ball {i + 1})", accel, A[f"G_{3 + i}"], "thesis (A.6)")
# (A.7)-(A.8) in full, and everything again for n = 3 (a, b, c, f, g, each G_i, the literal reading):
check(verify.appendix_a(2))
check(verify.appendix_a(3, full_solve_up_to=0))
print("states:", fo.state_names)

# %% [markdown]
# ## The Jacobi integral
# With zeta = beta = 0 the rotating-frame Lagrangian does not depend on t, so h = sum q'_k dL/dq'_k - L is
# conserved; with damping dh/dt = -q' . dF/dq' (the Rayleigh power).  First exactly:

# %%
rl = rotating_lagrangian(Scene(n=2))
h = rl.jacobi_integral()
show("Jacobi integral", sp.collect(h, [mu], evaluate=True), "rotating frame (2.25)-(2.27)", lhs="h")
check(verify.jacobi(2))
check(verify.jacobi(3))

# %% [markdown]
# Then along trajectories of the first-order system (evaluated from the symbolic structured form by
# `NumericFirstOrder`, DOP853 at rtol 1e-12): undamped, h stays constant to 1e-9 relative over 50 time
# units; damped (zeta = 0.05, beta = 0.02), h changes, and the change equals minus the Rayleigh work.

# %%
f = NumericFirstOrder(fo)
states = [sp.Symbol(nm, real=True) for nm in f.state_names]
params = [q.symbol for q in fo.parameters]
h_num = sp.lambdify([states, params], h)
power = sp.lambdify([states, params], sum(c.qd * sp.diff(rl.F, c.qd) for c in rl.eom.coordinates))
rng = np.random.default_rng(3)
y0 = np.concatenate([rng.normal(0, 0.05, 2), rng.uniform(-np.pi, np.pi, 2), rng.normal(0, 0.1, 4)])
fig, ax = plt.subplots(figsize=(7, 3))
for label, over in (("undamped", {"zeta": 0.0, "beta": 0.0}), ("zeta = 0.05, beta = 0.02", {"zeta": 0.05, "beta": 0.02})):
    p = f.defaults.copy()
    for name, v in over.items():
        p[f.parameter_names.index(name)] = v
    rhs_aug = lambda tt, z, p=p: np.r_[f(tt, z[:-1], p), -power(z[:-1], p)]  # noqa: E731  (last state: -work)
    sol = solve_ivp(rhs_aug, (0, 50), np.r_[y0, 0.0], args=(), method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True)
    assert sol.success
    hs = np.array([h_num(sol.y[:-1, i], p) for i in range(sol.y.shape[1])])
    drift = np.abs(hs - hs[0] - sol.y[-1]) / abs(hs[0])  # h(t) - h(0) + integral of the power
    print(f"{label}: h(0) = {hs[0]:.6g}, h(50) - h(0) = {hs[-1] - hs[0]:.3e}, largest |h - h(0) + work| / |h(0)| = {drift.max():.1e}")
    assert drift.max() <= 1e-9
    ax.plot(sol.t, (hs - hs[0]) / abs(hs[0]), label=label)
ax.set_xlabel("t (dimensionless)")
ax.set_ylabel(r"$(h(t) - h(0)) / |h(0)|$")
ax.set_title("Jacobi integral along a trajectory, n = 2", fontsize=10)
ax.legend(fontsize=8)
fig.tight_layout()
plt.show()
