"""What a ROSS rotor says about itself as a rigid body on two bearings (issue 38 item 1).

Everything is read through ROSS's own API (the same in ROSS 2.3 on Python 3.11 and ROSS 3 on >= 3.12):
`Rotor.M0` (the shaft and disk elements' assembled mass matrix), the elements' `dof_mapping()` and
`dof_global_index`, `Rotor.m`, `Rotor.CG`, `Rotor.Ip` (ROSS's element sums), and each bearing's
`K(frequency)`, `C(frequency)`, `M(frequency)` at the operating speed.

Rigid-body properties: the mass matrix projected on the rigid-body motions of the shaft's nodes,
P^T M0 P, with P's columns the translations in x and y, the tilts about x and y through the centre of
mass (x = beta (z - z_G), y = -alpha (z - z_G), ROSS's sign of its `It`) and the spin about z.  For a
rigid body this is diag(m, m, J_t, J_t, J_p) exactly; the translation-tilt coupling m (z_G' - z_G) of
the projection vanishing is the check that z_G is the centre of mass.  Each is compared with ROSS's
element sums (`Rotor.m`, `Rotor.CG`, `Rotor.Ip`) to round-off.

Axial positions in the two-plane scene are measured from the centre of mass (paper section 2.1: G at
z = 0): bearing 1 at +l_1 >= 0, bearing 2 at -l_2 <= 0, races at z - z_G.
"""

from __future__ import annotations

import contextlib
import math
import os
import sys
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import AdbgenError

RTOL = 1e-9  # projection against element sums: both are sums of the same element matrices


class RotorError(AdbgenError):
    """A ROSS rotor the rigid two-plane scene cannot represent (one line says why)."""


@contextlib.contextmanager
def _quiet():
    """Stdout (C level too: ccp's REFPROP notice) and warnings off while ROSS imports."""
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        with open(os.devnull, "w") as null, warnings.catch_warnings():
            warnings.simplefilter("ignore")
            os.dup2(null.fileno(), 1)
            yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)


def import_ross():
    """ROSS, imported with its dependency ccp's REFPROP notice (printed on stdout) kept off our output."""
    try:
        with _quiet():
            import ross
    except ImportError as exc:
        raise RotorError(f"ROSS is not installed ({exc}); pip install 'adbgen[ross]'") from None
    return ross


def load_rotor(source: Any):
    """A ROSS `Rotor` as given, or read from the .toml or .json file `Rotor.save` writes."""
    ross = import_ross()
    if isinstance(source, ross.Rotor):
        return source
    path = Path(source)
    if not path.is_file():
        raise RotorError(f"no ROSS rotor file at {path}")
    if path.suffix.lower() not in (".toml", ".json"):
        raise RotorError(f"{path}: a ROSS rotor file is the .toml or .json that Rotor.save writes")
    try:
        with _quiet():
            return ross.Rotor.load(path)
    except Exception as exc:  # ROSS raises what its parser raises
        raise RotorError(f"{path}: ROSS cannot load it as a rotor: {type(exc).__name__}: {exc}") from None


@dataclass(frozen=True)
class RigidBody:
    """The rotor as one rigid body: mass, axial centre of mass, transverse and polar inertia about G."""

    mass: float  # kg
    z_cg: float  # m, in ROSS's axial coordinate
    transverse_inertia: float  # J_t, kg m^2, about an axis through G normal to the shaft
    polar_inertia: float  # J_p, kg m^2
    projection: np.ndarray  # P^T M0 P (5 x 5: x, y, tilt about x, tilt about y, spin)


def node_position(rotor, node: int) -> float:
    """Axial position of a ROSS node (its index in `Rotor.nodes`)."""
    nodes = [int(n) for n in rotor.nodes]
    if int(node) not in nodes:
        raise RotorError(f"node {node} is not a node of the rotor (nodes {nodes[0]}..{nodes[-1]})")
    return float(rotor.nodes_pos[nodes.index(int(node))])


