# %% [markdown]
# # From the first-order form to code: the intermediate form, step by step
#
# A percent-format notebook (run as a script by the test suite, so every assert is a check).
# It lowers the thesis' rotating-frame model (2.25)-(2.27) in first-order form (Appendix A) to the
# intermediate form that every target (numba, C, CVODE, AUTO-07p) is rendered from.
#
# Data flow: first-order system -> straight-line programs (rhs, jac, jac_p, mass, forcing)
# -> printers (Python for numba, C99) -> jinja2 templates -> generated/.

# %%
import numpy as np
import sympy as sp

from adbgen.families.single_plane import models
from adbgen.codegen.interpret import compile_program
from adbgen.codegen.render import render_model, source_hash

# %% [markdown]
# ## 1. The model and its mass-matrix structure
# Two rotor coordinates (x, y) form the Schur core; each ball's row couples only to them, so the
# ball block of M is diagonal.  The intermediate form records the pattern.

# %%
spec = models.thesis_rotating(2)
system = spec.system()
ir = spec.build()
print("states:", ir.state_names)
print("parameters:", ir.parameter_names)
print("core:", ir.core, " leaves:", ir.leaves)
print("nonzero M entries:", ir.mass_pattern)
balls = [ir.state_names.index(name) for name in ir.leaves]
assert all((i, j) not in ir.mass_pattern for i in balls for j in balls if i != j)

# %% [markdown]
# ## 2. The rhs program
# Common subexpressions of the mass blocks and forcing (w_k), then the Schur complement S and its
# right-hand side as sums over balls, an unrolled LU solve of the 2x2 core, and the back-substitution
# of the ball accelerations (A.6).  No inverse of M is ever formed.

# %%
for lhs, rhs in ir.rhs.assignments:
    if not lhs.name.startswith("w_"):
        print(f"{lhs} = {rhs}")

# %% [markdown]
# ## 3. It equals the closed form
# Cramer's rule on the whole system (what Appendix A's (A.7)-(A.8) write out) is independent of
# the structured lowering; both agree to rounding at random points.

# %%
closed = sp.lambdify((list(system.states), [p.symbol for p in system.parameters]), system.rhs(), modules="math")
program = compile_program(ir, "rhs")
rng = np.random.default_rng(0)
for _ in range(20):
    y = rng.uniform(-1, 1, ir.n_states)
    p = np.array([q.default for q in ir.parameters]) * rng.uniform(0.5, 2, len(ir.parameters))
    assert np.allclose(program(0.0, y, p), closed(y, p), rtol=1e-12, atol=1e-14)
print("rhs program = closed form at 20 random points")

# %% [markdown]
# ## 4. Operation counts grow linearly in n
# One more ball adds about the same number of operations to the rhs program (common-subexpression
# elimination makes the increments differ by a few); nothing grows like n^2.

# %%
ns = (1, 2, 3, 4, 6, 8)
ops = {n: models.thesis_rotating(n).build().rhs.count_ops() for n in ns}
print("rhs operations:", ops)
slope, intercept = np.polyfit(ns, [ops[n] for n in ns], 1)
worst = max(abs(ops[n] - (intercept + slope * n)) / ops[n] for n in ns)
print(f"ops ~ {intercept:.0f} + {slope:.1f} n, largest deviation from the line {100 * worst:.1f} %")
assert worst < 0.05

# %% [markdown]
# ## 5. The Jacobian by the same structure
# Differentiating M q'' = f at fixed accelerations gives M d(q'')/dy = d(f - M q'')/dy: sparse
# derivative expressions (dR_k_j), each column solved with the factorised Schur complement.

# %%
jac = compile_program(ir, "jac")
y = rng.uniform(-1, 1, ir.n_states)
p = np.array([q.default for q in ir.parameters])
J = jac(0.0, y, p).reshape(ir.n_states, ir.n_states)
h = 1e-6
fd = np.column_stack([(program(0.0, y + h * e, p) - program(0.0, y - h * e, p)) / (2 * h) for e in np.eye(ir.n_states)])
assert np.max(np.abs(J - fd)) < 1e-6 * np.max(np.abs(J))
print("jac = central differences of rhs to", f"{np.max(np.abs(J - fd)) / np.max(np.abs(J)):.1e}")

# %% [markdown]
# ## 6. Rendering
# Every target's files come from the same programs; the source hash in each header covers the
# intermediate form and the templates.

# %%
files = render_model(ir)
print(sorted(files))
assert all(source_hash(ir) in text for text in files.values())
