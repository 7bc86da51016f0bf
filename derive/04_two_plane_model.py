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
# # 4. The two-plane rigid rotor
#
# Rodrigues, Champneys, Friswell & Wilson (2011), *Two-plane automatic balancing: a symmetry breaking
# analysis*, sections 2-3: a rigid rotor on two anisotropic bearings, a race of balls in each of two
# planes, static imbalance eps and couple imbalance chi.  `adbgen.families.two_plane` derives the model
# from the kinematics (rotation matrices, the inertia tensor turned by chi) by Lagrange's equations,
# applies the small-vibration approximation explicitly, and the result is compared with the paper's
# complex form (2)-(4), its rotating frame (7)-(8), the single-plane model of the thesis and the
# critical speeds (11), (32).  Every comparison is asserted.

# %%
import matplotlib.pyplot as plt
import numpy as np
import sympy as sp

from adbgen.families.two_plane import critical_speeds as cs
from adbgen.families.two_plane import verify
from adbgen.families.two_plane.model import lagrangian, rotations
from adbgen.families.two_plane.reductions import rotating_complex_rows, rotating_frame
from adbgen.families.two_plane.scene import TwoPlaneScene
from adbgen.notebooks import check, compare, show
from adbgen.references import two_plane_2011 as paper

# %% [markdown]
# ## Kinematics and the small-vibration approximation (section 2.2)
# Body frame xi = R_3(theta_0) R_2(phi_Y) R_1(phi_X) X'; the rotor's angular velocity from the rotation
# matrix, its inertia diag(J_t, J_t, J_p) turned by chi; ball k at (R_k cos theta_k, R_k sin theta_k, z_k).
# With a bookkeeping order h for the vibration (X, Y, phi_X, phi_Y and rates) and e for the imbalance
# (eps, chi), T, V and F are kept to total order 2 in (h, e).  Also dropped: each ball's own rotary
# inertia about the transverse axes (the order-h^2 part proportional to m_k R_k^2), which the paper's
# M and G do not contain.  What is dropped, for ball 1 of the paper's set-up (10):

# %%
scene = TwoPlaneScene()  # the paper's (10): two races of two balls, isotropic bearings
lag = lagrangian(scene)
s = lag.symbols
R1, R2, R3 = rotations(*(sp.Symbol(name, real=True) for name in ("phi_X", "phi_Y", "theta_0")))
for name, matrix in (("R_1", R1), ("R_2", R2), ("R_3", R3)):
    show(f"rotation {name} (xi = R_3 R_2 R_1 X')", matrix, "paper section 2.1", lhs=name)
print("coordinates:", [c.name for c in lag.coordinates], "| driven:", [c.name for c in lag.driven])
show("dropped from T of ball 1", lag.dropped_ball_terms[0], "section 2.2 (not in the paper's M, G)", lhs=r"\Delta T_1")
assert all(d != 0 and d.has(s.R[k]) for k, d in enumerate(lag.dropped_ball_terms))

# %% [markdown]
# ## The complex form (2)-(4) and its errata
# With q = (X + iY, phi_Y - i phi_X), the paper writes the rotor rows as
# M q'' + (C_m - i theta_0' G) q' + K_m q + C_d conj(q') + K_d conj(q) = forcing (2) (corrected: the
# paper prints C_d q'), with the mean and deviatoric parts of (1), K_m = (K_X + K_Y)/2, K_d = (K_X - K_Y)/2
# and the same for C (here K_d = C_d = 0: the paper's (10) is isotropic):

# %%
mx = paper.matrices(s, scene.n)
for name in ("M", "G", "K_m", "K_d", "C_m", "C_d"):
    show(name, mx[name], "paper (1)-(2)", lhs=name)
show("modified polar inertia, as printed", paper.modified_polar_inertia(s, printed=True), "paper (3), printed",
     lhs=r"\tilde{J}_p")
show("modified polar inertia, corrected", paper.modified_polar_inertia(s, printed=False), "paper (3), corrected",
     lhs=r"\tilde{J}_p")

