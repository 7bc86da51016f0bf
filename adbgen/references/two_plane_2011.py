"""The printed equations of Rodrigues, Champneys, Friswell & Wilson (2011), transcribed for comparison only.

Source: ../shared/references/two-plane-balancing-2011.txt ("Two-plane automatic balancing: a symmetry
breaking analysis", Int. J. Non-Linear Mech. 46(9)).  Nothing in `adbgen.families.two_plane` is built from this
module: the model is derived from the kinematics, and the tests show it equals these equations as exact
identities (each complex equation split into real and imaginary parts).

Complex rows are returned as "left-hand side minus right-hand side".  Row 1 of (2)/(7) is the X (x)
equation plus i times the Y (y) equation, row 2 the phi_Y (phi_y) equation minus i times the phi_X
(phi_x) one, as q = [X + iY, phi_Y - i phi_X] dictates.

Errata found by that comparison (each tested both ways):

- (2): the deviatoric damping term is printed C_d q'; the damping force C_X Re q' + i C_Y Im q' is
  C_m q' + C_d conj(q'), as the stiffness term K_d conj(q) already has.  The printed form fails as soon
  as the bearing damping is anisotropic (C_X != C_Y).
- (28), fourth row of the ball forcing: printed z (cos a^_12 sin a-_12 + cos a^_34 sin a-_34); with
  z_{3,4} = -z it is z (cos a^_12 sin a-_12 - cos a^_34 sin a-_34), as the second row already has.  The
  paper only uses (28) at C3 with a-_12 = a-_34 = pi, where both forms vanish, so (29)-(34) stand.
- (3), the modified polar inertia: printed J_p + J_t chi^2 + M eps^2.  The inertia of the rotor about
  the shaft axis, its principal axis p_3 tilted by chi, is J_p cos^2 chi + J_t sin^2 chi, so to the
  order kept J_p + (J_t - J_p) chi^2 + M eps^2; the printed value is what the linearised (not
  orthogonal) rotation [[1, 0, chi], [0, 1, 0], [-chi, 0, 1]] gives.
"""

from __future__ import annotations

import sympy as sp

from ..core import Coordinate

I = sp.I


def cis(a):
    """e^{i a} written with cos and sin (real symbols stay real)."""
    return sp.cos(a) + I * sp.sin(a)


def _c(name: str) -> Coordinate:
    return Coordinate.make(name)


def matrices(s, n_balls: int):
    """M, G, K_m, K_d, C_m, C_d of (1)-(2) and f_I, f_bk (without e^{i theta}); `s` a TwoPlaneSymbols."""
    M = sp.Matrix([[s.M + sum(s.m), sum(m * z for m, z in zip(s.m, s.z))],
                   [sum(m * z for m, z in zip(s.m, s.z)), s.Jt + sum(m * z**2 for m, z in zip(s.m, s.z))]])
    G = sp.Matrix([[0, 0], [0, s.Jp]])

    def per_axis(table, axis):  # (1)
        a, b = table[(1, axis)], table[(2, axis)]
        return sp.Matrix([[a + b, a * s.l1 - b * s.l2], [a * s.l1 - b * s.l2, a * s.l1**2 + b * s.l2**2]])

    KX, KY, CX, CY = per_axis(s.k, "X"), per_axis(s.k, "Y"), per_axis(s.c, "X"), per_axis(s.c, "Y")
    out = {"M": M, "G": G, "K_m": (KX + KY) / 2, "K_d": (KX - KY) / 2, "C_m": (CX + CY) / 2, "C_d": (CX - CY) / 2,
           "K_X": KX, "K_Y": KY, "C_X": CX, "C_Y": CY,
           "f_I": sp.Matrix([s.M * s.eps * cis(s.beta), s.chi * (s.Jt - s.Jp)]),
           "f_b": [sp.Matrix([s.m[k] * s.R[k], s.m[k] * s.R[k] * s.z[k]]) for k in range(n_balls)]}
    return out


def modified_polar_inertia(s, printed: bool = True):
    """tilde J_p below (4): printed J_p + J_t chi^2 + M eps^2; corrected J_p + (J_t - J_p) chi^2 + M eps^2."""
    return s.Jp + (s.Jt if printed else s.Jt - s.Jp) * s.chi**2 + s.M * s.eps**2


def _conj_dot(f: sp.Matrix, v: sp.Matrix):
    return sum((sp.conjugate(a) * b for a, b in zip(f, v)), sp.S.Zero)


