"""The paper's stability charts (Figs. 10(a-c), 11, 13(a-d), 14(a, b)) as data: the model, its parameter set, the
parameters tied to the imbalance (m/M = eps/R: what `adbgen continue --tie` is given), the ranges and the paper's
words.  Read by the family's science (`science.periodic_orbits`, the reproduction) and by `adbgen bench orbits`
(which times the charts); no computation here.
"""

from __future__ import annotations

from dataclasses import dataclass, field


def ties(cb_ratio: float = 0.01, dynamic: bool = False, heavy: float = 1.0) -> list[str]:
    """m/M = eps/R (static) or eps/R + chi with chi = eps/R (dynamic), c_b/m = cb_ratio in both races; `heavy`
    scales ball 1's mass (Fig. 13(c): 1.2)."""
    out = ["chi=epsilon/R_t"] if dynamic else []
    total = "2*epsilon/R_t" if dynamic else "epsilon/R_t"
    out += [f"m_2=M*{total}", "m_3=m_2", "m_4=m_2", f"m_1={heavy}*m_2" if heavy != 1.0 else "m_1=m_2",
            f"c_bt={cb_ratio}*m_2", "c_bb=c_bt"]
    return out


@dataclass
class ChartCase:
    figure: str
    model: str
    sets: dict
    ties: list
    text: str  # the paper's description
    range1: tuple = (0.5, 5.0)
    range2: tuple = (1e-5, 0.1)
    scale2: float = 1.0  # the paper's axis / epsilon (2 for eps/R + chi with chi = eps/R)
    label2: str = "eps/R = m/M"
    note: str = ""
    same_as: str = ""
    extra: dict = field(default_factory=dict)


CHARTS = [
    ChartCase("10(a)", "two_plane_rotating", {"beta": 0.0, "chi": 0.0}, ties(),
              "static imbalance, (41) (= (10)): \"The main area of interest for applications occurs where there is a "
              "large connected stable region for small eccentricities and supercritical rotation speeds. The torus "
              "instability curve which bounds this region asymptotes towards Omega = Omega_con as eps/R = m/M -> 0, "
              "hence, there is no stable region in the subcritical regime.\"",
              note="isotropic supports: the rotating-frame model, where the fixed frame's torus curves are Hopf curves "
                   "of the steady state B"),
    ChartCase("10(b)", "two_plane_rotating", {"beta": 1.0}, ties(dynamic=True), scale2=2.0, label2="eps/R + chi = m/M",
              text="dynamic imbalance, (41): \"We find that the regions of stability remain largely unchanged, however, "
                   "extra torus curves are now present. As discussed in Section 3, these arise because the introduction "
                   "of a small misalignment breaks the symmetry between the two races.\"",
              note="eps/R = chi, beta = 1, c_b/m = 0.01: the set-up of Fig. 14(a), which is this chart"),
    ChartCase("10(c)", "two_plane_rotating", {"beta": 0.0, "chi": 0.0, "l_1": 9.0}, ties(),
              "static imbalance, coupled supports (42) (l_1 = 9, l_2 = 3; Omega_cyl ~ 0.89, Omega_con ~ 4.07): "
              "\"bifurcation curves asymptote to the critical frequencies as the ball mass and eccentricity both tend "
              "to zero. The stable regions in the high eccentricity regimes have now almost disappeared, although more "
              "importantly, we find that the stable region for low eccentricities still exists, and has the same "
              "qualitative shape as before.\"",
              note="(42): bearing 1 at l_1 = 9, the rest as (10)"),
    ChartCase("11", "two_plane_fixed", {"beta": 0.0, "chi": 0.0}, ties(),
              "anisotropic supports (43), static imbalance: \"The stable region for the high eccentricity regime no "
              "longer exists, however, new 'wedge' shaped stable regions now occur for low eccentricities when the "
              "speeds are in the vicinity of the rigid body resonances. The bifurcation curves again emanate at the "
              "critical frequencies\" (1, 1.65, 2.24, 3.79 printed; 1, 1.659, 2.236, 3.777 derived, see the errata).",
              note="fixed frame, forced: B is the periodic response at the forcing period, its boundaries torus and "
                   "period-doubling curves of its Floquet multipliers"),
    ChartCase("13(a)", "two_plane_rotating", {"beta": 0.0, "chi": 0.0}, ties(),
              "'long' rotor, static imbalance: \"Panel (a) serves as the control case and is the same (except for the "
              "aspect ratio) as that of Figure 10(a).\"", same_as="10(a)"),
    ChartCase("13(b)", "two_plane_rotating", {"beta": 0.0, "chi": 0.0, "J_t": 0.5, "J_p": 1.0}, ties(),
              "'disk' rotor: \"the eigenfrequency corresponding to the conical whirl is always greater than the rotor "
              "speed Omega. This means that there is no conical critical speed Omega_con ... hence the ABB is not "
              "stabilised with respect to conical motions.\"",
              note="the paper does not print the disk's inertias; here J_t = 0.5, J_p = 1 (a thin disk, J_p = 2 J_t)"),
    ChartCase("13(c)", "two_plane_rotating", {"beta": 0.0, "chi": 0.0}, ties(heavy=1.2),
              "one ball 20 % heavier: \"the stable regions remain largely unchanged, however extra Hopf instability "
              "curves are present. These arise because the introduction of a different ball mass breaks the symmetry "
              "of the system.\""),
    ChartCase("13(d)", "two_plane_rotating", {"beta": 0.0, "chi": 0.0, "z_t": 1.0, "z_b": -3.0}, ties(),
              "balancing planes at z = 1 and 3: \"again the main point to note is the robustness of the stable region "
              "for low eccentricities and supercritical rotation speeds.\""),
    ChartCase("14(a)", "two_plane_rotating", {"beta": 1.0}, ties(dynamic=True), scale2=2.0, label2="eps/R + chi = m/M",
              text="'long' rotor, dynamic imbalance (eps/R = chi, beta = 1), c_b/m = 0.01: the chart with the marked "
                   "Hopf point (eps/R + chi = 0.01) whose limit cycles Fig. 14(c, d) continue.", same_as="10(b)"),
    ChartCase("14(b)", "two_plane_rotating", {"beta": 1.0}, ties(0.1, dynamic=True), scale2=2.0,
              label2="eps/R + chi = m/M",
              text="the same with c_b/m = 0.1: \"As a consequence much of the complicated structure in the high "
                   "eccentricity regime has been smoothed out.\""),
]
