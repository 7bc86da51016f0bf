"""Every two-plane result checked against the paper: exact identities and numbers with stated tolerances.

Each check returns a single-plane `CheckResult` (same type, same runner in `adbgen verify`); none
prints.  The tests call them one by one and add negative controls.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import sympy as sp

from ...core import Coordinate, is_identity, time_derivative
from ...references import two_plane_2011 as paper
from ..single_plane.scene import Scene
from ..single_plane.model import derive as derive_single_plane
from ..single_plane.symbols import DimensionalSymbols
from ...core.checks import (CONSISTENCY, DERIVED, NOT_REPRODUCED, CheckResult, Registered, flip_term,
                             moved, printed_tolerance, timed as _timed)
from . import critical_speeds as cs
from . import normal_form as nf
from .model import derive
from .reductions import (at_rest, autonomous_extension, complex_rows, osc_c, osc_s, rotating_complex_rows,
                         rotating_frame, single_plane_limit)
from .scene import TwoPlaneScene
from .symbols import R, TwoPlaneSymbols, c, k, l, m, symmetric_substitution, t, z
from .symmetry import GAMMAS, is_equivariant


def general_scene(law: str = "torque") -> TwoPlaneScene:
    """Anisotropic unequal bearings, three balls of unequal mass in one race and one in the other,
    unequal planes, static and couple imbalance."""
    speed = {"constant": {"law": "constant", "omega": 2.5}, "torque": {"law": "torque", "tau0": 0.3,
             "motor_slope": 0.01, "torsion_damping": 0.002}, "ramp": {"law": "ramp"}, "hill": {"law": "hill"}}[law]
    return TwoPlaneScene.from_mapping({
        "preset": "paper-43", "imbalance_phase": 0.4, "misalignment": 0.002,
        "bearing_1": {"position": 9.0, "stiffness": [0.5, 2.0], "damping": [0.01, 0.04]},
        "races": [{"z": 1.0, "radius": 1.0, "masses": [0.002, 0.0025, 0.003], "damping": 2e-5},
                  {"z": -3.0, "radius": 0.8, "masses": [0.004], "damping": 3e-5}],
        "speed": speed})


def _split_identity(mine: sp.Expr, theirs: sp.Expr) -> bool:
    d = sp.expand(mine - theirs)
    return is_identity(sp.re(d)) and is_identity(sp.im(d))


def _compare_fixed(eom, s, n, printed: bool, spin=None, flip: bool = False) -> list[str]:
    ref = paper.fixed_frame(s, n, spin=spin, printed=printed)
    if flip:
        ref = {**ref, "q1": flip_term(ref["q1"])}
    r1, r2 = complex_rows(eom)
    bad = [name for name, mine in (("q1", r1), ("q2", r2)) if not _split_identity(mine, ref[name])]
    bad += [c.name for k_, c in enumerate(eom.coordinates) if c.name.startswith("theta_")
            and not is_identity(eom.residual(k_), ref[c.name])]
    return bad


def fixed_frame(wrong: bool = False) -> CheckResult:
    """wrong: the printed C_d q' and J_p + J_t chi^2 taken as the reference."""
    def run():
        scene = general_scene()
        eom, s = derive(scene), TwoPlaneSymbols.for_scene(scene)
        bad = _compare_fixed(eom, s, scene.n, printed=wrong)
        if bad:
            return False, f"rows differ from (2)-(4): {bad}"
        printed_bad = _compare_fixed(eom, s, scene.n, printed=True)
        if printed_bad != ["q1", "q2", "theta_0"]:
            return False, f"the printed C_d q' and tilde J_p should fail rows q1, q2, theta_0; failed {printed_bad}"
        return True, (f"all {eom.size} rows identical (3 + 1 balls, anisotropic, eps and chi); the printed C_d q' "
                      "fails (erratum of (2)); (3)'s J_p + J_t chi^2 differs from the exact inertia at order chi^2 "
                      "(a modelling-order choice in an equation the paper never evaluates, not an erratum; "
                      "see docs/errata.md)")
    return _timed("fixed frame, torque drive", "paper (2)-(4), C_d conj(q'), tilde J_p to order chi^2", run)


def prescribed_speed(law: str = "ramp", wrong: bool = False) -> CheckResult:
    """The run-up model: rows (2), (4) of the torque model with theta_0 prescribed, and its speed law."""
    def run():
        scene = general_scene(law)
        eom, s = derive(scene), TwoPlaneSymbols.for_scene(scene)
        th0 = Coordinate.make("theta_0")
        bad = _compare_fixed(eom, s, scene.n, printed=False, spin=(th0.q, th0.qd, th0.qdd), flip=wrong)
        # The law at the scene's values, on a grid through the run-up (the Hill angle has logs and
        # arctangents that simplify does not always cancel): theta_0(0) = 0 and the rates by differentiation.
        values = {p.symbol: p.default for p in eom.parameters}
        law_ = {k_: v.xreplace(values) for k_, v in eom.driven_law.items()}
        grid = np.linspace(0.0, 2.5 * float(scene.speed.t_ramp if law == "ramp" else scene.speed.t_half), 11)[1:]
        rate = [sp.diff(law_[th0.q], t), sp.diff(law_[th0.qd], t)]
        errs = [abs(float((rate[0] - law_[th0.qd]).subs(t, g))) + abs(float((rate[1] - law_[th0.qdd]).subs(t, g)))
                for g in grid if abs(g - scene.speed.t_ramp) > 1e-9]
        consistent = max(errs) < 1e-9 and abs(float(law_[th0.q].subs(t, 0))) < 1e-9
        ok = not bad and consistent
        return ok, (f"rows identical; theta_0(0) = 0, theta_0' = d theta_0/dt, theta_0'' = d theta_0'/dt" if ok
                    else f"rows differ: {bad}; law consistent: {consistent}")
    return _timed(f"prescribed run-up ({law})", "paper (2), (4), section 6, (45)", run)


