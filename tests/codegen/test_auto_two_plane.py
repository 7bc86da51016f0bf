"""AUTO-07p on the two-plane models of generated/ (issue 8): the committed files, run as their headers say.

* two_plane_rotating: the balanced state B of (9) (m = 0.003 > m_c = M eps/(4R) = 0.0025, alpha_hat =
  arccos(m_c/m)) continued in Omega from 3 down to 0.5.  B's angles do not depend on Omega, so the
  branch is the same state all along; what changes is its stability.  Every stability change AUTO
  reports is a labelled Hopf point, at a zero of the leading real part of the numba Jacobian's
  eigenvalues at B (brentq, to 1e-5).  Against the normal form (section 3, (35)-(38)): at the start
  (Omega = 3) a_1 > a_2 and B is stable, as (38) predicts and AUTO finds.  The normal form puts B's
  stability changes at the critical speeds with the balls: the conical one, 1.796053 (a_1 - a_2
  changes sign through a pole), and near the cylindrical one, 0.995037 (a_1 = a_2 at 0.9945).  The
  full model loses stability earlier, at a Hopf point (Omega = 2.732: a complex pair, which the
  steady-state normal form does not contain), a second pair crosses at 1.3286, and there is no
  steady-state bifurcation (LP, BP) anywhere on [0.5, 3].
* two_plane_fixed: periodic orbits of the oscillator extension (40) of the anisotropic rotor (43),
  from the exact orbit "B with the rotor at rest", in Omega: the period stays 2 pi / Omega, the balls
  stay at B (no support force acts, whatever the anisotropy).
"""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import brentq

from adbgen.codegen.regenerate import DEFAULT_OUT
from adbgen.families.two_plane import normal_form as nf
from adbgen.families.two_plane.symbols import R, k, l, z

from autorun import auto_toolchain, read_fort7, run_auto, unlabelled_stability_changes  # noqa: F401

TOL = 1e-5


def committed_auto_files(name: str) -> dict[str, str]:
    folder = DEFAULT_OUT / name / "auto"
    files = {p.name: p.read_text() for p in folder.iterdir() if p.is_file()}
    assert f"{name}.c" in files and f"c.{name}" in files, f"generated/{name}/auto incomplete: run `adbgen regenerate`"
    return files


def normal_form_difference():
    """Omega -> a_1 - a_2 at the generated model's defaults ((10), eps = 0.01)."""
    m = importlib.import_module("generated.two_plane_rotating")
    get = lambda name: float(m.DEFAULTS[m.PARAM_NAMES.index(name)])  # noqa: E731
    s = nf.symmetric_model().s
    values = {s.M: get("M"), s.eps: get("epsilon"), R: get("R_t"), s.Jt: get("J_t"), s.Jp: get("J_p"), k: get("k_1"),
              l: get("l_1"), z: get("z_t")}
    co = nf.coefficients()
    return sp.lambdify(s.Omega, (co["a1"] - co["a2"]).xreplace(values))


@pytest.fixture(scope="module")
def rotating(auto_toolchain, tmp_path_factory):
    name = "two_plane_rotating"
    module = importlib.import_module(f"generated.{name}")
    points = run_auto(committed_auto_files(name), name, tmp_path_factory.mktemp("auto_two_plane"))
    return module, points


def spectrum(module, omega: float) -> np.ndarray:
    p = module.START_PARAMETERS.copy()
    p[module.PARAM_NAMES.index("Omega")] = omega
    return np.linalg.eigvals(module.jac(0.0, module.START, p))


def unstable(module, omega: float) -> int:
    return int(np.sum(spectrum(module, omega).real > 1e-12))


def stability_changes(module, hi: float, lo: float, step: float = 0.01) -> list[float]:
    """Omega where the number of unstable eigenvalues of the numba Jacobian at B changes, by bisection."""
    out = []
    grid = np.arange(hi, lo - 1e-12, -step)
    counts = [unstable(module, w) for w in grid]
    for a, b, ca, cb in zip(grid, grid[1:], counts, counts[1:]):
        if ca != cb:
            while a - b > 1e-10:
                mid = 0.5 * (a + b)
                a, b = (mid, b) if unstable(module, mid) == ca else (a, mid)
            out.append(0.5 * (a + b))
    return out