# %% [markdown]
# Two errata, found by comparing the derived rows with (2)-(3) on the most general scene (anisotropic,
# unequal bearings, three unequal balls in one race and one in the other, static and couple imbalance,
# torque drive): the deviatoric damping is C_d conj(q'), not C_d q' (the printed form fails once
# C_X != C_Y), and the inertia about the shaft of a rotor tilted by chi is J_p cos^2 chi + J_t sin^2 chi,
# i.e. J_p + (J_t - J_p) chi^2 + M eps^2 (the printed J_t chi^2 comes from a linearised rotation).  The
# check asserts the corrected rows are identities *and* that the printed ones fail exactly rows q1, q2
# and theta_0:

# %%
check(verify.fixed_frame())

# %% [markdown]
# ## The rotating frame (7)-(8)
# q = r e^{i Omega t}, theta_k = Omega t + alpha_k at constant speed with isotropic bearings: autonomous.
# Row 1 of (7) for the paper's set-up, derived and printed, split into real and imaginary parts:

# %%
rot = rotating_frame(scene)
r1, r2 = rotating_complex_rows(rot)
printed7 = paper.rotating_frame(s, scene.n)
show("(7), first row, derived (real part)", sp.collect(sp.expand(sp.re(r1)), [s.Omega]), "paper (7)")
for label, mine, ref in (("(7) row 1", r1, printed7["r1"]), ("(7) row 2", r2, printed7["r2"])):
    d = sp.expand(mine - ref)
    compare(f"{label}, real part of derived - printed", sp.re(d), 0, "paper (7)")
    compare(f"{label}, imaginary part of derived - printed", sp.im(d), 0, "paper (7)")
for k_ in range(scene.n):
    name = f"alpha_{k_ + 1}"
    compare(f"ball {k_ + 1}", rot.residual(rot.index(name)), printed7[name], "paper (8)")
check(verify.rotating())  # unequal bearings, balls and planes

# %% [markdown]
# ## Reduction to the single-plane model
# No tilt and one race: the two-plane equations become the thesis' (2.10)-(2.13) (torque drive, with the
# spin psi = theta_0 and phi_i = theta_i - theta_0), row by row:

# %%
check(verify.single_plane("torque"))

# %% [markdown]
# ## Critical speeds (11), (32)
# The undamped rotor's critical speeds are where det(K - Omega^2 (M - G) ) has double roots in
# w = Omega^2: Omega_cyl (cylindrical mode) and Omega_con (conical mode), (11) for the plain rotor and
# (32) with the balls' mass m at the race planes.  The derived determinant is
# c (w - Omega_cyl^2)^2 (w - Omega_con^2)^2 exactly; the numbers are those printed for (10), (42), (43).

# %%
check(verify.critical_speeds_symbolic())
for row in verify.critical_speed_numbers():
    check(row)

poly, w = cs.critical_speed_polynomial(scene, cs.exact_values(scene, with_balls=False))
roots = cs.critical_speeds(scene, with_balls=False)
show("critical-speed polynomial, (10) without balls", sp.factor(poly.as_expr()), "paper (11)", lhs="P(w)")
Om = np.linspace(0.2, 2.5, 1000)
P = sp.lambdify(w, poly.as_expr())(Om**2)
assert np.all(P >= -1e-12)  # double roots: P touches zero without crossing
fig, ax = plt.subplots(figsize=(7, 3))
ax.semilogy(Om, np.abs(P) + 1e-16, "k-", lw=1)
for r, name in zip(roots, ("cyl", "con")):
    ax.axvline(r, color="C3", lw=0.8)
    ax.text(r, 1e-6, rf" $\Omega_{{{name}}}$ = {r:.4f}", color="C3", fontsize=8)
ax.set_xlabel(r"$\Omega$")
ax.set_ylabel(r"$|P(\Omega^2)|$")
ax.set_title("critical-speed determinant of the plain rotor (10): double roots at (11)", fontsize=9)
fig.tight_layout()
plt.show()
assert abs(roots[0] - 1.0) < 1e-12 and abs(roots[1] - 1.81) < 5e-3