def rotating(wrong: bool = False) -> CheckResult:
    def run():
        scene = replace(general_scene("constant"), bearing_1=TwoPlaneScene.preset("paper-42").bearing_1,
                        bearing_2=TwoPlaneScene().bearing_2)
        eom, s = rotating_frame(scene), TwoPlaneSymbols.for_scene(scene)
        ref = paper.rotating_frame(s, scene.n)
        if wrong:
            ref = {**ref, "r1": flip_term(ref["r1"])}
        r1, r2 = rotating_complex_rows(eom)
        bad = [n for n, mine in (("r1", r1), ("r2", r2)) if not _split_identity(mine, ref[n])]
        bad += [c.name for k_, c in enumerate(eom.coordinates[4:], 4) if not is_identity(eom.residual(k_), ref[c.name])]
        return not bad, "all rows identical (unequal bearings, balls and planes)" if not bad else f"differ: {bad}"
    return _timed("rotating frame", "paper (5)-(8)", run)


def balanced_condition(wrong: bool = False) -> CheckResult:
    """At rest with r = 0 the rotor rows are -Omega^2 (9) and the ball rows vanish (wrong: Omega^2 dropped)."""
    def run():
        scene = TwoPlaneScene()
        eom, s = rotating_frame(scene), TwoPlaneSymbols.for_scene(scene)
        rows = dict(zip([c.name for c in eom.coordinates],
                        at_rest(eom, {sp.Symbol(n, real=True): 0 for n in ("x", "y", "phi_x", "phi_y")})))
        nine = paper.balanced_condition(s, scene.n)
        # f of M q'' = f at rest is minus the residual (7) there: +Omega^2 times (9).
        W2 = 1 if wrong else s.Omega**2
        ok = (_split_identity(rows["x"] + sp.I * rows["y"], W2 * nine[0])
              and _split_identity(rows["phi_y"] - sp.I * rows["phi_x"], W2 * nine[1])
              and all(rows[f"alpha_{i + 1}"] == 0 for i in range(scene.n)))
        return ok, "rotor rows = Omega^2 (9), ball rows 0" if ok else "rows differ from Omega^2 (9)"
    return _timed("balanced condition", "paper (9)", run)


def balanced_state_b(wrong: bool = False) -> CheckResult:
    """The paper's B of section 3.2.2 solves the paper's (9) (wrong: arccos(M eps/(2 m R)), a factor 2 dropped)."""
    def run():
        scene = TwoPlaneScene()
        s = TwoPlaneSymbols.for_scene(scene)
        nine = paper.balanced_condition(s, scene.n)
        sub = symmetric_substitution(s) | {s.chi: 0, s.beta: 0}
        a = sp.acos(s.M * s.eps / ((2 if wrong else 4) * m * R))
        B = {sp.Symbol(f"alpha_{i + 1}", real=True): sp.pi + (a if i % 2 == 0 else -a) for i in range(4)}
        solved = all(is_identity(sp.expand(e.xreplace(sub).xreplace(B))) for e in
                     [sp.re(sp.expand(x)) for x in nine] + [sp.im(sp.expand(x)) for x in nine])
        return solved, "alpha = pi +- arccos(M eps/(4 m R)) solves (9)" if solved else "B does not solve (9)"
    return _timed("B solves (9)", "paper (9), section 3.2.2", run, CONSISTENCY)


def single_plane(law: str = "torque", wrong: bool = False) -> CheckResult:
    """No tilt, one race: the two-plane equations are the single-plane model's (thesis (2.10)-(2.13));
    wrong: the second bearing's stiffness k_X dropped from the single-plane k_X."""
    def run():
        masses = (0.02, 0.03)
        speed2 = {"law": "torque", "tau0": 0.4, "motor_slope": 0.01} if law == "torque" else {"law": "constant", "omega": 5.0}
        two = TwoPlaneScene.from_mapping({
            "bearing_1": {"position": 2.0, "stiffness": [0.6, 0.9], "damping": [0.01, 0.02]},
            "races": [{"z": 1.5, "radius": 0.5, "masses": list(masses), "damping": 1e-4},
                      {"z": -1.0, "radius": 1.0, "masses": [], "damping": 0.0}],
            "speed": speed2})
        one = Scene.from_mapping({"n": 2, "ball_mass": list(masses), "ball_damping": [1e-4, 1e-4],
                                  "stiffness": [1.0, 1.4], "damping": [0.02, 0.03],
                                  "speed": {"law": "torque", "tau0": 0.4, "motor_slope": 0.01} if law == "torque"
                                  else {"law": "constant", "omega": 5.0}})
        s2, s1 = TwoPlaneSymbols.for_scene(two), DimensionalSymbols.for_scene(one)
        to_two = {s1.M: s2.M, s1.eps: s2.eps, s1.R: s2.R[0], s1.kX: s2.k[(1, "X")] + (0 if wrong else s2.k[(2, "X")]),
                  s1.kY: s2.k[(1, "Y")] + s2.k[(2, "Y")], s1.cX: s2.c[(1, "X")] + s2.c[(2, "X")],
                  s1.cY: s2.c[(1, "Y")] + s2.c[(2, "Y")], s1.I_z: s2.Jp, s1.tau0: s2.tau0, s1.kappa: s2.kappa,
                  s1.omega: s2.Omega}
        to_two.update({a: b for a, b in zip(s1.m, s2.m)})
        to_two.update({d: s2.cb[0] for d in s1.D})
        limit_values = {s2.beta: 0, s2.chi: 0, s2.c_r: 0}
        psi = Coordinate.make("psi")
        coords = {}
        if law == "torque":
            coords.update({sp.Symbol(f"theta_0{x}", real=True): getattr(psi, a) for x, a in (("", "q"), ("_dot", "qd"),
                                                                                              ("_ddot", "qdd"))})
            spin = (psi.q, psi.qd, psi.qdd)
        else:
            spin = (s2.Omega * t, s2.Omega, 0)
        for i in range(2):
            phi = Coordinate.make(f"phi_{i + 1}")
            th = Coordinate.make(f"theta_{i + 1}")
            coords.update({th.q: spin[0] + phi.q, th.qd: spin[1] + phi.qd, th.qdd: spin[2] + phi.qdd})
        limit = single_plane_limit(derive(two))
        reference = derive_single_plane(one)
        bad = []
        for k_, c in enumerate(reference.coordinates):
            theirs = reference.residual(k_).xreplace(to_two)
            mine = limit[c.name].xreplace(limit_values).xreplace(coords)
            if not is_identity(mine, theirs):
                bad.append(c.name)
        return not bad, (f"rows {', '.join(c.name for c in reference.coordinates)} identical" if not bad
                         else f"differ: {bad}")
    return _timed(f"single-plane limit ({law})", "paper below (4); thesis (2.10)-(2.13)", run)


