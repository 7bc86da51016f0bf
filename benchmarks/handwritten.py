"""The equations a heyoka user would write by hand for the benchmarks' problems A and B (issue 22 item 5),
as heyoka expressions: the peer "heyoka-hand" (`peers.HeyokaHandwritten`), beside "heyoka" fed the
generated statements.  Parameters are ``heyoka.par[k]`` in the generated model's order (no constant
folding); sin and cos of each angle once; the small linear solves written out.  A test checks each
form against the generated rhs at random states: a benchmark of a lookalike would be worth nothing.

Problem A, the thesis' rotating frame (2.25)-(2.27) in its Appendix A form (as `bench.baseline`):
one sum per ball quantity, the 2 x 2 system (A.3)-(A.4) solved by Cramer's rule (A.7)-(A.8), each
ball's acceleration (A.6).

Problem B, the paper's (2) and (4) for isotropic supports with the spin prescribed (section 6, the
Hill profile (45)), in real coordinates q = [X + iY, phi_Y - i phi_X]: each ball's equation (4) gives
its acceleration as an affine function of the rotor's four accelerations,

    theta_k'' = -c_k/(m_k R_k^2) (theta_k' - Omega) + (s_k X'' - c_k Y'' + z_k c_k phi_X'' + z_k s_k phi_Y'') / R_k,

(s_k, c_k = sin, cos theta_k), which, put into the forcing of (2), leaves four real equations in
(X'', Y'', phi_X'', phi_Y''), solved by Gaussian elimination on the expressions.  The spin angle is
one more state, theta_0' = Omega(t) (a heyoka user integrates the Hill profile rather than writing
its closed-form integral), Omega = Omega_max u^3 / (t_half^3 + u^3), u = Omega_cyl t, written with
products (heyoka's power of t divides by t, NaN at t = 0).
"""

from __future__ import annotations

# which hand-written form serves which generated model
FORMS = {"thesis_rotating": "A", "two_plane_hill": "B"}


def form_of(model_name: str) -> str | None:
    if model_name.startswith("thesis_rotating_n"):
        return "A"
    return FORMS.get(model_name)


def thesis_appendix_a(hy, module):
    """(state variables, right-hand sides) of thesis Appendix A for the module's n balls."""
    names = list(module.STATE_NAMES)
    n = (len(names) - 4) // 2
    par = {name: hy.par[k] for k, name in enumerate(module.PARAM_NAMES)}
    V = hy.make_vars(*names)
    x, yy = V[0], V[1]
    phi = V[2:2 + n]
    u, v = V[2 + n], V[3 + n]
    th = V[4 + n:]
    Omega, beta, delta, mu, zeta = (par[k] for k in ("Omega", "beta", "delta", "mu", "zeta"))
    s = [hy.sin(q) for q in phi]
    c = [hy.cos(q) for q in phi]
    W2 = Omega * Omega
    M = 1.0 + n * mu
    K = 1.0 - W2 * M
    A = W2 * x + 2.0 * Omega * v
    B = W2 * yy - 2.0 * Omega * u
    ss = hy.sum([si * si for si in s])
    sc = hy.sum([si * ci for si, ci in zip(s, c)])
    cc = hy.sum([ci * ci for ci in c])
    cen_c = hy.sum([(Omega + t) * (Omega + t) * ci for t, ci in zip(th, c)])
    cen_s = hy.sum([(Omega + t) * (Omega + t) * si for t, si in zip(th, s)])
    damp_s = hy.sum([t * si for t, si in zip(th, s)])
    damp_c = hy.sum([t * ci for t, ci in zip(th, c)])
    a = M - mu * ss  # (A.9)-(A.11)
    b = mu * sc
    c_ = M - mu * cc
    f = (-2.0 * zeta * u + 2.0 * Omega * M * v - K * x + 2.0 * Omega * zeta * yy + delta * W2 + mu * cen_c
         - mu * beta * damp_s - mu * A * ss + mu * B * sc)  # (A.12)
    g = (-2.0 * Omega * M * u - 2.0 * zeta * v - 2.0 * Omega * zeta * x - K * yy + mu * cen_s + mu * beta * damp_c
         + mu * A * sc - mu * B * cc)  # (A.13)
    det = a * c_ - b * b
    ud = (c_ * f - b * g) / det  # (A.7)-(A.8)
    vd = (a * g - b * f) / det
    rhs = [u, v] + list(th) + [ud, vd] + [-beta * t + (ud - A) * si - (vd - B) * ci for t, si, ci in zip(th, s, c)]
    return list(V), rhs


def _solve(rows, rhs):
    """Gaussian elimination (no pivoting: the rotor's mass matrix dominates) on expressions."""
    n = len(rows)
    rows = [list(r) for r in rows]
    rhs = list(rhs)
    for k in range(n):
        for i in range(k + 1, n):
            f = rows[i][k] / rows[k][k]
            rows[i] = [rows[i][j] - f * rows[k][j] for j in range(n)]
            rhs[i] = rhs[i] - f * rhs[k]
    out = [None] * n
    for k in reversed(range(n)):
        acc = rhs[k]
        for j in range(k + 1, n):
            acc = acc - rows[k][j] * out[j]
        out[k] = acc / rows[k][k]
    return out


