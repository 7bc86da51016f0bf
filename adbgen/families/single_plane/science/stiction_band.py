"""The stuck-equilibrium band of the thesis' balancer (issue 37, item 3): where both balls can stay stuck on
the race at constant speed, how wide that set is against the static friction coefficient mu_s, and the
residual vibration r it leaves.

Closed form.  A stuck ball is fixed in the rotating frame, so a stuck steady state is a static solution of
the thesis' rotating-frame equations (2.25) with every rate and acceleration 0 (the balls' rows (2.26) are
replaced by the stuck constraint phi_i' = 0): with z = x + i y (lengths over R, (2.15)),

    (K + 2 i Omega zeta) z = Omega^2 (delta + mu sum_k e^{i phi_k}),   K = 1 - Omega^2 (1 + n mu)   (2.27),

for ANY ball angles phi_k.  Ball k then moves on a circle, its inertial acceleration -omega^2 (Z + R e^{i phi_k})
in the rotating frame's axes (Z = R z), so in units of m R omega^2 the race must push it

    tangentially  F_k = -Im(z e^{-i phi_k})   (the force the stuck constraint needs, model measure stick_force_k),
    inwards       N_k = 1 + Re(z e^{-i phi_k}) (the normal force, normal_force_k),

and it stays stuck while |F_k| <= mu_s N_k (the stiction cone, stick_margin_k >= 0).  The band is the set of
(phi_1, phi_2) where both hold.  Without friction it shrinks to the balanced state (3.6) (z = 0: for n = 2,
phi_1 = -phi_2 = theta*, cos theta* = -delta / (2 mu)).

To first order in mu_s (1 + Re(.) -> 1, phi_k -> +-theta*) both conditions read |b cos theta*| + |a sin theta*|
<= mu_s for z = a + i b: in the plane of z the band is a rhombus, whatever Omega, zeta, so the largest
residual vibration the band leaves is

    r_max = mu_s / min(|cos theta*|, |sin theta*|)   (= 2 mu mu_s / delta when delta < sqrt(2) mu),

ten times mu_s for (5.1): balls nearly opposite each other at +-theta* (cos theta* = -0.1) are pushed almost
only radially by a displacement along y.  Along the symmetric line phi_1 = -phi_2 = theta its width is
mu_s / (mu sin theta* max_k |Im(g e^{-+i theta*})|), g = Omega^2 / (K + 2 i Omega zeta) (`width_first_order`).

Stability of a stuck state: with both balls held the system is the rotor alone carrying the balls' mass, the
linear rotating-frame rotor (2.25) with phi_k' = phi_k'' = 0, whose eigenvalues `stuck_eigenvalues` gives; a
stuck state strictly inside the band is stable when they all have negative real part (a small disturbance
keeps the margins positive and decays), on the band's edge it is marginal.  Whether a large disturbance
releases a ball is a question for the hybrid engine, not for this linearisation.

Thesis-specific (n = 2, the parameters (5.1)); checked against the emitted friction model's own measures in
tests/families/single_plane/science/test_stiction_band.py.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Rotor:
    """The thesis' dimensionless parameters (2.16), (2.19); defaults (5.1).  beta plays no part: a stuck
    ball does not move against the race, so its drag is 0."""
    Omega: float = 4.0
    zeta: float = 0.01
    delta: float = 0.01
    mu: float = 0.05
    n: int = 2

    @property
    def gain(self) -> complex:
        """g = Omega^2 / (K + 2 i Omega zeta): z = g (delta + mu sum e^{i phi_k}), (2.25) at rest."""
        K = 1.0 - self.Omega**2 * (1.0 + self.n * self.mu)
        return self.Omega**2 / complex(K, 2.0 * self.Omega * self.zeta)

    @property
    def theta_star(self) -> float:
        """The balanced state (3.6) for n = 2: phi_1 = -phi_2 = theta*, cos theta* = -delta / (2 mu)."""
        if self.n != 2 or self.delta > 2 * self.mu:
            raise ValueError("the balanced state (3.6) with n = 2 needs delta <= 2 mu")
        return float(np.arccos(-self.delta / (2 * self.mu)))


def displacement(rotor: Rotor, phis) -> np.ndarray:
    """z = x + i y (over R) of the stuck steady state with the balls at phis (last axis: the balls)."""
    phis = np.asarray(phis, dtype=float)
    return rotor.gain * (rotor.delta + rotor.mu * np.exp(1j * phis).sum(axis=-1))


def loads(rotor: Rotor, phis) -> tuple[np.ndarray, np.ndarray]:
    """(F_k, N_k) in units of m R omega^2: the tangential force a stuck ball needs and the race's normal
    force, -Im(z e^{-i phi_k}) and 1 + Re(z e^{-i phi_k})."""
    phis = np.asarray(phis, dtype=float)
    u = displacement(rotor, phis)[..., None] * np.exp(-1j * phis)
    return -u.imag, 1.0 + u.real


def margin(rotor: Rotor, phis, mu_s: float) -> np.ndarray:
    """min_k (mu_s N_k - |F_k|) in units of m R omega^2: >= 0 where every ball can stay stuck."""
    F, N = loads(rotor, phis)
    return (mu_s * N - np.abs(F)).min(axis=-1)


def residual_imbalance(rotor: Rotor, phis) -> np.ndarray:
    """|delta + mu sum e^{i phi_k}|: the imbalance left (over M R), r = |g| times it."""
    return np.abs(rotor.delta + rotor.mu * np.exp(1j * np.asarray(phis, float)).sum(axis=-1))


def r_max_first_order(rotor: Rotor, mu_s: float) -> float:
    """The largest residual vibration r over the band to first order in mu_s (the rhombus' far vertex)."""
    th = rotor.theta_star
    return mu_s / min(abs(np.cos(th)), abs(np.sin(th)))


def width_first_order(rotor: Rotor, mu_s: float) -> float:
    """The band's width along phi_1 = -phi_2 = theta, to first order in mu_s."""
    th = rotor.theta_star
    pull = max(abs((rotor.gain * np.exp(-1j * th)).imag), abs((rotor.gain * np.exp(1j * th)).imag))
    return mu_s / (rotor.mu * np.sin(th) * pull)


def symmetric_interval(rotor: Rotor, mu_s: float, step: float = 1e-3) -> tuple[float, float]:
    """The band along phi_1 = -phi_2 = theta: the interval of theta around theta* where both balls can stay
    stuck, its ends found by a scan of `step` and Brent's root finding (scipy.optimize.brentq) to 1e-14."""
    from scipy.optimize import brentq

    th = rotor.theta_star

    def f(theta):
        return float(margin(rotor, [theta, -theta], mu_s))

    ends = []
    for sign in (-1.0, 1.0):
        a = th
        while True:
            b = a + sign * step
            if not 0.0 < b < np.pi:
                raise ValueError(f"the band reaches theta = {b:.3f} at mu_s = {mu_s}: not an interval around theta*")
            if f(b) < 0:
                ends.append(brentq(f, a, b, xtol=1e-14))
                break
            a = b
    return ends[0], ends[1]


def band(rotor: Rotor, mu_s: float, points: int = 1441):
    """The band on a grid of the torus (phi_1, phi_2), `points` a side: its component holding the balanced
    state (periodic neighbours joined), as (the mask over the grid, the area fraction of the torus, the
    largest r = |z| on it, the largest residual imbalance on it).  Grid-resolved (a band thinner than the
    grid's step is missed): `r_max` gives the largest r exactly."""
    from scipy import ndimage

    grid = np.linspace(-np.pi, np.pi, points, endpoint=False)
    P1, P2 = np.meshgrid(grid, grid, indexing="ij")
    phis = np.stack([P1, P2], axis=-1)
    inside = margin(rotor, phis, mu_s) >= 0
    labels, _ = ndimage.label(inside)
    for a, b in ((labels[0, :], labels[-1, :]), (labels[:, 0], labels[:, -1])):  # the torus: wrap the edges
        for la, lb in zip(a, b):
            if la and lb and la != lb:
                labels[labels == lb] = la
    th = rotor.theta_star
    i1, i2 = (int(round((v + np.pi) / (2 * np.pi) * points)) % points for v in (th, -th))
    own = labels[i1, i2]
    if not own:
        return inside & False, 0.0, 0.0, 0.0
    mask = labels == own
    r = np.abs(displacement(rotor, phis))[mask]
    return mask, float(mask.mean()), float(r.max()), float(residual_imbalance(rotor, phis)[mask].max())


def angles_of(rotor: Rotor, z) -> np.ndarray | None:
    """The ball angles (n = 2) whose stuck state has displacement z, the branch through the balanced state
    (phi_1 = theta*, phi_2 = -theta* at z = 0): e^{i phi_1} + e^{i phi_2} = S = (z / g - delta) / mu, so
    phi_1,2 = arg S -+ arccos(|S| / 2).  None where |S| > 2 (no two balls give that z)."""
    S = (z / rotor.gain - rotor.delta) / rotor.mu
    if abs(S) > 2:
        return None
    half = np.arccos(abs(S) / 2)
    return np.array([np.angle(S) - half, np.angle(S) + half])


def reach(rotor: Rotor, mu_s: float, alpha: float, step: float = 1e-4) -> tuple[float, bool]:
    """How far the band reaches in the plane of z along the ray z = rho e^{i alpha}: the first rho where a
    ball's margin turns negative (a scan of `step`, then brentq to 1e-15), and whether it ends there (True)
    or at the balls' coincidence |S| = 2 (False: the band goes on, over the balls' other labelling)."""
    from scipy.optimize import brentq

    def f(rho):
        phis = angles_of(rotor, rho * np.exp(1j * alpha))
        return None if phis is None else float(margin(rotor, phis, mu_s))

    a = 0.0
    while True:
        b = a + step
        value = f(b)
        if value is None:
            return a, False
        if value < 0:
            return brentq(f, a, b, xtol=1e-15), True
        a = b


def r_max(rotor: Rotor, mu_s: float, directions: int = 2880) -> tuple[float, bool]:
    """The largest r = |z| over the band (taken star-shaped about z = 0 in the plane of z): the largest
    `reach` over `directions` rays, refined by a bounded scalar search (scipy minimize_scalar) around the
    best; and whether every ray ended on the stiction cone."""
    from scipy.optimize import minimize_scalar

    alphas = np.linspace(0, 2 * np.pi, directions, endpoint=False)
    reaches = [reach(rotor, mu_s, a) for a in alphas]
    k = int(np.argmax([r for r, _ in reaches]))
    h = 2 * np.pi / directions
    best = minimize_scalar(lambda a: -reach(rotor, mu_s, a)[0], bounds=(alphas[k] - h, alphas[k] + h),
                           method="bounded", options={"xatol": 1e-12})
    return max(-float(best.fun), reaches[k][0]), all(ended for _, ended in reaches)


def stuck_eigenvalues(rotor: Rotor) -> np.ndarray:
    """Eigenvalues of (2.25) with the balls held (phi_k' = phi_k'' = 0), in (x, y, x', y'): the same at every
    stuck state (the balls' angles enter only the forcing)."""
    m = 1.0 + rotor.n * rotor.mu
    K = 1.0 - rotor.Omega**2 * m
    C = np.array([[2 * rotor.zeta, -2 * rotor.Omega * m], [2 * rotor.Omega * m, 2 * rotor.zeta]])
    S = np.array([[K, -2 * rotor.Omega * rotor.zeta], [2 * rotor.Omega * rotor.zeta, K]])
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-S / m, -C / m]])
    return np.linalg.eigvals(A)