def critical_speeds_symbolic(wrong: bool = False) -> CheckResult:
    """The derived critical-speed polynomial has double roots exactly at (32)'s speeds (and (11)'s for m = 0);
    wrong: (32) with the balls' mass dropped (i.e. (11) claimed for m != 0)."""
    def run():
        scene = TwoPlaneScene()
        s = TwoPlaneSymbols.for_scene(scene)
        poly, w = cs.critical_speed_polynomial(scene, symmetric_substitution(s))
        cyl, con = paper.critical_speeds_32(s.M, s.Jt, s.Jp, k, l, 0 if wrong else m, z)
        cyl0, con0 = paper.critical_speeds_11(s.M, s.Jt, s.Jp, k, l)
        P, dP = poly.as_expr(), sp.diff(poly.as_expr(), w)
        ok = all(is_identity(e.xreplace({w: r**2})) for r in (cyl, con) for e in (P, dP)) and poly.degree() == 4
        ok0 = all(is_identity(e.xreplace({m: 0}).xreplace({w: r**2})) for r in (cyl0, con0) for e in (P, dP))
        return ok and ok0, "det = c (w - Omega_cyl^2)^2 (w - Omega_con^2)^2 with (32); (11) for m = 0" if ok and ok0 \
            else f"(32): {ok}, (11): {ok0}"
    return _timed("critical speeds, symbolic", "paper (11), (32)", run)


# Printed critical speeds of (43) the model does not give at the printed precision, by either
# definition; the model's values (6 decimals) are documented in docs/errata.md ("not errata") with what was
# tried.  The paper prints them as approximate ("simeq", "the frequencies of the maximum response"): the
# difference is unexplained, not shown to be the paper's mistake.
NOT_REPRODUCED_43 = {("Omega_con,X (43)", "det"): 1.659235, ("Omega_con,X (43)", "peak"): 1.659649,
                     ("Omega_con,Y (43)", "det"): 3.776920, ("Omega_con,Y (43)", "peak"): 3.783836}
STUDY_43 = ("tried: undamped critical speeds (double roots of the derived frozen-ball determinant) and the "
            "damped rotor's imbalance-response peaks (static and couple imbalance, c of (43)); neither gives "
            "the printed value; an unexplained difference, not an erratum (the paper prints the value as "
            "approximate): see docs/errata.md")


def critical_speed_numbers(wrong: bool = False) -> list[CheckResult]:
    """Critical speeds of (10), (42), (43) from the derived model, against the printed values at their
    printed precision (half a unit in the last digit).  Where the model does not give the printed value
    (NOT_REPRODUCED_43) the row says so and checks the model's own documented value instead.
    wrong: printed values (documented values) moved by 3 units of their last digit."""
    rows = []

    def num(name, preset, index, printed, how="det"):
        documented = NOT_REPRODUCED_43.get((name, how))

        def run():
            scene = TwoPlaneScene.preset(preset)
            if how == "det":
                got = cs.critical_speeds(scene, with_balls=False)[index]
            else:
                got = sorted(cs.response_peaks(scene, "static") + cs.response_peaks(scene, "couple"))[index]
            tol = printed_tolerance(printed)
            if documented is None:
                shown = moved(printed) if wrong else printed
                return abs(got - float(shown)) <= tol, f"{got:.6f} vs printed {shown} (tol {tol:g}, half a unit)"
            value = moved(f"{documented:.6f}") if wrong else f"{documented:.6f}"
            reproduced = abs(got - float(printed)) <= tol
            ok = not reproduced and abs(got - float(value)) <= 5e-7
            return ok, (f"{got:.6f}, printed {printed}: off by {abs(got - float(printed)):.4f} > {tol:g} "
                        f"(model value {value} as documented; {STUDY_43})" if not reproduced else
                        f"{got:.6f} now reproduces printed {printed}: update the errata")
        label = f"paper {preset.split('-')[1]} ({how})"
        rows.append(_timed(name + (", undamped" if how == "det" else ", response peak"), label, run, DERIVED,
                           NOT_REPRODUCED if documented is not None else ""))

    num("Omega_cyl (11)", "paper-10", 0, "1")
    num("Omega_con (11)", "paper-10", 1, "1.81")
    num("Omega_cyl (42)", "paper-42", 0, "0.89")
    num("Omega_con (42)", "paper-42", 1, "4.07")
    for i, (name, value) in enumerate((("Omega_cyl,X (43)", "1"), ("Omega_con,X (43)", "1.65"),
                                       ("Omega_cyl,Y (43)", "2.24"), ("Omega_con,Y (43)", "3.79"))):
        num(name, "paper-43", i, value)
        num(name, "paper-43", i, value, how="peak")
    return rows