def fixed_frame(s, n_balls: int, spin=None, printed: bool = True) -> dict[str, sp.Expr]:
    """(2)-(4).  Returns complex rows 'q1', 'q2' of (2), real rows 'theta_0' of (3), 'theta_k' of (4).

    spin = (theta_0, theta_0', theta_0'') substitutes a prescribed spin (then (3) is not returned);
    printed=True keeps C_d q' and the printed tilde J_p, printed=False the corrected forms.
    """
    X, Y, pX, pY = (_c(n) for n in ("X", "Y", "phi_X", "phi_Y"))
    th = [_c(f"theta_{k + 1}") for k in range(n_balls)]
    th0 = _c("theta_0")
    p, pd, pdd = spin if spin is not None else (th0.q, th0.qd, th0.qdd)
    q = sp.Matrix([X.q + I * Y.q, pY.q - I * pX.q])
    qd = sp.Matrix([X.qd + I * Y.qd, pY.qd - I * pX.qd])
    qdd = sp.Matrix([X.qdd + I * Y.qdd, pY.qdd - I * pX.qdd])
    mx = matrices(s, n_balls)
    damping_d = mx["C_d"] * (qd if printed else qd.applyfunc(sp.conjugate))
    lhs = (mx["M"] * qdd + (mx["C_m"] - I * pd * mx["G"]) * qd + mx["K_m"] * q + damping_d
           + mx["K_d"] * q.applyfunc(sp.conjugate))
    rhs = (pd**2 - I * pdd) * mx["f_I"] * cis(p)
    for k in range(n_balls):
        rhs += (th[k].qd ** 2 - I * th[k].qdd) * mx["f_b"][k] * cis(th[k].q)
    out = {"q1": lhs[0] - rhs[0], "q2": lhs[1] - rhs[1]}
    if spin is None:
        tau = s.tau0 - s.kappa * th0.qd
        out["theta_0"] = (modified_polar_inertia(s, printed) * th0.qdd + s.c_r * th0.qd
                          + sum((s.cb[k] * (th0.qd - th[k].qd) for k in range(n_balls)), sp.S.Zero)
                          + sp.im(sp.expand(_conj_dot(mx["f_I"], qdd) * cis(-p))) - tau)  # (3)
    for k in range(n_balls):
        out[th[k].name] = (s.m[k] * s.R[k] ** 2 * th[k].qdd + s.cb[k] * (th[k].qd - pd)
                           + sp.im(sp.expand(_conj_dot(mx["f_b"][k], qdd) * cis(-th[k].q))))  # (4)
    return out


def rotating_frame(s, n_balls: int) -> dict[str, sp.Expr]:
    """(7)-(8), isotropic supports (K = K_X = K_Y, C = C_X = C_Y), constant speed Omega."""
    x, y, px, py = (_c(n) for n in ("x", "y", "phi_x", "phi_y"))
    al = [_c(f"alpha_{k + 1}") for k in range(n_balls)]
    Om = s.Omega
    r = sp.Matrix([x.q + I * y.q, py.q - I * px.q])
    rd = sp.Matrix([x.qd + I * y.qd, py.qd - I * px.qd])
    rdd = sp.Matrix([x.qdd + I * y.qdd, py.qdd - I * px.qdd])
    mx = matrices(s, n_balls)
    M, G, K, C = mx["M"], mx["G"], mx["K_m"], mx["C_m"]
    lhs = M * rdd + (C + I * Om * (2 * M - G)) * rd + (K - Om**2 * (M - G) + I * Om * C) * r
    rhs = Om**2 * mx["f_I"]
    for k in range(n_balls):
        rhs += ((Om + al[k].qd) ** 2 - I * al[k].qdd) * mx["f_b"][k] * cis(al[k].q)
    out = {"r1": lhs[0] - rhs[0], "r2": lhs[1] - rhs[1]}
    acc = rdd + 2 * I * Om * rd - Om**2 * r
    for k in range(n_balls):
        out[al[k].name] = (s.m[k] * s.R[k] ** 2 * al[k].qdd + s.cb[k] * al[k].qd
                           + sp.im(sp.expand(_conj_dot(mx["f_b"][k], acc) * cis(-al[k].q))))  # (8)
    return out


def balanced_condition(s, n_balls: int) -> sp.Matrix:
    """(9): f_I + sum_k f_bk e^{i alpha_k} (zero at the balanced state B)."""
    mx = matrices(s, n_balls)
    al = [_c(f"alpha_{k + 1}") for k in range(n_balls)]
    return mx["f_I"] + sum((mx["f_b"][k] * cis(al[k].q) for k in range(n_balls)), sp.zeros(2, 1))


# --- section 3, symmetric set-up: m, R, z, k, l, c as plain symbols -------------------------------------
def critical_speeds_11(M, Jt, Jp, k, l):
    """(11): Omega_cyl = sqrt(2k/M), Omega_con = sqrt(2 k l^2 / (J_t - J_p)) (no balls)."""
    return sp.sqrt(2 * k / M), sp.sqrt(2 * k * l**2 / (Jt - Jp))


def critical_speeds_32(M, Jt, Jp, k, l, m, z):
    """(32): the critical speeds modified by the four balls."""
    return sp.sqrt(2 * k / (M + 4 * m)), sp.sqrt(2 * k * l**2 / (Jt + 4 * m * z**2 - Jp))


