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
# # 3. Steady states, their existence, and their stability
#
# Thesis ch. 3 (steady states (3.6), (3.9), (3.10); existence (3.14)-(3.18), Figures 3.1-3.2) and ch. 4
# (stability of the balanced state: windows in Omega, the pitchfork-Hopf point, the effect of damping).
# The closed forms come from `adbgen.families.single_plane.steady_states`; each is shown to be an exact
# zero of the *derived* rotating-frame equations (2.25)-(2.27).  Stability comes from the exact
# linearisation of the derived equations (`adbgen.core.linearisation`: lambda^2 M - lambda df/dq' - df/dq,
# no finite differences).

# %%
import matplotlib.pyplot as plt
import numpy as np
import sympy as sp

from adbgen.core.linearisation import Linearisation, hopf_crossing
from adbgen.families.single_plane import steady_states as ss
from adbgen.families.single_plane import verify
from adbgen.families.single_plane.reductions import rotating_frame
from adbgen.families.single_plane.scene import Scene
from adbgen.notebooks import check, latex, show

# %% [markdown]
# ## The closed forms
# Balanced states **1** (3.6): x = y = 0, sum cos phi_i = -delta/mu, sum sin phi_i = 0 (phi_3..phi_n free);
# coincident states **2+-** (3.9); in-line states **3(n-m)+-** (3.10), m balls at phi_1 and n - m opposite.

# %%
show("balanced state 1, n = 2, phi_1", ss.balanced(2)[sp.Symbol("phi_1", real=True)], "thesis (3.6)", lhs=r"\phi_1")
show("balanced state 1, n = 2, phi_2", ss.balanced(2)[sp.Symbol("phi_2", real=True)], "thesis (3.6)", lhs=r"\phi_2")
coin = ss.coincident(3, 1)
for sym in list(coin)[:3]:
    show(f"coincident state 2+, n = 3, {sym}", coin[sym], "thesis (3.9), K of (2.27)", lhs=latex(sym))

# %% [markdown]
# Each is an exact zero of the derived right-hand side (rates zero): for n = 2 and n = 3, state 1 (with
# phi_3 free), 2+, 2- and every in-line state 3(n-m)+- (the library's check, run here; `adbgen verify`
# runs it for n = 1, 2, 3, 4, 6).

# %%
check(verify.steady_states(2))
check(verify.steady_states(3))

# %% [markdown]
# ## Existence: (3.14), (3.16), (3.18) and Figures 3.1-3.2
# State 1 needs mu >= mu_c = delta/n (3.14).  States 2+- exist where the arccosine's argument in (3.9) has
# modulus at most 1, i.e. K^2 >= (2 Omega zeta)^2 ((n mu/delta)^2 - 1) (3.16); states 3(n-m)+- the same
# with (2m - n) mu (3.18).  Between the two critical speeds Omega_c1 < Omega < Omega_c2 they do not exist.

# %%
for m, number in ((3, "(3.16)"), (2, "(3.18)")):
    poly, s_ = ss.critical_speed_polynomial(3, m)
    show(f"existence boundary, n = 3, m = {m}, in s = Omega^2", poly.as_expr(), f"thesis {number} with equality")

pars = dict(mu_=0.05, zeta_=0.01, delta_=0.01)
fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
Om = np.linspace(0.6, 1.3, 1401)
for ax, m, fig_no, state in ((axes[0], 3, "3.1", "2±"), (axes[1], 2, "3.2", "3(3-2)±")):
    K2 = (1 - Om**2 * (1 + 3 * pars["mu_"])) ** 2
    rhs = (2 * Om * pars["zeta_"]) ** 2 * (((2 * m - 3) * pars["mu_"] / pars["delta_"]) ** 2 - 1)
    c1, c2 = ss.critical_speeds(3, m, pars["mu_"], pars["zeta_"], pars["delta_"])
    # the plotted curves cross exactly at the closed-form critical speeds
    crossings = Om[1:][np.diff(np.sign(K2 - rhs)) != 0]
    assert len(crossings) == 2 and np.allclose(crossings, [c1, c2], atol=1e-3), crossings
    exists = [ss.inline_exists(3, m, pars["mu_"], w, pars["zeta_"], pars["delta_"]) for w in Om]
    assert not any(e for w, e in zip(Om, exists) if c1 + 1e-6 < w < c2 - 1e-6) and all(e for w, e in zip(Om, exists) if w < c1 - 1e-6 or w > c2 + 1e-6)
    ax.plot(Om, K2, "k-", label="$K^2$")
    ax.plot(Om, rhs, "k--", label=r"$(2\Omega\zeta)^2(((2m-n)\mu/\delta)^2 - 1)$")
    ax.axvspan(c1, c2, color="0.85", label=f"{state} do not exist")
    for c in (c1, c2):
        ax.axvline(c, color="0.4", lw=0.6)
    ax.set_ylim(0, 1.2 * rhs.max())
    ax.set_xlabel(r"$\Omega$")
    ax.set_title(f"Fig. {fig_no}: n = 3, m = {m}; $\\Omega_{{c1}}$ = {c1:.4f}, $\\Omega_{{c2}}$ = {c2:.4f}", fontsize=9)
    ax.legend(fontsize=7, loc="upper right")