# Figure 13 ("long" and "disk" rotors): the text says the disk has J_t < J_p (no conical critical speed,
# section 5); the caption prints "long J_p > J_t" and "disk J_p < J_t", the reverse.
FIG13_TEXT = {"long": lambda jp, jt: jp < jt, "disk": lambda jp, jt: jp > jt}
FIG13_CAPTION = {"long": lambda jp, jt: jp > jt, "disk": lambda jp, jt: jp < jt}
FIG13_DISK = {"transverse_inertia": 0.5, "polar_inertia": 1.0}  # the disk chart's inertias (charts.CHARTS 13(b))


def figure_13_caption(wrong: bool = False) -> CheckResult:
    """Paper Figure 13's caption reverses its text's inequalities: the 'long' rotor of (10) (J_t = 3.25, J_p = 0.5,
    Figure 13(a) = Figure 10(a), conical critical speed (11) 1.81) has J_p < J_t, and a rotor with J_p > J_t has
    no conical critical speed ((11): 2 k l^2/(J_t - J_p) < 0), the text's 'disk'.  wrong: the caption's
    inequalities taken as the reference."""
    def run():
        ref = FIG13_CAPTION if wrong else FIG13_TEXT
        found = {}
        for kind, scene in (("long", TwoPlaneScene.preset("paper-10")), ("disk", TwoPlaneScene.from_mapping(FIG13_DISK))):
            speeds = cs.critical_speeds(scene, with_balls=False)
            found[kind] = (ref[kind](scene.polar_inertia, scene.transverse_inertia), len(speeds))
        ok = found["long"] == (True, 2) and found["disk"] == (True, 1)
        return ok, ("the long rotor of (10) (J_p < J_t) has the conical critical speed, a J_p > J_t rotor has none: "
                    "the text's inequalities, the caption's reversed (erratum)" if ok else
                    f"(inequality holds, number of critical speeds): {found}")
    return _timed("Figure 13 caption", "paper Fig. 13 caption against its text and (11)", run)


def normal_form_symbolic(wrong: bool = False) -> CheckResult:
    """a1, a2 of the derived branches against (23), (33), (34) (wrong: the factor 8 of a1 - a2 dropped)."""
    def run():
        co = nf.coefficients()
        s = nf.symmetric_model().s
        kap = nf.kappa_at_critical_mass()
        A1, A2 = paper.a1_a2_34(s.M, s.eps, R, kap)
        checks = {
            "a1 + a2 = (23)": is_identity(co["a1+a2"], paper.a_sum_23(s.M, s.eps, R)),
            "a1 = (33)": is_identity(co["a1"], A1),
            "a2 = (34)": is_identity(co["a2"], A2),
            "a1 - a2 = M eps kappa/(8R)": is_identity(co["a1"] - co["a2"], s.M * s.eps * kap / ((1 if wrong else 8) * R)),
        }
        bad = [k_ for k_, v in checks.items() if not v]
        return not bad, "a1, a2 from the derived B and C3 branches equal (23), (33), (34)" if not bad else f"fail: {bad}"
    return _timed("D4 normal form coefficients", "paper (23), (33), (34)", run)


def normal_form_consistency(wrong: bool = False) -> CheckResult:
    """The paper against itself: kappa (32) in its two printed forms, the normal form (20) against its
    Jacobians (36)-(38) and the eigenvalues of (38) (wrong: (38)'s second eigenvalue with a1 + a2 for a1 - a2)."""
    def run():
        s = nf.symmetric_model().s
        checks = {
            "kappa (32) two forms": is_identity(paper.kappa_32(s.M, s.Jt, s.Jp, k, l, m, z, s.Omega),
                                                paper.kappa_32(s.M, s.Jt, s.Jp, k, l, m, z, s.Omega, True)),
            "(36)": nf.jacobian() == paper.jacobian_36(nf.mu, nf.a1, nf.a2, nf.v1, nf.v2),
            "(37)": all(is_identity(a, b) for a, b in zip(nf.jacobian_at("C3"), paper.jacobian_37(nf.mu, nf.a1, nf.a2))),
            "(38)": all(is_identity(a, b) for a, b in zip(nf.jacobian_at("B"), paper.jacobian_38(nf.mu, nf.a1, nf.a2))),
        }
        ev = nf.jacobian_at("B").eigenvals()
        expected = {-2 * nf.mu, -2 * nf.mu * (nf.a1 + (1 if wrong else -1) * nf.a2) / (nf.a1 + nf.a2)}
        checks["eigenvalues of (38)"] = all(any(is_identity(e, x) for x in expected) for e in ev) and len(ev) == 2
        bad = [k_ for k_, v in checks.items() if not v]
        return not bad, "kappa (32) two forms agree; (20) gives (36)-(38) and (38)'s eigenvalues" if not bad else f"fail: {bad}"
    return _timed("normal form (20) vs (32), (36)-(38)", "paper (20), (32), (36)-(38)", run, CONSISTENCY)


def steady_state_28(wrong: bool = False) -> CheckResult:
    """The derived steady-state equations of the symmetric set-up are (28) (row 4 corrected)."""
    def run():
        sm = nf.symmetric_model()
        s = sm.s
        x, y, px, py = (sp.Symbol(n, real=True) for n in ("x", "y", "phi_x", "phi_y"))
        b12, h12, b34, h34 = sp.symbols("abar_12 ahat_12 abar_34 ahat_34", real=True)
        state = {"alpha_1": b12 + h12, "alpha_2": b12 - h12, "alpha_3": b34 + h34, "alpha_4": b34 - h34}
        rows = sm.rows_at_rest(state, {s.chi: 0})
        mine = [-rows["x"], -rows["phi_y"], -rows["y"], rows["phi_x"]]  # residual = -f at rest; Im r_2 = -phi_x
        args = (s.M, s.Jt, s.Jp, k, l, c, m, z, R, s.eps, s.Omega, [x, py, y, -px], b12, h12, b34, h34)
        corrected = [is_identity(a, b) for a, b in zip(mine, paper.steady_state_28(*args, printed=False))]
        printed = [is_identity(a, b) for a, b in zip(mine, paper.steady_state_28(*args, printed=True))]
        ok = all(printed if wrong else corrected) and printed == [True, True, True, False]
        return ok, ("rows 1-4 identical with row 4 corrected; the printed row 4 differs (erratum)" if ok
                    else f"corrected: {corrected}, printed: {printed}")
    return _timed("steady states of the symmetric set-up", "paper (27)-(28), row 4 corrected", run)


