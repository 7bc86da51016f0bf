"""Adding a family or a target touches its own folder plus one registry line (issue 8).

A toy family (a pendulum on a sprung cart: the cart is the Schur core, the pendulum the one "ball")
and two toy targets are registered with one call each and regenerated through the ordinary command
line with everything else; nothing in the package names them:

- ``pylist`` (issue 19: a target is one folder plus one registry line): tests/plugins/pylist/, its own
  printer, dialect and templates; it prints the loop form, and what it prints is run here against the
  generated numba module;
- ``listing`` (a JSON listing of a model's states, parameters and rhs statements): a target of the
  unrolled form (statements one by one), printed with pylist's printer and dialect.
"""

from __future__ import annotations

import importlib.util
import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from adbgen import families
from adbgen.cli import main
from adbgen.codegen import targets
from adbgen.core import Coordinate, EnergyTerm, Parameter, lagrange_equations
from adbgen.core.checks import CheckResult
from adbgen.core.first_order import first_order
from adbgen.core.description import Candidate, ClosedForm, Description, SteadyState, Symmetry
from adbgen.core.model_spec import Check, Continuation, ModelSpec
from adbgen.core.symbols import positive, t

def pendulum_on_cart():
    """A cart on an isotropic spring (X, Y) with a pendulum swinging in the X-z plane:
    T = (M + m)(X'^2 + Y'^2)/2 + m l X' phi' cos phi + m l^2 phi'^2/2, V = k (X^2 + Y^2)/2 - m g l cos phi,
    F = c_cart (X'^2 + Y'^2)/2 + c_pivot phi'^2/2."""
    M, m, l, k, g, c, cc = (positive(s) for s in ("M_cart", "m_bob", "l_rod", "k_spring", "g_acc", "c_pivot", "c_cart"))
    X, Y, phi = Coordinate.make("X"), Coordinate.make("Y"), Coordinate.make("phi")
    terms = [EnergyTerm("cart", T=M * (X.qd**2 + Y.qd**2) / 2, V=k * (X.q**2 + Y.q**2) / 2,
                        F=cc * (X.qd**2 + Y.qd**2) / 2),
             EnergyTerm("bob", T=m * ((X.qd + l * phi.qd * sp.cos(phi.q))**2 + Y.qd**2 + (l * phi.qd * sp.sin(phi.q))**2) / 2,
                        V=-m * g * l * sp.cos(phi.q), F=c * phi.qd**2 / 2)]
    params = tuple(sorted((Parameter(M, "cart mass", "kg", 2.0), Parameter(m, "bob mass", "kg", 0.5),
                           Parameter(l, "rod length", "m", 1.0), Parameter(k, "spring", "N/m", 10.0),
                           Parameter(g, "gravity", "m/s^2", 9.81), Parameter(c, "pivot damping", "N m s", 0.1),
                           Parameter(cc, "cart damping", "N s/m", 0.2)),
                          key=lambda p: p.name))
    return lagrange_equations((X, Y, phi), terms, t, parameters=params, reference="toy: pendulum on a sprung cart")


def describe(system) -> Description:
    """The toy's self-description: the pendulum plays the ball (the Schur leaf, an angle), the cart the
    rotor (its amplitude r = hypot(X, Y)); mirror symmetries X -> -X (with phi -> -phi) and Y -> -Y; the
    hanging and the inverted rest states in closed form; the bob's height as a measure."""
    q = {c.name: c.q for c in system.coordinates}
    l_rod = next(p.symbol for p in system.parameters if p.name == "l_rod")
    return Description(
        time_unit="s", units={"X": "m", "Y": "m", "phi": "rad"},
        roles={"X": "translation", "Y": "translation", "phi": "ball_angle"}, angles=("phi",), amplitude=("X", "Y"),
        measures={"bob_height": l_rod * (1 - sp.cos(q["phi"]))},
        symmetries=(Symmetry("mirror X", "reflection", {"X": ("X", -1), "phi": ("phi", -1)}),
                    Symmetry("mirror Y", "reflection", {"Y": ("Y", -1)})),
        parameter_sets={"toy": {p.name: p.default for p in system.parameters}},
        closed_forms=(ClosedForm("rest", (), (Candidate((), {}),)),
                      ClosedForm("inverted", (), (Candidate((), {"phi": sp.pi}),))),
        steady_states=(SteadyState("hanging", "at rest, hanging", "rest"),
                       SteadyState("inverted", "at rest, upside down", "inverted")),
        steady_state_names={"rest": "hanging at rest"})  # what sweeps call the cart at rest