def table(rotor: Rotor, mu_values, points: int = 1441) -> list[dict]:
    """One row per mu_s: the symmetric interval's width (exact, first order), the band's area fraction, its
    largest r (grid; first order) and largest residual imbalance."""
    rows = []
    for mu_s in mu_values:
        lo, hi = symmetric_interval(rotor, mu_s)
        _, area, _, _ = band(rotor, mu_s, points)
        largest, closed = r_max(rotor, mu_s)
        rows.append({"mu_s": float(mu_s), "width": hi - lo, "width_first_order": width_first_order(rotor, mu_s),
                     "area_fraction": area, "r_max": largest, "r_max_first_order": r_max_first_order(rotor, mu_s),
                     "imbalance_max": largest / abs(rotor.gain), "band_closed": closed})
    return rows


MU_S_VALUES = (0.0005, 0.001, 0.002, 0.005, 0.01, 0.015, 0.02, 0.025)


def figure(out, rotor: Rotor = Rotor(), mu_values=MU_S_VALUES) -> list[dict]:
    """docs/figures/stiction_band.png and .json: the band's width along phi_1 = -phi_2 and its area share
    of the torus, and the largest residual r and imbalance on it, against mu_s (exact; first order dashed).
    Drawn by `python3 -m adbgen.families.single_plane.science.stiction_band docs/figures`."""
    import json
    from pathlib import Path

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rows = table(rotor, mu_values)
    mus = [row["mu_s"] for row in rows]
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4))
    left.plot(mus, [row["width"] for row in rows], "o-", label="width along phi_1 = -phi_2 (rad)")
    left.plot(mus, [row["width_first_order"] for row in rows], "--", label="its first order")
    left.plot(mus, [row["area_fraction"] for row in rows], "s-", label="area share of the torus (grid)")
    left.set_xlabel("mu_s")
    left.legend(fontsize=8)
    left.set_title("stuck band around the balanced state, thesis (5.1), n = 2", fontsize=9)
    right.plot(mus, [row["r_max"] for row in rows], "o-", label="largest residual r = |z| on the band")
    right.plot(mus, [row["imbalance_max"] for row in rows], "s-", label="largest |delta + mu sum e^{i phi}|")
    right.plot(mus, [min(row["r_max_first_order"], rows[-1]["r_max"] * 1.5) for row in rows], "--",
               label="first order mu_s / |cos theta*| (clipped)")
    right.set_xlabel("mu_s")
    right.legend(fontsize=8)
    right.set_title("residual vibration at rest (lengths over R)", fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "stiction_band.png", dpi=110)
    plt.close(fig)
    (out / "stiction_band.json").write_text(json.dumps(rows, indent=1) + "\n")
    return rows


if __name__ == "__main__":
    import sys

    for row in figure(sys.argv[1] if len(sys.argv) > 1 else "docs/figures"):
        print(row)
