"""The B/C3 stability exchange at the critical speeds, paper section 3.2.3, on the generated
`two_plane_rotating` model (rotating frame (7)-(8), set-up (10), all four balls of mass m).

Three computations on the generated rhs, jac and mass_matrix only (no SymPy):

* **The normal form's coefficients by the paper's method** (section 3.2.2: "the best quadratic
  approximations to the branches"): the branches B (alpha_1,2 = b_12 +- alpha_hat,
  alpha_3,4 = b_34 +- h_34) and C3 (top race coincident, alpha_3,4 = b_34 +- alpha_hat) are solved by
  Newton with the ball mass m free at alpha_hat = 1, 2, 3 x 1e-3; m - m_c = c_2 s^2 + c_4 s^4 + c_6 s^6
  through the three points gives a_1 + a_2 (B, (21)) and a_1 (C3, (22)).  kappa = (a_1 - a_2) /
  (a_1 + a_2) ((23), (34)); B's eigenvalues (38) are -2 mu and -2 mu kappa, C3's (37) mu (1 - a_2/a_1)
  and -2 mu: B and C3 exchange stability where kappa changes sign, at its zero (Omega_cyl of (32))
  and at its pole (Omega_con).  Undamped (c = 0), as the paper's (28)-(32).
* **Critical speeds with the balls frozen** ((32) with m = m_c): the rotor block of the static
  stiffness K = -dF/dq = -M(y) dq''/dq at rest (exact at a steady state, where F = 0), c = 0;
  det K_rotor(Omega) = 0 located by brentq.
* **The full damped model's spectrum at B** near the pitchfork (m = m_c (1 + 1e-3)), split by the
  race swap gamma_r ((13)-(14): alpha_1 <-> alpha_3, alpha_2 <-> alpha_4, phi_x, phi_y -> -phi_x,
  -phi_y), which commutes with the Jacobian at B: its even part holds B's symmetric mode (1, 1) of (38),
  its odd part the mode (1, -1) towards C3.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, root

from ....analysis.loading import AnalysisError, Model
from ....analysis.steady import jacobian, refine, residual

MODEL = "two_plane_rotating"
RACE_DAMPING = 0.01  # c_b / m of (10)
S_VALUES = (1e-3, 2e-3, 3e-3)  # alpha_hat on the branches


def _index(model: Model, names) -> list[int]:
    return [model.index(n) for n in names]


def race_swap(model: Model) -> np.ndarray:
    """gamma_r of (13)-(14) as a state permutation with signs (N x N): the races exchanged, the tilt
    reversed (z_t = -z_b): the generated module's declared "race-swap" symmetry, (P y)[k] = s_k y[j_k]."""
    sym = next((s for s in model.symmetries if s["kind"] == "race-swap"), None)
    if sym is None:
        raise AnalysisError(f"{model.name} declares no race swap")
    P = np.zeros((model.n_states, model.n_states))
    P[np.arange(model.n_states), sym["states"]] = sym["signs"]
    return P