def test_b_is_followed_in_omega_and_its_stability_changes_at_hopf_points(rotating):
    module, points = rotating
    ipar = module.PARAM_NAMES.index("Omega") + 1
    omega = np.array([p.values[f"PAR({ipar})"] for p in points])
    assert omega[0] == pytest.approx(3.0) and points[0].stable
    assert np.all(np.diff(omega) <= 0) and omega.min() == pytest.approx(0.5)
    # the branch is B itself: alpha_1 (U(5)) and the rotor (U(1)..U(4)) stay where stpnt put them
    assert max(abs(p.values["U(5)"] - module.START[4]) for p in points) < 1e-9
    assert max(abs(p.values[f"U({i})"]) for p in points for i in (1, 2, 3, 4)) < 1e-12
    assert unlabelled_stability_changes(points) == []
    special = [p for p in points if p.kind]
    assert {p.kind for p in special} == {"HB"}, [(p.kind, p.values[f"PAR({ipar})"]) for p in special]
    hopf = [p.values[f"PAR({ipar})"] for p in special]
    changes = stability_changes(module, 3.0, 0.5)
    assert len(changes) == len(hopf), (hopf, changes)
    for w_auto, w_eig in zip(hopf, changes):
        assert abs(w_auto - w_eig) < TOL, (w_auto, w_eig)
        # a complex pair crosses (Hopf, not a steady-state bifurcation): two more unstable eigenvalues
        assert unstable(module, w_eig - 1e-4) - unstable(module, w_eig + 1e-4) == 2
        crossing = spectrum(module, w_eig)
        assert abs(crossing[np.argmin(np.abs(crossing.real))].imag) > 1e-3
    first = points.index(special[0])
    assert all(p.stable for p in points[: first + 1]) and not points[first + 1].stable
    print(f"\nAUTO along B: HB at Omega = {hopf}; numba Jacobian: unstable count changes at {changes}")


def test_against_the_normal_form(rotating):
    module, points = rotating
    ipar = module.PARAM_NAMES.index("Omega") + 1
    diff = normal_form_difference()
    assert diff(3.0) > 0 and points[0].stable  # (38): B stable where a_1 > a_2, and so it is at the start
    # the critical speeds with the balls (at m = m_c; `adbgen two-plane steady`): 0.995037, 1.796053
    omega_con = brentq(lambda w: 1 / diff(w), 1.75, 1.8)  # a_1 - a_2 changes sign through a pole there
    assert omega_con == pytest.approx(1.796053, abs=1e-6)
    assert diff(omega_con + 1e-3) > 0 > diff(omega_con - 1e-3)
    equal = brentq(diff, 0.9, 1.1)  # and through zero near the cylindrical one
    assert equal == pytest.approx(0.995037, abs=1e-3)
    first_hopf = next(p.values[f"PAR({ipar})"] for p in points if p.kind == "HB")
    assert first_hopf == pytest.approx(2.732, abs=2e-3) and first_hopf > omega_con
    # between the first Hopf point and Omega_con the normal form says stable, the full model is not
    between = [p for p in points if omega_con < p.values[f"PAR({ipar})"] < first_hopf - 1e-3]
    assert between and not any(p.stable for p in between) and diff(2.0) > 0
    print(f"\nnormal form: B stable for Omega > {omega_con} and < {equal:.4f}; AUTO: stable above {first_hopf:.6f} only")


def test_forced_anisotropic_orbits_in_omega(auto_toolchain, tmp_path):
    name = "two_plane_fixed"
    module = importlib.import_module(f"generated.{name}")
    points = run_auto(committed_auto_files(name), name, tmp_path)
    ipar = module.PARAM_NAMES.index("Omega") + 1
    omega = np.array([p.values[f"PAR({ipar})"] for p in points])
    assert omega[0] == pytest.approx(3.0) and omega.min() == pytest.approx(1.5) and len(points) > 10
    period = np.array([p.values["PERIOD"] for p in points])
    assert np.max(np.abs(period - 2 * math.pi / omega)) < 1e-8  # the oscillator fixes the period
    assert max(abs(p.values["MAX U(1)"]) for p in points) < 1e-12  # the rotor stays at rest: B balances it