def rigid_modes(rotor, z_ref: float) -> np.ndarray:
    """P: the rigid-body motions of the shaft's nodes (columns x, y, alpha, beta, theta), tilts about z_ref."""
    P = np.zeros((rotor.ndof, 5))
    for elm in rotor.shaft_elements:
        dofs = list(elm.dof_global_index.values())
        mp = elm.dof_mapping()
        for end, n in (("0", elm.n_l), ("1", elm.n_r)):
            z = node_position(rotor, n) - z_ref
            P[dofs[mp[f"x_{end}"]], 0] = 1.0
            P[dofs[mp[f"y_{end}"]], 1] = 1.0
            P[dofs[mp[f"y_{end}"]], 2] = -z  # tilt alpha about x: y = -alpha z
            P[dofs[mp[f"alpha_{end}"]], 2] = 1.0
            P[dofs[mp[f"x_{end}"]], 3] = z  # tilt beta about y: x = beta z
            P[dofs[mp[f"beta_{end}"]], 3] = 1.0
            if f"theta_{end}" in mp:
                P[dofs[mp[f"theta_{end}"]], 4] = 1.0
    return P


def rigid_body(rotor) -> RigidBody:
    """Mass, centre of mass, J_t, J_p from ROSS's mass matrix M0 projected on the rigid-body motions.

    The centre of mass is where the translation-tilt coupling of the projection vanishes:
    P_0(x)^T M0 P_0(beta) = m (z_G - z_0) with the tilts taken about z_0 = 0.  Each value is checked
    against ROSS's element sums (`Rotor.m`, `Rotor.CG`, `Rotor.Ip`); a disagreement is an error.
    """
    if not hasattr(rotor, "number_dof") or rotor.number_dof != 6:
        raise RotorError("the bridge reads ROSS's 6-dof shaft elements (x, y, z, alpha, beta, theta); "
                         f"this rotor has {getattr(rotor, 'number_dof', '?')} dof per node")
    M0 = np.asarray(rotor.M0, dtype=float)
    P0 = rigid_modes(rotor, 0.0)
    mass = float(P0[:, 0] @ M0 @ P0[:, 0])
    z_cg = float(P0[:, 0] @ M0 @ P0[:, 3]) / mass
    P = rigid_modes(rotor, z_cg)
    proj = P.T @ M0 @ P
    body = RigidBody(mass, z_cg, float(proj[3, 3]), float(proj[4, 4]), proj)
    check_rigid_body(rotor, body)
    return body


def check_rigid_body(rotor, body: RigidBody) -> None:
    """The projection against ROSS's element sums, and its structure: diag(m, m, J_t, J_t, J_p)."""
    p = body.projection
    sums = {"mass": (body.mass, float(rotor.m)), "centre of mass": (body.z_cg, float(rotor.CG)),
            "polar inertia": (body.polar_inertia, float(rotor.Ip)),
            "mass (y)": (float(p[1, 1]), body.mass), "transverse inertia (about x)": (float(p[2, 2]), float(p[3, 3]))}
    scale = {"centre of mass": max(float(rotor.L), 1e-300)}
    for what, (ours, theirs) in sums.items():
        if not math.isclose(ours, theirs, rel_tol=0, abs_tol=RTOL * scale.get(what, abs(theirs))):
            raise RotorError(f"rigid-body {what}: ROSS's mass matrix gives {ours!r}, its element sums {theirs!r}")
    off = p - np.diag(np.diag(p))
    big = np.max(np.abs(off)) / np.max(np.abs(np.diag(p)))
    if big > RTOL * 1e3:
        raise RotorError(f"the rigid-body projection of ROSS's mass matrix is not diagonal "
                         f"(largest coupling {big:.2e} of the diagonal): the rotor is not axisymmetric")


@dataclass(frozen=True)
class Support:
    """One bearing as the scene takes it: axial position and kxx, kyy, cxx, cyy at the operating speed."""

    node: int
    z: float
    k: tuple[float, float]
    c: tuple[float, float]