def energy_check(wrong: bool = False) -> CheckResult:
    """The bob row at rest is m g l sin phi (an identity: the check can fail; wrong: -sin phi's sign flipped)."""
    eom = pendulum_on_cart()
    rest = {c.qd: 0 for c in eom.coordinates}
    row = sp.simplify(eom.forcing[2].xreplace(rest))
    syms = {p.name: p.symbol for p in eom.parameters}
    ok = sp.simplify(row + (-1 if wrong else 1) * syms["m_bob"] * syms["g_acc"] * syms["l_rod"] * sp.sin(eom.coordinates[2].q)) == 0
    return CheckResult("pendulum row at rest", "toy", ok, "identity" if ok else f"row {row}", 0.0)


@dataclass(frozen=True)
class Pendulum:
    name: str = "toy-pendulum"
    title: str = "pendulum on a sprung cart"
    reference: str = "toy"
    scene_type: type = dict
    calls: list = None

    def load_scene(self, path):
        from adbgen.errors import SceneError

        raise SceneError("toy", "the toy family has no scene files")

    def derive(self, scene):
        return pendulum_on_cart()

    def forms(self):
        return {"fixed": self.derive}

    def verify(self, progress, ns=()):
        r = energy_check()
        progress(r)
        return [r]

    def checks(self, ns=()):
        from adbgen.core.checks import DERIVED, Registered

        return [Registered("pendulum row at rest", DERIVED, energy_check, "the gravity term's sign flipped")]

    def models(self):
        return [ModelSpec("toy_pendulum", "Pendulum on a sprung cart", 1,
                          lambda: first_order(pendulum_on_cart(), ("X", "Y")),
                          start=lambda system: ((0.0,) * 6, "hanging at rest"), family=self.name,
                          checks=(Check(("toy", "row"), energy_check),), continuation=Continuation("k_spring", direction=1),
                          kind="pendulum", describe=describe)]

    def kinds(self):
        return {}

    def model_for_scene(self, scene, name=None):
        return self.models()[0]

    def register_commands(self, subparsers):
        p = subparsers.add_parser("toy-pendulum", help="the toy family's command")
        p.set_defaults(fn=lambda args: print("pendulum period", round(2 * math.pi * math.sqrt(1.0 / 9.81), 6)) or 0)


class Listing(targets.Target):
    def dialect(self, which, kernel):
        return load_pylist().ListDialect("y", "p", "out", targets.columns(kernel))

    def skip_reason(self, ir):
        return None if ir.autonomous else "the listing is for autonomous models only"

    def context(self, ir):
        return {"rhs_outputs": len(ir.rhs.outputs)}

    def prove(self, proof):
        """The listing names the model's states and parameters and counts its rhs's stores (issue 20)."""
        ir = proof.model(self).as_unrolled()
        listing = json.loads(proof.files[proof.file(self, "listing/listing.json.j2")])
        proof.require(listing["states"] == list(ir.state_names) and listing["parameters"] == list(ir.parameter_names)
                      and listing["outputs"] == len(ir.rhs.outputs) == len(listing["rhs"]), "the listing is not the model's")