def kappa_32(M, Jt, Jp, k, l, m, z, Omega, second_form: bool = False):
    """(32), first line, or (second_form) the form through the critical speeds."""
    if second_form:
        cyl, con = critical_speeds_32(M, Jt, Jp, k, l, m, z)
        return z**2 * (1 - (Omega / cyl) ** 2) / (l**2 * (1 - (Omega / con) ** 2))
    return z**2 * (2 * k - (M + 4 * m) * Omega**2) / (2 * k * l**2 - Omega**2 * (Jt + 4 * m * z**2 - Jp))


def mR_31(M, eps, kappa, alpha_hat_34):
    """(31): m R on the C3 branch."""
    return M * eps / 2 / ((kappa + 1) * sp.cos(alpha_hat_34) + (1 - kappa))


def steady_state_28(M, Jt, Jp, k, l, c, m, z, R, eps, Omega, xvec, mean12, hat12, mean34, hat34,
                    printed: bool = True) -> list:
    """(28) as residuals (left minus right), x = [x, phi_y, y, -phi_x]; printed=False corrects row 4's sign."""
    K = sp.diag(2 * k, 2 * k * l**2)
    Mm = sp.diag(M + 4 * m, Jt + 4 * m * z**2)
    G = sp.diag(0, Jp)
    C = sp.diag(2 * c, 2 * c * l**2)
    A = K - Omega**2 * (Mm - G)
    big = sp.Matrix(sp.BlockMatrix([[A, -Omega * C], [Omega * C, A]]))
    c12, c34 = sp.cos(hat12), sp.cos(hat34)
    row4 = z * (c12 * sp.sin(mean12) + (1 if printed else -1) * c34 * sp.sin(mean34))
    rhs = Omega**2 * sp.Matrix([M * eps, 0, 0, 0]) + 2 * m * R * Omega**2 * sp.Matrix([
        c12 * sp.cos(mean12) + c34 * sp.cos(mean34), z * (c12 * sp.cos(mean12) - c34 * sp.cos(mean34)),
        c12 * sp.sin(mean12) + c34 * sp.sin(mean34), row4])
    return list(big * sp.Matrix(xvec) - rhs)


def a_sum_23(M, eps, R):
    """(23): a_1 + a_2."""
    return M * eps / (8 * R)


def a1_a2_34(M, eps, R, kappa):
    """(33)-(34)."""
    return M * eps * (1 + kappa) / (16 * R), M * eps * (1 - kappa) / (16 * R)


def normal_form_20(mu, a1, a2, v1, v2):
    """(20) (and (17)): the D4-equivariant pitchfork."""
    return sp.Matrix([mu * v1 - a1 * v1**3 - a2 * v2**2 * v1, mu * v2 - a1 * v2**3 - a2 * v1**2 * v2])


def unfolding_39(mu1, mu2, a1, a2, v1, v2):
    """(39): the D4 pitchfork unfolded by a misalignment (mu_1 = m - m_t, mu_2 = m - m_b)."""
    return sp.Matrix([mu1 * v1 - a1 * v1**3 - a2 * v2**2 * v1, mu2 * v2 - a1 * v2**3 - a2 * v1**2 * v2])


def jacobian_36(mu, a1, a2, v1, v2):
    """(36) as printed."""
    return sp.Matrix([[mu - 3 * a1 * v1**2 - a2 * v2**2, -2 * a2 * v1 * v2],
                      [-2 * a2 * v1 * v2, mu - 3 * a1 * v2**2 - a2 * v1**2]])


def jacobian_37(mu, a1, a2):
    """(37): Df at C3 = (0, alpha_hat), alpha_hat^2 = mu/a1."""
    return sp.Matrix([[mu * (1 - a2 / a1), 0], [0, -2 * mu]])


def jacobian_38(mu, a1, a2):
    """(38): Df at B = (alpha_hat, alpha_hat), alpha_hat^2 = mu/(a1 + a2)."""
    d = a1 + a2
    return sp.Matrix([[-2 * a1 * mu / d, -2 * a2 * mu / d], [-2 * a2 * mu / d, -2 * a1 * mu / d]])


def oscillator_40(s_, c_, Omega):
    """(40): s' = s + Omega c - s (s^2 + c^2), c' = -Omega s + c - c (s^2 + c^2)."""
    r2 = s_**2 + c_**2
    return s_ + Omega * c_ - s_ * r2, -Omega * s_ + c_ - c_ * r2


# Numbers printed in the text: (value, digits as printed).
PRINTED = {
    "Omega_cyl (11)": 1.0, "Omega_con (11)": 1.81,
    "Omega_cyl (42)": 0.89, "Omega_con (42)": 4.07,
    "Omega_cyl,X (43)": 1.0, "Omega_con,X (43)": 1.65, "Omega_cyl,Y (43)": 2.24, "Omega_con,Y (43)": 3.79,
}