@dataclass
class Pitchfork:
    """The symmetric set-up (10) of `model` with every ball of mass m (race damping c_b = 0.01 m)."""

    model: Model
    values: dict  # other parameters by name (e.g. Omega, epsilon, c_1, c_2)

    def params(self, m: float, **more) -> np.ndarray:
        v = dict(self.values, **more)
        v.update({f"m_{k}": m for k in range(1, 5)})
        v.update({"c_bt": RACE_DAMPING * m, "c_bb": RACE_DAMPING * m})
        return self.model.params(v)

    @property
    def m_c(self) -> float:
        p = self.model.params(self.values)
        get = lambda name: p[self.model.param_names.index(name)]  # noqa: E731
        return get("M") * get("epsilon") / (4 * get("R_t"))  # the pitchfork (section 3.2.1)

    def state(self, angles) -> np.ndarray:
        y = np.zeros(self.model.n_states)
        y[_index(self.model, ["alpha_1", "alpha_2", "alpha_3", "alpha_4"])] = angles
        return y

    def _unpack(self, kind: str, z: np.ndarray, s: float) -> tuple[np.ndarray, float]:
        y = np.zeros(self.model.n_states)
        y[_index(self.model, ["x", "y", "phi_x", "phi_y"])] = z[:4]
        if kind == "B":
            b12, b34, h34 = z[4:7]
            angles = [b12 + s, b12 - s, b34 + h34, b34 - h34]
        else:  # C3: top race coincident, bottom race split
            b12, b34 = z[4:6]
            angles = [b12, b12, b34 + s, b34 - s]
        y[_index(self.model, ["alpha_1", "alpha_2", "alpha_3", "alpha_4"])] = angles
        return y, float(z[-1])

    def _equations(self, kind: str, z: np.ndarray, s: float, Omega: float) -> np.ndarray:
        y, m = self._unpack(kind, z, s)
        rates = [i for i, r in enumerate(self.model.roles) if r.endswith("_rate")]
        acc = residual(self.model, y, self.params(m, Omega=Omega))[rates]
        # C3: the coincident balls' rows coincide; one of them is kept
        return acc if kind == "B" else np.delete(acc, self.model.leaves.index("alpha_2") + 4)

    def branch_mass(self, kind: str, s: float, Omega: float) -> float:
        """m on the branch `kind` ("B" or "C3") at alpha_hat = s."""
        # unknowns scaled to order one: the rotor's displacement by m_c, the mass as m / m_c
        scale = np.r_[np.full(4, self.m_c), np.ones(3 if kind == "B" else 2), self.m_c]
        z0 = np.r_[np.zeros(4), math.pi, math.pi, [s] if kind == "B" else [], 1.0]
        f = lambda u: self._equations(kind, u * scale, s, Omega) / self.m_c  # noqa: E731
        sol = root(f, z0, method="hybr", options={"xtol": 1e-15})
        if np.max(np.abs(f(sol.x))) > 1e-12:
            raise AnalysisError(f"{kind} branch at Omega = {Omega:g}, alpha_hat = {s:g}: Newton failed ({sol.message})")
        return float(sol.x[-1] * self.m_c)

    def slope(self, kind: str, Omega: float) -> float:
        """The quadratic coefficient of m - m_c along the branch: a_1 + a_2 (B) or a_1 (C3)."""
        s = np.asarray(S_VALUES)
        # near Omega_con a_1 grows without bound: alpha_hat shrinks so that m - m_c stays ~ 1e-3 m_c
        rough = abs(self.branch_mass(kind, 1e-4, Omega) - self.m_c) / 1e-8
        s = s * min(1.0, math.sqrt(1e-3 * self.m_c / max(rough * s[-1] ** 2, 1e-300)))
        dm = np.array([self.branch_mass(kind, v, Omega) for v in s]) - self.m_c
        A = np.column_stack([s**2, s**4, s**6])
        return float(np.linalg.solve(A, dm)[0])

    def coefficients(self, Omega: float) -> tuple[float, float]:
        """(a_1, a_2) of the normal form (20) at Omega."""
        a1 = self.slope("C3", Omega)
        return a1, self.slope("B", Omega) - a1

    def kappa(self, Omega: float) -> float:
        a1, a2 = self.coefficients(Omega)
        return (a1 - a2) / (a1 + a2)

    def exchange_speeds(self, brackets=((0.8, 1.2), (1.7, 1.9))) -> tuple[float, float]:
        """(Omega_1, Omega_2): the zero of kappa (a_1 = a_2, brentq, xtol 1e-12) and its pole.

        At the pole the C3 branch itself is singular (the tilt stiffness vanishes, Newton cannot
        solve it there), so the pole is the zero of the smooth 1/kappa interpolated (degree 6) through
        13 points of the bracket that keep |1/kappa| > 1e-3 away from it."""
        (a, b), (c, d) = brackets
        zero = brentq(self.kappa, a, b, xtol=1e-12)
        ws, inv = [], []
        for w in np.linspace(c, d, 13):
            try:
                v = 1.0 / self.kappa(float(w))
            except AnalysisError:
                continue
            if abs(v) > 1e-3:
                ws.append(float(w))
                inv.append(v)
        centre = 0.5 * (c + d)
        coef = np.polyfit(np.array(ws) - centre, inv, 6)
        roots = [r.real + centre for r in np.roots(coef) if abs(r.imag) < 1e-12 and c <= r.real + centre <= d]
        if len(roots) != 1:
            raise AnalysisError(f"kappa: {len(roots)} poles in [{c:g}, {d:g}]")
        return zero, float(roots[0])

    # ------------------------------------------------------------------ frozen balls, (32)

    def rotor_stiffness(self, Omega: float, m: float | None = None) -> np.ndarray:
        """K of the rotor rows (x, y, phi_x, phi_y) at B with the balls frozen: -M dq''/dq, c = 0."""
        m = self.m_c if m is None else m
        a = math.acos(min(1.0, self.m_c / m))
        y = self.state([math.pi + a, math.pi - a] * 2)
        p = self.params(m, Omega=Omega, c_1=0.0, c_2=0.0)
        n = self.model.n_coordinates
        J = jacobian(self.model, y, p)
        K = -np.asarray(self.model.module.mass_matrix(0.0, y, p)) @ J[n:, :n]
        return K[:4, :4]

    # ------------------------------------------------------------------ the full model at B

    def slow_spectrum(self, Omega: float, rel: float = 1e-3) -> dict:
        """B at m = m_c (1 + rel), damped (10): the eigenvalue nearest zero of the gamma_r-even and odd
        parts of the Jacobian, and the number of eigenvalues with positive real part in each."""
        m = self.m_c * (1 + rel)
        a = math.acos(self.m_c / m)
        p = self.params(m, Omega=Omega)
        st = refine(self.model, p, self.state([math.pi + a, math.pi - a] * 2))
        P = race_swap(self.model)
        w, V = np.linalg.eigh(0.5 * (P + P.T))
        out = {"y": st.y}
        for name, basis in (("even", V[:, w > 0]), ("odd", V[:, w < 0])):
            ev = np.linalg.eigvals(basis.T @ st.jacobian @ basis)
            out[name] = complex(ev[np.argmin(np.abs(ev))])
            out[f"{name}_unstable"] = int(np.sum(ev.real > 1e-12))
        return out