def supports(rotor, speed: float) -> tuple[Support, Support]:
    """The two bearings' direct coefficients at `speed` (rad/s) from each bearing's K, C, M(frequency).

    Refused in one line: other than two bearings, a bearing on a node not of the shaft (support masses,
    point masses), cross-coupled stiffness or damping (kxy, kyx, cxy, cyx; the paper's (1) has none),
    bearing mass coefficients.
    """
    bearings = list(rotor.bearing_elements)
    if len(bearings) != 2:
        raise RotorError(f"the two-plane scene has two bearings; this rotor has {len(bearings)}")
    if list(rotor.point_mass_elements):
        raise RotorError("the rotor has point masses (support masses): the rigid two-plane scene has none")
    out = []
    for b in bearings:
        if getattr(b, "n_link", None) is not None:
            raise RotorError(f"bearing at node {b.n} links to another node: the scene's bearings are to ground")
        mp = b.dof_mapping()
        ix, iy = mp["x_0"], mp["y_0"]
        K, C, Mb = (np.asarray(f(speed), dtype=float) for f in (b.K, b.C, b.M))
        for name, A in (("stiffness", K), ("damping", C)):
            cross = max(abs(A[ix, iy]), abs(A[iy, ix]))
            if cross > 1e-12 * max(abs(A[ix, ix]), abs(A[iy, iy]), 1e-300):
                raise RotorError(f"bearing at node {b.n} has cross-coupled {name} ({A[ix, iy]:.6g}, {A[iy, ix]:.6g} "
                                 f"at {speed:g} rad/s); the two-plane scene carries kxx, kyy, cxx, cyy only")
        if np.any(Mb != 0):
            raise RotorError(f"bearing at node {b.n} has mass coefficients; the two-plane scene has none")
        out.append(Support(int(b.n), node_position(rotor, b.n), (float(K[ix, ix]), float(K[iy, iy])),
                           (float(C[ix, ix]), float(C[iy, iy]))))
    return tuple(sorted(out, key=lambda s: -s.z))  # bearing 1 at +l_1 (larger z), bearing 2 at -l_2


def speed_dependent(rotor) -> bool:
    """Whether any bearing's coefficients change with the frequency (ROSS interpolates them)."""
    return any(getattr(b, "frequency", None) is not None and np.size(b.frequency) > 1 for b in rotor.bearing_elements)


@dataclass(frozen=True)
class Unbalance:
    """A point unbalance as ROSS's `run_unbalance_response` takes it: node, magnitude (kg m), phase (rad)."""

    node: int
    magnitude: float
    phase: float


def imbalance(rotor, body: RigidBody, unbalances: list[Unbalance]) -> dict:
    """The scene's static and couple imbalance from point unbalances (paper section 2.1).

    Static: M eps e^{i beta'} = sum u_k e^{i phi_k}.  Couple: the product of inertia of the unbalances
    about G, C e^{i gamma} = sum u_k (z_k - z_G) e^{i phi_k}, equals that of a principal axis tilted
    by chi about the body's eta axis, (J_t - J_p) sin chi cos chi (the model's inertia
    R_chi diag(J_t, J_t, J_p) R_chi^T), the body's xi axis put at gamma; then beta = beta' - gamma.
    """
    s = sum(u.magnitude * np.exp(1j * u.phase) for u in unbalances) if unbalances else 0j
    c = sum(u.magnitude * (node_position(rotor, u.node) - body.z_cg) * np.exp(1j * u.phase)
            for u in unbalances) if unbalances else 0j
    dJ = body.transverse_inertia - body.polar_inertia
    gamma = float(np.angle(c)) if abs(c) > 0 else 0.0
    chi = 0.0
    if abs(c) > 0:
        if dJ == 0:
            raise RotorError("a couple imbalance on a rotor with J_t = J_p tilts no principal axis")
        sin2 = 2 * abs(c) / dJ
        if abs(sin2) >= 1:
            raise RotorError(f"couple imbalance {abs(c):.4g} kg m^2 is too large for J_t - J_p = {dJ:.4g} kg m^2")
        chi = 0.5 * math.asin(sin2)
    beta = float(np.angle(s)) - gamma if abs(s) > 0 else 0.0
    beta = math.remainder(beta, 2 * math.pi)
    return {"eccentricity": float(abs(s)) / body.mass, "imbalance_phase": beta, "misalignment": chi}