def two_plane_hill(hy, module):
    """(state variables with theta_0 last, right-hand sides) of the paper's (2), (4) with the Hill run-up."""
    names = list(module.STATE_NAMES)
    par = {name: hy.par[k] for k, name in enumerate(module.PARAM_NAMES)}
    V = hy.make_vars(*names, "theta_0")
    X, Y, pX, pY = V[0:4]
    th = V[4:8]
    Xd, Yd, pXd, pYd = V[8:12]
    thd = V[12:16]
    th0 = V[16]
    P = par
    m = [P["m_1"], P["m_2"], P["m_3"], P["m_4"]]
    R = [P["R_t"], P["R_t"], P["R_b"], P["R_b"]]  # balls 1, 2 in the top race, 3, 4 in the bottom one
    z = [P["z_t"], P["z_t"], P["z_b"], P["z_b"]]
    cb = [P["c_bt"], P["c_bt"], P["c_bb"], P["c_bb"]]
    # the Hill profile (45), n = 3, and its derivative
    u = P["Omega_cyl"] * hy.time
    u3 = u * u * u
    th3 = P["t_half"] * P["t_half"] * P["t_half"]
    den = th3 + u3
    Om = P["Omega_max"] * u3 / den
    Omd = 3.0 * P["Omega_max"] * P["Omega_cyl"] * th3 * u * u / (den * den)
    # (1): bearing stiffness and damping, the same in X and Y
    k1, k2, c1, c2, l1, l2 = (P[k] for k in ("k_1", "k_2", "c_1", "c_2", "l_1", "l_2"))
    K11, K12, K22 = k1 + k2, k1 * l1 - k2 * l2, k1 * l1 * l1 + k2 * l2 * l2
    C11, C12, C22 = c1 + c2, c1 * l1 - c2 * l2, c1 * l1 * l1 + c2 * l2 * l2
    a1 = P["M"] + hy.sum(m)
    bz = hy.sum([mk * zk for mk, zk in zip(m, z)])
    a2 = P["J_t"] + hy.sum([mk * zk * zk for mk, zk in zip(m, z)])
    Jp = P["J_p"]
    s = [hy.sin(t) for t in th]
    c = [hy.cos(t) for t in th]
    ph = th0 + P["beta"]
    sI, cI, s0, c0 = hy.sin(ph), hy.cos(ph), hy.sin(th0), hy.cos(th0)
    Me = P["M"] * P["epsilon"]
    chiJ = P["chi"] * (P["J_t"] - Jp)
    # (4): theta_k'' = alpha_k + beta_k . (X'', Y'', phi_X'', phi_Y'')
    alpha = [-cb[k] / (m[k] * R[k] * R[k]) * (thd[k] - Om) for k in range(4)]
    beta_ = [[s[k] / R[k], -c[k] / R[k], z[k] * c[k] / R[k], z[k] * s[k] / R[k]] for k in range(4)]
    mR = [m[k] * R[k] for k in range(4)]
    W = [thd[k] * thd[k] for k in range(4)]
    # (2) split into real rows X, Y, phi_Y (Re of row 2) and phi_X (-Im of row 2): rotor terms, then
    # the balls' forcing m R (theta'^2 - i theta'') e^{i theta} with theta'' from (4)
    rows = [[a1, 0.0, 0.0, bz], [0.0, a1, -bz, 0.0], [0.0, -bz, a2, 0.0], [bz, 0.0, 0.0, a2]]
    rhs = [Me * (Om * Om * cI + Omd * sI) - (C11 * Xd + C12 * pYd + K11 * X + K12 * pY),
           Me * (Om * Om * sI - Omd * cI) - (C11 * Yd - C12 * pXd + K11 * Y - K12 * pX),
           -(chiJ * (Om * Om * s0 - Omd * c0)) + (C12 * Yd - C22 * pXd - Om * Jp * pYd + K12 * Y - K22 * pX),
           chiJ * (Om * Om * c0 + Omd * s0) - (C12 * Xd + C22 * pYd - Om * Jp * pXd + K12 * X + K22 * pY)]
    # row 3 is -(Im of row 2): b Y'' - a2 phi_X'' + ... = Im RHS2, written as -b Y'' + a2 phi_X'' = ...
    for k in range(4):
        # Re RHS1 += mR (W c + theta'' s); Im RHS1 += mR (W s - theta'' c); RHS2 the same times z
        parts = [(mR[k] * W[k] * c[k], mR[k] * s[k]), (mR[k] * W[k] * s[k], -mR[k] * c[k]),
                 (-(z[k] * mR[k] * W[k] * s[k]), z[k] * mR[k] * c[k]), (z[k] * mR[k] * W[k] * c[k], z[k] * mR[k] * s[k])]
        for i, (known, times_acc) in enumerate(parts):
            rhs[i] = rhs[i] + known + times_acc * alpha[k]
            rows[i] = [rows[i][j] - times_acc * beta_[k][j] for j in range(4)]
    Xdd, Ydd, pXdd, pYdd = _solve(rows, rhs)
    acc = [Xdd, Ydd, pXdd, pYdd]
    thdd = [alpha[k] + hy.sum([beta_[k][j] * acc[j] for j in range(4)]) for k in range(4)]
    out = [Xd, Yd, pXd, pYd] + list(thd) + acc + thdd + [Om]
    return list(V), out


__all__ = ["FORMS", "form_of", "thesis_appendix_a", "two_plane_hill"]