def slow_sign_changes(pf: Pitchfork, rel: float, part: str, lo: float, hi: float, count: int = 161) -> list[float]:
    """Speeds (midpoints of a grid of `count` on [lo, hi]) where the real part of B's slowest eigenvalue of
    the gamma_r class `part` changes sign, at m = m_c (1 + rel)."""
    w = np.linspace(lo, hi, count)
    v = np.array([pf.slow_spectrum(float(x), rel)[part].real for x in w])
    return [float(0.5 * (w[i] + w[i + 1])) for i in range(count - 1) if np.sign(v[i]) != np.sign(v[i + 1])]


SLOW_STUDY = (1e-2, 1e-3, 1e-4, 1e-5)  # (m - m_c)/m_c


def _critical_from_blocks(pf: Pitchfork, lo: float, hi: float, count: int = 400) -> list[float]:
    """Isotropic rotor, c = 0: K_rotor is diagonal, translation k_eff I and tilt k_eff' I (tested), so
    det K_rotor = k_eff^2 k_eff'^2 touches zero without changing sign; each critical speed is a sign
    change of one diagonal entry."""
    out = []
    for i in (0, 2):
        g = lambda w, i=i: float(pf.rotor_stiffness(w)[i, i])  # noqa: E731
        grid = np.linspace(lo, hi, count)
        vals = [g(w) for w in grid]
        for k in range(count - 1):
            if vals[k] * vals[k + 1] < 0:
                out.append(brentq(g, grid[k], grid[k + 1], xtol=1e-13))
    return sorted(out)


def frozen_critical_speeds(pf: Pitchfork, lo: float = 0.3, hi: float = 4.0) -> list[float]:
    """(32)'s Omega_cyl, Omega_con at m = m_c from the generated equations (balls frozen at B, c = 0)."""
    return _critical_from_blocks(pf, lo, hi)


@dataclass
class Exchange:
    m_c: float
    omega_1: float  # kappa = 0
    omega_2: float  # kappa pole
    frozen: list  # critical speeds with frozen balls, (32)
    small_eps: tuple  # (epsilon, Omega_1, Omega_2) at a smaller imbalance: the balls' share of (32)
    curve: dict  # Omega -> kappa
    slow: dict  # Omega -> slow_spectrum
    study: dict  # rel -> (last sign change of the even slow mode, of the odd one)


def compute(model: Model | None = None, omegas=None, small_epsilon: float = 1e-4) -> Exchange:
    from ....analysis.loading import load_model

    model = model or load_model(MODEL)
    pf = Pitchfork(model, {"c_1": 0.0, "c_2": 0.0})
    w1, w2 = pf.exchange_speeds()
    small = Pitchfork(model, {"c_1": 0.0, "c_2": 0.0, "epsilon": small_epsilon})
    s1, s2 = small.exchange_speeds()
    omegas = np.linspace(0.5, 3.0, 101) if omegas is None else np.asarray(omegas)
    curve = {}
    for w in omegas:
        try:
            curve[float(w)] = pf.kappa(float(w))
        except AnalysisError:
            curve[float(w)] = float("nan")  # at the pole itself
    damped = Pitchfork(model, {})
    slow = {float(w): damped.slow_spectrum(float(w)) for w in omegas}
    study = {}
    for rel in SLOW_STUDY:
        even = slow_sign_changes(damped, rel, "even", 0.9, 1.2)
        odd = slow_sign_changes(damped, rel, "odd", 1.6, 2.0)
        study[rel] = (even[-1] if even else None, odd[-1] if odd else None)
    return Exchange(pf.m_c, w1, w2, frozen_critical_speeds(pf), (small_epsilon, s1, s2), curve, slow, study)