def c3_relation_31(wrong: bool = False) -> CheckResult:
    """The derived C3 branch E(m, alpha_hat) = 0 is (31) with kappa(m) of (32) (wrong: kappa doubled)."""
    def run():
        s = nf.symmetric_model().s
        E = nf.c3_branch()[1]
        kap = (2 if wrong else 1) * paper.kappa_32(s.M, s.Jt, s.Jp, k, l, m, z, s.Omega)
        Q = sp.numer(sp.together(m * R - paper.mR_31(s.M, s.eps, kap, nf.a_hat)))
        ratio = sp.cancel(sp.expand(E) / sp.expand(Q))
        ok = not (ratio.free_symbols & {m, nf.a_hat}) and ratio != 0
        return ok, f"E / (31) = {ratio}" if ok else "E is not a multiple of (31)"
    return _timed("C3 branch relation", "paper (24)-(31)", run)


def criticality_35(wrong: bool = False) -> CheckResult:
    """(35): a1 > a2 outside the critical speeds, a2 > a1 between, for Omega_con > Omega_cyl (10) and a disc-like
    rotor with Omega_cyl > Omega_con."""
    def run():
        s = nf.symmetric_model().s
        co = nf.coefficients()
        msgs, ok = [], True
        for label, values in (("(10)", {s.Jt: 3.25, s.Jp: 0.5, l: 3}), ("Omega_cyl > Omega_con", {s.Jt: 3.25, s.Jp: 0.5, l: 1})):
            base = {s.M: 1, s.eps: 0.01, R: 1, k: 0.5, z: 2, **values}
            mc = float(nf.critical_mass().xreplace(base))
            cyl, con = (float(v.xreplace(base).xreplace({m: mc})) for v in paper.critical_speeds_32(
                s.M, s.Jt, s.Jp, k, l, m, z))
            lo, hi = sorted((cyl, con))
            diff = sp.lambdify(s.Omega, (co["a1"] - co["a2"]).xreplace(base))
            grid = [g for g in np.linspace(0.05, 6.0, 1191) if min(abs(g - lo), abs(g - hi)) > 1e-6]
            # wrong: the exchange claimed the other way round (a1 > a2 between the critical speeds)
            bad = [g for g in grid if (diff(g) > 0) != ((g < lo or g > hi) != wrong)]
            ok &= not bad
            msgs.append(f"{label}: Omega_1 = {lo:.6f}, Omega_2 = {hi:.6f}, {len(bad)} violations on {len(grid)} speeds")
        return ok, "; ".join(msgs)
    return _timed("stability exchange (35)", "paper (32), (35), Figure 7", run)


def figure_9(tolerance: float = 5e-3, wrong: bool = False) -> list[CheckResult]:
    """Full model against the normal form at (10), eps = 0.01, Omega = 3 (and 0.8, 1.4): slopes of
    m - m_c against alpha_hat^2, stability of B and C3, and the unfolding (39) with chi = 0.001.
    wrong: the normal form's slopes and unfolding masses taken 2 % too large."""
    off = 1.02 if wrong else 1.0
    from .branches import FullSteadyStates

    s = nf.symmetric_model().s
    co = nf.coefficients()
    rows = []
    base = {s.M: 1, s.eps: 0.01, R: 1, s.Jt: 3.25, s.Jp: 0.5, k: 0.5, l: 3, z: 2}
    m_c = float(nf.critical_mass().xreplace(base))
    for Om in (3.0, 0.8, 1.4):
        vals = base | {s.Omega: Om}
        a_1, a_sum = off * float(co["a1"].xreplace(vals)), off * float(co["a1+a2"].xreplace(vals))
        fs = FullSteadyStates(TwoPlaneScene(), epsilon=0.01, Omega=Om)
        for kind, target in (("B", a_sum), ("Ct3", a_1)):
            def run(kind=kind, target=target, fs=fs, Om=Om):
                branch = fs.continue_branch(kind, m_c)
                slope = branch.fit(m_c)[1]
                err = abs(slope - target) / abs(target)
                detail = f"Omega = {Om}: fitted slope {slope:.7g} vs normal form {target:.7g}, rel. error {err:.2e} (tol {tolerance:g})"
                if Om == 3.0:  # (37)-(38): a1 > a2 here, so B stable, C3 one unstable (real) direction
                    spec = fs.spectrum(branch, 4)
                    unstable = spec.eigenvalues[spec.eigenvalues.real > spec.zero_tol]
                    expect = 0 if kind == "B" else 1
                    stab_ok = spec.n_unstable == expect and np.all(np.abs(unstable.imag) < 1e-9)
                    detail += (f"; full model at mu = {branch.m[4] - m_c:.3g}: {spec.n_unstable} unstable "
                               f"(normal form: {expect})")
                    return err <= tolerance and stab_ok, detail
                return err <= tolerance, detail
            rows.append(_timed(f"Figure 9(a) {kind} slope, Omega={Om}", "paper (20)-(22), (34), (37)-(38)", run))

    def unfolding():
        chi = 1e-3
        vals = base | {s.Omega: 3.0, s.chi: chi}
        masses = {k_: off * v for k_, v in nf.unfolding_masses(vals).items()}
        slopes = nf.unfolded_slopes(vals)
        a_1 = float(co["a1"].xreplace(vals))
        fs = FullSteadyStates(TwoPlaneScene(), epsilon=0.01, Omega=3.0, chi=chi)
        msgs, ok = [], True
        for kind, key in (("Ct3", "m_b"), ("Cb3", "m_t")):
            c0, c2 = fs.continue_branch(kind, m_c).fit()
            e0 = abs(c0 - masses[key]) / masses[key]
            e2 = abs(c2 - slopes[kind]) / abs(slopes[kind])
            ok &= e0 <= 1e-3 and e2 <= tolerance
            msgs.append(f"{kind}: born at {c0:.7f} ({key} = {masses[key]:.7f}, rel. {e0:.1e}), slope {c2:.5g} "
                        f"(undamped branch {slopes[kind]:.5g}, rel. {e2:.1e}; (39)'s a_1 = {a_1:.5g})")
        ok &= masses["m_b"] < m_c < masses["m_t"]
        return ok, "; ".join(msgs)
    rows.append(_timed("unfolding, chi = 0.001", "paper (39), Figure 9(b)", unfolding))
    return rows


