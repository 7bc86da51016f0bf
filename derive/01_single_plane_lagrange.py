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
# # 1. The single-plane balancer by Lagrange's equations
#
# Thesis (*multi-ball ADB*, 2005) ch. 2.1, equations (2.1)-(2.14).  Every equation below is computed by
# `adbgen` when this notebook runs; every comparison is an `assert` (exact identities: the difference
# has canonical trigonometric form 0), so a notebook that stops matching the thesis fails CI.
# Source of truth: `derive/01_single_plane_lagrange.py`; re-render with `adbgen notebooks`.
#
# Coordinates (2.2): the rotor centre C at (X, Y) in the fixed frame, the spin angle psi, and each ball's
# angle phi_i relative to the rotor.  Positions (2.3)-(2.4):
# W = (X + eps cos psi, Y + eps sin psi) for the rotor's centre of mass, B_i = (X + R cos(psi + phi_i),
# Y + R sin(psi + phi_i)) for ball i.

# %%
import matplotlib.pyplot as plt
import mpmath
import numpy as np
import sympy as sp

from adbgen.families.single_plane import verify
from adbgen.families.single_plane.model import derive, lagrangian
from adbgen.families.single_plane.symbols import DimensionalSymbols
from adbgen.notebooks import check, compare, show
from adbgen.references import thesis

# %% [markdown]
# ## Energies (2.7)-(2.9)
# The most general scene: unequal balls, anisotropic support (k_X != k_Y, c_X != c_Y), gravity, and the
# spin driven by a torque tau0 - kappa psi' (2.9).  The Lagrangian is a sum of one term per body; a ball's
# term depends on X, Y, psi and its own phi_i only (this is what makes the equations scale in n).

# %%
scene = verify.general_scene(2)  # torque drive, m_1 != m_2, k_X != k_Y, gravity
lag = lagrangian(scene)
print("coordinates:", [c.name for c in lag.coordinates], " bodies:", [term.label for term in lag.terms])
rotor, ball = lag.terms[0], lag.terms[1]
show("T of the rotor", sp.factor_terms(sp.trigsimp(sp.expand(rotor.T))), "thesis (2.7)", lhs="T_{rotor}")
show("T of ball 1", sp.factor_terms(sp.trigsimp(sp.expand(ball.T))), "thesis (2.8)", lhs="T_{1}")
show("V", sp.expand(sum(term.V for term in lag.terms)), "thesis (2.8)", lhs="V")
show("Rayleigh dissipation", sum(term.F for term in lag.terms), "thesis (2.9)", lhs="F")
# Each ball's energy involves only the rotor coordinates and its own angle:
phi_2 = [c for c in lag.coordinates if c.name == "phi_2"][0]
assert not ({phi_2.q, phi_2.qd} & ball.T.free_symbols)

# %% [markdown]
# ## Lagrange's equations (2.1) against the printed (2.10)-(2.13)
# d/dt dL/dq'_k - dL/dq_k + dF/dq'_k = Q_k, formed term by term.  Each derived row M q'' - f is set
# beside the thesis' printed equation (transcribed once, in `adbgen.references.thesis`) and the two are
# shown identical.

# %%
eom = derive(scene)
s = DimensionalSymbols.for_scene(scene)
psi = eom.coordinates[eom.index("psi")]
printed = thesis.fixed_frame(s, scene.n, torque=s.tau0 - s.kappa * psi.qd)
numbers = {"X": "(2.10)", "Y": "(2.11)", "psi": "(2.12)", "phi_1": "(2.13), i = 1", "phi_2": "(2.13), i = 2"}
for name, reference in printed.items():
    compare(f"row {name}", eom.residual(eom.index(name)), reference, f"thesis {numbers[name]}")

# %% [markdown]
# The same comparison for n = 1, 3 (the library's checks, run here) and for the constant speed of (2.14),
# psi = omega t, where the psi row is dropped:

# %%
for n in (1, 3):
    check(verify.fixed_frame(n))
    check(verify.prescribed_speed(n))

# %% [markdown]
# ## The mass matrix: each ball couples only to the rotor
# The sparsity of M (n = 6, torque drive): the rotor block (X, Y, psi) is dense, each ball's row has
# entries only in the rotor columns and on the diagonal.  Appendix A's solve (notebook 2) rests on this.

