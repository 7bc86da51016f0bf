# %% [markdown]
# # The single-plane n-ball balancer, derived step by step
#
# A percent-format notebook (open it in Jupyter with jupytext, or run it as a script: the test suite
# runs it, so every statement here is checked).  Source: thesis ch. 2-3 and Appendix A
# (`../shared/references/thesis-multi-ball-adb-2005.txt`).
#
# Data flow: scene -> Lagrangian (2.3)-(2.9) -> Lagrange (2.1) -> fixed frame (2.10)-(2.13)
# -> non-dimensional (2.20)-(2.22) -> rotating frame (2.25)-(2.27) -> first-order form (A.1)-(A.14).

# %%
import sympy as sp

from adbgen.core import is_identity
from adbgen.references import thesis
from adbgen.families.single_plane.scene import Scene
from adbgen.families.single_plane import steady_states as ss
from adbgen.families.single_plane.model import derive, lagrangian
from adbgen.families.single_plane.reductions import first_order, nondimensionalise, rotating_frame
from adbgen.families.single_plane.symbols import DimensionalSymbols, Omega, beta, delta, mu, t, zeta

# %% [markdown]
# ## 1. The scene and the Lagrangian
# Three balls, the thesis' parameter set (5.1) realised in SI units.  Each body (the disc, each ball)
# is one energy term; a ball's term depends on X, Y, psi and its own phi_i only.

# %%
scene = Scene(n=3)
lag = lagrangian(scene)
print([term.label for term in lag.terms])
print("T of ball 1 =", sp.factor_terms(lag.terms[1].T))

# %% [markdown]
# ## 2. Lagrange's equations in the fixed frame (2.10)-(2.13)
# The spin is prescribed (psi = omega t), so there are 2 + n equations.  They equal the printed ones.

# %%
fixed = derive(scene)
s = DimensionalSymbols.for_scene(scene)
printed = thesis.fixed_frame(s, scene.n, spin=(s.omega * t, s.omega, 0))
assert all(is_identity(fixed.residual(fixed.index(k)), r) for k, r in printed.items())
print(fixed.mass_matrix())

# %% [markdown]
# ## 3. Non-dimensional form (2.20)-(2.22)
# X = R Xbar, t = tbar/omega_n, and mu, Omega, delta, G, zeta, beta of (2.16), (2.19).  With gravity the
# comparison exposes the erratum in (2.21): the term is -delta G (1 + n mu), not -G (1 + n mu).

# %%
with_gravity = Scene(n=3, gravity=True)
nondim = nondimensionalise(with_gravity)
G = sp.Symbol("G", nonnegative=True)
right = thesis.nondimensional(3, mu, Omega, zeta, beta, delta, G, t)
misprinted = thesis.nondimensional(3, mu, Omega, zeta, beta, delta, G, t, printed=True)
assert is_identity(nondim.residual(nondim.index("Y")), right["Y"])
assert not is_identity(nondim.residual(nondim.index("Y")), misprinted["Y"])

# %% [markdown]
# ## 4. Rotating frame (2.25)-(2.27)
# X = x cos(Omega t) - y sin(Omega t), Y = x sin + y cos; rotor rows projected on the rotating axes.
# With G = 0 no explicit t is left: the system is autonomous.

# %%
rot = rotating_frame(scene)
printed = thesis.rotating_frame(3, mu, Omega, zeta, beta, delta)
assert all(is_identity(rot.residual(rot.index(k)), r) for k, r in printed.items())
assert all(t not in f.free_symbols for f in rot.forcing)

# %% [markdown]
# ## 5. First-order form, Appendix A
# The Schur complement of the ball block is [[a, b], [b, c]] of (A.9)-(A.11); its right-hand side is
# (f, g) of (A.12)-(A.13) *as corrected*: the printed line break puts two terms of f on g's line.

# %%
fo = first_order(rot)
A = thesis.appendix_a(3, mu, Omega, zeta, beta, delta)
assert is_identity(fo.solve.schur[0, 0], A["a"]) and is_identity(fo.solve.schur[0, 1], A["b"])
assert is_identity(fo.solve.rhs[0], A["f"]) and is_identity(fo.solve.rhs[1], A["g"])
literal = thesis.appendix_a(3, mu, Omega, zeta, beta, delta, printed=True)
assert not is_identity(fo.solve.rhs[0], literal["f"])
print("states:", fo.state_names)

# %% [markdown]
# ## 6. Steady states (3.6), (3.9), (3.10), and the wedge of Fig. 3.1
# Each closed form is an exact zero of the derived right-hand side.

# %%
for name, state in {"1": ss.balanced(3), "2+": ss.coincident(3, 1), "3(3-2)-": ss.inline(3, 2, -1)}.items():
    assert ss.is_steady_state(rot, state), name
print("Omega_c1, Omega_c2 =", ss.critical_speeds(3, 3, 0.05, 0.01, 0.01))  # thesis: 0.8114, 1.0717