def equivariance(wrong: bool = False) -> CheckResult:
    """wrong: gamma_r claimed to hold with the couple imbalance chi too."""
    def run():
        scene = TwoPlaneScene()
        s = TwoPlaneSymbols.for_scene(scene)
        eom = rotating_frame(scene).map(lambda e: sp.expand(e.xreplace(symmetric_substitution(s))))
        static = eom.map(lambda e: e.xreplace({s.chi: 0}))
        holds = {g: is_equivariant(static, g) for g in GAMMAS}
        broken = {g: is_equivariant(eom, g) for g in GAMMAS}
        ok = all(holds.values()) and broken == {"gamma_12": True, "gamma_34": True, "gamma_r": wrong}
        return ok, ("(13)-(14) hold for gamma_12, gamma_34, gamma_r (chi = 0, any beta); gamma_r fails for chi != 0"
                    if ok else f"chi = 0: {holds}; chi != 0: {broken}")
    return _timed("D4 equivariance", "paper (13)-(16)", run)


def oscillator(wrong: bool = False) -> CheckResult:
    """wrong: the cycle with sin and cos exchanged."""
    def run():
        scene = TwoPlaneScene.preset("paper-43")
        ext = autonomous_extension(scene)
        Om = TwoPlaneSymbols.for_scene(scene).Omega
        on_cycle = {osc_s: sp.sin(Om * t), osc_c: sp.cos(Om * t)}
        if wrong:
            on_cycle = {osc_s: sp.cos(Om * t), osc_c: sp.sin(Om * t)}
        solves = all(is_identity(f.xreplace(on_cycle), sp.diff(x, t))
                     for f, x in zip(ext.oscillator, (sp.sin(Om * t), sp.cos(Om * t))))
        same = all(is_identity(a.xreplace(on_cycle), b) for a, b in zip(ext.eom.forcing, derive(scene).forcing))
        return solves and same, ("s = sin(Omega t), c = cos(Omega t) solve (40); substituted back, the extension "
                                 "is the fixed-frame model" if solves and same else f"{solves}, {same}")
    return _timed("autonomous extension", "paper (40)", run)


def jacobi_identity(wrong: bool = False) -> CheckResult:
    """wrong: the Rayleigh power dropped from the rate."""
    from .jacobi import rotating_lagrangian

    def run():
        scene = TwoPlaneScene.from_mapping({"misalignment": 0.002, "imbalance_phase": 0.3})
        rl = rotating_lagrangian(scene)
        rot = rotating_frame(scene)
        routes = all(is_identity(rl.eom.residual(i), rot.residual(i)) for i in range(rot.size))
        first, rate = rl.jacobi_rate_identities()
        if wrong:
            rate = sp.expand(rate - sum((c.qd * sp.diff(rl.F, c.qd) for c in rl.eom.coordinates), sp.S.Zero))
        ok = routes and all(is_identity(f) for f in first) and is_identity(rate)
        return ok, ("Lagrangian route = equation route; dh/dt = -q'.dF/dq' identically" if ok
                    else f"routes agree: {routes}; rate identity fails")
    return _timed("Jacobi integral, rotating frame", "paper (7)-(8), c = c_b = 0", run)


def friction_scene(law: str = "torque") -> TwoPlaneScene:
    """`general_scene` with ball-race friction, a rolling resistance of its own for each ball (issue 37)."""
    scene = general_scene(law)
    return replace(scene, rolling_resistance=tuple(0.01 * (k + 1) for k in range(scene.n)))


def friction_zero_limit(wrong: bool = False) -> CheckResult:
    """With friction (issue 37), mu_r_k = 0 gives the paper's equations exactly, row by row, under the torque
    drive (the spin's row holds the reaction of the friction) and at constant speed; at mu_r_k > 0 the rows
    must differ.  wrong: the frictionless model's first row with a flipped term."""
    def run():
        for law in ("torque", "constant"):
            scene = friction_scene(law)
            mine, today = derive(scene), derive(general_scene(law))
            mu = set(TwoPlaneSymbols.for_scene(scene).mu_r)
            if not mu or [c.name for c in mine.coordinates] != [c.name for c in today.coordinates]:
                return False, f"{law}: the friction model has other coordinates or no rolling resistance"
            zero = {m_: 0 for m_ in mu}
            rows = [today.residual(k_) for k_ in range(today.size)]
            if wrong:
                rows[0] = flip_term(rows[0])
            bad = [c.name for k_, c in enumerate(mine.coordinates)
                   if not is_identity(mine.residual(k_).xreplace(zero), rows[k_])]
            if bad:
                return False, f"{law}: rows {bad} differ from the frictionless model at mu_r = 0"
            if all(is_identity(mine.residual(k_), rows[k_]) for k_ in range(mine.size)):
                return False, f"{law}: the friction model equals the frictionless one at mu_r > 0: no friction derived"
        return True, "every row identical at mu_r = 0 (torque drive and constant speed, 3 + 1 balls); rows differ at mu_r > 0"
    return _timed("friction, zero limit", "paper (2)-(4) at mu_r = 0 (issue 37)", run)