# %%
big = derive(verify.general_scene(6))
M = big.mass_matrix()
names = [c.name for c in big.coordinates]
pattern = np.array([[M[i, j] != 0 for j in range(len(names))] for i in range(len(names))])
balls = [i for i, nm in enumerate(names) if nm.startswith("phi_")]
assert not any(pattern[i, j] for i in balls for j in balls if i != j)
fig, ax = plt.subplots(figsize=(3.6, 3.6))
ax.spy(pattern, markersize=14, color="k")
ax.set_xticks(range(len(names)), [f"${sp.latex(sp.Symbol(nm))}$" for nm in names], rotation=90)
ax.set_yticks(range(len(names)), [f"${sp.latex(sp.Symbol(nm))}$" for nm in names])
ax.set_title("non-zero entries of M, n = 6", fontsize=10)
fig.tight_layout()
plt.show()

# %% [markdown]
# ## An independent numeric check of Lagrange's equations
# Nothing symbolic: the positions (2.3)-(2.4) as complex numbers in mpmath (40 digits), T, V and F from
# them with every velocity by numerical differentiation along the motion, and the Lagrange residual
# d/dt dL/dq'_k - dL/dq_k + dF/dq'_k - Q_k by nested `mpmath.diff`, at a random state (q, q', q'').  It
# must equal the derived row M q'' - f at the same numbers to 1e-12 relative.  (The test suite runs the
# same construction for n = 1..6 and both speed laws, `tests/families/single_plane/test_numeric_lagrangian.py`.)

# %%
mpmath.mp.dps = 40
value = {p.symbol: mpmath.mpf(p.default) for p in s.parameters}
M_, eps_, R_, g_ = value[s.M], value[s.eps], value[s.R], value[s.g]
m_, D_ = [value[x] for x in s.m], [value[x] for x in s.D]
kX, kY, cX, cY, Iz, tau0, kappa = (value[x] for x in (s.kX, s.kY, s.cX, s.cY, s.I_z, s.tau0, s.kappa))


def positions(z):  # z = (X, Y, psi, phi_1, phi_2): W and the balls as x + i y
    C = mpmath.mpc(z[0], z[1])
    return [(M_, C + eps_ * mpmath.expj(z[2]))] + [(m_[i], C + R_ * mpmath.expj(z[2] + z[3 + i])) for i in range(2)]


def L(z, zd):
    T = Iz * zd[2] ** 2 / 2
    for j, (mass, _) in enumerate(positions(z)):
        v = mpmath.diff(lambda u: positions([a + u * b for a, b in zip(z, zd)])[j][1], 0)
        T += mass * abs(v) ** 2 / 2
    V = kX * z[0] ** 2 / 2 + kY * z[1] ** 2 / 2 + sum(mass * g_ * pos.imag for mass, pos in positions(z))
    return T - V


def F(zd):
    return cX * zd[0] ** 2 / 2 + cY * zd[1] ** 2 / 2 + sum(D_[i] * zd[3 + i] ** 2 / 2 for i in range(2))


def bump(v, k, u):
    return [a + (u if i == k else 0) for i, a in enumerate(v)]


rng = np.random.default_rng(2005)
q0, qd0, qdd0 = ([mpmath.mpf(float(x)) for x in rng.uniform(-1, 1, 5) * sc] for sc in (0.05, 1.0, 5.0))
curve = lambda u: ([a + b * u + c * u * u / 2 for a, b, c in zip(q0, qd0, qdd0)], [b + c * u for b, c in zip(qd0, qdd0)])  # noqa: E731
order = ["X", "Y", "psi", "phi_1", "phi_2"]
subs = {**value}
for c, a, b, cc in zip([eom.coordinates[eom.index(nm)] for nm in order], q0, qd0, qdd0):
    subs.update({c.q: a, c.qd: b, c.qdd: cc})
worst = 0
for k, name in enumerate(order):
    numeric = (mpmath.diff(lambda u: mpmath.diff(lambda w: L(curve(u)[0], bump(curve(u)[1], k, w)), 0), 0)
               - mpmath.diff(lambda w: L(bump(q0, k, w), qd0), 0) + mpmath.diff(lambda w: F(bump(qd0, k, w)), 0)
               - (tau0 - kappa * qd0[2] if name == "psi" else 0))
    symbolic = sp.N(eom.residual(eom.index(name)).xreplace(subs), 40)
    err = abs(numeric - mpmath.mpf(str(symbolic))) / max(1, abs(numeric))
    worst = max(worst, err)
    print(f"{name:6s} numeric {mpmath.nstr(numeric, 15):>22s}   symbolic {sp.N(symbolic, 15)!s:>22s}   rel. diff {mpmath.nstr(err, 3)}")
assert worst < 1e-12, worst
print(f"largest relative difference {mpmath.nstr(worst, 3)} (tolerance 1e-12)")