fig.tight_layout()
plt.show()

# %% [markdown]
# The printed numbers (Omega_c1,2 of Figs 3.1-3.2, the wedge tips (4.1)-(4.4) where the two critical
# speeds meet, the balanced positions of ch. 5 and the sign erratum of (5.2)) are the library's checks:

# %%
for row in verify.thesis_numbers():
    check(row)

# %% [markdown]
# ## Stability of the balanced state (ch. 4)
# The exact linearisation at state 1 (phi_3 = ... = pi, as the thesis takes it) for mu = 0.05,
# zeta = beta = delta = 0.01, along Omega.  For n >= 3 the balanced states form a continuum: n - 2
# eigenvalues are exactly zero and are not counted.  The thesis' picture (Figs 4.2(a), 4.6(a)): with two
# balls a small stability window near Omega = 1 and stability above the Hopf point H1; with three balls
# only above H1.

# %%
lins = {n: Linearisation(rotating_frame(Scene(n=n))) for n in (2, 3)}
balanced = {n: lins[n].point(ss.evaluate(ss.balanced(n, [sp.pi] * (n - 2), branch=-1), {"mu": 0.05, "delta": 0.01}))
            for n in (2, 3)}
grid = np.linspace(0.5, 4.0, 351)
leading, changes = {}, {}
for n, lin in lins.items():
    spec = [lin.spectrum(balanced[n], lin.parameters(Omega=w)) for w in grid]
    assert all(abs(lin.residual(balanced[n], lin.parameters(Omega=w))).max() < 1e-12 for w in grid[::50])
    assert all(s.n_zero == n - 2 for s in spec)
    leading[n] = np.array([s.leading().real for s in spec])
    stable = [s.stable for s in spec]
    changes[n] = [hopf_crossing(lin, lambda v, n=n: balanced[n], "Omega", (grid[i], grid[i + 1]))
                  for i in range(len(grid) - 1) if stable[i] != stable[i + 1]]
    print(f"n = {n}: stability changes at Omega = " + ", ".join(f"{v:.10f}" for v in changes[n]))
# the README's table (analysis layer on the generated code, and AUTO-07p) has these to 1e-9
assert np.allclose(changes[2], [1.0296941549, 1.0936342661, 1.8822393490], atol=1e-7)
assert np.allclose(changes[3], [1.8753674503], atol=1e-7)

fig, axes = plt.subplots(1, 2, figsize=(10, 3.4))
ax = axes[0]
for n, style in ((2, "k-"), (3, "C0-")):
    ax.plot(grid, leading[n], style, lw=1, label=f"n = {n}")
    for v in changes[n]:
        ax.plot(v, 0, "o", color=style[:-1], ms=4)
ax.axhline(0, color="0.5", lw=0.6)
ax.set_xlabel(r"$\Omega$")
ax.set_ylabel(r"largest Re $\lambda$ (non-zero)")
ax.set_title("state 1: leading eigenvalue; H points marked", fontsize=9)
ax.set_ylim(-0.02, 0.03)
ax.legend(fontsize=8)
ax = axes[1]
for w, marker in ((1.5, "x"), (3.0, "o")):
    ev = lins[2].spectrum(balanced[2], lins[2].parameters(Omega=w)).eigenvalues
    ax.plot(ev.real, ev.imag, marker, mfc="none", label=rf"$\Omega$ = {w} ({'stable' if (ev.real <= 1e-9).all() else 'unstable'})")
ax.axvline(0, color="0.5", lw=0.6)
ax.set_xlabel(r"Re $\lambda$")
ax.set_ylabel(r"Im $\lambda$")
ax.set_title("spectrum of state 1, n = 2", fontsize=9)
ax.legend(fontsize=8)
fig.tight_layout()
plt.show()

# %% [markdown]
# The chapter-4 numbers, from the same linearisation (the library's checks): the pitchfork-Hopf point
# (mu_c, Omega = 1.338096) for n = 2, 3, 4, the windows above, the zeta limit of Fig. 4.13(b) and the
# ball damping's widening of the stable region (Figs 4.9(a), 4.14(a)).

# %%
for row in verify.chapter4_numbers():
    check(row)