def load_pylist():
    """The toy target's folder, imported as a plug-in outside the package would be."""
    path = Path(__file__).parent / "pylist" / "target.py"
    spec = importlib.util.spec_from_file_location("_adbgen_toy_pylist_target", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture
def toy(tmp_path):
    pylist = load_pylist()
    templates = tmp_path / "listing_templates"  # the target's folder: its templates beside its config
    templates.mkdir()
    (templates / "listing.json.j2").write_text(
        '{"name": {{ ir.name | tojson }}, "states": {{ ir.state_names | list | tojson }}, '
        '"parameters": {{ ir.parameter_names | list | tojson }}, "outputs": {{ listing.rhs_outputs }}, '
        '"rhs": [{% for i, e in programs.rhs.outputs %}{{ e | tojson }}{{ ", " if not loop.last }}{% endfor %}], '
        '"hash": {{ source_hash | tojson }}}\n')
    families.register(Pendulum())
    targets.register(pylist.TARGET)
    targets.register(Listing(name="listing", files=(("listing/listing.json.j2", "{name}/{name}.json"),),
                             printer=pylist.PurePythonPrinter, templates=templates, functions=("rhs",)))
    yield pylist
    families.unregister("toy-pendulum")
    targets.unregister("listing")
    targets.unregister("pylist")


def test_a_registered_family_and_target_regenerate_with_the_others(toy, tmp_path, capsys):
    out = tmp_path / "gen"
    code = main(["regenerate", "--family", "toy-pendulum", "single-plane", "--n", "1", "--out", str(out), "--quiet"])
    assert code == 0, capsys.readouterr().err
    # the toy family got every target, the toy target rendered every autonomous model
    files = {p.relative_to(out).as_posix() for p in out.rglob("*") if p.is_file()}
    assert "thesis_rotating_n1/thesis_rotating_n1.json" in files and "thesis_rotating_n1/thesis_rotating_n1.c" in files
    assert "single_plane_fixed_n1/single_plane_fixed_n1.json" not in files  # forced: the listing skips it
    code = main(["regenerate", "--family", "toy-pendulum", "--out", str(out / "toy"), "--quiet"])
    assert code == 0, capsys.readouterr().err
    toy_files = {p.relative_to(out / "toy").as_posix() for p in (out / "toy").rglob("*") if p.is_file()}
    assert {"toy_pendulum/__init__.py", "toy_pendulum/toy_pendulum.c", "toy_pendulum/toy_pendulum_cvode_main.c",
            "toy_pendulum/auto/toy_pendulum.c", "toy_pendulum/auto/c.toy_pendulum", "toy_pendulum/toy_pendulum.json"} <= toy_files
    listing = json.loads((out / "toy" / "toy_pendulum" / "toy_pendulum.json").read_text())
    assert listing["states"] == ["X", "Y", "phi", "X_dot", "Y_dot", "phi_dot"] and listing["outputs"] == 6
    assert "k_spring" in (out / "toy" / "toy_pendulum" / "auto" / "c.toy_pendulum").read_text()

    # the generated numba module is the pendulum: from rest at X = 0 (no spring force) the cart recoils,
    # phi'' = -(M + m) g sin(phi) / (l (M + m sin^2 phi)), X'' = m l sin(phi) cos(phi) g / (l (M + m sin^2 phi))
    from adbgen.codegen.render_and_import import import_numba

    module = import_numba(out / "toy" / "toy_pendulum", "_adbgen_toy_pendulum")
    phi = 0.3
    f = module.rhs(0.0, np.array([0.0, 0.0, phi, 0.0, 0.0, 0.0]), module.params())
    den = 2.0 + 0.5 * math.sin(phi) ** 2
    assert f[5] == pytest.approx(-2.5 * 9.81 * math.sin(phi) / den, rel=1e-13)
    assert f[3] == pytest.approx(0.5 * 9.81 * math.sin(phi) * math.cos(phi) / den, rel=1e-13) and f[4] == 0.0
    # and it describes itself as its family declared (checked against its rhs before it was written)
    assert (module.FAMILY, module.KIND, module.ANGLES, module.AMPLITUDE) == ("toy-pendulum", "pendulum", ("phi",), ("X", "Y"))
    assert module.STEADY_STATES == ("hanging", "inverted") and module.steady_state("inverted", module.params())[2] == math.pi
    assert module.measure("bob_height", 0.0, np.array([0.0, 0.0, math.pi / 2, 0, 0, 0]), module.params()) == pytest.approx(1.0)

    # and its command and its checks are on the command line
    assert main(["toy-pendulum"]) == 0 and "pendulum period 2.006067" in capsys.readouterr().out
    assert main(["verify", "--model", "toy-pendulum"]) == 0 and "1 passed, 0 failed" in capsys.readouterr().out
    assert [r.passed for c in Pendulum().checks() for r in c.results(wrong=True)] == [False]


def test_unregistered_after_the_test():
    assert "toy-pendulum" not in families.names() and "listing" not in targets.names()
    assert families.names() == ("single-plane", "two-plane", "flexible")
    assert targets.names() == ("numba", "c", "cvode", "auto", "taylor", "lanes")


def _load_module(path: Path, alias: str):
    spec = importlib.util.spec_from_file_location(alias, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_toy_target_prints_the_loop_form_and_it_runs(toy, tmp_path, capsys):
    """pylist's module equals the generated numba module (rhs, jac) at random points, in the loop form:
    one ball loop whatever n, the same number of lines for 3 and 6 balls."""
    from adbgen.codegen.render_and_import import import_numba

    out = tmp_path / "gen"
    code = main(["regenerate", "--family", "single-plane", "--n", "3", "6", "--targets", "pylist", "numba",
                 "--out", str(out), "--quiet", "--skip-checks"])
    assert code == 0, capsys.readouterr().err
    sizes = {}
    rng = np.random.default_rng(5)
    for n in (3, 6):
        name = f"thesis_rotating_n{n}"
        path = out / name / f"{name}_pylist.py"
        text = path.read_text()
        assert "for i in range(" in text and "from math import *" in text and "math.sin" not in text
        sizes[n] = text.count("\n") - text.count("ball_slot")  # the slot tables are data, one line each
        toy_module = _load_module(path, f"_adbgen_pylist_{name}")
        ref = import_numba(out / name, f"_adbgen_pylist_ref_{name}")
        for _ in range(5):
            y = rng.uniform(-1, 1, ref.N_STATES)
            p = ref.DEFAULTS * rng.uniform(0.5, 1.5, ref.DEFAULTS.size)
            assert np.allclose(toy_module.rhs(0.3, list(y), list(p)), ref.rhs(0.3, y, p), rtol=1e-13, atol=1e-15)
            assert np.allclose(np.reshape(toy_module.jac(0.3, list(y), list(p)), (ref.N_STATES, ref.N_STATES)),
                               ref.jac(0.3, y, p), rtol=1e-12, atol=1e-14)
    assert sizes[3] == sizes[6], sizes


def test_the_toy_targets_dialect_is_what_prints(toy, tmp_path, capsys, monkeypatch):
    """Negative control: a pylist dialect that transposes matrix entries gives a wrong jac, which the
    target's own proof refuses before anything is written (issue 20)."""
    entry = toy.ListDialect.entry
    monkeypatch.setattr(toy.ListDialect, "entry",
                        lambda self, row, col: entry(self, row, col) if col is None else entry(self, col, row))
    out = tmp_path / "gen"
    assert main(["regenerate", "--family", "single-plane", "--n", "2", "--targets", "pylist", "numba",
                 "--out", str(out), "--quiet", "--skip-checks"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("adbgen: error: thesis_rotating_n2: pylist files: pylist jac differs"), err
    assert not out.exists() or not any(out.rglob("*.py"))