def _ball_acceleration(lag, k_: int) -> tuple[sp.Matrix, sp.Matrix]:
    """Ball k_'s acceleration in the space frame (its exact position of section 2.1 differentiated twice) and
    the race plane's tilt (Cxyz -> space-parallel), for the checks of the race's forces by Newton's law."""
    from .model import ball_position, rotations

    R1, R2, _ = rotations(Coordinate.make("phi_X").q, Coordinate.make("phi_Y").q, Coordinate.make("theta_0").q)
    tilt_T = (R2 * R1).T
    everything = lag.coordinates + lag.driven
    position = ball_position(lag.symbols, k_, lag.symbols.R[k_], tilt_T)
    return position.applyfunc(lambda x: time_derivative(time_derivative(x, everything, t), everything, t)), tilt_T


def friction_normal_force(wrong: bool = False) -> CheckResult:
    """N_k (`model.normal_forces`, Lagrange's equation of a radial coordinate) against Newton's law along the
    race radius, N_k = -m_k a_k . e_r, a_k the ball's position (exact rotations of section 2.1) differentiated
    twice and e_r the race plane's radial unit vector, both kept to first order in the vibration, identical
    under the torque drive (theta_0 a coordinate).  wrong: the Coriolis part of the derived force,
    2 m_k R_k theta_0' (theta_k' - theta_0'), dropped."""
    from .model import first_order, lagrangian, normal_forces

    def run():
        lag = lagrangian(friction_scene("torque"))
        s = lag.symbols
        th0 = Coordinate.make("theta_0")
        bad = []
        for k_, N in enumerate(normal_forces(lag)):
            ball = Coordinate.make(f"theta_{k_ + 1}")
            if wrong:
                N = N - 2 * s.m[k_] * s.R[k_] * th0.qd * (ball.qd - th0.qd)
            a, tilt_T = _ball_acceleration(lag, k_)
            e_r = tilt_T * sp.Matrix([sp.cos(ball.q), sp.sin(ball.q), 0])
            if not is_identity(N, first_order(-s.m[k_] * a.dot(e_r))):
                bad.append(k_ + 1)
        if bad:
            return False, f"the normal force of balls {bad} differs from Newton's law along the radius"
        return True, f"N_k = -m_k a_k . e_r to first order in the vibration, identically, for all {lag.scene.n} balls"
    return _timed("friction, normal force", "paper section 2.1 kinematics, Newton along the race radius (issue 37)", run)


def stiction_scene(law: str = "torque") -> TwoPlaneScene:
    """`friction_scene` with stiction (issue 37 item 2), mu_s_k = 2 mu_r_k: the hybrid model's modes."""
    scene = friction_scene(law)
    return replace(scene, static_friction=tuple(2 * r for r in scene.rolling_resistances()))


def friction_stick_rows(wrong: bool = False) -> CheckResult:
    """The hybrid system's rows (`model.stick_rows`), torque drive and constant speed: every ball slipping
    (stuck_k = 0) with mu_r = 0 gives the paper's rows exactly, and with slip_dir_k = sign(theta_k' - theta_0')
    the slip model's rows at any mu_r; every ball stuck (stuck_k = 1) gives ball rows m_k R_k^2 (theta_k'' -
    theta_0'') and, under the torque drive, the spin's row of the paper's model plus every ball's row (the
    balls carried by the rotor), with no friction coefficient left.  wrong: the spin's row keeps the kinetic
    reaction of a stuck ball (its stuck_k times the ball's slip row not added)."""
    from ...core.friction import slip_direction
    from .model import speed_law

    def run():
        for law in ("torque", "constant"):
            scene = stiction_scene(law)
            s = TwoPlaneSymbols.for_scene(scene)
            mine, slip, today = derive(scene), derive(friction_scene(law)), derive(general_scene(law))
            names = [c_.name for c_ in mine.coordinates]
            rows = mine.residuals()
            slipping, held = {x: 0 for x in s.stuck}, {x: 1 for x in s.stuck}
            if wrong and "theta_0" in names:
                i0 = names.index("theta_0")
                rows[i0] -= sum((x * rows[names.index(f"theta_{k_ + 1}")].xreplace(slipping)
                                 for k_, x in enumerate(s.stuck)), sp.S.Zero)
            zero = {x: 0 for x in s.mu_r} | slipping
            th0 = Coordinate.make("theta_0")
            spin = speed_law(scene, s) if law == "constant" else {}  # theta_0' = Omega there
            mode = {s.slip_dir[k_]: slip_direction((Coordinate.make(f"theta_{k_ + 1}").qd - th0.qd).xreplace(spin))
                    for k_ in range(scene.n)}
            bad = [n_ for i, n_ in enumerate(names) if not is_identity(rows[i].xreplace(zero), today.residual(i))]
            bad += [n_ + " (slip)" for i, n_ in enumerate(names)
                    if not is_identity(rows[i].xreplace(slipping).xreplace(mode), slip.residual(i))]
            for i, n_ in enumerate(names):
                stuck_row = rows[i].xreplace(held)
                if n_ == "theta_0":
                    want = today.residual(i) + sum((today.residual(names.index(f"theta_{k_ + 1}"))
                                                    for k_ in range(scene.n)), sp.S.Zero)
                elif n_.startswith("theta_"):
                    k_ = int(n_.split("_")[1]) - 1
                    ball = Coordinate.make(n_)
                    want = s.m[k_] * s.R[k_] ** 2 * (ball.qdd - (th0.qdd if "theta_0" in names else 0))
                else:
                    want = today.residual(i)
                if not is_identity(stuck_row, want) or set(s.mu_r) & stuck_row.free_symbols:
                    bad.append(n_ + " (stuck)")
            if bad:
                return False, f"{law}: rows {bad} differ"
        return True, ("torque drive and constant speed, 3 + 1 balls: slipping at mu_r = 0 the paper's rows, with "
                      "slip_dir = sign the slip model's; all stuck: the constraint rows, the spin's row of the "
                      "rotor carrying the balls, no mu_r")
    return _timed("friction, stick rows", "paper (2)-(4) with stick constraints (issue 37)", run)


def friction_stick_force(wrong: bool = False) -> CheckResult:
    """F_k (`model.stick_forces`: the frictionless ball row over R_k, at theta_k'' = theta_0'') against
    Newton's law along the race's tangent, m_k a_k . e_t = F_k - c_b (theta_k' - theta_0') / R_k (the race's
    friction and the race damping the ball's tangential forces), a_k the exact position of section 2.1
    differentiated twice and e_t the race plane's tangent, both to first order in the vibration, identical
    under the torque drive.  wrong: the race damping's part dropped from the derived force."""
    from .model import first_order, lagrangian, stick_forces

    def run():
        lag = lagrangian(stiction_scene("torque"))
        s = lag.symbols
        th0 = Coordinate.make("theta_0")
        bad = []
        for k_, F in enumerate(stick_forces(lag)):
            ball = Coordinate.make(f"theta_{k_ + 1}")
            drag = s.cb[k_] * (ball.qd - th0.qd) / s.R[k_]
            if wrong:
                F = F - drag
            a, tilt_T = _ball_acceleration(lag, k_)
            e_t = tilt_T * sp.Matrix([-sp.sin(ball.q), sp.cos(ball.q), 0])
            newton = (first_order(s.m[k_] * a.dot(e_t)) + drag).xreplace({ball.qdd: th0.qdd})
            if not is_identity(F, newton):
                bad.append(k_ + 1)
        if bad:
            return False, f"the stick force of balls {bad} differs from Newton's law along the tangent"
        return True, f"F_k = m_k a_k . e_t + c_b (theta_k' - theta_0') / R_k to first order, for all {lag.scene.n} balls"
    return _timed("friction, stick force", "paper section 2.1 kinematics, Newton along the race tangent (issue 37)", run)


def registered(ns=()) -> list[Registered]:
    """Every check of the family with what it compares and its deliberately wrong variant."""
    def one(fn, *args):
        return lambda wrong: fn(*args, wrong=wrong)
    return [
        Registered("fixed frame", DERIVED, one(fixed_frame), "the printed C_d q' and J_p + J_t chi^2"),
        Registered("prescribed run-up (ramp)", DERIVED, one(prescribed_speed, "ramp"), "q1 row with a flipped term"),
        Registered("prescribed run-up (hill)", DERIVED, one(prescribed_speed, "hill"), "q1 row with a flipped term"),
        Registered("rotating frame", DERIVED, one(rotating), "r1 row with a flipped term"),
        Registered("balanced condition", DERIVED, one(balanced_condition), "the factor Omega^2 dropped"),
        Registered("B solves (9)", CONSISTENCY, one(balanced_state_b), "arccos(M eps/(2 m R)): a factor 2 dropped"),
        Registered("single-plane limit (torque)", DERIVED, one(single_plane, "torque"), "a bearing's k_X dropped"),
        Registered("single-plane limit (constant)", DERIVED, one(single_plane, "constant"), "a bearing's k_X dropped"),
        Registered("critical speeds, symbolic", DERIVED, one(critical_speeds_symbolic), "(32) with m = 0"),
        Registered("normal form coefficients", DERIVED, one(normal_form_symbolic), "a1 - a2 without the factor 1/8"),
        Registered("normal form (20) vs (32), (36)-(38)", CONSISTENCY, one(normal_form_consistency),
                   "(38)'s eigenvalue with a1 + a2 for a1 - a2"),
        Registered("steady states (28)", DERIVED, one(steady_state_28), "the misprinted row 4 of (28)"),
        Registered("C3 relation (31)", DERIVED, one(c3_relation_31), "kappa doubled"),
        Registered("stability exchange (35)", DERIVED, one(criticality_35), "the exchange the other way round"),
        Registered("D4 equivariance", DERIVED, one(equivariance), "gamma_r claimed with chi != 0"),
        Registered("autonomous extension (40)", DERIVED, one(oscillator), "sin and cos exchanged on the cycle"),
        Registered("Jacobi integral", DERIVED, one(jacobi_identity), "the Rayleigh power dropped"),
        Registered("critical speed numbers", DERIVED, lambda wrong: critical_speed_numbers(wrong),
                   "printed (documented) values moved by 3 units of the last digit"),
        Registered("Figure 13 caption", DERIVED, one(figure_13_caption), "the caption's long J_p > J_t"),
        Registered("Figure 9", DERIVED, lambda wrong: figure_9(wrong=wrong), "normal-form slopes and masses 2 % too large"),
        Registered("friction, zero limit", DERIVED, one(friction_zero_limit), "the frictionless first row with a flipped term"),
        Registered("friction, normal force", DERIVED, one(friction_normal_force), "the Coriolis term 2 m R theta_0' (theta_k' - theta_0') dropped"),
        Registered("friction, stick rows", DERIVED, one(friction_stick_rows), "the spin's row keeping a stuck ball's kinetic friction"),
        Registered("friction, stick force", DERIVED, one(friction_stick_force), "the race damping's part of the stick force dropped"),
    ]



__all__ = ["general_scene"]
